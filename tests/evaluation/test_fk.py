"""Forward kinematics against values computed independently of kincalc.

Golden values come from the seed documents' printed link matrices and worked
examples (transcribed below as plain formulas), from Corke's published PUMA
560 poses, and from a second formulation (the textbook product of each
convention's link transforms) for random robots.
"""

import math

import numpy as np
import pytest
from randrobots import random_robot

from kincalc import load_robot
from kincalc.conventions import dh_to_mdh, mdh_to_dh, to_poe

c, s = np.cos, np.sin
D = np.deg2rad


def M(*rows):
    return np.array(rows, dtype=float)


# --- seed document 000, Example 4.1/4.2 -------------------------------------

def test_example_4_2_rr_reaches_the_book_target():
    rr = load_robot("bk_rr")
    for q in ([30, -60], [-8.2, 60]):
        p = rr.fk(D(q))[:3, 3]
        assert np.allclose(p, [12.99, 2.5, 0], atol=0.02)
    # the book's rejected sets zeta1 and zeta4 do not reach it
    for q in ([30, 60], [-8.2, -60]):
        assert np.linalg.norm(rr.fk(D(q))[:2, 3] - [12.99, 2.5]) > 1.0
    # exact: (30, -60) gives (10 cos30 + 5 cos(-30), 10 sin30 + 5 sin(-30))
    assert np.allclose(rr.fk(D([30, -60]))[:3, 3], [15 * math.cos(D(30)), 2.5, 0], atol=1e-12)


def _links(robot, q):
    return robot.link_transforms(np.asarray(q, float))


def test_example_4_5_printed_link_matrices():
    r = load_robot("bk_6r")
    h1, d2, l2, d4 = 0.66, 0.15, 0.432, 0.432
    rng = np.random.default_rng(45)
    for _ in range(50):
        t = rng.uniform(-np.pi, np.pi, 6)
        book = [
            M([c(t[0]), -s(t[0]), 0, 0], [s(t[0]), c(t[0]), 0, 0], [0, 0, 1, h1], [0, 0, 0, 1]),
            M([c(t[1]), -s(t[1]), 0, 0], [0, 0, 1, d2], [-s(t[1]), -c(t[1]), 0, 0], [0, 0, 0, 1]),
            M([c(t[2]), -s(t[2]), 0, l2], [s(t[2]), c(t[2]), 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]),
            M([c(t[3]), -s(t[3]), 0, 0], [0, 0, 1, d4], [-s(t[3]), -c(t[3]), 0, 0], [0, 0, 0, 1]),
            M([c(t[4]), -s(t[4]), 0, 0], [0, 0, -1, 0], [s(t[4]), c(t[4]), 0, 0], [0, 0, 0, 1]),
            M([c(t[5]), -s(t[5]), 0, 0], [0, 0, 1, 0], [-s(t[5]), -c(t[5]), 0, 0], [0, 0, 0, 1]),
        ]
        assert np.allclose(_links(r, t), book, atol=1e-12)
        # the book's position equation: [T_1^0]^-1 T_6^0 column 4
        T = r.fk(t)
        px, py, pz = T[:3, 3]
        t23 = t[1] + t[2]
        lhs = [c(t[0]) * px + s(t[0]) * py, -s(t[0]) * px + c(t[0]) * py, pz - h1]
        rhs = [-d4 * s(t23) + l2 * c(t[1]), d2, -d4 * c(t23) - l2 * s(t[1])]
        assert np.allclose(lhs, rhs, atol=1e-12)


def test_example_4_6_scara_printed_link_matrices_and_position():
    r = load_robot("bk_scara_euler")
    h1, l1, l2, d4 = 22, 26, 18, 4
    rng = np.random.default_rng(46)
    for _ in range(50):
        t1, t2, d3, t4, t5, t6 = rng.uniform(-3, 3, 6)
        book = [
            M([c(t1), -s(t1), 0, 0], [s(t1), c(t1), 0, 0], [0, 0, 1, h1], [0, 0, 0, 1]),
            M([c(t2), -s(t2), 0, l1], [s(t2), c(t2), 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]),
            M([1, 0, 0, l2], [0, -1, 0, 0], [0, 0, -1, -d3], [0, 0, 0, 1]),
            M([c(t4), -s(t4), 0, 0], [s(t4), c(t4), 0, 0], [0, 0, 1, d4], [0, 0, 0, 1]),
            M([c(t5), -s(t5), 0, 0], [0, 0, 1, 0], [-s(t5), -c(t5), 0, 0], [0, 0, 0, 1]),
            M([c(t6), -s(t6), 0, 0], [0, 0, -1, 0], [s(t6), c(t6), 0, 0], [0, 0, 0, 1]),
        ]
        assert np.allclose(_links(r, [t1, t2, d3, t4, t5, t6]), book, atol=1e-12)
    # the worked example: theta1 = 63.03, theta2 = -37.25, d3 = 12 put the tool at (28, 31, 6)
    T = r.fk([D(63.03), D(-37.25), 12, 0.3, 0.4, 0.5])
    assert np.allclose(T[:3, 3], [28, 31, 6], atol=5e-3)


