"""``kincalc check``: grade homework sheets, one or a class's at once; tables or JSON for
people and scripts, Gradescope's and PrairieLearn's results for autograders, a gradebook
and feedback files for teachers."""

from __future__ import annotations

import os
import sys
from typing import Annotated, List, Optional

import typer

from .common import DebugOpt, FileName, JsonOpt, PrecisionOpt, Words, joints_text

#: the output formats, and those that describe one submission
FORMATS = ("table", "json", "gradescope", "prairielearn")
ONE_SUBMISSION = ("gradescope", "prairielearn")

FormatOpt = Annotated[Optional[str], typer.Option(
    "--format", metavar="table|json|gradescope|prairielearn", show_default=False,
    click_type=Words(FORMATS),
    help="What to write: tables (the default), kincalc's JSON (as --json), or the "
         "results.json of a Gradescope or a PrairieLearn autograder (one sheet).")]
OutputOpt = Annotated[Optional[str], typer.Option(
    "-o", "--output", metavar="FILE", show_default=False, click_type=FileName(),
    help="Write the --format json, gradescope or prairielearn document to FILE instead of "
         "standard output ('-'). An existing FILE is not replaced without --force.")]
ForceOpt = Annotated[bool, typer.Option(
    "--force", help="Let --output and --gradebook replace an existing regular file (never a "
                    "sheet, a link or a device), and --feedback-dir replace the feedback "
                    "files kincalc wrote there (no other file).")]
VisibilityOpt = Annotated[Optional[str], typer.Option(
    "--visibility", metavar="visible|hidden|after_due_date|after_published",
    show_default=False,
    click_type=Words(("visible", "hidden", "after_due_date", "after_published")),
    help="With --format gradescope: when students see the results (Gradescope's "
         "visibility; default: visible).")]
GradebookOpt = Annotated[Optional[str], typer.Option(
    "--gradebook", metavar="FILE", show_default=False, click_type=FileName(),
    help="Also write a CSV gradebook: a row per sheet (student, file, each item's points, "
         "points, total, percent, error), an invalid sheet's too.")]
FeedbackDirOpt = Annotated[Optional[str], typer.Option(
    "--feedback-dir", metavar="DIR", show_default=False, click_type=FileName(),
    help="Also write a Markdown feedback file per sheet in DIR (made if missing), named "
         "after the sheet (hw.yaml: hw.md).")]


def check(
    sheets: Annotated[List[str], typer.Argument(
        metavar="SHEET.yaml...", show_default=False,
        help="One or more homework sheets (YAML; format in 'man kincalc-check').")],
    quiet: Annotated[bool, typer.Option(
        "--quiet", "-q", help="Print only each sheet's score line.")] = False,
    robots_dir: Annotated[Optional[List[str]], typer.Option(
        "--robots-dir", metavar="DIR", show_default=False,
        help="Also let a sheet's 'robot:' name a robot file in DIR (repeatable; looked up "
             "before the sheet's folder). Without it a sheet may name only a bundled robot, "
             "an inline robot or a file in its own folder.")] = None,
    fmt: FormatOpt = None,
    output: OutputOpt = None,
    force: ForceOpt = False,
    visibility: VisibilityOpt = None,
    gradebook: GradebookOpt = None,
    feedback_dir: FeedbackDirOpt = None,
    precision: PrecisionOpt = 4,
    json: JsonOpt = False,
    debug: DebugOpt = False,
):
    """Grade homework sheets: each answer right or wrong, with hints and a score.

    A sheet names a robot (bundled, a file in its folder, or inline) and lists
    items (dh, link, fk, ik, jacobian, reach, singular), each with the
    student's answer. Every item is graded against kincalc's own results;
    wrong answers get the error and, where one fits, the slip behind it
    (degrees read as radians, a joint's sign, two joints swapped, a
    transposed or inverted matrix, standard and modified DH mixed up). IK
    answers are graded per solution set; missed sets are listed by branch.

    Sheets are untrusted input: a sheet's robot file must lie in the sheet's
    folder (or a --robots-dir folder), and no message quotes another file.

    For autograders, --format gradescope or prairielearn writes the results
    file of one sheet; for a class, --gradebook and --feedback-dir write a
    gradebook row and a feedback file per sheet, an invalid sheet's too.

    Exit status: 0 every answer right, 1 some wrong, 2 an invalid sheet (the
    message names file and line; other sheets are still graded; the worst
    status counts).
    """
    from .progress import progress
    _names(output, gradebook, feedback_dir)
    if output == "-":
        output = None                    # '-o -' is standard output, as for quiz
    fmt = _format(fmt, json, len(sheets), output, visibility)
    dirs = _robots_dirs(robots_dir)
    files = _plan(sheets, output, force, gradebook, feedback_dir)   # before any work
    outcomes, documents = [], []
    with progress(len(sheets), "grading") as step:
        for k, path in enumerate(sheets):
            outcome = _grade(path, dirs, debug)
            outcomes.append(outcome)
            text = _document(outcome, fmt, visibility)
            if text is not None and output is None:
                sys.stdout.write(text)
            elif text is not None:
                documents.append(text)
            elif fmt == "table" and outcome.report is not None:
                _tables(outcome.report.to_dict(), precision, quiet)
            if files["feedback"]:
                _write_feedback(files["feedback"][k], outcome)
            step()
    _finish(files, outcomes, documents, feedback_dir)
    raise typer.Exit(max(o.status for o in outcomes))


