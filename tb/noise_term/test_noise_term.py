"""noise_term: bit-exact against model/hw/golden.py noise_term, every output bit.

Parameters: a_in, t_in, o_in are per-pass parameters (rtl/noise_term.v reads them
directly at the stage that needs them, no pipeline registers). The interface contract:
they are stable from the first vector's entry until the last vector's exit
(texture_pipeline writes parameters only while the pipeline is empty). So the stimulus
is a sequence of batches, each with its own parameter set: a batch is streamed with
random ce stalls and input gaps (tb/pipe.py run_vectors), drained completely (every
output out), then the parameter ports idle through a few clocks of random unrelated
values with in_valid = 0 (nothing may latch them), the next batch's parameters are
applied, and the next batch starts.

Stimulus: random vectors (a share over the full range of every input format, a
share from realistic small ranges) in batches of 1..256 vectors (log-uniform, so
both short fill/drain batches and long full-pipeline batches), each batch with its
own random (a, T, o); with transform pow2 T is diagonal with entries 0 or 2^e
(model/hw/quantize.py _check_pow2), with amplitude pow2 a is 0 or +-2^k (model/hw/quantize.py
quantize_texture), k over the whole range the format holds (0..a_w-2 for a > 0,
0..a_w-1 for a < 0: -2^(a_w-1) is legal), both signs; every amplitude of the stimulus,
hard cases included, is legal for the configuration (check_formats asserts it).
Then the hard cases of DESIGN.md that concern this block, as explicit vectors:
negative coordinates and floors of negatives, cell fractions of exactly 0, 1/2^p_frac
and just below 1 (p = k 2^p_frac, k 2^p_frac + 1, k 2^p_frac - 1), the last lattice
cell (the +1 corner wraps), coordinates and T at their format extremes (the transform
wraps mod 2^p_w), T = 0, a = 0 and a at its extremes, offsets 0 and max,
corner values -1 and 1 - 2^-(hash_bits-1) under extreme amplitudes, and the steepest
lattice slopes under extreme T and a (the output words' bounds); and an amplitude sweep:
every a = 0, +-2^k the format holds (and, with amplitude any, its extremes) against the
extreme corner values and the steepest slopes under the extreme T (every pow2
amplitude shift, both signs, at the bounds of an and ag).
Each hard case group with its own parameters is its own batch.
Expected values: golden noise_term per batch, vectorized over the batch.

Per-term exponents (formats.t_exp_w, a_exp_w > 0; test_noise_term_exponents_rtl over
pipe.exponent_configs): T and a are mantissas and every group has its exponents te, ae (t_in
= {te, T}, a_in = {ae, a}): 0, the largest or uniform, drawn from a generator of their own (so
a fixed-point configuration's stimulus is what it was); the identity and 1.0 are the
mantissas and exponents that hold them exactly; plus an exponent sweep: every te against the
extreme amplitudes on the steepest slopes under the extreme T (the bounds of an and ag at
every shift). PARAM_PIPE = 1 (folded configurations: noise_fold's units take another term
every clock): vectors_own_params also streams vectors that each carry their own (a, T, o,
te, ae), with stalls and gaps, so that a parameter delayed by a wrong count of stages fails.
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

SOURCES = ["noise_term.v", "noise_params.v", "noise_xform.v", "noise_grad.v", "noise_hash.v", "noise_blend.v", "lerp.v", "delay_line.v"]


def latency(cfg) -> int:
    """`LAT_NOISE_TERM (fpga_regs: `LAT_NOISE_TERM_FPGA) from rtl/tex_latency.vh (the block must match it)."""
    return hdlbuild.latency("noise_term", cfg)


@pytest.mark.parametrize("sim,config", hdlbuild.family_params(fpga_regs=True))
def test_noise_term_rtl(sim, config):
    pipe.run_block("noise_term", sim, test_file=__file__, config=config, sources=SOURCES)


# with per-term exponents: every configuration under Icarus, full_bfp under Verilator too
EXP_CONFIGS = dict(pipe.exponent_configs(1342, 1351, 1352))


@pytest.mark.parametrize("sim,name", [pytest.param(sim, n, id=f"{sim}-{n}") for sim in ("icarus", "verilator")
                                      for n in EXP_CONFIGS if sim == "icarus" or n == "full_bfp"
                                      if not os.environ.get("SIM") or os.environ["SIM"] == sim])
def test_noise_term_exponents_rtl(sim, name):
    pipe.run_block("noise_term", sim, test_file=__file__, config=EXP_CONFIGS[name], sources=SOURCES)


def test_noise_term_check():
    """noise_term's elaboration-time check (g_bad_params) both ways on full's parameters (A_EXP_W 3:
    AE_MAX 7, amplitude any, AN_SHIFT = A_FRAC + N_FRAC - F_FRAC = 13): refused with each term alone true (A_EXP_W -1 < 0; an A exponent
    on pow2 amplitudes, AMPLITUDE 1; an A exponent with AN_SHIFT = AE_MAX - 1, F_FRAC raised);
    accepted at the edge AN_SHIFT = AE_MAX and with no A exponent (A_EXP_W 0) on pow2 amplitudes,
    AMP_POW2 alone. (g_latency_mismatch depends on rtl/tex_latency.vh alone: no parameter set makes
    it true.)"""
    b = hdlbuild.block_params(hdlbuild.config_of("full"), "noise_term")
    ae_max = (1 << b["A_EXP_W"]) - 1
    f_edge = b["A_FRAC"] + b["N_FRAC"] - ae_max  # AN_SHIFT = AE_MAX
    hdlbuild.check_refusals(
        "noise_term", SOURCES, b,
        accept={"full": {}, "AN_SHIFT = AE_MAX": {"F_FRAC": f_edge},
                "no A exponent, pow2 a": {"A_EXP_W": 0, "AMPLITUDE": 1}},
        refuse={"A_EXP_W < 0": {"A_EXP_W": -1}, "A exponent, pow2 a": {"AMPLITUDE": 1},
                "AN_SHIFT < AE_MAX": {"F_FRAC": f_edge + 1}},
        error_module="noise_term_a_exponent_needs_amplitude_any_and_an_shift")


# ---------------------------------------------------------------------------
# Stimulus


MAX_BATCH = 256  # random batches: 1..MAX_BATCH vectors, log-uniform


class Vectors:
    """Per-vector inputs plus the parameter group (= batch) each vector belongs to."""

    def __init__(self, cfg, seed: int = 0):
        self.cfg = cfg
        self.s, self.a, self.T, self.o, self.te, self.ae, self.group, self.tag = [], [], [], [], [], [], [], []
        self.n_groups = 0
        # the exponents' own generator: the other draws stay what they are without exponents
        self.re = np.random.default_rng([seed, 29])

    def _rand_e(self, e_max: int) -> int:
        if not e_max:
            return 0
        k = int(self.re.integers(0, 3))
        return (0, e_max, int(self.re.integers(0, e_max + 1)))[k]

    def rand_te(self) -> int:
        """te for a group: 0, the largest, or uniform (0 without t_exp_w)."""
        return self._rand_e(self.cfg.d["te_max"])

    def rand_ae(self) -> int:
        return self._rand_e(self.cfg.d["ae_max"])

    def add(self, a, T, o, s_rows, tag, te=None, ae=None):
        """One parameter group: scalar a, T [3,3], o [3], the exponents (None: rand_te,
        rand_ae), and its vectors s_rows [m,3]."""
        te = self.rand_te() if te is None else te
        ae = self.rand_ae() if ae is None else ae
        g = self.n_groups
        self.n_groups += 1
        for s in np.asarray(s_rows, dtype=np.int64).reshape(-1, 3):
            self.s.append(s)
            self.a.append(int(a))
            self.T.append(np.asarray(T, dtype=np.int64).reshape(3, 3))
            self.o.append(np.asarray(o, dtype=np.int64).reshape(3))
            self.te.append(int(te))
            self.ae.append(int(ae))
            self.group.append(g)
            self.tag.append(tag)

    def arrays(self):
        return (np.array(self.s, dtype=np.int64), np.array(self.a, dtype=np.int64),
                np.array(self.T, dtype=np.int64), np.array(self.o, dtype=np.int64),
                np.array(self.te, dtype=np.int64), np.array(self.ae, dtype=np.int64),
                np.array(self.group, dtype=np.int64))


def _lim(w, signed=True):
    return (-(1 << (w - 1)), (1 << (w - 1)) - 1) if signed else (0, (1 << w) - 1)


def _uniform(r, lo, hi, size=None):
    return r.integers(lo, hi + 1, size=size, dtype=np.int64)


def a_limits(cfg):
    """(lo, hi): the most negative and most positive amplitudes legal for the configuration.

    amplitude any: the format's extremes; pow2: -2^(a_w-1) (the format's most negative
    value is -2^(a_w-1), a power of two that model/hw/quantize.py accepts) and 2^(a_w-2).
    """
    lo, hi = _lim(cfg.a_w)
    if cfg.amplitude == "pow2":
        return lo, 1 << (cfg.a_w - 2)
    return lo, hi


def pow2_amplitudes(cfg):
    """Every pow2 amplitude the format holds: 0, 2^k (k <= a_w-2), -2^k (k <= a_w-1)."""
    return [0] + [1 << k for k in range(cfg.a_w - 1)] + [-(1 << k) for k in range(cfg.a_w)]


def rand_a(cfg, r):
    if cfg.amplitude == "pow2":
        # 0 or +-2^k, k over every shift the format holds (a share near 1)
        if r.random() < 0.1:
            return 0
        neg = r.random() < 0.5
        kmax = cfg.a_w - 1 if neg else cfg.a_w - 2
        if r.random() < 0.5:
            k = int(_uniform(r, 0, kmax))
        else:
            k = int(np.clip(_uniform(r, cfg.a_frac - 3, cfg.a_frac + 3), 0, kmax))
        return -(1 << k) if neg else 1 << k
    lo, hi = _lim(cfg.a_w)
    if r.random() < 0.5:
        return int(_uniform(r, lo, hi))
    one = 1 << cfg.a_frac
    return int(_uniform(r, max(lo, -one), min(hi, one)))


def rand_T(cfg, r):
    if cfg.transform == "pow2":
        T = np.zeros((3, 3), dtype=np.int64)
        for j in range(3):
            if r.random() < 0.1:
                continue
            if r.random() < 0.5:
                e = int(_uniform(r, 0, cfg.t_w - 2))  # every shift the format holds
            else:
                e = int(np.clip(_uniform(r, cfg.t_frac - 3, cfg.t_frac + 3), 0, cfg.t_w - 2))
            T[j, j] = 1 << e
        return T
    lo, hi = _lim(cfg.t_w)
    if r.random() < 0.5:
        return _uniform(r, lo, hi, (3, 3))
    big = min(1 << (cfg.t_frac + 2), hi)  # |T| <= 4: realistic feature scales (or the mantissa's range)
    T = _uniform(r, -big, big, (3, 3))
    if r.random() < 0.3:
        T = np.diag(np.diag(T))
    return T


def rand_o(cfg, r):
    return _uniform(r, 0, (1 << cfg.o_w) - 1, 3)


def rand_s(cfg, r, m):
    lo, hi = _lim(cfg.s_w)
    full = _uniform(r, lo, hi, (m, 3))
    small = 1 << (cfg.s_frac + 3)  # |s| <= 8, within the format (s{s_w}.{s_frac} may hold less)
    near = _uniform(r, max(lo, -small), min(hi, small), (m, 3))
    return np.where((r.random(m) < 0.5)[:, None], full, near)


def eye(cfg):
    """(T, te): the identity, exact: T = I 2^t_frac, te = 0, or with a mantissa of t_w - 2
    bits below its one the exponent that makes up the rest (the format's largest diagonal
    when it holds no 1)."""
    te = min(max(0, cfg.t_frac - (cfg.t_w - 2)), cfg.d["te_max"])
    return np.eye(3, dtype=np.int64) * min(1 << (cfg.t_frac - te), _lim(cfg.t_w)[1]), te


def a_one(cfg):
    """(a, ae): the amplitude 1, exact (as eye: 2^a_frac, or a mantissa and an exponent), or the
    format's largest when it holds no 1 (fixed point, a_frac = a_w - 1)."""
    ae = min(max(0, cfg.a_frac - (cfg.a_w - 2)), cfg.d["ae_max"])
    return min(1 << (cfg.a_frac - ae), _lim(cfg.a_w)[1]), ae


