package mapm.format

import java.nio.file.{Files, Paths}

import mapm.numerics.FrameAccum
import org.scalatest.funsuite.AnyFunSuite
import scala.sys.process._

/** The register map ([[RegisterMap]]), its generated C header and the C driver (tools/driver):
  * the map's own rules, the header and driver compiled as C99 and as C++ with every warning an
  * error, and the driver run against a register file in C whose identification values and
  * recorded writes are checked here against the map. Cancels without gcc. */
class RegisterMapSpec extends AnyFunSuite {
  private val dir = Paths.get("target/regmap-test").toAbsolutePath
  private val driver = Paths.get("tools/driver").toAbsolutePath
  private lazy val gccPresent = mapm.testutil.HostTools.onPath("gcc") && mapm.testutil.HostTools.onPath("g++")

  test("the map: ID reads \"MAPM\" in memory order, words do not overlap, every counter has a 64-bit register in order, the causes start with the accumulation's faults") {
    val id = RegisterMap.Magic
    assert((0 until 4).map(i => ((id >> (8 * i)) & 0xff).toChar).mkString == "MAPM")
    val words = RegisterMap.registers.flatMap(r => (0 until r.words).map(r.offset + 4 * _))
    assert(words.distinct.size == words.size && words.forall(w => w % 4 == 0 && w < RegisterMap.SpaceBytes))
    for ((n, k) <- CounterSet.Names.zipWithIndex) {
      val r = RegisterMap("CNT_" + n.toUpperCase)
      assert(r.offset == RegisterMap.CounterBase + 8 * k && r.bits == 64 && r.access == Access.RO)
    }
    assert(RegisterMap.causes.take(FrameAccum.Faults.size).map(_.bit) == FrameAccum.Faults.map(_.bit))
    assert(RegisterMap.cause("RANGE").reason == FrameAccum.Range.reason)
    assertThrows[IllegalArgumentException](Register("X", 0x4, Access.RO, "", bits = 64))
    assertThrows[IllegalArgumentException](Register("X", 0x0, Access.RO, "", Seq(RegField("a", 0, 4, ""), RegField("b", 3, 2, ""))))
    assertThrows[IllegalArgumentException](RegField("a", 30, 4, ""))
  }

  test("the Markdown table lists every register, counter and cause") {
    val md = RegisterMap.markdown
    for (r <- RegisterMap.registers) assert(md.contains(s"`${r.name}`"), r.name)
    for (c <- RegisterMap.causes) assert(md.contains(s"| ${c.bit} | `${c.name}` | ${c.reason} |"))
  }

  private def compile(lang: String, out: String, sources: String*): Unit = {
    val cmd = (if (lang == "c") Seq("gcc", "-std=c99") else Seq("g++", "-x", "c++", "-std=c++17")) ++
      Seq("-Wall", "-Wextra", "-Werror", "-pedantic", "-I", dir.toString, "-I", driver.toString, "-o", dir.resolve(out).toString) ++ sources
    val log = new StringBuilder
    val rc = Process(cmd).!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
    assert(rc == 0, s"${cmd.mkString(" ")}\n$log")
  }

