"""One configuration at a time: ``robot.fk(q)`` and ``robot.jacobian(q)`` against the
per-configuration numpy loop a user writes from the DH table, in the same run.

    python benchmarks/fk_single.py [--robots puma560 ur5 kuka_kr16 stanford_arm_mdh]
                                   [--configs 300] [--repeat 7]

The references build each link matrix of the robot file's convention (standard or
modified DH) with ``np.cos``/``np.sin`` and ``np.array``, multiply them in turn, and for
the Jacobian take ``z_i x (p - o_i)`` with ``np.cross`` (Siciliano et al. 2009, eq.
3.30). Both are checked against kincalc before timing. Reported: the median over
``--repeat`` runs of the mean time per configuration, and kincalc's ratio to the
reference (target: <= 1.5x for both).
"""

import argparse
import os
import statistics
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import kincalc  # noqa: E402


def link_matrix(convention, joint, q):
    """The textbook link matrix ``T_{i-1}^i`` for joint value ``q`` (rad or m)."""
    theta = joint.theta + (q if joint.revolute else 0.0)
    d = joint.d + (0.0 if joint.revolute else q)
    ct, st = np.cos(theta), np.sin(theta)
    ca, sa = np.cos(joint.alpha), np.sin(joint.alpha)
    a = joint.a
    if convention == "dh":
        return np.array([[ct, -st * ca, st * sa, a * ct],
                         [st, ct * ca, -ct * sa, a * st],
                         [0.0, sa, ca, d],
                         [0.0, 0.0, 0.0, 1.0]])
    return np.array([[ct, -st, 0.0, a],
                     [st * ca, ct * ca, -sa, -sa * d],
                     [st * sa, ct * sa, ca, ca * d],
                     [0.0, 0.0, 0.0, 1.0]])


def loop_fk(robot, q):
    T = robot.base
    for joint, qi in zip(robot.joints, q):
        T = T @ link_matrix(robot.convention, joint, qi)
    return T @ robot.tool


def loop_jacobian(robot, q):
    """Columns from each joint's frame: the z axis and origin of frame i-1 (dh) or i
    (mdh), in the world frame."""
    T = robot.base
    axes, points = [], []
    for joint, qi in zip(robot.joints, q):
        A = link_matrix(robot.convention, joint, qi)
        if robot.convention == "mdh":
            T = T @ A
        axes.append(T[:3, 2])
        points.append(T[:3, 3])
        if robot.convention == "dh":
            T = T @ A
    p = (T @ robot.tool)[:3, 3]
    J = np.zeros((6, robot.dof))
    for i, joint in enumerate(robot.joints):
        if joint.revolute:
            J[:3, i] = np.cross(axes[i], p - points[i])
            J[3:, i] = axes[i]
        else:
            J[:3, i] = axes[i]
    return J


def per_config(f, qs, repeat):
    runs = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for q in qs:
            f(q)
        runs.append((time.perf_counter() - t0) / len(qs))
    return statistics.median(runs)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--robots", nargs="+",
                    default=["puma560", "ur5", "kuka_kr16", "stanford_arm_mdh"])
    ap.add_argument("--configs", type=int, default=300)
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    print(f"medians of {args.repeat} runs over {args.configs} configurations, us per call")
    print(f"{'robot':18s} {'fk':>7s} {'loop':>7s} {'ratio':>6s}   "
          f"{'jacobian':>8s} {'loop':>7s} {'ratio':>6s}")
    for name in args.robots:
        r = kincalc.load_robot(name)
        if r.convention not in ("dh", "mdh"):
            raise SystemExit(f"{name}: the reference loop is written for dh and mdh robots")
        qs = np.random.default_rng(0).uniform(-np.pi, np.pi, (args.configs, r.dof))
        for q in qs[:20]:
            assert np.allclose(loop_fk(r, q), r.fk(q), atol=1e-12)
            assert np.allclose(loop_jacobian(r, q), r.jacobian(q), atol=1e-12)
        t_fk = per_config(r.fk, qs, args.repeat)
        t_lf = per_config(lambda q: loop_fk(r, q), qs, args.repeat)
        t_j = per_config(r.jacobian, qs, args.repeat)
        t_lj = per_config(lambda q: loop_jacobian(r, q), qs, args.repeat)
        print(f"{name:18s} {t_fk * 1e6:7.1f} {t_lf * 1e6:7.1f} {t_fk / t_lf:6.2f}   "
              f"{t_j * 1e6:8.1f} {t_lj * 1e6:7.1f} {t_j / t_lj:6.2f}")


if __name__ == "__main__":
    main()
