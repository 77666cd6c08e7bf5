"""Configurations: the single source of every width, count and mode.

`load_config(name)` reads config/<name>.toml, checks it, and derives every
internal word width from the input formats (each derivation is a worst-case
magnitude bound, documented in docs/numerics.md). The golden model reads the
result. The RTL gets only the configuration's keys, as parameters of its top
(hdlbuild/params.py), and derives the same widths itself (rtl/tex_widths.vh, one
Verilog function per derivation below); tb/test_widths.py checks that the
elaborated RTL holds exactly these widths.

`variant(cfg, **changes)` and `random_config(seed)` make configurations that are
not files (checked the same way), `config_toml(cfg)` writes one as a file.

Run `python -m model.hw.config NAME` to print a configuration's keys and widths.
"""
from __future__ import annotations

import math
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]  # the repository (model/hw/config.py)
CONFIG_DIR = ROOT / "config"
CONFIG_NAMES = ("full", "reduced", "compact")
# features.filter is one string naming two orthogonal choices: the colour-map family (the box
# "sat", the trapezoid "sat2", "mip", the point lookup "none") and whether the noise terms are
# frequency-clamped (the suffix "_fc": fc_weight, fc_scale, the faded terms' spread in the width)
FILTER_KINDS = {"sat": ("sat", False), "sat_fc": ("sat", True), "sat2": ("sat2", False), "sat2_fc": ("sat2", True),
                "mip": ("mip", False), "none": ("none", False)}
SAT_FILTERS = ("sat", "sat_fc")  # the filters that read the summed-area table (the box)
SAT2_FILTERS = ("sat2", "sat2_fc")  # the trapezoid's (a second table: the running sum of csat)
TABLE_FILTERS = SAT_FILTERS + SAT2_FILTERS  # the filters whose tables include csat (sat2: and its running sum)


def cmap_family(cfg_or_filter) -> str:
    """The colour-map family of a configuration (or a filter name): "sat", "sat2", "mip" or "none"."""
    f = cfg_or_filter if isinstance(cfg_or_filter, str) else cfg_or_filter.filter
    return FILTER_KINDS[f][0]


def freq_clamp(cfg_or_filter) -> bool:
    """The configuration's (or filter name's) noise terms are frequency-clamped (sat_fc, sat2_fc)."""
    f = cfg_or_filter if isinstance(cfg_or_filter, str) else cfg_or_filter.filter
    return FILTER_KINDS[f][1]


class ConfigError(ValueError):
    """A configuration file that is malformed or inconsistent (one-line message)."""


# key -> (section, type, (lo, hi) or allowed values)
SCHEMA = {
    "quadric": ("features", str, ("full", "diagonal")),
    "noise_terms": ("features", int, (0, 8)),
    "blend": ("features", str, ("cubic", "linear")),
    "transform": ("features", str, ("affine", "pow2")),
    "amplitude": ("features", str, ("any", "pow2")),
    "filter": ("features", str, tuple(FILTER_KINDS)),
    "noise_gradient": ("features", bool, (False, True)),
    "noise_units": ("features", int, (1, 8)),
    # clocks the diagonal quadric takes a sample (QUADRIC_CLOCKS): 1 (6 multipliers), 2 (3: qmac_diag_fold),
    # 6 (1: qmac_diag_serial); more than 1 needs the folded noise terms, whose issue paces the pipeline
    "quadric_clocks": ("features", int, (1, 6)),
    "fpga_regs": ("features", bool, (False, True)),
    # sub-pixel samples a pixel (issue 27): 1, 2 or 4 texture samples at stratified offsets inside the
    # pixel (rtl/sample_expand.v, docs/filters.md "Sub-pixel samples"), each filtered with the
    # footprint of its cell of the pixel (SAMPLE_FOOTPRINT), averaged (rtl/sample_average.v); samples x the clocks of one
    "samples": ("features", int, (1, 4)),
    # clocks colour_map's box filter takes a sample (issue 27's colour-map fold, CMAP_CLOCKS): 1 (the
    # four channels at once), 4 (a channel a clock: rtl/cmap_sat.v CLOCKS, sat_integral_serial at both
    # window ends, one divider lane); 4 needs the filter "sat", folded noise terms and no fpga_regs
    "cmap_clocks": ("features", int, (1, 4)),
    "s_w": ("formats", int, (4, 32)),
    "s_frac": ("formats", int, (0, 24)),
    "q_w": ("formats", int, (4, 32)),
    "q_frac": ("formats", int, (0, 24)),
    "j_w": ("formats", int, (4, 24)),
    "je_w": ("formats", int, (3, 8)),
    "t_w": ("formats", int, (4, 24)),
    "t_frac": ("formats", int, (0, 28)),
    "a_w": ("formats", int, (4, 24)),
    "a_frac": ("formats", int, (0, 28)),
    # block floating point (issue 26): T_i = M_i 2^(te_i - t_frac), M_i s{t_w}.0 entries and one
    # exponent te_i in [0, 2^t_exp_w - 1] per term; a_i = A_i 2^(ae_i - a_frac) likewise;
    # 0 = fixed point (te_i = ae_i = 0: T_i s{t_w}.{t_frac}, a_i s{a_w}.{a_frac}). Optional
    # (OPTIONAL_KEYS): a file without them is fixed point, and its hash is what it was.
    "t_exp_w": ("formats", int, (0, 4)),
    "a_exp_w": ("formats", int, (0, 4)),
    "p_frac": ("formats", int, (2, 16)),
    "hash_bits": ("formats", int, (2, 10)),
    "n_frac": ("formats", int, (2, 16)),
    "f_frac": ("formats", int, (8, 20)),
    "c_frac": ("formats", int, (4, 20)),
    "norm_bits": ("formats", int, (4, 24)),
    "w_cap_log2": ("formats", int, (1, 20)),
    "div_bits": ("formats", int, (0, 24)),
    "n_log2_max": ("formats", int, (0, 10)),
    # filters "sat_fc", "sat2_fc" (frequency clamping, docs/filters.md): each term fades to its mean over
    # 2^fc_fade_log2 octaves of its footprint phi (noise cells a pixel), ending at phi =
    # 2^(fc_knee / 2^fc_log_frac); log2 phi in fc_log_frac fraction bits
    "fc_log_frac": ("formats", int, (1, 8)),
    "fc_knee": ("formats", int, (-1024, 1023)),
    "fc_fade_log2": ("formats", int, (0, 4)),
    "seed": ("hash", int, (0, 2**31 - 1)),
}


