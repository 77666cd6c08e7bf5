"""Mutation testing of rtl/ (issue 29 part 4, `make mutants [N=100] [SEED=1]`): N seeded single
mutations, each in a scratch copy of rtl/, each run against the mutated block's testbench and one
small frame; the share killed, and a table of every mutant.

The mutations (one per mutant, on a live line of an rtl/*.v file: not a comment, a string, a
preprocessor line, an `ifdef FORMAL block, a declaration (module, parameter, localparam, port,
reg, wire without `=`), nor a generate-time latency check):

- operator:   a binary + or - swapped, & and | swapped (binary or reduction), ^ to |, && and || swapped
- constant:   one bit of a literal flipped (sized: within its width; unsized: within its bit length)
- comparison: loosened or tightened: < to <=, > to >=, <= to < (inside parentheses), >= to >,
              == and != swapped
- stage:      a register stage skipped: `a <= b;` where b is a register written `b <= e;` becomes `a <= (e);`
- shift:      a shift amount off by one (<<, >>, >>>: n to n +- 1, x to (x + 1) or (x - 1))

A mutant is drawn kind first (by WEIGHTS), then a site, then one of the site's
alternatives, from random.Random(SEED); sites are drawn without replacement.

Each mutant is screened with Icarus first: the design is compiled for every configuration that
instantiates the mutated module (full, compact, reduced, full_fc, and the variants compact on two
noise units, compact with four terms, full with filter mip and none, compact with fpga_regs, compact with 4 and
reduced with 2 sub-pixel samples) and compared with the
unmutated compile. A mutant that compiles in none of them is stillborn (not counted; the next one
drawn takes its place); one that compiles in some only is killed (any testbench building the others
fails); the configurations whose compiled design differs are the ones its frames run on (none
differs: the mutation is dead code in every one of them, and only the block testbench, with its
random configurations, sees it).
Then Trivial Compiler Equivalence (TCE, Papadakis et al., ICSE 2015), with Yosys as the compiler
(tce_check): the compiles the mutation changes are those configurations and the builds of the block's
testbenches (each Icarus case, recorded by running its pytest cases with hdlbuild.run replaced:
tce_builds) whose Icarus compile differs from the unmutated one; on each parameter set the mutated
module's instances have in them (read from Icarus's compiled design: instance_params), the module
and its submodules are elaborated from rtl/ and from the scratch copy (hierarchy -chparam, proc,
flatten, opt -full, memory -nomap, ROMs mapped to logic, integer loop temporaries left unmatched) and
proved equivalent (equiv_make, equiv_struct -icells, then equiv_simple and, when it leaves few
signals unproven, equiv_induct, with undef states modelled; no $equiv cell left unproven:
yosys_equiv; when some are left, the same again with only the registers merged by equiv_struct:
RECIPES), within --tce-timeout seconds a mutant. A mutant
proved equivalent on every one of them is dropped before its tests (not counted, like a stillborn
one: the next one drawn takes its place) and listed with those parameter sets. A timeout, a
difference, an error keep it; so does a mutation no compile sees (code no checked parameter set
elaborates: nothing is proved about the parameter sets nobody checked). Verdicts are cached by the
mutated source, the sources it elaborates with and the parameter sets (out/mutants/cache/tce-*.json).
Then, with RTL_DIR set to the scratch copy (hdlbuild.rtl_dir(): builds go to a build/ beside it):

1. the mutated block's testbench, tb/<module>/, every Icarus case, `pytest -x` (a module without one,
   sat2_table or sat2_integral: the testbenches that build it, those whose sources name <module>.v);
2. if that passed: `python -m sim.frame` of each scene (default marble, noise terms, and
   zone_plate, the quadric) at 16x16 under Icarus on each of those configurations, every pixel
   against the golden model, until one fails.

The first test that fails kills the mutant (a timeout kills it too). Survivors that are
equivalent to the original (no input can tell them apart) are listed in EQUIVALENT below by
their id, with the reason (the ones Yosys cannot prove: the TCE check drops those it proves); the
report gives the share killed of all counted mutants (the raw share) and of the non-equivalent ones. Results are cached by mutant and by the sources its verdict depends on most (the mutated file,
rtl/*.vh, the block's testbench and the testbenches it imports, tb/pipe.py, sim/; out/mutants/cache/); a survivor is rerun
whenever the run's options changed. A rerun after a new test reruns only the mutants of that
block. An edit elsewhere (another rtl/ file, the golden model, which the RTL equals bit for bit
on every configuration) keeps a verdict; `rm -r out/mutants/cache` measures everything again.

    python -m verify.mutants --n 100 --seed 1 --jobs 2 [--files a.v,b.v] [--scenes marble,zone_plate] [--size 16]
        [--docs docs/verification.md] [--out out/mutants] [--tce-timeout 180] [--list] [--tce-only ID,...]
"""
from __future__ import annotations

import hashlib
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

from hdlbuild import ROOT, config_of, elaborate, gen_dir
from model.cli import Parser, UserError, progress_bar, resolve_scene, run_main
from model.hw.config import config_toml, doc_stamp, load_config, variant

RTL = ROOT / "rtl"
KINDS = ("operator", "constant", "comparison", "stage", "shift")
# the share of each kind among the drawn mutants (the sites: about 700 operators, 1300 constants,
# 250 comparisons, 80 shifts, 17 register stages)
WEIGHTS = {"operator": 0.3, "constant": 0.3, "comparison": 0.2, "stage": 0.08, "shift": 0.12}
TIMEOUT = 900  # seconds per test of a mutant (a hang is a kill)
TCE_TIMEOUT = 180  # seconds of Yosys per mutant, over all its parameter sets (past it: not proved, the mutant is kept)
TCE_RECIPE = 4  # the equivalence check's version (part of its verdicts' cache key; 3: the recipes of RECIPES in
# turn; 4: ROMs mapped to logic, integer loop temporaries not matched by equiv_make)
# How yosys_equiv merges the two designs before proving (equiv_struct), tried in order until one
# leaves no $equiv cell unproven. icells: every cell type (the logic the two share merged, a $equiv
# cell on each input that differs); it leaves $equiv cells it cannot prove in some modules even
# unmutated: its backward sweeps merge distinct cells of one design whose outputs earlier merges
# tied (tex_regs: two $eq compares of the field address with different constants, a $equiv cell
# between 1'0 and 1'1; fc_weight under full: x4 <= 0 and x4 >= ONE_L, lines 327 and 329; filter_width
# under tb full_sat2_fpga). ffs: the registers only (selected with the $equiv cells that tie their
# outputs), so that equiv_simple proves each register's next-state logic, and the outputs, from the
# merged registers and the inputs; slower (no shared logic merged: the SAT solver sees both copies),
# past 180 s on fc_weight under tb random7_fc, past 90 s on some sets of sat2_integral, cmap_sat2 and
# noise_hash that icells proves in seconds.
RECIPES = {"icells": "equiv_struct -icells", "ffs": "equiv_struct -icells t:$equiv t:$*dff*"}
INDUCT_MAX = 256  # equiv_induct only when equiv_simple leaves at most this many signal bits unproven

