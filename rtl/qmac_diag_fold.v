/*
 * qmac_diag_fold: quadric_mac's datapath for the diagonal quadric on half its multipliers
 * (quadric_mac's DIAG = 1, CLOCKS = 2 [quadric_clocks], FPGA_REGS = 0): the arithmetic of
 * qmac_diag, stage by stage, with one multiplier per k. The bit-exact twin of
 * model/hw/golden.py qmac_diag_fold (the values of qmac_diag):
 *
 *   v_k = ((Q_kk s_k) >>> s_frac) + Q_k3                   k = 0..2
 *   r_k = s_k (v_k + Q_k3)                                  k = 0..2
 *   v_3 = J
 *
 * (q = ((r_0 + r_1 + r_2) >>> s_frac) + v_3 in quadric_mac's stage 4). In the clock after a
 * vector enters (valid_reg[0]), the multiplier takes s_k x_k (x_k = v_k + Q_k3 from stage 1's
 * product, combinationally) instead of Q_kk s_k; the operands, not the products, are selected.
 * V_W (rtl/tex_widths.vh tw_v_w, model/hw/config.py v_w) holds v_k and x_k: nothing wraps.
 *
 * Formats: as qmac_diag:
 *   s_in   {r, t, s}, each s{S_W}.{S_FRAC}
 *   q_coef {J, I, H, G, F, E, D, C, B, A} (A at the LSBs), each s{Q_W}.{q_frac}; B, C, F are
 *          0 by contract and not read
 *   v_out  {v3 = J, v2, v1, v0}, each s{V_W}.{q_frac}
 *   r_out  {r2, r1, r0}, each s{S_W+V_W}.{S_FRAC+q_frac}
 *
 * Pipeline: 1 (the vector's first clock) the products Q_kk s_k, into registers that load only
 * in a vector's first clock | 2 (its second clock) v_k and the products s_k x_k, into registers
 * that load only in a vector's second clock | 3 those registers hold (J beside them). No register copies stage 2 into stage 3: the next vector's
 * second clock comes two enabled clocks later at the earliest (the contract), so stage 2's
 * registers still hold this vector in the clock quadric_mac's stage 4 reads them (out_valid).
 * Latency `LAT_QMAC_DIAG_FOLD (3) register stages; throughput one vector every other enabled
 * clock at most. CONTRACT: in_valid is never high in two consecutive enabled clocks
 * (texture_pipeline's CLOCKS-cycle issue), and q_coef is stable from the first vector's entry
 * until the last vector's exit. r_out and v_out hold a vector while out_valid is high (and until
 * the next vector's second clock). ce = 0 holds every register. rst (synchronous) clears the
 * valid chain only.
 *
 * Written for simulation speed: stages 1-2 computed in the one clocked process for the data
 * (blocking temporaries), only on an enabled clock that brings a vector into stage 1 or holds
 * one there, so that a simulator skips the idle clocks (the registers hold); no bus driven
 * piecewise. The process first assigns its temporaries whole, outside any if, so that they
 * are C++ locals in the Verilator model (it localizes only a variable wholly assigned outside
 * any branch; one first assigned under the if stays a member of the model, a store on every
 * write).
 */

`include "tex_latency.vh"

`default_nettype none

module qmac_diag_fold #(
    // quadric_mac's parameters of the same names (config/<name>.toml keys in brackets)
    parameter S_W    = 24,  // [s_w] texture coordinate word width
    parameter S_FRAC = 16,  // [s_frac] texture coordinate fraction bits
    parameter Q_W    = 24   // [q_w] quadric coefficient word width
) (clk, rst, ce, in_valid, s_in, q_coef, out_valid, r_out, v_out);

`include "tex_widths.vh"

localparam V_W  = tw_v_w(1, S_W, S_FRAC, Q_W);  // v_k and x_k = v_k + Q_k3 (q_frac)
localparam P1_W = S_W + Q_W;     // product Q_kk * s_k
localparam P2_W = S_W + V_W;     // product s_k * x_k
localparam MA_W = (S_W > Q_W) ? S_W : Q_W;  // multiplier operands (either use)
localparam MB_W = (V_W > S_W) ? V_W : S_W;
localparam LATENCY = `LAT_QMAC_DIAG_FOLD;
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
        qmac_diag_fold_latency_mismatch_see_tex_latency_vh u_error ();
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

// Q_k3 (D, G, I, J: stable parameters, read directly) sign-extended to V_W: q03_x .. q33_x,
// temporaries of the clocked process below (formed there only on a clock that uses them)

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
// stages 1-2 on one multiplier per k, computed in the one clocked process only on an enabled
// clock that brings a vector (in_valid: its first clock, stage 1) or holds one in stage 1
// (second: its second clock, stage 2); the registers hold otherwise

