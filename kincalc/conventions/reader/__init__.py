"""Robot files (YAML) -> :class:`~kincalc.model.Robot`, with file:line errors.

This is the only package that imports yaml: :mod:`~.nodes` (YAML composed with line
numbers, the nodes' shape) and :mod:`~.values` (their values: numbers, expressions,
poses), shared with homework sheets, and :mod:`~.robot_file` (the robot file's keys).
The format is described in the README ("Robot files") and in ``man/kincalc.1``.
Every problem is reported as a :class:`~kincalc.errors.RobotFileError` naming
the file, the line and the field, for example::

    arm.yaml:12: joint 3 (q3): 'alpha' is missing

Values are converted to SI (m, rad) here and nowhere else.
"""

from __future__ import annotations

from ...limits import MAX_MAGNITUDE  # noqa: F401 (kincalc.conventions.reader.MAX_MAGNITUDE)
from .nodes import NodeReader, compose_yaml, node_line
from .robot_file import RobotReader, load_robot_file, parse_robot_text, read_text
from .values import Reader

__all__ = ["NodeReader", "Reader", "RobotReader", "compose_yaml", "load_robot_file", "node_line",
           "parse_robot_text", "read_text"]
