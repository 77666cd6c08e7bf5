// noise_term: one noise term a n(T s + o) and its texture-space gradient a (dn/dp) T.
//
// The bit-exact twin of model/hw/golden.py noise_term(cfg, a, T, o, s, te, ae) (with
// noise_hash, noise_blend and lerp), for one vector per enabled clock:
//   p_j  = ((sum_k T_jk s_k) >> (TS_SHIFT - te)) + o_j  mod 2^P_W     (lattice cell . fraction)
//   v    = lattice values at the 8 cell corners (noise_hash), w/dw = blend weights (noise_blend)
//   n    = trilinear blend of v with the weights, x first, then y, then z (lerp)
//   an   = (a n) >> (AN_SHIFT - ae)
//   g_x  = (lerp(lerp(dx00, dx10, wy), lerp(dx01, dx11, wy), wz) dw_x) >> P_FRAC, dx = v1jk - v0jk
//   g_y  = (lerp(e10 - e00, e11 - e01, wz) dw_y) >> P_FRAC, g_z = ((fz1 - fz0) dw_z) >> P_FRAC
//   h_k  = (sum_j g_j T_jk) >> (H_SHIFT - te),   ag_k = (a h_k) >> (A_FRAC - ae)
// Every ">>" is a floor (arithmetic shift right of a signed word); a negative shift
// count is a left shift. te = ae = 0 without exponents (T_EXP_W = A_EXP_W = 0).
//
// Block floating point ([t_exp_w] T_EXP_W, [a_exp_w] A_EXP_W > 0; docs/numerics.md "Block
// floating point"): T and a are the term's mantissas M, A with one exponent each, T = M
// 2^(te - T_FRAC), a = A 2^(ae - A_FRAC); te rides in t_in above the nine entries and ae in
// a_in above the mantissa (so the ports are as they were at 0). Only the floor shifts move:
// noise_xform's TS_SHIFT - te (stage 2), noise_grad's H_SHIFT - te (stage 7) and A_FRAC - ae
// (stage 8), and a n's AN_SHIFT - ae here (stage 8), each a right shift (model/hw/config.py
// checks TS_SHIFT, H_SHIFT >= 2^T_EXP_W - 1 and AN_SHIFT, A_FRAC >= 2^A_EXP_W - 1; the
// elaboration too); the multipliers keep their T_W and A_W bit words. te needs an affine T
// and ae amplitude any.
//
// Formats (the parameters below; derived widths from rtl/tex_widths.vh):
//   s_in   3 x s{S_W}.{S_FRAC}, {r, t, s} (s at the LSBs)
//   a_in   s{A_W}.{A_FRAC}; A_EXP_W > 0: {ae u{A_EXP_W}, A s{A_W}} (A_W + A_EXP_W bits)
//   t_in   9 x s{T_W}.{T_FRAC}, T[j][k] at element 3*j + k; T_EXP_W > 0: {te u{T_EXP_W}, the
//          nine mantissas} (9 T_W + T_EXP_W bits)
//   o_in   3 x u{O_W}.{P_FRAC} (O_W = P_W = HASH_BITS + P_FRAC: a phase mod the lattice period)
//   an_out s{AN_W}.{F_FRAC};  ag_out 3 x s{AG_W}.{C_FRAC} (all 0 when NOISE_GRADIENT = 0);
//          AN_W, AG_W (and H_W) for the largest exponents (rtl/tex_widths.vh tw_*_w_e)
// Internal: p u{P_W}.{P_FRAC}; v, e, fz, n s{N_W}.{N_FRAC}; differences s{N_W+1}.{N_FRAC};
//   w, dw s{BLEND_W}.{P_FRAC} in [0, 1.5]; g s{GN_W}.{N_FRAC}; h s{H_W}.{C_FRAC + A_FRAC}.
// Blocks: p_j is noise_xform, once per axis (stages 1, 2); the gradient (g, h, ag) is
// noise_grad beside the value path (stages 4..8); noise_hash, noise_blend, lerp as below;
// the parameters as each stage sees them (pow2 decoders, PARAM_PIPE delays) noise_params.
//
// Transform (TRANSFORM): affine (0) uses multipliers for T s and g T. pow2 (1): T is
// diagonal with entries 0 or 2^e: T_jj s_j and g_j T_jj are shifts by e, decoded once per
// term by noise_params into tc = {T_jj == 0, e} per axis; no multipliers.
//
// Amplitude (AMPLITUDE): any (0) uses multipliers for a n and a h. pow2 (1): a is
// 0 or +-2^e, e in 0..A_W-2 for a > 0 and 0..A_W-1 for a < 0 (-2^(A_W-1), the format's
// most negative value, is legal), decoded once per term by noise_params into ac = {zero,
// neg, e} (1 + 1 + EA_W bits, EA_W = clog2(A_W)). Stage 8 then forms sign(a) n as
// s{N_W+1} and sign(a) h_k as s{H_W+1} (a conditional negation, 0 when a = 0; one extra
// bit so that even the most negative word negates exactly), shifts it left by e in the
// A_W + N_W (A_W + H_W) bit product word (|a n| <= 2^(A_W-1) 2^(N_W-1) < 2^(A_W+N_W-1):
// no overflow) and takes the same floor shift (>> AN_SHIFT, >> A_FRAC) as the multiplier path: the products
// are exactly a n and a h_k, so the results equal the golden model's for every n, h
// and legal a. No multipliers.
//
// Pipeline (LATENCY = `LAT_NOISE_TERM = 8 register stages, one vector per enabled clock):
//   1  transform products T_jk s_k (pow2: shifts)                    (noise_xform)
//   2  p = sum + o -> cell ip, fraction fp                            (noise_xform)
//   3  noise_hash (3 ROM levels) -> 8 corner values; noise_blend -> w, dw
//   4  x lerps -> e (4); noise_grad: dx and their y lerps (2)
//   5  y lerps -> fz (2); noise_grad: z lerps of the x and y differences
//   6  z lerp -> n; noise_grad: g = (. dw) >> P_FRAC (cubic; linear: dw = 1, a wire)
//   7  n delayed; noise_grad: h = (g T) >> H_SHIFT (pow2: shifts)
//   8  an = (a n) >> AN_SHIFT, noise_grad: ag = (a h) >> A_FRAC (pow2: shifts; output registers)
//      (with exponents: >> (AN_SHIFT - ae), >> (A_FRAC - ae); stages 2 and 7 >> (. - te))
// FPGA_REGS = 1 ([fpga_regs]; `LAT_NOISE_TERM_FPGA = 16 stages): eight more: stage 3 in
// three (P = 2: noise_hash one ROM level a clock, beside it noise_blend's f2 and f3 registered
// after its multipliers), and in stages 4, 5, 6 every lerp in three (LP = 2: b - a registered
// before the multiplier, the scaled step before the adder; the weights, slopes and the
// gradient's g wait beside them); the parameters of PARAM_PIPE travel 8 stages further.
//
// Parameters (PARAM_PIPE = 0): a_in, t_in, o_in are per-pass parameters, not per-vector
// data, read by the stage that needs them (stages 1, 2, 7, 8; noise_params gives each its
// words, pow2 T and a decoded).
// CONTRACT: a_in, t_in, o_in must be stable from the first vector's entry until the
// last vector's exit; texture_pipeline guarantees it: parameters are written only
// when the pipeline is empty (between passes). Changing them with vectors in flight
// gives those vectors a mixture of old and new parameters. PARAM_PIPE = 1 (noise_fold): the
// parameters are per-vector data, taken with in_valid and carried down beside the vector
// (noise_params: o and te 1 stage, T and te 6, a and ae 7).
// ce = 0 holds every register. rst clears the valid chain and the output registers
// (the output registers load only with a valid vector, so no X reaches the outputs).
//
// Multipliers per term (affine, cubic, any amplitude, gradient): 9 T s + 6 blend +
// 7 value lerps + 4 gradient lerps + 3 slopes + 9 g T + 1 a n + 3 a h = 42; pow2 T,
// linear, any amplitude: 7 + 4 + 1 + 3 = 15; pow2 T, linear, pow2 amplitude: 7 + 4 = 11
// (the lerps only); without the gradient (reduced: pow2 T, linear, pow2 amplitude) the 7
// value lerps alone.
// Each stage's combinational logic is one always @* or instance (event-driven simulation
// speed); the value path's registers load in one clocked process with the valid chain.

