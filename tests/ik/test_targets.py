"""kincalc.ik.target: one vectorised builder of IK targets for the command line, the
batch runner and homework sheets, against hand-built rotations."""

import numpy as np
import pytest

from kincalc.analysis.requests import to_si
from kincalc.ik.target import BadTarget, defect_text, target_form, targets_from
from kincalc.analysis.results import Units


def rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


RNG = np.random.default_rng(20261201)
ANGLES = RNG.uniform(-np.pi, np.pi, (50, 3))
XYZ = RNG.uniform(-1, 1, (50, 3))


@pytest.mark.parametrize("form, make", [
    ("rpy", lambda a: rz(a[2]) @ ry(a[1]) @ rx(a[0])),
    ("euler_zyz", lambda a: rz(a[0]) @ ry(a[1]) @ rz(a[2])),
    ("euler_xyz", lambda a: rx(a[0]) @ ry(a[1]) @ rz(a[2])),
])
def test_angle_forms_match_the_elementary_products(form, make):
    targets, defect = targets_from(form, ANGLES, XYZ)
    assert targets.kind == "pose" and (defect == None).all()  # noqa: E711
    for a, p, T in zip(ANGLES, XYZ, targets.T):
        assert np.allclose(T[:3, :3], make(a), atol=1e-14)
        assert np.array_equal(T[:3, 3], p) and np.array_equal(T[3], [0, 0, 0, 1])


def test_quaternion_and_axis_angle_of_the_same_rotation():
    axis = RNG.normal(size=(50, 3))
    angle = RNG.uniform(-np.pi, np.pi, 50)
    u = axis / np.linalg.norm(axis, axis=1, keepdims=True)
    quat = np.column_stack([np.cos(angle / 2), u * np.sin(angle / 2)[:, None]]) * 3.0
    a, da = targets_from("axis_angle", np.column_stack([axis, angle]), XYZ)
    q, dq = targets_from("quat", quat, XYZ)
    assert (da == None).all() and (dq == None).all()  # noqa: E711
    assert np.allclose(a.T, q.T, atol=1e-13)
    # a rotation by angle about u keeps u and turns a perpendicular vector by angle
    assert np.allclose(np.einsum("nij,nj->ni", a.T[:, :3, :3], u), u, atol=1e-13)


def test_only_a_quaternion_or_axis_of_zeros_is_zero():
    """A quaternion of 1e-300 (or an axis of 1e-13) was "the zero quaternion": its norm's
    square underflowed, or fell under 1e-12. Only the direction counts."""
    axis = RNG.normal(size=(20, 3))
    angle = RNG.uniform(-np.pi, np.pi, 20)
    u = axis / np.linalg.norm(axis, axis=1, keepdims=True)
    quat = np.column_stack([np.cos(angle / 2), u * np.sin(angle / 2)[:, None]])
    xyz = np.zeros((20, 3))
    ref, _ = targets_from("quat", quat, xyz)
    for scale in (1e-300, 1e-13, 1e300):
        q, dq = targets_from("quat", quat * scale, xyz)
        a, da = targets_from("axis_angle", np.column_stack([axis * scale, angle]), xyz)
        assert (dq == None).all() and (da == None).all()  # noqa: E711
        assert np.allclose(q.T, ref.T, atol=1e-14) and np.allclose(a.T, ref.T, atol=1e-13)
    _, d = targets_from("quat", np.array([[0.0, 0, 0, 0], [0, -0.0, 0, 5e-324]]), xyz[:2])
    assert d.tolist() == ["zero", None]


def test_defects_are_per_request_and_leave_the_others_alone():
    quat = np.array([[1.0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 2.0]])
    targets, defect = targets_from("quat", quat, np.zeros((3, 3)))
    assert defect.tolist() == [None, "zero", None]
    assert np.allclose(targets.T[2, :3, :3], rz(np.pi), atol=1e-15)
    M = np.tile(np.eye(3).ravel(), (3, 1))
    M[1, 0] = 1.1                                          # not orthonormal
    M[2] = (-np.eye(3)).ravel()                            # determinant -1
    _, defect = targets_from("matrix", M, np.zeros((3, 3)))
    assert defect.tolist() == [None, "not rotation", "not rotation"]
    T = np.tile(np.eye(4).ravel(), (2, 1))
    T[1, 12] = 1e-6
    _, defect = targets_from("T", T)
    assert defect.tolist() == [None, "last row"]
    assert defect_text("quat", "zero", "--quat") == "--quat must not be the zero quaternion"


def test_a_pose_is_reorthonormalised_to_the_nearest_rotation():
    R = rz(0.3) @ rx(-1.2)
    noisy = R + 1e-7 * RNG.normal(size=(3, 3))
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = noisy, [0.1, 0.2, 0.3]
    targets, defect = targets_from("T", T.ravel()[None])
    Rt = targets.T[0, :3, :3]
    assert defect[0] is None and np.allclose(Rt @ Rt.T, np.eye(3), atol=1e-15)
    assert np.abs(Rt - R).max() < 5e-7 and np.array_equal(targets.T[0, :3, 3], [0.1, 0.2, 0.3])
    top = targets_from("T", T[:3].ravel()[None])[0]          # 12 numbers: the top rows
    assert np.array_equal(top.T, targets.T)


