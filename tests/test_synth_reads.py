"""What `make synth` reads for a block (synth.run.block_files, stop 45): the block's module closure and nothing
else, so its gates move only when its own files do (read with all of rtl/, a block moved by about 1% whenever an
unrelated file changed: Yosys numbers cells across every file it reads, and ABC follows the numbering), and
explore.measure's netlist cache key covers exactly the files synth_one reads."""
from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from hdlbuild import ROOT, rtl_modules
from model.hw.config import CONFIG_NAMES, load_config
from synth import run as synth_run


def _blocks():
    return sorted({m for c in CONFIG_NAMES for m in synth_run.config_blocks(load_config(c)).values()})


@pytest.mark.parametrize("top", _blocks())
def test_block_files_are_its_closure(top):
    """Every module a listed file instantiates is defined in the list, and every listed file is needed (the
    top's, or instantiated by a listed one)."""
    mods = rtl_modules(ROOT / "rtl")
    files = [Path(f) for f in synth_run.block_files(top)]
    defined = {m for m, p in mods.items() if p in files}
    assert mods[top] in files
    used = {top}
    for f in files:
        text = f.read_text()
        inst = {n for n in mods if re.search(rf"^\s*{n}\s*(#|\w+\s*\()", text, re.M)} - {m for m, p in mods.items() if p == f}
        assert inst <= defined, (f.name, sorted(inst - defined))
        used |= inst
    assert {mods[m] for m in used} == set(files)


def test_colour_map_does_not_read_the_noise_unit():
    names = {Path(f).name for f in synth_run.block_files("colour_map")}
    assert "cmap_sat.v" in names and "noise_term.v" not in names and "isqrt.v" not in names


def test_synth_one_reads_block_files(monkeypatch, tmp_path):
    """synth_one hands synth.py exactly block_files(top) (a block) or the top and its glue (control)."""
    seen = []

    def fake_run(cmd, capture_output=True, text=True):
        seen.append(cmd)
        out = Path(cmd[cmd.index("--json") + 1])
        out.write_text(json.dumps({"ge_total": 1.0}))

        class R:
            returncode, stderr = 0, ""
        return R()

    monkeypatch.setattr(synth_run.subprocess, "run", fake_run)
    synth_run.synth_one("compact", "filter_width", out=tmp_path / "fw.json")
    cmd = seen[-1]
    files = cmd[cmd.index("--files") + 1:cmd.index("--include")]
    assert files == synth_run.block_files("filter_width")
    assert len(files) < len(synth_run.rtl_files())


def test_explore_cache_key_covers_what_is_read():
    from explore.measure import module_closure

    files = {str(p) for p in module_closure("colour_map") if p.suffix == ".v"}
    assert files == set(synth_run.block_files("colour_map"))