`default_nettype none

`include "tex_latency.vh"

module noise_term #(
    // formats and modes (config/<name>.toml keys in brackets); every internal width is
    // derived from them below (rtl/tex_widths.vh, the twin of model/hw/config.py)
    parameter S_W            = 24,  // [s_w] texture coordinate word s{S_W}.{S_FRAC}
    parameter S_FRAC         = 16,  // [s_frac]
    parameter T_W            = 17,  // [t_w] transform entry word s{T_W}.{T_FRAC}
    parameter T_FRAC         = 10,  // [t_frac]
    parameter A_W            = 16,  // [a_w] amplitude word s{A_W}.{A_FRAC}
    parameter A_FRAC         = 12,  // [a_frac]
    parameter P_FRAC         = 12,  // [p_frac] noise-space fraction bits (cell position, weights)
    parameter HASH_BITS      = 8,   // [hash_bits] lattice period 2^HASH_BITS per axis
    parameter N_FRAC         = 12,  // [n_frac] noise value / gradient fraction bits
    parameter F_FRAC         = 16,  // [f_frac] fraction bits of an_out
    parameter C_FRAC         = 12,  // [c_frac] fraction bits of ag_out
    parameter TRANSFORM      = 0,   // [transform] 0 affine, 1 pow2 (diagonal 0 / 2^k: shifts)
    parameter BLEND          = 1,   // [blend] 0 linear, 1 cubic
    parameter AMPLITUDE      = 0,   // [amplitude] 0 any, 1 pow2 (0 / +-2^k: shifts)
    parameter NOISE_GRADIENT = 1,   // [noise_gradient] 1: compute ag_out; 0: ag_out = 0
    // 0: a_in, t_in, o_in are per-pass parameters, stable while vectors are in flight, read
    // directly by the stage that needs them; 1: they belong to the vector entering with
    // in_valid and travel down the pipeline with it (noise_fold: another term every clock)
    parameter PARAM_PIPE     = 0,
    parameter FPGA_REGS      = 0,   // [fpga_regs] 1: the eight extra register stages above
    parameter T_EXP_W        = 0,   // [t_exp_w] T's per-term exponent te in t_in (0: none; affine only)
    parameter A_EXP_W        = 0,   // [a_exp_w] a's per-term exponent ae in a_in (0: none; amplitude any only)
    // the lattice permutation, entry i at [i*HASH_BITS +: HASH_BITS] (noise_hash)
    parameter [HASH_BITS*(1<<HASH_BITS)-1:0] PERM = {HASH_BITS*(1<<HASH_BITS){1'b0}}
) (clk, rst, ce, in_valid, s_in, a_in, t_in, o_in, out_valid, an_out, ag_out);

`include "tex_widths.vh"

// ---------------------------------------------------------------------------
// Formats and derived widths (model/hw/config.py derives the same; tb/test_widths.py)

localparam P        = FPGA_REGS ? 2 : 0;    // noise_hash's and noise_blend's optional register stages
localparam LP       = FPGA_REGS ? 2 : 0;    // each lerp's optional register stages
localparam LAT_XF   = `LAT_NOISE_XFORM;     // stages 1, 2 (noise_xform)
localparam STAGES   = LAT_XF + 6 + P + 3*LP; // register stages of this implementation
localparam LATENCY  = FPGA_REGS ? `LAT_NOISE_TERM_FPGA : `LAT_NOISE_TERM;  // must equal STAGES (checked below)
localparam LAT_GR   = FPGA_REGS ? `LAT_NOISE_GRAD_FPGA : `LAT_NOISE_GRAD;  // stages 4..8 (noise_grad)
localparam AFFINE   = (TRANSFORM == 0);
localparam GRAD     = (NOISE_GRADIENT != 0);
localparam AMP_POW2 = (AMPLITUDE == 1);

localparam HB       = HASH_BITS;
localparam P_W      = HASH_BITS + P_FRAC;                     // p: cell . fraction, mod the period
localparam O_W      = P_W;                                    // offset o: a phase of p
localparam N_W      = tw_bits_signed(64'd1 << N_FRAC);        // n in [-1, 1]
localparam BW       = P_FRAC + 2;                             // blend weight / slope, [0, 1.5]
localparam TE_MAX   = (1 << T_EXP_W) - 1;                    // the largest exponents (0: none)
localparam AE_MAX   = (1 << A_EXP_W) - 1;
localparam TE_W     = (T_EXP_W > 0) ? T_EXP_W : 1;            // te, ae as the children take them
localparam AE_W     = (A_EXP_W > 0) ? A_EXP_W : 1;
localparam TIN_W    = 9*T_W + T_EXP_W;                        // t_in: {te, T}
localparam AIN_W    = A_W + A_EXP_W;                          // a_in: {ae, a}
localparam AN_W     = tw_an_w_e(A_W, A_FRAC, N_FRAC, F_FRAC, AE_MAX);
localparam AG_W     = tw_ag_w_e(BLEND, TRANSFORM, T_W, T_FRAC, N_FRAC, C_FRAC, A_W, A_FRAC, TE_MAX, AE_MAX);
localparam AN_SHIFT = A_FRAC + N_FRAC - F_FRAC;
// the blocks' own derivations, restated for tb/test_widths.py (which reads them here, where
// every configuration has them): noise_xform's TS_SHIFT, noise_grad's GN_W, H_W, H_SHIFT
/* verilator lint_off UNUSEDPARAM */
localparam TS_SHIFT = S_FRAC + T_FRAC - P_FRAC;
localparam GN_W     = tw_bits_signed(3 * (64'd1 << N_FRAC));
localparam H_W      = tw_h_w_e(BLEND, TRANSFORM, T_W, T_FRAC, N_FRAC, C_FRAC, TE_MAX);
localparam H_SHIFT  = N_FRAC + T_FRAC - C_FRAC;
/* verilator lint_on UNUSEDPARAM */

input  wire                      clk;
input  wire                      rst;
input  wire                      ce;
input  wire                      in_valid;
input  wire [3*S_W-1:0]          s_in;
input  wire [AIN_W-1:0]          a_in;
input  wire [TIN_W-1:0]          t_in;
input  wire [3*O_W-1:0]          o_in;
output wire                      out_valid;
output wire [AN_W-1:0]           an_out;
output wire [3*AG_W-1:0]         ag_out;

localparam E_W      = $clog2(T_W - 1);      // pow2 shift amount 0..T_W-2
localparam TC_W     = AFFINE ? 9*T_W : 3*(E_W + 1);  // T as stages 1 and 7 read it
localparam TR_W     = AFFINE ? 3*T_W : E_W + 1;      // one row of it (noise_xform)
localparam ANP_W    = A_W + N_W;
localparam ANX_W    = ANP_W + ((AN_SHIFT < 0) ? -AN_SHIFT : 0) + AE_MAX;  // a n (<< ae)
localparam AN_R     = (AN_SHIFT > 0) ? AN_SHIFT : 0;   // an: floor shift right by AN_SHIFT,
localparam AN_L     = (AN_SHIFT < 0) ? -AN_SHIFT : 0;  //     or left by -AN_SHIFT
localparam EA_W     = $clog2(A_W);          // pow2 amplitude shift 0..A_W-1
localparam AC_W     = AMP_POW2 ? EA_W + 2 : A_W;   // a as stage 8 reads it

generate
    if (LATENCY != STAGES || LAT_GR != 5 + 3*LP) begin : g_latency_mismatch
        // elaboration error on purpose: rtl/tex_latency.vh and this block disagree
        noise_term_latency_mismatch_see_tex_latency_vh u_error ();
    end
    if (A_EXP_W < 0 || (A_EXP_W > 0 && (AMP_POW2 || AN_SHIFT < AE_MAX))) begin : g_bad_params
        // elaboration error on purpose: ae needs a's multiplier and a right shift of a n
        noise_term_a_exponent_needs_amplitude_any_and_an_shift u_error ();
    end
endgenerate

// ---------------------------------------------------------------------------
// The parameters as each stage sees them (noise_params): stage 1 reads tc_s1 (pow2 T
// decoded), stage 2 o_s2 and te_s2, stage 7 tc_s7 and te_s7, stage 8 ac_s8 (pow2 a decoded)
// and ae_s8. PARAM_PIPE = 0: the ports themselves (stable); PARAM_PIPE = 1: delayed with
// the vector (1, 6 and 7 enabled clocks), so that every stage works with its own term.

wire [TC_W-1:0]  tc_s1;
wire [3*O_W-1:0] o_s2;
/* verilator lint_off UNUSEDSIGNAL */  // without the gradient, stage 7 reads no T (nor te)
wire [TC_W-1:0]  tc_s7;
wire [TE_W-1:0]  te_s7;
/* verilator lint_on UNUSEDSIGNAL */
wire [TE_W-1:0]  te_s2;
wire [AC_W-1:0]  ac_s8;
/* verilator lint_off UNUSEDSIGNAL */  // pow2 amplitude without the gradient: no exponent read
wire [AE_W-1:0]  ae_s8;
/* verilator lint_on UNUSEDSIGNAL */

noise_params #(
    .T_W(T_W), .A_W(A_W), .O_W(O_W), .TRANSFORM(TRANSFORM), .AMPLITUDE(AMPLITUDE), .NOISE_GRADIENT(NOISE_GRADIENT),
    .PARAM_PIPE(PARAM_PIPE), .FPGA_REGS(FPGA_REGS), .T_EXP_W(T_EXP_W), .A_EXP_W(A_EXP_W)
) u_params (
    .clk(clk), .rst(rst), .ce(ce), .a_in(a_in), .t_in(t_in), .o_in(o_in),
    .tc_s1(tc_s1), .o_s2(o_s2), .te_s2(te_s2), .tc_s7(tc_s7), .te_s7(te_s7), .ac_s8(ac_s8), .ae_s8(ae_s8)
);

// ---------------------------------------------------------------------------
// Registers (stage numbers as in the header), loaded by the clocked process below; the
// stage logic is one always @* (or instance) per stage.

reg [STAGES-1:0]        valid_reg;
reg [8*N_W-1:0]         v_reg;                      // 3: corner (i, j, k) at element 4*i + 2*j + k
reg signed [BW-1:0]     wx_reg, wy_reg, wz_reg;     //    weights
reg [4*N_W-1:0]         e_reg;                      // 4: e[j][k] at element 2*j + k
reg signed [BW-1:0]     wy4_reg, wz4_reg;
reg [2*N_W-1:0]         fz_reg;                     // 5: fz[k] at element k
reg signed [BW-1:0]     wz5_reg;
reg signed [N_W-1:0]    n_reg;                      // 6
reg signed [N_W-1:0]    n7_reg;                     // 7
reg [AN_W-1:0]          an_reg;                     // 8 (output)

assign out_valid = valid_reg[STAGES-1];
assign an_out    = an_reg;

// ---------------------------------------------------------------------------
// Stages 1, 2: p_j = (T_j s >> TS_SHIFT) + o_j mod 2^P_W -> cell and fraction (noise_xform,
// row j of T: affine t_in, pow2 its decoded diagonal entry); stage 3: the blend weights w and
// slopes dw of each axis (noise_blend; the slopes only feed the gradient)

// each axis's signals stay its own (g_axis[j].ip_j, w_j, dw_j: read by name below), not
// slices of one vector driven from three places (docs/simulation.md)
genvar gj;
generate
    for (gj = 0; gj < 3; gj = gj + 1) begin : g_axis
        wire [P_FRAC-1:0] fp;
        wire [HB-1:0]     ip_j;      // cell of axis j (stage 2 registers)
        noise_xform #(
            .S_W(S_W), .S_FRAC(S_FRAC), .T_W(T_W), .T_FRAC(T_FRAC), .P_FRAC(P_FRAC), .HASH_BITS(HB),
            .TRANSFORM(TRANSFORM), .AXIS(gj), .T_EXP_W(T_EXP_W)
        ) u_xform (
            .clk(clk), .ce(ce), .s_in(s_in), .t_row(tc_s1[gj*TR_W +: TR_W]), .o_in(o_s2[gj*O_W +: O_W]),
            .te(te_s2), .ip(ip_j), .fp(fp)
        );
        // stage 3: w, dw of axis j (the slopes only feed the gradient)
        wire signed [BW-1:0] w_j;
        /* verilator lint_off UNUSEDSIGNAL */
        wire signed [BW-1:0] dw_j;
        /* verilator lint_on UNUSEDSIGNAL */
        // FPGA_REGS: f2 and f3 registered beside the hash's ROM levels
        noise_blend #(.BLEND(BLEND), .P_FRAC(P_FRAC), .BW(BW), .PIPE(P)) u_blend (
            .clk(clk), .ce(ce), .fp(fp), .w(w_j), .dw(dw_j)
        );
    end
endgenerate

// ---------------------------------------------------------------------------
// Stage 3: lattice values at the 8 corners (corner (i, j, k) at element 4*i + 2*j + k)

wire [8*N_W-1:0]     v_next;

// FPGA_REGS: the hash one ROM level a clock, beside noise_blend's two multipliers
noise_hash #(.H(HB), .N_FRAC(N_FRAC), .N_W(N_W), .PERM(PERM), .PIPE(P)) u_hash (
    .clk(clk),
    .ce(ce),
    .ix(g_axis[0].ip_j),
    .iy(g_axis[1].ip_j),
    .iz(g_axis[2].ip_j),
    .v_out(v_next)
);

