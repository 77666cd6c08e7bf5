"""make coverage (app/coverage.py, issue 29): the coverage file's parser and per-module sums on
a written example, and a tiny run (one block testbench under Verilator with COVERAGE=1) that
must leave the merged file, the annotated sources and a summary whose figures parse."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from app.coverage import doc_body, parse_dat, summarize

ROOT = Path(__file__).resolve().parents[1]


def _point(f, line, page, o, n, h="top.u"):
    kv = {"f": f, "l": str(line), "n": "1", "page": page, "o": o, "h": h}
    return "C '" + "".join(f"\x01{k}\x02{v}" for k, v in kv.items()) + f"' {n}\n"


def test_parse_and_summarize(tmp_path):
    dat = tmp_path / "x.dat"
    dat.write_text("# SystemC::Coverage-3\n"
                   + _point("rtl/foo.v", 10, "v_line/foo", "block", 3)
                   + _point("rtl/foo.v", 12, "v_line/foo", "block", 0)
                   + _point("rtl/foo.v", 12, "v_line/foo", "block", 2, h="top.v")  # another instance hit it
                   + _point("rtl/foo.v", 14, "v_branch/foo", "if", 0)
                   + _point("rtl/foo.v", 5, "v_toggle/foo", "a[0]", 1)
                   + _point("rtl/foo.v", 5, "v_toggle/foo", "a[1]", 0)
                   + _point("sim/frame_tb.v", 3, "v_line/frame_tb", "block", 0))  # not rtl/: left out
    pts = parse_dat(dat)
    assert len(pts) == 7 and pts[0][0]["f"] == "rtl/foo.v" and pts[0][1] == 3
    s = summarize(pts)
    assert list(s) == ["foo"]
    assert s["foo"]["lines"] == [2, 3] and s["foo"]["uncovered_lines"] == [14]
    assert s["foo"]["toggles"] == [1, 2] and s["foo"]["toggles_pct"] == 50.0
    body = doc_body({"tests": ["tb/x"], "runs": 1, "seconds": 1.0, "pytest_status": 0, "modules": s})
    assert "| foo | 2/3 | 66.7 | 1/2 | 50.0 | no |" in body and "`foo.v:14`" in body
    assert body.rstrip().splitlines()[-1].startswith("<!-- measured on:")


def test_tiny_coverage_run(tmp_path):
    """One Verilator parameter set of bitlen's testbench with coverage: merged.dat, annotated
    rtl/bitlen.v, and bitlen's figures in summary.json."""
    out = tmp_path / "cov"
    r = subprocess.run([sys.executable, "-m", "app.coverage", "--tests",
                        "tb/bitlen/test_bitlen.py::test_bitlen_rtl[verilator-w52]", "--jobs", "1", "--out", str(out),
                        "--no-doc"], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, (r.stdout + r.stderr)[-2000:]
    assert (out / "merged.dat").stat().st_size > 0
    assert (out / "annotated" / "bitlen.v").is_file() or list((out / "annotated").rglob("bitlen.v"))
    summ = json.loads((out / "summary.json").read_text())
    assert summ["runs"] == 1 and summ["pytest_status"] == 0
    b = summ["modules"]["bitlen"]
    assert 0 < b["lines_pct"] <= 100 and 0 < b["toggles_pct"] <= 100 and b["lines"][1] > 0


def test_bad_tests_path_one_line_exit_2():
    r = subprocess.run([sys.executable, "-m", "app.coverage", "--tests", "tb/no_such_dir", "--no-doc"], cwd=ROOT,
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and r.stderr.strip() == "coverage: --tests tb/no_such_dir: no such file or directory"
