"""Scene passes for the hardware: the library the render CLI (app.render) and the
RTL frame runner (sim.frame) share.

The paper's scenes (SCENES, scenes/<name>.toml), the frame size of a scene at a given width,
each front-end pass quantized for the hardware (prepare_passes), and 'over' compositing of
the passes' colours (composite, to8).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from model.hw import golden
from model.hw.config import ROOT
from model.hw.quantize import FormatError, quantize_pixels, quantize_texture

SCENE_DIR = ROOT / "scenes"
SCENES = ("wood", "marble", "seascape", "fire", "planet", "moonrise", "zone_plate", "torus")


@dataclass
class PassData:
    """One texture pass, quantized for the hardware (masked pixels only, row-major)."""

    name: str
    tex: object  # TextureParams (float)
    mask: np.ndarray  # bool [H, W]
    s: np.ndarray  # float [P, 3]
    J: np.ndarray  # float [P, 3, 2]
    ti: golden.TexInt
    info: dict  # terms_used, dropped_terms, texture, approximations (one line each)
    si: np.ndarray
    Jm: np.ndarray
    je: np.ndarray


def scene_path(name: str) -> Path:
    """A scene name's file (scenes/<name>.toml), or the path itself (model.cli.resolve_scene
    checks a command's --scene)."""
    p = Path(name)
    return p if p.suffix == ".toml" else SCENE_DIR / f"{name}.toml"


def configured_texture(cfg, tex):
    """The texture as configuration cfg computes it: its first cfg.noise_terms terms, the
    configuration's blend and noise-gradient choice, and no box filter where cfg has none."""
    from dataclasses import replace

    fc = None
    if cfg.filter == "sat_fc":  # the fade in octaves of the footprint (model/hw/golden.py fc_weight)
        fc = (cfg.fc_knee / (1 << cfg.fc_log_frac), float(1 << cfg.fc_fade_log2))
    return replace(tex, terms=list(tex.terms[:cfg.noise_terms]), blend=cfg.blend,
                   noise_gradient=bool(cfg.noise_gradient), filter=bool(tex.filter and cfg.filter != "none"), fc=fc)


def approximations(cfg, tex, name: str) -> list[str]:
    """Every way configuration cfg departs from the scene's texture `name` (one line each):
    noise terms dropped, blend replaced, noise gradient omitted or added, filter replaced."""
    out = []
    k = len(tex.terms)
    if k > cfg.noise_terms:
        out.append(f"texture {name}: noise terms {cfg.noise_terms}..{k - 1} dropped "
                   f"(configuration {cfg.name} keeps {cfg.noise_terms} of {k})")
    if k and tex.blend != cfg.blend:  # the blend only matters with noise
        out.append(f"texture {name}: blend {tex.blend} replaced by {cfg.blend} (configuration {cfg.name})")
    if min(k, cfg.noise_terms) and tex.noise_gradient != cfg.noise_gradient and tex.filter:
        out.append(f"texture {name}: noise gradient {'omitted from' if tex.noise_gradient else 'added to'} "
                   f"the filter width (configuration {cfg.name}: noise_gradient = {str(cfg.noise_gradient).lower()})")
    if tex.filter and cfg.filter != "sat":
        kind = {"mip": "a MIP map", "none": "point lookup", "sat_fc": "the box with frequency clamping"}[cfg.filter]
        out.append(f"texture {name}: box filter replaced by {kind} (configuration {cfg.name}: filter = {cfg.filter})")
    return out


def prepare_passes(cfg, passes) -> list[PassData]:
    """Quantize every pass; a value that does not fit names the pass and the value."""
    out = []
    for ps in passes:
        try:
            ti, info = quantize_texture(cfg, ps.texture)
            s = ps.s[ps.mask]
            J = ps.J[ps.mask]
            si, Jm, je = quantize_pixels(cfg, s, J)
        except FormatError as e:
            raise FormatError(f"pass '{ps.name}': {e}") from None
        info = {**info, "texture": ps.texture_name,
                "approximations": approximations(cfg, ps.texture, ps.texture_name or ps.name)}
        out.append(PassData(ps.name, ps.texture, ps.mask, s, J, ti, info, si, Jm, je))
    return out


def composite(layers, shape, background) -> np.ndarray:
    """'over' compositing, layers front to back: [(mask [H,W], rgba [P,4] 0..255 float)].

    Straight (non-premultiplied) alpha from the colour tables. Returns float RGBA
    [H, W, 4] in 0..255 over the opaque-or-not background.
    """
    H, W = shape
    acc = np.zeros((H, W, 3))
    acc_a = np.zeros((H, W))
    for mask, rgba in layers:
        rgba = np.asarray(rgba, dtype=np.float64)
        a = rgba[:, 3] / 255.0
        t = 1.0 - acc_a[mask]
        acc[mask] += (t * a)[:, None] * rgba[:, :3]
        acc_a[mask] += t * a
    bg = np.asarray(background, dtype=np.float64)
    ba = bg[3] / 255.0
    t = 1.0 - acc_a
    out = np.empty((H, W, 4))
    out[..., :3] = acc + (t * ba)[..., None] * bg[:3]
    out[..., 3] = 255.0 * (acc_a + t * ba)
    return out


def to8(img: np.ndarray) -> np.ndarray:
    return np.clip(np.rint(img), 0, 255).astype(np.uint8)


def frame_size(scene, size: int) -> tuple[int, int]:
    w0, h0 = scene.width, scene.height
    return size, max(1, round(size * h0 / w0))


def scene_approximations(pds) -> list[str]:
    """Every approximation of the passes' textures, each texture once, in pass order."""
    out = []
    for pd in pds:
        out += [a for a in pd.info["approximations"] if a not in out]
    return out
