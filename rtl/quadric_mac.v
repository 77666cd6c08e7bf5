/*
 * quadric_mac: the quadric q = x^T Q x, x = (s, t, r, 1), and its texture-space
 * gradient dq/ds = 2 (Q x)[0:3]. Twin of model/hw/golden.py quadric_mac().
 *
 *   v_k = ((Q_k0 s + Q_k1 t + Q_k2 r) >>> s_frac) + Q_k3        k = 0..3
 *   q   = ((s v0 + t v1 + r v2) >>> s_frac) + v3
 *   q_out  = q   shifted by f_frac - q_frac     (left, or floor right)
 *   cq_out = v_k shifted by c_frac - q_frac + 1 (the factor 2 is a shift)
 *
 * DIAG = 1 (diagonal: B = C = F = 0, model/hw/quantize.py guarantees it; B, C, F
 * are not read) computes the same form with 6 products instead of 15:
 *
 *   v_k = ((Q_kk s_k) >>> s_frac) + Q_k3                       k = 0..2
 *   q   = ((s (v0 + D) + t (v1 + G) + r (v2 + I)) >>> s_frac) + J
 *
 * Products are full precision and each three-product sum is formed before its
 * floor shift (>>> = floor), exactly as the golden model; every word is wide
 * enough for the worst-case magnitude (model/hw/config.py derives V_W, QV_W, QF_W),
 * so no intermediate ever wraps.
 *
 * Formats (the parameters; V_W, QV_W, QF_W derived in rtl/tex_widths.vh):
 *   s_in   {r, t, s}, each s{S_W}.{S_FRAC}
 *   q_coef {J, I, H, G, F, E, D, C, B, A} (A at the LSBs), each s{Q_W}.{Q_FRAC}
 *          Q = [[A B C D] [B E F G] [C F H I] [D G I J]]
 *   v_k    s{V_W}.{Q_FRAC} (internal)       q  s{QV_W}.{Q_FRAC} (internal)
 *   r_k    s{S_W+V_W}.{S_FRAC+Q_FRAC} (internal: the datapath's products)
 *   q_out  s{QF_W}.{F_FRAC}
 *   cq_out {cq2, cq1, cq0}, each s{C_W}.{C_FRAC} (sign-extended)
 *
 * The datapath (stages 1-3: the products, v = Q x and the products r_k of q) is one of four
 * modules, picked by the parameters; each delivers r_k and v_k such that
 * q = ((r_0 + r_1 + r_2) >>> s_frac) + v_3 (diagonal: v_3 = J) and v_0..v_2 = (Q x)[0:3]:
 *   qmac_full       DIAG = 0: the 12 products Q_kj s_j, v_0..v_3, the products s_k v_k
 *                   (FPGA_REGS: after two input register stages; the full quadric does not
 *                   fit the 85F, docs/fpga.md)
 *   qmac_diag       DIAG = 1, CLOCKS = 1: the 3 products Q_kk s_k, v_k and x_k = v_k + Q_k3,
 *                   the products s_k x_k
 *   qmac_diag_fold  DIAG = 1, CLOCKS = 2: the same on 3 multipliers, a vector at most every
 *                   other enabled clock
 *   qmac_diag_serial DIAG = 1, CLOCKS = 6: the same on 1 multiplier, a vector at most every
 *                   sixth enabled clock
 *   qmac_diag_pipe  DIAG = 1, FPGA_REGS = 1 (CLOCKS 1, 2 or 6: the FPGA has multipliers to
 *                   spare, the products are not folded): each product on mul_pipe (18x18
 *                   partial products registered before their sum), x_k in one adder
 * Stage 4 (here): q = (sum >>> s_frac) + v_3, and the output shifts (computed only on a clock
 * that brings a valid vector).
 * Latency `LAT_QM(FPGA_REGS, DIAG, CLOCKS): `LAT_QUADRIC_MAC (4) register stages (FPGA_REGS:
 * `LAT_QUADRIC_MAC_FPGA, 6; CLOCKS = 6: `LAT_QUADRIC_MAC_SERIAL, 8): the datapath's `LAT_QMAC_*
 * and stage 4, checked at elaboration. Throughput one vector per enabled clock (CLOCKS = 2: one
 * every other enabled clock, on half the multipliers; CLOCKS = 6: one in six, on one). ce = 0
 * holds every register. rst (synchronous) clears the valid chains and the output registers;
 * the output registers load only valid vectors, so the outputs are never X after reset.
 *
 * q_coef is a per-pass parameter, not per-vector data: no register carries it
 * down the pipeline; the datapath reads it straight from the port.
 * CONTRACT: q_coef must be stable from the first vector's entry until the last
 * vector's exit; texture_pipeline guarantees it: parameters are written only
 * when the pipeline is empty (between passes).
 *
 * Written for simulation speed: stage 4's arithmetic in its clocked process (blocking
 * temporaries, assigned whole first, outside any if, so that they are C++ locals in the
 * Verilator model), only on an enabled clock that brings it a valid vector; few clocked
 * processes, no bus driven piecewise.
 */

