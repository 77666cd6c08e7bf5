"""Self-test of the gate-count flow synth/synth.py (needs Yosys, except the
missing-Yosys test).  Run: .venv/bin/python -m pytest synth/selftest -q"""

import json
import os
import re
import shutil
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
SYNTH = os.path.join(os.path.dirname(HERE), "synth.py")
LIB = os.path.join(os.path.dirname(HERE), "cells.lib")
ADDER = os.path.join(HERE, "adder_tree.v")
RAM = os.path.join(HERE, "ram16.v")

HAVE_YOSYS = shutil.which(os.environ.get("YOSYS") or "yosys") is not None
needs_yosys = pytest.mark.skipif(not HAVE_YOSYS, reason="yosys not installed")


def run_synth(*args, env=None):
    proc = subprocess.run([sys.executable, SYNTH] + list(args), env=env,
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True, timeout=300)
    return proc


def synth_json(*args):
    proc = run_synth(*args)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def lib_area(cell):
    text = open(LIB).read()
    m = re.search(r"cell\(%s\)\s*\{\s*area\s*:\s*([0-9.]+)" % cell, text)
    return float(m.group(1))


@pytest.fixture(scope="module")
def adder8(tmp_path_factory):
    out = tmp_path_factory.mktemp("synth") / "adder8.json"
    res = synth_json("--top", "adder_tree", "--files", ADDER,
                     "--blocks", "u_ab=pair_ab", "u_cd", "--json", str(out))
    assert json.loads(out.read_text()) == res
    return res


@needs_yosys
def test_keys(adder8):
    for k in ("top", "yosys_version", "ge_total", "ge_comb", "ge_seq", "storage_bits",
              "transistors_cmos", "ge_cmos_crosscheck", "logic_depth", "cells", "blocks",
              "seconds"):
        assert k in adder8, k
    assert adder8["top"] == "adder_tree"
    assert adder8["yosys_version"].startswith("Yosys")


@needs_yosys
def test_totals(adder8):
    r = adder8
    assert r["ge_total"] > 0
    assert abs(r["ge_comb"] + r["ge_seq"] - r["ge_total"]) < 0.01
    # 10 output flops (W+2 bits), sync reset folded into logic before a plain DFF
    assert r["cells"].get("DFF") == 10
    assert abs(r["ge_seq"] - 10 * lib_area("DFF")) < 0.01
    assert r["storage_bits"] == 0
    assert r["unmapped_cells"] == {}
    # the GE total is the sum of the cell histogram weighted by the liberty areas
    total = sum(n * lib_area(c) for c, n in r["cells"].items())
    assert abs(total - r["ge_total"]) < 0.01


@needs_yosys
def test_cmos_crosscheck(adder8):
    r = adder8
    assert r["transistors_cmos"] > 0
    assert r["ge_cmos_crosscheck"] == pytest.approx(r["transistors_cmos"] / 4, abs=0.01)
    # same order of magnitude as the liberty GE
    assert 0.5 < r["ge_cmos_crosscheck"] / r["ge_total"] < 3


@needs_yosys
def test_logic_depth(adder8):
    # two ripple-ish 8-bit additions in series: well over a handful of cells
    assert adder8["logic_depth"] >= 4


@needs_yosys
def test_blocks(adder8):
    b = adder8["blocks"]
    assert set(b) == {"pair_ab", "u_cd"}
    assert 0 < b["pair_ab"] < adder8["ge_total"]
    assert b["pair_ab"] == b["u_cd"]          # same module, counted per instance
    assert b["pair_ab"] + b["u_cd"] < adder8["ge_total"]
    assert adder8["blocks_detail"]["pair_ab"]["ge_seq"] == 0


@needs_yosys
def test_monotonic_in_width(adder8):
    r4 = synth_json("--top", "adder_tree", "--files", ADDER, "--param", "W=4")
    assert r4["cells"].get("DFF") == 6
    assert 0 < r4["ge_total"] < adder8["ge_total"]
    r8 = synth_json("--top", "adder_tree", "--files", ADDER)   # flat, no blocks
    assert r8["ge_total"] > r4["ge_total"]
    assert r8["logic_depth"] > r4["logic_depth"]


@needs_yosys
def test_storage_macro_vs_flops():
    macro = synth_json("--top", "ram16", "--files", RAM)
    flops = synth_json("--top", "ram16", "--files", RAM, "--memories", "flops")
    assert macro["storage_bits"] == 128 and flops["storage_bits"] == 128
    assert macro["ram_macros"] == {"$mem_v2": 1}
    assert macro["cells"].get("DFF", 0) == 0
    assert flops["cells"].get("DFF", 0) == 128
    assert flops["ge_total"] > macro["ge_total"] + 128 * lib_area("DFF") - 0.01


@needs_yosys
def test_bad_block_name():
    proc = run_synth("--top", "adder_tree", "--files", ADDER, "--blocks", "u_nope=x")
    assert proc.returncode == 1
    assert "u_nope" in proc.stderr


def test_missing_yosys():
    env = dict(os.environ, YOSYS="/nonexistent")
    proc = run_synth("--top", "adder_tree", "--files", ADDER, env=env)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr == "synth: yosys not found (install Debian package yosys: make setup)\n"
