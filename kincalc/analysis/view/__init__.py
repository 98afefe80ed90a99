"""The page of ``kincalc view``: one self-contained HTML file that shows a robot in 3D.

:func:`page_html` is a pure function, robot (and an IK answer) in, HTML text out. The
page carries a JSON document (:func:`page_data`) and its own code, inlined from the
package data files next to this module:

* ``page.html`` the template, ``page.css`` its style;
* ``kin.js`` the kinematics, from the uniform chain kincalc exports (the JSON's ``chain``:
  ``fixed`` (n + 1, 4, 4), ``revolute`` (n,), ``offset`` (n,), SI):
  ``T_world_tool(q) = F_0 J_1(q_1 + c_1) F_1 ... J_n(q_n + c_n) F_n``, the geometric
  Jacobian and its measures, RPY and the quaternion as kincalc defines them;
* ``scene.js`` the 3D view (a canvas, the painter's algorithm), ``page.js`` the controls.

No network, no third-party code: the file opens from disk in any current browser.
Everything in the document is SI (m, rad) except ``ik``, which is the document of
``kincalc ik --json`` (:func:`kincalc.analysis.results.ik_document`) in the user's units;
the page converts at its edges with ``units.per_rad`` and ``units.per_m``.
"""

from __future__ import annotations

import html
import json
import math
import re
from importlib import resources

import numpy as np

from ...tolerances import LIMIT_TOL, SINGULAR_TOL
from ...version import __version__

#: the page warns "close to a singularity" when sigma_min / sigma_max of the scale-free
#: Jacobian (over the arm's generic rank) falls below this
NEAR_SINGULAR = 0.01
#: how long the page takes to move the arm to a chosen IK branch (animate on), ms
ANIMATION_MS = 1000
#: the package data files inlined into the page, by their place in the template
ASSETS = {"STYLE": "page.css", "KIN": "kin.js", "SCENE": "scene.js", "PAGE": "page.js"}
#: the ground grid's half width, as a fraction of the robot's characteristic length
GRID_FRACTION = 0.5
#: a joint's disc or square (radius), as a fraction of the characteristic length
JOINT_FRACTION = 0.035


def page_html(robot, units, q=None, ik=None) -> str:
    """The page of ``robot``: a complete HTML document, nothing else needed to show it.

    Parameters
    ----------
    robot : Robot
    units : Units
        The user's units (:class:`kincalc.analysis.results.Units`): the sliders, boxes
        and read-outs show angles and lengths in them.
    q : array_like (n,), optional
        The joints the page opens at (rad / m); default the robot's home.
    ik : IKResult, optional
        An answer of :func:`kincalc.ik.solve` (with ``units``): every solution is listed
        on the page, by branch, and a click moves the arm there.

    Returns
    -------
    str
        The HTML text (UTF-8 when written). Strings from the robot file reach the page
        only inside the JSON document (``<`` escaped, so no name can end the script) and
        the escaped ``<title>``; the page puts them into the DOM as text.
    """
    data = page_data(robot, units, q, ik)
    parts = {name: _asset(file) for name, file in ASSETS.items()}
    parts.update(VERSION=__version__, TITLE=html.escape(f"{robot.name} - kincalc view"),
                 DATA=embedded_json(data))
    # one pass: nothing substituted is searched again for placeholders
    return re.sub(r"\{\{([A-Z]+)\}\}", lambda m: parts[m.group(1)], _asset("page.html"))


def embedded_json(data) -> str:
    """``data`` as JSON safe inside an HTML ``<script>`` element: ``<``, ``>`` and ``&``
    as ``\\u`` escapes (no ``</script>`` or ``<!--`` can appear), and the line
    separators U+2028 and U+2029 too. Non-finite numbers are refused (ValueError)."""
    text = json.dumps(data, ensure_ascii=False, allow_nan=False, separators=(",", ":"))
    for ch in "<>&\u2028\u2029":
        text = text.replace(ch, f"\\u{ord(ch):04x}")
    return text


