"""Sub-pixel sample patterns in float: which offsets and footprints make `samples` = 2 worth its clock.

    python -m explore.sample_patterns [--scenes zone_plate,wood] [--size 256] [--truth-ss 16] [--band-ss 32]

For each scene, the float reference (model/reference.py, `full`'s lattice) rendered with one sample a
pixel and with each pattern below, against the converged truth (model/scene/truth.py, cached in
out/truth/) over the texture interior (model/scene/rim.py): PSNR in dB, one JSON line a scene and a
table at the end. A pattern is its offsets d_k (quarter pixels) and each sample's footprint (J's x and
y columns scaled):

- `diagonal J/sqrt2`: (-1, -1), (+1, +1), J / sqrt 2 (the unit's two samples until stop 38);
- `diagonal J/2`, `centre J/sqrt2` (both samples at the centre): what the footprint alone does;
- `horizontal`: (-1, 0), (+1, 0), J's x column halved: the pixel's left and right halves;
- `vertical`: (0, -1), (0, +1), J's y column halved: its upper and lower halves (the unit's two
  samples since stop 38, model/hw/config.py SAMPLE_OFFSETS, SAMPLE_FOOTPRINT);
- `grid`: the 2x2 grid, J / 2: the quarters (the unit's four samples).

The cells of `horizontal`, `vertical` and `grid` tile the pixel, so with f linear across it each
sample's box is its cell's average; the diagonal pair's cells are triangles no box of J / sqrt 2 fits.
"""
from __future__ import annotations

import json
import sys

import numpy as np

from model.cli import Parser, check_range, run_main
from model.scene.passes import SCENES

R2 = 1.0 / np.sqrt(2.0)
PATTERNS = {
    "diagonal J/sqrt2": (((-1, -1), (1, 1)), (R2, R2)),
    "diagonal J/2": (((-1, -1), (1, 1)), (0.5, 0.5)),
    "centre J/sqrt2": (((0, 0), (0, 0)), (R2, R2)),
    "horizontal": (((-1, 0), (1, 0)), (0.5, 1.0)),
    "vertical": (((0, -1), (0, 1)), (1.0, 0.5)),
    "grid": (((-1, -1), (1, -1), (-1, 1), (1, 1)), (0.5, 0.5)),
}


def shade_pattern(tex, s, J, offsets, scale, perm, hash_bits):
    """The mean colour of the samples at s + J d_k, each with the footprint J scaled by column (each
    sample shaded by the float reference at one sample a pixel: a scene's texture has samples = 1)."""
    from dataclasses import replace

    from model import reference

    one = replace(tex, samples=1)
    out = 0.0
    for dx, dy in offsets:
        sk = s + (dx * J[..., 0] + dy * J[..., 1]) / 4.0
        out = out + reference.shade(one, sk, J * np.asarray(scale), perm, hash_bits)
    return out / len(offsets)


def measure(scene: str, size: int, truth_ss: int, band_ss: int) -> dict:
    """{pattern: PSNR against the truth over the texture interior} for one scene (and "one sample")."""
    from model.hw.config import load_config
    from model.imageio import compare
    from model.scene.frontend import render_passes
    from model.scene.passes import composite, frame_size, scene_path
    from model.scene.rim import texture_interior
    from model.scene.scene import load_scene
    from model.scene.truth import truth_image

    cfg = load_config("full")
    sc = load_scene(scene_path(scene))
    W, H = frame_size(sc, size)
    passes = render_passes(sc, W, H)
    tr = truth_image(scene, cfg, size, ss=truth_ss, band_ss=band_ss, passes=passes)
    inner = texture_interior([p.mask for p in passes])
    out = {"scene": sc.name, "size": size, "interior_pixels": int(inner.sum())}
    for name, (offs, scale) in {"one sample": (((0, 0),), (1.0, 1.0)), **PATTERNS}.items():
        layers = [(p.mask, shade_pattern(p.texture, p.s[p.mask], p.J[p.mask], offs, scale, cfg.perm, cfg.hash_bits))
                  for p in passes]
        img = composite(layers, (H, W), sc.background)
        out[name] = compare(img[inner], tr[inner])["psnr_db"]
    return out


def main(argv=None) -> int:
    ap = Parser(prog="python -m explore.sample_patterns", description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", default=",".join(SCENES), help="comma-separated scene names (default: all eight)")
    ap.add_argument("--size", type=int, default=256, help="frame side in pixels")
    ap.add_argument("--truth-ss", type=int, default=16, help="the truth's samples a pixel axis (16)")
    ap.add_argument("--band-ss", type=int, default=32, help="the truth's samples a pixel axis in the band's tiles (32)")
    a = ap.parse_args(argv)

    def go():
        check_range("--size", a.size, 8, 1024)
        check_range("--truth-ss", a.truth_ss, 1, 64)
        check_range("--band-ss", a.band_ss, 1, 64)
        from model.cli import resolve_scene

        scenes = [resolve_scene(s)[1] for s in a.scenes.split(",") if s]  # a bad name fails before any work
        rows = []
        for s in scenes:
            rows.append(measure(str(s), a.size, a.truth_ss, a.band_ss))
            print(json.dumps(rows[-1]), flush=True)
        names = ["one sample", *PATTERNS]
        print("\n| scene | " + " | ".join(names) + " |\n|---|" + "---|" * len(names))
        for r in rows:
            print(f"| {r['scene']} | " + " | ".join("-" if r[n] is None else f"{r[n]:.2f}" for n in names) + " |")
        return 0
    return run_main(ap.prog, go)


if __name__ == "__main__":
    sys.exit(main())
