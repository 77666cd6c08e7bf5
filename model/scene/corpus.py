"""Scene corpora: seeded random scenes of the kind a user of the paper's model writes, and a
fixed list of hard cases.

A configuration's formats are chosen on a **fit** corpus (seed FIT_SEED) plus the eight paper
scenes, and its promise is checked on a disjoint **held-out** corpus (seed HELDOUT_SEED, plus
the hard cases, which nothing is tuned on). `generate(seed, n)` returns n scenes as
(name, TOML text); the same seed gives the same scenes on any machine (numpy's PCG64 seeded
with (seed, index), so scene k does not depend on n). `hard_cases()` returns the fixed list.
`write_corpus(out_dir, seed, n, hard)` writes them as files with an index.json that tags each
scene with what it needs of the hardware (model.scene.texture_needs.texture_needs of each texture:
transform, amplitude and quadric kinds, terms, blend, table size, mode, filter), so that a
configuration that accepts only some kinds (pow2 T, a diagonal quadric, K terms) is measured
on the sub-corpus it can render. The command is `make corpus SEED= N=` (explore.validate).

What a random scene holds (every value inside the ranges the scene format documents for the
paper's full model, model/scene/scene.py):
- geometry: a plane to the horizon, a sphere, a torus, a box, the teapot mesh, a tilted quad,
  or a screen-space close-up; a fifth of the scenes add a second object with its own texture;
  perspective or orthographic cameras;
- the texture matrix: a random rotation times a scale, plus an offset, so that s has the
  scene's own orientation and range (up to |s| ~ 100 on the horizon planes);
- the quadric: a ramp, a diagonal quadratic or a general one with cross terms (B, C, F), at
  non-round coefficients sized so that f spans a few table periods over the object;
- 0..8 noise terms of one of three families: rotated (T_i = 2^i s_i R_i S_i, R_i random
  rotations, S_i anisotropic scales from 1/4 upwards, some sheared), non-power-of-two
  diagonal, or a power-of-two fractal sum (T_i = 2^i, a_i = 2^-i), with any amplitudes and
  offsets outside the pow2 family; the largest T entry kept under the format limit (64);
- the colour table: 1..256 entries from stops (some with hard steps) or from explicit
  entries (smooth walks or harsh), mod or clamp, some with alpha; filter on in most scenes,
  the noise gradient in most; linear or cubic blend.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

FIT_SEED = 1
HELDOUT_SEED = 2
T_LIMIT = 63.0  # largest |T entry| written (the scene format's T range is [-64, 64))
S_LIMIT = 100.0  # |s| the random scenes stay under (every configuration's s range is [-128, 128))


# ---------------------------------------------------------------------------- TOML writing

def _num(x) -> str:
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    x = float(x)
    if x == int(x) and abs(x) < 1e15:
        return f"{x:.1f}"
    return repr(round(x, 9))


def _val(v) -> str:
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_val(x) for x in v) + "]"
    return _num(v)


def to_toml(scene: dict) -> str:
    """The scene dict ({'comment', 'scene', 'camera', 'object': [...], 'texture': {name: {...,
    'noise': [...]}}}) as a scene file."""
    out = [f"# {line}" for line in scene.get("comment", "").splitlines()]
    for table in ("scene", "camera"):
        out += ["", f"[{table}]"] + [f"{k} = {_val(v)}" for k, v in scene[table].items()]
    for obj in scene["object"]:
        out += ["", "[[object]]"] + [f"{k} = {_val(v)}" for k, v in obj.items()]
    for name, tex in scene["texture"].items():
        out += ["", f"[texture.{name}]"] + [f"{k} = {_val(v)}" for k, v in tex.items() if k != "noise"]
        for term in tex.get("noise", []):
            out += [f"[[texture.{name}.noise]]"] + [f"{k} = {_val(v)}" for k, v in term.items()]
    return "\n".join(out) + "\n"


# ---------------------------------------------------------------------------- random pieces

def rotation(axis, deg: float) -> np.ndarray:
    """The rotation by deg degrees about axis (Rodrigues)."""
    k = np.asarray(axis, dtype=np.float64)
    k = k / np.linalg.norm(k)
    t = math.radians(deg)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(t) * K + (1 - math.cos(t)) * (K @ K)


def _random_rotation(rng) -> np.ndarray:
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def _loguni(rng, lo, hi) -> float:
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def _r(x, digits=6):
    return np.round(np.asarray(x, dtype=np.float64), digits)


def _noise_terms(rng, family: str, k: int) -> list[dict]:
    """k noise terms of a family (rotated, diagonal, pow2), most significant first."""
    terms = []
    if family == "pow2":
        base = 2.0 ** int(rng.integers(-1, 3))
        a0 = 2.0 ** -int(rng.integers(1, 3))
        for i in range(k):
            t = base * 2.0 ** i
            if t > T_LIMIT:
                break
            terms.append({"a": a0 * 2.0 ** -i, "T": t})
        return terms
    base = _loguni(rng, 0.15, 4.0)
    lac = rng.uniform(1.6, 2.2)  # lacunarity: not a power of two
    gain = rng.uniform(0.4, 0.6)
    a0 = rng.uniform(0.15, 0.8) * rng.choice([-1.0, 1.0], p=[0.2, 0.8])
    R = _random_rotation(rng)
    for i in range(k):
        scale = base * lac ** i
        if family == "rotated":
            S = np.diag([_loguni(rng, 0.25, 1.0) ** 0.5 * scale for _ in range(3)])
            Ri = _random_rotation(rng) if rng.random() < 0.5 else np.linalg.matrix_power(R, i + 1)
            T = Ri @ S
            if rng.random() < 0.3:  # a shear
                Sh = np.eye(3)
                Sh[int(rng.integers(0, 3)), int(rng.integers(0, 3))] += rng.uniform(-0.8, 0.8)
                T = T @ Sh
        else:  # diagonal, non-power-of-two entries, some negative
            T = np.diag([scale * rng.uniform(0.6, 1.4) * rng.choice([-1.0, 1.0], p=[0.25, 0.75]) for _ in range(3)])
        m = np.max(np.abs(T))
        if m > T_LIMIT:
            if i == 0:
                T = T * (T_LIMIT / m)
            else:
                break
        term = {"a": float(_r(a0 * gain ** i * rng.uniform(0.8, 1.25))), "T": _r(T).tolist()}
        if rng.random() < 0.5:
            term["o"] = _r(rng.uniform(-40, 40, 3), 4).tolist()
        terms.append(term)
    return terms


def _colour_table(rng, n_log2: int) -> dict:
    n = 1 << n_log2
    alpha = rng.random() < 0.2
    if rng.random() < 0.6:  # stops
        k = int(rng.integers(2, 9))
        pos = np.sort(rng.uniform(0, 1, k))
        pos[0], pos[-1] = 0.0, 1.0
        if k > 2 and rng.random() < 0.3:
            j = int(rng.integers(1, k - 1))
            pos[j + 1] = pos[j]  # a hard step
        stops = []
        for p in pos:
            c = rng.integers(0, 256, 3).tolist()
            stops.append([round(float(p), 4)] + c + [int(rng.integers(40, 256)) if alpha else 255])
        return {"size": n, "colormap": stops}
    if rng.random() < 0.5:  # a smooth random walk
        walk = np.cumsum(rng.normal(0, 24, (n, 4)), axis=0) + rng.uniform(60, 200, 4)
        ent = np.clip(np.rint(walk), 0, 255).astype(int)
    else:  # harsh
        ent = rng.integers(0, 256, (n, 4))
    if not alpha:
        ent[:, 3] = 255
    return {"entries": ent.tolist()}


def _quadric(rng, smax: float, kind: str, mode: str) -> list[float]:
    """Coefficients A..J sized so that f spans a few table periods over |s| <= smax."""
    Q = np.zeros(10)
    periods = _loguni(rng, 0.5, 12.0) if mode == "mod" else 0.4
    if kind == "ramp":
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        Q[[3, 6, 8]] = d * periods / (2 * smax)  # 2D s + 2G t + 2I r
    else:
        q2 = periods / smax ** 2
        Q[[0, 4, 7]] = rng.uniform(-1, 1, 3) * q2  # A, E, H
        if kind == "cross":
            Q[[1, 2, 5]] = rng.uniform(-1, 1, 3) * q2  # B, C, F
        Q[[3, 6, 8]] = rng.uniform(-1, 1, 3) * periods / (4 * smax)
    Q[9] = rng.uniform(0.2, 0.6) if mode == "clamp" else rng.uniform(-2, 2)
    return [float(x) for x in _r(Q, 7)]


def _texture(rng, smax: float) -> dict:
    mode = "mod" if rng.random() < 0.65 else "clamp"
    r = rng.random()
    qkind = "ramp" if r < 0.35 else "diagonal" if r < 0.65 else "cross"
    k = int(rng.choice(np.arange(9), p=[0.08] + [0.115] * 8))
    family = str(rng.choice(["rotated", "diagonal", "pow2"], p=[0.45, 0.2, 0.35]))
    n_log2 = int(rng.choice(np.arange(9), p=[0.03, 0.03, 0.04, 0.05, 0.1, 0.1, 0.15, 0.15, 0.35]))
    tex = {"quadric": _quadric(rng, smax, qkind, mode), "blend": str(rng.choice(["cubic", "linear"], p=[0.75, 0.25])), "mode": mode}
    if rng.random() < 0.15:
        tex["filter"] = False
    if rng.random() < 0.1:
        tex["noise_gradient"] = False
    tex.update(_colour_table(rng, n_log2))
    terms = _noise_terms(rng, family, k)
    if mode == "clamp":  # keep f mostly inside the table
        for t in terms:
            t["a"] = float(_r(t["a"] * 0.5))
    if terms:
        tex["noise"] = terms
    return tex


def _tm(rng, scale: float) -> list:
    """A texture matrix: a random rotation times scale, plus an offset."""
    M = _random_rotation(rng) * scale if rng.random() < 0.7 else np.eye(3) * scale
    off = rng.uniform(-4, 4, 3)
    return _r(np.hstack([M, off[:, None]])).tolist()


def _camera(rng, dist: float, ortho: bool = False, look=(0.0, 0.0, 0.0)) -> dict:
    d = rng.normal(size=3)
    d[1] = abs(d[1]) + 0.3
    d = d / np.linalg.norm(d) * dist
    cam = {"width": 128, "height": 128, "position": _r(np.asarray(look) + d, 4).tolist(),
           "look_at": list(look), "up": [0.0, 1.0, 0.0]}
    if ortho:
        cam.update({"projection": "orthographic", "ortho_height": round(dist * 0.8, 3)})
    else:
        cam["fov_deg"] = round(float(rng.uniform(30, 60)), 2)
    return cam


def _object(rng, geom: str, tex: str) -> tuple[dict, float]:
    """An object of a geometry and the largest |s| its texture matrix gives (approximately)."""
    if geom == "plane":
        extent = _loguni(rng, 20, 800)
        scale = min(S_LIMIT / (extent + 5), _loguni(rng, 0.05, 1.0))
        M = np.array([[scale, 0, 0], [0, 0, scale], [0, scale, 0]]) @ rotation([0, 1, 0], rng.uniform(0, 360))
        tm = _r(np.hstack([M, rng.uniform(-2, 2, (3, 1))])).tolist()
        return ({"type": "plane", "point": [0.0, 0.0, 0.0], "normal": [0.0, 1.0, 0.0], "extent": round(extent, 2),
                 "texture": tex, "texture_matrix": tm}, scale * extent + 2)
    scale = _loguni(rng, 0.5, 4.0)
    if geom == "screen":
        scale = _loguni(rng, 0.02, 8.0)  # a close-up (a small scale magnifies the texture)
        return {"type": "screen", "texture": tex, "texture_matrix": _tm(rng, scale)}, scale + 4
    if geom == "sphere":
        obj = {"type": "sphere", "center": [0.0, 0.0, 0.0], "radius": 1.0}
    elif geom == "torus":
        obj = {"type": "torus", "center": [0.0, 0.0, 0.0], "axis": _r(rng.normal(size=3) + [0, 2, 0], 3).tolist(),
               "major": 1.0, "minor": round(float(rng.uniform(0.2, 0.5)), 3)}
    elif geom == "box":
        lo = -rng.uniform(0.5, 1.0, 3)
        obj = {"type": "box", "min": _r(lo, 3).tolist(), "max": _r(-lo, 3).tolist()}
    elif geom == "mesh":
        obj = {"type": "mesh", "builtin": "teapot", "subdivisions": 4,
               "transform": [[0.5, 0.0, 0.0, 0.0], [0.0, 0.0, 0.5, -0.8], [0.0, -0.5, 0.0, 0.0]]}
    else:  # a tilted quad
        R = _random_rotation(rng)
        v = [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]
        obj = {"type": "quad", "vertices": _r(np.asarray(v, float) @ R.T * 1.2, 12).tolist()}
    obj.update({"texture": tex, "texture_matrix": _tm(rng, scale)})
    return obj, scale * 1.8 + 4


GEOMETRIES = ("plane", "sphere", "torus", "box", "mesh", "quad", "screen")


def random_scene(seed: int, index: int) -> tuple[str, str]:
    """Scene `index` of corpus `seed`: (name, TOML text)."""
    rng = np.random.default_rng([int(seed), int(index)])
    name = f"c{seed}_{index:04d}"
    geom = str(rng.choice(GEOMETRIES, p=[0.22, 0.16, 0.12, 0.14, 0.1, 0.1, 0.16]))
    objs, texs = [], {}
    obj, smax = _object(rng, geom, "t0")
    objs.append(obj)
    texs["t0"] = _texture(rng, smax)
    if geom == "plane":
        cam = _camera(rng, 1.0, look=(0.0, 0.0, 0.0))
        cam["position"] = [0.0, round(float(rng.uniform(0.5, 3.0)), 3), 0.0]
        cam["look_at"] = [0.0, round(float(cam["position"][1] - rng.uniform(0.5, 8.0)), 3), -30.0]
        cam["fov_deg"] = round(float(rng.uniform(35, 60)), 2)
    else:
        cam = _camera(rng, float(rng.uniform(3.0, 5.0)), ortho=rng.random() < 0.15)
    if geom not in ("screen",) and rng.random() < 0.2:  # a second object, its own texture
        obj2, smax2 = _object(rng, str(rng.choice(["sphere", "box", "quad"])), "t1")
        for key, off in (("center", 0.6), ("min", 0.6), ("max", 0.6)):
            if key in obj2:
                obj2[key] = _r(np.asarray(obj2[key]) * 0.5 + [0, off, 0.3], 4).tolist()
        if "radius" in obj2:
            obj2["radius"] = 0.5
        if "vertices" in obj2:
            obj2["vertices"] = _r(np.asarray(obj2["vertices"]) * 0.5 + [0, 0.6, 0.3], 12).tolist()
        if geom == "plane":  # in front of the horizon camera
            for key in ("center", "min", "max"):
                if key in obj2:
                    obj2[key] = _r(np.asarray(obj2[key]) + [0, cam["position"][1] - 1.0, -4.0], 4).tolist()
            if "vertices" in obj2:
                obj2["vertices"] = _r(np.asarray(obj2["vertices"]) + [0, cam["position"][1] - 1.0, -4.0], 5).tolist()
        objs.append(obj2)
        texs["t1"] = _texture(rng, smax2)
    bg = rng.integers(0, 256, 3).tolist() + [255]
    scene = {"comment": f"corpus seed {seed}, scene {index}: {geom} (model/scene/corpus.py; regenerate, do not edit)",
             "scene": {"name": name, "description": f"random {geom} scene", "background": bg},
             "camera": cam, "object": objs, "texture": texs}
    return name, to_toml(scene)


def generate(seed: int, n: int) -> list[tuple[str, str]]:
    return [random_scene(seed, i) for i in range(n)]


# ---------------------------------------------------------------------------- hard cases

def _screen(name, comment, tex, tm=None, rect=None, width=128) -> tuple[str, str]:
    obj = {"type": "screen", "texture": "t0",
           "texture_matrix": tm if tm is not None else [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]}
    if rect is not None:
        obj["rect"] = rect
    scene = {"comment": comment, "scene": {"name": name, "background": [20, 20, 20, 255]},
             "camera": {"width": width, "height": width, "position": [0.0, 0.0, 3.0], "look_at": [0.0, 0.0, 0.0],
                        "up": [0.0, 1.0, 0.0], "fov_deg": 40.0},
             "object": [obj], "texture": {"t0": tex}}
    return name, to_toml(scene)


_MARBLE_MAP = [[0.00, 238, 238, 234, 255], [0.30, 226, 226, 224, 255], [0.40, 180, 182, 190, 255],
               [0.47, 96, 100, 116, 255], [0.50, 62, 66, 84, 255], [0.54, 110, 114, 128, 255],
               [0.62, 200, 202, 206, 255], [1.00, 238, 238, 234, 255]]
_RAMP = [[0.0, 0, 0, 0, 255], [1.0, 255, 255, 255, 255]]
_ZEBRA = [[0.0, 0, 0, 0, 255], [0.5, 0, 0, 0, 255], [0.5, 255, 255, 255, 255], [1.0, 255, 255, 255, 255]]


def rotated_marble() -> tuple[str, str]:
    """The marble scene (scenes/marble.toml) with its four transforms rotated: T_i = 2^i R^i, R a
    30-degree rotation about (1, 1, 1); amplitudes 0.47, 0.23, 0.11, 0.06 (issue 26)."""
    R = rotation([1, 1, 1], 30.0)
    terms = [{"a": a, "T": _r(2.0 ** i * np.linalg.matrix_power(R, i), 9).tolist()}
             for i, a in zip(range(1, 5), (0.47, 0.23, 0.11, 0.06))]
    scene = {"comment": "hard case: marble (scenes/marble.toml) with T_i = 2^i R^i, R 30 degrees about (1,1,1)",
             "scene": {"name": "hard_rotated_marble", "background": [40, 44, 52, 255]},
             "camera": {"width": 512, "height": 512, "position": [3.0, 2.6, 4.2], "look_at": [0.0, 0.0, 0.0],
                        "up": [0.0, 1.0, 0.0], "fov_deg": 40.0},
             "object": [{"name": "cube", "type": "box", "min": [-1.0, -1.0, -1.0], "max": [1.0, 1.0, 1.0],
                         "texture": "marble",
                         "texture_matrix": [[1.5, 0.0, 0.0, 0.0], [0.0, 1.5, 0.0, 0.0], [0.8, 0.7, 0.5, 0.0]]}],
             "texture": {"marble": {"quadric": [0.0] * 8 + [0.5, 0.0], "blend": "cubic", "mode": "mod", "size": 256,
                                    "colormap": _MARBLE_MAP, "noise": terms}}}
    return "hard_rotated_marble", to_toml(scene)


def hard_cases() -> list[tuple[str, str]]:
    """The fixed hard cases (DESIGN.md's list): names start with hard_."""
    out = [rotated_marble()]
    R = rotation([1, 2, 3], 41.0)
    # |s| near the s range (+-128): a horizon plane whose s reaches ~124, noise far from the origin
    scene = {"comment": "hard case: |s| up to ~124 on a horizon plane (s range [-128, 128)); lattice far from the origin",
             "scene": {"name": "hard_s_limit", "background": [150, 170, 205, 255]},
             "camera": {"width": 128, "height": 128, "position": [0.0, 1.5, 0.0], "look_at": [0.0, 1.2, -30.0],
                        "up": [0.0, 1.0, 0.0], "fov_deg": 50.0},
             "object": [{"type": "plane", "point": [0.0, 0.0, 0.0], "normal": [0.0, 1.0, 0.0], "extent": 1200.0,
                         "texture": "t0", "texture_matrix": [[0.1, 0.0, 0.0, 0.0], [0.0, 0.0, 0.1, 0.0], [0.0, 0.1, 0.0, 2.0]]}],
             "texture": {"t0": {"quadric": [0.0] * 9 + [0.35], "mode": "clamp", "size": 256,
                                "colormap": [[0.0, 10, 40, 120, 255], [0.5, 60, 120, 200, 255], [1.0, 250, 250, 255, 255]],
                                "noise": [{"a": 0.31, "T": _r(1.7 * R).tolist()}, {"a": 0.16, "T": _r(3.3 * R @ R).tolist()},
                                          {"a": 0.083, "T": 6.1}]}}}
    out.append(("hard_s_limit", to_toml(scene)))
    # |T| near its limit (64): rotated transforms with entries up to ~63
    out.append(_screen("hard_T_limit", "hard case: T entries near the format limit (+-64)",
                       {"quadric": [0.0] * 6 + [0.0, 0.0, 0.5, 0.0], "mode": "mod", "size": 256, "colormap": _MARBLE_MAP,
                        "noise": [{"a": 0.4, "T": _r(63.0 * rotation([0, 0, 1], 45.0) / math.sqrt(2) * 1.41).tolist()},
                                  {"a": -0.2, "T": [-62.9, 31.7, 0.37]}]},
                       tm=[[0.3, 0.0, 0.0, 0.0], [0.0, 0.3, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]))
    # w = 0: f constant (no noise, a constant quadric)
    out.append(_screen("hard_w_zero", "hard case: f constant, w = 0 everywhere (filter on)",
                       {"quadric": [0.0] * 9 + [0.3], "mode": "mod", "size": 256, "colormap": _ZEBRA}))
    # w at the cap: a fast zone plate on a horizon plane
    scene = {"comment": "hard case: w up to the cap (a zone plate to the horizon)",
             "scene": {"name": "hard_w_cap", "background": [0, 0, 0, 255]},
             "camera": {"width": 128, "height": 128, "position": [0.0, 1.0, 0.0], "look_at": [0.0, 0.6, -10.0],
                        "up": [0.0, 1.0, 0.0], "fov_deg": 60.0},
             "object": [{"type": "plane", "point": [0.0, 0.0, 0.0], "normal": [0.0, 1.0, 0.0], "extent": 400.0,
                         "texture": "t0", "texture_matrix": [[0.25, 0.0, 0.0, 0.0], [0.0, 0.0, 0.25, 0.0], [0.0, 1.0, 0.0, 0.0]]}],
             "texture": {"t0": {"quadric": [0.37, 0.0, 0.0, 0.0, 0.37, 0.0, 0.0, 0.0, 0.0, 0.0], "mode": "mod",
                                "size": 256, "colormap": _ZEBRA}}}
    out.append(("hard_w_cap", to_toml(scene)))
    # f on entry boundaries: f = (x + 0.5) / 128 on a 128-px frame with a 256-entry table (f N = 2x + 1)
    for mode in ("mod", "clamp"):
        out.append(_screen(f"hard_f_boundaries_{mode}",
                           "hard case: at 128 px every pixel's f = (2x + 1)/256 lies on an entry boundary",
                           {"quadric": [0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], "mode": mode, "size": 256,
                            "colormap": _ZEBRA, "filter": False}))
    # f exactly 0, 1 and N: constant f at the ends, clamp
    out.append(_screen("hard_f_ends_clamp", "hard case: f = 0, 1 and 256 entries (clamp), three bands",
                       {"quadric": [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.75, 0.0, 0.0, -0.25], "mode": "clamp", "size": 256,
                        "colormap": _RAMP}, tm=[[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0]]))
    # N = 1
    out.append(_screen("hard_n1", "hard case: a one-entry table with noise",
                       {"quadric": [0.0] * 10, "mode": "mod", "entries": [[200, 120, 40, 255]],
                        "noise": [{"a": 0.5, "T": 3.3}]}))
    # amplitudes that saturate f in clamp mode, negative and non-power-of-two T
    out.append(_screen("hard_saturate_clamp", "hard case: noise amplitudes that drive f far past both ends (clamp)",
                       {"quadric": [0.0] * 9 + [0.5], "mode": "clamp", "size": 64, "colormap": _RAMP,
                        "noise": [{"a": 1.9, "T": [-3.7, 2.9, -1.3]}, {"a": -1.3, "T": _r(-7.1 * R).tolist()}]},
                       tm=[[2.0, 0.0, 0.0, 0.0], [0.0, 2.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.5]]))
    # eight terms, rotated, with a cross-term quadric: the whole model at once
    terms = [{"a": float(_r(0.5 * 0.55 ** i)), "T": _r(1.7 ** i * np.linalg.matrix_power(R, i)).tolist(),
              "o": [11.3 * i, -7.7, 3.1]} for i in range(8)]
    out.append(_screen("hard_eight_terms", "hard case: 8 rotated terms (lacunarity 1.7) on a cross-term quadric",
                       {"quadric": [0.31, 0.17, -0.11, 0.05, 0.23, 0.07, -0.09, -0.13, 0.21, 0.4], "mode": "mod",
                        "size": 256, "colormap": _MARBLE_MAP, "noise": terms},
                       tm=[[3.0, 0.0, 0.0, -1.5], [0.0, 3.0, 0.0, -1.5], [0.0, 0.0, 0.0, 0.7]]))
    return out


# ---------------------------------------------------------------------------- corpus on disk

def scene_tags(path) -> dict:
    """What a scene needs of the hardware, from its file alone (no rendering): the union over its
    textures of model.scene.texture_needs.texture_needs' kinds."""
    from model.scene.texture_needs import texture_needs
    from model.scene.scene import load_scene

    sc = load_scene(path)
    order = {"pow2": 0, "diagonal": 1, "affine": 2, "any": 1}
    tags = {"noise_terms": 0, "transform": "pow2", "amplitude": "pow2", "quadric": "diagonal", "blends": [],
            "table_entries": 0, "modes": [], "filtered": False, "noise_gradient": False, "alpha": False}
    for obj in sc.objects:
        tex = sc.textures[obj.texture]
        tn = texture_needs(tex)
        tags["noise_terms"] = max(tags["noise_terms"], tn["noise_terms"])
        for t in tn["transforms"]:
            if order[t] > order[tags["transform"]]:
                tags["transform"] = t
        if "any" in tn["amplitudes"]:
            tags["amplitude"] = "any"
        if tn["quadric"] == "full":
            tags["quadric"] = "full"
        if tn["blend"] and tn["blend"] not in tags["blends"]:
            tags["blends"].append(tn["blend"])
        if tn["mode"] not in tags["modes"]:
            tags["modes"].append(tn["mode"])
        tags["table_entries"] = max(tags["table_entries"], tn["table_entries"])
        tags["filtered"] |= tn["filtered"]
        tags["unfiltered"] = tags.get("unfiltered", False) or not tn["filtered"]
        tags["noise_gradient"] |= tn["noise_gradient"]
        tags["alpha"] |= bool(np.any(np.asarray(tex.clut)[:, 3] < 255))
    tags["objects"] = sorted({o.type for o in sc.objects})
    return tags


def write_corpus(out_dir, seed: int, n: int, hard: bool = False, progress=None) -> Path:
    """Write corpus `seed` (n random scenes, plus the hard cases if hard) under out_dir/seed<seed>/
    with index.json ([{name, file, hard, tags}]); the folder is replaced whole (written beside it,
    then moved into place), so a stale scene never survives."""
    import shutil
    import tempfile

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    final = out_dir / f"seed{seed}"
    tmp = Path(tempfile.mkdtemp(prefix=f".seed{seed}-", dir=out_dir))
    items = generate(seed, n) + (hard_cases() if hard else [])
    index = []
    try:
        for name, text in (progress(items) if progress else items):
            p = tmp / f"{name}.toml"
            p.write_text(text)
            index.append({"name": name, "file": p.name, "hard": name.startswith("hard_"), "tags": scene_tags(p)})
        (tmp / "index.json").write_text(json.dumps({"seed": seed, "n": n, "hard": hard, "scenes": index}, indent=1) + "\n")
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    if final.exists():
        shutil.rmtree(final)
    tmp.rename(final)
    return final


def load_index(corpus_dir) -> list[dict]:
    """The index of a written corpus, each entry with its 'path'."""
    corpus_dir = Path(corpus_dir)
    idx = json.loads((corpus_dir / "index.json").read_text())
    return [{**e, "path": corpus_dir / e["file"]} for e in idx["scenes"]]
