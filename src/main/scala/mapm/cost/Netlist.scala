package mapm.cost

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}
import mapm.MapmError
import scala.collection.mutable

/** One flat module of library cells: what yosys `write_json` gives after synthesis to a Liberty
  * library (see [[Netlist.read]]).
  *
  * Nets are dense indices `0 until netCount`, one per distinct bit of the module. Net
  * [[Netlist.Zero]] is the constant 0 (yosys `"0"`, and also `"x"` and `"z"`), net
  * [[Netlist.One]] the constant 1.
  *
  * @param ports the module ports; yosys `splitnets -ports` leaves one port per bit, `a[0]`,
  *   `a[1]` ...: those are grouped back into one bus port `a` (bit `k` is the `k`-th lowest index)
  * @param cells the cell instances
  * @param names the named wires (yosys `netnames`), hidden (`$`-named) ones included
  */
final case class Netlist(top: String, ports: IndexedSeq[Netlist.Port], cells: IndexedSeq[Netlist.Instance], names: IndexedSeq[Netlist.NetName], netCount: Int) {
  import Netlist._

  /** The port called `name` (a bus name for split ports). */
  def port(name: String): Option[Port] = ports.find(_.name == name)

  /** The bit names of each net: the port bits and wire bits on it, ports first, visible wires
    * before hidden ones.
    */
  lazy val bitNames: IndexedSeq[Seq[String]] = {
    val out = Array.fill(netCount)(Vector.empty[String])
    for (p <- ports; (n, b) <- p.nets.zip(p.bitNames) if !out(n).contains(b)) out(n) :+= b
    for (w <- names.sortBy(_.hidden); (n, b) <- w.nets.zip(w.bitNames) if !out(n).contains(b)) out(n) :+= b
    out.toIndexedSeq
  }

  /** A short description of net `net` for messages: its first name, else its index. */
  def describe(net: Int): String = bitNames(net).headOption.getOrElse(s"#$net")

  /** The library cell of each instance; a [[MapmError]] for a type the library lacks. */
  def libraryCells(lib: Liberty.Library): IndexedSeq[Liberty.Cell] = cells.map { c =>
    lib.cells.getOrElse(c.cellType, MapmError.fail(s"cell type ${c.cellType} of instance ${c.name} is not in library ${lib.name}"))
  }

  /** The total area of the cells, split into sequential (cells with an `ff` or `latch` group)
    * and combinational, with the number of instances of each cell type.
    */
  def area(lib: Liberty.Library): Area = {
    val libCells = libraryCells(lib)
    val sequential = libCells.filter(_.isSequential).map(_.area).sum
    val combinational = libCells.filterNot(_.isSequential).map(_.area).sum
    Area(sequential + combinational, sequential, combinational, cells.groupBy(_.cellType).map { case (t, cs) => t -> cs.size })
  }

  /** What drives each net: a constant, an input (or inout) port bit, a cell output pin, or
    * nothing. A [[MapmError]] when a net has two drivers.
    */
  def drivers(lib: Liberty.Library): IndexedSeq[Driver] = {
    val out = Array.fill[Driver](netCount)(Driver.Undriven)
    out(Zero) = Driver.Constant
    out(One) = Driver.Constant
    def drive(net: Int, d: Driver): Unit = {
      if (out(net) != Driver.Undriven)
        MapmError.fail(s"net ${describe(net)} of module $top has two drivers: ${out(net)} and $d")
      out(net) = d
    }
    for (p <- ports if p.direction != Liberty.Direction.Output; (n, b) <- p.nets.zip(p.bitNames)) drive(n, Driver.FromPort(b))
    for (((inst, cell), i) <- cells.zip(libraryCells(lib)).zipWithIndex; pin <- cell.pins
         if pin.direction == Liberty.Direction.Output || pin.direction == Liberty.Direction.Inout;
         n <- inst.pins.get(pin.name)) drive(n, Driver.FromPin(i, s"${inst.name}/${pin.name}"))
    out.toIndexedSeq
  }
}

/** Reading yosys JSON netlists, and the parts of a [[Netlist]]. */
object Netlist {
  /** The net of the constant 0. */
  val Zero = 0

  /** The net of the constant 1. */
  val One = 1

  /** A module port: `nets(k)` is bit `k` (LSB first), `bitNames(k)` its name in the written
    * Verilog netlist as OpenSTA sees it (`a[3]`, or `a` for a one-bit port).
    */
  final case class Port(name: String, direction: Liberty.Direction, nets: IndexedSeq[Int], bitNames: IndexedSeq[String]) {
    /** The number of bits. */
    def width: Int = nets.size
  }

  /** A cell instance: its name, library cell type, and the net on each connected pin. */
  final case class Instance(name: String, cellType: String, pins: Map[String, Int])

  /** A named wire: `nets(k)` is bit `k` (LSB first), called `bitNames(k)`. `hidden` for yosys
    * internal (`$`-named) wires.
    */
  final case class NetName(name: String, nets: IndexedSeq[Int], bitNames: IndexedSeq[String], hidden: Boolean)

