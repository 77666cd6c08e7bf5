// texture_pipeline: the pixel pipeline of the texture unit (the RTL top).
//
// For every pixel (s, Jm, je) it computes, bit-exact with model/golden.py
// texture_pipeline / texture_stages,
//
//   f = q(s) + sum_i a_i n(T_i s + o_i)                 (quadric_mac + K x noise_term)
//   c = dq/ds + sum_i a_i (dn_i/dp) T_i                  (the texture-space gradient of f)
//   w = |c^T J| N                                        (filter_width, J = Jm 2^je)
//   rgba = colour_map(f, w)                              (SAT box filter / MIP / point)
//
// Formats (all widths `CFG_* from tex_cfg.vh, generated from config/<name>.toml):
//   s      s{S_W}.{S_FRAC}, three of them {r, t, s} (s at the LSBs)
//   Jm     s{J_W}.0, six of them, Jm[k][col] at element 2*k+col; je s{JE_W}.0 (J = Jm 2^je)
//   f      s{F_W}.{F_FRAC}: q (QF_W bits) and the K a_i n_i (AN_W bits) sign-extended to
//          F_W and summed exactly (F_W is their worst-case bound, docs/numerics.md)
//   c      3 x s{C_W}.{C_FRAC}: dq/ds (C_W) plus the K a_i grad n_i (AG_W), summed exactly
//   w      u{W_W}.{F_FRAC} colour-table entries; rgba RGBA8, R at [7:0], A at [31:24]
//
// Pixel input word, s_axis_tdata[PIX_W-1:0] (PIX_W = 3*S_W + 6*J_W + JE_W; model/regmap.py
// pack_pixels is its Python twin):
//   [3*S_W-1 : 0]                     s  = {r, t, s}      (element e at [e*S_W +: S_W])
//   [3*S_W+6*J_W-1 : 3*S_W]           jm = Jm[k][col] at element 2*k+col (J_W bits each)
//   [PIX_W-1 : 3*S_W+6*J_W]           je
//
// Register map (cfg_wr_addr is a 32-bit-word address; writes to unmapped addresses and past
// the end of a table are ignored; values are taken from the LSBs of cfg_wr_data, two's complement for signed
// fields; model/regmap.py write_sequence is the Python twin):
//   0x0000            CTRL: [0] mode (0 mod, 1 clamp), [1] filter_en,
//                     [8 +: N_LOG2_W] n_log2 (N = 2^n_log2 colour-table entries)
//   0x0010 + i        Q coefficient i = 0..9 (A..J), s{Q_W}.{Q_FRAC}
//   0x0100 + 16*k     noise term k = 0..K-1:  +0 a_k s{A_W}.{A_FRAC};
//                     +1+3*j+m T_k[j][m] s{T_W}.{T_FRAC}; +10+j o_k[j] u{O_W}.{P_FRAC}
//   0x1000 + n        clut[n], RGBA8 (R at [7:0]), n < 2^N_LOG2_MAX
//   0x2000 + 4*n + ch csat[n] channel ch (u{CSAT_W}); channels 0..2 go to a staging
//                     register, the write of channel 3 commits the whole entry n (write the
//                     four words of an entry in order, channel 3 last; the last csat entry
//                     committed must be entry N - 1, the whole-table sum: write csat in
//                     ascending order)
//   0x3000 + m        mip[m], RGBA8, m < 2^(N_LOG2_MAX+1) - 1 (levels one after another)
//   Table writes are forwarded to colour_map's write port one clock later. After rst every
//   parameter register is 0 (the tables are not reset). Write the parameters while no pixel
//   is in flight; they are held, unchanged, during a pass.
//
// Pipeline: quadric_mac and K noise_term instances in parallel on s, a registered adder tree
// of arity 4 for f (TREE_LEVELS = ceil(log4(K+1)) stages), filter_width, then colour_map.
// With the noise gradient (`CFG_NOISE_GRADIENT 1: grad f = grad q + sum a_i grad n_i), the
// tree also sums the gradients and filter_width follows it; the quadric's input waits so that
// its outputs meet the terms'. Without it (grad f = grad q), filter_width runs on the
// quadric's gradient in parallel with the noise terms, and q waits for the terms instead.
// f (in fewer bits, see below) or w waits for the other before colour_map; Jm, je and tlast
// travel in delay lines (delay_line) beside the data. Every
// register of the datapath shares one clock enable
//   ce = rst | !cm_valid | skid_ready_reg
// (the colour_map output is the last pipeline stage; it may advance whenever it is empty or
// the output skid buffer can take it). The output skid buffer (two registers, the pattern of
// alexforencich/verilog-axis axis_register, REG_TYPE = 2) has a registered input ready, so
// no combinational path runs from m_axis_tready to s_axis_tready or ce, and a stall on
// m_axis_tready never loses, duplicates or reorders a pixel. s_axis_tready = ce (& !rst):
// a pixel enters whenever the pipeline advances.
//
// Latency: LATENCY = T_CM + LAT_COLOUR_MAP enabled clocks from s_axis to the colour_map output,
// T_CM = max(T_F, T_WD) = max(LAT_FRONT + TREE_LEVELS, DLY_J + LAT_FILTER_WIDTH) (below), plus one clock in the
// skid buffer. Throughput: one pixel per clock while m_axis_tready is held high.
// Reset: synchronous, active high; clears every valid bit, the output registers, the
// parameter registers and the staging register (no output is X after reset).

