package mapm.cli

import mainargs.{ParserForMethods, arg, main}
import mapm.MapmError
import mapm.model.{Box, PhotonTree}
import mapm.numerics.Vec3

/** `mapm kdtree`: builds the photon KD-tree of dissertation 3.1.4 over photons from a CSV file and
  * prints it node by node (pre-order), as in Table 3.1.
  *
  * Input: a header line `x,y,z`, then one photon per line (blank lines are skipped).
  * Output: CSV `index,left,right,axis,x,y,z`; left/right are empty for a missing child, axis is
  * the node's split axis (x, y or z), and the coordinates are printed exactly as written in the input.
  */
object KdtreeCommand extends Command {
  val name = "kdtree"
  val summary = "build the photon KD-tree (3.1.4) over photons from a CSV file and print its nodes"

  /** Photons read from a CSV file: positions, the coordinate texts as written, and the file's line
    * number of each. */
  final case class PhotonCsv(positions: Array[Vec3], texts: Array[Array[String]], lines: Array[Int])

  /** Reads `x,y,z` photons; any malformed line is a [[MapmError]] naming the file and line. */
  def readPhotons(path: java.nio.file.Path): PhotonCsv = {
    val lines =
      try java.nio.file.Files.readAllLines(path).toArray(Array.empty[String]).toSeq
      catch {
        case _: java.nio.file.NoSuchFileException => MapmError.fail(s"kdtree: $path: file not found")
        case e: java.io.IOException => MapmError.fail(s"kdtree: cannot read $path: ${Option(e.getMessage).getOrElse(e.getClass.getSimpleName)}")
      }
    def at(line: Int) = s"$path line $line"
    MapmError.check(lines.nonEmpty && lines.head.split(",", -1).map(_.trim).toSeq == Seq("x", "y", "z"),
      s"${at(1)}: expected the header 'x,y,z'")
    val pos = Array.newBuilder[Vec3]
    val txt = Array.newBuilder[Array[String]]
    val num = Array.newBuilder[Int]
    for ((l, k) <- lines.zipWithIndex.drop(1) if l.trim.nonEmpty) {
      val f = l.split(",", -1).map(_.trim)
      MapmError.check(f.length == 3, s"${at(k + 1)}: expected 3 columns x,y,z, found ${f.length}")
      val v = f.zip(Seq("x", "y", "z")).map { case (s, c) =>
        val d = s.toDoubleOption.getOrElse(MapmError.fail(s"${at(k + 1)}: $c = '$s' is not a number"))
        MapmError.check(!d.isNaN && !d.isInfinite, s"${at(k + 1)}: $c = '$s' is not finite")
        d
      }
      pos += Vec3(v(0), v(1), v(2))
      txt += f
      num += k + 1
    }
    PhotonCsv(pos.result(), txt.result(), num.result())
  }

  /** Parses `xmin,ymin,zmin,xmax,ymax,zmax`. */
  def parseBox(text: String): Box = {
    val f = text.split(",", -1).map(_.trim)
    MapmError.check(f.length == 6, s"kdtree: --box '$text' needs 6 numbers xmin,ymin,zmin,xmax,ymax,zmax")
    val v = f.map(s => s.toDoubleOption.filter(d => !d.isNaN && !d.isInfinite)
      .getOrElse(MapmError.fail(s"kdtree: --box '$text': '$s' is not a finite number")))
    val b = Box(Vec3(v(0), v(1), v(2)), Vec3(v(3), v(4), v(5)))
    MapmError.check(b.lo.x <= b.hi.x && b.lo.y <= b.hi.y && b.lo.z <= b.hi.z, s"kdtree: --box '$text' has a minimum above its maximum")
    b
  }

  /** The output lines (header included) for the photons of `csv` (read from `path`) in `box`. */
  def table(csv: PhotonCsv, box: Box, path: java.nio.file.Path): Seq[String] = {
    for ((p, k) <- csv.positions.zipWithIndex if !box.contains(p))
      MapmError.fail(s"$path line ${csv.lines(k)}: photon (${csv.texts(k).mkString(",")}) lies outside the box ${box.lo} .. ${box.hi}")
    val t = PhotonTree.build(csv.positions, box)
    def idx(i: Int) = if (i < 0) "" else i.toString
    "index,left,right,axis,x,y,z" +: (0 until t.size).map { i =>
      (Seq(i.toString, idx(t.left(i)), idx(t.right(i)), PhotonTree.axisName(t.axis(i))) ++ csv.texts(t.photon(i))).mkString(",")
    }
  }

  @main
  def kdtree(
      @arg(doc = "CSV file with header x,y,z and one photon per line") photons: String,
      @arg(doc = "root box xmin,ymin,zmin,xmax,ymax,zmax (default: the photons' bounding box)") box: Option[String] = None
  ): Int = {
    val path = java.nio.file.Paths.get(photons)
    val csv = readPhotons(path)
    val b = box.map(parseBox).getOrElse(if (csv.positions.isEmpty) Box(Vec3.zero, Vec3.zero) else Box.of(csv.positions.toSeq))
    table(csv, b, path).foreach(println)
    0
  }

  lazy val parser: ParserForMethods[_] = ParserForMethods(this)

  def run(args: Seq[String]): Int = Args.run(this, args)
}
