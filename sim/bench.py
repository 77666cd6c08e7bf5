"""`make bench-sim`: RTL simulation throughput against the golden model's, on the same frame.

For each configuration (full, compact, reduced; CONFIG= one of them), a synthetic marble-like
pass (sim/frame_rtl.py synthetic_pass) of a 512x512 frame (PIXELS_VERILATOR= another pixel
count) is run through the golden model (model.hw.golden.texture_pipeline) and streamed
through texture_pipeline under Verilator (sim/frame_main.cpp; the build is timed apart and
done first), in the same process, alternately (golden model, Verilator, golden model, ...: both
see the same load); each is timed REPEAT= times (default 3) and the best kept. One JSON line a configuration: the golden model's pixels per second, the
Verilator run's (streaming: first pixel offered to last colour taken; run: the simulator's
start, load and file output included; frame: the whole run_frame_rtl call, packing the pixel
words in Python and reading the colours back included) and their ratios to the golden model's,
checked bit-exact; and the same in CPU seconds (`*_cpu*`: this process's CPU time for the golden
model, the simulator process's own for Verilator, streaming and whole run): less moved by other jobs than wall time, though not
immune (under load the memory-bound golden model loses more; docs/simulation.md). Then one line for Icarus on the first configuration (PIXELS_ICARUS= pixels,
default 16384: Icarus streams about a thousand full pixels a second). Each configuration also
gives the same pass cut in BENCH_PROCS runs (default: the machine's cores) on as many simulator
processes at once (`procs` fields: their wall time with start-ups, and the whole call; the golden
model stays on one core). docs/simulation.md explains the figures.
"""
from __future__ import annotations

import io
import json
import os
import resource
import sys
import time
from contextlib import redirect_stdout

import numpy as np

from model.hw.config import CONFIG_NAMES
from sim import frame_rtl

CONFIGS = ("full", "compact", "reduced")
# simulator processes at once in the `procs` figures (the frame cut in that many runs): the machine's
# cores, BENCH_PROCS= another count (the golden model runs on one core: docs/simulation.md)
PROCS = os.cpu_count() or 1  # main() applies BENCH_PROCS=

USAGE = "usage: python -m sim.bench [pgo | steps [N,N,...]]  (settings: CONFIG=, PIXELS_VERILATOR=, REPEAT=, BENCH_PROCS=, PIXELS_ICARUS=)"


def _env_int(name: str, default: int) -> int:
    """The positive integer in environment variable `name` (`default` when unset or empty)."""
    raw = os.environ.get(name) or ""
    if not raw:
        return default
    if not raw.strip().isdigit() or int(raw) < 1:
        raise ValueError(f"{name}={raw!r}: expected a positive integer")
    return int(raw)


