// colour_map: RGBA8 of the colour index f box-filtered over the filter width w (paper 3.3);
// the bit-exact twin of model/hw/golden.py colour_map. Stage 1 (here) forms the colour index
// u; a filter-family module, picked by FILTER, does the rest:
//   FILTER 1 (sat)  cmap_sat: the box filter from the summed-area table (sat_index,
//                   colour_table, sat_integral at both window ends, D = I(b) - I(a) once)
//                   and cmap_divide, the division D / 2w by the method DIV_BITS (0 exact,
//                   B > 0 on w normalised to B bits); w = 0 or filter off: the point lookup
//   FILTER 2 (mip)  cmap_mip: the colour-table MIP map (mip_index); filter off: clut[k]
//   FILTER 0 (none) cmap_point: the point lookup clut[k]
//   FILTER 3 (sat2) cmap_sat2: the trapezoid, the colour map convolved with two boxes of the
//                   screen components (a, b) of grad f N (w_in = {b, a}), from the SAT and its
//                   running sum (sat2_table), and cmap_divide; a or b = 0 the box, both the
//                   point lookup
// Only the configured family is built. Every family has the same ports (the stage-1
// registers, the table write port, out_valid, rgba_out; sat omits filter_en, point also w)
// and its own latency `LAT_CMAP_<FAMILY>, which with stage 1 makes `LAT_COLOUR_MAP (checked
// at elaboration); a new family is one more module and one more branch below.
//
// Formats (the parameters; derived widths from rtl/tex_widths.vh):
//   f_in   s{F_W}.{F_FRAC}   1.0 = the whole colour table
//   w_in   u{W_W}.{F_FRAC}   colour-table entries; contract: w <= 2^(W_CAP_LOG2 + F_FRAC)
//                            (FILTER 3: {b, a}, two such words, a at [W_W-1:0])
//                            (filter_width saturates there; the families' words are sized
//                            for it)
//   mode   0 mod (f taken mod 1), 1 clamp; filter_en 0: point lookup
//   n_log2 N = 2^n_log2 entries, n_log2 <= N_LOG2_MAX; tables loaded for that N
//   rgba_out RGBA8, channel c at [8c+7:8c] (R = 0, G = 1, B = 2, A = 3)
//
// Stage 1 (docs/numerics.md, "Colour map"):
//   u = (f mod 1) N (mod) or clip(f N, -W/2, N + W/2), W = 2^W_CAP_LOG2 (clamp; FILTER 3:
//       clip(f N, -W, N + W), the trapezoid's window reaching (a + b) / 2 <= W from u)
//       [s{U_W}.{F_FRAC} entries; clamp compares f with the thresholds shifted right
//        by n_log2, exact because they are multiples of 2^n_log2; the words that vary with
//        n_log2 are formed on their live bits (guard >> n_log2: bits GUARD - N_LOG2_MAX ..
//        GUARD; N; (f mod 1) N: F_FRAC + N_LOG2_MAX bits) and widened for the comparisons]
//   w registered, 0 when the filter is off; mode, n_log2 (and for mip filter_en) registered.
//
// Tables (colour_table, in the family): loaded by the host through the write port
// (synchronous, independent of ce): wr_table 0 clut, 1 csat (inclusive prefix sums of clut,
// eq. 13), 2 mip (2N - 1 entries, level l at 2N - (2N >> l)); wr_data channel c at
// [c*CSAT_W +: CSAT_W], clut and mip use the low 8 bits of each lane; wr_addr past a table's
// end, wr_table 3 and tables the configuration does not build are ignored. The host computes
// csat and mip (golden build_tables); the RTL equals golden for tables so built.
// Storage: sat 32 2^NMAX + 4 CSAT_W 2^NMAX bits (full, reduced: 24576; plus the whole-table
// sum csat[N - 1], the last csat entry written, as 4 CSAT_W = 64 flip-flops: write csat in
// ascending order), mip 32 2^NMAX + 32 (2^(NMAX+1) - 1) (24544), none 32 2^NMAX (8192).
//
// Pipeline: 1 u (here) | 2..14 the family (cmap_sat: 2 a, b | 3 sat_index x2 | 4 table reads
// | 5 sat_integral x2, the normaliser | 6 D, the divider operands | 7..14 box_divide; mip,
// none: 2-3 mip_index | 4 table reads | 5 select | 6..14 delay line).
// FPGA_REGS = 1 ([fpga_regs]) adds five register stages: stage 1 in two here (1a: the clamp
// thresholds' live bits, N, (f mod 1) N and the shifted f, registered; 1b: the comparisons),
// and four in the family
// (cmap_sat: 4b, 5a, 6a and cmap_divide's 6c; mip, none: a longer delay line).
// Latency `LAT_COLOUR_MAP = 14 (FPGA_REGS: `LAT_COLOUR_MAP_FPGA = 19; CLOCKS = 4:
// `LAT_COLOUR_MAP_SERIAL = 18) register stages; throughput one pixel per enabled clock (CLOCKS
// = 4: one per four).
// Reset (synchronous, active high) clears the valid chain and rgba_out (no X after reset);
// rgba_out loads only with a valid result.
// Written for simulation speed: stage 1(b)'s comparisons and selection computed in its
// clocked process (blocking temporaries) only on an enabled clock that brings a valid pixel,
// the stage-1 registers holding otherwise (the families do the same per stage); stage 1(a)'s
// shifts in one always @*; no bus driven piecewise.
// Each such process first assigns its temporaries whole, outside any if, so that they are
// C++ locals in the Verilator model (it localizes only a variable wholly assigned outside
// any branch; one first assigned under the if stays a member of the model, a store on every
// write).

