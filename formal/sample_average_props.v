// sample_average_props: sample_average (rtl/sample_average.v) against a reference of its header's
// rule kept here, for every pattern of rst, ce and in_valid and any colours (make formal;
// formal/run.py gives SAMPLES). Assumed: a reset at the first clock. The reference counts the
// samples of the pixel under way and sums their channels; on an enabled clock whose sample is the
// SAMPLES-th, the next clock must give out_valid with floor((sum + SAMPLES/2) / SAMPLES) in each
// channel and that sample's in_last, and on every other enabled clock out_valid low; ce = 0 holds
// every output. Asserted on every clock after the reset. The reference is the wrapper's own, so the
// check is bounded (bmc: the module's index and sums are not visible here to close an induction).

`default_nettype none

module sample_average_props #(
    parameter SAMPLES = 4  // sample_average's
) (
    input wire        clk,
    input wire        rst,
    input wire        ce,
    input wire        in_valid,
    input wire [31:0] in_rgba,
    input wire        in_last
);

wire        out_valid, out_last;
wire [31:0] out_rgba;
sample_average #(.SAMPLES(SAMPLES)) u_dut (
    .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .in_rgba(in_rgba), .in_last(in_last),
    .out_valid(out_valid), .out_rgba(out_rgba), .out_last(out_last));

localparam L2 = (SAMPLES > 2) ? 2 : 1;
reg        init = 1'b1;
reg [2:0]  m = 3'd0;            // samples of the pixel under way taken
reg [10:0] acc [0:3];           // their channels' sums
reg        ref_valid = 1'b0, ref_last = 1'b0;
reg [31:0] ref_rgba = 32'd0;
reg [10:0] s [0:3];             // with this clock's sample
integer    ch;

always @* begin
    for (ch = 0; ch < 4; ch = ch + 1)
        s[ch] = (m == 3'd0 ? 11'd0 : acc[ch]) + {3'd0, in_rgba[8*ch +: 8]};
end

always @(posedge clk) begin
    init <= 1'b0;
    if (rst) begin
        m         <= 3'd0;
        ref_valid <= 1'b0;
        ref_rgba  <= 32'd0;
        ref_last  <= 1'b0;
    end else if (ce) begin
        ref_valid <= in_valid && m == SAMPLES - 1;
        if (in_valid) begin
            for (ch = 0; ch < 4; ch = ch + 1)
                acc[ch] <= s[ch];
            m <= (m == SAMPLES - 1) ? 3'd0 : m + 3'd1;
            if (m == SAMPLES - 1) begin
                for (ch = 0; ch < 4; ch = ch + 1)
                    ref_rgba[8*ch +: 8] <= (s[ch] + SAMPLES / 2) >> L2;
                ref_last <= in_last;
            end
        end
    end
end

always @* begin
    if (init) assume(rst);
    if (!init) begin
        assert(out_valid == ref_valid);
        assert(out_rgba == ref_rgba && out_last == ref_last);
    end
end

endmodule

`default_nettype wire
