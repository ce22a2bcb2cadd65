package mapm.memory

import chisel3._
import chisel3.util._

/** Shape of one read-only memory port (docs/memory-port.md describes the protocol).
  *
  * @param addressBits byte-address width
  * @param dataBytes   bytes per response beat
  * @param idBits      request-id width; at most one request per id is outstanding at a time
  * @param maxBeats    most beats one request may ask for (1 = single-beat port)
  */
final case class MemPortParams(addressBits: Int, dataBytes: Int, idBits: Int, maxBeats: Int = 1) {
  require(addressBits >= 8 && addressBits <= 64, s"memory port address width must be 8..64 bits, got $addressBits")
  require(isPow2(dataBytes), s"memory port data width must be a power of two of bytes, got $dataBytes")
  require(idBits >= 1 && idBits <= 16, s"memory port id width must be 1..16 bits, got $idBits")
  require(isPow2(maxBeats), s"memory port beats per request must be a power of two, got $maxBeats")

  /** Width of the `len` field: beats minus one. */
  def lenBits: Int = log2Ceil(maxBeats) max 1
  def dataBits: Int = dataBytes * 8
  /** Bytes of the longest request. */
  def maxBytes: Int = dataBytes * maxBeats
  /** The same port with `extra` more id bits on top (what an arbiter of 2^extra ports emits). */
  def widenId(extra: Int): MemPortParams = copy(idBits = idBits + extra)
}

/** A read request: `len + 1` beats of `dataBytes` each from the consecutive bytes starting at `addr`. */
class MemReq(val p: MemPortParams) extends Bundle {
  /** Byte address of the first byte; aligned to the whole request (`(len + 1) * dataBytes`). */
  val addr = UInt(p.addressBits.W)
  /** Request id, echoed on every response beat. */
  val id = UInt(p.idBits.W)
  /** Number of beats minus one (AXI ARLEN convention); always 0 on a single-beat port. */
  val len = UInt(p.lenBits.W)
}

/** One response beat: the bytes of beat `k` of request `id` (beats of one request arrive in order). */
class MemResp(val p: MemPortParams) extends Bundle {
  /** Little-endian: byte `addr + k * dataBytes + j` is bits `[8j+7 : 8j]`. */
  val data = UInt(p.dataBits.W)
  /** Id of the request this beat answers. */
  val id = UInt(p.idBits.W)
  /** True on the final beat of the request. */
  val last = Bool()
}

/** The requester's view of a read-only memory port: requests out, response beats in.
  * The responder's view is `Flipped(new MemPort(p))`. */
class MemPort(val p: MemPortParams) extends Bundle {
  val req = Decoupled(new MemReq(p))
  val resp = Flipped(Decoupled(new MemResp(p)))
}
