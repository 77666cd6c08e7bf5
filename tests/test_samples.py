"""Sub-pixel samples (features.samples, issue 27; docs/filters.md "Sub-pixel samples"): the golden
twins sample_expand and sample_average against exact rational arithmetic at every edge of their
formats, the halved y column's rounding at its worst case, the configuration key's checks, and
the whole pipeline with samples against the float reference that samples the same way."""
from __future__ import annotations

import math
from fractions import Fraction
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from model import reference as R
from model.hw import golden as G
from model.hw.config import (SAMPLE_FOOTPRINT, SAMPLE_OFFSETS, ConfigError, clocks_per_pixel, clocks_per_sample, load_config,
                             variant)
from model.hw.quantize import quantize_pixels, quantize_texture
from model.texture import NoiseTerm, TextureParams

# the pixel-input formats of the named configurations and a small one where everything saturates
FORMATS = {"full": None, "compact": None, "reduced": None, "small": dict(s_w=8, s_frac=4, j_w=4, je_w=3)}


def _fmt(name: str, n: int) -> SimpleNamespace:
    f = FORMATS[name]
    if f is None:
        c = load_config(name)
        f = dict(s_w=c.s_w, s_frac=c.s_frac, j_w=c.j_w, je_w=c.je_w)
    return SimpleNamespace(samples=n, **f)


def _exact_expand(cfg, s, Jm, je, k):
    """sample_expand by the definition, in rationals: s + floor(m 2^(je - 2 + s_frac) + 1/2), saturated."""
    dx, dy = SAMPLE_OFFSETS[cfg.samples][k]
    lo, hi = -(1 << (cfg.s_w - 1)), (1 << (cfg.s_w - 1)) - 1
    e = je - 2 + cfg.s_frac
    out = []
    for r in range(3):
        m = dx * Jm[r][0] + dy * Jm[r][1]
        off = math.floor(Fraction(m) * Fraction(2) ** e + Fraction(1, 2))
        out.append(min(hi, max(lo, s[r] + off)))
    if cfg.samples == 4:
        jm_k, je_k = [list(row) for row in Jm], (je - 1 if je > -(1 << (cfg.je_w - 1)) else je)
    else:
        jm_k, je_k = [[row[0], math.floor(Fraction(row[1], 2) + Fraction(1, 2))] for row in Jm], je
    return out, jm_k, je_k


@st.composite
def _expand_case(draw):
    name = draw(st.sampled_from(sorted(FORMATS)))
    n = draw(st.sampled_from((2, 4)))
    cfg = _fmt(name, n)
    slo, shi = -(1 << (cfg.s_w - 1)), (1 << (cfg.s_w - 1)) - 1
    jlo, jhi = -(1 << (cfg.j_w - 1)), (1 << (cfg.j_w - 1)) - 1
    elo, ehi = -(1 << (cfg.je_w - 1)), (1 << (cfg.je_w - 1)) - 1
    sv = st.one_of(st.integers(slo, shi), st.sampled_from((slo, shi, slo + 1, shi - 1, 0)))
    jv = st.one_of(st.integers(jlo, jhi), st.sampled_from((jlo, jhi, 0, 1, -1)))
    # je around where the offset's exponent crosses 0 and its ends (the shifts' caps)
    ev = st.one_of(st.integers(elo, ehi), st.sampled_from((elo, ehi, 2 - cfg.s_frac, 1 - cfg.s_frac, 3 - cfg.s_frac,
                                                           -cfg.s_frac - cfg.j_w - 2, -cfg.s_frac - cfg.j_w - 1)))
    s = [draw(sv) for _ in range(3)]
    Jm = [[draw(jv) for _ in range(2)] for _ in range(3)]
    je = max(elo, min(ehi, draw(ev)))
    return cfg, s, Jm, je, draw(st.integers(0, n - 1))


@settings(max_examples=1500, deadline=None)
@given(_expand_case())
def test_sample_expand_is_the_exact_rounded_offset(case):
    """Every sample's s_k, Jm_k, je_k equal the definition evaluated in rationals (hypothesis,
    seeded by SEED): s at its ends (saturation), J's mantissas at theirs, je at its least value
    (4 samples: the footprint stays) and where the offset's shift turns from right to left."""
    cfg, s, Jm, je, k = case
    sk, jk, ek = G.sample_expand(cfg, np.array(s), np.array(Jm), np.array(je), k)
    es, ejm, eje = _exact_expand(cfg, s, Jm, je, k)
    assert sk.tolist() == es and jk.tolist() == ejm and int(ek) == eje


def test_sample_offsets_are_stratified():
    """The offsets of each sample count are the centres of equal cells that tile the pixel, and the
    footprint is that cell: their mean is 0, the cells (the footprint's scales of the pixel's x and
    y sides, centred on the offsets) cover the pixel [-1/2, 1/2]^2 once, point by point on a grid;
    4 samples are the 2x2 grid, 2 the vertical pair (the pixel's halves across y)."""
    g = (np.arange(64) + 0.5) / 64 - 0.5
    X, Y = np.meshgrid(g, g)
    for n, offs in SAMPLE_OFFSETS.items():
        a = np.array(offs, dtype=float)
        assert len(offs) == n and np.allclose(a.mean(axis=0), 0.0)
        fx, fy = SAMPLE_FOOTPRINT[n]
        cover = sum(((np.abs(X - dx / 4) < fx / 2) & (np.abs(Y - dy / 4) < fy / 2)).astype(int) for dx, dy in offs)
        assert (cover == 1).all(), n
    assert sorted(SAMPLE_OFFSETS[4]) == [(-1, -1), (-1, 1), (1, -1), (1, 1)]
    assert SAMPLE_OFFSETS[2] == ((0, -1), (0, 1)) and SAMPLE_FOOTPRINT[2] == (1.0, 0.5)


