/*
 * qmac_full: quadric_mac's datapath for the full quadric (stages 1-3; quadric_mac adds the
 * output stage, q and the output shifts). The bit-exact twin of model/hw/golden.py qmac_full.
 * For x = (s, t, r, 1) and Q = [[A B C D] [B E F G] [C F H I] [D G I J]]:
 *
 *   v_k = ((Q_k0 s + Q_k1 t + Q_k2 r) >>> s_frac) + Q_k3        k = 0..3  (v = Q x)
 *   r_k = s_k v_k                                                k = 0..2
 *
 * so that q = x^T Q x = ((r_0 + r_1 + r_2) >>> s_frac) + v_3 (quadric_mac's stage 4).
 * Products are full precision and each three-product sum is formed before its floor shift
 * (>>> = floor); V_W (rtl/tex_widths.vh tw_v_w, model/hw/config.py v_w) holds the worst-case
 * v_k, so no intermediate ever wraps.
 *
 * Formats:
 *   s_in   {r, t, s}, each s{S_W}.{S_FRAC}
 *   q_coef {J, I, H, G, F, E, D, C, B, A} (A at the LSBs), each s{Q_W}.{q_frac}
 *   v_out  {v3, v2, v1, v0}, each s{V_W}.{q_frac}
 *   r_out  {r2, r1, r0}, each s{S_W+V_W}.{S_FRAC+q_frac}
 * (q_frac, the coefficients' binary point, is not a parameter: nothing here depends on it.)
 *
 * Pipeline: [FPGA_REGS: two input register stages on s] | 1 the 12 products Q_kj s_j |
 * 2 v_0..v_3 (+ Q_k3, read from q_coef) | 3 the products s_k v_k, v registered beside them.
 * Latency `LAT_QMAC_FULL (3) register stages (FPGA_REGS: `LAT_QMAC_FULL_FPGA, 5);
 * throughput one vector per enabled clock. ce = 0 holds every register. rst (synchronous)
 * clears the valid chain only (the data registers are not reset: out_valid says when they
 * hold a vector).
 *
 * q_coef is a per-pass parameter, not per-vector data: stage 1 reads the nine Q_kj (j < 3)
 * and stage 2 the four Q_k3 straight from the port. CONTRACT: q_coef is stable from the
 * first vector's entry until the last vector's exit (quadric_mac's contract).
 *
 * Written for event-driven simulation speed: combinational logic in one always @*, one
 * clocked process for the data, no bus driven piecewise.
 */

`include "tex_latency.vh"

`default_nettype none

module qmac_full #(
    // quadric_mac's parameters of the same names (config/<name>.toml keys in brackets)
    parameter S_W       = 24,  // [s_w] texture coordinate word width
    parameter S_FRAC    = 16,  // [s_frac] texture coordinate fraction bits
    parameter Q_W       = 24,  // [q_w] quadric coefficient word width
    parameter FPGA_REGS = 0    // [fpga_regs] 1: two input register stages (the FPGA's clock)
) (clk, rst, ce, in_valid, s_in, q_coef, out_valid, r_out, v_out);

