package mapm.model

import mapm.numerics._

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

class SceneConfigSpec extends AnyFunSuite {
  import TestScenes._

  test("the Cornell box point-light scene parses with the values written in it") {
    val c = SceneConfig.load(cornellScene)
    assert(c.objFile == cornellObj.toAbsolutePath.normalize)
    assert(c.scene.triangles.size == 30)
    assert(c.shift == Vec3.zero)
    assert(c.camera == Camera(Vec3(278, 273, -530), Vec3(0, 0, 1), Vec3(0, 1, 0), 39.3))
    assert(c.pointLights == Seq(PointLight(Vec3(1, 25, 1), Vec3(1e7, 1e7, 1e7))))
    assert((c.width, c.height, c.finalGatherRays, c.photons, c.maxBounces, c.seed) == ((75, 60, 36, 2000, 5, 1L)))
    assert(c.h == KernelRadius.Auto(20))
    assert(c.format.isEmpty)
    assert(c.scene.emitters.isEmpty)
  }

  test("the area-light scene adds the ceiling light as two emissive triangles facing down") {
    val c = SceneConfig.load(cornellAreaScene)
    assert(c.pointLights.isEmpty)
    assert(c.scene.triangles.size == 32)
    assert(c.scene.emitters == Vector(30, 31))
    for (i <- c.scene.emitters) {
      val t = c.scene.triangles(i)
      assert(t.normal == Vec3(0, -1, 0))
      assert(Seq(t.v0, t.v1, t.v2).forall(_.y == 548.7))
      assert(c.scene.material(i).ke == Vec3(170, 120, 40) && c.scene.material(i).kd == Vec3.zero)
    }
    assert(c.scene.emitters.map(c.scene.triangles(_).area).sum == 130.0 * 105.0)
    assert(c.scene.bounds == Box(Vec3(0, 0, 0), Vec3(556, 548.8, 559.2)))
  }

  private def sceneFile(body: String): java.nio.file.Path = {
    val d = tempDir()
    write(d, "scene.json", body.replace("OBJ", cornellObj.toAbsolutePath.toString))
  }

  private val minimal = """{"obj": "OBJ", "camera": {"position": [1, 2, 3], "lookAt": [1, 2, 10]}"""

  test("defaults fill every key but obj and camera; lookAt gives the direction") {
    val c = SceneConfig.load(sceneFile(minimal + "}"))
    val d = SceneConfig.Defaults
    assert(c.camera == Camera(Vec3(1, 2, 3), Vec3(0, 0, 1), d.up, d.fovDeg))
    assert((c.width, c.height, c.finalGatherRays, c.photons, c.maxBounces, c.seed, c.h, c.directLightSamples) ==
      ((d.width, d.height, d.finalGatherRays, d.photons, d.maxBounces, d.seed, d.h, d.directLightSamples)))
    assert(c.pointLights.isEmpty && c.format.isEmpty)
    val f = SceneConfig.load(sceneFile(minimal + """, "h": 12.5, "format": "bf16", "seed": -7}"""))
    assert(f.h == KernelRadius.Fixed(12.5) && f.format == Some(FloatFormat.bf16) && f.seed == -7)
  }

  test("a scene below zero is moved into the positive octant, camera and lights with it") {
    val d = tempDir()
    write(d, "neg.obj", "v -5 2 -1\nv 3 4 -1\nv -5 4 7\nf 1 2 3\n")
    val p = write(d, "s.json",
      """{"obj": "neg.obj", "camera": {"position": [0, 0, -10], "direction": [0, 0, 2], "fov": 60},
        | "lights": [{"type": "point", "position": [-1, -1, -1], "power": [1, 2, 3]},
        |            {"type": "area", "vertices": [[-6, 9, 0], [-6, 9, 1], [-5, 9, 0]], "radiance": [1, 1, 1]}]}""".stripMargin)
    val c = SceneConfig.load(p)
    assert(c.shift == Vec3(6, 0, 1))
    assert(c.scene.bounds.lo == Vec3(0, 2, 0))
    assert(c.scene.triangles(0) == Triangle(Vec3(1, 2, 0), Vec3(9, 4, 0), Vec3(1, 4, 8), 0))
    assert(c.camera.position == Vec3(6, 0, -9) && c.camera.direction == Vec3(0, 0, 1))
    assert(c.pointLights == Seq(PointLight(Vec3(5, -1, 0), Vec3(1, 2, 3))))
    assert(c.scene.triangles(1) == Triangle(Vec3(0, 9, 1), Vec3(0, 9, 2), Vec3(1, 9, 1), 1))
  }

  /** Loads a scene whose text has `OBJ` for the Cornell OBJ path; returns (file, message). */
  private def error(body: String): (String, String) = {
    val p = sceneFile(body)
    val e = intercept[MapmError](SceneConfig.load(p))
    assert(!e.getMessage.contains("\n"))
    (p.toString, e.getMessage)
  }

