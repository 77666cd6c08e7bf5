// cmap_sat2: the trapezoid family of colour_map (filter "sat2", issue 27): RGBA8 of the colour
// index u averaged over the pixel when f is linear across it, the colour map convolved with
// two boxes of widths a and b (the screen components of grad f N); the bit-exact twin of
// model/hw/golden.py cmap_sat2.
//
// Formats (derived from the parameters by rtl/tex_widths.vh, as in colour_map):
//   u_in   s{U_W}.{F_FRAC} colour-table entries (colour_map's stage 1: f N taken mod N, or
//          clipped to [-W, N + W], W = 2^W_CAP_LOG2: sat2's guard, its window reaches W)
//   w_in   {b, a}, each u{W_W}.{F_FRAC} entries, W_W = W_CAP_LOG2 + F_FRAC + 1 (filter_width
//          with COMPONENTS; both 0 when the filter is off); contract a, b <= 2^(W_CAP_LOG2 + F_FRAC)
//   mode   0 mod, 1 clamp; n_log2: N = 2^n_log2 entries, n_log2 <= N_LOG2_MAX
//   rgba_out RGBA8, channel c at [8c+7:8c]
// Computation (docs/numerics.md, "The trapezoid"): the window ends (s{X2_W}.{XF}, XF = F_FRAC + 1)
//   e1 = 2u + a + b, e2 = 2u + a - b, e3 = 2u - a + b, e4 = 2u - a - b,
// per end sat_index, the reads of sat2_table (clut[kk], csat[kk-1], csat2[kk-1]: H, the
// running sum of csat) and sat2_integral (v1 = S(e) 2^XF, v2 = 2G(e) 2^2XF, mod 2^D2_W), then
//   a, b > 0:        D = v2(e1) - v2(e2) - v2(e3) + v2(e4) = 8 avg ab, divisor w = 4ab
//   a = 0 or b = 0:  D = v1(e1) - v1(e4) = 2 avg (a + b), w = a + b   (the box of width a + b,
//                    the same D and w as cmap_sat's)
//   a = b = 0:       w = 0, the point lookup clut[kk] of e1 = 2u
// (D mod 2^D2_W, exact: 0 <= D <= 255 * 2w < 2^D2_W) and out = cmap_divide(D, w) = D / 2w
// rounded (exact or normalised by DIV_BITS; w = 0: the point lookup passed through).
// Tables (sat2_table): the write port as colour_map's (wr_table 0 clut, 1 csat in ascending
// order; csat2 derived from the csat writes).
// Pipeline (stage numbers: colour_map's): 2 e1..e4 | 3 sat_index x4, the divisor ab or a + b
// | 4 sat2_table reads | 5 sat2_integral x4 (cmap_divide: the normaliser on w) | 6 D
// (cmap_divide: the operands) | 7..14 cmap_divide's box_divide.
// FPGA_REGS = 1 ([fpga_regs]): the table outputs registered (4b), sat2_integral's terms
// registered before their sums (5a), D registered (6a), cmap_divide's own stage (6c): as
// cmap_sat.
// Latency `LAT_CMAP_SAT2 = 13 register stages (FPGA_REGS: `LAT_CMAP_SAT2_FPGA = 17) from the
// stage-1 registers of colour_map; throughput one pixel per enabled clock.
// Reset (synchronous, active high) clears the valid chain and rgba_out (no X after reset).
// Written for event-driven simulation speed: combinational logic in one always @* per
// stage, one clocked process per stage group, no bus driven piecewise.

`default_nettype none

`include "tex_latency.vh"

module cmap_sat2 #(
    // colour_map's parameters of the same names (config/<name>.toml keys in brackets)
    parameter F_FRAC     = 13,  // [f_frac] fraction bits of u, a and b
    parameter W_CAP_LOG2 = 11,  // [w_cap_log2] a and b saturate at 2^W_CAP_LOG2 entries
    parameter N_LOG2_MAX = 8,   // [n_log2_max] log2 of the largest colour table (>= 1)
    parameter DIV_BITS   = 0,   // [div_bits] the division: 0 exact, B > 0 on a B-bit divisor
    parameter FPGA_REGS  = 0    // [fpga_regs] 1: the register stages above
) (clk, rst, ce, in_valid, u_in, w_in, mode, n_log2, wr_en, wr_table, wr_addr, wr_data, out_valid, rgba_out);

