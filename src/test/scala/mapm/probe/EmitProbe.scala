package mapm.probe

import mapm.pipeline.Configure
import mapm.numerics.FloatFormat

object EmitProbe {
  def main(args: Array[String]): Unit = {
    val Array(t, s, a) = args(0).split('/').map(_.toInt)
    val p = Configure.of(t, s, a, FloatFormat.fp32, 3)
    def rss = { val r = Runtime.getRuntime; (r.totalMemory - r.freeMemory) / 1e9 }
    val t0 = System.nanoTime()
    val fir = circt.stage.ChiselStage.emitCHIRRTL(new mapm.top.Mapm(p))
    val t1 = System.nanoTime()
    println(f"elaborate+chirrtl ${(t1 - t0) / 1e9}%.1f s, ${fir.length / 1e6}%.1f MB firrtl, heap $rss%.2f GB")
    // per-module FIRRTL sizes
    val mods = """(?m)^  (?:public )?module (\w+)""".r.findAllMatchIn(fir).toSeq
    val sizes = mods.zip(mods.drop(1).map(_.start) :+ fir.length).map { case (m, e) => m.group(1) -> (e - m.start) }
    println(s"  ${sizes.size} modules, ${sizes.map(_._2).sum / 1e6} MB in them")
    sizes.groupBy(_._1.replaceAll("_[0-9]+$", "")).map { case (k, v) => (k, v.size, v.map(_._2).sum) }.toSeq.sortBy(-_._3).take(25)
      .foreach { case (n, c, b) => println(f"  $n%-60s x$c%4d ${b / 1e3}%.0f kB") }
    if (args.contains("dump")) java.nio.file.Files.write(java.nio.file.Paths.get("/work/exp/s49/probe.fir"), fir.getBytes)
    if (args.length > 1) {
      val t2 = System.nanoTime()
      val sv = mapm.sim.Emit.systemVerilog(new mapm.top.Mapm(p))
      println(f"full emit ${(System.nanoTime() - t2) / 1e9}%.1f s, ${sv.length / 1e6}%.1f MB sv")
    }
  }
}
