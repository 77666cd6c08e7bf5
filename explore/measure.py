"""One point of the design space, measured: `measure(values, opts)` -> a record (a dict, JSON).

A point is a configuration (its keys, model.hw.config.SCHEMA). Its record holds:
- gates: synth.run's method exactly (each block synthesized alone by synth/synth.py with the
  Yosys liberty synth/cells.lib, times its instance count, plus texture_pipeline's glue with the
  blocks as black boxes): GE total, combinational, sequential, storage bits, logic depth, per
  block. Each block's report is cached under build/explore/blocks/ by a hash of its module, its
  parameter set (hdlbuild.block_params) and the RTL files it is built from, so a sweep
  synthesizes only blocks it has not seen (`blocks_synthesized` / `blocks_cached` say which);
- per scene (model.scene.passes.SCENES) at `size` px: pixels per clock (the pipeline's clocks
  for each pass's term count, model.hw.config.clocks_per_pixel), PSNR of the golden model
  against the float reference of the scene as written and against the supersampled truth (over
  the texture interior, the textured pixels less a one-pixel rim at every silhouette, where the
  truth mixes in coverage the texture unit does not compute, model/scene/rim.py; and, as
  psnr_truth_textured_db, over all textured pixels), and the largest error in LSB;
- a bit-exact check: `rtl_scenes` at `rtl_size` px streamed through the RTL under Verilator
  (sim.frame_rtl), every pixel against the golden model;
- with opts["corpus"] = {"n", "size"}: the held-out corpus (explore.validate.corpus_quality,
  against the float reference): scenes accepted and covered, the covered scenes' worst, 5th
  percentile and median PSNR, and the share at 50 dB (issue 26: no point is judged only on the
  scenes the formats were narrowed on).
A point the configuration checks reject, that a scene's values do not fit, that fails to
synthesize or whose RTL differs from the golden model is recorded with its error (status
"failed" or "mismatch"), never dropped.

The float reference and the truth depend only on the scene, the size and the lattice (seed and
hash_bits), not on the formats: computed once per scene and size (`truth`, cached on disk
by model.scene.truth; the reference in app.quality's per-process cache).
"""
from __future__ import annotations

import contextlib
import fcntl
import hashlib
import json
import time
from pathlib import Path

import numpy as np

from hdlbuild import ROOT, block_params
from model.hw.config import ConfigError, config_values, load_config, variant

BLOCK_CACHE = ROOT / "build" / "explore" / "blocks"
LOCK_DIR = ROOT / "build" / "explore" / "locks"
# the sweep's truth: samples a pixel axis, and in the band w > N/8 (model.scene.truth), a quarter
# of make render's 16 and 32, so that 24 truths (8 scenes, 3 lattices) take minutes, not hours;
# they rank configurations, docs/scenes.md gives the converged figures
TRUTH_SS, TRUTH_BAND_SS = 8, 16
# what a point's measurement depends on (its record is stored under a hash of these and its keys)
SOURCE_GLOBS = ("rtl/*.v", "rtl/*.vh", "model/hw/*.py", "model/reference.py", "model/texture.py", "model/imageio.py",
                "model/scene/frontend.py", "model/scene/passes.py", "model/scene/scene.py", "model/scene/teapot.py",
                "app/quality.py", "model/scene/truth.py", "scenes/*.toml", "sim/frame_tb.v",
                "sim/frame_rtl.py", "sim/frame_cocotb.py", "sim/frame_main.cpp", "synth/synth.py", "synth/run.py",
                "synth/cells.lib", "hdlbuild/*.py", "explore/measure.py", "explore/validate.py",
                "model/scene/corpus.py", "model/scene/rim.py")


def _hash(*parts) -> str:
    h = hashlib.sha256()
    for p in parts:
        h.update(p if isinstance(p, bytes) else repr(p).encode())
    return h.hexdigest()


def source_hash() -> str:
    """A hash of every file a point's measurement depends on (SOURCE_GLOBS)."""
    files = sorted({p for g in SOURCE_GLOBS for p in ROOT.glob(g) if p.is_file()})
    return _hash(*[(str(p.relative_to(ROOT)), p.read_bytes()) for p in files])[:16]


# the keys a point does not name: full_narrow's (full until issue 26: fixed point, no per-term exponents),
# so a point's values give the Config they gave before full took block floating point
POINT_BASE = ROOT / "config" / "candidates" / "full_narrow.toml"


