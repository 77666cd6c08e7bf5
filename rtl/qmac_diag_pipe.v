/*
 * qmac_diag_pipe: quadric_mac's datapath for the diagonal quadric with the FPGA's pipelined
 * products (quadric_mac's DIAG = 1, FPGA_REGS = 1 [fpga_regs], CLOCKS 1 or 2: the FPGA has
 * multipliers to spare, so the products are not folded and a vector may come every clock);
 * quadric_mac adds the output stage. The bit-exact twin of model/hw/golden.py qmac_diag_pipe
 * (the values of qmac_diag):
 *
 *   v_k = ((Q_kk s_k) >>> s_frac) + Q_k3                   k = 0..2
 *   r_k = s_k x_k,  x_k = v_k + Q_k3 = ((Q_kk s_k) >>> s_frac) + 2 Q_k3
 *   v_3 = J
 *
 * (q = ((r_0 + r_1 + r_2) >>> s_frac) + v_3 in quadric_mac's stage 4). Each product is on
 * mul_pipe (18x18 partial products registered before their sum), and x_k is formed from the
 * product in one adder (not v_k + Q_k3: two). V_W (rtl/tex_widths.vh tw_v_w,
 * model/hw/config.py v_w) holds v_k and x_k: nothing wraps.
 *
 * Formats: as qmac_diag:
 *   s_in   {r, t, s}, each s{S_W}.{S_FRAC}
 *   q_coef {J, I, H, G, F, E, D, C, B, A} (A at the LSBs), each s{Q_W}.{q_frac}; B, C, F are
 *          0 by contract and not read
 *   v_out  {v3 = J, v2, v1, v0}, each s{V_W}.{q_frac}
 *   r_out  {r2, r1, r0}, each s{S_W+V_W}.{S_FRAC+q_frac}
 * mul_pipe takes operands of up to 35 bits: Q_W, S_W and V_W at most 35.
 *
 * Pipeline: 1 the partials of Q_kk s_k | 2 their sums (the products) | 3 v_k and x_k |
 * 4 the partials of s_k x_k | 5 their sums (beside v_k and J).
 * Latency `LAT_QMAC_DIAG_PIPE (5) register stages; throughput one vector per enabled clock.
 * ce = 0 holds every register. rst (synchronous) clears the valid chain only.
 * CONTRACT: q_coef is stable from the first vector's entry until the last vector's exit
 * (quadric_mac's contract).
 *
 * Written for event-driven simulation speed: one clocked process for the data, no bus
 * driven piecewise.
 */

`include "tex_latency.vh"

`default_nettype none

module qmac_diag_pipe #(
    // quadric_mac's parameters of the same names (config/<name>.toml keys in brackets)
    parameter S_W    = 24,  // [s_w] texture coordinate word width
    parameter S_FRAC = 16,  // [s_frac] texture coordinate fraction bits
    parameter Q_W    = 24   // [q_w] quadric coefficient word width
) (clk, rst, ce, in_valid, s_in, q_coef, out_valid, r_out, v_out);

`include "tex_widths.vh"

localparam V_W  = tw_v_w(1, S_W, S_FRAC, Q_W);  // v_k and x_k (q_frac)
localparam P1_W = S_W + Q_W;     // product Q_kk * s_k
localparam P2_W = S_W + V_W;     // product s_k * x_k
localparam LATENCY = `LAT_QMAC_DIAG_PIPE;
localparam STAGES  = 5;          // this implementation: stages 1-5

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
        qmac_diag_pipe_latency_mismatch_see_tex_latency_vh u_error ();
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

// (p >>> S_FRAC) + q mod 2^V_W: a product's floor shift plus a V_W-bit term
function signed [V_W-1:0] floor_add;
    input signed [P1_W-1:0] p;
    input signed [V_W-1:0]  q;
    /* verilator lint_off UNUSEDSIGNAL */  // low S_FRAC bits dropped, top sign copies
    reg signed [P1_W+1:0]   m;
    /* verilator lint_on UNUSEDSIGNAL */
    begin
        m = {{2{p[P1_W-1]}}, p};
        floor_add = m[S_FRAC +: V_W] + q;
    end
endfunction

