// sat2_table: the tables of the trapezoid filter (cmap_sat2): clut, csat and csat2, the running
// sum of csat, each with four registered read ports (one per window end); the bit-exact twin of
// model/hw/golden.py sat2_table / sat2_table_write.
//
// Tables:
//   clut   2^NMAX entries RGBA8 (R at [7:0], A at [31:24])
//   csat   2^NMAX entries, 4 x u{CS_W}.0 (channel c at [c*CS_W +: CS_W]): the inclusive
//          prefix sums of clut (paper eq. 13), written by the host
//   csat2  2^NMAX entries, 4 x u{CS2_W}.0: H[j] = sum_{i<=j} csat[i], DERIVED here from the
//          csat writes: a csat write of entry j also writes H[j] = (j == 0 ? 0 : acc) + csat[j]
//          and acc = H[j] (a running-sum register, mod 2^CS2_W lanes)
//   total  = the last csat entry written, total2 = the last H written (registers)
// CONTRACT (as colour_table's total): a table load writes csat[0..N-1] in ascending order
// (golden build_tables, model/hw/regmap.py write_sequence do), so csat2[j] = H[j],
// total = csat[N - 1], total2 = H[N - 1]. The host writes nothing more than for the box filter.
// Read ports (registered, advance with ce; read-before-write): for end i = 0..3, clut at
// clut_addr[i] and csat, csat2 at csat_addr[i] (kk and kk - 1 of sat_index); total, total2
// static during a pass (no read register).
// Storage: (32 + 4 CS_W + 4 CS2_W) 2^NMAX bits + 4 (CS_W + 2 CS2_W) flip-flops (full: 256 x
// (32 + 64 + 96) = 49,152 bits and 224).
// Write port (synchronous, independent of ce): wr_en, wr_table (0 clut, 1 csat; 2, 3 are
// ignored), wr_addr (entries past 2^NMAX ignored), wr_data (4 lanes of CS_W bits; clut takes
// the low 8 bits of each). The tables are not reset: load them before use.
// Latency 1 (reads), one read per port per enabled clock.
// Written for event-driven simulation speed: one always @* for the running sum, the reads of
// the four ends in one clocked process.

`default_nettype none

module sat2_table #(
    parameter NMAX  = 8,                    // log2 of the table size (>= 1)
    parameter CS_W  = 16,                   // csat channel width (tw_csat_w)
    parameter CS2_W = 24                    // csat2 channel width (tw_csat2_w)
) (
    input  wire                  clk,
    input  wire                  ce,
    // write port
    input  wire                  wr_en,
    input  wire [1:0]            wr_table,
    input  wire [NMAX:0]         wr_addr,
    input  wire [4*CS_W-1:0]     wr_data,
    // read ports: end i at [i*NMAX +: NMAX] and so on
    input  wire [4*NMAX-1:0]     clut_addr,
    input  wire [4*NMAX-1:0]     csat_addr,
    output wire [4*32-1:0]       clut,
    output wire [16*CS_W-1:0]    csat,
    output wire [16*CS2_W-1:0]   csat2,
    output wire [4*CS_W-1:0]     total,
    output wire [4*CS2_W-1:0]    total2
);

localparam [1:0] TABLE_CLUT = 2'd0;
localparam [1:0] TABLE_CSAT = 2'd1;
localparam integer DEPTH    = 1 << NMAX;

wire [31:0] wr_rgba = {wr_data[3*CS_W +: 8], wr_data[2*CS_W +: 8], wr_data[1*CS_W +: 8], wr_data[0*CS_W +: 8]};
wire clut_we = wr_en && wr_table == TABLE_CLUT && !wr_addr[NMAX];
wire csat_we = wr_en && wr_table == TABLE_CSAT && !wr_addr[NMAX];

reg [31:0]         clut_mem  [0:DEPTH-1];
reg [4*CS_W-1:0]   csat_mem  [0:DEPTH-1];
reg [4*CS2_W-1:0]  csat2_mem [0:DEPTH-1];
reg [4*CS_W-1:0]   total_reg;
reg [4*CS2_W-1:0]  total2_reg;
reg [4*CS2_W-1:0]  acc_reg;    // the last H written

// H[j] = (j == 0 ? 0 : acc) + csat[j], per lane
reg [4*CS2_W-1:0]  h_new;
reg [CS2_W-1:0]    lane;
integer            hc;
always @* begin
    for (hc = 0; hc < 4; hc = hc + 1) begin
        lane = {CS2_W{1'b0}};
        lane[CS_W-1:0] = wr_data[hc*CS_W +: CS_W];
        h_new[hc*CS2_W +: CS2_W] = lane + ((wr_addr[NMAX-1:0] == {NMAX{1'b0}}) ? {CS2_W{1'b0}}
                                                                               : acc_reg[hc*CS2_W +: CS2_W]);
    end
end

always @(posedge clk) begin
    if (clut_we)
        clut_mem[wr_addr[NMAX-1:0]] <= wr_rgba;
    if (csat_we) begin
        csat_mem[wr_addr[NMAX-1:0]]  <= wr_data;
        csat2_mem[wr_addr[NMAX-1:0]] <= h_new;
        total_reg  <= wr_data;
        total2_reg <= h_new;
        acc_reg    <= h_new;
    end
end

reg [4*32-1:0]     clut_reg;
reg [16*CS_W-1:0]  csat_reg;
reg [16*CS2_W-1:0] csat2_reg;
integer            e;
always @(posedge clk) begin
    if (ce) begin
        for (e = 0; e < 4; e = e + 1) begin
            clut_reg[e*32 +: 32]             <= clut_mem[clut_addr[e*NMAX +: NMAX]];
            csat_reg[e*4*CS_W +: 4*CS_W]     <= csat_mem[csat_addr[e*NMAX +: NMAX]];
            csat2_reg[e*4*CS2_W +: 4*CS2_W]  <= csat2_mem[csat_addr[e*NMAX +: NMAX]];
        end
    end
end

assign clut   = clut_reg;
assign csat   = csat_reg;
assign csat2  = csat2_reg;
assign total  = total_reg;
assign total2 = total2_reg;

endmodule

`default_nettype wire