def _format(fmt, json: bool, count: int, output, visibility) -> str:
    """The output format asked for, or a UsageError for options that do not go together."""
    from ..errors import UsageError
    from ..homework.export import VISIBILITIES
    if fmt is None:
        fmt = "json" if json else "table"
    elif fmt not in FORMATS:
        raise UsageError(f"--format must be one of {', '.join(FORMATS)}, not {fmt!r}")
    elif json and fmt != "json":
        raise UsageError(f"--json and --format {fmt} ask for two formats; give one")
    if fmt in ONE_SUBMISSION and count != 1:
        raise UsageError(f"--format {fmt} describes one submission: give one sheet, not "
                         f"{count} (for a class's sheets use --gradebook FILE and "
                         "--feedback-dir DIR)")
    if visibility is not None and fmt != "gradescope":
        raise UsageError("--visibility is a setting of --format gradescope")
    if visibility is not None and visibility not in VISIBILITIES:
        raise UsageError(f"--visibility must be one of {', '.join(VISIBILITIES)}, not "
                         f"{visibility!r}")
    if output is not None and fmt == "table":
        raise UsageError("--output writes --format json, gradescope or prairielearn; "
                         "tables go to standard output")
    return fmt


def _names(output, gradebook, feedback_dir) -> None:
    """Refuse an empty name, and --gradebook - (standard output holds the sheets'
    results)."""
    from ..errors import UsageError
    for option, value, what in (("--output", output, "file"), ("--gradebook", gradebook, "file"),
                                ("--feedback-dir", feedback_dir, "folder")):
        if value is not None and not value.strip():
            raise UsageError(f"{option}: give a {what} name")
    if gradebook == "-":
        raise UsageError("--gradebook -: standard output is for the sheets' results; give a "
                         "file name")


def _robots_dirs(robots_dir) -> list:
    from ..errors import InputError
    dirs = list(robots_dir or [])
    for d in dirs:
        if not os.path.isdir(d):
            raise InputError(f"--robots-dir {d}: "
                             + ("no such folder" if not os.path.exists(d) else "not a folder"))
    return dirs


def _grade(path: str, dirs, debug: bool):
    """The :class:`~kincalc.homework.export.Outcome` of one sheet; an invalid sheet's error
    is said on stderr (``--debug`` raises it)."""
    import time

    from ..errors import KincalcError
    from ..homework import grade, load_sheet
    from ..homework.export import Outcome
    from ..limits import one_line
    start = time.monotonic()
    try:
        report = grade(load_sheet(path, dirs))
    except KincalcError as exc:
        if debug:
            raise
        message = one_line(exc)
        sys.stderr.write(f"kincalc: error: {message}\n")
        return Outcome(path, error=message, seconds=time.monotonic() - start)
    return Outcome(path, report=report, seconds=time.monotonic() - start)


