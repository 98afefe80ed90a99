"""Drawing arm configurations side by side (``kincalc plot``, ``ik --plot``), in 3D or
in the plane of a planar arm."""

from __future__ import annotations

import numpy as np

from .files import (check_output, default_style, fit_title, new_figure, panel_grid,
                    save_figure, title_inches)
from .geometry import arm_points, drawing_plane, joint_points
from .style import (Drawing, JOINT_FACE, LINK_COLOUR, TICK_STEPS, TRIAD_COLOURS,
                    TRIAD_FRACTION, require_matplotlib)


# --- arms ------------------------------------------------------------------------

def draw_arms(robot, Q, titles, path, *, suptitle=None, units=None, dpi=100) -> Drawing:
    """Draw the arm at each configuration of ``Q`` and write it to ``path``.

    One panel per configuration, at most ``MAX_COLUMNS`` a row, each
    ``PANEL_INCHES`` square. Links are thick lines, revolute joints circles,
    prismatic joints squares, the base and tool frames x/y/z triads
    (red/green/blue) ``TRIAD_FRACTION`` of the robot's characteristic
    length long. Every panel has the same equal-scaled limits. A planar arm
    (:func:`drawing_plane`) is drawn in 2D in its plane, with out-of-plane
    triad axes shown as a dot (towards the viewer) or a cross (away).

    Parameters
    ----------
    robot : Robot
    Q : array_like (k, n) or (n,)
        Joint values, rad / m.
    titles : sequence of k str
        Panel titles (see :func:`config_title`).
    path : str, Path or kincalc.outputs.Target
        Output file; its suffix picks the format: .png, .svg or .pdf. An existing
        file is refused unless given as a ``Target(path, force=True)``, and then
        only a regular file is replaced (:mod:`kincalc.outputs`).
    suptitle : str, optional
        Figure title; default the robot's name and title.
    units : Units, optional
        Display units (lengths in ``units.length``); default the robot's.
    dpi : int
        Pixels per inch of PNG output (and of raster parts of SVG/PDF).

    Returns
    -------
    Drawing

    Raises
    ------
    InputError
        Unsupported suffix, missing folder, unwritable or existing file.
    MissingExtra
        matplotlib is not installed.
    """
    from ..results import Units
    fmt = check_output(path)
    mpl = require_matplotlib("drawing")
    Q = np.atleast_2d(np.asarray(Q, dtype=float))
    if Q.ndim != 2 or Q.shape[1] != robot.dof or Q.shape[0] == 0:
        raise ValueError(f"expected Q of shape (k, {robot.dof}), got {np.shape(Q)}")
    titles = list(titles)
    if len(titles) != len(Q):
        raise ValueError(f"{len(Q)} configurations but {len(titles)} titles")
    units = units if units is not None else Units(length=robot.length_unit)
    scale = units.l
    unit_label = "" if units.length == "unitless" else f" ({units.length})"
    arms = [arm_points(robot, q) for q in Q]
    starts = [joint_points(robot, q) for q in Q]
    triad = TRIAD_FRACTION * robot.characteristic_length
    plane = drawing_plane(robot, Q)
    centre, half = _extent(arms, triad, scale, plane)
    cols, rows = panel_grid(len(Q))
    with default_style(mpl):
        fig = new_figure(cols, rows, dpi)
        fit_title(fig.suptitle("", fontsize=11),
                  suptitle if suptitle is not None else _robot_title(robot), title_inches(cols))
        for k, (arm, start, title) in enumerate(zip(arms, starts, titles)):
            if plane is None:
                # our zorder (links, joints, triads) rather than mplot3d's depth sort,
                # which hides triads and joints behind thick links
                ax = fig.add_subplot(rows, cols, k + 1, projection="3d", computed_zorder=False)
                _draw_3d(ax, robot, arm, start, triad, scale)
                _frame_3d(ax, centre, half, unit_label)
            else:
                ax = fig.add_subplot(rows, cols, k + 1)
                _draw_2d(ax, robot, arm, start, triad, scale, plane)
                _frame_2d(ax, centre, half, [f"{n}{unit_label}" for n in plane[2]])
            fit_title(ax.set_title("", fontsize="medium"), title, title_inches(1))
        projections = ["3d" if ax.name == "3d" else "2d" for ax in fig.axes]
        return save_figure(fig, path, fmt, dpi, projections)


