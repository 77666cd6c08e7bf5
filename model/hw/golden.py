"""The golden model: the texture pipeline in integer numpy, bit-exact with the RTL.

Every function here is the twin of the RTL module of the same name (rtl/<name>.v)
and computes exactly what that module computes: the same word widths, the same
floor (arithmetic shift right) truncations, the same saturations. All arrays
are int64 and every function is vectorized over whole frames ([..., ] leading
axes). Formats, bounds and rounding rules are in docs/numerics.md; the widths
are derived in model/hw/config.py from config/<name>.toml.

Conventions
- `>>` on int64 is floor division by a power of two (two's complement), the
  Verilog `>>>` on a signed word.
- x_frac names the fraction bits of a fixed-point value x.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from model.hw.config import (FC_KSF, SAMPLE_OFFSETS, SAT2_FILTERS, Config, clocks_per_sample, cmap_family,
                             freq_clamp, latency)

MODE_MOD, MODE_CLAMP = 0, 1
I64 = np.int64


def shift(x, n: int):
    """x * 2^n for n >= 0, floor(x / 2^-n) for n < 0 (arithmetic shift)."""
    return x << n if n >= 0 else x >> (-n)


def bitlen(x):
    """Bit length of non-negative int64 values < 2^53 (vectorized, exact)."""
    x = np.asarray(x, dtype=I64)
    _, e = np.frexp(x.astype(np.float64))
    return np.where(x > 0, e, 0).astype(I64)


def isqrt(L):
    """floor(sqrt(L)) for non-negative int64 L < 2^52, exact."""
    L = np.asarray(L, dtype=I64)
    r = np.floor(np.sqrt(L.astype(np.float64))).astype(I64)
    r = np.where(r * r > L, r - 1, r)
    r = np.where((r + 1) * (r + 1) <= L, r + 1, r)
    return r


# ---------------------------------------------------------------------------
# Texture parameters in integer form (what the write port loads)


@dataclass
class TexInt:
    """A texture's parameters as the hardware holds them (see model/hw/quantize.py)."""

    Q: np.ndarray  # int64 [10]: A..J, s{q_w}.{q_frac}
    a: np.ndarray  # int64 [K]: amplitude mantissas, s{a_w}.{a_frac} (a_i = a[i] 2^(ae[i] - a_frac))
    T: np.ndarray  # int64 [K, 3, 3]: T_i mantissas, s{t_w}.{t_frac} (T_i = T[i] 2^(te[i] - t_frac))
    o: np.ndarray  # int64 [K, 3]: offsets, u{p_w}.{p_frac} (mod 2^hash_bits lattice units)
    mode: int  # MODE_MOD or MODE_CLAMP
    n_log2: int  # N = 2^n_log2 colour-table entries
    filter: bool  # box filter (True) or point lookup (False)
    clut: np.ndarray  # int64 [N, 4]
    csat: np.ndarray = field(default=None)  # int64 [N, 4], inclusive prefix sums (eq. 13)
    mip: np.ndarray = field(default=None)  # int64 [2N - 1, 4], colour-table MIP levels
    # terms the texture uses: 0..k_used-1 (the CTRL register's term count; default all);
    # the hardware skips the others whatever their a, and so does texture_stages
    k_used: int = None
    # per-term exponents (formats.t_exp_w, a_exp_w; all 0 in a fixed-point configuration)
    te: np.ndarray = field(default=None)  # int64 [K]: u{t_exp_w}
    ae: np.ndarray = field(default=None)  # int64 [K]: u{a_exp_w}

    def __post_init__(self):
        if self.k_used is None:
            self.k_used = len(self.a)
        if self.te is None:
            self.te = np.zeros(len(self.a), dtype=I64)
        if self.ae is None:
            self.ae = np.zeros(len(self.a), dtype=I64)
        if self.csat is None or self.mip is None:
            self.csat, self.mip = build_tables(self.clut)


def build_tables(clut):
    """Summed-area colour table (eq. 13) and colour-table MIP map (3.3.1) of `clut`.

    MIP level l has N >> l entries, each the mean of 2^l entries rounded half up;
    levels are stored one after another, level l at offset 2N - (2N >> l).
    """
    clut = np.asarray(clut, dtype=I64)
    csat = np.cumsum(clut, axis=0)
    n = clut.shape[0]
    levels = []
    l = 0
    while (n >> l) >= 1:
        blocks = clut.reshape(n >> l, 1 << l, -1).sum(axis=1)
        levels.append((blocks + ((1 << l) >> 1)) >> l)
        l += 1
    return csat, np.concatenate(levels, axis=0)


def mip_offset(n: int, level):
    return 2 * n - ((2 * n) >> level)


# ---------------------------------------------------------------------------
# Blocks


def qmac_full(Q, s, s_frac: int):
    """rtl/qmac_full.v, quadric_mac's datapath for the full quadric: for x = (s, t, r, 1),
    v_k = ((Q_k0 s + Q_k1 t + Q_k2 r) >> s_frac) + Q_k3 (k = 0..3, v = Q x) and the products
    r_k = s_k v_k (k < 3), so that q = ((r_0 + r_1 + r_2) >> s_frac) + v_3.

    s: int64 [..., 3] s{s_w}.{s_frac}; Q: [10] A..J s{q_w}.{q_frac}.
    Returns r [..., 3] (s_frac + q_frac fraction bits) and v [..., 4] (q_frac)."""
    A, B, C, D, E, F, G, H, I, J = (int(x) for x in Q)
    s0, s1, s2 = s[..., 0], s[..., 1], s[..., 2]
    v0 = ((A * s0 + B * s1 + C * s2) >> s_frac) + D
    v1 = ((B * s0 + E * s1 + F * s2) >> s_frac) + G
    v2 = ((C * s0 + F * s1 + H * s2) >> s_frac) + I
    v3 = ((D * s0 + G * s1 + I * s2) >> s_frac) + J
    return np.stack([s0 * v0, s1 * v1, s2 * v2], axis=-1), np.stack([v0, v1, v2, v3], axis=-1)


def qmac_diag(Q, s, s_frac: int):
    """rtl/qmac_diag.v, quadric_mac's datapath for the diagonal quadric (B = C = F = 0,
    checked): v_k = (Q_kk s_k >> s_frac) + Q_k3 (k < 3), the products r_k = s_k (v_k + Q_k3)
    and v_3 = J, so that q = ((r_0 + r_1 + r_2) >> s_frac) + v_3 (one floor for the whole
    quadratic-plus-linear sum). Formats and results as qmac_full."""
    A, B, C, D, E, F, G, H, I, J = (int(x) for x in Q)
    if B or C or F:
        raise ValueError("qmac_diag: a diagonal quadric; B, C, F must be 0")
    s0, s1, s2 = s[..., 0], s[..., 1], s[..., 2]
    v0 = ((A * s0) >> s_frac) + D
    v1 = ((E * s1) >> s_frac) + G
    v2 = ((H * s2) >> s_frac) + I
    r = np.stack([s0 * (v0 + D), s1 * (v1 + G), s2 * (v2 + I)], axis=-1)
    return r, np.stack([v0, v1, v2, np.full_like(v0, J)], axis=-1)


def qmac_diag_fold(Q, s, s_frac: int):
    """rtl/qmac_diag_fold.v (quadric_clocks = 2): qmac_diag's values, its 6 products on 3
    multipliers over a vector's two clocks."""
    return qmac_diag(Q, s, s_frac)


def qmac_diag_serial(Q, s, s_frac: int):
    """rtl/qmac_diag_serial.v (quadric_clocks = 6): qmac_diag's values, its 6 products on one
    multiplier over six clocks."""
    return qmac_diag(Q, s, s_frac)


def qmac_diag_pipe(Q, s, s_frac: int):
    """rtl/qmac_diag_pipe.v (fpga_regs): qmac_diag's values, each product on mul_pipe and
    v_k + Q_k3 formed as (Q_kk s_k >> s_frac) + 2 Q_k3."""
    return qmac_diag(Q, s, s_frac)


def qmac_datapath(cfg: Config):
    """The twin of the datapath rtl/quadric_mac.v picks for cfg (its generate)."""
    if cfg.quadric != "diagonal":
        return qmac_full
    if cfg.fpga_regs:
        return qmac_diag_pipe
    return {2: qmac_diag_fold, 6: qmac_diag_serial}.get(cfg.quadric_clocks, qmac_diag)


