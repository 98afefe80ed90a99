"""One sheet per student (``kincalc quiz ROBOT --roster FILE --salt TEXT -o DIR``): the
roster read and checked, each student's seed, and their sheet and key.

A student's seed comes from the course's salt and their id alone (:func:`variant_seed`),
so a teacher regenerates any student's sheet and key from the roster, the salt and the
command line. A roster is untrusted input (a file exported from elsewhere): it is read
bounded (:data:`~kincalc.limits.MAX_FILE_BYTES`, :data:`~kincalc.limits.MAX_ROSTER_STUDENTS`),
and an id names files, so it may hold only the characters of :data:`ID_PATTERN`.
"""

from __future__ import annotations

import csv
import hashlib
import io
import re
from dataclasses import dataclass

from ..errors import RobotFileError
from ..limits import MAX_ROSTER_STUDENTS, MAX_STUDENT_ID, quote

#: a student id: a letter or digit, then letters, digits, ``.``, ``_`` or ``-`` (a file
#: name on every system, never ``..``, never hidden, no folder)
ID_PATTERN = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]*")

#: names Windows keeps for devices (``con.yaml`` is no file there)
_DEVICE_NAMES = {"con", "prn", "aux", "nul", *(f"com{k}" for k in range(10)),
                 *(f"lpt{k}" for k in range(10))}

#: hex digits of the SHA-256 digest taken for a seed (48 bits)
SEED_HEX_DIGITS = 12


class RosterError(RobotFileError):
    """An invalid roster: ``file:line: message`` (exit status 2)."""


@dataclass(frozen=True)
class Student:
    """A roster's row: the student's ``id`` and its ``line`` in the file."""

    id: str
    line: int


def variant_seed(salt: str, student_id: str) -> int:
    """The seed of a student's sheet.

    ``int(sha256(SALT + ":" + ID).hexdigest()[:12], 16)``, the text UTF-8: the first 48
    bits of the digest, so ``printf '%s' 'SALT:ID' | sha256sum | cut -c1-12`` gives it
    in hex. An id holds no ``:``, so different (salt, id) pairs hash different texts.

    Parameters
    ----------
    salt : str
        The course's salt (one per assignment, so that two assignments differ).
    student_id : str
        The id, as the roster has it.

    Returns
    -------
    int
        From 0 to 2**48 - 1.
    """
    digest = hashlib.sha256(f"{salt}:{student_id}".encode("utf-8")).hexdigest()
    return int(digest[:SEED_HEX_DIGITS], 16)


def id_problem(student_id: str) -> str | None:
    """Why ``student_id`` cannot name a student's files, or None when it can.

    Parameters
    ----------
    student_id : str

    Returns
    -------
    str or None
    """
    if not student_id:
        return "the id is empty"
    if len(student_id) > MAX_STUDENT_ID:
        return f"the id has {len(student_id)} characters; at most {MAX_STUDENT_ID}"
    if not ID_PATTERN.fullmatch(student_id):
        return (f"the id {quote(student_id)} is not a safe file name: letters, digits, '.', "
                "'_' and '-', starting with a letter or a digit")
    if student_id.split(".")[0].lower() in _DEVICE_NAMES:
        return f"the id {quote(student_id)} is a device name on Windows"
    return None


def _header(row, file: str, line: int) -> int:
    names = [c.strip().lower() for c in row]
    if "id" not in names:
        raise RosterError(file, line, "the first line must name the columns, one of them "
                                      "'id' (the student id; other columns are ignored)")
    if names.count("id") > 1:
        raise RosterError(file, line, "two columns are named 'id'")
    return names.index("id")


