"""delay_line (rtl/delay_line.v) bit-exact against golden delay_line, the stream twin: the
output is the input N enabled clocks earlier.

Parameter sets (W, N, CLEAR): no stage (N = 0, a wire, CLEAR 0 and 1), one stage, several,
a valid-bit line (W = 1, CLEAR = 1) and data lines (CLEAR = 0) as texture_pipeline
instantiates them (3 s_w bits of full's s, the filter width of reduced), a wide word.
Stimulus: a stream of random words with ce low 30% of the clocks (also in runs), rst
high at the first clocks and at random clocks later (CLEAR = 1 clears the line there,
whatever ce; CLEAR = 0 must ignore it); d_out is compared after every clock edge where
the twin knows it (a CLEAR = 0 line holds unknown words until N words went in).
"""
from __future__ import annotations

import random

import numpy as np

import cocotb
from cocotb.triggers import ReadOnly, RisingEdge, Timer

from model.hw import golden as G
from model.hw.config import load_config
from tb import pipe


def _sets():
    full, reduced = load_config("full"), load_config("reduced")
    return {"n0": {"W": 8, "N": 0, "CLEAR": 0}, "n0_clear": {"W": 1, "N": 0, "CLEAR": 1},
            "n1": {"W": 5, "N": 1, "CLEAR": 0}, "n1_clear": {"W": 1, "N": 1, "CLEAR": 1},
            "n3_clear": {"W": 12, "N": 3, "CLEAR": 1}, "valid7": {"W": 1, "N": 7, "CLEAR": 1},
            "full_s": {"W": 3 * full.s_w, "N": 4, "CLEAR": 0}, "reduced_w": {"W": reduced.w_w, "N": 2, "CLEAR": 0},
            "wide": {"W": 60, "N": 5, "CLEAR": 0}}


# every set under Icarus; under Verilator (a build costs 5-20 s) the widest
test_delay_line_rtl = pipe.block_test("delay_line", _sets(), ("n3_clear",), __file__)


@cocotb.test()
async def delay_line_bit_exact(dut):
    p = pipe.block_params()
    w, n, clear = p["W"], p["N"], p["CLEAR"]
    r = random.Random(int(pipe.rng(53).integers(1 << 30)))
    t_n = pipe.n_vectors() + 40
    d = [r.getrandbits(w) for _ in range(t_n)]
    ce, stall = [], False
    for _ in range(t_n):  # stalls of one clock and runs of them
        stall = r.random() < (0.7 if stall else 0.2)
        ce.append(0 if stall else 1)
    rst = [1 if t < 2 or r.random() < 0.01 else 0 for t in range(t_n)]
    # the twin streams clock numbers 1.. (so words of any width: which input each output
    # is; 0 a cleared stage, -1 unknown)
    src = G.delay_line(np.arange(1, t_n + 1), n, ce=ce, rst=rst, clear=bool(clear), fill=-1)
    exp = [d[i - 1] if i > 0 else int(i) for i in src]
    await pipe.start(dut, reset=False, valid=False)
    got = []
    for t in range(t_n):
        dut.d_in.value = d[t]
        dut.ce.value = ce[t]
        dut.rst.value = rst[t]
        await RisingEdge(dut.clk)
        await ReadOnly()
        got.append(int(dut.d_out.value) if src[t] >= 0 else -1)
        await Timer(1, unit="ns")
    known = int((src >= 0).sum())
    assert known > t_n // 2, "too few known outputs"
    pipe.check_equal(dut, got, exp, lambda t: f"clock {t} ce={ce[t]} rst={rst[t]}", f"delay_line {p} ({known} known)")
