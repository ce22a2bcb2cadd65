package mapm.model

import mapm.numerics._

import java.nio.{ByteBuffer, ByteOrder}
import java.nio.file.Files

import mapm.MapmError
import org.scalatest.funsuite.AnyFunSuite

class ImageIOSpec extends AnyFunSuite {
  private val img = RgbImage(3, 2, Array(
    Vec3(1, 2, 3), Vec3(0.5, 0.25, 0.125), Vec3(0, 0, 0),
    Vec3(-1, 1e-3, 65504), Vec3(7, 8, 9), Vec3(0.1f.toDouble, 0.2f.toDouble, 0.3f.toDouble)))

  test("PFM: header, little-endian floats, bottom row first; read back exactly") {
    val p = TestScenes.tempDir().resolve("a.pfm")
    ImageIO.writePfm(p, img)
    val bytes = Files.readAllBytes(p)
    val header = "PF\n3 2\n-1.0\n"
    assert(new String(bytes, 0, header.length, "US-ASCII") == header)
    assert(bytes.length == header.length + 3 * 2 * 12)
    val data = ByteBuffer.wrap(bytes, header.length, 72).order(ByteOrder.LITTLE_ENDIAN)
    // first stored pixel: bottom-left = pixel (0, 1)
    assert(data.getFloat == -1f && data.getFloat == 1e-3f && data.getFloat == 65504f)
    assert(bytes(header.length + 3) == 0xbf.toByte && bytes(header.length) == 0) // -1.0f = 0xbf800000, LSB first
    val back = ImageIO.readPfm(p)
    assert(back.width == 3 && back.height == 2)
    for (i <- 0 until 6; c <- 0 until 3) assert(back.pixels(i)(c) == img.pixels(i)(c).toFloat.toDouble)
  }

  test("PFM reading: big-endian and greyscale files; broken files are refused") {
    val d = TestScenes.tempDir()
    val head = "Pf\n2 1\n1.0\n".getBytes("US-ASCII")
    val be = ByteBuffer.allocate(head.length + 8).order(ByteOrder.BIG_ENDIAN)
    be.put(head).putFloat(0.5f).putFloat(2f)
    val p = TestScenes.write(d, "g.pfm", "")
    Files.write(p, be.array())
    val g = ImageIO.readPfm(p)
    assert(g.pixels.toSeq == Seq(Vec3(0.5, 0.5, 0.5), Vec3(2, 2, 2)))
    for ((name, text) <- Seq("short.pfm" -> "PF\n2 2\n-1.0\nabc", "magic.pfm" -> "P6\n2 2\n255\n", "dims.pfm" -> "PF\n0 2\n-1\n")) {
      val e = intercept[MapmError](ImageIO.readPfm(TestScenes.write(d, name, text)))
      assert(e.getMessage.contains(name) && e.getMessage.contains("not a valid PFM"))
    }
    assert(intercept[MapmError](ImageIO.readPfm(d.resolve("none.pfm"))).getMessage.contains("cannot read"))
  }

  test("tone map: the 99th-percentile luminance maps to 0.9, gamma 2.2, clamped; PNG holds those bytes") {
    // 100 pixels: luminance i/100 for grey pixels i = 0..99; the 99th percentile is pixel 98 (0.98).
    val pix = Array.tabulate(100)(i => Vec3(i / 100.0, i / 100.0, i / 100.0))
    pix(99) = Vec3(50, 0, 0) // a hot red pixel, luminance 0.2126 * 50 = 10.63: the largest
    val im = RgbImage(10, 10, pix)
    val s = 0.9 / 0.98
    assert(math.abs(ImageIO.exposure(pix) - s) < 1e-15)
    val t = ImageIO.toneMap(im)
    def byte(v: Double) = math.round(255 * math.pow(math.min(1, v * s), 1 / 2.2)).toInt
    for (i <- 0 until 99) assert(t(i) == byte(i / 100.0) * 0x010101, s"pixel $i")
    assert(t(98) == byte(0.98) * 0x010101 && byte(0.98) == math.round(255 * math.pow(0.9, 1 / 2.2)).toInt)
    assert(t(99) == 0xff0000)
    val p = TestScenes.tempDir().resolve("a.png")
    ImageIO.writePng(p, im)
    val read = javax.imageio.ImageIO.read(p.toFile)
    for (i <- 0 until 100) assert((read.getRGB(i % 10, i / 10) & 0xffffff) == t(i))
    // black stays black, NaN becomes black
    assert(ImageIO.toneMap(RgbImage(1, 2, Array(Vec3.zero, Vec3(Double.NaN, 0, 0)))).toSeq == Seq(0, 0))
  }
}
