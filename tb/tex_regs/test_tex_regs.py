"""tex_regs (the register decoder): every output, every clock, against its twin
model/hw/regmap.py tex_regs / TexRegs; and the register map's one table.

Python side (no simulator):
- rtl/tex_regmap.vh is what model/hw/regmap.py REGMAP_TABLE generates (regmap_vh()): the
  test fails on a stale or hand-edited include (`python -m model.hw.regmap --write`).
- write_sequence round-trips through the decoder's twin: the registers and tables that
  tex_regs(cfg, write_sequence(cfg, tex)) holds are tex again, for random textures of both
  configurations and of random valid ones, also with unmapped writes interleaved.

RTL (cocotb, both simulators, the named configurations and random valid parameter sets):
reset (every output 0, no X); random writes with gaps (cfg_wr_en low) to every register,
to noise terms k >= K and term fields past o_k, to table entries inside and past the end of
clut / csat / mip, to unmapped addresses of every region and to random addresses, and
resets in the middle; after every clock every output equals the twin's state. Then a
texture's write_sequence, checked the same way.

Per-term exponents (formats.t_exp_w, a_exp_w > 0; pipe.exponent_configs: full_bfp and a random
one under Icarus, full_exp too in the round trip): the TERM_E word of each term loads te_k and
ae_k, which tex_regs puts above the term's mantissas in t_all and a_all; without exponents
TERM_E is an ignored address. The round trip and the ignored writes run on them too.
"""
from __future__ import annotations

import os
import random

import numpy as np
import pytest

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ReadOnly, RisingEdge, Timer

import hdlbuild
from model.hw import regmap as RM
from model.hw.config import ROOT, SAT_FILTERS, load_config, random_config
from model.hw.golden import MODE_CLAMP, MODE_MOD, TexInt
from tb import pipe

SOURCES = ["tex_regs.v"]
N_RANDOM = 3  # random valid configurations besides full and reduced (RANDOM_CONFIGS= overrides)


@pytest.mark.parametrize("sim,config", hdlbuild.family_params(N_RANDOM))
def test_tex_regs_rtl(sim, config):
    pipe.run_block("tex_regs", sim, test_file=__file__, config=config, sources=SOURCES)


# with per-term exponents (the Python round trip on all three): full_bfp and exp1342 under Icarus
# (tb/frame's test_frame_exponents runs full_bfp's whole unit under Verilator)
EXP_CONFIGS = dict(pipe.exponent_configs(1342))


@pytest.mark.parametrize("sim,name", [pytest.param("icarus", n, id=f"icarus-{n}") for n in ("full_bfp", "exp1342")
                                      if os.environ.get("SIM", "icarus") == "icarus"])
def test_tex_regs_exponents_rtl(sim, name):
    pipe.run_block("tex_regs", sim, test_file=__file__, config=EXP_CONFIGS[name], sources=SOURCES)


def test_tex_regs_check():
    """tex_regs's elaboration-time check (g_bad_params, the register map's shape) both ways on full's
    parameters: refused past each bound the parameters reach (NOISE_TERMS 17 > RM_TERM_SLOTS 16;
    N_LOG2_MAX 10: the csat words' offsets, N_LOG2_MAX + RM_CSAT_LOG2 bits, reach the region's
    RM_REGION_LSB 12; T_EXP_W 33 and A_EXP_W 25 past the 32-bit TERM_E word), accepted at each edge
    (16 terms, N_LOG2_MAX 9, A_EXP_W 24: ae in bits 8..31) and with T_EXP_W 8, te filling bits
    0..7 below ae. (NCH != 4 depends on rtl/tex_regmap.vh alone. The te term bounds te by the
    word, not by ae's LSB: T_EXP_W 9..32 would overlap ae and elaborates; model/hw/config.py keeps
    t_exp_w far below, and this test does not pin that edge.)"""
    b = hdlbuild.block_params(hdlbuild.config_of("full"), "tex_regs")
    hdlbuild.check_refusals(
        "tex_regs", SOURCES, b,
        accept={"full": {}, "16 terms": {"NOISE_TERMS": 16}, "N_LOG2_MAX 9": {"N_LOG2_MAX": 9},
                "A_EXP_W 24": {"A_EXP_W": 24}, "T_EXP_W 8": {"T_EXP_W": 8}},
        refuse={"NOISE_TERMS 17": {"NOISE_TERMS": 17}, "N_LOG2_MAX 10": {"N_LOG2_MAX": 10},
                "T_EXP_W 33": {"T_EXP_W": 33}, "A_EXP_W 25": {"A_EXP_W": 25}},
        error_module="tex_regs_bad_parameters")


