// fc_weight: frequency clamping for the filter "sat_fc" (docs/filters.md): per pixel, the
// fade alpha_i of each noise term and the filter width wv that the faded terms' spread asks for.
//
// The bit-exact twin of model/hw/golden.py fc_weight(cfg, tex, Jm, je):
//   m     = max_k |Jm_k|                                 (the pixel's footprint in s, J = Jm 2^je)
//   lm    = fc_log2(m) + je 2^LF                        (log2 of it, 2^-LF octaves, LF = FC_LOG_FRAC)
//   lt_i  = fc_log2(max_jk |T_i,jk|) - T_FRAC 2^LF       (log2 of term i's frequency; static)
//   alpha_i = clip(FC_KNEE - lm - lt_i, 0, 2^AF)         (u1.AF, AF = FC_LOG_FRAC + FC_FADE_LOG2)
//           = 2^AF when m = 0, T_i = 0, a_i = 0, i >= k_used or !filter_en (the term unchanged)
//   sd_i  = (2^AF - alpha_i) |a_i|                       (u.{AF + A_FRAC}: the faded part's spread)
//   wv    = min(shift((max_i sd_i) FC_KS 2^n_log2, F_FRAC - AF - A_FRAC - FC_KSF), 2^(W_CAP_LOG2 + F_FRAC))
// with fc_log2(x) = (e << LF) + floor((x - 2^e) 2^LF / 2^e), e = bitlen(x) - 1 (Mitchell's
// piecewise-linear log2, exact at powers of two) and FC_KS = sigma sqrt(12) of the lattice
// noise in u.FC_KSF (model/hw/config.py fc_sigma12: the width of the box with the noise's
// standard deviation). The fade is linear in log2 of the footprint phi_i = max|J| max|T_i|
// (noise cells a pixel): the term is whole up to phi = 2^((FC_KNEE - 2^AF) 2^-LF) and gone
// (its mean, 0) from phi = 2^(FC_KNEE 2^-LF), Gritz's frequency clamping (1998); its
// spread moves into the box width, after Heitz et al. (2013).
//
// Formats: jm_in 6 x s{J_W}.0 (element 2*k + col), je_in s{JE_W}.0; a_all K x s{A_W}.{A_FRAC},
//   t_all K x 9 x s{T_W}.{T_FRAC} (the parameter registers, static during a pass);
//   alpha_out K x u{AF+1}.{AF} (term i at [i*(AF+1) +: AF+1]); wv_out u{W_W}.{F_FRAC} entries.
// Internal: m u{J_W}; lm, lt, the fade argument s{L_W}.{LF} (L_W below bounds every sum);
//   sd u{SD_W}.{AF + A_FRAC}; the scaled width u{PW_W}.
// Pipeline (LATENCY = `LAT_FC_WEIGHT = 7 register stages, one pixel per enabled clock):
//   1  m = max |Jm_k|, je     2  lm (bitlen, shift)     3  alpha_i     4  sd_i
//   5  max_i sd_i             6  its product with FC_KS 7  wv (shifts, saturation); alpha delayed to it
//   (alpha from stage 3 through a 4-stage delay_line)
// The static parts (max|T_i|, then lt_i, |a_i|, t_on_i) are registered functions of the
// parameter registers, updated every clock.
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
    parameter T_FRAC       = 10,
    parameter A_W          = 16,  // amplitudes s{A_W}.{A_FRAC}
    parameter A_FRAC       = 12,
    parameter F_FRAC       = 16,  // w fraction bits (entries)
    parameter W_CAP_LOG2   = 16,  // wv saturates at 2^W_CAP_LOG2 entries
    parameter N_LOG2_MAX   = 8,   // n_log2 0..N_LOG2_MAX
    parameter FC_LOG_FRAC  = 5,   // LF: fraction bits of log2 phi
    parameter FC_KNEE      = 112, // the fade's end, log2 phi in 2^-LF octaves
    parameter FC_FADE_LOG2 = 2,   // the fade spans 2^FC_FADE_LOG2 octaves
    parameter FC_KS        = 328, // sigma sqrt(12) of the lattice noise, u.FC_KSF (the configuration's blend)
    parameter FC_KSF       = 8
) (
    input  wire                              clk,
    input  wire                              rst,
    input  wire                              ce,
    input  wire                              in_valid,
    input  wire [6*J_W-1:0]                  jm_in,
    input  wire [JE_W-1:0]                   je_in,
    input  wire [NOISE_TERMS*A_W-1:0]        a_all,
    input  wire [NOISE_TERMS*9*T_W-1:0]      t_all,
    input  wire [KU_W-1:0]                   k_used,
    input  wire                              filter_en,
    input  wire [NL_W-1:0]                   n_log2,
    output wire                              out_valid,
    output wire [NOISE_TERMS*(AF+1)-1:0]     alpha_out,
    output reg  [W_W-1:0]                    wv_out
);
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
localparam TF_W  = $clog2(T_FRAC + 1);
// L_W: every term of FC_KNEE - lm - lt is below 2^(L_W - 3) in magnitude: |FC_KNEE| < 2^KB_W,
// fc_log2(m) < 2^(JB_W+LF), |je| 2^LF <= 2^(JE_W-1+LF), fc_log2(|T|) < 2^(TB_W+LF), T_FRAC 2^LF < 2^(TF_W+LF)
localparam L_M1  = (KB_W > JB_W + LF) ? KB_W : JB_W + LF;
localparam L_M2  = (L_M1 > JE_W + LF) ? L_M1 : JE_W + LF;
localparam L_M3  = (L_M2 > TB_W + LF) ? L_M2 : TB_W + LF;
localparam L_W   = ((L_M3 > TF_W + LF) ? L_M3 : TF_W + LF) + 3;
localparam SD_W  = AF + A_W;                                // (2^AF - alpha) |a| <= 2^AF 2^(A_W-1)
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