# Survivors shown equivalent to the original: mutant id -> why no input tells them apart.
# Kinds of argument: (loop) a loop bound loosened: the extra iteration indexes past the vector it
# writes, and Verilog drops a write out of range (its reads only feed that write); (trunc) the MSB
# index of a select raised: the extra high bits are cut where the result is assigned (the low bits
# of a sum or a concatenation's low part do not depend on them); (reset) the reset value of a data
# register that no valid output reads before it is loaded; (check) a term of an elaboration-time check
# (g_bad_*) changed where no parameter set that elaborates reaches it: the check only refuses;
# (contract) a value the block's documented contract rules out at that input.
_LOOP = "the extra iteration writes past the vector (or array), a write Verilog drops; its reads feed only that write"
# The last make mutants N=100 SEED=1 (stop 42, TCE_RECIPE 4, the testbenches' elaboration-check
# tests added): 121 drawn, 18 dropped as proved by TCE, 3 stillborn; 87 of 100 killed; of the 13
# survivors, 6ba15391 and bb98b115 rest on a contract (1 $equiv cell each), deb75bbc, 6d04301a,
# 9f45b138, f16028b6, 3cac89a1 are fc_weight's (icells leaves cells unproven in fc_weight unmutated,
# ffs runs past 180 s), 932109e8 and 46ddf5a3 differ only on signals no output reads, 731b2a03 compares
# the same values (noise_fold), and three change no compile (76f5d599, 30a5c7df, eda880b7: nothing to prove); each argued below.
# make mutants N=100 SEED=1 JOBS=2 on rtl 0fdb706a7fa6 (commit 250a9a7): 113 drawn, 12 dropped as proved by
# TCE, 1 stillborn; 85 of 100 killed; of the 15 survivors 6 were argued already, two are killed by tests
# added since (5f452dd6, fc_weight's out_valid set by reset: tb/fc_weight resets with ce = 0; 7d62b4af,
# noise_grad reading te without a T exponent: tb/noise_grad drives junk on te and ae without exponents),
# and seven are argued in the last block below: two selects cut where they are assigned, a zero cut, a
# loop bound, two branches forming the same registered product, a check's term no elaborating set reaches,
# and cmap_sat2's u_in (f N: even unless N = 1, where the colour is constant).
EQUIVALENT: dict[str, str] = {
    # issue 29, stop 33 (make mutants N=100 SEED=1 on rtl b18933406eb8)
    "73e2506c": "unused_w is read by nothing (a lint sink, UNUSEDSIGNAL): its width and bits change no logic",
    "0a718501": "(loop) hc = 4 writes h_new past its four lanes (and reads wr_data past its four): " + _LOOP
                + " (lane is a loop temporary)",
    "1bcdab25": "(check) K > RM_TERM_SLOTS to >= in g_bad_params' condition, the elaboration-time check: K <= 8 "
                "(features.noise_terms) < RM_TERM_SLOTS = 16, so both are false on every configuration and the "
                "designs that elaborate are the same (the check only refuses)",
    "e38316ac": "(trunc) bh is BH_W = B_W - SB bits: b[B_W:SB] is cut to b[B_W-1:SB]",
    "f3f3c5cf": "(loop) ip = 3K writes lt and tz past their 3K entries (and reads lt_c, tz_c past theirs): " + _LOOP,
    "18d1875b": "(trunc) r2_2_reg is P2_W bits: y2[P2_W:0] is cut to y2[P2_W-1:0]",
    "beda0c11": "(trunc) kk is NMAX bits: k[NMAX:0] is cut to k[NMAX-1:0]",
    "609a8579": "(check) || to && in sat2_integral's g_bad_params condition, the elaboration-time check: where every "
                "term is false (the check accepts) the mutated condition is false too, so the designs that "
                "elaborate are the same (the check only refuses)",
    "f9b2a78f": "(trunc) a_m is A_W bits: a_in[A_W+1:0] is cut to a_in[A_W-1:0]",
    "a865d988": "(trunc) the part-select written is CSAT_W bits: cfg_wr_data[CSAT_W+1:0] is cut to "
                "cfg_wr_data[CSAT_W-1:0]",
    "6124be27": "(trunc) axn_reg is NORM_BITS bits: ax_sh[NORM_BITS:0] is cut to ax_sh[NORM_BITS-1:0]",
    "ddd7e6cd": "(loop) c6c = 4 writes num_c past its four channels (and reads sum_c, pt_c past theirs): " + _LOOP
                + " (nsh_c is a loop temporary)",
    "a1ec2ddf": "(loop) li = NLN writes top, over and w_all past their NLN lanes (and reads r_bl, r_nz, lane past "
                "theirs): " + _LOOP + " (top_l, r_x, w_sh are loop temporaries)",
    "5692af14": "if (C0 > 0) differs from if (C0 >= 0) only at C0 = 0, where the else arm shifts pw right by "
                "(C0 < 0) ? -C0 : 0 = 0: pw either way",
    "0727bc71": "(loop) k2 = 3 writes lm0[3], past the array lm0[0:2] (and reads mnz, mb, m1 past their three): "
                + _LOOP + " (me, mx are loop temporaries)",
    "02a1bb36": "(trunc) e_dly_reg is SQ_LAT E_W bits: e_dly_cat[SQ_LAT*E_W+1:0] is cut to e_dly_cat[SQ_LAT*E_W-1:0]",
    "0feeead1": "(trunc) the part-select written is W_W bits: w_in[W_W+1:0] is cut to w_in[W_W-1:0]",
    "51132eac": "(loop) ch = 4 writes term_nx past its four channels (and reads cs_in, h_in, total_in, total2_in, "
                "c_in past theirs): " + _LOOP + " (cs, h, tt, ht2, z, kz, kzt, ii, r, kzf, ycs, fc, f2c, kzx are "
                "loop temporaries)",
    "3ccb146d": "(reset) qo_valid reaches the outputs only as noise_leaves' q_valid, ANDed there with every noise "
                "leaf's valid (v_all), whose delay lines rst clears; DLY_QO > 0 only with K > 0 terms (LAT_FRONT = "
                "LAT_QM when K = 0), so a valid bit left in u_dly_qov by a reset never makes an output valid",
    "ed444ca3": "unused_w is read by nothing (a lint sink, UNUSEDSIGNAL): its width and bits change no logic",
    "158aebc7": "q_bcf (B | C | F, 0 by contract) is read by nothing: a wire kept for lint (UNUSEDSIGNAL), not logic",
    "a9152661": "o_sel keeps its default only when no slot m matches (j_reg past the pixel's slots, or m U + gu >= "
                "K), where a_sel keeps its default 0: a term with a = 0 is exactly 0 whatever its offset o",
    "259be3f9": "d_w is 0 before this write: d_w[W_W:0] takes w_s zero-extended, so bit W_W gets the 0 it held",
    "d4e79b0f": "(loop) lk = NLN writes w_fin past its NLN lanes (and reads fin_over[NLN] past the vector): " + _LOOP,
    "8d4aed03": "LAT_CMAP_SAT2, LAT_CMAP_MIP and LAT_CMAP_POINT are equal (13, with FPGA_REGS 17; "
                "rtl/tex_latency.vh): whichever of them the inverted condition picks, LAT_FAM is the same number",
    "731b2a03": "kt runs 0..K < 2^KU_W, so kt[KU_W+1:0] is kt[KU_W-1:0] with two zero bits above, and k_used zero-"
                "extended compares equal to it exactly when it did",
    "c81a7f37": "(trunc) km is NMAX bits: kms[NMAX:0] is cut to kms[NMAX-1:0]",
    "6045c743": "cs is CS_W + 1 bits, 0 before this write: cs[CS_W+1:0] takes cs_in's CS_W-bit slice zero-extended, so"
                " bit CS_W gets the 0 it held (bit CS_W + 1, past cs's top, is a part-select write Verilog drops)",
    "3110b5f6": "clut_we holds only with wr_addr[NMAX] = 0 (sat2_table: !wr_addr[NMAX]), so wr_addr[NMAX:0] is the "
                "same index as wr_addr[NMAX-1:0]",
    "05e09ffd": "the delay line is KW bits wider (5 KW for 4 KW) than the concatenation it carries: its input is "
                "zero-extended, the extra output bits dropped; the bits the nets carry are delayed as before",
    "283b220c": "(loop) r2 = 3 writes lm2[3], past the array lm2[0:2] (and reads lm0[3], past lm0[0:2]): " + _LOOP,
    "2fc2c8ab": "(reset) at_last reaches the outputs only through busy_reg && at_last and !busy_reg || at_last; reset"
                " clears busy_reg, and busy_reg rises only in the clock that takes a pixel, the clock that loads "
                "at_last_reg (j_last == 0): while busy_reg = 0 its value is not read",
    "67ce33a5": "(reset) t_on is rewritten on every clock (no ce) from t_on_c, a function of the pass parameters: one"
                " clock after rst falls it holds the same value whatever rst wrote, and stage 3, where it is read "
                "(lok0), sees a pixel two clocks after it enters at the earliest",
    "6ba15391": "(contract) n_log2 is the loaded tables' size (colour_map, cmap_sat2: 'tables loaded for that N'); it"
                " changes only with a table load, which texture_pipeline makes only with the pipeline empty "
                "(tex_regs), so s2, s3 and s4 hold the same n_log2 whenever a pixel is in flight; tb/cmap_sat2 holds "
                "it per table",
    "84ffc093": "the extra generate iteration gl = 4 adds a fifth x lerp, g_lerp_x[4], whose y nothing reads (stage 4"
                " reads g_lerp_x[0..3].y by name): unused logic, its b past v_reg's eight corners",
    "c2e6abb5": "a zero of KV 2 O_W bits zero-extended to o_all's KV 3 O_W bits is the same zero",
    "c5e71ecd": "q_bcf (B | C | F, 0 by contract) is read by nothing: a wire kept for lint (UNUSEDSIGNAL), not logic",
    "f5b90fc6": "(trunc) ku_reg is KU_W = U_W - FF bits: u_in[U_W+1:FF] is cut to u_in[U_W-1:FF]",
    "a1382ea7": "without FPGA_REGS (P = 0, g_no5a) h_0y feeds only wn_0, hence wn_f, which s5_wn_reg takes only with "
                "FPGA_REGS (else {1'b0, w_y} + h2): the constant is not read",
    "b54fc3cb": "FX_Q = 0 takes g_fx instead of g_f: a sign extension by zero bits ({0{...}} in a concatenation is "
                "empty) is q_in itself",
    "54ba9431": "(trunc) valid_reg is LATENCY bits: vin[LATENCY:0] is cut to vin[LATENCY-1:0]",
    "867b0a9d": "(loop) cs2 = 4 writes v1_nx and v2_nx past their four channels (and reads term past its four): " + _LOOP,
    "86f55fb4": "(trunc) the slice written is DEN_W bits: the conditional's diff[DEN_W:0] is cut to diff[DEN_W-1:0] "
                "(rem[I +: DEN_W] on the other side is zero-extended and cut back)",
    "87a5b002": "(trunc) ag_next is AG_W bits: agp[AG_W:0] is cut to agp[AG_W-1:0]",
    "eef05fc2": "the delay line is 5 TW bits wide on 4 TW-bit nets: its input is zero-extended, the extra output bits"
                " dropped; the 4 TW bits the nets carry are delayed as before",
    "98ff867d": "(trunc) an_next is AN_W bits: an_w[AN_W+1:0] is cut to an_w[AN_W-1:0]",
    "47877a40": "(loop) the extra generate lane l = LANES reads and writes rem_in/rem_out past their LANES lanes: " + _LOOP,
    "6dfa04d7": "(loop) c = 4 writes num_x past its 4 channels: " + _LOOP + " (sum and pt are loop temporaries)",
    "c67ff000": "(loop) al3[K] is past the array al3[0:K-1]: " + _LOOP,
    "a1713a5f": "(loop) tn[(3K + ka) T_W +: T_W] is past tn's 3K entries: " + _LOOP,
    "99da974d": "(loop) sd4[K] is past the array sd4[0:K-1]: " + _LOOP,
    "d2d2d371": "(loop) pi = RM_Q_COUNT writes q_coef past its RM_Q_COUNT words: " + _LOOP
                + "; the register at that offset is written by its own decode as before",
    "23e05d09": "(trunc) {valid_reg[Q_W+2:0], in_valid} is cut to valid_reg's Q_W bits: the same low bits",
    "af4c8dca": "(trunc) last_issue_of returns J_W bits: q[J_W+1:0] is cut to q[J_W-1:0]",
    "dc5b47bc": "(trunc) prod_next is ACC_W bits in the pow2 branch (NPROD = 1): shl[ACC_W:0] is cut to shl[ACC_W-1:0]",
    "82555dfb": "a zero of 2 C_W bits zero-extended to c_step's 3 C_W bits is the same zero",
    "1aae2966": "the delay line is 7H bits wide on 6H-bit nets: its input is zero-extended, the extra output bits dropped; "
                "the 6H bits the nets carry are delayed as before",
    "1ae3f703": "FC_W = F_W takes g_fext instead of g_fnoext: a sign extension by zero bits ({0{...}} in a "
                "concatenation is empty) is f_dly itself",
    "6895a351": "inside `if (C0 >= 0)`, (C0 > 0) ? C0 : 0 differs from (C0 >= 0) ? C0 : 0 only at C0 = 0, where both are 0",
    "2f72ca41": "(reset) tn is rewritten on every clock (no ce) from the pass registers: one clock after rst falls it "
                "holds the same value whatever rst wrote, and no valid pixel reads it earlier",
    "335826b3": "(reset) c_acc_reg is loaded with c_step on a pixel's first term (first_o) before any sum is valid: "
                "its reset value never reaches the output",
    "b4115851": "m_nx's default is overwritten: the channel loop assigns all four D_W slices of it",
    "8f70a181": "(loop) k0 = 3 writes m0[3], past the array m0[0:2]: " + _LOOP + " (ja, jb are loop temporaries)",
    "5dae4462": "m = NJ adds an iteration whose condition never holds: NJ = ceil(K / U), so NJ U + gu >= K",
    "5e541f1d": "q <= MIN_CLOCKS - 1 differs from q < MIN_CLOCKS - 1 only at q = MIN_CLOCKS - 1, where the "
                "assignment writes the value q holds",
    "17c6677f": "tc's default is overwritten: the loop over j assigns all three E_W + 1-bit fields of tc (TC_W = 3 (E_W + 1))",
    "c38d2b94": "with the condition inverted a diagonal quadric on two clocks (FPGA_REGS 0) takes g_diag, qmac_diag, "
                "instead of g_diag_fold, qmac_diag_fold: the same values (golden qmac_diag_fold is qmac_diag; "
                "tb/qmac_diag and tb/qmac_diag_fold check each bit-exact), the same latency (LAT_QMAC_DIAG = "
                "LAT_QMAC_DIAG_FOLD = 3, rtl/tex_latency.vh), and a one-clock datapath takes a vector every other "
                "clock as well: only the multipliers double. An affine quadric cannot have two clocks (g_bad_clocks; "
                "model/hw/config.py: quadric_clocks = 2 needs a diagonal quadric)",
    "10ba35ae": "at f = lo_thr = -(guard >> n_log2) the unclamped u = f N is -guard exactly (guard = 2^GUARD, "
                "GUARD = W_CAP_LOG2 + F_FRAC - 1 > n_log2 since w_cap_log2 >= n_log2_max), the clamp's own value",
    "1ee186ff": "NG = 0 with CX_N > 0 takes g_cx instead of g_c0: the sign extension of ag, and ag (noise_term's "
                "ag_out) is 0 when NOISE_GRADIENT = 0, so c is 0 either way",
    # make mutants N=100 SEED=1 after noise_params (1e5234a): the survivors new to that draw
    "9edf807e": "(trunc) t_m is 9 T_W bits: t_in[9*T_W+1:0] is cut to t_in[9*T_W-1:0]",
    "53a5b39e": "(trunc) {valid_reg[STAGES+2:0], in_valid} is cut to valid_reg's STAGES bits: the same low bits",
    "8d84b3a2": "num_hi is 0 before this write: num_hi[NH:0] takes the NH-bit slice zero-extended, so bit NH gets the "
                "0 it held (past OW, a write Verilog drops)",
    "3498b2bf": "(loop) k = 3 writes prod_next past its NPROD = 3 products (and reads t_row, s_in past their 3 "
                "elements): " + _LOOP,
    "74027af8": "(check) a term of g_bad_params' condition, the elaboration-time check: MH_W < 0 is false where MH_W < 1"
                " is, so every parameter set the check accepts it still accepts, and the design it elaborates is the "
                "same (the check only refuses)",
    "61b21aae": "(check) || to && in g_bad_params' condition, the elaboration-time check: where every term is false "
                "(the check accepts) the mutated condition is false too, so the designs that elaborate are the same "
                "(the check only refuses)",
    "2b5d9fd8": "without FPGA_REGS (P = 0, g_no5a) sh0_y is read only under if (P != 0) (stage 5(b) finds sh0 itself): "
                "the constant is not read",
    "a4474a98": "ht is 0 before this write: ht[CS2_W+1:0] takes the CS2_W-bit slice zero-extended, so the two bits "
                "above CS2_W get the 0 they held (past D_W, a part-select write Verilog drops)",
    "2f8b87e0": "the extra generate iteration gl = 2 adds a third y lerp, g_lerp_y[2], whose y nothing reads (fz_reg "
                "reads g_lerp_y[0..1].y by name): unused logic, its a and b past e_reg's four words",
    "0ea780e8": "(trunc) out_reg is 32 bits: dd_reg[(DL-2)*32 +: 48] is cut to its low 32 bits, dd_reg[(DL-2)*32 +: 32]",
    "b016f30b": "(x >= z) ? x : z differs from (x > z) ? x : z only at x = z, where both give the same value",
    "44bad121": "(loop) ui = KV writes t_use past its KV terms: " + _LOOP,
    "bbad62b1": "(trunc) e is EA_W bits: i[EA_W+1:0] is cut to i[EA_W-1:0]",
    "1effb58f": "(trunc) ag_next is AG_W bits: agp[AG_W+1:0] is cut to agp[AG_W-1:0]",
    "e2c26b1e": "(trunc) cq_out_reg is 3 C_W bits: the two extra bits of c2_sh[C_W+1:0], the concatenation's top, are "
                "cut",
    "62862b39": "nlm1_x is 0 before this write: nlm1_x[NMAX:0] takes nlm1 (NMAX bits) zero-extended, so bit NMAX gets the"
                " 0 it held (past KU_W, a write Verilog drops)",
    "631d55bf": "the delay line is one bit wider than the concatenation it carries: its input is zero-extended, the "
                "extra output bit dropped; the bits the nets carry are delayed as before",
    "f2c7f971": "(trunc) rem is R_W bits: the conditional's rs[R_W+1:0] (all of rs) is cut to rs[R_W-1:0] (diff[R_W-1:0]"
                " on the other side is zero-extended and cut back)",
    "78320d08": "(trunc) ah is AH_W = A_W - SA bits: a[A_W+1:SA] is cut to a[A_W-1:SA]",
    "28bf94c4": "X_W = L_W takes g_pad instead of g_nopad: a zero extension by zero bits ({0{...}} in a concatenation is "
                "empty) is l_in itself",
    "dfc3e0b9": "lsum >= lmax differs from lsum > lmax only at lsum = lmax, where lmax = lsum writes the value lmax holds"
                " (lany is set either way)",
    # make mutants N=100 SEED=1 after the two sub-pixel samples (cd290f5): the survivors new to that draw
    "460c470f": "(check) KW + XF > D_W to >= in g_bad_params' condition, the elaboration-time check: only cmap_sat2 "
                "builds sat2_integral, with KW + XF = X_W (tw_x2_w) and D_W = tw_d2_w = 2 (W_CAP_LOG2 + F_FRAC) + 11, "
                "at least 8 more than X_W for every f_frac 8..20, w_cap_log2 1..20, n_log2_max 0..10 "
                "(model/hw/config.py), so both are false on every configuration and the designs that elaborate are "
                "the same (the check only refuses)",
    "76f5d599": "LAT_DP is read only by g_bad_latency, and `LAT_QMAC_DIAG_FOLD = `LAT_QMAC_DIAG = 3 "
                "(rtl/tex_latency.vh): a diagonal quadric on two clocks (CLOCKS = 0 is refused by g_bad_clocks) "
                "falls through to `LAT_QMAC_DIAG, the same number",
    "30a5c7df": "a zero of C_W bits zero-extended to c_acc_reg's 3 C_W bits is the same zero",
    "102b5d7b": "(check) || to && in g_bad_params' condition, the elaboration-time check: where every term is false "
                "(the check accepts) the mutated condition is false too, so the designs that elaborate are the same "
                "(the check only refuses)",
    # issue 29, stop 39 (make mutants N=100 SEED=1 on main with the cache emptied: the four that the
    # worktree run of this stop had counted killed while config/compact.toml changed under its shared out/)
    "66aa9dbf": "(loop) k = KV writes join_t past its KV fields (and reads e, m past theirs): " + _LOOP,
    "eda880b7": "(constant) RM_CLUT_LOG2 is 0 (rtl/tex_regmap.vh): NLMAX - 0 and NLMAX + 0 are the same shift",
    "882af73c": "(check) || to && in filter_width's latency and width check, the elaboration-time check: where "
                "every term is false (the check accepts) the mutated condition is false too, so the designs that "
                "elaborate are the same (the check only refuses)",
    "70269b40": "(trunc) ay_reg is GABS_W bits: gy_abs[GABS_W:0] is cut to gy_abs[GABS_W-1:0]",
    "554fe7a8": "(loop) ri = 4 writes rgba_wide[4 CSAT_W +: 8], past its 4 CSAT_W bits (and reads cfg_wr_data[32 +: 8],"
                " past its RM_DATA_W = 32): " + _LOOP,
    "deb75bbc": "(ja >= jb) ? ja : jb differs from (ja > jb) ? ja : jb only at ja = jb, where both give the same value",
    "6d04301a": "pw_x >= CAP_V differs from pw_x > CAP_V only at pw_x = CAP_V, where CAP_V[W_W-1:0] and "
                "pw_x[W_W-1:0] are the same value",
    "9f45b138": "x4 < 0 differs from x4 <= 0 only at x4 = 0, which then fails x4 >= ONE_L (ONE_L = 2^AF > 0: AF <= "
                "LF + 4 (fc_fade_log2 <= 4) < L_W - 1, L_W >= JB_W + LF + 3 with JB_W >= 3 (j_w >= 4)) and takes "
                "x4[AF:0] = 0, the value of the branch it skipped",
    "b8dd487d": "(loop) pi = 2^H writes perm_rom[2^H], past the array perm_rom[0:2^H-1] (and reads PERM past its 2^H "
                "entries): " + _LOOP,
    # make mutants N=100 SEED=1 with the TCE check (issue 29 part 4): the draws that replaced the seven mutants Yosys
    # proved equivalent (c9615a12, 64deaf40, 6a737c59, b0c1f383, cf82c493, 7faf3143, c96f3973: their arguments removed)
    "4b3fe497": "(loop) lj = NLN writes ov_c[NLN], past ov_c's NLN bits (and reads nz_r[NLN], top_r[NLN CMP_W +: "
                "CMP_W], past theirs): " + _LOOP,
    "414c2983": "(trunc) axn_reg is NORM_BITS bits: ax_sh[NORM_BITS+1:0] is cut to ax_sh[NORM_BITS-1:0]",
    "2767868f": "(trunc) wr_off is RL bits: cfg_wr_addr[RL+1:0] is cut to cfg_wr_addr[RL-1:0]",
    "bb98b115": "(contract) as 6ba15391: n_log2 is the loaded tables' size, changed only by a table load, which "
                "texture_pipeline makes only with the pipeline empty (tex_regs), so n_log2 and s2_n_log2_reg hold the same "
                "value whenever a pixel is in flight",
    "f16028b6": "(loop) the extra generate iteration go = K assigns al3_v[K (AF+1) +: AF+1], past al3_v's K (AF+1) bits, "
                "from al3[K], past the array al3[0:K-1]: " + _LOOP,
    # issue 29, stop 42 (make mutants N=100 SEED=1 on rtl of ef164b4, TCE_RECIPE 4: 1 $equiv cell left
    # on an internal signal the outputs never see, or ffs past 180 s on fc_weight)
    "932109e8": "csat_addr_a, the colour table's csat read address, feeds only csat_a, which cmap_point wires to "
                "unused_csat_a, read by nothing (a lint sink, UNUSEDSIGNAL: the point lookup reads only clut_a): "
                "another address reads another word nobody sees",
    "46ddf5a3": "stage s of the divider sets quotient bit Q_W-1-s (q_nx[l*Q_W+I] = !diff[DEN_W]) and passes the rest; after "
                "the Q_W stages every bit has been set, so stage 0's initial q_in bits, zeros or ones, never reach "
                "q_out (only the undecided low bits of the stages' q_reg differ)",
    "3cac89a1": "(loop) r1 = 3 writes m1[3 J_W +: J_W], past m1's 3 J_W bits, from m0[3], past the array m0[0:2]: " + _LOOP,
    # make mutants N=100 SEED=1 JOBS=2 on rtl 0fdb706a7fa6: the seven survivors no test can kill
    "1e31a638": "(trunc) the part-select written is W_W bits: w_sh[W_W+1:0] is cut to w_sh[W_W-1:0] (a bit of it past "
                "w_sh's SW bits reads x and is cut too)",
    "5bcb7f00": "(trunc) ay_reg is GABS_W bits: gy_abs[GABS_W+1:0] is cut to gy_abs[GABS_W-1:0] (bit GABS_W + 1, past "
                "gy_abs's G_W = GABS_W + 1 bits, reads x and is cut too)",
    "52c86c22": "C_W <= 35 to < 35 differs only at C_W = 35, where each product c_k Jm[k][col] takes g_reg instead of "
                "g_mul: the same exact signed product (PJ_W = C_W + J_W bits) behind one register loaded on ce, "
                "without reset, as mul_pipe gives it (exact for operands of at most 35 bits, its header; tb/mul_pipe "
                "widest, 35 x 35): prod_1a is the same word on every clock",
    "4cd8caba": "a zero of 6 CS_W bits cut to total's 4 CS_W bits is the same zero",
    "488fac80": "(loop) i5 = KP writes mt[2 KP], past the array mt[1:2 KP-1], the zero (i5 < K is false: KP = "
                "2^clog2(K) >= K): " + _LOOP + " (the tree's loop sets i5 = KP - 1 before it reads i5)",
    "f89fa157": "(check) 2 XF + 1 + CS2_W < 1 to <= 1 in sat2_integral's g_bad_params condition, the elaboration-time "
                "check: the two differ only where 2 XF + CS2_W = 0, which does not elaborate unmutated either (XF < 0:"
                " the replication {XF{1'b0}} is negative; XF >= 0: CS2_W <= 0, the select h[CS2_W-1:0] is reversed; "
                "Icarus refuses both), so the designs that elaborate are the same (the check only refuses); cmap_sat2, "
                "its only builder, has XF = F_FRAC + 1 >= 9 and CS2_W >= 8",
    "bcdd2c93": "(contract) u2[1] = 0 clears u_in's LSB. u_in is colour_map's stage 1, f N (cmap_sat2's header; "
                "colour_map.v: (f mod 1) << n_log2, or f << n_log2 clipped to -2^GUARD or N 2^F_FRAC + 2^GUARD, GUARD "
                "= W_CAP_LOG2 + F_FRAC; golden cmap_u), so its LSB is 0 whenever n_log2 >= 1; with n_log2 = 0 the "
                "table is one entry c, the colour function is c everywhere (mod and clamp), S(x) = c x and the "
                "four-point difference of G depends on c, a and b alone, not on the centre: D, the divisor and the "
                "point lookup clut[0] are those of u - 1 (golden cmap_sat2 of u and u & ~1 on tb/cmap_sat2's four "
                "sets, every n_log2, ~38,000 odd u each: none differ)",
    # make mutants N=100 SEED=1 JOBS=2 on rtl c847d677bc9b (stop 48): of its seven unexplained survivors two are
    # killed by tests added at stop 49 (b2b3a86b, noise_grad's ag registers loaded on ce || load: tb/noise_grad
    # checks that ag_out holds on every clock without ce and load; 2ec92faa, filter_width's left shift reading
    # e[E_W-3:0]: tb/filter_width's SHORT_EXPONENT configurations, where e reaches 2^(E_W-2) below the cap),
    # and five are argued here
    "942a921b": "(max) mt[i5] is the larger of two values, with no index beside it: a > b ? a : b and a >= b ? a : b "
                "differ only at a == b, where both give that one value",
    "06c02de3": "(ku == 0) to (ku == 1) in last_issue_of: at ku = 1 the branch's 0 is (1 - 1) / U = 0 as well; at ku = "
                "0 the mutant takes (0 - 1) / U, an integer division that truncates toward zero: 0 for U > 1, -1 for "
                "U = 1, and the next line raises q below MIN_CLOCKS - 1 to MIN_CLOCKS - 1 >= 0, as it does the "
                "original's 0: j_last is MIN_CLOCKS - 1 for k_used = 0 in both",
    "14a7e1eb": "(contract) f > hi_thr to f >= hi_thr differs only at f = hi_thr = 1.0 + (guard >> n_log2), where the "
                "mutant takes n_u + guard_u = N 2^F_FRAC + 2^GUARD and the original u_sh = f << n_log2 = N 2^F_FRAC + "
                "((2^GUARD >> n_log2) << n_log2): the same word whenever GUARD >= n_log2, and GUARD = W_CAP_LOG2 + "
                "F_FRAC - 1 (+1 for sat2) >= N_LOG2_MAX + 7 because model/hw/config.py requires w_cap_log2 >= "
                "n_log2_max and f_frac >= 8 (u_sh's U_W bits hold N + the guard: the clamp's range)",
    "f83c742c": "(trunc) u_mod[MW-0:0] = u_mod_i writes u_mod_i (MW bits, an unsigned wire: zero-extended) to bits MW..0: "
                "bit MW gets 0, which it holds from the line above (u_mod = 0), or, where MW = U_W, the write past "
                "the vector is dropped",
    "03a6c2c3": "mip_index with FILTER 0 reads w_in into nothing but a lint sink (unused_w = w_in; l = 0 always, its "
                "header): the all-ones w_in is the same design as the zeros",
}

