"""Limits on what kincalc reads and how much it is asked to compute, in one place.

Every input kincalc reads is untrusted (a robot file from the web, a student's
homework sheet, a pipe of batch records): each read is bounded, each number has
a magnitude limit, and each request (samples, trials) a size limit. Going past a
limit is a one-line :class:`~kincalc.errors.KincalcError` naming the limit, never
a MemoryError or a hang. The README's section "Limits" lists these numbers; a
test checks that it does.

Nothing here imports beyond the standard library.
"""

from __future__ import annotations

import contextlib
import errno
import re

#: the largest magnitude of a number in a robot file, a sheet, a batch record or on the
#: command line (metres, radians, or the user's units before conversion). Products of
#: larger lengths overflow (a robot of 1e160 m compared with one of 1 m looked "the same").
MAX_MAGNITUDE = 1e9

#: the largest robot file, homework sheet or --pose file kincalc reads, in bytes
MAX_FILE_BYTES = 1 << 20

#: the most joints a robot file (YAML or URDF chain) may give: a snake of 32 joints takes
#: up to a minute in ``selftest``, as a seven-joint arm solved numerically does
MAX_JOINTS = 32

#: the most joints ``--symbolic`` expands: the expressions grow about 1.7 times a joint
#: (12 joints take ~10 s, 32 would take days)
MAX_SYMBOLIC_JOINTS = 12

#: the most items one homework sheet may hold
MAX_SHEET_ITEMS = 200

#: the most ik and reach items one sheet may hold for a robot kincalc solves numerically (a
#: seven-joint arm: up to a second or two an item, where a closed form takes milliseconds)
MAX_NUMERIC_ITEMS = 20

#: the most students one ``kincalc quiz --roster`` file may list (each gets a sheet and a
#: key drawn for them, up to a second each)
MAX_ROSTER_STUDENTS = 2000

#: the longest student id of a roster, in characters (it names the student's files)
MAX_STUDENT_ID = 64

#: the longest arithmetic expression a number in a robot file or sheet may be, in characters
MAX_EXPRESSION = 500

#: the longest line of a --batch input, in bytes (a 4x4 pose with an id is ~400)
MAX_RECORD_BYTES = 1 << 16

#: how much of a --batch line longer than MAX_RECORD_BYTES is skipped looking for its
#: newline, in bytes: a line that runs on further (/dev/zero, a binary file) ends the
#: input there
MAX_BATCH_SKIP_BYTES = 1 << 24

#: user text quoted back in a message is cut to this many characters
MAX_QUOTE = 60

#: the most solution sets one ik item of a sheet may list (a six-joint arm has at most 16
#: solutions; each wrong set is analysed for slips, so the count bounds grading time)
MAX_IK_SETS = 16

#: the most samples ``kincalc workspace --samples`` takes (about 200 bytes of memory and
#: 5 microseconds each: 5e6 samples is ~1 GB and ~30 s)
MAX_SAMPLES = 5_000_000

#: the most test orientations ``kincalc workspace --orientations`` takes (each is tested
#: at every reachable test point, in chunks: 1000 take minutes for an arm without
#: closed-form IK)
MAX_ORIENTATIONS = 1000

#: the characters of a robot's or a joint's name (they head tables and label columns)
MAX_NAME = 64

#: the most worker processes ``--batch --jobs`` starts (each is a copy of kincalc, some
#: 25 MB: -j 1000 started 955 processes and 24 GB for one record)
MAX_JOBS = 64

#: the most round trips ``kincalc selftest --trials`` takes (drawn in chunks: memory stays
#: small, but a round trip takes up to a few milliseconds)
MAX_TRIALS = 1_000_000


#: a number as kincalc reads one from text (the command line, a pose file, a URDF, a CSV
#: cell): ASCII digits with an optional sign, point and exponent. Python's float() also
#: takes 1_0 (as 10), other scripts' digits and surrounding spaces: not numbers here
DECIMAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?", re.ASCII)
#: the words of the numbers that are not finite, which are read so that a message can say
#: "not a finite number" rather than "not a number" (every reader refuses them)
_NOT_FINITE = re.compile(r"[+-]?(?:inf|infinity|nan)", re.ASCII | re.IGNORECASE)


