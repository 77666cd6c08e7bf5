#!/usr/bin/env python3
"""Gate-count flow: Verilog-2005 -> Yosys -> gate equivalents (GE, NAND2 = 1).

Usage:
  synth.py --top TOP --files a.v b.v ... [--include DIR ...] [--define K=V ...]
           [--param NAME=VALUE ...] [--blocks INST[=LABEL] ...]
           [--keep-modules NAME ...] [--memories macro|flops] [--json out.json] [--keep DIR]

What it reports (JSON on stdout, and in --json):
  top, yosys_version, ge_total, ge_comb, ge_seq, storage_bits, rom_bits,
  transistors_cmos, ge_cmos_crosscheck, logic_depth, critical_path, cells,
  blocks, blocks_detail, memories, unmapped_cells, warnings, memories_mode,
  liberty, seconds.

Flow (one Yosys run for the numbers, plus a quick elaboration run when --blocks
is given, to resolve instance paths to module names):
  1. read_liberty -lib cells.lib (cell port directions, for ltp);
     read_verilog (Verilog-2005) -I/-D; hierarchy -check -top TOP [-chparam].
  2. synth -top TOP -flatten -run :fine  (everything up to and including
     `memory -nomap`).  Modules of --blocks instances get keep_hierarchy, so
     they stay separate modules; everything else is flattened.  Modules named by
     --keep-modules (every parameterisation of them) are kept likewise, so that
     instances with equal parameters are synthesized once (cmap_sat2's four
     sat2_integral, which flattened did not finish in 30 min); the totals of step 6
     still count every instance.
  3. Memories: every $mem_v2 cell is listed (width x size).  Memories with no
     write port (ROMs, e.g. constant case tables turned into ROMs by proc_rom)
     are always mapped to logic and their bits are reported as rom_bits, for
     information only.  Memories with a write port (RAMs: colour table, SAT,
     hash tables...) are the "storage":
       --memories macro (default): the RAM is left as an unmapped $mem_v2 cell,
          i.e. a black box standing for a RAM macro.  Its bits are reported as
          storage_bits and are NOT in ge_total; the logic around it (address
          arithmetic, write data, read-data muxing outside the array) is.
       --memories flops: the RAM is mapped to flip-flops plus read muxes
          (memory_map) and is in ge_total; storage_bits is still reported.
  4. The rest of synth's `fine` script (opt, techmap, abc -fast) gives a
     generic gate netlist.  On a flattened copy, FFs are legalized to plain
     D flip-flops (enables / sync resets become logic) and `stat -tech cmos`
     counts transistors; ge_cmos_crosscheck = transistors / 4.  Yosys has no
     transistor figure for FFs with asynchronous set/reset; those are counted
     as 20 transistors each (16 for $_DFF_P_ + 4), see CMOS_ASYNC_FF.  The
     generic netlist uses only simple gates (AND/OR at 6 transistors, XOR at
     12), so expect the cross-check to run ~1.2-1.6x the liberty GE: it
     catches gross errors (lost logic, wrong units), it is not a second GE.
  5. dfflibmap -liberty cells.lib; abc -liberty cells.lib; opt_clean;
     stat -liberty (per module).  GE of a module = its own cells + the GE of
     its sub-module instances (so shared modules count once per instance).
     Combinational vs sequential: cells with an `ff` group in the liberty
     file are sequential.
  6. Flatten, stat (totals, cell histogram), and `ltp` with the flip-flops and
     RAM macros deselected: the longest combinational path, counted in cells,
     between FF outputs/primary inputs and FF inputs/primary outputs.  That is
     logic_depth (the speed proxy; there is no timing in cells.lib).

Exit codes: 0 ok, 1 Yosys/design error, 2 Yosys not found or bad usage.
"""

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # run as a script: the repository's root
from hdlbuild import READ_ERRORS  # noqa: E402  (Yosys warnings made errors: `yosys -e`)

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_LIBERTY = os.path.join(HERE, "cells.lib")

