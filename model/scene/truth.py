"""The ground truth of a scene: stratified jittered supersampling of the unfiltered float
reference, adaptive by filter width, with its own convergence figure, cached on disk.

    from model.scene.truth import truth_image, truth
    img = truth_image("seascape", cfg, 256)            # float64 RGBA [H, W, 4], 0..255
    img, info = truth("seascape", cfg, 256)            # info: rates, band, convergence, cache file
    img, half, band, textured, meta = render_truth(scene, cfg, W, H)   # a loaded Scene, not cached

Sampling: the frame is cut into TILE x TILE-pixel tiles. A tile with a pixel of the band
(`band_mask`: the float reference's filter width w = |grad f| above N/8 table entries, i.e.
1/8 of the colour map, in any pass covering the pixel) gets band_ss x band_ss samples a pixel,
every other tile ss x ss. Each sample is the unfiltered float reference (model/reference.py) at
a ray through a point drawn uniformly in its stratum (one stratum per sample, an n x n grid in
the pixel), composited over the background as the passes are; the pixel is the samples' mean.
The jitter of a tile comes from numpy's PCG64 seeded by (seed, n, tile row, tile column), so a
truth is reproducible whatever order or band of tiles renders it. A tile is one window of the
front end (model.scene.frontend.Rays): memory is bounded by one tile's samples.

Convergence: from the same samples, the n/2 x n/2 estimate takes one sample of the four in every
2 x 2 group of strata (a random one, seeded), which is an n/2 x n/2 stratified jittered sample of
the pixel. How far the truth moves between n/2 and n (PSNR, max and mean abs difference in LSB,
over the textured pixels and over the band) bounds from above how far it is from the limit (for
a convergent estimate the n image is nearer than the n/2 one). It is reported beside the
differences measured against it (app.render): the truth serves where it moves less.

Cache: <cache_dir>/<scene>-<W>x<H>-ss<ss>-<band_ss>-j<seed>-p<perm seed>-h<hash_bits>-<key>.npz
(truth, half-rate estimate, band, textured mask) and .json (info), key = a hash of the scene
file and of the sources that compute the truth (reference, front end, scene parser, meshes,
compositing, this module). Written to a temporary name and renamed.
"""
from __future__ import annotations

import hashlib
import json
import os
import time
from pathlib import Path

import numpy as np

from model import reference
from model.hw.config import ROOT
from model.imageio import compare
from model.scene.passes import composite, frame_size

TRUTH_SS = 16  # samples per pixel axis outside the band's tiles
BAND_SS = 32  # samples per pixel axis in the tiles with a band pixel (issue 15: at least 32 x 32)
TILE = 16  # pixels per tile side
BAND_W = 1.0 / 8.0  # the band: filter width above N/8 entries (colour-map units)
JITTER_SEED = 15
CACHE_DIR = ROOT / "out" / "truth"
_SOURCES = ("model/reference.py", "model/texture.py", "model/scene/frontend.py", "model/scene/scene.py",
            "model/scene/teapot.py", "model/scene/passes.py", "model/scene/truth.py")


def band_mask(passes, cfg) -> tuple[np.ndarray, np.ndarray]:
    """(band, textured) [H, W] bool of the 1x passes: band where any pass covering the pixel has
    the float reference filter width w > N/8 entries (BAND_W of the colour map)."""
    H, W = passes[0].mask.shape if passes else (0, 0)
    band = np.zeros((H, W), bool)
    textured = np.zeros((H, W), bool)
    for ps in passes:
        w = reference.filter_width(ps.texture, ps.s[ps.mask], ps.J[ps.mask], cfg.perm, cfg.hash_bits)
        b = np.zeros((H, W), bool)
        b[ps.mask] = w > BAND_W
        band |= b
        textured |= ps.mask
    return band, textured


def source_key(path: Path) -> str:
    h = hashlib.sha256(Path(path).read_bytes())
    for src in _SOURCES:
        h.update((ROOT / src).read_bytes())
    return h.hexdigest()[:12]


