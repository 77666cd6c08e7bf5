// noise_xform: one axis of a noise term's coordinate transform, the lattice position
//   p_j = ((sum_k T_jk s_k) >> (TS_SHIFT - te)) + o_j  mod 2^P_W   (">>" a floor)
// split into the lattice cell ip = p_j >> P_FRAC and the fraction fp = p_j mod 2^P_FRAC.
// noise_term instantiates it once per axis j (AXIS); the bit-exact twin is
// model/hw/golden.py noise_xform(cfg, T_j, o_j, s, te).
//
// Block floating point (T_EXP_W > 0, [t_exp_w]; docs/numerics.md "Block floating point"):
// t_row holds the term's mantissas M_j (T_j = M_j 2^(te - T_FRAC)) and te its exponent, read
// at stage 2: the floor shift is TS_SHIFT - te (>= 0: model/hw/config.py checks TS_SHIFT >=
// 2^T_EXP_W - 1, and so does the elaboration below), formed as (sum << te) mod 2^ACC_W, then
// >> TS_SHIFT: the same P_W bits of the ACC_W-bit sum, so ACC_W and the multipliers stay
// what they are at te = 0. T_EXP_W = 0: no exponent (te is one bit, not read), the shift the
// constant TS_SHIFT, the block as it was.
//
// Transform (TRANSFORM): affine (0): t_row is row j of T, three multipliers. pow2 (1): T is
// diagonal with entries 0 or 2^e (model/hw/quantize.py guarantees it), and t_row is T_jj
// decoded by noise_term, {zero, e} (E_W + 1 bits): T_jj s_j is s_j << e, or 0; no multiplier.
// T s matters only mod 2^ACC_W (ACC_W = TS_SHIFT + P_W: p wraps), so the products are only
// that wide (the low ACC_W bits of the product of the sign-extended operands).
//
// Formats:
//   s_in   3 x s{S_W}.{S_FRAC}, {r, t, s} (s at the LSBs)
//   t_row  affine: 3 x s{T_W}.{T_FRAC}, T_jk at element k; pow2: {zero, e} of T_jj
//   o_in   u{P_W}.{P_FRAC} (P_W = HASH_BITS + P_FRAC: a phase mod the lattice period)
//   te     u{T_EXP_W} (T_EXP_W > 0; else 1 bit, ignored)
//   ip     u{HASH_BITS}.0, fp u0.{P_FRAC}
// Latency `LAT_NOISE_XFORM = 2 register stages: 1 the products (pow2: the shift), 2 p. s_in
// and t_row are read at stage 1, o_in and te one enabled clock later (stage 2: noise_term's
// PARAM_PIPE delays o and te by one clock). One vector per enabled clock; ce = 0 holds both
// stages; no reset (data only, the caller's valid chain says which stages hold a vector).

`default_nettype none

`include "tex_latency.vh"

module noise_xform #(
    parameter S_W       = 24,  // [s_w] texture coordinate word s{S_W}.{S_FRAC}
    parameter S_FRAC    = 16,  // [s_frac]
    parameter T_W       = 17,  // [t_w] transform entry word s{T_W}.{T_FRAC}
    parameter T_FRAC    = 10,  // [t_frac]
    parameter P_FRAC    = 12,  // [p_frac] noise-space fraction bits
    parameter HASH_BITS = 8,   // [hash_bits] lattice period 2^HASH_BITS
    parameter TRANSFORM = 0,   // [transform] 0 affine, 1 pow2 (diagonal 0 / 2^k: a shift)
    parameter AXIS      = 0,   // j, the axis (0..2): pow2 reads s_j
    parameter T_EXP_W   = 0    // [t_exp_w] T's per-term exponent te (0: none; affine only)
) (clk, ce, s_in, t_row, o_in, te, ip, fp);

