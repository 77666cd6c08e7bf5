// tex_regs: the register decoder of texture_pipeline: the parameter registers and the
// colour-table write staging, loaded through the 32-bit parameter write port.
//
// Register map: rtl/tex_regmap.vh (RM_* localparams, generated from the one table,
// model/hw/regmap.py REGMAP_TABLE; word addresses on cfg_wr_addr):
//   ADDR_CTRL          [CTRL_MODE_BIT] mode (0 mod, 1 clamp), [CTRL_FILTER_BIT] filter_en,
//                      [CTRL_NLOG2_LSB +: NL_W] n_log2
//   ADDR_Q + i         quadric coefficient i = 0..Q_COUNT-1 (A..J), s{Q_W}.{Q_FRAC}
//   ADDR_TERM + TERM_STRIDE*k + field, k < NOISE_TERMS: TERM_A a_k s{A_W}.{A_FRAC};
//                      TERM_T + 3*j + m T_k[j][m] s{T_W}.{T_FRAC}; TERM_O + j o_k[j] u{O_W}.{P_FRAC};
//                      TERM_E (T_EXP_W or A_EXP_W > 0; ignored without): te_k u{T_EXP_W} at
//                      [TERM_E_TE_LSB +: T_EXP_W], ae_k u{A_EXP_W} at [TERM_E_AE_LSB +: A_EXP_W]
//   ADDR_CLUT + n      clut[n], RGBA8 (R at [7:0]), n < 2^(N_LOG2_MAX + CLUT_LOG2)
//   ADDR_CSAT + 4n + ch  csat[n] channel ch, u{CSAT_W}: channels 0..2 go to a staging
//                      register, channel 3 commits the whole entry n (write entries in order)
//   ADDR_MIP + m       mip[m], RGBA8, m < 2^(N_LOG2_MAX + MIP_LOG2)
// Values are taken from the LSBs of cfg_wr_data (two's complement for signed fields). Writes
// to unmapped addresses, to terms k >= NOISE_TERMS and past the end of a table are ignored
// (never aliased). model/hw/regmap.py tex_regs is the Python twin (every output, every clock).
//
// Outputs (formats as above; the registers hold raw bit patterns):
//   mode, filter_en, n_log2 (NL_W = bits of N_LOG2_MAX); q_coef: coefficient i at
//   [i*Q_W +: Q_W]; a_all: term k {ae_k, a_k} at [k*AS_W +: AS_W] (AS_W = A_W + A_EXP_W);
//   t_all: term k {te_k, T_k} at [k*TS_W +: TS_W] (TS_W = 9*T_W + T_EXP_W), T_k[j][m] at
//   [k*TS_W + (3*j + m)*T_W +: T_W] (noise_term's a_in and t_in; without exponents a_k at
//   [k*A_W +: A_W], T_k[j][m] at [(9*k + 3*j + m)*T_W +: T_W]); o_all: o_k[j] at
//   [(3*k + j)*O_W +: O_W] (O_W = HASH_BITS + P_FRAC; with NOISE_TERMS = 0 the three are one
//   unused entry wide);
//   tbl_wr_*: colour_map's table write port: tbl_wr_table RM_TABLE_CLUT/CSAT/MIP, tbl_wr_addr
//   the entry, tbl_wr_data four CSAT_W-bit channel fields, channel c at [c*CSAT_W +: CSAT_W]
//   (an RGBA8 word: each byte in the low 8 bits of its field).
// Latency: a write is visible on the register outputs one clock later, and a table write on
// tbl_wr_* one clock later (tbl_wr_en high for that one clock). Throughput: one write per clock.
// Reset: synchronous, active high: every register output and the staging register 0,
// tbl_wr_en 0 (no output is X after reset).

