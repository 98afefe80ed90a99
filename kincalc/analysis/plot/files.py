"""Figures and files of kincalc's drawings: the output check, the figure's grid and
style, titles that fit, and saving with identical bytes for identical input."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

from ...errors import InputError
from ...limits import quote
from ...outputs import as_target, check_target, replacing
from .style import Drawing, FORMATS, HASH_SALT, MAX_COLUMNS, METADATA, PANEL_INCHES


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


def save_figure(fig, path, fmt, dpi, projections, titles=(), colour_label=None) -> Drawing:
    target = as_target(path)
    # to a temporary file renamed over the target when complete (kincalc.outputs)
    with replacing(target) as fh:
        fig.savefig(fh, format=fmt, dpi=dpi, metadata=METADATA[fmt])
    w_in, h_in = fig.get_size_inches()
    if fmt == "png":
        size = (int(round(w_in * dpi)), int(round(h_in * dpi)), "px")
    else:
        size = (int(round(w_in * 72)), int(round(h_in * 72)), "pt")
    return Drawing(str(target.path), fmt, *size, projections=tuple(projections),
                   titles=tuple(titles), colour_label=colour_label)


def title_inches(cols: int) -> float:
    """Width a title may take: its panels' width less a margin."""
    return PANEL_INCHES * cols - 0.3


def panel_grid(k: int) -> tuple[int, int]:
    cols = min(k, MAX_COLUMNS)
    return cols, math.ceil(k / cols)


def default_style(mpl):
    """matplotlib's defaults (not the user's matplotlibrc) plus our fixed settings (text is
    never mathtext), and matplotlib's word on a glyph its font lacks (a title in CJK or with
    an emoji) kept off stderr: a warning with kincalc's source line in it, not the user's
    business."""
    import contextlib
    import warnings

    from matplotlib import style
    stack = contextlib.ExitStack()
    stack.enter_context(style.context("default"))
    # a robot's title or joint name is text, not mathtext ('Arm $\frac{$' was a parse error)
    stack.enter_context(mpl.rc_context({"svg.hashsalt": HASH_SALT, "text.parse_math": False}))
    stack.enter_context(warnings.catch_warnings())
    warnings.filterwarnings("ignore", message=r"Glyph \d+ .* missing from", category=UserWarning)
    return stack


def new_figure(cols: int, rows: int, dpi):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    fig = Figure(figsize=(PANEL_INCHES * cols, PANEL_INCHES * rows), dpi=dpi,
                 layout="constrained")
    FigureCanvasAgg(fig)   # a renderer to measure titles with (savefig switches per format)
    # the default pads (3/72 in) let a centred suptitle touch the middle panel's title
    fig.get_layout_engine().set(h_pad=0.08, w_pad=0.08)
    return fig


def fit_title(text, title: str, inches: float) -> None:
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