def test_example_4_4_rpr_printed_link_matrices():
    r = load_robot("bk_rpr")
    h1, l2, l3 = 10, 4, 6
    t1, d2, t3 = 0.3, 1.7, -0.8
    A = _links(r, [t1, d2, t3])
    assert np.allclose(A[0], M([c(t1), -s(t1), 0, 0], [s(t1), c(t1), 0, 0], [0, 0, 1, h1], [0, 0, 0, 1]))
    assert np.allclose(A[1], M([0, -1, 0, 0], [0, 0, -1, -l2 - d2], [1, 0, 0, 0], [0, 0, 0, 1]))
    assert np.allclose(A[2], M([c(t3), -s(t3), 0, 0], [0, 0, 1, 0], [-s(t3), -c(t3), 0, 0], [0, 0, 0, 1]))
    # book: [T_1^0]^-1 T_4^0 column 4 = (0, l3 s3 - (l2 + d2), l3 c3)
    T = r.fk([t1, d2, t3])
    px, py, pz = T[:3, 3]
    assert np.allclose([c(t1) * px + s(t1) * py, -s(t1) * px + c(t1) * py, pz - h1],
                       [0, l3 * s(t3) - (l2 + d2), l3 * c(t3)], atol=1e-12)


def test_example_4_3_rrp_printed_inverse_product():
    r = load_robot("bk_rrp")
    h1, d2, l2 = 10, 3, 5
    t1, t2, d3 = 0.4, -1.1, 2.5
    A = _links(r, [t1, t2, d3])
    inv_book = M([c(t1) * c(t2), s(t1) * c(t2), s(t2), -s(t2) * h1],
                 [-c(t1) * s(t2), -s(t1) * s(t2), c(t2), -c(t2) * h1],
                 [s(t1), -c(t1), 0, -d2], [0, 0, 0, 1])
    assert np.allclose(np.linalg.inv(A[0] @ A[1]), inv_book, atol=1e-12)
    assert np.allclose(A[2], M([1, 0, 0, 0], [0, 0, 1, l2 + d3], [0, -1, 0, 0], [0, 0, 0, 1]))


def test_offset_wrist_printed_link_matrices():
    r = load_robot("bk_offset_wrist")
    l2, l3, l4, d6 = 10, 8, 3, 2
    t1, d2, t3, t4, t5, t6 = 0.2, 4.0, -0.5, 1.2, 0.7, -2.0
    A = _links(r, [t1, d2, t3, t4, t5, t6])
    book = [
        M([c(t1), -s(t1), 0, 0], [s(t1), c(t1), 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]),
        M([1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, d2], [0, 0, 0, 1]),
        M([c(t3), -s(t3), 0, l2], [s(t3), c(t3), 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]),
        M([c(t4), -s(t4), 0, l3], [s(t4), c(t4), 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]),
        M([c(t5), -s(t5), 0, l4], [0, 0, -1, 0], [s(t5), c(t5), 0, 0], [0, 0, 0, 1]),
        M([c(t6), -s(t6), 0, 0], [0, 0, -1, -d6], [s(t6), c(t6), 0, 0], [0, 0, 0, 1]),
    ]
    assert np.allclose(A, book, atol=1e-12)


# --- seed document 001, FER Zagreb homework ---------------------------------

