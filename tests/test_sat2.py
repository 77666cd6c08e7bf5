"""The trapezoid filter (filter "sat2", issue 27): the float reference against brute-force
supersampling, the golden model against the float reference at the error bound of its division
(docs/numerics.md "The trapezoid"), each degenerate case at its worst, the running-sum table the
unit derives, and the configuration's width check."""
from __future__ import annotations

import numpy as np
import pytest

from model import reference as R
from model.hw import golden as G
from model.hw.config import ROOT, ConfigError, load_config, variant

FULL = load_config(ROOT / "config" / "candidates" / "full_narrow.toml")  # full until issue 26: the widths sat2 was built on


def _cfg(div_bits=0, **kw):
    return variant(FULL, "t_sat2", filter="sat2", div_bits=div_bits, **kw)


def _tex(clut, mode, n_log2):
    return G.TexInt(Q=np.zeros(10, dtype=np.int64), a=np.zeros(0, dtype=np.int64), T=np.zeros((0, 3, 3), dtype=np.int64),
                    o=np.zeros((0, 3), dtype=np.int64), mode=mode, n_log2=n_log2, filter=True,
                    clut=np.asarray(clut, dtype=np.int64))


def _golden(cfg, clut, mode, n_log2, f, a, b):
    return G.colour_map(cfg, _tex(clut, mode, n_log2), f, np.stack([a, b], axis=-1)).astype(np.float64)


def _ref(cfg, clut, mode, n_log2, f, a, b):
    """The float trapezoid on the golden model's own (quantized) f, a, b."""
    one, n = float(1 << cfg.f_frac), 1 << n_log2
    return R.trapezoid_lookup(np.asarray(clut, dtype=np.uint8), f / one, a / one / n, b / one / n,
                              "clamp" if mode == G.MODE_CLAMP else "mod")


def _div_bound(cfg) -> float:
    """cmap_divide's error bound in LSB: 1/2 exact, 1/2 + 513 / 2^(B+1) normalised."""
    return 0.5 if cfg.div_bits == 0 else 0.5 + 513 / 2 ** (cfg.div_bits + 1)


def _worst_inputs(cfg, n_log2, r, n):
    """f anywhere (several tables either side), a, b log-uniform from one LSB to the cap, with
    the cap itself, 0 and one LSB mixed in; the worst tables are chosen by the caller."""
    ff, cap = cfg.f_frac, cfg.w_cap
    f = r.integers(-3 << (ff + 0), 4 << ff, size=n)
    e = r.uniform(0, np.log2(cap), size=(n, 2))
    ab = np.minimum((2.0 ** e).astype(np.int64), cap)
    pick = r.random((n, 2))
    ab = np.where(pick < 0.05, cap, np.where(pick < 0.08, 1, np.where(pick < 0.1, 0, ab)))
    return f, ab[:, 0], ab[:, 1]


def test_reference_against_supersampling():
    """trapezoid_lookup is the pixel average of C(f + gx x + gy y) over the unit square: against
    a 512 x 512 midpoint sum (error of that sum below 255 * 2 / 512 per axis crossing)."""
    r = np.random.default_rng(5)
    for mode in ("mod", "clamp"):
        clut = r.integers(0, 256, (8, 4)).astype(np.uint8)
        f = r.uniform(-0.5, 1.5, 32)
        g = 10.0 ** r.uniform(-2, 0.7, (32, 2)) / 8 * np.sign(r.uniform(-1, 1, (32, 2)))
        ref = R.trapezoid_lookup(clut, f, g[:, 0], g[:, 1], mode)
        m = 512
        xs = (np.arange(m) + 0.5) / m - 0.5
        bf = np.zeros_like(ref)
        for x in xs:
            bf += R.unfiltered_lookup(clut, f[:, None] + g[:, 0:1] * x + g[:, 1:2] * xs[None, :], mode).mean(axis=1)
        bf /= m
        assert np.abs(ref - bf).max() < 0.3, mode


def test_reference_degenerate_limits():
    """a or b 0: the box (filtered_lookup) of the other; both 0: the point lookup; a window
    inside one entry: that entry, exactly."""
    r = np.random.default_rng(6)
    clut = r.integers(0, 256, (16, 4)).astype(np.uint8)
    f = r.uniform(-1, 2, 200)
    w = r.uniform(0, 0.5, 200)
    for mode in ("mod", "clamp"):
        box = R.filtered_lookup(clut, f, w, mode)
        assert np.allclose(R.trapezoid_lookup(clut, f, w, 0 * w, mode), box, atol=1e-9)
        assert np.allclose(R.trapezoid_lookup(clut, f, 0 * w, -w, mode), box, atol=1e-9)
        assert np.array_equal(R.trapezoid_lookup(clut, f, 0 * w, 0 * w, mode), R.unfiltered_lookup(clut, f, mode))
        # a tiny second box changes the box by less than 255 * ratio
        assert np.allclose(R.trapezoid_lookup(clut, f, w, 1e-6 * w, mode), box, atol=1e-3)


