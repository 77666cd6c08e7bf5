"""qmac_diag (rtl/qmac_diag.v, quadric_mac's datapath for the diagonal quadric, a vector every
clock) bit-exact against golden qmac_diag: r_k = s_k (v_k + Q_k3), v_k = (Q_kk s_k >> s_frac)
+ Q_k3 and v_3 = J, every bit, latency `LAT_QMAC_DIAG.

Parameter sets (S_W, S_FRAC, Q_W): reduced and a random valid configuration with a diagonal
quadric, the edges "small" (8, 3, 6) and "frac0" (10, 0, 8: no fraction).
Stimulus: tb/quadric_mac's hard cases and random batches sharing a Q (B = C = F = 0), drained
between batches, with ce stalls and input gaps (tb/quadric_mac datapath_bit_exact).
"""
from __future__ import annotations

import cocotb

from tb import pipe
from tb.quadric_mac import test_quadric_mac as qm

SETS = qm.datapath_sets(("reduced",), (1403,), {"small": (8, 3, 6), "frac0": (10, 0, 8)})

# every set under Icarus, one under Verilator (a build costs 5-20 s)
test_qmac_diag_rtl = pipe.block_test("qmac_diag", SETS, ("reduced",), __file__, sources=["qmac_diag.v"])


@cocotb.test()
async def qmac_diag_bit_exact(dut):
    await qm.datapath_bit_exact(dut, "qmac_diag")
