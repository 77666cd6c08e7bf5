// cmap_divide: the box-filter division of colour_map's SAT filter families, one module with
// its two methods as a parameter (DIV_BITS); the bit-exact twin of model/hw/golden.py
// cmap_divide. Per channel c of a pixel (LANES channels an enabled clock: 4, or 1 when
// colour_map takes a pixel's channels on four clocks, features.cmap_clocks = 4):
//   w > 0: out_c = the box average D_c / (2w) rounded (docs/numerics.md, "Colour map"):
//     DIV_BITS = 0 (exact): out = floor((D + w) / (2w)) = floor(((D + w) >> 1) / w) by
//       box_divide on u{D_W-1} / u{W_W} (8 quotient bits: D + w <= 511 w < 2^8 * 2w, so
//       out <= 255, never 256);
//     DIV_BITS = B > 0 (normalised; built when B < W_W, else w never has more than B bits and
//       the exact division is built): h(s) = 2^s >> 1,
//         sh0 = bitlen(w >> B), w_r = w + h(sh0), sh = bitlen(w_r >> B) (sh0 or sh0 + 1),
//         den' = w_r >> sh = round(w / 2^sh) (u{B}, >= 2^(B-1) when sh > 0),
//         num' = (D + w + 2 h(sh)) >> (sh + 1) = round(((D + w) / 2) / 2^sh),
//         out = min(floor(num' / den'), 255) by box_divide on u{NQ_W} / u{B}, NQ_W = B + 8
//         (num' < 256 den' for B >= 10: no saturation needed) or B + 9 with SAT (B <= 9:
//         num' < 384 den', quotients up to 383 saturate); sh0, den', sh and w + 2 h(sh) are
//         computed once for the vector's LANES channels; error <= 1/2 + 513 / 2^(B+1) LSB;
//   w = 0: out = pt_c (the point lookup clut[k]), fed through the divider as num = pt_c,
//     den = 1 (normalised: sh = 0).
//
// Formats: w_in u{W_W}.{F_FRAC} entries (the fraction is immaterial here: D carries one more,
// D / 2w is the average); d_in 4 x u{D_W}.{F_FRAC+1} (D_c = I(b) - I(a), channel c at
// [c*D_W +: D_W]; contract: 0 <= D_c <= 255 * 2w, so D_c < 2^D_W); pt_in RGBA8 (channel c at
// [8c +: 8]); q_out RGBA8.
// Timing: w_in is the divisor of the vector whose D (in_valid, d_in, pt_in) comes WLEAD =
// 1 + 2 FPGA_REGS enabled clocks later (the normaliser works on w while colour_map's
// cmap_sat forms D). Latency `LAT_CMAP_DIVIDE = 9 register stages from d_in to q_out
// (FPGA_REGS: `LAT_CMAP_DIVIDE_FPGA = 10); throughput one pixel per enabled clock.
// Pipeline (stage numbers: cmap_sat's): w | 5 the normaliser (sh0 = bitlen(w >> B) by a
// leading-one detector, den', sh, w + 2 h(sh)) or w registered (exact) | (D arrives) 6 the
// numerators (D + w) >> 1 (exact) or (D + w + 2 h(sh)) >> (sh + 1), the divisor, registered |
// 7..14 box_divide (one quotient bit per stage).
// FPGA_REGS = 1 ([fpga_regs]): sh0 and the two candidates of 2 h(sh) registered (5a), w
// delayed beside it; then den', sh, w + 2 h(sh) (5b); these words wait a stage for D
// (cmap_sat's 6a); the sums D + w (+ 2 h(sh)) registered before the shift (6c; the exact
// division registers its operands there): one stage more after d_in, two before it.
// Reset (synchronous, active high) clears the valid chain and q_out (box_divide).
// Written for simulation speed: stage 6's operands are computed in its clocked process
// (blocking temporaries) only on a clock that brings a valid D, and hold otherwise (as do
// box_divide's stages; FPGA_REGS: exact, the 6c register after them loads on every enabled
// clock; normalised, stage 6 and 6c stay in always @* and a delay line on every enabled
// clock, so that the 6c words add no toggle points to this module); the normaliser (stage 5:
// w comes WLEAD enabled clocks before its D, and no valid of w reaches this block) stays in
// always @* on every enabled clock; one clocked process per stage group, no bus driven
// piecewise.
// Each such process first assigns its temporaries whole, outside any if, so that they are
// C++ locals in the Verilator model (it localizes only a variable wholly assigned outside
// any branch; one first assigned under the if stays a member of the model, a store on every
// write).