`default_nettype none

module tex_regs #(
    // formats (config/<name>.toml keys in brackets); the widths are derived from them below
    parameter NOISE_TERMS = 8,   // [noise_terms] K: noise terms with registers, 0..TERM_SLOTS
    parameter Q_W         = 24,  // [q_w] quadric coefficients s{Q_W}.{Q_FRAC}
    parameter A_W         = 16,  // [a_w] amplitudes s{A_W}.{A_FRAC}
    parameter T_W         = 17,  // [t_w] transform entries s{T_W}.{T_FRAC}
    parameter HASH_BITS   = 8,   // [hash_bits] with P_FRAC: offsets u{HASH_BITS + P_FRAC}.{P_FRAC}
    parameter P_FRAC      = 12,  // [p_frac]
    parameter N_LOG2_MAX  = 8,   // [n_log2_max] colour tables of up to 2^N_LOG2_MAX entries
    parameter T_EXP_W     = 0,   // [t_exp_w] T_k's per-term exponent te_k (0: none, no register)
    parameter A_EXP_W     = 0    // [a_exp_w] a_k's per-term exponent ae_k (0: none, no register)
) (clk, rst, cfg_wr_en, cfg_wr_addr, cfg_wr_data, mode, filter_en, n_log2, k_used, q_coef, a_all, t_all, o_all,
   tbl_wr_en, tbl_wr_table, tbl_wr_addr, tbl_wr_data);

`include "tex_widths.vh"
`include "tex_regmap.vh"

localparam K      = NOISE_TERMS;
localparam KV     = (K > 0) ? K : 1;                  // K = 0 still declares (unused) vectors
localparam O_W    = HASH_BITS + P_FRAC;               // noise offset word
localparam TS_W   = 9*T_W + T_EXP_W;                  // one term of t_all: {te, T}
localparam AS_W   = A_W + A_EXP_W;                    // one term of a_all: {ae, a}
localparam TE_W   = (T_EXP_W > 0) ? T_EXP_W : 1;      // the exponent registers (one unused bit when none)
localparam AE_W   = (A_EXP_W > 0) ? A_EXP_W : 1;
localparam CSAT_W = tw_csat_w(N_LOG2_MAX);            // summed-area channel
localparam NL_W   = tw_bits_unsigned(N_LOG2_MAX);     // n_log2
localparam KU_W   = tw_bits_unsigned(NOISE_TERMS);    // k_used, 0..K
localparam NLMAX  = N_LOG2_MAX;
localparam AW     = RM_ADDR_W;
localparam RL     = RM_REGION_LSB;                    // offset bits within a region
localparam TSL    = RM_TERM_STRIDE_LOG2;              // term field bits
localparam TNL    = RM_TERM_SLOTS_LOG2;               // term select bits
localparam CHL    = RM_CSAT_LOG2;                     // csat channel bits
localparam NCH    = RM_CSAT_CHANNELS;
// the table's constants at the widths they are compared at
localparam [RL-1:0]  OFF_CTRL = RM_ADDR_CTRL[RL-1:0];
localparam [RL-1:0]  OFF_Q    = RM_ADDR_Q[RL-1:0];
localparam [TSL-1:0] FLD_A    = RM_TERM_A[TSL-1:0];
localparam [TSL-1:0] FLD_T    = RM_TERM_T[TSL-1:0];
localparam [TSL-1:0] FLD_O    = RM_TERM_O[TSL-1:0];
localparam [TSL-1:0] FLD_E    = RM_TERM_E[TSL-1:0];
localparam [CHL-1:0] CH_LAST  = NCH[CHL-1:0] - 1'b1;  // the channel that commits an entry

input  wire                     clk;
input  wire                     rst;
// parameter write port
input  wire                     cfg_wr_en;
input  wire [AW-1:0]            cfg_wr_addr;
input  wire [RM_DATA_W-1:0]     cfg_wr_data;
// parameter registers
output reg                      mode;
output reg                      filter_en;
output reg  [NL_W-1:0]          n_log2;
output reg  [KU_W-1:0]          k_used;
output reg  [RM_Q_COUNT*Q_W-1:0] q_coef;
output wire [KV*AS_W-1:0]       a_all;
output wire [KV*TS_W-1:0]       t_all;
output reg  [KV*3*O_W-1:0]      o_all;
// colour-table write port (to colour_map)
output reg                      tbl_wr_en;
output reg  [1:0]               tbl_wr_table;
output reg  [NLMAX:0]           tbl_wr_addr;
output reg  [4*CSAT_W-1:0]      tbl_wr_data;

// address fields
wire [AW-RL-1:0] wr_region  = cfg_wr_addr[AW-1:RL];
wire [RL-1:0]    wr_off     = cfg_wr_addr[RL-1:0];
wire             wr_regs    = cfg_wr_en && wr_region == RM_REGION_REGS;
// the term window is aligned (the table checks it): term and field are bit slices
/* verilator lint_off UNUSEDSIGNAL */  // the low bits of the window base are 0
wire [RL-1:0]    term_base  = RM_ADDR_TERM[RL-1:0];
/* verilator lint_on UNUSEDSIGNAL */
wire             term_space = wr_off[RL-1:TSL+TNL] == term_base[RL-1:TSL+TNL];
wire [TNL-1:0]   term_sel   = wr_off[TSL +: TNL];
wire [TSL-1:0]   term_field = wr_off[0 +: TSL];
integer          pi, pj;

// the mantissa registers, and the exponents' (written only with T_EXP_W, A_EXP_W > 0; else
// constant 0 and not read)
reg  [KV*A_W-1:0]   a_reg;
reg  [KV*9*T_W-1:0] t_reg;
/* verilator lint_off UNUSEDSIGNAL */
reg  [KV*TE_W-1:0]  te_reg;
reg  [KV*AE_W-1:0]  ae_reg;
/* verilator lint_on UNUSEDSIGNAL */

// One process loads every parameter register (one wake-up a clock for an event-driven
// simulator, whatever K is); the loops unroll into one write enable per register.
always @(posedge clk) begin
    if (rst) begin
        mode      <= 1'b0;
        filter_en <= 1'b0;
        n_log2    <= {NL_W{1'b0}};
        k_used    <= {KU_W{1'b0}};
        q_coef    <= {RM_Q_COUNT*Q_W{1'b0}};
        a_reg     <= {KV*A_W{1'b0}};
        t_reg     <= {KV*9*T_W{1'b0}};
        te_reg    <= {KV*TE_W{1'b0}};
        ae_reg    <= {KV*AE_W{1'b0}};
        o_all     <= {KV*3*O_W{1'b0}};
    end else if (wr_regs) begin
        if (wr_off == OFF_CTRL) begin
            mode      <= cfg_wr_data[RM_CTRL_MODE_BIT];
            filter_en <= cfg_wr_data[RM_CTRL_FILTER_BIT];
            n_log2    <= cfg_wr_data[RM_CTRL_NLOG2_LSB +: NL_W];
            k_used    <= cfg_wr_data[RM_CTRL_KUSED_LSB +: KU_W];
        end
        for (pi = 0; pi < RM_Q_COUNT; pi = pi + 1) begin
            if (wr_off == OFF_Q + pi[RL-1:0])
                q_coef[pi*Q_W +: Q_W] <= cfg_wr_data[Q_W-1:0];
        end
        for (pi = 0; pi < K; pi = pi + 1) begin
            if (term_space && term_sel == pi[TNL-1:0]) begin
                if (term_field == FLD_A)
                    a_reg[pi*A_W +: A_W] <= cfg_wr_data[A_W-1:0];
                for (pj = 0; pj < 9; pj = pj + 1) begin
                    if (term_field == FLD_T + pj[TSL-1:0])
                        t_reg[(9*pi + pj)*T_W +: T_W] <= cfg_wr_data[T_W-1:0];
                end
                if (T_EXP_W > 0 && term_field == FLD_E)
                    te_reg[pi*TE_W +: TE_W] <= cfg_wr_data[RM_TERM_E_TE_LSB +: TE_W];
                if (A_EXP_W > 0 && term_field == FLD_E)
                    ae_reg[pi*AE_W +: AE_W] <= cfg_wr_data[RM_TERM_E_AE_LSB +: AE_W];
                for (pj = 0; pj < 3; pj = pj + 1) begin
                    if (term_field == FLD_O + pj[TSL-1:0])
                        o_all[(3*pi + pj)*O_W +: O_W] <= cfg_wr_data[O_W-1:0];
                end
            end
        end
    end
end

// the terms as noise_term takes them: {ae, a} and {te, T} (without exponents the registers),
// each joined by one function in one assign (per-term assigns would drive a_all piecewise);
// the functions' words hold the exponent registers (AE_W, TE_W: AS_W, TS_W when there are exponents)
localparam ASX_W = A_W + AE_W;
localparam TSX_W = 9*T_W + TE_W;
function [KV*ASX_W-1:0] join_a;
    input [KV*AE_W-1:0] e;
    input [KV*A_W-1:0]  m;
    integer k;
    begin
        for (k = 0; k < KV; k = k + 1)
            join_a[k*ASX_W +: ASX_W] = {e[k*AE_W +: AE_W], m[k*A_W +: A_W]};
    end
endfunction

function [KV*TSX_W-1:0] join_t;
    input [KV*TE_W-1:0]  e;
    input [KV*9*T_W-1:0] m;
    integer k;
    begin
        for (k = 0; k < KV; k = k + 1)
            join_t[k*TSX_W +: TSX_W] = {e[k*TE_W +: TE_W], m[k*9*T_W +: 9*T_W]};
    end
endfunction

generate
    if (A_EXP_W > 0) begin : g_ae
        assign a_all = join_a(ae_reg, a_reg);
    end else begin : g_a
        assign a_all = a_reg;
    end
    if (T_EXP_W > 0) begin : g_te
        assign t_all = join_t(te_reg, t_reg);
    end else begin : g_t
        assign t_all = t_reg;
    end
endgenerate

// colour tables: forwarded to colour_map one clock later; csat entries are staged
reg [(NCH-1)*CSAT_W-1:0] csat_stage_reg;

wire [CHL-1:0] csat_ch = wr_off[CHL-1:0];
// table index in range: clut n < 2^(NLMAX + CLUT_LOG2), csat 4n + ch < 2^(NLMAX + CSAT_LOG2),
// mip m < 2^(NLMAX + MIP_LOG2) (a write past the end of a table is ignored, never aliased)
wire clut_in_range = (wr_off >> (NLMAX + RM_CLUT_LOG2)) == {RL{1'b0}};
wire csat_in_range = (wr_off >> (NLMAX + RM_CSAT_LOG2)) == {RL{1'b0}};
wire mip_in_range  = (wr_off >> (NLMAX + RM_MIP_LOG2)) == {RL{1'b0}};

// an RGBA8 word spread over the four CSAT_W channel fields of the table write data
reg [4*CSAT_W-1:0] rgba_wide;
integer            ri;
always @* begin
    rgba_wide = {4*CSAT_W{1'b0}};
    for (ri = 0; ri < 4; ri = ri + 1)
        rgba_wide[ri*CSAT_W +: 8] = cfg_wr_data[ri*8 +: 8];
end

always @(posedge clk) begin
    if (rst) begin
        csat_stage_reg <= {(NCH-1)*CSAT_W{1'b0}};
        tbl_wr_en      <= 1'b0;
        tbl_wr_table   <= RM_TABLE_CLUT;
        tbl_wr_addr    <= {(NLMAX+1){1'b0}};
        tbl_wr_data    <= {4*CSAT_W{1'b0}};
    end else begin
        tbl_wr_en <= 1'b0;
        if (cfg_wr_en) begin
            case (wr_region)
                RM_REGION_CLUT: begin
                    tbl_wr_en    <= clut_in_range;
                    tbl_wr_table <= RM_TABLE_CLUT;
                    tbl_wr_addr  <= wr_off[NLMAX:0];
                    tbl_wr_data  <= rgba_wide;
                end
                RM_REGION_CSAT: begin
                    if (csat_ch == CH_LAST) begin
                        tbl_wr_en    <= csat_in_range;
                        tbl_wr_table <= RM_TABLE_CSAT;
                        tbl_wr_addr  <= wr_off[NLMAX+CHL:CHL];
                        tbl_wr_data  <= {cfg_wr_data[CSAT_W-1:0], csat_stage_reg};
                    end else begin
                        csat_stage_reg[csat_ch*CSAT_W +: CSAT_W] <= cfg_wr_data[CSAT_W-1:0];
                    end
                end
                RM_REGION_MIP: begin
                    tbl_wr_en    <= mip_in_range;
                    tbl_wr_table <= RM_TABLE_MIP;
                    tbl_wr_addr  <= wr_off[NLMAX:0];
                    tbl_wr_data  <= rgba_wide;
                end
                default: ;
            endcase
        end
    end
end

`ifdef FORMAL
// ---------------------------------------------------------------------------
// Formal properties (make formal). Written from the register map's addresses (absolute word
// addresses, not the decoder's bit slices): a register changes only on a write to its own
// address, and then to the written value (so a register write never changes another
// register); a table write reaches the table port one clock later with the table, the entry
// (the address minus the table's base) and the data it addressed, and nothing else does
// (tbl_wr_en only then: writes past a table's end and to other addresses never reach it).
integer              fa, fb;
reg                  f_past_valid = 1'b0;
reg                  f_rst, f_en;          // the last clock's reset and write
reg [AW-1:0]         f_addr;
reg [RM_DATA_W-1:0]  f_data;
reg [3*CSAT_W-1:0]   f_csat;              // the last value written to each staged csat channel c < 3
wire [AW-1:0]        f_coff = cfg_wr_addr - RM_ADDR_CSAT;   // a csat write's word offset
localparam           F_CH = $clog2(NCH);   // NCH words an entry (a power of two: the checks below)
always @(posedge clk) begin
    f_past_valid <= 1'b1;
    f_rst        <= rst;
    f_en         <= cfg_wr_en;
    f_addr       <= cfg_wr_addr;
    f_data       <= cfg_wr_data;
