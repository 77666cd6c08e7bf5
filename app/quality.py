"""Image quality of a configuration and of one-key steps from it: the figures behind its widths.

    python -m app.quality --config compact --size 512 [--step KEY=VALUE[,KEY=VALUE] ...]

For the configuration, and for each step (the configuration with those keys changed), the
golden model renders every scene (model.scene.passes.SCENES) and is compared with the float
reference of the scene as written (model/reference.py, with every term and the scene's
blend): PSNR in dB over the textured pixels, per scene and the worst. A step that the
configuration checks reject (model/hw/config.py) or that a scene's values do not fit
(model/hw/quantize.py) is reported with its one-line reason. docs/numerics.md quotes these
tables for the widths of config/compact.toml. The ray casting and the float reference do not
depend on the configuration's formats, so they are computed once per scene and size.
"""
from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from model import reference
from model.hw import golden
from model.hw.config import ConfigError, load_config, variant
from model.hw.quantize import FormatError
from model.imageio import compare
from model.scene.passes import SCENES, composite, frame_size, prepare_passes, scene_path
from model.scene.rim import texture_interior

_passes: dict = {}
_refs: dict = {}


def _scene(name: str, size: int):
    from model.scene.frontend import render_passes
    from model.scene.scene import load_scene

    if (name, size) not in _passes:
        sc = load_scene(scene_path(name))
        W, H = frame_size(sc, size)
        _passes[(name, size)] = (sc, W, H, render_passes(sc, W, H))
    return _passes[(name, size)]


def scene_images(cfg, name: str, size: int) -> dict:
    """The golden image of `name` under `cfg` and its float reference (the scene as written):
    {"golden", "reference": [H, W, 4] float, "textured": [H, W] bool, "interior": the textured pixels less
    the silhouette rims (model/scene/rim.py) [H, W] bool, "pixels": textured pixels
    streamed, "clocks": the pipeline's clocks for them (model.hw.config.clocks_per_pixel of each
    pass's k_used)}."""
    from model.hw.config import clocks_per_pixel

    sc, W, H, passes = _scene(name, size)
    pds = prepare_passes(cfg, passes)
    textured = np.zeros((H, W), bool)
    gold, ref = [], []
    pixels = clocks = 0
    for pd in pds:
        gold.append((pd.mask, golden.texture_pipeline(cfg, pd.ti, pd.si, pd.Jm, pd.je)))
        key = (name, size, pd.name, cfg.seed, cfg.hash_bits)  # the reference depends on the lattice only
        if key not in _refs:
            _refs[key] = reference.shade(pd.tex, pd.s, pd.J, cfg.perm, cfg.hash_bits)
        ref.append((pd.mask, _refs[key]))
        textured |= pd.mask
        pixels += len(pd.si)
        clocks += len(pd.si) * clocks_per_pixel(cfg, pd.ti.k_used)
    return {"golden": composite(gold, (H, W), sc.background), "reference": composite(ref, (H, W), sc.background),
            "textured": textured, "interior": texture_interior([pd.mask for pd in pds]), "pixels": pixels,
            "clocks": clocks}


def scene_psnr(cfg, name: str, size: int) -> tuple[float, float]:
    """(PSNR dB, largest error in LSB) of the golden image of `name` against its float reference."""
    im = scene_images(cfg, name, size)
    t = im["textured"]
    c = compare(im["golden"][t], im["reference"][t])
    return c["psnr_db"], c["max_abs_error_lsb"]


def quality(cfg, size: int, scenes=SCENES) -> dict:
    """{scene: psnr dB} and 'worst', or {'error': reason} when a scene cannot be rendered."""
    out = {}
    for s in scenes:
        try:
            out[s] = round(scene_psnr(cfg, s, size)[0], 2)
        except FormatError as e:
            return {"error": f"{s}: {e}"}
    out["worst"] = min(out.values())
    return out


def parse_step(text: str) -> dict:
    """--step KEY=VALUE[,KEY=VALUE]: the keys a step changes (ValueError on a malformed one)."""
    ch = {}
    for item in text.split(","):
        k, sep, v = item.partition("=")
        if not sep:
            raise ValueError(f"--step {text!r}: expected KEY=VALUE[,KEY=VALUE]")
        v = v.strip()
        ch[k.strip()] = (v == "true") if v in ("true", "false") else int(v) if v.lstrip("-").isdigit() else v
    return ch


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m app.quality", description=__doc__.split("\n\n")[0])
    ap.add_argument("--config", default="compact")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--step", action="append", default=[], help="KEY=VALUE[,KEY=VALUE]: one step from the configuration")
    ap.add_argument("--json", action="store_true", help="one JSON object per row instead of a table")
    args = ap.parse_args(argv)
    if not 8 <= args.size <= 1024:
        print(f"quality: --size {args.size}: expected 8..1024", file=sys.stderr)
        return 2
    try:
        base = load_config(args.config)
        steps = [(s, parse_step(s)) for s in args.step]
        cfgs = [("(as written)", base)] + [(s, variant(base, f"{base.name}-step", **ch)) for s, ch in steps]
    except (ConfigError, ValueError) as e:
        print(f"quality: {e}", file=sys.stderr)
        return 2
    if not args.json:
        print(f"PSNR (dB) of the golden model against the float reference, {args.size} px, "
              f"configuration {base.name}")
        print("| step | " + " | ".join(SCENES) + " | worst |")
        print("|---" * (len(SCENES) + 2) + "|")
    for label, cfg in cfgs:
        q = quality(cfg, args.size)
        if args.json:
            print(json.dumps({"config": base.name, "step": label, "size": args.size, **q}))
        elif "error" in q:
            print(f"| {label} | {q['error']} |")
        else:
            print(f"| {label} | " + " | ".join(f"{q[s]:.1f}" for s in SCENES) + f" | {q['worst']:.1f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
