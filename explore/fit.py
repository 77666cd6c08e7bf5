"""`make fit SCENE=a[,b...] DB=<target> [PXCLK=<min>] [AGAINST=truth]`: the smallest-GE configuration for some scenes.

    python -m explore.fit --scenes marble,seascape --db 38 [--pxclk 0.25] [--size 256] [--rtl-size 64]
                          [--against reference|truth] [--features-of full] [--name NAME] [--out out/fit]
                          [--results out/explore/results.json]

The target DB is the worst scene's PSNR over its textured pixels against the float reference of
the scene as written (--against reference, the default) or against its converged truth (--against
truth: model.scene.truth, the pixel's true average, what the eye sees; issue 27). Every figure
the fit checks -- the sweep's points it may start from, the descent, the fit corpus, the held-out
views -- is then measured against the same image.

1. What the scenes need (app.needs): terms, transform and amplitude kinds, blend, noise
   gradient, quadric, filter. `--features-of CONFIG` fixes the features to a configuration's
   instead (the "full, revisited" search: every feature of `full`, only the formats searched).
2. The start: the smallest-GE point of the sweep's results (out/explore/results.json and its
   stored points) that has those features or more, meets the target on these scenes at this size
   and runs at least PXCLK pixels per clock on each; else the named configuration with the fewest
   gates that has them. Its features are then cut to what the scenes need, and its noise units to
   the fewest that keep PXCLK (U >= ceil(K / floor(1 / PXCLK))).
3. A descent over the formats, on the golden model against the float reference (cheap: no
   synthesis): each precision (a word with its fraction), range word and width is narrowed one
   bit at a time while the worst scene stays at or above the target; the lattice (seed,
   hash_bits) stays the start's, since it is part of what the texture is.
4. The result is measured like a sweep point (explore.measure: gates, images, and the Verilator
   check) and stored with the sweep's points, written as a configuration file
   <out>/<name>.toml with <out>/<name>.json (its record, the start and the steps), and every
   scene is rendered with it through the RTL under Verilator at --rtl-size, bit-exact against the
   golden model (<out>/<name>/<scene>.png). Exit status 1 when no configuration meets the target
   or the RTL differs; 2 for a bad argument, before any work.

Held out (issue 26): the descent also watches the **fit corpus** (model.scene.corpus, seed
FIT_SEED): --corpus N of its scenes (default 16) whose needs the scenes' needs cover (transform
and amplitude kinds, quadric, blend, terms), at --corpus-size px; a narrowing step must keep their
5th-percentile PSNR at or above min(target, the start's 5th percentile - 1 dB), so that a format is
not cut to the scenes' own dyadic parameters. The answer is then checked on **held-out views** of
the scenes, which the descent never saw: each at half and one and a half times --size, and with the
camera moved (20 degrees about the up axis, 15% closer; a screen-space scene has only the sizes);
the report's `held_out_views` says how far each falls below the target.
"""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path

from explore import measure
from model.hw.config import (CONFIG_NAMES, QUADRIC_CLOCKS, SAT_FILTERS, ConfigError, clocks_per_pixel, config_toml, config_values,
                             load_config)
from model.hw.quantize import FormatError
from model.cli import Parser, UserError, check_range, progress_bar, run_main
from model.scene.passes import SCENES

ROOT = measure.ROOT
FEATURE_ORDER = {"transform": ("pow2", "affine"), "amplitude": ("pow2", "any"), "blend": ("linear", "cubic"),
                 "quadric": ("diagonal", "full"), "filter": ("none", "mip", "sat")}
# the descent's moves, in the order tried: (label, {key: delta}) -- precision pairs keep the range
MOVES = [("s precision", {"s_w": -1, "s_frac": -1}), ("q precision", {"q_w": -1, "q_frac": -1}),
         ("t precision", {"t_w": -1, "t_frac": -1}), ("a precision", {"a_w": -1, "a_frac": -1}),
         ("s range", {"s_w": -1}), ("q range", {"q_w": -1}), ("t range", {"t_w": -1}), ("a range", {"a_w": -1}),
         ("p_frac", {"p_frac": -1}), ("n_frac", {"n_frac": -1}), ("f_frac", {"f_frac": -1}),
         ("c_frac", {"c_frac": -1}), ("j_w", {"j_w": -1}), ("je_w", {"je_w": -1}), ("norm_bits", {"norm_bits": -1}),
         ("w_cap_log2", {"w_cap_log2": -1}), ("div_bits", {"div_bits": -1})]
