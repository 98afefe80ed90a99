"""Bayram's 8-DOF hybrid redundant arm (seed 004), solved with kincalc's numerical IK.

A. Bayram, "Bir artiksiz uzaysal manipulatorun modelleme ve kinematik analizinin
incelenmesi" (Modeling and kinematic analysis of a redundant spatial manipulator),
Yuzuncu Yil Universitesi. Run ``python examples/bayram_vgt.py``.

Mechanism
---------
``q = (psi0, s1, v1, p1, s2, v2, p2, psi23)`` (rad, m): a base rotation ``psi0``
about z, two planar variable-geometry-truss (VGT) modules each driven by three
screw actuators (legs ``s``, ``v`` and the diagonal ``p``), and a tool rotation
``psi23``. In a module (the paper's Fig. 2) the base ``A0 B0`` has length ``2 b``,
the top platform ``A11 B11`` length ``2 d``; leg ``s`` joins ``A0 A11``, leg ``v``
joins ``B0 B11`` and the diagonal ``p`` joins ``A0 B11``. In the module's plane,
with x along ``A0 -> B0``, the loop equations (4)-(7) are::

    2b + v cos(gamma) = p cos(beta)          s cos(alpha) + 2d cos(theta) = p cos(beta)
         v sin(gamma) = p sin(beta)          s sin(alpha) + 2d sin(theta) = p sin(beta)

``gamma``, ``beta``, ``alpha`` are the directions of ``v``, ``p``, ``s`` and ``theta``
the tilt of the top platform. Module 1 moves in the u2-u3 plane (x = u2) and tilts
about u1 by ``theta1``; module 2 moves in the u1-u3 plane of frame 11 and tilts about
u2 by ``theta2``; its in-plane x axis is ``-u1`` (that is what makes a positive
``theta2`` a positive rotation about u2, as eq. (3) and the ``h2`` terms of (19)-(20)
require). Orientation, eq. (3)::

    C = e^{u3 psi0} e^{u1 theta1} e^{u2 theta2} e^{u3 psi23}

position, eq. (2) with (12) and (13)::

    r = h1 u3 + C01 r_11/1 + C0,11 r_22/11 + h2 C0,22 u3,
    r_11/1  = [0, s1 ca1 + d ct1 - b, s1 sa1 + d st1]           (module 1, frame 1)
    r_22/11 = [-(s2 ca2 + d ct2 - b), 0, s2 sa2 + d st2]        (module 2, frame 11)

with ``C01 = Rz(psi0)``, ``C0,11 = Rz(psi0) Rx(theta1)``, ``C0,22 = C0,11 Ry(theta2)``.
Both modules have the same dimensions (the paper's eq. (13) uses b1 and d1 for module
2 as well).

Passive angles (eqs. (8)-(11), corrected, see below)::

    xi    = (p^2 - v^2 - 4 b^2) / (4 b v),    gamma = atan2(sigma1 sqrt(1 - xi^2), xi)
    beta  = atan2(v sin(gamma), 2b + v cos(gamma))
    k     = (p^2 + 4 d^2 - s^2) / (4 d p),    theta = beta + atan2(sigma2 sqrt(1 - k^2), k)
    alpha = atan2(p sin(beta) - 2d sin(theta), p cos(beta) - 2d cos(theta))

A module cannot be assembled when ``|xi| > 1`` or ``|k| > 1``; :func:`fk` then raises
ValueError. Inside :data:`LIMITS` this never happens (see below).

Assumptions (the paper gives no numbers for these)
--------------------------------------------------
* ``b1 = d1 = 0.18 m`` (base and top platform ``2b = 2d = 0.36 m``), ``h1 = h2 = 0.10 m``
  for both modules.
* Branches ``sigma1 = +1``, ``sigma2 = -1``. With the paper's own definition
  ``sin(theta - beta) = sigma2 sqrt(1 - k^2)`` the symmetric (rectangular) start needs
  ``theta - beta = -beta``, i.e. ``sin(theta - beta) < 0``. ``sigma2 = +1`` gives the
  other assembly of the same lengths, the top platform folded over the diagonal
  (``theta = 2 beta = 63.3 deg``, ``alpha = -26.7 deg``; start pose
  r = [-0.010, 0.004, 0.209] m, tool turned 87 deg), not the paper's start pose.
  ``sigma1 = +1`` puts leg v above the base (``gamma`` in (0, pi)).
* Start ``START_Q``: ``psi0 = psi23 = 0``, ``s = v = 0.222 m``,
  ``p = sqrt((2b)^2 + s^2) = 0.42295 m`` in both modules: two rectangles of height
  0.222 m, ``r = [0, 0, h1 + 2 * 0.222 + h2] = [0, 0, 0.644] m``, identity orientation
  (the paper's start pose).
* Strokes ``LIMITS``: ``psi0, psi23`` in [-pi, pi]; ``s, v`` in [0.20, 0.42] m;
  ``p`` in [0.28, 0.52] m. Every configuration in this box assembles, with margin: the
  extremes of ``xi`` and ``k`` over the box are at its corners and all lie within
  [-0.753, 0.962] (no leg comes closer than 15.9 deg to being collinear with a platform
  or the diagonal), so the FK is smooth on the whole box. This is why b = d = 0.18 m
  and not 0.10 m: Table 1 target 1 (a pure 0.266 m rise with identity orientation)
  forces both modules into rectangles with ``s1 + s2 = 0.71 m``, hence
  ``p = sqrt(4 b^2 + 0.355^2)`` in both; with ``b = 0.10`` that is 0.4075 m, and a box
  that contains it, the start and assembles everywhere has ``v_min > 0.2075 m`` and
  singular corners. With ``b = d = 0.18 m`` all five Table 1 targets are reachable.
  kincalc's ``solve_numeric`` does not catch exceptions from the user's FK (restarts
  are drawn uniformly in the limits), so an FK that can raise inside the limits would
  abort the solve; an everywhere-assemblable box avoids that.

Misprints found in the paper (the code uses the corrected forms)
---------------------------------------------------------------
* Eq. (10): printed ``theta1 = beta1 + atan2(k1, sigma2 sqrt(1 - k1^2))``; with the
  paper's own ``cos(theta1 - beta1) = k1``, ``sin(theta1 - beta1) = sigma2 sqrt(1 - k1^2)``
  (and eq. (8)'s atan2(sin, cos) order) it is ``theta1 = beta1 + atan2(sigma2
  sqrt(1 - k1^2), k1)``. The printed form gives theta = 90 deg or 90 deg + 2 beta at the
  symmetric start, never 0.
* Eq. (11): printed ``sin(alpha1) = (p1 sin(beta1) - 2 b1 sin(theta1)) / s1`` and
  ``cos(beta1) = (p1 cos(beta1) - 2 b1 cos(theta1)) / s1 = n1``; from (6)-(7) both use
  ``2 d1`` (the top platform), and the second is ``cos(alpha1) = n1``.
* Eq. (9): the condition printed ``(s3 != 0)`` is ``p1 != 0``.
* Eq. (13): printed ``r_22/11 = [0, -s2 ca2 - d1 ct2 + b1, s2 sa2 + d1 st2]``; module 2
  moves in the u1-u3 plane (the text, and eqs. (20)-(21), which have no ``S theta1``
  term from it in r3), so the in-plane component is the first one:
  ``[-s2 ca2 - d1 ct2 + b1, 0, s2 sa2 + d1 st2]``.
* Eq. (19): the coefficient of ``(-s2 ca2 - d1 ct2 + b1)`` is printed ``C theta1
  S psi0``; it is ``C psi0`` (the first column of C0,11 is [C psi0, S psi0, 0], as the
  coefficient ``S psi0`` in eq. (20) and 0 in eq. (21) confirm; the printed vector
  ``[C theta1 S psi0, S psi0, 0]`` is not even a unit vector).
* Eq. (2)'s ``C(0,11) = e^{u3 psi0} e^{u1 theta}`` lacks the index (theta1); eq. (3)
  writes ``psi3`` for ``psi23``.
Eqs. (4)-(8), (12), (16)-(18), (20) and (21) hold as printed.

Table 1 orientations are moving X-Y-Z ("1-2-3") Euler angles in degrees,
``R = Rx(Phi1) Ry(Phi2) Rz(Phi3)``. Table 2's first column is the paper's pose error,
eq. (24), of its genetic-algorithm solutions (percent); the other columns the percent
change of each joint, eq. (25): ``|q - q_start| / mean * 100``; here the mean length is
taken as the mid-stroke of :data:`LIMITS` (the paper does not say how its percentages
for the rotations are normalised; for them the change is printed in degrees).
"""

