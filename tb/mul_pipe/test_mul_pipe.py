"""mul_pipe (rtl/mul_pipe.v, latency 1) bit-exact against golden mul_pipe (a * b).

Parameter sets (A_W, B_W): both operands whole (18 x 18), one cut into parts (quadric_mac's
products under reduced and compact with fpga_regs: Q_kk s_k, s_k x_k), both cut (35 x 35,
the widest), narrow ones (2 x 5). Vectors: every combination of the operands' edges (0, 1,
-1, the extremes, the parts' boundaries 2^17 - 1, 2^17, -2^17), then VECTORS random ones
(each operand uniform over its word); streamed with ce stalls.
"""
from __future__ import annotations

import itertools

import numpy as np

import cocotb

from model.hw import golden as G
from model.hw.config import load_config
from tb import pipe


def _sets():
    out = {"whole": {"A_W": 18, "B_W": 18}, "narrow": {"A_W": 2, "B_W": 5}, "widest": {"A_W": 35, "B_W": 35}}
    for name in ("reduced", "compact"):  # quadric_mac's (diagonal, FPGA_REGS) products
        c = load_config(name)
        out[f"{name}_qs"] = {"A_W": c.q_w, "B_W": c.s_w}
        out[f"{name}_sx"] = {"A_W": c.s_w, "B_W": c.v_w}
    return out


# every set under Icarus, the widest under Verilator too
test_mul_pipe_rtl = pipe.block_test("mul_pipe", _sets(), ("widest",), __file__)


def test_mul_pipe_check():
    """mul_pipe's elaboration-time check (g_bad_params) both ways on the set "whole" (18 x 18 bits):
    refused with each term alone true (A_W 36 > 35, B_W 36 > 35); accepted at each edge (A_W 35,
    B_W 35: the widest two-part operands)."""
    import hdlbuild

    hdlbuild.check_refusals(
        "mul_pipe", ["mul_pipe.v"], _sets()["whole"],
        accept={"whole": {}, "A_W 35": {"A_W": 35}, "B_W 35": {"B_W": 35}},
        refuse={"A_W 36": {"A_W": 36}, "B_W 36": {"B_W": 36}},
        error_module="mul_pipe_operands_must_be_at_most_35_bits")


def _edges(w: int):
    lo, hi = -(1 << (w - 1)), (1 << (w - 1)) - 1
    v = {0, 1, -1, lo, hi, lo + 1, hi - 1}
    v |= {x for x in ((1 << 17) - 1, 1 << 17, -(1 << 17), (1 << 17) + 1, -(1 << 17) - 1) if lo <= x <= hi}
    return sorted(v)


@cocotb.test()
async def mul_pipe_bit_exact(dut):
    p = pipe.block_params()
    aw, bw = p["A_W"], p["B_W"]
    r = pipe.rng(61)
    ab = list(itertools.product(_edges(aw), _edges(bw)))
    n = pipe.n_vectors()
    ab += [(int(r.integers(-(1 << (aw - 1)), 1 << (aw - 1))), int(r.integers(-(1 << (bw - 1)), 1 << (bw - 1))))
           for _ in range(n)]
    a = [x for x, _ in ab]
    b = [y for _, y in ab]
    exp = [int(x) for x in G.mul_pipe(a, b)]

    def apply(i):
        dut.a.value = a[i] & ((1 << aw) - 1)
        dut.b.value = b[i] & ((1 << bw) - 1)

    def sample():
        return pipe.unpack(int(dut.p.value), aw + bw, 1, signed=True)[0]

    await pipe.start(dut, reset=False, valid=False)
    got = await pipe.run_stream(dut, apply, sample, len(ab), latency=1, seed=int(r.integers(1 << 30)))
    assert len(got) == len(ab) > n
    pipe.check_equal(dut, got, exp, lambda i: f"a={a[i]} b={b[i]}", f"mul_pipe {p}")
