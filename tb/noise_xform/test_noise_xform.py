"""noise_xform (rtl/noise_xform.v) bit-exact against golden noise_xform: one axis of a noise
term's transform, p_j = ((T_j s) >> (ts_shift - te)) + o_j mod 2^p_w, as {cell, fraction},
latency `LAT_NOISE_XFORM (rtl/tex_latency.vh), o and te read one enabled clock after s and T.

Parameter sets: noise_term's instances (texture_pipeline's parameters) under full, reduced
and two random valid configurations, every axis of the pow2 ones (which read s_j, T_jj
alone), and the axis 0 of the affine ones; and with per-term exponents (T_EXP_W > 0,
pipe.exponent_configs: full_bfp, full_exp (te_max = ts_shift: a shift of 0) and a random one),
axis 0.
Vectors: the format extremes of s, T (affine: each entry; pow2: T_jj = 0, 1, 2^(t_w-2)) and
o (0, 2^p_w - 1) in combination (with exponents: at te = 0 and te_max), then VECTORS random
ones (half over the whole formats, half |s| <= 8, |T| <= 4; te uniform over its format), each
with its own T, o and te (noise_fold's units change the term every clock).
"""
from __future__ import annotations

import itertools
import math
from types import SimpleNamespace

import numpy as np

import cocotb

import hdlbuild
from hdlbuild.params import ENUMS
from model.hw import golden as G
from tb import pipe


def _sets():
    out = {}
    for name, cfg in pipe.configs(1311, 1312):
        base = {"S_W": cfg.s_w, "S_FRAC": cfg.s_frac, "T_W": cfg.t_w, "T_FRAC": cfg.t_frac, "P_FRAC": cfg.p_frac,
                "HASH_BITS": cfg.hash_bits, "TRANSFORM": ENUMS["transform"][cfg.transform]}
        for axis in (range(3) if cfg.transform == "pow2" else (0,)):
            out[f"{name}_{cfg.transform}{axis}"] = {**base, "AXIS": axis}
    for name, cfg in pipe.exponent_configs(1313):
        out[f"{name}_affine0"] = {"S_W": cfg.s_w, "S_FRAC": cfg.s_frac, "T_W": cfg.t_w, "T_FRAC": cfg.t_frac,
                                  "P_FRAC": cfg.p_frac, "HASH_BITS": cfg.hash_bits, "TRANSFORM": 0, "AXIS": 0,
                                  "T_EXP_W": cfg.t_exp_w}
    return out


# every set under Icarus; under Verilator (a build costs 5-20 s) full's, reduced's and full_bfp's
test_noise_xform_rtl = pipe.block_test("noise_xform", _sets(), ("full_affine0", "reduced_pow22", "full_bfp_affine0"),
                                       __file__)


def test_noise_xform_check():
    """noise_xform's elaboration-time check (g_bad_params) both ways on full_bfp's set (affine, T_EXP_W
    4: TE_MAX 15, TS_SHIFT = S_FRAC + T_FRAC - P_FRAC = 26): refused with each term alone true
    (AXIS -1 < 0; AXIS 3 > 2; T_EXP_W -1 < 0; a T exponent on pow2 T, TRANSFORM 1; a T exponent
    with TS_SHIFT = TE_MAX - 1, S_FRAC lowered); accepted at each edge (AXIS 0; AXIS 2, pow2 T
    without an exponent, where the axis is read; TS_SHIFT = TE_MAX) and with no T exponent
    (T_EXP_W 0) on pow2 T, !AFFINE alone. (LATENCY != STAGES depends on rtl/tex_latency.vh alone: no
    parameter set makes it true.)"""
    b = _sets()["full_bfp_affine0"]
    te_max = (1 << b["T_EXP_W"]) - 1
    s_edge = te_max + b["P_FRAC"] - b["T_FRAC"]  # TS_SHIFT = TE_MAX
    pow2 = {"TRANSFORM": 1, "T_EXP_W": 0}
    hdlbuild.check_refusals(
        "noise_xform", ["noise_xform.v"], b,
        accept={"full_bfp (AXIS 0)": {}, "AXIS 2 (pow2)": {**pow2, "AXIS": 2}, "TS_SHIFT = TE_MAX": {"S_FRAC": s_edge},
                "no T exponent, pow2 T": pow2},
        refuse={"AXIS < 0": {"AXIS": -1}, "AXIS > 2": {"AXIS": 3}, "T_EXP_W < 0": {"T_EXP_W": -1},
                "T exponent, pow2 T": {"TRANSFORM": 1}, "TS_SHIFT < TE_MAX": {"S_FRAC": s_edge - 1}},
        error_module="noise_xform_latency_must_be_lat_noise_xform")


