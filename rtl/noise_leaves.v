// noise_leaves: the leaves of texture_pipeline's adder trees (sum_tree): the quadric's value
// and gradient and the noise terms', sign-extended to the exact-sum widths.
//
// Unfolded (NOISE_UNITS >= NOISE_TERMS): K noise_term instances on s, term k with amplitude
// a_k, 0 past the texture's k_used (it then contributes exactly 0, as noise_fold skips it);
// with FC (filter sat_fc) each term faded by its alpha (fc_scale). Folded: noise_fold's sum
// (fold_*) is the one noise leaf. Each noise leaf is delayed to LATENCY; leaf 0 is the
// quadric's q and grad q (q_in, cq_in), leaf 1 + k term k. model/hw/golden.py noise_leaves
// is the twin.
//
// Formats (rtl/tex_widths.vh): s_in 3 x s{S_W}.{S_FRAC}; a, T, o as noise_term's (term k of
// a_all {ae_k, a_k} at [k*AS_W +: AS_W], of t_all {te_k, T_k} at [k*TS_W +: TS_W]; the
// exponents only with T_EXP_W, A_EXP_W > 0, tex_regs' layout); alpha K x
// u1.{FC_AF}, FC_AF = FC_LOG_FRAC + FC_FADE_LOG2; q_in s{QF_W}.{F_FRAC}, cq_in 3 x
// s{C_W}.{C_FRAC}; fold_f s{F_W}.{F_FRAC}, fold_c 3 x s{C_W}.{C_FRAC}. Leaf i at
// f_leaves[i*F_W +: F_W] (s{F_W}.{F_FRAC}) and c_leaves[i*3*C_W +: 3*C_W] (3 x
// s{C_W}.{C_FRAC}; NOISE_GRADIENT 0: 0, the tree carries no gradient).
// Latency: the noise leaves LATENCY enabled clocks after in_valid (unfolded: after the
// pixel's s; folded: after noise_fold's px_valid, its sum arriving LAT_NOISE_TERM +
// LAT_NOISE_FOLD later); LATENCY >= that of the terms (`LAT_NOISE_TERM(_FPGA), plus
// `LAT_FC_SCALE with FC; folded: plus `LAT_NOISE_FOLD(_FPGA)), elaboration fails on less
// (K = 0: no noise leaf, LATENCY not used).
// q_in, cq_in, q_valid and the sign extensions are combinational (the caller brings q at
// the same clock). out_valid = q_valid and every noise leaf's valid. Throughput: one pixel
// per enabled clock. Reset: synchronous, active high, clears the valid bits.

`default_nettype none

`include "tex_latency.vh"

