package mapm.cli

import mapm.MapmError
import mapm.model.Table31
import org.scalatest.funsuite.AnyFunSuite

class KdtreeCommandSpec extends AnyFunSuite {
  private val table31Csv = java.nio.file.Paths.get("test-scenes/table-3-1/photons.csv")

  private def runKdtree(args: String*): Seq[String] = {
    val out = new java.io.ByteArrayOutputStream()
    val code = Console.withOut(out)(KdtreeCommand.run(args))
    assert(code == 0)
    out.toString("UTF-8").linesIterator.toSeq
  }

  test("kdtree on the seven photons of 3.1.4 in the example's box prints Table 3.1") {
    assert(java.nio.file.Files.exists(table31Csv), s"$table31Csv is missing")
    val rows = runKdtree("--photons", table31Csv.toString, "--box", "0,0,0.769442,555.036,548.8,559.2")
    assert(rows.head == "index,left,right,axis,x,y,z")
    assert(rows.length == 8)
    for (((i, l, r, pos), row) <- Table31.table.zip(rows.tail)) {
      val f = row.split(",", -1)
      assert(f(0) == i.toString && f(1) == (if (l < 0) "" else l.toString) && f(2) == (if (r < 0) "" else r.toString), row)
      assert(f.drop(4).map(_.toDouble).toSeq == Seq(pos.x, pos.y, pos.z), row)
    }
    assert(rows(1) == "0,1,4,z,0,509.39,171.588") // coordinates exactly as written in the input
    assert(rows.slice(1, 3).map(_.split(",")(3)) == Seq("z", "x") && rows(5).split(",")(3) == "x")
  }

  /** The error for a file with `content`, and whether it names the file. */
  private def badCsv(content: String): (String, Boolean) = {
    val f = java.nio.file.Files.createTempFile("kdtree", ".csv")
    java.nio.file.Files.writeString(f, content)
    f.toFile.deleteOnExit()
    val m = intercept[MapmError](KdtreeCommand.run(Seq("--photons", f.toString))).getMessage
    (m, m.contains(f.toString))
  }

  test("bad CSV input is one error naming the file and the line") {
    val cases = Seq(
      "1,2,3\n" -> "line 1: expected the header",
      "x,y,z\n1,2,3\n\n4,5\n" -> "line 4: expected 3 columns",
      "x,y,z\n1,2,3,4\n" -> "line 2: expected 3 columns",
      "x,y,z\n1,abc,3\n" -> "line 2: y = 'abc' is not a number",
      "x,y,z\n1,2,NaN\n" -> "line 2: z = 'NaN' is not finite",
      "x,y,z\n1,2,3\nInfinity,2,3\n" -> "line 3: x = 'Infinity' is not finite",
      "" -> "line 1: expected the header")
    for ((content, msg) <- cases) {
      val (m, namesFile) = badCsv(content)
      assert(m.contains(msg) && namesFile, s"'$m' lacks '$msg' or the file name")
    }
    val out = intercept[MapmError](KdtreeCommand.run(Seq("--photons", table31Csv.toString, "--box", "0,0,0,300,600,600")))
    assert(out.getMessage.contains("line 2") && out.getMessage.contains("outside the box"))
    assert(intercept[MapmError](KdtreeCommand.run(Seq("--photons", "/nonexistent/p.csv"))).getMessage.contains("file not found"))
    assert(intercept[MapmError](KdtreeCommand.run(Seq("--photons", table31Csv.toString, "--box", "1,2,3"))).getMessage.contains("6 numbers"))
  }

  test("default box is the photons' bounding box; an empty file gives only the header") {
    val rows = runKdtree("--photons", table31Csv.toString)
    assert(rows.length == 8 && rows(1).startsWith("0,1,4,z,"))
    val f = java.nio.file.Files.createTempFile("kdtree", ".csv")
    java.nio.file.Files.writeString(f, "x,y,z\n")
    assert(runKdtree("--photons", f.toString) == Seq("index,left,right,axis,x,y,z"))
  }
}
