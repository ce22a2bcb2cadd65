package mapm.model

import mapm.numerics._

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

class ObjLoaderSpec extends AnyFunSuite {
  import TestScenes._

  private val white = Vec3(0.725, 0.71, 0.68)

  test("the Cornell box: 30 triangles, the published bounding box, white/red/green walls") {
    val s = ObjLoader.load(cornellObj, Vec3(0.5, 0.5, 0.5))
    assert(s.triangles.size == 30)
    assert(s.bounds == Box(Vec3(0, 0, 0), Vec3(556, 548.8, 559.2)))
    val byName = s.materials.map(m => m.name -> m).toMap
    assert(byName.keySet == Set("white", "red", "green"))
    assert(byName("white").kd == white)
    assert(byName("red").kd == Vec3(0.63, 0.065, 0.05))
    assert(byName("green").kd == Vec3(0.14, 0.45, 0.091))
    assert(s.materials.forall(_.ke == Vec3.zero) && s.emitters.isEmpty)
    val count = s.triangles.groupBy(t => s.materials(t.material).name).map { case (k, v) => k -> v.size }
    assert(count == Map("white" -> 26, "red" -> 2, "green" -> 2))
    // Green wall on the plane x = 0, red wall between x = 549.6 and 556.
    for (t <- s.triangles if s.materials(t.material).name == "green"; v <- Seq(t.v0, t.v1, t.v2)) assert(v.x == 0)
    for (t <- s.triangles if s.materials(t.material).name == "red"; v <- Seq(t.v0, t.v1, t.v2)) assert(v.x >= 549.6 && v.x <= 556)
    assert(!s.triangles.exists(_.degenerate))
    // Floor: the quad (552.8,0,0) (0,0,0) (0,0,559.2) (549.6,0,559.2); shoelace area (552.8 + 549.6) * 559.2 / 2.
    val floor = s.triangles.filter(t => Seq(t.v0, t.v1, t.v2).forall(_.y == 0) && t.bounds.extent.x > 500)
    assert(floor.size == 2)
    assert(math.abs(floor.map(_.area).sum - 1102.4 * 559.2 / 2) < 1e-6)
  }

  test("quads and pentagons are fanned, negative indices resolve, faces without usemtl get the default material") {
    val d = tempDir()
    val obj = write(d, "a.obj",
      """# comment
        |v 0 0 0
        |v 1 0 0
        |v 1 1 0
        |v 0 1 0
        |v 0.5 1.5 0
        |f 1 2 3 4 5
        |vt 0 0
        |vn 0 0 1
        |g side
        |s off
        |f -5/1/1 -4/1/1 -3/1/1
        |f 1//1 2//1 \
        |  4//1
        |""".stripMargin)
    val s = ObjLoader.load(obj, Vec3(0.2, 0.3, 0.4))
    assert(s.materials == Vector(Material(ObjLoader.DefaultMaterialName, Vec3(0.2, 0.3, 0.4), Vec3.zero)))
    val v = Vector(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(0.5, 1.5, 0))
    assert(s.triangles == Vector(
      Triangle(v(0), v(1), v(2), 0), Triangle(v(0), v(2), v(3), 0), Triangle(v(0), v(3), v(4), 0),
      Triangle(v(0), v(1), v(2), 0), Triangle(v(0), v(1), v(3), 0)))
  }

  test("emissive materials (Ke) become area lights; Kd with one value means grey") {
    val d = tempDir()
    write(d, "m.mtl", "newmtl lamp\nKd 0.5\nKe 10 20 30\nNs 10\nillum 1\nnewmtl wall\nKd 0.1 0.2 0.3\n")
    val obj = write(d, "a.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nusemtl lamp\nf 1 2 3\nusemtl wall\nf 1 2 4\n")
    val s = ObjLoader.load(obj, Vec3.one)
    assert(s.materials == Vector(Material("lamp", Vec3(0.5, 0.5, 0.5), Vec3(10, 20, 30)), Material("wall", Vec3(0.1, 0.2, 0.3), Vec3.zero)))
    assert(s.emitters == Vector(0))
  }

  /** Loads `obj` (with `mtl` as m.mtl beside it) and returns the error message. */
  private def error(obj: String, mtl: Option[String] = None): (String, String) = {
    val d = tempDir()
    mtl.foreach(write(d, "m.mtl", _))
    val p = write(d, "bad.obj", obj)
    val e = intercept[MapmError](ObjLoader.load(p, Vec3.one))
    assert(!e.getMessage.contains("\n"), "one line")
    (p.toString, e.getMessage)
  }

  private val tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"

