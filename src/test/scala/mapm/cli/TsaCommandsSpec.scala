package mapm.cli

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}
import mapm.MapmError
import mapm.numerics.FloatFormat
import mapm.testutil.TsaReference
import org.scalatest.funsuite.AnyFunSuite
import scala.sys.process._

/** emit-tsa (Verilog that lints clean) and tsa-vectors (model and --hw runs, expected columns,
  * bad input), with expected outputs from the exact reference. */
class TsaCommandsSpec extends AnyFunSuite {
  private val e3m3 = FloatFormat(3, 3)

  private def tmp(): Path = Files.createTempDirectory("tsa-cli")
  private def write(p: Path, text: String): Path = { Files.write(p, text.getBytes(StandardCharsets.UTF_8)); p }
  private def read(p: Path): Seq[String] = new String(Files.readAllBytes(p), StandardCharsets.UTF_8).linesIterator.toSeq

  /** Runs a command with stdout captured; returns (exit code, stdout). */
  private def runCmd(cmd: Command, args: String*): (Int, String) = {
    val buf = new java.io.ByteArrayOutputStream
    val rc = Console.withOut(buf)(cmd.run(args))
    (rc, buf.toString(StandardCharsets.UTF_8))
  }

  /** Seeded e3m3 rows (one in ten with an arbitrary, possibly invalid pattern) and the exact
    * (tcl, tcr, error) for each. */
  private def rows(n: Int): Seq[(Long, Long, Long, Boolean, Boolean, Boolean)] = {
    val rnd = new scala.util.Random(11)
    val valid = TsaReference.allValid(e3m3)
    def pick() = if (rnd.nextInt(10) == 0) rnd.nextLong() & e3m3.mask else valid(rnd.nextInt(valid.length))
    Seq.fill(n) {
      val (p, h, s) = (pick(), pick(), pick())
      if (Seq(p, h, s).exists(TsaReference.invalid(e3m3, _))) (p, h, s, true, true, true)
      else (p, h, s, TsaReference.tcl(e3m3, p, h, s), TsaReference.tcr(e3m3, p, h, s), false)
    }
  }
  private def b(x: Boolean) = if (x) "1" else "0"
  private def csv(rs: Seq[(Long, Long, Long, Boolean, Boolean, Boolean)], expected: Boolean): String =
    (if (expected) "p,h,s,tcl,tcr,error\n" else "# no expected columns\np, h, s\n") + rs.map { case (p, h, s, l, r, e) =>
      s"${e3m3.hex(p)},0x${e3m3.hex(h)},${e3m3.hex(s)}" + (if (expected) s",${b(l)},${b(r)},${b(e)}" else "")
    }.mkString("\n")

  test("tsa-vectors: model outputs equal exact arithmetic; no expected columns is just a run") {
    val d = tmp()
    val rs = rows(3000)
    val in = write(d.resolve("in.csv"), csv(rs, expected = false))
    val (rc, out) = runCmd(TsaVectorsCommand, "--in", in.toString, "--format", "3,3", "--out", d.resolve("o.csv").toString)
    assert(rc == 0, out)
    val lines = read(d.resolve("o.csv"))
    assert(lines.head == "p,h,s,tcl,tcr,error")
    assert(lines.tail == rs.map { case (p, h, s, l, r, e) => s"${e3m3.hex(p)},${e3m3.hex(h)},${e3m3.hex(s)},${b(l)},${b(r)},${b(e)}" })
    assert(out.contains("3000 rows"))
  }

  test("tsa-vectors: a wrong expected value is counted, the first one named, and the exit code is 1") {
    val d = tmp()
    val rs = rows(200)
    val good = write(d.resolve("good.csv"), csv(rs, expected = true))
    assert(runCmd(TsaVectorsCommand, "--in", good.toString, "--format", "e3m3", "--out", d.resolve("o.csv").toString)._1 == 0)
    val flipped = rs.zipWithIndex.map { case (r, i) => if (i == 17 || i == 50) r.copy(_4 = !r._4) else r }
    val bad = write(d.resolve("bad.csv"), csv(flipped, expected = true))
    val (rc, out) = runCmd(TsaVectorsCommand, "--in", bad.toString, "--format", "e3m3", "--out", d.resolve("o.csv").toString)
    assert(rc == 1)
    assert(out.contains("2 mismatches"), out)
    assert(out.contains(s"first mismatch: $bad:19:"), out) // header on line 1, row 17 on line 19
  }