def quadric_mac(cfg: Config, Q, s):
    """q = x^T Q x and the texture-space gradient dq/ds = 2 (Q x)[0:3], x = (s, t, r, 1).

    s: int64 [..., 3] s{s_w}.{s_frac}; Q: int64 [10] A..J s{q_w}.{q_frac}.
    Returns q [...] with f_frac fraction bits and cq [..., 3] with c_frac bits.

    The datapath (qmac_datapath: qmac_full, or with quadric = "diagonal", B = C = F = 0
    checked, 6 products instead of 15: qmac_diag and its schedules) gives r, v; then
    q = ((r_0 + r_1 + r_2) >> s_frac) + v_3, and the output shifts.
    """
    if cfg.quadric == "diagonal" and (int(Q[1]) or int(Q[2]) or int(Q[5])):
        raise ValueError(f"quadric_mac: configuration {cfg.name!r} has a diagonal quadric; B, C, F must be 0")
    r, v = qmac_datapath(cfg)(Q, s, cfg.s_frac)
    q = ((r[..., 0] + r[..., 1] + r[..., 2]) >> cfg.s_frac) + v[..., 3]
    qf = shift(q, cfg.f_frac - cfg.q_frac)
    sh = cfg.c_frac - cfg.q_frac + 1  # the factor 2 of 2 Q x is a shift
    cq = np.stack([shift(v[..., 0], sh), shift(v[..., 1], sh), shift(v[..., 2], sh)], axis=-1)
    return qf, cq


def noise_hash(cfg: Config, ix, iy, iz):
    """Lattice value at integer corners: perm[perm[perm[ix] ^ iy] ^ iz], as s.{n_frac} in [-1, 1)."""
    P = cfg.perm
    h = P[P[P[ix] ^ iy] ^ iz]
    return (h - (1 << (cfg.hash_bits - 1))) << (cfg.n_frac - cfg.hash_bits + 1)


def noise_blend(cfg: Config, fp):
    """Blend weight and its slope for a cell fraction fp (u.{p_frac}).

    linear: w = fp, dw = 1; cubic: w = 3 fp^2 - 2 fp^3, dw = 6 (fp - fp^2), each
    power truncated (floor) to p_frac bits.
    """
    pf = cfg.p_frac
    if cfg.blend == "linear":
        return fp, np.full_like(fp, 1 << pf)
    f2 = (fp * fp) >> pf
    f3 = (f2 * fp) >> pf
    return 3 * f2 - 2 * f3, 6 * (fp - f2)


def lerp(pf, a, b, t):
    """a + floor((b - a) t / 2^pf): a, b any signed words of one format, t a blend weight
    u.{pf} in [0, 2^pf] (rtl/lerp.v, P_FRAC = pf)."""
    return a + (((b - a) * t) >> pf)


def noise_xform(cfg: Config, t_row, o_j, s, te: int = 0):
    """One axis of a term's transform (rtl/noise_xform.v): p_j = ((sum_k T_jk s_k) >> (ts_shift
    - te)) + o_j mod 2^p_w, u{p_w}.{p_frac} (the lattice cell p_j >> p_frac, the fraction below).
    s: int64 [..., 3]; t_row: row j of T's mantissas (3 entries s{t_w}.{t_frac}); te the term's
    exponent (0 without t_exp_w); o_j u{p_w}.{p_frac}."""
    d = cfg.d
    acc = int(t_row[0]) * s[..., 0] + int(t_row[1]) * s[..., 1] + int(t_row[2]) * s[..., 2]
    return ((acc >> (d["ts_shift"] - int(te))) + int(o_j)) & ((1 << d["p_w"]) - 1)


def noise_grad(cfg: Config, a: int, T, v, e, fz, wy, wz, dw, te: int = 0, ae: int = 0):
    """A term's texture-space gradient a (dn/dp) T (rtl/noise_grad.v) from its value path's
    corner values v[i][j][k], x lerps e[j][k], y lerps fz[k] (s.{n_frac}), the weights wy, wz
    and the slopes dw[j] (u.{p_frac}); T and a are mantissas with exponents te, ae:
    h_k = (sum_j g_j T_jk) >> (h_shift - te), ag_k = (a h_k) >> (a_frac - ae).
    Returns ag [..., 3] (c_frac bits)."""
    d, pf = cfg.d, cfg.p_frac
    dx = [[v[1][j][k] - v[0][j][k] for k in range(2)] for j in range(2)]
    gx = (lerp(pf, lerp(pf, dx[0][0], dx[1][0], wy), lerp(pf, dx[0][1], dx[1][1], wy), wz) * dw[0]) >> pf
    gy = (lerp(pf, e[1][0] - e[0][0], e[1][1] - e[0][1], wz) * dw[1]) >> pf
    gz = ((fz[1] - fz[0]) * dw[2]) >> pf
    ag = []
    for k in range(3):
        h = shift(gx * T[0, k] + gy * T[1, k] + gz * T[2, k], int(te) - d["h_shift"])
        ag.append((int(a) * h) >> (cfg.a_frac - int(ae)))
    return np.stack(ag, axis=-1)


def noise_params(cfg: Config, a: int, T, o, te: int = 0, ae: int = 0) -> dict:
    """A term's parameters as noise_term's stages read them (rtl/noise_params.v), the words of
    its ports: "tc" (stages 1, 7) T's nine mantissas s{t_w} (entry 3 j + k at element 3 j + k)
    with an affine transform; pow2 (T diagonal 0 / 2^e) per axis j {T_jj == 0, e} (e the highest
    set bit below the sign, 0 for T_jj = 0; E_W = clog2(t_w - 1) bits) at element j. "ac" (stage
    8) a s{a_w} with amplitude any; pow2 (a = 0 / +-2^e) {a == 0, sign, e} (e the lowest set bit,
    0 for a = 0; EA_W = clog2(a_w) bits). "o" the three offsets u{p_w} packed, "te", "ae" as
    given. Where each arrives: noise_params_delays."""
    tw, aw = cfg.t_w, cfg.a_w
    T = np.asarray(T, dtype=I64).reshape(3, 3)
    if cfg.transform == "affine":
        tc = sum((int(T[j, k]) & ((1 << tw) - 1)) << ((3 * j + k) * tw) for j in range(3) for k in range(3))
    else:
        ew = (tw - 2).bit_length()  # clog2(t_w - 1)
        tc = 0
        for j in range(3):
            t = int(T[j, j]) & ((1 << tw) - 1)
            tc |= ((t == 0) << ew | max((t & ((1 << (tw - 1)) - 1)).bit_length() - 1, 0)) << (j * (ew + 1))
    am = int(a) & ((1 << aw) - 1)
    if cfg.amplitude == "any":
        ac = am
    else:
        ea = (aw - 1).bit_length()  # clog2(a_w)
        ac = (am == 0) << (ea + 1) | (am >> (aw - 1)) << ea | ((am & -am).bit_length() - 1 if am else 0)
    pw = cfg.d["p_w"]
    ow = sum((int(o[j]) & ((1 << pw) - 1)) << (j * pw) for j in range(3))
    return {"tc": tc, "ac": ac, "o": ow, "te": int(te), "ae": int(ae)}


def noise_params_delays(cfg: Config, param_pipe: bool) -> dict:
    """The enabled clocks after which each output of rtl/noise_params.v shows its input term
    (port: (word of noise_params, delay)): none with per-pass parameters (param_pipe False);
    with param_pipe the stage that reads it, 1 (noise_xform's second stage), L - 2 (stage 7) and
    L - 1 (stage 8) of noise_term's latency L. Without the noise gradient tc_s7 and te_s7 are 0."""
    L, x = latency("noise_term", cfg), latency("noise_xform", cfg) - 1
    d = (lambda n: n) if param_pipe else (lambda n: 0)
    return {"tc_s1": ("tc", 0), "o_s2": ("o", d(x)), "te_s2": ("te", d(x)), "tc_s7": ("tc", d(L - 2)),
            "te_s7": ("te", d(L - 2)), "ac_s8": ("ac", d(L - 1)), "ae_s8": ("ae", d(L - 1))}


