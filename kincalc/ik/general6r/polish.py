"""Newton polishing of the general-6R candidates on the real robot (step 6 of
:mod:`kincalc.ik.general6r`), with the pose residual as a rotation vector."""

from __future__ import annotations

import numpy as np

from ...fk import entry_frames
from ...jacobian import frames_jacobian, jacobian_and_pose, scaled_ranks
from ...spatial import rotvec_from_matrix
from ..newton import polish
from .common import ACCEPT_TOL, GIVE_UP, GIVE_UP_LAST, NEWTON_ITERS, STEP_MAX, reduce_sum


# --- Newton polishing on the real robot -----------------------------------

def newton_curvature(chain) -> float:
    """A bound on the second derivatives of Newton's residual ``(dp / L, dw)`` on ``chain``
    (scaled by L), every component, per rad^2: twice the larger of 1 and the chain's length
    (the sum of its links' translations, a bound on the distance from any joint axis to the
    tool point; the derivatives of ``z_j x (p - o_j)`` are at most twice that, those of the
    axes at most 1). The ``settle`` bound of :func:`kincalc.ik.newton.polish`.

    Parameters
    ----------
    chain : Chain
        The robot's, with lengths divided by its length scale L.

    Returns
    -------
    float
    """
    reach = float(np.sqrt(reduce_sum(chain.fixed[1:, :3, 3] ** 2, axis=1)).sum())
    return 2.0 * max(1.0, reach)


def polish_candidates(chain, T, Q, iters=NEWTON_ITERS, give_up=GIVE_UP, curvature=None):
    """Newton (:func:`kincalc.ik.newton.polish`) on ``fk(q) = T`` for the candidates ``Q``.

    A candidate stops when its residual ``max(|dp| / L, |dw|)`` is at rounding level (below
    1e-13, or below ACCEPT_TOL / 100 and no longer halving, or a step that by the chain's
    curvature leaves it below 1e-14: quadratic convergence, not evaluated again), after
    ``iters`` steps, or when it is still far after a few (``GIVE_UP``: spurious candidates
    from complex eigenvalues; the few that would wander into a solution after many steps
    only find one that a good candidate already gave).

    Parameters
    ----------
    chain : Chain
        The robot's, with lengths divided by its length scale L.
    T : ndarray (m, 3, 4)
        Each candidate's target (rows 0-2 of ``T_world_tool``, translation scaled alike).
    Q : ndarray (m, 6)
        The starts (rad).
    iters : int
        Newton steps at most (steps of at most ``STEP_MAX`` rad).
    give_up : dict
        ``{step: bound}``: after that many steps, drop the candidates whose residual is
        still above ``bound``.
    curvature : float, optional
        :func:`newton_curvature` of ``chain`` (computed when not given).

    Returns
    -------
    q : ndarray (m, 6)
        Rad, not wrapped.
    residual : ndarray (m,)
        Each one's last residual: the largest component of ``(dp / L, dw)`` (rad), or for
        one that stopped after a step without an evaluation, a bound on it (below 1e-14).
    moved : ndarray (m,) of bool
        The candidates that took a step.
    """
    def evaluate(q, rows):
        # the walk for any number of rows: a candidate's bits do not depend on the others'
        # (Newton amplifies the last bit where a pose has a continuum of solutions)
        A = entry_frames(chain, q, column_walk=True)
        F = np.ascontiguousarray(A[:, :, -1].transpose(2, 0, 1))        # tool poses (m, 3, 4)
        Tr = T if len(rows) == len(T) else T[rows]      # the first pass: every row, in order
        R = Tr[:, :, :3] @ F[:, :, :3].swapaxes(-1, -2)
        # the Jacobian (that of jacobian_and_pose) only of the candidates that take a step
        return (np.concatenate([Tr[:, :, 3] - F[:, :, 3], rotvec_from_matrix(R)], axis=1),
                lambda keep: np.ascontiguousarray(frames_jacobian(
                    A if np.count_nonzero(keep) == len(keep) else A[..., keep],
                    chain.revolute).transpose(2, 0, 1)))
    return polish(evaluate, Q, iterations=iters, tol=1e-13, damping=1e-14,
                  stall=1e-2 * ACCEPT_TOL, give_up=give_up, max_step=STEP_MAX,
                  settle=newton_curvature(chain) if curvature is None else curvature)


