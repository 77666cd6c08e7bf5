"""box_divide (rtl/box_divide.v) against Python integer division, bit for bit.

Two halves in one file (the project's testbench convention):
- pytest entry `test_box_divide_rtl` over (simulator, configuration): the divider is built
  with its defaults, the widths colour_map's exact division uses (NUM_W = D_W - 1,
  DEN_W = W_W, Q_W = 8, LANES = 4 numerators sharing one divisor);
- pytest entry `test_box_divide_narrow_rtl`: the normalised division's widths (divisor of
  B = div_bits bits, NUM_W = B + 8; docs/numerics.md "Colour map") for each configuration
  with div_bits > 0, and the saturating build (SAT = 1, NUM_W = B + 9) that colour_map uses
  for div_bits <= 9, at B = 9 and B = 4;
- pytest entry `test_box_divide_random_rtl`: random configurations' dividers, a 1- and a 2-bit
  divisor with SAT, and SAT with NUM_W <= Q_W (sat_narrow: no quotient saturates, the
  overflow compare is not built);
- cocotb test `box_divide_vs_python`: random divisors (uniform over the whole DEN_W range
  and log-uniform) with random numerators meeting the precondition num < den 2^Q_W
  (SAT: num < den 2^(Q_W+1)), then the edge cases: den = 1, den at its maximum, den = 2^k
  and 2^k - 1, quotients 0, 1, 2^Q_W - 1 (SAT: also 2^Q_W, 2^Q_W + 1, 3 2^(Q_W-1), the
  largest) and every exact multiple boundary (num = q den - 1, q den, q den + 1), num at
  its maximum (den = 0 is outside the precondition: colour_map never divides by 0);
  streamed with random ce stalls and input gaps. Expected: num // den per lane (SAT:
  saturated to 2^Q_W - 1).

Environment: SIM, CONFIG narrow the parametrization; SEED fixes the randomness;
VECTORS = random vectors (default 2000; edge cases come on top). BD_NUM_W, BD_DEN_W, BD_SAT
(set by the pytest entries) give the parameters the divider was built with.
"""
from __future__ import annotations

import os
import random

import pytest

import cocotb

import hdlbuild
from model.hw.config import load_config
from tb import pipe

Q_W, LANES = 8, 4  # box_divide's defaults, as colour_map instantiates it


def widths(cfg):
    """NUM_W, DEN_W, SAT the divider was built with (default: box_divide's defaults)."""
    num_w = int(os.environ.get("BD_NUM_W", cfg.d_w - 1))
    den_w = int(os.environ.get("BD_DEN_W", cfg.w_w))
    return num_w, den_w, int(os.environ.get("BD_SAT", 0))


