"""texture_sum (rtl/texture_sum.v) bit-exact against golden texture_sum: f (out_valid, latency
LATENCY = hdlbuild.params.texture_sum_latency), grad f (c_valid: with the noise gradient at
f's latency, without it at the quadric's, `LAT_QUADRIC_MAC) and sat_fc's wv (`LAT_FC_WEIGHT
after the input), every bit; out_valid and c_valid exactly once a vector.

Configurations (texture_pipeline's parameters for the block, hdlbuild block_params): full
(eight affine terms, the noise gradient: the c tree), reduced (two terms, diagonal quadric,
no noise gradient: c is the quadric's, q waits for the terms), full_fc (sat_fc: fc_weight's
fades and wv), reduced with fpga_regs, random:3 (no noise term: the quadric's leaf alone), and
with per-term exponents (tb/pipe.py exponent_configs; {te_k, T_k} in t_all, {ae_k, a_k} in a_all, each
term's drawn 0, the largest, or uniform) full_exp (full with t_exp_w = 1, a_exp_w = 2) and exp1370
(four unfolded terms, fpga_regs, t_exp_w 3, a_exp_w 1).
The folded terms (noise_fold's sum, a leaf passed through noise_leaves) are covered by
tb/frame's folded configurations (compact).

Stimulus: batches (tb/pipe.py run_batches: random ce stalls and input gaps, drained between
batches), each with its own parameters: Q as tb/quadric_mac draws it (with a diagonal quadric
B, C, F random too: texture_sum must not pass them on), k_used 0..K, a, T, o as tb/noise_term
draws them (a share of a = 0), filter_en and n_log2 random; s as tb/noise_term draws it; Jm,
je uniform, with sat_fc as tb/fc_weight draws them (je sweeping each term's fade).
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

import cocotb
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge

from hdlbuild import config_of
from hdlbuild.params import block_params, latency
from model.hw import golden as G
from tb import pipe
from tb.fc_weight.test_fc_weight import make_pixels
from tb.noise_term.test_noise_term import rand_a, rand_o, rand_s, rand_T
from tb.quadric_mac.test_quadric_mac import rand_Q

CONFIGS = {"full": "full", "reduced": "reduced", "full_fc": "full_fc", "reduced_fpga": "fpga_regs:reduced",
           "k0": "random:3", **{n: c for n, c in pipe.exponent_configs(1370) if n in ("full_exp", "exp1370")}}
SOURCES = ["texture_sum.v", "quadric_mac.v", "qmac_full.v", "qmac_diag.v", "qmac_diag_fold.v", "qmac_diag_serial.v", "qmac_diag_pipe.v",
           "mul_pipe.v", "noise_leaves.v", "noise_term.v", "noise_params.v", "noise_xform.v", "noise_grad.v", "noise_hash.v",
           "noise_blend.v", "lerp.v", "fc_scale.v", "fc_weight.v", "bitlen.v", "sum_tree.v", "delay_line.v"]

# every set under Icarus; under Verilator (a build of eight noise terms costs a minute) reduced's
test_texture_sum_rtl = pipe.block_test("texture_sum", {n: block_params(config_of(c), "texture_sum")
                                                       for n, c in CONFIGS.items()},
                                       ("reduced_fpga",), __file__, config=CONFIGS, sources=SOURCES)


def test_texture_sum_check():
    """texture_sum's elaboration-time check (g_bad_latency) both ways: refused on full's parameters
    with LATENCY one above and one below its blocks' (LAT_FRONT + TREE_LEVELS = 10: the terms' 8,
    the tree's 2 levels over 9 leaves); accepted on the LATENCY of each of this testbench's
    configurations (full; full_fc: fc_scale's stage; reduced_fpga: the FPGA stages, folded; k0: no
    noise term, the quadric's latency and one leaf)."""
    import hdlbuild

    ps = {n: block_params(config_of(CONFIGS[n]), "texture_sum") for n in ("full", "full_fc", "reduced_fpga", "k0")}
    b = ps["full"]
    hdlbuild.check_refusals(  # each case a whole parameter set (the module's defaults beneath)
        "texture_sum", SOURCES, {},
        accept=ps,
        refuse={"LATENCY > LAT_FRONT + TREE_LEVELS": {**b, "LATENCY": b["LATENCY"] + 1},
                "LATENCY < LAT_FRONT + TREE_LEVELS": {**b, "LATENCY": b["LATENCY"] - 1}},
        error_module="texture_sum_latency_must_be_its_blocks")


def _int(sig):
    v = sig.value
    return int(v) if v.is_resolvable else None


async def _monitor(dut, rows, stop):
    """Every clock edge: (ce, in_valid, c_valid, c_out, wv_out): the inputs the edge takes (read
    half a clock before it: the stimulus writes them at or just after the edge before), the
    outputs after it."""
    while not stop:
        await FallingEdge(dut.clk)
        ce, iv = int(dut.ce.value), int(dut.in_valid.value)
        await RisingEdge(dut.clk)
        await ReadOnly()
        rows.append((ce, iv, _int(dut.c_valid), _int(dut.c_out), _int(dut.wv_out)))


def _batch(cfg, r, fc: bool, m: int, re):
    """One pass: its parameters (a TexInt-like namespace) and m pixels (s, Jm, je); re draws the
    exponents (a generator of their own: the other draws stay as without them)."""
    k = cfg.noise_terms
    tex = SimpleNamespace(Q=rand_Q(cfg, r), k_used=int(r.integers(0, k + 1)) if r.random() < 0.5 else k,
                          a=np.array([rand_a(cfg, r) if r.random() > 0.15 else 0 for _ in range(k)], dtype=np.int64),
                          T=np.array([rand_T(cfg, r) for _ in range(k)], dtype=np.int64).reshape(k, 3, 3),
                          o=np.array([rand_o(cfg, r) for _ in range(k)], dtype=np.int64).reshape(k, 3),
                          te=np.array([pipe.rand_exp(re, cfg.d["te_max"]) for _ in range(k)], dtype=np.int64),
                          ae=np.array([pipe.rand_exp(re, cfg.d["ae_max"]) for _ in range(k)], dtype=np.int64),
                          filter=bool(r.random() < 0.8), n_log2=int(r.integers(0, cfg.n_log2_max + 1)))
    # the RTL's coefficients: a diagonal quadric's B, C, F random (not to be passed on), the twin's 0
    tex.q_rtl = tex.Q.copy()
    if cfg.quadric == "diagonal":
        tex.Q[[1, 2, 5]] = 0
    s = rand_s(cfg, r, m)
    if fc:
        Jm, je = make_pixels(cfg, r, tex, m)
    else:
        Jm = r.integers(-(1 << (cfg.j_w - 1)), 1 << (cfg.j_w - 1), (m, 3, 2), dtype=np.int64)
        je = r.integers(cfg.je_min, cfg.je_max + 1, m, dtype=np.int64)
    return tex, s, Jm, je


@cocotb.test()
async def texture_sum_bit_exact(dut):
    cfg = pipe.cfg()
    p = pipe.block_params()
    k, fc, lat = p["NOISE_TERMS"], p["FC"], p["LATENCY"]
    lat_c = lat if cfg.noise_gradient else latency("quadric_mac", cfg)
    lat_wv = latency("fc_weight")
    r = pipe.rng(83)
    re = np.random.default_rng([83, 29])
    vec = {"s_in": [], "jm_in": [], "je_in": []}
    batches, par, exp = [], [], []
    for _ in range(max(2, pipe.n_vectors(300) // 100)):
        m = int(r.integers(20, 120))
        tex, s, Jm, je = _batch(cfg, r, bool(fc), m, re)
        f, c, wv = G.texture_sum(cfg, tex, s, Jm, je)
        wv = np.zeros(m, dtype=np.int64) if wv is None else wv
        start = len(vec["s_in"])
        vec["s_in"] += [pipe.pack(v, cfg.s_w) for v in s]
        vec["jm_in"] += [pipe.pack(v.reshape(-1), cfg.j_w) for v in Jm]
        vec["je_in"] += [int(v) & ((1 << cfg.je_w) - 1) for v in je]
        batches.append((start, start + m))
        par.append(tex)
        exp += [(int(f[t]), *(int(v) for v in c[t]), int(wv[t])) for t in range(m)]

    def set_params(b):
        tex = par[[x for x, _ in batches].index(b)]
        dut.q_coef.value = pipe.pack(tex.q_rtl, cfg.q_w)
        dut.k_used.value = tex.k_used
        dut.a_all.value = pipe.pack_a_all(cfg, tex.a, tex.ae)
        dut.t_all.value = pipe.pack_t_all(cfg, tex.T, tex.te)
        dut.o_all.value = pipe.pack(list(tex.o.reshape(-1)) or [0] * 3, cfg.o_w)
        dut.filter_en.value = int(tex.filter)
        dut.n_log2.value = tex.n_log2

    dut.fold_valid.value = 0
    dut.fold_f.value = 0
    dut.fold_c.value = 0
    set_params(0)
    await pipe.start(dut)
    rows, stop = [], []
    cocotb.start_soon(_monitor(dut, rows, stop))
    got_f = await pipe.run_batches(dut, batches, set_params, vec, lambda: pipe.to_signed(int(dut.f_out.value), cfg.f_w),
                                   latency=lat, junk={"s_in": 3 * cfg.s_w, "jm_in": 6 * cfg.j_w, "je_in": cfg.je_w},
                                   seed=k * 17 + lat)
    await RisingEdge(dut.clk)
    stop.append(True)
    # c and wv at their own latencies: the outputs after enabled edge E + L - 1 of a vector
    # that entered at enabled edge E
    enabled, issued, snap = 0, [], {}
    for ce, iv, cv, c, wv in rows:
        if ce:
            enabled += 1
            if iv:
                issued.append(enabled)
            snap[enabled] = (cv, c, wv)
    assert len(issued) == len(exp), f"{len(issued)} vectors entered, {len(exp)} sent"
    due = {e + lat_c - 1 for e in issued}
    extra = sorted(e for e, (cv, _, _) in snap.items() if cv and e not in due)
    assert not extra, f"c_valid with no vector due (after enabled edges {extra[:5]})"
    got = []
    for f, e in zip(got_f, issued):
        cv, c, _ = snap[e + lat_c - 1]
        got.append((f, *(pipe.unpack(c, cfg.c_w, 3) if cv and c is not None else (None,) * 3),
                    snap[e + lat_wv - 1][2] if fc else 0))
    pipe.check_equal(dut, got, exp, lambda t: f"s={vec['s_in'][t]:#x} jm={vec['jm_in'][t]:#x} je={vec['je_in'][t]}",
                     f"texture_sum {cfg.name} (latency f {lat}, c {lat_c}; K {k}, fc {fc})")
