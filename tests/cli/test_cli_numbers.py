"""Numbers beyond kincalc's limit on the command line (issue 14, item 6).

Robot files refused magnitudes beyond 1e9; the command line took 1e300 and printed
``q3=inf``, two numpy RuntimeWarnings, or "internal error: Out of range float values are
not JSON compliant". Every number now enters through
:func:`kincalc.cli.common.check_number` (tested through the CLI, where the values
enter); at the limit itself every computation stays finite (no warning even with the
CLI's backstop filter off); the TCV, whose e^(q_n/pi) outgrows any limit, is null beyond
ten turns (tested on ``FKResult``); and the backstop keeps numpy's warnings off stderr
(tested in a fresh interpreter: its stderr is the user's).
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from cli_contract import assert_contract, json_documents, run_cli
from kincalc.limits import MAX_MAGNITUDE


def run(*argv, stdin=b"", cwd=None):
    status, out, err = run_cli(list(argv), stdin, cwd)
    assert_contract(status, out, err, argv)
    return status, out, err


# --- 6. huge values ---------------------------------------------------------------------

BAD_NUMBERS = ["1e300", "-1e308", "1e10", "nan", "inf", "-inf", "1e309"]

#: (argv with {} where the bad number goes, the option or field the message must name)
NUMBER_CASES = [
    (["fk", "puma560", "0", "0", "{}", "0", "0", "0"], "joint q3"),
    (["fk", "puma560", "0", "0", "{}", "0", "0", "0", "--json"], "joint q3"),
    (["jacobian", "puma560", "0", "0", "{}", "0", "0", "0", "--json"], "joint q3"),
    (["plot", "puma560", "0", "0", "{}", "0", "0", "0", "-o", "x.png"], "joint q3"),
    (["ik", "puma560", "--xyz", "{}", "0", "0", "--rpy", "0", "0", "0"], "--xyz"),
    (["ik", "puma560", "--xyz", "0.4", "0", "0.3", "--rpy", "0", "{}", "0"], "--rpy"),
    (["ik", "puma560", "--xyz", "0.4", "0", "0.3", "--quat", "1", "0", "{}", "0"], "--quat"),
    (["ik", "puma560", "--xyz", "0.4", "0", "0.3", "--axis-angle", "0", "0", "1", "{}"],
     "--axis-angle"),
    (["ik", "puma560", "--xyz", "0.4", "0", "0.3", "--matrix", "1", "0", "0", "0", "1", "0",
      "0", "0", "{}"], "--matrix"),
    (["ik", "fer_rrpr", "--tcv", "0.4", "0", "0.3", "0", "0", "{}"], "--tcv"),
    (["ik", "puma560", "--from-q", "0 0 {} 0 0 0"], "--from-q: joint q3"),
    (["ik", "puma560", "--from-q", "0 0 0 0 0 0", "--near", "{} 0 0 0 0 0", "--json"],
     "--near: joint q1"),
    (["reach", "puma560", "--xyz", "{}", "0", "0", "--rpy", "0", "0", "0", "--json"], "--xyz"),
    (["reach", "bk_rr", "--xyz", "1", "{}", "0"], "--xyz"),
]


@pytest.mark.parametrize("value", BAD_NUMBERS)
@pytest.mark.parametrize("argv, names", NUMBER_CASES, ids=lambda c: c if isinstance(c, str)
                         else " ".join(c[:3]))
def test_numbers_beyond_the_limit_are_one_line_errors(argv, names, value, tmp_path):
    argv = [a.replace("{}", value) for a in argv]
    status, out, err = run(*argv, cwd=str(tmp_path))
    assert status == 2 and out == "", err
    assert names in err and ("too large" in err or "not a finite number" in err), err
    assert not any(tmp_path.iterdir())


#: texts Python's float() reads but that are no decimal number: 1_0 was read as 10, an
#: Arabic-Indic or a fullwidth digit as its value
NOT_DECIMAL = ["1_0", "\u0663", "\uff11", "0x10", "1e", "1.2.3"]


@pytest.mark.parametrize("value", NOT_DECIMAL)
@pytest.mark.parametrize("argv, names", NUMBER_CASES + [
    (["ik", "puma560", "--xyz", "0.4", "0", "0.3", "--rpy", "0", "0", "0", "--lock",
      "q1={}"], "--lock"),
    (["ik", "kuka_iiwa14", "--xyz", "0.4", "0", "0.3", "--rpy", "0", "0", "0", "--swivel",
      "{}"], "--swivel")], ids=lambda c: c if isinstance(c, str) else " ".join(c[:3]))
def test_a_number_is_decimal_digits(argv, names, value, tmp_path):
    argv = [a.replace("{}", value) for a in argv]
    status, out, err = run(*argv, cwd=str(tmp_path))
    assert status == 2 and out == "", err
    assert "not a number" in err or "no such option" in err or "expected" in err, err


def test_parse_decimal_reads_what_float_reads_of_decimal_text():
    """The strict reader against float(): the same value on decimal text (a seeded sample of
    signs, digits, points and exponents), a ValueError on everything float() takes besides."""
    from kincalc.limits import parse_decimal
    rng = np.random.default_rng(7)
    for _ in range(2000):
        x = float(rng.standard_normal() * 10.0 ** rng.integers(-12, 12))
        for text in (repr(x), f"{x:.3e}", f"{x:+.7f}", f"{abs(x):.0f}.", f".{rng.integers(99)}"):
            assert parse_decimal(text) == float(text), text
    for text in ["1_0", " 1", "1 ", "\u0663", "\uff11", "0x10", "1e", "", "+", ".", "e5", "1e+"]:
        with pytest.raises(ValueError):
            parse_decimal(text)
    assert np.isnan(parse_decimal("NaN")) and parse_decimal("-Infinity") == -np.inf


def test_the_limit_is_the_robot_files_and_is_inclusive():
    # 1e9 itself is a number kincalc takes (as robot files do); just beyond it is not
    status, out, _ = run("fk", "bk_rrp", "0", "0", str(MAX_MAGNITUDE), "--json")
    assert status == 0 and json_documents(out)[0]["q"][2] == MAX_MAGNITUDE
    status, _, err = run("fk", "bk_rrp", "0", "0", repr(MAX_MAGNITUDE * (1 + 1e-12)))
    assert status == 2 and "1e+09" in err


@pytest.mark.parametrize("argv", [
    ["fk", "planar_3r", "0", "0", "1e9", "--json"],
    ["fk", "planar_3r", "0", "0", "-1e9", "--json"],
    ["fk", "puma560", "1e9", "-1e9", "1e9", "-1e9", "1e9", "-1e9", "--json"],
    ["jacobian", "puma560", "1e9", "-1e9", "1e9", "-1e9", "1e9", "-1e9", "--json"],
    ["fk", "bk_rrp", "1e9", "1e9", "1e9", "--json"],
    ["jacobian", "bk_rrp", "1e9", "-1e9", "1e9", "--json", "--analytic", "rpy"],
    ["ik", "puma560", "--xyz", "1e9", "-1e9", "1e9", "--rpy", "1e9", "1e9", "1e9", "--json"],
    ["ik", "fer_rrpr", "--tcv", "1e9", "1e9", "1e9", "1e9", "1e9", "1e9", "--json"],
    ["ik", "fer_rrpr", "--tcv", "0.3", "0", "0.3", "1e-9", "0", "1e-9", "--json"],
    ["reach", "puma560", "--xyz", "1e9", "1e9", "1e9", "--rpy", "0", "0", "0", "--json"],
    ["ik", "puma560", "--from-q", "1e9 1e9 1e9 1e9 1e9 1e9", "--near", "-1e9 0 0 0 0 1e9",
     "--json"],
])
def test_largest_numbers_give_finite_json_and_no_warning(argv, monkeypatch):
    """At the limit every computation stays finite: strict JSON, and no RuntimeWarning
    even with the CLI's warning filter off (it is only a backstop)."""
    import warnings

    import kincalc.cli.main as m
    monkeypatch.setattr(m, "_quiet_numeric_warnings", lambda debug: None)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RuntimeWarning)
        status, out, err = run(*argv)
    assert not [w for w in caught if issubclass(w.category, RuntimeWarning)], \
        [str(w.message) for w in caught]
    assert status in (0, 1), err
    json_documents(out)


