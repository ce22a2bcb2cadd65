package mapm.fpu

import mapm.sim.VerilatorPipe
import scala.collection.mutable.ArrayBuffer

/** Streams operations through a fixed-latency Valid pipeline in Verilator, with random idle cycles
  * between them, and checks the stream at the output:
  *  - `out.valid` is set exactly `latency` cycles after each valid input and in no other cycle,
  *    so results leave in input order and none is lost or duplicated;
  *  - each result's fields equal the model's.
  * Idle cycles carry random data on every input, which must not disturb anything.
  */
object StreamCheck {
  final case class Report(operations: Int, cycles: Long, idleCycles: Int)

  /** @param pipe     a typed pipe over the unit's Valid input and output (`Sim.pipe(gen)(_.io.in,
    *                 _.io.out)`): rows (valid, operands in field order), outputs (valid, results)
    * @param operands operation i's values for the input's data fields (called from another thread:
    *                 no shared state)
    * @param model    the values the output's data fields must show for operation i
    * @param show     operation i, for a mismatch message
    * @param gap      probability of idle cycles (1 to 3 of them) before an operation
    */
  def run(pipe: VerilatorPipe, latency: Int, count: Int, operands: Int => Seq[BigInt], model: Int => Seq[BigInt],
          show: Int => String, gap: Double, seed: Long): Report = {
    val rnd = new scala.util.Random(seed)
    // The schedule: the operation entering in each cycle, or -1 for an idle cycle.
    val schedule = new ArrayBuffer[Int](count + count / 2 + latency + 4)
    for (i <- 0 until count) {
      if (rnd.nextDouble() < gap) for (_ <- 0 to rnd.nextInt(3)) schedule += -1
      schedule += i
    }
    for (_ <- 0 until latency + 2) schedule += -1
    val idle = schedule.count(_ < 0)

    val widths = pipe.inputs.map(_.width).toArray
    val garbage = new scala.util.Random(seed + 1) // used by the writer thread only
    val rows = schedule.iterator.map { op =>
      if (op >= 0) (BigInt(1) +: operands(op)).toArray
      else Array.tabulate(widths.length)(k => if (k == 0) BigInt(0) else BigInt(widths(k), garbage))
    }

    val errors = ArrayBuffer.empty[String]
    var errorCount = 0
    var done = 0
    var t = 0
    def error(msg: => String): Unit = { errorCount += 1; if (errors.length < 10) errors += msg }
    val cycles = pipe.run(rows) { out =>
      val op = if (t >= latency) schedule(t - latency) else -1
      val valid = out(0) == 1
      if (valid != (op >= 0)) error(s"cycle $t: out.valid = $valid, expected ${op >= 0} (operation $op)")
      else if (valid) {
        done += 1
        val (got, want) = (out.toSeq.tail, model(op))
        if (got != want) error(s"operation $op (${show(op)}): hardware ${hex(got)}, model ${hex(want)}")
      }
      t += 1
    }
    assert(errorCount == 0, s"${pipe.top}: $errorCount errors, first ones:\n" + errors.mkString("\n"))
    assert(cycles == schedule.length && done == count, s"${pipe.top}: ran $cycles cycles, $done of $count operations left")
    Report(count, cycles, idle)
  }

  private def hex(values: Seq[BigInt]): String = values.map(v => "0x" + v.toString(16)).mkString(" ")
}
