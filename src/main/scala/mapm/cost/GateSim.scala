package mapm.cost

import mapm.MapmError
import scala.annotation.switch
import scala.collection.mutable

/** A cycle-based, zero-delay, 64-lane bit-parallel simulator of a gate-level [[Netlist]], the
  * cells evaluated by their [[Liberty]] functions; it also counts switching activity per net.
  *
  * '''Lanes.''' Every net holds a `Long`: bit `l` is its value in lane `l`, 64 independent
  * simulations of the same netlist run at once. Lanes `0 until lanes` are the ones in use: only
  * they count toward activity (all 64 are simulated regardless).
  *
  * '''Cells.''' Combinational cells are levelized (a combinational loop is a [[MapmError]] naming
  * cells on it) and each output `function` compiled to a few two-input word operations; a
  * settle runs the whole flat program once. Flip-flops (`ff` groups) hold their state variables;
  * their outputs are functions of them like any cell output. All flip-flops must be clocked by
  * the one clock input port `clock`, directly (`clocked_on` a clock pin, rising edge, or its
  * complement, falling edge). `clear`/`preset` are applied when the flop is clocked, not
  * asynchronously: at an active edge the new state is 0 if `clear` holds, 1 if `preset` holds,
  * `clear_preset_var1` (`L`, `H`, `N` keep, `T` toggle, `X` taken as 0) if both hold, else
  * `next_state` (the inverted state likewise, `clear_preset_var2`, else the complement).
  * All state starts at 0 in every lane. Latches, tristate outputs and inout ports are refused
  * (a [[MapmError]]), as are cells the library lacks. A net nothing drives stays 0.
  *
  * '''Clock gates.''' A rising-edge flip-flop may also be clocked by a gated clock ([[ClockGates]]: a
  * latch open while the clock is low, ANDed with the clock, the only latches allowed): it loads
  * at a step only in the lanes where the gate's enable, settled in that cycle, is 1 (and its
  * parent gate's, for a gate behind a gate). The gated clock's activity is 2 and its duty 0.5 in
  * the enabled cycle-lanes, 0 in the others; [[gateDuty]] gives each gate's enabled fraction.
  *
  * '''Cycles.''' [[poke]] sets input ports; [[step]] is one clock cycle: combinational logic
  * settles with the inputs as poked and the current state (the values of the cycle, which
  * activity counts), then all rising-edge flops load at once; if the netlist has falling-edge
  * flops, logic settles again and they load. So inputs poked before `step()` are the inputs of
  * that cycle, as in a Verilator testbench that sets inputs and then raises the clock. [[peek]]
  * settles first if anything changed, so after `step()` it sees the new state with the inputs
  * still poked. The clock net itself stays 0 in the logic: it may feed only flip-flop clock pins.
  *
  * '''Activity.''' At each `step()`, the settled value of every net is compared with the one of
  * the step before: [[toggles]] sums the lanes that changed, [[highCount]] the lanes at 1, over
  * [[cycles]] steps since construction or [[resetActivity]] (the first step ever has no step
  * before, so it counts no toggles). [[activity]] is toggles per cycle and lane, [[duty]] the
  * fraction of cycle-lanes at 1; for the clock net they are 2 and 0.5.
  *
  * @param clock the name of the clock input port (needed only when the netlist has flip-flops)
  * @param lanes the number of lanes in use, 1 to 64
  */
final class GateSim(val netlist: Netlist, library: Liberty.Library, clock: String = "clock", val lanes: Int = 64) {
  import GateSim._
  import CellPrograms._

  MapmError.check(lanes >= 1 && lanes <= 64, s"gate simulation lanes must be 1 to 64, not $lanes")

  private val libCells = netlist.libraryCells(library)
  private val drivers = netlist.drivers(library)
  private val netCount = netlist.netCount

  for (p <- netlist.ports if p.direction == Liberty.Direction.Inout)
    MapmError.fail(s"gate simulation of ${netlist.top}: inout port ${p.name} is not supported")

