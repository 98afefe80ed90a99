"""kincalc's batched IK against the solvers users would otherwise pick: time and solution sets.

    python benchmarks/peers.py [--poses 100000] [--robots ur5 puma560] [--repeat 3]
                               [--per-pose-subset 5000] [--rtb-subset 1000]

Peers, each used when installed (``pip install '.[bench]'``; a missing one is
named in the output and skipped):

- EAIK (``EAIK`` on PyPI): ``Robot(H, P, R6T).calculate_IK_batched`` (C++,
  timed with 1 and with 2 worker threads);
- ik-geo (``ik-geo``): ``Robot.<family>(H, P).get_ik`` (Rust), per pose only;
- Robotics Toolbox for Python (``roboticstoolbox-python[ik]``):
  ``DHRobot.analytic_ik().solve`` (all solutions of one pose) and, for the
  Puma 560, ``models.DH.Puma560.ikine_a`` (one arm configuration per call,
  called for each of the 8).

Every peer is given the robot from kincalc's own model: EAIK and ik-geo the
joint axes ``H`` and offsets ``P`` of the product-of-exponentials form at
q = 0 (the points of consecutive intersecting axes moved to the intersection,
as IK-Geo's decompositions expect) and the tool orientation at q = 0; the
toolbox a ``DHRobot`` built from the robot file's DH table. Each description
is checked against kincalc's FK before use, and the toolbox's own models are
compared with the bundled file, in the output.

Poses: 90 % from kincalc FK of random joint values (``--poses`` in all), 10 %
random poses (position uniform in a ball of 1.1 x the reach, uniform random
orientation), which are mostly unreachable or have fewer solutions; shuffled
together so that a subset holds both kinds in proportion.

Timing: median over ``--repeat`` runs of the time per pose, in one process,
OMP/OpenBLAS threads set to 1. kincalc and EAIK run over all poses; per-pose
APIs over the first ``--per-pose-subset`` poses (the toolbox: ``--rtb-subset``,
and a quarter of it for ikine_a). The reference is one vectorised numpy FK of
the N seed configurations, written here from H and P without kincalc: dividing
by it makes the numbers comparable across machines.

Solution sets: each returned joint vector is checked by kincalc FK; it is
*exact* when it reproduces the pose to POSITION_TOL m and ORIENTATION_TOL rad.
Sets are compared joint vector by joint vector, modulo 2 pi, at MATCH_TOL rad.
"""

import argparse
import os
import platform
import statistics
import time
from dataclasses import dataclass, field
from datetime import date
from importlib import metadata

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import kincalc  # noqa: E402
from kincalc.ik.families import plan  # noqa: E402
from kincalc.ik.screws import Screws  # noqa: E402
from kincalc.ik.selftest import sample_configurations  # noqa: E402

#: a returned joint vector reproduces the pose if kincalc FK lands within these
POSITION_TOL = 1e-6       # m
ORIENTATION_TOL = 1e-6    # rad
#: two joint vectors are the same solution if every joint agrees to this, modulo 2 pi
MATCH_TOL = 1e-6          # rad (m for a prismatic joint)
#: the same, loose: tells solvers' rounding near a singularity from a different solution
LOOSE_MATCH_TOL = 1e-4
#: a peer's description of the robot must give kincalc's FK to this
DESCRIPTION_TOL = 1e-9
#: share of the poses drawn at random instead of from FK
RANDOM_SHARE = 0.1
#: poses per chunk when comparing sets (bounds the (chunk, K, K, n) arrays)
CHUNK = 4000


# --- the robot, as the peers take it --------------------------------------------------

def poe_description(robot):
    """``H (n, 3)``, ``P (n + 1, 3)`` and ``R_6T (3, 3)`` of ``robot`` at q = 0.

    ``T(q) = [prod_i Rot(H_i, q_i)] [R_6T | .]`` with position
    ``P_0 + R_01 P_1 + ... + R_0n P_n`` (IK-Geo's convention, world frame, m).
    The points of consecutive intersecting axes are moved to their
    intersection, so that ``P_i = 0`` there, as IK-Geo's families require.
    """
    S = Screws.of(robot)
    H, pts = S.axis.copy(), S.point.copy()
    for i in range(len(H) - 1):
        c = np.cross(H[i], H[i + 1])
        if np.linalg.norm(c) < 1e-9:
            continue                      # parallel: no intersection
        d = pts[i + 1] - pts[i]
        if abs(d @ c) / np.linalg.norm(c) > 1e-9 * S.scale:
            continue                      # skew lines
        s = np.linalg.lstsq(np.stack([H[i], -H[i + 1]], 1), d, rcond=None)[0]
        pts[i] = pts[i + 1] = pts[i] + s[0] * H[i]
    P = np.vstack([pts[:1], np.diff(pts, axis=0), S.M[:3, 3] - pts[-1]])
    return H, P, S.M[:3, :3].copy()


