"""Held-out validation: does a configuration keep its promise on scenes it was not tuned on?

    python -m explore.validate corpus [--seed S] [--n N] [--hard]      (make corpus SEED= N=)
    python -m explore.validate run --config NAME|PATH [--n N] [--size PX] [--rtl K] [--rtl-size PX]
                                  [--jobs J] [--scheduler ADDR] [--no-doc]   (make validate CONFIG=)
    python -m explore.validate steps --config NAME|PATH --step KEY=V[,KEY=V] ...
    python -m explore.validate derive --config NAME|PATH --db D [--n N] [--size PX] [--out F.json]

`corpus` writes a scene corpus (model/scene/corpus.py) under out/corpus/seed<S>/. `run` renders
every scene of the held-out corpus (seed HELDOUT_SEED, N random scenes plus the hard cases)
that the configuration accepts, on the golden model, as Dask tasks (a LocalCluster of --jobs
workers, or the scheduler named by --scheduler / DASK_SCHEDULER_ADDRESS), and measures each
against its float reference (the scene as written) and against its converged truth
(model.scene.truth, cached in out/truth/), over the textured pixels. A scene is rejected when
a value does not fit the configuration's formats (model.hw.quantize's one-line reason) or the
configuration would change the texture (terms dropped, blend or filter replaced, noise gradient
left out: model.scene.passes.approximations); rounding of parameters is not a rejection, it is
what the promise is measured on. Then K accepted scenes (the rotated marble first, then evenly
spread) go through the RTL under Verilator at --rtl-size, every pixel against the golden model.

The configuration's [promise] (config/<name>.toml: psnr_db against "reference" or "truth"; against the
truth also loss_db: a scene below psnr_db keeps it when no more than loss_db below the float reference's own
PSNR against the truth; the share of accepted scenes that must keep it) is checked; the summary goes to
docs/validation/<name>.json with the configuration's hash and the RTL source's hash, and
docs/validation.md is rewritten from every summary there (the ten worst scenes of each on a
contact sheet, docs/images/validation_<name>.png). Exit status 1 when the promise is broken,
2 on bad input.
"""
from __future__ import annotations

import argparse
import json
import re
import sys
import time
from pathlib import Path

import numpy as np

from model.hw.config import ROOT, STAMP, ConfigError, config_hash, load_config, rel_path
from model.scene.corpus import FIT_SEED, HELDOUT_SEED, load_index, write_corpus

CORPUS_DIR = ROOT / "out" / "corpus"
DOC = ROOT / "docs" / "validation.md"
SUMMARY_DIR = ROOT / "docs" / "validation"
DEFAULT_N = 200
DEFAULT_SIZE = 48


def promised(r: dict) -> bool:
    """A scene the promise covers: accepted, every texture filtered. A point-sampled table (filter
    off) changes colour wherever f crosses an entry boundary, so the smallest rounding of f flips
    whole pixels (random tables: up to 255 LSB); those scenes are measured and listed apart."""
    return "rejected" not in r and not r["tags"].get("unfiltered", False)


def corpus_dir(seed: int, n: int, hard: bool, root: Path = CORPUS_DIR) -> Path:
    """The corpus folder, written when it is missing or holds another n (the generator is seeded:
    the same seed and n give the same files)."""
    d = root / f"seed{seed}"
    idx = d / "index.json"
    if idx.is_file():
        meta = json.loads(idx.read_text())
        if meta.get("n") == n and meta.get("hard") == hard:
            return d
    return write_corpus(root, seed, n, hard)


def source_hash() -> str:
    """A hash of rtl/ (the sources the bit-exact check ran on)."""
    from model.hw.config import rtl_source_hash

    return rtl_source_hash()


def reason_group(msg: str) -> str:
    """A rejection reason with its numbers and names taken out, to group alike reasons."""
    g = re.sub(r"'[^']*'", "'*'", msg)
    g = re.sub(r"^(pass|texture) \S+: ", r"\1 *: ", g)
    g = re.sub(r"\[[0-9, ]+\]", "[*]", g)
    g = re.sub(r"-?\d+(\.\d+)?(e-?\d+)?", "#", g)
    return g


