"""Several texture passes in one simulator run (sim/frame_rtl.py run_passes_rtl, sim/frame_tb.v
segments): the run plan (plan_runs: passes packed in order into the fewest runs the harness
memories allow, a pass cut where a run fills), and the RTL under Verilator on passes split
across runs and gathered into one, every pass's colours bit-exact against the golden model."""
from __future__ import annotations

import math
import os
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from model.hw.config import clocks_per_pixel, load_config
from model.hw.golden import MODE_CLAMP, MODE_MOD, texture_pipeline
from sim import frame_rtl as F


def _check_plan(sizes, runs, max_pix, max_wr, max_seg):
    """Every pass's pixels covered once, in order, by its segments; every run within the limits."""
    covered = {i: [] for i in range(len(sizes))}
    order = [seg for run in runs for seg in run]
    assert order == sorted(order), f"segments out of order: {order}"
    for run in runs:
        assert run, "an empty run"
        assert sum(b - a for _, a, b in run) <= max_pix and len(run) <= max_seg
        assert sum(sizes[i][0] for i, _, _ in run) <= max_wr
        for i, a, b in run:
            assert a < b, f"an empty segment {(i, a, b)}"
            covered[i].append((a, b))
    for i, (_, npix) in enumerate(sizes):
        ends = [0] + [b for _, b in covered[i]]
        assert [a for a, _ in covered[i]] == ends[:-1] and ends[-1] == npix, f"pass {i}: {covered[i]} of {npix}"


def test_plan_packs_passes_into_fewest_runs():
    # everything fits: one run, every pass whole, the empty pass left out
    assert F.plan_runs([(30, 100), (30, 0), (30, 50)], 1000, 100, 10) == [[(0, 0, 100), (2, 0, 50)]]
    # pixels bind: a pass cut where the run fills, its rest in the next run (its writes again)
    assert F.plan_runs([(5, 300), (5, 900), (5, 250)], 1000, 100, 10) == [
        [(0, 0, 300), (1, 0, 700)], [(1, 700, 900), (2, 0, 250)]]
    # a pass longer than a run: in pieces of a whole run
    assert F.plan_runs([(5, 2500)], 1000, 100, 10) == [[(0, 0, 1000)], [(0, 1000, 2000)], [(0, 2000, 2500)]]
    # writes bind: two passes a run
    assert F.plan_runs([(40, 10)] * 5, 1000, 80, 10) == [[(0, 0, 10), (1, 0, 10)], [(2, 0, 10), (3, 0, 10)],
                                                         [(4, 0, 10)]]
    # passes a run bind
    assert F.plan_runs([(1, 10)] * 3, 1000, 100, 2) == [[(0, 0, 10), (1, 0, 10)], [(2, 0, 10)]]
    assert F.plan_runs([(1, 0)], 10, 10, 10) == []
    with pytest.raises(ValueError, match="pass 1: 101 parameter writes: a run takes at most 100"):
        F.plan_runs([(5, 10), (101, 10)], 1000, 100, 10)


@given(st.lists(st.tuples(st.integers(0, 40), st.integers(0, 300)), max_size=12),
       st.integers(1, 400), st.integers(40, 600), st.integers(1, 13))
def test_plan_covers_every_pixel_within_limits(sizes, max_pix, max_wr, max_seg):
    runs = F.plan_runs(sizes, max_pix, max_wr, max_seg)
    _check_plan(sizes, runs, max_pix, max_wr, max_seg)
    fewest = math.ceil(sum(n for _, n in sizes) / max_pix)
    assert len(runs) >= fewest
    # neither writes (at most 40 a segment) nor segments (at most one a pass in a run) bind: only
    # the pixels do, and every run but the last is full
    if max_wr >= 40 * max_seg and max_seg >= len(sizes):
        assert len(runs) == fewest, runs


def _passes(cfg, sizes, seed):
    """Distinct passes (colour table, filter, mode and offsets differ): (texint, s, Jm, je) each."""
    r = np.random.default_rng(seed)
    out = []
    for i, n in enumerate(sizes):
        tex, s, Jm, je = F.synthetic_pass(cfg.name, max(n, 1), seed=seed + i)
        clut = r.integers(0, 256, size=tex.clut.shape, dtype=np.int64)
        tex = replace(tex, clut=clut, csat=None, mip=None, filter=bool(i % 2 == 0),
                      mode=MODE_MOD if i % 3 else MODE_CLAMP)
        out.append((tex, s[:n], Jm[:n], je[:n]))
    return out


