"""The texture_pipeline register map and pixel stream formats, in Python.

The twin of the ports of rtl/texture_pipeline.v: what the parameter write port expects
(`write_sequence`), how rtl/tex_regs.v decodes it (`tex_regs`), how a pixel is packed into
s_axis_tdata (`pack_pixels`) and the colour unpacked from m_axis_tdata (`unpack_rgba`).
All widths come from the configuration (model/hw/config.py).

Register map: REGMAP_TABLE below, its one definition (word addresses, 32-bit data; signed
values two's complement in the LSBs of the word). rtl/tex_regmap.vh is generated from it
(`python -m model.hw.regmap --write`; --check, and tb/tex_regs, fail on a stale copy), the
decoder rtl/tex_regs.v reads that, `tex_regs` here is the decoder's twin, and
`write_sequence`'s writes round-trip through it.

Pixel word: {je, Jm, s} with s at the LSBs:

    [0 : 3*s_w)                   s, t, r (element e at e*s_w)
    [3*s_w : 3*s_w + 6*j_w)       Jm[k][col] at element 2*k + col
    [3*s_w + 6*j_w : pix_w)       je
"""
from __future__ import annotations

import numpy as np

from model.hw.config import TABLE_FILTERS, Config
from model.hw.golden import MODE_CLAMP, MODE_MOD, TexInt

# ---------------------------------------------------------------------------
# The register map, written once: every other copy is generated from this table or reads it.
#   - rtl/tex_regmap.vh: RM_<name> localparams for the RTL decoder rtl/tex_regs.v
#     (regmap_vh() writes it, `python -m model.hw.regmap --write` regenerates the committed
#     file, tb/tex_regs/test_tex_regs.py fails when it is stale);
#   - the Python constants below (ADDR_*, TERM_*, CTRL_*), read by write_sequence, the decoder's
#     twin tex_regs and the tests' writes (tb/frame/test_frame.py junk_writes).
# Each row: (name, value, meaning). Addresses are 32-bit-word addresses on cfg_wr_addr.
REGMAP_TABLE = (
    ("ADDR_W", 16, "bits of cfg_wr_addr"),
    ("DATA_W", 32, "bits of cfg_wr_data; a value sits in the LSBs, signed ones two's complement"),
    ("REGION_LSB", 12, "cfg_wr_addr[ADDR_W-1:REGION_LSB] selects a region (a base address >> REGION_LSB), "
                       "the bits below are the offset in it"),
    ("ADDR_CTRL", 0x0000, "CTRL register"),
    ("CTRL_MODE_BIT", 0, "CTRL bit: colour-table index mode (0 mod, 1 clamp)"),
    ("CTRL_FILTER_BIT", 1, "CTRL bit: filter_en"),
    ("CTRL_NLOG2_LSB", 8, "CTRL field [CTRL_NLOG2_LSB +: n_log2_w]: n_log2 (N = 2^n_log2 colour-table entries)"),
    ("CTRL_KUSED_LSB", 16, "CTRL field [CTRL_KUSED_LSB +: bits of K]: k_used, the noise terms the texture uses "
                           "(terms 0..k_used-1; the others are skipped: a pixel takes ceil(k_used / U) clocks)"),
    ("ADDR_Q", 0x0010, "quadric coefficient i (A..J) at ADDR_Q + i, s{q_w}.{q_frac}"),
    ("Q_COUNT", 10, "quadric coefficients"),
    ("ADDR_TERM", 0x0100, "noise term k at ADDR_TERM + TERM_STRIDE*k + field (terms k >= K are ignored)"),
    ("TERM_STRIDE", 16, "words per noise term (a power of two)"),
    ("TERM_SLOTS", 16, "noise-term slots in the address space (a power of two, >= 8)"),
    ("TERM_A", 0, "term field: a_k, s{a_w}.{a_frac}"),
    ("TERM_T", 1, "term fields TERM_T + 3*j + m: T_k[j][m], s{t_w}.{t_frac}"),
    ("TERM_O", 10, "term fields TERM_O + j: o_k[j], u{o_w}.{p_frac}"),
    ("TERM_E", 13, "term field: the exponents of T_k and a_k (formats.t_exp_w, a_exp_w > 0; ignored without): "
                   "te_k u{t_exp_w} at [TERM_E_TE_LSB +: t_exp_w], ae_k u{a_exp_w} at [TERM_E_AE_LSB +: a_exp_w]"),
    ("TERM_E_TE_LSB", 0, "TERM_E field: te_k (T_k = T mantissas 2^(te_k - t_frac))"),
    ("TERM_E_AE_LSB", 8, "TERM_E field: ae_k (a_k = a mantissa 2^(ae_k - a_frac))"),
    ("ADDR_CLUT", 0x1000, "clut[n], RGBA8 (R at [7:0]), at ADDR_CLUT + n"),
    ("CLUT_LOG2", 0, "clut words accepted: 2^(n_log2_max + CLUT_LOG2)"),
    ("ADDR_CSAT", 0x2000, "csat[n] channel ch (u{csat_w}) at ADDR_CSAT + CSAT_CHANNELS*n + ch: channels "
                          "0..2 are staged, channel 3 commits entry n (write entries in ascending order)"),
    ("CSAT_CHANNELS", 4, "words per csat entry"),
    ("CSAT_LOG2", 2, "csat words accepted: 2^(n_log2_max + CSAT_LOG2) (= CSAT_CHANNELS entries' words)"),
    ("ADDR_MIP", 0x3000, "mip[m], RGBA8, at ADDR_MIP + m (level l at offset 2N - (2N >> l))"),
    ("MIP_LOG2", 1, "mip words accepted: 2^(n_log2_max + MIP_LOG2)"),
    ("TABLE_CLUT", 0, "colour_map wr_table code of clut"),
    ("TABLE_CSAT", 1, "colour_map wr_table code of csat"),
    ("TABLE_MIP", 2, "colour_map wr_table code of mip"),
)
REGMAP = {name: value for name, value, _ in REGMAP_TABLE}


