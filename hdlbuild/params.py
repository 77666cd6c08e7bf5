"""The Verilog parameters of a configuration: the top's parameter set and each block's.

A configuration reaches the RTL only as parameters. `top_params(cfg)` is the parameter set
of `texture_pipeline` (one parameter per configuration key, enums as integers, and the
lattice permutation PERM); `texture_unit_source(cfg)` is the generated wrapper module
`texture_unit`, texture_pipeline with those values, that harnesses and flows instantiate.
`block_params(cfg, module)` is what texture_pipeline passes to one of its blocks, for the
blocks' own testbenches and gate counts. Every derived width the blocks need is derived
inside the RTL (rtl/tex_widths.vh); model/hw/config.py derives the same in Python, and
tb/test_widths.py checks that the two agree.
"""
from __future__ import annotations

import re

from model.hw.config import FC_KSF, ROOT, SAT_FILTERS, Config, cmap_family, folded, freq_clamp, rel_path, sum_tree_levels
from model.hw.config import latency as config_latency
from model.hw.regmap import REGMAP, pix_width

# config/<name>.toml enum values as the RTL's integer parameters
ENUMS = {
    "quadric": {"full": 0, "diagonal": 1},
    "blend": {"linear": 0, "cubic": 1},
    "transform": {"affine": 0, "pow2": 1},
    "amplitude": {"any": 0, "pow2": 1},
    "filter": {"none": 0, "sat": 1, "mip": 2, "sat_fc": 3, "sat2": 4, "sat2_fc": 5},
}
# configuration keys that are parameters of texture_pipeline (all of them but hash.seed, which
# reaches it as the permutation PERM, and the exponents' widths t_exp_w, a_exp_w: exponent_params)
TOP_KEYS = ("quadric", "quadric_clocks", "noise_terms", "noise_units", "blend", "transform", "amplitude", "filter", "noise_gradient",
            "s_w", "s_frac", "q_w", "q_frac", "j_w", "je_w", "t_w", "t_frac", "a_w", "a_frac", "p_frac",
            "hash_bits", "n_frac", "f_frac", "c_frac", "norm_bits", "w_cap_log2", "div_bits", "n_log2_max",
            "fc_log_frac", "fc_knee", "fc_fade_log2", "fpga_regs")

# texture_pipeline's ports: (direction, width or None for the pixel word, name)
PORTS = (("input", 1, "clk"), ("input", 1, "rst"),
         ("input", 1, "cfg_wr_en"), ("input", REGMAP["ADDR_W"], "cfg_wr_addr"),
         ("input", REGMAP["DATA_W"], "cfg_wr_data"),
         ("input", None, "s_axis_tdata"), ("input", 1, "s_axis_tvalid"), ("output", 1, "s_axis_tready"),
         ("input", 1, "s_axis_tlast"),
         ("output", 32, "m_axis_tdata"), ("output", 1, "m_axis_tvalid"), ("input", 1, "m_axis_tready"),
         ("output", 1, "m_axis_tlast"))


def value(cfg: Config, key: str) -> int:
    """A configuration key as the integer the RTL takes."""
    v = getattr(cfg, key)
    return ENUMS[key][v] if key in ENUMS else int(v)


def perm_literal(cfg: Config) -> str:
    """The permutation as one Verilog literal, entry i at bits [i*H +: H]."""
    hb = cfg.hash_bits
    word = 0
    for i, p in enumerate(cfg.perm):
        word |= int(p) << (i * hb)
    bits = hb << hb
    return f"{bits}'h{word:0{(bits + 3) // 4}x}"


def exponent_params(cfg: Config) -> dict:
    """T_EXP_W and A_EXP_W (formats.t_exp_w, a_exp_w: the per-term exponents, docs/numerics.md
    "Block floating point") for a block that takes them, only where nonzero (a fixed-point
    configuration's parameter sets, and so its generated top and its build and synthesis
    caches, stay as they were; 0 is every block's default)."""
    return {k.upper(): value(cfg, k) for k in ("t_exp_w", "a_exp_w") if getattr(cfg, k)}


def sample_params(cfg: Config) -> dict:
    """SAMPLES (features.samples: sub-pixel samples a pixel, sample_expand and sample_average)
    and CMAP_CLOCKS (features.cmap_clocks: colour_map's fold) only where they are not 1 (such a
    configuration's generated top and caches stay as they were; 1 is texture_pipeline's default)."""
    return {**({"SAMPLES": cfg.samples} if cfg.samples != 1 else {}),
            **({"CMAP_CLOCKS": cfg.cmap_clocks} if cfg.cmap_clocks != 1 else {})}