def measure_scene(config: str, path: str, size: int) -> dict:
    """One scene on one configuration: accepted or the reason not; PSNR against the float
    reference and the truth; what rounding moved. (A Dask task: plain arguments, a plain dict.)"""
    from model import reference
    from model.hw import golden
    from model.hw.quantize import FormatError
    from model.imageio import compare
    from model.scene.frontend import render_passes
    from model.scene.passes import composite, frame_size, prepare_passes, scene_departures
    from model.scene.scene import load_scene
    from model.scene.truth import truth

    cfg = load_config(config)
    name = Path(path).stem
    sc = load_scene(path)
    W, H = frame_size(sc, size)
    passes = render_passes(sc, W, H)
    out = {"name": name}
    try:
        pds = prepare_passes(cfg, passes)
    except FormatError as e:
        return {**out, "rejected": str(e)}
    # the configuration's own filter and samples are its point (sat_fc, mip, samples): not a rejection;
    # its promise says what it is measured against
    feat = scene_departures(pds)
    if feat:
        return {**out, "rejected": feat[0]}
    gold, ref = [], []
    textured = np.zeros((H, W), bool)
    for pd in pds:
        gold.append((pd.mask, golden.texture_pipeline(cfg, pd.ti, pd.si, pd.Jm, pd.je)))
        ref.append((pd.mask, reference.shade(pd.tex, pd.s, pd.J, cfg.perm, cfg.hash_bits)))
        textured |= pd.mask
    g = composite(gold, (H, W), sc.background)
    r = composite(ref, (H, W), sc.background)
    t_img, _ = truth(path, cfg, size, passes=passes)
    if not textured.any():
        return {**out, "rejected": "no textured pixel at this size"}
    c_ref = compare(np.rint(g[textured]), r[textured])
    c_tru = compare(np.rint(g[textured]), t_img[textured])
    c_rt = compare(np.rint(r[textured]), t_img[textured])  # the float reference's own (8 bits, as the unit's output)
    inf = 200.0  # an exact match (compare gives None) counts as 200 dB
    moves = {k: max(pd.info["f_moves"][k] for pd in pds) for k in ("params", "s")}
    return {**out, "psnr_ref": c_ref["psnr_db"] if c_ref["psnr_db"] is not None else inf,
            "psnr_truth": c_tru["psnr_db"] if c_tru["psnr_db"] is not None else inf,
            "psnr_ref_truth": c_rt["psnr_db"] if c_rt["psnr_db"] is not None else inf,
            "max_err_ref": c_ref["max_abs_error_lsb"], "pixels": int(textured.sum()),
            "f_moves_params": round(moves["params"], 4), "f_moves_s": round(moves["s"], 4),
            "rounded": sum(len([ln for ln in pd.info["quantized"] if " rounded to " in ln and ln.startswith("texture")])
                           for pd in pds)}


def scene_images(config: str, path: str, size: int) -> dict:
    """The golden, float reference and truth images of a scene (for the contact sheet)."""
    from model import reference
    from model.hw import golden
    from model.scene.frontend import render_passes
    from model.scene.passes import composite, frame_size, prepare_passes, to8
    from model.scene.scene import load_scene
    from model.scene.truth import truth

    cfg = load_config(config)
    sc = load_scene(path)
    W, H = frame_size(sc, size)
    passes = render_passes(sc, W, H)
    pds = prepare_passes(cfg, passes)
    g = composite([(pd.mask, golden.texture_pipeline(cfg, pd.ti, pd.si, pd.Jm, pd.je)) for pd in pds], (H, W),
                  sc.background)
    r = composite([(pd.mask, reference.shade(pd.tex, pd.s, pd.J, cfg.perm, cfg.hash_bits)) for pd in pds], (H, W),
                  sc.background)
    return {"golden": to8(g), "reference": to8(r), "truth": to8(truth(path, cfg, size, passes=passes)[0])}


def rtl_check(config: str, paths: list[str], size: int, progress: bool = True) -> dict:
    """Every pixel of each scene through the RTL under Verilator against the golden model."""
    from tqdm import tqdm

    from model.hw import golden
    from model.scene.frontend import render_passes
    from model.scene.passes import frame_size, prepare_passes
    from model.scene.scene import load_scene
    from sim.frame_rtl import run_passes_rtl

    cfg = load_config(config)
    out = {"scenes": 0, "exact": 0, "pixels": 0, "differing_pixels": 0, "failures": []}
    for path in tqdm(paths, desc=f"RTL {cfg.name}", unit="scene", file=sys.stderr, disable=not progress):
        sc = load_scene(path)
        W, H = frame_size(sc, size)
        pds = prepare_passes(cfg, render_passes(sc, W, H))
        rgba = run_passes_rtl(config, "verilator", [(pd.ti, pd.si, pd.Jm, pd.je) for pd in pds])
        bad = 0
        for pd, got in zip(pds, rgba):
            exp = golden.texture_pipeline(cfg, pd.ti, pd.si, pd.Jm, pd.je)
            bad += int(np.any(np.asarray(got) != exp, axis=-1).sum())
            out["pixels"] += len(pd.si)
        out["scenes"] += 1
        out["differing_pixels"] += bad
        if bad:
            out["failures"].append(f"{Path(path).stem}: {bad} pixels differ")
        else:
            out["exact"] += 1
    return out


def _pct(v, q):
    return round(float(np.percentile(v, q)), 2) if len(v) else None


def promised_key(promise: dict | None) -> str:
    """The per-scene figure a promise is judged on (against the reference without one)."""
    return "psnr_ref" if not promise or promise["against"] == "reference" else "psnr_truth"


def keeps_promise(promise: dict, r: dict) -> bool:
    """Whether one covered scene's figures (measure_scene's) keep the promise: its PSNR against the promised
    image at least psnr_db, or, with loss_db (against the truth), at least the float reference's own PSNR against
    the truth less loss_db where that is lower (a scene the paper's float algorithm itself renders far from the
    truth asks only that the unit lose no more than loss_db on it)."""
    v = r[promised_key(promise)]
    if "loss_db" in promise:
        return v >= min(promise["psnr_db"], r["psnr_ref_truth"] - promise["loss_db"])
    return v >= promise["psnr_db"]


