package mapm.evaluation

import java.awt.Color
import java.nio.file.{Files, Path}

import scala.jdk.CollectionConverters._

import mapm.MapmError
import org.knowm.xchart.{BitmapEncoder, CategoryChartBuilder}

/** A bar chart in a PNG, drawn by XChart, in the manner of the dissertation's Figures 4.9-4.20:
  * one bar per configuration (label under it, value on it), a y axis from 0 with gridlines, a
  * title and an axis label. With `group`, bars of one group (e.g. the same TSM count) share a
  * colour and a legend entry. A value that is NaN or infinite draws no bar. */
object BarChart {
  /** The bars' colour (of the first group). */
  val BarColor = new Color(70, 110, 170)
  /** Colours of the groups, in order of first appearance. */
  val GroupColors: Array[Color] = Array(BarColor, new Color(215, 120, 40), new Color(80, 150, 80), new Color(170, 60, 60),
    new Color(130, 90, 170), new Color(120, 120, 120), new Color(40, 160, 170), new Color(190, 160, 40))

  def write(path: Path, title: String, yLabel: String, bars: Seq[(String, Double)], group: String => String = _ => ""): Unit = {
    val chart = new CategoryChartBuilder().width(math.max(640, 120 + 46 * bars.size)).height(480).title(title).yAxisTitle(yLabel).build()
    val style = chart.getStyler
    val groups = bars.map { case (label, _) => group(label) }.distinct
    style.setLegendVisible(groups.size > 1)
    style.setOverlapped(true) // one series per group, each bar in its own category
    style.setChartBackgroundColor(Color.WHITE)
    style.setPlotBackgroundColor(Color.WHITE)
    style.setSeriesColors(groups.indices.map(i => GroupColors(i % GroupColors.length)).toArray)
    style.setXAxisLabelRotation(60)
    style.setLabelsVisible(true)
    style.setLabelsFontColorAutomaticEnabled(false)
    style.setLabelsFontColor(Color.BLACK)
    style.setLabelsPosition(1.0)
    style.setYAxisMin(0.0)
    style.setDecimalPattern("#,##0.###")
    for (gname <- groups) {
      val values: Seq[java.lang.Double] = bars.map { case (label, v) =>
        if (group(label) != gname || v.isNaN || v.isInfinite) null else java.lang.Double.valueOf(v) }
      chart.addSeries(if (gname.isEmpty) yLabel else gname, bars.map(_._1).asJava, values.asJava)
    }
    try {
      Option(path.toAbsolutePath.getParent).foreach(Files.createDirectories(_))
      Files.write(path, BitmapEncoder.getBitmapBytes(chart, BitmapEncoder.BitmapFormat.PNG))
    } catch { case e: java.io.IOException => MapmError.fail(s"$path: cannot write (${e.getMessage})") }
  }
}