from __future__ import annotations

import numpy as np

from kincalc.ik.numeric import solve_numeric
from kincalc.spatial import euler_xyz_from_matrix, matrix_from_euler_xyz, rot_x, rot_y, rot_z

# --- assumed dimensions (m) and branches -------------------------------------
B = 0.18          #: half width of a module's base, b1 (= b2)
D = 0.18          #: half width of a module's top platform, d1 (= d2)
H1 = 0.10         #: height of the base rotation unit
H2 = 0.10         #: height of the tool rotation unit
SIGMA1 = +1       #: sign of sin(gamma), eq. (8)
SIGMA2 = -1       #: sign of sin(theta - beta), eq. (10)

NAMES = ("psi0", "s1", "v1", "p1", "s2", "v2", "p2", "psi23")
REVOLUTE = [True, False, False, False, False, False, False, True]
#: characteristic length for the IK's scaling of lengths against angles (m)
SCALE = 0.5

_S = (0.20, 0.42)                 # legs s and v (m)
_P = (0.28, 0.52)                 # diagonal p (m)
#: joint limits (8, 2): rad for psi0, psi23; m for the actuator lengths
LIMITS = np.array([(-np.pi, np.pi), _S, _S, _P, _S, _S, _P, (-np.pi, np.pi)])

_S0 = 0.222
_P0 = float(np.hypot(2 * B, _S0))
#: the paper's start pose r = [0, 0, 0.644] m, zero Euler angles (two rectangles)
START_Q = np.array([0.0, _S0, _S0, _P0, _S0, _S0, _P0, 0.0])

