// noise_term: one noise term a n(T s + o) and its texture-space gradient a (dn/dp) T.
//
// The bit-exact twin of model/golden.py noise_term(cfg, a, T, o, s) (with noise_hash,
// noise_blend and _lerp), for one vector per enabled clock:
//   p_j  = ((sum_k T_jk s_k) >> TS_SHIFT) + o_j  mod 2^P_W     (lattice cell . fraction)
//   v    = lattice values at the 8 cell corners (noise_hash), w/dw = blend weights (noise_blend)
//   n    = trilinear blend of v with the weights, x first, then y, then z (lerp)
//   an   = (a n) >> AN_SHIFT
//   g_x  = (lerp(lerp(dx00, dx10, wy), lerp(dx01, dx11, wy), wz) dw_x) >> P_FRAC, dx = v1jk - v0jk
//   g_y  = (lerp(e10 - e00, e11 - e01, wz) dw_y) >> P_FRAC, g_z = ((fz1 - fz0) dw_z) >> P_FRAC
//   h_k  = (sum_j g_j T_jk) >> H_SHIFT,   ag_k = (a h_k) >> A_FRAC
// Every ">>" is a floor (arithmetic shift right of a signed word); a negative shift
// count is a left shift.
//
// Formats (`CFG_* widths from tex_cfg.vh, config/<name>.toml):
//   s_in   3 x s{S_W}.{S_FRAC}, {r, t, s} (s at the LSBs)
//   a_in   s{A_W}.{A_FRAC}
//   t_in   9 x s{T_W}.{T_FRAC}, T[j][k] at element 3*j + k
//   o_in   3 x u{O_W}.{P_FRAC} (O_W = P_W = HASH_BITS + P_FRAC: a phase mod the lattice period)
//   an_out s{AN_W}.{F_FRAC};  ag_out 3 x s{AG_W}.{C_FRAC} (all 0 when `CFG_NOISE_GRADIENT = 0)
// Internal: p u{P_W}.{P_FRAC}; v, e, fz, n s{N_W}.{N_FRAC}; differences s{N_W+1}.{N_FRAC};
//   w, dw s{BLEND_W}.{P_FRAC} in [0, 1.5]; g s{GN_W}.{N_FRAC}; h s{H_W}.{C_FRAC + A_FRAC}.
//   T s only matters mod 2^(TS_SHIFT + P_W) (p wraps), so the transform products are
//   only that wide.
//
// Transform (`CFG_TRANSFORM): affine (0) uses multipliers for T s and g T. pow2 (1):
// T is diagonal with entries 0 or 2^e (model/quantize.py guarantees it; the
// off-diagonal entries are ignored), so T_jj s_j and g_j T_jj are barrel shifts by
// e = the priority-encoded highest set bit of T_jj (0 when T_jj = 0); no multipliers.
//
// Amplitude (`CFG_AMPLITUDE): any (0) uses multipliers for a n and a h. pow2 (1): a is
// 0 or +-2^e (model/quantize.py guarantees it), e in 0..A_W-2 for a > 0 and 0..A_W-1
// for a < 0 (-2^(A_W-1), the format's most negative value, is legal). a_in is decoded
// once, combinationally, into ac_in = {zero, neg, e} (1 + 1 + EA_W bits, EA_W =
// clog2(A_W)): e = the lowest set bit of a_in (2^e has bit e alone, -2^e bits e..A_W-1),
// neg = the sign bit. Stage 8 then forms sign(a) n as s{N_W+1} and sign(a) h_k as
// s{H_W+1} (a conditional negation, 0 when a = 0; one extra bit so that even the most
// negative word negates exactly), shifts it left by e in the A_W + N_W (A_W + H_W) bit
// product word (|a n| <= 2^(A_W-1) 2^(N_W-1) < 2^(A_W+N_W-1): no overflow) and takes
// the same floor shift (>> AN_SHIFT, >> A_FRAC) as the multiplier path: the products
// are exactly a n and a h_k, so the results equal the golden model's for every n, h
// and legal a. No multipliers.
//
// Pipeline (LATENCY = `LAT_NOISE_TERM = 8 register stages, one vector per enabled clock):
//   1  transform products T_jk s_k (pow2: shifts)
//   2  p = sum + o -> cell ip, fraction fp
//   3  noise_hash (3 ROM levels) -> 8 corner values; noise_blend -> w, dw
//   4  x lerps -> e (4); gradient: dx and their y lerps (2)
//   5  y lerps -> fz (2); gradient: z lerps of the x and y differences
//   6  z lerp -> n; gradient: g = (. dw) >> P_FRAC (cubic; linear: dw = 1, a wire)
//   7  h = (g T) >> H_SHIFT (pow2: shifts); n delayed
//   8  an = (a n) >> AN_SHIFT, ag = (a h) >> A_FRAC (pow2: shifts; output registers)
//
// Parameters: a_in, t_in, o_in are per-pass parameters, not per-vector data. No
// register carries them down the pipeline: each is read directly by the stage that
// needs it (t_in by stages 1 and 7, o_in by stage 2, a_in by stage 8; pow2 T and a
// through their combinational decoders, tc_in and ac_in).
// CONTRACT: a_in, t_in, o_in must be stable from the first vector's entry until the
// last vector's exit; texture_pipeline guarantees it: parameters are written only
// when the pipeline is empty (between passes). Changing them with vectors in flight
// gives those vectors a mixture of old and new parameters.
// ce = 0 holds every register. rst clears the valid chain and the output registers
// (the output registers load only with a valid vector, so no X reaches the outputs).
//
// Multipliers per term (affine, cubic, any amplitude, gradient): 9 T s + 6 blend +
// 7 value lerps + 4 gradient lerps + 3 slopes + 9 g T + 1 a n + 3 a h = 42; pow2 T,
// linear, any amplitude: 7 + 4 + 1 + 3 = 15; pow2 T, linear, pow2 amplitude (reduced):
// 7 + 4 = 11 (the lerps only).

