"""Float parameters and pixels to the hardware's fixed-point formats.

Rounding is to nearest (ties to even, numpy rint). A value that does not fit its
format raises FormatError naming the parameter, its value and the format's range;
nothing is wrapped or saturated silently. The one deliberate reduction is
documented and reported: a configuration with fewer noise terms than a texture
keeps the texture's first K terms (scenes list them most significant first), as
the paper's 100k-gate model does (Fig. 11); `dropped_terms` says how many.
"""
from __future__ import annotations

import numpy as np

from model.hw.config import Config
from model.hw.golden import MODE_CLAMP, MODE_MOD, TexInt
from model.texture import QUADRIC_NAMES, TextureParams


class FormatError(ValueError):
    """A value that does not fit its fixed-point format (one-line message)."""


def fmt_name(w: int, frac: int, signed: bool = True) -> str:
    return f"{'s' if signed else 'u'}{w}.{frac}"


def to_fixed(name: str, value, w: int, frac: int, signed: bool = True):
    """round(value * 2^frac) as int64, or FormatError if any element does not fit."""
    v = np.asarray(value, dtype=np.float64)
    if not np.all(np.isfinite(v)):
        raise FormatError(f"{name}: non-finite value")
    x = np.rint(v * 2.0 ** frac)
    lo, hi = (-(1 << (w - 1)), (1 << (w - 1)) - 1) if signed else (0, (1 << w) - 1)
    bad = (x < lo) | (x > hi)
    if np.any(bad):
        idx = np.unravel_index(np.argmax(bad), bad.shape) if v.ndim else ()
        where = f"[{', '.join(str(int(i)) for i in idx)}]" if idx else ""
        raise FormatError(
            f"{name}{where} = {float(v[idx]):.6g} does not fit {fmt_name(w, frac, signed)} "
            f"(range [{lo / 2.0 ** frac:.10g}, {hi / 2.0 ** frac:.10g}])"
        )
    return x.astype(np.int64)


def block_exponent(name: str, value, w: int, frac: int, exp_w: int) -> int:
    """The exponent e in [0, 2^exp_w - 1] of a block-floating-point value (formats.t_exp_w,
    a_exp_w): the least e with every |round(value 2^(frac - e))| <= 2^(w-1) - 1, so the largest
    entry keeps the most bits (0 when exp_w = 0, or all of value fits at e = 0). FormatError
    when no exponent fits."""
    v = np.abs(np.asarray(value, dtype=np.float64))
    if not np.all(np.isfinite(v)):
        raise FormatError(f"{name}: non-finite value")
    lim = (1 << (w - 1)) - 1
    emax = (1 << exp_w) - 1
    for e in range(emax + 1):
        if np.max(np.rint(v * 2.0 ** (frac - e)), initial=0.0) <= lim:
            return e
    if exp_w == 0:
        return 0  # fixed point: to_fixed names the value that does not fit
    k = np.unravel_index(np.argmax(v), v.shape) if v.ndim else ()
    where = f"[{', '.join(str(int(i)) for i in k)}]" if k else ""
    raise FormatError(f"{name}{where} = {float(np.asarray(value, dtype=np.float64)[k]):.6g} does not fit "
                      f"{fmt_name(w, frac)} x 2^[0..{emax}] (|value| <= {lim * 2.0 ** (emax - frac):.10g})")


