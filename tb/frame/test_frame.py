"""texture_pipeline on whole pixel streams: RTL (sim/frame_tb.v harness) vs golden model.

The pytest side only: the harness's cocotb tests (`frame_run`, `frame_reset`: clock, reset,
wait for `done`, check the harness's protocol counters) live with the frame runner in
sim/frame_cocotb.py. Here, parametrized over (simulator, configuration): random textures
and pixel streams through sim.frame_rtl.run_frame_rtl, compared bit-exact with
model.hw.golden.texture_pipeline on every pixel; the same stream with random input gaps
and output stalls; a reset in the middle of a frame.

Environment: SIM, CONFIG narrow the parametrization; SEED fixes the randomness;
VECTORS scales the Verilator stream length (pixels per stream = max(3000, VECTORS));
Icarus streams 400 pixels; FRAME_PIXELS sets the length for both.
"""
from __future__ import annotations

import os

import numpy as np
import pytest

import hdlbuild
from model.hw.config import clocks_per_pixel, freq_clamp, load_config, variant
from model.hw.golden import MODE_CLAMP, MODE_MOD, TexInt, texture_pipeline, texture_stages



def _seed() -> int:
    s = os.environ.get("SEED")
    return int(s) if s else int.from_bytes(os.urandom(4), "little") >> 1


def _n_pixels(sim: str) -> int:
    """Pixels per stream. Verilator: VECTORS (at least 3000; make test-long: 100,000).
    Icarus runs this design at a few hundred clocks per second, so it gets a short stream
    (FRAME_PIXELS overrides both)."""
    if os.environ.get("FRAME_PIXELS"):
        return int(os.environ["FRAME_PIXELS"])
    if sim == "icarus":
        return 400
    return max(3000, int(os.environ.get("VECTORS", "3000")))


def _sint(r, w, size, scale_bits=None):
    """Signed ints of w bits: the full range, or |x| < 2^scale_bits."""
    if scale_bits is None:
        return r.integers(-(1 << (w - 1)), 1 << (w - 1), size=size, dtype=np.int64)
    b = min(scale_bits, w - 1)
    return r.integers(-(1 << b), 1 << b, size=size, dtype=np.int64)


def random_texture(cfg, r, kind: str, mode=None, filt=None, n_log2=None) -> TexInt:
    """A random texture: kind "full" draws every parameter over its whole format, "real"
    from small realistic ranges (|Q| < 4, |a| < 1, |T| < 16); mode, filt (filter on/off)
    and n_log2 are random unless given."""
    K = cfg.noise_terms
    full = kind == "full"
    Q = _sint(r, cfg.q_w, 10, None if full else cfg.q_frac + 2)
    if cfg.quadric == "diagonal":
        Q[[1, 2, 5]] = 0  # B, C, F: a diagonal-quadric configuration takes no cross terms
    a = _sint(r, cfg.a_w, K, None if full else cfg.a_frac)
    if cfg.amplitude == "pow2":  # 0 or +-2^k, k over the format (full) or up to 1.0 (real)
        kmax = cfg.a_w - 2 if full else cfg.a_frac
        a = (1 << r.integers(0, kmax + 1, size=K)) * r.choice(np.array([-1, 1], dtype=np.int64), size=K)
    if K:
        a[r.random(K) < 0.15] = 0  # some terms off
    if cfg.transform == "pow2":
        T = np.zeros((K, 3, 3), dtype=np.int64)
        for k in range(K):
            for j in range(3):
                if r.random() < 0.9:
                    hi = cfg.t_w - 2 if full else min(cfg.t_w - 2, cfg.t_frac + 4)
                    T[k, j, j] = 1 << int(r.integers(0, hi + 1))
    else:
        T = _sint(r, cfg.t_w, (K, 3, 3), None if full else cfg.t_frac + 4)
    o = r.integers(0, 1 << cfg.d["o_w"], size=(K, 3), dtype=np.int64)
    n_log2 = int(r.integers(0, cfg.n_log2_max + 1)) if n_log2 is None else n_log2
    clut = r.integers(0, 256, size=(1 << n_log2, 4), dtype=np.int64)
    if r.random() < 0.3:
        clut[:, :] = clut[:, :1]  # grey tables too
    mode = int(r.choice([MODE_MOD, MODE_CLAMP])) if mode is None else mode
    filt = bool(r.random() < 0.75) if filt is None else filt
    # the terms the texture uses: usually all, sometimes fewer (the rest must be skipped)
    k_used = int(r.integers(0, K + 1)) if r.random() < 0.3 else K
    # per-term exponents (formats.t_exp_w, a_exp_w > 0): 0, the largest or uniform (drawn only
    # with exponents: a fixed-point configuration's draws stay what they were)
    te, ae = (_exponents(r, K, e_max) for e_max in (cfg.d["te_max"], cfg.d["ae_max"]))
    return TexInt(Q=Q, a=a, T=T, o=o, mode=mode, n_log2=n_log2, filter=filt, clut=clut, k_used=k_used, te=te, ae=ae)


def _exponents(r, K: int, e_max: int) -> np.ndarray:
    """K exponents in 0..e_max: each 0, e_max or uniform (all 0 when e_max = 0, no draw)."""
    if not e_max:
        return np.zeros(K, dtype=np.int64)
    kind = r.integers(0, 3, size=K)
    return np.where(kind == 0, 0, np.where(kind == 1, e_max, r.integers(0, e_max + 1, size=K))).astype(np.int64)


