"""What a texture needs of the hardware, from its parameters alone: the kinds of its transforms,
amplitudes and quadric, its terms, blend and table, and the precision (integer and fraction bits)
its parameters need. The library half of `python -m app needs` (app/needs.py, which adds the
ranges a scene meets at a frame size); model.scene.corpus tags its scenes with it."""
from __future__ import annotations

import math

import numpy as np


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


def value_range(x) -> list[float] | None:
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
        "range_q": value_range(Q),
        "range_T": value_range([t.T for t in terms]) if terms else None,
        "range_o": value_range([t.o for t in terms]) if terms else None,
        "range_a": value_range([t.a for t in terms]) if terms else None,
        # the formats the parameters need (int bits with the sign, fraction bits: exact, and
        # within 2^-12 of the largest): a format with fewer rounds them (render reports say by how much)
        "precision": {"quadric": precision(Q), "T": precision([t.T for t in terms]) if terms else None,
                      "a": precision([t.a for t in terms]) if terms else None,
                      "o": precision([t.o for t in terms]) if terms else None},
    }