def _extent(arms, triad, scale, plane):
    """The common limits of every panel, in display units: ``(centre, half width)`` of
    the square (cube) around everything drawn, triads included, with room for labels;
    in the plane's coordinates for a planar arm."""
    drawn = [a.points for a in arms]
    for a in arms:
        for T in (a.base, a.tool):
            drawn.append(T[:3, 3] + triad * T[:3, :3].T)
    drawn = np.concatenate(drawn) * scale
    if plane is not None:
        u, v, _ = plane
        drawn = drawn @ np.stack([u, v], axis=1)
    lo, hi = drawn.min(axis=0), drawn.max(axis=0)
    return (lo + hi) / 2, max(float(np.max(hi - lo)) / 2, triad * scale) * 1.12


def _frame_3d(ax, centre, half, unit_label):
    """Orthographic, equal-scaled 3D axes around ``centre``, labelled, with round ticks."""
    from matplotlib.ticker import MaxNLocator
    ax.set_proj_type("ortho")
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_xlabel(f"x{unit_label}")
    ax.set_ylabel(f"y{unit_label}")
    ax.set_zlabel(f"z{unit_label}")
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(4, steps=TICK_STEPS))
    ax.tick_params(labelsize="small")   # 3D corners crowd tick labels


def _frame_2d(ax, centre, half, labels):
    """Equal-scaled 2D axes around ``centre``, ``labels`` on them, round ticks, a grid."""
    from matplotlib.ticker import MaxNLocator
    ax.set_aspect("equal")
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    ax.xaxis.set_major_locator(MaxNLocator(6, steps=TICK_STEPS))
    ax.yaxis.set_major_locator(MaxNLocator(6, steps=TICK_STEPS))
    ax.grid(True, color="0.9")
    ax.set_axisbelow(True)


def _robot_title(robot) -> str:
    return f"{robot.name} - {robot.title}" if robot.title else robot.name


def _draw_3d(ax, robot, arm, start, triad, scale):
    p = arm.points * scale
    ax.plot(p[:, 0], p[:, 1], p[:, 2], color=LINK_COLOUR, lw=5, solid_capstyle="round",
            solid_joinstyle="round", zorder=1)
    s = start * scale
    # squares larger and below circles: a revolute joint on a prismatic one stays visible
    for marker, size, mask in (("s", 110, ~robot.is_revolute), ("o", 70, robot.is_revolute)):
        if np.any(mask):
            ax.scatter(s[mask, 0], s[mask, 1], s[mask, 2], marker=marker, s=size,
                       c=JOINT_FACE, edgecolors="black", linewidths=1.0, depthshade=False,
                       zorder=3)
    for T, name in ((arm.base, "base"), (arm.tool, "tool")):
        o = T[:3, 3] * scale
        for j, colour in enumerate(TRIAD_COLOURS):
            e = o + T[:3, j] * triad * scale
            ax.plot([o[0], e[0]], [o[1], e[1]], [o[2], e[2]], color=colour, lw=2.5, zorder=4)
        ax.text(o[0], o[1], o[2], f"  {name}", fontsize="small", color="0.3")


def _draw_2d(ax, robot, arm, start, triad, scale, plane):
    u, v, _ = plane
    P = np.stack([u, v], axis=1)
    w = np.cross(u, v)
    p = arm.points @ P * scale
    ax.plot(p[:, 0], p[:, 1], color=LINK_COLOUR, lw=5, solid_capstyle="round",
            solid_joinstyle="round", zorder=2)
    s = start @ P * scale
    for marker, size, mask in (("s", 110, ~robot.is_revolute), ("o", 70, robot.is_revolute)):
        if np.any(mask):
            ax.scatter(s[mask, 0], s[mask, 1], marker=marker, s=size, c=JOINT_FACE,
                       edgecolors="black", linewidths=1.0, zorder=3)
    for T, name in ((arm.base, "base"), (arm.tool, "tool")):
        o = T[:3, 3] @ P * scale
        for j, colour in enumerate(TRIAD_COLOURS):
            axis = T[:3, j]
            d = axis @ P * triad * scale
            if np.linalg.norm(axis @ P) > 0.2:
                ax.annotate("", xy=o + d, xytext=o, zorder=4,
                            arrowprops=dict(arrowstyle="-|>", color=colour, lw=2.5,
                                            shrinkA=0, shrinkB=0, mutation_scale=12))
            else:  # (nearly) normal to the drawing: a ring around the origin (and any
                # joint drawn there) with a dot for towards the viewer, a cross for away
                ax.scatter([o[0]], [o[1]], marker="o", s=260, facecolors="white",
                           edgecolors=colour, linewidths=2, zorder=2.5)
                ax.scatter([o[0]], [o[1]], marker="." if axis @ w > 0 else "x",
                           s=40 if axis @ w > 0 else 30, c=colour, linewidths=2, zorder=6)
        ax.annotate(name, xy=o, xytext=(6, -12), textcoords="offset points",
                    fontsize="small", color="0.3")
