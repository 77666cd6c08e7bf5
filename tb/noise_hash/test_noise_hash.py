"""noise_hash (combinational, or PIPE register stages): the 8 corner lattice values of a
cell, bit-exact against model/hw/golden.py noise_hash at (ix + i, iy + j, iz + k) mod 2^hash_bits.

Coverage scales with VECTORS (budget 2 * VECTORS cells): every cell when 2^(3 hash_bits)
fits the budget; otherwise every (iy, iz) for fixed ix in
{0, 2^H - 1} when that fits, else a random sample of them; the rest random cells, plus
the edges iy, iz in {0, 2^H - 1} (the +1 corners wrap) for every ix.
Parameter sets: full and reduced (test_noise_hash_rtl), and random valid configurations
plus the smallest and widest lattice (test_noise_hash_family_rtl: other H, N_FRAC, PERM), and
full's and reduced's hash with PIPE = 1 and 2 (test_noise_hash_pipe_rtl: streamed with random ce
stalls, each result read PIPE enabled clocks after its cell; the outputs hold while ce = 0).
"""
from __future__ import annotations

import os

import numpy as np
import pytest

import cocotb

import hdlbuild
from model.hw import golden as G
from model.hw.config import ROOT, load_config, random_config, variant
from tb import pipe

SOURCES = ["noise_hash.v", "delay_line.v"]


@pytest.mark.parametrize("sim,config", hdlbuild.sim_params())
def test_noise_hash_rtl(sim, config):
    pipe.run_block("noise_hash", sim, test_file=__file__, config=config, sources=SOURCES)


def _family():
    """(sim, Config): random valid configurations (their H, N_FRAC, N_W and PERM), the
    smallest lattice (H = 2, N_FRAC = 2) and the widest (H = 10, N_FRAC = 16); Verilator
    builds only the first random one."""
    # full_narrow (full's formats until issue 26): its fixed-point a takes N_FRAC = 2, full's exponents do not
    full = load_config(str(ROOT / "config" / "candidates" / "full_narrow.toml"))
    cfgs = [random_config(s) for s in (1281, 1282, 1283, 1284)]
    cfgs += [variant(full, "hash_small", hash_bits=2, n_frac=2), variant(full, "hash_wide", hash_bits=10, n_frac=16)]
    sims = [os.environ["SIM"]] if os.environ.get("SIM") else list(hdlbuild.SIMS)
    return [pytest.param(sim, c, id=f"{sim}-{c.name}") for sim in sims for i, c in enumerate(cfgs)
            if sim == "icarus" or i == 0]


@pytest.mark.parametrize("sim,cfg", _family())
def test_noise_hash_family_rtl(sim, cfg):
    pipe.run_block("noise_hash", sim, test_file=__file__, config=cfg, sources=SOURCES)


def _pipes():
    """(sim, config, PIPE): full's and reduced's hash pipelined (Icarus both; Verilator PIPE = 2 of full)."""
    sims = [os.environ["SIM"]] if os.environ.get("SIM") else list(hdlbuild.SIMS)
    return [pytest.param(sim, c, k, id=f"{sim}-{c}-pipe{k}") for sim in sims for c in ("full", "reduced")
            for k in (1, 2) if sim == "icarus" or (c, k) == ("full", 2)]


@pytest.mark.parametrize("sim,config,pipe_stages", _pipes())
def test_noise_hash_pipe_rtl(sim, config, pipe_stages):
    params = {**hdlbuild.block_params(load_config(config), "noise_hash"), "PIPE": pipe_stages}
    pipe.run_block("noise_hash", sim, f"{config}-pipe{pipe_stages}", params, __file__, config=config,
                   sources=SOURCES)


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
    stages = pipe.block_params().get("PIPE", 0)
    cl = c.tolist()

    def apply(t):
        dut.ix.value, dut.iy.value, dut.iz.value = cl[t]

    def sample():
        return pipe.unpack(int(dut.v_out.value), cfg.n_w, 8)

    if stages == 0:
        got = np.array(await pipe.run_comb(dut, apply, sample, len(cl)), dtype=np.int64).reshape(exp.shape)
    else:
        await pipe.start(dut, reset=False, valid=False)
        got = np.array(await pipe.run_stream(dut, apply, sample, len(cl), stages), dtype=np.int64).reshape(exp.shape)
        how += f", PIPE = {stages} (streamed, ce stalls)"
    dut._log.info(f"{cfg.name}: {len(c)} cells ({how})")
    bad = np.flatnonzero((got != exp).any(axis=1))
    for t in bad[:10]:
        dut._log.error(f"cell {c[t].tolist()}: expected {exp[t].tolist()}, got {got[t].tolist()}")
    assert len(bad) == 0, f"{len(bad)} of {len(c)} cells differ from golden noise_hash"
