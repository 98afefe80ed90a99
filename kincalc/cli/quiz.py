"""``kincalc quiz``: a random exercise sheet (and its answer key) for teachers."""

from __future__ import annotations

from typing import Annotated, Optional

import typer

from ..errors import InputError
from ..limits import MAX_SHEET_ITEMS, quote
from .common import (SEED, BaseLinkOpt, DebugOpt, FileName, RobotArg, TipLinkOpt, load_robot,
                     output_target)

SeedOpt = Annotated[Optional[int], typer.Option(
    "--seed", metavar="S", click_type=SEED, show_default=False,
    help="Seed of the random draws: the same seed gives the same sheet, byte for byte. "
         "Default: a random seed, written into the sheet.")]
AnswersOpt = Annotated[bool, typer.Option(
    "--answers", help="Fill in every answer: the key, which 'kincalc check' grades as fully "
                      "correct.")]
ItemsOpt = Annotated[Optional[str], typer.Option(
    "--items", metavar="KIND,...", show_default=False,
    help="The exercises, one item each, in this order (a kind may repeat): dh, link, fk, ik, "
         "jacobian, reach, singular. Default: dh,link,fk,ik,jacobian,singular,reach, less "
         "the kinds that do not apply or cannot be drawn (each with a note).")]
OutputOpt = Annotated[Optional[str], typer.Option(
    "-o", "--output", metavar="FILE|DIR", show_default=False, click_type=FileName(),
    help="Write the sheet to FILE instead of standard output ('-'); with --roster, the "
         "folder DIR of the sheets (DIR/ID.yaml) and keys (DIR/keys/ID.yaml). An existing "
         "file is not replaced without --force.")]
ForceOpt = Annotated[bool, typer.Option(
    "--force", help="Let --output replace an existing regular file (never a link, a device "
                    "or the robot file).")]
SheetDegOpt = Annotated[Optional[bool], typer.Option(
    "--deg/--rad", show_default=False,
    help="Angles on the sheet in degrees or radians. Default: the robot file's angle unit.")]
RosterOpt = Annotated[Optional[str], typer.Option(
    "--roster", metavar="FILE", show_default=False, click_type=FileName(),
    help="A sheet per student: FILE is a CSV roster with an 'id' column; each student gets "
         "a sheet and its key in the folder -o DIR, drawn from a seed of --salt and the id.")]
SaltOpt = Annotated[Optional[str], typer.Option(
    "--salt", metavar="TEXT", show_default=False,
    help="With --roster: the course's salt, one per assignment (hw4-2026). A student's seed "
         "is int(sha256(SALT:ID)[:12], 16): the roster and the salt give the same sheets.")]


def quiz(
    robot: RobotArg,
    seed: SeedOpt = None,
    answers: AnswersOpt = False,
    items: ItemsOpt = None,
    output: OutputOpt = None,
    force: ForceOpt = False,
    deg: SheetDegOpt = None,
    roster: RosterOpt = None,
    salt: SaltOpt = None,
    base_link: BaseLinkOpt = None,
    tip_link: TipLinkOpt = None,
    debug: DebugOpt = False,
):
    """Write a random exercise sheet for ROBOT (the format 'kincalc check' grades).

    One item per kind of --items, each with a question, the inputs to type and,
    with --answers, the correct answer computed from the values as written:
    random joints (whole degrees, 0.001 length units) within the limits, a
    reachable pose rounded to a few decimals, a pose just beyond the reach, a
    singular configuration. Kinds that do not apply to the robot (dh for a
    product-of-exponentials robot, ik without a closed form) are left out with
    a note on standard error; so are, with the default --items, kinds no
    exercise of which can be drawn for it (a kind asked for by --items is then
    an error). With --roster, one sheet and one key per student.

    ROBOT is a bundled robot's name or a path to a robot YAML file.
    """
    import sys

    from ..homework.quiz import make_sheet, sheet_yaml, skipped
    kinds = _kinds(items)
    drawn_notes = [] if items is None else None      # the default kinds: leave out, note
    if output == "-":
        output = None                    # '-o -' is standard output, as for convert
    if roster is not None:
        _roster_quiz(robot, roster, salt, kinds, output, force, deg, seed, answers,
                     base_link, tip_link, drawn_notes is not None)
        return
    if salt is not None:
        raise InputError("--salt goes with --roster (the seed of each student's sheet)")
    target = None
    if output is not None:               # before any work: a refused file costs nothing
        from ..outputs import check_target
        target = output_target(output, "--output", force, robot)
        check_target(target)
    rob = load_robot(robot, base_link, tip_link)
    _numeric_limit(rob, kinds)
    drawn = seed is None
    if drawn:
        import secrets
        seed = secrets.randbelow(1_000_000)
    angle = None if deg is None else ("deg" if deg else "rad")
    ref = _robot_ref(robot, output)
    sheet = make_sheet(rob, seed, kinds, answers=answers, angle_unit=angle, robot_ref=ref,
                       notes=drawn_notes)
    if drawn:
        sys.stderr.write(f"kincalc: seed {seed} (give --seed {seed} to draw this sheet again)\n")
    notes = skipped(rob, kinds) + (drawn_notes or [])
    for kind, why in notes:
        sys.stderr.write(f"kincalc: note: {kind} left out: {why}\n")
    text = sheet_yaml(sheet, _comments(robot, seed, None if items is None else kinds, deg,
                                       answers, ref, notes))
    if output is None:
        sys.stdout.write(text)
        return
    from ..outputs import write_text
    write_text(target, text)             # a temporary file renamed over it when complete
    n = len(sheet["items"])
    sys.stderr.write(f"kincalc: wrote {output} ({n} item{'s' if n != 1 else ''}"
                     f"{', with answers' if answers else ''})\n")