def test_passes_split_across_runs_and_in_one_run_are_bit_exact():
    """Passes of 300, 0, 900, 250 and 100 pixels, split at 1000 pixels and 2 passes a run (three
    runs: a pass cut across two, random gaps and stalls), then all in one run: every pass's
    colours equal the golden model's, and the counted simulator starts are the planned runs; then
    cut for 3 simulator processes at once (procs=3: 3 runs of 517 pixels or fewer, the pool's wall
    time reported), the same colours."""
    cfg = load_config("full")
    seed = int(os.environ.get("SEED", "5"))
    sizes = [300, 0, 900, 250, 100]
    passes = _passes(cfg, sizes, seed)
    gold = [texture_pipeline(cfg, *p).astype(np.uint8) for p in passes]
    limits = {"MAX_PIX": 1000, "MAX_SEG": 2}
    nwr = len(F.write_sequence(cfg, passes[0][0]))
    plan = F.plan_runs([(nwr, n) for n in sizes], 1000, F.memory("verilator")["MAX_WR"], 2)
    assert len(plan) == 3 and (2, 0, 700) in plan[0] and (2, 700, 900) in plan[1]
    for lim, gaps, starts, procs in ((limits, 20, 3, 1), (None, 0, 1, 1), (None, 10, 3, 3)):
        before = F.STARTS
        got, info = F.run_passes_rtl(cfg, "verilator", passes, gaps=gaps, stalls=gaps, seed=seed,
                                     return_stats=True, limits=lim, procs=procs)
        assert info["starts"] == starts == F.STARTS - before == len(info["runs"]) and info["procs"] == procs
        if procs > 1:  # runs of ceil(1550 / 3) pixels at most, at once: the pool's wall time is below their sum
            assert len(F.plan_runs([(nwr, n) for n in sizes], 517, F.memory("verilator")["MAX_WR"], 4096)) == 3
            assert 0 < info["seconds"] < sum(st["run_seconds"] for st in info["runs"])
        assert [len(g) for g in got] == sizes
        for i, (g, e) in enumerate(zip(got, gold)):
            bad = np.nonzero(np.any(g != e, axis=-1))[0]
            assert bad.size == 0, f"limits {lim}: pass {i}: {bad.size} of {sizes[i]} pixels differ, first {bad[:5]}"
        assert [c > 0 for c in info["cycles"]] == [n > 0 for n in sizes], info["cycles"]
        if not gaps:  # clocks_per_pixel clocks a pixel, pass by pass
            p = [clocks_per_pixel(cfg, t.k_used) for t, *_ in passes]
            assert all(k * n <= c < k * n + 100 for c, n, k in zip(info["cycles"], sizes, p) if n), info["cycles"]


def test_nba_only_where_clk_is_the_one_trigger(tmp_path):
    """tick() runs the scheduler's NBA region alone only in a model whose one trigger is clk's rising edge
    (sim/frame_main.cpp): a build records its triggers, and a run of a model with another (a gate-level
    netlist's trigger on a register's changes) or of a build without the record gets +NBA_ONLY=0; a model
    without clk's trigger fails its build in one line naming what it found."""
    cfg = load_config("compact")
    header = tmp_path / f"V{F.TOPLEVEL}___024root.h"
    assert F.nba_only_plusargs(tmp_path) == ["+NBA_ONLY=0"]  # no record
    header.write_text(f"    CData/*0:0*/ {F.CLK_TRIGGER};\n")
    F._record_triggers(cfg, tmp_path)
    assert F.nba_only_plusargs(tmp_path) == []
    other = "__Vtrigprevexpr___TOP__frame_tb__DOT__u_pipe__DOT__v_reg__1"
    header.write_text(f"    CData/*0:0*/ {F.CLK_TRIGGER};\n    VlWide<4>/*127:0*/ {other};\n")
    F._record_triggers(cfg, tmp_path)
    assert F.nba_only_plusargs(tmp_path) == ["+NBA_ONLY=0"]
    header.write_text(f"    CData/*0:0*/ {other};\n")
    with pytest.raises(F.FrameRunError, match=r"frame_tb \[compact verilator\]: no trigger .*clk__0 .*v_reg__1"):
        F._record_triggers(cfg, tmp_path)