`default_nettype none

`include "tex_cfg.vh"
`include "tex_latency.vh"

module noise_term (
    input  wire                      clk,
    input  wire                      rst,
    input  wire                      ce,
    input  wire                      in_valid,
    input  wire [3*`CFG_S_W-1:0]     s_in,
    input  wire [`CFG_A_W-1:0]       a_in,
    input  wire [9*`CFG_T_W-1:0]     t_in,
    input  wire [3*`CFG_O_W-1:0]     o_in,
    output wire                      out_valid,
    output wire [`CFG_AN_W-1:0]      an_out,
    output wire [3*`CFG_AG_W-1:0]    ag_out
);

// ---------------------------------------------------------------------------
// Formats and derived widths (all from the configuration)

localparam STAGES   = 8;                    // register stages of this implementation
localparam LATENCY  = `LAT_NOISE_TERM;      // must equal STAGES (checked below)
localparam AFFINE   = (`CFG_TRANSFORM == 0);
localparam CUBIC    = (`CFG_BLEND == 1);
localparam GRAD     = (`CFG_NOISE_GRADIENT != 0);
localparam AMP_POW2 = (`CFG_AMPLITUDE == 1);

localparam S_W      = `CFG_S_W;
localparam T_W      = `CFG_T_W;
localparam A_W      = `CFG_A_W;
localparam A_FRAC   = `CFG_A_FRAC;
localparam O_W      = `CFG_O_W;
localparam P_W      = `CFG_P_W;
localparam P_FRAC   = `CFG_P_FRAC;
localparam HB       = `CFG_HASH_BITS;
localparam N_W      = `CFG_N_W;
localparam GN_W     = `CFG_GN_W;
localparam BW       = `CFG_BLEND_W;
localparam AN_W     = `CFG_AN_W;
localparam H_W      = `CFG_H_W;
localparam AG_W     = `CFG_AG_W;
localparam TS_SHIFT = `CFG_TS_SHIFT;        // s_frac + t_frac - p_frac >= 0
localparam AN_SHIFT = `CFG_AN_SHIFT;        // a_frac + n_frac - f_frac
localparam H_SHIFT  = `CFG_H_SHIFT;         // n_frac + t_frac - c_frac

localparam D_W      = N_W + 1;              // difference of two lattice-range values
localparam ACC_W    = TS_SHIFT + P_W;       // T s mod 2^ACC_W decides p
localparam MUL_W    = (ACC_W > T_W) ? ((ACC_W > S_W) ? ACC_W : S_W) : ((T_W > S_W) ? T_W : S_W);
localparam NPROD    = AFFINE ? 9 : 3;       // transform products per vector
localparam E_W      = $clog2(T_W - 1);      // pow2 shift amount 0..T_W-2
localparam TC_W     = AFFINE ? 9*T_W : 3*(E_W + 1);  // T as the gradient stage reads it
// h: sum of three g T products, then the shift; ag and an likewise
localparam HS_W     = GN_W + T_W + 2;
localparam HX_W     = HS_W + ((H_SHIFT < 0) ? -H_SHIFT : 0);
localparam ANP_W    = A_W + N_W;
localparam ANX_W    = ANP_W + ((AN_SHIFT < 0) ? -AN_SHIFT : 0);
localparam AGP_W    = A_W + H_W;
localparam EA_W     = $clog2(A_W);          // pow2 amplitude shift 0..A_W-1
localparam AC_W     = AMP_POW2 ? EA_W + 2 : A_W;   // a as stage 8 reads it

generate
    if (LATENCY != STAGES) begin : g_latency_mismatch
        // elaboration error on purpose: rtl/tex_latency.vh and this block disagree
        noise_term_latency_mismatch_see_tex_latency_vh u_error ();
    end
endgenerate

genvar gj, gk;

// ---------------------------------------------------------------------------
// Valid chain

reg [STAGES-1:0] valid_reg;
always @(posedge clk) begin
    if (rst) begin
        valid_reg <= {STAGES{1'b0}};
    end else if (ce) begin
        valid_reg <= {valid_reg[STAGES-2:0], in_valid};
    end
end
assign out_valid = valid_reg[STAGES-1];

// ---------------------------------------------------------------------------
// Parameters, stable for the whole pass (see the contract in the header): read
// directly where needed, not pipelined

wire [AC_W-1:0] ac_in;              // a as stage 8 needs it (any: a; pow2: {zero, neg, e})
wire [TC_W-1:0] tc_in;              // T as the gradient stage (7) needs it

generate
    if (AMP_POW2) begin : g_a_pow2
        // a = 2^e has bit e alone set, a = -2^e bits e..A_W-1 (-2^(A_W-1): bit A_W-1
        // alone): either way e is the lowest set bit, and neg the sign bit
        wire                zero = (a_in == {A_W{1'b0}});
        reg     [EA_W-1:0]  e;
        integer             i;
        // priority encoder: the lowest set bit of a (0 when a = 0)
        always @* begin
            e = {EA_W{1'b0}};
            for (i = A_W - 1; i >= 0; i = i - 1) begin
                if (a_in[i]) e = i[EA_W-1:0];
            end
        end
        assign ac_in = {zero, a_in[A_W-1], e};
    end else begin : g_a_any
        assign ac_in = a_in;
    end
endgenerate

// ---------------------------------------------------------------------------
// Stage 1: transform products (mod 2^ACC_W)

reg  [NPROD*ACC_W-1:0] prod_reg;
wire [NPROD*ACC_W-1:0] prod_next;

generate
    if (AFFINE) begin : g_s1_affine
        for (gj = 0; gj < 3; gj = gj + 1) begin : g_row
            for (gk = 0; gk < 3; gk = gk + 1) begin : g_col
                wire signed [T_W-1:0]   t_jk = t_in[(3*gj + gk)*T_W +: T_W];
                wire signed [S_W-1:0]   s_k  = s_in[gk*S_W +: S_W];
                // operands sign-extended to MUL_W: the low MUL_W bits of the product
                wire signed [MUL_W-1:0] prod = t_jk * s_k;
                assign prod_next[(3*gj + gk)*ACC_W +: ACC_W] = prod[ACC_W-1:0];
                if (MUL_W > ACC_W) begin : g_unused
                    // above bit ACC_W the product does not reach p (p wraps mod 2^P_W)
                    wire unused_prod = &{1'b0, prod[MUL_W-1:ACC_W]};
                end
            end
        end
        assign tc_in = t_in;
    end else begin : g_s1_pow2
        for (gj = 0; gj < 3; gj = gj + 1) begin : g_diag
            wire signed [T_W-1:0]   t_jj = t_in[(4*gj)*T_W +: T_W];
            wire                    zero = (t_jj == {T_W{1'b0}});
            reg         [E_W-1:0]   e;
            integer                 i;
            // priority encoder: the highest set bit of T_jj (T_jj = 2^e by construction)
            always @* begin
                e = {E_W{1'b0}};
                for (i = 0; i < T_W - 1; i = i + 1) begin
                    if (t_jj[i]) e = i[E_W-1:0];
                end
            end
            wire signed [S_W-1:0]   s_j  = s_in[gj*S_W +: S_W];
            // sign-extended to MUL_W + 1 bits (>= ACC_W + 1)
            wire signed [MUL_W:0]   s_ext = {{(MUL_W+1-S_W){s_j[S_W-1]}}, s_j};
            wire signed [MUL_W:0]   shl  = s_ext <<< e;   // T_jj s_j mod 2^(MUL_W+1)
            assign prod_next[gj*ACC_W +: ACC_W] = zero ? {ACC_W{1'b0}} : shl[ACC_W-1:0];
            assign tc_in[gj*(E_W+1) +: E_W+1] = {zero, e};
            // above bit ACC_W the product does not reach p (p wraps mod 2^P_W)
            wire unused_shl = &{1'b0, shl[MUL_W:ACC_W]};
        end
        // the quantizer guarantees a diagonal T: the off-diagonal entries are not read
        wire unused_offdiag = &{1'b0, t_in[1*T_W +: 3*T_W], t_in[5*T_W +: 3*T_W]};
    end
endgenerate

always @(posedge clk) begin
    if (ce) begin
        prod_reg <= prod_next;
    end
end

// ---------------------------------------------------------------------------
// Stage 2: p = (T s >> TS_SHIFT) + o mod 2^P_W -> cell and fraction

reg [3*HB-1:0]     ip_reg;
reg [3*P_FRAC-1:0] fp_reg;

generate
    for (gj = 0; gj < 3; gj = gj + 1) begin : g_s2
        wire [ACC_W-1:0] acc;
        if (AFFINE) begin : g_sum
            assign acc = prod_reg[(3*gj)*ACC_W +: ACC_W] + prod_reg[(3*gj + 1)*ACC_W +: ACC_W]
                       + prod_reg[(3*gj + 2)*ACC_W +: ACC_W];
        end else begin : g_diag
            assign acc = prod_reg[gj*ACC_W +: ACC_W];
        end
        wire [P_W-1:0] p = acc[ACC_W-1:TS_SHIFT] + o_in[gj*O_W +: P_W];
        if (TS_SHIFT > 0) begin : g_unused
            // the fraction dropped by the floor shift
            wire unused_acc = &{1'b0, acc[TS_SHIFT-1:0]};
        end
        always @(posedge clk) begin
            if (ce) begin
                ip_reg[gj*HB +: HB]         <= p[P_W-1:P_FRAC];
                fp_reg[gj*P_FRAC +: P_FRAC] <= p[P_FRAC-1:0];
            end
        end
    end
endgenerate

// ---------------------------------------------------------------------------
// Stage 3: lattice values at the 8 corners; blend weights and slopes

reg [8*N_W-1:0] v_reg;     // corner (i, j, k) at element 4*i + 2*j + k
reg [3*BW-1:0]  w_reg;     // weights x, y, z
wire [8*N_W-1:0] v_next;
wire [3*BW-1:0]  w_next;
wire [3*BW-1:0]  dw_next;

noise_hash u_hash (
    .ix(ip_reg[0 +: HB]),
    .iy(ip_reg[HB +: HB]),
    .iz(ip_reg[2*HB +: HB]),
    .v_out(v_next)
);

generate
    for (gj = 0; gj < 3; gj = gj + 1) begin : g_blend
        noise_blend #(
            .BLEND(`CFG_BLEND),
            .P_FRAC(P_FRAC),
            .BW(BW)
        ) u_blend (
            .fp(fp_reg[gj*P_FRAC +: P_FRAC]),
            .w(w_next[gj*BW +: BW]),
            .dw(dw_next[gj*BW +: BW])
        );
    end
