"""kincalc.ik.cache.per_robot: once per robot and arguments, afresh for what does not hash,
and the function's own errors passed on (not hidden by running it again uncached)."""

import pytest

from kincalc import load_robot
from kincalc.ik.cache import per_robot


def test_once_per_robot_and_arguments():
    calls = []

    @per_robot
    def f(robot, k):
        calls.append(k)
        return [robot.name, k]

    r = load_robot("puma560")
    assert f(r, 1) is f(r, 1) and f(r, 2) == ["puma560", 2]
    assert calls == [1, 2]


def test_an_unhashable_argument_is_computed_afresh():
    calls = []

    @per_robot
    def f(robot, k):
        calls.append(1)
        return len(k)

    r = load_robot("puma560")
    assert f(r, [1, 2]) == 2 and f(r, [1, 2]) == 2 and len(calls) == 2


def test_a_type_error_of_the_function_itself_is_raised_once():
    calls = []

    @per_robot
    def f(robot, k):
        calls.append(k)
        raise TypeError("inside f")

    with pytest.raises(TypeError, match="inside f"):
        f(load_robot("puma560"), 3)
    assert calls == [3]                   # not run a second time, uncached


def test_a_robot_built_with_numpy_arrays_hashes_and_is_labelled_as_one_of_tuples():
    """A Python caller's joints with numpy axes, points and limits (an independent
    campaign's poe arm): the robot did not hash, every per-robot cache was computed afresh,
    and the branch labels' numbers, counted in a table made anew on each call, were all 0, so
    every solution showed the +/- of every step."""
    import numpy as np

    from kincalc.conventions.conversion import convert
    from kincalc.model import Joint, Robot
    poe = convert(load_robot("puma560"), "poe")
    arrays = Robot(poe.name, "poe", M=poe.M, tool=poe.tool, joints=tuple(
        Joint(j.name, j.type, axis=np.array(j.axis), point=np.array(j.point),
              limits=None if j.limits is None else np.array(j.limits)) for j in poe.joints))
    assert hash(arrays) == hash(poe) and arrays == poe
    q = np.radians([10, -30, 150, 25, 40, 35])
    T = poe.fk(q)
    assert [s.branch for s in arrays.ik(T).solutions] == [s.branch for s in poe.ik(T).solutions]
    assert all("q1:" not in s.branch for s in arrays.ik(T).solutions)
