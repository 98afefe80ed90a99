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

The modules: :mod:`~.style` (formats, sizes, colours, :class:`Drawing`, :class:`ArmPoints`),
:mod:`~.geometry` (what an arm's drawing shows, in SI), :mod:`~.scene` (a figure of arms
before drawing: joint axes, the view that tells the panels apart, pedestal and ground,
labels' places), :mod:`~.views` (an arm in space drawn in that view), :mod:`~.files`
(figures, titles, saving), :mod:`~.arms`, :mod:`~.sections` and :mod:`~.sweeps` (the
kinds of drawing). They use fk, :mod:`kincalc.outputs` and
:mod:`kincalc.analysis.reports`; matplotlib only inside functions.
"""

from __future__ import annotations

from ...errors import MissingExtra  # noqa: F401 (kincalc.analysis.plot.MissingExtra)
from .arms import draw_arms
from .files import check_output
from .geometry import arm_points, config_title, drawing_plane, joint_points
from .scene import Scene, arm_scene, choose_view
from .sections import draw_sections
from .style import (ArmPoints, Drawing, FORMATS, MAX_COLUMNS, PANEL_INCHES, PLANAR_TOL,
                    TRIAD_FRACTION, require_matplotlib)

__all__ = ["ArmPoints", "Drawing", "FORMATS", "MAX_COLUMNS", "PANEL_INCHES", "PLANAR_TOL",
           "Scene", "TRIAD_FRACTION", "arm_points", "arm_scene", "check_output",
           "choose_view", "config_title", "draw_arms", "draw_sections", "drawing_plane",
           "joint_points", "require_matplotlib"]
