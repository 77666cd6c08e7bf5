"""noise_blend (rtl/noise_blend.v, combinational) bit-exact against golden noise_blend:
w, dw of a cell fraction fp, linear or cubic.

Parameter sets (BLEND, P_FRAC, BW): noise_term's instance (BW = blend_w = p_frac + 2)
under full (cubic), reduced (linear) and two random valid configurations, the smallest
legal (P_FRAC = 2, both blends; at P_FRAC = 1 the cubic slope reaches 3.0), a wide cubic
(P_FRAC = 20) and w, dw wider than needed.
Vectors: every fp when P_FRAC <= 12, else the edges fp = 0, 2^-P_FRAC, 1/2, 1 - 2^-P_FRAC
(where 3 f2 - 2 f3 reaches 1) and their neighbours, and VECTORS random fractions.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

import cocotb

from hdlbuild.params import ENUMS
from model.hw import golden as G
from tb import pipe

BLENDS = {v: k for k, v in ENUMS["blend"].items()}


def _sets():
    out = {}
    for name, cfg in pipe.configs(1221, 1222):
        out[name] = {"BLEND": ENUMS["blend"][cfg.blend], "P_FRAC": cfg.p_frac, "BW": cfg.blend_w}
    out.update({"cubic2": {"BLEND": 1, "P_FRAC": 2, "BW": 4}, "linear2": {"BLEND": 0, "P_FRAC": 2, "BW": 4},
                "cubic20": {"BLEND": 1, "P_FRAC": 20, "BW": 22}, "wide_w": {"BLEND": 1, "P_FRAC": 6, "BW": 12}})
    return out


# every set under Icarus; under Verilator (a build costs 5-20 s) the widest
test_noise_blend_rtl = pipe.block_test("noise_blend", _sets(), ("cubic20",), __file__,
                                      sources=["noise_blend.v", "delay_line.v"])


@cocotb.test()
async def noise_blend_bit_exact(dut):
    p = pipe.block_params()
    pf, bw = p["P_FRAC"], p["BW"]
    top = (1 << pf) - 1
    if pf <= 12:
        fp = np.arange(top + 1, dtype=np.int64)
    else:
        edge = np.array([0, 1, 2, top >> 1, (top >> 1) + 1, top - 1, top], dtype=np.int64)
        fp = np.concatenate([edge, pipe.rng(47).integers(0, top + 1, pipe.n_vectors())])
    w, dw = G.noise_blend(SimpleNamespace(blend=BLENDS[p["BLEND"]], p_frac=pf), fp)
    exp = np.stack([w, dw], -1)

    def apply(i):
        dut.fp.value = int(fp[i])

    got = await pipe.run_comb(dut, apply, lambda: (pipe.to_signed(int(dut.w.value), bw),
                                                   pipe.to_signed(int(dut.dw.value), bw)), len(fp))
    pipe.check_equal(dut, got, exp, lambda i: f"fp={fp[i]}", f"noise_blend {p}")