`default_nettype none

`include "tex_latency.vh"

module cmap_divide #(
    parameter W_W       = 28,  // width of w: W_CAP_LOG2 + F_FRAC + 1 (rtl/colour_map.v)
    parameter D_W       = 37,  // width of D (tw_d_w in rtl/tex_widths.vh): D < 2^D_W
    parameter DIV_BITS  = 0,   // [div_bits] the method: 0 exact; B > 0 w normalised to B bits
    parameter FPGA_REGS = 0,   // [fpga_regs] 1: the register stages above
    parameter LANES     = 4    // [cmap_clocks] channels a vector: 4 (cmap_clocks 1) or 1 (cmap_clocks 4)
) (clk, rst, ce, w_in, in_valid, d_in, pt_in, out_valid, q_out);

localparam Q_W    = 8;                 // quotient bits: one RGBA8 channel (box_divide stages)
localparam P      = FPGA_REGS ? 1 : 0; // each optional register stage (delay_line of P stages)
localparam LAT    = FPGA_REGS ? `LAT_CMAP_DIVIDE_FPGA : `LAT_CMAP_DIVIDE;
localparam NORM   = (DIV_BITS > 0) && (DIV_BITS < W_W);
localparam B      = NORM ? DIV_BITS : 1;
localparam HW     = W_W - B;            // high bits of w: sh0 = bitlen(w >> B), 0..HW
localparam SH_W   = $clog2(HW + 2);     // sh = sh0 or sh0 + 1, 0..HW + 1
localparam SAT    = (B <= 9) ? 1 : 0;   // num' / den' reaches 256 only for B <= 9
localparam NQ_W   = B + Q_W + SAT;      // num' < 256 den' (B >= 10), < 384 den' (B <= 9)
localparam NUM_DW = NORM ? NQ_W : D_W - 1;  // divider operands: numerator, divisor
localparam DEN_DW = NORM ? B : W_W;

input  wire               clk;
input  wire               rst;
input  wire               ce;
input  wire [W_W-1:0]     w_in;       // WLEAD enabled clocks before its D
input  wire               in_valid;
input  wire [LANES*D_W-1:0] d_in;
input  wire [LANES*Q_W-1:0] pt_in;
output wire               out_valid;
output wire [LANES*Q_W-1:0] q_out;

// elaboration fails (unknown module) on an unsupported configuration or latency
generate
    if (NORM && NQ_W > D_W - 1) begin : g_bad_params
        cmap_divide_unsupported_div_bits u_error ();
    end
    if (LANES != 1 && LANES != 4) begin : g_bad_lanes
        cmap_divide_lanes_must_be_1_or_4 u_error ();
    end
    if (LAT != 1 + P + Q_W) begin : g_bad_latency
        cmap_divide_latency_mismatch u_error ();
    end
endgenerate

// w at stage 5 (FPGA_REGS: a stage after w_in, beside 5a)
wire [W_W-1:0] w_y;
delay_line #(.W(W_W), .N(P)) u_dly_wy (.clk(clk), .rst(rst), .ce(ce), .d_in(w_in), .d_out(w_y));