// ---------------------------------------------------------------------------
// stages 1-2: Q_kk * s_k on mul_pipe (partials, then their sums registered)
wire [P1_W-1:0] y0, y1, y2;
mul_pipe #(.A_W(Q_W), .B_W(S_W)) u_mul_p0 (.clk(clk), .ce(ce), .a(qa), .b(s0), .p(y0));
mul_pipe #(.A_W(Q_W), .B_W(S_W)) u_mul_p1 (.clk(clk), .ce(ce), .a(qe), .b(s1), .p(y1));
mul_pipe #(.A_W(Q_W), .B_W(S_W)) u_mul_p2 (.clk(clk), .ce(ce), .a(qh), .b(s2), .p(y2));
reg signed [P1_W-1:0] p00_reg, p11_reg, p22_reg;  // A s, E t, H r
reg signed [S_W-1:0]  s0_1_reg, s1_1_reg, s2_1_reg, s0_2_reg, s1_2_reg, s2_2_reg;

// stage 3: v_k = (p >>> S_FRAC) + Q_k3 and x_k = v_k + Q_k3 = (p >>> S_FRAC) + 2 Q_k3
// (mod 2^V_W, where both fit)
wire signed [V_W-1:0] v0 = floor_add(p00_reg, q03_x),  x0 = floor_add(p00_reg, q03_x <<< 1);
wire signed [V_W-1:0] v1 = floor_add(p11_reg, q13_x),  x1 = floor_add(p11_reg, q13_x <<< 1);
wire signed [V_W-1:0] v2 = floor_add(p22_reg, q23_x),  x2 = floor_add(p22_reg, q23_x <<< 1);
reg signed [V_W-1:0] v0_reg, v1_reg, v2_reg, x0_reg, x1_reg, x2_reg, v0_4_reg, v1_4_reg, v2_4_reg;
reg signed [S_W-1:0] s0_3_reg, s1_3_reg, s2_3_reg;

// stages 4-5: s_k * x_k on mul_pipe; J stands in for v3
wire [P2_W-1:0] z0, z1, z2;
mul_pipe #(.A_W(S_W), .B_W(V_W)) u_mul_r0 (.clk(clk), .ce(ce), .a(s0_3_reg), .b(x0_reg), .p(z0));
mul_pipe #(.A_W(S_W), .B_W(V_W)) u_mul_r1 (.clk(clk), .ce(ce), .a(s1_3_reg), .b(x1_reg), .p(z1));
mul_pipe #(.A_W(S_W), .B_W(V_W)) u_mul_r2 (.clk(clk), .ce(ce), .a(s2_3_reg), .b(x2_reg), .p(z2));
reg signed [P2_W-1:0] r0_reg, r1_reg, r2_reg;
reg signed [V_W-1:0]  v0_5_reg, v1_5_reg, v2_5_reg, v3_5_reg;

always @(posedge clk) begin
    if (ce) begin
        // stages 1-2
        s0_1_reg <= s0;  s1_1_reg <= s1;  s2_1_reg <= s2;
        p00_reg <= y0;  p11_reg <= y1;  p22_reg <= y2;
        s0_2_reg <= s0_1_reg;  s1_2_reg <= s1_1_reg;  s2_2_reg <= s2_1_reg;
        // stage 3
        v0_reg <= v0;  v1_reg <= v1;  v2_reg <= v2;
        x0_reg <= x0;  x1_reg <= x1;  x2_reg <= x2;
        s0_3_reg <= s0_2_reg;  s1_3_reg <= s1_2_reg;  s2_3_reg <= s2_2_reg;
        // stages 4-5
        v0_4_reg <= v0_reg;  v1_4_reg <= v1_reg;  v2_4_reg <= v2_reg;
        r0_reg <= z0;  r1_reg <= z1;  r2_reg <= z2;
        v0_5_reg <= v0_4_reg;  v1_5_reg <= v1_4_reg;  v2_5_reg <= v2_4_reg;  v3_5_reg <= q33_x;
    end
end

assign r_out = {r2_reg, r1_reg, r0_reg};
assign v_out = {v3_5_reg, v2_5_reg, v1_5_reg, v0_5_reg};

endmodule

`default_nettype wire