# another order: the noise term's own formats first (8 of full's 10 noise terms' worth of gates
# are in them), the coordinates after
ORDERS = {"formats": MOVES,
          "noise-first": [m for m in MOVES if m[0] in ("p_frac", "n_frac", "t precision", "a precision", "t range",
                                                       "a range")]
                         + [m for m in MOVES if m[0] not in ("p_frac", "n_frac", "t precision", "a precision",
                                                             "t range", "a range")]}
DIV_START = 12  # an exact division (div_bits 0) is first replaced by a 12-bit normalised one, then narrowed


def has_features(v: dict, need: dict) -> bool:
    if v["noise_terms"] < need["noise_terms"] or (need["noise_gradient"] and not v["noise_gradient"]):
        return False
    return all(FEATURE_ORDER[k].index(v[k]) >= FEATURE_ORDER[k].index(need[k]) for k in FEATURE_ORDER if k in need)


AGAINST = ("reference", "truth")  # what the target's PSNR is measured against
_KEY = {"reference": "psnr_ref_db", "truth": "psnr_truth_db"}  # a sweep record's figure of each


def _scene_ok(rec: dict, scenes, db: float, pxclk: float, size: int, against: str = "reference") -> bool:
    if rec.get("status") != "ok" or rec.get("opts", {}).get("size") != size:
        return False
    sc = rec["scenes"]
    return all(s in sc and sc[s].get(_KEY[against]) is not None and sc[s][_KEY[against]] >= db
               and (sc[s]["pixels_per_clock"] or 1) >= pxclk for s in scenes)


def stored_records(results: Path) -> list[dict]:
    recs = []
    if results.exists():
        recs += json.loads(results.read_text())["records"]
    pdir = results.parent / "points"
    if pdir.is_dir():
        recs += [json.loads(p.read_text()) for p in sorted(pdir.glob("*.json"))]
    src = measure.source_hash()
    return [r for r in recs if r.get("source") == src]  # measured on this source only