def axis_rotations(h, q):
    """Rodrigues: rotations ``(N, 3, 3)`` by ``q (N,)`` about the unit axis ``h (3,)``."""
    K = np.array([[0, -h[2], h[1]], [h[2], 0, -h[0]], [-h[1], h[0], 0]])
    s, c = np.sin(q)[:, None, None], np.cos(q)[:, None, None]
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def numpy_fk(H, P, R6T, revolute, Q):
    """Reference FK without kincalc: rotations ``(N, 3, 3)``, positions ``(N, 3)`` (m).

    ``Q (N, n)`` in rad (revolute) or m (prismatic: a slide along ``H_i``).
    """
    R = np.broadcast_to(np.eye(3), (len(Q), 3, 3))
    p = np.broadcast_to(P[0], (len(Q), 3))
    for i in range(len(H)):
        if revolute[i]:
            R = R @ axis_rotations(H[i], Q[:, i])
        else:
            p = p + (R @ H[i]) * Q[:, i, None]
        p = p + R @ P[i + 1]
    return R @ R6T, p


# --- poses ----------------------------------------------------------------------------

def random_rotations(n, rng):
    """Uniformly distributed rotations ``(n, 3, 3)`` (normalised Gaussian quaternions)."""
    w, x, y, z = rng.standard_normal((4, n))
    s = np.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / s, x / s, y / s, z / s
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], -2)


@dataclass(frozen=True)
class Poses:
    T: np.ndarray          # (N, 4, 4) world <- tool, m
    seed: np.ndarray       # (N, n) joint values that made the pose; NaN for random poses
    from_fk: np.ndarray    # (N,) bool


def make_poses(robot, n, rng):
    """``n`` poses, shuffled: FK of random joints and ``RANDOM_SHARE`` random poses."""
    n_rand = int(round(n * RANDOM_SHARE))
    Q = sample_configurations(robot, n - n_rand, rng)
    T_fk = robot.fk(Q)
    centre = poe_description(robot)[1][0]          # on the first axis (the shoulder)
    reach = np.linalg.norm(T_fk[:, :3, 3] - centre, axis=1).max()
    u = rng.standard_normal((n_rand, 3))
    u *= (1.1 * reach * rng.uniform(0, 1, n_rand) ** (1 / 3) / np.linalg.norm(u, axis=1))[:, None]
    T_rand = np.broadcast_to(np.eye(4), (n_rand, 4, 4)).copy()
    T_rand[:, :3, :3] = random_rotations(n_rand, rng)
    T_rand[:, :3, 3] = centre + u
    order = rng.permutation(n)
    T = np.concatenate([T_fk, T_rand])[order]
    seed = np.concatenate([Q, np.full((n_rand, robot.dof), np.nan)])[order]
    from_fk = np.concatenate([np.ones(n - n_rand, bool), np.zeros(n_rand, bool)])[order]
    return Poses(T, seed, from_fk)


# --- solution sets --------------------------------------------------------------------

@dataclass
class Sets:
    """One solver's answers on the first ``len(q)`` poses, padded to K slots."""

    name: str
    q: np.ndarray           # (M, K, n)
    returned: np.ndarray    # (M, K) bool: a joint vector was returned in this slot
    flagged: np.ndarray     # (M, K) bool: the solver labelled it least-squares / failed
    flag_meaning: str = "least-squares flag"
    pos_err: np.ndarray = field(default=None)   # (M, K) m, NaN where not returned
    rot_err: np.ndarray = field(default=None)   # (M, K) rad

    @property
    def exact(self):
        return self.returned & (self.pos_err <= POSITION_TOL) & (self.rot_err <= ORIENTATION_TOL)


def pad(lists, n):
    """Lists (per pose) of ``(q (m, n), flags (m,))`` -> padded ``q``, ``returned``, ``flagged``."""
    K = max([len(q) for q, _ in lists] + [1])
    Q = np.zeros((len(lists), K, n))
    ret = np.zeros((len(lists), K), bool)
    flag = np.zeros((len(lists), K), bool)
    for i, (q, f) in enumerate(lists):
        m = len(q)
        if m:
            Q[i, :m], ret[i, :m], flag[i, :m] = q, True, f
    return Q, ret, flag