`include "tex_latency.vh"

`default_nettype none

module quadric_mac #(
    // formats and mode (config/<name>.toml keys in brackets); V_W, QV_W, QF_W are derived
    // from them below (rtl/tex_widths.vh, the twin of model/hw/config.py)
    parameter DIAG   = 0,   // [quadric] 0 full (10 coefficients), 1 diagonal (B = C = F = 0, not read)
    // [quadric_clocks] 1: a vector every enabled clock; 2 (diagonal only): a vector at most
    // every other enabled clock, the 6 products on 3 multipliers (stage 1's Q_kk s_k in the
    // vector's first clock, stage 2's s_k x_k in its second); 6 (diagonal only): a vector at
    // most every sixth enabled clock, the 6 products on 1 multiplier
    parameter CLOCKS = 1,
    parameter S_W    = 24,  // [s_w] texture coordinate word width
    parameter S_FRAC = 16,  // [s_frac] texture coordinate fraction bits
    parameter Q_W    = 24,  // [q_w] quadric coefficient word width
    parameter Q_FRAC = 16,  // [q_frac] quadric coefficient fraction bits
    parameter F_FRAC = 16,  // [f_frac] q_out fraction bits
    parameter C_FRAC = 12,  // [c_frac] cq_out fraction bits
    // cq_out element word width: at least the gradient's own bound (texture_pipeline: the
    // exact-sum width of grad f, which also holds the noise terms' gradients)
    parameter C_W    = 31,
    parameter FPGA_REGS = 0  // [fpga_regs] 1: the FPGA's pipelined products (above)
) (clk, rst, ce, in_valid, s_in, q_coef, out_valid, q_out, cq_out);

`include "tex_widths.vh"

localparam V_W  = tw_v_w(DIAG, S_W, S_FRAC, Q_W);                  // v_k = (Q x)_k (Q_FRAC)
localparam QV_W = tw_qv_w(DIAG, S_W, S_FRAC, Q_W);                 // q (Q_FRAC)
localparam QF_W = tw_qf_w(DIAG, S_W, S_FRAC, Q_W, Q_FRAC, F_FRAC); // q_out (F_FRAC)

input  wire              clk;
input  wire              rst;
input  wire              ce;
input  wire              in_valid;
input  wire [3*S_W-1:0]  s_in;
input  wire [10*Q_W-1:0] q_coef;
output wire              out_valid;
output wire [QF_W-1:0]   q_out;
output wire [3*C_W-1:0]  cq_out;

localparam LATENCY = `LAT_QM(FPGA_REGS, DIAG, CLOCKS);
// the datapath's latency (rtl/tex_latency.vh, the one source; each datapath checks its own)
localparam LAT_DP  = (DIAG != 0 && FPGA_REGS != 0) ? `LAT_QMAC_DIAG_PIPE
                   : (DIAG != 0 && CLOCKS == 2)    ? `LAT_QMAC_DIAG_FOLD
                   : (DIAG != 0 && CLOCKS == 6)    ? `LAT_QMAC_DIAG_SERIAL
                   : (DIAG != 0)                   ? `LAT_QMAC_DIAG
                   : (FPGA_REGS != 0)              ? `LAT_QMAC_FULL_FPGA
                   :                                 `LAT_QMAC_FULL;

