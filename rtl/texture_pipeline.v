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
// documents it) from the constants of rtl/tex_regmap.vh, generated from the one table of the
// register map, model/hw/regmap.py REGMAP_TABLE (python -m model.hw.regmap prints it; its
// write_sequence is what a host writes). CTRL (mode, filter_en, n_log2), the quadric
// coefficients, K noise terms (a_k, T_k, o_k), and the colour tables clut, csat (channels
// 0..2 staged, channel 3 commits an entry; write csat in ascending order, the last entry
// committed, N - 1, is the whole-table sum) and mip. Writes to unmapped addresses and past
// the end of a table are ignored. Table writes reach colour_map's write port one clock
// later. After rst every parameter register is 0 (the tables are not reset). Write the
// parameters while no pixel is in flight; they are held, unchanged, during a pass.
//
// Pipeline: quadric_mac and K noise_term instances (noise_leaves, which also makes the adder
// tree's leaves) in parallel on s, a registered adder tree (sum_tree) of arity 4 for f
// (TREE_LEVELS = ceil(log4(K+1)) stages), filter_width, then colour_map.
// With the noise gradient (NOISE_GRADIENT 1: grad f = grad q + sum a_i grad n_i), the
// tree also sums the gradients and filter_width follows it; the quadric's input waits so that
// its outputs meet the terms'. Without it (grad f = grad q), filter_width runs on the
// quadric's gradient in parallel with the noise terms, and q waits for the terms instead.
// f (in fewer bits) or w waits for the other before colour_map (cm_align); Jm, je and tlast
// travel in delay lines (delay_line) beside the data. Every
// register of the datapath shares one clock enable
//   ce = rst | !cm_valid | skid_ready
// (the colour_map output is the last pipeline stage; it may advance whenever it is empty or
// the output skid buffer can take it). The output skid buffer (axis_skid: two registers, the
// pattern of alexforencich/verilog-axis axis_register, REG_TYPE = 2) has a registered input ready, so
// no combinational path runs from m_axis_tready to s_axis_tready or ce, and a stall on
// m_axis_tready never loses, duplicates or reorders a pixel. s_axis_tready = ce (& !rst):
// a pixel enters whenever the pipeline advances.
//
// Latency: LATENCY = T_CM + LAT_COLOUR_MAP enabled clocks from s_axis to the colour_map output,
// T_CM = max(T_F, T_WD) = max(LAT_FRONT + TREE_LEVELS, DLY_J + LAT_FILTER_WIDTH) (below; sat_fc:
// LAT_FC_SCALE more in the terms and LAT_FC_WMAX after filter_width), plus one clock in the
// skid buffer. Throughput: one pixel per clock while m_axis_tready is held high.
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
                                    // clocks a pixel (diagonal quadric, folded terms)
    parameter BLEND          = 1,   // [blend] 0 linear, 1 cubic
    parameter TRANSFORM      = 0,   // [transform] 0 affine, 1 pow2
    parameter AMPLITUDE      = 0,   // [amplitude] 0 any, 1 pow2
    parameter FILTER         = 1,   // [filter] 0 none (point lookup), 1 sat, 2 mip, 3 sat_fc (sat with
                                    // frequency clamping: fc_weight, fc_scale; unfolded terms only),
                                    // 4 sat2 (the trapezoid: filter_width's two components, cmap_sat2)
    parameter NOISE_GRADIENT = 1,   // [noise_gradient] 1: grad f includes the noise terms'
    parameter FPGA_REGS      = 0,   // [fpga_regs] 1: the blocks' extra register stages for an FPGA
                                    // (rtl/tex_latency.vh `LAT_*_FPGA; docs/fpga.md)
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
localparam QF_W   = tw_qf_w(DIAG, S_W, S_FRAC, Q_W, Q_FRAC, F_FRAC);           // quadric value
localparam F_W    = tw_f_w(DIAG, S_W, S_FRAC, Q_W, Q_FRAC, F_FRAC, K, A_W, A_FRAC, N_FRAC); // f (exact sum)
localparam C_W    = tw_c_w(DIAG, S_W, S_FRAC, Q_W, Q_FRAC, C_FRAC, K, NOISE_GRADIENT, CUBIC, POW2T, T_W,
                           T_FRAC, N_FRAC, A_W, A_FRAC);                       // grad f (exact sum)
