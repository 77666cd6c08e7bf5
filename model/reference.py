"""Float64 reference model of the texture unit, written from the equations of
Hart et al. 1999, "Antialiased Parameterized Solid Texturing Simplified for
Consumer-Level Hardware Implementation", sections 2 and 3.

This is NOT a twin of the integer golden model (model/hw/golden.py) and shares no
code with it: it is the exact mathematics in float64, so that it can catch a
mistake that the golden model and the RTL make together. Every function is
vectorized over arrays of any shape (whole frames); trailing axes hold vector
components ([..., 3] for s, [..., 3, 2] for J = ds/d(x, y), [..., C] for colours).

Conventions (the project's):

* f is in colour-map units: f = 1 is one whole table. With an N-entry table the
  index is u = f * N (entries) and a filter width w (colour-map units) spans
  W = w * N entries. u and W are the float64 products f * N and w * N.
* Entry j of the table covers u in [j, j + 1): the colour function is
  C(u) = clut[floor(u) mod N] (mode "mod") or clut[clip(floor(u), 0, N - 1)]
  (mode "clamp"). The paper's eq. (2) writes round(); floor is used so that the
  summed-area table of eqs. (13)-(15) integrates exactly this piecewise-constant
  function (entry j's integral is clut[j] over a unit interval starting at j).
* The quadric is q(s) = x^T Q x, x = [s, t, r, 1], Q from A..J as in eqs. (3), (4).
* The noise is a hashed lattice value noise of period P = 2**hash_bits per axis.

Note on eq. (11): the paper writes grad q = 2 [s t r 0] Q [ds/dx; 0]. The
homogeneous coordinate must be 1, not 0: d(x^T Q x) = 2 x^T Q dx with
x = [s, t, r, 1] and dx = [ds, 0], so the linear terms D, G, I contribute
2 (D, G, I) . ds. With [s t r 0] a texture such as marble (f = r + ...) would get
no quadric gradient at all. This module uses [s t r 1].
"""
from __future__ import annotations

import numpy as np

from model.texture import TextureParams  # noqa: F401  (re-exported)


__all__ = [
    "TextureParams",
    "unfiltered_lookup",
    "filtered_lookup",
    "quadric_matrix",
    "quadric",
    "quadric_gradient",
    "quadric_screen_gradient",
    "noise",
    "noise_gradient",
    "texture_f",
    "texture_grad_f",
    "filter_width",
    "trapezoid_lookup",
    "shade",
]

MODES = ("mod", "clamp")
BLENDS = ("linear", "cubic")


# ---------------------------------------------------------------------------
# Colour table: eq. (2) and the box filter of eqs. (9), (13)-(15)


def _table(clut) -> np.ndarray:
    t = np.asarray(clut)
    if t.ndim != 2 or t.shape[0] < 1:
        raise ValueError(f"clut: expected an array [N, C] with N >= 1, got shape {t.shape}")
    return t.astype(np.float64)


def _check_mode(mode: str) -> None:
    if mode not in MODES:
        raise ValueError(f"mode: expected one of {MODES}, got {mode!r}")


def _entry(j: np.ndarray, n: int, mode: str) -> np.ndarray:
    """Table index of the entry covering [j, j + 1) (j integer-valued float64)."""
    if mode == "mod":
        return np.mod(j, n).astype(np.int64)  # np.mod of floats is exact (fmod)
    return np.clip(j, 0, n - 1).astype(np.int64)


def unfiltered_lookup(clut, f, mode: str) -> np.ndarray:
    """Point sample of the colour map, eq. (2): C(u) with u = f * N.

    clut: [N, C] (uint8 or any numeric); f: array of any shape (colour-map units).
    Returns float64 [..., C] (same units as clut: 0..255 for uint8 RGBA).
    Entry floor(u) is used, not round(u) as eq. (2) writes (see module docstring).
    """
    _check_mode(mode)
    table = _table(clut)
    u = np.asarray(f, dtype=np.float64) * table.shape[0]
    return table[_entry(np.floor(u), table.shape[0], mode)]