endgenerate

always @(posedge clk) begin
    if (ce) begin
        v_reg <= v_next;
        w_reg <= w_next;
    end
end

wire signed [BW-1:0] wx = w_reg[0 +: BW];
wire signed [BW-1:0] wy = w_reg[BW +: BW];
wire signed [BW-1:0] wz = w_reg[2*BW +: BW];

// ---------------------------------------------------------------------------
// Stage 4: x lerps e[j][k] = lerp(v0jk, v1jk, wx)

reg  [4*N_W-1:0] e_reg;    // e[j][k] at element 2*j + k
reg  [2*BW-1:0]  w4_reg;   // {wz, wy}
wire [4*N_W-1:0] e_next;

generate
    for (gj = 0; gj < 4; gj = gj + 1) begin : g_lerp_x
        lerp #(.W(N_W), .TW(BW), .P_FRAC(P_FRAC)) u_lerp (
            .a(v_reg[gj*N_W +: N_W]),
            .b(v_reg[(4 + gj)*N_W +: N_W]),
            .t(wx),
            .y(e_next[gj*N_W +: N_W])
        );
    end
endgenerate

always @(posedge clk) begin
    if (ce) begin
        e_reg  <= e_next;
        w4_reg <= {wz, wy};
    end
end

wire signed [BW-1:0] wy4 = w4_reg[0 +: BW];
wire signed [BW-1:0] wz4 = w4_reg[BW +: BW];