def noise_term(cfg: Config, a: int, T, o, s, te: int = 0, ae: int = 0):
    """One term: a n(T s + o) and its texture-space gradient a (dn/dp) T.

    s: int64 [..., 3]; a: s{a_w}.{a_frac}; T [3, 3] s{t_w}.{t_frac}; o [3] u{p_w}.{p_frac};
    te, ae: the term's exponents (T 2^te, a 2^ae; 0 in a fixed-point configuration).
    Returns an [...] (f_frac bits) and ag [..., 3] (c_frac bits). The transform is
    noise_xform (once per axis), the gradient noise_grad, as in the RTL.
    """
    d = cfg.d
    pf = cfg.p_frac
    T = np.asarray(T, dtype=I64)
    o = np.asarray(o, dtype=I64)
    mask_h = (1 << cfg.hash_bits) - 1
    ip, sw, ds = [], [], []
    for j in range(3):
        p = noise_xform(cfg, T[j], o[j], s, te)
        ip.append(p >> pf)
        w_, dw_ = noise_blend(cfg, p & ((1 << pf) - 1))
        sw.append(w_)
        ds.append(dw_)
    x = (ip[0], (ip[0] + 1) & mask_h)
    y = (ip[1], (ip[1] + 1) & mask_h)
    z = (ip[2], (ip[2] + 1) & mask_h)
    P = cfg.perm
    hx = (P[x[0]], P[x[1]])
    v = [[[None, None], [None, None]], [[None, None], [None, None]]]
    for i in range(2):
        for j in range(2):
            hxy = P[hx[i] ^ y[j]]
            for k in range(2):
                v[i][j][k] = (P[hxy ^ z[k]] - (1 << (cfg.hash_bits - 1))) << (cfg.n_frac - cfg.hash_bits + 1)
    sx, sy, sz = sw
    e = [[lerp(pf, v[0][j][k], v[1][j][k], sx) for k in range(2)] for j in range(2)]
    fz = [lerp(pf, e[0][k], e[1][k], sy) for k in range(2)]
    n = lerp(pf, fz[0], fz[1], sz)
    an = shift(int(a) * n, int(ae) - d["an_shift"])
    if not cfg.noise_gradient:
        return an, np.zeros(n.shape + (3,), dtype=I64)
    return an, noise_grad(cfg, a, T, v, e, fz, sy, sz, ds, te, ae)


def filter_width(cfg: Config, c, Jm, je, n_log2: int, components: bool = False):
    """Filter width w = |c^T J| N in units of 2^-f_frac colour-table entries.

    c [..., 3]: texture-space gradient of f (c_frac bits); Jm [..., 3, 2] Jacobian
    mantissas and je [...] its shared exponent (J = Jm 2^je). The screen gradient
    mantissa g = c^T Jm is normalised to norm_bits bits (floor), its Euclidean norm
    taken by an exact integer square root (floor), and the result scaled by
    2^(sh + je - c_frac + n_log2 + f_frac), floor, saturating at 2^w_cap_log2 entries.
    components (filter "sat2", the trapezoid): the two screen components instead,
    a = |g_x| and b = |g_y| normalised and scaled the same way, each saturating at
    2^w_cap_log2 entries: [..., 2] (a, b).
    """
    gx = c[..., 0] * Jm[..., 0, 0] + c[..., 1] * Jm[..., 1, 0] + c[..., 2] * Jm[..., 2, 0]
    gy = c[..., 0] * Jm[..., 0, 1] + c[..., 1] * Jm[..., 1, 1] + c[..., 2] * Jm[..., 2, 1]
    ax, ay = np.abs(gx), np.abs(gy)
    sh = np.maximum(bitlen(np.maximum(ax, ay)) - cfg.norm_bits, 0)
    ax, ay = ax >> sh, ay >> sh
    r = isqrt(ax * ax + ay * ay)
    e = sh + np.asarray(je, dtype=I64) - cfg.c_frac + n_log2 + cfg.f_frac
    cap_bits = cfg.w_cap_log2 + cfg.f_frac

    def scaled(r):
        over = (r > 0) & (bitlen(r) + e > cap_bits)
        w = np.where(e >= 0, r << np.clip(e, 0, 62), r >> np.clip(-e, 0, 63))
        return np.where(over, I64(1) << cap_bits, w)

    if components:
        return np.stack([scaled(ax), scaled(ay)], axis=-1)
    return scaled(r)


def sat_index(x, xf: int, mode, n_log2, nmax: int):
    """One end x (s.{xf} entries) of a box-filter window -> its table addresses and weights
    (rtl/sat_index.v), with k = floor(x / 2^xf), fr = x mod 2^xf and N = 2^n_log2:
      mod   (mode 0): kk = k mod N,           kx = floor(k / N)   (whole tables before x)
      clamp (mode 1): kk = clip(k, 0, N - 1), kx = k - kk         (whole entries past an edge)
    Returns {kk, km1 = (kk - 1) mod 2^nmax (csat address), first = (kk == 0), fr, kx}."""
    x = np.asarray(x, dtype=I64)
    n_log2 = np.asarray(n_log2, dtype=I64)
    k = x >> xf
    fr = x & ((1 << xf) - 1)
    n = I64(1) << n_log2
    clamp = np.asarray(mode) == MODE_CLAMP
    kk = np.where(clamp, np.clip(k, 0, n - 1), k & (n - 1))
    kx = np.where(clamp, k - kk, k >> n_log2)
    return {"kk": kk, "km1": (kk - 1) & ((1 << nmax) - 1), "first": (kk == 0).astype(I64), "fr": fr, "kx": kx}


def sat_integral(xf: int, c, before, first, fr, k, q, d_w: int | None = None):
    """One window end's share of the box-filter integral, per channel (rtl/sat_integral.v):
    p = (csat[kk-1] << xf) + fr clut[kk] (csat[kk-1] = before, read as 0 when first) and the
    whole-entry product e = k q. c, before, q [..., 4]; first, fr, k [...].
    d_w: the RTL's words, p mod 2^d_w and e mod 2^(d_w - xf); None: exact (colour_map: D =
    I(b) - I(a) is exact either way, and exact words keep its range check meaningful)."""
    first = np.asarray(first, dtype=I64)[..., None]
    fr = np.asarray(fr, dtype=I64)[..., None]
    k = np.asarray(k, dtype=I64)[..., None]
    p = (np.where(first != 0, 0, np.asarray(before, dtype=I64)) << xf) + fr * np.asarray(c, dtype=I64)
    e = k * np.asarray(q, dtype=I64)
    if d_w is not None:
        p, e = p & ((I64(1) << d_w) - 1), e & ((I64(1) << (d_w - xf)) - 1)
    return p, e


def sat_integral_serial(xf: int, ch, c, before, first, fr, k, q, d_w: int | None = None):
    """rtl/sat_integral_serial.v (colour_map's fold, cmap_clocks = 4): sat_integral's channel ch
    [...] (0..3) alone, p and e [...]: one channel an enabled clock, the others as sat_integral."""
    ch = np.asarray(ch, dtype=I64)[..., None]
    p, e = sat_integral(xf, c, before, first, fr, k, q, d_w)
    return (np.take_along_axis(p, ch, axis=-1)[..., 0], np.take_along_axis(e, ch, axis=-1)[..., 0])


def mip_index(filter_: int, ff: int, nmax: int, u, w, mode, n_log2, filter_en):
    """Colour-table MIP level and address of a colour index u (s.{ff} entries) for a filter
    width w (u.{ff} entries) (rtl/mip_index.v; FILTER = filter_, 2 mip, 0 point lookup only):
      l    = clip(bitlen(floor(w / 2^ff)) - 1, 0, min(n_log2, nmax)) when mip is used, else 0
      km   = floor(floor(u / 2^ff) / 2^l) mod N_l (mode 0) or clipped to [0, N_l - 1], N_l = N >> l
      addr = 2N - (2N >> l) + km
    With l = 0, addr is the point-lookup index floor(u) mod N or clamped (a clut address).
    Returns (addr, use_mip), use_mip = (filter_ == 2 and filter_en)."""
    u = np.asarray(u, dtype=I64)
    n_log2 = np.asarray(n_log2, dtype=I64)
    use_mip = (np.asarray(filter_en) != 0) & (filter_ == 2)
    top = np.minimum(n_log2, nmax)
    lvl = np.where(use_mip, np.clip(bitlen(np.asarray(w, dtype=I64) >> ff) - 1, 0, top), 0)
    km = (u >> ff) >> lvl
    nl = (I64(1) << n_log2) >> lvl
    km = np.where(np.asarray(mode) == MODE_CLAMP, np.clip(km, 0, nl - 1), km & (nl - 1))
    return mip_offset(I64(1) << n_log2, lvl) + km, use_mip.astype(I64)


