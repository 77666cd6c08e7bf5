// noise_grad: the texture-space gradient of one noise term, a (dn/dp) T, beside noise_term's
// value path (stages 4..8 of noise_term), from the value path's own intermediate values:
//   dx_jk = v1jk - v0jk,  g_x = (lerp(lerp(dx00, dx10, wy), lerp(dx01, dx11, wy), wz) dw_x) >> P_FRAC
//   g_y   = (lerp(e10 - e00, e11 - e01, wz) dw_y) >> P_FRAC,  g_z = ((fz1 - fz0) dw_z) >> P_FRAC
//   h_k   = (sum_j g_j T_jk) >> (H_SHIFT - te),  ag_k = (a h_k) >> (A_FRAC - ae)
// (">>" a floor; a negative shift count a left shift; BLEND linear: dw = 1, g_j is the lerped
// difference). Stages 6, 7 and 8 are written once for the three axes (g_axis). The bit-exact
// twin is model/hw/golden.py noise_grad(cfg, a, T, v, e, fz, wy, wz, dw, te, ae).
//
// Block floating point ([t_exp_w] T_EXP_W, [a_exp_w] A_EXP_W > 0; docs/numerics.md "Block
// floating point"): t_in and a_in are the term's mantissas (T = M 2^(te - T_FRAC), a = A
// 2^(ae - A_FRAC)) and te, ae its exponents: h_k = ((sum_j g_j M_jk) << te) >> H_SHIFT and
// ag_k = ((A h_k) << ae) >> A_FRAC, floor shifts right by H_SHIFT - te >= 0 and A_FRAC - ae >=
// 0 (model/hw/config.py checks H_SHIFT >= 2^T_EXP_W - 1 and A_FRAC >= 2^A_EXP_W - 1, and so
// does the elaboration below); the products keep their T_W and A_W bit mantissas, the
// shifted words TE_MAX (AE_MAX) bits more. At 0 (no exponent: te, ae one bit each, not read)
// the block is as it was.
//
// Formats (derived widths from rtl/tex_widths.vh, as noise_term's):
//   v      8 x s{N_W}.{N_FRAC}, corner (i, j, k) at element 4*i + 2*j + k (the lattice values)
//   e      4 x s{N_W}.{N_FRAC}, e[j][k] = lerp(v0jk, v1jk, wx) at element 2*j + k; fz 2 x, fz[k]
//   wy, wz s{BW}.{P_FRAC}, dw 3 x s{BW}.{P_FRAC} {z, y, x} (noise_blend's weights, slopes)
//   t_in   T as noise_term decodes it: affine 9 x s{T_W}.{T_FRAC}, T[j][k] at element 3*j + k;
//          pow2 3 x {zero, e} of T_jj (E_W + 1 bits, entry j at element j): g_k T_kk = g_k << e
//   a_in   a as noise_term decodes it: any s{A_W}.{A_FRAC}; pow2 {zero, neg, e} (noise_term's
//          header: sign(a) h_k << e, exact)
//   te     u{T_EXP_W}, ae u{A_EXP_W} (one bit each, ignored, when 0)
//   ag_out 3 x s{AG_W}.{C_FRAC}, component k at element k
//   Internal: differences s{N_W+1}.{N_FRAC}, g s{GN_W}.{N_FRAC}, h s{H_W}.{C_FRAC + A_FRAC}
//   (H_W and AG_W for the largest exponents, rtl/tex_widths.vh tw_h_w_e, tw_ag_w_e).
// Timing: the inputs of one vector arrive at the stages that read them, counted in enabled
// clocks after v, wy, dw (noise_term's stage 3 registers): e, wz 1 + LP later, fz 2 + 2 LP,
// t_in and te 3 + 3 LP, a_in, ae and load 4 + 3 LP (LP = 2 with FPGA_REGS, else 0: each lerp's extra
// registers). ag_out holds the vector LATENCY = `LAT_NOISE_GRAD (FPGA_REGS:
// `LAT_NOISE_GRAD_FPGA = `LAT_NOISE_GRAD + 3 LP) enabled clocks after its v: stages 4 (the
// x differences' y lerps), 5 (z lerps), 6 (g; FPGA_REGS: LP more beside the z lerp), 7 (h),
// 8 (ag, the output registers, loaded when load = 1, the caller's valid bit of that stage).
// One vector per enabled clock; ce = 0 holds every register; rst clears the outputs only.
//
// Multipliers (affine, cubic, any amplitude): 4 lerps + 3 slopes + 9 g T + 3 a h.