// elaboration fails (unknown module) on an unsupported CLOCKS, or when the datapath and
// stage 4 do not add up to this block's latency in rtl/tex_latency.vh
generate
    if (CLOCKS != 1 && ((CLOCKS != 2 && CLOCKS != 6) || DIAG == 0)) begin : g_bad_clocks
        quadric_mac_clocks_must_be_1_or_2_or_6_diagonal u_error ();
    end
    if (LATENCY != LAT_DP + 1) begin : g_bad_latency
        quadric_mac_latency_mismatch_see_tex_latency_vh u_error ();
    end
endgenerate

localparam P2_W = S_W + V_W;     // product r_k (s_k v_k; diagonal: s_k x_k)
localparam M2_W = P2_W + 2;      // sum of three such products

// output shifts (constant): q by F_FRAC - Q_FRAC, v by C_FRAC - Q_FRAC + 1
localparam integer QSH = F_FRAC - Q_FRAC;
localparam integer CSH = C_FRAC - Q_FRAC + 1;
localparam integer QSH_L = QSH > 0 ? QSH : 0;   // left part
localparam integer QSH_R = QSH < 0 ? -QSH : 0;  // right (floor) part
localparam integer CSH_L = CSH > 0 ? CSH : 0;
localparam integer CSH_R = CSH < 0 ? -CSH : 0;
// wide enough to hold the input sign-extended and shifted left, and the output
localparam QX_W = QV_W + QSH_L + QF_W;
localparam CX_W = V_W + CSH_L + C_W;

// ---------------------------------------------------------------------------
// stages 1-3: the datapath the parameters pick

wire              dp_valid;  // the datapath's out_valid: r and v hold a vector
wire [3*P2_W-1:0] dp_r;      // {r2, r1, r0}
wire [4*V_W-1:0]  dp_v;      // {v3, v2, v1, v0} (diagonal: v3 = J)

generate
    if (DIAG != 0 && FPGA_REGS != 0) begin : g_diag_pipe
        qmac_diag_pipe #(.S_W(S_W), .S_FRAC(S_FRAC), .Q_W(Q_W)) u_dp (
            .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .s_in(s_in), .q_coef(q_coef),
            .out_valid(dp_valid), .r_out(dp_r), .v_out(dp_v));
    end else if (DIAG != 0 && CLOCKS == 2) begin : g_diag_fold
        qmac_diag_fold #(.S_W(S_W), .S_FRAC(S_FRAC), .Q_W(Q_W)) u_dp (
            .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .s_in(s_in), .q_coef(q_coef),
            .out_valid(dp_valid), .r_out(dp_r), .v_out(dp_v));
    end else if (DIAG != 0 && CLOCKS == 6) begin : g_diag_serial
        qmac_diag_serial #(.S_W(S_W), .S_FRAC(S_FRAC), .Q_W(Q_W)) u_dp (
            .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .s_in(s_in), .q_coef(q_coef),
            .out_valid(dp_valid), .r_out(dp_r), .v_out(dp_v));
    end else if (DIAG != 0) begin : g_diag
        qmac_diag #(.S_W(S_W), .S_FRAC(S_FRAC), .Q_W(Q_W)) u_dp (
            .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .s_in(s_in), .q_coef(q_coef),
            .out_valid(dp_valid), .r_out(dp_r), .v_out(dp_v));
    end else begin : g_full
        qmac_full #(.S_W(S_W), .S_FRAC(S_FRAC), .Q_W(Q_W), .FPGA_REGS(FPGA_REGS)) u_dp (
            .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .s_in(s_in), .q_coef(q_coef),
            .out_valid(dp_valid), .r_out(dp_r), .v_out(dp_v));
    end
endgenerate

wire signed [P2_W-1:0] r0 = dp_r[0*P2_W +: P2_W];
wire signed [P2_W-1:0] r1 = dp_r[1*P2_W +: P2_W];
wire signed [P2_W-1:0] r2 = dp_r[2*P2_W +: P2_W];
wire signed [V_W-1:0]  v0 = dp_v[0*V_W +: V_W];
wire signed [V_W-1:0]  v1 = dp_v[1*V_W +: V_W];
wire signed [V_W-1:0]  v2 = dp_v[2*V_W +: V_W];
wire signed [V_W-1:0]  v3 = dp_v[3*V_W +: V_W];

