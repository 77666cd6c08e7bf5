// colour_map: RGBA8 of the colour index f box-filtered over the filter width w (paper 3.3);
// the bit-exact twin of model/hw/golden.py colour_map.
//
// Formats (the parameters; derived widths from rtl/tex_widths.vh):
//   f_in   s{F_W}.{F_FRAC}   1.0 = the whole colour table
//   w_in   u{W_W}.{F_FRAC}   colour-table entries; contract: w <= 2^(W_CAP_LOG2 + F_FRAC)
//                            (filter_width saturates there; D_W and X_W are sized for it;
//                            the normalised division's shift is at most W_W - B there)
//   mode   0 mod (f taken mod 1), 1 clamp; filter_en 0: point lookup
//   n_log2 N = 2^n_log2 entries, n_log2 <= N_LOG2_MAX; tables loaded for that N
//   rgba_out RGBA8, channel c at [8c+7:8c] (R = 0, G = 1, B = 2, A = 3)
//
// Computation (docs/numerics.md, "Colour map"):
//   u = (f mod 1) N (mod) or clip(f N, -W/2, N + W/2), W = 2^W_CAP_LOG2 (clamp)
//       [s{U_W}.{F_FRAC} entries; clamp compares f with the thresholds shifted right
//        by n_log2, exact because they are multiples of 2^n_log2]
//   FILTER 1 (sat): a = 2u - w, b = 2u + w (s{X_W}.{F_FRAC+1}), and per channel
//       D = I(b) - I(a) = ((whole + csat[kb-1] - csat[ka-1]) << XF) + fr_b clut[kb] - fr_a clut[ka]
//       (sat_index, sat_integral), whole = (kx_b - kx_a) total (mod: kx = whole tables
//       before x) or kx_b clut[kb] - kx_a clut[ka] (clamp: kx = whole entries past an edge),
//       formed by two KW x QW multipliers in either mode (mod: the bytes of total; QW = 8
//       for N_LOG2_MAX <= 8);
//       computed mod 2^D_W, exact since 0 <= D <= 255 * 2w < 2^D_W;
//       DIV_BITS = 0 (exact): out = floor((D + w) / (2w)) = floor(((D + w) >> 1) / w)
//       by box_divide on u{D_W-1} / u{W_W} (8 quotient bits: D + w <= 511 w < 2^8 * 2w, so
//       out <= 255, never 256);
//       DIV_BITS = B > 0 (normalised; built when B < W_W, else w never has more than B
//       bits and the exact division is built): h(s) = 2^s >> 1,
//         sh0 = bitlen(w >> B), w_r = w + h(sh0), sh = bitlen(w_r >> B) (sh0 or sh0 + 1),
//         den' = w_r >> sh = round(w / 2^sh) (u{B}, >= 2^(B-1) when sh > 0),
//         num' = (D + w + 2 h(sh)) >> (sh + 1) = round(((D + w) / 2) / 2^sh),
//         out = min(floor(num' / den'), 255) by box_divide on u{NQ_W} / u{B}, NQ_W = B + 8
//         (num' < 256 den' for B >= 10: no saturation needed) or B + 9 with SAT (B <= 9:
//         num' < 384 den', quotients up to 383 saturate); sh0, den', sh and w + 2 h(sh) are
//         computed once for the four channels; error <= 1/2 + 513 / 2^(B+1) LSB;
//       w = 0 or filter off: the point lookup clut[k], k = floor(u) mod N or clipped, which
//       is the clut read at window end a when w is forced to 0 (a = b = 2u), fed through the
//       divider as num = clut[k], den = 1 (normalised: sh = 0).
//   FILTER 2 (mip): mip[2N - (2N >> l) + (floor(u) >> l)], l = clip(floor(log2 w), 0,
//       n_log2) (mip_index); filter off: clut[k].
//   FILTER 0 (none): clut[k].
// Only the configured filter is built (generate on FILTER).
//
// Tables (colour_table): loaded by the host through the write port (synchronous,
// independent of ce): wr_table 0 clut, 1 csat (inclusive prefix sums of clut, eq. 13),
// 2 mip (2N - 1 entries, level l at 2N - (2N >> l)); wr_data channel c at
// [c*CSAT_W +: CSAT_W], clut and mip use the low 8 bits of each lane; wr_addr past a table's
// end, wr_table 3 and tables the configuration does not build are ignored. The host computes
// csat and mip (golden build_tables); the RTL equals golden for tables so built.
// Storage: sat 32 2^NMAX + 4 CSAT_W 2^NMAX bits (full, reduced: 24576; plus the whole-table
// sum csat[N - 1], the last csat entry written, as 4 CSAT_W = 64 flip-flops: write csat in
// ascending order), mip 32 2^NMAX +
// 32 (2^(NMAX+1) - 1) (24544), none 32 2^NMAX (8192).
//
// Pipeline (sat): 1 u | 2 a, b | 3 sat_index x2 | 4 colour_table reads, multiplier operands
// | 5 sat_integral x2 (normalised: with sh0, den', sh, w + 2 h(sh) from w) | 6 numerator
// (D + w) >> 1 (normalised: (D + w + 2 h(sh)) >> (sh + 1)), divisor | 7..14 box_divide (one
// quotient bit per stage). mip/none: 1 u | 2-3 mip_index | 4 table reads | 5 select | 6..14
// delay line.
// FPGA_REGS = 1 ([fpga_regs]) adds five register stages (P below): stage 1 in two (1a:
// the clamp thresholds and the shifted f, registered; 1b: the comparisons); N - 1 decoded from
// n_log2 in stage 2 and registered for sat_index (no extra stage); the table outputs
// registered before the multipliers (4b: the block RAM's clock-to-out off the multiplier
// path; the multipliers' q operands selected before it); sat_integral's products registered
// before their sums (5a), beside them the normalisation split in two (5a: sh0 = bitlen(w >>
// B); 5b: den', sh, w + 2 h(sh)); stage 6 in three (6a: D per channel; 6b: + w (+ 2 h(sh)),
// registered; 6c: the shift and the operand select; the exact division registers its
// operands in 6c). mip/none: the delay line is five stages longer.
// Latency `LAT_COLOUR_MAP = 14 (FPGA_REGS: `LAT_COLOUR_MAP_FPGA = 19) register stages;
// throughput one pixel per enabled clock.
// Reset (synchronous, active high) clears the valid chain and rgba_out (no X after reset);
// rgba_out loads only with a valid result.
// Written for event-driven simulation speed: combinational logic in one always @* per
// stage, one clocked process per stage group, no bus driven piecewise.

