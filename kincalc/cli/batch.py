"""``--batch FILE|-``: many inputs, one output record per input record, in order.

What a record is
----------------
The input is read as bytes, in pieces of at most :data:`READ_BYTES`, and cut into lines
at each newline (``\\n``; a CR before it is ignored, and a UTF-8 byte order mark at the
start of the input is dropped). A line holding nothing but ASCII whitespace (spaces,
tabs, a CR) is blank and skipped. Every other line is one *input record*, except the
header line of CSV, and gets exactly one output record: the answer, or
``{"index": i, "error": "record i+1: ..."}`` when it cannot be used. A line longer than
:data:`~kincalc.limits.MAX_RECORD_BYTES` is a record whatever it holds (its error); the
reader skips to its newline in pieces, at most
:data:`~kincalc.limits.MAX_BATCH_SKIP_BYTES` of it: a line that runs on further
(``/dev/zero``) ends the input there, after its error record, with one line on stderr.

Which format (``--input-format``, default ``auto``): ``jsonl`` or ``csv`` as given;
``auto`` takes a name ending in ``.jsonl`` or ``.ndjson`` as JSON lines and one ending
in ``.csv`` as CSV; for other names and stdin, the input is CSV when its first non-blank
line is a CSV header (comma-separated column names, each a letter or ``_`` followed by
letters, digits, ``_``, ``.`` or ``-``, and not a JSON word such as ``null``), else JSON
lines. So a JSON lines input whose first record is ``42``, ``[]`` or ``null`` is still
read as JSON lines.

A record holds a pose in any of the forms of PRODUCT.md:

* JSON: ``{"xyz": [x, y, z], "rpy": [r, p, y]}``, with ``euler_zyz``,
  ``euler_xyz``, ``quat``, ``axis_angle``, ``matrix``, ``approach`` or ``tcv``
  instead of ``rpy``; or ``{"T": [[...], ...]}`` (4x4); or ``{"q": [...]}``
  (the pose FK gives for these joints);
* CSV: columns ``x, y, z`` with ``roll, pitch, yaw`` or ``qw, qx, qy, qz`` or
  ``ax, ay, az`` (approach), or one column per joint named as in the robot file
  (plain comma-separated decimal numbers, no quoting).

An ``id`` field of a JSON record (a string, a number, true, false or null) is echoed in
its output record. Records are counted from 1 in messages ("record 3") and indexed from
0 in ``index``. Every number must be a finite JSON number or decimal CSV cell (not a
boolean, not NaN or Infinity) within :data:`~kincalc.limits.MAX_MAGNITUDE`; a field
given twice is an error.

Values are in the command's units (``--deg/--rad``, ``--unit``). A record that cannot be
read becomes its error record and the run goes on; the exit status then says so (2).
"""

from __future__ import annotations

import math
import sys

from ..limits import MAX_BATCH_SKIP_BYTES, MAX_MAGNITUDE, MAX_RECORD_BYTES, quote, size_text

#: pose keys of a JSON record and the number of values each takes
POSE_KEYS = {"xyz": 3, "rpy": 3, "euler_zyz": 3, "euler_xyz": 3, "quat": 4, "axis_angle": 4,
             "matrix": 9, "approach": 3, "tcv": 6}
#: CSV column groups and the pose key they fill
CSV_GROUPS = {("x", "y", "z"): "xyz", ("roll", "pitch", "yaw"): "rpy",
              ("qw", "qx", "qy", "qz"): "quat", ("ax", "ay", "az"): "approach"}
#: the input formats of --input-format
INPUT_FORMATS = ("auto", "jsonl", "csv")
#: file name endings that decide the input format when --input-format is auto
FORMAT_OF_SUFFIX = {".jsonl": "jsonl", ".ndjson": "jsonl", ".csv": "csv"}
#: the most bytes one read of the input takes
READ_BYTES = 1 << 16
#: the first line of a JSON lines input that would otherwise pass for a CSV header
_JSON_WORDS = {"null", "true", "false", "NaN", "Infinity"}
_BOM = b"\xef\xbb\xbf"


class RecordError(ValueError):
    """A batch record that cannot be used; the message names what is wrong."""


# --- records: one line of bytes -> pose keywords, or the reason it cannot be used ---------

def _parse(header, robot, start: int, lines) -> list:
    """``[(index, keywords or None, error or None)]`` of one chunk of lines (bytes, or
    None for a line over the length limit), the first being record ``start``. ``header``
    is None for JSON lines, the column names for CSV, or the reason the CSV header cannot
    be used."""
    out = []
    if header is None:
        for i, line in enumerate(lines, start):
            try:
                out.append((i, _json_record(_text(line)), None))
            except RecordError as exc:
                out.append((i, None, f"record {i + 1}: {exc}"))
        return out
    if isinstance(header, str):
        reason, layout = header, None
    else:
        layout, reason = _csv_layout(header, robot)
    for i, line in enumerate(lines, start):
        try:
            if layout is None:
                raise RecordError(reason)
            out.append((i, _csv_record(header, layout, _text(line)), None))
        except RecordError as exc:
            out.append((i, None, f"record {i + 1}: {exc}"))
    return out


def _text(line) -> str:
    """A record's line as text, without the whitespace around it."""
    if line is None:
        raise RecordError(f"longer than {size_text(MAX_RECORD_BYTES)}, kincalc's limit for a "
                          "--batch line")
    if b"\0" in line:
        raise RecordError("holds a NUL byte, so it is not a line of text")
    line = line.strip()
    try:
        return line.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise RecordError(f"not UTF-8 text (byte {line[exc.start]:#04x} at position "
                          f"{exc.start + 1})") from None


