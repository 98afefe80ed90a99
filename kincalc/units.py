"""Unit conversion at the edges of kincalc.

Inside the core everything is SI: metres and radians. Robot files and the CLI
speak the user's units; these helpers are the only place where factors live.
"""

from __future__ import annotations

import math

from .errors import InputError

#: metres per unit of each accepted length unit. ``unitless`` robots (textbook
#: examples with bare numbers) are carried with a factor of 1.
LENGTH_UNITS: dict[str, float] = {
    "m": 1.0,
    "cm": 0.01,
    "mm": 0.001,
    "in": 0.0254,
    "unitless": 1.0,
}

#: radians per unit of each accepted angle unit.
ANGLE_UNITS: dict[str, float] = {
    "deg": math.pi / 180.0,
    "rad": 1.0,
}


def length_factor(unit: str) -> float:
    """Return metres per ``unit`` (the factor from the user's length unit to m).

    Parameters
    ----------
    unit : str
        A key of :data:`LENGTH_UNITS`: ``'m'``, ``'cm'``, ``'mm'``, ``'in'`` or
        ``'unitless'`` (factor 1).

    Returns
    -------
    float
        Metres per ``unit``.

    Raises
    ------
    InputError
        An unknown unit (the message lists the accepted ones).
    """
    try:
        return LENGTH_UNITS[unit]
    except KeyError:
        raise InputError(
            f"unknown length unit {unit!r} (use one of {', '.join(LENGTH_UNITS)})"
        ) from None


def angle_factor(unit: str) -> float:
    """Return radians per ``unit`` (the factor from the user's angle unit to rad).

    Parameters
    ----------
    unit : str
        A key of :data:`ANGLE_UNITS`: ``'deg'`` or ``'rad'``.

    Returns
    -------
    float
        Radians per ``unit``.

    Raises
    ------
    InputError
        An unknown unit (the message lists the accepted ones).
    """
    try:
        return ANGLE_UNITS[unit]
    except KeyError:
        raise InputError(
            f"unknown angle unit {unit!r} (use one of {', '.join(ANGLE_UNITS)})"
        ) from None
