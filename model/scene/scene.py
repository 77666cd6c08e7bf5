"""Scene files: TOML parser and validation.

`load_scene(path)` reads a scene file (stdlib tomllib) and returns a `Scene`; any error --
malformed TOML, unknown key, missing field, wrong type, out-of-range value, colour stops
out of order, a reference to an undefined texture -- raises `SceneError`, whose str is ONE
line: ``<file>: <key path>: <what was expected>, got <what was found>``, e.g.
``scenes/wood.toml: texture.wood.noise[0].a: expected a number, got 'x'``.
``python -m model.scene.scene FILE...`` checks files: it prints a summary per file to stdout and
exits 0, or prints the error line to stderr and exits 2.

Schema (every key not listed is an error; [] = optional, with its default)
-------------------------------------------------------------------------
[scene]                       optional table
  [name]          str         default: the file's stem
  [description]   str
  [background]    [r,g,b,a]   integers 0..255, default [0,0,0,255]; what shows where no pass covers

[camera]                      required
  width, height   int         default image size, 1..16384 (render_passes may override)
  position, look_at, up       3-vectors; up must not be parallel to look_at - position
  [projection]    str         "perspective" (default) or "orthographic"
  fov_deg         number      vertical field of view, (0, 180); perspective only, required there
  ortho_height    number      world height of the view, > 0; orthographic only, required there

[[object]]                    one table per object, at least one
  type            str         screen | quad | polygon | triangle | plane | sphere | box | torus | mesh
  texture         str         name of a [texture.NAME] table
  [texture_matrix] 3x4        affine map from the world hit point P to s = (s,t,r):
                              s = M[:, :3] @ P + M[:, 3]; default [I | 0]
  [name]          str         unique among the objects, default "<type><index>"
  [layer]         str         objects with the same layer form ONE pass (z-buffered, nearest hit
                              wins) and must share a texture; default: the object's name, i.e.
                              each object its own layer
  per type:
    screen    [rect]           [x0, y0, x1, y1] in [0, 1] screen units (x right, y down), default
                               [0, 0, 1, 1]; pixels whose centre lies in rect are covered; the
                               "hit point" is P = ((x+0.5)/W, (y+0.5)/H, 0), depth 0 (front-most)
    quad      vertices         4 coplanar 3-vectors (any simple polygon, even-odd fill)
    polygon   vertices         >= 3 coplanar 3-vectors
    triangle  vertices         3 3-vectors
    plane     point, normal, extent   the plane through point, clipped to the disc of radius
                               extent around point ("to the horizon" but finite, so that |s|
                               stays inside the fixed-point range)
    sphere    center, radius
    box       min, max         axis-aligned, min < max on every axis
    torus     center, axis, major, minor     0 < minor < major
    mesh      either builtin = "teapot" [subdivisions = 8, 1..32]
              or vertices = [[x,y,z], ...] and triangles = [[i,j,k], ...] (0-based)
              [transform] 3x4  object -> world affine map applied to the vertices, default [I|0]

[texture.NAME]                one table per texture
  quadric         10 numbers  (inside the widest quadric format, full s24.16) A..J of eq. (3): q = A s^2 + 2B st + 2C sr + 2D s + E t^2
                              + 2F tr + 2G t + H r^2 + 2I r + J (note the factors 2)
  [blend]         str         "cubic" (default) or "linear" noise blend (whole texture)
  [mode]          str         "mod" (default) or "clamp"
  [filter]        bool        default true: box-filter the colour table (antialias)
  [noise_gradient] bool       default true: include a_i grad n_i in the filter width
  colour table: exactly one of
    colormap = [[pos, r, g, b, a], ...]   stops, pos in [0, 1] non-decreasing (two equal
                              positions make a hard step), colours 0..255; sampled at the
                              entry centres (k + 0.5)/N by linear interpolation, rounded;
                              [size] = N entries, a power of two 1..256, default 256
    entries = [[r, g, b, a], ...]         explicit table of integers 0..255, length a power of two 1..256
  [[texture.NAME.noise]]      0..8 terms a * n(T s + o), listed most significant first
    a             number      amplitude, inside the widest a format (full s16.12: [-8, 7.99976])
    T             number | 3-vector | 3x3   uniform scale, diagonal, or full matrix; every entry
                              inside the widest T format (full s17.10: [-64, 63.999])
    [o]           3-vector    offset in lattice units (the phase), default [0, 0, 0]

The value limits enforced here (quadric coefficients, a, T, the number of noise terms, the
colour-table size) are the widest over the configuration files (config/*.toml, read through
model.hw.config.widest_input_limits: no copy of a limit lives here). A configuration's own,
tighter limits are checked when the scene is quantized for it (model.hw.quantize) and listed
by `model.scene.frontend.fixed_point_violations`. Colour values of `entries` and `background`
are integers 0..255 (nothing is rounded); colour stops may be fractional (the table is
sampled and rounded, see colormap_to_clut).
"""
from __future__ import annotations

