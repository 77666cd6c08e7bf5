"""The ground truth (model/scene/truth.py): stratified jitter against an exact pixel integral,
the n/2 estimate, reproducibility, the cache and its key, the front end's window."""
from __future__ import annotations

import numpy as np
import pytest

from model.hw.config import load_config
from model.scene import truth as T
from model.scene.frontend import render_passes
from model.scene.passes import scene_path
from model.scene.scene import load_scene

# a screen square, f = s (s = x / W across the frame), clamped two-entry table: black for
# s < 1/2, white above. Pixel x covers s in [x/W, (x+1)/W); with W odd the edge s = 1/2 falls
# in the middle of pixel (W-1)/2, whose exact mean is half white.
EDGE = """
[camera]
width = {w}
height = 4
position = [0.5, 0.5, 2.0]
look_at = [0.5, 0.5, 0.0]
up = [0.0, 1.0, 0.0]
fov_deg = 40.0

[texture.t]
quadric = [0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
entries = [[0, 0, 0, 255], [255, 255, 255, 255]]
mode = "clamp"
filter = false

[[object]]
type = "screen"
texture = "t"
texture_matrix = [[{k}, 0.0, 0.0, {o}], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]
"""


def _edge_scene(tmp_path, w=5, k=1.0, o=0.0, name="edge"):
    p = tmp_path / f"{name}.toml"
    p.write_text(EDGE.format(w=w, k=k, o=o))
    return p


@pytest.mark.parametrize("n", [2, 4, 8])
def test_stratified_jitter_against_exact_coverage(tmp_path, n):
    """An edge at a fraction c of the pixel: with n x n strata only the n strata in the edge's
    column are random, so |truth - 255 (1 - c)| <= 255 / n, and the mean over pixels
    is unbiased. The edge is moved across a pixel (o) to cover many fractions."""
    cfg = load_config("full")
    errs = []
    for i, c in enumerate(np.linspace(0.05, 0.95, 7)):
        # f = s + o with s = (x + 0.5 + jitter) / W: the edge f = 1/2 at x = W/2 - o W; the
        # frame is 5 px wide, pixel 2 covers x in [2, 3): put the edge at 2 + c
        o = 0.5 - (2 + c) / 5
        p = _edge_scene(tmp_path, o=round(o, 12), name=f"edge{i}")
        img = T.truth_image(str(p), cfg, 5, ss=n, band_ss=n, cache_dir=tmp_path / "cache")
        exact = 255.0 * (1 - c)
        assert np.allclose(img[:, :2, :3], 0) and np.allclose(img[:, 3:, :3], 255)
        err = img[:, 2, 0] - exact
        assert np.all(np.abs(err) <= 255.0 / n + 1e-9), (n, c, err)
        errs += list(err)
    assert abs(np.mean(errs)) <= 255.0 / n / 4, np.mean(errs)  # no bias (half a stratum would be 255 / 2n)


def test_truth_reproducible_cached_and_keyed(tmp_path):
    cfg = load_config("full")
    p = _edge_scene(tmp_path, w=7, k=3.0)
    img1, info1 = T.truth(str(p), cfg, 7, ss=4, band_ss=8, cache_dir=tmp_path / "c")
    assert info1["cached"] is False and len(list((tmp_path / "c").glob("*.npz"))) == 1
    img2, info2 = T.truth(str(p), cfg, 7, ss=4, band_ss=8, cache_dir=tmp_path / "c")
    assert info2["cached"] is True and np.array_equal(img1, img2)
    assert np.array_equal(info1["band"], info2["band"])
    img3, _ = T.truth(str(p), cfg, 7, ss=4, band_ss=8, cache_dir=tmp_path / "d")  # rendered again: same jitter
    assert np.array_equal(img1, img3)
    _, info4 = T.truth(str(p), cfg, 7, ss=4, band_ss=8, seed=16, cache_dir=tmp_path / "c")
    assert info4["cached"] is False  # another jitter seed, another file
    p.write_text(p.read_text().replace("[255, 255, 255, 255]", "[255, 255, 254, 255]"))
    _, info5 = T.truth(str(p), cfg, 7, ss=4, band_ss=8, cache_dir=tmp_path / "c")
    assert info5["cached"] is False and len(list((tmp_path / "c").glob("*.npz"))) == 3
    reduced = load_config("reduced")  # another lattice, another file
    assert T.truth(str(p), reduced, 7, ss=4, band_ss=8, cache_dir=tmp_path / "c")[1]["cached"] is False


def test_band_rate_and_convergence(tmp_path):
    """f = 3 s on a 7 px frame: w = 3/7 > 1/8 everywhere, every tile at band_ss; the n/2
    estimate moves the edge pixel only, by at most 255 (2/n) per pixel."""
    cfg = load_config("full")
    p = _edge_scene(tmp_path, w=7, k=3.0)
    img, info = T.truth(str(p), cfg, 7, ss=2, band_ss=8, cache_dir=tmp_path)
    assert info["band"].all() and info["band_tiles"] == info["tiles"] == 1
    assert info["samples"] == 7 * 4 * 8 * 8
    cv = info["convergence"]["band"]
    assert cv["pixels"] == 28 and 0 < cv["max_abs_lsb"] <= 255 * 2 / 8 + 1e-6 and cv["psnr_db"] > 20
    p2 = _edge_scene(tmp_path, w=7, k=0.1, name="slow")  # w = 0.1 / 7 < 1/8: no band, ss only
    _, info2 = T.truth(str(p2), cfg, 7, ss=2, band_ss=8, cache_dir=tmp_path)
    assert not info2["band"].any() and info2["band_tiles"] == 0 and info2["samples"] == 7 * 4 * 2 * 2
    assert info2["convergence"]["band"]["psnr_db"] is None
    _, info3 = T.truth(str(p), cfg, 7, ss=3, band_ss=3, cache_dir=tmp_path)  # odd n: no n/2 estimate
    assert info3["convergence"]["all"]["psnr_db"] is None


@pytest.mark.parametrize("name", ["wood", "seascape", "zone_plate", "moonrise"])
def test_frontend_window_is_a_slice_of_the_frame(name):
    """A window of the frame gives the frame's passes on its pixels, bit for bit (meshes,
    planes, screens, spheres); a zero jitter is the pixel centre."""
    sc = load_scene(scene_path(name))
    full = render_passes(sc, 48, 48)
    y0, y1, x0, x1 = 13, 37, 5, 40
    win = render_passes(sc, 48, 48, window=(x0, y0, x1, y1), jitter=(np.zeros((24, 35)), np.zeros((24, 35))))
    assert [a.name for a in full] == [b.name for b in win]
    for a, b in zip(full, win):
        assert np.array_equal(a.mask[y0:y1, x0:x1], b.mask), a.name
        assert np.array_equal(a.s[y0:y1, x0:x1], b.s) and np.array_equal(a.J[y0:y1, x0:x1], b.J), a.name


def test_window_outside_frame_is_an_error():
    sc = load_scene(scene_path("zone_plate"))
    with pytest.raises(ValueError, match="window"):
        render_passes(sc, 8, 8, window=(0, 0, 9, 8))