@pytest.mark.parametrize("div_bits", (0, 8))
@pytest.mark.parametrize("mode", (G.MODE_MOD, G.MODE_CLAMP))
def test_golden_against_reference_at_the_division_bound(div_bits, mode):
    """The golden model's D is exact (integers mod 2^d2_w); its only error against the float
    trapezoid on the same inputs is cmap_divide's: at most 1/2 LSB exact, 1/2 + 513 / 2^(B+1)
    normalised. Worst tables: a zebra (every entry boundary a full step), all 255 (the largest
    D), random; N = 1, 2 and 256; widths up to the cap (many whole tables, far past both ends)."""
    cfg = _cfg(div_bits)
    r = np.random.default_rng(7 + div_bits + 3 * mode)
    worst = 0.0
    for n_log2 in (0, 1, 8):
        n = 1 << n_log2
        zebra = np.where((np.arange(n) & 1)[:, None] == 1, 255, 0) * np.ones((1, 4), dtype=np.int64)
        for clut in (zebra, np.full((n, 4), 255), r.integers(0, 256, (n, 4))):
            f, a, b = _worst_inputs(cfg, n_log2, r, 3000)
            err = np.abs(_golden(cfg, clut, mode, n_log2, f, a, b) - _ref(cfg, clut, mode, n_log2, f, a, b))
            worst = max(worst, float(err.max()))
    # (+ the reference's own limit: min(A, B) < TRAP_BOX max(A, B) taken as the box, within
    # 255 TRAP_BOX / 2)
    assert worst <= _div_bound(cfg) + 255 * R.TRAP_BOX / 2, worst
    assert worst > 0.4  # the bound is reached, not vacuous


@pytest.mark.parametrize("mode", (G.MODE_MOD, G.MODE_CLAMP))
def test_golden_degenerate_cases_bit_exact(mode):
    """a = 0 or b = 0: the box of width a + b, the same D and divisor as cmap_sat (bit-exact with
    filter "sat"); a = b = 0: the point lookup (filter "none")."""
    cfg = _cfg(8)
    box_cfg, point_cfg = variant(FULL, "t_sat", filter="sat", div_bits=8), variant(FULL, "t_none", filter="none")
    r = np.random.default_rng(8)
    for n_log2 in (0, 3, 8):
        clut = r.integers(0, 256, (1 << n_log2, 4))
        f, a, _ = _worst_inputs(cfg, n_log2, r, 2000)
        z = np.zeros_like(a)
        tex = _tex(clut, mode, n_log2)
        box = G.colour_map(box_cfg, tex, f, a)
        assert np.array_equal(G.colour_map(cfg, tex, f, np.stack([a, z], -1)), box)
        assert np.array_equal(G.colour_map(cfg, tex, f, np.stack([z, a], -1)), box)
        assert np.array_equal(G.colour_map(cfg, tex, f, np.stack([z, z], -1)), G.colour_map(point_cfg, tex, f, z))


