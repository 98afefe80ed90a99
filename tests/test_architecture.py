"""The house plan: which room of kincalc does what, and what each may import.

Rooms are layers, bottom up; a module imports only from its own layer or below, at
module level or inside a function alike (an import hidden in a function is still an
edge of the graph). The rules, each a test below:

1. no upward import (``LAYERS``);
2. no import of another kincalc module's underscore name;
3. typer, rich and click only in ``kincalc.cli``;
4. yaml only in the one YAML reader, ``kincalc.conventions.reader``;
5. matplotlib and sympy never at module level (optional extras, imported where used);
6. no module over 500 lines and no function over 80 (``MAX_MODULE_LINES``,
   ``MAX_FUNCTION_LINES``): a room that grows is split by job.

Read with ``ast``: nothing is imported to check it.
"""

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "kincalc"

#: the layers, bottom up: (name, what lives there, module prefixes)
LAYERS = [
    ("base", "the version, exceptions, named tolerances, units, input limits, safe output "
             "files, evenly spread samples, malloc's thresholds",
     ["kincalc.version", "kincalc.errors", "kincalc.tolerances", "kincalc.units",
      "kincalc.limits", "kincalc.outputs", "kincalc.samples", "kincalc.memory"]),
    ("geometry", "rotations and rigid transforms", ["kincalc.spatial"]),
    ("chain", "the uniform chain F_0 J_1 F_1 ... J_n F_n, as data", ["kincalc.chain"]),
    ("evaluation", "forward kinematics, Jacobians, the axes' structure",
     ["kincalc.fk", "kincalc.jacobian", "kincalc.structure"]),
    ("subproblems", "Paden-Kahan subproblems 1-6, batched", ["kincalc.subproblems"]),
    ("ik", "the one IK engine", ["kincalc.ik"]),
    ("model", "the robot as written (joints in its convention, units, limits), its chain, "
              "and the Python API's methods on it (fk, jacobian, ik): above the engine, "
              "which needs only the chain and the limits", ["kincalc.model"]),
    ("conventions", "dh / mdh / poe, the robot-file reader and writer, the library",
     ["kincalc.conventions", "kincalc.conventions.reader", "kincalc.conventions.writer",
      "kincalc.conventions.library"]),
    ("analysis", "reports and their words, reach, workspace, compare (screws, the branch "
                 "search, the match and its words), formulas, plots, "
                 "output files",
     ["kincalc.analysis", "kincalc.analysis.results", "kincalc.analysis.words", "kincalc.analysis.reach",
      "kincalc.analysis.workspace", "kincalc.analysis.compare", "kincalc.analysis.symbolic", "kincalc.analysis.plot",
      "kincalc.outputs"]),
    ("homework", "sheets, grading, quizzes", ["kincalc.homework"]),
    ("cli", "the command line", ["kincalc.cli"]),
    ("front door", "the package's lazy facade and `python -m kincalc`",
     ["kincalc", "kincalc.__main__"]),
]

EXTERNAL_ROOMS = {"typer": "kincalc.cli", "rich": "kincalc.cli", "click": "kincalc.cli",
                  "yaml": "kincalc.conventions.reader"}
NEVER_AT_MODULE_LEVEL = {"matplotlib", "sympy"}


def _modules():
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        out[name] = path
    return out


MODULES = _modules()


def _layer(module: str) -> int:
    best, length = None, -1
    for i, (_, _, prefixes) in enumerate(LAYERS):
        for p in prefixes:
            if (module == p or module.startswith(p + ".")) and len(p) > length:
                best, length = i, len(p)
    assert best is not None, f"{module} is in no layer of the house plan"
    return best


def _resolve(name: str) -> str | None:
    """The kincalc module ``name`` names (a name inside a module resolves to the module)."""
    while name:
        if name in MODULES:
            return name
        name = name.rpartition(".")[0]
    return None


