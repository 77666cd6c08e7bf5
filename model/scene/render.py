"""Model-only rendering of a scene: float reference, golden model, ground truth, reports.

`python -m model.scene.render --scene zone_plate --config full --size 256` (make render)
writes out/render/<scene>/<config>-<size>/: reference.exr (float reference, with
provenance attributes), reference.png, golden.png, unfiltered.png, truth.png
(8x8 supersampled unfiltered float reference, box-averaged), filter_width.png
(Fig. 9c: w from 1 entry, black, to N entries, white) and report.json.
`--all` renders every scene for both configurations and writes the contact sheet
docs/images/renders.png.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from model import reference
from model.hw import golden
from model.hw.config import CONFIG_NAMES, ROOT, load_config
from model.imageio import compare, contact_sheet, write_image
from model.scene.cli import (Parser, UserError, check_config, check_range, memory_available, resolve_scene,
                             run_main, staged)
from model.scene.passes import SCENES, composite, configured_texture, frame_size, prepare_passes, scene_approximations, to8


def git_describe() -> str:
    try:
        return subprocess.run(["git", "-C", str(ROOT), "describe", "--always", "--dirty"], capture_output=True,
                              text=True, timeout=10).stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


# memory of a render, measured (moonrise, full): ~1.1 KB a pixel, ~0.7 KB a truth sample
_BYTES_BASE, _BYTES_PIXEL, _BYTES_SAMPLE = 150 << 20, 1100, 700


def memory_needed(W: int, H: int, truth: bool, truth_ss: int) -> int:
    return _BYTES_BASE + _BYTES_PIXEL * W * H + (_BYTES_SAMPLE * W * H * truth_ss**2 if truth else 0)


def render(scene_name: str, config_name: str, size: int, truth: bool = True, truth_ss: int = 8,
           out_root: Path | None = None, progress: bool = True, strict: bool = False) -> dict:
    """Render one scene (a name or a .toml path) for one configuration into
    <out_root>/<scene>/<config>-<size>/ (staged: only a completed render is moved into place).
    strict: any approximation the configuration makes to the scene is an error (UserError)."""
    from model.scene.frontend import render_passes
    from model.scene.scene import load_scene

    t0 = time.perf_counter()
    check_range("--size", size, 1, 4096)
    check_range("--truth-ss", truth_ss, 1, 16)
    check_config(config_name)
    scene_name, path = resolve_scene(scene_name)
    target = (out_root or ROOT / "out" / "render") / scene_name / f"{config_name}-{size}"
    command = f"make render SCENE={scene_name} CONFIG={config_name} SIZE={size}"
    with staged(target, command) as out:
        cfg = load_config(config_name)
        scene = load_scene(path)
        W, H = frame_size(scene, size)
        need, avail = memory_needed(W, H, truth, truth_ss), memory_available()
        if avail is not None and need > avail:
            raise UserError(f"--size {size}: a {W}x{H} render" + (f" with {truth_ss}x{truth_ss} truth" if truth else "")
                            + f" needs about {need / 2**30:.1f} GiB of memory, {avail / 2**30:.1f} GiB available "
                            "(a smaller --size or --truth-ss, or --no-truth)")
        passes = render_passes(scene, W, H)
        pds = prepare_passes(cfg, passes)
        approx = scene_approximations(pds)
        if strict and approx:
            raise UserError(f"--strict: {approx[0]}" + (f" (and {len(approx) - 1} more)" if len(approx) > 1 else ""))
        rep = _render_into(out, scene_name, config_name, size, cfg, scene, W, H, pds, truth, truth_ss, progress)
        rep["approximations"] = approx
        rep["seconds"] = round(time.perf_counter() - t0, 2)
        (out / "report.json").write_text(json.dumps(rep, indent=2) + "\n")
    return rep


def _render_into(out, scene_name, config_name, size, cfg, scene, W, H, pds, truth, truth_ss, progress) -> dict:
    bar = _bar(progress, total=len(pds) * 3 + (1 if truth else 0), desc=f"{scene_name} {config_name} {W}x{H}")
    gold, unf, ref, cref, widths = [], [], [], [], np.zeros((H, W))
    for pd in pds:
        st = golden.texture_stages(cfg, pd.ti, pd.si, pd.Jm, pd.je)
        gold.append((pd.mask, st["rgba"]))
        n = 1 << pd.ti.n_log2
        widths[pd.mask] = np.maximum(widths[pd.mask], st["w"] / float(1 << cfg.f_frac) / n)
        bar.update()
        ti_off = golden.TexInt(**{**pd.ti.__dict__, "filter": False})
        unf.append((pd.mask, golden.texture_pipeline(cfg, ti_off, pd.si, pd.Jm, pd.je)))
        bar.update()
        r = reference.shade(pd.tex, pd.s, pd.J, cfg.perm, cfg.hash_bits)
        ref.append((pd.mask, r))
        # the reference of the texture as the configuration computes it (its approximations
        # made): the golden model's distance from it is the arithmetic error alone
        cref.append((pd.mask, reference.shade(configured_texture(cfg, pd.tex), pd.s, pd.J, cfg.perm, cfg.hash_bits)
                     if pd.info["approximations"] else r))
        bar.update()
    bg = scene.background
    img_gold = composite(gold, (H, W), bg)
    img_unf = composite(unf, (H, W), bg)
    img_ref = composite(ref, (H, W), bg)
    img_cref = composite(cref, (H, W), bg)
    textured = np.zeros((H, W), bool)
    for pd in pds:
        textured |= pd.mask
    img_truth = None
    if truth:
        img_truth = supersampled_truth(scene, cfg, W, H, truth_ss)
        bar.update()
    bar.close()
    prov = {"scene": scene_name, "config": config_name, "size": f"{W}x{H}", "git": git_describe(),
            "command": f"make render SCENE={scene_name} CONFIG={config_name} SIZE={size}",
            "generator": "model/reference.py (float64 reference)"}
    write_image(out / "reference.exr", (img_ref / 255.0).astype(np.float32), {"tex:" + k: v for k, v in prov.items()})
    write_image(out / "reference.png", to8(img_ref))
    write_image(out / "golden.png", to8(img_gold))
    write_image(out / "unfiltered.png", to8(img_unf))
    # Fig. 9c: filter width from 1 entry (black) to N entries (white), log-free linear grey as in the paper
    n_max = max((1 << pd.ti.n_log2) for pd in pds) if pds else 1
    grey = np.clip((widths * n_max - 1) / max(n_max - 1, 1), 0, 1) * 255
    write_image(out / "filter_width.png", to8(np.where(textured, grey, 0)))
    rep = {
        "status": "ok", "scene": scene_name, "config": config_name, "width": W, "height": H,
        "pixels_textured": int(textured.sum()),
        "passes": [{"name": pd.name, "pixels": int(pd.mask.sum()), **pd.info} for pd in pds],
    }
    cg = compare(img_gold[textured], img_ref[textured])
    rep["psnr_golden_vs_reference_db"] = cg["psnr_db"]
    rep["max_abs_error_lsb"] = cg["max_abs_error_lsb"]
    rep["mean_abs_error_lsb"] = cg["mean_abs_error_lsb"]
    cc = compare(img_gold[textured], img_cref[textured])
    rep["psnr_golden_vs_configured_reference_db"] = cc["psnr_db"]
    rep["max_abs_error_vs_configured_reference_lsb"] = cc["max_abs_error_lsb"]
    if img_truth is not None:
        write_image(out / "truth.png", to8(img_truth))
        rep["psnr_filtered_vs_truth_db"] = compare(img_gold[textured], img_truth[textured])["psnr_db"]
        rep["psnr_unfiltered_vs_truth_db"] = compare(img_unf[textured], img_truth[textured])["psnr_db"]
        rep["psnr_reference_vs_truth_db"] = compare(img_ref[textured], img_truth[textured])["psnr_db"]
        rep["truth_supersampling"] = f"{truth_ss}x{truth_ss}"
    else:
        rep["psnr_filtered_vs_truth_db"] = rep["psnr_unfiltered_vs_truth_db"] = None
    return rep


def supersampled_truth(scene, cfg, W, H, ss: int) -> np.ndarray:
    """Ground truth: the unfiltered float reference at ss x ss samples per pixel, box-averaged.

    Rendered in horizontal bands to bound memory; each band is a full-width
    render of ss*W x ss*H restricted to its rows by the front end's row window.
    """
    from model.scene.frontend import render_passes

    big = render_passes(scene, W * ss, H * ss)
    layers = []
    for ps in big:
        s = ps.s[ps.mask]
        rgba = reference.unfiltered_lookup(ps.texture.clut, reference.texture_f(ps.texture, s, cfg.perm, cfg.hash_bits),
                                           ps.texture.mode)
        layers.append((ps.mask, rgba))
    img = composite(layers, (H * ss, W * ss), scene.background)
    return img.reshape(H, ss, W, ss, 4).mean(axis=(1, 3))


class _NoBar:
    def update(self, n=1):
        pass

    def close(self):
        pass


def _bar(progress: bool, total: int, desc: str):
    if not progress:
        return _NoBar()
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="step", leave=False, file=sys.stderr)


def render_all(size: int, truth: bool, progress: bool = True, out_root: Path | None = None,
               strict: bool = False) -> list[dict]:
    """Every scene, both configurations; the contact sheet, renders.json and scenes.md go to
    docs/ (or, with out_root, to <out_root>/docs)."""
    reps = []
    rows = []
    root = out_root or ROOT / "out" / "render"
    docs = ROOT / "docs" if out_root is None else Path(out_root) / "docs"
    docs.mkdir(parents=True, exist_ok=True)
    for scene in SCENES:
        row = []
        for c in CONFIG_NAMES:
            rep = render(scene, c, size, truth=truth, progress=progress, out_root=out_root, strict=strict)
            reps.append(rep)
            print(json.dumps({k: rep[k] for k in ("scene", "config", "psnr_golden_vs_reference_db",
                                                   "psnr_filtered_vs_truth_db", "psnr_unfiltered_vs_truth_db",
                                                   "seconds")}), flush=True)
        from model.imageio import read_image

        base = root / scene
        row.append((f"{scene}: reference", read_image(base / f"full-{size}" / "reference.png")))
        row.append(("golden full", read_image(base / f"full-{size}" / "golden.png")))
        row.append(("golden reduced", read_image(base / f"reduced-{size}" / "golden.png")))
        row.append(("unfiltered (full)", read_image(base / f"full-{size}" / "unfiltered.png")))
        if truth:
            row.append(("truth 8x8", read_image(base / f"full-{size}" / "truth.png")))
        row.append(("filter width", read_image(base / f"full-{size}" / "filter_width.png")))
        rows.append(row)
    contact_sheet(docs / "images" / "renders.png", rows, tile=160,
                  title=f"make renders: the eight scenes, {size} px (golden model and float reference)")
    (docs / "images" / "renders.json").write_text(json.dumps(reps, indent=1) + "\n")
    write_scenes_md(reps, size, docs)
    return reps


PAPER = {
    "wood": "Fig. 1: carved wooden teapot, f = s^2 + t^2 + n(4s, 4t, r), earlywood/latewood map, mod (eq. 5).",
    "marble": "Fig. 2: marble, f = r + sum_{i=1..4} 2^-i n(2^i s) (eq. 7), marble cross-section map, mod.",
    "seascape": "Fig. 3: sky and water planes to the horizon, fractal sum (eq. 6), blue-white / blue-black maps, clamp.",
    "fire": "Fig. 4: one polygon, f = r + sum 2^-i n(2^i s, 0, 2^i r + phi) (eq. 8), fire map, clamp.",
    "planet": "Fig. 5: sphere with a fractal sum and a cartographic legend with a hard coastline; clouds 'over' it.",
    "moonrise": "Fig. 6: moon sphere, cloud polygon, water plane, highlight triangles with (7), alpha maps.",
    "zone_plate": "Fig. 8: unit square 256x256, f = 50 s^2 + 50 t^2 (eq. 16), harsh zebra map, mod.",
    "torus": "Fig. 9: torus, wood grain centred off one side; filter width image (9c).",
}


def write_scenes_md(reps: list[dict], size: int, docs: Path = ROOT / "docs") -> None:
    """docs/scenes.md: each scene beside the paper's description, with its report figures."""
    L = ["# The paper's scenes", "",
         f"Written by `make renders` ({size} px per side, both configurations). Images: "
         "![renders](images/renders.png)", "",
         "Columns: PSNR of the golden model against the float reference (the configuration's error), "
         "its largest error in LSB, and the PSNR against the 8x8 supersampled ground truth of the "
         "filtered (antialiased) and unfiltered golden images: the filter helps where filtered > unfiltered.", ""]
    for scene in SCENES:
        L += [f"## {scene}", "", PAPER[scene], "",
              "| config | pixels | PSNR vs reference (dB) | max err (LSB) | PSNR filtered vs truth | "
              "PSNR unfiltered vs truth | noise terms used / dropped | seconds |", "|---|---|---|---|---|---|---|---|"]
        for r in reps:
            if r["scene"] != scene:
                continue
            used = "; ".join(f"{p['terms_used']}/{p['dropped_terms']}" for p in r["passes"])
            L.append(f"| {r['config']} | {r['pixels_textured']} | {r['psnr_golden_vs_reference_db']} | "
                     f"{r['max_abs_error_lsb']} | {r['psnr_filtered_vs_truth_db']} | "
                     f"{r['psnr_unfiltered_vs_truth_db']} | {used} | {r['seconds']} |")
        L.append("")
    (docs / "scenes.md").write_text("\n".join(L))


