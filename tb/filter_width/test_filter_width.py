"""filter_width: bit-exact against model/hw/golden.py filter_width, every output bit.

Stimulus: n_vectors() random vectors, a third over the full range of every input
(c within the bound below, Jm, je, n_log2 = 0..n_log2_max), a third realistic
(|c| log-uniform around 1, normalised mantissas Jm, je around the pixel footprint)
and a third with je chosen so that w lands anywhere from below one table entry to
beyond the cap (the interesting region; full-range je mostly gives 0 or the cap).
Then the hard cases of DESIGN.md that concern this block, as explicit vectors:
c = 0 and J = 0 (w = 0), je at its min and max, the horizon (huge |J|: saturation
to the cap), w one step below, at and above N (one ulp of w where the root can
resolve it) and the cap, gx or gy alone nonzero (both signs), the maximal c and
Jm (widest g, every sign), normalising shifts 0..max, n_log2 = 0..n_log2_max.

c bound: g = c^T Jm must fit G_W (model/hw/config.py derives G_W from the largest
|c| the pipeline produces, cmax); stimulus c stays within
c_lim = (2^(G_W-1) - 1) / (3 2^(J_W-1)) >= cmax, which for the full configuration
is below the C_W word's own range (see rtl/filter_width.v).

Expected values: golden filter_width per n_log2 value, vectorized. The golden is
also checked against an independent plain-Python integer formulation,
w = min(floor(r 2^e), 2^(w_cap_log2 + f_frac)), with math.isqrt, and every
intermediate against its word width (g_w, gabs_w, l_w, r_w, e_w, w_w).
"""
from __future__ import annotations

import math
import os

import numpy as np
import pytest

import cocotb

import hdlbuild
from model.hw import golden as G
from model.hw.config import cmap_family
from tb import pipe

SOURCES = ["filter_width.v", "isqrt.v", "bitlen.v", "delay_line.v", "mul_pipe.v"]


def latency(cfg) -> int:
    """`LAT_FILTER_WIDTH (fpga_regs: `LAT_FILTER_WIDTH_FPGA) from rtl/tex_latency.vh (the block must match it)."""
    return hdlbuild.latency("filter_width", cfg)


@pytest.mark.parametrize("sim,config", hdlbuild.family_params(fpga_regs=True))
def test_filter_width_rtl(sim, config):
    pipe.run_block("filter_width", sim, test_file=__file__, config=config, sources=SOURCES)


@pytest.mark.parametrize("fpga", (False, True))
def test_filter_width_components_rtl(fpga):
    """COMPONENTS = 1 (filter "sat2": the two screen components a, b instead of |g|) on the
    candidate config/candidates/full_sat2.toml, and with fpga_regs, under Icarus (SIM= picks)."""
    from model.hw.config import ROOT, load_config, variant

    cfg = load_config(ROOT / "config" / "candidates" / "full_sat2.toml")
    if fpga:
        cfg = variant(cfg, "full_sat2_fpga", fpga_regs=True)
    pipe.run_block("filter_width", os.environ.get("SIM", "icarus"), test_file=__file__, config=cfg, sources=SOURCES)


# configurations whose exponent word e (E_W bits, signed) reaches its top magnitude bit below the cap:
# some e >= 2^(E_W-2) the inputs can give leaves w unsaturated, so the left shift must read e[E_W-2] too
# (kills mutant 2ec92faa, e[E_W-3:0]). With sh = 0, e is at most e0 = je_max - c_frac + n_log2_max +
# f_frac and r can be 1; with sh > 0, r >= 2^(NORM_BITS-1): w = r 2^e stays below 2^CAP_BITS only if
# e + NORM_BITS <= CAP_BITS. Of the named, candidate and random:0..5999 configurations six have it, by
# the first way (none of the named ones); random1884 (filter sat_fc) and random2230 (none) are two.
SHORT_EXPONENT = ("random:1884", "random:2230")


