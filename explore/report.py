"""docs/tradeoffs.md and its plots, from the sweep's results (explore.sweep, make explore).

    python -m explore.report [--results out/explore/results.json] [--docs docs]

Plots (matplotlib, written through OpenImageIO): GE against the worst scene's PSNR with the
Pareto front drawn, one marker per pixels-per-clock class, the paper's two budgets and the named
configurations labelled, twice: against the float reference (docs/images/tradeoffs.png) and
against the converged truth, the error the eye sees (docs/images/tradeoffs_truth.png, issue 27);
and per knob, what one step of it costs in GE and buys in dB (docs/images/tradeoffs_knobs.png).
The page says which configuration is best for the eye at each gate budget and pixel rate
(BUDGETS x EYE_RATES: the best worst scene against the truth).
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from explore import space
from explore.measure import ROOT
from explore.validate import promise_text

PAPER_BUDGETS = {"paper's reduced model (100,000 gates)": 100_000, "paper's full model (1,250,000 gates)": 1_250_000}
# pixels-per-clock classes (the slowest scene's): marker, label
PXCLK_CLASSES = [(1.0, "o", "1 px/clock"), (0.5, "s", "1/2 px/clock"), (0.25, "^", "1/4 to 1/2"),
                 (0.0, "v", "below 1/4")]


# "best for the eye": the gate budgets and the pixel rates (at least this many pixels a clock on every scene)
BUDGETS = (100_000, 250_000, 700_000, 1_250_000, 2_000_000)  # the last: above full (1.36M) and its filters
EYE_RATES = ((1.0, "1 px/clock"), (0.5, "1/2 px/clock"), (0.25, "1/4 px/clock"))
AXES = {"reference": ("worst_psnr_ref_db", "worst scene PSNR against its float reference (dB)"),
        "truth": ("worst_psnr_truth_db", "worst scene PSNR against its converged truth, texture interior (dB)")}


def best_for_eye(recs: list[dict]) -> list[dict]:
    """Per gate budget and pixel rate: the measured point within the budget, at least that many
    pixels a clock on its slowest scene, with the best worst scene against the truth (None: no point)."""
    ok = [r for r in recs if r["status"] == "ok" and r.get("worst_psnr_truth_db") is not None]
    rows = []
    for b in BUDGETS:
        for rate, lab in EYE_RATES:
            c = [r for r in ok if r["ge_total"] <= b and r["min_pixels_per_clock"] >= rate - 1e-9]
            best = max(c, key=lambda r: (r["worst_psnr_truth_db"], -r["ge_total"]), default=None)
            rows.append({"budget": b, "rate": lab, "best": best})
    return rows


def _cls(pxclk: float):
    for lo, m, lab in PXCLK_CLASSES:
        if pxclk >= lo - 1e-9:
            return m, lab
    return PXCLK_CLASSES[-1][1:]


def _f(v, fmt="{:,.0f}"):
    return "-" if v is None else fmt.format(v)


def knob_steps(recs: list[dict]) -> list[dict]:
    """One row per one-at-a-time step (and grid point) with its base measured: what the step
    costs in GE and in dB at the worst scene against the float reference."""
    by_label = {r.get("label"): r for r in recs}
    rows = []
    for r in recs:
        base = by_label.get(r.get("base"))
        if r.get("step") in (None,) or base is None or r is base:
            continue
        row = {"label": r["label"], "base": r["base"], "step": r["step"], "status": r["status"], "error": r.get("error")}
        if r["status"] == "ok" and base["status"] == "ok":
            row.update({"d_ge": r["ge_total"] - base["ge_total"], "d_ge_pct": 100 * (r["ge_total"] / base["ge_total"] - 1),
                        "d_db": r["worst_psnr_ref_db"] - base["worst_psnr_ref_db"],
                        "d_depth": r["logic_depth"] - base["logic_depth"],
                        "pxclk": r["min_pixels_per_clock"], "base_pxclk": base["min_pixels_per_clock"]})
        rows.append(row)
    return rows


def plot_front(recs: list[dict], path: Path, against: str = "reference") -> None:
    """GE against the worst scene's PSNR (against the float reference or the truth) and that front."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from model.imageio import write_figure

    y, ylabel = AXES[against]
    ok = [r for r in recs if r["status"] == "ok" and r.get(y) is not None]
    fig, ax = plt.subplots(figsize=(10, 6.5), dpi=110)
    seen = set()
    for r in ok:
        m, lab = _cls(r["min_pixels_per_clock"])
        ax.scatter(r["ge_total"], r[y], marker=m, s=36, color="tab:blue", alpha=0.75,
                   label=lab if lab not in seen else None, edgecolors="none")
        seen.add(lab)
    front = space.pareto(ok, y=y)
    ax.plot([r["ge_total"] for r in front], [r[y] for r in front], "-", color="tab:red",
            lw=1.5, label=f"Pareto front (GE against worst-scene PSNR vs {against})")
    for r in ok:
        if r.get("step") is None:
            ax.annotate(r["label"], (r["ge_total"], r[y]), textcoords="offset points",
                        xytext=(6, 6), fontsize=10, weight="bold")
    for lab, ge in PAPER_BUDGETS.items():
        ax.axvline(ge, color="gray", ls="--", lw=1)
        ax.text(ge, ax.get_ylim()[0] + 1, " " + lab, rotation=90, va="bottom", fontsize=8, color="gray")
    ax.set_xscale("log")
    ax.set_xlabel("gate equivalents (logic, Yosys + synth/cells.lib; storage apart)")
    ax.set_ylabel(ylabel)
    ax.set_title(f"Gates against image quality vs the {against} (marker: the slowest scene's pixels per clock)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    write_figure(path, fig)


def plot_knobs(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from model.imageio import write_figure

    rows = [r for r in rows if "d_ge" in r and r["step"] != "grid"]
    bases = sorted({r["base"] for r in rows})
    fig, axes = plt.subplots(len(bases), 1, figsize=(11, 3.6 * max(1, len(bases))), dpi=100, squeeze=False)
    for ax, b in zip(axes[:, 0], bases):
        rs = sorted((r for r in rows if r["base"] == b), key=lambda r: r["d_ge"])
        x = range(len(rs))
        ax.bar([i - 0.2 for i in x], [r["d_ge_pct"] for r in rs], width=0.4, color="tab:blue", label="GE change (%)")
        ax2 = ax.twinx()
        ax2.bar([i + 0.2 for i in x], [r["d_db"] for r in rs], width=0.4, color="tab:orange", label="worst-scene dB change")
        ax.set_xticks(list(x))
        ax.set_xticklabels([r["step"] for r in rs], rotation=60, ha="right", fontsize=7)
        ax.set_ylabel("GE change (%)", color="tab:blue")
        ax2.set_ylabel("worst PSNR change (dB)", color="tab:orange")
        ax.axhline(0, color="k", lw=0.5)
        ax.set_title(f"one step from `{b}`: what it costs in gates and buys in dB")
    fig.tight_layout()
    write_figure(path, fig)


HELD_OUT_HEAD = "## The configurations on the held-out corpus"


def _corpus_cell(r: dict) -> str:
    """A point's held-out corpus figures (explore.measure with opts corpus), or '-' when it has none."""
    c = r.get("corpus")
    if not c or c.get("min") is None:
        return "-"
    return f"{c['min']:.1f} / {c['p5']:.1f} / {c['share_at_db']:.0%} ({c['covered']} scenes)"


def held_out_record(docs: Path, label: str) -> dict | None:
    """docs/validation/<label>.json (`make validate CONFIG=<label's file>`), the point's held-out run, if any."""
    import json

    p = docs / "validation" / f"{label}.json"
    return json.loads(p.read_text()) if p.exists() else None


_HELD_VALUES: dict = {}


def held_out_of(docs: Path, rec: dict) -> dict | None:
    """The held-out run of the configuration a point is: docs/validation/<label>.json, else the run whose
    configuration file (config_path) has the point's keys exactly (a sweep step such as `compact quadric_clocks=6
    cmap_clocks=4 samples=4` is config/candidates/compact_q6c4_s4.toml)."""
    import json

    h = held_out_record(docs, rec["label"])
    if h is not None or not rec.get("config"):
        return h
    from explore.measure import values_of
    from model.hw.config import ConfigError, load_config

    want = {k: v for k, v in rec["config"].items() if k != "name"}
    for p in sorted((docs / "validation").glob("*.json")):
        run = json.loads(p.read_text())
        path = run.get("config_path") or run.get("config")
        if (p, path) not in _HELD_VALUES:
            try:
                _HELD_VALUES[(p, path)] = {k: v for k, v in values_of(load_config(str(ROOT / path) if
                                           (ROOT / path).is_file() else path)).items() if k != "name"}
            except (ConfigError, OSError):
                _HELD_VALUES[(p, path)] = None
        if _HELD_VALUES[(p, path)] == want:
            return run
    return None


def goal_100k_line(b: dict, worst: str, held: dict | None, lead: str = "the best measured") -> str:
    """Issue 27's 100,000-GE goal, judged by the rule that a figure counts only on scenes the configuration was not
    tuned on: every sweep point and candidate was chosen on the eight paper scenes, so the eight-scene figure meets
    the goal only with the point's held-out promise (docs/validation/<name>.json) holding beside it."""
    eight = b["worst_psnr_truth_db"] >= 36
    head = (f"Issue 27's goal, at most 100,000 GE with every scene at least 36 dB against the truth (any pixel rate): "
            f"{lead} is {b['label']}"
            + (f" (`{held['config']}`, {held['config_path']})" if held and held.get("config") != b["label"]
               and held.get("config_path") else "")
            + f", {b['ge_total']:,.0f} GE, {b['min_pixels_per_clock']:.3g} pixel a clock: "
            f"worst scene {worst} {b['worst_psnr_truth_db']:.1f} dB (over all textured pixels, rims included, "
            f"{_f(b.get('worst_psnr_truth_textured_db'), '{:.1f}')})")
    if not eight:
        return head + ": **not met**."
    h, pr = (held or {}).get("promise_result"), (held or {}).get("promise")
    if not h or not pr:
        return (head + ": met on the eight paper scenes, on which it was chosen; not measured held out (`make validate "
                f"CONFIG=<its file>`), so **not shown met** (a figure counts only on scenes a configuration was not "
                "tuned on).")
    t = held["psnr"]["truth"]
    verdict = "holds" if h["holds"] else "broken"
    return (head + f": met on the eight paper scenes, on which it was chosen; held out (`make validate`, "
            f"docs/validation.md: {held['covered']} covered scenes) against the truth min / 5% / median {t['min']} / "
            f"{t['p5']} / {t['median']} dB, its promise ({promise_text(pr)}) "
            f"{h['keep']}/{h['of']} ({h['share']:.1%}): {verdict}; the goal is "
            + ("**met**." if h["holds"] else "**not met** by a configuration whose figures count (a figure counts "
                                                "only on scenes the configuration was not tuned on)."))


# issue 27's 100,000-GE goal on formats that hold held out: compact (whose formats do) with 4 samples, and the two
# features with the most gates to give back (explore/space.py FEATURE_STEPS["compact"])
GAP_POINT = "compact samples=4"
# issue 27's folds of GAP_POINT (config/candidates/compact_q6_s4.toml, compact_q6c4_s4.toml): the same pixels, bit
# for bit, on fewer gates and more clocks
GAP_FOLDS = (("compact quadric_clocks=6 samples=4", "the quadric on one multiplier over six clocks (quadric_clocks=6)"),
             ("compact quadric_clocks=6 cmap_clocks=4 samples=4",
              "the colour map's box filter a channel a clock as well (cmap_clocks=4)"))
GAP_TRADES = (("compact filter=mip samples=4", "the MIP map in place of the summed-area table", ""),
              ("compact noise_gradient=false samples=4", "no noise gradient in the filter width",
               "; a change to every scene that asks for the gradient, as the paper's noisy scenes do "
               "(model.scene.passes.approximations), so `make validate` does not cover those"))


def goal_100k_gap(recs: list) -> list[str]:
    """What the 100,000-GE goal would take on formats that hold held out: GAP_POINT's gates by block, how far over
    the budget they are, and what each of GAP_TRADES gives back and costs (the worst scene against the truth)."""
    by = {r["label"]: r for r in recs if r.get("status") == "ok"}
    g = by.get(GAP_POINT)
    if g is None or g.get("worst_psnr_truth_db") is None:
        return []

    def worst(r):
        s = min(r["scenes"], key=lambda k: r["scenes"][k]["psnr_truth_db"])
        return f"{r['worst_psnr_truth_db']:.1f} dB ({s})"

    blocks = ", ".join(f"{k} {v:,.0f}" for k, v in sorted((g.get("blocks_ge") or {}).items(), key=lambda kv: -kv[1]))
    L = [f"What it would take on formats that hold held out: `{GAP_POINT}` (compact's formats, chosen on the fit "
         f"corpus, and 4 samples a pixel, {g['min_pixels_per_clock']:.3g} pixel a clock) is {g['ge_total']:,.0f} GE with "
         f"its worst scene at {worst(g)} against the truth: the goal's quality, {g['ge_total'] - 100_000:+,.0f} GE "
         f"({g['ge_total'] / 100_000 - 1:+.1%}) over its budget. Its blocks (GE): {blocks}."]
    for label, what, caveat in GAP_TRADES:
        r = by.get(label)
        if r is not None and r.get("worst_psnr_truth_db") is not None:
            L[-1] += (f" With {what} (`{label}`{caveat}): {r['ge_total']:,.0f} GE ({r['ge_total'] - g['ge_total']:+,.0f}), "
                      f"worst scene {worst(r)}.")
    L[-1] += " `python -m synth.run --config compact --hier colour_map` says where the colour map's gates are."
    folds = [(by[label], what) for label, what in GAP_FOLDS if label in by and by[label].get("worst_psnr_truth_db") is not None]
    if folds:
        same = all(r["scenes"][k]["psnr_truth_db"] == g["scenes"][k]["psnr_truth_db"] for r, _ in folds for k in g["scenes"])
        t = ("Folding gives gates back for clocks" + (" without changing a pixel's figure (every scene's PSNR as "
                                                       f"`{GAP_POINT}`'s)" if same else "") + ":")
        for r, what in folds:
            t += (f" with {what} (`{r['label']}`): {r['ge_total']:,.0f} GE ({r['ge_total'] - g['ge_total']:+,.0f}), "
                  f"{r['min_pixels_per_clock']:.3g} pixel a clock, worst scene {worst(r)};")
        last = folds[-1][0]
        t = t[:-1] + (f": {last['ge_total'] - 100_000:+,.0f} GE against the budget, "
                      + ("within it." if last["ge_total"] <= 100_000 else "still over it."))
        L.append("")
        L.append(t)
    return L


def goal_100k_lines(small: list[dict], docs: Path) -> list[str]:
    """The 100,000-GE goal over the points of at most 100,000 GE: judged on the best of those that meet it on the
    eight scenes and were measured held out (a promise that holds first), else on the best measured; then the best
    measured if it is another point, and how far the held-out corpus's worst scene is from 36 dB on every
    configuration measured there."""
    import json

    def worst_of(r):
        return min(r["scenes"], key=lambda s: r["scenes"][s]["psnr_truth_db"])

    def key(r):
        return (r["worst_psnr_truth_db"], -r["ge_total"])

    b = max(small, key=key)
    helds = [(r, held_out_of(docs, r)) for r in small if r["worst_psnr_truth_db"] >= 36]
    helds = [(r, h) for r, h in helds if h]
    holding = [(r, h) for r, h in helds if (h.get("promise_result") or {}).get("holds")]
    pick = max(holding or helds, key=lambda rh: key(rh[0])) if helds else (b, held_out_of(docs, b))
    r, h = pick
    L = [goal_100k_line(r, worst_of(r), h, "the best measured" if r is b else
                        "the best measured at 36 dB whose held-out promise " + ("holds" if holding else "was measured"))]
    if r is not b:
        hb = held_out_of(docs, b)
        pb, rb = (hb or {}).get("promise"), (hb or {}).get("promise_result")
        L[-1] += (f" The best on the eight scenes alone, {b['label']} ({b['ge_total']:,.0f} GE, "
                  f"{b['worst_psnr_truth_db']:.2f} dB against {r['worst_psnr_truth_db']:.2f}), "
                  + ("was not measured held out." if not (pb and rb) else
                     f"held out keeps its promise ({promise_text(pb)}) on {rb['keep']}/{rb['of']} ({rb['share']:.1%}): "
                     + ("holds." if rb["holds"] else "broken.")))
    mins = []
    for p in sorted((docs / "validation").glob("*.json")):
        run = json.loads(p.read_text())
        t = (run.get("psnr") or {}).get("truth") or {}
        if t.get("min") is not None:
            mins.append((t["min"], run["config"], t.get("median")))
    if mins:
        top = max(mins)
        med = {c: (m, md) for m, c, md in mins}
        L[-1] += (" On the held-out corpus itself (48-px random scenes and the hard cases), the goal's figure, the worst "
                  "scene against the truth, is " + ("below 36 dB on every configuration measured there, whatever its "
                                                    "gates" if top[0] < 36 else "at least 36 dB on some")
                  + f" (the highest: `{top[1]}`, {top[0]} dB, median {top[2]} dB"
                  + (f"; `full` {med['full'][0]} dB, median {med['full'][1]} dB" if "full" in med else "") + ").")
    return L


def held_out_section(docs: Path) -> list[str]:
    """The held-out figures of the named configurations (docs/validation/<name>.json, `make validate`),
    to stand next to the eight scenes' figures above."""
    import json

    rows = []
    for p in sorted((docs / "validation").glob("*.json")):
        s = json.loads(p.read_text())
        h, r = s.get("promise_result"), s["psnr"]["reference"]
        pr = s.get("promise")
        rows.append(f"| {s['config']} | {s['covered']} of {s['scenes']} | {r['min']} / {r['p5']} / {r['median']} | "
                    + (f"{pr['psnr_db']} dB vs {pr['against']}: {h['keep']}/{h['of']} ({h['share']:.1%}) "
                       f"{'holds' if h['holds'] else 'broken'}" if h and pr else "-") + " |")
    if not rows:
        return []
    return [HELD_OUT_HEAD, "",
            "The figures above are measured on the eight paper scenes, on which the formats were narrowed. On the "
            "held-out corpus (`make validate`, docs/validation.md: random scenes of the kind users write and the hard "
            "cases, none tuned on), the covered scenes' PSNR against the float reference (min / 5% / median, dB):", "",
            "| configuration | covered scenes | vs reference | promise |", "|---|---|---|---|", *rows, ""]


def write(res: dict, out: Path | None = None, docs: Path | None = None) -> Path:
    docs = docs or ROOT / "docs"
    recs, summ = res["records"], res["summary"]
    img = docs / "images"
    plot_front(recs, img / "tradeoffs.png")
    plot_front(recs, img / "tradeoffs_truth.png", "truth")
    rows = knob_steps(recs)
    plot_knobs(rows, img / "tradeoffs_knobs.png")
    front = space.pareto(recs)
    o = summ["opts"]
    L = ["# Speed against error: the design-space sweep", "",
         f"Written by `make explore` (explore/sweep.py) from out/explore/results.json: {summ['points']} configurations "
         f"({summ['ok']} measured, {summ['failed']} failed, each with its reason below), measured on source "
         f"`{summ['source']}` (explore.measure.source_hash). The points' own measuring time adds up to "
         f"{summ.get('point_seconds', 0) / 60:.0f} min (one worker's time, each point once); this run took "
         f"{summ['wall_seconds'] / 60:.1f} min on {summ['scheduler']} ({summ['workers']} workers), measuring "
         f"{summ.get('measured_now', '?')} points and reading the others from out/explore/points/ (a rerun measures "
         f"only what is missing or changed). Blocks synthesized {summ['blocks_synthesized']}, read from the block "
         f"cache {summ['blocks_cached']} (each point's counts, summed).", "",
         "Each point: gate equivalents from `make synth`'s method (each block alone through synth/synth.py, Yosys "
         "with synth/cells.lib, times its instances, plus texture_pipeline's glue; storage apart; each block's "
         "netlist cached by its parameter set), logic depth in cells, pixels per clock of each scene (its textures' "
         f"terms on the noise units), and per scene at {o['size']}x{o['size']}: PSNR of the golden model against the "
         "float reference of the scene as written and against the supersampled truth (model.scene.truth, stratified "
         f"jittered, {o.get('truth_ss', '-')}x{o.get('truth_ss', '-')} samples a pixel and "
         f"{o.get('truth_band_ss', '-')}x{o.get('truth_band_ss', '-')} where the filter width exceeds N/8; a quarter of "
         "the converged rates of docs/scenes.md, enough to rank configurations), "
         f"the largest error in LSB; and {', '.join(o['rtl_scenes'])} at {o['rtl_size']}x{o['rtl_size']} through the "
         "RTL under Verilator, every pixel against the golden model.", "",
         "## The plan (explore/space.py)", "",
         "1. The named configurations: " + ", ".join(f"`{n}`" for n in space.NAMED) + "; the candidates "
         + ", ".join(f"`{n}` (config/candidates/{n}.toml)" for n in space.CANDIDATES) + ".",
         f"2. A grid around `{space.GRID_BASE}` over the knobs that trade gates for clocks and quality: "
         + "; ".join(f"{k} in {list(v)}" for k, v in space.GRID.items()) + ".",
         "3. One-at-a-time steps from each named configuration: every feature switched (the filters among them: "
         "`sat2`, the trapezoid, and `sat_fc`, the frequency clamp), and the formats a few "
         "bits either way (a precision step moves a word and its fraction together, so the range stays).",
         f"4. A refinement around the Pareto front: each front point with every step that cost its base less than "
         f"{space.REFINE_DB} dB at the worst scene (at most {space.REFINE_MAX}).", "",
         "![GE against worst-scene PSNR](images/tradeoffs.png)", "",
         "## The Pareto front", "",
         "No other configuration has fewer gates and a better worst scene.", "",
         "| configuration | GE | worst PSNR vs reference (dB) | worst PSNR vs truth (dB) | slowest px/clock | logic depth "
         "| held-out corpus: worst / 5% / share at 50 dB |",
         "|---|---|---|---|---|---|---|"]
    L += [f"| {r['label']} | {r['ge_total']:,.0f} | {r['worst_psnr_ref_db']:.1f} | {r['worst_psnr_truth_db']:.1f} | "
          f"{r['min_pixels_per_clock']:.3g} | {r['logic_depth']} | {_corpus_cell(r)} |" for r in front]
    tfront = space.pareto(recs, y="worst_psnr_truth_db")
    L += ["", "## What the eye sees: the front against the truth", "",
          "The same points against the converged truth (the pixel's true average): no other configuration has fewer "
          "gates and a better worst scene against the truth. The filter sets this error, not the formats' bits: a "
          "point can lead the front against the reference and not this one. Measured over the texture interior "
          "(model/scene/rim.py): the textured pixels less a one-pixel rim at every silhouette, where the truth averages "
          "the pixel's coverage too (the texture mixed with what lies behind the edge) and the front end shades the "
          "pixel as covered: that error is the same for every configuration of the texture unit. The figure over "
          "all textured pixels, rims included, is in the table of every point below (worst vs truth, rims included).", "",
          "![GE against worst-scene PSNR vs truth](images/tradeoffs_truth.png)", "",
          "| configuration | GE | worst PSNR vs truth (dB) | worst PSNR vs reference (dB) | filter | slowest px/clock |",
          "|---|---|---|---|---|---|"]
    L += [f"| {r['label']} | {r['ge_total']:,.0f} | {r['worst_psnr_truth_db']:.1f} | {r['worst_psnr_ref_db']:.1f} | "
          f"{r['config'].get('filter', '-')} | {r['min_pixels_per_clock']:.3g} |" for r in tfront]
    L += ["", "### Best for the eye, by gate budget and pixel rate", "",
          "Among the measured points: within the gate budget, at least the pixel rate on the slowest scene, the best "
          "worst scene against the truth (dB, its GE).", "",
          "| gate budget | " + " | ".join(lab for _, lab in EYE_RATES) + " |", "|---|" + "---|" * len(EYE_RATES)]
    eye = best_for_eye(recs)
    for b in BUDGETS:
        cells = [e["best"] for e in eye if e["budget"] == b]
        L.append(f"| {b:,} | " + " | ".join("none measured" if r is None else
                                             f"{r['label']}: {r['worst_psnr_truth_db']:.1f} dB ({r['ge_total']:,.0f} GE)"
                                             for r in cells) + " |")
    small = [r for r in recs if r["status"] == "ok" and r["ge_total"] <= 100_000 and r.get("worst_psnr_truth_db") is not None]
    if small:
        L += [""] + goal_100k_lines(small, docs)
    gap = goal_100k_gap(recs)
    if gap:
        L += [""] + gap
    L += [""] + held_out_section(docs)
    L += ["## What one step of a knob costs", "",
          "Against its base (the worst scene, PSNR against the float reference); negative GE is a saving.", "",
          "![per knob](images/tradeoffs_knobs.png)", "",
          "| base | step | GE change | GE % | worst dB change | depth change | px/clock (base) |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        if "d_ge" in r:
            L.append(f"| {r['base']} | {r['step'] if r['step'] != 'grid' else r['label']} | {r['d_ge']:+,.0f} | "
                     f"{r['d_ge_pct']:+.1f}% | {r['d_db']:+.1f} | {r['d_depth']:+d} | "
                     f"{r['pxclk']:.3g} ({r['base_pxclk']:.3g}) |")
    scenes = o["scenes"]
    L += ["", "## Every point", "",
          "PSNR per scene against the float reference (dB); GE; bit-exact: the Verilator check.", "",
          "| configuration | status | GE | comb | seq | depth | px/clock | " + " | ".join(scenes)
          + " | worst vs truth | worst vs truth, rims included | max err (LSB) | bit-exact | held-out: worst / 5% / at 50 dB |",
          "|---|---|---|---|---|---|---|" + "---|" * len(scenes) + "---|---|---|---|---|"]
    for r in recs:
        if r["status"] == "failed":
            L.append(f"| {r['label']} | failed | " + " | ".join(["-"] * (6 + len(scenes) + 5)) + " |")
            continue
        sc = r["scenes"]
        L.append(f"| {r['label']} | {r['status']} | {r['ge_total']:,.0f} | {r['ge_comb']:,.0f} | {r['ge_seq']:,.0f} | "
                 f"{r['logic_depth']} | {r['min_pixels_per_clock']:.3g} | "
                 + " | ".join(f"{sc[s]['psnr_ref_db']:.1f}" for s in scenes)
                 + f" | {r['worst_psnr_truth_db']:.1f} | {_f(r.get('worst_psnr_truth_textured_db'), '{:.1f}')} | "
                 f"{max(v['max_error_lsb'] for v in sc.values())} | "
                 f"{'yes' if r['rtl']['bit_exact'] else 'NO'} ({r['rtl']['pixels']} px) | {_corpus_cell(r)} |")
    bad = [r for r in recs if r["status"] != "ok"]
    if bad:
        L += ["", "## Points that failed, and why", ""] + [f"- {r['label']}: {r['error']}" for r in bad]
    L += ["", "## Reproduce", "", "    make explore                 # the sweep (JOBS= workers; DASK_SCHEDULER_ADDRESS= or "
          "EXPLORE_FLAGS=--scheduler tcp://HOST:PORT for a cluster)",
          "    python -m explore.report     # this page again from out/explore/results.json", ""]
    from model.hw.config import doc_stamp

    L.append(doc_stamp(list(space.NAMED)))
    docs.mkdir(parents=True, exist_ok=True)
    p = docs / "tradeoffs.md"
    p.write_text("\n".join(L) + "\n")
    return p


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m explore.report")
    ap.add_argument("--results", type=Path, default=ROOT / "out" / "explore" / "results.json")
    ap.add_argument("--docs", type=Path, default=ROOT / "docs")
    a = ap.parse_args(argv)
    if not a.results.exists():
        print(f"explore.report: {a.results}: no results (run `make explore`)", file=sys.stderr)
        return 2
    print(write(json.loads(a.results.read_text()), docs=a.docs))
    return 0


if __name__ == "__main__":
    sys.exit(main())
