// Self-test design for synth/synth.py: a 16 x 8 RAM (one write port, one
// asynchronous read port), to check the storage accounting.
`default_nettype none

module ram16 (
    input  wire       clk,
    input  wire       we,
    input  wire [3:0] wa,
    input  wire [3:0] ra,
    input  wire [7:0] wd,
    output wire [7:0] rd
);
    reg [7:0] mem [0:15];

    always @(posedge clk)
        if (we)
            mem[wa] <= wd;

    assign rd = mem[ra];
endmodule

`default_nettype wire
