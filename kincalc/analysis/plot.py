"""Drawings of arms and workspace sections, written to PNG, SVG or PDF.

matplotlib is the optional extra ``plot`` (``pip install 'kincalc[plot]'``)
and is imported inside the functions that draw, never at module import. No
pyplot: figures are :class:`matplotlib.figure.Figure` objects saved through
their own canvas, so no GUI backend is ever selected and no global figure
state is kept.

Sizes are predictable: every panel is ``PANEL_INCHES`` square, at most
``MAX_COLUMNS`` panels a row, and files are saved without tight bounding
boxes, so ``k`` panels in ``c`` columns and ``r`` rows at ``dpi`` give a
``5c·dpi x 5r·dpi`` pixel PNG (``360c x 360r`` points for SVG and PDF).
Identical input gives identical bytes: matplotlib's default style is used
whatever the user's matplotlibrc says, SVG ids are salted with a fixed
string and no date is written into SVG or PDF files.

Geometry comes in SI (m, rad) and is drawn in the display length unit of a
:class:`~kincalc.analysis.results.Units`.
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

from .reports import joint_vector
from ..errors import InputError, MissingExtra, require_extra  # noqa: F401 (MissingExtra: kincalc.analysis.plot.MissingExtra)
from ..limits import quote
from ..outputs import as_target, check_target, replacing

#: Output formats, by file suffix.
FORMATS = ("png", "svg", "pdf")
#: Side of one panel, inches.
PANEL_INCHES = 5.0
#: Panels side by side before a new row starts.
MAX_COLUMNS = 4
#: Length of the base and tool axis triads, as a fraction of the robot's
#: characteristic length.
TRIAD_FRACTION = 0.15
#: Relative tolerance of the planarity test (points off the plane, axes off
#: the normal).
PLANAR_TOL = 1e-9

_HASH_SALT = "kincalc"
#: tick steps: round numbers only (matplotlib's MaxNLocator would also take 3, 4, 6, 8)
_TICK_STEPS = (1, 2, 2.5, 5, 10)
_METADATA = {"png": {}, "svg": {"Date": None}, "pdf": {"CreationDate": None}}
_LINK_COLOUR = "#3b4a5a"
_JOINT_FACE = "#f2a13a"
_TRIAD_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")   # x red, y green, z blue


def require_matplotlib(command: str):
    """Import and return matplotlib, or raise :class:`MissingExtra` naming ``command``.

    ``command`` is what the user ran, as it should read in the message:
    ``"kincalc plot"``, ``"kincalc ik --plot"``.
    """
    return require_extra(command, "matplotlib", "plot")


@dataclass(frozen=True)
class Drawing:
    """What :func:`draw_arms` and :func:`draw_sections` wrote.

    ``width`` and ``height`` are in ``size_unit``: pixels for PNG, points
    (1/72 inch, as the file declares them) for SVG and PDF. ``projections``
    are the panels' axes kinds, ``'2d'`` or ``'3d'``, read back from the
    figure.
    """

    path: str
    format: str
    width: int
    height: int
    size_unit: str
    projections: tuple[str, ...]

    @property
    def planar(self) -> bool:
        """True when every panel is a 2D drawing."""
        return all(p == "2d" for p in self.projections)

    def describe(self) -> str:
        """``"1000 x 500 px, png"``: size and format for a one-line report."""
        return f"{self.width} x {self.height} {self.size_unit}, {self.format}"


class ArmPoints(NamedTuple):
    """The drawing of one arm configuration, world frame, metres.

    ``points (m, 3)``: the polyline base origin, link corners, joints, tool
    point. ``tool (4, 4)``: ``T_world_tool``. ``base (4, 4)``: ``T_world_0``.
    """

    points: np.ndarray
    tool: np.ndarray
    base: np.ndarray


# --- geometry -------------------------------------------------------------------

def joint_points(robot, q) -> np.ndarray:
    """Where each joint is drawn: ``(n, 3)`` world points (m) on the joint axes.

    A revolute joint's point is the origin of its chain frame (the frame
    whose z axis is the joint axis, see :func:`kincalc.fk.chain_frames`); a
    prismatic joint's point is that origin before the joint's travel, where
    the sliding link leaves the previous one.
    """
    q = joint_vector(robot, q)
    frames = _frames(robot, q)
    travel = np.where(robot.is_revolute, 0.0, q + robot.chain.offset)
    return frames[:, :3, 3] - frames[:, :3, 2] * travel[:, None]


def arm_points(robot, q) -> ArmPoints:
    """The arm at joint values ``q (n,)`` (rad / m) as a polyline, world frame, metres.

    The polyline runs from the base origin (``robot.base``) through every
    joint (:func:`joint_points`; a prismatic joint adds its travel along its
    axis) to the tool point. A link whose offset has a component along the
    axis of the joint before it is drawn as an L: first along that axis,
    then across (for DH links ``d_i`` along ``z_{i-1}``, then ``a_i`` along
    ``x_i``), the corner being ``o + z ((p - o) . z)`` for the link from
    ``o`` to ``p`` with ``z`` the joint axis at ``o``.

    Returns
    -------
    ArmPoints
        ``points (m, 3)`` with ``n + 2 <= m``, the last one the tool
        position ``robot.fk(q)[:3, 3]``; ``tool (4, 4)`` ``T_world_tool``;
        ``base (4, 4)`` ``T_world_0``.
    """
    q = joint_vector(robot, q)
    frames = _frames(robot, q)
    starts = joint_points(robot, q)
    tool = robot.fk(q)
    base = np.array(robot.base, dtype=float)
    L = robot.characteristic_length
    pts = [base[:3, 3]]
    here, axis = base[:3, 3], base[:3, 2]
    for i in range(robot.dof):
        _leg(pts, here, axis, starts[i], L)
        here, axis = frames[i, :3, 3], frames[i, :3, 2]
        if not robot.joints[i].revolute:
            _append(pts, here, L)
    _leg(pts, here, axis, tool[:3, 3], L)
    return ArmPoints(np.array(pts), tool, base)


def _leg(pts, origin, axis, target, L):
    """Append the corner (when there is one) and ``target`` to the polyline.

    ``target`` is appended even when it repeats the last point, so that
    every joint and the tool are vertices of the polyline.
    """
    corner = origin + axis * float((target - origin) @ axis)
    tiny = 1e-6 * L
    if np.linalg.norm(corner - origin) > tiny and np.linalg.norm(target - corner) > tiny:
        _append(pts, corner, L)
    _append(pts, target, L, force=True)


def _append(pts, p, L, force=False):
    if force or np.linalg.norm(p - pts[-1]) > 1e-9 * L:
        pts.append(np.array(p, dtype=float))


def _frames(robot, q) -> np.ndarray:
    from ..fk import chain_frames
    return chain_frames(robot.chain, q)


def drawing_plane(robot, Q=None):
    """The plane a planar arm moves in, or ``None`` for an arm that needs 3D.

    An arm is planar when every revolute axis is parallel to one normal
    ``w``, every prismatic axis is perpendicular to it and every drawn point
    (over seeded random configurations within the limits, and ``Q (k, n)``
    when given) lies in one plane normal to ``w``.

    Returns
    -------
    (u, v, labels) or None
        ``u, v (3,)``: orthonormal in-plane directions with ``u x v = w``
        pointing at the viewer; world axes when the plane is a world
        coordinate plane. ``labels``: the names of ``u`` and ``v``.
    """
    rng = np.random.default_rng(20240607)
    L = robot.characteristic_length
    lo, hi = robot.limits.T
    span = np.where(robot.is_revolute, np.pi, L)
    lo = np.where(np.isfinite(lo), lo, -span)
    hi = np.where(np.isfinite(hi), hi, span)
    samples = rng.uniform(lo, hi, (6, robot.dof))
    if Q is not None:
        samples = np.concatenate([samples, np.asarray(Q, dtype=float).reshape(-1, robot.dof)])
    points, axes = [], []
    for q in samples:
        frames = _frames(robot, q)
        axes.append(frames[:, :3, 2])
        points.append(arm_points(robot, q).points)
    axes = np.concatenate(axes).reshape(len(samples), robot.dof, 3)
    points = np.concatenate(points)
    revolute = robot.is_revolute
    if np.any(revolute):
        w = axes[0, np.argmax(revolute)]
    else:  # only prismatic joints: the normal of their common plane, if any
        s, vt = np.linalg.svd(axes.reshape(-1, 3))[1:]
        if s[-1] > PLANAR_TOL * s[0]:
            return None
        w = vt[-1]
    if np.any(np.abs(np.abs(axes[:, revolute] @ w) - 1.0) > PLANAR_TOL):
        return None
    if np.any(np.abs(axes[:, ~revolute] @ w) > PLANAR_TOL):
        return None
    heights = points @ w
    if np.ptp(heights) > 10 * PLANAR_TOL * L:
        return None
    return _plane_basis(w)


def _plane_basis(w):
    """In-plane directions ``u, v`` for the normal ``w`` and their labels."""
    w = w / np.linalg.norm(w)
    e = np.eye(3)
    k = int(np.argmax(np.abs(w)))
    if abs(w[k]) > 1.0 - PLANAR_TOL:
        # a world coordinate plane: keep world axes, vertical axis up when there is one
        u, v = {2: (0, 1), 0: (1, 2), 1: (0, 2)}[k]
        return e[u], e[v], ("xyz"[u], "xyz"[v])
    ref = e[0] if abs(w[0]) < 0.9 else e[1]
    u = ref - w * (ref @ w)
    u /= np.linalg.norm(u)
    v = np.cross(w, u)
    return u, v, (f"u = ({_fmt_vec(u)})", f"v = ({_fmt_vec(v)})")


def _fmt_vec(x) -> str:
    return ", ".join(f"{c:.3g}" for c in np.round(x, 3) + 0.0)


def config_title(robot, q, units) -> str:
    """A panel title for joint values ``q (n,)`` (rad / m) in ``units``.

    ``"q = (0, -45, 180, 0, 45, 0) deg"``; prismatic joints are written as
    ``name=value unit``: ``"q = (0, 0, d3=0.5 m, 0, 0, 0) deg"``.
    """
    values = units.joints(robot, q)
    length = "" if units.length == "unitless" else f" {units.length}"
    parts = [_fmt_num(v) if j.revolute else f"{j.name}={_fmt_num(v)}{length}"
             for j, v in zip(robot.joints, values)]
    angle = f" {units.angle}" if any(j.revolute for j in robot.joints) else ""
    return f"q = ({', '.join(parts)}){angle}"


def _fmt_num(x: float) -> str:
    # 9 decimals: an IK solution's 1e-12 is a zero, and six digits are shown anyway
    s = f"{round(x, 9) + 0.0:.6g}"
    return "0" if s == "-0" else s


# --- files ---------------------------------------------------------------------

def check_output(path) -> str:
    """Check that a drawing can go to ``path``; return its format: png, svg or pdf.

    ``path`` is a file name or an :class:`kincalc.outputs.Target` (which says whether an
    existing file may be replaced, and which files are the command's inputs). Cheap and
    free of matplotlib, for commands to call before long work. Raises
    :class:`~kincalc.errors.InputError` for another suffix, or a file that may not be
    written (:func:`kincalc.outputs.check_target`: a missing folder, an existing file
    without ``force``, anything but a regular file, one of the inputs).
    """
    target = as_target(path)
    p = Path(target.path)
    fmt = p.suffix.lower().lstrip(".")
    if fmt not in FORMATS:
        what = f"unsupported format {p.suffix!r}" if p.suffix else "no format suffix"
        raise InputError(f"cannot draw to {quote(str(target.path), 300)}: {what} (use a file name ending in "
                         f"{', '.join('.' + f for f in FORMATS[:-1])} or .{FORMATS[-1]})")
    check_target(target)
    return fmt


def _save(fig, path, fmt, dpi, projections) -> Drawing:
    target = as_target(path)
    # to a temporary file renamed over the target when complete (kincalc.outputs)
    with replacing(target) as fh:
        fig.savefig(fh, format=fmt, dpi=dpi, metadata=_METADATA[fmt])
    w_in, h_in = fig.get_size_inches()
    if fmt == "png":
        size = (int(round(w_in * dpi)), int(round(h_in * dpi)), "px")
    else:
        size = (int(round(w_in * 72)), int(round(h_in * 72)), "pt")
    return Drawing(str(target.path), fmt, *size, projections=tuple(projections))


def _title_inches(cols: int) -> float:
    """Width a title may take: its panels' width less a margin."""
    return PANEL_INCHES * cols - 0.3


def _grid(k: int) -> tuple[int, int]:
    cols = min(k, MAX_COLUMNS)
    return cols, math.ceil(k / cols)


def _style(mpl):
    """matplotlib's defaults (not the user's matplotlibrc) plus our fixed settings."""
    import contextlib

    from matplotlib import style
    stack = contextlib.ExitStack()
    stack.enter_context(style.context("default"))
    stack.enter_context(mpl.rc_context({"svg.hashsalt": _HASH_SALT}))
    return stack


def _figure(cols: int, rows: int, dpi):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    fig = Figure(figsize=(PANEL_INCHES * cols, PANEL_INCHES * rows), dpi=dpi,
                 layout="constrained")
    FigureCanvasAgg(fig)   # a renderer to measure titles with (savefig switches per format)
    # the default pads (3/72 in) let a centred suptitle touch the middle panel's title
    fig.get_layout_engine().set(h_pad=0.08, w_pad=0.08)
    return fig


def _fit(text, title: str, inches: float) -> None:
    """Set ``title`` on the Text artist ``text``, wrapped at spaces to fit ``inches``.

    Line breaks already in ``title`` are kept.
    """
    fig = text.get_figure()
    renderer = fig.canvas.get_renderer()
    lines = title.split("\n")
    width = max(len(line) for line in lines)
    while True:
        text.set_text("\n".join(w for line in lines for w in (textwrap.wrap(line, width) or [""])))
        if width <= 10 or text.get_window_extent(renderer).width <= inches * fig.dpi:
            return
        width -= 2


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
    from .results import Units
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
    # everything drawn, for the common limits
    drawn = [a.points for a in arms]
    for a in arms:
        for T in (a.base, a.tool):
            drawn.append(T[:3, 3] + triad * T[:3, :3].T)
    drawn = np.concatenate(drawn) * scale
    if plane is not None:
        u, v, names = plane
        drawn = drawn @ np.stack([u, v], axis=1)
    lo, hi = drawn.min(axis=0), drawn.max(axis=0)
    centre = (lo + hi) / 2
    half = max(float(np.max(hi - lo)) / 2, triad * scale) * 1.12   # room for labels

    from matplotlib.ticker import MaxNLocator
    cols, rows = _grid(len(Q))
    with _style(mpl):
        fig = _figure(cols, rows, dpi)
        _fit(fig.suptitle("", fontsize=11),
             suptitle if suptitle is not None else _robot_title(robot), _title_inches(cols))
        for k, (arm, start, title) in enumerate(zip(arms, starts, titles)):
            if plane is None:
                # our zorder (links, joints, triads) rather than mplot3d's depth sort,
                # which hides triads and joints behind thick links
                ax = fig.add_subplot(rows, cols, k + 1, projection="3d", computed_zorder=False)
                _draw_3d(ax, robot, arm, start, triad, scale)
                ax.set_proj_type("ortho")
                ax.set_box_aspect((1, 1, 1))
                ax.set_xlim(centre[0] - half, centre[0] + half)
                ax.set_ylim(centre[1] - half, centre[1] + half)
                ax.set_zlim(centre[2] - half, centre[2] + half)
                ax.set_xlabel(f"x{unit_label}")
                ax.set_ylabel(f"y{unit_label}")
                ax.set_zlabel(f"z{unit_label}")
                for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
                    axis.set_major_locator(MaxNLocator(4, steps=_TICK_STEPS))
                ax.tick_params(labelsize="small")   # 3D corners crowd tick labels
            else:
                ax = fig.add_subplot(rows, cols, k + 1)
                _draw_2d(ax, robot, arm, start, triad, scale, plane)
                ax.set_aspect("equal")
                ax.set_xlim(centre[0] - half, centre[0] + half)
                ax.set_ylim(centre[1] - half, centre[1] + half)
                ax.set_xlabel(f"{names[0]}{unit_label}")
                ax.set_ylabel(f"{names[1]}{unit_label}")
                ax.xaxis.set_major_locator(MaxNLocator(6, steps=_TICK_STEPS))
                ax.yaxis.set_major_locator(MaxNLocator(6, steps=_TICK_STEPS))
                ax.grid(True, color="0.9")
                ax.set_axisbelow(True)
            _fit(ax.set_title("", fontsize="medium"), title, _title_inches(1))
        projections = ["3d" if ax.name == "3d" else "2d" for ax in fig.axes]
        return _save(fig, path, fmt, dpi, projections)


def _robot_title(robot) -> str:
    return f"{robot.name} - {robot.title}" if robot.title else robot.name


def _draw_3d(ax, robot, arm, start, triad, scale):
    p = arm.points * scale
    ax.plot(p[:, 0], p[:, 1], p[:, 2], color=_LINK_COLOUR, lw=5, solid_capstyle="round",
            solid_joinstyle="round", zorder=1)
    s = start * scale
    # squares larger and below circles: a revolute joint on a prismatic one stays visible
    for marker, size, mask in (("s", 110, ~robot.is_revolute), ("o", 70, robot.is_revolute)):
        if np.any(mask):
            ax.scatter(s[mask, 0], s[mask, 1], s[mask, 2], marker=marker, s=size,
                       c=_JOINT_FACE, edgecolors="black", linewidths=1.0, depthshade=False,
                       zorder=3)
    for T, name in ((arm.base, "base"), (arm.tool, "tool")):
        o = T[:3, 3] * scale
        for j, colour in enumerate(_TRIAD_COLOURS):
            e = o + T[:3, j] * triad * scale
            ax.plot([o[0], e[0]], [o[1], e[1]], [o[2], e[2]], color=colour, lw=2.5, zorder=4)
        ax.text(o[0], o[1], o[2], f"  {name}", fontsize="small", color="0.3")


def _draw_2d(ax, robot, arm, start, triad, scale, plane):
    u, v, _ = plane
    P = np.stack([u, v], axis=1)
    w = np.cross(u, v)
    p = arm.points @ P * scale
    ax.plot(p[:, 0], p[:, 1], color=_LINK_COLOUR, lw=5, solid_capstyle="round",
            solid_joinstyle="round", zorder=2)
    s = start @ P * scale
    for marker, size, mask in (("s", 110, ~robot.is_revolute), ("o", 70, robot.is_revolute)):
        if np.any(mask):
            ax.scatter(s[mask, 0], s[mask, 1], marker=marker, s=size, c=_JOINT_FACE,
                       edgecolors="black", linewidths=1.0, zorder=3)
    for T, name in ((arm.base, "base"), (arm.tool, "tool")):
        o = T[:3, 3] @ P * scale
        for j, colour in enumerate(_TRIAD_COLOURS):
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


# --- workspace sections -------------------------------------------------------------

def draw_sections(sections, path, *, suptitle, colour_label, dpi=100) -> Drawing:
    """Draw workspace sections as images side by side and write them to ``path``.

    Parameters
    ----------
    sections : sequence of dict
        Each ``{"title": str, "xlabel": str, "ylabel": str,
        "extent": (xmin, xmax, ymin, ymax), "grid": ndarray (H, W)}``; row 0
        of ``grid`` is at ``ymin`` (``origin='lower'``), NaN cells are empty
        and left blank.
    path : str, Path or kincalc.outputs.Target
        Output file: .png, .svg or .pdf, as for :func:`draw_arms`.
    suptitle : str
        Figure title.
    colour_label : str
        Label of the colour bar, shared by every panel (one colour scale).
    dpi : int

    Returns
    -------
    Drawing

    Raises
    ------
    InputError, MissingExtra
        As :func:`draw_arms`.
    """
    fmt = check_output(path)
    mpl = require_matplotlib("drawing")
    sections = list(sections)
    if not sections:
        raise ValueError("no sections to draw")
    grids = [np.asarray(s["grid"], dtype=float) for s in sections]
    for g in grids:
        if g.ndim != 2:
            raise ValueError(f"a section grid must be 2-D, got shape {g.shape}")
    finite = np.concatenate([g[np.isfinite(g)] for g in grids])
    vmin, vmax = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    if vmin == vmax:
        vmin, vmax = vmin - 0.5, vmax + 0.5

    from matplotlib.colors import Normalize
    from matplotlib.ticker import MaxNLocator
    cols, rows = _grid(len(sections))
    with _style(mpl):
        cmap = mpl.colormaps["viridis"].with_extremes(bad=(1.0, 1.0, 1.0, 0.0))
        norm = Normalize(vmin, vmax)
        fig = _figure(cols, rows, dpi)
        _fit(fig.suptitle("", fontsize=11), suptitle, _title_inches(cols))
        axes, image = [], None
        for k, (s, g) in enumerate(zip(sections, grids)):
            ax = fig.add_subplot(rows, cols, k + 1)
            image = ax.imshow(np.ma.masked_invalid(g), origin="lower", extent=tuple(s["extent"]),
                              cmap=cmap, norm=norm, aspect="equal", interpolation="nearest")
            _fit(ax.set_title("", fontsize="medium"), s["title"], _title_inches(1))
            ax.set_xlabel(s["xlabel"])
            ax.set_ylabel(s["ylabel"])
            ax.xaxis.set_major_locator(MaxNLocator(6, steps=_TICK_STEPS))
            ax.yaxis.set_major_locator(MaxNLocator(6, steps=_TICK_STEPS))
            axes.append(ax)
        fig.colorbar(image, ax=axes, label=colour_label, shrink=0.8)
        projections = ["2d"] * len(axes)
        return _save(fig, path, fmt, dpi, projections)