def random_pixels(cfg, r, n: int, kind: str):
    """s, Jm, je for n pixels: a share over the full formats, the rest realistic, plus hard cases."""
    full = kind == "full"
    s = _sint(r, cfg.s_w, (n, 3), None if full else cfg.s_frac + 2)
    Jm = _sint(r, cfg.j_w, (n, 3, 2))
    # je: where w is interesting (|c J| N around 1 entry: J ~ 2^-(n_log2 + a few)), plus the range
    je = r.integers(-(cfg.j_w - 1) - 12, -(cfg.j_w - 1) + 4, size=n).astype(np.int64)
    je = np.clip(je, cfg.d["je_min"], cfg.d["je_max"])  # inside the exponent's format
    wide = r.random(n) < 0.2
    je[wide] = r.integers(cfg.d["je_min"], cfg.d["je_max"] + 1, size=int(wide.sum()))
    small = r.random(n) < 0.2
    Jm[small] >>= r.integers(0, cfg.j_w - 1, size=(int(small.sum()), 1, 1))
    # hard cases, explicit: s = 0, s at the format extremes, Jm = 0 (w = 0), je extremes, tiny steps
    smin, smax = -(1 << (cfg.s_w - 1)), (1 << (cfg.s_w - 1)) - 1
    hard_s = [[0, 0, 0], [smin, smin, smin], [smax, smax, smax], [smin, 0, smax], [-1, -1, -1], [1, 1, 1],
              [1 << cfg.s_frac, 0, 0], [-(1 << cfg.s_frac), 0, 0], [(1 << cfg.s_frac) - 1, 0, 0]]
    m = min(len(hard_s), n)
    s[:m] = np.array(hard_s[:m], dtype=np.int64)
    if n > 2 * m:
        Jm[m:2 * m] = 0
        je[2 * m:2 * m + 3] = [cfg.d["je_min"], cfg.d["je_max"], 0][: max(0, min(3, n - 2 * m))]
    return s, Jm, je


