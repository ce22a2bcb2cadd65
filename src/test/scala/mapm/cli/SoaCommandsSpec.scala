package mapm.cli

import mapm.Slow
import java.nio.file.Files
import mapm.MapmError
import mapm.testutil.SharedFiles
import org.scalatest.funsuite.AnyFunSuite

/** The SOA commands: emit-soa writes the chain's Verilog, soa-vectors checks a vector file
  * (model and hardware) and reports mismatches through its exit code, bad input is one error. */
@Slow
class SoaCommandsSpec extends AnyFunSuite with SharedFiles {
  private def run(cmd: Command, args: String*): (Int, String) = {
    val out = new java.io.ByteArrayOutputStream()
    val code = Console.withOut(out)(cmd.run(args))
    (code, out.toString("UTF-8"))
  }

  test("emit-soa writes SOA_e5m10_g2.sv and reports the chain's latency 31, the cond check's 36, the SOA's 36 and the flip-flops") {
    val dir = Files.createTempDirectory("emit-soa")
    val (code, text) = run(EmitSoaCommand, "--format", "5,10", "--g", "2", "--out", dir.toString)
    assert(code == 0)
    val sv = new String(Files.readAllBytes(dir.resolve("SOA_e5m10_g2.sv")), "UTF-8")
    assert(sv.contains("module SOA_e5m10_g2(") && sv.contains("module ShaderChain_e5m10_g2(") && sv.contains("module CondCheck_e5m10_t1_a9m8c1_sg("))
    assert(text.linesIterator.exists(l => l.contains("whole chain") && l.contains(" 31 ")), text)
    assert(text.linesIterator.exists(l => l.contains("cond check") && l.contains(" 36 ")), text)
    assert(text.linesIterator.exists(l => l.contains("SOA (") && l.contains(" 36 ")), text)
    assert(text.linesIterator.exists(_.matches("""\s*flip-flops: \d+""")))
  }

  test("soa-vectors passes a public file on model and hardware, and fails it with the wrong g") {
    val file = requireShared("vectors/fp16_g3_public.csv").toString
    val (ok, text) = run(SoaVectorsCommand, "--in", file, "--format", "fp16", "--g", "3", "--hw")
    assert(ok == 0, text)
    assert(text.contains("model: 2000 rows, 0 mismatches") && text.contains("hardware: 2000 rows, 0 mismatches"), text)
    val (bad, badText) = run(SoaVectorsCommand, "--in", file, "--format", "fp16", "--g", "2")
    assert(bad == 1 && badText.contains("first: row id"), badText)
  }

  test("soa-vectors --arith conventional passes a conventional file in the model; the online model fails it") {
    val file = requireShared("vectors/conventional/bf16_public.csv").toString
    val (ok, text) = run(SoaVectorsCommand, "--in", file, "--format", "bf16", "--arith", "conventional")
    assert(ok == 0 && text.contains("model: 2000 rows, 0 mismatches"), text)
    val (bad, badText) = run(SoaVectorsCommand, "--in", file, "--format", "bf16")
    assert(bad == 1 && badText.contains("first: row id"), badText)
  }

  test("bad input is one MapmError naming the problem") {
    val f = Files.createTempFile("soa", ".csv")
    Files.writeString(f, "id,kernel,brdf,h,power,contrib,expected,flags,s,m,E\n0,3f8,3c00,3c00,3c00,3c00,3c00,0,,,\n")
    f.toFile.deleteOnExit()
    val m = intercept[MapmError](SoaVectorsCommand.run(Seq("--in", f.toString, "--format", "fp16")))
    assert(m.getMessage.contains(s"$f:2") && m.getMessage.contains("kernel"))
    assert(intercept[MapmError](SoaVectorsCommand.run(Seq("--in", "/nonexistent.csv"))).getMessage.contains("does not exist"))
    assert(intercept[MapmError](EmitSoaCommand.run(Seq("--g", "9"))).getMessage.contains("--g"))
  }
}