  /** The clock net, or -1 when the netlist has no port `clock`. */
  private val clockNet: Int = netlist.port(clock) match {
    case Some(p) if p.direction == Liberty.Direction.Input && p.width == 1 => p.nets.head
    case Some(p) => MapmError.fail(s"gate simulation of ${netlist.top}: clock port $clock must be a one-bit input, not ${p.width} bits ${p.direction}")
    case None    => -1
  }

  /** The clock network: inverters of the clock and clock gates, which the settle leaves out. */
  val clockNetwork: ClockGates.Network = ClockGates.find(netlist, libCells, clockNet)
  private val gates = clockNetwork.gates
  /** Each gate's enabled lanes in the current step, and the enabled cycle-lanes counted. */
  private val gateMask = new Array[Long](gates.size)
  private val gateEnabled = new Array[Long](gates.size)
  private val gateIndex: Map[Int, Int] = gates.map(_.held).zipWithIndex.toMap

  /** The compiled library cells, by name, as instances need them. */
  private val programs = mutable.HashMap.empty[String, CellProgram]
  private def program(cell: Liberty.Cell): CellProgram = programs.getOrElseUpdate(cell.name, CellPrograms.compile(cell, netlist.top))

  /** The instances in evaluation order (see [[evaluationOrder]]). */
  private val order: Array[Int] = evaluationOrder()

  /** The flip-flop instances, in netlist order, and their state slots (4 each, from `stateBase`). */
  private val flops: IndexedSeq[Int] = netlist.cells.indices.filter(i => libCells(i).ff.isDefined)
  private val scratchBase = netCount
  private val stateBase = scratchBase + netlist.cells.indices.filterNot(clockNetwork.cells).map(i => program(libCells(i)).temps).maxOption.getOrElse(0)
  private val flopSlot: Map[Int, Int] = flops.zipWithIndex.map { case (inst, k) => inst -> (stateBase + 4 * k) }.toMap

  /** Every slot's 64 lanes: the nets (`0 until netCount`), the scratch slots, the flop states. */
  private val values = new Array[Long](stateBase + 4 * flops.size)
  values(Netlist.One) = -1L
  for (base <- flopSlot.values) values(base + StateInverted) = -1L // state 0, inverted state 1

  /** The settle program: all cell outputs in evaluation order, 4 ints per instruction. */
  private val settleCode: Array[Int] = {
    val out = new mutable.ArrayBuilder.ofInt
    for (i <- order; (pin, code) <- program(libCells(i)).outputs if netlist.cells(i).pins.contains(pin)) emit(code, i, out)
    out.result()
  }

  /** Per clock edge: the programs that compute the flops' next state, and the (from, to) slot
    * pairs that then load it (those of the flops behind each gate apart).
    */
  private val (riseCode, riseLoad, fallCode, fallLoad, gatedLoad) = edgePrograms()

  /** Whether inputs or state changed since the last settle. */
  private var dirty = true
  // activity: the previous step's values, the toggle and high counts, by net
  private val previous = new Array[Long](netCount)
  private val toggleCounts = new Array[Long](netCount)
  private val highCounts = new Array[Long](netCount)
  private var sampledBefore = false
  private var sampledCycles = 0L
  private val laneMask = if (lanes == 64) -1L else (1L << lanes) - 1

  /** Ports by name, with the nets of their bits. */
  private val allPorts: Map[String, (Netlist.Port, Array[Int])] = netlist.ports.map(p => p.name -> (p -> p.nets.toArray)).toMap
  private val inputPorts = allPorts.filter { case (name, (p, _)) => p.direction == Liberty.Direction.Input && name != clock }

  // ---------------------------------------------------------------- compilation

  /** The net on pin `pin` of instance `inst`. */
  private def pinNet(pin: String, inst: Int): Int = netlist.cells(inst).pins.getOrElse(pin, MapmError.fail(
    s"gate simulation of ${netlist.top}: pin $pin of ${netlist.cells(inst).name} (${netlist.cells(inst).cellType}) is not connected"))

