/*
 * qmac_diag_serial (an experiment for issue 27, not in rtl/): quadric_mac's diagonal datapath on ONE
 * multiplier over six clocks, the values of qmac_diag / qmac_diag_fold:
 *   v_k = ((Q_kk s_k) >>> s_frac) + Q_k3,  r_k = s_k (v_k + Q_k3),  v_3 = J.
 * Clock 0 (in_valid): s into a rotating register; enabled clocks 1-3: Q_kk s_k (k = 0, 1, 2) into a
 * three-word chain; clocks 4-6: x_k = v_k + Q_k3 from the chain's head and s_k x_k. out_valid in
 * clock 7: latency 7 register stages (qmac_diag_fold: 3). CONTRACT: a vector every 6 enabled clocks
 * at most (quadric_clocks = 6); r_out and v_out hold from out_valid to the next vector's clock 4.
 * Formats as qmac_diag_fold. Checked against qmac_diag_fold by qmac_diag_serial_tb.v (3,000 vectors a
 * vector every 6 clocks, the most negative words among them; synth/experiments/README.md).
 */
`include "tex_latency.vh"
`default_nettype none
module qmac_diag_serial #(
    parameter S_W    = 24,
    parameter S_FRAC = 16,
    parameter Q_W    = 24
) (clk, rst, ce, in_valid, s_in, q_coef, out_valid, r_out, v_out);
`include "tex_widths.vh"
localparam V_W  = tw_v_w(1, S_W, S_FRAC, Q_W);
localparam P1_W = S_W + Q_W;
localparam P2_W = S_W + V_W;
localparam MA_W = (S_W > Q_W) ? S_W : Q_W;
localparam MB_W = (V_W > S_W) ? V_W : S_W;
input  wire              clk, rst, ce, in_valid;
input  wire [3*S_W-1:0]  s_in;
input  wire [10*Q_W-1:0] q_coef;
output wire              out_valid;
output wire [3*P2_W-1:0] r_out;
output wire [4*V_W-1:0]  v_out;

wire signed [Q_W-1:0] qa = q_coef[0*Q_W +: Q_W];
wire signed [Q_W-1:0] qd = q_coef[3*Q_W +: Q_W];
wire signed [Q_W-1:0] qe = q_coef[4*Q_W +: Q_W];
wire signed [Q_W-1:0] qg = q_coef[6*Q_W +: Q_W];
wire signed [Q_W-1:0] qh = q_coef[7*Q_W +: Q_W];
wire signed [Q_W-1:0] qi = q_coef[8*Q_W +: Q_W];
wire signed [Q_W-1:0] qj = q_coef[9*Q_W +: Q_W];
/* verilator lint_off UNUSEDSIGNAL */
wire [Q_W-1:0] q_bcf = q_coef[1*Q_W +: Q_W] | q_coef[2*Q_W +: Q_W] | q_coef[5*Q_W +: Q_W];
/* verilator lint_on UNUSEDSIGNAL */

reg [6:0] ph;            // one-hot phase: ph[0] = clock 1 ... ph[5] = clock 6, ph[6] = out_valid
assign out_valid = ph[6];
always @(posedge clk) begin
    if (rst) ph <= 7'd0;
    else if (ce) ph <= {ph[5:0], in_valid};
end

reg signed [S_W-1:0]  sr0, sr1, sr2;     // rotating: sr0 is the current k's s
reg signed [V_W-1:0]  vr0, vr1, vr2;     // rotating v_k (vr2 newest)
reg signed [P2_W-1:0] rr0, rr1, rr2;     // rotating r_k
reg signed [V_W-1:0]  v, x, q3;
reg signed [Q_W-1:0]  qkk;
reg signed [MA_W-1:0] ma;
reg signed [MB_W-1:0] mb;
/* verilator lint_off UNUSEDSIGNAL */
reg signed [MA_W+MB_W-1:0] y;
reg signed [P1_W+1:0] m;
/* verilator lint_on UNUSEDSIGNAL */
wire first_half = ph[0] | ph[1] | ph[2];

always @* begin
    qkk = ph[0] ? qa : ph[1] ? qe : qh;
    // Q_k3 of the product in flight in clocks 4-6: k = 0, 1, 2
    q3  = ph[3] ? {{(V_W-Q_W){qd[Q_W-1]}}, qd} : ph[4] ? {{(V_W-Q_W){qg[Q_W-1]}}, qg} : {{(V_W-Q_W){qi[Q_W-1]}}, qi};
    v   = m[S_FRAC +: V_W] + q3;
    x   = v + q3;
    ma  = first_half ? {{(MA_W-Q_W){qkk[Q_W-1]}}, qkk} : {{(MA_W-S_W){sr0[S_W-1]}}, sr0};
    mb  = first_half ? {{(MB_W-S_W){sr0[S_W-1]}}, sr0} : {{(MB_W-V_W){x[V_W-1]}}, x};
    y   = ma * mb;
end

// pr must hold Q_kk s_k for k in clocks 4-6: keep the three first-half products in a
// rotating register chain instead (p0 used in clock 4, p1 in 5, p2 in 6)
reg signed [P1_W-1:0] pq0, pq1, pq2;
always @* m = {{2{pq0[P1_W-1]}}, pq0};
always @(posedge clk) begin
    if (ce) begin
        if (in_valid) begin
            sr0 <= s_in[0*S_W +: S_W]; sr1 <= s_in[1*S_W +: S_W]; sr2 <= s_in[2*S_W +: S_W];
        end else if (|ph[5:0]) begin
            sr0 <= sr1; sr1 <= sr2; sr2 <= sr0;           // rotate every clock of the six
        end
        if (first_half) begin
            pq0 <= pq1; pq1 <= pq2; pq2 <= y[P1_W-1:0];   // after clock 3: pq0 = p0, pq1 = p1, pq2 = p2
        end else if (ph[3] | ph[4] | ph[5]) begin
            pq0 <= pq1; pq1 <= pq2;
            vr0 <= vr1; vr1 <= vr2; vr2 <= v;
            rr0 <= rr1; rr1 <= rr2; rr2 <= y[P2_W-1:0];
        end
    end
end

assign r_out = {rr2, rr1, rr0};
assign v_out = {{{(V_W-Q_W){qj[Q_W-1]}}, qj}, vr2, vr1, vr0};
endmodule
`default_nettype wire
