"""quadric_mac: bit-exact against model/hw/golden.py quadric_mac, every output bit.

Parameters: q_coef is a per-pass parameter (rtl/quadric_mac.v reads it directly at
the stage that needs it, no pipeline registers). The interface contract: it is stable
from the first vector's entry until the last vector's exit (texture_pipeline writes
parameters only while the pipeline is empty). So the stimulus is a sequence of
batches, each with its own Q: a batch is streamed with random ce stalls and input
gaps (tb/pipe.py run_vectors), drained completely (every output out), then the inputs
idle through a few clocks of random unrelated values with in_valid = 0 (nothing may
latch them), the next batch's Q is applied, and the next batch starts.

Stimulus: batches of 1..256 vectors (log-uniform: short fill/drain batches and long
full-pipeline batches) sharing a random quadric Q, Q and s each drawn half over the
full range of their formats and half from realistic small ranges (|Q| <= 4,
|s| <= 8). Then
the hard cases of DESIGN.md that concern this block, as explicit vectors:
coordinates at the most negative and most positive values of the format and
negative coordinates, an all-zero quadric, maximal coefficients (every sign
pattern of Q at its extremes aligned with s at its extremes, so v, q and 2 Q x
reach the extremes of their words), coordinates with a fraction of exactly 0 and
just below 1 (k 2^s_frac and k 2^s_frac - 1, both signs), identity-like quadrics.

Each hard case group with its own Q is its own batch.
Expected values: golden quadric_mac per batch, vectorized over the batch. The
golden itself is checked against plain Python integer arithmetic (no int64) and
every intermediate against its word width (v_w, qv_w, qf_w, c_w): the widths of
model/hw/config.py must hold the extremes.
"""
from __future__ import annotations

import math
import os

import numpy as np
import pytest

import cocotb

import hdlbuild
from model.hw import golden as G
from tb import pipe

SOURCES = ["quadric_mac.v", "qmac_full.v", "qmac_diag.v", "qmac_diag_fold.v", "qmac_diag_serial.v", "qmac_diag_pipe.v", "mul_pipe.v",
           "delay_line.v"]
MAX_BATCH = 256  # random batches: 1..MAX_BATCH vectors, log-uniform


def latency(cfg) -> int:
    """`LAT_QUADRIC_MAC (fpga_regs: `LAT_QUADRIC_MAC_FPGA) from rtl/tex_latency.vh (the block must
    match it)."""
    return hdlbuild.latency("quadric_mac", cfg)


@pytest.mark.parametrize("sim,config", hdlbuild.family_params(fpga_regs=True))
def test_quadric_mac_rtl(sim, config):
    pipe.run_block("quadric_mac", sim, test_file=__file__, config=config, sources=SOURCES)


# quadric_clocks = 6 (qmac_diag_serial, a vector every sixth clock): compact's formats, and with
# fpga_regs (qmac_diag_pipe: the FPGA does not fold the products)
@pytest.mark.parametrize("sim,config", [("icarus", "config/candidates/compact_q6.toml"),
                                        ("verilator", "config/candidates/compact_q6.toml"),
                                        ("icarus", "fpga_regs:config/candidates/compact_q6.toml")])
def test_quadric_mac_serial_rtl(sim, config):
    pipe.run_block("quadric_mac", sim, test_file=__file__, config=config, sources=SOURCES)


# random:6 (full quadric, fpga_regs): C_W > V_W + CSH, so the sign extension of v_k reaches grad q's
# top bits (27 of the named and random:0..399 configurations; none of family_params' draws)
@pytest.mark.parametrize("config", ["random:6"])
def test_quadric_mac_c_sign_rtl(config):
    pipe.run_block("quadric_mac", "icarus", test_file=__file__, config=config, sources=SOURCES)


