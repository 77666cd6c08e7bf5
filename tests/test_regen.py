"""`make regen` (app/regen.py): every stamped doc section has the job that writes it, the plan picks
the stale ones, and the lanes run jobs in order of their dependencies, a failed command failing its
job. The jobs themselves (hours of synthesis and simulation) are not run here: each is a command
tests/test_commands.py runs on a tiny input."""
from __future__ import annotations

import subprocess
import sys

from app import regen as R
from model.hw.config import ROOT, config_hash, load_config, rtl_source_hash


def test_every_stamped_section_has_its_job():
    """A doc section with a stamp that no job regenerates would stay stale after `make regen`; a job
    whose section has no stamp writes nothing the stamps check."""
    secs = R.stamped_sections()
    by_section = {}
    for j in R.jobs():
        assert j.section not in by_section, f"two jobs write {j.section}"
        by_section[j.section] = j.name
        assert j.commands and all(c.lstrip("-").startswith("make ") for c in j.commands), j
    assert len(secs) >= 12, secs.keys()
    assert set(secs) == set(by_section), (set(secs) ^ set(by_section))
    names = {j.name for j in R.jobs()}
    assert all(a in names for j in R.jobs() for a in j.after)


def test_stale_is_another_rtl_or_configuration():
    now = rtl_source_hash()
    assert not R.is_stale({"rtl": now})
    assert R.is_stale({"rtl": "0" * 12})
    assert R.is_stale({"full": "0" * 12, "rtl": now})
    assert not R.is_stale({"not_a_config": "0" * 12, "rtl": now})
    # a candidate (config/candidates/<name>.toml) is checked as the named ones are: docs quote them
    cand = load_config(ROOT / "config" / "candidates" / "compact_q6c4_s4.toml")
    assert not R.is_stale({"compact_q6c4_s4": config_hash(cand), "rtl": now})
    assert R.is_stale({"compact_q6c4_s4": "0" * 12, "rtl": now})
    assert "compact_q6c4_s4 000000000000, now " in R.banner_text({"compact_q6c4_s4": "0" * 12, "rtl": now}, ("make x",))
    # the plan: every job with --all, the longest first; --only by name
    allj = R.plan(all_=True)
    assert len(allj) == len(R.jobs()) and [j.minutes for j in allj] == sorted((j.minutes for j in allj), reverse=True)
    assert [j.name for j in R.plan(only=["frames", "synth"])] == ["synth", "frames"]


def test_lanes_keep_the_order_and_report_failures(tmp_path):
    """Two lanes: b waits for a (its `after`) though it is the longer; c's first command fails as
    expected ("-"), its second fails and its third never runs; every job's output is in its log."""
    sec = ("x.md", None)
    todo = [R.Job("b", sec, ("echo b-ran",), 5, after=("a",)),
            R.Job("c", sec, ("-false", "false", "touch " + str(tmp_path / "never")), 3),
            R.Job("a", sec, ("sleep 0.3", "echo a-ran"), 1)]
    res = {r["job"]: r for r in R.run(todo, 2, progress=False, logs=tmp_path)}
    assert res["a"]["rc"] == 0 and res["b"]["rc"] == 0 and res["c"]["rc"] != 0 and res["c"]["failed"] == "false" and "expected" in (tmp_path / "c.log").read_text()
    assert res["b"]["start"] >= res["a"]["end"]
    assert not (tmp_path / "never").exists()
    assert "a-ran" in (tmp_path / "a.log").read_text() and "b-ran" in (tmp_path / "b.log").read_text()


def test_make_regen_dry_run_and_bad_input():
    r = subprocess.run(["make", "-s", "--no-print-directory", "regen", "REGEN_FLAGS=--dry-run --all"], cwd=ROOT,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert [x.split()[0] for x in r.stdout.splitlines() if x.strip()] == [j.name for j in R.plan(all_=True)]
    bad = subprocess.run([sys.executable, "-m", "app.regen", "--only", "synth,nope"], cwd=ROOT, capture_output=True,
                         text=True, timeout=60)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "no job nope" in bad.stderr, bad.stderr
    bad = subprocess.run([sys.executable, "-m", "app.regen", "--jobs", "0"], cwd=ROOT, capture_output=True,
                         text=True, timeout=60)
    assert bad.returncode == 2 and "--jobs 0" in bad.stderr, bad.stderr


def test_mark_marks_stale_sections_and_unmarks_current_ones(tmp_path, monkeypatch):
    """A doc of two stamped sections, one measured on another rtl/: --mark puts the banner under that
    section's heading only (naming both hashes and its command), is idempotent, and takes it away
    once the section's stamp names today's rtl/ (as a rerun of its command would write it)."""
    now = rtl_source_hash()
    doc = tmp_path / "verification.md"
    text = ("# Verification\n\n## Formal\n\nproved.\n\n<!-- measured on: rtl=000000000000 -->\n\n"
            "## Mutants\n\nkilled.\n\n<!-- measured on: rtl=" + now + " -->\n")
    doc.write_text(text)
    monkeypatch.setattr(R, "DOCS", tmp_path)
    assert R.mark() == [("verification.md", "Formal")]
    lines = doc.read_text().splitlines()
    assert lines[2:5] == ["## Formal", "", R.banner_text({"rtl": "000000000000"}, ("make formal",))]
    assert "000000000000" in lines[4] and now in lines[4] and "`make formal`" in lines[4]
    assert sum(x.startswith(R.BANNER) for x in lines) == 1 and R.banners() == {("verification.md", "Formal"): lines[4]}
    once = doc.read_text()
    R.mark()
    assert doc.read_text() == once
    doc.write_text(once.replace("rtl=000000000000", "rtl=" + now))
    assert R.mark() == [] and doc.read_text() == text.replace("rtl=000000000000", "rtl=" + now)


def test_validate_commands_name_configurations_that_load():
    """Each `make validate CONFIG=...` line of docs/validation.md (what the validate job reruns) names a
    configuration the command loads: config/<name>.toml by its name, a candidate by its path (stop 52: a
    candidate's section named it by its name alone, and the job failed)."""
    cmds = R._validate_commands()
    assert len(cmds) > 1
    for c in cmds:
        load_config(c.split("CONFIG=", 1)[1].split()[0])
