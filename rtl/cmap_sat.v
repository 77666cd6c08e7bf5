// cmap_sat: the box-filter (SAT, summed-area table) family of colour_map: RGBA8 of the colour
// index u averaged over the window [u - w/2, u + w/2] (paper 3.3, eq. 13-15 and every edge
// case of 3.3.2 as one integral); the bit-exact twin of model/hw/golden.py cmap_sat.
//
// Formats (derived from the parameters by rtl/tex_widths.vh, as in colour_map):
//   u_in  s{U_W}.{F_FRAC} colour-table entries (colour_map's stage 1: f N taken mod N, or
//         clipped to [-W/2, N + W/2], W = 2^W_CAP_LOG2)
//   w_in  u{W_W}.{F_FRAC} entries, W_W = W_CAP_LOG2 + F_FRAC + 1; 0: the point lookup
//         (colour_map forces it when the filter is off); contract w <= 2^(W_CAP_LOG2 + F_FRAC)
//   mode  0 mod, 1 clamp; n_log2: N = 2^n_log2 entries, n_log2 <= N_LOG2_MAX
//   rgba_out RGBA8, channel c at [8c+7:8c]
// Computation (docs/numerics.md, "Colour map"): a = 2u - w, b = 2u + w (s{X_W}.{F_FRAC+1}),
// and per channel
//   D = I(b) - I(a) = ((whole + csat[kb-1] - csat[ka-1]) << XF) + fr_b clut[kb] - fr_a clut[ka]
// (sat_index, colour_table, sat_integral at both ends), whole = (kx_b - kx_a) total (mod: kx =
// whole tables before x) or kx_b clut[kb] - kx_a clut[ka] (clamp: kx = whole entries past an
// edge), formed by two KW x QW multipliers in either mode (mod: the bytes of total; QW = 8 for
// N_LOG2_MAX <= 8); computed mod 2^D_W, exact since 0 <= D <= 255 * 2w < 2^D_W (one
// expression, d_of below); then out = cmap_divide(D, w), the box average D / 2w rounded
// (exact or normalised by DIV_BITS), or, w = 0, the point lookup clut[k] read at window end a
// (a = b = 2u), which cmap_divide passes through.
// Tables (colour_table, FILTER 1: clut, csat and the whole-table sum total): the write port
// as colour_map's (wr_table 0 clut, 1 csat; csat in ascending order).
// Pipeline: 2 a, b | 3 sat_index x2 | 4 colour_table reads, multiplier operands | 5
// sat_integral x2 (cmap_divide: the normaliser on w) | 6 D (cmap_divide: the operands) |
// 7..14 cmap_divide's box_divide.
// FPGA_REGS = 1 ([fpga_regs]): N - 1 decoded from n_log2 in stage 2 and registered for
// sat_index (no extra stage); the table outputs registered before the multipliers (4b: the
// block RAM's clock-to-out off the multiplier path; the multipliers' q operands selected
// before it); sat_integral's products registered before their sums (5a); D registered (6a,
// two carry chains deep) before cmap_divide adds w; cmap_divide's own stage (6c).
// CLOCKS = 4 ([cmap_clocks], the fold; FPGA_REGS = 0 only): the same values a channel a clock.
// Stages 2-4 load once a pixel and hold (the contract: a pixel comes at most every 4 enabled
// clocks); on the four enabled clocks from stage 4's valid, channel c = 0..3 passes one
// sat_integral_serial at each window end (5), D of that channel (6), cmap_divide with one lane
// (the normaliser on the held w; 7..14 one box_divide lane), and the bytes are assembled
// (channel 0 in R), rgba_out and out_valid loading with the fourth (stage 18).
// Latency `LAT_CMAP_SAT = 13 register stages (FPGA_REGS: `LAT_CMAP_SAT_FPGA = 17; CLOCKS = 4:
// `LAT_CMAP_SAT_SERIAL = 17, the three later channels and the assembly register; the rule
// `LAT_CMS) from the stage-1 registers of colour_map; throughput one pixel per enabled clock
// (CLOCKS = 4: one per four).
// Reset (synchronous, active high) clears the valid chain and rgba_out (no X after reset).
// Written for simulation speed: stages 2..5 load only on the enabled clocks that bring them a
// valid pixel (stage 5 and sat_integral with FPGA_REGS: every enabled clock) and hold
// otherwise; stage 2's words, sat_index's and sat_integral's logic are computed in their
// clocked processes, so a simulator skips them on the other clocks; the multiplier operand
// select of stage 5 and D (stage 6) stay in always @* (their results are read by other
// modules in the same clock); one clocked process per stage group, no bus driven piecewise.
// Each such process first assigns its temporaries whole, outside any if, so that they are
// C++ locals in the Verilator model (it localizes only a variable wholly assigned outside
// any branch; one first assigned under the if stays a member of the model, a store on every
// write).

