// cm_align: f and w meet before colour_map (texture_pipeline's last alignment).
//
// f (the adder tree's sum) and w (filter_width's) reach this block at different clocks; the
// earlier of the two waits in a delay line for the later. With sat_fc (WV_MAX 1) w is first
// widened to max(w, wv), wv the faded terms' spread (fc_weight's, aligned to w by the
// caller), in one register stage (`LAT_FC_WMAX); with sat2_fc (WV_MAX 1, NW 2) the larger of
// the trapezoid's two widths {b, a} is: a >= b: {b, max(a, wv)}, else {max(b, wv), a}. While f waits it is carried in FC_W <= F_W
// bits: colour_map reads only f mod 1 in mod mode (mode 0, the low F_FRAC bits), and in
// clamp mode (mode 1) compares f with thresholds inside [-2^GUARD, 2^F_FRAC + 2^GUARD],
// GUARD = W_CAP_LOG2 + F_FRAC - 1 (sat2, NW = 2: W_CAP_LOG2 + F_FRAC), so saturating f to +-2^(GUARD+1) there (and wrapping it
// to FC_W bits in mod mode) changes no colour; f_out is that word sign-extended to F_W.
// model/hw/golden.py cm_align is the twin.
//
// Formats: f_in, f_out s{F_W}.{F_FRAC}; w_in, wv_in, w_out u{W_W}.{F_FRAC}, W_W =
// W_CAP_LOG2 + F_FRAC + 1 (NW = 2, filter sat2 or sat2_fc: w_in, w_out {b, a}, two such
// words, carried together); mode static during a pass (it is read as f enters).
// Latency: LATENCY_F register stages from f_in to the outputs, LATENCY_W from w_in (the
// caller's T_CM - T_F and T_CM - T_FW); LATENCY_W = (WV_MAX ? `LAT_FC_WMAX : 0) + the
// wait of w, and one of the two waits is 0 (elaboration fails otherwise). out_valid is the
// valid bit of the later path (f_valid or w_valid). Throughput: one pixel per enabled clock.
// Reset: synchronous, active high, clears the valid bits (data registers have no reset).

`default_nettype none

`include "tex_latency.vh"

module cm_align #(
    parameter F_W        = 40,  // f word (the exact sum's width, model/hw/config.py f_w)
    parameter F_FRAC     = 16,  // f fraction bits (1.0 = the whole table)
    parameter W_CAP_LOG2 = 16,  // w saturates at 2^W_CAP_LOG2 entries
    parameter WV_MAX     = 0,   // 1 (filters sat_fc, sat2_fc): w_out = max(w, wv) (NW 2: the larger word's)
    parameter NW         = 1,   // w words: 1, or 2 (filters sat2, sat2_fc: {b, a}; its clamp guard W)
    parameter LATENCY_F  = 0,   // stages from f_in to the outputs (f's wait)
    parameter LATENCY_W  = 0    // stages from w_in to the outputs (the max register and w's wait)
) (
    input  wire                              clk,
    input  wire                              rst,
    input  wire                              ce,
    input  wire                              mode,     // 0 mod (wrap), 1 clamp
    /* verilator lint_off UNUSEDSIGNAL */  // the earlier path's valid bit is not needed
    input  wire                              f_valid,
    input  wire                              w_valid,
    /* verilator lint_on UNUSEDSIGNAL */
    input  wire [F_W-1:0]                    f_in,
    input  wire [NW*(W_CAP_LOG2+F_FRAC+1)-1:0] w_in,
    /* verilator lint_off UNUSEDSIGNAL */  // WV_MAX 0: not read
    input  wire [W_CAP_LOG2+F_FRAC:0]        wv_in,
    /* verilator lint_on UNUSEDSIGNAL */
    output wire                              out_valid,
    output wire [F_W-1:0]                    f_out,
    output wire [NW*(W_CAP_LOG2+F_FRAC+1)-1:0] w_out
);