def test_fk_tcv_of_a_last_joint_turned_beyond_ten_turns_is_null():
    # e^(q_n/pi) is 1e9 at 65 rad and infinite from 2229 rad: the JSON said "Infinity"
    # (an internal error) and the table "nan nan inf"
    from kincalc import load_robot
    from kincalc.analysis.results import FKResult, Units
    from kincalc.spatial import TCV_MAX_ROLL
    robot = load_robot("planar_3r")
    assert TCV_MAX_ROLL == pytest.approx(np.pi * np.log(MAX_MAGNITUDE))
    for qn, given in ((TCV_MAX_ROLL * 0.999, True), (TCV_MAX_ROLL * 1.001, False),
                      (-TCV_MAX_ROLL * 1.001, False), (1e9, False)):
        q = np.array([0.0, 0.0, qn])
        tcv = FKResult(robot, q, robot.fk(q), Units(angle="rad")).to_dict()["tcv"]
        assert (tcv is not None) == given, qn
        if given:
            assert np.all(np.isfinite(tcv)) and max(map(abs, tcv)) <= MAX_MAGNITUDE * 1.01
    status, out, _ = run("fk", "planar_3r", "0", "0", "1e9")
    assert status == 0 and "nan" not in out and "inf" not in out


def test_numpy_warnings_never_reach_stderr_but_show_with_debug(tmp_path):
    """The backstop in main(): a computation that overflows (here a patched core
    function) prints no RuntimeWarning on the user's stderr; --debug shows it."""
    code = ("import sys, numpy as np, kincalc.analysis.reports as a\n"
            "orig = a.fk_report\n"
            "def noisy(*args, **kw):\n"
            "    np.float64(1e308) * 10\n"
            "    return orig(*args, **kw)\n"
            "a.fk_report = noisy\n"
            "from kincalc.cli.main import main\n"
            "sys.exit(main(sys.argv[1:]))\n")
    env = dict(os.environ, PYTHONWARNINGS="")
    quiet = subprocess.run([sys.executable, "-c", code, "fk", "puma560", "--json"],
                           capture_output=True, text=True, env=env, cwd=tmp_path, timeout=120)
    assert quiet.returncode == 0 and quiet.stderr == "", quiet.stderr
    loud = subprocess.run([sys.executable, "-c", code, "fk", "puma560", "--json", "--debug"],
                          capture_output=True, text=True, env=env, cwd=tmp_path, timeout=120)
    assert loud.returncode == 0 and "RuntimeWarning" in loud.stderr


