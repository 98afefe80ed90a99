"""The IK engine's post-processing of a pose's candidates, piece by piece, against values
computed here another way: the frames entry by entry, the cross product of the Levi-Civita
symbol, the label words (their rules written out per solution), the angle wrap and the
limits' normalisation on small and large batches, the duplicate screen with the chain's
offsets in its cosines."""

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.fk import FEW, chain_frames, entry_frames, frames_and_tool
from kincalc.ik.engine import singular
from kincalc.ik.joint_limits import close_pairs, duplicates
from kincalc.ik.joint_limits import normalise, violations
from kincalc.ik.words import branch_geometry, geometry
from kincalc.ik.selftest import sample_configurations
from kincalc.model import Joint, Robot
from kincalc.spatial import wrap
from kincalc.spatial import LEVI_CIVITA, wrap


def _chain_product(chain, q):
    """Frames after each joint's motion and the tool pose, multiplied out one by one."""
    T, frames = chain.fixed[0].copy(), []
    for i in range(chain.dof):
        x = q[i] + chain.offset[i]
        J = np.eye(4)
        if chain.revolute[i]:
            J[:2, :2] = [[np.cos(x), -np.sin(x)], [np.sin(x), np.cos(x)]]
        else:
            J[2, 3] = x
        T = T @ J
        frames.append(T)
        T = T @ chain.fixed[i + 1]
    return np.array(frames + [T])


@pytest.mark.parametrize("name", ["puma560", "stanford_arm", "ur5_poe", "puma560_mdh"])
@pytest.mark.parametrize("m", [3, FEW + 5])
def test_entry_frames_are_the_chain_product(name, m):
    """Both evaluations (stacked products for a few, the walk for many) give the frames of
    the chain multiplied out, entry by entry, and the joints' cosines, sines and values."""
    r = load_robot(name)
    Q = np.random.default_rng(1).uniform(-2, 2, (m, r.dof))
    A, f = entry_frames(r.chain, Q, coefficients=True)
    want = np.array([_chain_product(r.chain, q) for q in Q])          # (m, n + 1, 4, 4)
    assert A.shape == (3, 4, r.dof + 1, m)
    assert np.allclose(A, want[:, :, :3].transpose(2, 3, 1, 0), atol=1e-13)
    x = Q + r.chain.offset
    assert np.allclose(f, [np.cos(x), np.sin(x), x], atol=1e-15)
    assert np.array_equal(entry_frames(r.chain, Q), A)
    F, tool = frames_and_tool(r.chain, Q)                 # the same numbers, not just close
    assert np.array_equal(A[:, :, :-1], F[..., :3, :].transpose(2, 3, 1, 0))
    assert np.array_equal(A[:, :, -1], tool[:, :3].transpose(1, 2, 0))


def test_levi_civita_gives_the_cross_product_exactly():
    rng = np.random.default_rng(2)
    a, b = rng.normal(size=(2, 3, 50)) * 10.0 ** rng.integers(-8, 8, (2, 1, 50))
    got = LEVI_CIVITA @ (a[:, None] * b).reshape(9, -1)
    want = np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])
    assert np.array_equal(got, want)
    assert np.allclose(got.T, np.cross(a.T, b.T), rtol=1e-14, atol=0)


def _words(robot, family, F):
    """The words of one solution from its frames ``F (n, 4, 4)``, as ``man kincalc-ik``
    states the rules (codes as :func:`branch_geometry`)."""
    geo = geometry(robot, family)
    z, o = F[:, :3, 2], F[:, :3, 3]
    at = lambda p: F[p[0], :3, :3] @ p[1] + F[p[0], :3, 3]  # noqa: E731
    out = [0, 0, 0]
    if geo.shoulder is not None:
        side = geo.upward * np.dot(at(geo.shoulder) - o[0], np.cross(z[0], z[1]))
        out[0] = (1 if side >= 0 else 2) if geo.front == 0 else (3 if geo.front * side >= 0
                                                                   else 4)
    if geo.elbow is not None:
        j = geo.elbow[0]
        S, E, W, h = o[j], o[j + 1], at(geo.wrist_point), z[j] * geo.elbow_upward
        if geo.spatial:
            line, v = W - S - h * np.dot(h, W - S), E - S - h * np.dot(h, E - S)
            perp = v - line * np.dot(v, line) / np.dot(line, line)
            up = np.dot(perp, z[0]) * geo.upward
            if abs(up) < 1e-9 * robot.characteristic_length:
                up = np.dot(np.cross(E - S, W - E), h)
        else:
            up = np.dot(np.cross(W - S, E - S), h)
        out[1] = 1 if up >= 0 else 2
    if geo.wrist:
        out[2] = 1 if np.dot(np.cross(z[3], z[5]), z[4]) >= 0 else 2
    return out