  test("tsa-vectors: malformed input is one clear error naming the file and line") {
    val d = tmp()
    def err(text: String, fmt: String = "3,3"): String = {
      val f = write(d.resolve("x.csv"), text)
      intercept[MapmError](TsaVectorsCommand.run(Seq("--in", f.toString, "--format", fmt))).getMessage
    }
    assert(err("p,h\n1,2\n").contains("no 's' column"))
    assert(err("p,h,s\n1,2,zz\n").contains("x.csv:2: s = 'zz'"))
    assert(err("p,h,s\n1,2,100\n").contains("is not a e3m3 bit pattern"))
    assert(err("p,h,s,tcl\n1,2,3,7\n").contains("tcl = '7' must be 0 or 1"))
    assert(err("p,h,s\n1,2\n").contains("x.csv:2: 2 fields"))
    assert(err("").contains("empty"))
    assert(intercept[MapmError](TsaVectorsCommand.run(Seq("--in", d.resolve("none.csv").toString))).getMessage.contains("not found"))
  }

  test("tsa-vectors --hw: 3,000 e3m3 rows through the emitted Verilog in Verilator match exact arithmetic") {
    assume(Seq("sh", "-c", "command -v verilator").! == 0, "verilator is not installed")
    val d = tmp()
    val rs = rows(3000)
    val in = write(d.resolve("in.csv"), csv(rs, expected = true))
    val (rc, out) = runCmd(TsaVectorsCommand, "--in", in.toString, "--format", "3,3", "--hw", "--out", d.resolve("o.csv").toString)
    assert(rc == 0, out)
    assert(out.contains("0 mismatches (expected columns, model vs hardware)"), out)
    val lines = read(d.resolve("o.csv"))
    assert(lines.head == "p,h,s,tcl,tcr,error,hw_tcl,hw_tcr,hw_error")
    assert(lines.tail.map(_.split(",").drop(6).mkString(",")) == rs.map { case (_, _, _, l, r, e) => s"${b(l)},${b(r)},${b(e)}" })
  }

  test("emit-tsa: fp32, bf16 and e3m3 Verilog lint clean under verilator -Wall") {
    assume(Seq("sh", "-c", "command -v verilator").! == 0, "verilator is not installed")
    val d = tmp()
    for ((args, name) <- Seq(Seq("--exp", "8", "--man", "23") -> "TSA_e8m23_t16.sv",
                             Seq("--format", "bf16", "--tag-width", "1") -> "TSA_e8m7_t1.sv",
                             Seq("--exp", "3", "--man", "3", "--tag-width", "64") -> "TSA_e3m3_t64.sv")) {
      val (rc, out) = runCmd(EmitTsaCommand, args ++ Seq("--out", d.toString): _*)
      assert(rc == 0, out)
      val file = d.resolve(name)
      assert(Files.isRegularFile(file), s"$name not written: $out")
      // Waiver: DECLFILENAME only. firtool writes the TSA and its submodules into one file, so
      // most module names cannot match the file name; nothing else is waived.
      val log = new StringBuilder
      val lint = Seq("verilator", "--lint-only", "-Wall", "-Wno-DECLFILENAME", file.toString)
        .!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
      assert(lint == 0 && log.isEmpty, s"lint of $file:\n$log")
    }
  }

  test("emit-tsa: names the module after the format and tag width; bad widths are one clear error") {
    val d = tmp()
    val (rc, out) = runCmd(EmitTsaCommand, "--exp", "5", "--man", "10", "--tag-width", "3", "--out", d.toString)
    assert(rc == 0 && out.contains("latency 17 cycles"), out)
    val sv = read(d.resolve("TSA_e5m10_t3.sv")).mkString("\n")
    assert(sv.contains("module TSA_e5m10_t3("))
    assert(intercept[MapmError](EmitTsaCommand.run(Seq("--exp", "1"))).getMessage.contains("exponent width"))
    assert(intercept[MapmError](EmitTsaCommand.run(Seq("--format", "fp16", "--man", "3"))).getMessage.contains("not both"))
    assert(intercept[MapmError](EmitTsaCommand.run(Seq("--tag-width", "0"))).getMessage.contains("--tag-width"))
  }
}
