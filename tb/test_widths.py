"""The widths the RTL elaborates to equal the Python derivation (model/hw/config.py _derive).

The RTL gets only a configuration's keys as parameters and derives every word width itself
(rtl/tex_widths.vh); the golden model derives them in Python. For both configurations and
for random valid configurations, this test elaborates the configuration's top
(build/gen/<name>/texture_unit.v) and a noise_term with the parameters texture_pipeline
gives it under Icarus, reads every derived width back from the elaborated instances
(hierarchical references to their localparams, printed by $display), and compares each
with the Python value. A differing width is a derivation written twice that drifted apart.

Configurations with per-term exponents (formats.t_exp_w, a_exp_w > 0: tb.pipe.exponent_configs):
every width too, through the whole top (an_w, h_w, ag_w, f_w, c_w take the largest exponents).

Environment: RANDOM_WIDTH_CONFIGS (default 10) random configurations, RANDOM_SEED picks
another set.
"""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

import hdlbuild
from hdlbuild.params import block_params
from tb import pipe

# Python key -> elaborated name: under the top (texture_unit.u_pipe), or the stand-alone
# noise_term (nt) and cmap_sat (cs), which exist for every configuration (also without noise
# terms, or with another filter family)
TOP = "u.u_pipe"
TS = f"{TOP}.u_texture_sum"  # f and grad f: the quadric, the noise leaves, the adder trees
WIDTHS = {
    "v_w": f"{TS}.u_quadric_mac.V_W", "qv_w": f"{TS}.u_quadric_mac.QV_W", "qf_w": f"{TS}.u_quadric_mac.QF_W",
    "p_w": "nt.P_W", "o_w": "nt.O_W", "ts_shift": "nt.TS_SHIFT", "n_w": "nt.N_W", "gn_w": "nt.GN_W",
    "blend_w": "nt.BW", "an_shift": "nt.AN_SHIFT", "an_w": "nt.AN_W", "h_shift": "nt.H_SHIFT", "h_w": "nt.H_W",
    "ag_w": "nt.AG_W", "te_max": "nt.TE_MAX", "ae_max": "nt.AE_MAX",
    "f_w": f"{TOP}.F_W", "c_w": f"{TOP}.C_W", "n_log2_w": f"{TOP}.NL_W",
    "g_w": f"{TOP}.u_filter_width.G_W", "gabs_w": f"{TOP}.u_filter_width.GABS_W",
    "l_w": f"{TOP}.u_filter_width.L_W", "r_w": f"{TOP}.u_filter_width.R_W", "sh_w": f"{TOP}.u_filter_width.SH_W",
    "e_w": f"{TOP}.u_filter_width.E_W", "w_w": f"{TOP}.u_filter_width.W_W",
    "u_w": f"{TOP}.u_colour_map.U_W", "x_w": "cs.X_W", "x_frac": "cs.XF",
    "csat_w": f"{TOP}.u_colour_map.CS_W", "d_w": "cs.D_W",
    "fc_af": f"{TS}.FC_AF",
}
# the trapezoid's words (filter "sat2"), from a stand-alone cmap_sat2 (c2), built where they fit
# its 62-bit limit (the configuration check refuses sat2 beyond it)
SAT2_WIDTHS = {"x2_w": "c2.X_W", "csat2_w": "c2.CS2_W", "d2_w": "c2.D_W", "w2_w": "c2.WD_W"}
# the same word derived where it crosses between blocks: that copy (the top's, texture_sum's)
# must agree
CROSS = {"qf_w": f"{TS}.QF_W", "an_w": f"{TS}.u_noise_leaves.AN_W", "ag_w": f"{TS}.u_noise_leaves.AG_W",
         "o_w": f"{TOP}.O_W", "f_w": f"{TS}.F_W", "c_w": f"{TS}.C_W",
         "w_w": f"{TOP}.W_W", "csat_w": f"{TOP}.CSAT_W", "n_log2_w": f"{TOP}.u_filter_width.N_LOG2_W"}


def _configs():
    n = int(os.environ.get("RANDOM_WIDTH_CONFIGS", "10"))
    base = int(os.environ.get("RANDOM_SEED", "12")) * 100 + 50
    return list(hdlbuild.CONFIGS) + [f"random:{base + i}" for i in range(n)]


