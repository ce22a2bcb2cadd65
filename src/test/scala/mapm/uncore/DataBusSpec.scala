package mapm.uncore

import chisel3._
import chiseltest._
import mapm.Slow
import mapm.params.MapmParams
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.collection.mutable
import scala.util.Random

/** The Data bus as it is (3.2), against a reference written from its specification: groups are
  * taken in TSM order from a start that moves one place a cycle, each by the first SOM, in SOM
  * order from its own moving start, that is still unclaimed and has room in every lane for the
  * group's SOs of that lane. Under random SOM room and random TSM readiness: the grants and the
  * groups on each SOM's port equal the reference's every cycle, and every group reaches exactly
  * one SOM once (none lost, none duplicated). With room everywhere, no TSM waits longer than the
  * rotation allows. */
@Slow
class DataBusSpec extends AnyFunSuite with Sim {
  import DataBusSpec.Group

  /** The reference's choice for one cycle: for each TSM the SOM its group goes to, if any. */
  private def reference(groups: Seq[Option[Group]], free: Seq[Seq[Int]], a: Int, startT: Int, startS: Int): Map[Int, Int] = {
    val (t, s) = (groups.size, free.size)
    def fits(g: Group, j: Int) = (0 until a).forall(l => g.photons.flatten.count(_ % a == l) <= free(j)(l))
    val taken = mutable.Set.empty[Int]
    val grants = mutable.Map.empty[Int, Int]
    for (k <- 0 until t; i = (startT + k) % t; g <- groups(i))
      (0 until s).map(m => (startS + m) % s).find(j => !taken(j) && fits(g, j)).foreach { j => taken += j; grants(i) = j }
    grants.toMap
  }

  private def run(t: Int, s: Int, a: Int, seed: Long, perTsm: Int, roomy: Boolean): Unit = {
    val p = MapmParams.table48(t, s, a)
    val rs = p.rsPerSoa
    val rnd = new Random(seed)
    simulate(new DataBus(p)) { c =>
      val queues = Seq.tabulate(t)(i => mutable.Queue.tabulate(perTsm) { k =>
        Group(i * perTsm + k, Seq.fill(3)(if (rnd.nextInt(4) == 0) None else Some(rnd.nextInt(1 << 12))))
      })
      val delivered = mutable.Map.empty[Int, Int].withDefaultValue(0)
      val waited = Array.fill(t)(0)
      var (startT, startS, cycle) = (0, 0, 0)
      while (queues.exists(_.nonEmpty)) {
        assert(cycle < 200 * perTsm * t, "the Data bus stopped making progress")
        val offered = queues.map(q => if (q.nonEmpty && (roomy || rnd.nextDouble() < 0.7)) Some(q.head) else None)
        val free = Seq.fill(s)(Seq.fill(a)(if (roomy) rs else rnd.nextInt(rs + 1) min rnd.nextInt(4)))
        for (i <- 0 until t) DataBusSpec.offer(c.io.in(i), offered(i).map(g => (g.id, g.photons)))
        for (j <- 0 until s; l <- 0 until a) c.io.free(j)(l).poke(free(j)(l).U)
        val want = reference(offered, free, a, startT, startS)
        for (i <- 0 until t) assert(c.io.in(i).ready.peek().litToBoolean == want.contains(i), s"cycle $cycle: TSM $i ready")
        for (j <- 0 until s) {
          val from = want.collectFirst { case (i, `j`) => i }
          assert(c.io.out(j).valid.peek().litToBoolean == from.isDefined, s"cycle $cycle: SOM $j valid")
          from.foreach { i =>
            val g = offered(i).get
            assert(c.io.out(j).bits.query.q.peek().litValue == g.id, s"cycle $cycle: SOM $j got another group than TSM $i's")
            for ((ph, k) <- g.photons.zipWithIndex) {
              assert(c.io.out(j).bits.photon(k).valid.peek().litToBoolean == ph.isDefined)
              ph.foreach(v => assert(c.io.out(j).bits.photon(k).bits.peek().litValue == v))
            }
            delivered(g.id) += 1
          }
        }
        for (i <- 0 until t) {
          if (want.contains(i)) { queues(i).dequeue(); waited(i) = 0 }
          else if (offered(i).isDefined) {
            waited(i) += 1
            if (roomy) assert(waited(i) <= t - math.min(s, t), s"cycle $cycle: TSM $i waited ${waited(i)} cycles with room in every SOM")
          }
        }
        c.clock.step()
        startT = (startT + 1) % t; startS = (startS + 1) % s; cycle += 1
      }
      assert(delivered.size == t * perTsm && delivered.values.forall(_ == 1), "every group once")
    }
  }

  for ((t, s, a) <- Seq((3, 2, 2), (2, 3, 3), (4, 4, 1), (5, 3, 2))) {
    test(s"$t TSMs, $s SOMs of $a SOAs: the reference's grants every cycle, every group once, under random room and readiness") {
      run(t, s, a, seed = 11L * t + s, perTsm = 150, roomy = false)
    }
    test(s"$t TSMs, $s SOMs of $a SOAs: with room everywhere no TSM waits more than ${t - math.min(s, t)} cycles") {
      run(t, s, a, seed = 3L * t + s, perTsm = 40, roomy = true)
    }
  }
}

object DataBusSpec {
  /** One group: an id (carried as its query index) and up to three photons (None: an empty slot). */
  private final case class Group(id: Int, photons: Seq[Option[Int]])

  /** Drives a Data bus input: valid with the group (its id as the query index, its photons, None an
    * empty slot), or not valid. Shared with [[RingBusSpec]]. */
  def offer(port: chisel3.util.DecoupledIO[mapm.params.SoGroup], group: Option[(Int, Seq[Option[Int]])]): Unit = {
    port.valid.poke(group.isDefined.B)
    group.foreach { case (id, photons) =>
      port.bits.query.q.poke(id.U)
      for ((ph, k) <- photons.zipWithIndex) {
        port.bits.photon(k).valid.poke(ph.isDefined.B)
        port.bits.photon(k).bits.poke(ph.getOrElse(0).U)
      }
    }
  }
}
