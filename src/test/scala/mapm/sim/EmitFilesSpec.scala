package mapm.sim

import mapm.pipeline.Configure

import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.{Files, Path}

import scala.sys.process._

import mapm.cli.EmitCommand
import mapm.numerics.FloatFormat
import mapm.params.MapmParams
import org.scalatest.funsuite.AnyFunSuite

/** `mapm emit`'s files for a 2/1/2 MAPM in a 10-bit format, read back: the manifest against the
  * configuration's own cache and module counts (the data memories hold exactly the five caches of
  * Table 4.2 at their counts; each TS L1 is there once per TSM, each SOA's clock gate once per SOA),
  * the memories against the text of the emitted memory file, the `--repl-seq-mem` lines against the
  * manifest, and the file list against Verilator, which must elaborate the design from it alone. */
class EmitFilesSpec extends AnyFunSuite {
  private val (tsm, som, soa) = (2, 1, 2)
  private val p = Configure.of(tsm, som, soa, FloatFormat(5, 4), 3)
  private val top = s"Mapm_${p.name}"
  private lazy val dir: Path = {
    val d = Files.createTempDirectory("emit-files")
    val out = new java.io.ByteArrayOutputStream
    assert(Console.withOut(out)(EmitCommand.run(Seq("--tsm", s"$tsm", "--som", s"$som", "--soa", s"$soa", "--format", "5,4",
      "--out", d.toString))) == 0)
    assert(out.toString("UTF-8").contains(s"wrote ${d.resolve(s"$top.f")}"))
    d
  }
  private def read(f: String) = new String(Files.readAllBytes(dir.resolve(f)), UTF_8)
  private lazy val manifest = ujson.read(read(s"${top}_manifest.json"))
  private lazy val mems = manifest("memories").arr.toSeq

  test("the data memories hold the five caches at their counts; each TS L1 appears once per TSM") {
    val c = p.caches
    val cacheBytes = c.tsL1.sizeBytes.toLong * tsm + c.tsL2.sizeBytes + c.soq.sizeBytes + c.sopL1.sizeBytes.toLong * som + c.sopL2.sizeBytes
    val dataBits = mems.filter(_("module").str.startsWith("dataMem")).map(m => m("depth").num.toLong * m("width").num.toLong * m("instances").arr.size).sum
    assert(dataBits == 8 * cacheBytes, s"data memories $dataBits bits, caches ${8 * cacheBytes}")
    val l1 = mems.flatMap(_("instances").arr.map(_.str)).filter(i => i.contains(".ts.tsms_") && i.contains(".l1.dataMem"))
    assert(l1.size == tsm && l1.map(_.split('.')(2)).toSet == (0 until tsm).map(i => s"tsms_$i").toSet, l1)
    assert(mems.forall(m => m("readLatency").num == 1 && m("readPorts").num == 1 && m("writePorts").num == 1))
  }

  test("each memory of the manifest is a module of the memory file with that array, and its repl-seq-mem line says the same") {
    val sv = read(s"${top}_memories.sv")
    val defined = """(?m)^module\s+(\w+)""".r.findAllMatchIn(sv).map(_.group(1)).toSeq
    assert(defined.sorted == mems.map(_("module").str).sorted, "the memory file defines exactly the manifest's memories")
    val conf = read(s"${top}_memories.conf").linesIterator.toSeq
    for (m <- mems) {
      val (name, d, w) = (m("module").str, m("depth").num.toLong, m("width").num.toInt)
      val body = sv.substring(sv.indexOf(s"module $name("))
      assert(body.contains(s"reg [${w - 1}:0] Memory[0:${d - 1}];"), name)
      val mask = m("maskGranularity").numOpt.map(_.toInt)
      assert(mask.isDefined == body.takeWhile(_ != ';').contains("W0_mask"), name)
      val ports = if (mask.isDefined) "mwrite,read" else "write,read"
      assert(conf.contains(s"name $name depth $d width $w ports $ports" + mask.fold("")(g => s" mask_gran $g")), name)
    }
    assert(conf.size == mems.size)
  }

  test("the clock gate is the one black box, in a file of its own: each SOA's, and its stage and ring gates inside it") {
    val boxes = manifest("blackBoxes").arr.toSeq
    assert(boxes.map(_("module").str) == Seq("ClockGate"))
    val instances = boxes.head("instances").arr.map(_.str).toSeq
    assert(boxes.head("description").str.toLowerCase.contains("clock gate"))
    // One SOA gate per SOM lane; every other gate is inside an SOA (docs/soa.md, "Stage clock gating").
    val soaGates = instances.filter(_.endsWith(".soa_clock_g"))
    assert(soaGates.size == som * soa, soaGates)
    val lanes = soaGates.map(_.stripSuffix("_clock_g"))
    assert(instances.filterNot(soaGates.contains).forall(i => lanes.exists(l => i.startsWith(l + "."))))
    assert(instances.size > som * soa * mapm.shader.SOA.latency(FloatFormat(5, 4), 3), s"${instances.size} gates")
    assert(read(s"${top}_blackboxes.sv").contains("always_latch") && !read(s"$top.sv").contains("always_latch"))
  }

  test("the file list names the three files, and Verilator elaborates the design from it alone") {
    assume(Verilator.available, "verilator is not installed")
    val files = read(s"$top.f").linesIterator.toSeq
    assert(files.toSet == manifest("files").arr.map(_.str).toSet && files.size == 3)
    val log = new StringBuilder
    val rc = Process(Seq("verilator", "--lint-only", "-Wno-fatal", "-Wno-lint", "-Wno-style", "--top-module", top, "-f", s"$top.f"),
      dir.toFile).!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
    assert(rc == 0 && !log.toString.contains("%Error"), log.toString.linesIterator.take(10).mkString("\n"))
  }
}
