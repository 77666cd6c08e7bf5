"""What a scene needs of the hardware: `python -m app needs SCENE [--size 256] [--json]`.

For each texture the scene uses: its noise terms (those with a nonzero amplitude), the kind of
each transform T_i (affine, diagonal, powers of two), of each amplitude a_i (a power of two or
any value), the blend, the noise gradient, the quadric (axis-aligned or general), the colour
table (entries, mod or clamp, filtered); and the ranges the scene meets at a frame size: s, the
quadric coefficients, the T_i entries and offsets, a_i, f and the filter width w (in table
entries), from the front end's rays. `needs_config(needs)` is what the configuration keys must
at least be for the scene to render as written (model.hw.config's features, and the words the
ranges take), the starting point of `make fit`.
The render report (app.render) carries the same `needs` section.
"""
from __future__ import annotations

import json
import math
import sys

import numpy as np

from model import reference
from model.hw.config import load_config


from model.scene.texture_needs import precision, texture_needs, value_range  # noqa: F401 (precision: re-exported)


def needs(scene_name: str, size: int = 256, cfg=None) -> dict:
    """What scene `scene_name` (a name or a .toml path) needs, measured at `size` px; the
    noise (f, w) on cfg's lattice (default config `full`'s)."""
    from model.cli import resolve_scene
    from model.scene.frontend import render_passes
    from model.scene.passes import frame_size
    from model.scene.scene import load_scene

    name, path = resolve_scene(scene_name)
    sc = load_scene(path)
    W, H = frame_size(sc, size)
    return needs_of_passes(name, render_passes(sc, W, H), W, H, size, cfg)


def needs_of_passes(name: str, passes, W: int, H: int, size: int, cfg=None) -> dict:
    """needs() from the front end's passes of a render (model.scene.frontend.render_passes)."""
    cfg = cfg or load_config("full")
    tex: dict[str, dict] = {}
    for ps in passes:
        key = ps.texture_name or ps.name
        t = tex.setdefault(key, {**texture_needs(ps.texture), "pixels": 0, "_s": [], "_f": [], "_w": []})
        s, J = ps.s[ps.mask], ps.J[ps.mask]
        if not len(s):
            continue
        t["pixels"] += int(len(s))
        t["_s"].append(s)
        t["_f"].append(reference.texture_f(ps.texture, s, cfg.perm, cfg.hash_bits))
        t["_w"].append(reference.filter_width(ps.texture, s, J, cfg.perm, cfg.hash_bits) * len(ps.texture.clut))
    for t in tex.values():
        s, f, w = (np.concatenate(t.pop(k)) if t[k] else np.zeros(0) for k in ("_s", "_f", "_w"))
        t["range_s"] = value_range(s)
        t["range_f"] = value_range(f)
        t["range_w_entries"] = value_range(w)
    return {"scene": name, "size": size, "width": W, "height": H, "textures": tex}


def needs_config(nd: dict) -> dict:
    """The features the scene's textures need (the least configuration that renders them as
    written): terms, transform, amplitude, blend, noise gradient, quadric, filter."""
    ts = list(nd["textures"].values())
    anyt = lambda k, v: any(v in t[k] for t in ts)  # noqa: E731
    return {
        "noise_terms": max([t["noise_terms"] for t in ts] + [0]),
        "transform": "affine" if anyt("transforms", "affine") or anyt("transforms", "diagonal")
                     or any(t["offsets"] for t in ts) else "pow2",
        "amplitude": "any" if anyt("amplitudes", "any") else "pow2",
        "blend": "cubic" if any(t["blend"] == "cubic" for t in ts) else "linear",
        "noise_gradient": any(t["noise_gradient"] for t in ts),
        "quadric": "full" if any(t["quadric"] == "full" for t in ts) else "diagonal",
        "filter": "sat" if any(t["filtered"] for t in ts) else "none",
    }


def merge_needs(nds: list[dict]) -> dict:
    """needs_config of several scenes together (the most each key needs)."""
    cs = [needs_config(n) for n in nds]
    order = {"transform": ("pow2", "affine"), "amplitude": ("pow2", "any"), "blend": ("linear", "cubic"),
             "quadric": ("diagonal", "full"), "filter": ("none", "sat")}
    out = {"noise_terms": max(c["noise_terms"] for c in cs), "noise_gradient": any(c["noise_gradient"] for c in cs)}
    for k, o in order.items():
        out[k] = max((c[k] for c in cs), key=o.index)
    return out


def _fmt_rng(r) -> str:
    return "-" if r is None else f"[{r[0]:.4g}, {r[1]:.4g}]"


def text(nd: dict) -> str:
    L = [f"scene {nd['scene']} at {nd['width']}x{nd['height']}:"]
    for name, t in nd["textures"].items():
        L.append(f"  texture {name}: {t['pixels']} px, {t['noise_terms']} noise terms"
                 + (f" (T: {', '.join(t['transforms'])}{', offsets' if t['offsets'] else ''}; "
                    f"a: {', '.join(t['amplitudes'])}; {t['blend']} blend"
                    f"{', noise gradient' if t['noise_gradient'] else ''})" if t["noise_terms"] else "")
                 + f", {t['quadric']} quadric, {t['table_entries']}-entry table {t['mode']}"
                 + (", filtered" if t["filtered"] else ", unfiltered"))
        L.append(f"    s {_fmt_rng(t['range_s'])}  q {_fmt_rng(t['range_q'])}  T {_fmt_rng(t['range_T'])}  "
                 f"o {_fmt_rng(t['range_o'])}  a {_fmt_rng(t['range_a'])}  f {_fmt_rng(t['range_f'])}  "
                 f"w {_fmt_rng(t['range_w_entries'])} entries")
    c = needs_config(nd)
    L.append("  needs: " + ", ".join(f"{k} = {v}" for k, v in c.items()))
    return "\n".join(L)


def main(argv=None) -> int:
    from model.cli import Parser, check_range, run_main

    ap = Parser(prog="python -m app needs", description="what a scene needs of the hardware")
    ap.add_argument("scene", help="a scene name or a .toml path")
    ap.add_argument("--size", type=int, default=256, help="frame side for the ranges (px)")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args(argv)

    def go():
        check_range("--size", a.size, 2, 2048)
        nd = needs(a.scene, a.size)
        print(json.dumps({**nd, "needs": needs_config(nd)}, indent=1) if a.json else text(nd))
        return 0

    return run_main("needs", go)


if __name__ == "__main__":
    sys.exit(main())
