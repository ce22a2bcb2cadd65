package mapm.cost

import mapm.MapmError
import scala.collection.mutable

/** The clock network of a gate-level [[Netlist]]: the clock port, and the integrated clock gates
  * ([[mapm.util.ClockGate]] as synthesis maps it) that derive gated clocks from it.
  *
  * A gate is a latch, transparent while its parent clock is low, whose data input is the enable,
  * and logic that ANDs the parent clock with the latch's output: the gated clock. Synthesis may
  * map the AND to any cells (an AND, a NAND and an inverter ...) and give the latch's enable pin
  * the inverted clock (a latch open while its pin is high, as OSU's `LATCH`) or the clock itself
  * (one open while it is low). So each net the clock reaches is classified by its truth table
  * over the clock c of its gate level and the latch output h, composed through the cells' Liberty
  * functions: c or not c is that clock (a buffer, an inverter), h the latch, c and h a gated
  * clock, which is the clock of the next level (a gate behind a gate, as an SOA's stage gates
  * behind the SOM lane's SOA gate). Anything else a clock reaches, other than a flip-flop's clock
  * pin, is refused.
  *
  * In a cycle-based simulation a gated clock has a rising edge at the end of a cycle exactly when
  * its enable is 1 at the end of that cycle and its parent clock has the edge.
  */
object ClockGates {
  /** One gate: its latch's output `held` (which names the gate and its clock level), the clock
    * level it gates (`parent`: the root clock net or another gate's `held`) and its `enable` net
    * (the latch's data input). */
  final case class Gate(held: Int, parent: Int, enable: Int)

  /** The clock network: its cells (those on the clock's paths up to the flip-flops' clock pins);
    * `clockOf`, for each net that carries a clock as it is (the root, a buffered or a gated
    * clock), its level (the root clock net, or the gate's `held`); `levelOf`, for each net that
    * switches with a clock (those and their inverses, and the logic inside a gate), the level
    * whose edges it follows; and the gates, parents before children. */
  final case class Network(cells: Set[Int], clockOf: Map[Int, Int], levelOf: Map[Int, Int], gates: IndexedSeq[Gate]) {
    /** Every net of the network. */
    def nets: Set[Int] = levelOf.keySet ++ gates.map(_.held)
  }

  def empty(root: Int): Network =
    if (root < 0) Network(Set.empty, Map.empty, Map.empty, IndexedSeq.empty)
    else Network(Set.empty, Map(root -> root), Map(root -> root), IndexedSeq.empty)

  // Truth tables over (c, h): bit (c << 1 | h).
  private val C = 0xc
  private val NotC = 0x3
  private val H = 0xa
  private val CandH = 0x8
  private val NotCandH = 0x7
  private def value(table: Int, c: Boolean, h: Boolean): Boolean = ((table >> ((if (c) 2 else 0) | (if (h) 1 else 0))) & 1) != 0

  /** A net of the network: the clock level whose clock c its table reads, the latch output h it
    * may read (or -1), and its table. A function of c and h alone is one of the gated level's
    * clock: c and h is its clock, not (c and h) the clock inverted. */
  private final case class Node(level: Int, held: Int, table: Int)
  private def canonical(n: Node): Node =
    if (n.held >= 0 && n.table == CandH) Node(n.held, -1, C)
    else if (n.held >= 0 && n.table == NotCandH) Node(n.held, -1, NotC)
    else n