import math
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from model.texture import NoiseTerm, TextureParams

def _limits():
    """The widest input limits over the configuration files (model.hw.config), read once."""
    global _LIMITS
    if _LIMITS is None:
        from model.hw.config import widest_input_limits

        _LIMITS = widest_input_limits()
    return _LIMITS


_LIMITS = None

OBJECT_TYPES = ("screen", "quad", "polygon", "triangle", "plane", "sphere", "box", "torus", "mesh")
MAX_NOISE_TERMS = 8  # fallbacks only: the limits are read from the configurations (_limits)
MAX_CLUT = 256


class SceneError(ValueError):
    """A scene file error; str() is one line naming the file, the key path and the expectation."""

    def __init__(self, file, key, expected, got=None, *, raw=False):
        self.file, self.key = str(file), key
        if raw:
            msg = expected
        elif got is _MISSING:
            msg = f"missing (expected {expected})"
        elif got is _NOGOT:
            msg = f"expected {expected}"
        else:
            msg = f"expected {expected}, got {_show(got)}"
        self.msg = msg
        super().__init__(" ".join(f"{self.file}: {key}: {msg}".split()))


_MISSING = object()
_NOGOT = object()


class _Text(str):
    """A description shown as is in an error message (not quoted like a found string value)."""

    def __repr__(self):
        return str(self)


def _show(v) -> str:
    r = repr(v)
    return r if len(r) <= 60 else r[:57] + "..."


# ---------------------------------------------------------------------------- data classes


@dataclass
class Camera:
    position: np.ndarray
    look_at: np.ndarray
    up: np.ndarray
    projection: str = "perspective"  # or "orthographic"
    fov_deg: float = 45.0  # vertical, perspective
    ortho_height: float = 2.0  # world height of the view, orthographic

    def basis(self):
        """(forward, right, up_true), orthonormal; image x runs along right, image y along -up_true."""
        f = self.look_at - self.position
        f = f / np.linalg.norm(f)
        r = np.cross(f, self.up)
        r = r / np.linalg.norm(r)
        u = np.cross(r, f)
        return f, r, u


@dataclass
class SceneObject:
    name: str
    type: str
    texture: str
    texture_matrix: np.ndarray  # 3x4 float64, world point -> s
    layer: str
    params: dict  # per type, float64 arrays / floats (see module docstring); mesh: "vertices", "triangles", "clusters"
    index: int = 0  # position in the file


@dataclass
class Scene:
    path: str
    name: str
    width: int
    height: int
    background: np.ndarray  # uint8 [4] RGBA
    camera: Camera
    objects: list  # list of SceneObject, file order
    textures: dict  # name -> TextureParams
    description: str = ""
    layers: list = field(default_factory=list)  # layer names, file order of first appearance


# ---------------------------------------------------------------------------- value checkers