def test_zagreb_printed_T04_and_home_pose():
    r = load_robot("fer_rrpr")
    d1, d4 = 0.5, 0.1
    rng = np.random.default_rng(1)
    for _ in range(100):
        q1, q2, q3, q4 = rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(0, 0.6), rng.uniform(-3, 3)
        C1, S1, C2, S2, C4, S4 = c(q1), s(q1), c(q2), s(q2), c(q4), s(q4)
        book = M([C4 * S1 - C1 * C2 * S4, -S1 * S4 - C1 * C2 * C4, C1 * S2, C1 * S2 * (d4 + q3)],
                 [-C1 * C4 - C2 * S1 * S4, C1 * S4 - C2 * C4 * S1, S1 * S2, S1 * S2 * (d4 + q3)],
                 [-S2 * S4, -C4 * S2, -C2, d1 - d4 * C2 - q3 * C2], [0, 0, 0, 1])
        assert np.allclose(r.fk([q1, q2, q3, q4]), book, atol=1e-12)
    # home pose of the figure: p = (0, q3 + d4, d1)
    assert np.allclose(r.fk([D(90), D(90), 0.2, 0])[:3, 3], [0, 0.3, 0.5], atol=1e-12)


# --- a published PUMA 560 pose ----------------------------------------------

def test_puma560_corke_published_poses():
    # Corke, Robotics, Vision and Control (2011/2017), sec. 7.1: p560.fkine(qz) and fkine(qn)
    p = load_robot("puma560")
    Tz = p.fk(np.zeros(6))
    assert np.allclose(Tz[:3, :3], np.eye(3), atol=1e-12)
    assert np.allclose(Tz[:3, 3], [0.4521, -0.1500, 0.4318], atol=1e-4)
    Tn = p.fk([0, np.pi / 4, np.pi, 0, np.pi / 4, 0])
    assert np.allclose(Tn[:3, 3], [0.5963, -0.1501, -0.0144], atol=1e-4)
    assert np.allclose(Tn[:3, :3], [[0, 0, 1], [0, 1, 0], [-1, 0, 0]], atol=1e-4)


# --- second formulation: product of the convention's link transforms ---------

@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_chain_equals_product_of_link_transforms(convention):
    rng = np.random.default_rng({"dh": 1, "mdh": 2, "poe": 3}[convention])
    for _ in range(20):
        r = random_robot(rng, convention, n=int(rng.integers(1, 8)))
        q = rng.uniform(-3, 3, (200, r.dof))
        A = r.link_transforms(q)
        T = np.broadcast_to(r.base, (200, 4, 4))
        for i in range(r.dof):
            T = T @ A[:, i]
        if convention != "poe":
            T = T @ r.tool
        else:  # poe link frames end on the last axis; the flange is M at q = 0
            T = _poe_by_exponentials(r, q)
        assert np.allclose(T, r.fk(q), atol=1e-12)


def _poe_by_exponentials(r, q):
    """Brockett's formula written out with Rodrigues, independent of kincalc.fk."""
    out = []
    for qq in q:
        T = r.base.copy()
        for j, x in zip(r.joints, qq):
            w = np.array(j.axis)
            p = np.array(j.point)
            E = np.eye(4)
            if j.revolute:
                W = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
                R = np.eye(3) + np.sin(x) * W + (1 - np.cos(x)) * W @ W
                E[:3, :3] = R
                E[:3, 3] = (np.eye(3) - R) @ p
            else:
                E[:3, 3] = w * x
            T = T @ E
        out.append(T @ r.M @ r.tool)        # the flange at M, the tool on it
    return np.array(out)


@pytest.mark.parametrize("convention", ["dh", "mdh"])
def test_random_robots_same_fk_in_all_conventions(convention):
    rng = np.random.default_rng(7 if convention == "dh" else 8)
    for _ in range(20):
        r = random_robot(rng, convention, n=6)
        q = rng.uniform(-np.pi, np.pi, (1000, 6))
        other = dh_to_mdh(r) if convention == "dh" else mdh_to_dh(r)
        poe = to_poe(r)
        ref = r.fk(q)
        assert np.abs(other.fk(q) - ref).max() < 1e-12
        assert np.abs(poe.fk(q) - ref).max() < 1e-12
        assert np.allclose(_poe_by_exponentials(poe, q[:20]), ref[:20], atol=1e-12)


