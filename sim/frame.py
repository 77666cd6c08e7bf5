"""Full-frame RTL simulation of a scene, compared bit for bit with the golden model.

`python -m sim.frame --scene zone_plate --config full --sim verilator --size 64`
(make frame) quantizes each texture pass of the scene, streams it through the
RTL (sim/frame_rtl.py run_passes_rtl: HDL-side memories, one simulator start for every
pass of the frame, Python wakes once), composites
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

from hdlbuild import need_tool
from model import reference
from model.cli import Parser, UserError, check_config, config_label, check_range, progress_bar, resolve_scene, run_main, staged
from model.hw import golden
from model.hw.config import CONFIG_NAMES, ROOT, doc_stamp, load_config
from model.imageio import compare, contact_sheet, read_image, write_image
from model.scene.passes import SCENES, composite, configured_texture, frame_size, prepare_passes, scene_approximations, strict_violations, to8

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


def check_args(config_name: str, sim: str, size: int, gaps: int, stalls: int) -> None:
    """Every argument of a frame run, before anything is built or simulated (UserError)."""
    check_config(config_name)
    if sim not in SIMS:
        raise UserError(f"--sim {sim}: expected one of {', '.join(SIMS)}")
    check_range("--size", size, 1, 1024)
    check_range("--gaps", gaps, 0, 99, "percent of clocks without an input pixel")
    check_range("--stalls", stalls, 0, 99, "percent of clocks with the output stalled")
    need_tool(sim)
    if sim == "verilator":
        from sim.frame_rtl import frame_cxx

        frame_cxx()  # the harness's C++ compiler (FRAME_CXX)


def run_frame(scene_name: str, config_name: str, sim: str, size: int, out_root: Path | None = None,
              progress: bool = True, gaps: int = 0, stalls: int = 0, strict: bool = False, netlists=None,
              command: str | None = None) -> dict:
    """One scene (a name or a .toml path) through the RTL into
    <out_root>/<scene>/<config>/<sim>-<size>/ (staged: only a completed run is moved into place;
    a failed one leaves a failure report there). strict: any approximation the configuration
    makes to the scene is an error, raised before the simulation. netlists: the configuration's
    synthesized netlists simulated in place of rtl/ (synth/netlist.py; `make gls`, whose `command`
    the report names)."""
    check_args(config_name, sim, size, gaps, stalls)
    scene_name, path = resolve_scene(scene_name)
    target = (out_root or ROOT / "out" / "frames") / scene_name / config_label(config_name) / f"{sim}-{size}"
    command = command or f"make frame SCENE={scene_name} CONFIG={config_name} SIM={sim} SIZE={size}"
    with staged(target, command) as out:
        rep = _run_into(out, scene_name, path, config_name, sim, size, progress, gaps, stalls, strict, netlists)
        (out / "report.json").write_text(json.dumps(rep, indent=2) + "\n")
    return rep


def _prepare(scene_name, path, config_name, size, strict) -> dict:
    """A frame's texture passes, quantized, before any simulation: {"cfg", "scene", "W", "H",
    "pds", "approx", "t0"}; --strict violations raise UserError here."""
    from model.scene.frontend import render_passes
    from model.scene.scene import load_scene

    t0 = time.perf_counter()
    cfg = load_config(config_name)
    scene = load_scene(path)
    W, H = frame_size(scene, size)
    pds = prepare_passes(cfg, render_passes(scene, W, H))
    approx = scene_approximations(pds)
    bad = strict_violations(pds) if strict else []
    if bad:
        raise UserError(f"--strict: {bad[0]}" + (f" (and {len(bad) - 1} more)" if len(bad) > 1 else ""))
    return {"cfg": cfg, "scene": scene, "W": W, "H": H, "pds": pds, "approx": approx, "t0": t0}


def _rtl_passes(prep: dict) -> list:
    """What run_passes_rtl takes of a prepared frame's passes."""
    return [(pd.ti, pd.si, pd.Jm, pd.je) for pd in prep["pds"]]