def model(num: int, den: int, sat: int = 0) -> int:
    return min(num // den, (1 << Q_W) - 1) if sat else num // den


def limit(den: int, num_w: int, sat: int) -> int:
    """Numerators below this meet the precondition and fit the numerator word."""
    return min(den << (Q_W + (1 if sat else 0)), 1 << num_w)


def random_cases(r: random.Random, n: int, num_w: int, den_w: int, sat: int = 0):
    out = []
    for _ in range(n):
        if r.random() < 0.5:
            den = r.randrange(1, 1 << den_w)
        else:
            den = r.randrange(1, 1 << r.randint(1, den_w))
        lim = limit(den, num_w, sat)  # precondition and the numerator word
        nums = []
        for _ in range(LANES):
            x = r.random()
            if x < 0.6:
                nums.append(r.randrange(lim))
            elif x < 0.8:  # near a multiple of den
                q = r.randrange(lim // den + 1)
                nums.append(min(max(q * den + r.randint(-2, 2), 0), lim - 1))
            else:  # small numerators
                nums.append(r.randrange(min(lim, 1 << r.randint(1, num_w))))
        out.append((nums, den))
    return out


def edge_cases(r: random.Random, num_w: int, den_w: int, sat: int = 0):
    qmax = (1 << Q_W) - 1
    dens = {1, 2, 3, (1 << den_w) - 1, 1 << (den_w - 1), (1 << (den_w - 1)) - 1, (1 << (den_w - 1)) + 1}
    dens |= {1 << k for k in range(den_w)} | {(1 << k) - 1 for k in range(2, den_w)}
    qs = (1, 2, 127, 128, 254, 255) + ((256, 257, 383, 384, 511) if sat else ())
    out = []
    for den in sorted(d for d in dens if 0 < d < 1 << den_w):
        lim = limit(den, num_w, sat)
        cand = {0, 1, den - 1, den, den + 1, lim - 1, (qmax * den) - 1, qmax * den, qmax * den + 1,
                (den << (Q_W - 1)) - 1, den << (Q_W - 1), (1 << num_w) - 1}
        cand |= {q * den + d for q in qs for d in (-1, 0, 1)}
        cand = sorted(c for c in cand if 0 <= c < lim)
        for i in range(0, len(cand), LANES):
            nums = cand[i:i + LANES]
            nums += [r.randrange(lim) for _ in range(LANES - len(nums))]
            out.append((nums, den))
    return out


@cocotb.test()
async def box_divide_vs_python(dut):
    cfg = pipe.cfg()
    num_w, den_w, sat = widths(cfg)
    assert len(dut.num_in) == LANES * num_w and len(dut.den_in) == den_w, "unexpected box_divide widths"
    seed = int(pipe.rng(23).integers(1 << 30))
    r = random.Random(seed)
    cases = random_cases(r, pipe.n_vectors(), num_w, den_w, sat) + edge_cases(r, num_w, den_w, sat)
    r.shuffle(cases)
    await pipe.start(dut)
    assert dut.out_valid.value.is_resolvable and int(dut.out_valid.value) == 0, "out_valid after reset"
    assert dut.q_out.value.is_resolvable and int(dut.q_out.value) == 0, "q_out after reset"

    def apply(i):
        nums, den = cases[i]
        dut.num_in.value = pipe.pack(nums, num_w)
        dut.den_in.value = den

    def sample():
        return int(dut.q_out.value)

    got = await pipe.run_vectors(dut, apply, sample, len(cases), Q_W, seed=seed)
    bad = []
    for i, ((nums, den), g) in enumerate(zip(cases, got)):
        q = pipe.unpack(g, Q_W, LANES, signed=False)
        exp = [model(x, den, sat) for x in nums]
        if q != exp:
            bad.append(f"  vector {i}: num={nums} den={den}: expected {exp} got {q}")
    assert not bad, f"{len(bad)} of {len(cases)} vectors differ\n" + "\n".join(bad[:10])
    dut._log.info(f"{len(cases)} vectors x {LANES} lanes (NUM_W={num_w}, DEN_W={den_w}, Q_W={Q_W}, SAT={sat}): "
                  "all exact")


@pytest.mark.parametrize("sim,config", hdlbuild.sim_params())
def test_box_divide_rtl(sim, config):
    cfg = hdlbuild.config_of(config)
    # colour_map's exact division (the widths box_divide_vs_python assumes by default)
    pipe.run_block("box_divide", sim, None, {"NUM_W": cfg.d_w - 1, "DEN_W": cfg.w_w, "Q_W": Q_W, "LANES": LANES,
                                             "SAT": 0}, __file__, config=config)


def _narrow_params():
    """(sim, config, B, SAT): each configuration's normalised divider (div_bits > 0), and the
    saturating divider (B <= 9) at B = 9 and 4 (built under the first configuration)."""
    out = []
    for sim, config in hdlbuild.sim_params():
        b = load_config(config).div_bits
        if b > 0:
            out.append((sim, config, b, 1 if b <= 9 else 0))
    sims = sorted({s for s, _ in hdlbuild.sim_params()})
    config = hdlbuild.sim_params()[0][1]
    out += [(sim, config, b, 1) for sim in sims for b in (9, 4)]
    return out


RANDOM_SEEDS = (1291, 1292, 1293, 1294, 1295)  # random valid configurations (Icarus)


def _random_sets():
    out = {}
    for s in RANDOM_SEEDS:
        p = hdlbuild.block_params(hdlbuild.config_of(f"random:{s}"), "box_divide")
        out[f"random{s}"] = {k: p[k] for k in ("NUM_W", "DEN_W", "Q_W", "LANES", "SAT")}
    out["den2"] = {"NUM_W": 11, "DEN_W": 2, "Q_W": Q_W, "LANES": LANES, "SAT": 1}  # a 2-bit divisor
    out["den1"] = {"NUM_W": 10, "DEN_W": 1, "Q_W": Q_W, "LANES": LANES, "SAT": 1}  # div_bits = 1: den' is 1
    # SAT with NUM_W <= Q_W: every quotient fits, the overflow compare is not built (q = num // den)
    out["sat_narrow"] = {"NUM_W": 7, "DEN_W": 3, "Q_W": Q_W, "LANES": LANES, "SAT": 1}
    return out


@pytest.mark.parametrize("sim,name,params", pipe.block_cases(_random_sets()))
def test_box_divide_random_rtl(sim, name, params):
    """colour_map's divider under random valid configurations, and the narrowest divisor."""
    pipe.run_block("box_divide", sim, name, params, __file__, extra_env={
        "BD_NUM_W": str(params["NUM_W"]), "BD_DEN_W": str(params["DEN_W"]), "BD_SAT": str(params["SAT"])})


@pytest.mark.parametrize("sim,config,b,sat", _narrow_params())
def test_box_divide_narrow_rtl(sim, config, b, sat):
    """colour_map's normalised division: DEN_W = B, NUM_W = B + 8 (+ 1 with SAT)."""
    num_w = b + 8 + sat
    pipe.run_block("box_divide", sim, f"{config}_n{num_w}_d{b}_s{sat}",
                   {"NUM_W": num_w, "DEN_W": b, "Q_W": Q_W, "LANES": LANES, "SAT": sat}, __file__, config=config,
                   extra_env={"BD_NUM_W": str(num_w), "BD_DEN_W": str(b), "BD_SAT": str(sat)})
