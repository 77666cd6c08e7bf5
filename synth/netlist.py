"""The synthesized netlists of a configuration as Verilog, for gate-level simulation (`make gls`).

Each piece `make synth` counts (synth/run.py block_jobs: quadric_mac, noise_term, filter_width,
colour_map, fc_weight and fc_scale with sat_fc, and the control: texture_pipeline with its glue
flattened and the blocks as black boxes) is synthesized by synth_one, the same script, with
`--keep`: synth.py then writes the mapped netlist with `write_verilog -noattr` after its last step
(liberty-mapped, flattened). The netlists hold:
  - instances of the liberty cells of synth/cells.lib: their simulation models (cells_model(),
    build/gls/cells_sim.v) are written by Yosys itself from the liberty functions
    (`read_liberty` without -lib, `write_verilog -noattr`): plain Verilog (assigns, and always
    blocks for the flip-flops), no Yosys simulation library needed;
  - the RAMs left as macros ($mem_v2), which write_verilog writes as Verilog arrays;
  - in the control's netlist, the blocks' instances, with the parameters texture_pipeline gives
    them: each is checked against the parameter set that block's netlist was synthesized with
    (hdlbuild block_params), then dropped (a netlist module has no parameters).
Netlists are cached in build/gls/<config>/<label>/ under a stamp of the RTL, the flow and the
parameters; netlists(config) returns every file a simulation of the configuration's netlists needs.
"""
from __future__ import annotations

import hashlib
import re
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from hdlbuild import ROOT, block_params, config_of, write_if_changed
from synth.run import SynthError, block_jobs, synth_one
from synth.synth import DEFAULT_LIBERTY, find_yosys

GLS_DIR = ROOT / "build" / "gls"
# a black-box instance in write_verilog's output: `  name #(\n    .P(v),\n  ...  ) inst (`
# (an escaped instance name, \\a.b[0].c, ends with a space)
INSTANCE = re.compile(r"\n  (\w+) #\(\n((?:    \.\w+\([^\n]*\),?\n)*)  \) (\\\S+ |\S+) \(")
PARAM = re.compile(r"\.(\w+)\(([^\n]*)\),?")
LITERAL = re.compile(r"^(-?)(\d+)'(s?)([dhbo])([0-9a-fA-F_xzXZ]+)$")


def verilog_int(text) -> int:
    """A Verilog number as write_verilog writes it (32'd6, 32'sd22, 1024'h..) or a Python int."""
    if isinstance(text, int):
        return text
    s = str(text).strip()
    if re.fullmatch(r"-?\d+", s):
        return int(s)
    m = LITERAL.match(s)
    if not m:
        raise SynthError(f"gls: cannot read the Verilog number {s!r}")
    neg, width, signed, base, digits = m.groups()
    v = int(digits.replace("_", ""), {"d": 10, "h": 16, "b": 2, "o": 8}[base])
    if signed and base != "d" and v >> (int(width) - 1):
        v -= 1 << int(width)
    return -v if neg else v


def _hash(*parts) -> str:
    h = hashlib.sha256()
    for p in parts:
        h.update(p.read_bytes() if isinstance(p, Path) else repr(p).encode())
    return h.hexdigest()


def _flow_files() -> list[Path]:
    return [*sorted((ROOT / "rtl").glob("*.v")), *sorted((ROOT / "rtl").glob("*.vh")),
            ROOT / "synth" / "synth.py", ROOT / "synth" / "run.py", Path(DEFAULT_LIBERTY)]


def cells_model() -> Path:
    """build/gls/cells_sim.v: Verilog models of synth/cells.lib's cells, written by Yosys from the
    liberty file's functions (rewritten when the liberty file changes)."""
    out = GLS_DIR / "cells_sim.v"
    stamp = GLS_DIR / "cells_sim.stamp"
    want = _hash(Path(DEFAULT_LIBERTY))
    if out.exists() and stamp.exists() and stamp.read_text() == want:
        return out
    yosys = find_yosys()
    if yosys is None:
        raise SynthError("gls: yosys not found (make setup)")
    GLS_DIR.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".tmp.v")
    r = subprocess.run([yosys, "-q", "-p", f"read_liberty {DEFAULT_LIBERTY}; write_verilog -noattr {tmp}"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise SynthError(f"gls: yosys could not write the cell models: {(r.stdout + r.stderr).strip()[-200:]}")
    tmp.replace(out)
    stamp.write_text(want)
    return out


def default_param(mod: str, name: str) -> int:
    """A parameter's default in rtl/<mod>.v (a number: what an instance that leaves it out gets)."""
    src = (ROOT / "rtl" / f"{mod}.v").read_text()
    m = re.search(rf"\bparameter\s+(?:integer\s+)?{name}\s*=\s*([^,;)\s/]+)", src)
    if not m:
        raise SynthError(f"gls: no default of parameter {name} in rtl/{mod}.v")
    return verilog_int(m.group(1))


def strip_instances(text: str, cfg) -> tuple[str, list[str]]:
    """The control's netlist with each black-box block instance's parameters checked against
    block_params(cfg, block) (SynthError on a difference) and dropped; also the blocks' names."""
    seen = []

    def repl(m):
        mod, body, inst = m.group(1), m.group(2), m.group(3)
        want = {k: verilog_int(v) for k, v in block_params(cfg, mod).items()}
        got = {k: verilog_int(v) for k, v in PARAM.findall(body)}
        # a parameter left out on either side is at its default
        got = {**{k: default_param(mod, k) for k in want if k not in got}, **got}
        want = {**{k: default_param(mod, k) for k in got if k not in want}, **want}
        if got != want:
            diff = sorted(k for k in set(got) | set(want) if got.get(k) != want.get(k))
            raise SynthError(f"gls: {cfg.name}: texture_pipeline's {mod} instance {inst} has parameters {diff} "
                             f"other than its netlist's (hdlbuild block_params)")
        seen.append(mod)
        return f"\n  {mod} {inst} ("

    return INSTANCE.sub(repl, text), seen


def block_netlist(config, label: str) -> Path:
    """The Verilog netlist of one piece of `make synth`'s count (a label of block_jobs), for
    simulation: build/gls/<config>/<label>/netlist_sim.v (synthesized unless the cache is current)."""
    cfg = config_of(config)
    mod, lib = block_jobs(cfg)[label]
    keep = GLS_DIR / cfg.name / label
    out = keep / "netlist_sim.v"
    stamp = keep / "netlist.stamp"
    want = _hash(*_flow_files(), mod, sorted(block_params(cfg, mod).items()), [Path(f).name for f in lib])
    if out.exists() and stamp.exists() and stamp.read_text() == want:
        return out
    keep.mkdir(parents=True, exist_ok=True)
    synth_one(cfg, mod, lib, out=keep / "report.json", keep=keep)
    text = (keep / "netlist.v").read_text()
    if lib:
        text, blocks = strip_instances(text, cfg)
        if not blocks:
            raise SynthError(f"gls: {cfg.name}: no block instance found in texture_pipeline's netlist")
    if "#(" in text:
        raise SynthError(f"gls: {cfg.name}: {label}'s netlist still instantiates a module with parameters")
    write_if_changed(out, text)
    stamp.write_text(want)
    return out


def netlists(config, jobs: int = 2) -> list[Path]:
    """Every file a simulation of the configuration's synthesized pipeline needs in place of rtl/:
    the cell models and each piece's netlist (hdlbuild netlist_wrapper is the top's wrapper)."""
    cfg = config_of(config)
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as ex:
        files = list(ex.map(lambda label: block_netlist(cfg, label), block_jobs(cfg)))
    return [cells_model(), *files]
