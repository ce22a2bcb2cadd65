package mapm.memory

import java.nio.file.Files
import mapm.sim.{Emit, Verilator}
import mapm.params.{CacheParams, CachesParams, MemoryParams}
import org.scalatest.funsuite.AnyFunSuite
import scala.sys.process._

/** The emitted SystemVerilog of every memory-side module passes `verilator --lint-only -Wall`
  * without a single warning, at the Table 4.2 geometries and at small test geometries
  * (DECLFILENAME is off: one file holds the module and its submodules). */
class MemoryLintSpec extends AnyFunSuite {
  private def lint(name: String, gen: => chisel3.RawModule): Unit = {
    val dir = Files.createTempDirectory("lint")
    val file = Emit.toFile(gen, dir, s"$name.sv")
    val (top, _) = Emit.topPorts(new String(Files.readAllBytes(file), "UTF-8"))
    val log = new StringBuilder
    val rc = Process(Seq(Verilator.executable, "--lint-only", "-Wall", "-Wno-DECLFILENAME", "--top-module", top, file.toString))
      .!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
    assert(rc == 0 && log.isEmpty, s"$name ($top) lint:\n$log")
  }

  private val mem = MemoryParams()
  private val t42 = CachesParams()
  // The MAPM's caches at Table 4.2: the L1s feed their L2s one line per beat.
  private val tsL1 = CacheConfig(t42.tsL1, 8, 4, mem.addressBits, downBytes = t42.tsL1.lineBytes)
  private val sopL1 = CacheConfig(t42.sopL1, 16, 4, mem.addressBits, downBytes = t42.sopL1.lineBytes)
  private val configs = Seq(
    "tsL1" -> tsL1,
    "tsL2" -> CacheConfig.below(tsL1.down.widenId(4), t42.tsL2, mem.dataBytes),
    "soq" -> CacheConfig(t42.soq, 32, 6, mem.addressBits, mem.dataBytes),
    "sopL1" -> sopL1,
    "sopL2" -> CacheConfig.below(sopL1.down.widenId(4), t42.sopL2, mem.dataBytes),
    "fa8" -> CacheConfig(CacheParams(256, 32, 8), 8, 3, 16, 8, mshrs = 1, targets = 1),
    "dm" -> CacheConfig(CacheParams(512, 16, 1), 16, 2, 16, 16, mshrs = 2, targets = 2)
  )

  for ((name, cfg) <- configs) test(s"$name cache ${cfg.name} lints clean") {
    lint(name, new ReadOnlyCache(cfg))
  }

  test("memory arbiters lint clean") {
    // The MAPM's memory port: TS L2, SOQ and SOP L2 (different id widths and line lengths).
    lint("arbMem", new MemArbiter(Seq(configs(1)._2.down, configs(2)._2.down, configs(4)._2.down), mem.maxOutstanding))
    lint("arb1", new MemArbiter(configs(5)._2.down, 1, 1))
    lint("arb16", new MemArbiter(tsL1.down, 16, 8))
  }
}
