"""The texture interior of a frame: its textured pixels less a one-pixel rim at every silhouette.

    from model.scene.rim import silhouette_rim, texture_interior
    rim = silhouette_rim([ps.mask for ps in passes])          # [H, W] bool
    inner = texture_interior([ps.mask for ps in passes])      # textured and not on a rim

The texture unit shades a pixel that a pass covers at the pixel's centre, as if the pass covered
all of it (the front end samples coverage once a pixel, model/scene/frontend.py). The converged
truth (model/scene/truth.py) averages the pixel's samples, coverage included: on a pixel that a
silhouette crosses (the edge of a sphere, the horizon, a moon in front of a planet) the truth
mixes the pass's texture with what lies behind it, and no texture filter can give that mix. That
error is the front end's geometric aliasing, the same for every configuration of the unit.

A pixel is on a rim when some pass's coverage changes inside its 3x3 neighbourhood: the pixels on
both sides of every pass's silhouette (the covered one and the one beside it, which another pass
or the background may fill). The frame's border is not an edge (the neighbourhood is clipped to
the frame). The texture interior, where the truth is the texture's own average, is what the
texture unit's figures against the truth are measured on; figures over all textured pixels, rims
included, are reported beside them (app/render.py, explore/measure.py, explore/filters.py).
"""
from __future__ import annotations

import numpy as np


def _changes(m: np.ndarray) -> np.ndarray:
    """[H, W] bool: m is not constant in the pixel's 3x3 neighbourhood (clipped to the frame)."""
    H, W = m.shape
    p = np.pad(m, 1, mode="edge")
    lo, hi = m.copy(), m.copy()
    for dy in range(3):
        for dx in range(3):
            v = p[dy:dy + H, dx:dx + W]
            lo &= v
            hi |= v
    return lo != hi


def _each(masks, f) -> np.ndarray:
    """[H, W] bool: the OR of f(mask) over the masks ((0, 0) for none)."""
    masks = [np.asarray(m, bool) for m in masks]
    out = np.zeros(masks[0].shape if masks else (0, 0), bool)
    for m in masks:
        out |= f(m)
    return out


def silhouette_rim(masks) -> np.ndarray:
    """[H, W] bool: pixels on a one-pixel rim at any mask's edge, on both sides of it."""
    return _each(masks, _changes)


def texture_interior(masks) -> np.ndarray:
    """[H, W] bool: pixels that some mask covers and that lie on no mask's rim."""
    masks = list(masks)
    return _each(masks, lambda m: m) & ~silhouette_rim(masks)