`default_nettype none

`include "tex_latency.vh"

module noise_grad #(
    parameter T_W       = 17,  // [t_w] transform entry word s{T_W}.{T_FRAC}
    parameter T_FRAC    = 10,  // [t_frac]
    parameter A_W       = 16,  // [a_w] amplitude word s{A_W}.{A_FRAC}
    parameter A_FRAC    = 12,  // [a_frac]
    parameter P_FRAC    = 12,  // [p_frac] blend weight fraction bits
    parameter N_FRAC    = 12,  // [n_frac] noise value / gradient fraction bits
    parameter C_FRAC    = 12,  // [c_frac] fraction bits of ag_out
    parameter TRANSFORM = 0,   // [transform] 0 affine, 1 pow2 (diagonal 0 / 2^k: shifts)
    parameter BLEND     = 1,   // [blend] 0 linear (dw = 1), 1 cubic
    parameter AMPLITUDE = 0,   // [amplitude] 0 any, 1 pow2 (0 / +-2^k: shifts)
    parameter FPGA_REGS = 0,   // [fpga_regs] 1: each lerp in three stages (LP = 2)
    parameter T_EXP_W   = 0,   // [t_exp_w] T's per-term exponent te (0: none; affine only)
    parameter A_EXP_W   = 0    // [a_exp_w] a's per-term exponent ae (0: none; amplitude any only)
) (clk, rst, ce, v, wy, dw, e, wz, fz, t_in, te, a_in, ae, load, ag_out);

