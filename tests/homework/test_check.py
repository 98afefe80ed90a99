"""``kincalc check``: grading homework sheets (format: README "Homework sheets").

Every expected value here is derived independently of kincalc's own code:
by hand (the planar RR arm bk_rr: l1 = 10, l2 = 5), or by the small numpy
helpers below, written from the textbook formulas (standard DH
Rz(θ)Tz(d)Tx(a)Rx(α); Craig's modified DH Rx(α)Tx(a)Rz(θ)Tz(d); the law of
cosines for the RR arm; a closed-form SCARA + Euler-wrist IK for Bingül &
Küçük's Example 4.6; finite-difference Jacobians). The robots' tables are
transcribed here from robots/*.yaml. kincalc's own ``robot.fk`` is used only
as a second oracle that an IK solution reproduces its target.

Grading is exercised in-process (``parse_sheet`` + ``grade``); exit statuses,
stderr and ``--json`` through ``python -m kincalc`` in a subprocess, which
works from an editable or a regular install alike.
"""

from __future__ import annotations

import glob
import json
import math
import os
import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from kincalc.homework import SheetError, grade, load_sheet, parse_sheet

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(HERE)

# ---------------------------------------------------------------------------
# Independent kinematics (textbook formulas; angles in radians)

L1, L2 = 10.0, 5.0          # bk_rr (Bingül & Küçük Example 4.2)


def rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def ry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1.0]])


def rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def trans(x, y, z):
    T = np.eye(4)
    T[:3, 3] = [x, y, z]
    return T


def dh_link(theta, d, a, alpha):
    """Standard (distal) DH link matrix, written out entry by entry."""
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array([[ct, -st * ca, st * sa, a * ct],
                     [st, ct * ca, -ct * sa, a * st],
                     [0, sa, ca, d],
                     [0, 0, 0, 1.0]])


def mdh_link(alpha, a, theta, d):
    """Craig's modified DH link matrix T_{i-1}^i, written out entry by entry."""
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array([[ct, -st, 0, a],
                     [st * ca, ct * ca, -sa, -sa * d],
                     [st * sa, ct * sa, ca, ca * d],
                     [0, 0, 0, 1.0]])


def rr_fk(q1, q2):
    """bk_rr, by hand: a rotation by q1 + q2 about z at the RR arm's tip (radians)."""
    T = rz(q1 + q2)
    T[:3, 3] = [L1 * math.cos(q1) + L2 * math.cos(q1 + q2),
                L1 * math.sin(q1) + L2 * math.sin(q1 + q2), 0]
    return T


def rr_ik(x, y):
    """bk_rr by the law of cosines: [(q1, q2) deg] for both elbows, [] if unreachable."""
    c2 = (x * x + y * y - L1 ** 2 - L2 ** 2) / (2 * L1 * L2)
    if abs(c2) > 1:
        return []
    out = []
    for s in (+1, -1):
        q2 = s * math.acos(c2)
        q1 = math.atan2(y, x) - math.atan2(L2 * math.sin(q2), L1 + L2 * math.cos(q2))
        out.append((math.degrees(q1), math.degrees(q2)))
    return out


def rr_jacobian(q1, q2):
    """bk_rr geometric Jacobian (base frame, per rad), rows vx vy vz wx wy wz."""
    s1, c1, s12, c12 = math.sin(q1), math.cos(q1), math.sin(q1 + q2), math.cos(q1 + q2)
    return np.array([[-L1 * s1 - L2 * s12, -L2 * s12],
                     [L1 * c1 + L2 * c12, L2 * c12],
                     [0, 0], [0, 0], [0, 0], [1, 1.0]])


# puma560 (robots/puma560.yaml): standard DH, metres; rows (alpha deg, a, d)
PUMA = [(90, 0, 0), (0, 0.4318, 0), (-90, 0.0203, 0.15005), (90, 0, 0.4318), (-90, 0, 0), (0, 0, 0)]


def puma_fk(q_deg, degrees=True):
    q = np.radians(q_deg) if degrees else np.asarray(q_deg, float)
    T = np.eye(4)
    for (alpha, a, d), qi in zip(PUMA, q):
        T = T @ dh_link(qi, d, a, math.radians(alpha))
    return T


def fd_jacobian(fk, q_rad, h=1e-6):
    """Geometric Jacobian (base frame) by central differences of ``fk`` (radians)."""
    q_rad = np.asarray(q_rad, float)
    cols = []
    for i in range(len(q_rad)):
        dq = np.zeros_like(q_rad)
        dq[i] = h
        Tp, Tm = fk(q_rad + dq), fk(q_rad - dq)
        v = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        W = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ fk(q_rad)[:3, :3].T     # skew(w)
        cols.append(np.r_[v, W[2, 1], W[0, 2], W[1, 0]])
    return np.array(cols).T


# bk_scara_euler (robots/bk_scara_euler.yaml): modified DH; rows (alpha deg, a, d, type)
H1, SL1, SL2, D4 = 22.0, 26.0, 18.0, 4.0
SCARA = [(0, 0, H1, "R"), (0, SL1, 0, "R"), (180, SL2, 0, "P"), (0, 0, D4, "R"),
         (-90, 0, 0, "R"), (90, 0, 0, "R")]


def scara_fk(q):
    """q: degrees for revolute joints, length for d3."""
    T = np.eye(4)
    for (alpha, a, d, kind), qi in zip(SCARA, q):
        if kind == "R":
            T = T @ mdh_link(math.radians(alpha), a, math.radians(qi), d)
        else:
            T = T @ mdh_link(math.radians(alpha), a, 0.0, d + qi)
    return T


def rpy_matrix(roll, pitch, yaw):
    """Fixed X-Y-Z angles (deg): R = Rz(yaw) Ry(pitch) Rx(roll)."""
    return (rz(math.radians(yaw)) @ ry(math.radians(pitch)) @ rx(math.radians(roll)))[:3, :3]


def scara_ik(p, R):
    """All four solutions (deg / length) of the SCARA with Euler wrist, closed form.

    The wrist point (frames 4..6 share an origin) sits d4 below frame 3, so
    z = h1 - d3 - d4 and x, y are the planar RR of l1, l2; then
    R = Rz(θ1 + θ2) Rx(180) Rz(θ4) Ry(θ5) Rz(θ6) (Rx(-90) Rz(θ5) Rx(90) = Ry(θ5)),
    a Z-Y-Z Euler set with two wrist branches.
    """
    x, y, z = p
    d3 = H1 - D4 - z
    c2 = (x * x + y * y - SL1 ** 2 - SL2 ** 2) / (2 * SL1 * SL2)
    out = []
    for s2 in (+1, -1):
        t2 = s2 * math.acos(c2)
        t1 = math.atan2(y, x) - math.atan2(SL2 * math.sin(t2), SL1 + SL2 * math.cos(t2))
        M = (rx(math.pi) [:3, :3].T @ rz(-(t1 + t2))[:3, :3] @ R)
        for s5 in (+1, -1):
            t5 = s5 * math.acos(np.clip(M[2, 2], -1, 1))
            t4 = math.atan2(s5 * M[1, 2], s5 * M[0, 2])
            t6 = math.atan2(s5 * M[2, 1], -s5 * M[2, 0])
            out.append([math.degrees(t1), math.degrees(t2), d3, math.degrees(t4),
                        math.degrees(t5), math.degrees(t6)])
    return out


def wrap180(x):
    return (np.asarray(x, float) + 180.0) % 360.0 - 180.0


# ---------------------------------------------------------------------------
# Sheets

def sheet_text(items: str, robot: str = "bk_rr", head: str = "") -> str:
    return (f"robot: {robot}\n" + textwrap.dedent(head) + "items:\n"
            + textwrap.indent(textwrap.dedent(items), "  "))


def report(items: str, robot: str = "bk_rr", head: str = "", folder: str = "."):
    return grade(parse_sheet(sheet_text(items, robot, head), "hw.yaml", folder))


def one(items: str, robot: str = "bk_rr", head: str = ""):
    rep = report(items, robot, head)
    assert len(rep.items) == 1
    return rep.items[0]


def js(M) -> str:
    """A matrix or vector as YAML flow text."""
    return json.dumps(np.asarray(M, float).round(12).tolist())


def kincalc(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "kincalc", *args], capture_output=True,
                          text=True, cwd=cwd, timeout=60)


# ---------------------------------------------------------------------------
# Sanity of the independent oracles themselves

def test_oracles_agree_with_the_book():
    # Example 4.2: (12.99, 2.5) has the sets (30, -60) and (-8.2, 60)
    sols = rr_ik(12.99, 2.5)
    assert any(np.allclose(s, (30, -60), atol=0.05) for s in sols)
    assert any(np.allclose(s, (-8.2, 60), atol=0.05) for s in sols)
    # Example 4.6 link 3 as printed in the book: [[1,0,0,l2],[0,-1,0,0],[0,0,-1,-d3]]
    T3 = mdh_link(math.pi, SL2, 0, 12)
    assert np.allclose(T3, [[1, 0, 0, 18], [0, -1, 0, 0], [0, 0, -1, -12], [0, 0, 0, 1]])
    # the SCARA IK reproduces the pose through my own FK ...
    R = rpy_matrix(42, -17, 25)
    for q in scara_ik((28, 31, 6), R):
        T = scara_fk(q)
        assert np.allclose(T[:3, 3], (28, 31, 6), atol=1e-9)
        assert np.allclose(T[:3, :3], R, atol=1e-9)
    # ... and through kincalc's FK (a second oracle, same file)
    from kincalc import load_robot
    robot = load_robot("bk_scara_euler")
    for q in scara_ik((28, 31, 6), R):
        qs = np.array(q, float)
        qs[[0, 1, 3, 4, 5]] = np.radians(qs[[0, 1, 3, 4, 5]])
        assert np.allclose(robot.fk(qs), scara_fk(q), atol=1e-9)
    # the finite-difference Jacobian reproduces the hand-derived RR one
    J = fd_jacobian(lambda q: rr_fk(*q), np.radians([30, -60]))
    assert np.allclose(J, rr_jacobian(*np.radians([30, -60])), atol=1e-7)


# ---------------------------------------------------------------------------
# dh

def test_dh_right_standard_table():
    r = one("""\
        - id: t
          kind: dh
          answer: {convention: dh, table: [[q1, 0, l1, 0], [q2, 0, l2, 0]]}
        """)
    assert r.passed, r.message


def test_dh_right_mapping_form():
    r = one("""\
        - id: t
          kind: dh
          answer:
            convention: dh
            joints:
              - {type: revolute, alpha: 0, a: 10, d: 0, theta: 0}
              - {type: revolute, alpha: 0, a: 5, d: 0, theta: 0}
        """)
    assert r.passed, r.message