  /** Cell area in library units (um^2): the total, its sequential and combinational parts, and
    * the number of instances of each cell type.
    */
  final case class Area(total: Double, sequential: Double, combinational: Double, counts: Map[String, Int])

  /** What drives a net (see [[Netlist.drivers]]). */
  sealed trait Driver

  /** The cases of [[Driver]]. */
  object Driver {
    /** The constant nets [[Zero]] and [[One]]. */
    case object Constant extends Driver

    /** Nothing drives the net. */
    case object Undriven extends Driver

    /** A top port bit, by its name as OpenSTA knows it (`a[3]`). */
    final case class FromPort(name: String) extends Driver {
      override def toString: String = s"port $name"
    }

    /** Output pin of instance `instance` (an index into [[Netlist.cells]]); `name` is the pin as
      * OpenSTA knows it, `instanceName/PIN`.
      */
    final case class FromPin(instance: Int, name: String) extends Driver {
      override def toString: String = s"pin $name"
    }
  }

  /** Reads the yosys JSON netlist in `path` (see [[parse]]). */
  def read(path: Path, top: Option[String] = None): Netlist = {
    if (!Files.isRegularFile(path)) MapmError.fail(s"cannot read netlist $path: no such file")
    val text =
      try new String(Files.readAllBytes(path), StandardCharsets.UTF_8)
      catch { case e: java.io.IOException => MapmError.fail(s"cannot read netlist $path: ${e.getMessage}") }
    parse(text, path.toString, top)
  }

  /** Parses yosys `write_json` output `text` (`source` names it in messages). The module is
    * `top` if given, else the one yosys marked top, else the only one that is not a blackbox.
    * The netlist must be flat and mapped: every cell connection one bit.
    */
  def parse(text: String, source: String, top: Option[String] = None): Netlist = {
    val json =
      try ujson.read(text)
      catch { case e: ujson.ParsingFailedException => MapmError.fail(s"$source: not JSON: ${e.getMessage}") }
    fromJson(json, source, top)
  }

  /** The module `top` (as in [[parse]]) of a yosys netlist already read as JSON; instances of
    * the types in `blackBoxes` (SRAM arrays) may have multi-bit pins, read one pin a bit. */
  def fromJson(json: ujson.Value, source: String, top: Option[String] = None, blackBoxes: Set[String] = Set.empty): Netlist = {
    val r = new YosysReader(source)
    val (name, module) = r.topModule(json, top)
    val m = r.obj(module, s"module $name")
    val ports = r.ports(m, name)
    val cells = r.cells(m, name, blackBoxes)
    val names = r.netNames(m, name)
    Netlist(name, groupSplitPorts(ports), cells, names, r.netCount)
  }

  /** Reading one yosys JSON netlist of `source`: typed access with one-line errors, and the nets
    * numbered densely from 2 as they are met (0 and 1 are the constants). */
  private final class YosysReader(source: String) {
    def bad(what: String): Nothing = MapmError.fail(s"$source: not a yosys netlist: $what")
    def obj(v: ujson.Value, what: String): mutable.Map[String, ujson.Value] =
      v.objOpt.getOrElse(bad(s"$what is not an object"))
    def field(o: mutable.Map[String, ujson.Value], key: String, what: String): ujson.Value =
      o.getOrElse(key, bad(s"$what has no '$key'"))
    def flag(o: mutable.Map[String, ujson.Value], key: String): Boolean = o.get(key).exists {
      case ujson.Str(s) => s.exists(_ != '0')
      case ujson.Num(n) => n != 0
      case _            => false
    }
    def int(o: mutable.Map[String, ujson.Value], key: String): Int =
      o.get(key).flatMap(_.numOpt).fold(0)(_.toInt)

    /** The module named `top`, else the one marked top, else the only non-black-box one. */
    def topModule(json: ujson.Value, top: Option[String]): (String, ujson.Value) = {
      val modules = obj(field(obj(json, "the file"), "modules", "the file"), "modules")
      def attributes(m: ujson.Value): mutable.Map[String, ujson.Value] =
        m.objOpt.flatMap(_.get("attributes")).flatMap(_.objOpt).getOrElse(mutable.Map.empty[String, ujson.Value])
      val designs = modules.filterNot { case (_, m) => flag(attributes(m), "blackbox") }
      top match {
        case Some(t) => t -> modules.getOrElse(t, MapmError.fail(s"$source: no module $t (modules: ${modules.keys.mkString(", ")})"))
        case None =>
          designs.filter { case (_, m) => flag(attributes(m), "top") }.toSeq match {
            case Seq(one) => one
            case _ if designs.size == 1 => designs.head
            case _ => MapmError.fail(s"$source: ${designs.size} modules (${designs.keys.mkString(", ")}); name the top one")
          }
      }
    }

