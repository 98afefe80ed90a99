"""``kincalc selftest``: random joints -> FK -> IK round trips."""

from __future__ import annotations

from typing import Annotated

import typer

from ..limits import MAX_TRIALS
from .common import (BaseLinkOpt, DebugOpt, JsonOpt, RobotArg, StructureTolOpt, TipLinkOpt,
                     load_robot)


def selftest(
    robot: RobotArg,
    trials: Annotated[int, typer.Option("--trials", metavar="N", min=1, max=MAX_TRIALS,
                                        help="Number of random configurations.")] = 1000,
    seed: Annotated[int, typer.Option("--seed", min=0, help="Random seed (>= 0).")] = 0,
    json: JsonOpt = False,
    base_link: BaseLinkOpt = None,
    tip_link: TipLinkOpt = None,
    structure_tol: StructureTolOpt = None,
    debug: DebugOpt = False,
):
    """Check IK on random configurations within the limits (IKFast's --iktests metrics).

    For each configuration: FK, then IK; reports the success rate (the generating
    joints are among the solutions), missing-solution, no-solution and
    wrong-solution rates, the solution counts and the time per pose.
    Exit status 1 if any solution was wrong or any generating configuration missed.
    """
    from ..ik.families import plan
    from ..ik.selftest import run
    from ..analysis.results import SCHEMA_VERSION, Units, robot_summary
    rob = load_robot(robot, base_link, tip_link, structure_tol)
    _, fam, why = plan(rob)
    name, description = (fam.name, fam.description) if fam else (
        "numerical", f"one solution nearest home ({why})")
    m = run(rob, trials, seed)
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
