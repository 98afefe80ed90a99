"""URDF files -> :class:`~kincalc.model.Robot`: the kinematic subset, over the standard
library, with file:line errors.

A URDF (ROS's Unified Robot Description Format, https://wiki.ros.org/urdf/XML) is a tree
of ``<link>`` elements joined by ``<joint>`` elements. kincalc reads what kinematics needs
and nothing else:

* ``<joint name type>`` of type ``revolute``, ``continuous`` (a revolute joint without
  limits), ``prismatic`` or ``fixed`` (folded into the constant transforms); a ``floating``
  or ``planar`` joint, or a ``<mimic>`` on the chosen chain, is refused by name;
* its ``<parent link>``, ``<child link>``, ``<origin xyz rpy>`` (the child frame in the
  parent frame; rpy fixed X-Y-Z, ``R = Rz(y) Ry(p) Rx(r)``, as kincalc's RPY), ``<axis
  xyz>`` (in the joint frame, default ``1 0 0``) and ``<limit lower upper>`` (rad / m);
* everything else (visuals, collisions, meshes and their ``package://`` references,
  inertias, transmissions, gazebo tags) is ignored, never fetched.

The robot is the serial chain from a base link to a tip link, as a ``poe`` robot: each
joint's axis and a point on it in the base link's frame at q = 0, and ``M`` the tip
link's pose there. Defaults: the base is the tree's root; the tip is the end of the one
chain of moving joints (the leaf it leads to when only one does, else the child link
of its last moving joint); a tree whose moving joints branch (two fingers, two arms)
names its leaves and asks for ``tip_link``.

URDF is untrusted XML: it is parsed by expat with a document type declaration refused
(so no entity, internal or external, is ever expanded) and read through
:func:`kincalc.limits.read_bounded` with the size limit of robot files.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from ..errors import RobotFileError
from ..limits import MAX_JOINTS, MAX_MAGNITUDE, MAX_NAME, parse_decimal, quote
from ..model import Joint, Robot
from ..spatial import invert_transform, matrix_from_rpy, transform
from .reader import read_text
from .reader.robot_file import NAME_RE, joint_name_problem
from .urdf_xml import Element, parse_xml

MOVING = {"revolute": "revolute", "continuous": "revolute", "prismatic": "prismatic"}
REFUSED = {"floating": "a floating joint (6 DOF) is not a serial joint",
           "planar": "a planar joint (3 DOF) is not a serial joint"}


@dataclass(frozen=True)
class UrdfJoint:
    """A ``<joint>`` as read: the child frame in the parent frame ``origin (4, 4)`` (m),
    the unit ``axis (3,)`` in the joint frame, ``limits`` (rad / m) or None."""

    name: str
    type: str
    parent: str
    child: str
    origin: np.ndarray
    axis: np.ndarray
    limits: tuple | None
    mimic: bool
    line: int


class _Reader:
    """The checked values of one URDF's elements; every failure a RobotFileError naming
    the file, the line, the element and the attribute."""

    def __init__(self, file: str):
        self.file = file

    def fail(self, node: Element, message: str, attr: str | None = None):
        """Raise the error ``message`` at ``node``, on the line of its attribute ``attr``
        when given."""
        line = node.lines_of(attr)[0] if attr is not None else node.line
        raise RobotFileError(self.file, line, message)

    @staticmethod
    def shown(node: Element, name: str) -> str:
        """Attribute ``name`` quoted for a message, or, when its value runs over several
        lines, those lines only (a message shows the file's line it names, no other)."""
        first, last = node.lines_of(name)
        return f"a value over lines {first}-{last}" if last > first else quote(node.attrs[name])

    def one(self, node: Element, tag: str, where: str):
        """``node``'s child element ``tag``, or None; two of them are an error (URDF has
        one, and which of two a reader takes is not defined)."""
        found = [c for c in node.children if c.tag == tag]
        if len(found) > 1:
            self.fail(found[1], f"{where} has a second <{tag}> (the first on line "
                                f"{found[0].line}): a joint has one")
        return found[0] if found else None

    def attr(self, node: Element, name: str, default=None) -> str:
        if name in node.attrs:
            return node.attrs[name]
        if default is None:
            self.fail(node, f"<{node.tag}> has no '{name}' attribute")
        return default

    def name(self, node: Element, attr: str = "name") -> str:
        """A name attribute (a link's, a joint's, the link a joint names), on one line: the
        messages quote names, and a message shows no line of the file but the one it names."""
        value = self.attr(node, attr)
        first, last = node.lines_of(attr)
        if last > first:
            self.fail(node, f"<{node.tag} {attr}> runs on over lines {first}-{last}: a name "
                            "is one line", attr)
        if node.tag != "joint":     # a link's (a joint's is checked with its type)
            if not value.strip():
                self.fail(node, f"<{node.tag} {attr}> is empty: a link has a name", attr)
            if not value.isprintable():         # (a character reference: &#13;, &#27;)
                self.fail(node, f"link {quote(value)}: its name must not hold a control "
                                "character (a newline, a tab, ...)", attr)
        return value

    def numbers(self, node: Element, name: str, count: int, default: str) -> np.ndarray:
        text = self.attr(node, name, default)
        parts = text.split()
        try:
            values = [parse_decimal(p) for p in parts]
        except ValueError:
            hint = " (an unexpanded xacro expression? expand the file first)" \
                if "$" in text else ""
            self.fail(node, f"<{node.tag} {name}> {self.shown(node, name)} is not "
                            f"{_count(count)}{hint}", name)
        if len(values) != count:
            got = "an empty value" if not values else f"{len(values)}"
            self.fail(node, f"<{node.tag} {name}> needs {_count(count)}, got {got}", name)
        if not all(math.isfinite(v) and abs(v) <= MAX_MAGNITUDE for v in values):
            self.fail(node, f"<{node.tag} {name}> holds a number that is not finite or is "
                            f"larger than {MAX_MAGNITUDE:g}", name)
        return np.array(values)

    def joint(self, node: Element) -> UrdfJoint:
        name = self.name(node)
        kind = self.attr(node, "type")
        where = f"joint {quote(name)}"
        if kind not in MOVING and kind != "fixed" and kind not in REFUSED:
            self.fail(node, f"{where}: type {self.shown(node, 'type')} is not a URDF joint "
                            "type (revolute, continuous, prismatic, fixed, floating, planar)",
                      "type")
        links = {}
        for tag in ("parent", "child"):
            sub = self.one(node, tag, where)
            if sub is None:
                self.fail(node, f"{where} has no <{tag}>")
            links[tag] = self.name(sub, "link")
        origin = self.one(node, "origin", where)
        T = np.eye(4)
        if origin is not None:
            xyz = self.numbers(origin, "xyz", 3, "0 0 0")
            rpy = self.numbers(origin, "rpy", 3, "0 0 0")
            T = transform(matrix_from_rpy(rpy), xyz)
        axis = np.array([1.0, 0.0, 0.0])
        sub = self.one(node, "axis", where)
        if sub is not None and kind in MOVING:
            axis = self.numbers(sub, "xyz", 3, "1 0 0")
            norm = float(np.linalg.norm(axis))
            if norm < 1e-9:
                self.fail(sub, f"{where}: <axis xyz> is the zero vector")
            axis = axis / norm
        limits = None
        sub = self.one(node, "limit", where)
        if kind in ("revolute", "prismatic"):
            if sub is None:
                self.fail(node, f"{where}: a {kind} joint needs <limit lower upper>"
                                + (" (a revolute joint without limits is 'continuous')"
                                   if kind == "revolute" else ""))
            missing = [a for a in ("lower", "upper") if a not in sub.attrs]
            if missing:     # (URDF's default 0 would hold the joint still)
                self.fail(sub, f"{where}: <limit> has no {' or '.join(missing)}: a {kind} "
                               "joint needs both (a revolute joint without limits is "
                               "'continuous')")
            lo = self.numbers(sub, "lower", 1, "0")[0]
            hi = self.numbers(sub, "upper", 1, "0")[0]
            if lo > hi:
                self.fail(sub, f"{where}: <limit> lower {lo:g} is above upper {hi:g}")
            limits = (float(lo), float(hi))
        return UrdfJoint(name, kind, links["parent"], links["child"], T, axis, limits,
                         node.first("mimic") is not None, node.line)


def _count(n: int) -> str:
    return "a number" if n == 1 else f"{n} numbers"


def load_urdf(path, display_name: str | None = None, base_link: str | None = None,
              tip_link: str | None = None) -> Robot:
    """Read a URDF file as a ``poe`` :class:`~kincalc.model.Robot`.

    Parameters
    ----------
    path : str or Path
        The ``.urdf`` file.
    display_name : str, optional
        How errors name the file (default: ``path``).
    base_link, tip_link : str, optional
        The chain's first and last link (defaults: module docstring).

    Returns
    -------
    Robot
        Convention ``poe``, frame 0 the base link's frame: the joints' axes and points in
        it at q = 0 (m), ``M`` the tip link's pose in it at q = 0, limits in rad / m,
        display units m and deg.

    Raises
    ------
    RobotFileError
        An unreadable file, XML that is not well formed or has a DOCTYPE, an element or
        attribute that is missing or wrong (file:line, the element and attribute named),
        a refused joint on the chain, or a chain that cannot be chosen.
    """
    shown = display_name or str(path)
    robot = parse_urdf_text(read_text(path, shown, "a URDF file"), shown, base_link, tip_link,
                            stem=_stem(path))
    object.__setattr__(robot, "path", str(path))
    return robot


def _stem(path) -> str:
    from pathlib import Path
    return Path(str(path)).name.split(".")[0]


def parse_urdf_text(text: str, file: str = "<urdf>", base_link: str | None = None,
                    tip_link: str | None = None, stem: str = "urdf") -> Robot:
    """A URDF's text as a ``poe`` robot (:func:`load_urdf` without the file).

    Parameters
    ----------
    text : str
        The URDF.
    file : str
        How errors name it.
    base_link, tip_link : str, optional
        The chain's first and last link (defaults: module docstring).
    stem : str
        The robot's name when the URDF's own is not a valid robot name.

    Returns
    -------
    Robot
        As :func:`load_urdf`.

    Raises
    ------
    RobotFileError
        As :func:`load_urdf`.
    """
    root = parse_xml(text, file)
    reader = _Reader(file)
    links = {}
    for node in root.children:
        if node.tag == "link":
            name = reader.name(node)
            if name in links:
                reader.fail(node, f"link {quote(name)} is defined twice")
            links[name] = node
    joints, by_child = {}, {}
    for node in root.children:
        if node.tag != "joint":
            continue
        j = reader.joint(node)
        if j.name in joints:
            reader.fail(node, f"joint {quote(j.name)} is defined twice")
        for end in (j.parent, j.child):
            if end not in links:
                reader.fail(node, f"joint {quote(j.name)} names link {quote(end)}, which "
                                  "is not defined")
        if j.child in by_child:
            reader.fail(node, f"link {quote(j.child)} is the child of two joints "
                              f"({quote(by_child[j.child].name)} and {quote(j.name)})")
        joints[j.name] = j
        by_child[j.child] = j
    if not links:
        reader.fail(root, "the URDF has no <link>")
    chain = _chain(reader, root, links, joints, by_child, base_link, tip_link)
    between = "" if base_link is None and tip_link is None else (
        f" from {'the root' if base_link is None else 'link ' + quote(base_link)} to "
        f"{'its tip' if tip_link is None else 'link ' + quote(tip_link)}")
    return _robot(reader, root, chain, stem, between)


def _chain(reader, root, links, joints, by_child, base_link, tip_link) -> list:
    """The joints from the base link to the tip link, in order, each with whether it is
    walked upwards (child to parent: a fixed joint above the base link, as ROS's ``base``
    frame hangs off ``base_link``)."""
    roots = [name for name in links if name not in by_child]
    if not roots:
        reader.fail(root, "the links form a loop: no link is the root of the tree")
    if len(roots) > 1:
        reader.fail(root, f"the URDF is not one tree: {len(roots)} links have no parent "
                          f"({_names(roots)})")
    children: dict[str, list[UrdfJoint]] = {}
    for j in joints.values():
        children.setdefault(j.parent, []).append(j)
    reached, todo = {roots[0]}, [roots[0]]
    while todo:
        for j in children.get(todo.pop(), []):
            reached.add(j.child)
            todo.append(j.child)
    if len(reached) < len(links):
        lost = [name for name in links if name not in reached]
        reader.fail(root, f"the joints form a loop: links {_names(lost)} are not below the "
                          f"root link {quote(roots[0])}")
    base = roots[0] if base_link is None else base_link
    for name, what in ((base, "--base-link"), (tip_link, "--tip-link")):
        if name is not None and name not in links:
            reader.fail(root, f"{what} {quote(name)} is not a link of this URDF "
                              f"({_names(list(links))})")
    if tip_link is None:
        tip_link = _default_tip(reader, root, base, children, by_child)

    def up_to_root(link):
        out = [link]
        while out[-1] in by_child:
            out.append(by_child[out[-1]].parent)
        return out

    rising, falling = up_to_root(base), up_to_root(tip_link)
    meet = next(link for link in rising if link in set(falling))
    # from the base up to where the two meet (fixed joints only, walked backwards), then down
    up = [by_child[link] for link in rising[:rising.index(meet)]]
    down = [by_child[link] for link in falling[:falling.index(meet)]][::-1]
    for j in up:
        if j.type != "fixed":
            reader.fail(root, f"link {quote(tip_link)} is not below link {quote(base)}, and the "
                              f"way up from {quote(base)} runs through the moving joint "
                              f"{quote(j.name)}: choose a base link above it")
    path = [(j, True) for j in up] + [(j, False) for j in down]
    for j, _ in path:
        if j.type in REFUSED:
            raise RobotFileError(reader.file, j.line, f"joint {quote(j.name)}: "
                                 f"{REFUSED[j.type]}; kincalc reads serial chains")
        if j.mimic and j.type in MOVING:
            raise RobotFileError(reader.file, j.line, f"joint {quote(j.name)} is a <mimic> "
                                 "joint (it moves with another): not supported on the chain")
        if j.type in MOVING and joint_name_problem(j.name):
            raise RobotFileError(reader.file, j.line, f"joint {quote(j.name)}: its name "
                                 f"{joint_name_problem(j.name)}")
    return path


def _default_tip(reader, root, base: str, children, by_child) -> str:
    """The tip when none is given: the end of the one chain of moving joints below
    ``base`` (module docstring), or, for a base with none below it that hangs off the tree
    by fixed joints (ROS's ``base`` under ``base_link``), below the first link above it
    that has one. Each link is visited once."""

    def below(link, through_moving=False):
        """The moving joints first met below ``link`` through fixed joints, and the leaves
        reached (through fixed joints only, or through any)."""
        moving, leaves, todo = [], [], [link]
        while todo:                   # a stack, not recursion: a URDF may be deep
            here = todo.pop()
            joints = children.get(here, [])
            if not joints:
                leaves.append(here)
            for j in joints:
                if j.type != "fixed":
                    moving.append(j)
                if j.type == "fixed" or through_moving:
                    todo.append(j.child)
        return moving, leaves

    link = base
    while not below(link)[0] and link in by_child and by_child[link].type == "fixed":
        link = by_child[link].parent
    while True:
        moving, leaves = below(link)
        if not moving:
            # the chain ends here: its one leaf, or this link when fixed frames branch
            return leaves[0] if len(leaves) == 1 else link
        if len(moving) > 1:
            reader.fail(root, f"the tree branches below link {quote(link)} into "
                              f"{len(moving)} chains of moving joints; choose one with "
                              f"--tip-link (its leaves: {_names(sorted(below(link, True)[1]))})")
        link = moving[0].child


def _names(names: list[str], most: int = 8) -> str:
    shown = ", ".join(quote(n) for n in names[:most])
    return shown + (f", ... ({len(names)} in all)" if len(names) > most else "")


def _robot(reader, root, chain: list, stem: str, between: str = "") -> Robot:
    """The poe robot of ``chain``: frames accumulated from the base link at q = 0
    (``between``: the chain's ends as the user chose them, for a message)."""
    T = np.eye(4)
    out = []
    for j, upwards in chain:
        if upwards:
            T = T @ invert_transform(j.origin)
            continue
        T = T @ j.origin                  # the joint frame = the child link's frame at q = 0
        if j.type == "fixed":
            continue
        axis = T[:3, :3] @ j.axis
        out.append(Joint(name=j.name, type=MOVING[j.type], axis=tuple(axis.tolist()),
                         point=tuple(T[:3, 3].tolist()), limits=j.limits))
    if not out:
        reader.fail(root, f"the chain{between} has no moving joint")
    if len(out) > MAX_JOINTS:
        reader.fail(root, f"the chain has {len(out)} moving joints; kincalc takes robots of up "
                          f"to {MAX_JOINTS}")
    name = root.attrs.get("name", "")
    if not NAME_RE.match(name) or len(name) > MAX_NAME:       # (the file's name, then)
        name = re.sub(r"[^A-Za-z0-9_.\-]", "_", stem) or "urdf"
        name = (name if name[0].isalpha() else "urdf_" + name)[:MAX_NAME]
    lo = np.array([j.limits[0] if j.limits else -np.inf for j in out])
    hi = np.array([j.limits[1] if j.limits else np.inf for j in out])
    first, last = chain[0], chain[-1]
    links = (f"links {quote(first[0].child if first[1] else first[0].parent)} -> "
             f"{quote(last[0].child)}")
    return Robot(name=name, convention="poe", joints=tuple(out), M=T,
                 home=np.clip(0.0, lo, hi), title=f"from URDF, {links}",
                 source=f"URDF robot {quote(root.attrs.get('name', ''))}, {links}",
                 length_unit="m", angle_unit="deg")
