package mapm.util

import mapm.cost.Hierarchy
import mapm.params.{Hierarchy => MemoryHierarchy, MapmParams}
import mapm.sim.Emit
import mapm.top.Mapm
import org.scalatest.funsuite.AnyFunSuite

/** The cost blocks the modules are tagged with at elaboration: the rule on hand-built chains, and
  * on the emitted MAPM every module instance under the top falls in a block (so a module added
  * without a tag fails here, not silently in the top's area). */
class CostBlockSpec extends AnyFunSuite {
  import CostBlock._

  test("a module's block is its nearest tagged ancestor's; an untagged module right under the top has none") {
    val tags = Map("Top" -> Top, "Ts" -> TsBlock, "Cache" -> Caches, "Unc" -> Uncore)
    assert(of(Seq("Top"), tags) == Right(Top))
    assert(of(Seq("Top", "Ts"), tags) == Right(TsBlock))
    assert(of(Seq("Top", "Ts", "Tsm", "Tsa"), tags) == Right(TsBlock))
    assert(of(Seq("Top", "Ts", "Tsm", "Cache", "Mem"), tags) == Right(Caches))
    assert(of(Seq("Top", "Unc", "Arb"), tags) == Right(Uncore))
    val e = of(Seq("Top", "NewThing", "Part"), tags)
    assert(e.isLeft && e.left.toOption.get.contains("module Part (Top / NewThing / Part) has no cost block"), e)
    assert(of(Seq("Untagged"), Map.empty).isLeft)
  }

  for (p <- Seq(MapmParams.small, MemoryHierarchy.Scalable(MapmParams.table48(2, 3, 2)).copy(uncore =
         mapm.params.UncoreParams(mapm.params.L2Structure.Banked(2), mapm.params.L2Structure.Banked(2)))))
    test(s"every module instance of the emitted ${p.counts.label} MAPM (${p.uncore}) falls in a block") {
      val (sv, tags) = collect(Emit.systemVerilog(new Mapm(p), forSynthesis = true))
      val h = Hierarchy.parse(sv)
      val top = s"Mapm_${p.name}"
      assert(tags.get(top).contains(Top))
      for (b <- Seq(TsBlock, SoBlock, Uncore, Caches)) assert(tags.values.exists(_ == b), s"no module tagged $b")
      def walk(chain: Seq[String]): Seq[Seq[String]] = chain +: h.children.getOrElse(chain.last, Nil).distinct.flatMap(c => walk(chain :+ c))
      val chains = walk(Seq(top))
      assert(chains.size > 10)
      for (c <- chains) assert(of(c, tags).isRight, of(c, tags))
      // The L2s, the Data bus and the memory arbiter count in the uncore; the L1 caches' logic as caches.
      val blockOf = chains.map(c => c.last -> of(c, tags).toOption.get).toMap
      assert(blockOf.collect { case (m, b) if m.startsWith("DataBus") || m.startsWith("MemArbiter") || m.startsWith("L2_") => b }.toSet == Set(Uncore))
      assert(blockOf.collect { case (m, b) if m.startsWith("ROCache") => b }.toSet == Set(Caches))
    }
}