// ---------------------------------------------------------------------------
// Stage 5: y lerps fz[k] = lerp(e0k, e1k, wy)

reg  [2*N_W-1:0] fz_reg;
reg  [BW-1:0]    wz5_reg;
wire [2*N_W-1:0] fz_next;

generate
    for (gk = 0; gk < 2; gk = gk + 1) begin : g_lerp_y
        lerp #(.W(N_W), .TW(BW), .P_FRAC(P_FRAC)) u_lerp (
            .a(e_reg[gk*N_W +: N_W]),
            .b(e_reg[(2 + gk)*N_W +: N_W]),
            .t(wy4),
            .y(fz_next[gk*N_W +: N_W])
        );
    end
endgenerate

always @(posedge clk) begin
    if (ce) begin
        fz_reg  <= fz_next;
        wz5_reg <= wz4;
    end
end

wire signed [BW-1:0]  wz5 = wz5_reg;
wire signed [N_W-1:0] fz0 = fz_reg[0 +: N_W];
wire signed [N_W-1:0] fz1 = fz_reg[N_W +: N_W];

// ---------------------------------------------------------------------------
// Stage 6: z lerp n = lerp(fz0, fz1, wz)

reg  [N_W-1:0] n_reg;
wire [N_W-1:0] n_next;

lerp #(.W(N_W), .TW(BW), .P_FRAC(P_FRAC)) u_lerp_z (
    .a(fz0),
    .b(fz1),
    .t(wz5),
    .y(n_next)
);

