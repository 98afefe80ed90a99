"""The sheet of :mod:`kincalc.homework.quiz` as YAML text: the same bytes for the same
dict, in the layout a person writes."""

from __future__ import annotations

import numpy as np

from ...limits import printable


# --- YAML ------------------------------------------------------------------------------

def _scalar(v) -> str:
    if v is None:
        return "null"
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "no"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        text = repr(float(v) + 0.0)
        mantissa, _, exponent = text.partition("e")
        if exponent:        # YAML 1.1 floats need a dot and a signed exponent: 1.0e-05
            if "." not in mantissa:
                mantissa += ".0"
            exponent = exponent if exponent[0] in "+-" else "+" + exponent
            text = f"{mantissa}e{exponent}"
        return text
    from ...conventions.writer import yaml_string
    return yaml_string(str(v), plain_ok=True)


def _flat(v) -> bool:
    if isinstance(v, dict):
        return all(not isinstance(x, (dict, list)) for x in v.values())
    if isinstance(v, list):
        return all(not isinstance(x, (dict, list)) for x in v)
    return True


def _flow(v) -> str:
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_scalar(k)}: {_scalar(x)}" for k, x in v.items()) + "}"
    if isinstance(v, list):
        return "[" + ", ".join(_scalar(x) for x in v) + "]"
    return _scalar(v)


def _block(v, indent: int) -> list[str]:
    pad = " " * indent
    out = []
    if isinstance(v, dict):
        for k, x in v.items():
            if _flat(x):
                out.append(f"{pad}{_scalar(k)}: {_flow(x)}")
            else:
                out.append(f"{pad}{_scalar(k)}:")
                out.extend(_block(x, indent + 2))
        return out
    for x in v:
        if _flat(x):
            out.append(f"{pad}- {_flow(x)}")
        else:
            inner = _block(x, indent + 2)
            out.append(f"{pad}- {inner[0].lstrip()}")
            out.extend(inner[1:])
    return out


def sheet_yaml(sheet: dict, comments=()) -> str:
    """``sheet`` (a :func:`make_sheet` dict) as YAML text, ``comments`` as ``#`` lines
    on top (each on one line: a line break in one, from a file's name, is a space). Lists
    of numbers are written in flow style (a matrix one row a line), floats so that they read
    back as the same float, yes/no for booleans."""
    lines = [f"# {printable(c)}" if c else "#" for c in comments]    # (one line each)
    lines += _block(sheet, 0)
    return "\n".join(lines) + "\n"
