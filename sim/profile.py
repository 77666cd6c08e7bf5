"""`python -m sim.profile [--config full] [--pixels 65536]`: where a simulated clock goes, per RTL block.

Builds the Verilator frame harness with --prof-cfuncs (every always block and assignment its
own C++ function, named after its module and source line: ..._PROF__<module>__l<line>;
build/sim/frame_tb/<config>-verilator-profcfuncs), streams a synthetic pass
(sim/frame_rtl.py synthetic_pass) under `perf record -e cpu-clock` (a software clock: this
machine's virtual CPUs expose no hardware counters) and prints the samples per module and the
top blocks (module:line), as Markdown tables (docs/simulation.md). Functions of no module
(Verilator's scheduler, the C++ main, the start-up's memory clearing) are grouped by name.
Splitting the code into one function per block costs call overhead of its own (the scheduler's
`_eval_nba` share), so the shares are of the blocks, not a prediction of the -O2 build's time.

`--srcline`: the frame harness's own build (-O2, no --prof-cfuncs) with debug information
(-g: the same code; build/sim/frame_tb/<config>-verilator-g), --runs runs of the pass under
`perf record`, the samples by C++ source line (`perf report --sort srcline`), each line of the
generated model given to the pipeline block (the instance under texture_pipeline) whose
signal the statement names; Verilator's inlined helpers (verilated_funcs.h: sign extension,
signed multiply and shift) and the start-up (memory clearing, page faults) apart.

`--instructions`: the same build with DWARF 4 line information (valgrind 3.19 reads no DWARF 5;
build/sim/frame_tb/<config>-verilator-g4), one run of the pass under valgrind's cachegrind
(`--cache-sim=no`: instructions executed, which do not move with the machine's load as time
does), the instructions a clock by block as --srcline gives them, the total a clock, and a check
that the run's colours equal the kept run's. --plus adds the harness's plusargs (`--plus
+NBA_ONLY=0`: sim/frame_main.cpp's options); +HUGE_TEXT=0 always (valgrind cannot run the code
moved into huge pages). On this machine a clock's time follows its instructions (an IPC near 5 in
the model's one large function), so this is how two versions of the harness or the RTL compare
under load (docs/simulation.md, stop 51).
"""
from __future__ import annotations

import argparse
import collections
import os
import re
import shutil
import subprocess
import sys

from sim import frame_rtl