def test_the_warning_filter_needs_no_numpy_at_start_up():
    code = ("import sys, contextlib, io\nfrom kincalc.cli.main import main\n"
            "with contextlib.redirect_stdout(io.StringIO()): main(['--version'])\n"
            "print('numpy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=120).stdout.strip()
    assert out == "False"


def test_a_number_beyond_the_limit_is_quoted_as_given(tmp_path):
    """1.000000001e9 was quoted as 1e+09 ("1e+09 is too large": a value the user never
    typed, within the limit as shown) and 1e400 as inf."""
    status, out, err = run("ik", "puma560", "--xyz", "1.000000001e9", "0", "0", "--rpy", "0",
                           "0", "0", cwd=str(tmp_path))
    assert status == 2 and "--xyz: 1000000001.0 is too large" in err
    status, out, err = run("ik", "puma560", "--xyz", "1e400", "0", "0", "--rpy", "0", "0",
                           "0", cwd=str(tmp_path))
    assert status == 2 and "--xyz: not a finite number (nan, inf, or beyond 1.8e308)" in err


def test_any_white_space_around_a_number_but_no_zero_width_character(tmp_path):
    """As the README says: a no-break or thin space around a number (pasted from a document)
    is a space; a zero-width space is not, and the number is refused."""
    ok = run("fk", "puma560", "0", "10", "0", "0", "0", "0", "--json", cwd=str(tmp_path))
    for spaced in ("\u00a010", "10\u2009", "\u300010"):
        got = run("fk", "puma560", "0", spaced, "0", "0", "0", "0", "--json", cwd=str(tmp_path))
        assert got[0] == 0 and got[1] == ok[1]
    status, out, err = run("fk", "puma560", "0", "\u200b10", "0", "0", "0", "0", cwd=str(tmp_path))
    assert status == 2 and "is not a number" in err
