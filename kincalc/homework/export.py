"""A graded sheet for autograders and for people: Gradescope's and PrairieLearn's results
documents and a Markdown feedback page (``kincalc check --format gradescope|prairielearn``,
``--feedback-dir``).

Pure functions from an :class:`Outcome` (a sheet's :class:`~kincalc.homework.grade.Report`,
or the one-line error that kept it from being graded) to plain dicts and text; the
command line writes them. The fields are the ones the platforms document:

* Gradescope, "Autograder Specifications", Output format
  (https://gradescope-autograders.readthedocs.io/en/latest/specs/): top level ``score``,
  ``execution_time`` (seconds), ``output``, ``output_format``, ``visibility``,
  ``extra_data``, ``tests``; per test ``name``, ``number`` (a string), ``score``,
  ``max_score``, ``status`` (``"passed"``/``"failed"``), ``output``, ``output_format``
  (``"md"``: Markdown). Visibility is one of :data:`VISIBILITIES`.
* PrairieLearn, "External Grading", Grading results
  (https://prairielearn.readthedocs.io/en/latest/externalGrading/): ``gradable``,
  ``score`` in [0, 1], ``message``, ``format_errors`` (a submission that is not gradable),
  ``tests`` with ``name``, ``description``, ``points``, ``max_points``, ``message``,
  ``output``.

An item is right or wrong (no partial credit), so a test scores its points or 0.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass

from .grade import Report
from .slips import fmt
from ..limits import printable

#: Gradescope's visibility settings (its "Controlling Test Case Visibility")
VISIBILITIES = ("visible", "hidden", "after_due_date", "after_published")

#: the first line of every feedback file ``kincalc check --feedback-dir`` writes: only a
#: file that starts with it is ever replaced
FEEDBACK_MARK = "<!-- kincalc check feedback -->"


@dataclass(frozen=True)
class Outcome:
    """What grading one sheet gave.

    ``path`` the sheet as given; ``report`` its :class:`Report`, or None when it could not
    be graded; ``error`` then the one-line message (``file:line: ...``); ``seconds`` the
    time reading and grading took, if measured.
    """

    path: str
    report: Report | None = None
    error: str | None = None
    seconds: float | None = None

    @property
    def status(self) -> int:
        """The exit status this sheet alone gives: 0 all right, 1 some wrong, 2 invalid.

        Returns
        -------
        int
        """
        if self.report is None:
            return 2
        return 0 if self.report.all_correct else 1

    @property
    def student(self) -> str:
        """The sheet's ``student:``, or the file's name without its extension.

        Returns
        -------
        str
        """
        if self.report is not None and self.report.sheet.student:
            return self.report.sheet.student
        return os.path.splitext(os.path.basename(self.path))[0]


def number(x) -> str:
    """``x`` as a score reads: ``2``, ``2.5``, ``1234.5678``.

    Parameters
    ----------
    x : int or float

    Returns
    -------
    str
        Whole numbers without a decimal point, others to 12 significant digits (``%.12g``:
        1234.5678 as it is, 0.1 + 0.2 as 0.3).
    """
    return str(int(x)) if float(x).is_integer() else f"{float(x):.12g}"


def score_line(score: dict) -> str:
    """The score of a report in one line.

    Parameters
    ----------
    score : dict
        :attr:`Report.score` (``points``, ``total``, ``percent``, ``correct``, ``items``).

    Returns
    -------
    str
        ``"score: 2 of 4 points (50 %); 2 of 4 items right"``.
    """
    pts = f"{number(score['points'])} of {number(score['total'])} points " \
          f"({number(score['percent'])} %)"
    return f"score: {pts}; {score['correct']} of {score['items']} items right"


def md(text) -> str:
    """``text`` for a Markdown paragraph, heading or table cell, read as written: on one
    line with no control character (:func:`~kincalc.limits.printable`), the
    characters Markdown would read as markup (``* _ [ ] < > | # ` ~ & \\``)
    backslash-escaped, and a start that would open a list, a quote or a heading (``-``,
    ``+``, ``>``, ``=``, ``1.``, ``1)``) escaped too.

    Parameters
    ----------
    text : object
        ``str(text)`` is escaped.

    Returns
    -------
    str
    """
    out = re.sub(r"([\\`*_\[\]<>|#~&])", r"\\\1", printable(text))
    return re.sub(r"^(\s*)(?:([-+>=])|(\d+)([.)]))",
                  lambda m: m[1] + ("\\" + m[2] if m[2] else m[3] + "\\" + m[4]), out)


def _q(values) -> str:
    return " ".join(fmt(v) for v in values)


def _matrix_block(rows) -> list[str]:
    cells = [[fmt(v) for v in r] for r in rows]
    width = max(len(c) for r in cells for c in r)
    return ["```text", *("  ".join(c.rjust(width) for c in r) for r in cells), "```"]


def _ik_table(d: dict, esc) -> list[str]:
    out = ["| set | q | result | residual | branch / note |", "|---|---|---|---|---|"]
    for s in d.get("sets", []):
        res = s["residual"]
        resid = fmt(res["position"]) + ("" if res["orientation"] is None
                                         else " / " + fmt(res["orientation"]))
        note = s.get("branch", "") if s["status"] == "correct" else ""
        if s.get("note"):
            note = (note + "; " if note else "") + s["note"]
        out.append(f"| {s['set']} | {_q(s['q'])} | {s['status']} | {resid} | {esc(note)} |")
    for m in d.get("missed", []):
        out.append(f"| - | {_q(m['solution_q'])} | missed | | {esc(m['branch'])} |")
    return out


def _item_lines(item: dict, question, markdown: bool) -> list[str]:
    esc = md if markdown else str
    lines = []
    if question:
        lines += [("*Question:* " if markdown else "question: ") + esc(question.strip()), ""]
    lines += [("**Result:** " if markdown else "result: ") + esc(item["message"]), ""]
    bullet = "- " if markdown else ""
    if item["error"] is not None and item["kind"] != "ik":
        lines.append(f"{bullet}error: {fmt(item['error'])}")
    if item["hint"]:
        lines.append(f"{bullet}hint: {esc(item['hint'])}")
    if lines[-1]:
        lines.append("")
    d = item["details"]
    if item["kind"] == "ik" and (d.get("sets") or d.get("missed")):
        lines += [*_ik_table(d, esc), ""]
    elif not item["passed"] and item["kind"] in ("link", "fk", "jacobian") and "expected" in d:
        if "expected_tcv" in d:
            block = _matrix_block([d["expected_tcv"]])
            lines += ["expected tcv:", "", *(block if markdown else block[1:-1]), ""]
        block = _matrix_block(d["expected"])
        lines += ["expected:", "", *(block if markdown else block[1:-1]), ""]
    return lines


def item_markdown(item: dict, question: str | None = None) -> str:
    """One graded item as Markdown: the question, the result (right or wrong, and why),
    the error, the hint, and what was expected (the right matrix of a wrong ``link``, ``fk`` or
    ``jacobian`` answer; for ``ik`` a table of the sets given, each correct, wrong or
    duplicate, and of the solutions missed).

    Parameters
    ----------
    item : dict
        One entry of ``report.to_dict()["items"]``.
    question : str or None
        The item's ``question`` from the sheet, shown first when given.

    Returns
    -------
    str
        Markdown text, lines ending in ``\\n``; the sheet's and kincalc's words are
        escaped (:func:`md`).
    """
    return "\n".join(_item_lines(item, question, True)).rstrip("\n") + "\n"


def item_text(item: dict) -> str:
    """One graded item as plain text: :func:`item_markdown` without the question, the
    markup and the escapes (for a platform that shows the text as it is).

    Parameters
    ----------
    item : dict
        One entry of ``report.to_dict()["items"]``.

    Returns
    -------
    str
        Lines ending in ``\\n``.
    """
    return "\n".join(_item_lines(item, None, False)).rstrip("\n") + "\n"


def _title(item: dict) -> str:
    return f"item {item['id']} ({item['kind']})"


def _questions(report: Report) -> list:
    return [it.question for it in report.sheet.items]


def _heading(doc: dict) -> str:
    parts = [doc["sheet"], doc["title"], doc["student"]]
    return " — ".join(md(p) for p in parts if p)


def feedback_markdown(outcome: Outcome) -> str:
    """A sheet's feedback page (``--feedback-dir``): :data:`FEEDBACK_MARK`, a heading (the
    sheet, its title and student), the score, and every item by :func:`item_markdown`;
    or, for a sheet that could not be graded, the error.

    Parameters
    ----------
    outcome : Outcome

    Returns
    -------
    str
        Markdown text, lines ending in ``\\n``.
    """
    if outcome.report is None:
        return "\n".join([FEEDBACK_MARK, f"# {md(outcome.path)}", "",
                          "**This sheet could not be graded:**", "",
                          f"    {outcome.error}", ""])
    doc = outcome.report.to_dict()
    lines = [FEEDBACK_MARK, f"# {_heading(doc)}", "", f"**{score_line(doc['score'])}**", ""]
    for item, question in zip(doc["items"], _questions(outcome.report)):
        mark = "right" if item["passed"] else "wrong"
        lines += [f"## {md(_title(item))}: {mark}", "", item_markdown(item, question)]
    return "\n".join(lines).rstrip("\n") + "\n"


def gradescope_results(outcome: Outcome, visibility: str | None = None) -> dict:
    """Gradescope's ``results.json`` for one sheet.

    Parameters
    ----------
    outcome : Outcome
        A graded sheet: one test per item (``name`` "item ID (kind)", ``number`` its
        position from "1", ``score`` its points when right else 0, ``max_score`` its
        points, ``status``, ``output`` by :func:`item_markdown`, ``output_format`` "md"),
        ``score`` their sum, ``output`` the sheet and score line, ``extra_data`` kincalc's
        own JSON report (``kincalc check --json``). A sheet that could not be graded:
        ``score`` 0, no tests, ``output`` the error, ``extra_data`` ``{"error": ...}``.
    visibility : str or None
        One of :data:`VISIBILITIES`, set at the top level (the tests inherit it); None
        leaves it out (Gradescope's default, visible).

    Returns
    -------
    dict
        Plain JSON types.

    Raises
    ------
    ValueError
        ``visibility`` is not one of :data:`VISIBILITIES`.
    """
    if visibility is not None and visibility not in VISIBILITIES:
        raise ValueError(f"visibility must be one of {', '.join(VISIBILITIES)}")
    out: dict = {"score": 0}
    if outcome.seconds is not None:
        out["execution_time"] = round(outcome.seconds, 3)
    if outcome.report is None:
        out.update(output=f"**This sheet could not be graded:**\n\n    {outcome.error}\n",
                   output_format="md", tests=[], extra_data={"error": outcome.error})
    else:
        doc = outcome.report.to_dict()
        tests = [{"name": _title(item), "number": str(k),
                  "score": item["points"] if item["passed"] else 0,
                  "max_score": item["points"],
                  "status": "passed" if item["passed"] else "failed",
                  "output": item_markdown(item, question), "output_format": "md"}
                 for k, (item, question) in enumerate(zip(doc["items"],
                                                          _questions(outcome.report)), 1)]
        out.update(score=sum(t["score"] for t in tests),
                   output=f"{_heading(doc)}\n\n**{score_line(doc['score'])}**\n",
                   output_format="md", tests=tests, extra_data=doc)
    if visibility is not None:
        out["visibility"] = visibility
    return out


def prairielearn_results(outcome: Outcome) -> dict:
    """PrairieLearn's external-grader ``results.json`` for one sheet.

    Parameters
    ----------
    outcome : Outcome
        A graded sheet: ``gradable`` true, ``score`` points / total in [0, 1] (1 for a
        sheet worth 0 points), ``message`` the score line, one test per item (``name``
        "item ID (kind)", ``description`` the item's question or its kind and line,
        ``points`` its points when right else 0, ``max_points``, ``message`` the result line,
        ``output`` by :func:`item_text`), and ``report``, kincalc's own JSON report.
        A sheet that could not be graded: ``gradable`` false, ``message`` and
        ``format_errors`` the error, no score (as PrairieLearn asks).

    Returns
    -------
    dict
        Plain JSON types.
    """
    if outcome.report is None:
        return {"gradable": False, "message": f"This sheet could not be graded: "
                                              f"{outcome.error}",
                "format_errors": [outcome.error], "tests": []}
    doc = outcome.report.to_dict()
    score = doc["score"]
    tests = []
    for item, question in zip(doc["items"], _questions(outcome.report)):
        where = f"a {item['kind']} item" + ("" if item["line"] is None
                                            else f", line {item['line']} of the sheet")
        tests.append({"name": _title(item), "description": (question or where).strip(),
                      "points": item["points"] if item["passed"] else 0,
                      "max_points": item["points"],
                      "message": item["message"],
                      "output": item_text(item)})
    total = sum(t["max_points"] for t in tests)
    got = sum(t["points"] for t in tests)
    return {"gradable": True, "score": got / total if total else 1.0,
            "message": score_line(score), "tests": tests, "report": doc}