class _V:
    """Typed access to one TOML table with key paths for error messages."""

    def __init__(self, file, table, path):
        self.file, self.t, self.path = file, table, path

    def key(self, k):
        return f"{self.path}.{k}" if self.path else k

    def err(self, k, expected, got=_NOGOT):
        raise SceneError(self.file, self.key(k), expected, got)

    def check_keys(self, allowed):
        for k in self.t:
            if k not in allowed:
                raise SceneError(self.file, self.key(k), f"unknown key (expected one of: {', '.join(sorted(allowed))})",
                                 raw=True)

    def has(self, k):
        return k in self.t

    def get(self, k, what, default=_MISSING):
        if k not in self.t:
            if default is _MISSING:
                raise SceneError(self.file, self.key(k), what, _MISSING)
            return default
        return self.t[k]

    # scalars
    def num(self, k, default=_MISSING, lo=None, hi=None, lo_open=False, hi_open=False, what=None):
        desc = what or _range_desc("a number", lo, hi, lo_open, hi_open)
        v = self.get(k, desc, default)
        if v is default and default is not _MISSING:
            return default
        return _check_num(v, lambda: self.key(k), self.file, lo, hi, lo_open, hi_open, desc)

    def int(self, k, default=_MISSING, lo=None, hi=None, what=None):
        desc = what or _range_desc("an integer", lo, hi, False, False)
        v = self.get(k, desc, default)
        if v is default and default is not _MISSING:
            return default
        if isinstance(v, bool) or not isinstance(v, int):
            self.err(k, desc, v)
        if (lo is not None and v < lo) or (hi is not None and v > hi):
            self.err(k, desc, v)
        return v

    def str(self, k, default=_MISSING, choices=None):
        desc = "a string" if choices is None else "one of " + ", ".join(repr(c) for c in choices)
        v = self.get(k, desc, default)
        if v is default and default is not _MISSING:
            return default
        if not isinstance(v, str) or (choices is not None and v not in choices):
            self.err(k, desc, v)
        return v

    def bool(self, k, default=_MISSING):
        v = self.get(k, "true or false", default)
        if not isinstance(v, bool):
            self.err(k, "true or false", v)
        return v

    def vec(self, k, n, default=_MISSING, lo=None, hi=None, what=None):
        desc = what or f"a list of {n} numbers"
        v = self.get(k, desc, default)
        if v is default and default is not _MISSING:
            return np.asarray(default, dtype=np.float64)
        return _check_vec(v, n, lambda i=None: self.key(k) + ("" if i is None else f"[{i}]"),
                          self.file, desc, lo, hi)

    def mat(self, k, rows, cols, default=_MISSING):
        desc = f"a {rows}x{cols} matrix (a list of {rows} lists of {cols} numbers)"
        v = self.get(k, desc, default)
        if v is default and default is not _MISSING:
            return np.asarray(default, dtype=np.float64)
        return _check_mat(v, rows, cols, self.key(k), self.file, desc)

    def sub(self, k, default=_MISSING):
        v = self.get(k, "a table", default)
        if v is default and default is not _MISSING:
            return _V(self.file, {}, self.key(k))
        if not isinstance(v, dict):
            self.err(k, "a table", v)
        return _V(self.file, v, self.key(k))


def _range_desc(base, lo, hi, lo_open, hi_open):
    if lo is None and hi is None:
        return base
    if lo is not None and hi is not None:
        return f"{base} in {'(' if lo_open else '['}{lo}, {hi}{')' if hi_open else ']'}"
    if lo is not None:
        return f"{base} {'>' if lo_open else '>='} {lo}"
    return f"{base} {'<' if hi_open else '<='} {hi}"


def _is_num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _check_num(v, keyf, file, lo, hi, lo_open, hi_open, desc):
    if not _is_num(v) or not math.isfinite(v):
        raise SceneError(file, keyf(), desc, v)
    if lo is not None and (v < lo or (lo_open and v == lo)):
        raise SceneError(file, keyf(), desc, v)
    if hi is not None and (v > hi or (hi_open and v == hi)):
        raise SceneError(file, keyf(), desc, v)
    return float(v)


def _check_vec(v, n, keyf, file, desc, lo=None, hi=None):
    if not isinstance(v, list) or (n is not None and len(v) != n):
        raise SceneError(file, keyf(), desc, v)
    out = []
    for i, x in enumerate(v):
        edesc = _range_desc("a number", lo, hi, False, False)
        out.append(_check_num(x, lambda i=i: keyf(i), file, lo, hi, False, False, edesc))
    return np.asarray(out, dtype=np.float64)


