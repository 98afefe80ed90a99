"""IK target requests as the user writes them: from the user's units to the core's SI, and
how a file names a request's parts (the core, :mod:`kincalc.ik.target`, takes SI values
and returns what is wrong as data).
"""

from __future__ import annotations

import numpy as np

#: how a file (a batch record, a sheet's ``pose``) names the parts of an IK target, for the
#: core's messages about them (:meth:`kincalc.errors.TargetMismatch.words`)
FIELD_WORDS = {"approach": "approach", "tcv": "tcv", "prefix": "{field}: ",
               "orientation": "(rpy, euler_zyz, euler_xyz, quat, axis_angle, matrix, T or q)"}


def to_si(form: str | None, values, units):
    """Values of ``form`` in the user's units converted to SI.

    Angles of ``rpy``, ``euler_*`` and the angle of ``axis_angle`` from the display angle
    unit, the position of ``T`` and ``tcv`` from the display length unit; other forms
    are unit-free.

    Parameters
    ----------
    form : str or None
        The request's form (:func:`kincalc.ik.target.target_form`).
    values : array_like (N, k)
        The values in the user's units.
    units : Units
        The display units (:class:`kincalc.analysis.results.Units`): ``a`` and ``l``, display
        units per rad and per m.

    Returns
    -------
    ndarray (N, k)
        A new array (rad, m).
    """
    v = np.array(values, float)
    v = v.reshape(len(v), -1)
    if form in ("rpy", "euler_zyz", "euler_xyz"):
        v /= units.a
    elif form == "axis_angle":
        v[:, 3] /= units.a
    elif form == "tcv":
        v[:, :3] /= units.l
    elif form == "T":
        v[:, [3, 7, 11]] /= units.l
    return v
