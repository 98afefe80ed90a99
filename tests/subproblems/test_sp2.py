"""Subproblem 2, ``R(k1, theta1) R(k2, theta2) p1 = p2``: known answers, least squares,
ill-posed cases, golden values, batch shapes (see tests/subproblem_checks.py)."""

import numpy as np
import pytest

from kincalc.subproblems import sp2
from subproblem_checks import (LEAD, PI, X, Y, Z, check_batching, check_sane, is_local_minimum,
                               lengths, nearest_error, ok_count, rot, turn, unit)

N_DRAWS = 5000
ANGLE_TOL = 1e-7   # rad


def image(p1, k1, k2, t1, t2):
    """``R(k1, t1) R(k2, t2) p1``, broadcasting."""
    return turn(k1, t1, turn(k2, t2, p1))


def known_answers(rng, n, k1=None):
    """``(p1, p2, k1, k2, theta (n, 2))`` of n solvable problems (one shared first
    axis if given)."""
    k1 = unit(rng, n) if k1 is None else np.broadcast_to(k1, (n, 3))
    k2 = unit(rng, n)
    p1, t = lengths(rng, n)[:, 0], rng.uniform(-PI, PI, (n, 2))
    return p1, image(p1, k1, k2, t[:, 0], t[:, 1]), k1, k2, t


def slot_images(S, p1, k1, k2):
    """``R1 R2 p1`` of every slot ``(n, 2, 3)``."""
    return image(p1[:, None], k1[:, None], k2[:, None], S.theta[0], S.theta[1])


# --- 1. known answers --------------------------------------------------------

def test_known_answer_and_every_answer_solves_it():
    rng = np.random.default_rng(102)
    p1, p2, k1, k2, t = known_answers(rng, N_DRAWS)
    S = sp2(p1, p2, k1, k2)
    check_sane(S, (N_DRAWS,), 2, 2)
    assert S.ok[:, 0].all() and S.exact.all() and not S.free.any()
    err = nearest_error(S, t)
    assert err.max() < ANGLE_TOL, (err.argmax(), err.max())
    size = np.linalg.norm(p1, axis=-1)[:, None]
    res = np.linalg.norm(slot_images(S, p1, k1, k2) - p2[:, None], axis=-1) / size
    assert res[S.ok].max() < 1e-9
    assert (ok_count(S) == 2).mean() > 0.99


def test_cos_sin_are_those_of_theta():
    rng = np.random.default_rng(106)
    S = sp2(*known_answers(rng, N_DRAWS)[:4])
    for t, c, s in zip(S.theta, S.c, S.s):
        assert np.abs(c[S.ok] - np.cos(t[S.ok])).max() <= 1e-12
        assert np.abs(s[S.ok] - np.sin(t[S.ok])).max() <= 1e-12


# --- 2. least squares --------------------------------------------------------

def residual_checks(S, p1, p2, k1, k2):
    """Every ok slot a local minimum of ``|R1 R2 p1 - p2|``, and no worse than a dense
    scan of both angles."""
    grid = np.linspace(-PI, PI, 241)
    g1, g2 = np.meshgrid(grid, grid, indexing="ij")
    for i in range(len(p1)):
        def g(t):
            return np.linalg.norm(rot(k1[i], t[0]) @ rot(k2[i], t[1]) @ p1[i] - p2[i])

        scan = np.linalg.norm(image(p1[i], k1[i], k2[i], g1, g2) - p2[i], axis=-1).min()
        for sol in S.rows(i):
            assert is_local_minimum(g, sol), (i, sol)
            assert g(sol) <= scan + 1e-12, (i, sol, g(sol), scan)


def test_least_squares_with_unequal_norms_matches_the_directions():
    """``|p2| = 2 |p1|`` or ``|p1| / 2`` with a reachable direction: not exact, both
    solutions of the unit directions, at distance ``| |p1| - |p2| |`` (the least)."""
    rng = np.random.default_rng(302)
    n = 60
    p1, p2, k1, k2, t = known_answers(rng, n)
    p2 = p2 * rng.choice([0.5, 2.0], (n, 1))
    S = sp2(p1, p2, k1, k2)
    check_sane(S, (n,), 2, 2)
    assert not S.exact[S.ok].any() and not S.free.any()
    assert nearest_error(S, t).max() < ANGLE_TOL
    gap = np.abs(np.linalg.norm(p1, axis=-1) - np.linalg.norm(p2, axis=-1))
    dist = np.linalg.norm(slot_images(S, p1, k1, k2) - p2[:, None], axis=-1)
    size = np.broadcast_to(np.linalg.norm(p1, axis=-1)[:, None], S.ok.shape)
    assert (np.abs(dist - gap[:, None])[S.ok] <= 1e-9 * size[S.ok]).all()
    residual_checks(S, p1, p2, k1, k2)


