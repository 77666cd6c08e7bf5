"""The animation test (paper section 4.4): frames of a flight into the horizon (seascape) or of
an advancing phase (fire), filtered and unfiltered, against the converged truth of every frame.

    python -m app.animation --scene seascape --config full --frames 16 --size 128 [--rtl]
    (make animation SCENE=seascape FRAMES=16 SIZE=128 [RTL=1])

The animation is scenes/animation/<scene>.toml ([animation]: scene, frames, position_end and
look_at_end of the camera, or phi_texture / phi_axis / phi_end, the phase of a texture's noise
terms; each moves linearly over t = i / (frames - 1)). Every frame is rendered by the golden
model with the box filter and without it, and its truth by model.scene.truth.render_truth
(cached in out/truth/ keyed by the animation, the frame and the sources). Per frame, over the
band where the filter width exceeds N/8 entries (band_w_gt_n8) and over every textured pixel:
PSNR of filtered and unfiltered against the truth; and the temporal flicker, the mean absolute
frame-to-frame change of the error against the truth (RGB, LSB) over the pixels in the band of
both frames. --rtl runs every pass of every frame, filtered and unfiltered, through the RTL
under Verilator in one call (sim.frame_rtl.run_passes_rtl: one simulator start for all of
them, or as few as the harness memories allow), checks every pixel bit-exact against the golden
model, frame by frame, and reports the simulator starts and the seconds (report.json "rtl").
Writes out/animation/<scene>/<config>-<size>/ (staged: frames.gif,
filtered beside unfiltered beside truth; report.json), and, unless --no-docs, docs/animation.md
and docs/images/animation_<scene>.png (matplotlib; with --out: <out>/docs).
"""
from __future__ import annotations

import hashlib
import json
import sys
import time
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np

from app.common import add_truth_args, check_truth_args, git_describe
from hdlbuild import need_tool
from model.cli import Parser, UserError, check_config, config_label, check_range, progress_bar, run_main, staged
from model.hw import golden
from model.hw.config import CONFIG_NAMES, ROOT, doc_stamp, load_config, rtl_source_hash
from model.imageio import compare
from model.scene.passes import composite, frame_size, prepare_passes, scene_approximations, scene_path, to8
from model.scene import truth as T
from model.scene.rim import texture_interior

ANIM_DIR = ROOT / "scenes" / "animation"
_KEYS = {"scene", "frames", "position_end", "look_at_end", "phi_texture", "phi_axis", "phi_end"}


def load_animation(name: str) -> dict:
    """scenes/animation/<name>.toml (or a path) -> {"path", "scene", "frames", ...}; UserError names
    the file and key."""
    p = Path(name) if name.endswith(".toml") else ANIM_DIR / f"{name}.toml"
    if not p.is_file():
        known = ", ".join(sorted(x.stem for x in ANIM_DIR.glob("*.toml")))
        raise UserError(f"--scene {name}: no animation (scenes/animation/: {known})")
    try:
        a = tomllib.loads(p.read_text()).get("animation")
    except tomllib.TOMLDecodeError as e:
        raise UserError(f"{p}: malformed TOML: {e}") from None
    if not isinstance(a, dict):
        raise UserError(f"{p}: animation: expected an [animation] table")
    bad = sorted(set(a) - _KEYS)
    if bad:
        raise UserError(f"{p}: animation.{bad[0]}: unknown key (expected one of {', '.join(sorted(_KEYS))})")
    if "scene" not in a:
        raise UserError(f"{p}: animation.scene: missing (a scene name)")
    for k in ("position_end", "look_at_end"):
        v = a.get(k)
        if v is not None and not (isinstance(v, list) and len(v) == 3 and all(isinstance(x, (int, float)) for x in v)):
            raise UserError(f"{p}: animation.{k}: expected 3 numbers, got {v!r}")
    if "phi_end" in a and "phi_texture" not in a:
        raise UserError(f"{p}: animation.phi_texture: missing (phi_end needs the texture whose phase moves)")
    return {"path": p, "frames": 16, "phi_axis": 2, **a}


