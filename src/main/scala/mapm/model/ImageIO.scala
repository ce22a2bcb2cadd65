package mapm.model

import mapm.numerics._

import java.io.{BufferedOutputStream, IOException}
import java.nio.{ByteBuffer, ByteOrder}
import java.nio.file.{Files, Path}

import mapm.MapmError

/** An RGB image, row-major from the top-left pixel (index y * width + x). */
final case class RgbImage(width: Int, height: Int, pixels: Array[Vec3]) {
  require(width > 0 && height > 0 && pixels.length == width * height, s"image ${width}x$height needs ${width * height} pixels")
}

/** Image files: PFM for the exact floating-point result, PNG for looking at it.
  *
  * PFM (Portable Float Map): the ASCII header `PF\n<width> <height>\n-1.0\n` followed by
  * width * height * 3 IEEE single-precision floats (R, G, B per pixel). The negative scale declares
  * little-endian byte order, which is what is written. As the format prescribes, rows are stored
  * bottom to top: the file starts with the image's last row (y = height - 1). Reading accepts
  * either byte order (the sign of the scale) and greyscale `Pf` files (copied to all three channels).
  *
  * PNG (8-bit sRGB-ish): a simple, documented tone map. The luminance of each pixel is
  * Y = 0.2126 R + 0.7152 G + 0.0722 B; the image is scaled so that the 99th-percentile luminance
  * becomes 0.9 (the brightest 1% may clip, which keeps a few hot pixels, such as a light source
  * seen directly, from darkening the rest); then each channel is clamped to [0,1], raised to
  * 1/2.2 (display gamma 2.2) and rounded to 0..255. An all-black image stays black.
  */
object ImageIO {
  val Gamma = 2.2
  val Percentile = 0.99
  val PercentileTarget = 0.9

  def luminance(c: Vec3): Double = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z

  def writePfm(path: Path, image: RgbImage): Unit = {
    val header = s"PF\n${image.width} ${image.height}\n-1.0\n".getBytes("US-ASCII")
    val buf = ByteBuffer.allocate(header.length + 12 * image.pixels.length).order(ByteOrder.LITTLE_ENDIAN)
    buf.put(header)
    for (y <- image.height - 1 to 0 by -1; x <- 0 until image.width) {
      val c = image.pixels(y * image.width + x)
      buf.putFloat(c.x.toFloat).putFloat(c.y.toFloat).putFloat(c.z.toFloat)
    }
    write(path, buf.array())
  }

  def readPfm(path: Path): RgbImage = {
    val bytes =
      try Files.readAllBytes(path)
      catch { case e: IOException => MapmError.fail(s"$path: cannot read (${e.getMessage})") }
    def bad(msg: String): Nothing = MapmError.fail(s"$path: not a valid PFM file ($msg)")
    // Header: four whitespace-separated tokens, then exactly one whitespace byte before the data.
    var pos = 0
    def token(): String = {
      while (pos < bytes.length && Character.isWhitespace(bytes(pos).toChar)) pos += 1
      val start = pos
      while (pos < bytes.length && !Character.isWhitespace(bytes(pos).toChar)) pos += 1
      if (start == pos) bad("header ends early")
      new String(bytes, start, pos - start, "US-ASCII")
    }
    val channels = token() match { case "PF" => 3; case "Pf" => 1; case m => bad(s"magic '$m'") }
    val width = token().toIntOption.filter(_ > 0).getOrElse(bad("width"))
    val height = token().toIntOption.filter(_ > 0).getOrElse(bad("height"))
    val scale = token().toDoubleOption.filter(s => s != 0 && !s.isNaN).getOrElse(bad("scale"))
    pos += 1
    val need = width.toLong * height * channels * 4
    if (bytes.length - pos != need) bad(s"expected $need data bytes, found ${bytes.length - pos}")
    val buf = ByteBuffer.wrap(bytes, pos, need.toInt).order(if (scale < 0) ByteOrder.LITTLE_ENDIAN else ByteOrder.BIG_ENDIAN)
    val pixels = new Array[Vec3](width * height)
    for (y <- height - 1 to 0 by -1; x <- 0 until width) {
      pixels(y * width + x) =
        if (channels == 3) Vec3(buf.getFloat.toDouble, buf.getFloat.toDouble, buf.getFloat.toDouble)
        else { val g = buf.getFloat.toDouble; Vec3(g, g, g) }
    }
    RgbImage(width, height, pixels)
  }

  /** The factor the tone map multiplies radiance by: PercentileTarget over the 99th-percentile
    * luminance (over the maximum if that percentile is zero; 1 for a black image). */
  def exposure(pixels: Array[Vec3]): Double = {
    val lum = pixels.map(c => { val y = luminance(c); if (y.isNaN) 0.0 else y }).sorted
    if (lum.isEmpty) return 1.0
    val p = lum(math.max(0, math.ceil(Percentile * lum.length).toInt - 1))
    val ref = if (p > 0) p else lum.last
    if (ref > 0 && !ref.isInfinite) PercentileTarget / ref else 1.0
  }

  /** Tone-mapped 8-bit RGB per pixel, packed 0xRRGGBB. */
  def toneMap(image: RgbImage): Array[Int] = {
    val s = exposure(image.pixels)
    def channel(v: Double): Int = {
      val c = v * s
      val clamped = if (c > 1) 1.0 else if (c > 0) c else 0.0 // NaN -> 0
      math.round(255 * math.pow(clamped, 1 / Gamma)).toInt
    }
    image.pixels.map(c => (channel(c.x) << 16) | (channel(c.y) << 8) | channel(c.z))
  }

  def writePng(path: Path, image: RgbImage): Unit = {
    val img = new java.awt.image.BufferedImage(image.width, image.height, java.awt.image.BufferedImage.TYPE_INT_RGB)
    img.setRGB(0, 0, image.width, image.height, toneMap(image), 0, image.width)
    val out = new java.io.ByteArrayOutputStream()
    if (!javax.imageio.ImageIO.write(img, "png", out)) MapmError.fail(s"$path: no PNG writer available")
    write(path, out.toByteArray)
  }

  private def write(path: Path, data: Array[Byte]): Unit =
    try {
      Option(path.toAbsolutePath.getParent).foreach(Files.createDirectories(_))
      val out = new BufferedOutputStream(Files.newOutputStream(path))
      try out.write(data) finally out.close()
    } catch { case e: IOException => MapmError.fail(s"$path: cannot write (${e.getMessage})") }
}