@pytest.mark.parametrize("name", ["puma560", "kuka_kr16", "ur5", "abb_irb140", "stanford_arm",
                                  "fanuc_m10ia", "planar_3r", "fer_rrpr", "spong_scara"])
def test_label_words_are_their_rules(name):
    """The batched words (a matrix of differences, the Levi-Civita products, the spatial
    elbow's side from two triple products) against the rules evaluated per solution."""
    from kincalc.ik.families import plan
    r = load_robot(name)
    family = plan(r)[1].name
    Q = sample_configurations(r, 200, np.random.default_rng(3))
    F = chain_frames(r.chain, Q)
    got = branch_geometry(r, family, Q)
    want = np.array([_words(r, family, f) for f in F])
    assert got.shape == (len(Q), 3) and np.array_equal(got, want)
    for word, applies in enumerate(_applies(geometry(r, family))):
        assert len(np.unique(got[:, word])) == (2 if applies else 1), word    # both, or none


def _applies(geo):
    return geo.shoulder is not None, geo.elbow is not None, geo.wrist


def test_wrap_of_angles_within_a_half_turn_is_a_copy():
    x = np.array([-0.0, 0.5, -3.1, 3.1, np.nan])
    y = wrap(x)
    assert y is not x and np.array_equal(y[:4], x[:4]) and np.isnan(y[4])
    assert np.signbit(y[0]) == np.signbit(wrap(np.array([-2 * np.pi]))[0]) == False  # noqa: E712
    assert wrap(-np.pi) == np.pi and wrap(7.0) == pytest.approx(7.0 - 2 * np.pi)
    assert isinstance(wrap(0.5), np.ndarray) and wrap(0.5).shape == ()


def _limited(limits):
    joints = tuple(Joint(f"j{i + 1}", "revolute", alpha=np.pi / 2, a=0.1, d=0.2, theta=0.0,
                         limits=lim) for i, lim in enumerate(limits))
    return Robot("limited", "dh", joints)


@pytest.mark.parametrize("robot", [
    _limited([(-np.pi, np.pi), (0.0, 2 * np.pi), (-0.5, 0.5), (2.0, 5.0), None,
              (-7.0, 7.0)]),
    load_robot("stanford_arm"), load_robot("puma560")])
def test_normalise_is_the_same_on_few_and_many(robot):
    """Small batches compare with limits of their own shape, large ones broadcast: the same
    numbers, and each the turn the rule picks (within the limits, else missing them least)."""
    rng = np.random.default_rng(4)
    Q = rng.uniform(-9, 9, (700, robot.dof))
    many = normalise(robot, Q)
    few = np.array([normalise(robot, q[None])[0] for q in Q])
    assert np.array_equal(many, few) and not np.shares_memory(many, Q)
    lo, hi = robot.limits.T
    rev = robot.is_revolute
    turns = Q[:, :, None] + 2 * np.pi * np.arange(-4, 5)              # every representative
    miss = np.maximum(np.maximum(lo[:, None] - turns, turns - hi[:, None]), 0.0)
    best = np.take_along_axis(miss, np.argmin(miss, -1)[..., None], -1)[..., 0]
    d = np.abs(wrap(many - Q))
    assert (d[:, rev] < 1e-9).all() and np.array_equal(many[:, ~rev], Q[:, ~rev])
    got = np.maximum(np.maximum(lo - many, many - hi), 0.0)
    assert np.allclose(got[:, rev], best[:, rev], atol=1e-9)
    assert np.array_equal(violations(robot, many) != 0, got > 1e-9 * np.where(
        rev, 1.0, robot.characteristic_length))


def test_duplicate_screen_takes_cosines_with_offsets():
    """The key may be of q plus the chain's offsets (the cosines the FK check has): the
    same slots dropped."""
    r = load_robot("stanford_arm")
    rng = np.random.default_rng(5)
    q = np.repeat(rng.uniform(-3, 3, (40, 1, 6)), 4, axis=1)
    q[:, 1:] += rng.choice([0.0, 3e-7, 1e-3], (40, 3, 6))
    valid = rng.random((40, 4)) < 0.9
    x = q.reshape(-1, 6).T + r.chain.offset[:, None]
    f = np.cos(x), np.sin(x), x
    with_f = duplicates(r, q, valid, close_pairs(r, q, valid, f))
    assert np.array_equal(with_f, duplicates(r, q, valid, close_pairs(r, q, valid)))
    assert with_f.any()