def pose_errors(robot, T, sets):
    """Fill ``sets.pos_err`` (m) and ``sets.rot_err`` (rad) by kincalc FK."""
    M, K, n = sets.q.shape
    q = np.where(sets.returned[..., None], sets.q, 0.0)
    Tq = robot.fk(np.nan_to_num(q).reshape(-1, n)).reshape(M, K, 4, 4)
    pe = np.linalg.norm(Tq[..., :3, 3] - T[:M, None, :3, 3], axis=-1)
    # angle of R_a^T R_b from the chordal distance: exact, and accurate near zero
    chord = np.linalg.norm(Tq[..., :3, :3] - T[:M, None, :3, :3], axis=(-2, -1))
    re = 2 * np.arcsin(np.minimum(chord / np.sqrt(8), 1.0))
    bad = ~np.isfinite(q).all(-1)          # NaN joints miss by definition
    sets.pos_err = np.where(sets.returned, np.where(bad, np.inf, pe), np.nan)
    sets.rot_err = np.where(sets.returned, np.where(bad, np.inf, re), np.nan)


def joint_distance(a, b, revolute):
    """Max joint difference ``(..., Ka, Kb)`` of ``a (..., Ka, n)``, ``b (..., Kb, n)``, mod 2 pi."""
    d = a[..., :, None, :] - b[..., None, :, :]
    d = np.where(revolute, np.abs((d + np.pi) % (2 * np.pi) - np.pi), np.abs(d))
    return d.max(-1)


def found_in(a, a_ok, b, b_ok, revolute, tol=MATCH_TOL):
    """``(M, Ka)``: entry of ``a`` has a match in ``b`` (both masked), chunked over poses."""
    out = np.zeros(a_ok.shape, bool)
    for s in range(0, len(a), CHUNK):
        sl = slice(s, s + CHUNK)
        d = joint_distance(np.nan_to_num(a[sl]), np.nan_to_num(b[sl]), revolute)
        out[sl] = a_ok[sl] & np.any((d <= tol) & b_ok[sl][:, None, :], axis=-1)
    return out


def distinct_count(q, ok, revolute, tol=MATCH_TOL):
    """Distinct joint vectors per pose ``(M,)`` among ``q (M, K, n)`` where ``ok``."""
    K = q.shape[1]
    earlier = np.tril(np.ones((K, K), bool), -1)
    out = np.zeros(len(q), int)
    for s in range(0, len(q), CHUNK):
        sl = slice(s, s + CHUNK)
        d = joint_distance(np.nan_to_num(q[sl]), np.nan_to_num(q[sl]), revolute)
        dup = np.any((d <= tol) & ok[sl][:, None, :] & earlier, axis=-1)
        out[sl] = (ok[sl] & ~dup).sum(1)
    return out


# --- the solvers ----------------------------------------------------------------------

class Skip(Exception):
    """A peer cannot run here (not installed, or not for this robot); the message says why."""


def version(dist):
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return None


def timed(f, repeat, n):
    """Median over ``repeat`` runs of ``f()``'s time per pose (s); and its last result."""
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        ts.append((time.perf_counter() - t0) / n)
    return statistics.median(ts), out


def check_fk(name, fk, robot, rng):
    """Max deviation of a peer's FK ``fk(q) -> (4, 4)`` from kincalc's on 20 random q."""
    Q = sample_configurations(robot, 20, rng)
    dev = max(np.abs(fk(q) - robot.fk(q)).max() for q in Q)
    if not dev <= DESCRIPTION_TOL:
        raise Skip(f"{name}: its FK of the description differs from kincalc's by {dev:.1e}")
    return dev


class Peer:
    """A solver. ``prepare(robot, rng)`` describes the robot to it (or raises
    :class:`Skip`) and returns one line saying how; ``run(inputs(T))`` is what
    is timed; ``sets(T, robot)`` gives, per pose, ``(q (m, n), flags (m,))``."""

    name = ""             # package and version
    short = ""            # in the solution-set tables
    api = ""              # the call timed
    flag_meaning = "least-squares flag"
    timing_only = False   # same solver as the row before, another setting

    def prepare(self, robot, rng):
        raise NotImplementedError

    def sizes(self, N, args):
        """Poses to time and poses to compare sets on (each a prefix of the N)."""
        return N, N

    def inputs(self, T):
        return T

    def run(self, inputs):
        raise NotImplementedError

    def sets(self, T, robot):
        raise NotImplementedError


