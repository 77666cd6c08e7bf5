// sat2_integral: one window end's integrals for the trapezoid filter (cmap_sat2), per channel;
// the bit-exact twin of model/hw/golden.py sat2_integral (docs/numerics.md, "The trapezoid").
// With S(x) = integral_0^x C and G(x) = integral_0^x S of the colour function C (mod or
// clamp), at an end x = k + fr 2^-XF entries (sat_index: kk, first, fr, kx):
//   t  = {kx, fr} = kx 2^XF + fr (clamp: the first or last entry extended over the kx entries
//        past it, so no whole-entry term) or fr (mod: m = kx whole tables before x)
//   v1 = S(x) 2^XF   = (csat << XF) + t clut [+ (m T) << XF]
//   v2 = 2G(x) 2^2XF = (H << (2XF + 1)) + ((2t - 2^XF) csat << XF) + t^2 clut
//                      [+ (m (T (N (m - 1) - 1 + 2 kk) + 2 HT)) << 2XF + (m T fr) << (XF + 1)]
//   (csat = csat[kk-1], H = csat2[kk-1], both 0 when first; clut = clut[kk]; T = total,
//   HT = total2; N = 2^n_log2; the bracketed terms in mod mode only: the whole tables before x,
//   a quadratic term per table)
// both modulo 2^D_W on purpose: cmap_sat2 uses only their four-point differences, which are
// exact (0 <= Gamma <= 2040 ab < 2^D_W) because + - * commute with mod 2^D_W.
// Computed with the modes sharing their products (the same words: in clamp m = 0 and t^2 clut
// = fr^2 clut + 2 kx fr clut 2^XF + kx^2 clut 2^2XF), k = kx, Z = clamp ? clut : T:
//   v1 = (csat << XF) + fr clut + (k Z) << XF
//   v2 = (H << (2XF + 1)) + ((2 fr - 2^XF) csat << XF) + fr^2 clut + (k Z fr) << (XF + 1)
//        + (k I) << 2XF,  I = clamp ? 2 csat + k Z : ((k Z - T) << n_log2) + T (2 kk - 1) + 2 HT
// every product on its operands' own widths, kept mod the power of two its term needs (the term's
// shift fills the rest: k Z fr mod 2^(D_W - XF - 1), k I mod 2^(D_W - 2XF), ...), so no
// multiplier is D_W bits wide or depends on kx twice.
// Inputs: c_in RGBA8 (channel c at [8c +: 8]); cs_in 4 x u{CS_W}; h_in 4 x u{CS2_W}; total_in,
// total2_in likewise; first_in; fr_in u{XF}.{XF}; kx_in s{KW}.0; kk_in u{NMAX}; mode (0 mod, 1
// clamp); n_log2 u{NL_W}.
// Outputs: v1_out, v2_out, 4 x u{D_W} (channel c at [c*D_W +: D_W]).
// Latency 1 + PIPE (outputs registered, not reset: an internal stage of cmap_sat2); PIPE = 1
// (FPGA_REGS) registers the terms (the multipliers' outputs) before their sums; one vector per
// enabled clock.
// Written for event-driven simulation speed: the four channels in one always @* and one
// clocked process, no bus driven piecewise.

