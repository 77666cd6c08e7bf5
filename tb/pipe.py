"""cocotb helpers shared by the block testbenches, and their pytest side.

Blocks are fixed-latency pipelines with a clock enable `ce` (all registers hold
while ce = 0), `in_valid` and `out_valid`. `run_vectors` streams vectors into a
block with random ce stalls (random gaps on the input side too), collects every
output in order, and checks the latency and the count: a lost, duplicated or
reordered vector fails the test. `run_stream` does the same for an internal stage
without valid bits (sat_index, sat_integral, mip_index, colour_table), `run_comb`
for a combinational block.

Parameter sweeps (the verilog-axis habit): `block_cases(sets, verilator)` is the
pytest parametrization (sim, set name, parameters) over named HDL parameter sets,
every set under Icarus and the `verilator` ones under Verilator too; `run_block` builds
one set (or a configuration's own parameters) in its own build directory and hands it to the
cocotb side, where `block_params()` reads it back; `block_test` is the whole pytest entry.
Every block testbench launches through `run_block` (directly from its own parametrized
pytest function, over configurations from hdlbuild.sim_params / family_params, or through
`block_test`); none calls hdlbuild.run itself.
"""
from __future__ import annotations

import json
import os
import random
from pathlib import Path

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


def pack_a_all(cfg, a, ae) -> int:
    """The terms' amplitudes as texture_pipeline's a_all: term k's {ae_k, a_k} at k (a_w + a_exp_w)
    (the exponent above the mantissa; none with a_exp_w = 0: tex_regs' layout)."""
    return pack([(int(ae_k) << cfg.a_w) | (int(a_k) & ((1 << cfg.a_w) - 1)) for a_k, ae_k in zip(a, ae)],
                cfg.a_w + cfg.a_exp_w)


def pack_t_all(cfg, T, te) -> int:
    """The terms' transforms as texture_pipeline's t_all: term k's {te_k, T_k} at k (9 t_w + t_exp_w),
    T_k[j][m] at (3 j + m) t_w in it."""
    return pack([(int(te_k) << (9 * cfg.t_w)) | pack(np.asarray(T_k).reshape(-1), cfg.t_w) for T_k, te_k in zip(T, te)],
                9 * cfg.t_w + cfg.t_exp_w)


def rand_exp(rng, e_max: int) -> int:
    """A term's exponent: 0, the largest, or uniform in 0..e_max, equally likely (0 without exponents)."""
    return 0 if not e_max else (0, e_max, int(rng.integers(0, e_max + 1)))[int(rng.integers(0, 3))]


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


async def start(dut, period_ns: int = 10, reset: bool = True, valid: bool = True):
    """Start the clock, ce = 1; reset: pulse rst; valid: in_valid = 0 (blocks without
    rst or in_valid pass False)."""
    cocotb.start_soon(Clock(dut.clk, period_ns, unit="ns").start())
    if reset:
        dut.rst.value = 1
    dut.ce.value = 1
    if valid:
        dut.in_valid.value = 0
    for _ in range(3):
        await RisingEdge(dut.clk)
    if reset:
        dut.rst.value = 0
    await RisingEdge(dut.clk)


async def run_comb(dut, apply, sample, n: int):
    """A combinational block: apply(i), settle, sample(), for i < n; the samples in order."""
    from cocotb.triggers import Timer

    out = []
    for i in range(n):
        apply(i)
        await Timer(1, unit="ns")
        out.append(sample())
    return out


async def run_stream(dut, apply, sample, n: int, latency: int, stall_prob: float = 0.2, seed: int = 0):
    """A pipeline stage without valid bits (registers that advance with ce): vector i is
    applied for the i-th enabled clock edge and its result read `latency` enabled edges
    later; ce drops with probability stall_prob, and while it is low the outputs must hold.
    Returns the n samples in order (a wrong latency misaligns them: the comparison fails)."""
    r = random.Random(seed)
    results = []
    enabled = 0
    prev = None
    while len(results) < n:
        ce = 1 if r.random() >= stall_prob else 0
        apply(min(enabled, n - 1))
        dut.ce.value = ce
        await RisingEdge(dut.clk)
        await ReadOnly()
        enabled += ce
        if enabled >= latency:  # the registers hold a vector (before: X, not read)
            now = sample()
            if ce:
                results.append(now)
            elif prev is not None:
                assert now == prev, f"outputs changed while ce = 0 (after vector {enabled - latency})"
            prev = now
        await _after_readonly(dut)
    return results


