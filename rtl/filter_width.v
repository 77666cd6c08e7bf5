/*
 * filter_width: the box-filter width w = |c^T J| N in colour-table entries.
 * Twin of model/hw/golden.py filter_width().
 * Written for simulation speed: each stage's logic computed in the clocked processes
 * (blocking temporaries, straight-line code) only on an enabled clock that brings the stage
 * a valid vector, its registers holding otherwise (FPGA_REGS: the extra stages, the
 * products on mul_pipe and the last stage's split on every enabled clock); what another
 * module reads (the leading-one detectors' inputs) and the small squares of stage 4 stay in
 * always @*; no bus driven piecewise.
 * Each such process first assigns its temporaries whole, outside any if, so that they are
 * C++ locals in the Verilator model (it localizes only a variable wholly assigned outside
 * any branch; one first assigned under the if stays a member of the model, a store on every
 * write).
 *
 *   gx = sum_k c_k Jm[k][0],  gy = sum_k c_k Jm[k][1]       (exact, G_W bits)
 *   sh = max(bitlen(max(|gx|, |gy|)) - NORM_BITS, 0)        (leading-one detector)
 *   ax = |gx| >> sh,  ay = |gy| >> sh                        (< 2^NORM_BITS)
 *   r  = floor(sqrt(ax^2 + ay^2))                            (isqrt, exact)
 *   e  = sh + je - C_FRAC + n_log2 + F_FRAC                  (signed E_W bits)
 *   w  = e >= 0 ? r << e : r >> -e                           (floor)
 *   w  = 2^CAP_BITS  if r > 0 and bitlen(r) + e > CAP_BITS,  CAP_BITS = W_CAP_LOG2 + F_FRAC
 *   COMPONENTS = 1 (filter "sat2", the trapezoid): w_out = {b, a}, the two screen components
 *   a = |gx|, b = |gy| each scaled and saturated as w (ax, ay in place of r; the square root's
 *   datapath is then unused, its valid chain times the stages)
 *
 * bitlen(max(a, b)) = bitlen(a | b), and max(bitlen(m) - NB, 0) = bitlen(m >> NB),
 * so sh is one leading-one detector on the high bits of |gx| | |gy|. When the
 * saturation test is false, w < 2^CAP_BITS, so the left shift is done in W_W
 * bits; a right shift by R_W or more gives 0 (the golden model's clip at 63 is
 * the same thing).
 *
 * Formats (the parameters; derived widths from rtl/tex_widths.vh):
 *   c_in   {c2, c1, c0}, each s{C_W}.{C_FRAC}; G_W is derived from the word itself
 *          (|c_k| <= 2^(C_W-1)), so every c_in gives an exact g
 *   jm_in  Jm[k][col] at element 2 k + col, each s{J_W}.0 (J = Jm 2^je)
 *   je_in  s{JE_W}.0
 *   n_log2 u{N_LOG2_W}.0, 0..N_LOG2_MAX (N = 2^n_log2 colour-table entries)
 *   w_out  u{W_W}.{F_FRAC} colour-table entries, saturating at 2^W_CAP_LOG2 (COMPONENTS:
 *          {b, a}, 2 W_W bits, a at [W_W-1:0])
 *
 * Latency `LAT_FILTER_WIDTH register stages; throughput one vector per enabled
 * clock. ce = 0 holds every register. rst (synchronous) clears the valid chain
 * and the output register; the output register loads only valid vectors.
 *
 *   stage 1:       the 6 products c_k Jm[k][col]; je + n_log2 + F_FRAC - C_FRAC
 *   stage 2:       gx, gy and their absolute values
 *   stage 3:       leading-one detector, normalising shift
 *   stage 4:       L = ax^2 + ay^2, e
 *   stages 5..N-1: isqrt (N - 5 stages)
 *   stage N:       scale by 2^e, saturate
 *
 * FPGA_REGS = 1 ([fpga_regs]; `LAT_FILTER_WIDTH_FPGA = `LAT_FILTER_WIDTH + 4): stage 1 in
 * two, each product on mul_pipe (its 18x18 partial products registered before their sum, the
 * exponent's constant part beside them); stage 3 in two, the leading-one detector's sh
 * registered (with ax, ay) before the normalising shift; stage 4 in two, the squares ax^2,
 * ay^2 registered (with sh and the exponent) before their sum; the last stage in two,
 * bitlen(r) + e and the shifted r registered before the comparison with the cap; the isqrt
 * keeps its `LAT_FILTER_WIDTH - 5 stages.
 */

