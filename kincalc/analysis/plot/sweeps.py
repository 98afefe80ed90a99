"""Drawing a sweep of a held joint (``kincalc ik --sweep --plot``): each joint against
the swept value, one line per branch, the joint limits shaded."""

from __future__ import annotations

import numpy as np

from .files import (check_output, default_style, fit_title, new_figure, panel_grid,
                    save_figure, title_inches)
from .style import Drawing, TICK_STEPS, require_matplotlib

#: shade of the values beyond a joint's limits
LIMIT_SHADE = "#d9d9d9"


def draw_sweep(sw, path, *, units, dpi=100) -> Drawing:
    """Draw the sweep ``sw`` (:class:`kincalc.analysis.sweep.Sweep`) to ``path``.

    One panel per joint that is not held: its value on every branch (one colour per
    branch, numbered as in the tables) against the swept joint's value, both in the
    display ``units``; the values beyond the joint's limits shaded, the swept range beyond
    the swept joint's limits shaded too, and a dot where a branch meets another or
    leaves the reach. Joint values are the engine's (the representative nearest the
    joint's limits): where one moves by a whole turn to another representative the line
    breaks instead of crossing the panel.

    Parameters
    ----------
    sw : Sweep
    path : str, Path or kincalc.outputs.Target
        .png, .svg or .pdf.
    units : Units
    dpi : int

    Returns
    -------
    Drawing
    """
    fmt = check_output(path)
    mpl = require_matplotlib("drawing")
    from matplotlib.ticker import MaxNLocator
    robot = sw.robot
    held = {sw.joint} | {j for j, _ in sw.locks}
    panels = [j for j in range(robot.dof) if j not in held]
    scale = np.where(robot.is_revolute, units.a, units.l)
    x = sw.values * scale[sw.joint]
    cols, rows = panel_grid(len(panels))
    name = lambda j: f"{robot.joints[j].name} ({units.angle if robot.joints[j].revolute else units.length})"  # noqa: E501,E731
    with default_style(mpl):
        fig = new_figure(cols, rows, dpi)
        B = len(sw.branches)
        fit_title(fig.suptitle("", fontsize=11),
                  f"{robot.name}: {B} branch{'es' if B != 1 else ''} along {name(sw.joint)}",
                  title_inches(cols))
        colours = mpl.colormaps["tab10" if B <= 10 else "tab20"]
        lo_x, hi_x = robot.limits[sw.joint] * scale[sw.joint]
        for k, j in enumerate(panels):
            ax = fig.add_subplot(rows, cols, k + 1)
            lo, hi = robot.limits[j] * scale[j]
            for b in range(B):
                y = sw.q[:, b, j]
                xs, ys = _broken(x, y) if robot.is_revolute[j] else (x, y)
                # thinner in branch order: a branch drawn over another's values leaves
                # that one's edges showing
                ax.plot(xs, ys * scale[j], color=colours(b % colours.N),
                        lw=3.2 - 2.2 * b / max(B - 1, 1), label=f"{b + 1}" if k == 0 else None)
                ends = [i for i in (sw.branches[b].first, sw.branches[b].last)
                        if 0 < i < len(x) - 1]
                ax.plot(x[ends], y[ends] * scale[j], "o", color=colours(b % colours.N), ms=3)
            y0, y1 = ax.get_ylim()
            y0, y1 = min(y0, lo if np.isfinite(lo) else y0), max(y1, hi if np.isfinite(hi) else y1)
            pad = 0.05 * (y1 - y0 or 1.0)
            y0, y1 = y0 - pad, y1 + pad
            if np.isfinite(lo):
                ax.axhspan(y0, lo, color=LIMIT_SHADE, zorder=0, lw=0)
            if np.isfinite(hi):
                ax.axhspan(hi, y1, color=LIMIT_SHADE, zorder=0, lw=0)
            for a, z in ((x.min(), lo_x), (hi_x, x.max())):
                if z > a:
                    ax.axvspan(a, z, color=LIMIT_SHADE, zorder=0, lw=0)
            ax.set_ylim(y0, y1)
            ax.set_xlim(x.min(), x.max())
            ax.set_title(robot.joints[j].name, fontsize="medium")
            ax.set_xlabel(name(sw.joint))
            ax.set_ylabel(name(j))
            ax.xaxis.set_major_locator(MaxNLocator(6, steps=TICK_STEPS))
            ax.yaxis.set_major_locator(MaxNLocator(6, steps=TICK_STEPS))
        if B:
            fig.legend(title="branch (grey bands: beyond the joint limits)", loc="outside lower center",
                       ncols=min(B, 12), fontsize="small")
        return save_figure(fig, path, fmt, dpi, ["2d"] * len(panels))


def _broken(x, y):
    """``(x, y)`` with a gap (NaN) where ``y`` (rad) jumps by more than half a turn
    between neighbouring values: the branch's joint moved to the representative of
    another turn, not across the panel."""
    jump = np.flatnonzero(np.abs(np.diff(y)) > np.pi) + 1
    return np.insert(x, jump, np.nan), np.insert(y, jump, np.nan)
