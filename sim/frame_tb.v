// frame_tb: whole-frame streaming harness for texture_pipeline (simulation only, not RTL).
//
// The top of the simulation. cocotb only drives clk and rst and waits for `done`; every
// per-pixel action happens here, in the simulator:
//   1. $readmemh the parameter writes (+PARAMS=<file>, +NWR=<count>; one write a line,
//      {addr[15:0], data[31:0]}, 12 hex digits, model/hw/regmap.py writes_hex) and the pixel
//      words (+PIXELS=<file>, +NPIX=<count>; model/hw/regmap.py pixels_hex);
//   2. after rst falls, drive the writes through the parameter port, one a clock;
//   3. stream the pixels into s_axis (tlast on the last one) with pseudo-random input gaps
//      (+GAPS=<percent>: the source idles on that share of the clocks where it could offer a
//      new pixel) while the sink captures m_axis into a memory with pseudo-random stalls
//      (+STALLS=<percent>: m_axis_tready low on that share of the clocks); two xorshift32
//      generators seeded by +SEED=<n>;
//   4. check tlast (set on the last pixel and on no other), count outputs beyond NPIX during a
//      DRAIN-clock watch after the last one, count X on the outputs (4-state simulators), and
//      check the AXI-Stream rule on the output: once m_axis_tvalid is high, tvalid, tdata and
//      tlast hold until the sink takes the word (hold_err: clocks where they changed during a
//      stall; +FAULT_HOLD=1 plants a fault in this check's own copy, to test the check);
//      every error also prints a line "frame_tb: ERROR: ..." (the first of each kind) that
//      sim/frame_rtl.py shows in its failure message;
//   5. $writememh the NPIX colours (+OUT=<file>, one 8-hex-digit RGBA8 word a line) and a
//      statistics file (+STATS=<file>, "key value" lines), then raise `done`.
// A rst at any time restarts the whole sequence from step 2 (done falls).
//
// Cycle counts in the statistics: load_cycles (parameter writes), stream_cycles (from the
// first clock a pixel is offered to the clock the last colour is taken), total_cycles (rst
// release to done).

