"""Why an IK target has the answer it has, as data: what the engine and the reach search
found, in SI (m, rad), with joints by index. :mod:`kincalc.analysis.words` renders each in the
user's units; nothing here is a sentence, and no command-line option is named.

Each reason is a ``NamedTuple``, not a frozen dataclass: eleven of them are defined on
every ``kincalc ik`` and a dataclass costs about 8 times as much to define (start-up).
Being tuples, two reasons of different kinds with equal fields compare equal: tell
them apart by type (``isinstance``, as :mod:`kincalc.analysis.words` dispatches).
"""

from __future__ import annotations

from typing import NamedTuple


class Found(NamedTuple):
    """``count`` solutions, ``within`` of them within the joint limits."""
    count: int
    within: int


class Blocked(NamedTuple):
    """Every one of ``count`` solutions breaks a limit; ``worst``: per joint that does,
    ``(joint index, the least amount any solution is beyond it)``, m or rad."""
    count: int
    worst: tuple


class Missed(NamedTuple):
    """A candidate that does not reach the target: its position error (m) and
    orientation error (rad, None when no orientation was asked for)."""
    position_error: float
    orientation_error: float | None


class Answered(NamedTuple):
    """A candidate that reaches the target but is answered by a listed solution: one double
    root split by rounding, or a point of the listed solution's continuum. ``joint``: the
    joint in which they differ most (scaled: rad, or over the arm's size), ``amount`` by how
    much (rad / m)."""
    joint: int
    amount: float


class ArmMissed(NamedTuple):
    """A combination of the values of the arm's ``joints`` (indices) that puts the point
    they place (``point``: its name, e.g. "wrist centre") ``distance`` (m) from where the
    target needs it; the joints after them do not move it."""
    point: str
    distance: float
    joints: tuple


class NoSolution(NamedTuple):
    """No candidate reaches the target; ``best``: the closest one's miss, or None when
    the arm reaches the position but cannot place its tool at this pose."""
    best: Missed | None = None


class OrientationOut(NamedTuple):
    """The position is reachable, the orientation (``what``: 'orientation', 'approach
    direction', or 'approach vector' for a tool configuration vector) is not, for a robot
    that controls ``controls``. ``rolls``: for a five-joint arm that reaches the position
    and the approach, ``((roll error rad, branch), ...)`` of each solution; otherwise
    ``closest``: ``(branch, orientation error rad)`` of the closest solution; neither where
    no candidate reached the position (this orientation moved the point the family
    places, and the position alone is within reach)."""
    what: str
    controls: str = ""
    rolls: tuple = ()
    closest: tuple | None = None


class Outside(NamedTuple):
    """Where a position out of reach of the geometry (limits ignored) lies, from the
    nearest reachable point ``distance`` (m) away: ``where`` is 'beyond-outer-reach',
    'inside-inner-void' or 'outside-workspace'. ``motion``: 'plane' or 'line' when the
    tool moves in one and the target is ``off`` (m) off it; ``target`` and ``reach``
    (m): the target's and the nearest point's distances from the base; ``radial`` the
    nearest point lies on the line from the base through the target (then ``reach`` is the
    arm's reach in the target's direction, and ``distance`` ``|target - reach|``)."""
    where: str
    distance: float
    motion: str | None = None
    off: float = 0.0
    target: float = 0.0
    reach: float = 0.0
    radial: bool = False


class OutOfReach(NamedTuple):
    """Out of reach: of the geometry (``outside``), or only within the joint limits
    (``outside`` None; the nearest position reachable within them ``distance`` m away)."""
    outside: Outside | None = None
    distance: float = 0.0


class NumericFound(NamedTuple):
    """One solution found numerically; ``restart`` > 0 when the start did not converge
    and that seeded restart did."""
    restart: int = 0


class NumericMissed(NamedTuple):
    """No solution found numerically from the start and ``restarts`` restarts; the
    closest configuration's miss, and ``controls`` (pose components the robot controls,
    < 6 when an orientation was asked of a robot that cannot set it all, else None)."""
    miss: Missed
    restarts: int
    controls: int | None = None


class NoRoot(NamedTuple):
    """A step that found no real root (``all_branches``): joint ``joint`` would need
    ``cos(q - phase) = need`` (phase rad) with ``|need| > 1``, so ``what`` is out of
    reach on that branch; ``reversed_chain`` when solved on the reversed chain."""
    joint: int
    phase: float
    need: float
    what: str
    reversed_chain: bool = False
