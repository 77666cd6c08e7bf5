// axis_skid_loop: axis_skid with its input ready fed back into its output ready. A path from
// m_axis_tready to s_axis_tready through logic without a register would close a logic loop
// here, which `check -assert` (formal/run.py's axis_skid_ready task) rejects: the header's
// "no combinational path from m_axis_tready to s_axis_tready", checked on the netlist.

`default_nettype none

module axis_skid_loop #(
    parameter DATA_W = 32  // axis_skid's tdata width
) (
    input  wire              clk,
    input  wire              rst,
    input  wire [DATA_W-1:0] s_axis_tdata,
    input  wire              s_axis_tvalid,
    input  wire              s_axis_tlast,
    input  wire              ready_in,     // the downstream ready, combined with the loop
    output wire [DATA_W-1:0] m_axis_tdata,
    output wire              m_axis_tvalid,
    output wire              m_axis_tlast
);

wire s_ready;
axis_skid #(.DATA_W(DATA_W)) u_skid (
    .clk(clk), .rst(rst),
    .s_axis_tdata(s_axis_tdata), .s_axis_tvalid(s_axis_tvalid), .s_axis_tready(s_ready),
    .s_axis_tlast(s_axis_tlast),
    .m_axis_tdata(m_axis_tdata), .m_axis_tvalid(m_axis_tvalid), .m_axis_tready(s_ready ^ ready_in),
    .m_axis_tlast(m_axis_tlast)
);

endmodule

`default_nettype wire
