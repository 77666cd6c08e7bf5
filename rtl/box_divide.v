// box_divide: pipelined restoring divider, q = floor(num / den), LANES numerators
// sharing one divisor (the four colour channels of one pixel share the filter width).
//
// Formats: num u{NUM_W}.0 per lane, den u{DEN_W}.0, q u{Q_W}.0 per lane (integers).
// SAT = 0: precondition num < den * 2^Q_W (the quotient fits Q_W bits; den = 0 never meets
// it); then q = floor(num / den) exactly. Outside it q is some deterministic value, not the
// quotient. colour_map guarantees it (num <= 255.5 den, den >= 1; or, divisor normalised
// to CFG_DIV_BITS >= 10 bits, num < 256 den: docs/numerics.md "Colour map").
// SAT = 1: precondition num < den * 2^(Q_W+1); q = min(floor(num / den), 2^Q_W - 1), the
// quotient saturated (colour_map, divisor normalised to CFG_DIV_BITS <= 9 bits). Stage 0
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

`default_nettype none

`include "tex_cfg.vh"

module box_divide #(
    parameter NUM_W = `CFG_D_W - 1,  // numerator width per lane (colour_map: (D + w) / 2)
    parameter DEN_W = `CFG_W_W,      // divisor width (colour_map: the filter width w)
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

genvar s, l;
generate
    for (s = 0; s < Q_W; s = s + 1) begin : g_stage
        localparam integer I = Q_W - 1 - s;  // quotient bit decided by this stage

        // this stage's registers (the last stage keeps only its quotient, g_last.q_out_reg);
        // each stage reads the previous one's by its hierarchical name
        reg              valid_reg;
        wire             vin;
        wire [DEN_W-1:0] den;

        if (s == 0) begin : g_in
            assign vin = in_valid;
            assign den = den_in;
        end else begin : g_in
            assign vin = g_stage[s-1].valid_reg;
            assign den = g_stage[s-1].g_den.den_reg;
        end

        always @(posedge clk) begin
            if (rst)
                valid_reg <= 1'b0;
            else if (ce)
                valid_reg <= vin;
        end

        if (s < Q_W - 1) begin : g_den
            reg [DEN_W-1:0] den_reg;
            always @(posedge clk) begin
                if (ce)
                    den_reg <= den;
            end
        end

        for (l = 0; l < LANES; l = l + 1) begin : g_lane
            wire [RW-1:0]  rem;      // partial remainder entering the stage
            wire [Q_W-1:0] q_prev;   // quotient bits decided before this stage
            wire           ovf;      // SAT: num >= den 2^Q_W (q saturates); else 0

            if (s == 0) begin : g_in
                reg [RW-1:0] num_x;
                always @* begin
                    num_x = {RW{1'b0}};
                    num_x[NW-1:0] = num_in[l*NUM_W +: NW];
                end
                assign rem    = num_x;
                assign q_prev = {Q_W{1'b0}};
                if (SAT != 0 && NUM_W > Q_W) begin : g_ovf
                    reg [OW-1:0] num_hi, den_x;
                    always @* begin
                        num_hi = {OW{1'b0}};
                        num_hi[NUM_W-Q_W-1:0] = num_in[l*NUM_W+Q_W +: NUM_W-Q_W];
                        den_x = {OW{1'b0}};
                        den_x[DEN_W-1:0] = den_in;
                    end
                    assign ovf = (num_hi >= den_x);
                end else begin : g_no_ovf
                    // SAT = 0, or num < 2^Q_W <= den 2^Q_W (den >= 1): no overflow
                    assign ovf = 1'b0;
                end
            end else begin : g_in
                assign rem    = g_stage[s-1].g_lane[l].g_mid.rem_reg;
                assign q_prev = g_stage[s-1].g_lane[l].g_mid.q_reg;
                assign ovf    = g_stage[s-1].g_lane[l].g_mid.ovf_reg;
            end

            wire [DEN_W:0] hi   = rem[I +: DEN_W+1];   // rem >> I: < 2 den under the precondition
            wire [DEN_W:0] diff = hi - {1'b0, den};
            wire           ge   = !diff[DEN_W];        // hi >= den (both < 2^(DEN_W+1), no wrap)
            reg  [RW-1:0]  rem_next;
            reg  [Q_W-1:0] q_next;

            always @* begin
                // the bits above I+DEN_W are zero after the stage, the bits below I pass
                rem_next = rem & ~({RW{1'b1}} << I);
                rem_next[I +: DEN_W] = ge ? diff[DEN_W-1:0] : hi[DEN_W-1:0];
                q_next = q_prev;
                q_next[I] = ge;
            end

            if (s < Q_W - 1) begin : g_mid
                reg [RW-1:0]  rem_reg;  // remainder after this stage: < den 2^I
                reg [Q_W-1:0] q_reg;    // quotient bits decided so far
                wire          ovf_reg;  // SAT: the overflow flag (a register only if SAT)
                always @(posedge clk) begin
                    if (ce) begin
                        rem_reg <= rem_next;
                        q_reg   <= q_next;
                    end
                end
                if (SAT != 0) begin : g_sat
                    reg ovf_r;
                    always @(posedge clk) begin
                        if (ce)
                            ovf_r <= ovf;
                    end
                    assign ovf_reg = ovf_r;
                end else begin : g_nosat
                    assign ovf_reg = 1'b0;
                    wire unused_ovf = ovf;  // constant 0 without SAT
                end
            end else begin : g_last
                // output register: reset to 0, loads only a valid result; the final
                // remainder is not needed (floor division)
                // SAT: an overflowed lane's quotient is all ones
                wire [Q_W-1:0] q_fin;
                if (SAT != 0) begin : g_satq
                    assign q_fin = q_next | {Q_W{ovf}};
                end else begin : g_q
                    assign q_fin = q_next;
                    wire unused_ovf = ovf;  // constant 0 without SAT
                end
                reg [Q_W-1:0] q_out_reg;
                always @(posedge clk) begin
                    if (rst)
                        q_out_reg <= {Q_W{1'b0}};
                    else if (ce && vin)
                        q_out_reg <= q_fin;
                end
                wire unused_rem = &{1'b0, rem_next};
                assign q_out[l*Q_W +: Q_W] = q_out_reg;
            end
        end
    end
endgenerate

assign out_valid = g_stage[Q_W-1].valid_reg;

endmodule

`default_nettype wire
