`timescale 1ns/1ps
module tb;
localparam S_W=21, S_FRAC=13, Q_W=24;
`include "tex_widths.vh"
localparam V_W = tw_v_w(1, S_W, S_FRAC, Q_W);
localparam P2_W = S_W + V_W;
reg clk=0, rst=1, ce=1, in_valid=0;
reg [3*S_W-1:0] s_in; reg [10*Q_W-1:0] q;
wire ov_f, ov_s; wire [3*P2_W-1:0] r_f, r_s; wire [4*V_W-1:0] v_f, v_s;
qmac_diag_fold   #(.S_W(S_W),.S_FRAC(S_FRAC),.Q_W(Q_W)) uf(clk,rst,ce,in_valid,s_in,q,ov_f,r_f,v_f);
qmac_diag_serial #(.S_W(S_W),.S_FRAC(S_FRAC),.Q_W(Q_W)) us(clk,rst,ce,in_valid,s_in,q,ov_s,r_s,v_s);
always #5 clk = ~clk;
reg [3*P2_W-1:0] rf_q [0:4095]; reg [4*V_W-1:0] vf_q [0:4095]; integer wi=0, ri=0;
integer i, k, errors=0, checked=0;
always @(posedge clk) begin
  if (ov_f) begin rf_q[wi] = r_f; vf_q[wi] = v_f; wi = wi + 1; end
  if (ov_s) begin
    checked = checked + 1;
    if (r_s !== rf_q[ri] || v_s !== vf_q[ri]) begin errors = errors + 1;
      if (errors < 5) $display("MISMATCH %0d", ri); end
    ri = ri + 1;
  end
end
initial begin
  q = {$random,$random,$random,$random,$random,$random,$random,$random};
  q[1*Q_W +: Q_W] = 0; q[2*Q_W +: Q_W] = 0; q[5*Q_W +: Q_W] = 0;
  repeat (3) @(posedge clk); rst <= 0;
  for (i = 0; i < 3000; i = i + 1) begin
    @(posedge clk); s_in <= {$random,$random,$random}; in_valid <= 1;
    if (i % 7 == 3) s_in <= {3{ {1'b1, {(S_W-1){1'b0}}} }};
    @(posedge clk); in_valid <= 0;
    repeat (4) @(posedge clk);
  end
  repeat (20) @(posedge clk);
  $display("checked %0d of %0d errors %0d", checked, wi, errors);
  $finish;
end
endmodule
