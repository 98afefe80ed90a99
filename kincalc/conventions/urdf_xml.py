"""The XML layer of URDF files: an element tree with each element's and each attribute's
1-based lines, parsed by expat with a document type declaration refused (so no entity,
internal or external, is ever expanded).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from ..errors import RobotFileError


@dataclass
class Element:
    """One XML element: its tag, attributes, 1-based line and children, and the first and
    last line of each attribute (a start tag may run over several lines)."""

    tag: str
    attrs: dict
    line: int
    children: list = field(default_factory=list)
    attr_lines: dict = field(default_factory=dict)

    def lines_of(self, name: str) -> tuple[int, int]:
        """The first and last 1-based line of attribute ``name`` (the element's line when
        it has none)."""
        return self.attr_lines.get(name, (self.line, self.line))

    def first(self, tag: str):
        """The first child element named ``tag``, or None."""
        return next((c for c in self.children if c.tag == tag), None)


def parse_xml(text: str, file: str) -> Element:
    """The element tree of a URDF's text, a DOCTYPE (and so any entity) refused.

    Parameters
    ----------
    text : str
        The file's text.
    file : str
        How errors name the file.

    Returns
    -------
    Element
        The ``<robot>`` element, each element with its 1-based line.

    Raises
    ------
    RobotFileError
        XML that is not well formed, a DOCTYPE, or a root element other than ``<robot>``.
    """
    import xml.parsers.expat as expat

    parser = expat.ParserCreate()
    root: list[Element] = []
    stack: list[Element] = []

    data = text.encode("utf-8")       # what expat parses: its byte indexes are into it

    def start(tag, attrs):
        node = Element(tag, attrs, parser.CurrentLineNumber,
                       attr_lines=attribute_lines(data, parser.CurrentByteIndex,
                                                   parser.CurrentLineNumber))
        (stack[-1].children if stack else root).append(node)
        stack.append(node)

    def end(tag):
        stack.pop()

    def doctype(*args):
        raise RobotFileError(file, parser.CurrentLineNumber,
                             "a DOCTYPE is not accepted in a URDF (kincalc expands no entities)")

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.StartDoctypeDeclHandler = doctype
    parser.EntityDeclHandler = doctype
    try:
        parser.Parse(text, True)
    except expat.ExpatError as exc:
        raise RobotFileError(file, exc.lineno, "not well-formed XML: "
                             f"{expat.ErrorString(exc.code)}") from None
    if root[0].tag != "robot":
        raise RobotFileError(file, root[0].line, f"the root element is <{_cut_tag(root[0].tag)}>,"
                                                 " not <robot>: not a URDF")
    return root[0]


#: a start tag as expat has accepted it, and one attribute in it
_START_TAG = re.compile(rb"""<[^\s/>]+(?:\s+[^\s=/>]+\s*=\s*(?:"[^"]*"|'[^']*'))*\s*/?>""")
_ATTRIBUTE = re.compile(rb"""([^\s=/>]+)\s*=\s*("[^"]*"|'[^']*')""")


def attribute_lines(data: bytes, at: int, line: int) -> dict:
    """``{attribute: (first line, last line)}`` of the start tag at byte ``at`` of ``data``,
    whose ``<`` is on ``line``."""
    tag = _START_TAG.match(data, at)
    if tag is None:
        return {}
    out, pos, first = {}, at, line
    for m in _ATTRIBUTE.finditer(data, at, tag.end()):
        first += line_breaks(data, pos, m.start(2))      # (from the last: linear in the tag)
        pos = m.start(2)
        last = first + line_breaks(data, *m.span(2))
        out[m.group(1).decode("utf-8", "replace")] = (first, last)
    return out


def line_breaks(data: bytes, start: int, end: int) -> int:
    """The line breaks in ``data[start:end]`` as XML (and expat's line numbers) count them:
    LF, CR LF, and a lone CR."""
    return data.count(b"\n", start, end) + data.count(b"\r", start, end) \
        - data.count(b"\r\n", start, end)


def _cut_tag(tag: str) -> str:
    return tag if len(tag) <= 40 else tag[:37] + "..."