  /** Finds the network that grows from the clock net `root`; a [[MapmError]] names a cell that
    * reads a clock but is none of the above. */
  def find(netlist: Netlist, cells: IndexedSeq[Liberty.Cell], root: Int): Network = {
    if (root < 0) return empty(root)
    val readers = mutable.HashMap.empty[Int, mutable.ArrayBuffer[(Int, String)]] // net -> (instance, input pin)
    for ((c, i) <- netlist.cells.zipWithIndex; (pin, net) <- c.pins if cells(i).pin(pin).exists(_.direction == Liberty.Direction.Input))
      readers.getOrElseUpdate(net, mutable.ArrayBuffer.empty) += ((i, pin))
    def inputPins(i: Int): Seq[(String, Int)] = cells(i).inputs.flatMap(p => netlist.cells(i).pins.get(p.name).map(p.name -> _))
    def output(i: Int): (Liberty.Pin, Int) = {
      val outs = cells(i).outputs.flatMap(o => netlist.cells(i).pins.get(o.name).map(o -> _))
      if (outs.size != 1) refuse(netlist, i, "a clock reaches a cell with other than one connected output")
      outs.head
    }

    val nodes = mutable.HashMap(root -> Node(root, -1, C))
    val network = mutable.LinkedHashSet.empty[Int]
    val gates = mutable.ArrayBuffer.empty[Gate]
    val waiting = mutable.LinkedHashSet.empty[Int] // cells with inputs outside the network so far
    val queue = mutable.Queue(root)
    def add(net: Int, node: Node): Unit = { nodes(net) = canonical(node); queue += net }

    while (queue.nonEmpty) {
      val net = queue.dequeue()
      for ((i, pin) <- readers.getOrElse(net, Seq.empty) if !network(i)) {
        val cell = cells(i)
        if (cell.ff.exists(_.clockedOn.vars.contains(pin))) () // a flip-flop's clock pin: GateSim checks it
        else if (cell.latch.exists(!_.enable.exists(_.vars.contains(pin)))) refuse(netlist, i, "a clock reaches a latch's data")
        else if (cell.latch.isDefined) {
          val l = cell.latch.get
          val n = nodes(net)
          val open = (c: Boolean) => l.enable.exists(e => e.vars == Set(pin) && e.eval(_ => value(n.table, c, h = false)))
          if (n.held >= 0 || (n.table != C && n.table != NotC) || !open(false) || open(true))
            refuse(netlist, i, "a latch on a clock is not open exactly while its clock is low")
          val data = l.dataIn.map(_.vars).getOrElse(Set.empty)
          if (data.size != 1) refuse(netlist, i, "a clock-gate latch without one data pin")
          val (q, held) = output(i)
          if (!q.function.contains(BoolExpr.Var(l.state))) refuse(netlist, i, "a clock-gate latch whose output is not its state")
          network += i
          gates += Gate(held, n.level, netlist.cells(i).pins(data.head))
          add(held, Node(n.level, held, H))
        } else if (cell.ff.isDefined) refuse(netlist, i, "a clock reaches a flip-flop's data")
        else {
          val ins = inputPins(i)
          if (!ins.forall(p => nodes.contains(p._2))) waiting += i
          else {
            val from = ins.map(p => nodes(p._2))
            val levels = from.map(_.level).distinct
            val helds = from.map(_.held).filter(_ >= 0).distinct
            if (levels.size != 1 || helds.size > 1) refuse(netlist, i, "a cell combines clocks of different gates")
            val (pinOut, out) = output(i)
            val f = pinOut.function.getOrElse(refuse(netlist, i, "a clock reaches a cell without an output function"))
            val table = (0 until 4).filter { k =>
              val (c, h) = ((k & 2) != 0, (k & 1) != 0)
              f.eval(ins.map { case (name, n) => name -> value(nodes(n).table, c, h) }.toMap)
            }.map(1 << _).sum
            network += i
            waiting -= i
            add(out, Node(levels.head, helds.headOption.getOrElse(-1), table))
          }
        }
      }
    }
    for (i <- waiting if !network(i)) refuse(netlist, i, "a clock feeds logic")
    val clockOf = nodes.collect { case (n, node) if node.held < 0 && node.table == C => n -> node.level }
    val levelOf = nodes.collect { case (n, node) if node.table != H => n -> node.level }
    Network(network.toSet, clockOf.toMap, levelOf.toMap, gates.toIndexedSeq)
  }

  private def refuse(netlist: Netlist, i: Int, why: String): Nothing =
    MapmError.fail(s"gate simulation of ${netlist.top}: $why (${netlist.cells(i).name}, ${netlist.cells(i).cellType}); " +
      "only flip-flop clock pins and clock gates (a latch open while the clock is low, ANDed with it) may read a clock")
}
