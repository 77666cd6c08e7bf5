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
`ifdef FORMAL
        // Formal (make formal): the line against a plain shift register f_stage (stage i
        // the word that went in i + 1 enabled clocks ago); f_fill counts the enabled clocks
        // since the start (or CLEAR's reset, which empties both), as far as N. Proved: every
        // stage that holds a word that went in equals it, and d_out is the word of N enabled
        // clocks ago once N went in (CLEAR's reset: all zero).
        reg [N*W-1:0] f_stage;  // stage i at [i*W +: W]
        reg [31:0]  f_fill = 32'd0;
        integer     fi;
        always @(posedge clk) begin
            if (CLEAR != 0 && rst) begin
                f_stage <= {N*W{1'b0}};
                f_fill <= N;
            end else if (ce) begin
                f_stage[0 +: W] <= d_in;
                for (fi = 1; fi < N; fi = fi + 1) f_stage[fi*W +: W] <= f_stage[(fi-1)*W +: W];
                if (f_fill < N) f_fill <= f_fill + 1;
            end
        end
        always @* begin
            assert(f_fill <= N);
            for (fi = 0; fi < N; fi = fi + 1)
                if (fi < f_fill) assert(d_reg[fi*W +: W] == f_stage[fi*W +: W]);
            if (f_fill == N) assert(d_out == f_stage[(N-1)*W +: W]);
        end
`endif
    end
endgenerate

endmodule

`default_nettype wire
