"""noise_grad (rtl/noise_grad.v) bit-exact against golden noise_grad: a noise term's gradient
a (dn/dp) T from its value path's corner values v, lerps e and fz, weights wy, wz and slopes
dw, each input at the stage that reads it, latency `LAT_NOISE_GRAD (FPGA_REGS:
`LAT_NOISE_GRAD_FPGA; rtl/tex_latency.vh).

Parameter sets: noise_term's instances (texture_pipeline's parameters) under full (affine,
cubic, any amplitude), compact (pow2 T and a, cubic), two random valid configurations with
the gradient, the linear blend (full with blend linear, and compact's), and full and
compact with fpga_regs (each lerp in three stages); with per-term exponents (T_EXP_W,
A_EXP_W > 0; pipe.exponent_configs with the gradient: full_bfp, full_exp, two random ones,
one of them with fpga_regs).
Vectors: each with its own a and T (noise_fold changes the term every clock) and random
corner values over [-1, 1] (with the extremes -1, 1 - 2^-n_frac, the steepest differences),
cell fractions over [0, 1) (the weights and slopes noise_blend gives them, with 0, 1/2 and
just below 1), e and fz the golden lerps of v; T over its format (pow2: 0 / 2^e, every e),
a over its format (pow2: 0, +-2^k, every k); with exponents te and ae, 0 and their largest in
the first 64 vectors, uniform after; without exponents te and ae (one bit each, not read) random
junk every clock. Streamed with random ce stalls and gaps (load
= 0, the inputs random junk): a vector's later inputs follow it by the stage offsets of the
header; every load must show that vector's ag, and ag_out must hold on every other clock (ce = 0,
or load = 0 with junk on the inputs: the output registers load only with ce and load).
"""
from __future__ import annotations

import math
import random
from types import SimpleNamespace

import numpy as np

import cocotb
from cocotb.triggers import ReadOnly, RisingEdge, Timer

from hdlbuild.params import ENUMS, block_params
from model.hw import golden as G
from model.hw.config import latency, variant
from tb import pipe

KEYS = ("T_W", "T_FRAC", "A_W", "A_FRAC", "P_FRAC", "N_FRAC", "C_FRAC", "TRANSFORM", "BLEND", "AMPLITUDE", "FPGA_REGS",
        "T_EXP_W", "A_EXP_W")  # (the exponents only where a configuration has them)


def _sets():
    from model.hw.config import ROOT, load_config

    full, compact = load_config("full"), load_config("compact")
    cfgs = [("full", full), ("compact", compact), ("full_linear", variant(full, "full_linear", blend="linear")),
            ("compact_linear", variant(compact, "compact_linear", blend="linear")),
            ("full_fpga", variant(full, "full_fpga", fpga_regs=True)),
            ("compact_fpga", variant(compact, "compact_fpga", fpga_regs=True))]
    cfgs += [(n, c) for n, c in pipe.configs(1331, 1332, 1333) if n.startswith("random") and c.noise_gradient]
    cfgs += [(n, c) for n, c in pipe.exponent_configs(1341, 1342) if c.noise_gradient]
    # the edge of the exponent check (H_SHIFT = n_frac + t_frac - c_frac >= TE_MAX): full_narrow with a
    # 1-bit T exponent, t_frac 1 and c_frac 11, so H_SHIFT = TE_MAX = 1 exactly (kills mutant b217f56c)
    narrow = load_config(str(ROOT / "config" / "candidates" / "full_narrow.toml"))
    cfgs.append(("full_hte", variant(narrow, "full_hte", t_exp_w=1, t_frac=1, t_w=narrow.t_w - narrow.t_frac + 1,
                                     c_frac=narrow.n_frac)))
    out = {}
    for name, cfg in cfgs:
        p = block_params(cfg, "noise_term")
        out[name] = {k: p[k] for k in KEYS if k in p}
    return out


# every set under Icarus; under Verilator (a build costs 5-20 s) full's, compact with fpga_regs and full_bfp's
SOURCES = ["noise_grad.v", "lerp.v", "delay_line.v"]
test_noise_grad_rtl = pipe.block_test("noise_grad", _sets(), ("full", "compact_fpga", "full_bfp"), __file__,
                                      sources=SOURCES)



