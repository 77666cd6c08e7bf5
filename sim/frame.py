"""Full-frame RTL simulation of a scene, compared bit for bit with the golden model.

`python -m sim.frame --scene zone_plate --config full --sim verilator --size 64`
(make frame) quantizes each texture pass of the scene, streams it through the
RTL (sim/frame_rtl.py: HDL-side memories, Python wakes once per pass), composites
the passes, and writes out/frames/<scene>/<config>/<sim>-<size>/: rtl.png,
golden.png, reference.png, diff.png (heat map of |rtl - golden|, black when equal)
and report.json. On a mismatch it names the first differing pixels with their
inputs and both outputs and exits 1. `--all` runs every scene for both
configurations and writes docs/conformance.md and docs/images/conformance.png.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from model import reference
from model.hw import golden
from model.hw.config import CONFIG_NAMES, ROOT, ConfigError, load_config
from model.imageio import compare, contact_sheet, read_image, write_image
from model.hw.quantize import FormatError
from model.scene.passes import SCENES, composite, frame_size, prepare_passes, scene_path, to8

SIMS = ("verilator", "icarus")


def heat(d: np.ndarray) -> np.ndarray:
    """|difference| in LSB to a black-red-yellow-white heat map (0 stays black)."""
    x = np.clip(d / 32.0, 0, 1)  # 32 LSB and more saturate
    r = np.clip(3 * x, 0, 1)
    g = np.clip(3 * x - 1, 0, 1)
    b = np.clip(3 * x - 2, 0, 1)
    img = np.stack([r, g, b], -1) * 255
    img[d > 0] = np.maximum(img[d > 0], [96, 0, 0])  # any difference is visible
    return img.astype(np.uint8)


def run_frame(scene_name: str, config_name: str, sim: str, size: int, out_root: Path | None = None,
              progress: bool = True, gaps: int = 0, stalls: int = 0) -> dict:
    from model.scene.frontend import render_passes
    from model.scene.scene import load_scene
    from sim.frame_rtl import run_frame_rtl

    t0 = time.perf_counter()
    cfg = load_config(config_name)
    scene = load_scene(scene_path(scene_name))
    W, H = frame_size(scene, size)
    pds = prepare_passes(cfg, render_passes(scene, W, H))
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=len(pds), desc=f"{scene_name} {config_name} {sim} {W}x{H}", unit="pass", leave=False,
                   file=sys.stderr)
    rtl_l, gold_l, ref_l = [], [], []
    cycles = 0
    sim_s = 0.0
    stream_s = 0.0
    mismatches = []
    for pd in pds:
        g = golden.texture_pipeline(cfg, pd.ti, pd.si, pd.Jm, pd.je)
        if len(pd.si):
            r, cyc, secs, stats = run_frame_rtl(config_name, sim, pd.ti, pd.si, pd.Jm, pd.je, gaps=gaps,
                                                stalls=stalls, return_stats=True)
            stream_s += sum(st.get("stream_wall_us", 0) for st in stats) / 1e6
        else:
            r, cyc, secs = g.copy(), 0, 0.0
        cycles += cyc
        sim_s += secs
        bad = np.nonzero(np.any(r != g, axis=-1))[0]
        if len(bad):
            ys, xs = np.nonzero(pd.mask)
            for i in bad[:5]:
                mismatches.append({"pass": pd.name, "x": int(xs[i]), "y": int(ys[i]),
                                   "s": pd.si[i].tolist(), "Jm": pd.Jm[i].tolist(), "je": int(pd.je[i]),
                                   "rtl": r[i].tolist(), "golden": g[i].tolist()})
            mismatches.append({"pass": pd.name, "count": int(len(bad))})
        rtl_l.append((pd.mask, r))
        gold_l.append((pd.mask, g))
        ref_l.append((pd.mask, reference.shade(pd.tex, pd.s, pd.J, cfg.perm, cfg.hash_bits)))
        if bar:
            bar.update()
    if bar:
        bar.close()
    bg = scene.background
    img_rtl, img_gold, img_ref = (composite(L, (H, W), bg) for L in (rtl_l, gold_l, ref_l))
    textured = np.zeros((H, W), bool)
    for pd in pds:
        textured |= pd.mask
    out = (out_root or ROOT / "out" / "frames") / scene_name / config_name / f"{sim}-{size}"
    write_image(out / "rtl.png", to8(img_rtl))
    write_image(out / "golden.png", to8(img_gold))
    write_image(out / "reference.png", to8(img_ref))
    diff = np.zeros((H, W))
    for (mask, r), (_, g) in zip(rtl_l, gold_l):
        diff[mask] = np.maximum(diff[mask], np.abs(r.astype(int) - g.astype(int)).max(axis=-1))
    write_image(out / "diff.png", heat(diff))
    n_bad = sum(m.get("count", 0) for m in mismatches)
    px = int(sum(len(pd.si) for pd in pds))
    cr = compare(img_rtl[textured], img_ref[textured])
    rep = {
        "scene": scene_name, "config": config_name, "simulator": sim, "width": W, "height": H,
        "pixels_textured": int(textured.sum()), "pixels_streamed": px, "passes": len(pds),
        "mismatched_pixels": n_bad, "bit_exact": n_bad == 0,
        "psnr_vs_reference_db": cr["psnr_db"], "max_abs_error_lsb": cr["max_abs_error_lsb"],
        "cycles": int(cycles), "cycles_per_pixel": round(cycles / px, 4) if px else None,
        "sim_seconds": round(sim_s, 3), "stream_seconds": round(stream_s, 3),
        # streaming only (the HDL harness times its pixel loop); with simulator start-up apart
        "rtl_pixels_per_second": round(px / stream_s) if stream_s > 0 else None,
        "rtl_pixels_per_second_with_startup": round(px / sim_s) if sim_s > 0 else None,
        "input_gaps_percent": gaps, "output_stalls_percent": stalls,
        "first_mismatches": [m for m in mismatches if "count" not in m][:10],
        "seconds": round(time.perf_counter() - t0, 2),
    }
    (out / "report.json").write_text(json.dumps(rep, indent=2) + "\n")
    return rep


def conformance(size: int, sim: str) -> int:
    reps, rows = [], []
    for scene in SCENES:
        row = []
        for c in CONFIG_NAMES:
            rep = run_frame(scene, c, sim, size)
            reps.append(rep)
            print(json.dumps({k: rep[k] for k in ("scene", "config", "bit_exact", "psnr_vs_reference_db",
                                                   "cycles_per_pixel", "rtl_pixels_per_second")}), flush=True)
            row.append((f"{scene} {c}", read_image(ROOT / "out" / "frames" / scene / c / f"{sim}-{size}" / "rtl.png")))
        rows.append(row)
    contact_sheet(ROOT / "docs" / "images" / "conformance.png", [sum(rows[i:i + 2], []) for i in range(0, 8, 2)],
                  tile=180, title=f"make frames: RTL ({sim}) images, {size} px")
    L = ["# Conformance: RTL against the golden model, whole frames", "",
         f"Written by `make frames` ({size}x{size}, {sim}). Every pixel of every texture pass of the RTL "
         "is compared with the golden model; `bit_exact` means no bit differs.", "",
         "![RTL images](images/conformance.png)", "",
         "RTL pixels/s: simulator wall time of the streaming loop; with start-up: including the simulator's "
         "start (about 2 s a pass). PSNR vs reference: the RTL image against the float64 reference of the "
         "scene's texture as written (all its noise terms, its blend); `reduced` keeps the first 2 terms and a "
         "linear blend, so its PSNR measures that approximation, not an arithmetic error.", "",
         "| scene | config | bit_exact | mismatched pixels | PSNR vs reference (dB) | cycles/pixel | RTL pixels/s | with start-up |",
         "|---|---|---|---|---|---|---|---|"]
    for r in reps:
        L.append(f"| {r['scene']} | {r['config']} | {r['bit_exact']} | {r['mismatched_pixels']} | "
                 f"{r['psnr_vs_reference_db']} | {r['cycles_per_pixel']} | {r['rtl_pixels_per_second']} | "
                 f"{r['rtl_pixels_per_second_with_startup']} |")
    (ROOT / "docs" / "conformance.md").write_text("\n".join(L) + "\n")
    return 0 if all(r["bit_exact"] for r in reps) else 1


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m sim.frame", description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="zone_plate")
    ap.add_argument("--config", default="full", choices=CONFIG_NAMES)
    ap.add_argument("--sim", default="verilator", choices=SIMS)
    ap.add_argument("--size", type=int, default=64)
    ap.add_argument("--gaps", type=int, default=0, help="percent of cycles with no input pixel")
    ap.add_argument("--stalls", type=int, default=0, help="percent of cycles with the output stalled")
    ap.add_argument("--all", action="store_true")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    if not 1 <= a.size <= 1024:
        print(f"frame: --size {a.size}: expected 1..1024", file=sys.stderr)
        return 2
    try:
        if a.all:
            return conformance(a.size, a.sim)
        if not scene_path(a.scene).exists():
            print(f"frame: {scene_path(a.scene)}: no such scene (known: {', '.join(SCENES)})", file=sys.stderr)
            return 2
        rep = run_frame(a.scene, a.config, a.sim, a.size, progress=not a.quiet, gaps=a.gaps, stalls=a.stalls)
    except (FormatError, ConfigError) as e:
        print(f"frame: {e}", file=sys.stderr)
        return 2
    except RuntimeError as e:  # sim.frame_rtl.FrameRunError: a missing simulator, a failed build or run
        print(f"frame: {e}", file=sys.stderr)
        return 1
    print(json.dumps(rep, indent=2))
    if not rep["bit_exact"]:
        print(f"frame: {rep['mismatched_pixels']} pixels differ; first: {rep['first_mismatches'][:3]}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
