"""Per-robot caches for the solvers' robot-level constants."""

from __future__ import annotations

from functools import lru_cache, wraps


def per_robot(fn):
    """``fn(robot, *args)`` computed once per robot (and arguments), for the 64 robots used last.

    Robots hash by value (:class:`kincalc.model.Robot` is frozen); a robot-like object (or
    an argument) that does not hash is computed afresh on every call. A TypeError that
    ``fn`` itself raises goes to the caller (``fn`` is not run a second time).

    Parameters
    ----------
    fn : callable
        ``fn(robot, *args)``, the arguments hashable.

    Returns
    -------
    callable
        The cached function (shared results: do not modify them), with ``cache_clear()``.
    """
    cached = lru_cache(maxsize=64)(fn)

    @wraps(fn)
    def call(robot, *args):
        try:
            return cached(robot, *args)
        except TypeError:
            try:                           # an unhashable robot-like object or argument?
                hash((robot, *args))
            except TypeError:
                return fn(robot, *args)
            raise                          # fn's own
    call.cache_clear = cached.cache_clear
    return call
