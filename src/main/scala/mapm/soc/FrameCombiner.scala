package mapm.soc

import chisel3._
import chisel3.util._
import mapm.numerics.FrameAccum
import mapm.params.Rgb

/** Contributions to one pixel on their way to its bank, some already added together
  * ([[FrameCombiner]]): the pixel's offset in the tile, the sums of the good contributions (those
  * [[FrameConvert]] did not refuse), how many were good, and whether any was refused as not finite
  * or beyond the scale's range.
  *
  * @param sumBits bits of each sum: enough for `maxParts` contributions below 2^limitBits
  * @param maxParts the most contributions one partial may carry
  */
class FramePartial(tileLog2: Int, sumBits: Int, maxParts: Int) extends Bundle {
  val offset = UInt(tileLog2.W)
  val sum = Vec(Rgb.Channels, SInt(sumBits.W))
  val good = UInt(log2Ceil(maxParts + 1).W)
  val nonFinite = Bool()
  val range = Bool()
}

object FramePartial {
  /** The bits of a sum of `parts` contributions below 2^limitBits in magnitude, signed. */
  def sumBits(fa: FrameAccum, parts: Int): Int = fa.limitBits + 1 + log2Ceil(parts)
}

/** The frame accumulator's combining network: carries partials from `inputs` ports to `outputs`
  * ports (the banks), each to the output `dest` names, and adds two partials of the same pixel into
  * one wherever they meet, so a pixel that many lanes feed at once reaches its bank as a few
  * partials, not one per contribution (the combining switches of the NYU Ultracomputer's
  * fetch-and-add network). Adding is exact: the sums are integers.
  *
  * A butterfly of n = 2^k ports (the larger port count, rounded up to a power of two; unused inputs
  * idle): stage s pairs the positions that differ in bit k-1-s and sends each partial to the one
  * whose bit k-1-s is its destination's, so after k stages a partial sits at its destination. Each
  * 2 x 2 switch sends both partials when they go apart; when both want the same side it adds them if
  * they name the same pixel, else sends one (the two inputs take turns) and holds the other. Every
  * switch output is a short [[MergeQueue]], which adds a partial into its newest entry when both
  * name the same pixel (so a hot pixel's stream collapses even when its partials meet nowhere
  * else), and whose state is registered, so no ready runs from one stage through the next.
  *
  * Latency: k cycles when nothing waits. Throughput: one partial per output per cycle; n/2 log2 n
  * switches, each two adders of `sumBits` per channel and four queue entries.
  */
class FrameCombiner(inputs: Int, outputs: Int, tileLog2: Int, sumBits: Int, maxParts: Int) extends Module {
  require(inputs >= 1 && outputs >= 1, s"$inputs inputs, $outputs outputs")
  private val k = log2Ceil(inputs max outputs max 2)
  private val n = 1 << k
  private val destBits = log2Ceil(outputs max 2)
  override def desiredName = s"FrameCombiner_i${inputs}_o$outputs"
  private def partial = new FramePartial(tileLog2, sumBits, maxParts)

  val io = IO(new Bundle {
    val in = Vec(inputs, Flipped(Decoupled(partial)))
    /** The output each input's partial goes to (a function of its pixel: the bank). */
    val dest = Input(Vec(inputs, UInt(destBits.W)))
    val out = Vec(outputs, Decoupled(partial))
    /** No partial inside the network. */
    val idle = Output(Bool())
  })

  /** A partial and its destination between stages. */
  class Hop extends Bundle {
    val p = partial
    val dest = UInt(k.W)
  }

  /** Whether two partials may become one: the same pixel, and no more than `maxParts` good ones. */
  private def mergeable(a: FramePartial, b: FramePartial): Bool = a.offset === b.offset && (a.good +& b.good) <= maxParts.U

  private def add(a: FramePartial, b: FramePartial): FramePartial = {
    val r = Wire(partial)
    r.offset := a.offset
    for (ch <- 0 until Rgb.Channels) r.sum(ch) := a.sum(ch) + b.sum(ch)
    r.good := a.good + b.good
    r.nonFinite := a.nonFinite || b.nonFinite
    r.range := a.range || b.range
    r
  }

