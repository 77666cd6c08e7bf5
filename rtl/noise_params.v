// noise_params: a noise term's parameters a, T, o (and the exponents te, ae) as each stage of
// noise_term sees them.
//
// The bit-exact twin of model/hw/golden.py noise_params(cfg, a, T, o, te, ae) (the words) and
// noise_params_delays(cfg, param_pipe) (the delays). noise_term's stage 1 reads tc_s1, stage 2
// o_s2 and te_s2, stage 7 tc_s7 and te_s7, stage 8 ac_s8 and ae_s8:
//   tc  T as stages 1 and 7 read it: affine (TRANSFORM 0) T itself; pow2 (1): T is diagonal
//       with entries 0 or 2^e (model/hw/quantize.py guarantees it; the off-diagonal entries
//       are ignored), decoded into {T_jj == 0, e} per axis, e the highest set bit of T_jj
//       below the sign (0 when T_jj = 0), entry j at element j
//   ac  a as stage 8 reads it: any (AMPLITUDE 0) a itself; pow2 (1): a is 0 or +-2^e
//       (model/hw/quantize.py guarantees it), decoded into {a == 0, neg, e}: e the lowest set
//       bit of a (2^e has bit e alone, -2^e bits e..A_W-1; 0 when a = 0), neg the sign bit
//   o, te, ae  as they come (te, ae 0 without exponents: T_EXP_W, A_EXP_W = 0)
// The decoders are combinational (no multipliers), once per term.
//
// Formats (noise_term's; docs/numerics.md "Block floating point" for the exponents):
//   a_in   s{A_W}; A_EXP_W > 0: {ae u{A_EXP_W}, A s{A_W}} (A_W + A_EXP_W bits)
//   t_in   9 x s{T_W}, T[j][k] at element 3*j + k; T_EXP_W > 0: {te u{T_EXP_W}, the nine}
//   o_in   3 x u{O_W}
//   tc_s1, tc_s7  affine 9 x s{T_W}; pow2 3 x {zero, e u{E_W}}, E_W = clog2(T_W - 1)
//   ac_s8  any s{A_W}; pow2 {zero, neg, e u{EA_W}}, EA_W = clog2(A_W)
//   te_s2, te_s7  u{max(T_EXP_W, 1)};  ae_s8 u{max(A_EXP_W, 1)} (0 without exponents)
//
// Latency (delays in enabled clocks from the ports; one term per enabled clock):
// PARAM_PIPE = 0: none, every output is a wire (a_in, t_in, o_in are per-pass parameters,
// stable while vectors are in flight: noise_term's contract). PARAM_PIPE = 1 (noise_fold:
// another term every clock): each output is the term that entered with noise_term's vector,
// delayed to the stage that reads it, L = `LAT_NOISE_TERM (FPGA_REGS: `LAT_NOISE_TERM_FPGA):
//   tc_s1 0;  o_s2, te_s2 `LAT_NOISE_XFORM - 1 (1);  tc_s7, te_s7 L - 2;  ac_s8, ae_s8 L - 1
// (the decoded words are delayed, a few bits each in pow2 modes; te_s7 is te_s2 delayed
// further). Without the gradient (NOISE_GRADIENT = 0) stage 7 reads nothing: tc_s7 and te_s7
// are 0, and so are te and ae without exponents (no register carries them). ce = 0 holds
// every register; rst does not clear the delay lines (not needed: the valid chain is
// noise_term's).

`default_nettype none

`include "tex_latency.vh"

module noise_params #(
    // noise_term's formats and modes (config/<name>.toml keys in brackets)
    parameter T_W            = 17,  // [t_w] transform entry word s{T_W}
    parameter A_W            = 16,  // [a_w] amplitude word s{A_W}
    parameter O_W            = 20,  // offset word (noise_term's P_W = HASH_BITS + P_FRAC)
    parameter TRANSFORM      = 0,   // [transform] 0 affine, 1 pow2 (diagonal 0 / 2^k)
    parameter AMPLITUDE      = 0,   // [amplitude] 0 any, 1 pow2 (0 / +-2^k)
    parameter NOISE_GRADIENT = 1,   // [noise_gradient] 0: stage 7 reads no T (tc_s7 = te_s7 = 0)
    parameter PARAM_PIPE     = 0,   // 0: per-pass parameters (wires); 1: delayed with the vector
    parameter FPGA_REGS      = 0,   // [fpga_regs] noise_term's eight extra stages (longer delays)
    parameter T_EXP_W        = 0,   // [t_exp_w] te in t_in above the nine entries (0: none)
    parameter A_EXP_W        = 0    // [a_exp_w] ae in a_in above the mantissa (0: none)
) (clk, rst, ce, a_in, t_in, o_in, tc_s1, o_s2, te_s2, tc_s7, te_s7, ac_s8, ae_s8);

