"""``kincalc robots list | show | validate``."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, List, Optional

import typer

from .common import (BaseLinkOpt, DebugOpt, DegOpt, Integer, JsonOpt, PrecisionOpt, RobotArg,
                     RobotName, StructureTolOpt, TipLinkOpt, UnitOpt, Words, joints_text)

app = typer.Typer(help="The robot library: list, show and validate robot files.",
                  rich_markup_mode=None,
                  no_args_is_help=True, add_completion=False,
                  context_settings={"help_option_names": ["-h", "--help"]})


def structure_code(robot) -> str:
    return "".join("R" if j.revolute else "P" for j in robot.joints)


def _families() -> list:
    """The IK family names ``--family`` takes (at TAB only: the solvers are imported)."""
    from ..ik.solvers import SOLVERS
    return sorted(SOLVERS) + ["general-6r", "numerical"]


@app.command("list")
def list_(
    family: Annotated[Optional[str], typer.Option(
        "--family", metavar="NAME", show_default=False, click_type=Words(_families),
        help="Only robots whose IK family is NAME (as the ik column shows it, e.g. "
             "spherical-wrist, three-parallel, general-6r, or numerical).")] = None,
    dof: Annotated[Optional[int], typer.Option(
        "--dof", metavar="N", click_type=Integer(1), show_default=False,
        help="Only robots with N joints.")] = None,
    json: JsonOpt = False,
    debug: DebugOpt = False,
):
    """List every bundled robot: name, joints, convention, how ik answers, and title."""
    from ..errors import KincalcError, UsageError
    from ..limits import quote
    known = _families()
    if family is not None and family.removeprefix("reversed-") not in known:
        raise UsageError(f"--family: no IK family {quote(family)}; the families are "
                         f"{', '.join(known)} (and reversed-... of the six-joint ones)")
    from ..conventions.library import bundled_names, library_dir
    from ..conventions.reader import load_robot_file
    entries = []
    for name in bundled_names():
        try:
            r = load_robot_file(library_dir() / f"{name}.yaml")
        except KincalcError as exc:  # a broken bundled file is a bug; say so, keep listing
            entries.append({"name": name, "error": str(exc)})
            continue
        ik = _ik_method(r)
        # the name to type as ROBOT (the file's; its 'name:' may differ in a library of one's own)
        entries.append({"name": name, "dof": r.dof, "structure": structure_code(r),
                        "convention": r.convention, "units": r.length_unit,
                        "ik": ik["family"] or "numerical", "title": r.title})
    entries = [e for e in entries if "error" in e or (
        (dof is None or e["dof"] == dof) and (family is None or e["ik"] == family))]
    if json:
        from ..analysis.results import SCHEMA_VERSION
        from .render import emit_json
        emit_json({"kincalc": SCHEMA_VERSION, "command": "robots list",
                   "library": str(library_dir()), "robots": entries})
        return
    from rich import box
    from rich.table import Table
    from rich.text import Text

    from .render import console, file_words
    which = " ".join(w for w in (f"with {dof} joints" if dof else "",
                                 f"of IK family {family}" if family else "") if w)
    t = Table(box=box.SIMPLE, title=f"{len(entries)} bundled robot"
              + ("" if len(entries) == 1 else "s") + (f" {which}" if which
                                                                          else ""),
              title_justify="left")
    for col in ("name", "dof", "structure", "convention", "ik", "units"):
        t.add_column(col, no_wrap=True)
    # a title squeezed narrower than this reads a word a line: then it gets a panel of its own
    t.add_column("title", min_width=25)
    for e in entries:
        if "error" in e:
            t.add_row(file_words(e["name"]), "", "", "", "", "",
                      Text(f"broken: {file_words(e['error'])}", style="red"))
        else:
            t.add_row(e["name"], str(e["dof"]), e["structure"], e["convention"], e["ik"],
                      e["units"], file_words(e["title"]))
    console().print(t)


@app.command()
def show(
    robot: RobotArg,
    deg: DegOpt = True,
    unit: UnitOpt = None,
    precision: PrecisionOpt = 4,
    json: JsonOpt = False,
    base_link: BaseLinkOpt = None,
    tip_link: TipLinkOpt = None,
    structure_tol: StructureTolOpt = None,
    debug: DebugOpt = False,
):
    """Show a robot: its DH (or POE) table as a textbook prints it, limits, base, tool, source."""
    from ..analysis.results import SCHEMA_VERSION, robot_summary
    from .common import display_units, load_robot
    rob = load_robot(robot, base_link, tip_link, structure_tol)
    u = display_units(rob, deg, unit)
    doc = {"kincalc": SCHEMA_VERSION, "command": "robots show",
           "robot": robot_summary(rob), "units": u.to_dict()}
    doc["robot"].update(_details(rob, u))
    doc["robot"]["ik"] = _ik_method(rob)
    dh = None
    if rob.convention == "poe":
        # the DH table of the same axes (a URDF's, or any poe robot's), or why there is none
        from ..conventions.conversion import dh_of_axes
        dh, why = dh_of_axes(rob)
        doc["robot"]["dh"] = None if dh is None else {
            k: v for k, v in _details(dh, u).items() if k in ("joints", "base", "tool")}
        if dh is None:
            doc["robot"]["dh_note"] = why
    if json:
        from .render import emit_json
        emit_json(doc)
        return
    _show_tables(doc, rob, dh, u, precision)


def _details(rob, u) -> dict:
    joints = []
    for j in rob.joints:
        s = u.a if j.revolute else u.l
        entry = {"name": j.name, "type": j.type,
                 "limits": None if j.limits is None else [j.limits[0] * s, j.limits[1] * s]}
        if rob.convention == "poe":
            entry["axis"] = list(j.axis)
            entry["point"] = [v * u.l for v in j.point]
        else:
            entry.update({"alpha": j.alpha * u.a, "a": j.a * u.l, "d": j.d * u.l,
                          "theta": j.theta * u.a})
        joints.append(entry)
    return {"source": rob.source, "notes": rob.notes, "file_units":
            {"length": rob.length_unit, "angle": rob.angle_unit},
            "joints": joints, "base": u.pose(rob.base), "tool": u.pose(rob.written_tool),
            "home": u.joints(rob, rob.home),
            "path": rob.path, "characteristic_length": float(rob.characteristic_length * u.l)}


def _ik_method(rob) -> dict:
    """How ``kincalc ik`` answers for ``rob``: the closed-form family found from its axes,
    or the numerical solver and why."""
    from ..ik.families import plan
    _, family, why = plan(rob)
    if family is None:
        return {"method": "numerical", "family": None, "description": why}
    return {"method": "analytic", "family": family.name, "description": family.description}


def _var(name, offset, precision, unit):
    from .render import num
    if abs(offset) < 10.0 ** -(precision + 1):
        return name
    sign = "+" if offset > 0 else "-"
    return f"{name} {sign} {num(abs(offset), precision)}{unit}"


def _show_tables(doc, rob, dh, u, precision):
    """The tables of ``robots show``; ``dh``: a poe robot's standard DH robot (None when
    there is none, or for a dh or mdh robot)."""
    from ..limits import printable
    from .render import bold_line, console, file_words, kv_table, num
    c = console()
    r = doc["robot"]
    c.print(bold_line(file_words(rob.name), f" - {file_words(rob.title)}"))
    meta = [("convention", {"dh": "dh (standard, distal: A_i = Rz(θ) Tz(d) Tx(a) Rx(α))",
                            "mdh": "mdh (modified, Craig: A_i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ) Tz(d))",
                            "poe": "poe (product of exponentials, axes at q = 0)"}[rob.convention]),
            ("joints", f"{rob.dof} ({structure_code(rob)})"),
            ("file units", f"{rob.length_unit}, {rob.angle_unit}"),
            ("shown in", f"{u.length}, {u.angle}"),
            ("source", printable(rob.source) or "-")]
    from ..conventions.library import library_dir
    if rob.path and Path(rob.path).resolve().parent != library_dir().resolve():
        meta.append(("file", printable(rob.path)))
    ik = r["ik"]
    meta.append(("ik", f"{ik['family']}: {ik['description']}" if ik["family"] else
                 f"numerical ({ik['description']})"))
    c.print(kv_table(meta))
    _joint_table(c, rob, r, u, precision)
    if rob.convention == "poe" and r["dh"] is None:
        c.print(f"no standard DH table of these axes: {r['dh_note']}")
    elif rob.convention == "poe":
        _joint_table(c, dh, r["dh"], u, precision,
                     "Standard DH table of the same axes (kincalc convert --to dh)")
    c.print(f"home: {', '.join(num(v, precision) for v in r['home'])}")
    if rob.notes:
        c.print(f"notes: {file_words(rob.notes)}")


def _joint_table(c, rob, r, u, precision, title=None):
    """The robot's table (DH, modified DH or screws) with its limits, then its base and
    tool when they are not the identity; ``r`` holds the values in display units."""
    import numpy as np
    from rich import box
    from rich.table import Table

    from .render import matrix_table, num
    deg = "°" if u.angle == "deg" else ""
    t = Table(box=box.SIMPLE_HEAD, title_justify="left",
              title=title or {"dh": "Standard DH table", "mdh": "Modified DH table (Craig)",
                              "poe": "Joint screws (base frame, q = 0)"}[rob.convention])
    L = "" if u.length == "unitless" else f" {u.length}"
    if rob.convention == "dh":
        cols = ["i", "θ_i", "d_i", "a_i", "α_i"]
    elif rob.convention == "mdh":
        cols = ["i", "α_{i-1}", "a_{i-1}", "d_i", "θ_i"]
    else:
        cols = ["i", "type", "axis", "point"]
    for col in cols + ["limits"]:
        t.add_column(col, justify="right")
    for k, (j, e) in enumerate(zip(rob.joints, r["joints"]), start=1):
        s = deg if j.revolute else L
        lim = "-" if e["limits"] is None else \
            f"[{num(e['limits'][0], precision)}, {num(e['limits'][1], precision)}]{s}"
        if rob.convention == "poe":
            t.add_row(str(k), j.type, " ".join(num(v, precision) for v in e["axis"]),
                      " ".join(num(v, precision) for v in e["point"]), lim)
            continue
        theta = _var(j.name, e["theta"], precision, deg) if j.revolute \
            else f"{num(e['theta'], precision)}{deg}"
        d = f"{num(e['d'], precision)}" if j.revolute else _var(j.name, e["d"], precision, "")
        alpha = f"{num(e['alpha'], precision)}{deg}"
        a = num(e["a"], precision)
        row = [theta, d, a, alpha] if rob.convention == "dh" else [alpha, a, d, theta]
        t.add_row(str(k), *row, lim)
    c.print(t)
    if not np.allclose(r["base"], np.eye(4)):
        c.print(matrix_table(r["base"], precision, title="base: T_world^0"))
    if not np.allclose(r["tool"], np.eye(4)):
        c.print(matrix_table(r["tool"], precision,
                             title="tool: M (tool pose at q = 0)" if rob.convention == "poe"
                             else "tool: T_n^tool"))


@app.command()
def validate(
    files: Annotated[List[str], typer.Argument(
        metavar="FILE...", show_default=False, click_type=RobotName(),
        help="Robot YAML files to check, or bundled robots' names.")],
    json: JsonOpt = False,
    debug: DebugOpt = False,
):
    """Check robot files (or bundled robots); print one line per file. Exit 2 if any is
    invalid."""
    import sys

    from ..errors import KincalcError
    from ..conventions.library import load
    report, bad = [], 0
    for f in files:
        try:
            # a name as every command takes it: a bundled robot first, then a file
            r = load(f, display_name=f)
            report.append({"file": f, "valid": True, "name": r.name, "dof": r.dof,
                           "convention": r.convention, "error": None})
        except KincalcError as exc:
            if debug:
                raise
            bad += 1
            report.append({"file": f, "valid": False, "error": str(exc)})
    if json:
        from ..analysis.results import SCHEMA_VERSION
        from .render import emit_json
        emit_json({"kincalc": SCHEMA_VERSION, "command": "robots validate", "files": report})
    else:
        from ..limits import one_line, printable      # (a file name may hold an escape)
        for e in report:
            if e["valid"]:
                sys.stdout.write(f"ok: {printable(e['file'])}: {printable(e['name'])}, "
                                 f"{joints_text(e['dof'])}, {e['convention']}\n")
            else:
                sys.stderr.write(f"kincalc: error: {one_line(e['error'])}\n")
    if bad:
        raise typer.Exit(2)
