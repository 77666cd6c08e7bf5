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
                  "--docs", str(doc), "--quiet"])
    res = json.loads((tmp_path / "out" / "results.json").read_text())
    (r,) = res["mutants"]
    assert (r["id"], r["kind"], r["result"]) == ("6f92a850", "stage", "killed") and r["by"].startswith("tb/fc_weight/")
    assert rc == 0 and res["summary"]["killed_share"] == 1.0
    line = next(i for i, x in enumerate((mu.RTL / "fc_weight.v").read_text().split("\n"), 1) if x.strip() == "v2  <= v1;")
    assert r["line"] == line  # the line moves with edits to fc_weight.v; the mutant's id does not
    assert f"| 6f92a850 | fc_weight.v:{line} | stage |" in doc.read_text() and "<!-- measured on:" in doc.read_text()
    assert not (tmp_path / "out" / "run" / "6f92a850").exists()  # the scratch copy is gone