def test_regmap_vh_is_generated():
    """The committed rtl/tex_regmap.vh is exactly what the table generates."""
    path = ROOT / RM.REGMAP_VH
    assert path.exists(), f"{RM.REGMAP_VH} missing: python -m model.hw.regmap --write"
    assert path.read_text() == RM.regmap_vh(), (
        f"{RM.REGMAP_VH} is not what model/hw/regmap.py REGMAP_TABLE generates: "
        "python -m model.hw.regmap --write")


def test_regmap_table_names_unique():
    names = [n for n, _, _ in RM.REGMAP_TABLE]
    assert len(names) == len(set(names))
    assert not set(names) & set(RM.REGMAP_DERIVED)


# ---------------------------------------------------------------------------
# Stimulus (shared by the Python round trip and the cocotb test)


def random_texture(cfg, r) -> TexInt:
    """Every parameter over its whole format, random n_log2, mode, filter, k_used."""
    K = cfg.noise_terms

    def s(w, size):
        return r.integers(-(1 << (w - 1)), 1 << (w - 1), size=size, dtype=np.int64)

    Q = s(cfg.q_w, 10)
    n_log2 = int(r.integers(0, cfg.n_log2_max + 1))
    tex = TexInt(Q=Q, a=s(cfg.a_w, K), T=s(cfg.t_w, (K, 3, 3)),
                 o=r.integers(0, 1 << cfg.d["o_w"], size=(K, 3), dtype=np.int64),
                 mode=int(r.choice([MODE_MOD, MODE_CLAMP])), n_log2=n_log2, filter=bool(r.random() < 0.5),
                 clut=r.integers(0, 256, size=(1 << n_log2, 4), dtype=np.int64), k_used=int(r.integers(0, K + 1)))
    # the exponents (drawn only with them: a fixed-point configuration's draws stay as they were)
    if cfg.t_exp_w:
        tex.te = r.integers(0, 1 << cfg.t_exp_w, size=K, dtype=np.int64)
    if cfg.a_exp_w:
        tex.ae = r.integers(0, 1 << cfg.a_exp_w, size=K, dtype=np.int64)
    return tex


def term_fields(cfg) -> set:
    """The term fields the decoder loads under cfg (TERM_E only with exponents)."""
    return ({RM.TERM_A, *range(RM.TERM_T, RM.TERM_T + 9), *range(RM.TERM_O, RM.TERM_O + 3)}
            | ({RM.TERM_E} if cfg.t_exp_w or cfg.a_exp_w else set()))


def ignored_addresses(cfg) -> list[int]:
    """Addresses the decoder must ignore (no register changes, no table write)."""
    K, nmax = cfg.noise_terms, cfg.n_log2_max
    ctrl, q, term = RM.ADDR_CTRL, RM.ADDR_Q, RM.ADDR_TERM
    used_fields = term_fields(cfg)
    regs = {ctrl, *range(q, q + RM.Q_COUNT)}
    out = [ctrl + 1, q - 1, q + RM.Q_COUNT, q + RM.Q_COUNT + 5, term - 1]
    out += [term + RM.TERM_STRIDE * k + f for k in range(K) for f in range(RM.TERM_STRIDE) if f not in used_fields]
    out += [term + RM.TERM_STRIDE * k + f for k in range(K, RM.TERM_SLOTS) for f in (0, 1, 10)]
    out += [term + RM.TERM_STRIDE * RM.TERM_SLOTS, (1 << RM.REGION_LSB) - 1]
    out += [RM.ADDR_CLUT + (1 << nmax), RM.ADDR_CLUT + (1 << RM.REGION_LSB) - 1]
    out += [RM.ADDR_CSAT + RM.CSAT_CHANNELS * (1 << nmax) + 3, RM.ADDR_CSAT + (1 << RM.REGION_LSB) - 1]
    out += [RM.ADDR_MIP + (2 << nmax), RM.ADDR_MIP + (1 << RM.REGION_LSB) - 1]
    out += [0x4000, 0x7ABC, 0x8000, 0xF000, 0xFFFF]
    return [a for a in out if a not in regs and 0 <= a < RM.ADDR_SPACE]