def test_golden_cap_and_guard():
    """a = b = the cap (2^w_cap_log2 entries each: the window spans 2W), clamp mode with u at
    the guard (N + W) and beyond: the average of the edge entries, within the division bound."""
    cfg = _cfg(0)
    r = np.random.default_rng(9)
    clut = r.integers(0, 256, (256, 4))
    ff, cap = cfg.f_frac, cfg.w_cap
    f = np.array([0, 1 << ff, (1 << ff) + (cap >> 8), (1 << ff) + (cap >> 7), -(cap >> 8), 5 << ff, -(5 << ff),
                  1 << (cfg.f_w - 2)], dtype=np.int64)
    a = np.full(f.shape, cap)
    for mode in (G.MODE_MOD, G.MODE_CLAMP):
        for b in (a, a // 2, np.ones_like(a)):
            err = np.abs(_golden(cfg, clut, mode, 8, f, a, b) - _ref(cfg, clut, mode, 8, f, a, b))
            assert err.max() <= 0.5 + 255 * R.TRAP_BOX / 2, (mode, err.max())


def test_sat2_table_derives_the_running_sum():
    """sat2_table_write: a csat load in ascending order leaves csat2 = the running sum of csat,
    total = csat[N - 1], total2 = H[N - 1] (host_tables), whatever the storage held before; clut
    takes 8 bits a lane; writes past 2^nmax and to tables 2, 3 are ignored."""
    cfg = _cfg()
    r = np.random.default_rng(10)
    nmax = cfg.n_log2_max
    for n_log2 in (0, 1, 5, nmax):
        clut = r.integers(0, 256, (1 << n_log2, 4))
        tex = _tex(clut, G.MODE_MOD, n_log2)
        t = G.sat2_tables(nmax, fill=12345)
        t["acc"][:] = 999
        for i, e in enumerate(clut):
            G.sat2_table_write(t, nmax, cfg.csat_w, cfg.csat2_w, 0, i, e | 0xF00)
        for i, e in enumerate(tex.csat):
            G.sat2_table_write(t, nmax, cfg.csat_w, cfg.csat2_w, 1, i, e)
        for tbl, addr in ((1, (1 << nmax) + 3), (2, 0), (3, 1)):
            G.sat2_table_write(t, nmax, cfg.csat_w, cfg.csat2_w, tbl, addr, np.full(4, 77))
        h = G.host_tables(tex)
        n = 1 << n_log2
        assert np.array_equal(t["clut"][:n], clut)
        assert np.array_equal(t["csat2"][:n], h["csat2"]) and np.array_equal(t["total2"], h["total2"])
        assert np.array_equal(t["total"], h["total"])
        assert int(h["total2"].max()) < 1 << cfg.csat2_w


def test_sat2_config_widths():
    """d2_w = 2 (w_cap_log2 + f_frac) + 11 bits hold Gamma <= 2040 ab; a configuration whose
    second difference would not fit the golden model's int64 words is refused."""
    cfg = _cfg()
    assert cfg.d2_w == 2 * (cfg.w_cap_log2 + cfg.f_frac) + 11
    assert 2040 * cfg.w_cap ** 2 < 1 << cfg.d2_w and 4 * cfg.w_cap ** 2 < 1 << cfg.w2_w
    with pytest.raises(ConfigError, match="sat2"):
        _cfg(w_cap_log2=16, f_frac=16)


def test_filter_width_components():
    """filter_width's components (a, b) are |g_x| and |g_y| normalised and scaled as w: with one
    screen column of J zero the other component is w itself (isqrt(ax^2) = ax) and this one 0;
    each saturates at the cap alone."""
    cfg = _cfg()
    r = np.random.default_rng(11)
    n = 4000
    c = r.integers(-(1 << 12), 1 << 12, size=(n, 3))
    Jm = r.integers(-(1 << (cfg.j_w - 1)), 1 << (cfg.j_w - 1), size=(n, 3, 2))
    je = r.integers(cfg.je_min, cfg.je_max + 1, size=n)
    for col in (0, 1):
        J1 = Jm.copy()
        J1[..., 1 - col] = 0
        w = G.filter_width(cfg, c, J1, je, 8)
        ab = G.filter_width(cfg, c, J1, je, 8, components=True)
        assert np.array_equal(ab[:, col], w) and not ab[:, 1 - col].any()
    ab = G.filter_width(cfg, c, Jm, je, 8, components=True)
    w = G.filter_width(cfg, c, Jm, je, 8)
    assert (ab <= cfg.w_cap).all() and (ab.max(axis=1) <= w).all() and (ab == cfg.w_cap).any()


def test_random_config_draws_sat2():
    """random_config draws filter "sat2" (a quarter of the box draws whose words fit it, from a
    generator of its own): each such draw is a valid configuration whose colour_map is the trapezoid
    (FILTER 3) and whose filter_width gives the two components; the same draw with "sat" is valid too
    (only the filter was replaced). The design family's random:1202 is one, so tb/colour_map and
    tb/filter_width run a random sat2 configuration through the RTL."""
    import hdlbuild
    from model.hw.config import config_values, random_config

    cfgs = {s: random_config(s) for s in range(200)}
    sat2 = [s for s, c in cfgs.items() if c.filter == "sat2"]
    assert 10 <= len(sat2) <= 40, sat2  # 22 of 200 when written
    for s in sat2:
        c = cfgs[s]
        assert c.d2_w <= 61 and c.w_cap_log2 + c.f_frac <= 25
        assert hdlbuild.block_params(c, "colour_map")["FILTER"] == 3
        assert hdlbuild.block_params(c, "filter_width")["COMPONENTS"] == 1
        box = variant(c, f"box{s}", filter="sat")
        assert {k: v for k, v in config_values(box).items() if k != "filter"} == \
               {k: v for k, v in config_values(c).items() if k != "filter"}
    assert {c.filter for c in cfgs.values()} >= {"sat", "sat_fc", "sat2", "mip", "none"}
    assert hdlbuild.config_of("random:1202").filter == "sat2"