def test_dh_right_up_to_an_offset_names_it():
    # theta1 = q1 + 90: the same arm with joint 1's zero turned by 90 deg
    r = one("""\
        - id: t
          kind: dh
          answer: {convention: dh, table: [[q1 + 90, 0, l1, 0], [q2, 0, l2, 0]]}
        """)
    assert r.passed, r.message
    # theta1 = q1 + 90 means the robot's theta1 is the student's q1 + 90, q1 = theta1 - 90
    assert re.search(r"q1 = (robot )?theta1 - 90\b|theta1 = q1 \+ 90\b", r.message), r.message
    assert "q2 =" not in r.message, r.message                   # joint 2 unchanged


def test_dh_right_up_to_a_sign_names_it():
    # theta2 = -q2: joint 2 counted the other way round
    r = one("""\
        - id: t
          kind: dh
          answer: {convention: dh, table: [[q1, 0, l1, 0], [-q2, 0, l2, 0]]}
        """)
    assert r.passed, r.message
    assert re.search(r"q2 = -(robot )?theta2\b|theta2 = -q2\b", r.message), r.message
    assert "q1 =" not in r.message, r.message


def test_dh_right_up_to_sign_and_offset():
    # theta1 = 90 - q1: q1 = 90 - theta1
    r = one("""\
        - id: t
          kind: dh
          answer: {convention: dh, table: [[90 - q1, 0, l1, 0], [q2, 0, l2, 0]]}
        """)
    assert r.passed, r.message
    assert re.search(r"q1 = -(robot )?theta1 \+ 90\b|q1 = 90 - theta1\b", r.message), r.message


def test_dh_tool_ignore_grades_the_axes_only():
    # a2 = 6 moves only the end frame of a standard-DH RR table (joint axes: z0 at the
    # origin, z1 at distance a1 = 10): with 'tool: ignore' the table is right
    r = one("""\
        - id: t
          kind: dh
          tool: ignore
          answer: {convention: dh, table: [[q1, 0, l1, 0], [q2, 0, 6, 0]]}
        """)
    assert r.passed, r.message
    r = one("""\
        - id: t
          kind: dh
          tool: ignore
          answer: {convention: dh, table: [[q1, 0, 12, 0], [q2, 0, l2, 0]]}
        """)
    assert not r.passed, r.message


def test_dh_wrong_a_in_row_1_names_row_1():
    r = one("""\
        - id: t
          kind: dh
          answer: {convention: dh, table: [[q1, 0, 12, 0], [q2, 0, l2, 0]]}
        """)
    assert not r.passed
    # standard DH: joint 2's axis is z1, placed by row 1 (a1); row 2 is not to blame
    assert "row 1" in r.message, r.message
    assert r.hint is None or "row 2" not in r.hint, r.hint


def test_dh_wrong_a_in_row_2_names_row_2():
    # Row 1 (a = l1) puts joint 2's axis right; row 2's a = 6 instead of l2 = 5
    # makes the arm 1 unit too long past joint 2: row 2 is the first wrong row.
    # (In standard DH the last row also defines the end frame; the student's
    # table has no tool, so the message must blame row 2, not a missing tool.)
    r = one("""\
        - id: t
          kind: dh
          answer: {convention: dh, table: [[q1, 0, l1, 0], [q2, 0, 6, 0]]}
        """)
    assert not r.passed
    assert "row 2" in r.message, (r.message, r.hint)
    # without a tool in the answer, a right row 2 has a = l2 = 5 (not the a = 0 of a table
    # that keeps Tx(l2) as a separate tool transform)
    assert not (r.hint and re.search(r"row 2: .*\ba = 0\b", r.hint)), r.hint


def test_dh_modified_table_wrong_a_names_its_row():
    # Craig: row 2 is (alpha1, a1, d2, theta2) and places joint 2's axis; a1 = 12, not l1 = 10
    r = one("""\
        - id: t
          kind: dh
          answer:
            convention: mdh
            table: [[0, 0, 0, q1], [0, 12, 0, q2]]
            tool: {xyz: [5, 0, 0]}
        """)
    assert not r.passed
    assert "row 2" in r.message, r.message


def test_dh_modified_table_labelled_standard_gets_the_hint():
    # Craig's table of bk_rr (alpha, a, d, theta) with the tool Tx(l2), but
    # labelled 'dh': as standard DH it is Rz(q1) Rz(q2) Tx(l1) Tx(l2) — wrong.
    wrong = one("""\
        - id: t
          kind: dh
          answer:
            convention: dh
            columns: [alpha, a, d, theta]
            table: [[0, 0, 0, q1], [0, l1, 0, q2]]
            tool: {xyz: [5, 0, 0]}
        """)
    assert not wrong.passed
    assert wrong.hint and "modified" in wrong.hint.lower() and "standard" in wrong.hint.lower(), \
        wrong.hint
    right = one("""\
        - id: t
          kind: dh
          answer:
            convention: mdh
            table: [[0, 0, 0, q1], [0, l1, 0, q2]]
            tool: {xyz: [5, 0, 0]}
        """)
    assert right.passed, right.message


# ---------------------------------------------------------------------------
# link (puma560: standard DH, metres; bk_scara_euler: modified DH)

PUMA_Q3 = 37.0
PUMA_A3 = dh_link(math.radians(PUMA_Q3), 0.15005, 0.0203, math.radians(-90))


def link_item(M, q="[0, 0, 37, 0, 0, 0]", extra=""):
    return f"""\
        - id: l3
          kind: link
          link: 3
          q: {q}
          answer: {js(M)}
        {extra}"""


def test_link_right_by_hand():
    r = one(link_item(PUMA_A3), robot="puma560")
    assert r.passed, r.message


def test_link_q_as_just_q_i():
    r = one(link_item(PUMA_A3, q="37"), robot="puma560")
    assert r.passed, r.message


def test_link_modified_dh_matches_craig_formula():
    q2 = 25.0
    M = mdh_link(0.0, SL1, math.radians(q2), 0.0)
    r = one(f"""\
        - id: l2
          kind: link
          link: 2
          q: [10, {q2}, 5, 0, 0, 0]
          answer: {js(M)}
        """, robot="bk_scara_euler")
    assert r.passed, r.message
    # the standard-DH formula with the same numbers is wrong for this robot
    r = one(f"""\
        - id: l2
          kind: link
          link: 2
          q: [10, {q2}, 5, 0, 0, 0]
          answer: {js(dh_link(math.radians(q2), 0.0, SL1, 0.0))}
        """, robot="bk_scara_euler")
    # (Rz(θ) Tx(a) is not Tx(a) Rz(θ): the translation differs)
    assert not r.passed, r.message
    M3 = mdh_link(math.pi, SL2, 0, 12)
    D3 = dh_link(0, 12, SL2, math.pi)
    assert not np.allclose(M3, D3)
    r = one(f"""\
        - id: l3
          kind: link
          link: 3
          q: [0, 0, 12, 0, 0, 0]
          answer: {js(D3)}
        """, robot="bk_scara_euler")
    assert not r.passed


def test_link_full_transpose_is_wrong_with_a_transposed_hint():
    r = one(link_item(PUMA_A3.T), robot="puma560")
    assert not r.passed
    assert r.hint and "transpose" in r.hint.lower(), r.hint


def test_link_rotation_transposed_is_wrong_with_a_transposed_hint():
    M = PUMA_A3.copy()
    M[:3, :3] = M[:3, :3].T
    r = one(link_item(M), robot="puma560")
    assert not r.passed
    assert r.hint and "transpose" in r.hint.lower(), r.hint


def test_link_inverse_is_wrong_with_an_inverse_hint():
    r = one(link_item(np.linalg.inv(PUMA_A3)), robot="puma560")
    assert not r.passed
    assert r.hint and "invers" in r.hint.lower(), r.hint


# ---------------------------------------------------------------------------
# fk

def fk_item(answer: str, q="[30, -60]", extra=""):
    return f"""\
        - id: f
          kind: fk
          q: {q}
          answer: {answer}
        {extra}"""


def test_fk_rr_4x4_by_hand():
    T = rr_fk(*np.radians([30, -60]))
    assert np.allclose(T[:2, 3], [10 * math.sqrt(3) / 2 + 5 * math.sqrt(3) / 2, 5 - 2.5])
    assert one(fk_item(js(T))).passed
    assert one(fk_item(js(T[:3]))).passed          # 3x4 accepted


def test_fk_rr_position_and_rpy_by_hand():
    # p = (l1 c1 + l2 c12, l1 s1 + l2 s12, 0) = (12.9904, 2.5, 0); rpy = (0, 0, q1 + q2)
    r = one(fk_item("{position: [12.9904, 2.5, 0], rpy: [0, 0, -30]}"))
    assert r.passed, r.message
    r = one(fk_item("{position: [12.9904, 2.5, 0], rpy: [0, 0, 30]}"))
    assert not r.passed
    r = one(fk_item("{xyz: [12.9904, 2.5, 0]}"))      # only what is given is graded
    assert r.passed, r.message


def test_fk_puma_4x4_by_my_dh_product():
    q = [10, 20, 30, 40, 50, 60]
    r = one(fk_item(js(puma_fk(q)), q=js(q)), robot="puma560")
    assert r.passed, r.message


def test_fk_radians_slip():
    # the student typed the degree values into a calculator in radian mode
    T = rr_fk(30.0, -60.0)
    r = one(fk_item(js(T)))
    assert not r.passed
    assert r.hint and "radian" in r.hint.lower(), r.hint
    r = one(fk_item(js(puma_fk([10, 20, 30, 40, 50, 60], degrees=False)),
                    q="[10, 20, 30, 40, 50, 60]"), robot="puma560")
    assert not r.passed
    assert r.hint and "radian" in r.hint.lower(), r.hint


def test_fk_one_sign_flipped_names_the_joint():
    T = rr_fk(*np.radians([30, 60]))                # joint 2 with the wrong sign
    r = one(fk_item(f"{{position: {js(T[:3, 3])}, rpy: [0, 0, 90]}}"))
    assert not r.passed
    assert r.hint and "joint 2" in r.hint and "sign" in r.hint, r.hint
    q = [10, 20, 30, 40, 50, 60]
    r = one(fk_item(js(puma_fk([10, 20, 30, 40, -50, 60])), q=js(q)), robot="puma560")
    assert not r.passed
    assert r.hint and "joint 5" in r.hint and "sign" in r.hint, r.hint


def test_fk_two_joints_swapped():
    T = rr_fk(*np.radians([-60, 30]))
    r = one(fk_item(js(T)))
    assert not r.passed
    assert r.hint and "swap" in r.hint and "joint 1" in r.hint and "joint 2" in r.hint, r.hint
    q = [10, 20, 30, 40, 50, 60]
    r = one(fk_item(js(puma_fk([10, 30, 20, 40, 50, 60])), q=js(q)), robot="puma560")
    assert not r.passed
    assert r.hint and "swap" in r.hint and "joint 2" in r.hint and "joint 3" in r.hint, r.hint


def quat_of(R):
    w = math.sqrt(max(0.0, 1 + np.trace(R))) / 2
    return [w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w),
            (R[1, 0] - R[0, 1]) / (4 * w)]


def axis_angle_of(R):
    ang = math.acos((np.trace(R) - 1) / 2)
    axis = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / (2 * math.sin(ang))
    return [*axis, math.degrees(ang)]