  // Stage inputs: position x of the first stage is input x (idle beyond `inputs`).
  private var cur: Seq[DecoupledIO[Hop]] = (0 until n).map { x =>
    val w = Wire(Decoupled(new Hop))
    if (x < inputs) {
      w.valid := io.in(x).valid
      w.bits.p := io.in(x).bits
      w.bits.dest := io.dest(x)
      io.in(x).ready := w.ready
    } else {
      w.valid := false.B
      w.bits := DontCare
    }
    w
  }
  private val queues = scala.collection.mutable.ArrayBuffer[MergeQueue[Hop]]()
  for (s <- 0 until k) {
    val b = k - 1 - s
    val next = Array.fill[DecoupledIO[Hop]](n)(null)
    for (x0 <- 0 until n if ((x0 >> b) & 1) == 0) {
      val x1 = x0 | (1 << b)
      val ins = Seq(cur(x0), cur(x1))
      val outQ = Seq.fill(2)(Module(new MergeQueue(new Hop, FrameCombiner.Depth, (x: Hop, y: Hop) => mergeable(x.p, y.p), (x: Hop, y: Hop) => {
        val m = Wire(new Hop); m.dest := x.dest; m.p := add(x.p, y.p); m
      })))
      queues ++= outQ
      val side = ins.map(h => h.bits.dest(b))
      val both = ins(0).valid && ins(1).valid && side(0) === side(1)
      val same = both && mergeable(ins(0).bits.p, ins(1).bits.p)
      val turn = RegInit(false.B) // which input goes first when both want one side with different pixels
      val first = Mux(both && !same, turn, false.B) // index of the input sent alone on a clash
      for (o <- 0 until 2) {
        val q = outQ(o).io.enq
        val want = ins.map(h => h.valid && h.bits.dest(b) === o.U)
        q.valid := want(0) || want(1)
        val merged = Wire(new Hop)
        merged.dest := ins(0).bits.dest
        merged.p := add(ins(0).bits.p, ins(1).bits.p)
        q.bits := Mux(want(0) && want(1), Mux(same, merged, Mux(first, ins(1).bits, ins(0).bits)), Mux(want(0), ins(0).bits, ins(1).bits))
      }
      for (i <- 0 until 2) {
        val o = side(i)
        val enqReady = Mux(o, outQ(1).io.enq.ready, outQ(0).io.enq.ready)
        // Sent: alone on its side, merged, or the one whose turn it is on a clash.
        val goes = !both || same || first === i.U
        ins(i).ready := enqReady && goes
      }
      when(both && !same && Mux(side(0), outQ(1).io.enq.ready, outQ(0).io.enq.ready)) { turn := !turn }
      next(x0) = outQ(0).io.deq
      next(x1) = outQ(1).io.deq
    }
    cur = next.toSeq
  }
  for (y <- 0 until n) {
    if (y < outputs) {
      io.out(y).valid := cur(y).valid
      io.out(y).bits := cur(y).bits.p
      cur(y).ready := io.out(y).ready
    } else cur(y).ready := true.B // no partial is addressed beyond the outputs
  }
  io.idle := queues.map(!_.io.deq.valid).reduce(_ && _) && io.in.map(!_.valid).reduce(_ && _)
}

object FrameCombiner {
  /** Entries of each switch output's queue. */
  val Depth: Int = 4
}

/** A queue of `depth` entries that adds an entry into its newest one (`merge`) when `mergeable`
  * says they may and the newest is not leaving in that cycle; it takes one then even when full.
  * Latency: one cycle. Throughput: one entry in and one out per cycle. */
class MergeQueue[T <: Data](gen: T, depth: Int, mergeable: (T, T) => Bool, merge: (T, T) => T) extends Module {
  require(depth >= 2, s"a merging queue needs two entries, got $depth")
  override def desiredName = s"MergeQueue_$depth"
  val io = IO(new Bundle {
    val enq = Flipped(Decoupled(gen))
    val deq = Decoupled(gen)
  })
  private val data = Reg(Vec(depth, gen))
  private val count = RegInit(0.U(log2Ceil(depth + 1).W))
  private val head = RegInit(0.U(log2Ceil(depth).W))
  private def wrap(i: UInt): UInt = Mux(i >= depth.U, i - depth.U, i)
  private val newest = wrap(head +& count - 1.U)
  private val deqing = io.deq.ready && count =/= 0.U
  // Merge into the newest entry unless it is the one leaving now.
  private val canMerge = count =/= 0.U && mergeable(data(newest), io.enq.bits) && !(deqing && count === 1.U)
  io.enq.ready := canMerge || count =/= depth.U || deqing
  io.deq.valid := count =/= 0.U
  io.deq.bits := data(head)
  private val enqing = io.enq.valid && io.enq.ready
  when(enqing) {
    when(canMerge) { data(newest) := merge(data(newest), io.enq.bits) }
    .otherwise { data(wrap(head +& count)) := io.enq.bits }
  }
  when(deqing) { head := wrap(head +& 1.U) }
  count := count + (enqing && !canMerge).asUInt - deqing.asUInt
}
