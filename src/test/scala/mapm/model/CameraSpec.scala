package mapm.model

import mapm.numerics._

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

class CameraSpec extends AnyFunSuite {
  private val cam = SceneConfig.load(TestScenes.cornellScene).camera

  test("the centre ray of the default camera points along +z") {
    assert(cam.rayDirection(37.5, 30, 75, 60) == Vec3(0, 0, 1))
    assert(cam.pixelDirection(37, 30, 75, 61) == Vec3(0, 0, 1))
  }

  test("edge rays make half the field of view with the axis; image x runs to -x (red wall left)") {
    val half = math.toRadians(39.3) / 2
    val top = cam.rayDirection(37.5, 0, 75, 60)
    assert(math.abs(math.acos(top.z) - half) < 1e-12 && top.y > 0 && top.x == 0)
    val bottom = cam.rayDirection(37.5, 60, 75, 60)
    assert(math.abs(math.acos(bottom.z) - half) < 1e-12 && bottom.y < 0)
    // Horizontal: tan(angle) = tan(fov/2) * width / height.
    val left = cam.rayDirection(0, 30, 75, 60)
    assert(math.abs(left.x / left.z - math.tan(half) * 75 / 60) < 1e-12 && left.x > 0 && left.y == 0)
    // Pixel (0,0): top left, centre half a pixel in: tan = tan(fov/2) * (1 - 1/75) * 75/60 across, (1 - 1/60) up.
    val p = cam.pixelDirection(0, 0, 75, 60)
    assert(math.abs(p.x / p.z - math.tan(half) * (1 - 1.0 / 75) * 75 / 60) < 1e-12)
    assert(math.abs(p.y / p.z - math.tan(half) * (1 - 1.0 / 60)) < 1e-12)
  }

  test("a camera with up along its direction is refused") {
    intercept[MapmError](Camera(Vec3.zero, Vec3(0, 1, 0), Vec3(0, 1, 0), 40))
  }

  test("the Cornell centre ray hits the tall block's front face at z = 296 - 49 * 13 / 158") {
    val scene = ObjLoader.load(TestScenes.cornellObj, Vec3.one)
    val tree = TriKdTree.build(scene)
    val hits = PrimaryHits.trace(tree, cam, 75, 61)
    val centre = 30 * 75 + 37
    assert(hits.hit(centre))
    val p = hits.position(centre)
    assert(p.x == 278 && p.y == 273 && math.abs(p.z - (296 - 49.0 * 13 / 158)) < 1e-9, s"$p")
    // normal of the face from (265,*,296) to (423,*,247), turned to the camera: (-49, 0, -158)/|.|
    val n = Vec3(-49, 0, -158).normalized
    assert((hits.normal(centre) - n).length < 1e-12)
    assert(hits.triangle.forall(_ >= 0), "every primary ray of this camera enters the box")
  }
}
