"""What inverse kinematics must reach, for a batch of targets.

A :class:`Targets` holds ``N`` targets of one kind, world frame, SI:

* ``"pose"``: the whole pose ``T (N, 4, 4)``;
* ``"position"``: the tool position only (``T[:, :3, 3]``; the rotation part is the
  identity and means nothing) for robots that do not control the orientation;
* ``"approach"``: the position and the approach direction, the tool z axis
  (``approach (N, 3)``, unit), for five-joint arms that do not set the roll about it;
* ``"tcv"``: a tool configuration vector (Schilling 1990): the position, the approach
  and the last joint's value ``roll (N,)`` (rad);
* ``"swivel"``: the whole pose and, for an arm with a spherical shoulder and wrist, the
  swivel angle of its elbow ``swivel (N,)`` (rad; :mod:`kincalc.ik.swivel`).

:func:`target_form` names the format of a request from the fields it gives (and
refuses a combination that is not one target), :func:`targets_from` builds the targets
of many requests of one format at once (RPY, Euler angles, quaternions, axis-angle,
matrices, whole poses, approach directions, TCVs). The command line, the batch runner
and the homework grader all go through these two; what is wrong is returned as data
(:class:`BadTarget`, the ``defect`` codes) that each of them words with its own names
for the fields. Values arrive here in SI: the edge converts the user's units first
(:func:`kincalc.analysis.requests.to_si`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import spatial as sp
from ..errors import UsageError
from ..spatial import invert_transform
from ..tolerances import ORTHONORMAL

KINDS = ("pose", "position", "approach", "tcv", "swivel")


@dataclass(frozen=True)
class Targets:
    """``N`` IK targets of one ``kind`` (see the module docstring)."""

    T: np.ndarray
    kind: str = "pose"
    approach: np.ndarray | None = None
    roll: np.ndarray | None = None
    swivel: np.ndarray | None = None

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"kind must be one of {KINDS}, not {self.kind!r}")

    def __len__(self) -> int:
        return len(self.T)

    @staticmethod
    def poses(T) -> "Targets":
        """Whole-pose targets.

        Parameters
        ----------
        T : array_like (N, 4, 4) or (4, 4)
            Poses ``T_world_tool`` (world frame, SI).

        Returns
        -------
        Targets
            ``N`` targets of kind ``"pose"`` (one for a single pose).
        """
        T = np.asarray(T, float)
        return Targets(T.reshape(-1, 4, 4))

    def inverted(self) -> "Targets":
        """The inverse poses (for a chain solved from the tool: ``T^-1``).

        Returns
        -------
        Targets
            ``T_tool_world`` per target.

        Raises
        ------
        ValueError
            Targets of another kind than ``"pose"``: an approach, a roll or a swivel is
            the tool's, with no meaning at the base (no reversed family takes one: the
            approach families have five joints and are never reversed).
        """
        if self.kind != "pose":
            raise ValueError(f"only whole poses are solved from the tool, not {self.kind}")
        return Targets(invert_transform(self.T))

    def take(self, index) -> "Targets":
        """The targets at ``index``.

        Parameters
        ----------
        index : array_like of int or bool
            An index array or a mask ``(N,)`` into the N targets.

        Returns
        -------
        Targets
            The chosen targets, of the same kind.
        """
        pick = lambda x: None if x is None else x[index]  # noqa: E731
        return Targets(self.T[index], self.kind, pick(self.approach), pick(self.roll),
                       pick(self.swivel))


#: the fields of a target request and their number of values (``q``: one per joint,
#: ``T``: 16, or 12 for the top three rows); lengths in m, angles in rad
FIELDS = {"xyz": 3, "rpy": 3, "euler_zyz": 3, "euler_xyz": 3, "quat": 4, "axis_angle": 4,
          "matrix": 9, "approach": 3, "tcv": 6, "T": 16, "q": 0}
#: the fields that give an orientation (with ``xyz``, or holding the position: ``tcv``)
ORIENTATIONS = ("rpy", "euler_zyz", "euler_xyz", "quat", "axis_angle", "matrix", "approach",
                "tcv")
#: the fields that give the whole pose on their own
WHOLE = ("T", "q")


class BadTarget(UsageError):
    """A target request whose fields do not make one target (exit 2), as data.

    ``problem``: ``"two orientations"``, ``"whole and part"`` (a whole pose with a
    position or an orientation), ``"two wholes"``, ``"tcv and xyz"`` or ``"no position"``;
    ``fields``: the fields at fault, in the order given. :meth:`words` names them as the
    caller names them."""

    def __init__(self, problem: str, *fields: str):
        self.problem, self.fields = problem, fields
        super().__init__(self.words(lambda f: f))

    def words(self, name) -> str:
        """The message, with each field ``f`` spelled ``name(f)``.

        Parameters
        ----------
        name : callable
            ``name(field) -> str``: how the caller spells a field of :data:`FIELDS`
            (``--quat``, ``quat``).

        Returns
        -------
        str
        """
        f = [name(x) for x in self.fields]
        if self.problem == "two orientations":
            return f"give at most one orientation, not {' and '.join(f)}"
        if self.problem == "whole and part":
            return f"{f[0]} gives the whole pose; do not combine it with {f[1]}"
        if self.problem == "two wholes":
            return f"give either {f[0]} or {f[1]}, not both"
        if self.problem == "tcv and xyz":
            return f"{f[0]} holds the position; do not give {f[1]} as well"
        return (f"give the target position with {name('xyz')} (or the whole pose with "
                f"{' or '.join(name(w) for w in WHOLE)})")


def target_form(given) -> str | None:
    """The format of a request that gives the fields ``given``.

    Parameters
    ----------
    given : iterable of str
        Field names, in the order given; names not in :data:`FIELDS` are ignored.

    Returns
    -------
    str or None
        One of :data:`ORIENTATIONS` or :data:`WHOLE`, or None for a position alone.

    Raises
    ------
    BadTarget
        For fields that do not make one target: two orientations, a whole pose with a
        position or an orientation, two wholes, ``tcv`` with ``xyz``, or no position.
    """
    given = [f for f in given if f in FIELDS]
    orient = [f for f in given if f in ORIENTATIONS]
    whole = [f for f in given if f in WHOLE]
    if len(orient) > 1:
        raise BadTarget("two orientations", *orient)
    if whole and (orient or "xyz" in given):
        raise BadTarget("whole and part", whole[0], (orient + ["xyz"])[0])
    if len(whole) > 1:
        raise BadTarget("two wholes", *whole[:2])
    if whole:
        return whole[0]
    if orient == ["tcv"]:
        if "xyz" in given:
            raise BadTarget("tcv and xyz", "tcv", "xyz")
        return "tcv"
    if "xyz" not in given:
        raise BadTarget("no position")
    return orient[0] if orient else None


#: what can be wrong with the values of one request (:func:`targets_from`'s ``defect``):
#: ``zero`` (a zero quaternion, axis, approach or TCV approach part), ``not rotation``
#: (a matrix that is not a rotation to 6 digits: rows orthonormal, determinant +1),
#: ``last row`` (a pose whose last row is not 0 0 0 1, to 1e-9)
DEFECTS = ("zero", "not rotation", "last row")


def targets_from(form: str | None, values=None, xyz=None) -> tuple[Targets, np.ndarray]:
    """The targets of ``N`` requests of one ``form``, vectorised.

    Rotation matrices (whole poses and the ``matrix`` form) are re-orthonormalised, the
    nearest rotation by SVD, unless they are already orthonormal to rounding
    (:func:`kincalc.spatial.nearest_rotations`): a matrix typed to 6 or 12 digits is a
    rotation again.

    Parameters
    ----------
    form : str or None
        See :func:`target_form` (``"q"`` is not built here: its pose is the robot's FK);
        None for positions alone.
    values : array_like (N, k), optional
        The form's values (angles rad, lengths m; ``T`` 16 or 12 per row, ``matrix`` 9,
        row-major); unused for ``form`` None.
    xyz : array_like (N, 3), optional
        The positions (m, world frame), for the forms that do not hold one.

    Returns
    -------
    targets : Targets
        ``N`` targets (world frame, SI): kind ``"position"`` for ``form`` None,
        ``"approach"`` or ``"tcv"`` for those forms, else ``"pose"``.
    defect : ndarray (N,) of object
        None or one of :data:`DEFECTS` per request. A request with a defect holds the
        identity rotation (approach +z, roll 0) at the position given (a ``T``: the
        identity pose).
    """
    if form is not None:
        values = np.asarray(values, float)
        values = values.reshape(len(values), -1)
    N = len(values) if form is not None else len(xyz)
    T = np.zeros((N, 4, 4))
    T[:] = np.eye(4)
    if xyz is not None:
        T[:, :3, 3] = np.asarray(xyz, float).reshape(N, 3)
    defect = np.full(N, None, object)
    if form is None:
        return Targets(T, "position"), defect
    if form == "T":
        M = values if values.shape[1] == 16 else np.concatenate(
            [values, np.tile([0.0, 0.0, 0.0, 1.0], (N, 1))], axis=1)
        M = M.reshape(N, 4, 4)
        defect[~(np.abs(M[:, 3] - [0.0, 0.0, 0.0, 1.0]) <= 1e-9).all(-1)] = "last row"
        _rotations(M[:, :3, :3], defect)
        good = defect == None  # noqa: E711
        T[good, :3, :3] = sp.nearest_rotations(M[good, :3, :3])
        T[good, :3, 3] = M[good, :3, 3]
        return Targets(T), defect
    if form in ("approach", "tcv"):
        v = values[:, 3:] if form == "tcv" else values
        n = np.linalg.norm(v, axis=-1)
        zero = ~(n > 1e-300 if form == "tcv" else n >= 1e-12)
        defect[zero] = "zero"
        n = np.where(zero, 1.0, n)
        a = np.where(zero[:, None], [0.0, 0.0, 1.0], v / n[:, None])
        if form == "approach":
            return Targets(T, "approach", approach=a), defect
        T[:, :3, 3] = values[:, :3]
        return Targets(T, "tcv", approach=a, roll=np.pi * np.log(n)), defect
    if form in ("quat", "axis_angle"):
        R = _quat_or_axis(form, values, defect)
    elif form == "matrix":
        R = values.reshape(N, 3, 3)
        _rotations(R, defect)
    else:
        make = {"rpy": sp.matrix_from_rpy, "euler_zyz": sp.matrix_from_euler_zyz,
                "euler_xyz": sp.matrix_from_euler_xyz}[form]
        R = make(values)
    good = defect == None  # noqa: E711
    T[good, :3, :3] = sp.nearest_rotations(R[good]) if form == "matrix" else R[good]
    return Targets(T), defect


def _quat_or_axis(form: str, values, defect) -> np.ndarray:
    """The rotations ``(N, 3, 3)`` of quaternions or axis-angles ``values (N, 4)``, their
    ``defect`` set where the quaternion or axis is zero (the identity there). Only the
    direction counts: scaled by its largest entry first, a quaternion of 1e-300 is the
    identity's, not a zero one (its norm's square underflows)."""
    v = values[:, :3] if form == "axis_angle" else values
    size = np.abs(v).max(-1)
    zero = ~(size > 0)
    defect[zero] = "zero"
    v = v / np.where(zero, 1.0, size)[:, None]
    if form == "quat":
        return sp.matrix_from_quaternion(np.where(zero[:, None], [1.0, 0, 0, 0], v))
    return sp.matrix_from_axis_angle(np.where(zero[:, None], [0.0, 0, 1], v), values[:, 3])


_LAST_ROW = np.array([0.0, 0.0, 0.0, 1.0])


def api_poses(T) -> tuple[np.ndarray, np.ndarray]:
    """Poses given to the Python API read as the CLI reads them: each rotation checked to
    :data:`~kincalc.tolerances.ROTATION_TOL` and re-orthonormalised
    (:func:`kincalc.spatial.nearest_rotations`), the last row
    checked; a pose that is not one (or not finite) is kept as given.

    Parameters
    ----------
    T : array_like (N, 4, 4), ``T_world_tool`` (world frame, SI)

    Returns
    -------
    poses : ndarray (N, 4, 4)
    defect : ndarray (N,) of object
        None, or one of :data:`DEFECTS` (worded by :func:`defect_text`) for a finite
        matrix that is not a pose.
    """
    T = np.asarray(T, float)
    if (sp.orthonormality_error(T[:, :3, :3]) <= ORTHONORMAL).all() \
            and (T[:, 3] == _LAST_ROW).all():
        return T, np.full(len(T), None, object)      # poses to rounding (FK's): as given
    targets, defect = targets_from("T", T.reshape(len(T), 16))
    finite = np.isfinite(T).all((-1, -2))
    defect[~finite] = None
    poses = targets.T
    keep = (defect != None) | ~finite  # noqa: E711
    poses[keep] = T[keep]
    return poses, defect


def defect_text(form: str, defect: str, what: str) -> str:
    """What is wrong with a request's values, in words.

    Parameters
    ----------
    form : str
        The request's form (:func:`target_form`).
    defect : str
        One of :data:`DEFECTS`.
    what : str
        The field, as each caller names it (``--quat``, ``quat``).

    Returns
    -------
    str
    """
    if defect == "not rotation":
        return (f"{what} is not a rotation matrix (rows must be orthonormal with "
                "determinant +1, to 6 digits)")
    if defect == "last row":
        return f"{what}: the last row must be 0 0 0 1"
    return {"quat": f"{what} must not be the zero quaternion",
            "axis_angle": f"{what} needs a non-zero axis",
            "approach": f"{what} must not be the zero vector",
            "tcv": f"{what}: the approach part w4..w6 must not be zero"}[form]


def _rotations(R, defect) -> None:
    """Mark ``defect`` "not rotation" where ``R (N, 3, 3)`` is not a rotation to 6 digits
    (:func:`kincalc.spatial.is_rotation`) and no other defect is marked."""
    defect[~sp.is_rotation(R) & (defect == None)] = "not rotation"  # noqa: E711