def test_quadric_mac_check():
    """quadric_mac's elaboration-time check (g_bad_clocks) both ways on full's parameters (full
    quadric, CLOCKS 1): refused with CLOCKS != 1 and each inner term alone true (CLOCKS 2 or 6 on
    the full quadric: DIAG == 0; CLOCKS 3 on the diagonal one: neither 2 nor 6; likewise CLOCKS 0);
    accepted on CLOCKS 1 (full and diagonal) and CLOCKS 2 and 6 on the diagonal quadric (the folds). (g_bad_latency
    compares rtl/tex_latency.vh's latencies of the chosen datapath: no parameter set makes it true.)"""
    b = hdlbuild.block_params(hdlbuild.config_of("full"), "quadric_mac")
    assert b["DIAG"] == 0 and b["CLOCKS"] == 1
    hdlbuild.check_refusals(
        "quadric_mac", SOURCES, b,
        accept={"full, CLOCKS 1": {}, "diagonal, CLOCKS 1": {"DIAG": 1},
                "diagonal, CLOCKS 2": {"DIAG": 1, "CLOCKS": 2}, "diagonal, CLOCKS 6": {"DIAG": 1, "CLOCKS": 6}},
        refuse={"CLOCKS 2, full (DIAG == 0)": {"CLOCKS": 2}, "CLOCKS 6, full (DIAG == 0)": {"CLOCKS": 6},
                "CLOCKS 3, diagonal (not 2 or 6)": {"DIAG": 1, "CLOCKS": 3},
                "CLOCKS 0, diagonal": {"DIAG": 1, "CLOCKS": 0}},
        error_module="quadric_mac_clocks_must_be_1_or_2_or_6_diagonal")


# ---------------------------------------------------------------------------
# Stimulus


def _lim(w):
    return -(1 << (w - 1)), (1 << (w - 1)) - 1


def _uniform(r, lo, hi, size=None):
    return r.integers(lo, hi + 1, size=size, dtype=np.int64)


class Vectors:
    """Per-vector s and the Q of its group."""

    def __init__(self, diagonal=False):
        self.diagonal = diagonal
        self.s, self.Q, self.group, self.tag = [], [], [], []
        self.n_groups = 0

    def add(self, Q, s_rows, tag):
        g = self.n_groups
        self.n_groups += 1
        Q = np.asarray(Q, dtype=np.int64).reshape(10).copy()
        if self.diagonal:
            Q[[1, 2, 5]] = 0  # B, C, F: a diagonal-quadric configuration takes axis-aligned quadrics only
        for s in np.asarray(s_rows, dtype=np.int64).reshape(-1, 3):
            self.s.append(s)
            self.Q.append(Q)
            self.group.append(g)
            self.tag.append(tag)

    def arrays(self):
        return (np.array(self.s, dtype=np.int64).reshape(-1, 3), np.array(self.Q, dtype=np.int64).reshape(-1, 10),
                np.array(self.group, dtype=np.int64))


def rand_Q(cfg, r):
    lo, hi = _lim(cfg.q_w)
    if r.random() < 0.5:
        return _uniform(r, lo, hi, 10)
    big = 1 << (cfg.q_frac + 2)  # |Q| <= 4: realistic quadrics (spheres, planes, cylinders)
    Q = _uniform(r, max(lo, -big), min(hi, big), 10)
    if r.random() < 0.3:
        Q[[1, 2, 5]] = 0  # axis-aligned
    return Q


def rand_s(cfg, r, m):
    lo, hi = _lim(cfg.s_w)
    full = _uniform(r, lo, hi, (m, 3))
    small = 1 << (cfg.s_frac + 3)  # |s| <= 8
    near = _uniform(r, max(lo, -small), min(hi, small), (m, 3))
    return np.where((r.random(m) < 0.5)[:, None], full, near)


# index of Q[k][j] in (A..J): Q = [[A B C D] [B E F G] [C F H I] [D G I J]]
QIDX = ((0, 1, 2, 3), (1, 4, 5, 6), (2, 5, 7, 8), (3, 6, 8, 9))


