"""The fixed look of kincalc's drawings: formats, panel sizes, colours, the optional
matplotlib import, and what a drawing wrote (:class:`Drawing`) and draws
(:class:`ArmPoints`)."""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ...errors import require_extra


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

HASH_SALT = "kincalc"
#: tick steps: round numbers only (matplotlib's MaxNLocator would also take 3, 4, 6, 8)
TICK_STEPS = (1, 2, 2.5, 5, 10)
METADATA = {"png": {}, "svg": {"Date": None}, "pdf": {"CreationDate": None}}
LINK_COLOUR = "#3b4a5a"
JOINT_FACE = "#f2a13a"
TRIAD_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")   # x red, y green, z blue
GROUND_COLOUR = "#e8e4da"
PEDESTAL_COLOUR = "0.8"


def require_matplotlib(command: str):
    """Import and return matplotlib, or raise :class:`MissingExtra` naming ``command``.

    ``command`` is what the user ran, as it should read in the message:
    ``"kincalc plot"``, ``"kincalc ik --plot"``. The import runs in an empty temporary
    working directory: matplotlib reads a ``matplotlibrc`` in the working directory as it is
    imported, a file the user did not name (a student's folder the grader runs in may hold
    one), echoing its lines on stderr, waiting on a FIFO, reading a link to /dev/zero.
    """
    import sys
    if sys.modules.get("matplotlib") is not None:          # (imported already)
        return sys.modules["matplotlib"]
    with _away_from_the_working_directory():
        return require_extra(command, "matplotlib", "plot")


@contextlib.contextmanager
def _away_from_the_working_directory():
    """Run the block in a new empty directory, then return to the working directory (none to
    leave when it is gone: nothing is read there either)."""
    import os
    import tempfile
    try:
        here = os.getcwd()
    except OSError:
        yield
        return
    with tempfile.TemporaryDirectory(prefix="kincalc-") as empty:
        os.chdir(empty)
        try:
            yield
        finally:
            os.chdir(here)


@dataclass(frozen=True)
class Drawing:
    """What :func:`draw_arms` and :func:`draw_sections` wrote.

    ``width`` and ``height`` are in ``size_unit``: pixels for PNG, points
    (1/72 inch, as the file declares them) for SVG and PDF. ``projections``
    are the panels' kinds of view: ``'2d'`` (a planar arm in its plane, a
    section) or ``'3d'`` (an arm in space, seen from a direction).
    ``titles``: the panels' titles and ``colour_label`` the colour bar's label
    (None without one), read back from the figure.
    """

    path: str
    format: str
    width: int
    height: int
    size_unit: str
    projections: tuple[str, ...]
    titles: tuple[str, ...] = ()
    colour_label: str | None = None

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