@pytest.mark.parametrize("name", ["puma560", "ur5", "bk_rrp"])
def test_singular_from_frames_is_the_jacobians_rank(name):
    """The rank test on the frames entry by entry (the SVD only where the determinant does
    not prove full rank) against the Jacobian's own scaled ranks."""
    from kincalc.jacobian import scaled_ranks
    r = load_robot(name)
    rng = np.random.default_rng(6)
    Q = rng.uniform(-3, 3, (60, r.dof))
    Q[:20, min(4, r.dof - 1)] = 0.0
    F, tool = frames_and_tool(r.chain, Q)
    rank, position_rank = scaled_ranks(r.jacobian(Q), r.is_revolute, r.characteristic_length)
    full, full_pos = r.generic_ranks
    assert np.array_equal(singular(r, Q, F, tool), (rank < full) | (position_rank < full_pos))


@pytest.mark.parametrize("name", ["ur5", "mycobot_280", "bk_offset_wrist", "puma560", "kuka_kr16",
                                  "stanford_arm", "adept_cobra600", "siciliano_arm",
                                  "lynxmotion_al5d", "kinova_gen3_6dof", "spong_cylindrical"])
def test_slot_layout_whatever_the_batch(name):
    """The engine checks only the slots some pose of the batch keeps and puts the family's
    layout back: a pose solved alone (a three-parallel arm's "other arc" slots all empty, so
    not checked) and in a batch with singular poses (those slots live) lays its solutions
    out in the same slots, with the same values, labels and flags; an empty slot holds no
    candidate."""
    robot = load_robot(name)
    Q = sample_configurations(robot, 12, np.random.default_rng(5))
    Q[::2, min(4, robot.dof - 1)] = 0.0                  # wrist singular (UR: q5 = 0)
    Q[1::4, min(2, robot.dof - 1)] = 0.0                 # elbow stretched or folded
    T = robot.fk(Q)
    together = robot.ik_batch(T)
    for i in range(len(T)):
        alone = robot.ik_batch(T[i])
        assert alone.q.shape[1:] == together.q.shape[1:]
        assert alone.signs == together.signs
        v = alone.valid[0]
        assert np.array_equal(v, together.valid[i])
        np.testing.assert_allclose(alone.q[0][v], together.q[i][v], atol=1e-9)
        assert alone.labels[0][v].tolist() == together.labels[i][v].tolist()
        assert np.array_equal(alone.singular[0], together.singular[i])
        assert np.array_equal(alone.within[0][v], together.within[i][v])
        assert np.array_equal(alone.free[0][v], together.free[i][v])
        # every solution reaches its pose (FK, not the engine's own check)
        assert np.allclose(robot.fk(alone.q[0][v]), T[i], atol=1e-8)
    assert together.valid.any(axis=1).all()


def test_continuum_of_a_slot_after_dropped_ones():
    """UR5 at q5 = 0: each solution's continuum is the parallel joints' sum at that solution,
    read from the slot the check kept (slots no target kept, before it, are not counted)."""
    robot = load_robot("ur5")
    Q = sample_configurations(robot, 6, np.random.default_rng(5))
    Q[:, 4] = 0.0
    for q in Q:
        T = robot.fk(q)
        assert not robot.ik_batch(T).candidate.all()       # some slots are dropped
        sols = [s for s in robot.ik(T).solutions if s.continuum is not None]
        assert sols and all(s.singular for s in sols)
        for s in sols:
            c = s.continuum
            total = sum(sign * s.q[j] for j, sign in zip(c.joints, c.signs))
            assert abs(wrap(total - c.total)) < 1e-9


@pytest.mark.parametrize("name, has", [("bk_rpr", False), ("puma560", True), ("ur5", True),
                                       ("kuka_kr16", True), ("siciliano_arm", True)])
