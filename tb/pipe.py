"""cocotb helpers shared by the block testbenches.

Blocks are fixed-latency pipelines with a clock enable `ce` (all registers hold
while ce = 0), `in_valid` and `out_valid`. `run_vectors` streams vectors into a
block with random ce stalls (random gaps on the input side too), collects every
output in order, and checks the latency and the count: a lost, duplicated or
reordered vector fails the test.
"""
from __future__ import annotations

import os
import random

import numpy as np
import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ReadOnly, RisingEdge

from model.hw.config import load_config


def cfg():
    return load_config(os.environ.get("CONFIG", "full"))


def rng(salt: int = 0):
    return np.random.default_rng(int(os.environ.get("SEED", "1")) + salt)


def n_vectors(default: int = 2000) -> int:
    return int(os.environ.get("VECTORS", default))


def pack(values, width: int) -> int:
    """Pack a sequence of signed/unsigned ints, element 0 at the LSBs, each `width` bits."""
    m = (1 << width) - 1
    out = 0
    for i, v in enumerate(values):
        out |= (int(v) & m) << (i * width)
    return out


def unpack(word: int, width: int, count: int, signed: bool = True):
    m = (1 << width) - 1
    out = []
    for i in range(count):
        v = (int(word) >> (i * width)) & m
        if signed and v >> (width - 1):
            v -= 1 << width
        out.append(v)
    return out


def to_signed(v: int, width: int) -> int:
    v = int(v) & ((1 << width) - 1)
    return v - (1 << width) if v >> (width - 1) else v


async def start(dut, period_ns: int = 10):
    cocotb.start_soon(Clock(dut.clk, period_ns, unit="ns").start())
    dut.rst.value = 1
    dut.ce.value = 1
    dut.in_valid.value = 0
    for _ in range(3):
        await RisingEdge(dut.clk)
    dut.rst.value = 0
    await RisingEdge(dut.clk)


async def run_vectors(dut, apply, sample, n: int, latency: int, stall_prob: float = 0.2, gap_prob: float = 0.1,
                      seed: int = 0):
    """Stream n vectors: apply(i) drives vector i's inputs; sample() reads the outputs.

    Returns the list of n samples in order. ce drops with probability stall_prob
    per cycle, the input idles with probability gap_prob. Checks that every vector
    comes out after exactly `latency` enabled clock edges (= register stages: a
    vector sampled at enabled edge E is visible at the output after edge E+latency-1).
    """
    r = random.Random(seed)
    results = []
    issued = []  # enabled-cycle count at issue, per vector
    enabled = 0
    i = 0
    guard = 0
    while len(results) < n:
        ce = 1 if r.random() >= stall_prob else 0
        valid = 1 if (i < n and r.random() >= gap_prob) else 0
        if valid:
            apply(i)
        dut.ce.value = ce
        dut.in_valid.value = valid
        await RisingEdge(dut.clk)
        if ce:
            enabled += 1
            if valid:
                issued.append(enabled)
                i += 1
        await ReadOnly()
        if ce and int(dut.out_valid.value):
            k = len(results)
            assert k < len(issued), "out_valid with no vector in flight (duplicate or spurious output)"
            got_lat = enabled - issued[k] + 1  # register stages from input to output
            assert got_lat == latency, f"vector {k}: latency {got_lat}, expected {latency}"
            results.append(sample())
        guard += 1
        assert guard < 20 * (n + latency + 10), "pipeline stopped producing outputs"
        await _after_readonly(dut)
    dut.in_valid.value = 0
    return results


async def _after_readonly(dut):
    """Leave the read-only phase so the next iteration may drive inputs."""
    from cocotb.triggers import Timer

    await Timer(1, unit="ns")


async def run_batches(dut, batches, params, vectors, sample, latency: int, junk: dict, seed: int):
    """Stream vector batches that each hold one parameter set, draining between sets.

    batches: [(begin, end)] vector index ranges; params(b) drives the parameter inputs
    for the batch starting at b; vectors: {port name: list of packed words per vector};
    junk: {port name: width} of every input that gets unrelated random values for 0-3
    clocks with in_valid = 0 between batches (nothing may keep them). The pipeline is
    empty when run_vectors returns, so parameters change only between passes, as
    texture_pipeline guarantees. Returns all samples in order.
    """
    ri = random.Random(seed + 7)
    got = []
    for k, (b, e) in enumerate(batches):
        dut.in_valid.value = 0
        for _ in range(ri.randint(0, 3)):
            dut.ce.value = ri.randint(0, 1)
            for name, width in junk.items():
                getattr(dut, name).value = ri.getrandbits(width)
            await RisingEdge(dut.clk)
        params(b)

        def apply(i, b=b):
            for name, words in vectors.items():
                getattr(dut, name).value = words[b + i]

        got += await run_vectors(dut, apply, sample, e - b, latency=latency, seed=seed * 100003 + k)
    return got
