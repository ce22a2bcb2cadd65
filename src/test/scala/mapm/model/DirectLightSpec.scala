package mapm.model

import mapm.numerics._

import org.scalatest.funsuite.AnyFunSuite

class DirectLightSpec extends AnyFunSuite {
  private val grey = Material("floor", Vec3(0.5, 0.4, 0.3), Vec3.zero)
  /** A 200 x 200 floor at y = 0 centred on x = z = 100, and a camera 50 above looking straight down. */
  private def floor(extra: Seq[Triangle], mats: Vector[Material]) = {
    val a = Vec3(0, 0, 0); val b = Vec3(200, 0, 0); val c = Vec3(200, 0, 200); val d = Vec3(0, 0, 200)
    Scene(Vector(Triangle(a, b, c, 0), Triangle(a, c, d, 0)) ++ extra, grey +: mats)
  }
  private val cam = Camera(Vec3(100, 50, 100), Vec3(0, -1, 0), Vec3(0, 0, 1), 30)
  private val centre = 2 * 5 + 2 // pixel (2,2) of a 5 x 5 image looks straight down at (100, 0, 100)

  test("point light straight above: Kd/pi * 1/r^2 * P/(4 pi); blocked by an occluder: black") {
    val tree = TriKdTree.build(floor(Nil, Vector.empty))
    val prim = PrimaryHits.trace(tree, cam, 5, 5)
    assert(prim.position(centre) == Vec3(100, 0, 100))
    val light = PointLight(Vec3(100, 20, 100), Vec3(1000, 2000, 3000))
    val img = DirectLight.render(tree, prim, Seq(light), 0, 1)
    val want = Vec3(0.5 * 1000, 0.4 * 2000, 0.3 * 3000) / math.Pi / 400 / (4 * math.Pi)
    assert((img(centre) - want).length < 1e-9 * want.length)
    // Off centre: cos = 20 / r.
    val corner = prim.position(0)
    val r = (light.position - corner).length
    val wantCorner = Vec3(0.5 * 1000, 0.4 * 2000, 0.3 * 3000) / math.Pi * (20 / r) / (r * r) / (4 * math.Pi)
    assert((img(0) - wantCorner).length < 1e-6 * wantCorner.length)
    // A small occluder at y = 10 over the centre blocks only the centre pixel's light.
    val occ = Triangle(Vec3(95, 10, 95), Vec3(105, 10, 95), Vec3(100, 10, 106), 0)
    val tree2 = TriKdTree.build(floor(Seq(occ), Vector.empty))
    val below = cam.copy(position = Vec3(100, 5, 100), fovDeg = 160) // under the occluder, seeing the floor
    val img2 = DirectLight.render(tree2, PrimaryHits.trace(tree2, below, 5, 5), Seq(light), 0, 1)
    assert(img2(centre) == Vec3.zero && img2(0).maxComponent > 0)
    // A light below the floor gives nothing.
    assert(DirectLight.render(tree, prim, Seq(PointLight(Vec3(100, -5, 100), Vec3.one)), 0, 1).forall(_ == Vec3.zero))
  }

  test("rectangular area light above the pixel: Kd * L * form factor (closed form), sampled") {
    // Lamp 40 x 60 centred above (100, 0, 100) at height 30, facing down: four corner rectangles of 20 x 30.
    val h = 30.0
    val (x0, x1, z0, z1) = (80.0, 120.0, 70.0, 130.0)
    val lampV = Seq(Vec3(x0, h, z0), Vec3(x1, h, z0), Vec3(x1, h, z1), Vec3(x0, h, z1))
    val lamp = Seq(Triangle(lampV(0), lampV(1), lampV(2), 1), Triangle(lampV(0), lampV(2), lampV(3), 1))
    assert(lamp.forall(_.normal == Vec3(0, -1, 0)))
    val ke = Vec3(3, 2, 1)
    val tree = TriKdTree.build(floor(lamp, Vector(Material("lamp", Vec3.zero, ke))))
    // Keep the camera below the lamp so that it sees the floor.
    val camLow = cam.copy(position = Vec3(100, 25, 100))
    val prim = PrimaryHits.trace(tree, camLow, 5, 5)
    val img = DirectLight.render(tree, prim, Nil, 20000, 1)
    // Differential area to a parallel rectangle of sides a, b over one of its corners at distance h.
    def corner(a: Double, b: Double): Double = {
      val (x, y) = (a / h, b / h)
      (x / math.sqrt(1 + x * x) * math.atan(y / math.sqrt(1 + x * x)) + y / math.sqrt(1 + y * y) * math.atan(x / math.sqrt(1 + y * y))) / (2 * math.Pi)
    }
    val f = 4 * corner(20, 30)
    val want = Vec3(0.5, 0.4, 0.3).mul(ke) * f
    for (c <- 0 until 3) assert(math.abs(img(centre)(c) / want(c) - 1) < 0.02, s"${img(centre)} vs $want")
  }

  test("an emitter seen from its front shows Ke, from the back nothing of its own") {
    val lampDown = Seq(Triangle(Vec3(0, 10, 0), Vec3(200, 10, 0), Vec3(200, 10, 200), 1),
      Triangle(Vec3(0, 10, 0), Vec3(200, 10, 200), Vec3(0, 10, 200), 1))
    val ke = Vec3(5, 6, 7)
    val tree = TriKdTree.build(floor(lampDown, Vector(Material("lamp", Vec3.zero, ke))))
    // From below, looking up at its front.
    val up = Camera(Vec3(100, 5, 100), Vec3(0, 1, 0), Vec3(0, 0, 1), 30)
    assert(DirectLight.render(tree, PrimaryHits.trace(tree, up, 3, 3), Nil, 4, 1).forall(_ == ke))
    // From above, its back: black (Kd = 0 and no light above).
    assert(DirectLight.render(tree, PrimaryHits.trace(tree, cam, 3, 3), Nil, 4, 1).forall(_ == Vec3.zero))
  }
}
