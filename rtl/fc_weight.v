// fc_weight: frequency clamping for the filter "sat_fc" (docs/filters.md): per pixel, the
// fade alpha_i of each noise term and the filter width wv that the faded terms' spread asks for.
//
// The bit-exact twin of model/hw/golden.py fc_weight(cfg, tex, Jm, je), axis by axis (k = 0..2):
//   m_k   = max_c |Jm_kc|                                (row k of the pixel's J = Jm 2^je)
//   lm_k  = fc_log2(m_k) + je 2^LF                       (2^-LF octaves, LF = FC_LOG_FRAC)
//   lt_ik = fc_log2(max_j |T_i,jk|) - (T_FRAC - te_i) 2^LF  (column k of T_i; static)
//   L_i   = max_k (lm_k + lt_ik) over the axes with m_k != 0 and T_i column k != 0
//   alpha_i = clip(FC_KNEE - L_i, 0, 2^AF)               (u1.AF, AF = FC_LOG_FRAC + FC_FADE_LOG2)
//           = 2^AF when no axis qualifies, a_i = 0, i >= k_used or !filter_en (the term unchanged)
//   sd_i  = (2^AF - alpha_i) |a_i| 2^ae_i                (u.{AF + A_FRAC}: the faded part's spread)
//   wv    = min(shift((max_i sd_i) FC_KS 2^n_log2, F_FRAC - AF - A_FRAC - FC_KSF), 2^(W_CAP_LOG2 + F_FRAC))
// with fc_log2(x) = (e << LF) + floor((x - 2^e) 2^LF / 2^e), e = bitlen(x) - 1 (Mitchell's
// piecewise-linear log2, exact at powers of two) and FC_KS = sigma sqrt(12) of the lattice
// noise in u.FC_KSF (model/hw/config.py fc_sigma12: the width of the box with the noise's
// standard deviation). L_i is log2 of the largest entry of |T_i| |J|, the pixel's footprint
// in term i's cells within a factor 3 of |T_i J|'s; the fade is linear in it: the term is whole
// up to 2^((FC_KNEE - 2^AF) 2^-LF) cells a pixel and gone (its mean, 0) from 2^(FC_KNEE 2^-LF),
// frequency clamping (Gritz 1998); its spread moves into the box width, after Heitz et al. (2013).
// Block floating point ([t_exp_w] T_EXP_W, [a_exp_w] A_EXP_W > 0; docs/numerics.md "Block floating
// point"): T_i and a_i are mantissas with the term's exponents te_i, ae_i (T_i = M_i 2^(te_i -
// T_FRAC), a_i = A_i 2^(ae_i - A_FRAC)), which ride above each term's mantissas in t_all and a_all
// (as in noise_term's t_in and a_in); te = ae = 0 without them (the block as it was).
//
// Formats: jm_in 6 x s{J_W}.0 (element 2*k + col), je_in s{JE_W}.0; a_all K x s{A_W}.{A_FRAC},
//   t_all K x 9 x s{T_W}.{T_FRAC} (the parameter registers, static during a pass); with
//   exponents term i of a_all is {ae_i u{A_EXP_W}, A_i} (A_W + A_EXP_W bits) and of t_all
//   {te_i u{T_EXP_W}, its nine mantissas} (9 T_W + T_EXP_W bits);
//   alpha_out K x u{AF+1}.{AF} (term i at [i*(AF+1) +: AF+1]); wv_out u{W_W}.{F_FRAC} entries.
// Internal: m_k u{J_W}; lm, lt, L, the fade argument s{L_W}.{LF} (L_W below bounds every sum);
//   |a| 2^ae u{A_W + AE_MAX}; sd u{SD_W}.{AF + A_FRAC}; the scaled width u{PW_W}.
// Pipeline (LATENCY = `LAT_FC_WEIGHT = 8 register stages, one pixel per enabled clock):
//   1  m_k, je      2  lm_k (bitlen, shift)      3  L_i      4  alpha_i      5  sd_i
//   6  max_i sd_i   7  its product with FC_KS    8  wv (shifts, saturation)
//   (alpha from stage 4 through a 4-stage delay_line)
// The static parts (the column maxima of |T_i|, then lt_ik, |a_i|, t_on_i) are registered
// functions of the parameter registers, updated every clock.
// Parameters a_all, t_all, k_used, filter_en, n_log2 are per-pass registers, read directly by
// the stages (lt_i, t_on_i and |a_i| through their registered copies; no pipeline register
// carries them). CONTRACT: stable while pixels are in flight (texture_pipeline guarantees it).
// Reset: synchronous, active high, clears the valid bits.
`default_nettype none
`include "tex_latency.vh"
module fc_weight #(
    parameter NOISE_TERMS  = 8,   // K noise terms (1..8)
    parameter J_W          = 12,  // Jacobian mantissas s{J_W}.0
    parameter JE_W         = 8,   // Jacobian exponent s{JE_W}.0
    parameter T_W          = 17,  // transform entries s{T_W}.{T_FRAC}
    parameter T_FRAC       = 10,  // transform fraction bits
    parameter A_W          = 16,  // amplitudes s{A_W}.{A_FRAC}
    parameter A_FRAC       = 12,  // amplitude fraction bits
    parameter F_FRAC       = 16,  // w fraction bits (entries)
    parameter W_CAP_LOG2   = 16,  // wv saturates at 2^W_CAP_LOG2 entries
    parameter N_LOG2_MAX   = 8,   // n_log2 0..N_LOG2_MAX
    parameter FC_LOG_FRAC  = 5,   // LF: fraction bits of log2 phi
    parameter FC_KNEE      = 112, // the fade's end, log2 phi in 2^-LF octaves
    parameter FC_FADE_LOG2 = 2,   // the fade spans 2^FC_FADE_LOG2 octaves
    parameter FC_KS        = 328, // sigma sqrt(12) of the lattice noise, u.FC_KSF (the configuration's blend)
    parameter FC_KSF       = 8,   // FC_KS's fraction bits
    parameter T_EXP_W      = 0,   // [t_exp_w] T's per-term exponent te in t_all (0: none)
    parameter A_EXP_W      = 0    // [a_exp_w] a's per-term exponent ae in a_all (0: none)
) (clk, rst, ce, in_valid, jm_in, je_in, a_all, t_all, k_used, filter_en, n_log2, out_valid, alpha_out,
   wv_out);