def short_exponent(cfg) -> bool:
    """Some e >= 2^(E_W-2) leaves w below the cap (SHORT_EXPONENT's property)."""
    top, cap = 1 << (cfg.e_w - 2), cfg.w_cap_log2 + cfg.f_frac
    e0 = cfg.je_max - cfg.c_frac + cfg.n_log2_max + cfg.f_frac
    return (e0 >= top and 1 + top <= cap) or ((1 << cfg.sh_w) - 1 + e0 >= top and cfg.norm_bits + top <= cap)


@pytest.mark.parametrize("config", SHORT_EXPONENT)
def test_filter_width_short_exponent_rtl(config):
    """filter_width on a configuration whose exponent's top magnitude bit matters below the cap
    (SHORT_EXPONENT, checked here: the property, not the seed, is what the test needs), under Icarus
    (SIM= picks); build_vectors puts w below the cap at every such e."""
    cfg = hdlbuild.config_of(config)
    assert short_exponent(cfg), f"{config}: no e >= 2^(E_W-2) = {1 << (cfg.e_w - 2)} leaves w below the cap: pick another"
    pipe.run_block("filter_width", os.environ.get("SIM", "icarus"), test_file=__file__, config=cfg, sources=SOURCES)


def test_filter_width_check():
    """filter_width's elaboration-time check (g_bad_params) both ways on full's parameters: the
    root's word R_W = 1 bit (NORM_BITS 1) has fewer bits than isqrt's SQ_LAT stages, and NORM_BITS
    up to |g|'s own width (MH_W = 0: nothing above the window to normalise) are refused; the
    smallest and largest NORM_BITS past them (2 and GABS_W - 1) elaborate. (The latency terms
    depend on rtl/tex_latency.vh alone, and G_W >= C_W + J_W holds by tw_g_max: no parameter set
    makes them true.)"""
    b = hdlbuild.block_params(hdlbuild.config_of("full"), "filter_width")
    gabs_w = hdlbuild.config_of("full").gabs_w
    hdlbuild.check_refusals("filter_width", SOURCES, b,
                            accept={"full": {}, "NORM_BITS 2": {"NORM_BITS": 2},
                                    "NORM_BITS GABS_W - 1 (MH_W 1)": {"NORM_BITS": gabs_w - 1}},
                            refuse={"NORM_BITS 1 (R_W < SQ_LAT)": {"NORM_BITS": 1},
                                    "NORM_BITS GABS_W (MH_W 0)": {"NORM_BITS": gabs_w}},
                            error_module="filter_width_unsupported_latency_or_widths")


# ---------------------------------------------------------------------------
# Reference (plain Python integers)


