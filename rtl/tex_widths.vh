// tex_widths.vh: the derived word widths of the texture unit, as Verilog constant functions.
//
// Included inside the body of every block that derives a width from its formats
// (quadric_mac, noise_term, filter_width, colour_map, texture_pipeline): a function
// library, no macros, no state. Each function is the Verilog twin of one line of
// model/hw/config.py _derive (worst-case magnitude bounds, docs/numerics.md), and
// tb/test_widths.py checks, for both configurations and random valid parameter sets, that
// the widths the elaborated RTL holds equal the Python derivation.
//
// Magnitudes are 64-bit unsigned (the configuration check keeps every intermediate of a
// valid configuration below 2^62); widths and shifts are integers. The arguments are the
// configuration's formats under their config/<name>.toml names (s_w, s_frac, ...).

// number of bits of a non-negative value (0 for 0)
function integer tw_bitlen;
    input [63:0] x;
    integer i;
    begin
        tw_bitlen = 0;
        for (i = 0; i < 64; i = i + 1)
            if (x[i]) tw_bitlen = i + 1;
    end
endfunction

// two's-complement word holding every integer in [-m, m] (config.py bits_signed)
function integer tw_bits_signed;
    input [63:0] m;
    begin
        tw_bits_signed = tw_bitlen(m) + 1;
    end
endfunction