def _best(fn, repeat: int):
    best, out = float("inf"), None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def versus_golden(config: str, pixels: int, repeat: int = 3) -> dict:
    """Golden model and Verilator on the same synthetic pass of `pixels` pixels (best of `repeat`)."""
    from model.hw.golden import texture_pipeline

    cfg = frame_rtl.config_of(config)
    tex, s, Jm, je = frame_rtl.synthetic_pass(config, pixels)
    t0 = time.perf_counter()
    frame_rtl.build(cfg, "verilator")
    build_s = time.perf_counter() - t0
    # alternately, golden model then Verilator, so that both see the same load of this shared
    # machine (a load that comes or goes between two blocks of runs moved the ratio by 30%)
    # besides wall time, each side's CPU time (this process's for the golden model, the simulator's
    # own for Verilator): less moved by other jobs than wall time (docs/simulation.md)
    runs, golden_s, golden_cpu = [], float("inf"), float("inf")
    for _ in range(repeat):
        c = time.process_time()
        g_s, exp = _best(lambda: texture_pipeline(cfg, tex, s, Jm, je).astype(np.uint8), 1)
        golden_cpu = min(golden_cpu, time.process_time() - c)
        golden_s = min(golden_s, g_s)
        t = time.perf_counter()
        ch = resource.getrusage(resource.RUSAGE_CHILDREN)
        rgba, cycles, run_s, st = frame_rtl.run_frame_rtl(cfg, "verilator", tex, s, Jm, je, return_stats=True)
        frame_s = time.perf_counter() - t
        ch2 = resource.getrusage(resource.RUSAGE_CHILDREN)
        run_cpu = (ch2.ru_utime + ch2.ru_stime) - (ch.ru_utime + ch.ru_stime)
        stream_s = sum(x.get("stream_wall_us", 0) for x in st) / 1e6
        stream_cpu = sum(x.get("stream_cpu_us", 0) for x in st) / 1e6
        huge = min(x.get("huge_text_bytes", 0) for x in st)
        # the same pass cut in PROCS runs, PROCS simulator processes at once (the machine's cores)
        t = time.perf_counter()
        rgba_p, _, par_s, _ = frame_rtl.run_frame_rtl(cfg, "verilator", tex, s, Jm, je, return_stats=True, procs=PROCS)
        par_frame_s = time.perf_counter() - t
        runs.append((stream_s, run_s, frame_s, stream_cpu, run_cpu, par_s, par_frame_s))
        if np.any(rgba != exp) or np.any(rgba_p != exp):
            break
    stream_s, run_s, frame_s, stream_cpu, run_cpu, par_s, par_frame_s = (min(r[i] for r in runs) for i in range(7))
    golden = pixels / golden_s
    golden_c = pixels / max(golden_cpu, 1e-9)
    out = {
        "config": config, "pixels": pixels, "cycles": cycles, "clocks_per_pixel": round(cycles / pixels, 3),
        "golden_pixels_per_second": round(golden),
        "verilator_pixels_per_second_stream": round(pixels / max(stream_s, 1e-9)),
        "verilator_pixels_per_second_run": round(pixels / run_s),
        "verilator_pixels_per_second_frame": round(pixels / frame_s),
        "ratio_stream": round(pixels / max(stream_s, 1e-9) / golden, 3),
        "ratio_run": round(pixels / run_s / golden, 3),
        "ratio_frame": round(pixels / frame_s / golden, 3),
        "golden_pixels_per_cpu_second": round(golden_c),
        "verilator_pixels_per_cpu_second_stream": round(pixels / max(stream_cpu, 1e-9)),
        "verilator_pixels_per_cpu_second_run": round(pixels / max(run_cpu, 1e-9)),
        "ratio_stream_cpu": round(pixels / max(stream_cpu, 1e-9) / golden_c, 3),
        "ratio_run_cpu": round(pixels / max(run_cpu, 1e-9) / golden_c, 3),
        "fixed_seconds": round(frame_s - stream_s, 3),
        "huge_text_bytes": huge,  # the simulator's code and tables in huge pages (sim/frame_main.cpp huge_text)
        "procs": PROCS,
        "verilator_procs_pixels_per_second_run": round(pixels / par_s),
        "verilator_procs_pixels_per_second_frame": round(pixels / par_frame_s),
        "ratio_procs_run": round(pixels / par_s / golden, 3),
        "ratio_procs_frame": round(pixels / par_frame_s / golden, 3),
        "build_seconds": round(build_s, 2),
        "mismatches": int(np.count_nonzero(np.any(rgba != exp, axis=-1)) + np.count_nonzero(np.any(rgba_p != exp, axis=-1))),
    }
    out["bit_exact"] = out["mismatches"] == 0
    return out


def icarus(config: str, pixels: int) -> dict:
    """The Icarus cross-check's throughput (sim/frame_rtl.py main, checked against the golden model)."""
    with redirect_stdout(io.StringIO()) as buf:
        rc = frame_rtl.main(["--config", config, "--sim", "icarus", "--pixels", str(pixels), "--check"])
    rep = json.loads(buf.getvalue().strip().splitlines()[-1])
    rep["bit_exact"] = rc == 0 and rep.get("mismatches") == 0
    return rep


