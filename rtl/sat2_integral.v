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

generate
    if (D_W > 64 || KW + XF > D_W || 2 * XF + 1 + CS2_W < 1) begin : g_bad_params
        sat2_integral_unsupported_widths u_error ();
    end
endgenerate

// the terms of the four channels (PIPE = 1: registered before the sums)
reg [4*NT*D_W-1:0] term_nx;
// loop temporaries, all D_W bits (two's complement mod 2^D_W)
integer         ch;
reg [D_W-1:0]   t, m, frx, c, cs, h, tt, ht, nn, kk2, tsq, mt, q;
always @* begin
    // t and m: clamp {kx, fr} and 0; mod fr and kx (sign-extended)
    frx = {D_W{1'b0}};
    frx[XF-1:0] = fr_in;
    m = {{(D_W-KW){kx_in[KW-1]}}, kx_in};
    t = mode ? ((m << XF) | frx) : frx;
    if (mode)
        m = {D_W{1'b0}};
    nn = {{(D_W-1){1'b0}}, 1'b1} << n_log2;
    kk2 = {D_W{1'b0}};
    kk2[NMAX:1] = kk_in;
    tsq = t * t;
    for (ch = 0; ch < 4; ch = ch + 1) begin
        c = {D_W{1'b0}};
        c[7:0] = c_in[8*ch +: 8];
        cs = {D_W{1'b0}};
        h = {D_W{1'b0}};
        if (!first_in) begin
            cs[CS_W-1:0] = cs_in[ch*CS_W +: CS_W];
            h[CS2_W-1:0] = h_in[ch*CS2_W +: CS2_W];
        end
        tt = {D_W{1'b0}};
        tt[CS_W-1:0] = total_in[ch*CS_W +: CS_W];
        ht = {D_W{1'b0}};
        ht[CS2_W-1:0] = total2_in[ch*CS2_W +: CS2_W];
        mt = m * tt;
        q = m * (tt * (nn * (m - 1'b1) - 1'b1 + kk2) + (ht << 1));
        // v1: csat << XF, t clut, (m T) << XF
        term_nx[(ch*NT + 0)*D_W +: D_W] = cs << XF;
        term_nx[(ch*NT + 1)*D_W +: D_W] = t * c;
        term_nx[(ch*NT + 2)*D_W +: D_W] = mt << XF;
        // v2: H << (2XF + 1), ((2t - 2^XF) csat) << XF, t^2 clut, q << 2XF, (m T fr) << (XF + 1)
        term_nx[(ch*NT + 3)*D_W +: D_W] = h << (2*XF + 1);
        term_nx[(ch*NT + 4)*D_W +: D_W] = (((t << 1) - ({{(D_W-1){1'b0}}, 1'b1} << XF)) * cs) << XF;
        term_nx[(ch*NT + 5)*D_W +: D_W] = tsq * c;
        term_nx[(ch*NT + 6)*D_W +: D_W] = q << (2*XF);
        term_nx[(ch*NT + 7)*D_W +: D_W] = (mt * frx) << (XF + 1);
    end
end

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