def _log2_exact(name: str, v: int) -> int:
    if v <= 0 or v & (v - 1):
        raise AssertionError(f"register map: {name} = {v} must be a power of two")
    return v.bit_length() - 1


def _derived(rm: dict) -> dict:
    """Constants the decoder derives from the table (also emitted into rtl/tex_regmap.vh), with
    the table's consistency checked: no two registers share an address, every field fits."""
    lsb, aw = rm["REGION_LSB"], rm["ADDR_W"]
    d = {"TERM_STRIDE_LOG2": _log2_exact("TERM_STRIDE", rm["TERM_STRIDE"]),
         "TERM_SLOTS_LOG2": _log2_exact("TERM_SLOTS", rm["TERM_SLOTS"])}
    for name in ("REGS", "CLUT", "CSAT", "MIP"):
        base = rm["ADDR_CTRL" if name == "REGS" else f"ADDR_{name}"]
        if name != "REGS" and base & ((1 << lsb) - 1):
            raise AssertionError(f"register map: ADDR_{name} must start a region")
        d[f"REGION_{name}"] = base >> lsb
    regions = [d[f"REGION_{n}"] for n in ("REGS", "CLUT", "CSAT", "MIP")]
    assert len(set(regions)) == 4 and max(regions) < (1 << (aw - lsb)), "register map: regions overlap"
    assert _log2_exact("CSAT_CHANNELS", rm["CSAT_CHANNELS"]) == rm["CSAT_LOG2"], \
        "register map: CSAT_LOG2 != log2(CSAT_CHANNELS)"
    # region 0: CTRL, Q and the term window (aligned: the decoder selects term and field by bit slices)
    win = rm["TERM_STRIDE"] * rm["TERM_SLOTS"]
    assert rm["ADDR_TERM"] % win == 0, "register map: ADDR_TERM must be aligned to TERM_STRIDE * TERM_SLOTS"
    assert rm["TERM_SLOTS"] >= 8, "register map: fewer term slots than noise terms"
    regs = [rm["ADDR_CTRL"]] + [rm["ADDR_Q"] + i for i in range(rm["Q_COUNT"])]
    assert all(a >> lsb == d["REGION_REGS"] for a in regs + [rm["ADDR_TERM"], rm["ADDR_TERM"] + win - 1])
    assert not any(rm["ADDR_TERM"] <= a < rm["ADDR_TERM"] + win for a in regs), "register map: Q/CTRL in the term window"
    assert len(set(regs)) == len(regs), "register map: two registers share an address"
    fields = ([rm["TERM_A"]] + [rm["TERM_T"] + i for i in range(9)] + [rm["TERM_O"] + j for j in range(3)]
              + [rm["TERM_E"]])
    assert len(set(fields)) == len(fields) and max(fields) < rm["TERM_STRIDE"], "register map: term fields"
    # te and ae have at most 4 bits each (formats.t_exp_w, a_exp_w <= 4)
    assert rm["TERM_E_TE_LSB"] + 4 <= rm["TERM_E_AE_LSB"] <= rm["DATA_W"] - 4, "register map: TERM_E fields"
    ctrl = (rm["CTRL_MODE_BIT"], rm["CTRL_FILTER_BIT"])
    assert len(set(ctrl)) == 2 and max(ctrl) < rm["CTRL_NLOG2_LSB"] < rm["DATA_W"] - 4, "register map: CTRL fields"
    # n_log2 has at most 4 bits (n_log2_max <= 10), k_used at most 4 (K <= 8)
    assert rm["CTRL_NLOG2_LSB"] + 4 <= rm["CTRL_KUSED_LSB"] <= rm["DATA_W"] - 4, "register map: CTRL fields"
    return d