@cocotb.test()
async def noise_xform_bit_exact(dut):
    p = pipe.block_params()
    sw, tw, j, pow2 = p["S_W"], p["T_W"], p["AXIS"], p["TRANSFORM"] == 1
    pw = p["HASH_BITS"] + p["P_FRAC"]
    cfg = SimpleNamespace(d={"ts_shift": p["S_FRAC"] + p["T_FRAC"] - p["P_FRAC"], "p_w": pw})
    ew = math.ceil(math.log2(tw - 1))
    te_max = (1 << p.get("T_EXP_W", 0)) - 1
    r = pipe.rng(71)
    slo, shi = -(1 << (sw - 1)), (1 << (sw - 1)) - 1
    tlo, thi = -(1 << (tw - 1)), (1 << (tw - 1)) - 1
    s_ext = [slo, slo + 1, -1, 0, 1, shi]
    t_ext = [0, 1, 1 << (tw - 2)] if pow2 else [tlo, -1, 0, 1, thi]
    o_ext = [0, (1 << pw) - 1]
    S, T, O, E = [], [], [], []
    for sv, tv, ov, ev in itertools.product(itertools.product(s_ext, repeat=3), t_ext, o_ext, sorted({0, te_max})):
        S.append(sv)
        T.append([tv if (k == j or not pow2) else 0 for k in range(3)])
        O.append(ov)
        E.append(ev)
    m = pipe.n_vectors()
    for i in range(m):
        small = i % 2
        S.append(r.integers(-(8 << p["S_FRAC"]), (8 << p["S_FRAC"]) + 1, 3) if small else r.integers(slo, shi + 1, 3))
        if pow2:
            e = int(r.integers(0, tw - 1))
            T.append([(0 if r.random() < 0.1 else 1 << e) if k == j else 0 for k in range(3)])
        else:
            lim = min(4 << p["T_FRAC"], thi) if small else thi
            T.append(r.integers(-lim - (0 if small else 1), lim + 1, 3))
        O.append(int(r.integers(0, 1 << pw)))
        E.append(int(r.integers(0, te_max + 1)) if te_max else 0)  # (fixed point: the stream as it was)
    S, T, O = np.array(S, dtype=np.int64), np.array(T, dtype=np.int64), np.array(O, dtype=np.int64)
    n = len(S)
    exp = [int(x) for x in (G.noise_xform(cfg, T[i], O[i], S[i:i + 1], E[i])[0] for i in range(n))]

    def t_word(row):
        if not pow2:
            return pipe.pack(row, tw)
        t = int(row[j])
        return (1 << ew) if t == 0 else t.bit_length() - 1  # {zero, e}

    s_p = [pipe.pack(x, sw) for x in S] + [0]
    t_p = [t_word(x) for x in T] + [0]

    def apply(i):  # s, T of vector i at stage 1, o, te of vector i - 1 at stage 2 (i = n: a dummy)
        dut.s_in.value = s_p[i]
        dut.t_row.value = t_p[i]
        dut.o_in.value = int(O[i - 1]) if i > 0 else 0
        dut.te.value = E[i - 1] if i > 0 else 0

    def sample():
        return (int(dut.ip.value) << p["P_FRAC"]) | int(dut.fp.value)

    await pipe.start(dut, reset=False, valid=False)
    got = await pipe.run_stream(dut, apply, sample, n + 1, latency=hdlbuild.latency("noise_xform"),
                                seed=int(r.integers(1 << 30)))
    pipe.check_equal(dut, got[:n], exp, lambda i: f"s={S[i].tolist()} T_j={T[i].tolist()} o_j={O[i]} te={E[i]}",
                     f"noise_xform {p}")