def _tile(scene, cfg, W, H, n, tx, ty, seed):
    """(truth [h, w, 4], half-rate estimate [h, w, 4] or None) of tile (tx, ty) at n x n samples."""
    from model.scene.frontend import render_passes

    x0, y0 = tx * TILE, ty * TILE
    x1, y1 = min(x0 + TILE, W), min(y0 + TILE, H)
    h, w = y1 - y0, x1 - x0
    rng = np.random.default_rng([seed, n, ty, tx])
    jit = rng.random((2, h * n, w * n)) - 0.5
    big = render_passes(scene, W * n, H * n, window=(x0 * n, y0 * n, x1 * n, y1 * n), jitter=(jit[0], jit[1]))
    layers = []
    for ps in big:
        f = reference.texture_f(ps.texture, ps.s[ps.mask], cfg.perm, cfg.hash_bits)
        layers.append((ps.mask, reference.unfiltered_lookup(ps.texture.clut, f, ps.texture.mode)))
    img = composite(layers, (h * n, w * n), scene.background).reshape(h, n, w, n, 4)
    half = None
    if n % 2 == 0:
        m = n // 2
        g = img.reshape(h, m, 2, w, m, 2, 4).transpose(0, 1, 3, 4, 2, 5, 6).reshape(h, m, w, m, 4, 4)
        pick = rng.integers(0, 4, size=(h, m, w, m, 1, 1))
        half = np.take_along_axis(g, np.broadcast_to(pick, (h, m, w, m, 1, 4)), axis=4)[..., 0, :].mean(axis=(1, 3))
    return img.mean(axis=(1, 3)), half


def _convergence(img, half, mask) -> dict:
    if half is None or not mask.any():
        return {"psnr_db": None, "max_abs_lsb": None, "mean_abs_lsb": None, "pixels": int(mask.sum())}
    c = compare(half[mask], img[mask])
    return {"psnr_db": c["psnr_db"], "max_abs_lsb": round(c["max_abs_error_lsb"], 3),
            "mean_abs_lsb": round(c["mean_abs_error_lsb"], 4), "pixels": int(mask.sum())}