  test("malformed OBJ files give one line naming the file, the line and the problem") {
    val cases = Seq(
      ("v 0 0 0\nv 1 x 0\n", 2, "not a number"),
      ("v 0 0\n", 1, "3 coordinates"),
      ("v 0 0 NaN\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 1, "not finite"),
      ("v 1e999 0 0\n", 1, "not finite"),
      (tri + "f 1 2 9\n", 4, "out of range"),
      (tri + "f 0 1 2\n", 4, "out of range"),
      (tri + "f -4 1 2\n", 4, "out of range"),
      ("f 1 2 3\n" + tri, 1, "out of range"),
      (tri + "f 1 2\n", 4, "at least 3"),
      (tri + "f 1a 2 3\n", 4, "bad vertex index"),
      (tri + "f 1/a 2 3\n", 4, "cannot parse"),
      (tri + "f 1/x/1 2 3\n", 4, "cannot parse"),
      (tri + "bogus 1 2\nf 1 2 3\n", 4, "unknown"),
      (tri + "curv 0 1 1 2\n", 4, "unsupported"),
      (tri + "usemtl\nf 1 2 3\n", 4, "no material"),
      (tri + "vn 0 q 1\n", 4, "cannot parse"))
    for ((text, line, what) <- cases) {
      val (file, msg) = error(text)
      assert(msg.startsWith(s"$file:$line: "), s"'$msg' for\n$text")
      assert(msg.contains(what), s"'$msg' should say '$what'")
    }
  }

  test("empty and degenerate scenes, missing files and materials are reported") {
    assert(error("# nothing\n")._2.contains("no faces"))
    assert(error(tri)._2.contains("no faces"))
    assert(error("v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n")._2.contains("zero area"))
    val missing = TestScenes.tempDir().resolve("nope.obj")
    val e = intercept[MapmError](ObjLoader.load(missing, Vec3.one))
    assert(e.getMessage.contains(missing.toString) && e.getMessage.contains("not found"))
    val (f1, m1) = error("mtllib none.mtl\n" + tri + "f 1 2 3\n")
    assert(m1.startsWith(s"$f1:1: ") && m1.contains("none.mtl") && m1.contains("not found"))
    val (f2, m2) = error("mtllib m.mtl\n" + tri + "usemtl blue\nf 1 2 3\n", Some("newmtl red\nKd 1 0 0\n"))
    assert(m2.startsWith(s"$f2:5: ") && m2.contains("'blue'") && m2.contains("not defined"))
    val (f3, m3) = error(tri + "usemtl red\nf 1 2 3\n")
    assert(m3.startsWith(s"$f3:4: ") && m3.contains("no mtllib"))
  }

  test("malformed MTL files name the MTL file and line") {
    val obj = "mtllib m.mtl\n" + tri + "usemtl a\nf 1 2 3\n"
    val cases = Seq(
      ("newmtl a\nKd 0.5 x 0.5\n", 2, "not a number"),
      ("newmtl a\nKd 0.5 0.5\n", 2, "1 or 3 numbers"),
      ("newmtl a\nKd 1.5 0.5 0.5\n", 2, "at most 1"),
      ("newmtl a\nKd 0.5 0.5 0.5\nKe -1 0 0\n", 3, "negative"),
      ("newmtl a\nKd 0.5 0.5 0.5\nKe Infinity 0 0\n", 3, "not finite"),
      ("newmtl a\nKd 0.5 0.5 0.5\nnewmtl a\nKd 0.1 0.1 0.1\n", 3, "twice"),
      ("newmtl a\nKs 1 1 1\n", 1, "no Kd"),
      ("Kd 1 1 1\nnewmtl a\n", 1, "newmtl"),
      ("newmtl a\nNs abc\n", 2, "cannot parse"))
    for ((mtl, line, what) <- cases) {
      val (objFile, msg) = error(obj, Some(mtl))
      val mtlFile = java.nio.file.Path.of(objFile).resolveSibling("m.mtl").toString
      assert(msg.startsWith(s"$mtlFile:$line: "), s"'$msg' for\n$mtl")
      assert(msg.contains(what), s"'$msg' should say '$what'")
    }
  }

  test("a material name the OBJ library reads differently than written is one clear error (found by mapm fuzz)") {
    // A continued newmtl line joins the next statement into the checker's name; a name glued to the
    // keyword (newmtl\u1396a) is a newmtl statement to the library but not to the checker. Both
    // once escaped as a NoSuchElementException.
    val obj = "mtllib m.mtl\n" + tri + "usemtl a\nf 1 2 3\n"
    for (mtl <- Seq("newmtl a \\\nKd 0.5 0.5 0.5\n", "newmtl\u1396a\nKd 0.5 0.5 0.5\n")) {
      val (objFile, msg) = error(obj, Some(mtl))
      assert(!msg.contains('\n') && msg.startsWith(java.nio.file.Path.of(objFile).resolveSibling("m.mtl").toString + ":"), msg)
    }
  }
}
