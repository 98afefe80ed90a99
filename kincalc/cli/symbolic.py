"""``--symbolic`` and ``--latex`` output of ``kincalc fk`` and ``kincalc jacobian``."""

from __future__ import annotations


def symbolic_check(symbolic: bool, latex: bool, numeric_lengths: bool, q) -> None:
    """Reject option combinations that make no sense with --symbolic."""
    from ..errors import UsageError
    if numeric_lengths and not (symbolic or latex):
        raise UsageError("--numeric-lengths needs --symbolic or --latex")
    if q:
        raise UsageError("--symbolic derives the formulas for every configuration: "
                         "give no joint values Q")


def require_sympy_for(command: str, symbolic: bool, latex: bool) -> None:
    """sympy, or the one-line error naming ``kincalc COMMAND --symbolic`` (or ``--latex``
    when only that was given)."""
    from ..analysis.symbolic import require_sympy
    require_sympy(f"kincalc {command} {'--symbolic' if symbolic or not latex else '--latex'}")


def symbolic_output(result, json: bool, latex: bool) -> None:
    """JSON, LaTeX or tables of a SymbolicFK / SymbolicJacobian."""
    import sys
    if json:
        from .render import emit_json
        emit_json(result.to_dict())
    elif latex:
        sys.stdout.write(result.latex())
    else:
        _symbolic_tables(result)


#: names of the entries of a pose matrix, for the one-entry-a-line layout
_POSE_NAMES = (("r11", "r12", "r13", "px"), ("r21", "r22", "r23", "py"),
               ("r31", "r32", "r33", "pz"))


def _symbolic_tables(result) -> None:
    from ..analysis.symbolic import ROWS, expr_text, unicode_name
    from .common import joints_text
    from .render import bold_line, console, file_words
    c = console()
    robot, n = result.robot, result.notation
    unit = "" if result.length_unit == "unitless" else f", lengths in {result.length_unit}"
    title = f" - {robot.title}" if robot.title else ""
    c.print(bold_line(file_words(robot.name), f"{file_words(title)}  ({joints_text(robot.dof)}, "
                                              f"{robot.convention}, symbolic{unit})"))
    symbols = [unicode_name(str(s)) for s in n.joints]
    c.print("joint variables: " + ", ".join(
        f"{s} ({'angle' if j.revolute else 'length'})" for s, j in zip(symbols, robot.joints)),
        markup=False)
    if n.parameters:
        c.print("parameters: " + ", ".join(f"{s} = {v:g}" for s, v in n.parameters), markup=False)
    c.print()
    if hasattr(result, "links"):
        titles = result.titles()
        for i, (j, M) in enumerate(zip(robot.joints, result.links), start=1):
            _matrix(c, M, f"T_{i - 1}^{i}  (link {i}, joint {j.name})", expr_text)
        if result.base is not None:
            _matrix(c, result.base, titles["base"], expr_text)
        if result.tool is not None:
            _matrix(c, result.tool, titles["tool"], expr_text)
        _matrix(c, result.T, titles["T"], expr_text, names=_POSE_NAMES)
    else:
        L = result.length_unit
        per = "" if L == "unitless" else f" [{L}/rad]"
        names = tuple(tuple(f"J({r}, {s})" for s in symbols) for r in ROWS)
        _matrix(c, result.J, f"J ({result.frame} frame; rows vx vy vz{per} wx wy wz)",
                expr_text, headers=symbols, row_labels=ROWS, names=names, by_column=True)
    if n.legend:
        entries = [f"{unicode_name(str(s))} = {type(f).__name__} {expr_text(f.args[0])}"
                   if f.args[0].is_Symbol else
                   f"{unicode_name(str(s))} = {type(f).__name__}({expr_text(f.args[0])})"
                   for s, f in n.legend]
        line = "where"
        for k, e in enumerate(entries):     # wrap between entries, never inside one
            e += "," if k < len(entries) - 1 else ""
            if len(line) + 1 + len(e) > c.width and line.strip():
                c.print(line, markup=False, soft_wrap=True)
                line = "     "
            line += " " + e
        c.print(line, markup=False, soft_wrap=True)


def _matrix(c, M, title, text, headers=None, row_labels=None, names=None,
            by_column=False) -> None:
    """A matrix as a grid when it fits the console, else one entry a line
    (``names[r][k] = ...``, row by row or, ``by_column``, column by column)."""
    from rich import box
    from rich.table import Table
    rows = M.shape[0] - (1 if names is not None and M.shape == (4, 4) else 0)
    cells = [[text(M[r, k]) for k in range(M.shape[1])] for r in range(M.shape[0])]
    widths = [max(len(cells[r][k]) for r in range(M.shape[0])) for k in range(M.shape[1])]
    if headers:
        widths = [max(w, len(h)) for w, h in zip(widths, headers)]
    label_w = max((len(x) for x in row_labels), default=0) + 2 if row_labels else 0
    c.print(title, markup=False)
    if names is None or sum(widths) + 3 * len(widths) + label_w <= c.width:
        t = Table(box=box.SIMPLE, show_header=headers is not None, pad_edge=False)
        if row_labels:
            t.add_column("", style="bold")
        for k in range(M.shape[1]):
            t.add_column(headers[k] if headers else "", justify="right", no_wrap=True)
        for r in range(M.shape[0]):
            t.add_row(*([row_labels[r]] if row_labels else []), *cells[r])
        c.print(t)
        return
    c.print()
    width = max(len(x) for row in names for x in row)
    order = [(r, k) for k in range(M.shape[1]) for r in range(rows)] if by_column else \
        [(r, k) for r in range(rows) for k in range(M.shape[1])]
    for r, k in order:
        c.print(f"  {names[r][k]:<{width}} = {cells[r][k]}", markup=False, soft_wrap=True)
    c.print()
