/*
 * isqrt: pipelined integer square root, r_out = floor(sqrt(l_in)), exact.
 * Twin of model/hw/golden.py isqrt().
 *
 * Restoring digit-by-digit method, one result bit per iteration, R_W iterations
 * (most significant bit first). l_in is zero-padded to 2 R_W bits and consumed
 * two bits per iteration:
 *
 *   rs   = 4 rem + (next two bits of l)
 *   try  = 4 root + 1
 *   bit  = rs >= try;  rem = bit ? rs - try : rs;  root = 2 root + bit
 *
 * Invariant: rem <= 2 root, so rem < 2^R_W on entry to every iteration and rs,
 * try fit R_W + 2 bits.
 *
 * The R_W iterations are spread over LATENCY register stages, stage k holding
 * iterations t with floor(t LATENCY / R_W) = k (as even as possible); the last
 * stage ends in the output register.
 *
 * Formats: l_in u{L_W}.0, r_out u{R_W}.0. Needs 2 R_W >= L_W (then r_out
 * always fits) and 1 <= LATENCY <= R_W.
 *
 * Latency LATENCY register stages; throughput one result per enabled clock.
 * ce = 0 holds every register. rst (synchronous) clears the valid chain and the
 * output register; the output register loads only valid vectors (no X after reset).
 *
 * Written for simulation speed: all iterations in the one clocked process (blocking
 * temporaries, constant stage masks), each stage's only on an enabled clock that brings it
 * a valid vector (its registers hold otherwise), no bus driven piecewise.
 * Each such process first assigns its temporaries whole, outside any if, so that they are
 * C++ locals in the Verilator model (it localizes only a variable wholly assigned outside
 * any branch; one first assigned under the if stays a member of the model, a store on every
 * write).
 */