def _document(outcome, fmt: str, visibility) -> str | None:
    """The JSON line of ``outcome`` in a machine format (None for tables); with --json an
    invalid sheet's line is ``{"sheet": PATH, "error": MESSAGE}`` (the error is on stderr
    too), so there is a line per sheet."""
    from ..homework.export import gradescope_results, prairielearn_results
    from .render import json_line
    if fmt == "gradescope":
        return json_line(gradescope_results(outcome, visibility))
    if fmt == "prairielearn":
        return json_line(prairielearn_results(outcome))
    if fmt == "json":
        return json_line(outcome.report.to_dict() if outcome.report is not None
                         else {"sheet": outcome.path, "error": outcome.error})
    return None


def _plan(sheets, output, force: bool, gradebook, feedback_dir) -> dict:
    """The files to write, each checked before any sheet is graded (a refused file costs
    nothing): ``{"output": Target or None, "gradebook": ..., "feedback": [Target, ...]}``;
    the feedback folder is made here, after every check."""
    from ..outputs import Target, check_target, make_folder
    inputs = tuple((f"the sheet {s}", s) for s in sheets)
    out = {"output": None, "gradebook": None, "feedback": []}
    for key, option, path in (("output", "--output", output),
                              ("gradebook", "--gradebook", gradebook)):
        if path is not None:
            out[key] = Target(path, option, force, inputs)
            check_target(out[key])
    if feedback_dir is not None:
        out["feedback"] = _feedback_targets(feedback_dir, sheets, force, inputs)
    _no_clash([t for t in (out["output"], out["gradebook"], *out["feedback"]) if t])
    if feedback_dir is not None:
        make_folder(feedback_dir, "--feedback-dir")
    return out


def _no_clash(targets) -> None:
    """Refuse two targets that are one file: the same real path (links in the folders
    followed), or the same file where both exist (a hard link)."""
    from ..errors import UsageError
    from ..outputs import same_file
    seen = {}
    for t in targets:
        real = os.path.normcase(os.path.realpath(t.path))
        other = seen.get(real) or next((o for o in seen.values()
                                        if os.path.lexists(t.path) and same_file(o.path, t.path)),
                                       None)
        if other is not None:
            raise UsageError(f"{other.option} {other.shown} and {t.option} {t.shown} are the "
                             "same file; give each output a file of its own")
        seen[real] = t


def _feedback_targets(folder: str, sheets, force: bool, inputs) -> list:
    """One checked :class:`~kincalc.outputs.Target` per sheet in ``folder``: a new name, or
    with ``force`` a feedback file kincalc wrote (its first line the mark)."""
    from ..homework.export import FEEDBACK_MARK
    from ..homework.gradebook import feedback_names
    from ..outputs import Target, check_target, shown_path
    from ..errors import InputError
    where = f"--feedback-dir {shown_path(folder)}"
    if "\0" in folder:
        raise InputError(f"{where}: not a valid folder name (it holds a NUL character)")
    if os.path.lexists(folder) and not os.path.isdir(folder):
        raise InputError(f"{where}: not a folder")
    if not os.path.isdir(folder) and not os.path.isdir(os.path.dirname(os.path.abspath(folder))):
        raise InputError(f"{where}: the folder it would be made in does not exist")
    targets = [Target(os.path.join(folder, name), "--feedback-dir", force, inputs)
               for name in feedback_names(sheets)]
    if os.path.isdir(folder):
        mark = (FEEDBACK_MARK + "\n").encode()
        for t in targets:
            check_target(t)
            if os.path.lexists(t.path):
                with open(t.path, "rb") as fh:
                    if fh.read(len(mark)) != mark:
                        t.fail("is not a feedback file kincalc wrote (its first line is not "
                               f"{FEEDBACK_MARK}); not replaced, even with --force")
    return targets


def _write_feedback(target, outcome) -> None:
    from ..homework.export import feedback_markdown
    from ..outputs import write_text
    write_text(target, feedback_markdown(outcome))


