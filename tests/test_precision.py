"""The precision test (app/precision.py, make precision): its scene, its variants, its
thresholds, that fewer fraction bits of s cost PSNR where the texture is magnified, bad input."""
from __future__ import annotations

import json

import pytest

from model.hw.config import CONFIG_NAMES, ConfigError, load_config, variant
from app import precision as P
from model.scene.frontend import render_passes
from model.scene.passes import SCENES, prepare_passes
from model.scene.scene import load_scene


def test_scene_is_not_one_of_the_papers_eight():
    assert P.SCENE.is_file() and P.SCENE.stem not in SCENES and P.SCENE.parent.name == "fig10"


@pytest.mark.parametrize("config", CONFIG_NAMES)
def test_scene_fits_every_configuration(config):
    """The textures fit every configuration whole (terms, transforms, amplitudes): s_frac is
    what the test changes, not what a configuration drops."""
    cfg = load_config(config)
    sc = load_scene(P.SCENE)
    pds = prepare_passes(cfg, render_passes(sc, 32, 32))
    assert {pd.name for pd in pds} == {"teapot", "icosahedron"} and all(pd.mask.any() for pd in pds)
    for pd in pds:
        assert pd.info["dropped_terms"] == 0, pd.info
        assert not [a for a in pd.info["approximations"] if "dropped" in a or "box filter replaced" in a], pd.info


@pytest.mark.parametrize("config", CONFIG_NAMES)
@pytest.mark.parametrize("k", P.FRACS)
def test_variant_valid_and_keeps_the_range(config, k):
    cfg = load_config(config)
    v = P.precision_variant(cfg, k)
    assert v.s_frac == k and v.s_w - v.s_frac == cfg.s_w - cfg.s_frac
    assert v.p_frac == min(cfg.p_frac, k + cfg.t_frac) <= v.s_frac + v.t_frac
    changed = {key for key in ("s_w", "s_frac", "p_frac", "q_w", "q_frac", "t_frac", "f_frac", "n_frac", "hash_bits")
               if getattr(v, key) != getattr(cfg, key)}
    assert changed <= {"s_w", "s_frac", "p_frac", "q_w", "q_frac"}
    if changed & {"q_w", "q_frac"}:  # only where the unchanged q would overflow the golden model's int64, by one bit
        assert v.q_w - v.q_frac == cfg.q_w - cfg.q_frac and v.q_frac == cfg.q_frac - 1
        with pytest.raises(ConfigError, match="formats too wide"):
            variant(cfg, "x", s_frac=k, s_w=v.s_w, p_frac=v.p_frac)
    if k == cfg.s_frac:
        assert not changed


def test_threshold_and_plateau():
    ps = {6: 30.0, 7: 41.0, 8: 39.5, 9: 45.0, 10: 48.0, 11: 48.2}
    assert P.threshold(ps, 40) == 9  # 8 dips below: the threshold holds for every larger s_frac
    assert P.threshold(ps, 50) is None and P.threshold({6: None, 7: 41.0}, 40) == 7
    assert P.plateau(ps) == 10 and P.plateau({6: 36.9, 7: 37.1}) == 6


def test_fewer_bits_cost_psnr_where_magnified(tmp_path):
    """At 96 px the teapot's rings are magnified enough that 6 bits of s are visible steps and
    16 bits are not: the PSNR must fall with s_frac (it would not if s_frac were ignored). On
    full_wide, whose own s_frac is 16."""
    rep = P.run(96, ("full_wide",), (6, 9, 16), out_root=tmp_path, progress=False)
    ps = {x["s_frac"]: x["psnr_db"] for x in rep["configs"]["full_wide"]["rows"]}
    assert ps[6] < ps[9] - 3 < ps[16] - 3, ps
    assert rep["configs"]["full_wide"]["psnr_at_own_s_frac_db"] == ps[16]
    saved = json.loads((tmp_path / "precision" / "report.json").read_text())
    assert saved["configs"]["full_wide"]["threshold_s_frac"] == P.threshold(ps)
    for name in ("reference.png", "s6.png", "s9.png", "s16.png"):
        assert (tmp_path / "precision" / "full_wide" / name).is_file(), name
    md = (tmp_path / "docs" / "precision.md").read_text()
    assert "`full_wide` (config/full_wide.toml) has s_frac = 16" in md and f"{ps[6]:.2f}" in md


@pytest.mark.parametrize("args,expected", [
    (["--size", "4"], "--size 4: expected 8..1024"),
    (["--configs", "full,nope"], "--config nope: no such configuration"),
    (["--fracs", "6..x"], "--fracs 6..x: expected LO..HI"),
    (["--fracs", "0,6"], "--fracs 0: expected 1..23"),
    (["--scene", "/no/such.toml"], "--scene /no/such.toml: no such scene file"),
])
def test_bad_input_exits_2(capsys, tmp_path, args, expected):
    assert P.main([*args, "--out", str(tmp_path), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("precision: ") and expected in err and "\n" not in err, err
