"""Orientation formats: round trips (hypothesis), gimbal lock, quaternion sign, batching."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kincalc import spatial as sp

angle = st.floats(-math.pi, math.pi, allow_nan=False)
special = st.sampled_from([0.0, math.pi / 2, -math.pi / 2, math.pi, -math.pi,
                           math.pi / 2 - 1e-10, 1e-12, -1e-12])
any_angle = st.one_of(angle, special)
triple = st.tuples(any_angle, any_angle, any_angle)
quat = st.tuples(*[st.floats(-1, 1, allow_nan=False)] * 4).filter(
    lambda q: 0.1 < np.linalg.norm(q))


def is_rotation(R):
    return np.allclose(R @ R.T, np.eye(3), atol=1e-12) and np.isclose(np.linalg.det(R), 1.0)


def test_elementary_rotations_by_hand():
    c, s = math.cos(0.3), math.sin(0.3)
    assert np.allclose(sp.rot_z(0.3), [[c, -s, 0], [s, c, 0], [0, 0, 1]])
    assert np.allclose(sp.rot_y(0.3), [[c, 0, s], [0, 1, 0], [-s, 0, c]])
    assert np.allclose(sp.rot_x(0.3), [[1, 0, 0], [0, c, -s], [0, s, c]])


def test_rpy_matches_textbook_example_4_6():
    # Bingül & Küçük Example 4.6 prints R_XYZ(42, -17, 25) to 4 decimals
    R = sp.matrix_from_rpy(np.deg2rad([42, -17, 25]))
    book = [[0.8667, -0.4914, 0.0858], [0.4041, 0.5909, -0.6982], [0.29237, 0.6399, 0.7107]]
    assert np.allclose(R, book, atol=2e-4)


@settings(max_examples=300, deadline=None)
@given(triple)
def test_rpy_round_trip(a):
    R = sp.matrix_from_rpy(a)
    back = sp.rpy_from_matrix(R)
    assert np.allclose(sp.matrix_from_rpy(back), R, atol=1e-9)
    assert -math.pi / 2 - 1e-12 <= back[1] <= math.pi / 2 + 1e-12


@settings(max_examples=300, deadline=None)
@given(triple)
def test_zyz_round_trip(a):
    R = sp.matrix_from_euler_zyz(a)
    back = sp.euler_zyz_from_matrix(R)
    assert np.allclose(sp.matrix_from_euler_zyz(back), R, atol=1e-9)
    assert -1e-12 <= back[1] <= math.pi + 1e-12


@settings(max_examples=300, deadline=None)
@given(triple)
def test_xyz_round_trip(a):
    R = sp.matrix_from_euler_xyz(a)
    back = sp.euler_xyz_from_matrix(R)
    assert np.allclose(sp.matrix_from_euler_xyz(back), R, atol=1e-9)


@pytest.mark.parametrize("pitch", [math.pi / 2, -math.pi / 2])
def test_rpy_gimbal_lock_puts_rotation_in_yaw(pitch):
    R = sp.matrix_from_rpy([0.4, pitch, 1.1])
    r, p, y = sp.rpy_from_matrix(R)
    assert r == 0.0 and math.isclose(p, pitch)
    assert np.allclose(sp.matrix_from_rpy([r, p, y]), R, atol=1e-12)


@pytest.mark.parametrize("b", [0.0, math.pi])
def test_zyz_gimbal_lock(b):
    R = sp.matrix_from_euler_zyz([0.7, b, -0.2])
    a, bb, c = sp.euler_zyz_from_matrix(R)
    assert a == 0.0 and math.isclose(bb, b, abs_tol=1e-12)
    assert np.allclose(sp.matrix_from_euler_zyz([a, bb, c]), R, atol=1e-12)


@settings(max_examples=300, deadline=None)
@given(quat)
def test_quaternion_round_trip_and_sign(q):
    q = np.array(q) / np.linalg.norm(q)
    R = sp.matrix_from_quaternion(q)
    assert is_rotation(R)
    assert np.allclose(sp.matrix_from_quaternion(-q), R)
    back = sp.quaternion_from_matrix(R)
    assert back[0] >= 0
    assert np.allclose(back, q if q[0] >= 0 else -q, atol=1e-9) or \
        (abs(q[0]) < 1e-9 and np.allclose(np.abs(back), np.abs(q), atol=1e-9))


def test_quaternion_of_180_degree_turns():
    for axis in np.eye(3):
        R = sp.matrix_from_axis_angle(axis, math.pi)
        q = sp.quaternion_from_matrix(R)
        assert abs(q[0]) < 1e-15
        assert np.allclose(np.abs(q[1:]), axis)


@settings(max_examples=300, deadline=None)
@given(st.tuples(*[st.floats(-1, 1, allow_nan=False)] * 3).filter(
    lambda v: np.linalg.norm(v) > 1e-3), st.floats(0, math.pi))
def test_axis_angle_round_trip(axis, ang):
    R = sp.matrix_from_axis_angle(axis, ang)
    ax, an = sp.axis_angle_from_matrix(R)
    assert np.allclose(sp.matrix_from_axis_angle(ax, an), R, atol=1e-9)
    assert 0 <= an <= math.pi + 1e-12
    rv = sp.rotvec_from_matrix(R)
    assert np.allclose(sp.matrix_from_rotvec(rv), R, atol=1e-9)


def test_rotation_vector_against_rodrigues_by_hand():
    # 90 deg about z: rotation vector (0, 0, pi/2)
    assert np.allclose(sp.rotvec_from_matrix(sp.rot_z(math.pi / 2)), [0, 0, math.pi / 2])
    assert np.allclose(sp.rotvec_from_matrix(np.eye(3)), 0)


@pytest.mark.parametrize("angle", [1e-15, 1e-13, 1e-12, 3e-12, 1e-10])
def test_rotation_vector_of_a_tiny_rotation_keeps_its_direction(angle):
    """Below 2e-12 rad the axis of axis_angle_from_matrix is reported as z; the rotation
    vector, a Newton polish's orientation residual, must keep the rotation's own direction
    (it had pointed along z: a polish near rounding oscillated at 1e-12)."""
    rng = np.random.default_rng(7)
    for _ in range(20):
        r = rng.standard_normal(3)
        r *= angle / np.linalg.norm(r)
        R = np.eye(3) + sp.skew(r) + 0.5 * sp.skew(r) @ sp.skew(r)     # exp to O(angle^3)
        assert np.allclose(sp.rotvec_from_matrix(R), r, rtol=1e-3, atol=2e-16)


def test_rotation_vector_agrees_with_the_quaternion_route_at_every_angle():
    """rotvec_from_matrix reads angles up to a quarter turn from the skew part and the trace;
    the quaternion of axis_angle_from_matrix (Shepperd) is a second formulation."""
    rng = np.random.default_rng(9)
    axes = rng.normal(size=(400, 3))
    angles = np.concatenate([rng.uniform(0, np.pi, 392),
                             [1e-9, np.pi / 2 - 1e-9, np.pi / 2, np.pi / 2 + 1e-9, 2.0,
                              np.pi - 1e-9, np.pi - 1e-12, 1e-6]])
    R = sp.matrix_from_axis_angle(axes, angles)
    axis, angle = sp.axis_angle_from_matrix(R)
    want = axis * angle[:, None]
    got = sp.rotvec_from_matrix(R)
    half = angles > np.pi - 1e-6                    # a half turn: +-axis is one rotation
    assert np.allclose(got[~half], want[~half], atol=1e-12)
    assert np.allclose(np.abs(got[half]), np.abs(want[half]), atol=1e-6)


def test_tcv_round_trip():
    T = sp.transform(sp.matrix_from_rpy([0.1, 0.2, 0.3]), [1, 2, 3])
    w = sp.tcv_from_transform(T, 0.7)
    p, approach, qn = sp.transform_from_tcv(w)
    assert np.allclose(p, [1, 2, 3]) and np.allclose(approach, T[:3, 2])
    assert math.isclose(qn, 0.7)
    assert math.isclose(np.linalg.norm(w[3:]), math.exp(0.7 / math.pi))


@pytest.mark.parametrize("shape", [(), (1,), (2, 3, 4)])
def test_batched_equals_single(shape):
    rng = np.random.default_rng(3)
    a = rng.uniform(-3, 3, shape + (3,))
    Rb = sp.matrix_from_rpy(a)
    assert Rb.shape == shape + (3, 3)
    flat = a.reshape(-1, 3)
    single = np.array([sp.matrix_from_rpy(x) for x in flat]).reshape(shape + (3, 3))
    assert np.array_equal(Rb, single)
    for f in (sp.rpy_from_matrix, sp.euler_zyz_from_matrix, sp.euler_xyz_from_matrix,
              sp.quaternion_from_matrix, sp.rotvec_from_matrix):
        out = f(Rb)
        ref = np.array([f(R) for R in Rb.reshape(-1, 3, 3)])
        assert np.allclose(out.reshape(ref.shape), ref)


def test_inputs_not_modified():
    R = sp.matrix_from_rpy([0.1, 0.2, 0.3])
    keep = R.copy()
    sp.quaternion_from_matrix(R)
    sp.rpy_from_matrix(R)
    sp.invert_transform(sp.transform(R, [1, 2, 3]))
    assert np.array_equal(R, keep)


def test_log_transform_inverts_exponential():
    # exp of a twist by the closed form (Lynch & Park eq. 3.88), then log
    rng = np.random.default_rng(5)
    for _ in range(200):
        w = rng.normal(size=3)
        w *= rng.uniform(0, 3) / np.linalg.norm(w)
        v = rng.normal(size=3)
        th = np.linalg.norm(w)
        W = sp.skew(w / th)
        R = np.eye(3) + math.sin(th) * W + (1 - math.cos(th)) * W @ W
        G = np.eye(3) * th + (1 - math.cos(th)) * W + (th - math.sin(th)) * W @ W
        T = sp.transform(R, G @ (v / th))
        assert np.allclose(sp.log_transform(T), np.r_[v, w], atol=1e-9)


@pytest.mark.parametrize("to, back, angles", [
    ("matrix_from_euler_zyz", "euler_zyz_from_matrix", (0.0, -5.090312683512367e-10, 0.0)),
    ("matrix_from_euler_zyz", "euler_zyz_from_matrix", (0.3, math.pi - 7e-10, -1.0)),
    ("matrix_from_rpy", "rpy_from_matrix", (0.2, math.pi / 2 - 9e-10, 0.0)),
    ("matrix_from_rpy", "rpy_from_matrix", (2.0, -math.pi / 2 + 9e-10, 0.5)),
    ("matrix_from_euler_xyz", "euler_xyz_from_matrix", (1.0, math.pi / 2 - 9e-10, -0.4)),
])
def test_near_gimbal_lock_round_trip_is_within_the_lock_tolerance(to, back, angles):
    # a tilt below GIMBAL_TOL is read as lock (first angle 0); the middle angle must then
    # be the exact lock value, or the tilt comes back pointing the wrong way (hypothesis
    # found b = -5.09e-10 returned as +5.09e-10: a 1.02e-9 error)
    R = getattr(sp, to)(angles)
    R2 = getattr(sp, to)(getattr(sp, back)(R))
    assert np.abs(R2 - R).max() < 1e-9


@pytest.mark.parametrize("zero", [0.0, -0.0])
def test_half_turns_read_as_plus_pi_whatever_the_sign_of_zero(zero):
    """A half turn is +pi in every angle set: the sign a rounding leaves on a zero
    entry must not flip a printed 180 to -180 (README's fk example at q3 = 180 deg)."""
    from kincalc.spatial import euler_xyz_from_matrix, euler_zyz_from_matrix, rpy_from_matrix
    z = np.array([[-1.0, zero, 0.0], [zero, -1.0, zero], [0.0, zero, 1.0]])      # Rz(pi)
    x = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, zero], [0.0, zero, -1.0]])       # Rx(pi)
    assert rpy_from_matrix(z)[2] == np.pi and rpy_from_matrix(x)[0] == np.pi
    assert euler_xyz_from_matrix(x)[0] == np.pi
    assert euler_xyz_from_matrix(x @ z)[0] == np.pi and euler_xyz_from_matrix(x @ z)[2] == np.pi
    assert euler_zyz_from_matrix(z)[2] == np.pi