def point_config(values: dict, name: str | None = None):
    """The Config of a point's keys over POINT_BASE (checked like a file: ConfigError names the key).
    Its name is a hash of the values, so that builds of two points never share a directory."""
    name = name or "x" + _hash(sorted(values.items()))[:10]
    return variant(load_config(str(POINT_BASE)), name, **values)


def point_key(values: dict, opts: dict, src: str) -> str:
    """A point's record name: its values, the options (not where the corpus was written) and the source."""
    return _hash(sorted(values.items()), sorted((k, v) for k, v in opts.items() if k != "corpus_root"), src)[:20]


# ---------------------------------------------------------------------------- gates

def module_closure(top: str) -> list[Path]:
    """The RTL files `top` is built from (synth.run.block_files: all synth_one reads of it) and
    the include files."""
    from synth.run import block_files

    return sorted({Path(f) for f in block_files(top)} | set((ROOT / "rtl").glob("*.vh")))


@contextlib.contextmanager
def _locked(path: Path):
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path.with_suffix(".lock"), "w") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        yield


def synth_block(cfg, label: str, module: str, lib: tuple, stats: dict) -> dict:
    """synth.run.synth_one's report of one piece, from the cache when its module, parameters
    and files were seen before (stats counts 'synthesized' and 'cached')."""
    from synth.run import synth_one

    files = [str(p) for p in (sorted((ROOT / "rtl").glob("*.v*")) if lib else module_closure(module))]
    flow = [ROOT / "synth" / "synth.py", ROOT / "synth" / "cells.lib"]
    from synth.run import READS

    key = _hash(module, sorted(block_params(cfg, module).items()), bool(lib), READS,
                *[Path(f).read_bytes() for f in files], *[p.read_bytes() for p in flow])[:20]
    out = BLOCK_CACHE / f"{module}-{key}.json"
    with _locked(out):
        if out.exists():
            stats["cached"] += 1
            return json.loads(out.read_text())
        tmp = out.with_suffix(".tmp.json")
        rep = synth_one(cfg, module, lib, out=tmp)
        tmp.replace(out)
        stats["synthesized"] += 1
        return rep


def gates(cfg) -> dict:
    from synth.run import block_jobs, combine

    stats = {"synthesized": 0, "cached": 0}
    res = {label: synth_block(cfg, label, mod, lib, stats) for label, (mod, lib) in block_jobs(cfg).items()}
    rep = combine(cfg.name, cfg, res)
    return {"ge_total": rep["ge_total"], "ge_comb": rep["ge_comb"], "ge_seq": rep["ge_seq"],
            "storage_bits": rep["storage_bits"], "logic_depth": rep["logic_depth"],
            "logic_depth_by_block": rep["logic_depth_by_block"], "blocks_ge": rep["blocks"],
            "blocks_synthesized": stats["synthesized"], "blocks_cached": stats["cached"],
            "yosys_version": rep["yosys_version"]}


# ---------------------------------------------------------------------------- images

def truth(name: str, size: int, cfg, ss: int | None = None, band_ss: int | None = None) -> np.ndarray:
    """The converged truth of scene `name` at `size` px for cfg's lattice, [H, W, 4] float:
    model.scene.truth.truth_image (stratified jittered supersampling, more samples where the
    filter width is large; cached on disk, keyed by the scene, the reference's source and the
    lattice)."""
    from model.scene.truth import truth_image

    kw = {k: v for k, v in (("ss", ss), ("band_ss", band_ss)) if v}
    with _locked(LOCK_DIR / f"truth-{name}-{size}-{cfg.seed}-{cfg.hash_bits}"):  # workers wait, not redo
        return truth_image(name, cfg, size, **kw)


def images(cfg, scenes, size: int, opts: dict | None = None) -> dict:
    """Per scene: pixels per clock, PSNR against the float reference and the truth, largest error."""
    from model.imageio import compare
    from app.quality import scene_images

    out = {}
    opts = opts or {}
    for s in scenes:
        im = scene_images(cfg, s, size)
        t, inner = im["textured"], im["interior"]
        cr = compare(im["golden"][t], im["reference"][t])
        tr = truth(s, size, cfg, opts.get("truth_ss"), opts.get("truth_band_ss"))
        # against the truth over the texture interior (the texture unit's own error: the silhouette rims
        # mix in coverage it does not compute, model/scene/rim.py), and over all textured pixels
        ct, cta = compare(im["golden"][inner], tr[inner]), compare(im["golden"][t], tr[t])
        out[s] = {"pixels_per_clock": round(im["pixels"] / im["clocks"], 4) if im["clocks"] else None,
                  "psnr_ref_db": round(cr["psnr_db"], 2), "psnr_truth_db": round(ct["psnr_db"], 2),
                  "psnr_truth_textured_db": round(cta["psnr_db"], 2), "max_error_lsb": int(cr["max_abs_error_lsb"])}
    return out


