"""`make bench-sim`: RTL simulation throughput, pixels per second, per simulator.

A synthetic marble-like pass of the full configuration (sim/frame_rtl.py
synthetic_pass) streamed through texture_pipeline by the HDL-side harness;
simulation only (the build is timed apart). Both simulators stream a whole
512x512 frame (PIXELS_VERILATOR, PIXELS_ICARUS override the pixel counts; Icarus
takes about two minutes). Each run is checked bit-exact. docs/simulation.md
explains the figures and why Icarus cannot reach its goal on this arithmetic.
"""
from __future__ import annotations

import json
import os
import sys

from sim import frame_rtl

GOALS = {"verilator": 200_000, "icarus": 20_000}


def main() -> int:
    config = os.environ.get("CONFIG", "full")
    pixels = {"verilator": int(os.environ.get("PIXELS_VERILATOR", 512 * 512)),
              "icarus": int(os.environ.get("PIXELS_ICARUS", 512 * 512))}
    results = []
    for sim in ("verilator", "icarus"):
        buf = []
        import io
        from contextlib import redirect_stdout

        with redirect_stdout(io.StringIO()) as out:
            rc = frame_rtl.main(["--config", config, "--sim", sim, "--pixels", str(pixels[sim]), "--check"])
        rep = json.loads(out.getvalue().strip().splitlines()[-1])
        rep["goal_pixels_per_second"] = GOALS[sim]
        rep["goal_met"] = rep["pixels_per_second_stream"] >= GOALS[sim]
        rep["bit_exact"] = rc == 0 and rep.get("mismatches") == 0
        results.append(rep)
        buf.append(rep)
        print(json.dumps(rep), flush=True)
    return 0 if all(r["bit_exact"] for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
