"""The animation test (app/animation.py, make animation): the camera path and the phase,
the flicker measure, the per-frame truth cache, bad input, the RTL check (--rtl: every pass of
every frame in one simulator start, bit-exact frame by frame)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from model.hw.config import load_config
from app import animation as A
from model.scene.passes import scene_path
from model.scene.scene import load_scene


def test_camera_flies_and_phase_advances():
    sea = load_scene(scene_path("seascape"))
    anim = A.load_animation("seascape")
    s0, s1, sh = (A.frame_scene(sea, anim, t) for t in (0.0, 1.0, 0.5))
    assert np.array_equal(s0.camera.position, sea.camera.position)
    assert np.allclose(s1.camera.position, anim["position_end"])
    assert np.allclose(sh.camera.look_at - sh.camera.position, sea.camera.look_at - sea.camera.position)
    fire = load_scene(scene_path("fire"))
    fa = A.load_animation("fire")
    f1 = A.frame_scene(fire, fa, 1.0)
    for a, b in zip(fire.textures["fire"].terms, f1.textures["fire"].terms):
        assert np.allclose(b.o - a.o, [0.0, 0.0, fa["phi_end"]]) and np.array_equal(a.T, b.T)
    assert np.array_equal(f1.camera.position, fire.camera.position)


def _anim(tmp_path, body):
    p = tmp_path / "a.toml"
    p.write_text("[animation]\n" + body)
    return str(p)


def test_still_animation_has_no_flicker_and_reuses_its_truth(tmp_path):
    """No motion: every frame the same image and truth, so the flicker is 0 exactly; a second
    run reads every frame's truth from the cache."""
    p = _anim(tmp_path, 'scene = "seascape"\nframes = 3\nposition_end = [0.0, 2.0, 0.0]\n')
    rep = A.run(p, "full", None, 8, out_root=tmp_path / "o", docs=False, progress=False, truth_ss=2, band_ss=4)
    assert all(r["band_pixels"] for r in rep["rows"])
    assert rep["frames"] == 3 and all(r["flicker_filtered_lsb"] == 0 == r["flicker_unfiltered_lsb"]
                                      for r in rep["rows"][1:] if r["band_pixels"])
    moving = A.run("seascape", "full", 3, 8, out_root=tmp_path / "o", docs=False, progress=False, truth_ss=2, band_ss=4)
    assert any(r.get("flicker_unfiltered_lsb") for r in moving["rows"][1:])
    assert len(list((tmp_path / "o" / "truth").glob("anim-*.npz"))) == 6
    again = A.run("seascape", "full", 3, 8, out_root=tmp_path / "o", docs=False, progress=False, truth_ss=2, band_ss=4)
    assert again["rows"] == moving["rows"]
    saved = json.loads((tmp_path / "o" / "animation" / "seascape" / "full-8" / "report.json").read_text())
    assert saved["status"] == "ok" and saved["mean"] == again["mean"]


@pytest.mark.parametrize("args,expected", [
    (["--scene", "nope"], "--scene nope: no animation (scenes/animation: fire, seascape)"),
    (["--frames", "1"], "--frames 1: expected 2..1000"),
    (["--size", "2"], "--size 2: expected 4..1024"),
    (["--config", "x"], "--config x: no such configuration"),
])
def test_bad_input_exits_2(capsys, tmp_path, args, expected):
    assert A.main([*args, "--out", str(tmp_path), "--quiet", "--no-docs"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("animation: ") and expected.replace("animation: fire", "animation/: fire") in err, err
    assert "\n" not in err


@pytest.mark.parametrize("body,expected", [
    ('scene = "seascape"\nspeed = 2\n', "animation.speed: unknown key"),
    ('frames = 2\n', "animation.scene: missing"),
    ('scene = "seascape"\nposition_end = [1, 2]\n', "animation.position_end: expected 3 numbers"),
    ('scene = "fire"\nphi_end = 1.0\n', "animation.phi_texture: missing"),
    ('scene = "fire"\nphi_texture = "smoke"\nphi_end = 1.0\n', "animation.phi_texture: no texture 'smoke'"),
    ('scene = "nowhere"\n', "animation.scene: no such scene 'nowhere'"),
])
def test_bad_animation_file(capsys, tmp_path, body, expected):
    p = _anim(tmp_path, body)
    assert A.main(["--scene", p, "--size", "4", "--out", str(tmp_path), "--quiet", "--no-docs"]) == 2
    err = capsys.readouterr().err.strip()
    assert expected in err and "a.toml" in err and "\n" not in err, err


def test_rtl_runs_every_frame_in_one_simulator_start_bit_exact(tmp_path, monkeypatch):
    """--rtl: every pass of every frame, filtered and unfiltered, through Verilator in one
    simulator start, every pixel bit-exact frame by frame; then a colour changed in the last
    frame's RTL output (the simulator replaced by the golden model) is reported on that frame."""
    from sim import frame_rtl as F

    kw = dict(out_root=tmp_path / "o", docs=False, progress=False, truth_ss=2, band_ss=4)
    before = F.STARTS
    rep = A.run("seascape", "full", 3, 8, rtl=True, **kw)
    rtl = rep["rtl"]
    assert rtl["starts"] == 1 == F.STARTS - before, rtl
    assert rtl["passes"] >= 2 * 3 and rtl["pixels"] > 0, rtl  # filtered and unfiltered, every frame
    assert rep["rtl_bit_exact"] is True and [r["rtl_mismatches"] for r in rep["rows"]] == [0, 0, 0]
    saved = json.loads((tmp_path / "o" / "animation" / "seascape" / "full-8" / "report.json").read_text())
    assert saved["rtl"] == rtl and saved["rtl_bit_exact"] is True

    from model.hw import golden

    def fake(cfg, sim, passes, return_stats=False, **_):
        out = [golden.texture_pipeline(load_config(cfg), *p).astype(np.uint8) for p in passes]
        out[-1][0, 1] ^= 1  # one bit of one pixel of the last frame's last pass
        return out, {"starts": 0, "seconds": 0.0, "cycles": [], "runs": []}

    monkeypatch.setattr(F, "run_passes_rtl", fake)
    with pytest.raises(A.UserError, match=r"differs from the golden model on frame\(s\) \[2\]"):
        A.run("seascape", "full", 3, 8, rtl=True, **kw)