@pytest.mark.parametrize("shape", [(), (1,), (3,), (2, 3, 5)])
def test_batched_fk_equals_single(shape):
    r = load_robot("puma560")
    q = np.random.default_rng(0).uniform(-3, 3, shape + (6,))
    T = r.fk(q)
    assert T.shape == shape + (4, 4)
    single = np.array([r.fk(x) for x in q.reshape(-1, 6)])
    assert np.array_equal(T.reshape(-1, 4, 4), single)


def test_batch_larger_than_a_chunk():
    from kincalc import fk as fkmod
    r = load_robot("ur5") if "ur5" in _names() else load_robot("puma560")
    q = np.random.default_rng(1).uniform(-3, 3, (fkmod.CHUNK * 2 + 17, r.dof))
    T = r.fk(q)
    idx = [0, fkmod.CHUNK - 1, fkmod.CHUNK, fkmod.CHUNK * 2 + 16]
    assert np.allclose(T[idx], np.array([r.fk(q[i]) for i in idx]))


def test_fk_does_not_modify_input():
    r = load_robot("puma560")
    q = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    keep = q.copy()
    r.fk(q)
    r.jacobian(q)
    assert np.array_equal(q, keep)


def _names():
    from kincalc.conventions.library import bundled_names
    return bundled_names()


@pytest.mark.parametrize("name", ["puma560", "stanford_arm", "bk_rrp", "ur5_poe", "puma560_mdh"])
def test_chain_frames_few_and_many_configurations(name):
    """chain_frames multiplies stacked 4x4s for a few configurations and walks columns
    for many (the walk of fk): the two agree frame by frame, a single configuration is
    the batch's row, and the last frame times the chain's tool transform is fk."""
    from kincalc.fk import FEW as _FEW, chain_frames
    r = load_robot(name)
    Q = np.random.default_rng(3).uniform(-2, 2, (_FEW + 8, r.dof))
    many = chain_frames(r.chain, Q)
    few = np.concatenate([chain_frames(r.chain, Q[:_FEW]), chain_frames(r.chain, Q[_FEW:])])
    assert np.allclose(few, many, atol=1e-14)
    assert np.allclose(chain_frames(r.chain, Q[0]), many[0], atol=1e-14)
    assert np.allclose(few[:, -1] @ r.chain.fixed[-1], r.fk(Q), atol=1e-13)


@pytest.mark.parametrize("name", ["puma560", "stanford_arm", "bk_rrp", "ur5_poe", "puma560_mdh"])
def test_stacked_and_walked_evaluations_agree(name):
    """FK, the Jacobian, the FK check from cosines and sines, and the frames' columns,
    each for FEW configurations (stacked 4x4 products) and FEW + 8 (the column walk):
    the same numbers, on revolute and prismatic joints in every convention."""
    from kincalc.fk import FEW, chain_frames, entry_frames, frames_and_tool, tool_from_cs
    r = load_robot(name)
    Q = np.random.default_rng(5).uniform(-2, 2, (FEW + 8, r.dof))
    few, many = slice(0, FEW), slice(0, FEW + 8)
    assert np.allclose(r.fk(Q[few]), r.fk(Q[many])[few], atol=1e-14)
    assert np.allclose(r.jacobian(Q[few]), r.jacobian(Q[many])[few], atol=1e-13)
    x = Q.T.copy()                                  # joint-major, offsets not applied
    c, s = np.cos(x), np.sin(x)
    for part in (few, many):
        cols, p = tool_from_cs(r.chain, c[:, part], s[:, part], x[:, part])
        T = r.fk(Q[part])
        assert np.allclose(p.T, T[:, :3, 3], atol=1e-13)
        for j in range(3):
            assert np.allclose(cols[j].T, T[:, :3, j], atol=1e-14)
    for part in (few, many):
        F, T = frames_and_tool(r.chain, Q[part])
        assert np.allclose(T, r.fk(Q[part]), atol=1e-14)
        assert np.allclose(F, chain_frames(r.chain, Q[part]), atol=1e-14)
    stacked = entry_frames(r.chain, Q[few])
    walked = entry_frames(r.chain, Q[few], column_walk=True)
    assert np.allclose(stacked, walked, atol=1e-14)
    assert np.array_equal(walked, entry_frames(r.chain, Q[many])[..., few])


