package mapm.cost

import mapm.MapmError

/** The cells of each module of a hierarchical yosys JSON netlist, by module: its own library
  * cells (area from the Liberty file, sequential part apart) and the submodules it instantiates.
  * The whole-configuration cost multiplies each module's own figures by its instance count.
  */
object ModuleCells {
  /** One module's own cells. `children` lists a submodule type per instance. */
  final case class Own(module: String, cells: Int, areaUm2: Double, seqAreaUm2: Double, counts: Map[String, Int],
                       children: Seq[String])

  /** Each module's own cells in a netlist read as JSON ([[YosysJson]]; `json` names it in messages). */
  def of(root: ujson.Value, json: String, lib: Liberty.Library): Map[String, Own] = {
    val modules = root.obj.get("modules").map(_.obj).getOrElse(MapmError.fail(s"$json: not a yosys netlist (no modules)"))
    modules.map { case (name, m) =>
      val cells = m.obj.get("cells").map(_.obj.values.toSeq).getOrElse(Nil).map(_.obj("type").str)
      val (leaf, sub) = cells.partition(lib.cells.contains)
      val unknown = sub.filterNot(modules.contains)
      MapmError.check(unknown.isEmpty, s"cost: $json: module $name uses ${unknown.head}, neither a cell of ${lib.name} nor a module")
      val libCells = leaf.map(lib.cells)
      name -> Own(name, leaf.size, libCells.map(_.area).sum, libCells.filter(_.isSequential).map(_.area).sum,
        leaf.groupBy(identity).map { case (t, s) => t -> s.size }, sub)
    }.toMap
  }
}
