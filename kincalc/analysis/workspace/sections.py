"""Sections of the workspace for drawing (``kincalc workspace --plot``): the reachable
set in a plane at about :data:`SECTION_BINS` pixels across, its dexterous part, and the
manipulability inside it; world frame, SI. See :mod:`kincalc.analysis.workspace`.

The planes are chosen from the robot's first two axes, not per robot:

* **through the base axis**: the plane that contains joint 1's axis and the world axis
  (normal to it) nearest to where the arm reaches at home. When joint 1 is revolute
  every other plane through that axis is this one turned, so it shows the reach
  against the height;
* **through the shoulder**: the plane normal to joint 1's axis at the height of the
  shoulder (the point of joint 2's axis nearest to axis 1; joint 2's point when the
  axes are parallel): the reach around the robot at shoulder height. When that level
  holds less than :data:`SHOULDER_SHARE` of the fullest level's samples (a SCARA's
  shoulder above its tool's range) the plane goes **across the base axis** at the
  level nearest the shoulder's among those holding 90 % of the fullest one's;
* for a planar arm, **the plane of motion**.

Points in a plane come from the analysis's own samples. Turning joint 1 turns the whole
arm about its axis, so when joint 1 is revolute each sample's tool point moves on a
circle about that axis as far as joint 1's limits allow: the plane through the axis
gets the (up to two) points where that arc crosses it, and the plane normal to the axis
gets the arc itself for the samples whose height is within half a pixel of the plane
(random points along it). A prismatic joint 1 slides the arm along its axis instead:
the plane across the axis gets each sample slid onto it (when joint 1's travel reaches
it), the plane through the axis the segments of the samples near it. A planar arm whose
joint 1 is not normal to its plane has its samples projected onto it, at a resolution
their number supports.

The reachable set is the pixels holding a point, with holes of one pixel closed,
smoothed by a Gaussian of :data:`SMOOTH` pixels: its 0.5 contour is the boundary. The
dexterous part is tested on a coarser grid (:data:`DEXTERITY_BINS`; fewer without a
closed form) with the analysis's test orientations.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .dexterity import orientation_hits
from .sampling import joint_ranges
from ...ik.nearest import principal_directions
from ...spatial import into_turn

#: pixels across the larger side of a section
SECTION_BINS = 150
#: pixels across the grid of dexterity tests (closed form; damped least squares)
DEXTERITY_BINS = 40
DEXTERITY_BINS_NUMERIC = 20
#: points put on the arcs of the section normal to the base axis
ARC_POINTS = 1_500_000
#: Gaussian smoothing of the reachable pixels, of the manipulability's mean and of the
#: dexterous test points (pixels of their grids)
SMOOTH = 1.0
MEAN_SMOOTH = 2.0
DEXTERITY_SMOOTH = 0.7
#: the least share of the fullest level's samples the shoulder's level must hold
SHOULDER_SHARE = 0.25


@dataclass(frozen=True)
class Section:
    """One plane's section of the workspace, world frame, SI.

    ``name`` and ``reason``: which plane and why (words for a title). Plane coordinates
    of a world point ``X`` are ``(X . u, X . v)``; the plane is ``X . normal = level``.
    ``axis``: ``(point, direction)`` of joint 1's axis in plane coordinates (a point
    for a plane normal to it: direction None). ``other``: the trace of the other
    section's plane, ``(point, direction)`` in plane coordinates, or None. ``extent``:
    ``(umin, umax, vmin, vmax)`` (m) of the pixel grids. ``reach (H, W)``: the smoothed
    reachable pixels in [0, 1], row 0 at ``vmin``; its 0.5 contour is the boundary.
    ``manipulability (H, W)``: the mean measure of the points in and around each pixel
    (display units, as the analysis's statistics), NaN where none. ``dexterous``:
    ``(h, w)`` in [0, 1] over the same extent (0.5 contour), or None when the robot
    has no dexterous workspace. ``points``: the points put in the plane.
    """

    name: str
    reason: str
    u: np.ndarray
    v: np.ndarray
    normal: np.ndarray
    level: float
    axis: tuple
    other: tuple | None
    extent: tuple
    reach: np.ndarray
    manipulability: np.ndarray
    dexterous: np.ndarray | None
    points: int

    def coords(self, X) -> np.ndarray:
        """``(..., 2)`` plane coordinates (m) of world points ``X (..., 3)``."""
        return np.asarray(X, float) @ np.stack([self.u, self.v], axis=1)

    def world(self, ab) -> np.ndarray:
        """``(..., 3)`` world points of plane coordinates ``ab (..., 2)``."""
        ab = np.asarray(ab, float)
        return ab[..., :1] * self.u + ab[..., 1:] * self.v + self.level * self.normal

    def inside(self, ab, field=None) -> np.ndarray:
        """``(...,)`` the ``reach`` field (or ``field``, on the same extent) at plane
        coordinates ``ab (..., 2)``, interpolated bilinearly between pixel centres as
        the contour is: inside the boundary where it is 0.5 or more."""
        return bilinear(self.reach if field is None else field, self.extent, ab)


def bilinear(F, extent, ab) -> np.ndarray:
    """``F (H, W)`` over ``extent`` (pixel centres), interpolated at ``ab (..., 2)``; 0
    beyond its edge."""
    H, W = F.shape
    u0, u1, v0, v1 = extent
    x = (np.asarray(ab, float)[..., 0] - u0) / (u1 - u0) * W - 0.5
    y = (np.asarray(ab, float)[..., 1] - v0) / (v1 - v0) * H - 0.5
    Fp = np.pad(np.nan_to_num(F), 1)
    x, y = np.clip(x + 1, 0, W + 0.999), np.clip(y + 1, 0, H + 0.999)
    i, j = np.floor(y).astype(int), np.floor(x).astype(int)
    fy, fx = y - i, x - j
    i1, j1 = np.minimum(i + 1, H + 1), np.minimum(j + 1, W + 1)
    return ((1 - fy) * ((1 - fx) * Fp[i, j] + fx * Fp[i, j1])
            + fy * ((1 - fx) * Fp[i1, j] + fx * Fp[i1, j1]))


# --- the planes -----------------------------------------------------------------------

def _base_axis(robot):
    """``(c1, z1, c2, z2)``: points and directions of joints 1 and 2's axes (home)."""
    from ...fk import chain_frames
    F = chain_frames(robot.chain, np.asarray(robot.home, float))
    c2, z2 = (F[1, :3, 3], F[1, :3, 2]) if robot.dof > 1 else (F[0, :3, 3], F[0, :3, 2])
    return F[0, :3, 3], F[0, :3, 2], c2, z2


def _world_direction(d, prefer):
    """The world axis (+x, +y or +z) normal to ``d`` nearest to ``prefer``, else
    ``prefer`` made normal to ``d``."""
    candidates = [e for e in np.eye(3) if abs(e @ d) < 1e-9]
    if candidates:
        return max(candidates, key=lambda e: abs(e @ prefer) + 1e-12 * (e @ np.eye(3)[0]))
    p = prefer - d * (prefer @ d)
    if np.linalg.norm(p) < 1e-9:
        p = np.eye(3)[int(np.argmin(np.abs(d)))]
        p = p - d * (p @ d)
    return p / np.linalg.norm(p)


def _positive(v):
    """``v`` or ``-v``, whichever is a positive world axis when either is one."""
    k = int(np.argmax(np.abs(v)))
    return -v if abs(abs(v[k]) - 1) < 1e-9 and v[k] < 0 else v


def _in_plane(n, e1):
    """Directions ``(u, v)`` of the plane normal to ``n``: the other two world axes in
    their order (x before y before z) when ``n`` is a world axis, else ``e1`` and
    ``n x e1`` (made positive)."""
    k = int(np.argmax(np.abs(n)))
    if abs(abs(n[k]) - 1) < 1e-9:
        i, j = (a for a in range(3) if a != k)
        return np.eye(3)[i], np.eye(3)[j]
    return e1, _positive(np.cross(n, e1))


def shoulder_height(robot) -> float:
    """The height (m, along joint 1's axis from its chain frame's origin) of the
    shoulder: the point of joint 2's axis nearest to axis 1, or joint 2's point when
    the two axes are parallel."""
    c1, z1, c2, z2 = _base_axis(robot)
    cos = float(z1 @ z2)
    if 1 - cos * cos > 1e-12:
        t = float((c1 - c2) @ (z2 - cos * z1)) / (1 - cos * cos)
        c2 = c2 + t * z2
    return float((c2 - c1) @ z1)


# --- points in a plane ------------------------------------------------------------------

def _turns(robot, Q):
    """``(lo, hi)`` (N,): how far joint 1 may turn (or slide) each sample, within its
    limits."""
    lo, hi = joint_ranges(robot)
    if robot.is_revolute[0] and hi[0] - lo[0] >= 2 * np.pi - 1e-12:
        return np.full(len(Q), -np.pi), np.full(len(Q), np.pi)
    return lo[0] - Q[:, 0], hi[0] - Q[:, 0]


def _cylindrical(P, c1, z1, e1):
    """``(r, h, theta)`` of points ``P`` about the axis ``c1 + t z1`` (angle from
    ``e1`` towards ``z1 x e1``)."""
    d = P - c1
    h = d @ z1
    e2 = np.cross(z1, e1)
    return np.hypot(d @ e1, d @ e2), h, np.arctan2(d @ e2, d @ e1)


def _through_axis(P, w, turns, c1, z1, e1):
    """World points ``(M, 3)`` and measures ``(M,)`` where the samples' arcs about
    the axis cross the half planes at angles 0 and pi."""
    r, h, theta = _cylindrical(P, c1, z1, e1)
    lo, hi = turns
    out, ws = [], []
    for side, target in ((1.0, 0.0), (-1.0, np.pi)):
        phi = into_turn(target - theta, lo)                           # the first turn >= lo
        ok = phi <= hi + 1e-12
        out.append(c1 + h[ok, None] * z1 + side * r[ok, None] * e1)
        ws.append(w[ok])
    return np.concatenate(out), np.concatenate(ws)


def _around_axis(rng, P, w, turns, c1, z1, e1, level, tol):
    """World points and measures on the arcs of the samples within ``tol`` of the
    plane ``(X - c1) . z1 = level``, moved onto it: random points along each arc, about
    :data:`ARC_POINTS` in all."""
    r, h, theta = _cylindrical(P, c1, z1, e1)
    near = np.flatnonzero(np.abs(h - level) <= tol)
    if near.size == 0:
        return np.zeros((0, 3)), np.zeros(0)
    per = int(np.clip(ARC_POINTS // near.size, 1, 4000))
    lo, hi = turns[0][near], turns[1][near]
    beta = theta[near, None] + lo[:, None] + (hi - lo)[:, None] * rng.uniform(
        size=(near.size, per))
    e2 = np.cross(z1, e1)
    rr = r[near, None, None]
    X = (c1 + level * z1 + rr * (np.cos(beta)[..., None] * e1 + np.sin(beta)[..., None] * e2))
    return X.reshape(-1, 3), np.repeat(w[near], per)


def _in_slab(P, w, normal, level, tol):
    """The samples within ``tol`` of the plane ``X . normal = level``, onto it."""
    d = P @ normal - level
    ok = np.abs(d) <= tol
    return P[ok] - d[ok, None] * normal, w[ok]


# --- pixels ---------------------------------------------------------------------------------

def _blur(F, sigma):
    """``F (H, W)`` smoothed by a Gaussian of ``sigma`` pixels (zero beyond the edge)."""
    if sigma <= 0:
        return F
    k = np.arange(-int(np.ceil(3 * sigma)), int(np.ceil(3 * sigma)) + 1)
    g = np.exp(-0.5 * (k / sigma) ** 2)
    g /= g.sum()
    n = len(k) // 2
    for axis in (0, 1):
        P = np.pad(F, [(n, n) if a == axis else (0, 0) for a in (0, 1)])
        F = sum(gi * np.take(P, np.arange(i, i + F.shape[axis]), axis=axis)
                for i, gi in enumerate(g))
    return F


def _fields(ab, w, extent, shape):
    """``(reach, manipulability)`` pixel fields of the points ``ab (M, 2)`` with
    measures ``w (M,)`` (see :class:`Section`)."""
    from .volume import neighbourhood
    H, W = shape
    u0, u1, v0, v1 = extent
    j = np.floor((ab[:, 0] - u0) / (u1 - u0) * W).astype(np.int64)
    i = np.floor((ab[:, 1] - v0) / (v1 - v0) * H).astype(np.int64)
    ok = (i >= 0) & (i < H) & (j >= 0) & (j < W)
    flat = i[ok] * W + j[ok]
    count = np.bincount(flat, minlength=H * W).reshape(H, W).astype(float)
    total = np.bincount(flat, weights=w[ok], minlength=H * W).reshape(H, W)
    # a hole of one pixel is a pixel no sample happened to fall in: closed
    occupied = neighbourhood(neighbourhood(count > 0, np.logical_or), np.logical_and)
    reach = _blur(occupied.astype(float), SMOOTH)
    den = _blur(count, MEAN_SMOOTH)
    with np.errstate(invalid="ignore", divide="ignore"):
        manip = np.where(den > 1e-6, _blur(total, MEAN_SMOOTH) / den, np.nan)
    return reach, manip


def _grid(ab, pix):
    """``(extent, (H, W))``: pixels of side ``pix`` over the points ``ab`` and a margin
    of three pixels."""
    lo = np.floor(ab.min(axis=0) / pix - 3) * pix
    hi = np.ceil(ab.max(axis=0) / pix + 3) * pix
    W, H = (int(round(x)) for x in (hi - lo) / pix)
    return (float(lo[0]), float(lo[0] + W * pix), float(lo[1]), float(lo[1] + H * pix)), (H, W)


def _dexterity(robot, Q, P, vol, tests, fraction, sec, bins):
    """The dexterous field of section ``sec`` on a grid of about ``bins`` pixels
    across: 1 where a test point reaches every test orientation (or the ``fraction``)."""
    u0, u1, v0, v1 = sec.extent
    pix = max(u1 - u0, v1 - v0) / bins
    W, H = max(2, int(round((u1 - u0) / pix))), max(2, int(round((v1 - v0) / pix)))
    a = u0 + (np.arange(W) + 0.5) * (u1 - u0) / W
    b = v0 + (np.arange(H) + 0.5) * (v1 - v0) / H
    ab = np.stack(np.meshgrid(a, b), axis=-1).reshape(-1, 2)
    inside = np.flatnonzero(sec.inside(ab) >= 0.5)
    dex = np.zeros(H * W)
    if inside.size:
        at, hit = orientation_hits(robot, Q, P, vol.grid, vol.order, vol.sorted_cells,
                                   sec.world(ab[inside]), tests)
        dex[inside[at]] = hit.mean(axis=1) >= fraction - 1e-12
    return _blur(dex.reshape(H, W), DEXTERITY_SMOOTH)


# --- the sections -------------------------------------------------------------------------

def _planes(robot, P, dim, pix):
    """The planes' specifications: dicts of ``name``, ``reason``, ``u``, ``v``,
    ``normal``, ``level`` and how their points are found (``kind``: the plane "contains"
    joint 1's axis, is "across" it, or takes the samples in a "slab" about it; with the
    axis ``c1``, ``z1``, ``e1`` and the height ``h``)."""
    c1, z1, _, _ = _base_axis(robot)
    home = robot.fk(np.asarray(robot.home, float))[:3, 3] - c1
    e1 = _world_direction(z1, home - z1 * (home @ z1))
    revolute = bool(robot.is_revolute[0])
    h = (P - c1) @ z1
    common = dict(c1=c1, z1=z1, e1=e1)
    if dim == 2:
        basis = principal_directions(P)[2]
        n = basis[2]
        turning = revolute and abs(abs(n @ z1) - 1) < 1e-6
        u, v = _in_plane(n, e1 if turning else _positive(basis[0]))
        return [dict(common, name="the plane of motion", kind="across" if turning else "slab",
                     reason="every joint moves the arm in this plane", u=u, v=v,
                     normal=_positive(np.cross(u, v)), h=float(np.mean(h)),
                     level=float(P[0] @ _positive(np.cross(u, v))))]
    through = dict(common, name="through the base axis", kind="contains",
                   reason=("joint 1 turns it about its axis: reach against height"
                           if revolute else "joint 1 slides the arm along it"),
                   u=e1, v=_positive(z1))
    through["normal"] = _positive(np.cross(through["u"], through["v"]))
    through["level"] = float(c1 @ through["normal"])
    level, name = shoulder_height(robot), "through the shoulder"
    reason = "across the base axis at the height of joint 2's axis"
    counts, edges = np.histogram(h, bins=max(1, int(np.ceil(np.ptp(h) / pix))))
    k = int(np.clip(np.searchsorted(edges, level) - 1, 0, len(counts) - 1))
    if not edges[0] <= level <= edges[-1] or counts[k] < SHOULDER_SHARE * counts.max():
        # the shoulder's level holds few samples (a SCARA's shoulder above its tool's
        # range): the full level nearest to it
        mid = (edges[:-1] + edges[1:]) / 2
        full = np.flatnonzero(counts >= 0.9 * counts.max())
        m = full[np.argmin(np.abs(mid[full] - level))]
        level, name = float(mid[m]), "across the base axis"
        reason = "at the level nearest the shoulder's that the tool fills"
    u, v = _in_plane(z1, e1)
    normal = _positive(np.cross(u, v))
    across = dict(common, name=name, reason=reason, kind="across",
                  u=u, v=v, normal=normal, h=level, level=float((c1 + level * z1) @ normal))
    through["other"] = (c1 + level * z1, e1)
    across["other"] = (c1, e1)
    return [through, across]


def _points(rng, robot, Q, P, w, plane, pix):
    """World points ``(M, 3)`` of the plane and their measures; the pixel size (the
    slab's points set a coarser one)."""
    c1, z1, e1 = plane["c1"], plane["z1"], plane["e1"]
    turns = _turns(robot, Q)
    everything = plane["name"] == "the plane of motion"
    if plane["kind"] == "slab":
        X, ws = _in_slab(P, w, plane["normal"], plane["level"], np.inf if everything else pix)
        # pixels of a few points each: the slab's points are what there is
        while len(X) and pix < 1e3 and len(X) < 8 * np.unique(
                np.floor(X / pix), axis=0).shape[0]:
            pix *= 1.25
        return X, ws, pix
    if robot.is_revolute[0]:
        if plane["kind"] == "contains":
            return (*_through_axis(P, w, turns, c1, z1, e1), pix)
        tol = np.inf if everything else pix / 2
        return (*_around_axis(rng, P, w, turns, c1, z1, e1, plane["h"], tol), pix)
    # a prismatic joint 1 slides the arm along its axis: each sample on a segment
    if plane["kind"] == "contains":
        return (*_along_axis(rng, P, w, turns, z1, plane["normal"], plane["level"], pix / 2),
                pix)
    return (*_onto_level(P, w, turns, c1, z1, plane["h"]), pix)


def _along_axis(rng, P, w, travel, z1, normal, level, tol):
    """World points and measures on the segments along ``z1`` (as far as joint 1's
    ``travel`` allows) of the samples within ``tol`` of the plane ``X . normal =
    level``, which holds ``z1``: random points along each, about :data:`ARC_POINTS`."""
    near = np.flatnonzero(np.abs(P @ normal - level) <= tol)
    if near.size == 0:
        return np.zeros((0, 3)), np.zeros(0)
    per = int(np.clip(ARC_POINTS // near.size, 1, 4000))
    lo, hi = travel[0][near], travel[1][near]
    t = lo[:, None] + (hi - lo)[:, None] * rng.uniform(size=(near.size, per))
    X = P[near, None, :] - (P[near] @ normal - level)[:, None, None] * normal \
        + t[..., None] * z1
    return X.reshape(-1, 3), np.repeat(w[near], per)


def _onto_level(P, w, travel, c1, z1, level):
    """The samples slid along ``z1`` onto the plane ``(X - c1) . z1 = level``, those
    whose joint 1 ``travel`` reaches it."""
    t = level - (P - c1) @ z1
    ok = (travel[0] <= t) & (t <= travel[1])
    return P[ok] + t[ok, None] * z1, w[ok]


def workspace_sections(robot, rng, Q, P, w, vol, tests=None, fraction=1.0,
                       progress=None) -> list:
    """The :class:`Section` s of the workspace sampled by ``Q (N, n)`` with tool points
    ``P (N, 3)`` and manipulability ``w (N,)``: through the base axis and through the
    shoulder, or the plane of motion of a planar arm; none when the tool moves along a
    line. ``vol``: the analysis's :class:`~.volume.Volume` (its grid finds the starts of
    the dexterity tests); ``tests``: the :class:`~.dexterity.Orientations`, None when
    the robot has no dexterous workspace; ``fraction``: the share of them a dexterous
    point reaches. ``rng`` places the points along the arcs."""
    progress = progress or (lambda *a: None)
    dim = vol.grid.dim
    if dim < 2:
        return []
    c1, z1, _, _ = _base_axis(robot)
    r = np.linalg.norm(np.cross(P - c1, z1), axis=1)
    h = (P - c1) @ z1
    pix0 = max(2 * float(r.max()), float(np.ptp(h))) / SECTION_BINS
    out = []
    planes = _planes(robot, P, dim, pix0)
    for k, plane in enumerate(planes):
        progress("sections", k, len(planes))
        X, ws, pix = _points(rng, robot, Q, P, w, plane, pix0)
        if len(X) == 0:
            continue
        sec = _section(plane, X, ws, pix)
        if tests is not None:
            bins = DEXTERITY_BINS if tests.exact else DEXTERITY_BINS_NUMERIC
            sec = replace(sec, dexterous=_dexterity(robot, Q, P, vol, tests, fraction, sec,
                                                    bins))
        out.append(sec)
    progress("sections", len(planes), len(planes))
    return out


def _section(plane, X, ws, pix) -> Section:
    """The :class:`Section` of ``plane`` (:func:`_planes`) holding the world points
    ``X`` with measures ``ws``, at pixels of side ``pix``."""
    UV = np.stack([plane["u"], plane["v"]], axis=1)
    ab = X @ UV
    extent, shape = _grid(ab, pix)
    reach, manip = _fields(ab, ws, extent, shape)
    c1, z1 = plane["c1"], plane["z1"]
    axis = ((c1 @ UV, z1 @ UV) if np.linalg.norm(z1 @ UV) > 0.5 else
            ((c1 + plane.get("h", 0.0) * z1) @ UV, None))
    other = plane.get("other")
    return Section(plane["name"], plane["reason"], plane["u"], plane["v"], plane["normal"],
                   plane["level"], axis, None if other is None else (other[0] @ UV,
                                                                     other[1] @ UV),
                   extent, reach, manip, None, len(X))
