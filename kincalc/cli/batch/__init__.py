"""``--batch FILE|-``: many inputs, one output record per input record, in order.

What a record is
----------------
The input is read as bytes, in pieces of at most
:data:`~kincalc.cli.batch.runner.READ_BYTES`, and cut into lines at each newline
(``\\n``; a CR before it is ignored, and a UTF-8 byte order mark at the start of the
input is dropped). A line holding nothing but ASCII whitespace (spaces,
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
letters, digits, ``_``, ``.`` or ``-``, and not a JSON word such as ``null``; a single
name only when it is a pose column or a joint's name), else JSON lines. So a JSON lines input whose
first record is ``42``, ``[]``, ``null`` or a stray word is still read as JSON lines.

A record holds a pose in any of the forms of PRODUCT.md:

* JSON: ``{"xyz": [x, y, z], "rpy": [r, p, y]}``, with ``euler_zyz``,
  ``euler_xyz``, ``quat``, ``axis_angle``, ``matrix``, ``approach`` or ``tcv``
  instead of ``rpy``; or ``{"T": [[...], ...]}`` (4x4); or ``{"q": [...]}``
  (the pose FK gives for these joints); or an answer of ``fk --batch`` (read by its
  ``T``, its other fields checked; its error record stays an error);
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

The rooms: :mod:`~kincalc.cli.batch.records` reads a record (and
:mod:`~kincalc.cli.batch.uniform` the JSON lines of a chunk written alike, together),
:mod:`~kincalc.cli.batch.runner` cuts the input into chunks and runs them (processes, order,
progress), :mod:`~kincalc.cli.batch.chunks` solves a chunk through the core (its IK targets
built by :mod:`~kincalc.cli.batch.poses`) and :mod:`~kincalc.cli.batch.formats` writes it (the
joint values of ik answers by :mod:`~kincalc.cli.batch.numtext`, many numbers at once).
"""

from .runner import run, run_command

__all__ = ["run", "run_command"]
