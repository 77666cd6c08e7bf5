"""axis_skid (the output skid buffer): the AXI-Stream rules and the identity on the stream.

Parametrized over DATA_W (1, 8, 32 as texture_pipeline uses it, 67) and both simulators.
A source with random gaps (holding tdata/tlast while s_axis_tvalid is high and
s_axis_tready low, as the protocol asks of it) and a sink with random stalls (m_axis_tready
low), in phases of different gap and stall rates, including none (one beat per clock) and
a sink that stalls most clocks. Checked on every clock:
- no X or Z on any output after reset (m_axis_tdata/tlast 0, m_axis_tvalid 0);
- while m_axis_tvalid is high and m_axis_tready low, the next clock still has
  m_axis_tvalid high with the same m_axis_tdata and m_axis_tlast;
- s_axis_tready does not move when m_axis_tready does within a clock (it is a register);
- s_axis_tready is low exactly when the buffer holds two beats (accepted, not yet delivered:
  the output register and the skid register), so a stalled sink costs the source nothing
  until both are full;
- at full rate (no gaps, no stalls) one beat per clock, after one clock of latency;
and at the end that the beats out equal the twin model/hw/stream.py axis_skid of the beats
in: nothing lost, duplicated or reordered.
"""
from __future__ import annotations

import os
import random

import pytest

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ReadOnly, RisingEdge, Timer

import hdlbuild
from model.hw.stream import axis_skid
from tb import pipe

SOURCES = ["axis_skid.v"]
WIDTHS = (1, 8, 32, 67)
SIMS = [os.environ["SIM"]] if os.environ.get("SIM") else list(hdlbuild.SIMS)


@pytest.mark.parametrize("width", WIDTHS)
@pytest.mark.parametrize("sim", SIMS)
def test_axis_skid_rtl(sim, width):
    pipe.run_block("axis_skid", sim, f"w{width}", {"DATA_W": width}, __file__, sources=SOURCES,
                   extra_env={"DATA_W": str(width)})


def _val(sig, what):
    v = sig.value
    assert v.is_resolvable, f"{what}: {sig._name} = {v} (X or Z)"
    return int(v)


@cocotb.test()
async def stream_with_gaps_and_stalls(dut):
    w = int(os.environ["DATA_W"])
    seed = int(os.environ.get("SEED", "1"))
    rr = random.Random(seed)
    n = int(os.environ.get("VECTORS", "2000"))
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    dut.rst.value = 1
    dut.s_axis_tvalid.value = 0
    dut.s_axis_tdata.value = 0
    dut.s_axis_tlast.value = 0
    dut.m_axis_tready.value = 0
    for _ in range(3):
        await RisingEdge(dut.clk)
    await ReadOnly()
    for sig in (dut.m_axis_tvalid, dut.m_axis_tdata, dut.m_axis_tlast, dut.s_axis_tready):
        assert _val(sig, "in reset") == 0, f"{sig._name} not 0 in reset"
    await Timer(1, unit="ns")
    dut.rst.value = 0

    # phases: (beats, gap probability, stall probability)
    phases = [(n // 8, 0.0, 0.0), (n // 4, 0.3, 0.3), (n // 8, 0.0, 0.8), (n // 8, 0.8, 0.0),
              (n // 4, 0.5, 0.5), (n // 8, 0.0, 0.0)]
    sent, got = [], []
    beats = [(rr.getrandbits(w), rr.getrandbits(1)) for _ in range(sum(p[0] for p in phases))]
    # each beat's phase, for the probabilities of the clock it is offered in
    phase_of = [k for k, p in enumerate(phases) for _ in range(p[0])]
    i = 0            # next beat to offer
    holding = False  # a beat offered and not yet accepted: held unchanged
    prev = None      # (m_valid, m_ready, m_data, m_last) of the last clock
    full_rate_run = 0
    cycles = 0
    while len(got) < len(beats):
        await RisingEdge(dut.clk)
        await ReadOnly()
        cycles += 1
        assert cycles < 20 * len(beats) + 100, "the skid buffer stopped passing beats"
        m_valid = _val(dut.m_axis_tvalid, f"clock {cycles}")
        m_data = _val(dut.m_axis_tdata, f"clock {cycles}")
        m_last = _val(dut.m_axis_tlast, f"clock {cycles}")
        s_ready = _val(dut.s_axis_tready, f"clock {cycles}")
        held = len(sent) - len(got)
        assert s_ready == (held < 2), f"clock {cycles}: s_axis_tready {s_ready} with {held} beats held"
        if prev is not None and prev[0] and not prev[1]:
            assert m_valid, f"clock {cycles}: m_axis_tvalid dropped while stalled"
            assert (m_data, m_last) == prev[2:], (f"clock {cycles}: data/last changed while stalled: "
                                                  f"{prev[2]:#x}/{prev[3]} -> {m_data:#x}/{m_last}")
        await Timer(1, unit="ns")
        k = phase_of[min(i, len(beats) - 1)]
        _, gap_p, stall_p = phases[k]
        # source: offer a beat (or keep offering the one held)
        if not holding and i < len(beats) and rr.random() >= gap_p:
            holding = True
        dut.s_axis_tvalid.value = int(holding)
        if holding:
            dut.s_axis_tdata.value, dut.s_axis_tlast.value = beats[i]
        else:
            dut.s_axis_tdata.value = rr.getrandbits(w)  # junk, never to be taken
            dut.s_axis_tlast.value = rr.getrandbits(1)
        m_ready = int(rr.random() >= stall_p) if i < len(beats) else int(rr.random() < 0.7)
        dut.m_axis_tready.value = m_ready
        await Timer(1, unit="ns")
        assert _val(dut.s_axis_tready, "") == s_ready, f"clock {cycles}: s_axis_tready followed m_axis_tready"
        # the handshakes of the coming edge
        if holding and s_ready:
            sent.append(beats[i])
            i += 1
            holding = False
        if m_valid and m_ready:
            got.append((m_data, m_last))
        # full rate: no gaps and no stalls: a beat out on every clock once the first is through
        if gap_p == 0 and stall_p == 0 and i < len(beats) and phase_of[i] == k and k in (0, 5):
            full_rate_run = full_rate_run + 1 if (m_valid and m_ready and s_ready) else 0
        prev = (m_valid, m_ready, m_data, m_last)
    assert got == axis_skid(sent), "beats lost, duplicated, reordered or changed"
    assert sent == beats
    assert full_rate_run >= min(phases[5][0], phases[0][0]) - 4, f"full rate not reached: run {full_rate_run}"
    dut._log.info(f"DATA_W {w}: {len(beats)} beats in {cycles} clocks, in order")
