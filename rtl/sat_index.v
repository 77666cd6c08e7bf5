// sat_index: one end x of a box-filter window -> its colour-table addresses and weights.
//
// x is s{X_W}.{XF} in colour-table entries (XF = f_frac + 1). With k = floor(x / 2^XF)
// (s{KW}.0, KW = X_W - XF) and fr = x mod 2^XF (u{XF}.{XF}), as golden sat_index does:
//   mod   (mode 0): kk = k mod N,          kx = floor(k / N)  (whole tables before x)
//   clamp (mode 1): kk = clip(k, 0, N-1),  kx = k - kk        (whole entries past an edge)
// so that the integral of the colour function from 0 to x is
//   mod:   I(x) = ((kx total + csat[kk-1]) << XF) + fr clut[kk]        (csat[-1] = 0)
//   clamp: I(x) = ((kx clut[kk] + csat[kk-1]) << XF) + fr clut[kk]
// The clamp form equals golden's three cases, given csat = cumsum(clut): below (k < 0):
// kk = 0, I = (k << XF) clut[0] + fr clut[0] = x clut[0]; above (k >= N): kk = N-1,
// csat[N-2] = total - clut[N-1], so I = (total << XF) + (x - N 2^XF) clut[N-1]; inside: kx = 0.
// Outputs: kk (clut address), kk - 1 mod 2^NMAX (csat address), first = (kk == 0)
// (csat[kk-1] reads as 0), fr u{XF}.{XF}, kx s{KW}.0.
// N = 2^n_log2, n_log2 <= NMAX. NM1_IN = 1: N - 1 arrives decoded on nm1_in (colour_map
// with FPGA_REGS registers it beside x, taking the decode off the clamp comparison's path);
// NM1_IN = 0: nm1_in is not read, N - 1 is decoded from n_log2 here. Latency 1 (outputs registered, not reset: an internal
// stage of colour_map, which carries the valid bit); one x per enabled clock.
// Written for simulation speed: the logic in the one clocked process (blocking temporaries),
// computed only on an enabled clock (cmap_sat enables it only on a valid pixel's).
// Each such process first assigns its temporaries whole, outside any if, so that they are
// C++ locals in the Verilator model (it localizes only a variable wholly assigned outside
// any branch; one first assigned under the if stays a member of the model, a store on every
// write).

`default_nettype none

module sat_index #(
    parameter X_W  = 35,               // width of x (signed)
    parameter XF   = 17,               // fraction bits of x
    parameter NMAX = 8,                // log2 of the largest table (>= 1)
    parameter NL_W = 4,                // width of n_log2
    parameter NM1_IN = 0,              // 1: N - 1 from nm1_in (= ~(~0 << n_log2)); 0: decoded here
    parameter KW   = X_W - XF          // width of k and kx (derived: do not override)
) (
    input  wire            clk,
    input  wire            ce,
    input  wire [X_W-1:0]  x_in,       // signed
    input  wire            mode,       // 0 mod, 1 clamp
    input  wire [NL_W-1:0] n_log2,
    /* verilator lint_off UNUSEDSIGNAL */  // NM1_IN = 0: not read
    input  wire [NMAX-1:0] nm1_in,     // N - 1 (NM1_IN = 1)
    /* verilator lint_on UNUSEDSIGNAL */
    output wire [NMAX-1:0] kk_out,
    output wire [NMAX-1:0] km1_out,
    output wire            first_out,
    output wire [XF-1:0]   fr_out,
    output wire [KW-1:0]   kx_out      // signed
);

reg signed [KW-1:0]   k;      // floor(x / 2^XF)
reg        [XF-1:0]   fr;
reg        [NMAX-1:0] nm1;    // N - 1
reg [NMAX-1:0] kk;
reg [KW-1:0]   nm1_x;  // N - 1 zero-extended to KW bits
reg [KW-1:0]   k_hi;   // k - (N - 1): clamp's kx above the table
reg            above;  // clamp: k > N - 1
reg [KW-1:0]   kx;

reg [NMAX-1:0] kk_reg;
reg [NMAX-1:0] km1_reg;
reg            first_reg;
reg [XF-1:0]   fr_reg;
reg [KW-1:0]   kx_reg;

// computed in the clocked process (blocking temporaries) only on an enabled clock
/* verilator lint_off BLKSEQ */
always @(posedge clk) begin
    // every temporary wholly assigned first, outside the if (C++ locals: the header)
    k     = {KW{1'b0}};
    fr    = {XF{1'b0}};
    nm1   = {NMAX{1'b0}};
    nm1_x = {KW{1'b0}};
    above = 1'b0;
    k_hi  = {KW{1'b0}};
    kk    = {NMAX{1'b0}};
    kx    = {KW{1'b0}};
    if (ce) begin
        k   = x_in[X_W-1:XF];
        fr  = x_in[XF-1:0];
        nm1 = (NM1_IN != 0) ? nm1_in : ~({NMAX{1'b1}} << n_log2);
        nm1_x = {KW{1'b0}};
        nm1_x[NMAX-1:0] = nm1;
        // clamp: kx = k - kk taken case by case (below: k; above: k - (N - 1); inside: 0), so
        // that the subtraction runs beside the comparison instead of after it (one carry chain
        // on the path, not two)
        above = !k[KW-1] && (k > $signed(nm1_x));
        k_hi  = k - nm1_x;
        if (!mode)
            kk = k[NMAX-1:0] & nm1;
        else if (k[KW-1])
            kk = {NMAX{1'b0}};
        else if (above)
            kk = nm1;
        else
            kk = k[NMAX-1:0];
        // (separate statements: in one ?: an unsigned operand would make >>> a logical shift)
        if (!mode)
            kx = k >>> n_log2;
        else if (k[KW-1])
            kx = k;
        else if (above)
            kx = k_hi;
        else
            kx = {KW{1'b0}};
        kk_reg    <= kk;
        km1_reg   <= kk - 1'b1;
        first_reg <= (kk == {NMAX{1'b0}});
        fr_reg    <= fr;
        kx_reg    <= kx;
    end
end
/* verilator lint_on BLKSEQ */

assign kk_out    = kk_reg;
assign km1_out   = km1_reg;
assign first_out = first_reg;
assign fr_out    = fr_reg;
assign kx_out    = kx_reg;

endmodule

`default_nettype wire
