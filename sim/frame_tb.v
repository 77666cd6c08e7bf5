// frame_tb: whole-frame streaming harness for texture_pipeline (simulation only, not RTL).
//
// The top of the simulation. cocotb only drives clk and rst and waits for `done`; every
// per-pixel action happens here, in the simulator. A run is a list of passes (segments), each
// one texture's parameter writes and then its pixel stream, all loaded up front:
//   1. $readmemh the segment list (+SEGS=<file>, +NSEG=<count>; one pass a line,
//      {nwr[31:0], npix[31:0]}, 16 hex digits: the pass's parameter writes and pixels, npix >= 1),
//      the parameter writes of every pass concatenated (+PARAMS=<file>; one write a line,
//      {addr[15:0], data[31:0]}, 12 hex digits, model/hw/regmap.py writes_hex) and the pixel
//      words of every pass concatenated (+PIXELS=<file>; model/hw/regmap.py pixels_hex).
//      Without +NSEG the run is one pass of +NWR=<count> writes and +NPIX=<count> pixels;
//   2. after rst falls, for each pass in turn: drive its writes through the parameter port, one
//      a clock (no reset between passes: every pass writes every parameter register);
//   3. stream its pixels into s_axis (tlast on its last one) with pseudo-random input gaps
//      (+GAPS=<percent>: the source idles on that share of the clocks where it could offer a
//      new pixel) while the sink captures m_axis into a memory with pseudo-random stalls
//      (+STALLS=<percent>: m_axis_tready low on that share of the clocks); two xorshift32
//      generators seeded by +SEED=<n> once a run (they run on across the passes);
//   4. check tlast (set on the last pixel of each pass and on no other), count outputs beyond
//      the pass's last during a DRAIN-clock watch after it and outputs while a pass loads, count
//      X on the outputs (4-state simulators), and check the AXI-Stream rule on the output: once
//      m_axis_tvalid is high, tvalid, tdata and tlast hold until the sink takes the word
//      (hold_err: clocks where they changed during a stall; +FAULT_HOLD=1 plants a fault in
//      this check's own copy, to test the check); every error also prints a line
//      "frame_tb: ERROR: ..." (the first of each kind) that sim/frame_rtl.py shows in its
//      failure message; then the next pass from step 2;
//   5. after the last pass, $writememh the colours of every pass, concatenated (+OUT=<file>,
//      one 8-hex-digit RGBA8 word a line), the cycles of each pass (+SEGSTATS=<file>, if given;
//      one pass a line, {load_cycles[31:0], stream_cycles[31:0]}) and a statistics file
//      (+STATS=<file>, "key value" lines, totals over the passes), then raise `done`.
// A rst at any time restarts the whole sequence from the first pass's step 2 (done falls).
// +HOSTMEM=1: the simulator's C++ main (Verilator, sim/frame_main.cpp) fills the pixel memory
// and reads the colour memory itself, in binary; the harness then neither $readmemh's +PIXELS
// nor $writememh's +OUT (a 512x512 frame's text files cost more than its simulation).
//
// Cycle counts in the statistics: load_cycles (parameter writes), stream_cycles (from the
// first clock a pixel of a pass is offered to the clock its last colour is taken, summed over
// the passes), total_cycles (rst release to done: also the DRAIN watches).