def frame_scene(scene, anim: dict, t: float):
    """The scene at time t in [0, 1]: the camera moved, the phase advanced."""
    cam = scene.camera
    pos, look = cam.position, cam.look_at
    if "position_end" in anim:
        d = np.asarray(anim["position_end"], float) - cam.position
        pos = cam.position + t * d
        look = cam.look_at + t * (np.asarray(anim["look_at_end"], float) - cam.look_at if "look_at_end" in anim else d)
    elif "look_at_end" in anim:
        look = cam.look_at + t * (np.asarray(anim["look_at_end"], float) - cam.look_at)
    textures = dict(scene.textures)
    if "phi_texture" in anim:
        name = anim["phi_texture"]
        if name not in textures:
            raise UserError(f"{anim['path']}: animation.phi_texture: no texture {name!r} in the scene "
                            f"(known: {', '.join(textures)})")
        tex = textures[name]
        terms = []
        for term in tex.terms:
            o = np.array(term.o, float)
            o[int(anim["phi_axis"])] += t * float(anim.get("phi_end", 0.0))
            terms.append(replace(term, o=o))
        textures[name] = replace(tex, terms=terms)
    return replace(scene, camera=replace(cam, position=pos, look_at=look), textures=textures)


def _images(cfg, pds, shape, bg):
    filt, unf = [], []
    for pd in pds:
        filt.append((pd.mask, golden.texture_pipeline(cfg, pd.ti, pd.si, pd.Jm, pd.je)))
        ti_off = golden.TexInt(**{**pd.ti.__dict__, "filter": False})
        unf.append((pd.mask, golden.texture_pipeline(cfg, ti_off, pd.si, pd.Jm, pd.je)))
    return filt, unf


def _rtl_passes(pds, layers_f, layers_u) -> list:
    """A frame's passes for the RTL, filtered and unfiltered: [((texint, s, Jm, je), golden rgba), ...]."""
    out = []
    for pd, (_, gf), (_, gu) in zip(pds, layers_f, layers_u):
        if len(pd.si):
            ti_off = golden.TexInt(**{**pd.ti.__dict__, "filter": False})
            out += [((pd.ti, pd.si, pd.Jm, pd.je), gf), ((ti_off, pd.si, pd.Jm, pd.je), gu)]
    return out


def _rtl_exact(config_name, frames) -> tuple[list[int], dict]:
    """Every pass of every frame (frames: _rtl_passes of each) through the RTL under Verilator in
    one run_passes_rtl call: the pixels of each frame where the RTL differs from the golden
    model (any bit of RGBA), and {"starts": simulator starts, "seconds": wall time of the whole
    check, "sim_seconds": of the simulator runs, start-up included, "passes", "pixels"}."""
    from sim.frame_rtl import run_passes_rtl

    t0 = time.perf_counter()
    flat = [p for f in frames for p in f]
    rgba, info = run_passes_rtl(config_name, "verilator", [p for p, _ in flat], return_stats=True)
    bad, k = [], 0
    for f in frames:
        bad.append(sum(int(np.any(r != g, axis=-1).sum()) for r, (_, g) in zip(rgba[k:k + len(f)], f)))
        k += len(f)
    return bad, {"starts": info["starts"], "seconds": round(time.perf_counter() - t0, 2),
                 "sim_seconds": round(info["seconds"], 2), "passes": len(flat),
                 "pixels": int(sum(len(g) for _, g in flat))}


def _psnr(a, b, mask):
    return compare(a[mask], b[mask])["psnr_db"] if mask.any() else None


