"""noise_fold (rtl/noise_fold.v) bit-exact against golden noise_fold (the sums f_sum, c_sum)
and noise_fold_schedule (the handshake): every output after every clock.

Configurations (the fold's parameters from hdlbuild.block_params, as texture_pipeline's g_fold
gives them): compact (K = 5 terms on U = 1 unit, the quadric's two clocks a pixel at least,
pow2, the noise gradient), compact_u2 (U = 2, which does not divide K: the last slot's unit 1
has no term), full_u3 (K = 8 on U = 3, affine, amplitude any, one clock a pixel at least) and
full_u3_fpga (the same with FPGA_REGS: the registered parameters and last-issue flag, noise_term's
extra stages), reduced_u1 (K = 2 on one unit, no noise gradient: c_sum 0), full_bfp_u3
(config/candidates/full_bfp.toml on U = 3: per-term exponents, {te, T} and {ae, a} in t_all and
a_all). Icarus all; Verilator full_u3_fpga too (make coverage runs it).

Stimulus: batches (the fold drained between them: k_used and the parameters are per-pass
registers), each with its own k_used and terms: k_used = K (every term, every slot of every
unit; twice), 0 (the quadric's clocks alone), and below K with a non-zero a on every term past
k_used (the fold must give those slots a = 0), T and o random on every term (tb/noise_term's
draws), the exponents te and ae uniform over what the configuration holds; s as tb/noise_term draws it, the side word uniform. Per clock: the pixel offered
(in_valid) with random gaps, the source withdrawing and offering again (the fold takes a pixel
only on an enabled clock with in_ready), ce low in random runs (the pipeline's output stalls),
s_in and side_in random while in_valid = 0; one batch back to back without gaps or stalls
(a pixel taken on each pixel's last issue), one stalled half of its clocks, one with rst
pulses among the pixels (the fold empties: the pixels in flight are dropped, never shown), one of
them on an enabled clock of a pixel's last issue (FPGA_REGS: the valid bit registered beside the
parameters must clear too, or that pixel's sums show after the reset).
Checked every clock: in_ready, px_valid (before the edge) and sum_valid (after it); px_s and
px_side whenever a pixel is held; f_sum and c_sum whenever sum_valid (the pixel the schedule
says, its sums from golden noise_fold).
"""
from __future__ import annotations

import random
from types import SimpleNamespace

import numpy as np

import cocotb
from cocotb.triggers import ReadOnly, RisingEdge, Timer

import hdlbuild
from model.hw import golden as G
from model.hw.config import ROOT, clocks_per_sample, load_config, variant
from tb import pipe
from tb.noise_term.test_noise_term import rand_a, rand_o, rand_s, rand_T

SOURCES = ["noise_fold.v", "noise_term.v", "noise_params.v", "noise_xform.v", "noise_grad.v", "noise_hash.v",
           "noise_blend.v", "lerp.v", "delay_line.v"]


def _configs() -> dict:
    full, compact, reduced = load_config("full"), load_config("compact"), load_config("reduced")
    return {"compact": compact,
            "compact_u2": variant(compact, "compact_u2", noise_units=2),
            "full_u3": variant(full, "full_u3", noise_units=3),
            "full_u3_fpga": variant(full, "full_u3_fpga", noise_units=3, fpga_regs=True),
            "reduced_u1": variant(reduced, "reduced_u1", noise_units=1),
            "full_bfp_u3": variant(load_config(str(ROOT / "config" / "candidates" / "full_bfp.toml")), "full_bfp_u3",
                                   noise_units=3)}


CONFIGS = _configs()
test_noise_fold_rtl = pipe.block_test("noise_fold", {n: hdlbuild.block_params(c, "noise_fold") for n, c in CONFIGS.items()},
                                      ("full_u3_fpga",), __file__, config=CONFIGS, sources=SOURCES)


