"""The batch runner: the input read in pieces and cut into chunks of records, each chunk
solved by :func:`~kincalc.cli.batch.chunks.process_chunk` here or in worker processes
(``--jobs``), the output written in the input's order, with a progress line."""

from __future__ import annotations

import sys

from ...limits import (MAX_BATCH_SKIP_BYTES, MAX_JOBS, MAX_RECORD_BYTES, open_input, quote,
                       size_text)
from ...memory import keep_freed_memory
from .chunks import process_chunk
from .formats import csv_header
from .pool import ordered_map, start_pool, stop_pool
from .csv_input import header_problem, read_header
from .records import BLANK, BOM, FORMAT_OF_SUFFIX, INPUT_FORMATS

#: the most bytes one read of the input takes
READ_BYTES = 1 << 16

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
#: ik of a robot solved numerically runs pose by pose too (milliseconds each, a second
#: for a pose out of reach): chunks this small let --jobs share even a short input
NUMERIC_CHUNK_LINES = 8


def chunk_lines(kind: str, robot, locks: dict | None = None) -> int:
    """The records per chunk for ``kind`` on ``robot``: :data:`REACH_CHUNK_LINES` for
    reach, :data:`NUMERIC_CHUNK_LINES` for ik of a robot no closed form covers (held
    joints, ``locks``, may leave one that is: then the default), else
    :data:`CHUNK_LINES`."""
    if kind == "reach":
        return REACH_CHUNK_LINES
    if kind == "ik" and not locks:
        from ...ik.families import plan
        if plan(robot)[1] is None:
            return NUMERIC_CHUNK_LINES
    return CHUNK_LINES


def run_command(kind: str, robot, units, src: str, fmt: str, jobs: int, *, given=(),
                frame: str = "base", refused: dict | None = None,
                input_format: str = "auto", locks: dict | None = None, json: bool = False):
    """The --batch branch of a command: refuse the command's own inputs (``given``, the
    values of its joint or pose arguments), the options in ``refused`` and ``--json`` with
    ``--format csv`` (``json``: --json given), run, and leave with the batch's exit status.
    ``locks`` (ik): joints held for every record (SI)."""
    import typer

    from ...errors import UsageError
    from ..common import refuse_unknown_option
    for v in given:
        for token in v or ():
            refuse_unknown_option(token)
    if any(v is not None and len(v) for v in given):
        raise UsageError("--batch reads its input from a file; do not give "
                         f"{'pose options' if kind in ('ik', 'reach') else 'joint values'} too")
    for option, value in (refused or {}).items():
        if value:
            raise UsageError(f"{option} does not combine with --batch")
    if json and fmt == "csv":
        raise UsageError("--json and --format csv ask for two formats: --batch writes JSON "
                         "lines, or CSV with --format csv")
    raise typer.Exit(run(kind, robot, units, src, fmt, jobs, frame, input_format, locks))


def run(kind: str, robot, units, src: str, fmt: str, jobs: int = 1, frame: str = "base",
        input_format: str = "auto", locks: dict | None = None) -> int:
    """Answer every record of ``src`` with ``kind`` ('fk', 'jacobian', 'ik' or 'reach');
    write the output records to stdout; return the exit status (2 if any record was bad,
    1 if all were good but some pose had no solution, else 0)."""
    import contextlib
    from functools import partial

    from ...errors import InputError, UsageError
    if fmt not in ("jsonl", "csv"):
        raise UsageError(f"--format must be jsonl or csv, not {fmt!r}")
    if input_format not in INPUT_FORMATS:
        raise UsageError(f"--input-format must be {', '.join(INPUT_FORMATS[:-1])} or "
                         f"{INPUT_FORMATS[-1]}, not {quote(input_format)}")
    if not 1 <= jobs <= MAX_JOBS:
        raise UsageError(f"--jobs must be 1 to {MAX_JOBS}, not {jobs}")
    import gc
    source = _Source(src)
    keep_freed_memory()             # (kincalc.memory: each chunk reuses the last one's pages)
    bad = no = False
    answered = 0                        # chunks answered
    pool = None
    # the objects alive now (modules, the robot) and after the first chunk (the modules it
    # imports) are left alone by the collector until the end: its full passes over them
    # while the records' objects come and go were ~5 % of a run (a fork pool's workers
    # share them, as gc.freeze is meant for)
    gc.freeze()
    try:
        header, chunks, guessed = _chunked(source, chunk_lines(kind, robot, locks),
                                           input_format, robot)
        work = partial(process_chunk, kind, robot, units, header, fmt, frame, locks=locks,
                       guessed=guessed)
        # the workers start before any other thread of this process does (the progress
        # bar's): a fork copies a lock another thread holds, locked for good
        pool = start_pool(jobs) if jobs > 1 else None
        with _Output() as out, _progress(source) as advance, \
                contextlib.closing(ordered_map(work, chunks, pool, jobs)) as results:
            for answered, (text, b, n) in enumerate(results, 1):
                if fmt == "csv" and answered == 1:
                    out.write(csv_header(kind, robot))
                out.write(text)
                bad |= b
                no |= n
                advance(source.position)
                if answered == 1:
                    gc.freeze()
    finally:
        gc.unfreeze()
        if pool is not None:                    # (on Ctrl-C or a closed stdout too)
            stop_pool(pool)
        source.close()
    if source.stopped is not None:
        raise InputError(f"--batch {_shown(src)}: record {source.stopped} runs on for more than "
                         f"{size_text(MAX_BATCH_SKIP_BYTES)} without a newline (not a file of "
                         "lines?); reading stopped there")
    if not answered and header is not None and header_problem(header, robot, kind):
        # a header no record follows: its fault is said once (each record says it otherwise)
        raise InputError(f"--batch {_shown(src)}: line 1: {header_problem(header, robot, kind)}")
    if not answered and fmt == "csv":           # no record: the output's header alone
        sys.stdout.write(csv_header(kind, robot))
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

        from ...errors import InputError
        from ...limits import os_error_text
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
                self._file = open_input(src, buffering=0)
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
        from ...errors import InputError
        from ...limits import os_error_text
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
            if len(data) < len(BOM) and BOM.startswith(data):
                held, held_bytes = [data], len(data)    # (a pipe giving the mark bytewise)
                continue
            start = False
            if data.startswith(BOM):
                data = data[len(BOM):]
        if b"\n" not in data:             # more of one line: kept, not copied (a slow pipe)
            held.append(data)
            held_bytes += len(data)
            if held_bytes > MAX_RECORD_BYTES + 1:        # (+1: the CR of a CRLF may end it)
                skipped, held, held_bytes = held_bytes, [], 0
                yield [None], source.ready()
            continue
        if held:
            data = b"".join(held) + data
            held, held_bytes = [], 0
        parts = data.split(b"\n")
        last = parts.pop()
        # no line too long, the common case (a file's block is longer than a record, its
        # lines are not: their longest is found by C-level calls, not a test a line)
        if len(data) <= MAX_RECORD_BYTES or max(map(len, parts)) <= MAX_RECORD_BYTES:
            lines = [p for p in parts if p.strip(BLANK)]
        else:                                   # an over-long line is a record, blank or not
            lines = [None if _too_long(p) else p for p in parts
                     if _too_long(p) or p.strip(BLANK)]
        if len(last) > MAX_RECORD_BYTES + 1:
            lines.append(None)
            skipped = len(last)
        elif last:
            held, held_bytes = [last], len(last)
        if lines:
            yield lines, source.ready()
    tail = b"".join(held)
    if _too_long(tail):                 # (an over-long line is a record, blank or not)
        yield [None], False
    elif tail.strip(BLANK):
        yield [tail], False


