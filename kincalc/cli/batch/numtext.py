"""The text of many numbers at once: ``"%.12g" % x`` for a whole array, as bytes in a grid.

Python's float formatting costs ~150 ns a number, and an ik batch writes about fifty numbers
a pose. :func:`g12_cells` writes a whole array with a few dozen numpy operations (~55 ns a
number, the zero bytes removed) and gives exactly the text of ``"%.12g" % x``: 12
significant digits, trailing zeros and a bare point dropped, ``e`` notation below 1e-4 and
from 1e12 on, ``-0``, ``nan``, ``inf``. For ``a = |x|`` with decimal exponent ``X``
(-4 <= X <= 11) the 12 digits are ``D = round(a * 10^(11 - X))`` (half to even, of the exact
binary value), written by a table of the 10,000 four-digit groups, with the point after digit
``X`` (or "0." and zeros before them).

Exactness: ``10^k`` (k <= 15) is a double, so ``s = a * 10^k`` is the exact product rounded
once. Below 2^52 every half-integer is a double and rounding is monotonic, so s is on the same
side of a half-integer as the exact product, or on it; only then (``s`` a half-integer) is the
exact product's side found, by Dekker's error-free product (T. J. Dekker, "A floating-point
technique for extending the available precision", Numer. Math. 18, 1971). Values outside
those exponents, not finite, or rounding up to the next power of ten (9.9999999999995) are
written by ``"%.12g"`` itself, one by one: the same text by definition.
"""

from __future__ import annotations

import numpy as np

#: the width of a cell (bytes): a word of the sign and up to five characters "0.000" before
#: the digits, two of the 12 digits and the point (and the longest "%.12g" text,
#: "-1.23456789012e-308", fits)
CELL = 24
#: numbers formatted a block at a time (their work arrays stay in the cache)
BLOCK = 8192

_P10 = 10.0 ** np.arange(16)                      # exact: every power of ten to 1e22 is a double
_SPLIT = 134217729.0                              # 2^27 + 1, Veltkamp's splitter


