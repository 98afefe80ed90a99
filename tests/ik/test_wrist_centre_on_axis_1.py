"""Spherical-wrist arms whose wrist centre lies on axis 1: R-R-P (placed by the resultant)
and R-R-R (three cones, subproblem 5).

Then any value of joint 1 places the wrist centre (the wrist turns the orientation back): a
continuum per placement of joints 2-3 and wrist branch, joint 1 named free. On axis 1 the
placement of joints 2-3 is a double root (the wrist centre's distance from the axis is at
its least), which the resultant splits by rounding and the polish of the placed point took
up by turning joint 1 at random: one pose of an independent random-robot campaign gave 8
solutions in dh, mdh and poe alike, joint 1 anywhere from -4e-5 to 0.08 rad, four points of
each of its two continua, different in each convention; an R-R-R arm gave 4 in dh and mdh
and 2 in poe, joint 1 where the polish left it.

Checked without the solver: every answer reaches the pose (FK); each names joint 1 free;
no two answers hold the same placement and wrist branch; dh, mdh and poe answer alike; and
the generating joints lie on an answer's continuum (joint 1 turned to theirs, the other
joints kept on the pose by Gauss-Newton, ends at them).
"""

import numpy as np
import pytest
from randrobots import follow_joint

from kincalc.analysis.results import Units
from kincalc.analysis.words import continuum_text
from kincalc.conventions.conversion import convert
from kincalc.model import Joint, Robot
from kincalc.spatial import wrap

#: the campaign's arms (standard DH, rad and m): alpha, a, d, theta, type; base, tool
RRP = [(2.195243305361338, -0.065019655279264954, 0.77513463222267232, -1.3024508712180509,
        "revolute"),
       (-1.3938500337545705, 0.0, -0.3720398255573279, 1.4747797685843143, "revolute"),
       (1.5707963267948966, 0.02729486238179726, 0.54261659036220733, -2.3585201363837065,
        "prismatic"),
       (1.5707963267948966, 0.0, -0.082607005865384969, 1.3469431321770085, "revolute"),
       (1.5707963267948966, 0.0, 0.0, 3.1321220184893042, "revolute"),
       (-0.75466489103736745, 0.0, 0.0, -1.3486985576508823, "revolute")]
RRP_BASE = [[-0.59243738639974985, -0.80460523762468927, 0.040352878246175228, 0.18144413873207543],
            [-0.50745261778987949, 0.41160758505029915, 0.75701455509604254, -0.058129758417302169],
            [-0.62570742675313662, 0.42800655078629096, -0.6521507560296087, 0.20147082094170943],
            [0.0, 0.0, 0.0, 1.0]]
RRP_TOOL = [[-0.33848975698645822, -0.021073125808461435, 0.9407340792083112, 0.13381218952081531],
        [-0.93694992764628626, -0.084767419676043732, -0.33902701609913705, -0.16643355378789887],
        [0.086887959458531838, -0.99617789973986381, 0.0089484395849941389, 0.27659825895935414],
        [0.0, 0.0, 0.0, 1.0]]
#: joints that put the wrist centre on axis 1 (to 5e-16 m), and the same with joint 4 turned
RRP_GENERATING = [[-0.6841717756611994, -1.5545193877698245, -0.19440825664561923,
               -0.6778703146992617, -1.3893684715888792, 2.266913297144148],
              [-0.6841717756611994, -1.5545193877698245, -0.19440825664561923,
               -1.3469431321770085, -1.3893684715888792, 2.266913297144148]]

RRR = [(-2.8350775233417935, -0.013086634857481358, -0.01153661832439918, -1.4198503023168889,
        "revolute"),
       (1.0741592311604422, 0.15886444097788224, -1.2114106783024328, -1.8766568604046496,
        "revolute"),
       (-0.60747438340544879, 0.043861985060586382, 0.33095264576828304, -2.0577056996917809,
        "revolute"),
       (2.7918636619633528, 0.0, 0.0, -2.1545886815259974, "revolute"),
       (2.7780919372460078, 0.0, 0.0, 1.8242236258330147, "revolute"),
       (0.0, -0.61099294122021264, 0.0, -2.1454685093012311, "revolute")]
RRR_BASE = [[-0.63742804121497909, -0.7273534575990106, -0.25424877579174177, -0.37055984794705077],
            [-0.5763375491648659, 0.66909335796803293, -0.46920049844996697, 0.18072591626567192],
            [0.51139077200852068, -0.15254843834607429, -0.84569997768872129, 0.3379447290085027],
            [0.0, 0.0, 0.0, 1.0]]
RRR_TOOL = [[-0.3951607148221834, -0.24336791468352684, -0.88578782310653426, 0.085039003077114594],
            [0.59005640587143293, 0.67179207602611046, -0.44780447125795381, 0.12079533768961487],
            [0.70404648095939526, -0.69961951422978497, -0.12186503993176911, 0.026172035454550713],
            [0.0, 0.0, 0.0, 1.0]]
RRR_GENERATING = [[1.811754422535623, -4.817586207053446, -12.282272697692969,
                   -0.21760717200651536, -0.7935495535497767, -2.4679177365997402]]

CASES = [(RRP, RRP_BASE, RRP_TOOL, q) for q in RRP_GENERATING] + [
    (RRR, RRR_BASE, RRR_TOOL, q) for q in RRR_GENERATING]