  test("each kind of bad value gives one line naming the scene file and the key") {
    val cases = Seq(
      minimal + """, "widht": 5}""" -> "widht",
      minimal + """, "width": 0}""" -> "width",
      minimal + """, "width": 2.5}""" -> "width",
      minimal + """, "height": "60"}""" -> "height",
      minimal + """, "finalGatherRays": 0}""" -> "finalGatherRays",
      minimal + """, "width": 100000, "height": 100000}""" -> "finalGatherRays",
      minimal + """, "photons": -1}""" -> "photons",
      minimal + """, "maxBounces": 0}""" -> "maxBounces",
      minimal + """, "h": -1}""" -> "h",
      minimal + """, "h": {"auto": 0}}""" -> "h.auto",
      minimal + """, "h": {"atuo": 5}}""" -> "h.atuo",
      minimal + """, "h": "big"}""" -> "h",
      minimal + """, "seed": 1.5}""" -> "seed",
      minimal + """, "format": "fp99"}""" -> "format",
      minimal + """, "defaultKd": [0.5, 2, 0.5]}""" -> "defaultKd",
      minimal + """, "lights": {}}""" -> "lights",
      minimal + """, "lights": [{"type": "spot"}]}""" -> "lights[0].type",
      minimal + """, "lights": [{"position": [0, 0, 0]}]}""" -> "lights[0].type",
      minimal + """, "lights": [{"type": "point", "position": [0, 0, 0], "power": [1, -1, 1]}]}""" -> "lights[0].power",
      minimal + """, "lights": [{"type": "point", "position": [0, 0, 1e999], "power": [1, 1, 1]}]}""" -> "lights[0].position[2]",
      minimal + """, "lights": [{"type": "point", "position": [0, 0], "power": [1, 1, 1]}]}""" -> "lights[0].position",
      minimal + """, "lights": [{"type": "point", "position": [0, 0, 0], "power": [1, 1, 1], "colour": 1}]}""" -> "lights[0].colour",
      minimal + """, "lights": [{"type": "area", "vertices": [[0, 0, 0], [1, 0, 0]], "radiance": [1, 1, 1]}]}""" -> "lights[0].vertices",
      minimal + """, "lights": [{"type": "area", "vertices": [[0, 0, 0], [1, 0, 0], [2, 0, 0]], "radiance": [1, 1, 1]}]}""" -> "lights[0].vertices",
      minimal + """, "lights": [{"type": "area", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 1]], "radiance": [1, 1, 1]}]}""" -> "lights[0].vertices",
      minimal + """, "lights": [{"type": "area", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0]], "radiance": [1, -1, 1]}]}""" -> "lights[0].radiance",
      """{"camera": {"position": [1, 2, 3], "lookAt": [1, 2, 10]}}""" -> "obj",
      """{"obj": 5, "camera": {"position": [1, 2, 3], "lookAt": [1, 2, 10]}}""" -> "obj",
      """{"obj": "OBJ"}""" -> "camera",
      """{"obj": "OBJ", "camera": {"lookAt": [1, 2, 10]}}""" -> "camera.position",
      """{"obj": "OBJ", "camera": {"position": [1, 2, 3]}}""" -> "camera",
      """{"obj": "OBJ", "camera": {"position": [1, 2, 3], "lookAt": [1, 2, 3]}}""" -> "camera.lookAt",
      """{"obj": "OBJ", "camera": {"position": [1, 2, 3], "direction": [0, 0, 0]}}""" -> "camera.direction",
      """{"obj": "OBJ", "camera": {"position": [1, 2, 3], "direction": [0, 0, 1], "lookAt": [0, 0, 9]}}""" -> "camera",
      """{"obj": "OBJ", "camera": {"position": [1, 2, 3], "direction": [0, 1, 0]}}""" -> "camera.up",
      """{"obj": "OBJ", "camera": {"position": [1, 2, 3], "direction": [0, 0, 1], "fov": 180}}""" -> "camera.fov",
      """{"obj": "OBJ", "camera": {"position": [1, 2, 3], "direction": [0, 0, 1], "fov": 0}}""" -> "camera.fov",
      """{"obj": "OBJ", "camera": {"position": [1, 2, 3], "direction": [0, 0, 1], "fov": -5}}""" -> "camera.fov",
      """{"obj": "OBJ", "camera": {"position": [1, 2, 3], "direction": [0, 0, 1], "zoom": 2}}""" -> "camera.zoom",
      """[1, 2]""" -> "(top level)")
    for ((body, key) <- cases) {
      val (file, msg) = error(body)
      assert(msg.startsWith(s"$file: key '$key': "), s"'$msg' should name key '$key' for $body")
    }
  }

  test("broken JSON, a missing scene file and a missing OBJ are reported with the file") {
    val (file, msg) = error("{\n \"obj\": \"OBJ\",\n \"camera\": {]\n}")
    assert(msg.startsWith(s"$file:3: invalid JSON"), msg)
    val (file2, msg2) = error("{\"obj\": \"OBJ\"")
    assert(msg2.startsWith(s"$file2: invalid JSON"), msg2)
    val nope = tempDir().resolve("none.json")
    assert(intercept[MapmError](SceneConfig.load(nope)).getMessage == s"$nope: scene file not found")
    val d = tempDir()
    val p = write(d, "s.json", """{"obj": "gone.obj", "camera": {"position": [0, 0, 0], "direction": [0, 0, 1]}}""")
    val e = intercept[MapmError](SceneConfig.load(p)).getMessage
    assert(e.contains(d.resolve("gone.obj").toString) && e.contains("not found"), e)
  }
}
