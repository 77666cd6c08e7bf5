"""Model-only rendering of a scene: float reference, golden model, ground truth, reports.

`python -m app.render --scene zone_plate --config full --size 256` (make render)
writes out/render/<scene>/<config>-<size>/: reference.exr (float reference, with
provenance attributes), reference.png, golden.png, unfiltered.png, truth.png (the ground
truth, model.scene.truth: stratified jittered supersampling of the unfiltered float reference,
16x16 a pixel, 32x32 in the tiles of the band where the filter width exceeds N/8 entries;
cached in out/truth/), filter_width.png (Fig. 9c: w from 1 entry, black, to N entries, white)
and report.json (PSNR against the truth over the textured pixels and over that band,
`band_w_gt_n8`, each also over the texture interior, `*_interior_db`: the textured pixels less
a one-pixel rim at every silhouette, model/scene/rim.py; and how far the truth moves between
n/2 x n/2 and n x n samples).
`--all` renders every scene for both configurations and writes the contact sheet
docs/images/renders.png.
"""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from model import reference
from model.hw import golden
from model.hw.config import CONFIG_NAMES, ROOT, doc_stamp, load_config
from model.imageio import compare, contact_sheet, write_image
from app.common import add_truth_args, check_truth_args, git_describe
from model.cli import (Parser, UserError, check_config, config_label, check_range, memory_available, progress_bar, resolve_scene,
                       run_main, staged)
from model.scene.passes import SCENES, composite, configured_texture, frame_size, prepare_passes, scene_approximations, strict_violations, to8
from model.scene.rim import texture_interior
from model.scene.truth import BAND_SS, TILE, TRUTH_SS, truth, truth_image  # noqa: F401 (truth_image: the API)


# memory of a render, measured (moonrise, full): ~1.1 KB a pixel, ~0.7 KB a truth sample; the
# truth renders one TILE x TILE tile of samples at a time, beside its own per-pixel arrays
_BYTES_BASE, _BYTES_PIXEL, _BYTES_SAMPLE = 150 << 20, 1100, 700


def memory_needed(W: int, H: int, truth: bool, truth_ss: int, band_ss: int = BAND_SS) -> int:
    return _BYTES_BASE + _BYTES_PIXEL * W * H + (
        _BYTES_PIXEL * W * H + _BYTES_SAMPLE * (TILE * max(truth_ss, band_ss))**2 if truth else 0)


def truth_dir(out_root: Path | None) -> Path:
    """The truth cache of a render root: out/truth for out/render, else <out_root>/truth."""
    return ROOT / "out" / "truth" if out_root is None else Path(out_root) / "truth"


def render(scene_name: str, config_name: str, size: int, truth: bool = True, truth_ss: int = TRUTH_SS,
           out_root: Path | None = None, progress: bool = True, strict: bool = False, band_ss: int = BAND_SS) -> dict:
    """Render one scene (a name or a .toml path) for one configuration into
    <out_root>/<scene>/<config>-<size>/ (staged: only a completed render is moved into place).
    strict: any approximation the configuration makes to the scene is an error (UserError).
    truth_ss, band_ss: the truth's samples a pixel axis outside and inside the band's tiles."""
    from model.scene.frontend import render_passes
    from model.scene.scene import load_scene

    t0 = time.perf_counter()
    check_range("--size", size, 1, 4096)
    check_range("--truth-ss", truth_ss, 1, 64)
    check_range("--band-ss", band_ss, 1, 64)
    check_config(config_name)
    scene_name, path = resolve_scene(scene_name)
    target = (out_root or ROOT / "out" / "render") / scene_name / f"{config_label(config_name)}-{size}"
    command = f"make render SCENE={scene_name} CONFIG={config_name} SIZE={size}"
    with staged(target, command) as out:
        cfg = load_config(config_name)
        scene = load_scene(path)
        W, H = frame_size(scene, size)
        need, avail = memory_needed(W, H, truth, truth_ss, band_ss), memory_available()
        if avail is not None and need > avail:
            raise UserError(f"--size {size}: a {W}x{H} render" + (" with its truth" if truth else "")
                            + f" needs about {need / 2**30:.1f} GiB of memory, {avail / 2**30:.1f} GiB available "
                            "(a smaller --size or --truth-ss, or --no-truth)")
        passes = render_passes(scene, W, H)
        pds = prepare_passes(cfg, passes)
        approx = scene_approximations(pds)
        bad = strict_violations(pds) if strict else []
        if bad:
            raise UserError(f"--strict: {bad[0]}" + (f" (and {len(bad) - 1} more)" if len(bad) > 1 else ""))
        tr = (path, passes, truth_ss, band_ss, truth_dir(out_root)) if truth else None
        rep = _render_into(out, scene_name, config_name, size, cfg, scene, W, H, pds, tr, progress)
        rep["approximations"] = approx + rep.pop("w_saturated")
        rep["needs"] = _needs(scene_name, passes, W, H, size, cfg)
        rep["seconds"] = round(time.perf_counter() - t0, 2)
        (out / "report.json").write_text(json.dumps(rep, indent=2) + "\n")
    return rep