def _run_right(table, p2, b, x, mode):
    """Integral of C over [b, b + x] (b integer-valued float64 array, x >= 0 float64).

    table: [N, C] float64; p2: prefix sums of the table repeated twice, [2N + 1, C]
    (p2[k] = sum of the first k entries of table ++ table). Every sum of whole
    entries is taken from p2 (exact: integers below 2^53); only the fractional
    last entry and the whole-period count are floats.
    """
    n = table.shape[0]
    if mode == "mod":
        b0 = np.mod(b, n).astype(np.int64)
        k, r = np.divmod(x, n)  # k whole periods, r in [0, N): fmod is exact
        m = np.floor(r)
        fr = r - m  # exact (r >= 0)
        mi = m.astype(np.int64)
        whole = p2[b0 + mi] - p2[b0]  # mi entries from b0, wrapping at most once
        part = table[(b0 + mi) % n] * fr[..., None]
        return k[..., None] * p2[n] + whole + part
    # clamp: the run splits into (-inf, 0) [entry 0], [0, N] [the table], (N, inf) [entry N-1]
    below = np.where(b < 0, np.minimum(x, -b), 0.0)
    above = np.maximum(x - np.maximum(n - b, 0.0), 0.0)
    s0 = np.clip(b, 0, n)
    mid = np.clip(x - np.maximum(-b, 0.0), 0.0, n - s0)
    m = np.floor(mid)
    fr = mid - m
    s0i = s0.astype(np.int64)
    mi = m.astype(np.int64)
    whole = p2[s0i + mi] - p2[s0i]  # s0 + m <= N: the first copy of the table
    part = table[np.minimum(s0i + mi, n - 1)] * fr[..., None]
    return below[..., None] * table[0] + above[..., None] * table[n - 1] + whole + part


def _prefix2(table: np.ndarray) -> np.ndarray:
    p = np.zeros((2 * table.shape[0] + 1, table.shape[1]), dtype=np.float64)
    np.cumsum(np.concatenate([table, table]), axis=0, out=p[1:])
    return p


def filtered_lookup(clut, f, w, mode: str) -> np.ndarray:
    """Exact box filter of the colour map, eq. (9):

        (1 / W) * integral_{u - W/2}^{u + W/2} C(v) dv,   u = f * N,  W = |w| * N,

    with C the floor-convention colour function of `unfiltered_lookup`, extended
    beyond the table by mod or clamp (section 3.3.2). f and w broadcast together;
    both are in colour-map units. w == 0 returns C(u), the limit of a window inside
    one entry. Returns float64 [..., C].

    Mathematically this is (I(b) - I(a)) / W with I(x) = integral_0^x C:
      mod:   I(x) = floor(x / N) * total + S(x mod N)
      clamp: I(x) = x clut[0] (x < 0);  S(x) (0 <= x <= N);  total + (x - N) clut[N-1] (x > N)
      S(x) = sum_{k < floor(x)} clut[k] + frac(x) clut[floor(x)]
    It is evaluated without forming a and b, to avoid cancellation: the window is
    split at the boundaries of the entry j = floor(u) that holds u, into the part
    inside entry j and two runs leaving it (leftwards from j, rightwards from j + 1).
    The distances from u to those two boundaries are exact (the smaller of the two
    always is, by Sterbenz), so a tiny window just crossing a boundary gets its
    weights to full relative precision, and whole periods of a huge window (mod)
    are counted as integers. Exact up to float64 rounding for |u|, W < 2^52.
    """
    _check_mode(mode)
    table = _table(clut)
    n = table.shape[0]
    f, w = np.broadcast_arrays(np.asarray(f, dtype=np.float64), np.asarray(w, dtype=np.float64))
    u = f * n
    h = (np.abs(w) * n) / 2  # half window, entries
    j = np.floor(u)
    dl = u - j  # distance from u to the left boundary of entry j
    dr = (j + 1) - u  # ... and to its right boundary
    centre = table[_entry(j, n, mode)]
    inside = (h <= dl) & (h <= dr)  # also h == 0
    xl = np.maximum(h - dl, 0.0)  # length of the window left of entry j
    xr = np.maximum(h - dr, 0.0)  # ... and right of it
    right = _run_right(table, _prefix2(table), j + 1, xr, mode)
    # the left run [j - xl, j] is the right run [N - j, N - j + xl] of the mirrored
    # table (v -> N - v maps entry k to entry N-1-k, in both modes)
    rev = table[::-1]
    left = _run_right(rev, _prefix2(rev), n - j, xl, mode)
    num = centre * (np.minimum(h, dl) + np.minimum(h, dr))[..., None] + left + right
    den = np.where(inside, 1.0, 2.0 * h)
    return np.where(inside[..., None], centre, num / den[..., None])


