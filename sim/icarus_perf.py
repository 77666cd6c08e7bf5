"""Where Icarus spends its time on the pixel pipeline: `make icarus-perf`.

    python -m sim.icarus_perf [--config full] [--pixels 8192]   # cost table
    python -m sim.icarus_perf time [--config full] [--pixels N] [--stub BLOCK ...]
    python -m sim.icarus_perf census [--config full]            # vvp functor census per module
    python -m sim.icarus_perf evals [--config full]             # always @* evaluations per pixel
    python -m sim.icarus_perf opcost                            # vvp cost of one multiply

`time` builds sim/frame_tb.v under a Verilog clock (sim/icarus/perf_top.v, no cocotb,
no Python while it runs), streams a synthetic pass (sim/frame_rtl.py synthetic_pass), checks
every pixel against the golden model and prints the vvp CPU seconds. --stub replaces a block
by a latency-only stub (stub_source: the block's own header, zero data). The default
command prints the marginal vvp CPU per pixel of the whole pipeline and of its skeleton (all
four blocks stubbed), each run's fixed cost (start-up, table load) removed by timing two
sizes, the floor that the multiplies alone put under any RTL of this arithmetic, and that
floor added to the skeleton.

`census` counts, per module definition, the vvp functors that make event-driven simulation
slow (docs/simulation.md): .concat8 (a net driven piecewise), .reduce, net-level arithmetic,
other functors, processes, and multiplies (behavioural %mul and net-level; a pixel runs each
once). tb/test_sim_style.py asserts there is no .concat8.

`evals` instruments a copy of rtl/ so that every `always @* begin` block counts its
evaluations, and prints per module the instances of those blocks and their evaluations per
pixel: at most one per instance means no block reruns on glitches (inputs settling in
several delta cycles). tb/test_sim_style.py asserts it.

`opcost` times vvp on 100 straight-line statements in one always @* block (24-bit
operands): `p_k = a * b` (each product to its own variable: two loads, a multiply, a store,
the cheapest form a multiply takes in vvp) and `acc = acc + a * b` (a multiply-add); and on
100 nets `wire p_k = a * b`. The floor uses the plain product: a pixel cannot cost less than
its multiplies at that price. `opcost --write DIR` writes those sources (to profile vvp).
"""
from __future__ import annotations

import argparse
import collections
import json
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from hdlbuild import ROOT, gen_dir
from model.hw.config import load_config
from model.hw.regmap import pack_pixels, pix_width, pixels_hex, unpack_rgba, write_sequence, writes_hex

HERE = ROOT / "sim" / "icarus"
HARNESS = ROOT / "sim" / "frame_tb.v"
BLOCKS = ("quadric_mac", "noise_term", "filter_width", "colour_map")


def _need(tool: str) -> None:
    import shutil

    if shutil.which(tool) is None:
        sys.exit(f"icarus_perf: `{tool}` not found on PATH (make setup installs Icarus Verilog)")


def _prepare(config: str, pixels: int) -> Path:
    from model.hw.golden import texture_pipeline
    from sim.frame_rtl import synthetic_pass

    wdir = ROOT / "build" / "icarus_perf" / f"{config}-{pixels}"
    wdir.mkdir(parents=True, exist_ok=True)
    cfg = load_config(config)
    tex, s, Jm, je = synthetic_pass(config, pixels)
    words = pack_pixels(cfg, np.asarray(s).reshape(-1, 3), np.asarray(Jm).reshape(-1, 3, 2),
                        np.asarray(je).reshape(-1))
    # written every run: a pass prepared under another register map or golden model must not
    # be reused (the files are cheap; the simulation is the cost)
    (wdir / "params.hex").write_text(writes_hex(write_sequence(cfg, tex)))
    (wdir / "pixels.hex").write_text(pixels_hex(cfg, words))
    np.save(wdir / "expected.npy", texture_pipeline(cfg, tex, s, Jm, je).astype(np.uint8))
    return wdir