def _json_record(text: str) -> dict:
    """The pose keywords of one JSON lines record."""
    global _DECODER
    if _DECODER is None:
        import json
        _DECODER = (json.JSONDecoder(parse_constant=_not_finite),
                    json.JSONDecoder(parse_constant=_not_finite, object_pairs_hook=_unique_fields))
    if text.startswith("\ufeff"):
        raise RecordError("starts with a byte order mark (only the input's first line may)")
    try:
        rec = _DECODER[0].decode(text)
        # a field given twice: the decoder keeps the last; every key is followed by a
        # colon, so a record with no more colons than keys has none twice
        if type(rec) is dict and text.count(":") > len(rec):
            _DECODER[1].decode(text)
    except RecursionError:
        raise RecordError("not JSON (nested too deeply)") from None
    except RecordError:
        raise
    except ValueError as exc:
        # a JSONDecodeError has .msg; int() refusing a number of thousands of digits not
        raise RecordError(f"not JSON ({getattr(exc, 'msg', 'a number too long to read')})") \
            from None
    if type(rec) is not dict:
        raise RecordError(f"expected a JSON object ({{...}}), not {_json_kind(rec)}")
    return _pose_keywords(rec)


_DECODER = None


def _not_finite(word):
    """The JSON decoders' hook for NaN, Infinity and -Infinity (not JSON, but Python's
    json module reads them)."""
    raise RecordError(f"{word} is not a finite number (JSON has no NaN or Infinity)")


def _unique_fields(pairs) -> dict:
    out = dict(pairs)
    if len(out) != len(pairs):
        seen = set()
        twice = next(k for k, _ in pairs if k in seen or seen.add(k))
        raise RecordError(f"field {quote(twice)} is given twice")
    return out


def _json_kind(value) -> str:
    """How a JSON value reads in a message: null, true, an array, a string, ..."""
    if value is None or isinstance(value, bool):
        return "null" if value is None else str(value).lower()
    return {list: "an array", dict: "an object", str: "a string"}.get(type(value), "a number")


def _numbers(value, count: int, key: str) -> tuple:
    """The floats of the JSON array of field ``key``: ``count`` numbers (any number for
    0), each finite and within MAX_MAGNITUDE."""
    if type(value) is not list or (count and len(value) != count):
        raise RecordError(f"{key}: expected {count or 'a list of'} numbers")
    if not _NUMBER_TYPES.issuperset(map(type, value)):     # true, "1", [...], null
        bad = next(v for v in value if type(v) not in _NUMBER_TYPES)
        raise RecordError(f"{key}: {_json_kind(bad)} is not a number")
    try:
        out = tuple(map(float, value))
    except OverflowError:                               # an integer beyond any float
        k = next(k for k, v in enumerate(value) if abs(v) > MAX_MAGNITUDE)
        raise RecordError(f"{key}: value {k + 1} is beyond {_LIMIT}, {_WHY}") from None
    if not _within_range(out):
        _range_error(out, lambda k: f"{key}: value {k + 1}")
    return out


def _within_range(values) -> bool:
    """Whether every value is within MAX_MAGNITUDE (so finite: an overflow to infinity
    is caught, and no value is NaN, which neither a JSON number nor a decimal CSV cell can
    be; the JSON words NaN and Infinity are refused by the parser). Two C calls: this runs
    for every array of every record."""
    return not values or (min(values) >= -MAX_MAGNITUDE and max(values) <= MAX_MAGNITUDE)


def _range_error(values, name):
    """Raise the RecordError for the first value that is not finite or too large;
    ``name(k)`` names value k in the message."""
    for k, x in enumerate(values):
        if not math.isfinite(x):
            raise RecordError(f"{name(k)} is not a finite number")
        if abs(x) > MAX_MAGNITUDE:
            raise RecordError(f"{name(k)} ({x:.6g}) is beyond {_LIMIT}, {_WHY}")


_NUMBER_TYPES = frozenset({int, float})
#: MAX_MAGNITUDE as the messages write it (1e9), and why it is there
_LIMIT = f"{MAX_MAGNITUDE:.0e}".replace("e+0", "e").replace("e+", "e")
_WHY = "kincalc's limit for the magnitude of a number"
#: the fields of a JSON record, with the count of numbers of each (0: any)
_FIELDS = {**POSE_KEYS, "T": 0, "q": 0}
_KNOWN = frozenset(_FIELDS) | {"id"}


def _pose_keywords(rec: dict) -> dict:
    if not _KNOWN.issuperset(rec):
        unknown = next(k for k in rec if k not in _FIELDS and k != "id")
        raise RecordError(f"unknown field {quote(unknown)} (pose fields: "
                          f"{', '.join(_FIELDS)})")
    out = {}
    for key, value in rec.items():
        if key == "id":
            if isinstance(value, (list, dict)) or (type(value) is float and
                                                    not math.isfinite(value)):
                raise RecordError("id must be a string, a finite number, true, false or null")
        elif key == "T":
            if type(value) is list and value and type(value[0]) is list:
                value = [x for row in value for x in (row if type(row) is list else [row])]
            value = _numbers(value, 0, "T")
        else:
            value = _numbers(value, _FIELDS[key], key)
        out[key] = value
    if len(out) == ("id" in out):
        raise RecordError("no pose (give xyz and an orientation, T or q)")
    return out


def _csv_layout(header, robot):
    """``(layout, None)``: the pose keys a CSV record fills and the column of each of their
    values, ``[(key, [column, ...])]``; or ``(None, reason)`` when the header cannot be
    used (a column twice, or one that is not a pose or joint column)."""
    seen = set()
    for h in header:
        if h in seen:
            return None, f"column {quote(h)} appears twice in the CSV header"
        seen.add(h)
    where = {h: k for k, h in enumerate(header)}
    layout, used = [], set()
    for cols, key in CSV_GROUPS.items():
        if all(c in where for c in cols):
            layout.append((key, [where[c] for c in cols]))
            used |= set(cols)
    names = [j.name for j in robot.joints]
    if all(n in where for n in names):
        layout.append(("q", [where[n] for n in names]))
        used |= set(names)
    extra = [h for h in header if h not in used]
    if extra:
        return None, (f"unknown column {quote(extra[0])} (columns: x,y,z with roll,pitch,yaw "
                      f"or qw,qx,qy,qz or ax,ay,az; or the joints {','.join(names)})")
    return layout, None