`default_nettype none

`include "tex_latency.vh"

module cmap_sat #(
    // colour_map's parameters of the same names (config/<name>.toml keys in brackets)
    parameter F_FRAC     = 16,  // [f_frac] fraction bits of u and w
    parameter W_CAP_LOG2 = 16,  // [w_cap_log2] w saturates at 2^W_CAP_LOG2 entries
    parameter N_LOG2_MAX = 8,   // [n_log2_max] log2 of the largest colour table (>= 1)
    parameter DIV_BITS   = 0,   // [div_bits] box-filter division: 0 exact, B > 0 on B-bit w
    parameter FPGA_REGS  = 0,   // [fpga_regs] 1: the register stages above
    parameter CLOCKS     = 1    // [cmap_clocks] 1: a pixel a clock; 4: a channel a clock, a pixel in at
                                // most every 4 enabled clocks (FPGA_REGS = 0 only; the fold above)
) (clk, rst, ce, in_valid, u_in, w_in, mode, n_log2, wr_en, wr_table, wr_addr, wr_data, out_valid, rgba_out);

`include "tex_widths.vh"

localparam W_W    = W_CAP_LOG2 + F_FRAC + 1;                       // w
localparam U_W    = tw_u_w(N_LOG2_MAX, F_FRAC, W_CAP_LOG2);        // u (signed)
localparam X_W    = tw_x_w(N_LOG2_MAX, F_FRAC, W_CAP_LOG2);        // window ends (signed)
localparam XF     = F_FRAC + 1;                                    // their fraction bits
localparam CS_W   = tw_csat_w(N_LOG2_MAX);                         // summed-area channel
localparam D_W    = tw_d_w(F_FRAC, W_CAP_LOG2);                    // D = I(b) - I(a)
localparam NMAX   = N_LOG2_MAX;
localparam NL_W   = tw_bits_unsigned(N_LOG2_MAX);                  // n_log2
localparam KW     = X_W - XF;           // entry index of a window end (signed)
localparam TW     = D_W - XF;           // whole-entry part of D
localparam QW     = (CS_W - 8 > 8) ? CS_W - 8 : 8;  // multiplier operand: a byte of total, or clut

localparam P      = FPGA_REGS ? 1 : 0;  // each optional register stage (delay_line of P stages)
localparam LAT    = `LAT_CMS(FPGA_REGS, CLOCKS);  // the rule of rtl/tex_latency.vh
localparam SER    = (CLOCKS == 4) ? 1 : 0;  // the fold: three channels later, the assembly register
localparam LAT_DV = FPGA_REGS ? `LAT_CMAP_DIVIDE_FPGA : `LAT_CMAP_DIVIDE;

input  wire                 clk;
input  wire                 rst;
input  wire                 ce;
input  wire                 in_valid;
input  wire [U_W-1:0]       u_in;       // signed
input  wire [W_W-1:0]       w_in;
input  wire                 mode;       // 0 mod, 1 clamp
input  wire [NL_W-1:0]      n_log2;
// table write port
input  wire                 wr_en;
input  wire [1:0]           wr_table;   // 0 clut, 1 csat
input  wire [NMAX:0]        wr_addr;
input  wire [4*CS_W-1:0]    wr_data;
output wire                 out_valid;
output wire [31:0]          rgba_out;

// elaboration fails (unknown module) on an unsupported fold, or when the stages below do not
// add up to the latency: 2..5, 4b, 5a, 6a, then cmap_divide (CLOCKS = 4: then three channels
// and the assembly register)
generate
    if ((CLOCKS != 1 && CLOCKS != 4) || (CLOCKS == 4 && FPGA_REGS != 0)) begin : g_bad_params
        cmap_sat_clocks_must_be_1_or_4_without_fpga_regs u_error ();
    end
    if (LAT != 4 + 3*P + LAT_DV + 4*SER) begin : g_bad_latency
        cmap_sat_latency_mismatch u_error ();
    end
endgenerate