def zyz_of(R):
    b = math.acos(R[2, 2])
    return [math.degrees(math.atan2(R[1, 2], R[0, 2])), math.degrees(b),
            math.degrees(math.atan2(R[2, 1], -R[2, 0]))]


@pytest.mark.parametrize("form", ["quat", "axis_angle", "euler_zyz", "matrix"])
def test_fk_orientation_forms(form):
    q = [10, 20, 30, 40, 50, 60]
    T = puma_fk(q)
    R = T[:3, :3]
    value = {"quat": quat_of(R), "axis_angle": axis_angle_of(R), "euler_zyz": zyz_of(R),
             "matrix": R}[form]
    if form == "euler_zyz":                  # my Z-Y-Z angles rebuild R
        a, b, c = np.radians(value)
        assert np.allclose((rz(a) @ ry(b) @ rz(c))[:3, :3], R)
    r = one(fk_item(f"{{position: {js(T[:3, 3])}, {form}: {js(value)}}}", q=js(q)),
            robot="puma560")
    assert r.passed, r.message
    # the same orientation of a configuration 5 deg away in joint 6 is wrong
    R2 = puma_fk([10, 20, 30, 40, 50, 65])[:3, :3]
    value = {"quat": quat_of(R2), "axis_angle": axis_angle_of(R2), "euler_zyz": zyz_of(R2),
             "matrix": R2}[form]
    r = one(fk_item(f"{{position: {js(T[:3, 3])}, {form}: {js(value)}}}", q=js(q)),
            robot="puma560")
    assert not r.passed, r.message


def test_fk_transposed_and_inverse_hints():
    q = [10, 20, 30, 40, 50, 60]
    T = puma_fk(q)
    M = T.copy()
    M[:3, :3] = T[:3, :3].T
    r = one(fk_item(js(M), q=js(q)), robot="puma560")
    assert not r.passed and r.hint and "transpose" in r.hint.lower(), r.hint
    r = one(fk_item(js(np.linalg.inv(T)), q=js(q)), robot="puma560")
    assert not r.passed and r.hint and "invers" in r.hint.lower(), r.hint


# ---------------------------------------------------------------------------
# ik

def ik_item(answer: str, pose="{xyz: [12.99, 2.5, 0]}", extra=""):
    return f"""\
        - id: i
          kind: ik
          pose: {pose}
          answer: {answer}
        {extra}"""


def test_ik_example_4_2_right_sets():
    r = one(ik_item("[[30, -60], [-8.2, 60]]"))
    assert r.passed, (r.message, r.hint)
    assert [s["status"] for s in r.details["sets"]] == ["correct", "correct"]
    assert not r.details["missed"]


def test_ik_example_4_2_wrong_pairings():
    r = one(ik_item("[[30, 60], [-8.2, -60]]"))
    assert not r.passed
    assert [s["status"] for s in r.details["sets"]] == ["wrong", "wrong"]
    assert len(r.details["missed"]) == 2
    # my FK of (30, 60): far from the target, and the report says so
    miss = np.linalg.norm(rr_fk(*np.radians([30, 60]))[:2, 3] - [12.99, 2.5])
    assert r.details["sets"][0]["residual"]["position"] == pytest.approx(miss, abs=1e-3)


def test_ik_one_set_only_lists_the_other_as_missed():
    r = one(ik_item("[[30, -60]]"))
    assert not r.passed
    assert [s["status"] for s in r.details["sets"]] == ["correct"]
    (m,) = r.details["missed"]
    other = [s for s in rr_ik(12.99, 2.5) if s[1] > 0][0]      # (-8.2, 60) by the law of cosines
    assert np.allclose(m["solution_q"], other, atol=1e-6)
    assert "missed" in r.message


def test_ik_flat_single_set_accepted():
    r = one(ik_item("[30, -60]"))
    assert not r.passed and len(r.details["missed"]) == 1


def test_ik_empty_answer_for_unreachable_target_is_right():
    assert rr_ik(20, 0) == []                       # reach l1 + l2 = 15
    r = one(ik_item("[]", pose="{xyz: [20, 0, 0]}"))
    assert r.passed, r.message


def test_ik_empty_answer_for_reachable_target_is_wrong():
    r = one(ik_item("[]"))
    assert not r.passed
    assert len(r.details["missed"]) == 2


def test_ik_angles_modulo_360():
    r = one(ik_item("[[390, -60], [-8.2, 420]]"))
    assert r.passed, (r.message, r.hint)


SCARA_POSE = "{xyz: [28, 31, 6], rpy: [42, -17, 25]}"


def scara_solutions():
    return scara_ik((28, 31, 6), rpy_matrix(42, -17, 25))


def test_ik_example_4_6_book_set_is_wrong_and_names_theta4():
    sols = scara_solutions()
    # the right theta4 for the book's theta1 = 63.03, theta5 = +135.29 branch
    mine = [s for s in sols if abs(s[0] - 63.03) < 0.05 and abs(s[4] - 135.29) < 0.05]
    assert len(mine) == 1
    right_t4 = mine[0][3]
    assert right_t4 == pytest.approx(108.765, abs=1e-3)
    assert abs(wrap180(mine[0][5] - (-65.44))) < 0.05     # theta6 agrees with the book
    r = one(ik_item("[[63.03, -37.25, 12, -72.2, 135.29, -65.44]]", pose=SCARA_POSE),
            robot="bk_scara_euler")
    assert not r.passed
    (s,) = r.details["sets"]
    assert s["status"] == "wrong"
    note = s["note"]
    assert "theta4" in note, note
    numbers = [float(x) for x in re.findall(r"-?\d+\.\d+", note)]
    assert any(abs(x - 108.77) < 0.006 for x in numbers), note
    assert "theta4" in r.hint


def test_ik_example_4_6_four_right_sets_pass():
    sols = scara_solutions()
    assert len(sols) == 4
    answer = js(np.round(sols, 3))
    r = one(ik_item(answer, pose=SCARA_POSE), robot="bk_scara_euler")
    assert r.passed, (r.message, r.hint)
    assert r.details["required"] == 4
    # three of the four are not enough
    r = one(ik_item(js(np.round(sols[:3], 3)), pose=SCARA_POSE), robot="bk_scara_euler")
    assert not r.passed and len(r.details["missed"]) == 1
    assert np.allclose(wrap180(np.subtract(r.details["missed"][0]["solution_q"], sols[3])), 0,
                       atol=1e-3)


def test_ik_pose_as_T_and_as_q():
    sols = scara_solutions()
    T = scara_fk(sols[0])
    r = one(ik_item(js(np.round(sols, 3)), pose=f"{{T: {js(T)}}}"), robot="bk_scara_euler")
    assert r.passed, (r.message, r.hint)
    # pose: {q: ...} is the whole pose FK gives, orientation (q1 + q2 = -30) included:
    # the other elbow reaches the point with q1 + q2 = 51.8, so it is not a solution
    assert one(ik_item("[[30, -60]]", pose="{q: [30, -60]}")).passed
    mate = [s for s in rr_ik(*rr_fk(*np.radians([30, -60]))[:2, 3]) if s[1] > 0][0]
    assert abs(sum(mate) - 51.8) < 0.1
    r = one(ik_item(f"[[30, -60], {js(np.round(mate, 3))}]", pose="{q: [30, -60]}"))
    assert not r.passed
    assert [s["status"] for s in r.details["sets"]] == ["correct", "wrong"]
    # the position alone has both elbows
    assert one(ik_item(f"[[30, -60], {js(np.round(mate, 3))}]",
                       pose="{xyz: [12.990381, 2.5, 0]}")).passed


def test_ik_joint_limits():
    # z = -20 needs d3 = h1 - d4 - z = 38, beyond d3's limits [0, 30]: no solution counts
    pose = "{xyz: [28, 31, -20], rpy: [42, -17, 25]}"
    sols = scara_ik((28, 31, -20), rpy_matrix(42, -17, 25))
    assert all(abs(s[2] - 38) < 1e-9 for s in sols)
    assert one(ik_item("[]", pose=pose), robot="bk_scara_euler").passed
    r = one(ik_item("[]", pose=pose, extra="  limits: ignore\n"), robot="bk_scara_euler")
    assert not r.passed and len(r.details["missed"]) == 4
    r = one(ik_item(js(np.round(sols, 3)), pose=pose, extra="  limits: ignore\n"),
            robot="bk_scara_euler")
    assert r.passed, (r.message, r.hint)
    r = one(ik_item(js(np.round(sols[:1], 3)), pose=pose), robot="bk_scara_euler")
    assert not r.passed and "limit" in r.details["sets"][0]["note"]


# ---------------------------------------------------------------------------
# jacobian

Q_J = (30.0, -60.0)
J_RR = rr_jacobian(*np.radians(Q_J))


def jac_item(M, q=Q_J, extra=""):
    return f"""\
        - id: j
          kind: jacobian
          q: {js(q)}
          answer: {js(M)}
        {extra}"""


def test_jacobian_rr_by_hand_linear_rows_first():
    r = one(jac_item(J_RR))
    assert r.passed, (r.message, r.hint)
    assert "vx vy vz wx wy wz" in r.message


def test_jacobian_rr_angular_rows_first():
    r = one(jac_item(np.vstack([J_RR[3:], J_RR[:3]])))
    assert r.passed, (r.message, r.hint)
    assert "wx wy wz vx vy vz" in r.message


def test_jacobian_rr_planar_rows():
    r = one(jac_item(J_RR[:2]))
    assert r.passed, (r.message, r.hint)


def test_jacobian_transposed_is_wrong_with_hint():
    r = one(jac_item(J_RR.T))
    assert not r.passed
    assert r.hint and "transpose" in r.hint.lower(), r.hint


def test_jacobian_wrong_entry():
    J = J_RR.copy()
    J[0, 1] += 1.0
    r = one(jac_item(J))
    assert not r.passed


def test_jacobian_per_degree_hint():
    r = one(jac_item(J_RR * math.pi / 180))
    assert not r.passed
    assert r.hint and "degree" in r.hint.lower(), r.hint


def test_jacobian_puma_tool_frame():
    q = [10, 20, 30, 40, 50, 60]
    J = fd_jacobian(lambda x: puma_fk(x, degrees=False), np.radians(q))
    Rt = puma_fk(q)[:3, :3].T
    Jt = np.vstack([Rt @ J[:3], Rt @ J[3:]])            # both rows expressed in the tool frame
    r = one(jac_item(Jt, q=q, extra="  frame: tool\n"), robot="puma560")
    assert r.passed, (r.message, r.hint)
    r = one(jac_item(J, q=q, extra="  frame: tool\n"), robot="puma560")
    assert not r.passed
    assert r.hint and "base" in r.hint, r.hint


def test_jacobian_puma_by_finite_differences():
    q = [10, 20, 30, 40, 50, 60]
    J = fd_jacobian(lambda x: puma_fk(x, degrees=False), np.radians(q))
    r = one(jac_item(J, q=q), robot="puma560")
    assert r.passed, (r.message, r.hint)


