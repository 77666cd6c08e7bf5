"""Flip-flops into the ECP5 multipliers' output registers: a pass over Yosys's JSON netlist.

Yosys's `synth_ecp5` maps each product to MULT18X18D cells with none of their REG_* clocks set
(it has no register packing for the ECP5 DSP, as `xilinx_dsp` and `ice40_dsp` have for theirs), so
a register -> multiplier -> register stage of the RTL becomes fabric flip-flops, a route to the
DSP block, its combinational multiplier, and a route back: about 10 ns on the 85F, the clock limit
of `reduced` and `compact` with fpga_regs before this pass (docs/fpga.md). Vendor synthesis packs
such flip-flops into the DSP block; this pass does it for the output register, which nextpnr-ecp5
then times as its class MULT18X18D_REGS_OUTPUT (the multiply inside the block, before its register):

  When every used output bit P<i> of a MULT18X18D drives exactly one TRELLIS_FF's DI and nothing
  else, and those flip-flops share one clock and one clock enable (or none), have no set/reset
  (LSR tied to 0) and start at 0 (REGSET RESET), as the DSP's register does: P<i> then drives the
  flip-flop's Q net, the flip-flops go, and the cell's output register takes their place
  (REG_OUTPUT_CLK = CLK0, REG_OUTPUT_CE = CE0, REG_OUTPUT_RST = RST0 tied to 0; CLK0 and CE0 the
  flip-flops' clock and enable).

The function is unchanged cycle for cycle: each moved register is the same register (the same
clock, enable and initial value) inside the DSP block. tests/test_fpga.py checks that by
simulating a multiplier block's netlist before and after the pass under Icarus, cycle by cycle on
random inputs, with tests/ecp5_sim/MULT18X18D.v, a behavioural model of the cell's registers.

The input registers (REG_INPUTA/B_CLK) are not packed: measured on compact-fpga (seed 1), packing
both made the clock worse (106.2 -> 96.2 MHz), as the registers after the colour table's block RAM
read moved into the DSP block and the RAM's clock-to-out (5.8 ns) then met the route to it.

    python -m synth.dsp_regs IN.json OUT.json [--top NAME]
"""
from __future__ import annotations

import json
import sys
from collections import defaultdict
from pathlib import Path

from model.cli import Parser  # one-line errors, exit 2

MULT = "MULT18X18D"
FF = "TRELLIS_FF"


def _is_plain_ff(cell: dict) -> bool:
    """A TRELLIS_FF a DSP register can replace: rising clock, no set/reset, starting at 0."""
    p, c = cell["parameters"], cell["connections"]
    return (cell["type"] == FF and p.get("CLKMUX", "CLK") == "CLK" and p.get("REGSET", "RESET") == "RESET"
            and p.get("CEMUX", "1").strip() in ("CE", "1") and p.get("LSRMUX", "LSR") == "LSR"
            and c.get("LSR", ["0"]) == ["0"] and c.get("M", ["x"])[0] in ("x", "0")
            and p.get("LSRMODE", "LSR").strip() == "LSR")


def _ce(cell: dict):
    """The flip-flop's clock enable: its CE bit, or '1' when CEMUX ties it high."""
    return cell["connections"]["CE"][0] if cell["parameters"].get("CEMUX", "1").strip() == "CE" else "1"


def _unset(cell: dict, param: str) -> bool:
    return str(cell["parameters"].get(param, "NONE")).strip() == "NONE"


def absorb(netlist: dict, top: str) -> dict:
    """Rewrites `netlist` (Yosys JSON, module `top`) in place; the counts of what moved."""
    mod = netlist["modules"][top]
    cells = mod["cells"]
    sinks: dict = defaultdict(list)  # net bit -> [(cell, input port)], ("$port", name) for a top output
    for name, cell in cells.items():
        for port, bits in cell["connections"].items():
            if cell["port_directions"].get(port) != "output":
                for b in bits:
                    if isinstance(b, int):
                        sinks[b].append((name, port))
    for pname, port in mod["ports"].items():
        if port["direction"] != "input":
            for b in port["bits"]:
                if isinstance(b, int):
                    sinks[b].append(("$port", pname))

    counts = {"multipliers": 0, "output_registers": 0, "ffs_removed": 0}
    mults = sorted(n for n, c in cells.items() if c["type"] == MULT)

    for name in mults:
        m = cells[name]
        counts["multipliers"] += 1
        conn = m["connections"]
        if not (_unset(m, "REG_OUTPUT_CLK") and _unset(m, "REG_INPUTA_CLK") and _unset(m, "REG_INPUTB_CLK")
                and _unset(m, "REG_PIPELINE_CLK") and conn.get("CLK0", ["0"])[0] in ("0", "x")):
            continue  # registered already: left alone
        outs = [(p, bits[0]) for p, bits in conn.items()
                if p[0] == "P" and p[1:].isdigit() and isinstance(bits[0], int) and sinks.get(bits[0])]
        ffs = []
        for p, b in outs:
            s = sinks[b]
            if len(s) != 1 or s[0][0] == "$port" or s[0][1] != "DI" or not _is_plain_ff(cells[s[0][0]]):
                ffs = []
                break
            ffs.append((p, s[0][0]))
        clks = {cells[f]["connections"]["CLK"][0] for _, f in ffs}
        ces = {_ce(cells[f]) for _, f in ffs}
        if not ffs or len(clks) != 1 or len(ces) != 1:
            continue
        for p, f in ffs:
            conn[p] = cells.pop(f)["connections"]["Q"]
        conn.update(CLK0=[clks.pop()], CE0=[ces.pop()], RST0=["0"])
        m["port_directions"].update(CLK0="input", CE0="input", RST0="input")
        m["parameters"].update(REG_OUTPUT_CLK="CLK0", REG_OUTPUT_CE="CE0", REG_OUTPUT_RST="RST0")
        counts["output_registers"] += 1
        counts["ffs_removed"] += len(ffs)
    return counts


def main(argv=None) -> int:
    ap = Parser(prog="dsp_regs", description=__doc__.split("\n")[0])
    ap.add_argument("netlist", type=Path, help="Yosys JSON netlist (synth_ecp5 -json)")
    ap.add_argument("out", type=Path, help="the rewritten netlist")
    ap.add_argument("--top", help="the top module (default: the netlist's only one with attribute top)")
    a = ap.parse_args(argv)
    try:
        net = json.loads(a.netlist.read_text())
    except (OSError, ValueError) as e:
        ap.error(f"{a.netlist}: {e}")
    top = a.top or next((n for n, m in net.get("modules", {}).items() if m.get("attributes", {}).get("top")), None)
    if top not in net.get("modules", {}):
        ap.error(f"{a.netlist}: no top module {top!r}")
    counts = absorb(net, top)
    tmp = a.out.with_suffix(a.out.suffix + ".tmp")
    tmp.write_text(json.dumps(net))
    tmp.replace(a.out)
    print("dsp_regs: " + ", ".join(f"{k.replace('_', ' ')} {v}" for k, v in counts.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
