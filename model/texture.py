"""A texture of eq. (1), p(s) = clut(q(s) + sum_i a_i n(T_i s + o_i)), in float parameters.

This is what the scene front end produces and what both the float reference
(model.reference) and the quantizer feeding the golden model and the RTL
(model.hw.quantize) consume. Nothing here is fixed point.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

# Order of the 10 quadric coefficients of eq. (3): q = A s^2 + 2B st + 2C sr + 2D s
# + E t^2 + 2F tr + 2G t + H r^2 + 2I r + J.
QUADRIC_NAMES = ("A", "B", "C", "D", "E", "F", "G", "H", "I", "J")


@dataclass
class NoiseTerm:
    """One term a * n(T s + o) of eq. (1)."""

    a: float
    T: np.ndarray  # 3x3 float64, linear part of the affine map T_i
    o: np.ndarray  # 3 float64, offset (phase) of the affine map, in lattice units

    def __post_init__(self):
        self.a = float(self.a)
        self.T = np.asarray(self.T, dtype=np.float64).reshape(3, 3)
        self.o = np.asarray(self.o, dtype=np.float64).reshape(3)


@dataclass
class TextureParams:
    """Parameters of one texture: the quadric, the noise terms and the colour map."""

    Q: np.ndarray  # 10 float64 coefficients A..J of eq. (3)
    terms: list = field(default_factory=list)  # list of NoiseTerm
    blend: str = "cubic"  # "cubic" or "linear"
    mode: str = "mod"  # "mod" or "clamp"
    clut: np.ndarray = None  # uint8 [N, 4] RGBA, N a power of two (1..2^n_log2_max)
    filter: bool = True  # antialias (box filter the colour table) or point-sample it
    noise_gradient: bool = True  # include a_i grad n_i in grad f (eq. 10)
    # frequency clamping (filters "sat_fc", "sat2_fc", docs/filters.md): (knee, fade) in octaves of the
    # footprint, each term faded to its mean over [knee - fade, knee]; None: the box filter alone
    fc: tuple = None
    # the trapezoid (filters "sat2", "sat2_fc", docs/filters.md): the colour map averaged over the pixel for
    # f linear across it (two boxes of the screen components of grad f) instead of one box
    trapezoid: bool = False
    # sub-pixel samples (features.samples, docs/filters.md "Sub-pixel samples"): the pixel's colour the
    # average of `samples` samples at s + J d_k (model.hw.config.SAMPLE_OFFSETS), each with the footprint
    # of its cell (SAMPLE_FOOTPRINT: J's columns scaled); 1: the pixel's centre with its whole footprint
    samples: int = 1

    def __post_init__(self):
        self.Q = np.asarray(self.Q, dtype=np.float64).reshape(10)
        if self.clut is None:
            self.clut = np.zeros((1, 4), dtype=np.uint8)
        self.clut = np.asarray(self.clut, dtype=np.uint8)
        if self.clut.ndim != 2 or self.clut.shape[1] != 4:
            raise ValueError(f"clut: expected a uint8 array [N, 4], got shape {self.clut.shape}")
        if self.blend not in ("cubic", "linear"):
            raise ValueError(f"blend: expected 'cubic' or 'linear', got {self.blend!r}")
        if self.mode not in ("mod", "clamp"):
            raise ValueError(f"mode: expected 'mod' or 'clamp', got {self.mode!r}")
