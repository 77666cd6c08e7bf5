"""cmap_sat2 (rtl/cmap_sat2.v, the trapezoid family of colour_map, with sat2_table,
sat2_integral, sat_index and cmap_divide) bit-exact against golden cmap_sat2: RGBA8 of the colour
index u averaged over the trapezoid of the screen components (a, b), the box when one is 0, the
point lookup when both are.

Parameter sets (F_FRAC, W_CAP_LOG2, N_LOG2_MAX, DIV_BITS, FPGA_REGS): full's (the candidate
config/candidates/full_sat2.toml) with its normalised 8-bit division, the smallest colour-map
formats with the exact division (small: N_LOG2_MAX 1, W_CAP_LOG2 1, F_FRAC 8), a middle set with the
narrowest divisor (DIV_BITS 1), and full's with FPGA_REGS = 1; full under Verilator too.
Stimulus: tables of tb/colour_map (random N = 1, 8, max, a zebra, all 255: the largest D, edge
entries) loaded through the write port (csat in ascending order: the unit derives csat2; junk
writes that must be ignored after), then per table 6 (10 on three tables) of the hard f of
tb/colour_map x all pairs (a, b) of its hard widths (0, one LSB, around N, the cap) in both modes, and random (f, a, b, mode), f taken
to u as colour_map's stage 1 does (golden cmap_u, sat2's guard), streamed with ce stalls and gaps.
"""
from __future__ import annotations

import numpy as np

import cocotb

from model.hw import golden as G
from model.hw.config import ROOT, latency, load_config, variant
from tb import pipe
from tb.colour_map import test_colour_map as cm

KEYS = {"F_FRAC": "f_frac", "W_CAP_LOG2": "w_cap_log2", "N_LOG2_MAX": "n_log2_max", "DIV_BITS": "div_bits"}


def _sets():
    full = load_config(ROOT / "config" / "candidates" / "full_sat2.toml")
    out = {"full": {k: getattr(full, v) for k, v in KEYS.items()}}
    out["small"] = {"F_FRAC": 8, "W_CAP_LOG2": 1, "N_LOG2_MAX": 1, "DIV_BITS": 0}
    out["mid_div1"] = {"F_FRAC": 10, "W_CAP_LOG2": 6, "N_LOG2_MAX": 4, "DIV_BITS": 1}
    out["full_fpga"] = {**out["full"], "FPGA_REGS": 1}
    return out


# every set under Icarus, full under Verilator too (a build costs 5-20 s)
SOURCES = ["cmap_sat2.v", "cmap_divide.v", "sat2_table.v", "sat_index.v", "sat2_integral.v", "box_divide.v",
           "delay_line.v"]
test_cmap_sat2_rtl = pipe.block_test("cmap_sat2", _sets(), ("full",), __file__, sources=SOURCES)


def test_sat2_integral_check():
    """sat2_integral's elaboration-time check (g_bad_params; only cmap_sat2 builds the block) both
    ways: accepted on its defaults (full's words: XF 14, KW 14, CS_W 16, CS2_W 24, D_W 59) and on
    each bound's edge (KW + XF = MW = D_W with CS_W 13; D_W = 64; 2 XF + 8 = D_W - 1; CS_W = 9;
    CS_W + 1 + XF = D_W - 1), refused one past each."""
    import hdlbuild

    src = ["sat2_integral.v"]
    edge = {"KW": 24, "CS_W": 13, "D_W": 38}  # KW + XF = 38 = D_W, MW = KW + CS_W + 1 = 38 = D_W
    hdlbuild.check_refusals(
        "sat2_integral", src, {},
        accept={"defaults": {}, "KW + XF = MW = D_W": edge, "D_W 64": {"D_W": 64},
                "2 XF + 8 = D_W - 1": {"D_W": 37}, "CS_W 9": {"CS_W": 9},
                "CS_W + 1 + XF = D_W - 1": {"KW": 10, "CS_W": 26, "D_W": 42}},
        refuse={"D_W 65": {"D_W": 65}, "KW + XF = D_W + 1": {**edge, "KW": 25, "CS_W": 12},
                "MW = D_W + 1": {**edge, "CS_W": 14}, "2 XF + 8 = D_W": {"D_W": 36}, "CS_W 8": {"CS_W": 8},
                "CS_W + 1 + XF = D_W": {"KW": 10, "CS_W": 27, "D_W": 42}},
        error_module="sat2_integral_unsupported_widths")