def _too_long(line: bytes) -> bool:
    """Is ``line`` (without its newline) longer than MAX_RECORD_BYTES, not counting the CR of
    a CRLF line end (which is not part of the line)?"""
    return len(line) > MAX_RECORD_BYTES + line.endswith(b"\r")


def _chunked(source, size: int = 0, input_format: str = "auto", robot=None):
    """``(header, chunks, guessed)``: the header (None for JSON lines, the CSV column names,
    or the reason a CSV header cannot be used), an iterator of ``((first index, lines),
    flush)``, at most ``size`` records a chunk (default CHUNK_LINES), and whether the input
    is JSON lines because its first line is no CSV header (neither its name nor
    --input-format said). ``flush`` says that
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
            header = read_header(lines[0], fmt == "csv", robot)
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
    return header, chunks(), fmt == "auto" and header is None


class _Output:
    """stdout for whole chunks of output lines: a Ctrl-C while a chunk is being written
    takes effect when it is written, so the output never ends inside a line.

    A real stdout is written with ``os.write`` on its descriptor, looping over partial
    writes: CPython's buffered stdout (3.11) dropped the rest of a large write that a
    signal interrupted while the pipe was full (131072 of 2000000 bytes arrived), even
    with a handler that returns."""

    def __enter__(self):
        import signal
        self._writing = self._pending = self._stopping = False
        self._old = self._fd = None
        try:
            sys.stdout.flush()
            self._fd = sys.stdout.fileno()
            self._encoding = sys.stdout.encoding or "utf-8"
            ascii_text = bytes(range(128)).decode("ascii")
            # ASCII text as bytes goes out as it is where the encoding writes ASCII so
            self._ascii = ascii_text.encode(self._encoding, "backslashreplace") == \
                ascii_text.encode("ascii")
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
            self._stop()

    def _stop(self):
        """Raise KeyboardInterrupt, with Ctrl-C ignored from now on while the run stops (its
        workers, its generators, the interpreter): a second Ctrl-C there broke the
        shutdown, or came out as a traceback. (:func:`kincalc.cli.main.main` restores the
        handler for a caller in the same process.)"""
        import signal
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        self._stopping = True
        raise KeyboardInterrupt

    def write(self, text) -> None:
        """Write ``text``: str, or bytes of ASCII text."""
        import os
        self._writing = True
        try:
            if self._fd is None:
                sys.stdout.write(text if isinstance(text, str) else text.decode("ascii"))
                sys.stdout.flush()
            else:
                if isinstance(text, bytes) and not self._ascii:
                    text = text.decode("ascii")
                view = memoryview(text if isinstance(text, bytes) else
                                  text.encode(self._encoding, "backslashreplace"))
                while view:
                    view = view[os.write(self._fd, view):]
        except BrokenPipeError:
            if self._pending:                   # the reader went with the same Ctrl-C
                self._stop()
            raise
        finally:
            self._writing = False
        if self._pending:
            self._stop()

    def __exit__(self, *exc):
        if self._old is not None and not self._stopping:
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
