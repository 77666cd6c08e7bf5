// sat_integral: one window end's share of the box-filter integral, per channel:
//   p_out = (csat[kk-1] << XF) + fr clut[kk]       (mod 2^D_W)
//   e_out = k_in * q_in                            (mod 2^TW, TW = D_W - XF)
// p is the part of I(x) (sat_index) within the entry, e a whole-entry product: colour_map
// feeds the multiplier k_in * q_in with kx * clut[kk] (clamp: entries past an edge) or,
// in mod mode, with (kx_b - kx_a) times one byte of total (whole tables), so that the two
// ends' multipliers together form D = I(b) - I(a) without a third one.
//
// Inputs: c_in = clut[kk] (RGBA8, channel c at [8c +: 8]); before_in = csat[kk-1]
// (4 x u{CS_W}.0, channel c at [c*CS_W +: CS_W]), forced to 0 when first_in (kk == 0);
// fr_in u{XF}.{XF}; k_in s{KW}.0; q_in 4 x u{QW}.0 (channel c at [c*QW +: QW]).
// Outputs: p_out 4 x u{D_W}.{XF} (channel c at [c*D_W +: D_W]), e_out 4 x u{TW}.0
// (channel c at [c*TW +: TW]), both modulo a power of two on purpose: colour_map uses
// only D = I(b) - I(a), 0 <= D <= 255 * 2w < 2^D_W, and + - * commute with mod 2^D_W, so D
// comes out exact.
// Latency 1 + PIPE (outputs registered, not reset: an internal stage of colour_map); PIPE = 1
// (colour_map's FPGA_REGS) registers the products fr clut[kk] and k q and csat[kk-1] before the
// sum p (the multipliers' outputs, not their sum, end the first stage); one vector per
// enabled clock.
// Written for simulation speed: the four channels computed in one clocked process (blocking
// temporaries) only on an enabled clock (cmap_sat enables it only on the clocks that bring
// it a valid pixel), no bus driven piecewise.
// Each such process first assigns its temporaries whole, outside any if, so that they are
// C++ locals in the Verilator model (it localizes only a variable wholly assigned outside
// any branch; one first assigned under the if stays a member of the model, a store on every
// write).

`default_nettype none

module sat_integral #(
    parameter XF   = 17,                     // fraction bits of fr and of p
    parameter KW   = 18,                     // width of k_in (signed)
    parameter QW   = 8,                      // width of q_in (colour_map: max(8, CSAT_W - 8))
    parameter CS_W = 16,                     // csat channel width
    parameter D_W  = 41,                     // width of p (mod 2^D_W); D_W >= CS_W + XF, XF + 8
    parameter PIPE = 0,                      // 1: a register stage between the products and p
    parameter TW   = D_W - XF                // width of e (derived: do not override)
) (
    input  wire              clk,
    input  wire              ce,
    input  wire [31:0]       c_in,
    input  wire [4*CS_W-1:0] before_in,
    input  wire              first_in,
    input  wire [XF-1:0]     fr_in,
    input  wire [KW-1:0]     k_in,       // signed
    input  wire [4*QW-1:0]   q_in,
    output wire [4*D_W-1:0]  p_out,
    output wire [4*TW-1:0]   e_out
);

// the products and csat[kk-1], all four channels, computed in the clocked process below
// (blocking temporaries) only on an enabled clock: PIPE = 0 registers p and e; PIPE = 1
// registers the products fr clut[kk] (XF + 8 bits each), csat[kk-1] (CS_W bits each) and e
// (stage 1), then p = (csat[kk-1] << XF) + fr clut[kk] (stage 2). Every register and
// temporary is only as wide as its value (no bits constant by construction).
localparam M_W = XF + 8;                     // fr clut[kk] < 2^XF 2^8
integer              ch;
reg     [CS_W-1:0]   b_x;   // csat[kk-1], 0 when first_in
/* verilator lint_off UNUSEDSIGNAL */  // PIPE = 0 reads p_nx, PIPE = 1 b_nx and m_nx
reg     [4*CS_W-1:0] b_nx;
reg     [4*M_W-1:0]  m_nx;
reg     [4*D_W-1:0]  p_nx;
/* verilator lint_on UNUSEDSIGNAL */
reg     [4*TW-1:0]   e_nx;

reg [4*D_W-1:0] p_reg;
reg [4*TW-1:0]  e_reg;
// PIPE = 1: stage 1's registers (PIPE = 0: not read)
/* verilator lint_off UNUSEDSIGNAL */
reg [4*CS_W-1:0] b_p;
reg [4*M_W-1:0]  m_p;
reg [4*TW-1:0]   e_p;
/* verilator lint_on UNUSEDSIGNAL */

/* verilator lint_off BLKSEQ */
always @(posedge clk) begin
    // every temporary wholly assigned first, outside the if (C++ locals: the header)
    b_x  = {CS_W{1'b0}};
    b_nx = {(4*CS_W){1'b0}};
    m_nx = {(4*M_W){1'b0}};
    p_nx = {(4*D_W){1'b0}};
    e_nx = {(4*TW){1'b0}};
    if (ce) begin
        for (ch = 0; ch < 4; ch = ch + 1) begin
            b_x = first_in ? {CS_W{1'b0}} : before_in[ch*CS_W +: CS_W];
            b_nx[ch*CS_W +: CS_W] = b_x;
            m_nx[ch*M_W +: M_W]   = fr_in * c_in[8*ch +: 8];
            // k sign-extended times q zero-extended, mod 2^TW
            e_nx[ch*TW +: TW]     = $signed(k_in) * $signed({1'b0, q_in[ch*QW +: QW]});
            // PIPE = 0: p itself; PIPE = 1: stage 1's registered words summed (stage 2);
            // both addends zero-extended to D_W on purpose
            /* verilator lint_off WIDTH */
            p_nx[ch*D_W +: D_W]   = (PIPE == 0)
                ? {b_x, {XF{1'b0}}} + m_nx[ch*M_W +: M_W]
                : {b_p[ch*CS_W +: CS_W], {XF{1'b0}}} + m_p[ch*M_W +: M_W];
            /* verilator lint_on WIDTH */
        end
        if (PIPE == 0) begin
            p_reg <= p_nx;
            e_reg <= e_nx;
        end else begin
            b_p   <= b_nx;
            m_p   <= m_nx;
            e_p   <= e_nx;
            p_reg <= p_nx;
            e_reg <= e_p;
        end
    end
end
/* verilator lint_on BLKSEQ */

assign p_out = p_reg;
assign e_out = e_reg;

endmodule

`default_nettype wire