def aligned_Q(cfg, s, sign):
    """Q at its extremes with every term of x^T Q x of sign `sign` for x = (s, 1): |q| maximal."""
    qlo, qhi = _lim(cfg.q_w)
    x = [int(s[0]), int(s[1]), int(s[2]), 1]
    Q = np.zeros(10, dtype=np.int64)
    for k in range(4):
        for j in range(k, 4):
            p = x[k] * x[j]
            want = sign * (1 if p >= 0 else -1)
            Q[QIDX[k][j]] = qhi if want > 0 else qlo
    return Q


def build_vectors(cfg, r, n_random):
    v = Vectors(diagonal=cfg.quadric == "diagonal")
    slo, shi = _lim(cfg.s_w)
    qlo, qhi = _lim(cfg.q_w)
    one_s, one_q = 1 << cfg.s_frac, 1 << cfg.q_frac
    ext = [slo, shi, slo + 1, shi - 1, 0, -1, 1]

    # ---- hard cases
    # s at its extremes (every combination of ext), under random, zero, and extreme quadrics
    rows = np.array([[a, b, c] for a in ext for b in ext for c in ext], dtype=np.int64)
    v.add(np.zeros(10), rows, "Q=0")
    v.add(rand_Q(cfg, r), rows, "extreme s")
    v.add(np.full(10, qlo), rows, "Q=min")
    v.add(np.full(10, qhi), rows, "Q=max")
    # all-zero quadric on random coordinates
    v.add(np.zeros(10), rand_s(cfg, r, 32), "Q=0")
    # maximal coefficients: every sign pattern of s at its extremes, Q aligned for |q| max (both signs)
    corners = [[a, b, c] for a in (slo, shi) for b in (slo, shi) for c in (slo, shi)]
    for s in corners:
        for sign in (1, -1):
            v.add(aligned_Q(cfg, s, sign), [s], "aligned extremes")
    # v_k extremes: one row of Q at its extremes against s at its extremes, the rest random
    for s in corners[:4]:
        for sign in (1, -1):
            Q = rand_Q(cfg, r)
            for k in range(4):
                for j in range(3):
                    p = int(s[j])
                    Q[QIDX[k][j]] = qhi if sign * p >= 0 else qlo
                Q[QIDX[k][3]] = qhi if sign > 0 else qlo
            v.add(Q, [s], "v extremes")
    # random mixtures of extreme coefficients and extreme coordinates
    for _ in range(16):
        Q = r.choice(np.array([qlo, qhi, 0, -1, 1], dtype=np.int64), 10)
        v.add(Q, r.choice(np.array(ext, dtype=np.int64), (8, 3)), "mixed extremes")
    # fractions of exactly 0 and just below 1: k 2^s_frac, k 2^s_frac - 1, k 2^s_frac + 1, both signs
    kmax = shi >> cfg.s_frac
    ks = [-kmax - 1, -kmax, -3, -2, -1, 0, 1, 2, 3, kmax]
    vals = sorted({int(np.clip(x, slo, shi)) for k in ks for x in (k * one_s, k * one_s - 1, k * one_s + 1)})
    rows = [[vals[i], vals[(i + 7) % len(vals)], vals[(3 * i + 2) % len(vals)]] for i in range(len(vals))]
    rows += [[x, x, x] for x in vals]
    rows += [[x, 0, 0] for x in vals] + [[0, x, 0] for x in vals] + [[0, 0, x] for x in vals]
    unit_sphere = np.array([one_q, 0, 0, 0, one_q, 0, 0, one_q, 0, -one_q], dtype=np.int64)  # s^2+t^2+r^2-1
    for Q in (unit_sphere, rand_Q(cfg, r), np.full(10, one_q), np.full(10, -one_q),
              np.array([0, 0, 0, one_q, 0, 0, 0, 0, 0, 0]), np.array([0] * 9 + [qhi]),
              np.array([0] * 9 + [qlo])):
        v.add(Q, rows, "fraction 0 / just below 1")
    # coefficients with fraction 0 and just below 1 too, negative coordinates
    Qf = np.array([one_q - 1, -one_q, one_q + 1, -1, one_q - 1, 1, -one_q + 1, one_q, -1, one_q - 1])
    v.add(Qf, rand_s(cfg, r, 16), "Q fractions")
    v.add(Qf, -np.abs(rand_s(cfg, r, 16)), "negative s")
    n_hard = len(v.s)

    # ---- random batches of 1..MAX_BATCH vectors (log-uniform) sharing Q
    left = n_random
    while left > 0:
        m = min(left, int(math.exp(r.uniform(0.0, math.log(MAX_BATCH + 1)))))
        v.add(rand_Q(cfg, r), rand_s(cfg, r, m), "random")
        left -= m
    return v, n_hard