def _check_mat(v, rows, cols, key, file, desc):
    if not isinstance(v, list) or len(v) != rows:
        raise SceneError(file, key, desc, v)
    out = []
    for i, row in enumerate(v):
        if not isinstance(row, list) or len(row) != cols:
            raise SceneError(file, f"{key}[{i}]", f"a list of {cols} numbers", row)
        out.append([_check_num(x, lambda i=i, j=j: f"{key}[{i}][{j}]", file, None, None, False, False,
                               "a number") for j, x in enumerate(row)])
    return np.asarray(out, dtype=np.float64)


def _check_ints4(v, keyf, file):
    """[r, g, b, a]: four integers 0..255 (a fractional colour is an error, not rounded)."""
    desc = "[r, g, b, a], each an integer 0..255"
    if not isinstance(v, list) or len(v) != 4:
        raise SceneError(file, keyf(), desc, v)
    for i, x in enumerate(v):
        ok_int = (isinstance(x, int) and not isinstance(x, bool)) or (isinstance(x, float) and x.is_integer())
        if not ok_int or not 0 <= x <= 255:
            raise SceneError(file, keyf(i), "an integer 0..255 (colour values are not rounded)", x)
    return [int(x) for x in v]


def _is_pow2(n):
    return n >= 1 and (n & (n - 1)) == 0


# ---------------------------------------------------------------------------- sections


def _parse_camera(file, root):
    if not root.has("camera"):
        raise SceneError(file, "camera", "a [camera] table", _MISSING)
    c = root.sub("camera")
    c.check_keys({"position", "look_at", "up", "fov_deg", "width", "height", "projection", "ortho_height"})
    width = c.int("width", lo=1, hi=16384)
    height = c.int("height", lo=1, hi=16384)
    pos = c.vec("position", 3)
    look = c.vec("look_at", 3)
    up = c.vec("up", 3)
    proj = c.str("projection", "perspective", ("perspective", "orthographic"))
    if proj == "perspective":
        fov = c.num("fov_deg", lo=0, hi=180, lo_open=True, hi_open=True)
        if c.has("ortho_height"):
            c.err("ortho_height", "no ortho_height with a perspective projection", c.t["ortho_height"])
        ortho = 2.0
    else:
        ortho = c.num("ortho_height", lo=0, lo_open=True)
        if c.has("fov_deg"):
            c.err("fov_deg", "no fov_deg with an orthographic projection", c.t["fov_deg"])
        fov = 45.0
    fwd = look - pos
    if np.linalg.norm(fwd) < 1e-12:
        c.err("look_at", "a point different from camera.position", c.t["look_at"])
    if np.linalg.norm(np.cross(fwd / np.linalg.norm(fwd), up)) < 1e-9:
        c.err("up", "a vector not parallel to look_at - position", c.t["up"])
    return width, height, Camera(pos, look, up, proj, fov, ortho)


def _parse_colormap(file, tv):
    has_map, has_entries = tv.has("colormap"), tv.has("entries")
    if has_map == has_entries:
        tv.err("colormap", "exactly one of colormap (stops) or entries (explicit table)",
               _MISSING if not has_map else _Text("both"))
    if has_entries:
        if tv.has("size"):
            tv.err("size", "no size with explicit entries (the table length is the size)", tv.t["size"])
        ent = tv.t["entries"]
        desc = "a list of [r, g, b, a] entries, its length a power of two 1..256"
        if not isinstance(ent, list) or not _is_pow2(len(ent)) or len(ent) > _limits()["clut_max"][0]:
            tv.err("entries", desc, _Text(f"a list of {len(ent)}") if isinstance(ent, list) else ent)
        rows = [_check_ints4(e, lambda i=None, k=k: tv.key("entries") + f"[{k}]" + ("" if i is None else f"[{i}]"),
                             file) for k, e in enumerate(ent)]
        return np.asarray(rows, dtype=np.uint8)
    n = tv.int("size", 256, what="a power of two 1..256")
    if not _is_pow2(n) or n > _limits()["clut_max"][0]:
        tv.err("size", "a power of two 1..256", n)
    stops = tv.t["colormap"]
    desc = "a list of colour stops [pos, r, g, b, a]"
    if not isinstance(stops, list) or len(stops) < 1:
        tv.err("colormap", desc, stops)
    rows = []
    for k, st in enumerate(stops):
        key = tv.key("colormap") + f"[{k}]"
        if not isinstance(st, list) or len(st) != 5:
            raise SceneError(file, key, "a colour stop [pos, r, g, b, a]", st)
        pos = _check_num(st[0], lambda: key + "[0]", file, 0, 1, False, False, "a position in [0, 1]")
        col = [_check_num(x, lambda i=i: key + f"[{i}]", file, 0, 255, False, False, "a colour value in [0, 255]")
               for i, x in enumerate(st[1:], start=1)]
        if rows and pos < rows[-1][0]:
            raise SceneError(file, key + "[0]", f"stop positions in non-decreasing order (>= {rows[-1][0]:g})", st[0])
        rows.append([pos] + col)
    return colormap_to_clut(np.asarray(rows, dtype=np.float64), n)


