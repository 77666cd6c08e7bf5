// sum_tree: a registered adder tree, the exact sum of N words (texture_pipeline: f = q +
// sum_i a_i n_i, and each component of c = dq/ds + sum_i a_i grad n_i).
//
// Level 0 is the N leaves; level l has nodes_of(N, l) = ceil(nodes_of(N, l - 1) / ARITY)
// nodes, each a register holding the sum of its (up to ARITY) children on level l - 1, the
// missing children of the last node 0; LATENCY levels down to one node, the sum. ARITY is
// `SUM_TREE_ARITY (rtl/tex_latency.vh): fewer registers than a binary tree (one level for
// N <= 4, two for N <= 16). LANES independent sums run side by side (texture_pipeline sums
// the three components of c in one tree), each lane a node register of its own.
//
// Formats: every leaf and the sum are W-bit two's-complement words (any binary point, the
// same for all); sums are modulo 2^W, i.e. exact when the caller's W bounds the whole sum
// (then every partial sum fits too: texture_pipeline's F_W, C_W, model/hw/config.py f_w, c_w).
// Leaf i, lane j at leaves[(i*LANES + j)*W +: W]; lane j of the sum at sum_out[j*W +: W].
// Latency LATENCY = tw_tree_levels(N, `SUM_TREE_ARITY) register stages (0 for N = 1: a wire;
// the parent passes the value it aligns to, elaboration fails on another); one sum per
// enabled clock. Reset: synchronous, active high, clears the valid bits only (data
// registers have no reset). A level's node registers load only on an enabled clock that
// brings it a valid vector (in_valid, or the level below's valid bit) and hold otherwise, so
// that a simulator skips the idle levels; sum_out is the last valid sum while out_valid is low.

`default_nettype none

`include "tex_latency.vh"

module sum_tree #(
    parameter N       = 2,  // leaves (>= 1)
    parameter W       = 8,  // word width of every leaf, partial sum and the sum
    parameter LANES   = 1,  // independent sums side by side
    parameter LATENCY = 1   // register levels: must be tw_tree_levels(N, `SUM_TREE_ARITY)
) (
    /* verilator lint_off UNUSEDSIGNAL */  // LATENCY = 0: a wire, no register
    input  wire                 clk,
    input  wire                 rst,
    input  wire                 ce,
    /* verilator lint_on UNUSEDSIGNAL */
    input  wire                 in_valid,
    input  wire [N*LANES*W-1:0] leaves,
    output wire                 out_valid,
    output wire [LANES*W-1:0]   sum_out
);

`include "tex_widths.vh"

localparam ARITY = `SUM_TREE_ARITY;  // children of a node
localparam LW    = LANES*W;          // one leaf (all lanes)

// elaboration fails (unknown module) when the parent's latency is not the tree's
generate
    if (N < 1 || W < 1 || LANES < 1 || ARITY != 4 || LATENCY != tw_tree_levels(N, ARITY)) begin : g_bad_params
        sum_tree_latency_must_be_its_levels u_error ();
    end
endgenerate

// the valid bit of each level's node registers, v_reg[k] level k+1's (clocked in g_sum_node; declared
// here, where each level's enable reads it: LATENCY + 1 bits so that one level still has a legal shift
// expression; LATENCY = 0, the tree a wire: neither driven nor read)
/* verilator lint_off UNUSEDSIGNAL */
/* verilator lint_off UNDRIVEN */
reg [LATENCY:0] v_reg;
/* verilator lint_on UNDRIVEN */
/* verilator lint_on UNUSEDSIGNAL */

genvar gl, gi;
generate
    for (gl = 1; gl <= LATENCY; gl = gl + 1) begin : g_lvl
        localparam NN = tw_tree_nodes(N, gl, ARITY);      // nodes on this level
        localparam NP = tw_tree_nodes(N, gl - 1, ARITY);  // children on the level below
        // the valid of the level's children: in_valid (level 1) or the level below's valid bit
        if (gl == 1) begin : g_lv
            wire v = in_valid;
        end else begin : g_lv
            wire v = v_reg[gl-2];
        end
        // the children: the leaves (level 1) or the node registers of the level below
        for (gi = 0; gi < NP; gi = gi + 1) begin : g_kid
            wire [LW-1:0] v;
            if (gl == 1) begin : g_from_leaf
                assign v = leaves[gi*LW +: LW];
            end else begin : g_from_node
                assign v = g_lvl[gl-1].g_node[gi].s_reg;
            end
        end
        for (gi = 0; gi < NN; gi = gi + 1) begin : g_node
            localparam B  = ARITY*gi;                           // first child
            localparam NC = (NP - B < ARITY) ? NP - B : ARITY;  // children (1..4)
            // children 1..3 (g_k<i>.k), 0 where absent (each arm of a pair has the block's one
            // name: only one is built; an absent child is a constant, no coverage points)
            if (NC > 1) begin : g_k1
                wire [LW-1:0] k = g_kid[B+1].v;
            end else begin : g_k1
                /* verilator coverage_off */
                wire [LW-1:0] k = {LW{1'b0}};
                /* verilator coverage_on */
            end
            if (NC > 2) begin : g_k2
                wire [LW-1:0] k = g_kid[B+2].v;
            end else begin : g_k2
                /* verilator coverage_off */
                wire [LW-1:0] k = {LW{1'b0}};
                /* verilator coverage_on */
            end
            if (NC > 3) begin : g_k3
                wire [LW-1:0] k = g_kid[B+3].v;
            end else begin : g_k3
                /* verilator coverage_off */
                wire [LW-1:0] k = {LW{1'b0}};
                /* verilator coverage_on */
            end
            wire [LW-1:0] k0 = g_kid[B].v;
            reg  [LW-1:0] s_reg;
            reg  [LW-1:0] s_nx;  // the next sum (a blocking temporary of the process below)
            integer       j;
            // the sum computed and loaded only on an enabled clock that brings the level a valid
            // vector (s_reg holds otherwise); s_nx wholly assigned first, outside the if (a C++
            // local in the Verilator model)
            /* verilator lint_off BLKSEQ */
            always @(posedge clk) begin
                s_nx = {LW{1'b0}};
                if (ce && g_lv.v) begin
                    for (j = 0; j < LANES; j = j + 1)
                        s_nx[j*W +: W] = k0[j*W +: W] + g_k1.k[j*W +: W] + g_k2.k[j*W +: W] + g_k3.k[j*W +: W];
                    s_reg <= s_nx;
                end
            end
            /* verilator lint_on BLKSEQ */
        end
    end

    if (LATENCY == 0) begin : g_sum_leaf
        assign sum_out   = leaves[0 +: LW];
        assign out_valid = in_valid;
    end else begin : g_sum_node
        assign sum_out = g_lvl[LATENCY].g_node[0].s_reg;
        // valid through the tree (reset: no spurious sum after rst)
        always @(posedge clk) begin
            if (rst)
                v_reg <= {(LATENCY+1){1'b0}};
            else if (ce)
                v_reg <= {v_reg[LATENCY-1:0], in_valid};
        end
        assign out_valid = v_reg[LATENCY-1];
    end
endgenerate

endmodule

`default_nettype wire
