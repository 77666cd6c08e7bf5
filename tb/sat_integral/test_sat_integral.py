"""sat_integral (rtl/sat_integral.v, latency 1 + PIPE) bit-exact against golden sat_integral
with the RTL's words (d_w): p = (csat[kk-1] << XF) + fr clut[kk] mod 2^D_W, e = k q mod
2^(D_W - XF), four channels.

Parameter sets (XF, KW, QW, CS_W, D_W): colour_map's instances (KW = x_w - XF, QW =
max(8, csat_w - 8), CS_W = csat_w, D_W = d_w) under full, reduced, three random valid
configurations, the extremes of the colour-map formats (small, wide), QW wider than 8, and
reduced's with PIPE = 1 (colour_map's FPGA_REGS: latency 2).
Vectors: the edges (fr, k, q, before, clut at 0 and their extremes, first 0 and 1, the
largest p and the most negative e, which wrap mod 2^D_W / 2^TW), then VECTORS random
(each field uniform over its word); streamed with ce stalls.
"""
from __future__ import annotations

import itertools

import numpy as np

import cocotb

from model.hw import golden as G
from tb import pipe


def _sets():
    out = {name: {"XF": c.f_frac + 1, "KW": c.x_w - c.f_frac - 1, "QW": max(8, c.csat_w - 8), "CS_W": c.csat_w,
                  "D_W": c.d_w}
           for name, c in pipe.configs(1241, 1242, 1243, colour_edges=True)}
    out["wide_q"] = {"XF": 9, "KW": 12, "QW": 11, "CS_W": 19, "D_W": 30}
    out["reduced_pipe"] = {**out["reduced"], "PIPE": 1}
    return out


# every set under Icarus, two under Verilator (a build costs 5-20 s)
test_sat_integral_rtl = pipe.block_test("sat_integral", _sets(), ("full", "wide", "reduced_pipe"), __file__,
                                       sources=["sat_integral.v", "delay_line.v"])


@cocotb.test()
async def sat_integral_bit_exact(dut):
    p = pipe.block_params()
    xf, kw, qw, cs_w, d_w = p["XF"], p["KW"], p["QW"], p["CS_W"], p["D_W"]
    tw = d_w - xf
    r = pipe.rng(71)
    m = pipe.n_vectors()
    # columns: c[4], before[4], q[4], first, fr, k
    kmin, kmax = -(1 << (kw - 1)), (1 << (kw - 1)) - 1
    edge = []
    for c, b, q, first, fr, k in itertools.product((0, 255), (0, (1 << cs_w) - 1), (0, 1, (1 << qw) - 1), (0, 1),
                                                   (0, 1, (1 << xf) - 1), (kmin, -1, 0, 1, kmax)):
        edge.append([c] * 4 + [b] * 4 + [q] * 4 + [first, fr, k])
    rand = np.concatenate([r.integers(0, 256, (m, 4)), r.integers(0, 1 << cs_w, (m, 4)),
                           r.integers(0, 1 << qw, (m, 4)), r.integers(0, 2, (m, 1)), r.integers(0, 1 << xf, (m, 1)),
                           r.integers(kmin, kmax + 1, (m, 1))], axis=1)
    v = np.concatenate([np.array(edge, dtype=np.int64), rand])
    pe, ee = G.sat_integral(xf, v[:, 0:4], v[:, 4:8], v[:, 12], v[:, 13], v[:, 14], v[:, 8:12], d_w=d_w)
    exp = np.concatenate([pe, ee], axis=1)

    def apply(i):
        dut.c_in.value = pipe.pack(v[i, 0:4], 8)
        dut.before_in.value = pipe.pack(v[i, 4:8], cs_w)
        dut.q_in.value = pipe.pack(v[i, 8:12], qw)
        dut.first_in.value = int(v[i, 12])
        dut.fr_in.value = int(v[i, 13])
        dut.k_in.value = int(v[i, 14]) & ((1 << kw) - 1)

    def sample():
        return tuple(pipe.unpack(int(dut.p_out.value), d_w, 4, signed=False)
                     + pipe.unpack(int(dut.e_out.value), tw, 4, signed=False))

    await pipe.start(dut, reset=False, valid=False)
    got = await pipe.run_stream(dut, apply, sample, len(v), latency=1 + p.get("PIPE", 0), seed=int(r.integers(1 << 30)))
    pipe.check_equal(dut, got, exp, lambda i: f"inputs {v[i].tolist()}", f"sat_integral {p}")