def _run_into(out, scene_name, path, config_name, sim, size, progress, gaps, stalls, strict, netlists=None) -> dict:
    from sim.frame_rtl import run_passes_rtl

    prep = _prepare(scene_name, path, config_name, size, strict)
    # every pass of the frame in one simulator run (passes without pixels run nowhere)
    rtls, info = run_passes_rtl(config_name, sim, _rtl_passes(prep), gaps=gaps, stalls=stalls, return_stats=True,
                                netlists=netlists)
    timing = {"cycles": sum(info["cycles"]), "sim_s": info["seconds"], "stream_s": info["stream_seconds"],
              "starts": info["starts"]}
    return _finish(out, prep, scene_name, config_name, sim, progress, gaps, stalls, rtls, timing, netlists)


def _finish(out, prep, scene_name, config_name, sim, progress, gaps, stalls, rtls, timing, netlists=None,
            batch=None) -> dict:
    """Compare a prepared frame's RTL colours (rtls: each pass's) with the golden model, write
    its images into `out` and return its report. timing: the frame's {"cycles", "sim_s",
    "stream_s", "starts"}; batch: the simulator run it shared with other frames (make frames)."""
    cfg, scene, W, H, pds, approx, t0 = (prep[k] for k in ("cfg", "scene", "W", "H", "pds", "approx", "t0"))
    bar = progress_bar(progress, total=len(pds), desc=f"{scene_name} {config_name} {sim} {W}x{H}", unit="pass")
    rtl_l, gold_l, ref_l, cref_l = [], [], [], []
    mismatches = []
    cycles, sim_s, stream_s = timing["cycles"], timing["sim_s"], timing["stream_s"]
    for pd, r in zip(pds, rtls):
        g = golden.texture_pipeline(cfg, pd.ti, pd.si, pd.Jm, pd.je)
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
        rf = reference.shade(pd.tex, pd.s, pd.J, cfg.perm, cfg.hash_bits)
        ref_l.append((pd.mask, rf))
        # the reference of the texture as the configuration computes it: the arithmetic error alone
        cref_l.append((pd.mask, reference.shade(configured_texture(cfg, pd.tex), pd.s, pd.J, cfg.perm, cfg.hash_bits)
                       if pd.info["approximations"] else rf))
        bar.update()
    bar.close()
    bg = scene.background
    img_rtl, img_gold, img_ref, img_cref = (composite(L, (H, W), bg) for L in (rtl_l, gold_l, ref_l, cref_l))
    textured = np.zeros((H, W), bool)
    for pd in pds:
        textured |= pd.mask
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
    cc = compare(img_rtl[textured], img_cref[textured])
    rep = {
        "status": "ok" if n_bad == 0 else "mismatch",
        "scene": scene_name, "config": config_name, "simulator": sim, "width": W, "height": H,
        "netlists": bool(netlists),
        "pixels_textured": int(textured.sum()), "pixels_streamed": px, "passes": len(pds),
        "mismatched_pixels": n_bad, "bit_exact": n_bad == 0,
        # the scene's texture as written; what the configuration changed is in approximations,
        # and the configured reference (those approximations made) leaves the arithmetic error alone
        "approximations": approx,
        "psnr_vs_reference_db": cr["psnr_db"], "max_abs_error_lsb": cr["max_abs_error_lsb"],
        "psnr_vs_configured_reference_db": cc["psnr_db"], "max_abs_error_vs_configured_reference_lsb": cc["max_abs_error_lsb"],
        "cycles": int(cycles), "cycles_per_pixel": round(cycles / px, 4) if px else None,
        "sim_seconds": round(sim_s, 3), "stream_seconds": round(stream_s, 3), "simulator_starts": timing["starts"],
        # streaming only (the HDL harness times its pixel loop); with simulator start-up apart
        "rtl_pixels_per_second": round(px / stream_s) if stream_s > 0 else None,
        "rtl_pixels_per_second_with_startup": round(px / sim_s) if sim_s > 0 else None,
        "input_gaps_percent": gaps, "output_stalls_percent": stalls,
        "first_mismatches": [m for m in mismatches if "count" not in m][:10],
        "seconds": round(time.perf_counter() - t0, 2),
    }
    if batch is not None:  # make frames: one simulator run for every frame of the configuration
        rep["simulator_run"] = batch
    return rep


