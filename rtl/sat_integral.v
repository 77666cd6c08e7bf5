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
// Written for event-driven simulation speed: the four channels in one always @* and one
// clocked process, no bus driven piecewise.

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

// the products and csat[kk-1] << XF (stage 1 of PIPE = 1), all four channels
/* verilator lint_off UNUSEDSIGNAL */  // PIPE = 0 reads p0_nx, PIPE = 1 b_nx and m_nx
reg        [4*D_W-1:0] b_nx;
reg        [4*D_W-1:0] m_nx;
reg        [4*D_W-1:0] p0_nx;  // PIPE = 0: p itself (in this one always @*)
/* verilator lint_on UNUSEDSIGNAL */
reg        [4*TW-1:0]  e_nx;
// loop temporaries
integer              ch;
reg        [D_W-1:0] b_x;   // csat[kk-1] << XF
reg        [D_W-1:0] fr_x;  // fr zero-extended
reg        [D_W-1:0] c_x;   // clut[kk] zero-extended
reg signed [TW-1:0]  k_x;   // k sign-extended
reg signed [TW-1:0]  q_x;   // q zero-extended

always @* begin
    b_nx = {(4*D_W){1'b0}};
    p0_nx = {(4*D_W){1'b0}};
    m_nx = {(4*D_W){1'b0}};
    e_nx = {(4*TW){1'b0}};
    fr_x = {D_W{1'b0}};
    fr_x[XF-1:0] = fr_in;
    k_x = {TW{k_in[KW-1]}};
    k_x[KW-1:0] = k_in;
    for (ch = 0; ch < 4; ch = ch + 1) begin
        b_x = {D_W{1'b0}};
        if (!first_in)
            b_x[XF +: CS_W] = before_in[ch*CS_W +: CS_W];
        c_x = {D_W{1'b0}};
        c_x[7:0] = c_in[8*ch +: 8];
        q_x = {TW{1'b0}};
        q_x[QW-1:0] = q_in[ch*QW +: QW];
        b_nx[ch*D_W +: D_W] = b_x;
        m_nx[ch*D_W +: D_W] = fr_x * c_x;
        p0_nx[ch*D_W +: D_W] = b_x + fr_x * c_x;
        e_nx[ch*TW +: TW]   = k_x * q_x;
    end
end

// PIPE = 1: the products and csat[kk-1] registered, then summed (a block of its own)
wire [4*D_W-1:0] p_nx;
wire [4*TW-1:0]  e_p;
generate
    if (PIPE == 0) begin : g_comb
        assign p_nx = p0_nx;
        assign e_p  = e_nx;
    end else begin : g_pipe
        wire [4*D_W-1:0] b_p, m_p;
        delay_line #(.W(4*D_W), .N(1)) u_dly_b (.clk(clk), .rst(1'b0), .ce(ce), .d_in(b_nx), .d_out(b_p));
        delay_line #(.W(4*D_W), .N(1)) u_dly_m (.clk(clk), .rst(1'b0), .ce(ce), .d_in(m_nx), .d_out(m_p));
        delay_line #(.W(4*TW), .N(1))  u_dly_e (.clk(clk), .rst(1'b0), .ce(ce), .d_in(e_nx), .d_out(e_p));
        reg [4*D_W-1:0] p_sum;
        integer         cs;
        always @* begin
            for (cs = 0; cs < 4; cs = cs + 1)
                p_sum[cs*D_W +: D_W] = b_p[cs*D_W +: D_W] + m_p[cs*D_W +: D_W];
        end
        assign p_nx = p_sum;
    end
endgenerate

reg [4*D_W-1:0] p_reg;
reg [4*TW-1:0]  e_reg;

always @(posedge clk) begin
    if (ce) begin
        p_reg <= p_nx;
        e_reg <= e_p;
    end
end

assign p_out = p_reg;
assign e_out = e_reg;

endmodule

`default_nettype wire
