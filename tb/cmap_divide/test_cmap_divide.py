"""cmap_divide (rtl/cmap_divide.v) bit-exact against golden cmap_divide: the box average
D / (2w) rounded by the method DIV_BITS (0 exact, B > 0 normalised), or, w = 0, the point
lookup passed through, four channels a vector (LANES = 4), or one (LANES = 1: colour_map's fold,
cmap_clocks = 4, a pixel's channels as four vectors of the same w).

Parameter sets (W_W, D_W, DIV_BITS, FPGA_REGS, LANES): colour_map's (w_w, d_w, div_bits) under full,
reduced, compact, three random valid configurations and the extremes of the colour-map
formats (small, wide: exact); reduced with div_bits 0 (exact), 1 (the narrowest divisor, where
D + w + 2 h(sh) of a whole 255-valued window reaches 2^D_W), 4 and 9 (the saturating quotient)
and w_w - 1 (shift 0 or 1); with FPGA_REGS = 1: reduced (B = 10) and its div_bits 0, 1, 9,
full (B = 8); with LANES = 1 compact (B = 6), reduced's div_bits 0 (exact) and 9 (saturating).
Vectors: w at the normalisation's edges (every power of two from 2^(B-1) to the cap, +-1, the
rounding ties, where rounding w carries into the next power of two), 0 and the cap; D at 0,
at 255 * 2w (the largest quotient), at the rounding ties (2j - 1) w - 1, (2j - 1) w, (2j - 1)
w + 1 and random in [0, 255 * 2w]; then VECTORS random (w uniform and log-uniform); pt random.
Streamed with ce stalls and input gaps, w_in driven WLEAD = 1 + 2 FPGA_REGS enabled clocks
before the vector's D (the module's contract); the latency from d_in is checked.
"""
from __future__ import annotations

import random
from types import SimpleNamespace

import numpy as np

import cocotb
from cocotb.triggers import ReadOnly, RisingEdge

from model.hw import golden as G
from model.hw.config import latency, load_config
from tb import pipe


def _sets():
    out = {name: {"W_W": c.w_w, "D_W": c.d_w, "DIV_BITS": c.div_bits}
           for name, c in pipe.configs(1251, 1252, 1253, colour_edges=True)}
    out["compact"] = {"W_W": (c := load_config("compact")).w_w, "D_W": c.d_w, "DIV_BITS": c.div_bits}
    red = out["reduced"]
    for b in (0, 1, 4, 9, red["W_W"] - 1):
        out[f"reduced_div{b}"] = {**red, "DIV_BITS": b}
    out["reduced_fpga"] = {**red, "FPGA_REGS": 1}
    for b in (0, 1, 9):
        out[f"reduced_fpga_div{b}"] = {**red, "DIV_BITS": b, "FPGA_REGS": 1}
    out["full_fpga"] = {**out["full"], "FPGA_REGS": 1}
    for name in ("compact", "reduced_div0", "reduced_div9"):
        out[f"{name}_l1"] = {**out[name], "LANES": 1}
    return out


# every set under Icarus, four under Verilator (a build costs 5-20 s)
test_cmap_divide_rtl = pipe.block_test("cmap_divide", _sets(), ("full", "compact", "reduced_fpga", "compact_l1"),
                                      __file__,
                                      sources=["cmap_divide.v", "box_divide.v", "delay_line.v"])


def test_cmap_divide_check():
    """cmap_divide's elaboration-time check (g_bad_params) both ways on reduced's set (W_W 23,
    normalised on B = 10 bits: NQ_W = B + 8 = 18): refused with both terms true (NORM, and NQ_W >
    D_W - 1 at D_W 18; likewise B = 9, whose saturating quotient adds a bit: NQ_W 9 + 8 + 1 = 18);
    accepted at the edge NQ_W = D_W - 1 (D_W 19, B 10 and 9) and with the second term alone true
    (D_W 10 < NQ_W 10 + 1 of B = 1: exact division, DIV_BITS 0, and DIV_BITS = W_W, not
    normalised). (g_bad_latency depends on rtl/tex_latency.vh alone: no parameter set makes it
    true.)"""
    import hdlbuild

    red = _sets()["reduced"]
    hdlbuild.check_refusals(
        "cmap_divide", ["cmap_divide.v", "box_divide.v", "delay_line.v"], red,
        accept={"reduced": {}, "NQ_W = D_W - 1": {"D_W": 19}, "B 9: NQ_W = D_W - 1": {"DIV_BITS": 9, "D_W": 19},
                "exact (DIV_BITS 0), D_W 10": {"DIV_BITS": 0, "D_W": 10},
                "DIV_BITS = W_W (exact), D_W 10": {"DIV_BITS": red["W_W"], "D_W": 10}},
        refuse={"NORM and NQ_W > D_W - 1": {"D_W": 18}, "B 9: NQ_W > D_W - 1": {"DIV_BITS": 9, "D_W": 18}},
        error_module="cmap_divide_unsupported_div_bits")


def test_cmap_divide_lanes_check():
    """cmap_divide's LANES check (g_bad_lanes) both ways on compact's set: 1 and 4 accepted, 2 and 0
    refused."""
    import hdlbuild

    hdlbuild.check_refusals(
        "cmap_divide", ["cmap_divide.v", "box_divide.v", "delay_line.v"], _sets()["compact"],
        accept={"LANES 4": {}, "LANES 1": {"LANES": 1}}, refuse={"LANES 2": {"LANES": 2}, "LANES 0": {"LANES": 0}},
        error_module="cmap_divide_lanes_must_be_1_or_4")