`include "tex_latency.vh"

`default_nettype none

module filter_width #(
    // formats (config/<name>.toml keys in brackets); every other width is derived from
    // them below (rtl/tex_widths.vh, the twin of model/hw/config.py)
    parameter C_W        = 31,  // gradient element word width (texture_pipeline: the exact sum's)
    parameter C_FRAC     = 12,  // [c_frac] gradient fraction bits
    parameter J_W        = 12,  // [j_w] Jacobian mantissa word width
    parameter JE_W       = 8,   // [je_w] Jacobian exponent word width
    parameter NORM_BITS  = 12,  // [norm_bits] |g| normalised to this many bits
    parameter F_FRAC     = 16,  // [f_frac] w fraction bits
    parameter W_CAP_LOG2 = 16,  // [w_cap_log2] w saturates at 2^W_CAP_LOG2 entries
    parameter N_LOG2_MAX = 8,   // [n_log2_max] log2 of the largest colour table
    parameter COMPONENTS = 0,   // [filter] 1 ("sat2"): the two screen components, not |g|
    parameter FPGA_REGS  = 0    // [fpga_regs] 1: stages 1, 3, 4 and the last in two (above)
) (clk, rst, ce, in_valid, c_in, jm_in, je_in, n_log2, out_valid, w_out);

`include "tex_widths.vh"

localparam N_LOG2_W = tw_bits_unsigned(N_LOG2_MAX);                  // n_log2 word
localparam G_W      = tw_bits_signed(tw_g_max(C_W, J_W));            // g = c . Jm (signed)
localparam GABS_W   = tw_bits_unsigned(tw_g_max(C_W, J_W));          // |g|
localparam L_W      = tw_l_w(NORM_BITS);                             // ax^2 + ay^2
localparam R_W      = tw_r_w(NORM_BITS);                             // its square root
localparam SH_W     = tw_sh_w(GABS_W, NORM_BITS);                    // normalising shift
localparam E_W      = tw_e_w(SH_W, JE_W, C_FRAC, F_FRAC, N_LOG2_MAX); // scale exponent (signed)
localparam W_W      = W_CAP_LOG2 + F_FRAC + 1;                       // w (unsigned)
localparam NLN      = (COMPONENTS != 0) ? 2 : 1;                           // output lanes: w, or a and b

input  wire                clk;
input  wire                rst;
input  wire                ce;
input  wire                in_valid;
input  wire [3*C_W-1:0]    c_in;
input  wire [6*J_W-1:0]    jm_in;
input  wire [JE_W-1:0]     je_in;
input  wire [N_LOG2_W-1:0] n_log2;
output wire                out_valid;
output wire [NLN*W_W-1:0]  w_out;

localparam LATENCY  = FPGA_REGS ? `LAT_FILTER_WIDTH_FPGA : `LAT_FILTER_WIDTH;
localparam P        = FPGA_REGS ? 1 : 0;     // each optional register stage (stages 1a, 3a, 4a, last a)
localparam SQ_LAT   = `LAT_FILTER_WIDTH - 5; // isqrt stages
localparam VR       = 4 + 3*P;               // valid bits of stages 1..4 (1a, 3a, 4a)
localparam CAP_BITS = W_CAP_LOG2 + F_FRAC;   // w saturates at 2^CAP_BITS
localparam MH_W     = GABS_W - NORM_BITS;    // bits of |g| above the normalised window
localparam BLR_W    = $clog2(R_W + 1);       // bitlen(r), 0..R_W
// bitlen(r) + e compared with CAP_BITS: signed, wide enough for all three
localparam CMP_W0   = (E_W > BLR_W + 1) ? E_W : BLR_W + 1;
localparam CMP_W1   = ($clog2(CAP_BITS + 1) + 1 > CMP_W0) ? $clog2(CAP_BITS + 1) + 1 : CMP_W0;
localparam CMP_W    = CMP_W1 + 1;
localparam SW       = (R_W > W_W) ? R_W : W_W;  // shifter width
localparam PJ_W     = C_W + J_W;             // product c_k Jm[k][col]

