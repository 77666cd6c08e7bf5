// lerp: linear interpolation y = a + floor((b - a) * t / 2^P_FRAC), combinational.
//
// The twin of model/hw/golden.py lerp(pf, a, b, t) = a + (((b - a) * t) >> pf).
// Formats: a, b, y sW.F (any F, the same for all three); t sTW.P_FRAC, a blend
// weight in [0, 1] (0 <= t <= 2^P_FRAC), so y lies between a and b and fits W bits
// (the top bits of the scaled step are redundant sign bits and are dropped).
// Rounding: floor (arithmetic shift right) of the scaled step.
// Latency: 0 (combinational; the instantiating pipeline registers around it).
// Cost: one (W+1) x TW signed multiplier, two W-bit adders.
// Written for event-driven simulation speed: the whole body is one always @* with
// blocking assigns (one evaluation per input change, no net-level arithmetic).

`default_nettype none

module lerp #(
    parameter W      = 16,  // width of a, b and y (signed)
    parameter TW     = 10,  // width of t (signed word, value in [0, 2^P_FRAC])
    parameter P_FRAC = 8    // fraction bits of t
) (
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

always @* begin
    diff = b - a;                       // operands sign-extended to W+1 bits: exact
    step = (diff * t) >>> P_FRAC;       // exact product: |diff * t| < 2^(W+TW)
    // a + step lies between a and b, so the W-bit (mod 2^W) sum is exact
    y    = a + step[W-1:0];
end

endmodule

`default_nettype wire
