/*
 * qmac_diag_serial: quadric_mac's datapath for the diagonal quadric on ONE multiplier
 * (quadric_mac's DIAG = 1, CLOCKS = 6 [quadric_clocks], FPGA_REGS = 0): the arithmetic of
 * qmac_diag, one product a clock over six clocks. The bit-exact twin of model/hw/golden.py
 * qmac_diag_serial (the values of qmac_diag):
 *
 *   v_k = ((Q_kk s_k) >>> s_frac) + Q_k3                   k = 0..2
 *   r_k = s_k (v_k + Q_k3)                                  k = 0..2
 *   v_3 = J
 *
 * (q = ((r_0 + r_1 + r_2) >>> s_frac) + v_3 in quadric_mac's stage 4). The operands, not the
 * products, are selected: the one multiplier takes Q_kk s_k (k = 0, 1, 2) in the vector's
 * enabled clocks 1-3 and s_k x_k (x_k = v_k + Q_k3, formed combinationally from the first
 * product of a three-word chain) in clocks 4-6. V_W (rtl/tex_widths.vh tw_v_w,
 * model/hw/config.py v_w) holds v_k and x_k: nothing wraps.
 *
 * Formats: as qmac_diag:
 *   s_in   {r, t, s}, each s{S_W}.{S_FRAC}
 *   q_coef {J, I, H, G, F, E, D, C, B, A} (A at the LSBs), each s{Q_W}.{q_frac}; B, C, F are
 *          0 by contract and not read
 *   v_out  {v3 = J, v2, v1, v0}, each s{V_W}.{q_frac}
 *   r_out  {r2, r1, r0}, each s{S_W+V_W}.{S_FRAC+q_frac}
 *
 * Pipeline (enabled clocks after the vector's entry, a one-hot phase ph): the entry loads s
 * into a rotating register (sr0 the k in hand) | 1-3 Q_kk s_k into a three-word chain pq |
 * 4-6 v_k from pq's head and s_k x_k, into rotating registers vr and rr | 7 out_valid: vr, rr
 * hold the vector (J beside them, read from the port). Latency `LAT_QMAC_DIAG_SERIAL (7)
 * register stages; throughput one vector every sixth enabled clock at most. CONTRACT: in_valid
 * is never high twice within six enabled clocks (texture_pipeline's issue, quadric_clocks = 6),
 * and q_coef is stable from the first vector's entry until the last vector's exit. r_out and
 * v_out hold a vector from out_valid until the next vector's clock 4 (three enabled clocks
 * later at the earliest), so quadric_mac's stage 4 reads them in the out_valid clock. ce = 0
 * holds every register. rst (synchronous) clears the phase (the valid chain) only.
 *
 * Measured (synth/experiments/README.md, compact's formats s21.13, q 24 bits): 11,033 GE
 * against qmac_diag_fold's 25,783.
 *
 * Written for event-driven simulation speed: combinational logic in one always @*, one
 * clocked process for the data, no bus driven piecewise.
 */

`include "tex_latency.vh"

`default_nettype none

module qmac_diag_serial #(
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
localparam LATENCY = `LAT_QMAC_DIAG_SERIAL;
localparam STAGES  = 7;          // this implementation: the entry, six product clocks

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
        qmac_diag_serial_latency_mismatch_see_tex_latency_vh u_error ();
    end
endgenerate

// ---------------------------------------------------------------------------
// unpack

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

// ---------------------------------------------------------------------------
// the phase: ph[0] = clock 1 ... ph[5] = clock 6, ph[6] = out_valid

reg [LATENCY-1:0] ph;
assign out_valid = ph[LATENCY-1];

always @(posedge clk) begin
    if (rst)
        ph <= {LATENCY{1'b0}};
    else if (ce)
        ph <= {ph[LATENCY-2:0], in_valid};
end

// ---------------------------------------------------------------------------
// the one multiplier

wire first_half  = ph[0] | ph[1] | ph[2];  // Q_kk s_k
wire second_half = ph[3] | ph[4] | ph[5];  // s_k x_k

reg signed [S_W-1:0]  sr0, sr1, sr2;       // s, rotating: sr0 is the k in hand
reg signed [P1_W-1:0] pq0, pq1, pq2;       // Q_kk s_k, a chain: pq0 the k in hand in clocks 4-6
reg signed [V_W-1:0]  vr0, vr1, vr2;       // v_k, shifted in (vr2 the newest)
reg signed [P2_W-1:0] rr0, rr1, rr2;       // r_k, shifted in (rr2 the newest)

/* verilator lint_off UNUSEDSIGNAL */
reg signed [MA_W+MB_W-1:0] y;              // the product (each use fits its own word)
reg signed [P1_W+1:0]      m;              // pq0 sign-extended: bits above V_W + S_FRAC are copies
/* verilator lint_on UNUSEDSIGNAL */
reg signed [Q_W-1:0]  qkk;
reg signed [V_W-1:0]  q3, v, x;
reg signed [MA_W-1:0] ma;
reg signed [MB_W-1:0] mb;

always @* begin
    qkk = ph[0] ? qa : ph[1] ? qe : qh;                      // Q_kk of clocks 1-3
    q3  = ph[3] ? {{(V_W-Q_W){qd[Q_W-1]}}, qd}               // Q_k3 of clocks 4-6
        : ph[4] ? {{(V_W-Q_W){qg[Q_W-1]}}, qg}
        :         {{(V_W-Q_W){qi[Q_W-1]}}, qi};
    m   = {{2{pq0[P1_W-1]}}, pq0};
    v   = m[S_FRAC +: V_W] + q3;
    x   = v + q3;
    ma  = first_half ? {{(MA_W-Q_W){qkk[Q_W-1]}}, qkk} : {{(MA_W-S_W){sr0[S_W-1]}}, sr0};
    mb  = first_half ? {{(MB_W-S_W){sr0[S_W-1]}}, sr0} : {{(MB_W-V_W){x[V_W-1]}}, x};
    y   = ma * mb;
end

always @(posedge clk) begin
    if (ce) begin
        if (in_valid) begin
            sr0 <= s_in[0*S_W +: S_W];  sr1 <= s_in[1*S_W +: S_W];  sr2 <= s_in[2*S_W +: S_W];
        end else if (first_half | second_half) begin
            sr0 <= sr1;  sr1 <= sr2;  sr2 <= sr0;            // the next k (clock 3 and 6: back to s)
        end
        if (first_half) begin
            pq0 <= pq1;  pq1 <= pq2;  pq2 <= y[P1_W-1:0];    // after clock 3: pq0..pq2 = k 0..2
        end else if (second_half) begin
            pq0 <= pq1;  pq1 <= pq2;
            vr0 <= vr1;  vr1 <= vr2;  vr2 <= v;
            rr0 <= rr1;  rr1 <= rr2;  rr2 <= y[P2_W-1:0];
        end
    end
end

assign r_out = {rr2, rr1, rr0};
assign v_out = {{{(V_W-Q_W){qj[Q_W-1]}}, qj}, vr2, vr1, vr0};

endmodule

`default_nettype wire