REGMAP_DERIVED = _derived(REGMAP)

ADDR_CTRL = REGMAP["ADDR_CTRL"]
ADDR_Q = REGMAP["ADDR_Q"]
Q_COUNT = REGMAP["Q_COUNT"]
ADDR_TERM = REGMAP["ADDR_TERM"]
TERM_STRIDE = REGMAP["TERM_STRIDE"]
TERM_SLOTS = REGMAP["TERM_SLOTS"]
TERM_A, TERM_T, TERM_O, TERM_E = REGMAP["TERM_A"], REGMAP["TERM_T"], REGMAP["TERM_O"], REGMAP["TERM_E"]
TERM_E_TE_LSB, TERM_E_AE_LSB = REGMAP["TERM_E_TE_LSB"], REGMAP["TERM_E_AE_LSB"]
ADDR_CLUT = REGMAP["ADDR_CLUT"]
ADDR_CSAT = REGMAP["ADDR_CSAT"]
CSAT_CHANNELS = REGMAP["CSAT_CHANNELS"]
ADDR_MIP = REGMAP["ADDR_MIP"]
CTRL_MODE_BIT, CTRL_FILTER_BIT, CTRL_NLOG2_LSB = (REGMAP["CTRL_MODE_BIT"], REGMAP["CTRL_FILTER_BIT"],
                                                  REGMAP["CTRL_NLOG2_LSB"])
CTRL_KUSED_LSB = REGMAP["CTRL_KUSED_LSB"]
REGION_LSB = REGMAP["REGION_LSB"]
ADDR_SPACE = 1 << REGMAP["ADDR_W"]
TABLE_CLUT, TABLE_CSAT, TABLE_MIP = REGMAP["TABLE_CLUT"], REGMAP["TABLE_CSAT"], REGMAP["TABLE_MIP"]
REGMAP_VH = "rtl/tex_regmap.vh"