def run(scene_arg: str, config_name: str, frames: int | None, size: int, rtl: bool = False,
        out_root: Path | None = None, docs: bool = True, progress: bool = True,
        truth_ss: int = T.TRUTH_SS, band_ss: int = T.BAND_SS) -> dict:
    from model.scene.frontend import render_passes
    from model.scene.scene import load_scene

    t0 = time.perf_counter()
    check_config(config_name)
    check_range("--size", size, 4, 1024)
    anim = load_animation(scene_arg)
    n = check_range("--frames", int(frames or anim["frames"]), 2, 1000)
    if rtl:
        need_tool("verilator")
        from sim.frame_rtl import frame_cxx

        frame_cxx()  # the frame harness's C++ compiler (FRAME_CXX)
    spath = scene_path(anim["scene"])
    if not spath.is_file():
        raise UserError(f"{anim['path']}: animation.scene: no such scene {anim['scene']!r}")
    name = anim["path"].stem
    target = Path(out_root or ROOT / "out") / "animation" / name / f"{config_label(config_name)}-{size}"
    command = f"make animation SCENE={name} CONFIG={config_name} FRAMES={n} SIZE={size}" + (" RTL=1" if rtl else "")
    with staged(target, command) as out:
        cfg = load_config(config_name)
        scene = load_scene(spath)
        W, H = frame_size(scene, size)
        key = hashlib.sha256(anim["path"].read_bytes() + T.source_key(spath).encode()).hexdigest()[:12]
        cache = T.CACHE_DIR if out_root is None else Path(out_root) / "truth"
        bar = progress_bar(progress, total=n, desc=f"animation {name} {config_name} {W}x{H}")
        rows, gif, prev, approx, rtl_frames = [], [], None, [], []
        for i in range(n):
            t = i / (n - 1)
            sc = frame_scene(scene, anim, t)
            passes = render_passes(sc, W, H)
            pds = prepare_passes(cfg, passes)
            approx += [a for a in scene_approximations(pds) if a not in approx]
            lf, lu = _images(cfg, pds, (H, W), sc.background)
            img_f, img_u = composite(lf, (H, W), sc.background), composite(lu, (H, W), sc.background)
            stem = (f"anim-{name}-{i}of{n}-{W}x{H}-ss{truth_ss}-{band_ss}-j{T.JITTER_SEED}-p{cfg.seed}"
                    f"-h{cfg.hash_bits}-{key}")
            hit = T.load_cached(cache, stem)
            if hit is None:
                img_t, half, band, textured, meta = T.render_truth(sc, cfg, W, H, truth_ss, band_ss, passes=passes)
                info = T.save_cached(cache, stem, img_t, half, band, textured, {"frame": i, **meta})
            else:
                img_t, info = hit
            textured = np.zeros((H, W), bool)
            for pd in pds:
                textured |= pd.mask
            band = info["band"] & textured
            inner = band & texture_interior([pd.mask for pd in pds])  # the band less its silhouette rims
            err_f, err_u = img_f[..., :3] - img_t[..., :3], img_u[..., :3] - img_t[..., :3]
            row = {"frame": i, "t": round(t, 4), "band_pixels": int(band.sum()),
                   "band_psnr_filtered_db": _psnr(img_f, img_t, band), "band_psnr_unfiltered_db": _psnr(img_u, img_t, band),
                   "psnr_filtered_db": _psnr(img_f, img_t, textured), "psnr_unfiltered_db": _psnr(img_u, img_t, textured),
                   "band_psnr_filtered_interior_db": _psnr(img_f, img_t, inner),
                   "band_psnr_unfiltered_interior_db": _psnr(img_u, img_t, inner),
                   "truth_moves_band_db": info["convergence"]["band"]["psnr_db"]}
            if prev is not None:
                for suffix, both in (("", band & prev[0]), ("_interior", inner & prev[3])):
                    for key, e, pe in (("filtered", err_f, prev[1]), ("unfiltered", err_u, prev[2])):
                        row[f"flicker_{key}{suffix}_lsb"] = (round(float(np.abs(e - pe)[both].mean()), 4)
                                                             if both.any() else None)
            prev = (band, err_f, err_u, inner)
            if rtl:  # run once for all frames, after the loop
                rtl_frames.append(_rtl_passes(pds, lf, lu))
            rows.append(row)
            gif.append(np.concatenate([to8(img_f), to8(img_u), to8(img_t)], axis=1)[..., :3])
            bar.update()
        bar.close()
        if rtl:
            bad, rtl_info = _rtl_exact(config_name, rtl_frames)
            for row, b in zip(rows, bad):
                row["rtl_mismatches"] = b
        from PIL import Image

        ims = [Image.fromarray(g) for g in gif]
        ims[0].save(out / "frames.gif", save_all=True, append_images=ims[1:], duration=120, loop=0)

        def mean(k):
            v = [r[k] for r in rows if r.get(k) is not None]
            return round(float(np.mean(v)), 3) if v else None

        rep = {"status": "ok", "animation": name, "scene": anim["scene"], "config": config_name, "frames": n,
               "width": W, "height": H, "command": command, "git": git_describe(), "rtl_hash": rtl_source_hash(),
               "truth": f"{truth_ss}x{truth_ss}, {band_ss}x{band_ss} in the band's tiles", "approximations": approx,
               "mean": {k: mean(k) for k in ("band_psnr_filtered_db", "band_psnr_unfiltered_db", "psnr_filtered_db",
                                             "psnr_unfiltered_db", "flicker_filtered_lsb", "flicker_unfiltered_lsb",
                                             "band_psnr_filtered_interior_db", "band_psnr_unfiltered_interior_db",
                                             "flicker_filtered_interior_lsb", "flicker_unfiltered_interior_lsb")},
               "rows": rows}
        if rtl:
            rep["rtl_bit_exact"] = all(r["rtl_mismatches"] == 0 for r in rows)
            rep["rtl"] = rtl_info
        rep["seconds"] = round(time.perf_counter() - t0, 2)
        (out / "report.json").write_text(json.dumps(rep, indent=2) + "\n")
    if docs:
        write_docs(rep, ROOT / "docs" if out_root is None else Path(out_root) / "docs")
    if rtl and not rep["rtl_bit_exact"]:
        bad = [r["frame"] for r in rows if r["rtl_mismatches"]]
        raise UserError(f"--rtl: the RTL differs from the golden model on frame(s) {bad} (report: {target}/report.json)")
    return rep