TABLE_CLUT, TABLE_CSAT, TABLE_MIP = 0, 1, 2


def colour_tables(nmax: int, fill: int = -1) -> dict:
    """The storage of rtl/colour_table.v with every entry `fill` (the RTL does not reset
    it): clut, csat [2^nmax, 4], mip [2^(nmax+1) - 1, 4], total [4]."""
    n = 1 << nmax
    return {"clut": np.full((n, 4), fill, dtype=I64), "csat": np.full((n, 4), fill, dtype=I64),
            "mip": np.full((2 * n - 1, 4), fill, dtype=I64), "total": np.full(4, fill, dtype=I64)}


def colour_table_write(tables: dict, filter_: int, nmax: int, cs_w: int, wr_table: int, wr_addr: int, wr_data):
    """One write of colour_table's write port into `tables` (colour_tables): wr_data the
    4 lanes (u{cs_w} each); clut and mip take the low 8 bits of each lane; csat (built for
    filter_ 1) also loads total (the last csat entry written; contract: ascending order, so
    total = csat[N - 1]); addresses past a table's end, table 3 and tables not built are
    ignored."""
    addr = int(wr_addr) & ((2 << nmax) - 1)
    lanes = np.asarray(wr_data, dtype=I64) & ((1 << cs_w) - 1)
    if wr_table == TABLE_CLUT and addr < (1 << nmax):
        tables["clut"][addr] = lanes & 255
    elif wr_table == TABLE_CSAT and filter_ == 1 and addr < (1 << nmax):
        tables["csat"][addr] = lanes
        tables["total"] = lanes.copy()
    elif wr_table == TABLE_MIP and filter_ == 2 and addr < (2 << nmax) - 1:
        tables["mip"][addr] = lanes & 255


def host_tables(tex: TexInt) -> dict:
    """colour_table's contents after the host has loaded tex's tables (csat in ascending
    order, so total = csat[N - 1]); with sat2_table's csat2 = H, the running sum of csat
    (sat2_table_write), and total2 = H[N - 1]."""
    n = 1 << tex.n_log2
    csat2 = np.cumsum(np.asarray(tex.csat, dtype=I64)[:n], axis=0)
    return {"clut": tex.clut, "csat": tex.csat, "mip": tex.mip, "total": tex.csat[n - 1],
            "csat2": csat2, "total2": csat2[n - 1]}


def sat2_tables(nmax: int, fill: int = -1) -> dict:
    """The storage of rtl/sat2_table.v with every entry `fill` (not reset): clut, csat, csat2
    [2^nmax, 4], total, total2 [4] and the running-sum register acc [4]."""
    n = 1 << nmax
    return {"clut": np.full((n, 4), fill, dtype=I64), "csat": np.full((n, 4), fill, dtype=I64),
            "csat2": np.full((n, 4), fill, dtype=I64), "total": np.full(4, fill, dtype=I64),
            "total2": np.full(4, fill, dtype=I64), "acc": np.full(4, fill, dtype=I64)}


def sat2_table_write(tables: dict, nmax: int, cs_w: int, cs2_w: int, wr_table: int, wr_addr: int, wr_data):
    """One write of sat2_table's write port into `tables` (sat2_tables): wr_table 0 clut (the
    low 8 bits of each lane), 1 csat (u{cs_w} lanes), which also derives csat2, the running sum
    H[j] = (j == 0 ? 0 : acc) + csat[j] mod 2^cs2_w, acc = H[j], total = csat[j], total2 = H[j]
    (contract: a table load writes csat[0..N-1] in ascending order, so H[j] = sum_{i<=j} csat[i],
    total = csat[N - 1], total2 = H[N - 1]); addresses past 2^nmax, wr_table 2 and 3 ignored."""
    addr = int(wr_addr) & ((2 << nmax) - 1)
    lanes = np.asarray(wr_data, dtype=I64) & ((1 << cs_w) - 1)
    if addr >= (1 << nmax):
        return
    if wr_table == TABLE_CLUT:
        tables["clut"][addr] = lanes & 255
    elif wr_table == TABLE_CSAT:
        h = ((0 if addr == 0 else tables["acc"]) + lanes) & ((1 << cs2_w) - 1)
        tables["csat"][addr] = lanes
        tables["csat2"][addr] = h
        tables["total"] = lanes.copy()
        tables["total2"] = h.copy()
        tables["acc"] = h.copy()


def sat2_table(tables: dict, clut_addr, csat_addr) -> dict:
    """The read ports of rtl/sat2_table.v on `tables` (sat2_tables / host_tables), one set per
    window end: clut[clut_addr], csat[csat_addr], csat2[csat_addr] [..., 4] and total, total2."""
    z = np.zeros(np.shape(clut_addr) + (4,), dtype=I64)
    return {"clut": _read(tables["clut"], clut_addr), "csat": _read(tables["csat"], csat_addr),
            "csat2": _read(tables["csat2"], csat_addr), "total": z + tables["total"],
            "total2": z + tables["total2"]}


def _read(table, addr):
    """table[addr], 0 past the entries held (the RTL reads what was last written there)."""
    addr = np.asarray(addr, dtype=I64)
    inside = (addr >= 0) & (addr < len(table))
    return np.where(inside[..., None], table[np.clip(addr, 0, len(table) - 1)], 0)


def colour_table(tables: dict, filter_: int, clut_addr_a=0, clut_addr_b=0, csat_addr_a=0, csat_addr_b=0,
                 mip_addr=0) -> dict:
    """The read ports of rtl/colour_table.v on `tables` (colour_tables / host_tables):
    clut_a always; clut_b, csat_a, csat_b, total for filter_ 1 (sat); mip_data for filter_ 2;
    the ports of tables not built read 0. Each [..., 4] lanes."""
    z = np.zeros(np.shape(clut_addr_a) + (4,), dtype=I64)
    sat, mip = filter_ == 1, filter_ == 2
    return {"clut_a": _read(tables["clut"], clut_addr_a),
            "clut_b": _read(tables["clut"], clut_addr_b) if sat else z,
            "csat_a": _read(tables["csat"], csat_addr_a) if sat else z,
            "csat_b": _read(tables["csat"], csat_addr_b) if sat else z,
            "total": np.broadcast_to(tables["total"], z.shape) if sat else z,
            "mip_data": _read(tables["mip"], mip_addr) if mip else z}


def delay_line(d, n: int, ce=None, rst=None, clear: bool = False, fill: int = -1):
    """The output of rtl/delay_line.v (N = n stages) per clock of a stream: d[t] the input
    word during clock t, ce[t] its clock enable (default all 1), rst[t] its reset. Returns
    out[t], d_out after the edge of clock t: the input of the n-th latest enabled edge up to
    t (n = 0: d[t], a wire); before n enabled edges, `fill` (unknown, never reset) or 0 after
    a reset edge with clear (CLEAR = 1, which clears every stage whatever ce); clear = False
    ignores rst."""
    d = np.asarray(d, dtype=I64)
    t_n = len(d)
    ce = np.ones(t_n, dtype=bool) if ce is None else np.asarray(ce, dtype=bool)
    rst = np.zeros(t_n, dtype=bool) if rst is None or not clear else np.asarray(rst, dtype=bool)
    if n == 0:
        return d.copy()
    out = np.empty(t_n, dtype=I64)
    cuts = [0] + [int(t) for t in np.flatnonzero(rst)] + [t_n]
    for s, (lo, hi) in enumerate(zip(cuts[:-1], cuts[1:])):
        en = ce[lo:hi].copy()
        if s > 0:
            en[0] = False  # the reset edge clears, it does not shift
        pos = lo + np.flatnonzero(en)
        j = np.cumsum(en) - n
        if len(pos) == 0:
            pos = np.zeros(1, dtype=I64)
        out[lo:hi] = np.where(j >= 0, d[pos[np.clip(j, 0, len(pos) - 1)]], fill if s == 0 else 0)
    return out


