package mapm.model

import mapm.numerics._

import java.io.{BufferedReader, IOException, Reader}
import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}

import scala.collection.mutable
import scala.jdk.CollectionConverters._

import de.javagl.obj.{MtlReader, ObjReader}
import mapm.MapmError

/** Loads a Wavefront OBJ file and the MTL material libraries it names into a [[Scene]].
  *
  * Parsing is done by the de.javagl obj library; every line passes through a checker on the way in,
  * because the library is lenient where a renderer must not be (it keeps NaN coordinates, accepts
  * "Kd 0.5 x 0.5", out-of-range face indices and unknown statements). A problem ends the load with a
  * [[MapmError]] naming the file and line.
  *
  * What is read:
  *  - `v x y z [w]` vertices;
  *  - `f` faces of three or more vertices (`v`, `v/vt`, `v//vn`, `v/vt/vn`; negative indices count back
  *    from the last vertex), triangulated as a fan around their first vertex;
  *  - `mtllib` (paths relative to the OBJ file) and `usemtl`; from the MTL files `newmtl`, `Kd`
  *    (diffuse reflectance, required, each channel in [0,1]) and `Ke` (emitted radiance, >= 0,
  *    default 0). Other MTL statements are accepted and ignored (the model is purely diffuse);
  *  - `vt`, `vn`, `vp`, `g`, `o`, `s`, `l`, `p` and a few display statements are accepted and ignored.
  *
  * All numbers are kept as the doubles nearest to what is written (the library itself reads single
  * precision), so the Cornell box's bounding box is exactly (0,0,0)..(556,548.8,559.2).
  *
  * Faces before any `usemtl` get the material "default" with the reflectance the caller gives (the
  * Sponza model has no materials at all). A `usemtl` naming a material no library defines is an error.
  */
object ObjLoader {

  /** Name of the material given to faces that come before any `usemtl`. */
  val DefaultMaterialName = "default"

  /** Statements that carry nothing the renderer uses but are legal OBJ. */
  private val ignoredObjStatements =
    Set("vt", "vn", "vp", "g", "o", "s", "l", "p", "mg", "lod", "maplib", "usemap", "bevel", "c_interp",
        "d_interp", "shadow_obj", "trace_obj")

