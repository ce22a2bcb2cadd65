package mapm.format

import java.nio.{ByteBuffer, ByteOrder}

import mapm.MapmError
import mapm.model._
import mapm.numerics._
import org.scalatest.funsuite.AnyFunSuite

class MemoryImageSpec extends AnyFunSuite {
  private def scene(f: FloatFormat, nPhotons: Int, nQueries: Int, seed: Int): (PhotonMap, QuerySet) = {
    val rnd = new scala.util.Random(seed)
    def pt() = Vec3(rnd.nextDouble() * 50, rnd.nextDouble() * 40, rnd.nextDouble() * 60)
    val photons = Array.fill(nPhotons)(Photon(pt(), Vec3(rnd.nextDouble(), rnd.nextDouble(), rnd.nextDouble()), Vec3(0, -1, 0), Vec3(0, 1, 0)))
    val queries = Array.fill(nQueries)(QueryPoint(pt(), rnd.nextInt(1000), Vec3(rnd.nextDouble(), rnd.nextDouble(), rnd.nextDouble()), Vec3(0, 1, 0)))
    (PhotonMap.build(photons, Box(Vec3.zero, Vec3(50, 40, 60)), f, 3.0), QuerySet.build(queries, f))
  }

  import SlotLayout.{Packed, Wide}
  /** Record sizes by slot, as docs/memory-layout.md tabulates them: slot -> (node, photon, query, stream). */
  private val sizes = Map(2 -> (8, 16, 16, 4), 4 -> (8, 32, 32, 4), 8 -> (16, 64, 64, 4))

  for ((f, layout, slot) <- Seq((FloatFormat.fp32, Packed, 4), (FloatFormat.fp32, Wide, 4), (FloatFormat.fp16, Packed, 2),
                                (FloatFormat.fp16, Wide, 4), (FloatFormat.bf16, Packed, 2), (FloatFormat(6, 9), Packed, 2),
                                (FloatFormat.fp24, Packed, 4), (FloatFormat(10, 40), Packed, 8), (FloatFormat.fp64, Packed, 8),
                                (FloatFormat.fp64, Wide, 8)))
    test(s"write -> read -> equal for $f $layout ($slot-byte slots)") {
      val (map, queries) = scene(f, 1000, 300, f.width)
      val order = new scala.util.Random(1).shuffle((0 until 300).toList).toArray
      val img = mapm.sim.FrameImage.of(map, queries, layout, Some(order))
      assert(img.slot == slot)
      val file = java.nio.file.Files.createTempFile("mapm", ".img")
      file.toFile.deleteOnExit()
      img.write(file)
      val back = MemoryImage.read(file)
      assert(back == img)
      assert(java.nio.file.Files.size(file) == img.totalBytes)
      assert(back.nodeSplit.toSeq == map.split.toSeq && back.photon(3).toSeq == map.power(0).toSeq && back.stream.toSeq == order.toSeq)
      for (base <- Seq(img.nodeBase, img.photonBase, img.queryBase, img.streamBase)) assert(base % 64 == 0)
      val (node, photon, query, stream) = sizes(slot)
      assert(img.nodeBytes == node && img.photonBytes == photon && img.queryBytes == query)
      assert(img.totalBytes == MemoryLayout.align(img.streamBase + stream * 300L) && img.photonBase == MemoryLayout.align(64 + node * 1000L))
      // one changed field is noticed
      val other = MemoryImage.fromBytes(img.toBytes)
      other.pixel(5) += 1
      assert(other != img)
    }