def _kinds(items: str | None) -> list[str]:
    """The kinds of --items, checked (None: the default kinds)."""
    from ..homework.quiz import DEFAULT_KINDS, KINDS
    if items is None:
        return list(DEFAULT_KINDS)
    kinds = [k.strip() for k in items.split(",") if k.strip()]
    if not kinds:
        raise InputError(f"--items: give at least one kind ({', '.join(KINDS)})")
    unknown = [k for k in kinds if k not in KINDS]
    if unknown:
        raise InputError(f"--items: unknown exercise kind {quote(unknown[0])} (choose from "
                         f"{', '.join(KINDS)})")
    if len(kinds) > MAX_SHEET_ITEMS:        # (a sheet check would refuse)
        raise InputError(f"--items: {len(kinds)} kinds; a sheet holds at most "
                         f"{MAX_SHEET_ITEMS} items (kincalc's limit)")
    return kinds


def _numeric_limit(robot, kinds) -> None:
    """Refuse --items whose sheet check would refuse: too many ik and reach items for a
    robot solved numerically."""
    from ..homework.sheet.format import numeric_items_limit
    too_many = numeric_items_limit(robot, kinds)
    if too_many:
        raise InputError(f"--items: {too_many}")


def _comments(robot: str, seed: int, kinds, deg, answers: bool, ref: str, notes,
              student: str | None = None) -> list[str]:
    """The comment lines on top of a sheet: the command that draws it again (``kinds``
    None: the default --items), how to grade it, and the kinds left out."""
    import shlex

    from ..version import __version__
    items = [] if kinds is None else ["--items", ",".join(kinds)]
    command = " ".join(["kincalc quiz", shlex.quote(robot), "--seed", str(seed)] + items
                       + ([] if deg is None else ["--deg" if deg else "--rad"])
                       + (["--answers"] if answers else []))
    out = [f"Generated by kincalc {__version__}: {command}"]
    if student is not None:
        out.append(f"The {'key' if answers else 'sheet'} of student {student} (kincalc quiz "
                   "--roster: the seed comes from the course's salt and the id)")
    out.append("Grade it with: kincalc check FILE" + _robots_dir_option(ref)
               + ("" if answers else " (answer each item by adding 'answer:')"))
    return out + [f"{kind} left out: {why}" for kind, why in notes]