# the steps of docs/simulation.md (Verilator options, C++ -O, the compiler): 5 and 6, without options
# of their own, are the build sim/frame_rtl.py uses (and its compiler, FRAME_CXX: clang++ since stop 49)
GXX = {"CXX": "g++", "LINK": "g++"}  # g++ 12, the compiler of steps 0 to 4 and 7 to 12
CLANG = frame_rtl.compiler_vars("clang++")
O2 = dict(frame_rtl.CXX_OPT)  # the default's -O levels: -O2 (-O1 for the cold code)
O_S = {"OPT_FAST": "-Os", "OPT_SLOW": "-Os", "OPT_GLOBAL": "-Os", **GXX}  # Verilator's makefile's default
X_UNIQUE = ["--x-assign", "unique", "--x-initial", "unique"]
X_FAST = ["--x-assign", "fast", "--x-initial", "fast"]
STEPS = [
    ("C++ main, -Os, X unique", ["-Wno-fatal", *X_UNIQUE, "-O3"], O_S),
    ("--x-assign/--x-initial fast", ["-Wno-fatal", *X_FAST, "-O3"], O_S),
    ("C++ -O2", ["-Wno-fatal", *X_FAST, "-O3"], {**O2, **GXX}),
    ("C++ -O3", ["-Wno-fatal", *X_FAST, "-O3"], {"OPT_FAST": "-O3", "OPT_SLOW": "-O1", "OPT_GLOBAL": "-O2", **GXX}),
    ("--threads 2", ["-Wno-fatal", *X_FAST, "-O3", "--threads", "2"],
     {**O2, **GXX}),
    # the build sim/frame_rtl.py uses (binary pixel files since step 6 of docs/simulation.md),
    # evaluated through Vframe_tb::eval(), then (the default) its scheduler called directly
    ("binary pixel files, Vframe_tb::eval()", None, None, ["+EVAL_API=1"]),
    ("scheduler called directly (frame_main.cpp tick)", None, None, []),
    # C++ options on top of that (issue 28: none paid, docs/simulation.md)
    ("-march=native", ["-Wno-fatal", *X_FAST, "-O3", "-CFLAGS", "-march=native"],
     {**O2, **GXX}),
    ("C++ -O3 -march=native", ["-Wno-fatal", *X_FAST, "-O3", "-CFLAGS", "-march=native"],
     {"OPT_FAST": "-O3", "OPT_SLOW": "-O1", "OPT_GLOBAL": "-O3", **GXX}),
    ("--output-split 0 (one C++ file)", ["-Wno-fatal", *X_FAST, "-O3", "--output-split", "0"],
     {**O2, **GXX}),
    # stop 46 (docs/simulation.md): the clocked function split, and gcc's hardening options off
    ("--output-split-cfuncs 2000", ["-Wno-fatal", *X_FAST, "-O3", "--output-split-cfuncs", "2000"],
     {**O2, **GXX}),
    ("-fno-stack-protector -fno-plt -fomit-frame-pointer",
     ["-Wno-fatal", *X_FAST, "-O3", "-CFLAGS", "-fno-stack-protector -fno-plt -fomit-frame-pointer"],
     {**O2, **GXX}),
    # stop 49: the default build (5, 6 and `make bench-sim`) is clang++ 14's with ThinLTO (sim/frame_rtl.py
    # FRAME_CXX, LTO); 12 is its options under g++ 12 (the default before, no LTO), 13 clang++ at -O3 (with
    # ThinLTO), 14 clang++ -O2 without it (a step's fifth element: sim/frame_rtl.py settings for that step)
    ("g++ -O2 (the default's options, before stop 49's clang++)", ["-Wno-fatal", *X_FAST, "-O3"],
     {**O2, **GXX}),
    ("clang++ -O3", ["-Wno-fatal", *X_FAST, "-O3"],
     {**O2, "OPT_FAST": "-O3", **CLANG}),
    # the default build without its ThinLTO (clang++ -O2 alone: the default from stop 49's first commit)
    ("clang++ -O2 without ThinLTO", ["-Wno-fatal", *X_FAST, "-O3"],
     {**O2, **CLANG},
     [], {"LTO": False}),
    # stop 50: the default skips the falling edge's evaluation (sim/frame_main.cpp tick); this step
    # evaluates it, as before
    ("the falling edge evaluated too (+FALL_EVAL=1)", None, None, ["+FALL_EVAL=1"]),
    # stop 50: the default moves its code and tables into huge pages (sim/frame_main.cpp huge_text);
    # this step leaves them in the file's pages
    ("code and tables in the file's pages (+HUGE_TEXT=0)", None, None, ["+HUGE_TEXT=0"]),
    # stop 51: the default runs the scheduler's NBA region alone at a rising edge where no input
    # changed (sim/frame_main.cpp tick); this step runs its whole loop every clock, as before
    ("the scheduler's whole loop every clock (+NBA_ONLY=0)", None, None, ["+NBA_ONLY=0"]),
    # stop 52: the default verilates with -fdfg-synthesize-all (sim/frame_rtl.py RTL_ONLY_ARGS); this step without
    ("without -fdfg-synthesize-all", [a for a in frame_rtl.VERILATOR_ARGS if a not in frame_rtl.RTL_ONLY_ARGS],
     {**O2, **CLANG}),
]


def steps(config: str, pixels: int, repeat: int, only=None) -> int:
    """python -m sim.bench steps [i,j,...]: each build step of docs/simulation.md (or those listed)
    on the same frame (its own build directory, build/sim/frame_tb/<config>-verilator-step<i>; a
    step without options of its own: the default build, with its plusargs), one JSON line a step."""
    default = (frame_rtl.VERILATOR_ARGS, frame_rtl.CXX_OPT, frame_rtl.BUILD_TAG, frame_rtl.RUN_PLUSARGS, frame_rtl.LTO)
    ok = True
    try:
        for i, (name, vargs, cxx, *plus) in enumerate(STEPS):
            if only is not None and i not in only:
                continue
            own = vargs is not None
            frame_rtl.VERILATOR_ARGS = vargs if own else default[0]
            frame_rtl.CXX_OPT = cxx if own else default[1]
            frame_rtl.BUILD_TAG = f"-step{i}" if own else default[2]
            frame_rtl.RUN_PLUSARGS = plus[0] if plus else []
            frame_rtl.LTO = plus[1].get("LTO", default[4]) if len(plus) > 1 else default[4]
            rep = {"step": i, "what": name, **versus_golden(config, pixels, repeat)}
            ok &= rep["bit_exact"]
            print(json.dumps(rep), flush=True)
    finally:
        (frame_rtl.VERILATOR_ARGS, frame_rtl.CXX_OPT, frame_rtl.BUILD_TAG, frame_rtl.RUN_PLUSARGS,
         frame_rtl.LTO) = default
    return 0 if ok else 1


