package mapm.model

import mapm.numerics._

/** The shader arithmetic of the hardware SOA (`mapm.shader.SOA`), bit for bit:
  *  - color / shade: the online colour chain [[ShaderChainModel]] with `g` guard digits
  *    (truncated result, the SOA's special cases and flags, see docs/soa.md);
  *  - cond: [[CondModel]], the correctly rounded sequence of the conventional units
  *    (`mapm.shader.CondCheck`).
  *
  * The part of the chain shared by the three channels (MUL1, the divider, QN) depends on kernel,
  * BRDF and h alone, which are the same for every photon of a [[PhotonMap]] (a constant disc
  * kernel, a Lambertian BRDF, one h; see [[Shading]]): the last one computed is kept and reused
  * while its inputs repeat. With it, MUL2 (Q' × power) depends on the photon's power alone; its
  * products are kept per power value (up to [[HardwareShadeArith.Mul2Entries]] of them), so a
  * photon met by many queries costs one MUL3 per channel. Finished channels are kept too, per
  * (power, contribution), in a direct-mapped table of [[HardwareShadeArith.DoneSlots]] entries, so a
  * repeated pair costs one lookup. Thread-safe: the cache is one record behind a volatile field with
  * a concurrent map and a table of immutable entries (a thread that misses recomputes the same value).
  */
final class HardwareShadeArith(val format: FloatFormat, val g: Int) extends CondModelCond {
  import HardwareShadeArith.Cached

  /** The colour chain's model. */
  val chain: ShaderChainModel = new ShaderChainModel(format, g)

  @volatile private var cached: Cached = new Cached(0L, 0L, 0L, chain.front(0L, 0L, 0L))

  /** The cache record for (kernel, BRDF, h): the shared part of the chain and its MUL2 products. */
  private def lookup(kernel: Long, brdf: Long, h: Long): Cached = {
    val c = cached
    if (c.kernel == kernel && c.brdf == brdf && c.h == h) c
    else {
      val fresh = new Cached(kernel, brdf, h, chain.front(kernel, brdf, h))
      cached = fresh
      fresh
    }
  }

  /** The shared part of the chain for (kernel, BRDF, h), from the cache when it repeats. */
  def front(kernel: Long, brdf: Long, h: Long): ShaderChainModel.Front = lookup(kernel, brdf, h).front

  /** One channel: from the record's table of finished channels when (power, contribution) is
    * there, else through the cached front and MUL2 product (and then into the table). */
  private def channel(c: Cached, power: Long, contrib: Long): ShaderChainModel.Result = {
    val slot = HardwareShadeArith.slot(power, contrib)
    val e = c.done(slot)
    if (e != null && e.power == power && e.contrib == contrib) e.result
    else {
      val r = compute(c, power, contrib)
      c.done(slot) = new HardwareShadeArith.Done(power, contrib, r)
      r
    }
  }

  /** One channel through the cached front and MUL2 product. */
  private def compute(c: Cached, power: Long, contrib: Long): ShaderChainModel.Result = {
    var p2 = c.mul2.get(power)
    if (p2 == null) {
      p2 = chain.mul2(c.front, power)
      if (p2 != null && c.mul2.size < HardwareShadeArith.Mul2Entries) c.mul2.put(power, p2)
    }
    chain.channel(c.front, power, p2, contrib)
  }

  def color(kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long): Long =
    channel(lookup(kernel, brdf, h), power, contrib).bits

  override def shade(kernel: Long, brdf: Long, h: Long, pr: Long, pg: Long, pb: Long, cr: Long, cg: Long, cb: Long,
                     out: Array[Long]): Unit = {
    val f = lookup(kernel, brdf, h)
    out(0) = channel(f, pr, cr).bits; out(1) = channel(f, pg, cg).bits; out(2) = channel(f, pb, cb).bits
  }

  /** Decodes the channels of [[shadeValues]] (the fast decoder of the format). */
  private val codec = new FormatBits(format)

