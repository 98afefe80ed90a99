"""The one Newton iteration (kincalc.ik.newton: the Gauss-Newton polish and the Levenberg-Marquardt descent) and the solvers that use it."""

import numpy as np

import kincalc
from kincalc.ik.newton import _damped, _step, levenberg_marquardt, polish
from kincalc.ik.numeric import TOL, solve_numeric
from kincalc.ik.general6r import solve_general_6r
from kincalc.ik.selftest import sample_configurations


def _linear(A, b):
    def evaluate(x, rows):
        return b[rows] - (A[rows] @ x[..., None])[..., 0], lambda keep: A[rows][keep]
    return evaluate


def test_settle_skips_only_the_evaluation_that_confirms_convergence():
    """With ``settle`` (a bound on the second derivative: 2 for x^2), a step that provably
    lands below tol / 10 is not evaluated again: the same values as evaluating every step,
    one evaluation fewer for those, and a residual bound above the true residual."""
    t = np.array([2.0, 3.0, 0.25, 1.0, 1e10])

    def counting(seen):
        def evaluate(x, rows):
            seen.append(len(rows))
            return t[rows, None] - x * x, lambda keep: 2 * x[keep, :, None]
        return evaluate
    plain, settled = [], []
    x0 = np.sqrt(t)[:, None] + np.array([[1e-9], [-3e-10], [2e-3], [0.0], [1e-9]])
    x, res, moved = polish(counting(plain), x0, iterations=20, tol=1e-13)
    xs, rs, ms = polish(counting(settled), x0, iterations=20, tol=1e-13, settle=2.0)
    assert np.array_equal(x, xs) and np.array_equal(moved, ms)
    assert len(settled) < len(plain) and sum(settled) < sum(plain)
    # (the bound is on the exact residual; the evaluated one rounds)
    assert np.all(rs + 4e-16 * t >= np.abs(t - xs[:, 0] ** 2)) and np.all(rs[:3] < 1e-13)


def test_undamped_step_is_the_least_squares_solution():
    rng = np.random.default_rng(11)
    A, b = rng.normal(size=(20, 6, 4)), rng.normal(size=(20, 6))
    x, _, moved = polish(_linear(A, b), np.zeros((20, 4)), iterations=1, tol=0.0)
    ref = np.array([np.linalg.lstsq(a, y, rcond=None)[0] for a, y in zip(A, b)])
    assert moved.all() and np.allclose(x, ref, atol=1e-12)


def test_undamped_step_of_a_rank_deficient_jacobian_is_the_minimum_norm_one():
    rng = np.random.default_rng(12)
    A = rng.normal(size=(6, 3)) @ rng.normal(size=(3, 5))          # rank 3
    e = rng.normal(size=6)
    assert np.allclose(_step(A[None], e[None], 0.0)[0], np.linalg.pinv(A) @ e, atol=1e-10)


def test_damped_step_has_the_filter_factors_of_damped_least_squares():
    """(J^T J + l I)^-1 J^T e == V diag(s / (s^2 + l)) U^T e, l = damping |J|_F^2."""
    rng = np.random.default_rng(13)
    J = rng.normal(size=(8, 6, 6)) * np.logspace(0, -9, 6)          # ill-conditioned
    e = rng.normal(size=(8, 6))
    damping = 1e-14
    U, s, Vt = np.linalg.svd(J)
    lam = damping * (s * s).sum(-1, keepdims=True)
    ref = np.stack([Vt[m].T @ ((s[m] / (s[m] ** 2 + lam[m])) * (U[m].T @ e[m]))
                    for m in range(len(J))])
    got = _step(J, e, damping)
    assert np.allclose(got, ref, rtol=1e-6, atol=1e-9 * np.abs(ref).max())


def test_converges_quadratically_and_each_candidate_stops_on_its_own():
    # x^2 = t for t in (2, 3, 0.25) from 1.0: Newton's square roots
    t = np.array([2.0, 3.0, 0.25, 1.0])
    seen = []

    def evaluate(x, rows):
        seen.append(len(rows))
        return t[rows, None] - x * x, lambda keep: 2 * x[keep, :, None]
    x, res, moved = polish(evaluate, np.ones((4, 1)), iterations=20, tol=1e-15)
    assert np.allclose(x[:, 0], np.sqrt(t), rtol=0, atol=1e-15)
    assert res.max() < 1e-15 and list(moved) == [True, True, True, False]
    assert seen[0] == 4 and seen[1] == 3 and len(seen) <= 7        # quadratic: few steps