// static: per term tn_i = max_jk |T_i,jk| (a tree of maxima), registered; then from it
// lt_i = fc_log2(tn_i) - T_FRAC 2^LF, whether the term takes part (t_on_i), |a_i|, registered.
// These registers follow the parameter registers every clock (not on ce), two clocks behind;
// a pixel reads them at stage 3, three clocks after it enters at the earliest, and the
// parameters are written before the pass's first pixel enters.
function [T_W-1:0] t_abs;
    input [T_W-1:0] v;
    t_abs = v[T_W-1] ? -v : v;  // |-2^(T_W-1)| = 2^(T_W-1): right as unsigned
endfunction
function [T_W-1:0] t_max;
    input [T_W-1:0] x, y;
    t_max = (x > y) ? x : y;
endfunction
reg [T_W-1:0] tq [0:8];
reg [T_W-1:0] tn_c [0:K-1];
integer       i, j;
always @* begin
    for (i = 0; i < K; i = i + 1) begin
        for (j = 0; j < 9; j = j + 1)
            tq[j] = t_abs(t_all[(9*i + j)*T_W +: T_W]);
        tn_c[i] = t_max(t_max(t_max(tq[0], tq[1]), t_max(tq[2], tq[3])),
                        t_max(t_max(tq[4], tq[5]), t_max(tq[6], tq[7])));
        tn_c[i] = t_max(tn_c[i], tq[8]);
    end
