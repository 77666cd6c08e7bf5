"""Image read, write and comparison, all through OpenImageIO."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import OpenImageIO as oiio


class ImageError(RuntimeError):
    pass


def _buf(pixels: np.ndarray, fmt: str) -> oiio.ImageBuf:
    pixels = np.ascontiguousarray(pixels)
    if pixels.ndim == 2:
        pixels = pixels[..., None]
    h, w, c = pixels.shape
    buf = oiio.ImageBuf(oiio.ImageSpec(w, h, c, fmt))
    if not buf.set_pixels(oiio.ROI(0, w, 0, h, 0, 1, 0, c), pixels):
        raise ImageError(f"set_pixels failed: {buf.geterror()}")
    return buf


def write_image(path, pixels: np.ndarray, attrs: dict | None = None) -> None:
    """Write uint8 (PNG) or float32 (EXR) pixels [H, W, C]; attributes go into the header.

    Written to a temporary name and renamed, so a failure never leaves half a file.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fmt = "uint8" if pixels.dtype == np.uint8 else "float"
    buf = _buf(pixels.astype(np.uint8 if fmt == "uint8" else np.float32), fmt)
    for k, v in (attrs or {}).items():
        buf.specmod().attribute(k, str(v))
    tmp = path.with_name(f".{path.stem}.{os.getpid()}{path.suffix}")
    if not buf.write(str(tmp)):
        raise ImageError(f"{path}: write failed: {buf.geterror()}")
    tmp.replace(path)


def write_figure(path, fig, attrs: dict | None = None) -> None:
    """A matplotlib figure as a PNG, written through OpenImageIO (write_image), then closed."""
    fig.canvas.draw()
    pixels = np.asarray(fig.canvas.buffer_rgba(), dtype=np.uint8)
    write_image(path, pixels, attrs)
    import matplotlib.pyplot as plt

    plt.close(fig)


def read_image(path) -> np.ndarray:
    buf = oiio.ImageBuf(str(path))
    if buf.has_error:
        raise ImageError(f"{path}: {buf.geterror()}")
    return buf.get_pixels(oiio.UINT8 if buf.spec().format == oiio.UINT8 else oiio.FLOAT)


def read_attrs(path) -> dict:
    buf = oiio.ImageBuf(str(path))
    spec = buf.spec()
    return {a.name: a.value for a in spec.extra_attribs}


def compare(a: np.ndarray, b: np.ndarray) -> dict:
    """PSNR (peak = 255), max and mean absolute error in LSB of two same-shaped pixel sets.

    a, b: [..., C] in 0..255 units (any dtype); compared as 1-row float images by
    ImageBufAlgo.compare.
    """
    a = np.asarray(a, dtype=np.float32).reshape(1, -1, a.shape[-1]) / 255.0
    b = np.asarray(b, dtype=np.float32).reshape(1, -1, b.shape[-1]) / 255.0
    if a.shape[1] == 0:
        return {"psnr_db": None, "max_abs_error_lsb": 0.0, "mean_abs_error_lsb": 0.0}
    r = oiio.ImageBufAlgo.compare(_buf(a, "float"), _buf(b, "float"), 1e-9, 1e-9)
    psnr = float(r.PSNR) if np.isfinite(r.PSNR) else None  # identical images: infinite PSNR
    return {"psnr_db": None if psnr is None else round(psnr, 3),
            "max_abs_error_lsb": round(float(r.maxerror) * 255.0, 4),
            "mean_abs_error_lsb": round(float(r.meanerror) * 255.0, 4)}


def contact_sheet(path, rows: list[list[tuple[str, np.ndarray]]], tile: int = 192, title: str = "") -> None:
    """A labelled grid of RGB(A) uint8 images: rows of (label, image) pairs."""
    label_h = 22
    top = 30 if title else 0
    ncol = max(len(r) for r in rows)
    W = ncol * (tile + 8) + 8
    H = top + len(rows) * (tile + label_h + 8) + 8
    sheet = _buf(np.full((H, W, 3), 32, np.uint8), "uint8")
    if title:
        oiio.ImageBufAlgo.render_text(sheet, 8, 22, title, 18, "", (1, 1, 1))
    for i, row in enumerate(rows):
        for j, (label, img) in enumerate(row):
            if img is None:
                continue
            img = np.asarray(img)
            if img.shape[-1] == 4:  # composite alpha over mid grey for display
                a = img[..., 3:4] / 255.0
                img = (img[..., :3] * a + 64 * (1 - a)).astype(np.uint8)
            src = _buf(img[..., :3].astype(np.uint8), "uint8")
            h, w = img.shape[:2]
            scale = tile / max(h, w)
            dst = oiio.ImageBuf(oiio.ImageSpec(max(1, round(w * scale)), max(1, round(h * scale)), 3, "uint8"))
            oiio.ImageBufAlgo.resize(dst, src)
            x0 = 8 + j * (tile + 8)
            y0 = top + 8 + i * (tile + label_h + 8)
            oiio.ImageBufAlgo.paste(sheet, x0, y0 + label_h, 0, 0, dst)
            oiio.ImageBufAlgo.render_text(sheet, x0, y0 + 16, label, 14, "", (0.9, 0.9, 0.9))
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    if not sheet.write(str(path)):
        raise ImageError(f"{path}: write failed: {sheet.geterror()}")
