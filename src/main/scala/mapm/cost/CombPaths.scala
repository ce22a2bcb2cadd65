package mapm.cost

/** Combinational paths through a mapped netlist from its input ports to its output ports: the
  * paths that cross a part's boundary without a register and so join the timing of the part
  * before it to that of the part after it (docs/cost.md, "Paths between parts").
  *
  * A path runs through combinational library cells only. It stops at a cell with an `ff` or
  * `latch` group (a latch is taken as state: the only latches the design has are the clock
  * gates', whose output is a clock), and at any instance whose type is not a library cell (the
  * SRAM arrays kept as black boxes: their read data comes from a registered address, and nothing
  * in them is combinational from input to output). The clock and reset inputs are left out.
  */
object CombPaths {
  /** One combinational connection from input port `from` to output port `to` (ports by name,
    * buses whole), with an example of the bits it joins. */
  final case class Path(from: String, to: String, example: String) {
    override def toString: String = s"$from -> $to ($example)"
  }

  /** Inputs a path never starts from: the clock and the reset. */
  val NotStarts: Set[String] = Set("clock", "reset")

  /** The port a pin of a module instance belongs to (`a[3]` of port `a`). */
  private def portOf(pin: String): String = pin.indexOf('[') match { case -1 => pin; case k => pin.substring(0, k) }

  /** Every input-to-output combinational connection of `n`, by port, in port order. Instances
    * of the modules in `sub` (a hierarchical netlist's kept modules, read with their multi-bit
    * pins one a bit) pass from each input port to each output port that their entry pairs
    * (what [[of]] found for them, by port name); any other type that is not a library cell ends
    * a path. */
  def of(n: Netlist, lib: Liberty.Library, sub: Map[String, Seq[Path]] = Map.empty): Seq[Path] = {
    // The combinational cells' output nets, by each of their input nets.
    val fanout = Array.fill(n.netCount)(List.empty[Int])
    for (inst <- n.cells) lib.cells.get(inst.cellType) match {
      case Some(cell) if !cell.isSequential =>
        val outs = cell.outputs.flatMap(p => inst.pins.get(p.name))
        for (p <- cell.inputs; i <- inst.pins.get(p.name); o <- outs) fanout(i) = o :: fanout(i)
      case Some(_) => // a flip-flop or latch: the path ends
      case None => sub.get(inst.cellType) match {
        case Some(arcs) if arcs.nonEmpty =>
          val byPort = inst.pins.toSeq.groupBy { case (pin, _) => portOf(pin) }.map { case (port, ps) => port -> ps.map(_._2) }
          for ((from, to) <- arcs.map(a => (a.from, a.to)).distinct; i <- byPort.getOrElse(from, Nil); o <- byPort.getOrElse(to, Nil))
            fanout(i) = o :: fanout(i)
        case _ => // a black box (an SRAM array) or a module without paths: the path ends
      }
    }
    val outBits = Array.fill(n.netCount)(List.empty[(String, String)])
    for (p <- n.ports if p.direction == Liberty.Direction.Output; (net, b) <- p.nets.zip(p.bitNames)
         if net != Netlist.Zero && net != Netlist.One) outBits(net) = (p.name, b) :: outBits(net)
    val seen = Array.fill(n.netCount)(-1)
    val inputs = n.ports.filter(p => p.direction == Liberty.Direction.Input && !NotStarts(p.name))
    inputs.zipWithIndex.flatMap { case (port, k) =>
      val found = scala.collection.mutable.LinkedHashMap.empty[String, String]
      for ((start, bit) <- port.nets.zip(port.bitNames) if start != Netlist.Zero && start != Netlist.One && seen(start) != k) {
        seen(start) = k
        var stack = List(start)
        while (stack.nonEmpty) {
          val net = stack.head
          stack = stack.tail
          for ((o, ob) <- outBits(net) if !found.contains(o)) found(o) = s"$bit -> $ob"
          for (next <- fanout(net) if seen(next) != k) { seen(next) = k; stack = next :: stack }
        }
      }
      found.toSeq.map { case (o, ex) => Path(port.name, o, ex) }
    }
  }
}
