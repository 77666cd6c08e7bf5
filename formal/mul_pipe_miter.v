// mul_pipe_miter: mul_pipe (partial products, registered, summed) against the plain product
// a * b registered the same way (one enabled clock), for every a, b and ce pattern (make formal;
// formal/run.py gives A_W and B_W).

`default_nettype none

module mul_pipe_miter #(
    parameter A_W = 18,  // mul_pipe's operand widths
    parameter B_W = 18
) (
    input wire           clk,
    input wire           ce,
    input wire [A_W-1:0] a,
    input wire [B_W-1:0] b
);

wire [A_W+B_W-1:0] p;
mul_pipe #(.A_W(A_W), .B_W(B_W)) u_dut (.clk(clk), .ce(ce), .a(a), .b(b), .p(p));

reg signed [A_W+B_W-1:0] p_ref;
reg                      loaded = 1'b0;  // an enabled clock has passed (no reset: data only)
always @(posedge clk) begin
    if (ce) begin
        p_ref  <= $signed(a) * $signed(b);
        loaded <= 1'b1;
    end
end

always @* begin
    if (loaded) assert(p == p_ref);
end

endmodule

`default_nettype wire
