"""sat_index (rtl/sat_index.v, latency 1) bit-exact against golden sat_index: a window
end x -> kk, km1, first, fr, kx.

Parameter sets (X_W, XF, NMAX, NL_W): colour_map's instances under full, reduced, three
random valid configurations and the extremes of the colour-map formats (small: NMAX = 1,
the narrowest words; wide: NMAX = 10, f_frac = 20), a word wider than needed, and full and
small with NM1_IN = 1 (N - 1 on nm1_in, as colour_map with fpga_regs drives it).
Vectors: for every n_log2 in 0..NMAX and both modes (mod, clamp), window ends at k = 0
and N, crossing the edges (k = -N-1, -N, -1, 0, 1, N-1, N, N+1, 2N-1, 2N) and at the
extremes of the word, each with fr = 0, 2^-XF and 1 - 2^-XF; then VECTORS random (x
uniform over the word or near the table, random mode and n_log2); streamed with ce stalls.
"""
from __future__ import annotations

import itertools

import numpy as np

import cocotb

from model.hw import golden as G
from tb import pipe


def _sets():
    out = {name: {"X_W": c.x_w, "XF": c.f_frac + 1, "NMAX": c.n_log2_max, "NL_W": c.n_log2_w}
           for name, c in pipe.configs(1231, 1232, 1233, colour_edges=True)}
    out["wide_x"] = {"X_W": 30, "XF": 9, "NMAX": 3, "NL_W": 4}
    out["full_nm1"] = {**out["full"], "NM1_IN": 1}  # N - 1 on nm1_in (colour_map with fpga_regs)
    out["small_nm1"] = {**out["small"], "NM1_IN": 1}
    return out


# every set under Icarus, two under Verilator (a build costs 5-20 s)
test_sat_index_rtl = pipe.block_test("sat_index", _sets(), ("full", "small"), __file__)


def window_ends(r, x_w, xf, nmax, m):
    """(x, mode, n_log2) rows: the edges for every n_log2 and mode, then m random."""
    kw = x_w - xf
    rows = []
    for n_log2, mode in itertools.product(range(nmax + 1), (0, 1)):
        n = 1 << n_log2
        ks = [-(1 << (kw - 1)), -n - 1, -n, -1, 0, 1, n - 1, n, n + 1, 2 * n - 1, 2 * n, (1 << (kw - 1)) - 1]
        for k, fr in itertools.product(ks, (0, 1, (1 << xf) - 1)):
            if -(1 << (kw - 1)) <= k < (1 << (kw - 1)):
                rows.append(((k << xf) + fr, mode, n_log2))
    near = r.integers(-(4 << (nmax + xf)), 4 << (nmax + xf), m)
    wide = r.integers(-(1 << (x_w - 1)), 1 << (x_w - 1), m)
    x = np.clip(np.where(r.random(m) < 0.5, near, wide), -(1 << (x_w - 1)), (1 << (x_w - 1)) - 1)
    rand = np.stack([x, r.integers(0, 2, m), r.integers(0, nmax + 1, m)], -1)
    return np.concatenate([np.array(rows, dtype=np.int64).reshape(-1, 3), rand])


@cocotb.test()
async def sat_index_bit_exact(dut):
    p = pipe.block_params()
    x_w, xf, nmax = p["X_W"], p["XF"], p["NMAX"]
    kw = x_w - xf
    v = window_ends(pipe.rng(61), x_w, xf, nmax, pipe.n_vectors())
    g = G.sat_index(v[:, 0], xf, v[:, 1], v[:, 2], nmax)
    exp = np.stack([g["kk"], g["km1"], g["first"], g["fr"], g["kx"]], -1)

    def apply(i):
        dut.x_in.value = int(v[i, 0]) & ((1 << x_w) - 1)
        dut.mode.value = int(v[i, 1])
        dut.n_log2.value = int(v[i, 2])
        dut.nm1_in.value = (1 << int(v[i, 2])) - 1  # read only with NM1_IN = 1

    def sample():
        return (int(dut.kk_out.value), int(dut.km1_out.value), int(dut.first_out.value), int(dut.fr_out.value),
                pipe.to_signed(int(dut.kx_out.value), kw))

    await pipe.start(dut, reset=False, valid=False)
    got = await pipe.run_stream(dut, apply, sample, len(v), latency=1, seed=int(pipe.rng(62).integers(1 << 30)))
    pipe.check_equal(dut, got, exp, lambda i: f"x={v[i, 0]} mode={v[i, 1]} n_log2={v[i, 2]}", f"sat_index {p}")