`default_nettype none

module frame_tb #(
    parameter MAX_PIX = 262144,  // pixel and colour memory depth (pixels per run, all passes)
    parameter MAX_WR  = 16384,   // parameter-write memory depth (writes per run, all passes)
    parameter MAX_SEG = 1024,    // segment memory depth (passes per run)
    parameter DRAIN   = 256,     // clocks watched for spurious outputs after a pass's last colour
    parameter PIX_W   = 1        // the configuration's pixel word (model/hw/regmap.py pix_width)
) (
    // public for Verilator (built without --public-flat-rw): cocotb drives and watches them
    input  wire clk  /* verilator public_flat_rw */,
    input  wire rst  /* verilator public_flat_rw */,
    output reg  done /* verilator public_flat_rw */
);

// ---------------------------------------------------------------------------
// Stimulus and result memories, plusargs

// pix_mem, out_mem: public for Verilator's C++ main (+HOSTMEM=1)
reg [PIX_W-1:0] pix_mem      [0:MAX_PIX-1] /* verilator public_flat_rw */;
reg [47:0]      wr_mem       [0:MAX_WR-1];
reg [31:0]      out_mem      [0:MAX_PIX-1] /* verilator public_flat_rw */;
reg [63:0]      seg_mem      [0:MAX_SEG-1];  // {nwr, npix} of each pass
reg [63:0]      seg_stat_mem [0:MAX_SEG-1];  // {load_cycles, stream_cycles} of each pass

reg [8*1024-1:0] params_file, pixels_file, out_file, stats_file, segs_file, segstats_file;
integer npix, nwr, nseg, gaps, stalls, seed, fault_hold, have_segstats, seg_bad, hostmem, i;

initial begin
    done = 1'b0;
    npix = 0; nwr = 0; nseg = 0; gaps = 0; stalls = 0; seed = 1; fault_hold = 0; seg_bad = 0;
    if (!$value$plusargs("PARAMS=%s", params_file)) params_file = "params.hex";
    if (!$value$plusargs("PIXELS=%s", pixels_file)) pixels_file = "pixels.hex";
    if (!$value$plusargs("OUT=%s", out_file))       out_file    = "out.hex";
    if (!$value$plusargs("STATS=%s", stats_file))   stats_file  = "stats.txt";
    if (!$value$plusargs("SEGS=%s", segs_file))     segs_file   = "segs.hex";
    have_segstats = $value$plusargs("SEGSTATS=%s", segstats_file);
    if (!$value$plusargs("GAPS=%d", gaps))   gaps   = 0;
    if (!$value$plusargs("STALLS=%d", stalls)) stalls = 0;
    if (!$value$plusargs("SEED=%d", seed))   seed   = 1;
    if (!$value$plusargs("FAULT_HOLD=%d", fault_hold)) fault_hold = 0;
    if (!$value$plusargs("HOSTMEM=%d", hostmem)) hostmem = 0;
    if ($value$plusargs("NSEG=%d", nseg)) begin
        if (nseg < 1 || nseg > MAX_SEG) begin
            $display("frame_tb: ERROR: +NSEG=%0d outside 1..%0d", nseg, MAX_SEG);
            $finish;
        end
        $readmemh(segs_file, seg_mem, 0, nseg - 1);
    end else begin  // one pass: +NWR writes, +NPIX pixels
        if (!$value$plusargs("NPIX=%d", npix)) npix = 0;
        if (!$value$plusargs("NWR=%d", nwr))   nwr  = 0;
        nseg = 1;
        seg_mem[0] = {nwr[31:0], npix[31:0]};
    end
    npix = 0; nwr = 0;
    for (i = 0; i < nseg; i = i + 1) begin
        if (seg_mem[i][31:0] < 1 || seg_mem[i][31:0] > MAX_PIX || seg_mem[i][63:32] > MAX_WR) begin
            if (seg_bad == 0)
                $display("frame_tb: ERROR: pass %0d: %0d writes, %0d pixels (1..%0d pixels, at most %0d writes)",
                         i, seg_mem[i][63:32], seg_mem[i][31:0], MAX_PIX, MAX_WR);
            seg_bad = seg_bad + 1;
        end
        npix = npix + seg_mem[i][31:0];
        nwr  = nwr + seg_mem[i][63:32];
    end
    if (seg_bad != 0) $finish;
    if (npix < 1 || npix > MAX_PIX) begin
        $display("frame_tb: ERROR: %0d pixels in %0d passes: a run takes 1..%0d", npix, nseg, MAX_PIX);
        $finish;
    end
    if (nwr < 0 || nwr > MAX_WR) begin
        $display("frame_tb: ERROR: %0d parameter writes in %0d passes: a run takes at most %0d", nwr, nseg, MAX_WR);
        $finish;
    end
    if (nwr > 0) $readmemh(params_file, wr_mem, 0, nwr - 1);
    if (hostmem == 0) $readmemh(pixels_file, pix_mem, 0, npix - 1);
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
// Sequencer: pass by pass, load the writes, stream the pixels, drain; then write the results

localparam [1:0] ST_LOAD = 2'd0, ST_STREAM = 2'd1, ST_DRAIN = 2'd2, ST_DONE = 2'd3;

reg [1:0] state_reg /* verilator public_flat_rw */;
integer   out_idx   /* verilator public_flat_rw */;  // colours taken (all passes)
integer   wr_idx, in_idx, drain_cnt;                  // writes driven, pixels offered (all passes)
integer   seg_idx, wr_end, pix_end;                   // the current pass; its writes end, its pixels end
integer   seg_load, seg_stream;                       // the current pass's load and stream clocks
integer   load_cycles, stream_cycles, total_cycles;
integer   tlast_err, extra_out, x_err, in_count, hold_err;
// AXI-Stream hold check: the output word seen on a clock where it was offered and not taken
reg         hold_pending_reg;
reg  [31:0] hold_data_reg;
reg         hold_last_reg;
integer   fd;
reg       streaming_reg;  // a pixel of the current pass has been offered: stream_cycles counts
wire [31:0] seg_stream_taken = seg_stream + 1;  // the pass's stream clocks, the clock of its last colour included
wire [31:0] seg_load_now = seg_load;
wire        last_pass = (seg_idx == nseg - 1);
wire [63:0] next_seg = seg_mem[last_pass ? seg_idx : seg_idx + 1];

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
        seg_idx <= 0; wr_end <= seg_mem[0][63:32]; pix_end <= seg_mem[0][31:0];
        seg_load <= 0; seg_stream <= 0;
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
        hold_data_reg    <= m_tdata ^ {31'd0, fault_hold != 0};
        hold_last_reg    <= m_tlast;

        // parameter writes of the current pass
        cfg_wr_en_reg <= 1'b0;
        if (state_reg == ST_LOAD) begin
            load_cycles <= load_cycles + 1;
            seg_load    <= seg_load + 1;
            if (wr_idx < wr_end) begin
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
                if (in_idx < pix_end && !gap_now) begin
                    s_tvalid_reg  <= 1'b1;
                    s_tdata_reg   <= pix_mem[in_idx];
                    s_tlast_reg   <= (in_idx == pix_end - 1);
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
            if (streaming_reg) begin
                stream_cycles <= stream_cycles + 1;
                seg_stream    <= seg_stream + 1;
            end
            m_tready_reg <= !stall_now;
            if (m_tvalid && m_tready_reg) begin
                out_mem[out_idx] <= m_tdata;
                if (m_tlast != (out_idx == pix_end - 1)) begin
                    if (tlast_err == 0)
                        $display("frame_tb: ERROR: tlast %b on output %0d of %0d (pass %0d)", m_tlast, out_idx, npix, seg_idx);
                    tlast_err <= tlast_err + 1;
                end
                out_idx <= out_idx + 1;
                if (out_idx == pix_end - 1) begin
                    state_reg    <= ST_DRAIN;
                    m_tready_reg <= 1'b1;
                    seg_stat_mem[seg_idx] <= {seg_load_now, seg_stream_taken};
                end
            end
        end else if (state_reg == ST_DRAIN || state_reg == ST_LOAD) begin
            // no output between a pass's last colour and the next pass's first pixel
            if (m_tvalid && m_tready_reg) begin
                if (extra_out == 0)
                    $display("frame_tb: ERROR: an output after the last of pass %0d's pixels (%0d of %0d taken)",
                             seg_idx - (state_reg == ST_LOAD ? 1 : 0), out_idx, npix);
                extra_out <= extra_out + 1;
            end
            if (state_reg == ST_DRAIN) begin
                m_tready_reg <= 1'b1;
                drain_cnt    <= drain_cnt + 1;
                if (drain_cnt == DRAIN - 1) begin
                    drain_cnt <= 0;
                    if (last_pass) begin
                        state_reg <= ST_DONE;
                    end else begin  // the next pass: its writes, then its pixels
                        state_reg     <= ST_LOAD;
                        seg_idx       <= seg_idx + 1;
                        wr_end        <= wr_end + next_seg[63:32];
                        pix_end       <= pix_end + next_seg[31:0];
                        seg_load      <= 0;
                        seg_stream    <= 0;
                        streaming_reg <= 1'b0;
                    end
                end
            end
        end else if (state_reg == ST_DONE && !done) begin
            if (hostmem == 0) $writememh(out_file, out_mem, 0, npix - 1);
            if (have_segstats != 0)
                $writememh(segstats_file, seg_stat_mem, 0, nseg - 1);
            /* verilator lint_off BLKSEQ */  // a file handle, used at once (simulation only)
            fd = $fopen(stats_file, "w");
            /* verilator lint_on BLKSEQ */
            $fdisplay(fd, "npix %0d", npix);
            $fdisplay(fd, "nwr %0d", nwr);
            $fdisplay(fd, "nseg %0d", nseg);
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