def configs(*seeds, colour_edges: bool = False):
    """[(name, Config)] to derive block parameter sets from: full, reduced, random_config(seed)
    for each seed, and with colour_edges the extremes of the colour-map formats: "small"
    (n_log2_max = 1, w_cap_log2 = 1, f_frac = 8: the smallest tables and words) and "wide"
    (n_log2_max = 10, w_cap_log2 = 14, f_frac = 20)."""
    from model.hw.config import random_config, variant

    full = load_config("full")
    out = [("full", full), ("reduced", load_config("reduced"))]
    out += [(f"random{s}", random_config(s)) for s in seeds]
    if colour_edges:
        out += [("small", variant(full, "small", n_log2_max=1, w_cap_log2=1, f_frac=8, div_bits=0)),
                ("wide", variant(full, "wide", n_log2_max=10, w_cap_log2=14, f_frac=20, div_bits=0))]
    return out


def exponent_configs(*seeds):
    """[(name, Config)] with per-term exponents (formats.t_exp_w, a_exp_w; docs/numerics.md "Block
    floating point"), for the blocks that take them: full_bfp (config/candidates/full_bfp.toml),
    "full_exp" (full_narrow, full's formats until issue 26, with t_exp_w = 1 and a_exp_w = 2: the exponents as wide as its shifts allow,
    te_max = TS_SHIFT and ae_max = AN_SHIFT, so the largest exponent leaves a shift of 0), and per
    seed "exp<seed>": random_config(seed) (redrawn with seed + 1000 k until both exponents fit) made
    affine with amplitude any, with the widest exponents (at most 3 bits) its shifts allow."""
    from model.hw.config import ROOT, ConfigError, random_config, variant

    def widest(limit: int) -> int:
        return max((e for e in range(4) if (1 << e) - 1 <= limit), default=0)

    out = [("full_bfp", load_config(str(ROOT / "config" / "candidates" / "full_bfp.toml"))),
           ("full_exp", variant(load_config(str(ROOT / "config" / "candidates" / "full_narrow.toml")), "full_exp",
                                t_exp_w=1, a_exp_w=2))]
    for seed in seeds:
        for k in range(100):
            c = random_config(seed + 1000 * k)
            te = widest(min(c.s_frac + c.t_frac - c.p_frac, c.n_frac + c.t_frac - c.c_frac))
            ae = widest(min(c.a_frac + c.n_frac - c.f_frac, c.a_frac))
            if te and ae:
                try:
                    out.append((f"exp{seed}", variant(c, f"exp{seed}", transform="affine", amplitude="any",
                                                      t_exp_w=te, a_exp_w=ae)))
                    break
                except ConfigError:
                    continue
        else:
            raise ConfigError(f"exponent_configs: no configuration with exponents from seed {seed}")
    return out


def block_params() -> dict:
    """The HDL parameters the block under test was built with (run_block)."""
    return json.loads(os.environ["BLOCK_PARAMS"])


def block_cases(sets: dict, verilator=()):
    """pytest parameters (sim, name, params): every set of `sets` ({name: {PARAM: value}})
    under Icarus, the sets named in `verilator` under Verilator too (a Verilator build costs
    5-20 s, an Icarus one about 1 s); SIM= narrows."""
    import pytest

    sims = [os.environ["SIM"]] if os.environ.get("SIM") else ["icarus", "verilator"]
    return [pytest.param(sim, name, params, id=f"{sim}-{name}") for sim in sims for name, params in sets.items()
            if sim == "icarus" or name in verilator]


