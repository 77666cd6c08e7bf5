// bitlen: bl = bitlen(x) = the number of bits up to and including the top one of x
// (0 for x = 0), and nz = (x != 0). Combinational.
//
// Binary search: level b (from BW-1 down to 0) tests whether the value has a one at or
// above bit 2^b and if so shifts it down by 2^b and sets bit b of the top-one position;
// the remaining value is 1 (x != 0) or 0, added as the final +1.
//
// Formats: x u{W}.0; bl u{BW}.0, BW >= clog2(W + 1) bits (the caller sizes it); nz 1 bit.
// Latency 0 (combinational); throughput one word per clock.

`default_nettype none

module bitlen #(
    parameter W  = 8,  // input width
    parameter BW = 4   // output width: holds W
) (
    input  wire [W-1:0]  x,
    output wire [BW-1:0] bl,
    output wire          nz
);

// split_var: each level is its own signal (older Verilators see the packed chain as a loop)
wire [(BW+1)*W-1:0] lvl /* verilator split_var */;  // level b value at [b*W +: W]; level BW is x
wire [BW-1:0]       pos;                            // index of the top one (0 if x == 0)

assign lvl[BW*W +: W] = x;

genvar b;
generate
    for (b = 0; b < BW; b = b + 1) begin : g_level
        localparam STEP = 1 << b;
        wire [W-1:0] xv = lvl[(b+1)*W +: W];
        if (STEP < W) begin : g_test
            wire hi = |xv[W-1:STEP];
            assign pos[b] = hi;
            assign lvl[b*W +: W] = hi ? (xv >> STEP) : xv;
        end else begin : g_none
            assign pos[b] = 1'b0;
            assign lvl[b*W +: W] = xv;
        end
    end
endgenerate

// the final level is 0 or 1 (only bit 0 can be set): reducing it is bit 0
assign nz = |lvl[0 +: W];
assign bl = pos + {{(BW-1){1'b0}}, nz};

endmodule

`default_nettype wire
