"""sim/profile.py: where a simulated clock goes. The profiles themselves take minutes (perf, valgrind);
here, their bad input and the attribution of the generated C++ to pipeline blocks."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from sim import profile

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("argv, expected", [
    (["--instructions", "--plus", "NBA_ONLY=0"], "--plus 'NBA_ONLY=0'"),
    (["--instructions", "--pixels", "0"], "--pixels 0"),
])
def test_bad_input_one_line_exit_2(argv, expected):
    """A bad argument is one line and exit status 2, before anything is built."""
    r = subprocess.run([sys.executable, "-m", "sim.profile", *argv], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and expected in r.stderr, (r.returncode, r.stderr)


def test_blocks_give_each_line_its_block(tmp_path):
    """A line of the model's C++ goes to the instance under texture_pipeline its statement names (a
    statement spread over lines included), the harness's own signals to the harness, Verilator's
    helpers and the start-up to their own rows, anything else to 'other'."""
    (tmp_path / "Vframe_tb___024root__0.cpp").write_text("\n".join([
        "    vlSelfRef.frame_tb__DOT__u_pipe__DOT__u_pipe__DOT__u_colour_map__DOT__x_reg",
        "        = 3U;",
        "    vlSelfRef.frame_tb__DOT__out_idx = 1U;",
        "    vlSelfRef.frame_tb__DOT__u_pipe__DOT__u_pipe__DOT__ce = 1U;",
        "    __Vtemp_1 = 0U;",
    ]) + "\n")
    block = profile._Blocks(tmp_path)
    where = str(tmp_path / "Vframe_tb___024root__0.cpp")
    assert [block(where, n) for n in (1, 2, 3, 4, 5)] == [
        "u_colour_map", "u_colour_map", "frame_tb (the harness)", "texture_pipeline (its own logic)",
        "Verilator's temporaries and scheduler"]
    assert block("/x/include/verilated_funcs.h", 294) == profile.FUNCS
    assert block("./string/../sysdeps/x86_64/multiarch/memset-vec-unaligned-erms.S", 1).startswith("start-up")
    assert block("???", 0) == "other"