def test_shoulder_word_only_where_the_point_leaves_the_plane(name, has):
    """The shoulder word is the side of its point P of the plane of axes 1 and 2: an arm
    that keeps P in that plane whatever its joints (Example 4.4's RPR arm: products of
    1e-16 m at every seeded configuration, a word of rounding) has none."""
    robot = load_robot(name)
    family = {"bk_rpr": "position-3", "ur5": "three-parallel",
              "siciliano_arm": "position-3"}.get(name, "spherical-wrist")
    geo = geometry(robot, family)
    Q = sample_configurations(robot, 200, np.random.default_rng(2))
    A = entry_frames(robot.chain, Q)
    z1, z2, o1 = A[:, 2, 0], A[:, 2, 1], A[:, 3, 0]
    f, local = geo.placed
    P = np.einsum("abm,b->am", A[:, :3, f], local) + A[:, 3, f]
    side = np.einsum("am,am->m", P - o1, np.cross(z1, z2, axis=0))
    assert (geo.shoulder is not None) == has
    assert (np.abs(side).max() > 1e-6 * robot.characteristic_length) == has


#: a reversed offset-wrist arm of an independent random-robot campaign (standard DH: alpha,
#: a, d, theta, kind), at a pose where joint 4 lines axes 3 and 5 up: a double root, which
#: the closed form split by rounding into two solutions 2.8e-6 rad apart, each reaching the
#: pose (labels "j4:root 1" and "j4:root 2")
SPLIT_ROOT_ARM = [(2.8970603682662013, 0.0, -0.013793069065852202, 3.1297540493797502, "revolute"),
                  (1.5707963267948966, 0.032029708715551684, 0.51166296562628866,
                   0.82394443976148235, "revolute"),
                  (np.pi, -0.3955871678616999, -0.020368689328579846, -2.3447749278765295,
                   "revolute"),
                  (np.pi, 0.76999058778263196, -0.19402485949179893, 2.3696925029871956,
                   "revolute"),
                  (0.0, 0.0, 0.0, 2.633154708845959, "prismatic"),
                  (-np.pi / 2, -0.30501839967429573, -0.60169214710507268, 1.178712422981139,
                   "revolute")]
SPLIT_ROOT_Q = [1.3024888468736782, -0.8251654617298438, -2.790213535249602,
                -2.3696925029871956, -2.6715562591073754, -2.6667339759312627]


def test_a_double_root_split_by_rounding_comes_back_once():
    """Two solutions within SAME_DOUBLE_ROOT whose halfway configuration reaches the target
    too are one double root: the one that misses more goes (the engine's rule for polished
    copies, now for any two). Checked by FK: the kept one reaches, the generating
    configuration is next to it, single and batch agree, and no other two are that close."""
    joints = tuple(Joint(f"j{i + 1}", kind, alpha=al, a=a, d=d,
                         theta=th if kind == "revolute" else 0.0,
                         limits=(-5.0, 5.0) if kind == "prismatic" else (-np.pi, np.pi))
                   for i, (al, a, d, th, kind) in enumerate(SPLIT_ROOT_ARM))
    r = Robot(name="split_root", convention="dh", joints=joints)
    q0 = np.array(SPLIT_ROOT_Q)
    T = r.fk(q0)
    sols = r.ik(T).solutions
    Q = np.array([s.q for s in sols])
    assert np.abs(r.fk(Q) - T).max() < 1e-9
    near = np.abs(wrap(Q - q0)).max(-1) < 1e-5
    assert near.sum() == 1, [(s.q, s.branch) for s in sols]
    batch = r.ik_batch(T[None])
    assert int(batch.valid.sum()) == len(sols)
    assert all(np.abs(wrap(a - b)).max() > 1e-5 for k, a in enumerate(Q) for b in Q[:k])


#: a SCARA (slide, then three parallel revolute axes) and joints at its stretched elbow, where
#: rounding splits the elbow's double root into two copies ~2e-6 rad apart (the random-robot
#: campaign's scara43, in standard DH)
STRETCHED_SCARA = [(0.0, 0.015780980739033904, 0.0, -2.3829135839389828, "prismatic"),
                   (0.0, -0.46761020685489357, 0.0, -1.4512750156378911, "revolute"),
                   (np.pi, 0.39639680419647433, 0.0, 2.3015301078042789, "revolute"),
                   (0.0, 0.0, 0.0, 1.855797148969633, "revolute")]
STRETCHED_Q = [-0.18517518399912003, 2.220760059970716, -2.301530107804279, 0.7149983989736426]
STRETCHED_BASE = [[-0.16212194401091118, -0.91306169019129746, -0.37421227288149483,
                   0.23199535664214543],
                  [0.66357981337144911, -0.38155406417461668, 0.64348918203629935,
                   0.48924691863826153],
                  [-0.7303275337518339, -0.14399599305829219, 0.66774759260301364,
                   0.36740131726466119], [0, 0, 0, 1]]


