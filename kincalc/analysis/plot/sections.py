"""Drawing the XY and XZ sections of a workspace (``kincalc workspace --plot``)."""

from __future__ import annotations

import numpy as np

from .files import (check_output, default_style, fit_title, new_figure, panel_grid,
                    save_figure, title_inches)
from .style import Drawing, TICK_STEPS, require_matplotlib


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
    cols, rows = panel_grid(len(sections))
    with default_style(mpl):
        cmap = mpl.colormaps["viridis"].with_extremes(bad=(1.0, 1.0, 1.0, 0.0))
        norm = Normalize(vmin, vmax)
        fig = new_figure(cols, rows, dpi)
        fit_title(fig.suptitle("", fontsize=11), suptitle, title_inches(cols))
        axes, image = [], None
        for k, (s, g) in enumerate(zip(sections, grids)):
            ax = fig.add_subplot(rows, cols, k + 1)
            image = ax.imshow(np.ma.masked_invalid(g), origin="lower", extent=tuple(s["extent"]),
                              cmap=cmap, norm=norm, aspect="equal", interpolation="nearest")
            fit_title(ax.set_title("", fontsize="medium"), s["title"], title_inches(1))
            ax.set_xlabel(s["xlabel"])
            ax.set_ylabel(s["ylabel"])
            ax.xaxis.set_major_locator(MaxNLocator(6, steps=TICK_STEPS))
            ax.yaxis.set_major_locator(MaxNLocator(6, steps=TICK_STEPS))
            axes.append(ax)
        fig.colorbar(image, ax=axes, label=colour_label, shrink=0.8)
        projections = ["2d"] * len(axes)
        return save_figure(fig, path, fmt, dpi, projections)