/* verilator lint_off UNUSEDSIGNAL */
reg signed [MA_W+MB_W-1:0] y0, y1, y2;     // products (each use fits its own word)
reg signed [MA_W-1:0]      ma0, ma1, ma2;  // operands
reg signed [MB_W-1:0]      mb0, mb1, mb2;
reg signed [P1_W+1:0]      m0, m1, m2;
/* verilator lint_on UNUSEDSIGNAL */
reg signed [P1_W-1:0] p00_reg, p11_reg, p22_reg;  // stage 1: A s, E t, H r
reg signed [S_W-1:0]  s0_1_reg, s1_1_reg, s2_1_reg;
reg signed [V_W-1:0]  v0, v1, v2, x0, x1, x2;
reg signed [P2_W-1:0] r0_2_reg, r1_2_reg, r2_2_reg;  // stage 2: s_k x_k
reg signed [V_W-1:0]  v0_reg, v1_reg, v2_reg;
reg signed [V_W-1:0]  v3_3_reg;
reg signed [V_W-1:0]  q03_x, q13_x, q23_x, q33_x;
wire                  second = valid_reg[0];       // the vector in stage 1: its second clock

/* verilator lint_off BLKSEQ */
always @(posedge clk) begin
    // every temporary wholly assigned first, outside the if (C++ locals in the Verilator model)
    m0  = {(P1_W+2){1'b0}};  m1  = {(P1_W+2){1'b0}};  m2  = {(P1_W+2){1'b0}};
    v0  = {V_W{1'b0}};       v1  = {V_W{1'b0}};       v2  = {V_W{1'b0}};
    x0  = {V_W{1'b0}};       x1  = {V_W{1'b0}};       x2  = {V_W{1'b0}};
    ma0 = {MA_W{1'b0}};      ma1 = {MA_W{1'b0}};      ma2 = {MA_W{1'b0}};
    mb0 = {MB_W{1'b0}};      mb1 = {MB_W{1'b0}};      mb2 = {MB_W{1'b0}};
    y0  = {(MA_W+MB_W){1'b0}}; y1 = {(MA_W+MB_W){1'b0}}; y2 = {(MA_W+MB_W){1'b0}};
    q03_x = {V_W{1'b0}};     q13_x = {V_W{1'b0}};     q23_x = {V_W{1'b0}};     q33_x = {V_W{1'b0}};
    if (ce && (in_valid || second)) begin
        q03_x = {{(V_W-Q_W){qd[Q_W-1]}}, qd};
        q13_x = {{(V_W-Q_W){qg[Q_W-1]}}, qg};
        q23_x = {{(V_W-Q_W){qi[Q_W-1]}}, qi};
        q33_x = {{(V_W-Q_W){qj[Q_W-1]}}, qj};
        m0 = {{2{p00_reg[P1_W-1]}}, p00_reg};
        m1 = {{2{p11_reg[P1_W-1]}}, p11_reg};
        m2 = {{2{p22_reg[P1_W-1]}}, p22_reg};
        v0 = m0[S_FRAC +: V_W] + q03_x;
        v1 = m1[S_FRAC +: V_W] + q13_x;
        v2 = m2[S_FRAC +: V_W] + q23_x;
        x0 = v0 + q03_x;
        x1 = v1 + q13_x;
        x2 = v2 + q23_x;
        // the operands, not the products, are selected: one multiplier per k
        ma0 = second ? {{(MA_W-S_W){s0_1_reg[S_W-1]}}, s0_1_reg} : {{(MA_W-Q_W){qa[Q_W-1]}}, qa};
        ma1 = second ? {{(MA_W-S_W){s1_1_reg[S_W-1]}}, s1_1_reg} : {{(MA_W-Q_W){qe[Q_W-1]}}, qe};
        ma2 = second ? {{(MA_W-S_W){s2_1_reg[S_W-1]}}, s2_1_reg} : {{(MA_W-Q_W){qh[Q_W-1]}}, qh};
        mb0 = second ? {{(MB_W-V_W){x0[V_W-1]}}, x0} : {{(MB_W-S_W){s0[S_W-1]}}, s0};
        mb1 = second ? {{(MB_W-V_W){x1[V_W-1]}}, x1} : {{(MB_W-S_W){s1[S_W-1]}}, s1};
        mb2 = second ? {{(MB_W-V_W){x2[V_W-1]}}, x2} : {{(MB_W-S_W){s2[S_W-1]}}, s2};
        y0 = ma0 * mb0;
        y1 = ma1 * mb1;
        y2 = ma2 * mb2;
        // stage 1 (the vector's first clock)
        if (in_valid) begin
            p00_reg <= y0[P1_W-1:0];  p11_reg <= y1[P1_W-1:0];  p22_reg <= y2[P1_W-1:0];
            s0_1_reg <= s0;  s1_1_reg <= s1;  s2_1_reg <= s2;
        end
        // stage 2 (its second clock): v_k and the products s_k x_k, held through stage 3;
        // stage 3: J stands in for v3
        if (second) begin
            v0_reg <= v0;  v1_reg <= v1;  v2_reg <= v2;
            r0_2_reg <= y0[P2_W-1:0];  r1_2_reg <= y1[P2_W-1:0];  r2_2_reg <= y2[P2_W-1:0];
            v3_3_reg <= q33_x;
        end
    end
end
/* verilator lint_on BLKSEQ */

assign r_out = {r2_2_reg, r1_2_reg, r0_2_reg};
assign v_out = {v3_3_reg, v2_reg, v1_reg, v0_reg};

endmodule

`default_nettype wire
