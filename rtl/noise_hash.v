// noise_hash: the lattice values at the eight corners of a noise cell, combinational.
//
// The twin of model/golden.py noise_hash(cfg, ix, iy, iz) applied to the corners
// (ix + i, iy + j, iz + k) mod 2^H, i, j, k in {0, 1}, as noise_term uses them:
//   h    = perm[perm[perm[x] ^ y] ^ z]          (perm: the configuration's permutation)
//   v    = (h - 2^(H-1)) * 2^(N_FRAC - H + 1)   in [-1, 1)
// The permutation comes from build/gen/<config>/perm_rom.vh (model/gen_rtl.py), a
// constant function perm_lookup (a 2^H-entry ROM); no table is typed in here.
// The first two hash levels are shared between corners: 2 + 4 + 8 = 14 lookups.
// Formats: ix, iy, iz u{H}.0 (cell's low corner); v sN_W.N_FRAC, corner (i, j, k)
// at element 4*i + 2*j + k of v_out (element 0 at the LSBs).
// Latency: 0 (combinational: three ROM levels in series; noise_term registers it).

`default_nettype none

`include "tex_cfg.vh"

module noise_hash #(
    parameter H      = `CFG_HASH_BITS,  // lattice coordinate width, period 2^H (keep: the ROM is built for it)
    parameter N_FRAC = `CFG_N_FRAC,     // fraction bits of a lattice value
    parameter N_W    = `CFG_N_W         // width of a lattice value (signed, >= N_FRAC + 2)
) (
    input  wire [H-1:0]       ix,
    input  wire [H-1:0]       iy,
    input  wire [H-1:0]       iz,
    output wire [8*N_W-1:0]   v_out
);

`include "perm_rom.vh"

localparam V_SHIFT = N_FRAC - H + 1;  // >= 0 (checked by model/config.py)

// the two coordinates of each axis, {c + 1, c} (c + 1 wraps mod 2^H)
wire [H-1:0] ix1 = ix + 1'b1;
wire [H-1:0] iy1 = iy + 1'b1;
wire [H-1:0] iz1 = iz + 1'b1;
wire [2*H-1:0] xs = {ix1, ix};
wire [2*H-1:0] ys = {iy1, iy};
wire [2*H-1:0] zs = {iz1, iz};

genvar gi, gj, gk;
generate
    for (gi = 0; gi < 2; gi = gi + 1) begin : g_x
        wire [H-1:0] hx = perm_lookup(xs[gi*H +: H]);
        for (gj = 0; gj < 2; gj = gj + 1) begin : g_y
            wire [H-1:0] hxy = perm_lookup(hx ^ ys[gj*H +: H]);
            for (gk = 0; gk < 2; gk = gk + 1) begin : g_z
                wire [H-1:0]          h  = perm_lookup(hxy ^ zs[gk*H +: H]);
                // h - 2^(H-1) as an H-bit two's-complement word: invert the MSB
                wire signed [H-1:0]   hc = {~h[H-1], h[H-2:0]};
                wire signed [N_W-1:0] hv = {{(N_W-H){hc[H-1]}}, hc};  // sign-extended
                assign v_out[(4*gi + 2*gj + gk)*N_W +: N_W] = hv <<< V_SHIFT;
            end
        end
    end
endgenerate

endmodule

`default_nettype wire
