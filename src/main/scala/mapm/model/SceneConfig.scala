package mapm.model

import mapm.numerics._

import java.io.IOException
import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}

import scala.collection.mutable

import mapm.MapmError

/** The kernel radius h (3.1.6): fixed, or chosen from the photon map. */
sealed trait KernelRadius
object KernelRadius {
  /** h in scene units. */
  final case class Fixed(h: Double) extends KernelRadius
  /** h chosen so that a query point finds about `photonsPerQuery` photons on average. */
  final case class Auto(photonsPerQuery: Double) extends KernelRadius
}

/** A loaded scene description file (docs/scene-format.md): geometry, camera, lights and the render
  * settings, already moved into the positive octant.
  *
  * @param file               the scene file
  * @param objFile            the OBJ file it names
  * @param scene              the OBJ's triangles plus the file's area-light polygons, shifted by `shift`
  * @param camera             the camera, shifted by `shift`
  * @param pointLights        point lights, shifted by `shift`
  * @param width              image width in pixels
  * @param height             image height in pixels
  * @param finalGatherRays    final-gather rays per pixel
  * @param photons            number of photons to store
  * @param maxBounces         most photons one photon path stores
  * @param h                  kernel radius
  * @param seed               random seed of every sampling stage
  * @param format             number format for the accelerator, if the file sets one
  * @param directLightSamples area-light samples per pixel for the viewable image's direct light
  * @param shift              translation applied to everything so that the geometry lies in x, y, z >= 0
  */
final case class SceneConfig(
    file: Path,
    objFile: Path,
    scene: Scene,
    camera: Camera,
    pointLights: Seq[PointLight],
    width: Int,
    height: Int,
    finalGatherRays: Int,
    photons: Int,
    maxBounces: Int,
    h: KernelRadius,
    seed: Long,
    format: Option[FloatFormat],
    directLightSamples: Int,
    shift: Vec3)

object SceneConfig {
  object Defaults {
    val up = Vec3(0, 1, 0)
    val fovDeg = 39.3
    val width = 75
    val height = 60
    val finalGatherRays = 36
    val photons = 2000
    val maxBounces = 5
    val h: KernelRadius = KernelRadius.Auto(20)
    val seed = 1L
    val defaultKd = Vec3(0.75, 0.75, 0.75)
    val directLightSamples = 16
  }

  private val topKeys = Set("obj", "camera", "lights", "width", "height", "finalGatherRays", "photons", "maxBounces",
    "h", "seed", "format", "defaultKd", "directLightSamples", "comment")