# ---------------------------------------------------------------------------
# reach and singular (decided by hand)

@pytest.mark.parametrize("xyz,truth", [
    ((12.99, 2.5, 0), True),      # |p| = 13.23, between |l1 - l2| = 5 and l1 + l2 = 15
    ((20, 0, 0), False),          # beyond l1 + l2
    ((3, 0, 0), False),           # inside the hole of radius l1 - l2
    ((0, 14.9, 0), True),
])
def test_reach(xyz, truth):
    for answer, passed in (("yes", truth), ("no", not truth)):
        r = one(f"""\
            - id: r
              kind: reach
              pose: {{xyz: {js(xyz)}}}
              answer: {answer}
            """)
        assert r.passed == passed, (xyz, answer, r.message)


def test_reach_respects_joint_limits():
    # bk_scara_euler: z = -20 needs d3 = 38 > 30 (limit); z = 6 needs d3 = 12
    pose_far = "{xyz: [28, 31, -20], rpy: [42, -17, 25]}"
    pose_ok = "{xyz: [28, 31, 6], rpy: [42, -17, 25]}"
    assert one(f"- {{id: r, kind: reach, pose: {pose_ok}, answer: yes}}",
               robot="bk_scara_euler").passed
    r = one(f"- {{id: r, kind: reach, pose: {pose_far}, answer: no}}", robot="bk_scara_euler")
    assert r.passed, r.message


def test_reach_yaml_booleans():
    assert one("- {id: r, kind: reach, pose: {xyz: [12.99, 2.5, 0]}, answer: true}").passed
    assert one("- {id: r, kind: reach, pose: {xyz: [20, 0, 0]}, answer: false}").passed


def puma_is_singular(q_deg) -> bool:
    J = fd_jacobian(lambda x: puma_fk(x, degrees=False), np.radians(q_deg))
    s = np.linalg.svd(J, compute_uv=False)
    return s[-1] / s[0] < 1e-6


@pytest.mark.parametrize("robot,q,truth", [
    ("bk_rr", (30, 0), True),                  # arm stretched: det [J_v] = l1 l2 sin q2 = 0
    ("bk_rr", (30, 180), True),                # folded back
    ("bk_rr", (30, 90), False),
    ("puma560", (10, 20, 30, 40, 0, 60), True),    # wrist: q5 = 0 lines up axes 4 and 6
    ("puma560", (10, 20, 30, 40, 50, 60), False),
])
def test_singular(robot, q, truth):
    if robot == "puma560":
        assert puma_is_singular(q) == truth      # my own finite-difference Jacobian agrees
    else:
        assert (abs(L1 * L2 * math.sin(math.radians(q[1]))) < 1e-9) == truth
    for answer, passed in (("yes", truth), ("no", not truth)):
        r = one(f"- {{id: s, kind: singular, q: {js(q)}, answer: {answer}}}", robot=robot)
        assert r.passed == passed, (robot, q, answer, r.message)


# ---------------------------------------------------------------------------
# tolerances

def test_tolerance_sheet_and_item_override_ik_angle():
    # (30.3, -60): 0.3 deg off joint 1 -> wrong at the default 0.1 deg
    item = ik_item("[[30.3, -60], [-8.2, 60]]")
    assert not one(item).passed
    assert one(item, head="tolerance: {angle: 0.5}\n").passed
    assert one(ik_item("[[30.3, -60], [-8.2, 60]]", extra="  tolerance: {angle: 0.5}\n")).passed
    assert not one(ik_item("[[30.3, -60], [-8.2, 60]]", extra="  tolerance: {angle: 0.05}\n"),
                   head="tolerance: {angle: 0.5}\n").passed


def test_tolerance_position_and_matrix():
    p = rr_fk(*np.radians([30, -60]))[:3, 3] + [0.05, 0, 0]
    item = fk_item(f"{{position: {js(p)}}}")
    assert not one(item).passed                          # default 0.01 on bk_rr
    assert one(item, head="tolerance: {position: 0.1}\n").passed
    assert one(fk_item(f"{{position: {js(p)}}}", extra="  tolerance: {position: 0.1}\n")).passed
    M = PUMA_A3.copy()
    M[0, 0] += 0.003                                     # default matrix tolerance 0.002
    assert not one(link_item(M), robot="puma560").passed
    assert one(link_item(M, extra="  tolerance: {matrix: 0.005}\n"), robot="puma560").passed
    assert one(link_item(M), robot="puma560", head="tolerance: {matrix: 0.005}\n").passed


def test_default_tolerances_reported_and_used(tmp_path):
    path = tmp_path / "hw.yaml"
    path.write_text(sheet_text(fk_item("{xyz: [12.9904, 2.5, 0]}")))
    out = kincalc("check", str(path), "--json")
    assert out.returncode == 0, out.stderr
    tol = json.loads(out.stdout)["tolerance"]
    assert tol["angle"] == pytest.approx(0.1)
    assert tol["matrix"] == pytest.approx(0.002)
    assert 0.001 <= tol["position"] <= 0.05            # ~1e-3 x the 15-unit arm
    # the reported position tolerance is the one used
    p = rr_fk(*np.radians([30, -60]))[:3, 3]
    assert one(fk_item(f"{{position: {js(p + [0.5 * tol['position'], 0, 0])}}}")).passed
    assert not one(fk_item(f"{{position: {js(p + [2 * tol['position'], 0, 0])}}}")).passed
    # on a radian sheet the default angle tolerance is 0.1 deg in rad
    rad = parse_sheet(sheet_text(fk_item("{xyz: [12.9904, 2.5, 0]}", q="[0.5236, -1.0472]"),
                                 head="units: {angle: rad}\n"), "hw.yaml", ".")
    from kincalc.homework import Report
    t = Report(rad, []).to_dict()["tolerance"]
    assert t["angle"] == pytest.approx(math.radians(0.1), rel=0.05)


# ---------------------------------------------------------------------------
# units

def test_radian_sheet_on_a_degree_robot():
    head = "units: {angle: rad}\n"
    sols = [np.radians(s) for s in rr_ik(12.99, 2.5)]
    r = one(ik_item(js(np.round(sols, 5))), head=head)
    assert r.passed, (r.message, r.hint)
    # the same numbers read as degrees are wrong
    assert not one(ik_item(js(np.round(sols, 5)))).passed
    q = np.radians([30, -60])
    T = rr_fk(*q)
    r = one(fk_item(f"{{position: {js(T[:3, 3])}, rpy: {js([0, 0, q[0] + q[1]])}}}", q=js(q)),
            head=head)
    assert r.passed, r.message
    r = one(jac_item(rr_jacobian(*q), q=q), head=head)
    assert r.passed, r.message


def test_millimetre_sheet_on_a_metre_robot():
    q = [10, 20, 30, 40, 50, 60]
    T = puma_fk(q)
    r = one(fk_item(f"{{position: {js(T[:3, 3] * 1000)}}}", q=js(q)), robot="puma560",
            head="units: {length: mm}\n")
    assert r.passed, r.message
    r = one(fk_item(f"{{position: {js(T[:3, 3])}}}", q=js(q)), robot="puma560",
            head="units: {length: mm}\n")
    assert not r.passed


# ---------------------------------------------------------------------------
# score, unanswered items

def test_score_and_points():
    rep = report("""\
        - {id: a, kind: singular, q: [30, 0], answer: yes, points: 2}
        - {id: b, kind: singular, q: [30, 90], answer: yes}
        - {id: c, kind: reach, pose: {xyz: [20, 0, 0]}}
        """)
    assert [r.passed for r in rep.items] == [True, False, False]
    assert "no answer" in rep.items[2].message
    s = rep.to_dict()["score"]
    assert (s["points"], s["total"], s["percent"]) == (2, 4, 50.0)
    assert not rep.all_correct


# ---------------------------------------------------------------------------
# invalid sheets: exit 2, one line "file:LINE: message", no traceback

INVALID = [
    # (name, sheet text, expected line(s), words the message must contain)
    ("unknown kind",
     "robot: bk_rr\nitems:\n  - id: a\n    kind: fkk\n    q: [1, 2]\n", {4}, ["kind", "fkk"]),
    ("missing id",
     "robot: bk_rr\nitems:\n  - kind: fk\n    q: [1, 2]\n", {3}, ["id"]),
    ("duplicate id",
     "robot: bk_rr\nitems:\n  - {id: a, kind: singular, q: [1, 2]}\n"
     "  - {id: a, kind: singular, q: [3, 4]}\n", {4}, ["'a'"]),
    ("q of the wrong length",
     "robot: bk_rr\nitems:\n  - id: a\n    kind: fk\n    q: [1, 2, 3]\n", {5}, ["q", "3", "2"]),
    ("a non-number",
     "robot: bk_rr\nitems:\n  - id: a\n    kind: fk\n    q: [1, sixty]\n", {5}, ["sixty"]),
    ("unknown robot",
     "title: x\nrobot: bk_rrr\nitems:\n  - {id: a, kind: singular, q: [1, 2]}\n", {2},
     ["bk_rrr"]),
    ("unknown top-level key",
     "robot: bk_rr\nstudnet: Ada\nitems:\n  - {id: a, kind: singular, q: [1, 2]}\n", {2},
     ["studnet"]),
    ("dh variable in two cells",
     "robot: bk_rr\nitems:\n  - id: a\n    kind: dh\n    answer:\n      convention: dh\n"
     "      table:\n        - [q1, 0, l1, 0]\n        - [q2, q2, l2, 0]\n", {9}, ["row 2"]),
    ("dh two variables in one row",
     "robot: bk_rr\nitems:\n  - id: a\n    kind: dh\n    answer:\n      convention: dh\n"
     "      table:\n        - [q1, 0, x, 0]\n        - [q2, 0, l2, 0]\n", {8}, ["row 1"]),
    ("missing robot", "items:\n  - {id: a, kind: singular, q: [1, 2]}\n", {1}, ["robot"]),
    ("empty items", "robot: bk_rr\nitems: []\n", {2}, ["items"]),
    ("link out of range",
     "robot: bk_rr\nitems:\n  - {id: a, kind: link, link: 3, q: [1, 2], answer: [[1]]}\n", {3},
     ["link"]),
    ("unknown item key",
     "robot: bk_rr\nitems:\n  - id: a\n    kind: fk\n    q: [1, 2]\n    anwser: [[1]]\n", {6},
     ["anwser"]),
    ("bad yes/no",
     "robot: bk_rr\nitems:\n  - id: a\n    kind: singular\n    q: [1, 2]\n    answer: maybe\n",
     {6}, ["maybe"]),
    ("negative tolerance",
     "robot: bk_rr\ntolerance: {angle: -1}\nitems:\n  - {id: a, kind: singular, q: [1, 2]}\n",
     {2}, ["angle"]),
    ("sheet version",
     "kincalc-sheet: 2\nrobot: bk_rr\nitems:\n  - {id: a, kind: singular, q: [1, 2]}\n",
     {1}, ["2"]),
    ("ik set of the wrong length",
     "robot: bk_rr\nitems:\n  - id: a\n    kind: ik\n    pose: {xyz: [12.99, 2.5, 0]}\n"
     "    answer:\n      - [30, -60]\n      - [30, -60, 0]\n", {8}, ["set 2"]),
    ("fk answer of the wrong shape",
     "robot: bk_rr\nitems:\n  - id: a\n    kind: fk\n    q: [1, 2]\n    answer: [[1, 0], [0, 1]]\n",
     {6}, ["4x4"]),
    ("length unit on a unitless robot",
     "robot: bk_rr\nunits: {length: mm}\nitems:\n  - {id: a, kind: singular, q: [1, 2]}\n",
     {2}, ["mm"]),
    # found by the review of the new commands (each was an internal error or a wrong grade)
    ("zero quaternion in an fk answer",
     "robot: bk_rr\nitems:\n  - id: a\n    kind: fk\n    q: [1, 2]\n"
     "    answer: {position: [1, 2, 0], quat: [0, 0, 0, 0]}\n", {6}, ["quat", "zero"]),
    ("zero axis in an fk answer",
     "robot: bk_rr\nitems:\n  - id: a\n    kind: fk\n    q: [1, 2]\n"
     "    answer: {position: [1, 2, 0], axis_angle: [0, 0, 0, 30]}\n", {6}, ["axis"]),
    ("position and T in one fk answer",
     "robot: bk_rr\nitems:\n  - id: a\n    kind: fk\n    q: [1, 2]\n    answer:\n"
     "      position: [1, 2, 0]\n      T: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]\n",
     {7}, ["T", "position"]),
    ("a dh variable used by two rows",
     "robot: planar_3r\nitems:\n  - id: a\n    kind: dh\n    answer:\n      convention: dh\n"
     "      table:\n        - [q1, 0, 1, 0]\n        - [q1, 0, 1, 0]\n        - [q3, 0, 1, 0]\n",
     {9}, ["q1", "row 2"]),
    ("an absurdly large number",
     "robot: bk_rr\nitems:\n  - {id: a, kind: fk, q: [1, 1e200]}\n", {3}, ["too large"]),
]


