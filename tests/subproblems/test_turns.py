"""Turns about given axes making up a rotation (``kincalc.subproblems.turns``): known
answers, the nearest turn against a search over every angle, ill-posed cases, 0, 1 and 3
leading dimensions."""

import numpy as np

from kincalc.subproblems.turns import nearest_turn, two_turns
from subproblem_checks import PI, rot, unit


def _angle(Ra, Rb):
    """The angle (rad) between rotations, for stacks: ``|Ra - Rb|_F = 2 sqrt(2) sin(angle /
    2)`` (accurate for small angles)."""
    chord = np.linalg.norm(Ra - Rb, axis=(-2, -1)) / (2.0 * np.sqrt(2.0))
    return 2.0 * np.arcsin(np.minimum(chord, 1.0))


def test_nearest_turn_known_answers():
    rng = np.random.default_rng(1)
    k, t = unit(rng, 500), rng.uniform(-PI, PI, 500)
    d = nearest_turn(k, rot(k, t))
    assert np.abs(np.angle(np.exp(1j * (d - t)))).max() < 1e-12


def test_nearest_turn_is_the_nearest():
    """For any rotation, no turn about k on a grid of 7200 angles comes nearer."""
    rng = np.random.default_rng(2)
    k, E = unit(rng, 40), rot(unit(rng, 40), rng.uniform(-PI, PI, 40))
    d = nearest_turn(k, E)
    grid = np.linspace(-PI, PI, 7201)
    for i in range(40):
        best = _angle(rot(np.broadcast_to(k[i], (len(grid), 3)), grid), E[i]).min()
        assert _angle(rot(k[i], d[i]), E[i]) <= best + 1e-12


def test_nearest_turn_half_turn_normal_to_the_axis_is_zero():
    k = np.array([0.0, 0.0, 1.0])
    assert nearest_turn(k, rot(np.array([1.0, 0.0, 0.0]), PI)) == 0.0


def test_two_turns_known_answers_and_shapes():
    """``R(ka, x) R(kb, y) = E`` is rebuilt from the answer, at 0, 1 and 3 leading
    dimensions, and each problem of a batch is answered as it is alone."""
    rng = np.random.default_rng(3)
    lead = (2, 3, 4)
    ka, kb = unit(rng, *lead), unit(rng, *lead)
    E = rot(ka, rng.uniform(-PI, PI, lead)) @ rot(kb, rng.uniform(-PI, PI, lead))
    x, y = two_turns(ka, kb, E)
    assert x.shape == y.shape == lead
    assert _angle(rot(ka, x) @ rot(kb, y), E).max() < 1e-10
    flat = [a.reshape(-1, *a.shape[3:]) for a in (ka, kb, E)]
    x1, y1 = two_turns(*flat)
    assert np.allclose(x1, x.reshape(-1), atol=1e-13) and np.allclose(y1, y.reshape(-1), atol=1e-13)
    x0, y0 = two_turns(ka[1, 2, 3], kb[1, 2, 3], E[1, 2, 3])
    assert np.ndim(x0) == 0 and abs(x0 - x[1, 2, 3]) < 1e-13 and abs(y0 - y[1, 2, 3]) < 1e-13


def test_two_turns_about_one_axis_gives_the_sum_to_the_second():
    k = np.array([0.0, 0.6, 0.8])
    x, y = two_turns(k, k, rot(k, 1.25))
    assert abs(x) < 1e-15 and abs(y - 1.25) < 1e-12
