package mapm.sim

import java.nio.file.{Files, Path}

import scala.collection.immutable.{ListMap, SeqMap}

import mapm.MapmError

/** The `stats.json` the Verilator harness writes at the end of a run (tools/harness/main.cpp,
  * docs/harness.md), read once into typed fields.
  *
  * @param top                      the top module simulated
  * @param config                   the configuration block (TSM, SOM, ... by name); empty when the harness was built without one
  * @param result                   `PASS`, `FAIL`, or `STOPPED` (at `--max-cycles`, as asked: what came out was checked)
  * @param failure                  why it failed (None on a pass)
  * @param seed                     seed of the memory's response reordering
  * @param latency                  memory latency in cycles
  * @param latencyMax               largest drawn latency (equal to `latency` when fixed)
  * @param queryGap                 probability of a gap in the query stream per cycle
  * @param reqStall                 probability that the memory refuses a request per cycle
  * @param respGap                  probability that the memory holds back a response beat
  * @param bandwidthBytesPerCycle   memory bandwidth
  * @param clockGHz                 clock for the GB/s figure
  * @param cycles                   cycles simulated
  * @param queries                  queries fed in
  * @param queriesCompleted         queries whose shader operations all came out
  * @param soIssued                 shader operations out of the SOAs
  * @param soPassingCond            of them, those whose cond held
  * @param soPerCycle               `soIssued / cycles`
  * @param tsOps                    tree-search operations (None when the top has no `tsOps` counter)
  * @param tsOpsPerCycle            `tsOps / cycles` (None likewise)
  * @param stallCycles              the `stall*` counters by name
  * @param caches                   hits, misses and hit rate of each cache by name
  * @param memoryRequests           requests the memory served
  * @param bytesFetched             bytes the memory served
  * @param bytesPerCycle            `bytesFetched / cycles`
  * @param gbPerSecond              `bytesPerCycle` at `clockGHz`
  * @param counters                 every counter of the top by name
  * @param counterUnits             what each counter counts (`TSM-cycles` for the TSMs' stalls, summed over the TSMs); empty in the stats of older harnesses
  * @param wallSeconds              the harness's wall time
  * @param simulatedCyclesPerSecond `cycles / wallSeconds`
  * @param json                     the file as read, for writing it on with every key (`render`'s stats)
  */
final case class HarnessStats(
    top: String,
    config: SeqMap[String, Long],
    result: String,
    failure: Option[String],
    seed: Long,
    latency: Long,
    latencyMax: Long,
    queryGap: Double,
    reqStall: Double,
    respGap: Double,
    bandwidthBytesPerCycle: Double,
    clockGHz: Double,
    cycles: Long,
    queries: Long,
    queriesCompleted: Long,
    soIssued: Long,
    soPassingCond: Long,
    soPerCycle: Double,
    tsOps: Option[Long],
    tsOpsPerCycle: Option[Double],
    stallCycles: SeqMap[String, Long],
    caches: SeqMap[String, HarnessStats.Cache],
    memoryRequests: Long,
    bytesFetched: Long,
    bytesPerCycle: Double,
    gbPerSecond: Double,
    counters: SeqMap[String, Long],
    counterUnits: SeqMap[String, String],
    wallSeconds: Double,
    simulatedCyclesPerSecond: Double,
    json: ujson.Obj) {
  /** `full`, or `timing` when the SOAs were their timing model and the colours and
    * `soPassingCond` came from the model's expected SOs. */
  def fidelity: String = json.value.get("fidelity").flatMap(_.strOpt).getOrElse("full")

  /** The run ended at `--max-cycles` as asked, before the frame was done. */
  def stopped: Boolean = result == "STOPPED"
}

object HarnessStats {
  /** One cache's counts: `hitRate` is `hits / (hits + misses)`, 0 when it saw no access. */
  final case class Cache(hits: Long, misses: Long, hitRate: Double)