@pytest.mark.parametrize("name,text,lines,words", INVALID, ids=[c[0] for c in INVALID])
def test_invalid_sheet_in_process(name, text, lines, words):
    with pytest.raises(SheetError) as info:
        parse_sheet(text, "bad.yaml", ".")
    assert info.value.line in lines, (info.value.line, str(info.value))
    for w in words:
        assert w in str(info.value), str(info.value)


# the CLI: a subset (each one is a subprocess)
CLI_INVALID = ["unknown kind", "missing id", "duplicate id", "q of the wrong length",
               "a non-number", "unknown robot", "unknown top-level key",
               "dh variable in two cells"]


@pytest.mark.parametrize("name", CLI_INVALID)
def test_invalid_sheet_cli(name, tmp_path):
    _, text, lines, words = next(c for c in INVALID if c[0] == name)
    (tmp_path / "bad.yaml").write_text(text)
    out = kincalc("check", "bad.yaml", cwd=tmp_path)
    assert out.returncode == 2, (out.stdout, out.stderr)
    assert out.stdout == ""
    err = out.stderr.splitlines()
    assert len(err) == 1, out.stderr
    assert "Traceback" not in out.stderr and "internal error" not in out.stderr
    # the project's convention: "kincalc: error: FILE:LINE: message" (README)
    m = re.match(r"(?:kincalc: error: )?bad\.yaml:(\d+): (.+)", err[0])
    assert m, err[0]
    assert int(m.group(1)) in lines, err[0]
    for w in words:
        assert w in m.group(2), err[0]


def test_missing_sheet_file(tmp_path):
    out = kincalc("check", "nope.yaml", cwd=tmp_path)
    assert out.returncode == 2
    assert len(out.stderr.splitlines()) == 1 and "nope.yaml" in out.stderr
    assert "Traceback" not in out.stderr


# ---------------------------------------------------------------------------
# exit statuses, --json, several sheets

RIGHT = "robot: bk_rr\nstudent: Ada\nitems:\n  - {id: 1a, kind: singular, q: [30, 0], answer: yes}\n" \
        "  - {id: 1b, kind: ik, pose: {xyz: [12.99, 2.5, 0]}, answer: [[30, -60], [-8.2, 60]]}\n"
WRONG = "robot: bk_rr\nitems:\n  - {id: 1a, kind: singular, q: [30, 0], answer: yes}\n" \
        "  - {id: 1b, kind: singular, q: [30, 90], answer: yes, points: 3}\n"
BAD = "robot: bk_rr\nitems:\n  - {id: 1a, kind: nope, q: [30, 0], answer: yes}\n"


@pytest.fixture
def sheets(tmp_path):
    for name, text in (("right.yaml", RIGHT), ("wrong.yaml", WRONG), ("bad.yaml", BAD)):
        (tmp_path / name).write_text(text)
    return tmp_path


def test_exit_0_and_json_document(sheets):
    out = kincalc("check", "right.yaml", "--json", cwd=sheets)
    assert out.returncode == 0, out.stderr
    assert out.stdout.count("\n") == 1
    doc = json.loads(out.stdout)
    assert doc["kincalc"] and doc["command"] == "check"
    assert doc["sheet"].endswith("right.yaml")
    assert doc["robot"]["name"] == "bk_rr"
    assert doc["units"] == {"angle": "deg", "length": "unitless"}
    assert set(doc["tolerance"]) == {"position", "angle", "matrix"}
    assert doc["student"] == "Ada"
    assert [i["id"] for i in doc["items"]] == ["1a", "1b"]
    for item in doc["items"]:
        for key in ("id", "kind", "passed", "points", "error", "message", "hint", "details"):
            assert key in item
        assert item["passed"] is True
    assert [i["kind"] for i in doc["items"]] == ["singular", "ik"]
    assert doc["score"]["points"] == 2 and doc["score"]["total"] == 2
    assert doc["score"]["percent"] == 100.0


def test_exit_1_and_score(sheets):
    out = kincalc("check", "wrong.yaml", "--json", cwd=sheets)
    assert out.returncode == 1, out.stderr
    doc = json.loads(out.stdout)
    assert [i["passed"] for i in doc["items"]] == [True, False]
    assert doc["score"]["points"] == 1 and doc["score"]["total"] == 4
    assert doc["score"]["percent"] == 25.0
    out = kincalc("check", "wrong.yaml", cwd=sheets)          # tables
    assert out.returncode == 1
    assert "wrong" in out.stdout and "1 of 4 points" in out.stdout


def test_several_sheets_worst_status(sheets):
    out = kincalc("check", "right.yaml", "wrong.yaml", "--json", cwd=sheets)
    assert out.returncode == 1, out.stderr
    docs = [json.loads(line) for line in out.stdout.splitlines()]
    assert [d["sheet"].rsplit("/", 1)[-1] for d in docs] == ["right.yaml", "wrong.yaml"]
    out = kincalc("check", "wrong.yaml", "bad.yaml", "right.yaml", "--json", cwd=sheets)
    assert out.returncode == 2
    docs = [json.loads(line) for line in out.stdout.splitlines()]
    assert len(docs) == 3                                   # the valid sheets are still graded,
    assert [sorted(d) for d in docs][1] == ["error", "sheet"]  # the invalid one has its line
    assert "bad.yaml:3:" in docs[1]["error"] and "kincalc" in docs[0] and "kincalc" in docs[2]
    assert len(out.stderr.splitlines()) == 1 and "bad.yaml:3:" in out.stderr
    assert "Traceback" not in out.stderr
    out = kincalc("check", "right.yaml", "right.yaml", "--quiet", cwd=sheets)
    assert out.returncode == 0
    assert out.stdout.count("score:") == 2


def test_robot_file_next_to_the_sheet(tmp_path):
    # an RR arm in standard DH: same FK as bk_rr
    (tmp_path / "arm.yaml").write_text(
        "name: arm\nconvention: dh\nunits: {length: unitless, angle: deg}\n"
        "joints:\n  - {name: q1, type: revolute, alpha: 0, a: 10, d: 0, theta: 0}\n"
        "  - {name: q2, type: revolute, alpha: 0, a: 5, d: 0, theta: 0}\n")
    T = rr_fk(*np.radians([30, -60]))
    rep = report(fk_item(js(T)), robot="arm.yaml", folder=str(tmp_path))
    assert rep.items[0].passed, rep.items[0].message
    text = ("robot:\n  convention: dh\n  units: {length: unitless, angle: deg}\n  joints:\n"
            "    - {name: q1, type: revolute, alpha: 0, a: 10, d: 0, theta: 0}\n"
            "    - {name: q2, type: revolute, alpha: 0, a: 5, d: 0, theta: 0}\n"
            "items:\n" + textwrap.indent(textwrap.dedent(fk_item(js(T))), "  "))
    rep = grade(parse_sheet(text, "inline.yaml", "."))
    assert rep.items[0].passed, rep.items[0].message


# ---------------------------------------------------------------------------
# shipped examples

EXAMPLES = sorted(glob.glob(os.path.join(ROOT, "examples", "*.yaml")))


def example(name):
    path = os.path.join(ROOT, "examples", name)
    assert os.path.isfile(path), f"examples/{name} is shipped"
    return load_sheet(path)


def test_examples_are_shipped():
    assert EXAMPLES, "examples/*.yaml"


@pytest.mark.parametrize("path", EXAMPLES, ids=[os.path.basename(p) for p in EXAMPLES])
def test_shipped_examples_load_and_grade(path):
    sheet = load_sheet(path)
    assert sheet.items
    rep = grade(sheet)
    assert len(rep.items) == len(sheet.items)
    doc = rep.to_dict()
    json.dumps(doc)                                    # serialisable


def test_example_4_2_sheet():
    rep = grade(example("bk_example_4_2.yaml"))
    (r,) = rep.items
    # by the law of cosines only zeta2 = (30, -60) and zeta3 = (-8.2, 60) reach (12.99, 2.5)
    truth = rr_ik(12.99, 2.5)
    expect = ["correct" if any(np.allclose(q, t, atol=0.1) for t in truth) else "wrong"
              for q in ([30, 60], [30, -60], [-8.2, 60], [-8.2, -60])]
    assert expect == ["wrong", "correct", "correct", "wrong"]
    assert [s["status"] for s in r.details["sets"]] == expect
    assert not r.passed and not r.details["missed"]


def test_example_4_6_book_answer_sheet():
    rep = grade(example("bk_example_4_6_book_answer.yaml"))
    link, pos, ik = rep.items
    assert link.passed                     # the book's T_3^2 = my Craig matrix (oracle test)
    book = [63.03, -37.25, 12, -72.2, 135.29, -65.44]
    assert np.linalg.norm(scara_fk(book)[:3, 3] - (28, 31, 6)) < 2e-3   # position right
    assert pos.passed
    assert not ik.passed
    assert [s["status"] for s in ik.details["sets"]] == ["wrong"] * 4
    assert len(ik.details["missed"]) == 4
    for m in ik.details["missed"]:
        assert any(np.allclose(wrap180(np.subtract(m["solution_q"], s)), 0, atol=1e-3)
                   for s in scara_solutions())


