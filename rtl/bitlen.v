// bitlen: bl = bitlen(x) = the number of bits up to and including the top one of x
// (0 for x = 0), and nz = (x != 0). Combinational. Twin of model/hw/golden.py bitlen().
//
// PAR = 0, binary search: level b (from BW-1 down to 0) tests whether the value has a one at
// or above bit 2^b and if so shifts it down by 2^b and sets bit b of the top-one position;
// the remaining value is 1 (x != 0) or 0, added as the final +1.
// PAR = 1, in parallel (fewer logic levels, for an FPGA clock: filter_width with FPGA_REGS):
// above[i] = |x[W-1:i]; the top one is the i with x[i] and !above[i+1], and bl is the OR of
// the constants i + 1 it selects; nz = above[0]. The same bl and nz.
//
// Formats: x u{W}.0; bl u{BW}.0, BW >= clog2(W + 1) bits (the caller sizes it); nz 1 bit.
// Latency 0 (combinational); throughput one word per clock.
// Written for event-driven simulation speed: all levels in one always @* with blocking
// assigns (straight-line code), no bus driven piecewise.

`default_nettype none

module bitlen #(
    parameter W  = 8,  // input width
    parameter BW = 4,  // output width: holds W
    parameter PAR = 0  // 0: binary search; 1: in parallel (above)
) (
    input  wire [W-1:0]  x,
    output reg  [BW-1:0] bl,
    output reg           nz
);

localparam NL = $clog2(W);  // levels b with 2^b < W (the others cannot see a one that high)

generate
    if (PAR != 0) begin : g_par
        reg [W:0] above;  // above[i]: a one at or above bit i (above[W] = 0)
        integer   i;
        always @* begin
            above[W] = 1'b0;
            for (i = W - 1; i >= 0; i = i - 1)
                above[i] = above[i + 1] | x[i];
            // the top one at bit i - 1 gives bl = i (<= W: fits BW bits)
            bl = {BW{1'b0}};
            for (i = 1; i <= W; i = i + 1)
                if (x[i - 1] && !above[i])
                    bl = bl | i[BW-1:0];
            nz = above[0];
        end
    end else begin : g_search
        // v is a scratch word (blocking assigns, shifted down level by level): Verilator samples
        // it at the end of the evaluation, where it is 0 or 1 by construction (no toggle coverage)
        /* verilator coverage_off */
        reg [W-1:0]  v;    // the value at the current level (level BW is x)
        /* verilator coverage_on */
        reg [BW-1:0] pos;  // index of the top one (0 if x == 0); bits NL and up stay 0
        integer      b;
        always @* begin
            v   = x;
            pos = {BW{1'b0}};
            for (b = NL - 1; b >= 0; b = b - 1) begin
                // a one at or above bit 2^b: shift it down, set bit b of the position
                if (|(v >> (1 << b))) begin
                    v      = v >> (1 << b);
                    pos[b] = 1'b1;
                end
            end
            // the final level is 0 or 1 (only bit 0 can be set): reducing it is bit 0
            nz = |v;
            bl = pos + {{(BW-1){1'b0}}, nz};
        end
    end
endgenerate

endmodule

`default_nettype wire