// the stage-6 operand registers, loaded in the clocked process of the method's stage 6 below
// (FPGA_REGS, normalised: after its stage 6c); num, den: what box_divide reads (FPGA_REGS,
// exact: a stage later, 6c)
reg  [LANES*NUM_DW-1:0] s6_num_reg;
reg  [DEN_DW-1:0]       s6_den_reg;
wire [LANES*NUM_DW-1:0] num;
wire [DEN_DW-1:0]       den;

generate
    if (!NORM) begin : g_exact
        // ---- stage 5: w registered (FPGA_REGS: then a stage more, beside cmap_sat's 6a)
        reg [W_W-1:0] s5_w_reg;
        always @(posedge clk) begin
            if (ce)
                s5_w_reg <= w_y;
        end
        wire [W_W-1:0] w_s;    // w at stage 6
        delay_line #(.W(W_W), .N(P)) u_dly_w6 (.clk(clk), .rst(rst), .ce(ce), .d_in(s5_w_reg), .d_out(w_s));

        // ---- stage 6: num = (D + w) >> 1, den = w, or clut[k] / 1, computed in the clocked
        // process below (blocking temporaries) only on a clock that brings a valid D
        reg                  w_zero;
        reg  [D_W-1:0]       d_w;    // w zero-extended
        reg  [W_W-1:0]       den_x;
        reg  [LANES*(D_W-1)-1:0] num_x;
        integer              c;
        // D + w (< 2^D_W); floor((D + w) / 2w) = floor(((D + w) >> 1) / w): the LSB of
        // D + w is not needed
        /* verilator lint_off UNUSEDSIGNAL */
        reg  [D_W-1:0]       sum;
        /* verilator lint_on UNUSEDSIGNAL */
        reg  [D_W-2:0]       pt;     // clut[k] zero-extended
        /* verilator lint_off BLKSEQ */
        always @(posedge clk) begin
            // the temporaries wholly assigned first, outside the if (C++ locals: the header)
            w_zero = 1'b0;
            d_w    = {D_W{1'b0}};
            den_x  = {W_W{1'b0}};
            num_x  = {(LANES*(D_W-1)){1'b0}};
            sum    = {D_W{1'b0}};
            pt     = {(D_W-1){1'b0}};
            if (ce && in_valid) begin
                w_zero = (w_s == {W_W{1'b0}});
                d_w[W_W-1:0] = w_s;
                den_x = w_s;
                if (w_zero)
                    den_x[0] = 1'b1;
                for (c = 0; c < LANES; c = c + 1) begin
                    sum = d_in[c*D_W +: D_W] + d_w;
                    pt = {(D_W-1){1'b0}};
                    pt[Q_W-1:0] = pt_in[Q_W*c +: Q_W];
                    num_x[c*(D_W-1) +: D_W-1] = w_zero ? pt : sum[D_W-1:1];
                end
                s6_num_reg <= num_x;
                s6_den_reg <= den_x;
            end
        end
        /* verilator lint_on BLKSEQ */
        // FPGA_REGS: stage 6c (the normalised method's shift stage) as one more register of
        // the operands (on every enabled clock), so that both methods have the block's one
        // latency
        delay_line #(.W(LANES*(D_W-1) + W_W), .N(P)) u_dly_6c (.clk(clk), .rst(rst), .ce(ce),
            .d_in({s6_num_reg, s6_den_reg}), .d_out({num, den}));

    end else begin : g_norm
        // ---- normalised division (B = DIV_BITS > 0):
        //   sh0 = bitlen(w >> B); t = w >> (sh0 - 1) (B + 1 bits; {w, 0} when sh0 = 0)
        //   den' = round(w / 2^sh0) = (t + 1) >> 1, or, when t is all ones (the rounding
        //   carries to 2^B), den' = 2^(B-1) with sh = sh0 + 1; else sh = sh0
        //   num' = (D + w + 2 h(sh)) >> (sh + 1), h(s) = 2^s >> 1 (half of the dropped LSB)

        // stage 5(a) (FPGA_REGS): sh0 (the leading-one detector on the HW high bits of w) and
        // the two candidates of 2 h(sh), h_0 = 2^sh0 (0 when sh0 = 0) and h_1 = 2^(sh0 + 1),
        // registered; without FPGA_REGS stage 5(b) finds sh0 itself in its own always @* and
        // these words are constant 0 (a block reading a register and another block's result
        // would run twice a clock in an event-driven simulator)
        wire [SH_W-1:0] sh0_y;
        /* verilator lint_off UNUSEDSIGNAL */  // without FPGA_REGS stage 5 forms 2 h(sh) itself
        wire [W_W:0]    h_0y, h_1y;
        /* verilator lint_on UNUSEDSIGNAL */
        if (P != 0) begin : g_5a
            reg [SH_W-1:0] sh0;
            reg [W_W:0]    h_0, h_1;
            integer        i;
            always @* begin
                sh0 = {SH_W{1'b0}};
                for (i = 0; i < HW; i = i + 1)
                    if (w_in[B + i])
                        sh0 = i[SH_W-1:0] + {{(SH_W-1){1'b0}}, 1'b1};
                h_0 = {{W_W{1'b0}}, 1'b1} << sh0;
                if (sh0 == {SH_W{1'b0}})
                    h_0 = {(W_W+1){1'b0}};
                h_1 = {{(W_W-1){1'b0}}, 2'b10} << sh0;
            end
            delay_line #(.W(SH_W + 2*W_W + 2), .N(P)) u_dly_sh0 (.clk(clk), .rst(rst), .ce(ce),
                .d_in({sh0, h_0, h_1}), .d_out({sh0_y, h_0y, h_1y}));
        end else begin : g_no5a
            assign sh0_y = {SH_W{1'b0}};
            assign h_0y  = {(W_W+1){1'b0}};
            assign h_1y  = {(W_W+1){1'b0}};
        end

        // ---- stage 5(b): sh, den' and w + 2 h(sh) from w, once for the four channels
        // 2w >> sh0: < 2^(B+1), bits B..0 are t (bitlen(w) <= B + sh0)
        /* verilator lint_off UNUSEDSIGNAL */
        reg [W_W:0]    w2s;
        /* verilator lint_on UNUSEDSIGNAL */
        reg [B:0]      t;
        reg            ovf;    // t all ones: w rounds up to 2^B at shift sh0
        reg [B-1:0]    den_n;  // den' = round(w / 2^sh)
        reg [SH_W-1:0] sh;
        reg [W_W:0]    h2;     // 2 h(sh): 2^sh, 0 when sh = 0
        // FPGA_REGS: w + 2 h(sh) from the two candidates sh = sh0 and sh0 + 1, formed
        // beside the shift that decides between them (the same value)
        reg [W_W:0]    wn_0, wn_1, wn_f;
        reg [SH_W-1:0] sh0_v;  // sh0 (FPGA_REGS: from stage 5a)
        integer        i5;
        always @* begin
            if (P != 0) begin
                sh0_v = sh0_y;
            end else begin
                sh0_v = {SH_W{1'b0}};
                for (i5 = 0; i5 < HW; i5 = i5 + 1)
                    if (w_y[B + i5])
                        sh0_v = i5[SH_W-1:0] + {{(SH_W-1){1'b0}}, 1'b1};
            end
            w2s = {w_y, 1'b0} >> sh0_v;
            t = w2s[B:0];
            ovf = &t;
            den_n = t[B:1] + {{(B-1){1'b0}}, t[0]};
            if (ovf) begin
                den_n = {B{1'b0}};
                den_n[B-1] = 1'b1;
            end
            sh = sh0_v + {{(SH_W-1){1'b0}}, ovf};
            h2 = {{W_W{1'b0}}, 1'b1} << sh;
            if (sh == {SH_W{1'b0}})
                h2 = {(W_W+1){1'b0}};
            wn_0 = {1'b0, w_y} + h_0y;
            wn_1 = {1'b0, w_y} + h_1y;
            wn_f = ovf ? wn_1 : wn_0;
        end

        reg [B-1:0]    s5_den_reg;
        reg [SH_W-1:0] s5_sh_reg;
        reg [W_W:0]    s5_wn_reg;   // w + 2 h(sh) (< 2^(W_W+1)); 0 iff w = 0

        always @(posedge clk) begin
            if (ce) begin
                s5_den_reg <= den_n;
                s5_sh_reg  <= sh;
                s5_wn_reg  <= FPGA_REGS ? wn_f : {1'b0, w_y} + h2;
            end
        end

        // FPGA_REGS: the stage-5 words a stage more, beside cmap_sat's 6a
        wire [B-1:0]        den_s;
        wire [SH_W-1:0]     sh_s;
        wire [W_W:0]        wn_s;
        delay_line #(.W(B + SH_W + W_W + 1), .N(P)) u_dly_n6 (.clk(clk), .rst(rst), .ce(ce),
            .d_in({s5_den_reg, s5_sh_reg, s5_wn_reg}), .d_out({den_s, sh_s, wn_s}));

        // ---- stage 6: num' = (D + w + 2 h(sh)) >> (sh + 1) (< 2^NQ_W), den' (w = 0:
        // clut[k] / 1), computed in the operand registers' clocked process (blocking
        // temporaries) only on a clock that brings a valid D; FPGA_REGS: on every enabled
        // clock in always @*, the sums registered (6c) in a delay line as before
        reg                 w_zero;
        reg  [D_W-1:0]      d_wn;   // w + 2 h(sh) zero-extended
        reg  [B-1:0]        den_x;
        /* verilator lint_off UNUSEDSIGNAL */  // FPGA_REGS: stage 6c forms num from the sums
        reg  [LANES*NQ_W-1:0] num_x;
        /* verilator lint_on UNUSEDSIGNAL */
        integer             c;
        // sum = D + w + 2 h(sh), one bit wider: with B = 1, 2 h(sh) reaches w (w = 2^sh),
        // and D + 2w of a whole 255-valued window is 2^D_W (the make-fit sweep found it); its
        // LSB is below the rounding; nsh = sum >> (sh + 1) < 2^NQ_W (num' < 256 den', or
        // 384 den' with SAT: docs/numerics.md), its high bits are zero
        /* verilator lint_off UNUSEDSIGNAL */
        reg  [D_W:0]        sum;
        reg  [D_W-1:0]      nsh;
        /* verilator lint_on UNUSEDSIGNAL */
        reg  [NQ_W-1:0]     pt;     // clut[k] zero-extended
        if (P == 0) begin : g_s6
            // stage 6 in the operand registers' clocked process, only with a valid D
            /* verilator lint_off BLKSEQ */
            always @(posedge clk) begin
                // the temporaries wholly assigned first, outside the if (C++ locals: the header)
                w_zero = 1'b0;
                d_wn   = {D_W{1'b0}};
                den_x  = {B{1'b0}};
                num_x  = {(LANES*NQ_W){1'b0}};
                sum    = {(D_W+1){1'b0}};
                nsh    = {D_W{1'b0}};
                pt     = {NQ_W{1'b0}};
                if (ce && in_valid) begin
                    w_zero = (wn_s == {(W_W+1){1'b0}});
                    d_wn[W_W:0] = wn_s;
                    den_x = den_s;   // 0 when w = 0
                    if (w_zero)
                        den_x[0] = 1'b1;
                    for (c = 0; c < LANES; c = c + 1) begin
                        sum = {1'b0, d_in[c*D_W +: D_W]} + {1'b0, d_wn};
                        nsh = sum[D_W:1] >> sh_s;
                        pt = {NQ_W{1'b0}};
                        pt[Q_W-1:0] = pt_in[Q_W*c +: Q_W];
                        num_x[c*NQ_W +: NQ_W] = w_zero ? pt : nsh[NQ_W-1:0];
                    end
                    s6_num_reg <= num_x;
                    s6_den_reg <= den_x;
                end
            end
            /* verilator lint_on BLKSEQ */
        end else begin : g_6c
            // FPGA_REGS: stage 6 on every enabled clock into 6c's registers (a delay line), then
            // the shift and the operand select (the adder and the shifter on two clocks), and
            // the operand registers
            // the sums (and the words stage 6c reads) of the four channels
            reg  [LANES*(D_W+1)-1:0] sum_all;
            reg  [LANES*NQ_W-1:0]    pt_all;
            always @* begin
                w_zero = (wn_s == {(W_W+1){1'b0}});
                d_wn = {D_W{1'b0}};
                d_wn[W_W:0] = wn_s;
                den_x = den_s;   // 0 when w = 0
                if (w_zero)
                    den_x[0] = 1'b1;
                for (c = 0; c < LANES; c = c + 1) begin
                    sum = {1'b0, d_in[c*D_W +: D_W]} + {1'b0, d_wn};
                    nsh = sum[D_W:1] >> sh_s;
                    pt = {NQ_W{1'b0}};
                    pt[Q_W-1:0] = pt_in[Q_W*c +: Q_W];
                    num_x[c*NQ_W +: NQ_W] = w_zero ? pt : nsh[NQ_W-1:0];
                    sum_all[c*(D_W+1) +: D_W+1] = sum;
                    pt_all[c*NQ_W +: NQ_W] = pt;
                end
            end
            wire [LANES*(D_W+1)-1:0] sum_c;
            wire [LANES*NQ_W-1:0]    pt_c;
            wire [SH_W-1:0]      sh_c;
            wire                 wz_c;
            wire [B-1:0]         den_c;
            delay_line #(.W(LANES*(D_W+1) + LANES*NQ_W + SH_W + 1 + B), .N(1)) u_dly_6c (.clk(clk), .rst(rst),
                .ce(ce), .d_in({sum_all, pt_all, sh_s, w_zero, den_x}), .d_out({sum_c, pt_c, sh_c, wz_c, den_c}));
            reg [LANES*NQ_W-1:0] num_c;
            /* verilator lint_off UNUSEDSIGNAL */
            reg [D_W-1:0]    nsh_c;
            /* verilator lint_on UNUSEDSIGNAL */
            integer          c6c;
            always @* begin
                for (c6c = 0; c6c < LANES; c6c = c6c + 1) begin
                    nsh_c = sum_c[c6c*(D_W+1) + 1 +: D_W] >> sh_c;
                    num_c[c6c*NQ_W +: NQ_W] = wz_c ? pt_c[c6c*NQ_W +: NQ_W] : nsh_c[NQ_W-1:0];
                end
            end
            always @(posedge clk) begin
                if (ce) begin
                    s6_num_reg <= num_c;
                    s6_den_reg <= den_c;
                end
            end
        end
        assign num = s6_num_reg;
        assign den = s6_den_reg;
    end
endgenerate

// the operands' valid (FPGA_REGS: after 6c)
wire div_valid;
delay_line #(.W(1), .N(1 + P), .CLEAR(1)) u_dly_dv (.clk(clk), .rst(rst), .ce(ce), .d_in(in_valid),
                                                   .d_out(div_valid));

// ---- stages 7..14: one quotient bit per stage; exact: divisor w itself; normalised: B-bit
// divisors, and for B <= 9 the quotient can reach 256 (up to 383), saturated to 255 (SAT)
box_divide #(
    .NUM_W(NUM_DW), .DEN_W(DEN_DW), .Q_W(Q_W), .LANES(LANES), .SAT(NORM ? SAT : 0)
) u_divide (
    .clk(clk), .rst(rst), .ce(ce), .in_valid(div_valid),
    .num_in(num), .den_in(den),
    .out_valid(out_valid), .q_out(q_out)
);

endmodule

`default_nettype wire
