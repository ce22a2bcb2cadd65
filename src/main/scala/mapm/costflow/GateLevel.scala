package mapm.costflow

import mapm.cost.{ClockGates, GateSim, Liberty, Netlist, Sta}
import mapm.model.Progress
import mapm.sim.VerilatorPipe
import scala.collection.mutable.ArrayBuffer

/** Gate-level simulation of a synthesized unit on real operations: the check that synthesis kept
  * the function, and the switching activity of every net for the power analysis.
  *
  * The operations are dealt to the simulator's [[Lanes]] independent lanes in contiguous runs.
  * For a unit with a valid input, each cycle of a lane carries an operation with probability
  * `u.validRate` (a seeded Bernoulli pattern, the unit's share of a 16/16/2 frame); on the other
  * cycles `valid` is low and the data inputs keep their last values, as a registered bus does. A
  * free-running unit (the online multiplier and divider, whose stages each take a digit of another
  * operation every cycle) takes one operation, a whole row of inputs, every cycle.
  *
  * Reset is held for 4 cycles with every input low, then the activity counters start; they stop
  * when the last operation has entered, so the pipeline's drain does not dilute the activity.
  * Outputs are sampled before each clock edge, as [[VerilatorPipe]] samples them. Checks:
  *  - against the model: the outputs of every valid result, in order, equal the model's results
  *    for that lane's operations (units whose operations carry expected values);
  *  - against the RTL: each lane's input rows run through the unit's RTL in Verilator, whose
  *    valid results (every cycle's outputs for a free-running unit) must equal the netlist's,
  *    cycle for cycle.
  */
object GateLevel {
  val Lanes = 64
  private val resetCycles = 4

  /** Runs each lane's input rows `rows` through the unit's RTL in `pipe` and compares its
    * results, in order, with those the netlist gave (`seen`); `at` is each input port's column.
    * Each lane's first difference goes to `fail`. Returns the results compared. */
  private def rtlCheck(u: CostUnit, pipe: VerilatorPipe, rows: Array[ArrayBuffer[Array[BigInt]]], seen: Array[ArrayBuffer[Obs]],
                       at: Map[String, Int], fail: String => Unit): Long = {
    var checked = 0L
    Progress(s"RTL check in Verilator", Lanes.toLong)(bar => for (l <- 0 until Lanes if rows(l).nonEmpty) {
      bar.advance()
      val order = pipe.inputs.map(p => at.getOrElse(p.name, sys.error(s"RTL input ${p.name} is not in the netlist")))
      val (vOut, outs) = (u.validOut.map(pipe.out), u.outPorts.map(pipe.out))
      val theirs = ArrayBuffer.empty[Obs]
      var c = 0L
      pipe.run(rows(l).iterator.map(r => order.map(r).toArray), resetCycles) { o =>
        if (vOut.forall(o(_) != 0)) theirs += (c -> outs.map(o))
        c += 1
      }
      val mine = seen(l)
      checked += math.min(mine.length, theirs.length)
      mine.indices.find(i => i >= theirs.length || mine(i) != theirs(i)).orElse(
        if (theirs.length > mine.length) Some(mine.length) else None).foreach { i =>
        fail(s"lane $l: the netlist and the RTL differ at result $i: " +
          s"netlist ${mine.lift(i).map(describe(u, _)).getOrElse("none")}, RTL ${theirs.lift(i).map(describe(u, _)).getOrElse("none")}")
      }
    })
    checked
  }