def colormap_to_clut(stops: np.ndarray, n: int) -> np.ndarray:
    """Sample colour stops [K, 5] (pos, r, g, b, a) into an N-entry uint8 RGBA table.

    Entry k is the colour at its centre p = (k + 0.5)/N, linearly interpolated between the
    stops around p; at a hard step (two stops at one position) p takes the right-hand side;
    before the first / after the last stop the end colour holds. Rounded half up.
    """
    pos, col = stops[:, 0], stops[:, 1:]
    p = (np.arange(n) + 0.5) / n
    i = np.searchsorted(pos, p, side="right") - 1  # last stop with pos <= p
    out = np.empty((n, 4))
    lo = i < 0
    hi = i >= len(pos) - 1
    mid = ~lo & ~hi
    out[lo] = col[0]
    out[hi] = col[-1]
    im = i[mid]
    w = (p[mid] - pos[im]) / (pos[im + 1] - pos[im])
    out[mid] = col[im] + w[:, None] * (col[im + 1] - col[im])
    return np.clip(np.floor(out + 0.5), 0, 255).astype(np.uint8)


def _top(x: float) -> str:
    """x, the largest value of a format, in 8 significant digits, unless they round it up to the
    power of two the format stops below (s26.18's 127.99999618 as "128", a value it does not hold)."""
    t = f"{x:.8g}"
    return f"{x:.12g}" if float(t) > x and float(t) == int(float(t)) else t


def _parse_T(file, key, v):
    lo, hi, fmt = _limits()["T"]
    desc = (f"a number, a list of 3 numbers (diagonal) or a 3x3 matrix, entries in [{lo:.8g}, {_top(hi)}] "
            f"(the widest configuration, {fmt})")
    if _is_num(v):
        x = _check_num(v, lambda: key, file, lo, hi, False, False, desc)
        return np.eye(3) * x
    if isinstance(v, list) and len(v) == 3 and all(not isinstance(e, list) for e in v):
        d = _check_vec(v, 3, lambda i=None: key + ("" if i is None else f"[{i}]"), file, desc)
        M = np.diag(d)
    elif isinstance(v, list) and len(v) == 3:
        M = _check_mat(v, 3, 3, key, file, desc)
    else:
        raise SceneError(file, key, desc, v)
    if np.any((M < lo) | (M > hi)):
        raise SceneError(file, key, desc, v)
    return M