# --- half turns and wraps at the edge of (-pi, pi] (found reading the contracts) ------

def test_a_half_turn_reads_plus_180_whatever_sign_rounding_gave_its_sine():
    """sp.rot_z(-pi) holds sin = -1.2e-16: its yaw is +pi, as sp.rot_z(pi)'s, in every
    three-angle form (a table must not print -180 for one and 180 for the other)."""
    for R in (sp.rot_z(-np.pi), sp.rot_z(np.pi), sp.rot_z(np.pi + 1e-16), sp.rot_z(-np.pi + 1e-16)):
        assert sp.rpy_from_matrix(R)[2] == np.pi
        assert sp.euler_zyz_from_matrix(R)[0] + sp.euler_zyz_from_matrix(R)[2] == pytest.approx(np.pi)
    R = sp.rot_x(-np.pi)
    assert sp.rpy_from_matrix(R)[0] == np.pi
    assert sp.euler_xyz_from_matrix(R)[0] == np.pi
    # a real angle just short of -pi stays negative
    assert sp.rpy_from_matrix(sp.rot_z(-np.pi + 1e-6))[2] < 0


def test_wrap_stays_in_the_half_open_turn_far_from_zero():
    k = np.arange(-5000, 5000)
    for x in ((2 * k + 1) * np.pi, (2 * k + 1) * np.pi + 1e-13, (2 * k + 1) * np.pi - 1e-13):
        w = sp.wrap(x)
        assert np.all(w <= np.pi) and np.all(w > -np.pi)
        assert np.allclose(np.exp(1j * w), np.exp(1j * x), atol=1e-9)


