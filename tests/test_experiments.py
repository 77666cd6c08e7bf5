"""synth/experiments/: each experiment's Icarus testbench (the README's check) passes, and lints clean:
a measured prototype whose gates a doc quotes must still compute what it claims (qmac_diag_serial:
qmac_diag_fold's values on one multiplier; sat_integral_serial: sat_integral's, one channel a clock)."""
from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXP = ROOT / "synth" / "experiments"
# experiment: the rtl/ module its testbench checks it against
CHECKS = {"qmac_diag_serial": "qmac_diag_fold", "sat_integral_serial": "sat_integral"}


def test_every_experiment_is_checked():
    assert sorted(p.stem for p in EXP.glob("*.v") if not p.stem.endswith("_tb")) == sorted(CHECKS)
    readme = (EXP / "README.md").read_text()
    assert all(f"`{name}.v`" in readme for name in CHECKS)


@pytest.mark.parametrize("name", sorted(CHECKS))
def test_experiment_matches_its_rtl_twin(name, tmp_path):
    if not shutil.which("iverilog"):
        pytest.fail("iverilog not on PATH (make setup installs it)")
    vvp = tmp_path / f"{name}.vvp"
    subprocess.run(["iverilog", "-g2005", "-Wall", "-I", str(ROOT / "rtl"), "-o", str(vvp), str(EXP / f"{name}_tb.v"),
                    str(EXP / f"{name}.v"), str(ROOT / "rtl" / f"{CHECKS[name]}.v")], check=True, cwd=ROOT)
    out = subprocess.run(["vvp", "-n", str(vvp)], capture_output=True, text=True, check=True, cwd=ROOT).stdout
    m = re.search(r"checked (\d+) of (\d+) errors (\d+)", out)
    assert m, out
    checked, total, errors = map(int, m.groups())
    assert checked == total >= 1000 and errors == 0, out


@pytest.mark.parametrize("name", sorted(CHECKS))
def test_experiment_lints_clean(name):
    r = subprocess.run(["verilator", "--lint-only", "-Wall", "-Irtl", f"synth/experiments/{name}.v", "rtl/" + CHECKS[name] + ".v",
                        "--top-module", name], capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stderr
