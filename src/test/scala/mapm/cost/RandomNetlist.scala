package mapm.cost

import scala.collection.mutable.ArrayBuffer
import scala.util.Random

/** Random flat netlists of OSU 0.18 um cells, and a plain per-lane reference simulation of them
  * that uses [[OsuTruth]] (not the Liberty functions) and evaluates cells in creation order.
  */
object RandomNetlist {
  /** A random netlist; `creationOrder` lists its combinational instances in an order where each
    * comes after the drivers of its inputs (the netlist's own instance order is shuffled).
    */
  final case class Generated(netlist: Netlist, creationOrder: IndexedSeq[Int])

  /** The combinational cell types it draws from. */
  val combinationalTypes: IndexedSeq[String] = OsuTruth.inputs.keys.toIndexedSeq.sorted

  /** A netlist with input port `in` (`inputs` bits), clock port `clock`, `flops` flip-flops of
    * `flopTypes`, `cells` combinational cells, and output port `out` on the last `outputs` nets
    * made. Cell inputs come mostly from recent nets (deep logic), sometimes constants.
    */
  def apply(cells: Int, flops: Int, inputs: Int, outputs: Int, flopTypes: Seq[String], rnd: Random): Generated = {
    val clock = 2
    var nextNet = 3
    def newNet(): Int = { nextNet += 1; nextNet - 1 }
    val inNets = IndexedSeq.fill(inputs)(newNet())
    val flopQ = IndexedSeq.fill(flops)(newNet())
    val pool = ArrayBuffer.empty[Int] ++ inNets ++ flopQ
    def pick(): Int =
      if (rnd.nextInt(50) == 0) rnd.nextInt(2) // a constant
      else if (rnd.nextInt(10) < 7) pool(pool.size - 1 - rnd.nextInt(math.min(pool.size, 40)))
      else pool(rnd.nextInt(pool.size))
    val instances = ArrayBuffer.empty[Netlist.Instance]
    for (k <- 0 until cells) {
      val t = combinationalTypes(rnd.nextInt(combinationalTypes.size))
      val ins = OsuTruth.inputs(t).map(_ -> pick())
      val outs = OsuTruth.outputs(t).filter(p => p == "Y" || p == "YC" || rnd.nextInt(10) > 0).map(_ -> newNet())
      pool ++= outs.map(_._2)
      instances += Netlist.Instance(s"c$k", t, (ins ++ outs).toMap)
    }
    for ((q, k) <- flopQ.zipWithIndex) {
      val t = flopTypes(rnd.nextInt(flopTypes.size))
      val controls = if (t == "DFFSR") Seq("R" -> pick(), "S" -> pick()) else Seq.empty
      instances += Netlist.Instance(s"f$k", t, (Seq("CLK" -> clock, "D" -> pick(), "Q" -> q) ++ controls).toMap)
    }
    val shuffled = rnd.shuffle(instances.indices.toIndexedSeq)
    val position = shuffled.zipWithIndex.toMap
    val outNets = pool.takeRight(outputs).toIndexedSeq
    val ports = IndexedSeq(
      Netlist.Port("clock", Liberty.Direction.Input, IndexedSeq(clock), IndexedSeq("clock")),
      Netlist.Port("in", Liberty.Direction.Input, inNets, inNets.indices.map(i => s"in[$i]")),
      Netlist.Port("out", Liberty.Direction.Output, outNets, outNets.indices.map(i => s"out[$i]")))
    Generated(Netlist("random", ports, shuffled.map(instances), IndexedSeq.empty, nextNet), (0 until cells).map(position))
  }

  /** The reference simulation of `g` in 64 lanes, with [[GateSim]]'s documented cycle: settle,
    * rising-edge flops load (DFFSR: 0 if R is low, else 1 if S is low, else D), settle,
    * falling-edge flops load.
    */
  final class Reference(g: Generated) {
    private val netlist = g.netlist
    private val value = Array.ofDim[Boolean](64, netlist.netCount)
    private val flops = netlist.cells.indices.filter(i => netlist.cells(i).cellType.startsWith("DFF"))
    private val state = Array.ofDim[Boolean](64, netlist.cells.size)
    for (lane <- 0 until 64) value(lane)(Netlist.One) = true

    /** Sets net `net` in lane `lane`. */
    def set(net: Int, lane: Int, v: Boolean): Unit = value(lane)(net) = v

    /** Net `net` in all lanes, as [[GateSim.netLanes]] gives it. */
    def lanes(net: Int): Long = (0 until 64).foldLeft(0L)((acc, l) => if (value(l)(net)) acc | (1L << l) else acc)

    /** Evaluates flop outputs, then every combinational cell in creation order. */
    def settle(): Unit = for (lane <- 0 until 64) {
      val v = value(lane)
      for (f <- flops) v(netlist.cells(f).pins("Q")) = state(lane)(f)
      for (i <- g.creationOrder) {
        val c = netlist.cells(i)
        for (out <- OsuTruth.outputs(c.cellType); net <- c.pins.get(out))
          v(net) = OsuTruth.functions((c.cellType, out))(pin => v(c.pins(pin)))
      }
    }

    /** One clock cycle. */
    def step(): Unit = {
      def load(types: Set[String]): Unit = for (lane <- 0 until 64) {
        val v = value(lane)
        val next = flops.filter(f => types(netlist.cells(f).cellType)).map { f =>
          val p = netlist.cells(f).pins
          f -> (if (p.contains("R") && !v(p("R"))) false else if (p.contains("S") && !v(p("S"))) true else v(p("D")))
        }
        for ((f, s) <- next) state(lane)(f) = s
      }
      settle()
      load(Set("DFFPOSX1", "DFFSR"))
      settle()
      load(Set("DFFNEGX1"))
    }
  }
}
