"""Scene files: every shipped scene parses; every kind of error is one line naming file and key."""
from __future__ import annotations

import glob
import os
import subprocess
import sys

import numpy as np
import pytest

from model.scene.scene import SceneError, colormap_to_clut, load_scene, parse_scene

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = sorted(glob.glob(os.path.join(ROOT, "scenes", "*.toml")))
NAMES = ["fire", "marble", "moonrise", "planet", "seascape", "torus", "wood", "zone_plate"]

VALID = """
[scene]
name = "mini"
background = [10, 20, 30, 255]

[camera]
width = 32
height = 24
position = [0.0, 0.0, 4.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov_deg = 40.0

[[object]]
type = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
texture = "t"

[texture.t]
quadric = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]
mode = "mod"
size = 16
colormap = [[0.0, 0, 0, 0, 255], [0.5, 255, 0, 0, 255], [1.0, 255, 255, 255, 255]]

[[texture.t.noise]]
a = 0.5
T = 2.0
"""


def test_all_eight_scenes_present():
    assert [os.path.splitext(os.path.basename(s))[0] for s in SCENES] == NAMES


@pytest.mark.parametrize("path", SCENES, ids=[os.path.basename(s) for s in SCENES])
def test_scene_parses(path):
    sc = load_scene(path)
    assert sc.name == os.path.splitext(os.path.basename(path))[0]
    assert sc.width > 0 and sc.height > 0
    assert sc.background.dtype == np.uint8 and sc.background.shape == (4,)
    assert sc.objects and sc.textures and sc.layers
    for t in sc.textures.values():
        n = len(t.clut)
        assert n & (n - 1) == 0 and n <= 256
        assert len(t.terms) <= 8


def test_valid_minimal():
    sc = parse_scene(VALID, "mini.toml")
    assert (sc.width, sc.height) == (32, 24)
    assert list(sc.background) == [10, 20, 30, 255]
    t = sc.textures["t"]
    assert t.clut.shape == (16, 4) and t.mode == "mod" and t.blend == "cubic" and t.filter
    assert np.array_equal(t.terms[0].T, 2 * np.eye(3)) and t.terms[0].a == 0.5
    assert sc.objects[0].name == "sphere0" and sc.layers == ["sphere0"]


def _err(text, tmp_path, name="bad.toml"):
    f = tmp_path / name
    f.write_text(text)
    with pytest.raises(SceneError) as ei:
        load_scene(f)
    msg = str(ei.value)
    assert "\n" not in msg
    assert msg.startswith(str(f) + ": ")
    return msg