@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_a_double_root_split_by_rounding_is_answered_at_its_middle(convention):
    """Two copies of one double root (each reaching the target, 2.2e-6 rad apart, on either
    side of the stretched elbow) are answered once, at the joints halfway between them: the
    generating joints to 1e-8 (each copy is 1.1e-6 off), with the same joints and label in
    standard DH, modified DH and the product of exponentials (which copy missed less, and its
    label, elbow up or down, differed between them)."""
    from kincalc.conventions.conversion import convert
    joints = tuple(Joint(f"j{i + 1}", kind, alpha=al, a=a, d=d,
                         theta=th if kind == "revolute" else 0.0)
                   for i, (al, a, d, th, kind) in enumerate(STRETCHED_SCARA))
    dh = Robot(name="stretched", convention="dh", joints=joints,
               base=np.array(STRETCHED_BASE, float))
    r = dh if convention == "dh" else convert(dh, convention)
    q0 = np.array(STRETCHED_Q)
    T = dh.fk(q0)
    assert np.abs(r.fk(q0) - T).max() < 1e-14
    sols = r.ik(T).solutions
    assert len(sols) == 1, [(s.q, s.branch) for s in sols]
    assert np.abs(wrap(np.array(sols[0].q) - q0)).max() < 1e-8
    assert np.abs(r.fk(np.array(sols[0].q)) - T).max() < 1e-12
    assert "elbow" not in sols[0].branch                # neither side of the stretched elbow
    batch = r.ik_batch(T[None])
    assert int(batch.valid.sum()) == 1
    assert np.array_equal(batch.q[batch.valid][0], np.array(sols[0].q))


def test_two_exact_roots_close_together_are_two_solutions():
    """A PUMA 560 pose 5e-5 deg from the stretched elbow has two exact elbow roots 1.7e-6
    rad apart on each shoulder and wrist branch; their halfway joints reach the pose only to
    1e-13, less well than either root: two roots, as EAIK and ik-geo find them (an earlier
    engine took them for one double root and kept 4 solutions of 8)."""
    r = load_robot("puma560")
    q = np.radians([10, -45, -87.30836366293622 + 5e-5, 20, 30, 40])
    T = r.fk(q)
    sols = r.ik(T).solutions
    assert len(sols) == 8 and len({s.branch for s in sols}) == 8
    assert np.abs(r.fk(np.array([s.q for s in sols])) - T).max() < 1e-14
    assert min(np.abs(wrap(s.q - q)).max() for s in sols) < 1e-8    # (a root 1.7e-6 from another)


#: a reversed parallel-four-wrist arm (its joint 6 a slide; the random-robot campaign's
#: rp4w0) and joints at its stretched elbow, where the target changes to second order only:
#: its closed form placed the double root 1.3e-4 rad either side, two solutions each
#: reaching the pose to 2.5e-11 of the arm's size
FLAT_ROOT_ARM = """name: flat_root
convention: dh
units: {length: m, angle: rad}
joints:
  - {name: j1, type: revolute, alpha: 0.29520298696420388, a: 0, d: 1.8845997542935491, theta: -1.017729444441605}
  - {name: j2, type: revolute, alpha: -0.6465397763878199, a: 0.043082126964808426, d: -0.045217052155811309, theta: -0.94080727742463832}
  - {name: j3, type: revolute, alpha: 0, a: 1.1569560610169152, d: 0, theta: 2.9627958727322854}
  - {name: j4, type: revolute, alpha: 0, a: 1.1709599880758799, d: 0.94188729179636521, theta: -0.61894635022392341}
  - {name: j5, type: revolute, alpha: 3.1415926535897931, a: -0.024094197631002828, d: 0, theta: -0.74334595584806573}
  - {name: j6, type: prismatic, alpha: 1.6041831889192331, a: 0, d: -0.41922024986832057, theta: 1.2018906790119788}
base: [[0.79405027124860639, 0.068018252180544969, -0.60403450571992867, -0.3871645751245717], [0.60024709989599367, -0.24444117777801777, 0.76154575021658744, -0.20641353948677632], [-0.095851895111487839, -0.96727556982320184, -0.23492634213033026, -0.016170672492288873], [0, 0, 0, 1]]
tool: [[0.27734800978807694, -0.90513896767199375, -0.32218244934861062, 0.092121662282915906], [0.29046349547918149, -0.24065199494327327, 0.92613043094579162, -0.16050410016792882], [-0.91581059136734611, -0.35044267224683096, 0.19616547659537809, -0.10642034707206782], [0, 0, 0, 1]]
"""
FLAT_ROOT_Q = [-1.8976672705440027, 1.4691529834482973, -0.8957634032045916,
               -2.5226463033658693, -1.1650687622997897, -1.092149781691231]