# ---------------------------------------------------------------------------
# The trapezoid (filter "sat2", issue 27): exact for f linear across the pixel

TRAP_CAP = 2.0 ** 40  # widths (entries) beyond this are taken at it: a change below 255 N 2^-40
TRAP_BOX = 1e-7  # min(A, B) below this times max(A, B): the box of width A + B (within 255 * 1e-7 / 2)


def _int_tables(clut):
    """Exact integer tables of a clut: P[k] = sum_{j<k} clut[j] (k = 0..N) and
    Q2[k] = 2 integral_0^k S = sum_{j<k} (2 P[j] + clut[j]), int64 [N + 1, C]."""
    t = np.asarray(clut).astype(np.int64)
    n = t.shape[0]
    P = np.zeros((n + 1, t.shape[1]), dtype=np.int64)
    P[1:] = np.cumsum(t, axis=0)
    Q2 = np.zeros_like(P)
    Q2[1:] = np.cumsum(2 * P[:-1] + t, axis=0)
    return t, P, Q2


def _s_g2_int(t, P, Q2, k, mode):
    """S(k) and 2G(k) (S = integral_0^x C, G = integral_0^x S) at integer k (int64 array), as
    Python integers (object arrays [..., C]): mod, k = mN + r: S = m T + P[r],
    2G = T N m (m - 1) + m Q2[N] + 2 m T r + Q2[r]; clamp: x clut[0] and x^2 clut[0] below 0,
    T + (k - N) clut[N-1] and Q2[N] + 2 T (k - N) + (k - N)^2 clut[N-1] above N."""
    n = t.shape[0]
    T, G2N = P[n].astype(object), Q2[n].astype(object)
    if mode == "mod":
        m, r = np.divmod(k, n)
        mo, ro = m.astype(object)[..., None], r.astype(object)[..., None]
        S = mo * T + P[r].astype(object)
        G2 = T * n * mo * (mo - 1) + mo * G2N + 2 * mo * T * ro + Q2[r].astype(object)
        return S, G2
    kc = np.clip(k, 0, n)
    lo = np.minimum(k, 0).astype(object)[..., None]
    hi = np.maximum(k - n, 0).astype(object)[..., None]
    c0, cl = t[0].astype(object), t[n - 1].astype(object)
    S = P[kc].astype(object) + lo * c0 + hi * cl
    G2 = Q2[kc].astype(object) + lo * lo * c0 + 2 * hi * T + hi * hi * cl
    return S, G2


