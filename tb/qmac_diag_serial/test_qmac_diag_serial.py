"""qmac_diag_serial (rtl/qmac_diag_serial.v, quadric_mac's diagonal datapath on one multiplier,
quadric_clocks = 6) bit-exact against golden qmac_diag_serial (qmac_diag's values), every bit,
latency `LAT_QMAC_DIAG_SERIAL, a vector at most every sixth enabled clock (its contract).

Parameter sets (S_W, S_FRAC, Q_W): compact (S_W > Q_W: the multiplier's first operand is s's
width) and a random valid configuration, and the edges "narrow_s" (6, 2, 12: Q_W > S_W) and
"wide_s" (20, 18, 4: S_W > V_W = 7, so the multiplier's second operand is s's width and x_k is
sign-extended to it in clocks 4-6). Stimulus: tb/quadric_mac's hard cases and random batches
sharing a Q (B = C = F = 0), drained between batches, with ce stalls and input gaps, spacing 6
(tb/quadric_mac datapath_bit_exact).
"""
from __future__ import annotations

import cocotb

from tb import pipe
from tb.quadric_mac import test_quadric_mac as qm

SETS = qm.datapath_sets(("compact",), (1401,), {"narrow_s": (6, 2, 12), "wide_s": (20, 18, 4)})

# every set under Icarus, one under Verilator (a build costs 5-20 s)
test_qmac_diag_serial_rtl = pipe.block_test("qmac_diag_serial", SETS, ("compact",), __file__,
                                            sources=["qmac_diag_serial.v"])


@cocotb.test()
async def qmac_diag_serial_bit_exact(dut):
    await qm.datapath_bit_exact(dut, "qmac_diag_serial", spacing=6)
