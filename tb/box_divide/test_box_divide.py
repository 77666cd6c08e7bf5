"""box_divide (rtl/box_divide.v) against Python integer division, bit for bit.

Two halves in one file (the project's testbench convention):
- pytest entry `test_box_divide_rtl` over (simulator, configuration): the divider is built
  with its defaults, the widths colour_map uses (NUM_W = D_W - 1, DEN_W = W_W, Q_W = 8,
  LANES = 4 numerators sharing one divisor);
- cocotb test `box_divide_vs_python`: random divisors (uniform over the whole DEN_W range
  and log-uniform) with random numerators meeting the precondition num < den 2^Q_W, then
  the edge cases: den = 1, den at its maximum, den = 2^k and 2^k - 1, quotients 0, 1,
  2^Q_W - 1 and every exact multiple boundary (num = q den - 1, q den, q den + 1), num at
  its maximum (den = 0 is outside the precondition: colour_map never divides by 0);
  streamed with random ce stalls and input gaps. Expected: num // den per lane.

Environment: SIM, CONFIG narrow the parametrization; SEED fixes the randomness;
VECTORS = random vectors (default 2000; edge cases come on top).
"""
from __future__ import annotations

import random
from pathlib import Path

import pytest

import cocotb

import tb.runner
from tb import pipe

Q_W, LANES = 8, 4  # box_divide's defaults, as colour_map instantiates it


def widths(cfg):
    return cfg.d_w - 1, cfg.w_w  # NUM_W, DEN_W (box_divide's defaults)


def model(num: int, den: int) -> int:
    return num // den


def random_cases(r: random.Random, n: int, num_w: int, den_w: int):
    out = []
    for _ in range(n):
        if r.random() < 0.5:
            den = r.randrange(1, 1 << den_w)
        else:
            den = r.randrange(1, 1 << r.randint(1, den_w))
        lim = min(den << Q_W, 1 << num_w)  # precondition and the numerator word
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


def edge_cases(r: random.Random, num_w: int, den_w: int):
    qmax = (1 << Q_W) - 1
    dens = {1, 2, 3, (1 << den_w) - 1, 1 << (den_w - 1), (1 << (den_w - 1)) - 1, (1 << (den_w - 1)) + 1}
    dens |= {1 << k for k in range(den_w)} | {(1 << k) - 1 for k in range(2, den_w)}
    out = []
    for den in sorted(dens):
        lim = min(den << Q_W, 1 << num_w)
        cand = {0, 1, den - 1, den, den + 1, lim - 1, (qmax * den) - 1, qmax * den, qmax * den + 1,
                (den << (Q_W - 1)) - 1, den << (Q_W - 1), (1 << num_w) - 1}
        cand |= {q * den + d for q in (1, 2, 127, 128, 254, 255) for d in (-1, 0, 1)}
        cand = sorted(c for c in cand if 0 <= c < lim)
        for i in range(0, len(cand), LANES):
            nums = cand[i:i + LANES]
            nums += [r.randrange(lim) for _ in range(LANES - len(nums))]
            out.append((nums, den))
    return out


@cocotb.test()
async def box_divide_vs_python(dut):
    cfg = pipe.cfg()
    num_w, den_w = widths(cfg)
    assert len(dut.num_in) == LANES * num_w and len(dut.den_in) == den_w, "unexpected box_divide widths"
    seed = int(pipe.rng(23).integers(1 << 30))
    r = random.Random(seed)
    cases = random_cases(r, pipe.n_vectors(), num_w, den_w) + edge_cases(r, num_w, den_w)
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
        exp = [model(x, den) for x in nums]
        if q != exp:
            bad.append(f"  vector {i}: num={nums} den={den}: expected {exp} got {q}")
    assert not bad, f"{len(bad)} of {len(cases)} vectors differ\n" + "\n".join(bad[:10])
    dut._log.info(f"{len(cases)} vectors x {LANES} lanes (NUM_W={num_w}, DEN_W={den_w}, Q_W={Q_W}): all exact")


@pytest.mark.parametrize("sim,config", tb.runner.sim_params())
def test_box_divide_rtl(sim, config):
    tb.runner.run("box_divide", sources=["box_divide.v"], test_module="test_box_divide", sim=sim,
                  config=config, test_dir=Path(__file__).parent)