// elaboration fails (unknown module) on an unsupported configuration
generate
    if (LATENCY != `LAT_FILTER_WIDTH + 4*P || SQ_LAT < 1 || SQ_LAT > R_W || MH_W < 1 || $clog2(MH_W + 1) != SH_W || E_W <= SH_W
        || G_W < C_W + J_W) begin : g_bad_params
        filter_width_unsupported_latency_or_widths u_error ();
    end
endgenerate

// ---------------------------------------------------------------------------
// Registers are loaded by the clocked processes at the end; a value that only feeds a
// register is computed there (blocking temporaries), each stage's only on the enabled
// clocks that bring it a valid vector; the others in always @*.

// e without sh: je + n_log2 + F_FRAC - C_FRAC (modulo 2^E_W; the final e fits)
localparam signed [E_W-1:0] E_CONST = F_FRAC - C_FRAC;

reg [VR-1:0] valid_reg;  // stages 1..4 (and 1a, 3a, 4a)
reg       out_valid_reg;
wire      sq_valid;   // valid out of the isqrt (stage LATENCY - 1)

// stage registers
reg signed [PJ_W-1:0] px0_reg, px1_reg, px2_reg;  // c_k Jm[k][0]
reg signed [PJ_W-1:0] py0_reg, py1_reg, py2_reg;  // c_k Jm[k][1]
reg signed [E_W-1:0]  ek_1_reg, ek_2_reg, ek_3_reg, e_4_reg;
reg [GABS_W-1:0]      ax_reg, ay_reg;
reg [NORM_BITS-1:0]   axn_reg, ayn_reg;
reg [SH_W-1:0]        sh_reg;
reg [L_W-1:0]         l_reg;
reg [SQ_LAT*E_W-1:0]  e_dly_reg;  // e_dly_reg[k*E_W +: E_W]: e after k + 1 isqrt stages
reg [NLN*W_W-1:0]     w_reg;

// ---------------------------------------------------------------------------
// stage 1: products; the constant part of the exponent (in the clocked process; FPGA_REGS:
// the products on mul_pipe, the exponent's part delayed beside its partial products)

wire signed [E_W-1:0] ek_next = $signed({{(E_W-JE_W){je_in[JE_W-1]}}, je_in})
                              + $signed({{(E_W-N_LOG2_W){1'b0}}, n_log2}) + E_CONST;
wire signed [E_W-1:0] ek_1a;
wire [6*PJ_W-1:0]     prod_1a;  // product 2 k + col: c_k Jm[k][col]
delay_line #(.W(E_W), .N(P)) u_dly_1a (.clk(clk), .rst(rst), .ce(ce), .d_in(ek_next), .d_out(ek_1a));
generate
    if (FPGA_REGS) begin : g_pipe
        genvar gp;
        for (gp = 0; gp < 6; gp = gp + 1) begin : g_prod
            if (C_W <= 35 && J_W <= 35) begin : g_mul
                mul_pipe #(.A_W(C_W), .B_W(J_W)) u_mul (.clk(clk), .ce(ce), .a(c_in[(gp/2)*C_W +: C_W]),
                                                       .b(jm_in[gp*J_W +: J_W]), .p(prod_1a[gp*PJ_W +: PJ_W]));
            end else begin : g_reg  // operands wider than mul_pipe's two parts
                wire signed [PJ_W-1:0] pw = $signed(c_in[(gp/2)*C_W +: C_W]) * $signed(jm_in[gp*J_W +: J_W]);
                delay_line #(.W(PJ_W), .N(1)) u_dly (.clk(clk), .rst(1'b0), .ce(ce), .d_in(pw),
                                                     .d_out(prod_1a[gp*PJ_W +: PJ_W]));
            end
        end
    end else begin : g_comb
        // not read: stage 1 forms the products in the clocked process below
        assign prod_1a = {(6*PJ_W){1'b0}};
    end
endgenerate
//
// stage 2: gx, gy, absolute values; stage 3: the leading-one detector's input;
// stage 4: L = ax^2 + ay^2; the e delay line

// products sign-extended to G_W (>= C_W + J_W, since cmax >= 2^(C_W-2)): the sign
// bit replicated G_W - PJ_W + 1 times; the sum fits G_W by the precondition on c,
// so it is exact
// (stage 2's gx, gy and their absolute values: in the clocked process)
reg signed [G_W-1:0]  gx, gy;
/* verilator lint_off UNUSEDSIGNAL */
// the MSB of |g| in G_W bits is zero: |g| < 2^GABS_W (model/hw/config.py: gabs_w)
reg [G_W-1:0]         gx_abs, gy_abs;
// L: the squares (2 NORM_BITS bits) zero-extended and summed in L_W + 2 NORM_BITS
// bits (L_W >= 2 NORM_BITS; equal only for NORM_BITS = 1); L fits L_W
reg [L_W+2*NORM_BITS-1:0] l_x;
// the e delay: the oldest e drops out of the top
reg [(SQ_LAT+1)*E_W-1:0]  e_dly_cat;
/* verilator lint_on UNUSEDSIGNAL */
reg [2*NORM_BITS-1:0] ax2, ay2;
reg [MH_W-1:0]        mh;  // bitlen input: (ax | ay) >> NORM_BITS

always @* begin
    mh = ax_reg[GABS_W-1:NORM_BITS] | ay_reg[GABS_W-1:NORM_BITS];

    ax2 = axn_reg * axn_reg;
    ay2 = ayn_reg * ayn_reg;
    l_x = {{L_W{1'b0}}, ax2} + {{L_W{1'b0}}, ay2};
end

// ---------------------------------------------------------------------------
// stage 3: sh = bitlen((ax | ay) >> NORM_BITS); ax, ay >> sh
//
// bitlen: the leading-one detector (rtl/bitlen.v; FPGA_REGS: its parallel form, PAR).

wire [SH_W-1:0] sh;
/* verilator lint_off UNUSEDSIGNAL */
wire            mh_nz;  // sh > 0 says it too
/* verilator lint_on UNUSEDSIGNAL */
bitlen #(.W(MH_W), .BW(SH_W), .PAR(FPGA_REGS)) u_bitlen_mh (.x(mh), .bl(sh), .nz(mh_nz));

/* verilator lint_off UNUSEDSIGNAL */
// bits NORM_BITS and up of the shifted values are zero: |g| < 2^(sh + NORM_BITS)
reg [GABS_W-1:0] ax_sh, ay_sh;
/* verilator lint_on UNUSEDSIGNAL */

// FPGA_REGS: sh, ax, ay (and the exponent beside them) registered before the shift (3a)
wire [SH_W-1:0]       sh_p;
wire [GABS_W-1:0]     ax_p, ay_p;
wire signed [E_W-1:0] ek_2_p;
delay_line #(.W(SH_W + 2*GABS_W + E_W), .N(P)) u_dly_3a (.clk(clk), .rst(rst), .ce(ce),
    .d_in({sh, ax_reg, ay_reg, ek_2_reg}), .d_out({sh_p, ax_p, ay_p, ek_2_p}));

// (ax, ay >> sh: in the clocked process)

// stage 4 (FPGA_REGS: 4a) the squares, registered with sh and the exponent before their sum
// (a square on an FPGA's multiplier block, its output off the adder's path); without, L is
// l_x of stage 2-4's always @*
/* verilator lint_off UNUSEDSIGNAL */  // L fits its low L_W bits (as l_x)
wire [L_W+2*NORM_BITS-1:0] l_4;
/* verilator lint_on UNUSEDSIGNAL */
wire [SH_W-1:0]            sh_4;
wire signed [E_W-1:0]      ek_4;
generate
    if (FPGA_REGS) begin : g_4a
        wire [2*NORM_BITS-1:0] ax2_p, ay2_p;
        delay_line #(.W(4*NORM_BITS + SH_W + E_W), .N(1)) u_dly_4a (.clk(clk), .rst(rst), .ce(ce),
            .d_in({ax2, ay2, sh_reg, ek_3_reg}), .d_out({ax2_p, ay2_p, sh_4, ek_4}));
        assign l_4 = {{L_W{1'b0}}, ax2_p} + {{L_W{1'b0}}, ay2_p};
    end else begin : g_4
        assign l_4  = l_x;
        assign sh_4 = sh_reg;
        assign ek_4 = ek_3_reg;
    end
endgenerate

// ---------------------------------------------------------------------------
// stages 5..LATENCY-1: square root

wire [R_W-1:0] r;

isqrt #(
    .L_W(L_W),
    .R_W(R_W),
    .LATENCY(SQ_LAT)
) u_isqrt (
    .clk(clk),
    .rst(rst),
    .ce(ce),
    .in_valid(valid_reg[VR-1]),
    .l_in(l_reg),
    .out_valid(sq_valid),
    .r_out(r)
);

// ---------------------------------------------------------------------------
// stage LATENCY: w = r scaled by 2^e, saturated (COMPONENTS: a and b, ax and ay so scaled)

// the lanes scaled: r, or (COMPONENTS) ax and ay delayed beside the square root (from the
// stage-3 registers: stage 4, 4a, the isqrt's stages)
wire [NLN*R_W-1:0] lane;
generate
    if (COMPONENTS != 0) begin : g_comp
        wire [2*NORM_BITS-1:0] axy_d;
        delay_line #(.W(2*NORM_BITS), .N(1 + P + SQ_LAT)) u_dly_axy (.clk(clk), .rst(rst), .ce(ce),
            .d_in({ayn_reg, axn_reg}), .d_out(axy_d));
        assign lane = {{(R_W-NORM_BITS){1'b0}}, axy_d[NORM_BITS +: NORM_BITS],
                       {(R_W-NORM_BITS){1'b0}}, axy_d[0 +: NORM_BITS]};
        /* verilator lint_off UNUSEDSIGNAL */  // the square root's value (its valid times the stages)
        wire [R_W-1:0] unused_r = r;
        /* verilator lint_on UNUSEDSIGNAL */
    end else begin : g_norm
        assign lane = r;
    end
endgenerate

// bitlen of each lane, lane != 0
wire [NLN-1:0]       r_nz;
wire [NLN*BLR_W-1:0] r_bl;
genvar gl;
generate
    for (gl = 0; gl < NLN; gl = gl + 1) begin : g_bl
        bitlen #(.W(R_W), .BW(BLR_W)) u_bitlen_r (.x(lane[gl*R_W +: R_W]), .bl(r_bl[gl*BLR_W +: BLR_W]),
                                                  .nz(r_nz[gl]));
    end
endgenerate

localparam signed [CMP_W-1:0] CAP_S = CAP_BITS;
localparam [W_W-1:0]          W_CAP = {1'b1, {CAP_BITS{1'b0}}} ;

reg signed [E_W-1:0]     e;
/* verilator lint_off UNUSEDSIGNAL */  // FPGA_REGS: compared after a register (g_split); else over
reg [NLN*CMP_W-1:0]      top;   // bitlen(lane) + e
reg [NLN-1:0]            over;  // lane > 0 and bitlen(lane) + e > CAP_BITS
/* verilator lint_on UNUSEDSIGNAL */
reg [SW-1:0]             r_x;   // a lane zero-extended to the shifter width
/* verilator lint_off UNUSEDSIGNAL */
// when R_W > W_W, the bits of the shifted lane above W_W are zero unless over
reg [SW-1:0]             w_sh;
/* verilator lint_on UNUSEDSIGNAL */
reg signed [CMP_W-1:0]   top_l;
reg [NLN*W_W-1:0]        w_all; // the shifted lanes
integer                  li;

// FPGA_REGS: lane > 0, bitlen(lane) + e and the shifted lane registered (in the last stage's
// clocked process below) before the comparison with the cap (the valid beside them, reset);
// without FPGA_REGS the output register takes the lanes directly (not read)
/* verilator lint_off UNUSEDSIGNAL */
reg [NLN-1:0]       nz_r;
reg [NLN*CMP_W-1:0] top_r;
reg [NLN*W_W-1:0]   wsh_r;
/* verilator lint_on UNUSEDSIGNAL */
wire                fin_valid;
wire [NLN-1:0]      fin_over;  // FPGA_REGS: from the registers above (else not read)
generate
    if (FPGA_REGS) begin : g_split
        reg                 sqv_r;
        reg [NLN-1:0]       ov_c;
        integer             lj;
        always @(posedge clk) begin
            if (rst)
                sqv_r <= 1'b0;
            else if (ce)
                sqv_r <= sq_valid;
        end
        always @* begin
            for (lj = 0; lj < NLN; lj = lj + 1)
                ov_c[lj] = nz_r[lj] && ($signed(top_r[lj*CMP_W +: CMP_W]) > CAP_S);
        end
        assign fin_valid = sqv_r;
        assign fin_over  = ov_c;
    end else begin : g_direct
        assign fin_valid = sq_valid;
        assign fin_over  = {NLN{1'b0}};
    end
endgenerate

// the saturated lanes
reg [NLN*W_W-1:0] w_fin;
integer           lk;

// ---------------------------------------------------------------------------
// all registers: the clocked processes below, each stage computed (blocking temporaries)
// and loaded only on an enabled clock that brings it a valid vector: stage 1 in_valid (FPGA_REGS:
// the products' 1a), stage 2 stage 1's, stage 3 stage 2's (FPGA_REGS: 3a's), stage 4 stage 3's
// (FPGA_REGS: 4a's); the e delay line on every enabled clock
wire v_1 = (P != 0) ? valid_reg[0] : in_valid;
wire v_2 = valid_reg[P];
wire v_3 = valid_reg[1 + 2*P];
wire v_4 = valid_reg[2 + 3*P];
reg  [6*PJ_W-1:0] prod_x;
integer           pc;

/* verilator lint_off BLKSEQ */
always @(posedge clk) begin
    // every temporary wholly assigned first, outside the ifs (C++ locals: the header)
    prod_x    = {(6*PJ_W){1'b0}};
    gx        = {G_W{1'b0}};
    gy        = {G_W{1'b0}};
    gx_abs    = {G_W{1'b0}};
    gy_abs    = {G_W{1'b0}};
    ax_sh     = {GABS_W{1'b0}};
    ay_sh     = {GABS_W{1'b0}};
    e_dly_cat = {((SQ_LAT+1)*E_W){1'b0}};
    if (ce && v_1) begin
        // stage 1 (FPGA_REGS: from mul_pipe)
        if (P != 0)
            prod_x = prod_1a;
        else
            for (pc = 0; pc < 6; pc = pc + 1)
                prod_x[pc*PJ_W +: PJ_W] = $signed(c_in[(pc/2)*C_W +: C_W]) * $signed(jm_in[pc*J_W +: J_W]);
        px0_reg  <= prod_x[0*PJ_W +: PJ_W];  // c0 Jm[0][0]
        px1_reg  <= prod_x[2*PJ_W +: PJ_W];  // c1 Jm[1][0]
        px2_reg  <= prod_x[4*PJ_W +: PJ_W];  // c2 Jm[2][0]
        py0_reg  <= prod_x[1*PJ_W +: PJ_W];  // c0 Jm[0][1]
        py1_reg  <= prod_x[3*PJ_W +: PJ_W];  // c1 Jm[1][1]
        py2_reg  <= prod_x[5*PJ_W +: PJ_W];  // c2 Jm[2][1]
        ek_1_reg <= ek_1a;
    end
    if (ce && v_2) begin
        // stage 2
        gx = {{(G_W-PJ_W+1){px0_reg[PJ_W-1]}}, px0_reg[PJ_W-2:0]}
           + {{(G_W-PJ_W+1){px1_reg[PJ_W-1]}}, px1_reg[PJ_W-2:0]}
           + {{(G_W-PJ_W+1){px2_reg[PJ_W-1]}}, px2_reg[PJ_W-2:0]};
        gy = {{(G_W-PJ_W+1){py0_reg[PJ_W-1]}}, py0_reg[PJ_W-2:0]}
           + {{(G_W-PJ_W+1){py1_reg[PJ_W-1]}}, py1_reg[PJ_W-2:0]}
           + {{(G_W-PJ_W+1){py2_reg[PJ_W-1]}}, py2_reg[PJ_W-2:0]};
        gx_abs = gx[G_W-1] ? -gx : gx;
        gy_abs = gy[G_W-1] ? -gy : gy;
        ax_reg   <= gx_abs[GABS_W-1:0];
        ay_reg   <= gy_abs[GABS_W-1:0];
        ek_2_reg <= ek_1_reg;
    end
    if (ce && v_3) begin
        // stage 3
        ax_sh = ax_p >> sh_p;
        ay_sh = ay_p >> sh_p;
        axn_reg  <= ax_sh[NORM_BITS-1:0];
        ayn_reg  <= ay_sh[NORM_BITS-1:0];
        sh_reg   <= sh_p;
        ek_3_reg <= ek_2_p;
    end
    if (ce && v_4) begin
        // stage 4: e = sh + ek (FPGA_REGS: from stage 4a)
        l_reg    <= l_4[L_W-1:0];
        e_4_reg  <= $signed({{(E_W-SH_W){1'b0}}, sh_4}) + ek_4;
    end
    if (ce) begin
        // stages 5..LATENCY-1: e delayed alongside the square root
        e_dly_cat = {e_dly_reg, e_4_reg};
        e_dly_reg <= e_dly_cat[SQ_LAT*E_W-1:0];
    end
end

// the last stage: w = lane scaled by 2^e, saturated, loaded only with a valid result
// (FPGA_REGS: the scaled lanes registered on every enabled clock, then saturated)
always @(posedge clk) begin
    // every temporary wholly assigned first, outside the ifs (C++ locals: the header)
    e     = {E_W{1'b0}};
    top_l = {CMP_W{1'b0}};
    top   = {(NLN*CMP_W){1'b0}};
    over  = {NLN{1'b0}};
    r_x   = {SW{1'b0}};
    w_sh  = {SW{1'b0}};
    w_all = {(NLN*W_W){1'b0}};
    w_fin = {(NLN*W_W){1'b0}};
    if (ce && (P != 0 || sq_valid)) begin
        e     = e_dly_reg[(SQ_LAT-1)*E_W +: E_W];
        for (li = 0; li < NLN; li = li + 1) begin
            top_l = {{(CMP_W-BLR_W){1'b0}}, r_bl[li*BLR_W +: BLR_W]} + {{(CMP_W-E_W){e[E_W-1]}}, e};
            top[li*CMP_W +: CMP_W] = top_l;
            over[li] = r_nz[li] && (top_l > CAP_S);
            r_x   = {SW{1'b0}};
            r_x[R_W-1:0] = lane[li*R_W +: R_W];
            // left by e (e >= 0) or right by -e (e < 0; -e in E_W bits: 2^(E_W-1) reads
            // correctly unsigned)
            w_sh  = e[E_W-1] ? (r_x >> -e) : (r_x << e[E_W-2:0]);
            w_all[li*W_W +: W_W] = w_sh[W_W-1:0];
        end
        if (P != 0) begin
            nz_r  <= r_nz;
            top_r <= top;
            wsh_r <= w_all;
        end
    end
    if (rst) begin
        valid_reg     <= {VR{1'b0}};
        out_valid_reg <= 1'b0;
        w_reg         <= {(NLN*W_W){1'b0}};
    end else if (ce) begin
        valid_reg     <= {valid_reg[VR-2:0], in_valid};
        out_valid_reg <= fin_valid;
        if (fin_valid) begin
            // without FPGA_REGS the lanes just scaled above (fin_valid = sq_valid)
            for (lk = 0; lk < NLN; lk = lk + 1)
                if (P != 0)
                    w_fin[lk*W_W +: W_W] = fin_over[lk] ? W_CAP : wsh_r[lk*W_W +: W_W];
                else
                    w_fin[lk*W_W +: W_W] = over[lk] ? W_CAP : w_all[lk*W_W +: W_W];
            w_reg <= w_fin;
        end
    end
end
/* verilator lint_on BLKSEQ */

assign out_valid = out_valid_reg;
assign w_out     = w_reg;

endmodule

`default_nettype wire
