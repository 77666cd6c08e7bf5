"""fc_scale (filter "sat_fc"): bit-exact against model/hw/golden.py fc_scale, every output bit.

Stimulus: random a_i n_i and gradient words over their whole range, with alpha uniform in
[0, 2^AF], plus the hard cases: alpha 0, 1 and 2^AF (the term unchanged), the words' most
negative and largest values, -1 (the floor of a negative product), streamed with stalls and
gaps; with the noise gradient off the gradient output must be 0 whatever comes in.
"""
from __future__ import annotations

import os

import numpy as np
import pytest

import cocotb

import hdlbuild
from model.hw import golden as G
from tb import pipe
from tb.fc_weight.test_fc_weight import fc_variant

CASES = [(s, c) for s in hdlbuild.SIMS for c in (("full", "reduced", "random:7") if s == "icarus" else ("full",))
         if not os.environ.get("SIM") or os.environ["SIM"] == s]


@pytest.mark.parametrize("sim,config", CASES)
def test_fc_scale_rtl(sim, config):
    pipe.run_block("fc_scale", sim, test_file=__file__, config=fc_variant(config))


@cocotb.test()
async def vectors_bit_exact(dut):
    cfg = pipe.cfg()
    r = pipe.rng(91)
    af, nw, gw = cfg.fc_af, cfg.an_w, cfg.ag_w
    n = pipe.n_vectors()
    an = r.integers(-(1 << (nw - 1)), 1 << (nw - 1), n)
    ag = r.integers(-(1 << (gw - 1)), 1 << (gw - 1), (n, 3))
    al = r.integers(0, (1 << af) + 1, n)
    hard_a = [0, 1, 1 << af, (1 << af) - 1]
    hard_n = [-(1 << (nw - 1)), (1 << (nw - 1)) - 1, -1, 0, 1]
    k = 0
    for a in hard_a:
        for v in hard_n:
            al[k], an[k] = a, v
            ag[k] = [-(1 << (gw - 1)), (1 << (gw - 1)) - 1, -1]
            k += 1
    exp_n, exp_g = G.fc_scale(cfg, al, an, ag)
    if not cfg.noise_gradient:
        exp_g = np.zeros_like(exp_g)
    await pipe.start(dut)

    def apply(i):
        dut.alpha.value = int(al[i])
        dut.an_in.value = int(an[i]) & ((1 << nw) - 1)
        dut.ag_in.value = pipe.pack(ag[i], gw)

    def sample():
        return int(dut.an_out.value), int(dut.ag_out.value)

    got = await pipe.run_vectors(dut, apply, sample, n, hdlbuild.latency("fc_scale"), seed=3)
    for i, (gn, gg) in enumerate(got):
        assert pipe.to_signed(gn, nw) == int(exp_n[i]) and pipe.unpack(gg, gw, 3) == [int(x) for x in exp_g[i]], (
            f"vector {i}: alpha {al[i]} an {an[i]} ag {ag[i].tolist()}: got {pipe.to_signed(gn, nw)} "
            f"{pipe.unpack(gg, gw, 3)}, expected {int(exp_n[i])} {exp_g[i].tolist()}")
    dut._log.info(f"{n} vectors bit-exact")
