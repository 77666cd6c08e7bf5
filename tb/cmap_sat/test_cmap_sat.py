"""cmap_sat (rtl/cmap_sat.v, the box-filter family of colour_map, with cmap_divide) bit-exact
against golden cmap_sat: RGBA8 of the colour index u averaged over w from the summed-area
table, or, w = 0, the point lookup.

Parameter sets (F_FRAC, W_CAP_LOG2, N_LOG2_MAX, DIV_BITS, FPGA_REGS, CLOCKS): colour_map's under
full, reduced, compact, two random valid configurations and the extremes of the colour-map formats
(small, wide: exact division); reduced with div_bits 0 and 1; with FPGA_REGS = 1 reduced and
full; with CLOCKS = 4 (the fold: a channel a clock, a pixel at most every fourth enabled clock)
compact (normalised division), full (exact), reduced's div_bits 1 (the narrowest divisor) and
the small extreme.
Stimulus: the tables of tb/colour_map (random for every N, all 255: the largest D, all 0,
zebras, edge entries) loaded through the write port, then per table the colour_map
testbench's hard and random (f, w, mode) vectors, f taken to u as colour_map's stage 1 does
(golden cmap_u; w = 0 where the filter is off), streamed with ce stalls and input gaps.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

import cocotb

from model.hw import golden as G
from model.hw.config import latency, load_config, variant
from tb import pipe
from tb.colour_map import test_colour_map as cm

KEYS = {"F_FRAC": "f_frac", "W_CAP_LOG2": "w_cap_log2", "N_LOG2_MAX": "n_log2_max", "DIV_BITS": "div_bits"}


def _sets():
    cfgs = pipe.configs(1261, 1262, colour_edges=True) + [("compact", load_config("compact"))]
    out = {name: {k: getattr(c, v) for k, v in KEYS.items()} for name, c in cfgs}
    for b in (0, 1):
        out[f"reduced_div{b}"] = {**out["reduced"], "DIV_BITS": b}
    out["reduced_fpga"] = {**out["reduced"], "FPGA_REGS": 1}
    out["full_fpga"] = {**out["full"], "FPGA_REGS": 1}
    for name in ("compact", "full", "reduced_div1", "small"):
        out[f"{name}_c4"] = {**out[name], "CLOCKS": 4}
    return out


# every set under Icarus, three under Verilator (a build costs 5-20 s)
test_cmap_sat_rtl = pipe.block_test("cmap_sat", _sets(), ("full", "reduced_fpga", "compact_c4"), __file__,
                                   sources=["cmap_sat.v", "cmap_divide.v", "colour_table.v", "sat_index.v",
                                            "sat_integral.v", "sat_integral_serial.v", "box_divide.v",
                                            "delay_line.v"])


@cocotb.test()
async def cmap_sat_bit_exact(dut):
    p = pipe.block_params()
    cfg = variant(load_config("full"), "cmap_sat", filter="sat", fpga_regs=bool(p.get("FPGA_REGS", 0)),
                  **{v: p[k] for k, v in KEYS.items()})
    r = pipe.rng(97)
    clocks = p.get("CLOCKS", 1)  # the fold's latency rule reads cmap_clocks (cfg: full's, unfolded)
    lat = latency("cmap_sat", SimpleNamespace(fpga_regs=cfg.fpga_regs, cmap_clocks=clocks))
    dut.wr_en.value = 0
    await pipe.start(dut)
    assert int(dut.out_valid.value) == 0 and int(dut.rgba_out.value) == 0, "outputs after reset"
    umask, wmask = (1 << cfg.u_w) - 1, (1 << cfg.w_w) - 1
    sets = cm.table_sets(cfg, r)
    n_rand = -(-pipe.n_vectors() // len(sets))
    for name, n_log2, clut, full in sets:
        await cm.write_tables(dut, cfg, n_log2, clut, r)
        hv, rv = cm.hard_vectors(cfg, n_log2, full), cm.random_vectors(cfg, r, n_rand)
        f, w, mode, filt = (np.concatenate([a, b]) for a, b in zip(hv, rv))
        u = G.cmap_u(cfg, f, mode, n_log2)
        w = np.where(filt != 0, w, 0)
        tex = G.TexInt(Q=np.zeros(10, dtype=np.int64), a=np.zeros(0, dtype=np.int64),
                       T=np.zeros((0, 3, 3), dtype=np.int64), o=np.zeros((0, 3), dtype=np.int64),
                       mode=0, n_log2=n_log2, filter=True, clut=clut)
        exp = G.cmap_sat(cfg, G.host_tables(tex), u, w, mode, n_log2)
        ul, wl, ml = u.tolist(), w.tolist(), mode.tolist()

        def apply(i):
            dut.u_in.value = ul[i] & umask
            dut.w_in.value = wl[i] & wmask
            dut.mode.value = ml[i]
            dut.n_log2.value = n_log2

        def sample():
            return tuple(pipe.unpack(int(dut.rgba_out.value), 8, 4, signed=False))

        got = await pipe.run_vectors(dut, apply, sample, len(u), lat, seed=int(r.integers(1 << 30)), spacing=clocks)
        pipe.check_equal(dut, got, exp, lambda i: f"u={ul[i]} w={wl[i]} mode={ml[i]} n_log2={n_log2}",
                         f"table '{name}'")