`default_nettype none

`include "tex_latency.vh"

module colour_map #(
    // formats and modes (config/<name>.toml keys in brackets); every internal width is
    // derived from them below (rtl/tex_widths.vh, the twin of model/hw/config.py)
    parameter F_W        = 42,  // f_in word width (texture_pipeline: the exact sum's)
    parameter F_FRAC     = 16,  // [f_frac] fraction bits of f and w
    parameter W_CAP_LOG2 = 16,  // [w_cap_log2] w saturates at 2^W_CAP_LOG2 entries
    parameter N_LOG2_MAX = 8,   // [n_log2_max] log2 of the largest colour table (>= 1)
    parameter FILTER     = 1,   // [filter] 0 none (point lookup), 1 sat, 2 mip, 3 sat2
    parameter DIV_BITS   = 0,   // [div_bits] box-filter division: 0 exact, B > 0 on B-bit w
    parameter FPGA_REGS  = 0,   // [fpga_regs] 1: the five extra register stages above
    parameter CLOCKS     = 1    // [cmap_clocks] 4: cmap_sat takes a pixel's channels on four clocks
                                // (FILTER 1 without FPGA_REGS; a pixel in at most every 4 enabled clocks)
) (clk, rst, ce, in_valid, f_in, w_in, mode, n_log2, filter_en, wr_en, wr_table, wr_addr, wr_data,
   out_valid, rgba_out);

`include "tex_widths.vh"

localparam FF     = F_FRAC;
localparam W_W    = W_CAP_LOG2 + F_FRAC + 1;                       // w
localparam NW     = (FILTER == 3) ? 2 : 1;                         // w words: sat2's a and b
localparam GW     = (FILTER == 3) ? 1 : 0;                         // sat2: the guard W, not W/2
localparam U_W    = tw_u_w(N_LOG2_MAX, F_FRAC, W_CAP_LOG2 + GW);   // u = f N (signed)
localparam CS_W   = tw_csat_w(N_LOG2_MAX);                         // summed-area channel
localparam NMAX   = N_LOG2_MAX;
localparam NL_W   = tw_bits_unsigned(N_LOG2_MAX);                  // n_log2
localparam WCAP   = W_CAP_LOG2;

input  wire                 clk;
input  wire                 rst;
input  wire                 ce;
input  wire                 in_valid;
input  wire [F_W-1:0]       f_in;       // signed
input  wire [NW*W_W-1:0]    w_in;
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

localparam LAT    = `LAT_CM(FPGA_REGS, CLOCKS);   // the rule of rtl/tex_latency.vh
localparam P      = FPGA_REGS ? 1 : 0;  // each optional register stage (delay_line of P stages)

