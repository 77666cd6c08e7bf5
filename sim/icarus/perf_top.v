// perf_top: stand-alone top for timing frame_tb under Icarus without cocotb (sim/icarus_perf.py).
// Simulation only. Drives the clock and reset in Verilog and finishes when the harness is done.
`timescale 1ns/1ps
`default_nettype none
module perf_top;
reg  clk = 1'b0;
reg  rst = 1'b1;
wire done;
frame_tb #(.MAX_PIX(`PERF_MAX_PIX), .MAX_WR(16384), .DRAIN(256), .PIX_W(`PERF_PIX_W)) u_tb (.clk(clk), .rst(rst), .done(done));
always #5 clk = ~clk;
initial begin
    repeat (4) @(posedge clk);
    @(negedge clk) rst = 1'b0;
end
always @(posedge done) begin
    #20 $finish;
end
endmodule
`default_nettype wire
