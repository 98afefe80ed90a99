"""Hints of `kincalc check` name a slip only where the slip explains the wrong answer.

A slip is named when its result fits the answer (within HINT_FACTOR times the tolerance);
it explains nothing when the right result fits the answer as well: a slip that leaves the
result as it is (a joint the quantity does not depend on, a DH row both conventions write
alike) would be blamed for an answer that is only a little off. The classroom oracle of
the twenty-fourth session met each case below; each also keeps a real slip's hint.
"""

from __future__ import annotations

import textwrap

import numpy as np

from kincalc import load_robot
from kincalc.homework import grade, parse_sheet

PUMA = load_robot("puma560")


def graded(items: str, robot: str = "puma560"):
    text = f"robot: {robot}\nitems:\n" + textwrap.indent(textwrap.dedent(items), "  ")
    return grade(parse_sheet(text, "hw.yaml", ".")).items


def rows(M) -> str:
    return "[" + ", ".join("[" + ", ".join(repr(float(x)) for x in r) + "]" for r in M) + "]"


Q = np.array([-70, 17, -146, 15, -14, 157], float)


def test_a_position_off_is_not_blamed_on_a_joint_it_does_not_depend_on():
    """PUMA's tool point is its wrist centre: joint 4's sign leaves the position as it is
    (checked here), so an answer 1.3 tolerances off gets no "opposite sign" hint."""
    flip = Q.copy()
    flip[3] = -flip[3]
    p = PUMA.fk(np.radians(Q))[:3, 3]
    assert np.allclose(PUMA.fk(np.radians(flip))[:3, 3], p, atol=1e-12)
    tol = 1e-3 * PUMA.characteristic_length
    off = p + [1.3 * tol, 0, 0]
    (r,) = graded(f"- {{id: a, kind: fk, q: {Q.tolist()}, answer: {{position: {off.tolist()}}}}}")
    assert not r.passed
    assert r.hint is None, r.hint
    # a real slip keeps its hint: joint 2 with the opposite sign moves the tool point
    flip2 = Q.copy()
    flip2[1] = -flip2[1]
    p2 = PUMA.fk(np.radians(flip2))[:3, 3]
    (r,) = graded(f"- {{id: a, kind: fk, q: {Q.tolist()}, answer: {{position: {p2.tolist()}}}}}")
    assert not r.passed and r.hint and "joint 2" in r.hint and "opposite sign" in r.hint, r.hint


def test_a_link_entry_off_is_not_blamed_on_the_conventions_where_they_agree():
    """The PUMA's link 6 (alpha = a = d = 0) is the same matrix in standard and modified
    DH: an entry 0.0025 off is no "standard and modified DH mixed up"."""
    A = PUMA.link_transforms(np.radians([0, 0, 0, 0, 0, -101]))[5].copy()
    A[0, 0] += 0.0025
    (r,) = graded(f"- {{id: a, kind: link, link: 6, q: -101, answer: {rows(A)}}}")
    assert not r.passed
    assert r.hint is None, r.hint
    # link 2 differs between the conventions: its modified-DH matrix keeps the hint
    import dataclasses
    mdh = dataclasses.replace(PUMA, convention="mdh")
    B = mdh.link_transforms(np.radians([0, 40, 0, 0, 0, 0]))[1]
    (r,) = graded(f"- {{id: a, kind: link, link: 2, q: 40, answer: {rows(B)}}}")
    assert not r.passed and r.hint and "mixed up" in r.hint, r.hint


def test_a_jacobian_off_is_not_blamed_on_the_last_joint():
    """The PUMA's Jacobian in the base frame does not depend on joint 6."""
    q = np.radians(Q)
    J = PUMA.jacobian(q)
    q6 = q.copy()
    q6[5] = -q6[5]
    assert np.allclose(PUMA.jacobian(q6), J, atol=1e-12)
    off = J.copy()
    off[0, 0] += 1.3 * 1e-3 * PUMA.characteristic_length
    (r,) = graded(f"- {{id: a, kind: jacobian, q: {Q.tolist()}, answer: {rows(off)}}}")
    assert not r.passed
    assert r.hint is None, r.hint
    q2 = q.copy()
    q2[1] = -q2[1]
    (r,) = graded(f"- {{id: a, kind: jacobian, q: {Q.tolist()}, "
                  f"answer: {rows(PUMA.jacobian(q2))}}}")
    assert not r.passed and r.hint and "joint 2" in r.hint, r.hint


def ik_item(sets) -> str:
    return ("- id: a\n  kind: ik\n  pose: {xyz: [-0.0983, -0.8349, -0.1334], "
            "rpy: [-159.38, -39.73, -167.25]}\n  answer: "
            + rows(sets) + "\n")


def puma_solutions():
    from kincalc.spatial import matrix_from_rpy
    T = np.eye(4)
    T[:3, :3] = matrix_from_rpy(np.radians([-159.38, -39.73, -167.25]))
    T[:3, 3] = [-0.0983, -0.8349, -0.1334]
    sols = PUMA.ik(T).solutions
    assert len(sols) == 8 and all(s.within_limits for s in sols)
    return np.degrees([s.q for s in sols])


def test_a_set_off_in_one_joint_does_not_mix_branches_with_its_wrist_twin():
    """A set 0.11 deg off in q2 is near its own solution's q2, which the other wrist
    solution shares: no "the set mixes branches" (that says another branch's value)."""
    S = puma_solutions()
    for k in range(8):                  # (the twin comes before or after the solution)
        sets = S.copy()
        sets[k, 1] += 0.11
        twins = [j for j in range(8) if j != k and abs(S[j, 1] - S[k, 1]) < 1e-9]
        assert twins                              # the wrist's other solution shares q2
        (r,) = graded(ik_item(sets))
        assert not r.passed
        text = " ".join(str(e.get("note", "")) for e in r.details["sets"])
        assert "differs only in" in text and "mixes branches" not in text, (k, text)
    # a value near another branch's (not its own: an exact one is a wrong pairing of
    # roots) is still said to mix them
    other = next(k for k in range(8) if abs(S[k, 2] - S[0, 2]) > 1)
    sets = S.copy()
    sets[0, 2] = S[other, 2] + 0.5
    (r,) = graded(ik_item(sets))
    text = " ".join(str(e.get("note", "")) for e in r.details["sets"])
    assert "mixes branches" in text, text
