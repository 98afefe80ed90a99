"""Robot files (YAML) -> :class:`~kincalc.model.Robot`: the file's keys, read by
:class:`RobotReader` on the node reader of :mod:`~.nodes`, with ``file:line`` errors naming
the field, and converted to SI (m, rad)."""

from __future__ import annotations

import re
import unicodedata

import numpy as np

from ...errors import RobotFileError
from ...limits import (MAX_FILE_BYTES, MAX_JOINTS, MAX_NAME, TooLarge, cut, os_error_text,
                       printable, quote, read_bounded, size_text)
from ...model import CONVENTIONS, JOINT_TYPES, Joint, Robot
from ...units import ANGLE_UNITS, LENGTH_UNITS
from .nodes import compose_yaml
from .values import Reader

TOP_KEYS = {
    "name": True, "convention": True, "units": True, "joints": True,
    "title": False, "source": False, "notes": False, "parameters": False,
    "base": False, "tool": False, "home": False,
}
DH_JOINT_KEYS = {"name": True, "type": True, "alpha": True, "a": True, "d": True,
                 "theta": True, "limits": False}
POE_JOINT_KEYS = {"name": True, "type": True, "axis": True, "point": True, "limits": False}
NAME_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_.\-]*$")


def joint_name_problem(name: str) -> str | None:
    """Why ``name`` cannot name a joint, or None: it is empty, longer than
    :data:`~kincalc.limits.MAX_NAME`, or holds a character that is not printable (a newline
    would split a table's line; a joint's name heads a column of every table)."""
    if not name.strip():
        return "must not be empty"
    if len(name) > MAX_NAME:
        return f"is {len(name)} characters long; kincalc takes names of up to {MAX_NAME}"
    if not name.isprintable():
        bad = next(c for c in name if not c.isprintable())
        what = "a control character" if unicodedata.category(bad) == "Cc" else \
            "a space other than ' '" if unicodedata.category(bad).startswith("Z") else \
            "a character that is not printed"
        return f"must not hold {what} (it holds U+{ord(bad):04X})"
    return None


def load_robot_file(path, display_name: str | None = None) -> Robot:
    """Read and validate a robot file.

    Parameters
    ----------
    path : str or os.PathLike
        The YAML file.
    display_name : str, optional
        How to name the file in messages (defaults to ``str(path)``).

    Returns
    -------
    Robot
        The robot, SI inside (m, rad) whatever the file's units, with ``path`` set to
        ``str(path)``.

    Raises
    ------
    RobotFileError
        Unreadable file, YAML syntax error, or any invalid field.
    """
    shown = display_name or str(path)
    robot = parse_robot_text(read_text(path, shown, "a robot file"), shown)
    object.__setattr__(robot, "path", str(path))
    return robot


def read_text(path, shown: str, what: str, error=RobotFileError,
              limit: int = MAX_FILE_BYTES) -> str:
    """The UTF-8 text of ``path``, at most ``limit`` bytes of it (read through
    :func:`kincalc.limits.read_bounded`, so an endless device is refused, not read).

    Parameters
    ----------
    path : str or os.PathLike
        The file, or ``"-"`` for standard input.
    shown : str
        How to name the file in messages.
    what : str
        The kind of file, for messages (e.g. "a robot file").
    error : callable
        ``error(shown, line, message)`` gives the exception to raise
        (:class:`~kincalc.errors.RobotFileError` by default).
    limit : int
        The most bytes accepted (:data:`~kincalc.limits.MAX_FILE_BYTES` by default).

    Returns
    -------
    str

    Raises
    ------
    RobotFileError
        (Or ``error``.) Larger than ``limit``, a directory, unreadable (no such file,
        permission, ...), an invalid name, or not UTF-8. Only a failure to decode has a
        line: every other message is about the file, never its content.
    """
    try:
        data = read_bounded(path, limit)
    except TooLarge:
        raise error(shown, None, f"the file is larger than {size_text(limit)}, kincalc's "
                                 f"limit for {what}") from None
    except IsADirectoryError:
        raise error(shown, None, f"is a directory, not {what}") from None
    except OSError as exc:
        reason = os_error_text(exc)
        raise error(shown, None, reason if reason == "no such file" else
                    f"cannot read: {reason}") from None
    except ValueError:                       # a NUL character in the name
        raise error(shown, None, "cannot read: not a valid file name") from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[:exc.start].count(b"\n") + 1
        raise error(shown, line, f"not UTF-8 text (byte 0x{data[exc.start]:02x} "
                                 "cannot be decoded; save the file as UTF-8)") from None


