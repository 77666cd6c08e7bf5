"""noise_hash (combinational): the 8 corner lattice values of a cell, bit-exact against
model/hw/golden.py noise_hash at (ix + i, iy + j, iz + k) mod 2^hash_bits.

Coverage scales with VECTORS (budget 2 * VECTORS cells): every cell when 2^(3 hash_bits)
fits the budget; otherwise every (iy, iz) for fixed ix in
{0, 2^H - 1} when that fits, else a random sample of them; the rest random cells, plus
the edges iy, iz in {0, 2^H - 1} (the +1 corners wrap) for every ix.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import cocotb
from cocotb.triggers import Timer

import hdlbuild
from model.hw import golden as G
from tb import pipe


@pytest.mark.parametrize("sim,config", hdlbuild.sim_params())
def test_noise_hash_rtl(sim, config):
    hdlbuild.run("noise_hash", sources=["noise_hash.v"], test_module="test_noise_hash", sim=sim, config=config,
                  test_dir=Path(__file__).parent)


def cells(cfg, r, budget):
    H = cfg.hash_bits
    n = 1 << H
    m = n - 1
    if n ** 3 <= budget:
        g = np.stack(np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij"), -1).reshape(-1, 3)
        return g.astype(np.int64), "every cell"
    parts = []
    # edges: iy, iz in {0, m} for every ix
    e = np.array([0, m])
    parts.append(np.stack(np.meshgrid(np.arange(n), e, e, indexing="ij"), -1).reshape(-1, 3))
    fixed = np.array([0, m])
    if 2 * n * n <= budget:
        parts.append(np.stack(np.meshgrid(fixed, np.arange(n), np.arange(n), indexing="ij"), -1).reshape(-1, 3))
        how = "every (iy, iz) for ix in {0, max}"
    else:
        k = budget // 4
        parts.append(np.stack([r.choice(fixed, k), r.integers(0, n, k), r.integers(0, n, k)], -1))
        how = "sampled (iy, iz) for ix in {0, max}"
    used = sum(len(p) for p in parts)
    k = max(budget - used, 0)
    parts.append(r.integers(0, n, (k, 3)))
    return np.concatenate(parts).astype(np.int64), how + " + random cells"


@cocotb.test()
async def corners_bit_exact(dut):
    cfg = pipe.cfg()
    H = cfg.hash_bits
    m = (1 << H) - 1
    c, how = cells(cfg, pipe.rng(7), 2 * pipe.n_vectors())
    exp = np.stack([G.noise_hash(cfg, (c[:, 0] + i) & m, (c[:, 1] + j) & m, (c[:, 2] + k) & m)
                    for i in (0, 1) for j in (0, 1) for k in (0, 1)], -1)
    dut._log.info(f"{cfg.name}: {len(c)} cells ({how})")
    got = np.zeros_like(exp)
    for t, (x, y, z) in enumerate(c.tolist()):
        dut.ix.value = x
        dut.iy.value = y
        dut.iz.value = z
        await Timer(1, unit="ns")
        got[t] = pipe.unpack(int(dut.v_out.value), cfg.n_w, 8)
    bad = np.flatnonzero((got != exp).any(axis=1))
    for t in bad[:10]:
        dut._log.error(f"cell {c[t].tolist()}: expected {exp[t].tolist()}, got {got[t].tolist()}")
    assert len(bad) == 0, f"{len(bad)} of {len(c)} cells differ from golden noise_hash"