def block_test(module: str, sets: dict, verilator, test_file: str, **run_kw):
    """The pytest entry of a block testbench: test_<module>_rtl = block_test(...) runs the
    cocotb tests of `test_file` on every parameter set (block_cases, run_block). run_kw are
    run_block's keywords; a dict `config` gives each set its own configuration ({set name:
    configuration}: cfg() on the cocotb side, for a block whose twin reads a whole Config)."""
    import pytest

    @pytest.mark.parametrize("sim,name,params", block_cases(sets, verilator))
    def test(sim, name, params):
        kw = {**run_kw, **({"config": run_kw["config"][name]} if isinstance(run_kw.get("config"), dict) else {})}
        run_block(module, sim, name, params, test_file, **kw)

    return test


def run_block(module: str, sim: str, name: str | None = None, params: dict | None = None, test_file: str = "",
              config="full", sources=None, extra_env=None) -> None:
    """The one way a block testbench launches: build `module` (rtl/<module>.v, or `sources`)
    under `sim` with the HDL parameters `params` (None: the configuration's,
    hdlbuild.block_params) in build/sim/<module>/<name>-...-<sim> (name None: the
    configuration's name) and run the cocotb tests of `test_file` (the testbench's own
    __file__) on it. `config` (a name, "random:<seed>", "fpga_regs:<name>" or a Config) is the
    configuration the cocotb side reads (cfg()); block_params() there gives `params`;
    extra_env adds variables of the testbench's own."""
    import hdlbuild

    if not test_file:
        raise TypeError("run_block: test_file (the testbench's __file__) is required")
    test = Path(test_file)
    cfg = hdlbuild.config_of(config)
    if params is None:
        params = hdlbuild.block_params(cfg, module)
    hdlbuild.run(module, sources=sources or [f"{module}.v"], test_module=test.stem, sim=sim, config=cfg,
                 parameters=params, build_name=name, test_dir=test.parent,
                 extra_env={"BLOCK_PARAMS": json.dumps(params), **(extra_env or {})})


async def run_vectors(dut, apply, sample, n: int, latency: int, stall_prob: float = 0.2, gap_prob: float = 0.1,
                      seed: int = 0, spacing: int = 1):
    """Stream n vectors: apply(i) drives vector i's inputs; sample() reads the outputs.

    Returns the list of n samples in order. ce drops with probability stall_prob
    per cycle, the input idles with probability gap_prob. Checks that every vector
    comes out after exactly `latency` enabled clock edges (= register stages: a
    vector sampled at enabled edge E is visible at the output after edge E+latency-1).
    spacing: a vector enters at most every `spacing` enabled clocks (a block that takes
    several clocks a vector, quadric_mac CLOCKS = 2).
    """
    r = random.Random(seed)
    results = []
    issued = []  # enabled-cycle count at issue, per vector
    enabled = 0
    i = 0
    guard = 0
    while len(results) < n:
        ce = 1 if r.random() >= stall_prob else 0
        valid = 1 if (i < n and r.random() >= gap_prob and (not issued or enabled + 1 - issued[-1] >= spacing)) else 0
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


async def run_batches(dut, batches, params, vectors, sample, latency: int, junk: dict, seed: int,
                      spacing: int = 1):
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

        got += await run_vectors(dut, apply, sample, e - b, latency=latency, seed=seed * 100003 + k, spacing=spacing)
    return got


def check_equal(dut, got, exp, describe, what: str) -> None:
    """Assert got == exp element by element (sequences of ints or tuples); log the first
    ten differences with describe(i), the vector's inputs."""
    exp = [tuple(e) if np.ndim(e) else int(e) for e in exp]
    got = [tuple(g) if np.ndim(g) else int(g) for g in got]
    assert len(got) == len(exp), f"{what}: {len(got)} results for {len(exp)} vectors"
    bad = [i for i in range(len(exp)) if got[i] != exp[i]]
    for i in bad[:10]:
        dut._log.error(f"vector {i}: {describe(i)}: expected {exp[i]}, got {got[i]}")
    assert not bad, f"{what}: {len(bad)} of {len(exp)} vectors differ (first at {bad[0] if bad else None})"
    dut._log.info(f"{what}: {len(exp)} vectors bit-exact")