  /** The slot of a program reference for instance `inst`. */
  private def slot(ref: Ref, inst: Int): Int = ref match {
    case PinRef(pin)  => pinNet(pin, inst)
    case TempRef(k)   => scratchBase + k
    case ConstRef(b)  => if (b) Netlist.One else Netlist.Zero
    case StateRef(k)  => flopSlot(inst) + k
  }

  /** Appends `code` of instance `inst` to `out` as slot numbers. */
  private def emit(code: Seq[Instr], inst: Int, out: mutable.ArrayBuilder.ofInt): Unit =
    for (i <- code) { out += i.op; out += slot(i.dst, inst); out += slot(i.a, inst); out += slot(i.b, inst) }

  /** Orders all instances so that each comes after the drivers of the nets its outputs read
    * (flip-flop outputs read only their state): by logic level, and within a level by cell type,
    * so that the settle program runs long stretches of the same operations (which the processor
    * predicts well: about 1.4 times faster than a depth-first order). A [[MapmError]] names cells
    * on a combinational loop, or one the clock feeds.
    */
  private def evaluationOrder(): Array[Int] = {
    val n = netlist.cells.size
    val driverOf = drivers.map {
      case Netlist.Driver.FromPin(inst, _) if !clockNetwork.cells(inst) => inst
      case _                               => -1
    }.toArray
    val reads: Array[Array[Int]] = Array.tabulate(n) { i =>
      if (clockNetwork.cells(i)) Array.emptyIntArray
      else {
        val outputs = program(libCells(i)).outputs.filter { case (pin, _) => netlist.cells(i).pins.contains(pin) }
        outputs.flatMap(_._2).flatMap(instr => Seq(instr.a, instr.b)).collect { case PinRef(pin) => pinNet(pin, i) }.distinct.toArray
      }
    }
    for (i <- 0 until n if reads(i).exists(clockNetwork.nets))
      MapmError.fail(s"gate simulation of ${netlist.top}: the clock $clock feeds logic (${netlist.cells(i).name}, ${netlist.cells(i).cellType}); only flip-flop clock pins and clock gates may read it")
    val (fresh, open, finished) = (0, 1, 2)
    val mark = Array.fill(n)(fresh)
    val order = new mutable.ArrayBuilder.ofInt // depth-first: after the instances it reads
    val stack = new Array[Int](n) // instances being visited, each waiting on its next input
    val nextInput = new Array[Int](n)
    for (root <- 0 until n if mark(root) == fresh && !clockNetwork.cells(root)) {
      var depth = 1
      stack(0) = root
      nextInput(0) = 0
      mark(root) = open
      while (depth > 0) {
        val at = stack(depth - 1)
        if (nextInput(depth - 1) < reads(at).length) {
          val d = driverOf(reads(at)(nextInput(depth - 1)))
          nextInput(depth - 1) += 1
          if (d >= 0 && mark(d) == fresh) {
            stack(depth) = d
            nextInput(depth) = 0
            mark(d) = open
            depth += 1
          } else if (d >= 0 && mark(d) == open) {
            val loop = stack.slice(stack.indexOf(d), depth).toSeq
            val shown = loop.take(4).map(i => s"${netlist.cells(i).name} (${netlist.cells(i).cellType})")
            val more = if (loop.size > 4) s" and ${loop.size - 4} more" else ""
            MapmError.fail(s"gate simulation of ${netlist.top}: combinational loop through ${shown.mkString(", ")}$more")
          }
        } else {
          mark(at) = finished
          order += at
          depth -= 1
        }
      }
    }
    val topological = order.result()
    val level = new Array[Int](n)
    for (i <- topological; net <- reads(i) if driverOf(net) >= 0) level(i) = math.max(level(i), level(driverOf(net)) + 1)
    val typeRank = netlist.cells.map(_.cellType).distinct.sorted.zipWithIndex.toMap
    topological.sortBy(i => (level(i).toLong << 32) | typeRank(netlist.cells(i).cellType))
  }