`include "tex_widths.vh"

localparam W_W    = W_CAP_LOG2 + F_FRAC + 1;                       // a, b
localparam U_W    = tw_u_w(N_LOG2_MAX, F_FRAC, W_CAP_LOG2 + 1);    // u (signed; guard W)
localparam X_W    = tw_x2_w(N_LOG2_MAX, F_FRAC, W_CAP_LOG2);       // window ends (signed)
localparam XF     = F_FRAC + 1;                                    // their fraction bits
localparam CS_W   = tw_csat_w(N_LOG2_MAX);                         // csat channel
localparam CS2_W  = tw_csat2_w(N_LOG2_MAX);                        // csat2 channel
localparam D_W    = tw_d2_w(F_FRAC, W_CAP_LOG2);                   // D
localparam WD_W   = tw_w2_w(F_FRAC, W_CAP_LOG2);                   // the divisor 4ab or a + b
localparam NMAX   = N_LOG2_MAX;
localparam NL_W   = tw_bits_unsigned(N_LOG2_MAX);                  // n_log2
localparam KW     = X_W - XF;           // entry index of a window end (signed)

localparam P      = FPGA_REGS ? 1 : 0;  // each optional register stage (delay_line of P stages)
localparam LAT    = FPGA_REGS ? `LAT_CMAP_SAT2_FPGA : `LAT_CMAP_SAT2;
localparam LAT_DV = FPGA_REGS ? `LAT_CMAP_DIVIDE_FPGA : `LAT_CMAP_DIVIDE;

input  wire                 clk;
input  wire                 rst;
input  wire                 ce;
input  wire                 in_valid;
input  wire [U_W-1:0]       u_in;       // signed
input  wire [2*W_W-1:0]     w_in;       // {b, a}
input  wire                 mode;       // 0 mod, 1 clamp
input  wire [NL_W-1:0]      n_log2;
// table write port
input  wire                 wr_en;
input  wire [1:0]           wr_table;   // 0 clut, 1 csat
input  wire [NMAX:0]        wr_addr;
input  wire [4*CS_W-1:0]    wr_data;
output wire                 out_valid;
output wire [31:0]          rgba_out;

// elaboration fails (unknown module) when the stages below do not add up to the latency
// (2..5, 4b, 5a, 6a, then cmap_divide) or D does not fit 64 bits
generate
    if (LAT != 4 + 3*P + LAT_DV) begin : g_bad_latency
        cmap_sat2_latency_mismatch u_error ();
    end
    if (D_W > 62) begin : g_bad_params
        cmap_sat2_unsupported_widths u_error ();
    end
endgenerate

// ---- stage 2: the window ends e = 2u -+ a -+ b
reg [X_W-1:0] u2, a_x, b_x;
always @* begin
    u2 = {X_W{u_in[U_W-1]}};
    u2[U_W:1] = u_in;
    u2[0] = 1'b0;
    a_x = {X_W{1'b0}};
    a_x[W_W-1:0] = w_in[W_W-1:0];
    b_x = {X_W{1'b0}};
    b_x[W_W-1:0] = w_in[W_W +: W_W];
end

// the registers of stages 2..5 (loaded by one clocked process below)
reg [3:0]       sv_reg;         // valid of stage s (2..5) at bit s - 2
reg [4*X_W-1:0] s2_e_reg;       // e1..e4
reg [W_W-1:0]   s2_a_reg, s2_b_reg;
reg             s2_mode_reg;
reg [NL_W-1:0]  s2_n_log2_reg;
reg [NMAX-1:0]  s2_nm1_reg;     // FPGA_REGS: N - 1 for sat_index (else not read)

// ---- stage 3: table addresses and weights of the four ends; the divisor
wire [4*NMAX-1:0] kk, km1;
wire [3:0]        first;
wire [4*XF-1:0]   fr;
wire [4*KW-1:0]   kx;
genvar ge;
generate
    for (ge = 0; ge < 4; ge = ge + 1) begin : g_end
        sat_index #(.X_W(X_W), .XF(XF), .NMAX(NMAX), .NL_W(NL_W), .NM1_IN(FPGA_REGS)) u_index (
            .clk(clk), .ce(ce), .x_in(s2_e_reg[ge*X_W +: X_W]), .mode(s2_mode_reg), .n_log2(s2_n_log2_reg),
            .nm1_in(s2_nm1_reg), .kk_out(kk[ge*NMAX +: NMAX]), .km1_out(km1[ge*NMAX +: NMAX]),
            .first_out(first[ge]), .fr_out(fr[ge*XF +: XF]), .kx_out(kx[ge*KW +: KW])
        );
    end
endgenerate

// the divisor: 4ab (a, b > 0), a + b (the box), 0 (the point); box: the box's D
reg [WD_W-1:0] wd_n;
reg            box_n;
always @* begin
    box_n = (s2_a_reg == {W_W{1'b0}}) || (s2_b_reg == {W_W{1'b0}});
    wd_n = {WD_W{1'b0}};
    if (box_n)
        wd_n = {{(WD_W-W_W){1'b0}}, s2_a_reg} + {{(WD_W-W_W){1'b0}}, s2_b_reg};
    else
        wd_n = ({{(WD_W-W_W){1'b0}}, s2_a_reg} * {{(WD_W-W_W){1'b0}}, s2_b_reg}) << 2;
end

reg [WD_W-1:0]  s3_w_reg;
reg             s3_box_reg;
reg             s3_mode_reg;
reg [NL_W-1:0]  s3_n_log2_reg;

// ---- stage 4: table reads of the four ends
wire [4*32-1:0]    clut;
wire [16*CS_W-1:0] csat;
wire [16*CS2_W-1:0] csat2;
wire [4*CS_W-1:0]  total;
wire [4*CS2_W-1:0] total2;

sat2_table #(.NMAX(NMAX), .CS_W(CS_W), .CS2_W(CS2_W)) u_table (
    .clk(clk), .ce(ce),
    .wr_en(wr_en), .wr_table(wr_table), .wr_addr(wr_addr), .wr_data(wr_data),
    .clut_addr(kk), .csat_addr(km1),
    .clut(clut), .csat(csat), .csat2(csat2), .total(total), .total2(total2)
);

reg [WD_W-1:0]  s4_w_reg;
reg             s4_box_reg;
reg             s4_mode_reg;
reg [NL_W-1:0]  s4_n_log2_reg;
reg [4*NMAX-1:0] s4_kk_reg;
reg [4*KW-1:0]  s4_kx_reg;
reg [4*XF-1:0]  s4_fr_reg;
reg [3:0]       s4_first_reg;

// ---- stage 4b (FPGA_REGS): the table outputs and stage 4's registers registered again
// (x: P stages after the read; y: 2P, beside sat2_integral's terms)
wire [4*32-1:0]     clut_x;
wire [16*CS_W-1:0]  csat_x;
wire [16*CS2_W-1:0] csat2_x;
wire [WD_W-1:0]     s4x_w;
wire                s4x_box, s4x_mode, s4y_box;
wire [NL_W-1:0]     s4x_n_log2;
wire [4*NMAX-1:0]   s4x_kk;
wire [4*KW-1:0]     s4x_kx;
wire [4*XF-1:0]     s4x_fr;
wire [3:0]          s4x_first;
wire [31:0]         point_y;    // clut[kk] of e1 (= 2u): the point lookup
delay_line #(.W(128 + 16*CS_W + 16*CS2_W), .N(P)) u_dly_tbl (.clk(clk), .rst(rst), .ce(ce),
    .d_in({clut, csat, csat2}), .d_out({clut_x, csat_x, csat2_x}));
delay_line #(.W(WD_W + 2 + NL_W + 4*NMAX + 4*KW + 4*XF + 4), .N(P)) u_dly_s4 (.clk(clk), .rst(rst), .ce(ce),
    .d_in({s4_w_reg, s4_box_reg, s4_mode_reg, s4_n_log2_reg, s4_kk_reg, s4_kx_reg, s4_fr_reg, s4_first_reg}),
    .d_out({s4x_w, s4x_box, s4x_mode, s4x_n_log2, s4x_kk, s4x_kx, s4x_fr, s4x_first}));
delay_line #(.W(32 + 1), .N(P)) u_dly_s4y (.clk(clk), .rst(rst), .ce(ce),
    .d_in({clut_x[31:0], s4x_box}), .d_out({point_y, s4y_box}));

// ---- stage 5: the integrals of the four ends
wire [16*(D_W)-1:0] v1, v2;   // end i, channel c at [(4i + c) D_W +: D_W]
generate
    for (ge = 0; ge < 4; ge = ge + 1) begin : g_int
        sat2_integral #(.XF(XF), .KW(KW), .NMAX(NMAX), .NL_W(NL_W), .CS_W(CS_W), .CS2_W(CS2_W), .D_W(D_W),
                        .PIPE(P)) u_integral (
            .clk(clk), .ce(ce), .c_in(clut_x[ge*32 +: 32]), .cs_in(csat_x[ge*4*CS_W +: 4*CS_W]),
            .h_in(csat2_x[ge*4*CS2_W +: 4*CS2_W]), .total_in(total), .total2_in(total2),
            .first_in(s4x_first[ge]), .fr_in(s4x_fr[ge*XF +: XF]), .kx_in(s4x_kx[ge*KW +: KW]),
            .kk_in(s4x_kk[ge*NMAX +: NMAX]), .mode(s4x_mode), .n_log2(s4x_n_log2),
            .v1_out(v1[ge*4*D_W +: 4*D_W]), .v2_out(v2[ge*4*D_W +: 4*D_W])
        );
    end
endgenerate

reg             s5_box_reg;
reg [31:0]      s5_point_reg;

// ---- stages 2..5 registers
always @(posedge clk) begin
    if (rst)
        sv_reg <= 4'b0000;
    else if (ce)
        sv_reg <= {sv_reg[2:0], in_valid};
    if (ce) begin
        // stage 2
        s2_e_reg[0*X_W +: X_W] <= u2 + a_x + b_x;
        s2_e_reg[1*X_W +: X_W] <= u2 + a_x - b_x;
        s2_e_reg[2*X_W +: X_W] <= u2 - a_x + b_x;
        s2_e_reg[3*X_W +: X_W] <= u2 - a_x - b_x;
        s2_a_reg       <= w_in[W_W-1:0];
        s2_b_reg       <= w_in[W_W +: W_W];
        s2_mode_reg    <= mode;
        s2_n_log2_reg  <= n_log2;
        s2_nm1_reg     <= ~({NMAX{1'b1}} << n_log2);
        // stage 3
        s3_w_reg       <= wd_n;
        s3_box_reg     <= box_n;
        s3_mode_reg    <= s2_mode_reg;
        s3_n_log2_reg  <= s2_n_log2_reg;
        // stage 4
        s4_w_reg       <= s3_w_reg;
        s4_box_reg     <= s3_box_reg;
        s4_mode_reg    <= s3_mode_reg;
        s4_n_log2_reg  <= s3_n_log2_reg;
        s4_kk_reg      <= kk;
        s4_kx_reg      <= kx;
        s4_fr_reg      <= fr;
        s4_first_reg   <= first;
        // stage 5
        s5_box_reg     <= s4y_box;
        s5_point_reg   <= point_y;
    end
end

// ---- stage 6(a): D per channel (mod 2^D_W): the trapezoid's second difference of 2G, or the
// box's difference of S; FPGA_REGS: registered (6a) with the point lookup
reg [4*D_W-1:0] d_all;
integer         c6;
always @* begin
    for (c6 = 0; c6 < 4; c6 = c6 + 1) begin
        if (s5_box_reg)
            d_all[c6*D_W +: D_W] = v1[(0*4 + c6)*D_W +: D_W] - v1[(3*4 + c6)*D_W +: D_W];
        else
            d_all[c6*D_W +: D_W] = v2[(0*4 + c6)*D_W +: D_W] - v2[(1*4 + c6)*D_W +: D_W]
                                 - v2[(2*4 + c6)*D_W +: D_W] + v2[(3*4 + c6)*D_W +: D_W];
    end
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
cmap_divide #(.W_W(WD_W), .D_W(D_W), .DIV_BITS(DIV_BITS), .FPGA_REGS(FPGA_REGS)) u_divide (
    .clk(clk), .rst(rst), .ce(ce), .w_in(s4x_w), .in_valid(d_valid), .d_in(d_6), .pt_in(point_6),
    .out_valid(out_valid), .q_out(rgba_out)
);

endmodule

`default_nettype wire