def mul_pipe(a, b):
    """The product of rtl/mul_pipe.v: a * b, exact (the RTL sums its 18x18 partial products
    modulo 2^(A_W + B_W), where the product fits). Python integers (object arrays): a 35 x 35
    product does not fit int64."""
    return np.asarray(a, dtype=object) * np.asarray(b, dtype=object)


def sum_tree(leaves, w: int):
    """The sum of rtl/sum_tree.v: the leaves (a sequence of equal-shape int arrays, each a
    w-bit two's-complement word) added modulo 2^w (w <= 62), a signed w-bit result; exact
    when w bounds the whole sum (texture_pipeline's f_w, c_w)."""
    total = np.zeros(np.shape(leaves[0]), dtype=I64)
    for x in leaves:
        total = total + np.asarray(x, dtype=I64)
    half = I64(1) << (w - 1)
    return ((total + half) & ((half << 1) - 1)) - half


def box_divide(num, den, q_w: int = 8, sat: bool = False):
    """floor(num / den) per lane (rtl/box_divide.v; precondition num < den 2^q_w, with sat
    num < den 2^(q_w+1) and the quotient saturated to 2^q_w - 1). den broadcasts."""
    q = np.asarray(num, dtype=I64) // np.asarray(den, dtype=I64)
    return np.minimum(q, (1 << q_w) - 1) if sat else q


def colour_divide(cfg: Config, D, w):
    """out = the box average D / (2w) rounded, per channel (D [..., 4], w [...] > 0), as
    colour_map forms the operands of its box_divide.

    div_bits = 0: exact, floor((D + w) / (2w)) = floor(((D + w) >> 1) / w).
    div_bits = B > 0: w normalised to B significant bits, both operands rounded half up
    (docs/numerics.md "Colour map", with h(s) = 2^s >> 1):
        sh0 = bitlen(w >> B), wr = w + h(sh0), sh = bitlen(wr >> B)   (sh0 or sh0 + 1)
        den = wr >> sh                         = round(w / 2^sh), B bits (2^(B-1).. when sh > 0)
        num = (D + w + 2 h(sh)) >> (sh + 1)    = round(((D + w) / 2) / 2^sh)
        out = min(floor(num / den), 255)       (the min acts only for B <= 9)
    sh = 0 (w < 2^B) is the exact division.
    """
    b = cfg.div_bits
    w = w[..., None]
    if b == 0:
        return box_divide((D + w) >> 1, w)
    one = I64(1)
    sh0 = bitlen(w >> b)
    wr = w + ((one << sh0) >> 1)
    sh = bitlen(wr >> b)
    den = wr >> sh
    num = (D + w + (((one << sh) >> 1) << 1)) >> (sh + 1)
    return box_divide(num, den, sat=True)


def cmap_u(cfg: Config, f, mode, n_log2):
    """colour_map's stage 1: the colour index u = f N (units 2^-f_frac entries), mod: u taken
    mod N; clamp: u saturated to [-W/2, N + W/2], W = 2^w_cap_log2 (exact: any window beyond it
    sees only an edge entry; sat2: [-W, N + W], its window reaches W). f, mode [...] (n_log2 a
    scalar)."""
    ff = cfg.f_frac
    f = np.asarray(f, dtype=I64)
    guard = cfg.u_guard
    u_mod = (f & ((1 << ff) - 1)) << n_log2
    u_clamp = np.clip(f << n_log2, -guard, ((1 << n_log2) << ff) + guard)
    return np.where(np.asarray(mode) == MODE_MOD, u_mod, u_clamp)


def cmap_divide(cfg: Config, D, w, point):
    """rtl/cmap_divide.v: per channel the box average D / (2w) rounded by the configuration's
    method (colour_divide: div_bits = 0 exact, B > 0 normalised), or, where w = 0, the point
    lookup `point` passed through. D, point [..., 4]; w [...]."""
    w = np.asarray(w, dtype=I64)
    return np.where((w > 0)[..., None], colour_divide(cfg, np.asarray(D, dtype=I64), np.maximum(w, 1)),
                    np.asarray(point, dtype=I64))


def cmap_sat(cfg: Config, tables: dict, u, w, mode, n_log2):
    """rtl/cmap_sat.v, the box-filter family: RGBA8 [..., 4] of the colour index u (s.f_frac
    entries, after colour_map's stage 1) averaged over width w (0: the point lookup) from the
    tables held (colour_tables / host_tables): D = I(u + w/2) - I(u - w/2) (eq. 15 and every
    edge case of 3.3.2 as one integral), then cmap_divide. cmap_clocks = 4 (a channel a clock:
    sat_integral_serial, cmap_divide on one lane) computes the same values."""
    ff, nmax = cfg.f_frac, cfg.n_log2_max
    u = np.asarray(u, dtype=I64)
    w = np.asarray(w, dtype=I64)
    clamp = np.asarray(mode) == MODE_CLAMP
    # D = I(b) - I(a) over the window [a, b] = [2u - w, 2u + w] (units 2^-xf entries):
    # sat_index at both ends, the table reads, sat_integral at both ends
    xf = ff + 1
    ia = sat_index(2 * u - w, xf, mode, n_log2, nmax)
    ib = sat_index(2 * u + w, xf, mode, n_log2, nmax)
    rd = colour_table(tables, 1, clut_addr_a=ia["kk"], clut_addr_b=ib["kk"], csat_addr_a=ia["km1"],
                      csat_addr_b=ib["km1"])
    # mod: whole tables, (kx_b - kx_a) total as its two bytes; clamp: whole entries past an
    # edge, kx clut[kk] at each end
    dk = (ib["kx"] - ia["kx"])
    ka = np.where(clamp, ia["kx"], dk)
    kb = np.where(clamp, ib["kx"], dk)
    qa = np.where(clamp[..., None], rd["clut_a"], rd["total"] >> 8)
    qb = np.where(clamp[..., None], rd["clut_b"], rd["total"] & 255)
    pa, ea = sat_integral(xf, rd["clut_a"], rd["csat_a"], ia["first"], ia["fr"], ka, qa)
    pb, eb = sat_integral(xf, rd["clut_b"], rd["csat_b"], ib["first"], ib["fr"], kb, qb)
    whole = np.where(clamp[..., None], eb - ea, eb + (ea << 8))
    D = (whole << xf) + pb - pa
    # 0 <= D <= 255 * 2w for consistent tables (the average is in 0..255): never wrap silently
    if D.size and ((D < 0).any() or (D > 510 * w[..., None]).any()):
        raise ValueError("colour_map: average outside 0..255 (inconsistent csat/clut tables?)")
    # w = 0: a = b = 2u, and clut at end a is the point lookup clut[k]
    return cmap_divide(cfg, D, w, rd["clut_a"])


def cmap_mip(cfg: Config, tables: dict, u, w, mode, n_log2, filter_en):
    """rtl/cmap_mip.v, the MIP-map family: RGBA8 [..., 4] of the colour index u (s.f_frac
    entries, after colour_map's stage 1) in the MIP level of width w (mip_index), or, filter_en
    0, clut[k] (the point lookup), from the tables held (colour_tables / host_tables)."""
    addr, use_mip = mip_index(2, cfg.f_frac, cfg.n_log2_max, u, w, mode, n_log2, filter_en)
    rd = colour_table(tables, 2, clut_addr_a=addr & ((1 << cfg.n_log2_max) - 1), mip_addr=addr)
    return np.where((use_mip != 0)[..., None], rd["mip_data"], rd["clut_a"])


def cmap_point(cfg: Config, tables: dict, u, mode, n_log2):
    """rtl/cmap_point.v, the point-lookup family (filter "none"): clut[k] [..., 4], k =
    floor(u) mod N or clamped to [0, N - 1] (mip_index at level 0), from the tables held."""
    k, _ = mip_index(0, cfg.f_frac, cfg.n_log2_max, u, 0, mode, n_log2, 0)
    return colour_table(tables, 0, clut_addr_a=k)["clut_a"]