def trapezoid_lookup(clut, f, gx, gy, mode: str) -> np.ndarray:
    """The pixel's average of the colour map when f is linear across it (filter "sat2"):
    f + gx x + gy y with x, y uniform in [-1/2, 1/2], i.e. C convolved with two boxes of widths
    A = |gx| N and B = |gy| N entries (a trapezoid):

        (1 / AB) [G(u + A/2 + B/2) - G(u + A/2 - B/2) - G(u - A/2 + B/2) + G(u - A/2 - B/2)],

    u = f N, G(x) = integral_0^x S, S(x) = integral_0^x C (C as in `unfiltered_lookup`, extended
    by mod or clamp). Evaluated without cancellation: G is taken relative to the entry boundary
    z nearest u, G_z(x) = G(x) - G(z) - S(z) (x - z) (the four-point difference is the same),
    its whole-entry part from exact integer tables (Python integers) and only the fraction in
    float64. Degenerate cases as limits: a window inside one entry (also A = B = 0) is that
    entry's colour; min(A, B) < TRAP_BOX max(A, B) the box of width A + B (filtered_lookup);
    A, B above TRAP_CAP entries are taken at it. Returns float64 [..., C]."""
    _check_mode(mode)
    t, P, Q2 = _int_tables(clut)
    n = t.shape[0]
    f, gx, gy = np.broadcast_arrays(*(np.asarray(v, dtype=np.float64) for v in (f, gx, gy)))
    A = np.minimum(np.abs(gx) * n, TRAP_CAP)
    B = np.minimum(np.abs(gy) * n, TRAP_CAP)
    u = f * n
    if mode == "mod":
        u = np.mod(u, n)
    else:
        u = np.clip(u, -(A + B) - 1, n + (A + B) + 1)
    h = (A + B) / 2
    inside = np.floor(u - h) == np.floor(u + h)
    inside &= (u + h) < np.floor(u - h) + 1
    box = ~inside & (np.minimum(A, B) < TRAP_BOX * np.maximum(A, B))
    trap = ~inside & ~box
    out = np.asarray(unfiltered_lookup(clut, u / n, mode), dtype=np.float64)
    if box.any():
        out[box] = filtered_lookup(clut, u[box] / n, (A + B)[box] / n, mode)
    if trap.any():
        ut, At, Bt = u[trap], A[trap], B[trap]
        z = np.rint(ut)
        zi = z.astype(np.int64)
        Sz, G2z = _s_g2_int(t, P, Q2, zi, mode)
        acc = np.zeros(ut.shape + (t.shape[1],), dtype=np.float64)
        for sa, sb, sign in ((1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)):
            d = (ut - z) + sa * At / 2 + sb * Bt / 2
            fl = np.floor(d)
            fr = (d - fl)[..., None]
            k = zi + fl.astype(np.int64)
            Sk, G2k = _s_g2_int(t, P, Q2, k, mode)
            whole = (G2k - G2z - 2 * Sz * (k - zi).astype(object)[..., None]).astype(np.float64)
            part = 2.0 * (Sk - Sz).astype(np.float64) * fr + t[_entry(k.astype(np.float64), n, mode)] * fr * fr
            acc += sign * (whole + part)
        out[trap] = acc / (2.0 * At * Bt)[..., None]
    return out


# ---------------------------------------------------------------------------
# Quadric: eqs. (3), (4), (11)


def quadric_matrix(Qcoef) -> np.ndarray:
    """Symmetric Q [..., 4, 4] of eq. (4) from coefficients (A..J) [..., 10] of eq. (3)."""
    c = np.asarray(Qcoef, dtype=np.float64)
    if c.shape[-1:] != (10,):
        raise ValueError(f"Qcoef: expected [..., 10] coefficients A..J, got shape {c.shape}")
    A, B, C, D, E, F, G, H, I, J = np.moveaxis(c, -1, 0)
    rows = [[A, B, C, D], [B, E, F, G], [C, F, H, I], [D, G, I, J]]
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)


def _homog(s) -> np.ndarray:
    s = np.asarray(s, dtype=np.float64)
    return np.concatenate([s, np.ones(s.shape[:-1] + (1,))], axis=-1)


def quadric(Qcoef, s) -> np.ndarray:
    """q(s) = x^T Q x, x = [s, t, r, 1] (eq. 4). s: [..., 3]; returns [...]."""
    x = _homog(s)
    qx = np.matmul(quadric_matrix(Qcoef), x[..., None])[..., 0]
    return np.sum(x * qx, axis=-1)


def quadric_gradient(Qcoef, s) -> np.ndarray:
    """dq/ds = 2 (Q x)[0:3], x = [s, t, r, 1]. s: [..., 3]; returns [..., 3]."""
    x = _homog(s)
    return 2.0 * np.matmul(quadric_matrix(Qcoef), x[..., None])[..., :3, 0]


def quadric_screen_gradient(Qcoef, s, J) -> np.ndarray:
    """grad q = 2 [s t r 1] Q [J; 0 0] (eq. 11, homogeneous 1: see module docstring).

    s: [..., 3]; J = ds/d(x, y): [..., 3, 2]; returns [..., 2].
    """
    g = quadric_gradient(Qcoef, s)
    return np.matmul(g[..., None, :], np.asarray(J, dtype=np.float64))[..., 0, :]


# ---------------------------------------------------------------------------
# Noise: hashed lattice value noise (section 2.1.3)