  override def shadeValues(kernel: Long, brdf: Long, h: Long, pr: Long, pg: Long, pb: Long, cr: Long, cg: Long, cb: Long,
                           bits: Array[Long], values: Array[Double]): Unit = {
    shade(kernel, brdf, h, pr, pg, pb, cr, cg, cb, bits)
    values(0) = codec.toDouble(bits(0)); values(1) = codec.toDouble(bits(1)); values(2) = codec.toDouble(bits(2))
  }

  override def hasFlags: Boolean = true

  override def shadeFlags(kernel: Long, brdf: Long, h: Long, pr: Long, pg: Long, pb: Long, cr: Long, cg: Long, cb: Long,
                          out: Array[Long], flags: Array[Int]): Unit = {
    val f = lookup(kernel, brdf, h)
    val r = channel(f, pr, cr); out(0) = r.bits; flags(0) = r.flags
    val gr = channel(f, pg, cg); out(1) = gr.bits; flags(1) = gr.flags
    val b = channel(f, pb, cb); out(2) = b.bits; flags(2) = b.flags
  }
}

/** The cond check of both SOAs, online and conventional: [[CondModel]], the correctly rounded
  * sequence of the conventional units (`mapm.shader.CondCheck`).
  *
  * [[condClearBounds]]: CondModel rounds the same five operations to nearest with flush to zero
  * as [[RoundedShadeArith]] does (each within a factor 1 -/+ u, flushed terms below 5 smallest
  * normals, inputs with exponent field 0 read as zero, exactly as [[FloatFormat.decode]] reads
  * them), so the same bounds hold: d2 < lo surely passes, d2 > hi surely fails. */
trait CondModelCond extends ShadeArith {
  private lazy val u = math.pow(2, -format.manWidth - 1)
  private lazy val condHi = math.pow(1 + u, 6) * (1 + 1e-12)
  private lazy val condLo = math.pow(1 - u, 6) * (1 - 1e-12)
  private lazy val condAbs = 8 * format.minNormal

  def cond(qx: Long, qy: Long, qz: Long, px: Long, py: Long, pz: Long, h: Long): Boolean =
    CondModel.cond(format, qx, qy, qz, px, py, pz, h)

  override def condClearBounds(h: Long): (Double, Double) = {
    val hh = SoftFloat.mul(format, h, h)
    if (format.expField(hh) == format.expMax) super.condClearBounds(h)
    else {
      val h2 = format.decode(hh)
      ((h2 - condAbs) / condHi, (h2 + condAbs) / condLo)
    }
  }
}

object HardwareShadeArith {
  /** The most MUL2 products kept per (kernel, BRDF, h). */
  val Mul2Entries = 1 << 16

  /** Slots of the table of finished channels per (kernel, BRDF, h) (a power of two). */
  val DoneSlots: Int = 1 << 14

  /** The slot of (power, contribution) in the table of finished channels (a multiplicative hash). */
  private def slot(power: Long, contrib: Long): Int =
    (((power * 0x9E3779B97F4A7C15L) ^ (contrib * 0xC2B2AE3D27D4EB4FL)) >>> (64 - 14)).toInt

  /** A finished channel: the chain's result for (power, contribution) under one front. Immutable
    * (final fields), so a thread that reads a slot another one is writing sees a whole entry, the
    * old one or the new one, and checks its key. */
  private final class Done(val power: Long, val contrib: Long, val result: ShaderChainModel.Result)

  /** The cache of one (kernel, BRDF, h): the shared part of the chain, its MUL2 products per power,
    * and a direct-mapped table of finished channels per (power, contribution): the chain is a pure
    * function of its inputs, and a scene has few distinct photon powers and contributions (products
    * of light powers, material colours and 1/N), so most channels of a frame repeat one already done. */
  private final class Cached(val kernel: Long, val brdf: Long, val h: Long, val front: ShaderChainModel.Front) {
    val mul2 = new java.util.concurrent.ConcurrentHashMap[java.lang.Long, DigitString]()
    val done = new Array[Done](DoneSlots)
  }
}