def random_writes(cfg, rr: random.Random, n: int) -> list[tuple[int, int]]:
    """n writes: registers, terms (also k >= K), tables (inside and past the end), unmapped."""
    K, nmax = cfg.noise_terms, cfg.n_log2_max
    ign = ignored_addresses(cfg)
    out = []
    for _ in range(n):
        c = rr.random()
        if c < 0.08:
            a = RM.ADDR_CTRL
        elif c < 0.2:
            a = RM.ADDR_Q + rr.randrange(RM.Q_COUNT)
        elif c < 0.4:
            a = RM.ADDR_TERM + RM.TERM_STRIDE * rr.randrange(max(K, 1) + 1) + rr.randrange(RM.TERM_STRIDE)
        elif c < 0.5:
            a = RM.ADDR_CLUT + rr.randrange(2 << nmax)
        elif c < 0.7:
            a = RM.ADDR_CSAT + rr.randrange(RM.CSAT_CHANNELS << (nmax + 1))
        elif c < 0.8:
            a = RM.ADDR_MIP + rr.randrange(4 << nmax)
        elif c < 0.9:
            a = rr.choice(ign)
        else:
            a = rr.randrange(RM.ADDR_SPACE)
        d = rr.choice([rr.getrandbits(32), 0, 0xFFFFFFFF, rr.getrandbits(8), 1 << rr.randrange(32)])
        out.append((a, d))
    return out


def _configs():
    return ([load_config("full"), load_config("reduced")] + [random_config(1200 + i, name=f"random{1200 + i}")
                                                             for i in range(4)] + list(EXP_CONFIGS.values()))


@pytest.mark.parametrize("cfg", _configs(), ids=lambda c: c.name)
def test_write_sequence_round_trip(cfg):
    """tex_regs(cfg, write_sequence(cfg, tex)) holds tex: every register and the tables the
    configuration's filter reads; unmapped writes interleaved change nothing."""
    r = np.random.default_rng(7)
    rr = random.Random(7)
    ign = ignored_addresses(cfg)
    for trial in range(20):
        tex = random_texture(cfg, r)
        seq = RM.write_sequence(cfg, tex)
        if trial % 2:
            mixed = []
            for w in seq:
                if rr.random() < 0.3:
                    mixed.append((rr.choice(ign), rr.getrandbits(32)))
                mixed.append(w)
            seq = mixed
        st, tables = RM.tex_regs(cfg, seq)
        back = RM.texint_of_regs(cfg, st, tables)
        n = 1 << tex.n_log2
        assert np.array_equal(back.Q, tex.Q) and np.array_equal(back.a, tex.a)
        assert np.array_equal(back.T, tex.T) and np.array_equal(back.o, tex.o)
        assert np.array_equal(back.te, tex.te) and np.array_equal(back.ae, tex.ae)
        assert (back.mode, back.n_log2, back.filter, back.k_used) == (tex.mode, tex.n_log2, tex.filter, tex.k_used)
        assert np.array_equal(back.clut, tex.clut)
        assert set(tables[RM.TABLE_CLUT]) == set(range(n))
        if cfg.filter in SAT_FILTERS:
            assert np.array_equal(back.csat, tex.csat) and set(tables[RM.TABLE_CSAT]) == set(range(n))
        if cfg.filter == "mip":
            assert np.array_equal(back.mip, tex.mip) and set(tables[RM.TABLE_MIP]) == set(range(2 * n - 1))


@pytest.mark.parametrize("cfg", _configs()[:2] + list(EXP_CONFIGS.values())[:1], ids=lambda c: c.name)
def test_ignored_writes_change_nothing(cfg):
    st0, _ = RM.tex_regs(cfg, RM.write_sequence(cfg, random_texture(cfg, np.random.default_rng(3))))
    before = _state(st0)
    for a in ignored_addresses(cfg):
        for d in (0, 0xFFFFFFFF, 0x5A5A5A5A):
            assert st0.write(a, d) is None, f"write to {a:#06x} wrote a table entry"
            assert _state(st0, tables=False) == before[:-1], f"write to {a:#06x} changed a register"