    val dense = mutable.HashMap.empty[Int, Int]
    def net(bit: ujson.Value, what: String): Int = bit match {
      case ujson.Num(id) => dense.getOrElseUpdate(id.toInt, dense.size + 2)
      case ujson.Str("1") => One
      case ujson.Str("0") | ujson.Str("x") | ujson.Str("z") => Zero
      case other => bad(s"bad bit $other in $what")
    }
    /** The nets of a port or wire, and the names of its bits as a Verilog reader sees them. */
    def bits(o: mutable.Map[String, ujson.Value], wire: String): (IndexedSeq[Int], IndexedSeq[String]) = {
      val nets = field(o, "bits", wire).arrOpt.getOrElse(bad(s"bits of $wire are not a list")).map(net(_, wire)).toIndexedSeq
      val offset = int(o, "offset")
      val width = nets.size
      val names =
        if (width == 1 && (offset == 0 || wire.endsWith(s"[$offset]"))) IndexedSeq(wire)
        else (0 until width).map(k => s"$wire[${if (flag(o, "upto")) offset + width - 1 - k else offset + k}]")
      (nets, names)
    }

    /** Nets numbered so far, the two constants included. */
    def netCount: Int = dense.size + 2

    /** The ports of module `name` (`m`), one-bit ports not yet grouped. */
    def ports(m: mutable.Map[String, ujson.Value], name: String): Seq[Port] =
    obj(field(m, "ports", s"module $name"), s"ports of $name").toSeq.map { case (p, v) =>
        val o = obj(v, s"port $p")
        val direction = field(o, "direction", s"port $p").strOpt match {
          case Some("input")  => Liberty.Direction.Input
          case Some("output") => Liberty.Direction.Output
          case Some("inout")  => Liberty.Direction.Inout
          case other          => bad(s"bad direction $other of port $p")
        }
        val (nets, names) = bits(o, p)
        Port(p, direction, nets, names)
      }

    /** The instances of module `name`: library cells, and black boxes of the types in
      * `blackBoxes`, whose multi-bit pins become one pin a bit (`R0_addr[3]`). */
    def cells(m: mutable.Map[String, ujson.Value], name: String, blackBoxes: Set[String]): IndexedSeq[Instance] =
    obj(m.getOrElse("cells", ujson.Obj()), s"cells of $name").toIndexedSeq.map { case (c, v) =>
        val o = obj(v, s"cell $c")
        val cellType = field(o, "type", s"cell $c").strOpt.getOrElse(bad(s"type of cell $c is not a string"))
        val pins = obj(field(o, "connections", s"cell $c"), s"connections of cell $c").toSeq.flatMap { case (pin, conn) =>
          conn.arrOpt.getOrElse(bad(s"connection $pin of cell $c is not a list")).toSeq match {
            case Seq()    => Nil
            case Seq(bit) => Seq(pin -> net(bit, s"cell $c"))
            case more if blackBoxes(cellType) => more.zipWithIndex.map { case (bit, k) => s"$pin[$k]" -> net(bit, s"cell $c") }
            case more =>
              MapmError.fail(s"$source: pin $pin of cell $c ($cellType) connects ${more.size} bits; expected a flat netlist of library cells")
          }
        }
        Instance(c, cellType, pins.toMap)
      }

    /** The named wires of module `name`, with the names of their bits. */
    def netNames(m: mutable.Map[String, ujson.Value], name: String): IndexedSeq[NetName] =
    obj(m.get("netnames").filterNot(_.isNull).getOrElse(ujson.Obj()), s"netnames of $name").toIndexedSeq.map { case (w, v) =>
        val o = obj(v, s"netname $w")
        val (nets, bitNames) = bits(o, w)
        NetName(w, nets, bitNames, flag(o, "hide_name"))
      }
  }

  /** Groups one-bit ports named `base[index]` (what `splitnets -ports` leaves) into one port
    * `base`, bit `k` being the `k`-th lowest index, unless a port `base` exists already.
    */
  private def groupSplitPorts(ports: Seq[Port]): IndexedSeq[Port] = {
    val Indexed = """(.+)\[(\d+)\]""".r
    val taken = ports.map(_.name).toSet
    def busOf(p: Port): Option[(String, Int)] = p.name match {
      case Indexed(base, index) if p.width == 1 && !taken(base) => Some(base -> index.toInt)
      case _ => None
    }
    val out = mutable.ArrayBuffer.empty[Port]
    val buses = mutable.LinkedHashMap.empty[String, mutable.ArrayBuffer[(Int, Port)]]
    for (p <- ports) busOf(p) match {
      case Some((base, index)) =>
        if (!buses.contains(base)) out += Port(base, p.direction, IndexedSeq.empty, IndexedSeq.empty) // keeps the position
        buses.getOrElseUpdate(base, mutable.ArrayBuffer.empty) += index -> p
      case None => out += p
    }
    out.map { p =>
      buses.get(p.name) match {
        case Some(members) =>
          val sorted = members.sortBy(_._1).map(_._2)
          if (sorted.exists(_.direction != p.direction)) MapmError.fail(s"split port ${p.name} has bits of different directions")
          Port(p.name, p.direction, sorted.map(_.nets.head).toIndexedSeq, sorted.map(_.bitNames.head).toIndexedSeq)
        case None => p
      }
    }.toIndexedSeq
  }
}
