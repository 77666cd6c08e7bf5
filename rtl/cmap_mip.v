// cmap_mip: the MIP-map family of colour_map: RGBA8 of the colour index u looked up in
// the colour-table MIP level l = clip(floor(log2 w), 0, n_log2) (paper 3.3.1; mip_index), or,
// filter off, in clut (the point lookup); the bit-exact twin of model/hw/golden.py
// cmap_mip.
//
// Formats (derived from the parameters by rtl/tex_widths.vh, as in colour_map):
//   u_in  s{U_W}.{F_FRAC} colour-table entries (colour_map's stage 1: f N taken mod N, or
//         clipped to [-W/2, N + W/2], W = 2^W_CAP_LOG2)
//   w_in  u{W_W}.{F_FRAC} entries, W_W = W_CAP_LOG2 + F_FRAC + 1 (the filter width)
//   mode  0 mod, 1 clamp; n_log2: N = 2^n_log2 entries, n_log2 <= N_LOG2_MAX
//   rgba_out RGBA8, channel c at [8c+7:8c]
// Tables (colour_table, FILTER 2): the write port as colour_map's (wr_table 0 clut, 2 mip; the
// others are ignored).
// Pipeline: 2-3 mip_index | 4 table reads | 5 select | 6..13 delay line.
// FPGA_REGS = 1 ([fpga_regs]): the delay line is four stages longer (colour_map's latency).
// Latency `LAT_CMAP_MIP = 13 register stages (FPGA_REGS: `LAT_CMAP_MIP_FPGA = 17) from the
// stage-1 registers of colour_map; throughput one pixel per enabled clock.
// Reset (synchronous, active high) clears the valid chain and rgba_out (no X after reset);
// rgba_out loads only with a valid result.

`default_nettype none

`include "tex_latency.vh"

module cmap_mip #(
    // colour_map's parameters of the same names (config/<name>.toml keys in brackets)
    parameter F_FRAC     = 16,  // [f_frac] fraction bits of u and w
    parameter W_CAP_LOG2 = 16,  // [w_cap_log2] w saturates at 2^W_CAP_LOG2 entries (u's range)
    parameter N_LOG2_MAX = 8,   // [n_log2_max] log2 of the largest colour table (>= 1)
    parameter FPGA_REGS  = 0    // [fpga_regs] 1: the longer delay line above
) (clk, rst, ce, in_valid, u_in, w_in, filter_en, mode, n_log2, wr_en, wr_table, wr_addr, wr_data, out_valid, rgba_out);

`include "tex_widths.vh"

localparam W_W    = W_CAP_LOG2 + F_FRAC + 1;                       // w
localparam U_W    = tw_u_w(N_LOG2_MAX, F_FRAC, W_CAP_LOG2);        // u (signed)
localparam CS_W   = tw_csat_w(N_LOG2_MAX);                         // write-port lane
localparam NMAX   = N_LOG2_MAX;
localparam NL_W   = tw_bits_unsigned(N_LOG2_MAX);                  // n_log2
localparam LAT    = FPGA_REGS ? `LAT_CMAP_MIP_FPGA : `LAT_CMAP_MIP;

input  wire                 clk;
input  wire                 rst;
input  wire                 ce;
input  wire                 in_valid;
input  wire [U_W-1:0]       u_in;       // signed
input  wire [W_W-1:0]       w_in;
input  wire                 filter_en;  // 0: the point lookup in clut
input  wire                 mode;       // 0 mod, 1 clamp
input  wire [NL_W-1:0]      n_log2;
// table write port
input  wire                 wr_en;
input  wire [1:0]           wr_table;
input  wire [NMAX:0]        wr_addr;
input  wire [4*CS_W-1:0]    wr_data;
output wire                 out_valid;
output wire [31:0]          rgba_out;

// elaboration fails (unknown module) when the latency leaves fewer than three stages after
// the table read (mip_index 2, the read 1, the select and the output register)
generate
    if (LAT < 2 + 1 + 3) begin : g_bad_latency
        cmap_mip_latency_too_short u_error ();
    end
endgenerate

// ---- stages 2-3: point / MIP address
wire [NMAX:0] addr;
wire          use_mip;

mip_index #(.FILTER(2), .U_W(U_W), .W_W(W_W), .FF(F_FRAC), .NMAX(NMAX), .NL_W(NL_W)) u_index (
    .clk(clk), .ce(ce), .u_in(u_in), .w_in(w_in), .mode(mode),
    .n_log2(n_log2), .filter_en(filter_en),
    .addr_out(addr), .use_mip_out(use_mip)
);

// ---- stage 4: table reads
wire [31:0]       clut_a, mip_data;
// (colour_table drives these 0 with FILTER 2: constant, no coverage points)
/* verilator lint_off UNUSEDSIGNAL */
/* verilator coverage_off */
wire [31:0]       unused_clut_b;
wire [4*CS_W-1:0] unused_csat_a, unused_csat_b, unused_total;
/* verilator coverage_on */
/* verilator lint_on UNUSEDSIGNAL */
colour_table #(.FILTER(2), .NMAX(NMAX), .CS_W(CS_W), .NL_W(NL_W)) u_table (
    .clk(clk), .ce(ce),
    .wr_en(wr_en), .wr_table(wr_table), .wr_addr(wr_addr), .wr_data(wr_data),
    .clut_addr_a(addr[NMAX-1:0]), .clut_addr_b({NMAX{1'b0}}),
    .csat_addr_a({NMAX{1'b0}}), .csat_addr_b({NMAX{1'b0}}),
    .n_log2({NL_W{1'b0}}), .mip_addr(addr),
    .clut_a(clut_a), .clut_b(unused_clut_b), .csat_a(unused_csat_a),
    .csat_b(unused_csat_b), .total(unused_total), .mip_data(mip_data)
);

// ---- stages 5..LAT: select mip or clut, then a delay line to the block's latency; the last register is the
// output register (reset, loads only a valid result)
localparam DL = LAT - 3;  // register stages after the table read (>= 3)
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
        sv_reg <= {sv_reg[1:0], in_valid};
        dv_reg <= {dv_reg[DL-2:0], sv_reg[2]};
    end
    if (ce) begin
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

endmodule

`default_nettype wire
