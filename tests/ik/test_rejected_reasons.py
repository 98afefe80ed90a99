"""``--all-branches``: a rejected candidate that reaches the target is not said to miss it.

An independent oracle's case: a reversed point-plus-roll arm (R-R-R-P, a SCARA with the
slide last) at a singular pose, where the engine answers a double root once. The second
copy, 6.5e-6 rad from the first, reaches the pose to rounding, and was listed as "does not
reach the target: position reached, orientation off by 3.785e-16 rad"; the other rejects
said "orientation off by 2.7e-15 rad", an error no solution is refused for.
"""

import numpy as np

from kincalc.analysis.words import reason_text
from kincalc.analysis.results import Units
from kincalc.ik import Target, solve
from kincalc.ik.reasons import Answered
from kincalc.model import Joint, Robot
from kincalc.tolerances import ACCEPT_ORIENTATION, ACCEPT_POSITION

ROWS = [("revolute", 3.141592653589793, 0.3914464790597664, -0.3450299668723965,
         -2.661686084417327),
        ("revolute", 0.0, 0.4858775917609779, 0.4205529225948314, -1.939406090681977),
        ("revolute", 0.0, -0.29667879142454934, 0.3543687646023367, 1.9262012782899314),
        ("prismatic", 0.0, 0.0, -0.14274892484076843, -0.9120295984083415)]
LIMITS = [(-4.0, 1.5), (-1.5697483256423033, 0.01557754175468129),
          (-1.3092606782245166, -0.19762996556665102), (0.0, 0.6)]
Q = [0.062366812706441066, -1.202186004706907, -0.9944923881926682, 2.5140027297113217]


def test_a_rejected_copy_that_reaches_the_target_says_so():
    robot = Robot(name="scara_rrrp", convention="dh", joints=tuple(
        Joint(f"j{i + 1}", t, alpha=al, a=a, d=d, theta=th, limits=lim)
        for i, ((t, al, a, d, th), lim) in enumerate(zip(ROWS, LIMITS))))
    T = robot.fk(np.array(Q))
    res = solve(robot, Target(T), all_branches=True)
    assert res.solutions and res.rejected
    units = Units(length="m", angle="rad")
    L = robot.characteristic_length
    answered = 0
    for r in res.rejected:
        text = reason_text(r["reason"], robot, units)
        reaches = r["position_error"] <= ACCEPT_POSITION * L and (
            r["orientation_error"] is None or r["orientation_error"] <= ACCEPT_ORIENTATION)
        if reaches:
            answered += 1
            assert isinstance(r["reason"], Answered) and text.startswith("reaches the target")
            # the listed solution it is one root with lies as near as it says
            near = min(np.abs(np.array(r["q"]) - s.q).max() for s in res.solutions)
            assert near <= r["reason"].amount * (1 + 1e-9) < 1e-3
        else:
            assert text.startswith("does not reach")
            if r["orientation_error"] is None or r["orientation_error"] <= ACCEPT_ORIENTATION:
                assert "orientation off" not in text
    assert answered >= 1
