"""qmac_diag_pipe (rtl/qmac_diag_pipe.v, quadric_mac's diagonal datapath with the FPGA's
pipelined products, fpga_regs) bit-exact against golden qmac_diag_pipe (qmac_diag's values),
every bit, latency `LAT_QMAC_DIAG_PIPE.

Parameter sets (S_W, S_FRAC, Q_W): reduced and compact (the two configurations `make fpga`
builds), the edges "small" (8, 3, 6: no operand cut into parts by mul_pipe) and
"wide" (26, 16, 24: V_W = 34, every operand cut, near mul_pipe's 35-bit limit).
Stimulus: tb/quadric_mac's hard cases and random batches sharing a Q (B = C = F = 0), drained
between batches, with ce stalls and input gaps (tb/quadric_mac datapath_bit_exact).
"""
from __future__ import annotations

import cocotb

from tb import pipe
from tb.quadric_mac import test_quadric_mac as qm

SETS = qm.datapath_sets(("reduced", "compact"), (), {"small": (8, 3, 6), "wide": (26, 16, 24)})

# every set under Icarus, one under Verilator (a build costs 5-20 s)
test_qmac_diag_pipe_rtl = pipe.block_test("qmac_diag_pipe", SETS, ("wide",), __file__,
                                          sources=["qmac_diag_pipe.v", "mul_pipe.v"])


@cocotb.test()
async def qmac_diag_pipe_bit_exact(dut):
    await qm.datapath_bit_exact(dut, "qmac_diag_pipe")
