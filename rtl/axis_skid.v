// axis_skid: an AXI-Stream skid buffer (register slice) with a registered input ready.
//
// Computes the identity on the stream: every beat (tdata, tlast) accepted on s_axis
// (s_axis_tvalid && s_axis_tready at a clock edge) leaves on m_axis (m_axis_tvalid &&
// m_axis_tready) once, in order, unchanged; model/hw/stream.py axis_skid is the twin.
// The pattern of alexforencich/verilog-axis axis_register, REG_TYPE = 2: an output register
// and a temporary (skid) register. s_axis_tready is a register (ready next clock if the
// output is taken now or the temporary register stays empty), so no combinational path runs
// from m_axis_tready to s_axis_tready; while m_axis_tvalid is high and m_axis_tready low,
// m_axis_tdata and m_axis_tlast hold (the AXI-Stream rule).
//
// Formats: tdata any DATA_W-bit word, tlast one bit, passed through unchanged.
// Latency: one clock (a beat accepted at edge E is on m_axis after E). Throughput: one beat
// per clock while m_axis_tready is held high; a stall of m_axis_tready is absorbed by the
// temporary register (one beat), and s_axis_tready drops one clock later.
// Reset: synchronous, active high: m_axis_tvalid 0, s_axis_tready 0 (1 from the clock after),
// data and last registers 0 (no output is X after reset). The data registers load only
// beats with s_axis_tvalid high (never the X of an empty upstream stage).

`default_nettype none

module axis_skid #(
    parameter DATA_W = 32  // tdata width (>= 1)
) (
    input  wire              clk,
    input  wire              rst,
    // input stream
    input  wire [DATA_W-1:0] s_axis_tdata,
    input  wire              s_axis_tvalid,
    output wire              s_axis_tready,
    input  wire              s_axis_tlast,
    // output stream
    output wire [DATA_W-1:0] m_axis_tdata,
    output wire              m_axis_tvalid,
    input  wire              m_axis_tready,
    output wire              m_axis_tlast
);

reg              s_ready_reg;
reg [DATA_W-1:0] m_data_reg;
reg              m_valid_reg, m_valid_next;
reg              m_last_reg;
reg [DATA_W-1:0] temp_data_reg;
reg              temp_valid_reg, temp_valid_next;
reg              temp_last_reg;
reg              store_in_to_out, store_in_to_temp, store_temp_to_out;

// ready next clock if the output is taken now, or the temporary register stays empty
wire s_ready_early = m_axis_tready || (!temp_valid_reg && (!m_valid_reg || !s_axis_tvalid));

always @* begin
    m_valid_next      = m_valid_reg;
    temp_valid_next   = temp_valid_reg;
    store_in_to_out   = 1'b0;
    store_in_to_temp  = 1'b0;
    store_temp_to_out = 1'b0;
    if (s_ready_reg) begin
        // input is ready
        if (m_axis_tready || !m_valid_reg) begin
            // output is ready or empty: input to output
            m_valid_next    = s_axis_tvalid;
            store_in_to_out = 1'b1;
        end else begin
            // output is stalled: input to the temporary register
            temp_valid_next  = s_axis_tvalid;
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
        s_ready_reg    <= 1'b0;
        m_valid_reg    <= 1'b0;
        m_data_reg     <= {DATA_W{1'b0}};
        m_last_reg     <= 1'b0;
        temp_valid_reg <= 1'b0;
        temp_data_reg  <= {DATA_W{1'b0}};
        temp_last_reg  <= 1'b0;
    end else begin
        s_ready_reg    <= s_ready_early;
        m_valid_reg    <= m_valid_next;
        temp_valid_reg <= temp_valid_next;
        // data registers load only real beats
        if (store_in_to_out && s_axis_tvalid) begin
            m_data_reg <= s_axis_tdata;
            m_last_reg <= s_axis_tlast;
        end else if (store_temp_to_out) begin
            m_data_reg <= temp_data_reg;
            m_last_reg <= temp_last_reg;
        end
        if (store_in_to_temp && s_axis_tvalid) begin
            temp_data_reg <= s_axis_tdata;
            temp_last_reg <= s_axis_tlast;
        end
    end
end

assign s_axis_tready = s_ready_reg;
assign m_axis_tdata  = m_data_reg;
assign m_axis_tvalid = m_valid_reg;
assign m_axis_tlast  = m_last_reg;

`ifdef FORMAL
// ---------------------------------------------------------------------------
// Formal properties (Yosys `read -formal`; make formal, formal/axis_skid.sby). The source obeys
// AXI4-Stream (assumed); the skid buffer is proved to: keep the AXI4-Stream rules on m_axis
// (asserted), hold nothing but what it accepted (f_occ beats: accepted minus delivered, always
// m_axis_tvalid + the temporary register), and deliver an arbitrary accepted beat (f_pick) as it
// was accepted, after exactly the beats that were in the buffer ahead of it (in order, once).
reg              f_past_valid = 1'b0;
reg [1:0]        f_occ;                 // beats accepted and not yet delivered
reg              f_picked, f_done;      // the tracked beat: accepted / delivered
reg [DATA_W-1:0] f_data;                // its word
reg              f_last;
reg              f_ahead;               // beats ahead of it in the buffer (0 or 1)
(* anyseq *) wire f_pick;               // any accepted beat may be the tracked one
wire f_in  = s_axis_tvalid && s_axis_tready;
wire f_out = m_axis_tvalid && m_axis_tready;