# Survivors neither killed nor shown equivalent, with what was found (listed as open in the report).
OPEN: dict[str, str] = {
    "80e34b7e": "not equivalent, unreachable: with || a C_W or J_W above 35 (mul_pipe's two parts) takes mul_pipe "
                "when the other is at most 35; no configuration has one (C_W at most 33, J_W at most 13 over the "
                "named, candidate and random:0..299 configurations)",
}


# --------------------------------------------------------------------------- the sites


@dataclass(frozen=True)
class Mutant:
    file: str   # name in rtl/
    line: int   # 1-based
    col: int    # 0-based, in the raw line
    old: str
    new: str
    kind: str
    text: str   # the original line, stripped
    dup: int = 0  # n > 0: the (n+1)-th site of the file with the same text, column and change

    @property
    def id(self) -> str:
        """Stable under edits elsewhere in the file (no line number in it); a site whose line,
        column and change repeat an earlier one of its file (two identical lines) gets its
        occurrence number in the key, so that no two mutants share an id (nor a cached verdict)."""
        key = f"{self.file}|{self.text}|{self.col}|{self.old}|{self.new}" + (f"|{self.dup}" if self.dup else "")
        return hashlib.sha1(key.encode()).hexdigest()[:8]

    @property
    def module(self) -> str:
        return Path(self.file).stem

    def describe(self) -> str:
        return f"`{self.old}` -> `{self.new}`"

    def apply(self, src: str) -> str:
        lines = src.split("\n")
        raw = lines[self.line - 1]
        assert raw[self.col:self.col + len(self.old)] == self.old, (self, raw)
        lines[self.line - 1] = raw[:self.col] + self.new + raw[self.col + len(self.old):]
        return "\n".join(lines)


