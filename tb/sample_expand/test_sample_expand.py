"""sample_expand (rtl/sample_expand.v) bit-exact against golden sample_expand: every clock, the
offered sample's s_k, Jm_k, je_k for the sample index the block holds, and its handshake
(out_valid = in_valid, in_ready = out_ready with the last sample; the index advances on an
enabled edge where a sample is taken, returns to 0 after the last and on rst).

Parameter sets (SAMPLES, S_W, S_FRAC, J_W, JE_W): 2 and 4 samples on the formats of full,
compact and reduced (texture_pipeline's pixel input), and a small format (S_W 8, J_W 4, JE_W
3) where the offsets saturate s and the shifts reach both caps.
Vectors: every clock new inputs (the datapath is combinational: each clock checks the
sample the index selects), s uniform over its word and at its ends, Jm uniform, at +-2^(J_W-1)
and 0, je uniform over its word and at its least value (4 samples: the footprint is not
halved there) and around -S_FRAC (the offset's exponent crossing 0); in_valid, out_ready and
ce random, rst at random clocks.
"""
from __future__ import annotations

import random
from types import SimpleNamespace

import numpy as np

import cocotb
from cocotb.triggers import ReadOnly, RisingEdge, Timer

from model.hw import golden as G
from tb import pipe


def _sets():
    from model.hw.config import load_config

    out = {}
    for name in ("full", "compact", "reduced"):
        c = load_config(name)
        for n in (2, 4):
            out[f"{name}_s{n}"] = {"SAMPLES": n, "S_W": c.s_w, "S_FRAC": c.s_frac, "J_W": c.j_w, "JE_W": c.je_w}
    for n in (2, 4):
        out[f"small_s{n}"] = {"SAMPLES": n, "S_W": 8, "S_FRAC": 4, "J_W": 4, "JE_W": 3}
    return out


test_sample_expand_rtl = pipe.block_test("sample_expand", _sets(), ("full_s4", "small_s2"), __file__)


def _draw(r: random.Random, w: int, special) -> int:
    """A signed w-bit value: uniform, or one of `special` (clipped to the word)."""
    lo, hi = -(1 << (w - 1)), (1 << (w - 1)) - 1
    if r.random() < 0.3:
        return max(lo, min(hi, r.choice(special)))
    return r.randint(lo, hi)


@cocotb.test()
async def sample_expand_bit_exact(dut):
    p = pipe.block_params()
    n, sw, sf, jw, jew = p["SAMPLES"], p["S_W"], p["S_FRAC"], p["J_W"], p["JE_W"]
    cfg = SimpleNamespace(samples=n, s_w=sw, s_frac=sf, j_w=jw, je_w=jew)
    r = random.Random(int(pipe.rng(71).integers(1 << 30)))
    s_lo, s_hi = -(1 << (sw - 1)), (1 << (sw - 1)) - 1
    j_lo, j_hi = -(1 << (jw - 1)), (1 << (jw - 1)) - 1
    je_lo = -(1 << (jew - 1))
    await pipe.start(dut, reset=True, valid=True)
    dut.out_ready.value = 0
    idx, taken, last_seen, t_n = 0, 0, 0, pipe.n_vectors(3000)
    got, exp, desc = [], [], []
    for t in range(t_n):
        s = [_draw(r, sw, [s_lo, s_hi, s_lo + 1, s_hi - 1, 0]) for _ in range(3)]
        jm = [_draw(r, jw, [j_lo, j_hi, 0, 1, -1]) for _ in range(6)]
        je = _draw(r, jew, [je_lo, je_lo + 1, 2 - sf, 1 - sf, 3 - sf, -sf, 0, (1 << (jew - 1)) - 1])
        vin, rdy = int(r.random() < 0.8), int(r.random() < 0.8)
        ce, rst = int(r.random() < 0.8), int(r.random() < 0.02)
        dut.s_in.value = pipe.pack(s, sw)
        dut.jm_in.value = pipe.pack(jm, jw)
        dut.je_in.value = je & ((1 << jew) - 1)
        dut.in_valid.value, dut.out_ready.value, dut.ce.value, dut.rst.value = vin, rdy, ce, rst
        await Timer(1, unit="ns")
        sk, jk, ek = G.sample_expand(cfg, np.array(s), np.array(jm).reshape(3, 2), np.array(je), idx)
        exp.append((*[int(v) for v in sk], *[int(v) for v in jk.reshape(-1)], int(ek),
                    vin, int(rdy and idx == n - 1)))
        got.append((*pipe.unpack(int(dut.s_out.value), sw, 3), *pipe.unpack(int(dut.jm_out.value), jw, 6),
                    pipe.to_signed(int(dut.je_out.value), jew), int(dut.out_valid.value), int(dut.in_ready.value)))
        desc.append(f"clock {t}: idx {idx} s {s} jm {jm} je {je} in_valid {vin} out_ready {rdy}")
        await RisingEdge(dut.clk)
        if rst:
            idx = 0
        elif ce and vin and rdy:
            taken += 1
            last_seen += idx == n - 1
            idx = 0 if idx == n - 1 else idx + 1
        await ReadOnly()
        await Timer(1, unit="ns")
    assert taken > t_n // 3 and last_seen > taken // (2 * n), f"too few samples taken ({taken}, {last_seen} last)"
    pipe.check_equal(dut, got, exp, lambda i: desc[i], f"sample_expand {p}")
