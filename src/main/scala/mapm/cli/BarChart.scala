package mapm.cli

import java.awt.Color
import java.nio.file.{Files, Path}

import scala.jdk.CollectionConverters._

import mapm.MapmError
import org.knowm.xchart.{BitmapEncoder, CategoryChartBuilder}

/** A bar chart in a PNG, drawn by XChart, in the manner of the dissertation's Figures 4.9 and
  * 4.12: one bar per configuration (label under it, value on it), a y axis from 0 with gridlines,
  * a title and an axis label. A value that is NaN or infinite draws no bar. */
object BarChart {
  /** The bars' colour. */
  val BarColor = new Color(70, 110, 170)

  def write(path: Path, title: String, yLabel: String, bars: Seq[(String, Double)]): Unit = {
    val chart = new CategoryChartBuilder().width(math.max(640, 120 + 46 * bars.size)).height(480).title(title).yAxisTitle(yLabel).build()
    val style = chart.getStyler
    style.setLegendVisible(false)
    style.setChartBackgroundColor(Color.WHITE)
    style.setPlotBackgroundColor(Color.WHITE)
    style.setSeriesColors(Array(BarColor))
    style.setXAxisLabelRotation(60)
    style.setLabelsVisible(true)
    style.setLabelsFontColorAutomaticEnabled(false)
    style.setLabelsFontColor(Color.BLACK)
    style.setLabelsPosition(1.0)
    style.setYAxisMin(0.0)
    val values: Seq[java.lang.Double] = bars.map { case (_, v) => if (v.isNaN || v.isInfinite) null else java.lang.Double.valueOf(v) }
    chart.addSeries(yLabel, bars.map(_._1).asJava, values.asJava)
    try {
      Option(path.toAbsolutePath.getParent).foreach(Files.createDirectories(_))
      Files.write(path, BitmapEncoder.getBitmapBytes(chart, BitmapEncoder.BitmapFormat.PNG))
    } catch { case e: java.io.IOException => MapmError.fail(s"$path: cannot write (${e.getMessage})") }
  }
}
