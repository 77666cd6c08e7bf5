// texture_sum: the texture function of a pixel and its gradient, texture_pipeline's front:
//
//   f = q(s) + sum_i alpha_i a_i n(T_i s + o_i)          (quadric_mac, noise_leaves, sum_tree)
//   c = dq/ds + sum_i alpha_i a_i (dn_i/dp) T_i          (NOISE_GRADIENT 1; 0: c = dq/ds)
//
// alpha_i = 1 but with FC (filter sat_fc): the frequency clamp of term i from the pixel's
// footprint (fc_weight on Jm, je), each term faded by it (fc_scale, in noise_leaves), and
// wv_out the faded terms' spread, a filter width for the caller to align. The quadric and the
// K noise terms (or, folded, noise_fold's sum, brought in by the caller: fold_*) run in
// parallel; their leaves are summed exactly in registered adder trees (sum_tree) of f and,
// with the noise gradient, of c. The shorter of the two paths waits: with the noise gradient
// the quadric's input s (narrower than its outputs) waits DLY_Q stages so that q and grad q
// meet the terms'; without it grad q goes out at once (to filter_width, in parallel with the
// terms) and only q waits (DLY_QO). With a diagonal quadric B, C, F are 0 (quantize guarantees
// it) and quadric_mac does not read them: passing 0 makes that visible, so their registers go
// in the caller. model/hw/golden.py texture_sum is the twin.
//
// Formats (rtl/tex_widths.vh): s_in 3 x s{S_W}.{S_FRAC} (element e at [e*S_W +: S_W]); jm_in
// 6 x s{J_W}.0, je_in s{JE_W}.0; q_coef 10 x s{Q_W}.{Q_FRAC}; a, T, o as noise_term's (term k
// of a_all {ae_k, a_k}, of t_all {te_k, T_k}: tex_regs' layout, the exponents only with T_EXP_W,
// A_EXP_W > 0);
// fold_f s{F_W}.{F_FRAC}, fold_c 3 x s{C_W}.{C_FRAC}; f_out s{F_W}.{F_FRAC}, c_out 3 x
// s{C_W}.{C_FRAC} (F_W, C_W bound the whole sums: exact, docs/numerics.md); wv_out
// u{W_CAP_LOG2+F_FRAC+1}.{F_FRAC} colour-table entries.
// Latency: f_out and out_valid LATENCY enabled clocks after in_valid (folded: after noise_fold's
// px_valid), LATENCY = max(LAT_QM, LAT_NS) + TREE_LEVELS (LAT_QM `LAT_QM: `LAT_QUADRIC_MAC(_FPGA, _SERIAL);
// LAT_NS the terms': `LAT_NOISE_TERM(_FPGA), + `LAT_FC_SCALE with FC, folded +
// `LAT_NOISE_FOLD(_FPGA); TREE_LEVELS tw_tree_levels(leaves, `SUM_TREE_ARITY)); the caller
// passes it, elaboration fails on another. c_out and c_valid: with the noise gradient the same
// as f's; without it LAT_QM (the quadric's). wv_out `LAT_FC_WEIGHT after in_valid (valid:
// in_valid delayed by the caller). Throughput: one pixel per enabled clock (QUADRIC_CLOCKS 2:
// every other; 6: one in six). Parameters (q_coef, k_used, a, T, o, filter_en, n_log2) static during a pass.
// Reset: synchronous, active high, clears the valid bits.

`default_nettype none

`include "tex_latency.vh"