def test_point_line_distance_takes_lists():
    from kincalc.structure import point_line_distance
    assert point_line_distance([0, 2, 0], [0, 0, 0], [1, 0, 0]) == 2.0


def test_turn_toward_is_the_nearest_whole_turn_within_the_limits():
    """Against a brute-force search over k in -3..3 written with plain floats."""
    from kincalc.spatial import turn_toward
    rng = np.random.default_rng(17)
    for _ in range(300):
        n = 4
        lo = rng.uniform(-9, 0, n)
        hi = lo + rng.uniform(0.5, 12, n)
        x, near = rng.uniform(-12, 12, n), rng.uniform(-6, 6, n)
        got = turn_toward(x, near, lo, hi)
        for i in range(n):
            inside = [x[i] + 2 * np.pi * k for k in range(-3, 4)
                      if lo[i] - 1e-12 <= x[i] + 2 * np.pi * k <= hi[i] + 1e-12]
            want = min(inside, key=lambda v: abs(v - near[i])) if inside else x[i]
            assert got[i] == pytest.approx(want, abs=1e-12)
    X = rng.uniform(-4, 4, (5, 3, 4))                     # leading axes
    assert turn_toward(X, np.zeros(4), -np.full(4, np.pi), np.full(4, np.pi)).shape == X.shape