# Transistors assumed for an FF with asynchronous set or reset, which Yosys'
# `stat -tech cmos` does not price: its $_DFF_P_ (16) plus a reset gate (4).
CMOS_ASYNC_FF = 20

FF_LEGAL = ("-cell $_DFF_?_ 01 -cell $_DFF_???_ 01 -cell $_DFFSR_???_ 01 "
            "-cell $_DLATCH_?_ 01 -cell $_DLATCH_???_ 01")


class FlowError(Exception):
    pass


# --------------------------------------------------------------------------
# liberty

def parse_liberty(path):
    """Return {cell: {"area": float, "seq": bool}} from a (simple) liberty file."""
    with open(path) as f:
        text = f.read()
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    cells = {}
    heads = list(re.finditer(r"\bcell\s*\(\s*\"?([A-Za-z0-9_]+)\"?\s*\)", text))
    for i, m in enumerate(heads):
        body = text[m.end(): heads[i + 1].start() if i + 1 < len(heads) else len(text)]
        am = re.search(r"\barea\s*:\s*([0-9.eE+-]+)", body)
        if not am:
            raise FlowError("liberty cell %s has no area" % m.group(1))
        seq = bool(re.search(r"\b(ff|latch|ff_bank|latch_bank)\s*\(", body))
        cells[m.group(1)] = {"area": float(am.group(1)), "seq": seq}
    if not cells:
        raise FlowError("no cells in liberty file %s" % path)
    return cells


# --------------------------------------------------------------------------
# yosys helpers

def find_yosys():
    env = os.environ.get("YOSYS")
    if env:
        if os.sep in env:
            return env if (os.path.isfile(env) and os.access(env, os.X_OK)) else None
        return shutil.which(env)
    return shutil.which("yosys")


def ys_quote(s):
    """Quote one argument for a Yosys script line."""
    s = str(s)
    if re.search(r'[\s;"#]', s):
        if '"' in s:
            raise FlowError("cannot quote %r for yosys" % s)
        return '"%s"' % s
    return s


def ys_name(rtlil_id):
    """RTLIL id (\\foo or $paramod...) -> the form stat/log_id prints."""
    return rtlil_id[1:] if rtlil_id.startswith("\\") else rtlil_id


def run_yosys(yosys, script, workdir, logname):
    path = os.path.join(workdir, logname + ".ys")
    with open(path, "w") as f:
        f.write(script)
    log = os.path.join(workdir, logname + ".log")
    proc = subprocess.run([yosys, "-q", "-e", READ_ERRORS, "-l", log, "-s", path],
                          cwd=workdir, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, universal_newlines=True)
    if proc.returncode != 0:
        tail = []
        try:
            with open(log) as f:
                tail = f.read().splitlines()[-25:]
        except OSError:
            tail = proc.stdout.splitlines()[-25:]
        errs = [l for l in tail if "ERROR" in l] or tail[-5:]
        raise FlowError("yosys failed (%s):\n%s" % (logname, "\n".join(errs)))
    with open(log) as f:
        return f.read()


def _display_path(p):
    """Path relative to the repository root when inside it, else absolute."""
    p = os.path.abspath(p)
    root = os.path.dirname(HERE)
    return os.path.relpath(p, root) if p.startswith(root + os.sep) else p


def read(workdir, name):
    with open(os.path.join(workdir, name)) as f:
        return f.read()


# --------------------------------------------------------------------------
# parsers of Yosys text output

def parse_dump_instances(text):
    """`dump -m` output -> {module: [(cell_type, cell_name), ...]}."""
    mods, cur = {}, None
    for line in text.splitlines():
        m = re.match(r"^module (\S+)$", line)
        if m:
            cur = ys_name(m.group(1))
            mods.setdefault(cur, [])
            continue
        m = re.match(r"^\s+cell (\S+) (\S+)$", line)
        if m and cur is not None:
            mods[cur].append((ys_name(m.group(1)), ys_name(m.group(2))))
    return mods