`default_nettype none

module isqrt #(
    parameter L_W     = 25,        // input width (unsigned)
    parameter R_W     = 13,        // output width: iterations, one result bit each; 2 R_W >= L_W
    parameter LATENCY = 3          // register stages, 1..R_W
) (
    input  wire           clk,
    input  wire           rst,
    input  wire           ce,
    input  wire           in_valid,
    input  wire [L_W-1:0] l_in,
    output wire           out_valid,
    output wire [R_W-1:0] r_out
);

localparam X_W  = 2 * R_W;                  // padded radicand
localparam S_NN = (LATENCY > 1) ? LATENCY - 1 : 1;  // internal stage registers (>= 1 declared)

// elaboration fails (unknown module) on parameters outside the supported range
generate
    if (X_W < L_W || LATENCY < 1 || LATENCY > R_W) begin : g_bad_params
        isqrt_needs_2_r_w_ge_l_w_and_1_le_latency_le_r_w u_error ();
    end
endgenerate

// valid chain: vin[k] is the valid flag of the vector entering stage k
reg  [LATENCY-1:0] valid_reg;
wire [LATENCY:0]   vin = {valid_reg, in_valid};

assign out_valid = valid_reg[LATENCY-1];

wire [X_W-1:0] l_pad;

generate
    if (X_W > L_W) begin : g_pad
        assign l_pad = {{(X_W-L_W){1'b0}}, l_in};
    end else begin : g_nopad
        assign l_pad = l_in;
    end
endgenerate

// Iteration t belongs to stage (t LATENCY) / R_W. The state after the last
// iteration of stage k < LATENCY - 1 is registered in segment k of the *_reg
// vectors; the first iteration of stage k > 0 starts from segment k - 1.
// (One process for all iterations: event-driven simulators evaluate it once a
// clock instead of waking R_W^2 part-select readers.
// The stage boundaries are constant masks, so the loop body is only the
// iteration and its few reads.)

// FIRST[t]: iteration t > 0 is the first of its stage; LAST[t]: iteration
// t < R_W - 1 is the last of its stage (LAST[t] = FIRST[t + 1])
// (evaluated at elaboration only: no coverage points)
/* verilator coverage_off */
function [R_W-1:0] first_mask;
    input integer lat;
    integer i;
    begin
        first_mask = {R_W{1'b0}};
        for (i = 1; i < R_W; i = i + 1) begin
            first_mask[i] = ((i * lat) / R_W) != (((i - 1) * lat) / R_W);
        end
    end
endfunction
/* verilator coverage_on */

localparam [R_W-1:0] FIRST = first_mask(LATENCY);
localparam [R_W-1:0] LAST  = FIRST >> 1;

/* verilator lint_off UNUSEDSIGNAL */
// with LATENCY = 1 there is no internal stage and these registers are never read;
// x is consumed from the top, so its low bits in a stage register are zeros
reg [S_NN*R_W-1:0] root_reg;  // partial roots
reg [S_NN*R_W-1:0] rem_reg;   // remainders
reg [S_NN*X_W-1:0] x_reg;     // radicand bits not yet consumed, MSBs first
reg [S_NN*R_W-1:0] root_d, rem_d;  // their next values (blocking temporaries: whole words,
reg [S_NN*X_W-1:0] x_d;            // one non-blocking load each; a skipped stage's segment holds)
/* verilator lint_on UNUSEDSIGNAL */
reg [R_W-1:0]  root, rem;
// x: a scratch word (shifted up iteration by iteration); Verilator samples it at the end of
// the evaluation, when its low bits are 0 (no coverage points)
/* verilator coverage_off */
reg [X_W-1:0]  x;
/* verilator coverage_on */
reg [R_W+1:0]  rs;
/* verilator lint_off UNUSEDSIGNAL */
// the two MSBs of diff are zero when used: the new remainder is <= 2 root < 2^R_W
reg [R_W+1:0]  diff;
/* verilator lint_on UNUSEDSIGNAL */
integer        t, k;
reg [R_W-1:0]  r_reg;
// the iterations (blocking temporaries) and every register: one clocked process; a stage's
// iterations run, and its registers load, only on an enabled clock that brings the stage a
// valid vector (vin[k]); the stage registers hold otherwise
/* verilator lint_off BLKSEQ */
always @(posedge clk) begin
    // every temporary wholly assigned first, outside the if (C++ locals: the header)
    root   = {R_W{1'b0}};
    rem    = {R_W{1'b0}};
    x      = l_pad;
    rs     = {(R_W+2){1'b0}};
    diff   = {(R_W+2){1'b0}};
    root_d = root_reg;
    rem_d  = rem_reg;
    x_d    = x_reg;
    if (ce) begin
        for (t = 0; t < R_W; t = t + 1) begin
            // k = the stage of iteration t, a constant of the loop index (Yosys folds it;
            // a variable stepped through the loop in a clocked process it does not, and
            // makes multipliers and shifters of the part-selects)
            k = (t * LATENCY) / R_W;
            if (FIRST[t]) begin
                // first iteration of stage k: start from stage k - 1's register
                root = root_reg[(k-1)*R_W +: R_W];
                rem  = rem_reg[(k-1)*R_W +: R_W];
                x    = x_reg[(k-1)*X_W +: X_W];
            end
            if (vin[k]) begin
                // rs = 4 rem + (next two bits of x), trial = 4 root + 1; the new bit
                // goes straight into root (root[0] below)
                rs    = {rem, x[X_W-1 -: 2]};
                diff  = rs - {root, 2'b01};
                root  = {root[R_W-2:0], rs >= {root, 2'b01}};
                rem   = root[0] ? diff[R_W-1:0] : rs[R_W-1:0];
                x     = x << 2;
                if (LAST[t]) begin
                    // last iteration of stage k: into the stage register
                    root_d[k*R_W +: R_W] = root;
                    rem_d[k*R_W +: R_W]  = rem;
                    x_d[k*X_W +: X_W]    = x;
                end
            end
        end
        root_reg <= root_d;
        rem_reg  <= rem_d;
        x_reg    <= x_d;
    end
    // output register (stage LATENCY - 1): root after the last iteration
    if (rst) begin
        valid_reg <= {LATENCY{1'b0}};
        r_reg     <= {R_W{1'b0}};
    end else if (ce) begin
        valid_reg <= vin[LATENCY-1:0];
        if (vin[LATENCY-1]) begin
            r_reg <= root;
        end
    end
end
/* verilator lint_on BLKSEQ */
assign r_out = r_reg;

endmodule

`default_nettype wire