  /** The outcome: per net its activity (toggles per cycle) and duty over the `cycles` counted
    * cycles; results checked against the model and against the RTL, the mismatches and the first
    * one described. */
  final class Result(nl: Netlist, lib: Liberty.Library, val cycles: Long, activity: Array[Double], duty: Array[Double],
                     val checked: Int, val rtlChecked: Long, val rtlNote: String, val mismatches: Int,
                     val first: Option[String], network: ClockGates.Network, gateDuty: IndexedSeq[Double]) {
    private def act(net: Int): Sta.Activity = Sta.Activity(activity(net), duty(net))
    /** Activity of every instance pin (`inst/PIN`) of the netlist, from the net on it. */
    def pinActivity: Seq[(String, Sta.Activity)] =
      for (c <- nl.cells; (pin, net) <- c.pins.toSeq if net >= 0) yield s"${c.name}/$pin" -> act(net)
    /** Activity of every input port bit except the clock. */
    def portActivity: Seq[(String, Sta.Activity)] =
      for (p <- nl.ports if p.direction == Liberty.Direction.Input && p.name != "clock"; (net, i) <- p.nets.zipWithIndex)
        yield p.bitNames(i) -> act(net)
    private def outputsOf(sequential: Boolean): Seq[Int] = {
      nl.cells.indices.filter(i => cells(i).isSequential == sequential).flatMap { i =>
        cells(i).outputs.flatMap(o => nl.cells(i).pins.get(o.name)).filter(_ >= 0)
      }.distinct
    }
    /** Mean activity of the nets that combinational cells drive, and of the flip-flop outputs. */
    def meanActivity: Double = mean(outputsOf(sequential = false))
    def flopActivity: Double = mean(outputsOf(sequential = true))
    private def mean(nets: Seq[Int]): Double = if (nets.isEmpty) 0 else nets.map(activity(_)).sum / nets.size

    /** The clock gates' levels for the power analysis ([[Sta.GatedLevel]]): per gate, the
      * flip-flops its clock drives and the cells of its gated clock, at the gate's measured duty;
      * the gates' latches at duty 1. */
    def gatedLevels: Seq[Sta.GatedLevel] = {
      val level = nl.cells.indices.flatMap(i => gateOf(i).map(_ -> nl.cells(i).name)).groupMap(_._1)(_._2)
      val latches = nl.cells.indices.filter(i => network.cells(i) && cells(i).latch.isDefined).map(nl.cells(_).name)
      // The cells that drive a gated clock: their switching is the clock distribution's.
      val clockDrivers = nl.cells.indices.filter(i => network.cells(i) && cells(i).latch.isEmpty).map(nl.cells(_).name).toSet
      level.toSeq.sortBy(_._1).map { case (k, cs) => Sta.GatedLevel(cs, gateDuty(k), cs.filter(clockDrivers).toSet) } ++
        (if (latches.isEmpty) Nil else Seq(Sta.GatedLevel(latches, 1.0)))
    }

    private lazy val cells = nl.libraryCells(lib)
    /** The gate (its index in the network) whose clock each cell's power follows: a flip-flop's
      * clock's gate, a clock-network cell's level's gate; None on the clock port or outside. */
    private lazy val gateOf: IndexedSeq[Option[Int]] = {
      val gateAt = network.gates.map(_.held).zipWithIndex.toMap
      nl.cells.indices.map { i =>
        val c = nl.cells(i)
        val net =
          if (cells(i).ff.isDefined) cells(i).ff.get.clockedOn.vars.headOption.flatMap(c.pins.get).flatMap(network.clockOf.get)
          else if (network.cells(i) && cells(i).latch.isEmpty) cells(i).outputs.flatMap(o => c.pins.get(o.name)).headOption.flatMap(network.levelOf.get)
          else None
        net.flatMap(gateAt.get)
      }
    }

    /** The pins that stop every gate: the outputs of their latches (`inst/PIN`). */
    def gateStopPins: Seq[String] = {
      val drivers = nl.drivers(lib)
      network.gates.map(g => drivers(g.held) match {
        case Netlist.Driver.FromPin(_, pin) => pin
        case d => sys.error(s"a clock gate's latch output driven by $d")
      })
    }

    /** Each gate's enabled fraction of the counted cycles, in [[ClockGates.Network.gates]] order. */
    def gateDuties: IndexedSeq[Double] = gateDuty

    /** The flip-flops of the netlist. */
    def flops: Int = cells.count(_.ff.isDefined)

    /** Flip-flops clocked in an average cycle: those on the clock port every cycle, those behind a
      * gate at its duty. */
    def flopClocksPerCycle: Double =
      nl.cells.indices.filter(cells(_).ff.isDefined).map(i => gateOf(i).map(gateDuty).getOrElse(1.0)).sum
  }

  /** One observed result: the cycle and the values of the unit's `outPorts`. */
  private type Obs = (Long, IndexedSeq[BigInt])

