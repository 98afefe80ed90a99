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
