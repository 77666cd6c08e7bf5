"""cm_align (rtl/cm_align.v) bit-exact against golden cm_align: f_out, w_out and out_valid,
with f and w arriving LATENCY_F and LATENCY_W enabled clocks before the outputs (the skew of
texture_pipeline: the output pairs f and w entered that many enabled clocks apart).

Parameter sets (F_W, F_FRAC, W_CAP_LOG2, WV_MAX, LATENCY_F, LATENCY_W): the f and w formats of
full, reduced, compact and two random configurations, each with f waiting (f carried in fewer
bits where guard + 3 < F_W), w waiting, and with sat_fc's max(w, wv) stage (w waiting or f
waiting); a small format (F_W 12: saturation at +-2^6) and the plain wire (both 0); the
trapezoid's pair (NW 2, filters sat2 and sat2_fc: w = {b, a}, the clamp guard W) of full's
formats, waiting and with sat2_fc's stage (the larger of a and b max'd with wv), and small.
Vectors: every clock new f, w, wv, mode and the two valid bits (random, so the later path's
valid must be the output's), ce dropped at random (the outputs must hold); f uniform over
its word, and at +-2^(guard+1) + {-1, 0, 1} and small values; w, wv uniform over theirs (NW 2:
a and b each, a third of them equal).
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
    for name, cfg in pipe.configs(1401, 1402) + [("compact", load_config("compact"))]:
        fmt = {"F_W": cfg.f_w, "F_FRAC": cfg.f_frac, "W_CAP_LOG2": cfg.w_cap_log2}
        for tag, wv, lf, lw in (("fwait", 0, 3, 0), ("wwait", 0, 0, 2), ("fc", 1, 2, 1), ("fc_wwait", 1, 0, 4)):
            out[f"{name}_{tag}"] = {**fmt, "WV_MAX": wv, "LATENCY_F": lf, "LATENCY_W": lw}
    small = {"F_W": 12, "F_FRAC": 4, "W_CAP_LOG2": 2}
    out["small_fwait"] = {**small, "WV_MAX": 1, "LATENCY_F": 5, "LATENCY_W": 1}
    out["wire"] = {**small, "WV_MAX": 0, "LATENCY_F": 0, "LATENCY_W": 0}
    full = load_config("full")
    fmt = {"F_W": full.f_w, "F_FRAC": full.f_frac, "W_CAP_LOG2": full.w_cap_log2, "NW": 2}
    for tag, wv, lf, lw in (("fwait", 0, 3, 0), ("wwait", 0, 0, 2), ("fc", 1, 2, 1), ("fc_wwait", 1, 0, 4)):
        out[f"sat2_{tag}"] = {**fmt, "WV_MAX": wv, "LATENCY_F": lf, "LATENCY_W": lw}
    out["sat2_small_fc"] = {**small, "NW": 2, "WV_MAX": 1, "LATENCY_F": 5, "LATENCY_W": 1}
    return out


# under Verilator: each kind of wait (full_wwait: w waits, out_valid from w's path; make coverage)
test_cm_align_rtl = pipe.block_test("cm_align", _sets(), ("full_fc", "small_fwait", "full_fwait", "full_wwait",
                                                          "sat2_fc"),
                                    __file__, sources=["cm_align.v", "delay_line.v"])


def test_cm_align_check():
    """cm_align's elaboration-time check (g_bad_latency) both ways on full's sat_fc set (WV_MAX 1,
    f waits DLY_F = 2, w's DLY_W = 0): refused with each term alone true (DLY_F = -1; DLY_W = -1,
    the max stage alone in LATENCY_W 0; both waits 1; NW 3 and NW 0, neither 1 nor 2); accepted at
    each edge (DLY_W = 0 and DLY_F = 0, each beside the other's wait of 1 or more; both 0 without
    the max stage, WV_MAX 0: LAT_M = 0 != 1 but no max stage; NW 2). (LAT_M != 1 with WV_MAX
    depends on rtl/tex_latency.vh alone (`LAT_FC_WMAX): no parameter set makes it true.)"""
    import hdlbuild

    hdlbuild.check_refusals(
        "cm_align", ["cm_align.v", "delay_line.v"], _sets()["full_fc"],
        accept={"full_fc (DLY_W 0)": {}, "DLY_F 0, DLY_W 1": {"LATENCY_F": 0, "LATENCY_W": 2},
                "WV_MAX 0, both waits 0": {"WV_MAX": 0, "LATENCY_F": 0, "LATENCY_W": 0}, "NW 2": {"NW": 2}},
        refuse={"DLY_F < 0": {"LATENCY_F": -1}, "DLY_W < 0": {"LATENCY_F": 0, "LATENCY_W": 0},
                "DLY_F > 0 and DLY_W > 0": {"LATENCY_W": 2}, "NW 3": {"NW": 3}, "NW 0": {"NW": 0}},
        error_module="cm_align_latency_must_be_one_wait_and_the_max_stage")


@cocotb.test()
async def cm_align_bit_exact(dut):
    p = pipe.block_params()
    fw, ff, wc = p["F_W"], p["F_FRAC"], p["W_CAP_LOG2"]
    wvmax, lf, lw = p["WV_MAX"], p["LATENCY_F"], p["LATENCY_W"]
    nw = p.get("NW", 1)
    ww = wc + ff + 1
    cfg = SimpleNamespace(f_w=fw, f_frac=ff, w_cap_log2=wc, filter="sat2" if nw == 2 else "sat")
    r = pipe.rng(67)
    n = pipe.n_vectors()
    top = 1 << (wc + ff)  # 2^(guard+1)
    edge = np.array([s * top + d for s in (-1, 1) for d in (-1, 0, 1)] + [-(1 << (fw - 1)), (1 << (fw - 1)) - 1, 0, -1],
                    dtype=np.int64)
    f = np.concatenate([edge, r.integers(-(1 << (fw - 1)), 1 << (fw - 1), n, dtype=np.int64)])
    small = r.random(len(f)) < 0.3
    f[small] = r.integers(-2 * top, 2 * top + 1, int(small.sum()), dtype=np.int64)
    m = len(f)
    w = r.integers(0, 1 << ww, (m, nw) if nw == 2 else m, dtype=np.int64)
    if nw == 2:  # a = b a third of the time (the tie: a is the larger)
        tie = r.random(m) < 1 / 3
        w[tie, 1] = w[tie, 0]
    wv = r.integers(0, 1 << ww, m, dtype=np.int64)
    mode = r.integers(0, 2, m, dtype=np.int64)
    fv = r.integers(0, 2, m, dtype=np.int64)
    wvl = r.integers(0, 2, m, dtype=np.int64)
    f_exp, w_exp = G.cm_align(cfg, mode, f, w, wv if wvmax else None, f_waits=lf > 0)
    if nw == 2:  # as words {b, a}, Python ints (2 ww may pass 64 bits)
        w = [int(a) | (int(b) << ww) for a, b in w]
        w_exp = [int(a) | (int(b) << ww) for a, b in w_exp]
    lat_m = lw - (1 if wvmax else 0)  # w's own wait (the max stage is one register)
    # the later path brings the valid bit: f when w waits, else w (through the max stage)
    v_exp, lv = (fv, lf) if lat_m > 0 else (wvl, lw)

    await pipe.start(dut, valid=False)
    rs = random.Random(fw * 7 + lf * 3 + lw)
    e, checked, prev = 0, 0, None
    lmax = max(lf, lw)
    while e < m:
        ce = 1 if rs.random() >= 0.2 else 0
        dut.f_in.value = int(f[e]) & ((1 << fw) - 1)
        dut.w_in.value = int(w[e])
        dut.wv_in.value = int(wv[e])
        dut.mode.value = int(mode[e])
        dut.f_valid.value = int(fv[e])
        dut.w_valid.value = int(wvl[e])
        dut.ce.value = ce
        await Timer(1, unit="ns")
        await ReadOnly()
        if e >= lmax:
            got = (pipe.to_signed(int(dut.f_out.value), fw), int(dut.w_out.value), int(dut.out_valid.value))
            exp = (int(f_exp[e - lf]), int(w_exp[e - lw]), int(v_exp[e - lv]))
            assert got == exp, (f"vector {e}: f_in {int(f[e - lf])} mode {int(mode[e - lf])} w_in {int(w[e - lw])} "
                                f"wv {int(wv[e - lw])}: expected (f, w, valid) {exp}, got {got}")
            if prev is not None and prev[0] == e:
                assert prev[1] == got, f"vector {e}: outputs changed while ce = 0"
            prev = (e, got)
            checked += 1
        await RisingEdge(dut.clk)
        await Timer(1, unit="ns")
        e += ce
    dut._log.info(f"cm_align {p}: {m - lmax} vectors bit-exact ({checked} samples)")
