// lerp: linear interpolation y = a + floor((b - a) * t / 2^P_FRAC), combinational, or
// pipelined (noise_term's FPGA_REGS): PIPE = 1 a register between the multiplier and the
// adder, PIPE = 2 also one between the subtraction and the multiplier.
//
// The twin of model/hw/golden.py lerp(pf, a, b, t) = a + (((b - a) * t) >> pf).
// Formats: a, b, y sW.F (any F, the same for all three); t sTW.P_FRAC, a blend
// weight in [0, 1] (0 <= t <= 2^P_FRAC), so y lies between a and b and fits W bits
// (the top bits of the scaled step are redundant sign bits and are dropped).
// Rounding: floor (arithmetic shift right) of the scaled step.
// Latency: PIPE = 0: 0 (combinational; the instantiating pipeline registers around it);
// PIPE = 1, 2: PIPE (b - a, t and a registered; the scaled step and a registered; advancing
// with ce; y combinational after the last).
// Cost: one (W+1) x TW signed multiplier, two W-bit adders.
// Written for event-driven simulation speed: the whole body is one always @* with
// blocking assigns (one evaluation per input change, no net-level arithmetic).

`default_nettype none

module lerp #(
    parameter W      = 16,  // width of a, b and y (signed)
    parameter TW     = 10,  // width of t (signed word, value in [0, 2^P_FRAC])
    parameter P_FRAC = 8,   // fraction bits of t
    parameter PIPE   = 0    // 0..2: register stages (above)
) (
    /* verilator lint_off UNUSEDSIGNAL */  // PIPE = 0: no clock
    input  wire                 clk,
    input  wire                 ce,
    /* verilator lint_on UNUSEDSIGNAL */
    input  wire signed [W-1:0]  a,
    input  wire signed [W-1:0]  b,
    input  wire signed [TW-1:0] t,
    output reg  signed [W-1:0]  y
);

reg signed [W:0]    diff;   // b - a needs W+1 bits
// the dropped bits: step[W+TW:W] are sign copies (|step| <= |b - a|)
/* verilator lint_off UNUSEDSIGNAL */
reg signed [W+TW:0] step;
/* verilator lint_on UNUSEDSIGNAL */

generate
    if (PIPE == 0) begin : g_comb
        // one always @* (event-driven simulation: it runs once per input change)
        always @* begin
            diff = b - a;                       // operands sign-extended to W+1 bits: exact
            step = (diff * t) >>> P_FRAC;       // exact product: |diff * t| < 2^(W+TW)
            // a + step lies between a and b, so the W-bit (mod 2^W) sum is exact
            y    = a + step[W-1:0];
        end
    end else begin : g_pipe
        always @* diff = b - a;
        // PIPE = 2: b - a, t and a registered before the multiplier
        localparam P1 = (PIPE > 1) ? 1 : 0;
        wire signed [W:0]    diff_p;
        wire signed [TW-1:0] t_p;
        wire signed [W-1:0]  a_1;
        delay_line #(.W(2*W + 1 + TW), .N(P1)) u_dly1 (.clk(clk), .rst(1'b0), .ce(ce), .d_in({a, diff, t}),
                                                      .d_out({a_1, diff_p, t_p}));
        always @* step = (diff_p * t_p) >>> P_FRAC;
        // the step's W bits and a registered after the multiplier
        wire signed [W-1:0] a_p, step_p;
        delay_line #(.W(2*W), .N(1)) u_dly2 (.clk(clk), .rst(1'b0), .ce(ce), .d_in({a_1, step[W-1:0]}),
                                            .d_out({a_p, step_p}));
        always @* y = a_p + step_p;
    end
endgenerate

endmodule

`default_nettype wire
