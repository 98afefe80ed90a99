"""Drawing one panel of an arm in space: the orthographic view of a :class:`~.scene.Scene`
on plain 2D axes, so that the arm fills the panel and what is nearer the viewer is
drawn over what is farther (each link segment, joint and the pedestal in the order of
its depth). The ground is a grid of round spacing, lengths are read off a scale bar in
the display unit, and a small x/y/z sign in the corner shows the world's axes."""

from __future__ import annotations

import numpy as np

from .scene import AXIS_FRACTION, LABEL_OFFSET
from .style import (GROUND_COLOUR, JOINT_FACE, LINK_COLOUR, PEDESTAL_COLOUR, TICK_STEPS,
                    TRIAD_COLOURS, TRIAD_FRACTION)

#: colour of joint axes' arrows, numbers, labels, the scale bar and the world's axes
INK = "0.25"
#: the depth order: zorder 1 (farthest) to 2 (nearest); triads and labels above
DEPTH_Z = (1.0, 2.0)


def round_step(span: float, count: int) -> float:
    """The largest round number (``TICK_STEPS`` times a power of ten) not above ``span
    / count``: a grid or scale bar step."""
    raw = span / max(count, 1)
    if not raw > 0:
        return 1.0
    power = 10.0 ** np.floor(np.log10(raw))
    return float(max(s for s in TICK_STEPS if s * power <= raw * 1.0001) * power)


def draw_view(ax, scene, k, scale, unit):
    """Draw panel ``k`` of ``scene`` (in space) on the 2D axes ``ax``, lengths times
    ``scale`` (display units, named ``unit``; "" for none)."""
    c, half = scene.centre * scale, scene.half * scale
    ax.set_aspect("equal")
    ax.set_xlim(c[0] - half, c[0] + half)
    ax.set_ylim(c[1] - half, c[1] + half)
    ax.set_axis_off()
    depth = _depth_scale(scene)
    _ground(ax, scene, scale)
    _pedestal(ax, scene, scale, depth)
    p = scene.panels[k]
    to2 = lambda X: scene.screen(X) * scale                       # noqa: E731
    pts = p.arm.points
    for a, b in zip(pts[:-1], pts[1:]):
        ax.plot(*to2(np.stack([a, b])).T, color=LINK_COLOUR, lw=5, solid_capstyle="round",
                zorder=depth((a + b) / 2))
    for i in np.flatnonzero(p.revolute):
        z = depth(p.joints[i]) + 0.002
        cyl = to2(scene.cylinder(k, i))
        # a cylinder: a black-edged bar with round caps (a disc seen end-on)
        ax.plot(*cyl.T, color="black", lw=9, solid_capstyle="round", zorder=z)
        ax.plot(*cyl.T, color=JOINT_FACE, lw=6.6, solid_capstyle="round", zorder=z + 0.001)
        arrow = to2(scene.arrow(k, i))
        ax.plot(*arrow.T, color=INK, lw=1.8, zorder=z + 0.001)
        tip = to2(p.joints[i] + (AXIS_FRACTION + 0.045) * scene.length * p.axes[i])
        ax.text(*tip, str(i + 1), fontsize="x-small", color=INK, ha="center", va="center",
                zorder=z + 0.001)
    for i in np.flatnonzero(~p.revolute):
        ax.scatter(*to2(p.joints[i]), marker="s", s=110, c=JOINT_FACE, edgecolors="black",
                   linewidths=1.0, zorder=depth(p.joints[i]) + 0.003)
    frames(ax, scene, k, scale)
    _scale_bar(ax, c, half, unit)
    _world_axes(ax, scene, c, half)


def frames(ax, scene, k, scale):
    """Panel ``k``'s base and tool frames: their triads and their labels, placed clear
    of the rest (:attr:`Scene.labels`)."""
    p = scene.panels[k]
    for T, name in ((p.arm.base, "base"), (p.arm.tool, "tool")):
        for j, colour in enumerate(TRIAD_COLOURS):
            triad_axis(ax, scene, T, j, scale, colour)
        dx, dy = scene.labels[k][name]
        at = (scene.screen(T[:3, 3]) + LABEL_OFFSET * scene.half * np.array([dx, dy])) * scale
        ax.text(*at, name, fontsize="small", color=INK, zorder=6, **align(dx, dy))


def triad_axis(ax, scene, T, j, scale, colour):
    """Axis ``j`` of the frame ``T`` as an arrow, or as a dot (towards the viewer) or a
    cross (away) where it runs along the line of sight (:meth:`Scene.triad_mark`)."""
    o = scene.screen(T[:3, 3]) * scale
    mark = scene.triad_mark(T[:3, j])
    if mark == "arrow":
        e = scene.screen(T[:3, 3] + TRIAD_FRACTION * scene.length * T[:3, j]) * scale
        ax.annotate("", xy=e, xytext=o, zorder=4, arrowprops=dict(
            arrowstyle="-|>", color=colour, lw=2.2, shrinkA=0, shrinkB=0, mutation_scale=11))
    else:
        towards = mark == "towards"
        ax.scatter(*o, marker="." if towards else "x", s=45 if towards else 30, c=colour,
                   linewidths=2, zorder=6)