# fer_rrpr (robots/fer_rrpr.yaml): standard DH, m; rows (alpha deg, a, d, type, theta offset deg)
FER = [(90, 0, 0.5, "R", 0), (90, 0, 0, "R", 0), (0, 0, 0, "P", 90), (0, 0, 0.1, "R", 0)]


def fer_fk(q_si):
    T = np.eye(4)
    for (alpha, a, d, kind, off), qi in zip(FER, q_si):
        if kind == "R":
            T = T @ dh_link(qi + math.radians(off), d, a, math.radians(alpha))
        else:
            T = T @ dh_link(math.radians(off), d + qi, a, math.radians(alpha))
    return T


def test_example_homework_fer_rrpr_sheet():
    sheet = example("homework_fer_rrpr.yaml")
    q = np.array([math.radians(30), math.radians(60), 0.3, math.radians(45)])
    T = fer_fk(q)
    # item 2: T_1^2 at q2 = 60 is [[c,0,s,0],[s,0,-c,0],[0,1,0,0]]; the student wrote its transpose
    A2 = dh_link(math.radians(60), 0, 0, math.radians(90))
    assert np.allclose(sheet.items[1].answer, A2.T, atol=1e-3)
    # item 3: p = (0.3, 0.1732, 0.3) -> right
    assert np.allclose(T[:3, 3], [0.3, 0.1732, 0.3], atol=1e-3)
    # item 4: the tcv is (p, e^(q4/pi) * approach) of this q; set 1 is one solution
    assert np.allclose(T[:3, 2] * math.exp(q[3] / math.pi), [0.963019, 0.555999, -0.642013],
                       atol=1e-5)
    # item 5: the Jacobian by finite differences matches the student's to 1e-3
    J = fd_jacobian(fer_fk, q)
    assert np.allclose(J, sheet.items[4].answer, atol=1e-3)
    # item 6: at q2 = 0 the Jacobian loses rank -> singular; the student said no
    J0 = fd_jacobian(fer_fk, np.array([math.radians(30), 0, 0.3, math.radians(45)]))
    sv = np.linalg.svd(J0, compute_uv=False)
    assert sv[-1] / sv[0] < 1e-6
    # item 7: the tool stays within q3 + d4 <= 0.7 of (0, 0, d1 = 0.5); (0, 0, 1.5) is 1.0 away
    rep = grade(sheet)
    verdict = {r.id: r.passed for r in rep.items}
    expect = {"1": True, "2": False, "3": True, "4": False, "5": True, "6": False, "7": True}
    assert verdict == expect, [(r.id, r.message, r.hint) for r in rep.items]
    r2 = next(r for r in rep.items if r.id == "2")
    assert r2.hint and "transpose" in r2.hint.lower(), r2.hint
    r4 = next(r for r in rep.items if r.id == "4")
    assert [s["status"] for s in r4.details["sets"]] == ["correct"] and r4.details["missed"]


def test_fk_answer_as_tool_configuration_vector():
    # w = [p; e^(q4/pi) r3] (the FER Zagreb homework), from the independent DH product
    q = np.array([math.radians(30), math.radians(60), 0.3, math.radians(45)])
    T = fer_fk(q)
    w = np.concatenate([T[:3, 3], math.exp(q[3] / math.pi) * T[:3, 2]])
    right = one(f"- {{id: w, kind: fk, q: [30, 60, 0.3, 45], answer: {{tcv: {js(w)}}}}}",
                robot="fer_rrpr")
    assert right.passed, right.message
    bad = w.copy()
    bad[3:] = T[:3, 2]                 # forgot the e^(q4/pi) factor
    wrong = one(f"- {{id: w, kind: fk, q: [30, 60, 0.3, 45], answer: {{tcv: {js(bad)}}}}}",
                robot="fer_rrpr")
    assert not wrong.passed and "tcv" in wrong.message
    # what was expected is the vector the answer was compared with, not only T_0^4 (a
    # seeds check: the table showed the matrix alone)
    assert np.allclose(wrong.details["expected_tcv"], w, atol=1e-12)


def test_a_wrong_tcv_answer_shows_the_expected_vector(tmp_path):
    q = np.array([math.radians(30), math.radians(60), 0.3, math.radians(45)])
    T = fer_fk(q)
    w = np.concatenate([T[:3, 3], math.exp(q[3] / math.pi) * T[:3, 2]])
    text = ("robot: fer_rrpr\nitems:\n  - {id: w, kind: fk, q: [30, 60, 0.3, 45], "
            "answer: {tcv: [0.3, 0.173205, 0.3, 1.205e6, 6.96e5, -8.04e5]}}\n")
    status, out, _ = run_check(tmp_path, text)
    assert status == 1
    lines = out.splitlines()
    row = lines[lines.index("expected tcv") + 2].split()
    assert np.allclose([float(v) for v in row], w, atol=1e-4)
    status, out, _ = run_check(tmp_path, text, "--feedback-dir", "fb")
    assert "expected tcv:" in (tmp_path / "fb" / "hw.md").read_text()


def test_a_pose_the_robot_cannot_be_asked_for_names_file_line_and_sheet_keys(tmp_path):
    # planar_3r controls its orientation: a position alone is not a question for it. This
    # was found while grading, escaped as a command-line message and stopped every sheet
    bad = "robot: planar_3r\nitems:\n  - {id: b, kind: ik, pose: {xyz: [1, 1, 0]}, answer: [[0, 90, 0]]}\n"
    with pytest.raises(SheetError) as info:
        grade(parse_sheet(bad, "p3.yaml", "."))
    assert info.value.line == 3 and "--" not in str(info.value) and "rpy" in str(info.value)
    (tmp_path / "p3.yaml").write_text(bad)
    (tmp_path / "ok.yaml").write_text("robot: bk_rr\nitems:\n  - {id: s, kind: singular, "
                                      "q: [10, 0], answer: yes}\n")
    out = kincalc("check", "p3.yaml", "ok.yaml", "-q", cwd=tmp_path)
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and "p3.yaml:3:" in out.stderr
    assert "ok.yaml" in out.stdout and "1 of 1 items right" in out.stdout


def test_redundant_arm_ik_sets_are_checked_by_fk_and_none_called_missed():
    # a 7-joint arm has infinitely many solutions: kincalc's numerical solver finds one,
    # so a right set must pass without "missing" the solver's own
    q = "[10, 20, 30, 40, 50, 60, 70]"
    right = one(f"- {{id: a, kind: ik, pose: {{q: {q}}}, answer: [{q}]}}", robot="iiwa14")
    assert right.passed and not right.details["missed"], right.message
    wrong = one(f"- {{id: a, kind: ik, pose: {{q: {q}}}, answer: [[10, 20, 30, 40, 50, 60, 75]]}}",
                robot="iiwa14")
    assert not wrong.passed and not wrong.details["missed"]


# ---------------------------------------------------------------------------
# Sheets are untrusted input (issue 14): the robot: rule, limits, quotes cut

from kincalc.homework import sheet_robot_path  # noqa: E402
from kincalc.errors import InputError  # noqa: E402
from kincalc.limits import (MAX_FILE_BYTES, MAX_IK_SETS, MAX_NUMERIC_ITEMS, MAX_QUOTE,  # noqa: E402
                            MAX_SHEET_ITEMS)

SECRET = "KINCALC-SECRET-7d1e0b"
SINGULAR = "items:\n  - {id: a, kind: singular, q: [30, 0], answer: yes}\n"


def bk_rr_text() -> str:
    return open(os.path.join(ROOT, "robots", "bk_rr.yaml"), encoding="utf-8").read()


@pytest.fixture
def folders(tmp_path):
    """tmp/secret.yaml and tmp/outside/arm.yaml (a valid robot) outside the sheet's folder
    tmp/work, which holds arm.yaml, sub/arm.yaml, links out and in, a FIFO and robots/."""
    (tmp_path / "secret.yaml").write_text(f"name: {SECRET}\nkey: {SECRET}\n")
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "arm.yaml").write_text(bk_rr_text().replace("title:",
                                                                        f"title: {SECRET}"))
    work = tmp_path / "work"
    (work / "sub").mkdir(parents=True)
    (work / "robots").mkdir()
    for p in ("arm.yaml", "sub/arm.yaml", "robots/course.yaml"):
        (work / p).write_text(bk_rr_text())
    os.symlink("../outside/arm.yaml", work / "link.yaml")
    os.symlink("../outside", work / "linkdir")
    os.symlink("arm.yaml", work / "inlink.yaml")
    os.mkfifo(work / "fifo.yaml")
    return work


@pytest.mark.parametrize("name", ["arm.yaml", "./arm.yaml", "sub/arm.yaml", "sub/../arm.yaml",
                                  "inlink.yaml", "robots/course.yaml"])
def test_sheet_robot_path_inside_the_folder(folders, name):
    path = sheet_robot_path(name, str(folders))
    assert os.path.realpath(path).startswith(str(folders.resolve()))
    assert sheet_robot_path(str(folders / name), str(folders)) == str(folders / name)


@pytest.mark.parametrize("name", ["../secret.yaml", "../outside/arm.yaml", "link.yaml",
                                  "linkdir/arm.yaml", "sub/../../secret.yaml", "/etc/passwd",
                                  "/dev/zero", "..", "{TMP}/secret.yaml", "{TMP}/outside/arm.yaml"])
def test_sheet_robot_path_refuses_what_leads_out(folders, name):
    name = name.replace("{TMP}", str(folders.parent))
    with pytest.raises(InputError, match="is outside the sheet's folder"):
        sheet_robot_path(name, str(folders))
    # the message is the same whether the file exists or not (no oracle)
    ghost = name.replace("secret", "ghost").replace("arm.yaml", "ghost.yaml")
    if ghost != name:
        with pytest.raises(InputError, match="is outside the sheet's folder"):
            sheet_robot_path(ghost, str(folders))


def test_sheet_robot_path_robots_dirs(folders):
    robots = str(folders / "robots")
    with pytest.raises(InputError, match="neither a bundled robot nor a file"):
        sheet_robot_path("course.yaml", str(folders / "sub"))
    assert sheet_robot_path("course.yaml", str(folders / "sub"), [robots]) == \
        os.path.join(robots, "course.yaml")
    # the grader's folder comes first: a file of the same name next to the sheet loses
    (folders / "robots" / "arm.yaml").write_text(bk_rr_text())
    assert sheet_robot_path("arm.yaml", str(folders), [robots]) == os.path.join(robots, "arm.yaml")
    # a path out of the sheet's folder that lands in an allowed folder is allowed
    assert os.path.samefile(sheet_robot_path("../robots/course.yaml", str(folders / "sub"),
                                             [robots]), os.path.join(robots, "course.yaml"))
    with pytest.raises(InputError, match="is outside the sheet's folder or a --robots-dir"):
        sheet_robot_path("../secret.yaml", str(folders), [robots])


