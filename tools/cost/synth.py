#!/usr/bin/env python3
"""Synthesizes one design to the cells of a Liberty library with yosys (PyPI pyosys), for
`tools/mapm cost` (docs/cost.md). Written in the shape of OpenROAD-flow-scripts' synthesis script.

Usage: synth.py --verilog F.sv [F2.sv ...] --top T --lib L.lib --delay-ps D --abc plain,buffer
                --out DIR [--flatten | --keep M ...] [--blackbox M ...]

Generic synthesis runs once; then the process forks, one child per ABC script, each mapping its own
copy of the design (in parallel); a single script maps in the process itself (no second copy). Each child writes DIR/<script>/netlist.v (for OpenSTA),
netlist.json (for the gate-level simulator) and stat.txt (yosys `stat -liberty`).
--flatten maps one flat module; --keep keeps the named modules (and the top) as modules and
flattens everything else into them after generic synthesis, so that ABC maps, buffers and sizes
each kept module as a whole; without either the whole hierarchy is kept.
  plain   yosys' own delay-driven ABC mapping (`abc -D`)
  buffer  ABC maps for delay, then buffers wide fan-outs and sizes gates (buffer, upsize, dnsize)
Progress goes to stderr. On failure: one line 'mapm: ...' on stderr and exit code 1.
"""
import argparse, os, re, sys, time

def die(msg):
    print(f"mapm: {msg}", file=sys.stderr, flush=True)
    os._exit(1)

def log(msg):
    print(f"  synth: {msg}", file=sys.stderr, flush=True)

try:
    from pyosys import libyosys as ys
except Exception as e:  # pragma: no cover
    die(f"pyosys (yosys) does not import: {e}")

# ABC's buffering script: logic synthesis with delay-driven balancing (&syn2, SOP balancing with
# &if -g, choices with &synch2), mapping for delay (&nf), then buffering of wide fan-outs, primary
# inputs included (flip-flop outputs are primary inputs to ABC), and gate sizing. Measured against
# the earlier `strash; dch -f; &nf` start (docs/cost.md): it turns carry and AND chains into trees.
ABC_BUFFER = "+strash;&get,-n;&st;&syn2;&if,-g,-K,6;&synch2;&nf,{D};&put;buffer,-p;upsize,{D};dnsize,{D};stime,-p"

def lib_cells(lib_path):
    """The smallest buffer, inverter, tie-high and tie-low cells of the library, found by their functions."""
    text = open(lib_path).read()
    starts = [m for m in re.finditer(r'\bcell\s*\(\s*"?(\w+)"?\s*\)', text)]
    cells = {}
    for i, m in enumerate(starts):
        end = starts[i + 1].start() if i + 1 < len(starts) else len(text)
        cells[m.group(1)] = text[m.end():end]
    def area(n):
        a = re.search(r'\barea\s*:\s*([0-9.eE+-]+)', cells[n])
        return float(a.group(1)) if a else 1e30
    def with_fn(pat):
        return sorted([n for n, b in cells.items()
                       if re.search(r'function\s*:\s*"\s*' + pat + r'\s*"', b) and not re.search(r'\b(ff|latch)\s*\(', b)],
                      key=area)
    bufs, invs = with_fn(r'\(?\s*A\s*\)?'), with_fn(r"\(?\s*(!\s*A|A\s*')\s*\)?")
    his, los = with_fn('1'), with_fn('0')
    first = lambda cells: cells[0] if cells else None
    return (first(bufs), first(invs), first(his), first(los))

def generic(args):
    d = ys.Design()
    ys.run_pass(f"read_liberty -lib {args.lib}", d)  # the cells as black boxes with pin directions
    for f in args.verilog:
        ys.run_pass(f"read_verilog -sv -defer {f}", d)
    ys.run_pass(f"hierarchy -check -top {args.top}", d)
    for bb in args.blackbox:
        ys.run_pass(f"blackbox {bb}", d)
    ys.run_pass("synth -top %s%s" % (args.top, " -flatten" if args.flatten else ""), d)
    if args.keep:
        for m in [args.top] + args.keep:
            ys.run_pass(f"setattr -mod -set keep_hierarchy 1 {m}", d)
        ys.run_pass("flatten", d)
        ys.run_pass("opt_clean -purge", d)
    return d

