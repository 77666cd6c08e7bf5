// delay_line: d_out = d_in delayed by N enabled clocks (a shift register of N W-bit stages).
//
// Formats: any W-bit word, passed through unchanged.
// Latency N register stages (N = 0: a wire); throughput one word per enabled clock
// (ce = 0 holds every stage). CLEAR = 1: the synchronous reset rst clears every stage
// (for valid bits: no spurious word after reset); CLEAR = 0: rst is not used (data).
// One process per line: event-driven simulators wake once per clock, not once per stage (and
// no lint-only reduction logic, which such simulators would evaluate on every change).

`default_nettype none

module delay_line #(
    parameter W     = 1,  // word width
    parameter N     = 1,  // stages (>= 0)
    parameter CLEAR = 0   // 1: rst clears the line
) (
    /* verilator lint_off UNUSEDSIGNAL */  // N = 0: a wire; CLEAR = 0: rst not used
    input  wire         clk,
    input  wire         rst,
    input  wire         ce,
    /* verilator lint_on UNUSEDSIGNAL */
    input  wire [W-1:0] d_in,
    output wire [W-1:0] d_out
);

generate
    if (N == 0) begin : g_wire
        assign d_out = d_in;
    end else begin : g_line
        // one spare stage: N = 1 still has a legal shift expression (never read)
        /* verilator lint_off UNUSEDSIGNAL */
        reg [(N+1)*W-1:0] d_reg;
        /* verilator lint_on UNUSEDSIGNAL */
        always @(posedge clk) begin
            if (CLEAR != 0 && rst)
                d_reg <= {((N+1)*W){1'b0}};
            else if (ce)
                d_reg <= {d_reg[N*W-1:0], d_in};
        end
        assign d_out = d_reg[(N-1)*W +: W];
    end
endgenerate

endmodule

`default_nettype wire