def regmap_vh() -> str:
    """The text of rtl/tex_regmap.vh: the table as RM_<name> localparams (addresses sized to
    ADDR_W bits, region codes to ADDR_W - REGION_LSB bits, table codes to 2 bits)."""
    aw, rw = REGMAP["ADDR_W"], REGMAP["ADDR_W"] - REGMAP["REGION_LSB"]
    out = ["// tex_regmap.vh: the register map of texture_pipeline, as localparams.",
           "// Generated from model/hw/regmap.py REGMAP_TABLE by `python -m model.hw.regmap --write`. Do not edit:",
           "// tb/tex_regs/test_tex_regs.py fails when this file is not what the table generates.",
           "// Included inside the body of rtl/tex_regs.v (the decoder); addresses are 32-bit-word addresses.",
           "", "/* verilator lint_off UNUSEDPARAM */"]

    def line(name, value, what):
        if name.startswith("ADDR_") and name != "ADDR_W":
            decl = f"localparam [{aw - 1}:0] RM_{name} = {aw}'h{value:0{(aw + 3) // 4}x};"
        elif name.startswith("REGION_") and name != "REGION_LSB":
            decl = f"localparam [{rw - 1}:0] RM_{name} = {rw}'h{value:x};"
        elif name.startswith("TABLE_"):
            decl = f"localparam [1:0] RM_{name} = 2'd{value};"
        else:
            decl = f"localparam integer RM_{name} = {value};"
        out.append(f"{decl:<50} // {what}")

    for name, value, what in REGMAP_TABLE:
        line(name, value, what)
    out.append("// derived")
    for name, value in REGMAP_DERIVED.items():
        line(name, value, f"region code: ADDR_{'CTRL' if name == 'REGION_REGS' else name[7:]} >> REGION_LSB"
             if name.startswith("REGION_") else f"log2({name[:-5]})")
    out += ["/* verilator lint_on UNUSEDPARAM */", ""]
    return "\n".join(out)


class RegmapError(ValueError):
    """A parameter that does not fit its register (one-line message)."""


def pix_width(cfg: Config) -> int:
    """Bits of one s_axis_tdata word."""
    return 3 * cfg.s_w + 6 * cfg.j_w + cfg.je_w


def _fit(name: str, v, w: int, signed: bool) -> int:
    v = int(v)
    lo, hi = (-(1 << (w - 1)), (1 << (w - 1)) - 1) if signed else (0, (1 << w) - 1)
    if not lo <= v <= hi:
        raise RegmapError(f"{name} = {v} does not fit {'s' if signed else 'u'}{w} [{lo}, {hi}]")
    return v & 0xFFFFFFFF


def _rgba_word(px) -> int:
    return sum((int(px[c]) & 0xFF) << (8 * c) for c in range(4))


