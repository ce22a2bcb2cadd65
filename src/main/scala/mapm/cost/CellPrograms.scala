package mapm.cost

import mapm.MapmError
import scala.collection.mutable

/** [[GateSim]]'s instruction set and the compiler of library cells into it: each output
  * `function` of a [[Liberty.Cell]] becomes a few two-input word operations over slots, a
  * flip-flop's next state and inverted state likewise (clear and preset applied at the clock edge,
  * see [[GateSim]]). */
private[cost] object CellPrograms {
  // instruction op codes
  final val OpBuf = 0
  final val OpNot = 1
  final val OpAnd = 2
  final val OpOr = 3
  final val OpXor = 4
  final val OpNand = 5
  final val OpNor = 6
  final val OpXnor = 7
  final val OpAndN = 8
  final val OpOrN = 9

  // the four state slots of a flip-flop
  final val State = 0
  final val StateInverted = 1
  final val NextState = 2
  final val NextInverted = 3

  /** An operand or destination of an instruction, before it is placed in the slots. */
  sealed trait Ref

  /** The net on a cell pin. */
  final case class PinRef(pin: String) extends Ref

  /** Scratch slot `k` (shared by all cells: a cell's temporaries live only while it runs). */
  final case class TempRef(k: Int) extends Ref

  /** A constant net. */
  final case class ConstRef(value: Boolean) extends Ref

  /** State slot `k` of the flip-flop. */
  final case class StateRef(k: Int) extends Ref

  /** `dst = op(a, b)`; unary ops ignore `b`. */
  final case class Instr(op: Int, dst: Ref, a: Ref, b: Ref)

  /** A library cell compiled: per output pin its instructions; for a flip-flop its clock pin and
    * whether it loads on the rising edge, and the instructions of its next state; the number of
    * scratch slots they use.
    */
  final case class CellProgram(outputs: Seq[(String, Seq[Instr])], edge: Option[(String, Boolean)], next: Seq[Instr], temps: Int)

  /** Compiles [[BoolExpr]]s to two-input instructions, fusing a complement into the operation
    * where one fits (NAND, NOR, XNOR, AND-NOT, OR-NOT). `leaf` places a variable.
    */
  final class ExprCompiler(leaf: String => Ref) {
    /** The scratch slots used so far by this cell's programs. */
    var temps = 0
    private val code = mutable.ArrayBuffer.empty[Instr]

    /** The instructions that leave `e` in `dst`. */
    def program(e: BoolExpr, dst: Ref): Seq[Instr] = {
      code.clear()
      into(e, dst)
      code.toList
    }

    private def into(e: BoolExpr, dst: Ref): Unit = {
      import BoolExpr._
      def two(op: Int, x: BoolExpr, y: BoolExpr): Unit = { val a = operand(x); val b = operand(y); code += Instr(op, dst, a, b) }
      e match {
        case Var(_) | Const(_)    => val a = operand(e); code += Instr(OpBuf, dst, a, a)
        case Not(Not(x))          => into(x, dst)
        case Not(And(x, y))       => two(OpNand, x, y)
        case Not(Or(x, y))        => two(OpNor, x, y)
        case Not(Xor(x, y))       => two(OpXnor, x, y)
        case Not(x)               => val a = operand(x); code += Instr(OpNot, dst, a, a)
        case And(x, Not(y))       => two(OpAndN, x, y)
        case And(Not(x), y)       => two(OpAndN, y, x)
        case And(x, y)            => two(OpAnd, x, y)
        case Or(x, Not(y))        => two(OpOrN, x, y)
        case Or(Not(x), y)        => two(OpOrN, y, x)
        case Or(x, y)             => two(OpOr, x, y)
        case Xor(x, Not(y))       => two(OpXnor, x, y)
        case Xor(Not(x), y)       => two(OpXnor, x, y)
        case Xor(x, y)            => two(OpXor, x, y)
      }
    }

    /** Where the value of `e` is: a variable or constant in place, else a new scratch slot. */
    private def operand(e: BoolExpr): Ref = e match {
      case BoolExpr.Var(name) => leaf(name)
      case BoolExpr.Const(v)  => ConstRef(v)
      case _ =>
        val t = TempRef(temps)
        temps += 1
        into(e, t)
        t
    }
  }

  /** The programs of library cell `cell` (state variables as [[StateRef]]s); `top` names the
    * design in the message that refuses a cell it cannot simulate. */
  def compile(cell: Liberty.Cell, top: String): CellProgram = {
    def refuse(what: String): Nothing = MapmError.fail(s"gate simulation of $top: unsupported cell ${cell.name} ($what)")
    if (cell.latch.isDefined) refuse("latch")
    cell.pins.find(_.threeState.isDefined).foreach(p => refuse(s"tristate output ${p.name}"))
    cell.pins.find(_.direction == Liberty.Direction.Inout).foreach(p => refuse(s"inout pin ${p.name}"))
    val inputs = cell.inputs.map(_.name).toSet
    val stateVars = cell.ff.fold(Map.empty[String, Int])(ff => Map(ff.state -> State, ff.stateInverted -> StateInverted))
    val compiler = new ExprCompiler(name =>
      if (inputs(name)) PinRef(name)
      else stateVars.get(name).fold[Ref](MapmError.fail(s"gate simulation: function of cell ${cell.name} reads '$name', not an input pin"))(StateRef))
    val outputs = cell.outputs.map { pin =>
      val f = pin.function.getOrElse(refuse(s"output ${pin.name} has no function"))
      pin.name -> compiler.program(f, PinRef(pin.name))
    }
    val edge = cell.ff.map { ff =>
      ff.clockedOn match {
        case BoolExpr.Var(p) if inputs(p)                  => p -> true
        case BoolExpr.Not(BoolExpr.Var(p)) if inputs(p)    => p -> false
        case _ => refuse("clocked_on is not a clock pin or its complement")
      }
    }
    val next = cell.ff.map { ff =>
      val state = nextState(ff, cell.name)
      val readsInverted = cell.outputs.exists(_.function.exists(_.vars(ff.stateInverted)))
      compiler.program(state, StateRef(NextState)) ++
        (if (readsInverted) compiler.program(nextInverted(ff, state, cell.name), StateRef(NextInverted)) else Seq.empty)
    }
    CellProgram(outputs, edge, next.getOrElse(Seq.empty), compiler.temps)
  }

  /** The value of a `clear_preset_var` (for `var1` of the state, `var2` of the inverted one). */
  private def clearPresetValue(v: String, own: String, cellName: String): BoolExpr = v match {
    case "L" | "X" => BoolExpr.Const(false)
    case "H"       => BoolExpr.Const(true)
    case "N"       => BoolExpr.Var(own)
    case "T"       => BoolExpr.Not(BoolExpr.Var(own))
    case other     => MapmError.fail(s"gate simulation: cell $cellName has clear_preset_var '$other'")
  }

  /** The state after an active edge (see the class comment). */
  private def nextState(ff: Liberty.Ff, cellName: String): BoolExpr = {
    import BoolExpr._
    (ff.clear, ff.preset) match {
      case (None, None)       => ff.nextState
      case (Some(c), None)    => And(Not(c), ff.nextState)
      case (None, Some(p))    => Or(p, ff.nextState)
      case (Some(c), Some(p)) =>
        val both = clearPresetValue(ff.clearPresetVar1.getOrElse("L"), ff.state, cellName)
        Or(Or(And(And(c, p), both), And(Not(c), p)), And(And(Not(c), Not(p)), ff.nextState))
    }
  }

  /** The inverted state after an active edge: the complement, unless clear and preset both hold
    * and `clear_preset_var2` says otherwise.
    */
  private def nextInverted(ff: Liberty.Ff, state: BoolExpr, cellName: String): BoolExpr = {
    import BoolExpr._
    (ff.clear, ff.preset, ff.clearPresetVar2) match {
      case (Some(c), Some(p), Some(v2)) =>
        val both = And(c, p)
        Or(And(both, clearPresetValue(v2, ff.stateInverted, cellName)), And(Not(both), Not(state)))
      case _ => Not(state)
    }
  }
}