class EAIKPeer(Peer):
    def __init__(self, threads):
        self.threads = threads
        self.name = f"EAIK {version('EAIK')}"
        self.short = "EAIK"
        self.api = f"calculate_IK_batched, {threads} thread{'s' if threads > 1 else ''}"
        self.timing_only = threads != 1

    def prepare(self, robot, rng):
        try:
            from eaik.pybindings import EAIK
        except ImportError as e:
            raise Skip(f"EAIK: not installed ({e})") from None
        if not robot.is_revolute.all():
            raise Skip("EAIK: prismatic joints are not used in this benchmark")
        H, P, R6T = poe_description(robot)
        self.solver = EAIK.Robot(H.T.copy(), P.T.copy(), R6T, [], True)
        if not self.solver.has_known_decomposition():
            raise Skip(f"EAIK: no known decomposition for {robot.name}")
        dev = check_fk("EAIK", lambda q: np.asarray(self.solver.fwdkin(q)), robot, rng)
        return (f"Robot(H, P, R6T) from kincalc's POE form, family "
                f"{self.solver.get_kinematic_family()}; its FK agrees to {dev:.0e}")

    def run(self, T):
        return self.solver.calculate_IK_batched(list(T), self.threads)

    def sets(self, T, robot):
        res = self.run(T)
        return [(np.asarray(s.Q, float).reshape(-1, robot.dof), np.asarray(s.is_LS, bool))
                for s in res]


# ik-geo families by the kinematic structure kincalc finds (axes numbered from 1)
IKGEO_FAMILIES = (
    ("spherical_two_parallel", "spherical wrist 4-6, axes 2 || 3"),
    ("spherical_two_intersecting", "spherical wrist 4-6, axes 1 and 2 intersect"),
    ("spherical", "spherical wrist 4-6"),
    ("three_parallel_two_intersecting", "axes 2 || 3 || 4, axes 5 and 6 intersect"),
    ("three_parallel", "axes 2 || 3 || 4"),
)


def ikgeo_family(H, P):
    """The first IK-Geo family of ``IKGEO_FAMILIES`` that ``H, P`` (canonical) belong to."""
    par = [np.linalg.norm(np.cross(H[i], H[i + 1])) < 1e-9 for i in range(5)]
    meet = [not par[i] and np.linalg.norm(P[i + 1]) < 1e-12 for i in range(5)]
    spherical = meet[3] and meet[4]
    if spherical and par[1]:
        return IKGEO_FAMILIES[0]
    if spherical and meet[0]:
        return IKGEO_FAMILIES[1]
    if spherical:
        return IKGEO_FAMILIES[2]
    if par[1] and par[2] and meet[4]:
        return IKGEO_FAMILIES[3]
    if par[1] and par[2]:
        return IKGEO_FAMILIES[4]
    return None


class IKGeoPeer(Peer):
    def __init__(self):
        self.name = f"ik-geo {version('ik-geo')}"
        self.short = "ik-geo"
        self.api = "get_ik, per pose (timed on a subset)"

    def sizes(self, N, args):
        return min(N, args.per_pose_subset), N

    def prepare(self, robot, rng):
        try:
            import ik_geo
        except ImportError as e:
            raise Skip(f"ik-geo: not installed ({e})") from None
        if robot.dof != 6 or not robot.is_revolute.all():
            raise Skip("ik-geo: needs a 6R arm")
        H, P, self.R6T = poe_description(robot)
        fam = ikgeo_family(H, P)
        if fam is None:
            raise Skip(f"ik-geo: {robot.name} is none of the closed-form families used here")
        self.solver = getattr(ik_geo.Robot, fam[0])(H, P)

        # The binding reads a rotation column by column: it returns R^T from
        # forward_kinematics and must be given R^T (checked here against kincalc).
        def fk(q):
            R, t = self.solver.forward_kinematics(q)
            T = np.eye(4)
            T[:3, :3], T[:3, 3] = np.asarray(R).T @ self.R6T, t
            return T
        dev = check_fk("ik-geo", fk, robot, rng)
        return (f"Robot.{fam[0]}(H, P) ({fam[1]}), targets R R6T^T; the binding takes "
                f"and returns rotations transposed (we pass R^T); its FK agrees to {dev:.0e}")

    def inputs(self, T):
        Rt = np.ascontiguousarray(np.swapaxes(T[:, :3, :3] @ self.R6T.T, 1, 2))
        return [(Rt[i], T[i, :3, 3].copy()) for i in range(len(T))]

    def run(self, args):
        return [self.solver.get_ik(R, t) for R, t in args]

    def sets(self, T, robot):
        out = []
        for sols in self.run(self.inputs(T)):
            q = np.array([s[0] for s in sols], float).reshape(-1, robot.dof)
            out.append((q, np.array([s[1] for s in sols], bool)))
        return out


def rtb_dh_robot(robot):
    """A ``roboticstoolbox.DHRobot`` built from ``robot``'s standard DH table."""
    import roboticstoolbox as rtb
    from spatialmath import SE3
    if robot.convention != "dh" or not robot.is_revolute.all():
        raise Skip(f"rtb analytic_ik: needs a standard-DH arm of revolute joints ({robot.name}: "
                   f"{robot.convention}, joints {''.join(t[0].upper() for t in robot.joint_types)})")
    links = [rtb.RevoluteDH(a=j.a, d=j.d, alpha=j.alpha, offset=j.theta) for j in robot.joints]
    return rtb.DHRobot(links, name=robot.name, base=SE3(robot.base, check=False),
                       tool=SE3(robot.tool, check=False))