DECL = re.compile(r"^\s*(module|endmodule|parameter|localparam|input|output|inout|reg|integer|genvar|"
                  r"function|endfunction|task|endtask|generate|endgenerate|`)\b|^\s*`")
CHECK = re.compile(r"begin\s*:\s*g_(bad|latency_mismatch)|_mismatch_|mismatch_see")  # the generate-time checks
SYSTASK = re.compile(r"\$(display|error|fatal|finish|warning|info|stop|write)")


def live_code(src: str) -> list[str]:
    """Each line of `src` with what is not live code blanked (same length, spaces): comments,
    strings, preprocessor lines, `ifdef FORMAL blocks, declarations (a wire's `= expr` kept),
    generate-time latency checks and system-task lines."""
    out = []
    in_block = False
    stack: list[tuple[str, bool]] = []  # (macro, this branch excluded) of each open `ifdef
    for raw in src.split("\n"):
        m = list(raw)
        i, n = 0, len(raw)
        while i < n:
            if in_block:
                j = raw.find("*/", i)
                end = n if j < 0 else j + 2
                m[i:end] = " " * (end - i)
                in_block = j < 0
                i = end
            elif raw.startswith("//", i):
                m[i:] = " " * (n - i)
                break
            elif raw.startswith("/*", i):
                in_block = True
            elif raw[i] == '"':
                j = raw.find('"', i + 1)
                end = n if j < 0 else j + 1
                m[i:end] = " " * (end - i)
                i = end
            else:
                i += 1
        code = "".join(m)
        w = code.split()
        if w and w[0] in ("`ifdef", "`ifndef"):
            mac = w[1] if len(w) > 1 else ""
            stack.append((mac, mac == "FORMAL" if w[0] == "`ifdef" else False))
        elif w and w[0] == "`else" and stack:
            mac, ex = stack[-1]
            stack[-1] = (mac, (not ex) if mac == "FORMAL" else ex)
        elif w and w[0] == "`endif" and stack:
            stack.pop()
        skip = (any(ex for _, ex in stack) or not w or w[0].startswith("`") or DECL.match(code)
                or CHECK.search(code) or SYSTASK.search(code) or "initial" in w)
        if not skip and re.match(r"^\s*wire\b", code):
            k = code.find("=")
            code = " " * (k + 1) + code[k + 1:] if k >= 0 else ""
        out.append(" " * len(raw) if skip or not code.strip() else code.ljust(len(raw)))
    return out


TOKEN = re.compile(r"\d+\s*'[sS]?[bBoOdDhH]\s*[0-9a-fA-F_xXzZ?]+|'[sS]?[bBoOdDhH][0-9a-fA-F_xXzZ?]+|"
                   r"<<<|>>>|===|!==|<<|>>|<=|>=|==|!=|&&|\|\||~&|~\||~\^|\^~|[A-Za-z_][\w$]*|\d[\d_]*|\S")
REPL = re.compile(r"\{\s*(\((?:[^(){}]|\([^(){}]*\))*\)|[A-Za-z_]\w*|\d+)\s*\{")
SIZED = re.compile(r"(\d+)\s*'([sS]?)([bBoOdDhH])\s*([0-9a-fA-F_]+)$")


def _operand_end(code: str, i: int) -> int | None:
    """End of the shift amount starting at code[i] (an identifier with its selects, a number, a
    parenthesized expression), or None."""
    while i < len(code) and code[i] == " ":
        i += 1
    m = re.match(r"[A-Za-z_][\w$]*|\d[\d_]*", code[i:])
    if m:
        j = i + m.end()
    elif code[i:i + 1] == "(":
        j = i
    else:
        return None
    while j < len(code) and code[j] in "([":
        close = {"(": ")", "[": "]"}[code[j]]
        depth, k = 0, j
        while k < len(code):
            depth += code[k] == code[j]
            depth -= code[k] == close
            k += 1
            if depth == 0:
                break
        if depth:
            return None
        j = k
        if m:  # an identifier's selects only
            continue
        break
    return j


def _flip_sized(lit: str) -> list[str]:
    m = SIZED.match(lit)
    if not m:
        return []
    width, s, base, digits = int(m.group(1)), m.group(2), m.group(3), m.group(4).replace("_", "")
    radix = {"b": 2, "o": 8, "d": 10, "h": 16}[base.lower()]
    v = int(digits, radix)
    fmt = {2: "b", 8: "o", 10: "d", 16: "x"}[radix]
    return [f"{width}'{s}{base}{format(v ^ (1 << b), fmt)}" for b in range(min(width, 32))]


def sites(file: str, src: str) -> list[tuple[str, list[Mutant]]]:
    """Every mutation site of an rtl/ file: (kind, its alternatives)."""
    raws = src.split("\n")
    codes = live_code(src)
    out: list[tuple[str, list[Mutant]]] = []

    def add(kind, li, col, old, news):
        ms = [Mutant(file, li + 1, col, old, n, kind, raws[li].strip()) for n in news if n != old]
        if ms:
            out.append((kind, ms))

    # registers and what they are written with (one line each: `r <= expr;`)
    writes: dict[str, list[str]] = {}
    for code in codes:
        m = re.match(r"^\s*(?:if\s*\(.*\)\s*|else\s+)?([A-Za-z_]\w*)\s*<=\s*(.+?);\s*$", code)
        if m:
            writes.setdefault(m.group(1), []).append(m.group(2).strip())

    def constant(e: str) -> bool:
        return bool(re.fullmatch(r"[\d'sSbBoOdDhH_0-9a-fA-F{}\s]*|\{\s*\w+\s*\{[^}]*\}\s*\}", e))

    for li, code in enumerate(codes):
        if not code.strip():
            continue
        # a for loop's increment clause is not mutated (a loop that never ends is not a bug of the design)
        fm = re.search(r"\bfor\s*\(([^;]*;[^;]*;)", code)
        if fm:
            k = fm.end()
            close = code.find(")", k)
            code = code[:k] + " " * ((close if close >= 0 else len(code)) - k) + code[(close if close >= 0 else len(code)):]
        # a replication's count is a width (a sign extension's: a wider word truncated where it is
        # assigned), like a declaration's: not mutated
        code = REPL.sub(lambda m: m.group(0)[:m.start(1) - m.start(0)] + " " * len(m.group(1))
                        + m.group(0)[m.end(1) - m.start(0):], code)
        toks = [(t.group(0), t.start()) for t in TOKEN.finditer(code)]
        depth = 0
        prev = None
        for ti, (t, c) in enumerate(toks):
            nxt = toks[ti + 1][0] if ti + 1 < len(toks) else ""
            operand_before = prev is not None and (re.match(r"[\w$']", prev[-1]) is not None or prev in (")", "]", "}"))
            if t in "([{" and len(t) == 1:
                depth += 1
            elif t in ")]}" and len(t) == 1:
                depth -= 1
            elif t in ("+", "-") and operand_before and nxt != ":":
                add("operator", li, c, t, ["-" if t == "+" else "+"])
            elif t in ("&", "|") and nxt != "=":
                add("operator", li, c, t, ["|" if t == "&" else "&"])
            elif t == "^":
                add("operator", li, c, t, ["|"])
            elif t in ("&&", "||"):
                add("operator", li, c, t, ["||" if t == "&&" else "&&"])
            elif t in ("==", "!="):
                add("comparison", li, c, t, ["!=" if t == "==" else "=="])
            elif t in ("<", ">"):
                add("comparison", li, c, t, [t + "="])
            elif t == ">=" or (t == "<=" and depth > 0):
                add("comparison", li, c, t, [t[0]])
            elif t in ("<<", ">>", ">>>", "<<<"):
                j = _operand_end(code, c + len(t))
                if j is not None:
                    k = c + len(t)
                    amt = raws[li][k:j]
                    a = amt.strip()
                    lead = amt[:len(amt) - len(amt.lstrip())]
                    if re.fullmatch(r"\d+", a):
                        news = [f"{lead}{int(a) + 1}"] + ([f"{lead}{int(a) - 1}"] if int(a) > 0 else [])
                    else:
                        news = [f"{lead}({a} + 1)", f"{lead}({a} - 1)"]
                    add("shift", li, k, amt, news)
            elif "'" in t and SIZED.match(t):
                add("constant", li, c, t, _flip_sized(t))
            elif re.fullmatch(r"\d[\d_]*", t) and prev != "#" and "'" not in nxt:
                v = int(t.replace("_", ""))
                add("constant", li, c, t, [str(v ^ (1 << b)) for b in range(max(1, v.bit_length()))])
            prev = t
        # a register stage skipped: `a <= b;` with b a register written once with a non-constant `b <= e;`
        m = re.match(r"^(\s*(?:if\s*\(.*\)\s*|else\s+)?[A-Za-z_]\w*\s*<=\s*)([A-Za-z_]\w*)\s*;\s*$", code)
        if m:
            src_reg = m.group(2)
            es = [e for e in writes.get(src_reg, []) if not constant(e)]
            if len(es) == 1 and not re.search(rf"\b{src_reg}\b", es[0]):
                add("stage", li, m.start(2), src_reg, [f"({es[0]})"])
    return out


