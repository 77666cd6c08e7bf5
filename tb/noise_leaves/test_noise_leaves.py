"""noise_leaves (rtl/noise_leaves.v) bit-exact against golden noise_leaves(..., skip=False):
every leaf of f and c, the valid bit and the latency.

Configurations (unfolded: the K noise_term instances): full (eight terms, affine, the noise
gradient), reduced (two terms, diagonal quadric, no noise gradient: the c leaves are 0),
random:8 (sat_fc: each term faded by its alpha, fc_scale), random:10 (fpga_regs) and full_q12s12
(full on s12.10 and q12.11, Icarus: the one configuration here where q's leaf is sign-extended
into f, F_W 21 > QF_W 20; no named or random configuration has F_W > QF_W); full_exp and exp1370 carry per-term exponents ({te_k, T_k} in t_all, {ae_k, a_k} in a_all: each
term's drawn 0, the largest, or uniform); LATENCY
the terms' own, and (full: two, random:8 and exp1370: one) more (the delay lines of a slower quadric). The folded path (noise_fold's
sum, one leaf, passed through) is covered by tb/frame's folded configurations. random:3 has
K = 0: the quadric's leaf alone, combinational (q_valid toggled: out_valid follows it).

Stimulus: batches (tb/pipe.py run_batches, random ce stalls and input gaps, drained between
batches), each with its own parameters: k_used 0..K, per term a, T, o as tb/noise_term draws
them (a share of a = 0), q and grad q uniform over their words (held for the batch: the
leaves are combinational in them), alpha uniform over u1.FC_AF; s as tb/noise_term draws it.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import cocotb

import hdlbuild
from model.hw import golden as G
from model.hw.config import ROOT, folded, freq_clamp, latency, load_config, variant
from tb import pipe
from tb.noise_term.test_noise_term import rand_a, rand_o, rand_s, rand_T

SOURCES = ["noise_leaves.v", "noise_term.v", "noise_params.v", "noise_xform.v", "noise_grad.v", "noise_hash.v", "noise_blend.v",
           "lerp.v", "fc_scale.v", "delay_line.v"]
CONFIGS = (("full", 0), ("full", 2), ("reduced", 0), ("random:8", 0), ("random:8", 1), ("random:10", 0),
           ("random:3", 0), ("full_q12s12", 0), ("full_exp", 0), ("exp1370", 1))
# configurations of this testbench's own (a narrow s and q: q's sign extension, FX_Q > 0), and with
# per-term exponents (tb/pipe.py exponent_configs: full_exp, full with t_exp_w = 1, a_exp_w = 2;
# exp1370, a random configuration (unfolded, fpga_regs) with the widest exponents its shifts allow)
OWN = {"full_q12s12": lambda: variant(load_config(str(ROOT / "config" / "candidates" / "full_narrow.toml")), "full_q12s12",
                                      s_w=12, q_w=12),  # full_narrow: full until issue 26 (s_frac < 12)
       **{n: (lambda c=c: c) for n, c in pipe.exponent_configs(1370)}}


def config_of(config):
    return OWN[config]() if config in OWN else hdlbuild.config_of(config)


def params(cfg, extra: int) -> dict:
    """texture_pipeline's parameters for noise_leaves (LATENCY: the terms' own plus `extra`)."""
    nt = {k: v for k, v in hdlbuild.block_params(cfg, "noise_term").items() if k != "PARAM_PIPE"}
    fc = 1 if freq_clamp(cfg) and cfg.noise_terms > 0 else 0
    lat = latency("noise_term", cfg) + (latency("fc_scale") if fc else 0) + extra
    return {**nt, "QUADRIC": 1 if cfg.quadric == "diagonal" else 0, "Q_W": cfg.q_w, "Q_FRAC": cfg.q_frac,
            "NOISE_TERMS": cfg.noise_terms, "NOISE_UNITS": cfg.noise_units, "FC": fc,
            "FC_LOG_FRAC": cfg.fc_log_frac, "FC_FADE_LOG2": cfg.fc_fade_log2, "LATENCY": lat}


def _cases():
    return [pytest.param(sim, c, x, id=f"{sim}-{c.replace(':', '')}-x{x}") for sim in ("icarus", "verilator")
            for c, x in CONFIGS if sim == "icarus" or (c, x) in (("full", 0), ("random:8", 1))]


@pytest.mark.parametrize("sim,config,extra", _cases())
def test_noise_leaves_rtl(sim, config, extra):
    cfg = config_of(config)
    assert not folded(cfg)
    pipe.run_block("noise_leaves", sim, f"{cfg.name}-x{extra}", params(cfg, extra), __file__, config=cfg,
                   sources=SOURCES)


def test_noise_leaves_check():
    """noise_leaves' elaboration-time check (g_bad_latency) both ways on full's parameters (8
    unfolded terms, FC 0, LATENCY = the terms' own LAT_NS: their wait DLY_N = 0): refused with both terms true (NLEAF > 0 and DLY_N < 0:
    LATENCY one below LAT_NS, with the terms alone, with sat_fc's fc_scale stage, FC 1, and folded,
    U 4 < K: noise_fold's stage); accepted at the edge DLY_N = 0 (each of the three) and with the
    second term alone true (K 0: no noise leaf, NLEAF 0, LATENCY below the terms')."""
    b = params(config_of("full"), 0)
    lat_nt = latency("noise_term")
    assert b["LATENCY"] == lat_nt and not b["FC"] and not b["FPGA_REGS"]
    lat_fc, lat_fold = lat_nt + latency("fc_scale"), lat_nt + latency("noise_fold")
    fold = {"NOISE_UNITS": 4}
    hdlbuild.check_refusals(
        "noise_leaves", SOURCES, b,
        accept={"full (DLY_N 0)": {}, "FC: DLY_N 0": {"FC": 1, "LATENCY": lat_fc},
                "folded: DLY_N 0": {**fold, "LATENCY": lat_fold},
                "K 0 (NLEAF 0), DLY_N < 0": {"NOISE_TERMS": 0, "LATENCY": lat_nt - 1}},
        refuse={"DLY_N < 0": {"LATENCY": lat_nt - 1}, "FC: DLY_N < 0": {"FC": 1, "LATENCY": lat_fc - 1},
                "folded: DLY_N < 0": {**fold, "LATENCY": lat_fold - 1}},
        error_module="noise_leaves_latency_below_the_terms")


@cocotb.test()
async def noise_leaves_bit_exact(dut):
    cfg = pipe.cfg()
    p = pipe.block_params()
    k, fc, lat = p["NOISE_TERMS"], p["FC"], p["LATENCY"]
    kv = max(k, 1)
    r = pipe.rng(71)
    ng = cfg.noise_gradient
    n_batches = max(2, pipe.n_vectors(400) // 100)
    re = np.random.default_rng([71, 29])  # the exponents' own generator: the other draws stay as without them
    s_all, batches, par, exp_f, exp_c = [], [], [], [], []
    for b in range(n_batches):
        m = int(r.integers(1, 200))
        s = rand_s(cfg, r, m)
        tex = SimpleNamespace(k_used=int(r.integers(0, k + 1)), a=[rand_a(cfg, r) if r.random() > 0.15 else 0 for _ in range(k)],
                              T=[rand_T(cfg, r) for _ in range(k)], o=[rand_o(cfg, r) for _ in range(k)],
                              te=np.array([pipe.rand_exp(re, cfg.d["te_max"]) for _ in range(k)], dtype=np.int64),
                              ae=np.array([pipe.rand_exp(re, cfg.d["ae_max"]) for _ in range(k)], dtype=np.int64))
        q = int(r.integers(-(1 << (cfg.qf_w - 1)), 1 << (cfg.qf_w - 1)))
        cq = r.integers(-(1 << (cfg.c_w - 1)), 1 << (cfg.c_w - 1), 3, dtype=np.int64)
        alpha = r.integers(0, (1 << cfg.fc_af) + 1, kv, dtype=np.int64)
        fl, cl = G.noise_leaves(cfg, tex, s, np.full(m, q, dtype=np.int64), np.tile(cq, (m, 1)),
                                np.tile(alpha[:k], (m, 1)) if fc else None, skip=False)
        start = len(s_all)
        s_all += [pipe.pack(v, cfg.s_w) for v in s]
        batches.append((start, start + m))
        par.append((tex, q, cq, alpha))
        for t in range(m):
            exp_f.append(tuple(int(x[t]) for x in fl))
            exp_c.append(tuple(int(v) for x in cl for v in x[t]))

    def set_params(b):
        tex, q, cq, alpha = par[[x for x, _ in batches].index(b)]
        dut.k_used.value = tex.k_used
        dut.a_all.value = pipe.pack_a_all(cfg, tex.a, tex.ae)
        dut.t_all.value = pipe.pack_t_all(cfg, tex.T, tex.te)
        dut.o_all.value = pipe.pack([int(v) for o in tex.o for v in o] or [0] * 3, cfg.o_w)
        dut.alpha.value = pipe.pack(alpha, cfg.fc_af + 1)
        dut.q_in.value = q & ((1 << cfg.qf_w) - 1)
        dut.cq_in.value = pipe.pack(cq, cfg.c_w)

    dut.q_valid.value = 1
    dut.fold_valid.value = 0
    dut.fold_f.value = 0
    dut.fold_c.value = 0

    def sample():
        f = tuple(pipe.unpack(int(dut.f_leaves.value), cfg.f_w, k + 1))
        c = tuple(pipe.unpack(int(dut.c_leaves.value), cfg.c_w, 3 * (k + 1)))
        return f + c

    await pipe.start(dut)
    if k == 0:  # the quadric's leaf alone: combinational, out_valid = q_valid
        set_params(0)

        def apply(t):
            dut.q_in.value = int(q_all[t]) & ((1 << cfg.qf_w) - 1)
            dut.cq_in.value = pipe.pack(cq_all[t], cfg.c_w)
            dut.q_valid.value = t & 1

        def sample_v():
            assert int(dut.out_valid.value) == int(dut.q_valid.value), "K = 0: out_valid is not q_valid"
            return sample()

        q_all = r.integers(-(1 << (cfg.qf_w - 1)), 1 << (cfg.qf_w - 1), 200, dtype=np.int64)
        cq_all = r.integers(-(1 << (cfg.c_w - 1)), 1 << (cfg.c_w - 1), (200, 3), dtype=np.int64)
        fl, cl = G.noise_leaves(cfg, SimpleNamespace(k_used=0, a=[], T=[], o=[], te=[], ae=[]), np.zeros((200, 3), dtype=np.int64),
                                q_all, cq_all, skip=False)
        exp = [(int(fl[0][t]),) + tuple(int(v) for v in cl[0][t]) for t in range(200)]
        got = await pipe.run_comb(dut, apply, sample_v, 200)
        pipe.check_equal(dut, got, exp, lambda t: f"q={int(q_all[t])}", f"noise_leaves {cfg.name} K = 0")
        return
    got = await pipe.run_batches(dut, batches, set_params, {"s_in": s_all}, sample, latency=lat,
                                 junk={"s_in": 3 * cfg.s_w}, seed=k * 13 + lat)
    exp = [f + c for f, c in zip(exp_f, exp_c)]
    pipe.check_equal(dut, got, exp, lambda t: f"s={s_all[t]:#x}", f"noise_leaves {cfg.name} LATENCY {lat} (ng {ng})")
