package mapm.format

import java.nio.file.{Files, Path, Paths}

import mapm.model._

import mapm.numerics._
import org.scalatest.funsuite.AnyFunSuite
import scala.sys.process._

/** The generated `mapm_formats.h` ([[CHeader.formats]]) compiled with g++ into a small reader that
  * prints every field of a Scala-written memory image (2-, 4- and 8-byte slots) and expected-SO
  * file; its output must equal the same listing made from the Scala objects: an independent
  * check that the C++ getters and the Scala writers agree. Cancels without g++. */
class CHeaderSpec extends AnyFunSuite {
  private val dir = Paths.get("target/format-test")

  private lazy val gppPresent: Boolean = mapm.testutil.HostTools.onPath("g++")

  private val reader =
    """#include <cinttypes>
      |#include <cstdio>
      |#include <vector>
      |#include "mapm_formats.h"
      |static std::vector<uint8_t> load(const char* path) {
      |  std::vector<uint8_t> b;
      |  FILE* f = fopen(path, "rb");
      |  for (int c; (c = fgetc(f)) != EOF;) b.push_back((uint8_t)c);
      |  fclose(f);
      |  return b;
      |}
      |int main(int, char** argv) {
      |  const std::vector<uint8_t> img = load(argv[1]);
      |  const uint8_t* h = img.data();
      |  const unsigned s = image_slot(h);
      |  printf("image %d %u %u %u %u %u\n", image_magic(h) == IMAGE_MAGIC, image_version(h), image_exp_width(h), image_man_width(h), image_layout(h), s);
      |  printf("counts %u %u %" PRIu64 "\n", image_nodes(h), image_queries(h), image_h(h));
      |  printf("bases %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64 "\n", image_photon_base(h), image_query_base(h), image_stream_base(h), image_total_bytes(h));
      |  for (uint32_t i = 0; i < image_nodes(h); i++) {
      |    const uint8_t* n = h + IMAGE_BYTES + node_bytes(s) * i;
      |    const uint8_t* p = h + image_photon_base(h) + photon_bytes(s) * i;
      |    printf("node %u %" PRIu64 " %u photon %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64 "\n",
      |           i, (uint64_t)node_split(n, s), node_word(n, s), (uint64_t)photon_x(p, s), (uint64_t)photon_y(p, s), (uint64_t)photon_z(p, s),
      |           (uint64_t)photon_power_r(p, s), (uint64_t)photon_power_g(p, s), (uint64_t)photon_power_b(p, s), (uint64_t)photon_kernel(p, s),
      |           (uint64_t)photon_brdf(p, s));
      |  }
      |  for (uint32_t q = 0; q < image_queries(h); q++) {
      |    const uint8_t* r = h + image_query_base(h) + query_bytes(s) * q;
      |    printf("query %u %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64 " %u\n", q, (uint64_t)query_contrib_r(r, s),
      |           (uint64_t)query_contrib_g(r, s), (uint64_t)query_contrib_b(r, s), (uint64_t)query_x(r, s), (uint64_t)query_y(r, s),
      |           (uint64_t)query_z(r, s), query_pixel(r, s));
      |  }
      |  for (uint32_t k = 0; k < image_queries(h); k++) {
      |    const uint8_t* e = h + image_stream_base(h) + stream_bytes(s) * k;
      |    printf("stream %u %u\n", k, stream_query(e, s));
      |  }
      |  const std::vector<uint8_t> exp = load(argv[2]);
      |  const uint8_t* x = exp.data();
      |  const unsigned c = expected_colour_bytes(x);
      |  printf("expected %d %u %u %u %u %" PRIu64 " %u %u\n", expected_magic(x) == EXPECTED_MAGIC, expected_version(x), expected_exp_width(x),
      |         expected_man_width(x), c, expected_count(x), expected_width(x), expected_height(x));
      |  for (uint64_t i = 0; i < expected_count(x); i++) {
      |    const uint8_t* r = x + EXPECTED_BYTES + so_bytes(c) * i;
      |    const unsigned fl = so_flags(r, c), m = (1u << SO_FLAG_BITS) - 1;
      |    printf("so %u %u %" PRIu64 " %" PRIu64 " %" PRIu64 " %u %u %u %u\n", so_query(r, c), so_photon(r, c), (uint64_t)so_colour_r(r, c),
      |           (uint64_t)so_colour_g(r, c), (uint64_t)so_colour_b(r, c),
      |           fl & m, (fl >> SO_FLAG_BITS) & m, (fl >> (2 * SO_FLAG_BITS)) & m, (unsigned)((fl >> SO_COND_BIT) & 1));
      |  }
      |  return 0;
      |}
      |""".stripMargin