def test_rtl_only_options_not_in_netlist_or_coverage_builds(monkeypatch):
    """-fdfg-synthesize-all (RTL_ONLY_ARGS) verilates the RTL's frame harness, not the netlists' build nor a
    coverage build (sim/frame_rtl.py verilator_args)."""
    monkeypatch.delenv("COVERAGE", raising=False)
    assert F.RTL_ONLY_ARGS and all(a in F.verilator_args() for a in F.RTL_ONLY_ARGS)
    netlist = F.verilator_args(netlists=["netlist.v"])
    assert not set(F.RTL_ONLY_ARGS) & set(netlist) and netlist == [a for a in F.VERILATOR_ARGS if a not in F.RTL_ONLY_ARGS]
    monkeypatch.setenv("COVERAGE", "1")
    assert not set(F.RTL_ONLY_ARGS) & set(F.verilator_args())


def test_wipe_build_keeps_only_the_runs(tmp_path):
    """A stale build directory is emptied before the rebuild (a killed build's precompiled
    header would be trusted), but for runs/, the kept failed runs."""
    (tmp_path / "Vtop__pch.h.fast.gch").write_bytes(b"cut short")
    (tmp_path / "obj").mkdir()
    (tmp_path / "obj" / "Vtop.o").write_bytes(b"")
    (tmp_path / "build.stamp").write_text("old")
    (tmp_path / "runs" / "run-1-0").mkdir(parents=True)
    (tmp_path / "runs" / "run-1-0" / "sim.log").write_text("kept")
    F.wipe_build(tmp_path)
    assert [p.name for p in tmp_path.iterdir()] == ["runs"]
    assert (tmp_path / "runs" / "run-1-0" / "sim.log").read_text() == "kept"


@pytest.mark.parametrize("config", ["compact", "full"])
def test_harness_modes_same_colours(config, monkeypatch):
    """sim/frame_main.cpp's speed-ups change no colour and no clock: tick() skips the falling edge's
    evaluation (every process is clocked on the rising edge; +FALL_EVAL=1 evaluates it), runs the
    scheduler's NBA region alone at a rising edge where rst did not change (+NBA_ONLY=0 runs its
    whole loop; the mid-stream reset exercises both) and huge_text moves the executable's code and tables into huge pages (+HUGE_TEXT=0 leaves them; the
    default moves every read-only segment, 2 MiB-aligned by the link: HUGE_ARGS). Each mode gives the
    golden model's colours and the same clock count, with input gaps, output stalls and a reset in
    the middle of the stream (compact: five clocks a pixel, full: one)."""
    tex, s, Jm, je = F.synthetic_pass(config, 400, seed=3)
    cfg = load_config(config)
    exp = texture_pipeline(cfg, tex, s, Jm, je).astype(np.uint8)
    reset_at = len(F.write_sequence(cfg, tex)) + 300  # its parameter writes, then 300 clocks of the stream
    runs = {}
    for plus in ([], ["+FALL_EVAL=1"], ["+NBA_ONLY=0"], ["+HUGE_TEXT=0"]):
        monkeypatch.setattr(F, "RUN_PLUSARGS", plus)
        rgba, cycles, _, stats = F.run_frame_rtl(config, "verilator", tex, s, Jm, je, gaps=15, stalls=15, seed=4,
                                                 reset_at=reset_at, return_stats=True)
        bad = np.nonzero(np.any(rgba != exp, axis=-1))[0]
        assert bad.size == 0, f"{plus}: {bad.size} of 400 pixels differ, first {bad[:5]}"
        runs[tuple(plus)] = (cycles, tuple(st.get("total_cycles") for st in stats))
        huge = [st["huge_text_bytes"] for st in stats]
        # code, constant tables and headers: at least two 2 MiB segments moved, none with +HUGE_TEXT=0
        assert all(h == 0 for h in huge) if plus == ["+HUGE_TEXT=0"] else all(h >= 2 << 21 for h in huge), (plus, huge)
    assert len(set(runs.values())) == 1, runs