def units_for(k: int, pxclk: float) -> int:
    """The fewest noise units that keep pxclk pixels a clock with k terms."""
    if k == 0:
        return 1
    per = max(1, int(1 / pxclk + 1e-9))  # clocks a pixel allowed
    return -(-k // per)


def shape(v: dict, need: dict, pxclk: float, fixed: bool) -> dict:
    """The start cut to what the scenes need (unless the features are fixed) and to PXCLK."""
    v = dict(v)
    if not fixed:
        v.update({k: need[k] for k in FEATURE_ORDER})
        v["noise_gradient"] = need["noise_gradient"]
        v["noise_terms"] = need["noise_terms"]
    k = v["noise_terms"]
    v["noise_units"] = min(max(1, k), max(units_for(k, pxclk), 1)) if not fixed else v["noise_units"]
    per = max(1, int(1 / pxclk + 1e-9))
    folded = 0 < v["noise_units"] < k
    per_s = max(1, per // v.get("samples", 1))  # clocks a sample allowed
    # the quadric folds as far as the clocks a sample allow: 6 clocks on one multiplier, 2 on three
    fold = max([c for c in QUADRIC_CLOCKS if c <= per_s] or [1])
    v["quadric_clocks"] = fold if (folded and v["quadric"] == "diagonal" and not fixed) else \
        (v["quadric_clocks"] if fixed else 1)
    # and the colour map's box filter a channel a clock where a sample has 4 clocks (cmap_clocks = 4)
    cm = 4 if (folded and per_s >= 4 and v["filter"] == "sat" and not v.get("fpga_regs")) else 1
    v["cmap_clocks"] = v.get("cmap_clocks", 1) if fixed else cm
    return v


def scene_db(cfg, scene: str, size: int, against: str = "reference") -> float | None:
    """PSNR (dB, None: identical) of the golden image of `scene` (a name or a .toml path) over its
    textured pixels, against its float reference or its converged truth (model.scene.truth at the
    sweep's sample counts, measure.TRUTH_SS and TRUTH_BAND_SS, so that a sweep point's figure and the
    descent's are the same; cached on disk: the first call for a scene, size and lattice renders it)."""
    from app.quality import scene_images, scene_psnr
    from model.imageio import compare
    from model.scene.truth import truth_image

    if against == "reference":
        return scene_psnr(cfg, scene, size)[0]
    im = scene_images(cfg, scene, size)
    t = im["textured"]
    tr = truth_image(scene, cfg, size, ss=measure.TRUTH_SS, band_ss=measure.TRUTH_BAND_SS)
    return compare(im["golden"][t], tr[t])["psnr_db"]


def evaluate(v: dict, scenes, sizes, against: str = "reference") -> float | None:
    """The worst PSNR (golden model against the float reference, or the truth) of `scenes` at
    every frame side of `sizes`, or None when the configuration is rejected or a scene does not fit it."""
    try:
        cfg = measure.point_config(v)
        return min(min(scene_db(cfg, s, z, against) or 200.0, 200.0) for s in scenes for z in sizes)
    except (ConfigError, FormatError):
        return None


KIND_ORDER = {"transform": ("pow2", "diagonal", "affine"), "amplitude": ("pow2", "any"), "quadric": ("diagonal", "full")}


def corpus_scenes(need: dict, n: int) -> list[str]:
    """Up to n scenes of the fit corpus whose needs `need` covers (their paths)."""
    from model.scene.corpus import FIT_SEED, load_index, write_corpus

    if n <= 0:
        return []
    d = ROOT / "out" / "corpus" / f"seed{FIT_SEED}"
    if not (d / "index.json").is_file() or json.loads((d / "index.json").read_text()).get("n", 0) < 200:
        d = write_corpus(ROOT / "out" / "corpus", FIT_SEED, 200)
    need_t = "pow2" if need["transform"] == "pow2" else "affine"
    out = []
    for e in load_index(d):
        t = e["tags"]
        ok = (KIND_ORDER["transform"].index(t["transform"]) <= KIND_ORDER["transform"].index(need_t)
              and KIND_ORDER["amplitude"].index(t["amplitude"]) <= KIND_ORDER["amplitude"].index(need["amplitude"])
              and KIND_ORDER["quadric"].index(t["quadric"]) <= KIND_ORDER["quadric"].index(need["quadric"])
              and t["noise_terms"] <= need["noise_terms"] and all(b == need["blend"] for b in t["blends"])
              and not t.get("unfiltered") and (need["noise_gradient"] or not t["noise_gradient"]))
        if ok:
            out.append(str(e["path"]))
        if len(out) >= n:
            break
    return out


def corpus_p5(v: dict, paths, size: int, against: str = "reference") -> float | None:
    """The 5th-percentile PSNR of the corpus scenes (those the configuration renders)."""
    import numpy as np

    if not paths:
        return None
    try:
        cfg = measure.point_config(v)
    except ConfigError:
        return None
    vals = []
    for p in paths:
        try:
            vals.append(min(scene_db(cfg, p, size, against) or 200.0, 200.0))
        except FormatError:
            continue
    return float(np.percentile(vals, 5)) if vals else None


def moved_camera(scene: str, out_dir: Path) -> Path | None:
    """The scene with its camera turned 20 degrees about the up axis around look_at and moved 15%
    closer (None for a scene of screen-space objects only, which no camera moves)."""
    import tomllib

    import numpy as np

    from model.scene.corpus import rotation, to_toml
    from model.scene.passes import scene_path

    raw = tomllib.loads(scene_path(scene).read_text())
    if all(o.get("type") == "screen" for o in raw.get("object", [])):
        return None
    cam = raw["camera"]
    eye, at = np.asarray(cam["position"], float), np.asarray(cam["look_at"], float)
    cam["position"] = (at + 0.85 * rotation(cam.get("up", [0, 1, 0]), 20.0) @ (eye - at)).round(6).tolist()
    raw["scene"] = {**raw.get("scene", {}), "name": f"{Path(scene).stem}_moved"}
    out_dir.mkdir(parents=True, exist_ok=True)
    p = out_dir / f"{Path(scene).stem}_moved.toml"
    p.write_text(to_toml({"comment": f"held-out view of {scene}: the camera moved (explore/fit.py)", **raw}))
    return p


def held_out_views(cfg, scenes, db: float, size: int, out_dir: Path, against: str = "reference") -> list[dict]:
    """Each scene at half and 1.5 times the size and with a moved camera: PSNR against its float
    reference (or its truth), and how far below the target (0 when it holds)."""
    rows = []
    for s in scenes:
        views = [(f"{max(8, size // 2)} px", s, max(8, size // 2)), (f"{min(1024, size * 3 // 2)} px", s,
                                                                       min(1024, size * 3 // 2))]
        mc = moved_camera(s, out_dir)
        if mc is not None:
            views.append(("camera moved", str(mc), size))
        for label, path, z in views:
            try:
                q = scene_db(cfg, path, z, against)
                q = 200.0 if q is None else q
                rows.append({"scene": s, "view": label, "psnr_db": round(q, 2), "below_target_db": round(max(0.0, db - q), 2)})
            except FormatError as e:
                rows.append({"scene": s, "view": label, "error": str(e)})
    return rows


def descend(v: dict, scenes, db: float, sizes, log: list, progress: bool = True, order: str = "formats",
            corpus=(), corpus_size: int = 48, against: str = "reference") -> dict:
    floor = None
    if corpus:
        p0 = corpus_p5(v, corpus, corpus_size, against)
        floor = None if p0 is None else min(db, p0 - 1.0)
        log.append({"move": f"fit corpus: {len(corpus)} scenes at {corpus_size} px", "corpus_p5_db":
                    None if p0 is None else round(p0, 2), "corpus_floor_db": None if floor is None else round(floor, 2)})

    def holds(w, q):
        if q is None or q < db:
            return False
        if floor is None:
            return True
        c = corpus_p5(w, corpus, corpus_size, against)
        return c is not None and c >= floor

    if v["div_bits"] == 0 and v["filter"] in SAT_FILTERS:
        w = dict(v, div_bits=DIV_START)
        q = evaluate(w, scenes, sizes, against)
        if holds(w, q):
            log.append({"move": f"div_bits 0 -> {DIV_START}", "worst_db": round(q, 2)})
            v = w
    bar = progress_bar(progress, desc="fit: formats", unit="knob", iterable=ORDERS[order])
    for label, d in bar:
        while True:
            w = {**v, **{k: v[k] + x for k, x in d.items()}}
            if label == "div_bits" and w["div_bits"] < 1:
                break
            q = evaluate(w, scenes, sizes, against)
            if not holds(w, q):
                break
            log.append({"move": label, "to": {k: w[k] for k in d}, "worst_db": round(q, 2)})
            v = w
    bar.close()
    return v


def fit(scenes, db: float, pxclk: float = 0.0, size: int = 256, rtl_size: int = 64, features_of: str | None = None,
        name: str | None = None, out: Path | None = None, results: Path | None = None, progress: bool = True,
        also: tuple = (), order: str = "formats", fresh: bool = False, start_from: str | None = None,
        corpus_n: int = 16, corpus_size: int = 48, against: str = "reference") -> dict:
    """`also`: more frame sides at which the target must hold (the record is measured at `size`);
    `fresh`: start from a named configuration, not from the sweep's points; `start_from`: start
    from this configuration (a name of config/ or a .toml path, e.g. an earlier fit's), as it is."""
    from app.needs import merge_needs, needs

    t0 = time.perf_counter()
    out = out or ROOT / "out" / "fit"
    results = results or ROOT / "out" / "explore" / "results.json"
    pxclk_eff = pxclk if pxclk > 0 else 1 / 64
    need = merge_needs([needs(s, size) for s in scenes])
    fixed = features_of is not None
    if fixed:
        fv = config_values(load_config(features_of))
        need = {k: fv[k] for k in (*FEATURE_ORDER, "noise_terms", "noise_gradient")}
    # the start: the sweep's cheapest point that qualifies, else the cheapest named configuration with the features
    cands = [] if (fresh or start_from) else [
        r for r in stored_records(results) if has_features(r["config"], need) and _scene_ok(r, scenes, db, pxclk, size, against)
        and (not fixed or all(r["config"][k] == need[k] for k in need))]
    if start_from:
        start = {"from": f"configuration {start_from}", "ge_total": None, "values": config_values(load_config(start_from))}
    elif cands:
        best = min(cands, key=lambda r: r["ge_total"])
        start = {"from": f"sweep point {best.get('label', best.get('name'))}", "ge_total": best["ge_total"],
                 "values": best["config"]}
    else:
        named = [n for n in CONFIG_NAMES if has_features(config_values(load_config(n)), need)]
        if not named:
            named = ["full"]
        ge = {n: _named_ge(n) for n in named}
        n0 = features_of or min(named, key=lambda n: ge[n] if ge[n] is not None else float("inf"))
        start = {"from": f"configuration {n0}", "ge_total": ge.get(n0), "values": config_values(load_config(n0))}
    v = shape(start["values"], need, pxclk_eff, fixed)
    sizes = (size, *also)
    q0 = evaluate(v, scenes, sizes, against)
    log = [{"move": "start, cut to what the scenes need", "worst_db": None if q0 is None else round(q0, 2)}]
    if q0 is None or q0 < db:
        # the cut start misses the target: the start as it was, only its units for PXCLK
        v = dict(start["values"])
        q0 = evaluate(v, scenes, sizes, against)
        log.append({"move": "start as found (the cut missed the target)", "worst_db": None if q0 is None else round(q0, 2)})
        if q0 is None or q0 < db:
            raise FitError(f"no configuration found that meets {db} dB against the {against} on {', '.join(scenes)} "
                           f"(the start, {start['from']}, gives {q0 if q0 is None else round(q0, 2)} dB)")
    corpus = corpus_scenes(need, corpus_n)
    v = descend(v, scenes, db, sizes, log, progress, order, corpus, corpus_size, against)
    label = "all" if tuple(scenes) == SCENES else "-".join(scenes)
    name = name or f"fit-{label}-{db:g}db" + ("-truth" if against == "truth" else "") + (f"-{pxclk:g}px" if pxclk else "")
    cfg = measure.point_config(v, name=name.replace(".", "_"))
    # the RTL check is the render below (its images written): measure() does not simulate again
    opts = {"scenes": list(scenes), "size": size, "rtl_scenes": list(scenes), "rtl_size": rtl_size, "rtl": False,
            "truth_ss": measure.TRUTH_SS, "truth_band_ss": measure.TRUTH_BAND_SS}
    rec = measure.measure_cached(v, opts, results.parent / "points", label=f"fit {name}")
    if rec["status"] == "failed":
        raise FitError(f"the fitted configuration failed: {rec['error']}")
    if start.get("ge_total") is not None and start["ge_total"] < rec["ge_total"] and cands:
        # the sweep's point was cheaper after all (the descent never widens, but the cut may differ)
        v = start["values"]
        cfg = measure.point_config(v, name=name.replace(".", "_"))
        rec = measure.measure_cached(v, opts, results.parent / "points", label=f"fit {name}")
    out.mkdir(parents=True, exist_ok=True)
    imgs = measure.rtl_render(cfg, scenes, rtl_size, out / cfg.name)
    rec = {**rec, "rtl": imgs}
    if not imgs["bit_exact"]:
        rec.update(status="mismatch", error=f"RTL differs from the golden model on {imgs['mismatched_pixels']} pixels")
    toml = out / f"{cfg.name}.toml"
    toml.write_text(config_toml(cfg))
    views = held_out_views(cfg, scenes, db, size, out / cfg.name, against)
    rep = {"scenes": list(scenes), "target_db": db, "against": against, "min_pixels_per_clock": pxclk, "size": size,
           "target_sizes": list(sizes), "needs": need,
           "start": {k: start[k] for k in ("from", "ge_total")}, "steps": log, "config_file": str(toml.relative_to(ROOT)) if toml.is_relative_to(ROOT) else str(toml),
           "record": rec, "rtl_render": imgs, "fit_corpus": {"scenes": len(corpus), "size": corpus_size},
           "held_out_views": views,
           "held_out_worst_db": min((r["psnr_db"] for r in views if "psnr_db" in r), default=None), "pixels_per_clock_all_terms": round(1 / clocks_per_pixel(cfg), 4),
           "seconds": round(time.perf_counter() - t0, 1)}
    (out / f"{cfg.name}.json").write_text(json.dumps(rep, indent=1) + "\n")
    return rep


def _named_ge(n: str) -> float | None:
    p = ROOT / "synth" / "reports" / f"{n}.json"
    return json.loads(p.read_text())["ge_total"] if p.exists() else None


class FitError(RuntimeError):
    pass


def main(argv=None) -> int:
    ap = Parser(prog="python -m explore.fit", description="the smallest-GE configuration for some scenes (make fit)")
    ap.add_argument("--scenes", required=True, help="comma-separated scene names, or all")
    ap.add_argument("--db", type=float, required=True,
                    help="the worst scene's PSNR target against its float reference (or, --against truth, its truth)")
    ap.add_argument("--against", choices=AGAINST, default="reference",
                    help="measure every PSNR against the float reference or the converged truth (model.scene.truth)")
    ap.add_argument("--pxclk", type=float, default=0.0, help="at least this many pixels per clock on every scene")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--rtl-size", type=int, default=64, help="frame side of the RTL renders (px)")
    ap.add_argument("--fresh", action="store_true", help="start from a named configuration, not the sweep's points")
    ap.add_argument("--start", default=None, help="start from this configuration (a name or a .toml path)")
    ap.add_argument("--order", choices=tuple(ORDERS), default="formats", help="the descent's order of moves")
    ap.add_argument("--also-size", type=int, action="append", default=[],
                    help="another frame side at which the target must hold (the descent checks both)")
    ap.add_argument("--features-of", default=None, help="keep this configuration's features; search its formats")
    ap.add_argument("--name", default=None)
    ap.add_argument("--out", type=Path, default=None)
    ap.add_argument("--results", type=Path, default=None)
    ap.add_argument("--corpus", type=int, default=16, help="fit-corpus scenes the descent watches (0: none)")
    ap.add_argument("--corpus-size", type=int, default=48)
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)

    def go():
        scenes = SCENES if a.scenes == "all" else tuple(s.strip() for s in a.scenes.split(",") if s.strip())
        bad = [s for s in scenes if s not in SCENES]
        if bad or not scenes:
            raise UserError(f"--scenes: unknown scene '{bad[0] if bad else a.scenes}' (expected some of {', '.join(SCENES)})")
        if not 0 < a.db < 200:
            raise UserError(f"--db {a.db:g}: expected a PSNR in dB, 0 < DB < 200")
        if not 0 <= a.pxclk <= 1:
            raise UserError(f"--pxclk {a.pxclk:g}: expected pixels per clock in 0..1")
        check_range("--size", a.size, 8, 1024)
        check_range("--rtl-size", a.rtl_size, 2, 512)
        if a.features_of is not None and a.features_of not in CONFIG_NAMES:
            raise UserError(f"--features-of {a.features_of}: no such configuration (known: {', '.join(CONFIG_NAMES)})")
        if a.start is not None:
            load_config(a.start)  # a bad --start: one line, exit 2, before any work
        check_range("--corpus", a.corpus, 0, 200)
        check_range("--corpus-size", a.corpus_size, 8, 512)
        try:
            for z in a.also_size:
                check_range("--also-size", z, 8, 1024)
            rep = fit(scenes, a.db, a.pxclk, a.size, a.rtl_size, a.features_of, a.name, a.out, a.results, not a.quiet,
                      tuple(a.also_size), a.order, a.fresh, a.start, a.corpus, a.corpus_size, a.against)
        except FitError as e:
            print(f"fit: {e}", file=sys.stderr)
            return 1
        r = rep["record"]
        print(json.dumps({"config_file": rep["config_file"], "start": rep["start"], "ge_total": r["ge_total"],
                          "against": a.against, "worst_psnr_db": r["worst_psnr_ref_db"],
                          "worst_psnr_truth_db": r.get("worst_psnr_truth_db"), "min_pixels_per_clock": r["min_pixels_per_clock"],
                          "rtl_bit_exact": rep["rtl_render"]["bit_exact"], "rtl_pixels": rep["rtl_render"]["pixels"],
                          "fit_corpus_scenes": rep["fit_corpus"]["scenes"], "held_out_worst_db": rep["held_out_worst_db"],
                          "seconds": rep["seconds"]}, indent=1))
        return 0 if rep["rtl_render"]["bit_exact"] and r["status"] == "ok" else 1

    return run_main("fit", go)


if __name__ == "__main__":
    sys.exit(main())