def big_T(cfg, sign=1):
    """T at the format's extreme: a wrapping transform far from the origin."""
    if cfg.transform == "pow2":
        return np.eye(3, dtype=np.int64) << (cfg.t_w - 2)
    lo, hi = _lim(cfg.t_w)
    return np.full((3, 3), lo if sign < 0 else hi, dtype=np.int64)


def offset_for(cfg, T, s, target, te=0):
    """o that puts p = ((T s) >> (ts_shift - te)) + o mod 2^p_w exactly on `target` [3]."""
    acc = [sum(int(T[j][k]) * int(s[k]) for k in range(3)) for j in range(3)]
    m = (1 << cfg.p_w) - 1
    return np.array([(int(target[j]) - (acc[j] >> (cfg.ts_shift - te))) & m for j in range(3)], dtype=np.int64)


def find_cells(cfg):
    """Lattice cells with special corner values: (ix, iy, iz) tuples.

    lo/hi: the (0,0,0) corner value is -1 / the largest; steep: |v001 - v000| largest
    (the steepest z slope), both signs.
    """
    P = cfg.perm
    n = 1 << cfg.hash_bits
    m = n - 1
    inv = np.argsort(P)
    out = {}
    ix, iy = 3 % n, 5 % n
    hxy = int(P[int(P[ix]) ^ iy])
    out["lo"] = (ix, iy, int(inv[0]) ^ hxy)
    out["hi"] = (ix, iy, int(inv[m]) ^ hxy)
    k = min(n, 16)
    xs, ys, zs = np.meshgrid(np.arange(k), np.arange(n), np.arange(n), indexing="ij")
    h = P[P[xs] ^ ys]
    d = P[h ^ ((zs + 1) & m)] - P[h ^ zs]
    for name, idx in (("steep_up", np.argmax(d)), ("steep_down", np.argmin(d))):
        i = np.unravel_index(idx, d.shape)
        out[name] = (int(xs[i]), int(ys[i]), int(zs[i]))
    return out