  /** Reads and validates a scene file and everything it names. */
  def load(path: Path): SceneConfig = {
    val r = new JsonReader(path)
    val top = r.obj(readJson(path), "", topKeys)

    val objRel = r.str(top.getOrElse("obj", r.missing("obj")), "obj")
    val objFile = Option(path.toAbsolutePath.getParent).fold(Path.of(objRel))(_.resolve(objRel)).normalize()
    if (!Files.isRegularFile(objFile)) r.fail("obj", s"OBJ file $objFile not found" +
      (if (objRel.contains("shared/")) " (a shared model, read in place and never copied into the project: is ../shared beside the checkout?)" else ""))

    val camera = readCamera(r, top)
    val width = top.get("width").fold(Defaults.width)(v => r.int(v, "width", 1))
    val height = top.get("height").fold(Defaults.height)(v => r.int(v, "height", 1))
    val fgr = top.get("finalGatherRays").fold(Defaults.finalGatherRays)(v => r.int(v, "finalGatherRays", 1))
    if (width.toLong * height * fgr > Int.MaxValue)
      r.fail("finalGatherRays", s"width * height * finalGatherRays = ${width.toLong * height * fgr} query points is too many")
    val photons = top.get("photons").fold(Defaults.photons)(v => r.int(v, "photons", 0))
    if (photons > NodeWord.MaxNodes) r.fail("photons", s"must be at most ${NodeWord.MaxNodes} (the node record's index field), got $photons")
    val maxBounces = top.get("maxBounces").fold(Defaults.maxBounces)(v => r.int(v, "maxBounces", 1))
    val h = readKernelRadius(r, top)
    val seed = top.get("seed").fold(Defaults.seed)(v => r.long(v, "seed"))
    val format = top.get("format").map { v =>
      val s = r.str(v, "format")
      try FloatFormat.parse(s) catch { case e: MapmError => r.fail("format", e.getMessage) }
    }
    val defaultKd = top.get("defaultKd").fold(Defaults.defaultKd)(v => r.reflectance(v, "defaultKd"))
    val directSamples = top.get("directLightSamples").fold(Defaults.directLightSamples)(v => r.int(v, "directLightSamples", 0))
    top.get("comment").foreach(v => r.str(v, "comment"))
    val (pointLights, areaPolys) = readLights(r, top)

    val full = withAreaLights(ObjLoader.load(objFile, defaultKd), areaPolys)

    // Positive octant: the tree-search hardware assumes coordinates >= 0.
    val lo = full.bounds.lo
    val shift = Vec3(math.max(0, -lo.x), math.max(0, -lo.y), math.max(0, -lo.z))
    SceneConfig(path, objFile, full.translate(shift), camera.translate(shift), pointLights.map(_.translate(shift)).toSeq,
      width, height, fgr, photons, maxBounces, h, seed, format, directSamples, shift)
  }


  /** The scene file's JSON; a [[MapmError]] naming the file (and the line) when it cannot be read or parsed. */
  private def readJson(path: Path): ujson.Value = {
    val text =
      try new String(Files.readAllBytes(path), StandardCharsets.UTF_8)
      catch {
        case _: java.nio.file.NoSuchFileException => MapmError.fail(s"$path: scene file not found")
        case e: IOException                       => MapmError.fail(s"$path: cannot read (${e.getMessage})")
      }
    try ujson.read(text)
      catch {
        case e: ujson.ParseException =>
          val line = text.take(math.max(0, e.index)).count(_ == '\n') + 1
          MapmError.fail(s"$path:$line: invalid JSON (${e.clue})")
        case _: ujson.IncompleteParseException => MapmError.fail(s"$path: invalid JSON (the text ends early)")
        case e: Exception => MapmError.fail(s"$path: invalid JSON (${e.getMessage})")
      }
  }

  /** The `camera` block: position, a view direction (from `lookAt` or `direction`), up and field of view. */
  private def readCamera(r: JsonReader, top: collection.Map[String, ujson.Value]): Camera = {
    val cam = r.obj(top.getOrElse("camera", r.missing("camera")), "camera", Set("position", "lookAt", "direction", "up", "fov"))
    val position = r.vec(cam.getOrElse("position", r.missing("camera.position")), "camera.position")
    val direction = (cam.get("lookAt"), cam.get("direction")) match {
      case (Some(l), None) =>
        val d = r.vec(l, "camera.lookAt") - position
        if (d.length == 0) r.fail("camera.lookAt", "equals camera.position")
        d.normalized
      case (None, Some(dv)) =>
        val d = r.vec(dv, "camera.direction")
        if (d.length == 0) r.fail("camera.direction", "is the zero vector")
        d.normalized
      case (Some(_), Some(_)) => r.fail("camera", "give either lookAt or direction, not both")
      case (None, None)       => r.fail("camera", "needs lookAt or direction")
    }
    val up = cam.get("up").fold(Defaults.up)(v => r.vec(v, "camera.up"))
    if (direction.cross(up).length <= 1e-9 * up.length) r.fail("camera.up", s"is zero or parallel to the view direction")
    val fov = cam.get("fov").fold(Defaults.fovDeg)(v => r.num(v, "camera.fov"))
    if (!(fov > 0 && fov < 180)) r.fail("camera.fov", s"must be in (0, 180) degrees, got $fov")
    Camera(position, direction, up.normalized, fov)

  }

