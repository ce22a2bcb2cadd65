package mapm.format

import java.nio.file.{Files, Path, Paths}

import mapm.model._
import org.scalatest.funsuite.AnyFunSuite
import scala.sys.process._

/** The generated `mapm_formats.h` ([[CHeader.formats]]) compiled with g++ into a small reader that
  * prints every field of a Scala-written memory image (4-byte and packed slots) and expected-SO
  * file; its output must equal the same listing made from the Scala objects: an independent
  * check that the C++ getters and the Scala writers agree. Cancels without g++. */
class CHeaderSpec extends AnyFunSuite {
  private val dir = Paths.get("target/format-test")

  private lazy val gppPresent: Boolean =
    sys.env.getOrElse("PATH", "").split(java.io.File.pathSeparator).exists(d => Files.isExecutable(Paths.get(d, "g++")))

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
      |  printf("image %d %u %u %u %u %u\n", image_magic(h) == IMAGE_MAGIC, image_version(h), image_exp_width(h), image_man_width(h), image_packed(h), s);
      |  printf("counts %u %u %u %u\n", image_nodes(h), image_queries(h), image_stream_entries(h), image_h(h));
      |  printf("bases %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64 "\n", image_photon_base(h), image_query_base(h), image_stream_base(h), image_total_bytes(h));
      |  for (uint32_t i = 0; i < image_nodes(h); i++) {
      |    const uint8_t* n = h + IMAGE_BYTES + NODE_BYTES * i;
      |    const uint8_t* p = h + image_photon_base(h) + photon_bytes(s) * i;
      |    printf("node %u %u %u photon %u %u %u %u %u %u %u %u\n", i, node_split(n), node_word(n), photon_x(p, s), photon_y(p, s), photon_z(p, s),
      |           photon_power_r(p, s), photon_power_g(p, s), photon_power_b(p, s), photon_kernel(p, s), photon_brdf(p, s));
      |  }
      |  for (uint32_t q = 0; q < image_queries(h); q++) {
      |    const uint8_t* r = h + image_query_base(h) + query_bytes(s) * q;
      |    printf("query %u %u %u %u %u %u %u %u\n", q, query_contrib_r(r, s), query_contrib_g(r, s), query_contrib_b(r, s), query_x(r, s),
      |           query_y(r, s), query_z(r, s), query_pixel(r, s));
      |  }
      |  for (uint32_t k = 0; k < image_stream_entries(h); k++) {
      |    const uint8_t* e = h + image_stream_base(h) + stream_bytes(s) * k;
      |    printf("stream %u %u %u %u %u\n", k, stream_x(e, s), stream_y(e, s), stream_z(e, s), stream_query(e, s));
      |  }
      |  const std::vector<uint8_t> exp = load(argv[2]);
      |  const uint8_t* x = exp.data();
      |  printf("expected %d %u %u %u %" PRIu64 " %u %u\n", expected_magic(x) == EXPECTED_MAGIC, expected_version(x), expected_exp_width(x),
      |         expected_man_width(x), expected_count(x), expected_width(x), expected_height(x));
      |  for (uint64_t i = 0; i < expected_count(x); i++) {
      |    const uint8_t* r = x + EXPECTED_BYTES + SO_BYTES * i;
      |    const unsigned fl = so_flags(r), m = (1u << SO_FLAG_BITS) - 1;
      |    printf("so %u %u %u %u %u %u %u %u %u\n", so_query(r), so_photon(r), so_colour_r(r), so_colour_g(r), so_colour_b(r),
      |           fl & m, (fl >> SO_FLAG_BITS) & m, (fl >> (2 * SO_FLAG_BITS)) & m, (unsigned)((fl >> SO_COND_BIT) & 1));
      |  }
      |  return 0;
      |}
      |""".stripMargin

  private lazy val exe: Path = {
    Files.createDirectories(dir)
    Files.write(dir.resolve("mapm_formats.h"), CHeader.formats.getBytes("UTF-8"))
    Files.write(dir.resolve("reader.cpp"), reader.getBytes("UTF-8"))
    val out = dir.resolve("reader")
    val log = new StringBuilder
    val rc = Seq("g++", "-std=c++17", "-Wall", "-Werror", "-I", dir.toString, "-o", out.toString, dir.resolve("reader.cpp").toString)
      .!(ProcessLogger(l => log.append(l).append('\n')))
    assert(rc == 0, s"g++ failed on the generated header:\n$log")
    out
  }

  /** What the reader must print for `img` and the expected-SO `so` file contents. */
  private def listing(img: MemoryImage, so: ExpectedSoFile.Contents): Seq[String] = {
    val f = img.format
    Seq(s"image 1 1 ${f.expWidth} ${f.manWidth} ${if (img.packed) 1 else 0} ${img.slot}",
      s"counts ${img.nodeCount} ${img.queryCount} ${img.stream.length} ${img.h}",
      s"bases ${img.photonBase} ${img.queryBase} ${img.streamBase} ${img.totalBytes}") ++
      (0 until img.nodeCount).map(i => s"node $i ${img.nodeSplit(i)} ${img.nodeWord(i).toLong & 0xffffffffL} photon ${img.photon.map(_(i)).mkString(" ")}") ++
      (0 until img.queryCount).map(q => s"query $q ${img.contribution.map(_(q)).mkString(" ")} ${img.position.map(_(q)).mkString(" ")} ${img.pixel(q)}") ++
      img.stream.zipWithIndex.map { case (q, k) => s"stream $k ${img.position.map(_(q)).mkString(" ")} $q" } ++
      (s"expected 1 1 ${so.format.expWidth} ${so.format.manWidth} ${so.rows.size} ${so.width} ${so.height}" +:
        so.rows.map(r => s"so ${r.query} ${r.photon} ${r.colour.mkString(" ")} ${r.flags.mkString(" ")} ${if (r.cond) 1 else 0}"))
  }

  for ((f, packed) <- Seq((FloatFormat.fp32, false), (FloatFormat.fp16, true)))
    test(s"g++ reads a Scala-written ${f.name}${if (packed) " packed" else ""} image and expected-SO file through mapm_formats.h") {
      assume(gppPresent, "g++ is not on PATH: this test compiles the generated header with it")
      val rnd = new scala.util.Random(f.width)
      def pt() = Vec3(rnd.nextDouble() * 50, rnd.nextDouble() * 40, rnd.nextDouble() * 60)
      val photons = Array.fill(40)(Photon(pt(), Vec3(rnd.nextDouble(), rnd.nextDouble(), rnd.nextDouble()), Vec3(0, -1, 0), Vec3(0, 1, 0)))
      val queries = Array.fill(12)(QueryPoint(pt(), rnd.nextInt(1000), Vec3(rnd.nextDouble(), rnd.nextDouble(), rnd.nextDouble()), Vec3(0, 1, 0)))
      val map = PhotonMap.build(photons, Box(Vec3.zero, Vec3(50, 40, 60)), f, 3.0)
      val img = MemoryImage.from(map, QuerySet.build(queries, f), packed, Some(rnd.shuffle((0 until 12).toList).toArray))
      val rows = Seq.tabulate(30)(i => ExpectedSoFile.Row(rnd.nextInt(12), i, Seq.fill(3)(rnd.nextLong() & f.mask), Seq.fill(3)(rnd.nextInt(8)), rnd.nextBoolean()))
      Files.createDirectories(dir)
      val (imageFile, soFile) = (dir.resolve(s"${f.name}.img"), dir.resolve(s"${f.name}.so"))
      img.write(imageFile)
      ExpectedSoFile.write(soFile, f, 6, 2, rows)
      val printed = Seq(exe.toString, imageFile.toString, soFile.toString).!!.linesIterator.toSeq
      val want = listing(img, ExpectedSoFile.Contents(f, 6, 2, rows.sortBy(r => (r.query, r.photon)).toIndexedSeq))
      assert(printed.size == want.size)
      for ((got, w) <- printed.zip(want)) assert(got == w)
    }
}