def _needs(scene_name, passes, W, H, size, cfg) -> dict:
    """What the scene uses (app.needs): per texture and the least configuration."""
    from app.needs import needs_config, needs_of_passes

    nd = needs_of_passes(scene_name, passes, W, H, size, cfg)
    return {"textures": nd["textures"], "config": needs_config(nd)}


def _render_into(out, scene_name, config_name, size, cfg, scene, W, H, pds, tr, progress) -> dict:
    bar = progress_bar(progress, total=len(pds) * 3, desc=f"{scene_name} {config_name} {W}x{H}")
    gold, unf, ref, cref, widths = [], [], [], [], np.zeros((H, W))
    capped = []  # the filter width's saturation at 2^w_cap_log2 entries: a range the format sets, reported
    for pd in pds:
        st = golden.texture_stages(cfg, pd.ti, pd.si, pd.Jm, pd.je)  # (the width at the pixel's centre)
        if pd.ti.filter and len(st["w"]):
            nsat = int(np.count_nonzero(np.asarray(st["w"]) >= cfg.w_cap))
            if nsat:
                capped.append(f"pass {pd.name}: filter width saturated at 2^{cfg.w_cap_log2} entries "
                              f"(formats.w_cap_log2) on {nsat} of {len(st['w'])} pixels: the box there is "
                              "narrower than the pixel's footprint")
        # the pixel's colour: its samples' average with features.samples > 1 (texture_pipeline)
        gold.append((pd.mask, st["rgba"] if cfg.samples == 1 else golden.texture_pipeline(cfg, pd.ti, pd.si, pd.Jm, pd.je)))
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
    bar.close()
    img_truth = tinfo = None
    if tr is not None:
        path, passes, truth_ss, band_ss, cache = tr
        img_truth, tinfo = truth(str(path), cfg, size, ss=truth_ss, band_ss=band_ss, cache_dir=cache,
                                 progress=progress, passes=passes)
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
        "w_saturated": capped,
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
        band = tinfo["band"] & textured
        # the texture interior: the textured pixels less a one-pixel rim at every silhouette, where the
        # truth mixes coverage that no texture filter computes (model/scene/rim.py)
        inner = texture_interior([pd.mask for pd in pds])
        rim = textured & ~inner
        rep["pixels_interior"], rep["pixels_rim"] = int(inner.sum()), int(rim.sum())
        # the rims' own error (filtered): PSNR over the textured pixels were the interior exact is this
        # plus 10 log10(textured / rim pixels), a ceiling that no texture filter passes
        rep["psnr_filtered_vs_truth_rim_db"] = compare(img_gold[rim], img_truth[rim])["psnr_db"]
        imgs = (("filtered", img_gold), ("unfiltered", img_unf), ("reference", img_ref))
        for key, img in imgs:
            rep[f"psnr_{key}_vs_truth_db"] = compare(img[textured], img_truth[textured])["psnr_db"]
            rep[f"psnr_{key}_vs_truth_interior_db"] = compare(img[inner], img_truth[inner])["psnr_db"]
        rep["band_w_gt_n8"] = {"pixels": int(band.sum()), "pixels_interior": int((band & inner).sum()), **{
            f"psnr_{key}_vs_truth_db": compare(img[band], img_truth[band])["psnr_db"] for key, img in imgs}, **{
            f"psnr_{key}_vs_truth_interior_db": compare(img[band & inner], img_truth[band & inner])["psnr_db"]
            for key, img in imgs}}
        rep["truth_supersampling"] = tinfo["rate"]
        rep["truth"] = {k: v for k, v in tinfo.items() if k not in ("band", "textured")}
        rep["truth"]["margin_db"] = truth_margin(rep)
    else:
        rep["psnr_filtered_vs_truth_db"] = rep["psnr_unfiltered_vs_truth_db"] = None
        rep["psnr_filtered_vs_truth_interior_db"] = rep["psnr_unfiltered_vs_truth_interior_db"] = None
    return rep


