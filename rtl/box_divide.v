// box_divide: pipelined restoring divider, q = floor(num / den), LANES numerators
// sharing one divisor (the four colour channels of one pixel share the filter width).
//
// Formats: num u{NUM_W}.0 per lane, den u{DEN_W}.0, q u{Q_W}.0 per lane (integers).
// SAT = 0: precondition num < den * 2^Q_W (the quotient fits Q_W bits; den = 0 never meets
// it); then q = floor(num / den) exactly. Outside it q is some deterministic value, not the
// quotient. colour_map guarantees it (num <= 255.5 den, den >= 1; or, divisor normalised
// to div_bits >= 10 bits, num < 256 den: docs/numerics.md "Colour map").
// SAT = 1: precondition num < den * 2^(Q_W+1); q = min(floor(num / den), 2^Q_W - 1), the
// quotient saturated (colour_map, divisor normalised to div_bits <= 9 bits). Stage 0
// also compares num >> Q_W with den, in parallel with its quotient bit: num >= den 2^Q_W
// sets a per-lane flag that forces q to all ones (the other lanes meet the SAT = 0
// precondition, so bit RW of their numerator is 0 and the Q_W stages below are exact).
//
// One quotient bit per stage, MSB first: stage s decides bit i = Q_W-1-s with one
// (DEN_W+1)-bit compare-subtract on bits [i +: DEN_W+1] of the partial remainder
// (before stage s the remainder is < den * 2^(i+1), so those bits hold all of it
// above bit i). After stage s the remainder is < den * 2^i: DEN_W + i bits.
//
// Latency Q_W (register stages); throughput one division per enabled clock.
// Reset (synchronous, active high) clears the valid chain and q_out; the quotient
// register loads only with a valid result, so q_out is never X after reset.
// Written for event-driven simulation speed: one small always @* per (stage, lane) with
// constant part-selects (in Icarus a loop variable read costs more than a wake-up), one
// clocked process per stage, no bus driven piecewise, no net-level arithmetic.

