"""The cocotb side of the frame harness sim/frame_tb.v under Icarus: runs inside the simulator,
started by sim/frame_rtl.py (run_segments), never collected by pytest. (Under Verilator the
harness has a C++ main instead, sim/frame_main.cpp, that does the same.)

The tests `frame_run` and `frame_reset` only start the clock, reset, wait for the harness's
`done` and check the harness's own protocol counters (tlast, spurious outputs, X); every
pixel is driven and captured in Verilog, never from Python, and a run of several passes
wakes Python once. sim/frame_rtl.py passes the run's files and counts in the environment:
FRAME_NPIX (the pixels of all its passes), FRAME_TIMEOUT_CYCLES, FRAME_STATS, FRAME_OUT,
FRAME_PYSTATS and (frame_reset) FRAME_RESET_AT.
"""
from __future__ import annotations

import os
import time
from pathlib import Path

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, FallingEdge, RisingEdge, SimTimeoutError, with_timeout

from sim.frame_rtl import check_stats, read_stats


def _outputs_resolve(dut, what: str):
    """Every output of texture_pipeline is 0/1 (no X/Z): its value converts to an int.

    frame_tb's wires m_tdata, m_tvalid, m_tlast, s_tready are u_pipe's m_axis_tdata,
    m_axis_tvalid, m_axis_tlast, s_axis_tready."""
    vals = {}
    for name in ("m_tdata", "m_tvalid", "m_tlast", "s_tready"):
        v = getattr(dut, name).value
        try:
            vals[name] = int(v)
        except ValueError:
            raise AssertionError(f"{what}: {name} = {v} is not a resolved value") from None
    return vals


async def _reset(dut, cycles: int = 4):
    dut.rst.value = 1
    await ClockCycles(dut.clk, cycles)
    await FallingEdge(dut.clk)
    vals = _outputs_resolve(dut, "right after reset")
    assert vals["m_tvalid"] == 0, "m_axis_tvalid set during reset"
    assert vals["m_tdata"] == 0 and vals["m_tlast"] == 0, f"output registers not reset: {vals}"
    dut.rst.value = 0


async def _finish(dut, t0: float):
    timeout = int(os.environ.get("FRAME_TIMEOUT_CYCLES", "10000000"))
    try:
        await with_timeout(RisingEdge(dut.done), timeout * 10, "ns")
    except SimTimeoutError:
        raise AssertionError(
            f"harness not done after {timeout} clocks: {int(dut.out_idx.value)} of {os.environ['FRAME_NPIX']} "
            f"colours received (state {int(dut.state_reg.value)}): pixels lost or the pipeline stopped"
        ) from None
    wall = time.perf_counter() - t0
    npix = int(os.environ["FRAME_NPIX"])
    st = read_stats(os.environ["FRAME_STATS"])
    Path(os.environ["FRAME_PYSTATS"]).write_text(f"stream_wall_us {int(wall * 1e6)}\n")
    why = check_stats(st, npix, int(os.environ["FRAME_NWR"]))
    assert why is None, why
    n_out = sum(1 for line in Path(os.environ["FRAME_OUT"]).read_text().splitlines()
                if line.split("//", 1)[0].strip())
    assert n_out == npix, f"{n_out} colours in the output file, expected {npix}"
    dut._log.info(
        "frame: %d pixels, %d stream cycles (%.3f px/clk), %.3f s wall, %.0f px/s",
        npix, st["stream_cycles"], npix / max(st["stream_cycles"], 1), wall, npix / max(wall, 1e-9),
    )


@cocotb.test()
async def frame_run(dut):
    """Clock, reset, wait for the harness to load, stream and write the frame."""
    Clock(dut.clk, 10, unit="ns", impl="gpi").start()
    await _reset(dut)
    await _finish(dut, time.perf_counter())


@cocotb.test()
async def frame_reset(dut):
    """Reset in the middle of the frame; the harness reloads and streams again from pixel 0."""
    Clock(dut.clk, 10, unit="ns", impl="gpi").start()
    await _reset(dut)
    await ClockCycles(dut.clk, int(os.environ["FRAME_RESET_AT"]))
    await FallingEdge(dut.clk)
    out_idx, npix = int(dut.out_idx.value), int(os.environ["FRAME_NPIX"])
    assert int(dut.state_reg.value) == 1 and 0 < out_idx < npix, (
        f"reset not in the middle of the stream (state {int(dut.state_reg.value)}, {out_idx} of {npix} out)"
    )
    dut._log.info("reset after %d of %d colours", out_idx, npix)
    await _reset(dut, cycles=3)
    await _finish(dut, time.perf_counter())
