package mapm.uncore

import chisel3._
import chiseltest._
import mapm.Slow
import mapm.params.{MapmParams, SoBus}
import mapm.testutil.Sim
import org.scalatest.funsuite.AnyFunSuite
import scala.collection.mutable
import scala.util.Random

/** The ring bus against its specification, with a model of the SOMs' lanes that frees entries at
  * random (or at a fixed pace) and takes every group the bus hands over:
  *  - a SOM is never handed more SOs for a lane than the lane has free entries;
  *  - every group the bus accepts reaches exactly one SOM, once, and a TSM's groups arrive in the
  *    order it sent them;
  *  - the group of TSM i granted in the cycle where the rotation stood at r reaches SOM
  *    (i + r) mod N or (i + 1 + r) mod N exactly [[RingBus.latency]] cycles later, with r = cycle mod N;
  *  - with no more TSMs than SOMs and lanes that free an entry every D cycles, no group waits at the
  *    head of its queue longer than the bound of docs/mapm.md (3N + n D + 2 latency + 4).
  * At 2/2/1 and 3/2/2 every combination of group shapes (SOs per lane) across the TSMs is sent;
  * above, seeded random groups, random TSM readiness and random lane progress. */
@Slow
class RingBusSpec extends AnyFunSuite with Sim {
  private final case class Group(id: Int, tsm: Int, photons: Seq[Option[Int]])

  /** Drives `groups` (each TSM's in order) through a ring bus of `p` and checks the properties
    * above; `drain`: None for random lane progress, Some(d) for one entry every d cycles (and the
    * fairness bound checked). Returns the longest wait at a queue's head. */
  private def run(p: MapmParams, groups: Seq[Seq[Group]], rnd: Random, offerRate: Double, drain: Option[Int]): Int = {
    val (t, s, a, n) = (p.counts.tsm, p.counts.som, p.counts.soaPerSom, p.rsPerSoa)
    val slots = t max s
    var longest = 0
    simulate(new RingBus(p)) { c =>
      val lat = c.latency
      val queues = groups.map(g => mutable.Queue(g: _*))
      val free = Array.fill(s, a)(n)
      val delivered = mutable.Map.empty[Int, Int]
      val lastAt = Array.fill(t)(-1)   // the grant cycle of each TSM's latest group delivered
      val lastId = Array.fill(t)(-1)
      val enqAt = mutable.Map.empty[Int, Int]
      val total = groups.map(_.size).sum
      var cycle = 0
      def lanes(g: Group) = (0 until a).map(l => g.photons.flatten.count(_ % a == l))
      while (delivered.size < total) {
        assert(cycle < 400 * (total + 10), s"the ring bus stopped making progress ($total groups, ${delivered.size} delivered)")
        // The lanes' free entries, as the SOMs' lanes would show them this cycle.
        for (j <- 0 until s; l <- 0 until a) c.io.free(j)(l).poke(free(j)(l).U)
        val offered = queues.map(q => if (q.nonEmpty && rnd.nextDouble() < offerRate) Some(q.head) else None)
        for (i <- 0 until t) DataBusSpec.offer(c.io.in(i), offered(i).map(g => (g.id, g.photons)))
        val took = Array.fill(s, a)(0)
        for (j <- 0 until s if c.io.out(j).valid.peek().litToBoolean) {
          val id = c.io.out(j).bits.query.q.peek().litValue.toInt
          val g = groups.flatten.find(_.id == id).getOrElse(fail(s"cycle $cycle: SOM $j got a group no TSM sent ($id)"))
          assert(!delivered.contains(id), s"cycle $cycle: group $id reached a SOM twice")
          for ((ph, k) <- g.photons.zipWithIndex) {
            assert(c.io.out(j).bits.photon(k).valid.peek().litToBoolean == ph.isDefined, s"cycle $cycle: group $id's photon $k")
            ph.foreach(v => assert(c.io.out(j).bits.photon(k).bits.peek().litValue == v, s"cycle $cycle: group $id's photon $k"))
          }
          val grantAt = cycle - lat
          assert(grantAt >= 0 && (j - g.tsm - grantAt % slots + 2 * slots) % slots <= 1,
            s"cycle $cycle: TSM ${g.tsm}'s group reached SOM $j, not SOM ${(g.tsm + grantAt) % slots} or the next")
          assert(id > lastId(g.tsm), s"cycle $cycle: TSM ${g.tsm}'s groups out of order")
          val need = lanes(g)
          for (l <- 0 until a) {
            assert(need(l) <= free(j)(l), s"cycle $cycle: SOM $j lane $l got ${need(l)} SOs with ${free(j)(l)} free entries")
            took(j)(l) = need(l)
          }
          // At the head from its arrival in the queue or its predecessor's grant, whichever is later.
          val headAt = math.max(enqAt(id) + 1, lastAt(g.tsm) + 1)
          longest = longest max (grantAt - headAt)
          drain.foreach { d =>
            val bound = 3 * slots + n * d + 2 * lat + 4
            if (t <= s) assert(grantAt - headAt <= bound, s"cycle $cycle: TSM ${g.tsm}'s group waited ${grantAt - headAt} cycles at its head, more than $bound")
          }
          delivered(id) = j; lastAt(g.tsm) = grantAt; lastId(g.tsm) = id
        }
        for (i <- 0 until t if offered(i).isDefined && c.io.in(i).ready.peek().litToBoolean) enqAt(queues(i).dequeue().id) = cycle
        c.clock.step()
        cycle += 1
        // The SOMs take what they were handed; their lanes free entries.
        for (j <- 0 until s; l <- 0 until a) {
          free(j)(l) -= took(j)(l)
          val frees = drain match {
            case Some(d) => cycle % d == 0
            case None => rnd.nextInt(3) == 0
          }
          if (frees && free(j)(l) < n) free(j)(l) += 1
        }
      }
    }
    longest
  }