def elaborated_widths(config) -> dict:
    """{name: value} of every entry of WIDTHS and CROSS, read from the elaborated RTL."""
    if shutil.which("iverilog") is None:
        raise RuntimeError("iverilog: not found on PATH (run `make setup`)")
    cfg = hdlbuild.config_of(config)
    nt = block_params(cfg, "noise_term")
    nt_probe = "noise_term #(" + ", ".join(f".{k}({v})" for k, v in nt.items()) + ") nt ();"
    gdir = hdlbuild.gen_dir(cfg)
    sat2 = cfg.d2_w <= 62
    names = {**WIDTHS, **(SAT2_WIDTHS if sat2 else {}), **{f"{k}@top": v for k, v in CROSS.items()}}
    probe = ["module width_probe;", "texture_unit u ();", nt_probe,
             f"cmap_sat #(.F_FRAC({cfg.f_frac}), .W_CAP_LOG2({cfg.w_cap_log2}), .N_LOG2_MAX({cfg.n_log2_max}), "
             f".DIV_BITS({cfg.div_bits}), .FPGA_REGS({int(cfg.fpga_regs)})) cs ();"]
    if sat2:
        probe.append(f"cmap_sat2 #(.F_FRAC({cfg.f_frac}), .W_CAP_LOG2({cfg.w_cap_log2}), "
                     f".N_LOG2_MAX({cfg.n_log2_max}), .DIV_BITS({cfg.div_bits})) c2 ();")
    return _elaborate(cfg, probe, names, [str(gdir / "texture_unit.v")])


def _elaborate(cfg, probe: list, names: dict, gen: list) -> dict:
    """Elaborate the probe module's instances (`probe`: its lines so far) with rtl/ and the
    generated sources `gen` under Icarus, and read every entry of `names` back."""
    probe = probe + ["initial begin"]
    probe += [f'    $display("{k} %0d", {v});' for k, v in names.items()]
    probe += ["end", "endmodule", ""]
    bdir = hdlbuild.ROOT / "build" / "widths" / cfg.name
    bdir.mkdir(parents=True, exist_ok=True)
    (bdir / "width_probe.v").write_text("\n".join(probe))
    vvp = bdir / "probe.vvp"
    srcs = [str(bdir / "width_probe.v"), *gen] + sorted(str(p) for p in hdlbuild.RTL_DIR.glob("*.v"))
    # unconnected ports: the probe only elaborates (-Wnone: no port warnings)
    r = subprocess.run(["iverilog", "-g2005", "-Wnone", "-o", str(vvp), "-s", "width_probe", f"-I{hdlbuild.RTL_DIR}",
                        *srcs], capture_output=True, text=True)
    assert r.returncode == 0, f"{cfg.name}: iverilog failed:\n{r.stderr[-2000:]}"
    out = subprocess.run(["vvp", "-n", str(vvp)], capture_output=True, text=True, check=True).stdout
    got = {}
    for line in out.splitlines():
        k, _, v = line.partition(" ")
        if k in names:
            got[k] = int(v)
    assert set(got) == set(names), f"{cfg.name}: not printed: {sorted(set(names) - set(got))}"
    return got


@pytest.mark.parametrize("config", _configs())
def test_rtl_widths_equal_python(config):
    cfg = hdlbuild.config_of(config)
    got = elaborated_widths(cfg)
    bad = [f"{k}: RTL {got[k]}, Python {cfg.d[k]}" for k in (*WIDTHS, *SAT2_WIDTHS) if k in got and got[k] != cfg.d[k]]
    bad += [f"{k} (the copy at {CROSS[k]}): RTL {got[k + '@top']}, Python {cfg.d[k]}" for k in CROSS
            if got[k + "@top"] != cfg.d[k]]
    assert not bad, f"{cfg.name}: derived widths differ:\n  " + "\n  ".join(bad)


@pytest.mark.parametrize("name", [n for n, _ in pipe.exponent_configs(1361)])
def test_widths_with_exponents(name):
    """With per-term exponents: every width of the top and the stand-alone blocks equals the
    Python derivation's (an_w, h_w, ag_w, f_w, c_w take the largest exponents), and so do the
    copies where the words cross between blocks."""
    test_rtl_widths_equal_python(dict(pipe.exponent_configs(1361))[name])


# derived values the RTL has no word for: the model's own checks and bounds
MODEL_ONLY = {
    "fc_ks": "a value, not a width: hdlbuild passes it to the RTL as FC_KS (top_params)",
    "w_cap": "the saturated w, a value (filter_width and colour_map use W_CAP_LOG2 + F_FRAC)",
    "widest_product": "the int64 check of the golden model",
    "je_min": "the range of je (the RTL's je is a JE_W-bit word)",
    "je_max": "the range of je",
    "i_w": "the integral I(x) is never formed whole: colour_map forms D = I(b) - I(a) mod 2^D_W",
    "u_guard": "colour_map's clamp guard, a value (2^GUARD: W/2, sat2 W)",
}


def test_every_derived_width_is_checked():
    """Each width model/hw/config.py derives is read back from the RTL, or named model-only."""
    d = hdlbuild.config_of("full").d
    assert set(d) == set(WIDTHS) | set(SAT2_WIDTHS) | set(MODEL_ONLY), (
        f"derived but not checked: {sorted(set(d) - set(WIDTHS) - set(MODEL_ONLY))}; "
        f"checked but not derived: {sorted((set(WIDTHS) | set(SAT2_WIDTHS) | set(MODEL_ONLY)) - set(d))}")