// ---- stage 2: window ends a = 2u - w, b = 2u + w (filter off: w = 0, a = b = 2u), formed
// in the clocked process below
reg [X_W-1:0] u2;
reg [X_W-1:0] w_x;

// the registers of stages 2..5 (loaded by one clocked process below, each stage only on the
// enabled clocks that bring it a valid pixel: they hold otherwise)
reg [3:0]       sv_reg;         // valid of stage s (2..5) at bit s - 2
reg [X_W-1:0]   s2_a_reg;
reg [X_W-1:0]   s2_b_reg;
reg [W_W-1:0]   s2_w_reg;
reg             s2_mode_reg;
reg [NL_W-1:0]  s2_n_log2_reg;
reg [NMAX-1:0]  s2_nm1_reg;     // FPGA_REGS: N - 1 for sat_index (else not read)

// each stage's enable: ce on a clock that brings the stage a valid pixel (stages 2..4; stage
// 5 and sat_integral below: FPGA_REGS, whose words pass the extra stages 4b and 5a, on every
// enabled clock; CLOCKS = 4, on the pixel's four channel clocks)
wire ce3 = ce && sv_reg[0];
wire ce4 = ce && sv_reg[1];

// ---- stage 3: table addresses and weights of both ends
wire [NMAX-1:0] kk_a, kk_b, km1_a, km1_b;
wire            first_a, first_b;
wire [XF-1:0]   fr_a, fr_b;
wire [KW-1:0]   kx_a, kx_b;

sat_index #(.X_W(X_W), .XF(XF), .NMAX(NMAX), .NL_W(NL_W), .NM1_IN(FPGA_REGS)) u_index_a (
    .clk(clk), .ce(ce3), .x_in(s2_a_reg), .mode(s2_mode_reg), .n_log2(s2_n_log2_reg),
    .nm1_in(s2_nm1_reg), .kk_out(kk_a), .km1_out(km1_a), .first_out(first_a), .fr_out(fr_a), .kx_out(kx_a)
);
sat_index #(.X_W(X_W), .XF(XF), .NMAX(NMAX), .NL_W(NL_W), .NM1_IN(FPGA_REGS)) u_index_b (
    .clk(clk), .ce(ce3), .x_in(s2_b_reg), .mode(s2_mode_reg), .n_log2(s2_n_log2_reg),
    .nm1_in(s2_nm1_reg), .kk_out(kk_b), .km1_out(km1_b), .first_out(first_b), .fr_out(fr_b), .kx_out(kx_b)
);

reg [W_W-1:0]   s3_w_reg;
reg             s3_mode_reg;
reg [NL_W-1:0]  s3_n_log2_reg;

// ---- stage 4: table reads; multiplier operands of the whole-entry terms:
// clamp: kx_a (times clut[ka]), kx_b (times clut[kb]);
// mod:   dw = kx_b - kx_a >= 0 whole tables (times the two bytes of total)
wire [31:0]       clut_a, clut_b;
wire [4*CS_W-1:0] csat_a, csat_b, total;
/* verilator lint_off UNUSEDSIGNAL */
wire [31:0]       unused_mip_data;
/* verilator lint_on UNUSEDSIGNAL */