def quantize_texture(cfg: Config, tex: TextureParams) -> tuple[TexInt, dict]:
    """TextureParams -> (TexInt, info). info: terms_used, dropped_terms."""
    Q = np.array(
        [int(to_fixed(f"quadric.{n}", tex.Q[i], cfg.q_w, cfg.q_frac)) for i, n in enumerate(QUADRIC_NAMES)],
        dtype=np.int64,
    )
    if cfg.quadric == "diagonal":
        for i in (1, 2, 5):  # B, C, F: the cross terms
            if tex.Q[i] != 0:
                raise FormatError(
                    f"quadric.{QUADRIC_NAMES[i]} = {float(tex.Q[i]):.6g}: configuration {cfg.name} "
                    f"(quadric diagonal) needs B = C = F = 0"
                )
    n_entries = tex.clut.shape[0]
    n_log2 = int(n_entries).bit_length() - 1
    if n_entries < 1 or (1 << n_log2) != n_entries or n_log2 > cfg.n_log2_max:
        raise FormatError(
            f"clut: {n_entries} entries; expected a power of two from 1 to {1 << cfg.n_log2_max}"
        )
    K = cfg.noise_terms
    used = tex.terms[:K]
    a = np.zeros(K, dtype=np.int64)
    T = np.zeros((K, 3, 3), dtype=np.int64)
    o = np.zeros((K, 3), dtype=np.int64)
    period = float(1 << cfg.hash_bits)
    te = np.zeros(K, dtype=np.int64)
    ae = np.zeros(K, dtype=np.int64)
    for i, term in enumerate(used):
        ae[i] = block_exponent(f"noise[{i}].a", term.a, cfg.a_w, cfg.a_frac, cfg.a_exp_w)
        a[i] = to_fixed(f"noise[{i}].a", term.a, cfg.a_w, cfg.a_frac - int(ae[i]))
        if cfg.amplitude == "pow2":
            ia = abs(int(a[i]))
            if ia & (ia - 1) or ia / (1 << cfg.a_frac) != abs(term.a):
                raise FormatError(
                    f"noise[{i}].a = {term.a:.6g}: configuration {cfg.name} (amplitude pow2) "
                    f"needs 0 or +-2^k in {fmt_name(cfg.a_w, cfg.a_frac)}"
                )
        te[i] = block_exponent(f"noise[{i}].T", term.T, cfg.t_w, cfg.t_frac, cfg.t_exp_w)
        T[i] = to_fixed(f"noise[{i}].T", term.T, cfg.t_w, cfg.t_frac - int(te[i]))
        if cfg.transform == "pow2":
            _check_pow2(cfg, i, term.T, T[i])
        # the lattice is periodic with period 2^hash_bits: the offset is a phase, taken mod the period
        o[i] = to_fixed(f"noise[{i}].o", np.mod(term.o, period), cfg.d["o_w"] + 1, cfg.p_frac, signed=False)
        o[i] &= (1 << cfg.d["o_w"]) - 1
    tint = TexInt(
        Q=Q,
        a=a,
        T=T,
        o=o,
        mode=MODE_MOD if tex.mode == "mod" else MODE_CLAMP,
        n_log2=n_log2,
        filter=bool(tex.filter),
        clut=np.asarray(tex.clut, dtype=np.int64),
        k_used=len(used),
        te=te,
        ae=ae,
    )
    return tint, {"terms_used": len(used), "dropped_terms": max(0, len(tex.terms) - K)}


def parameter_changes(cfg: Config, tex: TextureParams, ti: TexInt) -> list[dict]:
    """Every texture parameter (quadric, noise[i].a, .T, .o) that quantizing changed:
    [{"param", "format", "change": largest |quantized - value|, "value", "got"}] (the entry with
    the largest change). The offsets are compared as phases (mod the lattice period)."""
    out = []

    def add(name, v, q, w, frac, signed=True):
        v = np.asarray(v, dtype=np.float64)
        q = np.asarray(q, dtype=np.float64) / 2.0 ** frac
        d = np.abs(q - v)
        if np.any(d > 0):
            k = np.unravel_index(np.argmax(d), d.shape) if d.ndim else ()
            out.append({"param": name, "format": fmt_name(w, frac, signed), "change": float(d[k]),
                        "value": float(v[k]), "got": float(q[k])})

    add("quadric", tex.Q, ti.Q, cfg.q_w, cfg.q_frac)
    period = float(1 << cfg.hash_bits)
    for i, term in enumerate(tex.terms[:ti.k_used]):
        add(f"noise[{i}].a", term.a, ti.a[i], cfg.a_w, cfg.a_frac - int(ti.ae[i]))
        add(f"noise[{i}].T", term.T, ti.T[i], cfg.t_w, cfg.t_frac - int(ti.te[i]))
        add(f"noise[{i}].o", np.mod(term.o, period), ti.o[i], cfg.d["o_w"], cfg.p_frac, signed=False)
    return out


