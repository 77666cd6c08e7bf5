"""The sweep's plan: which configurations `make explore` measures, and why.

Three parts (docs/tradeoffs.md restates them):
1. **The named configurations** (config/*.toml: full, reduced, compact) and `full_wide`, the
   formats `full` had before its 50-dB fit; and the candidates of CANDIDATES (config/candidates/).
2. **A grid over the knobs that matter most** for gates against clocks and quality, around
   `compact` (every noise term of the scenes on few units): noise units U (clocks a pixel),
   the blend, and the quadric's clocks: 4 x 2 x 2 points.
3. **One-at-a-time steps** from each named configuration: every feature switched (the filters
   too: sat2 and sat_fc, and sub-pixel samples, 2 and 4 a pixel: clocks for quality; measured
   against the truth like every point), and every
   format a few bits either way. A precision step keeps the range: the word and its fraction
   move together (s_w with s_frac, ...), so a step changes precision, not what fits.
4. **A refinement around the Pareto front** (`refine`): each front point of the first three
   parts with every one-at-a-time narrowing that cost its base less than REFINE_DB at the worst
   scene, so the front is searched where it is.

A point is a dict of configuration keys (model.hw.config.SCHEMA); a point the configuration
checks reject is still measured (its record says why it failed).
"""
from __future__ import annotations

from itertools import product

from model.hw.config import ROOT, SCHEMA, config_values, load_config

NAMED = ("full", "full_wide", "reduced", "compact")  # full_wide: what the 50-dB fit saved
# measured candidates (config/candidates/<name>.toml), points of their own: compact_narrow, compact's formats
# fitted to the eight scenes (98,793 GE), the one unit under 100,000 GE with every noise term, and
# compact_narrow_s2, it with 2 samples and j_w one narrower (issue 27's goal: at most 100,000 GE, 36 dB); and the
# trapezoid on full's held-out-safe words narrowed to fit it (issue 27, docs/filters.md: full's own f_frac and
# w_cap_log2 do not fit sat2, so the steps `full filter=sat2` fail): alone, with frequency clamping, and that with
# 4 samples, so that the fronts against the truth and the best-for-the-eye table hold the trapezoid
CANDIDATES = ("compact_narrow", "compact_narrow_s2", "full_sat2_heldout", "full_sat2_fc_heldout",
              "full_sat2_fc_s4_heldout")
GRID_BASE = "compact"
GRID = {"noise_units": (1, 2, 3, 5), "blend": ("cubic", "linear"), "quadric_clocks": (1, 2)}
REFINE_DB = 1.0  # a narrowing that cost its base less than this (worst scene, dB) is tried on the front
REFINE_MAX = 3  # at most this many refinement points

# precision steps: (label, {key: delta}); the word and its fraction move together
def _prec(word: str, frac: str, d: int) -> tuple[str, dict]:
    return (f"{frac}{d:+d}", {word: d, frac: d})


def _width(key: str, d: int) -> tuple[str, dict]:
    return (f"{key}{d:+d}", {key: d})


FORMAT_STEPS = [
    _prec("s_w", "s_frac", -2),
    _prec("q_w", "q_frac", -2),
    _prec("t_w", "t_frac", +2),
    _prec("a_w", "a_frac", -1),
    _width("p_frac", -2),
    _width("n_frac", -2),
    _width("f_frac", -2),
    _width("c_frac", -1),
    _width("j_w", -1),
    _width("norm_bits", -1),
    _width("w_cap_log2", +2),
    _width("div_bits", -2),
]
# feature steps per base: (label, {key: value})
FEATURE_STEPS = {
    "compact": [("transform=affine", {"transform": "affine"}), ("amplitude=any", {"amplitude": "any"}),
                ("filter=mip", {"filter": "mip"}), ("filter=none", {"filter": "none"}),
                ("filter=sat2", {"filter": "sat2"}),
                ("noise_gradient=false", {"noise_gradient": False}), ("noise_terms=4", {"noise_terms": 4}),
                ("div_bits=0", {"div_bits": 0}), ("hash_bits=8", {"hash_bits": 8}), ("samples=2", {"samples": 2}),
                ("filter=sat_fc", {"filter": "sat_fc"}),
                # issue 27's 100,000-GE goal (stop 43): four samples, and with them the two features whose
                # gates come back most (the colour map's MIP map for the SAT's; no noise gradient in the width)
                ("samples=4", {"samples": 4}), ("filter=mip samples=4", {"filter": "mip", "samples": 4}),
                ("noise_gradient=false samples=4", {"noise_gradient": False, "samples": 4}),
                # the quadric on one multiplier (qmac_diag_serial, six clocks a sample), alone and with four samples
                ("quadric_clocks=6", {"quadric_clocks": 6}), ("quadric_clocks=6 samples=4", {"quadric_clocks": 6, "samples": 4}),
                # and the colour map a channel a clock (cmap_sat CLOCKS = 4): both folds with four samples
                ("quadric_clocks=6 cmap_clocks=4 samples=4", {"quadric_clocks": 6, "cmap_clocks": 4, "samples": 4})],
    "reduced": [("noise_terms=4", {"noise_terms": 4, "noise_units": 4}), ("blend=cubic", {"blend": "cubic"}),
                ("noise_gradient=true", {"noise_gradient": True}), ("noise_units=1", {"noise_units": 1}),
                ("quadric=full", {"quadric": "full"}), ("filter=sat2", {"filter": "sat2"}),
                ("filter=sat_fc", {"filter": "sat_fc"}), ("samples=2", {"samples": 2}), ("samples=4", {"samples": 4}),
                ("filter=sat2 samples=4", {"filter": "sat2", "samples": 4})],
    # a step of full's noise term costs Yosys about 5 minutes: the one that says most; the filters
    # (issue 27: what the eye sees) change the colour map only, its noise terms come from the cache
    "full": [("pow2 T and a", {"transform": "pow2", "amplitude": "pow2"}), ("filter=sat2", {"filter": "sat2"}),
             ("filter=sat_fc", {"filter": "sat_fc"}), ("samples=2", {"samples": 2}), ("samples=4", {"samples": 4}),
             ("filter=sat2_fc samples=4", {"filter": "sat2_fc", "samples": 4})],
}
# the format steps taken from each base (full's formats are swept by `make fit`'s search, which
# synthesizes only what it keeps: a full-width noise term takes Yosys about 5 minutes)
FORMAT_BASES = ("compact", "reduced")
REDUCED_FORMAT_STEPS: set = set()  # reduced's formats: its feature steps only (time)


