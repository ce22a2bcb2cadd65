package mapm.probe

import java.nio.file.Paths

object WholeProbe {
  def main(args: Array[String]): Unit = {
    val dir = Paths.get(args(0))
    val w = mapm.cost.Sta.timeWhole(Seq(dir.resolve("netlist.v"), dir.resolve("blackboxes.v")), args(1),
      mapm.cost.CostTools.get.osu018Lib, Paths.get(args(2)), paths = 12, memoryLimitBytes = 20L << 30)
    println(f"fmax ${w.fmaxGHz * 1e3}%.1f MHz, ${w.instances} cells, ${w.seconds}%.0f s")
    w.worst.foreach(p => println(f"  ${p.periodNs}%.3f ns ${p.startPoint} -> ${p.endPoint} through ${p.through.mkString(" > ")}"))
  }
}