def _imports(module: str):
    """``(imported module or external top-level name, names taken, line, at module
    level)`` of every import statement of ``module``."""
    path = MODULES[module]
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    top_level = {id(n) for n in tree.body}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, [], node.lineno, id(node) in top_level
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[:len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            names = [a.name for a in node.names]
            # "from . import x" imports the module x when there is one
            subs = [f"{target}.{n}" for n in names if f"{target}.{n}" in MODULES]
            if subs:
                for s in subs:
                    yield s, [], node.lineno, id(node) in top_level
                names = [n for n in names if f"{target}.{n}" not in MODULES]
                if not names:
                    continue
            yield target, names, node.lineno, id(node) in top_level


def _shown(path: Path) -> str:
    try:
        return str(path.relative_to(PACKAGE.parent))
    except ValueError:
        return str(path)


def _edges():
    for module in MODULES:
        for target, names, line, top in _imports(module):
            yield module, target, names, line, top


def test_every_module_has_a_room():
    for module in MODULES:
        _layer(module)


def test_no_module_imports_upward():
    upward = []
    for module, target, _, line, _ in _edges():
        imported = _resolve(target) if target.startswith("kincalc") else None
        if imported is None or _layer(imported) <= _layer(module):
            continue
        upward.append(f"{_shown(MODULES[module])}:{line}: {module} "
                      f"({LAYERS[_layer(module)][0]}) imports {imported} "
                      f"({LAYERS[_layer(imported)][0]})")
    assert not upward, "imports upward:\n" + "\n".join(upward)


def test_no_underscore_names_across_modules():
    bad = []
    for module, target, names, line, _ in _edges():
        imported = _resolve(target) if target.startswith("kincalc") else None
        if imported is None or imported == module:
            continue
        private = [n for n in names if n.startswith("_") and not n.startswith("__")]
        if imported != target:              # "import kincalc.x._y" or "from .x._y import"
            private += [p for p in target[len(imported) + 1:].split(".") if p.startswith("_")]
        if private:
            bad.append(f"{module}:{line} takes {', '.join(private)} from {imported}")
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("library", sorted(EXTERNAL_ROOMS))
def test_external_libraries_stay_in_their_room(library):
    room = EXTERNAL_ROOMS[library]
    bad = [f"{module}:{line}" for module, target, _, line, _ in _edges()
           if target.split(".")[0] == library
           and not (module == room or module.startswith(room + "."))]
    assert not bad, f"{library} outside {room}: {bad}"


@pytest.mark.parametrize("library", sorted(NEVER_AT_MODULE_LEVEL))
def test_optional_extras_are_imported_where_used(library):
    bad = [f"{module}:{line}" for module, target, _, line, top in _edges()
           if top and target.split(".")[0] == library]
    assert not bad, f"{library} imported at module level: {bad}"


def test_the_version_is_the_projects():
    import re
    project = (PACKAGE.parent / "pyproject.toml").read_text(encoding="utf-8")
    wanted = re.search(r'^version = "([^"]+)"', project, re.M).group(1)
    assert f'__version__ = "{wanted}"' in (PACKAGE / "version.py").read_text(encoding="utf-8")


def test_the_plan_catches_an_upward_import(tmp_path, monkeypatch):
    """The checker itself: a module of the geometry layer importing the engine is found."""
    fake = PACKAGE / "spatial" / "rotations.py"
    source = fake.read_text(encoding="utf-8") + "\n\ndef _probe():\n    from ..ik import engine\n"
    probe = tmp_path / "rotations.py"
    probe.write_text(source, encoding="utf-8")
    monkeypatch.setitem(MODULES, "kincalc.spatial.rotations", probe)
    with pytest.raises(AssertionError, match="kincalc.spatial.rotations .geometry. imports "
                                             "kincalc.ik.engine .ik."):
        test_no_module_imports_upward()


def graph_summary() -> str:
    """Modules and lines per layer, and the import edges between layers (``python
    tests/test_architecture.py``): the house as it stands."""
    import collections
    modules, lines = collections.Counter(), collections.Counter()
    for name, path in MODULES.items():
        layer = _layer(name)
        modules[layer] += 1
        lines[layer] += len(path.read_text(encoding="utf-8").splitlines())
    edges = collections.Counter()
    for importer, target, _, _, _ in _edges():
        imported = _resolve(target) if target.startswith("kincalc") else None
        if imported is None:
            continue                                  # an external library
        a, b = _layer(importer), _layer(imported)
        if a != b:
            edges[(a, b)] += 1
    out = [f"{'layer':12s} {'modules':>7s} {'lines':>6s}  imports from (edges)"]
    for i, (name, _, _) in enumerate(LAYERS):
        below = ", ".join(f"{LAYERS[b][0]} {n}" for (a, b), n in sorted(edges.items()) if a == i)
        out.append(f"{name:12s} {modules[i]:7d} {lines[i]:6d}  {below}")
    big = sorted(((len(p.read_text(encoding='utf-8').splitlines()), n)
                  for n, p in MODULES.items()), reverse=True)[:5]
    out.append("largest modules: " + ", ".join(f"{n} {k}" for k, n in big))
    upward = sorted((LAYERS[a][0], LAYERS[b][0]) for (a, b) in edges if b > a)
    out.append(f"upward edges: {len(upward)} ({', '.join(f'{a} -> {b}' for a, b in upward)})")
    return "\n".join(out)


if __name__ == "__main__":
    print(graph_summary())


#: the size of a room's modules and functions (lines as the file has them, docstrings in)
MAX_MODULE_LINES = 500
MAX_FUNCTION_LINES = 80


def test_no_module_or_function_is_too_large():
    big, long = [], []
    for module, path in MODULES.items():
        text = path.read_text(encoding="utf-8")
        if len(text.splitlines()) > MAX_MODULE_LINES:
            big.append(f"{_shown(path)}: {len(text.splitlines())} lines")
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                length = node.end_lineno - node.lineno + 1
                if length > MAX_FUNCTION_LINES:
                    long.append(f"{_shown(path)}:{node.lineno}: {node.name}, {length} lines")
    assert not big, f"modules over {MAX_MODULE_LINES} lines (split them by job):\n" + \
        "\n".join(big)
    assert not long, f"functions over {MAX_FUNCTION_LINES} lines:\n" + "\n".join(long)