def _period(perm) -> tuple[np.ndarray, int]:
    perm = np.asarray(perm, dtype=np.int64)
    p = perm.shape[0]
    if perm.ndim != 1 or p < 2 or p & (p - 1) or not np.array_equal(np.sort(perm), np.arange(p)):
        raise ValueError("perm: expected a permutation of range(2**hash_bits)")
    return perm, p


def _blend(fr: np.ndarray, blend: str):
    """Blend weight and its derivative at the cell fraction fr."""
    if blend == "linear":
        return fr, np.ones_like(fr)
    if blend == "cubic":
        return fr * fr * (3.0 - 2.0 * fr), 6.0 * fr * (1.0 - fr)
    raise ValueError(f"blend: expected one of {BLENDS}, got {blend!r}")


def _noise(p, perm, blend, want_grad):
    perm, period = _period(perm)
    p = np.asarray(p, dtype=np.float64)
    if p.shape[-1:] != (3,):
        raise ValueError(f"p: expected [..., 3], got shape {p.shape}")
    base = np.floor(p)
    # fraction in [0, 1]; for p just below an integer it can round to 1.0, which
    # is harmless: the interpolation then returns the next corner, its limit
    fr = p - base
    i0 = np.mod(base, period).astype(np.int64)  # lattice corner, mod P (exact fmod)
    i1 = (i0 + 1) % period
    s, ds = _blend(fr, blend)
    wts = (1.0 - s, s)  # weights of corner offsets 0 and 1, per axis
    dws = (-ds, ds)
    idx = (i0, i1)
    half = period / 2
    val = np.zeros(p.shape[:-1])
    grad = np.zeros(p.shape) if want_grad else None
    for cx in (0, 1):
        for cy in (0, 1):
            for cz in (0, 1):
                h = perm[perm[perm[idx[cx][..., 0]] ^ idx[cy][..., 1]] ^ idx[cz][..., 2]]
                v = (h - half) / half  # corner value in [-1, 1)
                wx, wy, wz = wts[cx][..., 0], wts[cy][..., 1], wts[cz][..., 2]
                val += wx * wy * wz * v
                if want_grad:
                    grad[..., 0] += dws[cx][..., 0] * wy * wz * v
                    grad[..., 1] += wx * dws[cy][..., 1] * wz * v
                    grad[..., 2] += wx * wy * dws[cz][..., 2] * v
    return val, grad


def noise(p, perm, blend: str = "cubic") -> np.ndarray:
    """Lattice value noise n(p), p: [..., 3] in noise space; returns [...].

    Period P = len(perm) = 2**hash_bits per axis. The 8 corners floor(p) + {0,1}^3
    (each mod P) get values (h - P/2) / (P/2), h = perm[perm[perm[ix] ^ iy] ^ iz],
    blended trilinearly with weights s(fx) = fx (linear) or 3 fx^2 - 2 fx^3 (cubic),
    fx = p_x - floor(p_x).
    """
    return _noise(p, perm, blend, False)[0]


def noise_gradient(p, perm, blend: str = "cubic") -> np.ndarray:
    """Analytic dn/dp [..., 3] of `noise` (blend slope 1 or 6 fx - 6 fx^2).

    On a cell face the one-sided derivative from the cell holding p is returned
    (the linear blend's gradient is discontinuous there; the cubic one is not).
    """
    return _noise(p, perm, blend, True)[1]


# ---------------------------------------------------------------------------
# Texture: eqs. (1), (10)-(12)


def _terms(tex):
    """(a, T, o) of each noise term; accepts model.texture.NoiseTerm or 3-tuples."""
    out = []
    for term in tex.terms:
        if hasattr(term, "a"):
            a, T, o = term.a, term.T, term.o
        else:
            a, T, o = term
        out.append((float(a), np.asarray(T, dtype=np.float64).reshape(3, 3),
                    np.asarray(o, dtype=np.float64).reshape(3)))
    return out


def _perm_for(perm, hash_bits):
    perm = np.asarray(perm, dtype=np.int64)
    if hash_bits is not None and perm.shape[0] != 1 << int(hash_bits):
        raise ValueError(f"perm has {perm.shape[0]} entries, hash_bits={hash_bits} wants {1 << int(hash_bits)}")
    return perm