  /** Up to three photons (None: an empty slot) whose lanes mod `a` are `lanes`, padded with empty slots. */
  private def shaped(id: Int, tsm: Int, lanes: Seq[Int], rnd: Random, a: Int): Group =
    Group(id, tsm, lanes.map(l => Some(rnd.nextInt(1 << 10) * a + l)) ++ Seq.fill(3 - lanes.size)(None))

  private def ring(t: Int, s: Int, a: Int) = {
    val p = MapmParams.table48(t, s, a)
    p.copy(uncore = p.uncore.copy(soBus = SoBus.Ring))
  }

  for ((t, s, a) <- Seq((2, 2, 1), (3, 2, 2))) {
    test(s"$t/$s/$a: every combination of group shapes across the TSMs, each SOM handed no more than it has room for, every group once") {
      val rnd = new Random(t * 7 + s)
      // A shape: the lanes of up to three SOs (a multiset). Every TSM sends every shape against every other TSM's.
      def multisets(k: Int): Seq[Seq[Int]] =
        if (k == 0) Seq(Seq.empty) else multisets(k - 1).flatMap(x => (x.lastOption.getOrElse(0) until a).map(x :+ _))
      val shapes = (0 to 3).flatMap(multisets)
      val combos = Seq.fill(t)(shapes).foldLeft(Seq(Seq.empty[Seq[Int]]))((acc, ss) => for (x <- acc; y <- ss) yield x :+ y)
      var id = 0
      val groups = Seq.tabulate(t)(i => combos.map { c => id += 1; shaped(id, i, c(i), rnd, a) })
      run(ring(t, s, a), groups, rnd, offerRate = 0.8, drain = None)
    }
  }

  for ((t, s, a) <- Seq((2, 3, 3), (4, 4, 2), (5, 3, 2), (3, 5, 1), (8, 8, 2))) {
    test(s"$t/$s/$a: seeded random groups and stalls: room respected, every group once, in order, at its SOM after the bus's latency") {
      val rnd = new Random(31L * t + s)
      var id = 0
      val groups = Seq.tabulate(t)(i => Seq.fill(120) { id += 1; Group(id, i, Seq.fill(3)(if (rnd.nextInt(4) == 0) None else Some(rnd.nextInt(1 << 12)))) })
      run(ring(t, s, a), groups, rnd, offerRate = 0.7, drain = None)
    }
  }

  for ((t, s, a, d) <- Seq((2, 2, 1, 3), (4, 4, 2, 2), (3, 5, 2, 4), (5, 3, 2, 2))) {
    test(s"$t/$s/$a, lanes freeing an entry every $d cycles: every TSM always offering, ${if (t <= s) "no group waits past the fairness bound" else "every group served"}") {
      val rnd = new Random(17L * t + d)
      var id = 0
      val groups = Seq.tabulate(t)(i => Seq.fill(80) { id += 1; shaped(id, i, Seq.fill(1 + rnd.nextInt(3))(rnd.nextInt(a)).sorted, rnd, a) })
      val longest = run(ring(t, s, a), groups, rnd, offerRate = 1.0, drain = Some(d))
      info(s"longest wait at a queue's head: $longest cycles")
    }
  }

  test("3/3/1, one TSM's groups three SOs of one lane against the others' single SOs, lanes slow: it is not starved past the fairness bound") {
    val rnd = new Random(5)
    var id = 0
    // TSM 0 needs three free entries in a lane; TSMs 1 and 2 take every single entry as it frees.
    val groups = Seq.tabulate(3)(i => Seq.fill(if (i == 0) 10 else 200) { id += 1; shaped(id, i, Seq.fill(if (i == 0) 3 else 1)(0), rnd, 1) })
    val longest = run(ring(3, 3, 1), groups, rnd, offerRate = 1.0, drain = Some(6))
    info(s"longest wait at a queue's head: $longest cycles")
  }

  test("a SOM lane whose free count falls by more than it took trips the ring bus's assertion") {
    val caught = intercept[chiseltest.ChiselAssertionError] {
      simulate(new RingBus(ring(2, 2, 1))) { c =>
        for (j <- 0 until 2) c.io.free(j)(0).poke(4.U)
        c.clock.step(3)
        c.io.free(1)(0).poke(1.U) // nothing was handed over: the lane may not lose entries
        c.clock.step(2)
      }
    }
    assert(caught.getMessage.contains("An assertion in RingBus_t2_s2_a1"), caught.getMessage)
  }
}