module texture_sum #(
    parameter QUADRIC        = 0,   // 0 full (10 coefficients), 1 diagonal (B = C = F = 0)
    parameter QUADRIC_CLOCKS = 1,   // 2: the quadric MAC on half its multipliers, two clocks a pixel; 6: on one, six
    parameter NOISE_TERMS    = 8,   // K noise terms, 0..8
    parameter NOISE_UNITS    = 8,   // U units (U < K: folded, the caller's noise_fold sum is one leaf)
    parameter BLEND          = 1,   // 0 linear, 1 cubic
    parameter TRANSFORM      = 0,   // 0 affine, 1 pow2
    parameter AMPLITUDE      = 0,   // 0 any, 1 pow2
    parameter NOISE_GRADIENT = 1,   // 1: c includes the noise terms' gradients
    parameter FC             = 0,   // 1: frequency clamping (filters sat_fc, sat2_fc; unfolded terms only)
    parameter FPGA_REGS      = 0,   // 1: the blocks' FPGA register stages (rtl/tex_latency.vh)
    parameter LATENCY        = 10,  // f's latency: must be max(LAT_QM, LAT_NS) + TREE_LEVELS (above)
    parameter S_W            = 24,  // s{S_W}.{S_FRAC}
    parameter S_FRAC         = 16,
    parameter Q_W            = 24,  // quadric coefficients s{Q_W}.{Q_FRAC}
    parameter Q_FRAC         = 16,
    parameter J_W            = 12,  // Jacobian mantissas s{J_W}.0 (FC)
    parameter JE_W           = 8,   // shared Jacobian exponent s{JE_W}.0 (FC)
    parameter T_W            = 17,  // transform entries s{T_W}.{T_FRAC}
    parameter T_FRAC         = 10,
    parameter A_W            = 16,  // amplitudes s{A_W}.{A_FRAC}
    parameter A_FRAC         = 12,
    parameter P_FRAC         = 12,  // noise-space fraction bits
    parameter HASH_BITS      = 8,   // lattice period 2^HASH_BITS
    parameter N_FRAC         = 12,  // noise value / gradient fraction bits
    parameter F_FRAC         = 16,  // f fraction bits
    parameter C_FRAC         = 12,  // grad f fraction bits
    parameter W_CAP_LOG2     = 16,  // FC: wv saturates at 2^W_CAP_LOG2 entries
    parameter N_LOG2_MAX     = 8,   // FC: colour tables of up to 2^N_LOG2_MAX entries
    parameter FC_LOG_FRAC    = 5,   // FC: footprint log2 in 2^-FC_LOG_FRAC octaves
    parameter FC_KNEE        = 112, // FC: a term is gone at footprint 2^(FC_KNEE 2^-FC_LOG_FRAC)
    parameter FC_FADE_LOG2   = 2,   // FC: the fade spans 2^FC_FADE_LOG2 octaves
    parameter FC_KS          = 328, // FC: sigma sqrt(12) of the lattice noise in u.FC_KSF
    parameter FC_KSF         = 8,
    parameter T_EXP_W        = 0,   // T_k's per-term exponent te_k above its mantissas in t_all (0: none)
    parameter A_EXP_W        = 0,   // a_k's per-term exponent ae_k above its mantissa in a_all (0: none)
    parameter [HASH_BITS*(1<<HASH_BITS)-1:0] PERM = {HASH_BITS*(1<<HASH_BITS){1'b0}}  // lattice permutation
) (clk, rst, ce, in_valid, s_in, jm_in, je_in, q_coef, k_used, a_all, t_all, o_all, filter_en, n_log2,
   fold_valid, fold_f, fold_c, out_valid, f_out, c_valid, c_out, wv_out);

`include "tex_widths.vh"

localparam K      = NOISE_TERMS;
localparam KV     = (K > 0) ? K : 1;                                           // K = 0: unused vectors
localparam FOLD   = (K > 0) && (NOISE_UNITS < K);
localparam NLEAF  = FOLD ? 1 : K;                                              // noise leaves of the trees
localparam KU_W   = tw_bits_unsigned(K);
localparam NG     = NOISE_GRADIENT;
localparam O_W    = HASH_BITS + P_FRAC;
localparam FC_AF  = FC_LOG_FRAC + FC_FADE_LOG2;                                // alpha u1.FC_AF
localparam NL_W   = tw_bits_unsigned(N_LOG2_MAX);
localparam W_W    = W_CAP_LOG2 + F_FRAC + 1;
localparam QF_W   = tw_qf_w(QUADRIC, S_W, S_FRAC, Q_W, Q_FRAC, F_FRAC);        // quadric value
localparam TE_MAX = (1 << T_EXP_W) - 1;                                        // the largest exponents
localparam AE_MAX = (1 << A_EXP_W) - 1;
localparam TS_W   = 9*T_W + T_EXP_W;                                           // a term of t_all: {te, T}
localparam AS_W   = A_W + A_EXP_W;                                             // a term of a_all: {ae, a}
localparam F_W    = tw_f_w_e(QUADRIC, S_W, S_FRAC, Q_W, Q_FRAC, F_FRAC, K, A_W, A_FRAC, N_FRAC, AE_MAX);
localparam C_W    = tw_c_w_e(QUADRIC, S_W, S_FRAC, Q_W, Q_FRAC, C_FRAC, K, NOISE_GRADIENT, BLEND, TRANSFORM, T_W,
                             T_FRAC, N_FRAC, A_W, A_FRAC, TE_MAX, AE_MAX);
localparam LAT_QM = `LAT_QM(FPGA_REGS, QUADRIC, QUADRIC_CLOCKS);  // quadric_mac's (rtl/tex_latency.vh)
localparam LAT_NT = FPGA_REGS ? `LAT_NOISE_TERM_FPGA : `LAT_NOISE_TERM;
localparam LAT_NF = FPGA_REGS ? `LAT_NOISE_FOLD_FPGA : `LAT_NOISE_FOLD;
localparam LAT_NS = FOLD ? LAT_NT + LAT_NF : LAT_NT + (FC ? `LAT_FC_SCALE : 0);  // the noise leaves' own
localparam LAT_FRONT   = (K > 0 && LAT_NS > LAT_QM) ? LAT_NS : LAT_QM;         // q and the terms meet
localparam TREE_LEVELS = tw_tree_levels(NLEAF + 1, `SUM_TREE_ARITY);
localparam DLY_Q  = NG ? LAT_FRONT - LAT_QM : 0;                               // quadric input (s) wait
localparam DLY_QO = NG ? 0 : LAT_FRONT - LAT_QM;                               // quadric q output wait

input  wire                    clk;
input  wire                    rst;
input  wire                    ce;
input  wire                    in_valid;
input  wire [3*S_W-1:0]        s_in;
/* verilator lint_off UNUSEDSIGNAL */  // !FC: the footprint is not read; K = 0 or folded: no terms here
input  wire [6*J_W-1:0]        jm_in;      // Jm[k][col] at element 2*k+col
input  wire [JE_W-1:0]         je_in;
input  wire [10*Q_W-1:0]       q_coef;     // coefficient i at [i*Q_W +: Q_W]
input  wire [KU_W-1:0]         k_used;     // terms the texture uses: 0..k_used-1
input  wire [KV*AS_W-1:0]      a_all;      // {ae_k, a_k} at [k*AS_W +: AS_W]
input  wire [KV*TS_W-1:0]      t_all;      // {te_k, T_k} at [k*TS_W +: TS_W], T_k[j][m] at (3*j + m)*T_W in it
input  wire [KV*3*O_W-1:0]     o_all;      // o_k[j] at [(3*k + j)*O_W +: O_W]
input  wire                    filter_en;
input  wire [NL_W-1:0]         n_log2;
input  wire                    fold_valid; // folded: noise_fold's sum, LAT_NS after in_valid
input  wire [F_W-1:0]          fold_f;
input  wire [3*C_W-1:0]        fold_c;
/* verilator lint_on UNUSEDSIGNAL */
output wire                    out_valid;
output wire [F_W-1:0]          f_out;
output wire                    c_valid;
output wire [3*C_W-1:0]        c_out;
output wire [W_W-1:0]          wv_out;

// elaboration fails (unknown module) when the caller's latency is not this block's
generate
    if (LATENCY != LAT_FRONT + TREE_LEVELS) begin : g_bad_latency
        texture_sum_latency_must_be_its_blocks u_error ();
    end
endgenerate

// ---------------------------------------------------------------------------
// sat_fc: the terms' fades (fc_weight, `LAT_FC_WEIGHT stages), alpha delayed to the terms' outputs

/* verilator lint_off UNUSEDSIGNAL */  // no sat_fc: constant, not read
wire [KV*(FC_AF+1)-1:0] alpha_d;
/* verilator lint_on UNUSEDSIGNAL */
generate
    if (FC) begin : g_fcw
        if (`LAT_FC_WEIGHT > LAT_NT) begin : g_bad_fc_latency
            fc_weight_latency_exceeds_the_noise_term u_bad ();  // elaboration error
        end
        wire [K*(FC_AF+1)-1:0] alpha;
        /* verilator lint_off UNUSEDSIGNAL */  // valid: the shared pipeline valid is used instead
        wire                   fcw_valid;
        /* verilator lint_on UNUSEDSIGNAL */
        fc_weight #(
            .NOISE_TERMS(K), .J_W(J_W), .JE_W(JE_W), .T_W(T_W), .T_FRAC(T_FRAC), .A_W(A_W), .A_FRAC(A_FRAC),
            .F_FRAC(F_FRAC), .W_CAP_LOG2(W_CAP_LOG2), .N_LOG2_MAX(N_LOG2_MAX), .FC_LOG_FRAC(FC_LOG_FRAC),
            .FC_KNEE(FC_KNEE), .FC_FADE_LOG2(FC_FADE_LOG2), .FC_KS(FC_KS), .FC_KSF(FC_KSF), .T_EXP_W(T_EXP_W),
            .A_EXP_W(A_EXP_W)
        ) u_fc_weight (
            .clk(clk), .rst(rst), .ce(ce),
            .in_valid(in_valid), .jm_in(jm_in), .je_in(je_in),
            .a_all(a_all), .t_all(t_all), .k_used(k_used), .filter_en(filter_en), .n_log2(n_log2),
            .out_valid(fcw_valid), .alpha_out(alpha), .wv_out(wv_out)
        );
        delay_line #(.W(K*(FC_AF+1)), .N(LAT_NT - `LAT_FC_WEIGHT)) u_dly_alpha (.clk(clk), .rst(rst), .ce(ce),
                                                                                .d_in(alpha), .d_out(alpha_d));
    end else begin : g_nofcw
        assign alpha_d = {KV*(FC_AF+1){1'b0}};
        assign wv_out  = {W_W{1'b0}};
    end
endgenerate

// ---------------------------------------------------------------------------
// The quadric (its input or its value waiting for the terms) and the leaves

// what quadric_mac reads of the coefficients: a diagonal quadric's B, C, F are 0
reg [10*Q_W-1:0] q_use;
always @* begin
    q_use = q_coef;
    if (QUADRIC != 0) begin
        q_use[1*Q_W +: Q_W] = {Q_W{1'b0}};
        q_use[2*Q_W +: Q_W] = {Q_W{1'b0}};
        q_use[5*Q_W +: Q_W] = {Q_W{1'b0}};
    end
end

wire [3*S_W-1:0] qs_s;
wire             qs_valid;
delay_line #(.W(3*S_W), .N(DLY_Q))           u_dly_qs (.clk(clk), .rst(rst), .ce(ce), .d_in(s_in), .d_out(qs_s));
delay_line #(.W(1), .N(DLY_Q), .CLEAR(1))    u_dly_qv (.clk(clk), .rst(rst), .ce(ce), .d_in(in_valid), .d_out(qs_valid));

wire [QF_W-1:0]  qm_q;
wire [3*C_W-1:0] qm_cq;
wire             qm_valid;
quadric_mac #(
    .DIAG(QUADRIC), .CLOCKS(QUADRIC_CLOCKS), .S_W(S_W), .S_FRAC(S_FRAC), .Q_W(Q_W), .Q_FRAC(Q_FRAC),
    .F_FRAC(F_FRAC), .C_FRAC(C_FRAC), .C_W(C_W), .FPGA_REGS(FPGA_REGS)
) u_quadric_mac (
    .clk(clk), .rst(rst), .ce(ce),
    .in_valid(qs_valid), .s_in(qs_s), .q_coef(q_use),
    .out_valid(qm_valid), .q_out(qm_q), .cq_out(qm_cq)
);

wire [QF_W-1:0] qo_q;
wire            qo_valid;
delay_line #(.W(QF_W), .N(DLY_QO))        u_dly_qo (.clk(clk), .rst(rst), .ce(ce), .d_in(qm_q), .d_out(qo_q));
delay_line #(.W(1), .N(DLY_QO), .CLEAR(1)) u_dly_qov (.clk(clk), .rst(rst), .ce(ce), .d_in(qm_valid),
                                                       .d_out(qo_valid));

// leaf i at [i*F_W +: F_W], [i*3*C_W +: 3*C_W]: 0 the quadric's, 1 + k term k's (folded: the sum)
wire                       leaves_valid;
wire [(NLEAF+1)*F_W-1:0]   f_leaves;
/* verilator lint_off UNUSEDSIGNAL */  // !NG: no gradient tree
wire [(NLEAF+1)*3*C_W-1:0] c_leaves;
/* verilator lint_on UNUSEDSIGNAL */
noise_leaves #(
    .QUADRIC(QUADRIC), .NOISE_TERMS(K), .NOISE_UNITS(NOISE_UNITS), .FC(FC), .FC_LOG_FRAC(FC_LOG_FRAC),
    .FC_FADE_LOG2(FC_FADE_LOG2), .LATENCY(LAT_FRONT), .S_W(S_W), .S_FRAC(S_FRAC), .Q_W(Q_W), .Q_FRAC(Q_FRAC),
    .T_W(T_W), .T_FRAC(T_FRAC), .A_W(A_W), .A_FRAC(A_FRAC), .P_FRAC(P_FRAC), .HASH_BITS(HASH_BITS),
    .N_FRAC(N_FRAC), .F_FRAC(F_FRAC), .C_FRAC(C_FRAC), .TRANSFORM(TRANSFORM), .BLEND(BLEND),
    .AMPLITUDE(AMPLITUDE), .NOISE_GRADIENT(NOISE_GRADIENT), .FPGA_REGS(FPGA_REGS), .T_EXP_W(T_EXP_W),
    .A_EXP_W(A_EXP_W), .PERM(PERM)
) u_noise_leaves (
    .clk(clk), .rst(rst), .ce(ce),
    .in_valid(in_valid), .s_in(s_in),
    .k_used(k_used), .a_all(a_all), .t_all(t_all), .o_all(o_all), .alpha(alpha_d),
    .fold_valid(fold_valid), .fold_f(fold_f), .fold_c(fold_c),
    .q_valid(qo_valid), .q_in(qo_q), .cq_in(qm_cq),
    .out_valid(leaves_valid), .f_leaves(f_leaves), .c_leaves(c_leaves)
);

// ---------------------------------------------------------------------------
// The adder trees (sum_tree, TREE_LEVELS register levels): sums modulo 2^F_W / 2^C_W of
// sign-extended operands, i.e. exact. !NG: no c tree, c is the quadric's gradient.

sum_tree #(.N(NLEAF + 1), .W(F_W), .LANES(1), .LATENCY(TREE_LEVELS)) u_f_tree (
    .clk(clk), .rst(rst), .ce(ce),
    .in_valid(leaves_valid), .leaves(f_leaves),
    .out_valid(out_valid), .sum_out(f_out)
);

generate
    if (NG) begin : g_c_tree
        sum_tree #(.N(NLEAF + 1), .W(C_W), .LANES(3), .LATENCY(TREE_LEVELS)) u_c_tree (
            .clk(clk), .rst(rst), .ce(ce),
            .in_valid(leaves_valid), .leaves(c_leaves),
            .out_valid(c_valid), .sum_out(c_out)
        );
    end else begin : g_c_quadric
        assign c_valid = qm_valid;
        assign c_out   = qm_cq;
    end
endgenerate

endmodule

`default_nettype wire
