"""`make bench-model`: golden model and float reference throughput, as JSON.

A 512x512 frame of a texture with 8 noise terms (the full configuration's
maximum), random smooth s and J; each model timed over whole frames (best of 3).
`--size N` times an N x N frame instead (the command test runs it tiny). The texture's
noise scales stop at 2^5 = 32: the largest power of two inside every configuration's T
format (full s17.10 holds at most 63.999, reduced s12.6 at most 31.98).
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
                        terms=[NoiseTerm(2.0 ** -i, np.eye(3) * 2.0 ** min(i, 5), [0.37 * i, 0, 0]) for i in range(terms)])
    return tex, s, J


def best_of(fn, n=3):
    best = float("inf")
    for _ in range(n):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def main(argv=None) -> int:
    import argparse

    ap = argparse.ArgumentParser(prog="python -m model.hw.bench", description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=512)
    a = ap.parse_args(argv)
    if not 1 <= a.size <= 2048:
        print(f"bench-model: --size {a.size}: expected 1..2048", file=sys.stderr)
        return 2
    size = a.size
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
