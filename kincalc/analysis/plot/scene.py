"""What a figure of arms shows beyond the links, in SI: each revolute joint's axis, the
view that tells the panels apart, the pedestal and ground below the base, and where the
base and tool labels go (clear of everything else drawn).

A joint is drawn as a short cylinder along its axis with a thin arrow beyond it to the
axis's positive end, where its number is written. Two configurations with the same joint
points can differ in their joints' axes only: a wrist flip (joint 4 and 6 turned half a
turn, joint 5 negated) leaves the spherical wrist's centre where it was and reverses joint
5's axis, whose arrow then points the other way.

The view of a 3D figure is chosen from the data (:func:`choose_view`): the azimuth and
elevation among :data:`AZIMUTHS` x :data:`ELEVATIONS` whose orthographic projection keeps
the most different the two panels that look most alike, each arm's own spread counting
as well (a view along a link hides it).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ...fk import chain_frames
from ..reports import joint_vector
from .geometry import arm_points, drawing_plane, joint_points
from .style import ArmPoints, TRIAD_FRACTION

#: the cylinder of a revolute joint and its axis arrow, as fractions of the robot's
#: characteristic length
CYLINDER_FRACTION = 0.07
AXIS_FRACTION = 0.18
#: the pedestal's radius and least height (below the base frame), fractions of the length
PEDESTAL_RADIUS = 0.06
PEDESTAL_HEIGHT = 0.25
#: the views tried (degrees, matplotlib's azimuth and elevation)
AZIMUTHS = tuple(range(-180, 180, 10))
ELEVATIONS = (20, 30, 40)
#: matplotlib's default view, the tie-breaker
DEFAULT_VIEW = (-60.0, 30.0)
#: weight of each arm's own spread against the panels' difference when choosing a view
SPREAD_WEIGHT = 0.25
#: a triad axis whose screen length is under this fraction of its length is drawn as a
#: dot (towards the viewer) or a cross (away)
SIGHT_FRACTION = 0.25
#: a label's distance from the point it names, as a fraction of the panel's half width
LABEL_OFFSET = 0.09


class Panel(NamedTuple):
    """One configuration's drawing, world frame, metres.

    ``arm``: the links (:class:`ArmPoints`); ``joints (n, 3)``: the joint points;
    ``axes (n, 3)``: the unit joint axes; ``revolute (n,)``; ``marks (m, 3)``: the points
    the view is chosen on, the same rows for every panel of a robot (joint points, the
    positive ends of the joint axes, the tool point and its triad's ends).
    """

    arm: ArmPoints
    joints: np.ndarray
    axes: np.ndarray
    revolute: np.ndarray
    marks: np.ndarray


@dataclass(frozen=True)
class Scene:
    """A figure's geometry, SI, before any drawing.

    ``panels``: one :class:`Panel` each. ``plane``: the plane of a planar arm drawn in 2D
    (:func:`drawing_plane`), or None for a view of the arm in space from ``view =
    (azimuth, elevation)`` (degrees, :func:`choose_view`), orthographic. ``centre (2,)``
    and ``half``: the square every panel shows, in screen coordinates (m, see
    :meth:`screen`). In space, ``ground = (x0, x1, y0, y1, z)``: the rectangle of ground
    drawn (world, under everything drawn), and ``pedestal = (x, y, top, bottom,
    radius)``: the column from the base frame's origin down to it; None in 2D.
    ``labels``: per panel where the base and tool labels go, ``{"base": (dx, dy),
    "tool": (dx, dy)}``, unit directions on the screen. ``length``: the robot's
    characteristic length (m), the scale of the joints, axes and triads.
    """

    panels: tuple
    plane: tuple | None
    view: tuple | None
    centre: np.ndarray
    half: float
    ground: tuple | None
    pedestal: tuple | None
    labels: tuple
    length: float

    def screen(self, points) -> np.ndarray:
        """``(..., 2)`` screen coordinates (m) of world points ``(..., 3)``: the plane's
        coordinates for a planar arm, else the orthographic projection of the view."""
        if self.plane is not None:
            u, v, _ = self.plane
            return np.asarray(points, float) @ np.stack([u, v], axis=1)
        return project(points, self.view)

    def depth(self, points) -> np.ndarray:
        """``(...,)`` how near world points ``(..., 3)`` are to the viewer (m, larger is
        nearer): what is drawn over what in a view."""
        if self.plane is not None:
            u, v, _ = self.plane
            return np.asarray(points, float) @ np.cross(u, v)
        a, e = np.radians(self.view[0]), np.radians(self.view[1])
        eye = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
        return np.asarray(points, float) @ eye

    def triad_mark(self, axis) -> str:
        """How a triad's unit ``axis (3,)`` is drawn: ``"arrow"``, or along the line of
        sight (its screen length under ``SIGHT_FRACTION`` of its length) a dot
        (``"towards"`` the viewer) or a cross (``"away"``)."""
        if np.linalg.norm(self.screen(axis)) > SIGHT_FRACTION:
            return "arrow"
        return "towards" if self.depth(axis) > 0 else "away"

    def triad_marks(self) -> set:
        """``{(j, mark)}``: how the base and tool triads' axes ``j`` (0 x, 1 y, 2 z) are
        drawn in some panel (:meth:`triad_mark`), for the legend."""
        return {(j, self.triad_mark(T[:3, j])) for p in self.panels
                for T in (p.arm.base, p.arm.tool) for j in range(3)}

    def cylinder(self, k: int, i: int) -> np.ndarray:
        """``(2, 3)``: the ends of joint ``i``'s cylinder in panel ``k``."""
        p = self.panels[k]
        h = 0.5 * CYLINDER_FRACTION * self.length
        return np.stack([p.joints[i] - h * p.axes[i], p.joints[i] + h * p.axes[i]])

    def arrow(self, k: int, i: int) -> np.ndarray:
        """``(2, 3)``: joint ``i``'s axis arrow in panel ``k``, from the cylinder's
        positive end to the axis's positive end (where the joint's number goes)."""
        p = self.panels[k]
        h = 0.5 * CYLINDER_FRACTION * self.length
        return np.stack([p.joints[i] + h * p.axes[i],
                         p.joints[i] + AXIS_FRACTION * self.length * p.axes[i]])


def screen_axes(view) -> tuple[np.ndarray, np.ndarray]:
    """The world directions ``(right, up)`` of the screen seen from ``view = (azimuth,
    elevation)`` (degrees, as matplotlib's 3D axes take them): ``(-sin a, cos a, 0)``
    and ``(-sin e cos a, -sin e sin a, cos e)``."""
    a, e = np.radians(view[0]), np.radians(view[1])
    return (np.array([-np.sin(a), np.cos(a), 0.0]),
            np.array([-np.sin(e) * np.cos(a), -np.sin(e) * np.sin(a), np.cos(e)]))


def project(points, view) -> np.ndarray:
    """``(..., 2)``: the orthographic projection of ``points (..., 3)`` on the screen of
    ``view`` (:func:`screen_axes`), in the points' unit."""
    return np.asarray(points, float) @ np.stack(screen_axes(view), axis=1)


def arm_panel(robot, q) -> Panel:
    """The drawing of ``robot`` at joint values ``q (n,)`` (rad / m): see :class:`Panel`."""
    q = joint_vector(robot, q)
    arm = arm_points(robot, q)
    joints = joint_points(robot, q)
    axes = chain_frames(robot.chain, q)[:, :3, 2]
    L = robot.characteristic_length
    T = arm.tool
    marks = np.concatenate([joints, joints + AXIS_FRACTION * L * axes, T[None, :3, 3],
                            T[:3, 3] + TRIAD_FRACTION * L * T[:3, :3].T])
    return Panel(arm, joints, axes, np.array(robot.is_revolute), marks)


def arm_scene(robot, Q) -> Scene:
    """The geometry of a figure of ``robot`` at each configuration of ``Q (k, n)``.

    Returns
    -------
    Scene
        In 2D in the plane of a planar arm (:func:`drawing_plane`), otherwise in space
        seen from the view of :func:`choose_view`, with the ground at or below the
        lowest point drawn and at least ``PEDESTAL_HEIGHT`` below the base, and a
        pedestal from the base frame's origin down to it.
    """
    Q = np.atleast_2d(np.asarray(Q, dtype=float))
    panels = tuple(arm_panel(robot, q) for q in Q)
    L = robot.characteristic_length
    plane = drawing_plane(robot, Q)
    view = ground = pedestal = None
    drawn = np.concatenate([np.concatenate([p.arm.points, p.marks, _triad_ends(p.arm.base, L)])
                            for p in panels])
    if plane is None:
        view = choose_view([p.marks for p in panels], L)
        base = panels[0].arm.base[:3, 3]
        z = min(base[2] - PEDESTAL_HEIGHT * L, float(drawn[:, 2].min()) - 0.02 * L)
        r = PEDESTAL_RADIUS * L
        pedestal = (base[0], base[1], base[2], z, r)
        lo, hi = drawn[:, :2].min(axis=0) - 0.1 * L, drawn[:, :2].max(axis=0) + 0.1 * L
        ground = (lo[0], hi[0], lo[1], hi[1], z)
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])])
        ring = base + r * np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]])
        drawn = np.concatenate([drawn, corners, ring, ring - [0, 0, base[2] - z]])
    scene = Scene(panels, plane, view, np.zeros(2), 1.0, ground, pedestal, (), L)
    S = scene.screen(drawn)
    lo, hi = S.min(axis=0), S.max(axis=0)
    # room for the labels (and, in space, the scale bar and the axes under the ground)
    half = max(float(np.max(hi - lo)) / 2, TRIAD_FRACTION * L) * (1.12 if plane else 1.06)
    centre = (lo + hi) / 2
    scene = Scene(panels, plane, view, centre, half, ground, pedestal, (), L)
    labels = tuple({name: label_direction(scene, k, name) for name in ("base", "tool")}
                   for k in range(len(panels)))
    return Scene(panels, plane, view, centre, half, ground, pedestal, labels, L)