def apply(base: dict, change: dict, delta: bool) -> dict:
    v = dict(base)
    for k, x in change.items():
        v[k] = v[k] + x if delta else x
    return v


# the machinery's test (make test): three cheap points, one of them rejected by the configuration
# checks (w_cap_log2 below n_log2_max), so that a failed point is seen recorded
TEST_PLAN = ("reduced", [_width("div_bits", -2), _width("w_cap_log2", -3)])


def plan(kind: str = "full") -> list[dict]:
    """[{"label", "base", "step", "values"}] of parts 1-3, without duplicates (the first label wins);
    kind "test": TEST_PLAN."""
    if kind == "test":
        b, steps = TEST_PLAN
        v = config_values(load_config(b))
        return [{"label": b, "base": b, "step": None, "values": v}] + [
            {"label": f"{b} {lab}", "base": b, "step": lab, "values": apply(v, ch, True)} for lab, ch in steps]
    pts = []
    bases = {n: config_values(load_config(n)) for n in NAMED}
    for n in NAMED:
        pts.append({"label": n, "base": n, "step": None, "values": bases[n]})
    for n in CANDIDATES:
        pts.append({"label": n, "base": n, "step": None,
                    "values": config_values(load_config(str(ROOT / "config" / "candidates" / f"{n}.toml")))})
    for combo in product(*GRID.values()):
        ch = dict(zip(GRID, combo))
        pts.append({"label": "grid " + " ".join(f"{k}={v}" for k, v in ch.items()), "base": GRID_BASE,
                    "step": "grid", "values": apply(bases[GRID_BASE], ch, False)})
    for n in sorted(NAMED, key=lambda n: n == "full"):  # full's steps last: their noise terms take longest
        for label, ch in FEATURE_STEPS.get(n, []):
            pts.append({"label": f"{n} {label}", "base": n, "step": label, "values": apply(bases[n], ch, False)})
        if n in FORMAT_BASES:
            for label, ch in FORMAT_STEPS:
                if n == "reduced" and label not in REDUCED_FORMAT_STEPS:
                    continue
                pts.append({"label": f"{n} {label}", "base": n, "step": label, "values": apply(bases[n], ch, True)})
    return dedupe(pts)


def dedupe(pts: list[dict]) -> list[dict]:
    seen, out = set(), []
    for p in pts:
        k = tuple(sorted(p["values"].items()))
        if k not in seen:
            seen.add(k)
            out.append(p)
    return out


def pareto(recs: list[dict], x: str = "ge_total", y: str = "worst_psnr_ref_db") -> list[dict]:
    """The records no other record beats: fewer or equal GE and higher or equal worst PSNR, one
    strictly (ok records only), in increasing GE."""
    ok = sorted((r for r in recs if r["status"] == "ok"), key=lambda r: (r[x], -r[y]))
    front, best = [], float("-inf")
    for r in ok:
        if r[y] > best:
            front.append(r)
            best = r[y]
    return front


def refine(recs: list[dict], planned: list[dict]) -> list[dict]:
    """Part 4: front points (not the named ones) with each cheap narrowing of the steps measured."""
    by_label = {p["label"]: r for p, r in zip(planned, recs)}
    cheap = []
    for p, r in zip(planned, recs):
        base = by_label.get(p["base"])
        if p["step"] in (None, "grid") or r["status"] != "ok" or base is None or base["status"] != "ok":
            continue
        if r["ge_total"] < base["ge_total"] and base["worst_psnr_ref_db"] - r["worst_psnr_ref_db"] < REFINE_DB:
            cheap.append((p["values"], base["config"], p["step"]))
    front = [r for r in pareto(recs) if r["config"] not in [by_label[n]["config"] for n in NAMED if n in by_label]]
    out = []
    for fr in front:
        for vals, basevals, step in cheap:
            ch = {k: v for k, v in vals.items() if basevals[k] != v}
            # a format step moves the front point's word by the same bits; a feature step sets the value
            fmt = all(SCHEMA[k][0] == "formats" for k in ch)
            new = apply(fr["config"], {k: ch[k] - basevals[k] for k in ch}, True) if fmt else apply(fr["config"], ch, False)
            out.append({"label": f"refine {fr.get('label', fr['name'])} + {step}", "base": "refine", "step": step,
                        "values": new})
    known = {tuple(sorted(p["values"].items())) for p in planned}
    out = [p for p in dedupe(out) if tuple(sorted(p["values"].items())) not in known]
    return out[:REFINE_MAX]