@pytest.mark.parametrize("name,words", [("fifo.yaml", "neither a bundled robot"),
                                        ("sub", "neither a bundled robot"),
                                        ("arm.yaml\0x", "not a file name"),
                                        ("", "not a file name"),
                                        ("a" * 5000, "(5000 characters)")])
def test_sheet_robot_path_odd_names(folders, name, words):
    with pytest.raises(InputError) as info:
        sheet_robot_path(name, str(folders))
    assert words in str(info.value) and len(str(info.value)) < 300


def run_check(folder, text, *options):
    (folder / "hw.yaml").write_text(text)
    from cli_contract import run_cli
    return run_cli(["check", "hw.yaml", *options], cwd=folder)


@pytest.mark.parametrize("ref", ["/etc/passwd", "../secret.yaml", "link.yaml",
                                 "../outside/arm.yaml", "linkdir/arm.yaml", "/dev/zero"])
def test_check_never_reads_a_robot_outside_the_folder(folders, ref):
    status, out, err = run_check(folders, f"robot: {ref}\n" + SINGULAR)
    assert status == 2 and out == ""
    assert err.startswith("kincalc: error: hw.yaml:1: robot ") and err.count("\n") == 1
    assert "outside the sheet's folder" in err and "--robots-dir" in err
    assert SECRET not in err and "root:" not in err


def test_check_robots_dir_widens_the_rule(folders):
    text = "robot: ../outside/arm.yaml\n" + SINGULAR
    status, _, err = run_check(folders, text)
    assert status == 2 and "outside" in err
    status, out, err = run_check(folders, text, "--robots-dir", "../outside", "--json")
    assert status == 0, err
    assert SECRET in json.loads(out)["robot"]["title"]      # allowed: the grader said so
    status, _, err = run_check(folders, text, "--robots-dir", "nope")
    assert status == 2 and "--robots-dir nope: no such folder" in err


def test_check_grades_a_quiz_sheet_whose_robot_is_in_a_robots_dir(tmp_path):
    # kincalc quiz writes robot: ../robots/arm.yaml for a robot file beside the sheets'
    # folder; the grader allows that folder
    from cli_contract import run_cli
    (tmp_path / "robots").mkdir()
    (tmp_path / "robots" / "arm.yaml").write_text(bk_rr_text().replace("name: bk_rr", "name: arm"))
    (tmp_path / "sheets").mkdir()
    status, _, err = run_cli(["quiz", "robots/arm.yaml", "--seed", "1", "--answers", "-o",
                              "sheets/hw.yaml"], cwd=tmp_path)
    assert status == 0, err
    status, _, err = run_cli(["check", "sheets/hw.yaml", "-q"], cwd=tmp_path)
    assert status == 2 and "outside the sheet's folder" in err
    status, out, err = run_cli(["check", "sheets/hw.yaml", "-q", "--robots-dir", "robots"],
                               cwd=tmp_path)
    assert status == 0, err


def test_a_bad_robot_file_is_reported_by_line_never_by_content(folders):
    # another student's sheet in the same folder, named as the robot: the message says
    # it is no robot file and where, not what it holds
    (folders / "other.yaml").write_text(f"student: Bob\nrobot: bk_rr\nitems:\n"
                                        f"  - {{id: '{SECRET}', kind: singular, q: [0, 0]}}\n")
    status, out, err = run_check(folders, "robot: other.yaml\n" + SINGULAR)
    assert status == 2 and out == ""
    assert SECRET not in err and "Bob" not in err and "student" not in err
    assert "robot 'other.yaml' is not a valid robot file (the first problem is on its line 1)" \
        in err
    assert "kincalc robots validate" in err
    # a file that is no UTF-8: the line, not the byte
    (folders / "bin.yaml").write_bytes(b"name: x\n\xff\xfe" + SECRET.encode())
    status, _, err = run_check(folders, "robot: bin.yaml\n" + SINGULAR)
    assert status == 2 and "line 2" in err and "0xff" not in err and SECRET not in err


def test_a_robot_file_too_large(folders):
    (folders / "big.yaml").write_bytes(bk_rr_text().encode() + b"#" * MAX_FILE_BYTES)
    status, _, err = run_check(folders, "robot: big.yaml\n" + SINGULAR)
    assert status == 2, err
    assert "robot 'big.yaml': the file is larger than 1 MiB, kincalc's limit for a robot file" \
        in err


def test_an_endless_device_is_never_opened_as_a_robot(folders):
    # a symbolic link to /dev/zero leads outside; /dev/zero in an allowed folder is no
    # regular file: neither is opened
    os.symlink("/dev/zero", folders / "z.yaml")
    status, _, err = run_check(folders, "robot: z.yaml\n" + SINGULAR)
    assert status == 2 and "outside" in err
    status, _, err = run_check(folders, "robot: /dev/zero\n" + SINGULAR, "--robots-dir", "/dev")
    assert status == 2 and "neither a bundled robot nor a file" in err


def test_sheet_size_limit(tmp_path):
    big = tmp_path / "big.yaml"
    big.write_bytes(("robot: bk_rr\n" + SINGULAR).encode() + b"#" * MAX_FILE_BYTES)
    with pytest.raises(SheetError, match="larger than 1 MiB, kincalc's limit for a sheet"):
        load_sheet(str(big))
    from cli_contract import run_cli
    for path in (str(big), "/dev/zero"):
        status, out, err = run_cli(["check", path])
        assert status == 2 and out == "" and err.count("\n") == 1
        assert ("larger than 1 MiB" if path != "/dev/zero" else
                "is a character device, not read") in err   # a device is never opened
    # exactly at the limit is a sheet
    ok = ("robot: bk_rr\n" + SINGULAR).encode()
    big.write_bytes(ok + b"#" * (MAX_FILE_BYTES - len(ok)))
    assert len(load_sheet(str(big)).items) == 1


def items_text(n: int) -> str:
    return "robot: bk_rr\nitems:\n" + "".join(
        f"  - {{id: i{k}, kind: singular, q: [30, 0], answer: yes}}\n" for k in range(n))


def test_sheet_item_limit():
    assert len(parse_sheet(items_text(MAX_SHEET_ITEMS), "hw.yaml").items) == MAX_SHEET_ITEMS
    for n in (MAX_SHEET_ITEMS + 1, 3000):
        with pytest.raises(SheetError) as info:
            parse_sheet(items_text(n), "hw.yaml")
        assert info.value.line == 3                 # where the list starts
        assert f"'items' has {n} items; a sheet holds at most {MAX_SHEET_ITEMS}" in str(info.value)


def reach_items(robot: str, n: int, extra: str = "") -> str:
    return f"robot: {robot}\nitems:\n" + "".join(
        f"  - {{id: r{k}, kind: reach, pose: {{xyz: [0.3, 0.1, 0.4], rpy: [0, 90, 0]}}}}\n"
        for k in range(n)) + extra


def test_numeric_item_limit():
    """A sheet of 200 reach items for a seven-joint arm (solved numerically, a second or so
    an item) kept a grader busy for minutes: at most MAX_NUMERIC_ITEMS such items."""
    assert len(parse_sheet(reach_items("panda", MAX_NUMERIC_ITEMS), "hw.yaml").items) \
        == MAX_NUMERIC_ITEMS
    ik = "  - {id: i, kind: ik, pose: {xyz: [0.3, 0.1, 0.4], rpy: [0, 90, 0]}}\n"
    for text in (reach_items("panda", MAX_NUMERIC_ITEMS + 1), reach_items("panda", 199),
                 reach_items("panda", MAX_NUMERIC_ITEMS, ik)):
        with pytest.raises(SheetError) as info:
            parse_sheet(text, "hw.yaml")
        assert info.value.line == 3                 # where the list starts
        assert f"ik and reach items; for 'panda', which kincalc solves numerically" \
            in str(info.value)
        assert f"a sheet holds at most {MAX_NUMERIC_ITEMS}" in str(info.value)
    # an ik item holding a joint is solved in closed form, and a robot with one is not limited
    locked = ik.replace("rpy: [0, 90, 0]}", "rpy: [0, 90, 0]}, lock: {joint3: 0}")
    assert len(parse_sheet(reach_items("panda", MAX_NUMERIC_ITEMS, locked), "hw.yaml").items) \
        == MAX_NUMERIC_ITEMS + 1
    assert len(parse_sheet(reach_items("puma560", 199), "hw.yaml").items) == 199


