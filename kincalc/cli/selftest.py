"""``kincalc selftest``: random joints -> FK -> IK round trips."""

from __future__ import annotations

from typing import Annotated, Optional

import typer

from ..limits import MAX_TRIALS
from .common import (SEED, BaseLinkOpt, DebugOpt, Integer, JsonOpt, RobotArg, StructureTolOpt,
                     TipLinkOpt, load_robot)


def selftest(
    robot: RobotArg,
    trials: Annotated[int, typer.Option("--trials", metavar="N", click_type=Integer(1, MAX_TRIALS),
                                        help="Number of random configurations.")] = 1000,
    seed: Annotated[int, typer.Option("--seed", click_type=SEED,
                                      help="Random seed (>= 0).")] = 0,
    json: JsonOpt = False,
    base_link: BaseLinkOpt = None,
    tip_link: TipLinkOpt = None,
    structure_tol: StructureTolOpt = None,
    lock_joint: Annotated[Optional[str], typer.Option(
        "--lock-joint", metavar="JOINT", show_default=False,
        help="Redundant arms: hold JOINT (a name or number) at each configuration's own "
             "value and solve the others with every branch (ik --lock).")] = None,
    swivel: Annotated[bool, typer.Option(
        "--swivel", help="Arms with a spherical shoulder and wrist: solve each pose at its "
                         "configuration's own swivel angle (ik --swivel).")] = False,
    debug: DebugOpt = False,
):
    """Check IK on random configurations within the limits (IKFast's --iktests metrics).

    For each configuration: FK, then IK; reports the success rate (the generating
    joints are among the solutions), missing-solution, no-solution and
    wrong-solution rates, the solution counts and the time per pose.
    Exit status 1 if any solution was wrong or any generating configuration missed.
    """
    from ..errors import InputError
    from ..ik import Target, solve
    from ..ik.families import plan
    from ..ik.selftest import run
    from ..analysis.results import SCHEMA_VERSION, Units, robot_summary
    rob = load_robot(robot, base_link, tip_link, structure_tol)
    _, fam, why = plan(rob)
    name, description = (fam.name, fam.description) if fam else (
        "numerical", f"one solution nearest home ({why})")
    solver = None                       # (run's own: the robot's ik)
    if lock_joint is not None and swivel:
        raise InputError("--lock-joint and --swivel do not go together")
    if lock_joint is not None:
        from ..analysis.redundancy import generic_chain, solve_locked
        from .common import joint_index
        j = joint_index(lock_joint, rob, "--lock-joint")
        if rob.dof < 7:
            raise InputError(f"--lock-joint is for redundant arms: {rob.name} has {rob.dof} "
                             "joints, one held leaves fewer than a pose needs")
        chain = generic_chain(rob, j)                   # the family of any held value
        fam = plan(chain)[1]
        name = fam.name if fam else "numerical"
        description = (f"{rob.joints[j].name} held at each configuration's own value; the "
                       f"chain left: {fam.description if fam else 'numerical'}")

        def solver(q, T):
            return solve_locked(rob, Target(T), {j: float(q[j])})
    elif swivel:
        from ..ik.swivel import require_srs, swivel_angles
        require_srs(rob)
        name, description = "srs-swivel", "each pose at its configuration's swivel angle"

        def solver(q, T):
            return solve(rob, Target(T, swivel=float(swivel_angles(rob, q))))
    m = run(rob, trials, seed, solver)
    doc = {"kincalc": SCHEMA_VERSION, "command": "selftest", "robot": robot_summary(rob),
           "units": Units(length=rob.length_unit).to_dict(),
           "method": {"family": name, "description": description}, **m}
    if json:
        from .render import emit_json
        emit_json(doc)
    else:
        from .render import console, kv_table
        console().print(kv_table([
            ("robot", f"{rob.name} ({name})"), ("trials", f"{m['trials']} (seed {seed})"),
            ("success", f"{m['success_rate']:.2%}"), ("missing", f"{m['missing_rate']:.2%}"),
            ("no solution", f"{m['no_solution_rate']:.2%}"),
            ("wrong solutions", f"{m['wrong_solution_rate']:.2%}"),
            ("solutions per pose", ", ".join(f"{k}: {v}" for k, v in m["solutions_per_pose"].items())),
            ("time per pose", f"{m['time_per_pose_ms']['median']:.2f} ms median, "
                              f"{m['time_per_pose_ms']['mean']:.2f} ms mean")]))
    if m["wrong_solution_rate"] > 0 or m["missing_rate"] > 0 or m["no_solution_rate"] > 0:
        raise typer.Exit(1)
