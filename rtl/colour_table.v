// colour_table: the colour map's register-array tables, one write port, registered read ports.
//
// Tables (built according to FILTER, the others are not built and read as 0):
//   clut  2^NMAX entries RGBA8 (R at [7:0], A at [31:24])           FILTER 0, 1, 2
//   csat  2^NMAX entries, 4 x u{CS_W}.0, channel c at [c*CS_W +: CS_W]: the inclusive
//         prefix sums of clut (paper eq. 13), computed by the host     FILTER 1 (sat)
//   mip   2^(NMAX+1) - 1 entries RGBA8, MIP level l at 2N - (2N >> l)  FILTER 2 (mip)
// Read ports (registered, advance with ce; read-before-write on a same-clock write):
//   FILTER 1: clut at clut_addr_a and clut_addr_b (the two window ends), csat at
//             csat_addr_a and csat_addr_b, and total = csat[N - 1], the whole-table sum:
//             a register (4 CS_W flip-flops) that takes every csat entry written, so it
//             holds the last one. CONTRACT: the last csat write of a table load is entry
//             N - 1 (write csat in ascending order, as golden build_tables and
//             model/hw/regmap.py do; an update of clut[j] rewrites csat[j..N-1], so it ends
//             there too). Not a third read port of csat, and no n_log2 dependence.
//   FILTER 2: clut at clut_addr_a (point lookup), mip at mip_addr
//   FILTER 0: clut at clut_addr_a
// Storage: 32 2^NMAX (clut) + 4 CS_W 2^NMAX (csat, sat) or 32 (2^(NMAX+1) - 1) (mip) bits;
// full and reduced (NMAX = 8, CS_W = 16, sat): 8192 + 16384 = 24576 bits.
//
// Write port (synchronous, independent of ce): wr_en, wr_table (0 clut, 1 csat, 2 mip;
// 3 and tables not built are ignored), wr_addr (entries past a table's end are ignored),
// wr_data (4 lanes of CS_W bits, channel c at [c*CS_W +: CS_W]; clut and mip take the low 8
// bits of each lane). The tables are not reset: load them before use.
// Latency 1 (reads), one read per port per enabled clock.
// Written for event-driven simulation speed: no reductions on per-clock signals (unused
// inputs are marked for lint only).

