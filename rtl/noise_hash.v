// noise_hash: the lattice values at the eight corners of a noise cell.
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
// Latency: PIPE register stages (advancing with ce). PIPE = 0: combinational, the three
// ROM levels in series (noise_term registers the result); PIPE = 1 (noise_term's
// FPGA_REGS): the four second-level words and z registered between levels 2 and 3;
// PIPE = 2: also the two first-level words and y, z between levels 1 and 2 (one ROM
// level a clock). Throughput: one cell per enabled clock.
// Written for event-driven simulation speed: PIPE = 0 is one always @* with blocking
// assigns and direct ROM reads; the eight values are joined by one concatenation; each
// pipelined level is one always @* reading the level before it through a delay_line.
// (always @* also lists the ROM words; they change only at time 0.)

`default_nettype none

module noise_hash #(
    parameter H      = 8,           // lattice coordinate width, period 2^H (hash_bits)
    parameter N_FRAC = 12,          // fraction bits of a lattice value (n_frac >= H - 1)
    parameter N_W    = N_FRAC + 2,  // width of a lattice value (signed, >= N_FRAC + 2)
    // the permutation of 0..2^H-1, entry i at [i*H +: H] (default 0: a placeholder, every
    // configuration sets it)
    parameter [H*(1<<H)-1:0] PERM = {H*(1<<H){1'b0}},
    parameter PIPE   = 0            // register stages 0, 1 (before level 3) or 2 (and before level 2)
) (
    /* verilator lint_off UNUSEDSIGNAL */  // PIPE = 0: no clock
    input  wire               clk,
    input  wire               ce,
    /* verilator lint_on UNUSEDSIGNAL */
    input  wire [H-1:0]       ix,
    input  wire [H-1:0]       iy,
    input  wire [H-1:0]       iz,
    output reg  [8*N_W-1:0]   v_out
);

// the permutation as a ROM (a reg array written only by this initial block, the one kind
// of initial block the RTL conventions allow; Yosys maps it to logic)
// (constant after time 0: no coverage points)
/* verilator coverage_off */
reg [H-1:0] perm_rom [0:(1<<H)-1];
/* verilator coverage_on */
integer     pi;
initial begin
    for (pi = 0; pi < (1 << H); pi = pi + 1)
        perm_rom[pi] = PERM[pi*H +: H];
end

localparam V_SHIFT = N_FRAC - H + 1;  // >= 0 (checked by model/hw/config.py)

// the third level and the corner values: h = perm[hxy ^ z] for the four second-level words
// and z, z + 1; each corner's value h - 2^(H-1) as an H-bit two's-complement word (the MSB
// inverted), sign-extended to N_W bits and scaled by 2^V_SHIFT; corner (i, j, k) at element
// 4*i + 2*j + k
function [8*N_W-1:0] corners;
    input [H-1:0] h00, h01, h10, h11;  // second level, per (x, y)
    input [H-1:0] z0, z1;              // iz, iz + 1
    reg   [H-1:0] h;
    integer       c;
    begin
        for (c = 0; c < 8; c = c + 1) begin
            h = perm_rom[(c[2] ? (c[1] ? h11 : h10) : (c[1] ? h01 : h00)) ^ (c[0] ? z1 : z0)];
            corners[c*N_W +: N_W] = {{(N_W-H+1){~h[H-1]}}, h[H-2:0]} << V_SHIFT;
        end
    end
endfunction

generate
    if (PIPE == 0) begin : g_comb
        reg [H-1:0]   ix1, iy1, iz1;               // c + 1 (wraps mod 2^H)
        reg [H-1:0]   hx0, hx1;                    // first level, per x
        reg [H-1:0]   hxy00, hxy01, hxy10, hxy11;  // second level, per (x, y)
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
            v_out = corners(hxy00, hxy01, hxy10, hxy11, iz, iz1);
        end
    end else begin : g_pipe
        // level 1 (and the +1 corners), registered when PIPE = 2
        reg [H-1:0]   ix1, iy1, iz1;               // c + 1 (wraps mod 2^H)
        reg [H-1:0]   hx0, hx1;                    // first level, per x
        always @* begin
            ix1 = ix + 1'b1;
            iy1 = iy + 1'b1;
            iz1 = iz + 1'b1;
            hx0 = perm_rom[ix];
            hx1 = perm_rom[ix1];
        end
        wire [H-1:0] hx0_a, hx1_a, iy_a, iy1_a, iz_a, iz1_a;
        delay_line #(.W(6*H), .N(PIPE - 1)) u_dly_1 (.clk(clk), .rst(1'b0), .ce(ce),
            .d_in({hx0, hx1, iy, iy1, iz, iz1}), .d_out({hx0_a, hx1_a, iy_a, iy1_a, iz_a, iz1_a}));
        // level 2, registered
        reg [H-1:0]   hxy00_n, hxy01_n, hxy10_n, hxy11_n;
        always @* begin
            hxy00_n = perm_rom[hx0_a ^ iy_a];
            hxy01_n = perm_rom[hx0_a ^ iy1_a];
            hxy10_n = perm_rom[hx1_a ^ iy_a];
            hxy11_n = perm_rom[hx1_a ^ iy1_a];
        end
        wire [H-1:0] hxy00, hxy01, hxy10, hxy11, iz_b, iz1_b;
        delay_line #(.W(6*H), .N(1)) u_dly_2 (.clk(clk), .rst(1'b0), .ce(ce),
            .d_in({hxy00_n, hxy01_n, hxy10_n, hxy11_n, iz_a, iz1_a}), .d_out({hxy00, hxy01, hxy10, hxy11, iz_b, iz1_b}));
        // level 3 and the corner values
        always @* v_out = corners(hxy00, hxy01, hxy10, hxy11, iz_b, iz1_b);
    end
endgenerate

endmodule

`default_nettype wire
