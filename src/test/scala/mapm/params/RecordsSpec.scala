package mapm.params

import java.nio.{ByteBuffer, ByteOrder}

import chisel3._
import chisel3.util.MixedVec
import chiseltest._
import mapm.format.MemoryLayout
import mapm.numerics.NodeWord
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite

/** The record bundles of one slot size and format width, decoded from raw record bits. */
class DecodedRecords(slot: Int, width: Int) extends Bundle {
  val node = new NodeRecord(slot, width)
  val photon = new PhotonRecord(slot, width)
  val query = new QueryRecord(slot, width)
}

/** Raw record bits of one slot size: a node record, a photon record and a query record. */
class RawRecords(slot: Int) extends Bundle {
  val node = UInt((8 * MemoryLayout.node(slot).bytes).W)
  val photon = UInt((8 * MemoryLayout.photon(slot).bytes).W)
  val query = UInt((8 * MemoryLayout.queryHwBytes(slot)).W)
}

/** Decodes the raw bits of a node record, a photon record and a query record with
  * `.asTypeOf`, once per (slot bytes, format width) of `configs`. Combinational. */
class RecordDecoder(configs: Seq[(Int, Int)]) extends Module {
  val raw = IO(Input(MixedVec(configs.map { case (s, _) => new RawRecords(s) })))
  val out = IO(Output(MixedVec(configs.map { case (s, w) => new DecodedRecords(s, w) })))
  for ((d, r) <- out.zip(raw)) {
    d.node := r.node.asTypeOf(d.node)
    d.photon := r.photon.asTypeOf(d.photon)
    d.query := r.query.asTypeOf(d.query)
  }
}

/** The record bundles against the memory layout and the model's node word: records are built
  * byte by byte through [[MemoryLayout]]'s fields, and every bundle field must read back what was
  * written (format bits in `value`, the slot's upper bits in `pad`), for every slot size. */
class RecordsSpec extends AnyFunSuite with Sim {
  private val configs = Seq((4, 32), (4, 16), (2, 16), (2, 12), (8, 64), (8, 51))
  private val rnd = new scala.util.Random(20240607)

  private def buffer(bytes: Int) = ByteBuffer.allocate(bytes).order(ByteOrder.LITTLE_ENDIAN)
  /** The little-endian value of `b`'s bytes `from until to`. */
  private def bits(b: ByteBuffer, from: Int, to: Int): BigInt =
    (from until to).foldRight(BigInt(0))((i, acc) => (acc << 8) | (b.get(i) & 0xff))
  private def randomSlot(bytes: Int): Long = if (bytes == 8) rnd.nextLong() else rnd.nextLong() & ((1L << (8 * bytes)) - 1)
  private def unsigned(v: Long): BigInt = BigInt(v) & ((BigInt(1) << 64) - 1)
  private def check(slot: FormatSlot, width: Int, written: Long): Unit = {
    assert(slot.value.peek().litValue == (unsigned(written) & ((BigInt(1) << width) - 1)))
    assert(slot.pad.getWidth == 0 || slot.pad.peek().litValue == unsigned(written) >> width)
  }

  test("bundle widths are the records' sizes") {
    assert((new NodeWordBits).getWidth == 8 * MemoryLayout.node(4)("word").bytes)
    for ((s, w) <- configs) {
      assert((new NodeRecord(s, w)).getWidth == 8 * MemoryLayout.node(s).bytes)
      assert((new PhotonRecord(s, w)).getWidth == 8 * MemoryLayout.photon(s).bytes)
      assert((new QueryRecord(s, w)).getWidth == 8 * MemoryLayout.queryHwBytes(s))
    }
  }