localparam GUARD  = WCAP + FF - 1 + GW; // clamp guard W/2 (sat2: W) = 2^GUARD (units 2^-FF entries)
localparam CW     = (F_W > U_W) ? F_W : U_W;  // clamp comparison width

// the filter family's latency (after stage 1)
localparam LAT_FAM = (FILTER == 1) ? `LAT_CMS(FPGA_REGS, CLOCKS)
                   : (FILTER == 3) ? (FPGA_REGS ? `LAT_CMAP_SAT2_FPGA : `LAT_CMAP_SAT2)
                   : (FILTER == 2) ? (FPGA_REGS ? `LAT_CMAP_MIP_FPGA : `LAT_CMAP_MIP)
                   :                 (FPGA_REGS ? `LAT_CMAP_POINT_FPGA : `LAT_CMAP_POINT);

// elaboration fails (unknown module) when stage 1 and the family do not add up to the latency
// or on a fold of another family (cmap_sat checks its own)
generate
    if (LAT != 1 + P + LAT_FAM) begin : g_bad_latency
        colour_map_latency_mismatch u_error ();
    end
    if (CLOCKS != 1 && FILTER != 1) begin : g_bad_clocks
        colour_map_clocks_needs_filter_sat u_error ();
    end
endgenerate

// ---------------------------------------------------------------------------
// Stage 1: u (FPGA_REGS: in two, 1a the thresholds and shifted values, registered; 1b the
// comparisons and the selection)

localparam GL     = (GUARD > NMAX) ? GUARD - NMAX : 0;  // the lowest bit guard >> n_log2 can set
localparam GSW    = GUARD - GL + 1;     // guard >> n_log2: its live bits GL..GUARD
localparam MW     = FF + NMAX;          // (f mod 1) N < N << FF <= 2^MW

reg [CW-1:0]  f_c;       // f sign-extended to CW
reg [GSW-1:0] gsh_l;     // guard >> n_log2 = gsh_l << GL (n_log2 <= NMAX: no bit below GL is set)
reg [NMAX:0]  n_l;       // N = 2^n_log2
reg [MW-1:0]  u_mod_l;   // mod: (f mod 1) N
reg [U_W-1:0] u_sh;      // f N (clamp, between the thresholds)

always @* begin
    f_c = {CW{f_in[F_W-1]}};
    f_c[F_W-1:0] = f_in;
    gsh_l = {GSW{1'b0}};
    gsh_l[GSW-1] = 1'b1;
    gsh_l = gsh_l >> n_log2;
    n_l = {{NMAX{1'b0}}, 1'b1} << n_log2;
    u_mod_l = {{NMAX{1'b0}}, f_in[FF-1:0]} << n_log2;
    u_sh = f_c[U_W-1:0] << n_log2;
end

// FPGA_REGS: stage 1a's values and the inputs stage 1b reads, registered
wire            in_valid_i;
wire [CW-1:0]   f_i;
wire [GSW-1:0]  gsh_i;
wire [NMAX:0]   n_i;
wire [MW-1:0]   u_mod_i;
wire [U_W-1:0]  u_sh_i;
wire [NW*W_W-1:0] w_i;
wire            mode_i;
wire [NL_W-1:0] n_log2_i;
wire            filter_en_i;
delay_line #(.W(1), .N(P), .CLEAR(1)) u_dly_iv (.clk(clk), .rst(rst), .ce(ce), .d_in(in_valid), .d_out(in_valid_i));
// (two lines: stage 1b reads only the first, whose words all change together)
delay_line #(.W(CW + GSW + NMAX + 1 + MW + U_W), .N(P)) u_dly_1a (.clk(clk), .rst(rst), .ce(ce),
    .d_in({f_c, gsh_l, n_l, u_mod_l, u_sh}), .d_out({f_i, gsh_i, n_i, u_mod_i, u_sh_i}));
delay_line #(.W(NW*W_W + 2 + NL_W), .N(P)) u_dly_1i (.clk(clk), .rst(rst), .ce(ce),
    .d_in({w_in, mode, filter_en, n_log2}), .d_out({w_i, mode_i, filter_en_i, n_log2_i}));

// stage 1 (FPGA_REGS: 1b): the live words above placed in the words the comparisons take
// (their other bits are constants), and
// clamp: clip(f N, -guard, N + guard); f N < -guard iff f < -(guard >> n_log2), and
// f N > N + guard iff f > 1.0 + (guard >> n_log2); in between f N fits U_W bits
/* verilator coverage_off */  // the live words widened: no bit of their own to toggle
reg [CW-1:0]  gsh;       // guard >> n_log2
reg [CW-1:0]  lo_thr;    // -(guard >> n_log2)
reg [CW-1:0]  hi_thr;    // 1.0 + (guard >> n_log2)
reg [U_W-1:0] guard_u;   // guard
reg [U_W-1:0] n_u;       // N << FF
reg [U_W-1:0] u_mod;
/* verilator coverage_on */
reg [U_W-1:0] u_clamp;

reg             s1_valid_reg;
reg [U_W-1:0]   s1_u_reg;
reg [NW*W_W-1:0] s1_w_reg;         // w (sat2: {b, a}), 0 when the filter is off
reg             s1_mode_reg;
reg [NL_W-1:0]  s1_n_log2_reg;

// (computed in the clocked process, blocking temporaries, only on an enabled clock that
// brings a valid pixel: the stage-1 registers hold otherwise)
/* verilator lint_off BLKSEQ */
always @(posedge clk) begin
    // the temporaries wholly assigned first, outside any if (C++ locals: the header)
    gsh     = {CW{1'b0}};
    lo_thr  = {CW{1'b0}};
    hi_thr  = {CW{1'b0}};
    guard_u = {U_W{1'b0}};
    n_u     = {U_W{1'b0}};
    u_mod   = {U_W{1'b0}};
    u_clamp = {U_W{1'b0}};
    if (rst)
        s1_valid_reg <= 1'b0;
    else if (ce)
        s1_valid_reg <= in_valid_i;
    if (ce && in_valid_i) begin
        gsh = {CW{1'b0}};
        gsh[GUARD:GL] = gsh_i;
        lo_thr = -gsh;
        hi_thr = {CW{1'b0}};
        hi_thr[FF] = 1'b1;
        hi_thr = hi_thr + gsh;
        guard_u = {U_W{1'b0}};
        guard_u[GUARD] = 1'b1;
        n_u = {U_W{1'b0}};
        n_u[FF+NMAX:FF] = n_i;
        u_mod = {U_W{1'b0}};
        u_mod[MW-1:0] = u_mod_i;
        if ($signed(f_i) < $signed(lo_thr))
            u_clamp = -guard_u;
        else if ($signed(f_i) > $signed(hi_thr))
            u_clamp = n_u + guard_u;
        else
            u_clamp = u_sh_i;
        s1_u_reg         <= mode_i ? u_clamp : u_mod;
        s1_w_reg         <= filter_en_i ? w_i : {(NW*W_W){1'b0}};  // filter off: w = 0
        s1_mode_reg      <= mode_i;
        s1_n_log2_reg    <= n_log2_i;
    end
end
/* verilator lint_on BLKSEQ */

// ---------------------------------------------------------------------------
// Filter

generate
    if (FILTER == 1) begin : g_sat
        // ---- stages 2..14 (FPGA_REGS: ..19): the box filter and its division
        cmap_sat #(
            .F_FRAC(F_FRAC), .W_CAP_LOG2(W_CAP_LOG2), .N_LOG2_MAX(N_LOG2_MAX), .DIV_BITS(DIV_BITS),
            .FPGA_REGS(FPGA_REGS), .CLOCKS(CLOCKS)
        ) u_family (
            .clk(clk), .rst(rst), .ce(ce), .in_valid(s1_valid_reg), .u_in(s1_u_reg), .w_in(s1_w_reg),
            .mode(s1_mode_reg), .n_log2(s1_n_log2_reg),
            .wr_en(wr_en), .wr_table(wr_table), .wr_addr(wr_addr), .wr_data(wr_data),
            .out_valid(out_valid), .rgba_out(rgba_out)
        );
    end else if (FILTER == 3) begin : g_sat2
        // ---- stages 2..14 (FPGA_REGS: ..19): the trapezoid and its division
        cmap_sat2 #(
            .F_FRAC(F_FRAC), .W_CAP_LOG2(W_CAP_LOG2), .N_LOG2_MAX(N_LOG2_MAX), .DIV_BITS(DIV_BITS),
            .FPGA_REGS(FPGA_REGS)
        ) u_family (
            .clk(clk), .rst(rst), .ce(ce), .in_valid(s1_valid_reg), .u_in(s1_u_reg), .w_in(s1_w_reg),
            .mode(s1_mode_reg), .n_log2(s1_n_log2_reg),
            .wr_en(wr_en), .wr_table(wr_table), .wr_addr(wr_addr), .wr_data(wr_data),
            .out_valid(out_valid), .rgba_out(rgba_out)
        );
    end else if (FILTER == 2) begin : g_mip
        // stage 1: filter_en selects the MIP map (sat: only w = 0 carries it)
        reg s1_filter_en_reg;
        always @(posedge clk) begin
            if (ce)
                s1_filter_en_reg <= filter_en_i;
        end
        // ---- stages 2..14 (FPGA_REGS: ..19): MIP level, table reads, delay line
        cmap_mip #(
            .F_FRAC(F_FRAC), .W_CAP_LOG2(W_CAP_LOG2), .N_LOG2_MAX(N_LOG2_MAX), .FPGA_REGS(FPGA_REGS)
        ) u_family (
            .clk(clk), .rst(rst), .ce(ce), .in_valid(s1_valid_reg), .u_in(s1_u_reg), .w_in(s1_w_reg),
            .filter_en(s1_filter_en_reg), .mode(s1_mode_reg), .n_log2(s1_n_log2_reg),
            .wr_en(wr_en), .wr_table(wr_table), .wr_addr(wr_addr), .wr_data(wr_data),
            .out_valid(out_valid), .rgba_out(rgba_out)
        );
    end else if (FILTER == 0) begin : g_point
        /* verilator lint_off UNUSEDSIGNAL */  // the point lookup reads neither w nor filter_en
        wire unused_point = filter_en_i | (|s1_w_reg);
        /* verilator lint_on UNUSEDSIGNAL */
        // ---- stages 2..14 (FPGA_REGS: ..19): the point address, the clut read, delay line
        cmap_point #(
            .F_FRAC(F_FRAC), .W_CAP_LOG2(W_CAP_LOG2), .N_LOG2_MAX(N_LOG2_MAX), .FPGA_REGS(FPGA_REGS)
        ) u_family (
            .clk(clk), .rst(rst), .ce(ce), .in_valid(s1_valid_reg), .u_in(s1_u_reg),
            .mode(s1_mode_reg), .n_log2(s1_n_log2_reg),
            .wr_en(wr_en), .wr_table(wr_table), .wr_addr(wr_addr), .wr_data(wr_data),
            .out_valid(out_valid), .rgba_out(rgba_out)
        );
    end else begin : g_bad_filter
        colour_map_unknown_filter u_error ();
    end
endgenerate

endmodule

`default_nettype wire