def parse_decimal(text: str) -> float:
    """The number ``text`` writes, read strictly (:data:`DECIMAL`, or inf / nan in any case).

    Parameters
    ----------
    text : str
        One number's text, nothing around it.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        ``text`` is not a number so written.
    """
    if DECIMAL.fullmatch(text) or _NOT_FINITE.fullmatch(text):
        return float(text)
    raise ValueError(f"not a decimal number: {text!r}")


#: line and paragraph breaks (and tabs): folded to one space by :func:`printable`
_BREAKS = re.compile("[\t\n\v\f\r\x1c-\x1e\x85\u2028\u2029]+")
#: C0 and C1 controls and DEL, the bidirectional overrides, isolates and marks (which
#: reorder the text around them on screen), and the invisible zero-width space, word
#: joiner and zero-width no-break space (a message would show a name that looks like
#: another; the joiners ZWNJ and ZWJ, which scripts and emoji need, are kept): each shown
#: as U+FFFD by :func:`printable`
_CONTROLS = re.compile("[\x00-\x1f\x7f-\x9f\u200b\u200e\u200f\u202a-\u202e"
                       "\u2060-\u2069\ufeff]")


def printable(text) -> str:
    """``text`` on one line, with no control character: the one rule for words a file
    wrote (a robot's title, a sheet's names and ids) where people read them, on a terminal,
    in a CSV cell or in Markdown. Such words may hold anything YAML can: an escape sequence
    that recolours or retitles the terminal, a NUL, a newline that splits a one-line score
    or a Markdown page (JSON needs none of this: its encoder escapes them).

    Parameters
    ----------
    text : object
        ``str(text)`` is cleaned.

    Returns
    -------
    str
        Line breaks and tabs (runs of them) as one space; C0 controls, DEL, C1 controls,
        the bidirectional overrides, isolates and marks and the zero-width characters each
        as U+FFFD (the replacement character), so nothing reaches a terminal as an escape
        sequence or hides in a name.
    """
    return _CONTROLS.sub("\ufffd", _BREAKS.sub(" ", str(text)))


def one_line(text) -> str:
    """A message on one line: :func:`printable`, its runs of white space as one space, and
    none at its ends (a file name in it may hold an escape sequence)."""
    return " ".join(printable(text).split())


def quote(text, limit: int = MAX_QUOTE) -> str:
    """``repr(text)`` cut to about ``limit`` characters, for echoing a user's value in a
    one-line message.

    Parameters
    ----------
    text : object
        The value; ``str(text)`` is quoted.
    limit : int
        Characters of it kept (:data:`MAX_QUOTE` by default).

    Returns
    -------
    str
        ``repr(str(text))``, or when longer than ``limit`` the repr of its first ``limit``
        characters followed by ``... (<length> characters)``.
    """
    text = str(text)
    if len(text) <= limit:
        return repr(text)
    return f"{text[:limit]!r}... ({len(text)} characters)"


def cut(text, limit: int = MAX_QUOTE) -> str:
    """``text`` cut to ``limit`` characters, for names a message shows unquoted (a joint's
    name in "joint 2 (q2)").

    Parameters
    ----------
    text : object
        The value; ``str(text)`` is cut.
    limit : int
        Characters kept (:data:`MAX_QUOTE` by default).

    Returns
    -------
    str
        ``str(text)``, or its first ``limit`` characters followed by ``...``.
    """
    text = str(text)
    return text if len(text) <= limit else f"{text[:limit]}..."


def read_bounded(path, limit: int = MAX_FILE_BYTES) -> bytes:
    """The bytes of the regular file (or stdin, for ``"-"``) at ``path``, at most
    ``limit`` of them.

    Parameters
    ----------
    path : str or os.PathLike
        The file, or ``"-"`` for standard input.
    limit : int
        The most bytes accepted (:data:`MAX_FILE_BYTES` by default).

    Returns
    -------
    bytes
        The whole content, at most ``limit`` bytes.

    Raises
    ------
    TooLarge
        When the file holds more than ``limit`` bytes (read stops at ``limit + 1``,
        so an endless device such as /dev/zero is refused, not read).
    NoWriter
        A named pipe no process had open for writing (:func:`open_input`).
    OSError
        As ``open`` raises it (missing file, a directory, permission, a name too long).
    ValueError
        As ``open`` raises it for a name with a NUL character.
    """
    import sys
    if path == "-":
        if sys.stdin is None:                       # closed before the program started
            raise OSError(errno.EBADF, "standard input is closed")
        data = sys.stdin.buffer.read(limit + 1)
    else:
        with open_input(path) as fh:
            data = fh.read(limit + 1)
            if not data and _is_pipe(fh):
                raise NoWriter()
    if len(data) > limit:
        raise TooLarge(limit)
    return data