def truth_margin(rep: dict) -> dict:
    """How much less the truth moves (n/2 against n samples) than the differences measured
    against it, in dB: its movement's PSNR minus the highest PSNR measured against it (filtered,
    unfiltered), over all textured pixels and over the band. Positive: the truth moves less."""
    conv = rep["truth"]["convergence"]
    out = {}
    for region, figs in (("all", rep), ("band", rep["band_w_gt_n8"])):
        measured = [figs[f"psnr_{k}_vs_truth_db"] for k in ("filtered", "unfiltered")]
        moved = conv[region]["psnr_db"]
        out[region] = (None if moved is None or None in measured else round(moved - max(measured), 2))
    return out


def render_all(size: int, truth: bool, progress: bool = True, out_root: Path | None = None,
               strict: bool = False, truth_ss: int = TRUTH_SS, band_ss: int = BAND_SS) -> list[dict]:
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
            rep = render(scene, c, size, truth=truth, progress=progress, out_root=out_root, strict=strict,
                         truth_ss=truth_ss, band_ss=band_ss)
            reps.append(rep)
            print(json.dumps({k: rep.get(k) for k in ("scene", "config", "psnr_golden_vs_reference_db",
                                                       "psnr_filtered_vs_truth_db", "psnr_unfiltered_vs_truth_db",
                                                       "band_w_gt_n8", "seconds")}), flush=True)
        from model.imageio import read_image

        base = root / scene
        row.append((f"{scene}: reference", read_image(base / f"full-{size}" / "reference.png")))
        row.append(("golden full", read_image(base / f"full-{size}" / "golden.png")))
        row.append(("golden reduced", read_image(base / f"reduced-{size}" / "golden.png")))
        row.append(("unfiltered (full)", read_image(base / f"full-{size}" / "unfiltered.png")))
        if truth:
            row.append((f"truth {truth_ss}/{band_ss} ss", read_image(base / f"full-{size}" / "truth.png")))
        row.append(("filter width", read_image(base / f"full-{size}" / "filter_width.png")))
        rows.append(row)
    contact_sheet(docs / "images" / "renders.png", rows, tile=160,
                  title=f"make renders: the eight scenes, {size} px (golden model and float reference)")
    (docs / "images" / "renders.json").write_text(json.dumps(reps, indent=1) + "\n")
    write_scenes_md(reps, size, docs, truth_ss, band_ss)
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