def all_sites(files=None) -> list[tuple[str, list[Mutant]]]:
    """Every site of rtl/ (or of `files`): (kind, its mutants); each mutant's id unique (Mutant.dup)."""
    out = []
    for p in sorted(RTL.glob("*.v")):
        if files and p.name not in files:
            continue
        out += sites(p.name, p.read_text())
    seen: dict[str, int] = {}
    for i, (kind, alts) in enumerate(out):
        fixed = []
        for m in alts:
            n = seen.get(m.id, 0)
            seen[m.id] = n + 1
            fixed.append(replace(m, dup=n) if n else m)
        out[i] = (kind, fixed)
    return out


def draw(site_list, seed: int):
    """Mutants in the seeded order: a kind (by WEIGHTS) among those with sites left, a site of it
    (without replacement), one of its alternatives."""
    r = random.Random(seed)
    by_kind = {k: [alts for kk, alts in site_list if kk == k] for k in KINDS}
    by_kind = {k: v for k, v in by_kind.items() if v}
    while by_kind:
        ks = sorted(by_kind)
        k = r.choices(ks, weights=[WEIGHTS[x] for x in ks])[0]
        alts = by_kind[k].pop(r.randrange(len(by_kind[k])))
        if not by_kind[k]:
            del by_kind[k]
        yield r.choice(alts)


# --------------------------------------------------------------------------- the configurations


def frame_configs(work: Path) -> dict[str, str]:
    """{name: what sim.frame's --config takes}: the named configurations a mutant's frame may run
    on, in order, and the variants that reach the rest of rtl/ (compact on two noise units, compact
    with four terms so that marble's four use every one (k_used = K on folded units: 00d3bc02),
    filter mip and none, fpga_regs, sub-pixel samples: compact with 4, reduced with 2), written to
    configuration files under work/."""
    out = {n: n for n in ("full", "compact", "reduced", "full_fc")}
    full, compact = load_config("full"), load_config("compact")
    for name, cfg in (("compact_u2", variant(compact, "compact_u2", noise_units=2)),
                      ("compact_k4", variant(compact, "compact_k4", noise_terms=4)),
                      ("full_mip", variant(full, "full_mip", filter="mip")),
                      ("full_none", variant(full, "full_none", filter="none")),
                      ("compact_fpga", variant(compact, "compact_fpga", fpga_regs=True)),
                      ("compact_s4", variant(compact, "compact_s4", samples=4)),
                      ("reduced_s2", variant(load_config("reduced"), "reduced_s2", samples=2))):
        p = work / "configs" / f"{name}.toml"
        p.parent.mkdir(parents=True, exist_ok=True)
        text = config_toml(cfg)
        if not p.exists() or p.read_text() != text:
            p.write_text(text)
        out[name] = str(p)
    return out


def _normalized_hash(text: str, rtl: Path) -> str:
    """The compiled design's hash: addresses numbered in order, the rtl directory's path dropped."""
    ids: dict[str, str] = {}
    text = text.replace(str(rtl), "RTL")
    text = re.sub(r"0x[0-9a-f]{6,}", lambda m: ids.setdefault(m.group(0), f"@{len(ids)}"), text)
    return hashlib.sha256(text.encode()).hexdigest()


def compile_vvp(rtl: Path, top: str, files: list, vvp: Path, params: dict | None = None) -> tuple[bool, str]:
    """Icarus-compile `top` from `files` (names in `rtl`, or absolute paths) with the top's
    parameters `params`; (ok, the compiled design's text) or (False, the first error line)."""
    ok, log = elaborate(top, files, params or {}, rtl=rtl, out=vvp)
    if not ok:
        return False, (log.splitlines() or ["?"])[0]
    text = vvp.read_text()
    vvp.unlink()
    return True, text


def compile_top(rtl: Path, config: str, vvp: Path) -> tuple[bool, str]:
    """Icarus-compile texture_unit of `config` from `rtl`; (ok, the compiled design normalized:
    addresses numbered in order, the rtl directory's path dropped)."""
    gdir = gen_dir(config_of(config))
    ok, text = compile_vvp(rtl, "texture_unit", [*sorted(rtl.glob("*.v")), gdir / "texture_unit.v"], vvp)
    return (True, _normalized_hash(text, rtl)) if ok else (False, text)


def declared_params(module: str) -> list[str]:
    """The parameters rtl/<module>.v declares (one a line, the project's style; not its localparams)."""
    f = RTL / f"{module}.v"
    if not f.is_file():
        return []
    return re.findall(r"^\s*parameter\s+(?:(?:integer|signed|\[[^\]]*\])\s+)*([A-Za-z_]\w*)", f.read_text(), re.M)


def _literal(bits: str, signed: bool) -> str:
    """A Verilog literal of a compiled parameter's value (Icarus's C4<bits>, + when signed)."""
    v = int(bits, 2)
    if len(bits) <= 32 and not (signed and bits[0] == "1"):
        return str(v)
    if signed and len(bits) <= 32:
        return str(v - (1 << len(bits)))
    return f"{len(bits)}'{'s' if signed else ''}b{bits}"


def instance_params(vvp_text: str) -> dict[str, list[dict[str, str]]]:
    """{module: [its parameters' values, one dict per instance]} of a compiled design: the
    parameters each rtl/ module declares (not its localparams), as Verilog literals."""
    out: dict[str, list[dict[str, str]]] = {}
    names: dict[str, list[str]] = {}
    cur: dict | None = None
    for line in vvp_text.split("\n"):
        sm = re.search(r'\.scope (\w+), "[^"]*" "(\w+)"', line)
        if sm:
            cur = None
            if sm.group(1) == "module":
                mod = sm.group(2)
                if mod not in names:
                    names[mod] = declared_params(mod)
                cur = {"module": mod, "values": {}}
                out.setdefault(mod, []).append(cur["values"])
            continue
        pm = re.search(r'\.param/\w+ "(\w+)" .*, (\+?)C4<([01]+)>;', line)
        if pm and cur is not None and pm.group(1) in names[cur["module"]]:
            cur["values"][pm.group(1)] = _literal(pm.group(3), pm.group(2) == "+")
    return out


# --------------------------------------------------------------------------- one mutant


def source_hash(*paths: Path) -> str:
    h = hashlib.sha256()
    for base in paths:
        files = [base] if base.is_file() else sorted(p for p in base.rglob("*") if p.is_file()
                                                     and "__pycache__" not in p.parts and p.suffix in (".py", ".v", ".vh", ".cpp"))
        for p in files:
            h.update(str(p.relative_to(ROOT)).encode() + b"\0" + p.read_bytes())
    return h.hexdigest()[:16]


@dataclass
class Opts:
    scenes: tuple = ("marble", "zone_plate")
    size: int = 16
    seed: int = 1
    timeout: int = TIMEOUT
    keep: bool = False
    configs: dict = field(default_factory=dict)      # name -> --config argument
    baseline: dict = field(default_factory=dict)     # name -> compiled-design hash of rtl/
    instances: dict = field(default_factory=dict)    # name -> modules instantiated
    params: dict = field(default_factory=dict)       # name -> {module: [parameter values of each instance]}
    tce_timeout: int = TCE_TIMEOUT                   # seconds of Yosys per mutant (0: no TCE check)
    tb_sets: dict = field(default_factory=dict)      # module -> its testbenches' builds (tce_builds)
    lock: threading.Lock = field(default_factory=threading.Lock)


def _run(cmd, env, timeout, log: Path) -> tuple[str, int, str]:
    """('ok'|'fail'|'timeout', returncode, output) of a subprocess, its output to log."""
    try:
        r = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired as e:
        out = (e.stdout or b"").decode(errors="replace") if isinstance(e.stdout, bytes) else (e.stdout or "")
        log.write_text(out)
        return "timeout", -1, out
    out = r.stdout + r.stderr
    log.write_text(out)
    return ("ok" if r.returncode == 0 else "fail"), r.returncode, out


def testbenches(module: str) -> list[Path]:
    """tb/<module>/, or, for a module without one, the testbenches that build it (a test file of
    tb/ whose sources name "<module>.v"); [] when none does (the frames alone test it)."""
    own = ROOT / "tb" / module
    if own.is_dir():
        return [own]
    return sorted({p.parent for p in (ROOT / "tb").glob("*/test_*.py") if f'"{module}.v"' in p.read_text()})


# --------------------------------------------------------------------------- TCE: equivalence proved by Yosys

# Run as a command (`python -c`, cwd the checkout, SIM=icarus): the testbenches' pytest cases with
# hdlbuild.run replaced by a recorder, so that every case's build (top, sources, parameters) is
# listed without simulating anything; the list is printed as the last line, JSON.
_RECORD_BUILDS = """
import json, sys
import pytest
import hdlbuild
builds = []
def record(toplevel, sources, test_module, sim, config, extra_env=None, parameters=None, test_dir=None,
           build_name=None):
    cfg = hdlbuild.config_of(config)
    if parameters is None:
        parameters = hdlbuild.block_params(cfg, toplevel)
    builds.append({"name": build_name or cfg.name, "top": toplevel, "sources": [str(x) for x in sources],
                   "params": {k: (int(v) if isinstance(v, bool) else v) for k, v in parameters.items()}})
hdlbuild.run = record
pytest.main(["-q", "-p", "no:cacheprovider", "-p", "no:randomly", *sys.argv[1:]])
print(json.dumps(builds))
"""


def module_files(module: str) -> list[str]:
    """rtl/<module>.v and the files of the rtl/ modules it instantiates, transitively."""
    mods = {p.stem for p in RTL.glob("*.v")}
    seen, todo = [], [module]
    while todo:
        mod = todo.pop()
        if mod in seen or mod not in mods:
            continue
        seen.append(mod)
        text = re.sub(r"//[^\n]*|/\*.*?\*/", " ", (RTL / f"{mod}.v").read_text(), flags=re.S)
        for name in re.findall(r"^\s*([A-Za-z_]\w*)\s*(?:#\s*\(|[A-Za-z_]\w*\s*\()", text, re.M):
            if name in mods and name not in seen:
                todo.append(name)
    return [f"{x}.v" for x in seen]