`default_nettype none

`include "tex_cfg.vh"
`include "tex_latency.vh"

// The parameters restate the configuration's defines for readability; the blocks take their
// widths from the same defines, so keep the defaults.
module texture_pipeline #(
    parameter K        = `CFG_NOISE_TERMS,  // noise terms (0..8)
    parameter S_W      = `CFG_S_W,          // texture coordinate word
    parameter Q_W      = `CFG_Q_W,          // quadric coefficient word
    parameter J_W      = `CFG_J_W,          // Jacobian mantissa word
    parameter JE_W     = `CFG_JE_W,         // Jacobian shared exponent word
    parameter T_W      = `CFG_T_W,          // noise transform entry word
    parameter A_W      = `CFG_A_W,          // noise amplitude word
    parameter O_W      = `CFG_O_W,          // noise offset word
    parameter QF_W     = `CFG_QF_W,         // quadric value (f_frac) word
    parameter AN_W     = `CFG_AN_W,         // a_i n_i word
    parameter AG_W     = `CFG_AG_W,         // a_i grad n_i component word
    parameter F_W      = `CFG_F_W,          // f word (exact sum)
    parameter C_W      = `CFG_C_W,          // grad f component word (exact sum)
    parameter W_W      = `CFG_W_W,          // filter width word
    parameter CSAT_W   = `CFG_CSAT_W,       // summed-area table channel word
    parameter NL_W     = `CFG_N_LOG2_W,     // n_log2 word
    parameter NLMAX    = `CFG_N_LOG2_MAX,   // log2 of the largest colour table
    parameter PIX_W    = 3*S_W + 6*J_W + JE_W  // pixel input word
) (
    input  wire             clk,
    input  wire             rst,

    // parameter write port (32-bit words, register map above)
    input  wire             cfg_wr_en,
    input  wire [15:0]      cfg_wr_addr,
    input  wire [31:0]      cfg_wr_data,

    // pixel input stream: {je, jm, s}
    input  wire [PIX_W-1:0] s_axis_tdata,
    input  wire             s_axis_tvalid,
    output wire             s_axis_tready,
    input  wire             s_axis_tlast,

    // colour output stream: RGBA8, R at [7:0]
    output wire [31:0]      m_axis_tdata,
    output wire             m_axis_tvalid,
    input  wire             m_axis_tready,
    output wire             m_axis_tlast
);

// ---------------------------------------------------------------------------
// Latencies and alignment

// adder tree shape (arity TREE_ARITY, below): nodes on level l of a tree over n leaves
function integer tree_nodes_of;
    input integer n;
    input integer l;
    input integer arity;
    integer i;
    begin
        tree_nodes_of = n;
        for (i = 0; i < l; i = i + 1)
            tree_nodes_of = (tree_nodes_of + arity - 1) / arity;
    end
endfunction

// levels of register nodes down to one node
function integer tree_levels_of;
    input integer n;
    input integer arity;
    integer m;
    begin
        tree_levels_of = 0;
        for (m = n; m > 1; m = (m + arity - 1) / arity)
            tree_levels_of = tree_levels_of + 1;
    end
endfunction