def _triad_ends(T, L) -> np.ndarray:
    return T[:3, 3] + TRIAD_FRACTION * L * T[:3, :3].T


def choose_view(marks, L) -> tuple[float, float]:
    """The ``(azimuth, elevation)`` (degrees) that tells the panels apart.

    ``marks``: per panel an ``(m, 3)`` array of the same points (:attr:`Panel.marks`).
    The score of a view is the least RMS distance between two panels' projected marks
    (how alike the two most alike panels look) plus ``SPREAD_WEIGHT`` times the least
    second singular value of one panel's centred projected marks (how flat the flattest
    arm looks); one panel is scored on its spread alone. Ties go to the view nearest
    matplotlib's default (-60, 30).
    """
    M = np.stack([np.asarray(m, float) for m in marks]) / max(L, 1e-300)
    best, best_key = DEFAULT_VIEW, None
    for e in ELEVATIONS:
        for a in AZIMUTHS:
            S = project(M, (a, e))                                  # (k, m, 2)
            C = S - S.mean(axis=1, keepdims=True)
            spread = min(float(np.linalg.svd(c, compute_uv=False)[-1]) for c in C)
            score = SPREAD_WEIGHT * spread / np.sqrt(M.shape[1])
            if len(S) > 1:
                d = S[:, None] - S[None]                              # (k, k, m, 2)
                rms = np.sqrt(np.mean(np.sum(d * d, axis=-1), axis=-1))
                score += float(np.min(rms[np.triu_indices(len(S), 1)]))
            near = abs((a - DEFAULT_VIEW[0] + 180) % 360 - 180) + abs(e - DEFAULT_VIEW[1])
            key = (round(score, 9), -near)
            if best_key is None or key > best_key:
                best, best_key = (float(a), float(e)), key
    return best