def _state(st, tables=True):
    regs = (st.mode, st.filter_en, st.n_log2, st.k_used, tuple(st.q), tuple(st.a), tuple(map(tuple, st.T)),
            tuple(map(tuple, st.o)), tuple(st.te), tuple(st.ae))
    return regs + ((st.tbl_wr_en,) if tables else ())


# ---------------------------------------------------------------------------
# cocotb


def _pack(values, w):
    out = 0
    for i, v in enumerate(values):
        out |= (int(v) & ((1 << w) - 1)) << (i * w)
    return out


def expected_outputs(cfg, st: RM.TexRegs) -> dict:
    # term k of a_all {ae_k, a_k}, of t_all {te_k, T_k} (the exponents only with t_exp_w, a_exp_w > 0)
    a_terms = [a | (e << cfg.a_w) for a, e in zip(st.a, st.ae)]
    t_terms = [_pack(t, cfg.t_w) | (e << 9 * cfg.t_w) for t, e in zip(st.T, st.te)]
    return {
        "mode": st.mode, "filter_en": st.filter_en, "n_log2": st.n_log2, "k_used": st.k_used,
        "q_coef": _pack(st.q, cfg.q_w), "a_all": _pack(a_terms, cfg.a_w + cfg.a_exp_w),
        "t_all": _pack(t_terms, 9 * cfg.t_w + cfg.t_exp_w),
        "o_all": _pack([v for o in st.o for v in o], cfg.d["o_w"]),
        "tbl_wr_en": st.tbl_wr_en, "tbl_wr_table": st.tbl_wr_table, "tbl_wr_addr": st.tbl_wr_addr,
        "tbl_wr_data": st.tbl_wr_data,
    }


def _check(dut, cfg, st, what):
    exp = expected_outputs(cfg, st)
    for name, v in exp.items():
        got = getattr(dut, name).value
        assert got.is_resolvable, f"{what}: {name} = {got} (X or Z)"
        assert int(got) == v, f"{what}: {name} = {int(got):#x}, expected {v:#x}"


@cocotb.test()
async def writes_against_twin(dut):
    from model.hw.config import load_config as _load

    cfg = _load(os.environ["CONFIG"])
    seed = int(os.environ.get("SEED", "1"))
    rr = random.Random(seed)
    r = np.random.default_rng(seed)
    n = int(os.environ.get("VECTORS", "2000"))
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    st = RM.TexRegs(cfg)
    dut.rst.value = 1
    dut.cfg_wr_en.value = 0
    dut.cfg_wr_addr.value = 0
    dut.cfg_wr_data.value = 0
    for _ in range(2):
        await RisingEdge(dut.clk)
    await ReadOnly()
    _check(dut, cfg, st, "after reset")
    await Timer(1, unit="ns")

    async def clock(en, addr, data, rst=0, what=""):
        dut.rst.value = rst
        dut.cfg_wr_en.value = en
        dut.cfg_wr_addr.value = addr
        dut.cfg_wr_data.value = data
        await RisingEdge(dut.clk)
        if rst:
            st.reset()
        elif en:
            st.write(addr, data)
        else:
            st.idle()
        await ReadOnly()
        _check(dut, cfg, st, what)
        await Timer(1, unit="ns")

    # random writes with gaps and a few resets
    writes = random_writes(cfg, rr, n)
    for i, (a, d) in enumerate(writes):
        if rr.random() < 0.002:
            await clock(0, rr.getrandbits(16), rr.getrandbits(32), rst=1, what=f"reset before write {i}")
        while rr.random() < 0.2:  # cfg_wr_en low: address and data are junk
            await clock(0, rr.getrandbits(16), rr.getrandbits(32), what=f"gap before write {i}")
        await clock(1, a, d, what=f"write {i} ({a:#06x} <- {d:#010x})")
    # a texture's write sequence, back to back
    tex = random_texture(cfg, r)
    for i, (a, d) in enumerate(RM.write_sequence(cfg, tex)):
        await clock(1, a, d, what=f"write_sequence {i} ({a:#06x} <- {d:#010x})")
    await clock(0, 0, 0, what="idle")
    dut._log.info(f"{cfg.name}: {n} random writes and {len(RM.write_sequence(cfg, tex))} sequence writes match the twin")
