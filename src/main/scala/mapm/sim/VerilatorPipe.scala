package mapm.sim

import java.io.{BufferedReader, BufferedWriter, InputStreamReader, OutputStreamWriter}
import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}
import mapm.MapmError

/** Runs an emitted (CIRCT) SystemVerilog module cycle by cycle in Verilator, streaming port values.
  *
  * [[VerilatorPipe.build]] emits the module, writes a C++ harness specialised to its ports and
  * verilates both (cached by a hash of the Verilog in the [[BuildCache]], so a second build of the
  * same design, by any spec or command, is free).
  * [[run]] then feeds one row per clock cycle: the values of the pipe's [[inputs]], in that order.
  * For each row the harness applies the inputs, evaluates, records the [[outputs]] (in that order:
  * the values a test bench would peek in that cycle before the clock edge) and then clocks once.
  * Reset is held for `resetCycles` cycles before the first row.
  *
  * A pipe from [[VerilatorPipe.build]] has every port but `clock` and `reset` as inputs and
  * outputs, in declaration order, found by name with [[in]] and [[out]]. A pipe from
  * [[VerilatorPipe.of]] is typed instead: its inputs and outputs are the leaves of two chosen
  * fields of the module (say `io.in` and `io.out`) in field order, and every other input is held
  * at 0.
  *
  * The wire protocol is text: one line per cycle of space-separated hexadecimal values, which keeps
  * the harness generic and costs about a microsecond per port per cycle.
  */
final class VerilatorPipe private (val exe: Path, val top: String, harnessInputs: Seq[Emit.Port],
                                   harnessOutputs: Seq[Emit.Port], val inputs: Seq[Emit.Port],
                                   val outputs: Seq[Emit.Port]) {

  /** Index of an input port by name (e.g. `io_in_valid`). */
  def in(name: String): Int = indexOf(inputs, name)
  /** Index of an output port by name. */
  def out(name: String): Int = indexOf(outputs, name)

  private def indexOf(ports: Seq[Emit.Port], name: String): Int = {
    val i = ports.indexWhere(_.name == name)
    require(i >= 0, s"$top has no port '$name' (ports: ${ports.map(_.name).mkString(", ")})")
    i
  }

  /** For each harness input, its index in a row, or -1 for an input held at 0. */
  private val rowIndex: Array[Int] = harnessInputs.map(p => inputs.indexWhere(_.name == p.name)).toArray
  /** For each of [[outputs]], its index in the harness's output line. */
  private val lineIndex: Array[Int] = outputs.map(p => harnessOutputs.indexWhere(_.name == p.name)).toArray

  /** The same simulation with the named ports as its inputs and outputs (in harness order). */
  private[sim] def select(ins: Set[String], outs: Set[String]): VerilatorPipe =
    new VerilatorPipe(exe, top, harnessInputs, harnessOutputs, harnessInputs.filter(p => ins(p.name)),
      harnessOutputs.filter(p => outs(p.name)))

  /** Streams `rows` (one per cycle, values in [[inputs]] order) through the design and calls
    * `sink` with each cycle's output values (in [[outputs]] order). Returns the cycles run. */
  def run(rows: Iterator[Array[BigInt]], resetCycles: Int = 4)(sink: Array[BigInt] => Unit): Long = {
    val proc = new ProcessBuilder(exe.toString, resetCycles.toString).redirectErrorStream(false).start()
    val writerError = new java.util.concurrent.atomic.AtomicReference[Throwable](null)
    val writer = new Thread(() => {
      val w = new BufferedWriter(new OutputStreamWriter(proc.getOutputStream, StandardCharsets.US_ASCII), 1 << 16)
      try {
        val sb = new java.lang.StringBuilder
        rows.foreach { row =>
          require(row.length == inputs.length, s"row has ${row.length} values, $top has ${inputs.length} inputs")
          sb.setLength(0)
          var i = 0
          while (i < rowIndex.length) {
            if (i > 0) sb.append(' ')
            val k = rowIndex(i)
            sb.append(if (k < 0) "0" else row(k).toString(16))
            i += 1
          }
          sb.append('\n')
          w.write(sb.toString)
        }
      } catch { case t: Throwable => writerError.set(t) }
      finally w.close()
    }, s"verilator-pipe-$top")
    writer.setDaemon(true)
    writer.start()
    val r = new BufferedReader(new InputStreamReader(proc.getInputStream, StandardCharsets.US_ASCII), 1 << 16)
    var cycles = 0L
    var line = r.readLine()
    while (line != null) {
      val toks = line.split(' ')
      if (toks.length != harnessOutputs.length) MapmError.fail(s"$top harness printed '$line'")
      sink(lineIndex.map(k => BigInt(toks(k), 16)))
      cycles += 1
      line = r.readLine()
    }
    writer.join()
    val rc = proc.waitFor()
    Option(writerError.get).foreach(t => throw t)
    if (rc != 0) {
      val err = new String(proc.getErrorStream.readAllBytes(), StandardCharsets.UTF_8).trim
      MapmError.fail(s"$top simulation exited with $rc: $err")
    }
    cycles
  }

  /** [[run]] collecting every output row. */
  def runAll(rows: Seq[Array[BigInt]], resetCycles: Int = 4): IndexedSeq[Array[BigInt]] = {
    val out = IndexedSeq.newBuilder[Array[BigInt]]
    run(rows.iterator, resetCycles)(out += _)
    out.result()
  }
}

