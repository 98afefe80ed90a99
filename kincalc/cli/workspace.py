"""``kincalc workspace``: sampled workspace, envelope, volume, dexterity, plots."""

from __future__ import annotations

from typing import Annotated, Optional

import typer

from ..limits import MAX_ORIENTATIONS, MAX_SAMPLES
from .common import (NUMBER, SEED, BaseLinkOpt, DebugOpt, DegOpt, DpiOpt, FileName, Integer, JsonOpt,
                     PrecisionOpt, RobotArg, TipLinkOpt, UnitOpt, display_units, load_robot,
                     output, output_target)


def workspace(
    robot: RobotArg,
    samples: Annotated[int, typer.Option(
        "--samples", metavar="N", click_type=Integer(1000, MAX_SAMPLES),
        help="Joint configurations sampled uniformly within the limits.")] = 200_000,
    seed: Annotated[int, typer.Option(
        "--seed", metavar="S", click_type=SEED,
        help="Seed of the random generator, a non-negative integer: the same seed gives "
             "the same numbers.")] = 0,
    dexterity: Annotated[float, typer.Option(
        "--dexterity", metavar="F", click_type=NUMBER,
        help="Fraction of the test orientations a point must reach to count as dexterous "
             "(1 = every one, the textbook's dexterous workspace).")] = 1.0,
    orientations: Annotated[Optional[int], typer.Option(
        "--orientations", metavar="K", click_type=Integer(2, MAX_ORIENTATIONS), show_default=False,
        help="Number of test orientations for dexterity (default 48 for arms that control "
             "the full orientation, 24 for one angle).")] = None,
    plot: Annotated[Optional[str], typer.Option(
        "--plot", metavar="FILE", show_default=False, click_type=FileName(),
        help="Also draw sections of the reachable set through the base axis and through "
             "the shoulder (a planar arm: its plane), with their boundary, the dexterous part "
             "hatched and manipulability in colour, to FILE (.png, .svg or .pdf; needs the "
             "'plot' extra). An existing FILE is not replaced without --force.")] = None,
    dpi: DpiOpt = 100,
    force: Annotated[bool, typer.Option(
        "--force", help="Let --plot replace an existing regular file (never a link, a "
                        "device or the robot file).")] = False,
    deg: DegOpt = True,
    unit: UnitOpt = None,
    precision: PrecisionOpt = 4,
    json: JsonOpt = False,
    base_link: BaseLinkOpt = None,
    tip_link: TipLinkOpt = None,
    debug: DebugOpt = False,
):
    """Workspace: Monte-Carlo sampling of the joint space within the limits.

    Reports the reach envelope (least and greatest distance of the tool
    point from the base, z range), the reachable workspace volume (an area
    for planar arms) with a 95% confidence interval, the dexterous workspace
    (where the tool reaches every test orientation, or the --dexterity
    fraction of them) and manipulability statistics. Seeded: the same
    --seed and --samples give the same numbers.

    ROBOT is a bundled robot's name or a path to a robot YAML file.
    """
    from ..analysis.workspace import analyse
    plot_to = None
    if plot is not None:            # before the sampling: a refused file costs nothing
        from ..analysis.plot import check_output, require_matplotlib
        plot_to = output_target(plot, "--plot", force, robot)
        check_output(plot_to)
        require_matplotlib("kincalc workspace --plot")
    rob = load_robot(robot, base_link, tip_link)
    units = display_units(rob, deg, unit)
    with _progress() as report:
        result = analyse(rob, samples, seed, units=units, dexterity=dexterity,
                         orientations=orientations, sections=plot is not None,
                         progress=report)
    doc = result.to_dict()
    if plot is not None and not result.sections:
        import sys
        sys.stderr.write(f"kincalc: the tool moves along a line: no sections to draw; "
                         f"{plot} not written\n")
        plot = None
    if plot is not None:
        from ..analysis.plot import draw_sections
        from ..analysis.workspace import manipulability_unit
        unit = manipulability_unit(rob, units)
        draw_sections(result.sections, plot_to, units=units, dpi=dpi,
                      suptitle=f"{rob.title or rob.name}: workspace sections "
                               f"({samples} samples, seed {seed})",
                      colour_label="manipulability (Yoshikawa, as kincalc jacobian)"
                                   + (f", {unit}" if unit else ""))
        doc["plot"] = plot
    output(doc, json, _tables, rob, precision)


class _progress:
    """A rich progress bar on stderr while the analysis runs, when stderr is a terminal."""

    def __enter__(self):
        import sys
        self.bar = None
        if sys.stderr.isatty():
            from rich.console import Console
            from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
            self.bar = Progress(TextColumn("{task.description:<12}"), BarColumn(),
                                TextColumn("{task.percentage:>3.0f}%"), TimeElapsedColumn(),
                                console=Console(stderr=True), transient=True)
            self.bar.__enter__()
            self.tasks = {}
        return self.report

    def report(self, stage, done, total):
        if self.bar is None:
            return
        if stage not in self.tasks:
            self.tasks[stage] = self.bar.add_task(stage, total=total)
        self.bar.update(self.tasks[stage], completed=done)

    def __exit__(self, *exc):
        if self.bar is not None:
            self.bar.__exit__(*exc)
        return False


def _tables(doc, robot, precision):
    from .render import console, heading, kv_table, num
    c = console()
    c.print(heading(doc))
    u = doc["units"]
    L = "" if u["length"] == "unitless" else f" {u['length']}"
    e = doc["envelope"]
    vu = "" if u["length"] == "unitless" else " " + doc["volume_unit"]
    lo, hi = doc["volume_ci95"]

    def vol(x):   # volumes span mm^3 to m^3: significant digits, not decimals
        return f"{x:.{max(precision, 1)}g}"
    rows = [
        ("samples", f"{doc['samples']} (seed {doc['seed']})"),
        ("distance from the base", f"{num(e['min_distance'], precision)} to "
                                   f"{num(e['max_distance'], precision)}{L}"),
        ("z range", f"{num(e['z_min'], precision)} to {num(e['z_max'], precision)}{L}"),
        (f"reachable {doc['measure']}", f"{vol(doc['volume'])}{vu}  "
                                        f"(95% CI {vol(lo)} to {vol(hi)})"),
    ]
    d = doc["dexterous"]
    if d["defined"]:
        dlo, dhi = d["volume_ci95"]
        share = ("every" if d["fraction_required"] >= 1 else
                 f"{100 * d['fraction_required']:g}% of the")
        rows.append((f"dexterous {doc['measure']}",
                     f"{vol(d['volume'])}{vu}  (95% CI {vol(dlo)} to "
                     f"{vol(dhi)}; {share} test orientation reached at "
                     f"{d['dexterous_points']} of {d['reachable_test_points']} reachable "
                     "test points)"))
        rows.append(("  test orientations", d["orientations"]))
        rows.append(("  tested by", d["method"]))
    else:
        rows.append((f"dexterous {doc['measure']}", "none: " + d["reason"]))
    m = doc["manipulability"]
    rows += [
        ("manipulability", f"median {num(m['median'], precision + 2)}, 5-95% "
                           f"{num(m['p5'], precision + 2)} to {num(m['p95'], precision + 2)}, "
                           f"max {num(m['max'], precision + 2)}"),
        ("condition number", f"median {num(m['condition_median'], 2)}, 95th percentile "
                             f"{num(m['condition_p95'], 2)} (length-normalised Jacobian)"),
        ("near-singular samples", f"{100 * m['near_singular_fraction']:.3g}%"),
    ]
    if "plot" in doc:
        rows.append(("plot", doc["plot"]))
    c.print(kv_table(rows))