  test("fp32 bytes at the documented offsets, read back independently of the reader") {
    val f = FloatFormat.fp32
    val photons = Table31.photons.map(p => Photon(p, Vec3(1, 1, 1), Vec3(0, -1, 0), Vec3(0, 1, 0)))
    val map = PhotonMap.build(photons, Table31.box, f, 100.0)
    val queries = QuerySet.build(Array(QueryPoint(Vec3(0, 358.739, 280.736), 42, Vec3(0.5, 0.25, 1.0), Vec3(0, 1, 0))), f)
    val img = mapm.sim.FrameImage.of(map, queries)
    val bytes = img.toBytes
    val b = ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN)
    assert(new String(bytes.take(8), "US-ASCII") == "MAPMIMG1")
    assert(b.getShort(8) == 3 && b.get(10) == 8 && b.get(11) == 23 && b.get(12) == 0 && b.get(13) == 4)
    assert(b.getInt(16) == 7 && b.getInt(20) == 1 && b.getLong(24) == java.lang.Float.floatToIntBits(100f))
    // nodes at 64: Table 3.1's tree. Word = axis | hasLeft 4 | hasRight 8 | leftLeaf 16 | rightLeaf 32 | right << 6
    val words = (0 until 7).map(i => b.getInt(64 + 8 * i + 4))
    assert(words == Seq(2 | 4 | 8 | (4 << 6), 0 | 4 | 8 | 16 | 32 | (3 << 6), words(2) & 3, words(3) & 3, 0 | 4 | 8 | 16 | 32 | (6 << 6), words(5) & 3, words(6) & 3))
    assert(java.lang.Float.intBitsToFloat(b.getInt(64)) == 171.588f && java.lang.Float.intBitsToFloat(b.getInt(64 + 8)) == 114.27f)
    // photons at align64(64 + 56) = 128, 32 bytes each: node 4 = (72.7003, 548.8, 191.099)
    assert(b.getLong(32) == 128)
    val p4 = 128 + 32 * 4
    assert(Seq(0, 4, 8).map(o => java.lang.Float.intBitsToFloat(b.getInt(p4 + o))) == Seq(72.7003f, 548.8f, 191.099f))
    assert(java.lang.Float.intBitsToFloat(b.getInt(p4 + 24)) == (1 / (math.Pi * 100)).toFloat)
    assert(java.lang.Float.intBitsToFloat(b.getInt(p4 + 28)) == (1 / math.Pi).toFloat)
    // queries at align64(128 + 224) = 384: contribution, zero, position, pixel
    assert(b.getLong(40) == 384)
    assert(Seq(0, 4, 8).map(o => java.lang.Float.intBitsToFloat(b.getInt(384 + o))) == Seq(0.5f, 0.25f, 1.0f))
    assert(b.getInt(384 + 28) == 42 && b.getInt(384 + 12) == 0)
    assert(Seq(16, 20, 24).map(o => java.lang.Float.intBitsToFloat(b.getInt(384 + o))) == Seq(0f, 358.739f, 280.736f))
    // stream at 448: the query index, 4 bytes, the array padded to 64
    assert(b.getLong(48) == 448 && b.getLong(56) == 512 && bytes.length == 512)
    assert(b.getInt(448) == 0)
  }

  test("fp16 packed bytes at the documented offsets") {
    val f = FloatFormat.fp16
    val (map, queries) = scene(f, 3, 2, 9)
    val img = mapm.sim.FrameImage.of(map, queries, Packed)
    val b = ByteBuffer.wrap(img.toBytes).order(ByteOrder.LITTLE_ENDIAN)
    val pb = img.photonBase.toInt; val qb = img.queryBase.toInt; val sb = img.streamBase.toInt
    for (i <- 0 until 3; (field, k) <- Seq(map.px, map.py, map.pz, map.power(0), map.power(1), map.power(2), map.kernel, map.brdf).zipWithIndex)
      assert((b.getShort(pb + 16 * i + 2 * k) & 0xffff) == field(i))
    for (q <- 0 until 2) {
      for (c <- 0 until 3) assert((b.getShort(qb + 16 * q + 2 * c) & 0xffff) == queries.contribution(c)(q))
      assert((b.getShort(qb + 16 * q + 6) & 0xffff) == queries.qx(q) && (b.getShort(qb + 16 * q + 10) & 0xffff) == queries.qz(q))
      assert(b.getInt(qb + 16 * q + 12) == queries.pixel(q))
      assert(b.getInt(sb + 4 * q) == q)
    }
  }

  test("fp64 bytes at the documented offsets: 16-byte nodes, 64-byte photons and queries, 4-byte stream entries") {
    val f = FloatFormat.fp64
    val (map, queries) = scene(f, 5, 3, 4)
    val img = mapm.sim.FrameImage.of(map, queries, Packed)
    val b = ByteBuffer.wrap(img.toBytes).order(ByteOrder.LITTLE_ENDIAN)
    assert(b.getShort(8) == 3 && b.get(10) == 11 && b.get(11) == 52 && b.get(12) == 0 && b.get(13) == 8)
    assert(b.getLong(24) == java.lang.Double.doubleToLongBits(3.0) && b.getInt(16) == 5 && b.getInt(20) == 3)
    val pb = img.photonBase.toInt; val qb = img.queryBase.toInt; val sb = img.streamBase.toInt
    assert(pb == 192 && qb == pb + 5 * 64 && sb == qb + 3 * 64 && img.totalBytes == sb + 64)
    for (i <- 0 until 5) {
      assert(b.getLong(64 + 16 * i) == map.split(i) && b.getInt(64 + 16 * i + 8) == map.tree.nodeWords(i) && b.getInt(64 + 16 * i + 12) == 0)
      for ((field, k) <- Seq(map.px, map.py, map.pz, map.power(0), map.power(1), map.power(2), map.kernel, map.brdf).zipWithIndex)
        assert(b.getLong(pb + 64 * i + 8 * k) == field(i))
    }
    for (q <- 0 until 3) {
      for (c <- 0 until 3) assert(b.getLong(qb + 64 * q + 8 * c) == queries.contribution(c)(q))
      assert(b.getLong(qb + 64 * q + 24) == 0)
      assert(Seq(32, 40, 48).map(o => b.getLong(qb + 64 * q + o)) == Seq(queries.qx(q), queries.qy(q), queries.qz(q)))
      assert(b.getInt(qb + 64 * q + 56) == queries.pixel(q))
      assert(b.getInt(sb + 4 * q) == q)
    }
  }

  test("bad layout names, oversized trees and corrupt files are clear errors") {
    assert(intercept[MapmError](SlotLayout.parse("tight")).getMessage == "layout 'tight': expected packed or wide")
    val (m32, q32) = scene(FloatFormat.fp32, 10, 2, 1)
    assert(intercept[MapmError](NodeWord.checkSize(NodeWord.MaxNodes + 1)).getMessage.contains("26-bit right-child index"))
    NodeWord.checkSize(NodeWord.MaxNodes)
    val bytes = mapm.sim.FrameImage.of(m32, q32).toBytes
    assert(intercept[MapmError](MemoryImage.fromBytes(bytes.take(100), "x.img")).getMessage.contains("x.img"))
    val badMagic = bytes.clone(); badMagic(0) = 'X'
    assert(intercept[MapmError](MemoryImage.fromBytes(badMagic)).getMessage.contains("magic"))
    val badRight = bytes.clone()
    ByteBuffer.wrap(badRight).order(ByteOrder.LITTLE_ENDIAN).putInt(64 + 4, 4 | 8 | (500 << 6))
    assert(intercept[MapmError](MemoryImage.fromBytes(badRight)).getMessage.contains("right child 500"))
    assert(intercept[MapmError](MemoryImage.read(java.nio.file.Paths.get("/nonexistent/x.img"))).getMessage.contains("cannot read"))
    val badLayout = bytes.clone(); badLayout(12) = 2
    assert(intercept[MapmError](MemoryImage.fromBytes(badLayout)).getMessage.contains("layout code 2"))
    val badSlot = bytes.clone(); badSlot(13) = 2
    assert(intercept[MapmError](MemoryImage.fromBytes(badSlot)).getMessage.contains("slot size 2 does not match format fp32 in the packed layout (4)"))
  }
}