def parse_robot_text(text: str, file: str = "<robot>") -> Robot:
    """Parse the YAML ``text`` of a robot file.

    Parameters
    ----------
    text : str
        The robot file's text.
    file : str
        How to name it in messages.

    Returns
    -------
    Robot
        The robot, SI inside (m, rad) whatever the file's units.

    Raises
    ------
    RobotFileError
        Invalid YAML or any invalid field (``file:line: [joint k (name): ]message``).
    """
    root = compose_yaml(text, file)
    return RobotReader(file).robot(root)


class RobotReader(Reader):
    """The robot file's top level, parameters, joints and home values, on the checked
    values of :class:`~.nodes.Reader`."""

    def robot(self, root) -> Robot:
        """The robot of a file's root node.

        Sets ``self.L`` (m per file length unit) and ``self.A`` (rad per file angle unit)
        from the file's ``units`` and converts every value with them. A poe file's
        ``tool`` becomes the robot's ``M`` (its ``tool`` is then the identity).

        Parameters
        ----------
        root : yaml.Node
            From :func:`~.nodes.compose_yaml`.

        Returns
        -------
        Robot
            SI inside (m, rad); ``parameters`` in the file's units, ``expressions`` as
            written (none for poe).

        Raises
        ------
        RobotFileError
            (By :meth:`fail`.) A missing, unknown or invalid key, e.g. an invalid name,
            convention or unit, a poe file without ``tool``, or as :meth:`joint_list`,
            :meth:`read_parameters`, :meth:`pose`, :meth:`home_values`.
        """
        top = self.document(root, "the robot file", TOP_KEYS)
        name = self.text(top["name"], "'name'")
        if not name.strip():
            self.fail(top["name"], "'name' must not be empty")
        if len(name) > MAX_NAME:
            self.fail(top["name"], f"'name' is {len(name)} characters long; kincalc takes names "
                                   f"of up to {MAX_NAME}")
        if not NAME_RE.match(name):
            self.fail(top["name"], f"'name' {self.shown(top['name'])} must start with a letter "
                                   "(A-Z, a-z) and contain only such letters, digits, '_', '-' "
                                   "and '.'")
        convention = self.text(top["convention"], "'convention'")
        if convention not in CONVENTIONS:
            self.fail(top["convention"], f"'convention' must be one of {', '.join(CONVENTIONS)} "
                                         "(dh = standard, mdh = modified/Craig), not "
                                         f"{self.shown(top['convention'])}")
        units = self.mapping(top["units"], "'units'", {"length": True, "angle": True})
        length_unit = self.text(units["length"], "'units.length'")
        if length_unit not in LENGTH_UNITS:
            self.fail(units["length"], f"'units.length' must be one of {', '.join(LENGTH_UNITS)}, "
                                       f"not {self.shown(units['length'])}")
        angle_unit = self.text(units["angle"], "'units.angle'")
        if angle_unit not in ANGLE_UNITS:
            self.fail(units["angle"], f"'units.angle' must be one of {', '.join(ANGLE_UNITS)}, "
                                      f"not {self.shown(units['angle'])}")
        self.L = LENGTH_UNITS[length_unit]
        self.A = ANGLE_UNITS[angle_unit]

        if "parameters" in top:
            self.read_parameters(top["parameters"])

        joints = self.joint_list(top["joints"], convention)

        base = self.pose(top["base"], "'base'") if "base" in top else np.eye(4)
        if convention == "poe" and "tool" not in top:
            self.fail(root, "'tool' is missing: a poe robot needs the tool pose at q = 0 (M)")
        tool = self.pose(top["tool"], "'tool'") if "tool" in top else np.eye(4)
        # a poe file's tool is M, the flange (= tool) pose at q = 0
        tool, M = (np.eye(4), tool) if convention == "poe" else (tool, None)

        home = self.home_values(top["home"], joints) if "home" in top else None

        def opt_text(key):
            return self.text(top[key], f"'{key}'").strip() if key in top else ""

        return Robot(
            name=name, convention=convention, joints=tuple(joints), base=base, tool=tool, M=M,
            home=home, title=opt_text("title"), source=opt_text("source"),
            notes=opt_text("notes"), length_unit=length_unit, angle_unit=angle_unit,
            parameters=tuple(self.params.items()),
            expressions=tuple(self.exprs) if convention != "poe" else (),
        )

    def read_parameters(self, pnode) -> None:
        """The file's ``parameters`` (name -> number, in the file's units) into
        ``self.params``, for the expressions of the joints' entries.

        Parameters
        ----------
        pnode : yaml.Node
            The ``parameters`` mapping.

        Raises
        ------
        RobotFileError
            (By :meth:`fail`.) Not a mapping, a key that is not an identifier or is
            ``pi``, a name given twice, or a value as :meth:`number` refuses it.
        """
        import yaml
        if not isinstance(pnode, yaml.MappingNode):
            self.fail(pnode, "'parameters' must be a mapping of names to numbers")
        for knode, vnode in pnode.value:
            if not isinstance(knode, yaml.ScalarNode):
                self.fail(knode, "'parameters': keys must be plain names")
            pname = knode.value
            if not re.match(r"^[A-Za-z_][A-Za-z0-9_]*$", pname) or pname == "pi":
                self.fail(knode, f"parameter name {quote(pname)} must be an identifier "
                                 "other than 'pi'")
            if pname in self.params:
                self.fail(knode, f"parameter {quote(pname)} is given twice")
            self.params[pname] = self.number(vnode, f"parameter {quote(pname)}")

    def joint_list(self, node, convention: str) -> list:
        """The ``joints`` entries, in order, each with a name no other joint has.

        Parameters
        ----------
        node : yaml.Node
            The ``joints`` list.
        convention : {'dh', 'mdh', 'poe'}
            Which keys a joint has.

        Returns
        -------
        list of Joint
            SI (m, rad), as :meth:`joint_entry`.

        Raises
        ------
        RobotFileError
            (By :meth:`fail`, naming the joint.) Not a list, empty, a name used twice, or
            as :meth:`joint_entry`.
        """
        jnodes = self.sequence(node, "'joints'")
        if not jnodes:
            self.fail(node, "'joints' is empty; a robot needs at least one joint")
        if len(jnodes) > MAX_JOINTS:
            self.fail(node, f"'joints' lists {len(jnodes)} joints; kincalc takes robots of up "
                            f"to {MAX_JOINTS}")
        joints = []
        seen: dict[str, int] = {}
        for k, jnode in enumerate(jnodes, start=1):
            self.joint, self.joint_name = k, None
            joint = self.joint_entry(jnode, convention)
            if joint.name in seen:
                self.fail(jnode, f"name {quote(joint.name)} is already used by joint "
                                 f"{seen[joint.name]}")
            seen[joint.name] = k
            joints.append(joint)
        self.joint, self.joint_name = None, None
        return joints

    def home_values(self, hnode, joints) -> np.ndarray:
        """The ``home`` joint values, one per joint, each within its limits.

        Parameters
        ----------
        hnode : yaml.Node
            The ``home`` list, in the file's units.
        joints : sequence of Joint
            The robot's joints (SI), for their types and limits.

        Returns
        -------
        ndarray (n,)
            rad (revolute) / m (prismatic).

        Raises
        ------
        RobotFileError
            (By :meth:`fail`.) Not a list of n numbers, or a value outside its joint's
            limits (by more than 1e-12, SI).
        """
        items = self.sequence(hnode, "'home'")
        if len(items) != len(joints):
            self.fail(hnode, f"'home' has {len(items)} values but the robot has {len(joints)} joints")
        home = np.empty(len(joints))
        for k, (v, j) in enumerate(zip(items, joints)):
            home[k] = self.number(v, f"'home'[{k}]") * (self.A if j.revolute else self.L)
            if j.limits is not None and not (j.limits[0] - 1e-12 <= home[k] <= j.limits[1] + 1e-12):
                self.fail(v, f"'home' value for joint {k + 1} ({j.name}) is outside its limits")
        return home

    def joint_entry(self, node, convention: str) -> Joint:
        """One ``joints`` entry; for dh/mdh, its fields written as expressions go to
        ``self.exprs``.

        Parameters
        ----------
        node : yaml.Node
            The joint's mapping.
        convention : {'dh', 'mdh', 'poe'}
            dh/mdh: keys ``name type alpha a d theta [limits]``; poe: ``name type axis
            point [limits]``.

        Returns
        -------
        Joint
            SI: ``alpha``, ``theta`` in rad and ``a``, ``d`` in m; poe ``axis`` normalised
            and ``point`` in m (both in the base frame at q = 0); ``limits`` in rad
            (revolute) or m (prismatic).

        Raises
        ------
        RobotFileError
            (By :meth:`fail`.) A missing or unknown key, an empty name, a type other than
            revolute/prismatic, limits with lower > upper, a poe axis that is zero or not
            of unit norm (to 1e-6), or a value as :meth:`number` refuses it.
        """
        import yaml
        keys = POE_JOINT_KEYS if convention == "poe" else DH_JOINT_KEYS
        if isinstance(node, yaml.MappingNode):
            first, last = self.lines(node)
            for knode, vnode in node.value:
                # (for messages; a name over several lines is not quoted: the joint's
                # number names it, and a message shows nothing of other lines; nor is an
                # alias's text, written on a line outside the joint: '*s' of '&s secret')
                if knode.value == "name" and isinstance(vnode, yaml.ScalarNode) \
                        and self.on_one_line(vnode) \
                        and first <= self.lines(vnode)[0] <= last:
                    self.joint_name = cut(printable(vnode.value))
        fields = self.mapping(node, "the joint", keys)
        name = self.text(fields["name"], "'name'")
        if joint_name_problem(name):
            self.fail(fields["name"], f"'name' {joint_name_problem(name)}")
        jtype = self.text(fields["type"], "'type'")
        if jtype not in JOINT_TYPES:
            self.fail(fields["type"], "'type' must be revolute or prismatic, not "
                                      f"{self.shown(fields['type'])}")
        revolute = jtype == "revolute"
        limits = None
        if "limits" in fields:
            lo, hi = self.vector(fields["limits"], "'limits'", 2) * (self.A if revolute else self.L)
            if lo > hi:
                self.fail(fields["limits"], "'limits' must be [lower, upper] with lower <= upper")
            limits = (float(lo), float(hi))
        if convention == "poe":
            axis = self.vector(fields["axis"], "'axis'", 3)
            norm = float(np.linalg.norm(axis))
            if norm < 1e-9:
                self.fail(fields["axis"], "'axis' must not be the zero vector")
            if abs(norm - 1.0) > 1e-6:
                self.fail(fields["axis"], f"'axis' must be a unit vector (its norm is {norm:.6g})")
            point = self.vector(fields["point"], "'point'", 3) * self.L
            return Joint(name=name, type=jtype, axis=tuple(axis / norm), point=tuple(point),
                         limits=limits)
        self.exprs.append(tuple(
            (key, fields[key].value.strip()) for key in ("alpha", "a", "d", "theta")
            if isinstance(fields[key], yaml.ScalarNode)
            and fields[key].tag.rsplit(":", 1)[-1] not in ("int", "float")))
        return Joint(
            name=name, type=jtype,
            alpha=self.number(fields["alpha"], "'alpha'") * self.A,
            a=self.number(fields["a"], "'a'") * self.L,
            d=self.number(fields["d"], "'d'") * self.L,
            theta=self.number(fields["theta"], "'theta'") * self.A,
            limits=limits,
        )

