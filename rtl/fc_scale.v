// fc_scale: one noise term faded by its frequency-clamping weight (filter "sat_fc").
//
// The bit-exact twin of model/hw/golden.py fc_scale(cfg, alpha, an, ag):
//   an_out   = (an_in alpha) >> AF,   ag_out_k = (ag_in_k alpha) >> AF   (floor; k = 0..2)
// alpha = 2^AF leaves both exact; x alpha / 2^AF lies in [-|x|, |x|] and so does its floor
// (-|x| is an integer), so the outputs fit the input words.
//
// Formats: alpha u{AF+1}.{AF} in [0, 2^AF]; an_in/an_out s{AN_W}.{F_FRAC};
//   ag_in/ag_out 3 x s{AG_W}.{C_FRAC} (element k at [k*AG_W +: AG_W]; 0 and not multiplied
//   when NOISE_GRADIENT = 0).
// Latency: `LAT_FC_SCALE = 1 (registered outputs); throughput one term per enabled clock.
// Cost: an AN_W x (AF+2) signed multiplier (and three AG_W x (AF+2) with the noise gradient).
// Reset: synchronous, active high: clears out_valid.
`default_nettype none
module fc_scale #(
    parameter AN_W           = 20,  // a_i n_i word
    parameter AG_W           = 20,  // a_i grad n_i component word
    parameter AF             = 7,   // alpha fraction bits (fc_log_frac + fc_fade_log2)
    parameter NOISE_GRADIENT = 1    // 1: the gradient is faded too; 0: ag is 0 (passed as 0)
) (
    input  wire                   clk,
    input  wire                   rst,
    input  wire                   ce,
    input  wire                   in_valid,
    input  wire [AF:0]            alpha,
    input  wire [AN_W-1:0]        an_in,
    input  wire [3*AG_W-1:0]      ag_in,
    output reg                    out_valid,
    output reg  [AN_W-1:0]        an_out,
    output reg  [3*AG_W-1:0]      ag_out
);
wire signed [AF+1:0] al = {1'b0, alpha};  // alpha as a non-negative signed word
// products: |x alpha| <= 2^(W-1) 2^AF; the top bits after >> AF are sign copies (dropped)
/* verilator lint_off UNUSEDSIGNAL */
reg signed [AN_W+AF+1:0] pn;
reg signed [AG_W+AF+1:0] pg [0:2];
/* verilator lint_on UNUSEDSIGNAL */
integer k;
always @* begin
    pn = ($signed(an_in) * al) >>> AF;
    for (k = 0; k < 3; k = k + 1) begin
        if (NOISE_GRADIENT != 0)
            pg[k] = ($signed(ag_in[k*AG_W +: AG_W]) * al) >>> AF;
        else
            pg[k] = {(AG_W+AF+2){1'b0}};
    end
end
integer r;
always @(posedge clk) begin
    if (rst) begin
        out_valid <= 1'b0;
    end else if (ce) begin
        out_valid <= in_valid;
        an_out    <= pn[AN_W-1:0];
        for (r = 0; r < 3; r = r + 1)
            ag_out[r*AG_W +: AG_W] <= pg[r][AG_W-1:0];
    end
end
endmodule
`default_nettype wire
