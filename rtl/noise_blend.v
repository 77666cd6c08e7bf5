// noise_blend: the blend weight and its slope for a cell fraction, combinational.
//
// The twin of model/hw/golden.py noise_blend(cfg, fp):
//   linear (BLEND = 0): w = fp,                 dw = 1
//   cubic  (BLEND = 1): w = 3 f2 - 2 f3,        dw = 6 (fp - f2),
//                       f2 = floor(fp^2 / 2^P_FRAC), f3 = floor(f2 fp / 2^P_FRAC)
// Formats: fp u{P_FRAC}.{P_FRAC} in [0, 1); w and dw s{BW}.{P_FRAC}, never negative:
// w in [0, 1] (3 f2 - 2 f3 reaches exactly 1.0 near fp = 1), dw in [0, 1.5].
// All sums are taken mod 2^BW, exact because the results fit (BW >= P_FRAC + 2, and
// P_FRAC >= 2: at P_FRAC = 1 the floored f2 lets the cubic dw reach 3.0).
// Latency: PIPE register stages (advancing with ce). PIPE = 0: combinational (noise_term
// registers around it); PIPE = 1: fp and f2 registered between the two multipliers;
// PIPE = 2 (noise_term's FPGA_REGS): also fp, f2 and f3 after the second multiplier
// (each multiplier alone in its clock). Linear: fp delayed by PIPE stages.
// Cost: cubic two P_FRAC x P_FRAC unsigned multipliers in series; linear none.
// Written for event-driven simulation speed: the body is one always @* with blocking
// assigns (one evaluation per input change, no net-level arithmetic).

`default_nettype none

module noise_blend #(
    parameter BLEND  = 1,   // 0: linear, 1: cubic (blend)
    parameter P_FRAC = 12,  // fraction bits of fp, w and dw (p_frac)
    parameter BW     = 14,  // width of w and dw (blend_w, >= P_FRAC + 2)
    parameter PIPE   = 0    // register stages: 0, 1 (between fp^2 and f2 fp) or 2 (and after f2 fp)
) (
    /* verilator lint_off UNUSEDSIGNAL */  // PIPE = 0: no clock
    input  wire                     clk,
    input  wire                     ce,
    /* verilator lint_on UNUSEDSIGNAL */
    input  wire        [P_FRAC-1:0] fp,
    output reg  signed [BW-1:0]     w,
    output reg  signed [BW-1:0]     dw
);

localparam [BW-1:0] ONE = {{(BW-P_FRAC-1){1'b0}}, 1'b1, {P_FRAC{1'b0}}};  // 1.0

generate
    if (BLEND == 0) begin : g_linear
        wire [P_FRAC-1:0] fp_p;  // fp after PIPE stages
        delay_line #(.W(P_FRAC), .N(PIPE)) u_dly (.clk(clk), .rst(1'b0), .ce(ce), .d_in(fp), .d_out(fp_p));
        always @* begin
            w  = {{(BW-P_FRAC){1'b0}}, fp_p};
            dw = ONE;
        end
    end else begin : g_cubic
        // the fraction bits dropped by the floor shifts: sq, cube [P_FRAC-1:0]
        /* verilator lint_off UNUSEDSIGNAL */
        reg [2*P_FRAC-1:0] sq, cube;
        /* verilator lint_on UNUSEDSIGNAL */
        reg [BW-1:0]       f2_ext, f3_ext, slope;
        if (PIPE == 0) begin : g_comb
            // one always @* (event-driven simulation: it runs once per input change)
            always @* begin
                sq     = fp * fp;
                f2_ext = {{(BW-P_FRAC){1'b0}}, sq[2*P_FRAC-1:P_FRAC]};
                cube   = f2_ext[P_FRAC-1:0] * fp;
                f3_ext = {{(BW-P_FRAC){1'b0}}, cube[2*P_FRAC-1:P_FRAC]};
                slope  = {{(BW-P_FRAC){1'b0}}, fp} - f2_ext;      // fp >= f2
                w      = (f2_ext << 1) + f2_ext - (f3_ext << 1);
                dw     = (slope << 2) + (slope << 1);
            end
        end else begin : g_pipe
            always @* sq = fp * fp;
            // fp and f2 registered between the two multipliers
            wire [P_FRAC-1:0] fp_p, f2_p;
            delay_line #(.W(2*P_FRAC), .N(1)) u_dly (.clk(clk), .rst(1'b0), .ce(ce),
                                                     .d_in({fp, sq[2*P_FRAC-1:P_FRAC]}), .d_out({fp_p, f2_p}));
            always @* cube = f2_p * fp_p;
            // PIPE = 2: fp, f2 and f3 registered after the second multiplier
            wire [P_FRAC-1:0] fp_q, f2_q, f3_q;
            delay_line #(.W(3*P_FRAC), .N(PIPE - 1)) u_dly_3 (.clk(clk), .rst(1'b0), .ce(ce),
                                                              .d_in({fp_p, f2_p, cube[2*P_FRAC-1:P_FRAC]}),
                                                              .d_out({fp_q, f2_q, f3_q}));
            always @* begin
                f2_ext = {{(BW-P_FRAC){1'b0}}, f2_q};
                f3_ext = {{(BW-P_FRAC){1'b0}}, f3_q};
                slope  = {{(BW-P_FRAC){1'b0}}, fp_q} - f2_ext;    // fp >= f2
                w      = (f2_ext << 1) + f2_ext - (f3_ext << 1);
                dw     = (slope << 2) + (slope << 1);
            end
        end
    end
endgenerate

endmodule

`default_nettype wire