def _roster_quiz(robot: str, roster: str, salt, kinds, output, force: bool, deg, seed,
                 answers: bool, base_link, tip_link, lenient: bool) -> None:
    """``quiz --roster``: a sheet and a key per student, DIR/ID.yaml and DIR/keys/ID.yaml
    (every file checked before any is drawn; the folders made when the first is)."""
    import os
    import sys

    from ..homework.quiz import sheet_yaml, skipped
    from ..homework.roster import read_roster, variant_sheets
    from ..outputs import make_folder, write_text
    from .progress import progress
    if seed is not None or answers:
        raise InputError(f"{'--seed' if seed is not None else '--answers'} does not go with "
                         "--roster: each student's seed comes from --salt and the id, and "
                         "the keys are written anyway (DIR/keys/ID.yaml)")
    if not salt:
        raise InputError("--roster needs --salt TEXT, the course's salt, one per assignment "
                         "(for example --salt hw4-2026)")
    if output is None:
        raise InputError("--roster needs -o DIR, the folder for the sheets (and DIR/keys "
                         "for the keys)")
    students = read_roster(roster)
    keys = os.path.join(output, "keys")
    targets = _roster_targets(output, keys, [s.id for s in students], force, robot, roster)
    rob = load_robot(robot, base_link, tip_link)
    _numeric_limit(rob, kinds)
    angle = None if deg is None else ("deg" if deg else "rad")
    refs = (_robot_ref(robot, os.path.join(output, "x.yaml")),
            _robot_ref(robot, os.path.join(keys, "x.yaml")))
    notes = skipped(rob, kinds)
    for kind, why in notes:
        sys.stderr.write(f"kincalc: note: {kind} left out: {why}\n")
    with progress(len(students), "drawing sheets") as step:
        for student, (sheet_file, key_file) in zip(students, targets):
            drawn = [] if lenient else None
            sheet, key = variant_sheets(rob, student, salt, kinds, angle_unit=angle,
                                        robot_refs=refs, notes=drawn)
            for kind, why in drawn or []:
                sys.stderr.write(f"kincalc: note: {kind} left out of {student.id}'s sheet: "
                                 f"{why}\n")
            make_folder(keys, "-o")
            for doc, target, ref, is_key in ((sheet, sheet_file, refs[0], False),
                                             (key, key_file, refs[1], True)):
                write_text(target, sheet_yaml(doc, _comments(
                    robot, doc["seed"], None if lenient else kinds, deg, is_key, ref,
                    notes + (drawn or []), student.id)))
            step()
    n = len(students)
    sys.stderr.write(f"kincalc: wrote {n} sheet{'s' if n != 1 else ''} in {output} and "
                     f"{'their keys' if n != 1 else 'its key'} in {keys}\n")


def _roster_targets(folder: str, keys: str, ids, force: bool, robot: str, roster: str):
    """``[(sheet Target, key Target), ...]`` for the ids, each checked when its folder
    exists; the folders themselves must be folders (or not exist yet, in one that does)."""
    import os

    from ..outputs import check_target, shown_path
    for path in (folder, keys):
        if "\0" in path:
            raise InputError(f"--output {shown_path(path)}: not a valid folder name (it holds "
                             "a NUL character)")
        if os.path.lexists(path) and not os.path.isdir(path):
            raise InputError(f"--output {shown_path(path)}: not a folder (with --roster, -o "
                             "names the folder of the sheets)")
    if not os.path.isdir(os.path.dirname(os.path.abspath(folder))):
        raise InputError(f"--output {shown_path(folder)}: the folder it would be made in "
                         "does not exist")
    if os.path.realpath(keys) == os.path.realpath(folder):
        raise InputError(f"--output {shown_path(folder)}: its keys folder {shown_path(keys)} "
                         "is the sheets' folder (a link): the sheets would hold the answers")
    out, seen = [], set()
    for sid in ids:
        pair = tuple(output_target(os.path.join(d, f"{sid}.yaml"), "--output", force, robot,
                                   files=[("--roster", roster)]) for d in (folder, keys))
        for t, d in zip(pair, (folder, keys)):
            if os.path.isdir(d):
                check_target(t)
            real = os.path.realpath(t.path)
            if real in seen:
                t.fail("is also another sheet's or key's file (a link in the folders); "
                       "nothing written")
            seen.add(real)
        out.append(pair)
    return out


def _robots_dir_option(ref: str) -> str:
    """`` --robots-dir DIR`` when the sheet's robot file lies outside the sheet's folder:
    ``check`` looks for robot files only inside it unless the grader names another."""
    import posixpath
    if "/" not in ref or not ref.startswith("../"):
        return ""
    return f" --robots-dir {posixpath.dirname(ref)} (from the sheet's folder)"


def _robot_ref(robot: str, output: str | None) -> str:
    """What the sheet's ``robot:`` says: a bundled robot's name, or the robot file's
    path relative to the sheet's folder (the current one for standard output)."""
    import os

    from ..conventions.library import library_dir, resolve
    path, _ = resolve(robot)
    if path.resolve().parent == library_dir().resolve():
        return path.stem
    start = os.path.dirname(os.path.abspath(output)) if output is not None else os.getcwd()
    return os.path.relpath(os.path.abspath(path), start).replace(os.sep, "/")