def parse_dump_memories(text):
    """`dump -m t:$mem_v2` output -> list of memory dicts."""
    mems, cur_mod, cur = [], None, None
    for line in text.splitlines():
        m = re.match(r"^module (\S+)$", line)
        if m:
            cur_mod = ys_name(m.group(1))
            continue
        m = re.match(r"^\s+cell (\$mem(?:_v2)?) (\S+)$", line)
        if m:
            cur = {"module": cur_mod, "name": ys_name(m.group(2))}
            mems.append(cur)
            continue
        m = re.match(r"^\s+parameter \\(WIDTH|SIZE|RD_PORTS|WR_PORTS|ABITS) (\S+)$", line)
        if m and cur is not None:
            cur[m.group(1).lower()] = int(m.group(2))
            continue
        if re.match(r"^\s+end$", line):
            cur = None
    for mem in mems:
        mem["bits"] = mem.get("width", 0) * mem.get("size", 0)
        mem["kind"] = "ram" if mem.get("wr_ports", 0) > 0 else "rom"
    return mems


def parse_stat(text):
    """`stat` text -> {module: {"cells": {type: n}, "transistors": (n, plus)}}."""
    mods, cur, in_cells = {}, None, False
    for line in text.splitlines():
        m = re.match(r"^=== (.+) ===$", line)
        if m:
            name = m.group(1)
            cur = None if name == "design hierarchy" else name
            if cur is not None:
                mods[cur] = {"cells": {}, "transistors": None}
            in_cells = False
            continue
        if cur is None:
            continue
        if re.match(r"^\s+Number of cells:\s+\d+", line):
            in_cells = True
            continue
        if in_cells:
            m = re.match(r"^\s+(\S+)\s+(\d+)$", line)
            if m:
                mods[cur]["cells"][m.group(1)] = int(m.group(2))
                continue
            in_cells = False
        m = re.search(r"Estimated number of transistors:\s+(\d+)(\+?)", line)
        if m:
            mods[cur]["transistors"] = (int(m.group(1)), m.group(2) == "+")
    return mods


def parse_ltp(text):
    best, path = 0, []
    blocks = re.split(r"(?=Longest topological path in )", text)
    for b in blocks:
        m = re.match(r"Longest topological path in \S+ \(length=(\d+)\)", b)
        if not m:
            continue
        n = int(m.group(1))
        if n >= best:
            nodes = re.findall(r"^\s+\d+: (.+?)(?: \(via .*\))?$", b, flags=re.M)
            best, path = n, nodes
    return best, path


# --------------------------------------------------------------------------
# the flow

def read_cmd(args):
    flags = []
    for d in args.include or []:
        flags.append("-I" + os.path.abspath(d))
    for d in args.define or []:
        flags.append("-D" + d)
    files = [os.path.abspath(f) for f in args.files]
    for f in files:
        if not os.path.isfile(f):
            raise FlowError("no such file: %s" % f)
    cmd = "read_verilog " + " ".join(ys_quote(x) for x in flags + files) + "\n"
    lib = [os.path.abspath(f) for f in (getattr(args, "lib_files", None) or [])]
    if lib:  # modules read as black boxes (ports only): counted elsewhere
        cmd += "read_verilog -lib " + " ".join(ys_quote(x) for x in flags + lib) + "\n"
    return cmd


def hier_cmd(args):
    cmd = "hierarchy -check -top %s" % ys_quote(args.top)
    for p in args.param or []:
        if "=" not in p:
            raise FlowError("--param wants NAME=VALUE, got %r" % p)
        k, v = p.split("=", 1)
        cmd += " -chparam %s %s" % (ys_quote(k), ys_quote(v))
    return cmd + "\n"


def parse_blocks(specs):
    out = []
    for s in specs or []:
        inst, label = s.split("=", 1) if "=" in s else (s, s)
        path = [p for p in re.split(r"[./]", inst) if p]
        if not path or not label:
            raise FlowError("bad --blocks entry %r (want INST[=LABEL])" % s)
        out.append((label, inst, path))
    return out


