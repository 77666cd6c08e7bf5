// A hierarchical reference into a generate block declared further down: Icarus and Verilator resolve
// it, Yosys reads it as a new, undriven wire (its warning "is implicitly declared"), which synth/synth.py
// makes an error (READ_ERRORS). stop 52's sum_tree had one.
`default_nettype none
module forward_ref (
    input  wire clk,
    input  wire d,
    output wire q
);
generate
    if (1) begin : g_use
        wire v = g_def.r;
    end
    if (1) begin : g_def
        reg r;
        always @(posedge clk) r <= d;
    end
endgenerate
assign q = g_use.v;
endmodule
`default_nettype wire
