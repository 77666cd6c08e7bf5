"""The texture_pipeline register map and pixel stream formats, in Python.

The twin of the header of rtl/texture_pipeline.v: what the parameter write port
expects (`write_sequence`) and how a pixel is packed into s_axis_tdata
(`pack_pixels`) and the colour is unpacked from m_axis_tdata (`unpack_rgba`).
All widths come from the configuration (model/hw/config.py).

Register map (word addresses, 32-bit data; signed values two's complement in the
LSBs of the word):

    0x0000            CTRL: [0] mode (0 mod, 1 clamp), [1] filter_en,
                      [8 +: n_log2_w] n_log2
    0x0010 + i        quadric coefficient i = 0..9 (A..J)
    0x0100 + 16*k     noise term k < K:  +0 a_k; +1+3*j+m T_k[j][m]; +10+j o_k[j]
    0x1000 + n        clut[n]  RGBA8, R at [7:0]
    0x2000 + 4*n + ch csat[n] channel ch; channels 0..2 are staged, channel 3 commits
                      (entries in ascending order: the last one, N - 1, is the whole-table sum
                      the colour map keeps)
    0x3000 + m        mip[m]   RGBA8 (level l at offset 2N - (2N >> l))

Pixel word: {je, Jm, s} with s at the LSBs:

    [0 : 3*s_w)                   s, t, r (element e at e*s_w)
    [3*s_w : 3*s_w + 6*j_w)       Jm[k][col] at element 2*k + col
    [3*s_w + 6*j_w : pix_w)       je
"""
from __future__ import annotations

import numpy as np

from model.hw.config import Config
from model.hw.golden import MODE_CLAMP, MODE_MOD, TexInt

ADDR_CTRL = 0x0000
ADDR_Q = 0x0010
ADDR_TERM = 0x0100
TERM_STRIDE = 16
TERM_A, TERM_T, TERM_O = 0, 1, 10
ADDR_CLUT = 0x1000
ADDR_CSAT = 0x2000
ADDR_MIP = 0x3000
CTRL_MODE_BIT, CTRL_FILTER_BIT, CTRL_NLOG2_LSB = 0, 1, 8


class RegmapError(ValueError):
    """A parameter that does not fit its register (one-line message)."""


def pix_width(cfg: Config) -> int:
    """Bits of one s_axis_tdata word."""
    return 3 * cfg.s_w + 6 * cfg.j_w + cfg.je_w


def _fit(name: str, v, w: int, signed: bool) -> int:
    v = int(v)
    lo, hi = (-(1 << (w - 1)), (1 << (w - 1)) - 1) if signed else (0, (1 << w) - 1)
    if not lo <= v <= hi:
        raise RegmapError(f"{name} = {v} does not fit {'s' if signed else 'u'}{w} [{lo}, {hi}]")
    return v & 0xFFFFFFFF


def _rgba_word(px) -> int:
    return sum((int(px[c]) & 0xFF) << (8 * c) for c in range(4))


def write_sequence(cfg: Config, tex: TexInt) -> list[tuple[int, int]]:
    """The (address, data) writes that load `tex` into texture_pipeline.

    Every parameter register is written (noise terms beyond len(tex.a) get zeros),
    so a pass never depends on the previous one. The colour tables written are the
    ones the configuration's filter reads: clut always, csat for "sat", mip for "mip".
    """
    if cfg.d["o_w"] > 32 or cfg.q_w > 32 or cfg.a_w > 32 or cfg.t_w > 32 or cfg.csat_w > 32:
        raise RegmapError(f"{cfg.name}: a parameter wider than 32 bits does not fit one register word")
    n_log2 = int(tex.n_log2)
    if not 0 <= n_log2 <= cfg.n_log2_max:
        raise RegmapError(f"n_log2 = {n_log2} outside 0..{cfg.n_log2_max}")
    if tex.mode not in (MODE_MOD, MODE_CLAMP):
        raise RegmapError(f"mode = {tex.mode!r}")
    n = 1 << n_log2
    K = cfg.noise_terms
    w: list[tuple[int, int]] = []
    ctrl = (int(tex.mode) << CTRL_MODE_BIT) | (int(bool(tex.filter)) << CTRL_FILTER_BIT) | (n_log2 << CTRL_NLOG2_LSB)
    w.append((ADDR_CTRL, ctrl))
    Q = np.asarray(tex.Q, dtype=np.int64).reshape(10)
    for i in range(10):
        w.append((ADDR_Q + i, _fit(f"Q[{i}]", Q[i], cfg.q_w, True)))
    a = np.asarray(tex.a, dtype=np.int64).reshape(-1)
    T = np.asarray(tex.T, dtype=np.int64).reshape(-1, 3, 3)
    o = np.asarray(tex.o, dtype=np.int64).reshape(-1, 3)
    if np.any(a[K:] != 0):
        raise RegmapError(f"texture has {int(np.count_nonzero(a[K:]))} non-zero terms beyond K = {K}")
    for k in range(K):
        base = ADDR_TERM + TERM_STRIDE * k
        have = k < len(a)
        w.append((base + TERM_A, _fit(f"a[{k}]", a[k] if have else 0, cfg.a_w, True)))
        for j in range(3):
            for m in range(3):
                w.append((base + TERM_T + 3 * j + m, _fit(f"T[{k}][{j}][{m}]", T[k, j, m] if have else 0, cfg.t_w, True)))
        for j in range(3):
            w.append((base + TERM_O + j, _fit(f"o[{k}][{j}]", o[k, j] if have else 0, cfg.d["o_w"], False)))
    clut = np.asarray(tex.clut, dtype=np.int64)
    if clut.shape != (n, 4):
        raise RegmapError(f"clut shape {clut.shape}, expected ({n}, 4) for n_log2 = {n_log2}")
    if np.any((clut < 0) | (clut > 255)):
        raise RegmapError("clut entries must be 0..255")
    for i in range(n):
        w.append((ADDR_CLUT + i, _rgba_word(clut[i])))
    if cfg.filter == "sat":
        csat = np.asarray(tex.csat, dtype=np.int64)
        for i in range(n):
            for c in range(4):
                w.append((ADDR_CSAT + 4 * i + c, _fit(f"csat[{i}][{c}]", csat[i, c], cfg.csat_w, False)))
    elif cfg.filter == "mip":
        mip = np.asarray(tex.mip, dtype=np.int64)
        for i in range(2 * n - 1):
            w.append((ADDR_MIP + i, _rgba_word(mip[i])))
    return w