def test_fixed_variables_keep_their_start_and_the_others_solve_without_them():
    # x0 + x1 = 3 and x0 - x1 = c: with x0 fixed (rows 0 and 2) only x1 moves, to the
    # least-squares answer x1 = (3 - c) / 2 whatever x0; row 1 solves both exactly
    c = np.array([1.0, 1.0, -1.0])
    x0 = np.array([[0.5, 0.0], [0.5, 0.0], [2.0, 0.0]])
    fixed = np.array([[True, False], [False, False], [True, False]])
    A = np.array([[1.0, 1.0], [1.0, -1.0]])

    def evaluate(x, rows):
        return np.stack([3.0 - x[:, 0] - x[:, 1], c[rows] - x[:, 0] + x[:, 1]], -1), \
            lambda keep: np.broadcast_to(A, (np.count_nonzero(keep), 2, 2))
    x, _, _ = polish(evaluate, x0, iterations=5, tol=1e-14, fixed=fixed)
    assert x[0, 0] == 0.5 and x[2, 0] == 2.0
    assert np.allclose(x[[0, 2], 1], (3.0 - c[[0, 2]]) / 2, atol=1e-14)
    assert np.allclose(x[1], [2.0, 1.0], atol=1e-14)


def test_give_up_and_step_limit():
    # x^2 = -1 has no real root: dropped after 2 steps; steps capped at 0.1
    def evaluate(x, rows):
        return -1.0 - x * x, lambda keep: 2 * x[keep, :, None]
    x0 = np.array([[1.0], [0.5]])
    x, res, moved = polish(evaluate, x0, iterations=50, tol=1e-15, give_up={2: 1e-3},
                           max_step=0.1)
    assert moved.all() and (res > 1e-3).all()
    assert np.all(np.abs(x - x0) <= 2 * 0.1 + 1e-15)                # two capped steps


def test_general_6r_keeps_every_solution_at_a_nearly_singular_pose():
    """A nearly singular pose of the Manocha-Canny arm (the generating configuration's
    smallest singular value is ~1e-6, its solutions come in pairs 1e-5 rad apart), where
    the polish steps along a nearly singular direction: every solution the numerical
    solver finds from 300 seeded starts is among the general 6R elimination's."""
    r = kincalc.load_robot("manocha_canny_6r")
    Q = sample_configurations(r, 2000, np.random.default_rng(1))
    q_gen = Q[1599]
    assert np.linalg.svd(r.jacobian(q_gen), compute_uv=False)[-1] < 1e-5
    T = r.fk(q_gen)
    found = solve_general_6r(r, T)
    for q in found:
        assert np.allclose(r.fk(q), T, atol=1e-9)
    rng = np.random.default_rng(5)
    reference = []
    for _ in range(300):
        res = solve_numeric(r.fk, T, rng.uniform(-np.pi, np.pi, 6), jacobian=r.jacobian,
                            scale=r.characteristic_length, least_change=False, restarts=0)
        # roots to the solver's own tolerance (a descent that stalls short of it, within
        # the acceptance, is a solution too, but here 1e-4 rad from its root)
        if res.converged and np.hypot(res.position_error / r.characteristic_length,
                                      res.orientation_error) <= TOL:
            reference.append(res.q)
    assert reference

    def wrapped(a, b):
        return np.abs(np.angle(np.exp(1j * (a - b)))).max(-1)
    for q in reference:
        assert wrapped(found, q).min() < 1e-5, f"missed {np.round(q, 4)}"


def _circle_and_diagonal(x, rows):
    """x^2 + y^2 = 1 and x = y: the solutions (+-1, +-1) / sqrt(2)."""
    e = np.stack([1.0 - (x[:, 0] ** 2 + x[:, 1] ** 2), x[:, 1] - x[:, 0]], axis=-1)
    return e, lambda keep: np.stack([np.stack([2 * x[keep, 0], 2 * x[keep, 1]], -1),
                                     np.stack([np.ones(keep.sum()), -np.ones(keep.sum())],
                                              -1)], axis=1)


def test_levenberg_marquardt_converges_from_far_starts():
    starts = np.random.default_rng(3).uniform(-5, 5, (200, 2))
    x, e, steps = levenberg_marquardt(_circle_and_diagonal, starts, lo=-np.inf, hi=np.inf,
                                      iterations=100, tol=1e-14)
    root = np.sqrt(0.5)
    assert np.abs(e).max() <= 1e-14
    assert np.allclose(np.abs(x), root, atol=1e-14) and np.allclose(x[:, 0], x[:, 1])
    assert (steps < 100).all()


def test_levenberg_marquardt_holds_limits_and_fixed_variables():
    # the circle's root (0.707, 0.707) lies beyond x <= 0.5: the nearest point of the box
    # on the way, with x held on its limit, and a fixed y never moves
    x, e, _ = levenberg_marquardt(_circle_and_diagonal, [[0.2, 0.3]], lo=[-1, -1],
                                  hi=[0.5, 2], iterations=200, tol=1e-14)
    assert x[0, 0] == 0.5 and np.abs(e).max() > 1e-3           # held exactly on the limit
    x, _, _ = levenberg_marquardt(_circle_and_diagonal, [[0.2, 0.3]], lo=-np.inf,
                                  hi=np.inf, iterations=50, tol=1e-14, fixed=[False, True])
    a = x[0, 0]                     # y held: a stationary point of |e|^2 along x alone
    assert x[0, 1] == 0.3 and abs(-4 * a * (0.91 - a * a) - 2 * (0.3 - a)) < 1e-6


