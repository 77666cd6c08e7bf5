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
// Written for simulation speed: each stage's next values are computed in its one clocked
// process (blocking temporaries) and only on a clock that brings the stage a valid vector,
// so that a simulator skips an idle stage (its registers hold; only the valid chain and
// q_out are reset, and q_out loads only a valid result); no bus driven piecewise, no
// net-level arithmetic.
// Each such process first assigns its temporaries whole, outside any if, so that they are
// C++ locals in the Verilator model (it localizes only a variable wholly assigned outside
// any branch; one first assigned under the if stays a member of the model, a store on every
// write).

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

genvar s;
generate
    for (s = 0; s < Q_W; s = s + 1) begin : g_stage
        localparam integer I = Q_W - 1 - s;  // quotient bit decided by this stage
        // the remainder bits below I (they pass unchanged)
        localparam [RW-1:0]  LOW  = ~({RW{1'b1}} << I);

        // this stage's inputs: the previous stage's registers (stage 0: the ports, widened
        // in the stage's process), lane l at [l*RW +: RW] (remainder < den 2^(I+1)) and
        // [l*Q_W +: Q_W] (quotient bits so far), and their valid
        wire                 v_in;
        wire [DEN_W-1:0]     den;
        wire [LANES*RW-1:0]  rem_in;
        wire [LANES*Q_W-1:0] q_in;
        wire [LANES-1:0]     ovf_in;  // SAT: num >= den 2^Q_W (q saturates); else 0

        if (s == 0) begin : g_in
            assign v_in   = in_valid;
            assign den    = den_in;
            assign rem_in = {(LANES*RW){1'b0}};   // not read: stage 0 widens num_in itself
            assign q_in   = {(LANES*Q_W){1'b0}};
            assign ovf_in = {LANES{1'b0}};        // not read: stage 0 compares num_in itself
        end else begin : g_in
            assign v_in   = valid_reg[s-1];
            assign den    = g_stage[s-1].g_mid.den_reg;
            assign rem_in = g_stage[s-1].g_mid.rem_reg;
            assign q_in   = g_stage[s-1].g_mid.q_reg;
            assign ovf_in = g_stage[s-1].g_mid.ovf_reg;
        end

        // the stage's next values, computed in its clocked process only on a clock that
        // brings it a valid vector (the registers hold otherwise): per lane one
        // compare-subtract on bits [I +: DEN_W+1] of the partial remainder rem (< 2 den
        // under the precondition): hi >= den iff hi - den does not borrow (both
        // < 2^(DEN_W+1), no wrap); the bits above I+DEN_W are zero after the stage, the bits
        // below I pass; hi >= den (!diff[DEN_W]): bits [I +: DEN_W] take hi - den, else hi
        /* verilator lint_off UNUSEDSIGNAL */  // the last stage reads only rem[DEN_W:0]
        reg [RW-1:0]         rem;     // lane temporaries (blocking, in the clocked process)
        /* verilator lint_on UNUSEDSIGNAL */
        reg [DEN_W:0]        diff;    // hi - den, hi = rem >> I
        reg [LANES*Q_W-1:0]  q_nx;
        integer              k;

        if (s < Q_W - 1) begin : g_mid
            reg [DEN_W-1:0]     den_reg;
            reg [LANES*RW-1:0]  rem_reg;  // remainder after this stage: < den 2^I
            reg [LANES*Q_W-1:0] q_reg;    // quotient bits decided so far
            reg [LANES-1:0]     ovf_r;    // SAT: the overflow flags (else not read)
            wire [LANES-1:0]    ovf_reg;
            reg [LANES*RW-1:0]  rem_nx;   // temporaries of the process below
            reg [LANES-1:0]     ovf_nx;
            /* verilator lint_off BLKSEQ */
            always @(posedge clk) begin
                // the temporaries wholly assigned first, outside the if (C++ locals: the header)
                rem    = {RW{1'b0}};
                diff   = {(DEN_W+1){1'b0}};
                q_nx   = {(LANES*Q_W){1'b0}};
                rem_nx = {(LANES*RW){1'b0}};
                ovf_nx = {LANES{1'b0}};
                if (ce && v_in) begin
                    for (k = 0; k < LANES; k = k + 1) begin
                        if (s == 0) begin
                            rem = {RW{1'b0}};
                            rem[NW-1:0] = num_in[k*NUM_W +: NW];
                            q_nx[k*Q_W +: Q_W] = {Q_W{1'b0}};
                            // SAT = 0, or num < 2^Q_W <= den 2^Q_W (den >= 1): no overflow
                            ovf_nx[k] = (SAT != 0 && NUM_W > Q_W)
                                      && (num_hi(num_in[k*NUM_W +: NUM_W]) >= den_ow(den_in));
                        end else begin
                            rem = rem_in[k*RW +: RW];
                            q_nx[k*Q_W +: Q_W] = q_in[k*Q_W +: Q_W];
                            ovf_nx[k] = ovf_in[k];
                        end
                        diff = rem[I +: DEN_W+1] - {1'b0, den};
                        rem_nx[k*RW +: RW] = rem & LOW;
                        rem_nx[k*RW+I +: DEN_W] = diff[DEN_W] ? rem[I +: DEN_W] : diff[DEN_W-1:0];
                        q_nx[k*Q_W+I] = !diff[DEN_W];
                    end
                    den_reg <= den;
                    rem_reg <= rem_nx;
                    q_reg   <= q_nx;
                    ovf_r   <= ovf_nx;
                end
            end
            /* verilator lint_on BLKSEQ */
            assign ovf_reg = (SAT != 0) ? ovf_r : {LANES{1'b0}};  // SAT = 0: ovf_r unread
        end else begin : g_last
            // output register: reset to 0, loads only a valid result; the final remainder
            // is not needed (floor division); SAT: an overflowed lane's quotient is all ones
            /* verilator lint_off UNUSEDSIGNAL */
            wire [LANES*RW-1:0] unused_rem = rem_in;  // read only at [0 +: DEN_W+1] a lane
            /* verilator lint_on UNUSEDSIGNAL */
            reg [LANES*Q_W-1:0] q_out_reg;
            /* verilator lint_off BLKSEQ */
            always @(posedge clk) begin
                rem  = {RW{1'b0}};
                diff = {(DEN_W+1){1'b0}};
                q_nx = {(LANES*Q_W){1'b0}};
                if (rst)
                    q_out_reg <= {(LANES*Q_W){1'b0}};
                else if (ce && v_in) begin
                    for (k = 0; k < LANES; k = k + 1) begin
                        rem = rem_in[k*RW +: RW];
                        diff = rem[I +: DEN_W+1] - {1'b0, den};
                        q_nx[k*Q_W +: Q_W] = q_in[k*Q_W +: Q_W];
                        q_nx[k*Q_W+I] = !diff[DEN_W];
                        if (SAT != 0 && ovf_in[k])
                            q_nx[k*Q_W +: Q_W] = {Q_W{1'b1}};
                    end
                    q_out_reg <= q_nx;
                end
            end
            /* verilator lint_on BLKSEQ */
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