localparam W_W   = W_CAP_LOG2 + F_FRAC + 1;                                 // filter width word
localparam LAT_M = WV_MAX ? `LAT_FC_WMAX : 0;                               // the max(w, wv) stage
localparam DLY_F = LATENCY_F;                                               // f's wait
localparam DLY_W = LATENCY_W - LAT_M;                                       // w's wait
localparam GUARD = W_CAP_LOG2 + F_FRAC - 1 + (NW - 1);                      // clamp-mode guard
localparam FC_W  = (DLY_F > 0 && GUARD + 3 < F_W) ? GUARD + 3 : F_W;        // f while it waits

// elaboration fails (unknown module) on a latency this block cannot have
generate
    if (LAT_M != 1 && WV_MAX != 0 || DLY_F < 0 || DLY_W < 0 || (DLY_F > 0 && DLY_W > 0)
        || (NW != 1 && NW != 2)) begin : g_bad_latency
        cm_align_latency_must_be_one_wait_and_the_max_stage u_error ();
    end
endgenerate

// f saturated (clamp mode) or wrapped (mod mode) to FC_W bits
wire [FC_W-1:0] f_carry;
generate
    if (FC_W < F_W) begin : g_fsat
        wire signed [F_W-1:0] f_s   = f_in;
        // (constants: no coverage points)
        /* verilator coverage_off */
        wire signed [F_W-1:0] f_top = {{(F_W-GUARD-2){1'b0}}, 1'b1, {(GUARD+1){1'b0}}};  //  2^(GUARD+1)
        wire signed [F_W-1:0] f_bot = -f_top;                                              // -2^(GUARD+1)
        /* verilator coverage_on */
        // above FC_W: sign copies of a value that fits FC_W (not read)
        /* verilator lint_off UNUSEDSIGNAL */
        wire [F_W-1:0] f_clip = (f_s > f_top) ? f_top : (f_s < f_bot) ? f_bot : f_in;
        /* verilator lint_on UNUSEDSIGNAL */
        assign f_carry = mode ? f_clip[FC_W-1:0] : f_in[FC_W-1:0];
    end else begin : g_fwhole
        /* verilator lint_off UNUSEDSIGNAL */  // mode: f is carried whole
        wire unused_mode = mode;
        /* verilator lint_on UNUSEDSIGNAL */
        assign f_carry = f_in;
    end
endgenerate

// sat_fc: w = max(w, wv); sat2_fc: the larger of {b, a} max'd with wv; one register
wire [NW*W_W-1:0] wd_w;
wire           wd_valid;
generate
    if (WV_MAX) begin : g_wmax
        reg [NW*W_W-1:0] w_reg;
        reg              v_reg;
        wire [NW*W_W-1:0] w_max;
        if (NW == 2) begin : g_pair
            wire [W_W-1:0] wa = w_in[0 +: W_W];
            wire [W_W-1:0] wb = w_in[W_W +: W_W];
            wire           a_ge = (wa >= wb);
            wire [W_W-1:0] wl = a_ge ? wa : wb;               // the larger of the two
            wire [W_W-1:0] wm = (wv_in > wl) ? wv_in : wl;    // ... widened to wv
            assign w_max = a_ge ? {wb, wm} : {wm, wa};
        end else begin : g_one
            assign w_max = (wv_in > w_in) ? wv_in : w_in;
        end
        always @(posedge clk) begin
            if (rst) begin
                v_reg <= 1'b0;
            end else if (ce) begin
                v_reg <= w_valid;
                w_reg <= w_max;
            end
        end
        assign wd_w     = w_reg;
        assign wd_valid = v_reg;
    end else begin : g_wdirect
        assign wd_w     = w_in;
        assign wd_valid = w_valid;
    end
endgenerate

// f waits DLY_F stages for w, or w waits DLY_W stages for f (one of them is 0)
wire [FC_W-1:0] f_dly;
delay_line #(.W(FC_W), .N(DLY_F)) u_dly_f (.clk(clk), .rst(rst), .ce(ce), .d_in(f_carry), .d_out(f_dly));
delay_line #(.W(NW*W_W), .N(DLY_W))  u_dly_w (.clk(clk), .rst(rst), .ce(ce), .d_in(wd_w), .d_out(w_out));
// the later of the two paths brings the valid bit (the earlier one is delayed to match it)
assign out_valid = (DLY_W > 0) ? f_valid : wd_valid;

// f back to F_W bits (sign-extended)
generate
    if (FC_W < F_W) begin : g_fext
        assign f_out = {{(F_W-FC_W){f_dly[FC_W-1]}}, f_dly};
    end else begin : g_fnoext
        assign f_out = f_dly;
    end
endgenerate

endmodule

`default_nettype wire
