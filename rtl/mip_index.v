// mip_index: colour-table MIP map (paper 3.3.1) and point-lookup address of a colour index u.
//
// u is s{U_W}.{FF} colour-table entries, w u{W_W}.{FF} entries (the filter width). As
// golden colour_map (filter "mip"):
//   level l = clip(bitlen(floor(w / 2^FF)) - 1, 0, n_log2)   (0 when the filter is off)
//   km      = floor(floor(u / 2^FF) / 2^l), taken mod N_l (mode 0) or clipped to
//             [0, N_l - 1] (mode 1), N_l = N >> l entries in level l
//   addr    = 2N - (2N >> l) + km                             (level l's offset in mip)
// With l = 0 the address is the point-lookup index k = floor(u) (mod N or clamped), so
// addr[NMAX-1:0] also addresses clut. FILTER 0 (point lookup only): l = 0 always.
// Output use_mip: read mip (filter on, FILTER 2), else clut.
// Latency 2 (outputs registered, not reset: an internal stage of colour_map, which
// carries the valid bit); one vector per enabled clock.
// Written for event-driven simulation speed: no reductions on per-clock signals.

`default_nettype none

module mip_index #(
    parameter FILTER = 2,                // 2 mip; 0 point lookup only (1, sat, does not use this)
    parameter U_W    = 33,               // width of u (signed)
    parameter W_W    = 33,               // width of w
    parameter FF     = 16,               // fraction bits of u and w
    parameter NMAX   = 8,                // log2 of the largest table (>= 1)
    parameter NL_W   = 4                 // width of n_log2
) (
    input  wire            clk,
    input  wire            ce,
    input  wire [U_W-1:0]  u_in,       // signed
    input  wire [W_W-1:0]  w_in,
    input  wire            mode,       // 0 mod, 1 clamp
    input  wire [NL_W-1:0] n_log2,
    input  wire            filter_en,
    output wire [NMAX:0]   addr_out,
    output wire            use_mip_out
);

localparam KU_W = U_W - FF;  // width of floor(u) (signed)

// ---- stage 1: entry index floor(u), level
wire [NL_W-1:0] lvl;
wire use_mip = (FILTER == 2) && filter_en;

generate
    if (FILTER == 2) begin : g_level
        wire [W_W-FF-1:0] we = w_in[W_W-1:FF];  // whole entries of w
        reg [NL_W-1:0] lvl_c;
        integer i;
        // l = min(bitlen(we) - 1, n_log2), 0 for we = 0: the largest i <= n_log2 with we >= 2^i
        always @* begin
            lvl_c = {NL_W{1'b0}};
            for (i = 1; i <= NMAX; i = i + 1)
                if (use_mip && (we >> i) != {(W_W-FF){1'b0}} && n_log2 >= i[NL_W-1:0])
                    lvl_c = i[NL_W-1:0];
        end
        assign lvl = lvl_c;
        /* verilator lint_off UNUSEDSIGNAL */
        wire [FF-1:0] unused_w = w_in[FF-1:0];
        /* verilator lint_on UNUSEDSIGNAL */
    end else begin : g_nolevel
        assign lvl = {NL_W{1'b0}};
        /* verilator lint_off UNUSEDSIGNAL */
        wire [W_W-1:0] unused_w = w_in;
        wire           unused_filter_en = filter_en;
        /* verilator lint_on UNUSEDSIGNAL */
    end
endgenerate

reg [KU_W-1:0] ku_reg;
reg [NL_W-1:0] lvl_reg;
reg            mode_reg;
reg [NL_W-1:0] n_log2_reg;
reg            use_mip_reg;

always @(posedge clk) begin
    if (ce) begin
        ku_reg      <= u_in[U_W-1:FF];
        lvl_reg     <= lvl;
        mode_reg    <= mode;
        n_log2_reg  <= n_log2;
        use_mip_reg <= use_mip;
    end
end

// the fraction of u does not reach the table index
/* verilator lint_off UNUSEDSIGNAL */
wire [FF-1:0] unused_frac = u_in[FF-1:0];
/* verilator lint_on UNUSEDSIGNAL */

// ---- stage 2: entry in level l, address
wire signed [KU_W-1:0] kms = $signed(ku_reg) >>> lvl_reg;      // floor(u) >> l
wire [NMAX-1:0] nlm1 = ~({NMAX{1'b1}} << (n_log2_reg - lvl_reg));  // N_l - 1
// level offset 2N - (2N >> l): ones in bits [n_log2+1-l, n_log2]
wire [NL_W:0] n1  = {1'b0, n_log2_reg} + 1'b1;  // log2(2N), one bit wider: no wrap
wire [NMAX:0] off = ~({(NMAX+1){1'b1}} << n1) & ({(NMAX+1){1'b1}} << (n1 - {1'b0, lvl_reg}));

reg [KU_W-1:0] nlm1_x;
reg [NMAX-1:0] km;

always @* begin
    nlm1_x = {KU_W{1'b0}};
    nlm1_x[NMAX-1:0] = nlm1;
    if (!mode_reg)
        km = kms[NMAX-1:0] & nlm1;
    else if (kms[KU_W-1])
        km = {NMAX{1'b0}};
    else if (kms > $signed(nlm1_x))
        km = nlm1;
    else
        km = kms[NMAX-1:0];
end

reg [NMAX:0] addr_reg;
reg          use_mip2_reg;

always @(posedge clk) begin
    if (ce) begin
        addr_reg     <= off + {1'b0, km};
        use_mip2_reg <= use_mip_reg;
    end
end

assign addr_out    = addr_reg;
assign use_mip_out = use_mip2_reg;

endmodule

`default_nettype wire