def texture_f(tex, s, perm, hash_bits=None) -> np.ndarray:
    """Colour-map index f = q(s) + sum_i a_i n(T_i s + o_i) (eq. 1). s: [..., 3]; returns [...]."""
    perm = _perm_for(perm, hash_bits)
    s = np.asarray(s, dtype=np.float64)
    f = quadric(tex.Q, s)
    for a, T, o in _terms(tex):
        f = f + a * noise(s @ T.T + o, perm, tex.blend)
    return f


def texture_grad_f(tex, s, J, perm, hash_bits=None) -> np.ndarray:
    """Screen gradient of f, eq. (10): grad q + sum_i a_i (dn/dp)(T_i s + o_i) T_i J.

    s: [..., 3]; J = ds/d(x, y): [..., 3, 2]; returns [..., 2]. The noise terms are
    included only if tex.noise_gradient (eq. 12); otherwise grad f = grad q.
    """
    perm = _perm_for(perm, hash_bits)
    s = np.asarray(s, dtype=np.float64)
    J = np.asarray(J, dtype=np.float64)
    g = quadric_gradient(tex.Q, s)  # df/ds, [..., 3]
    if tex.noise_gradient:
        for a, T, o in _terms(tex):
            g = g + a * (noise_gradient(s @ T.T + o, perm, tex.blend) @ T)
    return np.matmul(g[..., None, :], J)[..., 0, :]


def filter_width(tex, s, J, perm, hash_bits=None) -> np.ndarray:
    """Box filter width w = |grad f| (Euclidean, colour-map units), section 3.1. Returns [...]."""
    g = texture_grad_f(tex, s, J, perm, hash_bits)
    return np.hypot(g[..., 0], g[..., 1])


def mitchell_log2(x) -> np.ndarray:
    """log2 with the mantissa taken as linear (Mitchell 1962): e + x / 2^e - 1, e = floor(log2 x),
    for x > 0: exact at powers of two, at most 0.086 below log2 x. The fade of the
    frequency clamp is defined on it (the hardware's fc_log2 is its floor in fixed point)."""
    x = np.asarray(x, dtype=np.float64)
    m, e = np.frexp(x)  # x = m 2^e, m in [0.5, 1)
    return (e - 1) + (2.0 * m - 1.0)


def fc_alpha(tex, J) -> list:
    """The fade alpha_i [...] of each noise term under frequency clamping (tex.fc = (knee, fade)
    octaves): alpha_i = clip((knee - L_i) / fade, 0, 1), L_i = max_k (mitchell_log2(max_c |J_kc|) +
    mitchell_log2(max_j |T_i,jk|)) over the axes k where both are non-zero, the footprint of a
    pixel in term i's cells; 1 where no axis qualifies."""
    knee, fade = tex.fc
    J = np.asarray(J, dtype=np.float64)
    mk = np.max(np.abs(J), axis=-1)  # [..., 3]
    lj = mitchell_log2(np.where(mk > 0, mk, 1.0))
    out = []
    for _a, T, _o in _terms(tex):
        tk = np.max(np.abs(T), axis=0)
        ok = (mk > 0) & (tk > 0)
        L = np.max(np.where(ok, lj + mitchell_log2(np.where(tk > 0, tk, 1.0)), -np.inf), axis=-1)
        al = np.clip((knee - L) / fade, 0.0, 1.0)
        out.append(np.where(ok.any(axis=-1), al, 1.0))
    return out


