"""Robots as written: the DH, modified DH and POE conventions and conversions between
them (:mod:`~kincalc.conventions.conversion`), the robot-file reader, the one YAML reader
with line numbers (:mod:`~kincalc.conventions.reader`), the robot-file writer
(:mod:`~kincalc.conventions.writer`) and the bundled library
(:mod:`~kincalc.conventions.library`).

``convert``, ``dh_to_mdh``, ``mdh_to_dh`` and ``to_poe`` are importable from here; they
load numpy when first used (the command line's ``--help`` imports this package's
library, not the conversions).
"""

__all__ = ["convert", "dh_to_mdh", "mdh_to_dh", "to_poe"]


def __getattr__(name):
    if name in __all__:
        from . import conversion
        return getattr(conversion, name)
    raise AttributeError(f"module 'kincalc.conventions' has no attribute {name!r}")