  /** Reads and checks `path`; a [[MapmError]] names the file and the first missing or mistyped key. */
  def read(path: Path): HarnessStats = {
    val text =
      try new String(Files.readAllBytes(path), "UTF-8")
      catch { case e: java.io.IOException => MapmError.fail(s"$path: cannot read the harness stats (${e.getMessage})") }
    parse(text, path.toString)
  }

  /** Parses the text of a stats.json; `source` names it in errors. */
  def parse(text: String, source: String): HarnessStats = {
    def bad(key: String, what: String): Nothing = MapmError.fail(s"$source: the harness stats' '$key' is not $what")
    val root =
      try ujson.read(text)
      catch { case e: Exception => MapmError.fail(s"$source: the harness stats are not JSON (${e.getMessage})") }
    val json = root match {
      case o: ujson.Obj => o
      case _            => MapmError.fail(s"$source: the harness stats are not a JSON object")
    }
    val top = json.value
    // `key` is the value's path from the top, dotted, for the messages
    def at(in: collection.Map[String, ujson.Value], key: String): ujson.Value =
      in.getOrElse(key.split('.').last, MapmError.fail(s"$source: the harness stats lack '$key'"))
    def num(v: ujson.Value, key: String): Double = v.numOpt.getOrElse(bad(key, "a number"))
    def whole(v: ujson.Value, key: String): Long = {
      val d = num(v, key)
      if (d != math.rint(d)) bad(key, s"a whole number: $d")
      d.toLong
    }
    def obj(v: ujson.Value, key: String): collection.Map[String, ujson.Value] = v.objOpt.getOrElse(bad(key, "an object"))
    def d(k: String): Double = num(at(top, k), k)
    def l(k: String): Long = whole(at(top, k), k)
    def nullable[T](k: String)(read: (ujson.Value, String) => T): Option[T] = at(top, k) match {
      case ujson.Null => None
      case v          => Some(read(v, k))
    }
    def wholes(k: String, block: ujson.Value): SeqMap[String, Long] =
      ListMap.from(obj(block, k).iterator.map { case (n, v) => n -> whole(v, s"$k.$n") })
    val caches = ListMap.from(obj(at(top, "caches"), "caches").iterator.map { case (n, v) =>
      val c = obj(v, s"caches.$n")
      n -> Cache(whole(at(c, s"caches.$n.hits"), s"caches.$n.hits"), whole(at(c, s"caches.$n.misses"), s"caches.$n.misses"),
        num(at(c, s"caches.$n.hitRate"), s"caches.$n.hitRate"))
    })
    HarnessStats(at(top, "top").strOpt.getOrElse(bad("top", "a string")), top.get("config").map(wholes("config", _)).getOrElse(ListMap.empty),
      at(top, "result").strOpt.getOrElse(bad("result", "a string")), nullable("failure")((v, k) => v.strOpt.getOrElse(bad(k, "a string"))),
      l("seed"), l("latency"), l("latencyMax"), d("queryGap"), d("reqStall"), d("respGap"), d("bandwidthBytesPerCycle"),
      d("clockGHz"), l("cycles"), l("queries"), l("queriesCompleted"), l("soIssued"), l("soPassingCond"), d("soPerCycle"),
      nullable("tsOps")(whole), nullable("tsOpsPerCycle")(num), wholes("stallCycles", at(top, "stallCycles")), caches,
      l("memoryRequests"), l("bytesFetched"), d("bytesPerCycle"), d("gbPerSecond"), wholes("counters", at(top, "counters")),
      top.get("counterUnits").map(u => ListMap.from(obj(u, "counterUnits").iterator.map { case (n, v) =>
        n -> v.strOpt.getOrElse(bad(s"counterUnits.$n", "a string")) })).getOrElse(ListMap.empty[String, String]),
      d("wallSeconds"), d("simulatedCyclesPerSecond"), json)
  }
}
