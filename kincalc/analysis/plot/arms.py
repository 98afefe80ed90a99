"""Drawing arm configurations side by side (``kincalc plot``, ``ik --plot``), in 3D or
in the plane of a planar arm; the geometry comes from :mod:`~.scene`."""

from __future__ import annotations

import numpy as np

from .files import (check_output, default_style, fit_title, new_figure, panel_grid,
                    save_figure, title_inches)
from .scene import arm_scene
from .style import (Drawing, JOINT_FACE, LINK_COLOUR, TICK_STEPS, TRIAD_COLOURS,
                    require_matplotlib)
from .views import draw_view, frames


# --- arms ------------------------------------------------------------------------

def draw_arms(robot, Q, titles, path, *, suptitle=None, units=None, dpi=100) -> Drawing:
    """Draw the arm at each configuration of ``Q`` and write it to ``path``.

    One panel per configuration, at most ``MAX_COLUMNS`` a row, each
    ``PANEL_INCHES`` square, every panel with the same equal-scaled limits. Links are
    thick lines, prismatic joints squares, the base and tool frames x/y/z triads
    (red/green/blue) ``TRIAD_FRACTION`` of the robot's characteristic length long,
    labelled where they keep clear of the rest. In 3D a revolute joint is a short
    cylinder on its axis with an arrow to the axis's positive end and the joint's
    number there (so a wrist flip, which reverses joint 5's axis, shows); the arm
    stands on a pedestal on a ground grid, seen from the view that tells the panels
    apart (:func:`~.scene.choose_view`). A planar arm (:func:`drawing_plane`) is drawn
    in 2D in its plane: revolute joints are circles (their axes face the viewer), and a
    triad axis normal to the page is a dot (towards the viewer) or a cross (away), as
    the legend says.

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
        With the panels' titles and the view of each 3D panel read back from the figure.

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
    unit_label = "" if units.length == "unitless" else f" ({units.length})"
    scene = arm_scene(robot, Q)
    cols, rows = panel_grid(len(Q))
    with default_style(mpl):
        fig = new_figure(cols, rows, dpi)
        fit_title(fig.suptitle("", fontsize=11),
                  suptitle if suptitle is not None else _robot_title(robot), title_inches(cols))
        for k, title in enumerate(titles):
            ax = fig.add_subplot(rows, cols, k + 1)
            if scene.plane is None:
                draw_view(ax, scene, k, units.l, "" if units.length == "unitless"
                          else units.length)
            else:
                _frame_2d(ax, scene.centre * units.l, scene.half * units.l,
                          [f"{n}{unit_label}" for n in scene.plane[2]])
                _draw_2d(ax, scene, k, units.l)
            fit_title(ax.set_title("", fontsize="medium"), title, title_inches(1))
        _legend(fig, scene, mpl)
        return save_figure(fig, path, fmt, dpi, ["2d" if scene.plane else "3d"] * len(Q),
                           titles=[ax.get_title() for ax in fig.axes])


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


def _draw_2d(ax, scene, k, scale):
    u, v, _ = scene.plane
    P = np.stack([u, v], axis=1)
    p = scene.panels[k]
    pts = p.arm.points @ P * scale
    ax.plot(pts[:, 0], pts[:, 1], color=LINK_COLOUR, lw=5, solid_capstyle="round",
            solid_joinstyle="round", zorder=2)
    s = p.joints @ P * scale
    for marker, size, mask in (("s", 110, ~p.revolute), ("o", 70, p.revolute)):
        if np.any(mask):
            ax.scatter(s[mask, 0], s[mask, 1], marker=marker, s=size, c=JOINT_FACE,
                       edgecolors="black", linewidths=1.0, zorder=3)
    frames(ax, scene, k, scale)


def _legend(fig, scene, mpl):
    """One legend under the panels: what the marks mean."""
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], color=LINK_COLOUR, lw=4, label="link")]
    revolute = any(np.any(p.revolute) for p in scene.panels)
    prismatic = any(np.any(~p.revolute) for p in scene.panels)
    if revolute and scene.plane is None:
        handles.append(Line2D([], [], color=JOINT_FACE, lw=6, label="revolute joint, "
                              "+ axis arrow"))
    elif revolute:
        handles.append(Line2D([], [], ls="", marker="o", ms=8, mfc=JOINT_FACE, mec="black",
                              label="revolute joint"))
    if prismatic:
        handles.append(Line2D([], [], ls="", marker="s", ms=9, mfc=JOINT_FACE, mec="black",
                              label="prismatic joint"))
    marks = scene.triad_marks()
    for j, (name, colour) in enumerate(zip("xyz", TRIAD_COLOURS)):
        if (j, "arrow") in marks:
            handles.append(Line2D([], [], color=colour, lw=2.5, label=f"{name} (base, tool)"))
        out, into = (("out of the page", "into the page") if scene.plane is not None
                     else ("towards you", "away from you"))
        if (j, "towards") in marks:
            handles.append(Line2D([], [], ls="", marker=".", ms=9, color=colour,
                                  label=f"{name} {out}"))
        if (j, "away") in marks:
            handles.append(Line2D([], [], ls="", marker="x", ms=6, mew=2, color=colour,
                                  label=f"{name} {into}"))
    cols = min(len(handles), 3 if len(fig.axes) == 1 else 4 if len(fig.axes) == 2 else 8)
    fig.legend(handles=handles, loc="outside lower center", ncols=cols, fontsize="small",
               frameon=False, handlelength=1.6, columnspacing=1.2)