module noise_leaves #(
    parameter QUADRIC        = 0,   // 0 full, 1 diagonal quadric (its value's width)
    parameter NOISE_TERMS    = 8,   // K terms
    parameter NOISE_UNITS    = 8,   // U units (U < K: folded, noise_fold's sum is the one leaf)
    parameter FC             = 0,   // 1: each term faded by its alpha (filter sat_fc, unfolded only)
    parameter FC_LOG_FRAC    = 5,   // sat_fc: alpha u1.(FC_LOG_FRAC + FC_FADE_LOG2)
    parameter FC_FADE_LOG2   = 2,
    parameter LATENCY        = 8,   // the noise leaves' latency (>= the terms', above)
    parameter S_W            = 24,  // s{S_W}.{S_FRAC}
    parameter S_FRAC         = 16,
    parameter Q_W            = 24,  // quadric coefficients s{Q_W}.{Q_FRAC} (q's width)
    parameter Q_FRAC         = 16,
    parameter T_W            = 17,  // transform entries s{T_W}.{T_FRAC}
    parameter T_FRAC         = 10,
    parameter A_W            = 16,  // amplitudes s{A_W}.{A_FRAC}
    parameter A_FRAC         = 12,
    parameter P_FRAC         = 12,  // noise-space fraction bits
    parameter HASH_BITS      = 8,   // lattice period 2^HASH_BITS
    parameter N_FRAC         = 12,  // noise value / gradient fraction bits
    parameter F_FRAC         = 16,  // f fraction bits
    parameter C_FRAC         = 12,  // grad f fraction bits
    parameter TRANSFORM      = 0,   // 0 affine, 1 pow2
    parameter BLEND          = 1,   // 0 linear, 1 cubic
    parameter AMPLITUDE      = 0,   // 0 any, 1 pow2
    parameter NOISE_GRADIENT = 1,   // 1: the terms' gradients are leaves of the c tree
    parameter FPGA_REGS      = 0,   // 1: the terms' FPGA register stages
    parameter T_EXP_W        = 0,   // T_k's per-term exponent te_k above its mantissas in t_all (0: none)
    parameter A_EXP_W        = 0,   // a_k's per-term exponent ae_k above its mantissa in a_all (0: none)
    parameter [HASH_BITS*(1<<HASH_BITS)-1:0] PERM = {HASH_BITS*(1<<HASH_BITS){1'b0}}  // lattice permutation
) (clk, rst, ce, in_valid, s_in, k_used, a_all, t_all, o_all, alpha, fold_valid, fold_f, fold_c,
   q_valid, q_in, cq_in, out_valid, f_leaves, c_leaves);

`include "tex_widths.vh"

localparam K     = NOISE_TERMS;
localparam KV    = (K > 0) ? K : 1;                                            // K = 0: unused vectors
localparam FOLD  = (K > 0) && (NOISE_UNITS < K);
localparam NLEAF = FOLD ? 1 : K;                                               // noise leaves
localparam KU_W  = tw_bits_unsigned(K);
localparam CUBIC = BLEND;
localparam POW2T = TRANSFORM;
localparam NG    = NOISE_GRADIENT;
localparam O_W   = HASH_BITS + P_FRAC;
localparam FC_AF = FC_LOG_FRAC + FC_FADE_LOG2;
localparam QF_W  = tw_qf_w(QUADRIC, S_W, S_FRAC, Q_W, Q_FRAC, F_FRAC);
localparam TE_MAX = (1 << T_EXP_W) - 1;                                       // the largest exponents
localparam AE_MAX = (1 << A_EXP_W) - 1;
localparam TS_W  = 9*T_W + T_EXP_W;                                            // a term of t_all: {te, T}
localparam AS_W  = A_W + A_EXP_W;                                              // a term of a_all: {ae, a}
localparam AN_W  = tw_an_w_e(A_W, A_FRAC, N_FRAC, F_FRAC, AE_MAX);
localparam AG_W  = tw_ag_w_e(CUBIC, POW2T, T_W, T_FRAC, N_FRAC, C_FRAC, A_W, A_FRAC, TE_MAX, AE_MAX);
localparam F_W   = tw_f_w_e(QUADRIC, S_W, S_FRAC, Q_W, Q_FRAC, F_FRAC, K, A_W, A_FRAC, N_FRAC, AE_MAX);
localparam C_W   = tw_c_w_e(QUADRIC, S_W, S_FRAC, Q_W, Q_FRAC, C_FRAC, K, NOISE_GRADIENT, CUBIC, POW2T, T_W,
                            T_FRAC, N_FRAC, A_W, A_FRAC, TE_MAX, AE_MAX);
localparam LAT_NT = FPGA_REGS ? `LAT_NOISE_TERM_FPGA : `LAT_NOISE_TERM;
localparam LAT_NF = FPGA_REGS ? `LAT_NOISE_FOLD_FPGA : `LAT_NOISE_FOLD;
localparam LAT_NS = FOLD ? LAT_NT + LAT_NF : LAT_NT + (FC ? `LAT_FC_SCALE : 0);  // the terms' own latency
localparam DLY_N  = LATENCY - LAT_NS;                                          // their wait for LATENCY
localparam LN_W   = FOLD ? F_W : AN_W;                                         // a noise leaf's value
localparam LG_W   = FOLD ? C_W : AG_W;                                         // its gradient components
localparam FX_Q   = F_W - QF_W;                                                // sign bits added to q
localparam FX_N   = F_W - LN_W;                                                // to a noise leaf
localparam CX_N   = C_W - LG_W;                                                // to each gradient component