def test_cmap_sat2_check():
    """cmap_sat2's elaboration-time check (g_bad_params) both ways on full's set (F_FRAC 13,
    W_CAP_LOG2 11: D_W = 2 (W_CAP_LOG2 + F_FRAC) + 11 = 59): refused one past the bound (D_W 63,
    W_CAP_LOG2 + F_FRAC = 26), accepted at its edge (D_W 61, the largest D_W parameters give: D_W is
    always odd, so D_W > 62 and D_W >= 62 refuse the same sets). (g_bad_latency depends on
    rtl/tex_latency.vh alone: no parameter set makes it true.)"""
    import hdlbuild

    b = _sets()["full"]
    hdlbuild.check_refusals(
        "cmap_sat2", SOURCES, b,
        accept={"full": {}, "D_W 61": {"W_CAP_LOG2": 25 - b["F_FRAC"]}},
        refuse={"D_W 63 > 62": {"W_CAP_LOG2": 26 - b["F_FRAC"]}},
        error_module="cmap_sat2_unsupported_widths")


def _config(p):
    return variant(load_config("full"), "cmap_sat2", filter="sat2", fpga_regs=bool(p.get("FPGA_REGS", 0)),
                   **{v: p[k] for k, v in KEYS.items()})


def _tables(cfg, r):
    big = 1 << cfg.n_log2_max
    sets = cm.table_sets(cfg, r, variant=True)
    sets.append((f"all 255 N={big}", cfg.n_log2_max, np.full((big, 4), 255, dtype=np.int64), True))
    edges = r.integers(0, 256, size=(big, 4))
    edges[0], edges[-1] = 255, 0
    sets.append((f"edges N={big}", cfg.n_log2_max, edges, False))
    return sets


def _vectors(cfg, r, n_log2, full, n_rand):
    """(f, a, b, mode): hard f x hard (a, b) pairs in both modes, then n_rand random."""
    fs = cm.hard_f(cfg, n_log2)
    fs = fs[r.permutation(len(fs))[:10 if full else 6]]
    ws = cm.hard_w(cfg, n_log2, False)
    A, B = np.meshgrid(ws, ws, indexing="ij")
    F, AB = np.meshgrid(fs, np.arange(A.size), indexing="ij")
    F, a, b = F.ravel(), A.ravel()[AB.ravel()], B.ravel()[AB.ravel()]
    hf, ha, hb = np.concatenate([F, F]), np.concatenate([a, a]), np.concatenate([b, b])
    hm = np.repeat([G.MODE_MOD, G.MODE_CLAMP], len(F))
    rf, ra, rm, _ = cm.random_vectors(cfg, r, n_rand)
    _, rb, _, _ = cm.random_vectors(cfg, r, n_rand)
    return (np.concatenate([hf, rf]), np.concatenate([ha, ra]), np.concatenate([hb, rb]),
            np.concatenate([hm, rm]))


@cocotb.test()
async def cmap_sat2_bit_exact(dut):
    cfg = _config(pipe.block_params())
    r = pipe.rng(131)
    lat = latency("cmap_sat2", cfg)
    dut.wr_en.value = 0
    await pipe.start(dut)
    assert int(dut.out_valid.value) == 0 and int(dut.rgba_out.value) == 0, "outputs after reset"
    umask, wmask, ww = (1 << cfg.u_w) - 1, (1 << cfg.w_w) - 1, cfg.w_w
    sets = _tables(cfg, r)
    n_rand = -(-pipe.n_vectors() // len(sets))
    for name, n_log2, clut, full in sets:
        await cm.write_tables(dut, cfg, n_log2, clut, r)
        f, a, b, mode = _vectors(cfg, r, n_log2, full, n_rand)
        u = G.cmap_u(cfg, f, mode, n_log2)
        tex = G.TexInt(Q=np.zeros(10, dtype=np.int64), a=np.zeros(0, dtype=np.int64),
                       T=np.zeros((0, 3, 3), dtype=np.int64), o=np.zeros((0, 3), dtype=np.int64),
                       mode=0, n_log2=n_log2, filter=True, clut=clut)
        exp = G.cmap_sat2(cfg, G.host_tables(tex), u, a, b, mode, n_log2)
        ul, al, bl, ml = u.tolist(), a.tolist(), b.tolist(), mode.tolist()

        def apply(i):
            dut.u_in.value = ul[i] & umask
            dut.w_in.value = ((bl[i] & wmask) << ww) | (al[i] & wmask)
            dut.mode.value = ml[i]
            dut.n_log2.value = n_log2

        def sample():
            return tuple(pipe.unpack(int(dut.rgba_out.value), 8, 4, signed=False))

        got = await pipe.run_vectors(dut, apply, sample, len(u), lat, seed=int(r.integers(1 << 30)))
        pipe.check_equal(dut, got, exp, lambda i: f"u={ul[i]} a={al[i]} b={bl[i]} mode={ml[i]} n_log2={n_log2}",
                         f"table '{name}'")