  /** The lanes in which gate `k` (and every gate above it) lets the clock through this cycle. */
  private def enableGates(): Unit = for (k <- gates.indices) {
    val g = gates(k)
    val parent = gateIndex.get(g.parent).map(gateMask).getOrElse(-1L)
    gateMask(k) = values(g.enable) & parent
    values(g.held) = values(g.enable) // the latch ends the cycle holding the enable
  }

  /** The next-state programs and load pairs of the rising-edge and falling-edge flops, and of
    * the flops behind each gate. */
  private def edgePrograms(): (Array[Int], Array[Int], Array[Int], Array[Int], Array[Array[Int]]) = {
    val code = Map(true -> new mutable.ArrayBuilder.ofInt, false -> new mutable.ArrayBuilder.ofInt)
    val load = Map(true -> new mutable.ArrayBuilder.ofInt, false -> new mutable.ArrayBuilder.ofInt)
    val gated = Array.fill(gates.size)(new mutable.ArrayBuilder.ofInt)
    for (inst <- flops) {
      val prog = program(libCells(inst))
      val (clockPin, rising) = prog.edge.get
      val cellName = netlist.cells(inst).name
      if (clockNet < 0)
        MapmError.fail(s"gate simulation of ${netlist.top}: flip-flop $cellName needs the clock, but there is no input port $clock")
      val net = clockNetwork.clockOf.getOrElse(pinNet(clockPin, inst), -2)
      val gate = gateIndex.get(net)
      if (net != clockNet && gate.isEmpty)
        MapmError.fail(s"gate simulation of ${netlist.top}: flip-flop $cellName is clocked by ${netlist.describe(pinNet(clockPin, inst))}, not by the clock port $clock or a clock gate")
      if (gate.isDefined && !rising)
        MapmError.fail(s"gate simulation of ${netlist.top}: flip-flop $cellName loads on the falling edge of a gated clock")
      emit(prog.next, inst, code(rising))
      val base = flopSlot(inst)
      val to = gate.map(gated).getOrElse(load(rising))
      to ++= Array(base + NextState, base + State)
      if (prog.next.exists(_.dst == StateRef(NextInverted))) to ++= Array(base + NextInverted, base + StateInverted)
    }
    (code(true).result(), load(true).result(), code(false).result(), load(false).result(), gated.map(_.result()))
  }

  // ---------------------------------------------------------------- running

  /** Runs a program of 4-int instructions (op, destination, a, b) over the slots. */
  private def run(code: Array[Int]): Unit = {
    val v = values
    val end = code.length
    var pc = 0
    while (pc < end) {
      val a = v(code(pc + 2))
      val b = v(code(pc + 3))
      v(code(pc + 1)) = (code(pc): @switch) match {
        case OpBuf  => a
        case OpNot  => ~a
        case OpAnd  => a & b
        case OpOr   => a | b
        case OpXor  => a ^ b
        case OpNand => ~(a & b)
        case OpNor  => ~(a | b)
        case OpXnor => ~(a ^ b)
        case OpAndN => a & ~b
        case OpOrN  => a | ~b
      }
      pc += 4
    }
  }

  /** Copies each (from, to) slot pair: the flops load their computed next state. */
  private def load(pairs: Array[Int]): Unit = {
    var k = 0
    while (k < pairs.length) { values(pairs(k + 1)) = values(pairs(k)); k += 2 }
  }

  /** As [[load]], in the lanes of `mask` only. */
  private def load(pairs: Array[Int], mask: Long): Unit = {
    var k = 0
    while (k < pairs.length) { values(pairs(k + 1)) = (values(pairs(k)) & mask) | (values(pairs(k + 1)) & ~mask); k += 2 }
  }

  /** Settles the combinational logic if an input or the state changed since the last settle. */
  private def settle(): Unit = if (dirty) { run(settleCode); dirty = false }

