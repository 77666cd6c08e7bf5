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
from model.hw.config import CONFIG_NAMES, ROOT, ConfigError, load_config
from model.hw.quantize import FormatError
from model.imageio import compare, contact_sheet, write_image
from model.scene.passes import SCENES, composite, frame_size, prepare_passes, scene_path, to8


def git_describe() -> str:
    try:
        return subprocess.run(["git", "-C", str(ROOT), "describe", "--always", "--dirty"], capture_output=True,
                              text=True, timeout=10).stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def render(scene_name: str, config_name: str, size: int, truth: bool = True, truth_ss: int = 8,
           out_root: Path | None = None, progress: bool = True) -> dict:
    from model.scene.frontend import render_passes
    from model.scene.scene import load_scene

    t0 = time.perf_counter()
    cfg = load_config(config_name)
    scene = load_scene(scene_path(scene_name))
    W, H = frame_size(scene, size)
    passes = render_passes(scene, W, H)
    pds = prepare_passes(cfg, passes)
    bar = _bar(progress, total=len(pds) * 3 + (1 if truth else 0), desc=f"{scene_name} {config_name} {W}x{H}")
    gold, unf, ref, widths = [], [], [], np.zeros((H, W))
    for pd in pds:
        st = golden.texture_stages(cfg, pd.ti, pd.si, pd.Jm, pd.je)
        gold.append((pd.mask, st["rgba"]))
        n = 1 << pd.ti.n_log2
        widths[pd.mask] = np.maximum(widths[pd.mask], st["w"] / float(1 << cfg.f_frac) / n)
        bar.update()
        ti_off = golden.TexInt(**{**pd.ti.__dict__, "filter": False})
        unf.append((pd.mask, golden.texture_pipeline(cfg, ti_off, pd.si, pd.Jm, pd.je)))
        bar.update()
        ref.append((pd.mask, reference.shade(pd.tex, pd.s, pd.J, cfg.perm, cfg.hash_bits)))
        bar.update()
    bg = scene.background
    img_gold = composite(gold, (H, W), bg)
    img_unf = composite(unf, (H, W), bg)
    img_ref = composite(ref, (H, W), bg)
    textured = np.zeros((H, W), bool)
    for pd in pds:
        textured |= pd.mask
    img_truth = None
    if truth:
        img_truth = supersampled_truth(scene, cfg, W, H, truth_ss)
        bar.update()
    bar.close()
    out = (out_root or ROOT / "out" / "render") / scene_name / f"{config_name}-{size}"
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
        "scene": scene_name, "config": config_name, "width": W, "height": H,
        "pixels_textured": int(textured.sum()),
        "passes": [{"name": pd.name, "pixels": int(pd.mask.sum()), **pd.info} for pd in pds],
    }
    cg = compare(img_gold[textured], img_ref[textured])
    rep["psnr_golden_vs_reference_db"] = cg["psnr_db"]
    rep["max_abs_error_lsb"] = cg["max_abs_error_lsb"]
    rep["mean_abs_error_lsb"] = cg["mean_abs_error_lsb"]
    if img_truth is not None:
        write_image(out / "truth.png", to8(img_truth))
        rep["psnr_filtered_vs_truth_db"] = compare(img_gold[textured], img_truth[textured])["psnr_db"]
        rep["psnr_unfiltered_vs_truth_db"] = compare(img_unf[textured], img_truth[textured])["psnr_db"]
        rep["psnr_reference_vs_truth_db"] = compare(img_ref[textured], img_truth[textured])["psnr_db"]
        rep["truth_supersampling"] = f"{truth_ss}x{truth_ss}"
    else:
        rep["psnr_filtered_vs_truth_db"] = rep["psnr_unfiltered_vs_truth_db"] = None
    rep["seconds"] = round(time.perf_counter() - t0, 2)
    (out / "report.json").write_text(json.dumps(rep, indent=2) + "\n")
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


def render_all(size: int, truth: bool, progress: bool = True) -> list[dict]:
    reps = []
    rows = []
    for scene in SCENES:
        row = []
        for c in CONFIG_NAMES:
            rep = render(scene, c, size, truth=truth, progress=progress)
            reps.append(rep)
            print(json.dumps({k: rep[k] for k in ("scene", "config", "psnr_golden_vs_reference_db",
                                                   "psnr_filtered_vs_truth_db", "psnr_unfiltered_vs_truth_db",
                                                   "seconds")}), flush=True)
        from model.imageio import read_image

        base = ROOT / "out" / "render" / scene
        row.append((f"{scene}: reference", read_image(base / f"full-{size}" / "reference.png")))
        row.append(("golden full", read_image(base / f"full-{size}" / "golden.png")))
        row.append(("golden reduced", read_image(base / f"reduced-{size}" / "golden.png")))
        row.append(("unfiltered (full)", read_image(base / f"full-{size}" / "unfiltered.png")))
        if truth:
            row.append(("truth 8x8", read_image(base / f"full-{size}" / "truth.png")))
        row.append(("filter width", read_image(base / f"full-{size}" / "filter_width.png")))
        rows.append(row)
    contact_sheet(ROOT / "docs" / "images" / "renders.png", rows, tile=160,
                  title=f"make renders: the eight scenes, {size} px (golden model and float reference)")
    (ROOT / "docs" / "images" / "renders.json").write_text(json.dumps(reps, indent=1) + "\n")
    write_scenes_md(reps, size)
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


def write_scenes_md(reps: list[dict], size: int) -> None:
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
    (ROOT / "docs" / "scenes.md").write_text("\n".join(L))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m model.scene.render", description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="zone_plate")
    ap.add_argument("--config", default="full", choices=CONFIG_NAMES)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--all", action="store_true", help="all scenes, both configurations, contact sheet")
    ap.add_argument("--no-truth", action="store_true", help="skip the 8x8 supersampled ground truth")
    ap.add_argument("--truth-ss", type=int, default=8)
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    if a.size < 1 or a.size > 4096:
        print(f"render: --size {a.size}: expected 1..4096", file=sys.stderr)
        return 2
    try:
        if a.all:
            render_all(a.size, truth=not a.no_truth, progress=not a.quiet)
        else:
            if not scene_path(a.scene).exists():
                print(f"render: {scene_path(a.scene)}: no such scene (known: {', '.join(SCENES)})", file=sys.stderr)
                return 2
            rep = render(a.scene, a.config, a.size, truth=not a.no_truth, truth_ss=a.truth_ss, progress=not a.quiet)
            print(json.dumps(rep, indent=2))
    except (FormatError, ConfigError) as e:
        print(f"render: {e}", file=sys.stderr)
        return 2
    except Exception as e:  # scene errors carry their own one-line message
        if type(e).__name__ == "SceneError":
            print(str(e), file=sys.stderr)
            return 2
        raise
    return 0


if __name__ == "__main__":
    sys.exit(main())