  test("the header and the driver compile as C99 and as C++ with -Wall -Wextra -Werror -pedantic; the driver runs against a register file in C") {
    assume(gccPresent, "gcc and g++ are needed")
    Files.createDirectories(dir)
    Files.writeString(dir.resolve("mapm_regs.h"), RegisterMap.cHeader)
    // A register file: the identification values come from this spec; STATUS reads busy for two
    // polls after START, then done (and error when the program sets ERROR_CAUSE).
    val hw = Map("HW_COUNTS" -> (16L | 16L << 8 | 2L << 16 | 3L << 24), "HW_FORMAT" -> (8L | 23L << 8 | 4L << 16),
      "HW_MEMORY" -> (16L | 6L << 8 | 32L << 16), "HW_FRAME" -> (13L | 64L << 8 | 24L << 16), "HW_INDICES" -> (24L | 22L << 8))
    def reg(n: String) = RegisterMap(n).offset
    val prog =
      s"""#include <stdio.h>
         |#include <string.h>
         |#include "mapm_driver.h"
         |static uint32_t regs[MAPM_REG_SPACE_BYTES / 4];
         |static int busyPolls;
         |static uint32_t rd(void* ctx, uint32_t off) {
         |  (void)ctx;
         |  if (off == MAPM_REG_STATUS) { if (busyPolls > 0) { busyPolls--; return MAPM_STATUS_BUSY_MASK; } return regs[off / 4]; }
         |  return regs[off / 4];
         |}
         |static void wr(void* ctx, uint32_t off, uint32_t v) {
         |  (void)ctx;
         |  printf("w %u %u\\n", off, v);
         |  if (off == MAPM_REG_CONTROL && (v & MAPM_CONTROL_START_MASK)) busyPolls = 2;
         |  else if (off != MAPM_REG_CONTROL && off != MAPM_REG_IRQ_STATUS) regs[off / 4] = v;
         |}
         |int main(void) {
         |  mapm_bus bus = {rd, wr, 0, 0};
         |  mapm_info info;
         |  mapm_frame f;
         |  char line[512];
         |  int rc;
         |  printf("noid %d\\n", mapm_identify(&bus, &info));
         |  regs[MAPM_REG_ID / 4] = MAPM_ID_MAGIC;
         |  regs[MAPM_REG_VERSION / 4] = MAPM_REGMAP_VERSION + 1;
         |  printf("version %d\\n", mapm_identify(&bus, &info));
         |  regs[MAPM_REG_VERSION / 4] = MAPM_REGMAP_VERSION;
         |  ${hw.map { case (k, v) => s"regs[MAPM_REG_$k / 4] = ${v}u;" }.mkString(" ")}
         |  rc = mapm_identify(&bus, &info);
         |  printf("info %d %u %u %u %u %u %u %u %u %u %u %u %u %u %u %u\\n", rc, info.tsm, info.som, info.soa, info.guard, info.exp_width, info.man_width,
         |         info.slot_bytes, info.data_bytes, info.id_bits, info.addr_bits, info.tile_log2, info.acc_bits, info.count_bits, info.query_bits, info.node_bits);
         |  memset(&f, 0, sizeof f);
         |  f.exp_width = 5; f.man_width = 10; f.slot_bytes = 2;
         |  printf("format %d\\n", mapm_configure(&bus, &info, &f));
         |  f.exp_width = 8; f.man_width = 23; f.slot_bytes = 4;
         |  f.node_base = 64; f.photon_base = 0x123456789ull; f.query_base = 0x40000; f.stream_base = 0x50000; f.frame_base = 0x60000;
         |  f.radius = 0x3f800000u; f.node_count = 2000; f.query_count = 123575; f.pixel_base = 0; f.pixel_count = 4500; f.frame_scale = -38; f.use_stream = 1;
         |  printf("configure %d\\n", mapm_configure(&bus, &info, &f));
         |  printf("start %d\\n", mapm_start(&bus, 0));
         |  regs[MAPM_REG_STATUS / 4] = MAPM_STATUS_DONE_MASK;
         |  printf("shortwait %d\\n", mapm_wait(&bus, 1));
         |  printf("wait %d\\n", mapm_wait(&bus, 10));
         |  regs[(MAPM_COUNTER_BASE + 8) / 4] = 0x89abcdefu; regs[(MAPM_COUNTER_BASE + 12) / 4] = 0x1234567u;
         |  printf("counter %llu\\n", (unsigned long long)mapm_counter(&bus, 1));
         |  regs[MAPM_REG_STATUS / 4] = MAPM_STATUS_DONE_MASK | MAPM_STATUS_ERROR_MASK;
         |  regs[MAPM_REG_ERROR_CAUSE / 4] = MAPM_ERR_OVERLAP | MAPM_ERR_PIXEL;
         |  rc = mapm_wait(&bus, 10);
         |  mapm_describe(&bus, rc, line, sizeof line);
         |  printf("hw %d %s\\n", rc, line);
         |  mapm_describe(&bus, MAPM_E_FORMAT, line, 8);
         |  printf("short %s\\n", line);
         |  return 0;
         |}
         |""".stripMargin
    Files.writeString(dir.resolve("prog.c"), prog)
    val srcs = Seq(dir.resolve("prog.c").toString, driver.resolve("mapm_driver.c").toString,
      Paths.get("docs/examples/mapm_run_frame.c").toAbsolutePath.toString)
    compile("c", "prog_c", srcs: _*)
    compile("c++", "prog_cpp", srcs: _*)
    for (exe <- Seq("prog_c", "prog_cpp")) {
      val out = Process(Seq(dir.resolve(exe).toString)).!!.linesIterator.toSeq
      def line(tag: String) = out.find(_.startsWith(tag + " ")).getOrElse(fail(s"no $tag line in\n${out.mkString("\n")}")).drop(tag.length + 1)
      assert(line("noid") == "-1" && line("version") == "-2" && line("format") == "-3")
      assert(line("info") == "0 16 16 2 3 8 23 4 16 6 32 13 64 24 24 22")
      assert(line("configure") == "0" && line("start") == "0")
      assert(line("shortwait") == "-5" && line("wait") == "0" && line("hw").startsWith("-6 "))
      assert(line("counter") == (0x89abcdefL | 0x1234567L << 32).toString)
      assert(line("hw") == "-6 the frame pass ended in error: " +
        Seq("OVERLAP", "PIXEL").map(RegisterMap.cause(_).reason).mkString("; "))
      assert(line("short") == "the arr")
      // Every frame register written once with its value, low word then high word.
      val writes = out.filter(_.startsWith("w ")).map(_.split(' ')).map(a => a(1).toInt -> a(2).toLong)
      val want = Seq("NODE_BASE" -> 64L, "PHOTON_BASE" -> 0x123456789L, "QUERY_BASE" -> 0x40000L, "STREAM_BASE" -> 0x50000L,
        "FRAME_BASE" -> 0x60000L, "RADIUS" -> 0x3f800000L).flatMap { case (n, v) => Seq(reg(n) -> (v & 0xffffffffL), reg(n) + 4 -> (v >>> 32)) } ++
        Seq("NODE_COUNT" -> 2000L, "QUERY_COUNT" -> 123575L, "PIXEL_BASE" -> 0L, "PIXEL_COUNT" -> 4500L, "FRAME_SCALE" -> ((-38L) & 0xffffffffL), "QUERY_ORDER" -> 1L).map { case (n, v) => reg(n) -> v }
      assert(writes.take(want.size) == want)
      assert(writes.drop(want.size) == Seq(reg("IRQ_STATUS") -> 1L, reg("IRQ_ENABLE") -> 0L, reg("CONTROL") -> 1L))
    }
  }
}
