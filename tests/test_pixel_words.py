"""Pixel words of the frame harness (model/hw/regmap.py): the binary uint32 form that the
Verilator C++ main loads (pack_pixels_u32) holds the same bits as pack_pixels's Python ints,
and unpack_pixels reads them back, in every named configuration and at the fields' extremes."""
from __future__ import annotations

import numpy as np
import pytest

from model.hw.config import CONFIG_NAMES, load_config
from model.hw.regmap import RegmapError, pack_pixels, pack_pixels_u32, pix_width, unpack_pixels


def _random_pixels(cfg, n, seed=1):
    r = np.random.default_rng(seed)

    def sint(w, size):
        x = r.integers(-(1 << (w - 1)), 1 << (w - 1), size=size, dtype=np.int64)
        x.reshape(-1)[:2] = [-(1 << (w - 1)), (1 << (w - 1)) - 1]  # both extremes
        return x

    return sint(cfg.s_w, (n, 3)), sint(cfg.j_w, (n, 3, 2)), sint(cfg.je_w, n)


@pytest.mark.parametrize("name", CONFIG_NAMES)
def test_pack_pixels_u32_equals_pack_pixels(name):
    cfg = load_config(name)
    s, Jm, je = _random_pixels(cfg, 500)
    u = pack_pixels_u32(cfg, s, Jm, je)
    assert u.dtype == np.uint32 and u.shape == (500, (pix_width(cfg) + 31) // 32)
    ints = [sum(int(x) << (32 * k) for k, x in enumerate(row)) for row in u]
    assert ints == pack_pixels(cfg, s, Jm, je)
    s2, Jm2, je2 = unpack_pixels(cfg, ints)
    assert np.array_equal(s2, s) and np.array_equal(Jm2, Jm) and np.array_equal(je2, je)


def test_pack_pixels_u32_range_checked():
    cfg = load_config("reduced")
    s, Jm, je = _random_pixels(cfg, 4)
    s[0, 0] = 1 << (cfg.s_w - 1)
    with pytest.raises(RegmapError, match="pixel s outside"):
        pack_pixels_u32(cfg, s, Jm, je)
