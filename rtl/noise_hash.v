// noise_hash: the lattice values at the eight corners of a noise cell, combinational.
//
// The twin of model/hw/golden.py noise_hash(cfg, ix, iy, iz) applied to the corners
// (ix + i, iy + j, iz + k) mod 2^H, i, j, k in {0, 1}, as noise_term uses them:
//   h    = perm[perm[perm[x] ^ y] ^ z]          (perm: the configuration's permutation)
//   v    = (h - 2^(H-1)) * 2^(N_FRAC - H + 1)   in [-1, 1)
// The permutation is the parameter PERM (the configuration's, model/hw/config.py
// permutation(), set by the top), held in a constant array perm_rom (a 2^H-entry ROM,
// read directly) that an initial block fills from PERM; no table is typed in here.
// The first two hash levels are shared between corners: 2 + 4 + 8 = 14 lookups.
// Formats: ix, iy, iz u{H}.0 (cell's low corner); v sN_W.N_FRAC, corner (i, j, k)
// at element 4*i + 2*j + k of v_out (element 0 at the LSBs).
// Latency: 0 (combinational: three ROM levels in series; noise_term registers it).
// Written for event-driven simulation speed: the body is one always @* with blocking
// assigns and direct ROM reads; the eight values are joined by one concatenation.
// (always @* also lists the ROM words; they change only at time 0.)

`default_nettype none

module noise_hash #(
    parameter H      = 8,           // lattice coordinate width, period 2^H (hash_bits)
    parameter N_FRAC = 12,          // fraction bits of a lattice value (n_frac >= H - 1)
    parameter N_W    = N_FRAC + 2,  // width of a lattice value (signed, >= N_FRAC + 2)
    // the permutation of 0..2^H-1, entry i at [i*H +: H] (default 0: a placeholder, every
    // configuration sets it)
    parameter [H*(1<<H)-1:0] PERM = {H*(1<<H){1'b0}}
) (
    input  wire [H-1:0]       ix,
    input  wire [H-1:0]       iy,
    input  wire [H-1:0]       iz,
    output reg  [8*N_W-1:0]   v_out
);

// the permutation as a ROM (a reg array written only by this initial block, the one kind
// of initial block the RTL conventions allow; Yosys maps it to logic)
reg [H-1:0] perm_rom [0:(1<<H)-1];
integer     pi;
initial begin
    for (pi = 0; pi < (1 << H); pi = pi + 1)
        perm_rom[pi] = PERM[pi*H +: H];
end

localparam V_SHIFT = N_FRAC - H + 1;  // >= 0 (checked by model/hw/config.py)

reg [H-1:0]   ix1, iy1, iz1;               // c + 1 (wraps mod 2^H)
reg [H-1:0]   hx0, hx1;                    // first level, per x
reg [H-1:0]   hxy00, hxy01, hxy10, hxy11;  // second level, per (x, y)
reg [H-1:0]   h;                           // third level, per corner
reg [N_W-1:0] v000, v001, v010, v011, v100, v101, v110, v111;

// corner value of h: h - 2^(H-1) as an H-bit two's-complement word (the MSB inverted),
// sign-extended to N_W bits and scaled by 2^V_SHIFT
always @* begin
    ix1   = ix + 1'b1;
    iy1   = iy + 1'b1;
    iz1   = iz + 1'b1;
    hx0   = perm_rom[ix];
    hx1   = perm_rom[ix1];
    hxy00 = perm_rom[hx0 ^ iy];
    hxy01 = perm_rom[hx0 ^ iy1];
    hxy10 = perm_rom[hx1 ^ iy];
    hxy11 = perm_rom[hx1 ^ iy1];
    h     = perm_rom[hxy00 ^ iz];
    v000  = {{(N_W-H+1){~h[H-1]}}, h[H-2:0]} << V_SHIFT;
    h     = perm_rom[hxy00 ^ iz1];
    v001  = {{(N_W-H+1){~h[H-1]}}, h[H-2:0]} << V_SHIFT;
    h     = perm_rom[hxy01 ^ iz];
    v010  = {{(N_W-H+1){~h[H-1]}}, h[H-2:0]} << V_SHIFT;
    h     = perm_rom[hxy01 ^ iz1];
    v011  = {{(N_W-H+1){~h[H-1]}}, h[H-2:0]} << V_SHIFT;
    h     = perm_rom[hxy10 ^ iz];
    v100  = {{(N_W-H+1){~h[H-1]}}, h[H-2:0]} << V_SHIFT;
    h     = perm_rom[hxy10 ^ iz1];
    v101  = {{(N_W-H+1){~h[H-1]}}, h[H-2:0]} << V_SHIFT;
    h     = perm_rom[hxy11 ^ iz];
    v110  = {{(N_W-H+1){~h[H-1]}}, h[H-2:0]} << V_SHIFT;
    h     = perm_rom[hxy11 ^ iz1];
    v111  = {{(N_W-H+1){~h[H-1]}}, h[H-2:0]} << V_SHIFT;
    v_out = {v111, v110, v101, v100, v011, v010, v001, v000};
end

endmodule

`default_nettype wire