def vectors(p, r, m):
    """(w, D [n, 4], pt [n, 4]) within the contract 0 <= D <= 255 * 2w."""
    w_w, b = p["W_W"], p["DIV_BITS"]
    cap = 1 << (w_w - 1)
    ws = [0, 1, 2, 3, cap - 1, cap]
    for k in range(max(b - 1, 0), w_w):
        q = 1 << k
        ws += [q - 1, q, q + 1]
        sh0 = k + 1 - b
        if b and sh0 >= 1:
            h = 1 << (sh0 - 1)
            ws += [q + h - 1, q + h, q + 2 * h - 1, q + 2 * h, 2 * q - h - 1, 2 * q - h]
    ws = np.unique(np.clip(np.array(ws, dtype=np.int64), 0, cap))
    w, d = [], []
    for wv in ws.tolist():
        j = int(r.integers(1, 256))
        ds = [0, 510 * wv, max(0, (2 * j - 1) * wv - 1), (2 * j - 1) * wv, min(510 * wv, (2 * j - 1) * wv + 1)]
        for dv in ds:
            w.append(wv)
            d.append([dv, 510 * wv - dv, int(r.integers(0, 510 * wv + 1)), dv])
    wr = np.where(r.random(m) < 0.5, r.integers(0, cap + 1, m),
                  np.minimum((r.random(m) * 2.0 ** r.integers(0, w_w, m)).astype(np.int64), cap))
    dr = (r.random((m, 4)) * (510 * wr[:, None] + 1)).astype(np.int64)
    dr = np.minimum(dr, 510 * wr[:, None])
    w = np.concatenate([np.array(w, dtype=np.int64), wr])
    d = np.concatenate([np.array(d, dtype=np.int64).reshape(-1, 4), dr])
    pt = r.integers(0, 256, (len(w), 4))
    return w, d, pt


async def stream(dut, w, d, pt, p, lead: int, lat: int, seed: int):
    """Drive vector i's w on an enabled edge and its D, pt, in_valid `lead` enabled edges later,
    with ce stalls and gaps (junk on the idle inputs); returns the outputs in order, each
    checked to come `lat` enabled edges after its D."""
    rr = random.Random(seed)
    d_w, w_w, lanes = p["D_W"], p["W_W"], p.get("LANES", 4)
    n = len(w)
    hist = []        # per enabled edge: the vector whose w it took (None: none)
    issued = []      # enabled edge that took each vector's D
    out = []
    nxt = 0
    enabled = 0
    guard = 0
    while len(out) < n:
        ce = 1 if rr.random() >= 0.2 else 0
        wi = nxt if (nxt < n and rr.random() >= 0.1) else None
        dut.w_in.value = int(w[wi]) if wi is not None else rr.getrandbits(w_w)
        di = hist[-lead] if len(hist) >= lead else None
        dut.in_valid.value = int(di is not None)
        dut.d_in.value = pipe.pack(d[di], d_w) if di is not None else rr.getrandbits(lanes * d_w)
        dut.pt_in.value = pipe.pack(pt[di], 8) if di is not None else rr.getrandbits(8 * lanes)
        dut.ce.value = ce
        await RisingEdge(dut.clk)
        if ce:
            enabled += 1
            hist.append(wi)
            if wi is not None:
                nxt += 1
            if di is not None:
                issued.append(enabled)
        await ReadOnly()
        if ce and int(dut.out_valid.value):
            k = len(out)
            assert k < len(issued), "out_valid with no vector in flight"
            assert enabled - issued[k] + 1 == lat, f"vector {k}: latency {enabled - issued[k] + 1}, expected {lat}"
            out.append(tuple(pipe.unpack(int(dut.q_out.value), 8, lanes, signed=False)))
        guard += 1
        assert guard < 20 * (n + lat + lead + 10), "pipeline stopped producing outputs"
        await pipe._after_readonly(dut)
    return out


@cocotb.test()
async def cmap_divide_bit_exact(dut):
    p = pipe.block_params()
    fpga = p.get("FPGA_REGS", 0)
    lat = latency("cmap_divide", SimpleNamespace(fpga_regs=bool(fpga)))
    r = pipe.rng(83)
    w, d, pt = vectors(p, r, pipe.n_vectors())
    exp = G.cmap_divide(SimpleNamespace(div_bits=p["DIV_BITS"]), d, w, pt)
    if p.get("LANES", 4) == 1:  # a pixel's channels in turn, each a vector of the pixel's w
        w, d, pt, exp = np.repeat(w, 4), d.reshape(-1, 1), pt.reshape(-1, 1), exp.reshape(-1, 1)
    await pipe.start(dut)
    assert int(dut.out_valid.value) == 0 and int(dut.q_out.value) == 0, "outputs after reset"
    got = await stream(dut, w, d, pt, p, 1 + 2 * fpga, lat, seed=int(r.integers(1 << 30)))
    pipe.check_equal(dut, got, exp, lambda i: f"w={w[i]} D={d[i].tolist()} pt={pt[i].tolist()}", f"cmap_divide {p}")
