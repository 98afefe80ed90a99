"""The dexterous workspace: the positions reached with every test orientation (Craig,
sec. 4.3), SO(3) test sets by the super-Fibonacci spiral; see
:mod:`kincalc.analysis.workspace`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .sampling import joint_ranges
from .volume import reached, starts, wilson

DEXTERITY_POINTS = 400
#: test orientations for the dexterous workspace: SO(3) and one-angle robots
ORIENTATIONS_3D = 48
ORIENTATIONS_1D = 24
#: (point, orientation) pairs of the dexterity test solved at a time (~25 kB each while
#: solved by damped least squares: the memory stays ~200 MB whatever --orientations is)
PAIR_CHUNK = 1 << 13


def _batchable(robot) -> bool:
    """Does :meth:`Robot.ik_batch` cover this robot (a closed-form family)?"""
    from ...errors import UnsupportedRobot
    try:
        robot.ik_batch(robot.fk(np.asarray(robot.home, float))[None])
    except UnsupportedRobot:
        return False
    return True


# --- orientations ------------------------------------------------------------

def super_fibonacci(count: int) -> np.ndarray:
    """``(count, 3, 3)`` near-uniform rotations: Alexa's super-Fibonacci spiral
    (M. Alexa, "Super-Fibonacci spirals: fast, low-discrepancy sampling of SO(3)",
    CVPR 2022; constants phi = sqrt(2), psi = 1.533751168755204288118041)."""
    from ...spatial import matrix_from_quaternion
    s = np.arange(count) + 0.5
    t = s / count
    r, R = np.sqrt(t), np.sqrt(1.0 - t)
    a = 2 * np.pi * s / np.sqrt(2.0)
    b = 2 * np.pi * s / 1.533751168755204288118041
    quat = np.stack([r * np.sin(a), r * np.cos(a), R * np.sin(b), R * np.cos(b)], axis=1)
    return matrix_from_quaternion(quat[:, [3, 0, 1, 2]])


def _orientation_family(robot):
    """How the robot's orientation varies: ``("SO(3)", None)``, ``("axis", n (3,))``
    for one angle about a fixed world axis, or ``(None, why)``."""
    full, full_pos = robot.generic_ranks
    rng = np.random.default_rng(7)
    lo, hi = joint_ranges(robot)
    Jw = robot.jacobian(rng.uniform(lo, hi, (8, robot.dof)))[:, 3:, :]
    Jw = np.swapaxes(Jw, 1, 2).reshape(-1, 3)
    s = np.linalg.svd(Jw, compute_uv=False)
    rot_rank = int(np.sum(s > 1e-9 * max(s[0], 1e-300)))
    if full == 6 and rot_rank == 3:
        return "SO(3)", None
    if rot_rank == 1 and full == full_pos + 1:   # the angle is free of the position
        n = Jw[np.argmax(np.linalg.norm(Jw, axis=1))]
        return "axis", n / np.linalg.norm(n)
    if rot_rank == 0:
        return None, "the tool never turns: its orientation is fixed"
    return None, (f"the robot controls {full} of the 6 pose components, so at any position "
                  "its orientation is confined to a subset: no position admits every "
                  "orientation")


@dataclass(frozen=True)
class Orientations:
    """The test orientations of the dexterous workspace: ``R (K, 3, 3)`` (world), what
    they are in words (``about``), and whether the closed form tests them (``exact``,
    :meth:`Robot.ik_batch`) rather than damped least squares."""

    R: np.ndarray
    about: str
    exact: bool


def test_orientations(robot, Q, count, units) -> Orientations | str:
    """The :class:`Orientations` of ``robot`` (``count`` of them, default 48 for SO(3)
    and 24 for one angle), or the sentence why the dexterous workspace is not defined.
    ``Q (N, n)``: samples (the first one's orientation starts the one-angle set)."""
    kind, extra = _orientation_family(robot)
    if kind is None:
        return extra
    if kind == "SO(3)":
        count = count or ORIENTATIONS_3D
        Rset = super_fibonacci(count)
        about = f"{count} near-uniform orientations (super-Fibonacci spiral)"
    else:
        count = count or ORIENTATIONS_1D
        from ...spatial import matrix_from_axis_angle
        R0 = robot.fk(Q[0])[:3, :3]
        angles = 2 * np.pi * np.arange(count) / count
        Rset = matrix_from_axis_angle(np.broadcast_to(extra, (count, 3)), angles) @ R0
        about = (f"{count} tool angles {2 * np.pi / count * units.a:.4g} {units.angle} apart "
                 f"about the axis {np.round(extra, 6).tolist()}")
    return Orientations(Rset, about, _batchable(robot))


def orientation_hits(robot, Q, P, grid, order, sorted_cells, targets, orientations,
                     progress=None):
    """Which of the points ``targets (M, 3)`` the robot reaches, and with which test
    orientations: ``(at, hit)`` with ``at`` the indices of the reachable targets and
    ``hit (len(at), K)`` bool. Searches start from the samples ``Q``, ``P`` nearest each
    target (``grid``, ``order``, ``sorted_cells``: the volume's grid and its samples
    sorted by cell); ``progress("dexterity", done, 2)`` after each stage."""
    progress = progress or (lambda *a: None)
    cand = starts(grid, order, sorted_cells, targets, per_cell=4)
    Rs = robot.fk(Q[np.maximum(cand, 0)].reshape(-1, robot.dof))[:, :3, :3].reshape(
        cand.shape + (3, 3))
    progress("dexterity", 0, 2)
    reachable = reached(robot, Q, P, cand, targets)
    progress("dexterity", 1, 2)
    # every (point, orientation) pair of the reachable points, PAIR_CHUNK pairs at a time
    # (each pair is solved on its own: the chunks change nothing but the memory)
    Rset = orientations.R
    K = len(Rset)
    at = np.flatnonzero(reachable)
    hit = np.zeros((len(at), K), bool)
    step = max(1, PAIR_CHUNK // K)
    for s in range(0, len(at), step):
        a = at[s:s + step]
        hit[s:s + len(a)] = reached(
            robot, Q, P, np.repeat(cand[a], K, axis=0), np.repeat(targets[a], K, axis=0),
            R_goal=np.tile(Rset, (len(a), 1, 1)), Rc=np.repeat(Rs[a], K, axis=0),
            exact=orientations.exact).reshape(len(a), K)
    progress("dexterity", 2, 2)
    return at, hit


def dexterous(robot, rng, grid, Q, P, order, sorted_cells, region, volume, volume_ci,
               fraction, count, units, progress) -> dict:
    """The dexterous workspace: random points of ``region`` (cells), each tested with
    every orientation of a fixed set. Its volume is the reachable ``volume`` times the
    share of the reachable test points that are dexterous (a ratio, so it never
    exceeds the reachable volume), with Wilson's interval on that share."""
    tests = test_orientations(robot, Q, count, units)
    if isinstance(tests, str):
        return {"defined": False, "reason": tests, "volume": None, "volume_ci95": None}
    m = DEXTERITY_POINTS
    cells = np.argwhere(region)
    pick = cells[rng.integers(0, len(cells), m)]
    targets = grid.point(pick, rng.uniform(size=(m, grid.dim)))
    at, hit = orientation_hits(robot, Q, P, grid, order, sorted_cells, targets, tests,
                               progress)
    exact, about = tests.exact, tests.about
    share = hit.mean(axis=1)
    k, a = int(np.sum(share >= fraction - 1e-12)), len(at)
    f_lo, f_hi = wilson(k, a)
    return {
        "defined": True,
        "orientations": about,
        "method": ("closed-form IK per point and orientation (exact)" if exact else
                   "damped least squares from the nearest samples (can miss an orientation, "
                   "so the volume may come out low)"),
        "fraction_required": fraction,
        "test_points": m,
        "reachable_test_points": a,
        "dexterous_points": k,
        "volume": volume * k / max(a, 1),
        "volume_ci95": [volume_ci[0] * f_lo, volume_ci[1] * f_hi],
        "dexterous_share": k / max(a, 1),
        "orientation_coverage_mean": float(share.mean()) if a else 0.0,
    }
