/*
 * sat_integral_serial: sat_integral's share of one window end for ONE channel a clock (issue 27's
 * colour-map fold, measured before it is built in; not in rtl/, not in any configuration):
 *   p_out = (csat[kk-1][ch] << XF) + fr clut[kk][ch]    (mod 2^D_W)
 *   e_out = k_in * q_in[ch]                             (mod 2^TW, TW = D_W - XF)
 * for the channel ch_in, the other inputs as sat_integral's (held for a pixel's four clocks,
 * ch_in = 0, 1, 2, 3). The values are sat_integral's channel ch_in (PIPE = 0).
 * Formats: c_in RGBA8 (channel c at [8c +: 8]); before_in 4 x u{CS_W}.0 (0 when first_in);
 * fr_in u{XF}.{XF}; k_in s{KW}.0; q_in 4 x u{QW}.0; p_out u{D_W}.{XF}; e_out u{TW}.0.
 * Latency 1 (outputs registered, not reset); one channel an enabled clock, a pixel every 4.
 */

`default_nettype none

module sat_integral_serial #(
    parameter XF   = 17,          // fraction bits of fr and of p
    parameter KW   = 18,          // width of k_in (signed)
    parameter QW   = 8,           // width of each q
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

wire [7:0]      c = c_in[8*ch_in +: 8];
wire [CS_W-1:0] b = first_in ? {CS_W{1'b0}} : before_in[CS_W*ch_in +: CS_W];
wire [QW-1:0]   q = q_in[QW*ch_in +: QW];
wire [XF+7:0]   m = fr_in * c;

reg [D_W-1:0] p_reg;
reg [TW-1:0]  e_reg;
always @(posedge clk) begin
    if (ce) begin
        /* verilator lint_off WIDTH */  // both addends zero-extended to D_W on purpose
        p_reg <= {b, {XF{1'b0}}} + m;
        /* verilator lint_on WIDTH */
        e_reg <= $signed(k_in) * $signed({1'b0, q});
    end
end

assign p_out = p_reg;
assign e_out = e_reg;

endmodule

`default_nettype wire