PROF = re.compile(r"__PROF__(\w+?)__l(\d+)")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m sim.profile", description=__doc__.splitlines()[0])
    ap.add_argument("--config", default="full")
    ap.add_argument("--pixels", type=int, default=65536)
    ap.add_argument("--top", type=int, default=15)
    ap.add_argument("--srcline", action="store_true", help="the -O2 build with -g, samples by C++ line and block")
    ap.add_argument("--runs", type=int, default=6, help="--srcline: runs of the pass recorded")
    ap.add_argument("--instructions", action="store_true",
                    help="instructions a clock by block, one run under valgrind's cachegrind")
    ap.add_argument("--plus", action="append", default=[], help="--instructions: a plusarg of the run (+NBA_ONLY=0)")
    a = ap.parse_args(argv)
    if a.pixels < 1:
        print(f"sim.profile: --pixels {a.pixels}: expected a positive count", file=sys.stderr)
        return 2
    bad = [x for x in a.plus if not re.fullmatch(r"\+\w+=\w+", x)]
    if bad:
        print(f"sim.profile: --plus {bad[0]!r}: expected a plusarg such as +NBA_ONLY=0", file=sys.stderr)
        return 2
    if a.instructions:
        if shutil.which("valgrind") is None:
            print("sim.profile: valgrind not found (make setup installs it; apt-get install valgrind)", file=sys.stderr)
            return 2
        return instructions(a.config, a.pixels, a.top, a.plus)
    if shutil.which("perf") is None:
        print("sim.profile: perf not found (apt-get install linux-perf)", file=sys.stderr)
        return 2
    if a.srcline:
        return srcline(a.config, a.pixels, a.runs, a.top)
    frame_rtl.VERILATOR_ARGS = frame_rtl.VERILATOR_ARGS + ["--prof-cfuncs"]
    frame_rtl.BUILD_TAG = "-profcfuncs"
    tex, s, Jm, je = frame_rtl.synthetic_pass(a.config, a.pixels)
    os.environ["FRAME_KEEP"] = "1"
    frame_rtl.run_frame_rtl(a.config, "verilator", tex, s, Jm, je)
    bdir = frame_rtl.build_dir(a.config, "verilator")
    rdir = max((bdir / "runs").iterdir(), key=lambda p: p.stat().st_mtime)
    args = (rdir / "cmdline.txt").read_text().split()
    data = rdir / "perf.data"
    subprocess.run(["perf", "record", "-q", "-e", "cpu-clock", "-F", "10000", "-o", str(data), *args], cwd=rdir,
                   check=True, stdout=subprocess.DEVNULL)
    rep = subprocess.run(["perf", "report", "-i", str(data), "--stdio", "--no-children", "--sort", "symbol"],
                         cwd=rdir, check=True, capture_output=True, text=True).stdout
    by_mod, by_blk = collections.Counter(), collections.Counter()
    for line in rep.splitlines():
        m = re.match(r"\s*([\d.]+)%\s+\[[.k]\]\s+(\S+)", line)
        if not m:
            continue
        pct, sym = float(m.group(1)), m.group(2)
        p = PROF.search(sym)
        if p:
            by_mod[p.group(1)] += pct
            by_blk[f"{p.group(1)}:{p.group(2)}"] += pct
        else:
            by_mod[sym.split("___024root___")[-1] if "___024root___" in sym else sym] += pct
    print(f"{a.config}, {a.pixels} pixels, perf cpu-clock samples by module (%):\n")
    print("| module or function | % |\n|---|---|")
    for k, v in by_mod.most_common(a.top):
        print(f"| {k} | {v:.1f} |")
    print(f"\ntop blocks (module:line of rtl/<module>.v):\n\n| block | % |\n|---|---|")
    for k, v in by_blk.most_common(a.top):
        print(f"| {k} | {v:.1f} |")
    return 0


NAME = re.compile(r"frame_tb__DOT__(\w+)")


def _owner(lines: list[str], i: int) -> str:
    """The pipeline block whose signal the C++ statement around line i (0-based) names."""
    j = i
    while j > 0 and not lines[j - 1].rstrip().endswith((";", "{", "}")):
        j -= 1
    m = NAME.search(" ".join(lines[j:i + 1]))
    if not m:
        return "Verilator's temporaries and scheduler"
    parts = m.group(1).split("__DOT__")
    if parts[:2] != ["u_pipe", "u_pipe"]:
        return "frame_tb (the harness)"
    rest = parts[2:]
    if len(rest) < 2:
        return "texture_pipeline (its own logic)"
    if rest[0] == "u_texture_sum" and len(rest) > 2 and rest[1] == "u_noise_leaves":
        return "u_texture_sum.u_noise_leaves (the noise terms)"
    return rest[0]


def _kept_run(config: str, pixels: int, cflags: str, tag: str):
    """Build the frame harness with extra C++ flags (its own build directory), run a synthetic pass
    and keep the run: (build directory, run directory, its command line)."""
    frame_rtl.VERILATOR_ARGS = frame_rtl.VERILATOR_ARGS + ["-CFLAGS", cflags]
    frame_rtl.BUILD_TAG = tag
    tex, s, Jm, je = frame_rtl.synthetic_pass(config, pixels)
    os.environ["FRAME_KEEP"] = "1"
    frame_rtl.run_frame_rtl(config, "verilator", tex, s, Jm, je)
    bdir = frame_rtl.build_dir(config, "verilator")
    rdir = max((bdir / "runs").iterdir(), key=lambda p: p.stat().st_mtime)
    return bdir, rdir, (rdir / "cmdline.txt").read_text().strip()


STARTUP = ("Slow.cpp", "memset", "clear_page", "page_fault", "mm_fault", "do_anonymous", "unmap", "dl-")
FUNCS = "verilated_funcs.h (sign extension, signed multiply and shift, inlined)"