@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_the_two_sides_of_a_flat_double_root_are_one_solution_between_them(convention):
    """Two solutions 2.6e-4 rad apart, neither reaching the pose to rounding, whose halfway
    joints reach it better than both, are the two sides of one double root: answered once,
    at those joints (1e-7 from the generating joints, the pose to rounding), alike in
    standard DH, modified DH and the product of exponentials."""
    from kincalc import parse_robot_text
    from kincalc.conventions.conversion import convert
    dh = parse_robot_text(FLAT_ROOT_ARM)
    r = dh if convention == "dh" else convert(dh, convention)
    q0 = np.array(FLAT_ROOT_Q)
    T = dh.fk(q0)
    Q = np.array([s.q for s in r.ik(T).solutions])
    assert np.abs(r.fk(Q) - T).max() < 1e-13
    d = np.abs(np.where(r.is_revolute, wrap(Q - q0), Q - q0)).max(-1)
    assert np.count_nonzero(d < 1e-2) == 1, d
    assert d.min() < 1e-6


#: an R-R-R-P arm (solved from the tool: a reversed point-plus-roll) and joints at which
#: axis 2 lines up with the others: its placement's double root came as two copies 1.1e-6
#: rad apart, each, and the joints halfway, reaching the pose to rounding (2e-15)
ROUNDED_ROOT_ARM = """name: rounded_root
convention: dh
units: {length: m, angle: rad}
joints:
  - {name: j1, type: revolute, alpha: 0, a: 0.2096937988630283, d: -0.5384121136328055, theta: -1.6881100870589356}
  - {name: j2, type: revolute, alpha: 3.1415926535897931, a: -0.040284228106519847, d: 0.010499303545724523, theta: -2.7754511846769168}
  - {name: j3, type: revolute, alpha: 0, a: 1.011494383987845, d: 0, theta: -1.5474345275397001}
  - {name: j4, type: prismatic, alpha: 0, a: 0, d: -0.069844423967616157, theta: 1.5473853954059864}
base: [[0.0045098678879632592, -0.80816951481736932, -0.5889326756187766, -0.4673942376684328], [-0.81655123652244921, 0.33699527685810515, -0.46869847611122889, -0.10514225985376113], [0.57725535010538642, 0.48300747271153793, -0.65839201246637313, -0.39659297880757793], [0, 0, 0, 1]]
tool: [[-0.41894344668768735, 0.095661125761802746, 0.9029592114239855, -0.061051421275444467], [-0.044216407566594368, -0.99540449493147332, 0.08493998335368165, -0.24565687474536729], [0.90693511222101542, -0.0043405631205474388, 0.42124798127997087, 0.23408960166271658], [0, 0, 0, 1]]
"""
ROUNDED_ROOT_Q = [-2.720762347406069, 2.7754511846769168, -2.1346067422546184,
                  -1.875583763941596]


def test_copies_that_rounding_cannot_tell_apart_are_answered_between_them():
    """Two copies of a double root and the joints halfway all reaching the pose to rounding
    (a few 1e-15, where which one misses least is noise) are answered halfway, 1e-8 from the
    generating joints, with one label, in standard DH and the product of exponentials (the
    copy that missed less was kept in one, 5.5e-7 from the other's answer, 'root 2' against
    'root 1')."""
    from kincalc import parse_robot_text
    from kincalc.conventions.conversion import convert
    dh = parse_robot_text(ROUNDED_ROOT_ARM)
    q0 = np.array(ROUNDED_ROOT_Q)
    T = dh.fk(q0)
    answers = []
    for r in (dh, convert(dh, "mdh"), convert(dh, "poe")):
        sols = r.ik(T).solutions
        assert len(sols) == 1, [(s.q, s.branch) for s in sols]
        assert np.abs(r.fk(np.array(sols[0].q)) - T).max() < 1e-13
        answers.append((np.array(sols[0].q), sols[0].branch))
    for q, label in answers:
        assert np.abs(np.where(dh.is_revolute, wrap(q - q0), q - q0)).max() < 1e-8
        assert label == answers[0][1]