def tce_builds(module: str, opts: Opts, work: Path) -> list[dict]:
    """The builds of the module's testbenches (each Icarus case: name, top, sources, parameters),
    each with its unmutated compile (hash) and the parameter sets of the module's instances in it
    (sets); recorded once a run (cheap: no simulation)."""
    with opts.lock:
        if module in opts.tb_sets:
            return opts.tb_sets[module]
    tbs = testbenches(module)
    builds = []
    if tbs:
        env = dict(os.environ, SIM="icarus", PYTHONPATH=str(ROOT))
        for k in ("CONFIG", "VECTORS", "WAVES", "RANDOM_CONFIGS", "RANDOM_SEED", "RTL_DIR"):
            env.pop(k, None)
        r = subprocess.run([sys.executable, "-c", _RECORD_BUILDS, *(str(tb.relative_to(ROOT)) for tb in tbs)],
                           cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
        lines = r.stdout.strip().splitlines()
        try:
            builds = json.loads(lines[-1]) if lines else []
        except json.JSONDecodeError:
            builds = []
        if not builds:
            raise RuntimeError(f"tce: no builds recorded for {module}'s testbenches: {(r.stderr or r.stdout)[-300:]}")
        tmp = work / "baseline"
        tmp.mkdir(parents=True, exist_ok=True)
        for i, b in enumerate(builds):
            ok, text = compile_vvp(RTL, b["top"], b["sources"], tmp / f"{module}-{threading.get_ident()}-{i}.vvp", b["params"])
            if not ok:
                raise RuntimeError(f"tce: testbench build {b['top']} {b['name']} does not compile: {text}")
            b["hash"] = _normalized_hash(text, RTL)
            b["sets"] = instance_params(text).get(module, [])
    with opts.lock:
        opts.tb_sets[module] = builds
    return builds


def _chparams(params: dict) -> str:
    return " ".join(f"-chparam {k} {v}" for k, v in sorted(params.items()))


def loop_temporaries(rtl: Path, files: list[str]) -> list[str]:
    """The names the files declare `integer`: loop counters and temporaries (a procedural loop's
    counter ends one past its last iteration, so a loop bound loosened changes it even where every
    write of the extra iteration is dropped)."""
    names = []
    for f in files:
        text = re.sub(r"//[^\n]*|/\*.*?\*/", " ", (rtl / f).read_text(), flags=re.S)
        for decl in re.findall(r"\binteger\s+([^;]+);", text):
            names += [m.group(1) for part in decl.split(",") if (m := re.match(r"\s*([A-Za-z_]\w*)", part))]
    return names


def yosys_equiv(gold: Path, gate: Path, module: str, files: list[str], params: dict, timeout: float,
                log: Path | None = None, recipes: tuple[str, ...] = tuple(RECIPES)) -> tuple[str, str, str]:
    """Is `module` from `gate` equivalent to the one from `gold` under `params`? Both elaborated
    alike (proc, flatten, opt -full, memory -nomap, then memory_map -rom-only -keepdc: a ROM's reads
    as logic the SAT solver sees, its x bits kept; the wires of loop_temporaries made private, so
    that equiv_make does not match them: a signal it does not match is neither a cut point nor a
    proof obligation, and the ports, never hidden, are all matched); equiv_make matches their
    signals by name (a $equiv cell on each pair), then each recipe in turn (RECIPES: equiv_struct merges what the two
    share, a $equiv cell left on each input it merges to prove), on a fresh copy: equiv_simple -seq 2
    proves what it can and, when at most INDUCT_MAX signal bits are left unproven, equiv_induct -seq 2
    the rest (undef states modelled in both: an x where the original has a value is a difference).
    Proved: one recipe leaves no $equiv cell unproven (equiv_status); a recipe that leaves some
    unproven hands over to the next, a timeout (the budget spent) or an error ends the check.
    ('proved' | 'not proved' | 'timeout' | 'error', a detail, the recipe that proved it or '')."""
    t0 = time.perf_counter()

    temps = sorted(set(loop_temporaries(gold, files)) | set(loop_temporaries(gate, files)))
    hide = f"rename -hide {' '.join(f'w:{n} w:*.{n}' for n in temps)}\n" if temps else ""

    def elab(rtl: Path, name: str) -> str:
        return (f"read_verilog -defer -I{rtl} {' '.join(str(rtl / f) for f in files)}\n"
                f"hierarchy -check -top {module} {_chparams(params)}\n"
                f"proc\nflatten\nopt -full\nmemory -nomap\nmemory_map -rom-only -keepdc\n{hide}opt_clean\n"
                f"rename -top {name}\ndesign -stash {name}\n")

    def yosys(script: str, tag: str) -> tuple[str, int] | None:
        left = timeout - (time.perf_counter() - t0)
        if left <= 0:
            return None
        try:
            r = subprocess.run(["yosys", "-p", script], capture_output=True, text=True, timeout=left)
        except subprocess.TimeoutExpired:
            return None
        out = r.stdout + r.stderr
        if log is not None:
            with open(log, "a") as f:
                f.write(f"#### {tag}\n{script}\n{out}\n")
        return out, r.returncode

    def step(script: str, tag: str, note: str = "") -> tuple[int, int] | tuple[str, str]:
        """(cells, unproven) of equiv_status after `script`, or the verdict that ends the check."""
        r = yosys(script, tag)
        if r is None:
            return "timeout", f"over {timeout:.0f} s{note}"
        out, rc = r
        found = re.findall(r"Found (\d+) \$equiv cells in equiv:\s*\n\s*Of those cells (\d+) are proven and (\d+) are "
                           r"unproven", out)
        if rc != 0 or not found:
            err = re.search(r"^ERROR: (.*)$", out, re.M)
            return "error", (err.group(1) if err else f"yosys exit {rc}")[:120]
        return int(found[-1][0]), int(found[-1][2])

    def prove(made: Path, recipe: str, il: Path) -> tuple[str, str]:
        note = f" ({recipe})"
        st = step(f"read_rtlil {made}\n{RECIPES[recipe]}\nequiv_simple -undef -seq 2\nequiv_status\nwrite_rtlil {il}\n",
                  f"{recipe}: equiv_struct, equiv_simple", note)
        if isinstance(st[0], str):
            return st
        cells, unproven = st
        if cells == 0:
            return "error", "no signals matched"
        if unproven == 0:
            return "proved", f"{cells} $equiv cells proven (equiv_simple)"
        if unproven > INDUCT_MAX:
            return "not proved", f"{unproven} of {cells} $equiv cells unproven by equiv_simple"
        st = step(f"read_rtlil {il}\nequiv_induct -undef -seq 2\nequiv_status\n", f"{recipe}: equiv_induct",
                  f" (equiv_induct, {recipe})")
        if isinstance(st[0], str):
            return st
        if st[1] == 0:
            return "proved", f"{st[0]} $equiv cells proven (equiv_induct)"
        return "not proved", f"{st[1]} of {st[0]} $equiv cells unproven by equiv_induct"

    with tempfile.TemporaryDirectory(prefix="tce-") as tmp:
        made = Path(tmp) / "made.il"
        st = step(elab(gold, "gold") + elab(gate, "gate")
                  + "design -copy-from gold -as gold gold\ndesign -copy-from gate -as gate gate\n"
                  f"equiv_make gold gate equiv\nhierarchy -top equiv\nasync2sync\nequiv_status\nwrite_rtlil {made}\n",
                  "elaborate, equiv_make", " (elaboration)")
        if isinstance(st[0], str):
            return st[0], st[1], ""
        if st[0] == 0:
            return "error", "no signals matched", ""
        tried = []
        for recipe in recipes:
            res, detail = prove(made, recipe, Path(tmp) / f"{recipe}.il")
            if res == "proved":
                return res, f"{detail} ({recipe})", recipe
            tried.append(f"{recipe}: {detail}")
            if res != "not proved":
                return res, "; ".join(tried), ""
        return "not proved", "; ".join(tried), ""


def tce_file(m: Mutant, candidates: list, cache: Path) -> Path:
    """The TCE verdict's cache file: keyed by the mutant, the mutated source, the sources it
    elaborates with (rtl/*.vh, the files of the modules it instantiates), the parameter sets, the recipe."""
    h = hashlib.sha256()
    h.update(json.dumps([TCE_RECIPE, m.apply((RTL / m.file).read_text()), candidates], sort_keys=True).encode())
    for p in [*sorted(RTL.glob("*.vh")), *(RTL / f for f in module_files(m.module))]:
        h.update(p.name.encode() + b"\0" + p.read_bytes())
    return cache / f"tce-{m.id}-{h.hexdigest()[:16]}.json"


def tce_check(m: Mutant, opts: Opts, work: Path, changed: list[str], rtl: Path | None = None) -> dict:
    """Trivial Compiler Equivalence with Yosys as the compiler: is the mutated module equivalent to
    the original under every parameter set it is elaborated with by a compile the mutation changes?
    Those compiles: the configurations `changed` (the screen's: their Icarus compile differs) and the
    module's testbench builds whose Icarus compile differs. A compile that does not differ is the same
    design (nothing to prove); when none differs the mutation is in code no checked compile elaborates
    and nothing is proved ('unchanged', kept: a parameter set no one checked may reach it).
    {'result': 'proved' | 'not proved' | 'timeout' | 'error' | 'unchanged' | 'off', 'sets': [{params,
    from}], 'detail', 'seconds'}; cached (out/mutants/cache/tce-*.json)."""
    t0 = time.perf_counter()
    if opts.tce_timeout <= 0:
        return {"result": "off", "sets": [], "detail": "", "seconds": 0.0}
    builds = tce_builds(m.module, opts, work)
    candidates = []  # (from, params, where it comes from: a configuration or a testbench build)
    for name in opts.configs:
        for ps in opts.params.get(name, {}).get(m.module, []):
            candidates.append([name, ps, "config"])
    for b in builds:
        for ps in b["sets"]:
            candidates.append([f"tb {b['top']} {b['name']}", ps, "tb"])
    cache = work / "cache"
    cache.mkdir(parents=True, exist_ok=True)
    cf = tce_file(m, [[c[0], c[1]] for c in candidates] + [sorted(changed)], cache)
    if cf.exists():
        rec = json.loads(cf.read_text())
        if rec["result"] != "timeout" or rec.get("limit", 0) >= opts.tce_timeout:
            return {**rec, "cached": True}
    own = rtl is None
    if own:
        rtl = scratch_rtl(m, work / "run" / f"{m.id}-tce")
    wdir = rtl.parent
    try:
        sets: dict[str, dict] = {}  # the parameter sets to prove on: json -> {params, from}
        for name, ps, kind in candidates:
            if kind == "config" and name in changed:
                src = sets.setdefault(json.dumps(ps, sort_keys=True), {"params": ps, "from": []})["from"]
                src += [name] if name not in src else []
        for i, b in enumerate(builds):
            ok, text = compile_vvp(rtl, b["top"], b["sources"], wdir / f"tce-{i}.vvp", b["params"])
            if not ok:  # the testbench's build fails: not equivalent (its test kills it)
                return _tce_done(cf, t0, "not proved", [], f"testbench build {b['name']} does not compile")
            if _normalized_hash(text, rtl) != b["hash"]:
                for ps in b["sets"]:
                    sets.setdefault(json.dumps(ps, sort_keys=True), {"params": ps, "from": []})["from"].append(
                        f"tb {b['top']} {b['name']}")
        todo = [sets[k] for k in sorted(sets)]
        if not todo:
            return _tce_done(cf, t0, "unchanged", [], "no compile differs: the mutated code is in no checked design")
        files = module_files(m.module)
        for i, st in enumerate(todo):
            left = opts.tce_timeout - (time.perf_counter() - t0)
            res, detail, st["recipe"] = yosys_equiv(RTL, rtl, m.module, files, st["params"], left,
                                                    (wdir / f"tce-{i}.log") if opts.keep else None)
            if res != "proved":
                return _tce_done(cf, t0, res, todo[:i + 1],
                                 f"{detail} on {', '.join(st['from'][:3])} (set {i + 1} of {len(todo)})",
                                 limit=opts.tce_timeout)
        by = {r: sum(st["recipe"] == r for st in todo) for r in RECIPES}
        return _tce_done(cf, t0, "proved", todo, f"{len(todo)} parameter sets ("
                         + ", ".join(f"{n} by {r}" for r, n in by.items() if n) + ")",
                         recipe="+".join(r for r, n in by.items() if n))
    finally:
        if own and not opts.keep:
            shutil.rmtree(wdir, ignore_errors=True)


def _tce_done(cf: Path, t0: float, result: str, sets: list, detail: str, limit: int = 0, recipe: str = "") -> dict:
    """The TCE verdict, cached (a timeout with its limit: a rerun with a longer one tries again; a
    proof with the recipes that proved its sets, each set's in its 'recipe')."""
    rec = {"result": result, "sets": sets, "detail": detail, "seconds": round(time.perf_counter() - t0, 1),
           **({"limit": limit} if result == "timeout" else {}), **({"recipe": recipe} if recipe else {})}
    cf.write_text(json.dumps(rec, indent=1))
    return rec


def scratch_rtl(m: Mutant, wdir: Path) -> Path:
    """A fresh copy of rtl/ under wdir with the mutation applied: its path (wdir/rtl)."""
    if wdir.exists():
        shutil.rmtree(wdir)
    rtl = wdir / "rtl"
    rtl.mkdir(parents=True)
    for p in RTL.iterdir():
        if p.is_file():
            shutil.copy2(p, rtl / p.name)
    (rtl / m.file).write_text(m.apply((RTL / m.file).read_text()))
    return rtl


def screen(m: Mutant, opts: Opts, rtl: Path) -> tuple[list[str], int, list[str]]:
    """Compile every configuration that instantiates the module from the mutated copy `rtl`: the
    configurations whose compiled design differs (the frames run on them), how many compiled, the
    errors of those that did not."""
    changed, compiled, errors = [], 0, []
    for name, arg in opts.configs.items():
        if m.module not in opts.instances[name]:
            continue
        ok, h = compile_top(rtl, arg, rtl.parent / f"{name}.vvp")
        if not ok:
            errors.append(f"{name}: {h}".replace(f"{rtl}/", "rtl/"))
            continue
        compiled += 1
        if h != opts.baseline[name]:
            changed.append(name)
    return changed, compiled, errors


def run_mutant(m: Mutant, opts: Opts, work: Path, tb_passed: bool = False) -> dict:
    """Screen, then test one mutant; its result record. tb_passed: the block's testbench is known
    to pass on it (a survivor cached under the same sources): only the frames run."""
    t0 = time.perf_counter()
    wdir = work / "run" / m.id
    rtl = scratch_rtl(m, wdir)
    rec = {**asdict(m), "id": m.id, "mutation": m.describe(), "module": m.module}
    changed, compiled, errors = screen(m, opts, rtl)
    if errors and not compiled:
        rec.update(result="stillborn", by=f"does not compile ({errors[0]})", seconds=round(time.perf_counter() - t0, 1))
        _cleanup(wdir, opts)
        return rec
    if errors:  # elaborates in some configurations only: any testbench building the others fails
        rec.update(result="killed", by=f"elaboration ({errors[0]})", seconds=round(time.perf_counter() - t0, 1))
        _cleanup(wdir, opts)
        return rec
    rec["frame_configs"] = changed
    # TCE: a mutant Yosys proves equivalent to the original on every parameter set the changed
    # compiles elaborate it with is dropped before its tests (not counted, like a stillborn one)
    rec["tce"] = tce_check(m, opts, work, changed, rtl)
    if rec["tce"]["result"] == "proved":
        rec.update(result="equivalent", by="proved equivalent by Yosys (TCE)", seconds=round(time.perf_counter() - t0, 1))
        _cleanup(wdir, opts)
        return rec
    env = dict(os.environ, RTL_DIR=str(rtl), SIM="icarus", SEED=str(opts.seed), PYTHONPATH=str(ROOT))
    for k in ("CONFIG", "VECTORS", "WAVES", "RANDOM_CONFIGS", "RANDOM_SEED"):
        env.pop(k, None)
    tbs = testbenches(m.module)
    rec["tb"] = "passed" if tbs else "none"
    if tbs and not tb_passed:
        st, rc, out = _run([sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider", "-p", "no:randomly",
                            *(str(tb.relative_to(ROOT)) for tb in tbs)], env, opts.timeout, wdir / "tb.log")
        if st != "ok" and rc != 5:
            failed = re.findall(r"^FAILED (\S+)", out, re.M)
            by = failed[0] if failed else (f"tb/{m.module} (timeout)" if st == "timeout" else
                                             f"tb/{m.module} (exit {rc})")
            rec.update(result="killed", by=by, seconds=round(time.perf_counter() - t0, 1))
            _cleanup(wdir, opts)
            return rec
    for name in changed:  # a frame of each scene on each configuration the mutation changes
        for scene in opts.scenes:
            fout = wdir / "frame"
            st, rc, out = _run([sys.executable, "-m", "sim.frame", "--scene", scene, "--config",
                                opts.configs[name], "--sim", "icarus", "--size", str(opts.size), "--out", str(fout),
                                "--quiet"], env, opts.timeout, wdir / "frame.log")
            if st != "ok":
                what = "timeout" if st == "timeout" else (
                    "pixels differ" if "pixels differ" in out else
                    (out.strip().splitlines() or ["?"])[-1][:80])
                rec.update(result="killed", by=f"frame {scene} {name} {opts.size}px ({what})",
                           seconds=round(time.perf_counter() - t0, 1))
                _cleanup(wdir, opts)
                return rec
    rec.update(result="survived", by=("" if changed else "no frame: no named configuration's compiled design changes"),
               seconds=round(time.perf_counter() - t0, 1))
    _cleanup(wdir, opts)
    return rec


def _cleanup(wdir: Path, opts: Opts) -> None:
    if not opts.keep:
        shutil.rmtree(wdir, ignore_errors=True)


# --------------------------------------------------------------------------- the run


def prepare(work: Path, opts: Opts) -> None:
    """The frame configurations, the unmutated compile of each and the modules it instantiates."""
    opts.configs = frame_configs(work)
    tmp = work / "baseline"
    tmp.mkdir(parents=True, exist_ok=True)
    for name, arg in opts.configs.items():
        ok, text = compile_vvp(RTL, "texture_unit", [*sorted(RTL.glob("*.v")), gen_dir(config_of(arg)) / "texture_unit.v"],
                               tmp / f"{name}.vvp")
        if not ok:
            raise RuntimeError(f"rtl/ does not compile for {name}: {text}")
        opts.baseline[name] = _normalized_hash(text, RTL)
        opts.params[name] = instance_params(text)
        opts.instances[name] = set(opts.params[name])


def tb_imports(tbs: list[Path]) -> list[Path]:
    """The other testbenches whose code the testbenches `tbs` import (`from tb.<name>...`:
    shared stimulus or sets), transitively: their stimulus is the testbenches' too."""
    seen: set[Path] = set(tbs)
    todo = list(tbs)
    while todo:
        for f in sorted(todo.pop().glob("*.py")):
            for name in re.findall(r"^\s*(?:from|import)\s+tb\.(\w+)", f.read_text(), re.M):
                d = ROOT / "tb" / name
                if d.is_dir() and d not in seen:
                    seen.add(d)
                    todo.append(d)
    return sorted(seen - set(tbs))


def cache_file(m: Mutant, cache: Path) -> Path:
    """The mutant's record under the sources its verdict depends on: the mutated file, rtl/*.vh,
    tb/pipe.py, sim/, the block's testbenches and the testbenches they import."""
    tbs = testbenches(m.module)
    deps = [RTL / m.file, *sorted(RTL.glob("*.vh")), ROOT / "tb" / "pipe.py", ROOT / "sim", *tbs, *tb_imports(tbs)]
    return cache / f"{m.id}-{source_hash(*deps)}.json"


def opts_key(opts: Opts) -> str:
    """What a survivor's verdict also depends on (a kill stands whatever the frames are)."""
    return json.dumps([list(opts.scenes), opts.size, opts.seed, opts.timeout, list(opts.configs)])


def run_all(n: int, seed: int, jobs: int, files, opts: Opts, work: Path, progress: bool = True) -> list[dict]:
    """Draw and run mutants until n of them are not stillborn; their records in drawn order."""
    site_list = all_sites(files)
    if not site_list:
        raise UserError(f"--files {','.join(files or [])}: no mutation sites")
    prepare(work, opts)
    cache = work / "cache"
    cache.mkdir(parents=True, exist_ok=True)
    gen = draw(site_list, seed)
    results: dict[int, dict] = {}
    valid = 0
    bar = progress_bar(progress, total=n, desc="mutants", unit="mutant")
    lock = threading.Lock()

    def one(i, m):
        cf = cache_file(m, cache)
        if cf.exists():
            rec = json.loads(cf.read_text())
            if rec["result"] in ("killed", "survived") and "frame_configs" in rec:  # compiled everywhere: TCE first
                rec["tce"] = tce_check(m, opts, work, rec["frame_configs"])
                if rec["tce"]["result"] == "proved" and rec["result"] == "survived":
                    return i, {**rec, "result": "equivalent", "by": "proved equivalent by Yosys (TCE)", "cached": True}
                # proved, yet killed: a test tells them apart, the kill stands (the report names the conflict)
            if rec["result"] != "survived" or rec.get("opts") == opts_key(opts):
                return i, {**rec, "cached": True}
            # a survivor of other frames: its testbench passed under these sources, the frames run again
            rec = {**run_mutant(m, opts, work, tb_passed=rec.get("tb") == "passed"), "opts": opts_key(opts)}
        else:
            rec = {**run_mutant(m, opts, work), "opts": opts_key(opts)}
        if rec["result"] != "equivalent":  # a TCE verdict is cached on its own (tce_file)
            cf.write_text(json.dumps(rec, indent=1))
        return i, rec

    with ThreadPoolExecutor(max_workers=max(1, jobs)) as ex:
        pending = set()
        i = 0
        exhausted = False
        while True:
            while not exhausted and valid + len(pending) < n:
                m = next(gen, None)
                if m is None:
                    exhausted = True
                    break
                pending.add(ex.submit(one, i, m))
                i += 1
            if not pending:
                break
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for f in done:
                k, rec = f.result()
                with lock:
                    results[k] = rec
                    if rec["result"] not in ("stillborn", "equivalent"):
                        valid += 1
                        bar.update()
                        bar.set_postfix(killed=sum(r["result"] == "killed" for r in results.values()))
    bar.close()
    return [results[k] for k in sorted(results)]


def summarize(recs: list[dict]) -> dict:
    counted = [r for r in recs if r["result"] not in ("stillborn", "equivalent")]
    killed = [r for r in counted if r["result"] == "killed"]
    surv = [r for r in counted if r["result"] == "survived"]
    equiv = [r for r in surv if r["id"] in EQUIVALENT]
    noted = [r for r in surv if r["id"] in OPEN]
    by_kind = {}
    for k in KINDS:
        rs = [r for r in counted if r["kind"] == k]
        by_kind[k] = {"mutants": len(rs), "killed": sum(r["result"] == "killed" for r in rs)}
    n = len(counted)
    tce = [r for r in recs if r["result"] == "equivalent"]
    return {"drawn": len(recs), "mutants": n, "killed": len(killed), "survived": len(surv), "equivalent": len(equiv),
            "open": len(noted), "unexplained": len(surv) - len(equiv) - len(noted),
            "stillborn": sum(r["result"] == "stillborn" for r in recs), "tce_dropped": len(tce),
            "tce_conflicts": sum(r["result"] == "killed" and r.get("tce", {}).get("result") == "proved" for r in recs),
            "killed_share": round(len(killed) / n, 4) if n else None,
            "score": round(len(killed) / (n - len(equiv)), 4) if n - len(equiv) else None,
            "by_kind": by_kind}


def _cell(s: str) -> str:
    return re.sub(r"/\S*?/run/\w+/rtl/", "rtl/", str(s)).replace("|", "\\|")


def section(recs: list[dict], s: dict, args: dict, seconds: float) -> str:
    """The "## Mutants" section of docs/verification.md."""
    cmd = f"make mutants N={args['n']} SEED={args['seed']}"
    borrowed = "; ".join(f"{p.stem} ({', '.join(str(tb.relative_to(ROOT)) for tb in testbenches(p.stem))})"
                         for p in sorted(RTL.glob("*.v"))
                         if not (ROOT / "tb" / p.stem).is_dir() and testbenches(p.stem)) or "none"
    L = ["## Mutants", "",
         f"Written by `{cmd}` (verify/mutants.py; JOBS={args['jobs']}, {seconds / 60:.1f} min on this machine's "
         f"2 cores, {sum(bool(r.get('cached')) for r in recs)} of the {len(recs)} drawn mutants' verdicts from the cache "
         f"of earlier runs; the mutants' own times add up to {sum(r['seconds'] for r in recs) / 60:.0f} min, what a run "
         "with an empty cache, `rm -r out/mutants/cache`, takes with JOBS=1). "
         f"{s['mutants']} seeded single mutations of rtl/ (kinds: an operator swapped, a constant bit flipped, "
         "a comparison loosened or tightened, a register stage skipped, a shift amount off by one; only live lines: "
         "no comments, `ifdef FORMAL` blocks, declarations or latency checks), each in a scratch copy of rtl/, run "
         f"against the mutated block's testbench (tb/<module>/, every Icarus case, stopping at the first failure; "
         f"a module without one against the testbenches that build it: {borrowed}) "
         f"and then, if it passed, small frames ({', '.join(args['scenes'])} at {args['size']}x{args['size']}, Icarus, "
         "every pixel against the golden model) on each configuration whose compiled design the mutation changes "
         "(full, compact, reduced, full_fc and the variants compact on two noise units, compact with four terms, full "
         "with filter mip and none, compact with fpga_regs), until one fails. The first failing test is named.", "",
         "Before its tests, a mutant that compiles everywhere is checked for Trivial Compiler Equivalence (TCE, "
         "Papadakis et al., ICSE 2015) with Yosys as the compiler, proved rather than argued: on every compile the "
         "mutation changes (a configuration above, or a build of the block's testbench, each under Icarus; a compile "
         "that does not change is the same design), the mutated module and the original are elaborated under each "
         "parameter set its instances there have (`hierarchy -chparam`, `proc; flatten; opt -full; memory -nomap; "
         "memory_map -rom-only -keepdc`, the `integer` loop temporaries' wires hidden from `equiv_make`: a loop bound "
         "loosened leaves its counter one higher, which no output sees) and proved equal: `equiv_make`, then "
         "`equiv_struct -icells` (the logic both share merged, a `$equiv` cell on each merged input), "
         "`equiv_simple -undef -seq 2` and, when it leaves at most "
         f"{INDUCT_MAX} signal bits unproven, `equiv_induct -undef -seq 2` (undef states modelled: an x where the "
         "original has a value is a difference), no `$equiv` cell left unproven (`equiv_status`); when that leaves "
         "some unproven, the same with the registers merged only (`equiv_struct -icells t:$equiv t:$*dff*`: "
         "`-icells` alone leaves unprovable `$equiv` cells in tex_regs, fc_weight and filter_width even unmutated); "
         "within "
         f"{args.get('tce_timeout', TCE_TIMEOUT)} s a mutant. Proved on every one, the mutant is dropped: not counted "
         "among the N, like a stillborn one the next draw takes its place, and listed below with the parameter sets. "
         "Not proved (a difference, a timeout, an error), or no compile differs (the mutated code is in no design a "
         "checked parameter set elaborates: nothing proved, a parameter set nobody checked may reach it), the "
         "mutant runs its tests.", "",
         f"**Killed: {s['killed']} of {s['mutants']} ({100 * s['killed_share']:.1f}%)**, the raw share; "
         f"{s['drawn']} drawn: {s['tce_dropped']} proved equivalent by Yosys (TCE, dropped and replaced)"
         + (f", {s['stillborn']} did not compile (stillborn, replaced)" if s['stillborn'] else "")
         + f"; survived {s['survived']}, of which {s['equivalent']} argued equivalent and {s['open']} open (below); "
         f"score without the argued ones {100 * s['score']:.1f}%"
         + (f"; {s['tce_conflicts']} proved equivalent by Yosys yet killed by a test (the kill counted; named below)."
            if s['tce_conflicts'] else "."), "",
         "| kind | mutants | killed |", "|---|---:|---:|"]
    for k, v in s["by_kind"].items():
        L.append(f"| {k} | {v['mutants']} | {v['killed']} |")
    L += ["", "| id | file:line | kind | mutation | result | killed by |", "|---|---|---|---|---|---|"]
    for r in recs:
        if r["result"] == "stillborn":
            continue
        res = ("dropped: proved equivalent (TCE)" if r["result"] == "equivalent" else
               r["result"] + (" (equivalent)" if r["result"] == "survived" and r["id"] in EQUIVALENT else
                              " (open)" if r["result"] == "survived" and r["id"] in OPEN else ""))
        L.append(f"| {r['id']} | {r['file']}:{r['line']} | {r['kind']} | {_cell(r['mutation'])} | {res} | {_cell(r['by'])} |")
    tce = [r for r in recs if r["result"] == "equivalent"]
    if tce:
        L += ["", "Proved equivalent by Yosys (TCE), each on the parameter sets of its module's instances in the "
              "compiles the mutation changes (where from):", ""]
        for r in tce:
            sets = "; ".join(f"{_pset(x['params'])} ({', '.join(dict.fromkeys(x['from']))})" for x in r["tce"]["sets"])
            L.append(f"- {r['id']} {r['file']}:{r['line']} {_cell(r['mutation'])} in `{_cell(r['text'])}`: "
                     f"{len(r['tce']['sets'])} parameter sets: {_cell(sets)}")
    surv = [r for r in recs if r["result"] == "survived"]
    if surv:
        L += ["", "Survivors (TCE: what Yosys found):", ""]
        for r in surv:
            why = EQUIVALENT.get(r["id"]) or ("open: " + OPEN[r["id"]] if r["id"] in OPEN
                                              else "NOT EXPLAINED: needs a test or an equivalence argument")
            L.append(f"- {r['id']} {r['file']}:{r['line']} {_cell(r['mutation'])} in `{_cell(r['text'])}`: {why}"
                     f" (TCE: {_tce_note(r)})")
    conflicts = [r for r in recs if r["result"] == "killed" and r.get("tce", {}).get("result") == "proved"]
    if conflicts:
        L += ["", "Proved equivalent by Yosys yet killed (Yosys's semantics and Icarus's differ there; the kill counts):",
              ""]
        for r in conflicts:
            L.append(f"- {r['id']} {r['file']}:{r['line']} {_cell(r['mutation'])} in `{_cell(r['text'])}`: "
                     f"killed by {_cell(r['by'])}")
    L += ["", doc_stamp(["full", "compact", "reduced", "full_fc"])]
    return "\n".join(L) + "\n"


def _pset(ps: dict) -> str:
    """A parameter set, short: a long literal (a permutation table) by its width."""
    return " ".join(f"{k}={v if len(v) <= 16 else v.split(chr(39))[0] + '-bit table'}" for k, v in ps.items()) or "defaults"


def _tce_note(r: dict) -> str:
    t = r.get("tce") or {}
    res = t.get("result", "not run")
    return {"unchanged": "no compile differs, nothing to prove", "off": "off"}.get(
        res, f"{res}{': ' + t['detail'] if t.get('detail') else ''}")


def write_section(doc: Path, text: str) -> None:
    """Replace (or add) the "## Mutants" section of doc, keeping every other section."""
    old = doc.read_text() if doc.exists() else "# Verification\n\nWhat the tests prove beyond random vectors (issue 29).\n"
    lines = old.split("\n")
    start = next((i for i, x in enumerate(lines) if x.strip() == "## Mutants"), None)
    if start is None:
        new = old.rstrip("\n") + "\n\n" + text
    else:
        end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("## ")), len(lines))
        rest = "\n".join(lines[end:])
        new = "\n".join(lines[:start]).rstrip("\n") + "\n\n" + text + ("\n" + rest if rest.strip() else "")
    doc.parent.mkdir(parents=True, exist_ok=True)
    doc.write_text(new.lstrip("\n"))