def pgo(config: str, pixels: int, repeat: int) -> int:
    """python -m sim.bench pgo: gcc's (g++ 12's) profile-guided build of the frame harness (docs/simulation.md, stop
    44): built with -fprofile-generate into build/sim/pgo/<config>, trained on the bench frame, rebuilt
    in the same build directory with -fprofile-use; one JSON line of the trained build beside the golden
    model (compare with `make bench-sim` in the same minutes: the default build is not timed here)."""
    import shutil

    prof = frame_rtl.build_root() / "sim" / "pgo" / config
    shutil.rmtree(prof, ignore_errors=True)
    default = (frame_rtl.VERILATOR_ARGS, frame_rtl.BUILD_TAG, frame_rtl.CXX_OPT)
    try:
        frame_rtl.BUILD_TAG = "-pgo"
        frame_rtl.CXX_OPT = {**default[2], **GXX}  # gcc's profile-guided build (g++ 12, no LTO)
        frame_rtl.VERILATOR_ARGS = [*default[0], "-CFLAGS", f"-fprofile-generate={prof}",
                                    "-LDFLAGS", f"-fprofile-generate={prof}"]
        versus_golden(config, pixels, 1)  # the build and its training run
        frame_rtl.VERILATOR_ARGS = [*default[0], "-CFLAGS", f"-fprofile-use={prof} -fprofile-correction -Wno-missing-profile",
                                    "-LDFLAGS", f"-fprofile-use={prof}"]
        rep = {"step": "pgo", "what": "gcc -fprofile-use (trained on this frame)", **versus_golden(config, pixels, repeat)}
    finally:
        frame_rtl.VERILATOR_ARGS, frame_rtl.BUILD_TAG, frame_rtl.CXX_OPT = default
    print(json.dumps(rep), flush=True)
    return 0 if rep["bit_exact"] else 1


def main(argv=None) -> int:
    global PROCS
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] in (["-h"], ["--help"]):
        print(USAGE)
        return 0
    try:
        if argv and argv[0] not in ("pgo", "steps"):
            raise ValueError(f"unknown argument {argv[0]!r}")
        if argv[:1] == ["pgo"] and len(argv) > 1 or argv[:1] == ["steps"] and len(argv) > 2:
            raise ValueError(f"unexpected argument {argv[-1]!r}")
        if argv[:1] == ["steps"] and len(argv) > 1 and not all(x.isdigit() for x in argv[1].split(",")):
            raise ValueError(f"steps {argv[1]!r}: expected step numbers such as 1,3")
        if os.environ.get("CONFIG") and os.environ["CONFIG"] not in CONFIG_NAMES:
            raise ValueError(f"CONFIG={os.environ['CONFIG']!r}: not a configuration ({', '.join(CONFIG_NAMES)})")
        pixels = _env_int("PIXELS_VERILATOR", 512 * 512)
        repeat = _env_int("REPEAT", 3)
        PROCS = _env_int("BENCH_PROCS", PROCS)
        pixels_icarus = _env_int("PIXELS_ICARUS", 16384)
    except ValueError as e:
        print(f"sim.bench: {e} ({USAGE})", file=sys.stderr)
        return 2
    if argv[:1] == ["pgo"]:
        return pgo(os.environ.get("CONFIG", "full"), pixels, repeat)
    if argv[:1] == ["steps"]:
        only = {int(x) for x in argv[1].split(",")} if len(argv) > 1 else None
        return steps(os.environ.get("CONFIG", "full"), pixels, repeat, only)
    configs = [os.environ["CONFIG"]] if os.environ.get("CONFIG") else list(CONFIGS)
    ok = True
    for config in configs:
        rep = versus_golden(config, pixels, repeat)
        ok &= rep["bit_exact"]
        print(json.dumps(rep), flush=True)
    rep = icarus(configs[0], pixels_icarus)
    ok &= rep["bit_exact"]
    print(json.dumps(rep), flush=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