def write_sequence(cfg: Config, tex: TexInt) -> list[tuple[int, int]]:
    """The (address, data) writes that load `tex` into texture_pipeline.

    Every parameter register is written (noise terms beyond len(tex.a) get zeros; with
    per-term exponents, cfg.t_exp_w or a_exp_w > 0, each term's TERM_E word too: te_k, ae_k),
    so a pass never depends on the previous one. The colour tables written are the
    ones the configuration's filter reads: clut always, csat for "sat", "sat_fc", "sat2" and "sat2_fc" (sat2's
    running sum of csat is derived by the unit from the csat writes, in ascending order), mip for "mip".
    """
    if cfg.d["o_w"] > 32 or cfg.q_w > 32 or cfg.a_w > 32 or cfg.t_w > 32 or cfg.csat_w > 32:
        raise RegmapError(f"{cfg.name}: a parameter wider than 32 bits does not fit one register word")
    n_log2 = int(tex.n_log2)
    if not 0 <= n_log2 <= cfg.n_log2_max:
        raise RegmapError(f"n_log2 = {n_log2} outside 0..{cfg.n_log2_max}")
    if tex.mode not in (MODE_MOD, MODE_CLAMP):
        raise RegmapError(f"mode = {tex.mode!r}")
    n = 1 << n_log2
    K = cfg.noise_terms
    w: list[tuple[int, int]] = []
    k_used = min(int(tex.k_used), K)
    ctrl = ((int(tex.mode) << CTRL_MODE_BIT) | (int(bool(tex.filter)) << CTRL_FILTER_BIT) | (n_log2 << CTRL_NLOG2_LSB)
            | (k_used << CTRL_KUSED_LSB))
    w.append((ADDR_CTRL, ctrl))
    Q = np.asarray(tex.Q, dtype=np.int64).reshape(Q_COUNT)
    for i in range(Q_COUNT):
        w.append((ADDR_Q + i, _fit(f"Q[{i}]", Q[i], cfg.q_w, True)))
    a = np.asarray(tex.a, dtype=np.int64).reshape(-1)
    T = np.asarray(tex.T, dtype=np.int64).reshape(-1, 3, 3)
    o = np.asarray(tex.o, dtype=np.int64).reshape(-1, 3)
    if np.any(a[K:] != 0):
        raise RegmapError(f"texture has {int(np.count_nonzero(a[K:]))} non-zero terms beyond K = {K}")
    te = np.asarray(tex.te, dtype=np.int64).reshape(-1)
    ae = np.asarray(tex.ae, dtype=np.int64).reshape(-1)
    exps = bool(cfg.t_exp_w or cfg.a_exp_w)  # TERM_E is written only with exponents
    for k in range(K):
        base = ADDR_TERM + TERM_STRIDE * k
        have = k < len(a)
        w.append((base + TERM_A, _fit(f"a[{k}]", a[k] if have else 0, cfg.a_w, True)))
        for j in range(3):
            for m in range(3):
                w.append((base + TERM_T + 3 * j + m, _fit(f"T[{k}][{j}][{m}]", T[k, j, m] if have else 0, cfg.t_w, True)))
        for j in range(3):
            w.append((base + TERM_O + j, _fit(f"o[{k}][{j}]", o[k, j] if have else 0, cfg.d["o_w"], False)))
        if exps:
            tk = _fit(f"te[{k}]", te[k] if have else 0, cfg.t_exp_w, False) if cfg.t_exp_w else 0
            ak = _fit(f"ae[{k}]", ae[k] if have else 0, cfg.a_exp_w, False) if cfg.a_exp_w else 0
            w.append((base + TERM_E, (tk << TERM_E_TE_LSB) | (ak << TERM_E_AE_LSB)))
    for name, e, ew in (("te", te, cfg.t_exp_w), ("ae", ae, cfg.a_exp_w)):
        if not ew and np.any(e[:K] != 0):
            raise RegmapError(f"{name} = {e[:K].tolist()}: the configuration has no exponent ({name[0]}_exp_w = 0)")
    clut = np.asarray(tex.clut, dtype=np.int64)
    if clut.shape != (n, 4):
        raise RegmapError(f"clut shape {clut.shape}, expected ({n}, 4) for n_log2 = {n_log2}")
    if np.any((clut < 0) | (clut > 255)):
        raise RegmapError("clut entries must be 0..255")
    for i in range(n):
        w.append((ADDR_CLUT + i, _rgba_word(clut[i])))
    if cfg.filter in TABLE_FILTERS:
        csat = np.asarray(tex.csat, dtype=np.int64)
        for i in range(n):
            for c in range(4):
                w.append((ADDR_CSAT + CSAT_CHANNELS * i + c, _fit(f"csat[{i}][{c}]", csat[i, c], cfg.csat_w, False)))
    elif cfg.filter == "mip":
        mip = np.asarray(tex.mip, dtype=np.int64)
        for i in range(2 * n - 1):
            w.append((ADDR_MIP + i, _rgba_word(mip[i])))
    return w


# ---------------------------------------------------------------------------
# The decoder's twin (rtl/tex_regs.v)


def _mask(w: int) -> int:
    return (1 << w) - 1


