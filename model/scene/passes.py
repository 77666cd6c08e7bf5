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
from model.hw.config import ROOT, cmap_family, freq_clamp
from model.hw.quantize import FormatError, parameter_changes, quantize_pixels, quantize_texture, quantized_texture

# STRICT's tolerance for rounding (docs/numerics.md, "Rounding a scene's parameters"): quantizing
# the texture parameters (Q, a, T, o) may move f by at most this many entries of the texture's
# colour table, at any of the pass's pixels (measured on QUANT_SAMPLE of them with the float
# reference). The pixels' own rounding (s, J) is reported beside it, not held to it: s18.10 moves
# f by up to 2.6 entries at wood's steepest pixels, where the box filter spans many entries.
STRICT_F_ENTRIES = 0.5
QUANT_SAMPLE = 4096
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
    info: dict  # terms_used, dropped_terms, texture, approximations and quantized (one line each), f_moves
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
    if freq_clamp(cfg):  # the fade in octaves of the footprint (model/hw/golden.py fc_weight)
        fc = (cfg.fc_knee / (1 << cfg.fc_log_frac), float(1 << cfg.fc_fade_log2))
    return replace(tex, terms=list(tex.terms[:cfg.noise_terms]), blend=cfg.blend,
                   noise_gradient=bool(cfg.noise_gradient), filter=bool(tex.filter and cfg.filter != "none"), fc=fc,
                   trapezoid=cmap_family(cfg) == "sat2", samples=cfg.samples)


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
        kind = {"mip": "a MIP map", "none": "point lookup", "sat_fc": "the box with frequency clamping",
                "sat2": "the trapezoid (exact for f linear across the pixel)",
                "sat2_fc": "the trapezoid with frequency clamping"}[cfg.filter]
        out.append(f"texture {name}: box filter replaced by {kind} (configuration {cfg.name}: filter = {cfg.filter})")
    if cfg.samples > 1:
        out.append(f"texture {name}: {cfg.samples} sub-pixel samples a pixel, each filtered with the footprint J / "
                   f"sqrt({cfg.samples}) (configuration {cfg.name}: samples = {cfg.samples})")
    return out


def _entries(tex, d, f0=None, f1=None) -> float:
    """The largest f difference in table entries (mod: the shorter way round; clamp: after clamping)."""
    n = len(tex.clut)
    if tex.mode == "clamp":
        d = np.clip(f1, 0, 1) - np.clip(f0, 0, 1)
    else:
        d = d - np.rint(d)
    return float(np.max(np.abs(d)) * n) if d.size else 0.0


def quantization_report(cfg, tex, ti, s, J, si, Jm, je, tname: str, pname: str) -> tuple[list[str], dict]:
    """What quantizing changed (one line each) and how far it moves f, in table entries:
    every parameter the formats changed with its largest change, the f move of the parameters
    together and of the pixels' s (float reference on up to QUANT_SAMPLE pixels), and the
    largest relative change of the filter width from the pixels' J. ({"params", "s"}: the f
    moves in entries; STRICT allows STRICT_F_ENTRIES.)"""
    from dataclasses import replace

    from model import reference

    lines = [f"texture {tname}: {c['param']} rounded to {c['format']}: largest change {c['change']:.3g} "
             f"({c['value']:.6g} -> {c['got']:.6g})" for c in parameter_changes(cfg, tex, ti)]
    moves = {"params": 0.0, "s": 0.0}
    if not len(s):
        return lines, moves
    idx = np.unique(np.linspace(0, len(s) - 1, min(len(s), QUANT_SAMPLE)).astype(np.int64))
    ss, sq = s[idx], np.asarray(si[idx], dtype=np.float64) / (1 << cfg.s_frac)
    kept = replace(tex, terms=list(tex.terms[:ti.k_used]))
    f0 = reference.texture_f(kept, ss, cfg.perm, cfg.hash_bits)
    n = len(tex.clut)
    if lines:
        fq = reference.texture_f(quantized_texture(cfg, tex, ti), ss, cfg.perm, cfg.hash_bits)
        moves["params"] = _entries(tex, fq - f0, f0, fq)
        lines.append(f"texture {tname}: the rounded parameters move f by up to {moves['params']:.3g} entries of its "
                     f"{n}-entry table (STRICT allows {STRICT_F_ENTRIES})")
    fs = reference.texture_f(kept, sq, cfg.perm, cfg.hash_bits)
    moves["s"] = _entries(tex, fs - f0, f0, fs)
    ds = float(np.max(np.abs(sq - ss)))
    if ds > 0:
        lines.append(f"pass {pname}: pixel s rounded to s{cfg.s_w}.{cfg.s_frac}: largest change {ds:.3g}, f moves by "
                     f"up to {moves['s']:.3g} entries at its steepest pixel (the input format's own rounding: reported, not "
                     "an error under STRICT)")
    Jq = np.asarray(Jm[idx], dtype=np.float64) * np.exp2(np.asarray(je[idx], dtype=np.float64))[:, None, None]
    Jf = J[idx]
    big = np.max(np.abs(Jf.reshape(len(idx), 6)), axis=1)
    rel = np.max(np.abs(Jq - Jf).reshape(len(idx), 6), axis=1) / np.where(big > 0, big, 1.0)
    if np.any(rel > 0):
        lines.append(f"pass {pname}: pixel J rounded to {cfg.j_w}-bit mantissas (a shared exponent, {cfg.je_w} bits): "
                     f"largest change {float(np.max(rel)):.3g} of the pixel's largest entry")
    return lines, moves


def strict_violations(pds) -> list[str]:
    """What STRICT rejects: every approximation of the configuration (terms, blend, gradient,
    filter), and rounding that moves f by more than STRICT_F_ENTRIES entries."""
    out = scene_approximations(pds, quantized=False)
    for pd in pds:
        mv = pd.info.get("f_moves", {})
        v = mv.get("params", 0.0)
        if v > STRICT_F_ENTRIES:
            line = (f"texture {pd.info['texture'] or pd.name}: rounding its parameters moves f by {v:.3g} entries "
                    f"(> {STRICT_F_ENTRIES}; `needs` gives the formats they need)")
            if line not in out:
                out.append(line)
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
        tname = ps.texture_name or ps.name
        lines, moves = quantization_report(cfg, ps.texture, ti, s, J, si, Jm, je, tname, ps.name)
        info = {**info, "texture": ps.texture_name, "approximations": approximations(cfg, ps.texture, tname),
                "quantized": lines, "f_moves": moves}
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


# the approximations that are the configuration's own choice of filter (sat_fc, mip, sat2, ...) or of
# sub-pixel samples: what the configuration is, measured by its promise, not a departure that rejects
# a scene from a corpus (explore.validate)
CHOICE_MARKERS = (" box filter replaced by ", " sub-pixel samples a pixel")


def scene_departures(pds) -> list[str]:
    """scene_approximations (unquantized) less the configuration's filter and sample choices
    (CHOICE_MARKERS): what rejects a scene from a corpus."""
    return [a for a in scene_approximations(pds, quantized=False) if not any(m in a for m in CHOICE_MARKERS)]


def scene_approximations(pds, quantized: bool = True) -> list[str]:
    """Every approximation of the passes' textures, each texture once, in pass order: what the
    configuration leaves out or replaces, then (quantized) what its formats round."""
    out = []
    for pd in pds:
        out += [a for a in pd.info["approximations"] if a not in out]
    if quantized:
        for pd in pds:
            out += [a for a in pd.info.get("quantized", []) if a not in out]
    return out
