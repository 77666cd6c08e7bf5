"""isqrt: r = floor(sqrt(l)) bit-exact against Python's math.isqrt (and golden isqrt).

Two kinds of build:
- test_isqrt_rtl(sim, config): the widths filter_width uses (L_W = l_w,
  R_W = r_w, LATENCY = `LAT_FILTER_WIDTH - 5, hdlbuild.block_params): n_vectors() random radicands
  (a share uniform over the whole input word, a share small, a share near perfect
  squares) plus the edges: 0..15, every power of two and its neighbours, k^2 - 1,
  k^2, k^2 + 1 for the largest roots, the largest radicand filter_width produces
  (2 (2^norm_bits - 1)^2) and the largest the word holds.
- test_isqrt_small_rtl(sim, variant): small parametrized builds, every radicand
  of the word (exhaustive), for one result bit per stage, an uneven split of the
  iterations, an odd L_W and an output wider than needed.
"""
from __future__ import annotations

import math
import os

import numpy as np
import pytest

import cocotb

import hdlbuild
from model.hw import golden as G
from tb import pipe

SOURCES = ["isqrt.v"]

# (L_W, R_W, LATENCY) of the exhaustive small builds: one result bit per stage; an odd
# L_W, a result word wider than needed and an uneven split of the iterations over the stages;
# the smallest legal root (R_W = 3, filter_width needs 3 stages) and one stage for all the
# iterations
SMALL = [(12, 6, 6), (11, 7, 2), (6, 3, 1), (9, 5, 1)]


def sqrt_latency() -> int:
    """The isqrt stages inside filter_width: `LAT_FILTER_WIDTH - 5 (with or without fpga_regs)."""
    return hdlbuild.latency("filter_width") - 5


@pytest.mark.parametrize("sim,config", hdlbuild.sim_params())
def test_isqrt_rtl(sim, config):
    cfg = hdlbuild.config_of(config)
    lat = sqrt_latency()
    pipe.run_block("isqrt", sim, test_file=__file__, config=config, sources=SOURCES,
                   extra_env={"ISQRT_L_W": str(cfg.l_w), "ISQRT_R_W": str(cfg.r_w), "ISQRT_LAT": str(lat),
                             "ISQRT_EXHAUSTIVE": "0"})


def test_isqrt_check():
    """isqrt's elaboration-time check (g_bad_params) both ways on full's parameters (L_W 25, R_W 13,
    LATENCY 3): refused with each term alone true (X_W = 2 R_W = 26 < L_W 27; LATENCY 0 < 1;
    LATENCY 14 > R_W); accepted at each edge (2 R_W = L_W 26; LATENCY 1; LATENCY = R_W 13)."""
    b = hdlbuild.block_params(hdlbuild.config_of("full"), "isqrt")
    r_w = b["R_W"]
    hdlbuild.check_refusals(
        "isqrt", SOURCES, b,
        accept={"full": {}, "2 R_W = L_W": {"L_W": 2 * r_w}, "LATENCY 1": {"LATENCY": 1},
                "LATENCY = R_W": {"LATENCY": r_w}},
        refuse={"2 R_W < L_W": {"L_W": 2 * r_w + 1}, "LATENCY < 1": {"LATENCY": 0},
                "LATENCY > R_W": {"LATENCY": r_w + 1}},
        error_module="isqrt_needs_2_r_w_ge_l_w_and_1_le_latency_le_r_w")


RANDOM_SEEDS = (1271, 1272, 1273)  # random valid configurations: filter_width's isqrt (Icarus)


@pytest.mark.parametrize("sim,name,params", pipe.block_cases(
    {f"random{s}": hdlbuild.block_params(hdlbuild.config_of(f"random:{s}"), "isqrt") for s in RANDOM_SEEDS}))
def test_isqrt_random_rtl(sim, name, params):
    """filter_width's isqrt under random valid configurations (random vectors and edges)."""
    pipe.run_block("isqrt", sim, name, params, __file__, extra_env={
        "ISQRT_L_W": str(params["L_W"]), "ISQRT_R_W": str(params["R_W"]), "ISQRT_LAT": str(params["LATENCY"]),
        "ISQRT_EXHAUSTIVE": "0"})


def small_params():
    """(sim, variant) pairs, narrowed by SIM=: the first variant on every simulator, the
    others on Icarus only (a Verilator build costs more than the exhaustive run)."""
    sims = sorted({s for s, _ in hdlbuild.sim_params()})
    return [pytest.param(s, v, id=f"{s}-L{v[0]}R{v[1]}P{v[2]}") for i, v in enumerate(SMALL) for s in sims
            if i == 0 or s == "icarus"]


