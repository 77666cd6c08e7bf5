"""Formal proofs of the RTL's stream, schedule, register and equivalence properties (`make formal`).

The properties live in the RTL under `ifdef FORMAL` (axis_skid, noise_fold, tex_regs, delay_line)
or in the small miters of this directory (bitlen_miter.v, mul_pipe_miter.v, axis_skid_loop.v);
formal/run.py generates one SymbiYosys job per property set and parameter set (build/formal/),
the parameters taken from the configurations (hdlbuild.params), runs them with yowasp-sby, the
yowasp Yosys and Debian's z3, and writes the Formal section of docs/verification.md.
Layer: beside sim and synth (imports model and hdlbuild).
"""