def _stem(rep: dict) -> str:
    return f"{rep['animation']}_{rep['config']}_{rep['frames']}f_{rep['width']}" + ("_rtl" if "rtl_bit_exact" in rep else "")


def write_docs(rep: dict, docs: Path) -> None:
    """docs/animation.md: one section per animation (the others kept), and its plot."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = rep["rows"]
    (docs / "images").mkdir(parents=True, exist_ok=True)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.6, 3.6), dpi=100)
    fr = [r["frame"] for r in rows]
    for k, lab in (("band_psnr_filtered_db", "filtered"), ("band_psnr_unfiltered_db", "unfiltered")):
        a1.plot(fr, [r[k] if r[k] is not None else np.nan for r in rows], marker="o", label=lab)
    a1.set_xlabel("frame")
    a1.set_ylabel("PSNR against the truth, band w > N/8 (dB)")
    a1.legend()
    a1.grid(True, alpha=0.3)
    for k, lab in (("flicker_filtered_lsb", "filtered"), ("flicker_unfiltered_lsb", "unfiltered")):
        a2.plot(fr[1:], [r.get(k) if r.get(k) is not None else np.nan for r in rows[1:]], marker="o", label=lab)
    a2.set_xlabel("frame")
    a2.set_ylabel("flicker in the band (mean |change of error|, LSB)")
    a2.legend()
    a2.grid(True, alpha=0.3)
    fig.suptitle(f"{rep['command']}")
    fig.tight_layout()
    img = docs / "images" / f"animation_{_stem(rep)}.png"
    fig.savefig(img.with_name(f".{img.name}"), format="png")
    plt.close(fig)
    img.with_name(f".{img.name}").replace(img)

    state = docs / "images" / "animation.json"
    reps = json.loads(state.read_text()) if state.is_file() else {}
    reps[rep["command"]] = rep  # one section per distinct command
    state.write_text(json.dumps(reps, indent=1) + "\n")
    L = ["# The animation test (paper section 4.4)", "",
         "Written by `make animation` (app/animation.py), one section per animation, each from its "
         "command. Each frame: the golden model with the box filter and without it, against the frame's truth "
         "(model/scene/truth.py, stratified jittered, more samples in the tiles of the band where the filter "
         "width exceeds N/8 entries); PSNR over that band (`band_w_gt_n8`) and over every textured pixel; flicker: "
         "the mean absolute frame-to-frame change of the error against the truth over the pixels in the band "
         "of both frames (RGB, LSB). The GIF of each run (filtered | unfiltered | truth) is in its output "
         "directory, out/animation/<scene>/<config>-<size>/frames.gif.", ""]
    for cmd, r in sorted(reps.items()):
        m, nm = r["mean"], r["animation"]
        L += [f"## {nm}: {r['config']}, {r['frames']} frames, {r['width']}x{r['height']}", "",
              f"`{cmd}` ({r['seconds']} s; git {r['git']}; truth {r['truth']}"
              + (f"; RTL bit-exact on every frame: {r['rtl_bit_exact']}" if "rtl_bit_exact" in r else "")
              + (f", {r['rtl']['passes']} passes in {r['rtl']['starts']} simulator start(s), {r['rtl']['seconds']} s"
                 if "rtl" in r else "") + ").", "",
              f"![{nm}](images/animation_{_stem(r)}.png)", "",
              "| | filtered | unfiltered |", "|---|---|---|",
              f"| mean PSNR in the band (dB) | {m['band_psnr_filtered_db']} | {m['band_psnr_unfiltered_db']} |",
              f"| mean PSNR, all textured pixels (dB) | {m['psnr_filtered_db']} | {m['psnr_unfiltered_db']} |",
              f"| mean flicker in the band (LSB) | {m['flicker_filtered_lsb']} | {m['flicker_unfiltered_lsb']} |", "",
              "| frame | band pixels | band filtered (dB) | band unfiltered (dB) | flicker filtered | flicker unfiltered "
              "| truth moves in band (dB) |", "|---|---|---|---|---|---|---|"]
        for x in r["rows"]:
            L.append(f"| {x['frame']} | {x['band_pixels']} | {x['band_psnr_filtered_db']} | {x['band_psnr_unfiltered_db']} | "
                     f"{x.get('flicker_filtered_lsb', '-')} | {x.get('flicker_unfiltered_lsb', '-')} | "
                     f"{x['truth_moves_band_db']} |")
        L.append("")
    # a section of an older run (or from before the runs recorded their rtl/) keeps the doc stale
    L.append(doc_stamp(sorted({r["config"] for r in reps.values()}), ran_on=[r.get("rtl_hash") for r in reps.values()]))
    (docs / "animation.md").write_text("\n".join(L) + "\n")


def main(argv=None) -> int:
    ap = Parser(prog="animation", description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="seascape", help="an animation of scenes/animation/ (or a .toml path)")
    ap.add_argument("--config", default="full", help=f"one of {', '.join(CONFIG_NAMES)}")
    ap.add_argument("--frames", type=int, help="frames (default: the animation's)")
    ap.add_argument("--size", type=int, default=128, help="image width, 4..1024")
    ap.add_argument("--rtl", action="store_true", help="every pass also through the RTL (Verilator), bit-exact")
    add_truth_args(ap, T.TRUTH_SS, T.BAND_SS)
    ap.add_argument("--out", type=Path, help="output root (default out/; the docs then go to <out>/docs)")
    ap.add_argument("--no-docs", action="store_true", help="do not write docs/animation.md")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)

    def go():
        check_truth_args(a)
        rep = run(a.scene, a.config, a.frames, a.size, a.rtl, a.out, not a.no_docs, not a.quiet, a.truth_ss, a.band_ss)
        print(json.dumps({k: rep[k] for k in ("animation", "config", "frames", "mean", "seconds")}
                         | ({"rtl_bit_exact": rep["rtl_bit_exact"], "rtl": rep["rtl"]} if a.rtl else {})))
        return 0

    return run_main("animation", go)


if __name__ == "__main__":
    sys.exit(main())