def align(dx, dy) -> dict:
    """Text alignment for a label placed in the direction ``(dx, dy)`` from its point:
    the text extends away from it."""
    return {"ha": "left" if dx > 0.38 else "right" if dx < -0.38 else "center",
            "va": "bottom" if dy > 0.38 else "top" if dy < -0.38 else "center"}


def _depth_scale(scene):
    """A function from world points to a zorder in ``DEPTH_Z``: nearer is higher."""
    p = np.concatenate([pn.arm.points for pn in scene.panels])
    d = scene.depth(p)
    lo, span = float(d.min()) - scene.length, float(np.ptp(d)) + 2 * scene.length
    return lambda x: DEPTH_Z[0] + (DEPTH_Z[1] - DEPTH_Z[0]) * (float(scene.depth(x)) - lo) / span


def _ground(ax, scene, scale):
    """The ground rectangle, filled, with grid lines at a round spacing."""
    x0, x1, y0, y1, z = (v * scale for v in scene.ground)
    corners = np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]]) / scale
    ax.fill(*(scene.screen(corners) * scale).T, color=GROUND_COLOUR, lw=0, zorder=0.1)
    step = round_step(max(x1 - x0, y1 - y0), 8)
    for lo, hi, other, along in ((x0, x1, (y0, y1), 0), (y0, y1, (x0, x1), 1)):
        for t in np.arange(np.ceil(lo / step), np.floor(hi / step) + 1) * step:
            seg = np.zeros((2, 3))
            seg[:, along], seg[:, 1 - along], seg[:, 2] = t, other, z
            ax.plot(*(scene.screen(seg / scale) * scale).T, color="white", lw=0.9, zorder=0.2)


def _pedestal(ax, scene, scale, depth):
    """The pedestal: a grey column (its silhouette, see-through: it hides nothing) with
    its top."""
    x, y, top, bottom, r = scene.pedestal
    a = np.linspace(0, 2 * np.pi, 49)
    ring = np.stack([x + r * np.cos(a), y + r * np.sin(a), np.zeros_like(a)], axis=1)
    up = np.array([0, 0, 1.0])
    t = scene.screen(ring + top * up) * scale
    b = scene.screen(ring + bottom * up) * scale
    # the silhouette: the hull of the two ellipses (a convex outline in orthographic view)
    hull = _hull(np.concatenate([t, b]))
    z = depth(np.array([x, y, (top + bottom) / 2]))
    ax.fill(*hull.T, fc=PEDESTAL_COLOUR, alpha=0.45, lw=1, ec="0.55", zorder=z)
    ax.fill(*t.T, fc="0.88", alpha=0.6, lw=1, ec="0.55", zorder=z + 0.001)


def _hull(P):
    """The convex hull of points ``P (m, 2)``, counter-clockwise (monotone chain)."""
    P = P[np.lexsort((P[:, 1], P[:, 0]))]

    def half(points):
        out = []
        for p in points:
            while len(out) >= 2:
                a, b = out[-1] - out[-2], p - out[-2]
                if a[0] * b[1] - a[1] * b[0] > 0:       # a left turn: keep
                    break
                out.pop()
            out.append(p)
        return out
    lower, upper = half(P), half(P[::-1])
    return np.array(lower[:-1] + upper[:-1])


def _scale_bar(ax, c, half, unit):
    """A bar of round length in the bottom left corner, labelled with it."""
    step = round_step(0.5 * half, 1)
    x0, y0 = c[0] - 0.94 * half, c[1] - 0.92 * half
    ax.plot([x0, x0 + step], [y0, y0], color=INK, lw=2, solid_capstyle="butt", zorder=6)
    for x in (x0, x0 + step):
        ax.plot([x, x], [y0 - 0.015 * half, y0 + 0.015 * half], color=INK, lw=1, zorder=6)
    ax.text(x0 + step / 2, y0 + 0.03 * half, f"{step:g}{' ' + unit if unit else ''}",
            fontsize="x-small", color=INK, ha="center", va="bottom", zorder=6)


def _world_axes(ax, scene, c, half):
    """The world's x, y and z in the bottom right corner, as seen in the view."""
    o = np.array([c[0] + 0.8 * half, c[1] - 0.84 * half])
    for j, name in enumerate("xyz"):
        d = scene.screen(np.eye(3)[j]) * 0.11 * half
        ax.annotate("", xy=o + d, xytext=o, zorder=6, arrowprops=dict(
            arrowstyle="-|>", color="0.45", lw=1.2, shrinkA=0, shrinkB=0, mutation_scale=7))
        n = np.linalg.norm(d)
        at = o + d + (d / n if n > 1e-12 * half else np.array([0, 1.0])) * 0.04 * half
        ax.text(*at, name, fontsize="x-small", color="0.35", ha="center", va="center",
                zorder=6)
