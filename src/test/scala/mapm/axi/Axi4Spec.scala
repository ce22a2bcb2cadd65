package mapm.axi

import chisel3._
import chisel3.util._
import chiseltest._
import mapm.memory.{BurstClient, MemImage, MemPortParams, MemSim}
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.collection.mutable
import scala.util.Random

/** The read bridge with a checker on its AXI4 side: what the tests drive. */
class ReadBridgeChecked(mp: MemPortParams, ap: Axi4Params) extends Module {
  val bridge = Module(new Axi4ReadBridge(mp, ap, 16))
  val checker = Module(new Axi4Checker(ap))
  val io = IO(new Bundle {
    val mem = Flipped(new mapm.memory.MemPort(mp))
    val ar = Decoupled(new Axi4Addr(ap))
    val r = Flipped(Decoupled(new Axi4R(ap)))
    val readError = Output(Bool())
    val masterFault = Output(UInt(Axi4Checker.MasterRules.size.W))
    val slaveFault = Output(UInt(Axi4Checker.SlaveRules.size.W))
    val idle = Output(Bool())
  })
  bridge.io.mem <> io.mem
  io.ar <> bridge.io.ar
  bridge.io.r <> io.r
  bridge.io.drop := false.B
  io.readError := bridge.io.readError
  val a = checker.io.axi
  a.ar.valid := io.ar.valid; a.ar.ready := io.ar.ready; a.ar.bits := io.ar.bits
  a.r.valid := io.r.valid; a.r.ready := io.r.ready; a.r.bits := io.r.bits
  a.aw.valid := false.B; a.aw.ready := false.B; a.aw.bits := 0.U.asTypeOf(a.aw.bits)
  a.w.valid := false.B; a.w.ready := false.B; a.w.bits := 0.U.asTypeOf(a.w.bits)
  a.b.valid := false.B; a.b.ready := false.B; a.b.bits := 0.U.asTypeOf(a.b.bits)
  io.masterFault := checker.io.masterFault
  io.slaveFault := checker.io.slaveFault
  io.idle := checker.io.idle
}

/** What an AXI4 read slave may do wrong, once. */
sealed trait RFault
object RFault {
  case object UnknownId extends RFault
  case object EarlyLast extends RFault
  case object MissingLast extends RFault
  case object DropValid extends RFault
  case object ChangeData extends RFault
}

/** An AXI4 read slave: takes AR with random readiness, answers each burst after a random latency,
  * interleaving the beats of different ids, holding each offered beat until taken; with `fault`
  * it breaks one rule once. Checks the AR payload (INCR, full beats, inside the memory). */