def test_tcv_gives_position_approach_and_roll():
    w = np.array([[0.1, 0.2, 0.3, 0.0, 0.0, -np.exp(0.5 / np.pi)]])
    targets, defect = targets_from("tcv", w)
    assert targets.kind == "tcv" and defect[0] is None
    assert np.allclose(targets.approach, [[0, 0, -1]]) and np.isclose(targets.roll[0], 0.5)
    assert np.array_equal(targets.T[0, :3, 3], [0.1, 0.2, 0.3])
    assert targets_from("tcv", np.zeros((1, 6)))[1][0] == "zero"


def test_forms_and_the_combinations_that_are_not_one_target():
    assert target_form(["xyz"]) is None
    assert target_form(["xyz", "quat"]) == "quat" and target_form(["T"]) == "T"
    assert target_form(["tcv"]) == "tcv" and target_form(["q"]) == "q"
    for given, problem in [(["xyz", "rpy", "quat"], "two orientations"),
                           (["T", "xyz"], "whole and part"), (["q", "rpy"], "whole and part"),
                           (["T", "q"], "two wholes"), (["tcv", "xyz"], "tcv and xyz"),
                           (["rpy"], "no position"), ([], "no position")]:
        with pytest.raises(BadTarget) as e:
            target_form(given)
        assert e.value.problem == problem
    with pytest.raises(BadTarget) as e:
        target_form(["xyz", "euler_zyz", "axis_angle"])
    assert e.value.words(lambda f: "--" + f.replace("_", "-")) == \
        "give at most one orientation, not --euler-zyz and --axis-angle"


def test_user_units_to_si():
    units = Units(angle="deg", length="mm")
    assert np.allclose(to_si("rpy", [[90.0, 0, -45]], units), [[np.pi / 2, 0, -np.pi / 4]])
    assert np.allclose(to_si("axis_angle", [[0, 0, 2, 180]], units), [[0, 0, 2, np.pi]])
    T = np.eye(4)
    T[:3, 3] = [100, 200, 300]
    assert np.allclose(to_si("T", T.ravel()[None], units).reshape(4, 4)[:3, 3], [.1, .2, .3])
    assert np.allclose(to_si("tcv", [[100, 0, 0, 0, 0, 2]], units), [[.1, 0, 0, 0, 0, 2]])


# --- a rotation typed to a few digits ---------------------------------------------------------

def test_a_matrix_typed_to_6_digits_is_the_rotation_it_stands_for():
    """The ``matrix`` and ``T`` forms re-orthonormalise a matrix that is a rotation to 6
    digits (the nearest rotation, by SVD: orthonormal to rounding, within 1e-6 of the
    typed one); one that is a rotation to rounding already keeps its bits."""
    from kincalc.spatial import nearest_rotations
    rng = np.random.default_rng(6)
    n = 2000          # (1e-6 refused 2.4 % of them: rounding moves R R^T by up to 1.7e-6)
    R = np.array([rz(a) @ ry(b) @ rx(c) for a, b, c in rng.uniform(-3, 3, (n, 3))])
    typed = np.round(R, 6)
    for form, values in (("matrix", typed.reshape(n, 9)),
                         ("T", np.concatenate([typed, np.zeros((n, 3, 1))], 2).reshape(n, 12))):
        t, defect = targets_from(form, values, xyz=np.zeros((n, 3)))
        assert (defect == None).all()  # noqa: E711
        got = t.T[:, :3, :3]
        assert np.abs(got @ np.swapaxes(got, 1, 2) - np.eye(3)).max() < 1e-14
        assert np.abs(got - R).max() < 1e-6
    assert np.array_equal(nearest_rotations(R), R)           # FK-exact: untouched


def test_the_python_api_reads_a_pose_as_the_cli_does():
    """robot.ik and robot.ik_batch on a pose typed to 6 digits: the solutions of the rotation
    it stands for (before, 'orientation not reachable, off by 4e-5 deg'); not a pose:
    ValueError naming the defect."""
    from kincalc import load_robot
    r = load_robot("puma560")
    q = np.radians([10, 20, 30, 40, 50, 60])
    T = r.fk(q)
    T6 = np.round(T, 6)
    res = r.ik(T6)
    assert len(res.solutions) == 8 and res.reachable
    assert min(np.abs(s.q - q).max() for s in res.solutions) < 1e-5
    assert r.ik_batch(T6[None]).counts.tolist() == [8]
    bad = T6.copy()
    bad[0, :3] *= 1.01
    with pytest.raises(ValueError, match="not a rotation"):
        r.ik(bad)
    bad = T6.copy()
    bad[3, 3] = 2.0
    with pytest.raises(ValueError, match="last row"):
        r.ik(bad)
    assert r.ik_batch(np.stack([bad, T6])).counts.tolist() == [0, 8]
