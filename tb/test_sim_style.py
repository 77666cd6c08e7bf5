"""The RTL stays fast in event-driven simulators (docs/simulation.md).

Icarus turns a net driven piecewise (several continuous assigns to part-selects of one
vector, or several instance outputs into part-selects of one net) into a .concat8
functor that re-resolves the whole net bit by bit, in 8-state, on every change of any
piece: it was about half of all Icarus time on this pipeline. No module may have one.
"""
from __future__ import annotations

import shutil

import pytest

from sim.icarus_perf import census_of_config


@pytest.mark.parametrize("config", ["full", "reduced"])
def test_no_net_driven_piecewise(config):
    if shutil.which("iverilog") is None:
        pytest.fail("iverilog not found: `make setup` installs it")
    rows, nets = census_of_config(config)
    per_module = {m: r["concat8"] for m, r in rows.items() if r["concat8"]}
    assert not per_module, f"{config}: nets driven piecewise (.concat8) {dict(nets)} in modules {per_module}"
    # the census saw the whole design (a parse that finds nothing would pass vacuously)
    assert rows["noise_term"]["threads"] > 0 and rows["texture_pipeline"]["threads"] > 0
