// mul_pipe: a signed product p = a * b with a register stage inside the multiplier, for an
// FPGA's 18x18 multipliers (quadric_mac with FPGA_REGS).
//
// Each operand wider than 18 bits is cut into a high part and a 17-bit unsigned low part,
//   a = ah 2^SA + al, b = bh 2^SB + bl   (SA = 17 when A_W > 18, else 0 and al = 0; SB alike)
// so that every partial product ah bh, ah bl, al bh, al bl is at most 18 x 18 bits signed
// (one ECP5 MULT18X18D each; the partials of a zero part are constant 0 and vanish in
// synthesis). The partials are registered; p is their sum, shifted into place,
//   p = (ah bh << (SA + SB)) + (ah bl << SA) + (al bh << SB) + al bl,
// combinational after the registers (the caller registers it): exact, p fits A_W + B_W bits.
//
// Formats: a s{A_W}.0, b s{B_W}.0 (any binary points: the product's is their sum), A_W and
// B_W at most 35 (two parts); p s{A_W+B_W}.0.
// Latency 1 register stage (the partials) before p; one product per enabled clock; no reset
// (data only).

`default_nettype none

module mul_pipe #(
    parameter A_W = 18,  // a word width (2..35)
    parameter B_W = 18   // b word width (2..35)
) (
    input  wire                   clk,
    input  wire                   ce,
    input  wire [A_W-1:0]         a,    // signed
    input  wire [B_W-1:0]         b,    // signed
    output wire [A_W+B_W-1:0]     p     // signed, a * b
);

localparam P_W  = A_W + B_W;
localparam SA   = (A_W > 18) ? 17 : 0;  // a's low part: SA bits (0: not cut)
localparam SB   = (B_W > 18) ? 17 : 0;
localparam AH_W = A_W - SA;             // high parts (signed)
localparam BH_W = B_W - SB;

// elaboration fails (unknown module) on operands wider than two parts
generate
    if (A_W > 35 || B_W > 35) begin : g_bad_params
        mul_pipe_operands_must_be_at_most_35_bits u_error ();
    end
endgenerate

// the parts: high signed, low zero-extended to 18 bits (a signed operand of value >= 0)
wire signed [AH_W-1:0] ah = a[A_W-1:SA];
wire signed [BH_W-1:0] bh = b[B_W-1:SB];
wire signed [17:0]     al;
wire signed [17:0]     bl;
generate
    if (SA > 0) begin : g_acut
        assign al = {1'b0, a[SA-1:0]};
    end else begin : g_awhole
        assign al = 18'sd0;
    end
    if (SB > 0) begin : g_bcut
        assign bl = {1'b0, b[SB-1:0]};
    end else begin : g_bwhole
        assign bl = 18'sd0;
    end
endgenerate

// the partial products, registered
reg signed [AH_W+BH_W-1:0] hh_reg;
reg signed [AH_W+17:0]     hl_reg;
reg signed [BH_W+17:0]     lh_reg;
reg signed [35:0]          ll_reg;

always @(posedge clk) begin
    if (ce) begin
        hh_reg <= ah * bh;
        hl_reg <= ah * bl;
        lh_reg <= al * bh;
        ll_reg <= al * bl;
    end
end

// their sum, each sign-extended to WX bits (wider than any partial) and shifted into place;
// mod 2^P_W it is the exact product
localparam WX = P_W + 36;
/* verilator lint_off UNUSEDSIGNAL */  // above P_W: bits of the modular sum, not read
reg signed [WX-1:0] hh_x, hl_x, lh_x, ll_x, sum;
/* verilator lint_on UNUSEDSIGNAL */
always @* begin
    hh_x = {{(WX-AH_W-BH_W){hh_reg[AH_W+BH_W-1]}}, hh_reg};
    hl_x = {{(WX-AH_W-18){hl_reg[AH_W+17]}}, hl_reg};
    lh_x = {{(WX-BH_W-18){lh_reg[BH_W+17]}}, lh_reg};
    ll_x = {{(WX-36){ll_reg[35]}}, ll_reg};
    sum  = (hh_x <<< (SA + SB)) + (hl_x <<< SA) + (lh_x <<< SB) + ll_x;
end

assign p = sum[P_W-1:0];

endmodule

`default_nettype wire
