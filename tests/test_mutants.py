"""verify/mutants.py (make mutants): which lines it mutates, how a mutant is applied, the docs
section it writes, and a tiny run (one known mutant of delay_line, killed by its testbench)."""
from __future__ import annotations

import json
import shutil

import pytest

from verify import mutants as mu

SRC = """// header: a + b & c  (a comment: never mutated)
`default_nettype none
module m #(
    parameter W = 4  // parameter: not mutated
) (
    input  wire [W-1:0] a,
    output reg  [W-1:0] y
);
localparam H = W - 1;   /* a declaration */
wire [W-1:0] s = a + 4'd3;
reg [W-1:0] r1, r2;
`ifdef FORMAL
    always @* assert (a + 1 != 0);
`endif
always @(posedge clk) begin
    r1 <= s ^ {W{1'b0}};  /* tail comment + */
    r2 <= r1;
    if (a < 2) y <= r2 >> 1;
end
endmodule
"""


def test_sites_are_live_code_only():
    sl = mu.sites("m.v", SRC)
    lines = {m.line for _, alts in sl for m in alts}
    assert lines == {10, 16, 17, 18}  # the wire's right-hand side and the always block's body
    got = {(m.line, m.kind, m.old, m.new) for _, alts in sl for m in alts}
    assert (10, "operator", "+", "-") in got and (10, "constant", "4'd3", "4'd2") in got
    assert (16, "operator", "^", "|") in got
    assert not any(m.old == "W" or m.line == 16 and m.kind == "constant" and m.old == "W" for _, a in sl for m in a)
    assert (17, "stage", "r1", "(s ^ {W{1'b0}})") in got  # r2 <= r1 skips r1's stage
    assert (18, "comparison", "<", "<=") in got and (18, "shift", " 1", " 2") in got and (18, "shift", " 1", " 0") in got
    # a replication count and the nonblocking assignment's <= are not mutated
    assert not any(m.line == 16 and m.old == "W" for _, a in sl for m in a)
    assert not any(m.old == "<=" for _, a in sl for m in a)


def test_apply_changes_one_place():
    m = next(m for _, alts in mu.sites("m.v", SRC) for m in alts if m.kind == "comparison")
    out = m.apply(SRC)
    diff = [(a, b) for a, b in zip(SRC.split("\n"), out.split("\n")) if a != b]
    assert diff == [("    if (a < 2) y <= r2 >> 1;", "    if (a <= 2) y <= r2 >> 1;")]


def test_draw_is_seeded_and_covers_the_rtl():
    sl = mu.all_sites()
    kinds = {k for k, _ in sl}
    assert kinds == set(mu.KINDS)
    a = [m.id for m, _ in zip(mu.draw(sl, 5), range(30))]
    assert a == [m.id for m, _ in zip(mu.draw(sl, 5), range(30))] and len(set(a)) == 30


def test_testbenches_of_a_module():
    """A block's own testbench (noise_fold's: tb/noise_fold); a module without one (sat2_integral) is run
    under the testbenches that build it; texture_pipeline, which none builds, has only the frames."""
    tb = mu.ROOT / "tb"
    assert mu.testbenches("bitlen") == [tb / "bitlen"]
    assert mu.testbenches("noise_fold") == [tb / "noise_fold"]
    assert tb / "cmap_sat2" in mu.testbenches("sat2_integral") and tb / "cmap_sat2" in mu.testbenches("sat2_table")
    assert mu.testbenches("texture_pipeline") == []
    # the stimulus tb/noise_fold imports from tb/noise_term is part of its verdicts' cache key
    assert mu.tb_imports([tb / "noise_fold"]) == [tb / "noise_term"]
    assert mu.tb_imports([tb / "bitlen"]) == []


def test_section_merges(tmp_path):
    doc = tmp_path / "verification.md"
    doc.write_text("# Verification\n\n## Formal\n\nproved.\n\n## Mutants\n\nold\n\n## Coverage\n\n98%\n")
    mu.write_section(doc, "## Mutants\n\nnew\n")
    t = doc.read_text()
    assert "## Formal\n\nproved." in t and "## Coverage\n\n98%" in t and "new" in t and "old" not in t
    doc2 = tmp_path / "none.md"
    mu.write_section(doc2, "## Mutants\n\nx\n")
    assert doc2.read_text().startswith("# Verification") and "## Mutants\n\nx" in doc2.read_text()


