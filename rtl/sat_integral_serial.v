// sat_integral_serial: sat_integral's share of one window end for ONE channel an enabled clock
// (colour_map's fold, features.cmap_clocks = 4: cmap_sat takes a pixel's four channels on four
// clocks through one of these at each window end instead of two four-channel sat_integral);
// the bit-exact twin of model/hw/golden.py sat_integral_serial:
//   p_out = (csat[kk-1][ch] << XF) + fr clut[kk][ch]    (mod 2^D_W)
//   e_out = k_in * q_in[ch]                             (mod 2^TW, TW = D_W - XF)
// for the channel ch = ch_in; the values are sat_integral's channel ch (PIPE = 0).
//
// Inputs: as sat_integral's, held by the caller for a pixel's four clocks while ch_in steps
// 0, 1, 2, 3: c_in = clut[kk] (RGBA8, channel c at [8c +: 8]); before_in = csat[kk-1]
// (4 x u{CS_W}.0, channel c at [c*CS_W +: CS_W]), read as 0 when first_in (kk == 0); fr_in
// u{XF}.{XF}; k_in s{KW}.0; q_in 4 x u{QW}.0 (channel c at [c*QW +: QW]).
// Outputs: p_out u{D_W}.{XF}, e_out u{TW}.0 of one channel, modulo a power of two on purpose
// (sat_integral's header: colour_map uses only D = I(b) - I(a), which comes out exact).
// Latency 1 (outputs registered, not reset: an internal stage of cmap_sat); one channel an
// enabled clock (cmap_sat enables it only on the four clocks of a pixel's channels), a pixel
// every four.
// Written for simulation speed: the channel's products computed in the clocked process
// (blocking temporaries) only on an enabled clock; the temporaries first assigned whole,
// outside the if, so that they are C++ locals in the Verilator model.

`default_nettype none

module sat_integral_serial #(
    parameter XF   = 17,          // fraction bits of fr and of p
    parameter KW   = 18,          // width of k_in (signed)
    parameter QW   = 8,           // width of each q (colour_map: max(8, CSAT_W - 8))
    parameter CS_W = 16,          // csat channel width
    parameter D_W  = 41,          // width of p (mod 2^D_W); D_W >= CS_W + XF, XF + 8
    parameter TW   = D_W - XF     // width of e (derived: do not override)
) (
    input  wire              clk,
    input  wire              ce,
    input  wire [1:0]        ch_in,
    input  wire [31:0]       c_in,
    input  wire [4*CS_W-1:0] before_in,
    input  wire              first_in,
    input  wire [XF-1:0]     fr_in,
    input  wire [KW-1:0]     k_in,       // signed
    input  wire [4*QW-1:0]   q_in,
    output wire [D_W-1:0]    p_out,
    output wire [TW-1:0]     e_out
);

localparam M_W = XF + 8;    // fr clut[kk][ch] < 2^XF 2^8

reg [7:0]      c_x;         // clut[kk][ch]
reg [CS_W-1:0] b_x;         // csat[kk-1][ch], 0 when first_in
reg [QW-1:0]   q_x;         // q[ch]
reg [M_W-1:0]  m_x;         // fr clut[kk][ch]

reg [D_W-1:0]  p_reg;
reg [TW-1:0]   e_reg;

/* verilator lint_off BLKSEQ */
always @(posedge clk) begin
    // every temporary wholly assigned first, outside the if (C++ locals: the header)
    c_x = 8'd0;
    b_x = {CS_W{1'b0}};
    q_x = {QW{1'b0}};
    m_x = {M_W{1'b0}};
    if (ce) begin
        c_x = c_in[8*ch_in +: 8];
        b_x = first_in ? {CS_W{1'b0}} : before_in[CS_W*ch_in +: CS_W];
        q_x = q_in[QW*ch_in +: QW];
        m_x = fr_in * c_x;
        // both addends zero-extended to D_W on purpose
        /* verilator lint_off WIDTH */
        p_reg <= {b_x, {XF{1'b0}}} + m_x;
        /* verilator lint_on WIDTH */
        // k sign-extended times q zero-extended, mod 2^TW
        e_reg <= $signed(k_in) * $signed({1'b0, q_x});
    end
end
/* verilator lint_on BLKSEQ */

assign p_out = p_reg;
assign e_out = e_reg;

endmodule

`default_nettype wire
