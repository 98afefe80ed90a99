"""Targets from the command line's pose options and the batch records' fields.

The core (:mod:`kincalc.ik.target`) names a request's format and builds its target in
SI; this module reads the user's numbers (in the display units, bounded), words what
the core finds wrong in the command line's names (``--rpy``, ``--pose FILE``) or a
batch record's (``rpy``), and reads ``--pose`` files.
"""

from __future__ import annotations

from ..errors import InputError, UsageError
from .common import check_numbers

#: how the command line names the fields of a target request
OPTION_NAMES = {"q": "--from-q", "T": "--pose"}


def option_name(field: str) -> str:
    """The command-line option of a request field (``euler_zyz`` -> ``--euler-zyz``,
    ``q`` -> ``--from-q``)."""
    return OPTION_NAMES.get(field) or "--" + field.replace("_", "-")


def build_target(robot, units, *, xyz=None, rpy=None, euler_zyz=None, euler_xyz=None,
                 quat=None, axis_angle=None, matrix=None, approach=None, tcv=None, pose=None,
                 from_q=None, T=None, q=None):
    """A :class:`~kincalc.ik.Target` from the pose options (user units -> SI).

    ``T`` (a 4x4 matrix, or 16 or 12 numbers) and ``q`` (joint values) are the
    batch-record forms of ``--pose`` and ``--from-q``, named as the records name them."""
    import numpy as np

    from ..ik import Target
    from ..ik.target import BadTarget, defect_text, target_form, targets_from, to_si
    given = {"xyz": xyz, "rpy": rpy, "euler_zyz": euler_zyz, "euler_xyz": euler_xyz,
             "quat": quat, "axis_angle": axis_angle, "matrix": matrix, "approach": approach,
             "tcv": tcv, "T": T if pose is None else pose, "q": q if from_q is None else from_q}
    record = {"T": T is not None, "q": q is not None}
    name = lambda f: f if record.get(f) else option_name(f)  # noqa: E731
    for f in ("xyz", "rpy", "euler_zyz", "euler_xyz", "quat", "axis_angle", "matrix",
              "approach", "tcv"):
        if given[f] is not None:
            check_numbers(np.asarray(given[f], float).ravel(), name(f))
    try:
        form = target_form(f for f, v in given.items() if v is not None)
    except BadTarget as exc:
        raise UsageError(exc.words(name)) from None
    if form == "q":
        from .common import parse_joints
        tokens = from_q.replace(",", " ").split() if from_q is not None else [str(x) for x in q]
        qv = parse_joints(tokens, robot, units, option=name("q"))
        return Target(robot.fk(qv), orientation=True)
    if form == "T":
        values = _read_pose(pose) if pose is not None else pose_values(np.array(T, float), "T")
        what = f"--pose {pose}" if pose is not None else "T"
    else:
        values = None if form is None else np.asarray(given[form], float).ravel()
        what = name(form) if form else None
    v = None if form is None else to_si(form, values[None], units)
    p = None if xyz is None else np.asarray(xyz, float)[None] / units.l
    targets, defect = targets_from(form, v, p)
    if defect[0] is not None:
        raise InputError(defect_text(form, defect[0], what))
    return Target.of(targets)


def pose_values(M, what):
    """``M`` (16 or 12 numbers, or a 4x4 matrix) as 16 or 12 bounded numbers, the field
    named ``what``; an InputError otherwise."""
    M = M.ravel()
    if M.size not in (12, 16):
        raise InputError(f"{what}: expected a 4x4 matrix (16 finite numbers), got {M.size}")
    check_numbers(M, what)
    return M


def _read_pose(src: str):
    import json as _json

    import numpy as np

    from ..limits import TooLarge, os_error_text, read_bounded, size_text
    what = f"--pose {src}"
    try:
        raw = read_bounded(src)
    except TooLarge as exc:
        raise InputError(f"{what}: larger than {size_text(exc.limit)}, kincalc's limit for "
                         "a pose file (a 4x4 matrix is a few hundred bytes)") from None
    except OSError as exc:
        raise InputError(f"{what}: cannot read ({os_error_text(exc)})") from None
    except ValueError:
        raise InputError(f"{what}: cannot read (not a valid file name)") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise InputError(f"{what}: not UTF-8 text; expected 16 numbers or JSON rows of a "
                         "4x4 matrix") from None
    try:
        data = _json.loads(text)
        if isinstance(data, dict):
            data = data.get("T", data.get("target", {}).get("T") if isinstance(
                data.get("target"), dict) else None)
        M = np.array(data, dtype=float)
    except (ValueError, TypeError, RecursionError):
        try:
            M = np.array(text.replace(",", " ").replace("[", " ").replace("]", " ").split(),
                         dtype=float)
        except ValueError:
            raise InputError(f"{what}: expected 16 numbers or JSON rows of a 4x4 matrix")\
                from None
    return pose_values(M, what)