def _finish(files: dict, outcomes, documents, feedback_dir) -> None:
    """Write the documents kept for --output and the gradebook, and say in one line what
    was written."""
    from ..outputs import shown_path, write_text
    wrote = []
    if files["output"] is not None:
        write_text(files["output"], "".join(documents))
        wrote.append(files["output"].shown)
    if files["gradebook"] is not None:
        from ..homework.gradebook import gradebook_csv
        write_text(files["gradebook"], gradebook_csv(outcomes))
        bad = sum(o.report is None for o in outcomes)
        wrote.append(f"{files['gradebook'].shown} ({_count(len(outcomes), 'sheet')}"
                     + (f", {bad} invalid" if bad else "") + ")")
    if files["feedback"]:
        wrote.append(f"{_count(len(outcomes), 'feedback file')} in {shown_path(feedback_dir)}")
    if wrote:
        listed = ", ".join(wrote[:-1]) + " and " + wrote[-1] if len(wrote) > 1 else wrote[0]
        sys.stderr.write(f"kincalc: wrote {listed}\n")


def _count(n: int, what: str) -> str:
    return f"{n} {what}{'' if n == 1 else 's'}"


def _tables(doc, precision: int, quiet: bool):
    from rich.table import Table
    from rich.text import Text

    from ..homework.export import score_line
    from ..limits import printable as text      # a sheet's words: no control character
    from .render import bold_line, console, matrix_table
    c = console()
    who = f" — {doc['student']}" if doc["student"] else ""
    if quiet:
        c.print(f"{text(doc['sheet'])}{text(who)}: {score_line(doc['score'])}",
                highlight=False, soft_wrap=True)          # one line, however long
        return
    r = doc["robot"]
    title = f" — {doc['title']}" if doc["title"] else ""
    c.print(bold_line(text(doc["sheet"]), text(title) + text(who)))
    u, t = doc["units"], doc["tolerance"]
    lu = "" if u["length"] == "unitless" else f" {u['length']}"
    c.print(f"robot {text(r['name'])} ({joints_text(r['dof'])}, {r['convention']}); "
            f"tolerances: position {t['position']:g}{lu}, angle {t['angle']:g} {u['angle']}, "
            f"matrix entries {t['matrix']:g}", highlight=False)
    for item in doc["items"]:
        mark = ("right", "green") if item["passed"] else ("wrong", "red")
        c.print()
        c.print(Text.assemble((f"item {text(item['id'])}", "bold"), f" ({item['kind']}): ",
                              mark), highlight=False)
        rows = Table(box=None, show_header=False, pad_edge=False, padding=(0, 2, 0, 2))
        rows.add_column(style="dim", no_wrap=True)
        rows.add_column(overflow="fold")
        rows.add_row("result", text(item["message"]))
        if item["error"] is not None and item["kind"] != "ik":
            rows.add_row("error", f"{item['error']:.{max(precision, 1)}g}")
        if item["hint"] and item["kind"] != "ik":
            rows.add_row("hint", text(item["hint"]))
        c.print(rows)
        d = item["details"]
        if item["kind"] == "ik" and (d.get("sets") or d.get("missed")):
            c.print(_ik_table(d, precision))
        elif not item["passed"] and item["kind"] in ("link", "fk", "jacobian") \
                and "expected" in d:
            if "expected_tcv" in d:
                c.print(matrix_table([d["expected_tcv"]], precision, title="expected tcv"))
            c.print(matrix_table(d["expected"], precision, title="expected"))
    c.print()
    c.print(Text(score_line(doc["score"]), style="bold"), highlight=False)


def _ik_table(d, precision):
    from rich import box
    from rich.table import Table
    from rich.text import Text

    from .render import num
    t = Table(box=box.SIMPLE_HEAD, pad_edge=False)
    for name in ("set", "q", "result", "residual", "branch / note"):
        t.add_column(name, overflow="fold", no_wrap=name in ("set", "result"))
    for s in d["sets"]:
        res = s["residual"]
        resid = num(res["position"], precision) + (
            "" if res["orientation"] is None else " / " + num(res["orientation"], precision))
        colour = {"correct": "green", "duplicate": "yellow"}.get(s["status"], "red")
        note = s.get("branch", "") if s["status"] == "correct" and "branch" in s else ""
        if s.get("note"):
            note = (note + "; " if note else "") + s["note"]
        t.add_row(str(s["set"]), " ".join(num(v, precision) for v in s["q"]),
                  Text(s["status"], style=colour), resid, note)
    for m in d["missed"]:
        t.add_row("-", " ".join(num(v, precision) for v in m["solution_q"]),
                  Text("missed", style="red"), "", m["branch"])
    return t
