package mapm.cli

import mapm.cost.{GateSim, Liberty, Netlist, Sta}

/** Gate-level simulation of a synthesized unit on real operations: the check that synthesis kept
  * the function, and the switching activity of every net for the power analysis.
  *
  * The operations are dealt to the simulator's [[Lanes]] independent lanes in contiguous runs.
  * In each lane every cycle carries an operation with probability `u.validRate` (a seeded
  * Bernoulli pattern, the unit's share of a 16/16/2 frame); on the other cycles `valid` is low and
  * the data inputs keep their last values, as a registered bus does. Reset is held for 4 cycles,
  * then the counters start; they stop when the last operation has entered, so the pipeline's
  * drain does not dilute the activity. The outputs of every valid result are compared, in order,
  * with the model's results for that lane's operations.
  */
object GateLevel {
  val Lanes = 64
  private val resetCycles = 4

  /** The outcome: operations checked, mismatches (and the first, described), and per net its
    * activity (toggles per cycle) and duty over the `cycles` counted cycles. */
  final class Result(nl: Netlist, lib: Liberty.Library, val cycles: Long, activity: Array[Double], duty: Array[Double],
                     val checked: Int, val mismatches: Int, val first: Option[String]) {
    private def act(net: Int): Sta.Activity = Sta.Activity(activity(net), duty(net))
    /** Activity of every instance pin (`inst/PIN`) of the netlist, from the net on it. */
    def pinActivity: Seq[(String, Sta.Activity)] =
      for (c <- nl.cells; (pin, net) <- c.pins.toSeq if net >= 0) yield s"${c.name}/$pin" -> act(net)
    /** Activity of every input port bit except the clock. */
    def portActivity: Seq[(String, Sta.Activity)] =
      for (p <- nl.ports if p.direction == Liberty.Direction.Input && p.name != "clock"; (net, i) <- p.nets.zipWithIndex)
        yield p.bitNames(i) -> act(net)
    private def outputsOf(sequential: Boolean): Seq[Int] = {
      val cells = nl.libraryCells(lib)
      nl.cells.indices.filter(i => cells(i).isSequential == sequential).flatMap { i =>
        cells(i).outputs.flatMap(o => nl.cells(i).pins.get(o.name)).filter(_ >= 0)
      }.distinct
    }
    /** Mean activity of the nets that combinational cells drive, and of the flip-flop outputs. */
    def meanActivity: Double = mean(outputsOf(sequential = false))
    def flopActivity: Double = mean(outputsOf(sequential = true))
    private def mean(nets: Seq[Int]): Double = if (nets.isEmpty) 0 else nets.map(activity(_)).sum / nets.size
  }

  def run(u: CostUnit, nl: Netlist, lib: Liberty.Library, ops: IndexedSeq[UnitOp], seed: Long): Result = {
    val sim = new GateSim(nl, lib, clock = "clock")
    val rnd = new scala.util.Random(seed)
    val per = (ops.length + Lanes - 1) / Lanes
    val next = Array.tabulate(Lanes)(l => l * per)            // next operation of each lane
    val end = Array.tabulate(Lanes)(l => math.min(ops.length, (l + 1) * per))
    val expect = Array.tabulate(Lanes)(l => l * per)          // next result each lane expects
    var mismatches = 0
    var checked = 0
    var first: Option[String] = None
    val hasReset = nl.port("reset").isDefined

    def pokeAll(port: String, v: BigInt): Unit = (0 until Lanes).foreach(l => sim.poke(port, l, v))
    def collect(): Unit = for (l <- 0 until Lanes if sim.peek(u.validOut, l) != 0) {
      if (expect(l) >= end(l)) {
        mismatches += 1
        if (first.isEmpty) first = Some(s"lane $l: a result beyond its ${end(l) - l * per} operations")
      } else {
        val op = ops(expect(l))
        val got = u.outPorts.map(sim.peek(_, l))
        if (got.indices.exists(i => got(i) != op.expect(i))) {
          mismatches += 1
          if (first.isEmpty) first = Some(s"operation ${expect(l)}: " + u.outPorts.indices.map(i =>
            s"${u.outPorts(i)} ${got(i).toString(16)} (model ${op.expect(i).toString(16)})").mkString(", "))
        }
        checked += 1
        expect(l) += 1
      }
    }

    // Reset with every input low.
    for (p <- nl.ports if p.direction == Liberty.Direction.Input && p.name != "clock") pokeAll(p.name, 0)
    if (hasReset) pokeAll("reset", 1)
    for (_ <- 0 until resetCycles) sim.step()
    if (hasReset) pokeAll("reset", 0)
    sim.resetActivity()
    var cycles = 0L
    while ((0 until Lanes).exists(l => next(l) < end(l))) {
      for (l <- 0 until Lanes) {
        val go = next(l) < end(l) && rnd.nextDouble() < u.validRate
        sim.poke(u.validIn, l, if (go) 1 else 0)
        if (go) {
          val op = ops(next(l))
          for (i <- u.inPorts.indices) sim.poke(u.inPorts(i), l, op.in(i))
          next(l) += 1
        }
      }
      sim.step()
      cycles += 1
      collect()
    }
    val counted = sim.cycles
    val activity = Array.tabulate(nl.netCount)(sim.activity)
    val duty = Array.tabulate(nl.netCount)(sim.duty)
    (0 until Lanes).foreach(l => sim.poke(u.validIn, l, 0))
    for (_ <- 0 to u.latency + 1) { sim.step(); collect() }
    val lost = (0 until Lanes).map(l => end(l) - expect(l)).sum
    if (lost > 0) { mismatches += lost; if (first.isEmpty) first = Some(s"$lost operations produced no result") }
    new Result(nl, lib, counted, activity, duty, checked, mismatches, first)
  }
}