def test_quiz_refuses_what_check_would(capsys):
    from kincalc.cli.main import main
    many = ",".join(["reach"] * (MAX_NUMERIC_ITEMS + 1))
    assert main(["quiz", "panda", "--seed", "1", "--items", many]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1
    assert f"--items: {MAX_NUMERIC_ITEMS + 1} ik and reach items; for 'panda'" in err
    assert main(["quiz", "puma560", "--seed", "1", "--items", many]) == 0
    assert capsys.readouterr().out.count("kind: reach") == MAX_NUMERIC_ITEMS + 1


def test_ik_answer_set_limit():
    sets = ", ".join(["[30, -60]"] * (MAX_IK_SETS + 1))
    text = f"robot: bk_rr\nitems:\n  - {{id: a, kind: ik, pose: {{xyz: [12.99, 2.5, 0]}}, " \
           f"answer: [{sets}]}}\n"
    with pytest.raises(SheetError, match=f"17 solution sets; an ik item takes at most "
                                         f"{MAX_IK_SETS}"):
        parse_sheet(text, "hw.yaml")
    ok = text.replace(sets, ", ".join(["[30, -60]"] * MAX_IK_SETS))
    assert len(parse_sheet(ok, "hw.yaml").items[0].answer) == MAX_IK_SETS


@pytest.mark.parametrize("text,words", [
    ("robot: " + "x" * 5000 + "\n" + SINGULAR, ["robot 'xxx", "(5000 characters)"]),
    ("robot: bk_rr\ntolerance: " + "9" * 1_000_000 + "\n" + SINGULAR,
     ["'tolerance' must be a mapping", "(1000000 characters)"]),
    ("robot: bk_rr\ntolerance: {angle: " + "9" * 1000 + "}\n" + SINGULAR,
     ["'tolerance.angle'", "(1000 characters)"]),
    ("robot: bk_rr\nitems:\n  - {id: " + "i" * 5000 + ", kind: fkk}\n",
     ["item 'iii", "(5000 characters)", "'kind'", "'fkk'"]),
    ("robot: bk_rr\nitems:\n  - {id: a, kind: " + "k" * 5000 + "}\n",
     ["'kind' must be one of", "(5000 characters)"]),
    ("robot: bk_rr\nitems:\n  - {id: a, kind: singular, q: [30, 0], answer: " + "m" * 5000 + "}\n",
     ["yes or no", "(5000 characters)"]),
    ("robot: bk_rr\nitems:\n  - {id: a, kind: link, link: " + "7" * 500 + ", q: [1, 2]}\n",
     ["'link'"]),
    ("robot: bk_rr\nparameters: {[a]: 1}\n" + SINGULAR, ["'parameters'", "plain names"]),
])
def test_quotes_of_the_sheet_are_cut(text, words):
    with pytest.raises(SheetError) as info:
        parse_sheet(text, "hw.yaml")
    message = str(info.value)
    assert len(message) < 2 * MAX_QUOTE + 300, message[:500]
    for w in words:
        assert w in message, message


TWO_LINK_URDF = """<robot name="two_link">
  <link name="base_link"/><link name="upper_arm"/><link name="forearm"/>
  <joint name="shoulder" type="continuous"><parent link="base_link"/>
    <child link="upper_arm"/><axis xyz="0 0 1"/></joint>
  <joint name="elbow" type="continuous"><parent link="upper_arm"/><child link="forearm"/>
    <origin xyz="0.4 0 0"/><axis xyz="0 0 1"/></joint>
  <link name="tool0"/>
  <joint name="tool" type="fixed"><parent link="forearm"/><child link="tool0"/>
    <origin xyz="0.3 0 0"/></joint>
</robot>
"""


def test_a_sheet_robot_may_be_a_urdf_and_its_problems_are_told_by_line(folders):
    (folders / "arm.urdf").write_text(TWO_LINK_URDF)
    status, out, err = run_check(folders, "robot: arm.urdf\n" + SINGULAR)
    assert status == 0, err
    # a URDF whose names carry someone else's secret: only the line is told
    bad = TWO_LINK_URDF.replace('<link name="tool0"/>', "") \
        .replace("</robot>", f'<link name="{SECRET}"/></robot>')
    (folders / "bad.urdf").write_text(bad)
    status, _, err = run_check(folders, "robot: bad.urdf\n" + SINGULAR)
    assert status == 2 and SECRET not in err and "tool0" not in err
    assert "robot 'bad.urdf' is not a valid robot file (the first problem is on its line" in err


def test_ik_item_with_a_lock_grades_the_branches_of_the_chain_left():
    """An iiwa item holding A3: the branches of the held chain within the limits (each
    checked here by FK, with A3 at its value) are what the sheet must list; a set that
    moves the held joint is wrong even though it reaches the pose; a missing branch is
    named."""
    import kincalc as kc
    from kincalc.analysis.redundancy import solve_locked
    from kincalc.ik import Target
    r = kc.load_robot("iiwa14")
    q0 = np.radians([10, 20, 30, -40, 50, 60, 70])
    T = r.fk(q0)
    sols = [s.q for s in solve_locked(r, Target(T), {2: q0[2]}).solutions if s.within_limits]
    assert len(sols) >= 4
    for q in sols:
        assert np.allclose(r.fk(q), T, atol=1e-9) and np.isclose(q[2], q0[2])
    pose = "{q: [10, 20, 30, -40, 50, 60, 70]}"
    rows = ", ".join(js(np.degrees(q)) for q in sols)
    item = f"""\
        - id: i
          kind: ik
          pose: {pose}
          lock: {{A3: 30}}
          answer: [{rows}]
        """
    res = one(item, robot="iiwa14")
    assert res.passed, (res.message, res.hint)
    # drop one: missed; add a set with A3 moved (another point of the self-motion)
    other = solve_locked(r, Target(T), {2: q0[2] + 0.3}).solutions[0].q
    rows = ", ".join(js(np.degrees(q)) for q in sols[1:] + [other])
    res = one(item.replace(item[item.index("answer"):], f"answer: [{rows}]\n"), robot="iiwa14")
    assert not res.passed
    assert len(res.details["missed"]) == 1
    moved = [s for s in res.details["sets"] if s["status"] == "wrong"]
    assert len(moved) == 1 and "holds joint 3 (A3) at 30;" in moved[0]["note"]


def test_ik_item_lock_errors_name_the_line():
    for lock, words in (("{A9: 30}", "unknown key 'A9'"), ("{A3: x}", "lock.A3"),
                        ("[30]", "'lock' must be a mapping"),
                        ("{1: 0, 2: 0, 3: 0, 4: 0, 5: 0, 6: 0, 7: 0}", "from 1 to 6")):
        text = sheet_text(f"""\
            - id: i
              kind: ik
              pose: {{xyz: [0.5, 0, 0.5], rpy: [0, 90, 0]}}
              lock: {lock}
            """, robot="iiwa14")
        with pytest.raises(Exception) as e:
            parse_sheet(text, "hw.yaml", ".")
        assert words in str(e.value) and "hw.yaml:" in str(e.value), str(e.value)


@pytest.mark.parametrize("text, line", [
    ("-----BEGIN KEY-----\nS3CRET\n", 1),
    ("kincalc-sheet: 1\nrobot: bk_rr\nitems:\n  - {id: a, kind: jacobian, q: [0, 0],\n"
     "     frame: 'base\n     S3CRET', answer: {rank: 2}}\n", 5),
    ("kincalc-sheet: 1\nrobot: bk_rr\nitems:\n  - id: a\n    kind: fk\n    q: [0, 0]\n"
     "    answer: {xyz: [\"1 +\n       S3CRET\", 0, 0]}\n", 7),
])
def test_a_sheet_error_echoes_no_other_line(text, line):
    """A value written over several lines is named by its lines, never quoted: the one
    line a message names is all of the file it shows."""
    with pytest.raises(SheetError) as info:
        parse_sheet(text, "hw.yaml", ".")
    assert info.value.line == line and "S3CRET" not in str(info.value), str(info.value)
    assert "a text over lines" in str(info.value)


@pytest.mark.parametrize("kind, shown", [("[fk]", "a list"), ("{answer: 1}", "a mapping")])
@pytest.mark.parametrize("answer", ["", "    answer: {xyz: [1, 0, 0]}\n"])
def test_a_kind_that_is_no_text_is_an_invalid_sheet(kind, shown, answer):
    """A list or mapping as 'kind' was let through as "no kind": the item's answer then
    reached an assertion (an internal error, exit 3) instead of a sheet error."""
    text = (f"kincalc-sheet: 1\nrobot: bk_rr\nitems:\n  - id: a\n    kind: {kind}\n"
            f"    q: [0, 0]\n{answer}")
    with pytest.raises(SheetError) as info:
        parse_sheet(text, "hw.yaml", ".")
    assert info.value.line == 5 and "'kind' must be one of" in str(info.value)
    assert str(info.value).endswith(f"not {shown}")


@pytest.mark.parametrize("name", ["../secret.yaml", "link.yaml", "linkdir/arm.yaml",
                                  "sub/../../secret.yaml", "/etc/passwd",
                                  "{TMP}/secret.yaml", "{TMP}/outside/arm.yaml"])
def test_nothing_outside_the_folder_is_asked_about(folders, name, monkeypatch):
    """A robot path that leads out is refused before the file system is asked anything
    about where it leads (no lstat or stat of the file, of a folder on the way to it, or
    of a link's target): only the sheet's folder, the folders above it, and the links in it
    are looked at. (os.path.realpath of the name itself looked at /etc/passwd; a fuzz
    campaign's strace.)"""
    name = name.replace("{TMP}", str(folders.parent))
    asked = []
    for fn in ("lstat", "stat"):
        real = getattr(os, fn)
        monkeypatch.setattr(os, fn, lambda p, *a, _real=real, **k: (
            asked.append(os.fsdecode(p)), _real(p, *a, **k))[1])
    with pytest.raises(InputError, match="is outside the sheet's folder"):
        sheet_robot_path(name, str(folders))
    root = str(folders.resolve())
    for p in asked:
        p = os.path.abspath(p)
        assert p == root or p.startswith(root + os.sep) or root.startswith(p.rstrip(os.sep)
                                                                           + os.sep) \
            or p == os.sep, (name, p)


def test_a_tcv_ik_set_a_turn_off_in_the_last_joint_is_wrong():
    """The vector holds e^(q4 / pi): q4 + 360 deg does not reach it (an fk item says so),
    while q1 + 360 deg does. IK sets were compared modulo a turn in every joint."""
    from kincalc import load_robot
    from kincalc.spatial import tcv_from_transform
    r = load_robot("fer_rrpr")
    q = np.radians([30, 60, 0, 45])
    q[2] = 0.3
    w = [round(float(x), 9) for x in tcv_from_transform(r.fk(q), q[3])]
    pose = f"{{tcv: {w}}}"
    rep = report(f"""\
        - {{id: right, kind: ik, pose: {pose}, answer: [[30, 60, 0.3, 45], [-150, -60, 0.3, 45]]}}
        - {{id: q1, kind: ik, pose: {pose}, answer: [[390, 60, 0.3, 45], [-150, -60, 0.3, 45]]}}
        - {{id: q4, kind: ik, pose: {pose}, answer: [[30, 60, 0.3, 405], [-150, -60, 0.3, 45]]}}
        - {{id: fk, kind: fk, q: [30, 60, 0.3, 405], answer: {{tcv: {w}}}}}
        """, robot="fer_rrpr")
    passed = {r.id: r.passed for r in rep.items}
    assert passed == {"right": True, "q1": True, "q4": False, "fk": False}, passed


ARM_WITH_BASE = ("{name: arm, convention: dh, units: {length: m, angle: deg}, joints: ["
                 "{name: q1, type: revolute, theta: 0, d: 0.3, a: 0, alpha: 90}, "
                 "{name: q2, type: revolute, theta: 0, d: 0, a: 0.4, alpha: 0}], "
                 "base: {xyz: [0.1, -0.05, 0.2], rpy: [0, 0, 30]}, tool: {xyz: [0, 0, 0.08]}}")
ROWS = "[[q1, 0.3, 0, 90], [q2, 0, 0.4, 0]]"


def test_dh_rows_without_the_base_get_the_base_hint():
    """A missing tool had its hint, a missing base none: the rows were only said to put
    joint 1's axis 0.1118 m away (the base's offset, sqrt(0.1^2 + 0.05^2))."""
    r = one(f"- {{id: t, kind: dh, answer: {{convention: dh, table: {ROWS}}}}}",
            robot=ARM_WITH_BASE)
    assert not r.passed and "0.1118" in r.message, r.message
    assert r.hint and "base and tool frames are left out" in r.hint, r.hint
    r = one(f"- {{id: t, kind: dh, tool: ignore, answer: {{convention: dh, table: {ROWS}}}}}",
            robot=ARM_WITH_BASE)
    assert not r.passed and r.hint and "base frame is left out" in r.hint, r.hint
    # the base given: right; rows wrong too: no such hint
    r = one(f"- {{id: t, kind: dh, tool: ignore, answer: {{convention: dh, table: {ROWS}, "
            "base: {xyz: [0.1, -0.05, 0.2], rpy: [0, 0, 30]}}}", robot=ARM_WITH_BASE)
    assert r.passed, r.message
    r = one("- {id: t, kind: dh, tool: ignore, answer: {convention: dh, table: "
            "[[q1, 0.3, 0, 60], [q2, 0, 0.4, 0]]}}", robot=ARM_WITH_BASE)
    assert not r.passed and not (r.hint and "left out" in r.hint), r.hint
