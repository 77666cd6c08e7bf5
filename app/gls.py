"""Gate-level simulation: `make gls CONFIG=reduced [GLS_SIZE=32] [GLS_SCENES=a,b]`.

Every piece of the texture unit that `make synth` counts is synthesized by the same Yosys script
and written as a Verilog netlist (synth/netlist.py: liberty-mapped gates, with Verilog models of
synth/cells.lib's cells that Yosys writes from the liberty functions, and the RAM macros as
arrays); the netlists replace rtl/ in the frame harness (sim/frame_rtl.py, `netlists=`), which
runs every scene through them under Verilator, every pixel compared with the golden model
(sim/frame.py run_frame). Exit status 1 when a pixel differs.

    python -m app.gls --config reduced [--size 32] [--scenes zone_plate,marble] [--jobs 2] [--out DIR]

Writes out/gls/<config>-<size>/ (each scene's frame report and images, summary.json); a run of
every scene at 32x32 of a configuration of GLS_CONFIGS also writes synth/reports/gls_<name>.json and
the "Gate-level simulation" section of docs/verification.md (each configuration of GLS_CONFIGS with
such a report: scenes, pixels, mismatches, the run's times, the rtl/ modules it elaborates that no
row above it does, and how many of rtl/'s modules the rows simulate at gate level in all).
"""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path

from app.common import git_describe, write_doc_section
from hdlbuild import need_tool
from model.cli import Parser, UserError, check_config, check_range, config_label, run_main
from model.hw.config import CONFIG_NAMES, ROOT, doc_stamp, load_config, read_stamp
from model.scene.passes import SCENES

REPORTS = ROOT / "synth" / "reports"
# the configurations the doc reports, in its order: the named three, then one for each family of blocks they
# leave out, so that every module of rtl/ is simulated at gate level in one of them (tests/test_gls.py holds it):
# frequency clamping (fc_weight, fc_scale), the trapezoid (cmap_sat2, sat2_integral, sat2_table), both folds
# and sub-pixel samples (qmac_diag_serial, sat_integral_serial, sample_expand, sample_average), the MIP map
# (cmap_mip, mip_index), the point lookup (cmap_point) and the FPGA's registers (mul_pipe, qmac_diag_pipe)
GLS_CONFIGS = (*CONFIG_NAMES, "reduced_fc", *(f"config/candidates/{c}.toml" for c in (
    "compact_sat2", "compact_q6c4_s4", "compact_mip", "compact_point", "compact_fpga")))
DOC_SIZE = 32  # the size the doc's figures are measured at (the issue's: every scene at 32x32)
TITLE = "Gate-level simulation"


