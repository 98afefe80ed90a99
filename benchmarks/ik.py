"""Inverse kinematics: time per pose and solution sets, against other tools, same run.

    python benchmarks/ik.py [--poses 500] [--robots puma560 ur5]

For each robot: random joint configurations within the limits -> FK -> IK.
kincalc (``robot.ik(T)``, one call per pose) is timed, and when installed
(optional, e.g. ``pip install eaik roboticstoolbox-python``; never a runtime
dependency) EAIK's ``IK`` and Robotics Toolbox's ``ikine_a`` on the same poses.
Reported: median time per pose and the ratio to kincalc, solutions per pose,
how many returned solutions reproduce the pose (FK residual < 1e-6 m / rad:
"real") and how many do not (least-squares answers), and how often the
generating configuration is among the answers.
"""

import argparse
import statistics
import time

import numpy as np

import kincalc
from kincalc.ik.selftest import sample_configurations
from kincalc.spatial import rotation_error


def residual_ok(robot, q, T, tol=1e-6):
    Tq = robot.fk(q) if not callable(robot) else robot(q)
    return np.linalg.norm(Tq[:3, 3] - T[:3, 3]) < tol and rotation_error(Tq[:3, :3], T[:3, :3]) < tol


def contains(robot, sols, q, tol=1e-5):
    for s in sols:
        d = (np.asarray(s) - q + np.pi) % (2 * np.pi) - np.pi
        if np.all(np.abs(d) < tol):
            return True
    return False


def run_tool(name, robot, poses, Q, solve, fk=None):
    times, counts, real, fake, hits = [], [], 0, 0, 0
    for q, T in zip(Q, poses):
        t0 = time.perf_counter()
        sols = solve(T)
        times.append(time.perf_counter() - t0)
        counts.append(len(sols))
        ok = [s for s in sols if residual_ok(fk or robot, s, T)]
        real += len(ok)
        fake += len(sols) - len(ok)
        hits += contains(robot, ok, q)
    return {"tool": name, "median_us": statistics.median(times) * 1e6,
            "mean_solutions": float(np.mean(counts)), "real": real, "not_real": fake,
            "found_generating": hits / len(Q)}


def eaik_solver(robot):
    try:
        from eaik.IK_DH import DhRobot
    except ImportError:
        return None
    if robot.convention != "dh" or not np.allclose(robot.base, np.eye(4)) or \
            not np.allclose(robot.tool, np.eye(4)) or any(j.theta for j in robot.joints):
        return None
    er = DhRobot(np.array([j.alpha for j in robot.joints]), np.array([j.a for j in robot.joints]),
                 np.array([j.d for j in robot.joints]))
    try:
        er.IK(np.eye(4))
    except RuntimeError as exc:   # EAIK has no solver for this structure (e.g. general 6R)
        print(f"  eaik refuses {robot.name}: {exc}")
        return None

    def solve(T):
        s = er.IK(T)
        return [q for q, ls in zip(s.Q, s.is_LS)] if len(s.Q) else []
    return solve, None


def rtb_solver(robot):
    try:
        import roboticstoolbox as rtb
        from spatialmath import SE3
    except ImportError:
        return None
    if robot.name != "puma560":   # RTB's ikine_a exists for its own PUMA model
        return None
    p = rtb.models.DH.Puma560()   # RTB's own model (d1 = 0.672 m): judged by its own FK

    def solve(T):
        out = []
        for cfg in ("lun", "lul", "ldn", "ldf", "run", "rul", "rdn", "rdf", "luf", "ldf", "ruf", "rdf"):
            sol = p.ikine_a(SE3(T, check=False), config=cfg)
            if sol.success:
                out.append(np.array(sol.q))
        uniq = []
        for q in out:
            if not contains(robot, uniq, q, 1e-8):
                uniq.append(q)
        return uniq
    return solve, (lambda q: np.array(p.fkine(q).A))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--poses", type=int, default=500)
    ap.add_argument("--robots", nargs="+", default=["puma560", "ur5", "kuka_kr16"])
    args = ap.parse_args()
    for name in args.robots:
        r = kincalc.load_robot(name)
        Q = sample_configurations(r, args.poses, np.random.default_rng(0))
        poses = r.fk(Q)
        r.ik(poses[0])
        rows = [run_tool("kincalc", r, poses, Q, lambda T: [s.q for s in r.ik(T).solutions])]
        for label, make in (("eaik", eaik_solver), ("rtb ikine_a", rtb_solver)):
            made = make(r)
            if made is None:
                continue
            solver, fk = made
            P = poses if fk is None else np.array([fk(q) for q in Q])
            rows.append(run_tool(label, r, P, Q, solver, fk))
        print(f"\n{name}: {args.poses} poses, medians")
        print(f"{'tool':14s} {'us/pose':>9s} {'x kincalc':>9s} {'sols/pose':>9s} {'real':>6s} "
              f"{'not real':>8s} {'found q':>8s}")
        base = rows[0]["median_us"]
        for row in rows:
            print(f"{row['tool']:14s} {row['median_us']:9.1f} {row['median_us'] / base:9.2f} "
                  f"{row['mean_solutions']:9.2f} {row['real']:6d} {row['not_real']:8d} "
                  f"{row['found_generating']:8.1%}")


if __name__ == "__main__":
    main()