def polish_from_both_sides(chain, T, Q, patient, curvature=None):
    """Newton for candidates of which the ``patient`` ones (the last resort's, from the
    perturbed robots) are given up later and also started past their landing point.

    The real robot's solutions lie some 1e-3 .. 1e-2 rad from the perturbed robots'
    candidates. Where two of them are close (a nearly singular Jacobian, common at the
    special poses that need the last resort: e.g. kinova_gen3_lite's two wrist solutions
    0.09 rad apart sharing the pivot angle), the perturbation is large against their
    separation: a perturbed robot's pair merges or turns into a complex pair, whose
    candidates (its real part, twice) lie near the real pair's midpoint, or the pair moves
    onto one of them. Newton's basins part near the midpoint, so every run lands on the same
    solution and the other was lost. So each patient candidate ``c`` that converged to a
    solution ``q`` is also started from its reflection ``2 c - q`` across its start: where
    ``c`` lay between the pair, nearer ``q``, that point lies beyond the midpoint, on the
    other one's side. The patient candidates are given up later (``GIVE_UP_LAST``, per
    candidate; the others ``GIVE_UP``, in the same Newton run): between a close pair Newton
    converges only linearly until it is nearer one of them than their separation, and from
    these starts that takes more than six steps (the restarts keep the default).

    Parameters
    ----------
    chain : Chain
        The robot's, with lengths divided by its length scale L.
    T : ndarray (m, 3, 4)
        Each candidate's target (as for :func:`polish_candidates`).
    Q : ndarray (m, 6)
        The starts (rad).
    patient : ndarray (m,) of bool
        The candidates given up later and restarted.
    curvature : float, optional
        :func:`newton_curvature` of ``chain`` (computed when not given).

    Returns
    -------
    q : ndarray (m + r, 6)
        Rad, not wrapped: the m candidates, then the r reflected starts.
    residual : ndarray (m + r,)
    moved : ndarray (m + r,) of bool
    src : ndarray (r,) of int
        The candidate each reflected start comes from (a restart that lands at a singular
        solution has residual inf: it is its source's root again).
    """
    give_up = {step: np.where(patient, GIVE_UP_LAST.get(step, np.inf), GIVE_UP.get(step, np.inf))
               for step in sorted(set(GIVE_UP) | set(GIVE_UP_LAST))}
    if curvature is None:
        curvature = newton_curvature(chain)
    q, res, moved = polish_candidates(chain, T, Q, give_up=give_up, curvature=curvature)
    src = np.flatnonzero(patient & (res < ACCEPT_TOL))
    if not len(src):
        return q, res, moved, src
    q2, res2, moved2 = polish_candidates(chain, T[src], 2.0 * Q[src] - q[src],
                                         curvature=curvature)
    # a restart is for a regular partner: one landing at a singular solution lands, within
    # the merge tolerance or just beyond it, on the root its source found
    landed = np.flatnonzero(res2 < ACCEPT_TOL)
    res2[landed[~regular(chain, q2[landed])]] = np.inf
    return np.concatenate([q, q2]), np.concatenate([res, res2]), \
        np.concatenate([moved, moved2]), src


def regular(chain, Q) -> np.ndarray:
    """Is each configuration regular (the Jacobian of full rank, by the engine's test:
    :func:`kincalc.jacobian.scaled_ranks`, singular values against ``SINGULAR_TOL``)?

    Parameters
    ----------
    chain : Chain
        The robot's, with lengths divided by its length scale (so the Jacobian is scaled).
    Q : ndarray (m, 6)
        Joint values (rad).

    Returns
    -------
    ndarray (m,) of bool
    """
    if not len(Q):
        return np.zeros(0, bool)
    J, _ = jacobian_and_pose(chain, Q, column_walk=True)
    return scaled_ranks(J, chain.revolute, 1.0)[0] == 6
