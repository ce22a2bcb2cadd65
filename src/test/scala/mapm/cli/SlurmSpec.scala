package mapm.cli

import mapm.evaluation._

import mapm.Slow
import java.nio.file.{Files, Paths}

import org.scalatest.funsuite.AnyFunSuite

/** A sweep through a real Slurm cluster (.ci/run starts one with tools/slurm-local.sh): two
  * configurations of a tiny frame as a job array and its collect step, against the same sweep run
  * locally. Outside CI, a machine without a running cluster cancels it with the reason. */
@Slow
class SlurmSpec extends AnyFunSuite {
  test("sweep --slurm: the array tasks and the collect step give the local run's CSV, cycles identical") {
    assume(mapm.testutil.HostTools.onPath("verilator"), "verilator is not on PATH")
    val running = mapm.testutil.HostTools.onPath("sbatch") && sys.env.contains("SLURM_CONF") &&
      scala.util.Try(scala.sys.process.Process(Seq("sinfo", "-h")).!!).isSuccess
    if (sys.env.get("CI").contains("true")) assert(running, "CI must start Slurm (tools/slurm-local.sh start) before the tests")
    assume(running, "no Slurm cluster answers (start one: tools/slurm-local.sh start; eval \"$(tools/slurm-local.sh env)\")")
    val spec = new SweepSpec
    val base = Paths.get("target/slurm-test")
    val args = Seq("--configs", "1/1/1,2/1/2", "--scene", spec.tinyScene.toString, "--threads", "1", "--no-cost")
    assert(SweepCommand.run(args ++ Seq("--out", base.resolve("local").toString, "--jobs", "1")) == 0)
    val t0 = System.nanoTime()
    assert(SweepCommand.run(args ++ Seq("--out", base.resolve("slurm").toString, "--slurm")) == 0)
    info(f"through Slurm in ${(System.nanoTime() - t0) / 1e9}%.1f s")
    val local = spec.readCsv(base.resolve("local/sweep-test-tiny-sweep.csv"))
    val slurm = spec.readCsv(base.resolve("slurm/sweep-test-tiny-sweep.csv"))
    assert(slurm.map(_("config")) == Seq("1/1/1", "2/1/2") && slurm.forall(_("result") == "PASS"))
    val same = Seq("cycles", "so_per_cycle", "ts_ops_per_cycle", "bytes_fetched") ++ SweepReport.caches.map("hit_rate_" + _)
    assert(slurm.map(r => same.map(r)) == local.map(r => same.map(r)))
    // each task ran in its own Slurm job and left its log
    val logs = base.resolve("slurm/sweep-test-tiny-rtl/slurm")
    for (i <- 0 to 1) assert(new String(Files.readAllBytes(logs.resolve(s"task-$i.log")), "UTF-8").contains("PASS cycles"))
    assert(Files.isRegularFile(logs.resolve("collect.log")))
  }
}