def run_gls(config: str, size: int = DOC_SIZE, scenes=SCENES, jobs: int = 2, out_root: Path | None = None,
            progress: bool = True) -> dict:
    """Synthesize `config`'s netlists, build the harness on them and run `scenes` at `size`
    through it; the summary (also out_root/summary.json)."""
    from sim.frame import run_frame
    from sim.frame_rtl import build
    from synth.netlist import netlists

    cfg = load_config(config)
    out_root = out_root or ROOT / "out" / "gls" / f"{config_label(config)}-{size}"
    t0 = time.perf_counter()
    files = netlists(config, jobs)
    t1 = time.perf_counter()
    build(cfg, "verilator", files)
    t2 = time.perf_counter()
    rows = []
    for scene in scenes:
        rep = run_frame(scene, config, "verilator", size, out_root=out_root, progress=progress, netlists=files,
                        command=f"make gls CONFIG={config} GLS_SIZE={size} GLS_SCENES={scene}")
        rows.append({k: rep[k] for k in ("scene", "width", "height", "pixels_streamed", "mismatched_pixels",
                                          "bit_exact", "cycles", "sim_seconds")})
        if progress:
            print(f"gls {config} {scene} {rep['width']}x{rep['height']}: {rep['pixels_streamed']} pixels, "
                  f"{rep['mismatched_pixels']} differ", flush=True)
    t3 = time.perf_counter()
    summary = {
        "config": cfg.name, "size": size, "scenes": rows,
        "pixels": sum(r["pixels_streamed"] for r in rows),
        "mismatched_pixels": sum(r["mismatched_pixels"] for r in rows),
        "bit_exact": all(r["bit_exact"] for r in rows),
        "netlists": [str(Path(f).relative_to(ROOT)) for f in files],
        "synth_seconds": round(t1 - t0, 1), "build_seconds": round(t2 - t1, 1), "sim_seconds": round(t3 - t2, 1),
        "seconds": round(t3 - t0, 1), "git": git_describe(),
        "stamp": doc_stamp([cfg]),
    }
    out_root.mkdir(parents=True, exist_ok=True)
    (out_root / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary


def write_doc() -> None:
    """The "Gate-level simulation" section of docs/verification.md from synth/reports/gls_*.json."""
    from hdlbuild import elaborated_modules, rtl_modules

    reps = [(c, json.loads((REPORTS / f"gls_{config_label(c)}.json").read_text())) for c in GLS_CONFIGS
            if (REPORTS / f"gls_{config_label(c)}.json").exists()]
    if not reps:
        return
    L = ["Written by `make gls CONFIG=<name>` (app/gls.py). Every piece `make synth` counts is synthesized by the "
         "same Yosys script and written with `write_verilog -noattr` after its last step (synth/netlist.py): "
         "gates of synth/cells.lib, whose Verilog models Yosys writes from the liberty functions (`read_liberty` "
         "without `-lib`, then `write_verilog`: plain assigns and always blocks, no Yosys simulation library), and "
         "the RAM macros (`$mem_v2`) as Verilog arrays. The control's netlist (texture_pipeline with its glue "
         "flattened) instantiates the blocks' netlists; each instance's parameters are checked against the set "
         "its block's netlist was synthesized with, then dropped. The netlists replace rtl/ in the frame harness "
         "(sim/frame_rtl.py `netlists=`, Verilator; the C++ of a gate-level netlist is compiled at -O0, where -O2 "
         "takes many times longer), and every scene runs through them, every pixel against the golden model. "
         "Beside the named configurations, one configuration a family of blocks they leave out (app/gls.py "
         "GLS_CONFIGS; config/candidates/compact_mip, compact_point and compact_fpga are there for it), so that "
         "every module of rtl/ is simulated at gate level in one of them; \"modules first here\" are the rtl/ "
         "modules a configuration elaborates (Verilator's `--json-only` tree, hdlbuild.elaborated_modules) that no "
         "row above it does.",
         "", "| configuration | rtl/ | scenes | size | pixels | pixels differing | synthesis s | build s | simulation s | "
         "total s | modules first here |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    rtls = [(read_stamp(r.get("stamp", "")) or {}).get("rtl", "?") for _, r in reps]
    seen: set[str] = set()
    for i, ((c, r), h) in enumerate(zip(reps, rtls)):
        mods = set(elaborated_modules(c))
        first = f"{len(mods)}: all it elaborates" if i == 0 else (", ".join(sorted(mods - seen)) or "-")
        seen |= mods
        L.append(f"| {r['config']} | {h} | {len(r['scenes'])} | {r['size']}x{r['size']} | {r['pixels']:,} | "
                 f"{r['mismatched_pixels']} | {r['synth_seconds']} | {r['build_seconds']} | {r['sim_seconds']} | "
                 f"{r['seconds']} | {first} |")
    every = sorted(rtl_modules())
    left = [m for m in every if m not in seen]
    L += ["", f"**Modules of rtl/ simulated at gate level: {len(every) - len(left)} of {len(every)}**"
          + (f" (not yet: {', '.join(left)})." if left else "."),
          "", "Times are wall seconds on this machine's 2 cores (synthesis: every piece, JOBS at a time; a netlist "
          "cached in build/gls/ under a stamp of the RTL, the flow and the parameters, or a current build, costs "
          "nothing, so the synthesis column is small when an earlier run of the same RTL synthesized the pieces). "
          "`make test` runs compact on every scene at 4x4 (tests/test_gls.py).", "",
          doc_stamp([load_config(c) for c, _ in reps], ran_on=rtls)]  # a row of an older run keeps the section stale
    write_doc_section(TITLE, "\n".join(L))


def main(argv=None) -> int:
    ap = Parser(prog="gls", description=__doc__.split("\n\n")[0])
    ap.add_argument("--config", default="reduced", help="a configuration name or .toml path")
    ap.add_argument("--size", type=int, default=DOC_SIZE, help=f"frame side in pixels (default {DOC_SIZE})")
    ap.add_argument("--scenes", default="", help="comma-separated scene names (default: all eight)")
    ap.add_argument("--jobs", type=int, default=2, help="blocks synthesized at a time")
    ap.add_argument("--out", default="", help="output root (default out/gls/<config>-<size>)")
    a = ap.parse_args(argv)

    def go() -> int:
        check_config(a.config)
        check_range("--size", a.size, 1, 1024)
        check_range("--jobs", a.jobs, 1, 64)
        scenes = [s for s in a.scenes.split(",") if s] or list(SCENES)
        bad = [s for s in scenes if s not in SCENES]
        if bad:
            raise UserError(f"--scenes {bad[0]}: expected some of {', '.join(SCENES)}")
        need_tool("verilator")
        summ = run_gls(a.config, a.size, scenes, a.jobs, Path(a.out) if a.out else None)
        if a.size == DOC_SIZE and set(scenes) == set(SCENES) and not a.out and a.config in GLS_CONFIGS:
            REPORTS.mkdir(parents=True, exist_ok=True)
            (REPORTS / f"gls_{config_label(a.config)}.json").write_text(json.dumps(summ, indent=2) + "\n")
            write_doc()
        print(f"gls {summ['config']}: {len(scenes)} scenes at {a.size}x{a.size}, {summ['pixels']} pixels, "
              f"{summ['mismatched_pixels']} differ from the golden model ({summ['seconds']} s: synthesis "
              f"{summ['synth_seconds']}, build {summ['build_seconds']}, simulation {summ['sim_seconds']})")
        return 0 if summ["bit_exact"] else 1

    return run_main("gls", go)


if __name__ == "__main__":
    sys.exit(main())