def stub_source(module: str) -> str:
    """A latency-only stub of rtl/<module>.v: its own module header (parameters, derived
    widths and port declarations, copied from the file up to its last output declaration),
    out_valid = in_valid delayed by `LAT_<MODULE>, every other output 0."""
    text = (ROOT / "rtl" / f"{module}.v").read_text()
    start = text.index(f"module {module}")
    end = list(re.finditer(r"^\s*output\s+(?:wire|reg)\b[^;]*;", text, flags=re.M))[-1].end()
    header = text[start:end].replace("output reg", "output wire")
    outs = [o for o in re.findall(r"output\s+wire\s*(?:signed\s*)?(?:\[[^\]]*\])?\s*(\w+)", header) if o != "out_valid"]
    lat = f"`LAT_{module.upper()}"
    if re.search(r"parameter\s+FPGA_REGS\b", header):  # the block's latency under its FPGA_REGS
        lat = f"(FPGA_REGS ? `LAT_{module.upper()}_FPGA : `LAT_{module.upper()})"
    lines = [f"// {module} stub (sim/icarus_perf.py): out_valid = in_valid delayed by {lat}, data 0.",
             "`default_nettype none", '`include "tex_latency.vh"', header,
             f"reg [{lat}-1:0] v_reg;",
             "always @(posedge clk) begin",
             f"    if (rst) v_reg <= {{{lat}{{1'b0}}}};",
             f"    else if (ce) v_reg <= {{v_reg[{lat}-2:0], in_valid}};",
             "end",
             f"assign out_valid = v_reg[{lat}-1];"]
    lines += [f"assign {o} = 0;" for o in outs]
    lines += ["endmodule", "`default_nettype wire", ""]
    return "\n".join(lines)


def _compile(config: str, pixels: int, stubs=(), out: Path | None = None) -> Path:
    _need("iverilog")
    stubs = set(stubs)
    sdir = ROOT / "build" / "icarus_perf" / "stubs"
    sdir.mkdir(parents=True, exist_ok=True)
    for m in stubs:
        (sdir / f"{m}.v").write_text(stub_source(m))
    srcs = [sdir / f"{p.stem}.v" if p.stem in stubs else p for p in sorted((ROOT / "rtl").glob("*.v"))]
    srcs += [HARNESS, HERE / "perf_top.v"]
    tag = "-".join(sorted(stubs)) or "rtl"
    vvp = out or ROOT / "build" / "icarus_perf" / f"{config}-{tag}-{pixels}.vvp"
    vvp.parent.mkdir(parents=True, exist_ok=True)
    return _iverilog(config, pixels, srcs, ROOT / "rtl", vvp)


def _iverilog(config: str, pixels: int, srcs, rtl_dir: Path, vvp: Path) -> Path:
    """Build perf_top over `srcs` and the configuration's texture_unit (includes from
    `rtl_dir`) into `vvp`."""
    cfg = load_config(config)
    subprocess.run(["iverilog", "-g2005", "-o", str(vvp), "-s", "perf_top", f"-DPERF_MAX_PIX={pixels}",
                    f"-DPERF_PIX_W={pix_width(cfg)}", f"-I{rtl_dir}"]
                   + [str(s) for s in srcs] + [str(gen_dir(cfg) / "texture_unit.v")], check=True)
    return vvp


def _vvp(vvp: Path, wdir: Path, pixels: int, out: Path, stats: Path) -> str:
    """Run a perf_top build on the pass prepared in `wdir`; its standard output."""
    nwr = sum(1 for _ in open(wdir / "params.hex"))
    return subprocess.run(["vvp", "-n", str(vvp), f"+PARAMS={wdir / 'params.hex'}", f"+PIXELS={wdir / 'pixels.hex'}",
                           f"+OUT={out}", f"+STATS={stats}", f"+NPIX={pixels}", f"+NWR={nwr}"],
                          check=True, capture_output=True, text=True).stdout


def time_run(config: str, pixels: int, stubs=()) -> dict:
    """vvp CPU seconds for `pixels` pixels (best of one run) and the mismatch count."""
    wdir = _prepare(config, pixels)
    vvp = _compile(config, pixels, stubs)
    out = wdir / ("out-" + ("-".join(sorted(stubs)) or "rtl") + ".hex")
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    _vvp(vvp, wdir, pixels, out, wdir / "stats.txt")
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    from sim.frame_rtl import read_hex

    got = unpack_rgba(np.array(read_hex(out), dtype=np.uint64).astype(np.uint32))
    exp = np.load(wdir / "expected.npy")
    mism = int(np.count_nonzero(np.any(exp != got, axis=-1))) if got.shape == exp.shape else pixels
    return {"config": config, "pixels": pixels, "stubs": sorted(stubs), "cpu_s": round(cpu, 3),
            "wall_s": round(wall, 3), "mismatches": mism}