localparam W_W    = W_CAP_LOG2 + F_FRAC + 1;                                   // filter width
localparam CSAT_W = tw_csat_w(N_LOG2_MAX);                                     // summed-area channel
localparam NL_W   = tw_bits_unsigned(N_LOG2_MAX);                              // n_log2
localparam NLMAX  = N_LOG2_MAX;
localparam PIX_W  = 3*S_W + 6*J_W + JE_W;                                      // pixel input word
localparam FCL    = (FILTER == 3) && (K > 0) && !FOLD;                         // frequency clamping
localparam CM_FILTER = (FILTER == 3) ? 1 : (FILTER == 4) ? 3 : FILTER;       // colour_map: the box, sat2 its own
localparam NW     = (FILTER == 4) ? 2 : 1;                                     // sat2: w = {b, a}
localparam FC_AF  = FC_LOG_FRAC + FC_FADE_LOG2;                                // alpha u1.FC_AF

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
localparam LAT_QM      = FPGA_REGS ? `LAT_QUADRIC_MAC_FPGA  : `LAT_QUADRIC_MAC;
localparam LAT_NT      = FPGA_REGS ? `LAT_NOISE_TERM_FPGA   : `LAT_NOISE_TERM;
localparam LAT_FW      = FPGA_REGS ? `LAT_FILTER_WIDTH_FPGA : `LAT_FILTER_WIDTH;
localparam LAT_CM      = FPGA_REGS ? `LAT_COLOUR_MAP_FPGA   : `LAT_COLOUR_MAP;
localparam LAT_FCW     = `LAT_FC_WEIGHT;
localparam LAT_FCS     = FCL ? `LAT_FC_SCALE : 0;                        // sat_fc: fc_scale after each term
localparam LAT_NF      = FPGA_REGS ? `LAT_NOISE_FOLD_FPGA   : `LAT_NOISE_FOLD;
localparam LAT_NS      = FOLD ? LAT_NT + LAT_NF : LAT_NT + LAT_FCS;      // noise leaves (noise_fold: + LAT_NF)
localparam LAT_FRONT   = (K > 0 && LAT_NS > LAT_QM) ? LAT_NS : LAT_QM;  // q and the terms meet here
localparam TREE_LEVELS = tw_tree_levels(NLEAF + 1, `SUM_TREE_ARITY);     // adder tree (sum_tree) stages
localparam T_F         = LAT_FRONT + TREE_LEVELS;                        // f (and c) out of the tree
// With the noise gradient (NG), grad f = grad q + sum a_i grad n_i comes out of the tree with
// f, and filter_width follows the tree: the quadric's input waits DLY_Q so that its outputs
// meet the terms'. Without it, grad f = grad q: filter_width takes the quadric's gradient
// straight away, in parallel with the noise terms, and only q waits (DLY_QO) for the terms.
localparam NG          = NOISE_GRADIENT;
localparam DLY_Q       = NG ? LAT_FRONT - LAT_QM : 0;                    // quadric input (s) delay
localparam DLY_QO      = NG ? 0 : LAT_FRONT - LAT_QM;                    // quadric q output delay
localparam DLY_J       = NG ? T_F : LAT_QM;                              // Jm, je to filter_width
localparam T_FW        = DLY_J + LAT_FW;                                 // w out of filter_width
localparam T_WD        = T_FW + (FCL ? `LAT_FC_WMAX : 0);                // sat_fc: then max(w, wv) (cm_align)
localparam T_CM        = (T_WD > T_F) ? T_WD : T_F;                       // colour_map input
// total latency to the colour_map output (the skid buffer adds one more clock); for readers
// and waveform viewers only, nothing below needs it
/* verilator lint_off UNUSEDPARAM */
localparam LATENCY     = T_CM + LAT_CM;
/* verilator lint_on UNUSEDPARAM */

localparam JM_W = 6*J_W;

// ---------------------------------------------------------------------------
// Flow control

wire cm_valid;          // colour_map output (last pipeline stage) holds a pixel
wire skid_ready;        // the output skid buffer can take a pixel this clock (a register)
wire advance = !cm_valid || skid_ready;
wire ce      = rst || advance;  // rst: every block's reset sees an enabled clock