CASES = {
    # kind: (transform of VALID, key path expected in the message, a word expected)
    "malformed_toml": (lambda s: s.replace("[camera]", "[camera"), "(toml)", "malformed TOML"),
    "duplicate_key": (lambda s: s.replace("width = 32", "width = 32\nwidth = 33"), "(toml)", "malformed TOML"),
    "unknown_top": (lambda s: "lights = 3\n" + s, "lights", "unknown key"),
    "unknown_object_key": (lambda s: s.replace("radius = 1.0", "radius = 1.0\nraduis = 1.0"), "object[0].raduis", "unknown key"),
    "unknown_texture_key": (lambda s: s.replace('mode = "mod"', 'mode = "mod"\nmodes = 1'), "texture.t.modes", "unknown key"),
    "unknown_noise_key": (lambda s: s.replace("T = 2.0", "T = 2.0\nphase = 1.0"), "texture.t.noise[0].phase", "unknown key"),
    "missing_radius": (lambda s: s.replace("radius = 1.0\n", ""), "object[0].radius", "missing"),
    "unknown_table": (lambda s: s.replace("[camera]", "[cameraX]"), "cameraX", "unknown key"),
    "missing_camera": (lambda s: s[:s.index("[camera]")] + s[s.index("[[object]]"):], "camera", "missing"),
    "missing_fov": (lambda s: s.replace("fov_deg = 40.0\n", ""), "camera.fov_deg", "missing"),
    "missing_quadric": (lambda s: s.replace("quadric = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]\n", ""),
                        "texture.t.quadric", "missing"),
    "missing_colormap": (lambda s: s.replace("colormap = [[0.0, 0, 0, 0, 255], [0.5, 255, 0, 0, 255], "
                                             "[1.0, 255, 255, 255, 255]]\n", ""), "texture.t.colormap", "missing"),
    "missing_a": (lambda s: s.replace("a = 0.5\n", ""), "texture.t.noise[0].a", "missing"),
    "type_a": (lambda s: s.replace("a = 0.5", 'a = "x"'), "texture.t.noise[0].a", "expected a number"),
    "type_width": (lambda s: s.replace("width = 32", "width = 32.5"), "camera.width", "integer"),
    "type_bool": (lambda s: s.replace('mode = "mod"', 'mode = "mod"\nfilter = 1'), "texture.t.filter", "true or false"),
    "type_vec": (lambda s: s.replace("center = [0.0, 0.0, 0.0]", "center = [0.0, 0.0]"), "object[0].center", "3 numbers"),
    "type_vec_elem": (lambda s: s.replace("center = [0.0, 0.0, 0.0]", 'center = [0.0, "a", 0.0]'), "object[0].center[1]", "number"),
    "type_T": (lambda s: s.replace("T = 2.0", "T = [1.0, 2.0]"), "texture.t.noise[0].T", "3x3"),
    "type_objtype": (lambda s: s.replace('type = "sphere"', 'type = "cone"'), "object[0].type", "one of"),
    "range_radius": (lambda s: s.replace("radius = 1.0", "radius = -1.0"), "object[0].radius", "> 0"),
    "range_fov": (lambda s: s.replace("fov_deg = 40.0", "fov_deg = 200.0"), "camera.fov_deg", "(0, 180)"),
    "range_size": (lambda s: s.replace("size = 16", "size = 300"), "texture.t.size", "power of two"),
    "range_size_pow2": (lambda s: s.replace("size = 16", "size = 24"), "texture.t.size", "power of two"),
    "range_colour": (lambda s: s.replace("[0.5, 255, 0, 0, 255]", "[0.5, 256, 0, 0, 255]"), "texture.t.colormap[1][1]", "[0, 255]"),
    "range_stop_pos": (lambda s: s.replace("[1.0, 255, 255, 255, 255]", "[1.5, 255, 255, 255, 255]"), "texture.t.colormap[2][0]", "[0, 1]"),
    "range_a": (lambda s: s.replace("a = 0.5", "a = 9.0"), "texture.t.noise[0].a", "[-8, 7.9997559] (the widest configuration, full_wide s16.12)"),
    "range_T": (lambda s: s.replace("T = 2.0", "T = 200.0"), "texture.t.noise[0].T", "[-64, 63.999512] (the widest configuration, full s18.18 x 2^[0..7])"),
    # issue 16: |T| in [64, 128) passed the parser although no configuration holds it
    "range_T_64": (lambda s: s.replace("T = 2.0", "T = 64.0"), "texture.t.noise[0].T", "full s18.18 x 2^[0..7]"),
    # issue 16: fractional colour-table entries were rounded silently
    "entries_fraction": (lambda s: s.replace("size = 16\ncolormap = [[0.0, 0, 0, 0, 255], [0.5, 255, 0, 0, 255], "
                                             "[1.0, 255, 255, 255, 255]]", "entries = [[127.5, 0, 0, 255]]"),
                         "texture.t.entries[0][0]", "not rounded"),
    "background_fraction": (lambda s: s.replace("background = [10, 20, 30, 255]", "background = [10.5, 20, 30, 255]"),
                            "scene.background[0]", "integer 0..255"),
    "range_quadric": (lambda s: s.replace("quadric = [1.0,", "quadric = [500.0,"), "texture.t.quadric[0]", "[-128, 127.999999046] (the widest configuration, full s28.20)"),
    "range_background": (lambda s: s.replace("background = [10, 20, 30, 255]", "background = [10, 20, 30, 999]"),
                         "scene.background[3]", "255"),
    "stop_order": (lambda s: s.replace("[0.5, 255, 0, 0, 255], [1.0,", "[0.5, 255, 0, 0, 255], [0.25,"),
                   "texture.t.colormap[2][0]", "non-decreasing"),
    "stop_shape": (lambda s: s.replace("[0.5, 255, 0, 0, 255]", "[0.5, 255, 0, 0]"), "texture.t.colormap[1]", "colour stop"),
    "undefined_texture": (lambda s: s.replace('texture = "t"', 'texture = "wood"'), "object[0].texture", "texture.NAME"),
    "too_many_terms": (lambda s: s + "\n[[texture.t.noise]]\na = 0.1\nT = 1.0\n" * 8, "texture.t.noise", "at most 8"),
    "entries_and_colormap": (lambda s: s.replace("size = 16", "entries = [[0, 0, 0, 255]]"), "texture.t.colormap", "exactly one"),
    "entries_len": (lambda s: s.replace("size = 16\ncolormap = [[0.0, 0, 0, 0, 255], [0.5, 255, 0, 0, 255], "
                                        "[1.0, 255, 255, 255, 255]]",
                                        "entries = [[0, 0, 0, 255], [1, 1, 1, 255], [2, 2, 2, 255]]"),
                    "texture.t.entries", "power of two"),
    "up_parallel": (lambda s: s.replace("up = [0.0, 1.0, 0.0]", "up = [0.0, 0.0, 2.0]"), "camera.up", "not parallel"),
    "box_order": (lambda s: s.replace('type = "sphere"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0',
                                      'type = "box"\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, -1.0, 1.0]'), "object[0].max", "max > min"),
    "torus_minor": (lambda s: s.replace('type = "sphere"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0',
                                        'type = "torus"\ncenter = [0.0, 0.0, 0.0]\naxis = [0.0, 1.0, 0.0]\n'
                                        'major = 1.0\nminor = 1.5'), "object[0].minor", "major"),
    "nonplanar_quad": (lambda s: s.replace('type = "sphere"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0',
                                           'type = "quad"\nvertices = [[0, 0, 0], [1, 0, 0], [1, 1, 0.3], [0, 1, 0]]'),
                       "object[0].vertices", "coplanar"),
    "plane_extent_missing": (lambda s: s.replace('type = "sphere"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0',
                                                 'type = "plane"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]'),
                             "object[0].extent", "missing"),
    "mesh_index": (lambda s: s.replace('type = "sphere"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0',
                                       'type = "mesh"\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n'
                                       'triangles = [[0, 1, 3]]'), "object[0].triangles[0]", "vertex indices"),
    "mesh_builtin": (lambda s: s.replace('type = "sphere"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0',
                                         'type = "mesh"\nbuiltin = "bunny"'), "object[0].builtin", "teapot"),
    "layer_textures": (lambda s: s.replace('texture = "t"', 'texture = "t"\nlayer = "L"')
                       + '\n[[object]]\ntype = "sphere"\ncenter = [1, 0, 0]\nradius = 0.5\ntexture = "u"\nlayer = "L"\n'
                       + '[texture.u]\nquadric = [0, 0, 0, 0, 0, 0, 0, 0, 0, 0]\nentries = [[0, 0, 0, 255]]\n',
                       "object[1].layer", "share texture"),
    "duplicate_name": (lambda s: s.replace('texture = "t"', 'texture = "t"\nname = "ball"')
                       + '\n[[object]]\nname = "ball"\ntype = "sphere"\ncenter = [1, 0, 0]\nradius = 0.5\ntexture = "t"\n',
                       "object[1].name", "no other object"),
    "ortho_with_fov": (lambda s: s.replace("fov_deg = 40.0", 'fov_deg = 40.0\nprojection = "orthographic"\northo_height = 2.0'),
                       "camera.fov_deg", "orthographic"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_error_one_line_names_file_and_key(case, tmp_path):
    fix, key, word = CASES[case]
    text = fix(VALID)
    assert text != VALID
    msg = _err(text, tmp_path)
    assert f": {key}: " in msg, msg
    assert word in msg, msg


def test_errors_in_object_keys_of_later_objects(tmp_path):
    text = VALID + '\n[[object]]\ntype = "sphere"\ncenter = [1, 0, 0]\nradius = "big"\ntexture = "t"\n'
    msg = _err(text, tmp_path)
    assert ": object[1].radius: " in msg and "'big'" in msg


def test_unreadable_and_non_utf8(tmp_path):
    with pytest.raises(SceneError) as ei:
        load_scene(tmp_path / "nope.toml")
    assert "nope.toml" in str(ei.value) and "\n" not in str(ei.value)
    f = tmp_path / "bin.toml"
    f.write_bytes(b"\xff\xfe[camera]\n")
    with pytest.raises(SceneError) as ei:
        load_scene(f)
    assert "bin.toml" in str(ei.value) and "\n" not in str(ei.value)


def test_cli_exit_codes(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(VALID.replace("a = 0.5", 'a = "x"'))
    r = subprocess.run([sys.executable, "-m", "model.scene.scene", str(bad)], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(str(bad)) and "texture.t.noise[0].a" in lines[0]
    assert r.stdout == ""
    good = os.path.join(ROOT, "scenes", "wood.toml")
    r = subprocess.run([sys.executable, "-m", "model.scene.scene", good], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0 and "wood" in r.stdout and r.stderr == ""


def test_colormap_sampling():
    # a hard step at 0.5: entries below are exactly the left colour, above the right colour
    stops = np.array([[0.0, 0, 0, 0, 255], [0.5, 0, 0, 0, 255], [0.5, 255, 255, 255, 255], [1.0, 255, 255, 255, 255]], float)
    c = colormap_to_clut(stops, 256)
    assert np.all(c[:128] == [0, 0, 0, 255]) and np.all(c[128:] == 255)
    # a linear ramp is sampled at the entry centres (k + 0.5)/N, rounded half up
    c = colormap_to_clut(np.array([[0.0, 0, 0, 0, 0], [1.0, 255, 255, 255, 255]], float), 4)
    assert list(c[:, 0]) == [32, 96, 159, 223]
    # stops inside (0, 1): constant colour outside them
    c = colormap_to_clut(np.array([[0.25, 10, 10, 10, 10], [0.75, 20, 20, 20, 20]], float), 8)
    assert list(c[:, 0]) == [10, 10, 11, 14, 16, 19, 20, 20]
    # a single stop: constant
    assert np.all(colormap_to_clut(np.array([[0.3, 1, 2, 3, 4]], float), 2) == [1, 2, 3, 4])


def test_T_forms_and_entries():
    text = VALID.replace("T = 2.0", "T = [1.0, 0.0, 4.0]\no = [0.0, 0.0, 0.25]") + (
        "\n[[texture.t.noise]]\na = 0.25\nT = [[1.0, 2.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n")
    t = parse_scene(text).textures["t"]
    assert np.array_equal(t.terms[0].T, np.diag([1.0, 0.0, 4.0])) and np.array_equal(t.terms[0].o, [0, 0, 0.25])
    assert t.terms[1].T[0, 1] == 2.0
    text = VALID.replace("size = 16\ncolormap = [[0.0, 0, 0, 0, 255], [0.5, 255, 0, 0, 255], [1.0, 255, 255, 255, 255]]",
                         "entries = [[0, 0, 0, 255], [255, 128, 0, 64]]")
    t = parse_scene(text).textures["t"]
    assert t.clut.tolist() == [[0, 0, 0, 255], [255, 128, 0, 64]]
