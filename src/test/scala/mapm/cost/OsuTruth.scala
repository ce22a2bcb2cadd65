package mapm.cost

/** Hand-written truth functions of the OSU 0.18 um combinational cells (from the cell names and
  * data sheet meaning, not from the Liberty file), for checking the parser and the simulator.
  */
object OsuTruth {
  /** Pin values by name. */
  type Env = String => Boolean

  private def family(names: Seq[String], pin: String, f: Env => Boolean): Seq[((String, String), Env => Boolean)] =
    names.map(n => (n, pin) -> f)

  /** The function of each (cell, output pin). */
  val functions: Map[(String, String), Env => Boolean] = (
    family(Seq("INVX1", "INVX2", "INVX4", "INVX8"), "Y", e => !e("A")) ++
      family(Seq("BUFX2", "BUFX4", "CLKBUF1", "CLKBUF2", "CLKBUF3"), "Y", e => e("A")) ++
      family(Seq("AND2X1", "AND2X2"), "Y", e => e("A") && e("B")) ++
      family(Seq("OR2X1", "OR2X2"), "Y", e => e("A") || e("B")) ++
      Seq(
        ("NAND2X1", "Y") -> ((e: Env) => !(e("A") && e("B"))),
        ("NAND3X1", "Y") -> ((e: Env) => !(e("A") && e("B") && e("C"))),
        ("NOR2X1", "Y") -> ((e: Env) => !(e("A") || e("B"))),
        ("NOR3X1", "Y") -> ((e: Env) => !(e("A") || e("B") || e("C"))),
        ("AOI21X1", "Y") -> ((e: Env) => !((e("A") && e("B")) || e("C"))),
        ("AOI22X1", "Y") -> ((e: Env) => !((e("A") && e("B")) || (e("C") && e("D")))),
        ("OAI21X1", "Y") -> ((e: Env) => !((e("A") || e("B")) && e("C"))),
        ("OAI22X1", "Y") -> ((e: Env) => !((e("A") || e("B")) && (e("C") || e("D")))),
        ("XOR2X1", "Y") -> ((e: Env) => e("A") != e("B")),
        ("XNOR2X1", "Y") -> ((e: Env) => e("A") == e("B")),
        ("MUX2X1", "Y") -> ((e: Env) => !(if (e("S")) e("A") else e("B"))), // an inverting mux
        ("FAX1", "YC") -> ((e: Env) => Seq("A", "B", "C").count(e) >= 2),
        ("FAX1", "YS") -> ((e: Env) => Seq("A", "B", "C").count(e) % 2 == 1),
        ("HAX1", "YC") -> ((e: Env) => e("A") && e("B")),
        ("HAX1", "YS") -> ((e: Env) => e("A") != e("B")))).toMap

  /** The input pins of each combinational cell. */
  val inputs: Map[String, Seq[String]] = functions.keys.map(_._1).map { c =>
    c -> (c match {
      case _ if c.startsWith("INV") || c.startsWith("BUF") || c.startsWith("CLKBUF") => Seq("A")
      case "AOI22X1" | "OAI22X1" => Seq("A", "B", "C", "D")
      case "MUX2X1" => Seq("A", "B", "S")
      case "NAND3X1" | "NOR3X1" | "AOI21X1" | "OAI21X1" | "FAX1" => Seq("A", "B", "C")
      case _ => Seq("A", "B")
    })
  }.toMap

  /** The output pins of each combinational cell. */
  def outputs(cell: String): Seq[String] = if (cell == "FAX1" || cell == "HAX1") Seq("YC", "YS") else Seq("Y")
}