localparam LAT_QM      = `LAT_QUADRIC_MAC;
localparam LAT_NT      = `LAT_NOISE_TERM;
localparam LAT_FW      = `LAT_FILTER_WIDTH;
localparam LAT_CM      = `LAT_COLOUR_MAP;
localparam LAT_FRONT   = (K > 0 && LAT_NT > LAT_QM) ? LAT_NT : LAT_QM;  // q and the terms meet here
localparam DLY_N       = LAT_FRONT - LAT_NT;                             // extra stages for an, ag
localparam TREE_ARITY  = 4;                                              // adder tree fan-in
localparam TREE_LEVELS = tree_levels_of(K + 1, TREE_ARITY);              // adder tree stages
localparam T_F         = LAT_FRONT + TREE_LEVELS;                        // f (and c) out of the tree
// With the noise gradient (NG), grad f = grad q + sum a_i grad n_i comes out of the tree with
// f, and filter_width follows the tree: the quadric's input waits DLY_Q so that its outputs
// meet the terms'. Without it, grad f = grad q: filter_width takes the quadric's gradient
// straight away, in parallel with the noise terms, and only q waits (DLY_QO) for the terms.
localparam NG          = `CFG_NOISE_GRADIENT;
localparam DLY_Q       = NG ? LAT_FRONT - LAT_QM : 0;                    // quadric input (s) delay
localparam DLY_QO      = NG ? 0 : LAT_FRONT - LAT_QM;                    // quadric q output delay
localparam DLY_J       = NG ? T_F : LAT_QM;                              // Jm, je to filter_width
localparam T_WD        = DLY_J + LAT_FW;                                 // w out of filter_width
localparam T_CM        = (T_WD > T_F) ? T_WD : T_F;                       // colour_map input
localparam DLY_F       = T_CM - T_F;                                     // f waits for w
localparam DLY_W       = T_CM - T_WD;                                    // or w waits for f
// total latency to the colour_map output (the skid buffer adds one more clock); for readers
// and waveform viewers only, nothing below needs it
/* verilator lint_off UNUSEDPARAM */
localparam LATENCY     = T_CM + LAT_CM;
/* verilator lint_on UNUSEDPARAM */

localparam JM_W = 6*J_W;
localparam ND_W = AN_W + 3*AG_W + 1;  // a noise term's outputs and valid

// register map
localparam [3:0] REGION_REGS = 4'h0;
localparam [3:0] REGION_CLUT = 4'h1;
localparam [3:0] REGION_CSAT = 4'h2;
localparam [3:0] REGION_MIP  = 4'h3;
localparam [1:0] TABLE_CLUT  = 2'd0;
localparam [1:0] TABLE_CSAT  = 2'd1;
localparam [1:0] TABLE_MIP   = 2'd2;

// ---------------------------------------------------------------------------
// Flow control

wire cm_valid;          // colour_map output (last pipeline stage) holds a pixel
reg  skid_ready_reg;    // the output skid buffer can take a pixel this clock
wire advance = !cm_valid || skid_ready_reg;
wire ce      = rst || advance;  // rst: every block's reset sees an enabled clock

assign s_axis_tready = advance && !rst;
wire in_valid = s_axis_tvalid && !rst;

// ---------------------------------------------------------------------------
// Parameter registers

wire [3:0] wr_region = cfg_wr_addr[15:12];
wire       wr_regs   = cfg_wr_en && wr_region == REGION_REGS;

reg            mode_reg;
reg            filter_en_reg;
reg [NL_W-1:0] n_log2_reg;

always @(posedge clk) begin
    if (rst) begin
        mode_reg      <= 1'b0;
        filter_en_reg <= 1'b0;
        n_log2_reg    <= {NL_W{1'b0}};
    end else if (wr_regs && cfg_wr_addr[11:0] == 12'h000) begin
        mode_reg      <= cfg_wr_data[0];
        filter_en_reg <= cfg_wr_data[1];
        n_log2_reg    <= cfg_wr_data[8 +: NL_W];
    end
end

wire [10*Q_W-1:0] q_coef;
localparam KV = (K > 0) ? K : 1;  // K = 0 still declares (unused) vectors
/* verilator lint_off UNUSEDSIGNAL */  // read by no noise term when K = 0
wire [KV*A_W-1:0]   a_all;
wire [KV*9*T_W-1:0] t_all;
wire [KV*3*O_W-1:0] o_all;
/* verilator lint_on UNUSEDSIGNAL */

genvar gi, gj;
generate
    for (gi = 0; gi < 10; gi = gi + 1) begin : g_qreg
        localparam [11:0] ADDR = 12'h010 + gi;
        reg [Q_W-1:0] val_reg;
        always @(posedge clk) begin
            if (rst)
                val_reg <= {Q_W{1'b0}};
            else if (wr_regs && cfg_wr_addr[11:0] == ADDR)
                val_reg <= cfg_wr_data[Q_W-1:0];
        end
        assign q_coef[gi*Q_W +: Q_W] = val_reg;
    end

    if (K == 0) begin : g_no_terms
        assign a_all = {A_W{1'b0}};
        assign t_all = {9*T_W{1'b0}};
        assign o_all = {3*O_W{1'b0}};
    end
    for (gi = 0; gi < K; gi = gi + 1) begin : g_term_reg
        localparam [3:0] TERM = gi;  // registers 0x100 + 16*TERM ..
        wire term_wr = wr_regs && cfg_wr_addr[11:8] == 4'h1 && cfg_wr_addr[7:4] == TERM;
        wire [3:0] field = cfg_wr_addr[3:0];
        reg [A_W-1:0] a_reg;
        always @(posedge clk) begin
            if (rst)
                a_reg <= {A_W{1'b0}};
            else if (term_wr && field == 4'd0)
                a_reg <= cfg_wr_data[A_W-1:0];
        end
        assign a_all[gi*A_W +: A_W] = a_reg;
        for (gj = 0; gj < 9; gj = gj + 1) begin : g_t
            localparam [3:0] FIELD = 1 + gj;
            reg [T_W-1:0] t_reg;
            always @(posedge clk) begin
                if (rst)
                    t_reg <= {T_W{1'b0}};
                else if (term_wr && field == FIELD)
                    t_reg <= cfg_wr_data[T_W-1:0];
            end
            assign t_all[(gi*9 + gj)*T_W +: T_W] = t_reg;
        end
        for (gj = 0; gj < 3; gj = gj + 1) begin : g_o
            localparam [3:0] FIELD = 10 + gj;
            reg [O_W-1:0] o_reg;
            always @(posedge clk) begin
                if (rst)
                    o_reg <= {O_W{1'b0}};
                else if (term_wr && field == FIELD)
                    o_reg <= cfg_wr_data[O_W-1:0];
            end
            assign o_all[(gi*3 + gj)*O_W +: O_W] = o_reg;
        end
    end
endgenerate

// colour tables: forwarded to colour_map one clock later; csat entries are staged
reg [3*CSAT_W-1:0] csat_stage_reg;
reg                tbl_wr_en_reg;
reg [1:0]          tbl_wr_table_reg;
reg [NLMAX:0]      tbl_wr_addr_reg;
reg [4*CSAT_W-1:0] tbl_wr_data_reg;

wire [1:0] csat_ch = cfg_wr_addr[1:0];
// table index in range: clut n < 2^NLMAX, csat 4n + ch < 2^(NLMAX+2), mip m < 2^(NLMAX+1)
// (a write past the end of a table is ignored, never aliased)
wire clut_in_range = (cfg_wr_addr[11:0] >> NLMAX) == 12'd0;
wire csat_in_range = (cfg_wr_addr[11:0] >> (NLMAX + 2)) == 12'd0;
wire mip_in_range  = (cfg_wr_addr[11:0] >> (NLMAX + 1)) == 12'd0;

// an RGBA8 word spread over the four CSAT_W channel fields of the table write data
wire [4*CSAT_W-1:0] rgba_wide;
generate
    for (gi = 0; gi < 4; gi = gi + 1) begin : g_rgba_wide
        if (CSAT_W > 8) begin : g_pad
            assign rgba_wide[gi*CSAT_W +: CSAT_W] = {{(CSAT_W-8){1'b0}}, cfg_wr_data[gi*8 +: 8]};
        end else begin : g_nopad
            assign rgba_wide[gi*CSAT_W +: CSAT_W] = cfg_wr_data[gi*8 +: 8];
        end
    end
endgenerate

always @(posedge clk) begin
    if (rst) begin
        csat_stage_reg   <= {3*CSAT_W{1'b0}};
        tbl_wr_en_reg    <= 1'b0;
        tbl_wr_table_reg <= TABLE_CLUT;
        tbl_wr_addr_reg  <= {(NLMAX+1){1'b0}};
        tbl_wr_data_reg  <= {4*CSAT_W{1'b0}};
    end else begin
        tbl_wr_en_reg <= 1'b0;
        if (cfg_wr_en) begin
            case (wr_region)
                REGION_CLUT: begin
                    tbl_wr_en_reg    <= clut_in_range;
                    tbl_wr_table_reg <= TABLE_CLUT;
                    tbl_wr_addr_reg  <= cfg_wr_addr[NLMAX:0];
                    tbl_wr_data_reg  <= rgba_wide;
                end
                REGION_CSAT: begin
                    if (csat_ch == 2'd3) begin
                        tbl_wr_en_reg    <= csat_in_range;
                        tbl_wr_table_reg <= TABLE_CSAT;
                        tbl_wr_addr_reg  <= cfg_wr_addr[NLMAX+2:2];
                        tbl_wr_data_reg  <= {cfg_wr_data[CSAT_W-1:0], csat_stage_reg};
                    end else begin
                        csat_stage_reg[csat_ch*CSAT_W +: CSAT_W] <= cfg_wr_data[CSAT_W-1:0];
                    end
                end
                REGION_MIP: begin
                    tbl_wr_en_reg    <= mip_in_range;
                    tbl_wr_table_reg <= TABLE_MIP;
                    tbl_wr_addr_reg  <= cfg_wr_addr[NLMAX:0];
                    tbl_wr_data_reg  <= rgba_wide;
                end
                default: ;
            endcase
        end
    end
end

// ---------------------------------------------------------------------------
// Input fields

wire [3*S_W-1:0]  px_s  = s_axis_tdata[0 +: 3*S_W];
wire [JM_W-1:0]   px_jm = s_axis_tdata[3*S_W +: JM_W];
wire [JE_W-1:0]   px_je = s_axis_tdata[3*S_W + JM_W +: JE_W];

// ---------------------------------------------------------------------------
// Front: quadric_mac and K noise terms in parallel

// NG: the quadric is the shorter block: its input (s and valid, narrower than its outputs)
// waits DLY_Q stages so that its outputs meet the noise terms' at LAT_FRONT.
wire [3*S_W-1:0] qs_s;
wire             qs_valid;
delay_line #(.W(3*S_W), .N(DLY_Q))           u_dly_qs (.clk(clk), .rst(rst), .ce(ce), .d_in(px_s), .d_out(qs_s));
delay_line #(.W(1), .N(DLY_Q), .CLEAR(1))    u_dly_qv (.clk(clk), .rst(rst), .ce(ce), .d_in(in_valid), .d_out(qs_valid));

wire [QF_W-1:0]  qm_q;
wire [3*C_W-1:0] qm_cq;
wire             qm_valid;

quadric_mac u_quadric_mac (
    .clk(clk), .rst(rst), .ce(ce),
    .in_valid(qs_valid),
    .s_in(qs_s),
    .q_coef(q_coef),
    .out_valid(qm_valid),
    .q_out(qm_q),
    .cq_out(qm_cq)
);

// Each term's outputs and the quadric's, sign-extended to the exact-sum widths, are the
// leaves of the adder tree. (Wide flat buses are avoided on per-clock paths: every signal
// below lives in its own generate block, which keeps event-driven simulators fast.)
wire [K:0] front_valid;  // bit 0 quadric, bit 1+k noise term k

// !NG: q (and its valid) wait DLY_QO stages for the terms; its gradient goes to filter_width
wire [QF_W-1:0] qo_q;
delay_line #(.W(QF_W), .N(DLY_QO))        u_dly_qo (.clk(clk), .rst(rst), .ce(ce), .d_in(qm_q), .d_out(qo_q));
delay_line #(.W(1), .N(DLY_QO), .CLEAR(1)) u_dly_qov (.clk(clk), .rst(rst), .ce(ce), .d_in(qm_valid),
                                                       .d_out(front_valid[0]));
wire [F_W-1:0]   q_f_ext;
wire [3*C_W-1:0] q_c_ext = NG ? qm_cq : {3*C_W{1'b0}};  // !NG: the tree carries no gradient
generate
    if (F_W > QF_W) begin : g_qext
        assign q_f_ext = {{(F_W-QF_W){qo_q[QF_W-1]}}, qo_q};
    end else begin : g_qnoext
        assign q_f_ext = qo_q[F_W-1:0];
    end

    for (gi = 0; gi < K; gi = gi + 1) begin : g_term
        wire [AN_W-1:0]   an;
        wire [3*AG_W-1:0] ag;
        wire              nt_valid;
        noise_term u_noise_term (
            .clk(clk), .rst(rst), .ce(ce),
            .in_valid(in_valid),
            .s_in(px_s),
            .a_in(a_all[gi*A_W +: A_W]),
            .t_in(t_all[gi*9*T_W +: 9*T_W]),
            .o_in(o_all[gi*3*O_W +: 3*O_W]),
            .out_valid(nt_valid),
            .an_out(an),
            .ag_out(ag)
        );
        // delayed to LAT_FRONT (normally DLY_N = 0)
        wire [ND_W-1:0] nd_in = {nt_valid, ag, an};
        wire [ND_W-1:0] nd_out;
        delay_line #(.W(ND_W), .N(DLY_N)) u_dly_n (.clk(clk), .rst(rst), .ce(ce), .d_in(nd_in), .d_out(nd_out));
        assign front_valid[gi+1] = nd_out[AN_W+3*AG_W];
        // sign extension to the exact-sum widths
        wire [F_W-1:0]   f_ext;
        wire [3*C_W-1:0] c_ext;
        if (F_W > AN_W) begin : g_anext
            assign f_ext = {{(F_W-AN_W){nd_out[AN_W-1]}}, nd_out[0 +: AN_W]};
        end else begin : g_annoext
            assign f_ext = nd_out[0 +: F_W];
        end
        if (`CFG_NOISE_GRADIENT) begin : g_grad
            for (gj = 0; gj < 3; gj = gj + 1) begin : g_agext
                wire [AG_W-1:0] agk = nd_out[AN_W + gj*AG_W +: AG_W];
                if (C_W > AG_W) begin : g_ext
                    assign c_ext[gj*C_W +: C_W] = {{(C_W-AG_W){agk[AG_W-1]}}, agk};
                end else begin : g_noext
                    assign c_ext[gj*C_W +: C_W] = agk[C_W-1:0];
                end
            end
        end else begin : g_no_grad
            // grad f = grad q: the terms' ag outputs are 0 by construction and not summed
            assign c_ext = {3*C_W{1'b0}};
            wire unused_ag = &{1'b0, nd_out[AN_W +: 3*AG_W]};
        end
    end

    // tree leaves: 0 the quadric, 1..K the terms
    for (gi = 0; gi <= K; gi = gi + 1) begin : g_leaf
        wire [F_W-1:0]   f;
        wire [3*C_W-1:0] c;
        if (gi == 0) begin : g_q
            assign f = q_f_ext;
            assign c = q_c_ext;
        end else begin : g_n
            assign f = g_term[gi-1].f_ext;
            assign c = g_term[gi-1].c_ext;
        end
    end
endgenerate

// every block of the front must agree on validity (they share in_valid and ce)
wire sum_in_valid = &front_valid;

// ---------------------------------------------------------------------------
// Adder tree of arity TREE_ARITY: level 0 is the K + 1 leaves, level l has
// tree_nodes(l) = ceil(tree_nodes(l - 1) / TREE_ARITY) nodes, each a register holding the
// sum of its (up to TREE_ARITY) children; TREE_LEVELS levels down to one node (fewer
// registers than a binary tree: one level for K <= 3, two for K <= 15). Sums are modulo
// 2^F_W / 2^C_W of sign-extended operands, i.e. exact two's complement sums: every partial
// sum is bounded by the whole sum's bound, which F_W and C_W hold (model/config.py f_w, c_w).

genvar gl;
generate
    for (gl = 0; gl <= TREE_LEVELS; gl = gl + 1) begin : g_lvl
        localparam NN = tree_nodes_of(K + 1, gl, TREE_ARITY);  // nodes (level 0: leaves) on this level
        wire [NN*F_W-1:0]   f_bus;
        wire [NN*3*C_W-1:0] c_bus;
        if (gl == 0) begin : g_leaves
            for (gi = 0; gi < NN; gi = gi + 1) begin : g_in
                assign f_bus[gi*F_W +: F_W]       = g_leaf[gi].f;
                assign c_bus[gi*3*C_W +: 3*C_W]   = g_leaf[gi].c;
            end
        end else begin : g_nodes
            localparam NP = tree_nodes_of(K + 1, gl - 1, TREE_ARITY);  // children on the level below
            for (gi = 0; gi < NN; gi = gi + 1) begin : g_node
                localparam NC = (NP - TREE_ARITY*gi < TREE_ARITY) ? NP - TREE_ARITY*gi : TREE_ARITY;
                wire [NC*F_W-1:0]   f_kids = g_lvl[gl-1].f_bus[TREE_ARITY*gi*F_W +: NC*F_W];
                wire [NC*3*C_W-1:0] c_kids = g_lvl[gl-1].c_bus[TREE_ARITY*gi*3*C_W +: NC*3*C_W];
                reg  [F_W-1:0]      f_sum_c;
                reg  [3*C_W-1:0]    c_sum_c;
                integer             k, ch;
                always @* begin
                    f_sum_c = {F_W{1'b0}};
                    c_sum_c = {3*C_W{1'b0}};
                    for (k = 0; k < NC; k = k + 1) begin
                        f_sum_c = f_sum_c + f_kids[k*F_W +: F_W];
                        for (ch = 0; ch < 3; ch = ch + 1)
                            c_sum_c[ch*C_W +: C_W] = c_sum_c[ch*C_W +: C_W] + c_kids[(3*k + ch)*C_W +: C_W];
                    end
                end
                reg [F_W-1:0]   f_reg;
                reg [3*C_W-1:0] c_reg;
                always @(posedge clk) begin
                    if (ce) begin
                        f_reg <= f_sum_c;
                        c_reg <= c_sum_c;
                    end
                end
                assign f_bus[gi*F_W +: F_W]     = f_reg;
                assign c_bus[gi*3*C_W +: 3*C_W] = c_reg;
            end
        end
    end
endgenerate

wire [F_W-1:0]   f_sum = g_lvl[TREE_LEVELS].f_bus;
wire [3*C_W-1:0] c_sum = g_lvl[TREE_LEVELS].c_bus;

// valid through the tree (reset: no spurious pixel after rst)
wire sum_valid;
generate
    if (TREE_LEVELS == 0) begin : g_tv0
        assign sum_valid = sum_in_valid;
    end else begin : g_tv
        // TREE_LEVELS + 1 bits so that one level still has a legal shift expression
        reg [TREE_LEVELS:0] v_reg;
        always @(posedge clk) begin
            if (rst)
                v_reg <= {(TREE_LEVELS+1){1'b0}};
            else if (ce)
                v_reg <= {v_reg[TREE_LEVELS-1:0], sum_in_valid};
        end
        assign sum_valid = v_reg[TREE_LEVELS-1];
    end
endgenerate

// ---------------------------------------------------------------------------
// Jm, je: from the input to filter_width (DLY_J stages); tlast: to the colour_map output

localparam JD_W = JM_W + JE_W;
wire [JD_W-1:0] jd_out;
delay_line #(.W(JD_W), .N(DLY_J)) u_dly_j (.clk(clk), .rst(rst), .ce(ce), .d_in({px_je, px_jm}), .d_out(jd_out));

wire cm_last;
delay_line #(.W(1), .N(T_CM + LAT_CM)) u_dly_last (.clk(clk), .rst(rst), .ce(ce), .d_in(s_axis_tlast),
                                                  .d_out(cm_last));

// ---------------------------------------------------------------------------
// filter_width on grad f (NG: the tree's c; otherwise the quadric's gradient)

wire [W_W-1:0] fw_w;
wire           fw_valid;

filter_width u_filter_width (
    .clk(clk), .rst(rst), .ce(ce),
    .in_valid(NG ? sum_valid : qm_valid),
    .c_in(NG ? c_sum : qm_cq),
    .jm_in(jd_out[0 +: JM_W]),
    .je_in(jd_out[JM_W +: JE_W]),
    .n_log2(n_log2_reg),
    .out_valid(fw_valid),
    .w_out(fw_w)
);

// !NG: the c sums of the tree are constant 0 (no register survives synthesis)
/* verilator lint_off UNUSEDSIGNAL */
wire unused_c_sum = &{1'b0, c_sum};
/* verilator lint_on UNUSEDSIGNAL */

// While it waits, f is carried in FC_W <= F_W bits: colour_map reads only f mod 1 in mod mode
// (the low F_FRAC bits), and in clamp mode compares f with thresholds inside
// [-2^GUARD, 2^F_FRAC + 2^GUARD], GUARD = W_CAP_LOG2 + F_FRAC - 1, so saturating f to
// +-2^(GUARD+1) there changes no result. mode_reg is static during a pass.
localparam GUARD = `CFG_W_CAP_LOG2 + `CFG_F_FRAC - 1;
localparam FC_W  = (DLY_F > 0 && GUARD + 3 < F_W) ? GUARD + 3 : F_W;
wire [FC_W-1:0] f_carry;
generate
    if (FC_W < F_W) begin : g_fsat
        wire signed [F_W-1:0] f_s   = f_sum;
        wire signed [F_W-1:0] f_top = {{(F_W-GUARD-2){1'b0}}, 1'b1, {(GUARD+1){1'b0}}};  //  2^(GUARD+1)
        wire signed [F_W-1:0] f_bot = -f_top;                                              // -2^(GUARD+1)
        wire [F_W-1:0] f_clip = (f_s > f_top) ? f_top : (f_s < f_bot) ? f_bot : f_sum;
        assign f_carry = mode_reg ? f_clip[FC_W-1:0] : f_sum[FC_W-1:0];
        /* verilator lint_off UNUSEDSIGNAL */
        wire unused_fhi = &{1'b0, f_clip[F_W-1:FC_W]};  // sign copies of a value that fits FC_W
        /* verilator lint_on UNUSEDSIGNAL */
    end else begin : g_fwhole
        assign f_carry = f_sum;
    end
endgenerate

// f waits DLY_F stages for w, or w waits DLY_W stages for f (one of them is 0)
wire [FC_W-1:0] f_dly;
wire [W_W-1:0]  cm_w;
delay_line #(.W(FC_W), .N(DLY_F)) u_dly_f (.clk(clk), .rst(rst), .ce(ce), .d_in(f_carry), .d_out(f_dly));
delay_line #(.W(W_W), .N(DLY_W))  u_dly_w (.clk(clk), .rst(rst), .ce(ce), .d_in(fw_w), .d_out(cm_w));
// the later of the two paths brings the valid bit (the earlier one is delayed to match it)
wire cm_in_valid = (DLY_W > 0) ? sum_valid : fw_valid;

// ---------------------------------------------------------------------------
// colour_map

wire [31:0] cm_rgba;
wire [F_W-1:0] f_cm;  // f back to F_W bits (sign-extended)
generate
    if (FC_W < F_W) begin : g_fext
        assign f_cm = {{(F_W-FC_W){f_dly[FC_W-1]}}, f_dly};
    end else begin : g_fnoext
        assign f_cm = f_dly;
    end
endgenerate

colour_map u_colour_map (
    .clk(clk), .rst(rst), .ce(ce),
    .in_valid(cm_in_valid),
    .f_in(f_cm),
    .w_in(cm_w),
    .mode(mode_reg),
    .n_log2(n_log2_reg),
    .filter_en(filter_en_reg),
    .out_valid(cm_valid),
    .rgba_out(cm_rgba),
    .wr_en(tbl_wr_en_reg),
    .wr_table(tbl_wr_table_reg),
    .wr_addr(tbl_wr_addr_reg),
    .wr_data(tbl_wr_data_reg)
);

// ---------------------------------------------------------------------------
// Output skid buffer (alexforencich/verilog-axis axis_register, REG_TYPE = 2)

reg [31:0] m_data_reg;
reg        m_valid_reg, m_valid_next;
reg        m_last_reg;
reg [31:0] temp_data_reg;
reg        temp_valid_reg, temp_valid_next;
reg        temp_last_reg;
reg        store_in_to_out, store_in_to_temp, store_temp_to_out;

// ready next clock if the output is taken now, or the temporary register stays empty
wire skid_ready_early = m_axis_tready || (!temp_valid_reg && (!m_valid_reg || !cm_valid));

always @* begin
    m_valid_next      = m_valid_reg;
    temp_valid_next   = temp_valid_reg;
    store_in_to_out   = 1'b0;
    store_in_to_temp  = 1'b0;
    store_temp_to_out = 1'b0;
    if (skid_ready_reg) begin
        // input is ready
        if (m_axis_tready || !m_valid_reg) begin
            // output is ready or empty: input to output
            m_valid_next    = cm_valid;
            store_in_to_out = 1'b1;
        end else begin
            // output is stalled: input to the temporary register
            temp_valid_next  = cm_valid;
            store_in_to_temp = 1'b1;
        end
    end else if (m_axis_tready) begin
        // input is not ready, output is ready: temporary register to output
        m_valid_next      = temp_valid_reg;
        temp_valid_next   = 1'b0;
        store_temp_to_out = 1'b1;
    end
end

always @(posedge clk) begin
    if (rst) begin
        skid_ready_reg <= 1'b0;
        m_valid_reg    <= 1'b0;
        m_data_reg     <= 32'd0;
        m_last_reg     <= 1'b0;
        temp_valid_reg <= 1'b0;
        temp_data_reg  <= 32'd0;
        temp_last_reg  <= 1'b0;
    end else begin
        skid_ready_reg <= skid_ready_early;
        m_valid_reg    <= m_valid_next;
        temp_valid_reg <= temp_valid_next;
        // data registers load only real pixels (never the X of an empty pipeline stage)
        if (store_in_to_out && cm_valid) begin
            m_data_reg <= cm_rgba;
            m_last_reg <= cm_last;
        end else if (store_temp_to_out) begin
            m_data_reg <= temp_data_reg;
            m_last_reg <= temp_last_reg;
        end
        if (store_in_to_temp && cm_valid) begin
            temp_data_reg <= cm_rgba;
            temp_last_reg <= cm_last;
        end
    end
end

assign m_axis_tdata  = m_data_reg;
assign m_axis_tvalid = m_valid_reg;
assign m_axis_tlast  = m_last_reg;

endmodule

`default_nettype wire