always @(posedge clk) begin
    if (ce) n_reg <= n_next;
end

// ---------------------------------------------------------------------------
// Stage 7: n delayed (the gradient's h is computed here)

reg [N_W-1:0] n7_reg;
always @(posedge clk) begin
    if (ce) n7_reg <= n_reg;
end

// ---------------------------------------------------------------------------
// Stage 8: an = (a n) >> AN_SHIFT (output register)

wire signed [N_W-1:0]   n8 = n7_reg;
wire signed [ANX_W-1:0] an_prod;              // a n, exact: A_W + N_W bits
wire signed [ANX_W-1:0] an_sh;
generate
    if (AMP_POW2) begin : g_an_pow2
        // a n = sign(a) n << e (0 when a = 0)
        wire                    zero  = ac_in[EA_W + 1];
        wire                    neg   = ac_in[EA_W];
        wire        [EA_W-1:0]  e     = ac_in[EA_W-1:0];
        wire signed [N_W:0]     n_ext = {n8[N_W-1], n8};
        wire signed [N_W:0]     n_sgn = zero ? {(N_W+1){1'b0}} : (neg ? -n_ext : n_ext);
        wire signed [ANX_W-1:0] n_sx  = {{(ANX_W-N_W-1){n_sgn[N_W]}}, n_sgn};
        assign an_prod = n_sx <<< e;
    end else begin : g_an_any
        wire signed [A_W-1:0] a_s = ac_in;
        assign an_prod = a_s * n8;
    end
    if (AN_SHIFT >= 0) begin : g_an_r
        assign an_sh = an_prod >>> AN_SHIFT;
    end else begin : g_an_l
        assign an_sh = an_prod <<< (-AN_SHIFT);
    end
    if (ANX_W > AN_W) begin : g_an_unused
        // an fits AN_W bits (model/config.py bound); the rest are sign copies
        wire unused_an = &{1'b0, an_sh[ANX_W-1:AN_W]};
    end
endgenerate

reg [AN_W-1:0] an_reg;
always @(posedge clk) begin
    if (rst) begin
        an_reg <= {AN_W{1'b0}};
    end else if (ce && valid_reg[STAGES-2]) begin
        an_reg <= an_sh[AN_W-1:0];
    end
end
assign an_out = an_reg;

// ---------------------------------------------------------------------------
// Gradient: stages 4..8 beside the value path

generate
    if (GRAD) begin : g_grad
        // slopes dw delayed to stage 6 (cubic only; linear: dw = 1, unused)
        reg  [3*BW-1:0] dw3_reg, dw4_reg, dw5_reg;
        always @(posedge clk) begin
            if (ce) begin
                dw3_reg <= dw_next;
                dw4_reg <= dw3_reg;
                dw5_reg <= dw4_reg;
            end
        end

        // stage 4: dx[j][k] = v1jk - v0jk; dxy[k] = lerp(dx0k, dx1k, wy)
        wire [4*D_W-1:0] dx;
        for (gj = 0; gj < 4; gj = gj + 1) begin : g_dx
            wire        [N_W-1:0] v0_w = v_reg[gj*N_W +: N_W];
            wire        [N_W-1:0] v1_w = v_reg[(4 + gj)*N_W +: N_W];
            wire signed [D_W-1:0] v0 = {v0_w[N_W-1], v0_w};   // sign-extended
            wire signed [D_W-1:0] v1 = {v1_w[N_W-1], v1_w};
            assign dx[gj*D_W +: D_W] = v1 - v0;
        end
        wire [2*D_W-1:0] dxy_next;
        reg  [2*D_W-1:0] dxy_reg;
        for (gk = 0; gk < 2; gk = gk + 1) begin : g_dxy
            lerp #(.W(D_W), .TW(BW), .P_FRAC(P_FRAC)) u_lerp (
                .a(dx[gk*D_W +: D_W]),
                .b(dx[(2 + gk)*D_W +: D_W]),
                .t(wy),
                .y(dxy_next[gk*D_W +: D_W])
            );
        end
        always @(posedge clk) begin
            if (ce) dxy_reg <= dxy_next;
        end

        // stage 5: gxl = lerp(dxy0, dxy1, wz); gyl = lerp(e10 - e00, e11 - e01, wz)
        wire [D_W-1:0] gxl_next, gyl_next;
        lerp #(.W(D_W), .TW(BW), .P_FRAC(P_FRAC)) u_lerp_gx (
            .a(dxy_reg[0 +: D_W]),
            .b(dxy_reg[D_W +: D_W]),
            .t(wz4),
            .y(gxl_next)
        );
        wire [2*D_W-1:0] ey;
        for (gk = 0; gk < 2; gk = gk + 1) begin : g_ey
            wire        [N_W-1:0] e0_w = e_reg[gk*N_W +: N_W];
            wire        [N_W-1:0] e1_w = e_reg[(2 + gk)*N_W +: N_W];
            wire signed [D_W-1:0] e0 = {e0_w[N_W-1], e0_w};   // sign-extended
            wire signed [D_W-1:0] e1 = {e1_w[N_W-1], e1_w};
            assign ey[gk*D_W +: D_W] = e1 - e0;
        end
        lerp #(.W(D_W), .TW(BW), .P_FRAC(P_FRAC)) u_lerp_gy (
            .a(ey[0 +: D_W]),
            .b(ey[D_W +: D_W]),
            .t(wz4),
            .y(gyl_next)
        );
        reg [D_W-1:0] gxl_reg, gyl_reg;
        always @(posedge clk) begin
            if (ce) begin
                gxl_reg <= gxl_next;
                gyl_reg <= gyl_next;
            end
        end

        // stage 6: g_j = (gl_j dw_j) >> P_FRAC, gl_z = fz1 - fz0
        wire signed [D_W-1:0] fz0_ext = {fz0[N_W-1], fz0};   // sign-extended
        wire signed [D_W-1:0] fz1_ext = {fz1[N_W-1], fz1};
        wire        [3*D_W-1:0] gl = {fz1_ext - fz0_ext, gyl_reg, gxl_reg};
        wire        [3*GN_W-1:0] g_next;
        reg         [3*GN_W-1:0] g_reg;
        for (gj = 0; gj < 3; gj = gj + 1) begin : g_slope
            wire signed [D_W-1:0] gl_j = gl[gj*D_W +: D_W];
            if (CUBIC) begin : g_cubic
                wire signed [BW-1:0]       dw_j = dw5_reg[gj*BW +: BW];
                wire signed [D_W+BW-1:0]   prod = gl_j * dw_j;   // exact
                wire signed [D_W+BW-1:0]   sh   = prod >>> P_FRAC;
                assign g_next[gj*GN_W +: GN_W] = sh[GN_W-1:0];
                // |g| <= 3 * 2^N_FRAC fits GN_W bits; the rest are sign copies
                wire unused_sh = &{1'b0, sh[D_W+BW-1:GN_W]};
            end else begin : g_linear
                // dw = 2^P_FRAC: (gl dw) >> P_FRAC = gl
                wire signed [GN_W-1:0] gl_ext = gl_j;
                assign g_next[gj*GN_W +: GN_W] = gl_ext;
            end
        end
        if (!CUBIC) begin : g_dw_unused
            wire unused_dw = &{1'b0, dw5_reg};
        end
        always @(posedge clk) begin
            if (ce) g_reg <= g_next;
        end

        // stage 7: h_k = (sum_j g_j T_jk) >> H_SHIFT
        wire [3*H_W-1:0] h_next;
        reg  [3*H_W-1:0] h_reg;
        for (gk = 0; gk < 3; gk = gk + 1) begin : g_h
            wire signed [HX_W-1:0] hsum;
            if (AFFINE) begin : g_affine
                wire signed [T_W-1:0]  t0 = tc_in[(0 + gk)*T_W +: T_W];
                wire signed [T_W-1:0]  t1 = tc_in[(3 + gk)*T_W +: T_W];
                wire signed [T_W-1:0]  t2 = tc_in[(6 + gk)*T_W +: T_W];
                wire signed [GN_W-1:0] g0 = g_reg[0 +: GN_W];
                wire signed [GN_W-1:0] g1 = g_reg[GN_W +: GN_W];
                wire signed [GN_W-1:0] g2 = g_reg[2*GN_W +: GN_W];
                wire signed [HX_W-1:0] p0 = g0 * t0;
                wire signed [HX_W-1:0] p1 = g1 * t1;
                wire signed [HX_W-1:0] p2 = g2 * t2;
                assign hsum = p0 + p1 + p2;
            end else begin : g_pow2
                // g_k T_kk = g_k << e_k, or 0
                wire                   zero = tc_in[gk*(E_W+1) + E_W];
                wire        [E_W-1:0]  e    = tc_in[gk*(E_W+1) +: E_W];
                wire signed [GN_W-1:0] g_k  = g_reg[gk*GN_W +: GN_W];
                wire signed [HX_W-1:0] g_ext = {{(HX_W-GN_W){g_k[GN_W-1]}}, g_k};
                assign hsum = zero ? {HX_W{1'b0}} : (g_ext <<< e);
            end
            wire signed [HX_W-1:0] hsh;
            if (H_SHIFT >= 0) begin : g_r
                assign hsh = hsum >>> H_SHIFT;
            end else begin : g_l
                assign hsh = hsum <<< (-H_SHIFT);
            end
            assign h_next[gk*H_W +: H_W] = hsh[H_W-1:0];
            if (HX_W > H_W) begin : g_unused
                // h fits H_W bits (model/config.py bound); the rest are sign copies
                wire unused_h = &{1'b0, hsh[HX_W-1:H_W]};
            end
        end
        always @(posedge clk) begin
            if (ce) h_reg <= h_next;
        end

        // stage 8: ag_k = (a h_k) >> A_FRAC (output registers)
        reg [3*AG_W-1:0] ag_reg;
        for (gk = 0; gk < 3; gk = gk + 1) begin : g_ag
            wire signed [H_W-1:0]   h_k  = h_reg[gk*H_W +: H_W];
            wire signed [AGP_W-1:0] prod;               // a h_k, exact
            if (AMP_POW2) begin : g_pow2
                // a h_k = sign(a) h_k << e (0 when a = 0)
                wire                    zero  = ac_in[EA_W + 1];
                wire                    neg   = ac_in[EA_W];
                wire        [EA_W-1:0]  e     = ac_in[EA_W-1:0];
                wire signed [H_W:0]     h_ext = {h_k[H_W-1], h_k};
                wire signed [H_W:0]     h_sgn = zero ? {(H_W+1){1'b0}} : (neg ? -h_ext : h_ext);
                wire signed [AGP_W-1:0] h_sx  = {{(AGP_W-H_W-1){h_sgn[H_W]}}, h_sgn};
                assign prod = h_sx <<< e;
            end else begin : g_any
                wire signed [A_W-1:0] a_s = ac_in;
                assign prod = a_s * h_k;
            end
            wire signed [AGP_W-1:0] sh   = prod >>> A_FRAC;
            always @(posedge clk) begin
                if (rst) begin
                    ag_reg[gk*AG_W +: AG_W] <= {AG_W{1'b0}};
                end else if (ce && valid_reg[STAGES-2]) begin
                    ag_reg[gk*AG_W +: AG_W] <= sh[AG_W-1:0];
                end
            end
            if (AGP_W > AG_W) begin : g_unused
                // ag fits AG_W bits (model/config.py bound); the rest are sign copies
                wire unused_ag = &{1'b0, sh[AGP_W-1:AG_W]};
            end
        end
        assign ag_out = ag_reg;
    end else begin : g_no_grad
        assign ag_out = {3*AG_W{1'b0}};
        // without the gradient, dw, the T codes and the difference terms are not needed
        wire unused_grad = &{1'b0, dw_next, tc_in};
    end
endgenerate

endmodule

`default_nettype wire
