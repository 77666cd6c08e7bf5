// sample_expand: each pixel offered SAMPLES times, as its sub-pixel texture samples.
//
// For the pixel (s, Jm, je) at the input (J = Jm 2^je, the 3x2 screen Jacobian of s: column 0
// per pixel step in x, column 1 in y) it offers sample k = 0..SAMPLES-1, in that order,
//   s_k  = sat(s + round(J d_k))       d_k = (dx, dy) / 4 pixel, dx, dy in {-1, 0, +1}
//   J_k  = the footprint of the sample's cell of the pixel (the cells tile the pixel)
// with the stratified offsets (docs/filters.md, "Sub-pixel samples"; model/hw/golden.py
// sample_expand is the twin; model/hw/config.py SAMPLE_OFFSETS, SAMPLE_FOOTPRINT):
//   SAMPLES = 2: d_0 = (0, -1)/4, d_1 = (0, +1)/4, J_k = J with its y column halved
//                (the vertical pair: the pixel's two halves across y)
//   SAMPLES = 4: d_k = (dx, dy)/4, dx = k[0] ? +1 : -1, dy = k[1] ? +1 : -1, J_k = J / 2
//                (the 2x2 grid: the pixel's quarters)
// round(J d_k) in s's units: m = dx Jm[r][0] + dy Jm[r][1] (exact), m 2^(je - 2 + S_FRAC)
// rounded half up (floor(x + 1/2)); s_k saturates to s's range (a sample past the range's edge
// is taken at the edge). J_k: SAMPLES = 4: je - 1, Jm unchanged (exact; at je's least value
// the footprint stays J); SAMPLES = 2: Jm_k[r][1] = floor((Jm[r][1] + 1) / 2) (half up, within
// half a unit of Jm[r][1] / 2), Jm_k[r][0] and je unchanged.
//
// Formats: s 3 x s{S_W}.{S_FRAC} ({r, t, s}, element e at [e*S_W +: S_W]); Jm 6 x s{J_W}.0
// (Jm[k][col] at element 2*k+col); je s{JE_W}.0. The same on the output.
//
// Handshake (in the pipeline's clock-enable domain, texture_pipeline's ce): out_valid = in_valid;
// a sample is taken on an enabled edge with in_valid and out_ready; the input pixel is taken
// (in_ready) with its last sample, so the input must hold its data while in_valid is high and
// in_ready low (the AXI4-Stream rule texture_pipeline's s_axis follows). A pixel takes SAMPLES
// accepted clocks. in_ready = out_ready && (the sample index is the last): out_ready to in_ready
// is combinational (texture_pipeline's front ready, itself a function of registers).
// Latency: 0 (the datapath is combinational from the input and the sample index register).
// Reset: synchronous, active high: the sample index returns to 0.