def write_scenes_md(reps: list[dict], size: int, docs: Path = ROOT / "docs", truth_ss: int = TRUTH_SS,
                    band_ss: int = BAND_SS) -> None:
    """docs/scenes.md: each scene beside the paper's description, with its report figures."""
    L = ["# The paper's scenes", "",
         f"Written by `make renders` ({size} px per side, every configuration). Images: "
         "![renders](images/renders.png)", "",
         "Columns: PSNR of the golden model against the float reference (the configuration's error), "
         "its largest error in LSB, and the PSNR against the ground truth of the filtered (antialiased) "
         "and unfiltered golden images, over every textured pixel and over the band `band_w_gt_n8` (the "
         "pixels where the float reference's filter width exceeds N/8 table entries, the horizon's): the "
         "filter helps where filtered > unfiltered. 'interior' is the same over the texture interior, the "
         "textured pixels less a one-pixel rim at every silhouette (model/scene/rim.py: there the truth "
         "averages the pixel's coverage, which the front end samples once, the same error for every "
         "configuration), filtered / unfiltered.", "",
         f"The truth (model/scene/truth.py) is the unfiltered float reference, stratified and jittered "
         f"(seeded), {truth_ss}x{truth_ss} samples a pixel, {band_ss}x{band_ss} in the {TILE}x{TILE}-pixel "
         "tiles that hold a band pixel, one truth per lattice (the configurations' seed and hash_bits). "
         "'truth moves' is how far it moves between n/2 x n/2 and n x n samples (PSNR of the one against "
         "the other, all textured pixels / the band, and the largest change in LSB): an upper bound on its "
         "own error, to read beside the differences measured against it; 'margin' is that PSNR less the "
         "highest PSNR measured against the truth (filtered or unfiltered), all / band: positive where the "
         "truth moves less than the differences it measures.", ""]
    f = lambda v: "-" if v is None else v  # noqa: E731
    for scene in SCENES:
        L += [f"## {scene}", "", PAPER[scene], "",
              "| config | pixels | PSNR vs reference (dB) | max err (LSB) | PSNR filtered vs truth | "
              "PSNR unfiltered vs truth | interior pixels | interior: filtered / unfiltered vs truth | band pixels | "
              "band: filtered vs truth | band: unfiltered vs truth | "
              "truth moves (dB, all / band; max LSB) | margin (dB, all / band) | noise terms used / dropped | seconds |",
              "|---" * 15 + "|"]
        for r in reps:
            if r["scene"] != scene:
                continue
            used = "; ".join(f"{p['terms_used']}/{p['dropped_terms']}" for p in r["passes"])
            b = r.get("band_w_gt_n8") or {}
            tr = r.get("truth") or {"convergence": {"all": {}, "band": {}}, "margin_db": {}}
            cv, mg = tr["convergence"], tr["margin_db"]
            L.append(f"| {r['config']} | {r['pixels_textured']} | {r['psnr_golden_vs_reference_db']} | "
                     f"{r['max_abs_error_lsb']} | {f(r['psnr_filtered_vs_truth_db'])} | "
                     f"{f(r['psnr_unfiltered_vs_truth_db'])} | {f(r.get('pixels_interior'))} | "
                     f"{f(r.get('psnr_filtered_vs_truth_interior_db'))} / {f(r.get('psnr_unfiltered_vs_truth_interior_db'))} | "
                     f"{f(b.get('pixels'))} | "
                     f"{f(b.get('psnr_filtered_vs_truth_db'))} | {f(b.get('psnr_unfiltered_vs_truth_db'))} | "
                     f"{f(cv['all'].get('psnr_db'))} / {f(cv['band'].get('psnr_db'))}; {f(cv['all'].get('max_abs_lsb'))} | "
                     f"{f(mg.get('all'))} / {f(mg.get('band'))} | {used} | {r['seconds']} |")
        L.append("")
    L.append(doc_stamp(sorted({r["config"] for r in reps})))
    (docs / "scenes.md").write_text("\n".join(L) + "\n")


def main(argv=None) -> int:
    ap = Parser(prog="render", description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="zone_plate", help="a scene name (scenes/NAME.toml) or a path to a .toml file")
    ap.add_argument("--config", default="full", help=f"one of {', '.join(CONFIG_NAMES)}")
    ap.add_argument("--size", type=int, default=256, help="image width, 1..4096 (and what memory allows)")
    ap.add_argument("--all", action="store_true", help="all scenes, both configurations, contact sheet")
    ap.add_argument("--no-truth", action="store_true", help="skip the supersampled ground truth")
    add_truth_args(ap, TRUTH_SS, BAND_SS)
    ap.add_argument("--out", type=Path, help="output root (default out/render; --all: its docs too)")
    ap.add_argument("--strict", action="store_true", help="any approximation of the scene by the configuration is an error")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)

    def go():
        check_range("--size", a.size, 1, 4096)
        check_truth_args(a)
        if a.all:
            render_all(a.size, truth=not a.no_truth, progress=not a.quiet, out_root=a.out, strict=a.strict,
                       truth_ss=a.truth_ss, band_ss=a.band_ss)
        else:
            rep = render(a.scene, a.config, a.size, truth=not a.no_truth, truth_ss=a.truth_ss, out_root=a.out,
                         progress=not a.quiet, strict=a.strict, band_ss=a.band_ss)
            print(json.dumps(rep, indent=2))
        return 0

    return run_main("render", go)


if __name__ == "__main__":
    sys.exit(main())
