"""sum_tree (rtl/sum_tree.v) bit-exact against golden sum_tree(leaves, W), latency
model.hw.config.sum_tree_levels(N) (`SUM_TREE_ARITY, rtl/tex_latency.vh).

Parameter sets (N, W, LANES): texture_pipeline's two trees under full, reduced, compact and
two random valid configurations (f: N = leaves, W = f_w, one lane; c: W = c_w, three lanes,
where the configuration has the noise gradient), and the shapes around the levels: N = 1
(a wire, latency 0), 4 (one full node), 5 (a node of one child), 16, 17 (three levels),
W = 2 and W = 62. Vectors: every leaf at -2^(W-1), -1, 0, 1, 2^(W-1) - 1 (all equal, and
alternating), then VECTORS leaves uniform over the word: the sums wrap modulo 2^W as the
twin's do (the tree is exact where the caller's W bounds the sum).
"""
from __future__ import annotations

import random

import numpy as np

import cocotb

from model.hw import golden as G
from model.hw.config import folded, sum_tree_levels
from tb import pipe


def _leaves(cfg) -> int:
    """texture_pipeline's leaves: the quadric and a leaf a term (noise_fold: one)."""
    return 1 + (1 if folded(cfg) else cfg.noise_terms)


def _sets():
    from model.hw.config import load_config

    out = {}
    for name, cfg in pipe.configs(1301, 1302) + [("compact", load_config("compact"))]:
        n = _leaves(cfg)
        out[f"{name}_f"] = {"N": n, "W": cfg.f_w, "LANES": 1, "LATENCY": sum_tree_levels(n)}
        if cfg.noise_gradient:
            out[f"{name}_c"] = {"N": n, "W": cfg.c_w, "LANES": 3, "LATENCY": sum_tree_levels(n)}
    for n, w, lanes in ((1, 9, 2), (4, 7, 1), (5, 11, 3), (16, 2, 1), (17, 62, 2)):
        out[f"n{n}_w{w}"] = {"N": n, "W": w, "LANES": lanes, "LATENCY": sum_tree_levels(n)}
    return out


# every set under Icarus; under Verilator (a build costs 5-20 s) the deepest and full's c tree
test_sum_tree_rtl = pipe.block_test("sum_tree", _sets(), ("n17_w62", "full_c"), __file__)


def test_sum_tree_check():
    """sum_tree's elaboration-time check (g_bad_params) both ways on the set n5_w11 (N 5 leaves of 3
    lanes, W 11, LATENCY 2 levels): refused with each term alone true (N 0 < 1, LATENCY its 0
    levels; W 0 < 1; LANES 0 < 1; LATENCY one above and one below the tree's levels); accepted at
    each edge (N 1, no level; W 1; LANES 1). (ARITY != 4 depends on rtl/tex_latency.vh alone
    (`SUM_TREE_ARITY): no parameter set makes it true.)"""
    import hdlbuild

    b = _sets()["n5_w11"]
    lv = sum_tree_levels(b["N"])
    hdlbuild.check_refusals(
        "sum_tree", ["sum_tree.v"], b,
        accept={"n5_w11": {}, "N 1": {"N": 1, "LATENCY": sum_tree_levels(1)}, "W 1": {"W": 1}, "LANES 1": {"LANES": 1}},
        refuse={"N < 1": {"N": 0, "LATENCY": sum_tree_levels(0)}, "W < 1": {"W": 0}, "LANES < 1": {"LANES": 0},
                "LATENCY > levels": {"LATENCY": lv + 1}, "LATENCY < levels": {"LATENCY": lv - 1}},
        error_module="sum_tree_latency_must_be_its_levels")


@cocotb.test()
async def sum_tree_bit_exact(dut):
    p = pipe.block_params()
    n, w, lanes, lat = p["N"], p["W"], p["LANES"], p["LATENCY"]
    r = pipe.rng(61)
    lo, hi = -(1 << (w - 1)), (1 << (w - 1)) - 1
    ext = [lo, -1, 0, 1, hi]
    edge = [np.full((n, lanes), e, dtype=np.int64) for e in ext]
    edge += [np.array([[ext[(i + j + k) % 5] for j in range(lanes)] for i in range(n)], dtype=np.int64)
             for k in range(5)]
    m = pipe.n_vectors()
    rand = r.integers(lo, hi + 1, (m, n, lanes), dtype=np.int64)
    v = np.concatenate([np.stack(edge), rand])  # [vector, leaf, lane]
    exp_l = G.sum_tree([v[:, i, :] for i in range(n)], w)  # [vector, lane]
    exp = [tuple(int(x) for x in row) for row in exp_l]
    words = [pipe.pack(v[t].reshape(-1), w) for t in range(len(v))]

    def apply(t):
        dut.leaves.value = words[t]

    def sample():
        return tuple(pipe.unpack(int(dut.sum_out.value), w, lanes))

    await pipe.start(dut)
    if lat == 0:  # a wire: the sum and the valid bit follow the inputs at once
        def apply_v(t):
            apply(t)
            dut.in_valid.value = t & 1

        def sample_v():
            assert int(dut.out_valid.value) == int(dut.in_valid.value), "N = 1: out_valid is not in_valid"
            return sample()

        got = await pipe.run_comb(dut, apply_v, sample_v, len(v))
    else:
        got = await pipe.run_vectors(dut, apply, sample, len(v), latency=lat, seed=random.Random(n * 131 + w).randint(0, 999))
    pipe.check_equal(dut, got, exp, lambda t: f"leaves={v[t].tolist()}", f"sum_tree {p}")