def main(argv=None) -> int:
    ap = Parser(prog="render", description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="zone_plate", help="a scene name (scenes/NAME.toml) or a path to a .toml file")
    ap.add_argument("--config", default="full", help=f"one of {', '.join(CONFIG_NAMES)}")
    ap.add_argument("--size", type=int, default=256, help="image width, 1..4096 (and what memory allows)")
    ap.add_argument("--all", action="store_true", help="all scenes, both configurations, contact sheet")
    ap.add_argument("--no-truth", action="store_true", help="skip the 8x8 supersampled ground truth")
    ap.add_argument("--truth-ss", type=int, default=8, help="truth supersampling per axis, 1..16")
    ap.add_argument("--out", type=Path, help="output root (default out/render; --all: its docs too)")
    ap.add_argument("--strict", action="store_true", help="any approximation of the scene by the configuration is an error")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)

    def go():
        check_range("--size", a.size, 1, 4096)
        check_range("--truth-ss", a.truth_ss, 1, 16)
        if a.all:
            render_all(a.size, truth=not a.no_truth, progress=not a.quiet, out_root=a.out, strict=a.strict)
        else:
            rep = render(a.scene, a.config, a.size, truth=not a.no_truth, truth_ss=a.truth_ss, out_root=a.out,
                         progress=not a.quiet, strict=a.strict)
            print(json.dumps(rep, indent=2))
        return 0

    return run_main("render", go)


if __name__ == "__main__":
    sys.exit(main())
