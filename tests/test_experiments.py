"""synth/experiments/: a measured prototype whose gates a doc quotes must still compute what it claims.
Each experiment's Verilog (synth/experiments/<name>.v) comes with an Icarus testbench (<name>_tb.v) that
checks it against its rtl/ twin and prints "checked N of N errors 0"; CHECKS lists them (experiment ->
rtl/ module), and a test here runs each and lints it (git history: this file at stop 46). Both of issue
27's prototypes, qmac_diag_serial and sat_integral_serial, are rtl/'s now (tb/qmac_diag_serial,
tb/sat_integral_serial), so there is none today, and this test keeps it so until the next experiment
brings its check."""
from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXP = ROOT / "synth" / "experiments"
# experiment: the rtl/ module its testbench checks it against
CHECKS: dict[str, str] = {}


def test_every_experiment_is_checked():
    assert sorted(p.stem for p in EXP.glob("*.v") if not p.stem.endswith("_tb")) == sorted(CHECKS)
    assert sorted(p.stem[:-3] for p in EXP.glob("*_tb.v")) == sorted(CHECKS)
    readme = (EXP / "README.md").read_text()
    assert all(f"`{name}.v`" in readme for name in CHECKS)
