"""Tests of the float64 reference model (model/reference.py).

The colour-table box filter is checked against an exact rational-arithmetic
oracle that enumerates the table entries inside the window; the noise, quadric
and texture derivatives against finite differences and small scalar
re-implementations written from the paper's equations.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from model.hw.config import load_config
from model.reference import (
    filter_width,
    filtered_lookup,
    noise,
    noise_gradient,
    quadric,
    quadric_gradient,
    quadric_matrix,
    quadric_screen_gradient,
    shade,
    texture_f,
    texture_grad_f,
    unfiltered_lookup,
)
from model.texture import NoiseTerm, TextureParams

MODES = ("mod", "clamp")
BLENDS = ("linear", "cubic")
NS = (1, 2, 3, 7, 16, 256)
FULL = load_config("full")
PERMS = {name: load_config(name).perm for name in ("full", "reduced")}

# The reference computes each piece of the window (inside the entry of u, the
# runs leaving it) relative to an exact boundary distance, so its error is a few
# float64 roundings of terms <= 255: ~1e-13. 1e-9 of full scale (255) leaves a
# wide margin, yet a wrong piece as short as 1e-9 of the window (an entry off by
# one, a wrap miscounted, a window end misplaced by one ulp-sized step of u when
# W ~ 1e-6) still fails.
TOL_BOX = 1e-9 * 255


def random_clut(n: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).integers(0, 256, size=(n, 4)).astype(np.uint8)


# ---------------------------------------------------------------------------
# exact oracle for the box filter


def _sum_cells(clut: np.ndarray, lo: int, hi: int, mode: str) -> list[int]:
    """Sum of C over the whole cells k = lo .. hi-1 (cell k = [k, k+1)), in integers."""
    n = clut.shape[0]
    total = np.zeros(clut.shape[1], dtype=np.int64)
    if hi <= lo:
        return [0] * clut.shape[1]
    if mode == "mod":
        periods, rem = divmod(hi - lo, n)
        total += periods * clut.sum(axis=0, dtype=np.int64)
        total += clut[(lo + np.arange(rem)) % n].sum(axis=0, dtype=np.int64)
    else:
        total += max(0, min(hi, 0) - lo) * clut[0].astype(np.int64)
        total += max(0, hi - max(lo, n)) * clut[n - 1].astype(np.int64)
        total += clut[max(lo, 0):max(min(hi, n), 0)].sum(axis=0, dtype=np.int64)
    return [int(v) for v in total]


def exact_box(clut: np.ndarray, f: float, w: float, mode: str) -> np.ndarray:
    """(1/W) integral of C over [u - W/2, u + W/2] in exact rationals (u = f*N, W = |w|*N as float64)."""
    n = clut.shape[0]
    u = Fraction(float(np.float64(f) * n))
    width = Fraction(float(np.abs(np.float64(w)) * n))

    def entry(k: int) -> np.ndarray:
        return clut[k % n] if mode == "mod" else clut[min(max(k, 0), n - 1)]

    if width == 0:
        return entry(math.floor(u)).astype(np.float64)
    a, b = u - width / 2, u + width / 2
    ka, kb = math.floor(a), math.floor(b)
    if ka == kb:
        return entry(ka).astype(np.float64)
    acc = [Fraction(int(v)) * (ka + 1 - a) + Fraction(int(e)) * (b - kb)
           for v, e in zip(entry(ka), entry(kb))]
    acc = [x + y for x, y in zip(acc, _sum_cells(clut, ka + 1, kb, mode))]
    return np.array([float(x / width) for x in acc])


def test_oracle_self_check():
    # hand-computed: clut [0, 255, 10], u = 0.3 * 3 = 0.9, W = 3 * 0.5 = 1.5: [0.15, 1.65]
    clut = np.array([[0], [255], [10]], dtype=np.uint8)
    f, w = 0.3, 0.5
    u, W = f * 3, w * 3
    a, b = u - W / 2, u + W / 2
    expect = ((1 - a) * 0 + (b - 1) * 255) / W
    assert exact_box(clut, f, w, "mod")[0] == pytest.approx(expect, abs=1e-12)
    # window [-1.2, 1.8] in clamp: 1.2 of entry 0, 1 of entry 0, 0.8 of entry 1
    assert exact_box(clut, 0.1, 1.0, "clamp")[0] == pytest.approx(0.8 * 255 / 3, abs=1e-12)
    assert exact_box(clut, 0.1, 1.0, "mod")[0] == pytest.approx(265 / 3, abs=1e-12)


# ---------------------------------------------------------------------------
# box filter vs oracle


def special_f(n: int) -> list[float]:
    return [0.0, 1.0, -1.0, n / n, 0.5, 1 / n, -1 / n, (n - 1) / n, 1 - 1e-15, 1e-15, -1e-15,
            -0.5 / n, 2.5, -3.25, 1e3 + 1 / (3 * n), -7.3, 1e-300]


def special_w(n: int) -> list[float]:
    return [0.0, 1e-300, 1e-13, 1e-6, 0.5 / n, 1 / n, 2 / n, 0.5, 1 - 2**-40, 1.0, 1 + 2**-40,
            1.5, 2.0, 7.3, 1e6, 1e6 + 0.37, 3.0e6 + 1e-3]


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("n", NS)
def test_box_filter_special_grid(n, mode):
    clut = random_clut(n, 100 + n)
    fs, ws = special_f(n), special_w(n)
    F, W = np.meshgrid(fs, ws, indexing="ij")
    got = filtered_lookup(clut, F, W, mode)
    assert got.shape == F.shape + (4,)
    for i, f in enumerate(fs):
        for k, w in enumerate(ws):
            np.testing.assert_allclose(got[i, k], exact_box(clut, f, w, mode), rtol=0, atol=TOL_BOX,
                                       err_msg=f"N={n} {mode} f={f!r} w={w!r}")


@st.composite
def box_case(draw):
    n = draw(st.sampled_from(NS))
    mode = draw(st.sampled_from(MODES))
    seed = draw(st.integers(0, 2**32 - 1))
    # f: anywhere, on an entry or table boundary, or just beside one
    k = draw(st.integers(-3 * n, 3 * n))
    f = draw(st.one_of(
        st.floats(-5, 5, allow_nan=False),
        st.just(k / n),
        st.builds(lambda e, s: k / n + s * e, st.floats(1e-15, 1e-6), st.sampled_from((-1, 1))),
        st.floats(-1e4, 1e4, allow_nan=False),
    ))
    # w: zero, tiny, around one entry, around one table, multiples, huge
    m = draw(st.integers(1, 4 * n))
    w = draw(st.one_of(
        st.just(0.0),
        st.floats(0, 3, allow_nan=False),
        st.builds(lambda e: 10.0**e, st.floats(-14, 6.5)),
        st.just(m / n),
        st.builds(lambda e, s: 1 + s * e, st.floats(1e-15, 1e-3), st.sampled_from((-1, 1))),
        st.builds(lambda e: 1e6 + e, st.floats(0, 1)),
        st.floats(-3, 0, allow_nan=False),  # |w| is used: a negative width is the same window
    ))
    return n, mode, seed, f, w


@settings(max_examples=400, deadline=None)
@given(box_case())
def test_box_filter_matches_exact_integral(case):
    n, mode, seed, f, w = case
    clut = random_clut(n, seed)
    np.testing.assert_allclose(filtered_lookup(clut, f, w, mode), exact_box(clut, f, w, mode),
                               rtol=0, atol=TOL_BOX)


@settings(max_examples=100, deadline=None)
@given(st.sampled_from(NS), st.integers(0, 2**32 - 1), st.integers(-5000, 5000),
       st.sampled_from(MODES), st.floats(1e-14, 1e-3), st.integers(-3, 3))
def test_box_filter_window_ends_on_boundaries(n, seed, j, mode, eps, shift):
    # u on an entry boundary +- a tiny step, window ending exactly on / just past boundaries
    clut = random_clut(n, seed)
    for f in (j / n, (j + 0.5) / n, j / n + eps, j / n - eps):
        for w in ((2 * abs(shift) + 1) / n, 1.0, 2 * eps, (1 + eps) / n):
            np.testing.assert_allclose(filtered_lookup(clut, f, w, mode), exact_box(clut, f, w, mode),
                                       rtol=0, atol=TOL_BOX, err_msg=f"f={f!r} w={w!r}")


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("n", NS)
def test_w_zero_is_unfiltered_lookup(n, mode):
    clut = random_clut(n, n)
    f = np.concatenate([np.random.default_rng(0).uniform(-3, 3, 500), np.arange(-2 * n, 2 * n + 1) / n])
    np.testing.assert_array_equal(filtered_lookup(clut, f, 0.0, mode), unfiltered_lookup(clut, f, mode))


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("n", NS)
def test_small_w_limit(n, mode):
    clut = random_clut(n, 7 * n)
    rng = np.random.default_rng(1)
    # u at least 1e-6 from an entry boundary: a window of 1e-9 entries stays inside
    j = rng.integers(-3 * n, 3 * n, 300)
    f = (j + rng.uniform(1e-6, 1 - 1e-6, j.shape)) / n
    unf = unfiltered_lookup(clut, f, mode)
    for w in (1e-9 / n, 1e-12):
        np.testing.assert_array_equal(filtered_lookup(clut, f, w, mode), unf)
    # on a boundary the symmetric window's limit is the mean of the two entries
    on = j / n
    mean2 = (unfiltered_lookup(clut, on - 0.5 / n, mode) + unfiltered_lookup(clut, on, mode)) / 2
    np.testing.assert_allclose(filtered_lookup(clut, on, 1e-12, mode), mean2, rtol=0, atol=TOL_BOX)


def test_unfiltered_lookup_floor_convention():
    n = 7
    clut = random_clut(n, 3)
    j = np.arange(-20, 21)
    for off in (0.0, 0.25, 0.999):
        f = (j + off) / n
        # ((j + off) / n) * n can round below j when off = 0; compare with its own floor
        k = np.floor(f * n).astype(int)
        np.testing.assert_array_equal(unfiltered_lookup(clut, f, "mod"), clut[k % n])
        np.testing.assert_array_equal(unfiltered_lookup(clut, f, "clamp"), clut[np.clip(k, 0, n - 1)])
    assert np.array_equal(unfiltered_lookup(clut, -1e-300, "mod"), clut[n - 1])
    assert np.array_equal(unfiltered_lookup(clut, -1e-300, "clamp"), clut[0])
    assert np.array_equal(unfiltered_lookup(clut, 1.0, "clamp"), clut[n - 1])
    assert np.array_equal(unfiltered_lookup(clut, 1.0, "mod"), clut[0])


@pytest.mark.parametrize("n", NS)
def test_whole_tables_in_mod_mode_give_the_average(n):
    clut = random_clut(n, 11 * n)
    rng = np.random.default_rng(2)
    f = np.concatenate([rng.uniform(-10, 10, 200), [0.0, 1.0, -1.0, 1e-300, -1e-300, 1e5 + 0.1, 0.5 / n]])
    for k in (1, 2, 5, 1000):
        # whole periods: the average whatever the phase (rounding of ~1e-14 of 255)
        np.testing.assert_allclose(filtered_lookup(clut, f, float(k), "mod"),
                                   np.broadcast_to(clut.mean(axis=0), f.shape + (4,)), rtol=0, atol=TOL_BOX)


@pytest.mark.parametrize("n", NS)
def test_clamp_huge_window_tends_to_mean_of_end_entries(n):
    clut = random_clut(n, 13 * n)
    f = np.array([-3.0, -0.2, 0.0, 0.5, 1.0, 4.0])
    w = 1e6
    # exact value is (c0 + cN-1)/2 + (sum(clut) - u c0 + (u - N) cN-1) / W: bounded by 255 (N + |u|) / (W/2)
    bound = 255 * (n + np.abs(f) * n) / (w * n / 2)
    got = filtered_lookup(clut, f, w, "clamp")
    lim = (clut[0].astype(float) + clut[-1]) / 2
    assert np.all(np.abs(got - lim) <= bound[:, None])


def test_box_filter_broadcasts_over_frames():
    clut = random_clut(16, 5)
    rng = np.random.default_rng(3)
    f = rng.uniform(-2, 2, (3, 5, 7))
    w = rng.uniform(0, 2, (5, 1))
    got = filtered_lookup(clut, f, w, "mod")
    assert got.shape == (3, 5, 7, 4)
    fb, wb = np.broadcast_arrays(f, w)
    for idx in [(0, 0, 0), (2, 4, 6), (1, 2, 3)]:
        np.testing.assert_allclose(got[idx], exact_box(clut, fb[idx], wb[idx], "mod"), rtol=0, atol=TOL_BOX)


# ---------------------------------------------------------------------------
# noise


def corner_value(ix: int, iy: int, iz: int, perm: np.ndarray) -> float:
    P = len(perm)
    h = perm[perm[perm[ix % P] ^ (iy % P)] ^ (iz % P)]
    return (h - P / 2) / (P / 2)


def noise_scalar(p, perm, blend) -> float:
    """Straight from the definition: one point, math.floor, nested lerps."""
    base = [math.floor(c) for c in p]
    fr = [c - b for c, b in zip(p, base)]
    sm = [x if blend == "linear" else 3 * x * x - 2 * x ** 3 for x in fr]

    def lerp(a, b, t):
        return a + t * (b - a)

    def c(dx, dy, dz):
        return corner_value(base[0] + dx, base[1] + dy, base[2] + dz, perm)

    x00 = lerp(c(0, 0, 0), c(1, 0, 0), sm[0])
    x10 = lerp(c(0, 1, 0), c(1, 1, 0), sm[0])
    x01 = lerp(c(0, 0, 1), c(1, 0, 1), sm[0])
    x11 = lerp(c(0, 1, 1), c(1, 1, 1), sm[0])
    return lerp(lerp(x00, x10, sm[1]), lerp(x01, x11, sm[1]), sm[2])


def test_reference_uses_config_permutation():
    assert FULL.hash_bits == 8 and len(FULL.perm) == 256
    assert len(PERMS["reduced"]) == 2 ** load_config("reduced").hash_bits


@pytest.mark.parametrize("cfg", ("full", "reduced"))
@pytest.mark.parametrize("blend", BLENDS)
def test_noise_matches_scalar_definition(cfg, blend):
    perm = PERMS[cfg]
    rng = np.random.default_rng(4)
    p = np.concatenate([rng.uniform(-40, 40, (150, 3)), rng.uniform(-1e6, 1e6, (50, 3))])
    got = noise(p.reshape(10, 20, 3), perm, blend).reshape(-1)
    want = np.array([noise_scalar(q, perm, blend) for q in p])
    # same arithmetic up to association order: differences of a few ulps of values <= 1
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-14)


@pytest.mark.parametrize("cfg", ("full", "reduced"))
@pytest.mark.parametrize("blend", BLENDS)
def test_noise_at_lattice_points_is_corner_value(cfg, blend):
    perm = PERMS[cfg]
    P = len(perm)
    rng = np.random.default_rng(5)
    k = np.concatenate([rng.integers(-3 * P, 3 * P, (300, 3)), rng.integers(-10**6, 10**6, (50, 3))])
    want = np.array([corner_value(*map(int, q), perm) for q in k])
    np.testing.assert_array_equal(noise(k.astype(float), perm, blend), want)


@pytest.mark.parametrize("blend", BLENDS)
def test_noise_negative_cells(blend):
    perm = FULL.perm
    sm = 0.75 if blend == "linear" else 3 * 0.75**2 - 2 * 0.75**3
    # p = -0.25 lies in cell -1 at fraction 0.75 (not cell 0 at 0.25, as truncation would give)
    for y, z in [(0, 0), (-3, 5), (-1, -1)]:
        want = (1 - sm) * corner_value(-1, y, z, perm) + sm * corner_value(0, y, z, perm)
        assert noise([-0.25, y, z], perm, blend) == pytest.approx(want, abs=1e-15)
        want = (1 - sm) * corner_value(y, -1, z, perm) + sm * corner_value(y, 0, z, perm)
        assert noise([y, -0.25, z], perm, blend) == pytest.approx(want, abs=1e-15)
        want = (1 - sm) * corner_value(y, z, -1, perm) + sm * corner_value(y, z, 0, perm)
        assert noise([y, z, -0.25], perm, blend) == pytest.approx(want, abs=1e-15)


@pytest.mark.parametrize("cfg", ("full", "reduced"))
@pytest.mark.parametrize("blend", BLENDS)
def test_noise_periodicity(cfg, blend):
    perm = PERMS[cfg]
    P = len(perm)
    rng = np.random.default_rng(6)
    # multiples of 2^-20 with |p| < 2^22: adding P*k (|P k| < 2^21) is exact, so equality is exact
    p = np.round(rng.uniform(-2e3, 2e3, (400, 3)) * 2**20) / 2**20
    shifts = rng.integers(-4000, 4000, (400, 3)) * P
    base = noise(p, perm, blend)
    np.testing.assert_array_equal(noise(p + shifts, perm, blend), base)
    np.testing.assert_array_equal(noise_gradient(p + shifts, perm, blend), noise_gradient(p, perm, blend))
    # far from the origin (~1e6), general fractions: p + P*k rounds to ulp(1e6) ~ 1.2e-10,
    # and |dn/dp| <= 3 per axis, so the values agree to ~1e-9
    q = rng.uniform(0, 1, (200, 3)) * 7
    far = q + P * np.round(1e6 / P)
    np.testing.assert_allclose(noise(far, perm, blend), noise(q, perm, blend), rtol=0, atol=1e-8)


@pytest.mark.parametrize("blend", BLENDS)
def test_noise_continuous_across_cell_faces(blend):
    perm = FULL.perm
    rng = np.random.default_rng(7)
    for axis in range(3):
        p = rng.uniform(-600, 600, (300, 3))
        k = rng.integers(-600, 600, 300).astype(float)
        for eps in (1e-4, 1e-7, 1e-10):
            lo, hi = p.copy(), p.copy()
            lo[:, axis] = k - eps
            hi[:, axis] = k + eps
            # |dn/dp| <= 2 (corner spread) * 1.5 (max blend slope) = 3 per axis: jump <= 6 eps,
            # plus rounding of k +- eps (ulp(600) ~ 1e-13) times that slope
            d = np.abs(noise(hi, perm, blend) - noise(lo, perm, blend))
            assert np.all(d <= 6 * eps + 1e-12), (axis, eps, d.max())


def _interior_points(rng, n, margin=0.05, span=300):
    cells = rng.integers(-span, span, (n, 3))
    return cells + rng.uniform(margin, 1 - margin, (n, 3))


@pytest.mark.parametrize("cfg", ("full", "reduced"))
@pytest.mark.parametrize("blend", BLENDS)
def test_noise_gradient_matches_finite_differences(cfg, blend):
    perm = PERMS[cfg]
    rng = np.random.default_rng(8)
    p = _interior_points(rng, 400)
    g = noise_gradient(p, perm, blend)
    h = 1e-5
    fd = np.empty_like(p)
    for a in range(3):
        e = np.zeros(3)
        e[a] = h
        fd[:, a] = (noise(p + e, perm, blend) - noise(p - e, perm, blend)) / (2 * h)
    # inside a cell n is a polynomial of degree <= 3 per axis: central-difference error
    # h^2/6 |n'''| <= 1e-10/6 * 24, plus rounding 1e-16 * 300 / h ~ 3e-9
    np.testing.assert_allclose(g, fd, rtol=0, atol=1e-8)
    assert np.abs(g).max() > 0.5  # not trivially zero


def test_cubic_noise_gradient_continuous_across_faces_linear_not():
    perm = FULL.perm
    rng = np.random.default_rng(9)
    eps = 1e-8
    jumps = {}
    for blend in BLENDS:
        worst = 0.0
        for axis in range(3):
            p = rng.uniform(-300, 300, (300, 3))
            k = rng.integers(-300, 300, 300).astype(float)
            lo, hi = p.copy(), p.copy()
            lo[:, axis] = k - eps
            hi[:, axis] = k + eps
            worst = max(worst, np.abs(noise_gradient(hi, perm, blend) - noise_gradient(lo, perm, blend)).max())
        jumps[blend] = worst
    # cubic: second derivatives are bounded by 2 * 6 = 12 (value spread times max |s''|)
    # and by 2 * 1.5^2 across axes, so the gradient moves <= ~30 * 2 eps across the face
    assert jumps["cubic"] <= 60 * eps + 1e-12
    # linear: the gradient jumps (this shows the check above can see a discontinuity)
    assert jumps["linear"] > 0.1


# ---------------------------------------------------------------------------
# quadric


def random_qcoef(rng):
    return rng.uniform(-3, 3, 10)


def test_quadric_matches_eq3():
    rng = np.random.default_rng(10)
    for _ in range(20):
        c = random_qcoef(rng)
        A, B, C, D, E, F, G, H, I, J = c
        s = rng.uniform(-5, 5, (50, 3))
        x, y, z = s.T
        want = (A * x * x + 2 * B * x * y + 2 * C * x * z + 2 * D * x + E * y * y + 2 * F * y * z
                + 2 * G * y + H * z * z + 2 * I * z + J)
        # same polynomial, different summation order: rounding ~1e-16 * 500
        np.testing.assert_allclose(quadric(c, s), want, rtol=0, atol=1e-11)
    Q = quadric_matrix(c)
    assert np.array_equal(Q, Q.T)


def test_quadric_gradient_and_screen_gradient_match_finite_differences():
    rng = np.random.default_rng(11)
    c = random_qcoef(rng)
    s0 = rng.uniform(-5, 5, (200, 3))
    J = rng.uniform(-1, 1, (200, 3, 2)) * 10.0 ** rng.uniform(-3, 2, (200, 1, 1))
    # q is quadratic, so a central difference is exact for any step: use step 1
    # (error is only rounding, ~1e-16 times |q| <~ 1e6)
    g = quadric_gradient(c, s0)
    for a in range(3):
        e = np.zeros(3)
        e[a] = 1.0
        np.testing.assert_allclose(g[:, a], (quadric(c, s0 + e) - quadric(c, s0 - e)) / 2, rtol=0, atol=1e-8)
    sg = quadric_screen_gradient(c, s0, J)
    for a in range(2):
        sp, sm = s0 + J[:, :, a], s0 - J[:, :, a]
        np.testing.assert_allclose(sg[:, a], (quadric(c, sp) - quadric(c, sm)) / 2, rtol=0, atol=1e-8)


def test_linear_quadric_terms_have_a_gradient():
    # f = r (marble's ramp): I = 1/2. The paper's eq. (11) with [s t r 0] would give 0
    c = np.zeros(10)
    c[8] = 0.5
    J = np.array([[0.0, 0.0], [0.0, 0.0], [0.25, -2.0]])
    np.testing.assert_allclose(quadric_screen_gradient(c, [1.0, 2.0, 3.0], J), [0.25, -2.0], rtol=0, atol=0)


# ---------------------------------------------------------------------------
# texture


def random_texture(rng, blend, mode="mod", filt=True, k=3, nent=16):
    terms = [NoiseTerm(a=rng.uniform(-1, 1), T=rng.uniform(-4, 4, (3, 3)), o=rng.uniform(-10, 10, 3))
             for _ in range(k)]
    return TextureParams(Q=random_qcoef(rng) * 0.3, terms=terms, blend=blend, mode=mode,
                         clut=random_clut(nent, int(rng.integers(1 << 30))), filter=filt, noise_gradient=True)


@pytest.mark.parametrize("blend", BLENDS)
def test_texture_f_is_quadric_plus_noise_terms(blend):
    rng = np.random.default_rng(12)
    tex = random_texture(rng, blend)
    perm = FULL.perm
    s = rng.uniform(-6, 6, (40, 3))
    want = quadric(tex.Q, s) + np.array(
        [sum(t.a * noise_scalar(t.T @ si + t.o, perm, blend) for t in tex.terms) for si in s])
    np.testing.assert_allclose(texture_f(tex, s, perm, FULL.hash_bits), want, rtol=0, atol=1e-12)
    # terms given as (a, T, o) tuples are the same texture
    tup = TextureParams(Q=tex.Q, terms=[(t.a, t.T, t.o) for t in tex.terms], blend=blend, clut=tex.clut)
    np.testing.assert_array_equal(texture_f(tup, s, perm, FULL.hash_bits), texture_f(tex, s, perm, FULL.hash_bits))


@pytest.mark.parametrize("blend", BLENDS)
def test_texture_grad_f_matches_finite_differences(blend):
    rng = np.random.default_rng(13)
    tex = random_texture(rng, blend)
    perm = FULL.perm
    n = 600
    s0 = rng.uniform(-6, 6, (n, 3))
    J = rng.uniform(-1, 1, (n, 3, 2)) * 10.0 ** rng.uniform(-3, 0, (n, 1, 1))
    h = 1e-4
    f = lambda s: texture_f(tex, s, perm, FULL.hash_bits)
    pts = [s0 + sg * h * J[:, :, a] for a in range(2) for sg in (1, -1)]
    # keep pixels whose finite-difference stencil stays inside one noise cell for every term
    ok = np.ones(n, bool)
    for t in tex.terms:
        cells = [np.floor(p @ t.T.T + t.o) for p in [s0] + pts]
        ok &= np.all([np.all(c == cells[0], axis=-1) for c in cells], axis=0)
    assert ok.sum() > n // 2
    fd = np.stack([(f(pts[0]) - f(pts[1])) / (2 * h), (f(pts[2]) - f(pts[3])) / (2 * h)], axis=-1)
    g = texture_grad_f(tex, s0, J, perm, FULL.hash_bits)
    # per cell f(s0 + J x) is a polynomial; central-difference error h^2/6 |f'''| with
    # |f'''| <~ 24 * |a| |T J|^3 + 0 (quadric) <~ 24 * 12^3: ~7e-5 worst case, rounding 1e-16*100/h ~ 1e-10
    np.testing.assert_allclose(g[ok], fd[ok], rtol=1e-6, atol=1e-4)
    assert np.abs(g[ok]).max() > 1.0


def test_texture_grad_without_noise_gradient_is_quadric_gradient():
    rng = np.random.default_rng(14)
    tex = random_texture(rng, "cubic")
    tex.noise_gradient = False
    s = rng.uniform(-3, 3, (30, 3))
    J = rng.uniform(-1, 1, (30, 3, 2))
    np.testing.assert_array_equal(texture_grad_f(tex, s, J, FULL.perm, FULL.hash_bits),
                                  quadric_screen_gradient(tex.Q, s, J))


@pytest.mark.parametrize("mode", MODES)
def test_shade_composes_f_width_and_lookup(mode):
    rng = np.random.default_rng(15)
    perm = FULL.perm
    s = rng.uniform(-3, 3, (4, 6, 3))
    J = rng.uniform(-0.3, 0.3, (4, 6, 3, 2))
    for filt in (True, False):
        tex = random_texture(rng, "cubic", mode=mode, filt=filt)
        f = texture_f(tex, s, perm, FULL.hash_bits)
        w = filter_width(tex, s, J, perm, FULL.hash_bits)
        g = texture_grad_f(tex, s, J, perm, FULL.hash_bits)
        np.testing.assert_allclose(w, np.sqrt((g ** 2).sum(-1)), rtol=1e-15)
        want = filtered_lookup(tex.clut, f, w, mode) if filt else unfiltered_lookup(tex.clut, f, mode)
        got = shade(tex, s, J, perm, FULL.hash_bits)
        assert got.shape == (4, 6, 4)
        np.testing.assert_array_equal(got, want)
    with pytest.raises(ValueError):
        texture_f(tex, s, perm, 6)  # a 256-entry permutation is not hash_bits = 6


def test_zone_plate_filter_width():
    # Fig. 8: f = 50 s^2 + 50 t^2 on the unit square, ds/dx = dt/dy = 1/256: |grad f| = 100 |(s, t)| / 256
    c = np.zeros(10)
    c[0] = c[4] = 50.0
    tex = TextureParams(Q=c, terms=[], blend="cubic", mode="mod", clut=random_clut(16, 1))
    s = np.stack(np.meshgrid(np.arange(256) / 256, np.arange(256) / 256, indexing="xy") + (np.zeros((256, 256)),), -1)
    J = np.zeros((256, 256, 3, 2))
    J[..., 0, 0] = J[..., 1, 1] = 1 / 256
    w = filter_width(tex, s, J, FULL.perm, FULL.hash_bits)
    np.testing.assert_allclose(w, 100 * np.hypot(s[..., 0], s[..., 1]) / 256, rtol=1e-14)
    out = shade(tex, s, J, FULL.perm, FULL.hash_bits)
    assert out.shape == (256, 256, 4) and out.min() >= 0 and out.max() <= 255