def build_vectors(cfg, r, n_random, seed: int = 0):
    v = Vectors(cfg, seed)
    I, te_i = eye(cfg)
    one_a, _ = a_one(cfg)
    pf, pw, H = cfg.p_frac, cfg.p_w, cfg.hash_bits
    mask_p, mask_h = (1 << pw) - 1, (1 << H) - 1
    alo, ahi = a_limits(cfg)
    slo, shi = _lim(cfg.s_w)
    one_s = 1 << cfg.s_frac

    # ---- hard cases
    # T = 0: p = o for any s; offsets at 0 and the max
    for o in (np.zeros(3, np.int64), np.full(3, mask_p, np.int64), rand_o(cfg, r)):
        for a in (ahi, alo, rand_a(cfg, r)):
            v.add(a, np.zeros((3, 3)), o, rand_s(cfg, r, 4), "T=0")
    # a = 0 (the output must be exactly 0), with random everything else
    for _ in range(6):
        v.add(0, rand_T(cfg, r), rand_o(cfg, r), rand_s(cfg, r, 4), "a=0")
    # identity transform: negative coordinates and the floor of negatives, offsets 0 and max
    q = 1 << (cfg.s_frac - pf) if cfg.s_frac >= pf else 1  # one p ulp in s units (T = I)
    negs = [-1, -q + 1, -q, -q - 1, -one_s, -one_s - 1, -one_s + 1, -one_s // 2, -3 * one_s - q,
            slo, slo + 1, -(1 << (cfg.s_w - 2))]
    pos = [0, 1, q - 1, q, one_s - 1, one_s, one_s + q, shi, shi - 1]
    vals = [min(max(x, slo), shi) for x in negs + pos]  # a narrow s (few integer bits) holds less
    rows = [[vals[i], vals[(i + 5) % len(vals)], vals[(3 * i + 1) % len(vals)]] for i in range(len(vals))]
    rows += [[x, x, x] for x in vals]
    for o in (np.zeros(3, np.int64), np.full(3, mask_p, np.int64)):
        v.add(rand_a(cfg, r), I, o, rows, "identity", te=te_i)
        v.add(ahi, I, o, rows, "identity a=max", te=te_i)
    # p exactly on fractions 0, 1 ulp, 1/2 and just below 1 (every axis), cells 0, 1, random, last
    fracs = [0, 1, 1 << (pf - 1), (1 << pf) - 1]
    cells = [0, 1, mask_h, int(r.integers(0, mask_h + 1))]
    for fx in fracs:
        for fy in fracs:
            for fz in fracs:
                T = rand_T(cfg, r)
                s = rand_s(cfg, r, 1)[0]
                c = [cells[int(i)] for i in r.integers(0, len(cells), 3)]
                te = v.rand_te()
                o = offset_for(cfg, T, s, [(c[0] << pf) | fx, (c[1] << pf) | fy, (c[2] << pf) | fz], te)
                v.add(rand_a(cfg, r), T, o, [s], "fraction", te=te)
    # k 2^pf and k 2^pf - 1 for negative and positive k straight from s (T = I, o = 0)
    if cfg.s_frac >= pf:
        ks = [-(1 << (H - 1)), -3, -2, -1, 1, 2, 3, (1 << (H - 1)) - 1]
        rows = []
        for k in ks:
            base = k << cfg.s_frac  # p = k 2^pf exactly
            rows.append([base, base - q, base - 1])  # fractions 0, just below 1, just below 1
            rows.append([base + q - 1, base + q, base - q - 1])
        v.add(rand_a(cfg, r), I, np.zeros(3, np.int64), np.clip(rows, slo, shi), "k 2^pf", te=te_i)
    # far from the origin: s and T at their extremes (the transform wraps), last cell
    ext = [[slo, slo, slo], [shi, shi, shi], [slo, shi, slo], [shi, slo, shi], [slo, 0, shi], [-1, shi, slo]]
    for sign in (1, -1):
        T = big_T(cfg, sign)
        for a in (ahi, alo):
            v.add(a, T, rand_o(cfg, r), ext, "extreme s,T")
            v.add(a, T, np.full(3, mask_p, np.int64), ext, "extreme s,T o=max")
            for s in ext[:3]:
                te = v.rand_te()
                o = offset_for(cfg, T, s, [(mask_h << pf) | ((1 << pf) - 1)] * 3, te)
                v.add(a, T, o, [s], "extreme s,T last cell", te=te)
    # corner values -1 and max at fraction 0 under extreme amplitudes (an at its bounds)
    cells_sp = find_cells(cfg)
    for name in ("lo", "hi"):
        ix, iy, iz = cells_sp[name]
        for a in (alo, ahi, one_a):
            T = rand_T(cfg, r)
            s = rand_s(cfg, r, 1)[0]
            te = v.rand_te()
            o = offset_for(cfg, T, s, [ix << pf, iy << pf, iz << pf], te)
            v.add(a, T, o, [s], f"corner {name}", te=te)
    # steepest z slope at fz = 1/2 (cubic slope 1.5), extreme T and a: ag at its bounds
    for name in ("steep_up", "steep_down"):
        ix, iy, iz = cells_sp[name]
        for sign in (1, -1):
            for a in (alo, ahi):
                for fz in (1 << (pf - 1), (1 << pf) - 1, 1):
                    T = big_T(cfg, sign)
                    s = rand_s(cfg, r, 1)[0]
                    te = v.rand_te()
                    o = offset_for(cfg, T, s, [ix << pf, iy << pf, (iz << pf) | fz], te)
                    v.add(a, T, o, [s], f"{name} T{'+' if sign > 0 else '-'}", te=te)
    # amplitude sweep: every pow2 amplitude (every shift e, both signs, and 0), plus the
    # configuration's extremes, on the extreme corner values (an at its bounds) and on the
    # steepest slopes under the extreme T (ag at its bounds), with a few random vectors
    amps = set(pow2_amplitudes(cfg)) | {alo, ahi, alo + 1, ahi - 1, one_a, -one_a}
    amps = sorted(amps)
    if cfg.amplitude == "pow2":
        amps = [a for a in amps if a == 0 or not (abs(a) & (abs(a) - 1))]
    for a in amps:
        for name, T in (("lo", rand_T(cfg, r)), ("hi", rand_T(cfg, r)),
                        ("steep_up", big_T(cfg, 1)), ("steep_down", big_T(cfg, -1))):
            ix, iy, iz = cells_sp[name]
            fz = 0 if name in ("lo", "hi") else 1 << (pf - 1)
            s = rand_s(cfg, r, 3)
            te = v.rand_te()
            o = offset_for(cfg, T, s[0], [ix << pf, iy << pf, (iz << pf) | fz], te)
            v.add(a, T, o, s, f"amplitude {a} {name}", te=te)
    # exponent sweep (exponents only): every te, with ae cycling and at its largest, against the
    # extreme amplitudes on the steepest slopes under the extreme T (an and ag at their bounds)
    te_max, ae_max = cfg.d["te_max"], cfg.d["ae_max"]
    if te_max or ae_max:
        pairs = sorted({(te, te % (ae_max + 1)) for te in range(te_max + 1)}
                       | {(te_max, ae_max), (0, ae_max), (te_max, 0)})
        for te, ae in pairs:
            for name, sign in (("steep_up", 1), ("steep_down", -1)):
                ix, iy, iz = cells_sp[name]
                T = big_T(cfg, sign)
                s = rand_s(cfg, r, 2)
                o = offset_for(cfg, T, s[0], [ix << pf, iy << pf, (iz << pf) | (1 << (pf - 1))], te)
                v.add(alo if (te + ae) % 2 else ahi, T, o, s, f"exponents te={te} ae={ae} {name}", te=te, ae=ae)
    n_hard = len(v.s)

    # ---- random batches of 1..MAX_BATCH vectors (log-uniform) sharing (a, T, o)
    left = n_random
    while left > 0:
        m = min(left, int(math.exp(r.uniform(0.0, math.log(MAX_BATCH + 1)))))
        v.add(rand_a(cfg, r), rand_T(cfg, r), rand_o(cfg, r), rand_s(cfg, r, m), "random")
        left -= m
    return v, n_hard


