"""colour_map (rtl/colour_map.v) against model/hw/golden.py colour_map, bit for bit.

Two halves in one file (the project's testbench convention; each build by tb/pipe.py's
run_block with the configuration's parameters):
- pytest entries: `test_colour_map_rtl` over (simulator, configuration),
  `test_colour_map_filter_variants_rtl`, the same cocotb test on each configuration with
  its filter switched to "mip" and to "none" (model.hw.config.variant), so that every
  FILTER branch is simulated, and
  `test_colour_map_div_variants_rtl`, the same with formats.div_bits switched: the saturating normalised division (B = 4, 9 on reduced), B = W_W - 1
  (shift 0 or 1) and a normalised division on full's wide w (B = 10);
- the cocotb test `colour_map_vs_golden`: for a series of colour tables (random, one for
  every N = 2^n_log2, n_log2 = 0..n_log2_max; all 255 and all 0, the quotient extremes;
  a harsh 0/255 zebra; N = 1) it loads clut, csat and mip (golden build_tables) through the
  write port (with random ce: writes must not depend on it, plus junk writes that must be
  ignored: wr_table 3, tables the configuration does not build, addresses past a table's
  end), then streams random vectors (f over the whole s{F_W} range and a realistic range,
  w over [0, w_cap] uniformly and log-uniformly, both modes, filter on and off) and the
  hard cases (every f in a list of edge values x every w in a list, both modes, filter on;
  filter off on a subset; with div_bits = B > 0 also the normalisation's edges: w around
  every power of two from 2^(B-1) to the cap, at the rounding ties and where rounding w
  carries into the next power of two, x a few f) with random ce stalls and input gaps, and
  compares every output bit with golden colour_map, computed vectorized per (mode, filter)
  group. The all-255 tables give the largest D (255 * 2w), where the quotient is largest.

Environment: SIM, CONFIG narrow the parametrization; SEED fixes the randomness;
VECTORS = random vectors in all (default 2000; the hard cases come on top).
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

import cocotb
from cocotb.triggers import RisingEdge

import hdlbuild
from model.hw import golden
from model.hw.config import TABLE_FILTERS, cmap_family, load_config, variant
from tb import pipe

ROOT = Path(__file__).resolve().parents[2]
SOURCES = ["colour_map.v", "cmap_sat.v", "cmap_divide.v", "cmap_mip.v", "cmap_point.v", "colour_table.v", "sat_index.v",
           "sat_integral.v", "box_divide.v", "mip_index.v", "delay_line.v", "cmap_sat2.v", "sat2_table.v",
           "sat2_integral.v", "sat_integral_serial.v"]
TABLE_CLUT, TABLE_CSAT, TABLE_MIP = 0, 1, 2


def latency(cfg) -> int:
    """`LAT_COLOUR_MAP (fpga_regs: `LAT_COLOUR_MAP_FPGA) from rtl/tex_latency.vh."""
    return hdlbuild.latency("colour_map", cfg)


# ---------------------------------------------------------------------------
# stimulus


def table_sets(cfg, r, variant=False):
    """(name, n_log2, clut[N, 4], full) for every table the test loads; full: the whole
    cross product of hard f and w values, else f x the w values that matter for this N."""
    nmax = cfg.n_log2_max
    big = 1 << nmax
    zebra = np.where((np.arange(big) & 1)[:, None] == 1, 255, 0) * np.ones((1, 4), dtype=np.int64)
    zebra[:, 3] = 255 - zebra[:, 3]  # alpha the other way round
    edges = r.integers(0, 256, size=(big, 4))  # extremes at the ends (clamp mode's edge entries)
    edges[0], edges[-1] = 255, 0
    if variant:  # mip / none builds: fewer tables
        sets = [("random N=1", 0, r.integers(0, 256, size=(1, 4)), True),
                (f"random N={1 << min(3, nmax)}", min(3, nmax), r.integers(0, 256, size=(1 << min(3, nmax), 4)), False),
                (f"random N={big}", nmax, r.integers(0, 256, size=(big, 4)), True),
                (f"zebra N={big}", nmax, zebra, False)]
        return [(name, n, np.asarray(c, dtype=np.int64), full) for name, n, c, full in sets]
    sets = []
    for n in range(nmax + 1):
        sets.append((f"random N={1 << n}", n, r.integers(0, 256, size=(1 << n, 4)), n in (0, nmax)))
    sets.append((f"all 255 N={big}", nmax, np.full((big, 4), 255), True))
    sets.append(("all 255 N=1", 0, np.full((1, 4), 255), False))
    sets.append((f"all 0 N={big}", nmax, np.zeros((big, 4), dtype=np.int64), False))
    sets.append((f"zebra N={big}", nmax, zebra, False))
    sets.append(("zebra N=2", 1, np.array([[0, 255, 0, 255], [255, 0, 255, 0]]), False))
    sets.append((f"edges N={big}", nmax, edges, True))
    return [(name, n, np.asarray(c, dtype=np.int64), full) for name, n, c, full in sets]


def hard_f(cfg, n_log2):
    ff, fw = cfg.f_frac, cfg.f_w
    one, N = 1 << ff, 1 << n_log2
    gsh = (1 << (cfg.w_cap_log2 + ff - 1)) >> n_log2  # clamp guard / N
    fmin, fmax = -(1 << (fw - 1)), (1 << (fw - 1)) - 1
    v = [0, 1, -1, one, one - 1, one + 1, -one, -one + 1, -one - 1, N * one, N * one - 1, N * one + 1,
         -N * one, 2 * one + 3, -3 * one - 5,
         one >> n_log2, (one >> n_log2) - 1, ((N - 1) * one) >> n_log2, (((N - 1) * one) >> n_log2) - 1,
         one >> (n_log2 + 1), ((2 * N - 1) * one) >> (n_log2 + 1),
         -gsh, -gsh - 1, -gsh + 1, one + gsh, one + gsh + 1, one + gsh - 1,
         fmin, fmax, fmin + 1, fmax - 1, 1 << (fw - 2), -(1 << (fw - 2))]
    return np.unique(np.clip(np.array(v, dtype=np.int64), fmin, fmax))


def hard_w(cfg, n_log2, full=True):
    ff = cfg.f_frac
    one, N = 1 << ff, 1 << n_log2
    cap = cfg.w_cap
    if full:
        v = [0, 1, 2, 3, one >> 1, one - 1, one, one + 1, N * one - 1, N * one, N * one + 1, 2 * N * one,
             3 * N * one + 7, 5 * one + 12345, cap // 3, cap - 1, cap]
    else:
        v = [0, 1, one - 1, N * one - 1, N * one, N * one + 1, cap]
    return np.unique(np.clip(np.array(v, dtype=np.int64), 0, cap))


def norm_w(cfg):
    """w at the edges of the normalised division (div_bits = B > 0; docs/numerics.md "Colour
    map"): for every power of two 2^k, 2^(B-1) <= 2^k <= cap, with sh0 = bitlen(2^k) - B and
    h = 2^(sh0-1): 2^k - 1, 2^k, 2^k + 1; the rounding ties 2^k + h - 1, 2^k + h (B = 9:
    2^18 + 511 with all-255 entries is a quotient of 256, saturated); 2^k + 2h - 1, 2^k + 2h;
    where rounding carries into 2^B (sh = sh0 + 1): 2^(k+1) - h - 1, 2^(k+1) - h; the cap."""
    b, cap = cfg.div_bits, cfg.w_cap
    if b == 0 or b >= cfg.w_w:
        return np.zeros(0, dtype=np.int64)
    v = [cap, cap - 1]
    for k in range(b - 1, cfg.w_w):
        p = 1 << k
        v += [p - 1, p, p + 1]
        sh0 = k + 1 - b
        if sh0 >= 1:
            h = 1 << (sh0 - 1)
            v += [p + h - 1, p + h, p + 2 * h - 1, p + 2 * h, 2 * p - h - 1, 2 * p - h]
    return np.unique(np.clip(np.array(v, dtype=np.int64), 1, cap))


def random_vectors(cfg, r, n):
    """n random (f, w, mode, filter_en): half over the whole formats, half realistic."""
    fw, ff, cap = cfg.f_w, cfg.f_frac, cfg.w_cap
    full = r.random(n) < 0.5
    f = np.where(full, r.integers(-(1 << (fw - 1)), 1 << (fw - 1), size=n, dtype=np.int64),
                 r.integers(-3 << ff, 4 << ff, size=n, dtype=np.int64))
    e = r.integers(0, cfg.w_w, size=n)
    w_log = (r.random(n) * (2.0 ** e)).astype(np.int64)
    w = np.where(r.random(n) < 0.4, r.integers(0, cap + 1, size=n, dtype=np.int64), np.minimum(w_log, cap))
    w = np.where(r.random(n) < 0.05, 0, w)
    mode = r.integers(0, 2, size=n)
    filt = (r.random(n) < 0.85).astype(np.int64)
    return f, w, mode, filt


def hard_vectors(cfg, n_log2, full=True):
    fs, ws = hard_f(cfg, n_log2), hard_w(cfg, n_log2, full)
    F, W = np.meshgrid(fs, ws, indexing="ij")
    # the normalised division's edges (div_bits > 0) x a few f: 0, 1, 1/3 of the table,
    # the middle of the last entry, just below 0, the largest
    one, N = 1 << cfg.f_frac, 1 << n_log2
    fn = np.array([0, 1, one // 3, ((2 * N - 1) * one) >> (n_log2 + 1), -one - 1, (1 << (cfg.f_w - 1)) - 1])
    FN, WN = np.meshgrid(fn, norm_w(cfg), indexing="ij")
    F, W = np.concatenate([F.ravel(), FN.ravel()]), np.concatenate([W.ravel(), WN.ravel()])
    out = []
    for mode in (golden.MODE_MOD, golden.MODE_CLAMP):
        out.append((F, W, np.full(F.shape, mode), np.ones(F.shape, dtype=np.int64)))
        # filter off: the point lookup, whatever w
        wo = np.resize(np.array([0, 1 << cfg.f_frac, cfg.w_cap], dtype=np.int64), fs.shape)
        out.append((fs, wo, np.full(fs.shape, mode), np.zeros(fs.shape, dtype=np.int64)))
    return [np.concatenate(c) for c in zip(*out)]


def expected(cfg, n_log2, clut, f, w, mode, filt):
    """golden colour_map per (mode, filter) group -> packed RGBA words."""
    out = np.zeros(f.shape, dtype=np.int64)
    for m in (golden.MODE_MOD, golden.MODE_CLAMP):
        for fe in (0, 1):
            sel = (mode == m) & (filt == fe)
            if not sel.any():
                continue
            tex = golden.TexInt(Q=np.zeros(10, dtype=np.int64), a=np.zeros(0, dtype=np.int64),
                                T=np.zeros((0, 3, 3), dtype=np.int64), o=np.zeros((0, 3), dtype=np.int64),
                                mode=m, n_log2=n_log2, filter=bool(fe), clut=clut)
            rgba = golden.colour_map(cfg, tex, f[sel], w[sel]).astype(np.int64)
            out[sel] = rgba[:, 0] | (rgba[:, 1] << 8) | (rgba[:, 2] << 16) | (rgba[:, 3] << 24)
    return out


# ---------------------------------------------------------------------------
# cocotb side


async def write_tables(dut, cfg, n_log2, clut, r):
    """Load clut, csat and mip through the write port, ce random; then junk that must be ignored."""
    csat, mip = golden.build_tables(clut)
    cw, nmax = cfg.csat_w, cfg.n_log2_max
    writes = [(TABLE_CLUT, a, e) for a, e in enumerate(clut)]
    if cfg.filter in TABLE_FILTERS:  # sat, sat_fc, sat2 (which derives csat2 from these writes)
        writes += [(TABLE_CSAT, a, e) for a, e in enumerate(csat)]
    if cfg.filter == "mip":
        writes += [(TABLE_MIP, a, e) for a, e in enumerate(mip)]
    junk = lambda: r.integers(0, 1 << cw, size=4)  # noqa: E731
    for _ in range(4):
        writes.append((3, int(r.integers(0, 2 << nmax)), junk()))
        # addresses past the end of clut / csat (2^nmax entries) and mip (2^(nmax+1) - 1)
        writes.append((TABLE_CLUT, int(r.integers(1 << nmax, 2 << nmax)), junk()))
        writes.append((TABLE_CSAT, int(r.integers(1 << nmax, 2 << nmax)), junk()))
        writes.append((TABLE_MIP, (2 << nmax) - 1, junk()))
        # tables the configuration does not build
        if cfg.filter not in TABLE_FILTERS:
            writes.append((TABLE_CSAT, int(r.integers(0, 1 << n_log2)), junk()))
        if cfg.filter != "mip":
            writes.append((TABLE_MIP, int(r.integers(0, (2 << n_log2) - 1)), junk()))
    # a clut / mip entry carries 8 bits per lane: set the upper lane bits, they must be ignored
    hi = ((1 << cw) - 1) ^ 0xFF
    dut.in_valid.value = 0
    for table, addr, e in writes:
        e = [int(x) | (hi if table in (TABLE_CLUT, TABLE_MIP) else 0) for x in e]
        dut.wr_en.value = 1
        dut.wr_table.value = table
        dut.wr_addr.value = addr
        dut.wr_data.value = pipe.pack(e, cw)
        dut.ce.value = int(r.random() < 0.5)
        await RisingEdge(dut.clk)
    dut.wr_en.value = 0
    dut.ce.value = 1


@cocotb.test()
async def colour_map_vs_golden(dut):
    cfg = pipe.cfg()
    r = pipe.rng(11)
    lat = latency(cfg)
    dut.wr_en.value = 0
    await pipe.start(dut)
    # after reset, before any table or vector: outputs resolved and 0 (no X)
    assert dut.out_valid.value.is_resolvable and int(dut.out_valid.value) == 0, "out_valid after reset"
    assert dut.rgba_out.value.is_resolvable and int(dut.rgba_out.value) == 0, "rgba_out after reset"
    dut.wr_en.value = 0
    dut.wr_table.value = 0
    dut.wr_addr.value = 0
    dut.wr_data.value = 0
    fmask = (1 << cfg.f_w) - 1
    sets = table_sets(cfg, r, variant=os.environ.get("CM_VARIANT") == "1")
    n_rand = -(-pipe.n_vectors() // len(sets))
    total = 0
    for name, n_log2, clut, full in sets:
        await write_tables(dut, cfg, n_log2, clut, r)
        hf, hw, hm, he = hard_vectors(cfg, n_log2, full)
        rf, rw, rm, re_ = random_vectors(cfg, r, n_rand)
        f = np.concatenate([hf, rf])
        w = np.concatenate([hw, rw])
        mode = np.concatenate([hm, rm])
        filt = np.concatenate([he, re_])
        perm = r.permutation(len(f))
        f, w, mode, filt = f[perm], w[perm], mode[perm], filt[perm]
        if cmap_family(cfg) == "sat2":  # w = (a, b): b the same widths in another order
            w = np.stack([w, w[r.permutation(len(w))]], axis=-1)
        exp = expected(cfg, n_log2, clut, f, w, mode, filt)
        fl, ml, el = f.tolist(), mode.tolist(), filt.tolist()
        wl = (w[:, 0] | (w[:, 1] << cfg.w_w)).tolist() if w.ndim == 2 else w.tolist()
        wmask = (1 << (w.ndim * cfg.w_w)) - 1

        def apply(i):
            dut.f_in.value = fl[i] & fmask
            dut.w_in.value = wl[i] & wmask
            dut.mode.value = ml[i]
            dut.n_log2.value = n_log2
            dut.filter_en.value = el[i]

        def sample():
            return int(dut.rgba_out.value)

        got = await pipe.run_vectors(dut, apply, sample, len(f), lat, seed=int(r.integers(1 << 30)),
                                     spacing=cfg.cmap_clocks)  # the fold: a pixel at most every 4 clocks
        got = np.array(got, dtype=np.int64)
        bad = np.nonzero(got != exp)[0]
        if len(bad):
            lines = []
            for i in bad[:10]:
                lines.append(f"  vector {i}: f={fl[i]} w={wl[i]} mode={ml[i]} filter_en={el[i]} n_log2={n_log2}: "
                             f"expected {int(exp[i]):08x} got {int(got[i]):08x}")
            raise AssertionError(f"table '{name}': {len(bad)} of {len(f)} vectors differ\n" + "\n".join(lines))
        total += len(f)
        dut._log.info(f"table '{name}': {len(f)} vectors ({len(hf)} hard cases) bit-exact")
    dut._log.info(f"{total} vectors over {len(sets)} tables, latency {lat}: all bit-exact")


# ---------------------------------------------------------------------------
# pytest side


def run_colour_map(sim: str, config, extra_env=None) -> None:
    """colour_map built with the parameters of `config` (a name or a variant), by pipe.run_block."""
    pipe.run_block("colour_map", sim, test_file=__file__, config=config, sources=SOURCES, extra_env=extra_env)


@pytest.mark.parametrize("sim,config", hdlbuild.family_params(fpga_regs=True))
def test_colour_map_rtl(sim, config):
    run_colour_map(sim, config)


def test_colour_map_check():
    """colour_map's elaboration-time check (g_bad_filter, the else of the family chain) both ways on
    full's parameters (FILTER 1, sat): refused on a FILTER no family takes (4, one past the last,
    and -1, one below the first); accepted on each of 0 (point), 1 (sat), 2 (mip) and 3 (sat2, on
    full_sat2's formats F_FRAC 13, W_CAP_LOG2 11: full's D does not fit cmap_sat2's 62 bits).
    (g_bad_latency compares rtl/tex_latency.vh's latencies of the chosen family: no parameter set
    makes it true.)"""
    b = hdlbuild.block_params(hdlbuild.config_of("full"), "colour_map")
    hdlbuild.check_refusals(
        "colour_map", SOURCES, b,
        accept={"FILTER 1 (full)": {}, "FILTER 0": {"FILTER": 0}, "FILTER 2": {"FILTER": 2},
                "FILTER 3": {"FILTER": 3, "F_FRAC": 13, "W_CAP_LOG2": 11}},
        refuse={"FILTER 4": {"FILTER": 4}, "FILTER -1": {"FILTER": -1}},
        error_module="colour_map_unknown_filter")


def test_colour_map_cmap_clocks_rtl():
    """The same cocotb test on colour_map's fold (config/candidates/compact_q6c4.toml, cmap_clocks
    = 4: cmap_sat a channel a clock, `LAT_COLOUR_MAP_SERIAL), a pixel at most every fourth enabled
    clock, every table, under Icarus and Verilator (SIM= picks one)."""
    from model.hw.config import ROOT

    cfg = load_config(ROOT / "config" / "candidates" / "compact_q6c4.toml")
    for sim in ([os.environ["SIM"]] if os.environ.get("SIM") else ["icarus", "verilator"]):
        run_colour_map(sim, cfg)


def test_colour_map_cmap_clocks_check():
    """The fold's elaboration-time checks both ways on compact's parameters: colour_map refuses
    CLOCKS = 4 on another family than the box (FILTER 2, mip: g_bad_clocks) and cmap_sat refuses
    it with FPGA_REGS (g_bad_params) and CLOCKS = 2; CLOCKS 1 and 4 are accepted."""
    b = hdlbuild.block_params(hdlbuild.config_of("compact"), "colour_map")
    hdlbuild.check_refusals("colour_map", SOURCES, b, accept={"CLOCKS 1": {}, "CLOCKS 4": {"CLOCKS": 4}},
                            refuse={"CLOCKS 4 mip": {"CLOCKS": 4, "FILTER": 2}},
                            error_module="colour_map_clocks_needs_filter_sat")
    hdlbuild.check_refusals("colour_map", SOURCES, b, accept={"CLOCKS 4 FILTER 1": {"CLOCKS": 4}},
                            refuse={"CLOCKS 4 fpga_regs": {"CLOCKS": 4, "FPGA_REGS": 1},
                                    "CLOCKS 2": {"CLOCKS": 2}},
                            error_module="cmap_sat_clocks_must_be_1_or_4_without_fpga_regs")


def _variant_params():
    """Icarus only unless SIM= asks for a simulator (the variants are a cheap extra check)."""
    sims = [os.environ["SIM"]] if os.environ.get("SIM") else ["icarus"]
    cfgs = [os.environ["CONFIG"]] if os.environ.get("CONFIG") else list(hdlbuild.CONFIGS)
    return [(s, c, f) for s in sims for c in cfgs for f in ("mip", "none")]


def test_colour_map_sat2_rtl():
    """The same cocotb test on the trapezoid (config/candidates/full_sat2.toml: colour_map picks
    cmap_sat2, w_in = {b, a}, the clamp guard W), the variants' tables, under Icarus (SIM= picks)."""
    from model.hw.config import ROOT

    run_colour_map(os.environ.get("SIM", "icarus"), load_config(ROOT / "config" / "candidates" / "full_sat2.toml"),
                   extra_env={"CM_VARIANT": "1"})


@pytest.mark.parametrize("sim,config,filt", _variant_params())
def test_colour_map_filter_variants_rtl(sim, config, filt):
    """The same cocotb test with the configuration's filter switched to mip / none."""
    run_colour_map(sim, variant(load_config(config), f"{config}_{filt}", filter=filt), extra_env={"CM_VARIANT": "1"})


def _edge_params():
    """The extremes of the colour-map formats (tb/pipe.py configs colour_edges: "small", n_log2_max 1,
    w_cap_log2 1, f_frac 8; "wide", n_log2_max 10, w_cap_log2 14, f_frac 20) under Verilator unless
    SIM= asks for a simulator (wide's tables are 1024 entries: slow under Icarus)."""
    sims = [os.environ["SIM"]] if os.environ.get("SIM") else ["verilator"]
    return [(s, name) for s in sims for name in ("small", "wide")]


@pytest.mark.parametrize("sim,name", _edge_params())
def test_colour_map_edges_rtl(sim, name):
    """The same cocotb test on the extremes of the colour-map formats: the clamp thresholds
    guard >> n_log2 (gsh, lo_thr, hi_thr), N << F_FRAC and (f mod 1) N at their lowest and
    highest bits, every table size of each."""
    run_colour_map(sim, dict(pipe.configs(colour_edges=True))[name])


def _div_variant_params():
    """Icarus only unless SIM= asks for a simulator; CONFIG= narrows the configurations."""
    sims = [os.environ["SIM"]] if os.environ.get("SIM") else ["icarus"]
    cfgs = [os.environ["CONFIG"]] if os.environ.get("CONFIG") else list(hdlbuild.CONFIGS)
    # 1: the narrowest divisor, where D + w + 2 h(sh) of a whole 255-valued window reaches 2^D_W
    # (found by `make fit`'s descent; cmap_divide's sum is one bit wider since)
    bits = {"reduced": (1, 4, 9, load_config("reduced").w_w - 1), "full": (10,)}
    return [(s, c, b) for s in sims for c in cfgs for b in bits.get(c, ())]


@pytest.mark.parametrize("sim,config,bits", _div_variant_params())
def test_colour_map_div_variants_rtl(sim, config, bits):
    """The same cocotb test with the configuration's div_bits switched."""
    run_colour_map(sim, variant(load_config(config), f"{config}_div{bits}", div_bits=bits))


@pytest.mark.parametrize("bits", (0, 1, 9))
def test_colour_map_fpga_div_variants_rtl(bits):
    """reduced with fpga_regs (the normalisation split across stages 5a/5b, w + 2 h(sh) from its
    two candidates, the shift a stage after the sum, 6c) and div_bits switched to the exact
    division (its operands registered in 6c), the narrowest divisor and a saturating one, under
    Icarus (SIM= picks the simulator)."""
    run_colour_map(os.environ.get("SIM", "icarus"),
                   variant(load_config("reduced"), f"reduced_fpga_div{bits}", div_bits=bits, fpga_regs=True))
