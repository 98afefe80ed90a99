"""The frozen robot description.

A :class:`Robot` keeps the joints in the convention they were written in
(standard DH, modified DH or product of exponentials), in SI units, and
derives from them one uniform *chain* (:class:`kincalc.chain.Chain`):

    T_world_tool(q) = F_0 · J_1(q_1) · F_1 · J_2(q_2) · ... · J_n(q_n) · F_n

where each ``F_i`` is a constant transform (the robot's ``base`` is folded
into ``F_0`` and its ``tool`` into ``F_n``) and ``J_i`` is a rotation about,
or a translation along, the local z axis by ``q_i + offset_i``. Forward
kinematics and Jacobians run on that chain whatever the convention; the
convention's own link frames (for printing ``T_{i-1}^i``) come from
:meth:`Robot.link_transforms`.

The methods ``fk``, ``jacobian`` and ``ik`` are the Python API's front door: they call
down into :mod:`kincalc.fk`, :mod:`kincalc.jacobian` and the engine :mod:`kincalc.ik`,
which see the robot only through its chain and limits (this module sits above them in the
house plan, ``tests/test_architecture.py``).

Link transforms by convention (lengths in m, angles in rad):

* ``dh`` (standard, distal; Spong/Corke): ``A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``
* ``mdh`` (modified, proximal; Craig): ``A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)``
* ``poe`` (Brockett; Lynch & Park ch. 4):
  ``T = base · exp([S_1] q_1) ··· exp([S_n] q_n) · M · tool``
  with ``S_i`` the screw of a unit axis through a point, both in the base frame
  at q = 0, and ``M`` the flange pose at q = 0 (a robot file's ``tool``).

In every convention ``tool`` is ``T_flange_tool``, the tool on the flange.

For dh/mdh a revolute joint's variable adds to ``theta`` and a prismatic
joint's to ``d``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from .chain import Chain
from .fk import chain_frames, forward_kinematics
from .jacobian import jacobian_base, jacobian_tool, scaled_ranks
from .samples import spread
from .spatial import invert_transform, rot_x, rot_z, transform

CONVENTIONS = ("dh", "mdh", "poe")
JOINT_TYPES = ("revolute", "prismatic")


@dataclass(frozen=True)
class Joint:
    """One joint, in SI units (m, rad).

    For ``dh``/``mdh`` robots ``alpha``, ``a``, ``d``, ``theta`` are the row of
    the DH table (for ``mdh``, ``alpha`` and ``a`` are alpha_{i-1}, a_{i-1}).
    For ``poe`` robots ``axis`` (unit, shape (3,)) and ``point`` (shape (3,))
    locate the joint axis in the base frame at q = 0.
    ``limits`` is ``(lower, upper)`` or ``None`` for an unlimited joint.
    """

    name: str
    type: str
    alpha: float = 0.0
    a: float = 0.0
    d: float = 0.0
    theta: float = 0.0
    axis: tuple[float, float, float] | None = None
    point: tuple[float, float, float] | None = None
    limits: tuple[float, float] | None = None

    def __post_init__(self):        # floats and tuples whatever was given: hashable by value
        for name in ("alpha", "a", "d", "theta", "axis", "point", "limits"):
            v = getattr(self, name)
            if v is not None:
                object.__setattr__(self, name, tuple(map(float, v)) if np.ndim(v) else float(v))

    @property
    def revolute(self) -> bool:
        return self.type == "revolute"


@dataclass(frozen=True)
class Robot:
    """A serial robot. Immutable and picklable.

    Attributes
    ----------
    name, title, source : str
        Identifier, human title and citation.
    convention : {'dh', 'mdh', 'poe'}
    joints : tuple of Joint
    base : ndarray (4, 4)
        ``T_world_0``: pose of the robot's frame 0 in the world (user) frame.
    tool : ndarray (4, 4)
        ``T_flange_tool``, in every convention: the pose of the tool in the flange frame,
        the frame that moves with the last link (dh/mdh: link frame n; poe: the frame at
        ``M`` at q = 0). Identity when the tool is the flange.
    M : ndarray (4, 4) or None
        poe only (None for dh/mdh): ``T_0_flange`` at q = 0, the flange's pose in frame 0
        at the zero configuration (Lynch & Park's M). A poe robot file's ``tool`` entry is
        this M (:attr:`written_tool`).
    home : ndarray (n,)
        A home configuration (rad / m).
    length_unit, angle_unit : str
        The units the robot file was written in; the CLI shows lengths in
        ``length_unit`` unless told otherwise.
    parameters : tuple of (name, value)
        The file's named ``parameters``, values in the file's units.
    expressions : tuple of tuple of (field, source)
        Per joint, the DH fields (``alpha``, ``a``, ``d``, ``theta``) the file
        gave as expressions over parameters (e.g. ``('d', 'h1')``), as written.
        Used to print link matrices with the table's own names.
    structure_tol : float or None
        How nearly axes must meet (as a fraction of the arm's size) or be parallel (sine
        of their angle) for the IK engine to take the structure as meant, solve the
        nearest robot that has it in closed form and refine on this one; None: the
        defaults :data:`~kincalc.tolerances.STRUCTURE_POINT_TOL` and
        :data:`~kincalc.tolerances.STRUCTURE_ANGLE_TOL` (``kincalc ik --structure-tol``).
    """

    name: str
    convention: str
    joints: tuple[Joint, ...]
    base: np.ndarray = field(default_factory=lambda: np.eye(4))
    tool: np.ndarray = field(default_factory=lambda: np.eye(4))
    M: np.ndarray | None = None
    home: np.ndarray | None = None
    title: str = ""
    source: str = ""
    notes: str = ""
    length_unit: str = "m"
    angle_unit: str = "deg"
    path: str | None = None
    parameters: tuple = ()
    expressions: tuple = ()
    structure_tol: float | None = None

    def __post_init__(self):
        if self.convention not in CONVENTIONS:
            raise ValueError(f"unknown convention {self.convention!r}")
        object.__setattr__(self, "joints", tuple(self.joints))
        base = np.array(self.base, dtype=float)
        tool = np.array(self.tool, dtype=float)
        base.setflags(write=False)
        tool.setflags(write=False)
        object.__setattr__(self, "base", base)
        object.__setattr__(self, "tool", tool)
        if (self.M is None) != (self.convention != "poe"):
            raise ValueError("a poe robot needs M (the flange pose at q = 0) and a dh/mdh "
                             "robot has none (its flange is link frame n)")
        if self.M is not None:
            M = np.array(self.M, dtype=float)
            M.setflags(write=False)
            object.__setattr__(self, "M", M)
        home = np.zeros(self.dof) if self.home is None else np.array(self.home, dtype=float)
        home.setflags(write=False)
        object.__setattr__(self, "home", home)

    # --- basic facts -------------------------------------------------------

    @property
    def dof(self) -> int:
        return len(self.joints)

    @property
    def joint_types(self) -> list[str]:
        return [j.type for j in self.joints]

    @cached_property
    def is_revolute(self) -> np.ndarray:
        """Boolean mask ``(n,)``: True for revolute joints (read-only)."""
        out = np.array([j.revolute for j in self.joints], dtype=bool)
        out.setflags(write=False)
        return out

    @cached_property
    def limits(self) -> np.ndarray:
        """Joint limits ``(n, 2)`` in rad / m; ``-inf, inf`` for unlimited joints
        (read-only)."""
        out = np.empty((self.dof, 2))
        for i, j in enumerate(self.joints):
            out[i] = j.limits if j.limits is not None else (-np.inf, np.inf)
        out.setflags(write=False)
        return out

    def __hash__(self):
        # computed once: the per-robot caches of the solvers hash the robot on every call
        try:
            return self.__dict__["_hash"]
        except KeyError:
            value = self.__dict__["_hash"] = hash((self.name, self.convention, self.joints,
                                                   self.structure_tol))
            return value

    def __getstate__(self):
        # string hashes differ between processes: a pickled robot (a batch's worker)
        # computes its hash again
        return {k: v for k, v in self.__dict__.items() if k != "_hash"}

    def __eq__(self, other):
        if not isinstance(other, Robot):
            return NotImplemented
        return (self.name == other.name and self.convention == other.convention
                and self.joints == other.joints and self.structure_tol == other.structure_tol
                and np.array_equal(self.base, other.base)
                and np.array_equal(self.tool, other.tool)
                and (self.M is None) == (other.M is None)
                and (self.M is None or np.array_equal(self.M, other.M)))

    @property
    def written_tool(self) -> np.ndarray:
        """The robot file's ``tool`` entry ``(4, 4)``, m: ``T_n_tool`` for dh/mdh, and for
        poe the tool's pose in frame 0 at q = 0, ``M @ tool``."""
        return self.tool if self.M is None else self.M @ self.tool

    # --- the uniform chain -------------------------------------------------

    @cached_property
    def chain(self) -> "Chain":
        """The uniform chain ``F_0 J_1 F_1 ... J_n F_n`` (see module docstring)."""
        return _chain_of(self)

    @cached_property
    def characteristic_length(self) -> float:
        """A length scale of the robot (m): the sum of the chain's fixed offsets.

        Used to make position tolerances and singularity tests scale-free.
        Prismatic joints count with their offset (dh's ``d``) and upper limit when finite.
        """
        F, c = self.chain.fixed, self.chain
        total = np.sum(np.linalg.norm(F[1:, :3, 3], axis=-1)) + np.abs(c.offset[~c.revolute]).sum()
        for j in self.joints:
            if not j.revolute and j.limits is not None:
                total += max(abs(j.limits[0]), abs(j.limits[1]))
        return float(total) if total > 0 else 1.0

    @cached_property
    def generic_ranks(self) -> tuple[int, int]:
        """``(rank of J, rank of its linear rows)`` at a generic configuration.

        A planar arm has rank 2 or 3, a SCARA 4: a configuration is singular
        when either rank drops below these. Taken as the largest rank over a
        few configurations spread within the limits (:func:`kincalc.samples.spread`).
        """
        lo, hi = self.limits.T
        lo = np.where(np.isfinite(lo), lo, -np.pi)
        hi = np.where(np.isfinite(hi), hi, np.pi)
        J = self.jacobian(spread(5, lo, hi))
        rank, position_rank = scaled_ranks(J, self.is_revolute, self.characteristic_length)
        return int(rank.max()), int(position_rank.max())

    # --- kinematics (delegating to the numeric core) ----------------------

    def fk(self, q, *, column_walk: bool = False) -> np.ndarray:
        """Forward kinematics: the tool pose for joint values.

        Parameters
        ----------
        q : array_like (..., n)
            Joint values, rad (revolute) / m (prismatic); any leading batch shape.
        column_walk : bool
            Each configuration's bits the same in any batch (what kincalc prints uses it). By
            default up to 32 configurations are stacked 4x4 products: 3x faster for one, other
            last bits (:func:`kincalc.fk.forward_kinematics`).

        Returns
        -------
        ndarray (..., 4, 4)
            ``T_world_tool = base @ T_0^n(q) @ tool``, lengths in m.

        Raises
        ------
        ValueError
            ``q``'s last axis is not ``n`` long.
        """
        return forward_kinematics(self.chain, q, column_walk=column_walk)

    def jacobian(self, q, frame: str = "base", *, column_walk: bool = False) -> np.ndarray:
        """The geometric Jacobian: tool-point velocity and angular velocity per joint rate.

        Parameters
        ----------
        q : array_like (..., n)
            Joint values, rad / m.
        frame : {'base', 'tool'}
            ``'base'``: velocities of the tool point in the world frame; ``'tool'``:
            the same velocities expressed in the tool frame.
        column_walk : bool
            As :meth:`fk`'s.

        Returns
        -------
        ndarray (..., 6, n)
            Rows ``vx vy vz wx wy wz``; a revolute column is ``[z_i x (p - o_i); z_i]``
            (m/rad and rad/rad), a prismatic one ``[z_i; 0]``.

        Raises
        ------
        ValueError
            An unknown ``frame``, or ``q`` of the wrong length.
        """
        if frame == "base":
            return jacobian_base(self.chain, q, column_walk=column_walk)
        if frame == "tool":
            return jacobian_tool(self.chain, q, column_walk=column_walk)
        raise ValueError(f"frame must be 'base' or 'tool', not {frame!r}")

    def ik(self, T, orientation: bool = True, **options):
        """Inverse kinematics: every solution for one tool pose, each labelled and flagged.

        Parameters
        ----------
        T : array_like (4, 4)
            The target ``T_world_tool``, lengths in m. Its rotation is read as the CLI
            reads one: a rotation to 6 digits, re-orthonormalised (the nearest rotation)
            unless it is one to rounding already.
        orientation : bool
            False: reach the position only (robots that do not control orientation).
        **options
            Those of :func:`kincalc.ik.solve` (``all_branches``, ``explain``, ``near``: the
            current joints ``(n,)``, rad / m, ``numeric``, ``units``, ``reasons``).

        Returns
        -------
        IKResult
            :class:`~kincalc.ik.IKResult`: ``solutions``, each with ``q (n,)`` (rad / m),
            ``branch``, FK residuals (m, rad), limit ``violations``, ``singular`` and the
            joints the target leaves ``free``; ``reason`` says why, as data
            (:mod:`kincalc.ik.reasons`). :func:`kincalc.analysis.results.ik_document`
            renders it.

        Raises
        ------
        TargetMismatch
            The target's kind does not fit the robot (an orientation for a robot that sets
            none, ...).
        ValueError
            ``T`` is not a pose: its rotation not orthonormal with determinant +1 to 6
            digits, or its last row not 0 0 0 1.
        """
        # lazily: the engine is large, and a robot is often loaded only to be shown
        from .ik import Target, solve
        from .ik.target import api_poses, defect_text
        T = np.asarray(T, float)
        if orientation and T.shape == (4, 4):
            poses, defect = api_poses(T[None])
            if defect[0] is not None:
                raise ValueError(defect_text("T", defect[0], "T"))
            T = poses[0]
        return solve(self, Target(T, orientation), **options)

    def ik_batch(self, T):
        """Every IK solution for each of many poses, vectorised over the poses.

        Parameters
        ----------
        T : array_like (N, 4, 4) or (4, 4)
            Targets ``T_world_tool``, lengths in m; rotations read as :meth:`ik` reads them
            (a matrix that is not a pose is solved as given: no solution).

        Returns
        -------
        Solved
            :class:`~kincalc.ik.engine.Solved`: ``q (N, K, n)`` (rad / m), ``valid (N,
            K)`` (a solution in that slot), ``labels``, ``within (N, K)``, ``singular (N,
            K)``, FK residuals. ``robot.ik`` is the same engine for one pose.

        Raises
        ------
        UnsupportedRobot
            No closed form covers the robot (:mod:`kincalc.ik.families`); ``robot.ik``
            then answers numerically.
        """
        from .ik.engine import solve_batch
        from .ik.target import api_poses
        T = np.asarray(T, float)
        if T.ndim in (2, 3) and T.shape[-2:] == (4, 4):
            T = api_poses(T.reshape(-1, 4, 4))[0].reshape(T.shape)
        return solve_batch(self, T)

    def link_transforms(self, q) -> np.ndarray:
        """The convention's link transforms ``T_{i-1}^i``.

        Parameters
        ----------
        q : array_like (..., n)
            Joint values, rad / m.

        Returns
        -------
        ndarray (..., n, 4, 4)
            The pose of link frame i in link frame i - 1 (m): the DH (or modified DH) link
            frames of the robot file, frame 0 the robot's base frame before ``base`` is
            applied. For poe robots, frame i sits on joint i's axis (z along it) and moves
            with link i.

        Raises
        ------
        ValueError
            ``q`` of the wrong length.
        """
        q = np.asarray(q, dtype=float)
        if q.shape[-1:] != (self.dof,):
            raise ValueError(f"expected q of shape (..., {self.dof}), got {q.shape}")
        if self.convention == "poe":
            return _poe_link_transforms(self, q)
        mats = []
        for i, j in enumerate(self.joints):
            qi = q[..., i]
            theta = j.theta + (qi if j.revolute else 0.0 * qi)
            d = j.d + (0.0 * qi if j.revolute else qi)
            if self.convention == "dh":
                A = _rz_tz(theta, d) @ transform(rot_x(j.alpha), [j.a, 0.0, 0.0])
            else:
                A = transform(rot_x(j.alpha), [j.a, 0.0, 0.0]) @ _rz_tz(theta, d)
            mats.append(A)
        return np.stack(mats, axis=-3)


def _rz_tz(theta, d) -> np.ndarray:
    """``Rz(theta) Tz(d)`` for arrays ``theta, d (...,)``."""
    theta = np.asarray(theta, dtype=float)
    d = np.broadcast_to(np.asarray(d, dtype=float), theta.shape)
    T = transform(rot_z(theta))
    T[..., 2, 3] = d
    return T


def axis_frame(axis, point) -> np.ndarray:
    """A frame with its z axis along a joint axis.

    Parameters
    ----------
    axis, point : array_like (3,)
        The axis direction (normalised here) and a point on it (m).

    Returns
    -------
    ndarray (4, 4)
        The frame's pose: origin ``point``, z along ``axis``, x chosen deterministically
        perpendicular to z (from the x or y axis of the frame the inputs are in).
    """
    z = np.asarray(axis, dtype=float)
    z = z / np.linalg.norm(z)
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = helper - z * (helper @ z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return transform(np.stack([x, y, z], axis=-1), point)


def _poe_link_transforms(robot: Robot, q: np.ndarray) -> np.ndarray:
    frames = chain_frames(robot.chain, q)  # world-frame joint frames after motion
    Tw0 = invert_transform(robot.base)
    T0 = Tw0 @ frames                      # (..., n, 4, 4) in frame 0
    prev = np.concatenate([np.broadcast_to(np.eye(4), T0.shape[:-3] + (1, 4, 4)),
                           T0[..., :-1, :, :]], axis=-3)
    return invert_transform(prev) @ T0


def _chain_of(robot: Robot) -> Chain:
    """The uniform chain of ``robot``'s joints in its convention (module docstring)."""
    n = robot.dof
    pre, post, offset = [], [], np.zeros(n)
    for i, j in enumerate(robot.joints):
        if robot.convention == "poe":
            C = axis_frame(j.axis, j.point)
            pre.append(C)
            post.append(invert_transform(C))
            continue
        Xa = transform(rot_x(j.alpha), [j.a, 0.0, 0.0])   # Rx(alpha) Tx(a) == Tx(a) Rx(alpha)
        Rt = transform(rot_z(j.theta))
        Td = transform(None, [0.0, 0.0, j.d])
        if robot.convention == "dh":
            if j.revolute:            # Rz(q + theta) · Tz(d) Tx(a) Rx(alpha)
                pre.append(np.eye(4)); post.append(Td @ Xa); offset[i] = j.theta
            else:                     # Tz(q + d) · Rz(theta) Tx(a) Rx(alpha)
                pre.append(np.eye(4)); post.append(Rt @ Xa); offset[i] = j.d
        else:
            if j.revolute:            # Rx(alpha) Tx(a) · Rz(q + theta) · Tz(d)
                pre.append(Xa); post.append(Td); offset[i] = j.theta
            else:                     # Rx(alpha) Tx(a) Rz(theta) · Tz(q + d)
                pre.append(Xa @ Rt); post.append(np.eye(4)); offset[i] = j.d
    fixed = np.empty((n + 1, 4, 4))
    fixed[0] = robot.base @ pre[0] if n else robot.base
    for i in range(1, n):
        fixed[i] = post[i - 1] @ pre[i]
    flange = np.eye(4) if robot.M is None else robot.M
    fixed[n] = (post[n - 1] if n else np.eye(4)) @ flange @ robot.tool
    # Snap exact-looking zeros and ones so the evaluator can skip them
    # (cos(pi/2) = 6e-17 would otherwise cost a multiply per sample).
    snapped = np.where(np.abs(fixed) < 1e-15, 0.0, fixed)
    snapped = np.where(np.abs(np.abs(snapped) - 1.0) < 1e-15, np.sign(snapped), snapped)
    revolute = robot.is_revolute
    for arr in (snapped, revolute, offset):
        arr.setflags(write=False)
    return Chain(snapped, revolute, offset)