`default_nettype none

module colour_table #(
    parameter FILTER = 1,                   // 0 none (point lookup), 1 sat, 2 mip
    parameter NMAX   = 8,                   // log2 of the table size (>= 1)
    parameter CS_W   = 16,                  // summed-area table channel width
    parameter NL_W   = 4                    // width of n_log2
) (
    input  wire                clk,
    input  wire                ce,
    // write port
    input  wire                wr_en,
    input  wire [1:0]          wr_table,
    input  wire [NMAX:0]       wr_addr,
    input  wire [4*CS_W-1:0]   wr_data,
    // read ports
    input  wire [NMAX-1:0]     clut_addr_a,
    input  wire [NMAX-1:0]     clut_addr_b,
    input  wire [NMAX-1:0]     csat_addr_a,
    input  wire [NMAX-1:0]     csat_addr_b,
    input  wire [NL_W-1:0]     n_log2,
    input  wire [NMAX:0]       mip_addr,
    output wire [31:0]         clut_a,
    output wire [31:0]         clut_b,
    output wire [4*CS_W-1:0]   csat_a,
    output wire [4*CS_W-1:0]   csat_b,
    output wire [4*CS_W-1:0]   total,
    output wire [31:0]         mip_data
);

localparam [1:0] TABLE_CLUT = 2'd0;
localparam [1:0] TABLE_CSAT = 2'd1;
localparam [1:0] TABLE_MIP  = 2'd2;
localparam integer DEPTH     = 1 << NMAX;              // clut, csat entries
localparam integer MIP_DEPTH = (1 << (NMAX + 1)) - 1;  // mip entries

// an RGBA8 entry from the low 8 bits of each write lane
wire [31:0] wr_rgba = {wr_data[3*CS_W +: 8], wr_data[2*CS_W +: 8],
                       wr_data[1*CS_W +: 8], wr_data[0*CS_W +: 8]};

// clut: built in every configuration
reg [31:0] clut_mem [0:DEPTH-1];
reg [31:0] clut_a_reg;

always @(posedge clk) begin
    if (wr_en && wr_table == TABLE_CLUT && !wr_addr[NMAX])
        clut_mem[wr_addr[NMAX-1:0]] <= wr_rgba;
end

always @(posedge clk) begin
    if (ce)
        clut_a_reg <= clut_mem[clut_addr_a];
end

assign clut_a = clut_a_reg;

generate
    if (FILTER == 1) begin : g_sat
        reg [31:0]       clut_b_reg;
        reg [4*CS_W-1:0] csat_mem [0:DEPTH-1];
        reg [4*CS_W-1:0] csat_a_reg;
        reg [4*CS_W-1:0] csat_b_reg;
        reg [4*CS_W-1:0] total_reg;  // the last csat entry written: csat[N - 1] (contract)
        wire csat_we = wr_en && wr_table == TABLE_CSAT && !wr_addr[NMAX];

        always @(posedge clk) begin
            if (csat_we) begin
                csat_mem[wr_addr[NMAX-1:0]] <= wr_data;
                total_reg <= wr_data;
            end
        end

        always @(posedge clk) begin
            if (ce) begin
                clut_b_reg <= clut_mem[clut_addr_b];
                csat_a_reg <= csat_mem[csat_addr_a];
                csat_b_reg <= csat_mem[csat_addr_b];
            end
        end

        assign clut_b   = clut_b_reg;
        assign csat_a   = csat_a_reg;
        assign csat_b   = csat_b_reg;
        assign total    = total_reg;  // static during a pass: no read register needed
        assign mip_data = 32'd0;
        // the mip table is not built in this configuration; total needs no n_log2
        /* verilator lint_off UNUSEDSIGNAL */
        wire [NMAX:0]   unused_mip_addr = mip_addr;
        wire [NL_W-1:0] unused_n_log2   = n_log2;
        /* verilator lint_on UNUSEDSIGNAL */
    end else if (FILTER == 2) begin : g_mip
        reg [31:0] mip_mem [0:MIP_DEPTH-1];
        reg [31:0] mip_reg;

        always @(posedge clk) begin
            if (wr_en && wr_table == TABLE_MIP && wr_addr != {(NMAX+1){1'b1}})
                mip_mem[wr_addr] <= wr_rgba;
        end

        always @(posedge clk) begin
            if (ce)
                mip_reg <= mip_mem[mip_addr];
        end

        assign clut_b   = 32'd0;
        assign csat_a   = {4*CS_W{1'b0}};
        assign csat_b   = {4*CS_W{1'b0}};
        assign total    = {4*CS_W{1'b0}};
        assign mip_data = mip_reg;
        // csat and the second clut port are not built; clut and mip use 8 bits per lane
        /* verilator lint_off UNUSEDSIGNAL */
        wire [NMAX-1:0]   unused_clut_addr_b = clut_addr_b;
        wire [NMAX-1:0]   unused_csat_addr_a = csat_addr_a;
        wire [NMAX-1:0]   unused_csat_addr_b = csat_addr_b;
        wire [NL_W-1:0]   unused_n_log2      = n_log2;
        wire [4*CS_W-1:0] unused_wr_data     = wr_data;  // the low 8 bits of each lane are used
        /* verilator lint_on UNUSEDSIGNAL */
    end else begin : g_point
        assign clut_b   = 32'd0;
        assign csat_a   = {4*CS_W{1'b0}};
        assign csat_b   = {4*CS_W{1'b0}};
        assign total    = {4*CS_W{1'b0}};
        assign mip_data = 32'd0;
        // point lookup only: one clut read port, 8 bits per write lane
        /* verilator lint_off UNUSEDSIGNAL */
        wire [NMAX-1:0]   unused_clut_addr_b = clut_addr_b;
        wire [NMAX-1:0]   unused_csat_addr_a = csat_addr_a;
        wire [NMAX-1:0]   unused_csat_addr_b = csat_addr_b;
        wire [NL_W-1:0]   unused_n_log2      = n_log2;
        wire [NMAX:0]     unused_mip_addr    = mip_addr;
        wire [4*CS_W-1:0] unused_wr_data     = wr_data;  // the low 8 bits of each lane are used
        /* verilator lint_on UNUSEDSIGNAL */
    end
endgenerate

endmodule

`default_nettype wire