#: Table 1: r1, r2, r3 (m), Phi1, Phi2, Phi3 (deg, moving X-Y-Z Euler angles)
TARGETS = np.array([
    [0.0, 0.0, 0.91, 0.0, 0.0, 0.0],
    [0.223, 0.027, 0.725, 0.0, 30.0, 60.0],
    [-0.188, -0.156, 0.669, 10.0, 10.0, -10.0],
    [-0.188, 0.294, 0.648, -30.0, -30.0, -30.0],
    [0.009, 0.081, 0.778, 25.0, 10.0, -25.0],
])
#: Table 2, first column: pose error of the paper's GA solutions, eq. (24) (%)
PAPER_ERRORS = np.array([1.35, 1.08, 11.8, 4.65, 6.61])
#: Table 2, the other columns: % change of psi0, s1, v1, p1, s2, v2, p2, psi23, eq. (25)
PAPER_CHANGES = np.array([
    [0.1, 47.8, 47.8, 24.1, 47.8, 47.8, 24.1, 0.1],
    [63.4, 46.7, 9.5, 5.3, 40.8, 6.2, 24.1, 47.8],
    [0.3, 18.3, 38.6, 0.09, 0.0, 6.0, 24.1, 3.2],
    [0.09, 47.8, 0.0, 24.1, 47.8, 0.0, 24.0, 8.4],
    [18.6, 35.6, 34.3, 22.1, 0.0, 35.8, 24.1, 2.5],
])