end
reg [K*T_W-1:0] tn;  // tn_i at [i*T_W +: T_W]
integer         ia;
always @(posedge clk) begin
    for (ia = 0; ia < K; ia = ia + 1)
        tn[ia*T_W +: T_W] <= rst ? {T_W{1'b0}} : tn_c[ia];
end
reg signed [L_W-1:0] lt_c    [0:K-1];
reg                  t_on_c  [0:K-1];
reg        [A_W-1:0] a_abs_c [0:K-1];
reg        [A_W-1:0] av;
reg      [TB_W-1:0]  te;    // e = bitlen(tn) - 1 (0 for tn = 0: masked by t_on)
/* verilator lint_off UNUSEDSIGNAL */  // above bit LF: the leading one (and zeros)
reg    [T_W+LF-1:0]  tx;    // floor(tn 2^LF / 2^e) = 2^LF + the fraction
/* verilator lint_on UNUSEDSIGNAL */
wire [K*TB_W-1:0]    tbl;   // bitlen(tn_i)
genvar               gb;
generate
    for (gb = 0; gb < K; gb = gb + 1) begin : g_tbl
        /* verilator lint_off UNUSEDSIGNAL */  // tn = 0 is t_on's test
        wire tnz;
        /* verilator lint_on UNUSEDSIGNAL */
        bitlen #(.W(T_W), .BW(TB_W)) u_bitlen_t (.x(tn[gb*T_W +: T_W]), .bl(tbl[gb*TB_W +: TB_W]), .nz(tnz));
    end
endgenerate
always @* begin
    for (i = 0; i < K; i = i + 1) begin
        te = (tn[i*T_W +: T_W] != 0) ? tbl[i*TB_W +: TB_W] - 1'b1 : {TB_W{1'b0}};
        tx = {tn[i*T_W +: T_W], {LF{1'b0}}} >> te;
        lt_c[i] = $signed({{(L_W-TB_W-LF){1'b0}}, te, tx[LF-1:0]}) - $signed(TF_SH);
        av = a_all[i*A_W +: A_W];
        a_abs_c[i] = av[A_W-1] ? -av : av;
        t_on_c[i]  = (tn[i*T_W +: T_W] != 0) && (av != 0) && (i < k_used);
    end
end
reg signed [L_W-1:0] lt    [0:K-1];
reg                  t_on  [0:K-1];
reg        [A_W-1:0] a_abs [0:K-1];
integer              ip;
always @(posedge clk) begin
    for (ip = 0; ip < K; ip = ip + 1) begin
        if (rst) begin
            lt[ip]    <= {L_W{1'b0}};
            t_on[ip]  <= 1'b0;
            a_abs[ip] <= {A_W{1'b0}};
        end else begin
            lt[ip]    <= lt_c[ip];
            t_on[ip]  <= t_on_c[ip];
            a_abs[ip] <= a_abs_c[ip];
        end
    end
end

// stage 1: m = max |Jm_k| (a tree of maxima)
function [J_W-1:0] j_abs;
    input [J_W-1:0] v;
    j_abs = v[J_W-1] ? -v : v;  // |-2^(J_W-1)| = 2^(J_W-1) as unsigned
endfunction
function [J_W-1:0] j_max;
    input [J_W-1:0] x, y;
    j_max = (x > y) ? x : y;
endfunction
wire [J_W-1:0] m0 = j_max(j_max(j_max(j_abs(jm_in[0*J_W +: J_W]), j_abs(jm_in[1*J_W +: J_W])),
                                j_max(j_abs(jm_in[2*J_W +: J_W]), j_abs(jm_in[3*J_W +: J_W]))),
                          j_max(j_abs(jm_in[4*J_W +: J_W]), j_abs(jm_in[5*J_W +: J_W])));
reg [J_W-1:0]  m1;
reg [JE_W-1:0] je1;
reg            v1;
always @(posedge clk) begin
    if (rst) begin
        v1 <= 1'b0;
    end else if (ce) begin
        v1  <= in_valid;
        m1  <= m0;
        je1 <= je_in;
    end
end

// stage 2: lm = fc_log2(m) + je 2^LF; mz = (m = 0)
wire [JB_W-1:0] mb;
wire            mnz;
bitlen #(.W(J_W), .BW(JB_W)) u_bitlen_m (.x(m1), .bl(mb), .nz(mnz));
reg [JB_W-1:0]       me;
/* verilator lint_off UNUSEDSIGNAL */  // above bit LF: the leading one (and zeros)
reg [J_W+LF-1:0]     mx;    // floor(m 2^LF / 2^e) = 2^LF + the fraction
/* verilator lint_on UNUSEDSIGNAL */
reg signed [L_W-1:0] lm0;
always @* begin
    me  = mnz ? mb - 1'b1 : {JB_W{1'b0}};
    mx  = {m1, {LF{1'b0}}} >> me;
    lm0 = $signed({{(L_W-JB_W-LF){1'b0}}, me, mx[LF-1:0]})
          + $signed({{(L_W-JE_W-LF){je1[JE_W-1]}}, je1, {LF{1'b0}}});
end
reg signed [L_W-1:0] lm2;
reg                  mz2, v2;
always @(posedge clk) begin
    if (rst) begin
        v2 <= 1'b0;
    end else if (ce) begin
        v2  <= v1;
        lm2 <= lm0;
        mz2 <= !mnz;
    end
end

// stage 3: alpha_i = clip(FC_KNEE - lm - lt_i, 0, 2^AF)
reg signed [L_W-1:0] x3;
reg        [AF:0]    al0 [0:K-1];
integer              i3;
always @* begin
    for (i3 = 0; i3 < K; i3 = i3 + 1) begin
        x3 = KNEE_L - lm2 - lt[i3];
        if (mz2 || !filter_en || !t_on[i3])
            al0[i3] = ONE[AF:0];
        else if (x3 <= $signed({L_W{1'b0}}))
            al0[i3] = {(AF+1){1'b0}};
        else if (x3 >= ONE_L)
            al0[i3] = ONE[AF:0];
        else
            al0[i3] = x3[AF:0];
    end
end
reg [AF:0] al3 [0:K-1];
reg        v3;
integer    r3;
always @(posedge clk) begin
    if (rst) begin
        v3 <= 1'b0;
    end else if (ce) begin
        v3 <= v2;
        for (r3 = 0; r3 < K; r3 = r3 + 1)
            al3[r3] <= al0[r3];
    end
end

// stage 4: sd_i = (2^AF - alpha_i) |a_i|
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
        v4 <= v3;
        for (r4 = 0; r4 < K; r4 = r4 + 1)
            sd4[r4] <= sd0[r4];
    end
end

// stage 5: the widest spread (a balanced tree of maxima: node i of mt holds the larger of
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

// stage 6: the product smax FC_KS
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

// stage 7: wv = min(shift(pr << n_log2, C0), 2^CAPB)
reg [PW_W-1:0] pw;
reg [W_W-1:0]  wv0;
always @* begin
    pw = {{(PW_W-SD_W-KS_W){1'b0}}, pr6} << n_log2;
    if (C0 >= 0)
        pw = pw << ((C0 >= 0) ? C0 : 0);
    else
        pw = pw >> ((C0 < 0) ? -C0 : 0);
    wv0 = ({{W_W{1'b0}}, pw} > CAP_V) ? CAP_V[W_W-1:0] : pw[W_W-1:0];
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
// alpha, from stage 3, waits the four stages of wv (delay_line)
wire [K*(AF+1)-1:0] al3_v;
genvar go;
generate
    for (go = 0; go < K; go = go + 1) begin : g_out
        assign al3_v[go*(AF+1) +: AF+1] = al3[go];
    end
endgenerate
delay_line #(.W(K*(AF+1)), .N(4)) u_dly_alpha (.clk(clk), .rst(rst), .ce(ce), .d_in(al3_v), .d_out(alpha_out));

endmodule

`default_nettype wire
