// Self-test design for synth/synth.py: a registered adder of four W-bit
// inputs, two of the additions in a sub-module instance each.
`default_nettype none

module add2 #(
    parameter W = 8
) (
    input  wire [W-1:0] a,
    input  wire [W-1:0] b,
    output wire [W:0]   y
);
    assign y = {1'b0, a} + {1'b0, b};
endmodule

module adder_tree #(
    parameter W = 8
) (
    input  wire           clk,
    input  wire           rst,
    input  wire [W-1:0]   a,
    input  wire [W-1:0]   b,
    input  wire [W-1:0]   c,
    input  wire [W-1:0]   d,
    output reg  [W+1:0]   sum
);
    wire [W:0] ab;
    wire [W:0] cd;

    add2 #(.W(W)) u_ab (.a(a), .b(b), .y(ab));
    add2 #(.W(W)) u_cd (.a(c), .b(d), .y(cd));

    always @(posedge clk) begin
        if (rst)
            sum <= {(W+2){1'b0}};
        else
            sum <= {1'b0, ab} + {1'b0, cd};
    end
endmodule

`default_nettype wire