def quantized_texture(cfg: Config, tex: TextureParams, ti: TexInt) -> TextureParams:
    """The float texture with the quantized parameters (what the hardware holds), its first
    ti.k_used terms."""
    from dataclasses import replace

    from model.texture import NoiseTerm

    terms = [NoiseTerm(a=float(ti.a[i]) * 2.0 ** (int(ti.ae[i]) - cfg.a_frac),
                       T=ti.T[i] * 2.0 ** (int(ti.te[i]) - cfg.t_frac),
                       o=ti.o[i] / float(1 << cfg.p_frac)) for i in range(ti.k_used)]
    return replace(tex, Q=ti.Q / float(1 << cfg.q_frac), terms=terms)


def _check_pow2(cfg: Config, i: int, Tf, Ti) -> None:
    """pow2 transform: T diagonal, each entry 0 or 2^k exactly representable (a shift)."""
    Tf = np.asarray(Tf, dtype=np.float64)
    for r in range(3):
        for c in range(3):
            v = Tf[r, c]
            if r != c and v != 0:
                raise FormatError(
                    f"noise[{i}].T[{r},{c}] = {v:.6g}: configuration {cfg.name} (transform pow2) needs a diagonal T"
                )
            if r == c and v != 0:
                iv = int(Ti[r, c])
                if iv <= 0 or iv & (iv - 1) or iv / (1 << cfg.t_frac) != v:
                    raise FormatError(
                        f"noise[{i}].T[{r},{r}] = {v:.6g}: configuration {cfg.name} (transform pow2) "
                        f"needs 0 or a power of two in {fmt_name(cfg.t_w, cfg.t_frac)}"
                    )


def quantize_pixels(cfg: Config, s, J):
    """Pixels to the input stream formats: s [..., 3] and J [..., 3, 2] floats ->
    (s int64 s{s_w}.{s_frac}, Jm int64 [..., 3, 2] s{j_w}.0, je int64 [...]).

    The Jacobian is a block-floating-point value per pixel: je is the smallest
    exponent with every |round(J / 2^je)| <= 2^(j_w-1) - 1, floored at the least
    exponent je_min (tiny Jacobians lose their low bits there, never wrap).
    """
    s_i = to_fixed("pixel s", s, cfg.s_w, cfg.s_frac)
    J = np.asarray(J, dtype=np.float64)
    if not np.all(np.isfinite(J)):
        raise FormatError("pixel J: non-finite value")
    m = np.max(np.abs(J.reshape(J.shape[:-2] + (6,))), axis=-1)
    lim = (1 << (cfg.j_w - 1)) - 1
    je_min, je_max = cfg.d["je_min"], cfg.d["je_max"]
    with np.errstate(divide="ignore"):
        je = np.ceil(np.log2(np.where(m > 0, m, 1.0) / lim)).astype(np.int64)
    je = np.where(m > 0, je, je_min)
    je = np.maximum(je, je_min)
    for _ in range(2):  # log2 rounding: settle on the least exponent that fits
        Jm = np.rint(J / np.exp2(je)[..., None, None])
        too_big = np.max(np.abs(Jm.reshape(Jm.shape[:-2] + (6,))), axis=-1) > lim
        je = np.where(too_big, je + 1, je)
    fits_lower = (je > je_min) & (np.max(np.abs(np.rint(J / np.exp2(je - 1)[..., None, None])).reshape(J.shape[:-2] + (6,)), axis=-1) <= lim)
    je = np.where(fits_lower, je - 1, je)
    if np.any(je > je_max):
        idx = np.unravel_index(np.argmax(je), je.shape)
        raise FormatError(f"pixel J{list(idx)}: |J| = {m[idx]:.6g} needs exponent {je[idx]} > {je_max} (je_w = {cfg.je_w})")
    Jm = np.rint(J / np.exp2(je)[..., None, None]).astype(np.int64)
    return s_i, Jm, je.astype(np.int64)


def float_of(x, frac: int):
    return np.asarray(x, dtype=np.float64) / (1 << frac)