localparam K     = NOISE_TERMS;
localparam LF    = FC_LOG_FRAC;
localparam AF    = FC_LOG_FRAC + FC_FADE_LOG2;
localparam KU_W  = $clog2(K + 1);
localparam NL_W  = $clog2(N_LOG2_MAX + 1) > 0 ? $clog2(N_LOG2_MAX + 1) : 1;
localparam W_W   = W_CAP_LOG2 + F_FRAC + 1;
localparam CAPB  = W_CAP_LOG2 + F_FRAC;                     // wv saturates at 2^CAPB
localparam JB_W  = $clog2(J_W + 1);                         // bitlen(m), m <= 2^(J_W-1)
localparam TB_W  = $clog2(T_W + 1);                         // bitlen(|T|), |T| <= 2^(T_W-1)
localparam KNEE_ABS = (FC_KNEE < 0) ? -FC_KNEE : FC_KNEE;
localparam KB_W  = $clog2(KNEE_ABS + 1);
localparam TE_MAX = (1 << T_EXP_W) - 1;                     // the largest exponents (0: none)
localparam AE_MAX = (1 << A_EXP_W) - 1;
localparam TS_W  = 9*T_W + T_EXP_W;                         // one term of t_all: {te, T}
localparam AS_W  = A_W + A_EXP_W;                           // one term of a_all: {ae, a}
localparam AA_W  = A_W + AE_MAX;                            // |a| 2^ae
localparam TF_W  = $clog2(((T_FRAC > TE_MAX) ? T_FRAC : TE_MAX) + 1);
// L_W: every term of FC_KNEE - lm - lt is below 2^(L_W - 3) in magnitude: |FC_KNEE| < 2^KB_W,
// fc_log2(m) < 2^(JB_W+LF), |je| 2^LF <= 2^(JE_W-1+LF), fc_log2(|T|) < 2^(TB_W+LF), T_FRAC 2^LF and
// te 2^LF < 2^(TF_W+LF); at most four of them add in one direction (five with an exponent, te
// beside T_FRAC: one bit more)
localparam L_M1  = (KB_W > JB_W + LF) ? KB_W : JB_W + LF;
localparam L_M2  = (L_M1 > JE_W + LF) ? L_M1 : JE_W + LF;
localparam L_M3  = (L_M2 > TB_W + LF) ? L_M2 : TB_W + LF;
localparam L_W   = ((L_M3 > TF_W + LF) ? L_M3 : TF_W + LF) + 3 + ((T_EXP_W > 0) ? 1 : 0);
localparam TE_W  = (T_EXP_W > 0) ? T_EXP_W : 1;             // te, ae words (1 bit, 0, when none)
localparam AE_W  = (A_EXP_W > 0) ? A_EXP_W : 1;
localparam SD_W  = AF + AA_W;                               // (2^AF - alpha) |a| 2^ae <= 2^AF 2^(A_W-1+AE_MAX)
localparam KS_W  = $clog2(FC_KS + 1) > 0 ? $clog2(FC_KS + 1) : 1;
localparam integer C0 = F_FRAC - AF - A_FRAC - FC_KSF;  // signed (may be negative)           // the constant part of wv's shift
localparam PW_W  = SD_W + KS_W + N_LOG2_MAX + ((C0 > 0) ? C0 : 0);  // the shifted product
localparam ONE   = 1 << AF;
localparam [PW_W+W_W-1:0] CAP_V = {{PW_W{1'b0}}, 1'b1, {CAPB{1'b0}}};  // 2^CAPB (W_W = CAPB + 1)
localparam integer   KNEE_I = FC_KNEE;
localparam signed [L_W-1:0] KNEE_L = KNEE_I[L_W-1:0];
localparam integer   ONE_I  = ONE;
localparam signed [L_W-1:0] ONE_L  = ONE_I[L_W-1:0];      // 2^AF < 2^(L_W-1): AF <= LF + 4
localparam integer   TF_SHI = T_FRAC << LF;                 // T_FRAC 2^LF
localparam [L_W-1:0] TF_SH  = TF_SHI[L_W-1:0];

// the ports (declared after the widths they use)
input  wire                              clk;
input  wire                              rst;
input  wire                              ce;
input  wire                              in_valid;
input  wire [6*J_W-1:0]                  jm_in;
input  wire [JE_W-1:0]                   je_in;
input  wire [NOISE_TERMS*AS_W-1:0]       a_all;
input  wire [NOISE_TERMS*TS_W-1:0]       t_all;
input  wire [KU_W-1:0]                   k_used;
input  wire                              filter_en;
input  wire [NL_W-1:0]                   n_log2;
output wire                              out_valid;
output wire [NOISE_TERMS*(AF+1)-1:0]     alpha_out;
output reg  [W_W-1:0]                    wv_out;

localparam STAGES  = 8;               // register stages of this implementation (below)
localparam LATENCY = `LAT_FC_WEIGHT;  // must equal STAGES
localparam AL_DLY  = STAGES - 4;      // alpha (stage 4) waits for wv

// elaboration fails (unknown module) when rtl/tex_latency.vh and this block disagree
generate
    if (LATENCY != STAGES) begin : g_latency_mismatch
        fc_weight_latency_mismatch_see_tex_latency_vh u_error ();
    end
endgenerate

// static: per term and axis tn_ik = max_j |T_i,jk| (column k), registered; then from it
// lt_ik = fc_log2(tn_ik) - T_FRAC 2^LF and tz_ik = (tn_ik = 0), |a_i|, t_on_i, registered.
// These registers follow the parameter registers every clock (not on ce), two clocks behind;
// a pixel reads them at stage 3, three clocks after it enters at the earliest, and the
// parameters are written before the pass's first pixel enters.
function [T_W-1:0] t_abs;
    input [T_W-1:0] v;
    t_abs = v[T_W-1] ? -v : v;  // |-2^(T_W-1)| = 2^(T_W-1): right as unsigned
endfunction
function [T_W-1:0] t_max3;
    input [T_W-1:0] x, y, z;
    t_max3 = (x > y) ? ((x > z) ? x : z) : ((y > z) ? y : z);
endfunction
reg [3*K*T_W-1:0] tn;  // tn_ik at [(3*i + k)*T_W +: T_W]
integer           ia, ka;
always @(posedge clk) begin
    for (ia = 0; ia < K; ia = ia + 1)
        for (ka = 0; ka < 3; ka = ka + 1)
            tn[(3*ia + ka)*T_W +: T_W] <= rst ? {T_W{1'b0}} :
                t_max3(t_abs(t_all[ia*TS_W + (0 + ka)*T_W +: T_W]), t_abs(t_all[ia*TS_W + (3 + ka)*T_W +: T_W]),
                       t_abs(t_all[ia*TS_W + (6 + ka)*T_W +: T_W]));
end

wire [3*K*TB_W-1:0]  tbl;   // bitlen(tn_ik)
genvar               gb;
generate
    for (gb = 0; gb < 3*K; gb = gb + 1) begin : g_tbl
        /* verilator lint_off UNUSEDSIGNAL */  // tn = 0 is tested directly
        wire tnz;
        /* verilator lint_on UNUSEDSIGNAL */
        bitlen #(.W(T_W), .BW(TB_W)) u_bitlen_t (.x(tn[gb*T_W +: T_W]), .bl(tbl[gb*TB_W +: TB_W]), .nz(tnz));
    end
endgenerate
reg signed [L_W-1:0] lt_c    [0:3*K-1];
reg                  tz_c    [0:3*K-1];
reg        [AA_W-1:0] a_abs_c [0:K-1];
reg                  t_on_c  [0:K-1];
reg        [A_W-1:0] av, avm;
reg      [TB_W-1:0]  te;    // e = bitlen(tn) - 1 (0 for tn = 0: masked by tz)
/* verilator lint_off UNUSEDSIGNAL */  // above bit LF: the leading one (and zeros)
reg    [T_W+LF-1:0]  tx;    // floor(tn 2^LF / 2^e) = 2^LF + the fraction
/* verilator lint_on UNUSEDSIGNAL */
reg        [L_W-1:0] te_sh; // te_i 2^LF (0 without an exponent)
reg       [AE_W-1:0] ae_i;  // ae_i (0 without an exponent)
integer              i, j;
always @* begin
    for (j = 0; j < 3*K; j = j + 1) begin
        te_sh = {L_W{1'b0}};
        if (T_EXP_W > 0) te_sh = {{(L_W-TE_W){1'b0}}, t_all[(j/3)*TS_W + 9*T_W +: TE_W]} << LF;
        tz_c[j] = (tn[j*T_W +: T_W] == 0);
        te = tz_c[j] ? {TB_W{1'b0}} : tbl[j*TB_W +: TB_W] - 1'b1;
        tx = {tn[j*T_W +: T_W], {LF{1'b0}}} >> te;
        lt_c[j] = $signed({{(L_W-TB_W-LF){1'b0}}, te, tx[LF-1:0]}) - $signed(TF_SH) + $signed(te_sh);
    end
    for (i = 0; i < K; i = i + 1) begin
        av = a_all[i*AS_W +: A_W];
        avm = av[A_W-1] ? -av : av;         // |a|: -2^(A_W-1) is 2^(A_W-1) as unsigned
        /* verilator lint_off WIDTH */  // with an exponent AA_W > A_W: zero-extended on purpose
        a_abs_c[i] = avm;
        /* verilator lint_on WIDTH */
        ae_i = {AE_W{1'b0}};
        if (A_EXP_W > 0) ae_i = a_all[i*AS_W + A_W +: AE_W];
        a_abs_c[i] = a_abs_c[i] << ae_i;    // |a| 2^ae (no exponent: ae = 0)
        t_on_c[i]  = (av != 0) && (i < k_used);
    end
end
reg signed [L_W-1:0] lt    [0:3*K-1];
reg                  tz    [0:3*K-1];
reg                  t_on  [0:K-1];
reg       [AA_W-1:0] a_abs [0:K-1];
integer              ip;
always @(posedge clk) begin
    for (ip = 0; ip < 3*K; ip = ip + 1) begin
        lt[ip] <= rst ? {L_W{1'b0}} : lt_c[ip];
        tz[ip] <= rst ? 1'b1 : tz_c[ip];
    end
    for (ip = 0; ip < K; ip = ip + 1) begin
        t_on[ip]  <= rst ? 1'b0 : t_on_c[ip];
        a_abs[ip] <= rst ? {AA_W{1'b0}} : a_abs_c[ip];
    end
end

// stage 1: m_k = max_c |Jm_kc|
function [J_W-1:0] j_abs;
    input [J_W-1:0] v;
    j_abs = v[J_W-1] ? -v : v;  // |-2^(J_W-1)| = 2^(J_W-1) as unsigned
endfunction
reg [J_W-1:0]  m0 [0:2];
reg [J_W-1:0]  ja, jb;
integer        k0;
always @* begin
    for (k0 = 0; k0 < 3; k0 = k0 + 1) begin
        ja = j_abs(jm_in[(2*k0)*J_W +: J_W]);
        jb = j_abs(jm_in[(2*k0 + 1)*J_W +: J_W]);
        m0[k0] = (ja > jb) ? ja : jb;
    end
end
reg [3*J_W-1:0] m1;  // m_k at [k*J_W +: J_W] (a flat vector: it feeds bitlen ports)
reg [JE_W-1:0]  je1;
reg             v1;
integer         r1;
always @(posedge clk) begin
    if (rst) begin
        v1 <= 1'b0;
    end else if (ce) begin
        v1  <= in_valid;
        je1 <= je_in;
        for (r1 = 0; r1 < 3; r1 = r1 + 1)
            m1[r1*J_W +: J_W] <= m0[r1];
    end
end

// stage 2: lm_k = fc_log2(m_k) + je 2^LF; mz_k = (m_k = 0)
wire [3*JB_W-1:0]    mb;
wire [2:0]           mnz;
genvar               gm;
generate
    for (gm = 0; gm < 3; gm = gm + 1) begin : g_mb
        bitlen #(.W(J_W), .BW(JB_W)) u_bitlen_m (.x(m1[gm*J_W +: J_W]), .bl(mb[gm*JB_W +: JB_W]), .nz(mnz[gm]));
    end
endgenerate
reg [JB_W-1:0]       me;
/* verilator lint_off UNUSEDSIGNAL */  // above bit LF: the leading one (and zeros)
reg [J_W+LF-1:0]     mx;    // floor(m 2^LF / 2^e) = 2^LF + the fraction
/* verilator lint_on UNUSEDSIGNAL */
reg signed [L_W-1:0] lm0 [0:2];
integer              k2;
always @* begin
    for (k2 = 0; k2 < 3; k2 = k2 + 1) begin
        me  = mnz[k2] ? mb[k2*JB_W +: JB_W] - 1'b1 : {JB_W{1'b0}};
        mx  = {m1[k2*J_W +: J_W], {LF{1'b0}}} >> me;
        lm0[k2] = $signed({{(L_W-JB_W-LF){1'b0}}, me, mx[LF-1:0]})
                  + $signed({{(L_W-JE_W-LF){je1[JE_W-1]}}, je1, {LF{1'b0}}});
    end
end
reg signed [L_W-1:0] lm2 [0:2];
reg        [2:0]     mz2;
reg                  v2;
integer              r2;
always @(posedge clk) begin
    if (rst) begin
        v2 <= 1'b0;
    end else if (ce) begin
        v2  <= v1;
        mz2 <= ~mnz;
        for (r2 = 0; r2 < 3; r2 = r2 + 1)
            lm2[r2] <= lm0[r2];
    end
end

// stage 3: L_i = max_k (lm_k + lt_ik) over the qualifying axes (none: no footprint)
reg signed [L_W-1:0] lsum, lmax;
reg                  lany, ok;
reg signed [L_W-1:0] l0   [0:K-1];
reg                  lok0 [0:K-1];
integer              i3, k3;
always @* begin
    for (i3 = 0; i3 < K; i3 = i3 + 1) begin
        lany = 1'b0;
        lmax = {L_W{1'b0}};
        for (k3 = 0; k3 < 3; k3 = k3 + 1) begin
            lsum = lm2[k3] + lt[3*i3 + k3];
            ok   = !mz2[k3] && !tz[3*i3 + k3];
            if (ok && (!lany || lsum > lmax))
                lmax = lsum;
            lany = lany | ok;
        end
        l0[i3]   = lmax;
        lok0[i3] = lany && t_on[i3] && filter_en;
    end
end
reg signed [L_W-1:0] l3   [0:K-1];
reg                  lok3 [0:K-1];
reg                  v3;
integer              r3;
always @(posedge clk) begin
    if (rst) begin
        v3 <= 1'b0;
    end else if (ce) begin
        v3 <= v2;
        for (r3 = 0; r3 < K; r3 = r3 + 1) begin
            l3[r3]   <= l0[r3];
            lok3[r3] <= lok0[r3];
        end
    end
end

// stage 4: alpha_i = clip(FC_KNEE - L_i, 0, 2^AF)
reg signed [L_W-1:0] x4;
reg        [AF:0]    al0 [0:K-1];
integer              i4a;
always @* begin
    for (i4a = 0; i4a < K; i4a = i4a + 1) begin
        x4 = KNEE_L - l3[i4a];
        if (!lok3[i4a])
            al0[i4a] = ONE[AF:0];
        else if (x4 <= $signed({L_W{1'b0}}))
            al0[i4a] = {(AF+1){1'b0}};
        else if (x4 >= ONE_L)
            al0[i4a] = ONE[AF:0];
        else
            al0[i4a] = x4[AF:0];
    end
end
reg [AF:0] al3 [0:K-1];
reg        v4a;
integer    r4a;
always @(posedge clk) begin
    if (rst) begin
        v4a <= 1'b0;
    end else if (ce) begin
        v4a <= v3;
        for (r4a = 0; r4a < K; r4a = r4a + 1)
            al3[r4a] <= al0[r4a];
    end
end

// stage 5: sd_i = (2^AF - alpha_i) |a_i|
reg [AF:0]     om;
reg [SD_W-1:0] sd0 [0:K-1];
integer        i4;
always @* begin
    for (i4 = 0; i4 < K; i4 = i4 + 1) begin
        om = ONE[AF:0] - al3[i4];
        sd0[i4] = om * a_abs[i4];
    end
end
reg [SD_W-1:0] sd4 [0:K-1];
reg            v4;
integer        r4;
always @(posedge clk) begin
    if (rst) begin
        v4 <= 1'b0;
    end else if (ce) begin
        v4 <= v4a;
        for (r4 = 0; r4 < K; r4 = r4 + 1)
            sd4[r4] <= sd0[r4];
    end
end

// stage 6: the widest spread (a balanced tree of maxima: node i of mt holds the larger of
// nodes 2i and 2i + 1; the leaves KP..2KP-1 are the terms, 0 past K)
localparam KP = 1 << $clog2(K);
reg [SD_W-1:0] mt [1:2*KP-1];
reg [SD_W-1:0] smax0;
integer        i5;
always @* begin
    for (i5 = 0; i5 < KP; i5 = i5 + 1)
        mt[KP + i5] = (i5 < K) ? sd4[i5] : {SD_W{1'b0}};
    for (i5 = KP - 1; i5 >= 1; i5 = i5 - 1)
        mt[i5] = (mt[2*i5] > mt[2*i5 + 1]) ? mt[2*i5] : mt[2*i5 + 1];
    smax0 = mt[1];
end
reg [SD_W-1:0] smax5;
reg            v5;
always @(posedge clk) begin
    if (rst) begin
        v5 <= 1'b0;
    end else if (ce) begin
        v5    <= v4;
        smax5 <= smax0;
    end
end

// stage 7: the product smax FC_KS
reg [SD_W+KS_W-1:0] pr6;
reg                 v6;
always @(posedge clk) begin
    if (rst) begin
        v6 <= 1'b0;
    end else if (ce) begin
        v6  <= v5;
        pr6 <= smax5 * FC_KS[KS_W-1:0];
    end
end

// stage 8: wv = min(shift(pr << n_log2, C0), 2^CAPB)
reg [PW_W-1:0] pw;
reg [PW_W+W_W-1:0] pw_x;  // pw zero-extended: pw_x[W_W-1:0] is in range when PW_W < W_W
reg [W_W-1:0]  wv0;
always @* begin
    pw = {{(PW_W-SD_W-KS_W){1'b0}}, pr6} << n_log2;
    if (C0 >= 0)
        pw = pw << ((C0 >= 0) ? C0 : 0);
    else
        pw = pw >> ((C0 < 0) ? -C0 : 0);
    pw_x = {{W_W{1'b0}}, pw};
    wv0 = (pw_x > CAP_V) ? CAP_V[W_W-1:0] : pw_x[W_W-1:0];
end
reg        v7;
always @(posedge clk) begin
    if (rst) begin
        v7 <= 1'b0;
    end else if (ce) begin
        v7     <= v6;
        wv_out <= wv0;
    end
end
assign out_valid = v7;
// alpha, from stage 4, waits the AL_DLY stages of wv (delay_line)
wire [K*(AF+1)-1:0] al3_v;
genvar go;
generate
    for (go = 0; go < K; go = go + 1) begin : g_out
        assign al3_v[go*(AF+1) +: AF+1] = al3[go];
    end
endgenerate
delay_line #(.W(K*(AF+1)), .N(AL_DLY)) u_dly_alpha (.clk(clk), .rst(rst), .ce(ce), .d_in(al3_v), .d_out(alpha_out));

endmodule

`default_nettype wire
