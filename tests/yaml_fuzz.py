"""Mutations of YAML files for the fuzz tests of robot files and homework sheets.

:func:`mutate` turns a valid file into what a careless or hostile author could hand
kincalc: a line deleted or duplicated (a key missing or given twice), a value of
another type, huge, NaN or an expression, a key renamed, an anchor and aliases up
to a "billion laughs" bomb, a recursive alias, a tag such as
``!!python/object/apply``, broken YAML, binary junk, a file cut short or
re-indented. It works on the text, line by line, so the mutants keep most of the
seed's structure and reach deep into the reader.
"""

from __future__ import annotations

import yaml
from hypothesis import strategies as st


def bomb(levels: int, kind: str) -> str:
    """A one-line "billion laughs": ``levels`` nested anchors, each nine aliases of the
    one before (9**levels leaves in the node graph from a few hundred bytes of text)."""
    if kind == "list":
        inner = "&l0 [lol, lol, lol, lol, lol, lol, lol, lol, lol]"
        for k in range(1, levels + 1):
            inner = f"&l{k} [{inner}, " + ", ".join([f"*l{k - 1}"] * 8) + "]"
        return inner
    inner = "&m0 {a: lol, b: lol, c: lol}"
    for k in range(1, levels + 1):
        inner = f"&m{k} {{k0: {inner}, " + ", ".join(f"k{j}: *m{k - 1}" for j in range(1, 9)) + "}"
    return inner


#: values a field may be given instead of its own (YAML text, inserted as they are)
ODD_VALUES = [
    "null", "~", "''", "yes", "true", "[]", "{}", "[1, 2]", "{a: 1}", ".nan", "-.inf",
    "1e999", "1e308", "-1e10", "1" + "0" * 400, "0x1F", "0o17", "1_000", "l1 * 2", "pi/2",
    "'(' * 3", "\"" + "(" * 60 + "1" + ")" * 60 + "\"", "\"" + "-" * 3000 + "1\"",
    "\"__import__('os').system('touch pwned')\"", "x" * 5000, "\"1 / 0\"",
    "!!python/object/apply:os.system ['touch pwned']", "!!python/name:os.system",
    "!!python/object:os.Popen {args: [touch, pwned]}", "!!binary aGVsbG8=", "!!float 1",
    "!!int abc", "!!str 5", "!custom 7", "!!set {a: null}", "!!omap [{a: 1}]",
    "!!timestamp 2001-12-14", "&a 1", "*undefined", "&r [*r]", "&r {k: *r}",
    bomb(9, "list"), bomb(6, "map"), "'\u00e4\u00df\U0001f916'", "\"\\0\\x07\\u200b\"",
    "[" * 40 + "]" * 40, "{{{", "[1, 2", "'unclosed", "|\n  block",
]

#: keys a line's key may be renamed to
ODD_KEYS = ["name", "jonits", "<<", "? [a, b]", "1", "''", "k" * 3000]

#: whole lines to append (a top-level key with an odd value)
ODD_LINES = ["bomb: " + bomb(9, "list") + "\n", "alias: *undefined\n", "again: &j [*j]\n",
             "parameters: " + bomb(5, "map") + "\n", "%YAML 1.1\n", "---\n", "...\n"]

OPS = ["retype", "retype", "retype", "delete", "duplicate", "rekey", "append", "junk",
       "truncate", "indent", "flow"]


def _retype(line: str, at: int, value: str) -> str:
    """``line`` with the value after its colon at ``at`` replaced by ``value``."""
    rest = line[at + 1:]
    end = next((i for i, c in enumerate(rest) if c in ",}\n"), len(rest))
    if "\n" in value or value.startswith(("|", "!!", "!", "&", "*", "?")):
        end = len(rest.rstrip("\n"))          # block values and tags take the line
    return line[:at + 1] + " " + value + rest[end:]


@st.composite
def mutate(draw, text: str, values=(), keys=(), max_ops: int = 3) -> bytes:
    """1 to ``max_ops`` mutations of the YAML ``text``, as bytes; ``values`` and ``keys``
    are added to :data:`ODD_VALUES` and :data:`ODD_KEYS` (a secret, paths)."""
    values = ODD_VALUES + list(values)
    keys = ODD_KEYS + list(keys)
    for _ in range(draw(st.integers(1, max_ops))):
        op = draw(st.sampled_from(OPS))
        lines = text.splitlines(keepends=True)
        k = draw(st.integers(0, max(len(lines) - 1, 0)))
        line = lines[k] if lines else ""
        if op == "retype" and ":" in line:
            cols = [i for i, c in enumerate(line) if c == ":"]
            lines[k] = _retype(line, draw(st.sampled_from(cols)), draw(st.sampled_from(values)))
        elif op == "delete" and lines:
            del lines[k]
        elif op == "duplicate" and lines:
            lines.insert(k, line)
        elif op == "rekey" and ":" in line:
            indent = line[:len(line) - len(line.lstrip(" -"))]
            lines[k] = indent + draw(st.sampled_from(keys)) + line[line.index(":"):]
        elif op == "append":
            lines.append(draw(st.sampled_from(ODD_LINES)))
        elif op == "junk":
            data = draw(st.binary(min_size=1, max_size=40))
            pos = draw(st.integers(0, len(text)))
            raw = text.encode("utf-8", "surrogateescape")
            return raw[:pos] + data + raw[pos:]
        elif op == "truncate":
            lines = lines[:k]
        elif op == "indent" and lines:
            lines[k] = draw(st.sampled_from(["\t", "   ", ""])) + line.lstrip()
        elif op == "flow":
            try:                # the same content in flow style (one line, or wrapped)
                text = yaml.safe_dump(yaml.safe_load(text), default_flow_style=True,
                                      allow_unicode=True,
                                      width=draw(st.sampled_from([40, 10 ** 6])))
            except Exception:   # not YAML any more, or a tag safe_load refuses: as it is
                pass
            continue
        text = "".join(lines)
    return text.encode("utf-8", "surrogateescape")


def padded(text: str, size: int) -> bytes:
    """``text`` with a comment appended so that the file is exactly ``size`` bytes."""
    data = text.encode("utf-8")
    pad = size - len(data) - 3
    assert pad >= 0, "the seed is larger than the size asked for"
    return data + b"\n#" + b"x" * pad + b"\n"