  test("record bundles decode random records written through MemoryLayout") {
    simulate(new RecordDecoder(configs)) { c =>
      for (_ <- 0 until 300) {
        for ((((s, w), d), r) <- configs.zip(c.out).zip(c.raw)) {
          val nodeLayout = MemoryLayout.node(s)
          val node = buffer(nodeLayout.bytes)
          val split = randomSlot(nodeLayout("split").bytes)
          val word = rnd.nextInt()
          nodeLayout.put(node, 0, "split", split)
          nodeLayout.put(node, 0, "word", word.toLong)
          r.node.poke(bits(node, 0, nodeLayout.bytes).U)

          val photonLayout = MemoryLayout.photon(s)
          val photon = buffer(photonLayout.bytes)
          val pv = MemoryLayout.PhotonFields.map(f => f -> randomSlot(s)).toMap
          for ((f, x) <- pv) photonLayout.put(photon, 0, f, x)
          r.photon.poke(bits(photon, 0, photonLayout.bytes).U)

          val queryLayout = MemoryLayout.query(s)
          val query = buffer(queryLayout.bytes)
          val qv = queryLayout.fields.map(f => f.name -> randomSlot(f.bytes)).toMap
          for ((f, x) <- qv) queryLayout.put(query, 0, f, x)
          r.query.poke(bits(query, 0, MemoryLayout.queryHwBytes(s)).U)

          check(d.node.split, w, split)
          assert(d.node.pad.getWidth == 8 * (nodeLayout.bytes - nodeLayout("word").end) && (d.node.pad.getWidth == 0 || d.node.pad.peek().litValue == 0))
          val nw = d.node.word
          assert(nw.axis.peek().litValue == NodeWord.axis(word))
          assert(nw.hasLeft.peek().litToBoolean == ((word & NodeWord.HasLeft) != 0))
          assert(nw.hasRight.peek().litToBoolean == ((word & NodeWord.HasRight) != 0))
          assert(nw.leftIsLeaf.peek().litToBoolean == ((word & NodeWord.LeftIsLeaf) != 0))
          assert(nw.rightIsLeaf.peek().litToBoolean == ((word & NodeWord.RightIsLeaf) != 0))
          assert(nw.right.peek().litValue == NodeWord.right(word))

          val ph = d.photon
          val byName = Seq("x" -> ph.x, "y" -> ph.y, "z" -> ph.z, "power_r" -> ph.power(0), "power_g" -> ph.power(1),
            "power_b" -> ph.power(2), "kernel" -> ph.kernel, "brdf" -> ph.brdf)
          assert(byName.map(_._1) == MemoryLayout.PhotonFields)
          for ((f, slotField) <- byName) check(slotField, w, pv(f))

          for ((ch, k) <- Rgb.Names.zipWithIndex) check(d.query.contrib(k), w, qv("contrib_" + ch))
          for ((a, k) <- Seq("x", "y", "z").zipWithIndex) check(d.query.pos(k), w, qv(a))
          assert(d.query.pixel.peek().litValue == (unsigned(qv("pixel")) & 0xffffffffL))
          assert(d.query.gap.getWidth == 0 || d.query.gap.peek().litValue == bits(query, queryLayout("contrib_b").end, queryLayout("x").offset))
          assert(d.query.tail.getWidth == 0 || d.query.tail.peek().litValue == bits(query, queryLayout("pixel").end, queryLayout.bytes))
        }
      }
    }
  }

  test("the hardware reads whole query records; the gap after the contribution and the tail are the layout's unused bytes") {
    for (s <- Seq(2, 4, 8)) assert(MemoryLayout.queryHwBytes(s) == MemoryLayout.query(s).bytes)
    assert((new QueryRecord(2, 16)).gap.getWidth == 0 && (new QueryRecord(2, 16)).tail.getWidth == 0)
    assert((new QueryRecord(4, 32)).gap.getWidth == 32 && (new QueryRecord(4, 32)).tail.getWidth == 0)
    assert((new QueryRecord(8, 64)).gap.getWidth == 64 && (new QueryRecord(8, 64)).tail.getWidth == 32)
  }
}
