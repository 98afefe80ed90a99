"""The reachable volume: the grid of sampled tool points, the band's hit-or-miss
membership tests and the Wilson interval; see :mod:`kincalc.analysis.workspace`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...ik.nearest import descend, motion_frame

#: mean samples per occupied grid cell the grid is sized for
SAMPLES_PER_CELL = 24
#: hit-or-miss points in the boundary band (volume) and test points (dexterity)
BAND_POINTS = 3000
#: a point counts as reached when damped least squares gets within this of it
#: (relative to the robot's characteristic length; rad for orientation)
REACHED = 1e-7
#: z for 95 % two-sided intervals
Z95 = 1.959963984540054


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


def make_grid(P, robot, per_cell=SAMPLES_PER_CELL) -> Grid:
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


def neighbourhood(mask, fn):
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


def starts(grid, order, sorted_cells, targets, per_cell=3):
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


def reached(robot, Q, P, cand, targets, R_goal=None, Rc=None, tries=3, exact=False):
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
        from ...spatial import rotation_error
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


@dataclass(frozen=True)
class Volume:
    """The volume estimate of :func:`estimate_volume` (m^3, or m^2 for a planar arm) with
    its 95 % interval, the grid it was counted on, the samples sorted by cell (``order``,
    ``sorted_cells``: for the starts of later searches), the cells inside or on the
    boundary band (``reachable``, the grid's shape), and the method's figures (``info``)."""

    volume: float
    volume_ci: tuple
    grid: Grid
    order: np.ndarray
    sorted_cells: np.ndarray
    reachable: np.ndarray
    info: dict


def estimate_volume(robot, rng, Q, P, progress) -> Volume:
    """The reachable volume from the samples ``Q (N, n)`` and their tool points ``P (N,
    d)``: cells holding samples with all neighbours occupied count whole; the band of
    cells around them by hit-or-miss of ``BAND_POINTS`` random points, each searched from
    the nearest samples with damped least squares (:func:`reached`)."""
    grid = make_grid(P, robot)
    cells = grid.flat(grid.cell(P))
    order = np.argsort(cells, kind="stable")
    sorted_cells = cells[order]
    occupied = np.zeros(grid.shape, bool)
    occupied.flat[np.unique(cells)] = True
    inside = neighbourhood(occupied, np.logical_and)
    near = neighbourhood(occupied, np.logical_or)
    band = near & ~inside
    band_idx = np.argwhere(band)
    m = BAND_POINTS
    pick = band_idx[rng.integers(0, len(band_idx), m)]
    targets = grid.point(pick, rng.uniform(size=(m, grid.dim)))
    cand = starts(grid, order, sorted_cells, targets)
    progress("volume", 0, 1)
    hit = reached(robot, Q, P, cand, targets)
    progress("volume", 1, 1)
    cell_v = grid.h ** grid.dim
    n_in, n_band = int(inside.sum()), int(band.sum())
    k = int(hit.sum())
    f_lo, f_hi = wilson(k, m)
    info = {"cell": grid.h, "cells_inside": n_in, "cells_band": n_band,
            "band_points": m, "band_points_inside": k,
            "method": "grid of cells sized for about "
                      f"{SAMPLES_PER_CELL} samples each; inside cells counted whole, "
                      "the boundary band by hit-or-miss with damped least squares; "
                      "95 % Wilson interval"}
    return Volume(cell_v * (n_in + n_band * k / m),
                  (cell_v * (n_in + n_band * f_lo), cell_v * (n_in + n_band * f_hi)),
                  grid, order, sorted_cells, inside | band, info)