  def run(u: CostUnit, nl: Netlist, lib: Liberty.Library, ops: IndexedSeq[UnitOp], seed: Long,
          rtl: Option[VerilatorPipe] = None): Result = {
    val sim = new GateSim(nl, lib, clock = "clock")
    val rnd = new scala.util.Random(seed)
    val ins = nl.ports.filter(p => p.direction == Liberty.Direction.Input && p.name != "clock" && p.name != "reset")
      .map(_.name)
    val at = ins.zipWithIndex.toMap
    val validAt = u.validIn.map(at)
    val inAt = u.inPorts.map(at)
    val per = (ops.length + Lanes - 1) / Lanes
    val next = Array.tabulate(Lanes)(l => l * per)            // next operation of each lane
    val end = Array.tabulate(Lanes)(l => math.min(ops.length, (l + 1) * per))
    val expect = Array.tabulate(Lanes)(l => l * per)          // next result each lane expects
    val cur = Array.fill(Lanes)(Array.fill(ins.length)(BigInt(0)))
    val rows = Array.fill(Lanes)(ArrayBuffer.empty[Array[BigInt]])
    val seen = Array.fill(Lanes)(ArrayBuffer.empty[Obs])
    var mismatches = 0
    var checked = 0
    var first: Option[String] = None
    def fail(msg: => String): Unit = { mismatches += 1; if (first.isEmpty) first = Some(msg) }
    val hasReset = nl.port("reset").isDefined

    def pokeAll(port: String, v: BigInt): Unit = (0 until Lanes).foreach(l => sim.poke(port, l, v))
    def apply(cycle: Long): Unit = for (l <- 0 until Lanes) {
      for (i <- ins.indices) sim.poke(ins(i), l, cur(l)(i))
      if (rtl.isDefined) rows(l) += cur(l).clone()
      if (u.validOut.forall(v => sim.peek(v, l) != 0)) {
        val got = u.outPorts.map(sim.peek(_, l))
        seen(l) += (cycle -> got)
        if (u.checksModel) {
          if (expect(l) >= end(l)) fail(s"lane $l: a result beyond its ${end(l) - l * per} operations")
          else {
            val op = ops(expect(l))
            if (got.indices.exists(i => got(i) != op.expect(i)))
              fail(s"operation ${expect(l)}: " + u.outPorts.indices.map(i =>
                s"${u.outPorts(i)} ${got(i).toString(16)} (model ${op.expect(i).toString(16)})").mkString(", "))
            checked += 1
            expect(l) += 1
          }
        }
      }
    }

    for (p <- ins) pokeAll(p, 0)
    if (hasReset) pokeAll("reset", 1)
    for (_ <- 0 until resetCycles) sim.step()
    if (hasReset) pokeAll("reset", 0)
    sim.resetActivity()
    var cycle = 0L
    Progress("gate-level simulation", ops.length.toLong) { bar =>
      while ((0 until Lanes).exists(l => next(l) < end(l))) {
        for (l <- 0 until Lanes) {
          val go = next(l) < end(l) && (validAt.isEmpty || rnd.nextDouble() < u.validRate)
          validAt.foreach(v => cur(l)(v) = if (go) 1 else 0)
          if (go) {
            val op = ops(next(l))
            for (i <- inAt.indices) cur(l)(inAt(i)) = op.in(i)
            next(l) += 1
            bar.advance()
          }
        }
        apply(cycle)
        sim.step()
        cycle += 1
      }
    }
    val counted = sim.cycles
    val activity = Array.tabulate(nl.netCount)(sim.activity)
    val duty = Array.tabulate(nl.netCount)(sim.duty)
    val gateDuty = sim.clockNetwork.gates.indices.map(sim.gateDuty)
    for (l <- 0 until Lanes; v <- validAt) cur(l)(v) = 0
    if (u.validIn.isDefined) for (_ <- 0 to u.latency + 1) { apply(cycle); sim.step(); cycle += 1 }
    if (u.checksModel) {
      val lost = (0 until Lanes).map(l => end(l) - expect(l)).sum
      if (lost > 0) fail(s"$lost operations produced no result")
    }

    // The same rows through the RTL, lane by lane.
    val rtlChecked = rtl.map(pipe => rtlCheck(u, pipe, rows, seen, at, fail(_))).getOrElse(0L)
    val note = if (rtl.isDefined) s"$rtlChecked results of ${u.top} in Verilator" else "skipped: verilator not found"
    new Result(nl, lib, counted, activity, duty, checked, rtlChecked, note, mismatches, first,
      sim.clockNetwork, gateDuty)
  }

  private def describe(u: CostUnit, o: Obs): String =
    s"cycle ${o._1}: " + u.outPorts.indices.map(i => s"${u.outPorts(i)} ${o._2(i).toString(16)}").mkString(" ")
}