def per_pixel_us(config: str, pixels: int, stubs=()) -> tuple[float, int]:
    """Marginal vvp CPU microseconds per pixel, (t(2P) - t(P)) / P, fixed costs removed; and
    the pixels that differed from the golden model in either run."""
    small = time_run(config, pixels, stubs)
    big = time_run(config, 2 * pixels, stubs)
    return max(big["cpu_s"] - small["cpu_s"], 0.0) / pixels * 1e6, small["mismatches"] + big["mismatches"]


def table(config: str, pixels: int) -> list[dict]:
    """The whole pipeline, its skeleton (the four blocks stubbed: harness, parameter registers,
    adder tree, delay lines, skid buffer), the floor set by the multiplies alone, and that floor
    on top of the skeleton: no RTL of this arithmetic under this harness runs faster."""
    steps = ["whole pipeline", "skeleton", "census", "op cost"]
    rows = []
    _progress(0, steps)
    whole, mismatches = per_pixel_us(config, pixels)
    rows.append({"part": "whole pipeline", "us_per_pixel": round(whole, 1),
                 "pixels_per_second": round(1e6 / whole, 1) if whole else None, "mismatches": mismatches})
    _progress(1, steps)
    skeleton, _ = per_pixel_us(config, pixels, BLOCKS)
    rows.append({"part": "skeleton (the four blocks stubbed)", "us_per_pixel": round(skeleton, 1),
                 "pixels_per_second": round(1e6 / skeleton, 1) if skeleton else None})
    _progress(2, steps)
    muls = sum(r["mul"] for r in census_of_config(config)[0].values())
    _progress(3, steps)
    ns = opcost()["ns_per_multiply"]
    floor = muls * ns / 1e3
    rows.append({"part": f"floor: {muls} multiplies a pixel x {ns} ns (opcost)", "us_per_pixel": round(floor, 1),
                 "pixels_per_second": round(1e6 / floor, 1) if floor else None})
    rows.append({"part": "floor: skeleton + multiplies", "us_per_pixel": round(skeleton + floor, 1),
                 "pixels_per_second": round(1e6 / (skeleton + floor), 1) if skeleton + floor else None})
    _progress(4, steps)
    return rows


def _instrumented(config: str, pixels: int, td: Path) -> tuple[Path, dict]:
    """A copy of rtl/ in which every `always @* begin` block first calls a perf_top task that
    counts its module's evaluations, and a perf_top that prints the counts when done; built.
    Returns the vvp and, per module, the instances of those blocks in the elaborated design."""
    (td / "rtl").mkdir()
    blocks = []
    for f in sorted((ROOT / "rtl").iterdir()):
        text = f.read_text()
        if f.suffix == ".v":
            text, n = re.subn(r"^(\s*)always @\*\s*begin\s*(?://.*)?$",
                              lambda m: f"{m.group(0)}\n{m.group(1)}    perf_top.bump_{f.stem};", text, flags=re.M)
            if n:
                blocks.append(f.stem)
        (td / "rtl" / f.name).write_text(text)
    top = (HERE / "perf_top.v").read_text()
    decl = "".join(f"integer ev_{m} = 0;\ntask bump_{m}; ev_{m} = ev_{m} + 1; endtask\n" for m in blocks)
    show = " ".join(f'$display("evals {m} %0d", ev_{m});' for m in blocks)
    assert "wire done;\n" in top and "#20 $finish;" in top, "sim/icarus/perf_top.v changed: update evals()"
    (td / "perf_top.v").write_text(top.replace("wire done;\n", "wire done;\n" + decl)
                                   .replace("#20 $finish;", f"#20 {show} $finish;"))
    srcs = sorted((td / "rtl").glob("*.v")) + [HARNESS, td / "perf_top.v"]
    vvp = _iverilog(config, pixels, srcs, td / "rtl", td / f"evals-{pixels}.vvp")
    text = vvp.read_text()
    return vvp, {m: len(re.findall(rf"%fork TD_perf_top\.bump_{m},", text)) for m in blocks}


