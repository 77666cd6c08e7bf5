// sample_average: the pixel's colour as the average of its SAMPLES sub-pixel samples' colours.
//
// Takes the colours of consecutive samples (sample_expand's order: a pixel's SAMPLES samples one
// after the other, no other pixel between them) and, with the pixel's last one, outputs
//   rgba = floor((sum_k rgba_k + SAMPLES / 2) / SAMPLES)      per channel (rounded half up)
// with the last sample's tlast (model/hw/golden.py sample_average is the twin).
// Formats: rgba_k and rgba RGBA8 (R at [7:0], A at [31:24]); the sums u{8 + log2 SAMPLES}.
// Latency: 1 enabled clock from a pixel's last sample to its colour (out_valid for one enabled
// clock a pixel: the pipeline's last register stage, in texture_pipeline's clock-enable domain:
// ce = 0 holds every register). Throughput: a pixel per SAMPLES input samples.
// Reset: synchronous, active high: no partial sum, out_valid low, the output registers 0.

`default_nettype none

module sample_average #(
    parameter SAMPLES = 4    // [samples] sub-pixel samples a pixel: 2 or 4
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        ce,
    input  wire        in_valid,
    input  wire [31:0] in_rgba,
    input  wire        in_last,
    output reg         out_valid,
    output reg  [31:0] out_rgba,
    output reg         out_last
);

localparam L2  = (SAMPLES > 2) ? 2 : 1;   // log2 SAMPLES
localparam K_W = L2;                       // the sample index
localparam A_W = 8 + L2;                   // a channel's sum

generate
    if (SAMPLES != 2 && SAMPLES != 4) begin : g_bad_params
        initial begin
            $display("sample_average: SAMPLES = %0d must be 2 or 4", SAMPLES);
            $finish;
        end
    end
endgenerate

reg  [K_W-1:0]   idx_reg;
reg  [4*A_W-1:0] acc_reg;       // channel ch's sum of the pixel's samples so far at [ch*A_W +: A_W]
localparam [K_W-1:0] K_LAST = {K_W{1'b1}};     // SAMPLES - 1 (SAMPLES a power of two)
localparam [A_W-1:0] HALF   = 1 << (L2 - 1);   // SAMPLES / 2: rounding half up
wire             last = (idx_reg == K_LAST);

wire [4*A_W-1:0] acc_next;      // with this sample
wire [31:0]      avg;
genvar ch;
generate
    for (ch = 0; ch < 4; ch = ch + 1) begin : g_ch
        wire [A_W-1:0] prev = (idx_reg == {K_W{1'b0}}) ? {A_W{1'b0}} : acc_reg[ch*A_W +: A_W];
        wire [A_W-1:0] sum  = prev + {{L2{1'b0}}, in_rgba[8*ch +: 8]};
        /* verilator lint_off UNUSEDSIGNAL */  // the low L2 bits: the fraction the division drops
        wire [A_W-1:0] rnd  = sum + HALF;   // <= 255 SAMPLES + SAMPLES / 2 < 2^A_W
        /* verilator lint_on UNUSEDSIGNAL */
        assign acc_next[ch*A_W +: A_W] = sum;
        assign avg[8*ch +: 8] = rnd[L2 +: 8];
    end
endgenerate

always @(posedge clk) begin
    if (rst) begin
        idx_reg   <= {K_W{1'b0}};
        acc_reg   <= {4*A_W{1'b0}};
        out_valid <= 1'b0;
        out_rgba  <= 32'd0;
        out_last  <= 1'b0;
    end else if (ce) begin
        out_valid <= in_valid && last;
        if (in_valid) begin
            acc_reg <= acc_next;
            idx_reg <= last ? {K_W{1'b0}} : idx_reg + 1'b1;
            if (last) begin
                out_rgba <= avg;
                out_last <= in_last;
            end
        end
    end
end

endmodule

`default_nettype wire