def test_entry_frames_refuses_joint_values_of_the_wrong_length():
    """(2, 3) values for a 6-joint chain are not one configuration."""
    from kincalc.fk import entry_frames
    r = load_robot("puma560")
    for walk in (False, True):
        with pytest.raises(ValueError, match=r"\(\.\.\., 6\)"):
            entry_frames(r.chain, np.zeros((2, 3)), column_walk=walk)
        assert entry_frames(r.chain, np.zeros((2, 6)), column_walk=walk).shape == (3, 4, 7, 2)


@pytest.mark.parametrize("seed", range(6))
def test_dh_frames_are_dh_frames(seed):
    """The one DH-frame construction (used by convert and the general 6R solver): on
    random axes, including parallel, meeting and coincident pairs and prismatic joints,
    every frame has z along its axis and each step is Rz Tz Tx Rx (no y-components)."""
    from kincalc.structure import dh_frames
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 8))
    dirs = rng.normal(size=(n, 3))
    pts = rng.uniform(-1, 1, (n, 3))
    for k in range(1, n):                  # make some consecutive pairs special
        kind = rng.integers(0, 4)
        if kind == 1:
            dirs[k] = dirs[k - 1]                                    # parallel
        elif kind == 2:
            pts[k] = pts[k - 1] + 0.3 * dirs[k - 1]                  # meeting
        elif kind == 3:
            dirs[k], pts[k] = dirs[k - 1], pts[k - 1] + dirs[k - 1]  # coincident
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    revolute = rng.random(n) < 0.7
    F = dh_frames(dirs, pts, 1.0, 1e-9, revolute)
    for i in range(n):
        assert np.allclose(F[i, :3, 2], dirs[i], atol=1e-9)
        if revolute[i]:                    # the frame's z line is the joint's axis
            off = F[i, :3, 3] - pts[i]
            assert np.linalg.norm(off - dirs[i] * (off @ dirs[i])) < 1e-9
    for i in range(1, n + 1):
        A = np.linalg.inv(F[i - 1]) @ F[i]
        assert abs(A[2, 0]) < 1e-9                              # x_i is normal to z_{i-1}
        theta = np.arctan2(A[1, 0], A[0, 0])
        assert abs(-A[0, 3] * np.sin(theta) + A[1, 3] * np.cos(theta)) < 1e-9  # meets z_{i-1}


def test_dh_frames_of_nearly_parallel_axes_are_finite():
    """Axes 1.2e-7 rad from antiparallel, their directions 7e-15 off unit length (a 12-digit
    pose's rotation moved them so, in the general 6R solver's shifted xarm6): 1 - (u.v)^2
    rounded to 0 and the common normal came out NaN ("SVD did not converge"). Its length is
    now |u x v|^2 and the directions' lengths are kept: the frames are finite, x normal to
    both axes, and the normal runs along x from frame 0's origin on axis 1 to frame 1's on
    axis 2, to the feet's conditioning (eps |w| / |u x v|^2 ~ 1e-2 m, 5.8e6 m along the
    axes; taking the directions for unit left it 0.29 m off)."""
    from kincalc.structure import dh_frames
    dirs = np.array([[-4.44400000959557e-09, 1.22076e-07, -1.0], [0.0, 0.0, 1.0]])
    pts = np.array([[1.906697022491244e-11, -0.703000007791385, 0.290999936256003],
                    [0.0, 0.0, 0.0]])
    assert dirs[0] @ dirs[1] == -1.0 and np.linalg.norm(dirs[0]) > 1 + 7e-15
    F = dh_frames(dirs[None], pts[None], 1.15, 1e-7)[0]
    assert np.isfinite(F).all()
    x, gap = F[1, :3, 0], F[1, :3, 3] - F[0, :3, 3]
    assert abs(x @ dirs[0]) < 1e-9 and abs(x @ dirs[1]) < 1e-9
    assert np.linalg.norm(gap - x * (gap @ x)) < 2e-2 and abs(gap @ x) < 1.0


@pytest.mark.parametrize("count", [1, 40])
def test_jacobian_zeros_are_positive(count):
    """A zero of the Jacobian is +0.0 in both evaluations (z_a d_b - z_b d_a of signed zeros
    gave -0.0, which numpy prints as '-0.')."""
    r = load_robot("puma560")
    q = np.tile([1.2174, -1.4296, 1.4390, 2.8684, -0.6245, 1.8170], (count, 1))
    for J in (r.jacobian(q), r.jacobian(q, frame="tool")):
        assert not np.signbit(J[J == 0.0]).any()