def rtb_model_note(robot):
    """Does the toolbox's own DH model of this robot match the bundled file? One line."""
    import roboticstoolbox as rtb
    models = {"ur5": "UR5", "ur3": "UR3", "ur10": "UR10", "puma560": "Puma560"}
    if robot.name not in models or robot.convention != "dh":
        return None
    m = getattr(rtb.models.DH, models[robot.name])()
    diffs = []
    for i, (link, j) in enumerate(zip(m.links, robot.joints), 1):
        for key, theirs, ours in (("a", link.a, j.a), ("d", link.d, j.d),
                                  ("alpha", link.alpha, j.alpha), ("offset", link.offset, j.theta)):
            if abs(theirs - ours) > 1e-12:
                diffs.append(f"{key}{i} {theirs:g} (kincalc {ours:g})")
    for what, A, B in (("base", m.base.A, robot.base), ("tool", m.tool.A, robot.tool)):
        if not np.allclose(A, B, atol=1e-12):
            diffs.append(f"{what} differs")
    head = f"rtb models.DH.{models[robot.name]}"
    return (f"{head} matches the bundled file" if not diffs else
            f"{head} differs from the bundled file: {', '.join(diffs)}; "
            "analytic_ik is given a DHRobot built from kincalc's table instead")


class RTBAnalyticPeer(Peer):
    def __init__(self):
        self.name = f"rtb {version('roboticstoolbox-python')}"
        self.short = "rtb analytic_ik"
        self.api = "analytic_ik().solve, per pose (subset)"

    def sizes(self, N, args):
        m = min(N, args.rtb_subset)
        return m, m

    def prepare(self, robot, rng):
        try:
            import roboticstoolbox  # noqa: F401
        except ImportError as e:
            raise Skip(f"roboticstoolbox: not installed ({e})") from None
        dh = rtb_dh_robot(robot)
        dev = check_fk("rtb", lambda q: dh.fkine(q).A, robot, rng)
        t0 = time.perf_counter()
        try:
            self.solver = dh.analytic_ik()
        except ImportError as e:            # SymPy missing: roboticstoolbox-python[ik]
            raise Skip(f"rtb analytic_ik: {e}") from None
        except (ValueError, NotImplementedError) as e:
            raise Skip(f"rtb analytic_ik: {e}") from None
        derive = time.perf_counter() - t0
        kind = str(self.solver).splitlines()[0]
        return (f"DHRobot from kincalc's DH table, FK agrees to {dev:.0e}; {kind}; "
                f"symbolic derivation {derive:.1f} s (once per robot, not timed below)")

    def run(self, T):
        return [self.solver.solve(T[i], joint_limits=False) for i in range(len(T))]

    def sets(self, T, robot):
        out = []
        for s in self.run(T):
            q = np.asarray(s.q, float).reshape(-1, robot.dof)
            out.append((q, np.zeros(len(q), bool)))
        return out


PUMA_CONFIGS = [a + b + c for a in "lr" for b in "ud" for c in "nf"]


