"""sample_average (rtl/sample_average.v) bit-exact against golden sample_average: a stream of
sample colours (in_valid at random, ce dropped at random, rst at random clocks) is cut into
pixels of SAMPLES consecutive valid samples (counted on enabled edges, restarted by rst), and
each pixel's average and its last sample's tlast must appear one enabled edge after its last
sample, with out_valid high for that one enabled clock and low otherwise; while ce = 0 the
outputs hold.

Parameter sets: SAMPLES 2 and 4. Colours uniform RGBA8, with runs of 0 and 255 channels (the
sums' ends and the rounding of exact halves).
"""
from __future__ import annotations

import random
from types import SimpleNamespace

import numpy as np

import cocotb
from cocotb.triggers import ReadOnly, RisingEdge, Timer

from model.hw import golden as G
from tb import pipe

test_sample_average_rtl = pipe.block_test("sample_average", {"s2": {"SAMPLES": 2}, "s4": {"SAMPLES": 4}},
                                          ("s2", "s4"), __file__)


@cocotb.test()
async def sample_average_bit_exact(dut):
    n = pipe.block_params()["SAMPLES"]
    cfg = SimpleNamespace(samples=n)
    r = random.Random(int(pipe.rng(73).integers(1 << 30)))
    await pipe.start(dut, reset=True, valid=True)
    group: list = []
    pend = None  # the pixel whose average the registers show: (rgba, last) or None
    prev = None
    pixels, t_n = 0, pipe.n_vectors(3000)
    for t in range(t_n):
        mode = r.random()
        rgba = [r.choice((0, 255, 1, 254)) if mode < 0.3 else r.randint(0, 255) for _ in range(4)]
        vin, last = int(r.random() < 0.7), int(r.random() < 0.5)
        ce, rst = int(r.random() < 0.8), int(r.random() < 0.01)
        dut.in_valid.value, dut.in_rgba.value, dut.in_last.value = vin, pipe.pack(rgba, 8), last
        dut.ce.value, dut.rst.value = ce, rst
        await RisingEdge(dut.clk)
        await ReadOnly()
        now = (int(dut.out_valid.value), int(dut.out_rgba.value), int(dut.out_last.value))
        if rst:
            group, pend = [], None
            assert now == (0, 0, 0), f"clock {t}: after rst the outputs are {now}"
        elif ce:
            pend = None
            if vin:
                group.append(rgba)
                if len(group) == n:
                    avg = G.sample_average(cfg, np.array(group))
                    pend = (pipe.pack([int(v) for v in avg], 8), last)
                    group = []
            if pend is None:
                assert now[0] == 0, f"clock {t}: out_valid high with no pixel complete"
            else:
                pixels += 1
                assert now == (1, *pend), (f"clock {t}: pixel {pixels}: got valid {now[0]} rgba {now[1]:08x} last "
                                           f"{now[2]}, expected rgba {pend[0]:08x} last {pend[1]}")
        elif prev is not None:
            assert now == prev, f"clock {t}: outputs changed while ce = 0"
        prev = now
        await Timer(1, unit="ns")
    assert pixels > t_n // (3 * n), f"too few pixels ({pixels})"
