"""Verilog includes generated from a configuration (tables the RTL must not type in).

`python -m model.hw.gen_rtl CONFIG OUTDIR` writes every generated file into OUTDIR: tex_cfg.vh
(the widths, model/hw/config.py verilog_header) and perm_rom.vh: the lattice hash
permutation of the configuration (model/hw/config.py permutation(), 2^hash_bits entries)
as a ROM (constant array perm_rom) read by the function `perm_lookup`. rtl/noise_hash.v
includes it inside its module body; hdlbuild.gen_dir() regenerates both in
build/gen/<config>/. This module is the one writer of generated files (`python -m
model.hw.config NAME OUT_DIR` calls it).
"""
from __future__ import annotations

import os
import threading
import sys
from pathlib import Path

from model.hw.config import Config, ConfigError, _rel, load_config, verilog_header


def perm_rom(cfg: Config) -> str:
    """The permutation table as a constant array `perm_rom` and `function perm_lookup(idx)`.

    A ROM: a reg array written only by its initial block (the one kind of initial
    block the RTL conventions allow). Simulators index it directly (a case function
    becomes a 2^H-leaf decision tree per call in Verilator's C++); Yosys turns it into
    a $mem without write ports, mapped to logic. No include guard: it is included
    inside a module body, once per module that uses it. Widths are the
    `CFG_HASH_BITS define of tex_cfg.vh (include it first).
    """
    hb = cfg.hash_bits
    n = 1 << hb
    lines = [
        f"// Generated from {_rel(cfg.path)} by model/hw/gen_rtl.py. Do not edit.",
        f"// Configuration: {cfg.name}. Lattice hash permutation perm[0..{n - 1}] (seed {cfg.seed}) as a",
        "// ROM (constant array) and its read function. Included inside a module body; needs tex_cfg.vh.",
        f"reg [`CFG_HASH_BITS-1:0] perm_rom [0:{n - 1}];",
        "initial begin",
    ]
    for i, v in enumerate(cfg.perm):
        lines.append(f"    perm_rom[{i}] = {hb}'d{int(v)};")
    lines += [
        "end",
        "",
        "function [`CFG_HASH_BITS-1:0] perm_lookup;",
        "    input [`CFG_HASH_BITS-1:0] idx;",
        "    begin",
        "        perm_lookup = perm_rom[idx];",
        "    end",
        "endfunction",
    ]
    return "\n".join(lines) + "\n"


# file name -> generator
GENERATED = {"tex_cfg.vh": verilog_header, "perm_rom.vh": perm_rom}


def write(cfg: Config, outdir) -> list[Path]:
    """Write every generated include of `cfg` into outdir (only files whose text changed)."""
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, gen in GENERATED.items():
        text = gen(cfg)
        p = out / name
        if not p.exists() or p.read_text() != text:
            # parallel writers (processes and threads): each its own temporary, atomic rename
            tmp = p.with_suffix(p.suffix + f".{os.getpid()}.{threading.get_ident()}")
            tmp.write_text(text)
            tmp.replace(p)
        written.append(p)
    return written


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2:
        print("usage: python -m model.hw.gen_rtl CONFIG OUTDIR", file=sys.stderr)
        return 2
    try:
        cfg = load_config(argv[0])
    except ConfigError as e:
        print(f"gen_rtl: {e}", file=sys.stderr)
        return 2
    write(cfg, argv[1])
    return 0


if __name__ == "__main__":
    sys.exit(main())