def tce_only(ids: list[str], files, opts: Opts, work: Path) -> int:
    """--tce-only: screen each mutant (which configurations' compiles it changes) and run its TCE
    check alone (cached like a run's); one JSON line a mutant: id, module, result, recipe, seconds,
    detail (ids are unique: Mutant.dup)."""
    found = {m.id: m for _, alts in all_sites(files) for m in alts if m.id in ids}
    missing = [x for x in ids if x not in found]
    if missing:
        raise UserError(f"--tce-only: no mutant {', '.join(missing)} among the sites"
                        + (f" of {','.join(files)}" if files else ""))
    prepare(work, opts)
    for x in ids:
        m = found[x]
        wdir = work / "run" / f"{m.id}-tce-only"
        rtl = scratch_rtl(m, wdir)
        try:
            changed, compiled, errors = screen(m, opts, rtl)
            t = ({"result": "error", "detail": f"does not compile ({errors[0]})", "seconds": 0.0} if errors else
                 tce_check(m, opts, work, changed, rtl))
        finally:
            _cleanup(wdir, opts)
        print(json.dumps({"id": m.id, "module": m.module, "where": f"{m.file}:{m.line}", "mutation": m.describe(),
                          "result": t["result"], "recipe": t.get("recipe", ""), "seconds": t["seconds"],
                          "cached": t.get("cached", False), "sets": len(t.get("sets", [])), "detail": t["detail"]}),
              flush=True)
    return 0


