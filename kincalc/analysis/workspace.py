"""Workspace analysis: seeded Monte-Carlo sampling of the joint space.

:func:`analyse` samples joint values uniformly within the limits and reports

* the **reach envelope**: the least and greatest distance of the tool point
  from the base frame's origin and its z range (world frame). Samples give a
  first estimate; the extremes are then refined by local optimisation from
  the best samples, so a fully stretched arm's reach comes out to ~1e-9 of
  its link lengths instead of the few per cent a sampled maximum misses by;
* the **reachable workspace volume** (an area for planar arms) with a 95 %
  confidence interval. The samples' tool points are binned into a grid with
  about :data:`SAMPLES_PER_CELL` samples per occupied cell. Cells whose whole
  3^d neighbourhood is occupied count as inside; cells next to an occupied
  cell but not inside form the *band* where the boundary runs; cells further
  out count as outside. The band's inside fraction is estimated by
  hit-or-miss: uniform random points in band cells, each tested for
  membership by damped least squares from the nearest samples
  (:func:`descend`). The interval is the binomial (Wilson) interval of that
  fraction, given the grid assumptions (inside cells are wholly inside,
  outside cells wholly outside), which hold when the sampling is dense
  enough for the grid, the reason for the samples-per-cell rule;
* the **dexterous workspace** (Craig, *Introduction to Robotics*, sec. 4.3:
  the positions the tool reaches with every orientation; here every one of a
  fixed near-uniform set of test orientations, or a stated fraction of them):
  random points of the reachable set, each tested with each orientation by
  :func:`descend`; its volume is the dexterous fraction of the reachable
  region with a Wilson interval. Defined for robots that control the full
  orientation (SO(3), test set by Alexa's super-Fibonacci spiral, CVPR 2022)
  and for arms whose orientation is one angle about a fixed axis (planar
  arms, SCARAs);
* **manipulability** statistics: Yoshikawa's measure, the product of the
  Jacobian's singular values up to its generic rank (the quantity ``kincalc
  jacobian`` prints, in the same display units), and the condition number of
  the length-normalised Jacobian.

Frames and units: world frame, SI (m, rad) inside; :meth:`Workspace.to_dict`
converts to display units.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import BadValue, UsageError
from ..ik.nearest import descend, motion_frame
from ..limits import MAX_ORIENTATIONS, MAX_SAMPLES

#: mean samples per occupied grid cell the grid is sized for
SAMPLES_PER_CELL = 24
#: hit-or-miss points in the boundary band (volume) and test points (dexterity)
BAND_POINTS = 3000
DEXTERITY_POINTS = 400
#: test orientations for the dexterous workspace: SO(3) and one-angle robots
ORIENTATIONS_3D = 48
ORIENTATIONS_1D = 24
#: a point counts as reached when damped least squares gets within this of it
#: (relative to the robot's characteristic length; rad for orientation)
REACHED = 1e-7
#: samples the manipulability statistics use (the first ones drawn), and the
#: condition-number statistics (an SVD each)
MANIPULABILITY_SAMPLES = 200_000
CONDITION_SAMPLES = 50_000
#: samples per chunk of the FK pass (the progress bar moves per chunk)
CHUNK = 1 << 16
#: (point, orientation) pairs of the dexterity test solved at a time (~25 kB each while
#: solved by damped least squares: the memory stays ~200 MB whatever --orientations is)
PAIR_CHUNK = 1 << 13
#: z for 95 % two-sided intervals
Z95 = 1.959963984540054


def joint_ranges(robot) -> tuple[np.ndarray, np.ndarray]:
    """``(lo, hi)`` (n,) sampling ranges in SI: the limits, with unlimited revolute
    joints sampled over one turn [-pi, pi]. Unlimited prismatic joints are refused."""
    lo, hi = (np.array(x, float) for x in robot.limits.T)
    for i, j in enumerate(robot.joints):
        if np.isfinite(lo[i]) and np.isfinite(hi[i]):
            continue
        if not j.revolute:
            raise UsageError(f"{robot.name}: prismatic joint {j.name} has no limits, so its "
                             "workspace is unbounded; give it limits in the robot file")
        lo[i], hi[i] = -np.pi, np.pi
    return lo, hi


def sample_tool_points(robot, rng, count: int, progress=None):
    """``(Q (count, n), P (count, 3))``: joints drawn uniformly within
    :func:`joint_ranges` and their tool points (m, world), in chunks through the
    vectorised FK (``progress("sampling", done, count)`` after each)."""
    lo, hi = joint_ranges(robot)
    Q = np.empty((count, robot.dof))
    P = np.empty((count, 3))
    for start in range(0, count, CHUNK):
        stop = min(start + CHUNK, count)
        Q[start:stop] = rng.uniform(lo, hi, (stop - start, robot.dof))
        P[start:stop] = robot.fk(Q[start:stop])[:, :3, 3]
        if progress is not None:
            progress("sampling", stop, count)
    return Q, P


# --- the reach envelope ------------------------------------------------------

def _push(robot, X, direction, rounds: int = 40):
    """Move each configuration as far as it goes along ``direction(P) -> (B, 3)`` unit
    vectors, by damped least squares towards a goal one robot length beyond the
    tool point along that direction, repeated until the tool stops moving.
    Returns the final configurations ``(B, n)``."""
    L = max(robot.characteristic_length, 1e-12)
    for _ in range(rounds):
        P = robot.fk(X)[:, :3, 3]
        u = direction(P)
        X_new, _, _ = descend(robot, X, P + L * u, iterations=8, tol=0.0)
        moved = np.linalg.norm(robot.fk(X_new)[:, :3, 3] - P, axis=1)
        X = X_new
        if np.all(moved < 1e-12 * L):
            break
    return X


def envelope(robot, Q, P, keep: int = 16) -> dict:
    """Reach envelope from samples ``Q (N, n)`` with tool points ``P (N, 3)``,
    refined from the ``keep`` best samples of each extreme.

    Returns SI values ``{min_distance, max_distance, z_min, z_max}`` (m, from the
    base frame's origin, world z) and the joints where each is attained.
    """
    o = robot.base[:3, 3]
    d = np.linalg.norm(P - o, axis=1)
    z = P[:, 2]
    ez = np.array([0.0, 0.0, 1.0])

    def outward(Pc):
        v = Pc - o
        return v / np.maximum(np.linalg.norm(v, axis=1, keepdims=True), 1e-300)

    out = {}
    for name, values, sign, direction in (
            ("max_distance", d, 1, outward),
            ("min_distance", d, -1, None),
            ("z_max", z, 1, lambda Pc: np.broadcast_to(ez, Pc.shape)),
            ("z_min", z, -1, lambda Pc: np.broadcast_to(-ez, Pc.shape))):
        best = np.argsort(-sign * values)[:keep]
        if name == "min_distance":   # a least-squares problem itself: the goal is the origin
            X = descend(robot, Q[best], o, iterations=300)[0]
        else:
            X = _push(robot, Q[best], direction)
        Pr = robot.fk(X)[:, :3, 3]
        vr = np.linalg.norm(Pr - o, axis=1) if name.endswith("distance") else Pr[:, 2]
        k = int(np.argmax(sign * vr))
        # never worse than the samples themselves
        if sign * vr[k] >= sign * values[best[0]]:
            out[name], out[name + "_q"] = float(vr[k]), X[k]
        else:
            out[name], out[name + "_q"] = float(values[best[0]]), Q[best[0]]
    return out


# --- the grid ----------------------------------------------------------------

@dataclass
class Grid:
    """Cells of edge ``h`` (m) over coordinates ``U = (P - origin) @ basis``."""

    origin: np.ndarray
    basis: np.ndarray
    lo: np.ndarray
    h: float
    shape: tuple

    @property
    def dim(self) -> int:
        return self.basis.shape[1]

    def coords(self, P):
        return (P - self.origin) @ self.basis

    def cell(self, P) -> np.ndarray:
        """``(N, d)`` integer cell indices of points ``P (N, 3)``."""
        return np.floor((self.coords(P) - self.lo) / self.h).astype(np.int64)

    def flat(self, idx) -> np.ndarray:
        return np.ravel_multi_index(tuple(np.asarray(idx).T), self.shape, mode="clip")

    def point(self, idx, frac) -> np.ndarray:
        """World points at fractional positions ``frac (N, d)`` in cells ``idx (N, d)``."""
        return self.origin + (self.lo + (idx + frac) * self.h) @ self.basis.T


def _make_grid(P, robot, per_cell=SAMPLES_PER_CELL) -> Grid:
    origin, basis = motion_frame(P, robot)
    U = (P - origin) @ basis
    d = basis.shape[1]
    lo, hi = U.min(axis=0), U.max(axis=0)
    extent = np.maximum(hi - lo, 1e-9 * max(robot.characteristic_length, 1e-12))
    h = float((np.prod(extent) * per_cell / len(P)) ** (1.0 / d))
    for _ in range(2):   # resize for the occupied fraction, which is not known up front
        shape = tuple(int(x) for x in np.ceil(extent / h) + 3)
        g = Grid(origin, basis, lo - h, h, shape)
        occupied = np.unique(g.flat(g.cell(P))).size
        h *= (per_cell * occupied / len(P)) ** (1.0 / d)
    shape = tuple(int(x) for x in np.ceil(extent / h) + 3)
    return Grid(origin, basis, lo - h, h, shape)


def _neighbourhood(mask, fn):
    """Reduce ``mask`` over each cell's 3^d neighbourhood with ``fn`` (all or any)."""
    d = mask.ndim
    out = mask.copy()
    padded = np.pad(mask, 1, constant_values=False)
    for off in np.ndindex(*(3,) * d):
        view = padded[tuple(slice(o, o + s) for o, s in zip(off, mask.shape))]
        out = fn(out, view)
    return out


def wilson(k: int, m: int, z: float = Z95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion ``k / m``."""
    if m == 0:
        return 0.0, 1.0
    p = k / m
    den = 1 + z * z / m
    mid = (p + z * z / (2 * m)) / den
    half = z * np.sqrt(p * (1 - p) / m + z * z / (4 * m * m)) / den
    return max(0.0, mid - half), min(1.0, mid + half)


def _starts(grid, order, sorted_cells, targets, per_cell=3):
    """Indices into the samples of candidate starts near each target point:
    up to ``per_cell`` samples from each cell of the target's 3^d neighbourhood.

    Returns ``(M, K)`` sample indices, -1 where a neighbour cell is empty."""
    tc = grid.cell(targets)
    cand = []
    for off in np.ndindex(*(3,) * grid.dim):
        c = grid.flat(np.clip(tc + np.array(off) - 1, 0, np.array(grid.shape) - 1))
        first = np.searchsorted(sorted_cells, c, side="left")
        last = np.searchsorted(sorted_cells, c, side="right")
        for k in range(per_cell):
            j = first + k
            ok = j < last
            cand.append(np.where(ok, order[np.minimum(j, len(order) - 1)], -1))
    return np.stack(cand, axis=1)


def _reached(robot, Q, P, cand, targets, R_goal=None, Rc=None, tries=3, exact=False):
    """``(M,)`` bool: does the robot reach each target (position, and orientation
    ``R_goal (M, 3, 3)`` if given)? ``cand (M, K)`` are candidate starts (sample
    indices, -1 for none), ``Rc (M, K, 3, 3)`` their orientations when ``R_goal``
    is given. Starts from the nearest candidate (in position, plus orientation);
    the next candidates only where the first failed. ``exact``: poses go through
    :meth:`Robot.ik_batch` instead (see :func:`_batchable`)."""
    M = len(targets)
    L = max(robot.characteristic_length, 1e-12)
    if R_goal is not None and exact:
        # the closed form is exact: no start to choose, no branch to miss
        T = np.zeros((M, 4, 4))
        T[:, :3, :3], T[:, :3, 3], T[:, 3, 3] = R_goal, targets, 1.0
        sol = robot.ik_batch(T)
        return np.any(sol.valid & sol.within, axis=1)
    safe = np.maximum(cand, 0)
    cost = np.linalg.norm(P[safe] - targets[:, None, :], axis=2) / L
    if R_goal is not None:
        from ..spatial import rotation_error
        cost = cost + rotation_error(Rc, R_goal[:, None])
    cost[cand < 0] = np.inf
    order = np.argsort(cost, axis=1)
    hit = np.zeros(M, bool)
    for t in range(min(tries, cand.shape[1])):
        todo = np.flatnonzero(~hit & np.isfinite(cost[np.arange(M), order[:, t]]))
        if todo.size == 0:
            break
        start = Q[safe[todo, order[todo, t]]]
        _, pe, oe = descend(robot, start, targets[todo],
                            None if R_goal is None else R_goal[todo])
        ok = pe <= REACHED * L
        if oe is not None:
            ok &= oe <= REACHED
        hit[todo[ok]] = True
    return hit


def _batchable(robot) -> bool:
    """Does :meth:`Robot.ik_batch` cover this robot (a closed-form family)?"""
    from ..errors import UnsupportedRobot
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
    from ..spatial import matrix_from_quaternion
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


# --- the analysis --------------------------------------------------------------

@dataclass
class Workspace:
    """Result of :func:`analyse`; SI values (m, m^d, rad), world frame."""

    robot: object
    samples: int
    seed: int
    ranges: tuple
    envelope: dict
    dim: int
    volume: float
    volume_ci: tuple
    grid: dict
    dexterous: dict
    manipulability: dict
    sections: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)
    units: object = None

    def to_dict(self) -> dict:
        from .results import json_numbers, json_header
        u = self.units
        l, a = u.l, u.a
        e = self.envelope
        out = json_header("workspace", self.robot, u)
        vol_unit = {3: "volume", 2: "area", 1: "length"}[self.dim]
        out.update({
            "samples": self.samples,
            "seed": self.seed,
            "joint_ranges": [list(pair) for pair in zip(u.joints(self.robot, self.ranges[0]),
                                                        u.joints(self.robot, self.ranges[1]))],
            "envelope": {
                "min_distance": json_numbers(e["min_distance"] * l),
                "max_distance": json_numbers(e["max_distance"] * l),
                "z_min": json_numbers(e["z_min"] * l),
                "z_max": json_numbers(e["z_max"] * l),
                "at": {k: u.joints(self.robot, e[k + "_q"])
                       for k in ("min_distance", "max_distance", "z_min", "z_max")},
                "from": "base frame origin; z in the world frame",
            },
            "dimension": self.dim,
            "measure": vol_unit,
            "volume": json_numbers(self.volume * l ** self.dim),
            "volume_ci95": json_numbers(np.array(self.volume_ci) * l ** self.dim),
            "volume_unit": (u.length if self.dim == 1 or u.length == "unitless"
                            else f"{u.length}^{self.dim}"),
            "grid": {k: (json_numbers(v * l) if k == "cell" else v) for k, v in self.grid.items()},
            "dexterous": {k: (json_numbers(np.asarray(v) * l ** self.dim)
                              if k in ("volume", "volume_ci95") and v is not None else
                              json_numbers(v) if isinstance(v, float) else v)
                          for k, v in self.dexterous.items()},
            "manipulability": {k: json_numbers(v) if isinstance(v, float) else v
                               for k, v in self.manipulability.items()},
        })
        return out


def _manipulability(robot, Q, units) -> tuple[np.ndarray, dict]:
    """Per-sample Yoshikawa measure ``(N,)`` (as ``kincalc jacobian`` reports it, in
    display units) and statistics including the normalised condition number."""
    from ..tolerances import SINGULAR_TOL
    J = robot.jacobian(Q)
    n = robot.dof
    full, _ = robot.generic_ranks
    Jd = J.copy()
    Jd[:, :3, :] *= np.where(robot.is_revolute, units.l, 1.0)
    if full == n:
        w = np.sqrt(np.abs(np.linalg.det(np.swapaxes(Jd, 1, 2) @ Jd)))
    elif full == 6:
        w = np.sqrt(np.abs(np.linalg.det(Jd @ np.swapaxes(Jd, 1, 2))))
    else:
        w = np.prod(np.linalg.svd(Jd, compute_uv=False)[:, :full], axis=1)
    L = robot.characteristic_length
    Jn = J[: min(len(J), CONDITION_SAMPLES)]
    Jn[:, :3, :] /= L
    Jn[:, :, ~robot.is_revolute] *= L
    s = np.linalg.svd(Jn, compute_uv=False)
    cond = s[:, 0] / np.maximum(s[:, full - 1], 1e-300)
    singular = s[:, full - 1] < SINGULAR_TOL * np.maximum(s[:, 0], 1.0)
    pct = np.percentile(w, [5, 50, 95])
    stats = {
        "measure": "Yoshikawa: product of the Jacobian's singular values up to its generic "
                   f"rank {full}, lengths in {units.length}",
        "min": float(w.min()), "p5": float(pct[0]), "median": float(pct[1]),
        "mean": float(w.mean()), "p95": float(pct[2]), "max": float(w.max()),
        "at_max": units.joints(robot, Q[int(np.argmax(w))]),
        "condition_median": float(np.median(cond)),
        "condition_p95": float(np.percentile(cond, 95)),
        "near_singular_fraction": float(np.mean(singular)),
        "samples": int(len(w)),
        "condition_samples": int(len(Jn)),
    }
    return w, stats


def analyse(robot, samples: int = 200_000, seed: int = 0, *, units=None,
            dexterity: float = 1.0, orientations: int | None = None,
            sections: bool = False, progress=None) -> Workspace:
    """Monte-Carlo workspace analysis of ``robot`` (see the module docstring).

    ``samples`` joint configurations drawn with ``numpy.random.default_rng(seed)``;
    ``dexterity`` in (0, 1]: the fraction of test orientations a point must reach
    to count as dexterous; ``orientations``: how many test orientations (default
    48 for SO(3), 24 for one angle). ``sections=True`` also builds the XY and XZ
    sections for plotting. ``progress(stage, done, total)`` is called as work
    proceeds.

    Raises
    ------
    BadValue
        ``samples`` outside 1000 ... :data:`~kincalc.limits.MAX_SAMPLES` (every sample's
        joints and tool point are kept: the grid, the envelope and the starts of the
        boundary tests index them), a ``seed`` that is not a non-negative integer,
        ``orientations`` beyond :data:`~kincalc.limits.MAX_ORIENTATIONS`, ``dexterity``
        outside (0, 1], or a prismatic joint without limits.
    """
    import time

    from .results import Units
    units = units or Units(length=robot.length_unit)
    if not 1000 <= samples <= MAX_SAMPLES:
        raise BadValue("samples", f"from 1000 to {MAX_SAMPLES} (kincalc's limit)", samples)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise BadValue("seed", "a non-negative integer", seed)
    if orientations is not None and not 2 <= orientations <= MAX_ORIENTATIONS:
        raise BadValue("orientations", f"from 2 to {MAX_ORIENTATIONS} (kincalc's limit)",
                       orientations)
    if not 0.0 < dexterity <= 1.0:
        raise BadValue("dexterity", "a fraction in (0, 1]", dexterity)
    progress = progress or (lambda *a: None)
    rng = np.random.default_rng(seed)
    lo, hi = joint_ranges(robot)
    times = {}

    t0 = time.perf_counter()
    Q, P = sample_tool_points(robot, rng, samples, progress)
    times["sampling"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    env = envelope(robot, Q, P)
    times["envelope"] = time.perf_counter() - t0

    # --- volume ------------------------------------------------------------
    t0 = time.perf_counter()
    grid = _make_grid(P, robot)
    cells = grid.flat(grid.cell(P))
    order = np.argsort(cells, kind="stable")
    sorted_cells = cells[order]
    occupied = np.zeros(grid.shape, bool)
    occupied.flat[np.unique(cells)] = True
    inside = _neighbourhood(occupied, np.logical_and)
    near = _neighbourhood(occupied, np.logical_or)
    band = near & ~inside
    band_idx = np.argwhere(band)
    m = BAND_POINTS
    pick = band_idx[rng.integers(0, len(band_idx), m)]
    targets = grid.point(pick, rng.uniform(size=(m, grid.dim)))
    cand = _starts(grid, order, sorted_cells, targets)
    progress("volume", 0, 1)
    hit = _reached(robot, Q, P, cand, targets)
    progress("volume", 1, 1)
    cell_v = grid.h ** grid.dim
    n_in, n_band = int(inside.sum()), int(band.sum())
    k = int(hit.sum())
    f_lo, f_hi = wilson(k, m)
    volume = cell_v * (n_in + n_band * k / m)
    volume_ci = (cell_v * (n_in + n_band * f_lo), cell_v * (n_in + n_band * f_hi))
    times["volume"] = time.perf_counter() - t0
    grid_info = {"cell": grid.h, "cells_inside": n_in, "cells_band": n_band,
                 "band_points": m, "band_points_inside": k,
                 "method": "grid of cells sized for about "
                           f"{SAMPLES_PER_CELL} samples each; inside cells counted whole, "
                           "the boundary band by hit-or-miss with damped least squares; "
                           "95 % Wilson interval"}

    # --- dexterity -----------------------------------------------------------
    t0 = time.perf_counter()
    dex = _dexterous(robot, rng, grid, Q, P, order, sorted_cells, inside | band,
                     volume, volume_ci, dexterity, orientations, units, progress)
    times["dexterous"] = time.perf_counter() - t0

    # --- manipulability --------------------------------------------------------
    t0 = time.perf_counter()
    sub = Q[: min(samples, MANIPULABILITY_SAMPLES)]
    w, manip = _manipulability(robot, sub, units)
    times["manipulability"] = time.perf_counter() - t0

    secs = _sections(grid, P[: len(sub)], w, robot, env) if sections else []
    return Workspace(robot=robot, samples=samples, seed=seed, ranges=(lo, hi), envelope=env,
                     dim=grid.dim, volume=volume, volume_ci=volume_ci, grid=grid_info,
                     dexterous=dex, manipulability=manip, sections=secs, timings=times,
                     units=units)


def _dexterous(robot, rng, grid, Q, P, order, sorted_cells, region, volume, volume_ci,
               fraction, count, units, progress) -> dict:
    """The dexterous workspace: random points of ``region`` (cells), each tested with
    every orientation of a fixed set. Its volume is the reachable ``volume`` times the
    share of the reachable test points that are dexterous (a ratio, so it never
    exceeds the reachable volume), with Wilson's interval on that share."""
    kind, extra = _orientation_family(robot)
    if kind is None:
        return {"defined": False, "reason": extra, "volume": None, "volume_ci95": None}
    if kind == "SO(3)":
        count = count or ORIENTATIONS_3D
        Rset = super_fibonacci(count)
        about = f"{count} near-uniform orientations (super-Fibonacci spiral)"
    else:
        count = count or ORIENTATIONS_1D
        from ..spatial import matrix_from_axis_angle
        R0 = robot.fk(Q[0])[:3, :3]
        angles = 2 * np.pi * np.arange(count) / count
        Rset = matrix_from_axis_angle(np.broadcast_to(extra, (count, 3)), angles) @ R0
        about = (f"{count} tool angles {2 * np.pi / count * units.a:.4g} {units.angle} apart "
                 f"about the axis {np.round(extra, 6).tolist()}")
    exact = _batchable(robot)
    m = DEXTERITY_POINTS
    cells = np.argwhere(region)
    pick = cells[rng.integers(0, len(cells), m)]
    targets = grid.point(pick, rng.uniform(size=(m, grid.dim)))
    cand = _starts(grid, order, sorted_cells, targets, per_cell=4)
    Rs = robot.fk(Q[np.maximum(cand, 0)].reshape(-1, robot.dof))[:, :3, :3].reshape(
        cand.shape + (3, 3))
    progress("dexterity", 0, 2)
    reachable = _reached(robot, Q, P, cand, targets)
    progress("dexterity", 1, 2)
    # every (point, orientation) pair of the reachable points, PAIR_CHUNK pairs at a time
    # (each pair is solved on its own: the chunks change nothing but the memory)
    K = len(Rset)
    at = np.flatnonzero(reachable)
    hit = np.zeros((len(at), K), bool)
    step = max(1, PAIR_CHUNK // K)
    for s in range(0, len(at), step):
        a = at[s:s + step]
        hit[s:s + len(a)] = _reached(
            robot, Q, P, np.repeat(cand[a], K, axis=0), np.repeat(targets[a], K, axis=0),
            R_goal=np.tile(Rset, (len(a), 1, 1)), Rc=np.repeat(Rs[a], K, axis=0),
            exact=exact).reshape(len(a), K)
    progress("dexterity", 2, 2)
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


def _sections(grid, P, w, robot, env) -> list:
    """XY and XZ sections (one for a planar arm): per-cell mean manipulability of the
    samples in a slab one cell thick, NaN where no sample falls."""
    out = []
    U = grid.coords(P)
    idx = np.floor((U - grid.lo) / grid.h).astype(int)
    d = grid.dim

    def image(ax_u, ax_v, keep):
        H, W = grid.shape[ax_v], grid.shape[ax_u]
        total = np.zeros(H * W)
        count = np.zeros(H * W)
        flat = idx[keep, ax_v] * W + idx[keep, ax_u]
        np.add.at(total, flat, w[keep])
        np.add.at(count, flat, 1)
        img = np.where(count > 0, total / np.maximum(count, 1), np.nan).reshape(H, W)
        ext = (grid.lo[ax_u], grid.lo[ax_u] + W * grid.h, grid.lo[ax_v], grid.lo[ax_v] + H * grid.h)
        return img, ext

    if d == 3:
        # the XY section through the widest layer, the XZ section through the base origin
        layers = np.bincount(idx[:, 2], minlength=grid.shape[2])
        kz = int(np.argmax(layers))
        img, ext = image(0, 1, idx[:, 2] == kz)
        zc = grid.lo[2] + (kz + 0.5) * grid.h
        out.append({"title": f"XY section at z = {zc:.4g} m", "xlabel": "x", "ylabel": "y",
                    "extent": ext, "grid": img, "name": "XY", "across": "z", "level": zc})
        ky = int(np.floor((robot.base[1, 3] - grid.lo[1]) / grid.h))
        img, ext = image(0, 2, idx[:, 1] == ky)
        yc = grid.lo[1] + (ky + 0.5) * grid.h
        out.append({"title": f"XZ section at y = {yc:.4g} m", "xlabel": "x", "ylabel": "z",
                    "extent": ext, "grid": img, "name": "XZ", "across": "y", "level": yc})
    elif d == 2:
        img, ext = image(0, 1, np.ones(len(P), bool))
        out.append({"title": "the plane of motion", "xlabel": "u" if grid.basis[2].any() else "x",
                    "ylabel": "v" if grid.basis[2].any() else "y", "extent": ext, "grid": img})
    return out
