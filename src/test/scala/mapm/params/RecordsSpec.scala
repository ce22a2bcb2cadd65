package mapm.params

import java.nio.{ByteBuffer, ByteOrder}

import chisel3._
import chisel3.util.MixedVec
import chiseltest._
import mapm.format.MemoryLayout
import mapm.model.NodeWord
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite

/** The record bundles of one slot size and format width, decoded from raw record bits. */
class DecodedRecords(slot: Int, width: Int) extends Bundle {
  val node = new NodeRecord(width)
  val photon = new PhotonRecord(slot, width)
  val query = new QueryHwRecord(slot, width)
}

/** Decodes the raw bits of a node record, a photon record and the SOQ part of a query record with
  * `.asTypeOf`, once per (slot bytes, format width) of `configs`. Combinational. */
class RecordDecoder(configs: Seq[(Int, Int)]) extends Module {
  val nodeRaw = IO(Input(UInt((8 * MemoryLayout.node.bytes).W)))
  val photonRaw = IO(Input(Vec(configs.size, UInt((8 * MemoryLayout.photon(4).bytes).W))))
  val queryRaw = IO(Input(UInt((8 * MemoryLayout.queryHwBytes(4)).W)))
  val out = IO(Output(MixedVec(configs.map { case (s, w) => new DecodedRecords(s, w) })))
  for ((d, i) <- out.zipWithIndex) {
    d.node := nodeRaw.asTypeOf(d.node)
    d.photon := photonRaw(i).asTypeOf(d.photon)
    d.query := queryRaw.asTypeOf(d.query)
  }
}

/** The record bundles against the memory layout and the model's node word: records are built
  * byte by byte through [[MemoryLayout]]'s fields, and every bundle field must read back what was
  * written (format bits in `value`, the slot's upper bits in `pad`). */
class RecordsSpec extends AnyFunSuite with Sim {
  private val configs = Seq((4, 32), (4, 16), (2, 16))
  private val rnd = new scala.util.Random(20240607)

  private def buffer(bytes: Int) = ByteBuffer.allocate(bytes).order(ByteOrder.LITTLE_ENDIAN)
  /** The little-endian value of `b`'s bytes `from until to`. */
  private def bits(b: ByteBuffer, from: Int, to: Int): BigInt =
    (from until to).foldRight(BigInt(0))((i, acc) => (acc << 8) | (b.get(i) & 0xff))
  private def randomSlot(slot: Int): Long = rnd.nextLong() & ((1L << (8 * slot)) - 1)
  private def check(slot: FormatSlot, width: Int, written: Long): Unit = {
    assert(slot.value.peek().litValue == BigInt(written & ((1L << width) - 1)))
    assert(slot.pad.getWidth == 0 || slot.pad.peek().litValue == BigInt(written >>> width))
  }

  test("bundle widths are the records' sizes") {
    assert((new NodeRecord(32)).getWidth == 8 * MemoryLayout.node.bytes)
    assert((new NodeWordBits).getWidth == 8 * MemoryLayout.node("word").bytes)
    for ((s, w) <- configs) {
      assert((new PhotonRecord(s, w)).getWidth == 8 * MemoryLayout.photon(s).bytes)
      assert((new QueryHwRecord(s, w)).getWidth == 8 * MemoryLayout.queryHwBytes(s))
    }
  }

  test("record bundles decode random records written through MemoryLayout") {
    simulate(new RecordDecoder(configs)) { c =>
      for (_ <- 0 until 300) {
        val node = buffer(MemoryLayout.node.bytes)
        val split = randomSlot(MemoryLayout.node("split").bytes)
        val word = rnd.nextInt()
        MemoryLayout.node.put(node, 0, "split", split)
        MemoryLayout.node.put(node, 0, "word", word.toLong)
        c.nodeRaw.poke(bits(node, 0, MemoryLayout.node.bytes).U)

        val queries = configs.map { case (s, _) =>
          val layout = MemoryLayout.query(s)
          val q = buffer(layout.bytes)
          val v = layout.fields.map(f => f.name -> randomSlot(f.bytes)).toMap
          for ((f, x) <- v) layout.put(q, 0, f, x)
          (q, v)
        }
        val photons = configs.map { case (s, _) =>
          val layout = MemoryLayout.photon(s)
          val b = buffer(MemoryLayout.photon(4).bytes)
          val v = MemoryLayout.PhotonFields.map(f => f -> randomSlot(s)).toMap
          for ((f, x) <- v) layout.put(b, 0, f, x)
          (b, v)
        }
        for (i <- configs.indices) c.photonRaw(i).poke(bits(photons(i)._1, 0, MemoryLayout.photon(4).bytes).U)

        for ((((s, w), d), i) <- configs.zip(c.out).zipWithIndex) {
          check(d.node.split, w, split)
          val nw = d.node.word
          assert(nw.axis.peek().litValue == NodeWord.axis(word))
          assert(nw.hasLeft.peek().litToBoolean == ((word & NodeWord.HasLeft) != 0))
          assert(nw.hasRight.peek().litToBoolean == ((word & NodeWord.HasRight) != 0))
          assert(nw.leftIsLeaf.peek().litToBoolean == ((word & NodeWord.LeftIsLeaf) != 0))
          assert(nw.rightIsLeaf.peek().litToBoolean == ((word & NodeWord.RightIsLeaf) != 0))
          assert(nw.right.peek().litValue == NodeWord.right(word))

          val pv = photons(i)._2
          val ph = d.photon
          val byName = Seq("x" -> ph.x, "y" -> ph.y, "z" -> ph.z, "power_r" -> ph.power(0), "power_g" -> ph.power(1),
            "power_b" -> ph.power(2), "kernel" -> ph.kernel, "brdf" -> ph.brdf)
          assert(byName.map(_._1) == MemoryLayout.PhotonFields)
          for ((f, slotField) <- byName) check(slotField, w, pv(f))

          // The query decoders of every config share one input: poke this config's record and read its own.
          val (qb, qv) = queries(i)
          c.queryRaw.poke(bits(qb, 0, MemoryLayout.queryHwBytes(4)).U)
          for ((ch, k) <- Rgb.Names.zipWithIndex) check(d.query.contrib(k), w, qv("contrib_" + ch))
          assert(d.query.rest.peek().litValue == bits(qb, MemoryLayout.query(s)("contrib_b").end, MemoryLayout.queryHwBytes(s)))
        }
      }
    }
  }
}