`include "tex_widths.vh"

localparam V_W  = tw_v_w(0, S_W, S_FRAC, Q_W);  // v_k = (Q x)_k (q_frac)
localparam P1_W = S_W + Q_W;     // product Q_kj * s_j
localparam M1_W = P1_W + 2;      // sum of three such products
localparam P2_W = S_W + V_W;     // product s_k * v_k
localparam XIN  = FPGA_REGS ? 2 : 0;  // input register stages
localparam LATENCY = FPGA_REGS ? `LAT_QMAC_FULL_FPGA : `LAT_QMAC_FULL;
localparam STAGES  = XIN + 3;    // this implementation: the input stages, stages 1-3

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
        qmac_full_latency_mismatch_see_tex_latency_vh u_error ();
    end
endgenerate

// ---------------------------------------------------------------------------
// unpack

wire [3*S_W-1:0] s_x;  // s_in after XIN register stages
generate
    if (XIN > 0) begin : g_xin
        delay_line #(.W(3*S_W), .N(XIN)) u_dly_s (.clk(clk), .rst(rst), .ce(ce), .d_in(s_in), .d_out(s_x));
    end else begin : g_noxin
        assign s_x = s_in;
    end
endgenerate
wire signed [S_W-1:0] s0 = s_x[0*S_W +: S_W];
wire signed [S_W-1:0] s1 = s_x[1*S_W +: S_W];
wire signed [S_W-1:0] s2 = s_x[2*S_W +: S_W];

wire signed [Q_W-1:0] qa = q_coef[0*Q_W +: Q_W];
wire signed [Q_W-1:0] qb = q_coef[1*Q_W +: Q_W];
wire signed [Q_W-1:0] qc = q_coef[2*Q_W +: Q_W];
wire signed [Q_W-1:0] qd = q_coef[3*Q_W +: Q_W];
wire signed [Q_W-1:0] qe = q_coef[4*Q_W +: Q_W];
wire signed [Q_W-1:0] qf = q_coef[5*Q_W +: Q_W];
wire signed [Q_W-1:0] qg = q_coef[6*Q_W +: Q_W];
wire signed [Q_W-1:0] qh = q_coef[7*Q_W +: Q_W];
wire signed [Q_W-1:0] qi = q_coef[8*Q_W +: Q_W];
wire signed [Q_W-1:0] qj = q_coef[9*Q_W +: Q_W];

// Q_k3 (D, G, I, J: stable parameters, read directly) sign-extended to V_W
// (V_W > Q_W always: v_w bounds |Q_k3| + more)
wire signed [V_W-1:0] q03_x = {{(V_W-Q_W){qd[Q_W-1]}}, qd};
wire signed [V_W-1:0] q13_x = {{(V_W-Q_W){qg[Q_W-1]}}, qg};
wire signed [V_W-1:0] q23_x = {{(V_W-Q_W){qi[Q_W-1]}}, qi};
wire signed [V_W-1:0] q33_x = {{(V_W-Q_W){qj[Q_W-1]}}, qj};

// valid chain (XIN input stages included: the vector's s waits in the delay line)
reg [LATENCY-1:0] valid_reg;
assign out_valid = valid_reg[LATENCY-1];

always @(posedge clk) begin
    if (rst)
        valid_reg <= {LATENCY{1'b0}};
    else if (ce)
        valid_reg <= {valid_reg[LATENCY-2:0], in_valid};
end

// ---------------------------------------------------------------------------
// stage 1: products Q_kj * s_j (row k of Q times (s, t, r))
reg signed [P1_W-1:0] p00_reg, p01_reg, p02_reg;  // A s, B t, C r
reg signed [P1_W-1:0] p10_reg, p11_reg, p12_reg;  // B s, E t, F r
reg signed [P1_W-1:0] p20_reg, p21_reg, p22_reg;  // C s, F t, H r
reg signed [P1_W-1:0] p30_reg, p31_reg, p32_reg;  // D s, G t, I r
reg signed [S_W-1:0]  s0_1_reg, s1_1_reg, s2_1_reg;

// stage 2: v_k = (sum >>> S_FRAC) + Q_k3
//
// The sum is exact in M1_W bits; bits [S_FRAC + V_W - 1 : S_FRAC] are
// floor(sum / 2^S_FRAC) modulo 2^V_W, and the final v_k fits V_W (config), so
// adding Q_k3 modulo 2^V_W gives v_k exactly.

/* verilator lint_off UNUSEDSIGNAL */
// the S_FRAC low bits are dropped by the floor shift; the bits above
// S_FRAC + V_W are sign copies of a value that fits V_W (model/hw/config.py: v_w)
reg signed [M1_W-1:0] m0, m1, m2, m3;
/* verilator lint_on UNUSEDSIGNAL */
reg signed [V_W-1:0] v0, v1, v2, v3;

always @* begin
    m0 = {{2{p00_reg[P1_W-1]}}, p00_reg} + {{2{p01_reg[P1_W-1]}}, p01_reg}
       + {{2{p02_reg[P1_W-1]}}, p02_reg};
    m1 = {{2{p10_reg[P1_W-1]}}, p10_reg} + {{2{p11_reg[P1_W-1]}}, p11_reg}
       + {{2{p12_reg[P1_W-1]}}, p12_reg};
    m2 = {{2{p20_reg[P1_W-1]}}, p20_reg} + {{2{p21_reg[P1_W-1]}}, p21_reg}
       + {{2{p22_reg[P1_W-1]}}, p22_reg};
    m3 = {{2{p30_reg[P1_W-1]}}, p30_reg} + {{2{p31_reg[P1_W-1]}}, p31_reg}
       + {{2{p32_reg[P1_W-1]}}, p32_reg};
    v0 = m0[S_FRAC +: V_W] + q03_x;
    v1 = m1[S_FRAC +: V_W] + q13_x;
    v2 = m2[S_FRAC +: V_W] + q23_x;
    v3 = m3[S_FRAC +: V_W] + q33_x;
end

reg signed [V_W-1:0]  v0_reg, v1_reg, v2_reg, v3_reg;
reg signed [S_W-1:0]  s0_2_reg, s1_2_reg, s2_2_reg;
reg signed [P2_W-1:0] r0_reg, r1_reg, r2_reg;
reg signed [V_W-1:0]  v0_3_reg, v1_3_reg, v2_3_reg, v3_3_reg;

always @(posedge clk) begin
    if (ce) begin
        // stage 1
        p00_reg <= qa * s0;  p01_reg <= qb * s1;  p02_reg <= qc * s2;
        p10_reg <= qb * s0;  p11_reg <= qe * s1;  p12_reg <= qf * s2;
        p20_reg <= qc * s0;  p21_reg <= qf * s1;  p22_reg <= qh * s2;
        p30_reg <= qd * s0;  p31_reg <= qg * s1;  p32_reg <= qi * s2;
        s0_1_reg <= s0;  s1_1_reg <= s1;  s2_1_reg <= s2;
        // stage 2
        v0_reg <= v0;  v1_reg <= v1;  v2_reg <= v2;  v3_reg <= v3;
        s0_2_reg <= s0_1_reg;  s1_2_reg <= s1_1_reg;  s2_2_reg <= s2_1_reg;
        // stage 3: products s_k * v_k
        r0_reg <= s0_2_reg * v0_reg;
        r1_reg <= s1_2_reg * v1_reg;
        r2_reg <= s2_2_reg * v2_reg;
        v0_3_reg <= v0_reg;  v1_3_reg <= v1_reg;  v2_3_reg <= v2_reg;  v3_3_reg <= v3_reg;
    end
end

assign r_out = {r2_reg, r1_reg, r0_reg};
assign v_out = {v3_3_reg, v2_3_reg, v1_3_reg, v0_3_reg};

endmodule

`default_nettype wire