def promise_text(p: dict) -> str:
    """A promise in words, for the docs."""
    if "loss_db" in p:
        return (f"{p['psnr_db']} dB vs truth, or within {p['loss_db']} dB of the float reference's, on "
                f"{p['share']:.0%}")
    return f"{p['psnr_db']} dB vs {p['against']} on {p['share']:.0%}"


def summarize(cfg, results: list[dict], n: int, size: int) -> dict:
    acc = [r for r in results if "rejected" not in r]
    rej = [r for r in results if "rejected" in r]
    groups: dict = {}
    for r in rej:
        g = groups.setdefault(reason_group(r["rejected"]), {"count": 0, "example": r["rejected"], "scenes": []})
        g["count"] += 1
        g["scenes"].append(r["name"])
    cov = [r for r in acc if promised(r)]
    unf = [r for r in acc if not promised(r)]

    def st(rs, key):
        v = np.array([r[key] for r in rs])
        return {"min": round(float(v.min()), 2) if len(v) else None, "p5": _pct(v, 5), "median": _pct(v, 50),
                "count": len(v)}

    stats = {"reference": st(cov, "psnr_ref"), "truth": st(cov, "psnr_truth"),
             "unfiltered_reference": st(unf, "psnr_ref"), "unfiltered_truth": st(unf, "psnr_truth")}
    if cov and all("psnr_ref_truth" in r for r in cov):
        stats["reference_truth"] = st(cov, "psnr_ref_truth")
    promise = cfg.promise
    held = None
    if promise and cov:
        below = [r["name"] for r in cov if not keeps_promise(promise, r)]
        keep = len(cov) - len(below)
        held = {"keep": keep, "of": len(cov), "share": round(keep / len(cov), 4),
                "holds": keep / len(cov) >= promise["share"], "below": sorted(below)}
    worst = sorted(cov, key=lambda r: r[promised_key(promise)])[:10]
    return {"config": cfg.name, "config_path": rel_path(cfg.path),
            "config_hash": config_hash(cfg), "source_hash": source_hash(), "corpus_seed": HELDOUT_SEED, "n": n,
            "hard_cases": True, "size": size, "scenes": len(results), "accepted": len(acc), "covered": len(cov), "rejected": len(rej),
            "rejections": sorted(groups.values(), key=lambda g: -g["count"]), "psnr": stats, "promise": promise,
            "promise_result": held, "worst": worst, "results": results}