def check_formats(cfg, s, a, T, o, te, ae):
    for name, x, w, sg in (("s", s, cfg.s_w, True), ("a", a, cfg.a_w, True), ("T", T, cfg.t_w, True),
                           ("o", o, cfg.o_w, False), ("te", te, cfg.t_exp_w, False), ("ae", ae, cfg.a_exp_w, False)):
        lo, hi = _lim(w, sg)
        assert x.min() >= lo and x.max() <= hi, f"stimulus {name} outside its format"
    if cfg.transform == "pow2":
        off = T.copy()
        for j in range(3):
            off[:, j, j] = 0
        d = T[:, [0, 1, 2], [0, 1, 2]]
        assert not off.any() and (d >= 0).all() and not (d & (d - 1)).any(), "pow2 stimulus T not 0 / 2^e diagonal"
    if cfg.amplitude == "pow2":
        m = np.abs(a)
        assert not (m & (m - 1)).any(), "pow2 stimulus a not 0 / +-2^k"


def batches(group):
    """(begin, end) index ranges of the consecutive vectors sharing one parameter set."""
    starts = np.flatnonzero(np.r_[True, group[1:] != group[:-1]])
    ends = np.r_[starts[1:], len(group)]
    return [(int(b), int(e)) for b, e in zip(starts, ends)]