  /** Loads `path`; `defaultKd` is the reflectance of faces that use no material. */
  def load(path: Path, defaultKd: Vec3): Scene = {
    MapmError.check(Files.isRegularFile(path), s"$path: OBJ file not found")
    val file = path.toString
    val vertices = mutable.ArrayBuffer.empty[Vec3]
    val mtlLibs = mutable.ArrayBuffer.empty[(String, Int)] // name, line
    val usemtlLine = mutable.LinkedHashMap.empty[String, Int]
    var currentMtl: Option[String] = None
    var faceWithoutMtl = false

    def checkLine(text: String, line: Int): Unit = {
      def bad(msg: String): Nothing = MapmError.fail(s"$file:$line: $msg")
      val tokens = text.trim.split("\\s+")
      if (tokens.head.isEmpty || tokens.head.startsWith("#")) return
      tokens.head.toLowerCase match {
        case "v" =>
          if (tokens.length < 4) bad(s"vertex needs 3 coordinates: '$text'")
          val c = tokens.tail.map(t => t.toDoubleOption.getOrElse(bad(s"vertex coordinate '$t' is not a number")))
          if (!c.forall(x => !x.isNaN && !x.isInfinite)) bad(s"vertex coordinate is not finite: '$text'")
          vertices += Vec3(c(0), c(1), c(2))
        case "f" =>
          if (tokens.length < 4) bad(s"face needs at least 3 vertices: '$text'")
          for (ref <- tokens.tail) {
            val s = ref.takeWhile(_ != '/')
            val i = s.toIntOption.getOrElse(bad(s"bad vertex index '$ref' in face"))
            val resolved = if (i < 0) vertices.size + i else i - 1
            if (i == 0 || resolved < 0 || resolved >= vertices.size)
              bad(s"vertex index $i out of range (${vertices.size} vertices defined before this face)")
          }
          if (currentMtl.isEmpty) faceWithoutMtl = true
        case "mtllib" =>
          if (tokens.length < 2) bad("mtllib names no file")
          tokens.tail.foreach(n => mtlLibs += ((n, line)))
        case "usemtl" =>
          val name = text.trim.drop(6).trim
          if (name.isEmpty) bad("usemtl names no material")
          currentMtl = Some(name)
          if (!usemtlLine.contains(name)) usemtlLine(name) = line
        case kw if ignoredObjStatements(kw) => ()
        case kw => bad(s"unknown or unsupported OBJ statement '$kw'")
      }
    }

    val obj = readChecked(path, checkLine)((r: Reader) => ObjReader.read(r))
    MapmError.check(obj.getNumVertices == vertices.size, s"$file: vertex count mismatch while parsing")
    MapmError.check(obj.getNumFaces > 0, s"$file: no faces (the scene is empty)")

    val library = loadMaterials(path, mtlLibs.toSeq)
    val materials = mutable.ArrayBuffer.empty[Material]
    val materialIndex = mutable.HashMap.empty[Option[String], Int]
    if (faceWithoutMtl) { materialIndex(None) = 0; materials += Material(DefaultMaterialName, defaultKd, Vec3.zero) }
    for ((name, line) <- usemtlLine) {
      val m = library.getOrElse(name, MapmError.fail(
        s"$file:$line: material '$name' is not defined" +
          (if (mtlLibs.isEmpty) " (the file names no mtllib)" else s" in ${mtlLibs.map(_._1).mkString(", ")}")))
      materialIndex(Some(name)) = materials.size
      materials += m
    }

    // The library lists each material's faces in a material group; faces in none have no usemtl.
    val faceMaterial = new java.util.IdentityHashMap[de.javagl.obj.ObjFace, String]()
    for (g <- 0 until obj.getNumMaterialGroups; group = obj.getMaterialGroup(g); k <- 0 until group.getNumFaces)
      faceMaterial.put(group.getFace(k), group.getName)
    val triangles = mutable.ArrayBuffer.empty[Triangle]
    for (f <- 0 until obj.getNumFaces) {
      val face = obj.getFace(f)
      val mat = materialIndex(Option(faceMaterial.get(face)))
      val v = (0 until face.getNumVertices).map(k => vertices(face.getVertexIndex(k)))
      for (k <- 1 until v.size - 1) triangles += Triangle(v(0), v(k), v(k + 1), mat)
    }
    MapmError.check(triangles.exists(!_.degenerate), s"$file: every triangle has zero area")
    Scene(triangles.toVector, materials.toVector)
  }