def mapped(d, args, script, out_dir):
    t0 = time.time()
    buf, inv, hi, lo = lib_cells(args.lib)
    ys.run_pass(f"dfflibmap -liberty {args.lib}", d)
    ys.run_pass("opt_clean", d)
    # ABC's view of the inputs it maps from: each driven by the library's smallest inverter (a
    # flip-flop's output stage is about as strong), each output loading 0.01 pF (a few flip-flop
    # D pins). Without a driving cell ABC takes inputs as ideal and leaves a flip-flop that drives
    # a whole operand row unbuffered (measured: 12 ns clock-to-Q on a pipeline's valid bit).
    constr = os.path.join(out_dir, "abc.constr")
    os.makedirs(out_dir, exist_ok=True)
    with open(constr, "w") as f:
        f.write((f"set_driving_cell {inv}\n" if inv else "") + "set_load 0.01\n")
    if script == "plain":
        ys.run_pass(f"abc -D {args.delay_ps} -constr {constr} -liberty {args.lib}", d)
    else:
        abc = ABC_BUFFER.replace("{D}", f"-D,{args.delay_ps}")
        ys.run_pass(f"abc -D {args.delay_ps} -constr {constr} -liberty {args.lib} -script {abc}", d)
    ys.run_pass("opt_clean", d)
    ys.run_pass("setundef -zero", d)
    ys.run_pass("splitnets", d)        # no `assign {a, b} = ...` for OpenSTA
    ys.run_pass("opt_clean -purge", d)
    if hi and lo:
        ys.run_pass(f"hilomap -hicell {hi} Y -locell {lo} Y", d)
    if buf:
        ys.run_pass(f"insbuf -buf {buf} A Y", d)
    ys.run_pass("rename -enumerate", d)  # plain instance names (_123_) for OpenSTA's get_pins
    ys.run_pass("check -assert" if not args.blackbox else "check", d)
    os.makedirs(out_dir, exist_ok=True)
    ys.run_pass(f"write_verilog -noattr -noexpr -nohex -nodec {os.path.join(out_dir, 'netlist.v')}", d)
    ys.run_pass(f"write_json {os.path.join(out_dir, 'netlist.json')}", d)
    if args.blackbox:  # their port declarations, for OpenSTA to link the instances
        ys.run_pass(f"write_verilog -noattr -blackboxes {os.path.join(out_dir, 'blackboxes.v')}", d)
    ys.run_pass(f"tee -q -o {os.path.join(out_dir, 'stat.txt')} stat -liberty {args.lib}", d)
    log(f"{script} ABC script: mapped in {time.time() - t0:.1f} s")

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--verilog", nargs="+", required=True)
    ap.add_argument("--top", required=True)
    ap.add_argument("--lib", required=True)
    ap.add_argument("--delay-ps", type=int, required=True)
    ap.add_argument("--abc", default="plain,buffer")
    ap.add_argument("--out", required=True)
    ap.add_argument("--flatten", action="store_true")
    ap.add_argument("--blackbox", nargs="*", default=[])
    ap.add_argument("--keep", nargs="*", default=[])
    args = ap.parse_args()
    scripts = [s for s in args.abc.split(",") if s]
    for s in scripts:
        if s not in ("plain", "buffer"):
            die(f"unknown ABC script '{s}' (plain, buffer)")
    for f in args.verilog + [args.lib]:
        if not os.path.isfile(f):
            die(f"synthesis input {f} not found")
    t0 = time.time()
    log(f"generic synthesis of {args.top} ...")
    try:
        d = generic(args)
    except Exception as e:
        die(f"yosys failed on {args.top}: {e}")
    log(f"generic synthesis done in {time.time() - t0:.1f} s; mapping with {', '.join(scripts)} ...")
    if len(scripts) == 1:
        # One script maps in this process: a forked child would copy, page by page, the design it
        # rewrites while this process still held the original (twice the memory of a large design).
        try:
            mapped(d, args, scripts[0], os.path.join(args.out, scripts[0]))
        except Exception as e:
            die(f"yosys failed to map {args.top} with the {scripts[0]} ABC script: {e}")
        log(f"done in {time.time() - t0:.1f} s")
        return
    children = []
    for s in scripts:
        pid = os.fork()
        if pid == 0:
            try:
                mapped(d, args, s, os.path.join(args.out, s))
            except Exception as e:
                die(f"yosys failed to map {args.top} with the {s} ABC script: {e}")
            os._exit(0)
        children.append(pid)
    bad = [pid for pid in children if os.waitpid(pid, 0)[1] != 0]
    if bad:
        sys.exit(1)
    log(f"done in {time.time() - t0:.1f} s")

if __name__ == "__main__":
    main()