// the weights beside the lerps' extra registers (FPGA_REGS), stages 4 and 5
wire signed [BW-1:0] wy_p, wz_p, wz4_p;
delay_line #(.W(2*BW), .N(LP)) u_dly_w3 (.clk(clk), .rst(rst), .ce(ce), .d_in({wy_reg, wz_reg}), .d_out({wy_p, wz_p}));
delay_line #(.W(BW), .N(LP))   u_dly_w4 (.clk(clk), .rst(rst), .ce(ce), .d_in(wz4_reg), .d_out(wz4_p));

// ---------------------------------------------------------------------------
// Stage 4: x lerps e[j][k] = lerp(v0jk, v1jk, wx); stage 5: y lerps fz[k] = lerp(e0k, e1k, wy)

// (each lerp's y is read by name in the clocked process, not through one vector)
genvar gl;
generate
    for (gl = 0; gl < 4; gl = gl + 1) begin : g_lerp_x
        wire signed [N_W-1:0] y;
        lerp #(.W(N_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp (
            .clk(clk), .ce(ce), .a(v_reg[gl*N_W +: N_W]), .b(v_reg[(4+gl)*N_W +: N_W]), .t(wx_reg), .y(y)
        );
    end
    for (gl = 0; gl < 2; gl = gl + 1) begin : g_lerp_y
        wire signed [N_W-1:0] y;
        lerp #(.W(N_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp (
            .clk(clk), .ce(ce), .a(e_reg[gl*N_W +: N_W]), .b(e_reg[(2+gl)*N_W +: N_W]), .t(wy4_reg), .y(y)
        );
    end
