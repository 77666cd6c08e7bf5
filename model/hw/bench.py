"""`make bench-model`: golden model and float reference throughput, as JSON.

A 512x512 frame of a texture with 8 noise terms (the full configuration's
maximum), random smooth s and J; each model timed over whole frames (best of 3).
"""
from __future__ import annotations

import json
import sys
import time

import numpy as np

from model import reference
from model.hw import golden
from model.hw.config import load_config
from model.hw.quantize import quantize_pixels, quantize_texture
from model.texture import NoiseTerm, TextureParams


def bench_frame(size=512, terms=8, seed=0):
    rng = np.random.default_rng(seed)
    ys, xs = np.mgrid[0:size, 0:size] / size
    s = np.stack([4 * xs - 2, 4 * ys - 2, 0.5 * xs * ys], -1)
    J = np.zeros((size, size, 3, 2))
    J[..., 0, 0] = J[..., 1, 1] = 4 / size
    J[..., 2, 0], J[..., 2, 1] = 0.5 * ys / size, 0.5 * xs / size
    clut = rng.integers(0, 256, (256, 4)).astype(np.uint8)
    tex = TextureParams(Q=[1, 0, 0, 0, 1, 0, 0, 0, 0, 0], clut=clut, mode="mod",
                        terms=[NoiseTerm(2.0 ** -i, np.eye(3) * 2.0 ** min(i, 6), [0.37 * i, 0, 0]) for i in range(terms)])
    return tex, s, J


def best_of(fn, n=3):
    best = float("inf")
    for _ in range(n):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def main() -> int:
    size = 512
    tex, s, J = bench_frame(size)
    px = size * size
    out = {"frame": f"{size}x{size}", "noise_terms": 8, "pixels": px}
    for name in ("full", "reduced"):
        cfg = load_config(name)
        tex.blend = cfg.blend
        ti, info = quantize_texture(cfg, tex)
        si, Jm, je = quantize_pixels(cfg, s, J)
        t = best_of(lambda: golden.texture_pipeline(cfg, ti, si, Jm, je))
        out[f"golden_{name}_pixels_per_second"] = round(px / t)
        out[f"golden_{name}_noise_terms_evaluated"] = info["terms_used"]
    cfg = load_config("full")
    t = best_of(lambda: reference.shade(tex, s, J, cfg.perm, cfg.hash_bits), n=1)
    out["reference_pixels_per_second"] = round(px / t)
    out["goal_golden_pixels_per_second"] = 250000
    out["goal_met"] = out["golden_full_pixels_per_second"] >= 250000
    print(json.dumps(out, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