`default_nettype none

`include "tex_latency.vh"

module colour_map #(
    // formats and modes (config/<name>.toml keys in brackets); every internal width is
    // derived from them below (rtl/tex_widths.vh, the twin of model/hw/config.py)
    parameter F_W        = 42,  // f_in word width (texture_pipeline: the exact sum's)
    parameter F_FRAC     = 16,  // [f_frac] fraction bits of f and w
    parameter W_CAP_LOG2 = 16,  // [w_cap_log2] w saturates at 2^W_CAP_LOG2 entries
    parameter N_LOG2_MAX = 8,   // [n_log2_max] log2 of the largest colour table (>= 1)
    parameter FILTER     = 1,   // [filter] 0 none (point lookup), 1 sat, 2 mip
    parameter DIV_BITS   = 0,   // [div_bits] box-filter division: 0 exact, B > 0 on B-bit w
    parameter FPGA_REGS  = 0    // [fpga_regs] 1: the four extra register stages above
) (clk, rst, ce, in_valid, f_in, w_in, mode, n_log2, filter_en, wr_en, wr_table, wr_addr, wr_data,
   out_valid, rgba_out);

`include "tex_widths.vh"

localparam FF     = F_FRAC;
localparam W_W    = W_CAP_LOG2 + F_FRAC + 1;                       // w
localparam U_W    = tw_u_w(N_LOG2_MAX, F_FRAC, W_CAP_LOG2);        // u = f N (signed)
localparam X_W    = tw_x_w(N_LOG2_MAX, F_FRAC, W_CAP_LOG2);        // window ends (signed)
localparam XF     = F_FRAC + 1;                                    // their fraction bits
localparam CS_W   = tw_csat_w(N_LOG2_MAX);                         // summed-area channel
localparam D_W    = tw_d_w(F_FRAC, W_CAP_LOG2);                    // D = I(b) - I(a)
localparam NMAX   = N_LOG2_MAX;
localparam NL_W   = tw_bits_unsigned(N_LOG2_MAX);                  // n_log2
localparam WCAP   = W_CAP_LOG2;

input  wire                 clk;
input  wire                 rst;
input  wire                 ce;
input  wire                 in_valid;
input  wire [F_W-1:0]       f_in;       // signed
input  wire [W_W-1:0]       w_in;
input  wire                 mode;       // 0 mod, 1 clamp
input  wire [NL_W-1:0]      n_log2;
input  wire                 filter_en;
// table write port
input  wire                 wr_en;
input  wire [1:0]           wr_table;   // 0 clut, 1 csat, 2 mip
input  wire [NMAX:0]        wr_addr;
input  wire [4*CS_W-1:0]    wr_data;
output wire                 out_valid;
output wire [31:0]          rgba_out;

localparam LAT    = FPGA_REGS ? `LAT_COLOUR_MAP_FPGA : `LAT_COLOUR_MAP;
localparam P      = FPGA_REGS ? 1 : 0;  // each optional register stage (delay_line of P stages)

localparam KW     = X_W - XF;           // entry index of a window end (signed)
localparam TW     = D_W - XF;           // whole-entry part of D
localparam QW     = (CS_W - 8 > 8) ? CS_W - 8 : 8;  // multiplier operand: a byte of total, or clut
localparam GUARD  = WCAP + FF - 1;      // clamp guard W/2 = 2^GUARD (units 2^-FF entries)
localparam CW     = (F_W > U_W) ? F_W : U_W;  // clamp comparison width

// box-filter division (sat): exact (DIV_BITS = 0, or >= W_W: w never has more bits), or on
// w normalised to B = DIV_BITS significant bits
localparam NORM   = (FILTER == 1) && (DIV_BITS > 0) && (DIV_BITS < W_W);
localparam B      = NORM ? DIV_BITS : 1;
localparam HW     = W_W - B;            // high bits of w: sh0 = bitlen(w >> B), 0..HW
localparam SH_W   = $clog2(HW + 2);     // sh = sh0 or sh0 + 1, 0..HW + 1
localparam SAT    = (B <= 9) ? 1 : 0;   // num' / den' reaches 256 only for B <= 9
localparam NQ_W   = B + 8 + SAT;        // num' < 256 den' (B >= 10), < 384 den' (B <= 9)

// elaboration fails (unknown module) on an unsupported configuration
generate
    if (NORM && NQ_W > D_W - 1) begin : g_bad_params
        colour_map_unsupported_div_bits u_error ();
    end
endgenerate

// ---------------------------------------------------------------------------
// Stage 1: u (FPGA_REGS: in two, 1a the thresholds and shifted values, registered; 1b the
// comparisons and the selection)

reg [CW-1:0]  f_c;       // f sign-extended to CW
reg [CW-1:0]  gsh;       // guard >> n_log2
reg [CW-1:0]  lo_thr;    // -(guard >> n_log2)
reg [CW-1:0]  hi_thr;    // 1.0 + (guard >> n_log2)
reg [U_W-1:0] guard_u;   // guard
reg [U_W-1:0] n_u;       // N << FF
reg [U_W-1:0] u_mod;
reg [U_W-1:0] u_sh;      // f N (clamp, between the thresholds)

always @* begin
    f_c = {CW{f_in[F_W-1]}};
    f_c[F_W-1:0] = f_in;
    gsh = {CW{1'b0}};
    gsh[GUARD] = 1'b1;
    gsh = gsh >> n_log2;
    lo_thr = -gsh;
    hi_thr = {CW{1'b0}};
    hi_thr[FF] = 1'b1;
    hi_thr = hi_thr + gsh;
    guard_u = {U_W{1'b0}};
    guard_u[GUARD] = 1'b1;
    n_u = {U_W{1'b0}};
    n_u[FF] = 1'b1;
    n_u = n_u << n_log2;
    // mod: (f mod 1) N
    u_mod = {U_W{1'b0}};
    u_mod[FF-1:0] = f_in[FF-1:0];
    u_mod = u_mod << n_log2;
    u_sh = f_c[U_W-1:0] << n_log2;
end

// FPGA_REGS: stage 1a's values and the inputs stage 1b reads, registered
wire            in_valid_i;
/* verilator lint_off UNUSEDSIGNAL */  // without FPGA_REGS stage 1 compares f_c itself
wire [CW-1:0]   f_i, lo_thr_i, hi_thr_i;
wire [U_W-1:0]  n_u_i, u_sh_i;
/* verilator lint_on UNUSEDSIGNAL */
wire [U_W-1:0]  u_mod_i;
wire [W_W-1:0]  w_i;
wire            mode_i;
wire [NL_W-1:0] n_log2_i;
wire            filter_en_i;
delay_line #(.W(1), .N(P), .CLEAR(1)) u_dly_iv (.clk(clk), .rst(rst), .ce(ce), .d_in(in_valid), .d_out(in_valid_i));
// (two lines: stage 1b reads only the first, whose words all change together)
delay_line #(.W(3*CW + 3*U_W), .N(P)) u_dly_1a (.clk(clk), .rst(rst), .ce(ce),
    .d_in({f_c, lo_thr, hi_thr, n_u, u_mod, u_sh}), .d_out({f_i, lo_thr_i, hi_thr_i, n_u_i, u_mod_i, u_sh_i}));
delay_line #(.W(W_W + 2 + NL_W), .N(P)) u_dly_1i (.clk(clk), .rst(rst), .ce(ce),
    .d_in({w_in, mode, filter_en, n_log2}), .d_out({w_i, mode_i, filter_en_i, n_log2_i}));

reg [U_W-1:0] u_clamp;
// clamp: clip(f N, -guard, N + guard); f N < -guard iff f < -(guard >> n_log2), and
// f N > N + guard iff f > 1.0 + (guard >> n_log2); in between f N fits U_W bits
generate
    if (P != 0) begin : g_1b
        always @* begin
            if ($signed(f_i) < $signed(lo_thr_i))
                u_clamp = -guard_u;
            else if ($signed(f_i) > $signed(hi_thr_i))
                u_clamp = n_u_i + guard_u;
            else
                u_clamp = u_sh_i;
        end
    end else begin : g_1
        // in stage 1's own always @* (the same comparisons, one block a clock)
        always @* begin
            if ($signed(f_c) < $signed(lo_thr))
                u_clamp = -guard_u;
            else if ($signed(f_c) > $signed(hi_thr))
                u_clamp = n_u + guard_u;
            else
                u_clamp = u_sh;
        end
    end
endgenerate

reg             s1_valid_reg;
reg [U_W-1:0]   s1_u_reg;
reg [W_W-1:0]   s1_w_reg;          // w, 0 when the filter is off
reg             s1_mode_reg;
reg [NL_W-1:0]  s1_n_log2_reg;

always @(posedge clk) begin
    if (rst)
        s1_valid_reg <= 1'b0;
    else if (ce)
        s1_valid_reg <= in_valid_i;
    if (ce) begin
        s1_u_reg         <= mode_i ? u_clamp : u_mod_i;
        s1_w_reg         <= filter_en_i ? w_i : {W_W{1'b0}};  // filter off: w = 0
        s1_mode_reg      <= mode_i;
        s1_n_log2_reg    <= n_log2_i;
    end
end

// ---------------------------------------------------------------------------
// Filter

generate
    if (FILTER == 1) begin : g_sat
        // ---- stage 2: window ends a = 2u - w, b = 2u + w (filter off: w = 0, a = b = 2u)
        reg [X_W-1:0] u2;
        reg [X_W-1:0] w_x;
        always @* begin
            u2 = {X_W{s1_u_reg[U_W-1]}};
            u2[U_W:1] = s1_u_reg;
            u2[0] = 1'b0;
            w_x = {X_W{1'b0}};
            w_x[W_W-1:0] = s1_w_reg;
        end

        // the registers of stages 2..6 (loaded by one clocked process below)
        reg [4:0]       sv_reg;         // valid of stage s (2..6) at bit s - 2
        reg [X_W-1:0]   s2_a_reg;
        reg [X_W-1:0]   s2_b_reg;
        reg [W_W-1:0]   s2_w_reg;
        reg             s2_mode_reg;
        reg [NL_W-1:0]  s2_n_log2_reg;
        reg [NMAX-1:0]  s2_nm1_reg;     // FPGA_REGS: N - 1 for sat_index (else not read)

        // ---- stage 3: table addresses and weights of both ends
        wire [NMAX-1:0] kk_a, kk_b, km1_a, km1_b;
        wire            first_a, first_b;
        wire [XF-1:0]   fr_a, fr_b;
        wire [KW-1:0]   kx_a, kx_b;

        sat_index #(.X_W(X_W), .XF(XF), .NMAX(NMAX), .NL_W(NL_W), .NM1_IN(FPGA_REGS)) u_index_a (
            .clk(clk), .ce(ce), .x_in(s2_a_reg), .mode(s2_mode_reg), .n_log2(s2_n_log2_reg),
            .nm1_in(s2_nm1_reg), .kk_out(kk_a), .km1_out(km1_a), .first_out(first_a), .fr_out(fr_a), .kx_out(kx_a)
        );
        sat_index #(.X_W(X_W), .XF(XF), .NMAX(NMAX), .NL_W(NL_W), .NM1_IN(FPGA_REGS)) u_index_b (
            .clk(clk), .ce(ce), .x_in(s2_b_reg), .mode(s2_mode_reg), .n_log2(s2_n_log2_reg),
            .nm1_in(s2_nm1_reg), .kk_out(kk_b), .km1_out(km1_b), .first_out(first_b), .fr_out(fr_b), .kx_out(kx_b)
        );

        reg [W_W-1:0]   s3_w_reg;
        reg             s3_mode_reg;
        reg [NL_W-1:0]  s3_n_log2_reg;

        // ---- stage 4: table reads; multiplier operands of the whole-entry terms:
        // clamp: kx_a (times clut[ka]), kx_b (times clut[kb]);
        // mod:   dw = kx_b - kx_a >= 0 whole tables (times the two bytes of total)
        wire [31:0]       clut_a, clut_b;
        wire [4*CS_W-1:0] csat_a, csat_b, total;
        /* verilator lint_off UNUSEDSIGNAL */
        wire [31:0]       unused_mip_data;
        /* verilator lint_on UNUSEDSIGNAL */

        colour_table #(.FILTER(FILTER), .NMAX(NMAX), .CS_W(CS_W), .NL_W(NL_W)) u_table (
            .clk(clk), .ce(ce),
            .wr_en(wr_en), .wr_table(wr_table), .wr_addr(wr_addr), .wr_data(wr_data),
            .clut_addr_a(kk_a), .clut_addr_b(kk_b), .csat_addr_a(km1_a), .csat_addr_b(km1_b),
            .n_log2(s3_n_log2_reg), .mip_addr({(NMAX+1){1'b0}}),
            .clut_a(clut_a), .clut_b(clut_b), .csat_a(csat_a), .csat_b(csat_b), .total(total),
            .mip_data(unused_mip_data)
        );

        reg [W_W-1:0]   s4_w_reg;
        reg             s4_mode_reg;
        reg [KW-1:0]    s4_k_a_reg, s4_k_b_reg;
        reg [XF-1:0]    s4_fr_a_reg, s4_fr_b_reg;
        reg             s4_first_a_reg, s4_first_b_reg;

        // ---- stage 4b (FPGA_REGS): the table outputs and stage 4's registers registered
        // again (x: P stages after the read; y: 2P, beside sat_integral's products)
        wire [31:0]       clut_ax, clut_bx, clut_ay;
        wire [4*CS_W-1:0] csat_ax, csat_bx;
        wire [W_W-1:0]    s4x_w, s4y_w;
        wire              s4x_mode, s4y_mode;
        wire [KW-1:0]     s4x_k_a, s4x_k_b;
        wire [XF-1:0]     s4x_fr_a, s4x_fr_b;
        wire              s4x_first_a, s4x_first_b;
        delay_line #(.W(64 + 8*CS_W), .N(P)) u_dly_tbl (.clk(clk), .rst(rst), .ce(ce),
            .d_in({clut_a, clut_b, csat_a, csat_b}), .d_out({clut_ax, clut_bx, csat_ax, csat_bx}));
        delay_line #(.W(W_W + 3 + 2*KW + 2*XF), .N(P)) u_dly_s4 (.clk(clk), .rst(rst), .ce(ce),
            .d_in({s4_w_reg, s4_mode_reg, s4_k_a_reg, s4_k_b_reg, s4_fr_a_reg, s4_fr_b_reg, s4_first_a_reg,
                   s4_first_b_reg}),
            .d_out({s4x_w, s4x_mode, s4x_k_a, s4x_k_b, s4x_fr_a, s4x_fr_b, s4x_first_a, s4x_first_b}));
        delay_line #(.W(32 + W_W + 1), .N(P)) u_dly_s4y (.clk(clk), .rst(rst), .ce(ce),
            .d_in({clut_ax, s4x_w, s4x_mode}), .d_out({clut_ay, s4y_w, s4y_mode}));

        // ---- stage 5: partial integrals and whole-entry products of both ends
        // q operands: clamp clut[ka], clut[kb]; mod total >> 8 (a), total mod 2^8 (b); selected
        // from the table outputs themselves (FPGA_REGS: then registered in stage 4b with them,
        // so that the selection is off the multipliers' path)
        reg [4*QW-1:0] q_a_n, q_b_n;
        reg [QW-1:0]   qa, qb;
        integer        qc;
        always @* begin
            q_a_n = {(4*QW){1'b0}};
            q_b_n = {(4*QW){1'b0}};
            for (qc = 0; qc < 4; qc = qc + 1) begin
                qa = {QW{1'b0}};
                qb = {QW{1'b0}};
                if (s4_mode_reg) begin
                    qa[7:0] = clut_a[8*qc +: 8];
                    qb[7:0] = clut_b[8*qc +: 8];
                end else begin
                    qa[CS_W-9:0] = total[qc*CS_W+8 +: CS_W-8];
                    qb[7:0]      = total[qc*CS_W +: 8];
                end
                q_a_n[qc*QW +: QW] = qa;
                q_b_n[qc*QW +: QW] = qb;
            end
        end
        wire [4*QW-1:0] q_a, q_b;
        delay_line #(.W(8*QW), .N(P)) u_dly_q (.clk(clk), .rst(rst), .ce(ce), .d_in({q_a_n, q_b_n}),
                                               .d_out({q_a, q_b}));

        wire [4*D_W-1:0] p_a, p_b;
        wire [4*TW-1:0]  e_a, e_b;

        sat_integral #(.XF(XF), .KW(KW), .QW(QW), .CS_W(CS_W), .D_W(D_W), .PIPE(P)) u_integral_a (
            .clk(clk), .ce(ce), .c_in(clut_ax), .before_in(csat_ax), .first_in(s4x_first_a),
            .fr_in(s4x_fr_a), .k_in(s4x_k_a), .q_in(q_a), .p_out(p_a), .e_out(e_a)
        );
        sat_integral #(.XF(XF), .KW(KW), .QW(QW), .CS_W(CS_W), .D_W(D_W), .PIPE(P)) u_integral_b (
            .clk(clk), .ce(ce), .c_in(clut_bx), .before_in(csat_bx), .first_in(s4x_first_b),
            .fr_in(s4x_fr_b), .k_in(s4x_k_b), .q_in(q_b), .p_out(p_b), .e_out(e_b)
        );

        reg             s5_mode_reg;
        reg [31:0]      s5_point_reg;   // clut[ka]: the point lookup when w = 0

        // divider operands of stage 6: exact (num (D_W-1)-bit, den = w) or normalised (num'
        // NQ_W-bit, den' B-bit); each branch below drives them (whole, from one always @*)
        localparam NUM_DW = NORM ? NQ_W : D_W - 1;
        localparam DEN_DW = NORM ? B : W_W;
        wire [4*NUM_DW-1:0] num;
        wire [DEN_DW-1:0]   den;

        reg [4*NUM_DW-1:0]  s6_num_reg;
        reg [DEN_DW-1:0]    s6_den_reg;

        // ---- stages 2..6 registers
        always @(posedge clk) begin
            if (rst)
                sv_reg <= 5'b00000;
            else if (ce)
                sv_reg <= {sv_reg[3:0], s1_valid_reg};
            if (ce) begin
                // stage 2
                s2_a_reg       <= u2 - w_x;
                s2_b_reg       <= u2 + w_x;
                s2_w_reg       <= s1_w_reg;
                s2_mode_reg    <= s1_mode_reg;
                s2_n_log2_reg  <= s1_n_log2_reg;
                s2_nm1_reg     <= ~({NMAX{1'b1}} << s1_n_log2_reg);
                // stage 3
                s3_w_reg       <= s2_w_reg;
                s3_mode_reg    <= s2_mode_reg;
                s3_n_log2_reg  <= s2_n_log2_reg;
                // stage 4 (mod: dw = kx_b - kx_a on both ends)
                s4_w_reg       <= s3_w_reg;
                s4_mode_reg    <= s3_mode_reg;
                s4_k_a_reg     <= s3_mode_reg ? kx_a : kx_b - kx_a;
                s4_k_b_reg     <= s3_mode_reg ? kx_b : kx_b - kx_a;
                s4_fr_a_reg    <= fr_a;
                s4_fr_b_reg    <= fr_b;
                s4_first_a_reg <= first_a;
                s4_first_b_reg <= first_b;
                // stage 5
                s5_mode_reg    <= s4y_mode;
                s5_point_reg   <= clut_ay;
                // stage 6
                s6_num_reg     <= num;
                s6_den_reg     <= den;
            end
        end

        // ---- stage 6a: D = (whole << XF) + p_b - p_a per channel (mod 2^D_W), whole = e_b - e_a
        // (clamp) or e_b + (e_a << 8) (mod); FPGA_REGS: registered (6a), with the point
        // lookup's clut[k], before stage 6b adds w and selects the divider operands
        // D of channel c (one function for both forms: stage 6a, or inside stage 6's always @*)
        function [D_W-1:0] d_of;
            input          mode_c;
            input [TW-1:0] ea, eb;
            input [D_W-1:0] pa, pb;
            reg   [TW-1:0] ea_x;   // e_a (clamp: negated) or e_a << 8 (mod)
            reg   [TW-1:0] whole;  // whole entries of D, mod 2^TW
            begin
                ea_x  = mode_c ? -ea : ea << 8;
                whole = eb + ea_x;
                d_of  = {whole, {XF{1'b0}}} + pb - pa;
            end
        endfunction
        // the same D mod 2^D_W for stage 6a with FPGA_REGS, two carry chains deep instead of
        // four: both whole forms side by side (e_b - e_a, e_b + (e_a << 8)) and p_b - p_a beside
        // them, then one sum
        function [D_W-1:0] d_of_par;
            input          mode_c;
            input [TW-1:0] ea, eb;
            input [D_W-1:0] pa, pb;
            reg   [TW-1:0] whole;
            reg   [D_W-1:0] pd;
            begin
                whole    = mode_c ? eb - ea : eb + (ea << 8);
                pd       = pb - pa;
                d_of_par = {whole, {XF{1'b0}}} + pd;
            end
        endfunction
        wire [4*D_W-1:0] d_6;      // FPGA_REGS: D of the four channels, registered (else 0)
        // (without FPGA_REGS these stage-6a words are constant 0 and stage 6 reads the stage-5
        // registers themselves: an always @* reading a register and a delayed copy of another
        // would run twice a clock in an event-driven simulator)
        wire [31:0]      point_6;
        if (P != 0) begin : g_6a
            reg [4*D_W-1:0] d_all;
            integer         c6;
            always @* begin
                for (c6 = 0; c6 < 4; c6 = c6 + 1)
                    d_all[c6*D_W +: D_W] = d_of_par(s5_mode_reg, e_a[c6*TW +: TW], e_b[c6*TW +: TW], p_a[c6*D_W +: D_W],
                                                p_b[c6*D_W +: D_W]);
            end
            delay_line #(.W(4*D_W + 32), .N(1)) u_dly_d (.clk(clk), .rst(rst), .ce(ce), .d_in({d_all, s5_point_reg}),
                                                        .d_out({d_6, point_6}));
        end else begin : g_no6a
            assign d_6     = {(4*D_W){1'b0}};
            assign point_6 = 32'd0;
        end

        if (!NORM) begin : g_exact
            // ---- exact division (DIV_BITS = 0): the divisor is w itself
            reg [W_W-1:0] s5_w_reg;
            always @(posedge clk) begin
                if (ce)
                    s5_w_reg <= s4y_w;
            end

            // ---- stage 6(b): divider operands; num = (D + w) >> 1, den = w, or clut[k] / 1
            wire [W_W-1:0]      w_6;   // FPGA_REGS: w registered with D (6a); else 0, w is s5_w_reg
            if (P != 0) begin : g_w6
                delay_line #(.W(W_W), .N(1)) u_dly_w6 (.clk(clk), .rst(rst), .ce(ce), .d_in(s5_w_reg), .d_out(w_6));
            end else begin : g_now6
                assign w_6 = {W_W{1'b0}};
            end
            reg  [W_W-1:0]      w_s;   // w at stage 6(b)
            reg  [31:0]         pt_s;  // clut[k] at stage 6(b)
            reg                 w_zero;
            reg  [D_W-1:0]      d_w;    // w zero-extended
            reg  [W_W-1:0]      den_x;
            reg  [4*(D_W-1)-1:0] num_x;
            integer             c;
            // D + w (< 2^D_W); floor((D + w) / 2w) = floor(((D + w) >> 1) / w): the LSB of
            // D + w is not needed
            /* verilator lint_off UNUSEDSIGNAL */
            reg  [D_W-1:0]      sum;
            /* verilator lint_on UNUSEDSIGNAL */
            reg  [D_W-2:0]      pt;     // clut[k] zero-extended
            always @* begin
                w_s  = (P != 0) ? w_6 : s5_w_reg;
                pt_s = (P != 0) ? point_6 : s5_point_reg;
                w_zero = (w_s == {W_W{1'b0}});
                d_w = {D_W{1'b0}};
                d_w[W_W-1:0] = w_s;
                den_x = w_s;
                if (w_zero)
                    den_x[0] = 1'b1;
                for (c = 0; c < 4; c = c + 1) begin
                    sum = (P != 0 ? d_6[c*D_W +: D_W]
                                  : d_of(s5_mode_reg, e_a[c*TW +: TW], e_b[c*TW +: TW], p_a[c*D_W +: D_W],
                                         p_b[c*D_W +: D_W])) + d_w;
                    pt = {(D_W-1){1'b0}};
                    pt[7:0] = pt_s[8*c +: 8];
                    num_x[c*(D_W-1) +: D_W-1] = w_zero ? pt : sum[D_W-1:1];
                end
            end
            // FPGA_REGS: stage 6c (the normalised branch's shift stage) as a register of the
            // operands, so that both divisions have the block's one latency
            delay_line #(.W(4*(D_W-1) + W_W), .N(P)) u_dly_6c (.clk(clk), .rst(rst), .ce(ce),
                .d_in({num_x, den_x}), .d_out({num, den}));

        end else begin : g_norm
            // ---- normalised division (B = DIV_BITS > 0), docs/numerics.md "Colour map":
            //   sh0 = bitlen(w >> B); t = w >> (sh0 - 1) (B + 1 bits; {w, 0} when sh0 = 0)
            //   den' = round(w / 2^sh0) = (t + 1) >> 1, or, when t is all ones (the rounding
            //   carries to 2^B), den' = 2^(B-1) with sh = sh0 + 1; else sh = sh0
            //   num' = (D + w + 2 h(sh)) >> (sh + 1), h(s) = 2^s >> 1 (half of the dropped LSB)
            // stage 5: sh, den' and w + 2 h(sh) from w, once for the four channels

            // FPGA_REGS: sh0 and the two candidates of 2 h(sh), h_0 = 2^sh0 (0 when sh0 = 0)
            // and h_1 = 2^(sh0 + 1), registered (5a), beside sat_integral's products; w is s4y_w
            // (without: sh0 in the stage-5 always @* below, these are constant 0)
            wire [SH_W-1:0] sh0_y;
            wire [W_W:0]    h_0y, h_1y;
            if (P != 0) begin : g_5a
                reg [SH_W-1:0] sh0;    // bitlen(w >> B): leading-one detector on the HW high bits
                reg [W_W:0]    h_0, h_1;
                integer        i;
                always @* begin
                    sh0 = {SH_W{1'b0}};
                    for (i = 0; i < HW; i = i + 1)
                        if (s4x_w[B + i])
                            sh0 = i[SH_W-1:0] + {{(SH_W-1){1'b0}}, 1'b1};
                    h_0 = {{W_W{1'b0}}, 1'b1} << sh0;
                    if (sh0 == {SH_W{1'b0}})
                        h_0 = {(W_W+1){1'b0}};
                    h_1 = {{(W_W-1){1'b0}}, 2'b10} << sh0;
                end
                delay_line #(.W(SH_W + 2*W_W + 2), .N(1)) u_dly_sh0 (.clk(clk), .rst(rst), .ce(ce),
                    .d_in({sh0, h_0, h_1}), .d_out({sh0_y, h_0y, h_1y}));
            end else begin : g_no5a
                assign sh0_y = {SH_W{1'b0}};
                assign h_0y  = {(W_W+1){1'b0}};
                assign h_1y  = {(W_W+1){1'b0}};
            end
            reg [SH_W-1:0] sh0_v;  // sh0 (FPGA_REGS: from stage 5a)
            integer        i5;
            // 2w >> sh0: < 2^(B+1), bits B..0 are t (bitlen(w) <= B + sh0)
            /* verilator lint_off UNUSEDSIGNAL */
            reg [W_W:0]    w2s;
            /* verilator lint_on UNUSEDSIGNAL */
            reg [B:0]      t;
            reg            ovf;    // t all ones: w rounds up to 2^B at shift sh0
            reg [B-1:0]    den_n;  // den' = round(w / 2^sh)
            reg [SH_W-1:0] sh;
            reg [W_W:0]    h2;     // 2 h(sh): 2^sh, 0 when sh = 0
            // FPGA_REGS: w + 2 h(sh) from the two candidates sh = sh0 and sh0 + 1, formed
            // beside the shift that decides between them (the same value)
            reg [W_W:0]    wn_0, wn_1, wn_f;
            always @* begin
                if (P != 0) begin
                    sh0_v = sh0_y;
                end else begin
                    sh0_v = {SH_W{1'b0}};
                    for (i5 = 0; i5 < HW; i5 = i5 + 1)
                        if (s4y_w[B + i5])
                            sh0_v = i5[SH_W-1:0] + {{(SH_W-1){1'b0}}, 1'b1};
                end
                w2s = {s4y_w, 1'b0} >> sh0_v;
                t = w2s[B:0];
                ovf = &t;
                den_n = t[B:1] + {{(B-1){1'b0}}, t[0]};
                if (ovf) begin
                    den_n = {B{1'b0}};
                    den_n[B-1] = 1'b1;
                end
                sh = sh0_v + {{(SH_W-1){1'b0}}, ovf};
                h2 = {{W_W{1'b0}}, 1'b1} << sh;
                if (sh == {SH_W{1'b0}})
                    h2 = {(W_W+1){1'b0}};
                wn_0 = {1'b0, s4y_w} + h_0y;
                wn_1 = {1'b0, s4y_w} + h_1y;
                wn_f = ovf ? wn_1 : wn_0;
            end

            reg [B-1:0]    s5_den_reg;
            reg [SH_W-1:0] s5_sh_reg;
            reg [W_W:0]    s5_wn_reg;   // w + 2 h(sh) (< 2^(W_W+1)); 0 iff w = 0

            always @(posedge clk) begin
                if (ce) begin
                    s5_den_reg <= den_n;
                    s5_sh_reg  <= sh;
                    s5_wn_reg  <= FPGA_REGS ? wn_f : {1'b0, s4y_w} + h2;
                end
            end

            // ---- stage 6(b): num' = (D + w + 2 h(sh)) >> (sh + 1) (< 2^NQ_W), den' (w = 0:
            // clut[k] / 1), with D from stage 6a
            wire [B-1:0]        den_6;
            wire [SH_W-1:0]     sh_6;
            wire [W_W:0]        wn_6;
            // FPGA_REGS: registered with D (6a); else 0, stage 6 reads the stage-5 registers
            if (P != 0) begin : g_n6
                delay_line #(.W(B + SH_W + W_W + 1), .N(1)) u_dly_n6 (.clk(clk), .rst(rst), .ce(ce),
                    .d_in({s5_den_reg, s5_sh_reg, s5_wn_reg}), .d_out({den_6, sh_6, wn_6}));
            end else begin : g_non6
                assign den_6 = {B{1'b0}};
                assign sh_6  = {SH_W{1'b0}};
                assign wn_6  = {(W_W+1){1'b0}};
            end
            reg  [B-1:0]        den_s;
            reg  [SH_W-1:0]     sh_s;
            reg  [W_W:0]        wn_s;
            reg  [31:0]         pt_s;
            reg                 w_zero;
            reg  [D_W-1:0]      d_wn;   // w + 2 h(sh) zero-extended
            reg  [B-1:0]        den_x;
            /* verilator lint_off UNUSEDSIGNAL */  // FPGA_REGS: stage 6c forms num from the sums
            reg  [4*NQ_W-1:0]   num_x;
            /* verilator lint_on UNUSEDSIGNAL */
            integer             c;
            // dd = D (< 2^D_W, computed mod 2^D_W); sum = D + w + 2 h(sh), one bit wider: with
            // B = 1, 2 h(sh) reaches w (w = 2^sh), and D + 2w of a whole 255-valued window is
            // 2^D_W (the make-fit sweep found it); its LSB is below the rounding; nsh = sum >>
            // (sh + 1) < 2^NQ_W (num' < 256 den', or 384 den' with SAT: docs/numerics.md),
            // its high bits are zero
            reg  [D_W-1:0]      dd;
            /* verilator lint_off UNUSEDSIGNAL */
            reg  [D_W:0]        sum;
            reg  [D_W-1:0]      nsh;
            /* verilator lint_on UNUSEDSIGNAL */
            reg  [NQ_W-1:0]     pt;     // clut[k] zero-extended
            // FPGA_REGS: the sums (and the words stage 6c reads) of the four channels, registered
            // (else not read)
            /* verilator lint_off UNUSEDSIGNAL */
            reg  [4*(D_W+1)-1:0] sum_all;
            reg  [4*NQ_W-1:0]    pt_all;
            /* verilator lint_on UNUSEDSIGNAL */
            always @* begin
                den_s = (P != 0) ? den_6 : s5_den_reg;
                sh_s  = (P != 0) ? sh_6 : s5_sh_reg;
                wn_s  = (P != 0) ? wn_6 : s5_wn_reg;
                pt_s  = (P != 0) ? point_6 : s5_point_reg;
                w_zero = (wn_s == {(W_W+1){1'b0}});
                d_wn = {D_W{1'b0}};
                d_wn[W_W:0] = wn_s;
                den_x = den_s;   // 0 when w = 0
                if (w_zero)
                    den_x[0] = 1'b1;
                for (c = 0; c < 4; c = c + 1) begin
                    dd = (P != 0) ? d_6[c*D_W +: D_W]
                                  : d_of(s5_mode_reg, e_a[c*TW +: TW], e_b[c*TW +: TW], p_a[c*D_W +: D_W],
                                         p_b[c*D_W +: D_W]);
                    sum = {1'b0, dd} + {1'b0, d_wn};
                    nsh = sum[D_W:1] >> sh_s;
                    pt = {NQ_W{1'b0}};
                    pt[7:0] = pt_s[8*c +: 8];
                    num_x[c*NQ_W +: NQ_W] = w_zero ? pt : nsh[NQ_W-1:0];
                    sum_all[c*(D_W+1) +: D_W+1] = sum;
                    pt_all[c*NQ_W +: NQ_W] = pt;
                end
            end
            if (P != 0) begin : g_6c
                // ---- stage 6c (FPGA_REGS): the sums registered with sh, w = 0 and den'; then
                // the shift and the operand select (the adder and the shifter on two clocks)
                wire [4*(D_W+1)-1:0] sum_c;
                wire [4*NQ_W-1:0]    pt_c;
                wire [SH_W-1:0]      sh_c;
                wire                 wz_c;
                wire [B-1:0]         den_c;
                delay_line #(.W(4*(D_W+1) + 4*NQ_W + SH_W + 1 + B), .N(1)) u_dly_6c (.clk(clk), .rst(rst),
                    .ce(ce), .d_in({sum_all, pt_all, sh_s, w_zero, den_x}), .d_out({sum_c, pt_c, sh_c, wz_c, den_c}));
                reg [4*NQ_W-1:0] num_c;
                /* verilator lint_off UNUSEDSIGNAL */
                reg [D_W-1:0]    nsh_c;
                /* verilator lint_on UNUSEDSIGNAL */
                integer          c6c;
                always @* begin
                    for (c6c = 0; c6c < 4; c6c = c6c + 1) begin
                        nsh_c = sum_c[c6c*(D_W+1) + 1 +: D_W] >> sh_c;
                        num_c[c6c*NQ_W +: NQ_W] = wz_c ? pt_c[c6c*NQ_W +: NQ_W] : nsh_c[NQ_W-1:0];
                    end
                end
                assign num = num_c;
                assign den = den_c;
            end else begin : g_no6c
                assign num = num_x;
                assign den = den_x;
            end

        end

        // the operands' valid: stage 6's, FPGA_REGS: four stages later (4b, 5a, 6a, 6c)
        wire div_valid;
        delay_line #(.W(1), .N(4*P), .CLEAR(1)) u_dly_dv (.clk(clk), .rst(rst), .ce(ce), .d_in(sv_reg[4]),
                                                         .d_out(div_valid));

        // ---- stages 7..14: one quotient bit per stage (LAT = 6 + 8, FPGA_REGS: 11 + 8);
        // exact: divisor w itself; normalised: B-bit divisors, and for B <= 9 the quotient can
        // reach 256 (up to 383), saturated to 255 (SAT)
        box_divide #(
            .NUM_W(NUM_DW), .DEN_W(DEN_DW), .Q_W(8), .LANES(4), .SAT(NORM ? SAT : 0)
        ) u_divide (
            .clk(clk), .rst(rst), .ce(ce), .in_valid(div_valid),
            .num_in(s6_num_reg), .den_in(s6_den_reg),
            .out_valid(out_valid), .q_out(rgba_out)
        );
    end else begin : g_lookup
        // stage 1: filter_en selects the MIP map (sat: only w = 0 carries it)
        reg s1_filter_en_reg;

        // ---- stages 2-3: point / MIP address
        wire [NMAX:0] addr;
        wire          use_mip;

        mip_index #(.FILTER(FILTER), .U_W(U_W), .W_W(W_W), .FF(FF), .NMAX(NMAX), .NL_W(NL_W)) u_index (
            .clk(clk), .ce(ce), .u_in(s1_u_reg), .w_in(s1_w_reg), .mode(s1_mode_reg),
            .n_log2(s1_n_log2_reg), .filter_en(s1_filter_en_reg),
            .addr_out(addr), .use_mip_out(use_mip)
        );

        // ---- stage 4: table reads
        wire [31:0]       clut_a, mip_data;
        /* verilator lint_off UNUSEDSIGNAL */
        wire [31:0]       unused_clut_b;
        wire [4*CS_W-1:0] unused_csat_a, unused_csat_b, unused_total;
        /* verilator lint_on UNUSEDSIGNAL */

        colour_table #(.FILTER(FILTER), .NMAX(NMAX), .CS_W(CS_W), .NL_W(NL_W)) u_table (
            .clk(clk), .ce(ce),
            .wr_en(wr_en), .wr_table(wr_table), .wr_addr(wr_addr), .wr_data(wr_data),
            .clut_addr_a(addr[NMAX-1:0]), .clut_addr_b({NMAX{1'b0}}),
            .csat_addr_a({NMAX{1'b0}}), .csat_addr_b({NMAX{1'b0}}),
            .n_log2({NL_W{1'b0}}), .mip_addr(addr),
            .clut_a(clut_a), .clut_b(unused_clut_b), .csat_a(unused_csat_a),
            .csat_b(unused_csat_b), .total(unused_total), .mip_data(mip_data)
        );

        // ---- stages 5..LAT: select, then a delay line to the block's latency; the last
        // register is the output register (reset, loads only a valid result)
        localparam DL = LAT - 4 - P;  // register stages after the table read (>= 3)
        reg [2:0]           sv_reg;   // valid for stages 2..4
        reg                 use_mip_reg;
        reg [DL-1:0]        dv_reg;
        reg [(DL-1)*32-1:0] dd_reg;
        reg [31:0]          out_reg;

        always @(posedge clk) begin
            if (rst) begin
                sv_reg <= 3'b000;
                dv_reg <= {DL{1'b0}};
            end else if (ce) begin
                sv_reg <= {sv_reg[1:0], s1_valid_reg};
                dv_reg <= {dv_reg[DL-2:0], sv_reg[2]};
            end
            if (ce) begin
                s1_filter_en_reg <= filter_en_i;
                use_mip_reg      <= use_mip;
                dd_reg           <= {dd_reg[(DL-2)*32-1:0], use_mip_reg ? mip_data : clut_a};
            end
            if (rst)
                out_reg <= 32'd0;
            else if (ce && dv_reg[DL-2])
                out_reg <= dd_reg[(DL-2)*32 +: 32];
        end

        assign out_valid = dv_reg[DL-1];
        assign rgba_out  = out_reg;
    end
endgenerate

endmodule

`default_nettype wire