def test_levenberg_marquardt_rejects_points_the_model_refuses():
    # the model is undefined for x > 1 (inf residuals): every step there is rejected
    def evaluate(x, rows):
        e = np.where(x > 1.0, np.inf, 2.0 - 3.0 * x)
        return e, lambda keep: np.full((keep.sum(), 1, 1), 3.0)
    x, e, _ = levenberg_marquardt(evaluate, [[0.0]], lo=-np.inf, hi=np.inf, iterations=60,
                                  tol=1e-14, max_step=10.0)
    assert abs(x[0, 0] - 2 / 3) < 1e-14 and np.isfinite(e).all()


def test_damped_step_primal_and_dual_agree():
    rng = np.random.default_rng(11)
    for r, n in ((3, 7), (6, 6), (6, 4)):
        J, e, lam = rng.normal(size=(5, r, n)), rng.normal(size=(5, r)), np.full(5, 1e-2)
        mu = lam * (1 + (J * J).sum((1, 2)) / n)
        H = J.swapaxes(1, 2) @ J + mu[:, None, None] * np.eye(n)
        want = np.linalg.solve(H, (J.swapaxes(1, 2) @ e[..., None]))[..., 0]
        assert np.allclose(_damped(J, e, lam), want, atol=1e-12)


def test_levenberg_marquardt_with_fewer_free_variables_than_residuals():
    """A redundant system (6 residuals, 7 variables) with 4 variables fixed: the step's
    system is chosen by the free variables (3 < 6: the normal equations), not by all 7
    (the dual J J^T, of rank 3, was singular to rounding: numpy's LinAlgError from the
    numerical solver's least-change steps on the Panda). The descent reaches the
    least-squares point of the 3 free variables."""
    rng = np.random.default_rng(21)
    A, b = rng.normal(size=(6, 7)), rng.normal(size=6)
    fixed = np.array([True, False, True, True, False, False, True])
    x0 = rng.normal(size=7)

    def evaluate(x, rows):
        return b - x @ A.T, lambda keep: np.broadcast_to(A, (int(keep.sum()), 6, 7))
    x, e, _ = levenberg_marquardt(evaluate, x0[None], lo=-np.inf, hi=np.inf, iterations=100,
                                  tol=1e-14, fixed=fixed)
    free = ~fixed
    best = np.linalg.lstsq(A[:, free], b - A[:, fixed] @ x0[fixed], rcond=None)[0]
    assert np.array_equal(x[0, fixed], x0[fixed])
    assert np.allclose(x[0, free], best, atol=1e-9)


def test_damped_step_of_a_rank_deficient_system_is_the_svd_one():
    """Both forms singular to rounding (a zero Jacobian with no damping left): the SVD
    step, zero here, rather than numpy's LinAlgError."""
    J, e = np.zeros((2, 3, 4)), np.ones((2, 3))
    assert np.array_equal(_damped(J, e, np.zeros(2)), np.zeros((2, 4)))


def test_levenberg_marquardt_counts_a_gain_far_below_the_residual():
    """Out of reach: a residual of 8.6 that no step lowers, and a reachable part of 2.7e-8
    (|e|^2 changes by 1e-15, below the rounding of 74): taken all the same, since the
    gain is computed as (e' - e).(e' + e), not as a difference of squared norms."""
    def evaluate(x, rows):
        e = np.stack([np.full(len(x), 8.6), 0.1 - x[:, 0]], axis=-1)
        return e, lambda keep: np.broadcast_to([[0.0], [1.0]], (int(keep.sum()), 2, 1))
    x, e, _ = levenberg_marquardt(evaluate, [[0.1 - 2.7e-8]], lo=-np.inf, hi=np.inf,
                                  iterations=50, tol=1e-14)
    assert x[0, 0] == 0.1 and e[0, 1] == 0.0


def test_numerical_solutions_are_within_prismatic_limits_to_the_last_bit():
    """A prismatic joint held on its limit: the descent clips in scaled units (q / scale),
    and q = x scale may land an ulp beyond the limit (0.30000000000000004 for 0.3)."""
    hi, scale = 0.3, 0.543718592964824                 # (hi / scale) * scale > hi in floats
    assert (hi / scale) * scale > hi

    def fk(q):
        T = np.eye(4)
        T[0, 3], T[1, 3] = q
        return T
    T = np.eye(4)
    T[0, 3], T[1, 3] = 5.0, 0.1
    res = solve_numeric(fk, T, np.zeros(2), limits=[[-1, hi], [-1, 1]],
                        revolute=[False, False], scale=scale, orientation=False, restarts=0)
    assert res.q[0] == hi and res.q[1] == 0.1