@pytest.mark.parametrize("sim,variant", small_params())
def test_isqrt_small_rtl(sim, variant):
    """Exhaustive small builds, each in its own build directory (build_name)."""
    l_w, r_w, lat = variant
    pipe.run_block("isqrt", sim, f"L{l_w}R{r_w}P{lat}", {"L_W": l_w, "R_W": r_w, "LATENCY": lat}, __file__,
                   sources=SOURCES, extra_env={"ISQRT_L_W": str(l_w), "ISQRT_R_W": str(r_w), "ISQRT_LAT": str(lat),
                                               "ISQRT_EXHAUSTIVE": "1"})


# ---------------------------------------------------------------------------
# Stimulus


def build_vectors(l_w, r_w, exhaustive, r, n_random, norm_bits):
    top = (1 << l_w) - 1
    if exhaustive:
        v = list(range(top + 1))
        r.shuffle(v)
        return v, len(v)
    edges = set(range(16))
    for k in range(l_w):
        edges |= {(1 << k) - 1, 1 << k, (1 << k) + 1}
    kmax = math.isqrt(top)
    for k in list(range(max(0, kmax - 8), kmax + 1)) + [1 << (r_w - 1), (1 << (r_w - 1)) - 1]:
        edges |= {k * k - 1, k * k, k * k + 1, (k + 1) * (k + 1) - 1}
    edges |= {top, top - 1, 2 * ((1 << norm_bits) - 1) ** 2, 2 * ((1 << norm_bits) - 1) ** 2 - 1}
    v = sorted(x for x in edges if 0 <= x <= top)
    n_hard = len(v)
    m = n_random
    kind = r.integers(0, 3, m)
    full = r.integers(0, top + 1, m, dtype=np.int64)
    small = r.integers(0, min(top, 1 << 12) + 1, m, dtype=np.int64)
    k = r.integers(0, kmax + 1, m, dtype=np.int64)
    near = np.clip(k * k + r.integers(-2, 3, m), 0, top)
    v += [int(x) for x in np.where(kind == 0, full, np.where(kind == 1, small, near))]
    return v, n_hard


# ---------------------------------------------------------------------------
# cocotb tests


def params():
    return (int(os.environ["ISQRT_L_W"]), int(os.environ["ISQRT_R_W"]), int(os.environ["ISQRT_LAT"]),
            os.environ.get("ISQRT_EXHAUSTIVE") == "1")


@cocotb.test()
async def reset_outputs(dut):
    """After reset: out_valid = 0 and every output bit 0 (no X)."""
    _, r_w, _, _ = params()
    await pipe.start(dut)
    assert str(dut.out_valid.value) == "0"
    assert str(dut.r_out.value) == "0" * r_w, f"r_out after reset: {dut.r_out.value}"


@cocotb.test()
async def vectors_bit_exact(dut):
    """Edges plus random radicands (or every radicand), streamed with stalls and gaps."""
    l_w, r_w, lat, exhaustive = params()
    cfg = pipe.cfg()
    r = pipe.rng(31)
    v, n_hard = build_vectors(l_w, r_w, exhaustive, r, pipe.n_vectors(), cfg.norm_bits)
    n = len(v)
    exp = [math.isqrt(x) for x in v]
    gold = G.isqrt(np.array(v, dtype=np.int64))
    assert (gold == np.array(exp, dtype=np.int64)).all(), "golden isqrt differs from math.isqrt"
    assert max(exp) < (1 << r_w), "a root does not fit R_W"
    dut._log.info(f"isqrt L_W={l_w} R_W={r_w} LATENCY={lat}: {n} vectors "
                  f"({'exhaustive' if exhaustive else f'{n_hard} edges'})")

    def apply(i):
        dut.l_in.value = v[i]

    def sample():
        return int(dut.r_out.value)

    await pipe.start(dut)
    got = await pipe.run_vectors(dut, apply, sample, n, latency=lat, seed=int(os.environ.get("SEED", "1")))
    bad = [i for i in range(n) if got[i] != exp[i]]
    for i in bad[:10]:
        dut._log.error(f"vector {i}: l={v[i]}: expected r={exp[i]}, got r={got[i]}")
    assert not bad, f"{len(bad)} of {n} vectors differ from math.isqrt (first at {bad[0]})"
