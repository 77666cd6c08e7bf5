// MULT18X18D: a behavioural model of the Lattice ECP5 18x18 multiplier cell for the tests of
// synth/dsp_regs.py (Yosys ships the cell as a black box only). It models what that pass and
// Yosys's dsp_map use: P = A * B (each operand signed when SIGNEDA / SIGNEDB is 1), with the
// input registers (REG_INPUTA_CLK, REG_INPUTB_CLK), the pipeline register (REG_PIPELINE_CLK) and
// the output register (REG_OUTPUT_CLK) each present when its clock parameter is not "NONE".
// The registers are clocked by CLK0 (the only clock the pass uses: nextpnr-ecp5 times a
// registered MULT18X18D on CLK0), enabled by the CE port their *_CE parameter names, reset
// synchronously to 0 by the RST port their *_RST parameter names (RESETMODE "SYNC"), and start
// at 0 (the global set/reset at configuration). The C port, SOURCEA/B (the shift chains) and the
// other clocks are not modelled: the netlists tested tie them to constants.
`default_nettype none

module MULT18X18D (
    input  wire A17, A16, A15, A14, A13, A12, A11, A10, A9, A8, A7, A6, A5, A4, A3, A2, A1, A0,
    input  wire B17, B16, B15, B14, B13, B12, B11, B10, B9, B8, B7, B6, B5, B4, B3, B2, B1, B0,
    input  wire C17, C16, C15, C14, C13, C12, C11, C10, C9, C8, C7, C6, C5, C4, C3, C2, C1, C0,
    input  wire SIGNEDA, SIGNEDB, SOURCEA, SOURCEB,
    input  wire CLK0, CLK1, CLK2, CLK3, CE0, CE1, CE2, CE3, RST0, RST1, RST2, RST3,
    output wire P35, P34, P33, P32, P31, P30, P29, P28, P27, P26, P25, P24, P23, P22, P21, P20, P19, P18, P17, P16, P15, P14, P13, P12, P11, P10, P9, P8, P7, P6, P5, P4, P3, P2, P1, P0
);
    parameter REG_INPUTA_CLK = "NONE";
    parameter REG_INPUTA_CE = "CE0";
    parameter REG_INPUTA_RST = "RST0";
    parameter REG_INPUTB_CLK = "NONE";
    parameter REG_INPUTB_CE = "CE0";
    parameter REG_INPUTB_RST = "RST0";
    parameter REG_INPUTC_CLK = "NONE";
    parameter REG_PIPELINE_CLK = "NONE";
    parameter REG_PIPELINE_CE = "CE0";
    parameter REG_PIPELINE_RST = "RST0";
    parameter REG_OUTPUT_CLK = "NONE";
    parameter REG_OUTPUT_CE = "CE0";
    parameter REG_OUTPUT_RST = "RST0";
    parameter GSR = "ENABLED";
    parameter RESETMODE = "SYNC";

    function sel_ce(input [8*4-1:0] name);
        sel_ce = (name == "CE3") ? CE3 : (name == "CE2") ? CE2 : (name == "CE1") ? CE1 : CE0;
    endfunction
    function sel_rst(input [8*4-1:0] name);
        sel_rst = (name == "RST3") ? RST3 : (name == "RST2") ? RST2 : (name == "RST1") ? RST1 : RST0;
    endfunction

    wire [17:0] a = {A17, A16, A15, A14, A13, A12, A11, A10, A9, A8, A7, A6, A5, A4, A3, A2, A1, A0};
    wire [17:0] b = {B17, B16, B15, B14, B13, B12, B11, B10, B9, B8, B7, B6, B5, B4, B3, B2, B1, B0};
    reg  [17:0] a_r = 18'd0, b_r = 18'd0;
    reg  [35:0] m_r = 36'd0, p_r = 36'd0;
    wire [17:0] a_in = (REG_INPUTA_CLK == "NONE") ? a : a_r;
    wire [17:0] b_in = (REG_INPUTB_CLK == "NONE") ? b : b_r;
    wire signed [36:0] a_x = {{19{SIGNEDA & a_in[17]}}, a_in};
    wire signed [36:0] b_x = {{19{SIGNEDB & b_in[17]}}, b_in};
    wire signed [36:0] prod = a_x * b_x;
    wire [35:0] m = (REG_PIPELINE_CLK == "NONE") ? prod[35:0] : m_r;
    wire [35:0] p = (REG_OUTPUT_CLK == "NONE") ? m : p_r;
    assign {P35, P34, P33, P32, P31, P30, P29, P28, P27, P26, P25, P24, P23, P22, P21, P20, P19, P18, P17, P16, P15, P14, P13, P12, P11, P10, P9, P8, P7, P6, P5, P4, P3, P2, P1, P0} = p;

    always @(posedge CLK0) begin
        if (sel_rst(REG_INPUTA_RST)) a_r <= 18'd0; else if (sel_ce(REG_INPUTA_CE)) a_r <= a;
        if (sel_rst(REG_INPUTB_RST)) b_r <= 18'd0; else if (sel_ce(REG_INPUTB_CE)) b_r <= b;
        if (sel_rst(REG_PIPELINE_RST)) m_r <= 36'd0; else if (sel_ce(REG_PIPELINE_CE)) m_r <= prod[35:0];
        if (sel_rst(REG_OUTPUT_RST)) p_r <= 36'd0; else if (sel_ce(REG_OUTPUT_CE)) p_r <= m;
    end
endmodule