def _csv_patterns():
    import re
    # a line of plain numbers (digits, signs, points, exponents) needs no cell-by-cell look
    plain = re.compile(r"[0-9eE+\-.,\s]*", re.ASCII)
    number = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?", re.ASCII)
    header = re.compile(r"[A-Za-z_][\w.\-]*(?:[ \t]*,[ \t]*[A-Za-z_][\w.\-]*)*", re.ASCII)
    return plain, number, header


_PLAIN = _NUMBER = _HEADER = None


def _csv_record(header, layout, text: str) -> dict:
    """The pose keywords of one CSV line: decimal numbers, one per column."""
    global _PLAIN, _NUMBER
    if _PLAIN is None:
        _PLAIN, _NUMBER, _ = _csv_patterns()
    cells = text.split(",")
    if len(cells) != len(header):
        raise RecordError(f"{len(cells)} values for {len(header)} columns")
    values = None
    if _PLAIN.fullmatch(text):
        try:
            values = list(map(float, cells))
        except ValueError:
            pass
    if values is None:                  # find the cell that is not a number, and say so
        for h, c in zip(header, cells):
            c = c.strip()
            if not _NUMBER.fullmatch(c):
                raise RecordError(f"column {quote(h)}: " + (
                    "empty cell" if not c else f"{quote(c)} is not a number"))
        values = list(map(float, cells))
    if not _within_range(values):
        _range_error(values, lambda k: f"column {quote(header[k])}")
    return {key: tuple(values[k] for k in cols) for key, cols in layout}


def _read_header(line, forced: bool):
    """The column names of a CSV header line. With ``forced`` (--input-format csv, or a
    name ending in .csv), the reason when the line cannot be read; otherwise None when it
    is not a header (then the input is JSON lines)."""
    global _HEADER
    if _HEADER is None:
        _, _, _HEADER = _csv_patterns()
    try:
        text = _text(line)
    except RecordError as exc:
        return f"the CSV header (the first line) cannot be used: {exc}" if forced else None
    if not forced and (text in _JSON_WORDS or not _HEADER.fullmatch(text)):
        return None
    return tuple(c.strip() for c in text.split(","))


def _csv_cell(value):
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    return value


# --- chunked, vectorised batch runs of fk, jacobian, ik and reach ------------------------
#
# The input is read in pieces of at most READ_BYTES and cut into chunks of CHUNK_LINES
# records; each chunk is parsed, solved through the vectorised core and formatted by the
# pure function process_chunk, in this process or, with --jobs N, in N worker processes
# (at most 2 N chunks in flight, so memory stays constant whatever the input's size; the
# output keeps the input's order). All reading happens in this process's only thread:
# the workers are forked with no other thread alive (a reader thread holding stdin's
# lock while the pool forked deadlocked the workers, issue 14).

CHUNK_LINES = 2048
#: reach analyses pose by pose (milliseconds each): smaller chunks, so that answers and
#: the progress bar come at once and --jobs has work to share
REACH_CHUNK_LINES = 64
#: the per-pose fields of a reach record, in CSV column order
REACH_FIELDS = ["index", "reachable", "verdict", "distance", "solutions",
                "solutions_within_limits", "reason", "error"]
#: pose forms solved in one vectorised step (others go through build_target per record)
_FAST_FORMS = {frozenset({"xyz", "rpy"}), frozenset({"xyz", "euler_zyz"}),
               frozenset({"xyz", "euler_xyz"}), frozenset({"xyz", "quat"}),
               frozenset({"T"}), frozenset({"q"})}


def run_command(kind: str, robot, units, src: str, fmt: str, jobs: int, *, given=(),
                frame: str = "base", refused: dict | None = None,
                input_format: str = "auto"):
    """The --batch branch of a command: refuse the command's own inputs (``given``, the
    values of its joint or pose arguments) and the options in ``refused``, run, and leave
    with the batch's exit status."""
    import typer

    from ..errors import UsageError
    if any(v is not None and len(v) for v in given):
        raise UsageError("--batch reads its input from a file; do not give "
                         f"{'pose options' if kind in ('ik', 'reach') else 'joint values'} too")
    for option, value in (refused or {}).items():
        if value:
            raise UsageError(f"{option} does not combine with --batch")
    raise typer.Exit(run(kind, robot, units, src, fmt, jobs, frame, input_format))


def run(kind: str, robot, units, src: str, fmt: str, jobs: int = 1, frame: str = "base",
        input_format: str = "auto") -> int:
    """Answer every record of ``src`` with ``kind`` ('fk', 'jacobian', 'ik' or 'reach');
    write the output records to stdout; return the exit status (2 if any record was bad,
    1 if all were good but some pose had no solution, else 0)."""
    import contextlib
    from functools import partial

    from ..errors import InputError, UsageError
    if fmt not in ("jsonl", "csv"):
        raise UsageError(f"--format must be jsonl or csv, not {fmt!r}")
    if input_format not in INPUT_FORMATS:
        raise UsageError(f"--input-format must be {', '.join(INPUT_FORMATS[:-1])} or "
                         f"{INPUT_FORMATS[-1]}, not {quote(input_format)}")
    if jobs < 1:
        raise UsageError(f"--jobs must be at least 1, not {jobs}")
    source = _Source(src)
    bad = no = False
    pool = None
    try:
        header, chunks = _chunked(source, REACH_CHUNK_LINES if kind == "reach" else CHUNK_LINES,
                                  input_format)
        work = partial(process_chunk, kind, robot, units, header, fmt, frame)
        # the workers start before any other thread of this process does (the progress
        # bar's): a fork copies a lock another thread holds, locked for good
        pool = _pool(jobs) if jobs > 1 else None
        with _Output() as out, _progress(source) as advance, \
                contextlib.closing(_ordered_map(work, chunks, pool, jobs)) as results:
            if fmt == "csv":
                out.write(_csv_header(kind, robot))
            for text, b, n in results:
                out.write(text)
                bad |= b
                no |= n
                advance(source.position)
    finally:
        if pool is not None:
            # on Ctrl-C or a closed stdout: drop what has not started, let the rest finish
            pool.shutdown(wait=True, cancel_futures=True)
        source.close()
    if source.stopped is not None:
        raise InputError(f"--batch {_shown(src)}: record {source.stopped} runs on for more than "
                         f"{size_text(MAX_BATCH_SKIP_BYTES)} without a newline (not a file of "
                         "lines?); reading stopped there")
    return 2 if bad else 1 if no else 0


