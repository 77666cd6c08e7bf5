// noise_fold: the K noise terms of a pixel on U noise units, U terms a clock.
//
// Computes, for each pixel (s, side),
//   f_sum = sum_{k < K_used} a_k n(T_k s + o_k)          (noise_term's an, exact)
//   c_sum = sum_{k < K_used} a_k (dn_k/dp) T_k           (noise_term's ag, exact; 0 without
//                                                         the noise gradient)
// the same sums texture_pipeline's parallel terms and adder tree form (the sums are exact
// two's complement sums, so their order does not change a bit: the golden model's
// texture_stages is the twin for every U). Terms k >= K_used are skipped: a pixel takes
// P = max(MIN_CLOCKS, ceil(K_used / U)) clocks, so a texture with fewer terms costs fewer clocks
// (MIN_CLOCKS = 2 or 6 where the quadric MAC takes two or six clocks a pixel).
//
// Schedule: a pixel is taken into hold registers (s and `side`, the data that travel with
// it: texture_pipeline's Jm, je and tlast); on the next P enabled clocks, issue j = 0..P-1
// gives unit u term k = j U + u (its a forced to 0 when k >= K_used) with that term's
// parameters, which travel down the unit with the vector (noise_term PARAM_PIPE = 1). The
// last issue clock is the pixel's exit from the fold stage: px_valid is high, px_s and
// px_side hold it (texture_pipeline starts the quadric and the delay lines there), and the
// next pixel may be taken in the same clock (in_ready), so a pixel enters every P clocks.
// FPGA_REGS: each unit's term parameters, selected by the issue index, are registered with
// the vector and its valid before the unit (the term select off the unit's first stage), and
// whether an issue is the pixel's last is a register beside the issue index (no k_used
// decode on the path to in_ready; k_used is read when a pixel is taken and as it issues).
// The units' outputs are summed over the units and accumulated over the P issues (tags
// first / last travel with the vectors); f_sum, c_sum and sum_valid appear LATENCY =
// `LAT_NOISE_TERM + `LAT_NOISE_FOLD (FPGA_REGS: `LAT_NOISE_TERM_FPGA + `LAT_NOISE_FOLD_FPGA)
// enabled clocks after the pixel's px_valid.
//
// Formats: s_in 3 x s{S_W}.{S_FRAC}; a_all, t_all, o_all: term k's {ae, a} at [k*AS_W +: AS_W],
// {te, T} at [k*TS_W +: TS_W], o at [3*k*O_W +: 3*O_W] (as texture_pipeline's parameter
// registers, tex_regs; AS_W = A_W + A_EXP_W, TS_W = 9*T_W + T_EXP_W: the exponents te, ae
// only with T_EXP_W, A_EXP_W > 0, noise_term's a_in and t_in; a term past k_used gets {ae, a} = 0);
// k_used u{KU_W}.0 (0..K); f_sum s{F_W}.{F_FRAC}, c_sum 3 x s{C_W}.{C_FRAC} (F_W, C_W: the
// exact-sum widths of texture_pipeline, which hold K terms and the quadric).
// Throughput: one pixel per P enabled clocks. in_ready is a function of registers only.
// ce = 0 holds every register; rst (synchronous) empties the fold (no pixel, no sum in
// flight). k_used and the parameters must be stable while pixels are in flight (they are
// texture_pipeline's per-pass registers).

`default_nettype none

`include "tex_latency.vh"

