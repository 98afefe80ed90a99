"""The one YAML reader with line numbers, part one: YAML text composed into nodes (plain
tags only, errors with their line), and :class:`NodeReader`, which walks the nodes
checking their shape with ``file:line`` errors. :mod:`~.values` reads the values on it;
robot files and homework sheets both read through the two.
"""

from __future__ import annotations

import difflib

from ...errors import RobotFileError
from ...limits import quote


def compose_yaml(text: str, file: str):
    """The node tree of the YAML ``text`` (plain tags only, see :func:`_plain_tags`), for
    :class:`Reader`.

    Parameters
    ----------
    text : str
        The file's text.
    file : str
        How to name the file in messages.

    Returns
    -------
    yaml.Node
        The root node (nothing is constructed from it).

    Raises
    ------
    RobotFileError
        Invalid YAML (with the line where the mistake starts, when known), a control
        character, nesting too deep, an empty file, or a tag other than plain YAML's.
    """
    import yaml
    loader_cls = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
    try:
        node = yaml.compose(text, Loader=loader_cls)
    except yaml.MarkedYAMLError as exc:
        raise RobotFileError(file, *_yaml_error(exc)) from None
    except yaml.reader.ReaderError as exc:
        line = text[:exc.position].count("\n") + 1 if isinstance(exc.position, int) else None
        what = f"#x{exc.character:04x}" if isinstance(exc.character, int) else repr(exc.character)
        raise RobotFileError(file, line, f"not valid YAML: character {what} is not allowed "
                                         "(control characters cannot appear in YAML)") from None
    except yaml.YAMLError as exc:
        raise RobotFileError(file, None, f"not valid YAML: {_one_line(str(exc))[:200]}") from None
    except RecursionError:               # the pure-Python composer on deep nesting
        raise RobotFileError(file, None, "not valid YAML: nested too deeply") from None
    if node is None:
        raise RobotFileError(file, 1, "the file is empty")
    _plain_tags(node, file)
    return node


#: the tags of plain YAML: text, numbers, yes/no, null, lists and mappings
PLAIN_TAGS = {f"tag:yaml.org,2002:{t}" for t in ("str", "int", "float", "bool", "null", "seq",
                                                  "map")}


def _plain_tags(root, file: str):
    """Refuse any other tag (``!!python/object``, ``!!binary``, ``!custom``): nothing is
    ever constructed from one, but a file that has one is not what it looks like. Each
    node is visited once, so an alias bomb costs its text's length, not its size."""
    import yaml
    seen, todo = set(), [root]
    while todo:
        node = todo.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        if node.tag not in PLAIN_TAGS:
            tag = node.tag.replace("tag:yaml.org,2002:", "!!")
            what = ("a merge key '<<' is not allowed; write its keys out" if tag == "!!merge"
                    else f"the tag {quote(tag)} is not allowed")
            raise RobotFileError(file, node_line(node), what + " (kincalc reads plain YAML: "
                                 "text, numbers, lists, mappings)")
        if isinstance(node, yaml.SequenceNode):
            todo.extend(node.value)
        elif isinstance(node, yaml.MappingNode):
            for k, v in node.value:
                todo.extend((k, v))


def _yaml_error(exc) -> tuple[int | None, str]:
    """(line, message) for a PyYAML error, pointing where the user's mistake starts.

    For an unclosed bracket or quote PyYAML reports the place it gave up; the
    construct it was parsing ("while parsing a flow sequence") starts earlier,
    and that line is the one to fix.
    """
    problem = exc.problem or "syntax error"
    pm, cm = exc.problem_mark, exc.context_mark
    context = exc.context or ""
    if context.startswith("while") and ("flow" in context or "quoted" in context) \
            and cm is not None:
        where = f"; found at line {pm.line + 1}" if pm is not None and pm.line != cm.line else ""
        what = context[len("while "):]
        return cm.line + 1, f"not valid YAML: {problem} ({what} that starts here{where})"
    line = (pm or cm).line + 1 if (pm or cm) is not None else None
    text = f"{context}, {problem}" if context else problem
    return line, f"not valid YAML: {text}"


def _one_line(text: str) -> str:
    return " ".join(text.split())


def node_line(node) -> int:
    """The 1-based line where ``node`` starts.

    Parameters
    ----------
    node : yaml.Node

    Returns
    -------
    int
    """
    return node.start_mark.line + 1


#: the ways to write a pose (a base, a tool): position, roll-pitch-yaw, a matrix