input  wire                    clk;
input  wire                    rst;
input  wire                    ce;
/* verilator lint_off UNUSEDSIGNAL */  // folded or K = 0: the terms' inputs are not read
input  wire                    in_valid;
input  wire [3*S_W-1:0]        s_in;
input  wire [KU_W-1:0]         k_used;     // terms the texture uses: 0..k_used-1
input  wire [KV*AS_W-1:0]      a_all;      // {ae_k, a_k} at [k*AS_W +: AS_W]
input  wire [KV*TS_W-1:0]      t_all;      // {te_k, T_k} at [k*TS_W +: TS_W], T_k[j][m] at (3*j + m)*T_W in it
input  wire [KV*3*O_W-1:0]     o_all;      // o_k[j] at [(3*k + j)*O_W +: O_W]
input  wire [KV*(FC_AF+1)-1:0] alpha;      // sat_fc: alpha_k at [k*(FC_AF+1) +: FC_AF+1], at the terms' outputs
input  wire                    fold_valid; // folded: noise_fold's sum
input  wire [F_W-1:0]          fold_f;
input  wire [3*C_W-1:0]        fold_c;
input  wire [3*C_W-1:0]        cq_in;      // grad q (NOISE_GRADIENT 0: not a leaf)
/* verilator lint_on UNUSEDSIGNAL */
input  wire                    q_valid;
input  wire [QF_W-1:0]         q_in;
output wire                    out_valid;
output wire [(NLEAF+1)*F_W-1:0]   f_leaves;
output wire [(NLEAF+1)*3*C_W-1:0] c_leaves;

generate
    if (NLEAF > 0 && DLY_N < 0) begin : g_bad_latency
        noise_leaves_latency_below_the_terms u_error ();  // elaboration error
    end
endgenerate

reg [(NLEAF+1)*F_W-1:0]   f_all;   // leaf i at [i*F_W +: F_W] (each slice written by its own block)
/* verilator lint_off UNDRIVEN */  // !NG: no gradient leaves (c_leaves 0)
/* verilator lint_off UNUSEDSIGNAL */
reg [(NLEAF+1)*3*C_W-1:0] c_all;
/* verilator lint_on UNUSEDSIGNAL */
/* verilator lint_on UNDRIVEN */

