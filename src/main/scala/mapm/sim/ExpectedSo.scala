package mapm.sim

import java.nio.{ByteBuffer, ByteOrder}
import java.nio.file.{Files, Path}

import mapm.MapmError
import mapm.format.ExpectedSoFile
import mapm.model._
import mapm.numerics._
/** The shader operations the MAPM must report for a frame, computed by the model in the
  * hardware's arithmetic, and the model frame accumulated from them exactly ([[ExactSum]]).
  *
  * Per query: the tree search ([[TreeSearcher]]) gives the photons; each SO's colour bits and
  * flags come from the SOA's arithmetic ([[ShadeArith.hardware]]: the online chain with g guard
  * digits, or the conventional chain) and its cond from [[CondModel]] (the SOA's cond check),
  * whatever cond is, as the hardware reports every SO. The
  * file is an [[ExpectedSoFile]], records sorted by (query, photon).
  */
object ExpectedSo {
  /** @param count   SOs (records written)
    * @param tsOps   tree-search operations of the model
    * @param passing SOs whose cond holds
    * @param frame   the model frame: per pixel and channel, the exact sum of the passing colours,
    *                rounded once (`frame(3 p + c)`) */
  final case class Result(count: Long, tsOps: Long, passing: Long, frame: Array[Double], coproc: Option[CoprocFrame])

  /** The frame as the coprocessor makes it ([[FrameAccum]], docs/coprocessor.md): the frame buffer's
    * values decoded (`frame(3 p + c)`), at `scale`, the one [[FrameAccum.scaleFor]] gives the
    * largest passing colour, and the faults the accumulation saw. */
  final case class CoprocFrame(frame: Array[Double], scale: Int, faults: Int)

  /** Computes every SO of `queries` against `map` in arithmetic `arith` (online with `g` guard
    * digits, or conventional) on `threads` threads, writes them to `file` for a `width` x `height`
    * image and returns the counts and model frame. */
  def write(map: PhotonMap, queries: QuerySet, g: Int, width: Int, height: Int, file: Path, threads: Int,
            progress: Option[String] = None, arith: Arith = Arith.Online, coproc: Boolean = false): Result = {
    MapmError.check(map.format == queries.format, s"expected SOs: photon map (${map.format}) and queries (${queries.format}) differ in format")
    val fmt = map.format
    val codec = new ExpectedSoFile.Codec(fmt)
    val shade = ShadeArith.hardware(fmt, g, arith)
    val nq = queries.size
    val chunk = 512
    val chunks = (nq + chunk - 1) / chunk
    val buffers = new Array[Array[Byte]](chunks)
    val tsOps = new java.util.concurrent.atomic.AtomicLong(0)
    val bar = progress.map(new Progress(_, nq.toLong))
    val searchers = ThreadLocal.withInitial(() => new TreeSearcher(map.search))
    Parallel.forRange(chunks, threads, chunk = 1) { c =>
      val (from, until) = (c * chunk, math.min(nq, (c + 1) * chunk))
      buffers(c) = chunkRecords(map, queries, shade, codec, searchers.get, from, until, tsOps)
      bar.foreach(_.advance((until - from).toLong))
    }
    bar.foreach(_.finish())
    val rec = codec.record.bytes
    val count = buffers.map(_.length.toLong / rec).sum
    val sum = new ExactSum(fmt, 3 * width * height)
    var passing = 0L
    try {
      val out = new java.io.BufferedOutputStream(Files.newOutputStream(file), 1 << 20)
      try {
        out.write(ExpectedSoFile.headerBytes(fmt, count, width, height))
        for (b <- buffers) {
          out.write(b)
          val r = ByteBuffer.wrap(b).order(ByteOrder.LITTLE_ENDIAN)
          for (at <- 0 until b.length by rec if codec.cond(r, at)) {
            passing += 1
            val q = codec.query(r, at)
            val p = queries.pixel(q)
            MapmError.check(p >= 0 && p < width * height, s"query $q: pixel $p outside the ${width}x$height image")
            for (ch <- 0 until 3) sum.add(3 * p + ch, codec.colour(r, at, ch))
          }
        }
      } finally out.close()
    } catch { case e: java.io.IOException => MapmError.fail(s"cannot write expected SOs $file: ${e.getMessage}") }
    // The coprocessor's frame, where a run asks for it: the scale from the largest passing colour,
    // then every colour again.
    def coprocFrame: CoprocFrame = {
      val fa = FrameAccum.default(fmt)
      var maxAbs = 0.0
      def passingColours(f: (Int, Seq[Long]) => Unit): Unit = for (b <- buffers) {
        val r = ByteBuffer.wrap(b).order(ByteOrder.LITTLE_ENDIAN)
        for (at <- 0 until b.length by rec if codec.cond(r, at)) f(queries.pixel(codec.query(r, at)), Seq.tabulate(3)(ch => codec.colour(r, at, ch)))
      }
      passingColours((_, cs) => cs.foreach(c => if (fmt.isFinite(c)) maxAbs = math.max(maxAbs, math.abs(fmt.decode(c)))))
      val scale = fa.scaleFor(maxAbs)
      val sums = new FrameSums(fa, width * height, 3, scale)
      passingColours((p, cs) => sums.add(p, cs))
      CoprocFrame(Array.tabulate(3 * width * height)(i => fmt.decode(sums.resolve(i / 3)(i % 3))), scale, sums.faults)
    }
    Result(count, tsOps.get, passing, Array.tabulate(3 * width * height)(sum.toDouble), if (coproc) Some(coprocFrame) else None)
  }

  /** The records of queries [from, until), sorted by (query, photon). */
  private def chunkRecords(map: PhotonMap, queries: QuerySet, shade: ShadeArith, codec: ExpectedSoFile.Codec, searcher: TreeSearcher,
                           from: Int, until: Int, tsOps: java.util.concurrent.atomic.AtomicLong): Array[Byte] = {
    val buf = new java.io.ByteArrayOutputStream()
    val rec = ByteBuffer.allocate(codec.record.bytes).order(ByteOrder.LITTLE_ENDIAN)
    val colour = new Array[Long](3)
    val channelFlags = new Array[Int](3)
    var ts = 0L
    for (q <- from until until) {
      searcher.search(queries.x(q), queries.y(q), queries.z(q), map.hValue)
      ts += searcher.tsCount
      val photons = java.util.Arrays.copyOf(searcher.so, searcher.soCount)
      java.util.Arrays.sort(photons)
      for (i <- photons) {
        shade.shadeFlags(map.kernel(i), map.brdf(i), map.h, map.power(0)(i), map.power(1)(i), map.power(2)(i),
          queries.contribution(0)(q), queries.contribution(1)(q), queries.contribution(2)(q), colour, channelFlags)
        var flags = 0
        for (c <- 0 until 3) flags |= channelFlags(c) << (ExpectedSoFile.FlagBits * c)
        if (shade.cond(queries.qx(q), queries.qy(q), queries.qz(q), map.px(i), map.py(i), map.pz(i), map.h))
          flags |= 1 << ExpectedSoFile.CondBit
        codec.put(rec, 0, q, i, colour, flags)
        buf.write(rec.array())
      }
    }
    tsOps.addAndGet(ts)
    buf.toByteArray
  }
}
