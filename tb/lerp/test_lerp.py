"""lerp (rtl/lerp.v, combinational) bit-exact against golden lerp(P_FRAC, a, b, t).

Parameter sets (W, TW, P_FRAC): noise_term's two instances (the lattice values, W = n_w,
and the gradient differences, W = n_w + 1; TW = blend_w = p_frac + 2) under full and
reduced and two random valid configurations, the smallest legal lerp (W = 2, P_FRAC = 1,
TW = 3), a wide one (W = 40, P_FRAC = 18) and t wider than needed (TW = P_FRAC + 6).
Vectors: the edges t = 0, 1 (2^P_FRAC), 1 - 2^-P_FRAC, 1/2 with a, b at the extremes of
the word (-2^(W-1), -1, 0, 1, 2^(W-1) - 1) in every pair, then VECTORS random (a, b)
uniform over the word and t uniform over [0, 2^P_FRAC].
"""
from __future__ import annotations

import itertools

import numpy as np

import cocotb

from model.hw import golden as G
from tb import pipe


def _sets():
    out = {}
    for i, (name, cfg) in enumerate(pipe.configs(1201, 1202)):
        for kind in ("nd", "nd", "n", "d")[i]:  # the lattice values (n_w) and the gradient differences (n_w + 1)
            out[f"{name}_{kind}"] = {"W": cfg.n_w + (kind == "d"), "TW": cfg.blend_w, "P_FRAC": cfg.p_frac}
    out["smallest"] = {"W": 2, "TW": 3, "P_FRAC": 1}
    out["wide"] = {"W": 40, "TW": 20, "P_FRAC": 18}
    out["wide_t"] = {"W": 9, "TW": 11, "P_FRAC": 5}
    return out


# every set under Icarus; under Verilator (a build costs 5-20 s) the widest
test_lerp_rtl = pipe.block_test("lerp", _sets(), ("wide",), __file__, sources=["lerp.v", "delay_line.v"])


@cocotb.test()
async def lerp_bit_exact(dut):
    p = pipe.block_params()
    w, pf = p["W"], p["P_FRAC"]
    r = pipe.rng(41)
    ext = [-(1 << (w - 1)), -1, 0, 1, (1 << (w - 1)) - 1]
    ts = [0, 1 << pf, (1 << pf) - 1, 1 << (pf - 1), 1]
    edge = np.array([(a, b, t) for a, b in itertools.product(ext, ext) for t in ts], dtype=np.int64)
    m = pipe.n_vectors()
    rand = np.stack([r.integers(-(1 << (w - 1)), 1 << (w - 1), m), r.integers(-(1 << (w - 1)), 1 << (w - 1), m),
                     r.integers(0, (1 << pf) + 1, m)], -1)
    v = np.concatenate([edge, rand])
    exp = G.lerp(pf, v[:, 0], v[:, 1], v[:, 2])
    assert (np.minimum(v[:, 0], v[:, 1]) <= exp).all() and (exp <= np.maximum(v[:, 0], v[:, 1])).all()

    def apply(i):
        dut.a.value = int(v[i, 0]) & ((1 << w) - 1)
        dut.b.value = int(v[i, 1]) & ((1 << w) - 1)
        dut.t.value = int(v[i, 2])

    got = await pipe.run_comb(dut, apply, lambda: pipe.to_signed(int(dut.y.value), w), len(v))
    pipe.check_equal(dut, got, exp, lambda i: f"a={v[i, 0]} b={v[i, 1]} t={v[i, 2]}", f"lerp {p}")