def _parse_texture(file, name, tv):
    tv.check_keys({"quadric", "blend", "mode", "filter", "noise_gradient", "colormap", "size", "entries", "noise"})
    L = _limits()
    qlo, qhi, qfmt = L["quadric"]
    qdesc = f"in [{qlo:.8g}, {_top(qhi)}] (the widest configuration, {qfmt})"
    Q = tv.vec("quadric", 10, what=f"a list of 10 quadric coefficients A..J, each {qdesc}")
    if np.any((Q < qlo) | (Q > qhi)):
        k = int(np.argmax((Q < qlo) | (Q > qhi)))
        raise SceneError(file, tv.key("quadric") + f"[{k}]", f"a coefficient {qdesc}", float(Q[k]))
    blend = tv.str("blend", "cubic", ("cubic", "linear"))
    mode = tv.str("mode", "mod", ("mod", "clamp"))
    filt = tv.bool("filter", True)
    ngrad = tv.bool("noise_gradient", True)
    clut = _parse_colormap(file, tv)
    terms = []
    noise = tv.get("noise", "", [])
    if not isinstance(noise, list) or not all(isinstance(x, dict) for x in noise):
        tv.err("noise", "an array of tables [[texture.NAME.noise]]", noise)
    kmax, kcfg = L["noise_terms"]
    if len(noise) > kmax:
        tv.err("noise", f"at most {kmax} noise terms (the most of any configuration, {kcfg})",
               _Text(f"{len(noise)} terms"))
    for i, nt in enumerate(noise):
        nv = _V(file, nt, tv.key("noise") + f"[{i}]")
        nv.check_keys({"a", "T", "o"})
        alo, ahi, afmt = L["a"]
        a = nv.num("a", lo=alo, hi=ahi, what=f"a number in [{alo:.8g}, {_top(ahi)}] (the widest configuration, {afmt})")
        T = _parse_T(file, nv.key("T"), nv.get("T", "a number, a list of 3 numbers or a 3x3 matrix"))
        o = nv.vec("o", 3, [0.0, 0.0, 0.0])
        terms.append(NoiseTerm(a, T, o))
    return TextureParams(Q=Q, terms=terms, blend=blend, mode=mode, clut=clut, filter=filt, noise_gradient=ngrad)


_TYPE_KEYS = {
    "screen": {"rect"},
    "quad": {"vertices"},
    "polygon": {"vertices"},
    "triangle": {"vertices"},
    "plane": {"point", "normal", "extent"},
    "sphere": {"center", "radius"},
    "box": {"min", "max"},
    "torus": {"center", "axis", "major", "minor"},
    "mesh": {"builtin", "subdivisions", "vertices", "triangles", "transform"},
}
_COMMON_KEYS = {"type", "name", "texture", "texture_matrix", "layer"}


def _points(file, ov, k, n_exact=None, n_min=None):
    v = ov.get(k, "a list of [x, y, z] points")
    cnt = (f"{n_exact} " if n_exact else f"at least {n_min} " if n_min else "")
    desc = f"a list of {cnt}[x, y, z] points"
    if not isinstance(v, list) or (n_exact and len(v) != n_exact) or (n_min and len(v) < n_min):
        ov.err(k, desc, v)
    return np.asarray([_check_vec(p, 3, lambda i=None, j=j: ov.key(k) + f"[{j}]" + ("" if i is None else f"[{i}]"),
                                  file, "a point [x, y, z]") for j, p in enumerate(v)])


def _planar_polygon(file, ov, verts):
    """Check a polygon is planar and not degenerate; return its unit normal (Newell's method)."""
    nrm = np.zeros(3)
    for i in range(len(verts)):
        a, b = verts[i], verts[(i + 1) % len(verts)]
        nrm += np.cross(a, b)
    size = np.max(np.ptp(verts, axis=0))
    if np.linalg.norm(nrm) <= 1e-12 * max(size, 1e-300) ** 2:
        ov.err("vertices", "a non-degenerate polygon (non-zero area)", _Text("zero area"))
    nrm /= np.linalg.norm(nrm)
    dist = np.abs((verts - verts[0]) @ nrm)
    if np.max(dist) > 1e-6 * size:
        ov.err("vertices", "coplanar points", _Text(f"a point {np.max(dist):.3g} off the plane"))
    return nrm


