// lerp: linear interpolation y = a + floor((b - a) * t / 2^P_FRAC), combinational.
//
// The twin of model/golden.py _lerp(pf, a, b, t) = a + (((b - a) * t) >> pf).
// Formats: a, b, y sW.F (any F, the same for all three); t sTW.P_FRAC, a blend
// weight in [0, 1] (0 <= t <= 2^P_FRAC), so y lies between a and b and fits W bits
// (the top bits of the scaled step are redundant sign bits and are dropped).
// Rounding: floor (arithmetic shift right) of the scaled step.
// Latency: 0 (combinational; the instantiating pipeline registers around it).
// Cost: one (W+1) x TW signed multiplier, two W-bit adders.

`default_nettype none

module lerp #(
    parameter W      = 16,  // width of a, b and y (signed)
    parameter TW     = 10,  // width of t (signed word, value in [0, 2^P_FRAC])
    parameter P_FRAC = 8    // fraction bits of t
) (
    input  wire signed [W-1:0]  a,
    input  wire signed [W-1:0]  b,
    input  wire signed [TW-1:0] t,
    output wire signed [W-1:0]  y
);

wire signed [W:0]    a_ext = {a[W-1], a};  // sign-extended: b - a needs W+1 bits
wire signed [W:0]    b_ext = {b[W-1], b};
wire signed [W:0]    diff  = b_ext - a_ext;
wire signed [W+TW:0] prod  = diff * t;   // exact: |diff * t| < 2^(W+TW)
wire signed [W+TW:0] step  = prod >>> P_FRAC;

// a + step lies between a and b, so the W-bit (mod 2^W) sum is exact
assign y = a + step[W-1:0];

// the dropped bits: step[W+TW:W] are sign copies (|step| <= |b - a|)
wire unused_step = &{1'b0, step[W+TW:W]};

endmodule

`default_nettype wire