class TexRegs:
    """The register state of rtl/tex_regs.v, as the RTL holds it (unsigned bit patterns).

    Fields after each write, one clock of the RTL per write (a clock without a write: `idle`):
    mode, filter_en, n_log2; q[Q_COUNT] (q_w bits), a[K], T[K][9], o[K][3], te[K] (t_exp_w
    bits), ae[K] (a_exp_w bits; both 0 without exponents); csat_stage[3];
    the table-write port registers tbl_wr_en, tbl_wr_table, tbl_wr_addr, tbl_wr_data (the
    four csat_w-bit channel fields packed, channel 0 at the LSBs), as forwarded to colour_map.
    """

    def __init__(self, cfg: Config):
        self.cfg = cfg
        self.K = cfg.noise_terms
        self.nmax = cfg.n_log2_max
        self.reset()

    def reset(self):
        K = self.K
        self.mode = self.filter_en = self.n_log2 = self.k_used = 0
        self.q = [0] * Q_COUNT
        self.a = [0] * K
        self.T = [[0] * 9 for _ in range(K)]
        self.o = [[0] * 3 for _ in range(K)]
        self.te = [0] * K
        self.ae = [0] * K
        self.csat_stage = [0] * (CSAT_CHANNELS - 1)
        self.tbl_wr_en = 0
        self.tbl_wr_table = TABLE_CLUT
        self.tbl_wr_addr = 0
        self.tbl_wr_data = 0

    def idle(self):
        """A clock without a write."""
        self.tbl_wr_en = 0

    def _rgba_wide(self, data: int) -> int:
        cw = self.cfg.csat_w
        return sum(((data >> (8 * c)) & 0xFF) << (c * cw) for c in range(4))

    def write(self, addr: int, data: int):
        """A clock with a write of `data` to `addr`; returns (table, index, data) when it writes
        a colour-table entry (what colour_map receives one clock later), else None."""
        cfg, lsb = self.cfg, REGION_LSB
        addr &= ADDR_SPACE - 1
        data &= 0xFFFFFFFF
        region, off = addr >> lsb, addr & _mask(lsb)
        self.tbl_wr_en = 0
        nmax, cw = self.nmax, cfg.csat_w
        if region == REGMAP_DERIVED["REGION_REGS"]:
            if off == ADDR_CTRL & _mask(lsb):
                self.mode = (data >> CTRL_MODE_BIT) & 1
                self.filter_en = (data >> CTRL_FILTER_BIT) & 1
                self.n_log2 = (data >> CTRL_NLOG2_LSB) & _mask(cfg.n_log2_w)
                self.k_used = (data >> CTRL_KUSED_LSB) & _mask(k_used_width(cfg))
            for i in range(Q_COUNT):
                if off == (ADDR_Q & _mask(lsb)) + i:
                    self.q[i] = data & _mask(cfg.q_w)
            t0 = ADDR_TERM & _mask(lsb)
            if t0 <= off < t0 + TERM_STRIDE * TERM_SLOTS:
                k, f = divmod(off - t0, TERM_STRIDE)
                if k < self.K:
                    if f == TERM_A:
                        self.a[k] = data & _mask(cfg.a_w)
                    if TERM_T <= f < TERM_T + 9:
                        self.T[k][f - TERM_T] = data & _mask(cfg.t_w)
                    if TERM_O <= f < TERM_O + 3:
                        self.o[k][f - TERM_O] = data & _mask(cfg.d["o_w"])
                    if f == TERM_E:  # without exponents (width 0) the field holds nothing
                        self.te[k] = (data >> TERM_E_TE_LSB) & _mask(cfg.t_exp_w)
                        self.ae[k] = (data >> TERM_E_AE_LSB) & _mask(cfg.a_exp_w)
            return None
        if region in (REGMAP_DERIVED["REGION_CLUT"], REGMAP_DERIVED["REGION_MIP"]):
            mip = region == REGMAP_DERIVED["REGION_MIP"]
            self.tbl_wr_en = int(off >> (nmax + REGMAP["MIP_LOG2" if mip else "CLUT_LOG2"]) == 0)
            self.tbl_wr_table = TABLE_MIP if mip else TABLE_CLUT
            self.tbl_wr_addr = off & _mask(nmax + 1)
            self.tbl_wr_data = self._rgba_wide(data)
        elif region == REGMAP_DERIVED["REGION_CSAT"]:
            chl = REGMAP["CSAT_LOG2"]
            ch = off & _mask(chl)
            if ch == CSAT_CHANNELS - 1:
                self.tbl_wr_en = int(off >> (nmax + REGMAP["CSAT_LOG2"]) == 0)
                self.tbl_wr_table = TABLE_CSAT
                self.tbl_wr_addr = (off >> chl) & _mask(nmax + 1)
                self.tbl_wr_data = sum(v << (c * cw) for c, v in enumerate(self.csat_stage + [data & _mask(cw)]))
            else:
                self.csat_stage[ch] = data & _mask(cw)
        if self.tbl_wr_en:
            return self.tbl_wr_table, self.tbl_wr_addr, self.tbl_wr_data
        return None


