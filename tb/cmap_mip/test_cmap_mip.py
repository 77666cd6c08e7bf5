"""cmap_mip (rtl/cmap_mip.v, the MIP-map family of colour_map) bit-exact against golden
cmap_mip: RGBA8 of the colour index u in the MIP level of width w, or, filter off, clut[k].

Parameter sets (F_FRAC, W_CAP_LOG2, N_LOG2_MAX, FPGA_REGS): colour_map's under full, reduced,
two random valid configurations and the extremes of the colour-map formats (small, wide);
reduced with FPGA_REGS = 1 (the longer delay line).
Stimulus: tb/colour_map's tables for the mip and none builds (random N = 1, 8, 2^n_log2_max,
a zebra) with their MIP maps (golden build_tables) loaded through the write port, then per
table the colour_map testbench's hard and random (f, w, mode, filter_en) vectors, f taken to
u as colour_map's stage 1 does (golden cmap_u; w = 0 where the filter is off), streamed with
ce stalls and input gaps.
"""
from __future__ import annotations

import numpy as np

import cocotb

from model.hw import golden as G
from model.hw.config import latency, load_config, variant
from tb import pipe
from tb.colour_map import test_colour_map as cm

KEYS = {"F_FRAC": "f_frac", "W_CAP_LOG2": "w_cap_log2", "N_LOG2_MAX": "n_log2_max"}
MODULE = "cmap_mip"


def lookup_sets():
    """The parameter sets of the lookup families (cmap_mip, cmap_point)."""
    out = {name: {k: getattr(c, v) for k, v in KEYS.items()} for name, c in pipe.configs(1271, 1272, colour_edges=True)}
    out["reduced_fpga"] = {**out["reduced"], "FPGA_REGS": 1}
    return out


# every set under Icarus, two under Verilator (a build costs 5-20 s)
test_cmap_mip_rtl = pipe.block_test(MODULE, lookup_sets(), ("full", "reduced_fpga"), __file__,
                                   sources=[f"{MODULE}.v", "mip_index.v", "colour_table.v"])


async def lookup_bit_exact(dut, module: str, filt: str):
    """Load the tables, stream the vectors, compare with golden `module` (cmap_mip, cmap_point)."""
    p = pipe.block_params()
    cfg = variant(load_config("full"), module, filter=filt, fpga_regs=bool(p.get("FPGA_REGS", 0)),
                  **{v: p[k] for k, v in KEYS.items()})
    r = pipe.rng(101)
    lat = latency(module, cfg)
    dut.wr_en.value = 0
    await pipe.start(dut)
    assert int(dut.out_valid.value) == 0 and int(dut.rgba_out.value) == 0, "outputs after reset"
    umask, wmask = (1 << cfg.u_w) - 1, (1 << cfg.w_w) - 1
    sets = cm.table_sets(cfg, r, variant=True)
    n_rand = -(-pipe.n_vectors() // len(sets))
    for name, n_log2, clut, full in sets:
        await cm.write_tables(dut, cfg, n_log2, clut, r)
        hv, rv = cm.hard_vectors(cfg, n_log2, full), cm.random_vectors(cfg, r, n_rand)
        f, w, mode, filt_en = (np.concatenate([a, b]) for a, b in zip(hv, rv))
        u = G.cmap_u(cfg, f, mode, n_log2)
        w = np.where(filt_en != 0, w, 0)
        csat, mip = G.build_tables(clut)
        tables = {"clut": clut, "csat": csat, "mip": mip, "total": csat[-1]}
        if module == "cmap_mip":
            exp = G.cmap_mip(cfg, tables, u, w, mode, n_log2, filt_en)
        else:
            exp = G.cmap_point(cfg, tables, u, mode, n_log2)
        ul, wl, ml, el = u.tolist(), w.tolist(), mode.tolist(), filt_en.tolist()

        def apply(i):
            dut.u_in.value = ul[i] & umask
            if module == "cmap_mip":
                dut.w_in.value = wl[i] & wmask
                dut.filter_en.value = el[i]
            dut.mode.value = ml[i]
            dut.n_log2.value = n_log2

        def sample():
            return tuple(pipe.unpack(int(dut.rgba_out.value), 8, 4, signed=False))

        got = await pipe.run_vectors(dut, apply, sample, len(u), lat, seed=int(r.integers(1 << 30)))
        pipe.check_equal(dut, got, exp, lambda i: f"u={ul[i]} w={wl[i]} mode={ml[i]} filter_en={el[i]} "
                                                  f"n_log2={n_log2}", f"table '{name}'")


@cocotb.test()
async def cmap_mip_bit_exact(dut):
    await lookup_bit_exact(dut, MODULE, "mip")