  /** Reads the MTL libraries (relative to the OBJ file) into materials by name. */
  private def loadMaterials(objPath: Path, libs: Seq[(String, Int)]): Map[String, Material] = {
    val dir = Option(objPath.toAbsolutePath.getParent).getOrElse(objPath.toAbsolutePath)
    val found = mutable.LinkedHashMap.empty[String, Material]
    for ((name, line) <- libs.distinctBy(_._1)) {
      val mtlPath = dir.resolve(name)
      MapmError.check(Files.isRegularFile(mtlPath), s"$objPath:$line: material library '$name' not found ($mtlPath)")
      val file = mtlPath.toString
      val defined = mutable.HashMap.empty[String, Int]
      val values = mutable.HashMap.empty[(String, String), Vec3] // (material, "kd"/"ke") -> value as written
      var current = ""

      def checkLine(text: String, line: Int): Unit = {
        def bad(msg: String): Nothing = MapmError.fail(s"$file:$line: $msg")
        val tokens = text.trim.split("\\s+")
        tokens.head.toLowerCase match {
          case "newmtl" =>
            current = text.trim.drop(6).trim
            if (current.isEmpty) bad("newmtl names no material")
            if (defined.contains(current) || found.contains(current))
              bad(s"material '$current' is defined twice")
            defined(current) = line
          case kw @ ("kd" | "ke") =>
            val what = if (kw == "kd") "Kd" else "Ke"
            val args = tokens.tail
            if (args.length != 1 && args.length != 3) bad(s"$what needs 1 or 3 numbers: '$text'")
            val c = args.map(t => t.toDoubleOption.getOrElse(bad(s"$what value '$t' is not a number")))
            if (!c.forall(x => !x.isNaN && !x.isInfinite)) bad(s"$what value is not finite: '$text'")
            if (c.exists(_ < 0)) bad(s"$what must not be negative: '$text'")
            if (kw == "kd" && c.exists(_ > 1)) bad(s"Kd must be at most 1 (energy conservation): '$text'")
            values((current, kw)) = if (c.length == 1) Vec3(c(0), c(0), c(0)) else Vec3(c(0), c(1), c(2))
          case _ => ()
        }
      }

      val mtls = readChecked(mtlPath, checkLine)((r: Reader) => MtlReader.read(r)).asScala
      // The library delimits the materials; their values are the checker's exact doubles (the
      // library keeps single-precision floats).
      for (m <- mtls) {
        // The library splits lines its own way; a name it reads that no newmtl line gave the checker
        // (unusual spaces or control characters around it) is an error, not a guess.
        val line = defined.getOrElse(m.getName, MapmError.fail(
          s"$file: material name '${m.getName.filter(c => c >= ' ')}' is read differently by the OBJ library than written (unusual spaces or control characters)"))
        val kd = values.getOrElse((m.getName, "kd"), MapmError.fail(s"$file:$line: material '${m.getName}' has no Kd"))
        found(m.getName) = Material(m.getName, kd, values.getOrElse((m.getName, "ke"), Vec3.zero))
      }
    }
    found.toMap
  }

  /** Runs the library's `parse` on the file through a reader that hands every logical line (with
    * `\` continuations joined) to `check` first, and turns anything the library throws into a
    * [[MapmError]] naming the file and the line it was reading. */
  private def readChecked[T](path: Path, check: (String, Int) => Unit)(parse: Reader => T): T = {
    val in =
      try Files.newBufferedReader(path, StandardCharsets.UTF_8)
      catch { case e: IOException => MapmError.fail(s"$path: cannot read (${e.getMessage})") }
    val reader = new CheckedLineReader(in, check)
    try parse(reader)
    catch {
      case e: MapmError => throw e
      case e: java.nio.charset.CharacterCodingException =>
        MapmError.fail(s"$path:${reader.lineNumber + 1}: not UTF-8 text (${e.getClass.getSimpleName})")
      case e @ (_: IOException | _: RuntimeException) =>
        val msg = Option(e.getMessage).getOrElse(e.getClass.getSimpleName).linesIterator.nextOption().getOrElse("")
        MapmError.fail(s"$path:${reader.lineNumber}: cannot parse ($msg)")
    }
    finally in.close()
  }

  /** A BufferedReader that counts the lines the library reads and checks each one.
    *
    * The library takes a BufferedReader as it is (it wraps other readers), so overriding
    * `readLine` sees exactly the lines it parses, in order. */
  private final class CheckedLineReader(in: Reader, check: (String, Int) => Unit) extends BufferedReader(in) {
    /** Physical line number of the last line returned (1-based). */
    var lineNumber = 0
    private var logicalStart = 0
    private val pending = new StringBuilder

    override def readLine(): String = {
      val s = super.readLine()
      if (s != null) {
        lineNumber += 1
        if (pending.isEmpty) logicalStart = lineNumber
        val t = s.trim
        if (t.endsWith("\\")) pending.append(t.dropRight(1)).append(' ')
        else {
          pending.append(t)
          val full = pending.toString
          pending.clear()
          check(full, logicalStart)
        }
      } else if (pending.nonEmpty) {
        val full = pending.toString
        pending.clear()
        check(full, logicalStart)
      }
      s
    }
  }
}