def top_params(cfg: Config) -> dict:
    """texture_pipeline's parameters for `cfg` (name -> integer, PERM a Verilog literal)."""
    out = {k.upper(): value(cfg, k) for k in TOP_KEYS}
    out.update(exponent_params(cfg))
    out.update(sample_params(cfg))
    # derived from the blend (model/hw/config.py fc_sigma12): sigma sqrt(12) in u.FC_KSF
    out["FC_KS"], out["FC_KSF"] = cfg.fc_ks, FC_KSF
    out["PERM"] = perm_literal(cfg)
    return out


def _fc(cfg: Config) -> bool:
    """The terms are faded (sat_fc's and sat2_fc's frequency clamping: texture_pipeline FCL; unfolded terms only)."""
    return freq_clamp(cfg) and cfg.noise_terms > 0 and not folded(cfg)


def _pick(cfg: Config, *keys) -> dict:
    return {k.upper(): value(cfg, k) for k in keys}


def block_params(cfg: Config, module: str) -> dict:
    """The parameters texture_pipeline gives `module` under `cfg` (its own testbench and gate
    count use the same)."""
    if module == "texture_pipeline":
        return top_params(cfg)
    if module == "quadric_mac":
        p = _pick(cfg, "s_w", "s_frac", "q_w", "q_frac", "f_frac", "c_frac")
        return {"DIAG": value(cfg, "quadric"), "CLOCKS": cfg.quadric_clocks, **p, "C_W": cfg.c_w,
                **_pick(cfg, "fpga_regs")}
    if module == "noise_term":
        return {**_pick(cfg, "s_w", "s_frac", "t_w", "t_frac", "a_w", "a_frac", "p_frac", "hash_bits", "n_frac",
                        "f_frac", "c_frac", "transform", "blend", "amplitude", "noise_gradient", "fpga_regs"),
                "PARAM_PIPE": 1 if folded(cfg) else 0,  # noise_fold's units take a term a clock
                **exponent_params(cfg), "PERM": perm_literal(cfg)}
    if module == "noise_fold":  # folded terms (texture_pipeline's g_fold; side: {tlast, je, Jm})
        nt = {k: v for k, v in block_params(cfg, "noise_term").items() if k != "PARAM_PIPE"}
        return {**nt, "NOISE_TERMS": cfg.noise_terms, "NOISE_UNITS": cfg.noise_units, "F_W": cfg.f_w,
                "C_W": cfg.c_w, "SIDE_W": 6 * cfg.j_w + cfg.je_w + 1,
                "MIN_CLOCKS": max(cfg.quadric_clocks, cfg.cmap_clocks)}  # texture_pipeline's MIN_CLK
    if module == "noise_hash":
        return {"H": cfg.hash_bits, "N_FRAC": cfg.n_frac, "N_W": cfg.n_w, "PERM": perm_literal(cfg)}
    if module == "filter_width":
        return {"C_W": cfg.c_w, **_pick(cfg, "c_frac", "j_w", "je_w", "norm_bits", "f_frac", "w_cap_log2",
                                        "n_log2_max", "fpga_regs"),
                **({"COMPONENTS": 1} if cmap_family(cfg) == "sat2" else {})}  # sat2: the two screen components
    if module == "colour_map":  # its family alone (sat_fc: the box, sat2_fc: the trapezoid; the fade is before it)
        return {"F_W": cfg.f_w, **_pick(cfg, "f_frac", "w_cap_log2", "n_log2_max", "div_bits", "fpga_regs"),
                "FILTER": {"none": 0, "sat": 1, "mip": 2, "sat2": 3}[cmap_family(cfg)],
                **({"CLOCKS": cfg.cmap_clocks} if cfg.cmap_clocks != 1 else {})}
    if module == "fc_weight":
        return {"NOISE_TERMS": cfg.noise_terms, **_pick(cfg, "j_w", "je_w", "t_w", "t_frac", "a_w", "a_frac", "f_frac",
                                                        "w_cap_log2", "n_log2_max", "fc_log_frac", "fc_knee",
                                                        "fc_fade_log2"),
                "FC_KS": cfg.fc_ks, "FC_KSF": FC_KSF, **exponent_params(cfg)}
    if module == "fc_scale":
        return {"AN_W": cfg.an_w, "AG_W": cfg.ag_w, "AF": cfg.fc_af, "NOISE_GRADIENT": value(cfg, "noise_gradient")}
    if module == "box_divide":  # as colour_map divides: exact, or on a div_bits-bit w (cmap_clocks 4: one lane)
        b, lanes = cfg.div_bits, 4 // cfg.cmap_clocks
        if cmap_family(cfg) == "sat2":  # the trapezoid's divisor 4ab, w2_w bits
            if 0 < b < cfg.w2_w:
                sat = 1 if b <= 9 else 0
                return {"NUM_W": b + 8 + sat, "DEN_W": b, "Q_W": 8, "LANES": lanes, "SAT": sat}
            return {"NUM_W": cfg.d2_w - 1, "DEN_W": cfg.w2_w, "Q_W": 8, "LANES": lanes, "SAT": 0}
        if cfg.filter in SAT_FILTERS and 0 < b < cfg.w_w:
            sat = 1 if b <= 9 else 0
            return {"NUM_W": b + 8 + sat, "DEN_W": b, "Q_W": 8, "LANES": lanes, "SAT": sat}
        return {"NUM_W": cfg.d_w - 1, "DEN_W": cfg.w_w, "Q_W": 8, "LANES": lanes, "SAT": 0}
    if module == "sat_integral_serial":  # cmap_sat's two with cmap_clocks = 4 (colour_map's words)
        return {"XF": cfg.f_frac + 1, "KW": cfg.x_w - cfg.f_frac - 1, "QW": max(8, cfg.csat_w - 8),
                "CS_W": cfg.csat_w, "D_W": cfg.d_w}
    if module == "texture_sum":  # the top's keys but the filter's (FC: sat_fc's fades), and its latency
        top = {k: v for k, v in top_params(cfg).items() if k not in ("FILTER", "NORM_BITS", "DIV_BITS", "CMAP_CLOCKS")}
        return {**top, "FC": int(_fc(cfg)), "LATENCY": texture_sum_latency(cfg)}
    if module == "tex_regs":
        return {"NOISE_TERMS": cfg.noise_terms, **_pick(cfg, "q_w", "a_w", "t_w", "hash_bits", "p_frac", "n_log2_max"),
                **exponent_params(cfg)}
    if module == "sample_expand":
        return {"SAMPLES": cfg.samples, **_pick(cfg, "s_w", "s_frac", "j_w", "je_w")}
    if module == "sample_average":
        return {"SAMPLES": cfg.samples}
    if module == "axis_skid":
        return {"DATA_W": 32}
    if module == "isqrt":
        return {"L_W": cfg.l_w, "R_W": cfg.r_w, "LATENCY": latency("filter_width") - 5}  # with or without fpga_regs
    raise KeyError(f"block_params: no parameter set for module '{module}'")


