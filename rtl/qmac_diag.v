/*
 * qmac_diag: quadric_mac's datapath for the diagonal quadric (B = C = F = 0; quadric_mac's
 * DIAG = 1, CLOCKS = 1, FPGA_REGS = 0), stages 1-3 on 6 products instead of 15; quadric_mac
 * adds the output stage. The bit-exact twin of model/hw/golden.py qmac_diag. With
 * Q = [[A 0 0 D] [0 E 0 G] [0 0 H I] [D G I J]] and (Q_00, Q_11, Q_22) = (A, E, H),
 * (Q_03, Q_13, Q_23) = (D, G, I):
 *
 *   v_k = ((Q_kk s_k) >>> s_frac) + Q_k3                   k = 0..2  (v = (Q x)[0:3])
 *   r_k = s_k (v_k + Q_k3)                                  k = 0..2
 *   v_3 = J
 *
 * so that q = x^T Q x = ((r_0 + r_1 + r_2) >>> s_frac) + v_3 (quadric_mac's stage 4: one
 * floor for the quadratic-plus-linear sum, as the golden model). Products are full precision;
 * V_W (rtl/tex_widths.vh tw_v_w, model/hw/config.py v_w) bounds |Q_kk s_k| >> s_frac + 1 +
 * 2 |Q_k3|, so v_k and v_k + Q_k3 fit and nothing wraps.
 *
 * Formats:
 *   s_in   {r, t, s}, each s{S_W}.{S_FRAC}
 *   q_coef {J, I, H, G, F, E, D, C, B, A} (A at the LSBs), each s{Q_W}.{q_frac}; B, C, F are
 *          0 by contract (model/hw/quantize.py) and not read
 *   v_out  {v3 = J, v2, v1, v0}, each s{V_W}.{q_frac}
 *   r_out  {r2, r1, r0}, each s{S_W+V_W}.{S_FRAC+q_frac}
 * (q_frac, the coefficients' binary point, is not a parameter: nothing here depends on it.)
 *
 * Pipeline: 1 the 3 products Q_kk s_k | 2 v_k and x_k = v_k + Q_k3 (Q_k3 read from q_coef) |
 * 3 the products s_k x_k, v_k and J registered beside them.
 * Latency `LAT_QMAC_DIAG (3) register stages; throughput one vector per enabled clock.
 * ce = 0 holds every register. rst (synchronous) clears the valid chain only (out_valid says
 * when the data registers hold a vector).
 *
 * q_coef is a per-pass parameter: stage 1 reads A, E, H and stages 2-3 D, G, I, J straight
 * from the port. CONTRACT: q_coef is stable from the first vector's entry until the last
 * vector's exit (quadric_mac's contract).
 *
 * Written for event-driven simulation speed: combinational logic in one always @*, one
 * clocked process for the data, no bus driven piecewise.
 */

`include "tex_latency.vh"

`default_nettype none

module qmac_diag #(
    // quadric_mac's parameters of the same names (config/<name>.toml keys in brackets)
    parameter S_W    = 24,  // [s_w] texture coordinate word width
    parameter S_FRAC = 16,  // [s_frac] texture coordinate fraction bits
    parameter Q_W    = 24   // [q_w] quadric coefficient word width
) (clk, rst, ce, in_valid, s_in, q_coef, out_valid, r_out, v_out);

`include "tex_widths.vh"

localparam V_W  = tw_v_w(1, S_W, S_FRAC, Q_W);  // v_k and v_k + Q_k3 (q_frac)
localparam P1_W = S_W + Q_W;     // product Q_kk * s_k
localparam P2_W = S_W + V_W;     // product s_k * x_k
localparam LATENCY = `LAT_QMAC_DIAG;
localparam STAGES  = 3;          // this implementation: stages 1-3

input  wire              clk;
input  wire              rst;
input  wire              ce;
input  wire              in_valid;
input  wire [3*S_W-1:0]  s_in;
input  wire [10*Q_W-1:0] q_coef;
output wire              out_valid;
output wire [3*P2_W-1:0] r_out;
output wire [4*V_W-1:0]  v_out;

// elaboration fails (unknown module) if rtl/tex_latency.vh disagrees with the stages above
generate
    if (LATENCY != STAGES) begin : g_bad_latency
        qmac_diag_latency_mismatch_see_tex_latency_vh u_error ();
    end
endgenerate

// ---------------------------------------------------------------------------
// unpack

wire signed [S_W-1:0] s0 = s_in[0*S_W +: S_W];
wire signed [S_W-1:0] s1 = s_in[1*S_W +: S_W];
wire signed [S_W-1:0] s2 = s_in[2*S_W +: S_W];