def main(argv=None) -> int:
    ap = Parser(prog="mutants", description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100, help="mutants (not counting stillborn ones)")
    ap.add_argument("--seed", type=int, default=1, help="the draw's seed (also the testbenches' SEED)")
    ap.add_argument("--jobs", type=int, default=int(os.environ.get("JOBS", 2)), help="mutants run at once")
    ap.add_argument("--files", help="only these rtl/ files (comma-separated names, e.g. bitlen.v)")
    ap.add_argument("--scenes", default="marble,zone_plate", help="the frames' scenes (comma-separated)")
    ap.add_argument("--size", type=int, default=16, help="the frame's width")
    ap.add_argument("--timeout", type=int, default=TIMEOUT, help="seconds per test of a mutant")
    ap.add_argument("--tce-timeout", type=int, default=TCE_TIMEOUT,
                    help="seconds of Yosys's equivalence check per mutant (0: no check)")
    ap.add_argument("--out", type=Path, default=ROOT / "out" / "mutants", help="results.json, the cache, scratch copies")
    ap.add_argument("--docs", type=Path, help="write the Mutants section of this file (make mutants: docs/verification.md)")
    ap.add_argument("--list", action="store_true", help="print the drawn mutants and the site counts; run nothing")
    ap.add_argument("--report", action="store_true", help="rewrite --docs from OUT/results.json (the equivalence notes "
                    "as they are now); run nothing")
    ap.add_argument("--tce-only", metavar="ID[,ID...]", help="only the TCE check of these mutants (ids of any site "
                    "of --files), one JSON line each; runs no test and writes no docs")
    ap.add_argument("--keep", action="store_true", help="keep each mutant's scratch directory and logs")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    a.out = a.out.resolve()  # the scratch copies' paths are passed to Icarus whole (compile_vvp)

    def go():
        if a.n < 1:
            raise UserError(f"--n {a.n}: expected at least 1")
        if a.size < 1 or a.size > 1024:
            raise UserError(f"--size {a.size}: expected 1..1024")
        files = [f for f in (a.files or "").split(",") if f]
        for f in files:
            if not (RTL / f).is_file():
                raise UserError(f"--files: no rtl/{f}")
        if shutil.which("iverilog") is None:
            raise UserError("iverilog: not found on PATH (run `make setup`)")
        if a.list:
            sl = all_sites(files)
            counts = {k: sum(kk == k for kk, _ in sl) for k in KINDS}
            print(json.dumps({"sites": counts}))
            for m, _ in zip(draw(sl, a.seed), range(a.n)):
                print(f"{m.id} {m.file}:{m.line} {m.kind} {m.describe()}  | {m.text}")
            return 0
        scenes = tuple(x for x in a.scenes.split(",") if x)
        for x in scenes:
            resolve_scene(x)
        if a.report:
            res = json.loads((a.out / "results.json").read_text())
            if a.docs:
                write_section(a.docs, section(res["mutants"], summarize(res["mutants"]), res["args"], res["seconds"]))
            print(json.dumps(summarize(res["mutants"])))
            return 0
        if a.tce_timeout > 0 and shutil.which("yosys") is None:
            raise UserError("yosys: not found on PATH (run `make setup`; --tce-timeout 0 runs without the TCE check)")
        opts = Opts(scenes=scenes, size=a.size, seed=a.seed, timeout=a.timeout, keep=a.keep, tce_timeout=a.tce_timeout)
        if a.tce_only:
            return tce_only([x for x in a.tce_only.split(",") if x], files, opts, a.out)
        t0 = time.perf_counter()
        recs = run_all(a.n, a.seed, a.jobs, files, opts, a.out, progress=not a.quiet)
        secs = time.perf_counter() - t0
        s = summarize(recs)
        args = {"n": a.n, "seed": a.seed, "jobs": a.jobs, "scenes": list(scenes), "size": a.size, "files": files,
                "tce_timeout": a.tce_timeout}
        a.out.mkdir(parents=True, exist_ok=True)
        (a.out / "results.json").write_text(json.dumps({"summary": s, "args": args, "seconds": round(secs, 1),
                                                        "mutants": recs}, indent=1) + "\n")
        if a.docs:
            write_section(a.docs, section(recs, s, args, secs))
        print(json.dumps({**s, "seconds": round(secs, 1)}))
        for r in recs:
            if r["result"] == "survived":
                print(f"survived {r['id']} {r['file']}:{r['line']} {r['mutation']} | {r['text']}"
                      + (f" (equivalent: {EQUIVALENT[r['id']]})" if r["id"] in EQUIVALENT else
                         f" (open: {OPEN[r['id']]})" if r["id"] in OPEN else ""), file=sys.stderr)
        return 0 if s["unexplained"] == 0 else 1

    return run_main("mutants", go)


if __name__ == "__main__":
    sys.exit(main())