def junk_writes(cfg, r) -> list[tuple[int, int]]:
    """Writes the register map must ignore (addresses from model/hw/regmap.py REGMAP_TABLE):
    unmapped registers, terms k >= K, term fields past o_k (but TERM_E with exponents),
    table indices past the end of clut / csat / mip, unmapped regions."""
    from model.hw import regmap as RM

    K, nmax = cfg.noise_terms, cfg.n_log2_max
    region = 1 << RM.REGION_LSB  # words per region
    q_end, term_end = RM.ADDR_Q + RM.Q_COUNT, RM.ADDR_TERM + RM.TERM_STRIDE * RM.TERM_SLOTS
    addrs = [RM.ADDR_CTRL + 1, RM.ADDR_Q - 1, q_end, q_end + 5, q_end + 6, RM.ADDR_TERM - 1]
    loaded = {RM.TERM_E} if cfg.t_exp_w or cfg.a_exp_w else set()  # the exponents' word (else ignored)
    addrs += [RM.ADDR_TERM + RM.TERM_STRIDE * k + f for k in range(K) for f in range(RM.TERM_O + 3, RM.TERM_STRIDE)
              if f not in loaded]
    addrs += [RM.ADDR_TERM + RM.TERM_STRIDE * k for k in range(K, RM.TERM_SLOTS)] + [term_end, region - 1]
    addrs += [RM.ADDR_CLUT + (1 << nmax), RM.ADDR_CLUT + (2 << nmax), RM.ADDR_CLUT + region - 1]
    addrs += [RM.ADDR_CSAT + RM.CSAT_CHANNELS * (1 << nmax) + c for c in range(RM.CSAT_CHANNELS)]
    addrs += [RM.ADDR_CSAT + region - 1]
    addrs += [RM.ADDR_MIP + (2 << nmax), RM.ADDR_MIP + region - 1]
    used = {RM.ADDR_CTRL >> RM.REGION_LSB, RM.ADDR_CLUT >> RM.REGION_LSB, RM.ADDR_CSAT >> RM.REGION_LSB,
            RM.ADDR_MIP >> RM.REGION_LSB}
    free = [g for g in range(RM.ADDR_SPACE // region) if g not in used]  # unmapped regions
    addrs += [free[0] * region, free[1] * region, free[len(free) // 2] * region, free[-1] * region,
              RM.ADDR_SPACE - 1]
    return [(a, int(r.integers(0, 1 << 32))) for a in addrs if a < RM.ADDR_SPACE]


def _compare(cfg, tex, s, Jm, je, got, what: str):
    exp = texture_stages(cfg, tex, s, Jm, je)
    if cfg.samples > 1:  # the pixel's colour averages its samples' (f, c, w: the pixel centre's, for the message)
        exp["rgba"] = texture_pipeline(cfg, tex, s, Jm, je)
    bad = np.nonzero(np.any(got != exp["rgba"].astype(np.uint8), axis=-1))[0]
    if bad.size:
        i = int(bad[0])
        raise AssertionError(
            f"{what}: {bad.size} of {len(s)} pixels differ; first at pixel {i}: s={s[i].tolist()} "
            f"Jm={Jm[i].tolist()} je={int(je[i])} f={int(exp['f'][i])} c={exp['c'][i].tolist()} "
            f"w={int(exp['w'][i])} expected rgba={exp['rgba'][i].tolist()} got={got[i].tolist()} "
            f"(mode {tex.mode}, n_log2 {tex.n_log2}, filter {tex.filter})"
        )
    return exp


def _frame_rtl():
    from sim.frame_rtl import run_frame_rtl

    return run_frame_rtl


@pytest.mark.parametrize("sim,config", hdlbuild.sim_params())
def test_frame_random(sim, config):
    """(a) random textures (full-range and realistic), random streams: every pixel bit-exact;
    (b) the same stream with random input gaps and output stalls: the same pixels."""
    run_frame_rtl = _frame_rtl()
    cfg = load_config(config)
    seed = _seed()
    print(f"[frame {config} {sim}] SEED={seed}")
    r = np.random.default_rng(seed)
    n = _n_pixels(sim)
    # (texture kind, pixel kind, overrides): SAT filter in both modes, point lookup with the
    # largest table, everything random over the full formats, and N = 1
    cases = (
        ("real", "real", dict(mode=MODE_MOD, filt=True)),
        ("real", "real", dict(mode=MODE_CLAMP, filt=True)),
        ("real", "full", dict(filt=False, n_log2=cfg.n_log2_max)),
        ("full", "full", dict()),
        ("real", "real", dict(n_log2=0)),
    )
    # every pass of this multi-texture frame runs with random input gaps and output stalls
    # (the harness checks the AXI-Stream hold rule on every stalled clock); the first also
    # without, for the one-pixel-per-clock check and the same-pixels check
    for t, (tkind, pkind, over) in enumerate(cases):
        tex = random_texture(cfg, r, tkind, **over)
        s, Jm, je = random_pixels(cfg, r, n, pkind)
        got, cycles, secs = run_frame_rtl(config, sim, tex, s, Jm, je, gaps=30, stalls=40, seed=seed + t,
                                          extra_writes=junk_writes(cfg, r))
        exp = _compare(cfg, tex, s, Jm, je, got, f"texture {t} ({tkind}/{pkind}), gaps 30% / stalls 40%")
        w = exp["w"]
        print(f"  texture {t}: mode {tex.mode} n_log2 {tex.n_log2} filter {int(tex.filter)} "
              f"terms {int(np.count_nonzero(tex.a))}: {n} px, gaps 30% / stalls 40%: {cycles} cycles, "
              f"{secs:.2f} s; w=0: {np.mean(w == 0):.2f}, w saturated: {np.mean(w == cfg.d['w_cap']):.2f}")
        assert cycles > n, f"gaps/stalls had no effect: {cycles} cycles for {n} pixels"
        if t == 0:
            got0, cycles, _ = run_frame_rtl(config, sim, tex, s, Jm, je, seed=seed + 99)
            assert np.array_equal(got, got0), "gaps/stalls changed the pixels"
            p = clocks_per_pixel(cfg, tex.k_used)
            print(f"  texture 0 without gaps or stalls: {cycles} cycles ({n / cycles:.3f} px/clk; "
                  f"{tex.k_used} terms on {cfg.noise_units} units: {p} clocks a pixel)")
            assert cycles < p * n + 100, f"not one pixel per {p} clocks without stalls: {cycles} cycles for {n} pixels"


def complement_texture(cfg, tex: TexInt) -> TexInt:
    """tex with every parameter register field complemented bit for bit where the configuration's
    formats take any value: Q (signed: -1 - Q; a diagonal quadric's B, C, F stay 0), a (amplitude
    any), T (transform affine), o (u{o_w}), te, ae (u{t_exp_w}, u{a_exp_w}: e_max - e); a pow2 T
    or a as tex. k_used, the tables, mode and filter as tex."""
    Q = -1 - tex.Q
    if cfg.quadric == "diagonal":
        Q[[1, 2, 5]] = 0
    a = tex.a.copy() if cfg.amplitude == "pow2" else -1 - tex.a
    T = tex.T.copy() if cfg.transform == "pow2" else -1 - tex.T
    o = ((1 << cfg.d["o_w"]) - 1) - tex.o
    te, ae = cfg.d["te_max"] - tex.te, cfg.d["ae_max"] - tex.ae
    return TexInt(Q=Q, a=a, T=T, o=o, mode=tex.mode, n_log2=tex.n_log2, filter=tex.filter, clut=tex.clut,
                  k_used=tex.k_used, te=te, ae=ae)


def ignored_field_writes(cfg, word: int) -> list[tuple[int, int]]:
    """Writes of `word` (u32) to the parameter registers the configuration ignores: T's off-diagonal
    entries of every term with a pow2 transform, B, C, F with a diagonal quadric."""
    from model.hw import regmap as RM

    out = []
    if cfg.transform == "pow2":
        out += [(RM.ADDR_TERM + RM.TERM_STRIDE * k + RM.TERM_T + 3 * j + m, word)
                for k in range(cfg.noise_terms) for j in range(3) for m in range(3) if j != m]
    if cfg.quadric == "diagonal":
        out += [(RM.ADDR_Q + i, word) for i in (1, 2, 5)]
    return out


@pytest.mark.parametrize("sim,config", hdlbuild.sim_params())
def test_frame_registers_both_ways(sim, config):
    """Every parameter register bit both ways in one simulator run, on every term: passes that
    alternate a random texture over its whole formats and its complement (complement_texture:
    every bit of Q, a, T, o and the exponents flipped); with a pow2 transform or amplitude the
    passes walk each diagonal T entry and each a through every power of two (a's sign flipping),
    and write the registers the configuration ignores (off-diagonal T, a diagonal quadric's B, C, F)
    with a random word and its complement in turn, which must change nothing; every other pass uses
    half of the terms (the ones past k_used are written all the same and must not count). Each
    pass's pixels (full formats) bit-exact against the golden model of its texture."""
    from model.hw.regmap import pack_pixels_u32, unpack_rgba, write_sequence
    from sim.frame_rtl import run_segments

    cfg = load_config(config)
    seed = _seed()
    print(f"[frame {config} {sim}] SEED={seed}")
    r = np.random.default_rng(seed + 41)
    n = 32 if sim == "icarus" else 200
    K = cfg.noise_terms
    base = random_texture(cfg, r, "full", n_log2=min(2, cfg.n_log2_max))
    comp = complement_texture(cfg, base)
    n_pass = max(3, cfg.t_w if cfg.transform == "pow2" else 0, cfg.a_w if cfg.amplitude == "pow2" else 0)
    junk = int(r.integers(0, 1 << 32))
    passes, segments = [], []
    for i in range(n_pass):
        t = complement_texture(cfg, comp) if i % 2 == 0 else complement_texture(cfg, base)  # a copy
        t.k_used = K if i % 2 else K // 2
        for k in range(K):
            if cfg.transform == "pow2":  # T_jj = 2^e, e walking 0..t_w - 2
                for j in range(3):
                    t.T[k, j, j] = 1 << ((i + k + j) % (cfg.t_w - 1))
            if cfg.amplitude == "pow2":  # a = +-2^e, e walking 0..a_w - 2, the sign flipping
                t.a[k] = (-1) ** i * (1 << ((i + k) % (cfg.a_w - 1)))
        s, Jm, je = random_pixels(cfg, r, n, "full")
        passes.append((t, s, Jm, je))
        segments.append((write_sequence(cfg, t) + ignored_field_writes(cfg, junk ^ (0xFFFFFFFF if i % 2 else 0)),
                         pack_pixels_u32(cfg, s, Jm, je)))
    outs, _ = run_segments(cfg, sim, segments, gaps=20, stalls=20, seed=seed)
    for i, ((t, s, Jm, je), out) in enumerate(zip(passes, outs)):
        _compare(cfg, t, s, Jm, je, unpack_rgba(out), f"pass {i} of {n_pass} (k_used {t.k_used} of {K})")


@pytest.mark.parametrize("sim", sorted({sim for sim, _ in hdlbuild.sim_params()}))
def test_frame_harness_checks_hold_and_reports_its_reason(sim):
    """Issue 16: the harness checks that tvalid/tdata/tlast hold while the sink stalls, and its
    own reason reaches the pytest failure message (not "simulator exited with 1"). A fault
    planted in the check's copy of the held word (+FAULT_HOLD) must fail the run with that reason."""
    from sim.frame_rtl import FrameRunError

    config = "reduced"
    cfg = load_config(config)
    r = np.random.default_rng(_seed())
    tex = random_texture(cfg, r, "real")
    s, Jm, je = random_pixels(cfg, r, 200, "real")
    with pytest.raises(FrameRunError) as ei:
        _frame_rtl()(config, sim, tex, s, Jm, je, stalls=50, fault_hold=True)
    msg = str(ei.value)
    assert "frame_tb: ERROR: output" in msg and "changed while the sink stalled" in msg, msg
    assert "simulator exited" not in msg and "\n" not in msg, msg


@pytest.mark.parametrize("sim,config", hdlbuild.sim_params())
def test_frame_reset(sim, config):
    """(c) reset in the middle of a frame (with gaps and stalls): reload, stream again, all correct;
    no output is X right after either reset (checked inside the cocotb test)."""
    run_frame_rtl = _frame_rtl()
    cfg = load_config(config)
    seed = _seed()
    print(f"[frame reset {config} {sim}] SEED={seed}")
    r = np.random.default_rng(seed + 7)
    n = min(_n_pixels(sim), 3000)
    tex = random_texture(cfg, r, "real")
    s, Jm, je = random_pixels(cfg, r, n, "real")
    from model.hw.regmap import write_sequence

    nwr = len(write_sequence(cfg, tex))
    reset_at = nwr + 2 + int(r.integers(n // 4, n // 2))  # inside the stream (~1 px / clock)
    got, _, _ = run_frame_rtl(config, sim, tex, s, Jm, je, gaps=10, stalls=10, seed=seed, reset_at=reset_at)
    _compare(cfg, tex, s, Jm, je, got, "after a mid-frame reset")


def _unit_params():
    """(sim, base configuration, noise_units): U = 1, 2 and K of compact and reduced."""
    sims = sorted({sim for sim, _ in hdlbuild.sim_params()})
    out = []
    for base in ("compact", "reduced"):
        k = load_config(base).noise_terms
        out += [(sim, base, u) for sim in sims for u in sorted({1, 2, k})]
    return out


@pytest.mark.parametrize("sim,base,units", _unit_params())
def test_frame_noise_units(sim, base, units):
    """The noise terms on U units (noise_fold; U = K: all in parallel) give the same bits for
    every U: one texture and stream (the same seed for every U), its terms 0..k_used-1, through
    the RTL with random input gaps and output stalls, then without (ceil(k_used / U) clocks a
    pixel), then with a reset in the middle of the frame; every run equal to the golden model,
    which does not depend on U, so the runs of U = 1, 2, K are bit-identical with each other."""
    run_frame_rtl = _frame_rtl()
    b = load_config(base)
    # U = K: every term in parallel, and a quadric of one clock (two need folded terms)
    qc = b.quadric_clocks if units < b.noise_terms else 1
    cfg = variant(b, f"{base}-u{units}", noise_units=units, quadric_clocks=qc)
    seed = _seed()
    print(f"[frame {cfg.name} {sim}] SEED={seed}")
    r = np.random.default_rng(seed + 11)
    n = min(_n_pixels(sim), 2000)
    tex = random_texture(load_config(base), r, "real", filt=True)
    s, Jm, je = random_pixels(cfg, r, n, "real")
    got, cycles, _ = run_frame_rtl(cfg, sim, tex, s, Jm, je, gaps=30, stalls=40, seed=seed)
    _compare(cfg, tex, s, Jm, je, got, f"{cfg.name}, gaps 30% / stalls 40%")
    _check_clocks_and_reset(cfg, sim, tex, s, Jm, je, got, r, seed + 1, f"{tex.k_used} terms on {units} units")


@pytest.mark.parametrize("sim,samples", [("icarus", 1), ("verilator", 1), ("verilator", 4)])
def test_frame_quadric_serial(sim, samples):
    """The quadric on one multiplier over six clocks (quadric_clocks = 6, qmac_diag_serial:
    config/candidates/compact_q6.toml), alone and with 4 sub-pixel samples (issue 27's small
    configuration): one texture through the RTL with random input gaps and output stalls, then
    without (max(6, ceil(k_used / U)) clocks a sample), then with a mid-frame reset; every pixel
    equal to the golden model's."""
    run_frame_rtl = _frame_rtl()
    b = load_config("config/candidates/compact_q6.toml")
    cfg = b if samples == 1 else variant(b, f"{b.name}-s{samples}", samples=samples)
    seed = _seed()
    print(f"[frame {cfg.name} {sim}] SEED={seed}")
    r = np.random.default_rng(seed + 13)
    n = min(_n_pixels(sim), 2000)
    tex = random_texture(b, r, "real", filt=True)
    s, Jm, je = random_pixels(cfg, r, n, "real")
    got, _, _ = run_frame_rtl(cfg, sim, tex, s, Jm, je, gaps=30, stalls=40, seed=seed)
    _compare(cfg, tex, s, Jm, je, got, f"{cfg.name}, gaps 30% / stalls 40%")
    _check_clocks_and_reset(cfg, sim, tex, s, Jm, je, got, r, seed + 1, f"{tex.k_used} terms, quadric on 6 clocks")


@pytest.mark.parametrize("sim,name", [("icarus", "compact_c4"), ("verilator", "compact_c4"),
                                      ("verilator", "compact_q6c4_s4")])
def test_frame_cmap_clocks(sim, name):
    """colour_map's box filter a channel a clock (cmap_clocks = 4: cmap_sat's fold, sat_integral_serial,
    one divider lane): compact with it and a texture of 3 terms, so that noise_fold's pacing is the
    fold's own 4 clocks a sample (compact's quadric takes 2, its terms 3 on one unit), and issue 27's
    small unit config/candidates/compact_q6c4_s4.toml (both folds, 4 samples: 24 clocks a pixel). One
    texture through the RTL with random input gaps and output stalls, then without (the clocks a pixel
    counted), then with a mid-frame reset; every pixel equal to the golden model's."""
    run_frame_rtl = _frame_rtl()
    if name == "compact_c4":
        b = load_config("compact")
        cfg = variant(b, name, cmap_clocks=4)
    else:
        b = cfg = load_config(f"config/candidates/{name}.toml")
    seed = _seed()
    print(f"[frame {cfg.name} {sim}] SEED={seed}")
    r = np.random.default_rng(seed + 17)
    n = min(_n_pixels(sim), 2000)
    tex = random_texture(b, r, "real", filt=True)
    if name == "compact_c4":
        tex.k_used = 3
        assert clocks_per_pixel(cfg, tex.k_used) == 4 > clocks_per_pixel(b, tex.k_used)
    s, Jm, je = random_pixels(cfg, r, n, "real")
    got, _, _ = run_frame_rtl(cfg, sim, tex, s, Jm, je, gaps=30, stalls=40, seed=seed)
    _compare(cfg, tex, s, Jm, je, got, f"{cfg.name}, gaps 30% / stalls 40%")
    _check_clocks_and_reset(cfg, sim, tex, s, Jm, je, got, r, seed + 1, f"{tex.k_used} terms, colour map on 4 clocks")


def random_folds(seed: int):
    """A random valid configuration (model.hw.config.random_config, from `seed` on) made to fold
    everything the design family folds, at its own formats: a diagonal quadric on one multiplier
    over six clocks (quadric_clocks = 6), its noise terms on fewer units than terms, the box filter
    a channel a clock (cmap_clocks = 4) where its filter is the box's family (sat, sat2: made sat;
    mip and none stay, on one clock), 1, 2 or 4 sub-pixel samples, no FPGA registers (which
    unfold both). random_config never draws quadric_clocks 6, cmap_clocks 4 or samples, so the
    folds were run on compact's formats alone (the tests above). (seed used, Config)."""
    from model.hw.config import ConfigError, random_config

    for s in range(seed, seed + 200):
        b = random_config(s)
        if b.noise_terms < 2:
            continue
        r = np.random.default_rng([s, 50])
        box = b.filter in ("sat", "sat2")
        try:
            return s, variant(b, f"folds{s}", quadric="diagonal", noise_units=int(r.integers(1, b.noise_terms)),
                              quadric_clocks=6, cmap_clocks=4 if box else 1, filter="sat" if box else b.filter,
                              samples=int(r.choice([1, 2, 4])), fpga_regs=False)
        except ConfigError:
            continue
    raise AssertionError(f"random_folds({seed}): no configuration in 200 seeds")


@pytest.mark.parametrize("sim,seed", [("verilator", 0), ("verilator", 40), ("icarus", 80)])
def test_frame_folds_random(sim, seed):
    """Every fold at once on random formats (random_folds: the quadric on six clocks, the noise
    terms folded, the box filter a channel a clock, sub-pixel samples): random textures over the
    whole formats and realistic ones, with random input gaps and output stalls, then without
    (the clocks a pixel counted), then with a mid-frame reset; every pixel bit-exact."""
    run_frame_rtl = _frame_rtl()
    used, cfg = random_folds(seed)
    seed_r = _seed()
    print(f"[frame {cfg.name} (random_folds({seed}): random:{used}) {sim}] SEED={seed_r}")
    r = np.random.default_rng(seed_r + 19)
    n = min(_n_pixels(sim), 1500)
    for kind in ("full", "real"):
        tex = random_texture(cfg, r, kind, filt=True)
        s, Jm, je = random_pixels(cfg, r, n, kind)
        got, _, _ = run_frame_rtl(cfg, sim, tex, s, Jm, je, gaps=30, stalls=40, seed=seed_r)
        _compare(cfg, tex, s, Jm, je, got, f"{cfg.name} ({kind}), gaps 30% / stalls 40%")
    _check_clocks_and_reset(cfg, sim, tex, s, Jm, je, got, r, seed_r + 1,
                            f"{tex.k_used} terms on {cfg.noise_units} units, filter {cfg.filter}, "
                            f"{cfg.samples} samples, quadric on 6 clocks, colour map on {cfg.cmap_clocks}")


def _check_clocks_and_reset(cfg, sim, tex, s, Jm, je, got, r, seed: int, what: str):
    """The stream `got` came from with gaps and stalls, run again without them (the same pixels, in
    clocks_per_pixel clocks a pixel) and with a reset in the middle of the frame (every pixel after
    it equal to the golden model)."""
    run_frame_rtl = _frame_rtl()
    n = len(s)
    got0, cycles, _ = run_frame_rtl(cfg, sim, tex, s, Jm, je, seed=seed)
    assert np.array_equal(got, got0), "gaps/stalls changed the pixels"
    p = clocks_per_pixel(cfg, tex.k_used)
    print(f"  {what}: {cycles} cycles for {n} px ({p} clocks a pixel expected)")
    assert p * n <= cycles < p * n + 100, f"{cycles} cycles for {n} pixels, expected {p} a pixel"
    from model.hw.regmap import write_sequence

    reset_at = len(write_sequence(cfg, tex)) + 2 + int(r.integers(p * n // 4, p * n // 2))
    got_r, _, _ = run_frame_rtl(cfg, sim, tex, s, Jm, je, gaps=10, stalls=10, seed=seed + 1, reset_at=reset_at)
    _compare(cfg, tex, s, Jm, je, got_r, f"{cfg.name}, after a mid-frame reset")


@pytest.mark.parametrize("sim,grad", [(s, g) for s in sorted({sim for sim, _ in hdlbuild.sim_params()})
                                      for g in (False, True)])
def test_frame_sat_fc(sim, grad):
    """The frequency-clamping filter (sat_fc: fc_weight, fc_scale, the max of w and wv) through
    the whole pipeline: reduced_fc, and with the noise gradient (its gradients faded too);
    random textures, pixels whose footprints sweep every term from whole (alpha 1) through the
    fade to gone (alpha 0), with gaps and stalls: every pixel bit-exact."""
    run_frame_rtl = _frame_rtl()
    base = load_config("reduced_fc")
    cfg = variant(base, "reduced_fc_ng", noise_gradient=True) if grad else base
    seed = _seed()
    print(f"[frame {cfg.name} {sim}] SEED={seed}")
    r = np.random.default_rng(seed + 23)
    n = min(_n_pixels(sim), 2000)
    from model.hw.golden import fc_weight

    one = 1 << cfg.fc_af
    seen = set()
    for t, mode in enumerate((MODE_MOD, MODE_CLAMP, MODE_MOD, MODE_CLAMP)):
        tex = random_texture(cfg, r, "real", mode=mode, filt=True)
        if t >= 2:  # a constant quadric (the seascape's): the faded terms' spread wv is the width
            tex.Q[:9] = 0
            tex.k_used = max(tex.k_used, 1)
            if tex.a[0] == 0:  # a term that fades (any nonzero amplitude of the format)
                tex.a[0] = 1 << cfg.a_frac
        s, Jm, je = random_pixels(cfg, r, n, "real")
        je[: n // 2] = r.integers(cfg.je_min, cfg.je_max + 1, n // 2)  # footprints of every size
        alpha, wv = fc_weight(cfg, tex, Jm, je)
        w_grad = texture_stages(variant(cfg, "reduced_sat", filter="sat"), tex, s, Jm, je)["w"]
        seen |= {"wv"} if (wv > w_grad).any() else set()
        live = alpha[:, :tex.k_used][:, np.asarray(tex.a[:tex.k_used]) != 0]
        seen |= {"0"} if (live == 0).any() else set()
        seen |= {"1"} if (live == one).any() else set()
        seen |= {"fade"} if ((live > 0) & (live < one)).any() else set()
        got, cycles, _ = run_frame_rtl(cfg, sim, tex, s, Jm, je, gaps=30, stalls=40, seed=seed + t)
        _compare(cfg, tex, s, Jm, je, got, f"{cfg.name} texture {t}, gaps 30% / stalls 40%")
    assert seen == {"0", "1", "fade", "wv"}, f"the stimulus does not cover the fade (alpha 0, 1, between; wv > w): {sorted(seen)}"


@pytest.mark.parametrize("sim", sorted({sim for sim, _ in hdlbuild.sim_params()}))
def test_frame_sat2_fc(sim):
    """The trapezoid with frequency clamping (sat2_fc: sat_fc's fc_weight and fc_scale, sat2's
    filter_width components and cmap_sat2, cm_align widening the larger of a and b to wv) through
    the whole pipeline: reduced_fc with filter sat2_fc and the noise gradient (its gradients
    faded too); random textures in both modes, footprints from whole terms to gone, with gaps and
    stalls: every pixel bit-exact, and wv above the larger width and below it both met."""
    run_frame_rtl = _frame_rtl()
    cfg = variant(load_config("reduced_fc"), "reduced_sat2_fc_ng", filter="sat2_fc", noise_gradient=True)
    seed = _seed()
    print(f"[frame {cfg.name} {sim}] SEED={seed}")
    r = np.random.default_rng(seed + 27)
    n = min(_n_pixels(sim), 1500)
    from model.hw.golden import filter_width, texture_sum

    seen = set()
    for t, mode in enumerate((MODE_MOD, MODE_CLAMP)):
        tex = random_texture(cfg, r, "real", mode=mode, filt=True)
        tex.Q[:9] = 0  # a constant quadric (the seascape's): the faded terms' spread is the width
        tex.k_used = max(tex.k_used, 1)
        if tex.a[0] == 0:
            tex.a[0] = 1 << cfg.a_frac
        s, Jm, je = random_pixels(cfg, r, n, "real")
        je[: n // 2] = r.integers(cfg.je_min, cfg.je_max + 1, n // 2)  # footprints of every size
        _, c, wv = texture_sum(cfg, tex, s, Jm, je)
        ab = filter_width(cfg, c, Jm, je, tex.n_log2, components=True)  # (a, b) before the widening
        seen |= {"wv"} if (wv > ab.max(axis=1)).any() else set()
        seen |= {"ab"} if ((wv > 0) & (wv <= ab.max(axis=1))).any() else set()
        got, cycles, _ = run_frame_rtl(cfg, sim, tex, s, Jm, je, gaps=30, stalls=40, seed=seed + t)
        _compare(cfg, tex, s, Jm, je, got, f"{cfg.name} texture {t}, gaps 30% / stalls 40%")
    assert seen == {"wv", "ab"}, f"the stimulus does not widen a trapezoid and keep another: {sorted(seen)}"


def _sample_params():
    """(sim, base, samples, filter): sub-pixel samples (sample_expand, sample_average) on full
    (one clock a sample), compact (folded terms: 5 clocks a sample) and reduced with the trapezoid,
    under Verilator; reduced under Icarus too (the 4-state check of the new blocks). SIM= narrows."""
    sims = [os.environ["SIM"]] if os.environ.get("SIM") else ["icarus", "verilator"]
    cases = [("verilator", "full", 2, None), ("verilator", "compact", 4, None), ("verilator", "reduced", 4, "sat2"),
             ("icarus", "reduced", 2, None)]
    return [c for c in cases if c[0] in sims]


@pytest.mark.parametrize("sim,base,samples,filt", _sample_params())
def test_frame_samples(sim, base, samples, filt):
    """features.samples = 2 or 4 through the whole pipeline: each pixel's samples (s + J d_k, the
    footprint of its cell) and their average, bit-exact with the golden model's
    texture_pipeline on random textures and pixels (the hard cases of random_pixels: s at its ends,
    where the offsets saturate; J = 0; je at its ends), with random input gaps and output stalls,
    then without them (samples x clocks_per_sample clocks a pixel), then with a mid-frame reset."""
    run_frame_rtl = _frame_rtl()
    b = load_config(base)
    cfg = variant(b, f"{base}-s{samples}{'-' + filt if filt else ''}", samples=samples, **({"filter": filt} if filt else {}))
    seed = _seed()
    print(f"[frame {cfg.name} {sim}] SEED={seed}")
    r = np.random.default_rng(seed + 31)
    n = min(_n_pixels(sim), 1500)
    for t, (tkind, pkind, over) in enumerate((("real", "real", dict(mode=MODE_MOD, filt=True)),
                                              ("real", "full", dict(mode=MODE_CLAMP)))):
        tex = random_texture(cfg, r, tkind, **over)
        s, Jm, je = random_pixels(cfg, r, n, pkind)
        got, _, _ = run_frame_rtl(cfg, sim, tex, s, Jm, je, gaps=30, stalls=40, seed=seed + t)
        _compare(cfg, tex, s, Jm, je, got, f"{cfg.name} texture {t}, gaps 30% / stalls 40%")
        if t == 0:
            _check_clocks_and_reset(cfg, sim, tex, s, Jm, je, got, r, seed + 7, f"{samples} samples, {tex.k_used} terms")


def _fpga_params():
    """(sim, base): reduced and compact with features.fpga_regs = true, under Verilator (SIM=
    narrows; CONFIG= picks one base)."""
    sims = [os.environ["SIM"]] if os.environ.get("SIM") else ["verilator"]
    bases = [os.environ["CONFIG"]] if os.environ.get("CONFIG") in ("reduced", "compact") else ["reduced", "compact"]
    return [(sim, base) for sim in sims for base in bases]


@pytest.mark.parametrize("sim,base", _fpga_params())
def test_frame_fpga_regs(sim, base):
    """features.fpga_regs (the blocks' extra register stages, the longer latencies of
    rtl/tex_latency.vh `LAT_*_FPGA) changes no pixel: a random texture and stream through the
    fpga_regs build with random input gaps and output stalls, then without (still one pixel
    per clocks_per_pixel clocks), every pixel equal to the golden model."""
    run_frame_rtl = _frame_rtl()
    cfg = hdlbuild.config_of(f"fpga_regs:{base}")
    assert cfg.fpga_regs
    seed = _seed()
    print(f"[frame {cfg.name} {sim}] SEED={seed}")
    r = np.random.default_rng(seed + 13)
    n = min(_n_pixels(sim), 2000)
    for t, (tkind, over) in enumerate((("real", dict(mode=MODE_MOD, filt=True)),
                                       ("real", dict(mode=MODE_CLAMP, filt=True)), ("full", dict()))):
        tex = random_texture(cfg, r, tkind, **over)
        s, Jm, je = random_pixels(cfg, r, n, tkind)
        got, cycles, _ = run_frame_rtl(cfg, sim, tex, s, Jm, je, gaps=30, stalls=40, seed=seed + t)
        _compare(cfg, tex, s, Jm, je, got, f"{cfg.name} texture {t} ({tkind}), gaps 30% / stalls 40%")
        if t == 0:
            got0, cycles, _ = run_frame_rtl(cfg, sim, tex, s, Jm, je, seed=seed + 99)
            assert np.array_equal(got, got0), "gaps/stalls changed the pixels"
            p = clocks_per_pixel(cfg, tex.k_used)
            assert p * n <= cycles < p * n + 100, f"{cycles} cycles for {n} pixels, expected {p} a pixel"
    # every k_used 0..K, pass after pass in one simulator start (the folded issue's last-issue
    # flag is a register under fpga_regs, formed from k_used as a pixel is taken)
    from sim.frame_rtl import run_passes_rtl

    passes = []
    for ku in range(cfg.noise_terms + 1):
        tex = random_texture(cfg, r, "real", mode=MODE_MOD, filt=True)
        tex.k_used = ku
        passes.append((tex, *random_pixels(cfg, r, 200, "real")))
    got_all = run_passes_rtl(cfg, sim, passes, gaps=30, stalls=40, seed=seed + 7)
    for (tex, s, Jm, je), got in zip(passes, got_all):
        _compare(cfg, tex, s, Jm, je, got, f"{cfg.name} k_used {tex.k_used}, gaps 30% / stalls 40%")


def _exponent_params():
    """(sim, name): configurations with per-term exponents (formats.t_exp_w, a_exp_w > 0) under
    Verilator (SIM= narrows): full (config/full.toml since issue 26: eight unfolded terms, the box
    filter) and exp1351 (tb.pipe.exponent_configs: three terms folded on two units, fpga_regs,
    mip, no noise gradient: noise_fold's parameter selection with {te, T} and {ae, a}); make
    test-long (VECTORS >= 100000) adds full_fc (its terms faded, sat_fc: fc_weight at the top)."""
    sims = [os.environ["SIM"]] if os.environ.get("SIM") else ["verilator"]
    names = ["full", "exp1351"] + (["full_fc"] if int(os.environ.get("VECTORS", "0")) >= 100000 else [])
    return [(sim, n) for sim in sims for n in names]


def _exponent_config(name: str):
    from tb import pipe

    if name.startswith("full"):
        return load_config(name)
    return dict(pipe.exponent_configs(1351))[name]


@pytest.mark.parametrize("sim,name", _exponent_params())
def test_frame_exponents(tmp_path, sim, name):
    """Per-term exponents through the whole unit (TERM_E, tex_regs, noise_fold or noise_leaves,
    noise_term; fc_weight with sat_fc): random textures whose terms each draw te and ae (0, the
    largest, or uniform; the first texture every term with an extreme pair: te_max and ae 0, 0 and
    ae_max) and streams with random input gaps and output stalls, junk writes to the
    ignored addresses, every pixel bit-exact against the golden model; on full also the
    rotated marble of the held-out corpus (model/scene/corpus.py rotated_marble: four rotated
    terms, the scene of issue 26) at 16x16 through sim.frame, bit-exact."""
    run_frame_rtl = _frame_rtl()
    cfg = _exponent_config(name)
    assert cfg.t_exp_w and cfg.a_exp_w
    seed = _seed()
    print(f"[frame {cfg.name} {sim}] SEED={seed}")
    r = np.random.default_rng(seed + 31)
    n = min(_n_pixels(sim), 1500)
    for t, (tkind, pkind) in enumerate((("real", "real"), ("full", "full"), ("real", "real"))):
        tex = random_texture(cfg, r, tkind, filt=True if t != 1 else None)
        if t == 0:  # every term used, the extreme exponents on live terms: te_max with ae 0, then 0 with ae_max
            tex.k_used = cfg.noise_terms
            tex.te[:] = np.where(np.arange(cfg.noise_terms) % 2 == 0, cfg.d["te_max"], 0)
            tex.ae[:] = np.where(np.arange(cfg.noise_terms) % 2 == 0, 0, cfg.d["ae_max"])
            tex.a[tex.a == 0] = 1 << (cfg.a_w - 3)
        s, Jm, je = random_pixels(cfg, r, n, pkind)
        if freq_clamp(cfg):  # footprints of every size: every term from whole to gone
            je[: n // 2] = r.integers(cfg.je_min, cfg.je_max + 1, n // 2)
        got, cycles, _ = run_frame_rtl(cfg, sim, tex, s, Jm, je, gaps=30, stalls=40, seed=seed + t,
                                       extra_writes=junk_writes(cfg, r))
        _compare(cfg, tex, s, Jm, je, got, f"{cfg.name} texture {t} ({tkind}/{pkind}), te {tex.te.tolist()} "
                                           f"ae {tex.ae.tolist()}, gaps 30% / stalls 40%")
    if name == "full":
        from model.scene.corpus import rotated_marble
        from sim.frame import run_frame

        scene, text = rotated_marble()
        path = tmp_path / f"{scene}.toml"
        path.write_text(text)
        rep = run_frame(str(path), "full", sim, 16, out_root=tmp_path / "frames", progress=False)
        assert rep["pixels_streamed"] > 0
        assert rep["bit_exact"], f"{scene} full {sim}: {rep['mismatched_pixels']} pixels differ"