def test_two_samples_footprint_bound_at_its_worst_case():
    """Two samples' footprint halves J's y column as floor((Jm + 1) / 2): within 1/2 of Jm / 2 (docs/numerics.md
    "Sub-pixel samples"), exact at even Jm and 1/2 off at every odd one (the worst case), for every Jm of the
    widest Jacobian format (j_w 24, so every narrower one); the x column and the exponent unchanged."""
    jm = np.arange(-(1 << 23), 1 << 23, dtype=np.int64)
    Jm = np.stack([np.zeros_like(jm), jm], axis=-1)[:, None, :].repeat(3, axis=1)
    cfg = SimpleNamespace(samples=2, s_w=32, s_frac=0, j_w=24, je_w=8)
    _, got, je = G.sample_expand(cfg, np.zeros((len(jm), 3), np.int64), Jm, np.zeros(len(jm), np.int64), 0)
    err = np.abs(got[:, 0, 1] - jm / 2)
    assert (err <= 0.5).all() and (err[jm % 2 == 1] == 0.5).all() and (err[jm % 2 == 0] == 0).all()
    assert (got[..., 0] == 0).all() and (je == 0).all()


def test_sample_average_rounds_half_up():
    """The average of every pair of channel values (2 samples) and of sums at the ends and the exact
    halves (4 samples) is floor(sum / n + 1/2)."""
    a, b = np.meshgrid(np.arange(256), np.arange(256))
    got = G.sample_average(SimpleNamespace(samples=2), np.stack([a, b])[..., None].repeat(4, -1))
    assert (got[..., 0] == np.floor((a + b) / 2 + 0.5)).all()
    v = np.array([[0, 0, 0, 2], [255, 255, 255, 254], [0, 1, 1, 0], [3, 3, 2, 255]])
    got = G.sample_average(SimpleNamespace(samples=4), v[..., None].repeat(4, -1).transpose(1, 0, 2))
    assert got[:, 0].tolist() == [math.floor(sum(r) / 4 + 0.5) for r in v]


def test_samples_key_checked_and_counted_in_clocks():
    """features.samples takes 1, 2 or 4 (3: a one-line error naming the key); a pixel takes samples x
    the clocks of one sample (compact: 5 a sample)."""
    with pytest.raises(ConfigError, match="features.samples = 3"):
        variant(load_config("full"), "bad", samples=3)
    c = variant(load_config("compact"), "c4", samples=4)
    assert clocks_per_sample(c) == clocks_per_sample(load_config("compact")) == 5 and clocks_per_pixel(c) == 20


@pytest.mark.parametrize("name,n", [("full", 2), ("full", 4), ("reduced", 4)])
def test_pipeline_with_samples_close_to_sampling_reference(name, n):
    """The golden model with samples against the float reference that samples the same way (the
    configured texture: configured_texture sets its samples): on a gentle texture, the median pixel
    within 1 LSB, every pixel off the mod wrap within the bound of test_golden's one-sample test
    (full 6, reduced 10 LSB: averaging samples does not add to the largest error)."""
    from model.scene.passes import configured_texture

    cfg = variant(load_config(name), f"{name}_s{n}", samples=n)
    rng = np.random.default_rng(12)
    ramp = np.linspace(0, 255, 64).astype(np.uint8)
    clut = np.stack([ramp, ramp[::-1], ramp, np.full(64, 255, np.uint8)], -1)
    terms = [NoiseTerm(0.5 ** i, np.eye(3) * 2 ** i, [0.25 * i, 0, 0]) for i in range(1, 3)]
    tex = TextureParams(Q=[0, 0, 0, 0, 0, 0, 0, 0, 0.5, 0], terms=terms, clut=clut, mode="mod", blend=cfg.blend)
    s = rng.uniform(-3, 3, (4000, 3))
    J = rng.normal(0, 0.002, (4000, 3, 2))
    ti, _ = quantize_texture(cfg, tex)
    si, Jm, je = quantize_pixels(cfg, s, J)
    got = G.texture_pipeline(cfg, ti, si, Jm, je).astype(float)
    ctex = configured_texture(cfg, tex)
    assert ctex.samples == n
    sq, Jq = si / (1 << cfg.s_frac), Jm * np.exp2(je)[:, None, None]
    ref = R.shade(ctex, sq, Jq, cfg.perm, cfg.hash_bits)
    err = np.abs(got - ref).max(axis=-1)
    assert np.median(err) <= 1.0
    # off the wrap (as test_golden: a sample whose window reaches within one entry of the ramp's
    # 255 -> 0 step may land on its other side), for any of the pixel's samples
    f = R.texture_f(ctex, sq, cfg.perm, cfg.hash_bits)
    w = G.texture_stages(cfg, ti, si, Jm, je)["w"] / (1 << cfg.f_frac)
    wrap = np.abs(f - np.rint(f)) * len(clut) <= w + 2.0
    worst = float(err[~wrap].max())
    assert worst <= {"full": 6.0, "reduced": 10.0}[name], f"{cfg.name}: {worst:.2f} LSB off the wrap"
    # and the samples are not the centre: the sampled reference differs from the one-sample one
    one = R.shade(configured_texture(load_config(name), tex), sq, Jq, cfg.perm, cfg.hash_bits)
    assert np.abs(ref - one).max() > 1.0