# ---------------------------------------------------------------------------
# Expected values


def batches(group):
    """(begin, end) index ranges of the consecutive vectors sharing one Q."""
    starts = np.flatnonzero(np.r_[True, group[1:] != group[:-1]])
    ends = np.r_[starts[1:], len(group)]
    return [(int(b), int(e)) for b, e in zip(starts, ends)]


def expected(cfg, s, Q, group):
    qf = np.zeros(len(s), dtype=np.int64)
    cq = np.zeros((len(s), 3), dtype=np.int64)
    for b, e in batches(group):
        assert (Q[b:e] == Q[b]).all()
        qf[b:e], cq[b:e] = G.quadric_mac(cfg, Q[b], s[b:e])
    return qf, cq


def _shift(x: int, n: int) -> int:
    return x << n if n >= 0 else x >> -n


def _fits(x: int, w: int) -> bool:
    return -(1 << (w - 1)) <= x < (1 << (w - 1))


def check_golden_bigint(cfg, s, Q, exp_qf, exp_cq):
    """Plain Python integers (unbounded): the golden's int64 never wraps and every word holds."""
    sf = cfg.s_frac
    bad = []
    for i in range(len(s)):
        A, B, C, D, E, F, Gc, H, I, J = (int(x) for x in Q[i])
        s0, s1, s2 = (int(x) for x in s[i])
        if cfg.quadric == "diagonal":
            assert B == C == F == 0
            v0, v1, v2 = ((A * s0) >> sf) + D, ((E * s1) >> sf) + Gc, ((H * s2) >> sf) + I
            x = (v0 + D, v1 + Gc, v2 + I)  # the second factors of q: V_W words in the RTL too
            q = ((s0 * x[0] + s1 * x[1] + s2 * x[2]) >> sf) + J
            words_v = (v0, v1, v2) + x
        else:
            v0 = ((A * s0 + B * s1 + C * s2) >> sf) + D
            v1 = ((B * s0 + E * s1 + F * s2) >> sf) + Gc
            v2 = ((C * s0 + F * s1 + H * s2) >> sf) + I
            v3 = ((D * s0 + Gc * s1 + I * s2) >> sf) + J
            q = ((s0 * v0 + s1 * v1 + s2 * v2) >> sf) + v3
            words_v = (v0, v1, v2, v3)
        qf = _shift(q, cfg.f_frac - cfg.q_frac)
        cq = [_shift(x, cfg.c_frac - cfg.q_frac + 1) for x in (v0, v1, v2)]
        ok = (all(_fits(x, cfg.v_w) for x in words_v) and _fits(q, cfg.qv_w) and _fits(qf, cfg.qf_w)
              and all(_fits(x, cfg.c_w) for x in cq))
        if not ok or qf != int(exp_qf[i]) or cq != [int(x) for x in exp_cq[i]]:
            bad.append((i, (words_v, q, qf, cq)))
    return bad


# ---------------------------------------------------------------------------
# cocotb tests