def _shown(name: str) -> str:
    """A file name as a message shows it: as given, or quoted and cut when it holds
    characters that would break the line (or is very long)."""
    return name if name.isprintable() and len(name) <= 1000 else quote(name, 200)


class _Source:
    """The bytes of a --batch input (a file, or stdin for '-'), read in pieces of at most
    READ_BYTES, counting the bytes read (for the progress bar). ``ready()`` says whether a
    read would return at once: always for a regular file, and from a pipe or terminal
    when something has arrived."""

    def __init__(self, src: str):
        import os
        import stat

        from ..errors import InputError
        from ..limits import os_error_text
        self.src, self.position, self.size, self.stopped = src, 0, None, None
        self._file = self._poll = None
        fd = None
        try:
            if src == "-":
                if sys.stdin is None:
                    raise InputError("--batch -: there is no standard input")
                try:
                    fd = sys.stdin.fileno()
                except (AttributeError, OSError, ValueError):   # an in-memory stdin (tests)
                    buffer = getattr(sys.stdin, "buffer", None)
                    if buffer is not None:
                        self._read = getattr(buffer, "read1", buffer.read)
                    else:                                       # text only: as UTF-8
                        self._read = lambda n: sys.stdin.read(n).encode("utf-8",
                                                                        "surrogateescape")
                else:
                    self._read = lambda n: os.read(fd, n)
            else:
                self._file = open(src, "rb", buffering=0)
                fd = self._file.fileno()
                self._read = self._file.read
            mode = None if fd is None else os.fstat(fd).st_mode
        except OSError as exc:
            self.close()
            raise InputError(f"--batch {_shown(src)}: cannot read ({os_error_text(exc)})") \
                from None
        if mode is not None and not stat.S_ISREG(mode):
            import select
            self._poll = select.poll()
            self._poll.register(fd, select.POLLIN)
        elif mode is not None and self._file is not None:
            self.size = os.fstat(fd).st_size
        self._fd = fd

    def read(self) -> bytes:
        """Up to READ_BYTES bytes (at least one, waiting for them), b"" at the end."""
        from ..errors import InputError
        from ..limits import os_error_text
        while True:
            try:
                data = self._read(READ_BYTES)
            except BlockingIOError:         # a non-blocking stdin: wait for it
                self._poll.poll()
                continue
            except OSError as exc:
                raise InputError(f"--batch {_shown(self.src)}: cannot read "
                                 f"({os_error_text(exc)})") from None
            self.position += len(data or b"")
            return data or b""

    def ready(self) -> bool:
        return self._poll is None or bool(self._poll.poll(0))

    def close(self) -> None:
        if self._file is not None:
            self._file.close()


def _blocks(source):
    """The records of ``source`` as they are read: for each read that completes some,
    ``(lines, more)`` with the lines (bytes, without the newline; None for a line longer
    than MAX_RECORD_BYTES) and whether more input is ready without waiting. Blank lines are
    left out. Memory stays within 2 READ_BYTES + MAX_RECORD_BYTES: an over-long line is
    skipped in pieces, at most MAX_BATCH_SKIP_BYTES of it (``source.stopped`` is then set
    and the input ends)."""
    held, held_bytes = [], 0        # the start of a line whose newline has not come yet
    skipped = None                  # inside an over-long line: the bytes skipped so far
    start = True                    # a byte order mark may still be ahead
    while True:
        data = source.read()
        if not data:
            break
        if skipped is not None:
            nl = data.find(b"\n")
            if nl < 0:
                skipped += len(data)
                if skipped > MAX_BATCH_SKIP_BYTES:
                    source.stopped = True
                    return
                continue
            data, skipped = data[nl + 1:], None
        if start:
            data = b"".join(held) + data
            held, held_bytes = [], 0
            if len(data) < len(_BOM) and _BOM.startswith(data):
                held, held_bytes = [data], len(data)    # (a pipe giving the mark bytewise)
                continue
            start = False
            if data.startswith(_BOM):
                data = data[len(_BOM):]
        if b"\n" not in data:             # more of one line: kept, not copied (a slow pipe)
            held.append(data)
            held_bytes += len(data)
            if held_bytes > MAX_RECORD_BYTES:
                skipped, held, held_bytes = held_bytes, [], 0
                yield [None], source.ready()
            continue
        if held:
            data = b"".join(held) + data
            held, held_bytes = [], 0
        parts = data.split(b"\n")
        last = parts.pop()
        if len(data) <= MAX_RECORD_BYTES:       # no line too long: the common case
            lines = [p for p in parts if p.strip()]
        else:                                   # an over-long line is a record, blank or not
            lines = [p if len(p) <= MAX_RECORD_BYTES else None for p in parts
                     if len(p) > MAX_RECORD_BYTES or p.strip()]
        if len(last) > MAX_RECORD_BYTES:
            lines.append(None)
            skipped = len(last)
        elif last:
            held, held_bytes = [last], len(last)
        if lines:
            yield lines, source.ready()
    tail = b"".join(held)
    if tail.strip():
        yield [tail], False