colour_table #(.FILTER(1), .NMAX(NMAX), .CS_W(CS_W), .NL_W(NL_W)) u_table (
    .clk(clk), .ce(ce4),
    .wr_en(wr_en), .wr_table(wr_table), .wr_addr(wr_addr), .wr_data(wr_data),
    .clut_addr_a(kk_a), .clut_addr_b(kk_b), .csat_addr_a(km1_a), .csat_addr_b(km1_b),
    .n_log2(s3_n_log2_reg), .mip_addr({(NMAX+1){1'b0}}),
    .clut_a(clut_a), .clut_b(clut_b), .csat_a(csat_a), .csat_b(csat_b), .total(total),
    .mip_data(unused_mip_data)
);

reg [W_W-1:0]   s4_w_reg;
reg             s4_mode_reg;
reg [KW-1:0]    s4_k_a_reg, s4_k_b_reg;
reg [XF-1:0]    s4_fr_a_reg, s4_fr_b_reg;
reg             s4_first_a_reg, s4_first_b_reg;

// ---- stage 4b (FPGA_REGS): the table outputs and stage 4's registers registered
// again (x: P stages after the read; y: 2P, beside sat_integral's products)
wire [31:0]       clut_ax, clut_bx, clut_ay;
wire [4*CS_W-1:0] csat_ax, csat_bx;
wire [W_W-1:0]    s4x_w;
wire              s4x_mode, s4y_mode;
wire [KW-1:0]     s4x_k_a, s4x_k_b;
wire [XF-1:0]     s4x_fr_a, s4x_fr_b;
wire              s4x_first_a, s4x_first_b;
delay_line #(.W(64 + 8*CS_W), .N(P)) u_dly_tbl (.clk(clk), .rst(rst), .ce(ce),
    .d_in({clut_a, clut_b, csat_a, csat_b}), .d_out({clut_ax, clut_bx, csat_ax, csat_bx}));
delay_line #(.W(W_W + 3 + 2*KW + 2*XF), .N(P)) u_dly_s4 (.clk(clk), .rst(rst), .ce(ce),
    .d_in({s4_w_reg, s4_mode_reg, s4_k_a_reg, s4_k_b_reg, s4_fr_a_reg, s4_fr_b_reg, s4_first_a_reg,
           s4_first_b_reg}),
    .d_out({s4x_w, s4x_mode, s4x_k_a, s4x_k_b, s4x_fr_a, s4x_fr_b, s4x_first_a, s4x_first_b}));
delay_line #(.W(32 + 1), .N(P)) u_dly_s4y (.clk(clk), .rst(rst), .ce(ce),
    .d_in({clut_ax, s4x_mode}), .d_out({clut_ay, s4y_mode}));

