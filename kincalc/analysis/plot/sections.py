"""Drawing the sections of a workspace (``kincalc workspace --plot``): each section's
reachable region filled with its manipulability and outlined by its boundary, the
dexterous part hatched, joint 1's axis and the other section's plane marked."""

from __future__ import annotations

import numpy as np

from .files import (check_output, default_style, fit_title, new_figure, panel_grid,
                    save_figure, title_inches)
from .style import Drawing, TICK_STEPS, require_matplotlib

#: the boundary of the reachable region, the dexterous part, joint 1's axis
BOUNDARY_COLOUR = "black"
DEXTEROUS_COLOUR = "#b2182b"
AXIS_COLOUR = "0.2"
#: the colour map of the manipulability and how many bands it has at most
COLOUR_MAP = "YlGnBu"
BANDS = 9


# --- workspace sections -------------------------------------------------------------

def draw_sections(sections, path, *, suptitle, colour_label, units=None, dpi=100) -> Drawing:
    """Draw workspace sections side by side and write them to ``path``.

    Each panel is one :class:`~kincalc.analysis.workspace.Section`: its reachable
    region (``reach`` at 0.5 and above) filled with bands of its manipulability on one
    colour scale for every panel (the colour bar, labelled ``colour_label``), outlined
    by its boundary (the 0.5 contour); the dexterous part (``dexterous`` at 0.5 and
    above) hatched and outlined; joint 1's axis drawn dash-dotted (a cross where it
    pierces the plane) and the other section's plane dotted. The title names the plane,
    its level and why it was chosen; the axes are the plane's coordinates.

    Parameters
    ----------
    sections : sequence of Section
    path : str, Path or kincalc.outputs.Target
        Output file: .png, .svg or .pdf, as for :func:`draw_arms`.
    suptitle : str
        Figure title.
    colour_label : str
        Label of the colour bar, with its unit.
    units : Units, optional
        Display units of lengths; default metres.
    dpi : int

    Returns
    -------
    Drawing
        With the panels' titles and the colour bar's label read back from the figure.

    Raises
    ------
    InputError, MissingExtra
        As :func:`draw_arms`.
    """
    from ..results import Units
    fmt = check_output(path)
    mpl = require_matplotlib("drawing")
    sections = list(sections)
    if not sections:
        raise ValueError("no sections to draw")
    units = units if units is not None else Units()
    levels = _levels(sections)
    cols, rows = panel_grid(len(sections))
    with default_style(mpl):
        cmap = mpl.colormaps[COLOUR_MAP]
        fig = new_figure(cols, rows, dpi)
        fit_title(fig.suptitle("", fontsize=11), suptitle, title_inches(cols))
        axes, filled = [], None
        for k, sec in enumerate(sections):
            ax = fig.add_subplot(rows, cols, k + 1)
            filled = _panel(ax, sec, units, levels, cmap) or filled
            axes.append(ax)
        bar = None
        if filled is not None:
            bar = fig.colorbar(filled, ax=axes, label=superscripts(colour_label), shrink=0.8)
        _legend(fig, sections)
        return save_figure(fig, path, fmt, dpi, ["2d"] * len(axes),
                           titles=[ax.get_title() for ax in axes],
                           colour_label=None if bar is None else bar.ax.get_ylabel())


def _levels(sections):
    """The colour bands' edges: round numbers across every section's manipulability."""
    from matplotlib.ticker import MaxNLocator
    values = np.concatenate([s.manipulability[(s.reach >= 0.5) & np.isfinite(s.manipulability)]
                             for s in sections])
    if values.size == 0:
        return None
    lo, hi = float(values.min()), float(values.max())
    if hi <= lo:
        lo, hi = lo - 0.5 * abs(lo or 1), hi + 0.5 * abs(hi or 1)
    return MaxNLocator(BANDS, steps=TICK_STEPS).tick_values(lo, hi)


def superscripts(text: str) -> str:
    """``"m^3"`` as ``"m³"``: powers written as superscripts."""
    import re
    return re.sub(r"\^(\d+)", lambda m: m.group(1).translate(str.maketrans(
        "0123456789", "\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079")), text)


def axis_name(d) -> str:
    """``"x"``, ``"y"`` or ``"z"`` for a (positive) world axis, else ``"(a, b, c)"``."""
    d = np.asarray(d, float)
    k = int(np.argmax(np.abs(d)))
    if abs(d[k] - 1) < 1e-9:
        return "xyz"[k]
    return "(" + ", ".join(f"{c:.3g}" for c in np.round(d, 3) + 0.0) + ")"


