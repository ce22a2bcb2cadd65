package mapm.model

import mapm.numerics._

/** The shader arithmetic of the conventional SOA (`mapm.shader.SOA` with conventional arithmetic),
  * bit for bit: the colour of [[ConvChainModel]] (four correctly rounded operations per channel,
  * the online chain's special cases and flags) and the cond check of [[CondModelCond]].
  *
  * The shared part t2 = RN(RN(kernel * BRDF) / h) of the last (kernel, BRDF, h) is kept: it is the
  * same for every photon of a [[PhotonMap]]. Thread-safe: one immutable record behind a volatile
  * field (a thread that misses recomputes the same value).
  */
final class ConvShadeArith(val format: FloatFormat) extends CondModelCond {
  import ConvShadeArith.Front

  @volatile private var last: Front = new Front(0L, 0L, 0L, ConvChainModel.front(format, 0L, 0L, 0L))

  private def front(kernel: Long, brdf: Long, h: Long): Long = {
    val c = last
    if (c.kernel == kernel && c.brdf == brdf && c.h == h) c.t2
    else { val t2 = ConvChainModel.front(format, kernel, brdf, h); last = new Front(kernel, brdf, h, t2); t2 }
  }

  private def channel(kernel: Long, brdf: Long, h: Long, t2: Long, power: Long, contrib: Long): ShaderChainModel.Result =
    ConvChainModel.channel(format, kernel, brdf, h, t2, power, contrib)

  def color(kernel: Long, brdf: Long, h: Long, power: Long, contrib: Long): Long =
    channel(kernel, brdf, h, front(kernel, brdf, h), power, contrib).bits

  override def shade(kernel: Long, brdf: Long, h: Long, pr: Long, pg: Long, pb: Long, cr: Long, cg: Long, cb: Long,
                     out: Array[Long]): Unit = {
    val t2 = front(kernel, brdf, h)
    out(0) = channel(kernel, brdf, h, t2, pr, cr).bits
    out(1) = channel(kernel, brdf, h, t2, pg, cg).bits
    out(2) = channel(kernel, brdf, h, t2, pb, cb).bits
  }

  override def hasFlags: Boolean = true

  override def shadeFlags(kernel: Long, brdf: Long, h: Long, pr: Long, pg: Long, pb: Long, cr: Long, cg: Long, cb: Long,
                          out: Array[Long], flags: Array[Int]): Unit = {
    val t2 = front(kernel, brdf, h)
    val r = channel(kernel, brdf, h, t2, pr, cr); out(0) = r.bits; flags(0) = r.flags
    val g = channel(kernel, brdf, h, t2, pg, cg); out(1) = g.bits; flags(1) = g.flags
    val b = channel(kernel, brdf, h, t2, pb, cb); out(2) = b.bits; flags(2) = b.flags
  }
}

object ConvShadeArith {
  private final class Front(val kernel: Long, val brdf: Long, val h: Long, val t2: Long)
}