def test_noise_fold_check():
    """noise_fold's elaboration-time check (g_bad_params) both ways on full_u3's set (K 8 terms on
    U 3 units, F_W 46, C_W 32, MIN_CLOCKS 1): refused with each term alone true (U 0 < 1; U 9 > K; F_W = AN_W - 1; C_W = AG_W - 1,
    AN_W and AG_W a term's value and gradient words; MIN_CLOCKS 0 < 1); accepted at each edge (U 1;
    U = K; F_W = AN_W; C_W = AG_W; MIN_CLOCKS 2, 6 (the serial quadric's) and 9 > ceil(K / U))."""
    c = CONFIGS["full_u3"]
    b = hdlbuild.block_params(c, "noise_fold")
    k = b["NOISE_TERMS"]
    hdlbuild.check_refusals(
        "noise_fold", SOURCES, b,
        accept={"full_u3": {}, "U 1": {"NOISE_UNITS": 1}, "U = K": {"NOISE_UNITS": k}, "F_W = AN_W": {"F_W": c.an_w},
                "C_W = AG_W": {"C_W": c.ag_w}, "MIN_CLOCKS 2": {"MIN_CLOCKS": 2},
                "MIN_CLOCKS 6": {"MIN_CLOCKS": 6}, "MIN_CLOCKS 9": {"MIN_CLOCKS": 9}},
        refuse={"U < 1": {"NOISE_UNITS": 0}, "U > K": {"NOISE_UNITS": k + 1}, "F_W < AN_W": {"F_W": c.an_w - 1},
                "C_W < AG_W": {"C_W": c.ag_w - 1}, "MIN_CLOCKS < 1": {"MIN_CLOCKS": 0}},
        error_module="noise_fold_needs_1_le_units_le_terms")


def _batches(cfg, r, n_pixels: int) -> list[dict]:
    """The batches: k_used, the terms (a non-zero past k_used), pixels, the clock streams' style."""
    K = cfg.noise_terms
    below = [int(r.integers(1, K)) if K > 1 else 0 for _ in range(2)]
    plan = [(K, "plain"), (0, "plain"), (below[0], "plain"), (K, "back2back"), (below[1], "stalled"),
            (K, "reset"), (1, "plain")]
    out = []
    for ku, style in plan:
        a = []
        for k in range(K):
            v = rand_a(cfg, r) if r.random() > 0.1 else 0
            while k >= ku and v == 0:  # past k_used: non-zero, the fold must ignore it
                v = rand_a(cfg, r)
            a.append(v)
        m = max(2, int(n_pixels * r.uniform(0.5, 1.5)))
        out.append({"k_used": ku, "a": a, "T": [rand_T(cfg, r) for _ in range(K)], "o": [rand_o(cfg, r) for _ in range(K)],
                    "te": [int(r.integers(0, cfg.d["te_max"] + 1)) for _ in range(K)],
                    "ae": [int(r.integers(0, cfg.d["ae_max"] + 1)) for _ in range(K)],
                    "s": rand_s(cfg, r, m), "style": style})
    return out