def section_title(sec, units) -> str:
    """``"Through the base axis (x-z plane, y = 0 m)"`` and the reason on a second line."""
    unit = "" if units.length == "unitless" else f" {units.length}"
    u, v, n = axis_name(sec.u), axis_name(sec.v), axis_name(sec.normal)
    where = (f"{u}-{v} plane, {n} = {sec.level * units.l + 0.0:.4g}{unit}" if len(n) == 1
             else f"normal {n}, at {sec.level * units.l + 0.0:.4g}{unit}")
    return f"{sec.name[0].upper()}{sec.name[1:]} ({where})\n{sec.reason}"


def _centres(sec, F, scale):
    """Pixel centres ``(x (W,), y (H,))`` of a field ``F`` over the section's extent."""
    u0, u1, v0, v1 = (e * scale for e in sec.extent)
    H, W = F.shape
    return (u0 + (np.arange(W) + 0.5) * (u1 - u0) / W,
            v0 + (np.arange(H) + 0.5) * (v1 - v0) / H)


def _panel(ax, sec, units, levels, cmap):
    """One section on ``ax``; returns the filled contours (for the colour bar) or None."""
    from matplotlib.ticker import MaxNLocator
    scale = units.l
    x, y = _centres(sec, sec.reach, scale)
    filled = None
    if levels is not None:
        m = np.ma.masked_where((sec.reach < 0.5) | ~np.isfinite(sec.manipulability),
                               sec.manipulability)
        filled = ax.contourf(x, y, m, levels=levels, cmap=cmap, extend="neither", zorder=1)
    ax.contour(x, y, sec.reach, levels=[0.5], colors=BOUNDARY_COLOUR, linewidths=1.6,
               zorder=3)
    if sec.dexterous is not None and np.any(sec.dexterous >= 0.5):
        dx, dy = _centres(sec, sec.dexterous, scale)
        hatch = ax.contourf(dx, dy, sec.dexterous, levels=[0.5, 1.5], colors="none",
                            hatches=["////"], zorder=2)
        hatch.set_edgecolor(DEXTEROUS_COLOUR)
        hatch.set_linewidth(0)
        ax.contour(dx, dy, sec.dexterous, levels=[0.5], colors=DEXTEROUS_COLOUR,
                   linewidths=1.2, zorder=2.5)
    _marks(ax, sec, scale)
    u0, u1, v0, v1 = (e * scale for e in sec.extent)
    ax.set_xlim(u0, u1)
    ax.set_ylim(v0, v1)
    ax.set_aspect("equal")
    unit = "" if units.length == "unitless" else f" ({units.length})"
    ax.set_xlabel(axis_name(sec.u) + unit)
    ax.set_ylabel(axis_name(sec.v) + unit)
    ax.xaxis.set_major_locator(MaxNLocator(6, steps=TICK_STEPS))
    ax.yaxis.set_major_locator(MaxNLocator(6, steps=TICK_STEPS))
    ax.grid(True, color="0.92", zorder=0)
    ax.set_axisbelow(True)
    fit_title(ax.set_title("", fontsize="medium"), section_title(sec, units), title_inches(1))
    return filled


def _marks(ax, sec, scale):
    """Joint 1's axis (dash-dotted, or a cross where it pierces the plane) and the trace
    of the other section's plane (dotted), across the whole panel."""
    u0, u1, v0, v1 = (e * scale for e in sec.extent)
    span = 2 * max(u1 - u0, v1 - v0)
    for line, style in ((sec.axis, dict(color=AXIS_COLOUR, ls="-.", lw=1.1)),
                        (sec.other, dict(color="0.35", ls=":", lw=1.3))):
        if line is None:
            continue
        p, d = line
        p = np.asarray(p, float) * scale
        if d is None:
            ax.plot(*p, marker="+", ms=12, mew=1.6, color=AXIS_COLOUR, zorder=4)
            continue
        d = np.asarray(d, float) / np.linalg.norm(d)
        ends = np.stack([p - span * d, p + span * d])
        ax.plot(*ends.T, zorder=4, **style)


def _legend(fig, sections):
    """What the lines and the hatching mean, under the panels."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    handles = [Line2D([], [], color=BOUNDARY_COLOUR, lw=1.6, label="boundary of the reach")]
    if any(s.dexterous is not None and np.any(s.dexterous >= 0.5) for s in sections):
        handles.append(Patch(fc="none", ec=DEXTEROUS_COLOUR, hatch="////",
                             label="dexterous (every test orientation)"))
    handles.append(Line2D([], [], color=AXIS_COLOUR, ls="-.", lw=1.1, marker="+", ms=8,
                          label="axis of joint 1"))
    if any(s.other is not None for s in sections):
        handles.append(Line2D([], [], color="0.35", ls=":", lw=1.3,
                              label="plane of the other section"))
    cols = len(handles) if len(fig.axes) > 2 else 2      # the colour bar is an axes too
    fig.legend(handles=handles, loc="outside lower center", ncols=cols,
               fontsize="small", frameon=False)