always @(posedge clk) begin
    f_past_valid <= 1'b1;
    if (rst) begin
        f_occ    <= 2'd0;
        f_picked <= 1'b0;
        f_done   <= 1'b0;
        f_ahead  <= 1'b0;
    end else begin
        f_occ <= f_occ + {1'b0, f_in} - {1'b0, f_out};
        if (f_in && f_pick && !f_picked) begin
            f_picked <= 1'b1;
            f_data   <= s_axis_tdata;
            f_last   <= s_axis_tlast;
            f_ahead  <= f_occ[0] && !f_out;      // the beat ahead of it stays (f_occ <= 1 here)
        end else if (f_picked && !f_done && f_out) begin
            if (f_ahead)
                f_ahead <= 1'b0;
            else
                f_done <= 1'b1;
        end
    end
end

always @* begin
    // the first clock is a reset (the buffer's state before it is not defined)
    if (!f_past_valid) assume(rst);
end

always @(posedge clk) begin
    if (f_past_valid && !$past(rst)) begin
        // AXI4-Stream source rule on s_axis (assumed): a beat offered and not taken stays, unchanged
        if ($past(s_axis_tvalid && !s_axis_tready))
            assume(s_axis_tvalid && s_axis_tdata == $past(s_axis_tdata) && s_axis_tlast == $past(s_axis_tlast));
        // the same rule on m_axis (asserted): output data, last and valid hold while stalled
        if ($past(m_axis_tvalid && !m_axis_tready))
            assert(m_axis_tvalid && m_axis_tdata == $past(m_axis_tdata) && m_axis_tlast == $past(m_axis_tlast));
    end
    // reset: no output beat, not ready, the clock after a reset
    if (f_past_valid && $past(rst))
        assert(!m_axis_tvalid && !s_axis_tready);
end

always @* begin
    if (f_past_valid) begin
        // nothing appears that was not accepted, nothing accepted is lost or doubled: the beats
        // held are the beats accepted minus those delivered, at most two
        assert(f_occ == {1'b0, m_valid_reg} + {1'b0, temp_valid_reg});
        assert(!temp_valid_reg || m_valid_reg);
        // ready only with room: a beat accepted has a register to go to
        assert(!s_axis_tready || !temp_valid_reg);
        // the tracked beat, accepted and not yet delivered: in the output register with no beat
        // ahead of it, in the temporary register behind the output register's beat
        if (f_picked && !f_done) begin
            if (!f_ahead)
                assert(m_valid_reg && m_data_reg == f_data && m_last_reg == f_last);
            else
                assert(temp_valid_reg && temp_data_reg == f_data && temp_last_reg == f_last && m_valid_reg);
        end
        // it leaves as it came, after exactly the beats ahead of it (in order, once)
        if (f_picked && !f_done && !f_ahead && f_out)
            assert(m_axis_tdata == f_data && m_axis_tlast == f_last);
    end
end
`endif

endmodule

`default_nettype wire
