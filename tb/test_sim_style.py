"""The RTL stays fast in event-driven simulators (docs/simulation.md): no net driven
piecewise, and no always @* block rerunning within a clock.

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
    assert not per_module and not nets, (
        f"{config}: nets driven piecewise (.concat8) {dict(nets)} in modules {per_module}")
    # the census saw the whole design (a parse that finds nothing would pass vacuously)
    assert rows["noise_term"]["threads"] > 0 and rows["axis_skid"]["threads"] > 0


# Blocks that read a combinational result computed outside them beside their registers, so
# they run again when it settles (at most twice a clock): filter_width's stage blocks read
# bitlen instances' outputs; cmap_divide's stage 6 (the normalised division, full) reads D,
# formed combinationally in cmap_sat from sat_integral's outputs, beside its own stage-5
# registers (D + w needs both in one clock). sat_integral was here too and no longer reruns.
# Full: filter_width 4.8 runs for 4 blocks, cmap_divide 2.5 for 2 (sim.icarus_perf evals).
RERUN_ALLOWED = {"filter_width", "cmap_divide"}


@pytest.mark.parametrize("config", ["full", "reduced"])
def test_always_blocks_run_once_a_clock(config):
    """Icarus runs an always @* block again whenever an input changes after it ran; a block
    fed by another block's result in the same clock runs twice. Each block instance may run
    at most once a pixel (twice for RERUN_ALLOWED), counted by sim.icarus_perf.evals."""
    if shutil.which("iverilog") is None:
        pytest.fail("iverilog not found: `make setup` installs it")
    from sim.icarus_perf import evals

    rows = evals(config, 512)
    assert rows["lerp"]["instances"] > 0 and rows["lerp"]["evals_per_pixel"] > 0  # counted at all
    over = {m: r for m, r in rows.items()
            if r["evals_per_pixel"] > r["instances"] * (2 if m in RERUN_ALLOWED else 1)}
    assert not over, f"{config}: always @* blocks rerun within a clock: {over}"