def arm(rows, base, tool) -> Robot:
    return Robot(name="wrist_on_axis_1", convention="dh", base=np.array(base),
                 tool=np.array(tool), joints=tuple(
                     Joint(f"j{i + 1}", kind, alpha=al, a=a, d=d, theta=th)
                     for i, (al, a, d, th, kind) in enumerate(rows)))


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


def answers(rows, base, tool, q) -> dict:
    """``{convention: (robot, T, solutions)}`` of the arm in dh, mdh and poe at the pose of
    ``q``, each solution checked: it reaches the pose (FK) and names joint 1 free."""
    r0 = arm(rows, base, tool)
    assert wrist_centre_offset(r0, q) < 1e-12
    out = {}
    for convention in ("dh", "mdh", "poe"):
        r = convert(r0, convention)
        T = r.fk(q)
        S = np.array([s.q for s in r.ik(T).solutions if 0 in s.free])
        assert len(S) == len(r.ik(T).solutions) and np.abs(r.fk(S) - T).max() < 1e-12
        out[convention] = r, T, S[np.lexsort(S.T[::-1])]
    return out


def on_one_continuum(r, T, a, b) -> bool:
    """Joint 1 of ``a`` turned (either way) to ``b``'s, the others kept on the pose ``T``
    (Gauss-Newton), ends at ``b``."""
    def miss(x):
        F = r.fk(x)
        return np.concatenate([F[:3, 3] - T[:3, 3], (F[:3, :3] - T[:3, :3]).ravel()])
    ends = [follow_joint(miss, a, 0, b[0], way, (1, 2, 3, 4, 5)) for way in (1, -1)]
    return any(e is not None and np.abs(wrap(e - b)).max() < 1e-6 for e in ends)


@pytest.mark.parametrize("rows, base, tool, q", CASES, ids=["RRP", "RRP joint 4", "RRR"])
def test_the_continuum_of_joint_1_is_answered_alike_in_every_convention(rows, base, tool, q):
    q = np.array(q)
    got = answers(rows, base, tool, q)
    for convention, (r, T, S) in got.items():
        assert any(on_one_continuum(r, T, x, q) for x in S), convention
    assert got["dh"][2].shape == got["mdh"][2].shape == got["poe"][2].shape
    assert np.abs(got["dh"][2] - got["mdh"][2]).max() < 1e-8
    assert np.abs(got["dh"][2] - got["poe"][2]).max() < 1e-8


@pytest.mark.parametrize("q", RRP_GENERATING)
def test_the_rrp_arm_answers_each_continuum_once(q):
    """Its two continua (one per wrist branch) once each: no answer is a point of another's.
    (Not asked of the R-R-R arm: its continuum passes through the wrist's singularity,
    where the two wrist branches meet, and its representatives are per wrist branch and
    arc of the wrist's band.)"""
    for convention, (r, T, S) in answers(RRP, RRP_BASE, RRP_TOOL, np.array(q)).items():
        assert not any(on_one_continuum(r, T, S[i], S[k])
                       for i in range(len(S)) for k in range(len(S)) if i != k), convention


#: a plain elbow arm (standard DH, rad and m: alpha, a, d, theta, type) and joints that put
#: its wrist centre on axis 1 (an independent campaign's case: q1 was named free with no
#: relation, so turning it alone looked allowed, and turned the tool by as much)
ELBOW = [(-np.pi / 2, 0.0, 0.0, 0.0, "revolute"), (0.0, 0.3, 0.0, 0.0, "revolute"),
         (np.pi / 2, 0.0, 0.0, 0.0, "revolute"), (np.pi / 2, 0.0, 0.2, 0.0, "revolute"),
         (-np.pi / 2, 0.0, 0.0, 0.0, "revolute"), (np.pi / 2, 0.0, 0.0, 0.0, "revolute")]
ELBOW_GENERATING = [1.0, -0.8993197572187999, -1.0390167986396537, -2.504273882511016,
                    2.0954124801207135, 2.8228313412701045]


@pytest.mark.parametrize("rows, base, tool, q", CASES + [(ELBOW, np.eye(4), np.eye(4),
                                                          ELBOW_GENERATING)],
                         ids=["RRP", "RRP joint 4", "RRR", "elbow"])
def test_the_wrist_is_named_as_following_joint_1(rows, base, tool, q):
    """Each answer's continuum names joint 1 free and the wrist's joints as following it:
    joint 1 turned by 0.05 rad with those joints alone kept on the pose (Gauss-Newton)
    stays on it, and turned alone it leaves the orientation. (Not further: the R-R-R arm's
    wrist reaches a band of orientations only, and its continuum ends in an arc.)"""
    r = arm(rows, base, tool)
    T = r.fk(np.array(q))
    assert wrist_centre_offset(r, q) < 1e-12

    def miss(x):
        F = r.fk(x)
        return np.concatenate([F[:3, 3] - T[:3, 3], (F[:3, :3] - T[:3, :3]).ravel()])
    sols = r.ik(T).solutions
    assert sols
    for s in sols:
        c = s.continuum
        assert (c.free, c.joints) == (0, (3, 4, 5)), c
        assert continuum_text(c, [j.name for j in r.joints], Units("deg")) == \
            "j1 free, j4, j5, j6 follow it to keep the target"
        alone = np.array(s.q)
        alone[0] += 0.05
        assert np.abs(miss(alone)).max() > 1e-3
        assert follow_joint(miss, s.q, 0, s.q[0] + 0.05, 1, c.joints, steps=10) is not None
