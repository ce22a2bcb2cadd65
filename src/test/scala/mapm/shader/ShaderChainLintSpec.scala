package mapm.shader

import mapm.Slow
import java.nio.file.Files
import mapm.numerics.FloatFormat
import mapm.sim.Emit
import org.scalatest.funsuite.AnyFunSuite
import scala.sys.process._

/** Verilator's lint (`--lint-only -Wall`) on the emitted SystemVerilog of the shader chain.
  * One waiver: DECLFILENAME, because CIRCT writes every module of the design into one file. */
@Slow
class ShaderChainLintSpec extends AnyFunSuite {
  private val configs = Seq(FloatFormat.fp32 -> 0, FloatFormat.fp32 -> 2, FloatFormat.fp32 -> 3, FloatFormat.fp16 -> 0,
    FloatFormat.fp16 -> 2, FloatFormat.fp16 -> 3, FloatFormat.bf16 -> 3, FloatFormat.fp64 -> 3, FloatFormat(5, 4) -> 0)
  for ((f, g) <- configs)
    test(s"ShaderChain $f g = $g passes verilator --lint-only -Wall") {
      val dir = Files.createTempDirectory("soa-lint")
      val top = ShaderChain.name(f, g)
      val file = Emit.toFile(new ShaderChain(f, g), dir, s"$top.sv")
      val log = new StringBuilder
      val rc = Process(Seq("verilator", "--lint-only", "-Wall", "-Wno-DECLFILENAME", "--top-module", top, file.toString))
        .!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
      assert(rc == 0 && !log.toString.contains("%Warning"), log.toString.linesIterator.take(20).mkString("\n"))
    }
}
