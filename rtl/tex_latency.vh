// Latencies (register stages, counted in enabled clock edges) of the pipeline blocks.
// Each block's own header restates its value; the block is built to exactly this depth,
// its testbench checks it, and texture_pipeline aligns its delay lines with it.
// LAT_<BLOCK>_FPGA: the same block with its FPGA_REGS parameter set (the configuration key
// features.fpga_regs): the extra register stages that let an FPGA build close its clock
// (docs/fpga.md); each block's header says where they are. model/hw/config.py latency() reads
// this file (the one copy of these numbers).
`ifndef TEX_LATENCY_VH
`define TEX_LATENCY_VH
`define LAT_QUADRIC_MAC       4
`define LAT_QUADRIC_MAC_FPGA  6
// quadric_mac with quadric_clocks = 6 (diagonal, FPGA_REGS = 0): qmac_diag_serial's six clocks
`define LAT_QUADRIC_MAC_SERIAL 8
// quadric_mac's latency for its parameters (FPGA_REGS, DIAG, CLOCKS): the one rule, used by
// quadric_mac, texture_sum and texture_pipeline (model/hw/config.py latency("quadric_mac", cfg))
`define LAT_QM(fpga, diag, clocks) (((fpga) != 0) ? `LAT_QUADRIC_MAC_FPGA : (((diag) != 0 && (clocks) == 6) ? `LAT_QUADRIC_MAC_SERIAL : `LAT_QUADRIC_MAC))
// quadric_mac's datapaths (stages 1-3; quadric_mac adds its output stage, checked there)
`define LAT_QMAC_FULL         3
`define LAT_QMAC_FULL_FPGA    5
`define LAT_QMAC_DIAG         3
`define LAT_QMAC_DIAG_FOLD    3
`define LAT_QMAC_DIAG_SERIAL  7
`define LAT_QMAC_DIAG_PIPE    5
`define LAT_NOISE_TERM        8
`define LAT_NOISE_TERM_FPGA   16
`define LAT_NOISE_XFORM       2
`define LAT_NOISE_GRAD        5
`define LAT_NOISE_GRAD_FPGA   11
`define LAT_NOISE_FOLD        1
`define LAT_NOISE_FOLD_FPGA   2
`define LAT_FILTER_WIDTH      8
`define LAT_FILTER_WIDTH_FPGA 12
`define LAT_COLOUR_MAP        14
`define LAT_COLOUR_MAP_FPGA   19
`define LAT_CMAP_SAT          13
`define LAT_CMAP_SAT_FPGA     17
// cmap_sat with cmap_clocks = 4 (a channel a clock, FPGA_REGS = 0): the later three channels
// and the assembly register after `LAT_CMAP_SAT; colour_map adds its stage 1
`define LAT_CMAP_SAT_SERIAL   17
`define LAT_COLOUR_MAP_SERIAL 18
// cmap_sat's and colour_map's latencies for their parameters (FPGA_REGS, CLOCKS): the one rule,
// used by cmap_sat, colour_map and texture_pipeline (model/hw/config.py latency(module, cfg))
`define LAT_CMS(fpga, clocks) (((fpga) != 0) ? `LAT_CMAP_SAT_FPGA : (((clocks) == 4) ? `LAT_CMAP_SAT_SERIAL : `LAT_CMAP_SAT))
`define LAT_CM(fpga, clocks) (((fpga) != 0) ? `LAT_COLOUR_MAP_FPGA : (((clocks) == 4) ? `LAT_COLOUR_MAP_SERIAL : `LAT_COLOUR_MAP))
`define LAT_CMAP_SAT2         13
`define LAT_CMAP_SAT2_FPGA    17
`define LAT_CMAP_DIVIDE       9
`define LAT_CMAP_DIVIDE_FPGA  10
`define LAT_CMAP_MIP          13
`define LAT_CMAP_MIP_FPGA     17
`define LAT_CMAP_POINT        13
`define LAT_CMAP_POINT_FPGA   17
`define LAT_FC_WEIGHT         8
`define LAT_FC_SCALE          1
// cm_align: sat_fc's max(w, wv) register stage
`define LAT_FC_WMAX           1
// sample_average: the average of a pixel's sub-pixel samples (features.samples > 1)
`define LAT_SAMPLE_AVERAGE    1
// sum_tree: an adder tree of this arity, its latency the levels down to one node
// (tw_tree_levels in rtl/tex_widths.vh, model/hw/config.py sum_tree_levels)
`define SUM_TREE_ARITY        4
`endif