def passive_angles(s, v, p, b=B, d=D, sigma1=SIGMA1, sigma2=SIGMA2):
    """``(alpha, beta, gamma, theta)`` (rad) of one VGT module with leg lengths
    ``s, v, p`` (m), eqs. (8)-(11) corrected; ValueError if it cannot be assembled."""
    xi = (p * p - v * v - 4 * b * b) / (4 * b * v)
    if not abs(xi) <= 1:
        raise ValueError(f"VGT module cannot be assembled: cos(gamma) = {xi:.6g} (s={s}, v={v}, p={p})")
    gamma = np.arctan2(sigma1 * np.sqrt(1 - xi * xi), xi)
    beta = np.arctan2(v * np.sin(gamma), 2 * b + v * np.cos(gamma))
    k = (p * p + 4 * d * d - s * s) / (4 * d * p)
    if not abs(k) <= 1:
        raise ValueError(f"VGT module cannot be assembled: cos(theta - beta) = {k:.6g} (s={s}, v={v}, p={p})")
    theta = beta + np.arctan2(sigma2 * np.sqrt(1 - k * k), k)
    alpha = np.arctan2(p * np.sin(beta) - 2 * d * np.sin(theta), p * np.cos(beta) - 2 * d * np.cos(theta))
    return float(alpha), float(beta), float(gamma), float(theta)


def module(s, v, p):
    """``(theta, x, z)``: the top platform's tilt (rad) and its centre relative to the
    base centre in the module's plane (m), eq. (12)."""
    alpha, _, _, theta = passive_angles(s, v, p)
    return (theta, s * np.cos(alpha) + D * np.cos(theta) - B, s * np.sin(alpha) + D * np.sin(theta))


def fk(q) -> np.ndarray:
    """Tool pose ``T (4, 4)`` (world <- tool) for ``q = (psi0, s1, v1, p1, s2, v2, p2,
    psi23)`` (rad, m); eqs. (2), (3), (12), (13). ValueError if a module cannot be
    assembled."""
    psi0, s1, v1, p1, s2, v2, p2, psi23 = np.asarray(q, float)
    th1, y1, z1 = module(s1, v1, p1)
    th2, x2, z2 = module(s2, v2, p2)
    C01 = rot_z(psi0)
    C011 = C01 @ rot_x(th1)
    C022 = C011 @ rot_y(th2)
    r = (np.array([0.0, 0.0, H1]) + C01 @ np.array([0.0, y1, z1])
         + C011 @ np.array([-x2, 0.0, z2]) + H2 * C022[:, 2])
    T = np.eye(4)
    T[:3, :3] = C022 @ rot_z(psi23)
    T[:3, 3] = r
    return T


def target_pose(row) -> np.ndarray:
    """A Table 1 row (m, deg) as a 4x4 pose."""
    T = np.eye(4)
    T[:3, :3] = matrix_from_euler_xyz(np.radians(row[3:6]))
    T[:3, 3] = row[:3]
    return T


def solve(T, q0=START_Q):
    """kincalc's numerical IK: the solution nearest ``q0`` within :data:`LIMITS`."""
    return solve_numeric(fk, T, q0, limits=LIMITS, revolute=REVOLUTE, scale=SCALE, orientation=True)


def percent_change(q, q_start=START_Q) -> np.ndarray:
    """Eq. (25) for the six actuator lengths: ``|q - q_start| / mid-stroke * 100``."""
    mean = LIMITS[1:7].mean(axis=1)
    return np.abs(np.asarray(q)[1:7] - q_start[1:7]) / mean * 100