def _chunked(source, size: int = 0, input_format: str = "auto"):
    """``(header, chunks)``: the header (None for JSON lines, the CSV column names, or the
    reason a CSV header cannot be used) and an iterator of ``((first index, lines),
    flush)``, at most ``size`` records a chunk (default CHUNK_LINES). ``flush`` says that
    nothing more has arrived: from a pipe a chunk is what has arrived, and its answers (and
    those of the chunks before it) should be written before waiting for more, so that a
    producer writing one pose at a time gets each answer at once."""
    import itertools
    size = size or CHUNK_LINES
    blocks = _blocks(source)
    fmt = input_format
    if fmt == "auto":
        name = source.src.lower()
        fmt = next((f for s, f in FORMAT_OF_SUFFIX.items() if name.endswith(s)), "auto")
    header, first = None, []
    if fmt != "jsonl":
        first = list(itertools.islice(blocks, 1))
        if first:
            (lines, more), = first
            header = _read_header(lines[0], fmt == "csv")
            if header is not None:
                first = [(lines[1:], more)]

    def chunks():
        index, block = 0, []
        try:
            for lines, more in itertools.chain(first, blocks):
                block += lines
                while len(block) >= size or (block and not more):
                    chunk, block = block[:size], block[size:]
                    yield (index, chunk), not (more or block)
                    index += len(chunk)
            if block:
                yield (index, block), True
                index += len(block)
            if source.stopped:
                source.stopped = index          # the over-long record is the last one
        finally:
            source.close()
    return header, chunks()


def _ordered_map(fn, items, pool, jobs: int = 1):
    """``fn(item)`` for the ``(item, flush)`` pairs of ``items``, in order: here, or over
    the ``jobs`` worker processes of ``pool`` with at most 2 jobs items in flight. After an
    item with ``flush``, every result so far is given before the next item is asked for
    (asking may wait for input)."""
    if pool is None:
        for item, _ in items:
            yield fn(item)
        return
    from collections import deque
    window = deque()
    for item, flush in items:
        window.append(_submit(pool, fn, item))
        while window and (flush or len(window) >= 2 * jobs):
            yield window.popleft().result()
    while window:
        yield window.popleft().result()