localparam AFFINE   = (TRANSFORM == 0);
localparam GRAD     = (NOISE_GRADIENT != 0);
localparam AMP_POW2 = (AMPLITUDE == 1);
localparam LATENCY  = FPGA_REGS ? `LAT_NOISE_TERM_FPGA : `LAT_NOISE_TERM;  // noise_term's
localparam D2       = `LAT_NOISE_XFORM - 1;   // delays to stages 2, 7 and 8 (PARAM_PIPE = 1)
localparam D7       = LATENCY - 2;
localparam D8       = LATENCY - 1;
localparam TE_W     = (T_EXP_W > 0) ? T_EXP_W : 1;   // te, ae as noise_term's children take them
localparam AE_W     = (A_EXP_W > 0) ? A_EXP_W : 1;
localparam TIN_W    = 9*T_W + T_EXP_W;               // t_in: {te, T}
localparam AIN_W    = A_W + A_EXP_W;                 // a_in: {ae, a}
localparam E_W      = $clog2(T_W - 1);               // pow2 shift amount 0..T_W-2
localparam TC_W     = AFFINE ? 9*T_W : 3*(E_W + 1);  // T as stages 1 and 7 read it
localparam EA_W     = $clog2(A_W);                   // pow2 amplitude shift 0..A_W-1
localparam AC_W     = AMP_POW2 ? EA_W + 2 : A_W;     // a as stage 8 reads it

/* verilator lint_off UNUSEDSIGNAL */  // PARAM_PIPE = 0: no register, clk, rst, ce not read
input  wire              clk;
input  wire              rst;
input  wire              ce;
/* verilator lint_on UNUSEDSIGNAL */
input  wire [AIN_W-1:0]  a_in;
input  wire [TIN_W-1:0]  t_in;
input  wire [3*O_W-1:0]  o_in;
output wire [TC_W-1:0]   tc_s1;
output wire [3*O_W-1:0]  o_s2;
output wire [TE_W-1:0]   te_s2;
output wire [TC_W-1:0]   tc_s7;
output wire [TE_W-1:0]   te_s7;
output wire [AC_W-1:0]   ac_s8;
output wire [AE_W-1:0]   ae_s8;

// the mantissas and the exponents (0 when there are none: not read then)
wire [A_W-1:0]   a_m = a_in[A_W-1:0];
wire [9*T_W-1:0] t_m = t_in[9*T_W-1:0];
/* verilator lint_off UNUSEDSIGNAL */  // PARAM_PIPE = 1 without exponents: not read
wire [TE_W-1:0]  te_in;
wire [AE_W-1:0]  ae_in;
/* verilator lint_on UNUSEDSIGNAL */
wire [AC_W-1:0]  ac_in;             // a as stage 8 needs it (any: a; pow2: {zero, neg, e})
wire [TC_W-1:0]  tc_in;             // T as stages 1 and 7 need it (affine: T; pow2: {zero, e})

generate
    if (T_EXP_W > 0) begin : g_te
        assign te_in = t_in[9*T_W +: TE_W];
    end else begin : g_no_te
        assign te_in = {TE_W{1'b0}};
    end
    if (A_EXP_W > 0) begin : g_ae
        assign ae_in = a_in[A_W +: AE_W];
    end else begin : g_no_ae
        assign ae_in = {AE_W{1'b0}};
    end

    if (AMP_POW2) begin : g_a_pow2
        // a = 2^e has bit e alone set, a = -2^e bits e..A_W-1 (-2^(A_W-1): bit A_W-1
        // alone): either way e is the lowest set bit, and neg the sign bit
        reg [AC_W-1:0] ac;
        reg [EA_W-1:0] e;
        integer        i;
        always @* begin
            // priority encoder: the lowest set bit of a (0 when a = 0)
            e = {EA_W{1'b0}};
            for (i = A_W - 1; i >= 0; i = i - 1) begin
                if (a_m[i]) e = i[EA_W-1:0];
            end
            ac = {a_m == {A_W{1'b0}}, a_m[A_W-1], e};
        end
        assign ac_in = ac;
    end else begin : g_a_any
        assign ac_in = a_m;
    end

    if (AFFINE) begin : g_t_affine
        assign tc_in = t_m;
    end else begin : g_t_pow2
        // T_jj = 2^e: e is the highest set bit of T_jj below the sign (0 when T_jj = 0)
        reg [TC_W-1:0]        tc;
        reg signed [T_W-1:0]  t_jj;
        reg [E_W-1:0]         e;
        integer               i, j;
        always @* begin
            tc = {TC_W{1'b0}};
            for (j = 0; j < 3; j = j + 1) begin
                t_jj = t_m[(4*j)*T_W +: T_W];
                e    = {E_W{1'b0}};
                for (i = 0; i < T_W - 1; i = i + 1) begin
                    if (t_jj[i]) e = i[E_W-1:0];
                end
                tc[j*(E_W+1) +: E_W+1] = {t_jj == {T_W{1'b0}}, e};
            end
        end
        assign tc_in = tc;
        // the quantizer guarantees a diagonal T: the off-diagonal entries are not read
        /* verilator lint_off UNUSEDSIGNAL */
        wire [6*T_W-1:0] t_offdiag = {t_m[5*T_W +: 3*T_W], t_m[1*T_W +: 3*T_W]};
        /* verilator lint_on UNUSEDSIGNAL */
    end
endgenerate

assign tc_s1 = tc_in;

// the delays (PARAM_PIPE = 1) or wires (0)
generate
    if (PARAM_PIPE != 0) begin : g_param_pipe
        delay_line #(.W(3*O_W), .N(D2)) u_dly_o  (.clk(clk), .rst(rst), .ce(ce), .d_in(o_in),  .d_out(o_s2));
        delay_line #(.W(AC_W),  .N(D8)) u_dly_ac (.clk(clk), .rst(rst), .ce(ce), .d_in(ac_in), .d_out(ac_s8));
        if (GRAD) begin : g_t
            delay_line #(.W(TC_W), .N(D7)) u_dly_tc (.clk(clk), .rst(rst), .ce(ce), .d_in(tc_in), .d_out(tc_s7));
        end else begin : g_no_t
            assign tc_s7 = {TC_W{1'b0}};
        end
        if (T_EXP_W > 0) begin : g_te_pipe
            delay_line #(.W(TE_W), .N(D2)) u_dly_te2 (.clk(clk), .rst(rst), .ce(ce), .d_in(te_in), .d_out(te_s2));
            if (GRAD) begin : g_te7
                delay_line #(.W(TE_W), .N(D7 - D2)) u_dly_te7 (.clk(clk), .rst(rst), .ce(ce), .d_in(te_s2),
                                                               .d_out(te_s7));
            end else begin : g_no_te7
                assign te_s7 = {TE_W{1'b0}};
            end
        end else begin : g_te_none
            assign te_s2 = {TE_W{1'b0}};
            assign te_s7 = {TE_W{1'b0}};
        end
        if (A_EXP_W > 0) begin : g_ae_pipe
            delay_line #(.W(AE_W), .N(D8)) u_dly_ae (.clk(clk), .rst(rst), .ce(ce), .d_in(ae_in), .d_out(ae_s8));
        end else begin : g_ae_none
            assign ae_s8 = {AE_W{1'b0}};
        end
    end else begin : g_param_static
        assign o_s2  = o_in;
        assign tc_s7 = GRAD ? tc_in : {TC_W{1'b0}};
        assign ac_s8 = ac_in;
        assign te_s2 = te_in;
        assign te_s7 = GRAD ? te_in : {TE_W{1'b0}};
        assign ae_s8 = ae_in;
    end
endgenerate

endmodule

`default_nettype wire