LOG_DIR = ROOT / "build" / "explore" / "logs"


@contextlib.contextmanager
def _output_to(path: Path):
    """This process's stdout and stderr (file descriptors: the simulator builds' too) into
    `path` for the duration, so that a sweep's progress bar is not buried in build logs."""
    import os
    import sys

    path.parent.mkdir(parents=True, exist_ok=True)
    sys.stdout.flush()
    sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    with open(path, "a") as f:
        os.dup2(f.fileno(), 1)
        os.dup2(f.fileno(), 2)
        try:
            yield
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])


def rtl_check(cfg, scenes, size: int, out_dir: Path | None = None) -> dict:
    """Every pixel of `scenes` at `size` px through the RTL under Verilator against the golden
    model: {"bit_exact", "pixels", "mismatched_pixels", "scenes", "size"}; with out_dir, each
    scene's RTL image is written there as <scene>.png."""
    from model.hw import golden
    from model.imageio import write_image
    from model.scene.frontend import render_passes
    from model.scene.passes import composite, frame_size, prepare_passes, scene_path, to8
    from model.scene.scene import load_scene
    from sim.frame_rtl import run_frame_rtl

    px = bad = 0
    for s in scenes:
        sc = load_scene(scene_path(s))
        W, H = frame_size(sc, size)
        layers = []
        for pd in prepare_passes(cfg, render_passes(sc, W, H)):
            if not len(pd.si):
                continue
            g = golden.texture_pipeline(cfg, pd.ti, pd.si, pd.Jm, pd.je)
            r = run_frame_rtl(cfg, "verilator", pd.ti, pd.si, pd.Jm, pd.je)[0]
            px += len(g)
            bad += int(np.any(r != g, axis=-1).sum())
            layers.append((pd.mask, r))
        if out_dir is not None:
            write_image(Path(out_dir) / f"{s}.png", to8(composite(layers, (H, W), sc.background)))
    return {"bit_exact": bad == 0 and px > 0, "pixels": px, "mismatched_pixels": bad, "scenes": list(scenes),
            "size": size}


def rtl_render(cfg, scenes, size: int, out_dir: Path) -> dict:
    """rtl_check with each scene's RTL image written to out_dir (its logs beside them)."""
    with _output_to(LOG_DIR / f"{cfg.name}.log"):
        return rtl_check(cfg, scenes, size, out_dir)


# ---------------------------------------------------------------------------- a point

def measure(values: dict, opts: dict) -> dict:
    """The record of one point. opts: scenes, size, rtl_scenes, rtl_size, rtl (bool)."""
    from model.hw.config import clocks_per_pixel
    from model.hw.quantize import FormatError
    from synth.run import SynthError

    t0 = time.perf_counter()
    rec = {"config": dict(values), "opts": dict(opts), "status": "ok", "error": None}
    try:
        cfg = point_config(values)
        rec["name"] = cfg.name
        rec["pixels_per_clock_all_terms"] = round(1 / clocks_per_pixel(cfg), 4)
        rec["scenes"] = images(cfg, opts["scenes"], opts["size"], opts)
        ok = [v for v in rec["scenes"].values()]
        rec["worst_psnr_ref_db"] = min(v["psnr_ref_db"] for v in ok)
        rec["worst_psnr_truth_db"] = min(v["psnr_truth_db"] for v in ok)
        rec["worst_psnr_truth_textured_db"] = min(v["psnr_truth_textured_db"] for v in ok)
        rec["min_pixels_per_clock"] = min(v["pixels_per_clock"] for v in ok if v["pixels_per_clock"])
        if opts.get("corpus"):
            from explore.validate import corpus_quality

            rec["corpus"] = corpus_quality(cfg, n=opts["corpus"]["n"], size=opts["corpus"]["size"],
                                           root=Path(opts["corpus_root"]) if opts.get("corpus_root") else None)
        rec.update(gates(cfg))
        if opts.get("rtl", True):
            with _output_to(LOG_DIR / f"{cfg.name}.log"):
                rec["rtl"] = rtl_check(cfg, opts["rtl_scenes"], opts["rtl_size"])
            if not rec["rtl"]["bit_exact"]:
                rec["status"] = "mismatch"
                rec["error"] = f"RTL differs from the golden model on {rec['rtl']['mismatched_pixels']} pixels"
    except (ConfigError, FormatError, SynthError) as e:
        rec["status"], rec["error"] = "failed", f"{type(e).__name__}: {e}"
    except Exception as e:  # a simulator or tool failure: recorded with the point, not dropped
        rec["status"], rec["error"] = "failed", f"{type(e).__name__}: {str(e).strip().splitlines()[-1] if str(e).strip() else ''}"
    rec["seconds"] = round(time.perf_counter() - t0, 1)
    rec["log"] = str((LOG_DIR / f"{rec.get('name', 'x')}.log").relative_to(ROOT)) if opts.get("rtl", True) else None
    return rec