#: the regular files read within :func:`inputs_recorded` (device and inode), or None when
#: nothing records them: a command's outputs refuse them (:mod:`kincalc.outputs`), so a
#: file read along the way (the robot a homework sheet names) is never written over
_inputs_read: set | None = None


@contextlib.contextmanager
def inputs_recorded():
    """Record the regular files :func:`open_input` opens within the block (a command's run:
    the CLI runs each command so; a script using the library records nothing)."""
    global _inputs_read
    saved, _inputs_read = _inputs_read, set()
    try:
        yield
    finally:
        _inputs_read = saved


def was_read(path) -> bool:
    """Whether the file at ``path`` is one read within :func:`inputs_recorded` (the same device
    and inode: a link to it too); False when nothing records or it cannot be stat'ed."""
    import os
    if not _inputs_read:
        return False
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return False
    return (st.st_dev, st.st_ino) in _inputs_read


def open_input(path, buffering: int = -1):
    """``path`` opened for reading, binary, without waiting for a writer.

    ``open`` of a named pipe (FIFO) blocks until some process opens it for writing, for
    ever if none does. Opened non-blocking, then set back to blocking reads, a pipe nobody
    writes to reads as empty at once, while a pipe with a writer (``kincalc fk <(...)``,
    ``/dev/stdin``) is read as before, each read waiting for its data. Regular files are
    unaffected.

    Parameters
    ----------
    path : str or os.PathLike
    buffering : int
        As ``open``'s: -1 (default) buffered, ``read(n)`` gives ``n`` bytes unless the
        file ends first; 0 unbuffered, ``read(n)`` gives what one read returns.

    Returns
    -------
    file object (``rb``)

    Raises
    ------
    OSError, ValueError
        As ``os.open`` raises them (missing file, permission, a NUL in the name, ...); a
        directory opens and raises IsADirectoryError on its first read.
    """
    import os
    nonblock = getattr(os, "O_NONBLOCK", 0)
    fd = os.open(path, os.O_RDONLY | nonblock | getattr(os, "O_BINARY", 0))
    try:
        if _inputs_read is not None:
            import stat
            st = os.fstat(fd)
            if stat.S_ISREG(st.st_mode):
                _inputs_read.add((st.st_dev, st.st_ino))
        if nonblock:
            os.set_blocking(fd, True)
        return open(fd, "rb", buffering=buffering)
    except BaseException:
        os.close(fd)
        raise


def _is_pipe(fh) -> bool:
    import os
    import stat
    return stat.S_ISFIFO(os.fstat(fh.fileno()).st_mode)


class NoWriter(OSError):
    """A named pipe that no process had open for writing: kincalc does not wait for one
    (:func:`open_input`)."""

    def __init__(self):
        super().__init__(errno.ENXIO, "a named pipe that no process writes to (kincalc does "
                                      "not wait for a writer)")


class TooLarge(Exception):
    """A file beyond its size limit (``limit`` bytes)."""

    def __init__(self, limit: int):
        super().__init__(f"larger than {size_text(limit)} (kincalc's limit for this file)")
        self.limit = limit


def size_text(nbytes: int) -> str:
    """A size in words: ``1 MiB``, ``64 KiB`` or ``500 bytes``.

    Parameters
    ----------
    nbytes : int
        The size, in bytes.

    Returns
    -------
    str
        In MiB or KiB when a whole number of them, else in bytes.
    """
    for unit, size in (("MiB", 1 << 20), ("KiB", 1 << 10)):
        if nbytes >= size and nbytes % size == 0:
            return f"{nbytes // size} {unit}"
    return f"{nbytes} bytes"


def os_error_text(exc: OSError) -> str:
    """A short reason for an OSError of opening a user's file (no path in it).

    Parameters
    ----------
    exc : OSError
        The error of opening or reading the file.

    Returns
    -------
    str
        "no such file", "is a directory", "the name is too long for a file", or else the
        error's ``strerror`` (its type's name when it has none).
    """
    if exc.errno == errno.ENAMETOOLONG:
        return "the name is too long for a file"
    if exc.errno == errno.ENOENT:
        return "no such file"
    if exc.errno == errno.EISDIR:
        return "is a directory"
    return exc.strerror or type(exc).__name__
