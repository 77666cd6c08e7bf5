"""sat_integral_serial (rtl/sat_integral_serial.v, colour_map's fold: one channel an enabled
clock, latency 1) bit-exact against golden sat_integral_serial with the RTL's words (d_w):
sat_integral's channel ch_in, p = (csat[kk-1][ch] << XF) + fr clut[kk][ch] mod 2^D_W and
e = k q[ch] mod 2^(D_W - XF).

Parameter sets (XF, KW, QW, CS_W, D_W): tb/sat_integral's (colour_map's instances under full,
reduced, three random valid configurations, the extremes of the colour-map formats, QW wider
than 8) and compact's (the fold's configuration).
Vectors: tb/sat_integral's edges (fr, k, q, before, clut at 0 and their extremes, first 0 and
1, the words that wrap mod 2^D_W / 2^TW), each channel's lanes distinct so that a wrong lane is
seen, then VECTORS random; each vector for its four channels ch = 0..3 in turn (as cmap_sat
drives it, the operands held), then the random ones with a random channel each; streamed with
ce stalls.
"""
from __future__ import annotations

import itertools

import numpy as np

import cocotb

from model.hw import golden as G
from model.hw.config import load_config
from tb import pipe
from tb.sat_integral import test_sat_integral as si


def _sets():
    out = {k: v for k, v in si._sets().items() if "PIPE" not in v}
    c = load_config("compact")
    out["compact"] = {"XF": c.f_frac + 1, "KW": c.x_w - c.f_frac - 1, "QW": max(8, c.csat_w - 8), "CS_W": c.csat_w,
                      "D_W": c.d_w}
    return out


# every set under Icarus, two under Verilator (a build costs 5-20 s)
test_sat_integral_serial_rtl = pipe.block_test("sat_integral_serial", _sets(), ("compact", "wide"), __file__,
                                              sources=["sat_integral_serial.v"])


@cocotb.test()
async def sat_integral_serial_bit_exact(dut):
    p = pipe.block_params()
    xf, kw, qw, cs_w, d_w = p["XF"], p["KW"], p["QW"], p["CS_W"], p["D_W"]
    r = pipe.rng(73)
    m = pipe.n_vectors()
    kmin, kmax = -(1 << (kw - 1)), (1 << (kw - 1)) - 1
    # columns: c[4], before[4], q[4], first, fr, k; the edges with each lane's words distinct
    # (the extreme in one lane, its neighbours elsewhere) so that a wrong channel differs
    edge = []
    for c, b, q, first, fr, k in itertools.product((0, 255), (0, (1 << cs_w) - 1), (0, 1, (1 << qw) - 1), (0, 1),
                                                   (0, 1, (1 << xf) - 1), (kmin, -1, 0, 1, kmax)):
        lane = int(r.integers(4))
        cs = [int(r.integers(256)) for _ in range(4)]
        bs = [int(r.integers(1 << cs_w)) for _ in range(4)]
        qs = [int(r.integers(1 << qw)) for _ in range(4)]
        cs[lane], bs[lane], qs[lane] = c, b, q
        edge.append(cs + bs + qs + [first, fr, k])
    rand = np.concatenate([r.integers(0, 256, (m, 4)), r.integers(0, 1 << cs_w, (m, 4)),
                           r.integers(0, 1 << qw, (m, 4)), r.integers(0, 2, (m, 1)), r.integers(0, 1 << xf, (m, 1)),
                           r.integers(kmin, kmax + 1, (m, 1))], axis=1)
    e4 = np.repeat(np.array(edge, dtype=np.int64), 4, axis=0)           # each edge for ch = 0..3
    v = np.concatenate([e4, rand])
    ch = np.concatenate([np.tile(np.arange(4), len(edge)), r.integers(0, 4, m)])
    pe, ee = G.sat_integral_serial(xf, ch, v[:, 0:4], v[:, 4:8], v[:, 12], v[:, 13], v[:, 14], v[:, 8:12], d_w=d_w)
    exp = np.stack([pe, ee], axis=1)

    def apply(i):
        dut.ch_in.value = int(ch[i])
        dut.c_in.value = pipe.pack(v[i, 0:4], 8)
        dut.before_in.value = pipe.pack(v[i, 4:8], cs_w)
        dut.q_in.value = pipe.pack(v[i, 8:12], qw)
        dut.first_in.value = int(v[i, 12])
        dut.fr_in.value = int(v[i, 13])
        dut.k_in.value = int(v[i, 14]) & ((1 << kw) - 1)

    def sample():
        return (int(dut.p_out.value), int(dut.e_out.value))

    await pipe.start(dut, reset=False, valid=False)
    got = await pipe.run_stream(dut, apply, sample, len(v), latency=1, seed=int(r.integers(1 << 30)))
    pipe.check_equal(dut, got, exp, lambda i: f"ch={ch[i]} inputs {v[i].tolist()}", f"sat_integral_serial {p}")
