package mapm.cli

import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.numerics.{FloatFormat, ShaderChainModel}
import Args.FloatFormatReader

/** `mapm soa-bench`: speed and accuracy of the shader-chain model on seeded random operations
  * (kernel, h and power near 1.0, BRDF and contribution in (0, 1]). Prints channel evaluations
  * per second on one thread, once with every channel computed on its own and once with the
  * three channels of an operation sharing MUL1, the divider and QN as the hardware does, and
  * the largest error against the float64 reference. */
object SoaBenchCommand extends Command {
  val name = "soa-bench"
  val summary = "measure the shader-chain model's speed and error on random operations"

  @main
  def soaBench(
      @arg(doc = "float format") format: FloatFormat = FloatFormat.fp32,
      @arg(name = "g", doc = "guard digits per online unit") g: Int = 3,
      @arg(doc = "random operations per timed pass (3 channels each)") ops: Int = 1000000,
      @arg(doc = "random seed") seed: Long = 1
  ): Int = {
    Args.checkSeed(seed)
    MapmError.check(ops >= 1, s"soa-bench: --ops must be at least 1, got $ops")
    val model = new ShaderChainModel(format, g)
    val rnd = new scala.util.Random(seed)
    val spread = math.min(20, format.bias / 2)
    def operand(lo: Int, hi: Int): Long =
      format.pack(0, format.bias + lo + rnd.nextInt(hi - lo + 1), rnd.nextLong() & format.manMask)
    // Per operation: kernel, BRDF, h, power r/g/b, contribution r/g/b.
    val in = Array.fill(ops)(Array(operand(-spread, spread), operand(-spread, -1), operand(-spread, spread),
      operand(-spread, spread), operand(-spread, spread), operand(-spread, spread),
      operand(-spread, -1), operand(-spread, -1), operand(-spread, -1)))

    var sink = 0L
    def separate(): Unit = in.foreach { o =>
      var c = 0
      while (c < 3) { sink += model.colour(o(0), o(1), o(2), o(3 + c), o(6 + c)).bits; c += 1 }
    }
    def shared(): Unit = in.foreach { o =>
      val f = model.front(o(0), o(1), o(2))
      var c = 0
      while (c < 3) { sink += model.channel(f, o(3 + c), o(6 + c)).bits; c += 1 }
    }
    // Rates per second of this thread's CPU time (the machine may be shared) and of wall time.
    val cpu = java.lang.management.ManagementFactory.getThreadMXBean
    def rate(body: () => Unit): (Double, Double) = {
      body() // warm-up pass (JIT)
      val c0 = cpu.getCurrentThreadCpuTime; val t0 = System.nanoTime()
      body()
      val c1 = cpu.getCurrentThreadCpuTime; val t1 = System.nanoTime()
      (3.0 * ops / ((c1 - c0) / 1e9), 3.0 * ops / ((t1 - t0) / 1e9))
    }
    val sep = rate(() => separate())
    val shr = rate(() => shared())

    var worst = 0.0; var normal = 0L
    in.foreach { o =>
      for (c <- 0 until 3) {
        val r = model.colour(o(0), o(1), o(2), o(3 + c), o(6 + c))
        if (r.flags == 0) {
          normal += 1
          worst = math.max(worst, model.ulpError(r.bits, model.reference(o(0), o(1), o(2), o(3 + c), o(6 + c))))
        }
      }
    }
    println(s"shader chain model, format $format, g = $g (N = ${model.digits} digits per unit), $ops operations x 3 channels")
    println(f"  million channels per CPU-second (wall-clock second), one thread:")
    println(f"    each channel alone:          ${sep._1 / 1e6}%.2f (${sep._2 / 1e6}%.2f)")
    println(f"    MUL1+DIV+QN shared per op:   ${shr._1 / 1e6}%.2f (${shr._2 / 1e6}%.2f)")
    println(f"  max error vs float64 reference: $worst%.3f ulp over $normal normal results")
    if (sink == 42) println("") // keeps the timed work observable to the JIT
    0
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