@cocotb.test()
async def reset_outputs(dut):
    """After reset: out_valid = 0 and every output bit 0 (no X)."""
    cfg = pipe.cfg()
    await pipe.start(dut)
    assert str(dut.out_valid.value) == "0"
    assert str(dut.q_out.value) == "0" * cfg.qf_w, f"q_out after reset: {dut.q_out.value}"
    assert str(dut.cq_out.value) == "0" * (3 * cfg.c_w), f"cq_out after reset: {dut.cq_out.value}"


@cocotb.test()
async def vectors_bit_exact(dut):
    """Hard cases plus n_vectors() random vectors, in drained batches with stalls and gaps."""
    cfg = pipe.cfg()
    r = pipe.rng(21)
    v, n_hard = build_vectors(cfg, r, pipe.n_vectors())
    s, Q, group = v.arrays()
    slo, shi = _lim(cfg.s_w)
    qlo, qhi = _lim(cfg.q_w)
    assert s.min() >= slo and s.max() <= shi and Q.min() >= qlo and Q.max() <= qhi, "stimulus outside its format"
    n = len(s)
    exp_qf, exp_cq = expected(cfg, s, Q, group)
    bad = check_golden_bigint(cfg, s, Q, exp_qf, exp_cq)
    for i, vals in bad[:5]:
        dut._log.error(f"golden vs big-int / word widths, vector {i} [{v.tag[i]}]: s={s[i].tolist()} "
                       f"Q={Q[i].tolist()}: golden qf={exp_qf[i]} cq={exp_cq[i].tolist()}, "
                       f"big-int (v0..v3, q, qf, cq)={vals}")
    assert not bad, f"{len(bad)} vectors where the golden model wraps or a word width of model/hw/config.py overflows"
    bs = batches(group)
    sizes = [e - b for b, e in bs]
    dut._log.info(f"{cfg.name}: {n} vectors ({n_hard} hard cases) in {len(bs)} batches "
                  f"(1 Q each, sizes {min(sizes)}..{max(sizes)}); "
                  f"|qf| max 2^{np.log2(max(1, np.abs(exp_qf).max())):.2f} of qf_w {cfg.qf_w}, "
                  f"|cq| max 2^{np.log2(max(1, np.abs(exp_cq).max())):.2f} of c_w {cfg.c_w}")

    s_p = [pipe.pack(x, cfg.s_w) for x in s]

    def sample():
        return int(dut.q_out.value), int(dut.cq_out.value)

    def params(b):
        dut.q_coef.value = pipe.pack(Q[b], cfg.q_w)

    await pipe.start(dut)
    got = await pipe.run_batches(
        dut, bs, params, {"s_in": s_p}, sample, latency(cfg),
        junk={"s_in": 3 * cfg.s_w, "q_coef": 10 * cfg.q_w},
        seed=int(os.environ.get("SEED", "1")), spacing=cfg.quadric_clocks)  # CLOCKS = 2: every other clock
    assert len(got) == n
    got_qf = np.array([pipe.to_signed(g[0], cfg.qf_w) for g in got], dtype=np.int64)
    got_cq = np.array([pipe.unpack(g[1], cfg.c_w, 3) for g in got], dtype=np.int64)
    bad = np.flatnonzero((got_qf != exp_qf) | (got_cq != exp_cq).any(axis=1))
    for i in bad[:10]:
        dut._log.error(f"vector {i} [{v.tag[i]}]: s={s[i].tolist()} Q={Q[i].tolist()}: "
                       f"expected q={exp_qf[i]} cq={exp_cq[i].tolist()}, got q={got_qf[i]} cq={got_cq[i].tolist()}")
    assert len(bad) == 0, f"{len(bad)} of {n} vectors differ from golden quadric_mac (first at {bad[0]})"


# ---------------------------------------------------------------------------
# The datapaths (rtl/qmac_full.v, qmac_diag.v, qmac_diag_fold.v, qmac_diag_pipe.v): their
# testbenches (tb/qmac_*/) share the parameter sets and the check below.

DP_KEYS = {"S_W": "s_w", "S_FRAC": "s_frac", "Q_W": "q_w"}