def render_truth(scene, cfg, W: int, H: int, ss: int = TRUTH_SS, band_ss: int = BAND_SS, seed: int = JITTER_SEED,
                 passes=None, progress: bool = False, desc: str = "truth"):
    """The truth of a loaded scene (not cached): (image, n/2 estimate or None, band, textured,
    meta); meta: size, rates, tiles, samples, lattice, pixel counts, convergence."""
    from model.cli import progress_bar

    if passes is None:
        from model.scene.frontend import render_passes

        passes = render_passes(scene, W, H)
    band, textured = band_mask(passes, cfg)
    img, half = np.zeros((H, W, 4)), np.zeros((H, W, 4))
    have_half = True
    nty, ntx = -(-H // TILE), -(-W // TILE)
    in_band = [[bool(band[ty * TILE:(ty + 1) * TILE, tx * TILE:(tx + 1) * TILE].any()) for tx in range(ntx)]
               for ty in range(nty)]
    rates = [[band_ss if b else ss for b in row] for row in in_band]
    samples = sum(r * r * min(TILE, W - tx * TILE) * min(TILE, H - ty * TILE)
                  for ty, row in enumerate(rates) for tx, r in enumerate(row))
    bar = progress_bar(progress, total=samples, desc=desc)
    for ty in range(nty):
        for tx in range(ntx):
            n = rates[ty][tx]
            t, hf = _tile(scene, cfg, W, H, n, tx, ty, seed)
            sl = np.s_[ty * TILE:ty * TILE + t.shape[0], tx * TILE:tx * TILE + t.shape[1]]
            img[sl] = t
            if hf is None:
                have_half = False
            else:
                half[sl] = hf
            bar.update(n * n * t.shape[0] * t.shape[1])
    bar.close()
    half = half if have_half else None
    meta = {"width": W, "height": H, "ss": ss, "band_ss": band_ss, "tile": TILE,
            "rate": f"{ss}x{ss} a pixel, {band_ss}x{band_ss} in the {TILE}x{TILE}-pixel tiles with a band pixel",
            "tiles": nty * ntx, "band_tiles": sum(b for row in in_band for b in row), "samples": samples,
            "jitter_seed": seed, "lattice": {"seed": cfg.seed, "hash_bits": cfg.hash_bits},
            "band_pixels": int(band.sum()), "textured_pixels": int(textured.sum()),
            "convergence": {"all": _convergence(img, half, textured), "band": _convergence(img, half, band)},
            "convergence_rates": "n/2 x n/2 against n x n (n = the tile's rate)"}
    return img, half, band, textured, meta


def truth(scene_name: str, cfg, size: int, ss: int = TRUTH_SS, band_ss: int = BAND_SS, seed: int = JITTER_SEED,
          cache_dir: Path | None = None, progress: bool = False, passes=None) -> tuple[np.ndarray, dict]:
    """(truth image float64 RGBA [H, W, 4] in 0..255, info) of a scene (a name or a .toml path)
    at `size` px wide, for the lattice of configuration cfg (cfg.perm, cfg.hash_bits: nothing
    else of cfg matters). Read from the cache when there; else rendered and cached.
    info: size, rates, samples, band and textured pixel counts, convergence {"all", "band"}
    (n/2 against n: psnr_db, max_abs_lsb, mean_abs_lsb), cache file, seconds; info["band"] and
    info["textured"] are the [H, W] masks (not in the .json). passes: the scene's 1x passes at
    this size, if the caller has them (spares ray-casting them again)."""
    from model.cli import resolve_scene
    from model.scene.scene import load_scene

    name, path = resolve_scene(scene_name)
    scene = load_scene(path)
    W, H = frame_size(scene, size)
    cache = Path(cache_dir) if cache_dir is not None else CACHE_DIR
    stem = f"{name}-{W}x{H}-ss{ss}-{band_ss}-j{seed}-p{cfg.seed}-h{cfg.hash_bits}-{source_key(path)}"
    hit = load_cached(cache, stem)
    if hit is not None:
        return hit
    t0 = time.perf_counter()
    img, half, band, textured, meta = render_truth(scene, cfg, W, H, ss, band_ss, seed, passes, progress,
                                                   f"truth {name} {W}x{H}")
    info = {"scene": name, **meta, "seconds": round(time.perf_counter() - t0, 2)}
    return img, save_cached(cache, stem, img, half, band, textured, info)


def load_cached(cache: Path, stem: str):
    """(truth, info) from <cache>/<stem>.npz/.json, or None."""
    npz, js = cache / f"{stem}.npz", cache / f"{stem}.json"
    if not (npz.is_file() and js.is_file()):
        return None
    with np.load(npz) as z:
        info = json.loads(js.read_text())
        info.update(band=z["band"], textured=z["textured"], cached=True)
        return z["truth"], info


def save_cached(cache: Path, stem: str, img, half, band, textured, info: dict) -> dict:
    """Write <cache>/<stem>.npz/.json (temporary names, renamed); -> info with the masks."""
    npz, js = cache / f"{stem}.npz", cache / f"{stem}.json"
    info = {**info, "cache": str(npz)}
    cache.mkdir(parents=True, exist_ok=True)
    tmp = cache / f".{stem}.{os.getpid()}"
    np.savez(f"{tmp}.npz", truth=img, half=half if half is not None else np.zeros(0), band=band, textured=textured)
    Path(f"{tmp}.json").write_text(json.dumps(info, indent=1) + "\n")
    os.replace(f"{tmp}.npz", npz)
    os.replace(f"{tmp}.json", js)
    return {**info, "band": band, "textured": textured, "cached": False}


def truth_image(scene_name: str, cfg, size: int, **kw) -> np.ndarray:
    """The truth image alone (float64 RGBA [H, W, 4], 0..255): see `truth`."""
    return truth(scene_name, cfg, size, **kw)[0]