wire fold_ready;         // the front can take a pixel (always, unless the terms are folded)
assign s_axis_tready = advance && !rst && fold_ready;
wire in_valid = s_axis_tvalid && !rst;

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
wire [KV*A_W-1:0]   a_all_reg;    // a_k at [k*A_W +: A_W]
wire [KV*9*T_W-1:0] t_all_reg;    // T_k[j][m] at [(9*k + 3*j + m)*T_W +: T_W]
wire [KV*3*O_W-1:0] o_all_reg;    // o_k[j] at [(3*k + j)*O_W +: O_W]
/* verilator lint_on UNUSEDSIGNAL */
wire                tbl_wr_en_reg;
wire [1:0]          tbl_wr_table_reg;
wire [NLMAX:0]      tbl_wr_addr_reg;
wire [4*CSAT_W-1:0] tbl_wr_data_reg;

tex_regs #(
    .NOISE_TERMS(K), .Q_W(Q_W), .A_W(A_W), .T_W(T_W), .HASH_BITS(HASH_BITS), .P_FRAC(P_FRAC),
    .N_LOG2_MAX(N_LOG2_MAX)
) u_regs (
    .clk(clk), .rst(rst),
    .cfg_wr_en(cfg_wr_en), .cfg_wr_addr(cfg_wr_addr), .cfg_wr_data(cfg_wr_data),
    .mode(mode_reg), .filter_en(filter_en_reg), .n_log2(n_log2_reg), .k_used(k_used_reg),
    .q_coef(q_coef), .a_all(a_all_reg), .t_all(t_all_reg), .o_all(o_all_reg),
    .tbl_wr_en(tbl_wr_en_reg), .tbl_wr_table(tbl_wr_table_reg), .tbl_wr_addr(tbl_wr_addr_reg),
    .tbl_wr_data(tbl_wr_data_reg)
);


