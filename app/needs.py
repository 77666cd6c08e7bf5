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


def _pow2(x: float) -> bool:
    if x == 0:
        return True
    m, _ = math.frexp(abs(x))
    return m == 0.5


def _kind_T(T: np.ndarray) -> str:
    off = T - np.diag(np.diag(T))
    if np.any(off != 0):
        return "affine"
    return "pow2" if all(_pow2(float(v)) for v in np.diag(T)) else "diagonal"


def _rng(x) -> list[float] | None:
    x = np.asarray(x, dtype=np.float64)
    return [float(x.min()), float(x.max())] if x.size else None


FRAC_CAP = 24  # fraction bits past which a value counts as not exactly representable


def precision(values) -> dict | None:
    """The fixed-point precision values need: {"int_bits": bits left of the point (sign
    included) for the largest |value|, "frac_bits": the fewest fraction bits that hold every
    value exactly (None past FRAC_CAP: not a dyadic fraction, e.g. cos 30 degrees),
    "frac_bits_rel12": the fewest that hold each within 2^-12 of its magnitude's scale}."""
    v = np.asarray(values, dtype=np.float64).ravel()
    if not v.size:
        return None
    m = float(np.max(np.abs(v)))
    ib = max(1, int(math.floor(math.log2(m))) + 2) if m > 0 else 1
    exact = next((f for f in range(FRAC_CAP + 1) if np.all(v * 2.0 ** f == np.rint(v * 2.0 ** f))), None)
    rel = next((f for f in range(FRAC_CAP + 1)
                if np.all(np.abs(np.rint(v * 2.0 ** f) / 2.0 ** f - v) <= 2.0 ** -12 * max(m, 1e-300))), FRAC_CAP)
    return {"int_bits": ib, "frac_bits": exact, "frac_bits_rel12": rel}


def texture_needs(tex) -> dict:
    terms = [t for t in tex.terms if t.a != 0]
    Q = np.asarray(tex.Q, dtype=np.float64)
    return {
        "noise_terms": len(terms),
        "transforms": [_kind_T(t.T) for t in terms],
        "offsets": bool(any(np.any(t.o != 0) for t in terms)),
        "amplitudes": ["pow2" if _pow2(t.a) else "any" for t in terms],
        "blend": tex.blend if terms else None,
        "noise_gradient": bool(tex.noise_gradient and terms and tex.filter),
        "quadric": "diagonal" if Q[1] == 0 and Q[2] == 0 and Q[5] == 0 else "full",  # B, C, F
        "table_entries": int(len(tex.clut)),
        "mode": tex.mode,
        "filtered": bool(tex.filter),
        "range_q": _rng(Q),
        "range_T": _rng([t.T for t in terms]) if terms else None,
        "range_o": _rng([t.o for t in terms]) if terms else None,
        "range_a": _rng([t.a for t in terms]) if terms else None,
        # the formats the parameters need (int bits with the sign, fraction bits: exact, and
        # within 2^-12 of the largest): a format with fewer rounds them (render reports say by how much)
        "precision": {"quadric": precision(Q), "T": precision([t.T for t in terms]) if terms else None,
                      "a": precision([t.a for t in terms]) if terms else None,
                      "o": precision([t.o for t in terms]) if terms else None},
    }


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
        t["range_s"] = _rng(s)
        t["range_f"] = _rng(f)
        t["range_w_entries"] = _rng(w)
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
