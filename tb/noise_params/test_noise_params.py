"""noise_params (rtl/noise_params.v) bit-exact against golden noise_params (the words: T and a
as the stages read them, pow2 decoded) and noise_params_delays (which enabled clock's term each
output shows): every output port after every clock.

Parameter sets: noise_term's under full (affine T, amplitude any, gradient), reduced (pow2 T,
pow2 a, no gradient) and compact (pow2, gradient), each with PARAM_PIPE 0 (per-pass
parameters: wires) and 1 (noise_fold: delayed with the vector), compact's and full's also with
FPGA_REGS 1 (noise_term's eight extra stages: longer delays); full_bfp (per-term exponents te,
ae in t_in, a_in) with PARAM_PIPE 0 and 1; a random configuration's.
Stimulus: a new term every clock, ce low 30% of the clocks (also in runs), rst at random (the
lines ignore it): T and a legal for the mode (pow2: diagonal 0 / 2^e with random off-diagonal
entries, which are ignored; a 0 / +-2^e over every e) or, a share, arbitrary words (the
decoders are defined for every word), the format extremes among them; o and the exponents
uniform over their formats. An output is compared where the twin knows it (a delayed one holds
unknown words until its line has filled).
"""
from __future__ import annotations

import random
from types import SimpleNamespace

import numpy as np

import cocotb
from cocotb.triggers import ReadOnly, RisingEdge, Timer

from hdlbuild.params import ENUMS
from model.hw import golden as G
from model.hw.config import ROOT, load_config, random_config, variant
from tb import pipe


def _params(cfg, param_pipe: int, fpga_regs: int = 0) -> dict:
    return {"T_W": cfg.t_w, "A_W": cfg.a_w, "O_W": cfg.d["p_w"], "TRANSFORM": ENUMS["transform"][cfg.transform],
            "AMPLITUDE": ENUMS["amplitude"][cfg.amplitude], "NOISE_GRADIENT": int(cfg.noise_gradient),
            "PARAM_PIPE": param_pipe, "FPGA_REGS": fpga_regs, "T_EXP_W": cfg.t_exp_w, "A_EXP_W": cfg.a_exp_w}


def _sets():
    full, reduced, compact = load_config("full"), load_config("reduced"), load_config("compact")
    bfp = load_config(str(ROOT / "config" / "candidates" / "full_bfp.toml"))
    rnd = random_config(1361)
    rnd = variant(rnd, "r1361", t_exp_w=0, a_exp_w=0)
    out = {}
    for name, cfg in (("full", full), ("reduced", reduced), ("compact", compact), ("full_bfp", bfp)):
        for pp in (0, 1):
            out[f"{name}_pp{pp}"] = _params(cfg, pp)
    out["full_pp1_fpga"] = _params(full, 1, 1)
    out["compact_pp1_fpga"] = _params(compact, 1, 1)
    out["random_pp1"] = _params(rnd, 1)
    return out


# every set under Icarus; under Verilator (a build costs 5-20 s) compact's folded one
test_noise_params_rtl = pipe.block_test("noise_params", _sets(), ("compact_pp1_fpga",), __file__,
                                        sources=["noise_params.v", "delay_line.v"])


def _signed(r, w: int) -> int:
    return r.randint(-(1 << (w - 1)), (1 << (w - 1)) - 1)


def _term(r, p) -> tuple:
    """(a, T [3][3], o [3], te, ae): legal for the mode, or (a share) arbitrary words."""
    tw, aw = p["T_W"], p["A_W"]
    ext_t = (-(1 << (tw - 1)), (1 << (tw - 1)) - 1, 0, -1, 1)
    ext_a = (-(1 << (aw - 1)), (1 << (aw - 1)) - 1, 0, -1, 1)
    T = [[_signed(r, tw) if r.random() < 0.8 else r.choice(ext_t) for _ in range(3)] for _ in range(3)]
    if p["TRANSFORM"] == 1 and r.random() < 0.7:
        for j in range(3):
            T[j][j] = 0 if r.random() < 0.2 else 1 << r.randint(0, tw - 2)
    a = _signed(r, aw) if r.random() < 0.8 else r.choice(ext_a)
    if p["AMPLITUDE"] == 1 and r.random() < 0.7:
        k = r.randint(0, aw - 1)
        a = 0 if r.random() < 0.15 else (-(1 << k) if k == aw - 1 or r.random() < 0.5 else 1 << k)
    o = [r.getrandbits(p["O_W"]) for _ in range(3)]
    return a, T, o, r.getrandbits(p["T_EXP_W"]) if p["T_EXP_W"] else 0, r.getrandbits(p["A_EXP_W"]) if p["A_EXP_W"] else 0


@cocotb.test()
async def noise_params_bit_exact(dut):
    p = pipe.block_params()
    tw, aw = p["T_W"], p["A_W"]
    cfg = SimpleNamespace(t_w=tw, a_w=aw, transform=("affine", "pow2")[p["TRANSFORM"]],
                          amplitude=("any", "pow2")[p["AMPLITUDE"]], d={"p_w": p["O_W"]}, fpga_regs=bool(p["FPGA_REGS"]))
    r = random.Random(int(pipe.rng(1361).integers(1 << 30)))
    t_n = min(pipe.n_vectors(), 600) + 40
    terms = [_term(r, p) for _ in range(t_n)]
    words = [G.noise_params(cfg, a, np.array(T), o, te, ae) for a, T, o, te, ae in terms]
    ce, stall = [], False
    for _ in range(t_n):
        stall = r.random() < (0.7 if stall else 0.2)
        ce.append(0 if stall else 1)
    rst = [1 if t < 2 or r.random() < 0.01 else 0 for t in range(t_n)]
    delays = G.noise_params_delays(cfg, bool(p["PARAM_PIPE"]))
    grad = bool(p["NOISE_GRADIENT"])
    src = {port: G.delay_line(np.arange(1, t_n + 1), n, ce=ce, fill=-1) for port, (_, n) in delays.items()}
    await pipe.start(dut, reset=False, valid=False)
    got, exp, known = {k: [] for k in delays}, {k: [] for k in delays}, 0
    for t in range(t_n):
        a, T, o, te, ae = terms[t]
        dut.t_in.value = pipe.pack([T[j][k] for j in range(3) for k in range(3)], tw) | te << (9 * tw)
        dut.a_in.value = (a & ((1 << aw) - 1)) | ae << aw
        dut.o_in.value = pipe.pack(o, p["O_W"])
        dut.ce.value = ce[t]
        dut.rst.value = rst[t]
        await RisingEdge(dut.clk)
        await ReadOnly()
        for port, (word, _) in delays.items():
            i = int(src[port][t])
            if i <= 0:
                continue
            known += 1
            zero = port.endswith("_s7") and not grad  # stage 7 reads nothing without the gradient
            got[port].append(int(getattr(dut, port).value))
            exp[port].append(0 if zero else words[i - 1][word])
        await Timer(1, unit="ns")
    assert known > 4 * t_n, "too few known outputs"
    for port in delays:
        pipe.check_equal(dut, got[port], exp[port], lambda k: f"{port} output {k}", f"noise_params {port} {p}")