localparam STAGES   = 2;                                 // register stages of this implementation
localparam LATENCY  = `LAT_NOISE_XFORM;                  // must equal STAGES (checked below)
localparam AFFINE   = (TRANSFORM == 0);
localparam P_W      = HASH_BITS + P_FRAC;                // p: cell . fraction, mod the period
localparam TS_SHIFT = S_FRAC + T_FRAC - P_FRAC;          // >= 0 (model/hw/config.py checks)
localparam ACC_W    = TS_SHIFT + P_W;                    // T s mod 2^ACC_W decides p
localparam E_W      = $clog2(T_W - 1);                   // pow2 shift amount 0..T_W-2
localparam TR_W     = AFFINE ? 3*T_W : E_W + 1;          // t_row
localparam MUL_W    = (ACC_W > S_W) ? ACC_W : S_W;       // pow2: the shifted s (>= ACC_W)
localparam NPROD    = AFFINE ? 3 : 1;                    // products
localparam TE_W     = (T_EXP_W > 0) ? T_EXP_W : 1;       // te (not read when T_EXP_W = 0)
localparam TE_MAX   = (1 << T_EXP_W) - 1;                // the largest exponent

input  wire              clk;
input  wire              ce;
input  wire [3*S_W-1:0]  s_in;
input  wire [TR_W-1:0]   t_row;
input  wire [P_W-1:0]    o_in;
/* verilator lint_off UNUSEDSIGNAL */  // T_EXP_W = 0: no exponent
input  wire [TE_W-1:0]   te;
/* verilator lint_on UNUSEDSIGNAL */
output reg  [HASH_BITS-1:0] ip;
output reg  [P_FRAC-1:0]    fp;

// elaboration fails (unknown module) when rtl/tex_latency.vh and this block disagree
generate
    if (LATENCY != STAGES || AXIS < 0 || AXIS > 2 || T_EXP_W < 0
        || (T_EXP_W > 0 && (!AFFINE || TS_SHIFT < TE_MAX))) begin : g_bad_params
        noise_xform_latency_must_be_lat_noise_xform u_error ();
    end
endgenerate

// stage 1: the products T_jk s_k mod 2^ACC_W at element k (pow2: T_jj s_j alone)
reg [NPROD*ACC_W-1:0] prod_next;
reg [NPROD*ACC_W-1:0] prod_reg;
generate
    if (AFFINE) begin : g_affine
        integer k;
        always @* begin
            for (k = 0; k < 3; k = k + 1)
                prod_next[k*ACC_W +: ACC_W] = $signed(t_row[k*T_W +: T_W]) * $signed(s_in[k*S_W +: S_W]);
        end
    end else begin : g_pow2
        // s_j sign-extended to MUL_W + 1 bits (>= ACC_W + 1) and shifted; above bit ACC_W the
        // product does not reach p
        /* verilator lint_off UNUSEDSIGNAL */
        reg signed [MUL_W:0] shl;
        /* verilator lint_on UNUSEDSIGNAL */
        wire signed [S_W-1:0] s_j = s_in[AXIS*S_W +: S_W];
        always @* begin
            shl = {{(MUL_W+1-S_W){s_j[S_W-1]}}, s_j} <<< t_row[E_W-1:0];
            prod_next = t_row[E_W] ? {ACC_W{1'b0}} : shl[ACC_W-1:0];
        end
        // only the diagonal entry's s is read
        /* verilator lint_off UNUSEDSIGNAL */
        wire [3*S_W-1:0] s_unused = s_in;
        /* verilator lint_on UNUSEDSIGNAL */
    end
endgenerate

// stage 2: p = (sum >> (TS_SHIFT - te)) + o mod 2^P_W; the fraction dropped by the floor
// shift is the low TS_SHIFT - te bits of the sum (T_EXP_W = 0: acc[TS_SHIFT-1:0])
/* verilator lint_off UNUSEDSIGNAL */
reg [ACC_W-1:0] acc;
/* verilator lint_on UNUSEDSIGNAL */
integer         i;
always @* begin
    acc = prod_reg[0 +: ACC_W];
    for (i = 1; i < NPROD; i = i + 1)
        acc = acc + prod_reg[i*ACC_W +: ACC_W];
end

// the sum with the floor shift's P_W bits at [ACC_W-1:TS_SHIFT]: acc itself, or (block
// floating point) acc << te mod 2^ACC_W (bits ACC_W-1-te..TS_SHIFT-te of acc: TS_SHIFT >= te)
/* verilator lint_off UNUSEDSIGNAL */  // the bits below TS_SHIFT: the fraction dropped
wire [ACC_W-1:0] acc_e;
/* verilator lint_on UNUSEDSIGNAL */
generate
    if (T_EXP_W > 0) begin : g_exp
        assign acc_e = acc << te;
    end else begin : g_fixed
        assign acc_e = acc;
    end
endgenerate

always @(posedge clk) begin
    if (ce) begin
        prod_reg <= prod_next;
        {ip, fp} <= acc_e[ACC_W-1:TS_SHIFT] + o_in;
    end
end

endmodule

`default_nettype wire