def k_used_width(cfg: Config) -> int:
    """Bits of the CTRL k_used field: 0..K (tex_regs KU_W)."""
    return max(1, int(cfg.noise_terms).bit_length())


def _signed(v: int, w: int) -> int:
    return v - (1 << w) if v >> (w - 1) & 1 else v


def tex_regs(cfg: Config, writes, state: TexRegs | None = None):
    """The twin of rtl/tex_regs.v: apply (address, data) writes (one a clock) to the register
    state (a fresh, reset one unless given). Returns (state, table), `table` the colour-table
    entries written: {TABLE_*: {index: [4 channel values]}}, later writes winning."""
    st = TexRegs(cfg) if state is None else state
    tables: dict = {TABLE_CLUT: {}, TABLE_CSAT: {}, TABLE_MIP: {}}
    cw = cfg.csat_w
    for addr, data in writes:
        tw = st.write(addr, data)
        if tw is not None:
            t, i, d = tw
            tables[t][i] = [(d >> (c * cw)) & _mask(cw) for c in range(4)]
    st.idle()
    return st, tables


def texint_of_regs(cfg: Config, st: TexRegs, tables) -> TexInt:
    """The texture that register state and colour tables hold (signed fields read back as
    signed): write_sequence(cfg, tex) applied by tex_regs must give back tex."""
    K, n = cfg.noise_terms, 1 << st.n_log2
    arr = lambda rows: np.array(rows, dtype=np.int64)  # noqa: E731

    def table(t, size):
        return arr([tables[t].get(i, [0, 0, 0, 0]) for i in range(size)]).reshape(size, 4)

    return TexInt(Q=arr([_signed(v, cfg.q_w) for v in st.q]),
                  a=arr([_signed(v, cfg.a_w) for v in st.a]),
                  T=arr([[_signed(v, cfg.t_w) for v in t] for t in st.T]).reshape(K, 3, 3),
                  o=arr(st.o).reshape(K, 3), mode=st.mode, n_log2=st.n_log2, filter=bool(st.filter_en),
                  clut=table(TABLE_CLUT, n), csat=table(TABLE_CSAT, n), mip=table(TABLE_MIP, 2 * n - 1),
                  k_used=st.k_used, te=arr(st.te), ae=arr(st.ae))


def _pixel_fields(cfg: Config, s, Jm, je) -> list[tuple[np.ndarray, int]]:
    """The fields of the pixel words, least significant first: (int64 column [P], width), each
    range-checked against its format (RegmapError otherwise)."""
    s = np.asarray(s, dtype=np.int64).reshape(-1, 3)
    P = s.shape[0]
    Jm = np.asarray(Jm, dtype=np.int64).reshape(P, 6)  # element 2*k + col = Jm[k][col]
    je = np.asarray(je, dtype=np.int64).reshape(P)
    for name, x, wd in (("s", s, cfg.s_w), ("Jm", Jm, cfg.j_w), ("je", je, cfg.je_w)):
        lo, hi = -(1 << (wd - 1)), (1 << (wd - 1)) - 1
        if x.size and (x.min() < lo or x.max() > hi):
            raise RegmapError(f"pixel {name} outside s{wd} [{lo}, {hi}]")
    return [(s[:, e], cfg.s_w) for e in range(3)] + [(Jm[:, e], cfg.j_w) for e in range(6)] + [(je, cfg.je_w)]