class RTBIkineAPeer(Peer):
    def __init__(self):
        self.name = f"rtb {version('roboticstoolbox-python')}"
        self.short = "rtb ikine_a"
        self.api = "ikine_a x 8 configs, per pose (subset)"
        self.flag_meaning = "success=False mark"

    def sizes(self, N, args):
        m = min(N, max(args.rtb_subset // 4, 1))
        return m, m

    def prepare(self, robot, rng):
        try:
            import roboticstoolbox as rtb
        except ImportError as e:
            raise Skip(f"roboticstoolbox: not installed ({e})") from None
        if robot.name != "puma560":
            raise Skip(f"rtb ikine_a: a hand-written Puma 560 solution, not for {robot.name}")
        self.model = rtb.models.DH.Puma560()
        d1 = self.model.links[0].d
        # the toolbox's Python model measures from the mounting surface (d1 = 0.672 m);
        # the bundled file (and RTB for MATLAB) from the shoulder: same arm otherwise
        self.model.links[0].d = 0.0
        dev = check_fk("rtb ikine_a", lambda q: self.model.fkine(q).A, robot, rng)
        return (f"models.DH.Puma560 with links[0].d {d1:g} -> 0 (kincalc's base frame is "
                f"at the shoulder); FK then agrees to {dev:.0e}")

    def run(self, T):
        return [[self.model.ikine_a(T[i], config=c) for c in PUMA_CONFIGS] for i in range(len(T))]

    def sets(self, T, robot):
        out = []
        for per_config in self.run(T):
            qs = [np.asarray(s.q, float) for s in per_config if np.all(np.isfinite(s.q))]
            fl = [not s.success for s in per_config if np.all(np.isfinite(s.q))]
            out.append((np.array(qs).reshape(-1, robot.dof), np.array(fl, bool)))
        return out


# --- one robot ------------------------------------------------------------------------

def fmt_us(s):
    return f"{s * 1e6:9.2f}" if s < 1e-4 else f"{s * 1e6:9.0f}"


def count_histogram(counts):
    vals, n = np.unique(counts, return_counts=True)
    return " ".join(f"{v}:{c}" for v, c in zip(vals, n))


def bench_robot(name, args):
    robot = kincalc.load_robot(name)
    rng = np.random.default_rng(args.seed)
    family = plan(robot)[1]
    poses = make_poses(robot, args.poses, rng)
    N, n = args.poses, robot.dof
    T = poses.T
    print(f"\n== {name}: {robot.title}")
    print(f"   kincalc family: {family.name if family else 'none'}; {N} poses: "
          f"{poses.from_fk.sum()} by FK of random q within the limits, "
          f"{(~poses.from_fk).sum()} random (ball of 1.1 x reach, random orientation)")

    # the reference: vectorised numpy FK of the seed configurations, kincalc-independent
    H, P, R6T = poe_description(robot)
    Qs = np.where(np.isnan(poses.seed), 0.0, poses.seed)
    t_ref, (R_ref, p_ref) = timed(lambda: numpy_fk(H, P, R6T, robot.is_revolute, Qs),
                                  args.repeat, N)
    Tk = robot.fk(Qs)
    ref_dev = max(np.abs(R_ref - Tk[:, :3, :3]).max(), np.abs(p_ref - Tk[:, :3, 3]).max())

    rows = [("numpy FK reference (POE)", "vectorised, N configs", N, t_ref)]
    try:
        t_kc, B = timed(lambda: robot.ik_batch(T), args.repeat, N)
    except kincalc.KincalcError as e:
        print(f"   SKIPPED the robot: kincalc ik_batch: {e}")
        return
    rows.append(("kincalc " + version("kincalc"), "ik_batch, vectorised", N, t_kc))
    kc = Sets("kincalc", B.q, B.valid.copy(), np.zeros_like(B.valid))
    pose_errors(robot, T, kc)

    peers = [EAIKPeer(1), EAIKPeer(2), IKGeoPeer(), RTBAnalyticPeer(), RTBIkineAPeer()]
    setup_lines, results = [], []
    for peer in peers:
        try:
            line = peer.prepare(robot, np.random.default_rng(1))
        except Skip as e:
            if f"   SKIPPED {e}" not in setup_lines:
                setup_lines.append(f"   SKIPPED {e}")
            continue
        m_time, m_sets = peer.sizes(N, args)
        args_time = peer.inputs(T[:m_time])
        t, _ = timed(lambda: peer.run(args_time), args.repeat, m_time)
        rows.append((peer.name, peer.api, m_time, t))
        if peer.timing_only:
            continue
        setup_lines.append(f"   {peer.short}: {line}")
        q, ret, fl = pad(peer.sets(T[:m_sets], robot), n)
        s = Sets(peer.short, q, ret, fl, peer.flag_meaning)
        pose_errors(robot, T, s)
        results.append(s)
    try:
        note = rtb_model_note(robot)
    except ImportError:
        note = None

    for line in setup_lines:
        print(line)
    if note:
        print(f"   {note}")
    print(f"   numpy FK reference agrees with kincalc FK to {ref_dev:.0e}")

    print(f"\n   timing, median of {args.repeat} runs, per pose "
          f"(OMP_NUM_THREADS={os.environ['OMP_NUM_THREADS']})")
    print(f"   {'solver':26s} {'call':42s} {'poses':>7s} {'us/pose':>9s} "
          f"{'x kincalc':>10s} {'x numpy FK':>11s}")
    for who, api, m, t in rows:
        print(f"   {who:26s} {api:42s} {m:7d} {fmt_us(t)} {t / t_kc:10.3f} {t / t_ref:11.1f}")

    report_sets(robot, poses, kc, results)


def report_sets(robot, poses, kc, peers):
    rev = robot.is_revolute
    N = len(kc.q)
    print(f"\n   solution sets (pose check by kincalc FK: exact = within {POSITION_TOL:g} m and "
          f"{ORIENTATION_TOL:g} rad; joint vectors matched modulo 2 pi at {MATCH_TOL:g})")
    hdr = (f"   {'solver':18s} {'poses':>6s} {'sols/pose':>9s} {'returned':>9s} {'flagged':>8s} "
           f"{'exact':>9s} {'miss':>6s} {'>1mm':>6s} {'>1cm':>6s} {'max miss m':>10s} "
           f"{'seed found':>11s} {'kc found':>9s} {'kc missed':>9s} {'extra':>6s} {'same set':>9s}")
    print(hdr)
    seed = np.nan_to_num(poses.seed)[:, None, :]
    for s in [kc] + peers:
        M = len(s.q)
        ex = s.exact
        miss = s.returned & ~ex
        pe = np.where(miss, np.nan_to_num(s.pos_err, posinf=1e9), 0.0)
        seed_ok = found_in(seed[:M], poses.from_fk[:M, None], s.q, ex, rev)[:, 0]
        n_fk = poses.from_fk[:M].sum()
        if s is kc:
            kc_found = kc_missed = extra = same = "-"
        else:
            a = found_in(kc.q[:M], kc.exact[:M], s.q, ex, rev)           # kincalc's, in the peer's
            b = found_in(s.q, ex, kc.q[:M], kc.exact[:M], rev)           # the peer's, in kincalc's
            kc_found = a.sum()
            kc_missed = (kc.exact[:M] & ~a).sum()
            extra = (ex & ~b).sum()
            same_pose = ~np.any(kc.exact[:M] & ~a, 1) & ~np.any(ex & ~b, 1)
            same = f"{same_pose.sum()}/{M}"
        print(f"   {s.name:18s} {M:6d} {s.returned.sum() / M:9.3f} {s.returned.sum():9d} "
              f"{(s.flagged & s.returned).sum():8d} {ex.sum():9d} {miss.sum():6d} "
              f"{(pe > 1e-3).sum():6d} {(pe > 1e-2).sum():6d} {pe.max() if miss.any() else 0:10.2e} "
              f"{f'{seed_ok.sum()}/{n_fk}':>11s} {kc_found!s:>9s} {kc_missed!s:>9s} {extra!s:>6s} "
              f"{same:>9s}")

    print("\n   returned per pose (count:poses), FK poses | random poses")
    for s in [kc] + peers:
        M = len(s.q)
        c = s.returned.sum(1)
        fk = poses.from_fk[:M]
        print(f"   {s.name:18s} {count_histogram(c[fk]):40s} | {count_histogram(c[~fk])}")

    # the peers' flagged or inexact answers, and what kincalc says on those poses
    for s in peers:
        M = len(s.q)
        miss = s.returned & ~s.exact
        flagged = s.returned & s.flagged
        if not (miss.any() or flagged.any()):
            print(f"\n   {s.name}: every returned solution is exact; none flagged")
            continue
        bad_pose = np.any(miss | flagged, 1)
        fk = poses.from_fk[:M]
        pe = s.pos_err[miss]
        print(f"\n   {s.name}: {miss.sum()} inexact solutions ({100 * miss.sum() / s.returned.sum():.1f} % "
              f"of returned) on {bad_pose.sum()} poses ({(bad_pose & fk).sum()} FK, "
              f"{(bad_pose & ~fk).sum()} random); {flagged.sum()} carry the {s.flag_meaning}, "
              f"{(miss & flagged).sum()} of them inexact; unflagged but inexact: "
              f"{(miss & ~flagged).sum()}; flagged but exact: {(flagged & ~miss).sum()}")
        share = [f"{what} poses {(miss & sl[:, None]).sum()} of {(s.returned & sl[:, None]).sum()} "
                 f"({100 * (miss & sl[:, None]).sum() / max((s.returned & sl[:, None]).sum(), 1):.1f} %)"
                 for what, sl in (("FK", fk), ("random", ~fk))]
        print(f"      inexact share of returned: {'; '.join(share)}")
        if miss.any():
            print(f"      position miss: median {np.median(pe):.2e} m, max {pe.max():.2e} m; "
                  f"orientation miss: median {np.median(s.rot_err[miss]):.2e} rad, "
                  f"max {np.max(s.rot_err[miss]):.2e} rad")
        kcc = kc.exact[:M].sum(1)
        print(f"      kincalc on those poses returns (count:poses) {count_histogram(kcc[bad_pose])};"
              f" the peer's exact ones there: {count_histogram(s.exact[bad_pose].sum(1))}")
        for i in np.flatnonzero(bad_pose)[:3]:
            k = np.flatnonzero(miss[i] | flagged[i])
            errs = ", ".join(f"{s.pos_err[i, j]:.1e} m/{s.rot_err[i, j]:.1e} rad" for j in k)
            print(f"      e.g. pose {i} ({'FK' if fk[i] else 'random'}): kincalc {kcc[i]} exact, "
                  f"peer {s.returned[i].sum()} returned, {s.exact[i].sum()} exact; misses {errs}")

    # where a peer's exact set and kincalc's differ: how far the nearest match is
    for s in peers:
        M = len(s.q)
        a = found_in(kc.q[:M], kc.exact[:M], s.q, s.exact, rev)
        b = found_in(s.q, s.exact, kc.q[:M], kc.exact[:M], rev)
        differ = np.flatnonzero(np.any(kc.exact[:M] & ~a, 1) | np.any(s.exact & ~b, 1))
        if not len(differ):
            continue
        a2 = found_in(kc.q[:M], kc.exact[:M], s.q, s.exact, rev, LOOSE_MATCH_TOL)
        b2 = found_in(s.q, s.exact, kc.q[:M], kc.exact[:M], rev, LOOSE_MATCH_TOL)
        loose = np.any(kc.exact[:M] & ~a2, 1) | np.any(s.exact & ~b2, 1)
        print(f"\n   {s.name}: exact set differs from kincalc's on {len(differ)} of {M} poses "
              f"({loose.sum()} when matching at {LOOSE_MATCH_TOL:g} rad)")
        for i in differ[:4]:
            d = joint_distance(kc.q[i], s.q[i], rev)
            lost = [f"{d[j][s.returned[i]].min():.1e}" if s.returned[i].any() else "none returned"
                    for j in np.flatnonzero(kc.exact[i] & ~a[i])]
            extra = [f"{d[:, j][kc.exact[i]].min():.1e}" if kc.exact[i].any() else "-"
                     for j in np.flatnonzero(s.exact[i] & ~b[i])]
            print(f"      pose {i} ({'FK' if poses.from_fk[i] else 'random'}): kincalc {kc.exact[i].sum()}, "
                  f"peer {s.exact[i].sum()} exact of {s.returned[i].sum()}; kincalc's not found "
                  f"(nearest peer answer, rad): {lost or '-'}; peer's not in kincalc's "
                  f"(nearest kincalc, rad): {extra or '-'}")

    # kincalc: every answer exact, and as many as anyone found
    kc_bad = (kc.returned & ~kc.exact).sum()
    print(f"\n   kincalc: {kc.returned.sum()} solutions, {kc_bad} not reproducing the pose "
          f"(max {np.nanmax(kc.pos_err):.1e} m, {np.nanmax(kc.rot_err):.1e} rad)")
    print("   kincalc's count against the distinct exact, unflagged solutions found by anyone:")
    for M in sorted({len(s.q) for s in peers} | {N}, reverse=True):
        group = [s for s in peers if len(s.q) >= M]
        qs = np.concatenate([kc.q[:M]] + [s.q[:M] for s in group], 1)
        oks = np.concatenate([kc.exact[:M]] + [s.exact[:M] & ~s.flagged[:M] for s in group], 1)
        kcc = kc.exact[:M].sum(1)
        found = []
        for tol in (MATCH_TOL, LOOSE_MATCH_TOL):
            union = distinct_count(qs, oks, rev, tol)
            fewer = np.flatnonzero(kcc < union)
            found.append(f"equal on {M - len(fewer)}, fewer on {len(fewer)} at {tol:g} rad"
                         + (f" (poses {', '.join(map(str, fewer[:4]))}: kincalc "
                            f"{kcc[fewer[:4]].tolist()}, all {union[fewer[:4]].tolist()})"
                            if len(fewer) else ""))
        who = ", ".join(["kincalc"] + [s.name for s in group])
        print(f"   first {M} poses ({who}): {'; '.join(found)}")


def cpu_name():
    """The processor's model name where the system tells it (Linux), else the platform's."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--poses", type=int, default=100_000)
    ap.add_argument("--robots", nargs="+", default=["ur5", "puma560"])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--per-pose-subset", type=int, default=5000,
                    help="poses timed for per-pose APIs (ik-geo); its sets use all poses")
    ap.add_argument("--rtb-subset", type=int, default=1000,
                    help="poses for the toolbox's analytic_ik (time and sets); ikine_a a quarter")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    print(f"kincalc peers benchmark, {date.today()}, {cpu_name()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, numpy {np.__version__}")
    vers = {d: version(d) for d in ("EAIK", "ik-geo", "roboticstoolbox-python", "sympy")}
    print("peers: " + ", ".join(f"{d} {v}" if v else f"{d} NOT INSTALLED" for d, v in vers.items()))
    if not all(vers.values()):
        print("  (missing peers are skipped: pip install '.[bench]')")
    for name in args.robots:
        bench_robot(name, args)


if __name__ == "__main__":
    main()
