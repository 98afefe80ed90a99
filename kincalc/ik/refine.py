"""Newton's method on the pose equations of the true robot, for solutions that are
already close: the closed-form answers of a robot that is only nearly of its family.

A calibrated model or a datasheet rounded to a few digits gives axes that meet or are
parallel to 1e-7 instead of exactly. The family's closed form then solves a robot a
hair away from the true one, and its answers miss the target by about that much. Each
such answer lies next to a solution of the true robot (of the same branch); a few
Gauss-Newton steps from it (:func:`kincalc.ik.newton.polish`) reach that solution to
rounding (quadratic convergence).
A candidate that does not converge is left as it was, and the caller's FK check
rejects it.
"""

from __future__ import annotations

import numpy as np

from ..jacobian import jacobian_and_pose
from ..spatial import cross, rotvec_from_matrix
from .joint_limits import joint_scale
from .newton import polish

#: Newton steps at most; from 1e-7 off, three reach rounding, but next to a double
#: singularity (two singular values of 1e-10 and 1e-16, a spherical wrist at q5 ~ 1e-8
#: with its shoulder folded) Newton converges linearly: eight left 1.2e-9, twelve 5e-12
ITERATIONS = 16
#: stop once the largest scaled residual is below this
CONVERGED = 1e-15


def refine(robot, q, T, *, mode: str = "pose", approach=None,
           iterations: int = ITERATIONS, held=None) -> np.ndarray:
    """Candidates ``q (M, n)`` (rad / m) moved onto solutions of ``robot.fk(q) = T``.

    Parameters
    ----------
    robot : Robot
        The true robot.
    q : ndarray (M, n)
        Starting joint values, each close to a solution (rad for revolute, m for
        prismatic joints).
    T : ndarray (4, 4) or (M, 4, 4)
        Target tool pose(s) in the world frame, SI.
    mode : {"pose", "position", "approach"}
        The equations to solve: the whole pose; the tool position only; or the
        position and the approach direction ``approach (3,)`` (unit, world), the tool
        z axis, for five-joint arms. Fewer joints than equations: least squares
        (Gauss-Newton), which for a reachable target is Newton's method on the
        components the robot controls.
    held : ndarray (M, n) of bool, optional
        Joints that keep their starting values (:func:`kincalc.ik.newton.polish`'s ``fixed``).

    Returns
    -------
    ndarray (M, n)
        The refined joint values (a copy; ``q`` is not modified). Rows that did not
        converge hold their last iterate: check them by FK.
    """
    q = np.array(q, dtype=float).reshape(-1, robot.dof)
    T = np.broadcast_to(np.asarray(T, float), (len(q), 4, 4))
    L = max(robot.characteristic_length, 1e-12)
    col = joint_scale(robot)                        # prismatic joints in units of L
    if approach is not None:
        approach = np.broadcast_to(np.asarray(approach, float), (len(q), 3))

    def evaluate(y, rows):
        A, e = linearised(robot, y * col, T[rows], L, mode,
                           None if approach is None else approach[rows])
        return e, lambda keep: A[keep] * col
    y, _, moved = polish(evaluate, q / col, iterations=iterations, tol=CONVERGED, fixed=held)
    return np.where(moved[:, None], y * col, q)


def linearised(robot, q, T, L, mode: str = "pose", approach=None):
    """The equations of :func:`refine` linearised at ``q (m, n)`` (rad / m), for the targets
    ``T (m, 4, 4)`` (world frame, m): ``(A (m, r, n), e (m, r))``, the derivative of the model
    (``r`` rows: position, then orientation or approach; base frame) by the joints and the
    residuals ``target - model``, lengths divided by ``L`` (m), orientations in rad (the
    rotation vector of ``R_target R^T``)."""
    J, Tq = jacobian_and_pose(robot.chain, q, column_walk=True)   # (m, 6, n) base frame
    ep = (T[:, :3, 3] - Tq[:, :3, 3]) / L
    Jv = J[:, :3] / L
    if mode == "position":
        return Jv, ep
    Jw = J[:, 3:]
    if mode == "approach":
        z = Tq[:, :3, 2]
        a = np.broadcast_to(np.asarray(approach, float), z.shape)
        # turning z by w moves it by w x z; only the part of w across z matters
        Jw = Jw - z[:, :, None] * np.einsum("mi,min->mn", z, Jw)[:, None, :]
        return np.concatenate([Jv, Jw], axis=1), np.concatenate([ep, cross(z, a)], axis=-1)
    ew = rotvec_from_matrix(T[:, :3, :3] @ np.swapaxes(Tq[:, :3, :3], -1, -2))
    return np.concatenate([Jv, Jw], axis=1), np.concatenate([ep, ew], axis=-1)
