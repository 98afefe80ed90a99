"""The files kincalc writes (drawings, robot files, exercise sheets), none ever destroyed.

Every writer goes through here: ``kincalc plot -o``, ``ik --plot``, ``workspace --plot``,
``view -o``, ``convert -o``, ``quiz -o`` (and ``quiz --roster``), ``check -o``, ``check --gradebook`` and
``check --feedback-dir``, and the drawing functions of :mod:`kincalc.analysis.plot`. The
rules (README, "Output files"):

* an existing file is refused unless ``force``;
* ``force`` replaces a regular file only: a folder, a symbolic link, a device, a FIFO or
  a socket is refused whatever the flag (run as root, replacing ``/dev/...`` with a
  drawing is not a mistake to make easy);
* a command's own input (its robot file, --pose file, ...) is refused, ``force`` or not:
  the same file is the same device and inode (:func:`os.path.samefile`), so a hard link
  or a symbolic link to the input is caught too; so is any file the command read along
  the way (:func:`kincalc.limits.was_read`: the robot a homework sheet names), at the
  latest when the output is written;
* checks come before any work (:func:`check_target`), and again at the end;
* the data go to a temporary file in the target's folder, which is renamed over the
  target only when complete (:func:`replacing`): a failed or interrupted write leaves the
  old file whole and no half-written new one;
* a new file gets mode ``0o666 & ~umask``, as other tools' outputs do (not the 0600 of
  a temporary file); a replaced file keeps its mode.

Standard library only. Messages name the option the path came with (``-o``, ``--plot``).
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from dataclasses import dataclass

from .errors import InputError
from .limits import quote, was_read

_KINDS = ((stat.S_ISLNK, "a symbolic link"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a named pipe (FIFO)"),
          (stat.S_ISSOCK, "a socket"))


@dataclass(frozen=True)
class Target:
    """A file to write and what may be done to it.

    ``path`` as the user gave it; ``option`` how it was given (``"-o"``, ``"--plot"``),
    for messages; ``force`` lets an existing regular file be replaced; ``inputs`` are
    ``(what, path)`` pairs of the files the command reads (``("the robot file",
    "arm.yaml")``), which are never written.
    """

    path: str
    option: str = "-o"
    force: bool = False
    inputs: tuple = ()

    @property
    def shown(self) -> str:
        """The path for a one-line message: as given, quoted when unprintable, cut when
        absurdly long (:func:`shown_path`).

        Returns
        -------
        str
        """
        return shown_path(self.path)

    def fail(self, reason: str):
        """Refuse the target.

        Parameters
        ----------
        reason : str
            What is wrong with it.

        Raises
        ------
        InputError
            Always: ``"<option> <path>: <reason>"``.
        """
        raise InputError(f"{self.option} {self.shown}: {reason}")


#: longer paths are cut in messages (a path is echoed whole up to this many characters)
_SHOWN_PATH = 300


def shown_path(path) -> str:
    """``path`` for a one-line message.

    Parameters
    ----------
    path : str or os.PathLike
        The path as the user gave it.

    Returns
    -------
    str
        ``str(path)`` as given; quoted when unprintable (a newline), cut (by
        :func:`kincalc.limits.quote`) when longer than a few hundred characters.
    """
    p = str(path)
    return p if p.isprintable() and len(p) <= _SHOWN_PATH else quote(p, _SHOWN_PATH)


def as_target(path) -> Target:
    """``path`` as a :class:`Target`.

    Parameters
    ----------
    path : str, os.PathLike or Target
        A Target is returned as it is; a path becomes ``Target(path)`` (option ``-o``,
        no ``force``, no inputs).

    Returns
    -------
    Target

    Raises
    ------
    TypeError
        ``path`` is none of these (from :func:`os.fspath`).
    """
    if isinstance(path, Target):
        return path
    return Target(os.fspath(path))


def check_target(target) -> str:
    """Refuse a file that may not be written (see the module's rules); return its folder.

    Cheap (a few ``stat`` calls), for commands to call before long work.

    Parameters
    ----------
    target : str, os.PathLike or Target
        The file to write (:func:`as_target`).

    Returns
    -------
    str
        The absolute path of the folder the file is to be written in.

    Raises
    ------
    InputError
        No file name, a NUL character in it, a missing folder, a folder, one of the
        command's inputs, an existing file without ``force``, or anything but a regular
        file.
    """
    t = as_target(target)
    path = str(t.path)
    if not path:
        raise InputError(f"{t.option}: give a file name")
    if "\0" in path:               # no such name reaches a real argv, but main() takes any
        t.fail("is not a valid file name (it holds a NUL character)")
    if path.endswith(("/", os.sep)):
        t.fail("names a folder; give a file name")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        t.fail(f"the folder {shown_path(folder)} does not exist")
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return folder
    except OSError as exc:
        t.fail(f"cannot write: {exc.strerror}")
    for what, source in t.inputs:
        if source is not None and same_file(path, source):
            t.fail(f"that is {what}, which this command reads; kincalc never writes over "
                   "its input")
    if was_read(path):
        t.fail("that is a file this command read (a robot file a sheet names, ...); kincalc "
               "never writes over its input")
    if stat.S_ISDIR(st.st_mode):
        t.fail("is a folder, cannot write a file there; give a file name")
    kind = special_kind(st.st_mode)
    if kind is not None or not stat.S_ISREG(st.st_mode):
        t.fail(f"is {kind or 'not a regular file'}; kincalc replaces regular files only, "
               "even with --force")
    if not t.force:
        t.fail("the file exists; use --force to overwrite it")
    return folder


def special_kind(mode: int) -> str | None:
    """What a file that is no regular file is, in words, from its ``lstat`` mode.

    Parameters
    ----------
    mode : int
        ``os.lstat(path).st_mode`` (the link itself, not what it points to).

    Returns
    -------
    str or None
        ``"a symbolic link"``, ``"a character device"``, ``"a block device"``, ``"a named
        pipe (FIFO)"`` or ``"a socket"``; None for anything else (a regular file, a folder).
    """
    return next((name for test, name in _KINDS if test(mode)), None)


def same_file(a: str, b) -> bool:
    """Whether ``a`` and ``b`` are one existing file (device and inode: a hard or a
    symbolic link too); False when either is missing or unreadable."""
    try:
        return os.path.samefile(a, os.fspath(b))
    except (OSError, ValueError):
        return False


@contextlib.contextmanager
def replacing(target, *, binary: bool = True):
    """Write ``target`` through a temporary file: ``with replacing(t) as fh: fh.write(...)``.

    ``fh`` is a file object open for writing (bytes, or UTF-8 text with ``binary=False``)
    on a new temporary file in the target's folder. When the block ends without an
    exception the target is checked again, and the file renamed over it (with ``force``)
    or linked to its name (without: if a file of that name appeared meanwhile it is left
    alone). Otherwise the temporary file is removed and the target is untouched.

    Parameters
    ----------
    target : str, os.PathLike or Target
        The file to write (:func:`as_target`), checked by :func:`check_target` first.
    binary : bool
        True: ``fh`` takes bytes; False: text, written as UTF-8 with newlines as given.

    Yields
    ------
    file object
        The temporary file, open for writing.

    Raises
    ------
    InputError
        As :func:`check_target`, or when the folder or the file cannot be written.
    """
    t = as_target(target)
    folder = check_target(t)
    path = str(t.path)
    try:
        old = os.stat(path, follow_symlinks=False)
        mode = stat.S_IMODE(old.st_mode) & 0o777
    except FileNotFoundError:
        mode = 0o666 & ~_umask()
    # Ctrl-C is held back until the file is written and named, or its temporary removed: a
    # Ctrl-C as a block ended (roster sheets, 4 runs of 12) left .kincalc-XXXX.tmp behind
    with _ctrl_c_held():
        try:
            fd, tmp = tempfile.mkstemp(prefix=".kincalc-", suffix=".tmp", dir=folder)
        except OSError as exc:
            t.fail(f"cannot write in {folder}: {exc.strerror}")
        try:
            if hasattr(os, "fchmod"):
                os.fchmod(fd, mode)
            with os.fdopen(fd, "wb" if binary else "w",
                           **({} if binary else {"encoding": "utf-8", "newline": ""})) as fh:
                yield fh
                fh.flush()
                os.fsync(fh.fileno())
            check_target(t)                       # changed while we worked?
            _commit(tmp, path, t)
        except OSError as exc:
            t.fail(f"cannot write: {exc.strerror or exc}")
        finally:
            with contextlib.suppress(OSError):
                os.unlink(tmp)


@contextlib.contextmanager
def _ctrl_c_held():
    """Ctrl-C (SIGINT) held back in this block, taken after it (by the handler there was).

    A handler of this process's own, not a blocked signal: the signal may be delivered to
    any thread (a blocked main thread does not keep another from taking it), and Python runs
    the handler in the main thread all the same."""
    import signal
    import threading
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught = []
    old = signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    if old is signal.SIG_IGN:                 # (a run started with Ctrl-C ignored)
        signal.signal(signal.SIGINT, old)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)
        if caught and callable(old):
            old(signal.SIGINT, None)          # (Python's own: KeyboardInterrupt)
        elif caught:
            raise KeyboardInterrupt           # (the default action, or a handler not Python's)


def _commit(tmp: str, path: str, t: Target) -> None:
    if t.force and os.path.lexists(path):
        os.replace(tmp, path)                 # a regular file (just checked): atomic
        return
    try:
        os.link(tmp, path)                    # atomic, and never over an existing name
    except FileExistsError:
        t.fail("the file exists; use --force to overwrite it")
    except OSError:                           # a file system without hard links
        if os.path.lexists(path):
            t.fail("the file exists; use --force to overwrite it")
        os.replace(tmp, path)


def make_folder(path, option: str) -> None:
    """Make the folder ``path`` (and its parents) that a command writes its files in.

    Parameters
    ----------
    path : str or os.PathLike
        The folder, as the user gave it.
    option : str
        How it was given (``"--feedback-dir"``, ``"-o"``), for the message.

    Raises
    ------
    InputError
        It cannot be made (a name too long, no permission, a file in the way): one line
        naming the option and the folder, with the system's reason.
    """
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{option} {shown_path(path)}: cannot make the folder: "
                         f"{exc.strerror or exc}") from None


def write_text(target, text: str) -> None:
    """Write ``text`` (UTF-8) to ``target`` by :func:`replacing`.

    Parameters
    ----------
    target : str, os.PathLike or Target
        The file to write (:func:`as_target`).
    text : str
        The whole content; newlines are written as they are.

    Raises
    ------
    InputError
        As :func:`replacing`.
    """
    with replacing(target, binary=False) as fh:
        fh.write(text)


def _umask() -> int:
    """The process's umask (Linux: read, not set; elsewhere set and restored)."""
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask
