"""``kincalc compare``: are two robot definitions the same robot?"""

from __future__ import annotations

from typing import Annotated

import typer

from .common import (SEED, BaseLinkOpt, DebugOpt, DegOpt, Integer, JsonOpt, PrecisionOpt,
                     RobotName, TipLinkOpt, UnitOpt, display_units, joints_text, load_robot,
                     output)

RobotAArg = Annotated[str, typer.Argument(
    metavar="ROBOT_A", show_default=False, click_type=RobotName(),
    help="The reference: a bundled robot's name or a path to a robot YAML file.")]
RobotBArg = Annotated[str, typer.Argument(
    metavar="ROBOT_B", show_default=False, click_type=RobotName(),
    help="The robot compared with it (same forms).")]
AllowOffsetsOpt = Annotated[bool, typer.Option(
    "--allow-offsets", help="Let each joint of ROBOT_B have a constant offset and the "
                            "opposite sign (qB = sign * qA + offset); they are found and "
                            "printed.")]
FreeBaseOpt = Annotated[bool, typer.Option(
    "--free-base", help="Allow any constant difference of the base frames (found and "
                        "printed).")]
FreeToolOpt = Annotated[bool, typer.Option(
    "--free-tool", help="Allow any constant difference of the tool frames (found and "
                        "printed).")]
SamplesOpt = Annotated[int, typer.Option(
    "--samples", metavar="N", click_type=Integer(1, 1_000_000),
    help="Random configurations of ROBOT_A (within its limits) on which the answer is "
         "checked by forward kinematics, besides q = 0.")]
SeedOpt = Annotated[int, typer.Option(
    "--seed", metavar="S", click_type=SEED,
    help="Seed of those configurations (a non-negative integer).")]


def compare(
    robot_a: RobotAArg,
    robot_b: RobotBArg,
    allow_offsets: AllowOffsetsOpt = False,
    free_base: FreeBaseOpt = False,
    free_tool: FreeToolOpt = False,
    samples: SamplesOpt = 200,
    seed: SeedOpt = 0,
    deg: DegOpt = True,
    unit: UnitOpt = None,
    precision: PrecisionOpt = 4,
    json: JsonOpt = False,
    base_link: BaseLinkOpt = None,
    tip_link: TipLinkOpt = None,
    debug: DebugOpt = False,
):
    """Are ROBOT_A and ROBOT_B the same robot (same tool pose for every joint value)?

    Prints the verdict, the largest position and orientation difference of
    the tool over the sampled configurations and where (in ROBOT_A's joint
    values) it occurs; with --allow-offsets the offsets and sign changes that
    make them agree; otherwise the first joint whose axis cannot be made to
    match, and why. Exit status 0 same, 1 different, 2 bad input.
    """
    from ..analysis.compare import compare as _compare
    from ..conventions.library import URDF_SUFFIXES
    if (base_link or tip_link) and not any(r.lower().endswith(URDF_SUFFIXES)
                                           for r in (robot_a, robot_b)):
        load_robot(robot_a, base_link, tip_link)       # refused: neither robot is a URDF
    # the links choose the chain of whichever robot is a URDF (a YAML robot has none)
    a, b = (load_robot(r, *((base_link, tip_link) if r.lower().endswith(URDF_SUFFIXES)
                            else (None, None))) for r in (robot_a, robot_b))
    units = display_units(a, deg, unit)
    result = _compare(a, b, units, arguments=(robot_a, robot_b), samples=samples, seed=seed,
                      allow_offsets=allow_offsets, free_base=free_base, free_tool=free_tool)
    output(result.to_dict(), json, _tables, a, precision)
    if not result.match.same:
        raise typer.Exit(1)


def _tables(doc, robot, precision):
    from rich.text import Text

    from .render import console, file_words, kv_table, matrix_table, num, vec
    c = console()
    u = doc["units"]
    length = "" if u["length"] == "unitless" else f" {u['length']}"
    for tag, r in zip(("A (reference)", "B (candidate)"), doc["robots"]):
        title = f" - {r['title']}" if r["title"] else ""
        given = "" if r["argument"] in ("", r["name"]) else f"{r['argument']}: "
        c.print(Text.assemble(f"{tag}: {file_words(given)}", (file_words(r["name"]), "bold"),
                              f"{file_words(title)}  ({joints_text(r['dof'])}, "
                              f"{r['convention']})"))
    rows = [("same robot", "yes" if doc["same"] else "no"),
            ("why", doc["reason"])]
    if doc["first_bad_joint"] is not None:
        rows.append(("first joint that differs",
                     "the tool" if doc["first_bad_joint"] == len(doc["signs"]) + 1
                     else str(doc["first_bad_joint"])))
    if doc["position_error"] is not None:
        rows += [
            ("largest position difference", f"{num(doc['position_error'], precision)}{length}"),
            ("largest orientation difference",
             f"{num(doc['orientation_error'], precision)} {u['angle']}"),
            ("  at q (of A)", vec(doc["worst_q"], precision)),
            ("checked on", f"{doc['samples'] + 1} configurations of A (q = 0 and "
                           f"{doc['samples']} random, seed {doc['seed']})"),
            ("tolerance", f"{doc['position_tolerance']:.3g}{length} ({doc['tolerance']:g} x "
                          f"length scale {num(doc['length_scale'], precision)}{length}), "
                          f"{doc['orientation_tolerance']:.3g} {u['angle']}"),
        ]
    options = [o.replace("_", "-") for o in ("allow_offsets", "free_base", "free_tool") if doc[o]]
    if options:
        rows.append(("allowed", ", ".join(f"--{o}" for o in options)))
        rows += [("offsets (B = sign * A + offset)", vec(doc["offsets"], precision)),
                 ("signs", "  ".join("+1" if s > 0 else "-1" for s in doc["signs"]))]
    for line in doc["explanation"][1:]:
        label, _, text = line.partition(": ")
        if label.startswith(("base", "tool")):
            continue
        rows.append((label, text))
    c.print(kv_table(rows))
    for key, title in (("base", "base: B = base * A * tool"), ("tool", "tool")):
        if doc[key] is not None:
            c.print(matrix_table(doc[key], precision, title=title))