def evals(config: str, pixels: int) -> dict:
    """Per module: instances of its `always @* begin` blocks, and their evaluations per pixel
    (marginal over P and 2P pixels). A block whose inputs change once a clock runs once; more
    evaluations than instances means blocks rerun as their inputs settle (glitches)."""
    counts = {}
    with tempfile.TemporaryDirectory() as tds:
        for n in (pixels, 2 * pixels):
            td = Path(tds) / str(n)
            td.mkdir()
            vvp, blocks = _instrumented(config, n, td)
            stdout = _vvp(vvp, _prepare(config, n), n, td / "out.hex", td / "stats.txt")
            counts[n] = {m: int(c) for m, c in re.findall(r"^evals (\w+) (\d+)$", stdout, flags=re.M)}
    return {m: {"instances": blocks[m],
                "evals_per_pixel": round((counts[2 * pixels][m] - counts[pixels][m]) / pixels, 2)}
            for m in blocks}


def _progress(i: int, steps) -> None:
    done = "#" * i + "." * (len(steps) - i)
    what = steps[i] if i < len(steps) else "done"
    print(f"\r[{done}] {what:20s}", end="\n" if i == len(steps) else "", file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------
# census


def census(vvp: Path):
    """Per module definition: Counter of concat8 / reduce / arith / functors / threads;
    and the names of the nets driven through a .concat8."""
    scope_def, parent = {}, {}
    rows = collections.defaultdict(collections.Counter)
    c8, c8_nets = set(), collections.Counter()
    cur = None
    lines = vvp.read_text().splitlines()

    def module_of(scope):
        while scope is not None and scope_def.get(scope) is None:
            scope = parent.get(scope)
        return scope_def.get(scope, "?") if scope else "?"

    for line in lines:
        m = re.match(r'(S_\w+)\s+\.scope (\w+), "([^"]*)" "([^"]*)"[^;]*?(?:, (S_\w+))?;', line)
        if m:
            lab, kind, _inst, defn, par = m.groups()
            scope_def[lab] = defn if kind == "module" else None
            parent[lab] = par
            cur = lab
            continue
        m = re.match(r'\s+\.scope (S_\w+);', line)
        if m:
            cur = m.group(1)
            continue
        if line.startswith("    .thread"):
            rows[module_of(cur)]["threads"] += 1
            continue
        if re.match(r'\s+%mul\b', line) or re.search(r'\.arith/mult\b', line):
            rows[module_of(cur)]["mul"] += 1  # multiplies, behavioural or net-level
        m = re.match(r'(\S+)\s+\.(\w+)(/\S+)?\s', line)
        if not m or cur is None:
            continue
        lab, op = m.group(1), m.group(2)
        mod = module_of(cur)
        if op == "concat8":
            c8.add(lab)
            rows[mod]["concat8"] += 1
        elif op == "reduce":
            rows[mod]["reduce"] += 1
        elif op in ("arith", "cmp"):
            rows[mod]["arith"] += 1
        elif op in ("functor", "part", "concat", "extend", "sfunc", "ufunc", "shift", "repeat", "substitute"):
            rows[mod]["functors"] += 1
    for line in lines:
        m = re.match(r'\S+\s+\.net\S*\s+"([^"]+)".*,\s*(\S+);', line)
        if m and m.group(2) in c8:
            c8_nets[m.group(1)] += 1
    return rows, c8_nets


def census_of_config(config: str):
    _need("iverilog")
    with tempfile.TemporaryDirectory() as td:
        vvp = Path(td) / "census.vvp"
        srcs = sorted(str(p) for p in (ROOT / "rtl").glob("*.v"))
        subprocess.run(["iverilog", "-g2005", "-o", str(vvp), "-s", "texture_unit", f"-I{ROOT / 'rtl'}"]
                       + srcs + [str(gen_dir(config) / "texture_unit.v")], check=True)
        return census(vvp)


# ---------------------------------------------------------------------------
# opcost

OPCOST_V = """
module top;
reg clk = 1'b0; integer n = 0;
reg [23:0] a_reg, b_reg;
reg [47:0] acc, out_reg;
%s
always #5 clk = ~clk;
always @* begin
    acc = 48'd0;
%s
end
always @(posedge clk) begin
    n <= n + 1; a_reg <= a_reg + 24'd3; b_reg <= b_reg ^ 24'h5a5a5a; out_reg <= acc;
    if (n == %d) $finish;
end
initial begin a_reg = 24'd1; b_reg = 24'd7; end
endmodule
"""


def opcost_sources(ops: int = 100, clocks: int = 50_000) -> dict[str, str]:
    """The Verilog that `opcost` times: per form, an empty block and one of `ops` statements."""
    forms = {"multiply": lambda k: (f"reg [47:0] p{k};", f"    p{k} = a_reg * b_reg;"),
             "multiply_add": lambda k: ("", "    acc = acc + a_reg * b_reg;"),
             "net_multiply": lambda k: (f"wire [47:0] p{k} = a_reg * b_reg;", "")}
    out = {}
    for name, form in forms.items():
        for k in (0, ops):
            lines = [form(i) for i in range(k)]
            out[f"{name}{k}"] = OPCOST_V % ("\n".join(d for d, _ in lines),
                                            "\n".join(b for _, b in lines if b), clocks)
    return out


def opcost(clocks: int = 50_000, ops: int = 100) -> dict:
    """vvp CPU per operation: marginal over an empty block, per clock and operation."""
    _need("iverilog")
    srcs = opcost_sources(ops, clocks)
    out = {}
    with tempfile.TemporaryDirectory() as td:
        cpu = {}
        for tag, text in srcs.items():
            src = Path(td) / f"{tag}.v"
            src.write_text(text)
            vvp = Path(td) / f"{tag}.vvp"
            subprocess.run(["iverilog", "-o", str(vvp), str(src)], check=True, capture_output=True)
            r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            subprocess.run(["vvp", "-n", str(vvp)], check=True, stdout=subprocess.DEVNULL)
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu[tag] = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
        for name in ("multiply", "multiply_add", "net_multiply"):
            out[f"ns_per_{name}"] = round((cpu[f"{name}{ops}"] - cpu[f"{name}0"]) / clocks / ops * 1e9, 1)
        out["clock_us_empty"] = round(cpu["multiply0"] / clocks * 1e6, 3)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", nargs="?", default="table", choices=("table", "time", "census", "evals", "opcost"))
    ap.add_argument("--config", default="full", choices=("full", "reduced"))
    ap.add_argument("--pixels", type=int, default=8192)
    ap.add_argument("--stub", action="append", default=[], choices=BLOCKS)
    ap.add_argument("--write", metavar="DIR", help="opcost: write its Verilog sources to DIR and stop")
    a = ap.parse_args(argv)
    if a.pixels < 1:
        sys.exit(f"icarus_perf: --pixels {a.pixels}: must be at least 1")
    if a.what == "time":
        r = time_run(a.config, a.pixels, a.stub)
        print(json.dumps(r))
        return 1 if r["mismatches"] and not a.stub else 0
    if a.what == "census":
        rows, nets = census_of_config(a.config)
        cols = ["concat8", "reduce", "arith", "functors", "threads", "mul"]
        print(f"{'module':20s}" + "".join(f"{c:>10s}" for c in cols))
        tot = collections.Counter()
        for mod in sorted(rows, key=lambda m: -sum(rows[m].values())):
            print(f"{mod:20s}" + "".join(f"{rows[mod][c]:10d}" for c in cols))
            tot.update(rows[mod])
        print(f"{'total':20s}" + "".join(f"{tot[c]:10d}" for c in cols))
        if nets:
            print("nets driven piecewise (.concat8):", ", ".join(f"{n} x{k}" for n, k in sorted(nets.items())))
        return 0
    if a.what == "evals":
        print(f"{'module':20s}{'instances':>12s}{'evals/pixel':>14s}")
        for m, r in sorted(evals(a.config, a.pixels).items(), key=lambda kv: -kv[1]["evals_per_pixel"]):
            print(f"{m:20s}{r['instances']:12d}{r['evals_per_pixel']:14.2f}")
        return 0
    if a.what == "opcost" and a.write:
        d = Path(a.write)
        d.mkdir(parents=True, exist_ok=True)
        for tag, text in opcost_sources().items():
            (d / f"{tag}.v").write_text(text)
        print(f"opcost sources written to {d}/ (build: iverilog -o X.vvp {d}/multiply100.v; run: vvp -n X.vvp)")
        return 0
    if a.what == "opcost":
        print(json.dumps(opcost()))
        return 0
    print(f"Icarus, {a.config} configuration, marginal vvp CPU per pixel ({a.pixels} and {2 * a.pixels} pixels)",
          file=sys.stderr)
    rows = table(a.config, a.pixels)
    for r in rows:
        print(json.dumps(r))
    return 1 if rows[0]["mismatches"] else 0


if __name__ == "__main__":
    sys.exit(main())
