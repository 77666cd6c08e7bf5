// texture_pipeline: the pixel pipeline of the texture unit (the RTL top).
//
// For every pixel (s, Jm, je) it computes, bit-exact with model/hw/golden.py
// texture_pipeline / texture_stages,
//
//   f = q(s) + sum_i a_i n(T_i s + o_i)                 (quadric_mac + K x noise_term)
//   c = dq/ds + sum_i a_i (dn_i/dp) T_i                  (the texture-space gradient of f)
//   w = |c^T J| N                                        (filter_width, J = Jm 2^je)
//   rgba = colour_map(f, w)                              (SAT box filter / MIP / point)
// With the filter "sat_fc" (FILTER 3, docs/filters.md) each term is faded by its frequency
// clamp alpha_i (fc_weight, from the pixel's footprint; fc_scale) before the sums, f = q +
// sum_i alpha_i a_i n_i and c likewise, and w = max(|c^T J| N, wv), wv the faded terms' spread.
// With "sat2" (FILTER 4, the trapezoid) w is the pair {b, a} = {|c^T J_y|, |c^T J_x|} N
// (filter_width COMPONENTS) and colour_map averages over the trapezoid they span (cmap_sat2).
// "sat2_fc" (FILTER 5) is the two together: sat_fc's fades and sat2's colour map, the larger
// of {b, a} widened to max(., wv) (cm_align). The filter key is one parameter; inside, the
// frequency clamp (FC_ON) and the colour-map family (CM_FILTER) are chosen apart.
//
// Formats (every width derived from the parameters below, rtl/tex_widths.vh):
//   s      s{S_W}.{S_FRAC}, three of them {r, t, s} (s at the LSBs)
//   Jm     s{J_W}.0, six of them, Jm[k][col] at element 2*k+col; je s{JE_W}.0 (J = Jm 2^je)
//   f      s{F_W}.{F_FRAC}: q (QF_W bits) and the K a_i n_i (AN_W bits) sign-extended to
//          F_W and summed exactly (F_W is their worst-case bound, docs/numerics.md)
//   c      3 x s{C_W}.{C_FRAC}: dq/ds (C_W) plus the K a_i grad n_i (AG_W), summed exactly
//   w      u{W_W}.{F_FRAC} colour-table entries; rgba RGBA8, R at [7:0], A at [31:24]
//
// Pixel input word, s_axis_tdata[PIX_W-1:0] (PIX_W = 3*S_W + 6*J_W + JE_W; model/hw/regmap.py
// pack_pixels is its Python twin):
//   [3*S_W-1 : 0]                     s  = {r, t, s}      (element e at [e*S_W +: S_W])
//   [3*S_W+6*J_W-1 : 3*S_W]           jm = Jm[k][col] at element 2*k+col (J_W bits each)
//   [PIX_W-1 : 3*S_W+6*J_W]           je
//
// Register map (cfg_wr_addr is a 32-bit-word address): decoded by tex_regs (rtl/tex_regs.v
// documents it) from rtl/tex_regmap.vh, generated from model/hw/regmap.py REGMAP_TABLE (its
// write_sequence is what a host writes). After rst every parameter register is 0 (the tables
// are not reset). Write the parameters while no pixel is in flight; they are held during a pass.
//
// Pipeline: the pixel at the front (the input, or the one noise_fold issues when the terms
// are folded onto fewer units), then texture_sum (f and grad f: quadric_mac and the K
// noise_terms in parallel on s, with sat_fc fc_weight's fades, summed in registered adder
// trees, sum_tree, of arity 4: TREE_LEVELS = ceil(log4(K+1)) stages), filter_width on grad f
// (with the noise gradient after the trees, without it on the quadric's gradient, in
// parallel with the terms), then colour_map. f (in fewer bits) or w waits for the other
// before colour_map (cm_align); Jm, je and tlast travel in delay lines (delay_line) beside
// the data. Every register of the datapath shares one clock enable
//   ce = rst | !out_valid | skid_ready
// (the colour_map output, or with SAMPLES > 1 sample_average's, is the last pipeline stage; it
// may advance whenever it is empty or the output skid buffer can take it). The output skid buffer (axis_skid: two registers, the
// pattern of alexforencich/verilog-axis axis_register, REG_TYPE = 2) has a registered input ready, so
// no combinational path runs from m_axis_tready to s_axis_tready or ce, and a stall on
// m_axis_tready never loses, duplicates or reorders a pixel. s_axis_tready = ce (& !rst)
// and the front's ready: a pixel enters whenever the pipeline advances and the front can take it.
//
// Latency: LATENCY = T_CM + LAT_CM enabled clocks from s_axis to the colour_map output (LAT_CM:
// `LAT_COLOUR_MAP, with FPGA_REGS _FPGA, with CMAP_CLOCKS = 4 _SERIAL: rtl/tex_latency.vh `LAT_CM),
// T_CM = max(T_F, T_WD) = max(LAT_FRONT + TREE_LEVELS, DLY_J + LAT_FILTER_WIDTH) (below; sat_fc:
// LAT_FC_SCALE more in the terms and LAT_FC_WMAX after filter_width), plus one clock in the
// skid buffer; with SAMPLES > 1, from the pixel's last sample, plus LAT_SAMPLE_AVERAGE.
// Throughput: one pixel per SAMPLES x ceil(k_used / NOISE_UNITS) clocks (at least QUADRIC_CLOCKS and
// CMAP_CLOCKS a sample; one pixel a clock unfolded at SAMPLES = 1) while m_axis_tready is held high.
// SAMPLES > 1 (sample_expand, sample_average): the pixel's SAMPLES sub-pixel samples enter one
// after the other (s_axis_tready with the last), each filtered with the footprint of its cell of the
// pixel (2: the halves across y, J's y column halved; 4: the quarters, J / 2),
// and their colours are averaged (docs/filters.md "Sub-pixel samples").
// Reset: synchronous, active high; clears every valid bit, the output registers, the
// parameter registers and the staging register (no output is X after reset).

