// sample_expand_props: sample_expand's handshake (rtl/sample_expand.v's header) checked against a
// count of its own, for every pattern of rst, ce, in_valid and out_ready and any data (make formal;
// formal/run.py gives the parameters). Assumed: a reset at the first clock, and the input's
// AXI4-Stream rule (a pixel offered and not taken stays, its data unchanged, until taken or reset).
// Asserted, on every clock after the reset:
//   - out_valid = in_valid;
//   - in_ready only with out_ready;
//   - n, the samples taken since the last pixel was taken (a sample: an enabled clock with
//     out_valid and out_ready), is below SAMPLES, and in_ready = out_ready && n = SAMPLES - 1: each
//     pixel is taken with its SAMPLES-th sample, never sooner or later, and ce = 0 takes nothing;
//   - while one pixel is held, its samples' footprint (jm_out, je_out) is the same for each sample.
// The offsets' arithmetic is the simulations' (tb/sample_expand, tb/frame, bit-exact against the
// golden model). The count is the wrapper's own, so the check is bounded (bmc: the module's sample
// index is not visible here to close an induction).

`default_nettype none

module sample_expand_props #(
    parameter SAMPLES = 4,  // sample_expand's parameters
    parameter S_W     = 8,
    parameter S_FRAC  = 4,
    parameter J_W     = 4,
    parameter JE_W    = 3
) (
    input wire               clk,
    input wire               rst,
    input wire               ce,
    input wire               in_valid,
    input wire [3*S_W-1:0]   s_in,
    input wire [6*J_W-1:0]   jm_in,
    input wire [JE_W-1:0]    je_in,
    input wire               out_ready
);

wire               in_ready, out_valid;
wire [3*S_W-1:0]   s_out;
wire [6*J_W-1:0]   jm_out;
wire [JE_W-1:0]    je_out;
sample_expand #(.SAMPLES(SAMPLES), .S_W(S_W), .S_FRAC(S_FRAC), .J_W(J_W), .JE_W(JE_W)) u_dut (
    .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .in_ready(in_ready), .s_in(s_in), .jm_in(jm_in),
    .je_in(je_in), .out_valid(out_valid), .out_ready(out_ready), .s_out(s_out), .jm_out(jm_out), .je_out(je_out));

localparam D_W = 3*S_W + 6*J_W + JE_W;
reg           init = 1'b1;     // the first clock
reg           held = 1'b0;     // the last clock offered a pixel it did not take (and no reset)
reg [D_W-1:0] data_p;
reg [2:0]     n = 3'd0;        // samples taken since the last pixel taken
reg           fp_ok = 1'b0;    // a sample of the held pixel was taken: its footprint is in fp
reg [6*J_W+JE_W-1:0] fp;

always @(posedge clk) begin
    init   <= 1'b0;
    held   <= !rst && in_valid && !(ce && in_ready);
    data_p <= {s_in, jm_in, je_in};
    if (rst) begin
        n     <= 3'd0;
        fp_ok <= 1'b0;
    end else if (ce && out_valid && out_ready) begin
        n     <= in_ready ? 3'd0 : n + 3'd1;
        fp_ok <= !in_ready;
        fp    <= {jm_out, je_out};
    end else if (!in_valid) begin
        fp_ok <= 1'b0;
    end
end

always @* begin
    if (init) assume(rst);
    if (held && !rst) assume(in_valid && {s_in, jm_in, je_in} == data_p);
    if (!init) begin
        assert(out_valid == in_valid);
        assert(!in_ready || out_ready);
        assert(n < SAMPLES);
        assert(in_ready == (out_ready && n == SAMPLES - 1));
        if (fp_ok && in_valid && !rst) assert({jm_out, je_out} == fp);
    end
end

endmodule

`default_nettype wire
