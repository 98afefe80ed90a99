"""The man pages in man/ stay in step with the command line.

For every command path (kincalc, fk, jacobian, ik, reach, workspace, plot, view,
selftest, robots, robots list, robots show, robots validate, completion) the ``--help`` text is taken from the CLI itself,
in-process through ``kincalc.cli.main.main`` with stdout captured by capsys
(there is no ``kincalc/__main__.py``, so ``python -m kincalc`` is not used).
Every long option it lists (both halves of ``--deg / --rad``) must be in
the command's man page, with an entry of its own under OPTIONS; no page may
document an option the command does not have; every sub-command must be in
kincalc.1; and ``groff -man -ww -z`` must accept every page without a
warning.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from kincalc import __version__
from kincalc.cli.main import main

MAN = Path(__file__).parents[2] / "man"

#: Every command path, and the page that documents it. A new command makes
#: test_every_command_has_a_page fail until it is added here (with a page).
PAGES: dict[tuple[str, ...], str] = {
    (): "kincalc.1",
    ("fk",): "kincalc-fk.1",
    ("jacobian",): "kincalc-jacobian.1",
    ("ik",): "kincalc-ik.1",
    ("reach",): "kincalc-reach.1",
    ("workspace",): "kincalc-workspace.1",
    ("plot",): "kincalc-plot.1",
    ("view",): "kincalc-view.1",
    ("check",): "kincalc-check.1",
    ("quiz",): "kincalc-quiz.1",
    ("compare",): "kincalc-compare.1",
    ("convert",): "kincalc-convert.1",
    ("selftest",): "kincalc-selftest.1",
    ("robots",): "kincalc-robots.1",
    ("robots", "list"): "kincalc-robots.1",
    ("robots", "show"): "kincalc-robots.1",
    ("robots", "validate"): "kincalc-robots.1",
    ("completion",): "kincalc-completion.1",
}
PAGE_FILES = sorted(set(PAGES.values()))

LONG_OPTION = re.compile(r"(?<![\w-])--([A-Za-z0-9][A-Za-z0-9_-]*)")
ROFF_LONG_OPTION = re.compile(r"(?:\\-\\-|--)([A-Za-z0-9][A-Za-z0-9_]*(?:(?:\\-|-)[A-Za-z0-9_]+)*)")


def _name(path: tuple[str, ...]) -> str:
    return " ".join(("kincalc",) + path)


# --- the CLI's help ---------------------------------------------------------

def help_text(path: tuple[str, ...], capsys, monkeypatch) -> str:
    """``kincalc PATH... --help`` as the user sees it (exit status 0)."""
    monkeypatch.setenv("COLUMNS", "80")  # deterministic wrapping
    capsys.readouterr()
    status = main([*path, "--help"])
    out, err = capsys.readouterr()
    assert status == 0, f"'{_name(path)} --help' exited {status}: {err}"
    assert out.strip(), f"'{_name(path)} --help' printed nothing"
    return out


def _section(text: str, title: str) -> list[str]:
    """The lines of a click help section ("Options:", "Commands:")."""
    lines, inside = [], False
    for line in text.splitlines():
        if re.match(r"^\S.*:\s*$", line):
            inside = line.strip() == f"{title}:"
            continue
        if inside:
            lines.append(line)
    return lines


def help_options(text: str) -> set[str]:
    """Every long option (without the leading ``--``) in the Options section.

    Only the first column is read (``  --deg / --rad  Angles ...``), so an
    option mentioned in another option's description is not counted.
    """
    options = set()
    for line in _section(text, "Options"):
        m = re.match(r"^ {1,4}(-\S.*?)(?: {2,}|$)", line)
        if m:
            options |= set(LONG_OPTION.findall(m.group(1)))
    return options


def help_commands(text: str) -> list[str]:
    out = []
    for line in _section(text, "Commands"):
        m = re.match(r"^ {1,4}([A-Za-z][\w-]*)(?: {2,}|$)", line)
        if m:
            out.append(m.group(1))
    return out


def command_tree(capsys, monkeypatch) -> set[tuple[str, ...]]:
    """Every command path reachable from ``kincalc --help``."""
    seen, todo = set(), [()]
    while todo:
        path = todo.pop()
        seen.add(path)
        todo += [path + (c,) for c in help_commands(help_text(path, capsys, monkeypatch))]
    return seen


# --- the man pages ------------------------------------------------------------

def page_source(page: str) -> str:
    p = MAN / page
    assert p.is_file(), f"man page {p} is missing"
    return p.read_text(encoding="utf-8")


def plain(source: str) -> str:
    """Roff source with font changes, \\- and \\& undone and blanks collapsed."""
    s = re.sub(r"\\f(?:[BIRP]|\(..|\[[^]]*\])", "", source)
    s = s.replace("\\-", "-").replace("\\&", "").replace("\\~", " ").replace('"', "")
    return " ".join(s.split())


def options_section(source: str) -> dict[str, list[str]]:
    """The OPTIONS section, split at ``.SS`` lines: {subsection title: lines}.

    The lines before the first ``.SS`` are under the key ``""``.
    """
    parts: dict[str, list[str]] = {}
    inside, key = False, ""
    for line in source.splitlines():
        if line.startswith(".SH"):
            inside = line.split(None, 1)[1].strip().strip('"') == "OPTIONS" \
                if len(line.split()) > 1 else False
            key = ""
            continue
        if not inside:
            continue
        if line.startswith(".SS"):
            key = plain(line[3:])
            continue
        parts.setdefault(key, []).append(line)
    return parts


def tagged_options(lines: list[str]) -> set[str]:
    """Long options named in the tag lines of ``.TP`` entries."""
    out, take = set(), False
    for line in lines:
        if line.startswith('.\\"'):
            continue
        if take:
            out |= {m.replace("\\-", "-") for m in ROFF_LONG_OPTION.findall(line)}
            take = False
        if line.strip() == ".TP" or line.startswith(".TP "):
            take = True
    return out


def page_mentions(source: str, option: str) -> bool:
    roff = option.replace("-", "\\-")
    pattern = r"(?:\\-\\-|--)(?:%s|%s)(?![A-Za-z0-9_]|\\?-[A-Za-z0-9])" % (
        re.escape(roff), re.escape(option))
    return re.search(pattern, source) is not None


def documented_options(source: str, path: tuple[str, ...]) -> set[str]:
    """Options with an entry under OPTIONS for ``path``: its own ``.SS``
    subsection when the section is split by sub-command, else the whole section."""
    parts = options_section(source)
    own = parts.get(_name(path))
    if own is not None:
        return tagged_options(own)
    return tagged_options([line for lines in parts.values() for line in lines])


# --- tests ----------------------------------------------------------------------

def test_every_command_has_a_page(capsys, monkeypatch):
    tree = command_tree(capsys, monkeypatch)
    missing = sorted(_name(p) for p in tree - PAGES.keys())
    gone = sorted(_name(p) for p in PAGES.keys() - tree)
    assert not missing, f"commands without a man page in PAGES: {missing}"
    assert not gone, f"PAGES lists commands the CLI no longer has: {gone}"
    for page in PAGE_FILES:
        assert (MAN / page).is_file(), f"man page {MAN / page} is missing"


@pytest.mark.parametrize("path", list(PAGES), ids=_name)
def test_help_options_are_in_the_page(path, capsys, monkeypatch):
    options = help_options(help_text(path, capsys, monkeypatch))
    assert "help" in options, "the help parser found no options; has the help format changed?"
    source = page_source(PAGES[path])
    missing = sorted(f"--{o}" for o in options if not page_mentions(source, o))
    assert not missing, f"{PAGES[path]} does not mention these options of '{_name(path)}': {missing}"


@pytest.mark.parametrize("path", list(PAGES), ids=_name)
def test_help_options_have_an_entry_under_options(path, capsys, monkeypatch):
    options = help_options(help_text(path, capsys, monkeypatch))
    documented = documented_options(page_source(PAGES[path]), path)
    missing = sorted(f"--{o}" for o in options - documented)
    assert not missing, (f"{PAGES[path]}: no .TP entry under OPTIONS for these options of "
                         f"'{_name(path)}': {missing}")


@pytest.mark.parametrize("page", PAGE_FILES)
def test_page_documents_no_option_the_cli_lacks(page, capsys, monkeypatch):
    source = page_source(page)
    parts = options_section(source)
    assert parts, f"{page} has no OPTIONS section"
    paths = [p for p, pg in PAGES.items() if pg == page]
    real = {p: help_options(help_text(p, capsys, monkeypatch)) for p in paths}
    for title, lines in parts.items():
        owner = [p for p in paths if _name(p) == title]
        allowed = real[owner[0]] if owner else set().union(*real.values())
        extra = sorted(f"--{o}" for o in tagged_options(lines) - allowed)
        where = f"{page} OPTIONS" + (f" ({title})" if title else "")
        assert not extra, f"{where} documents options the CLI does not have: {extra}"


def test_pages_mention_only_real_options(capsys, monkeypatch):
    real = set().union(*(help_options(help_text(p, capsys, monkeypatch)) for p in PAGES))
    for page in PAGE_FILES:
        named = {m.replace("\\-", "-") for m in ROFF_LONG_OPTION.findall(page_source(page))}
        unknown = sorted(f"--{o}" for o in named - real)
        assert not unknown, f"{page} mentions options no command has: {unknown}"


def test_every_sub_command_is_in_kincalc_1(capsys, monkeypatch):
    text = plain(page_source("kincalc.1"))
    for path in sorted(command_tree(capsys, monkeypatch)):
        if path:
            assert _name(path) in text, f"kincalc.1 does not mention '{_name(path)}'"


@pytest.mark.parametrize("page", PAGE_FILES)
def test_page_header(page):
    source = page_source(page)
    th = [line for line in source.splitlines() if line.startswith(".TH ")]
    assert len(th) == 1, f"{page} needs exactly one .TH line"
    name = page.rsplit(".", 1)[0]
    assert th[0].split()[1].replace("\\-", "-") == name.upper(), f"{page}: .TH names another page"
    assert th[0].split()[2] == page.rsplit(".", 1)[1], f"{page}: .TH section differs from the file's"
    assert f"kincalc {__version__}" in th[0], f"{page}: .TH does not carry version {__version__}"
    for heading in ("NAME", "SYNOPSIS", "DESCRIPTION", "OPTIONS", "EXIT STATUS", "EXAMPLES",
                    "SEE ALSO"):
        assert re.search(rf'^\.SH "?{heading}"?\s*$', source, re.M), f"{page} has no {heading}"


@pytest.mark.parametrize("page", PAGE_FILES)
def test_page_is_ascii(page):
    # special characters are roff escapes (\(*a, \(de, ...), so groff needs no preconv
    bad = [(n, line) for n, line in enumerate((MAN / page).read_bytes().splitlines(), 1)
           if not line.isascii()]
    assert not bad, f"{page}: non-ASCII text on line(s) {[n for n, _ in bad]}"


@pytest.mark.parametrize("page", PAGE_FILES)
def test_groff_reports_no_warnings(page):
    groff = shutil.which("groff")
    if groff is None:
        pytest.skip("groff is not installed, so 'groff -man -ww -z' cannot check the page")
    r = subprocess.run([groff, "-man", "-ww", "-z", str(MAN / page)],
                       capture_output=True, text=True, timeout=60)
    assert r.stderr == "", f"groff warnings for {page}:\n{r.stderr}"
    assert r.returncode == 0, f"groff exited {r.returncode} for {page}"
