"""qmac_full (rtl/qmac_full.v, quadric_mac's datapath for the full quadric) bit-exact against
golden qmac_full: r_k = s_k v_k and v = Q x, every bit, latency `LAT_QMAC_FULL
(FPGA_REGS: `LAT_QMAC_FULL_FPGA).

Parameter sets (S_W, S_FRAC, Q_W, FPGA_REGS): full and a random valid configuration with a
full quadric, the edges "small" (8, 3, 6), "frac0" (10, 0, 8: no fraction) and "wide"
(22, 12, 20: words near the int64 twin's limit); full and wide also with FPGA_REGS = 1.
Stimulus: tb/quadric_mac's hard cases (s and Q at their extremes, aligned signs, fractions 0
and just below 1) and random batches sharing a Q, drained between batches (q_coef is a
per-pass parameter), with ce stalls and input gaps (tb/quadric_mac datapath_bit_exact).
"""
from __future__ import annotations

import cocotb

from tb import pipe
from tb.quadric_mac import test_quadric_mac as qm

SETS = qm.datapath_sets(("full",), (1402,), {"small": (8, 3, 6), "frac0": (10, 0, 8), "wide": (22, 12, 20)},
                        fpga=("full", "wide"))

# every set under Icarus, two under Verilator (a build costs 5-20 s)
test_qmac_full_rtl = pipe.block_test("qmac_full", SETS, ("full", "wide_fpga"), __file__,
                                     sources=["qmac_full.v", "delay_line.v"])


@cocotb.test()
async def qmac_full_bit_exact(dut):
    await qm.datapath_bit_exact(dut, "qmac_full")
