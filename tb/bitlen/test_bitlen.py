"""bitlen (rtl/bitlen.v, combinational) bit-exact against golden bitlen: bl = bitlen(x),
nz = (x != 0).

Parameter sets (W, BW): filter_width's two instances (the normalising shift, W = gabs_w -
norm_bits, BW = sh_w; bitlen(r), W = r_w, BW = clog2(r_w + 1)) under full, reduced and a
random valid configuration, the smallest words (W = 1, 2), a wide one (W = 52, golden's
exact range) and an output wider than needed; each in both forms (PAR = 0, 1).
Vectors: every x when W <= 12, else 0, every 2^k - 1, 2^k, 2^k + 1, the largest word and
VECTORS random words (log-uniform: each bit length equally likely).
"""
from __future__ import annotations

import math

import numpy as np

import cocotb

from model.hw import golden as G
from tb import pipe


def _sets():
    out = {}
    for name, cfg in pipe.configs(1211):
        out[f"{name}_sh"] = {"W": cfg.gabs_w - cfg.norm_bits, "BW": cfg.sh_w}
        out[f"{name}_r"] = {"W": cfg.r_w, "BW": math.ceil(math.log2(cfg.r_w + 1))}
    out.update({"w1": {"W": 1, "BW": 1}, "w2": {"W": 2, "BW": 2}, "w52": {"W": 52, "BW": 6},
                "wide_bl": {"W": 5, "BW": 7}})
    # PAR = 1 (the parallel form, filter_width with fpga_regs): every set again
    out.update({f"{name}_par": {**p, "PAR": 1} for name, p in list(out.items())})
    return out


# every set under Icarus; under Verilator (a build costs 5-20 s) the widest
test_bitlen_rtl = pipe.block_test("bitlen", _sets(), ("w52", "w52_par"), __file__)


@cocotb.test()
async def bitlen_bit_exact(dut):
    p = pipe.block_params()
    w = p["W"]
    if w <= 12:
        x = np.arange(1 << w, dtype=np.int64)
    else:
        r = pipe.rng(43)
        k = np.arange(w + 1, dtype=np.int64)
        edge = np.concatenate([[0, (1 << w) - 1], (1 << k[:w]) - 1, 1 << k[:w], (1 << k[1:w]) + 1])
        m = pipe.n_vectors()
        rand = r.integers(0, 1 << 62, m) >> (62 - r.integers(0, w + 1, m))
        x = np.concatenate([edge, rand]) & ((1 << w) - 1)
    exp = np.stack([G.bitlen(x), (x != 0).astype(np.int64)], -1)

    def apply(i):
        dut.x.value = int(x[i])

    got = await pipe.run_comb(dut, apply, lambda: (int(dut.bl.value), int(dut.nz.value)), len(x))
    pipe.check_equal(dut, got, exp, lambda i: f"x={x[i]}", f"bitlen {p}")