`default_nettype none

module sample_expand #(
    parameter SAMPLES = 4,   // [samples] sub-pixel samples a pixel: 2 or 4
    parameter S_W     = 24,  // [s_w] texture coordinates s{S_W}.{S_FRAC}
    parameter S_FRAC  = 16,  // [s_frac]
    parameter J_W     = 12,  // [j_w] Jacobian mantissas s{J_W}.0
    parameter JE_W    = 8    // [je_w] Jacobian exponent s{JE_W}.0
) (
    input  wire                clk,
    input  wire                rst,
    input  wire                ce,
    input  wire                in_valid,
    output wire                in_ready,
    input  wire [3*S_W-1:0]    s_in,
    input  wire [6*J_W-1:0]    jm_in,
    input  wire [JE_W-1:0]     je_in,
    output wire                out_valid,
    input  wire                out_ready,
    output wire [3*S_W-1:0]    s_out,
    output wire [6*J_W-1:0]    jm_out,
    output wire [JE_W-1:0]     je_out
);

localparam K_W    = (SAMPLES > 2) ? 2 : 1;          // the sample index
localparam M_W    = J_W + 1;                        // m = +-Jm0 +- Jm1
localparam O_W    = S_W + J_W + 3;                  // the offset and the sum before saturation
localparam E_W    = JE_W + 7;                       // je - 2 + S_FRAC (S_FRAC <= 24)
localparam SHL_MAX = S_W + 1;                       // a larger left shift saturates the same
localparam SHR_MAX = J_W + 2;                       // a larger right shift rounds to 0 the same

generate
    if (SAMPLES != 2 && SAMPLES != 4) begin : g_bad_params
        initial begin
            $display("sample_expand: SAMPLES = %0d must be 2 or 4", SAMPLES);
            $finish;
        end
    end
endgenerate

localparam [K_W-1:0] K_LAST = {K_W{1'b1}};     // SAMPLES - 1 (SAMPLES a power of two)
reg [K_W-1:0] idx_reg;
wire last = (idx_reg == K_LAST);
assign in_ready  = out_ready && last;
assign out_valid = in_valid;

always @(posedge clk) begin
    if (rst)
        idx_reg <= {K_W{1'b0}};
    else if (ce && in_valid && out_ready)
        idx_reg <= last ? {K_W{1'b0}} : idx_reg + 1'b1;
end

// the offset's direction: the grid dx from index bit 0, dy from bit 1; the pair dx = 0, dy from bit 0
localparam DX_ON = (SAMPLES == 4);
wire dx_pos = idx_reg[0];
wire dy_pos = idx_reg[K_W-1];

// the exponent of the offset in s's units: je - 2 + S_FRAC
localparam signed [E_W-1:0] E_BIAS = S_FRAC - 2;
wire signed [E_W-1:0] e_off = $signed({{(E_W-JE_W){je_in[JE_W-1]}}, je_in}) + E_BIAS;
wire                  e_neg = e_off[E_W-1];
wire [E_W-1:0]        e_mag = e_neg ? -e_off : e_off;
wire [E_W-1:0]        shl   = (e_mag > SHL_MAX) ? SHL_MAX : e_mag;
wire [E_W-1:0]        shr   = (e_mag > SHR_MAX) ? SHR_MAX : e_mag;

localparam signed [O_W-1:0] S_MAX = (1 <<< (S_W - 1)) - 1;
localparam signed [O_W-1:0] S_MIN = -(1 <<< (S_W - 1));

genvar r;
generate
    for (r = 0; r < 3; r = r + 1) begin : g_coord
        wire signed [J_W-1:0] j0 = jm_in[(2*r)*J_W +: J_W];
        wire signed [J_W-1:0] j1 = jm_in[(2*r + 1)*J_W +: J_W];
        wire signed [M_W-1:0] t0 = !DX_ON ? {M_W{1'b0}} :
                                   dx_pos ? $signed({j0[J_W-1], j0}) : -$signed({j0[J_W-1], j0});
        wire signed [M_W-1:0] t1 = dy_pos ? $signed({j1[J_W-1], j1}) : -$signed({j1[J_W-1], j1});
        wire signed [O_W-1:0] m  = $signed({{(O_W-M_W){t0[M_W-1]}}, t0}) + $signed({{(O_W-M_W){t1[M_W-1]}}, t1});
        // m 2^e rounded half up: e >= 0 exact (the shift capped where the sum saturates anyway),
        // e < 0 floor((m + 2^(sh-1)) / 2^sh) (capped where every m rounds to 0)
        wire signed [O_W-1:0] half = $signed({{(O_W-1){1'b0}}, 1'b1} << (shr - 1'b1));
        wire signed [O_W-1:0] off  = e_neg ? ((m + half) >>> shr) : (m <<< shl);
        wire signed [S_W-1:0] s0   = s_in[r*S_W +: S_W];
        wire signed [O_W-1:0] sum  = $signed({{(O_W-S_W){s0[S_W-1]}}, s0}) + off;
        assign s_out[r*S_W +: S_W] = (sum > S_MAX) ? S_MAX[S_W-1:0] :
                                     (sum < S_MIN) ? S_MIN[S_W-1:0] : sum[S_W-1:0];
    end
endgenerate

// the footprint of the sample's cell
localparam [JE_W-1:0] JE_MIN = {1'b1, {(JE_W-1){1'b0}}};
genvar c;
generate
    if (SAMPLES == 4) begin : g_quarter
        // J / 2: the exponent one less (exact)
        assign jm_out = jm_in;
        assign je_out = (je_in == JE_MIN) ? je_in : je_in - 1'b1;
    end else begin : g_half_y
        // J's y column halved, rounded half up: floor((Jm + 1) / 2) fits J_W bits
        for (c = 0; c < 3; c = c + 1) begin : g_row
            wire signed [J_W-1:0] jy = jm_in[(2*c + 1)*J_W +: J_W];
            /* verilator lint_off UNUSEDSIGNAL */  // |h| <= 2^(J_W-2): its top bit is its sign
            wire signed [J_W:0]   h  = ($signed({jy[J_W-1], jy}) + 1) >>> 1;
            /* verilator lint_on UNUSEDSIGNAL */
            assign jm_out[(2*c)*J_W +: J_W]     = jm_in[(2*c)*J_W +: J_W];
            assign jm_out[(2*c + 1)*J_W +: J_W] = h[J_W-1:0];
        end
        assign je_out = je_in;
    end
endgenerate

endmodule

`default_nettype wire