def run_frames(scenes, config_name: str, sim: str, size: int, out_root: Path | None = None,
               strict: bool = False) -> list[dict]:
    """Every scene of `scenes` through the RTL of one configuration, each into
    <out_root>/<scene>/<config>/<sim>-<size>/ as run_frame writes it, with every pass of every
    frame in one run_passes_rtl call: one simulator start for all of them where the harness
    memories hold them (sim/frame_rtl.py MEMORY; more pixels are split into the fewest runs).
    A frame's sim_seconds and stream_seconds are its share of the runs' (by pixels and by
    clocks); its report's simulator_run gives the whole call's frames, starts and seconds."""
    from sim.frame_rtl import run_passes_rtl

    check_args(config_name, sim, size, 0, 0)
    root = out_root or ROOT / "out" / "frames"
    preps = []
    for scene_arg in scenes:
        name, path = resolve_scene(scene_arg)
        preps.append((name, _prepare(name, path, config_name, size, strict)))
    flat = [p for _, prep in preps for p in _rtl_passes(prep)]
    t0 = time.perf_counter()
    rtls, info = run_passes_rtl(config_name, sim, flat, return_stats=True)
    batch = {"frames": len(preps), "passes": len(flat), "starts": info["starts"],
             "seconds": round(info["seconds"], 3), "stream_seconds": round(info["stream_seconds"], 3),
             "call_seconds": round(time.perf_counter() - t0, 3)}
    total_cycles = max(sum(info["cycles"]), 1)
    total_px = max(sum(len(p[1]) for p in flat), 1)
    reps, k = [], 0
    for name, prep in preps:
        n = len(prep["pds"])
        cyc = sum(info["cycles"][k:k + n])
        px = sum(len(pd.si) for pd in prep["pds"])
        timing = {"cycles": cyc, "sim_s": info["seconds"] * px / total_px,
                  "stream_s": info["stream_seconds"] * cyc / total_cycles, "starts": info["starts"]}
        target = root / name / config_label(config_name) / f"{sim}-{size}"
        command = f"make frames FRAMES_SIZE={size}"
        with staged(target, command) as out:
            rep = _finish(out, prep, name, config_name, sim, False, 0, 0, rtls[k:k + n], timing, batch=batch)
            (out / "report.json").write_text(json.dumps(rep, indent=2) + "\n")
        reps.append(rep)
        k += n
    return reps