def expected(cfg, s, a, T, o, te, ae, group):
    an = np.zeros(len(s), dtype=np.int64)
    ag = np.zeros((len(s), 3), dtype=np.int64)
    for b, e in batches(group):
        assert (a[b:e] == a[b]).all() and (T[b:e] == T[b]).all() and (o[b:e] == o[b]).all()
        assert (te[b:e] == te[b]).all() and (ae[b:e] == ae[b]).all()
        an[b:e], ag[b:e] = G.noise_term(cfg, int(a[b]), T[b], o[b], s[b:e], int(te[b]), int(ae[b]))
    return an, ag


def param_words(cfg, a, T, o, te, ae):
    """The parameter ports' words per vector: a_in = {ae, a}, t_in = {te, T} (the exponents
    only with t_exp_w, a_exp_w > 0), o_in."""
    a_p = [pipe.pack([x], cfg.a_w) | (int(e) << cfg.a_w) for x, e in zip(a, ae)]
    t_p = [pipe.pack(x.reshape(9), cfg.t_w) | (int(e) << (9 * cfg.t_w)) for x, e in zip(T, te)]
    o_p = [pipe.pack(x, cfg.o_w) for x in o]
    return a_p, t_p, o_p


# ---------------------------------------------------------------------------
# cocotb tests