  /** `h`: a fixed kernel radius, or `{"auto": photonsPerQuery}`. */
  private def readKernelRadius(r: JsonReader, top: collection.Map[String, ujson.Value]): KernelRadius =
    top.get("h").fold(Defaults.h) {
      case ujson.Num(_) =>
        val x = r.num(top("h"), "h")
        if (!(x > 0)) r.fail("h", s"must be > 0, got $x")
        KernelRadius.Fixed(x)
      case o: ujson.Obj =>
        val m = r.obj(o, "h", Set("auto"))
        val t = r.num(m.getOrElse("auto", r.missing("h.auto")), "h.auto")
        if (!(t > 0)) r.fail("h.auto", s"target photons per query must be > 0, got $t")
        KernelRadius.Auto(t)
      case other => r.fail("h", s"must be a number or {\"auto\": photonsPerQuery}, got ${r.kind(other)}")
    }

  /** The `lights`: point lights as they are, and area-light polygons (vertices, radiance, kd) to join the geometry. */
  private def readLights(r: JsonReader, top: collection.Map[String, ujson.Value]): (Seq[PointLight], Seq[(Seq[Vec3], Vec3, Vec3)]) = {
    val pointLights = mutable.ArrayBuffer.empty[PointLight]
    val areaPolys = mutable.ArrayBuffer.empty[(Seq[Vec3], Vec3, Vec3)] // vertices, radiance, kd
    top.get("lights").foreach { lv =>
      val arr = lv match { case a: ujson.Arr => a.value; case other => r.fail("lights", s"must be an array, got ${r.kind(other)}") }
      for ((l, i) <- arr.zipWithIndex) {
        val key = s"lights[$i]"
        val typ = l match {
          case o: ujson.Obj => r.str(o.value.getOrElse("type", r.missing(s"$key.type")), s"$key.type")
          case other        => r.fail(key, s"must be an object, got ${r.kind(other)}")
        }
        typ match {
          case "point" =>
            val m = r.obj(l, key, Set("type", "position", "power"))
            val pos = r.vec(m.getOrElse("position", r.missing(s"$key.position")), s"$key.position")
            val power = r.vec(m.getOrElse("power", r.missing(s"$key.power")), s"$key.power")
            if (power.x < 0 || power.y < 0 || power.z < 0) r.fail(s"$key.power", s"must not be negative, got $power")
            pointLights += PointLight(pos, power)
          case "area" =>
            val m = r.obj(l, key, Set("type", "vertices", "radiance", "kd"))
            val vs = m.getOrElse("vertices", r.missing(s"$key.vertices")) match {
              case a: ujson.Arr if a.value.size >= 3 => a.value.zipWithIndex.map { case (v, j) => r.vec(v, s"$key.vertices[$j]") }.toSeq
              case other => r.fail(s"$key.vertices", s"must be an array of 3 or more [x, y, z] points, got ${r.kind(other)}")
            }
            val radiance = r.vec(m.getOrElse("radiance", r.missing(s"$key.radiance")), s"$key.radiance")
            if (radiance.x < 0 || radiance.y < 0 || radiance.z < 0) r.fail(s"$key.radiance", s"must not be negative, got $radiance")
            val kd = m.get("kd").fold(Vec3.zero)(v => r.reflectance(v, s"$key.kd"))
            val tris = vs.indices.drop(1).dropRight(1).map(k => Triangle(vs(0), vs(k), vs(k + 1), 0))
            val normal = tris.map(_.crossNormal).reduce(_ + _)
            if (normal.length == 0 || tris.exists(_.degenerate)) r.fail(s"$key.vertices", "the polygon has a zero-area part")
            val size = Box.of(vs).extent.length
            val n = normal.normalized
            if (vs.exists(v => math.abs((v - vs(0)).dot(n)) > 1e-6 * size)) r.fail(s"$key.vertices", "the polygon is not planar")
            areaPolys += ((vs, radiance, kd))
          case other => r.fail(s"$key.type", s"must be \"point\" or \"area\", got \"$other\"")
        }
      }
    }

    (pointLights.toSeq, areaPolys.toSeq)
  }

