"""cmap_point (rtl/cmap_point.v, the point-lookup family of colour_map, filter "none")
bit-exact against golden cmap_point: clut[k], k = floor(u) mod N or clamped.

Parameter sets and stimulus: those of tb/cmap_mip (lookup_sets, lookup_bit_exact), with the
clut table alone built (the mip writes must be ignored) and w, filter_en not read.
"""
from __future__ import annotations

import cocotb

from tb import pipe
from tb.cmap_mip.test_cmap_mip import lookup_bit_exact, lookup_sets

MODULE = "cmap_point"

# every set under Icarus, two under Verilator (a build costs 5-20 s)
test_cmap_point_rtl = pipe.block_test(MODULE, lookup_sets(), ("full", "reduced_fpga"), __file__,
                                     sources=[f"{MODULE}.v", "mip_index.v", "colour_table.v"])


@cocotb.test()
async def cmap_point_bit_exact(dut):
    await lookup_bit_exact(dut, MODULE, "none")
