"""Names and words a robot file gives are text in every table, never rich markup.

A joint named ``[/]`` (any printable character is allowed) made fk, jacobian, ik and
robots show exit 3 with rich's MarkupError; ``arm[left]_1`` was shown as ``arm_1``; a name
holding ``[link=...]`` or ``[blink red]`` sent a hyperlink or an escape sequence to the
terminal; a broken library file whose error quoted a key ``[/]`` broke ``robots list``
(hostile-input campaign, twenty-fourth session). The console reads no markup now; kincalc's
own bold and colours are styles.
"""

from __future__ import annotations

import pytest

from cli_contract import run_cli

NAMES = ["[/]", "arm[left]_1", "[link=https://evil.example/x]q1[/link]", "[blink red]q2"]


def robot_file(tmp_path, names, title="title [bold]not bold[/bold]"):
    rows = "\n".join(f"  - {{name: '{n}', type: revolute, alpha: 0, a: {0.3 - 0.1 * k}, d: 0, "
                     "theta: 0}" for k, n in enumerate(names))
    path = tmp_path / "arm.yaml"
    path.write_text(f"name: arm\ntitle: '{title}'\nconvention: dh\n"
                    f"units: {{length: m, angle: deg}}\njoints:\n{rows}\n")
    return str(path)


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("argv", [["fk", "{f}", "10", "20"], ["jacobian", "{f}", "10", "20"],
                                  ["ik", "{f}", "--xyz", "0.4", "0.1", "0"],
                                  ["ik", "{f}", "--xyz", "0.4", "0.1", "0", "--explain"],
                                  ["robots", "show", "{f}"],
                                  ["reach", "{f}", "--xyz", "0.4", "0.1", "0"]])
def test_a_name_with_brackets_is_shown_as_written(tmp_path, name, argv):
    f = robot_file(tmp_path, [name, "q2" if name != "[blink red]q2" else "q0"])
    status, out, err = run_cli([a.format(f=f) for a in argv])
    assert status == 0 and err == "", err
    if argv[0] != "reach":                  # (reach names no joint of a reachable pose)
        assert name in out, out
    assert "\x1b" not in out and "\\[" not in out
    if argv[:2] == ["robots", "show"]:
        assert "title [bold]not bold[/bold]" in out


def test_a_broken_library_file_quoting_markup_is_listed(tmp_path, monkeypatch):
    (tmp_path / "b.yaml").write_text("name: b\n'[/]': 1\nconvention: dh\njoints: []\n")
    monkeypatch.setenv("KINCALC_ROBOTS", str(tmp_path))
    status, out, err = run_cli(["robots", "list"])
    assert status == 0 and err == "", err
    assert "unknown key '[/]'" in " ".join(out.split())
    assert "1 bundled robot\n" in out or "1 bundled robot " in out