// (Verilator inlines this block into noise_term, whose copy of these functions it then reports
// as hidden: the same functions, not a conflict)
/* verilator lint_off VARHIDDEN */
`include "tex_widths.vh"
/* verilator lint_on VARHIDDEN */

localparam LP       = FPGA_REGS ? 2 : 0;                      // each lerp's optional register stages
localparam STAGES   = 5 + 3*LP;                               // register stages of this implementation
localparam LATENCY  = FPGA_REGS ? `LAT_NOISE_GRAD_FPGA : `LAT_NOISE_GRAD;  // must equal STAGES
localparam AFFINE   = (TRANSFORM == 0);
localparam CUBIC    = (BLEND == 1);
localparam AMP_POW2 = (AMPLITUDE == 1);
localparam N_W      = tw_bits_signed(64'd1 << N_FRAC);        // n in [-1, 1]
localparam D_W      = N_W + 1;                                // difference of two lattice-range values
localparam GN_W     = tw_bits_signed(3 * (64'd1 << N_FRAC));  // |dn/dp| <= 2 * 1.5
localparam BW       = P_FRAC + 2;                             // blend weight / slope, [0, 1.5]
localparam TE_MAX   = (1 << T_EXP_W) - 1;                    // the largest exponents
localparam AE_MAX   = (1 << A_EXP_W) - 1;
localparam TE_W     = (T_EXP_W > 0) ? T_EXP_W : 1;            // te, ae (not read when 0)
localparam AE_W     = (A_EXP_W > 0) ? A_EXP_W : 1;
localparam H_W      = tw_h_w_e(BLEND, TRANSFORM, T_W, T_FRAC, N_FRAC, C_FRAC, TE_MAX);
localparam AG_W     = tw_ag_w_e(BLEND, TRANSFORM, T_W, T_FRAC, N_FRAC, C_FRAC, A_W, A_FRAC, TE_MAX, AE_MAX);
localparam H_SHIFT  = N_FRAC + T_FRAC - C_FRAC;
localparam H_R      = (H_SHIFT > 0) ? H_SHIFT : 0;            // h: floor shift right by H_SHIFT,
localparam H_L      = (H_SHIFT < 0) ? -H_SHIFT : 0;           //    or left by -H_SHIFT
localparam HX_W     = GN_W + T_W + 2 + H_L + TE_MAX;          // h before its shift (<< te)
localparam E_W      = $clog2(T_W - 1);                        // pow2 T shift amount 0..T_W-2
localparam TC_W     = AFFINE ? 9*T_W : 3*(E_W + 1);           // t_in
localparam EA_W     = $clog2(A_W);                            // pow2 amplitude shift 0..A_W-1
localparam AC_W     = AMP_POW2 ? EA_W + 2 : A_W;              // a_in
localparam AGP_W    = A_W + H_W + AE_MAX;                     // a h (<< ae)

input  wire               clk;
input  wire               rst;
input  wire               ce;
input  wire [8*N_W-1:0]   v;
input  wire [BW-1:0]      wy;
/* verilator lint_off UNUSEDSIGNAL */  // linear: dw = 1, not read
input  wire [3*BW-1:0]    dw;
/* verilator lint_on UNUSEDSIGNAL */
input  wire [4*N_W-1:0]   e;
input  wire [BW-1:0]      wz;
input  wire [2*N_W-1:0]   fz;
input  wire [TC_W-1:0]    t_in;
input  wire [AC_W-1:0]    a_in;
/* verilator lint_off UNUSEDSIGNAL */  // T_EXP_W, A_EXP_W = 0: no exponents, not read
input  wire [TE_W-1:0]    te;
input  wire [AE_W-1:0]    ae;
/* verilator lint_on UNUSEDSIGNAL */
input  wire               load;
output wire [3*AG_W-1:0]  ag_out;

generate
    if (LATENCY != STAGES) begin : g_latency_mismatch
        // elaboration error on purpose: rtl/tex_latency.vh and this block disagree
        noise_grad_latency_mismatch_see_tex_latency_vh u_error ();
    end
    if (T_EXP_W < 0 || A_EXP_W < 0 || (T_EXP_W > 0 && (!AFFINE || H_SHIFT < TE_MAX))
        || (A_EXP_W > 0 && (AMP_POW2 || A_FRAC < AE_MAX))) begin : g_bad_params
        // elaboration error on purpose: an exponent needs its multiplier and a right shift
        noise_grad_exponents_need_affine_any_and_right_shifts u_error ();
    end
endgenerate

// the exponents as stages 7 and 8 read them: 0 without (the shifts by them vanish)
/* verilator lint_off UNUSEDSIGNAL */  // pow2 T (a): shifts, no exponent
wire [TE_W-1:0] te_h = (T_EXP_W > 0) ? te : {TE_W{1'b0}};
wire [AE_W-1:0] ae_h = (A_EXP_W > 0) ? ae : {AE_W{1'b0}};
/* verilator lint_on UNUSEDSIGNAL */

// stage 4: dx[j][k] = v1jk - v0jk (operands sign-extended to D_W bits: exact);
// dxy[k] = lerp(dx0k, dx1k, wy)
reg signed [D_W-1:0]  dx00, dx01, dx10, dx11;
always @* begin
    dx00 = $signed(v[4*N_W +: N_W]) - $signed(v[0*N_W +: N_W]);
    dx01 = $signed(v[5*N_W +: N_W]) - $signed(v[1*N_W +: N_W]);
    dx10 = $signed(v[6*N_W +: N_W]) - $signed(v[2*N_W +: N_W]);
    dx11 = $signed(v[7*N_W +: N_W]) - $signed(v[3*N_W +: N_W]);
end
wire signed [D_W-1:0] dxy0_next, dxy1_next;
lerp #(.W(D_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_dxy0 (
    .clk(clk), .ce(ce), .a(dx00), .b(dx10), .t(wy), .y(dxy0_next)
);
lerp #(.W(D_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_dxy1 (
    .clk(clk), .ce(ce), .a(dx01), .b(dx11), .t(wy), .y(dxy1_next)
);

// stage 5: gxl = lerp(dxy0, dxy1, wz); gyl = lerp(e10 - e00, e11 - e01, wz)
reg signed [D_W-1:0]  dxy0_reg, dxy1_reg, ey0, ey1;
always @* begin
    ey0 = $signed(e[2*N_W +: N_W]) - $signed(e[0*N_W +: N_W]);  // sign-extended to D_W bits: exact
    ey1 = $signed(e[3*N_W +: N_W]) - $signed(e[1*N_W +: N_W]);
end
wire signed [D_W-1:0] gxl_next, gyl_next;
lerp #(.W(D_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_gx (
    .clk(clk), .ce(ce), .a(dxy0_reg), .b(dxy1_reg), .t(wz), .y(gxl_next)
);
lerp #(.W(D_W), .TW(BW), .P_FRAC(P_FRAC), .PIPE(LP)) u_lerp_gy (
    .clk(clk), .ce(ce), .a(ey0), .b(ey1), .t(wz), .y(gyl_next)
);

// the slopes beside stages 4 and 5 (FPGA_REGS: beside the lerps' extra registers)
/* verilator lint_off UNUSEDSIGNAL */  // linear: dw = 1, not read
reg  [3*BW-1:0] dw4_reg, dw5_reg;
/* verilator lint_on UNUSEDSIGNAL */
wire [3*BW-1:0] dw3_p, dw4_p;
delay_line #(.W(3*BW), .N(LP)) u_dly_dw3 (.clk(clk), .rst(rst), .ce(ce), .d_in(dw), .d_out(dw3_p));
delay_line #(.W(3*BW), .N(LP)) u_dly_dw4 (.clk(clk), .rst(rst), .ce(ce), .d_in(dw4_reg), .d_out(dw4_p));

reg signed [D_W-1:0] gxl_reg, gyl_reg;
always @(posedge clk) begin
    if (ce) begin
        dxy0_reg <= dxy0_next;
        dxy1_reg <= dxy1_next;
        dw4_reg  <= dw3_p;
        dw5_reg  <= dw4_p;
        gxl_reg  <= gxl_next;
        gyl_reg  <= gyl_next;
    end
end

// Stages 6..8, once for each axis (g_axis[k]): every axis's signals stay its own (the
// registers below, read by name), not slices of one vector driven from three places, and each
// stage's block reads registers only, so that it runs once a clock (docs/simulation.md).
reg signed [GN_W-1:0] g0_reg, g1_reg, g2_reg;  // stage 6: g_j
reg signed [H_W-1:0]  h0_reg, h1_reg, h2_reg;  // stage 7: h_k
reg [AG_W-1:0]        ag0_reg, ag1_reg, ag2_reg;  // stage 8: ag_k (the output)

genvar gk;
generate
    for (gk = 0; gk < 3; gk = gk + 1) begin : g_axis
        // stage 6: g_k = (gl_k dw_k) >> P_FRAC (linear: dw = 1, g = gl), gl_k the lerped
        // difference of axis k (z: fz1 - fz0, sign-extended: exact); |g| <= 3 * 2^N_FRAC fits
        // GN_W bits, the rest of sh are sign copies
        reg signed [D_W-1:0]  gl_k;
        reg signed [GN_W-1:0] g_next;
        if (CUBIC) begin : g_cubic
            /* verilator lint_off UNUSEDSIGNAL */
            reg signed [D_W+BW-1:0] sh;
            /* verilator lint_on UNUSEDSIGNAL */
            always @* begin
                if (gk == 0)      gl_k = gxl_reg;
                else if (gk == 1) gl_k = gyl_reg;
                else              gl_k = $signed(fz[1*N_W +: N_W]) - $signed(fz[0*N_W +: N_W]);
                sh     = (gl_k * $signed(dw5_reg[gk*BW +: BW])) >>> P_FRAC;  // exact product
                g_next = sh[GN_W-1:0];
            end
        end else begin : g_linear
            always @* begin
                if (gk == 0)      gl_k = gxl_reg;
                else if (gk == 1) gl_k = gyl_reg;
                else              gl_k = $signed(fz[1*N_W +: N_W]) - $signed(fz[0*N_W +: N_W]);
                g_next = gl_k;
            end
        end
        // FPGA_REGS: g beside the z lerp's extra registers
        wire [GN_W-1:0] g_p;
        delay_line #(.W(GN_W), .N(LP)) u_dly_g (.clk(clk), .rst(rst), .ce(ce), .d_in(g_next), .d_out(g_p));

        // stage 7: h_k = (sum_j g_j T_jk) >> (H_SHIFT - te) (pow2: g_k T_kk = g_k << e_k, or 0);
        // h fits H_W bits (model/hw/config.py bound), the rest of the word are sign copies
        reg [H_W-1:0]         h_next;
        /* verilator lint_off UNUSEDSIGNAL */
        reg signed [HX_W-1:0] hsum;
        /* verilator lint_on UNUSEDSIGNAL */
        if (AFFINE) begin : g_h_affine
            // with an exponent (sum << te) >> H_SHIFT: H_SHIFT >= TE_MAX, so H_L = 0
            always @* begin
                hsum = (((g0_reg * $signed(t_in[(0+gk)*T_W +: T_W])
                        + g1_reg * $signed(t_in[(3+gk)*T_W +: T_W])
                        + g2_reg * $signed(t_in[(6+gk)*T_W +: T_W])) <<< te_h) <<< H_L) >>> H_R;
                h_next = hsum[H_W-1:0];
            end
        end else begin : g_h_pow2
            reg signed [GN_W-1:0] g_k;  // g of this axis alone
            always @* begin
                g_k    = (gk == 0) ? g0_reg : (gk == 1) ? g1_reg : g2_reg;
                hsum   = {{(HX_W-GN_W){g_k[GN_W-1]}}, g_k};
                hsum   = t_in[gk*(E_W+1) + E_W] ? {HX_W{1'b0}} : (hsum <<< t_in[gk*(E_W+1) +: E_W]);
                hsum   = (hsum <<< H_L) >>> H_R;
                h_next = hsum[H_W-1:0];
            end
        end

        // stage 8: ag_k = (a h_k) >> (A_FRAC - ae); ag fits AG_W bits (model/hw/config.py
        // bound), the rest of the product are sign copies
        reg signed [H_W-1:0]    h_k;
        reg [AG_W-1:0]          ag_next;
        /* verilator lint_off UNUSEDSIGNAL */
        reg signed [AGP_W-1:0]  agp;
        /* verilator lint_on UNUSEDSIGNAL */
        if (AMP_POW2) begin : g_ag_pow2
            // a h_k = sign(a) h_k << e (0 when a = 0); sign-extended first: even the most
            // negative word negates
            reg signed [H_W:0] h_ext;
            always @* begin
                h_k     = (gk == 0) ? h0_reg : (gk == 1) ? h1_reg : h2_reg;
                h_ext   = {h_k[H_W-1], h_k};
                h_ext   = a_in[EA_W + 1] ? {(H_W+1){1'b0}} : (a_in[EA_W] ? -h_ext : h_ext);
                agp     = ({{(AGP_W-H_W-1){h_ext[H_W]}}, h_ext} <<< a_in[EA_W-1:0]) >>> A_FRAC;
                ag_next = agp[AG_W-1:0];
            end
        end else begin : g_ag_any
            // with an exponent (a h_k << ae) >> A_FRAC: A_FRAC >= AE_MAX
            always @* begin
                h_k     = (gk == 0) ? h0_reg : (gk == 1) ? h1_reg : h2_reg;
                agp     = (($signed(a_in) * h_k) <<< ae_h) >>> A_FRAC;
                ag_next = agp[AG_W-1:0];
            end
        end
    end
endgenerate

// stages 6..8 registers of the three axes: one process
always @(posedge clk) begin
    if (ce) begin
        g0_reg <= g_axis[0].g_p;
        g1_reg <= g_axis[1].g_p;
        g2_reg <= g_axis[2].g_p;
        h0_reg <= g_axis[0].h_next;
        h1_reg <= g_axis[1].h_next;
        h2_reg <= g_axis[2].h_next;
    end
    if (rst) begin
        ag0_reg <= {AG_W{1'b0}};
        ag1_reg <= {AG_W{1'b0}};
        ag2_reg <= {AG_W{1'b0}};
    end else if (ce && load) begin
        ag0_reg <= g_axis[0].ag_next;
        ag1_reg <= g_axis[1].ag_next;
        ag2_reg <= g_axis[2].ag_next;
    end
end

// the output: the three axes' registers in one concatenation
assign ag_out = {ag2_reg, ag1_reg, ag0_reg};

endmodule

`default_nettype wire