class NodeReader:
    """Walks the node tree checking its shape (mappings and their keys, sequences, texts)
    with ``file:line`` errors; :class:`~.values.Reader` adds the values (numbers,
    expressions, vectors, poses). Callers see nodes only through its methods (no module
    outside this package imports yaml)."""

    def __init__(self, file: str):
        self.file = file
        self.params: dict[str, float] = {}
        self.A = 1.0
        self.joint: int | None = None
        self.joint_name: str | None = None
        self.exprs: list[tuple] = []

    # errors --------------------------------------------------------------
    def fail(self, node, message: str):
        """Report a problem at ``node``.

        Parameters
        ----------
        node : yaml.Node or None
            Where the problem is (None: the file as a whole, no line).
        message : str
            What is wrong, naming the field.

        Raises
        ------
        RobotFileError
            Always, with the file, ``node``'s line and the current ``joint`` and
            ``joint_name`` (subclasses may raise their own error instead).
        """
        line = node_line(node) if node is not None else None
        raise RobotFileError(self.file, line, message, self.joint, self.joint_name)

    # node kinds ----------------------------------------------------------
    def document(self, root, what: str, keys: dict) -> dict:
        """:meth:`mapping` of a whole file's ``root``. A file that is one text, not a mapping
        (a key, a ``.env``, a script given by mistake), is named by its length only: its
        one line may be a secret, and it is no line of a robot file to show.

        Parameters
        ----------
        root : yaml.Node
            The file's document.
        what : str
            The file's kind, for messages (``"the robot file"``).
        keys : dict of str to bool
            As for :meth:`mapping`.

        Returns
        -------
        dict of str to yaml.Node
            As :meth:`mapping`.
        """
        import yaml
        if isinstance(root, yaml.ScalarNode) and root.value != "" \
                and self.on_one_line(root):                 # (over lines: named by them)
            kind = what.replace("the ", "a ", 1)
            self.fail(root, f"{what} must be a mapping (key: value), not a text of "
                            f"{len(root.value)} characters (is it {kind}?)")
        return self.mapping(root, what, keys)

    def mapping(self, node, what: str, keys: dict[str, bool]) -> dict:
        """The entries of a mapping node, checked against the keys it may have.

        Parameters
        ----------
        node : yaml.Node
            The mapping.
        what : str
            How to name it in messages (``"'units'"``).
        keys : dict of str to bool
            The allowed keys, each True when required.

        Returns
        -------
        dict of str to yaml.Node
            Key -> value node, in the file's order.

        Raises
        ------
        RobotFileError
            (By :meth:`fail`.) Not a mapping, a key that is not a plain name, a key given
            twice, an unknown key (with the closest allowed one), a required key missing.
        """
        import yaml
        if not isinstance(node, yaml.MappingNode):
            self.fail(node, f"{what} must be a mapping (key: value), not {self.kind(node)}")
        out: dict = {}
        for knode, vnode in node.value:
            key = knode.value if isinstance(knode, yaml.ScalarNode) else None
            if key is None:
                self.fail(knode, f"{what}: keys must be plain names")
            if key in out:
                self.fail(knode, f"{what}: {quote(key)} is given twice")
            if key not in keys:
                close = difflib.get_close_matches(key, list(keys), n=1)
                hint = f" (did you mean {close[0]!r}?)" if close else \
                    f" (allowed: {', '.join(keys)})"
                self.fail(knode, f"unknown key {quote(key)} in {what}{hint}")
            out[key] = vnode
        for key, required in keys.items():
            if required and key not in out:
                self.fail(node, f"{key!r} is missing"
                          + ("" if what in ("the robot file", "the joint") else f" in {what}"))
        return out

    @staticmethod
    def is_mapping(node) -> bool:
        """Whether ``node`` is a mapping.

        Parameters
        ----------
        node : yaml.Node

        Returns
        -------
        bool
        """
        import yaml
        return isinstance(node, yaml.MappingNode)

    @staticmethod
    def is_scalar(node) -> bool:
        """Whether ``node`` is a scalar (text, a number, ...).

        Parameters
        ----------
        node : yaml.Node

        Returns
        -------
        bool
        """
        import yaml
        return isinstance(node, yaml.ScalarNode)

    @staticmethod
    def is_sequence(node) -> bool:
        """Whether ``node`` is a sequence (a list).

        Parameters
        ----------
        node : yaml.Node

        Returns
        -------
        bool
        """
        import yaml
        return isinstance(node, yaml.SequenceNode)

    @staticmethod
    def plain_keys(node) -> dict:
        """``{key: value node}`` of a mapping node's plain-text keys, without validation: for
        a first look at a mapping whose checks depend on one of its entries.

        Parameters
        ----------
        node : yaml.MappingNode
            The mapping (not checked to be one).

        Returns
        -------
        dict of str to yaml.Node
            Other keys skipped, the last of repeated keys kept.
        """
        return {k.value: v for k, v in node.value if NodeReader.is_scalar(k)}

    def names(self, node, what: str):
        """``(name, value node)`` of each entry of a mapping of plain names, in order.

        Parameters
        ----------
        node : yaml.Node
            The mapping.
        what : str
            How to name it in messages.

        Yields
        ------
        name : str
        value : yaml.Node

        Raises
        ------
        RobotFileError
            (By :meth:`fail`, when iterated.) Not a mapping; an entry whose key is not a
            plain name, when it is reached.
        """
        if not self.is_mapping(node):
            self.fail(node, f"{what} must be a mapping of names to numbers")
        for knode, vnode in node.value:
            if not self.is_scalar(knode):
                self.fail(knode, f"{what}: keys must be plain names")
            yield knode.value, vnode

    @staticmethod
    def put_first(node, key: str, value: str) -> None:
        """Give the mapping ``node`` the text entry ``key: value`` first, unless it has
        ``key`` (for a default the reader should treat as written).

        Parameters
        ----------
        node : yaml.MappingNode
            Modified in place; the new entry carries ``node``'s start line.
        key, value : str
            The entry, as text scalars.
        """
        import yaml
        if any(k.value == key for k, _ in node.value):
            return
        mark = node.start_mark
        node.value.insert(0, (yaml.ScalarNode("tag:yaml.org,2002:str", key, mark, mark),
                              yaml.ScalarNode("tag:yaml.org,2002:str", value, mark, mark)))

    @staticmethod
    def kind(node) -> str:
        """What ``node`` is, for a message: "a mapping", "a list", "empty" or its quoted
        text.

        Parameters
        ----------
        node : yaml.Node

        Returns
        -------
        str
        """
        import yaml
        if isinstance(node, yaml.MappingNode):
            return "a mapping"
        if isinstance(node, yaml.SequenceNode):
            return "a list"
        return NodeReader.shown(node) if node.value != "" else "empty"

    @staticmethod
    def shown(node) -> str:
        """A scalar's text for a message: quoted (cut to ``MAX_QUOTE`` characters) when it
        lies on one line of the file, else only the lines it runs over. A message names
        one line, and echoes nothing of the file but that line: a file that is no robot
        file (a key, a ``.env``) read as one must not show its second line.

        Parameters
        ----------
        node : yaml.ScalarNode

        Returns
        -------
        str
            ``'text'``, or ``a text over lines A-B``.
        """
        first, last = NodeReader.lines(node)
        return f"a text over lines {first}-{last}" if last > first else quote(node.value)

    @staticmethod
    def on_one_line(node) -> bool:
        """Whether ``node`` is written on one line of the file (a message may quote it)."""
        first, last = NodeReader.lines(node)
        return first == last

    @staticmethod
    def lines(node) -> tuple[int, int]:
        """The first and the last 1-based line of the file ``node`` is written on.

        Parameters
        ----------
        node : yaml.Node

        Returns
        -------
        (int, int)
            Equal for a node on one line (a block text ``|`` starts on the line of its
            ``|``).
        """
        end = node.end_mark
        return node.start_mark.line + 1, end.line + (1 if end.column > 0 else 0)

    def sequence(self, node, what: str, length: int | None = None) -> list:
        """The items of a list node.

        Parameters
        ----------
        node : yaml.Node
            The list.
        what : str
            How to name it in messages.
        length : int, optional
            The number of items it must have.

        Returns
        -------
        list of yaml.Node

        Raises
        ------
        RobotFileError
            (By :meth:`fail`.) Not a list, or not ``length`` items.
        """
        import yaml
        if not isinstance(node, yaml.SequenceNode):
            self.fail(node, f"{what} must be a list, not {self.kind(node)}")
        if length is not None and len(node.value) != length:
            self.fail(node, f"{what} must have {length} entries, not {len(node.value)}")
        return node.value

    def text(self, node, what: str) -> str:
        """The text of a scalar node (a number is taken as its text).

        Parameters
        ----------
        node : yaml.Node
            The scalar.
        what : str
            How to name it in messages.

        Returns
        -------
        str
            As written.

        Raises
        ------
        RobotFileError
            (By :meth:`fail`.) Not a scalar, or empty (null).
        """
        import yaml
        if not isinstance(node, yaml.ScalarNode) or node.tag.endswith(":null"):
            self.fail(node, f"{what} must be text, not {self.kind(node) if not isinstance(node, yaml.ScalarNode) else 'empty'}")
        return str(node.value)
