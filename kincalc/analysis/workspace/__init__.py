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
  (:func:`~kincalc.ik.nearest.descend`). The interval is the binomial (Wilson) interval of that
  fraction, given the grid assumptions (inside cells are wholly inside,
  outside cells wholly outside), which hold when the sampling is dense
  enough for the grid, the reason for the samples-per-cell rule;
* the **dexterous workspace** (Craig, *Introduction to Robotics*, sec. 4.3:
  the positions the tool reaches with every orientation; here every one of a
  fixed near-uniform set of test orientations, or a stated fraction of them):
  random points of the reachable set, each tested with each orientation by
  :func:`~kincalc.ik.nearest.descend`; its volume is the dexterous fraction of the reachable
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

from ...errors import BadValue, UnsupportedRobot
from ...limits import MAX_ORIENTATIONS, MAX_SAMPLES
from .dexterity import dexterous, super_fibonacci, test_orientations
from .sampling import envelope, joint_ranges, sample_tool_points
from .sections import Section, workspace_sections
from .volume import estimate_volume, wilson

__all__ = ["Section", "Workspace", "analyse", "envelope", "joint_ranges",
           "manipulability_unit", "sample_tool_points", "super_fibonacci", "wilson",
           "workspace_sections"]

#: samples the manipulability statistics use (the first ones drawn), and the
#: condition-number statistics (an SVD each)
MANIPULABILITY_SAMPLES = 200_000
CONDITION_SAMPLES = 50_000


# --- the analysis --------------------------------------------------------------

@dataclass(frozen=True)
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
        from ..results import json_numbers, json_header
        u = self.units
        l = u.l
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


def manipulability_unit(robot, units) -> str:
    """The unit of the manipulability the analysis reports (``"m^3"`` for a six-joint
    revolute arm in m): its linear rows are length per radian for revolute joints and
    pure numbers for prismatic ones, so the product of the singular values up to the
    generic rank is a length to the power of the position rank less the number of
    prismatic joints (one of them per linear direction); "" for a pure number or
    unitless lengths."""
    power = robot.generic_ranks[1] - int(np.sum(~robot.is_revolute))
    if power <= 0 or units.length == "unitless":
        return ""
    return units.length if power == 1 else f"{units.length}^{power}"


def _manipulability(robot, Q, units) -> tuple[np.ndarray, dict]:
    """Per-sample Yoshikawa measure ``(N,)`` (as ``kincalc jacobian`` reports it, in
    display units) and statistics including the normalised condition number."""
    from ...tolerances import SINGULAR_TOL
    from ...jacobian import scale_free
    from ..results import display_jacobian
    J = robot.jacobian(Q)
    n = robot.dof
    full, _ = robot.generic_ranks
    Jd = display_jacobian(robot, J, units)
    if full == n:
        w = np.sqrt(np.abs(np.linalg.det(np.swapaxes(Jd, 1, 2) @ Jd)))
    elif full == 6:
        w = np.sqrt(np.abs(np.linalg.det(Jd @ np.swapaxes(Jd, 1, 2))))
    else:
        w = np.prod(np.linalg.svd(Jd, compute_uv=False)[:, :full], axis=1)
    L = robot.characteristic_length
    Jn = scale_free(J[: min(len(J), CONDITION_SAMPLES)], robot.is_revolute, L)
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


def _single_point(robot, lo, hi) -> str:
    """Why no joint moves the tool point (the joints' ranges ``lo``, ``hi``: rad / m)."""
    why = ("every joint's limits are one value" if np.all(hi - lo <= 0.0) else
           "every axis passes through it, or the joints that would move it are held by "
           "their limits")
    return f"{robot.name}: no joint moves the tool point ({why}): the workspace is a single point"


def analyse(robot, samples: int = 200_000, seed: int = 0, *, units=None,
            dexterity: float = 1.0, orientations: int | None = None,
            sections: bool = False, progress=None) -> Workspace:
    """Monte-Carlo workspace analysis of ``robot`` (see the module docstring).

    ``samples`` joint configurations drawn with ``numpy.random.default_rng(seed)``;
    ``dexterity`` in (0, 1]: the fraction of test orientations a point must reach
    to count as dexterous; ``orientations``: how many test orientations (default
    48 for SO(3), 24 for one angle). ``sections=True`` also builds the sections for
    drawing (:mod:`~.sections`: through the base axis and through the shoulder).
    ``progress(stage, done, total)`` is called as work proceeds.

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

    from ..results import Units
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
    if np.ptp(P, axis=0).max() <= 1e-9 * max(robot.characteristic_length, 1e-12):
        # (a grid sized to the samples' spread would be sized to rounding: no volume)
        raise UnsupportedRobot(_single_point(robot, lo, hi))

    t0 = time.perf_counter()
    env = envelope(robot, Q, P)
    times["envelope"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    vol = estimate_volume(robot, rng, Q, P, progress)
    times["volume"] = time.perf_counter() - t0
    grid, volume, volume_ci = vol.grid, vol.volume, vol.volume_ci

    # --- dexterity -----------------------------------------------------------
    t0 = time.perf_counter()
    dex = dexterous(robot, rng, grid, Q, P, vol.order, vol.sorted_cells, vol.reachable,
                    volume, volume_ci, dexterity, orientations, units, progress)
    times["dexterous"] = time.perf_counter() - t0

    # --- manipulability --------------------------------------------------------
    t0 = time.perf_counter()
    sub = Q[: min(samples, MANIPULABILITY_SAMPLES)]
    w, manip = _manipulability(robot, sub, units)
    times["manipulability"] = time.perf_counter() - t0

    secs = []
    if sections:
        t0 = time.perf_counter()
        tests = test_orientations(robot, Q, orientations, units) if dex["defined"] else None
        secs = workspace_sections(robot, rng, sub, P[: len(sub)], w, vol, tests, dexterity,
                                  progress)
        times["sections"] = time.perf_counter() - t0
    return Workspace(robot=robot, samples=samples, seed=seed, ranges=(lo, hi), envelope=env,
                     dim=grid.dim, volume=volume, volume_ci=volume_ci, grid=vol.info,
                     dexterous=dex, manipulability=manip, sections=secs, timings=times,
                     units=units)