def test_bad_input(capsys):
    assert mu.main(["--files", "nosuch.v"]) == 2
    assert mu.main(["--n", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and all(x.startswith("mutants: ") for x in err)


@pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus (make setup)")
def test_tiny_run_kills_a_known_mutant(tmp_path):
    """Seed 15 on fc_weight.v draws a register stage skipped (`v2 <= v1` -> `v2 <= (in_valid)`: the
    valid bit one clock early): tb/fc_weight kills it on its first case."""
    doc = tmp_path / "verification.md"
    rc = mu.main(["--n", "1", "--seed", "15", "--files", "fc_weight.v", "--jobs", "1", "--out", str(tmp_path / "out"),
                  "--docs", str(doc), "--quiet", "--tce-timeout", "20"])  # TCE runs out: the tests decide
    res = json.loads((tmp_path / "out" / "results.json").read_text())
    (r,) = res["mutants"]
    assert (r["id"], r["kind"], r["result"]) == ("6f92a850", "stage", "killed") and r["by"].startswith("tb/fc_weight/")
    assert rc == 0 and res["summary"]["killed_share"] == 1.0
    line = next(i for i, x in enumerate((mu.RTL / "fc_weight.v").read_text().split("\n"), 1) if x.strip() == "v2  <= v1;")
    assert r["line"] == line  # the line moves with edits to fc_weight.v; the mutant's id does not
    assert f"| 6f92a850 | fc_weight.v:{line} | stage |" in doc.read_text() and "<!-- measured on:" in doc.read_text()
    assert not (tmp_path / "out" / "run" / "6f92a850").exists()  # the scratch copy is gone


# --------------------------------------------------------------------------- TCE (Yosys)

PLANTED = """`default_nettype none
module planted #(
    parameter W = 4
) (
    input  wire         clk,
    input  wire [W-1:0] a,
    input  wire [W-1:0] b,
    output reg  [W-1:0] y,
    output wire [W-1:0] s,
    output wire [W-1:0] z
);
wire [W-1:0] lo = a[W-1:0];
assign z = {1'b0, a[W-1:1]};
assign s = a + b;
always @(posedge clk) y <= lo ^ b;
/* verilator lint_off UNUSEDSIGNAL */
wire [W-1:0] unused_w = b & {W{1'b1}};
/* verilator lint_on UNUSEDSIGNAL */
endmodule
"""


def _planted(tmp_path, monkeypatch, changes=True, timeout=60):
    """An rtl/ of one module (planted.v) elaborated by one configuration "cfg" with W = 4 and W = 7
    (its two instances); compile_top says the mutation changes cfg's compile (or not), no testbench,
    and every frame passes: a mutant the TCE check does not drop survives."""
    rtl = tmp_path / "rtl"
    rtl.mkdir()
    (rtl / "planted.v").write_text(PLANTED)
    monkeypatch.setattr(mu, "RTL", rtl)
    monkeypatch.setattr(mu, "compile_top", lambda r, arg, vvp: (True, "changed" if changes else "h0"))
    monkeypatch.setattr(mu, "testbenches", lambda module: [])
    monkeypatch.setattr(mu, "_run", lambda *a, **k: ("ok", 0, ""))
    return mu.Opts(scenes=("marble",), tce_timeout=timeout, configs={"cfg": "cfg"}, baseline={"cfg": "h0"},
                   instances={"cfg": {"planted"}}, params={"cfg": {"planted": [{"W": "4"}, {"W": "7"}]}})


def _mutant(line_text: str, old: str, new: str) -> mu.Mutant:
    return next(m for _, alts in mu.sites("planted.v", PLANTED) for m in alts
                if m.text == line_text and m.old == old and m.new == new)


needs_yosys = pytest.mark.skipif(shutil.which("yosys") is None or shutil.which("iverilog") is None,
                                 reason="needs Yosys and Icarus (make setup)")


@needs_yosys
def test_tce_drops_a_truncation_past_the_width(tmp_path, monkeypatch):
    """a[W-1:0] -> a[W+1:0] into a W-bit wire: the two bits past a's top are x, cut where assigned:
    proved on both parameter sets, the mutant is dropped before its tests (and the verdict cached)."""
    opts = _planted(tmp_path, monkeypatch)
    m = _mutant("wire [W-1:0] lo = a[W-1:0];", "-", "+")
    rec = mu.run_mutant(m, opts, tmp_path / "out")
    assert rec["result"] == "equivalent" and rec["by"] == "proved equivalent by Yosys (TCE)"
    assert rec["tce"]["result"] == "proved" and [s["params"] for s in rec["tce"]["sets"]] == [{"W": "4"}, {"W": "7"}]
    assert all(s["from"] == ["cfg"] for s in rec["tce"]["sets"]) and "tb" not in rec
    again = mu.tce_check(m, opts, tmp_path / "out", ["cfg"])
    assert again["cached"] and again["result"] == "proved"
    # a lint sink's operator: read by nothing, proved too
    sink = _mutant("wire [W-1:0] unused_w = b & {W{1'b1}};", "&", "|")
    assert mu.run_mutant(sink, opts, tmp_path / "out")["result"] == "equivalent"


@needs_yosys
def test_tce_keeps_a_live_change(tmp_path, monkeypatch):
    """a + b -> a - b on an output: not proved, the mutant runs its tests (here: survives them); so
    is a register's XOR made an OR, and a select whose bit past the top (x) reaches an output."""
    opts = _planted(tmp_path, monkeypatch)
    m = _mutant("assign s = a + b;", "+", "-")
    rec = mu.run_mutant(m, opts, tmp_path / "out")
    assert rec["tce"]["result"] == "not proved" and "unproven" in rec["tce"]["detail"]
    assert rec["result"] == "survived" and rec["frame_configs"] == ["cfg"]
    # the flipped bit of the XOR's source (lo ^ b -> lo | b) in the register: not proved either
    m2 = _mutant("always @(posedge clk) y <= lo ^ b;", "^", "|")
    assert mu.run_mutant(m2, opts, tmp_path / "out")["tce"]["result"] == "not proved"
    # a[W-1:1] -> a[W+1:1] under a zero bit: z's top bit is x (a[W], past a's top) where it was 0;
    # Icarus simulates that x, so the check models undef states and does not prove it
    m3 = _mutant("assign z = {1'b0, a[W-1:1]};", "-", "+")
    assert mu.run_mutant(m3, opts, tmp_path / "out")["tce"]["result"] == "not proved"


@needs_yosys
def test_tce_timeout_and_unchanged_keep_the_mutant(tmp_path, monkeypatch):
    """A check that runs out of time proves nothing: the truncation Yosys proves in time is kept when
    the limit is 20 ms; a mutation no compile sees changed ('unchanged') is kept too."""
    m = _mutant("wire [W-1:0] lo = a[W-1:0];", "-", "+")
    opts = _planted(tmp_path, monkeypatch, timeout=0.02)
    rec = mu.run_mutant(m, opts, tmp_path / "out")
    assert rec["tce"]["result"] == "timeout" and rec["result"] == "survived"
    (tmp_path / "u").mkdir()
    opts = _planted(tmp_path / "u", monkeypatch, changes=False)
    rec = mu.run_mutant(m, opts, tmp_path / "out_u")
    assert rec["tce"]["result"] == "unchanged" and rec["result"] == "survived" and rec["frame_configs"] == []


@pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus (make setup)")
def test_instance_params_of_a_compile(tmp_path, monkeypatch):
    """The parameters of each instance from Icarus's compiled design: declared ones only (not a
    localparam), negative and wide values as Verilog literals."""
    rtl = tmp_path / "rtl"
    rtl.mkdir()
    (rtl / "leaf.v").write_text("module leaf #(\n    parameter W = 4,\n    parameter signed S = 0,\n"
                                "    parameter [39:0] T = 0\n) (output wire [W-1:0] y);\nlocalparam L = W + 1;\n"
                                "assign y = L[W-1:0];\nendmodule\n")
    (rtl / "top.v").write_text("module top (output wire [2:0] a, output wire [5:0] b);\n"
                               "leaf #(.W(3), .S(-5)) u_a (.y(a));\nleaf #(.W(6), .T(40'hF000000001)) u_b (.y(b));\n"
                               "endmodule\n")
    monkeypatch.setattr(mu, "RTL", rtl)
    assert mu.declared_params("leaf") == ["W", "S", "T"] and mu.module_files("top") == ["top.v", "leaf.v"]
    ok, text = mu.compile_vvp(rtl, "top", ["top.v", "leaf.v"], tmp_path / "top.vvp")
    assert ok
    got = mu.instance_params(text)
    assert got["top"] == [{}] and len(got["leaf"]) == 2
    assert {"W": "3", "S": "-5", "T": "40'b" + "0" * 40} in got["leaf"]
    assert {"W": "6", "S": "0", "T": "40'b" + format(0xF000000001, "040b")} in got["leaf"]


@pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus (make setup)")
def test_tce_builds_of_the_testbenches(tmp_path):
    """The parameter sets a testbench elaborates a module with, without simulating: tb/delay_line's
    cases, the top's parameters read back from each Icarus compile (a module without a testbench of
    its own, sat2_integral, gets the sets of its instances in the builds of the testbenches that build it)."""
    opts = mu.Opts()
    own = mu.tce_builds("delay_line", opts, tmp_path)
    assert {b["name"] for b in own} >= {"n0", "n1_clear", "wide"} and all(b["top"] == "delay_line" for b in own)
    wide = next(b for b in own if b["name"] == "wide")
    assert wide["sets"] == [{"W": "60", "N": "5", "CLEAR": "0"}] and len(wide["hash"]) == 64
    n0 = next(b for b in own if b["name"] == "n0")
    assert n0["sets"] == [{"W": "8", "N": "0", "CLEAR": "0"}] and n0["hash"] != wide["hash"]
    assert mu.tce_builds("delay_line", opts, tmp_path) is own  # recorded once a run


def _equiv_by_recipe(module: str, mid: str, cfg, tmp_path, timeout: float | dict = 60, chain: bool = True) -> dict:
    """`module`'s mutant `mid` against rtl/'s under `cfg`'s parameters (the ones texture_pipeline gives
    it): yosys_equiv's verdict under each recipe alone, and under all of them in turn ('chain');
    timeout: seconds for every recipe, or {recipe: seconds} (the chain gets the largest)."""
    per = timeout if isinstance(timeout, dict) else {r: timeout for r in mu.RECIPES}
    import hdlbuild

    m = next(m for m in mu.draw(mu.all_sites([f"{module}.v"]), 1) if m.id == mid)
    rtl = mu.scratch_rtl(m, tmp_path / m.id)
    params = {k: int(v) if isinstance(v, bool) else v for k, v in hdlbuild.block_params(cfg, module).items()}
    files = mu.module_files(module)
    out = {r: mu.yosys_equiv(mu.RTL, rtl, module, files, params, per[r], recipes=(r,)) for r in mu.RECIPES}
    if chain:
        out["chain"] = mu.yosys_equiv(mu.RTL, rtl, module, files, params, max(per.values()))
    return out


@needs_yosys
def test_tce_recipes_prove_no_killed_mutant(tmp_path):
    """Mutants tb/tex_regs kills (make mutants N=100 SEED=1) differ in behaviour: no recipe proves
    them. 8d8a7c8b (pi < K -> pi <= K) looks like the loop bounds argued equivalent, but with no terms
    (random1202: NOISE_TERMS 0) its one iteration writes term 0's registers, which stay 0 otherwise;
    d86606c6 (csat_in_range's == -> !=) under full."""
    from model.hw.config import load_config, random_config

    for mid, cfg in (("8d8a7c8b", random_config(1202, name="random1202")), ("d86606c6", load_config("full"))):
        got = _equiv_by_recipe("tex_regs", mid, cfg, tmp_path)
        assert all(got[r][0] == "not proved" for r in mu.RECIPES), (mid, got)
        res, detail, recipe = got["chain"]
        assert (res, recipe) == ("not proved", "") and all(f"{r}: " in detail for r in mu.RECIPES), (mid, detail)


@needs_yosys
def test_tce_fallback_proves_tex_regs_survivors(tmp_path):
    """2767868f (tex_regs' wr_off = cfg_wr_addr[RL-1:0] -> [RL+1:0], cut to RL bits where assigned) and
    554fe7a8 (ri < 4 -> ri <= 4: the extra iteration's write is past rgba_wide and dropped, only the
    integer ri ends one higher, a loop temporary equiv_make does not match) are equivalent;
    equiv_struct -icells leaves $equiv cells unproven in tex_regs even unmutated, so the first recipe
    does not prove them and the register-only one (ffs) does."""
    from model.hw.config import load_config

    for mid in ("2767868f", "554fe7a8"):
        got = _equiv_by_recipe("tex_regs", mid, load_config("full"), tmp_path)
        assert got["icells"][0] == "not proved" and got["ffs"][0] == "proved", (mid, got)
        res, detail, recipe = got["chain"]
        assert (res, recipe) == ("proved", "ffs") and detail.endswith("(ffs)"), (mid, got["chain"])


@needs_yosys
def test_tce_rom_x_bits_are_a_difference(tmp_path):
    """noise_hash's permutation ROM (perm_rom, filled by an initial loop; a memory under reduced) is
    mapped to logic for the SAT solver with its x bits kept: 67c3291b (pi = 0 -> pi = 1) leaves entry
    0 unwritten, an x where the original holds PERM's first entry, and no recipe proves it (a timeout
    proves nothing either); b8dd487d
    (pi < 2^H -> pi <= 2^H: the extra write, past the ROM, is dropped) is proved."""
    from model.hw.config import load_config

    # (icells runs past 15 s on it, ffs finds the difference: neither proves it). ffs's bound is a
    # ceiling, not a speed test: under a load of 4 on the 2 cores (a fresh-clone make test beside
    # gate-level full and the mutants, stop 46) it passed 15 s; it ends as soon as it finds it.
    got = _equiv_by_recipe("noise_hash", "67c3291b", load_config("reduced"), tmp_path,
                           timeout={"icells": 15, "ffs": 300}, chain=False)
    assert all(got[r][0] != "proved" for r in mu.RECIPES) and "not proved" in {v[0] for v in got.values()}, got
    assert _equiv_by_recipe("noise_hash", "b8dd487d", load_config("reduced"), tmp_path)["chain"][0] == "proved"


def test_check_refusals_fails_when_a_check_is_wrong(tmp_path, monkeypatch):
    """hdlbuild.check_refusals, the idiom of the testbenches' test_<block>_check (the tests that
    kill mutants of the elaboration-time checks): it passes on a check that refuses what it should,
    and fails when a case meant to be accepted is refused, when one meant to be refused elaborates,
    and when a refusal comes from something other than the check (another module's check)."""
    import hdlbuild

    src = ["filter_width.v", "isqrt.v", "bitlen.v", "delay_line.v", "mul_pipe.v"]
    base = hdlbuild.block_params(hdlbuild.config_of("full"), "filter_width")
    err = "filter_width_unsupported_latency_or_widths"
    hdlbuild.check_refusals("filter_width", src, base, {"full": {}}, {"NORM_BITS 1": {"NORM_BITS": 1}}, err)
    with pytest.raises(AssertionError, match="accept 'n1'.*refused"):
        hdlbuild.check_refusals("filter_width", src, base, {"n1": {"NORM_BITS": 1}}, {}, err)
    with pytest.raises(AssertionError, match="refuse 'full'.*elaborated"):
        hdlbuild.check_refusals("filter_width", src, base, {}, {"full": {}}, err)
    # NORM_BITS 1 also trips isqrt's own check: with filter_width's check's `||` made `&&` between
    # its root-width terms (a scratch copy of rtl/, as make mutants builds), only isqrt refuses
    rtl = tmp_path / "rtl"
    shutil.copytree(hdlbuild.rtl_dir(), rtl)
    fw = rtl / "filter_width.v"
    text = fw.read_text()
    assert text.count("SQ_LAT > R_W || MH_W < 1") == 1
    fw.write_text(text.replace("SQ_LAT > R_W || MH_W < 1", "SQ_LAT > R_W && MH_W < 1"))
    monkeypatch.setenv("RTL_DIR", str(rtl))
    assert hdlbuild.rtl_dir() == rtl
    with pytest.raises(AssertionError, match="not by the check"):
        hdlbuild.check_refusals("filter_width", src, base, {}, {"NORM_BITS 1": {"NORM_BITS": 1}}, err)


def test_mutant_ids_are_unique():
    """Two identical lines of a file (the same text, column and change: 129 such pairs in rtl/ at
    stop 42, e.g. tex_regs.v's two `for (k = 0; k < KV; ...)` loops) are two mutants with two ids,
    so neither takes the other's cached verdict; the first one's id is what it was (line numbers
    stay out of the key, so an edit elsewhere in the file keeps every id)."""
    ms = [m for _, alts in mu.all_sites() for m in alts]
    ids = [m.id for m in ms]
    assert len(ids) == len(set(ids))
    dups = [m for m in ms if m.dup]
    assert dups, "rtl/ has repeated lines: some sites must carry an occurrence number"
    first = mu.Mutant(dups[0].file, 1, dups[0].col, dups[0].old, dups[0].new, dups[0].kind, dups[0].text)
    assert first.id in ids and first.id != dups[0].id