def _parse_object(file, i, ov, textures):
    typ = ov.str("type", choices=OBJECT_TYPES)
    ov.check_keys(_COMMON_KEYS | _TYPE_KEYS[typ])
    name = ov.str("name", f"{typ}{i}")
    tex = ov.str("texture")
    if tex not in textures:
        ov.err("texture", "the name of a [texture.NAME] table (defined: " + ", ".join(sorted(textures)) + ")", tex)
    M = ov.mat("texture_matrix", 3, 4, np.hstack([np.eye(3), np.zeros((3, 1))]))
    layer = ov.str("layer", name)
    p = {}
    if typ == "screen":
        r = ov.vec("rect", 4, [0.0, 0.0, 1.0, 1.0], lo=0, hi=1, what="[x0, y0, x1, y1] in [0, 1]")
        if not (r[0] < r[2] and r[1] < r[3]):
            ov.err("rect", "x0 < x1 and y0 < y1", ov.t["rect"])
        p["rect"] = r
    elif typ in ("quad", "polygon", "triangle"):
        n = {"quad": 4, "triangle": 3}.get(typ)
        v = _points(file, ov, "vertices", n_exact=n, n_min=None if n else 3)
        p["vertices"] = v
        p["normal"] = _planar_polygon(file, ov, v)
    elif typ == "plane":
        p["point"] = ov.vec("point", 3)
        nrm = ov.vec("normal", 3)
        if np.linalg.norm(nrm) < 1e-12:
            ov.err("normal", "a non-zero vector", ov.t["normal"])
        p["normal"] = nrm / np.linalg.norm(nrm)
        p["extent"] = ov.num("extent", lo=0, lo_open=True)
    elif typ == "sphere":
        p["center"] = ov.vec("center", 3)
        p["radius"] = ov.num("radius", lo=0, lo_open=True)
    elif typ == "box":
        lo, hi = ov.vec("min", 3), ov.vec("max", 3)
        if not np.all(lo < hi):
            ov.err("max", "max > min on every axis", ov.t["max"])
        p["min"], p["max"] = lo, hi
    elif typ == "torus":
        p["center"] = ov.vec("center", 3)
        ax = ov.vec("axis", 3)
        if np.linalg.norm(ax) < 1e-12:
            ov.err("axis", "a non-zero vector", ov.t["axis"])
        p["axis"] = ax / np.linalg.norm(ax)
        p["major"] = ov.num("major", lo=0, lo_open=True)
        p["minor"] = ov.num("minor", lo=0, hi=p["major"], lo_open=True, hi_open=True,
                            what=f"a number in (0, major = {p['major']:g})")
    elif typ == "mesh":
        X = ov.mat("transform", 3, 4, np.hstack([np.eye(3), np.zeros((3, 1))]))
        if abs(np.linalg.det(X[:, :3])) < 1e-12:
            ov.err("transform", "an invertible 3x4 affine map", ov.t["transform"])
        if ov.has("builtin"):
            for k in ("vertices", "triangles"):
                if ov.has(k):
                    ov.err(k, "no vertices/triangles with builtin", ov.t[k])
            ov.str("builtin", choices=("teapot",))
            n = ov.int("subdivisions", 8, lo=1, hi=32)
            from model.scene.teapot import teapot_mesh

            V, T, C = teapot_mesh(n)
        else:
            if ov.has("subdivisions"):
                ov.err("subdivisions", "no subdivisions without builtin", ov.t["subdivisions"])
            if not ov.has("vertices"):
                ov.err("vertices", "vertices and triangles, or builtin = \"teapot\"", _MISSING)
            V = _points(file, ov, "vertices", n_min=3)
            tri = ov.get("triangles", "a list of [i, j, k] vertex indices")
            if not isinstance(tri, list) or not tri:
                ov.err("triangles", "a non-empty list of [i, j, k] vertex indices", tri)
            T = []
            for j, t in enumerate(tri):
                key = ov.key("triangles") + f"[{j}]"
                if (not isinstance(t, list) or len(t) != 3
                        or not all(isinstance(x, int) and not isinstance(x, bool) and 0 <= x < len(V) for x in t)):
                    raise SceneError(file, key, f"3 vertex indices in 0..{len(V) - 1}", t)
                T.append(t)
            T = np.asarray(T, dtype=np.int64)
            C = np.arange(len(T)) // 8  # clusters of 8 consecutive triangles
        V = V @ X[:, :3].T + X[:, 3]
        e1, e2 = V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]]
        keep = np.linalg.norm(np.cross(e1, e2), axis=1) > 1e-15
        if not np.any(keep):
            ov.err("triangles", "at least one triangle of non-zero area", _Text("only degenerate triangles"))
        p["vertices"], p["triangles"], p["clusters"] = V, T[keep], C[keep]
    return SceneObject(name=name, type=typ, texture=tex, texture_matrix=M, layer=layer, params=p, index=i)