def store(path: Path, rec: dict) -> None:
    """A point's record, written whole (a temporary renamed) so that a killed sweep leaves none half-written."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(rec, indent=1) + "\n")
    tmp.replace(path)


def measure_cached(values: dict, opts: dict, pdir: Path, label: str, base: str | None = None,
                   step: str | None = None) -> dict:
    """measure(), read from <pdir>/<point_key>.json when this point was measured on this source."""
    src = source_hash()
    f = pdir / f"{point_key(values, opts, src)}.json"
    if f.exists():
        return json.loads(f.read_text())
    rec = measure(values, opts)
    rec.update({"label": label, "base": base, "step": step, "source": src})
    store(f, rec)
    return rec


def values_of(name_or_cfg) -> dict:
    """A configuration's keys (a name of config/, or a Config)."""
    cfg = load_config(name_or_cfg) if isinstance(name_or_cfg, str) else name_or_cfg
    return config_values(cfg)


def main(argv=None) -> int:
    """`python -m explore.measure --config C`: one configuration's images measured as a sweep point's
    (`images`: per scene the pixels a clock, PSNR against the float reference and against the truth
    with the sweep's sample counts), without its gates or RTL check (`python -m synth.run --config C`
    and `make frame` give those): a configuration file's figures against the truth without a sweep."""
    import sys

    from model.cli import Parser, UserError, check_config, check_range, progress_bar, run_main
    from model.scene.passes import SCENES

    ap = Parser(prog="python -m explore.measure", description=main.__doc__.split("\n\n")[0])
    ap.add_argument("--config", required=True, help="a configuration of config/ or a configuration file's path")
    ap.add_argument("--size", type=int, default=256, help="frame side in pixels (the sweep's: 256)")
    ap.add_argument("--scenes", default=",".join(SCENES), help="comma-separated scene names (default: all eight)")
    ap.add_argument("--json", action="store_true", help="one JSON object per scene instead of a table")
    ap.add_argument("--quiet", action="store_true", help="no progress bar")
    a = ap.parse_args(argv)

    def go():
        check_range("--size", a.size, 8, 1024)
        cfg = load_config(check_config(a.config))
        scenes = [s for s in a.scenes.split(",") if s]
        bad = [s for s in scenes if s not in SCENES]
        if bad or not scenes:
            raise UserError(f"--scenes {a.scenes}: expected names of {', '.join(SCENES)}")
        opts = {"truth_ss": TRUTH_SS, "truth_band_ss": TRUTH_BAND_SS}
        rows = {}
        for s in progress_bar(not a.quiet and sys.stderr.isatty(), iterable=scenes, desc=cfg.name, unit="scene"):
            rows.update(images(cfg, [s], a.size, opts))
            if a.json:
                print(json.dumps({"config": cfg.name, "scene": s, **rows[s]}), flush=True)
        if not a.json:
            print(f"{cfg.name} at {a.size} px (truth {TRUTH_SS}x{TRUTH_SS} samples a pixel, {TRUTH_BAND_SS}x"
                  f"{TRUTH_BAND_SS} in the band): PSNR dB")
            print("| scene | pixels a clock | vs reference | vs truth (interior) | vs truth (textured) |\n|---|---:|---:|---:|---:|")
            for s, v in rows.items():
                print(f"| {s} | {v['pixels_per_clock']} | {v['psnr_ref_db']:.2f} | {v['psnr_truth_db']:.2f} | "
                      f"{v['psnr_truth_textured_db']:.2f} |")
            worst = min(rows, key=lambda s: rows[s]["psnr_truth_db"])
            print(f"worst against the truth: {worst} {rows[worst]['psnr_truth_db']:.2f} dB; against the reference: "
                  f"{min(v['psnr_ref_db'] for v in rows.values()):.2f} dB")
        return 0
    return run_main(ap.prog, go)


if __name__ == "__main__":
    raise SystemExit(main())