// ---------------------------------------------------------------------------
// stage 4: q = (sum >>> S_FRAC) + v3, then the output shifts, and the output registers and
// their valid bit: one clocked process, the arithmetic only on an enabled clock that brings a
// valid vector (dp_valid; the output registers hold otherwise)

/* verilator lint_off UNUSEDSIGNAL */
// low S_FRAC bits dropped by the floor, high bits are sign copies
// of a value that fits QV_W (model/hw/config.py: qv_w)
reg signed [M2_W-1:0] mq;
// q -> q_out: bits dropped by a right (floor) shift and bits above QF_W, which are
// sign copies: q_out fits QF_W (model/hw/config.py: qf_w)
reg signed [QX_W-1:0] q_x, q_sh;
// v_k -> cq_k: bits dropped by a right (floor) shift and bits above C_W, which are
// sign copies: 2 v_k fits C_W (model/hw/config.py: c_w >= bits of cq_max)
reg signed [CX_W-1:0] v0_x, v1_x, v2_x, c0_sh, c1_sh, c2_sh;
/* verilator lint_on UNUSEDSIGNAL */
reg signed [QV_W-1:0] q;

reg             out_valid_reg;
reg [QF_W-1:0]  q_out_reg;
reg [3*C_W-1:0] cq_out_reg;

/* verilator lint_off BLKSEQ */
always @(posedge clk) begin
    // every temporary wholly assigned first, outside the if (C++ locals in the Verilator model)
    mq    = {M2_W{1'b0}};
    q     = {QV_W{1'b0}};
    q_x   = {QX_W{1'b0}};
    q_sh  = {QX_W{1'b0}};
    v0_x  = {CX_W{1'b0}};
    v1_x  = {CX_W{1'b0}};
    v2_x  = {CX_W{1'b0}};
    c0_sh = {CX_W{1'b0}};
    c1_sh = {CX_W{1'b0}};
    c2_sh = {CX_W{1'b0}};
    if (ce && dp_valid) begin
        mq = {{2{r0[P2_W-1]}}, r0} + {{2{r1[P2_W-1]}}, r1} + {{2{r2[P2_W-1]}}, r2};
        q  = mq[S_FRAC +: QV_W] + {{(QV_W-V_W){v3[V_W-1]}}, v3};
        // q: sign-extend to QX_W, shift by the constant QSH, keep QF_W bits
        q_x  = {{(QX_W-QV_W){q[QV_W-1]}}, q};
        q_sh = (q_x <<< QSH_L) >>> QSH_R;
        // v_k: sign-extend to CX_W, shift by the constant CSH, keep C_W bits
        v0_x  = {{(CX_W-V_W){v0[V_W-1]}}, v0};
        v1_x  = {{(CX_W-V_W){v1[V_W-1]}}, v1};
        v2_x  = {{(CX_W-V_W){v2[V_W-1]}}, v2};
        c0_sh = (v0_x <<< CSH_L) >>> CSH_R;
        c1_sh = (v1_x <<< CSH_L) >>> CSH_R;
        c2_sh = (v2_x <<< CSH_L) >>> CSH_R;
    end
    if (rst) begin
        out_valid_reg <= 1'b0;
        q_out_reg     <= {QF_W{1'b0}};
        cq_out_reg    <= {3*C_W{1'b0}};
    end else if (ce) begin
        out_valid_reg <= dp_valid;
        if (dp_valid) begin
            q_out_reg  <= q_sh[QF_W-1:0];
            cq_out_reg <= {c2_sh[C_W-1:0], c1_sh[C_W-1:0], c0_sh[C_W-1:0]};
        end
    end
end
/* verilator lint_on BLKSEQ */

assign out_valid = out_valid_reg;
assign q_out     = q_out_reg;
assign cq_out    = cq_out_reg;

endmodule

`default_nettype wire