final class AxiReadSlave(ar: DecoupledIO[Axi4Addr], r: DecoupledIO[Axi4R], p: Axi4Params, mem: MemImage, rnd: Random,
                         fault: Option[RFault] = None) {
  private final class Burst(val id: BigInt, val addr: Long, val beats: Int, val readyAt: Long) { var next = 0 }
  private val bursts = mutable.ArrayBuffer[Burst]()
  private var offered: Option[(BigInt, BigInt, Boolean)] = None // id, data, last
  private var offeredOf: Option[Burst] = None
  private var arReady = false
  private var cycle = 0L
  var injected = false

  def drive(): Unit = {
    arReady = rnd.nextDouble() < 0.6
    ar.ready.poke(arReady.B)
    if (offered.isEmpty && rnd.nextDouble() < 0.7) {
      val ready = bursts.filter(_.readyAt <= cycle)
      if (ready.nonEmpty) {
        val b = ready(rnd.nextInt(ready.size))
        val last = b.next == b.beats - 1
        var (id, l) = (b.id, last)
        if (!injected) fault match {
          case Some(RFault.UnknownId) =>
            (0 until (1 << p.idBits)).map(BigInt(_)).find(i => !bursts.exists(_.id == i)).foreach { i => id = i; injected = true }
          case Some(RFault.EarlyLast) if b.beats > 1 && b.next == 0 => l = true; injected = true
          case Some(RFault.MissingLast) if last => l = false; injected = true
          case _ =>
        }
        offered = Some((id, mem.read(b.addr + b.next * p.dataBytes, p.dataBytes), l))
        offeredOf = Some(b)
      }
    }
    r.valid.poke(offered.isDefined.B)
    offered.foreach { case (id, d, l) =>
      r.bits.id.poke(id.U); r.bits.data.poke(d.U); r.bits.last.poke(l.B); r.bits.resp.poke(0.U)
    }
  }

  def observe(): Boolean = {
    var progress = false
    if (arReady && ar.valid.peek().litToBoolean) {
      val a = ar.bits
      assert(a.burst.peek().litValue == 1 && a.size.peek().litValue == p.sizeCode, "INCR bursts of full beats")
      val addr = a.addr.peek().litValue.toLong
      val beats = a.len.peek().litValue.toInt + 1
      assert(addr + beats * p.dataBytes <= mem.size, s"burst at $addr outside the memory")
      bursts += new Burst(a.id.peek().litValue, addr, beats, cycle + 1 + rnd.nextInt(30))
      progress = true
    }
    if (offered.isDefined) {
      if (r.ready.peek().litToBoolean) {
        val b = offeredOf.get
        b.next += 1
        if (b.next == b.beats) bursts -= b
        offered = None
        progress = true
      } else if (!injected && (fault.contains(RFault.DropValid) || fault.contains(RFault.ChangeData))) {
        injected = true
        if (fault.contains(RFault.DropValid)) offered = None
        else offered = offered.map { case (id, d, l) => (id, d ^ 1, l) }
      }
    }
    cycle += 1
    progress
  }
}

/** [[Axi4ReadBridge]] and [[Axi4Checker]]: the bridge's bursts and beats through a reordering AXI4
  * slave under random stalls, checked beat by beat and by the checker (no rule broken); every
  * rule of the slave's and of the master's broken once and flagged, alone; ARVALID independent of
  * ARREADY within a cycle. */
class Axi4Spec extends AnyFunSuite with Sim {
  private val mp = MemPortParams(addressBits = 16, dataBytes = 16, idBits = 3, maxBeats = 4)
  private val ap = Axi4Params(addrBits = 32, dataBytes = 16, idBits = 4)

  private def run(c: ReadBridgeChecked, seed: Int, fault: Option[RFault]): (BurstClient, AxiReadSlave) = {
    val rnd = new Random(seed)
    val mem = new MemImage(1 << 12, seed)
    c.io.mem.req.valid.poke(false.B)
    c.io.r.valid.poke(false.B)
    MemSim.reset(c.clock, c.reset)
    val client = new BurstClient(c.io.mem, mem, 200, 0.2 + 0.8 * rnd.nextDouble(), 0.3 + 0.7 * rnd.nextDouble(), rnd, 0)
    val slave = new AxiReadSlave(c.io.ar, c.io.r, ap, mem, rnd, fault)
    if (fault.isEmpty)
      MemSim.run(c.clock, Seq(() => client.drive(), () => slave.drive()), Seq(() => client.observe(), () => slave.observe()), client.done)
    else {
      // A broken slave may wedge the traffic: run until the fault shows, a bounded number of cycles.
      var n = 0
      while (n < 20000 && c.io.slaveFault.peek().litValue == 0) {
        client.drive(); slave.drive()
        try client.observe() catch { case _: AssertionError => () } // the client sees the broken beat too
        slave.observe()
        c.clock.step(); n += 1
      }
    }
    // Nothing offered in the cycle the caller steps to read the checker.
    c.io.mem.req.valid.poke(false.B)
    c.io.r.valid.poke(false.B)
    (client, slave)
  }