def _u64(x):
    """int64 values as uint64 words (two's complement): + - * wrap mod 2^64, silently."""
    return np.asarray(x, dtype=I64).astype(np.uint64)


def sat2_integral(xf: int, d_w: int, rd: dict, first, fr, kx, kk, mode, n_log2):
    """One window end's integrals for the trapezoid (rtl/sat2_integral.v), per channel, from
    sat_index's (kk, first, fr, kx) of an end x (units 2^-xf entries) and the table reads rd
    (sat2_table: clut[kk], csat[kk-1], csat2[kk-1], read as 0 when first; total, total2),
    N = 2^n_log2 (docs/numerics.md "The trapezoid"):
      t  = kx 2^xf + fr (clamp: the last or first entry extended over the kx entries past
           it) or fr (mod, with m = kx whole tables before x)
      v1 = S(x) 2^xf  = (csat << xf) + t clut [+ (m T) << xf]
      v2 = 2G(x) 2^2xf = (H << (2xf + 1)) + ((2t - 2^xf) csat << xf) + t^2 clut
           [+ (m (T (N (m - 1) - 1 + 2 kk) + 2 HT)) << 2xf + (m T fr) << (xf + 1)]
    (S = integral of C, G = integral of S; T = total, HT = total2), both mod 2^d_w.
    Returns (v1, v2) [..., 4]."""
    clamp = (np.asarray(mode) == MODE_CLAMP)[..., None]
    first = (np.asarray(first) != 0)[..., None]
    fr = np.asarray(fr, dtype=I64)[..., None]
    kx = np.asarray(kx, dtype=I64)[..., None]
    kk = np.asarray(kk, dtype=I64)[..., None]
    c = _u64(rd["clut"])
    cs = _u64(np.where(first, 0, rd["csat"]))
    h = _u64(np.where(first, 0, rd["csat2"]))
    tt, ht = _u64(rd["total"]), _u64(rd["total2"])
    t = _u64(np.where(clamp, (kx << xf) + fr, fr))
    m = _u64(np.where(clamp, 0, kx))
    one = np.uint64(1)
    X, X2 = np.uint64(xf), np.uint64(2 * xf)
    v1 = (cs << X) + t * c + ((m * tt) << X)
    nn = _u64(I64(1) << np.asarray(n_log2, dtype=I64))
    q = m * (tt * (nn * (m - one) - one + (_u64(kk) << one)) + (ht << one))
    v2 = ((h << (X2 + one)) + (((t << one) - (one << X)) * cs << X) + t * t * c
          + (q << X2) + ((m * tt * _u64(fr)) << (X + one)))
    mask = np.uint64((1 << d_w) - 1)
    return (v1 & mask).astype(I64), (v2 & mask).astype(I64)


def cmap_sat2(cfg: Config, tables: dict, u, a, b, mode, n_log2):
    """rtl/cmap_sat2.v, the trapezoid (filter "sat2"): RGBA8 [..., 4] of the colour index u
    (s.f_frac entries, colour_map's stage 1) averaged over the pixel when f is linear across
    it: the colour map convolved with two boxes of widths a and b (u.f_frac entries, the screen
    components of grad f N), from the tables held (sat2_tables / host_tables). The window ends
    e1..e4 = 2u + a + b, 2u + a - b, 2u - a + b, 2u - a - b (units 2^-x_frac entries) and
      a, b > 0: D = 2G(e1) - 2G(e2) - 2G(e3) + 2G(e4) (units 2^-2x_frac), divisor 4ab
      a or b = 0 (the box of width a + b): D = S(e1) - S(e4) (units 2^-x_frac), divisor a + b
      a = b = 0: the point lookup clut at e1 = 2u
    then cmap_divide: floor((D + w) / 2w) exact or normalised (D / 2w = the average)."""
    xf, nmax, dw = cfg.x_frac, cfg.n_log2_max, cfg.d2_w
    u = np.asarray(u, dtype=I64)
    a = np.asarray(a, dtype=I64)
    b = np.asarray(b, dtype=I64)
    ends = (2 * u + a + b, 2 * u + a - b, 2 * u - a + b, 2 * u - a - b)
    v1s, v2s, point = [], [], None
    for e in ends:
        ix = sat_index(e, xf, mode, n_log2, nmax)
        rd = sat2_table(tables, ix["kk"], ix["km1"])
        v1, v2 = sat2_integral(xf, dw, rd, ix["first"], ix["fr"], ix["kx"], ix["kk"], mode, n_log2)
        v1s.append(v1)
        v2s.append(v2)
        if point is None:
            point = rd["clut"]
    box = ((a == 0) | (b == 0))[..., None]
    M = (I64(1) << dw) - 1
    D = np.where(box, v1s[0] - v1s[3], v2s[0] - v2s[1] - v2s[2] + v2s[3]) & M
    w = np.where(box[..., 0], a + b, 4 * a * b)
    # 0 <= D <= 255 * 2w for consistent tables (the average is in 0..255): never wrap silently
    if D.size and (D > 510 * w[..., None]).any():
        raise ValueError("cmap_sat2: average outside 0..255 (inconsistent csat/clut tables?)")
    return cmap_divide(cfg, D, w, point)


def colour_map(cfg: Config, tex: TexInt, f, w):
    """RGBA8 of f (f_frac bits, 1.0 = whole table) box-filtered over width w.

    u = f N (units 2^-f_frac entries); mod: u taken mod N; clamp: u saturated to
    [-W/2, N + W/2] with W = 2^w_cap_log2 (exact: any window beyond it sees only an
    edge entry; sat2: [-W, N + W]).
    Filter "sat2": w [..., 2] holds the screen components (a, b) and cmap_sat2 averages
    the colour map over the trapezoid they span. Filter "sat": D = I(u + w/2) - I(u - w/2) (eq. 15 and every edge
    case of 3.3.2 as one integral), out = floor(D / w + 1/2) (div_bits = 0) or the
    normalised division of colour_divide (cmap_sat, cmap_divide); w = 0 or filter off: the
    point lookup C(u).
    Filter "mip": level floor(log2 w), point lookup in it.

    Contract (as the RTL's): 0 <= w <= 2^(w_cap_log2 + f_frac) (filter_width saturates
    there) and csat = cumsum(clut), mip from build_tables (the host writes them).
    """
    if np.any(np.asarray(w) > (1 << (cfg.w_cap_log2 + cfg.f_frac))) or np.any(np.asarray(w) < 0):
        raise ValueError(f"colour_map: w outside [0, 2^{cfg.w_cap_log2 + cfg.f_frac}]")
    n_log2 = tex.n_log2
    f = np.asarray(f, dtype=I64)
    w = np.asarray(w, dtype=I64)
    u = cmap_u(cfg, f, tex.mode, n_log2)
    filt = {"none": 0, "sat": 1, "mip": 2, "sat2": 3}[cmap_family(cfg)]
    tables = host_tables(tex)
    if filt == 3:  # the trapezoid: w [..., 2] = (a, b); filter off: both 0, the point lookup
        ab = w if tex.filter else np.zeros_like(w)
        out = cmap_sat2(cfg, tables, u, ab[..., 0], ab[..., 1], tex.mode, n_log2)
    elif filt == 1:  # the box filter; filter off: w = 0, its point lookup
        out = cmap_sat(cfg, tables, u, w if tex.filter else np.zeros_like(w), tex.mode, n_log2)
    elif filt == 2:
        out = cmap_mip(cfg, tables, u, w if tex.filter else np.zeros_like(w), tex.mode, n_log2, int(tex.filter))
    else:
        out = cmap_point(cfg, tables, u, tex.mode, n_log2)
    return out.astype(np.uint8)


def fc_log2(x, lf: int):
    """Piecewise-linear log2 (Mitchell 1962) of integers x >= 1 in lf fraction bits
    (rtl/fc_weight.v): e = bitlen(x) - 1, ((e << lf) + floor((x - 2^e) 2^lf / 2^e)), exact
    at powers of two, at most 0.086 octave below log2 x between them. x = 0 gives -2^lf - 1
    (callers mask it)."""
    x = np.asarray(x, dtype=I64)
    e = np.maximum(bitlen(x) - 1, 0)
    m = x - (I64(1) << e)
    frac = np.where(e >= lf, m >> np.clip(e - lf, 0, 63), m << np.clip(lf - e, 0, 63))
    return (e << lf) + frac