def test_noise_grad_check():
    """noise_grad's elaboration-time check (g_bad_params) both ways on full's set (3-bit T and A
    exponents): refused with each term alone true (a negative exponent width; a T exponent
    without the affine multiplier, TRANSFORM 1, or with a right shift H_SHIFT = n_frac + t_frac -
    c_frac below its largest value TE_MAX; an A exponent on pow2 amplitudes, AMPLITUDE 1, or with
    fewer fraction bits than its largest value AE_MAX); accepted at each edge (H_SHIFT = TE_MAX,
    A_FRAC = AE_MAX) and with no exponents on pow2 T and amplitudes (compact's kind)."""
    import hdlbuild

    b = _sets()["full"]
    te_max, ae_max = (1 << b["T_EXP_W"]) - 1, (1 << b["A_EXP_W"]) - 1
    c_edge = b["N_FRAC"] + b["T_FRAC"] - te_max  # H_SHIFT = TE_MAX
    hdlbuild.check_refusals(
        "noise_grad", SOURCES, b,
        accept={"full": {}, "H_SHIFT = TE_MAX": {"C_FRAC": c_edge}, "A_FRAC = AE_MAX": {"A_FRAC": ae_max},
                "no exponents, pow2 T and a": {"T_EXP_W": 0, "A_EXP_W": 0, "TRANSFORM": 1, "AMPLITUDE": 1}},
        refuse={"T_EXP_W < 0": {"T_EXP_W": -1}, "A_EXP_W < 0": {"A_EXP_W": -1},
                "T exponent, pow2 T": {"A_EXP_W": 0, "TRANSFORM": 1},
                "H_SHIFT < TE_MAX": {"C_FRAC": c_edge + 1},
                "A exponent, pow2 a": {"T_EXP_W": 0, "AMPLITUDE": 1},
                "A_FRAC < AE_MAX": {"A_FRAC": ae_max - 1}},
        error_module="noise_grad_exponents_need_affine_any_and_right_shifts")