// the same for a signed integer argument (bits_signed of a negative m uses |m|)
function integer tw_bits_signed_int;
    input integer m;
    integer a;
    begin
        a = (m < 0) ? -m : m;
        tw_bits_signed_int = tw_bits_signed({32'd0, a});
    end
endfunction

// unsigned word holding every integer in [0, m] (config.py bits_unsigned)
function integer tw_bits_unsigned;
    input [63:0] m;
    begin
        tw_bits_unsigned = (tw_bitlen(m) > 1) ? tw_bitlen(m) : 1;
    end
endfunction

// a bound on |x| shifted by sh: x << sh, or floor(x / 2^-sh) + 1 (config.py _shift_bound)
function [63:0] tw_shift_bound;
    input [63:0] x;
    input integer sh;
    begin
        tw_shift_bound = (sh >= 0) ? (x << sh) : ((x >> (-sh)) + 64'd1);
    end
endfunction

// 2^(w-1): the largest magnitude of a w-bit two's-complement word
function [63:0] tw_pow2m1;
    input integer w;
    begin
        tw_pow2m1 = 64'd1 << (w - 1);
    end
endfunction

// floor(sqrt(x)), bit by bit
function [63:0] tw_isqrt;
    input [63:0] x;
    reg [63:0] r;
    integer b;
    begin
        r = 64'd0;
        for (b = 31; b >= 0; b = b - 1)
            if ((r | (64'd1 << b)) * (r | (64'd1 << b)) <= x) r = r | (64'd1 << b);
        tw_isqrt = r;
    end
endfunction

// adder tree shape (sum_tree, texture_pipeline): nodes on level l of a tree of the given
// arity over n leaves (level 0: the leaves), and its levels down to one node (its latency;
// model/hw/config.py sum_tree_levels)
function integer tw_tree_nodes;
    input integer n, l, arity;
    integer i;
    begin
        tw_tree_nodes = n;
        for (i = 0; i < l; i = i + 1)
            tw_tree_nodes = (tw_tree_nodes + arity - 1) / arity;
    end
endfunction

function integer tw_tree_levels;
    input integer n, arity;
    integer m;
    begin
        tw_tree_levels = 0;
        for (m = n; m > 1; m = (m + arity - 1) / arity)
            tw_tree_levels = tw_tree_levels + 1;
    end
endfunction

// ---------------------------------------------------------------------------
// quadric: v_k = (Q x)_k and q (fraction q_frac)

// |v_k| bound; diag: 1 = diagonal quadric (v_k + Q_k3 is the factor of q)
function [63:0] tw_vmax;
    input integer diag, s_w, s_frac, q_w;
    begin
        if (diag != 0)
            tw_vmax = ((tw_pow2m1(q_w) * tw_pow2m1(s_w)) >> s_frac) + 64'd1 + 2 * tw_pow2m1(q_w);
        else
            tw_vmax = ((3 * tw_pow2m1(q_w) * tw_pow2m1(s_w)) >> s_frac) + 64'd1 + tw_pow2m1(q_w);
    end
endfunction

// |q| bound (fraction q_frac)
function [63:0] tw_qsum;
    input integer diag, s_w, s_frac, q_w;
    begin
        if (diag != 0)
            tw_qsum = ((3 * tw_pow2m1(s_w) * tw_vmax(diag, s_w, s_frac, q_w)) >> s_frac) + 64'd1 + tw_pow2m1(q_w);
        else
            tw_qsum = ((3 * tw_pow2m1(s_w) * tw_vmax(diag, s_w, s_frac, q_w)) >> s_frac) + 64'd1
                      + tw_vmax(diag, s_w, s_frac, q_w);
    end
endfunction

// v_w, qv_w: the words of v_k and q; qf_w: q with f_frac fraction bits
function integer tw_v_w;
    input integer diag, s_w, s_frac, q_w;
    begin
        tw_v_w = tw_bits_signed(tw_vmax(diag, s_w, s_frac, q_w));
    end
endfunction

function integer tw_qv_w;
    input integer diag, s_w, s_frac, q_w;
    begin
        tw_qv_w = tw_bits_signed(tw_qsum(diag, s_w, s_frac, q_w));
    end
endfunction

function integer tw_qf_w;
    input integer diag, s_w, s_frac, q_w, q_frac, f_frac;
    begin
        tw_qf_w = tw_bits_signed(tw_shift_bound(tw_qsum(diag, s_w, s_frac, q_w), f_frac - q_frac));
    end
endfunction

// |dq/ds| bound with c_frac fraction bits (2 v_k)
function [63:0] tw_cq_max;
    input integer diag, s_w, s_frac, q_w, q_frac, c_frac;
    begin
        tw_cq_max = tw_shift_bound(2 * tw_vmax(diag, s_w, s_frac, q_w), c_frac - q_frac);
    end
endfunction

// ---------------------------------------------------------------------------
// noise term: n in [-1, 1) with n_frac fraction bits, a n, a grad n

// Block floating point (formats.t_exp_w, a_exp_w; docs/numerics.md): T_i = M_i 2^(te_i -
// t_frac), a_i = A_i 2^(ae_i - a_frac); the bounds take the largest exponents te_max = 2^t_exp_w
// - 1 and ae_max = 2^a_exp_w - 1 (the *_e functions; the others are the same at te_max =
// ae_max = 0, fixed point)

// |a n| bound with f_frac fraction bits, and its word
function [63:0] tw_an_max_e;
    input integer a_w, a_frac, n_frac, f_frac, ae_max;
    begin
        tw_an_max_e = tw_shift_bound(tw_pow2m1(a_w) * (64'd1 << n_frac), ae_max - (a_frac + n_frac - f_frac));
    end
endfunction

function [63:0] tw_an_max;
    input integer a_w, a_frac, n_frac, f_frac;
    begin
        tw_an_max = tw_an_max_e(a_w, a_frac, n_frac, f_frac, 0);
    end
endfunction

function integer tw_an_w_e;
    input integer a_w, a_frac, n_frac, f_frac, ae_max;
    begin
        tw_an_w_e = tw_bits_signed(tw_an_max_e(a_w, a_frac, n_frac, f_frac, ae_max));
    end
endfunction

function integer tw_an_w;
    input integer a_w, a_frac, n_frac, f_frac;
    begin
        tw_an_w = tw_an_w_e(a_w, a_frac, n_frac, f_frac, 0);
    end
endfunction

// |h_k| = |(g T)_k| bound (fraction c_frac + a_frac): |g_j| <= 3 2^n_frac (cubic slope 1.5)
// or 2 2^n_frac (linear); pow2 T: one product per h_k, T_kk <= 2^(t_w - 2)
function [63:0] tw_h_max_e;
    input integer cubic, pow2, t_w, t_frac, n_frac, c_frac, te_max;
    reg [63:0] g, hs;
    begin
        g  = (cubic != 0) ? 3 * (64'd1 << n_frac) : 2 * (64'd1 << n_frac);
        hs = (pow2 != 0) ? (g << (t_w - 2)) : 3 * g * tw_pow2m1(t_w);
        tw_h_max_e = tw_shift_bound(hs, te_max - (n_frac + t_frac - c_frac));
    end
endfunction

function [63:0] tw_h_max;
    input integer cubic, pow2, t_w, t_frac, n_frac, c_frac;
    begin
        tw_h_max = tw_h_max_e(cubic, pow2, t_w, t_frac, n_frac, c_frac, 0);
    end
endfunction

function integer tw_h_w_e;
    input integer cubic, pow2, t_w, t_frac, n_frac, c_frac, te_max;
    begin
        tw_h_w_e = tw_bits_signed(tw_h_max_e(cubic, pow2, t_w, t_frac, n_frac, c_frac, te_max));
    end
endfunction

function integer tw_h_w;
    input integer cubic, pow2, t_w, t_frac, n_frac, c_frac;
    begin
        tw_h_w = tw_h_w_e(cubic, pow2, t_w, t_frac, n_frac, c_frac, 0);
    end
endfunction

// |a h_k| bound (fraction c_frac), and its word
function [63:0] tw_ag_max_e;
    input integer cubic, pow2, t_w, t_frac, n_frac, c_frac, a_w, a_frac, te_max, ae_max;
    begin
        tw_ag_max_e = tw_shift_bound(tw_pow2m1(a_w) * tw_h_max_e(cubic, pow2, t_w, t_frac, n_frac, c_frac, te_max),
                                     ae_max - a_frac);
    end
endfunction

function [63:0] tw_ag_max;
    input integer cubic, pow2, t_w, t_frac, n_frac, c_frac, a_w, a_frac;
    begin
        tw_ag_max = tw_ag_max_e(cubic, pow2, t_w, t_frac, n_frac, c_frac, a_w, a_frac, 0, 0);
    end
endfunction

function integer tw_ag_w_e;
    input integer cubic, pow2, t_w, t_frac, n_frac, c_frac, a_w, a_frac, te_max, ae_max;
    begin
        tw_ag_w_e = tw_bits_signed(tw_ag_max_e(cubic, pow2, t_w, t_frac, n_frac, c_frac, a_w, a_frac, te_max, ae_max));
    end
endfunction

function integer tw_ag_w;
    input integer cubic, pow2, t_w, t_frac, n_frac, c_frac, a_w, a_frac;
    begin
        tw_ag_w = tw_ag_w_e(cubic, pow2, t_w, t_frac, n_frac, c_frac, a_w, a_frac, 0, 0);
    end
endfunction

// ---------------------------------------------------------------------------
// the exact sums over the quadric and k noise terms

// f = q + sum a_i n_i (fraction f_frac); *_e: a_i with exponents up to ae_max
function integer tw_f_w_e;
    input integer diag, s_w, s_frac, q_w, q_frac, f_frac, k, a_w, a_frac, n_frac, ae_max;
    begin
        tw_f_w_e = tw_bits_signed(tw_shift_bound(tw_qsum(diag, s_w, s_frac, q_w), f_frac - q_frac)
                                  + k * tw_an_max_e(a_w, a_frac, n_frac, f_frac, ae_max));
    end
endfunction

function integer tw_f_w;
    input integer diag, s_w, s_frac, q_w, q_frac, f_frac, k, a_w, a_frac, n_frac;
    begin
        tw_f_w = tw_f_w_e(diag, s_w, s_frac, q_w, q_frac, f_frac, k, a_w, a_frac, n_frac, 0);
    end
endfunction

// |grad f| component bound (fraction c_frac): dq/ds, plus the k a_i grad n_i when grad != 0
// (*_e: T_i and a_i with exponents up to te_max, ae_max)
function [63:0] tw_c_max_e;
    input integer diag, s_w, s_frac, q_w, q_frac, c_frac, k, grad, cubic, pow2, t_w, t_frac, n_frac, a_w, a_frac,
                  te_max, ae_max;
    begin
        tw_c_max_e = tw_cq_max(diag, s_w, s_frac, q_w, q_frac, c_frac)
                     + ((grad != 0) ? k * tw_ag_max_e(cubic, pow2, t_w, t_frac, n_frac, c_frac, a_w, a_frac, te_max,
                                                       ae_max) : 64'd0);
    end
endfunction

function integer tw_c_w_e;
    input integer diag, s_w, s_frac, q_w, q_frac, c_frac, k, grad, cubic, pow2, t_w, t_frac, n_frac, a_w, a_frac,
                  te_max, ae_max;
    begin
        tw_c_w_e = tw_bits_signed(tw_c_max_e(diag, s_w, s_frac, q_w, q_frac, c_frac, k, grad, cubic, pow2, t_w, t_frac,
                                             n_frac, a_w, a_frac, te_max, ae_max));
    end
endfunction

function integer tw_c_w;
    input integer diag, s_w, s_frac, q_w, q_frac, c_frac, k, grad, cubic, pow2, t_w, t_frac, n_frac, a_w, a_frac;
    begin
        tw_c_w = tw_c_w_e(diag, s_w, s_frac, q_w, q_frac, c_frac, k, grad, cubic, pow2, t_w, t_frac, n_frac, a_w,
                          a_frac, 0, 0);
    end
endfunction

// ---------------------------------------------------------------------------
// filter width, from the gradient word c_w (its bound: 2^(c_w - 1))

// |g| = |c . Jm| bound, g = 3 products of c and j_w-bit mantissas
function [63:0] tw_g_max;
    input integer c_max_w, j_w;
    begin
        tw_g_max = 3 * tw_pow2m1(c_max_w) * tw_pow2m1(j_w);
    end
endfunction

// ax^2 + ay^2 of two norm_bits-bit values, and its square root
function integer tw_l_w;
    input integer norm_bits;
    begin
        tw_l_w = tw_bits_unsigned(2 * ((64'd1 << norm_bits) - 1) * ((64'd1 << norm_bits) - 1));
    end
endfunction

function integer tw_r_w;
    input integer norm_bits;
    begin
        tw_r_w = tw_bits_unsigned(tw_isqrt(2 * ((64'd1 << norm_bits) - 1) * ((64'd1 << norm_bits) - 1)));
    end
endfunction

// normalising shift word: 0..gabs_w - norm_bits
function integer tw_sh_w;
    input integer gabs_w, norm_bits;
    integer d;
    begin
        d = (gabs_w > norm_bits) ? gabs_w - norm_bits : 0;
        tw_sh_w = tw_bits_unsigned({32'd0, d});
    end
endfunction

// w exponent e = sh + je - c_frac + n_log2 + f_frac, over every sh, je and n_log2
function integer tw_e_w;
    input integer sh_w, je_w, c_frac, f_frac, n_log2_max;
    integer lo, hi;
    begin
        lo = -(1 << (je_w - 1)) - c_frac + f_frac;
        hi = (1 << sh_w) - 1 + (1 << (je_w - 1)) - 1 - c_frac + n_log2_max + f_frac;
        tw_e_w = (tw_bits_signed_int(-lo) > tw_bits_signed_int(hi)) ? tw_bits_signed_int(-lo)
                                                                     : tw_bits_signed_int(hi);
    end
endfunction

// ---------------------------------------------------------------------------
// colour map: u = f N, window ends x = 2u -+ w, table integrals

// w_cap = 2^(w_cap_log2 + f_frac): the saturated filter width (units 2^-f_frac entries)
function [63:0] tw_w_cap;
    input integer w_cap_log2, f_frac;
    begin
        tw_w_cap = 64'd1 << (w_cap_log2 + f_frac);
    end
endfunction

function [63:0] tw_u_max;
    input integer n_log2_max, f_frac, w_cap_log2;
    begin
        tw_u_max = ((64'd1 << n_log2_max) << f_frac) + (tw_w_cap(w_cap_log2, f_frac) >> 1);
    end
endfunction

function integer tw_u_w;
    input integer n_log2_max, f_frac, w_cap_log2;
    begin
        tw_u_w = tw_bits_signed(tw_u_max(n_log2_max, f_frac, w_cap_log2));
    end
endfunction

function [63:0] tw_x_max;
    input integer n_log2_max, f_frac, w_cap_log2;
    begin
        tw_x_max = 2 * tw_u_max(n_log2_max, f_frac, w_cap_log2) + tw_w_cap(w_cap_log2, f_frac);
    end
endfunction

function integer tw_x_w;
    input integer n_log2_max, f_frac, w_cap_log2;
    begin
        tw_x_w = tw_bits_signed(tw_x_max(n_log2_max, f_frac, w_cap_log2));
    end
endfunction

// summed-area table channel: 255 N
function integer tw_csat_w;
    input integer n_log2_max;
    begin
        tw_csat_w = tw_bits_unsigned(255 * (64'd1 << n_log2_max));
    end
endfunction

// integral I(x) per channel, |I| <= 255 (|x| + N) (units 2^-(f_frac + 1))
function integer tw_i_w;
    input integer n_log2_max, f_frac, w_cap_log2;
    begin
        tw_i_w = tw_bits_signed(255 * (tw_x_max(n_log2_max, f_frac, w_cap_log2)
                                       + ((64'd1 << n_log2_max) << (f_frac + 1))));
    end
endfunction

// D = I(b) - I(a) <= 255 2 w_cap
function integer tw_d_w;
    input integer f_frac, w_cap_log2;
    begin
        tw_d_w = tw_bits_unsigned(255 * 2 * tw_w_cap(w_cap_log2, f_frac));
    end
endfunction

// ---------------------------------------------------------------------------
// the trapezoid (filter "sat2", rtl/cmap_sat2.v): u guarded by w_cap (tw_u_w with
// w_cap_log2 + 1), window ends e = 2u -+ a -+ b, the running sum of csat
// H[k] <= 255 N (N + 1) / 2, the second difference Gamma <= 2040 ab < 2^(2(w_cap_log2 +
// f_frac) + 11) and its divisor 4ab <= 2^(2(w_cap_log2 + f_frac) + 2)

function integer tw_x2_w;
    input integer n_log2_max, f_frac, w_cap_log2;
    begin
        tw_x2_w = tw_bits_signed(2 * tw_u_max(n_log2_max, f_frac, w_cap_log2 + 1)
                                 + 2 * tw_w_cap(w_cap_log2, f_frac));
    end
endfunction

function integer tw_csat2_w;
    input integer n_log2_max;
    begin
        tw_csat2_w = tw_bits_unsigned(255 * (((64'd1 << n_log2_max) * ((64'd1 << n_log2_max) + 1)) >> 1));
    end
endfunction

function integer tw_d2_w;
    input integer f_frac, w_cap_log2;
    begin
        tw_d2_w = 2 * (w_cap_log2 + f_frac) + 11;
    end
endfunction

function integer tw_w2_w;
    input integer f_frac, w_cap_log2;
    begin
        tw_w2_w = 2 * (w_cap_log2 + f_frac) + 3;
    end
endfunction