@pytest.mark.parametrize("scale", [1.0, 3.0])
def test_least_squares_out_of_the_cone_is_the_closest_pair(scale):
    """The direction of ``p2`` out of reach (its height along ``k1`` beyond the cone of
    ``R2 p1``), with equal or unequal norms: one slot, not exact, the global least."""
    rng = np.random.default_rng(303)
    k1, k2, u = unit(rng, 400), unit(rng, 400), unit(rng, 400)
    # heights of R2 u along k1 over a scan, against that of the target
    heights = (turn(k2[:, None], np.linspace(-PI, PI, 721), u[:, None]) * k1[:, None]).sum(-1)
    p2 = unit(rng, 400)
    h2 = (p2 * k1).sum(-1)
    out = (h2 > heights.max(-1) + 0.05) | (h2 < heights.min(-1) - 0.05)
    k1, k2, u, p2 = k1[out][:60], k2[out][:60], u[out][:60], p2[out][:60]
    n = len(u)
    assert n == 60
    p1 = u * 10.0 ** rng.uniform(-3, 3, (n, 1))
    p2 = p2 * np.linalg.norm(p1, axis=-1, keepdims=True) * scale
    S = sp2(p1, p2, k1, k2)
    check_sane(S, (n,), 2, 2)
    assert (ok_count(S) == 1).all() and not S.exact.any() and not S.free.any()
    residual_checks(S, p1, p2, k1, k2)


# --- 3. ill-posed cases ------------------------------------------------------

def test_parallel_axes_are_free_with_the_sum_determined():
    # k1 = k2: only theta1 + theta2 is determined; theta2 = 0 represents it
    S = sp2(X, Y, Z, Z)
    check_sane(S, (), 2, 2)
    assert S.ok.tolist() == [True, False] and S.free[0] and S.exact[0]
    assert S.rows() == [(pytest.approx(PI / 2, abs=1e-15), 0.0)]
    assert [u[0] for u in S.undetermined] == [True, True]          # either angle
    S = sp2(X, Y + Z, Z, Z)                  # another height: no pair, still free
    assert S.free[0] and not S.exact[0]


def test_point_on_the_second_axis_is_free():
    # p1 on k2: theta2 free (0), theta1 turns p1 onto p2
    S = sp2([0, 0, 1], [1, 0, 0], Y, Z)
    check_sane(S, (), 2, 2)
    assert S.free[0] and S.exact[0]
    assert S.rows() == [(pytest.approx(PI / 2, abs=1e-15), 0.0)]
    assert [u[0] for u in S.undetermined] == [False, True]          # theta2 only


def test_rotated_point_on_the_first_axis_is_free():
    # R_x(t2) e_y = e_z at t2 = pi/2, then e_z is on k1 = z: theta1 free (0)
    S = sp2(Y, Z, Z, X)
    check_sane(S, (), 2, 2)
    assert S.free[0] and S.exact[0]
    assert S.rows() == [(0.0, pytest.approx(PI / 2, abs=1e-15))]
    assert [u[0] for u in S.undetermined] == [True, False]          # theta1 only


@pytest.mark.parametrize("lead", [(), (1,), (2, 3, 4)])
def test_which_angle_is_undetermined_is_each_angles_own_test_at_any_batch_shape(lead):
    """An angle is undetermined when turning it changes nothing: theta1 where p2 lies on k1
    (R1 turns p2's preimage about itself), theta2 where p1 lies on k2. Checked by turning
    each angle of the returned pair and seeing whether the equation still holds. (Parallel
    axes, where only the sum is fixed and either angle stands for the continuum, are the
    test above.)"""
    from kincalc.spatial import matrix_from_axis_angle
    cases = [(Y, Z, Z, X), ([0, 0, 1], [1, 0, 0], Y, Z), (X, Y, Z, X), (X, Y, Z, Y)]
    for p1, p2, k1, k2 in cases:
        p1, p2, k1, k2 = (np.broadcast_to(np.asarray(v, float), lead + (3,)) for v in
                          (p1, p2, k1, k2))
        S = sp2(p1, p2, k1, k2)
        if not S.free.any():
            assert S.undetermined is None
            continue
        t1, t2 = (t[..., 0].reshape(-1) for t in S.theta)
        for i, u in enumerate(S.undetermined):
            for j in range(t1.size):
                a = [t1[j], t2[j]]
                a[i] += 0.7
                R = matrix_from_axis_angle(k1.reshape(-1, 3)[j], a[0]) @ \
                    matrix_from_axis_angle(k2.reshape(-1, 3)[j], a[1])
                holds = np.allclose(R @ p1.reshape(-1, 3)[j], p2.reshape(-1, 3)[j])
                assert bool(u[..., 0].reshape(-1)[j]) == holds


