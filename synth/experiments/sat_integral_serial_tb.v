// sat_integral_serial against rtl/sat_integral.v (PIPE = 0), compact's parameters: random
// vectors (the most negative k and the largest words included), each held for four clocks with
// ch = 0..3; each channel's p and e must equal sat_integral's. Prints "checked N of N errors E".
`timescale 1ns/1ps
`default_nettype none
module sat_integral_serial_tb;
localparam XF = 16, KW = 11, QW = 8, CS_W = 16, D_W = 33, TW = D_W - XF, N = 3000;
reg clk = 0, ce = 1, first = 0;
reg [1:0] ch = 0;
reg [31:0] c; reg [4*CS_W-1:0] before; reg [XF-1:0] fr; reg [KW-1:0] k; reg [4*QW-1:0] q;
wire [4*D_W-1:0] p4; wire [4*TW-1:0] e4; wire [D_W-1:0] p1; wire [TW-1:0] e1;
sat_integral #(.XF(XF), .KW(KW), .QW(QW), .CS_W(CS_W), .D_W(D_W), .PIPE(0)) u_ref (
    .clk(clk), .ce(ce), .c_in(c), .before_in(before), .first_in(first), .fr_in(fr), .k_in(k),
    .q_in(q), .p_out(p4), .e_out(e4));
sat_integral_serial #(.XF(XF), .KW(KW), .QW(QW), .CS_W(CS_W), .D_W(D_W)) u_dut (
    .clk(clk), .ce(ce), .ch_in(ch), .c_in(c), .before_in(before), .first_in(first), .fr_in(fr),
    .k_in(k), .q_in(q), .p_out(p1), .e_out(e1));
integer i, j, errors = 0, seed = 1;
task tick; begin #5 clk = 1; #5 clk = 0; end endtask
initial begin
    for (i = 0; i < N; i = i + 1) begin
        c = $random(seed); before = {$random(seed), $random(seed)}; fr = $random(seed);
        k = $random(seed); q = $random(seed); first = ($random(seed) & 7) == 0;
        if (i % 7 == 1) begin k = {1'b1, {(KW-1){1'b0}}}; fr = {XF{1'b1}}; c = ~0; before = ~0; q = ~0; end
        for (j = 0; j < 4; j = j + 1) begin
            ch = j; tick;
            if (p1 !== p4[j*D_W +: D_W] || e1 !== e4[j*TW +: TW]) begin
                errors = errors + 1;
                if (errors < 5) $display("vector %0d ch %0d: p %h / %h e %h / %h", i, j, p1, p4[j*D_W +: D_W], e1, e4[j*TW +: TW]);
            end
        end
    end
    $display("checked %0d of %0d errors %0d", N, N, errors);
    $finish;
end
endmodule
`default_nettype wire