@cocotb.test()
async def reset_outputs(dut):
    """After reset: out_valid = 0 and every output bit 0 (no X)."""
    cfg = pipe.cfg()
    await pipe.start(dut)
    assert str(dut.out_valid.value) == "0"
    assert str(dut.an_out.value) == "0" * cfg.an_w, f"an_out after reset: {dut.an_out.value}"
    assert str(dut.ag_out.value) == "0" * (3 * cfg.ag_w), f"ag_out after reset: {dut.ag_out.value}"


@cocotb.test()
async def vectors_bit_exact(dut):
    """Hard cases plus n_vectors() random vectors, in drained batches with stalls and gaps."""
    cfg = pipe.cfg()
    r = pipe.rng(11)
    v, n_hard = build_vectors(cfg, r, pipe.n_vectors(), int(os.environ.get("SEED", "1")))
    s, a, T, o, te, ae, group = v.arrays()
    check_formats(cfg, s, a, T, o, te, ae)
    n = len(s)
    exp_an, exp_ag = expected(cfg, s, a, T, o, te, ae, group)
    bs = batches(group)
    sizes = [e - b for b, e in bs]
    dut._log.info(f"{cfg.name}: {n} vectors ({n_hard} hard cases) in {len(bs)} batches "
                  f"(1 parameter set each, sizes {min(sizes)}..{max(sizes)})")

    s_p = [pipe.pack(x, cfg.s_w) for x in s]
    a_p, t_p, o_p = param_words(cfg, a, T, o, te, ae)

    def sample():
        return int(dut.an_out.value), int(dut.ag_out.value)

    def params(b):
        dut.a_in.value = a_p[b]
        dut.t_in.value = t_p[b]
        dut.o_in.value = o_p[b]

    await pipe.start(dut)
    got = await pipe.run_batches(
        dut, bs, params, {"s_in": s_p}, sample, latency(cfg),
        junk={"s_in": 3 * cfg.s_w, "a_in": cfg.a_w + cfg.a_exp_w, "t_in": 9 * cfg.t_w + cfg.t_exp_w, "o_in": 3 * cfg.o_w},
        seed=int(os.environ.get("SEED", "1")))
    assert len(got) == n
    got_an = np.array([pipe.to_signed(g[0], cfg.an_w) for g in got], dtype=np.int64)
    got_ag = np.array([pipe.unpack(g[1], cfg.ag_w, 3) for g in got], dtype=np.int64)
    bad = np.flatnonzero((got_an != exp_an) | (got_ag != exp_ag).any(axis=1))
    for i in bad[:10]:
        dut._log.error(
            f"vector {i} [{v.tag[i]}]: s={s[i].tolist()} a={a[i]} T={T[i].tolist()} o={o[i].tolist()} "
            f"te={te[i]} ae={ae[i]}: "
            f"expected an={exp_an[i]} ag={exp_ag[i].tolist()}, got an={got_an[i]} ag={got_ag[i].tolist()}")
    assert len(bad) == 0, f"{len(bad)} of {n} vectors differ from golden noise_term (first at {bad[0]})"