  test("clean traffic over 8 seeds: every beat right, no rule broken, idle at the end") {
    simulate(new ReadBridgeChecked(mp, ap)) { c =>
      c.clock.setTimeout(0)
      for (seed <- 0 until 8) {
        val (client, _) = run(c, seed, None)
        assert(client.beats > 200)
        c.clock.step()
        assert(c.io.masterFault.peek().litValue == 0 && c.io.slaveFault.peek().litValue == 0, s"seed $seed")
        assert(c.io.idle.peek().litToBoolean && !c.io.readError.peek().litToBoolean, s"seed $seed")
      }
    }
  }

  private val rBits = Map[RFault, Int](RFault.UnknownId -> 0, RFault.EarlyLast -> 1, RFault.MissingLast -> 1, RFault.DropValid -> 2, RFault.ChangeData -> 2)
  for ((f, bit) <- rBits) test(s"a slave's $f is reported as \"${Axi4Checker.SlaveRules(bit)}\", not hung") {
    simulate(new ReadBridgeChecked(mp, ap)) { c =>
      c.clock.setTimeout(0)
      val (_, slave) = run(c, 3, Some(f))
      assert(slave.injected, s"$f was never injected")
      c.clock.step()
      assert(c.io.slaveFault.peek().litValue == (BigInt(1) << bit), s"$f")
      assert(c.io.masterFault.peek().litValue == 0)
    }
  }

  test("ARVALID and the AR payload do not depend on ARREADY in the same cycle") {
    simulate(new ReadBridgeChecked(mp, ap)) { c =>
      c.io.r.valid.poke(false.B)
      c.io.ar.ready.poke(false.B)
      c.io.mem.req.valid.poke(false.B)
      MemSim.reset(c.clock, c.reset)
      c.io.mem.req.valid.poke(true.B); c.io.mem.req.bits.addr.poke(0x40.U); c.io.mem.req.bits.id.poke(5.U); c.io.mem.req.bits.len.poke(3.U)
      c.clock.step()
      c.io.mem.req.valid.poke(false.B)
      for (ready <- Seq(false, true, false)) {
        c.io.ar.ready.poke(ready.B)
        assert(c.io.ar.valid.peek().litToBoolean && c.io.ar.bits.addr.peek().litValue == 0x40 && c.io.ar.bits.id.peek().litValue == 5)
      }
      c.io.ar.ready.poke(true.B)
      c.clock.step()
      assert(!c.io.ar.valid.peek().litToBoolean)
    }
  }
}

/** [[Axi4Checker]] alone, its port poked directly: each rule broken once is flagged alone. */
class Axi4CheckerSpec extends AnyFunSuite with Sim {
  private val ap = Axi4Params(addrBits = 32, dataBytes = 16, idBits = 4)

  private def idle(c: Axi4Checker): Unit = {
    val a = c.io.axi
    for (ch <- Seq(a.aw, a.ar)) { ch.valid.poke(false.B); ch.ready.poke(false.B); ch.bits.burst.poke(1.U); ch.bits.size.poke(4.U); ch.bits.len.poke(0.U); ch.bits.addr.poke(0.U); ch.bits.id.poke(0.U) }
    a.w.valid.poke(false.B); a.w.ready.poke(false.B); a.w.bits.last.poke(false.B); a.w.bits.data.poke(0.U)
    a.b.valid.poke(false.B); a.b.ready.poke(false.B); a.b.bits.id.poke(0.U); a.b.bits.resp.poke(0.U)
    a.r.valid.poke(false.B); a.r.ready.poke(false.B); a.r.bits.id.poke(0.U); a.r.bits.last.poke(false.B); a.r.bits.data.poke(0.U)
  }
  private def fire[T <: Data](c: Axi4Checker, ch: DecoupledIO[T])(set: T => Unit): Unit = {
    set(ch.bits); ch.valid.poke(true.B); ch.ready.poke(true.B); c.clock.step(); ch.valid.poke(false.B); ch.ready.poke(false.B)
  }
  private def aw(c: Axi4Checker, id: Int, len: Int, addr: Long = 0) = fire[Axi4Addr](c, c.io.axi.aw) { b => b.id.poke(id.U); b.len.poke(len.U); b.addr.poke(addr.U) }
  private def ar(c: Axi4Checker, id: Int, len: Int, addr: Long = 0) = fire[Axi4Addr](c, c.io.axi.ar) { b => b.id.poke(id.U); b.len.poke(len.U); b.addr.poke(addr.U) }
  private def w(c: Axi4Checker, last: Boolean) = fire[Axi4W](c, c.io.axi.w) { b => b.last.poke(last.B) }
  private def bResp(c: Axi4Checker, id: Int) = fire[Axi4B](c, c.io.axi.b) { b => b.id.poke(id.U) }