def _tables():
    """The lookup tables: the four digit characters of each group 0000..9999 (a little-endian
    uint32, first character lowest), its trailing zeros (4 for 0000), and by byte count k
    (0..16) the masks of the first k bytes of two words and a point placed after them."""
    g = np.arange(10000)
    chars = (ord("0") + g[:, None] // np.array([1000, 100, 10, 1]) % 10).astype(np.uint8)
    four = chars.view("<u4").ravel().astype("<u8")
    trailing = sum((g % p == 0).astype(np.int8) for p in (10, 100, 1000, 10000))
    first = np.zeros((17, 16), np.uint8)           # the first k bytes of two words
    dot = np.zeros((17, 16), np.uint8)             # "." as byte k
    for k in range(17):
        first[k, :k] = 0xFF
        if k < 16:
            dot[k, k] = ord(".")
    before = np.zeros((16, 8), np.uint8)           # exponent X = -4 .. 11: "0.000" .. "0." ..
    for x in range(-4, 0):
        text = ("0." + "0" * (-x - 1)).encode()
        before[x + 4, 6 - len(text):6] = list(text)
    first, dot = first.view("<u8"), dot.view("<u8")
    return (four, trailing, first[:, 0].copy(), first[:, 1].copy(), dot[:, 0].copy(),
            dot[:, 1].copy(), before.view("<u8").ravel())


_TABLES = None


def g12_cells(x, out=None) -> np.ndarray:
    """The characters of ``"%.12g" % v`` for every value ``v`` of ``x``, a cell of
    :data:`CELL` bytes each, in order, with zero bytes between and around them (the
    caller removes them: ``b[b != 0]``); the last two bytes of every cell are zero.

    Parameters
    ----------
    x : array_like (...) of float
        Any values (NaN, infinities, -0.0, subnormals included).
    out : ndarray (..., CELL // 8) of uint64, optional
        Where to write the cells (may be a view into a larger grid).

    Returns
    -------
    ndarray (..., CELL // 8) of little-endian uint64: ``out``, or a new array.
    """
    global _TABLES
    if _TABLES is None:
        _TABLES = _tables()
    x = np.asarray(x, float)
    if out is None:
        out = np.empty(x.shape + (CELL // 8,), "<u8")
    xs, outs = (x[None], out[None]) if x.ndim == 0 else (x, out)
    rows = max(1, BLOCK // max(1, int(np.prod(xs.shape[1:]))))
    with np.errstate(all="ignore"):               # (NaN, infinities and zeros: no warning)
        for k in range(0, len(xs), rows):         # blocks whose work arrays stay in the cache
            _cells(xs[k:k + rows], outs[k:k + rows])
    return out


def _cells(x, out):
    """Fill ``out (..., 3)`` uint64, the cells of ``x (...)``: a word of the sign and the
    zeros before the digits, two words of the digits and the point."""
    four, trailing, first0, first1, dot0, dot1, before = _TABLES
    a = np.abs(x)
    e = np.floor(np.log10(a))                     # NaN, -inf for 0, inf: not in range
    zero = a == 0
    ok = (e >= -4) & (e <= 11)
    X = np.where(ok, e, 0).astype(np.intp)
    s = a * _P10[11 - X]                          # the exact product, rounded once
    D = np.rint(s)
    near = np.nonzero(s - np.floor(s) == 0.5)
    if len(near[0]):                              # on a half: the exact product's side
        D[near] = _round_exact(a[near], _P10[11 - X[near]], s[near])
    ok &= (D >= 1e11) & (D < 1e12)                # log10 a step off, or 10^12 after rounding
    ok |= zero
    D = np.where(ok & ~zero, D, 0).astype(np.int64)
    X[zero] = 0
    hi = D // 100000000
    rest = D - hi * 100000000
    mid = rest // 10000
    lo = rest - mid * 10000
    w0 = four[hi] | (four[mid] << np.uint64(32))            # digits 1-8
    w1 = four[lo]                                          # digits 9-12
    zeros = np.where(lo != 0, trailing[lo], 4 + np.where(mid != 0, trailing[mid],
                                                         4 + trailing[hi]))
    kept = np.maximum(12 - zeros, X + 1)                    # digits written (0 -> "0")
    lead = np.where((X < 0) | (X == 11), 16, X + 1)        # digits before the point
    shown = kept + (kept > lead)                            # characters from the digits on
    m0, m1 = first0[lead], first1[lead]
    # the digits from `lead` on move up a byte, the point goes between
    u0 = w0 & ~m0
    out[..., 1] = ((w0 & m0) | (u0 << np.uint64(8)) | dot0[lead]) & first0[shown]
    out[..., 2] = ((w1 & m1) | ((w1 & ~m1) << np.uint64(8)) | (u0 >> np.uint64(56))
                   | dot1[lead]) & first1[shown]
    out[..., 0] = before[X + 4] | np.signbit(x).astype("<u8") * np.uint64(ord("-"))
    odd = np.nonzero(~ok)
    if len(odd[0]):                               # the rest: by "%.12g" itself
        text = b"".join(b"%-24.12g" % v for v in x[odd].tolist()).replace(b" ", b"\0")
        out[odd] = np.frombuffer(text, "<u8").reshape(-1, 3)


def _round_exact(a, p, s):
    """``round(a * p)``, half to even, of the exact product of two doubles whose rounded
    product ``s`` is on a half: Dekker's product gives its error ``err`` (``a * p = s + err``
    exactly), whose sign is the side."""
    def split(v):
        t = _SPLIT * v
        h = t - (t - v)
        return h, v - h
    ah, al = split(a)
    ph, pl = split(p)
    err = ((ah * ph - s) + ah * pl + al * ph) + al * pl
    base = np.floor(s)
    return base + ((err > 0) | ((err == 0) & (base % 2 == 1)))