genvar gi;
generate
    for (gi = 0; gi < NLEAF; gi = gi + 1) begin : g_term
        wire [LN_W-1:0]   an;
        wire [3*LG_W-1:0] ag;
        wire              nt_valid;
        if (FOLD) begin : g_folded
            assign an       = fold_f;
            assign ag       = fold_c;
            assign nt_valid = fold_valid;
        end else begin : g_unit
            // a term past the texture's k_used contributes nothing (a = 0), as noise_fold skips it
            wire [AS_W-1:0] a_k = (gi < k_used) ? a_all[gi*AS_W +: AS_W] : {AS_W{1'b0}};
            wire [LN_W-1:0]   nt_an;
            wire [3*LG_W-1:0] nt_ag;
            wire              nt_out_valid;
            noise_term #(
                .S_W(S_W), .S_FRAC(S_FRAC), .T_W(T_W), .T_FRAC(T_FRAC), .A_W(A_W), .A_FRAC(A_FRAC),
                .P_FRAC(P_FRAC), .HASH_BITS(HASH_BITS), .N_FRAC(N_FRAC), .F_FRAC(F_FRAC), .C_FRAC(C_FRAC),
                .TRANSFORM(TRANSFORM), .BLEND(BLEND), .AMPLITUDE(AMPLITUDE), .NOISE_GRADIENT(NOISE_GRADIENT),
                .FPGA_REGS(FPGA_REGS), .T_EXP_W(T_EXP_W), .A_EXP_W(A_EXP_W), .PERM(PERM)
            ) u_noise_term (
                .clk(clk), .rst(rst), .ce(ce),
                .in_valid(in_valid),
                .s_in(s_in),
                .a_in(a_k),
                .t_in(t_all[gi*TS_W +: TS_W]),
                .o_in(o_all[gi*3*O_W +: 3*O_W]),
                .out_valid(nt_out_valid),
                .an_out(nt_an),
                .ag_out(nt_ag)
            );
            if (FC) begin : g_fc
                // sat_fc: the term faded by its alpha (fc_weight's, delayed to the term's output)
                fc_scale #(.AN_W(LN_W), .AG_W(LG_W), .AF(FC_AF), .NOISE_GRADIENT(NOISE_GRADIENT)) u_fc_scale (
                    .clk(clk), .rst(rst), .ce(ce),
                    .in_valid(nt_out_valid),
                    .alpha(alpha[gi*(FC_AF+1) +: FC_AF+1]),
                    .an_in(nt_an), .ag_in(nt_ag),
                    .out_valid(nt_valid), .an_out(an), .ag_out(ag)
                );
            end else begin : g_nofc
                assign an       = nt_an;
                assign ag       = nt_ag;
                assign nt_valid = nt_out_valid;
            end
        end
        // delayed to LATENCY (normally DLY_N = 0)
        wire [LN_W-1:0]   an_d;
        wire [3*LG_W-1:0] ag_d;
        wire              v_d;
        delay_line #(.W(LN_W), .N(DLY_N))           u_dly_an (.clk(clk), .rst(rst), .ce(ce), .d_in(an), .d_out(an_d));
        delay_line #(.W(3*LG_W), .N(DLY_N))         u_dly_ag (.clk(clk), .rst(rst), .ce(ce), .d_in(ag), .d_out(ag_d));
        delay_line #(.W(1), .N(DLY_N), .CLEAR(1))   u_dly_v  (.clk(clk), .rst(rst), .ce(ce), .d_in(nt_valid),
                                                              .d_out(v_d));
        wire v_all;  // this term's valid and all before it
        if (gi == 0) begin : g_v0
            assign v_all = v_d & q_valid;
        end else begin : g_vn
            assign v_all = v_d & g_term[gi-1].v_all;
        end
    end

    if (NLEAF == 0) begin : g_v_q
        assign out_valid = q_valid;
    end else begin : g_v_terms
        assign out_valid = g_term[NLEAF-1].v_all;
    end

    // sign extension in processes, each writing its leaf's slice of one variable (f_all,
    // c_all: a net driven by slices from several places would be re-resolved whole, bit by
    // bit, on every change of any slice in event-driven simulation; docs/simulation.md)
    for (gi = 0; gi <= NLEAF; gi = gi + 1) begin : g_leaf
        if (gi == 0) begin : g_q
            if (FX_Q > 0) begin : g_fx
                always @* f_all[0 +: F_W] = {{FX_Q{q_in[QF_W-1]}}, q_in};
            end else begin : g_f
                always @* f_all[0 +: F_W] = q_in;
            end
            // !NG: the tree carries no gradient (the quadric's goes to filter_width; c_leaves 0)
            if (NG) begin : g_c
                always @* c_all[0 +: 3*C_W] = cq_in;
            end
        end else begin : g_n
            wire [LN_W-1:0]   an = g_term[gi-1].an_d;
            /* verilator lint_off UNUSEDSIGNAL */  // !NG: the terms' ag outputs are 0, not summed
            wire [3*LG_W-1:0] ag = g_term[gi-1].ag_d;
            /* verilator lint_on UNUSEDSIGNAL */
            if (FX_N > 0) begin : g_fx
                always @* f_all[gi*F_W +: F_W] = {{FX_N{an[LN_W-1]}}, an};
            end else begin : g_f
                always @* f_all[gi*F_W +: F_W] = an;
            end
            if (NG && CX_N > 0) begin : g_cx
                always @* c_all[gi*3*C_W +: 3*C_W] = {{CX_N{ag[3*LG_W-1]}}, ag[2*LG_W +: LG_W],
                                                      {CX_N{ag[2*LG_W-1]}}, ag[LG_W +: LG_W],
                                                      {CX_N{ag[LG_W-1]}}, ag[0 +: LG_W]};
            end else if (NG) begin : g_c
                always @* c_all[gi*3*C_W +: 3*C_W] = ag;
            end
        end
    end
    if (NG) begin : g_cl
        assign c_leaves = c_all;
    end else begin : g_cl0
        assign c_leaves = {(NLEAF+1)*3*C_W{1'b0}};
    end
endgenerate
assign f_leaves = f_all;

endmodule

`default_nettype wire