  /** `scene` with each area-light polygon (vertices, radiance, kd) added as emissive triangles of a material of its own. */
  private def withAreaLights(scene: Scene, polys: Seq[(Seq[Vec3], Vec3, Vec3)]): Scene = {
    val lightMaterials = polys.zipWithIndex.map { case ((_, ke, kd), i) => Material(s"area-light-$i", kd, ke) }
    val lightTris = polys.zipWithIndex.flatMap { case ((vs, _, _), i) =>
      val mat = scene.materials.size + i
      vs.indices.drop(1).dropRight(1).map(k => Triangle(vs(0), vs(k), vs(k + 1), mat))
    }
    Scene(scene.triangles ++ lightTris, scene.materials ++ lightMaterials)
  }

  /** Typed access to JSON values with errors that name the scene file and the key. */
  private final class JsonReader(file: Path) {
    def fail(key: String, msg: String): Nothing = MapmError.fail(s"$file: key '$key': $msg")
    def missing(key: String): Nothing = fail(key, "is required")

    def kind(v: ujson.Value): String = v match {
      case _: ujson.Obj => "an object"
      case _: ujson.Arr => "an array"
      case _: ujson.Str => "a string"
      case _: ujson.Num => "a number"
      case ujson.Null   => "null"
      case _            => "a boolean"
    }

    /** An object whose keys are all in `allowed`. */
    def obj(v: ujson.Value, key: String, allowed: Set[String]): collection.Map[String, ujson.Value] = v match {
      case o: ujson.Obj =>
        for (k <- o.value.keys if !allowed(k))
          fail(if (key.isEmpty) k else s"$key.$k", s"unknown key (allowed here: ${allowed.toSeq.sorted.mkString(", ")})")
        o.value
      case other => fail(if (key.isEmpty) "(top level)" else key, s"must be an object, got ${kind(other)}")
    }

    def num(v: ujson.Value, key: String): Double = v match {
      case ujson.Num(x) if !x.isNaN && !x.isInfinite => x
      case ujson.Num(x) => fail(key, s"must be finite, got $x")
      case other        => fail(key, s"must be a number, got ${kind(other)}")
    }

    def str(v: ujson.Value, key: String): String = v match {
      case ujson.Str(s) => s
      case other        => fail(key, s"must be a string, got ${kind(other)}")
    }

    def int(v: ujson.Value, key: String, min: Int): Int = {
      val x = num(v, key)
      if (x != math.rint(x) || x > Int.MaxValue || x < Int.MinValue) fail(key, s"must be a whole number, got $x")
      if (x < min) fail(key, s"must be >= $min, got ${x.toLong}")
      x.toInt
    }

    def long(v: ujson.Value, key: String): Long = {
      val x = num(v, key)
      if (x != math.rint(x) || math.abs(x) > (1L << 53)) fail(key, s"must be a whole number of magnitude <= 2^53, got $x")
      x.toLong
    }

    def vec(v: ujson.Value, key: String): Vec3 = v match {
      case a: ujson.Arr if a.value.size == 3 =>
        Vec3(num(a(0), s"$key[0]"), num(a(1), s"$key[1]"), num(a(2), s"$key[2]"))
      case a: ujson.Arr => fail(key, s"must have 3 numbers, got ${a.value.size}")
      case other        => fail(key, s"must be an array of 3 numbers, got ${kind(other)}")
    }

    def reflectance(v: ujson.Value, key: String): Vec3 = {
      val c = vec(v, key)
      if (Seq(c.x, c.y, c.z).exists(x => x < 0 || x > 1)) fail(key, s"each channel must be in [0, 1], got $c")
      c
    }
  }
}