def resolve_blocks(yosys, args, workdir, blocks):
    """Elaborate only, and map each instance path to its (derived) module."""
    script = read_cmd(args) + hier_cmd(args) + "tee -q -o inst.txt dump -m * %C\n"
    run_yosys(yosys, script, workdir, "elab")
    insts = parse_dump_instances(read(workdir, "inst.txt"))
    resolved = []
    for label, inst, path in blocks:
        mod = args.top
        for p in path:
            kids = dict((n, t) for t, n in insts.get(mod, []))
            if p not in kids:
                raise FlowError("--blocks: no instance %r in module %s (have: %s)"
                                % (p, mod, ", ".join(sorted(kids)) or "none"))
            mod = kids[p]
        resolved.append((label, inst, mod))
    return resolved


def main_flow(args, yosys):
    t0 = time.time()
    lib_path = os.path.abspath(args.liberty)
    lib = parse_liberty(lib_path)
    seq_cells = sorted(c for c in lib if lib[c]["seq"])
    keep = args.keep
    if keep:
        os.makedirs(keep, exist_ok=True)
        workdir = os.path.abspath(keep)
        tmp = None
    else:
        tmp = tempfile.TemporaryDirectory(prefix="synth_")
        workdir = tmp.name
    try:
        ver = subprocess.run([yosys, "-V"], stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, universal_newlines=True)
        yosys_version = ver.stdout.strip().splitlines()[0] if ver.stdout.strip() else "?"

        blocks = parse_blocks(args.blocks)
        resolved = resolve_blocks(yosys, args, workdir, blocks) if blocks else []
        keep_mods = sorted(set(m for _, _, m in resolved))

        L = ys_quote(lib_path)
        s = []
        s.append("read_liberty -lib %s\n" % L)
        s.append(read_cmd(args))
        s.append(hier_cmd(args))
        for m in keep_mods:
            s.append("setattr -mod -set keep_hierarchy 1 %s\n" % ys_quote(m))
        for m in args.keep_modules or []:  # the module and its derived ($paramod...\NAME) copies
            s.append("setattr -mod -set keep_hierarchy 1 %s %s\n" % (ys_quote(m), ys_quote("$paramod*\\" + m)))
        s.append("synth -top %s -flatten -run :fine\n" % ys_quote(args.top))
        s.append("tee -q -o mem.txt dump -m t:$mem_v2 t:$mem\n")
        # --- synth's `fine` step, with our choice of which memories to map
        s.append("opt -fast -full\n")
        if args.memories == "flops":
            s.append("memory_map\n")
        else:
            s.append("memory_map t:$mem_v2 r:WR_PORTS=0 %i\n")
        s.append("opt -full\ntechmap\nopt -fast\nabc -fast\nopt -fast\n")
        s.append("hierarchy -check\ntee -q -o check.txt check\n")
        # --- CMOS transistor cross-check on a flattened generic copy
        s.append("design -save generic\n")
        s.append("setattr -mod -unset keep_hierarchy\nflatten\n")
        s.append("dfflegalize %s\nopt_clean\n" % FF_LEGAL)
        s.append("tee -q -o cmos.txt stat -tech cmos\n")
        s.append("design -load generic\n")
        # --- map to the liberty cells
        s.append("dfflibmap -liberty %s\n" % L)
        s.append("abc -liberty %s\n" % L)
        s.append("opt_clean\n")
        s.append("tee -q -o stat_hier.txt stat -liberty %s\n" % L)
        # --- flat totals and logic depth
        s.append("setattr -mod -unset keep_hierarchy\nflatten\nopt_clean\n")
        s.append("tee -q -o stat_flat.txt stat -liberty %s\n" % L)
        desel = ["t:%s" % c for c in seq_cells] + ["t:$mem_v2", "t:$mem"]
        sel = " ".join(desel) + " %u" * (len(desel) - 1) + " %n"
        s.append("tee -q -o ltp.txt ltp %s\n" % sel)
        if keep:
            s.append("write_verilog -noattr netlist.v\n")
        log = run_yosys(yosys, "".join(s), workdir, "synth")

        mems = parse_dump_memories(read(workdir, "mem.txt"))
        hier = parse_stat(read(workdir, "stat_hier.txt"))
        flat = parse_stat(read(workdir, "stat_flat.txt"))
        cmos = parse_stat(read(workdir, "cmos.txt"))
        depth, path = parse_ltp(read(workdir, "ltp.txt"))

        top = args.top
        if top not in flat:
            raise FlowError("top module %s missing from stat output" % top)

        # --- per-module GE, recursive over kept sub-modules
        ram_bits_mod = {}
        for mem in mems:
            if mem["kind"] == "ram":
                ram_bits_mod[mem["module"]] = ram_bits_mod.get(mem["module"], 0) + mem["bits"]
        memo = {}

        def mod_cost(name, stack=()):
            if name in memo:
                return memo[name]
            if name in stack:
                raise FlowError("recursive hierarchy at %s" % name)
            comb = seqa = 0.0
            bits = ram_bits_mod.get(name, 0)
            unk = {}
            for ctype, n in hier.get(name, {"cells": {}})["cells"].items():
                if ctype in lib:
                    if lib[ctype]["seq"]:
                        seqa += n * lib[ctype]["area"]
                    else:
                        comb += n * lib[ctype]["area"]
                elif ctype in hier:
                    c, q, b, u = mod_cost(ctype, stack + (name,))
                    comb += n * c
                    seqa += n * q
                    bits += n * b
                    for k, v in u.items():
                        unk[k] = unk.get(k, 0) + n * v
                else:
                    unk[ctype] = unk.get(ctype, 0) + n
            memo[name] = (comb, seqa, bits, unk)
            return memo[name]

        # --- flat totals
        cells = dict(sorted(flat[top]["cells"].items()))
        ge_comb = sum(n * lib[c]["area"] for c, n in cells.items() if c in lib and not lib[c]["seq"])
        ge_seq = sum(n * lib[c]["area"] for c, n in cells.items() if c in lib and lib[c]["seq"])
        unmapped = {c: n for c, n in cells.items() if c not in lib}
        ram_macros = {c: n for c, n in unmapped.items() if c in ("$mem_v2", "$mem")}
        unmapped = {c: n for c, n in unmapped.items() if c not in ram_macros}

        h_comb, h_seq, h_bits, _ = mod_cost(top)
        if abs((h_comb + h_seq) - (ge_comb + ge_seq)) > 1e-6 * max(1.0, ge_comb + ge_seq):
            print("synth: warning: hierarchical GE %.3f != flat GE %.3f"
                  % (h_comb + h_seq, ge_comb + ge_seq), file=sys.stderr)

        blocks_out, blocks_detail = {}, {}
        for label, inst, mod in resolved:
            key = ys_name(mod)
            c, q, b, _ = mod_cost(key)
            blocks_out[label] = round(c + q, 3)
            blocks_detail[label] = {"instance": inst, "module": key,
                                    "ge": round(c + q, 3), "ge_comb": round(c, 3),
                                    "ge_seq": round(q, 3), "storage_bits": b}

        # --- CMOS cross-check
        ctop = cmos.get(top, {"cells": {}, "transistors": None})
        tr, plus = ctop["transistors"] or (0, False)
        cmos_extra, cmos_unknown = 0, {}
        if plus:
            for c, n in ctop["cells"].items():
                if re.match(r"^\$_(DFF_[NP][NP][01]|DFFSR_[NP]{3})_$", c):
                    cmos_extra += CMOS_ASYNC_FF * n
                elif re.match(r"^\$_(DFF_[NP]|BUF|NOT|AND|NAND|OR|NOR|ANDNOT|ORNOT|XOR|XNOR|"
                              r"AOI3|OAI3|AOI4|OAI4|MUX|NMUX)_$", c):
                    pass
                else:
                    cmos_unknown[c] = n
        transistors = tr + cmos_extra

        storage_bits = sum(m["bits"] for m in mems if m["kind"] == "ram")
        rom_bits = sum(m["bits"] for m in mems if m["kind"] == "rom")

        warnings = []
        for line in log.splitlines():
            m = re.match(r"^Warning: (.*)$", line)
            if m and m.group(1) not in warnings:
                warnings.append(m.group(1))
        for c, n in unmapped.items():
            warnings.insert(0, "unmapped cell type %s x%d has no area (not in GE)" % (c, n))
        if unmapped:
            print("synth: warning: unmapped cells not counted: %s" % unmapped, file=sys.stderr)

        res = {
            "top": top,
            "yosys_version": yosys_version,
            "liberty": _display_path(lib_path),
            "files": [_display_path(f) for f in args.files],
            "defines": list(args.define or []),
            "params": list(args.param or []),
            "memories_mode": args.memories,
            "ge_total": round(ge_comb + ge_seq, 3),
            "ge_comb": round(ge_comb, 3),
            "ge_seq": round(ge_seq, 3),
            "storage_bits": storage_bits,
            "rom_bits": rom_bits,
            "transistors_cmos": transistors,
            "ge_cmos_crosscheck": round(transistors / 4.0, 2),
            "cmos_unpriced_cells": cmos_unknown,
            "logic_depth": depth,
            "critical_path": [path[0], path[-1]] if path else [],
            "cells": cells,
            "ram_macros": ram_macros,
            "unmapped_cells": unmapped,
            "blocks": blocks_out,
            "blocks_detail": blocks_detail,
            "memories": [{k: m.get(k) for k in ("module", "name", "kind", "width", "size",
                                                "rd_ports", "wr_ports", "bits")} for m in mems],
            "warnings": warnings[:30],
            "seconds": round(time.time() - t0, 2),
        }
        return res
    finally:
        if tmp is not None:
            tmp.cleanup()