def _into_limits_reference(x, lo, hi):
    """Brute force over 41 turns: x within [lo, hi]; else the turn within them nearest x;
    else the turn missing them least (the lower of two alike)."""
    if not math.isfinite(x) or lo <= x <= hi:
        return x
    turns = [x + 2 * math.pi * k for k in range(-20, 21)]
    inside = [t for t in turns if lo <= t <= hi]
    if inside:
        return min(inside, key=lambda t: abs(t - x))
    return min(turns, key=lambda t: (max(lo - t, t - hi), t))


def test_into_limits_is_the_turn_within_the_limits_nearest_the_angle():
    rng = np.random.default_rng(11)
    los = [-np.pi, 0.0, -0.5, 3 * np.pi, -4 * np.pi, 2.0, -5 * np.pi, -np.inf, 1.0]
    his = [np.pi, 2 * np.pi, 0.7, 3.5 * np.pi, 4 * np.pi, 2.1, 0.5, 0.3, np.inf]
    lo, hi = np.array(los), np.array(his)
    X = rng.uniform(-40, 40, (300, len(lo)))
    X[:10] = np.where(np.isfinite(lo), lo, 0.0) - rng.uniform(0, 1e-9, (10, len(lo)))
    X[10, :] = np.nan
    got = sp.into_limits(X, lo, hi)
    for x, g in zip(X, got):
        want = [_into_limits_reference(*args) for args in zip(x.tolist(), los, his)]
        assert np.allclose(g, want, atol=1e-12, equal_nan=True), (x, g, want)
    assert sp.into_limits(X[:, :1], lo[:1], hi[:1]).shape == (300, 1)
    within = np.clip(X, -0.5, 0.7)
    assert np.array_equal(sp.into_limits(within, -0.5, 0.7), within, equal_nan=True)   # kept


def test_into_turn_is_the_one_whole_turn_from_base():
    rng = np.random.default_rng(4)
    x, base = rng.uniform(-50, 50, 1000), rng.uniform(-10, 10, 1000)
    y = sp.into_turn(x, base)
    k = (y - x) / (2 * np.pi)
    assert np.allclose(k, np.rint(k), atol=1e-9)                    # whole turns
    assert ((y >= base) & (y < base + 2 * np.pi)).all()
    assert sp.into_turn(-np.pi / 2, 0.0) == 1.5 * np.pi and sp.into_turn(2 * np.pi, 0.0) == 0.0


def test_into_turn_of_a_tiny_negative_angle_stays_below_the_turn():
    # np.mod(-1e-17, 2 pi) rounds to 2 pi itself, outside [0, 2 pi)
    assert sp.into_turn(-1e-17, 0.0) == 0.0
    assert sp.into_turn(1.0 - 1e-17, 1.0) == 1.0