def fc_weight(cfg: Config, tex: TexInt, Jm, je):
    """Frequency clamping (filters "sat_fc" and "sat2_fc", rtl/fc_weight.v; docs/filters.md): per term i the
    fade alpha_i u1.{fc_af} and the width wv of the faded terms' spread (u.{f_frac} entries).

    The footprint of a pixel in term i's noise cells is taken axis by axis: s_k moves by up to
    m_k = max_c |J_kc| a pixel (J = Jm 2^je, row k), and term i's lattice by up to
    t_ik = max_j |T_i,jk| cells per unit of s_k (column k of T_i), so
      L_i = max_k (fc_log2(m_k) + je 2^lf + fc_log2(t_ik) - (t_frac - te_i) 2^lf)   (2^-lf octaves, lf = fc_log_frac)
    over the axes with m_k > 0 and t_ik > 0 (log2 of the largest entry of |T_i| |J|, within a
    factor 3 of |T_i J|'s), and
      alpha_i = clip(fc_knee - L_i, 0, 2^fc_af)       (1 = the term as it is, 0 = its mean, 0)
    (so the fade spans 2^fc_fade_log2 octaves below phi = 2^(fc_knee 2^-lf)); alpha_i = 1 when
    no axis qualifies (J or T_i zero), a_i = 0, the term is past k_used or the texture is
    unfiltered. A faded term's spread stands in for it in the filter width: sd_i = (2^fc_af -
    alpha_i) |a_i| 2^ae_i (u.{fc_af + a_frac}), and
      wv = min(shift((max_i sd_i) fc_ks 2^n_log2, f_frac - fc_af - a_frac - FC_KSF), 2^(w_cap_log2 + f_frac))
    with fc_ks = sigma sqrt(12) of the lattice noise (config.fc_sigma12). Returns (alpha [..., K], wv [...])."""
    lf, af = cfg.fc_log_frac, cfg.fc_af
    one = I64(1) << af
    Jm = np.asarray(Jm, dtype=I64)
    m = np.max(np.abs(Jm), axis=-1)  # [..., 3]: per row k of J
    lm = fc_log2(m, lf) + (np.asarray(je, dtype=I64) << lf)[..., None]
    K = cfg.noise_terms
    alpha = np.full(m.shape[:-1] + (K,), one, dtype=I64)
    sd = np.zeros(m.shape[:-1], dtype=I64)
    neg = I64(-(1 << 62))
    for i in range(min(tex.k_used, len(tex.a), K)):
        a = int(tex.a[i])
        if not tex.filter or a == 0:
            continue
        tk = np.max(np.abs(np.asarray(tex.T[i], dtype=I64)), axis=0)  # [3]: per column k of T_i
        lt = np.where(tk > 0, fc_log2(np.maximum(tk, 1), lf) - ((cfg.t_frac - int(tex.te[i])) << lf), neg)
        ok = (m > 0) & (tk > 0)
        L = np.max(np.where(ok, lm + lt, neg), axis=-1)
        al = np.where(ok.any(axis=-1), np.clip(cfg.fc_knee - L, 0, one), one)
        alpha[..., i] = al
        sd = np.maximum(sd, ((one - al) * abs(a)) << int(tex.ae[i]))
    cap = I64(1) << (cfg.w_cap_log2 + cfg.f_frac)
    wv = shift((sd * cfg.fc_ks) << tex.n_log2, cfg.f_frac - af - cfg.a_frac - FC_KSF)
    return alpha, np.minimum(wv, cap)


def fc_scale(cfg: Config, alpha, an, ag):
    """A term's value and gradient faded: (an alpha) >> fc_af, (ag alpha) >> fc_af, floor
    (rtl/fc_scale.v); alpha = 2^fc_af leaves them exact."""
    alpha = np.asarray(alpha, dtype=I64)
    return (an * alpha) >> cfg.fc_af, (ag * alpha[..., None]) >> cfg.fc_af


def noise_leaves(cfg: Config, tex, s, q, cq, alpha=None, skip: bool = True):
    """The leaves of the adder trees (rtl/noise_leaves.v): f leaves [q, a_k n_k, ...] and c
    leaves [cq, a_k grad n_k, ...] (without the noise gradient every c leaf is 0: the tree
    carries none), term k of the texture's (k < k_used), faded by alpha[..., k] (sat_fc,
    fc_scale). A term past k_used or with a = 0 contributes exactly 0: skip leaves it out
    (texture_stages: the sums are the same), else its leaf is 0 (the RTL's K leaves; folded,
    noise_fold's one leaf is their sum)."""
    s = np.asarray(s, dtype=I64)
    zc = np.zeros(np.shape(cq), dtype=I64)
    fl, cl = [np.asarray(q, dtype=I64)], [np.asarray(cq, dtype=I64) if cfg.noise_gradient else zc]
    for i in range(cfg.noise_terms if not skip else min(tex.k_used, len(tex.a), cfg.noise_terms)):
        if i >= min(tex.k_used, len(tex.a)) or tex.a[i] == 0:
            if not skip:
                fl.append(np.zeros(np.shape(q), dtype=I64))
                cl.append(zc)
            continue
        an, ag = noise_term(cfg, int(tex.a[i]), tex.T[i], tex.o[i], s, int(tex.te[i]), int(tex.ae[i]))
        if alpha is not None:
            an, ag = fc_scale(cfg, alpha[..., i], an, ag)
        fl.append(an)
        cl.append(ag if cfg.noise_gradient else zc)
    return fl, cl


def noise_fold(cfg: Config, tex, s):
    """The sums of rtl/noise_fold.v for pixels s [..., 3]: f_sum [...] = sum over k < k_used of
    a_k n_k and c_sum [..., 3] = sum of a_k grad n_k (0 without the noise gradient), exact
    (f_w, c_w bound them: modulo 2^f_w, 2^c_w as the RTL adds). Terms k >= k_used are ignored
    whatever their a (the fold gives their slots {ae, a} = 0); tex.te, tex.ae: the terms'
    exponents (formats.t_exp_w, a_exp_w). noise_fold_schedule gives the clocks."""
    s = np.asarray(s, dtype=I64)
    # noise_leaves' term leaves (k < k_used) beside a zero quadric leaf, summed as the RTL adds
    fl, cl = noise_leaves(cfg, tex, s, np.zeros(s.shape[:-1], dtype=I64), np.zeros(s.shape, dtype=I64))
    return sum_tree(fl, cfg.f_w), sum_tree(cl, cfg.c_w)


def noise_fold_schedule(cfg: Config, k_used: int, in_valid, ce, rst=None) -> dict:
    """The handshake of rtl/noise_fold.v per clock of a stream: in_valid[t], ce[t], rst[t] the
    inputs during clock t (k_used static). A pixel is taken on an enabled edge with in_valid and
    in_ready; it then has P = clocks_per_sample(cfg, k_used) enabled issue clocks, px_valid high on the last
    (its exit: the next pixel may be taken on that edge); its sums appear (sum_valid) after the
    LATENCY-th enabled edge counted from that last one, LATENCY = latency noise_term + noise_fold
    (rtl/tex_latency.vh). rst empties the fold: the held pixel and every sum in flight are dropped.
    Returns int64 arrays over t: in_ready, px_valid and px (the held pixel: its index in take
    order, -1 none) during clock t; take (1: a pixel taken at edge t); sum_valid and sum_px
    (the pixel whose sums f_sum, c_sum show, -1 none) after edge t (registers: they hold
    while ce = 0)."""
    n = len(in_valid)
    ce = np.ones(n, dtype=bool) if ce is None else np.asarray(ce, dtype=bool)
    rst = np.zeros(n, dtype=bool) if rst is None else np.asarray(rst, dtype=bool)
    P = clocks_per_sample(cfg, k_used)
    lat = latency("noise_term", cfg) + latency("noise_fold", cfg)
    out = {k: np.zeros(n, dtype=I64) for k in ("in_ready", "px_valid", "px", "take", "sum_valid", "sum_px")}
    busy, j, held, taken, enabled = False, 0, -1, 0, 0
    pending: list[tuple[int, int]] = []  # (enabled edge at which its sums show, pixel)
    sv, spx = 0, -1
    for t in range(n):
        last = busy and j == P - 1
        ready = (not busy) or last
        out["in_ready"][t], out["px_valid"][t], out["px"][t] = ready, last, held if busy else -1
        if rst[t]:
            busy, j, pending, sv, spx = False, 0, [], 0, -1
        elif ce[t]:
            enabled += 1
            if last:
                pending.append((enabled + lat - 1, held))
            if in_valid[t] and ready:
                busy, j, held = True, 0, taken
                taken += 1
                out["take"][t] = 1
            elif last:
                busy = False
            elif busy:
                j += 1
            sv, spx = 0, -1
            if pending and pending[0][0] == enabled:
                sv, spx = 1, pending.pop(0)[1]
        out["sum_valid"][t], out["sum_px"][t] = sv, spx
    return out