# keys a file may leave out, with the value it then has; config_values leaves them out at that value
# (so the hash of a configuration that does not use them is unchanged)
OPTIONAL_KEYS = {"t_exp_w": 0, "a_exp_w": 0, "samples": 1, "cmap_clocks": 1}
SAMPLE_COUNTS = (1, 2, 4)  # features.samples: the values the sample blocks implement
QUADRIC_CLOCKS = (1, 2, 6)  # features.quadric_clocks: quadric_mac's datapaths (rtl/quadric_mac.v CLOCKS)
CMAP_CLOCKS = (1, 4)  # features.cmap_clocks: cmap_sat's (rtl/cmap_sat.v CLOCKS)
# the sub-pixel samples' offsets d_k = (dx, dy) / 4 pixel, in quarter pixels, in the order the unit
# takes them (rtl/sample_expand.v: 4 samples dx from the sample index's bit 0, dy from its bit 1; 2 samples
# the vertical pair, dy from bit 0), and each sample's footprint: the scale of J's columns (x, y), so that
# the samples' cells tile the pixel (2: its upper and lower halves, 4: its quarters). The vertical pair
# (issue 27, stop 38): the diagonal pair with the isotropic J / sqrt 2 was worse than one sample (zone plate
# 24.0 dB against 35.9; the float experiment in docs/numerics.md "Sub-pixel samples")
SAMPLE_OFFSETS = {1: ((0, 0),), 2: ((0, -1), (0, 1)), 4: ((-1, -1), (1, -1), (-1, 1), (1, 1))}
SAMPLE_FOOTPRINT = {1: (1.0, 1.0), 2: (1.0, 0.5), 4: (0.5, 0.5)}


def bits_signed(maxabs: int) -> int:
    """Width of a two's-complement word holding every integer in [-maxabs, maxabs]."""
    return int(maxabs).bit_length() + 1


def bits_unsigned(maxval: int) -> int:
    return max(1, int(maxval).bit_length())


def permutation(n: int, seed: int) -> np.ndarray:
    """The lattice hash permutation of range(n): Fisher-Yates driven by a 32-bit LCG.

    Plain integer arithmetic so that it never depends on numpy's generators.
    """
    p = list(range(n))
    x = seed & 0xFFFFFFFF
    for i in range(n - 1, 0, -1):
        x = (1664525 * x + 1013904223) & 0xFFFFFFFF
        j = (x >> 8) % (i + 1)
        p[i], p[j] = p[j], p[i]
    return np.array(p, dtype=np.int64)


@dataclass
class Config:
    name: str
    quadric: str
    noise_terms: int
    blend: str
    transform: str
    amplitude: str
    filter: str
    noise_gradient: bool
    noise_units: int
    quadric_clocks: int
    fpga_regs: bool
    s_w: int
    s_frac: int
    q_w: int
    q_frac: int
    j_w: int
    je_w: int
    t_w: int
    t_frac: int
    a_w: int
    a_frac: int
    p_frac: int
    hash_bits: int
    n_frac: int
    f_frac: int
    c_frac: int
    norm_bits: int
    w_cap_log2: int
    div_bits: int
    n_log2_max: int
    fc_log_frac: int
    fc_knee: int
    fc_fade_log2: int
    seed: int
    t_exp_w: int = 0
    a_exp_w: int = 0
    samples: int = 1
    cmap_clocks: int = 1
    path: str = ""
    # the file's [promise] (PROMISE_KEYS; None for a configuration that states none): what the
    # configuration keeps on the held-out corpus (explore.validate); not a parameter of the RTL
    promise: dict = field(default=None, repr=False)
    perm: np.ndarray = field(default=None, repr=False)
    d: dict = field(default_factory=dict)  # derived widths

    def __getattr__(self, item):  # derived widths read as attributes: cfg.v_w
        d = self.__dict__.get("d")
        if d is not None and item in d:
            return d[item]
        raise AttributeError(item)


