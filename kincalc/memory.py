"""Keeping freed memory for the next chunk of a batch (glibc's malloc only).

A batch is solved in chunks of some thousand poses, each making and freeing temporaries of
0.1 to a few MB. glibc's malloc, as it starts, hands out blocks of 128 KiB and more by
``mmap`` and gives memory at the top of its heap back to the system once 128 KiB of it are
free (its dynamic threshold moves up to the sizes it sees freed, and trims at twice that).
Either way the next chunk's temporaries arrive as fresh pages, which the kernel zeroes on
first touch: on chunks of 2048 PUMA poses a third of the batched solver's time, and 37,500
page faults for 50,000 poses in ``ik --batch`` (11,000 with the thresholds raised). Raising
them to glibc's largest ``mmap`` threshold (32 MiB on 64-bit systems) and twice that keeps
the pages between chunks; the peak memory is the same (what the largest chunk needs), only
its return to the system waits for the heap's free top to pass 64 MiB. Other C libraries
(macOS, musl, Windows) are left as they are.
"""

from __future__ import annotations

#: glibc's ``mallopt`` parameters (malloc.h)
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3

#: blocks below this come from the heap, not from ``mmap`` (glibc's largest threshold on a
#: 64-bit system: a larger value is refused)
MMAP_THRESHOLD = 32 << 20

#: the heap's free top is given back to the system only beyond this
TRIM_THRESHOLD = 64 << 20

#: the outcome, once tried (None: not yet)
_kept: bool | None = None


def keep_freed_memory() -> bool:
    """Ask glibc's malloc to keep freed blocks for reuse (see the module's docstring).

    Tried once per process (later calls return the first outcome); changes no result, only
    where memory comes from.

    Returns
    -------
    bool
        True when the C library is glibc and took both settings.
    """
    global _kept
    if _kept is None:
        _kept = _mallopt()
    return _kept


def _mallopt() -> bool:
    """Both settings by glibc's ``mallopt``; False where the C library has none."""
    try:
        import ctypes
        mallopt = ctypes.CDLL(None).mallopt
    except (ImportError, OSError, AttributeError, TypeError):   # no ctypes, libc, mallopt
        return False
    mallopt.argtypes, mallopt.restype = (ctypes.c_int, ctypes.c_int), ctypes.c_int
    return bool(mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD)
                and mallopt(_M_TRIM_THRESHOLD, TRIM_THRESHOLD))