class _Blocks:
    """Gives a generated C++ line (file, line) to its pipeline block (_owner), the model's files read once."""

    def __init__(self, bdir):
        self.bdir, self.texts = bdir, {}

    def __call__(self, where: str, line: int) -> str:
        f = re.search(r"(Vframe_tb___024root__\d+\.cpp)$", where)
        if f:
            if f.group(1) not in self.texts:
                self.texts[f.group(1)] = (self.bdir / f.group(1)).read_text().splitlines()
            return _owner(self.texts[f.group(1)], line - 1)
        if where.endswith("verilated_funcs.h"):
            return FUNCS
        if any(k in where for k in STARTUP):
            return "start-up and exit (memory clearing, page faults, loading)"
        return "other"


def instructions(config: str, pixels: int, top: int, plus: list[str]) -> int:
    """--instructions: one run of the kept pass under cachegrind, instructions a clock by block."""
    bdir, rdir, cmd = _kept_run(config, pixels, "-g -gdwarf-4", "-g4")
    work = rdir / "cachegrind"
    work.mkdir(exist_ok=True)
    args = cmd.split()
    for key, val in (("WALL", "wall.txt"), ("OUTBIN", "out.bin"), ("STATS", "stats.txt"), ("SEGSTATS", "segstats.hex")):
        args = [f"+{key}={work / val}" if a.startswith(f"+{key}=") else a for a in args]
    out = work / "cachegrind.out"
    subprocess.run(["valgrind", "--tool=cachegrind", "--cache-sim=no", f"--cachegrind-out-file={out}", *args,
                    "+HUGE_TEXT=0", *plus], cwd=rdir, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    if (work / "out.bin").read_bytes() != (rdir / "out.bin").read_bytes():
        print(f"sim.profile: the run under cachegrind ({' '.join(plus) or 'no plusargs'}) gave other colours than "
              f"the kept run {rdir}", file=sys.stderr)
        return 1
    stats = dict(line.split() for line in (work / "stats.txt").read_text().splitlines() if line.strip())
    clocks = int(stats["total_cycles"])
    block = _Blocks(bdir)
    by, where, total = collections.Counter(), None, 0
    for line in out.read_text().splitlines():
        if line.startswith("fl="):
            where = line[3:].strip()
            continue
        m = re.match(r"(\d+) (\d+)$", line)
        if m and where is not None:
            n = int(m.group(2))
            total += n
            by[block(where, int(m.group(1)))] += n
    print(f"{config}, {pixels} pixels, {clocks} clocks, {' '.join(plus) or 'default plusargs'}: instructions "
          f"(valgrind cachegrind) a clock by block, the run's start-up included:\n")
    print("| block (instance in texture_pipeline) or function | instructions a clock | % |\n|---|---|---|")
    for k, v in by.most_common(top):
        print(f"| {k} | {v / clocks:,.1f} | {100 * v / total:.1f} |")
    print(f"| total | {total / clocks:,.1f} | 100.0 |")
    return 0


def srcline(config: str, pixels: int, runs: int, top: int) -> int:
    bdir, rdir, cmd = _kept_run(config, pixels, "-g", "-g")
    data = rdir / "perf.data"
    subprocess.run(["perf", "record", "-q", "-e", "cpu-clock", "-F", "10000", "-o", str(data), "sh", "-c",
                    f"for i in $(seq {runs}); do {cmd} >/dev/null; done"], cwd=rdir, check=True,
                   stdout=subprocess.DEVNULL)
    rep = subprocess.run(["perf", "report", "-i", str(data), "--stdio", "--no-children", "--sort", "srcline"],
                         cwd=rdir, check=True, capture_output=True, text=True).stdout
    by = collections.Counter()
    block = _Blocks(bdir)
    for line in rep.splitlines():
        m = re.match(r"\s*([\d.]+)%\s+(\S+)", line)
        if not m:
            continue
        pct, where = float(m.group(1)), m.group(2)
        f = re.match(r"(.+):(\d+)$", where)
        by[block(f.group(1), int(f.group(2))) if f else block(where, 0)] += pct
    print(f"{config}, {pixels} pixels x {runs} runs, -O2 -g, perf cpu-clock samples by block (%):\n")
    print("| block (instance in texture_pipeline) or function | % |\n|---|---|")
    for k, v in by.most_common(top):
        print(f"| {k} | {v:.1f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