  /** Counts toggles and high lanes of every net against the previous step. */
  private def sample(): Unit = {
    val (v, prev, toggled, high, mask, end) = (values, previous, toggleCounts, highCounts, laneMask, netCount)
    val compare = sampledBefore
    var net = 2
    while (net < end) {
      val now = v(net) & mask
      if (compare) toggled(net) += java.lang.Long.bitCount(now ^ prev(net))
      high(net) += java.lang.Long.bitCount(now)
      prev(net) = now
      net += 1
    }
    for (k <- gates.indices) gateEnabled(k) += java.lang.Long.bitCount(gateMask(k) & mask)
    sampledBefore = true
    sampledCycles += 1
  }

  /** Runs `n` clock cycles (see the class comment). */
  def step(n: Int = 1): Unit = for (_ <- 0 until n) {
    settle()
    enableGates()
    sample()
    run(riseCode)
    load(riseLoad)
    for (k <- gates.indices) load(gatedLoad(k), gateMask(k))
    dirty = true
    if (fallCode.nonEmpty) {
      settle()
      run(fallCode)
      load(fallLoad)
      dirty = true
    }
  }

  /** The input port `port` (not the clock) and its nets, or a [[MapmError]] listing the inputs. */
  private def inputPort(port: String): (Netlist.Port, Array[Int]) = inputPorts.getOrElse(port, {
    val hint = if (port == clock) "the clock is driven by step()" else s"inputs: ${inputPorts.keys.toSeq.sorted.mkString(", ")}"
    MapmError.fail(s"gate simulation of ${netlist.top}: no input port $port to poke ($hint)")
  })

  /** The port `port` and its nets, or a [[MapmError]] listing the ports. */
  private def anyPort(port: String): (Netlist.Port, Array[Int]) = allPorts.getOrElse(port,
    MapmError.fail(s"gate simulation of ${netlist.top}: no port $port (ports: ${allPorts.keys.toSeq.sorted.mkString(", ")})"))

  /** Fails unless `lane` is one of the 64. */
  private def checkLane(lane: Int): Unit = MapmError.check(lane >= 0 && lane < 64, s"gate simulation lane $lane is not 0 to 63")

  /** Sets input port `port` in lane `lane` to `value` (unsigned, below 2^width). */
  def poke(port: String, lane: Int, value: BigInt): Unit = {
    val (p, nets) = inputPort(port)
    checkLane(lane)
    MapmError.check(value >= 0 && value.bitLength <= p.width, s"gate simulation: $value does not fit the ${p.width} bits of input $port")
    val bit = 1L << lane
    for (k <- nets.indices) values(nets(k)) = if (value.testBit(k)) values(nets(k)) | bit else values(nets(k)) & ~bit
    dirty = true
  }

  /** Sets input port `port` in lanes `0 until laneValues.size` to `laneValues` (see [[poke]]). */
  def poke(port: String, laneValues: Seq[BigInt]): Unit = {
    MapmError.check(laneValues.size <= 64, s"gate simulation: ${laneValues.size} values for 64 lanes")
    for ((v, lane) <- laneValues.zipWithIndex) poke(port, lane, v)
  }

  /** Sets input port `port` of at most 64 bits in lane `lane` to `value`, unsigned (all 64 bits
    * for a 64-bit port; otherwise it must be below 2^width).
    */
  def pokeLong(port: String, lane: Int, value: Long): Unit = {
    val (p, nets) = inputPort(port)
    checkLane(lane)
    MapmError.check(p.width <= 64, s"gate simulation: input $port has ${p.width} bits; use poke")
    MapmError.check(p.width == 64 || (value >>> p.width) == 0, s"gate simulation: $value does not fit the ${p.width} bits of input $port")
    val bit = 1L << lane
    var k = 0
    while (k < nets.length) {
      values(nets(k)) = if (((value >>> k) & 1L) != 0) values(nets(k)) | bit else values(nets(k)) & ~bit
      k += 1
    }
    dirty = true
  }

  /** The value of port `port` (input or output) in lane `lane`, after settling. */
  def peek(port: String, lane: Int): BigInt = {
    val (_, nets) = anyPort(port)
    checkLane(lane)
    settle()
    nets.indices.foldLeft(BigInt(0))((acc, k) => if (((values(nets(k)) >>> lane) & 1L) != 0) acc.setBit(k) else acc)
  }