def obstacles(scene, k) -> np.ndarray:
    """``(s, 2, 2)``: the screen segments drawn in panel ``k`` (links, joints, axes,
    triads, pedestal), for placing labels clear of them."""
    p = scene.panels[k]
    L = scene.length
    segs = [np.stack([p.arm.points[:-1], p.arm.points[1:]], axis=1)]
    for i in np.flatnonzero(p.revolute):
        segs.append(scene.cylinder(k, i)[None])
        segs.append(scene.arrow(k, i)[None])
    for T in (p.arm.base, p.arm.tool):
        ends = _triad_ends(T, L)
        segs.append(np.stack([np.broadcast_to(T[:3, 3], ends.shape), ends], axis=1))
    # joints are markers: a segment of no length each
    segs.append(np.stack([p.joints, p.joints], axis=1))
    if scene.pedestal is not None:
        x, y, top, bottom, _ = scene.pedestal
        segs.append(np.array([[[x, y, top], [x, y, bottom]]]))
    return scene.screen(np.concatenate(segs))


def label_direction(scene, k, name) -> tuple[float, float]:
    """The unit screen direction ``(dx, dy)`` from the origin of frame ``name`` ("base"
    or "tool") of panel ``k`` to its label: of 16 directions, the one whose label (a
    point ``LABEL_OFFSET`` of the half width away, and one twice as far) keeps farthest
    from every segment drawn."""
    p = scene.panels[k]
    T = p.arm.base if name == "base" else p.arm.tool
    anchor = scene.screen(T[:3, 3])
    segs = obstacles(scene, k)
    r = LABEL_OFFSET * scene.half
    best, best_d = (1.0, -1.0), -1.0
    # from down-right round the clock: the first of equals is the usual place
    for t in np.radians(np.arange(-45, 315, 22.5)):
        d = np.array([np.cos(t), np.sin(t)])
        clear = min(_distance(anchor + f * r * d, segs) for f in (1.0, 1.6, 2.2))
        if clear > best_d + 1e-9 * scene.half:
            best, best_d = (float(d[0]), float(d[1])), clear
    return best


def _distance(x, segs) -> float:
    """Least distance from the point ``x (2,)`` to the segments ``segs (s, 2, 2)``."""
    a, b = segs[:, 0], segs[:, 1]
    ab = b - a
    t = np.clip(np.sum((x - a) * ab, axis=1) / np.maximum(np.sum(ab * ab, axis=1), 1e-300),
                0.0, 1.0)
    return float(np.min(np.linalg.norm(a + t[:, None] * ab - x, axis=1)))
