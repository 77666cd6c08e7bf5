// tex_regmap.vh: the register map of texture_pipeline, as localparams.
// Generated from model/hw/regmap.py REGMAP_TABLE by `python -m model.hw.regmap --write`. Do not edit:
// tb/tex_regs/test_tex_regs.py fails when this file is not what the table generates.
// Included inside the body of rtl/tex_regs.v (the decoder); addresses are 32-bit-word addresses.

/* verilator lint_off UNUSEDPARAM */
localparam integer RM_ADDR_W = 16;                 // bits of cfg_wr_addr
localparam integer RM_DATA_W = 32;                 // bits of cfg_wr_data; a value sits in the LSBs, signed ones two's complement
localparam integer RM_REGION_LSB = 12;             // cfg_wr_addr[ADDR_W-1:REGION_LSB] selects a region (a base address >> REGION_LSB), the bits below are the offset in it
localparam [15:0] RM_ADDR_CTRL = 16'h0000;         // CTRL register
localparam integer RM_CTRL_MODE_BIT = 0;           // CTRL bit: colour-table index mode (0 mod, 1 clamp)
localparam integer RM_CTRL_FILTER_BIT = 1;         // CTRL bit: filter_en
localparam integer RM_CTRL_NLOG2_LSB = 8;          // CTRL field [CTRL_NLOG2_LSB +: n_log2_w]: n_log2 (N = 2^n_log2 colour-table entries)
localparam integer RM_CTRL_KUSED_LSB = 16;         // CTRL field [CTRL_KUSED_LSB +: bits of K]: k_used, the noise terms the texture uses (terms 0..k_used-1; the others are skipped: a pixel takes ceil(k_used / U) clocks)
localparam [15:0] RM_ADDR_Q = 16'h0010;            // quadric coefficient i (A..J) at ADDR_Q + i, s{q_w}.{q_frac}
localparam integer RM_Q_COUNT = 10;                // quadric coefficients
localparam [15:0] RM_ADDR_TERM = 16'h0100;         // noise term k at ADDR_TERM + TERM_STRIDE*k + field (terms k >= K are ignored)
localparam integer RM_TERM_STRIDE = 16;            // words per noise term (a power of two)
localparam integer RM_TERM_SLOTS = 16;             // noise-term slots in the address space (a power of two, >= 8)
localparam integer RM_TERM_A = 0;                  // term field: a_k, s{a_w}.{a_frac}
localparam integer RM_TERM_T = 1;                  // term fields TERM_T + 3*j + m: T_k[j][m], s{t_w}.{t_frac}
localparam integer RM_TERM_O = 10;                 // term fields TERM_O + j: o_k[j], u{o_w}.{p_frac}
localparam integer RM_TERM_E = 13;                 // term field: the exponents of T_k and a_k (formats.t_exp_w, a_exp_w > 0; ignored without): te_k u{t_exp_w} at [TERM_E_TE_LSB +: t_exp_w], ae_k u{a_exp_w} at [TERM_E_AE_LSB +: a_exp_w]
localparam integer RM_TERM_E_TE_LSB = 0;           // TERM_E field: te_k (T_k = T mantissas 2^(te_k - t_frac))
localparam integer RM_TERM_E_AE_LSB = 8;           // TERM_E field: ae_k (a_k = a mantissa 2^(ae_k - a_frac))
localparam [15:0] RM_ADDR_CLUT = 16'h1000;         // clut[n], RGBA8 (R at [7:0]), at ADDR_CLUT + n
localparam integer RM_CLUT_LOG2 = 0;               // clut words accepted: 2^(n_log2_max + CLUT_LOG2)
localparam [15:0] RM_ADDR_CSAT = 16'h2000;         // csat[n] channel ch (u{csat_w}) at ADDR_CSAT + CSAT_CHANNELS*n + ch: channels 0..2 are staged, channel 3 commits entry n (write entries in ascending order)
localparam integer RM_CSAT_CHANNELS = 4;           // words per csat entry
localparam integer RM_CSAT_LOG2 = 2;               // csat words accepted: 2^(n_log2_max + CSAT_LOG2) (= CSAT_CHANNELS entries' words)
localparam [15:0] RM_ADDR_MIP = 16'h3000;          // mip[m], RGBA8, at ADDR_MIP + m (level l at offset 2N - (2N >> l))
localparam integer RM_MIP_LOG2 = 1;                // mip words accepted: 2^(n_log2_max + MIP_LOG2)
localparam [1:0] RM_TABLE_CLUT = 2'd0;             // colour_map wr_table code of clut
localparam [1:0] RM_TABLE_CSAT = 2'd1;             // colour_map wr_table code of csat
localparam [1:0] RM_TABLE_MIP = 2'd2;              // colour_map wr_table code of mip
// derived
localparam integer RM_TERM_STRIDE_LOG2 = 4;        // log2(TERM_STRIDE)
localparam integer RM_TERM_SLOTS_LOG2 = 4;         // log2(TERM_SLOTS)
localparam [3:0] RM_REGION_REGS = 4'h0;            // region code: ADDR_CTRL >> REGION_LSB
localparam [3:0] RM_REGION_CLUT = 4'h1;            // region code: ADDR_CLUT >> REGION_LSB
localparam [3:0] RM_REGION_CSAT = 4'h2;            // region code: ADDR_CSAT >> REGION_LSB
localparam [3:0] RM_REGION_MIP = 4'h3;             // region code: ADDR_MIP >> REGION_LSB
/* verilator lint_on UNUSEDPARAM */
