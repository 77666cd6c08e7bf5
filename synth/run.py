"""Gate counts of the pipeline per configuration: `make synth`, `make synth-check`, `make synth-blocks`.

Each block module is synthesized on its own (synth/synth.py, Yosys, GE liberty
synth/cells.lib) with the configuration's generated parameters; the pipeline total
is the sum of its blocks times their instance counts plus the glue of
texture_pipeline itself (synthesized with the blocks as black boxes). Blocks
have registered outputs, so the logic depth of the pipeline is the largest of
the blocks' and the glue's. Storage (colour table, SAT, MIP levels) is counted
as bits, apart from logic GE.

    python -m synth.run --config full      # synth/reports/full.json and .md
    python -m synth.run --all              # both
    python -m synth.run --check            # budgets met or missed; fail above a configuration's ceiling
    python -m synth.run --blocks           # GE of each block for both configurations
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from hdlbuild import ROOT, block_params, config_of, module_names, rtl_modules
from model.hw.config import (CONFIG_NAMES, STAMP, ConfigError, base_of, clocks_per_pixel, cmap_family, config_hash, freq_clamp,
                             is_config_file, load_config,
                             noise_term_instances, rtl_source_hash)
from model.hw.config import fc_variant as config_fc_variant

REPORTS = ROOT / "synth" / "reports"
# each configuration's budget: the paper's gate count of its model (section 4.2; compact: the
# 100k-gate budget with the full model's image quality, issue 13)
BUDGET = {"reduced": 100_000, "full": 1_250_000, "compact": 100_000}
PAPER_MODELS = ("full", "reduced")  # budgets that are the paper's gate counts
# A budget a configuration's promise is measured to miss: `make synth-check` prints the budget as MISSED
# (with the excess) and fails only above this ceiling, a guard against growth. full: its held-out promise
# (issue 26: 50 dB against the float reference on 99% of the held-out scenes) costs 1,361,859 GE in block
# floating point; every narrower step measured breaks the promise (docs/numerics.md, "Block floating point").
CEILING = {"full": (1_400_000, "issue 26: the held-out promise costs more than the paper's budget"),
           "reduced": (115_000, "issue 26: re-derived on 6,400 fit scenes (stop 41), q s24.17, f_frac 14 and c_frac 10 "
                                "keep the held-out promise (69 of 69 over five unseen draws); stop 36's formats "
                                "(106,438 GE, derived on 800) break it on two of them, the narrow ones (95,414 GE) more"),
           "compact": (135_000, "issue 26: re-derived on 3,200 fit scenes (stop 39) and c_frac 10 from 6,400 (stop 41), "
                                "these formats keep the held-out promise; its narrow formats (98,793 GE) break it by 4 "
                                "scenes, stop 36's (125,965 GE, derived on 800) by 1")}
# block label -> module; the noise term is instantiated once per term, or (folded) per noise unit
BLOCKS = {"quadric": "quadric_mac", "noise_term": "noise_term", "filter_width": "filter_width",
          "colour_map": "colour_map"}
TOP = "texture_pipeline"
GLUE = ("delay_line", "tex_regs", "axis_skid", "noise_fold", "sum_tree", "cm_align", "noise_leaves", "texture_sum")  # small modules counted with the top's glue (control), not as blocks
# the blocks of the frequency-clamping filters ("sat_fc", "sat2_fc"): fc_weight once, fc_scale a term
FC_BLOCKS = {"fc_weight": "fc_weight", "fc_scale": "fc_scale"}
# the blocks of sub-pixel samples (features.samples > 1): the sample sequencer at the front, the average at the end
SAMPLE_BLOCKS = {"sample_expand": "sample_expand", "sample_average": "sample_average"}
# modules kept whole inside a block (synth.py --keep-modules), so that equal instances are synthesized once:
# cmap_sat2's four sat2_integral (the colour-map family "sat2": filters sat2, sat2_fc; flattened, colour_map
# did not finish in 30 min)
KEEP_MODULES = {"sat2": ("sat2_integral",)}


def config_blocks(cfg) -> dict:
    """label -> module of the blocks `cfg` instantiates (the fc blocks only with sat_fc, sat2_fc; the
    sample blocks only with samples > 1)."""
    return {**BLOCKS, **(FC_BLOCKS if freq_clamp(cfg) and cfg.noise_terms > 0 else {}),
            **(SAMPLE_BLOCKS if cfg.samples > 1 else {})}


def _cell(v) -> str:
    """A report value as a table cell: numbers with thousands separators, None as a dash."""
    if v is None:
        return "-"
    return str(v) if isinstance(v, (bool, str)) else f"{v:,}"


def rtl_files():
    return sorted(str(p) for p in (ROOT / "rtl").glob("*.v"))


# What a block's synthesis reads: its module closure, nothing else (stop 45). Yosys numbers the
# cells it creates across every file read, and ABC's result follows that numbering, so a block
# read with all of rtl/ moved by about 1% whenever another, unrelated file changed (docs/synthesis.md,
# docs/simulation.md stop 44); read alone, a block's gates change only when its own files do, and
# explore.measure's netlist cache (keyed by these files) holds exactly what synth_one computes.
READS = "closure"


def block_files(top: str) -> list[str]:
    """The rtl/*.v files block `top` is built from: its own and those of every module it
    instantiates, transitively (rtl/*.vh come in through --include)."""
    mods = rtl_modules(ROOT / "rtl")
    return sorted(str(mods[m]) for m in module_names(top, ROOT / "rtl"))


def synth_one(config, top: str, lib_files=(), out: Path | None = None, keep: Path | None = None,
              keep_modules=()) -> dict:
    """One block (or the top's glue, with `lib_files` as black boxes) with the parameters the
    configuration (a name or a Config) gives it (hdlbuild block_params); its report is written
    to `out` (default build/synth/<config>/<top>.json). keep: a directory for Yosys's scripts,
    logs and the mapped netlist netlist.v (synth/netlist.py simulates it). keep_modules: modules
    synthesized as modules of their own (`stat` of the kept hierarchy: keep's stat_hier.txt)."""
    cfg = config_of(config)
    params = block_params(cfg, top)
    files = [f for f in rtl_files() if Path(f).stem in (top, *GLUE)] if lib_files else block_files(top)
    out = out or ROOT / "build" / "synth" / cfg.name / f"{top}.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    cmd = [sys.executable, str(ROOT / "synth" / "synth.py"), "--top", top, "--files", *files,
           "--include", str(ROOT / "rtl"), "--json", str(out),
           "--param", *(f"{k}={v}" for k, v in params.items())]
    if lib_files:
        cmd += ["--lib-files", *lib_files]
    if keep is not None:
        cmd += ["--keep", str(keep)]
    kept = (*KEEP_MODULES.get(cmap_family(cfg), ()), *keep_modules) if not lib_files else ()
    if kept:
        cmd += ["--keep-modules", *kept]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        msg = (r.stderr.strip().splitlines() or ["?"])[-1]
        raise SynthError(f"synth: {top} ({cfg.name}): {msg}")
    return json.loads(out.read_text())


class SynthError(SystemExit):
    """A block failed to synthesize (one line); a SystemExit, so the commands end with it."""


def block_jobs(cfg) -> dict:
    """label -> (module, black-box files) of every separately synthesized piece of the pipeline."""
    lib = [f for f in rtl_files() if Path(f).stem not in (TOP, *GLUE)]
    return {**{label: (mod, ()) for label, mod in config_blocks(cfg).items()}, "control": (TOP, tuple(lib))}


def combine(config: str, cfg, res: dict) -> dict:
    """The pipeline's figures from its pieces' reports (`res`: label -> synth.py report): each
    block times its instance count, plus the glue."""
    count = {"quadric": 1, "noise_term": noise_term_instances(cfg), "filter_width": 1, "colour_map": 1, "control": 1,
             "fc_weight": 1, "fc_scale": cfg.noise_terms, "sample_expand": 1, "sample_average": 1}
    blocks = {}
    for k, r in res.items():
        label = "noise_terms" if k == "noise_term" else k
        blocks[label] = round(r["ge_total"] * count[k], 1)
    tot = lambda key: round(sum(res[k][key] * count[k] for k in res), 1)  # noqa: E731
    rep = {
        "config": config,
        "yosys_version": res["control"]["yosys_version"],
        "ge_total": tot("ge_total"),
        "ge_comb": tot("ge_comb"),
        "ge_seq": tot("ge_seq"),
        "storage_bits": int(sum(res[k]["storage_bits"] * count[k] for k in res)),
        "rom_bits": int(sum(res[k].get("rom_bits", 0) * count[k] for k in res)),
        "transistors_cmos": int(sum(res[k]["transistors_cmos"] * count[k] for k in res)),
        "logic_depth": max(res[k]["logic_depth"] for k in res),
        "logic_depth_by_block": {k: res[k]["logic_depth"] for k in res},
        "pixels_per_clock": round(1 / clocks_per_pixel(cfg), 4),
        "noise_units": cfg.noise_units,
        "noise_terms": cfg.noise_terms,
        "blocks": blocks,
        "block_ge_each": {k: res[k]["ge_total"] for k in res},
        "method": "each block synthesized alone (Yosys synth, abc -liberty synth/cells.lib), times its instance "
                  "count, plus texture_pipeline glue with the blocks as black boxes; storage apart",
    }
    rep["ge_cmos_crosscheck"] = round(rep["transistors_cmos"] / 4, 1)
    return rep


def synth_config(config: str, jobs: int = 2, reports: Path | None = None) -> dict:
    """Every block of a configuration (a name, or a configuration file's path); the report goes to
    synth/reports/<name>.json (reports: elsewhere, e.g. out/synth/ for a file outside config/)."""
    t0 = time.perf_counter()
    config_arg = config
    cfg = load_config(config)
    reports = reports or REPORTS
    # a file's path: its blocks take the loaded configuration (a file outside config/ has no name to load by)
    src = cfg if Path(config).suffix == ".toml" else config
    config = cfg.name if Path(config).suffix == ".toml" else config
    with ThreadPoolExecutor(max_workers=jobs) as ex:
        futs = {label: ex.submit(synth_one, src, mod, lib) for label, (mod, lib) in block_jobs(cfg).items()}
        res = {k: f.result() for k, f in futs.items()}
    rep = combine(cfg.name, cfg, res)
    if Path(config_arg).suffix == ".toml":  # the command that reruns it names the file, not a name config/ lacks
        p = Path(config_arg).resolve()
        rep["config_path"] = str(p.relative_to(ROOT)) if p.is_relative_to(ROOT) else str(p)
    budget = BUDGET.get(config) or BUDGET.get(base_of(config))  # a variant file: its base's budget
    rep.update({"budget_ge": budget, "paper_gates": budget if config in PAPER_MODELS else None,
                "within_budget": budget is not None and rep["ge_total"] <= budget,
                "seconds": round(time.perf_counter() - t0, 1),
                "config_hash": config_hash(cfg), "rtl_hash": rtl_source_hash()})
    reports.mkdir(parents=True, exist_ok=True)
    (reports / f"{cfg.name}.json").write_text(json.dumps(rep, indent=2) + "\n")
    (reports / f"{cfg.name}.md").write_text(markdown(rep))
    return rep


def markdown(rep: dict) -> str:
    lines = [f"# Synthesis report: `{rep['config']}`", "",
             f"Generated by `make synth CONFIG={rep.get('config_path', rep['config'])}` ({rep['yosys_version']}).", "",
             "| figure | value |", "|---|---|"]
    for k in ("ge_total", "ge_comb", "ge_seq", "storage_bits", "transistors_cmos", "ge_cmos_crosscheck",
              "logic_depth", "pixels_per_clock", "noise_terms", "budget_ge", "within_budget"):
        v = rep[k]
        lines.append(f"| {k} | {v:,} |" if isinstance(v, (int, float)) and not isinstance(v, bool) else f"| {k} | {v} |")
    lines += ["", "| block | GE | share | logic depth |", "|---|---|---|---|"]
    depth = rep["logic_depth_by_block"]
    for k, v in rep["blocks"].items():
        d = depth["noise_term" if k == "noise_terms" else k]
        lines.append(f"| {k} | {v:,.0f} | {100 * v / rep['ge_total']:.1f}% | {d} |")
    return "\n".join(lines) + "\n"


def keeps(name: str) -> str:
    """What a configuration builds, in words, from its configuration file (nothing typed twice)."""
    c = load_config(name)
    quad = ("the general quadric (10 coefficients, 15 multipliers)" if c.quadric == "full"
            else "an axis-aligned quadric (B = C = F = 0: 6 multipliers)")
    trans = ("general affine T_i (multipliers)" if c.transform == "affine"
             else "T_i diagonal powers of two (shifts)")
    amp = "amplitudes a_i of any value (multipliers)" if c.amplitude == "any" else "amplitudes a_i = 0 or +-2^k (shifts)"
    grad = "analytic noise gradient in the filter width" if c.noise_gradient else "no noise gradient in the filter width"
    filt = {"sat": "SAT box filter with every mod/clamp edge case (exact integral, "
                   + ("exact division" if c.div_bits == 0 else f"division on a {c.div_bits}-bit normalised width")
                   + ")", "sat2": "the trapezoid filter from a second summed-area table (cmap_sat2)",
            "mip": "MIP-map colour-table filter", "none": "no colour-table filter"}[cmap_family(c)]
    if freq_clamp(c):
        filt += " with frequency clamping of the noise terms (fc_weight, fc_scale)"
    return (f"{quad}; {c.noise_terms} noise terms, {trans}, {amp}, {c.blend} blend, {grad}; {filt}; "
            f"s{c.s_w}.{c.s_frac} coordinates, Jacobian mantissas {c.j_w} bits, colour index .{c.f_frac}, "
            f"gradient .{c.c_frac}, filter width capped at 2^{c.w_cap_log2} entries (config/{name}.toml, "
            f"docs/numerics.md); 1/{clocks_per_pixel(c)} pixel/clock with all {c.noise_terms} terms")


def config_diff(a: str, b: str) -> list[tuple[str, object, object]]:
    """(key, value in a, value in b) for every configuration key whose values differ."""
    from model.hw.config import SCHEMA

    ca, cb = load_config(a), load_config(b)
    return [(k, getattr(ca, k), getattr(cb, k)) for k in SCHEMA if getattr(ca, k) != getattr(cb, k)]


def write_doc() -> None:
    """docs/synthesis.md from synth/reports/*.json."""
    reps = {c: json.loads((REPORTS / f"{c}.json").read_text()) for c in CONFIG_NAMES if (REPORTS / f"{c}.json").exists()}
    if not reps:
        return
    L = ["# Synthesis: gate counts against the paper", "",
         "Written by `make synth` from synth/reports/*.json. Gate equivalents (GE, NAND2 = 1) from Yosys "
         f"({next(iter(reps.values()))['yosys_version']}) mapped to synth/cells.lib (Nangate 45 nm cell areas "
         "divided by NAND2_X1's; sources in the file). Storage (colour table, SAT, MIP levels) is counted in bits, "
         "apart from logic; ROM tables (the hash permutation) are logic. `stat -tech cmos` transistors / 4 is a "
         "cross-check (it prices generic gates, so it runs above the liberty GE). Logic depth is the longest "
         "combinational path in cells. Method: " + next(iter(reps.values()))["method"] + ".", "",
         "| | " + " | ".join(reps) + " |", "|---|" + "---|" * len(reps)]
    rows = [("paper's gates", "paper_gates"), ("budget (GE)", "budget_ge"), ("GE total (logic)", "ge_total"),
            ("GE combinational", "ge_comb"), ("GE sequential", "ge_seq"), ("storage bits", "storage_bits"),
            ("CMOS transistors / 4", "ge_cmos_crosscheck"), ("logic depth (cells)", "logic_depth"),
            ("pixels per clock", "pixels_per_clock"), ("noise terms", "noise_terms"),
            ("within budget", "within_budget")]
    for label, key in rows:
        L.append(f"| {label} | " + " | ".join(_cell(reps[c].get(key)) for c in reps) + " |")
    L += ["", "## Per block (GE, all instances)", "", "| block | " + " | ".join(reps) + " |",
          "|---|" + "---|" * len(reps)]
    for b in next(iter(reps.values()))["blocks"]:
        L.append(f"| {b} | " + " | ".join(f"{reps[c]['blocks'][b]:,.0f} ({100 * reps[c]['blocks'][b] / reps[c]['ge_total']:.0f}%)"
                                          for c in reps) + " |")
    L += ["", "## What each configuration keeps", ""] + [f"- `{c}`: {keeps(c)}." for c in reps]
    if len(reps) > 1:
        L += ["", "What `reduced` drops against `full` (every key of the two configuration files that differs):", "",
              "| key | full | reduced |", "|---|---|---|"]
        L += [f"| {k} | {a} | {b} |" for k, a, b in config_diff("full", "reduced")]
        L += ["", "What that costs in image quality (PSNR against the float reference and the supersampled "
              "truth, per scene): docs/scenes.md (`make renders`)."]
    if "compact" in reps and "reduced" in reps:
        L += ["", "## Two ways to the 100,000-GE budget", "",
              "`reduced` is the paper's way: fewer noise terms and a linear blend, one pixel a clock. `compact` "
              "spends clocks instead of image quality: every noise term of the scenes, the cubic blend and the "
              "noise gradient, on one noise unit (`noise_units`) and a quadric on half its multipliers "
              "(`quadric_clocks`), max(K_used, 2) clocks a pixel (docs/numerics.md: the measurement behind each "
              "width; docs/conformance.md: clocks per pixel and PSNR of every scene). Every key in which they "
              "differ:", "", "| key | reduced | compact |", "|---|---|---|"]
        L += [f"| {k} | {a} | {b} |" for k, a, b in config_diff("reduced", "compact")]
    L += ["", "## Changes to the counts", "",
          "The blocks take their formats as parameters and derive their widths themselves (issue 12): "
          "filter_width bounds its products by its input word (g_w = c_w + j_w + 1, one bit wider than the "
          "old bound on c), texture_pipeline masks the amplitudes of the terms past k_used, and the off-diagonal "
          "T entries (pow2 transforms) and B, C, F (diagonal quadric), which the blocks never read, no longer "
          "reach them, so their registers go. Against the reports of commit cdb7f89 (`git show "
          "cdb7f89:synth/reports/reduced.json`): full +0.5% (the wider g and the k_used masks), reduced -1.8% (the registers).", "",
          "colour_map split into filter-family modules (issue 25: cmap_sat, cmap_divide, cmap_mip, cmap_point; "
          "the same flip-flops, the same function; D in one expression, the FPGA build's two-carry-chain form, in "
          "both builds). Against the reports of commit ccbc7bc, colour_map: full -0.60% (35,239 -> 35,027 GE), "
          "reduced -0.67% (31,587 -> 31,374), compact +0.03% (30,337 -> 30,345); sequential GE unchanged in all "
          "three. That is Yosys/ABC noise: the same run moved blocks whose RTL and flow did not change since "
          "ccbc7bc by as much (quadric -0.13 / -0.33 / -1.11%, noise_term +0.19 / -0.38 / -1.05%, filter_width "
          "+0.61 / -0.08 / +0.87%), and the old colour_map with only the D expression swapped synthesizes to "
          "35,297 (full) and 31,574 (reduced) GE.", "",
          "texture_pipeline's adder tree as its own block (sum_tree, counted with the glue), noise_term split "
          "into noise_xform (the transform, once per axis) and noise_grad (the gradient): the same flip-flops "
          "(sequential GE unchanged in all three), the same function (bit-exact block and frame tests). Against "
          "the reports of commit cc7172b (before both splits), noise_term (each): full +1.20% (57,559 -> 58,249 "
          "GE), reduced -0.26%, compact -0.05%; control (with the tree) -0.04 / +0.25 / +0.03%; totals +0.87 / "
          "-0.31 / -0.15%. That is Yosys/ABC noise: the same noise_term RTL synthesized before the colour_map "
          "split reached main (another set of rtl/ files) gave full +0.55%, reduced +0.28%, compact +0.47%, and "
          "this run moved blocks that did not change by as much (quadric -0.16 / -0.42 / -1.21%, filter_width "
          "+0.30 / +0.57 / +0.89%).", "",
          "texture_pipeline's adder-tree leaves (noise_leaves: the noise_term and fc_scale instances, noise_fold's "
          "sum, the sign extension) and the f / w alignment before colour_map (cm_align) as modules of their own, "
          "counted with the glue (the noise_term instances still counted as blocks): the same flip-flops "
          "(sequential GE unchanged in all three), the same function (bit-exact block and frame tests). Against "
          "the reports of commit 3c6b346, totals: full -0.49% (601,570 -> 598,632 GE), reduced -0.07%, compact "
          "+0.10% (99,660 -> 99,759, within its 100,000 budget); control full +1.62%, reduced -0.03%, compact "
          "-0.09%. Yosys/ABC noise: blocks whose RTL did not change moved as much in the same run (noise_term "
          "-0.77 / +0.09 / +0.16%, filter_width -0.82 / -0.40 / -0.13%, quadric +0.46 / -0.20 / +0.37%).", "",
          "quadric_mac split into its datapath modules (issue 25: qmac_full, qmac_diag, qmac_diag_fold, "
          "qmac_diag_pipe, picked by its parameters; stage 4 stays in quadric_mac): the same flip-flops "
          "(sequential GE unchanged in all three), the same function (bit-exact block and frame tests). Against "
          "`make synth` on its base commit 8ee46ea, quadric: full +1.30% (61,111 -> 61,907 GE), reduced -0.41% "
          "(26,753 -> 26,642), compact +2.27% (19,250 -> 19,688); totals full +0.28% (598,632 -> 600,329), "
          "reduced -0.01% (94,897 -> 94,889), compact +0.50% (99,759 -> 100,262: over its 100,000 budget by 262). "
          "ABC's mapping of the same logic in another cell order: the flattened quadric's generic netlist "
          "already differs (CMOS cross-check, compact 103,608 -> 104,516 transistors) while its flip-flops do "
          "not; the name of the datapath instance changes nothing (u_dp or u_datapath: 19,687.6 GE); and the "
          "new files alone move blocks whose RTL did not change (noise_term, compact, synthesized on 8ee46ea "
          "with the four qmac_*.v files beside it, unused: 23,123 -> 23,271 GE, +0.64%; the old quadric_mac "
          "likewise: 19,250 -> 19,251). compact's 241-GE margin (0.24%) is inside that noise.", "",
          "The split's reports were not regenerated then. Measured on main 7e893f8 (`make synth CONFIG=compact`): "
          "compact 100,210.0 GE (sequential 26,854.5), over its budget by 210; quadric 19,578.3. The split's logic is "
          "not the cause: the quadric's flattened coarse netlist (Yosys `synth -flatten -run :fine`, `stat -width`, "
          "quadric_mac with compact's parameters) has the same cells at the same widths on 8ee46ea's rtl/ and on "
          "7e893f8's (the valid chain's one 4-bit register became a 1-bit and a 3-bit one), and the quadric "
          "synthesized alone (`python synth/synth.py --top quadric_mac --files rtl/*.v --include rtl --param DIAG=1 "
          "CLOCKS=2 S_W=18 S_FRAC=10 Q_W=17 Q_FRAC=10 F_FRAC=11 C_FRAC=5 C_W=21 FPGA_REGS=0`) has the same "
          "flip-flops on both (3,145.0 GE sequential) and 19,250.3 -> 19,578.3 GE: ABC's mapping of the same logic.", "",
          "qmac_diag_fold (compact) without its stage-3 copy: stage 3 registered stage 2's products s_k x_k and "
          "v_k a second time (3 (s_w + v_w) + 3 v_w = 204 flip-flops at compact's widths, 18 and 25). Stage 2's "
          "registers now load only in a vector's second clock and hold through stage 3, which the fold's contract "
          "allows (the next vector's second clock comes two enabled clocks later at the earliest); the same latency, "
          "the same values (tb/qmac_diag_fold, tb/quadric_mac, tb/frame compact, bit-exact). quadric (compact) "
          "synthesized alone (the command above): 19,578.3 -> 18,333.3 GE, sequential 3,145.0 -> 2,482.0. The "
          "reports above (synth/reports/*.json, the rtl hash in the stamp below) predate the quadric_mac split "
          "and this change: `make synth` has not been rerun on them yet, so compact's total with both is not "
          "measured here (the reports after the texture_sum split, below, measure it).", "",
          "texture_sum (issue 25: f and grad f of a pixel, the quadric with its wait, sat_fc's fc_weight and "
          "its alpha delay, noise_leaves and the adder trees, out of texture_pipeline; counted with the glue, "
          "flattened into the control as before): the same flip-flops (sequential GE of the control unchanged "
          "in all three), the same function (bit-exact block and frame tests). The reports above are `make synth` "
          "on main b110d87's rtl/ with it (so with the quadric_mac split, qmac_diag_fold's saving and b110d87). "
          "Control, against the reports before (`git show d7fad7d:synth/reports/<config>.json`): compact -0.02% "
          "(17,301 -> 17,298 GE), reduced -0.07% (8,300 -> 8,295), full -1.07% (28,401 -> 28,097; the same "
          "28,097.3 on 7e893f8, before a37e37c and b110d87, so it is this change's). Totals: compact -0.97% "
          "(99,759 -> 98,788: qmac_diag_fold's registers, sequential 26,855 -> 26,192), reduced +0.28% (94,897 "
          "-> 95,167), full +0.95% (598,632 -> 604,291), the rest of it in blocks this change did not touch: "
          "full quadric +1.47% (61,111 -> 62,011; 61,907 measured on the quadric_mac split's base), noise_terms "
          "+1.07% (462,398 -> 467,350; noise_term's RTL changed in b110d87), filter_width +0.98% (11,708 -> "
          "11,823, its RTL unchanged); on 7e893f8 the same change gave full 601,473 (+0.19% against the "
          "quadric_mac split's 600,329). Yosys/ABC noise on unchanged logic, as above.", "",
          "noise_params (issue 25: noise_term's pow2 decoders and parameter delays, 1e5234a) and fc_weight's "
          "exponent ports (2449d81, none at t_exp_w = a_exp_w = 0): the reports above are `make synth` on main "
          "1e5234a's rtl/: full 604,291 -> 601,571 (-0.45%), reduced 95,167 -> 95,454 (+0.30%), compact "
          "98,788 -> 98,784 (-0.00%); flip-flops unchanged (noise_term alone: the same 265 / 685 / 793 in "
          "reduced / compact / full). Within 0.5%, all of it in the combinational logic ABC maps.", "",
          "The per-term exponents through the unit (issue 26: TERM_E and {te, T}, {ae, a} through the pipeline, "
          "15cd2f8, 0ab6cec, f5395c3; none at t_exp_w = a_exp_w = 0) and sat2_integral's shared products "
          "(111ffd9, filter sat2 only): the reports above are `make synth` on main 36ef353's rtl/ (be1dcd3ec12f), "
          "against 1e5234a's: full 601,571 -> 601,357 (-0.04%), reduced 95,454 -> 95,414 (-0.04%), compact "
          "98,784 -> 98,793 (+0.01%); sequential GE unchanged in all three (67,558.4 / 22,009.5 / 26,191.5). "
          "Within 0.5%: ABC's mapping of the same logic. Again on main 48ac614's rtl/ (b18933406eb8, with filter "
          "sat2_fc's plumbing, 05259b0): every total and block the same to the tenth of a GE.", "",
          "`full` in block floating point (issue 26, stop 34): config/full.toml took the formats of "
          "config/candidates/full_bfp_lean.toml (T_i and a_i as mantissas with an exponent a term, s22.14, "
          "p_frac = n_frac 16, f_frac 20, c_frac 13, the exact filter width), the narrowest measured that keep its "
          "promise on the held-out corpus; the formats it had, fitted to the eight paper scenes, are "
          "config/candidates/full_narrow.toml (601,357 GE on the same rtl/). full 601,357 -> 1,361,116 GE "
          "(`make synth CONFIG=full`, 928 s; the candidate's report gave the same to the tenth): noise terms "
          "464,934 -> 1,126,700 (140,837 each), quadric 61,460 -> 99,966, filter_width 11,831 -> 29,582, colour_map 35,016 -> 59,645 (the exact "
          "division), control 28,117 -> 45,224. Over the paper's 1,250,000 by 111,116 GE (8.9%): `make synth-check` prints "
          "the budget as MISSED and fails only above full's ceiling of 1,400,000 (synth/run.py CEILING), because "
          "every narrower step measured breaks the held-out promise (docs/numerics.md, \"Block floating point\").", "",
          "`reduced` and `compact` re-derived on the fit corpus (issue 26, stop 36: `python -m explore.validate derive`, "
          "docs/numerics.md; their narrow formats are config/candidates/reduced_narrow.toml and compact_narrow.toml, "
          "the figures before on the same rtl/): reduced 95,414 -> 106,513 GE (q s15.8 -> s23.16, f_frac 11 -> 13: "
          "quadric 27,142 -> 35,924, colour_map 31,473 -> 33,008, control 8,304 -> 8,995; noise terms and filter width "
          "within 0.6%), over the paper's 100,000 by 6,513 (6.5%); compact 98,793 -> 126,051 GE (s18.10 -> s20.12, "
          "q s17.10 -> s23.16, j_w 6, p_frac 11, n_frac 12, f_frac 14, c_frac 8: quadric 18,298 -> 26,855, noise "
          "term 23,273 -> 34,774, filter_width 9,719 -> 11,873, colour_map 30,197 -> 33,040, control 17,307 -> 19,509), "
          "over its 100,000 budget by 26,051 (26.1%). `compact` re-derived again on the fit corpus's first 3,200 "
          "scenes (stop 39, docs/numerics.md; stop 36's formats are config/candidates/compact_fit800.toml): s21.13, "
          "q s24.17, j_w 5, p_frac 12, n_frac 13, f_frac 15, norm_bits 6, 131,372 GE on today's rtl/ (125,965 before: "
          "quadric 26,804 -> 28,049, noise term 34,740 -> 39,386, filter_width 11,919 -> 10,989, colour_map "
          "32,993 -> 33,493), over its 100,000 budget by 31.4%. `make synth-check` prints both budgets as MISSED and "
          "fails above their ceilings (then 110,000 and 135,000, synth/run.py CEILING): reduced keeps its held-out "
          "promise (9 of 9), and now compact too (22 of 22, docs/validation.md).", "",
          "Both re-chosen on the fit corpus's first 6,400 scenes (issue 26, stop 41, docs/numerics.md \"Stop 41\"; the "
          "formats before are config/candidates/reduced_fit800.toml and compact_fit3200.toml): reduced by the descent "
          "(`python -m explore.validate derive --config config/candidates/reduced_narrow.toml --db 33 --n 6400`: q "
          "s23.16 -> s24.17, f_frac 13 -> 14, c_frac 6 -> 10), 106,438 -> 110,385 GE (quadric 35,971 -> 37,372, "
          "filter_width 11,313 -> 12,997, colour_map 32,895 -> 33,719, control 8,995 -> 9,104), over the paper's "
          "100,000 by 10.4%, its ceiling raised from 110,000 to 115,000 for it; compact by one word (c_frac 8 -> 10), "
          "131,372 -> 132,578 GE (quadric 28,049 -> 28,378, filter_width 10,989 -> 11,610, control 19,455 -> 19,649), "
          "over its 100,000 budget by 32.6%.", "",
          "Where compact's gates are (stop 43, for issue 27's 100,000-GE goal; `python -m synth.run --config compact "
          "--hier <block>`: each module the block instantiates synthesized as a module of its own, which stops "
          "optimisation across the boundaries, so these run a little above the per-block figures of the table): "
          "colour_map 33,969 GE (sat_integral x2 16,882, box_divide 5,840, cmap_sat's own 5,027, cmap_divide's own "
          "3,419, sat_index x2 1,327); quadric_mac 28,813 (qmac_diag_fold, its three multipliers and their fold, "
          "26,690); noise_term 47,317 (eleven lerps 23,659, noise_grad's own 9,642, noise_blend x3 6,854); "
          "filter_width 11,750 (its own logic 11,110). compact with 4 samples a pixel, the goal's quality against the "
          "truth on formats that hold held out (docs/tradeoffs.md: 135,378 GE), takes 5 clocks a sample, and every "
          "block but the noise unit holds a new sample one clock in five. Folds that would spend those clocks on "
          "fewer gates (not built; an estimate, not a measurement): the colour map one channel a clock (its four "
          "channels' integrals and divisions on one lane: about three quarters of sat_integral's and box_divide's "
          "22,700, less the registers that hold a pixel's four channels, ~15,000); the quadric's six products on one "
          "multiplier over six clocks (about two thirds of qmac_diag_fold's, less the operand selection, ~16,000; a "
          "5-term pixel then takes 6 clocks a sample); the filter width's six products over two clocks (~3,000). "
          "About 34,000 together, close to the 35,378 the goal needs. The quadric's fold, measured since as a "
          "datapath of its own (stop 44, synth/experiments/: one multiplier over six clocks, the values of "
          "qmac_diag_fold, checked against it): 11,033 GE against qmac_diag_fold's 25,783 with compact's formats, "
          "-14,750. The colour map's fold, its largest parts measured likewise (stop 45, synth/experiments/README.md: "
          "sat_integral one channel a clock, checked against sat_integral on 3,000 vectors x 4 channels): 2,373 GE "
          "against sat_integral's 8,475 with compact's formats, twice; box_divide on one lane 1,761 against four "
          "lanes' 5,751: -16,194 measured, before cmap_sat's and cmap_divide's per-channel lanes (~2,000-3,000, not "
          "measured). The two measured folds: -30,944 GE; on today's compact (130,357 GE, each block read alone, below, "
          "plus the sample blocks' 2,801) they leave compact samples=4 at about 102,200 GE, the estimated rest and the "
          "filter width over two clocks (~3,000) at about 96,000-97,000: an estimate from measured parts.", "",
          "Each block read alone (stop 45): `make synth` hands Yosys a block's module closure (synth.run.block_files: "
          "its file and those of every module it instantiates), no longer all of rtl/. Yosys numbers the cells it "
          "creates across every file it reads, and ABC's mapping follows the numbering, so a block read with all of "
          "rtl/ moved by about 1% whenever an unrelated file changed (the notes above: blocks whose RTL did not "
          "change moved as much as the change measured); read alone, its gates change only with its own files, and "
          "explore's netlist cache (keyed by those files) holds what `make synth` computes. The same rtl/ "
          "(d92758265fd8), all files read -> the closure: full 1,378,899 -> 1,366,641 GE (-0.9%; quadric 105,444 -> "
          "99,795, noise terms 1,138,452 -> 1,132,508), reduced 110,484 -> 108,174 (-2.1%; quadric 37,208 -> 35,407), "
          "compact 132,200 -> 130,357 (-1.4%; noise terms 39,300 -> 38,078); control (the glue, read as before) "
          "unchanged.", ""]
    L += ["## Reproduce", "", "    make setup", "    make synth          # every configuration, synth/reports/",
          "    make synth-check    # each budget met or missed; fails above a ceiling",
          "    make synth-blocks   # GE of each block for every configuration",
          "    python -m synth.run --config compact --hier colour_map   # where a block's gates are, module by module", ""]
    # the stamp: the configurations' hashes the reports recorded (none before issue 26's reports)
    if all("config_hash" in r for r in reps.values()):
        L.append(STAMP + " " + " ".join(f"{c}={r['config_hash']}" for c, r in reps.items())
                 + f" rtl={next(iter(reps.values()))['rtl_hash']} -->")
    (ROOT / "docs" / "synthesis.md").write_text("\n".join(L) + "\n")


def check() -> int:
    """Each named configuration's logic GE against its budget (BUDGET): within it, OK; over it and under
    the configuration's CEILING (a budget its promise is measured to miss), MISSED, printed with the
    excess and the reason, not a failure; over the ceiling (or over a budget with none), a failure."""
    bad = 0
    for c in CONFIG_NAMES:
        p = REPORTS / f"{c}.json"
        if not p.exists():
            print(f"synth-check: {p} missing: run `make synth`", file=sys.stderr)
            return 2
        rep = json.loads(p.read_text())
        ge, budget = rep["ge_total"], BUDGET[c]
        ceiling, why = CEILING.get(c, (budget, ""))
        over = ge - budget
        if ge <= budget:
            verdict = "OK"
        elif ge <= ceiling:
            verdict = f"MISSED by {over:,.0f} GE ({100 * over / budget:.1f}%; {why}); within the ceiling {ceiling:,}: OK"
        else:
            verdict = f"OVER by {over:,.0f} GE" + (f", over the ceiling {ceiling:,}" if ceiling > budget else "")
        print(f"synth-check: {c}: {ge:,.0f} GE (logic; {rep['storage_bits']:,} storage bits apart) "
              f"vs budget {budget:,}{' (the paper' + chr(39) + 's)' if c in PAPER_MODELS else ''}: {verdict}")
        bad += ge > ceiling
    return 1 if bad else 0


def fc_variant(c: str):
    """Configuration c with the frequency-clamping filter (its terms unfolded)."""
    return config_fc_variant(load_config(c))


def blocks_table() -> int:
    """Each block's GE in every named configuration, and the cost of each filter: the
    colour_map with "sat" (the configuration's own), and what "sat_fc" adds (fc_weight once,
    fc_scale once a term, on the configuration's formats)."""
    print(f"{'block':<22}" + "".join(f"{c:>14}" for c in CONFIG_NAMES))
    res = {c: {} for c in CONFIG_NAMES}
    for c in CONFIG_NAMES:
        with ThreadPoolExecutor(max_workers=2) as ex:
            futs = {label: ex.submit(synth_one, c, mod) for label, mod in BLOCKS.items()}
            fcv = fc_variant(c)
            futs.update({f"{label} (sat_fc)": ex.submit(synth_one, fcv, mod) for label, mod in FC_BLOCKS.items()})
            for label, f in futs.items():
                res[c][label] = f.result()
    for label in res[CONFIG_NAMES[0]]:
        print(f"{label:<22}" + "".join(f"{res[c][label]['ge_total']:>14,.0f}" for c in CONFIG_NAMES))
    print(f"{'sat_fc adds (K terms)':<22}" + "".join(
        f"{res[c]['fc_weight (sat_fc)']['ge_total'] + load_config(c).noise_terms * res[c]['fc_scale (sat_fc)']['ge_total']:>14,.0f}"
        for c in CONFIG_NAMES))
    print(json.dumps({c: {k: {"ge": v["ge_total"], "ge_seq": v["ge_seq"], "storage_bits": v["storage_bits"],
                              "logic_depth": v["logic_depth"]} for k, v in res[c].items()} for c in CONFIG_NAMES},
                     indent=1))
    return 0


def hier_table(config: str, top: str) -> int:
    """Where a block's gates are: `top` synthesized with every module it instantiates kept as a
    module of its own (so the total can differ from the flattened block's by what optimisation
    across the boundaries saves); one line a module (its parameterisations together): instances,
    GE of all of them with their own sub-modules, and without (the shares of the last add up to 1).
    Read from the run's `stat` of the kept hierarchy (synth.py's stat_hier.txt)."""
    from synth.synth import parse_liberty, parse_stat

    cfg = config_of(config)
    keep = ROOT / "build" / "synth" / cfg.name / f"{top}.hier"
    rep = synth_one(cfg, top, out=keep.with_suffix(".json"), keep=keep,
                    keep_modules=[m for m in module_names(top) if m != top])
    hier = parse_stat((keep / "stat_hier.txt").read_text())
    area = {c: v["area"] for c, v in parse_liberty(ROOT / "synth" / "cells.lib").items()}
    top_key = next(k for k in hier if k.rsplit("\\", 1)[-1] == top)
    own = {k: sum(n * area[c] for c, n in m["cells"].items() if c in area) for k, m in hier.items()}

    def subs(k):
        return {c: n for c, n in hier[k]["cells"].items() if c in hier}

    def inclusive(k):
        return own[k] + sum(n * inclusive(c) for c, n in subs(k).items())

    count: dict[str, int] = {}

    def walk(k, mult):
        for c, n in subs(k).items():
            count[c] = count.get(c, 0) + mult * n
            walk(c, mult * n)

    walk(top_key, 1)
    rows: dict[str, list] = {}
    for k, n in count.items():
        r = rows.setdefault(k.rsplit("\\", 1)[-1], [0, 0.0, 0.0])
        r[0] += n
        r[1] += n * inclusive(k)
        r[2] += n * own[k]
    tot = inclusive(top_key)
    rows[f"{top} (own)"] = [1, tot, own[top_key]]
    print(f"{top} ({cfg.name}): {tot:,.1f} GE as kept modules ({rep['ge_total']:,.1f} once flattened, as make synth "
          f"counts a block)")
    print(f"{'module':<20}{'instances':>10}{'GE with subs':>14}{'GE own':>10}{'share':>8}")
    for name, (n, ge_all, ge_own) in sorted(rows.items(), key=lambda kv: -kv[1][2]):
        print(f"{name:<20}{n:>10}{ge_all:>14,.0f}{ge_own:>10,.0f}{ge_own / tot:>8.1%}")
    return 0


def samples_table() -> int:
    """What sub-pixel samples add to each named configuration (features.samples 2 and 4): the GE of
    sample_expand and sample_average on its formats (the glue's change, a wider latency delay line
    of one bit, is left out); the clocks a pixel multiply by the sample count."""
    from model.hw.config import variant

    rows = {}
    with ThreadPoolExecutor(max_workers=2) as ex:
        futs = {(c, n, mod): ex.submit(synth_one, variant(load_config(c), f"{c}_s{n}", samples=n), mod)
                for c in CONFIG_NAMES for n in (2, 4) for mod in SAMPLE_BLOCKS.values()}
        for key, f in futs.items():
            rows[key] = f.result()
    print(f"{'samples':<10}{'block':<18}" + "".join(f"{c:>12}" for c in CONFIG_NAMES))
    for n in (2, 4):
        for mod in SAMPLE_BLOCKS.values():
            print(f"{n:<10}{mod:<18}" + "".join(f"{rows[(c, n, mod)]['ge_total']:>12,.0f}" for c in CONFIG_NAMES))
        print(f"{n:<10}{'adds':<18}" + "".join(
            f"{sum(rows[(c, n, m)]['ge_total'] for m in SAMPLE_BLOCKS.values()):>12,.0f}" for c in CONFIG_NAMES))
    print(json.dumps({f"{c}_s{n}": {m: {"ge": rows[(c, n, m)]["ge_total"], "ge_seq": rows[(c, n, m)]["ge_seq"],
                                        "logic_depth": rows[(c, n, m)]["logic_depth"]} for m in SAMPLE_BLOCKS.values()}
                      for c in CONFIG_NAMES for n in (2, 4)}, indent=1))
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m synth.run")
    ap.add_argument("--config", help="a configuration of config/ (named, or a variant file such as full_fc), or a "
                                     "configuration file's path (its report goes to out/synth/<name>.json)")
    ap.add_argument("--all", action="store_true")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--blocks", action="store_true")
    ap.add_argument("--hier", metavar="MODULE", help="where MODULE's gates are (with --config): each module it "
                                                     "instantiates synthesized as its own, one line each")
    ap.add_argument("--samples", action="store_true", help="the GE sub-pixel samples (2, 4) add to each named configuration")
    ap.add_argument("--jobs", type=int, default=int(os.environ.get("JOBS", 2)))
    a = ap.parse_args(argv)
    path_cfg = a.config is not None and (a.config.endswith(".toml") or os.sep in a.config)
    if path_cfg:
        try:
            load_config(a.config)
        except ConfigError as e:
            print(f"synth: --config {a.config}: {e}", file=sys.stderr)
            return 2
    elif a.config is not None and not is_config_file(a.config):
        print(f"synth: --config {a.config}: no such configuration in config/", file=sys.stderr)
        return 2
    if a.check:
        return check()
    if a.blocks:
        return blocks_table()
    if a.samples:
        return samples_table()
    if a.hier:
        if a.hier not in rtl_modules():
            print(f"synth: --hier {a.hier}: no such module in rtl/", file=sys.stderr)
            return 2
        try:
            block_params(config_of(a.config or "full"), a.hier)
        except KeyError:
            print(f"synth: --hier {a.hier}: a module inside a block (no configuration gives it parameters); name "
                  f"the block that instantiates it", file=sys.stderr)
            return 2
        return hier_table(a.config or "full", a.hier)
    cfgs = CONFIG_NAMES if a.all or not a.config else (a.config,)
    for c in cfgs:
        rep = synth_config(c, a.jobs, ROOT / "out" / "synth" if path_cfg else None)
        print(json.dumps({k: rep[k] for k in ("config", "ge_total", "ge_comb", "ge_seq", "storage_bits",
                                               "logic_depth", "blocks", "within_budget", "seconds")}, indent=1))
    write_doc()
    return 0


if __name__ == "__main__":
    sys.exit(main())