def test_zero_points_are_free_and_finite():
    for p1, p2 in [(np.zeros(3), np.zeros(3)), (np.zeros(3), X), (X, np.zeros(3))]:
        S = sp2(p1, p2, Z, X)
        check_sane(S, (), 2, 2)
        assert S.free[S.ok].all()


# --- 4. golden cases ---------------------------------------------------------

def test_golden_two_quarter_turns():
    # R_z(t1) R_x(t2) e_z = e_x: t2 = -+pi/2 takes e_z to +-e_y, then t1 = -+pi/2
    S = sp2(Z, X, Z, X)
    assert S.ok.all() and S.exact.all() and not S.free.any()
    assert sorted(S.rows()) == [(-PI / 2, -PI / 2), (PI / 2, PI / 2)]


def test_golden_scaled_target_is_least_squares():
    # the same directions, |p2| = 2 |p1|: the same angles, not exact
    S = sp2(Z, 2 * X, Z, X)
    assert S.ok.all() and not S.exact.any()
    assert sorted(S.rows()) == [(-PI / 2, -PI / 2), (PI / 2, PI / 2)]


def test_golden_tangent():
    # R_x(t2) (e_x + e_y)/sqrt2 = (1, cos t2, sin t2)/sqrt2 reaches the height 1/sqrt2
    # along z only at t2 = pi/2: one (double) root; then R_z(pi/2) (1, 0, 1)/sqrt2 is
    # the target (0, 1, 1)/sqrt2
    S = sp2(np.array([1, 1, 0]) / 2 ** 0.5, np.array([0, 1, 1]) / 2 ** 0.5, Z, X)
    assert S.ok.tolist() == [True, False] and S.exact[0] and not S.free[0]
    assert S.rows() == [(pytest.approx(PI / 2, abs=1e-7), pytest.approx(PI / 2, abs=1e-7))]


@pytest.mark.parametrize("p1, p2, k1, k2", [(Z, -Z, X, Y), (-Z, Z, -X, -Y), (X, -X, Z, Z)])
def test_golden_half_turns_are_pi_not_minus_pi(p1, p2, k1, k2):
    S = sp2(p1, p2, k1, k2)
    assert S.exact[S.ok].all() and S.ok.any()
    for sol in S.rows():
        assert set(sol) <= {0.0, PI}, S.rows()


# --- 5. shapes ---------------------------------------------------------------

def mixed_batch(rng, k1=None):
    """``LEAD`` problems: solvable, least-squares (scaled target) and free ones."""
    n = int(np.prod(LEAD))
    p1, p2, k1, k2, _ = known_answers(rng, n, k1)
    p1, p2, k2 = p1.copy(), p2.copy(), k2.copy()
    p2[1::5] *= 2.0
    p1[2::5] = 3.0 * k2[2::5]
    k2[3::7] = k1[3::7]
    return [a.reshape(LEAD + (3,)) for a in (p1, p2, np.broadcast_to(k1, (n, 3)), k2)]


def test_batch_shapes_agree_with_each_problem_alone():
    rng = np.random.default_rng(501)
    S = check_batching(sp2, mixed_batch(rng), 2, 2)
    assert S.free.any() and not S.exact.all()


def test_a_shared_axis_broadcasts_against_per_problem_points():
    rng = np.random.default_rng(502)
    k1 = unit(rng)
    check_batching(sp2, mixed_batch(rng, k1), 2, 2, shared={2: k1})


def test_free_angles_names_the_undetermined_angle():
    """p1 on k2: theta2 is undetermined; p2 on k1: theta1; k1 along k2: both."""
    from kincalc.subproblems.sp2 import free_angles
    x, y, z = np.eye(3)
    yes = np.array(True)
    assert free_angles(yes, z, x, y, z) == (False, True)          # p1 on k2
    assert free_angles(yes, x, z, z, y) == (True, False)          # p2 on k1
    assert free_angles(yes, x, y, z, z) == (True, True)           # k1 along k2
    assert free_angles(np.array(False), z, x, y, z) == (False, False)