object VerilatorPipe {
  /** Emits `gen`, generates its harness and verilates it, cached by content: in the
    * [[BuildCache]] (kind `pipe`), or in the folder `cacheDir` when one is given.
    * Modules whose names start with one of `noInline` stay their own C++ classes instead of being
    * inlined: for a design of many copies of one unit this compiles the unit once (a bench of 64
    * CondChecks builds in seconds rather than minutes). */
  def build(gen: => chisel3.RawModule, cacheDir: Option[Path] = None, noInline: Seq[String] = Seq.empty): VerilatorPipe =
    fromVerilog(Emit.systemVerilog(gen), cacheDir, noInline)

  /** Builds the pipe for already-emitted SystemVerilog text (`noInline` as in [[build]]). */
  def fromVerilog(sv: String, cacheDir: Option[Path], noInline: Seq[String] = Seq.empty): VerilatorPipe = {
    val (top, ports) = Emit.topPorts(sv)
    val ins = ports.filter(p => p.isInput && p.name != "clock" && p.name != "reset")
    val outs = ports.filterNot(_.isInput)
    require(ports.exists(_.name == "clock"), s"$top has no clock port")
    val harness = harnessSource(top, ins, outs, hasReset = ports.exists(_.name == "reset"))
    val kept = """(?m)^module\s+(\w+)""".r.findAllMatchIn(sv).map(_.group(1)).filter(m => noInline.exists(m.startsWith)).toSeq.distinct
    val config = if (kept.isEmpty) "" else ("`verilator_config" +: kept.map(m => s"""no_inline -module "$m"""")).mkString("", "\n", "\n")
    def fill(d: Path): Unit = {
      val svFile = d.resolve(s"$top.sv")
      val cpp = d.resolve("harness.cpp")
      Files.write(svFile, sv.getBytes(StandardCharsets.UTF_8))
      Files.write(cpp, harness.getBytes(StandardCharsets.UTF_8))
      val vlt = if (config.isEmpty) Seq.empty else {
        val f = d.resolve("no-inline.vlt"); Files.write(f, config.getBytes(StandardCharsets.UTF_8)); Seq(f)
      }
      Verilator.build(vlt :+ svFile, cpp, top, d, "sim")
    }
    val built = (d: Path) => Files.isExecutable(d.resolve("sim"))
    val exe = cacheDir match {
      case None => BuildCache.entry("pipe", top, Seq(sv, harness, config, Verilator.optFlags.mkString(" ")), built)(fill).resolve("sim")
      case Some(c) =>
        val d = c.resolve(s"$top-${Verilator.hash(sv, harness, config, Verilator.optFlags.mkString(" "))}").toAbsolutePath
        if (!built(d)) { AtomicDir.delete(d); AtomicDir.create(d)(fill) }
        d.resolve("sim")
    }
    new VerilatorPipe(exe, top, ins, outs, ins, outs)
  }

  /** A typed pipe: emits `gen` and builds it as [[build]] does, then takes as rows the input
    * leaves of `in` and as output rows the output leaves of `out`, each in field order (the order
    * Chisel declares them: a Valid's `valid` before its `bits`, a Vec's elements by index), e.g.
    * `of(new FMul(fmt))(_.io.in, _.io.out)` has rows (valid, a, b) and outputs (valid, bits).
    * Inputs outside `in` are held at 0. */
  def of[M <: chisel3.RawModule](gen: => M, cacheDir: Option[Path] = None, noInline: Seq[String] = Seq.empty)(
      in: M => chisel3.Data, out: M => chisel3.Data): VerilatorPipe = {
    var dut: Option[M] = None
    val sv = Emit.systemVerilog { val m = gen; dut = Some(m); m }
    val all = fromVerilog(sv, cacheDir, noInline)
    val m = dut.get
    val named = chisel3.reflect.DataMirror.fullModulePorts(m)
    def names(d: chisel3.Data): Set[String] = {
      val ls = leaves(d)
      val found = named.collect { case (n, p) if ls.exists(_ eq p) => n }
      require(found.length == ls.length, s"${all.top}: ${ls.length - found.length} leaves of the chosen field are not ports")
      found.toSet
    }
    val pipe = all.select(names(in(m)), names(out(m)))
    require(pipe.inputs.nonEmpty && pipe.outputs.nonEmpty, s"${all.top}: the chosen fields have no inputs or no outputs")
    pipe
  }

  /** The ground-typed elements of `d` (`d` itself when it has no fields). */
  private def leaves(d: chisel3.Data): Seq[chisel3.Data] = d match {
    case r: chisel3.Record => r.elements.values.toSeq.flatMap(leaves)
    case v: chisel3.Vec[_] => v.flatMap(leaves)
    case e => Seq(e)
  }

  private def words(width: Int): Int = (width + 31) / 32

  /** C++ statement that sets input `p` from the hex token `tok`. */
  private def setInput(p: Emit.Port): String =
    if (p.width <= 64) s"top->${p.name} = parse_hex64(tok);"
    else s"parse_hex_words(tok, top->${p.name}.data(), ${words(p.width)});"

  /** C++ statement that prints output `p` as hex. */
  private def printOutput(p: Emit.Port): String =
    if (p.width <= 64) s"""print_hex64((uint64_t)top->${p.name});"""
    else s"print_hex_words(top->${p.name}.data(), ${words(p.width)});"

  private[sim] def harnessSource(top: String, ins: Seq[Emit.Port], outs: Seq[Emit.Port], hasReset: Boolean): String = {
    val sets = ins.map(p => s"    tok = next_token(&cur); if (!tok) bad_line(line); ${setInput(p)}").mkString("\n")
    val prints = outs.zipWithIndex.map { case (p, i) =>
      (if (i > 0) "    putchar_unlocked(' ');\n" else "") + s"    ${printOutput(p)}"
    }.mkString("\n")
    val reset = if (hasReset) "top->reset = 1;" else ""
    val unreset = if (hasReset) "top->reset = 0;" else ""
    s"""// Generated by mapm.sim.VerilatorPipe for $top: one line of hex input values per cycle on
       |// stdin, one line of hex output values per cycle on stdout.
       |#include "V$top.h"
       |#include "verilated.h"
       |#include <cstdio>
       |#include <cstdint>
       |#include <cstdlib>
       |#include <cstring>
       |
       |static void bad_line(const char* line) { fprintf(stderr, "bad input line: %s\\n", line); exit(3); }
       |static char* next_token(char** cur) {
       |  char* p = *cur; while (*p == ' ') p++;
       |  if (*p == 0 || *p == '\\n') return nullptr;
       |  char* s = p; while (*p && *p != ' ' && *p != '\\n') p++;
       |  if (*p) { *p = 0; p++; }
       |  *cur = p; return s;
       |}
       |static uint64_t parse_hex64(const char* s) { return strtoull(s, nullptr, 16); }
       |static void parse_hex_words(const char* s, uint32_t* w, int n) {
       |  for (int i = 0; i < n; i++) w[i] = 0;
       |  int len = strlen(s);
       |  for (int k = 0; k < len; k++) {
       |    char c = s[len - 1 - k]; int v = (c <= '9') ? c - '0' : (c | 32) - 'a' + 10;
       |    if (k / 8 < n) w[k / 8] |= (uint32_t)v << (4 * (k % 8));
       |  }
       |}
       |static void print_hex64(uint64_t v) { printf("%llx", (unsigned long long)v); }
       |static void print_hex_words(const uint32_t* w, int n) {
       |  int i = n - 1; while (i > 0 && w[i] == 0) i--;
       |  printf("%x", w[i]); for (i = i - 1; i >= 0; i--) printf("%08x", w[i]);
       |}
       |
       |int main(int argc, char** argv) {
       |  int reset_cycles = argc > 1 ? atoi(argv[1]) : 4;
       |  VerilatedContext* ctx = new VerilatedContext;
       |  V$top* top = new V$top{ctx};
       |  top->clock = 0; $reset
       |  for (int i = 0; i < reset_cycles; i++) { top->eval(); top->clock = 1; top->eval(); top->clock = 0; }
       |  $unreset
       |  top->eval();
       |  static char line[1 << 16];
       |  while (fgets(line, sizeof line, stdin)) {
       |    char* cur = line; char* tok;
       |$sets
       |    top->eval();
       |$prints
       |    putchar_unlocked('\\n');
       |    top->clock = 1; top->eval(); top->clock = 0;
       |  }
       |  top->final();
       |  fflush(stdout);
       |  delete top; delete ctx;
       |  return 0;
       |}
       |""".stripMargin
  }
}