def _streams(cfg, b: dict, rr: random.Random) -> tuple[list, list, list, dict]:
    """(in_valid, ce, rst) per clock of a batch and its schedule (golden noise_fold_schedule):
    every pixel taken, the last one's sums shown, then two enabled idle clocks (sum_valid low
    again: the next batch starts from an empty fold)."""
    m, style = len(b["s"]), b["style"]
    stall_on, stall_stay, gap = {"plain": (0.2, 0.6, 0.3), "back2back": (0.0, 0.0, 0.0),
                                 "stalled": (0.5, 0.7, 0.2), "reset": (0.2, 0.5, 0.3)}[style]
    n = 4 * (m * clocks_per_sample(cfg, b["k_used"]) + 40)
    while True:
        ce, stalled = [], False
        for _ in range(n):
            stalled = rr.random() < (stall_stay if stalled else stall_on)
            ce.append(0 if stalled else 1)
        iv = [0 if rr.random() < gap else 1 for _ in range(n)]
        rst = [1 if style == "reset" and rr.random() < 0.02 else 0 for _ in range(n)]
        if style == "reset":  # and one on an enabled clock of a pixel's last issue (its sums must never show)
            lasts = [t for t in np.flatnonzero(G.noise_fold_schedule(cfg, b["k_used"], iv, ce, rst)["px_valid"])
                     if ce[t]]
            if lasts:
                rst[lasts[len(lasts) // 4]] = 1
        sch = G.noise_fold_schedule(cfg, b["k_used"], iv, ce, rst)
        takes = np.flatnonzero(sch["take"])
        if len(takes) < m:
            n *= 2
            continue
        t_m = int(takes[m - 1])  # the last pixel's take: no offer and no reset after it
        iv = iv[:t_m + 1] + [0] * (n - t_m - 1)
        rst = rst[:t_m + 1] + [0] * (n - t_m - 1)
        sch = G.noise_fold_schedule(cfg, b["k_used"], iv, ce, rst)
        shown = np.flatnonzero(sch["sum_px"] == m - 1)
        if not len(shown):
            n *= 2
            continue
        end = int(shown[0])
        ce_after = np.flatnonzero(np.asarray(ce[end + 1:]) == 1)
        if len(ce_after) < 2:
            n *= 2
            continue
        end += int(ce_after[1]) + 2
        sch = {k: v[:end] for k, v in sch.items()}
        return iv[:end], ce[:end], rst[:end], sch


@cocotb.test()
async def noise_fold_bit_exact(dut):
    cfg = pipe.cfg()
    p = pipe.block_params()
    K, U, side_w = p["NOISE_TERMS"], p["NOISE_UNITS"], p["SIDE_W"]
    assert (K, U) == (cfg.noise_terms, cfg.noise_units)
    r = pipe.rng(29)
    rr = random.Random(int(r.integers(1 << 30)))
    batches = _batches(cfg, r, min(pipe.n_vectors(), 60))
    s_mask = (1 << (3 * cfg.s_w)) - 1
    got = {k: [] for k in ("ready", "held", "sv", "sum")}
    exp = {k: [] for k in got}
    where = {k: [] for k in got}
    await pipe.start(dut)
    dut.s_in.value = 0
    dut.side_in.value = 0
    for bi, b in enumerate(batches):
        tex = SimpleNamespace(k_used=b["k_used"], a=b["a"], T=b["T"], o=b["o"], te=b["te"], ae=b["ae"])
        f_exp, c_exp = G.noise_fold(cfg, tex, b["s"])
        s_words = [pipe.pack(v, cfg.s_w) for v in b["s"]]
        sides = [rr.getrandbits(side_w) for _ in s_words]
        iv, ce, rst, sch = _streams(cfg, b, rr)
        dut.k_used.value = b["k_used"]
        dut.a_all.value = pipe.pack_a_all(cfg, b["a"], b["ae"])
        dut.t_all.value = pipe.pack_t_all(cfg, b["T"], b["te"])
        dut.o_all.value = pipe.pack([int(v) for o in b["o"] for v in o], cfg.o_w)
        taken = 0
        for t in range(len(iv)):
            if iv[t]:
                dut.s_in.value, dut.side_in.value = s_words[taken], sides[taken]
            else:
                dut.s_in.value, dut.side_in.value = rr.getrandbits(3 * cfg.s_w), rr.getrandbits(side_w)
            dut.in_valid.value, dut.ce.value, dut.rst.value = iv[t], ce[t], rst[t]
            taken += int(sch["take"][t])
            at = f"batch {bi} (k_used {b['k_used']}, {b['style']}) clock {t}"
            await ReadOnly()  # during clock t: in_ready, px_* (functions of registers and k_used)
            got["ready"].append((int(dut.in_ready.value), int(dut.px_valid.value)))
            exp["ready"].append((int(sch["in_ready"][t]), int(sch["px_valid"][t])))
            where["ready"].append(at)
            if sch["px"][t] >= 0:
                i = int(sch["px"][t])
                got["held"].append((int(dut.px_s.value), int(dut.px_side.value)))
                exp["held"].append((s_words[i] & s_mask, sides[i]))
                where["held"].append(f"{at}, pixel {i}")
            await RisingEdge(dut.clk)
            await ReadOnly()  # after edge t: sum_valid, f_sum, c_sum
            got["sv"].append(int(dut.sum_valid.value))
            exp["sv"].append(int(sch["sum_valid"][t]))
            where["sv"].append(at)
            if sch["sum_valid"][t]:
                i = int(sch["sum_px"][t])
                got["sum"].append((pipe.to_signed(int(dut.f_sum.value), cfg.f_w),
                                   *pipe.unpack(int(dut.c_sum.value), cfg.c_w, 3)))
                exp["sum"].append((int(f_exp[i]), *(int(v) for v in c_exp[i])))
                where["sum"].append(f"{at}, pixel {i} s={b['s'][i].tolist()}")
            await Timer(1, unit="ns")
        assert taken == len(s_words), f"batch {bi}: {taken} of {len(s_words)} pixels taken"
    dut.rst.value = 0
    assert len(got["sum"]) > sum(len(b["s"]) for b in batches) // 2, "too few sums shown"
    for k, what in (("ready", "in_ready, px_valid"), ("held", "px_s, px_side"), ("sv", "sum_valid"),
                    ("sum", "f_sum, c_sum")):
        pipe.check_equal(dut, got[k], exp[k], lambda i, k=k: where[k][i], f"noise_fold {cfg.name} {what}")