def _pool(jobs: int):
    """A pool of ``jobs`` worker processes, started now, that leave Ctrl-C to this
    process."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    # fork on Linux: this process reads its input in its only thread, so nothing is
    # locked when the workers are forked, and they start in milliseconds (forkserver and
    # spawn cost 0.5 s more a run: 1.27 s against 0.71 s for 3 records, 2.36 s against
    # 1.43 s for 5,000). Elsewhere the platform's default (macOS: spawn, since system
    # libraries there do not survive a fork)
    method = "fork" if sys.platform.startswith("linux") else None
    pool = ProcessPoolExecutor(max_workers=jobs, initializer=_worker_start,
                               mp_context=multiprocessing.get_context(method))
    _submit(pool, int, 0).result()      # a fork pool starts every worker at its first task
    return pool


def _submit(pool, fn, item):
    """``pool.submit(fn, item)`` with SIGINT blocked, so that a worker it forks is born
    with SIGINT blocked (until :func:`_worker_start` ignores it)."""
    import signal
    if not hasattr(signal, "pthread_sigmask"):
        return pool.submit(fn, item)
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        return pool.submit(fn, item)
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _worker_start():
    """In a worker: ignore Ctrl-C (the parent stops the run and writes only whole lines;
    a worker's KeyboardInterrupt traceback was noise), and exit when the parent is gone
    (killed, so never shutting the pool down)."""
    import os
    import signal
    import threading
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    threading.Thread(target=_exit_with_parent, args=(os.getppid(),), daemon=True).start()


def _exit_with_parent(parent: int) -> None:
    import os
    import time
    while os.getppid() == parent:
        time.sleep(1.0)
    os._exit(1)


class _Output:
    """stdout for whole chunks of output lines: a Ctrl-C while a chunk is being written
    takes effect when it is written, so the output never ends inside a line.

    A real stdout is written with ``os.write`` on its descriptor, looping over partial
    writes: CPython's buffered stdout (3.11) dropped the rest of a large write that a
    signal interrupted while the pipe was full (131072 of 2000000 bytes arrived), even
    with a handler that returns."""

    def __enter__(self):
        import signal
        self._writing = self._pending = False
        self._old = self._fd = None
        try:
            sys.stdout.flush()
            self._fd = sys.stdout.fileno()
            self._encoding = sys.stdout.encoding or "utf-8"
        except (AttributeError, OSError, ValueError):   # a test's in-memory stdout
            self._fd = None
        try:
            # (a run started with SIGINT ignored, as a background job, keeps ignoring it)
            if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
                self._old = signal.signal(signal.SIGINT, self._interrupt)
        except ValueError:                      # not the main thread: leave signals alone
            pass
        return self

    def _interrupt(self, signum, frame):
        if self._writing:
            self._pending = True
        else:
            raise KeyboardInterrupt

    def write(self, text: str) -> None:
        import os
        self._writing = True
        try:
            if self._fd is None:
                sys.stdout.write(text)
                sys.stdout.flush()
            else:
                view = memoryview(text.encode(self._encoding, "backslashreplace"))
                while view:
                    view = view[os.write(self._fd, view):]
        except BrokenPipeError:
            if self._pending:                   # the reader went with the same Ctrl-C
                raise KeyboardInterrupt from None
            raise
        finally:
            self._writing = False
        if self._pending:
            raise KeyboardInterrupt

    def __exit__(self, *exc):
        if self._old is not None:
            import signal
            signal.signal(signal.SIGINT, self._old)
        return False


class _progress:
    """A rich progress bar on stderr when stderr is a terminal and the input a file."""

    def __init__(self, source):
        self.source, self.bar = source, None

    def __enter__(self):
        if self.source.size and sys.stderr.isatty():
            from rich.console import Console
            from rich.progress import (BarColumn, DownloadColumn, Progress, TextColumn,
                                       TimeRemainingColumn)
            self.bar = Progress(TextColumn("{task.description}"), BarColumn(), DownloadColumn(),
                                TimeRemainingColumn(), console=Console(stderr=True),
                                transient=True)
            self.bar.start()
            self.task = self.bar.add_task(self.source.src, total=self.source.size)
            return lambda pos: self.bar.update(self.task, completed=pos)
        return lambda pos: None

    def __exit__(self, *exc):
        if self.bar is not None:
            self.bar.stop()
        return False


def _csv_header(kind, robot) -> str:
    names = [j.name for j in robot.joints]
    if kind == "fk":
        cols = ["index", "id", "x", "y", "z", "roll", "pitch", "yaw", "within_limits", "error"]
    elif kind == "jacobian":
        cols = ["index", "id"] + [f"J{r}_{c}" for r in ("vx", "vy", "vz", "wx", "wy", "wz")
                                  for c in names] + ["rank", "manipulability", "singular", "error"]
    elif kind == "reach":
        cols = REACH_FIELDS
    else:
        cols = ["index", "id", "solution", "branch"] + names + ["within_limits", "error"]
    return ",".join(cols) + "\n"


def process_chunk(kind, robot, units, header, fmt, frame, item) -> tuple[str, bool, bool]:
    """Parse, solve and format one chunk ``item = (first index, lines)``; returns
    ``(text, any record bad, any pose without a solution)``. Pure: safe to run in a
    worker process. Numbers that come out NaN or infinite make their record an error
    (each chunk function checks its results), so floating-point warnings are not shown."""
    from functools import partial

    import numpy as np
    start, lines = item
    parsed = _parse(header, robot, start, lines)
    solve = {"fk": _fk_chunk, "jacobian": _jacobian_chunk, "reach": _reach_chunk,
             "ik": partial(_ik_chunk, fmt=fmt)}[kind]
    with np.errstate(all="ignore"):
        records, no = solve(robot, units, parsed, frame)
    bad = any("error" in r for r in records)
    if fmt == "jsonl":
        dump = _ik_json if kind == "ik" else _strict_json().encode
        text = "".join(dump(r) + "\n" for r in records)
    else:
        text = _csv_rows(kind, robot, records)
    return text, bad, no


def _ik_json(r) -> str:
    """One ik output record as JSON; the solutions' joint values are written with 12
    significant digits by one format per solution (json.dumps spends ~0.5 us on the
    shortest repr of each float, most of a batch run's time)."""
    import json
    strict = _strict_json()
    if "solutions" not in r:
        return strict.encode(r)
    head = strict.encode({k: v for k, v in r.items() if k != "solutions"})[:-1]
    if isinstance(r["solutions"], _SolutionsJSON):
        return f'{head}, "solutions": [{r["solutions"]}]}}'
    sols = ", ".join('{"q": [%s], "branch": %s, "within_limits": %s}'
                     % (", ".join(["%.12g"] * len(s["q"])) % tuple(s["q"]),
                        json.dumps(s["branch"]), "true" if s["within_limits"] else "false")
                     for s in r["solutions"])
    return f'{head}, "solutions": [{sols}]}}'


def _strict_json():
    """The one JSON encoder of output records: NaN or Infinity in a record is an error
    (a bug: the chunk functions make non-finite results error records), never written.
    json.dumps(..., allow_nan=False) built an encoder a call: 2 us a record."""
    global _ENCODER
    if _ENCODER is None:
        import json
        _ENCODER = json.JSONEncoder(allow_nan=False)
    return _ENCODER


_ENCODER = None


class _SolutionsJSON(str):
    """A pose's solutions already written as JSON (the items of the array), by
    :func:`_solutions_json` for a whole chunk at once."""


def _solutions_json(ql, labels, within, owner, count) -> list:
    """The JSON text of each pose's solutions, for ``count`` poses: ``ql (s, n)`` the
    display values (rounded), ``labels``/``within (s,)`` and ``owner (s,)`` the pose of
    each solution, ascending. One %-format runs over all solutions of the chunk (per
    solution formatting in Python was the largest cost of a batch run); the numbers are
    written with 12 significant digits, as :func:`_ik_json` writes them."""
    import json

    import numpy as np
    s, n = ql.shape
    one = ('{"q": [' + ", ".join(["%.12g"] * n) + '], "branch": %s, "within_limits": %s}\x1e')
    quoted = {lab: json.dumps(lab) for lab in set(labels)}
    cells = np.empty((s, n + 2), object)
    cells[:, :n] = ql
    cells[:, n] = [quoted[lab] for lab in labels]
    cells[:, n + 1] = np.where(within, "true", "false")
    items = ((one * s) % tuple(cells.ravel().tolist())).split("\x1e")
    ends = np.searchsorted(owner, np.arange(1, count + 1)).tolist()
    out, start = [], 0
    for end in ends:
        out.append(_SolutionsJSON(", ".join(items[start:end])))
        start = end
    return out


def _round(a):
    """Arrays as nested lists rounded to 12 decimals, -0.0 as 0.0 (as results.json_numbers)."""
    import numpy as np
    return (np.round(a, 12) + 0.0).tolist()


def _head(i, kw):
    return {"index": i} if kw is None or "id" not in kw else {"index": i, "id": kw["id"]}


def _joint_rows(robot, units, parsed, what):
    """``(good [(index, kw)], q (m, n) SI, error records)`` from records that must hold
    joint values only."""
    import numpy as np
    good, qs, errors = [], [], []
    for i, kw, err in parsed:
        if err is None:
            keys = set(kw) - {"id"}
            if keys != {"q"}:
                err = (f"record {i + 1}: {what} takes joint values ('q', or one CSV column "
                       f"per joint), not {', '.join(sorted(keys - {'q'}))}")
            elif len(kw["q"]) != robot.dof:
                err = (f"record {i + 1}: {robot.name} has {robot.dof} joints, got "
                       f"{len(kw['q'])} values")
        if err is not None:
            errors.append((i, {**_head(i, kw), "error": err}))
            continue
        good.append((i, kw))
        qs.append(kw["q"])
    q = np.array(qs, float).reshape(-1, robot.dof)
    return good, q / np.where(robot.is_revolute, units.a, units.l), errors


def _merge(records, errors):
    out = records + [r for _, r in errors]
    out.sort(key=lambda r: r["index"])
    return out


def _finite_rows(good, arrays, errors):
    """``(good, arrays)`` without the records whose results (row k of every array) are
    not all finite; those become error records. Inputs within MAX_MAGNITUDE give finite
    results: this is the guarantee that no output holds NaN or Infinity."""
    import numpy as np
    if not good:
        return good, arrays
    ok = np.ones(len(good), bool)
    for a in arrays:
        ok &= np.isfinite(a).reshape(len(good), -1).all(axis=1)
    if ok.all():
        return good, arrays
    for k in np.flatnonzero(~ok):
        i, kw = good[k]
        errors.append((i, {**_head(i, kw), "error": f"record {i + 1}: the result is not a "
                           "finite number for these values"}))
    return [g for g, o in zip(good, ok) if o], [a[ok] for a in arrays]


def _fk_chunk(robot, units, parsed, frame):
    from ..spatial import rpy_from_matrix
    good, q, errors = _joint_rows(robot, units, parsed, "fk")
    T = robot.fk(q)
    T[:, :3, 3] *= units.l
    rpy = rpy_from_matrix(T[:, :3, :3]) * units.a
    good, (q, T, rpy) = _finite_rows(good, (q, T, rpy), errors)
    from ..ik.engine import within_limits
    within = within_limits(robot, q)
    Tl, xyz, rpyl = _round(T), _round(T[:, :3, 3]), _round(rpy)
    recs = [{**_head(i, kw), "T": Tl[k], "xyz": xyz[k], "rpy": rpyl[k],
             "within_limits": bool(within[k])} for k, (i, kw) in enumerate(good)]
    return _merge(recs, errors), False


def _jacobian_chunk(robot, units, parsed, frame):
    import numpy as np

    from ..jacobian import rotate_jacobian, scaled_ranks
    good, q, errors = _joint_rows(robot, units, parsed, "jacobian")
    Jb = robot.jacobian(q)                                                 # (m, 6, n) SI, base
    good, (q, Jb) = _finite_rows(good, (q, Jb), errors)
    J = Jb
    if frame == "tool" and len(q):
        J = rotate_jacobian(Jb, np.swapaxes(robot.fk(q)[:, :3, :3], -1, -2))
    # rank and singularity as 'kincalc jacobian' (analysis.jacobian_report)
    rank, position_rank = scaled_ranks(Jb, robot.is_revolute, robot.characteristic_length)
    full, full_pos = robot.generic_ranks
    singular = (rank < full) | (position_rank < full_pos)
    Jd = J.copy()
    Jd[:, :3] *= np.where(robot.is_revolute, units.l, 1.0)
    manip = np.prod(np.linalg.svd(Jd, compute_uv=False)[:, :full], axis=-1) if len(q) \
        else np.zeros(0)
    good, (Jd, manip, rank, singular) = _finite_rows(good, (Jd, manip, rank, singular), errors)
    Jl = _round(Jd)
    recs = [{**_head(i, kw), "J": Jl[k], "rank": int(rank[k]),
             "manipulability": float(manip[k]), "singular": bool(singular[k])}
            for k, (i, kw) in enumerate(good)]
    return _merge(recs, errors), False


def _poses(robot, units, parsed):
    """Group records by how they are solved: ``(full [(index, kw)], T (m, 4, 4) SI,
    partial [(index, kw, Target)], error records)``. Full poses of the common forms are
    built in one vectorised step per form (:func:`kincalc.ik.target.targets_from`); the
    rest go through build_target one by one."""
    import numpy as np

    from ..errors import KincalcError
    from ..ik.target import defect_text, targets_from, to_si
    from .common import check_numbers
    from .targets import pose_values, build_target
    groups, partial, errors = {}, [], []
    full, Ts = [], []
    for i, kw, err in parsed:
        if err is None:
            form = frozenset(kw) - {"id"}
            if form in _FAST_FORMS and (form != {"q"} or len(kw["q"]) == robot.dof):
                groups.setdefault(form, []).append((i, kw))
                continue
            try:
                target = build_target(robot, units, **{k: v for k, v in kw.items() if k != "id"})
            except KincalcError as exc:
                err = f"record {i + 1}: {_words(exc)}"
            else:
                if target.orientation and target.tcv is None and target.approach is None:
                    full.append((i, kw))
                    Ts.append(target.T)
                else:
                    partial.append((i, kw, target))
                continue
        errors.append((i, {**_head(i, kw), "error": err}))
    for form, items in groups.items():
        if form == {"q"}:
            q = np.array([kw["q"] for _, kw in items]) / np.where(robot.is_revolute, units.a,
                                                                  units.l)
            T = robot.fk(q)
        else:
            key = "T" if form == {"T"} else next(iter(form - {"xyz"}))
            xyz = None
            if key == "T":
                v = np.array([_pose_matrix(kw["T"]).ravel() for _, kw in items])
            else:
                v = np.array([kw[key] for _, kw in items], float)
                xyz = np.array([kw["xyz"] for _, kw in items], float).reshape(-1, 3) / units.l
            targets, defect = targets_from(key, to_si(key, v, units), xyz)
            bad = ~np.isfinite(v).all(-1) | (defect != None)  # noqa: E711
            for k in np.flatnonzero(bad):
                i, kw = items[k]
                try:
                    if key == "T":           # a wrong count, or a number beyond the limits
                        pose_values(np.array(kw["T"], float), "T")
                    else:
                        check_numbers(v[k], key)
                    msg = defect_text(key, defect[k], key)
                except KincalcError as exc:
                    msg = str(exc)
                errors.append((i, {**_head(i, kw), "error": f"record {i + 1}: {msg}"}))
            items = [it for it, b in zip(items, bad) if not b]
            T = targets.T[~bad]
        full += items
        Ts.extend(T)
    T = np.array(Ts, float).reshape(-1, 4, 4)
    return full, T, partial, errors


#: how a batch record names the parts of an IK target, for the core's messages about
#: them (:class:`kincalc.errors.TargetMismatch`)
RECORD_WORDS = {"approach": "approach", "tcv": "tcv", "prefix": "{field}: ",
                "orientation": "(rpy, euler_zyz, euler_xyz, quat, axis_angle, matrix, tcv, T "
                               "or q)"}


def _words(exc) -> str:
    """A core error's message for a record, its fields named as records name them."""
    from ..errors import TargetMismatch
    return exc.words(RECORD_WORDS) if isinstance(exc, TargetMismatch) else str(exc)


def _pose_matrix(flat):
    """A record's ``T`` (16 or 12 numbers) as a 4x4 matrix, NaN for another count."""
    import numpy as np
    a = np.array(flat, float)
    if a.size == 16:
        return a.reshape(4, 4)
    if a.size == 12:
        return np.vstack([a.reshape(3, 4), [0, 0, 0, 1]])
    return np.full((4, 4), np.nan)


def _ik_chunk(robot, units, parsed, frame, fmt="jsonl"):
    import numpy as np

    from ..ik import Target
    from ..errors import KincalcError
    from ..errors import UnsupportedRobot
    from ..ik.solve import solve
    full, T, partial, errors = _poses(robot, units, parsed)
    qdisp = np.where(robot.is_revolute, units.a, units.l)
    recs, no = [], False
    try:
        B = robot.ik_batch(T) if len(T) else None
    except UnsupportedRobot:
        B = None
        for (i, kw), t in zip(full, T):
            partial.append((i, kw, Target(t, orientation=True)))
    if B is not None:
        valid = B.valid & np.isfinite(B.q).all(axis=-1)         # (a NaN is no solution)
        q = B.q[valid]                                                     # (s, n)
        within = B.within[valid]
        owner, _ = np.nonzero(valid)
        labels = B.labels[valid].tolist()
        counts = valid.sum(axis=1)
        # each pose's solutions: written as JSON in bulk, or as dicts for the CSV rows
        if fmt == "jsonl":
            sols_of = _solutions_json(np.round(q * qdisp, 12) + 0.0, labels, within, owner,
                                      len(full))
        else:
            sols_of = [[] for _ in full]
            for o, ql, lab, w in zip(owner.tolist(), _round(q * qdisp), labels, within.tolist()):
                sols_of[o].append({"q": ql, "branch": lab, "within_limits": w})
        for ((i, kw), c, sols) in zip(full, counts.tolist(), sols_of):
            no |= not c
            recs.append({**_head(i, kw), "reachable": bool(c), "solutions": sols})
    for i, kw, target in partial:
        try:
            result = solve(robot, target)
        except KincalcError as exc:        # a question this robot cannot take: its record
            errors.append((i, {**_head(i, kw), "error": f"record {i + 1}: {_words(exc)}"}))
            continue
        sols = [{"q": _round(np.asarray(s.q) * qdisp), "branch": s.branch,
                 "within_limits": not s.violations} for s in result.solutions
                if np.isfinite(s.q).all()]
        no |= not sols
        recs.append({**_head(i, kw), "reachable": bool(sols), "solutions": sols})
    return _merge(recs, errors), no


def _reach_chunk(robot, units, parsed, frame):
    """Reach records of one chunk (the analysis runs pose by pose)."""
    import math

    from ..errors import KincalcError
    from ..analysis.reach import reach
    from ..analysis.results import json_numbers
    from .targets import build_target
    out, no = [], False
    for index, kw, error in parsed:
        head = _head(index, kw)
        if error is None:
            try:
                pose = {k: v for k, v in kw.items() if k != "id"}
                result = reach(robot, build_target(robot, units, **pose), units=units)
            except KincalcError as exc:
                error = f"record {index + 1}: {_words(exc)}"
        if error is not None:
            out.append({**head, "error": error})
            continue
        if result.distance is not None and not math.isfinite(result.distance):
            out.append({**head, "error": f"record {index + 1}: the distance is not a finite "
                        "number for this pose"})
            continue
        no |= not result.reachable
        out.append({**head, "reachable": result.reachable, "verdict": result.verdict,
                    "distance": None if result.distance is None else
                    json_numbers(result.distance * units.l),
                    "solutions": result.solutions,
                    "solutions_within_limits": result.within_limits,
                    "reason": result.reason})
    return out, no


def _csv_rows(kind, robot, records) -> str:
    import csv
    import io
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    n = robot.dof
    if kind == "reach":
        for r in records:
            w.writerow([_csv_cell(r.get(c)) for c in REACH_FIELDS])
        return buf.getvalue()
    for r in records:
        head = [r["index"], r.get("id", "")]
        if "error" in r:
            width = {"fk": 7, "jacobian": 6 * n + 3, "ik": n + 3}[kind]
            w.writerow(head + [""] * width + [r["error"]])
        elif kind == "fk":
            w.writerow(head + r["xyz"] + r["rpy"] + [_csv_cell(r["within_limits"]), ""])
        elif kind == "jacobian":
            w.writerow(head + [x for row in r["J"] for x in row] +
                       [r["rank"], r["manipulability"], _csv_cell(r["singular"]), ""])
        elif not r["solutions"]:
            w.writerow(head + ["", "no solution"] + [""] * n + ["", ""])
        else:
            for k, s in enumerate(r["solutions"]):
                w.writerow(head + [k, s["branch"]] + s["q"] + [_csv_cell(s["within_limits"]), ""])
    return buf.getvalue()