def cm_align(cfg: Config, mode, f, w, wv=None, f_waits: bool = False):
    """f and w as colour_map receives them (rtl/cm_align.v): with wv (frequency clamping) w = max(w, wv)
    (sat_fc), or with the trapezoid's pair w [..., 2] = (a, b) (sat2_fc) the larger of the two
    max'd with wv: a >= b: (max(a, wv), b), else (a, max(b, wv));
    while f waits (f_waits) it is carried in fc_w = guard + 3 bits where that is fewer than
    f_w (guard = w_cap_log2 + f_frac - 1, sat2: w_cap_log2 + f_frac): clamp mode (mode 1) saturates it to
    +-2^(guard+1), mod mode wraps it to fc_w bits; colour_map gives the same colour either
    way (rtl/cm_align.v). Returns (f, w)."""
    f = np.asarray(f, dtype=I64)
    w = np.asarray(w, dtype=I64)
    sat2 = getattr(cfg, "filter", None) in SAT2_FILTERS  # sat2: colour_map's guard W
    if wv is not None and sat2:  # the trapezoid: the larger component widened (sat2_fc)
        a, b = w[..., 0], w[..., 1]
        ge = a >= b
        w = np.stack([np.where(ge, np.maximum(a, wv), a), np.where(ge, b, np.maximum(b, wv))], axis=-1)
    elif wv is not None:
        w = np.maximum(w, wv)
    guard = cfg.w_cap_log2 + cfg.f_frac - 1 + sat2
    fc_w = guard + 3
    if f_waits and fc_w < cfg.f_w:
        top = 1 << (guard + 1)
        wrap = ((f + (1 << (fc_w - 1))) & ((1 << fc_w) - 1)) - (1 << (fc_w - 1))
        f = np.where(np.asarray(mode) == MODE_CLAMP, np.clip(f, -top, top), wrap)
    return f, w


def texture_sum(cfg: Config, tex: TexInt, s, Jm, je):
    """f and grad f of pixels s [..., 3] (rtl/texture_sum.v): (f, c, wv). f = q + sum a_i n_i
    and, with the noise gradient, c = dq/ds + sum a_i grad n_i, summed exactly in the adder
    trees (sum_tree); without it c = dq/ds (the quadric's, to filter_width). With sat_fc or sat2_fc
    (unfolded terms) each term is faded by fc_weight's alpha (from Jm [..., 3, 2], je) and wv
    is the faded terms' spread; otherwise wv is None."""
    s = np.asarray(s, dtype=I64)
    fc = freq_clamp(cfg)
    alpha, wv = fc_weight(cfg, tex, Jm, je) if fc else (None, None)
    q, cq = quadric_mac(cfg, tex.Q, s)
    fl, cl = noise_leaves(cfg, tex, s, q, cq, alpha)
    # without the noise gradient the tree carries none: grad f = grad q (to filter_width)
    return sum_tree(fl, cfg.f_w), (sum_tree(cl, cfg.c_w) if cfg.noise_gradient else cq), wv


def texture_stages(cfg: Config, tex: TexInt, s, Jm, je):
    """The whole pixel pipeline with its intermediate signals: f, c, w and rgba.

    f = q + sum a_i n_i and c = dq/ds + sum a_i (dn_i/dp) T_i are summed exactly
    (words wide enough, docs/numerics.md), over the terms the texture uses (k_used), in
    any order: the sums are exact, so the RTL's order (all terms at once, or U a clock on
    noise units, noise_fold) gives the same bits. A term with a = 0 contributes exactly 0
    (a * anything = 0 before every floor shift), so it is skipped.
    """
    f, c, wv = texture_sum(cfg, tex, s, Jm, je)
    sat2 = cmap_family(cfg) == "sat2"  # the two screen components (a, b) instead of |grad f|
    w = filter_width(cfg, c, np.asarray(Jm, dtype=I64), je, tex.n_log2, components=sat2)
    # the faded terms' spread widens the box (sat_fc) or the trapezoid's larger side (sat2_fc); f whole (the RTL may carry it in
    # fewer bits, the same colour)
    f_cm, w = cm_align(cfg, tex.mode, f, w, wv)
    out = {"f": f, "c": c, "w": w.max(axis=-1) if sat2 else w, "rgba": colour_map(cfg, tex, f_cm, w)}
    if sat2:
        out["ab"] = w
    return out


def sample_expand(cfg: Config, s, Jm, je, k: int):
    """Sub-pixel sample k of pixels s [..., 3], Jm [..., 3, 2], je [...] (rtl/sample_expand.v):
    (s_k, Jm_k, je_k). s_k = sat(s + round(J d_k)), d_k = SAMPLE_OFFSETS[samples][k] / 4 pixel,
    round(J d_k) = floor(m 2^(je - 2 + s_frac) + 1/2) with m = dx Jm[r][0] + dy Jm[r][1],
    saturated to s's range; the footprint of the sample's cell (SAMPLE_FOOTPRINT): 4 samples
    J / 2 as je - 1 (at je's least value je), 2 samples J's y column halved, Jm_k[r][1] =
    floor((Jm[r][1] + 1) / 2) (x column and je unchanged)."""
    s = np.asarray(s, dtype=I64)
    Jm = np.asarray(Jm, dtype=I64)
    je = np.asarray(je, dtype=I64)
    dx, dy = SAMPLE_OFFSETS[cfg.samples][k]
    m = dx * Jm[..., 0] + dy * Jm[..., 1]  # [..., 3]
    e = (je - 2 + cfg.s_frac)[..., None]
    # the RTL caps the shifts where the result no longer changes: left past s_w + 1 it saturates,
    # right past j_w + 2 every m rounds to 0; the same caps keep int64 exact here
    shl = np.minimum(np.maximum(e, 0), cfg.s_w + 1)
    shr = np.minimum(np.maximum(-e, 0), cfg.j_w + 2)
    off = np.where(e >= 0, m << shl, (m + ((I64(1) << shr) >> 1)) >> shr)
    lo, hi = -(1 << (cfg.s_w - 1)), (1 << (cfg.s_w - 1)) - 1
    s_k = np.clip(s + off, lo, hi)
    if cfg.samples == 4:
        je_min = -(1 << (cfg.je_w - 1))
        return s_k, Jm, np.where(je > je_min, je - 1, je)
    Jm_k = Jm.copy()
    Jm_k[..., 1] = (Jm[..., 1] + 1) >> 1
    return s_k, Jm_k, je


def sample_average(cfg: Config, rgba):
    """The average of a pixel's samples' colours (rtl/sample_average.v): rgba [samples, ..., 4]
    RGBA8 -> [..., 4], floor((sum + samples / 2) / samples) per channel."""
    n = cfg.samples
    return (np.sum(np.asarray(rgba, dtype=I64), axis=0) + n // 2) // n


def texture_pipeline(cfg: Config, tex: TexInt, s, Jm, je):
    """RGBA8 [..., 4] for pixels s [..., 3], Jm [..., 3, 2], je [...]: the RTL top's twin
    (features.samples > 1: each pixel's sub-pixel samples, sample_expand, through the pipeline,
    their colours averaged, sample_average)."""
    if cfg.samples == 1:
        return texture_stages(cfg, tex, s, Jm, je)["rgba"]
    outs = [texture_stages(cfg, tex, *sample_expand(cfg, s, Jm, je, k))["rgba"] for k in range(cfg.samples)]
    return sample_average(cfg, outs)