  private val cases: Seq[(String, Boolean, Int, Axi4Checker => Unit)] = Seq(
    ("a correct write and read", true, -1, c => { aw(c, 2, 1); w(c, false); w(c, true); bResp(c, 2); ar(c, 1, 0); fire[Axi4R](c, c.io.axi.r) { b => b.id.poke(1.U); b.last.poke(true.B) } }),
    ("ARVALID dropped before ARREADY", true, 0, c => { c.io.axi.ar.valid.poke(true.B); c.clock.step(); c.io.axi.ar.valid.poke(false.B); c.clock.step() }),
    ("AW address changed before AWREADY", true, 1, c => { c.io.axi.aw.valid.poke(true.B); c.clock.step(); c.io.axi.aw.bits.addr.poke(64.U); c.clock.step() }),
    ("W data changed before WREADY", true, 2, c => { aw(c, 0, 0); c.io.axi.w.valid.poke(true.B); c.clock.step(); c.io.axi.w.bits.data.poke(1.U); c.clock.step() }),
    ("an AR burst across 4 KiB", true, 3, c => ar(c, 0, 3, 4096 - 32)),
    ("an AW burst that is not INCR", true, 4, c => fire[Axi4Addr](c, c.io.axi.aw) { b => b.burst.poke(2.U) }),
    ("a W beat with no AW", true, 5, c => w(c, true)),
    ("WLAST early", true, 5, c => { aw(c, 0, 2); w(c, true) }),
    ("a read id reused", true, 6, c => { ar(c, 3, 0); ar(c, 3, 0) }),
    ("an R beat for no read", false, 0, c => fire[Axi4R](c, c.io.axi.r) { b => b.id.poke(7.U); b.last.poke(true.B) }),
    ("RLAST missing", false, 1, c => { ar(c, 1, 1); fire[Axi4R](c, c.io.axi.r) { b => b.id.poke(1.U) }; fire[Axi4R](c, c.io.axi.r) { b => b.id.poke(1.U) } }),
    ("RVALID dropped", false, 2, c => { c.io.axi.r.valid.poke(true.B); c.clock.step(); c.io.axi.r.valid.poke(false.B); c.clock.step() }),
    ("a B before the write's data", false, 3, c => { aw(c, 4, 1); w(c, false); bResp(c, 4) }),
    ("BVALID dropped", false, 4, c => { c.io.axi.b.valid.poke(true.B); c.clock.step(); c.io.axi.b.valid.poke(false.B); c.clock.step() }))

  for ((name, master, bit, body) <- cases) test(s"$name: ${if (bit < 0) "nothing flagged" else s"${if (master) "master" else "slave"} rule $bit flagged alone"}") {
    simulate(new Axi4Checker(ap)) { c =>
      idle(c)
      MemSim.reset(c.clock, c.reset)
      body(c)
      c.clock.step()
      val (m, s) = (c.io.masterFault.peek().litValue, c.io.slaveFault.peek().litValue)
      if (bit < 0) assert(m == 0 && s == 0 && c.io.idle.peek().litToBoolean)
      else if (master) assert(m == (BigInt(1) << bit) && s == 0, s"master $m slave $s")
      else assert(s == (BigInt(1) << bit) && m == 0, s"master $m slave $s")
    }
  }
}
