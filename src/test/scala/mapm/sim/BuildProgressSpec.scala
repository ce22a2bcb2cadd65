package mapm.sim

import java.nio.file.Files

import org.scalatest.funsuite.AnyFunSuite

/** [[BuildProgress]]: the C++ file count read from Verilator's Makefiles, and the status lines a
  * build not on a terminal gets (verilating, then files compiled out of the total, then linking). */
class BuildProgressSpec extends AnyFunSuite {
  private def makefiles(): java.nio.file.Path = {
    val obj = Files.createTempDirectory("build-progress")
    Files.write(obj.resolve("Vtop_classes.mk"),
      """# comment
        |VM_CLASSES_FAST += \
        |	Vtop \
        |	Vtop___024root__DepSet_h1__0 \
        |
        |VM_CLASSES_SLOW += \
        |	Vtop__ConstPool_0 \
        |
        |VM_SUPPORT_FAST += \
        |
        |VM_SUPPORT_SLOW += \
        |	Vtop__Syms \
        |
        |VM_GLOBAL_FAST += \
        |	verilated \
        |	verilated_threads \
        |
        |VM_GLOBAL_SLOW += \
        |""".stripMargin.getBytes("UTF-8"))
    Files.write(obj.resolve("Vtop.mk"),
      """VM_USER_CFLAGS = \
        |	-std=c++17 \
        |
        |VM_USER_CLASSES = \
        |	main \
        |
        |VM_USER_DIR = \
        |	/somewhere \
        |""".stripMargin.getBytes("UTF-8"))
    obj
  }

  test("the C++ files are the entries of the class, support, global and user lists (the classes as one file without parallel builds)") {
    val obj = makefiles()
    assert(BuildProgress.units(obj, "top") == 7)
    // Without parallel builds the generated classes compile as one __ALL file.
    val mk = obj.resolve("Vtop_classes.mk")
    Files.write(mk, ("VM_PARALLEL_BUILDS = 0\n" + new String(Files.readAllBytes(mk), "UTF-8")).getBytes("UTF-8"))
    assert(BuildProgress.units(obj, "top") == 4)
    assert(BuildProgress.units(Files.createTempDirectory("empty"), "top") == 0)
  }

  test("a build not on a terminal gets a status line at each tick: verilating, files compiled of the total, linking") {
    val obj = makefiles()
    val lines = new java.util.concurrent.LinkedBlockingQueue[String]()
    val p = new BuildProgress("Vtop", obj, "top", lines.put(_), everyMillis = 40)
    def next(): String = Option(lines.poll(5, java.util.concurrent.TimeUnit.SECONDS)).getOrElse(fail("no status line"))
    try {
      assert(next().startsWith("Vtop: verilating ("))
      p.line("g++ -Os -c -o Vtop.o Vtop.cpp")
      p.line("make: something else")
      lines.clear()
      assert(next().startsWith("Vtop: compiled 1 of 7 C++ files ("))
      (2 to 7).foreach(i => p.line(s"ccache g++ -c -o f$i.o f$i.cpp"))
      lines.clear()
      assert(next().startsWith("Vtop: linking ("))
    } finally p.close()
    lines.clear()
    Thread.sleep(150)
    assert(lines.isEmpty, "no line after the build ends")
  }
}
