// bitlen_miter: bitlen's two forms (PAR = 0, binary search; PAR = 1, in parallel) against each
// other and against a plain statement of the definition (bl = the index of the top one + 1,
// nz = x != 0), for every x (make formal; formal/run.py gives W and BW).

`default_nettype none

module bitlen_miter #(
    parameter W  = 8,  // bitlen's input width
    parameter BW = 4   // its output width
) (
    input wire [W-1:0] x
);

wire [BW-1:0] bl_search, bl_par;
wire          nz_search, nz_par;
bitlen #(.W(W), .BW(BW), .PAR(0)) u_search (.x(x), .bl(bl_search), .nz(nz_search));
bitlen #(.W(W), .BW(BW), .PAR(1)) u_par    (.x(x), .bl(bl_par),    .nz(nz_par));

reg [BW-1:0] bl_ref;
integer      i;
always @* begin
    bl_ref = {BW{1'b0}};
    for (i = 0; i < W; i = i + 1)
        if (x[i]) bl_ref = i + 1;
end

always @* begin
    assert(bl_search == bl_ref && nz_search == (x != 0));
    assert(bl_par == bl_ref && nz_par == (x != 0));
end

endmodule

`default_nettype wire
