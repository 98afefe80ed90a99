"""Screws.turn, the rotation every family solver applies: each layout it takes (one
vector for every angle, a vector per angle, several vectors per angle, broadcast angles)
against the rotation matrix of the axis and angle."""

import numpy as np
import pytest

import kincalc
from kincalc.ik.screws import Screws
from kincalc.spatial import matrix_from_axis_angle


@pytest.mark.parametrize("layout", ["one vector", "per angle", "two per angle", "broadcast"])
def test_turn_is_the_rotation_about_the_joint_axis(layout):
    S = Screws.of(kincalc.load_robot("puma560"))
    rng = np.random.default_rng(5)
    t = rng.uniform(-np.pi, np.pi, (3, 4))
    v = {"one vector": rng.normal(size=3), "per angle": rng.normal(size=(3, 4, 3)),
         "two per angle": rng.normal(size=(3, 4, 2, 3)),
         "broadcast": rng.normal(size=(4, 3))}[layout]
    for i in range(6):
        R = matrix_from_axis_angle(S.axis[i], t)                          # (3, 4, 3, 3)
        if layout == "two per angle":
            want = (R[:, :, None] @ v[..., None])[..., 0]
        else:
            want = (R @ np.broadcast_to(v, (3, 4, 3))[..., None])[..., 0]
        got = S.turn(i, np.cos(t), np.sin(t), v)
        assert got.shape == want.shape
        np.testing.assert_allclose(got, want, atol=1e-14)