def parse_roster(text: str, file: str = "<roster>") -> list[Student]:
    """The students of a roster's CSV ``text``.

    The first line that is not blank names the columns; the one named ``id`` (any case)
    holds the student ids, the others are ignored. Blank lines are skipped.

    Parameters
    ----------
    text : str
        The CSV text (a leading byte-order mark is dropped).
    file : str
        The file's name, for messages.

    Returns
    -------
    list of Student
        In the file's order.

    Raises
    ------
    RosterError
        Naming the file and line: not CSV, no ``id`` column, a row without an id, an id
        that :func:`id_problem` refuses, an id given twice (or twice but for case: one
        file on some systems), more than :data:`~kincalc.limits.MAX_ROSTER_STUDENTS`
        students, or none.
    """
    reader = csv.reader(io.StringIO(text.removeprefix("\ufeff"), newline=""), strict=True)
    column, students, seen, end = None, [], {}, 0
    try:
        for row in reader:
            # the record's first line: a quoted field may span lines, and line_num is the last
            line, end = end + 1, reader.line_num
            if not any(c.strip() for c in row):
                continue
            if column is None:
                column = _header(row, file, line)
                continue
            sid = row[column].strip() if column < len(row) else ""
            if "\n" in sid or "\r" in sid:     # (quoted: the rest is on other lines, unquoted)
                raise RosterError(file, line, f"the id runs on over lines {line}-{end} (a "
                                              "quoted cell with a line break): one line each")
            why = id_problem(sid)
            if why is not None:
                raise RosterError(file, line, why)
            first = seen.get(sid.casefold())
            if first is not None:
                raise RosterError(file, line, f"the id {quote(sid)} is already on line "
                                              f"{first.line}" + ("" if first.id == sid else
                                                                 f" (as {quote(first.id)}: "
                                                                 "file names differing only "
                                                                 "in case are one file on "
                                                                 "some systems)"))
            if len(students) == MAX_ROSTER_STUDENTS:
                raise RosterError(file, line, f"more than {MAX_ROSTER_STUDENTS} students "
                                              "(kincalc's limit)")
            seen[sid.casefold()] = student = Student(sid, line)
            students.append(student)
    except csv.Error as exc:
        raise RosterError(file, reader.line_num or None, f"not a CSV file: {exc}") from None
    if not students:
        raise RosterError(file, None, "no students: give a line 'id' and then one id a line")
    return students


def read_roster(path: str) -> list[Student]:
    """The students of the roster file at ``path`` (UTF-8 CSV, at most
    :data:`~kincalc.limits.MAX_FILE_BYTES`), by :func:`parse_roster`.

    Parameters
    ----------
    path : str

    Returns
    -------
    list of Student

    Raises
    ------
    RosterError
        The file cannot be read, is too large, is not UTF-8, or as :func:`parse_roster`.
    """
    from ..conventions.reader import read_text
    return parse_roster(read_text(path, path, "a roster", RosterError), path)


def variant_sheets(robot, student: Student, salt: str, kinds, *, angle_unit=None,
                   robot_refs=(None, None), notes: list | None = None) -> tuple[dict, dict]:
    """A student's sheet and its key, drawn from :func:`variant_seed`.

    Parameters
    ----------
    robot : Robot
    student : Student
    salt : str
        The course's salt.
    kinds : sequence of str
        The exercises, as for :func:`kincalc.homework.quiz.make_sheet`.
    angle_unit : {'deg', 'rad'} or None
        As for ``make_sheet``.
    robot_refs : (str or None, str or None)
        What the sheet's and the key's ``robot:`` say (they may lie in different folders).
    notes : list or None
        As for ``make_sheet``: the kinds left out because none could be drawn.

    Returns
    -------
    (dict, dict)
        The sheet (no answers) and the key (every answer), each a ``make_sheet`` dict with
        ``student: ID`` after its title; they differ only in the answers and ``robot:``.
    """
    from .quiz import make_sheet
    seed = variant_seed(salt, student.id)
    key = make_sheet(robot, seed, kinds, answers=True, angle_unit=angle_unit,
                     robot_ref=robot_refs[1], notes=notes)
    key = {"kincalc-sheet": key.pop("kincalc-sheet"), "title": key.pop("title"),
           "student": student.id, **key}
    sheet = dict(key, robot=robot_refs[0] or robot.name,
                 items=[{k: v for k, v in it.items() if k != "answer"} for it in key["items"]])
    return sheet, key
