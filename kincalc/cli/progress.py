"""A progress bar on standard error, for commands that work through many files (``kincalc
check`` over a class's sheets, ``kincalc quiz --roster``).

Only when standard error is a terminal: in a pipe, a file or a test nothing is drawn, so
what a script reads stays clean. The bar goes when the work is done (transient). Lines the
command writes meanwhile go above it: its messages on standard error always, and its
output on standard output when that is a terminal too (the bar is taken down for each
batch of whole lines and drawn again after; standard output to a file or a pipe is left
alone).
"""

from __future__ import annotations

import contextlib
import os
import sys

#: fewer units than this get no bar (one sheet is done before a bar would be seen)
MIN_UNITS = 2


def _is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):       # a closed or a fake stream
        return False


@contextlib.contextmanager
def progress(total: int, what: str):
    """A bar for ``total`` units of work: ``with progress(n, "grading") as step:`` and
    ``step()`` after each unit.

    Parameters
    ----------
    total : int
        The number of units.
    what : str
        The words before the bar.

    Yields
    ------
    callable
        ``step()``, which advances the bar by one unit (and does nothing when no bar is
        drawn: fewer than :data:`MIN_UNITS` units, or standard error not a terminal).
    """
    if total < MIN_UNITS or not _is_terminal(sys.stderr):
        yield lambda: None
        return
    from rich.console import Console
    from rich.progress import (BarColumn, MofNCompleteColumn, Progress, TextColumn,
                               TimeRemainingColumn)
    console = Console(file=sys.stderr, highlight=False,
                      no_color=bool(os.environ.get("NO_COLOR")) or None)
    bar = Progress(TextColumn(what), BarColumn(), MofNCompleteColumn(), TimeRemainingColumn(),
                   console=console, transient=True, redirect_stderr=True,
                   redirect_stdout=False)
    stdout = sys.stdout
    with bar:
        task = bar.add_task(what, total=total)
        # rich's own stdout proxy is bypassed by a Console printing to stdout (rich
        # unwraps it), which glued results to the bar: ours is not unwrapped
        above = _AboveTheBar(stdout, bar) if _is_terminal(stdout) else None
        if above is not None:
            sys.stdout = above
        try:
            yield lambda: bar.advance(task)
        finally:
            if above is not None:
                sys.stdout = stdout
                above.close()


class _AboveTheBar:
    """Standard output while a bar is drawn on a terminal: whole lines only, each batch
    written with the bar taken down first and drawn again after, so that output and bar
    never share a line. Anything else is the stream's."""

    def __init__(self, stream, bar):
        self._stream, self._bar, self._pending = stream, bar, ""

    def write(self, text: str) -> int:
        lines, _, self._pending = (self._pending + text).rpartition("\n")
        if lines or _:
            self._bar.stop()
            try:
                self._stream.write(lines + "\n")
                self._stream.flush()
            finally:
                self._bar.start()
        return len(text)

    def flush(self) -> None:
        """Whole lines are written at once; a partial line waits for its end."""

    def close(self) -> None:
        """Write what is left of a partial line (the bar is gone by then or going)."""
        if self._pending:
            self._stream.write(self._pending)
            self._pending = ""
        self._stream.flush()

    def __getattr__(self, name):
        return getattr(self._stream, name)
