"""Joint 6 a hair from the wrist singularity of a three-parallel arm, moved into the elbow's
reach (:func:`kincalc.ik.wrists.into_elbow_reach`).

Checked against plane geometry written here: in the plane normal to h, axis 4 sits at
``a + R(-sigma q6) b`` from axis 2 (``R`` the rotation about h), and the planar elbow
reaches it when that distance lies between ``|l2 - l3|`` and ``l2 + l3``; the elbow's
link lengths are read off the joint frames at q = 0 (kincalc.fk.chain_frames), not from
the solver's screws.
"""

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.fk import chain_frames
from kincalc.ik.screws import Screws
from kincalc.ik.wrists import into_elbow_reach
from kincalc.tolerances import ROUNDED_POSE


def _plane(r):
    """``(h, e1, e2, l2, l3)``: axis 2's direction, a basis of the plane normal to it and
    the elbow's two lengths across h, from the joint frames at q = 0 (world frame, m)."""
    F = chain_frames(r.chain, np.zeros((1, 6)))[0]
    h = F[1, :3, 2]
    across = lambda d: d - (d @ h) * h  # noqa: E731
    l2 = np.linalg.norm(across(F[2, :3, 3] - F[1, :3, 3]))
    l3 = np.linalg.norm(across(F[3, :3, 3] - F[2, :3, 3]))
    e1 = across(np.array([1.0, 0.3, 0.2]))
    e1 /= np.linalg.norm(e1)
    return h, e1, np.cross(h, e1), l2, l3


def _turned(h, v, t):
    """``v`` (normal to h) turned by ``t`` about h."""
    return np.cos(t)[..., None] * v + np.sin(t)[..., None] * np.cross(h, v)


def _reach_of(h, a, b, sigma, q6):
    """The distance from axis 2 to axis 4 with joint 6 at ``q6``."""
    return np.linalg.norm(a + _turned(h, b, -sigma * q6), axis=-1)


@pytest.mark.parametrize("name", ["ur5", "ur10e", "ur3"])
@pytest.mark.parametrize("sigma", [1.0, -1.0])
def test_out_of_reach_moves_to_the_nearer_end_of_the_arc(name, sigma):
    r = load_robot(name)
    S = Screws.of(r)
    h, e1, e2, l2, l3 = _plane(r)
    rng = np.random.default_rng(31)
    n = 400
    # axis 6 at A from axis 2, axis 4 at B from axis 6: the circle of axis 4 crosses the
    # outer edge of the elbow's reach (A + B > l2 + l3 > |A - B|)
    A = rng.uniform(0.5, 0.9, n) * (l2 + l3)
    B = rng.uniform(0.2, 0.6, n) * (l2 + l3)
    ta, tb = rng.uniform(-np.pi, np.pi, (2, n))
    a = _turned(h, np.broadcast_to(e1, (n, 3)), ta) * A[:, None]
    b = _turned(h, np.broadcast_to(e2, (n, 3)), tb) * B[:, None]
    q6 = rng.uniform(-np.pi, np.pi, n)
    d = _reach_of(h, a, b, sigma, q6)
    at = a + _turned(h, b, -sigma * q6)
    sine = np.full(n, 1e-15)                  # the orientation allows any move here
    out = into_elbow_reach(S, a, b, sigma, q6, at, sine)
    inside = (d <= l2 + l3) & (d >= abs(l2 - l3))
    assert np.array_equal(out[inside], q6[inside])           # untouched, bit for bit
    moved = ~inside
    assert moved.sum() > 50
    # now on the edge of the reach it crossed
    edge = np.where(d > l2 + l3, l2 + l3, abs(l2 - l3))[moved]
    assert np.allclose(_reach_of(h, a, b, sigma, out)[moved], edge, rtol=0, atol=1e-9)
    # and no point of that edge is nearer to q6: scan the circle
    grid = np.linspace(-np.pi, np.pi, 20001)
    for k in np.flatnonzero(moved)[:40]:
        dk = _reach_of(h, np.broadcast_to(a[k], (len(grid), 3)),
                       np.broadcast_to(b[k], (len(grid), 3)), sigma, grid)
        ok = (dk <= l2 + l3) & (dk >= abs(l2 - l3))
        best = np.abs(np.angle(np.exp(1j * (grid[ok] - q6[k])))).min()
        got = abs(np.angle(np.exp(1j * (out[k] - q6[k]))))
        assert got <= best + 2 * np.pi / 20000


def test_a_move_the_orientation_does_not_allow_is_not_made():
    # turning joint 6 by d turns the tool by about sin(angle of axis 6 from h) * d: beyond a
    # pose's rounding (ROUNDED_POSE) the value is kept (that branch has no solution)
    r = load_robot("ur5")
    S = Screws.of(r)
    h, e1, e2, l2, l3 = _plane(r)
    a = 0.8 * (l2 + l3) * e1[None]
    b = 0.5 * (l2 + l3) * e2[None]
    q6 = np.array([np.pi / 2])                 # axis 4 straight out: beyond the reach
    at = a + _turned(h, b, -q6)
    assert _reach_of(h, a, b, 1.0, q6)[0] > l2 + l3
    free = into_elbow_reach(S, a, b, 1.0, q6, at, np.array([1e-15]))
    move = abs(free[0] - q6[0])
    assert move > 1e-3
    kept = into_elbow_reach(S, a, b, 1.0, q6, at, np.array([2 * ROUNDED_POSE / move]))
    assert kept[0] == q6[0]
    made = into_elbow_reach(S, a, b, 1.0, q6, at, np.array([0.5 * ROUNDED_POSE / move]))
    assert made[0] == free[0]


def test_the_arcs_edges_shift_by_the_error_of_the_plane():
    # axis 6 a hair off h: the arcs (of axis 6 along h) put axis 4 at a distance off the
    # exact one ``at`` by about the tilt times the offsets; the move puts the plane's
    # distance that much inside the edge, so that the exact one lands on it
    r = load_robot("ur5")
    S = Screws.of(r)
    h, e1, e2, l2, l3 = _plane(r)
    rng = np.random.default_rng(32)
    n = 200
    a = _turned(h, np.broadcast_to(e1, (n, 3)), rng.uniform(-np.pi, np.pi, n)) * 0.7 * (l2 + l3)
    b = _turned(h, np.broadcast_to(e2, (n, 3)), rng.uniform(-np.pi, np.pi, n)) * 0.45 * (l2 + l3)
    q6 = rng.uniform(-np.pi, np.pi, n)
    at = a + _turned(h, b, -q6)
    err = rng.uniform(-3e-8, 3e-8, n)                      # the exact distance minus the plane's
    at = at * (1.0 + err / np.linalg.norm(at, axis=-1))[:, None]
    out = into_elbow_reach(S, a, b, 1.0, q6, at, np.full(n, 1e-15))
    moved = out != q6
    assert moved.sum() > 50
    d = _reach_of(h, a, b, 1.0, out)[moved]
    edge = np.where(np.linalg.norm(at, axis=-1) > l2 + l3, l2 + l3, abs(l2 - l3))[moved]
    assert np.allclose(d + err[moved], edge, rtol=0, atol=1e-12)
