package mapm.cli

import java.awt.{BasicStroke, Color, Font, RenderingHints}
import java.awt.image.BufferedImage
import java.nio.file.{Files, Path}

import mapm.MapmError

/** A plain bar chart drawn with java.awt into a PNG, in the manner of the dissertation's
  * Figures 4.9 and 4.12: one bar per configuration (label under it, value above it), a y axis with
  * gridlines, a title and an axis label. */
object BarChart {
  def write(path: Path, title: String, yLabel: String, bars: Seq[(String, Double)]): Unit = {
    val (w, h) = (math.max(640, 120 + 46 * bars.size), 480)
    val (left, right, top, bottom) = (80, 20, 50, 90)
    val img = new BufferedImage(w, h, BufferedImage.TYPE_INT_RGB)
    val g = img.createGraphics()
    g.setRenderingHint(RenderingHints.KEY_ANTIALIASING, RenderingHints.VALUE_ANTIALIAS_ON)
    g.setRenderingHint(RenderingHints.KEY_TEXT_ANTIALIASING, RenderingHints.VALUE_TEXT_ANTIALIAS_ON)
    g.setColor(Color.WHITE); g.fillRect(0, 0, w, h)
    val finite = bars.map(_._2).filter(v => !v.isNaN && !v.isInfinite)
    val maxV = niceCeil(if (finite.isEmpty) 1.0 else math.max(finite.max, 1e-9))
    val plotH = h - top - bottom
    def y(v: Double): Int = top + plotH - (v / maxV * plotH).round.toInt
    g.setFont(new Font(Font.SANS_SERIF, Font.BOLD, 16)); g.setColor(Color.BLACK)
    g.drawString(title, (w - g.getFontMetrics.stringWidth(title)) / 2, 28)
    g.setFont(new Font(Font.SANS_SERIF, Font.PLAIN, 12))
    for (k <- 0 to 5) { // gridlines and y ticks
      val v = maxV * k / 5
      g.setColor(new Color(220, 220, 220)); g.drawLine(left, y(v), w - right, y(v))
      g.setColor(Color.BLACK)
      val s = if (maxV >= 10) f"$v%.0f" else f"$v%.2f"
      g.drawString(s, left - 8 - g.getFontMetrics.stringWidth(s), y(v) + 4)
    }
    g.setStroke(new BasicStroke(1.5f))
    g.drawLine(left, top, left, top + plotH); g.drawLine(left, top + plotH, w - right, top + plotH)
    val rot = g.getTransform
    g.rotate(-math.Pi / 2); g.drawString(yLabel, -(top + plotH / 2 + g.getFontMetrics.stringWidth(yLabel) / 2), 18); g.setTransform(rot)
    val slot = (w - left - right).toDouble / math.max(1, bars.size)
    for (((label, v), i) <- bars.zipWithIndex) {
      val x0 = (left + i * slot + slot * 0.15).toInt
      val bw = math.max(2, (slot * 0.7).toInt)
      if (!v.isNaN && !v.isInfinite) {
        g.setColor(new Color(70, 110, 170)); g.fillRect(x0, y(v), bw, top + plotH - y(v))
        g.setColor(Color.BLACK)
        val s = if (v >= 100) f"$v%.0f" else if (v >= 10) f"$v%.1f" else f"$v%.2f"
        g.setFont(new Font(Font.SANS_SERIF, Font.PLAIN, 10)); g.drawString(s, x0 + (bw - g.getFontMetrics.stringWidth(s)) / 2, y(v) - 4)
      }
      g.setFont(new Font(Font.SANS_SERIF, Font.PLAIN, 11)); g.setColor(Color.BLACK)
      val t = g.getTransform
      g.translate(x0 + bw / 2 + 4, top + plotH + 8); g.rotate(-math.Pi / 3)
      g.drawString(label, -g.getFontMetrics.stringWidth(label), 0); g.setTransform(t)
    }
    g.dispose()
    val out = new java.io.ByteArrayOutputStream()
    if (!javax.imageio.ImageIO.write(img, "png", out)) MapmError.fail(s"$path: no PNG writer available")
    try { Option(path.toAbsolutePath.getParent).foreach(Files.createDirectories(_)); Files.write(path, out.toByteArray) }
    catch { case e: java.io.IOException => MapmError.fail(s"$path: cannot write (${e.getMessage})") }
  }

  /** The smallest of 1, 2, 2.5, 5 times a power of ten at or above v (the axis top). */
  private def niceCeil(v: Double): Double = {
    val p = math.pow(10, math.floor(math.log10(v)))
    Seq(1.0, 2.0, 2.5, 5.0, 10.0).map(_ * p).find(_ >= v * (1 - 1e-12)).getOrElse(10 * p)
  }
}