def c_limit(cfg) -> int:
    """Largest |c_k| for which every g = c^T Jm fits G_W (>= the config's cmax)."""
    return min((1 << (cfg.c_w - 1)) - 1, ((1 << (cfg.g_w - 1)) - 1) // (3 << (cfg.j_w - 1)))


def rmax(cfg) -> int:
    return math.isqrt(2 * ((1 << cfg.norm_bits) - 1) ** 2)


def ref(cfg, c, Jm, je, nl):
    """w and the intermediates (gx, gy, sh, L, r, e), unbounded integers."""
    gx = sum(int(c[k]) * int(Jm[k][0]) for k in range(3))
    gy = sum(int(c[k]) * int(Jm[k][1]) for k in range(3))
    ax, ay = abs(gx), abs(gy)
    sh = max(max(ax, ay).bit_length() - cfg.norm_bits, 0)
    ax, ay = ax >> sh, ay >> sh
    L = ax * ax + ay * ay
    r = math.isqrt(L)
    e = sh + int(je) - cfg.c_frac + int(nl) + cfg.f_frac
    exact = r << e if e >= 0 else r >> -e
    w = min(exact, 1 << (cfg.w_cap_log2 + cfg.f_frac))
    return w, (gx, gy, sh, L, r, e)


def widths_ok(cfg, mids, w) -> bool:
    gx, gy, sh, L, r, e = mids
    sg = lambda x, n: -(1 << (n - 1)) <= x < (1 << (n - 1))  # noqa: E731
    return (sg(gx, cfg.g_w) and sg(gy, cfg.g_w) and max(abs(gx), abs(gy)) < (1 << cfg.gabs_w)
            and 0 <= sh < (1 << cfg.sh_w) and 0 <= L < (1 << cfg.l_w) and 0 <= r < (1 << cfg.r_w)
            and sg(e, cfg.e_w) and 0 <= w < (1 << cfg.w_w))


def pair_for_root(r_target: int, nb: int, rng) -> tuple[int, int] | None:
    """(ax, ay), both < 2^nb, with isqrt(ax^2 + ay^2) == r_target."""
    lim = (1 << nb) - 1
    if r_target <= lim and rng.random() < 0.5:
        return r_target, 0
    lo = max(0, math.isqrt(max(0, r_target * r_target - lim * lim)))
    hi = min(lim, r_target)
    for _ in range(64):
        ax = int(rng.integers(lo, hi + 1))
        rest = r_target * r_target - ax * ax
        if rest < 0:
            continue
        ay = math.isqrt(rest)
        for d in (0, 1):
            if ay + d <= lim and math.isqrt(ax * ax + (ay + d) ** 2) == r_target:
                return ax, ay + d
    return None


# ---------------------------------------------------------------------------
# Stimulus


class Vectors:
    def __init__(self):
        self.c, self.Jm, self.je, self.nl, self.tag = [], [], [], [], []

    def add(self, c, Jm, je, nl, tag):
        self.c.append([int(x) for x in c])
        self.Jm.append([[int(Jm[k][0]), int(Jm[k][1])] for k in range(3)])
        self.je.append(int(je))
        self.nl.append(int(nl))
        self.tag.append(tag)

    def arrays(self):
        return (np.array(self.c, dtype=np.int64).reshape(-1, 3), np.array(self.Jm, dtype=np.int64).reshape(-1, 3, 2),
                np.array(self.je, dtype=np.int64), np.array(self.nl, dtype=np.int64))


def _u(r, lo, hi, size=None):
    return r.integers(lo, hi + 1, size=size, dtype=np.int64)


def rand_full(cfg, r):
    cl = c_limit(cfg)
    jlo, jhi = -(1 << (cfg.j_w - 1)), (1 << (cfg.j_w - 1)) - 1
    return (_u(r, -cl, cl, 3), _u(r, jlo, jhi, (3, 2)), int(_u(r, cfg.je_min, cfg.je_max)),
            int(_u(r, 0, cfg.n_log2_max)))


def rand_real(cfg, r):
    """|c| log-uniform in [2^-6, 2^10], normalised Jm (quantize_pixels), je near a pixel footprint."""
    cl = c_limit(cfg)
    mag = np.exp2(r.uniform(-6, 10, 3) + cfg.c_frac)
    c = np.clip(np.rint(mag * r.choice([-1, 1], 3) * (r.random(3) < 0.9)), -cl, cl).astype(np.int64)
    lim = (1 << (cfg.j_w - 1)) - 1
    Jm = _u(r, -lim, lim, (3, 2))
    k = int(r.integers(0, 6))
    Jm[k // 2, k % 2] = lim * int(r.choice([-1, 1]))  # block floating point: the largest entry normalised
    je = int(np.clip(-(cfg.j_w - 1) - int(r.integers(2, 12)), cfg.je_min, cfg.je_max))  # |J| ~ 2^-2..2^-12
    return c, Jm, je, int(_u(r, 0, cfg.n_log2_max))


def aim_je(cfg, c, Jm, nl, target_log2):
    """je that puts w near 2^target_log2 (units 2^-f_frac entries), clipped to its range."""
    _, (_, _, sh, _, rr, _) = ref(cfg, c, Jm, 0, nl)
    if rr == 0:
        return None
    e = round(target_log2 - math.log2(rr))
    return int(np.clip(e - sh + cfg.c_frac - nl - cfg.f_frac, cfg.je_min, cfg.je_max))


def build_vectors(cfg, r, n_random):
    v = Vectors()
    nb, ff, cf = cfg.norm_bits, cfg.f_frac, cfg.c_frac
    cb = cfg.w_cap_log2 + ff
    cl = c_limit(cfg)
    jlo, jhi = -(1 << (cfg.j_w - 1)), (1 << (cfg.j_w - 1)) - 1
    nls = list(range(cfg.n_log2_max + 1))
    eye = [[1, 0], [0, 1], [0, 0]]
    Z = [[0, 0], [0, 0], [0, 0]]

    def je_for(e, sh, nl):
        return e - sh + cf - nl - ff

    def in_je(je):
        return cfg.je_min <= je <= cfg.je_max

    # ---- hard cases
    # c = 0 and J = 0: w = 0 (any je, n_log2, including je max)
    for je in (cfg.je_min, 0, cfg.je_max):
        for nl in (0, cfg.n_log2_max):
            v.add([0, 0, 0], rand_full(cfg, r)[1], je, nl, "c=0")
            v.add(rand_full(cfg, r)[0], Z, je, nl, "J=0")
    # je at its min and max with random c, Jm; the horizon: huge |J| (je max, Jm extreme)
    for _ in range(8):
        c, Jm, _, nl = rand_full(cfg, r)
        v.add(c, Jm, cfg.je_min, nl, "je=min")
        v.add(c, Jm, cfg.je_max, nl, "je=max")
        c, Jm, _, nl = rand_real(cfg, r)
        v.add(c, Jm, cfg.je_min, nl, "je=min real")
        v.add(c, Jm, cfg.je_max, nl, "je=max real (horizon)")
        v.add(c, np.where(np.asarray(Jm) >= 0, jhi, jlo), cfg.je_max, nl, "horizon Jm extreme")
    # the maximal c and Jm: widest g, every sign pattern of the products
    for sc in ((1, 1, 1), (-1, -1, -1), (1, -1, 1)):
        for jx in (jlo, jhi):
            for jy in (jlo, jhi, 0):
                c = [s * cl for s in sc]
                c_neg = [-s * cl for s in sc]
                Jm = [[jx * s, jy * s] for s in sc]  # every product c_k Jm[k][.] of one sign
                Jm = np.clip(Jm, jlo, jhi)
                for nl in (0, cfg.n_log2_max):
                    for je in (cfg.je_min, cfg.je_max, je_for(0, cfg.gabs_w - nb, nl)):
                        if in_je(je):
                            v.add(c, Jm, je, nl, "widest g")
                            v.add(c_neg, Jm, je, nl, "widest g")
    v.add([-cl] * 3, [[jlo, jlo]] * 3, cfg.je_max, cfg.n_log2_max, "widest g")
    v.add([-cl] * 3, [[jlo, jlo]] * 3, int(np.clip(je_for(0, cfg.gabs_w - nb, 0), cfg.je_min, cfg.je_max)), 0,
          "widest g")
    # gx or gy alone nonzero, both signs, every normalising shift
    for col in (0, 1):
        for sgn in (1, -1):
            for k in range(0, cfg.gabs_w + 1):
                mag = (1 << k) - 1 if k > 0 else 1
                # |g| = mag, as c_0 Jm[0][col] with c_0 <= c_lim
                jm = max(1, -(-mag // cl))
                jm = min(jm, jhi)
                c0 = min(cl, mag // jm if mag >= jm else mag)
                Jm = [[0, 0], [0, 0], [0, 0]]
                Jm[0][col] = sgn * jm
                nl = int(r.integers(0, cfg.n_log2_max + 1))
                je = aim_je(cfg, [c0, 0, 0], Jm, nl, int(r.integers(ff - 2, cb + 2)))
                if je is not None:
                    v.add([c0, 0, 0], Jm, je, nl, f"g{'xy'[col]} alone")
    # w one step below, at and above N = 2^n_log2 entries and the cap 2^cb, for every n_log2:
    # gx = ax, gy = ay (c = (ax, ay, 0), Jm = I, optionally scaled by 2^k: sh = k)
    rm = rmax(cfg)
    for nl in nls:
        for T in (1 << (nl + ff), 1 << cb):
            cases = []  # (r, e)
            for e in range(-4, cb + 1):
                if e >= 0:
                    base = T >> e
                    if base << e == T and 1 <= base - 1 and base + 1 <= rm:
                        cases += [(base - 1, e), (base, e), (base + 1, e)]
                else:
                    base = T << -e
                    if base + (1 << -e) <= rm:
                        cases += [(base - 1, e), (base, e), (base + (1 << -e) - 1, e), (base + (1 << -e), e)]
            # keep the finest steps (smallest e) and a few coarser ones
            cases = cases[:12] + cases[12::7]
            for rr, e in cases:
                p = pair_for_root(rr, nb, r)
                if p is None:
                    continue
                ax, ay = p
                for k in (0, int(r.integers(1, cfg.gabs_w - nb + 1))):
                    sx, sy = r.choice([-1, 1], 2)
                    if k > 0 and max(ax, ay).bit_length() < nb:
                        continue  # the normalisation would not undo the scale exactly
                    Jm = [[int(sx) << k, 0], [0, int(sy) << k], [0, 0]] if k < cfg.j_w - 1 else None
                    c = [ax, ay, 0]
                    if Jm is None:  # scale through c instead
                        Jm, c = [[int(sx), 0], [0, int(sy)], [0, 0]], [ax << k, ay << k, 0]
                        if max(c) > cl:
                            continue
                    je = je_for(e, k, nl)
                    if in_je(je):
                        v.add(c, Jm, je, nl, "w near N" if T != 1 << cb else "w near cap")
    # e at and above 2^(E_W-2), w below the cap (r < 2^(cb - e), sh = 0): the left shift reads every
    # magnitude bit of e (only where the inputs reach such an e: SHORT_EXPONENT's configurations)
    for e in range(1 << (cfg.e_w - 2), cb):
        for rr in sorted({1, min((1 << (cb - e)) - 1, rm)}):
            p = pair_for_root(rr, nb, r)
            for nl in (0, cfg.n_log2_max):
                je = je_for(e, 0, nl)
                if p is not None and in_je(je):
                    v.add([p[0], p[1], 0], eye, je, nl, "e >= 2^(E_W-2) below the cap")
    # exact one-ulp neighbours of N where the root resolves them (e = 0)
    for nl in nls:
        T = 1 << (nl + ff)
        for rr in (T - 1, T, T + 1):
            if rr <= rm:
                ax, ay = pair_for_root(rr, nb, r)
                je = je_for(0, 0, nl)
                if in_je(je):
                    v.add([ax, ay, 0], eye, je, nl, "w = N +- 1 ulp")
    # n_log2 from 0 to n_log2_max on the same realistic gradients
    for _ in range(4):
        c, Jm, je, _ = rand_real(cfg, r)
        for nl in nls:
            v.add(c, Jm, je, nl, "n_log2 sweep")
    n_hard = len(v.c)

    # ---- random
    for i in range(n_random):
        kind = i % 3
        if kind == 0:
            c, Jm, je, nl = rand_full(cfg, r)
        else:
            c, Jm, je, nl = rand_real(cfg, r)
            if kind == 2:
                je2 = aim_je(cfg, c, Jm, nl, float(r.uniform(ff - 6, cb + 2)))
                je = je if je2 is None else je2
        v.add(c, Jm, je, nl, ("random full", "random real", "random aimed")[kind])
    return v, n_hard


# ---------------------------------------------------------------------------
# Expected values


def expected(cfg, c, Jm, je, nl):
    w = np.zeros(len(c), dtype=np.int64)
    for n in np.unique(nl):
        m = nl == n
        w[m] = G.filter_width(cfg, c[m], Jm[m], je[m], int(n))
    return w


# ---------------------------------------------------------------------------
# cocotb tests


@cocotb.test()
async def reset_outputs(dut):
    """After reset: out_valid = 0 and every output bit 0 (no X)."""
    cfg = pipe.cfg()
    await pipe.start(dut)
    assert str(dut.out_valid.value) == "0"
    nw = 2 if cmap_family(cfg) == "sat2" else 1  # sat2, sat2_fc: {b, a}
    assert str(dut.w_out.value) == "0" * (nw * cfg.w_w), f"w_out after reset: {dut.w_out.value}"


@cocotb.test()
async def vectors_bit_exact(dut):
    """Hard cases plus n_vectors() random vectors, streamed with stalls and gaps."""
    cfg = pipe.cfg()
    r = pipe.rng(41)
    v, n_hard = build_vectors(cfg, r, pipe.n_vectors())
    c, Jm, je, nl = v.arrays()
    n = len(c)
    cl = c_limit(cfg)
    assert np.abs(c).max() <= cl and Jm.min() >= -(1 << (cfg.j_w - 1)) and Jm.max() < (1 << (cfg.j_w - 1))
    assert je.min() >= cfg.je_min and je.max() <= cfg.je_max and nl.min() >= 0 and nl.max() <= cfg.n_log2_max
    exp = expected(cfg, c, Jm, je, nl)

    # the golden against the plain-integer formulation, and the word widths
    bad = []
    for i in range(n):
        w, mids = ref(cfg, c[i], Jm[i], je[i], nl[i])
        if w != int(exp[i]) or not widths_ok(cfg, mids, w):
            bad.append((i, w, mids))
    for i, w, mids in bad[:5]:
        dut._log.error(f"golden vs plain integers / word widths, vector {i} [{v.tag[i]}]: c={c[i].tolist()} "
                       f"Jm={Jm[i].tolist()} je={je[i]} n_log2={nl[i]}: golden w={exp[i]}, "
                       f"plain w={w} (gx, gy, sh, L, r, e)={mids}")
    assert not bad, f"{len(bad)} vectors where the golden differs from plain integers or a word overflows"

    cap = 1 << (cfg.w_cap_log2 + cfg.f_frac)
    n_entries = (1 << nl) << cfg.f_frac
    cover = {"w=0": int((exp == 0).sum()), "w=cap": int((exp == cap).sum()),
             "0<w<cap": int(((exp > 0) & (exp < cap)).sum()), "w=N": int((exp == n_entries).sum()),
             "w=N-1ulp": int((exp == n_entries - 1).sum()), "w=N+1ulp": int((exp == n_entries + 1).sum())}
    dut._log.info(f"{cfg.name}: {n} vectors ({n_hard} hard cases), c_lim = {cl}; coverage {cover}")
    assert cover["w=N"] > 0 and cover["w=cap"] > 0 and cover["w=0"] > 0

    c_p = [pipe.pack(x, cfg.c_w) for x in c]
    j_p = [pipe.pack(x.reshape(6), cfg.j_w) for x in Jm]
    e_p = [pipe.pack([x], cfg.je_w) for x in je]
    n_p = [int(x) for x in nl]

    def apply(i):
        dut.c_in.value = c_p[i]
        dut.jm_in.value = j_p[i]
        dut.je_in.value = e_p[i]
        dut.n_log2.value = n_p[i]

    def sample():
        return int(dut.w_out.value)

    await pipe.start(dut)
    got = await pipe.run_vectors(dut, apply, sample, n, latency=latency(cfg), seed=int(os.environ.get("SEED", "1")))
    got = np.array(got, dtype=np.int64)
    if cmap_family(cfg) == "sat2":  # COMPONENTS: w_out = {b, a}
        ab = np.zeros((n, 2), dtype=np.int64)
        for k in np.unique(nl):
            m = nl == k
            ab[m] = G.filter_width(cfg, c[m], Jm[m], je[m], int(k), components=True)
        exp = ab[:, 0] | (ab[:, 1] << cfg.w_w)
    bad = np.flatnonzero(got != exp)
    for i in bad[:10]:
        dut._log.error(f"vector {i} [{v.tag[i]}]: c={c[i].tolist()} Jm={Jm[i].tolist()} je={je[i]} "
                       f"n_log2={nl[i]}: expected w={exp[i]}, got w={got[i]}")
    assert len(bad) == 0, f"{len(bad)} of {n} vectors differ from golden filter_width (first at {bad[0]})"