@cocotb.test()
async def vectors_own_params(dut):
    """PARAM_PIPE = 1 (a folded configuration's units): vectors each with their own (a, T, o,
    te, ae), taken with in_valid, streamed with stalls and gaps; every output is its own
    vector's golden noise_term. (PARAM_PIPE = 0: the parameters are per pass; nothing to do.)"""
    from model.hw.config import folded

    cfg = pipe.cfg()
    if not folded(cfg):
        dut._log.info(f"{cfg.name}: PARAM_PIPE = 0, parameters per pass (vectors_bit_exact)")
        return
    r = pipe.rng(13)
    v = Vectors(cfg, int(os.environ.get("SEED", "1")) + 1)
    for _ in range(min(pipe.n_vectors(), 500)):
        v.add(rand_a(cfg, r), rand_T(cfg, r), rand_o(cfg, r), rand_s(cfg, r, 1), "own")
    s, a, T, o, te, ae, group = v.arrays()
    check_formats(cfg, s, a, T, o, te, ae)
    exp_an, exp_ag = expected(cfg, s, a, T, o, te, ae, group)
    s_p = [pipe.pack(x, cfg.s_w) for x in s]
    a_p, t_p, o_p = param_words(cfg, a, T, o, te, ae)

    def apply(i):
        dut.s_in.value = s_p[i]
        dut.a_in.value = a_p[i]
        dut.t_in.value = t_p[i]
        dut.o_in.value = o_p[i]

    await pipe.start(dut)
    got = await pipe.run_vectors(dut, apply, lambda: (int(dut.an_out.value), int(dut.ag_out.value)), len(s),
                                 latency(cfg), seed=int(os.environ.get("SEED", "1")) + 5)
    got_an = np.array([pipe.to_signed(g[0], cfg.an_w) for g in got], dtype=np.int64)
    got_ag = np.array([pipe.unpack(g[1], cfg.ag_w, 3) for g in got], dtype=np.int64)
    pipe.check_equal(dut, list(zip(got_an, *got_ag.T)), list(zip(exp_an, *exp_ag.T)),
                     lambda i: f"s={s[i].tolist()} a={a[i]} T={T[i].tolist()} o={o[i].tolist()} te={te[i]} ae={ae[i]}",
                     f"noise_term {cfg.name} (own parameters)")