def pose_error_percent(T_found, row) -> float:
    """Eq. (24) with X = [r (m), Phi (rad)]: ``|X_given - X_found| / |X_given| * 100``."""
    given = np.concatenate([row[:3], np.radians(row[3:6])])
    found = np.concatenate([T_found[:3, 3], euler_xyz_from_matrix(T_found[:3, :3])])
    return float(np.linalg.norm(given - found) / np.linalg.norm(given) * 100)


def main() -> None:
    T0 = fk(START_Q)
    print("Bayram's 8-DOF VGT arm (seed 004). Assumed b = d = %.2f m, h1 = h2 = %.2f m, "
          "sigma1 = %+d, sigma2 = %+d." % (B, H1, SIGMA1, SIGMA2))
    print("Limits: psi0, psi23 in [-180, 180] deg; s, v in [%.2f, %.2f] m; p in [%.2f, %.2f] m."
          % (*_S, *_P))
    print("Start q = (psi0 s1 v1 p1 s2 v2 p2 psi23) = (0, %.3f, %.3f, %.5f, %.3f, %.3f, %.5f, 0)"
          % tuple(START_Q[1:7]))
    print("Start pose r = [%.4f, %.4f, %.4f] m, Euler X-Y-Z = %s deg\n"
          % (*(T0[:3, 3].round(12) + 0.0), np.degrees(euler_xyz_from_matrix(T0[:3, :3])).round(6) + 0.0))

    rows = []
    for i, row in enumerate(TARGETS, 1):
        res = solve(target_pose(row))
        rows.append(res)
        oe = np.degrees(res.orientation_error)
        print(f"Target {i}: r = {row[:3].tolist()} m, Phi = {row[3:].tolist()} deg")
        print(f"  reached: {'yes' if res.converged else 'NO (not reachable with the assumed dimensions)'}"
              f"   position error {res.position_error:.2e} m   orientation error {oe:.2e} deg"
              f"   eq.(24) error {pose_error_percent(fk(res.q), row):.1e} %"
              f"   (paper, GA: {PAPER_ERRORS[i - 1]:g} %)")
        at = [NAMES[j] for j in res.at_limits]
        print(f"  iterations {res.iterations}, restarts {res.restarts}, scaled distance from start "
              f"{res.distance:.4f}, at a limit: {', '.join(at) if at else 'none'}")

    print("\nJoint values found (psi in deg, lengths in m) and change from the start, eq. (25)")
    head = f"{'#':>2} {'ok':>3} " + " ".join(f"{n:>8}" for n in NAMES)
    print(head)
    for i, res in enumerate(rows, 1):
        q = res.q
        vals = np.round([np.degrees(q[0]), *q[1:7], np.degrees(q[7])], 6) + 0.0
        fmt = ["%8.2f"] + ["%8.4f"] * 6 + ["%8.2f"]
        print(f"{i:>2} {'yes' if res.converged else 'NO':>3} " + " ".join(f % v for f, v in zip(fmt, vals)))
    print("\nChange from the start: psi in deg, lengths in % of mid-stroke (paper's Table 2 in brackets)")
    print(head)
    for i, res in enumerate(rows, 1):
        q = res.q
        pc = percent_change(q)
        cells = [f"{np.degrees(abs(q[0] - START_Q[0])):8.2f}"]
        cells += [f"{c:8.1f}" for c in pc]
        cells += [f"{np.degrees(abs(q[7] - START_Q[7])):8.2f}"]
        print(f"{i:>2} {'yes' if res.converged else 'NO':>3} " + " ".join(cells))
        print(f"{'':>6} " + " ".join(f"{'[' + format(c, 'g') + ']':>8}" for c in PAPER_CHANGES[i - 1]))
    n_ok = sum(r.converged for r in rows)
    print(f"\n{n_ok} of {len(rows)} targets reached to kincalc's tolerance "
          "(scaled pose error <= 1e-10), each the least-change solution from the start "
          "as kincalc's local solver finds it.")


if __name__ == "__main__":
    main()
