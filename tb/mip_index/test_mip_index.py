"""mip_index (rtl/mip_index.v, latency 2) bit-exact against golden mip_index: the MIP
level's address of a colour index u for a filter width w, and use_mip.

Parameter sets (FILTER, U_W, W_W, FF, NMAX, NL_W): colour_map's instance (U_W = u_w,
W_W = w_w, FF = f_frac) under full and reduced (their formats with the mip filter), three
random valid configurations, the extremes of the colour-map formats (small, wide), and
FILTER = 0 (point lookup only) for full's and the small formats.
Vectors: for every n_log2 in 0..NMAX, both modes and filter_en 0/1: u at 0, N, crossing
the edges (floor(u) = -N-1, -1, 0, N-1, N, 2N) and at the extremes of the word, with w = 0,
2^l entries and 2^l entries - 2^-FF for every level l up to NMAX + 1, and the largest w;
then VECTORS random; streamed with ce stalls.
"""
from __future__ import annotations

import itertools

import numpy as np

import cocotb

from model.hw import golden as G
from tb import pipe


def _params(c, filter_):
    return {"FILTER": filter_, "U_W": c.u_w, "W_W": c.w_w, "FF": c.f_frac, "NMAX": c.n_log2_max, "NL_W": c.n_log2_w}


def _sets():
    cs = dict(pipe.configs(1251, 1252, 1253, colour_edges=True))
    out = {name: _params(c, 2) for name, c in cs.items()}
    out.update({"full_point": _params(cs["full"], 0), "small_point": _params(cs["small"], 0)})
    return out


# every set under Icarus, two under Verilator (a build costs 5-20 s)
test_mip_index_rtl = pipe.block_test("mip_index", _sets(), ("full", "full_point"), __file__)


@cocotb.test()
async def mip_index_bit_exact(dut):
    p = pipe.block_params()
    filt, u_w, w_w, ff, nmax = p["FILTER"], p["U_W"], p["W_W"], p["FF"], p["NMAX"]
    r = pipe.rng(81)
    umin, umax = -(1 << (u_w - 1)), (1 << (u_w - 1)) - 1
    ws = {0, (1 << w_w) - 1} | {(1 << (l + ff)) - d for l in range(nmax + 2) for d in (0, 1)}
    ws = sorted(x for x in ws if 0 <= x < (1 << w_w))
    rows = []
    for n_log2, mode, en in itertools.product(range(nmax + 1), (0, 1), (0, 1)):
        n = 1 << n_log2
        us = {umin, umax} | {(k << ff) + f for k in (-n - 1, -1, 0, n - 1, n, 2 * n) for f in (0, (1 << ff) - 1)}
        for u, w in itertools.product(sorted(x for x in us if umin <= x <= umax), ws):
            rows.append((u, w, mode, n_log2, en))
    m = pipe.n_vectors()
    near = r.integers(-(4 << (nmax + ff)), 4 << (nmax + ff), m)
    u = np.clip(np.where(r.random(m) < 0.5, near, r.integers(umin, umax + 1, m)), umin, umax)
    w = r.integers(0, 1 << 62, m) >> (62 - r.integers(0, w_w + 1, m))  # log-uniform: every level
    rand = np.stack([u, w, r.integers(0, 2, m), r.integers(0, nmax + 1, m), r.integers(0, 2, m)], -1)
    v = np.concatenate([np.array(rows, dtype=np.int64), rand])
    addr, use = G.mip_index(filt, ff, nmax, v[:, 0], v[:, 1], v[:, 2], v[:, 3], v[:, 4])
    exp = np.stack([addr, use], -1)

    def apply(i):
        dut.u_in.value = int(v[i, 0]) & ((1 << u_w) - 1)
        dut.w_in.value = int(v[i, 1])
        dut.mode.value = int(v[i, 2])
        dut.n_log2.value = int(v[i, 3])
        dut.filter_en.value = int(v[i, 4])

    await pipe.start(dut, reset=False, valid=False)
    got = await pipe.run_stream(dut, apply, lambda: (int(dut.addr_out.value), int(dut.use_mip_out.value)), len(v),
                                latency=2, seed=int(r.integers(1 << 30)))
    pipe.check_equal(dut, got, exp, lambda i: f"u={v[i, 0]} w={v[i, 1]} mode={v[i, 2]} n_log2={v[i, 3]} "
                     f"filter_en={v[i, 4]}", f"mip_index {p}")