endgenerate

// ---------------------------------------------------------------------------
// Stage 6: z lerp n = lerp(fz0, fz1, wz)
// Stage 7: n delayed (the gradient's h is computed here)

wire signed [N_W-1:0] n_next;

lerp #(.W(N_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_z (
    .clk(clk), .ce(ce), .a(fz_reg[0 +: N_W]), .b(fz_reg[N_W +: N_W]), .t(wz5_reg), .y(n_next)
);

// ---------------------------------------------------------------------------
// Stage 8: an = (a n) >> (AN_SHIFT - ae) (output register)

reg [AN_W-1:0] an_next;

generate
    if (AMP_POW2) begin : g_an_pow2
        // a n = sign(a) n << e (0 when a = 0); an fits AN_W bits (model/hw/config.py
        // bound), the rest of the word are sign copies
        reg signed [N_W:0]      n_ext;
        /* verilator lint_off UNUSEDSIGNAL */
        reg signed [ANX_W-1:0]  an_w;
        /* verilator lint_on UNUSEDSIGNAL */
        always @* begin
            n_ext = {n7_reg[N_W-1], n7_reg};  // sign-extended: even the most negative word negates
            n_ext = ac_s8[EA_W + 1] ? {(N_W+1){1'b0}} : (ac_s8[EA_W] ? -n_ext : n_ext);
            an_w  = (({{(ANX_W-N_W-1){n_ext[N_W]}}, n_ext} <<< ac_s8[EA_W-1:0]) <<< AN_L) >>> AN_R;
            an_next = an_w[AN_W-1:0];
        end
    end else begin : g_an_any
        // with an exponent ((a n) << ae) >> AN_SHIFT: AN_SHIFT >= AE_MAX, so AN_L = 0 (without,
        // ae_s8 is a constant 0)
        /* verilator lint_off UNUSEDSIGNAL */
        reg signed [ANX_W-1:0]  an_w;
        /* verilator lint_on UNUSEDSIGNAL */
        always @* begin
            an_w  = ((($signed(ac_s8) * n7_reg) <<< ae_s8) <<< AN_L) >>> AN_R;
            an_next = an_w[AN_W-1:0];
        end
    end
endgenerate

// ---------------------------------------------------------------------------
// Value path registers and the valid chain: one clocked process. ce = 0 holds
// every register; rst clears the valid chain and the output register.

always @(posedge clk) begin
    if (ce) begin
        v_reg    <= v_next;
        wx_reg   <= g_axis[0].w_j;
        wy_reg   <= g_axis[1].w_j;
        wz_reg   <= g_axis[2].w_j;
        e_reg    <= {g_lerp_x[3].y, g_lerp_x[2].y, g_lerp_x[1].y, g_lerp_x[0].y};
        wy4_reg  <= wy_p;
        wz4_reg  <= wz_p;
        fz_reg   <= {g_lerp_y[1].y, g_lerp_y[0].y};
        wz5_reg  <= wz4_p;
        n_reg    <= n_next;
        n7_reg   <= n_reg;
    end
    if (rst) begin
        valid_reg <= {STAGES{1'b0}};
        an_reg    <= {AN_W{1'b0}};
    end else if (ce) begin
        valid_reg <= {valid_reg[STAGES-2:0], in_valid};
        if (valid_reg[STAGES-2]) an_reg <= an_next;
    end
end

// ---------------------------------------------------------------------------
// Gradient: noise_grad, stages 4..8 beside the value path, from its stage 3..5 registers
// (and the slopes, registered at stage 3 here)

generate
    if (GRAD) begin : g_grad
        reg [3*BW-1:0] dw_reg;  // stage 3: slopes {z, y, x}
        always @(posedge clk) begin
            if (ce) dw_reg <= {g_axis[2].dw_j, g_axis[1].dw_j, g_axis[0].dw_j};
        end
        noise_grad #(
            .T_W(T_W), .T_FRAC(T_FRAC), .A_W(A_W), .A_FRAC(A_FRAC), .P_FRAC(P_FRAC), .N_FRAC(N_FRAC),
            .C_FRAC(C_FRAC), .TRANSFORM(TRANSFORM), .BLEND(BLEND), .AMPLITUDE(AMPLITUDE), .FPGA_REGS(FPGA_REGS),
            .T_EXP_W(T_EXP_W), .A_EXP_W(A_EXP_W)
        ) u_grad (
            .clk(clk), .rst(rst), .ce(ce),
            .v(v_reg), .wy(wy_reg), .dw(dw_reg), .e(e_reg), .wz(wz4_reg), .fz(fz_reg),
            .t_in(tc_s7), .te(te_s7), .a_in(ac_s8), .ae(ae_s8), .load(valid_reg[STAGES-2]),
            .ag_out(ag_out)
        );
    end else begin : g_no_grad
        assign ag_out = {3*AG_W{1'b0}};
    end
endgenerate

endmodule

`default_nettype wire
