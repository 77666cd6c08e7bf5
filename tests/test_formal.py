"""The formal proofs (formal/run.py, `make formal`): the quick tasks prove here, planted bugs make
them fail, and docs/verification.md lists every task as `make formal` last ran it.

Quick tasks (Task.quick): one or two parameter sets of each block, each a few seconds; the rest
(and the slow sets) run in `make formal`. Each job runs in pytest's tmp_path (not build/formal/,
which `make formal` may be using).
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from formal.run import DOC, SECTION, run_task, tasks

ROOT = Path(__file__).resolve().parents[1]
TASKS = {t.name: t for t in tasks()}
QUICK = [n for n, t in TASKS.items() if t.quick]


@pytest.mark.parametrize("name", QUICK)
def test_quick_proof(name, tmp_path):
    r = run_task(TASKS[name], workdir=tmp_path)
    assert r.status == "PASS", f"{name}: {r.status}\n{r.log.read_text()[-3000:]}"


# (task, file, text in the RTL, the planted bug, the status it must give)
PLANTED = {
    # the temporary register drops the beat it should keep while the output is stalled
    "skid_drops_a_beat": ("axis_skid.stream", "axis_skid.v", "temp_valid_next  = s_axis_tvalid;",
                          "temp_valid_next  = 1'b0;", "FAIL"),
    # the output register takes the next beat while the output is stalled (overwrites one)
    "skid_overwrites": ("axis_skid.stream", "axis_skid.v", "if (m_axis_tready || !m_valid_reg) begin",
                        "if (1'b1) begin", "FAIL"),
    # s_axis_tready through logic from m_axis_tready: a logic loop in the wrapper
    "skid_comb_ready": ("axis_skid.ready_path", "axis_skid.v", "assign s_axis_tready = s_ready_reg;",
                        "assign s_axis_tready = s_ready_reg && m_axis_tready;", "ERROR"),
    # the last term of a pixel issued with a = 0 (a term skipped)
    "fold_skips_a_term": ("noise_fold.compact", "noise_fold.v", "a_sel = (m*U + gu < k_used)",
                          "a_sel = (m*U + gu + 1 < k_used)", "FAIL"),
    # in_ready only when empty (a pixel every P + 1 slots: not the header's rule)
    "fold_in_ready": ("noise_fold.compact", "noise_fold.v", "assign in_ready = !busy_reg || at_last;",
                      "assign in_ready = !busy_reg;", "FAIL"),
    # the pixel taken with its first sample, not its last
    "expand_takes_early": ("sample_expand.s4", "sample_expand.v", "assign in_ready  = out_ready && last;",
                           "assign in_ready  = out_ready;", "FAIL"),
    # the sample index steps on a clock without ce
    "expand_ignores_ce": ("sample_expand.s2", "sample_expand.v", "    else if (ce && in_valid && out_ready)",
                          "    else if (in_valid && out_ready)", "FAIL"),
    # the average truncated instead of rounded half up
    "average_truncates": ("sample_average.s2", "sample_average.v", "wire [A_W-1:0] rnd  = sum + HALF;",
                          "wire [A_W-1:0] rnd  = sum;", "FAIL"),
}


@pytest.mark.parametrize("bug", sorted(PLANTED))
def test_planted_bug_fails(bug, tmp_path):
    task, fname, old, new, want = PLANTED[bug]
    src = (ROOT / "rtl" / fname).read_text()
    assert src.count(old) == 1, f"{bug}: '{old}' is not in rtl/{fname} once (update the planted bug)"
    r = run_task(TASKS[task], override={fname: src.replace(old, new)}, workdir=tmp_path)
    assert r.status == want, f"{bug}: {task} gave {r.status}, expected {want}\n{r.log.read_text()[-3000:]}"


def test_doc_lists_every_task():
    """docs/verification.md's Formal section has a row per task, each PASS, with its mode and depth."""
    text = DOC.read_text()
    assert SECTION in text
    section = text.split(SECTION, 1)[1]
    for name, t in TASKS.items():
        m = re.search(rf"^\| `{re.escape(name)}` \|.*\| (\w+) \| (\d+) \| (\w+) \| [\d.]+ \| (?:yes)? \|$", section, flags=re.M)
        assert m, f"docs/verification.md: no row for {name} (rerun make formal)"
        assert (m.group(1), int(m.group(2)), m.group(3)) == (t.mode, t.depth, "PASS"), f"{name}: {m.groups()}"


def test_rtl_yosys_misreads_is_an_error(tmp_path):
    """A name Yosys does not resolve as the simulators do (a reference into a generate block declared further
    down, as tests/data/forward_ref.v has; here planted in axis_skid) makes the job an ERROR, not a proof of
    other logic (formal/run.py, hdlbuild READ_ERRORS)."""
    src = (ROOT / "rtl" / "axis_skid.v").read_text()
    assert src.count("\nendmodule") == 1
    plant = ("generate\n    if (1) begin : g_use\n        wire v = g_def.r;\n    end\n"
             "    if (1) begin : g_def\n        reg r;\n        always @(posedge clk) r <= 1'b0;\n    end\nendgenerate\n")
    r = run_task(TASKS["axis_skid.stream"], override={"axis_skid.v": src.replace("\nendmodule", "\n" + plant + "endmodule")},
                 workdir=tmp_path)
    assert r.status == "ERROR" and "implicitly declared" in r.log.read_text(), r.log.read_text()[-2000:]