def page_data(robot, units, q=None, ik=None) -> dict:
    """The JSON document the page runs on (see the module docstring); arguments as
    :func:`page_html`."""
    from ...conventions.conversion import CONVENTION_NAMES
    from ..plot.style import JOINT_FACE, LINK_COLOUR, TRIAD_COLOURS, TRIAD_FRACTION
    from ..results import ik_document
    chain = robot.chain
    q = robot.home if q is None else np.asarray(q, float)
    size = robot.characteristic_length
    rank, position_rank = robot.generic_ranks
    return {
        "kincalc": __version__,
        "command": "kincalc view",
        "robot": {"name": robot.name, "title": robot.title, "source": robot.source},
        "convention_name": CONVENTION_NAMES[robot.convention],
        "units": {"angle": units.angle, "length": units.length,
                  "per_rad": units.a, "per_m": units.l},
        "joints": [{"name": j.name, "type": j.type, "limits": _limits(j)}
                   for j in robot.joints],
        "chain": {"fixed": chain.fixed.tolist(), "revolute": chain.revolute.tolist(),
                  "offset": chain.offset.tolist()},
        "base": np.asarray(robot.base, float).tolist(),
        "q": q.tolist(),
        "home": np.asarray(robot.home, float).tolist(),
        "size": size,
        "generic_rank": rank,
        "generic_position_rank": position_rank,
        "singular_tol": SINGULAR_TOL,
        "near_singular": NEAR_SINGULAR,
        "limit_tol": LIMIT_TOL,
        "animation_ms": ANIMATION_MS,
        "grid": _grid(size),
        "style": {"link": LINK_COLOUR, "revolute": JOINT_FACE, "prismatic": "#9c7bc4",
                  "edge": "#3a3a3a", "axis": "#8a8f98", "grid": "#e3e6ea", "text": "#444444",
                  "triad_colours": list(TRIAD_COLOURS), "triad_fraction": TRIAD_FRACTION,
                  "joint_fraction": JOINT_FRACTION},
        "dh": dh_table(robot),
        "ik": None if ik is None else ik_document(ik),
    }


def dh_table(robot) -> dict:
    """The robot's DH table for the page: its own (standard or modified DH), or for a
    poe robot (a URDF's) the standard DH table of the same axes (:func:`~kincalc.
    conventions.conversion.dh_of_axes`; none, with the reason as its note, where DH cannot
    describe them to full accuracy).

    Returns
    -------
    dict
        ``title``, ``columns`` (the table's heads), ``rows``: per joint, per column
        ``[value, kind, variable]``, the value SI, kind ``"angle"`` or ``"length"``, and
        the joint's name where its variable adds to that entry (else None); ``note``.
    """
    from ...conventions.conversion import dh_of_axes
    table, why = (robot, "") if robot.convention != "poe" else dh_of_axes(robot)
    if table is None:
        return {"title": "No standard DH table of these axes", "columns": [], "rows": [],
                "note": why}
    if table.convention == "dh":
        fields = (("theta", "angle"), ("d", "length"), ("a", "length"), ("alpha", "angle"))
        columns = ["\u03b8_i", "d_i", "a_i", "\u03b1_i"]
        title, formula = "Standard DH table", "A_i = Rz(\u03b8_i) Tz(d_i) Tx(a_i) Rx(\u03b1_i)"
    else:
        fields = (("alpha", "angle"), ("a", "length"), ("d", "length"), ("theta", "angle"))
        columns = ["\u03b1_{i-1}", "a_{i-1}", "d_i", "\u03b8_i"]
        title = "Modified DH table (Craig)"
        formula = "A_i = Rx(\u03b1_{i-1}) Tx(a_{i-1}) Rz(\u03b8_i) Tz(d_i)"
    if robot.convention == "poe":
        title = "Standard DH table of the same axes (kincalc convert --to dh)"
    moving = {"revolute": "theta", "prismatic": "d"}
    rows = [[[float(getattr(j, f)), kind, j.name if moving[j.type] == f else None]
             for f, kind in fields] for j in table.joints]
    note = formula + "; a joint's variable adds to \u03b8 (revolute) or d (prismatic)."
    if not (np.allclose(table.base, np.eye(4)) and np.allclose(table.written_tool, np.eye(4))):
        note += " The base and tool transforms are not in the table (kincalc robots show " \
                "lists them)."
    return {"title": title, "columns": columns, "rows": rows, "note": note}


def _limits(joint):
    """A joint's limits ``[lower, upper]`` (rad / m), or None when it has none."""
    if joint.limits is None or not all(math.isfinite(v) for v in joint.limits):
        return None
    return [float(joint.limits[0]), float(joint.limits[1])]


def _grid(size: float) -> dict:
    """The ground grid: ``half`` its half width (m), a round number near
    :data:`GRID_FRACTION` of the robot's size, and ``step`` a quarter of it."""
    raw = GRID_FRACTION * size
    decade = 10.0 ** math.floor(math.log10(raw))
    half = next(k * decade for k in (1, 2, 2.5, 5, 10) if k * decade >= raw)
    return {"half": half, "step": half / 4}


def _asset(name: str) -> str:
    """A package data file of this module, as text."""
    return resources.files(__package__).joinpath(name).read_text(encoding="utf-8")