def conformance(size: int, sim: str, out_root: Path | None = None, strict: bool = False, scenes=SCENES) -> int:
    """Every scene (or the given ones), every configuration; docs/conformance.md and its contact
    sheet (with out_root: <out_root>/docs)."""
    reps, rows = [], []
    root = out_root or ROOT / "out" / "frames"
    docs = ROOT / "docs" if out_root is None else Path(out_root) / "docs"
    for c in CONFIG_NAMES:
        check_args(c, sim, size, 0, 0)  # every argument before anything is written
    (docs / "images").mkdir(parents=True, exist_ok=True)
    # each configuration's frames in one simulator run (run_frames), reported scene by scene
    by_config = {}
    for c in CONFIG_NAMES:
        by_config[c] = run_frames(scenes, c, sim, size, out_root=out_root, strict=strict)
        b = by_config[c][0]["simulator_run"] if by_config[c] else {}
        print(json.dumps({"config": c, **b}), flush=True)
    for i, scene in enumerate(scenes):
        row = []
        for c in CONFIG_NAMES:
            rep = by_config[c][i]
            reps.append(rep)
            print(json.dumps({k: rep[k] for k in ("scene", "config", "bit_exact", "psnr_vs_reference_db",
                                                   "cycles_per_pixel", "rtl_pixels_per_second")}), flush=True)
            row.append((f"{scene} {c}", read_image(root / rep["scene"] / c / f"{sim}-{size}" / "rtl.png")))
        rows.append(row)
    contact_sheet(docs / "images" / "conformance.png", [sum(rows[i:i + 2], []) for i in range(0, len(rows), 2)],
                  tile=180, title=f"make frames: RTL ({sim}) images, {size} px")
    L = ["# Conformance: RTL against the golden model, whole frames", "",
         f"Written by `make frames` ({size}x{size}, {sim}). Every pixel of every texture pass of the RTL "
         "is compared with the golden model; `bit_exact` means no bit differs.", "",
         "![RTL images](images/conformance.png)", "",
         "RTL pixels/s: simulator wall time of the streaming loop; with start-up: including the simulator's "
         "start (once a frame: every pass of a frame in one run; under Verilator's C++ main a few hundredths of a second). PSNR vs reference: the RTL image against the float64 reference of the "
         "scene's texture as written (all its noise terms, its blend); `reduced` keeps the first 2 terms and a "
         "linear blend, so its PSNR measures that approximation, not an arithmetic error; `compact` keeps every "
         "term and the cubic blend on one noise unit (noise_units = 1), so a pixel takes as many clocks as its "
         "texture has terms (cycles/pixel: the clocks from the first pixel offered to the last colour taken, "
         "over the pixels).", "",
         "| scene | config | bit_exact | mismatched pixels | PSNR vs reference (dB) | cycles/pixel | RTL pixels/s | with start-up |",
         "|---|---|---|---|---|---|---|---|"]
    for r in reps:
        L.append(f"| {r['scene']} | {r['config']} | {r['bit_exact']} | {r['mismatched_pixels']} | "
                 f"{r['psnr_vs_reference_db']} | {r['cycles_per_pixel']} | {r['rtl_pixels_per_second']} | "
                 f"{r['rtl_pixels_per_second_with_startup']} |")
    L.append(doc_stamp([load_config(c) for c in CONFIG_NAMES]))
    (docs / "conformance.md").write_text("\n".join(L) + "\n")
    return 0 if all(r["bit_exact"] for r in reps) else 1


def main(argv=None) -> int:
    ap = Parser(prog="frame", description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="zone_plate", help="a scene name (scenes/NAME.toml) or a path to a .toml file")
    ap.add_argument("--config", default="full", help=f"one of {', '.join(CONFIG_NAMES)}")
    ap.add_argument("--sim", default="verilator", help=f"one of {', '.join(SIMS)}")
    ap.add_argument("--size", type=int, default=64, help="image width, 1..1024")
    ap.add_argument("--gaps", type=int, default=0, help="percent of cycles with no input pixel, 0..99")
    ap.add_argument("--stalls", type=int, default=0, help="percent of cycles with the output stalled, 0..99")
    ap.add_argument("--out", type=Path, help="output root (default out/frames; --all: its docs too)")
    ap.add_argument("--strict", action="store_true", help="any approximation of the scene by the configuration is an error")
    ap.add_argument("--all", action="store_true")
    ap.add_argument("--scenes", help="--all: only these scenes (comma-separated names; default all)")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    from sim.frame_rtl import FrameRunError, frame_procs

    def go():
        frame_procs()  # FRAME_PROCS checked before any work
        if a.all:
            scenes = SCENES
            if a.scenes:
                scenes = tuple(x for x in a.scenes.split(",") if x)
                for x in scenes:
                    if x not in SCENES:
                        raise UserError(f"--scenes {a.scenes}: {x} is not a scene of the paper (known: {', '.join(SCENES)})")
            return conformance(a.size, a.sim, out_root=a.out, strict=a.strict, scenes=scenes)
        rep = run_frame(a.scene, a.config, a.sim, a.size, out_root=a.out, progress=not a.quiet, gaps=a.gaps,
                        stalls=a.stalls, strict=a.strict)
        print(json.dumps(rep, indent=2))
        if not rep["bit_exact"]:
            print(f"frame: {rep['mismatched_pixels']} pixels differ; first: {rep['first_mismatches'][:3]}",
                  file=sys.stderr)
            return 1
        return 0

    try:
        return run_main("frame", go)
    except FrameRunError as e:  # the simulator failed or the harness found a protocol error: not an input error
        print(f"frame: {' '.join(str(e).split())}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