module noise_fold #(
    // noise_term's formats and modes (config/<name>.toml keys in brackets)
    parameter S_W            = 19,  // [s_w]
    parameter S_FRAC         = 11,  // [s_frac]
    parameter T_W            = 13,  // [t_w]
    parameter T_FRAC         = 6,   // [t_frac]
    parameter A_W            = 8,   // [a_w]
    parameter A_FRAC         = 5,   // [a_frac]
    parameter P_FRAC         = 8,   // [p_frac]
    parameter HASH_BITS      = 5,   // [hash_bits]
    parameter N_FRAC         = 9,   // [n_frac]
    parameter F_FRAC         = 11,  // [f_frac]
    parameter C_FRAC         = 6,   // [c_frac]
    parameter TRANSFORM      = 1,   // [transform] 0 affine, 1 pow2
    parameter BLEND          = 1,   // [blend] 0 linear, 1 cubic
    parameter AMPLITUDE      = 1,   // [amplitude] 0 any, 1 pow2
    parameter NOISE_GRADIENT = 1,   // [noise_gradient]
    parameter NOISE_TERMS    = 8,   // [noise_terms] K: parameter sets (1..8)
    parameter NOISE_UNITS    = 1,   // [noise_units] U: noise_term instances (1..K)
    parameter F_W            = 32,  // f_sum word (texture_pipeline's exact-sum width)
    parameter C_W            = 24,  // c_sum element word (likewise)
    parameter SIDE_W         = 1,   // data that travel with a pixel (held, not read)
    parameter MIN_CLOCKS     = 1,   // [quadric_clocks] a pixel takes at least this many clocks (>= 1)
    parameter FPGA_REGS      = 0,   // [fpga_regs] the noise units' extra register stages (noise_term)
    parameter T_EXP_W        = 0,   // [t_exp_w] T's per-term exponent te above its mantissas (0: none)
    parameter A_EXP_W        = 0,   // [a_exp_w] a's per-term exponent ae above its mantissa (0: none)
    parameter [HASH_BITS*(1<<HASH_BITS)-1:0] PERM = {HASH_BITS*(1<<HASH_BITS){1'b0}}  // lattice permutation
) (clk, rst, ce, in_valid, in_ready, s_in, side_in, k_used, a_all, t_all, o_all,
   px_valid, px_s, px_side, sum_valid, f_sum, c_sum);

`include "tex_widths.vh"

localparam K       = NOISE_TERMS;
localparam U       = NOISE_UNITS;
localparam NJ      = (K + U - 1) / U;                    // issues of a pixel with every term
localparam NJE     = (NJ > MIN_CLOCKS) ? NJ : MIN_CLOCKS;  // issues of a pixel at most
localparam J_W     = (NJE > 1) ? $clog2(NJE) : 1;        // issue index
localparam KU_W    = $clog2(K + 1);                      // k_used
localparam O_W     = HASH_BITS + P_FRAC;
localparam TS_W    = 9*T_W + T_EXP_W;                    // a term of t_all: {te, T}
localparam AS_W    = A_W + A_EXP_W;                      // a term of a_all: {ae, a}
localparam AN_W    = tw_an_w_e(A_W, A_FRAC, N_FRAC, F_FRAC, (1 << A_EXP_W) - 1);
localparam AG_W    = tw_ag_w_e(BLEND, TRANSFORM, T_W, T_FRAC, N_FRAC, C_FRAC, A_W, A_FRAC, (1 << T_EXP_W) - 1,
                               (1 << A_EXP_W) - 1);
localparam LAT_NT  = FPGA_REGS ? `LAT_NOISE_TERM_FPGA : `LAT_NOISE_TERM;
localparam LAT_F   = FPGA_REGS ? `LAT_NOISE_FOLD_FPGA : `LAT_NOISE_FOLD;  // the fold's own stages
localparam XR      = LAT_F - 1;                          // the parameter register (FPGA_REGS)
/* verilator lint_off UNUSEDPARAM */
localparam LATENCY = LAT_NT + LAT_F;                      // px_valid to sum_valid (for readers)
/* verilator lint_on UNUSEDPARAM */
localparam GRAD    = (NOISE_GRADIENT != 0);

input  wire                 clk;
input  wire                 rst;
input  wire                 ce;
input  wire                 in_valid;
output wire                 in_ready;
input  wire [3*S_W-1:0]     s_in;
input  wire [SIDE_W-1:0]    side_in;
input  wire [KU_W-1:0]      k_used;
input  wire [K*AS_W-1:0]    a_all;
input  wire [K*TS_W-1:0]    t_all;
input  wire [K*3*O_W-1:0]   o_all;
output wire                 px_valid;
output wire [3*S_W-1:0]     px_s;
output wire [SIDE_W-1:0]    px_side;
output wire                 sum_valid;
output wire [F_W-1:0]       f_sum;
output wire [3*C_W-1:0]     c_sum;

// elaboration fails (unknown module) on an unsupported fold
generate
    if (U < 1 || U > K || F_W < AN_W || C_W < AG_W || MIN_CLOCKS < 1) begin : g_bad_params
        noise_fold_needs_1_le_units_le_terms u_error ();
    end
endgenerate

// ---------------------------------------------------------------------------
// Issue: hold registers and the issue index

reg              busy_reg;       // the hold registers carry a pixel being issued
reg [J_W-1:0]    j_reg;          // this clock's issue
reg [3*S_W-1:0]  s_reg;
reg [SIDE_W-1:0] side_reg;

// the pixel's last issue: P - 1 = max(ceil(K_used / U), MIN_CLOCKS) - 1 (k_used is static;
// issues past the terms give every unit a = 0), a table over the K + 1 values of k_used
// (constant per entry: a LUT per bit, no arithmetic on the path to in_ready)
function [J_W-1:0] last_issue_of;
    input integer ku;
    integer q;
    begin
        q = (ku == 0) ? 0 : (ku - 1) / U;
        if (q < MIN_CLOCKS - 1) q = MIN_CLOCKS - 1;
        last_issue_of = q[J_W-1:0];  // q < NJE <= 2^J_W
    end
endfunction

reg [J_W-1:0]  j_last;
integer        kt;
always @* begin
    j_last = {J_W{1'b0}};
    for (kt = 0; kt <= K; kt = kt + 1)
        if (k_used == kt[KU_W-1:0]) j_last = last_issue_of(kt);
end

// at_last: this clock's issue is the pixel's last (j_reg == j_last). FPGA_REGS: registered
// beside j_reg (from k_used when the pixel is taken and at each issue), which takes the k_used
// table and the comparison off the path to in_ready and the pipeline's clock enables
wire at_last;
generate
    if (FPGA_REGS != 0) begin : g_at_last_reg
        reg at_last_reg;
        always @(posedge clk) begin
            if (rst)
                at_last_reg <= 1'b0;
            else if (ce) begin
                if (in_valid && in_ready)
                    at_last_reg <= (j_last == {J_W{1'b0}});
                else if (busy_reg)
                    at_last_reg <= (j_reg + 1'b1 == j_last);
            end
        end
        assign at_last = at_last_reg;
    end else begin : g_at_last
        assign at_last = (j_reg == j_last);
    end
endgenerate

wire last_issue = busy_reg && at_last;
assign in_ready = !busy_reg || at_last;
assign px_valid = last_issue;
assign px_s     = s_reg;
assign px_side  = side_reg;

always @(posedge clk) begin
    if (rst) begin
        busy_reg <= 1'b0;
        j_reg    <= {J_W{1'b0}};
    end else if (ce) begin
        if (in_valid && in_ready) begin
            busy_reg <= 1'b1;
            j_reg    <= {J_W{1'b0}};
        end else if (last_issue) begin
            busy_reg <= 1'b0;
        end else if (busy_reg) begin
            j_reg <= j_reg + 1'b1;
        end
    end
    if (ce && in_valid && in_ready) begin
        s_reg    <= s_in;
        side_reg <= side_in;
    end
end

`ifdef FORMAL
// ---------------------------------------------------------------------------
// Formal properties (Yosys `read -formal`; make formal, formal/: noise_term cut to free outputs).
// Under any pattern of ce (the pipeline's stalls), in_valid (gaps) and rst, with k_used <= K and
// stable while a pixel issues (assumed: the header's contract): a pixel taken with k_used terms
// has exactly P = max(MIN_CLOCKS, ceil(k_used / U)) issue slots (enabled clocks), counted here as
// f_n; issue f_n gives unit u term f_n U + u (its a zeroed past k_used), so every term
// k < k_used is issued once (f_issued) and none is skipped; px_valid marks the last slot, and
// in_ready = !busy || last slot (the header's rule).
reg          f_past_valid = 1'b0;
reg [7:0]    f_n;         // issue slots of the held pixel so far
reg [K-1:0]  f_issued;    // its terms issued so far
wire [7:0]   f_ku   = {{(8-KU_W){1'b0}}, k_used};
// P of each k_used: max(MIN_CLOCKS, ceil(k_used / U)), at elaboration
function integer f_slots;
    input integer ku;
    begin
        f_slots = (ku + U - 1) / U;
        if (f_slots < MIN_CLOCKS) f_slots = MIN_CLOCKS;
    end
endfunction
reg [7:0]    f_p;
integer      fq;
always @* begin
    f_p = 8'd0;
    for (fq = 0; fq <= K; fq = fq + 1)
        if (f_ku == fq) f_p = f_slots(fq);
end
wire         f_take = ce && in_valid && in_ready;
wire         f_last = (f_n == f_p - 1'b1);
reg [K-1:0]  f_now, f_used, f_before;  // terms of this slot, of the pixel, of its earlier slots
integer      fk;
always @* begin
    // term k is issued on slot k / U (unit k mod U)
    for (fk = 0; fk < K; fk = fk + 1) begin
        f_used[fk]   = (fk < f_ku);
        f_now[fk]    = (fk < f_ku) && (f_n == fk / U);
        f_before[fk] = (fk < f_ku) && (f_n > fk / U);
    end
end

always @(posedge clk) begin
    f_past_valid <= 1'b1;
    if (rst) begin
        f_n      <= 8'd0;
        f_issued <= {K{1'b0}};
    end else if (ce) begin
        if (f_take) begin
            f_n      <= 8'd0;
            f_issued <= {K{1'b0}};
        end else if (busy_reg) begin
            f_n      <= f_n + 8'd1;
            f_issued <= f_issued | f_now;
        end
    end
end

always @* begin
    if (!f_past_valid) assume(rst);
    assume(k_used <= K);
end

always @(posedge clk) begin
    // k_used is static while a pixel issues (texture_pipeline's per-pass register)
    if (f_past_valid && busy_reg)
        assume(k_used == $past(k_used));
    if (f_past_valid && !$past(rst)) begin
        // ce = 0 holds the issue state
        if (!$past(ce))
            assert(busy_reg == $past(busy_reg) && j_reg == $past(j_reg));
        // a pixel leaves the hold registers after its last slot, unless the next one is taken
        if ($past(ce && busy_reg))
            assert(busy_reg == ($past(f_take) || !$past(f_last)));
    end
end

always @* begin
    if (f_past_valid && !rst) begin
        if (busy_reg) begin
            // the issue index counts the slots, never past P
            assert(j_reg == f_n[J_W-1:0] && f_n < f_p);
            // the terms issued so far are those of the earlier slots, each once
            assert(f_issued == f_before);
            assert((f_issued & f_now) == {K{1'b0}});
            // the last slot completes the pixel's terms: none skipped
            if (f_last)
                assert((f_issued | f_now) == f_used);
        end
        // px_valid on the last slot only; in_ready: empty, or the last slot
        assert(px_valid == (busy_reg && f_last));
        assert(in_ready == (!busy_reg || f_last));
    end
end
`endif

// ---------------------------------------------------------------------------
// Units: unit u gets term j U + u (a = 0 past K_used); first / last tags beside them

wire [U*AN_W-1:0]   an_u;
wire [U*3*AG_W-1:0] ag_u;
wire                out_valid;   // unit 0's (all units share the valid)

// the vector and its valid as the units see them (FPGA_REGS: registered beside the parameters)
wire [3*S_W-1:0]    s_u;
wire                v_u;
delay_line #(.W(3*S_W), .N(XR)) u_dly_s (.clk(clk), .rst(rst), .ce(ce), .d_in(s_reg), .d_out(s_u));
delay_line #(.W(1), .N(XR), .CLEAR(1)) u_dly_v (.clk(clk), .rst(rst), .ce(ce), .d_in(busy_reg), .d_out(v_u));

genvar gu;
generate
    for (gu = 0; gu < U; gu = gu + 1) begin : g_unit
        reg [AS_W-1:0]  a_sel;
        reg [TS_W-1:0]  t_sel;
        reg [3*O_W-1:0] o_sel;
        integer         m;
        always @* begin
            a_sel = {AS_W{1'b0}};
            t_sel = {TS_W{1'b0}};
            o_sel = {3*O_W{1'b0}};
            for (m = 0; m < NJ; m = m + 1) begin
                if (j_reg == m[J_W-1:0] && m*U + gu < K) begin
                    a_sel = (m*U + gu < k_used) ? a_all[(m*U + gu)*AS_W +: AS_W] : {AS_W{1'b0}};
                    t_sel = t_all[(m*U + gu)*TS_W +: TS_W];
                    o_sel = o_all[(m*U + gu)*3*O_W +: 3*O_W];
                end
            end
        end
`ifdef FORMAL
        // the parameters this unit gets on slot f_n: those of term f_n U + u (a = 0 past
        // k_used; nothing past K)
        reg [AS_W-1:0]  f_a;
        reg [TS_W-1:0]  f_t;
        reg [3*O_W-1:0] f_o;
        integer         fm;
        always @* begin
            f_a = {AS_W{1'b0}};
            f_t = {TS_W{1'b0}};
            f_o = {3*O_W{1'b0}};
            for (fm = gu; fm < K; fm = fm + U) begin
                if (f_n == fm / U) begin
                    f_a = (fm < f_ku) ? a_all[fm*AS_W +: AS_W] : {AS_W{1'b0}};
                    f_t = t_all[fm*TS_W +: TS_W];
                    f_o = o_all[fm*3*O_W +: 3*O_W];
                end
            end
            if (f_past_valid && !rst && busy_reg)
                assert(a_sel == f_a && t_sel == f_t && o_sel == f_o);
        end
`endif
        wire [AS_W-1:0]  a_u;
        wire [TS_W-1:0]  t_u;
        wire [3*O_W-1:0] o_u;
        delay_line #(.W(AS_W + TS_W + 3*O_W), .N(XR)) u_dly_param (.clk(clk), .rst(rst), .ce(ce),
            .d_in({a_sel, t_sel, o_sel}), .d_out({a_u, t_u, o_u}));
        wire v;
        noise_term #(
            .S_W(S_W), .S_FRAC(S_FRAC), .T_W(T_W), .T_FRAC(T_FRAC), .A_W(A_W), .A_FRAC(A_FRAC),
            .P_FRAC(P_FRAC), .HASH_BITS(HASH_BITS), .N_FRAC(N_FRAC), .F_FRAC(F_FRAC), .C_FRAC(C_FRAC),
            .TRANSFORM(TRANSFORM), .BLEND(BLEND), .AMPLITUDE(AMPLITUDE), .NOISE_GRADIENT(NOISE_GRADIENT),
            .PARAM_PIPE(1), .FPGA_REGS(FPGA_REGS), .T_EXP_W(T_EXP_W), .A_EXP_W(A_EXP_W), .PERM(PERM)
        ) u_noise_term (
            .clk(clk), .rst(rst), .ce(ce),
            .in_valid(v_u),
            .s_in(s_u), .a_in(a_u), .t_in(t_u), .o_in(o_u),
            .out_valid(v),
            .an_out(an_u[gu*AN_W +: AN_W]),
            .ag_out(ag_u[gu*3*AG_W +: 3*AG_W])
        );
        if (gu == 0) begin : g_v
            assign out_valid = v;
        end else begin : g_nv
            /* verilator lint_off UNUSEDSIGNAL */
            wire unused_v = v;  // every unit's valid equals unit 0's
            /* verilator lint_on UNUSEDSIGNAL */
        end
    end
endgenerate

wire first_o, last_o;
delay_line #(.W(2), .N(LAT_NT + XR)) u_dly_tags (.clk(clk), .rst(rst), .ce(ce),
                                             .d_in({last_issue, busy_reg && j_reg == {J_W{1'b0}}}),
                                             .d_out({last_o, first_o}));

// ---------------------------------------------------------------------------
// Sum over the units, accumulated over the issues (exact: the partial sums of at most K
// terms fit F_W / C_W, whose bounds hold K terms and the quadric)

reg [F_W-1:0]   f_step;
reg [3*C_W-1:0] c_step;
reg [F_W-1:0]   f_acc_reg;
reg [3*C_W-1:0] c_acc_reg;
reg             sum_valid_reg;
integer         ui, ci, cj;

always @* begin
    f_step = {F_W{1'b0}};
    c_step = {3*C_W{1'b0}};
    for (ui = 0; ui < U; ui = ui + 1) begin
        f_step = f_step + {{(F_W-AN_W){an_u[ui*AN_W + AN_W-1]}}, an_u[ui*AN_W +: AN_W]};
        for (ci = 0; ci < 3; ci = ci + 1)
            c_step[ci*C_W +: C_W] = c_step[ci*C_W +: C_W]
                + {{(C_W-AG_W){ag_u[(3*ui+ci)*AG_W + AG_W-1]}}, ag_u[(3*ui+ci)*AG_W +: AG_W]};
    end
end

always @(posedge clk) begin
    if (rst) begin
        sum_valid_reg <= 1'b0;
        f_acc_reg     <= {F_W{1'b0}};
        c_acc_reg     <= {3*C_W{1'b0}};
    end else if (ce) begin
        sum_valid_reg <= out_valid && last_o;
        if (out_valid) begin
            f_acc_reg <= first_o ? f_step : f_acc_reg + f_step;
            for (cj = 0; cj < 3; cj = cj + 1)
                c_acc_reg[cj*C_W +: C_W] <= first_o ? c_step[cj*C_W +: C_W]
                                                    : c_acc_reg[cj*C_W +: C_W] + c_step[cj*C_W +: C_W];
        end
    end
end

assign sum_valid = sum_valid_reg;
assign f_sum     = f_acc_reg;
assign c_sum     = GRAD ? c_acc_reg : {3*C_W{1'b0}};

endmodule

`default_nettype wire