def write_doc(summary_dir: Path = SUMMARY_DIR, doc: Path = DOC) -> None:
    """docs/validation.md from every summary in docs/validation/."""
    sums = [json.loads(p.read_text()) for p in sorted(summary_dir.glob("*.json"))]
    order = {"full": 0, "reduced": 1, "compact": 2}
    sums.sort(key=lambda s: (order.get(s["config"], 9), s["config"]))
    L = ["# Held-out validation", "",
         "Written by `make validate CONFIG=<name>` (explore/validate.py); each configuration's summary is "
         "docs/validation/<name>.json. Every configuration is measured on the **held-out corpus** (model/scene/corpus.py, "
         f"seed {HELDOUT_SEED}: random scenes of the kind a user writes, plus the fixed hard cases; the fit corpus is "
         f"seed {FIT_SEED}), none of which any configuration was tuned on. A scene is *rejected* when a value does "
         "not fit the configuration's formats or the configuration would change the texture (terms, blend, filter, "
         "noise gradient); rounding a parameter is not a rejection: it is what the figures below measure. PSNR is "
         "over the textured pixels, against the float reference of the scene as written and against the converged "
         "truth (model.scene.truth). The promise is the configuration file's `[promise]`: a PSNR every covered scene "
         "keeps against the reference or the truth (psnr_db); against the truth it may add loss_db: a scene below "
         "psnr_db still keeps it when it falls no more than loss_db below the float reference's own PSNR against the "
         "truth (the reference rounded to 8 bits like the unit's output): no worse for the eye than the paper's float "
         "algorithm by more than that, on the scenes that algorithm itself renders far from the truth.", "",
         "The promise covers the accepted scenes whose textures are all filtered (`covered`): a point-sampled table "
         "changes colour wherever f crosses an entry boundary, so the smallest rounding of f flips whole pixels (up to "
         "255 LSB on a random table); the unfiltered ones are measured apart, in each configuration's section.", "",
         "GE is `make synth`'s total (synth/reports/<name>.json) where the configuration has a report.", "",
         "| configuration | hash | GE | scenes | accepted | covered | PSNR vs reference: min / 5% / median | vs truth: "
         "min / 5% / median | promise | kept | RTL bit-exact |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
    for s in sums:
        p, h, rtl = s["promise"], s["promise_result"], s.get("rtl") or {}
        ps = promise_text(p) if p else "none stated"
        kept = (f"{h['keep']}/{h['of']} ({h['share']:.1%}) {'**holds**' if h['holds'] else '**broken**'}" if h else "-")
        r, t = s["psnr"]["reference"], s["psnr"]["truth"]
        rp = ROOT / "synth" / "reports" / f"{s['config']}.json"
        ge = f"{json.loads(rp.read_text())['ge_total']:,.0f}" if rp.is_file() else "-"
        L.append(f"| {s['config']} | {s['config_hash']} | {ge} | {s['scenes']} at {s['size']} px | {s['accepted']} | "
                 f"{s.get('covered', '-')} | "
                 f"{r['min']} / {r['p5']} / {r['median']} | {t['min']} / {t['p5']} / {t['median']} | {ps} | {kept} | "
                 + (f"{rtl['exact']}/{rtl['scenes']} scenes, {rtl['pixels']:,} pixels" if rtl else "-") + " |")
    checked = [s for s in sums if s.get("rtl")]
    L += ["", "RTL source hash of each RTL check: " + (", ".join(f"{s['config']} {s['source_hash']}" for s in checked)
                                                       or "none (no configuration was checked through the RTL)"), ""]
    for s in sums:
        # the command that reruns the section (app/regen.py reads it): a configuration of config/candidates/ by its path
        arg = s["config"] if s["config_path"] == f"config/{s['config']}.toml" else s["config_path"]
        L += [f"## {s['config']}", "", f"`make validate CONFIG={arg} N={s['n']} SIZE={s['size']}` "
              f"(configuration hash {s['config_hash']}, {s['config_path']}).", ""]
        u, ut = s["psnr"].get("unfiltered_reference"), s["psnr"].get("unfiltered_truth")
        if u and u.get("count"):
            L += [f"Unfiltered accepted scenes ({u['count']}), not covered by the promise: against the reference "
                  f"min / 5% / median {u['min']} / {u['p5']} / {u['median']} dB, against the truth {ut['min']} / "
                  f"{ut['p5']} / {ut['median']} dB.", ""]
        h = s.get("promise_result")
        if h and h.get("below"):
            L += [f"Covered scenes below the promise ({len(h['below'])}): " + ", ".join(h["below"][:40])
                  + (" ..." if len(h["below"]) > 40 else "") + ".", ""]
        if s["rejections"]:
            L += ["Rejected, by reason:", "", "| scenes | reason (an example) |", "|---|---|"]
            L += [f"| {g['count']} | {g['example']} |" for g in s["rejections"]]
            L.append("")
        if s["worst"]:
            L += ["The ten worst accepted scenes (golden, float reference, truth: "
                  f"docs/images/validation_{s['config']}.png):", "",
                  "| scene | vs reference dB | vs truth dB | largest error (LSB) | f moved by rounded parameters (entries) |",
                  "|---|---|---|---|---|"]
            L += [f"| {w['name']} | {w['psnr_ref']:.2f} | {w['psnr_truth']:.2f} | {w['max_err_ref']:.0f} | "
                  f"{w['f_moves_params']} |" for w in s["worst"]]
            L += ["", f"![worst scenes of {s['config']}](images/validation_{s['config']}.png)", ""]
        if s.get("rtl", {}).get("failures"):
            L += ["RTL failures: " + "; ".join(s["rtl"]["failures"]), ""]
    steps_dir = summary_dir / "steps"
    for p in sorted(steps_dir.glob("*.json")) if steps_dir.is_dir() else []:
        t = json.loads(p.read_text())
        L += [f"## Steps from {t['config']} on the fit corpus", "",
              f"What each width is worth on the fit corpus (seed {t['seed']}, {t['n']} random scenes, filtered ones, "
              f"{t['size']} px), against the float reference (configuration hash {t['config_hash']}): `{t['command']}`.",
              "", "| step | scenes | rejected | min | 5% | median | share at the promise |", "|---|---|---|---|---|---|---|"]
        L += [f"| {r['step']} | {r['scenes']} | {r['rejected']} | {r['min']} | {r['p5']} | {r['median']} | "
              f"{r['at_promise']} (>= {r['promise_db']} dB) |" for r in t["rows"]]
        L.append("")
    # the stamp: every configuration summarised, as measured (test_validate checks them against the files)
    L.append(STAMP + " " + " ".join(f"{x['config']}={x['config_hash']}" for x in sums) + " -->")
    doc.write_text("\n".join(L) + "\n")


def run(config: str, n: int, size: int, rtl: int, rtl_size: int, jobs: int, scheduler: str | None,
        doc: bool, progress: bool = True, out_root: Path | None = None, docs: Path | None = None) -> dict:
    from explore.sweep import client_for
    from model.imageio import contact_sheet

    cfg = load_config(config)
    out_root = Path(out_root) if out_root else ROOT / "out"
    docs = Path(docs) if docs else ROOT / "docs"
    d = corpus_dir(HELDOUT_SEED, n, True, out_root / "corpus")
    idx = load_index(d)
    t0 = time.perf_counter()
    client, cluster = client_for(scheduler, jobs)
    try:
        from distributed import as_completed
        from tqdm import tqdm

        futs = {client.submit(measure_scene, config, str(e["path"]), size, pure=False): e for e in idx}
        results = []
        with tqdm(total=len(futs), desc=f"validate {cfg.name}", unit="scene", file=sys.stderr,
                  disable=not progress) as bar:
            for f in as_completed(futs):
                r = f.result()
                r["tags"] = futs[f]["tags"]
                results.append(r)
                bar.update()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    results.sort(key=lambda r: r["name"])
    summ = summarize(cfg, results, n, size)
    summ["model_seconds"] = round(time.perf_counter() - t0, 1)
    acc = [r["name"] for r in results if "rejected" not in r]
    if rtl and acc:
        first = [a for a in acc if a == "hard_rotated_marble"]
        rest = [a for a in acc if a not in first]
        pick = first + [rest[i] for i in np.linspace(0, len(rest) - 1, max(0, min(rtl - len(first), len(rest))))
                        .astype(int).tolist()] if rest else first
        pick = list(dict.fromkeys(pick))[:rtl]
        summ["rtl"] = {**rtl_check(config, [str(d / f"{p}.toml") for p in pick], rtl_size, progress),
                       "size": rtl_size, "names": pick}
    od = out_root / "validate"
    od.mkdir(parents=True, exist_ok=True)
    (od / f"{cfg.name}.json").write_text(json.dumps(summ, indent=1) + "\n")
    if doc:
        (docs / "validation").mkdir(parents=True, exist_ok=True)
        rows = []
        for w in summ["worst"]:
            im = scene_images(config, str(d / f"{w['name']}.toml"), size)
            rows.append([(f"{w['name']} {w['psnr_ref']:.1f} dB", im["golden"]), ("reference", im["reference"]),
                         (f"truth ({w['psnr_truth']:.1f} dB)", im["truth"])])
        if rows:
            (docs / "images").mkdir(parents=True, exist_ok=True)
            contact_sheet(docs / "images" / f"validation_{cfg.name}.png", rows, tile=128,
                          title=f"validate {cfg.name}: the ten worst held-out scenes")
        (docs / "validation" / f"{cfg.name}.json").write_text(json.dumps(summ, indent=1) + "\n")
        write_doc(docs / "validation", docs / "validation.md")
    return summ


_CQ_PASSES: dict = {}
_CQ_REFS: dict = {}


def corpus_quality(cfg, seed: int = HELDOUT_SEED, n: int = 40, size: int = 32, db: float = 50.0,
                   root: Path | None = None) -> dict:
    """A configuration on a corpus against the float reference only (no truth: cheap enough for
    every sweep point): scenes accepted and covered (filtered), the covered scenes' PSNR min, 5th
    percentile and median, and the share at `db`. The ray casting and the reference (which depend
    on the scene and the lattice only) are cached per process."""
    from model import reference
    from model.hw import golden
    from model.hw.quantize import FormatError
    from model.imageio import compare
    from model.scene.frontend import render_passes
    from model.scene.passes import composite, frame_size, prepare_passes, scene_departures
    from model.scene.scene import load_scene

    d = corpus_dir(seed, n, seed == HELDOUT_SEED, (Path(root) if root else ROOT / "out") / "corpus")
    vals, acc = [], 0
    for e in load_index(d):
        key = (str(e["path"]), size)
        if key not in _CQ_PASSES:
            sc = load_scene(e["path"])
            W, H = frame_size(sc, size)
            _CQ_PASSES[key] = (sc, W, H, render_passes(sc, W, H))
        sc, W, H, passes = _CQ_PASSES[key]
        try:
            pds = prepare_passes(cfg, passes)
        except FormatError:
            continue
        if scene_departures(pds):
            continue
        acc += 1
        if e["tags"].get("unfiltered"):
            continue
        rk = (*key, cfg.seed, cfg.hash_bits)
        if rk not in _CQ_REFS:
            _CQ_REFS[rk] = composite([(pd.mask, reference.shade(pd.tex, pd.s, pd.J, cfg.perm, cfg.hash_bits))
                                      for pd in pds], (H, W), sc.background)
        g = composite([(pd.mask, golden.texture_pipeline(cfg, pd.ti, pd.si, pd.Jm, pd.je)) for pd in pds], (H, W),
                      sc.background)
        t = np.zeros((H, W), bool)
        for pd in pds:
            t |= pd.mask
        if t.any():
            c = compare(np.rint(g[t]), _CQ_REFS[rk][t])["psnr_db"]
            vals.append(200.0 if c is None else c)
    v = np.array(vals)
    return {"seed": seed, "n": n, "size": size, "accepted": acc, "covered": len(v),
            "min": round(float(v.min()), 2) if len(v) else None, "p5": _pct(v, 5), "median": _pct(v, 50),
            "db": db, "share_at_db": round(float((v >= db).mean()), 4) if len(v) else None}


def steps(config: str, step_texts: list[str], seed: int, n: int, size: int, progress: bool = True,
          out_root: Path | None = None) -> list[dict]:
    """The configuration and one-or-more-key steps from it on a corpus (seed; the fit corpus by
    default), against the float reference only (the arithmetic; no truth): per step the covered
    scenes' PSNR (min, 5th percentile, median) and the share at the promise. The figures behind
    a configuration's re-derivation: `python -m explore.validate steps --config full --step t_w=17,t_frac=10`."""
    from model import reference
    from model.hw import golden
    from tqdm import tqdm

    from app.quality import parse_step
    from model.hw.config import variant
    from model.hw.quantize import FormatError
    from model.imageio import compare
    from model.scene.frontend import render_passes
    from model.scene.passes import composite, frame_size, prepare_passes, scene_departures
    from model.scene.scene import load_scene

    base = load_config(config)
    cfgs = [("(as written)", base)] + [(t, variant(base, f"{base.name}-step", **parse_step(t))) for t in step_texts]
    d = corpus_dir(seed, n, seed == HELDOUT_SEED, (Path(out_root) if out_root else ROOT / "out") / "corpus")
    idx = load_index(d)
    vals = {label: [] for label, _ in cfgs}
    rej = {label: 0 for label, _ in cfgs}
    for e in tqdm(idx, desc=f"steps {base.name}", unit="scene", file=sys.stderr, disable=not progress):
        if e["tags"].get("unfiltered"):
            continue
        sc = load_scene(e["path"])
        W, H = frame_size(sc, size)
        passes = render_passes(sc, W, H)
        ref_img = None
        for label, cfg in cfgs:
            try:
                pds = prepare_passes(cfg, passes)
            except FormatError:
                rej[label] += 1
                continue
            if scene_departures(pds):
                rej[label] += 1
                continue
            if ref_img is None:  # the reference depends on the lattice only, the same for every step
                ref_img = composite([(pd.mask, reference.shade(pd.tex, pd.s, pd.J, cfg.perm, cfg.hash_bits))
                                     for pd in pds], (H, W), sc.background)
            g = composite([(pd.mask, golden.texture_pipeline(cfg, pd.ti, pd.si, pd.Jm, pd.je)) for pd in pds],
                          (H, W), sc.background)
            t = np.zeros((H, W), bool)
            for pd in pds:
                t |= pd.mask
            if t.any():
                c = compare(np.rint(g[t]), ref_img[t])["psnr_db"]
                vals[label].append(200.0 if c is None else c)
    out = []
    pdb = (base.promise or {}).get("psnr_db", 50.0)
    for label, _ in cfgs:
        v = np.array(vals[label])
        out.append({"step": label, "scenes": len(v), "rejected": rej[label],
                    "min": round(float(v.min()), 2) if len(v) else None, "p5": _pct(v, 5), "median": _pct(v, 50),
                    "at_promise": round(float((v >= pdb).mean()), 4) if len(v) else None, "promise_db": pdb})
    return out


# The descent of `derive`: each precision key starts at least this wide (the configuration's own
# value, if wider) and is narrowed one bit at a time by the moves of DERIVE_ORDER, best first. A
# fixed-point pair (s, q) moves its fraction with the width: its integer bits, the range the
# configuration accepts, stay the file's (a range is a promise to the scene format, not a
# precision to trade). The file's own words are the floor: they were fitted to the eight paper
# scenes, whose noise the corpus scenes a narrow configuration accepts need not exercise
# (reduced accepts 60 of the 800 fit scenes, 57 of them without a noise term), so a descent on
# the corpus alone would narrow the noise words to nothing; the corpus can only widen a word.
DERIVE_START = {"s_frac": 14, "q_frac": 18, "j_w": 10, "p_frac": 14, "n_frac": 14, "f_frac": 16, "c_frac": 10,
                "norm_bits": 10}
DERIVE_ORDER = [("c_frac",), ("f_frac",), ("n_frac",), ("p_frac",), ("norm_bits",), ("j_w",),
                ("q_frac", "q_w"), ("s_frac", "s_w")]


def derive(config: str, db: float, seed: int = FIT_SEED, n: int = 800, size: int = 48, max_steps: int = 200,
           root: Path | None = None, progress: bool = True) -> dict:
    """Re-derive a configuration's precisions on a corpus (the fit corpus by default): from DERIVE_START,
    a best-first descent: each step tries every move of DERIVE_ORDER (one bit less) and takes, of those
    that keep (a) as many accepted scenes as at the start and (b) a share of the covered scenes of at
    least the configuration's promised share (1.0 without a promise) at `db` dB or more against the
    float reference, the one whose worst covered scene loses least (then the median); no key goes
    below the file's own value (see DERIVE_START); a move that fails is dropped (one the configuration
    checks refuse, a key below what another key needs, is tried again at the next step); it stops
    when no move keeps (a) and (b) (or after `max_steps`). `db` is the promise
    plus the margin the held-out corpus needs (the fit corpus is what the descent was tuned on).
    Returns the start, every step tried (taken or not, with its figures) and the final keys."""
    from model.hw.config import config_values, variant

    base = load_config(config)
    share = (base.promise or {}).get("share", 1.0)
    vals = config_values(base)
    cur = {k: max(int(vals[k]), v) for k, v in DERIVE_START.items()}
    for w, f in (("s_w", "s_frac"), ("q_w", "q_frac")):  # the file's integer bits, the fraction widened
        cur[w] = int(vals[w]) - int(vals[f]) + cur[f]
    floor = {k: int(vals[k]) for k in cur}  # the file's own words: never narrower (see DERIVE_START)

    def measure(keys):
        return corpus_quality(variant(base, f"{base.name}-derive", **keys), seed, n, size, db, root)

    t0 = time.time()
    start = cur_m = measure(cur)
    if not start["covered"]:
        raise ValueError(f"derive {base.name}: no covered scene on corpus seed {seed} n {n}")
    tried = []

    def ok(m):
        return m["accepted"] == start["accepted"] and m["share_at_db"] is not None and m["share_at_db"] >= share

    live = list(DERIVE_ORDER)  # a move that failed once is not tried again (narrowing never helps it)
    for step in range(1, max_steps + 1):
        best = None
        for keys in list(live):
            nxt = dict(cur)
            for k in keys:
                nxt[k] -= 1
            if any(nxt[k] < floor[k] for k in keys):
                live.remove(keys)
                continue
            try:
                m = measure(nxt)
            except (ConfigError, ValueError) as e:  # a key below what another needs now: tried again next step
                tried.append({"step": step, "move": "/".join(keys), "taken": False, "error": str(e)})
                continue
            row = {"step": step, "move": "/".join(keys), "keys": {k: nxt[k] for k in keys}, "taken": False,
                   **{x: m[x] for x in ("accepted", "covered", "min", "p5", "median", "share_at_db")}}
            row["keeps"] = ok(m)
            tried.append(row)
            if not row["keeps"]:
                live.remove(keys)
            elif best is None or (m["min"], m["median"]) > (best[1]["min"], best[1]["median"]):
                best = (nxt, m, row)
        if best is None:
            break
        cur, m, row = best
        cur_m = m
        row["taken"] = True
        if progress:
            print(f"derive {base.name} step {step}: {row['move']} -> {', '.join(f'{k} {v}' for k, v in row['keys'].items())}: "
                  f"min {m['min']} dB, median {m['median']} dB, share at {db} dB {m['share_at_db']} "
                  f"({len(live)} moves live, {time.time() - t0:.0f} s)", file=sys.stderr, flush=True)
    final = cur_m  # the figures of the last move taken (or the start): not measured again
    return {"config": base.name, "config_path": rel_path(base.path), "seed": seed, "n": n, "size": size, "db": db,
            "share": share, "start": start, "final": final, "keys": cur,
            "changed": {k: (int(vals[k]), v) for k, v in cur.items() if int(vals[k]) != v},
            "tried": tried, "seconds": round(time.time() - t0, 1)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m explore.validate", description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    c = sub.add_parser("corpus", help="write a scene corpus under out/corpus/seed<S>/")
    c.add_argument("--seed", type=int, default=HELDOUT_SEED)
    c.add_argument("--n", type=int, default=DEFAULT_N)
    c.add_argument("--hard", action="store_true", help="add the fixed hard cases (the held-out corpus has them)")
    c.add_argument("--out", type=Path, default=CORPUS_DIR)
    r = sub.add_parser("run", help="validate a configuration on the held-out corpus")
    r.add_argument("--config", required=True, help="a configuration name or a .toml path")
    r.add_argument("--n", type=int, default=DEFAULT_N)
    r.add_argument("--size", type=int, default=DEFAULT_SIZE)
    r.add_argument("--rtl", type=int, default=4, help="accepted scenes to check through the RTL (0: none)")
    r.add_argument("--rtl-size", type=int, default=32)
    r.add_argument("--jobs", type=int, default=2)
    r.add_argument("--scheduler", default=None)
    r.add_argument("--no-doc", action="store_true", help="print the summary; leave docs/ alone")
    r.add_argument("--quiet", action="store_true")
    r.add_argument("--out", type=Path, default=None, help="output root (corpus, results), default out/")
    r.add_argument("--docs", type=Path, default=None, help="docs folder to write, default docs/")
    st = sub.add_parser("steps", help="a configuration and steps from it on a corpus, against the float reference")
    st.add_argument("--config", required=True)
    st.add_argument("--step", action="append", default=[], help="KEY=VALUE[,KEY=VALUE]: one step")
    st.add_argument("--seed", type=int, default=FIT_SEED, help="the corpus (default the fit corpus)")
    st.add_argument("--n", type=int, default=DEFAULT_N)
    st.add_argument("--size", type=int, default=DEFAULT_SIZE)
    st.add_argument("--quiet", action="store_true")
    st.add_argument("--root", type=Path, default=None, help="output root holding corpus/ (default out/)")
    st.add_argument("--write", action="store_true",
                    help="keep the table as docs/validation/steps/<config>.json (docs/validation.md shows it)")
    dv = sub.add_parser("derive", help="re-derive a configuration's formats on the fit corpus (a descent)")
    dv.add_argument("--config", required=True)
    dv.add_argument("--db", type=float, required=True, help="the PSNR (dB, vs the float reference) to keep")
    dv.add_argument("--seed", type=int, default=FIT_SEED, help="the corpus (default the fit corpus)")
    dv.add_argument("--n", type=int, default=800)
    dv.add_argument("--size", type=int, default=DEFAULT_SIZE)
    dv.add_argument("--max-steps", type=int, default=200)
    dv.add_argument("--root", type=Path, default=None, help="output root holding corpus/ (default out/)")
    dv.add_argument("--out", type=Path, default=None, help="write the result as JSON here")
    dv.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    if a.cmd == "derive":
        if not 8 <= a.size <= 1024 or not 1 <= a.max_steps <= 1000 or not 0 < a.db < 200 or not 1 <= a.n <= 100000:
            print(f"validate derive: --size {a.size} --max-steps {a.max_steps} --db {a.db} --n {a.n}: expected size 8..1024, "
                  f"max-steps 1..1000, db in (0, 200), n 1..100000", file=sys.stderr)
            return 2
        try:
            d = derive(a.config, a.db, a.seed, a.n, a.size, a.max_steps, a.root, not a.quiet)
        except (ConfigError, ValueError) as e:
            print(f"validate derive: {e}", file=sys.stderr)
            return 2
        if a.out:
            a.out.parent.mkdir(parents=True, exist_ok=True)
            a.out.write_text(json.dumps(d, indent=1) + "\n")
        st, fi = d["start"], d["final"]
        print(f"derive {d['config']} on corpus seed {d['seed']} (n {d['n']}, {d['size']} px) to {d['db']} dB on "
              f"{d['share']:.0%}: {fi['accepted']} accepted, {fi['covered']} covered; start min/p5/median "
              f"{st['min']}/{st['p5']}/{st['median']} dB, final {fi['min']}/{fi['p5']}/{fi['median']} dB, "
              f"share at {d['db']} dB {fi['share_at_db']} ({d['seconds']} s)")
        print("changed from the file: " + (", ".join(f"{k} {a0} -> {b0}" for k, (a0, b0) in d["changed"].items())
                                          or "nothing"))
        return 0
    if a.cmd == "steps":
        try:
            rows = steps(a.config, a.step, a.seed, a.n, a.size, not a.quiet, a.root)
        except (ConfigError, ValueError) as e:
            print(f"validate steps: {e}", file=sys.stderr)
            return 2
        if a.write:
            sd = SUMMARY_DIR / "steps"
            sd.mkdir(parents=True, exist_ok=True)
            cfg = load_config(a.config)
            cmd = (f"python -m explore.validate steps --config {a.config} --seed {a.seed} --n {a.n} --size {a.size} "
                   + " ".join(f"--step {t}" for t in a.step))
            (sd / f"{cfg.name}.json").write_text(json.dumps(
                {"config": cfg.name, "config_path": rel_path(cfg.path), "config_hash": config_hash(cfg), "seed": a.seed,
                 "n": a.n, "size": a.size,
                 "command": cmd, "rows": rows}, indent=1) + "\n")
            write_doc()
        print(f"PSNR (dB) against the float reference, corpus seed {a.seed} (filtered scenes), {a.size} px, "
              f"configuration {a.config}")
        print("| step | scenes | rejected | min | 5% | median | share >= promise |")
        print("|---|---|---|---|---|---|---|")
        for r in rows:
            print(f"| {r['step']} | {r['scenes']} | {r['rejected']} | {r['min']} | {r['p5']} | {r['median']} | "
                  f"{r['at_promise']} (>= {r['promise_db']} dB) |")
        return 0
    if a.cmd == "corpus":
        if not 0 <= a.n <= 100000 or a.seed < 0:
            print(f"corpus: --n {a.n} --seed {a.seed}: expected n 0..100000 and seed >= 0", file=sys.stderr)
            return 2
        d = write_corpus(a.out, a.seed, a.n, a.hard)
        print(f"corpus: {len(load_index(d))} scenes in {d}")
        return 0
    for k, lo, hi in (("n", 0, 100000), ("size", 8, 1024), ("rtl", 0, 1000), ("rtl_size", 8, 256), ("jobs", 1, 64)):
        if not lo <= getattr(a, k) <= hi:
            print(f"validate: --{k.replace('_', '-')} {getattr(a, k)}: expected {lo}..{hi}", file=sys.stderr)
            return 2
    try:
        load_config(a.config)
    except ConfigError as e:
        print(f"validate: {e}", file=sys.stderr)
        return 2
    if a.rtl:
        from hdlbuild import need_simulator

        try:
            need_simulator("verilator")
        except Exception as e:  # the one-line error of a missing simulator
            print(f"validate: {e}", file=sys.stderr)
            return 2
    s = run(a.config, a.n, a.size, a.rtl, a.rtl_size, a.jobs, a.scheduler, not a.no_doc, not a.quiet, a.out, a.docs)
    p, h = s["promise"], s["promise_result"]
    r = s["psnr"]["reference"]
    print(f"validate {s['config']}: {s['accepted']}/{s['scenes']} accepted; vs reference min {r['min']} p5 {r['p5']} "
          f"median {r['median']} dB; vs truth median {s['psnr']['truth']['median']} dB"
          + (f"; promise {promise_text(p)}: {h['keep']}/{h['of']} ({h['share']:.1%}) "
             f"{'holds' if h['holds'] else 'BROKEN'}" if h else "; no promise stated")
          + (f"; RTL {s['rtl']['exact']}/{s['rtl']['scenes']} scenes bit-exact" if s.get("rtl") else ""))
    if s.get("rtl") and s["rtl"]["exact"] != s["rtl"]["scenes"]:
        return 1
    return 0 if not h or h["holds"] else 1


if __name__ == "__main__":
    sys.exit(main())
