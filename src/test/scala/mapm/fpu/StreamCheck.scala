package mapm.fpu

import mapm.sim.VerilatorPipe
import scala.collection.mutable.ArrayBuffer

/** Streams operations through a fixed-latency Valid pipeline simulated by [[VerilatorPipe]], with
  * random idle cycles between them, and checks the stream at the output:
  *  - `out.valid` is set exactly `latency` cycles after each valid input and in no other cycle,
  *    so results leave in input order and none is lost or duplicated;
  *  - each result equals the reference (`check` returns a description of a mismatch, or null).
  * Idle cycles carry random data on every input port, which must not disturb anything.
  */
object StreamCheck {
  final case class Report(operations: Int, cycles: Long, idleCycles: Int)

  /** @param ports  the data input ports, in the order of the arrays `input` returns
    * @param input  operation i's values for `ports` (called from another thread: no shared state)
    * @param check  compares operation i's output row (values in `pipe.outputs` order, see
    *               `pipe.out`) with the reference: null when right, else a description
    * @param gap    probability of idle cycles (1 to 3 of them) before an operation
    */
  def run(pipe: VerilatorPipe, latency: Int, count: Int, ports: Seq[String], input: Int => Array[BigInt],
          check: (Int, Array[BigInt]) => String, gap: Double, seed: Long,
          validIn: String = "io_in_valid", validOut: String = "io_out_valid"): Report = {
    val rnd = new scala.util.Random(seed)
    // The schedule: the operation entering in each cycle, or -1 for an idle cycle.
    val schedule = new ArrayBuffer[Int](count + count / 2 + latency + 4)
    for (i <- 0 until count) {
      if (rnd.nextDouble() < gap) for (_ <- 0 to rnd.nextInt(3)) schedule += -1
      schedule += i
    }
    for (_ <- 0 until latency + 2) schedule += -1
    val idle = schedule.count(_ < 0)

    val vIn = pipe.in(validIn)
    val slots = ports.map(pipe.in).toArray
    val widths = pipe.inputs.map(_.width).toArray
    val garbage = new scala.util.Random(seed + 1) // used by the writer thread only
    val rows = schedule.iterator.map { op =>
      val row = Array.tabulate(pipe.inputs.length)(k => BigInt(widths(k), garbage))
      row(vIn) = if (op >= 0) 1 else 0
      if (op >= 0) { val vals = input(op); for (k <- slots.indices) row(slots(k)) = vals(k) }
      row
    }

    val vOut = pipe.out(validOut)
    val errors = ArrayBuffer.empty[String]
    var errorCount = 0
    var done = 0
    var t = 0
    def error(msg: => String): Unit = { errorCount += 1; if (errors.length < 10) errors += msg }
    val cycles = pipe.run(rows) { out =>
      val op = if (t >= latency) schedule(t - latency) else -1
      val valid = out(vOut) == 1
      if (valid != (op >= 0)) error(s"cycle $t: out.valid = $valid, expected ${op >= 0} (operation $op)")
      else if (valid) {
        done += 1
        val msg = check(op, out)
        if (msg != null) error(s"operation $op: $msg")
      }
      t += 1
    }
    assert(errorCount == 0, s"${pipe.top}: $errorCount errors, first ones:\n" + errors.mkString("\n"))
    assert(cycles == schedule.length && done == count, s"${pipe.top}: ran $cycles cycles, $done of $count operations left")
    Report(count, cycles, idle)
  }
}