  /** The value of port `port` of at most 64 bits in lane `lane`, after settling. */
  def peekLong(port: String, lane: Int): Long = {
    val (p, nets) = anyPort(port)
    MapmError.check(p.width <= 64, s"gate simulation: port $port has ${p.width} bits; use peek")
    checkLane(lane)
    settle()
    var out = 0L
    var k = 0
    while (k < nets.length) { out |= ((values(nets(k)) >>> lane) & 1L) << k; k += 1 }
    out
  }

  /** The 64 lanes of net `net`, after settling. */
  def netLanes(net: Int): Long = { settle(); values(net) }

  // ---------------------------------------------------------------- activity

  /** The number of steps counted since construction or [[resetActivity]]. */
  def cycles: Long = sampledCycles

  /** The lanes in use in which `net` changed from one counted step to the next, summed over
    * the steps (the clock net: 0, see [[activity]]).
    */
  def toggles(net: Int): Long = toggleCounts(net)

  /** The lanes in use in which `net` was 1, summed over the counted steps. */
  def highCount(net: Int): Long = highCounts(net)

  /** The fraction of counted cycle-lanes in which gate `k` of [[clockNetwork]] let the clock
    * through (its enable and its parents' were 1); 0 before any step. */
  def gateDuty(k: Int): Double = if (sampledCycles == 0) 0.0 else gateEnabled(k).toDouble / (sampledCycles * lanes)

  /** The enabled fraction of the clock net `level` (the root's: 1). */
  private def levelDuty(level: Int): Double = gateIndex.get(level).map(gateDuty).getOrElse(1.0)

  /** Toggles of `net` per cycle and lane: for a net of the clock network that switches with a
    * clock ([[ClockGates.Network.levelOf]]), 2 times that clock's enabled fraction (2 for the
    * root clock); 0 before any step. */
  def activity(net: Int): Double = clockNetwork.levelOf.get(net).map(l => 2 * levelDuty(l)).getOrElse(
    if (sampledCycles == 0) 0.0 else toggles(net).toDouble / (sampledCycles * lanes))

  /** The fraction of counted cycle-lanes in which `net` was 1: half the enabled fraction for a
    * net that switches with a clock (0.5 for the root clock); 0 before any step. */
  def duty(net: Int): Double = clockNetwork.levelOf.get(net).map(l => 0.5 * levelDuty(l)).getOrElse(
    if (sampledCycles == 0) 0.0 else highCount(net).toDouble / (sampledCycles * lanes))

  /** Restarts the activity counts (to leave out reset and warm-up): the next step's toggles
    * still compare with the step before it.
    */
  def resetActivity(): Unit = {
    java.util.Arrays.fill(toggleCounts, 0L)
    java.util.Arrays.fill(highCounts, 0L)
    java.util.Arrays.fill(gateEnabled, 0L)
    sampledCycles = 0
  }

  /** The name OpenSTA knows for what drives `net`: `instance/PIN` or a port bit `a[3]`; None for
    * the constants and nets nothing drives.
    */
  def driverName(net: Int): Option[String] = drivers(net) match {
    case Netlist.Driver.FromPin(_, name) => Some(name)
    case Netlist.Driver.FromPort(name)   => Some(name)
    case _                               => None
  }

  /** The activity of every driven net, in net order: its driver's name, its bit names, the counts
    * and the ratios (see [[activity]], [[duty]]).
    */
  def activityReport: IndexedSeq[NetActivity] = (0 until netCount).flatMap { net =>
    driverName(net).map(d => NetActivity(net, d, netlist.bitNames(net), toggles(net), highCount(net), activity(net), duty(net)))
  }
}

/** The activity record and the compiled-program representation of [[GateSim]]. */
object GateSim {
  /** The switching activity of net `net` driven by `driver` (its OpenSTA pin or port name),
    * with its wire names.
    */
  final case class NetActivity(net: Int, driver: String, names: Seq[String], toggles: Long, high: Long, activity: Double, duty: Double)
}