`default_nettype none

`include "tex_latency.vh"

// Every parameter is one key of a configuration file (config/<name>.toml, in brackets);
// a configuration sets all of them (hdlbuild writes build/gen/<name>/texture_unit.v, a
// wrapper with the configuration's values). Every word width is derived from them here and
// in the blocks (rtl/tex_widths.vh, the twin of model/hw/config.py; tb/test_widths.py
// checks that the two agree). The defaults are placeholders of a valid configuration.
module texture_pipeline #(
    parameter QUADRIC        = 0,   // [quadric] 0 full (10 coefficients), 1 diagonal (B = C = F = 0)
    parameter NOISE_TERMS    = 8,   // [noise_terms] K: noise terms a_i n(T_i s + o_i), 0..8
    parameter NOISE_UNITS    = 8,   // [noise_units] U: noise units, 1..K; U < K: the terms on U units, U a
                                    // clock (noise_fold), ceil(K_used / U) clocks a pixel
    parameter QUADRIC_CLOCKS = 1,   // [quadric_clocks] 2: the quadric MAC on half its multipliers, two
                                    // clocks a pixel; 6: on one multiplier, six clocks a pixel (diagonal
                                    // quadric, folded terms)
    parameter BLEND          = 1,   // [blend] 0 linear, 1 cubic
    parameter TRANSFORM      = 0,   // [transform] 0 affine, 1 pow2
    parameter AMPLITUDE      = 0,   // [amplitude] 0 any, 1 pow2
    parameter FILTER         = 1,   // [filter] 0 none (point lookup), 1 sat, 2 mip, 3 sat_fc (sat with
                                    // frequency clamping: fc_weight, fc_scale; unfolded terms only),
                                    // 4 sat2 (the trapezoid: filter_width's two components, cmap_sat2),
                                    // 5 sat2_fc (sat2 with sat_fc's frequency clamping)
    parameter NOISE_GRADIENT = 1,   // [noise_gradient] 1: grad f includes the noise terms'
    parameter FPGA_REGS      = 0,   // [fpga_regs] 1: the blocks' extra register stages for an FPGA
                                    // (rtl/tex_latency.vh `LAT_*_FPGA; docs/fpga.md)
    parameter SAMPLES        = 1,   // [samples] sub-pixel samples a pixel, 1, 2 or 4 (sample_expand,
                                    // sample_average): SAMPLES x the clocks of one sample a pixel
    parameter CMAP_CLOCKS    = 1,   // [cmap_clocks] 4: colour_map's box filter a channel a clock, four
                                    // clocks a sample (filter sat, folded terms, no FPGA_REGS)
    parameter S_W            = 24,  // [s_w] texture coordinates s{S_W}.{S_FRAC}
    parameter S_FRAC         = 16,  // [s_frac]
    parameter Q_W            = 24,  // [q_w] quadric coefficients s{Q_W}.{Q_FRAC}
    parameter Q_FRAC         = 16,  // [q_frac]
    parameter J_W            = 12,  // [j_w] Jacobian mantissas s{J_W}.0
    parameter JE_W           = 8,   // [je_w] shared Jacobian exponent s{JE_W}.0
    parameter T_W            = 17,  // [t_w] transform entries s{T_W}.{T_FRAC}
    parameter T_FRAC         = 10,  // [t_frac]
    parameter A_W            = 16,  // [a_w] amplitudes s{A_W}.{A_FRAC}
    parameter A_FRAC         = 12,  // [a_frac]
    parameter P_FRAC         = 12,  // [p_frac] noise-space fraction bits
    parameter HASH_BITS      = 8,   // [hash_bits] lattice period 2^HASH_BITS
    parameter N_FRAC         = 12,  // [n_frac] noise value / gradient fraction bits
    parameter F_FRAC         = 16,  // [f_frac] f fraction bits (1.0 = the whole table)
    parameter C_FRAC         = 12,  // [c_frac] grad f fraction bits
    parameter NORM_BITS      = 12,  // [norm_bits] |grad f| normalised to this many bits
    parameter W_CAP_LOG2     = 16,  // [w_cap_log2] w saturates at 2^W_CAP_LOG2 entries
    parameter DIV_BITS       = 0,   // [div_bits] box-filter division: 0 exact, B > 0 on B-bit w
    parameter N_LOG2_MAX     = 8,   // [n_log2_max] colour tables of up to 2^N_LOG2_MAX entries
    parameter FC_LOG_FRAC    = 5,   // [fc_log_frac] sat_fc: log2 of the footprint in 2^-FC_LOG_FRAC octaves
    parameter FC_KNEE        = 112, // [fc_knee] sat_fc: a term is gone at footprint 2^(FC_KNEE 2^-FC_LOG_FRAC)
    parameter FC_FADE_LOG2   = 2,   // [fc_fade_log2] sat_fc: the fade spans 2^FC_FADE_LOG2 octaves
    parameter FC_KS          = 328, // sat_fc: sigma sqrt(12) of the lattice noise in u.FC_KSF (derived from
    parameter FC_KSF         = 8,   // [blend] by model/hw/config.py fc_sigma12; hdlbuild sets both)
    parameter T_EXP_W        = 0,   // [t_exp_w] T_i = T mantissas 2^(te_i - T_FRAC), te_i u{T_EXP_W} per
                                    // term (block floating point, docs/numerics.md; 0: none; affine only)
    parameter A_EXP_W        = 0,   // [a_exp_w] a_i = a mantissa 2^(ae_i - A_FRAC), ae_i u{A_EXP_W} per
                                    // term (0: none; amplitude any only)
    // [hash.seed] the lattice permutation (model/hw/config.py permutation()), entry i at
    // [i*HASH_BITS +: HASH_BITS]
    parameter [HASH_BITS*(1<<HASH_BITS)-1:0] PERM = {HASH_BITS*(1<<HASH_BITS){1'b0}}
) (clk, rst, cfg_wr_en, cfg_wr_addr, cfg_wr_data, s_axis_tdata, s_axis_tvalid, s_axis_tready, s_axis_tlast,
   m_axis_tdata, m_axis_tvalid, m_axis_tready, m_axis_tlast);

`include "tex_widths.vh"
`include "tex_regmap.vh"  // RM_ADDR_W, RM_DATA_W: the write port (the decoder is tex_regs)

// ---------------------------------------------------------------------------
// Derived widths (the same functions as the blocks': each block derives its own internal
// widths, the top derives the words that cross between blocks)

localparam K      = NOISE_TERMS;
localparam U      = NOISE_UNITS;
localparam FOLD   = (K > 0) && (U < K);                                        // terms on U units
localparam NLEAF  = FOLD ? 1 : K;                                              // noise leaves of the tree
localparam KU_W   = tw_bits_unsigned(K);                                       // k_used, 0..K
localparam DIAG   = QUADRIC;
localparam CUBIC  = BLEND;
localparam POW2T  = TRANSFORM;
localparam O_W    = HASH_BITS + P_FRAC;                                        // noise offset word
localparam TE_MAX = (1 << T_EXP_W) - 1;                                        // the largest exponents
localparam AE_MAX = (1 << A_EXP_W) - 1;
localparam TS_W   = 9*T_W + T_EXP_W;                                           // a term's {te, T}
localparam AS_W   = A_W + A_EXP_W;                                             // a term's {ae, a}
localparam F_W    = tw_f_w_e(DIAG, S_W, S_FRAC, Q_W, Q_FRAC, F_FRAC, K, A_W, A_FRAC, N_FRAC, AE_MAX); // f (exact sum)
localparam C_W    = tw_c_w_e(DIAG, S_W, S_FRAC, Q_W, Q_FRAC, C_FRAC, K, NOISE_GRADIENT, CUBIC, POW2T, T_W,
                             T_FRAC, N_FRAC, A_W, A_FRAC, TE_MAX, AE_MAX);     // grad f (exact sum)
localparam W_W    = W_CAP_LOG2 + F_FRAC + 1;                                   // filter width
localparam CSAT_W = tw_csat_w(N_LOG2_MAX);                                     // summed-area channel
localparam NL_W   = tw_bits_unsigned(N_LOG2_MAX);                              // n_log2
localparam NLMAX  = N_LOG2_MAX;
localparam PIX_W  = 3*S_W + 6*J_W + JE_W;                                      // pixel input word
localparam FC_ON  = (FILTER == 3) || (FILTER == 5);                          // sat_fc, sat2_fc: the clamp
localparam SAT2   = (FILTER == 4) || (FILTER == 5);                          // sat2, sat2_fc: the trapezoid
localparam MIN_CLK = (CMAP_CLOCKS > QUADRIC_CLOCKS) ? CMAP_CLOCKS : QUADRIC_CLOCKS;  // noise_fold's least clocks a sample
localparam FCL    = FC_ON && (K > 0) && !FOLD;                                 // frequency clamping
localparam CM_FILTER = SAT2 ? 3 : (FILTER == 3) ? 1 : FILTER;                // colour_map: the box, sat2 its own
localparam NW     = SAT2 ? 2 : 1;                                              // sat2: w = {b, a}

input  wire             clk;
input  wire             rst;

// parameter write port (32-bit words, register map above)
input  wire             cfg_wr_en;
input  wire [RM_ADDR_W-1:0] cfg_wr_addr;
input  wire [RM_DATA_W-1:0] cfg_wr_data;

// pixel input stream: {je, jm, s}
input  wire [PIX_W-1:0] s_axis_tdata;
input  wire             s_axis_tvalid;
output wire             s_axis_tready;
input  wire             s_axis_tlast;

// colour output stream: RGBA8, R at [7:0]
output wire [31:0]      m_axis_tdata;
output wire             m_axis_tvalid;
input  wire             m_axis_tready;
output wire             m_axis_tlast;

// ---------------------------------------------------------------------------
// Latencies and alignment

// each block's latency under FPGA_REGS (the block picks the same value from the same parameter)
localparam LAT_QM      = `LAT_QM(FPGA_REGS, QUADRIC, QUADRIC_CLOCKS);   // quadric_mac's (rtl/tex_latency.vh)
localparam LAT_NT      = FPGA_REGS ? `LAT_NOISE_TERM_FPGA   : `LAT_NOISE_TERM;
localparam LAT_FW      = FPGA_REGS ? `LAT_FILTER_WIDTH_FPGA : `LAT_FILTER_WIDTH;
localparam LAT_CM      = `LAT_CM(FPGA_REGS, CMAP_CLOCKS);             // colour_map's (rtl/tex_latency.vh)
localparam LAT_FCW     = `LAT_FC_WEIGHT;
localparam LAT_FCS     = FCL ? `LAT_FC_SCALE : 0;                        // sat_fc: fc_scale after each term
localparam LAT_NF      = FPGA_REGS ? `LAT_NOISE_FOLD_FPGA   : `LAT_NOISE_FOLD;
localparam LAT_NS      = FOLD ? LAT_NT + LAT_NF : LAT_NT + LAT_FCS;      // noise leaves (noise_fold: + LAT_NF)
localparam LAT_FRONT   = (K > 0 && LAT_NS > LAT_QM) ? LAT_NS : LAT_QM;  // q and the terms meet here
localparam TREE_LEVELS = tw_tree_levels(NLEAF + 1, `SUM_TREE_ARITY);     // adder tree (sum_tree) stages
localparam T_F         = LAT_FRONT + TREE_LEVELS;                        // f (and c) out of the tree
// With the noise gradient (NG) grad f comes out of the tree with f and filter_width follows
// the tree; without it grad f = grad q, and filter_width takes it from the quadric at once.
localparam NG          = NOISE_GRADIENT;
localparam DLY_J       = NG ? T_F : LAT_QM;                              // Jm, je to filter_width
localparam T_FW        = DLY_J + LAT_FW;                                 // w out of filter_width
localparam T_WD        = T_FW + (FCL ? `LAT_FC_WMAX : 0);                // sat_fc: then max(w, wv) (cm_align)
localparam T_CM        = (T_WD > T_F) ? T_WD : T_F;                       // colour_map input
// total latency to the colour_map output (the skid buffer adds one more clock); for readers
// and waveform viewers only, nothing below needs it
/* verilator lint_off UNUSEDPARAM */
localparam LATENCY     = T_CM + LAT_CM + ((SAMPLES > 1) ? `LAT_SAMPLE_AVERAGE : 0);
/* verilator lint_on UNUSEDPARAM */

localparam JM_W = 6*J_W;

// ---------------------------------------------------------------------------
// Flow control

wire cm_valid;          // colour_map output holds a sample's colour
wire out_valid;         // the last pipeline stage (colour_map, or SAMPLES > 1 sample_average) holds a pixel
wire skid_ready;        // the output skid buffer can take a pixel this clock (a register)
wire advance = !out_valid || skid_ready;
wire ce      = rst || advance;  // rst: every block's reset sees an enabled clock

wire fold_ready;         // the front can take a sample (always, unless the terms are folded)
wire smp_ready;          // the pixel's last sample is taken (SAMPLES = 1: fold_ready)
assign s_axis_tready = advance && !rst && smp_ready;
wire pix_valid = s_axis_tvalid && !rst;

// ---------------------------------------------------------------------------
// Parameter registers and colour-table write staging (tex_regs: the register map, decoded
// from rtl/tex_regmap.vh; written while no pixel is in flight)

wire                mode_reg;
wire                filter_en_reg;
wire [NL_W-1:0]     n_log2_reg;
/* verilator lint_off UNUSEDSIGNAL */  // K = 0: no term to skip
wire [KU_W-1:0]     k_used_reg;   // terms the texture uses: 0..k_used-1
/* verilator lint_on UNUSEDSIGNAL */
localparam KV = (K > 0) ? K : 1;  // K = 0 still declares (unused) vectors
wire [10*Q_W-1:0]   q_coef;       // coefficient i at [i*Q_W +: Q_W]
/* verilator lint_off UNUSEDSIGNAL */  // read by no noise term when K = 0
wire [KV*AS_W-1:0]  a_all_reg;    // {ae_k, a_k} at [k*AS_W +: AS_W] (ae: A_EXP_W > 0 only)
wire [KV*TS_W-1:0]  t_all_reg;    // {te_k, T_k} at [k*TS_W +: TS_W], T_k[j][m] at (3*j + m)*T_W in it
wire [KV*3*O_W-1:0] o_all_reg;    // o_k[j] at [(3*k + j)*O_W +: O_W]
/* verilator lint_on UNUSEDSIGNAL */
wire                tbl_wr_en_reg;
wire [1:0]          tbl_wr_table_reg;
wire [NLMAX:0]      tbl_wr_addr_reg;
wire [4*CSAT_W-1:0] tbl_wr_data_reg;

tex_regs #(
    .NOISE_TERMS(K), .Q_W(Q_W), .A_W(A_W), .T_W(T_W), .HASH_BITS(HASH_BITS), .P_FRAC(P_FRAC),
    .N_LOG2_MAX(N_LOG2_MAX), .T_EXP_W(T_EXP_W), .A_EXP_W(A_EXP_W)
) u_regs (
    .clk(clk), .rst(rst),
    .cfg_wr_en(cfg_wr_en), .cfg_wr_addr(cfg_wr_addr), .cfg_wr_data(cfg_wr_data),
    .mode(mode_reg), .filter_en(filter_en_reg), .n_log2(n_log2_reg), .k_used(k_used_reg),
    .q_coef(q_coef), .a_all(a_all_reg), .t_all(t_all_reg), .o_all(o_all_reg),
    .tbl_wr_en(tbl_wr_en_reg), .tbl_wr_table(tbl_wr_table_reg), .tbl_wr_addr(tbl_wr_addr_reg),
    .tbl_wr_data(tbl_wr_data_reg)
);


// What the blocks read of the transforms: with pow2 transforms the off-diagonal T entries are
// 0 and noise_term does not read them. Passing 0 makes that visible here, so their registers
// go (they would in a flat synthesis anyway; the per-block gate count keeps the blocks apart;
// texture_sum does the same for a diagonal quadric's coefficients).
reg [KV*TS_W-1:0]   t_use;
integer             ui, uj;
always @* begin
    t_use = t_all_reg;
    if (POW2T != 0) begin
        for (ui = 0; ui < KV; ui = ui + 1)
            for (uj = 0; uj < 9; uj = uj + 1)
                if (uj % 4 != 0) t_use[ui*TS_W + uj*T_W +: T_W] = {T_W{1'b0}};
    end
end

// ---------------------------------------------------------------------------
// Input fields

wire [3*S_W-1:0]  pix_s  = s_axis_tdata[0 +: 3*S_W];
wire [JM_W-1:0]   pix_jm = s_axis_tdata[3*S_W +: JM_W];
wire [JE_W-1:0]   pix_je = s_axis_tdata[3*S_W + JM_W +: JE_W];

// The sample at the front's input (in_*): the pixel itself, or (SAMPLES > 1) its sub-pixel
// samples one after the other (sample_expand: offset s, footprint its cell's); each
// sample carries the pixel's tlast, and sample_average takes the last sample's
wire              in_valid;
wire [3*S_W-1:0]  in_s;
wire [JM_W-1:0]   in_jm;
wire [JE_W-1:0]   in_je;

generate
    if (SAMPLES > 1) begin : g_samples
        sample_expand #(
            .SAMPLES(SAMPLES), .S_W(S_W), .S_FRAC(S_FRAC), .J_W(J_W), .JE_W(JE_W)
        ) u_sample_expand (
            .clk(clk), .rst(rst), .ce(ce),
            .in_valid(pix_valid), .in_ready(smp_ready), .s_in(pix_s), .jm_in(pix_jm), .je_in(pix_je),
            .out_valid(in_valid), .out_ready(fold_ready), .s_out(in_s), .jm_out(in_jm), .je_out(in_je)
        );
    end else begin : g_one_sample
        assign smp_ready = fold_ready;
        assign in_valid  = pix_valid;
        assign in_s      = pix_s;
        assign in_jm     = pix_jm;
        assign in_je     = pix_je;
    end
endgenerate

// The pixel at the front (px_*): the input itself, or (FOLD) the pixel noise_fold issues,
// at its last issue clock (px_valid); the quadric, the delay lines of Jm, je and tlast and
// (unfolded) the noise terms start there. Folded, the noise terms' sum comes out of
// noise_fold LAT_NT + LAT_NF clocks after px_valid, as one leaf of the adder tree.
wire              px_valid;
wire [3*S_W-1:0]  px_s;
wire [JM_W-1:0]   px_jm;
wire [JE_W-1:0]   px_je;
wire              px_last;
/* verilator lint_off UNUSEDSIGNAL */  // unfolded: constant, not read
wire [F_W-1:0]    fold_f;
wire [3*C_W-1:0]  fold_c;
wire              fold_valid;
/* verilator lint_on UNUSEDSIGNAL */

generate
    if (FOLD) begin : g_fold
        wire [JM_W+JE_W:0] side;
        noise_fold #(
            .S_W(S_W), .S_FRAC(S_FRAC), .T_W(T_W), .T_FRAC(T_FRAC), .A_W(A_W), .A_FRAC(A_FRAC),
            .P_FRAC(P_FRAC), .HASH_BITS(HASH_BITS), .N_FRAC(N_FRAC), .F_FRAC(F_FRAC), .C_FRAC(C_FRAC),
            .TRANSFORM(TRANSFORM), .BLEND(BLEND), .AMPLITUDE(AMPLITUDE), .NOISE_GRADIENT(NOISE_GRADIENT),
            .NOISE_TERMS(K), .NOISE_UNITS(U), .F_W(F_W), .C_W(C_W), .SIDE_W(JM_W + JE_W + 1),
            .MIN_CLOCKS(MIN_CLK), .FPGA_REGS(FPGA_REGS), .T_EXP_W(T_EXP_W), .A_EXP_W(A_EXP_W), .PERM(PERM)
        ) u_noise_fold (
            .clk(clk), .rst(rst), .ce(ce),
            .in_valid(in_valid), .in_ready(fold_ready),
            .s_in(in_s), .side_in({s_axis_tlast, in_je, in_jm}),
            .k_used(k_used_reg), .a_all(a_all_reg), .t_all(t_use), .o_all(o_all_reg),
            .px_valid(px_valid), .px_s(px_s), .px_side(side),
            .sum_valid(fold_valid), .f_sum(fold_f), .c_sum(fold_c)
        );
        assign px_jm   = side[0 +: JM_W];
        assign px_je   = side[JM_W +: JE_W];
        assign px_last = side[JM_W + JE_W];
    end else begin : g_direct
        assign fold_ready = 1'b1;
        assign px_valid   = in_valid;
        assign px_s       = in_s;
        assign px_jm      = in_jm;
        assign px_je      = in_je;
        assign px_last    = s_axis_tlast;
        assign fold_f     = {F_W{1'b0}};
        assign fold_c     = {3*C_W{1'b0}};
        assign fold_valid = 1'b0;
    end
endgenerate

// ---------------------------------------------------------------------------
// f and grad f (texture_sum: the quadric and the K noise terms, faded with sat_fc, summed in
// the adder trees): f at T_F; c with f (NG) or the quadric's at LAT_QM (!NG); sat_fc's wv
// LAT_FCW after the front, delayed here to filter_width's output (T_FW)
wire [F_W-1:0]   f_sum;
wire             sum_valid;
wire [3*C_W-1:0] c_fw;
wire             c_fw_valid;
/* verilator lint_off UNUSEDSIGNAL */  // no sat_fc: constant, not read
wire [W_W-1:0]   fc_wv;
wire [W_W-1:0]   fc_wv_d;
/* verilator lint_on UNUSEDSIGNAL */

texture_sum #(
    .QUADRIC(QUADRIC), .QUADRIC_CLOCKS(QUADRIC_CLOCKS), .NOISE_TERMS(K), .NOISE_UNITS(U), .BLEND(BLEND),
    .TRANSFORM(TRANSFORM), .AMPLITUDE(AMPLITUDE), .NOISE_GRADIENT(NOISE_GRADIENT), .FC(FCL ? 1 : 0),
    .FPGA_REGS(FPGA_REGS), .LATENCY(T_F), .S_W(S_W), .S_FRAC(S_FRAC), .Q_W(Q_W), .Q_FRAC(Q_FRAC), .J_W(J_W),
    .JE_W(JE_W), .T_W(T_W), .T_FRAC(T_FRAC), .A_W(A_W), .A_FRAC(A_FRAC), .P_FRAC(P_FRAC), .HASH_BITS(HASH_BITS),
    .N_FRAC(N_FRAC), .F_FRAC(F_FRAC), .C_FRAC(C_FRAC), .W_CAP_LOG2(W_CAP_LOG2), .N_LOG2_MAX(N_LOG2_MAX),
    .FC_LOG_FRAC(FC_LOG_FRAC), .FC_KNEE(FC_KNEE), .FC_FADE_LOG2(FC_FADE_LOG2), .FC_KS(FC_KS), .FC_KSF(FC_KSF),
    .T_EXP_W(T_EXP_W), .A_EXP_W(A_EXP_W), .PERM(PERM)
) u_texture_sum (
    .clk(clk), .rst(rst), .ce(ce),
    .in_valid(px_valid), .s_in(px_s), .jm_in(px_jm), .je_in(px_je),
    .q_coef(q_coef), .k_used(k_used_reg), .a_all(a_all_reg), .t_all(t_use), .o_all(o_all_reg),
    .filter_en(filter_en_reg), .n_log2(n_log2_reg),
    .fold_valid(fold_valid), .fold_f(fold_f), .fold_c(fold_c),
    .out_valid(sum_valid), .f_out(f_sum), .c_valid(c_fw_valid), .c_out(c_fw), .wv_out(fc_wv)
);

generate
    // colour_map's fold needs a sample at most every CMAP_CLOCKS clocks: noise_fold's pacing
    if (CMAP_CLOCKS != 1 && !FOLD) begin : g_bad_cmap_clocks
        texture_pipeline_cmap_clocks_needs_folded_terms u_bad ();  // elaboration error
    end
    if (FCL) begin : g_wv
        if (LAT_FCW > T_FW) begin : g_bad_fc_latency
            fc_weight_latency_exceeds_filter_width u_bad ();  // elaboration error
        end
        delay_line #(.W(W_W), .N(T_FW - LAT_FCW)) u_dly_wv (.clk(clk), .rst(rst), .ce(ce), .d_in(fc_wv),
                                                            .d_out(fc_wv_d));
    end else begin : g_nowv
        assign fc_wv_d = {W_W{1'b0}};
    end
endgenerate

// ---------------------------------------------------------------------------
// Jm, je: from the input to filter_width (DLY_J stages); tlast: to the colour_map output

localparam JD_W = JM_W + JE_W;
wire [JD_W-1:0] jd_out;
delay_line #(.W(JD_W), .N(DLY_J)) u_dly_j (.clk(clk), .rst(rst), .ce(ce), .d_in({px_je, px_jm}), .d_out(jd_out));

wire cm_last;
delay_line #(.W(1), .N(T_CM + LAT_CM)) u_dly_last (.clk(clk), .rst(rst), .ce(ce), .d_in(px_last),
                                                  .d_out(cm_last));

// ---------------------------------------------------------------------------
// filter_width on grad f (texture_sum's c: NG the tree's, otherwise the quadric's gradient)

wire [NW*W_W-1:0] fw_w;
wire           fw_valid;

filter_width #(
    .C_W(C_W), .C_FRAC(C_FRAC), .J_W(J_W), .JE_W(JE_W), .NORM_BITS(NORM_BITS), .F_FRAC(F_FRAC),
    .W_CAP_LOG2(W_CAP_LOG2), .N_LOG2_MAX(N_LOG2_MAX), .COMPONENTS(NW - 1), .FPGA_REGS(FPGA_REGS)
) u_filter_width (
    .clk(clk), .rst(rst), .ce(ce),
    .in_valid(c_fw_valid),
    .c_in(c_fw),
    .jm_in(jd_out[0 +: JM_W]),
    .je_in(jd_out[JM_W +: JE_W]),
    .n_log2(n_log2_reg),
    .out_valid(fw_valid),
    .w_out(fw_w)
);


// f and w meet (cm_align: f saturated while it waits, sat_fc's max(w, wv), the delay lines)
wire [F_W-1:0] f_cm;
wire [NW*W_W-1:0] cm_w;
wire           cm_in_valid;
cm_align #(
    .F_W(F_W), .F_FRAC(F_FRAC), .W_CAP_LOG2(W_CAP_LOG2), .WV_MAX(FCL ? 1 : 0), .NW(NW),
    .LATENCY_F(T_CM - T_F), .LATENCY_W(T_CM - T_FW)
) u_cm_align (
    .clk(clk), .rst(rst), .ce(ce), .mode(mode_reg),
    .f_valid(sum_valid), .w_valid(fw_valid), .f_in(f_sum), .w_in(fw_w), .wv_in(fc_wv_d),
    .out_valid(cm_in_valid), .f_out(f_cm), .w_out(cm_w)
);

// ---------------------------------------------------------------------------
// colour_map

wire [31:0] cm_rgba;

colour_map #(
    .F_W(F_W), .F_FRAC(F_FRAC), .W_CAP_LOG2(W_CAP_LOG2), .N_LOG2_MAX(N_LOG2_MAX), .FILTER(CM_FILTER),
    .DIV_BITS(DIV_BITS), .FPGA_REGS(FPGA_REGS), .CLOCKS(CMAP_CLOCKS)
) u_colour_map (
    .clk(clk), .rst(rst), .ce(ce),
    .in_valid(cm_in_valid),
    .f_in(f_cm),
    .w_in(cm_w),
    .mode(mode_reg),
    .n_log2(n_log2_reg),
    .filter_en(filter_en_reg),
    .out_valid(cm_valid),
    .rgba_out(cm_rgba),
    .wr_en(tbl_wr_en_reg),
    .wr_table(tbl_wr_table_reg),
    .wr_addr(tbl_wr_addr_reg),
    .wr_data(tbl_wr_data_reg)
);

// ---------------------------------------------------------------------------
// The pixel's colour: colour_map's, or (SAMPLES > 1) the average of its samples' (sample_average,
// one more register stage)

wire [31:0] out_rgba;
wire        out_last;

generate
    if (SAMPLES > 1) begin : g_average
        sample_average #(.SAMPLES(SAMPLES)) u_sample_average (
            .clk(clk), .rst(rst), .ce(ce),
            .in_valid(cm_valid), .in_rgba(cm_rgba), .in_last(cm_last),
            .out_valid(out_valid), .out_rgba(out_rgba), .out_last(out_last)
        );
    end else begin : g_colour
        assign out_valid = cm_valid;
        assign out_rgba  = cm_rgba;
        assign out_last  = cm_last;
    end
endgenerate

// ---------------------------------------------------------------------------
// Output skid buffer (axis_skid: registered input ready, one clock)

axis_skid #(.DATA_W(32)) u_skid (
    .clk(clk), .rst(rst),
    .s_axis_tdata(out_rgba), .s_axis_tvalid(out_valid), .s_axis_tready(skid_ready), .s_axis_tlast(out_last),
    .m_axis_tdata(m_axis_tdata), .m_axis_tvalid(m_axis_tvalid), .m_axis_tready(m_axis_tready),
    .m_axis_tlast(m_axis_tlast)
);

endmodule

`default_nettype wire