def texture_sum_latency(cfg: Config) -> int:
    """rtl/texture_sum.v's latency (f's, T_F in texture_pipeline): the quadric and the noise
    leaves meet (the later of the two), then the adder tree's levels."""
    terms = latency("noise_term", cfg) + (latency("noise_fold", cfg) if folded(cfg) else
                                          latency("fc_scale") if _fc(cfg) else 0)
    front = max(latency("quadric_mac", cfg), terms if cfg.noise_terms else 0)
    return front + sum_tree_levels(1 + (1 if folded(cfg) else cfg.noise_terms))


def latency(module: str, cfg: Config | None = None) -> int:
    """A block's latency in register stages under cfg (model.hw.config.latency: rtl/tex_latency.vh)."""
    return config_latency(module, cfg)


def texture_unit_source(cfg: Config, netlist: bool = False) -> str:
    """The wrapper module `texture_unit`: texture_pipeline with the parameters of `cfg`.
    netlist: around texture_pipeline's synthesized netlist (synth/netlist.py, `make gls`), which
    was synthesized with those parameters and takes none (they stay in the header comment)."""
    params = top_params(cfg)
    lines = [f"// Generated from {rel_path(cfg.path)} by hdlbuild/params.py. Do not edit.",
             f"// texture_unit: texture_pipeline with the parameters of configuration `{cfg.name}`",
             "// (rtl/texture_pipeline.v documents the ports).",
             "`default_nettype none", "",
             "module texture_unit (" + ", ".join(n for _, _, n in PORTS) + ");"]
    for d, w, n in PORTS:
        w = pix_width(cfg) if w is None else w
        lines.append(f"{d:<6} wire {f'[{w - 1}:0] ' if w > 1 else ''}{n};")
    ports = ", ".join(f".{n}({n})" for _, _, n in PORTS)
    if netlist:
        lines[1] += " (its synthesized netlist)"
        lines.append("// parameters it was synthesized with: " + ", ".join(f"{k}={v}" for k, v in params.items()))
        lines.append(f"texture_pipeline u_pipe ({ports});")
    else:
        lines.append("texture_pipeline #(")
        lines.append(",\n".join(f"    .{k}({v})" for k, v in params.items()))
        lines.append(f") u_pipe ({ports});")
    lines += ["endmodule", "", "`default_nettype wire", ""]
    return "\n".join(lines)
