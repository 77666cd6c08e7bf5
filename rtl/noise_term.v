// noise_term: one noise term a n(T s + o) and its texture-space gradient a (dn/dp) T.
//
// The bit-exact twin of model/hw/golden.py noise_term(cfg, a, T, o, s) (with noise_hash,
// noise_blend and lerp), for one vector per enabled clock:
//   p_j  = ((sum_k T_jk s_k) >> TS_SHIFT) + o_j  mod 2^P_W     (lattice cell . fraction)
//   v    = lattice values at the 8 cell corners (noise_hash), w/dw = blend weights (noise_blend)
//   n    = trilinear blend of v with the weights, x first, then y, then z (lerp)
//   an   = (a n) >> AN_SHIFT
//   g_x  = (lerp(lerp(dx00, dx10, wy), lerp(dx01, dx11, wy), wz) dw_x) >> P_FRAC, dx = v1jk - v0jk
//   g_y  = (lerp(e10 - e00, e11 - e01, wz) dw_y) >> P_FRAC, g_z = ((fz1 - fz0) dw_z) >> P_FRAC
//   h_k  = (sum_j g_j T_jk) >> H_SHIFT,   ag_k = (a h_k) >> A_FRAC
// Every ">>" is a floor (arithmetic shift right of a signed word); a negative shift
// count is a left shift.
//
// Formats (the parameters below; derived widths from rtl/tex_widths.vh):
//   s_in   3 x s{S_W}.{S_FRAC}, {r, t, s} (s at the LSBs)
//   a_in   s{A_W}.{A_FRAC}
//   t_in   9 x s{T_W}.{T_FRAC}, T[j][k] at element 3*j + k
//   o_in   3 x u{O_W}.{P_FRAC} (O_W = P_W = HASH_BITS + P_FRAC: a phase mod the lattice period)
//   an_out s{AN_W}.{F_FRAC};  ag_out 3 x s{AG_W}.{C_FRAC} (all 0 when NOISE_GRADIENT = 0)
// Internal: p u{P_W}.{P_FRAC}; v, e, fz, n s{N_W}.{N_FRAC}; differences s{N_W+1}.{N_FRAC};
//   w, dw s{BLEND_W}.{P_FRAC} in [0, 1.5]; g s{GN_W}.{N_FRAC}; h s{H_W}.{C_FRAC + A_FRAC}.
//   T s only matters mod 2^(TS_SHIFT + P_W) (p wraps), so the transform products are
//   only that wide.
//
// Transform (TRANSFORM): affine (0) uses multipliers for T s and g T. pow2 (1):
// T is diagonal with entries 0 or 2^e (model/hw/quantize.py guarantees it; the
// off-diagonal entries are ignored), so T_jj s_j and g_j T_jj are barrel shifts by
// e = the priority-encoded highest set bit of T_jj (0 when T_jj = 0); no multipliers.
//
// Amplitude (AMPLITUDE): any (0) uses multipliers for a n and a h. pow2 (1): a is
// 0 or +-2^e (model/hw/quantize.py guarantees it), e in 0..A_W-2 for a > 0 and 0..A_W-1
// for a < 0 (-2^(A_W-1), the format's most negative value, is legal). a_in is decoded
// once, combinationally, into ac_in = {zero, neg, e} (1 + 1 + EA_W bits, EA_W =
// clog2(A_W)): e = the lowest set bit of a_in (2^e has bit e alone, -2^e bits e..A_W-1),
// neg = the sign bit. Stage 8 then forms sign(a) n as s{N_W+1} and sign(a) h_k as
// s{H_W+1} (a conditional negation, 0 when a = 0; one extra bit so that even the most
// negative word negates exactly), shifts it left by e in the A_W + N_W (A_W + H_W) bit
// product word (|a n| <= 2^(A_W-1) 2^(N_W-1) < 2^(A_W+N_W-1): no overflow) and takes
// the same floor shift (>> AN_SHIFT, >> A_FRAC) as the multiplier path: the products
// are exactly a n and a h_k, so the results equal the golden model's for every n, h
// and legal a. No multipliers.
//
// Pipeline (LATENCY = `LAT_NOISE_TERM = 8 register stages, one vector per enabled clock):
//   1  transform products T_jk s_k (pow2: shifts)
//   2  p = sum + o -> cell ip, fraction fp
//   3  noise_hash (3 ROM levels) -> 8 corner values; noise_blend -> w, dw
//   4  x lerps -> e (4); gradient: dx and their y lerps (2)
//   5  y lerps -> fz (2); gradient: z lerps of the x and y differences
//   6  z lerp -> n; gradient: g = (. dw) >> P_FRAC (cubic; linear: dw = 1, a wire)
//   7  h = (g T) >> H_SHIFT (pow2: shifts); n delayed
//   8  an = (a n) >> AN_SHIFT, ag = (a h) >> A_FRAC (pow2: shifts; output registers)
// FPGA_REGS = 1 ([fpga_regs]; `LAT_NOISE_TERM_FPGA = 16 stages): eight more: stage 3 in
// three (P = 2: noise_hash one ROM level a clock, beside it noise_blend's f2 registered
// after its first multiplier and f3 after its second), and in stages 4, 5, 6 every lerp in three (LP = 2: b - a registered before
// the multiplier, the scaled step before the adder; the weights, slopes and the gradient's
// g wait beside them); the parameters of PARAM_PIPE travel 8 stages further (T 14, a 15).
//
// Parameters (PARAM_PIPE = 0): a_in, t_in, o_in are per-pass parameters, not per-vector
// data. No register carries them down the pipeline: each is read directly by the stage that
// needs it (t_in by stages 1 and 7, o_in by stage 2, a_in by stage 8; pow2 T and a
// through their combinational decoders, tc_in and ac_in).
// CONTRACT: a_in, t_in, o_in must be stable from the first vector's entry until the
// last vector's exit; texture_pipeline guarantees it: parameters are written only
// when the pipeline is empty (between passes). Changing them with vectors in flight
// gives those vectors a mixture of old and new parameters. PARAM_PIPE = 1 (noise_fold): the
// parameters are per-vector data, taken with in_valid and carried down beside the vector
// (o for 1 stage, T for 6, a for 7; in pow2 modes the decoded shifts, a few bits each).
// ce = 0 holds every register. rst clears the valid chain and the output registers
// (the output registers load only with a valid vector, so no X reaches the outputs).
//
// Multipliers per term (affine, cubic, any amplitude, gradient): 9 T s + 6 blend +
// 7 value lerps + 4 gradient lerps + 3 slopes + 9 g T + 1 a n + 3 a h = 42; pow2 T,
// linear, any amplitude: 7 + 4 + 1 + 3 = 15; pow2 T, linear, pow2 amplitude: 7 + 4 = 11
// (the lerps only); without the gradient (reduced: pow2 T, linear, pow2 amplitude) the 7
// value lerps alone.
//
// Written for event-driven simulation speed: each stage's combinational logic is one
// always @* with blocking assigns to local regs (or a lerp / noise_hash / noise_blend
// instance, each one always @* inside), every instance output and every register an
// instance reads is its own variable (no bus driven piecewise, no port on a part-select),
// and the registers load in two clocked processes (value path with the valid chain;
// gradient).

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
    // the lattice permutation, entry i at [i*HASH_BITS +: HASH_BITS] (noise_hash)
    parameter [HASH_BITS*(1<<HASH_BITS)-1:0] PERM = {HASH_BITS*(1<<HASH_BITS){1'b0}}
) (clk, rst, ce, in_valid, s_in, a_in, t_in, o_in, out_valid, an_out, ag_out);

`include "tex_widths.vh"

// ---------------------------------------------------------------------------
// Formats and derived widths (model/hw/config.py derives the same; tb/test_widths.py)

localparam P        = FPGA_REGS ? 2 : 0;    // noise_hash's and noise_blend's optional register stages
localparam LP       = FPGA_REGS ? 2 : 0;    // each lerp's optional register stages
localparam STAGES   = 8 + P + 3*LP;         // register stages of this implementation
localparam LATENCY  = FPGA_REGS ? `LAT_NOISE_TERM_FPGA : `LAT_NOISE_TERM;  // must equal STAGES (checked below)
localparam AFFINE   = (TRANSFORM == 0);
localparam CUBIC    = (BLEND == 1);
localparam GRAD     = (NOISE_GRADIENT != 0);
localparam AMP_POW2 = (AMPLITUDE == 1);

localparam HB       = HASH_BITS;
localparam P_W      = HASH_BITS + P_FRAC;                     // p: cell . fraction, mod the period
localparam O_W      = P_W;                                    // offset o: a phase of p
localparam N_W      = tw_bits_signed(64'd1 << N_FRAC);        // n in [-1, 1]
localparam GN_W     = tw_bits_signed(3 * (64'd1 << N_FRAC));  // |dn/dp| <= 2 * 1.5
localparam BW       = P_FRAC + 2;                             // blend weight / slope, [0, 1.5]
localparam AN_W     = tw_an_w(A_W, A_FRAC, N_FRAC, F_FRAC);
localparam H_W      = tw_h_w(BLEND, TRANSFORM, T_W, T_FRAC, N_FRAC, C_FRAC);
localparam AG_W     = tw_ag_w(BLEND, TRANSFORM, T_W, T_FRAC, N_FRAC, C_FRAC, A_W, A_FRAC);
localparam TS_SHIFT = S_FRAC + T_FRAC - P_FRAC;   // >= 0 (model/hw/config.py checks)
localparam AN_SHIFT = A_FRAC + N_FRAC - F_FRAC;
localparam H_SHIFT  = N_FRAC + T_FRAC - C_FRAC;

input  wire                      clk;
input  wire                      rst;
input  wire                      ce;
input  wire                      in_valid;
input  wire [3*S_W-1:0]          s_in;
input  wire [A_W-1:0]            a_in;
input  wire [9*T_W-1:0]          t_in;
input  wire [3*O_W-1:0]          o_in;
output wire                      out_valid;
output wire [AN_W-1:0]           an_out;
output wire [3*AG_W-1:0]         ag_out;

localparam D_W      = N_W + 1;              // difference of two lattice-range values
localparam ACC_W    = TS_SHIFT + P_W;       // T s mod 2^ACC_W decides p
localparam MUL_W    = (ACC_W > T_W) ? ((ACC_W > S_W) ? ACC_W : S_W) : ((T_W > S_W) ? T_W : S_W);
localparam NPROD    = AFFINE ? 9 : 3;       // transform products per vector
localparam E_W      = $clog2(T_W - 1);      // pow2 shift amount 0..T_W-2
localparam TC_W     = AFFINE ? 9*T_W : 3*(E_W + 1);  // T as stages 1 and 7 read it
// h: sum of three g T products, then the shift; ag and an likewise
localparam HS_W     = GN_W + T_W + 2;
localparam HX_W     = HS_W + ((H_SHIFT < 0) ? -H_SHIFT : 0);
localparam ANP_W    = A_W + N_W;
localparam ANX_W    = ANP_W + ((AN_SHIFT < 0) ? -AN_SHIFT : 0);
localparam H_R      = (H_SHIFT > 0) ? H_SHIFT : 0;     // h: floor shift right by H_SHIFT,
localparam H_L      = (H_SHIFT < 0) ? -H_SHIFT : 0;    //    or left by -H_SHIFT
localparam AN_R     = (AN_SHIFT > 0) ? AN_SHIFT : 0;   // an likewise
localparam AN_L     = (AN_SHIFT < 0) ? -AN_SHIFT : 0;
localparam AGP_W    = A_W + H_W;
localparam EA_W     = $clog2(A_W);          // pow2 amplitude shift 0..A_W-1
localparam AC_W     = AMP_POW2 ? EA_W + 2 : A_W;   // a as stage 8 reads it

generate
    if (LATENCY != STAGES) begin : g_latency_mismatch
        // elaboration error on purpose: rtl/tex_latency.vh and this block disagree
        noise_term_latency_mismatch_see_tex_latency_vh u_error ();
    end
endgenerate

// ---------------------------------------------------------------------------
// Parameters, stable for the whole pass (see the contract in the header): read
// directly where needed, not pipelined. The decoders below change only when the
// parameters do (between passes).

wire [AC_W-1:0] ac_in;              // a as stage 8 needs it (any: a; pow2: {zero, neg, e})
// T as stages 1 and 7 need it (affine: T; pow2: {zero, e} per diagonal entry, entry j
// at element j); without the gradient, affine stage 1 reads t_in and this is unused
/* verilator lint_off UNUSEDSIGNAL */
wire [TC_W-1:0] tc_in;
/* verilator lint_on UNUSEDSIGNAL */

generate
    if (AMP_POW2) begin : g_a_pow2
        // a = 2^e has bit e alone set, a = -2^e bits e..A_W-1 (-2^(A_W-1): bit A_W-1
        // alone): either way e is the lowest set bit, and neg the sign bit
        reg [AC_W-1:0] ac;
        reg [EA_W-1:0] e;
        integer        i;
        always @* begin
            // priority encoder: the lowest set bit of a (0 when a = 0)
            e = {EA_W{1'b0}};
            for (i = A_W - 1; i >= 0; i = i - 1) begin
                if (a_in[i]) e = i[EA_W-1:0];
            end
            ac = {a_in == {A_W{1'b0}}, a_in[A_W-1], e};
        end
        assign ac_in = ac;
    end else begin : g_a_any
        assign ac_in = a_in;
    end

    if (AFFINE) begin : g_t_affine
        assign tc_in = t_in;
    end else begin : g_t_pow2
        // T_jj = 2^e: e is the highest set bit of T_jj below the sign (0 when T_jj = 0)
        reg [TC_W-1:0]        tc;
        reg signed [T_W-1:0]  t_jj;
        reg [E_W-1:0]         e;
        integer               i, j;
        always @* begin
            tc = {TC_W{1'b0}};
            for (j = 0; j < 3; j = j + 1) begin
                t_jj = t_in[(4*j)*T_W +: T_W];
                e    = {E_W{1'b0}};
                for (i = 0; i < T_W - 1; i = i + 1) begin
                    if (t_jj[i]) e = i[E_W-1:0];
                end
                tc[j*(E_W+1) +: E_W+1] = {t_jj == {T_W{1'b0}}, e};
            end
        end
        assign tc_in = tc;
        // the quantizer guarantees a diagonal T: the off-diagonal entries are not read
        /* verilator lint_off UNUSEDSIGNAL */
        wire [6*T_W-1:0] t_offdiag = {t_in[5*T_W +: 3*T_W], t_in[1*T_W +: 3*T_W]};
        /* verilator lint_on UNUSEDSIGNAL */
    end
endgenerate

// ---------------------------------------------------------------------------
// The parameters as each stage sees them: stage 1 reads t_in / tc_in itself; stage 2 reads
// o_s2, stage 7 tc_s7 and stage 8 ac_s8. PARAM_PIPE = 0: the ports themselves (stable);
// PARAM_PIPE = 1: delayed with the vector (1, 6 and 7 enabled clocks), so that every stage
// works with its own vector's term.

wire [3*O_W-1:0] o_s2;
/* verilator lint_off UNUSEDSIGNAL */  // without the gradient, stage 7 reads no T
wire [TC_W-1:0]  tc_s7;
/* verilator lint_on UNUSEDSIGNAL */
wire [AC_W-1:0]  ac_s8;

generate
    if (PARAM_PIPE != 0) begin : g_param_pipe
        delay_line #(.W(3*O_W), .N(1)) u_dly_o  (.clk(clk), .rst(rst), .ce(ce), .d_in(o_in),  .d_out(o_s2));
        delay_line #(.W(AC_W),  .N(7 + P + 3*LP)) u_dly_ac (.clk(clk), .rst(rst), .ce(ce), .d_in(ac_in), .d_out(ac_s8));
        if (GRAD) begin : g_t
            delay_line #(.W(TC_W), .N(6 + P + 3*LP)) u_dly_tc (.clk(clk), .rst(rst), .ce(ce), .d_in(tc_in), .d_out(tc_s7));
        end else begin : g_no_t
            assign tc_s7 = {TC_W{1'b0}};
        end
    end else begin : g_param_static
        assign o_s2  = o_in;
        assign tc_s7 = tc_in;
        assign ac_s8 = ac_in;
    end
endgenerate

// ---------------------------------------------------------------------------
// Registers (stage numbers as in the header), loaded by the clocked process at the
// end; the stage logic is one always @* (or instance) per stage.

reg [STAGES-1:0]        valid_reg;
reg [NPROD*ACC_W-1:0]   prod_reg;               // 1: T_jk s_k at element 3*j + k (pow2: T_jj s_j at j)
reg [HB-1:0]            ix_reg, iy_reg, iz_reg;     // 2: cell
reg [P_FRAC-1:0]        fpx_reg, fpy_reg, fpz_reg;  //    fraction
reg signed [N_W-1:0]    v000_reg, v001_reg, v010_reg, v011_reg;   // 3: corner (i, j, k) values
reg signed [N_W-1:0]    v100_reg, v101_reg, v110_reg, v111_reg;
reg signed [BW-1:0]     wx_reg, wy_reg, wz_reg;     //    weights
reg signed [N_W-1:0]    e00_reg, e01_reg, e10_reg, e11_reg;       // 4: e[j][k]
reg signed [BW-1:0]     wy4_reg, wz4_reg;
reg signed [N_W-1:0]    fz0_reg, fz1_reg;           // 5: fz[k]
reg signed [BW-1:0]     wz5_reg;
reg signed [N_W-1:0]    n_reg;                      // 6
reg signed [N_W-1:0]    n7_reg;                     // 7
reg [AN_W-1:0]          an_reg;                     // 8 (output)

assign out_valid = valid_reg[STAGES-1];
assign an_out    = an_reg;

// ---------------------------------------------------------------------------
// Stage 1: transform products (mod 2^ACC_W)
// Stage 2: p = (T s >> TS_SHIFT) + o mod 2^P_W -> cell and fraction

reg [NPROD*ACC_W-1:0]   prod_next;
reg [HB-1:0]            ix_next, iy_next, iz_next;
reg [P_FRAC-1:0]        fpx_next, fpy_next, fpz_next;

generate
    if (AFFINE) begin : g_s12_affine
        // T_jk s_k mod 2^ACC_W: the low ACC_W bits of the product of the sign-extended
        // operands; above bit ACC_W the product does not reach p (p wraps mod 2^P_W)
        always @* begin
            prod_next[0*ACC_W +: ACC_W] = $signed(t_in[0*T_W +: T_W]) * $signed(s_in[0*S_W +: S_W]);
            prod_next[1*ACC_W +: ACC_W] = $signed(t_in[1*T_W +: T_W]) * $signed(s_in[1*S_W +: S_W]);
            prod_next[2*ACC_W +: ACC_W] = $signed(t_in[2*T_W +: T_W]) * $signed(s_in[2*S_W +: S_W]);
            prod_next[3*ACC_W +: ACC_W] = $signed(t_in[3*T_W +: T_W]) * $signed(s_in[0*S_W +: S_W]);
            prod_next[4*ACC_W +: ACC_W] = $signed(t_in[4*T_W +: T_W]) * $signed(s_in[1*S_W +: S_W]);
            prod_next[5*ACC_W +: ACC_W] = $signed(t_in[5*T_W +: T_W]) * $signed(s_in[2*S_W +: S_W]);
            prod_next[6*ACC_W +: ACC_W] = $signed(t_in[6*T_W +: T_W]) * $signed(s_in[0*S_W +: S_W]);
            prod_next[7*ACC_W +: ACC_W] = $signed(t_in[7*T_W +: T_W]) * $signed(s_in[1*S_W +: S_W]);
            prod_next[8*ACC_W +: ACC_W] = $signed(t_in[8*T_W +: T_W]) * $signed(s_in[2*S_W +: S_W]);
        end
        // the fraction dropped by the floor shift: acc[TS_SHIFT-1:0]
        /* verilator lint_off UNUSEDSIGNAL */
        reg [ACC_W-1:0] ax, ay, az;
        /* verilator lint_on UNUSEDSIGNAL */
        always @* begin
            ax = prod_reg[0*ACC_W +: ACC_W] + prod_reg[1*ACC_W +: ACC_W] + prod_reg[2*ACC_W +: ACC_W];
            ay = prod_reg[3*ACC_W +: ACC_W] + prod_reg[4*ACC_W +: ACC_W] + prod_reg[5*ACC_W +: ACC_W];
            az = prod_reg[6*ACC_W +: ACC_W] + prod_reg[7*ACC_W +: ACC_W] + prod_reg[8*ACC_W +: ACC_W];
            {ix_next, fpx_next} = ax[ACC_W-1:TS_SHIFT] + o_s2[0*O_W +: P_W];   // p mod 2^P_W
            {iy_next, fpy_next} = ay[ACC_W-1:TS_SHIFT] + o_s2[1*O_W +: P_W];
            {iz_next, fpz_next} = az[ACC_W-1:TS_SHIFT] + o_s2[2*O_W +: P_W];
        end
    end else begin : g_s12_pow2
        // T_jj s_j = s_j << e_j, or 0: s_j sign-extended to MUL_W + 1 bits (>= ACC_W + 1);
        // above bit ACC_W the product does not reach p (p wraps mod 2^P_W)
        /* verilator lint_off UNUSEDSIGNAL */
        reg signed [MUL_W:0]   shl;
        /* verilator lint_on UNUSEDSIGNAL */
        reg signed [S_W-1:0]   s_j;
        always @* begin
            s_j = s_in[0*S_W +: S_W];
            shl = {{(MUL_W+1-S_W){s_j[S_W-1]}}, s_j} <<< tc_in[0*(E_W+1) +: E_W];
            prod_next[0*ACC_W +: ACC_W] = tc_in[0*(E_W+1) + E_W] ? {ACC_W{1'b0}} : shl[ACC_W-1:0];
            s_j = s_in[1*S_W +: S_W];
            shl = {{(MUL_W+1-S_W){s_j[S_W-1]}}, s_j} <<< tc_in[1*(E_W+1) +: E_W];
            prod_next[1*ACC_W +: ACC_W] = tc_in[1*(E_W+1) + E_W] ? {ACC_W{1'b0}} : shl[ACC_W-1:0];
            s_j = s_in[2*S_W +: S_W];
            shl = {{(MUL_W+1-S_W){s_j[S_W-1]}}, s_j} <<< tc_in[2*(E_W+1) +: E_W];
            prod_next[2*ACC_W +: ACC_W] = tc_in[2*(E_W+1) + E_W] ? {ACC_W{1'b0}} : shl[ACC_W-1:0];
        end
        // the fraction dropped by the floor shift: acc[TS_SHIFT-1:0]
        /* verilator lint_off UNUSEDSIGNAL */
        reg [ACC_W-1:0] ax, ay, az;
        /* verilator lint_on UNUSEDSIGNAL */
        always @* begin
            ax = prod_reg[0*ACC_W +: ACC_W];
            ay = prod_reg[1*ACC_W +: ACC_W];
            az = prod_reg[2*ACC_W +: ACC_W];
            {ix_next, fpx_next} = ax[ACC_W-1:TS_SHIFT] + o_s2[0*O_W +: P_W];   // p mod 2^P_W
            {iy_next, fpy_next} = ay[ACC_W-1:TS_SHIFT] + o_s2[1*O_W +: P_W];
            {iz_next, fpz_next} = az[ACC_W-1:TS_SHIFT] + o_s2[2*O_W +: P_W];
        end
    end
endgenerate

// ---------------------------------------------------------------------------
// Stage 3: lattice values at the 8 corners (corner (i, j, k) at element 4*i + 2*j + k);
// blend weights w and slopes dw (the slopes only feed the gradient)

wire [8*N_W-1:0]     v_next;
wire signed [BW-1:0] wx_next, wy_next, wz_next;
/* verilator lint_off UNUSEDSIGNAL */
wire signed [BW-1:0] dwx_next, dwy_next, dwz_next;
/* verilator lint_on UNUSEDSIGNAL */

// FPGA_REGS: the hash one ROM level a clock, beside noise_blend's two multipliers
noise_hash #(.H(HB), .N_FRAC(N_FRAC), .N_W(N_W), .PERM(PERM), .PIPE(P)) u_hash (
    .clk(clk),
    .ce(ce),
    .ix(ix_reg),
    .iy(iy_reg),
    .iz(iz_reg),
    .v_out(v_next)
);

// the weights beside the lerps' extra registers (FPGA_REGS), stages 4 and 5
wire signed [BW-1:0] wy_p, wz_p, wz4_p;
delay_line #(.W(2*BW), .N(LP)) u_dly_w3 (.clk(clk), .rst(rst), .ce(ce), .d_in({wy_reg, wz_reg}), .d_out({wy_p, wz_p}));
delay_line #(.W(BW), .N(LP))   u_dly_w4 (.clk(clk), .rst(rst), .ce(ce), .d_in(wz4_reg), .d_out(wz4_p));

noise_blend #(.BLEND(BLEND), .P_FRAC(P_FRAC), .BW(BW), .PIPE(P)) u_blend_x (
    .clk(clk), .ce(ce), .fp(fpx_reg), .w(wx_next), .dw(dwx_next)
);
noise_blend #(.BLEND(BLEND), .P_FRAC(P_FRAC), .BW(BW), .PIPE(P)) u_blend_y (
    .clk(clk), .ce(ce), .fp(fpy_reg), .w(wy_next), .dw(dwy_next)
);
noise_blend #(.BLEND(BLEND), .P_FRAC(P_FRAC), .BW(BW), .PIPE(P)) u_blend_z (
    .clk(clk), .ce(ce), .fp(fpz_reg), .w(wz_next), .dw(dwz_next)
);

// ---------------------------------------------------------------------------
// Stage 4: x lerps e[j][k] = lerp(v0jk, v1jk, wx)

wire signed [N_W-1:0] e00_next, e01_next, e10_next, e11_next;

lerp #(.W(N_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_x00 (
    .clk(clk), .ce(ce), .a(v000_reg), .b(v100_reg), .t(wx_reg), .y(e00_next)
);
lerp #(.W(N_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_x01 (
    .clk(clk), .ce(ce), .a(v001_reg), .b(v101_reg), .t(wx_reg), .y(e01_next)
);
lerp #(.W(N_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_x10 (
    .clk(clk), .ce(ce), .a(v010_reg), .b(v110_reg), .t(wx_reg), .y(e10_next)
);
lerp #(.W(N_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_x11 (
    .clk(clk), .ce(ce), .a(v011_reg), .b(v111_reg), .t(wx_reg), .y(e11_next)
);

// ---------------------------------------------------------------------------
// Stage 5: y lerps fz[k] = lerp(e0k, e1k, wy)

wire signed [N_W-1:0] fz0_next, fz1_next;

lerp #(.W(N_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_y0 (
    .clk(clk), .ce(ce), .a(e00_reg), .b(e10_reg), .t(wy4_reg), .y(fz0_next)
);
lerp #(.W(N_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_y1 (
    .clk(clk), .ce(ce), .a(e01_reg), .b(e11_reg), .t(wy4_reg), .y(fz1_next)
);

// ---------------------------------------------------------------------------
// Stage 6: z lerp n = lerp(fz0, fz1, wz)
// Stage 7: n delayed (the gradient's h is computed here)

wire signed [N_W-1:0] n_next;

lerp #(.W(N_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_z (
    .clk(clk), .ce(ce), .a(fz0_reg), .b(fz1_reg), .t(wz5_reg), .y(n_next)
);

// ---------------------------------------------------------------------------
// Stage 8: an = (a n) >> AN_SHIFT (output register)

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
        /* verilator lint_off UNUSEDSIGNAL */
        reg signed [ANX_W-1:0]  an_w;
        /* verilator lint_on UNUSEDSIGNAL */
        always @* begin
            an_w  = (($signed(ac_s8) * n7_reg) <<< AN_L) >>> AN_R;
            an_next = an_w[AN_W-1:0];
        end
    end
endgenerate

// ---------------------------------------------------------------------------
// Value path registers and the valid chain: one clocked process. ce = 0 holds
// every register; rst clears the valid chain and the output register.

always @(posedge clk) begin
    if (ce) begin
        prod_reg <= prod_next;
        ix_reg   <= ix_next;
        iy_reg   <= iy_next;
        iz_reg   <= iz_next;
        fpx_reg  <= fpx_next;
        fpy_reg  <= fpy_next;
        fpz_reg  <= fpz_next;
        v000_reg <= v_next[0*N_W +: N_W];
        v001_reg <= v_next[1*N_W +: N_W];
        v010_reg <= v_next[2*N_W +: N_W];
        v011_reg <= v_next[3*N_W +: N_W];
        v100_reg <= v_next[4*N_W +: N_W];
        v101_reg <= v_next[5*N_W +: N_W];
        v110_reg <= v_next[6*N_W +: N_W];
        v111_reg <= v_next[7*N_W +: N_W];
        wx_reg   <= wx_next;
        wy_reg   <= wy_next;
        wz_reg   <= wz_next;
        e00_reg  <= e00_next;
        e01_reg  <= e01_next;
        e10_reg  <= e10_next;
        e11_reg  <= e11_next;
        wy4_reg  <= wy_p;
        wz4_reg  <= wz_p;
        fz0_reg  <= fz0_next;
        fz1_reg  <= fz1_next;
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
// Gradient: stages 3..8 beside the value path (its own registers and clocked process)

generate
    if (GRAD) begin : g_grad
        reg [3*BW-1:0]        dw3_reg, dw4_reg, dw5_reg;  // slopes {z, y, x} delayed to stage 6
        reg signed [D_W-1:0]  dxy0_reg, dxy1_reg;         // 4
        reg signed [D_W-1:0]  gxl_reg, gyl_reg;           // 5
        reg signed [GN_W-1:0] gx_reg, gy_reg, gz_reg;     // 6
        reg [3*H_W-1:0]       h_reg;                      // 7: h_k at element k
        reg [3*AG_W-1:0]      ag_reg;                     // 8 (outputs)

        // stage 4: dx[j][k] = v1jk - v0jk; dxy[k] = lerp(dx0k, dx1k, wy)
        reg signed [D_W-1:0]  dx00, dx01, dx10, dx11;
        always @* begin
            dx00 = v100_reg - v000_reg;     // operands sign-extended to D_W bits: exact
            dx01 = v101_reg - v001_reg;
            dx10 = v110_reg - v010_reg;
            dx11 = v111_reg - v011_reg;
        end
        wire signed [D_W-1:0] dxy0_next, dxy1_next;
        lerp #(.W(D_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_dxy0 (
            .clk(clk), .ce(ce), .a(dx00), .b(dx10), .t(wy_reg), .y(dxy0_next)
        );
        lerp #(.W(D_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_dxy1 (
            .clk(clk), .ce(ce), .a(dx01), .b(dx11), .t(wy_reg), .y(dxy1_next)
        );

        // stage 5: gxl = lerp(dxy0, dxy1, wz); gyl = lerp(e10 - e00, e11 - e01, wz)
        reg signed [D_W-1:0]  ey0, ey1;
        always @* begin
            ey0 = e10_reg - e00_reg;        // operands sign-extended to D_W bits: exact
            ey1 = e11_reg - e01_reg;
        end
        wire signed [D_W-1:0] gxl_next, gyl_next;
        lerp #(.W(D_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_gx (
            .clk(clk), .ce(ce), .a(dxy0_reg), .b(dxy1_reg), .t(wz4_reg), .y(gxl_next)
        );
        lerp #(.W(D_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_gy (
            .clk(clk), .ce(ce), .a(ey0), .b(ey1), .t(wz4_reg), .y(gyl_next)
        );

        // stage 6: g_j = (gl_j dw_j) >> P_FRAC, gl_z = fz1 - fz0 (linear: dw = 1, g = gl)
        reg signed [D_W-1:0]  glz;
        reg signed [GN_W-1:0] gx_next, gy_next, gz_next;
        if (CUBIC) begin : g_cubic
            // |g| <= 3 * 2^N_FRAC fits GN_W bits; the rest of sh are sign copies
            /* verilator lint_off UNUSEDSIGNAL */
            reg signed [D_W+BW-1:0] sh;
            /* verilator lint_on UNUSEDSIGNAL */
            always @* begin
                glz = fz1_reg - fz0_reg;        // sign-extended to D_W bits: exact
                sh  = (gxl_reg * $signed(dw5_reg[0*BW +: BW])) >>> P_FRAC;  // exact product
                gx_next = sh[GN_W-1:0];
                sh  = (gyl_reg * $signed(dw5_reg[1*BW +: BW])) >>> P_FRAC;
                gy_next = sh[GN_W-1:0];
                sh  = (glz * $signed(dw5_reg[2*BW +: BW])) >>> P_FRAC;
                gz_next = sh[GN_W-1:0];
            end
        end else begin : g_linear
            // dw = 2^P_FRAC: (gl dw) >> P_FRAC = gl
            always @* begin
                glz = fz1_reg - fz0_reg;        // sign-extended to D_W bits: exact
                gx_next = gxl_reg;
                gy_next = gyl_reg;
                gz_next = glz;
            end
        end

        // FPGA_REGS: the slopes beside the lerps' extra registers (stages 4, 5), and g
        // beside the z lerp's (stage 6)
        wire [3*BW-1:0]        dw3_p, dw4_p;
        wire signed [GN_W-1:0] gx_p, gy_p, gz_p;
        delay_line #(.W(3*BW), .N(LP))   u_dly_dw3 (.clk(clk), .rst(rst), .ce(ce), .d_in(dw3_reg), .d_out(dw3_p));
        delay_line #(.W(3*BW), .N(LP))   u_dly_dw4 (.clk(clk), .rst(rst), .ce(ce), .d_in(dw4_reg), .d_out(dw4_p));
        delay_line #(.W(3*GN_W), .N(LP)) u_dly_g (.clk(clk), .rst(rst), .ce(ce), .d_in({gx_next, gy_next, gz_next}),
                                                 .d_out({gx_p, gy_p, gz_p}));

        // stage 7: h_k = (sum_j g_j T_jk) >> H_SHIFT; h fits H_W bits (model/hw/config.py
        // bound), the rest of the word are sign copies
        reg [3*H_W-1:0]         h_next;
        /* verilator lint_off UNUSEDSIGNAL */
        reg signed [HX_W-1:0]   hsum;
        /* verilator lint_on UNUSEDSIGNAL */
        if (AFFINE) begin : g_h_affine
            always @* begin
                hsum = ((gx_reg * $signed(tc_s7[0*T_W +: T_W]) + gy_reg * $signed(tc_s7[3*T_W +: T_W])
                       + gz_reg * $signed(tc_s7[6*T_W +: T_W])) <<< H_L) >>> H_R;
                h_next[0*H_W +: H_W] = hsum[H_W-1:0];
                hsum = ((gx_reg * $signed(tc_s7[1*T_W +: T_W]) + gy_reg * $signed(tc_s7[4*T_W +: T_W])
                       + gz_reg * $signed(tc_s7[7*T_W +: T_W])) <<< H_L) >>> H_R;
                h_next[1*H_W +: H_W] = hsum[H_W-1:0];
                hsum = ((gx_reg * $signed(tc_s7[2*T_W +: T_W]) + gy_reg * $signed(tc_s7[5*T_W +: T_W])
                       + gz_reg * $signed(tc_s7[8*T_W +: T_W])) <<< H_L) >>> H_R;
                h_next[2*H_W +: H_W] = hsum[H_W-1:0];
            end
        end else begin : g_h_pow2
            // g_k T_kk = g_k << e_k, or 0
            always @* begin
                hsum = {{(HX_W-GN_W){gx_reg[GN_W-1]}}, gx_reg};
                hsum = tc_s7[0*(E_W+1) + E_W] ? {HX_W{1'b0}} : (hsum <<< tc_s7[0*(E_W+1) +: E_W]);
                hsum = (hsum <<< H_L) >>> H_R;
                h_next[0*H_W +: H_W] = hsum[H_W-1:0];
                hsum = {{(HX_W-GN_W){gy_reg[GN_W-1]}}, gy_reg};
                hsum = tc_s7[1*(E_W+1) + E_W] ? {HX_W{1'b0}} : (hsum <<< tc_s7[1*(E_W+1) +: E_W]);
                hsum = (hsum <<< H_L) >>> H_R;
                h_next[1*H_W +: H_W] = hsum[H_W-1:0];
                hsum = {{(HX_W-GN_W){gz_reg[GN_W-1]}}, gz_reg};
                hsum = tc_s7[2*(E_W+1) + E_W] ? {HX_W{1'b0}} : (hsum <<< tc_s7[2*(E_W+1) +: E_W]);
                hsum = (hsum <<< H_L) >>> H_R;
                h_next[2*H_W +: H_W] = hsum[H_W-1:0];
            end
        end

        // stage 8: ag_k = (a h_k) >> A_FRAC; ag fits AG_W bits (model/hw/config.py bound),
        // the rest of the product are sign copies
        reg [3*AG_W-1:0]        ag_next;
        /* verilator lint_off UNUSEDSIGNAL */
        reg signed [AGP_W-1:0]  agp;
        /* verilator lint_on UNUSEDSIGNAL */
        if (AMP_POW2) begin : g_ag_pow2
            // a h_k = sign(a) h_k << e (0 when a = 0)
            reg signed [H_W-1:0] h_k;
            reg signed [H_W:0]   h_ext;
            always @* begin
                h_k   = h_reg[0*H_W +: H_W];
                h_ext = {h_k[H_W-1], h_k};    // sign-extended: even the most negative word negates
                h_ext = ac_s8[EA_W + 1] ? {(H_W+1){1'b0}} : (ac_s8[EA_W] ? -h_ext : h_ext);
                agp   = ({{(AGP_W-H_W-1){h_ext[H_W]}}, h_ext} <<< ac_s8[EA_W-1:0]) >>> A_FRAC;
                ag_next[0*AG_W +: AG_W] = agp[AG_W-1:0];
                h_k   = h_reg[1*H_W +: H_W];
                h_ext = {h_k[H_W-1], h_k};
                h_ext = ac_s8[EA_W + 1] ? {(H_W+1){1'b0}} : (ac_s8[EA_W] ? -h_ext : h_ext);
                agp   = ({{(AGP_W-H_W-1){h_ext[H_W]}}, h_ext} <<< ac_s8[EA_W-1:0]) >>> A_FRAC;
                ag_next[1*AG_W +: AG_W] = agp[AG_W-1:0];
                h_k   = h_reg[2*H_W +: H_W];
                h_ext = {h_k[H_W-1], h_k};
                h_ext = ac_s8[EA_W + 1] ? {(H_W+1){1'b0}} : (ac_s8[EA_W] ? -h_ext : h_ext);
                agp   = ({{(AGP_W-H_W-1){h_ext[H_W]}}, h_ext} <<< ac_s8[EA_W-1:0]) >>> A_FRAC;
                ag_next[2*AG_W +: AG_W] = agp[AG_W-1:0];
            end
        end else begin : g_ag_any
            always @* begin
                agp   = ($signed(ac_s8) * $signed(h_reg[0*H_W +: H_W])) >>> A_FRAC;
                ag_next[0*AG_W +: AG_W] = agp[AG_W-1:0];
                agp   = ($signed(ac_s8) * $signed(h_reg[1*H_W +: H_W])) >>> A_FRAC;
                ag_next[1*AG_W +: AG_W] = agp[AG_W-1:0];
                agp   = ($signed(ac_s8) * $signed(h_reg[2*H_W +: H_W])) >>> A_FRAC;
                ag_next[2*AG_W +: AG_W] = agp[AG_W-1:0];
            end
        end

        always @(posedge clk) begin
            if (ce) begin
                dw3_reg  <= {dwz_next, dwy_next, dwx_next};
                dw4_reg  <= dw3_p;
                dw5_reg  <= dw4_p;
                dxy0_reg <= dxy0_next;
                dxy1_reg <= dxy1_next;
                gxl_reg  <= gxl_next;
                gyl_reg  <= gyl_next;
                gx_reg   <= gx_p;
                gy_reg   <= gy_p;
                gz_reg   <= gz_p;
                h_reg    <= h_next;
            end
            if (rst) begin
                ag_reg <= {3*AG_W{1'b0}};
            end else if (ce && valid_reg[STAGES-2]) begin
                ag_reg <= ag_next;
            end
        end
        assign ag_out = ag_reg;
    end else begin : g_no_grad
        assign ag_out = {3*AG_W{1'b0}};
    end
endgenerate

endmodule

`default_nettype wire