end
always @(posedge clk) begin
    if (rst)
        f_csat <= {3*CSAT_W{1'b0}};
    else if (cfg_wr_en && cfg_wr_addr >= RM_ADDR_CSAT && f_coff < (1 << RL))
        for (fa = 0; fa < NCH - 1; fa = fa + 1)
            if (f_coff[F_CH-1:0] == fa) f_csat[fa*CSAT_W +: CSAT_W] <= cfg_wr_data[CSAT_W-1:0];
end

// the previous value of every register output
reg                      f_mode, f_filter_en;
reg [NL_W-1:0]           f_n_log2;
reg [KU_W-1:0]           f_k_used;
reg [RM_Q_COUNT*Q_W-1:0] f_q;
reg [KV*AS_W-1:0]        f_a;
reg [KV*TS_W-1:0]        f_t;
reg [KV*3*O_W-1:0]       f_o;
always @(posedge clk) begin
    {f_mode, f_filter_en, f_n_log2, f_k_used} <= {mode, filter_en, n_log2, k_used};
    {f_q, f_a, f_t, f_o} <= {q_coef, a_all, t_all, o_all};
end

wire f_wr = f_past_valid && !f_rst && f_en;   // a write landed at this clock's edge
always @* begin
    if (!f_past_valid) assume(rst);  // the first clock is a reset
    // the staging register holds the channels written last (an invariant for the induction)
    if (f_past_valid) assert(csat_stage_reg == f_csat);
    if (f_past_valid && f_rst) begin
        assert({mode, filter_en, n_log2, k_used} == 0 && q_coef == 0 && a_all == 0 && t_all == 0 && o_all == 0);
        assert(!tbl_wr_en);
    end
    if (f_past_valid && !f_rst) begin
        // CTRL
        if (f_wr && f_addr == RM_ADDR_CTRL)
            assert(mode == f_data[RM_CTRL_MODE_BIT] && filter_en == f_data[RM_CTRL_FILTER_BIT]
                   && n_log2 == f_data[RM_CTRL_NLOG2_LSB +: NL_W] && k_used == f_data[RM_CTRL_KUSED_LSB +: KU_W]);
        else
            assert(mode == f_mode && filter_en == f_filter_en && n_log2 == f_n_log2 && k_used == f_k_used);
        // quadric coefficient i at ADDR_Q + i
        for (fa = 0; fa < RM_Q_COUNT; fa = fa + 1)
            if (f_wr && f_addr == RM_ADDR_Q + fa)
                assert(q_coef[fa*Q_W +: Q_W] == f_data[Q_W-1:0]);
            else
                assert(q_coef[fa*Q_W +: Q_W] == f_q[fa*Q_W +: Q_W]);
        // term k's fields at ADDR_TERM + TERM_STRIDE k + field
        for (fa = 0; fa < K; fa = fa + 1) begin
            if (f_wr && f_addr == RM_ADDR_TERM + RM_TERM_STRIDE*fa + RM_TERM_A)
                assert(a_all[fa*AS_W +: A_W] == f_data[A_W-1:0]);
            else
                assert(a_all[fa*AS_W +: A_W] == f_a[fa*AS_W +: A_W]);
            for (fb = 0; fb < 9; fb = fb + 1)
                if (f_wr && f_addr == RM_ADDR_TERM + RM_TERM_STRIDE*fa + RM_TERM_T + fb)
                    assert(t_all[fa*TS_W + fb*T_W +: T_W] == f_data[T_W-1:0]);
                else
                    assert(t_all[fa*TS_W + fb*T_W +: T_W] == f_t[fa*TS_W + fb*T_W +: T_W]);
            for (fb = 0; fb < 3; fb = fb + 1)
                if (f_wr && f_addr == RM_ADDR_TERM + RM_TERM_STRIDE*fa + RM_TERM_O + fb)
                    assert(o_all[(3*fa + fb)*O_W +: O_W] == f_data[O_W-1:0]);
                else
                    assert(o_all[(3*fa + fb)*O_W +: O_W] == f_o[(3*fa + fb)*O_W +: O_W]);
        end
        // the table port: clut entry n at ADDR_CLUT + n, mip entry m at ADDR_MIP + m (RGBA8
        // spread over the channel fields), csat entry n channel 3 at ADDR_CSAT + 4n + 3 (with
        // the staged channels 0..2)
        if (f_wr && f_addr >= RM_ADDR_CLUT && f_addr - RM_ADDR_CLUT < (1 << (NLMAX + RM_CLUT_LOG2))) begin
            assert(tbl_wr_en && tbl_wr_table == RM_TABLE_CLUT && tbl_wr_addr == f_addr - RM_ADDR_CLUT);
            for (fa = 0; fa < 4; fa = fa + 1)
                assert(tbl_wr_data[fa*CSAT_W +: CSAT_W] == f_data[fa*8 +: 8]);
        end else if (f_wr && f_addr >= RM_ADDR_MIP && f_addr - RM_ADDR_MIP < (1 << (NLMAX + RM_MIP_LOG2))) begin
            assert(tbl_wr_en && tbl_wr_table == RM_TABLE_MIP && tbl_wr_addr == f_addr - RM_ADDR_MIP);
            for (fa = 0; fa < 4; fa = fa + 1)
                assert(tbl_wr_data[fa*CSAT_W +: CSAT_W] == f_data[fa*8 +: 8]);
        end else if (f_wr && f_addr >= RM_ADDR_CSAT && f_addr - RM_ADDR_CSAT < (1 << (NLMAX + RM_CSAT_LOG2))
                     && ((f_addr - RM_ADDR_CSAT) & (NCH - 1)) == NCH - 1) begin
            assert(tbl_wr_en && tbl_wr_table == RM_TABLE_CSAT && tbl_wr_addr == (f_addr - RM_ADDR_CSAT) >> F_CH);
            assert(tbl_wr_data == {f_data[CSAT_W-1:0], f_csat});
        end else
            assert(!tbl_wr_en);
    end
end
// the exponents (T_EXP_W, A_EXP_W > 0): term k's at ADDR_TERM + TERM_STRIDE k + TERM_E (te_reg and
// ae_reg, which the generate above places above each term's mantissas in t_all and a_all;
// without exponents never written: 0 after reset)
integer              fe;
reg [KV*TE_W-1:0]    f_te;
reg [KV*AE_W-1:0]    f_ae;
always @(posedge clk) {f_te, f_ae} <= {te_reg, ae_reg};
always @* begin
    if (f_past_valid && f_rst)
        assert(te_reg == 0 && ae_reg == 0);
    if (f_past_valid && !f_rst)
        for (fe = 0; fe < K; fe = fe + 1)
            if (f_wr && f_addr == RM_ADDR_TERM + RM_TERM_STRIDE*fe + RM_TERM_E && T_EXP_W + A_EXP_W > 0)
                assert((T_EXP_W == 0 || te_reg[fe*TE_W +: TE_W] == f_data[RM_TERM_E_TE_LSB +: TE_W])
                       && (A_EXP_W == 0 || ae_reg[fe*AE_W +: AE_W] == f_data[RM_TERM_E_AE_LSB +: AE_W]));
            else
                assert(te_reg[fe*TE_W +: TE_W] == f_te[fe*TE_W +: TE_W] && ae_reg[fe*AE_W +: AE_W] == f_ae[fe*AE_W +: AE_W]);
end
`endif

// elaboration checks: the table's shape this decoder assumes
generate
    if (NCH != 4 || K > RM_TERM_SLOTS || NLMAX + RM_CSAT_LOG2 >= RL
        || RM_TERM_E_TE_LSB + T_EXP_W > RM_DATA_W || RM_TERM_E_AE_LSB + A_EXP_W > RM_DATA_W) begin : g_bad_params
        // a module that does not exist: elaboration fails with this instance name
        tex_regs_bad_parameters u_bad ();
    end
endgenerate

endmodule

`default_nettype wire