// ---- stage 5: partial integrals and whole-entry products of both ends
// q operands: clamp clut[ka], clut[kb]; mod total >> 8 (a), total mod 2^8 (b); selected
// from the table outputs themselves (FPGA_REGS: then registered in stage 4b with them,
// so that the selection is off the multipliers' path)
reg [4*QW-1:0] q_a_n, q_b_n;
reg [QW-1:0]   qa, qb;
integer        qc;
always @* begin
    q_a_n = {(4*QW){1'b0}};
    q_b_n = {(4*QW){1'b0}};
    for (qc = 0; qc < 4; qc = qc + 1) begin
        qa = {QW{1'b0}};
        qb = {QW{1'b0}};
        if (s4_mode_reg) begin
            qa[7:0] = clut_a[8*qc +: 8];
            qb[7:0] = clut_b[8*qc +: 8];
        end else begin
            qa[CS_W-9:0] = total[qc*CS_W+8 +: CS_W-8];
            qb[7:0]      = total[qc*CS_W +: 8];
        end
        q_a_n[qc*QW +: QW] = qa;
        q_b_n[qc*QW +: QW] = qb;
    end
end
wire [4*QW-1:0] q_a, q_b;
delay_line #(.W(8*QW), .N(P)) u_dly_q (.clk(clk), .rst(rst), .ce(ce), .d_in({q_a_n, q_b_n}),
                                       .d_out({q_a, q_b}));

// ---- stages 2..4 registers
/* verilator lint_off BLKSEQ */
always @(posedge clk) begin
    // the temporaries wholly assigned first, outside any if (C++ locals: the header)
    u2  = {X_W{1'b0}};
    w_x = {X_W{1'b0}};
    if (rst)
        sv_reg <= 4'b0000;
    else if (ce)
        sv_reg <= {sv_reg[2:0], in_valid};
    if (ce && in_valid) begin
        // stage 2
        u2 = {X_W{u_in[U_W-1]}};
        u2[U_W:1] = u_in;
        u2[0] = 1'b0;
        w_x = {X_W{1'b0}};
        w_x[W_W-1:0] = w_in;
        s2_a_reg       <= u2 - w_x;
        s2_b_reg       <= u2 + w_x;
        s2_w_reg       <= w_in;
        s2_mode_reg    <= mode;
        s2_n_log2_reg  <= n_log2;
        s2_nm1_reg     <= ~({NMAX{1'b1}} << n_log2);
    end
    if (ce3) begin
        // stage 3
        s3_w_reg       <= s2_w_reg;
        s3_mode_reg    <= s2_mode_reg;
        s3_n_log2_reg  <= s2_n_log2_reg;
    end
    if (ce4) begin
        // stage 4 (mod: dw = kx_b - kx_a on both ends)
        s4_w_reg       <= s3_w_reg;
        s4_mode_reg    <= s3_mode_reg;
        s4_k_a_reg     <= s3_mode_reg ? kx_a : kx_b - kx_a;
        s4_k_b_reg     <= s3_mode_reg ? kx_b : kx_b - kx_a;
        s4_fr_a_reg    <= fr_a;
        s4_fr_b_reg    <= fr_b;
        s4_first_a_reg <= first_a;
        s4_first_b_reg <= first_b;
    end
end
/* verilator lint_on BLKSEQ */

// ---- stage 6(a): D = (whole << XF) + p_b - p_a per channel (mod 2^D_W), whole = e_b - e_a
// (clamp) or e_b + (e_a << 8) (mod), two carry chains deep: both whole forms side by side and
// p_b - p_a beside them, then one sum; FPGA_REGS: registered (6a) with the point lookup's
// clut[k], else cmap_divide reads it from the stage-5 registers in its stage 6
function [D_W-1:0] d_of;
    input           mode_c;
    input [TW-1:0]  ea, eb;
    input [D_W-1:0] pa, pb;
    reg   [TW-1:0]  whole;
    reg   [D_W-1:0] pd;
    begin
        whole = mode_c ? eb - ea : eb + (ea << 8);
        pd    = pb - pa;
        d_of  = {whole, {XF{1'b0}}} + pd;
    end
endfunction

generate
    if (CLOCKS == 1) begin : g_lanes
        // ---- stage 5: both ends' sat_integral, the four channels at once
        wire ce5 = ce && (sv_reg[2] || P != 0);
        wire [4*D_W-1:0] p_a, p_b;
        wire [4*TW-1:0]  e_a, e_b;

        sat_integral #(.XF(XF), .KW(KW), .QW(QW), .CS_W(CS_W), .D_W(D_W), .PIPE(P)) u_integral_a (
            .clk(clk), .ce(ce5), .c_in(clut_ax), .before_in(csat_ax), .first_in(s4x_first_a),
            .fr_in(s4x_fr_a), .k_in(s4x_k_a), .q_in(q_a), .p_out(p_a), .e_out(e_a)
        );
        sat_integral #(.XF(XF), .KW(KW), .QW(QW), .CS_W(CS_W), .D_W(D_W), .PIPE(P)) u_integral_b (
            .clk(clk), .ce(ce5), .c_in(clut_bx), .before_in(csat_bx), .first_in(s4x_first_b),
            .fr_in(s4x_fr_b), .k_in(s4x_k_b), .q_in(q_b), .p_out(p_b), .e_out(e_b)
        );


        reg             s5_mode_reg;
        reg [31:0]      s5_point_reg;   // clut[ka]: the point lookup when w = 0
        always @(posedge clk) begin
            if (ce5) begin
                s5_mode_reg    <= s4y_mode;
                s5_point_reg   <= clut_ay;
            end
        end

        reg [4*D_W-1:0] d_all;
        integer         c6;
        always @* begin
            for (c6 = 0; c6 < 4; c6 = c6 + 1)
                d_all[c6*D_W +: D_W] = d_of(s5_mode_reg, e_a[c6*TW +: TW], e_b[c6*TW +: TW], p_a[c6*D_W +: D_W],
                                            p_b[c6*D_W +: D_W]);
        end
        wire [4*D_W-1:0] d_6;
        wire [31:0]      point_6;
        delay_line #(.W(4*D_W + 32), .N(P)) u_dly_d (.clk(clk), .rst(rst), .ce(ce), .d_in({d_all, s5_point_reg}),
                                                    .d_out({d_6, point_6}));

        // D's valid: stage 5's (FPGA_REGS: three stages later, 4b, 5a, 6a)
        wire d_valid;
        delay_line #(.W(1), .N(3*P), .CLEAR(1)) u_dly_dv (.clk(clk), .rst(rst), .ce(ce), .d_in(sv_reg[3]),
                                                         .d_out(d_valid));

        // ---- stages 6..14: the division (w from stage 4, 4b with FPGA_REGS: 1 + 2P stages before D)
        cmap_divide #(.W_W(W_W), .D_W(D_W), .DIV_BITS(DIV_BITS), .FPGA_REGS(FPGA_REGS)) u_divide (
            .clk(clk), .rst(rst), .ce(ce), .w_in(s4x_w), .in_valid(d_valid), .d_in(d_6), .pt_in(point_6),
            .out_valid(out_valid), .q_out(rgba_out)
        );
    end else begin : g_serial
        // ---- CLOCKS = 4: a pixel's channels c = 0..3 on the four enabled clocks from stage 4's
        // valid (its registers and the table outputs hold meanwhile: the next pixel comes at
        // least four enabled clocks later); ch_d[c - 1]: channel c is at stage 5's input
        reg  [2:0] ch_d;
        always @(posedge clk) begin
            if (rst)
                ch_d <= 3'b000;
            else if (ce)
                ch_d <= {ch_d[1:0], sv_reg[2]};
        end
        wire       ch_on = sv_reg[2] || (|ch_d);           // a channel enters stage 5
        wire [1:0] ch    = {ch_d[1] | ch_d[2], ch_d[0] | ch_d[2]};
        wire       ce5s  = ce && ch_on;
        /* verilator lint_off UNUSEDSIGNAL */  // stage 5's valid is s5_valid_reg, a channel's
        wire       unused_sv3 = sv_reg[3];
        /* verilator lint_on UNUSEDSIGNAL */

        // ---- stage 5: one channel of both ends' integrals (sat_integral_serial)
        wire [D_W-1:0] p_a, p_b;
        wire [TW-1:0]  e_a, e_b;
        sat_integral_serial #(.XF(XF), .KW(KW), .QW(QW), .CS_W(CS_W), .D_W(D_W)) u_integral_a (
            .clk(clk), .ce(ce5s), .ch_in(ch), .c_in(clut_ax), .before_in(csat_ax), .first_in(s4x_first_a),
            .fr_in(s4x_fr_a), .k_in(s4x_k_a), .q_in(q_a), .p_out(p_a), .e_out(e_a)
        );
        sat_integral_serial #(.XF(XF), .KW(KW), .QW(QW), .CS_W(CS_W), .D_W(D_W)) u_integral_b (
            .clk(clk), .ce(ce5s), .ch_in(ch), .c_in(clut_bx), .before_in(csat_bx), .first_in(s4x_first_b),
            .fr_in(s4x_fr_b), .k_in(s4x_k_b), .q_in(q_b), .p_out(p_b), .e_out(e_b)
        );
        reg       s5_valid_reg;      // stage 5 holds a channel
        reg       s5_mode_reg;
        reg [7:0] s5_point_reg;      // clut[ka][ch]: the point lookup when w = 0
        always @(posedge clk) begin
            if (rst)
                s5_valid_reg <= 1'b0;
            else if (ce)
                s5_valid_reg <= ch_on;
            if (ce5s) begin
                s5_mode_reg  <= s4y_mode;
                s5_point_reg <= clut_ay[8*ch +: 8];
            end
        end

        // ---- stage 6: D of the channel (cmap_divide reads it from the stage-5 registers)
        reg [D_W-1:0] d_1;
        always @* d_1 = d_of(s5_mode_reg, e_a, e_b, p_a, p_b);

        // ---- stages 6..14: the division, one channel a vector (w from stage 4, which holds
        // it for the pixel's four channels)
        wire       dv_valid;
        wire [7:0] dv_q;
        cmap_divide #(.W_W(W_W), .D_W(D_W), .DIV_BITS(DIV_BITS), .FPGA_REGS(0), .LANES(1)) u_divide (
            .clk(clk), .rst(rst), .ce(ce), .w_in(s4x_w), .in_valid(s5_valid_reg), .d_in(d_1),
            .pt_in(s5_point_reg), .out_valid(dv_valid), .q_out(dv_q)
        );

        // ---- stage 18: the four bytes assembled (channel 0 first: R at [7:0]); out_valid
        // with the fourth
        reg [1:0]  oc;               // the channel dv_q holds
        reg [23:0] bytes_reg;        // channels 0..2, the latest at [23:16]
        reg        out_valid_reg;
        reg [31:0] rgba_reg;
        always @(posedge clk) begin
            if (rst) begin
                oc            <= 2'd0;
                out_valid_reg <= 1'b0;
                rgba_reg      <= 32'd0;
            end else if (ce) begin
                out_valid_reg <= dv_valid && (oc == 2'd3);
                if (dv_valid) begin
                    oc <= oc + 2'd1;
                    if (oc == 2'd3)
                        rgba_reg  <= {dv_q, bytes_reg};
                    else
                        bytes_reg <= {dv_q, bytes_reg[23:8]};
                end
            end
        end
        assign out_valid = out_valid_reg;
        assign rgba_out  = rgba_reg;
    end
endgenerate

endmodule

`default_nettype wire
