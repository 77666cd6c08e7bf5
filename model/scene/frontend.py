"""Scene front end: camera, ray-cast primitives, per-pixel texture coordinates s and Jacobian J.

    passes = render_passes(scene, width, height)

returns one `Pass` per layer of the scene (a layer is one object, or the objects sharing a
`layer` name in the scene file, z-buffered against each other: the nearest hit wins).

Conventions
-----------
* Image: pixel (x, y), x = column to the RIGHT, y = row DOWN, arrays indexed [y, x].
  Rays go through pixel centres (x + 0.5, y + 0.5).
* Camera: forward f = normalize(look_at - position), right r = normalize(f x up),
  up_true u = r x f. Perspective: ray origin E = position, direction
  D(x, y) = f + k (x + 0.5 - W/2) r - k (y + 0.5 - H/2) u with k = 2 tan(fov/2) / H
  (square pixels, fov vertical). Orthographic: origin E + k (x + 0.5 - W/2) r - k (y + 0.5 - H/2) u
  with k = ortho_height / H, direction f.
* s = M[:, :3] P + M[:, 3] for the world hit point P and the object's texture_matrix M.
* J[y, x] = ds/d(x, y), float64 [3, 2]: column 0 = ds/dx (one pixel right), column 1 = ds/dy
  (one pixel DOWN), in texture units per pixel. It is computed analytically from the ray-surface
  intersection, perspective correct: with ray O(x) + t D(x) hitting a surface of normal n,
      V = dO/dx + t dD/dx,   dP/dx = V - D (n . V) / (n . D),   ds/dx = M[:, :3] dP/dx
  (and the same for y): the hit point moves in the tangent plane. Triangle meshes use the flat
  triangle normal. `screen` objects have P = ((x+0.5)/W, (y+0.5)/H, 0), so dP/dx = (1/W, 0, 0),
  dP/dy = (0, 1/H, 0) exactly.
* depth = distance from the eye along the ray (screen objects: 0, i.e. in front of everything);
  surface = (object index in the file << 32) + piece (box: 2 * axis + (0 min / 1 max face);
  mesh: triangle index; other primitives: 0), to tell smooth pieces apart.
* Outside a pass's mask: s = 0, J = 0, depth = inf, surface = -1 (finite, never NaN).
  Rays that hit a surface exactly edge-on (n . D = 0, no finite J) count as misses.

Passes and compositing
----------------------
The list is in FRONT-TO-BACK compositing order: the first pass is the front-most, and the
renderer accumulates each pass UNDER what it has so far (equivalently: composite back to front,
from the last pass to the first, each with "over"), then the background under everything.
To make one list order right at every pixel:
* occlusion: a pixel of a pass is dropped from its mask where an OPAQUE pass (another layer whose
  colour table has alpha 255 in every entry) has a strictly nearer hit (a z-buffer test);
* order: the transparent passes come first, in scene-file order, then the opaque ones, in
  scene-file order. So at any pixel the surviving passes are the transparent ones nearer than the
  nearest opaque hit, then that opaque hit; scene files list transparent layers front to back
  among themselves (planet: clouds before planet; moonrise: clouds, highlight, ...).
`alpha_mode` is "opaque" (every colour-table alpha is 255: the pass hides whatever is behind it
in its mask) or "over" (the colour table carries alpha < 255); both are composited with "over".
`composite_over` below is the reference definition of this compositing.

Speed: every primitive is intersected vectorised over the whole frame (numpy); the only Python
loops are over objects, polygon edges and mesh clusters (8 triangles each), each mesh cluster
tested only on the pixels inside the screen rectangle of its bounding box.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from model.scene.scene import Scene, SceneObject
from model.texture import TextureParams

T_EPS = 1e-9  # smallest accepted ray parameter (relative to |D| ~ 1)


@dataclass
class Pass:
    """One texture pass: the pixels one layer covers, with s and J per pixel."""

    name: str  # layer name (the object's name for a one-object layer)
    texture: TextureParams
    mask: np.ndarray  # bool [H, W]: pixels this pass covers (after occlusion by nearer opaque passes)
    s: np.ndarray  # float64 [H, W, 3]: texture coordinates (s, t, r); 0 outside mask
    J: np.ndarray  # float64 [H, W, 3, 2]: ds/dx (column 0, x right), ds/dy (column 1, y down); 0 outside
    alpha_mode: str  # "opaque" or "over" (see module docstring); composited front to back in list order
    depth: np.ndarray = None  # float64 [H, W]: distance from the eye along the ray; inf outside; 0 for screen
    surface: np.ndarray = None  # int64 [H, W]: id of the smooth piece hit (object, face, triangle); -1 outside
    texture_name: str = ""
    objects: list = field(default_factory=list)  # names of the objects in this layer


# ---------------------------------------------------------------------------- rays


class Rays:
    """Primary rays of a W x H frame, flattened row-major (index = y * W + x).

    window = (x0, y0, x1, y1): only the pixels x0 <= x < x1, y0 <= y < y1 of the frame (the
    camera and k still those of the whole W x H frame), flattened row-major over the window
    (index = (y - y0) * (x1 - x0) + (x - x0)). jitter = (jx, jy), float arrays of the window's
    shape in [-0.5, 0.5): each ray goes through (x + 0.5 + jx, y + 0.5 + jy) instead of the
    pixel centre (the supersampled truth's stratified jitter, model.scene.truth)."""

    def __init__(self, cam, W: int, H: int, window=None, jitter=None):
        x0, y0, x1, y1 = window or (0, 0, W, H)
        if not (0 <= x0 < x1 <= W and 0 <= y0 < y1 <= H):
            raise ValueError(f"window {window}: not inside the {W}x{H} frame")
        self.W, self.H = W, H
        self.x0, self.y0, self.Ww, self.Hw = x0, y0, x1 - x0, y1 - y0
        self.N = self.Ww * self.Hw
        self.ortho = cam.projection == "orthographic"
        f, r, u = cam.basis()
        self.f, self.r, self.u, self.E = f, r, u, cam.position.astype(np.float64)
        px = (np.arange(x0, x1) + 0.5) - W / 2.0
        py = (np.arange(y0, y1) + 0.5) - H / 2.0
        px, py = np.meshgrid(px, py)  # [Hw, Ww]
        if jitter is not None:
            px, py = px + jitter[0], py + jitter[1]
        self.px, self.py = px.ravel() + W / 2.0, py.ravel() + H / 2.0  # frame coordinates of every ray
        px, py = px.ravel(), py.ravel()
        if self.ortho:
            k = cam.ortho_height / H
            self.k = k
            self.O = self.E + k * px[:, None] * r - k * py[:, None] * u
            self.D = np.broadcast_to(f, (self.N, 3))
            self.dOdx, self.dOdy = k * r, -k * u
            self.dDdx, self.dDdy = np.zeros(3), np.zeros(3)
        else:
            k = 2.0 * math.tan(math.radians(cam.fov_deg) / 2.0) / H
            self.k = k
            self.O = np.broadcast_to(self.E, (self.N, 3))
            self.D = f + k * px[:, None] * r - k * py[:, None] * u
            self.dOdx, self.dOdy = np.zeros(3), np.zeros(3)
            self.dDdx, self.dDdy = k * r, -k * u
        self.Dlen = np.linalg.norm(self.D, axis=1) if not self.ortho else np.ones(self.N)

    def project(self, P: np.ndarray):
        """Continuous image coordinates (X, Y) (pixel centres at x + 0.5) and depth along f of points [..., 3]."""
        rel = P - self.E
        z = rel @ self.f
        a, b = rel @ self.r, rel @ self.u
        if self.ortho:
            X, Y = a / self.k, -b / self.k
        else:
            with np.errstate(divide="ignore", invalid="ignore"):
                X, Y = a / (z * self.k), -b / (z * self.k)
        return X + self.W / 2.0, Y + self.H / 2.0, z


# ---------------------------------------------------------------------------- intersections
# Each returns (t [N], n [N, 3], sid [N]) over all rays: t = inf where missed, n a (not
# necessarily unit) surface normal at the hit, sid an id of the smooth surface piece.


def _miss(N):
    return np.full(N, np.inf), np.zeros((N, 3)), np.zeros(N, dtype=np.int64)


def _hit_plane_generic(rays, p0, nrm):
    O, D = rays.O, rays.D
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((p0 - O) @ nrm) / (D @ nrm)
    t = np.where(np.isfinite(t) & (t > T_EPS), t, np.inf)
    return t


def _hit_plane(p, rays):
    t = _hit_plane_generic(rays, p["point"], p["normal"])
    ok = np.isfinite(t)
    P = rays.O[ok] + t[ok, None] * rays.D[ok]
    far = np.linalg.norm(P - p["point"], axis=1) > p["extent"]
    idx = np.flatnonzero(ok)[far]
    t[idx] = np.inf
    n = np.broadcast_to(p["normal"], (rays.N, 3))
    return t, n, np.zeros(rays.N, dtype=np.int64)


def _hit_polygon(p, rays):
    V, nrm = p["vertices"], p["normal"]
    t = _hit_plane_generic(rays, V[0], nrm)
    ok = np.flatnonzero(np.isfinite(t))
    P = rays.O[ok] + t[ok, None] * rays.D[ok]
    drop = int(np.argmax(np.abs(nrm)))
    keep = [i for i in range(3) if i != drop]
    q, v2 = P[:, keep], V[:, keep]
    inside = np.zeros(len(ok), dtype=bool)
    m = len(v2)
    for i in range(m):  # even-odd crossing test, one edge at a time
        a, b = v2[i], v2[(i + 1) % m]
        if a[1] == b[1]:
            continue
        cond = (a[1] > q[:, 1]) != (b[1] > q[:, 1])
        xint = a[0] + (q[:, 1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
        inside ^= cond & (q[:, 0] < xint)
    t[ok[~inside]] = np.inf
    n = np.broadcast_to(nrm, (rays.N, 3))
    return t, n, np.zeros(rays.N, dtype=np.int64)


def _hit_sphere(p, rays):
    C, R = p["center"], p["radius"]
    O, D = rays.O, rays.D
    oc = O - C
    a = np.einsum("ij,ij->i", D, D)
    b = np.einsum("ij,ij->i", oc, D)
    c = np.einsum("ij,ij->i", oc, oc) - R * R
    disc = b * b - a * c
    t = np.full(rays.N, np.inf)
    ok = disc >= 0
    sq = np.sqrt(disc[ok])
    bb, aa, cc = b[ok], a[ok], c[ok]
    qq = -(bb + np.copysign(sq, bb))  # stable pair of roots: qq / a and c / qq
    with np.errstate(divide="ignore", invalid="ignore"):
        r1, r2 = qq / aa, cc / qq
    lo, hi = np.minimum(r1, r2), np.maximum(r1, r2)
    tt = np.where(lo > T_EPS, lo, np.where(hi > T_EPS, hi, np.inf))
    tt[~np.isfinite(tt)] = np.inf
    t[ok] = tt
    hit = np.isfinite(t)
    n = np.zeros((rays.N, 3))
    n[hit] = O[hit] + t[hit, None] * D[hit] - C
    return t, n, np.zeros(rays.N, dtype=np.int64)


def _hit_box(p, rays):
    lo, hi = p["min"], p["max"]
    O, D = rays.O, rays.D
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / D
        t1, t2 = (lo - O) * inv, (hi - O) * inv
    tmin, tmax = np.fmin(t1, t2), np.fmax(t1, t2)
    an, af = np.argmax(tmin, axis=1), np.argmin(tmax, axis=1)
    rows = np.arange(rays.N)
    tn, tf = tmin[rows, an], tmax[rows, af]
    hit = (tn <= tf) & (tf > T_EPS)
    use_near = tn > T_EPS
    t = np.where(hit, np.where(use_near, tn, tf), np.inf)
    axis = np.where(use_near, an, af)
    dsign = D[rows, axis] > 0
    side = np.where(use_near, ~dsign, dsign)  # face hit: 0 = min face, 1 = max face
    n = np.zeros((rays.N, 3))
    n[rows, axis] = 1.0
    sid = np.where(hit, 2 * axis + side, 0).astype(np.int64)
    return t, n, sid


def _quartic_real_roots(c3, c2, c1, c0):
    """Real roots of u^4 + c3 u^3 + c2 u^2 + c1 u + c0 for stacked coefficients [M] -> [M, 4] (nan if complex)."""
    M = len(c3)
    comp = np.zeros((M, 4, 4))
    comp[:, 0, 0], comp[:, 0, 1], comp[:, 0, 2], comp[:, 0, 3] = -c3, -c2, -c1, -c0
    comp[:, 1, 0] = comp[:, 2, 1] = comp[:, 3, 2] = 1.0
    ev = np.linalg.eigvals(comp)
    scale = 1.0 + np.abs(ev.real)
    re = np.where(np.abs(ev.imag) <= 1e-4 * scale, ev.real, np.nan)
    # polish with Newton on the quartic
    for _ in range(4):
        f = (((re + c3[:, None]) * re + c2[:, None]) * re + c1[:, None]) * re + c0[:, None]
        df = ((4 * re + 3 * c3[:, None]) * re + 2 * c2[:, None]) * re + c1[:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(df != 0, f / df, 0.0)
        re = re - np.clip(step, -1e-2 * scale, 1e-2 * scale)
    return re


def _hit_torus(p, rays):
    C, a, R, r = p["center"], p["axis"], p["major"], p["minor"]
    t = np.full(rays.N, np.inf)
    n = np.zeros((rays.N, 3))
    # bounding sphere cull
    Dn = rays.D / rays.Dlen[:, None]
    oc = rays.O - C
    b = np.einsum("ij,ij->i", oc, Dn)
    c = np.einsum("ij,ij->i", oc, oc) - (R + r) ** 2
    disc = b * b - c
    cand = np.flatnonzero((disc >= 0) & (-b + np.sqrt(np.maximum(disc, 0)) > 0))
    if len(cand) == 0:
        return t, n, np.zeros(rays.N, dtype=np.int64)
    d = Dn[cand]
    t0 = np.maximum(-b[cand] - np.sqrt(disc[cand]), 0.0)  # enter the bounding sphere (or start inside)
    q = oc[cand] + t0[:, None] * d  # shifted origin, relative to the centre
    bb = np.einsum("ij,ij->i", q, d)
    qq = np.einsum("ij,ij->i", q, q)
    qa, da = q @ a, d @ a
    G = qq + R * R - r * r
    c3 = 4 * bb
    c2 = 4 * bb * bb + 2 * G - 4 * R * R * (1 - da * da)
    c1 = 4 * bb * G - 4 * R * R * (2 * bb - 2 * qa * da)
    c0 = G * G - 4 * R * R * (qq - qa * qa)
    u = _quartic_real_roots(c3, c2, c1, c0)
    tt = t0[:, None] + u
    # accept roots that are on the surface and in front of the origin
    P = (rays.O[cand] - C)[:, None, :] + tt[..., None] * d[:, None, :]
    h = P @ a
    rad = np.sqrt(np.maximum(np.einsum("ijk,ijk->ij", P, P) - h * h, 0.0))
    resid = np.abs(np.hypot(rad - R, h) - r)
    good = np.isfinite(tt) & (tt > T_EPS) & (resid <= 1e-7 * (R + r))
    tt = np.where(good, tt, np.inf)
    k = np.argmin(tt, axis=1)
    tbest = tt[np.arange(len(cand)), k]
    hit = np.isfinite(tbest)
    ci = cand[hit]
    t[ci] = tbest[hit] / rays.Dlen[ci]  # in units of the unnormalised D
    Ph = rays.O[ci] + t[ci, None] * rays.D[ci] - C
    hh = Ph @ a
    radial = Ph - hh[:, None] * a
    rl = np.linalg.norm(radial, axis=1)
    ring = R * radial / np.where(rl > 0, rl, 1.0)[:, None]
    n[ci] = Ph - ring
    return t, n, np.zeros(rays.N, dtype=np.int64)


def _hit_mesh(p, rays):
    V, T, Cl = p["vertices"], p["triangles"], p["clusters"]
    v0 = V[T[:, 0]]
    e1 = V[T[:, 1]] - v0
    e2 = V[T[:, 2]] - v0
    nrm = np.cross(e1, e2)
    W, H = rays.W, rays.H
    wx0, wy0, wx1, wy1 = rays.x0, rays.y0, rays.x0 + rays.Ww - 1, rays.y0 + rays.Hw - 1  # the window, inclusive
    zt = np.full(rays.N, np.inf)
    zi = np.full(rays.N, -1, dtype=np.int64)
    # contiguous cluster ranges
    starts = np.flatnonzero(np.r_[True, Cl[1:] != Cl[:-1]])
    ends = np.r_[starts[1:], len(Cl)]
    # bounding boxes of every cluster, projected
    tv = np.stack([v0, v0 + e1, v0 + e2], axis=1)  # [T, 3, 3]
    tmin, tmax = tv.min(axis=1), tv.max(axis=1)
    bmin = np.minimum.reduceat(tmin, starts, axis=0)
    bmax = np.maximum.reduceat(tmax, starts, axis=0)
    corners = np.stack([np.stack([np.where(m & 1, bmax[:, 0], bmin[:, 0]),
                                  np.where(m & 2, bmax[:, 1], bmin[:, 1]),
                                  np.where(m & 4, bmax[:, 2], bmin[:, 2])], axis=-1) for m in range(8)], axis=1)
    X, Y, Z = rays.project(corners)  # [C, 8]
    zmin, zmax = Z.min(axis=1), Z.max(axis=1)
    near = 1e-6 * (1.0 + np.abs(Z).max())
    # a corner behind the eye (perspective): no projected rectangle, test the whole frame
    full = (zmin <= near) if not rays.ortho else np.zeros(len(zmin), dtype=bool)
    with np.errstate(invalid="ignore"):
        x0 = np.where(full, 0, np.floor(np.nan_to_num(X.min(axis=1), nan=0) - 1.0))
        x1 = np.where(full, W - 1, np.ceil(np.nan_to_num(X.max(axis=1), nan=W) + 1.0))
        y0 = np.where(full, 0, np.floor(np.nan_to_num(Y.min(axis=1), nan=0) - 1.0))
        y1 = np.where(full, H - 1, np.ceil(np.nan_to_num(Y.max(axis=1), nan=H) + 1.0))
    x0, x1 = np.clip(x0, wx0, wx1).astype(np.int64), np.clip(x1, wx0, wx1).astype(np.int64)
    y0, y1 = np.clip(y0, wy0, wy1).astype(np.int64), np.clip(y1, wy0, wy1).astype(np.int64)
    live = (zmax > 0) & (x0 <= x1) & (y0 <= y1)
    if rays.Ww < W or rays.Hw < H:  # a cluster wholly outside the window (its rectangle clipped to an edge)
        with np.errstate(invalid="ignore"):
            live &= full | ~((X.max(axis=1) + 1 < wx0) | (X.min(axis=1) - 1 > wx1 + 1)
                             | (Y.max(axis=1) + 1 < wy0) | (Y.min(axis=1) - 1 > wy1 + 1))
    if not rays.ortho:
        live &= ~(~full & ((X.max(axis=1) < -1) | (X.min(axis=1) > W + 1) | (Y.max(axis=1) < -1) | (Y.min(axis=1) > H + 1)))
    for c in np.flatnonzero(live):
        xs = np.arange(x0[c], x1[c] + 1)
        ys = np.arange(y0[c], y1[c] + 1)
        idx = ((ys[:, None] - wy0) * rays.Ww + (xs[None, :] - wx0)).ravel()
        sl = slice(starts[c], ends[c])
        O = rays.O[idx][:, None, :]
        D = rays.D[idx][:, None, :]
        E1, E2, P0 = e1[sl][None], e2[sl][None], v0[sl][None]
        pvec = np.cross(D, E2)
        det = np.einsum("ijk,ijk->ij", np.broadcast_to(E1, pvec.shape), pvec)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            tvec = O - P0
            u = np.einsum("ijk,ijk->ij", tvec, pvec) * inv
            qvec = np.cross(tvec, E1)
            v = np.einsum("ijk,ijk->ij", np.broadcast_to(D, qvec.shape), qvec) * inv
            tt = np.einsum("ijk,ijk->ij", np.broadcast_to(E2, qvec.shape), qvec) * inv
        ok = (det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (tt > T_EPS)
        tt = np.where(ok, tt, np.inf)
        k = np.argmin(tt, axis=1)
        tb = tt[np.arange(len(idx)), k]
        better = tb < zt[idx]
        zt[idx[better]] = tb[better]
        zi[idx[better]] = starts[c] + k[better]
    hit = zi >= 0
    n = np.zeros((rays.N, 3))
    n[hit] = nrm[zi[hit]]
    return zt, n, np.where(hit, zi, 0)


_HIT = {
    "plane": _hit_plane,
    "quad": _hit_polygon,
    "polygon": _hit_polygon,
    "triangle": _hit_polygon,
    "sphere": _hit_sphere,
    "box": _hit_box,
    "torus": _hit_torus,
    "mesh": _hit_mesh,
}


def intersect(ob: SceneObject, rays: Rays):
    """Ray-cast one object: (t [N], n [N, 3], sid [N]); t = inf where missed, in units of rays.D."""
    return _HIT[ob.type](ob.params, rays)


# ---------------------------------------------------------------------------- shading: s and J


def _lin(M, X):
    """Rows of X [K, 3] mapped by the 3x3 matrix M (einsum: faster than a BLAS call on 3-wide rows)."""
    return np.einsum("ij,kj->ki", M, X)


def _object_sample(ob: SceneObject, rays: Rays):
    """Per-pixel (depth [N], s [N, 3], J [N, 3, 2], sid [N]) of one object; depth = inf where missed."""
    N = rays.N
    M, m = ob.texture_matrix[:, :3], ob.texture_matrix[:, 3]
    s = np.zeros((N, 3))
    J = np.zeros((N, 3, 2))
    if ob.type == "screen":
        W, H = rays.W, rays.H
        x0, y0, x1, y1 = ob.params["rect"]
        U, Vv = rays.px / W, rays.py / H
        cov = (U >= x0) & (U < x1) & (Vv >= y0) & (Vv < y1)
        P = np.stack([U, Vv, np.zeros(N)], axis=1)
        s[cov] = _lin(M, P[cov]) + m
        J[cov] = np.stack([M[:, 0] / W, M[:, 1] / H], axis=1)
        depth = np.where(cov, 0.0, np.inf)
        return depth, s, J, np.zeros(N, dtype=np.int64)
    t, n, sid = intersect(ob, rays)
    hit = np.isfinite(t)
    idx = np.flatnonzero(hit)
    th, nh, Dh = t[idx], n[idx], rays.D[idx]
    nD = np.einsum("ij,ij->i", nh, Dh)
    nlen = np.linalg.norm(nh, axis=1)
    graze = np.abs(nD) <= 1e-12 * nlen * rays.Dlen[idx]
    P = rays.O[idx] + th[:, None] * Dh
    cols = []
    for dO, dD in ((rays.dOdx, rays.dDdx), (rays.dOdy, rays.dDdy)):
        Vt = dO + th[:, None] * dD
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.einsum("ij,ij->i", nh, Vt) / nD
        cols.append(_lin(M, Vt - Dh * ratio[:, None]))
    s[idx] = _lin(M, P) + m
    J[idx] = np.stack(cols, axis=2)
    depth = np.full(N, np.inf)
    depth[idx] = th * rays.Dlen[idx]
    if np.any(graze):  # exactly grazing rays: no finite Jacobian; treat as misses
        g = idx[graze]
        depth[g], s[g], J[g] = np.inf, 0.0, 0.0
    return depth, s, J, sid


def render_passes(scene: Scene, width: int | None = None, height: int | None = None, window=None,
                  jitter=None) -> list:
    """Ray-cast the scene at width x height (default: the scene's) into a list of `Pass`.

    The list is in front-to-back compositing order (see the module docstring). window =
    (x0, y0, x1, y1) and jitter (see `Rays`): only that rectangle of the frame, the passes'
    arrays of its shape [y1 - y0, x1 - x0], every ray moved by its jitter.
    """
    W = int(width or scene.width)
    H = int(height or scene.height)
    rays = Rays(scene.camera, W, H, window, jitter)
    N = rays.N
    W, H = rays.Ww, rays.Hw  # the arrays' shape
    layers = []
    for lname in scene.layers:
        obs = [ob for ob in scene.objects if ob.layer == lname]
        depth = np.full(N, np.inf)
        s = np.zeros((N, 3))
        J = np.zeros((N, 3, 2))
        surf = np.full(N, -1, dtype=np.int64)
        for ob in obs:
            d, so, Jo, sid = _object_sample(ob, rays)
            win = d < depth
            depth[win], s[win], J[win] = d[win], so[win], Jo[win]
            surf[win] = (ob.index << 32) + sid[win]
        tex = scene.textures[obs[0].texture]
        opaque = bool(np.all(tex.clut[:, 3] == 255))
        name = obs[0].name if len(obs) == 1 else lname
        layers.append(dict(name=name, tex=tex, tname=obs[0].texture, depth=depth, s=s, J=J, surf=surf,
                           opaque=opaque, objects=[ob.name for ob in obs]))
    # occlusion by nearer opaque layers (z-buffer over the opaque layers, excluding oneself)
    opaque_depths = [L["depth"] for L in layers if L["opaque"]]
    if opaque_depths:
        stack = np.stack(opaque_depths)
        order = np.sort(stack, axis=0)
        first = order[0]
        second = order[1] if len(order) > 1 else np.full(N, np.inf)
    passes = []
    for L in sorted(layers, key=lambda L: L["opaque"]):  # stable: transparent first, file order kept
        depth = L["depth"]
        mask = np.isfinite(depth)
        if opaque_depths:
            if L["opaque"]:
                # nearest opaque depth among the others: `second` where this layer is the nearest
                occ = np.where(depth <= first, second, first)
            else:
                occ = first
            mask &= ~(occ < depth)
        s, J, surf = L["s"], L["J"], L["surf"]
        s[~mask], J[~mask], surf[~mask] = 0.0, 0.0, -1
        depth = np.where(mask, depth, np.inf)
        passes.append(Pass(name=L["name"], texture=L["tex"], mask=mask.reshape(H, W), s=s.reshape(H, W, 3),
                           J=J.reshape(H, W, 3, 2), alpha_mode="opaque" if L["opaque"] else "over",
                           depth=depth.reshape(H, W), surface=surf.reshape(H, W), texture_name=L["tname"],
                           objects=L["objects"]))
    return passes


def composite_over(rgba_layers, masks, background) -> np.ndarray:
    """Reference compositing of pass colours, front to back in list order.

    rgba_layers: list of float [H, W, 4] in [0, 1] (straight, not premultiplied alpha), in pass order;
    masks: list of bool [H, W]; background: RGBA (0..255). Returns float [H, W, 4] in [0, 1]
    (straight alpha). Equivalent to painting the background, then the last pass "over" it, ...,
    then the first pass "over" everything.
    """
    H, W = masks[0].shape if masks else (1, 1)
    acc = np.zeros((H, W, 3))  # premultiplied colour accumulated so far
    trans = np.ones((H, W))  # remaining transmittance
    for rgba, m in zip(rgba_layers, masks):
        a = np.where(m, rgba[..., 3], 0.0)
        acc += (trans * a)[..., None] * rgba[..., :3]
        trans *= 1.0 - a
    bg = np.asarray(background, dtype=np.float64) / 255.0
    acc += (trans * bg[3])[..., None] * bg[:3]
    alpha = 1.0 - trans * (1.0 - bg[3])
    out = np.zeros((H, W, 4))
    out[..., :3] = np.where(alpha[..., None] > 0, acc / np.maximum(alpha, 1e-300)[..., None], 0.0)
    out[..., 3] = alpha
    return out


# ---------------------------------------------------------------------------- fixed-point limits


def fixed_point_violations(scene: Scene, cfg, passes=None) -> list:
    """Every way the scene (and, if given, its passes) leaves configuration cfg's input ranges.

    The limits are the configuration's own (config/<name>.toml), applied by the code that
    quantizes for the hardware (model.hw.quantize): no copy of a limit lives here. Checks each
    texture's quadric and colour table, each noise term the configuration keeps (the first
    cfg.noise_terms; the rest are dropped, an approximation, not a violation: see
    model.scene.passes.approximations), and, for passes, s and J on every covered pixel.
    Returns one message per violation, "texture.NAME: ..." or "pass NAME: ...".
    """
    from model.hw.quantize import FormatError, quantize_pixels, quantize_texture
    from model.texture import NoiseTerm

    out = []

    def check(prefix, fn):
        try:
            fn()
        except FormatError as e:
            out.append(f"{prefix}: {e}")

    zero = NoiseTerm(0.0, np.zeros((3, 3)), np.zeros(3))
    for name, t in scene.textures.items():
        check(f"texture.{name}", lambda t=t: quantize_texture(cfg, replace(t, terms=[])))
        for i, nt in enumerate(t.terms[:cfg.noise_terms]):
            # the term alone (zero quadric, one-entry table): each violation reported once
            alone = replace(t, Q=np.zeros(10), clut=np.zeros((1, 4), np.uint8), terms=[zero] * i + [nt])
            check(f"texture.{name}", lambda alone=alone: quantize_texture(cfg, alone))
    for p in passes or []:
        if p.mask.any():
            check(f"pass {p.name}", lambda p=p: quantize_pixels(cfg, p.s[p.mask], p.J[p.mask]))
    return out