wire signed [Q_W-1:0] qa = q_coef[0*Q_W +: Q_W];
wire signed [Q_W-1:0] qd = q_coef[3*Q_W +: Q_W];
wire signed [Q_W-1:0] qe = q_coef[4*Q_W +: Q_W];
wire signed [Q_W-1:0] qg = q_coef[6*Q_W +: Q_W];
wire signed [Q_W-1:0] qh = q_coef[7*Q_W +: Q_W];
wire signed [Q_W-1:0] qi = q_coef[8*Q_W +: Q_W];
wire signed [Q_W-1:0] qj = q_coef[9*Q_W +: Q_W];
/* verilator lint_off UNUSEDSIGNAL */
// B, C, F: 0 by contract and not read
wire [Q_W-1:0] q_bcf = q_coef[1*Q_W +: Q_W] | q_coef[2*Q_W +: Q_W] | q_coef[5*Q_W +: Q_W];
/* verilator lint_on UNUSEDSIGNAL */

// Q_k3 (D, G, I, J: stable parameters, read directly) sign-extended to V_W
wire signed [V_W-1:0] q03_x = {{(V_W-Q_W){qd[Q_W-1]}}, qd};
wire signed [V_W-1:0] q13_x = {{(V_W-Q_W){qg[Q_W-1]}}, qg};
wire signed [V_W-1:0] q23_x = {{(V_W-Q_W){qi[Q_W-1]}}, qi};
wire signed [V_W-1:0] q33_x = {{(V_W-Q_W){qj[Q_W-1]}}, qj};

// valid chain
reg [LATENCY-1:0] valid_reg;
assign out_valid = valid_reg[LATENCY-1];

always @(posedge clk) begin
    if (rst)
        valid_reg <= {LATENCY{1'b0}};
    else if (ce)
        valid_reg <= {valid_reg[LATENCY-2:0], in_valid};
end

// ---------------------------------------------------------------------------
// stage 1: Q_kk * s_k
reg signed [P1_W-1:0] p00_reg, p11_reg, p22_reg;  // A s, E t, H r
reg signed [S_W-1:0]  s0_1_reg, s1_1_reg, s2_1_reg;

// stage 2: v_k = (p >>> S_FRAC) + Q_k3 and x_k = v_k + Q_k3; both fit V_W
// (model/hw/config.py: v_w bounds |Q_kk s_k| >> S_FRAC + 1 + 2 |Q_k3|)
/* verilator lint_off UNUSEDSIGNAL */
// the S_FRAC low bits are dropped by the floor shift; the bits above
// S_FRAC + V_W are sign copies
reg signed [P1_W+1:0] m0, m1, m2;
/* verilator lint_on UNUSEDSIGNAL */
reg signed [V_W-1:0] v0, v1, v2;

always @* begin
    m0 = {{2{p00_reg[P1_W-1]}}, p00_reg};
    m1 = {{2{p11_reg[P1_W-1]}}, p11_reg};
    m2 = {{2{p22_reg[P1_W-1]}}, p22_reg};
    v0 = m0[S_FRAC +: V_W] + q03_x;
    v1 = m1[S_FRAC +: V_W] + q13_x;
    v2 = m2[S_FRAC +: V_W] + q23_x;
end

reg signed [V_W-1:0]  v0_reg, v1_reg, v2_reg, x0_reg, x1_reg, x2_reg;
reg signed [S_W-1:0]  s0_2_reg, s1_2_reg, s2_2_reg;
reg signed [P2_W-1:0] r0_reg, r1_reg, r2_reg;
reg signed [V_W-1:0]  v0_3_reg, v1_3_reg, v2_3_reg, v3_3_reg;

always @(posedge clk) begin
    if (ce) begin
        // stage 1
        p00_reg <= qa * s0;  p11_reg <= qe * s1;  p22_reg <= qh * s2;
        s0_1_reg <= s0;  s1_1_reg <= s1;  s2_1_reg <= s2;
        // stage 2
        v0_reg <= v0;  v1_reg <= v1;  v2_reg <= v2;
        x0_reg <= v0 + q03_x;  x1_reg <= v1 + q13_x;  x2_reg <= v2 + q23_x;
        s0_2_reg <= s0_1_reg;  s1_2_reg <= s1_1_reg;  s2_2_reg <= s2_1_reg;
        // stage 3: s_k * x_k; J stands in for v3
        r0_reg <= s0_2_reg * x0_reg;
        r1_reg <= s1_2_reg * x1_reg;
        r2_reg <= s2_2_reg * x2_reg;
        v0_3_reg <= v0_reg;  v1_3_reg <= v1_reg;  v2_3_reg <= v2_reg;  v3_3_reg <= q33_x;
    end
end

assign r_out = {r2_reg, r1_reg, r0_reg};
assign v_out = {v3_3_reg, v2_3_reg, v1_3_reg, v0_3_reg};

endmodule

`default_nettype wire