def shade_fc(tex, s, J, perm, hash_bits=None) -> np.ndarray:
    """shade with frequency clamping (filter "sat_fc", docs/filters.md; tex.filter true):
    f = q + sum_i alpha_i a_i n_i, grad f = grad q + sum_i alpha_i a_i (dn_i/dp) T_i (with
    tex.noise_gradient), w = max(|grad f J|, wv), wv = max_i (1 - alpha_i) |a_i| sigma sqrt(12)
    with sigma the lattice noise's standard deviation (model.hw.config.fc_sigma12), then the box.
    With the trapezoid (tex.trapezoid, filter "sat2_fc") the screen components A = |grad f J_x|,
    B = |grad f J_y| instead, the larger of the two widened to max(., wv) (A >= B: (max(A, wv),
    B), else (A, max(B, wv))), then trapezoid_lookup."""
    from model.hw.config import fc_sigma12

    perm = _perm_for(perm, hash_bits)
    s = np.asarray(s, dtype=np.float64)
    J = np.asarray(J, dtype=np.float64)
    alphas = fc_alpha(tex, J)
    f = quadric(tex.Q, s)
    g = quadric_gradient(tex.Q, s)
    wv = np.zeros(f.shape)
    k12 = fc_sigma12(tex.blend)
    for (a, T, o), al in zip(_terms(tex), alphas):
        val, grad = _noise(s @ T.T + o, perm, tex.blend, tex.noise_gradient)
        f = f + al * a * val
        if tex.noise_gradient:
            g = g + (al * a)[..., None] * (grad @ T)
        wv = np.maximum(wv, (1.0 - al) * abs(a) * k12)
    gs = np.matmul(g[..., None, :], J)[..., 0, :]
    if getattr(tex, "trapezoid", False):
        A, B = np.abs(gs[..., 0]), np.abs(gs[..., 1])
        ge = A >= B
        return trapezoid_lookup(tex.clut, f, np.where(ge, np.maximum(A, wv), A), np.where(ge, B, np.maximum(B, wv)),
                                tex.mode)
    w = np.maximum(np.hypot(gs[..., 0], gs[..., 1]), wv)
    return filtered_lookup(tex.clut, f, w, tex.mode)


def shade(tex, s, J, perm, hash_bits=None) -> np.ndarray:
    """Texture colour, float64 RGBA [..., 4] in clut units (0..255).

    filtered_lookup(clut, f, w, mode) if tex.filter, else unfiltered_lookup(clut, f, mode);
    with frequency clamping (tex.fc, filter "sat_fc", "sat2_fc") shade_fc; with the trapezoid
    (tex.trapezoid, filter "sat2") trapezoid_lookup on the two screen components of grad f.
    With sub-pixel samples (tex.samples > 1) the mean of shade_samples' samples.
    """
    if getattr(tex, "samples", 1) > 1:
        return shade_samples(tex, s, J, perm, hash_bits)
    return _shade_one(tex, s, J, perm, hash_bits)


def shade_samples(tex, s, J, perm, hash_bits=None) -> np.ndarray:
    """The mean colour of a pixel's tex.samples sub-pixel samples (features.samples): sample k at
    s + J d_k, d_k = model.hw.config.SAMPLE_OFFSETS[samples][k] / 4 pixel (J's columns: one pixel
    step in x and in y), each shaded with the footprint of its cell of the pixel, J with its columns
    scaled by SAMPLE_FOOTPRINT[samples] (2: J's y column halved, the pixel's upper and lower halves;
    4: J / 2, its quarters)."""
    from model.hw.config import SAMPLE_FOOTPRINT, SAMPLE_OFFSETS

    n = tex.samples
    s = np.asarray(s, dtype=np.float64)
    J = np.asarray(J, dtype=np.float64)
    Jk = J * np.asarray(SAMPLE_FOOTPRINT[n])
    out = 0.0
    for dx, dy in SAMPLE_OFFSETS[n]:
        out = out + _shade_one(tex, s + (dx * J[..., 0] + dy * J[..., 1]) / 4.0, Jk, perm, hash_bits)
    return out / n


def _shade_one(tex, s, J, perm, hash_bits=None) -> np.ndarray:
    """shade at one sample a pixel (the pixel's centre s, its footprint J)."""
    if tex.filter and getattr(tex, "fc", None) is not None:
        return shade_fc(tex, s, J, perm, hash_bits)
    f = texture_f(tex, s, perm, hash_bits)
    if not tex.filter:
        return unfiltered_lookup(tex.clut, f, tex.mode)
    if getattr(tex, "trapezoid", False):
        g = texture_grad_f(tex, s, J, perm, hash_bits)
        return trapezoid_lookup(tex.clut, f, g[..., 0], g[..., 1], tex.mode)
    return filtered_lookup(tex.clut, f, filter_width(tex, s, J, perm, hash_bits), tex.mode)