def _stimulus(p, r, n):
    """n vectors: (a, T [3, 3], v [2][2][2], wx, wy, wz, dw [3], te, ae) as Python ints."""
    nf, pf, tw, aw = p["N_FRAC"], p["P_FRAC"], p["T_W"], p["A_W"]
    te_max, ae_max = (1 << p.get("T_EXP_W", 0)) - 1, (1 << p.get("A_EXP_W", 0)) - 1
    blend = SimpleNamespace(blend="cubic" if p["BLEND"] else "linear", p_frac=pf)
    one = 1 << nf
    vext = [-one, one - 1, 0]
    fext = [0, 1 << (pf - 1), (1 << pf) - 1, 1]
    out = []
    for i in range(n):
        if i < 64:  # extremes: corner values at -1 / 1 - ulp in alternation, edge fractions
            v = [[[vext[(i + 3 * a + 2 * b + c) % 2] if i % 4 else vext[(a + i) % 2]
                   for c in range(2)] for b in range(2)] for a in range(2)]
            fr = [fext[(i + k) % 4] for k in range(3)]
        else:
            v = [[[int(r.integers(-one, one)) for _ in range(2)] for _ in range(2)] for _ in range(2)]
            fr = [int(r.integers(0, 1 << pf)) for _ in range(3)]
        w, dw = G.noise_blend(blend, np.array(fr, dtype=np.int64))
        if p["TRANSFORM"]:
            T = np.zeros((3, 3), dtype=np.int64)
            for j in range(3):
                T[j, j] = 0 if r.random() < 0.1 else 1 << int(r.integers(0, tw - 1))
        else:
            lim = (1 << (tw - 1))
            big = min(4 << p["T_FRAC"], lim - 1)  # |T| <= 4, within the format (t_frac may exceed t_w: mantissas)
            T = r.integers(-lim, lim, (3, 3)) if i % 2 or i < 64 else r.integers(-big, big + 1, (3, 3))
            if i < 64:
                T = np.full((3, 3), -lim if i % 3 else lim - 1, dtype=np.int64)
        if p["AMPLITUDE"]:
            k = int(r.integers(0, aw))
            a = 0 if r.random() < 0.1 else (-(1 << k) if (k == aw - 1 or r.random() < 0.5) else 1 << k)
        else:
            a = int(r.integers(-(1 << (aw - 1)), 1 << (aw - 1))) if i >= 64 else [-(1 << (aw - 1)), (1 << (aw - 1)) - 1][i % 2]
        # the exponents: 0 and the largest in alternation among the extremes, then uniform (fixed
        # point: no draw, the stream as it was)
        te = (te_max * ((i // 2) % 2) if i < 64 else int(r.integers(0, te_max + 1))) if te_max else 0
        ae = (ae_max * ((i // 4) % 2) if i < 64 else int(r.integers(0, ae_max + 1))) if ae_max else 0
        out.append((a, np.asarray(T, dtype=np.int64), v, [int(x) for x in w], [int(x) for x in dw], te, ae))
    return out


@cocotb.test()
async def noise_grad_bit_exact(dut):
    p = pipe.block_params()
    nf, pf, tw, aw = p["N_FRAC"], p["P_FRAC"], p["T_W"], p["A_W"]
    nw, bw = nf + 2, pf + 2
    lat = latency("noise_grad", SimpleNamespace(fpga_regs=bool(p["FPGA_REGS"])))
    lp = 2 if p["FPGA_REGS"] else 0
    assert lat == 5 + 3 * lp, f"`LAT_NOISE_GRAD{'_FPGA' if lp else ''} = {lat}: not this testbench's stages"
    off = {"e": 1 + lp, "fz": 2 + 2 * lp, "t": 3 + 3 * lp, "a": 4 + 3 * lp}  # after v, wy, dw
    cfg = SimpleNamespace(d={"h_shift": nf + p["T_FRAC"] - p["C_FRAC"]}, p_frac=pf, a_frac=p["A_FRAC"])
    r = pipe.rng(81)
    vec = _stimulus(p, r, pipe.n_vectors())
    n = len(vec)
    ew, eaw = math.ceil(math.log2(tw - 1)), math.ceil(math.log2(aw))
    ag_w = len(dut.ag_out.value) // 3

    words, exp = [], []
    for a, T, v, w, dw, te, ae in vec:
        e = [[G.lerp(pf, v[0][j][k], v[1][j][k], w[0]) for k in range(2)] for j in range(2)]
        fz = [G.lerp(pf, e[0][k], e[1][k], w[1]) for k in range(2)]
        exp.append(tuple(int(x) for x in G.noise_grad(cfg, a, T, v, e, fz, w[1], w[2], dw, te, ae)))
        if p["TRANSFORM"]:
            t_word = pipe.pack([(1 << ew) if T[j, j] == 0 else int(T[j, j]).bit_length() - 1 for j in range(3)], ew + 1)
        else:
            t_word = pipe.pack(T.reshape(9), tw)
        if p["AMPLITUDE"]:
            a_word = ((a == 0) << (eaw + 1)) | ((a < 0) << eaw) | ((abs(a) & -abs(a)).bit_length() - 1 if a else 0)
        else:
            a_word = a & ((1 << aw) - 1)
        words.append({"v": pipe.pack([v[i][j][k] for i in range(2) for j in range(2) for k in range(2)], nw),
                      "wy": w[1], "dw": pipe.pack(dw, bw), "wz": w[2],
                      "e": pipe.pack([e[j][k] for j in range(2) for k in range(2)], nw),
                      "fz": pipe.pack(fz, nw), "t_in": t_word, "a_in": a_word, "te": te, "ae": ae})
    widths = {"v": 8 * nw, "wy": bw, "dw": 3 * bw, "wz": bw, "e": 4 * nw, "fz": 2 * nw,
              "t_in": len(dut.t_in.value), "a_in": len(dut.a_in.value), "te": len(dut.te.value),
              "ae": len(dut.ae.value)}
    port_off = {"v": 0, "wy": 0, "dw": 0, "e": off["e"], "wz": off["e"], "fz": off["fz"], "t_in": off["t"],
                "a_in": off["a"]}
    # the exponents beside T and a; without them (T_EXP_W, A_EXP_W 0) the ports are one bit each and
    # not read (the header): junk every clock, from a generator of its own (the stream as it was),
    # which must not reach ag
    port_off.update({"te": off["t"], "ae": off["a"]})
    no_exp = {port for port, key in (("te", "T_EXP_W"), ("ae", "A_EXP_W")) if not p.get(key, 0)}
    dut.te.value = 0
    dut.ae.value = 0

    await pipe.start(dut, valid=False)
    rr = random.Random(int(r.integers(1 << 30)))
    rj = random.Random(int(r.integers(1 << 30)))  # the junk on an exponent port that is not read
    hist = []  # the vector (or None: a gap) entering at each enabled clock
    got, idx = [], []
    nxt, guard = 0, 0
    held = int(dut.ag_out.value)  # the output registers: loaded only when ce and load (the header)
    n_held = 0
    while len(got) < n:
        ce = 1 if rr.random() >= 0.2 else 0
        cur = nxt if (nxt < n and rr.random() >= 0.1) else None
        for port, d in port_off.items():
            k = cur if d == 0 else (hist[-d] if len(hist) >= d else None)
            if port in no_exp:
                getattr(dut, port).value = rj.getrandbits(widths[port])
                continue
            getattr(dut, port).value = words[k][port] if k is not None else rr.getrandbits(widths[port])
        ld = hist[-off["a"]] if len(hist) >= off["a"] else None
        dut.load.value = int(ld is not None)
        dut.ce.value = ce
        await RisingEdge(dut.clk)
        await ReadOnly()
        now = int(dut.ag_out.value)
        if not (ce and ld is not None):  # a stall (its inputs held or not) or a gap (junk inputs): held
            assert now == held, (f"ag_out changed on a clock with ce = {ce}, load = {int(ld is not None)} "
                                 f"(clock {guard}): {held:#x} -> {now:#x}")
            n_held += 1
        held = now
        if ce:
            hist.append(cur)
            if cur is not None:
                nxt += 1
            if ld is not None:
                got.append(tuple(pipe.unpack(int(dut.ag_out.value), ag_w, 3)))
                idx.append(ld)
        guard += 1
        assert guard < 20 * (n + 20), "no progress"
        await Timer(1, unit="ns")
    assert idx == list(range(n)), "vectors out of order"
    assert n_held > 0, "no clock without a load: the hold was not checked"
    pipe.check_equal(dut, got, exp, lambda i: f"a={vec[i][0]} T={vec[i][1].tolist()} v={vec[i][2]} w={vec[i][3]} "
                                              f"te={vec[i][5]} ae={vec[i][6]}",
                     f"noise_grad {p}")