def pack_pixels(cfg: Config, s, Jm, je) -> list[int]:
    """s_axis_tdata words (Python ints, pix_width(cfg) bits) for pixels s [P, 3], Jm [P, 3, 2], je [P].

    Each field is range-checked against its format (RegmapError otherwise).
    """
    s = np.asarray(s, dtype=np.int64).reshape(-1, 3)
    P = s.shape[0]
    Jm = np.asarray(Jm, dtype=np.int64).reshape(P, 6)  # element 2*k + col = Jm[k][col]
    je = np.asarray(je, dtype=np.int64).reshape(P)
    for name, x, wd in (("s", s, cfg.s_w), ("Jm", Jm, cfg.j_w), ("je", je, cfg.je_w)):
        lo, hi = -(1 << (wd - 1)), (1 << (wd - 1)) - 1
        if x.size and (x.min() < lo or x.max() > hi):
            raise RegmapError(f"pixel {name} outside s{wd} [{lo}, {hi}]")
    # words are wider than 64 bits: Python ints, built one field column at a time
    fields = [(s[:, e], cfg.s_w) for e in range(3)] + [(Jm[:, e], cfg.j_w) for e in range(6)] + [(je, cfg.je_w)]
    words = [0] * P
    shift = 0
    for col, wd in fields:
        m = (1 << wd) - 1
        vals = (col & m).tolist()  # two's complement in wd bits (numpy & on int64)
        if shift == 0:
            words = vals
        else:
            words = [wv | (v << shift) for wv, v in zip(words, vals)]
        shift += wd
    return words


def unpack_pixels(cfg: Config, words):
    """Inverse of pack_pixels: (s [P, 3], Jm [P, 3, 2], je [P]) int64."""
    words = [int(x) for x in words]
    out = []
    shift = 0
    for count, wd in ((3, cfg.s_w), (6, cfg.j_w), (1, cfg.je_w)):
        m = (1 << wd) - 1
        cols = []
        for _ in range(count):
            v = np.array([(x >> shift) & m for x in words], dtype=np.int64)
            cols.append(np.where(v >> (wd - 1), v - (1 << wd), v))
            shift += wd
        out.append(np.stack(cols, axis=-1) if cols else np.zeros((len(words), 0), dtype=np.int64))
    return out[0], out[1].reshape(-1, 3, 2), out[2][:, 0]


def unpack_rgba(words) -> np.ndarray:
    """m_axis_tdata words -> uint8 [..., 4] (R, G, B, A)."""
    w = np.asarray(words, dtype=np.uint32)
    return np.stack([(w >> (8 * c)) & 0xFF for c in range(4)], axis=-1).astype(np.uint8)


def pixels_hex(cfg: Config, words) -> str:
    """$readmemh text of pixel words (one per line, fixed width)."""
    nd = (pix_width(cfg) + 3) // 4
    return "".join(f"{x:0{nd}x}\n" for x in words)


def writes_hex(writes) -> str:
    """$readmemh text of (address, data) writes: {addr[15:0], data[31:0]}, 12 hex digits a line."""
    return "".join(f"{a & 0xFFFF:04x}{d & 0xFFFFFFFF:08x}\n" for a, d in writes)