`default_nettype none

module frame_tb #(
    parameter MAX_PIX = 262144,  // pixel and colour memory depth (pixels per run)
    parameter MAX_WR  = 16384,   // parameter-write memory depth
    parameter DRAIN   = 256,     // clocks watched for spurious outputs after the last colour
    parameter PIX_W   = 1        // the configuration's pixel word (model/hw/regmap.py pix_width)
) (
    // public for Verilator (built without --public-flat-rw): cocotb drives and watches them
    input  wire clk  /* verilator public_flat_rw */,
    input  wire rst  /* verilator public_flat_rw */,
    output reg  done /* verilator public_flat_rw */
);

// ---------------------------------------------------------------------------
// Stimulus and result memories, plusargs

reg [PIX_W-1:0] pix_mem [0:MAX_PIX-1];
reg [47:0]      wr_mem  [0:MAX_WR-1];
reg [31:0]      out_mem [0:MAX_PIX-1];

reg [8*1024-1:0] params_file, pixels_file, out_file, stats_file;
integer npix, nwr, gaps, stalls, seed, fault_hold;

initial begin
    done = 1'b0;
    npix = 0; nwr = 0; gaps = 0; stalls = 0; seed = 1; fault_hold = 0;
    if (!$value$plusargs("PARAMS=%s", params_file)) params_file = "params.hex";
    if (!$value$plusargs("PIXELS=%s", pixels_file)) pixels_file = "pixels.hex";
    if (!$value$plusargs("OUT=%s", out_file))       out_file    = "out.hex";
    if (!$value$plusargs("STATS=%s", stats_file))   stats_file  = "stats.txt";
    if (!$value$plusargs("NPIX=%d", npix))   npix   = 0;
    if (!$value$plusargs("NWR=%d", nwr))     nwr    = 0;
    if (!$value$plusargs("GAPS=%d", gaps))   gaps   = 0;
    if (!$value$plusargs("STALLS=%d", stalls)) stalls = 0;
    if (!$value$plusargs("SEED=%d", seed))   seed   = 1;
    if (!$value$plusargs("FAULT_HOLD=%d", fault_hold)) fault_hold = 0;
    if (npix < 1 || npix > MAX_PIX) begin
        $display("frame_tb: ERROR: +NPIX=%0d outside 1..%0d", npix, MAX_PIX);
        $finish;
    end
    if (nwr < 0 || nwr > MAX_WR) begin
        $display("frame_tb: ERROR: +NWR=%0d outside 0..%0d", nwr, MAX_WR);
        $finish;
    end
    if (nwr > 0) $readmemh(params_file, wr_mem, 0, nwr - 1);
    $readmemh(pixels_file, pix_mem, 0, npix - 1);
end

// ---------------------------------------------------------------------------
// Device under test

reg              cfg_wr_en_reg;
reg  [15:0]      cfg_wr_addr_reg;
reg  [31:0]      cfg_wr_data_reg;
reg  [PIX_W-1:0] s_tdata_reg;
reg              s_tvalid_reg;
reg              s_tlast_reg;
// read by the cocotb test (no X after reset): public for Verilator, which is built without
// --public-flat-rw (sim/frame_rtl.py; that flag makes the C++ several times larger)
wire             s_tready /* verilator public_flat_rw */;
wire [31:0]      m_tdata  /* verilator public_flat_rw */;
wire             m_tvalid /* verilator public_flat_rw */;
wire             m_tlast  /* verilator public_flat_rw */;
reg              m_tready_reg;

texture_unit u_pipe (  // texture_pipeline with the configuration's parameters (hdlbuild)
    .clk(clk),
    .rst(rst),
    .cfg_wr_en(cfg_wr_en_reg),
    .cfg_wr_addr(cfg_wr_addr_reg),
    .cfg_wr_data(cfg_wr_data_reg),
    .s_axis_tdata(s_tdata_reg),
    .s_axis_tvalid(s_tvalid_reg),
    .s_axis_tready(s_tready),
    .s_axis_tlast(s_tlast_reg),
    .m_axis_tdata(m_tdata),
    .m_axis_tvalid(m_tvalid),
    .m_axis_tready(m_tready_reg),
    .m_axis_tlast(m_tlast)
);

// ---------------------------------------------------------------------------
// Pseudo-random gaps and stalls: xorshift32, one step a clock

reg [31:0] gap_rng_reg, stall_rng_reg;

function [31:0] xorshift32;
    input [31:0] x;
    reg   [31:0] y;
    begin
        y = x ^ (x << 13);
        y = y ^ (y >> 17);
        xorshift32 = y ^ (y << 5);
    end
endfunction

wire gap_now   = (gap_rng_reg % 100) < gaps;
wire stall_now = (stall_rng_reg % 100) < stalls;

// ---------------------------------------------------------------------------
// Sequencer

localparam [1:0] ST_LOAD = 2'd0, ST_STREAM = 2'd1, ST_DRAIN = 2'd2, ST_DONE = 2'd3;

reg [1:0] state_reg /* verilator public_flat_rw */;
integer   out_idx   /* verilator public_flat_rw */;
integer   wr_idx, in_idx, drain_cnt;
integer   load_cycles, stream_cycles, total_cycles;
integer   tlast_err, extra_out, x_err, in_count, hold_err;
// AXI-Stream hold check: the output word seen on a clock where it was offered and not taken
reg         hold_pending_reg;
reg  [31:0] hold_data_reg;
reg         hold_last_reg;
integer   fd;
reg       streaming_reg;  // a pixel has been offered: stream_cycles counts

always @(posedge clk) begin
    if (rst) begin
        state_reg       <= ST_LOAD;
        done            <= 1'b0;
        cfg_wr_en_reg   <= 1'b0;
        cfg_wr_addr_reg <= 16'd0;
        cfg_wr_data_reg <= 32'd0;
        s_tdata_reg     <= {PIX_W{1'b0}};
        s_tvalid_reg    <= 1'b0;
        s_tlast_reg     <= 1'b0;
        m_tready_reg    <= 1'b0;
        streaming_reg   <= 1'b0;
        gap_rng_reg     <= 32'h9e3779b9 ^ seed;
        stall_rng_reg   <= 32'h7f4a7c15 ^ (seed * 3 + 1);
        wr_idx <= 0; in_idx <= 0; out_idx <= 0; drain_cnt <= 0; in_count <= 0;
        load_cycles <= 0; stream_cycles <= 0; total_cycles <= 0;
        tlast_err <= 0; extra_out <= 0; x_err <= 0; hold_err <= 0;
        hold_pending_reg <= 1'b0;
        hold_data_reg    <= 32'd0;
        hold_last_reg    <= 1'b0;
    end else begin
        gap_rng_reg   <= xorshift32(gap_rng_reg);
        stall_rng_reg <= xorshift32(stall_rng_reg);
        if (state_reg != ST_DONE)
            total_cycles <= total_cycles + 1;

        // outputs of the DUT must never be X (4-state simulators; always 0 in Verilator)
        if ((^{s_tready, m_tvalid}) === 1'bx || (m_tvalid && (^{m_tdata, m_tlast}) === 1'bx))
            x_err <= x_err + 1;

        // AXI-Stream: a word offered and not taken stays, unchanged, until it is taken
        if (hold_pending_reg && (m_tvalid !== 1'b1 || m_tdata !== hold_data_reg || m_tlast !== hold_last_reg)) begin
            if (hold_err == 0)
                $display("frame_tb: ERROR: output %0d changed while the sink stalled: tvalid %b, tdata %h -> %h, tlast %b -> %b",
                         out_idx, m_tvalid, hold_data_reg, m_tdata, hold_last_reg, m_tlast);
            hold_err <= hold_err + 1;
        end
        hold_pending_reg <= m_tvalid && !m_tready_reg;
        hold_data_reg    <= m_tdata ^ {31'd0, fault_hold[0]};
        hold_last_reg    <= m_tlast;

        // parameter writes
        cfg_wr_en_reg <= 1'b0;
        if (state_reg == ST_LOAD) begin
            load_cycles <= load_cycles + 1;
            if (wr_idx < nwr) begin
                cfg_wr_en_reg   <= 1'b1;
                cfg_wr_addr_reg <= wr_mem[wr_idx][47:32];
                cfg_wr_data_reg <= wr_mem[wr_idx][31:0];
                wr_idx          <= wr_idx + 1;
            end else begin
                state_reg <= ST_STREAM;
            end
        end

        // pixel source (valid held until taken: AXI-Stream)
        if (state_reg == ST_STREAM || state_reg == ST_DRAIN) begin
            if (s_tvalid_reg && s_tready)
                in_count <= in_count + 1;
            if (!s_tvalid_reg || s_tready) begin
                if (in_idx < npix && !gap_now) begin
                    s_tvalid_reg  <= 1'b1;
                    s_tdata_reg   <= pix_mem[in_idx];
                    s_tlast_reg   <= (in_idx == npix - 1);
                    in_idx        <= in_idx + 1;
                    streaming_reg <= 1'b1;
                end else begin
                    s_tvalid_reg <= 1'b0;
                    s_tlast_reg  <= 1'b0;
                end
            end
        end

        // colour sink
        if (state_reg == ST_STREAM) begin
            if (streaming_reg)
                stream_cycles <= stream_cycles + 1;
            m_tready_reg <= !stall_now;
            if (m_tvalid && m_tready_reg) begin
                out_mem[out_idx] <= m_tdata;
                if (m_tlast != (out_idx == npix - 1)) begin
                    if (tlast_err == 0)
                        $display("frame_tb: ERROR: tlast %b on output %0d of %0d", m_tlast, out_idx, npix);
                    tlast_err <= tlast_err + 1;
                end
                out_idx <= out_idx + 1;
                if (out_idx == npix - 1) begin
                    state_reg    <= ST_DRAIN;
                    m_tready_reg <= 1'b1;
                end
            end
        end else if (state_reg == ST_DRAIN) begin
            m_tready_reg <= 1'b1;
            if (m_tvalid && m_tready_reg) begin
                if (extra_out == 0)
                    $display("frame_tb: ERROR: an output after the last of %0d pixels", npix);
                extra_out <= extra_out + 1;
            end
            drain_cnt <= drain_cnt + 1;
            if (drain_cnt == DRAIN - 1)
                state_reg <= ST_DONE;
        end else if (state_reg == ST_DONE && !done) begin
            $writememh(out_file, out_mem, 0, npix - 1);
            /* verilator lint_off BLKSEQ */  // a file handle, used at once (simulation only)
            fd = $fopen(stats_file, "w");
            /* verilator lint_on BLKSEQ */
            $fdisplay(fd, "npix %0d", npix);
            $fdisplay(fd, "nwr %0d", nwr);
            $fdisplay(fd, "in_count %0d", in_count);
            $fdisplay(fd, "out_count %0d", out_idx);
            $fdisplay(fd, "load_cycles %0d", load_cycles);
            $fdisplay(fd, "stream_cycles %0d", stream_cycles);
            $fdisplay(fd, "total_cycles %0d", total_cycles);
            $fdisplay(fd, "tlast_err %0d", tlast_err);
            $fdisplay(fd, "extra_out %0d", extra_out);
            $fdisplay(fd, "x_err %0d", x_err);
            $fdisplay(fd, "hold_err %0d", hold_err);
            $fdisplay(fd, "gaps %0d", gaps);
            $fdisplay(fd, "stalls %0d", stalls);
            $fclose(fd);
            done <= 1'b1;
        end
    end
end

endmodule

`default_nettype wire
