package mapm.cost

import java.nio.file.{Files, Path}
import mapm.MapmError
import upickle.core.{NoOpVisitor, ObjVisitor, Visitor}

/** Reading a large yosys JSON netlist with only the parts the cost flow uses: the value of every
  * key in `skip` (by default the attributes, net names, cell port directions and parameters) is
  * dropped while the file is parsed, never built. A whole 16/16/2 coprocessor's netlist is 1.4 GB
  * of JSON, which does not fit a 12 GB heap as a whole tree. */
object YosysJson {
  /** The keys whose values the cost flow does not read. */
  val Unused: Set[String] = Set("attributes", "netnames", "port_directions", "parameters")

  def read(path: Path, skip: Set[String] = Unused): ujson.Value = {
    MapmError.check(Files.isRegularFile(path), s"cost: netlist $path not found")
    try ujson.transform(ujson.Readable.fromPath(path), new Filter(ujson.Value, skip))
    catch { case e: upickle.core.Abort => MapmError.fail(s"$path: not JSON: ${e.getMessage}")
            case e: ujson.ParsingFailedException => MapmError.fail(s"$path: not JSON: ${e.getMessage}") }
  }

  /** `d` with the values of the keys in `skip` (at any depth) replaced by null. */
  private final class Filter[T, J](d: Visitor[T, J], skip: Set[String]) extends Visitor.Delegate[T, J](d) {
    override def visitObject(length: Int, jsonableKeys: Boolean, index: Int): ObjVisitor[T, J] = {
      val o = d.visitObject(length, jsonableKeys, index)
      new ObjVisitor[T, J] {
        private var skipping = false
        def visitKey(index: Int): Visitor[_, _] = new Visitor.Delegate[Any, Any](o.visitKey(index).asInstanceOf[Visitor[Any, Any]]) {
          override def visitString(s: CharSequence, index: Int): Any = { skipping = skip(s.toString); super.visitString(s, index) }
        }
        def visitKeyValue(v: Any): Unit = o.visitKeyValue(v)
        def subVisitor: Visitor[_, _] = if (skipping) NoOpVisitor else new Filter(o.subVisitor.asInstanceOf[Visitor[Any, Any]], skip)
        def visitValue(v: T, index: Int): Unit =
          o.visitValue((if (skipping) ujson.Null else v).asInstanceOf[T], index)
        def visitEnd(index: Int): J = o.visitEnd(index)
      }
    }
  }
}
