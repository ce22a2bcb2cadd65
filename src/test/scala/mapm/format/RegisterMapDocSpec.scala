package mapm.format

import java.nio.file.{Files, Paths}

import org.scalatest.funsuite.AnyFunSuite

/** docs/coprocessor.md holds the register table exactly as [[RegisterMap.markdown]] writes it
  * (between its markers), so the documentation cannot drift from the hardware's decoder.
  * `MAPM_WRITE_DOCS=1` rewrites the section instead. */
class RegisterMapDocSpec extends AnyFunSuite {
  private val doc = Paths.get("docs/coprocessor.md")
  private val begin = "<!-- register map: written by mapm.format.RegisterMap.markdown (RegisterMapDocSpec checks it) -->"
  private val end = "<!-- end of register map -->"

  test("docs/coprocessor.md's register table is RegisterMap.markdown") {
    assume(Files.isRegularFile(doc), s"$doc not found")
    val text = Files.readString(doc)
    val (a, b) = (text.indexOf(begin), text.indexOf(end))
    assert(a >= 0 && b > a, "the register map's markers are missing")
    val section = text.substring(a + begin.length, b).trim
    if (sys.env.get("MAPM_WRITE_DOCS").contains("1"))
      Files.writeString(doc, text.substring(0, a + begin.length) + "\n\n" + RegisterMap.markdown + "\n" + text.substring(b))
    else assert(section == RegisterMap.markdown.trim, "the table differs from RegisterMap.markdown: rerun with MAPM_WRITE_DOCS=1")
  }
}