def datapath_sets(configs, seeds, edges: dict, fpga=()) -> dict:
    """{name: HDL parameters} of a datapath: (S_W, S_FRAC, Q_W) of the named `configs` and of
    the random valid configurations `seeds`, plus `edges` ({name: (S_W, S_FRAC, Q_W)}); the
    sets named in `fpga` also with FPGA_REGS = 1 (qmac_full), as <name>_fpga."""
    from model.hw.config import load_config, random_config

    cfgs = [(n, load_config(n)) for n in configs] + [(f"random{s}", random_config(s)) for s in seeds]
    out = {name: {k: getattr(c, v) for k, v in DP_KEYS.items()} for name, c in cfgs}
    for name, (sw, sf, qw) in edges.items():
        out[name] = {"S_W": sw, "S_FRAC": sf, "Q_W": qw}
    out.update({f"{k}_fpga": {**out[k], "FPGA_REGS": 1} for k in fpga})
    return out


async def datapath_bit_exact(dut, module: str, spacing: int = 1):
    """The datapath `module` (its golden twin of the same name) on the hard cases and
    n_vectors(500) random vectors of build_vectors, in drained batches (q_coef stable within
    one) with stalls and gaps, a vector at most every `spacing` enabled clocks; r_out and v_out
    every bit, the latency from rtl/tex_latency.vh."""
    from types import SimpleNamespace

    p = pipe.block_params()
    sw, sf, qw = p["S_W"], p["S_FRAC"], p["Q_W"]
    v_w = len(dut.v_out) // 4
    p2_w = sw + v_w
    assert len(dut.v_out) == 4 * v_w and len(dut.r_out) == 3 * p2_w, "r_out / v_out widths"
    diagonal = module != "qmac_full"
    # the stimulus' formats (q_frac only places the hard cases' fractions: the datapath has none)
    fmt = SimpleNamespace(s_w=sw, s_frac=sf, q_w=qw, q_frac=qw // 2, quadric="diagonal" if diagonal else "full")
    lat = hdlbuild.latency(module, SimpleNamespace(fpga_regs=bool(p.get("FPGA_REGS", 0))))
    twin = getattr(G, module)
    r = pipe.rng(23)
    v, n_hard = build_vectors(fmt, r, pipe.n_vectors(500))
    s, Q, group = v.arrays()
    bs = batches(group)
    exp_r = np.zeros((len(s), 3), dtype=np.int64)
    exp_v = np.zeros((len(s), 4), dtype=np.int64)
    for b, e in bs:
        exp_r[b:e], exp_v[b:e] = twin(Q[b], s[b:e], sf)
    lim = lambda x, w: (x >= -(1 << (w - 1))).all() and (x < (1 << (w - 1))).all()  # noqa: E731
    assert lim(exp_v, v_w) and lim(exp_r, p2_w), f"the twin's v or r overflows V_W = {v_w}"

    def sample():
        return int(dut.r_out.value), int(dut.v_out.value)

    def params(b):
        dut.q_coef.value = pipe.pack(Q[b], qw)

    await pipe.start(dut)
    assert int(dut.out_valid.value) == 0, "out_valid after reset"
    got = await pipe.run_batches(
        dut, bs, params, {"s_in": [pipe.pack(x, sw) for x in s]}, sample, lat,
        junk={"s_in": 3 * sw, "q_coef": 10 * qw}, seed=int(os.environ.get("SEED", "1")), spacing=spacing)
    got = [tuple(pipe.unpack(g[0], p2_w, 3)) + tuple(pipe.unpack(g[1], v_w, 4)) for g in got]
    exp = [tuple(exp_r[i]) + tuple(exp_v[i]) for i in range(len(s))]
    pipe.check_equal(dut, got, exp, lambda i: f"[{v.tag[i]}] s={s[i].tolist()} Q={Q[i].tolist()}",
                     f"{module} {p} ({n_hard} hard cases), (r0, r1, r2, v0, v1, v2, v3)")
