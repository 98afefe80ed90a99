"""A sheet's words where people read them: the one rule for text a sheet (a student)
wrote, shown on a terminal, in a CSV cell or in Markdown.

A name, a title or an item id may hold anything YAML can: an escape sequence that
recolours or retitles the terminal, a NUL, a newline that splits a one-line score or a
Markdown page. :func:`printable` folds line breaks to spaces and shows every other
control character as U+FFFD; JSON needs none of this (its encoder escapes them).
"""

from __future__ import annotations

import re

#: line and paragraph breaks (and tabs): folded to one space
_BREAKS = re.compile("[\t\n\v\f\r\x1c-\x1e\x85\u2028\u2029]+")
#: C0 and C1 controls and DEL, and the bidirectional overrides and isolates (which
#: reorder the text around them on screen): each shown as U+FFFD
_CONTROLS = re.compile("[\x00-\x1f\x7f-\x9f\u202a-\u202e\u2066-\u2069]")


def printable(text) -> str:
    """``text`` on one line, with no control character.

    Parameters
    ----------
    text : object
        ``str(text)`` is cleaned.

    Returns
    -------
    str
        Line breaks and tabs (runs of them) as one space; C0 controls, DEL, C1 controls
        and the bidirectional overrides and isolates each as U+FFFD (the replacement
        character), so nothing reaches a terminal as an escape sequence.
    """
    return _CONTROLS.sub("\ufffd", _BREAKS.sub(" ", str(text)))