def pack_pixels(cfg: Config, s, Jm, je) -> list[int]:
    """s_axis_tdata words (Python ints, pix_width(cfg) bits) for pixels s [P, 3], Jm [P, 3, 2], je [P].

    Each field is range-checked against its format (RegmapError otherwise).
    """
    # words are wider than 64 bits: Python ints, built one field column at a time
    fields = _pixel_fields(cfg, s, Jm, je)
    words = [0] * len(fields[0][0])
    shift = 0
    for col, wd in fields:
        m = (1 << wd) - 1
        vals = (col & m).tolist()  # two's complement in wd bits (numpy & on int64)
        if shift == 0:
            words = vals
        else:
            words = [wv | (v << shift) for wv, v in zip(words, vals)]
        shift += wd
    return words


def pack_pixels_u32(cfg: Config, s, Jm, je) -> np.ndarray:
    """pack_pixels's words as uint32 [P, ceil(pix_width(cfg) / 32)], least significant word first,
    in numpy throughout (the binary pixel file of the Verilator frame harness, sim/frame_main.cpp)."""
    fields = _pixel_fields(cfg, s, Jm, je)
    nw = (pix_width(cfg) + 31) // 32
    out = np.zeros((len(fields[0][0]), nw + 1), dtype=np.uint64)  # a spare word: the last field's carry
    shift = 0
    for col, wd in fields:
        if wd > 32:
            raise RegmapError(f"pixel field of {wd} bits: pack_pixels_u32 takes at most 32")
        v = (col & ((1 << wd) - 1)).astype(np.uint64) << np.uint64(shift % 32)  # spans at most two words
        out[:, shift // 32] |= v & np.uint64(0xFFFFFFFF)
        out[:, shift // 32 + 1] |= v >> np.uint64(32)
        shift += wd
    return out[:, :nw].astype(np.uint32)


def unpack_pixels(cfg: Config, words):
    """Inverse of pack_pixels: (s [P, 3], Jm [P, 3, 2], je [P]) int64."""
    words = [int(x) for x in words]
    out = []
    shift = 0
    for count, wd in ((3, cfg.s_w), (6, cfg.j_w), (1, cfg.je_w)):
        m = (1 << wd) - 1
        cols = []
        for _ in range(count):
            v = np.array([(x >> shift) & m for x in words], dtype=np.int64)
            cols.append(np.where(v >> (wd - 1), v - (1 << wd), v))
            shift += wd
        out.append(np.stack(cols, axis=-1) if cols else np.zeros((len(words), 0), dtype=np.int64))
    return out[0], out[1].reshape(-1, 3, 2), out[2][:, 0]


def unpack_rgba(words) -> np.ndarray:
    """m_axis_tdata words -> uint8 [..., 4] (R, G, B, A)."""
    w = np.asarray(words, dtype=np.uint32)
    return np.stack([(w >> (8 * c)) & 0xFF for c in range(4)], axis=-1).astype(np.uint8)


def pixels_hex(cfg: Config, words) -> str:
    """$readmemh text of pixel words (one per line, fixed width)."""
    nd = (pix_width(cfg) + 3) // 4
    return "".join(f"{x:0{nd}x}\n" for x in words)


def writes_hex(writes) -> str:
    """$readmemh text of (address, data) writes: {addr[15:0], data[31:0]}, 12 hex digits a line."""
    return "".join(f"{a & 0xFFFF:04x}{d & 0xFFFFFFFF:08x}\n" for a, d in writes)


def main(argv=None) -> int:
    """python -m model.hw.regmap [--write | --check]: print rtl/tex_regmap.vh as the table
    generates it, write it (--write), or exit 1 when the committed file differs (--check)."""
    import argparse

    from model.hw.config import ROOT

    ap = argparse.ArgumentParser(description=main.__doc__)
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--write", action="store_true")
    g.add_argument("--check", action="store_true")
    args = ap.parse_args(argv)
    path = ROOT / REGMAP_VH
    text = regmap_vh()
    if args.write:
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
            print(f"wrote {REGMAP_VH}")
        return 0
    if args.check:
        ok = path.exists() and path.read_text() == text
        print(f"{REGMAP_VH}: {'current' if ok else 'STALE (python -m model.hw.regmap --write)'}")
        return 0 if ok else 1
    print(text, end="")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