  private lazy val exe: Path = {
    Files.createDirectories(dir)
    Files.write(dir.resolve("mapm_formats.h"), CHeader.formats.getBytes("UTF-8"))
    mapm.testutil.HostTools.gpp(dir, "reader", reader, Seq(dir))
  }

  /** What the reader must print for `img` and the expected-SO `so` file contents. */
  private def listing(img: MemoryImage, so: ExpectedSoFile.Contents): Seq[String] = {
    val f = img.format
    def u(v: Long): String = java.lang.Long.toUnsignedString(v)
    Seq(s"image 1 ${MemoryLayout.Version} ${f.expWidth} ${f.manWidth} ${img.layout.code} ${img.slot}",
      s"counts ${img.nodeCount} ${img.queryCount} ${u(img.h)}",
      s"bases ${img.photonBase} ${img.queryBase} ${img.streamBase} ${img.totalBytes}") ++
      (0 until img.nodeCount).map(i => s"node $i ${u(img.nodeSplit(i))} ${img.nodeWord(i).toLong & 0xffffffffL} photon ${img.photon.map(a => u(a(i))).mkString(" ")}") ++
      (0 until img.queryCount).map(q => s"query $q ${img.contribution.map(a => u(a(q))).mkString(" ")} ${img.position.map(a => u(a(q))).mkString(" ")} ${img.pixel(q)}") ++
      img.stream.zipWithIndex.map { case (q, k) => s"stream $k $q" } ++
      (s"expected 1 ${ExpectedSoFile.Version} ${so.format.expWidth} ${so.format.manWidth} ${if (so.format.width > 32) 8 else 4} ${so.rows.size} ${so.width} ${so.height}" +:
        so.rows.map(r => s"so ${r.query} ${r.photon} ${r.colour.map(u).mkString(" ")} ${r.flags.mkString(" ")} ${if (r.cond) 1 else 0}"))
  }

  for ((f, layout) <- Seq((FloatFormat.fp32, SlotLayout.Packed), (FloatFormat.fp16, SlotLayout.Packed), (FloatFormat.fp16, SlotLayout.Wide),
                          (FloatFormat.fp64, SlotLayout.Packed), (FloatFormat(10, 40), SlotLayout.Wide)))
    test(s"g++ reads a Scala-written ${f.name} $layout image and expected-SO file through mapm_formats.h") {
      assume(gppPresent, "g++ is not on PATH: this test compiles the generated header with it")
      val rnd = new scala.util.Random(f.width)
      def pt() = Vec3(rnd.nextDouble() * 50, rnd.nextDouble() * 40, rnd.nextDouble() * 60)
      val photons = Array.fill(40)(Photon(pt(), Vec3(rnd.nextDouble(), rnd.nextDouble(), rnd.nextDouble()), Vec3(0, -1, 0), Vec3(0, 1, 0)))
      val queries = Array.fill(12)(QueryPoint(pt(), rnd.nextInt(1000), Vec3(rnd.nextDouble(), rnd.nextDouble(), rnd.nextDouble()), Vec3(0, 1, 0)))
      val map = PhotonMap.build(photons, Box(Vec3.zero, Vec3(50, 40, 60)), f, 3.0)
      val img = mapm.sim.FrameImage.of(map, QuerySet.build(queries, f), layout, Some(rnd.shuffle((0 until 12).toList).toArray))
      val rows = Seq.tabulate(30)(i => ExpectedSoFile.Row(rnd.nextInt(12), i, Seq.fill(3)(rnd.nextLong() & f.mask), Seq.fill(3)(rnd.nextInt(8)), rnd.nextBoolean()))
      Files.createDirectories(dir)
      val (imageFile, soFile) = (dir.resolve(s"${f.name}-$layout.img"), dir.resolve(s"${f.name}-$layout.so"))
      img.write(imageFile)
      ExpectedSoFile.write(soFile, f, 6, 2, rows)
      val printed = Seq(exe.toString, imageFile.toString, soFile.toString).!!.linesIterator.toSeq
      val want = listing(img, ExpectedSoFile.Contents(f, 6, 2, rows.sortBy(r => (r.query, r.photon)).toIndexedSeq))
      assert(printed.size == want.size)
      for ((got, w) <- printed.zip(want)) assert(got == w)
    }
}
