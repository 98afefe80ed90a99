"""Random robots for property tests (seeded; no robot names, only geometry)."""

import numpy as np

from kincalc.model import Joint, Robot
from kincalc.spatial import matrix_from_rpy, transform


def random_pose(rng, scale=0.5):
    return transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-scale, scale, 3))


def random_robot(rng, convention="dh", n=6, types=None, base_tool=True):
    """A random serial robot: lengths in [-0.5, 0.5] m, twists and offsets anywhere."""
    types = types or ["revolute" if rng.random() < 0.8 else "prismatic" for _ in range(n)]
    joints = []
    for i, t in enumerate(types):
        lim = (-np.pi, np.pi) if t == "revolute" else (0.0, 0.5)
        if convention == "poe":
            axis = rng.normal(size=3)
            axis /= np.linalg.norm(axis)
            joints.append(Joint(f"q{i + 1}", t, axis=tuple(axis),
                                point=tuple(rng.uniform(-0.5, 0.5, 3)), limits=lim))
        else:
            joints.append(Joint(f"q{i + 1}", t, alpha=rng.uniform(-np.pi, np.pi),
                                a=rng.uniform(-0.5, 0.5), d=rng.uniform(-0.5, 0.5),
                                theta=rng.uniform(-np.pi, np.pi), limits=lim))
    base = random_pose(rng) if base_tool else np.eye(4)
    M = random_pose(rng) if convention == "poe" else None
    tool = random_pose(rng) if base_tool else np.eye(4)
    return Robot(name=f"random_{convention}", convention=convention, joints=tuple(joints),
                 base=base, tool=tool, M=M)
