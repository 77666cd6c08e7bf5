"""make coverage (app/coverage.py, issue 29): the coverage file's parser, the per-module sums and
the doc section on a written example; app/coverage_reasons.toml against rtl/ (every reason names
a line that is there, in a known category); and a tiny run (one block testbench under Verilator
with COVERAGE=1) that must leave the merged file, the annotated sources and a summary whose
figures parse, summarized again by --reuse without a test run; every coverage_off region of rtl/
has its reason."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

import app.coverage as cov
from app.coverage import (CATEGORIES, coverage_off_regions, doc_body, exclusion_errors, load_exclusions, load_reasons,
                          load_toggle_notes, parse_dat, summarize, totals)
from model.cli import UserError

ROOT = Path(__file__).resolve().parents[1]


def _point(f, line, page, o, n, h="top.u", col="1", span=None):
    kv = {"f": f, "l": str(line), "n": col, "page": page, "o": o, "h": h, **({"S": span} if span else {})}
    return "C '" + "".join(f"\x01{k}\x02{v}" for k, v in kv.items()) + f"' {n}\n"


def test_parse_summarize_and_doc(tmp_path, monkeypatch):
    rtl = tmp_path / "rtl"
    rtl.mkdir()
    (rtl / "foo.v").write_text("\n".join(f"// line {i}" for i in range(1, 12)) + "\nif (P != 0) x <= 1;  // 12\n"
                               "y <= a | b;  // 13\nif (q) z <= 0;  // 14\n")
    monkeypatch.setattr(cov, "RTL", rtl)
    dat = tmp_path / "x.dat"
    dat.write_text("# SystemC::Coverage-3\n"
                   + _point("rtl/foo.v", 10, "v_line/foo", "block", 3)
                   + _point("rtl/foo.v", 12, "v_line/foo", "block", 0, span="12-13")
                   + _point("rtl/foo.v", 12, "v_line/foo", "block", 2, h="top.v", span="12-13")  # another instance hit it
                   + _point("rtl/foo.v", 13, "v_line/foo", "cond_then", 0, col="7")
                   + _point("rtl/foo.v", 14, "v_branch/foo", "if", 0, span="14")
                   + _point("rtl/foo.v", 5, "v_toggle/foo", "a[0]:0->1", 1)
                   + _point("rtl/foo.v", 5, "v_toggle/foo", "a[0]:1->0", 0)
                   + _point("rtl/foo.v", 6, "v_toggle/foo", "g[1].b[3]:0->1", 0)
                   + _point("rtl/foo.v", 6, "v_toggle/foo", "g[2].b[3]:0->1", 0)
                   + _point("rtl/tex_widths.vh", 3, "v_line/foo", "block", 0)  # a header: constant functions
                   + _point("sim/frame_tb.v", 3, "v_line/frame_tb", "block", 0))  # not rtl/: left out
    pts = parse_dat(dat)
    assert len(pts) == 11 and pts[0][0]["f"] == "rtl/foo.v" and pts[0][1] == 3
    s = summarize(pts)
    assert list(s) == ["foo"]
    f = s["foo"]
    assert f["lines"] == [2, 4] and f["uncovered_lines"] == [13, 14] and f["lines_pct"] == 50.0
    assert f["uncovered"] == [{"line": 13, "span": "13", "point": "cond_then"}, {"line": 14, "span": "14", "point": "if"}]
    assert f["toggles"] == [1, 4] and f["toggles_pct"] == 25.0 and f["untoggled"] == {"g[*].b": 2, "a": 1}
    assert totals(s) == {"lines": [2, 4], "toggles": [1, 4], "lines_pct": 50.0, "toggles_pct": 25.0}
    reasons = [{"module": "foo", "text": "if (q)", "reason": "unreachable: q is 0 when P = 0"},
               {"module": "foo", "text": "a | b", "point": "block", "reason": "reachable, not tested: wrong point"}]
    regions = [{"module": "foo", "first": 3, "last": 5, "lines": ["reg [7:0] rom [0:3];"]}]
    body = doc_body({"tests": ["tb/x"], "runs": 1, "seconds": 1.0, "pytest_status": 0, "modules": s,
                     "command": "make coverage JOBS=1"}, reasons, {"foo": "b is a constant when P = 0."},
                    [{"module": "foo", "text": "rom", "reason": "a ROM written at time 0."}], regions)
    assert "Excluded from coverage, constant by construction: 1 `/* verilator coverage_off */" in body
    assert "- foo (lines 3-5): `rom`: a ROM written at time 0." in body
    assert "Written by `make coverage JOBS=1`" in body
    assert "| foo | 2/4 | 50.0 | 1/4 | 25.0 | no |" in body and "| **total** | 2/4 | 50.0 | 1/4 | 25.0 | 0 of 1 modules |" in body
    assert "| foo | 14 | if | `if (q) z <= 0;  // 14` | unreachable: q is 0 when P = 0 |" in body
    # the second entry names another point: not this one's reason; `|` escaped in the table
    assert "| foo | 13 | cond_then | `y <= a \\| b;  // 13` | not analysed yet |" in body
    assert "Line points no test reached: 2 (unreachable: 1, elaboration only: 0, reachable, not tested: 0, " \
           "not analysed yet: 1)" in body
    assert "Modules below the goal: foo." in body and "- foo: `g[*].b` 2, `a` 1. b is a constant when P = 0." in body
    assert body.rstrip().splitlines()[-1].startswith("<!-- measured on:")


def test_reasons_name_lines_in_rtl():
    """Each entry of app/coverage_reasons.toml is in a known category and its text is in its module's
    source (an entry whose line was edited away is stale: update it with the RTL)."""
    reasons = load_reasons()
    for mod in load_toggle_notes():
        assert (ROOT / "rtl" / f"{mod}.v").is_file(), f"coverage toggle note for no module: {mod}"
    for e in reasons:
        assert e["reason"].split(":")[0] in CATEGORIES, e
        src = ROOT / "rtl" / f"{e['module']}.v"
        assert src.is_file() and e["text"] in src.read_text(), f"stale coverage reason: {e['module']}: {e['text']!r}"


def test_every_coverage_off_region_has_a_reason():
    """Every /* verilator coverage_off */ region of rtl/ has an [[excluded]] entry in
    app/coverage_reasons.toml (an exclusion needs its reason) and every entry names a region
    (a stale one fails too)."""
    regions = coverage_off_regions()
    assert regions, "no coverage_off region found in rtl/ (the parser sees none?)"
    assert exclusion_errors(regions, load_exclusions()) == []
    for e in load_exclusions():
        assert len(e["reason"]) > 20, e


def test_exclusion_check_catches_a_region_without_reason(tmp_path):
    rtl = tmp_path / "rtl"
    rtl.mkdir()
    (rtl / "foo.v").write_text("module foo;\n/* verilator coverage_off */\nreg [3:0] rom [0:3];\n"
                               "/* verilator coverage_on */\nwire a;\n// verilator coverage_off\nwire b;\n"
                               "// verilator coverage_on\nendmodule\n")
    regions = coverage_off_regions(rtl)
    assert [(r["module"], r["first"], r["last"], r["lines"]) for r in regions] == [
        ("foo", 2, 4, ["reg [3:0] rom [0:3];"]), ("foo", 6, 8, ["wire b;"])]
    rom = {"module": "foo", "text": "rom [0:3]", "reason": "a ROM."}
    errs = exclusion_errors(regions, [rom])
    assert errs == ["rtl/foo.v:6-8: coverage_off region with no [[excluded]] reason"]
    # a text outside every region (wire a is between them), or in another module: stale
    for bad in ({"module": "foo", "text": "wire a;", "reason": "x"}, {"module": "bar", "text": "wire b;", "reason": "x"}):
        errs = exclusion_errors(regions, [rom, {"module": "foo", "text": "wire b", "reason": "y"}, bad])
        assert errs == [f"[[excluded]] {bad['module']}: {bad['text']!r} is in no coverage_off region of "
                        f"rtl/{bad['module']}.v"]
    assert exclusion_errors(regions, [rom, {"module": "foo", "text": "wire b", "reason": "y"}]) == []
    (rtl / "foo.v").write_text("/* verilator coverage_off */\nwire a;\n")
    with pytest.raises(ValueError, match="never switched on again"):
        coverage_off_regions(rtl)
    (rtl / "foo.v").write_text("wire a;\n/* verilator coverage_on */\n")
    with pytest.raises(ValueError, match="coverage_on with no coverage_off"):
        coverage_off_regions(rtl)


def test_bad_reasons_file(tmp_path):
    p = tmp_path / "r.toml"
    p.write_text('[[uncovered]]\nmodule = "foo"\ntext = "x"\nreason = "because"\n')
    with pytest.raises(UserError, match="must start with one of"):
        load_reasons(p)
    p.write_text('[[uncovered]]\nmodule = "foo"\nreason = "unreachable: P = 0"\n')
    with pytest.raises(UserError, match=r"\[\[uncovered\]\] entry 1: missing text"):
        load_reasons(p)
    p.write_text('[[excluded]]\nmodule = "foo"\ntext = "rom"\n')
    with pytest.raises(UserError, match=r"\[\[excluded\]\] entry 1: missing reason"):
        load_exclusions(p)
    p.write_text('[[toggles]]\nmodule = "foo"\n')
    with pytest.raises(UserError, match=r"\[\[toggles\]\] entry 1: missing reason"):
        load_toggle_notes(p)


def test_tiny_coverage_run(tmp_path):
    """One Verilator parameter set of bitlen's testbench with coverage: merged.dat, annotated
    rtl/bitlen.v, and bitlen's figures in summary.json; --reuse summarizes it again, no test run."""
    out = tmp_path / "cov"
    args = [sys.executable, "-m", "app.coverage", "--jobs", "1", "--out", str(out), "--no-doc"]
    r = subprocess.run([*args, "--tests", "tb/bitlen/test_bitlen.py::test_bitlen_rtl[verilator-w52]"], cwd=ROOT,
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, (r.stdout + r.stderr)[-2000:]
    assert (out / "merged.dat").stat().st_size > 0
    assert (out / "annotated" / "bitlen.v").is_file() or list((out / "annotated").rglob("bitlen.v"))
    summ = json.loads((out / "summary.json").read_text())
    assert summ["runs"] == 1 and summ["pytest_status"] == 0
    assert summ["command"] == "make coverage JOBS=1 COVERAGE_TESTS=tb/bitlen/test_bitlen.py::test_bitlen_rtl[verilator-w52]"
    b = summ["modules"]["bitlen"]
    assert 0 < b["lines_pct"] <= 100 and 0 < b["toggles_pct"] <= 100 and b["lines"][1] > 0
    # the coverage_off region around g_search's scratch word v leaves no point of it (and pos has its own)
    names = {kv.get("o", "").rsplit(":", 1)[0] for kv, _ in parse_dat(out / "merged.dat")
             if kv.get("f", "").endswith("rtl/bitlen.v")}
    assert any(n.startswith("g_search.pos[") for n in names) and not any(n.startswith("g_search.v[") for n in names)
    assert summ["totals"]["lines"] == [sum(m["lines"][i] for m in summ["modules"].values()) for i in (0, 1)]
    (out / "merged.dat").unlink()
    r = subprocess.run([*args, "--reuse"], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, (r.stdout + r.stderr)[-2000:]
    again = json.loads((out / "summary.json").read_text())
    assert (out / "merged.dat").is_file() and again["modules"] == summ["modules"] and again["seconds"] == summ["seconds"]


def test_bad_tests_path_one_line_exit_2():
    r = subprocess.run([sys.executable, "-m", "app.coverage", "--tests", "tb/no_such_dir", "--no-doc"], cwd=ROOT,
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and r.stderr.strip() == "coverage: --tests tb/no_such_dir: no such file or directory"


def test_reuse_without_a_run_one_line_exit_2(tmp_path):
    r = subprocess.run([sys.executable, "-m", "app.coverage", "--reuse", "--out", str(tmp_path), "--no-doc"], cwd=ROOT,
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and r.stderr.strip().startswith("coverage: --reuse: no run to reuse in")
    assert len(r.stderr.strip().splitlines()) == 1
