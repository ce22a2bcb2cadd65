package mapm.model

import mapm.numerics._

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}

/** Files and small scenes shared by the scene-side specs. */
object TestScenes {
  val cornellDir: Path = Path.of("test-scenes/cornell-box")
  val cornellObj: Path = cornellDir.resolve("cornell-box.obj")
  val cornellScene: Path = cornellDir.resolve("scene.json")
  val cornellAreaScene: Path = cornellDir.resolve("scene-area.json")

  /** A fresh temporary directory. */
  def tempDir(): Path = {
    val d = Files.createTempDirectory("mapm-scene-test")
    d.toFile.deleteOnExit()
    d
  }

  def write(dir: Path, name: String, text: String): Path = {
    val p = dir.resolve(name)
    Files.write(p, text.getBytes(StandardCharsets.UTF_8))
    p.toFile.deleteOnExit()
    p
  }

  /** The closed axis-aligned box [0,s]^3 made of 12 triangles, all with reflectance `kd`; the top
    * face (y = s) uses material `topMaterial` (1 = emissive, facing down) when `emissiveTop` is given. */
  def closedBox(s: Double, kd: Vec3, emissiveTop: Option[Vec3] = None): Scene = {
    def v(x: Double, y: Double, z: Double) = Vec3(x * s, y * s, z * s)
    def quad(a: Vec3, b: Vec3, c: Vec3, d: Vec3, m: Int) = Seq(Triangle(a, b, c, m), Triangle(a, c, d, m))
    val top = if (emissiveTop.isDefined) 1 else 0
    val tris =
      quad(v(0, 0, 0), v(1, 0, 0), v(1, 0, 1), v(0, 0, 1), 0) ++ // floor
      quad(v(0, 1, 0), v(1, 1, 0), v(1, 1, 1), v(0, 1, 1), top) ++ // ceiling, (b-a) x (c-a) = -y: faces down
      quad(v(0, 0, 0), v(0, 1, 0), v(0, 1, 1), v(0, 0, 1), 0) ++
      quad(v(1, 0, 0), v(1, 1, 0), v(1, 1, 1), v(1, 0, 1), 0) ++
      quad(v(0, 0, 0), v(1, 0, 0), v(1, 1, 0), v(0, 1, 0), 0) ++
      quad(v(0, 0, 1), v(1, 0, 1), v(1, 1, 1), v(0, 1, 1), 0)
    val mats = Vector(Material("grey", kd, Vec3.zero)) ++ emissiveTop.map(ke => Material("lamp", kd, ke))
    Scene(tris.toVector, mats)
  }
}
