"""colour_table (rtl/colour_table.v) against golden colour_table (the read ports) and
colour_table_write (the write port), clock by clock.

Parameter sets (FILTER, NMAX, CS_W, NL_W): colour_map's instance (CS_W = csat_w,
NL_W = n_log2_w) under full and reduced (sat), full's formats with the mip and no filter,
two random valid configurations, the smallest tables (NMAX = 1) for each filter and the
largest (NMAX = 10).
Stimulus, one clock at a time with random read addresses and ce low 20% of the clocks
(the write port ignores ce): load every entry of every table (clut and mip in random
order, csat in ascending order: the contract, so total = csat[N - 1]); write every entry
of every table with a random full-width word, then its complement, then the word again (a
pass over the table each: every bit of every entry both ways); reload csat for
each n_log2 in ascending order (total follows csat[N - 1]); then random writes mixed with
reads (same-clock read-before-write), writes past each table's end, to table 3 and to the
tables this FILTER does not build (ignored), lanes with bits above 8 (clut, mip keep the
low byte). After every enabled clock edge all six read ports are compared with the twin
(registered reads; total follows the last csat write); reads of entries not yet written
are not compared.
"""
from __future__ import annotations

import random

import numpy as np

import cocotb
from cocotb.triggers import ReadOnly, RisingEdge, Timer

from model.hw import golden as G
from tb import pipe


def _params(c, filter_=None, nmax=None):
    f = {"none": 0, "sat": 1, "sat_fc": 1, "mip": 2}[c.filter] if filter_ is None else filter_
    return {"FILTER": f, "NMAX": c.n_log2_max if nmax is None else nmax, "CS_W": c.csat_w, "NL_W": c.n_log2_w}


def _sets():
    cs = dict(pipe.configs(1261, 1262, colour_edges=True))
    out = {name: _params(c) for name, c in cs.items() if name not in ("small", "wide")}
    out.update({"full_mip": _params(cs["full"], 2), "full_none": _params(cs["full"], 0)})
    out.update({f"small_{f}": _params(cs["small"], i) for i, f in enumerate(("none", "sat", "mip"))})
    out["wide"] = _params(cs["wide"], 1)
    return out


# every set under Icarus; under Verilator (a build costs 5-20 s) full's formats and the smallest tables
# with each FILTER (Verilator's toggle coverage counts the bits of the small tables' memories only)
test_colour_table_rtl = pipe.block_test("colour_table", _sets(), ("full", "full_mip", "full_none", "small_none",
                                                                 "small_sat", "small_mip"), __file__)


PORTS = ("clut_a", "clut_b", "csat_a", "csat_b", "total", "mip_data")


@cocotb.test()
async def colour_table_bit_exact(dut):
    p = pipe.block_params()
    filt, nmax, cs_w = p["FILTER"], p["NMAX"], p["CS_W"]
    n = 1 << nmax
    r = random.Random(int(pipe.rng(91).integers(1 << 30)))
    lanes_w = {"clut_a": 8, "clut_b": 8, "csat_a": cs_w, "csat_b": cs_w, "total": cs_w, "mip_data": 8}

    def lanes():
        return [r.getrandbits(cs_w) for _ in range(4)]

    # the write sequence: (table, addr, data) or None (no write this clock)
    load = [(0, a, lanes()) for a in r.sample(range(n), n)] + [(1, a, lanes()) for a in range(n)]
    load += [(2, a, lanes()) for a in r.sample(range(2 * n - 1), 2 * n - 1)]
    # every entry of every table (built or not) three times over: a random full-width word, its
    # complement, the word again, one table-long pass each (so that reads see every value): every
    # bit of every entry goes both ways
    ones = (1 << cs_w) - 1
    for tbl, depth in ((0, n), (1, n), (2, 2 * n - 1)):
        words = [lanes() for _ in range(depth)]
        for flip in (0, ones, 0):
            load += [(tbl, a, [x ^ flip for x in words[a]]) for a in range(depth)]
    for n_log2 in range(nmax + 1):  # a table of N = 2^n_log2 entries: csat ascending
        load += [(1, a, lanes()) for a in range(1 << n_log2)]
    mixed = []
    for _ in range(pipe.n_vectors()):
        x = r.random()
        if x < 0.4:
            mixed.append(None)
        elif x < 0.85:
            t = r.randrange(3)
            mixed.append((t, r.randrange(2 * n - 1 if t == 2 else n), lanes()))
        else:  # ignored: past the end, table 3
            mixed.append(r.choice([(0, n + r.randrange(n), lanes()), (1, n + r.randrange(n), lanes()),
                                   (2, 2 * n - 1, lanes()), (3, r.randrange(2 * n), lanes())]))
    writes = load + mixed
    tables = G.colour_tables(nmax, fill=-1)
    state = None  # the read registers (golden), per port
    await pipe.start(dut, reset=False, valid=False)
    dut.wr_en.value = 0
    dut.n_log2.value = 0
    compared = bad = 0
    for t, wr in enumerate(writes):
        ce = 1 if r.random() >= 0.2 else 0
        addr = {"clut_addr_a": r.randrange(n), "clut_addr_b": r.randrange(n), "csat_addr_a": r.randrange(n),
                "csat_addr_b": r.randrange(n), "mip_addr": r.randrange(2 * n - 1)}
        for k, a in addr.items():
            getattr(dut, k).value = a
        dut.n_log2.value = r.randrange(nmax + 1)
        dut.ce.value = ce
        dut.wr_en.value = wr is not None
        if wr is not None:
            dut.wr_table.value, dut.wr_addr.value = wr[0], wr[1]
            dut.wr_data.value = pipe.pack(wr[2], cs_w)
        await RisingEdge(dut.clk)
        if ce:  # read before write: the tables as they were before this edge
            state = {k: v.copy() for k, v in G.colour_table(tables, filt, **addr).items()}
        if wr is not None:
            G.colour_table_write(tables, filt, nmax, cs_w, *wr)
        await ReadOnly()
        if state is not None:
            exp = dict(state, total=G.colour_table(tables, filt)["total"])
            for k in PORTS:
                e = [int(x) for x in exp[k]]
                if min(e) < 0:
                    continue  # an entry not written yet
                g = pipe.unpack(int(getattr(dut, k).value), lanes_w[k], 4, signed=False)
                compared += 1
                if g != e:
                    bad += 1
                    if bad <= 10:
                        dut._log.error(f"clock {t} ({'load' if t < len(load) else 'mixed'}) {k}: expected {e}, "
                                       f"got {g} (write {wr}, reads {addr})")
        if t == len(load) - 1 and filt == 1:  # the contract: total = csat[N - 1] after an ascending load
            assert [int(x) for x in tables["total"]] == [int(x) for x in tables["csat"][n - 1]]
        await Timer(1, unit="ns")
    assert compared > len(mixed), f"only {compared} reads compared"
    assert not bad, f"colour_table {p}: {bad} of {compared} port reads differ"
    dut._log.info(f"colour_table {p}: {compared} port reads bit-exact over {len(writes)} clocks")