`default_nettype none

module sat2_integral #(
    parameter XF    = 14,                   // fraction bits of fr
    parameter KW    = 14,                   // width of kx (signed): X2_W - XF
    parameter NMAX  = 8,                    // log2 of the largest table (kk's width)
    parameter NL_W  = 4,                    // width of n_log2
    parameter CS_W  = 16,                   // csat channel width
    parameter CS2_W = 24,                   // csat2 channel width
    parameter D_W   = 59,                   // width of v1, v2 (mod 2^D_W)
    parameter PIPE  = 0                     // 1: a register stage between the terms and the sums
) (
    input  wire               clk,
    input  wire               ce,
    input  wire [31:0]        c_in,
    input  wire [4*CS_W-1:0]  cs_in,
    input  wire [4*CS2_W-1:0] h_in,
    input  wire [4*CS_W-1:0]  total_in,
    input  wire [4*CS2_W-1:0] total2_in,
    input  wire               first_in,
    input  wire [XF-1:0]      fr_in,
    input  wire [KW-1:0]      kx_in,      // signed
    input  wire [NMAX-1:0]    kk_in,
    input  wire               mode,       // 0 mod, 1 clamp
    input  wire [NL_W-1:0]    n_log2,
    output wire [4*D_W-1:0]   v1_out,
    output wire [4*D_W-1:0]   v2_out
);

localparam NT = 8;                          // terms a channel: 3 of v1, 5 of v2
localparam MW = KW + CS_W + 1;              // k Z (signed, exact)
localparam YW = D_W - XF;                   // (2 fr - 2^XF) csat, mod 2^YW
localparam QW = D_W - 2 * XF;               // k I, mod 2^QW
localparam EW = D_W - XF - 1;               // k Z fr, mod 2^EW

generate
    if (D_W > 64 || KW + XF > D_W || 2 * XF + 1 + CS2_W < 1 || CS_W < 9 || MW > D_W || 2 * XF + 8 >= D_W
        || CS_W + 1 + XF >= D_W || QW < 1) begin : g_bad_params
        sat2_integral_unsupported_widths u_error ();
    end
endgenerate

// the terms of the four channels (PIPE = 1: registered before the sums)
reg [4*NT*D_W-1:0] term_nx;
// loop temporaries: two's complement, each product formed at the width of the word it is
// assigned to (signed operands sign-extended, the result cut mod 2^width on purpose)
integer                 ch;
reg signed [KW-1:0]     k;            // kx
reg signed [XF:0]       fs;           // fr, as a non-negative signed word
reg signed [XF+1:0]     y;            // 2 fr - 2^XF
reg [2*XF-1:0]          f2;           // fr^2
reg signed [NMAX+1:0]   kk21;         // 2 kk - 1
reg signed [CS_W:0]     cs, tt, z;    // csat[kk-1] (0 when first), T, Z = clamp ? clut : T
reg signed [CS2_W+1:0]  ht2;          // 2 HT
reg [D_W-1:0]           h;            // H (0 when first)
reg signed [MW-1:0]     kz;           // k Z
reg signed [MW:0]       kzt;          // k Z - T
reg signed [QW-1:0]     ii, r;        // I, k I (mod 2^QW)
reg signed [EW-1:0]     kzf;          // k Z fr (mod 2^EW)
reg signed [YW-1:0]     ycs;          // (2 fr - 2^XF) csat (mod 2^YW)
reg [XF+7:0]            fc;           // fr clut
reg [2*XF+7:0]          f2c;          // fr^2 clut
reg signed [D_W-1:0]    kzx;          // k Z, sign-extended
/* verilator lint_off WIDTH */
always @* begin
    k = kx_in;
    fs = {1'b0, fr_in};
    y = $signed({1'b0, fr_in, 1'b0}) - $signed({2'b01, {XF{1'b0}}});
    f2 = fr_in * fr_in;
    kk21 = {1'b0, kk_in, 1'b0} - 1'b1;
    for (ch = 0; ch < 4; ch = ch + 1) begin
        cs = {(CS_W+1){1'b0}};
        h = {D_W{1'b0}};
        if (!first_in) begin
            cs[CS_W-1:0] = cs_in[ch*CS_W +: CS_W];
            h[CS2_W-1:0] = h_in[ch*CS2_W +: CS2_W];
        end
        tt = {1'b0, total_in[ch*CS_W +: CS_W]};
        ht2 = {1'b0, total2_in[ch*CS2_W +: CS2_W], 1'b0};
        z = mode ? {{(CS_W-8){1'b0}}, 1'b0, c_in[8*ch +: 8]} : tt;
        kz = k * z;
        kzt = kz - tt;
        if (mode)
            ii = (cs <<< 1) + kz;
        else
            ii = (kzt <<< n_log2) + tt * kk21 + ht2;
        r = k * ii;
        kzf = kz * fs;
        ycs = y * cs;
        fc = fr_in * c_in[8*ch +: 8];
        f2c = f2 * c_in[8*ch +: 8];
        kzx = kz;
        // v1: csat << XF, fr clut, (k Z) << XF
        term_nx[(ch*NT + 0)*D_W +: D_W] = {{(D_W-CS_W-1-XF){1'b0}}, cs, {XF{1'b0}}};
        term_nx[(ch*NT + 1)*D_W +: D_W] = {{(D_W-XF-8){1'b0}}, fc};
        term_nx[(ch*NT + 2)*D_W +: D_W] = kzx << XF;
        // v2: H << (2XF + 1), ((2 fr - 2^XF) csat) << XF, fr^2 clut, (k I) << 2XF, (k Z fr) << (XF + 1)
        term_nx[(ch*NT + 3)*D_W +: D_W] = h << (2*XF + 1);
        term_nx[(ch*NT + 4)*D_W +: D_W] = {ycs, {XF{1'b0}}};
        term_nx[(ch*NT + 5)*D_W +: D_W] = {{(D_W-2*XF-8){1'b0}}, f2c};
        term_nx[(ch*NT + 6)*D_W +: D_W] = {r, {(2*XF){1'b0}}};
        term_nx[(ch*NT + 7)*D_W +: D_W] = {kzf, {(XF+1){1'b0}}};
    end
end
/* verilator lint_on WIDTH */

wire [4*NT*D_W-1:0] term;
generate
    if (PIPE) begin : g_pipe
        reg [4*NT*D_W-1:0] term_reg;
        always @(posedge clk) begin
            if (ce)
                term_reg <= term_nx;
        end
        assign term = term_reg;
    end else begin : g_comb
        assign term = term_nx;
    end
endgenerate

reg [4*D_W-1:0] v1_nx, v2_nx;
integer         cs2;
always @* begin
    for (cs2 = 0; cs2 < 4; cs2 = cs2 + 1) begin
        v1_nx[cs2*D_W +: D_W] = term[(cs2*NT + 0)*D_W +: D_W] + term[(cs2*NT + 1)*D_W +: D_W]
                              + term[(cs2*NT + 2)*D_W +: D_W];
        v2_nx[cs2*D_W +: D_W] = term[(cs2*NT + 3)*D_W +: D_W] + term[(cs2*NT + 4)*D_W +: D_W]
                              + term[(cs2*NT + 5)*D_W +: D_W] + term[(cs2*NT + 6)*D_W +: D_W]
                              + term[(cs2*NT + 7)*D_W +: D_W];
    end
end

reg [4*D_W-1:0] v1_reg, v2_reg;
always @(posedge clk) begin
    if (ce) begin
        v1_reg <= v1_nx;
        v2_reg <= v2_nx;
    end
end

assign v1_out = v1_reg;
assign v2_out = v2_reg;

endmodule

`default_nettype wire