`default_nettype none

module box_divide #(
    parameter NUM_W = 40,           // numerator width per lane (colour_map: (D + w) / 2)
    parameter DEN_W = 33,           // divisor width (colour_map: the filter width w)
    parameter Q_W   = 8,             // quotient bits = pipeline stages (>= 2)
    parameter LANES = 4,             // numerators per vector (one shared divisor)
    parameter SAT   = 0              // 1: saturate the quotient at 2^Q_W - 1 (see above)
) (
    input  wire                   clk,
    input  wire                   rst,
    input  wire                   ce,
    input  wire                   in_valid,
    input  wire [LANES*NUM_W-1:0] num_in,   // lane l at [l*NUM_W +: NUM_W]
    input  wire [DEN_W-1:0]       den_in,
    output wire                   out_valid,
    output wire [LANES*Q_W-1:0]   q_out     // lane l at [l*Q_W +: Q_W]
);

// partial remainder word: holds any numerator that meets the precondition
localparam RW = DEN_W + Q_W;
// numerator bits that reach the remainder word (more only if NUM_W > RW, and those are
// zero under the precondition)
localparam NW = (NUM_W < RW) ? NUM_W : RW;
// SAT: width of the overflow compare (num >> Q_W) >= den (both zero-extended to it)
localparam OW = (NUM_W - Q_W > DEN_W) ? NUM_W - Q_W : DEN_W;
localparam NH = (NUM_W > Q_W) ? NUM_W - Q_W : 1;  // bits of num >> Q_W

// valid chain: valid of stage s at bit s (bit Q_W-1: out_valid)
reg  [Q_W-1:0] valid_reg;

always @(posedge clk) begin
    if (rst)
        valid_reg <= {Q_W{1'b0}};
    else if (ce)
        valid_reg <= {valid_reg[Q_W-2:0], in_valid};
end

genvar s, l;
generate
    for (s = 0; s < Q_W; s = s + 1) begin : g_stage
        localparam integer I = Q_W - 1 - s;  // quotient bit decided by this stage
        // the remainder bits below I (they pass unchanged)
        localparam [RW-1:0]  LOW  = ~({RW{1'b1}} << I);

        // this stage's inputs: the previous stage's registers (stage 0: the ports), lane l
        // at [l*RW +: RW] (remainder < den 2^(I+1)) and [l*Q_W +: Q_W] (quotient bits so far)
        wire [DEN_W-1:0]     den;
        wire [LANES*RW-1:0]  rem_in;
        wire [LANES*Q_W-1:0] q_in;
        wire [LANES-1:0]     ovf_in;  // SAT: num >= den 2^Q_W (q saturates); else 0

        // next values of this stage's registers, lane l computed by g_lane[l]
        reg  [LANES*RW-1:0]  rem_nx;
        reg  [LANES*Q_W-1:0] q_nx;

        if (s == 0) begin : g_in
            reg [LANES*RW-1:0] num_x;
            reg [LANES-1:0]    ovf_x;
            integer            k;
            always @* begin
                num_x = {(LANES*RW){1'b0}};
                ovf_x = {LANES{1'b0}};
                for (k = 0; k < LANES; k = k + 1) begin
                    num_x[k*RW +: NW] = num_in[k*NUM_W +: NW];
                    // SAT = 0, or num < 2^Q_W <= den 2^Q_W (den >= 1): no overflow
                    if (SAT != 0 && NUM_W > Q_W)
                        ovf_x[k] = (num_hi(num_in[k*NUM_W +: NUM_W]) >= den_ow(den_in));
                end
            end
            assign den    = den_in;
            assign rem_in = num_x;
            assign q_in   = {(LANES*Q_W){1'b0}};
            assign ovf_in = ovf_x;
        end else begin : g_in
            assign den    = g_stage[s-1].g_mid.den_reg;
            assign rem_in = g_stage[s-1].g_mid.rem_reg;
            assign q_in   = g_stage[s-1].g_mid.q_reg;
            assign ovf_in = g_stage[s-1].g_mid.ovf_reg;
        end

        for (l = 0; l < LANES; l = l + 1) begin : g_lane
            // one compare-subtract on bits [I +: DEN_W+1] of the partial remainder rem
            // (< 2 den under the precondition): hi >= den iff hi - den does not borrow
            // (both < 2^(DEN_W+1), no wrap)
            reg [RW-1:0]  rem;
            reg [DEN_W:0] diff;   // hi - den, hi = rem >> I
            always @* begin
                rem  = rem_in[l*RW +: RW];
                diff = rem[I +: DEN_W+1] - {1'b0, den};
                // the bits above I+DEN_W are zero after the stage, the bits below I pass;
                // hi >= den (!diff[DEN_W]): bits [I +: DEN_W] take hi - den, else hi
                rem_nx[l*RW +: RW] = rem & LOW;
                rem_nx[l*RW+I +: DEN_W] = diff[DEN_W] ? rem[I +: DEN_W] : diff[DEN_W-1:0];
                q_nx[l*Q_W +: Q_W] = q_in[l*Q_W +: Q_W];
                q_nx[l*Q_W+I] = !diff[DEN_W];
            end
        end

        if (s < Q_W - 1) begin : g_mid
            reg [DEN_W-1:0]     den_reg;
            reg [LANES*RW-1:0]  rem_reg;  // remainder after this stage: < den 2^I
            reg [LANES*Q_W-1:0] q_reg;    // quotient bits decided so far
            wire [LANES-1:0]    ovf_reg;  // SAT: the overflow flags (registers only if SAT)
            always @(posedge clk) begin
                if (ce) begin
                    den_reg <= den;
                    rem_reg <= rem_nx;
                    q_reg   <= q_nx;
                end
            end
            if (SAT != 0) begin : g_sat
                reg [LANES-1:0] ovf_r;
                always @(posedge clk) begin
                    if (ce)
                        ovf_r <= ovf_in;
                end
                assign ovf_reg = ovf_r;
            end else begin : g_nosat
                assign ovf_reg = {LANES{1'b0}};
                /* verilator lint_off UNUSEDSIGNAL */
                wire [LANES-1:0] unused_ovf = ovf_in;  // constant 0 without SAT
                /* verilator lint_on UNUSEDSIGNAL */
            end
        end else begin : g_last
            // output register: reset to 0, loads only a valid result; the final remainder
            // is not needed (floor division); SAT: an overflowed lane's quotient is all ones
            /* verilator lint_off UNUSEDSIGNAL */
            wire [LANES*RW-1:0] unused_rem = rem_nx;
            /* verilator lint_on UNUSEDSIGNAL */
            reg [LANES*Q_W-1:0] q_fin;
            reg [LANES*Q_W-1:0] q_out_reg;
            integer             k;
            always @* begin
                q_fin = q_nx;
                if (SAT != 0)
                    for (k = 0; k < LANES; k = k + 1)
                        if (ovf_in[k])
                            q_fin[k*Q_W +: Q_W] = {Q_W{1'b1}};
            end
            always @(posedge clk) begin
                if (rst)
                    q_out_reg <= {(LANES*Q_W){1'b0}};
                else if (ce && valid_reg[Q_W-2])
                    q_out_reg <= q_fin;
            end
            assign q_out = q_out_reg;
        end
    end
endgenerate

// SAT overflow compare operands: num >> Q_W and den, zero-extended to OW bits
function [OW-1:0] num_hi;
    /* verilator lint_off UNUSEDSIGNAL */
    input [NUM_W-1:0] num;  // the low Q_W bits are not compared
    /* verilator lint_on UNUSEDSIGNAL */
    begin
        num_hi = {OW{1'b0}};
        num_hi[NH-1:0] = num[NUM_W-1 -: NH];
    end
endfunction

function [OW-1:0] den_ow;
    input [DEN_W-1:0] den;
    begin
        den_ow = {OW{1'b0}};
        den_ow[DEN_W-1:0] = den;
    end
endfunction

assign out_valid = valid_reg[Q_W-1];

endmodule

`default_nettype wire