def clocks_per_sample(cfg: Config, k_used: int | None = None) -> int:
    """Clocks the pipeline takes one texture sample for a texture of k_used terms (default: all
    K): ceil(k_used / noise_units), at least quadric_clocks and cmap_clocks (noise_units = noise_terms,
    quadric_clocks = cmap_clocks = 1: one sample a clock); noise_fold's issue clocks."""
    k = cfg.noise_terms if k_used is None else k_used
    return max(1, cfg.quadric_clocks, cfg.cmap_clocks, -(-k // cfg.noise_units))


def clocks_per_pixel(cfg: Config, k_used: int | None = None) -> int:
    """Clocks the pipeline takes a pixel: features.samples sub-pixel samples of
    clocks_per_sample each (samples = 1, noise_units = noise_terms, quadric_clocks = 1: one
    pixel a clock)."""
    return cfg.samples * clocks_per_sample(cfg, k_used)


def latency(module: str, cfg: Config | None = None) -> int:
    """A block's latency in register stages under cfg, from rtl/tex_latency.vh: `LAT_<MODULE>,
    or `LAT_<MODULE>_FPGA when cfg.fpga_regs (the FPGA's extra register stages; cfg None:
    fpga_regs false). The RTL block picks the same value from its FPGA_REGS parameter.
    quadric_mac on one multiplier (diagonal, quadric_clocks = 6, no fpga_regs): `LAT_QUADRIC_MAC_SERIAL
    (the rule of rtl/tex_latency.vh's `LAT_QM, which quadric_mac and its callers use); colour_map and
    cmap_sat a channel a clock (cmap_clocks = 4, no fpga_regs): `LAT_<MODULE>_SERIAL (`LAT_CM, `LAT_CMS)."""
    import re

    text = (ROOT / "rtl" / "tex_latency.vh").read_text()
    name = f"LAT_{module.upper()}"
    if cfg is not None and cfg.fpga_regs and re.search(rf"`define\s+{name}_FPGA\s", text):
        name += "_FPGA"  # (a block without a `LAT_<MODULE>_FPGA has no extra stages)
    elif (module == "quadric_mac" and cfg is not None and getattr(cfg, "quadric_clocks", 1) == 6
          and getattr(cfg, "quadric", "full") == "diagonal"):
        name += "_SERIAL"
    elif module in ("colour_map", "cmap_sat") and cfg is not None and getattr(cfg, "cmap_clocks", 1) == 4:
        name += "_SERIAL"
    m = re.search(rf"`define\s+{name}\s+(\d+)", text)
    if not m:
        raise KeyError(f"rtl/tex_latency.vh: no {name}")
    return int(m.group(1))


def sum_tree_levels(n: int) -> int:
    """The register levels (= latency) of rtl/sum_tree.v over n leaves: an adder tree of arity
    `SUM_TREE_ARITY (rtl/tex_latency.vh) down to one node (rtl/tex_widths.vh tw_tree_levels)."""
    import re

    text = (ROOT / "rtl" / "tex_latency.vh").read_text()
    arity = int(re.search(r"`define\s+SUM_TREE_ARITY\s+(\d+)", text).group(1))
    levels = 0
    while n > 1:
        n, levels = -(-n // arity), levels + 1
    return levels


def folded(cfg: Config) -> bool:
    """The noise terms run on fewer units than there are terms (rtl/noise_fold.v)."""
    return cfg.noise_terms > 0 and cfg.noise_units < cfg.noise_terms


def noise_term_instances(cfg: Config) -> int:
    """noise_term instances in the RTL: one per unit (folded) or per term."""
    return cfg.noise_units if folded(cfg) else cfg.noise_terms


def _derive(c: Config) -> dict:
    """Every internal width from the input formats: worst-case magnitudes, no guessing."""
    d = {}
    smax = 1 << (c.s_w - 1)  # |s| <= smax (two's complement extreme)
    qmax = 1 << (c.q_w - 1)
    if c.quadric == "diagonal":
        # v_k = (Q_kk s_k >> s_frac) + Q_k3 and the factor v_k + Q_k3 of q  [frac q_frac]
        vmax = (qmax * smax >> c.s_frac) + 1 + 2 * qmax
        # q = (s (v0 + D) + t (v1 + G) + r (v2 + I)) >> s_frac + J
        qsum = (3 * smax * vmax >> c.s_frac) + 1 + qmax
    else:
        # v_k = (Q_k0 s + Q_k1 t + Q_k2 r) >> s_frac + Q_k3              [frac q_frac]
        vmax = (3 * qmax * smax >> c.s_frac) + 1 + qmax
        # q = (s v0 + t v1 + r v2) >> s_frac + v3
        qsum = (3 * smax * vmax >> c.s_frac) + 1 + vmax
    d["v_w"] = bits_signed(vmax)
    d["qv_w"] = bits_signed(qsum)
    # q and 2v re-expressed with f_frac / c_frac fraction bits
    d["qf_w"] = bits_signed(_shift_bound(qsum, c.f_frac - c.q_frac))
    cq_max = _shift_bound(2 * vmax, c.c_frac - c.q_frac)
    # noise: p = (T s) >> (s_frac + t_frac - p_frac) + o, wrapped to hash_bits + p_frac
    d["p_w"] = c.hash_bits + c.p_frac
    d["o_w"] = d["p_w"]
    d["ts_shift"] = c.s_frac + c.t_frac - c.p_frac
    # per-term exponents (t_exp_w, a_exp_w; 0: none): T s >> (ts_shift - te), a n >> (an_shift - ae)
    d["te_max"] = (1 << c.t_exp_w) - 1
    d["ae_max"] = (1 << c.a_exp_w) - 1
    # noise value n in [-1, 1) with n_frac fraction bits; gradient |dn/dp| <= 2 * 1.5
    nmax = 1 << c.n_frac
    d["n_w"] = bits_signed(nmax)
    d["gn_w"] = bits_signed(3 * nmax)  # 2 (value difference) * 1.5 (cubic slope)
    d["blend_w"] = c.p_frac + 2  # blend weight in [0, 1], slope in [0, 1.5]: unsigned p_frac+1 bits
    amax = 1 << (c.a_w - 1)
    tmax = 1 << (c.t_w - 1)
    d["an_shift"] = c.a_frac + c.n_frac - c.f_frac
    an_max = _shift_bound(amax * nmax, d["ae_max"] - d["an_shift"])
    d["an_w"] = bits_signed(an_max)
    # h_k = sum_j gn_j T_jk >> (n_frac + t_frac - c_frac); ag_k = a h_k >> a_frac
    d["h_shift"] = c.n_frac + c.t_frac - c.c_frac
    # |g_j| <= 2 nmax (linear: lerps stay within the lattice span) or 3 nmax (cubic slope 1.5);
    # pow2: T diagonal with 0 <= T_kk <= 2^(t_w - 2), one product per h_k
    gmax = 3 * nmax if c.blend == "cubic" else 2 * nmax
    hsum = gmax << (c.t_w - 2) if c.transform == "pow2" else 3 * gmax * tmax
    h_max = _shift_bound(hsum, d["te_max"] - d["h_shift"])
    d["h_w"] = bits_signed(h_max)
    ag_max = _shift_bound(amax * h_max, d["ae_max"] - c.a_frac)
    d["ag_w"] = bits_signed(ag_max)
    # sums over the quadric and the K noise terms
    k = c.noise_terms
    fmax = _shift_bound(qsum, c.f_frac - c.q_frac) + k * an_max
    d["f_w"] = bits_signed(fmax)
    cmax = cq_max + (k * ag_max if c.noise_gradient else 0)  # no noise gradient: grad f = grad q
    d["c_w"] = bits_signed(cmax)
    # screen gradient mantissa g = c . Jm (3 products)
    # (from the word c_w, as filter_width sees it: |c_k| <= 2^(c_w - 1))
    jmax = 1 << (c.j_w - 1)
    gmax = 3 * (1 << (d["c_w"] - 1)) * jmax
    d["g_w"] = bits_signed(gmax)
    d["gabs_w"] = bits_unsigned(gmax)
    # normalised |g| pair, sum of squares, square root
    d["l_w"] = bits_unsigned(2 * ((1 << c.norm_bits) - 1) ** 2)
    d["r_w"] = bits_unsigned(math.isqrt(2 * ((1 << c.norm_bits) - 1) ** 2))
    d["sh_w"] = bits_unsigned(max(0, d["gabs_w"] - c.norm_bits))
    # w exponent: e = sh + je - c_frac + n_log2 + f_frac
    je_lo, je_hi = -(1 << (c.je_w - 1)), (1 << (c.je_w - 1)) - 1
    d["je_min"], d["je_max"] = je_lo, je_hi
    e_lo = je_lo - c.c_frac + c.f_frac
    e_hi = (1 << d["sh_w"]) - 1 + je_hi - c.c_frac + c.n_log2_max + c.f_frac
    d["e_w"] = max(bits_signed(-e_lo), bits_signed(e_hi))
    # filter width w in units of 2^-f_frac colour-table entries, saturating at 2^w_cap_log2 entries
    d["w_w"] = c.w_cap_log2 + c.f_frac + 1
    d["w_cap"] = 1 << (c.w_cap_log2 + c.f_frac)
    # colour index u = f * N in units of 2^-f_frac entries (clamp mode: guarded by w_cap/2,
    # sat2 by w_cap: its window reaches (a + b) / 2 <= w_cap from u)
    nmax_entries = 1 << c.n_log2_max
    d["u_guard"] = d["w_cap"] if c.filter in SAT2_FILTERS else d["w_cap"] >> 1
    umax = max(nmax_entries << c.f_frac, 0) + d["u_guard"]
    d["u_w"] = bits_signed(umax)
    # window ends x = 2u -+ w in units of 2^-(f_frac+1) entries
    xmax = 2 * umax + d["w_cap"]
    d["x_w"] = bits_signed(xmax)
    d["x_frac"] = c.f_frac + 1
    # integral I(x) per channel: |I| <= 255 * (|x| + N) (units 2^-x_frac), D = I(b) - I(a)
    d["csat_w"] = bits_unsigned(255 * nmax_entries)
    d["i_w"] = bits_signed(255 * (xmax + (nmax_entries << d["x_frac"])))
    d["d_w"] = bits_unsigned(255 * 2 * d["w_cap"])
    d["n_log2_w"] = bits_unsigned(c.n_log2_max)
    # filter "sat2" (the trapezoid, docs/numerics.md "The trapezoid"): window ends
    # e = 2u -+ a -+ b (units 2^-x_frac), the running sum of csat H[k] = sum_{j<=k} csat[j]
    # (<= 255 N (N + 1) / 2), the trapezoid's second difference of 2G, Gamma = 8 avg a b
    # <= 2040 a b (units 2^-2 x_frac), and its divisor 4ab (cmap_divide's w)
    d["x2_w"] = bits_signed(2 * ((nmax_entries << c.f_frac) + d["w_cap"]) + 2 * d["w_cap"])  # u guarded by W
    d["csat2_w"] = bits_unsigned(255 * nmax_entries * (nmax_entries + 1) // 2)
    d["d2_w"] = bits_unsigned(2040 * d["w_cap"] ** 2)
    d["w2_w"] = bits_unsigned(4 * d["w_cap"] ** 2)
    # widest intermediate must stay inside int64 (numpy) with margin
    widest = max(
        c.q_w + c.s_w + 2,
        c.s_w + d["v_w"] + 2,
        d["c_w"] + c.j_w + 2,
        d["i_w"],
        c.a_w + d["h_w"],
        d["gn_w"] + c.t_w + 4,
    )
    d["widest_product"] = widest
    # frequency clamping (filter "sat_fc", fc_weight): alpha u1.{fc_af} per term; the faded
    # terms' spread width (2^fc_af - alpha) |a| in u.{fc_af + a_frac}, times the blend's
    # sigma sqrt(12) (fc_ks, u.{FC_KSF}: the standard deviation of lattice noise with values
    # uniform in [-1, 1), times sqrt(12), the width of a box of that deviation)
    d["fc_af"] = c.fc_log_frac + c.fc_fade_log2
    d["fc_ks"] = int(round(fc_sigma12(c.blend) * (1 << FC_KSF)))
    return d


FC_KSF = 8  # fraction bits of fc_ks


def fc_sigma12(blend: str) -> float:
    """sqrt(12) x the standard deviation of lattice value noise (corner values uniform in
    [-1, 1), variance 1/3; a blend weight s(t) per axis gives variance 1/3 E[(1-s)^2 + s^2]^3,
    E = 2/3 linear, 26/35 cubic (s = 3t^2 - 2t^3))."""
    e = 2.0 / 3.0 if blend == "linear" else 26.0 / 35.0
    return math.sqrt(12.0 * e ** 3 / 3.0)


def _shift_bound(x: int, sh: int) -> int:
    return x << sh if sh >= 0 else (x >> -sh) + 1


def load_config(name_or_path) -> Config:
    """The configuration config/<name>.toml, or the file at a path (a name with a suffix)."""
    p = Path(name_or_path)
    if not p.suffix:
        p = CONFIG_DIR / f"{name_or_path}.toml"
    if not p.exists():
        raise ConfigError(f"{p}: no such configuration (known: {', '.join(CONFIG_NAMES)})")
    return _from_raw(_read_raw(p), p)


def config_file_names() -> tuple:
    """Every configuration file of config/: the named configurations first, then the others by name."""
    rest = sorted(p.stem for p in CONFIG_DIR.glob("*.toml") if p.stem.isidentifier() and p.stem not in CONFIG_NAMES)
    return CONFIG_NAMES + tuple(rest)


def is_config_file(name: str) -> bool:
    """A name of a configuration file of config/ (a named configuration or a variant file)."""
    return name.isidentifier() and (CONFIG_DIR / f"{name}.toml").is_file()


def stamped_config(name: str) -> Config | None:
    """The configuration a doc stamp's name stands for: config/<name>.toml, else the candidate
    config/candidates/<name>.toml (a candidate's name is its file's stem); None for another name
    (a variant made in code, out/fit/'s answers). Stamps of candidates are checked as the named ones
    are (app/regen.py is_stale, tests/test_validate.py)."""
    if is_config_file(name):
        return load_config(name)
    p = CONFIG_DIR / "candidates" / f"{name}.toml"
    if name.isidentifier() and p.is_file():
        c = load_config(p)
        return c if c.name == name else None
    return None


def base_of(name: str) -> str | None:
    """The `base` the file config/<name>.toml names (None: it has none, or there is no file)."""
    p = CONFIG_DIR / f"{name}.toml"
    return tomllib.loads(p.read_text()).get("base") if is_config_file(name) else None


def fc_variant(base: Config) -> Config:
    """base with the frequency-clamping filter (filter "sat_fc"), its terms unfolded (at least one)."""
    k = max(base.noise_terms, 1)
    return variant(base, f"{base.name}_fc", filter="sat_fc", noise_terms=k, noise_units=k, quadric_clocks=1)


def _read_raw(p: Path, seen: tuple = ()) -> dict:
    """A configuration file's table; `base = "<name>"` takes every key of config/<name>.toml (or, when
    config/ has no such file, config/candidates/<name>.toml) that the file does not set itself (a variant
    names only what it changes)."""
    try:
        raw = tomllib.loads(p.read_text())
    except tomllib.TOMLDecodeError as e:
        raise ConfigError(f"{p}: malformed TOML: {e}") from None
    base = raw.pop("base", None)
    if base is None:
        return raw
    bp = CONFIG_DIR / f"{base}.toml" if isinstance(base, str) else None
    if bp is not None and not bp.exists():  # a candidate may build on another candidate
        bp = CONFIG_DIR / "candidates" / f"{base}.toml"
    if bp is None or not bp.exists():
        raise ConfigError(f"{p}: base = {base!r}: no such configuration in config/ or config/candidates/")
    if bp.resolve() in seen or bp.resolve() == p.resolve():
        raise ConfigError(f"{p}: base = {base!r}: a cycle of bases")
    out = _read_raw(bp, seen + (p.resolve(),))
    for sec, val in raw.items():
        if isinstance(val, dict) and isinstance(out.get(sec), dict):
            out[sec] = {**out[sec], **val}
        else:
            out[sec] = val
    return out


def _from_raw(raw: dict, p: Path) -> Config:
    """Check a configuration's {section: {key: value}} table and derive its widths."""
    vals = {}
    known_sections = {"features", "formats", "hash", "promise"}
    promise = _promise(raw.get("promise"), p)
    for sec in raw:
        if sec in ("name", "promise"):
            continue
        if sec not in known_sections:
            raise ConfigError(f"{p}: unknown key '{sec}' (expected one of {sorted(known_sections)})")
        for key in raw[sec]:
            if key not in SCHEMA or SCHEMA[key][0] != sec:
                raise ConfigError(f"{p}: unknown key '{sec}.{key}'")
    for key, (sec, typ, rng) in SCHEMA.items():
        if key not in raw.get(sec, {}) and key in OPTIONAL_KEYS:
            vals[key] = OPTIONAL_KEYS[key]
            continue
        if key not in raw.get(sec, {}):
            raise ConfigError(f"{p}: missing key '{sec}.{key}'")
        v = raw[sec][key]
        if type(v) is not typ:
            raise ConfigError(f"{p}: '{sec}.{key}' = {v!r}: expected {typ.__name__}")
        if typ is str and v not in rng:
            raise ConfigError(f"{p}: '{sec}.{key}' = {v!r}: expected one of {list(rng)}")
        if typ is int and not (rng[0] <= v <= rng[1]):
            raise ConfigError(f"{p}: '{sec}.{key}' = {v}: expected {rng[0]}..{rng[1]}")
        vals[key] = v
    cfg = Config(name=raw.get("name", p.stem), path=str(p), promise=promise, **vals)
    _check(cfg, p)
    cfg.perm = permutation(1 << cfg.hash_bits, cfg.seed)
    cfg.d = _derive(cfg)
    if cfg.d["gabs_w"] > 52 or cfg.d["l_w"] > 52:  # golden.bitlen / isqrt go through float64: exact below 2^53
        raise ConfigError(f"{p}: formats too wide: |grad f| needs {cfg.d['gabs_w']} bits (> 52)")
    if cfg.d["widest_product"] > 62:
        raise ConfigError(f"{p}: formats too wide: an intermediate needs {cfg.d['widest_product']} bits (> 62, int64)")
    _check_rtl(cfg, p)
    return cfg


# [promise]: key -> (type, what)
PROMISE_KEYS = {
    "psnr_db": ((int, float), "the PSNR in dB it keeps, per scene"),
    "loss_db": ((int, float), "against the truth only: a scene below psnr_db still keeps the promise when its PSNR "
                              "against the truth is at most loss_db below the float reference's own (the scene as "
                              "written, rounded to 8 bits like the unit's output) against it"),
    "against": (str, '"reference" (the float reference of the scene as written) or "truth" (the converged truth)'),
    "share": ((int, float), "the share of the held-out scenes it accepts that must keep it, 0..1"),
    "note": (str, "where the figure comes from"),
}


def _promise(tab, p: Path) -> dict | None:
    """A file's [promise] table, checked: {psnr_db, against, share, note; loss_db with against "truth"}."""
    if tab is None:
        return None
    if not isinstance(tab, dict):
        raise ConfigError(f"{p}: 'promise' must be a table")
    for k, v in tab.items():
        if k not in PROMISE_KEYS:
            raise ConfigError(f"{p}: unknown key 'promise.{k}' (expected one of {sorted(PROMISE_KEYS)})")
        typ, what = PROMISE_KEYS[k]
        if not isinstance(v, typ) or isinstance(v, bool):
            raise ConfigError(f"{p}: 'promise.{k}' = {v!r}: expected {what}")
    for k in ("psnr_db", "against", "share"):
        if k not in tab:
            raise ConfigError(f"{p}: missing key 'promise.{k}'")
    if "loss_db" in tab and (tab["against"] != "truth" or tab["loss_db"] < 0):
        raise ConfigError(f"{p}: 'promise.loss_db' = {tab['loss_db']} against {tab['against']!r}: expected a loss of "
                          f"0 dB or more against \"truth\"")
    if tab["against"] not in ("reference", "truth"):
        raise ConfigError(f"{p}: 'promise.against' = {tab['against']!r}: expected {PROMISE_KEYS['against'][1]}")
    if not 0 < tab["share"] <= 1:
        raise ConfigError(f"{p}: 'promise.share' = {tab['share']}: expected a share in (0, 1]")
    return dict(tab)


def _check(c: Config, p: Path) -> None:
    def need(cond, msg):
        if not cond:
            raise ConfigError(f"{p}: {msg}")

    need(c.s_frac < c.s_w, "formats.s_frac must be < s_w")
    need(c.q_frac < c.q_w, "formats.q_frac must be < q_w")
    need(c.t_frac < c.t_w or c.t_exp_w > 0, "formats.t_frac must be < t_w (without an exponent, t_exp_w = 0)")
    need(c.a_frac < c.a_w or c.a_exp_w > 0, "formats.a_frac must be < a_w (without an exponent, a_exp_w = 0)")
    need(c.s_frac + c.t_frac >= c.p_frac, "formats.p_frac must be <= s_frac + t_frac")
    te_max, ae_max = (1 << c.t_exp_w) - 1, (1 << c.a_exp_w) - 1
    need(c.t_exp_w == 0 or c.transform == "affine", "formats.t_exp_w > 0 needs transform = \"affine\"")
    need(c.a_exp_w == 0 or c.amplitude == "any", "formats.a_exp_w > 0 needs amplitude = \"any\"")
    need(c.t_exp_w == 0 or c.s_frac + c.t_frac - c.p_frac >= te_max, "formats: s_frac + t_frac - p_frac must be >= 2^t_exp_w - 1 "
                                                   "(T s is shifted right by it less the exponent)")
    need(c.t_exp_w == 0 or c.n_frac + c.t_frac - c.c_frac >= te_max, "formats: n_frac + t_frac - c_frac must be >= 2^t_exp_w - 1")
    need(c.a_exp_w == 0 or c.a_frac + c.n_frac - c.f_frac >= ae_max, "formats: a_frac + n_frac - f_frac must be >= 2^a_exp_w - 1")
    need(c.a_frac >= ae_max, "formats: a_frac must be >= 2^a_exp_w - 1")
    need(c.n_frac >= c.hash_bits - 1, "formats.n_frac must be >= hash_bits - 1 (lattice values are exact)")
    need(c.w_cap_log2 >= c.n_log2_max, "formats.w_cap_log2 must be >= n_log2_max (w must reach N)")
    need(c.noise_units <= max(c.noise_terms, 1), f"features.noise_units = {c.noise_units} must be <= noise_terms "
                                                 f"= {c.noise_terms} (U noise units take the K terms U a clock)")
    need(not freq_clamp(c) or not (0 < c.noise_units < c.noise_terms),
         f"features.filter = \"{c.filter}\" needs unfolded noise terms (noise_units = noise_terms)")
    need(c.samples in SAMPLE_COUNTS, f"features.samples = {c.samples}: expected one of {list(SAMPLE_COUNTS)}")
    need(c.quadric_clocks in QUADRIC_CLOCKS, f"features.quadric_clocks = {c.quadric_clocks}: expected one of {list(QUADRIC_CLOCKS)}")
    need(c.quadric_clocks == 1 or (c.quadric == "diagonal" and 0 < c.noise_units < c.noise_terms),
         f"features.quadric_clocks = {c.quadric_clocks} needs a diagonal quadric and folded noise terms (noise_units < noise_terms)")
    need(c.cmap_clocks in CMAP_CLOCKS, f"features.cmap_clocks = {c.cmap_clocks}: expected one of {list(CMAP_CLOCKS)}")
    need(c.cmap_clocks == 1 or (c.filter == "sat" and 0 < c.noise_units < c.noise_terms and not c.fpga_regs),
         f"features.cmap_clocks = {c.cmap_clocks} needs filter = \"sat\", folded noise terms (noise_units < "
         f"noise_terms) and fpga_regs = false")


def _check_rtl(c: Config, p: Path) -> None:
    """The limits the RTL blocks check at elaboration (their g_bad_params), on the derived
    widths: a configuration that passes here elaborates."""
    def need(cond, msg):
        if not cond:
            raise ConfigError(f"{p}: {msg}")

    need(c.gabs_w > c.norm_bits, f"formats.norm_bits = {c.norm_bits} must be < {c.gabs_w} (the bits of |grad f| "
                                 "filter_width normalises)")
    need(c.e_w > c.sh_w, "formats: the filter-width exponent must be wider than its normalising shift")
    need(c.r_w >= 3, "formats.norm_bits too small for the 3-stage square root")
    if c.filter in SAT_FILTERS and 0 < c.div_bits < c.w_w:
        nq_w = c.div_bits + 8 + (1 if c.div_bits <= 9 else 0)
        need(nq_w <= c.d_w - 1, f"formats.div_bits = {c.div_bits}: the normalised quotient needs {nq_w} bits, "
                                f"the box-filter integral has {c.d_w - 1}")
    if c.filter in SAT2_FILTERS:
        # Gamma + 4ab + 2h(sh) < 2^(d2_w + 1) must fit the golden model's int64 (numpy) words
        need(c.d2_w <= 61, f"features.filter = \"{c.filter}\": 2 (w_cap_log2 + f_frac) = "
                           f"{2 * (c.w_cap_log2 + c.f_frac)} must be <= 50 (the trapezoid's second difference "
                           f"has {c.d2_w} bits; at most 61)")


def rel_path(path) -> str:
    """A path relative to the repository root when inside it, else absolute (for reports)."""
    p = Path(path).resolve()
    return str(p.relative_to(ROOT)) if p.is_relative_to(ROOT) else str(p)


# ---------------------------------------------------------------------------
# Configurations that are not files: variants of a configuration, random valid points of
# the family, and their TOML text (a simulator process reads a configuration by path)


def config_values(cfg: Config) -> dict:
    """{key: value} of every configuration key of cfg (the schema's keys; an OPTIONAL_KEYS key
    only where it differs from its default)."""
    return {key: getattr(cfg, key) for key in SCHEMA
            if key not in OPTIONAL_KEYS or getattr(cfg, key) != OPTIONAL_KEYS[key]}


def config_hash(cfg: Config) -> str:
    """A short hash of cfg's keys (not its name, path or promise): a generated report records it
    for each configuration it measured, and tests/test_stale_docs.py fails when it no longer
    matches the file."""
    import hashlib
    import json

    return hashlib.sha256(json.dumps(config_values(cfg), sort_keys=True).encode()).hexdigest()[:12]


def rtl_source_hash() -> str:
    """A short hash of rtl/ (every file's name and bytes): what a generated doc's RTL figures ran on."""
    import hashlib

    h = hashlib.sha256()
    for p in sorted((ROOT / "rtl").glob("*.v*")):
        h.update(p.name.encode() + b"\0" + p.read_bytes())
    return h.hexdigest()[:12]


STAMP = "<!-- measured on:"


def doc_stamp(configs, rtl: bool = True, ran_on=None) -> str:
    """The line a generated doc ends with: the hash of each configuration it measured (and of rtl/),
    as `<!-- measured on: full=<hash> reduced=<hash> rtl=<hash> -->`;
    tests/test_validate.py fails when a configuration changed since (rerun the doc's command).
    ran_on: for a doc assembled from several runs' reports, the rtl/ hash each row ran on (None: a
    report that did not record it); the stamp names the first that is not today's ("unrecorded" for
    None), so a doc with a row of an older run stays stale until that row is measured again."""
    cfgs = []
    for c in configs:  # Configs, or names (stamped_config: a name that is none, e.g. "compact-fpga", is skipped)
        if isinstance(c, Config):
            cfgs.append(c)
        elif all(x.name != c for x in cfgs) and (sc := stamped_config(str(c))) is not None:
            cfgs.append(sc)
    parts = [f"{c.name}={config_hash(c)}" for c in cfgs]
    if rtl:
        now = rtl_source_hash()
        old = [h or "unrecorded" for h in (ran_on or ()) if h != now]
        parts.append(f"rtl={old[0] if old else now}")
    return f"{STAMP} {' '.join(parts)} -->"


def read_stamp(text: str) -> dict | None:
    """{name: hash} of a doc's stamp (rtl included), or None when it has none."""
    for line in text.splitlines():
        if line.startswith(STAMP):
            return dict(kv.split("=", 1) for kv in line[len(STAMP):].replace("-->", "").split())
    return None


def config_toml(cfg: Config) -> str:
    """cfg as configuration-file text (load_config of it gives the same configuration)."""
    lines = [f"# Configuration `{cfg.name}`, written by model/hw/config.py config_toml.", "",
             f"name = \"{cfg.name}\""]
    for sec in ("features", "formats", "hash"):
        lines += ["", f"[{sec}]"]
        for key, (s, typ, _rng) in SCHEMA.items():
            if s == sec:
                v = getattr(cfg, key)
                lines.append(f"{key} = " + (f'"{v}"' if typ is str else ("true" if v is True else "false")
                                            if typ is bool else str(int(v))))
    return "\n".join(lines) + "\n"


def variant(base: Config, name: str | None = None, **changes) -> Config:
    """base with some keys changed, checked like a file (ConfigError names the key)."""
    vals = config_values(base)
    for k in changes:
        if k not in SCHEMA:
            raise ConfigError(f"{base.path}: unknown key '{k}'")
    vals.update(changes)
    raw = {"name": name or base.name}
    for key, (sec, _t, _r) in SCHEMA.items():
        if key in vals:
            raw.setdefault(sec, {})[key] = vals[key]
    return _from_raw(raw, Path(f"<{raw['name']}>"))


def random_config(seed: int, name: str | None = None, tries: int = 1000) -> Config:
    """A random valid configuration (every key drawn; redrawn until it passes every check).

    The draw stays near the sizes a texture unit uses (a few bits either side of the
    named configurations) so that block simulations of it stay quick.
    """
    r = np.random.default_rng(seed)
    fpga_regs = bool(np.random.default_rng([seed, 17]).integers(0, 2))
    base = load_config("full_wide")  # the keys not drawn (fc_*, no per-term exponents): full's before issue 26
    for _ in range(tries):
        v = config_values(base)
        v["quadric"] = str(r.choice(["full", "diagonal"]))
        v["noise_terms"] = int(r.integers(0, 9))
        v["blend"] = str(r.choice(["cubic", "linear"]))
        v["transform"] = str(r.choice(["affine", "pow2"]))
        v["amplitude"] = str(r.choice(["any", "pow2"]))
        v["filter"] = str(r.choice(["sat", "sat", "mip", "none"]))
        v["noise_gradient"] = bool(r.integers(0, 2))
        v["s_frac"] = int(r.integers(6, 18))
        v["s_w"] = v["s_frac"] + int(r.integers(5, 10))
        v["q_frac"] = int(r.integers(4, 18))
        v["q_w"] = v["q_frac"] + int(r.integers(6, 9))
        v["j_w"] = int(r.integers(4, 14))
        v["je_w"] = int(r.integers(4, 9))
        v["t_frac"] = int(r.integers(2, 12))
        v["t_w"] = v["t_frac"] + int(r.integers(3, 8))
        v["a_frac"] = int(r.integers(3, 14))
        v["a_w"] = v["a_frac"] + int(r.integers(2, 5))
        v["hash_bits"] = int(r.integers(2, 9))
        v["p_frac"] = int(r.integers(3, 14))
        v["n_frac"] = int(r.integers(max(2, v["hash_bits"] - 1), 14))
        v["f_frac"] = int(r.integers(8, 18))
        v["c_frac"] = int(r.integers(4, 14))
        v["norm_bits"] = int(r.integers(4, 14))
        v["n_log2_max"] = int(r.integers(1, 9))
        v["w_cap_log2"] = v["n_log2_max"] + int(r.integers(0, 9))
        v["div_bits"] = int(r.choice([0, int(r.integers(4, 16))]))
        v["seed"] = int(r.integers(0, 2**31 - 1))
        v["noise_units"] = int(r.integers(1, max(v["noise_terms"], 1) + 1))
        v["quadric_clocks"] = int(r.choice([1, 2])) if (v["quadric"] == "diagonal"
                                                          and v["noise_units"] < v["noise_terms"]) else 1
        if v["filter"] == "sat" and v["noise_units"] == v["noise_terms"] and r.random() < 0.5:
            v["filter"] = "sat_fc"  # frequency clamping needs the terms unfolded
            v["fc_log_frac"] = int(r.integers(1, 7))
            v["fc_fade_log2"] = int(r.integers(0, 4))
            v["fc_knee"] = int(r.integers(-2, 6)) << v["fc_log_frac"]
        # the trapezoid (issue 27) in place of a quarter of the box draws whose words fit it (d2_w <= 61:
        # w_cap_log2 + f_frac <= 25), drawn from a generator of its own, so that the other keys' draws are
        # what they were
        if (v["filter"] == "sat" and v["w_cap_log2"] + v["f_frac"] <= 25
                and np.random.default_rng([seed, 27]).random() < 0.25):
            v["filter"] = "sat2"
        # the trapezoid with frequency clamping in place of half the sat_fc draws whose words fit it
        # (a generator of its own again: the other draws are what they were)
        if (v["filter"] == "sat_fc" and v["w_cap_log2"] + v["f_frac"] <= 25
                and np.random.default_rng([seed, 28]).random() < 0.5):
            v["filter"] = "sat2_fc"
        # drawn from a generator of its own, so that the other keys' draws are what they were
        v["fpga_regs"] = fpga_regs
        try:
            return variant(base, name or f"random{seed}", **v)
        except ConfigError:
            continue
    raise ConfigError(f"random_config({seed}): no valid configuration in {tries} draws")


# ---------------------------------------------------------------------------
# Input limits of a configuration: what a scene may hold (the one copy of the limits; the
# scene parser takes the widest over the configuration files, model.hw.quantize enforces a
# configuration's own, model.scene.frontend.fixed_point_violations reports them)


def fixed_range(w: int, frac: int, signed: bool = True) -> tuple[float, float]:
    """The closed range of values a format sN.F / uN.F holds."""
    lo, hi = (-(1 << (w - 1)), (1 << (w - 1)) - 1) if signed else (0, (1 << w) - 1)
    return lo / 2.0 ** frac, hi / 2.0 ** frac


def t_format(cfg: Config) -> str:
    """T_i's format: s{t_w}.{t_frac}, or with exponents s{t_w}.{t_frac} x 2^[0..te_max]."""
    f = f"s{cfg.t_w}.{cfg.t_frac}"
    return f + (f" x 2^[0..{cfg.d['te_max']}]" if cfg.t_exp_w else "")


def a_format(cfg: Config) -> str:
    """a_i's format: s{a_w}.{a_frac}, or with exponents s{a_w}.{a_frac} x 2^[0..ae_max]."""
    f = f"s{cfg.a_w}.{cfg.a_frac}"
    return f + (f" x 2^[0..{cfg.d['ae_max']}]" if cfg.a_exp_w else "")


def input_limits(cfg: Config) -> dict:
    """{quantity: (lo, hi, format)} of the scene values cfg takes, plus the counts
    (noise_terms, clut_max) and the modes that restrict values (quadric, transform, amplitude)."""
    return {
        "s": (*fixed_range(cfg.s_w, cfg.s_frac), f"s{cfg.s_w}.{cfg.s_frac}"),
        "quadric": (*fixed_range(cfg.q_w, cfg.q_frac), f"s{cfg.q_w}.{cfg.q_frac}"),
        "T": (*fixed_range(cfg.t_w, cfg.t_frac - cfg.d["te_max"]), t_format(cfg)),
        "a": (*fixed_range(cfg.a_w, cfg.a_frac - cfg.d["ae_max"]), a_format(cfg)),
        "noise_terms": cfg.noise_terms,
        "clut_max": 1 << cfg.n_log2_max,
        "quadric_mode": cfg.quadric, "transform": cfg.transform, "amplitude": cfg.amplitude,
    }


def widest_input_limits(names=None) -> dict:
    """The widest limits over the configuration files (every file of config/ unless names are
    given): {quantity: (lo, hi, 'config format')} for s, quadric, T, a; noise_terms and clut_max
    the largest (with the configuration)."""
    out = {}
    for name in (config_file_names() if names is None else names):
        lim = input_limits(load_config(name))
        for k in ("s", "quadric", "T", "a"):
            lo, hi, fmt = lim[k]
            if k not in out or hi - lo > out[k][1] - out[k][0]:
                out[k] = (lo, hi, f"{name} {fmt}")
        for k in ("noise_terms", "clut_max"):
            if k not in out or lim[k] > out[k][0]:
                out[k] = (lim[k], name)
    return out


def main(argv=None) -> int:
    """python -m model.hw.config NAME|PATH: the configuration's keys and derived widths (JSON)."""
    import json

    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1:
        print("usage: python -m model.hw.config NAME|PATH", file=sys.stderr)
        return 2
    try:
        cfg = load_config(argv[0])
    except ConfigError as e:
        print(f"config: {e}", file=sys.stderr)
        return 2
    print(json.dumps({"name": cfg.name, "path": rel_path(cfg.path), "keys": config_values(cfg), "derived": cfg.d},
                     indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
