"""A spherical-wrist arm with a slide (R-R-P and a wrist) whose wrist centre lies on axis 1.

Then any value of joint 1 places the wrist centre (the wrist turns the orientation back): a
continuum per placement of joints 2-3 and wrist branch, joint 1 named free. On axis 1 the
placement of joints 2-3 is a double root (the wrist centre's distance from the axis is at
its least), which the resultant splits by rounding and the polish of the placed point took
up by turning joint 1 at random: one pose of an independent random-robot campaign gave 8
solutions in dh, mdh and poe alike, joint 1 anywhere from -4e-5 to 0.08 rad, four points of
each of its two continua, different in each convention.

Checked without the solver: every answer reaches the pose (FK); each names joint 1 free;
no two answers hold the same placement and wrist branch; dh, mdh and poe answer alike; and
the generating joints lie on an answer's continuum (joint 1 turned to theirs, the other
joints kept on the pose by Gauss-Newton, ends at them).
"""

import numpy as np
import pytest
from randrobots import follow_joint

from kincalc.conventions.conversion import convert
from kincalc.model import Joint, Robot

#: the campaign's arm (standard DH, rad and m): alpha, a, d, theta, type
ROWS = [(2.195243305361338, -0.065019655279264954, 0.77513463222267232, -1.3024508712180509,
         "revolute"),
        (-1.3938500337545705, 0.0, -0.3720398255573279, 1.4747797685843143, "revolute"),
        (1.5707963267948966, 0.02729486238179726, 0.54261659036220733, -2.3585201363837065,
         "prismatic"),
        (1.5707963267948966, 0.0, -0.082607005865384969, 1.3469431321770085, "revolute"),
        (1.5707963267948966, 0.0, 0.0, 3.1321220184893042, "revolute"),
        (-0.75466489103736745, 0.0, 0.0, -1.3486985576508823, "revolute")]
BASE = [[-0.59243738639974985, -0.80460523762468927, 0.040352878246175228, 0.18144413873207543],
        [-0.50745261778987949, 0.41160758505029915, 0.75701455509604254, -0.058129758417302169],
        [-0.62570742675313662, 0.42800655078629096, -0.6521507560296087, 0.20147082094170943],
        [0.0, 0.0, 0.0, 1.0]]
TOOL = [[-0.33848975698645822, -0.021073125808461435, 0.9407340792083112, 0.13381218952081531],
        [-0.93694992764628626, -0.084767419676043732, -0.33902701609913705, -0.16643355378789887],
        [0.086887959458531838, -0.99617789973986381, 0.0089484395849941389, 0.27659825895935414],
        [0.0, 0.0, 0.0, 1.0]]
#: joints that put the wrist centre on axis 1 (to 5e-16 m), and the same with joint 4 turned
GENERATING = [[-0.6841717756611994, -1.5545193877698245, -0.19440825664561923,
               -0.6778703146992617, -1.3893684715888792, 2.266913297144148],
              [-0.6841717756611994, -1.5545193877698245, -0.19440825664561923,
               -1.3469431321770085, -1.3893684715888792, 2.266913297144148]]


def arm() -> Robot:
    return Robot(name="wrist_on_axis_1", convention="dh", base=np.array(BASE),
                 tool=np.array(TOOL), joints=tuple(
                     Joint(f"j{i + 1}", kind, alpha=al, a=a, d=d, theta=th)
                     for i, (al, a, d, th, kind) in enumerate(ROWS)))


def wrist_centre_offset(r, q) -> float:
    """Distance from axis 1 of the wrist centre, where axes 4 and 5 meet (their nearest
    points), from the joint frames (z: the joint's axis)."""
    from kincalc.fk import chain_frames
    F = chain_frames(r.chain, np.asarray(q, float))
    (k4, p4), (k5, p5) = [(F[i][:3, 2], F[i][:3, 3]) for i in (3, 4)]
    t = np.linalg.lstsq(np.stack([k4, -k5], 1), p5 - p4, rcond=None)[0]
    c, k1, p1 = p4 + t[0] * k4, F[0][:3, 2], F[0][:3, 3]
    assert np.linalg.norm(c - (p5 + t[1] * k5)) < 1e-12          # (the axes meet)
    d = c - p1
    return float(np.linalg.norm(d - (d @ k1) * k1))


@pytest.mark.parametrize("q", GENERATING)
def test_the_continuum_of_joint_1_is_answered_once_per_wrist_branch(q):
    q = np.array(q)
    r0 = arm()
    assert wrist_centre_offset(r0, q) < 1e-12
    answers = {}
    for convention in ("dh", "mdh", "poe"):
        r = convert(r0, convention)
        T = r.fk(q)
        sols = r.ik(T).solutions
        S = np.array([s.q for s in sols])
        assert len(S) and np.abs(r.fk(S) - T).max() < 1e-12
        assert all(0 in s.free for s in sols)
        placements = {(round(s.q[1], 6), round(s.q[2], 6), bool(s.q[4] > 0)) for s in sols}
        assert len(placements) == len(sols), S
        answers[convention] = S[np.lexsort(S.T[::-1])]

        def miss(x):
            F = r.fk(x)
            return np.concatenate([F[:3, 3] - T[:3, 3], (F[:3, :3] - T[:3, :3]).ravel()])
        ends = [follow_joint(miss, s.q, 0, q[0], way, (1, 2, 3, 4, 5))
                for s in sols for way in (1, -1)]
        assert any(e is not None and np.abs(e - q).max() < 1e-6 for e in ends), convention
    assert answers["dh"].shape == answers["mdh"].shape == answers["poe"].shape
    assert np.abs(answers["dh"] - answers["mdh"]).max() < 1e-8
    assert np.abs(answers["dh"] - answers["poe"]).max() < 1e-8
