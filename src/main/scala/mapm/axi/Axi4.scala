package mapm.axi

import chisel3._
import chisel3.util._

/** Shape of an AXI4 master port (AMBA AXI4, ARM IHI 0022): address and data widths and the id
  * width. Bursts are INCR of whole data beats; a burst never crosses a 4 KiB boundary.
  *
  * @param addrBits  byte-address width
  * @param dataBytes bytes per data beat (AxSIZE = log2(dataBytes) on every burst)
  * @param idBits    AxID / xID width
  */
final case class Axi4Params(addrBits: Int = 32, dataBytes: Int = 16, idBits: Int = 6) {
  require(addrBits >= 12 && addrBits <= 64, s"AXI4 address width must be 12..64 bits, got $addrBits")
  require(dataBytes >= 4 && dataBytes <= 128 && isPow2(dataBytes), s"AXI4 data width must be a power of two of 4..128 bytes, got $dataBytes")
  require(idBits >= 1 && idBits <= 16, s"AXI4 id width must be 1..16 bits, got $idBits")
  def dataBits: Int = 8 * dataBytes
  /** AxSIZE of a full beat. */
  def sizeCode: Int = log2Ceil(dataBytes)
}

object Axi4 {
  /** AxBURST INCR. */
  val BurstIncr: UInt = 1.U(2.W)
  /** xRESP codes: OKAY, EXOKAY, SLVERR, DECERR. */
  val RespOkay: UInt = 0.U(2.W)
  /** Longest INCR burst, in beats (AxLEN + 1). */
  val MaxBeats: Int = 256
  /** No burst may cross this boundary. */
  val BoundaryBytes: Int = 4096
}

/** AW or AR: one burst of `len + 1` beats of 2^size bytes from `addr`. */
class Axi4Addr(p: Axi4Params) extends Bundle {
  val id = UInt(p.idBits.W)
  val addr = UInt(p.addrBits.W)
  val len = UInt(8.W)
  val size = UInt(3.W)
  val burst = UInt(2.W)
  val lock = Bool()
  val cache = UInt(4.W)
  val prot = UInt(3.W)
  val qos = UInt(4.W)
}

/** W: one beat of write data; bytes whose `strb` bit is low are not written. */
class Axi4W(p: Axi4Params) extends Bundle {
  val data = UInt(p.dataBits.W)
  val strb = UInt(p.dataBytes.W)
  val last = Bool()
}

/** B: the response to one write burst. */
class Axi4B(p: Axi4Params) extends Bundle {
  val id = UInt(p.idBits.W)
  val resp = UInt(2.W)
}

/** R: one beat of read data. */
class Axi4R(p: Axi4Params) extends Bundle {
  val id = UInt(p.idBits.W)
  val data = UInt(p.dataBits.W)
  val resp = UInt(2.W)
  val last = Bool()
}

/** The master's view of an AXI4 port: five channels, each a valid/ready handshake. */
class Axi4(val p: Axi4Params) extends Bundle {
  val aw = Decoupled(new Axi4Addr(p))
  val w = Decoupled(new Axi4W(p))
  val b = Flipped(Decoupled(new Axi4B(p)))
  val ar = Decoupled(new Axi4Addr(p))
  val r = Flipped(Decoupled(new Axi4R(p)))
}

/** AXI4-Lite AW or AR: one 32-bit register access at `addr`. */
class Axi4LiteAddr(addrBits: Int) extends Bundle {
  val addr = UInt(addrBits.W)
  val prot = UInt(3.W)
}

/** AXI4-Lite W: 32 bits of write data and their byte strobes. */
class Axi4LiteW extends Bundle {
  val data = UInt(32.W)
  val strb = UInt(4.W)
}

/** AXI4-Lite B. */
class Axi4LiteB extends Bundle {
  val resp = UInt(2.W)
}

/** AXI4-Lite R. */
class Axi4LiteR extends Bundle {
  val data = UInt(32.W)
  val resp = UInt(2.W)
}

/** AXI4-Lite, 32-bit data: the master's view of the register port (the slave's is `Flipped`). */
class Axi4Lite(val addrBits: Int) extends Bundle {
  val aw = Decoupled(new Axi4LiteAddr(addrBits))
  val w = Decoupled(new Axi4LiteW)
  val b = Flipped(Decoupled(new Axi4LiteB))
  val ar = Decoupled(new Axi4LiteAddr(addrBits))
  val r = Flipped(Decoupled(new Axi4LiteR))
}