def parse_scene(text: str, source: str = "<string>") -> Scene:
    """Parse scene TOML text; `source` names the file in error messages."""
    file = source
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise SceneError(file, "(toml)", f"malformed TOML: {e}", raw=True) from None
    root = _V(file, data, "")
    root.check_keys({"scene", "camera", "object", "texture"})
    sc = root.sub("scene", {})
    sc.check_keys({"name", "description", "background"})
    name = sc.str("name", Path(source).stem)
    desc = sc.str("description", "")
    bg = (np.asarray(_check_ints4(sc.t["background"], lambda i=None: "scene.background" + ("" if i is None else f"[{i}]"),
                                  file)) if sc.has("background") else np.array([0, 0, 0, 255]))
    width, height, cam = _parse_camera(file, root)

    textures = {}
    tt = root.sub("texture", {})
    if not tt.t:
        raise SceneError(file, "texture", "at least one [texture.NAME] table", _MISSING)
    for tname, tdata in tt.t.items():
        if not isinstance(tdata, dict):
            tt.err(tname, "a table [texture.NAME]", tdata)
        textures[tname] = _parse_texture(file, tname, _V(file, tdata, f"texture.{tname}"))

    objs = root.get("object", "at least one [[object]] table")
    if not isinstance(objs, list) or not objs or not all(isinstance(o, dict) for o in objs):
        root.err("object", "an array of tables [[object]], at least one", objs)
    objects, names = [], set()
    for i, o in enumerate(objs):
        ob = _parse_object(file, i, _V(file, o, f"object[{i}]"), textures)
        if ob.name in names:
            raise SceneError(file, f"object[{i}].name", "a name no other object has", ob.name)
        names.add(ob.name)
        objects.append(ob)
    layers, layer_tex = [], {}
    for ob in objects:
        if ob.layer not in layer_tex:
            layers.append(ob.layer)
            layer_tex[ob.layer] = ob.texture
        elif layer_tex[ob.layer] != ob.texture:
            raise SceneError(file, f"object[{ob.index}].layer",
                             f"objects of layer {ob.layer!r} to share texture {layer_tex[ob.layer]!r}", ob.texture)
    return Scene(path=str(source), name=name, width=width, height=height,
                 background=bg.astype(np.uint8), camera=cam, objects=objects,
                 textures=textures, description=desc, layers=layers)


def load_scene(path) -> Scene:
    """Read and validate a scene file; raises SceneError (one line) on any problem."""
    path = Path(path)
    try:
        text = path.read_bytes().decode("utf-8")
    except OSError as e:
        raise SceneError(path, "(file)", f"cannot read: {e.strerror or e}", raw=True) from None
    except UnicodeDecodeError as e:
        raise SceneError(path, "(file)", f"malformed TOML: not UTF-8 ({e.reason})", raw=True) from None
    return parse_scene(text, str(path))


def summary(scene: Scene) -> str:
    lines = [f"{scene.path}: scene {scene.name!r}, {scene.width}x{scene.height}, "
             f"{len(scene.objects)} object(s), {len(scene.layers)} layer(s), {len(scene.textures)} texture(s)"]
    for ob in scene.objects:
        lines.append(f"  object {ob.name}: {ob.type}, texture {ob.texture}, layer {ob.layer}")
    for tname, t in scene.textures.items():
        lines.append(f"  texture {tname}: {len(t.terms)} noise term(s), {t.blend}, {t.mode}, "
                     f"{len(t.clut)} entries, filter={t.filter}")
    return "\n".join(lines)


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if not argv:
        print("usage: python -m model.scene.scene FILE...", file=sys.stderr)
        return 2
    for f in argv:
        try:
            sc = load_scene(f)
        except SceneError as e:
            print(str(e), file=sys.stderr)
            return 2
        print(summary(sc))
    return 0


if __name__ == "__main__":
    sys.exit(main())