def main(argv=None):
    ap = argparse.ArgumentParser(description="Yosys gate-count flow (GE = NAND2 equivalents).")
    ap.add_argument("--top", required=True, help="top module")
    ap.add_argument("--files", nargs="+", required=True, help="Verilog-2005 source files")
    ap.add_argument("--include", nargs="*", default=[], help="include directories (-I)")
    ap.add_argument("--define", nargs="*", default=[], help="macro definitions K or K=V (-D)")
    ap.add_argument("--lib-files", nargs="*", default=[],
                    help="Verilog files whose modules are black boxes (their GE is counted separately)")
    ap.add_argument("--param", nargs="*", default=[], help="top-level parameter overrides NAME=VALUE")
    ap.add_argument("--blocks", nargs="*", default=[],
                    help="instance paths (a.b or a/b) of the top to report separately, as INST[=LABEL]")
    ap.add_argument("--keep-modules", nargs="*", default=[],
                    help="modules (every parameterisation) kept as separate modules, synthesized once")
    ap.add_argument("--memories", choices=("macro", "flops"), default="macro",
                    help="RAMs (arrays with a write port): macro = black box, bits reported "
                         "apart from GE (default); flops = map to FFs + muxes, inside GE")
    ap.add_argument("--liberty", default=DEFAULT_LIBERTY, help="liberty file (default: synth/cells.lib)")
    ap.add_argument("--json", help="also write the JSON result to this file")
    ap.add_argument("--keep", help="keep the Yosys scripts, logs and mapped netlist in this directory")
    args = ap.parse_args(argv)

    yosys = find_yosys()
    if yosys is None:
        print("synth: yosys not found (install Debian package yosys: make setup)", file=sys.stderr)
        return 2
    try:
        res = main_flow(args, yosys)
    except FlowError as e:
        print("synth: %s" % e, file=sys.stderr)
        return 1
    text = json.dumps(res, indent=2)
    print(text)
    if args.json:
        d = os.path.dirname(os.path.abspath(args.json))
        os.makedirs(d, exist_ok=True)
        with open(args.json, "w") as f:
            f.write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
