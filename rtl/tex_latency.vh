// Latencies (register stages, counted in enabled clock edges) of the pipeline blocks.
// Each block's own header restates its value; the block is built to exactly this depth,
// its testbench checks it, and texture_pipeline aligns its delay lines with it.
`ifndef TEX_LATENCY_VH
`define TEX_LATENCY_VH
`define LAT_QUADRIC_MAC  4
`define LAT_NOISE_TERM   8
`define LAT_FILTER_WIDTH 8
`define LAT_COLOUR_MAP   14
`define LAT_FC_WEIGHT    8
`define LAT_FC_SCALE     1
`endif