// What the blocks read of the parameters: with a diagonal quadric B, C, F are 0 (quantize
// guarantees it) and quadric_mac does not read them; with pow2 transforms the off-diagonal
// T entries are 0 and noise_term does not read them. Passing 0 makes that visible here, so
// their registers go (they would in a flat synthesis anyway; the per-block gate count keeps
// the blocks apart).
reg [10*Q_W-1:0]    q_use;
reg [KV*9*T_W-1:0]  t_use;
integer             ui, uj;
always @* begin
    q_use = q_coef;
    if (DIAG != 0) begin
        q_use[1*Q_W +: Q_W] = {Q_W{1'b0}};
        q_use[2*Q_W +: Q_W] = {Q_W{1'b0}};
        q_use[5*Q_W +: Q_W] = {Q_W{1'b0}};
    end
    t_use = t_all_reg;
    if (POW2T != 0) begin
        for (ui = 0; ui < KV; ui = ui + 1)
            for (uj = 0; uj < 9; uj = uj + 1)
                if (uj % 4 != 0) t_use[(9*ui + uj)*T_W +: T_W] = {T_W{1'b0}};
    end
end

// ---------------------------------------------------------------------------
// Input fields

wire [3*S_W-1:0]  in_s  = s_axis_tdata[0 +: 3*S_W];
wire [JM_W-1:0]   in_jm = s_axis_tdata[3*S_W +: JM_W];
wire [JE_W-1:0]   in_je = s_axis_tdata[3*S_W + JM_W +: JE_W];

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
            .MIN_CLOCKS(QUADRIC_CLOCKS), .FPGA_REGS(FPGA_REGS), .PERM(PERM)
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
// sat_fc: the frequency-clamping weights of the pixel (fc_weight, LAT_FCW stages from the
// front), alpha delayed to the terms' outputs (LAT_NT) and wv to filter_width's (T_FW)

/* verilator lint_off UNUSEDSIGNAL */  // no sat_fc: constant, not read
wire [KV*(FC_AF+1)-1:0] fc_alpha_d;
wire [W_W-1:0]          fc_wv_d;
/* verilator lint_on UNUSEDSIGNAL */
generate
    if (FCL) begin : g_fcw
        if (LAT_FCW > LAT_NT || LAT_FCW > T_FW) begin : g_bad_fc_latency
            fc_weight_latency_exceeds_the_noise_term_or_filter_width u_bad ();  // elaboration error
        end
        wire [K*(FC_AF+1)-1:0] alpha;
        wire [W_W-1:0]         wv;
        /* verilator lint_off UNUSEDSIGNAL */  // valid: the shared pipeline valid is used instead
        wire                   fcw_valid;
        /* verilator lint_on UNUSEDSIGNAL */
        fc_weight #(
            .NOISE_TERMS(K), .J_W(J_W), .JE_W(JE_W), .T_W(T_W), .T_FRAC(T_FRAC), .A_W(A_W), .A_FRAC(A_FRAC),
            .F_FRAC(F_FRAC), .W_CAP_LOG2(W_CAP_LOG2), .N_LOG2_MAX(N_LOG2_MAX), .FC_LOG_FRAC(FC_LOG_FRAC),
            .FC_KNEE(FC_KNEE), .FC_FADE_LOG2(FC_FADE_LOG2), .FC_KS(FC_KS), .FC_KSF(FC_KSF)
        ) u_fc_weight (
            .clk(clk), .rst(rst), .ce(ce),
            .in_valid(px_valid), .jm_in(px_jm), .je_in(px_je),
            .a_all(a_all_reg), .t_all(t_use), .k_used(k_used_reg), .filter_en(filter_en_reg), .n_log2(n_log2_reg),
            .out_valid(fcw_valid), .alpha_out(alpha), .wv_out(wv)
        );
        delay_line #(.W(K*(FC_AF+1)), .N(LAT_NT - LAT_FCW)) u_dly_alpha (.clk(clk), .rst(rst), .ce(ce),
                                                                         .d_in(alpha), .d_out(fc_alpha_d));
        delay_line #(.W(W_W), .N(T_FW - LAT_FCW)) u_dly_wv (.clk(clk), .rst(rst), .ce(ce), .d_in(wv),
                                                            .d_out(fc_wv_d));
    end else begin : g_nofcw
        assign fc_alpha_d = {KV*(FC_AF+1){1'b0}};
        assign fc_wv_d    = {W_W{1'b0}};
    end
endgenerate

// ---------------------------------------------------------------------------
// Front: quadric_mac and K noise terms in parallel

// NG: the quadric is the shorter block: its input (s and valid, narrower than its outputs)
// waits DLY_Q stages so that its outputs meet the noise terms' at LAT_FRONT.
wire [3*S_W-1:0] qs_s;
wire             qs_valid;
delay_line #(.W(3*S_W), .N(DLY_Q))           u_dly_qs (.clk(clk), .rst(rst), .ce(ce), .d_in(px_s), .d_out(qs_s));
delay_line #(.W(1), .N(DLY_Q), .CLEAR(1))    u_dly_qv (.clk(clk), .rst(rst), .ce(ce), .d_in(px_valid), .d_out(qs_valid));

wire [QF_W-1:0]  qm_q;
wire [3*C_W-1:0] qm_cq;
wire             qm_valid;

quadric_mac #(
    .DIAG(DIAG), .CLOCKS(QUADRIC_CLOCKS), .S_W(S_W), .S_FRAC(S_FRAC), .Q_W(Q_W), .Q_FRAC(Q_FRAC),
    .F_FRAC(F_FRAC), .C_FRAC(C_FRAC), .C_W(C_W), .FPGA_REGS(FPGA_REGS)
) u_quadric_mac (
    .clk(clk), .rst(rst), .ce(ce),
    .in_valid(qs_valid),
    .s_in(qs_s),
    .q_coef(q_use),
    .out_valid(qm_valid),
    .q_out(qm_q),
    .cq_out(qm_cq)
);

// !NG: q (and its valid) wait DLY_QO stages for the terms; its gradient goes to filter_width
wire [QF_W-1:0] qo_q;
wire            qo_valid;
delay_line #(.W(QF_W), .N(DLY_QO))        u_dly_qo (.clk(clk), .rst(rst), .ce(ce), .d_in(qm_q), .d_out(qo_q));
delay_line #(.W(1), .N(DLY_QO), .CLEAR(1)) u_dly_qov (.clk(clk), .rst(rst), .ce(ce), .d_in(qm_valid),
                                                       .d_out(qo_valid));
// the leaves of the adder trees (noise_leaves: the K noise terms, faded with sat_fc, or
// noise_fold's sum, and the quadric's, sign-extended): leaf i at [i*F_W +: F_W], [i*3*C_W +: 3*C_W]
wire                       sum_in_valid;
wire [(NLEAF+1)*F_W-1:0]   f_leaves;
/* verilator lint_off UNUSEDSIGNAL */  // !NG: no gradient tree
wire [(NLEAF+1)*3*C_W-1:0] c_leaves;
/* verilator lint_on UNUSEDSIGNAL */
noise_leaves #(
    .QUADRIC(QUADRIC), .NOISE_TERMS(K), .NOISE_UNITS(U), .FC(FCL ? 1 : 0), .FC_LOG_FRAC(FC_LOG_FRAC),
    .FC_FADE_LOG2(FC_FADE_LOG2), .LATENCY(LAT_FRONT), .S_W(S_W), .S_FRAC(S_FRAC), .Q_W(Q_W), .Q_FRAC(Q_FRAC),
    .T_W(T_W), .T_FRAC(T_FRAC), .A_W(A_W), .A_FRAC(A_FRAC), .P_FRAC(P_FRAC), .HASH_BITS(HASH_BITS),
    .N_FRAC(N_FRAC), .F_FRAC(F_FRAC), .C_FRAC(C_FRAC), .TRANSFORM(TRANSFORM), .BLEND(BLEND),
    .AMPLITUDE(AMPLITUDE), .NOISE_GRADIENT(NOISE_GRADIENT), .FPGA_REGS(FPGA_REGS), .PERM(PERM)
) u_noise_leaves (
    .clk(clk), .rst(rst), .ce(ce),
    .in_valid(px_valid), .s_in(px_s),
    .k_used(k_used_reg), .a_all(a_all_reg), .t_all(t_use), .o_all(o_all_reg), .alpha(fc_alpha_d),
    .fold_valid(fold_valid), .fold_f(fold_f), .fold_c(fold_c),
    .q_valid(qo_valid), .q_in(qo_q), .cq_in(qm_cq),
    .out_valid(sum_in_valid), .f_leaves(f_leaves), .c_leaves(c_leaves)
);

// ---------------------------------------------------------------------------
// Adder trees (sum_tree, TREE_LEVELS register levels): f = q + sum a_i n_i over the leaves,
// and with NG c = dq/ds + sum a_i grad n_i, three lanes; sums modulo 2^F_W / 2^C_W of
// sign-extended operands, i.e. exact (F_W and C_W bound the whole sums, model/hw/config.py
// f_w, c_w). !NG: the tree carries no gradient (the quadric's goes to filter_width).

wire [F_W-1:0]   f_sum;
wire             sum_valid;
/* verilator lint_off UNUSEDSIGNAL */  // !NG: c is constant 0 and not read
wire [3*C_W-1:0] c_sum;
/* verilator lint_on UNUSEDSIGNAL */

sum_tree #(.N(NLEAF + 1), .W(F_W), .LANES(1), .LATENCY(TREE_LEVELS)) u_f_tree (
    .clk(clk), .rst(rst), .ce(ce),
    .in_valid(sum_in_valid), .leaves(f_leaves),
    .out_valid(sum_valid), .sum_out(f_sum)
);

generate
    if (NG) begin : g_c_tree
        /* verilator lint_off UNUSEDSIGNAL */  // the same as sum_valid (f's tree)
        wire c_valid;
        /* verilator lint_on UNUSEDSIGNAL */
        sum_tree #(.N(NLEAF + 1), .W(C_W), .LANES(3), .LATENCY(TREE_LEVELS)) u_c_tree (
            .clk(clk), .rst(rst), .ce(ce),
            .in_valid(sum_in_valid), .leaves(c_leaves),
            .out_valid(c_valid), .sum_out(c_sum)
        );
    end else begin : g_c_zero
        assign c_sum = {3*C_W{1'b0}};
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
// filter_width on grad f (NG: the tree's c; otherwise the quadric's gradient)

wire [NW*W_W-1:0] fw_w;
wire           fw_valid;

filter_width #(
    .C_W(C_W), .C_FRAC(C_FRAC), .J_W(J_W), .JE_W(JE_W), .NORM_BITS(NORM_BITS), .F_FRAC(F_FRAC),
    .W_CAP_LOG2(W_CAP_LOG2), .N_LOG2_MAX(N_LOG2_MAX), .COMPONENTS(NW - 1), .FPGA_REGS(FPGA_REGS)
) u_filter_width (
    .clk(clk), .rst(rst), .ce(ce),
    .in_valid(NG ? sum_valid : qm_valid),
    .c_in(NG ? c_sum : qm_cq),
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
    .DIV_BITS(DIV_BITS), .FPGA_REGS(FPGA_REGS)
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
// Output skid buffer (axis_skid: registered input ready, one clock)

axis_skid #(.DATA_W(32)) u_skid (
    .clk(clk), .rst(rst),
    .s_axis_tdata(cm_rgba), .s_axis_tvalid(cm_valid), .s_axis_tready(skid_ready), .s_axis_tlast(cm_last),
    .m_axis_tdata(m_axis_tdata), .m_axis_tvalid(m_axis_tvalid), .m_axis_tready(m_axis_tready),
    .m_axis_tlast(m_axis_tlast)
);

endmodule

`default_nettype wire
