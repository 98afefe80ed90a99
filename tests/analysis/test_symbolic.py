"""Symbolic link transforms, T_0^n and Jacobians (kincalc fk/jacobian --symbolic).

The formulas are checked against the numeric core: evaluated at seeded
random joint values (with the robot's parameter values put in for the
length symbols) they must give ``robot.link_transforms``, ``robot.fk`` and
``robot.jacobian`` for every bundled dh/mdh robot, the bundled poe robot
and a few poe robots written here. Then the printed forms: the textbook
abbreviations (C12, C23, S234), the JSON strings read back by sympy, the
LaTeX, --numeric-lengths, and the message when sympy is missing.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
import time

import numpy as np
import pytest

sympy = pytest.importorskip("sympy")

import kincalc  # noqa: E402
from kincalc.cli.main import main  # noqa: E402
from kincalc.conventions.library import bundled_names  # noqa: E402
from kincalc.conventions.reader import parse_robot_text  # noqa: E402
from kincalc.analysis.symbolic import require_sympy, symbolic_fk, symbolic_jacobian  # noqa: E402
from kincalc.units import LENGTH_UNITS  # noqa: E402

#: the 6- and 7-joint robots whose tool-frame Jacobian is checked too (the
#: base-frame Jacobian and T are checked for every robot; the 7-joint arms
#: take 1-2 s each per frame).
FULL_6R = {"puma560", "puma560_mdh", "bk_6r", "bk_scara_euler", "kuka_kr16", "ur5",
           "stanford_arm", "fanuc_lrmate200id", "kinova_gen3"}

POE_ROBOTS = {
    # a SCARA with a prismatic joint, as screws
    "poe_scara": """
name: poe_scara
convention: poe
units: {length: m, angle: deg}
joints:
  - {name: t1, type: revolute,  axis: [0, 0, 1],  point: [0, 0, 0]}
  - {name: t2, type: revolute,  axis: [0, 0, 1],  point: [0.4, 0, 0]}
  - {name: d3, type: prismatic, axis: [0, 0, -1], point: [0.65, 0, 0.3]}
  - {name: t4, type: revolute,  axis: [0, 0, -1], point: [0.65, 0, 0.3]}
tool: {xyz: [0.65, 0, 0.2], rpy: [180, 0, 0]}
""",
    # a tilted axis (0, 3/5, 4/5), a base transform and a tool rotation
    "poe_tilted": """
name: poe_tilted
convention: poe
units: {length: mm, angle: deg}
base: {xyz: [10, 20, 30], rpy: [0, 0, 90]}
joints:
  - {name: a, type: revolute, axis: [0, 0, 1],     point: [0, 0, 100]}
  - {name: b, type: revolute, axis: [0, 0.6, 0.8], point: [50, 0, 100]}
  - {name: c, type: revolute, axis: [1, 0, 0],     point: [250, 30, 100]}
tool: {xyz: [300, 30, 100], rpy: [0, 90, 0]}
""",
}


def _robot(name):
    if name in POE_ROBOTS:
        return parse_robot_text(POE_ROBOTS[name], name)
    return kincalc.load_robot(name)


def _random_q(robot, rng, k=3):
    q = rng.uniform(-np.pi, np.pi, (k, robot.dof))
    for i, j in enumerate(robot.joints):
        if not j.revolute:
            lo, hi = j.limits if j.limits is not None else (0.0, robot.characteristic_length)
            q[:, i] = rng.uniform(lo, hi, k)
    return q


def _evaluator(result, M):
    """A numpy function of the joint values (file units) for the sympy matrix M."""
    n = result.notation
    expr = n.expand(M).xreplace(n.substitutions())
    free = expr.free_symbols - set(n.joints)
    assert not free, f"unexpected symbols {free}"
    f = sympy.lambdify(n.joints, expr, "numpy")
    return lambda q: np.array(f(*q), dtype=float)


def _file_units(robot, q):
    """SI joint values -> the symbols' units (prismatic in the file's length unit)."""
    return np.where(robot.is_revolute, q, q / LENGTH_UNITS[robot.length_unit])


def _to_si_pose(robot, T):
    T = T.copy()
    T[:3, 3] *= LENGTH_UNITS[robot.length_unit]
    return T


def _to_si_jacobian(robot, J):
    J = J.copy()
    J[:3, robot.is_revolute] *= LENGTH_UNITS[robot.length_unit]
    return J


def _dh_names():
    out = []
    for name in bundled_names():
        r = kincalc.load_robot(name)
        if r.convention in ("dh", "mdh"):
            out.append(name)
    return out


DH_ROBOTS = _dh_names()


# --- against the numeric core ---------------------------------------------------

@pytest.mark.parametrize("name", DH_ROBOTS + ["ur5_poe", *POE_ROBOTS])
def test_fk_formulas_match_numeric_fk(name):
    robot = _robot(name)
    rng = np.random.default_rng(sum(map(ord, name)))
    res = symbolic_fk(robot)
    T = _evaluator(res, res.T)
    links = [_evaluator(res, A) for A in res.links]
    for q in _random_q(robot, rng):
        qs = _file_units(robot, q)
        np.testing.assert_allclose(_to_si_pose(robot, T(qs)), robot.fk(q), atol=1e-9,
                                   err_msg=f"{name}: T at q = {q}")
        A = robot.link_transforms(q)
        for i, f in enumerate(links):
            np.testing.assert_allclose(_to_si_pose(robot, f(qs)), A[i], atol=1e-9,
                                       err_msg=f"{name}: T_{i}^{i + 1} at q = {q}")


JACOBIAN_CASES = [(n, "base") for n in DH_ROBOTS + ["ur5_poe", *POE_ROBOTS]] + [
    (n, "tool") for n in sorted(n for n in DH_ROBOTS
                                if kincalc.load_robot(n).dof < 6 or n in FULL_6R)
    + ["ur5_poe", *POE_ROBOTS]]


@pytest.mark.parametrize("name, frame", JACOBIAN_CASES)
def test_jacobian_formulas_match_numeric_jacobian(name, frame):
    robot = _robot(name)
    rng = np.random.default_rng(sum(map(ord, name)) + 7)
    res = symbolic_jacobian(robot, frame=frame)
    assert res.J.shape == (6, robot.dof)
    J = _evaluator(res, res.J)
    for q in _random_q(robot, rng):
        np.testing.assert_allclose(_to_si_jacobian(robot, J(_file_units(robot, q))),
                                   robot.jacobian(q, frame=frame), atol=1e-9,
                                   err_msg=f"{name} ({frame} frame) at q = {q}")


@pytest.mark.parametrize("name", ["puma560", "kuka_kr16", "fer_rrpr", "ur5_poe"])
def test_numeric_lengths_leave_only_joint_symbols(name):
    robot = _robot(name)
    res = symbolic_fk(robot, numeric_lengths=True)
    jac = symbolic_jacobian(robot, numeric_lengths=True)
    assert res.notation.parameters == () and jac.notation.parameters == ()
    allowed = set(res.notation.joints) | {s for s, _ in res.notation.legend}
    for M in (*res.links, res.T):
        assert M.free_symbols <= allowed
    assert jac.J.free_symbols <= set(jac.notation.joints) | {s for s, _ in jac.notation.legend}
    q = _random_q(robot, np.random.default_rng(3), 1)[0]
    T = _evaluator(res, res.T)(_file_units(robot, q))
    np.testing.assert_allclose(_to_si_pose(robot, T), robot.fk(q), atol=1e-9)


def test_numeric_lengths_in_another_unit():
    robot = kincalc.load_robot("fer_rrpr")          # metres
    res = symbolic_jacobian(robot, numeric_lengths=True, length_unit="mm")
    assert res.length_unit == "mm"
    q = np.array([0.3, -1.1, 0.25, 0.7])
    J = _evaluator(res, res.J)(np.where(robot.is_revolute, q, q * 1000))
    J[:3, robot.is_revolute] /= 1000
    np.testing.assert_allclose(J, robot.jacobian(q), atol=1e-12)


# --- the simplifier ----------------------------------------------------------------

def _collapse(e):
    from kincalc.analysis.symbolic.simplify import collapse
    return collapse(sympy.expand(e), sympy)


@pytest.mark.parametrize("closed", ["cos(x + y)", "cos(x - y)", "sin(x + y)", "sin(x - y)",
                                    "sin(y - x)", "-3*l*cos(z)*sin(x - y)",
                                    "l*cos(x + y + z) - m*sin(x + y)", "cos(x - y - z)",
                                    "2*sin(x + y)*cos(z + w)"])
def test_collapse_recovers_sums_of_angles(closed):
    x, y, z, w, l, m = sympy.symbols("x y z w l m", real=True)
    target = sympy.sympify(closed, locals=dict(x=x, y=y, z=z, w=w, l=l, m=m))
    expanded = sympy.expand(sympy.expand_trig(target))
    assert expanded != target
    assert sympy.expand(_collapse(expanded) - target) == 0, _collapse(expanded)


def test_collapse_pythagoras_and_what_it_leaves_alone():
    x, y, l = sympy.symbols("x y l", real=True)
    c, s = sympy.cos, sympy.sin
    assert _collapse(l * c(x) ** 2 * c(y) + l * s(x) ** 2 * c(y)) == l * c(y)
    # coefficients that do not match are not touched
    e = 2 * c(x) * c(y) - 3 * s(x) * s(y)
    assert _collapse(e) == e
    e = c(x) * s(x) + c(y)
    assert _collapse(e) == e


# --- the forms ---------------------------------------------------------------

def _strings(M):
    from kincalc.analysis.symbolic import expr_str
    return [[expr_str(M[r, c]) for c in range(M.shape[1])] for r in range(M.shape[0])]


@pytest.mark.parametrize("name", ["puma560", "ur5_poe", "kinova_gen3", "manocha_canny_6r",
                                  "fer_rrpr", "kuka_kr16"])
def test_printed_strings_are_the_matrices(name):
    """What is printed (reordered, factored, decimals) reads back as the same
    function of the symbols, the abbreviations taken as free symbols."""
    from kincalc.analysis.symbolic import expr_str
    robot = kincalc.load_robot(name)
    rng = np.random.default_rng(5)
    fk, jac = symbolic_fk(robot), symbolic_jacobian(robot)
    for M in (*fk.links, fk.T, jac.J):
        syms = sorted(M.free_symbols, key=str)
        names = {str(x): x for x in syms}
        back = sympy.Matrix(M.shape[0], M.shape[1],
                            lambda r, c: sympy.sympify(expr_str(M[r, c]), locals=names))
        f, g = sympy.lambdify(syms, M, "numpy"), sympy.lambdify(syms, back, "numpy")
        for _ in range(2):
            v = rng.uniform(-1, 1, len(syms))
            np.testing.assert_allclose(np.array(g(*v), float), np.array(f(*v), float),
                                       rtol=1e-12, atol=1e-12)


def test_planar_rr_collapses_to_c12_s12():
    res = symbolic_fk(kincalc.load_robot("bk_rr"))
    T = _strings(res.T)
    assert T[0][:3] == ["C12", "-S12", "0"] and T[1][:3] == ["S12", "C12", "0"]
    # the tool Tx(l2) = Tx(5) is numeric, l1 keeps its name
    assert T[0][3] == "l1*C1 + 5*C12" and T[1][3] == "l1*S1 + 5*S12"
    legend = {str(s): str(f) for s, f in res.notation.legend}
    assert legend["C12"] == "cos(theta1 + theta2)" and legend["S1"] == "sin(theta1)"


def test_planar_3r_jacobian_has_c123():
    res = symbolic_jacobian(kincalc.load_robot("planar_3r"))
    J = _strings(res.J)
    assert J[0] == ["-l1*S1 - l2*S12 - l3*S123", "-l2*S12 - l3*S123", "-l3*S123"]
    assert J[1] == ["l1*C1 + l2*C12 + l3*C123", "l2*C12 + l3*C123", "l3*C123"]
    assert J[5] == ["1", "1", "1"]


def test_puma_has_c23_s23_in_the_textbook_form():
    res = symbolic_fk(kincalc.load_robot("puma560"))
    T = _strings(res.T)
    # Craig, Introduction to Robotics, eq. 3.14 (with Corke's a2, a3, d3, d4)
    assert T[0][3] == "C1*(a2*C2 + a3*C23 - d4*S23) + d3*S1"
    assert T[1][3] == "S1*(a2*C2 + a3*C23 - d4*S23) - d3*C1"
    assert T[2][3] == "a2*S2 + d4*C23 + a3*S23"
    assert T[0][0] == "C1*(C23*(C4*C5*C6 - S4*S6) - S23*S5*C6) - S1*(C4*S6 + S4*C5*C6)"
    assert T[2][2] == "C23*C5 - S23*C4*S5"
    assert [str(s) for s, _ in res.notation.parameters] == ["a2", "a3", "d3", "d4"]


def test_ur5_poe_collapses_three_parallel_axes():
    res = symbolic_fk(kincalc.load_robot("ur5_poe"))
    T = _strings(res.T)
    assert T[2][2] == "-S234*S5"
    assert "C234" in T[0][0] and "S234" in T[2][0]


def test_scara_euler_keeps_the_book_names():
    res = symbolic_fk(kincalc.load_robot("bk_scara_euler"))
    assert [str(s) for s, _ in res.notation.parameters] == ["h1", "l1", "l2", "d4"]
    T = _strings(res.T)
    assert T[2][3] == "h1 - d3 - d4"
    assert T[0][3] == "l1*C1 + l2*C12"
    # alpha = 180 on the prismatic joint: exact integers, the variable in d
    assert _strings(res.links[2])[:3] == [["1", "0", "0", "l2"], ["0", "-1", "0", "0"],
                                          ["0", "0", "-1", "-d3"]]


def test_fer_homework_tool_position():
    """p = (0, q3 + d4, d1) at q1 = q2 = 90 deg, q4 = 0 (the homework's result)."""
    robot = kincalc.load_robot("fer_rrpr")
    res = symbolic_fk(robot)
    q1, q2, q3, q4 = res.notation.joints
    p = res.notation.expand(res.T[:3, 3]).subs({q1: sympy.pi / 2, q2: sympy.pi / 2, q4: 0})
    d1, d4 = (s for s, _ in res.notation.parameters)
    assert sympy.simplify(p - sympy.Matrix([0, q3 + d4, d1])) == sympy.zeros(3, 1)


def test_constant_angles_are_exact():
    # kuka_kr16: theta offset 90 deg on A3, base and tool Rx(180)
    res = symbolic_fk(kincalc.load_robot("kuka_kr16"))
    for M in (*res.links, res.base, res.tool):
        for e in M:
            assert not e.atoms(sympy.Float), f"inexact entry {e}"
            assert not (e.atoms(sympy.cos, sympy.sin) and e.atoms(sympy.pi)), e
    assert _strings(res.base) == [["1", "0", "0", "0"], ["0", "-1", "0", "0"],
                                  ["0", "0", "-1", "0"], ["0", "0", "0", "1"]]


def test_joint_symbols_fall_back_to_theta_and_d():
    text = """
name: odd_names
convention: dh
units: {length: m, angle: deg}
parameters: {q1: 0.5}
joints:
  - {name: q1, type: revolute, alpha: 0, a: q1, d: 0, theta: 0}
  - {name: slide, type: prismatic, alpha: 0, a: 0, d: 0, theta: 0}
"""
    res = symbolic_fk(parse_robot_text(text))
    assert [str(s) for s in res.notation.joints] == ["theta1", "d2"]
    assert _strings(res.T)[0][3] == "q1*C1"


# --- the command line ------------------------------------------------------------

def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_json_strings_read_back_with_sympy(capsys):
    code, out, err = run(capsys, "fk", "bk_scara_euler", "--symbolic", "--json")
    assert code == 0, err
    doc = json.loads(out)
    for key in ("kincalc", "command", "robot", "units"):
        assert key in doc
    assert doc["command"] == "fk" and doc["symbolic"] is True
    assert doc["units"] == {"angle": "rad", "length": "unitless"}
    assert doc["parameters"] == {"h1": 22, "l1": 26, "l2": 18, "d4": 4}
    assert [j["symbol"] for j in doc["joints"]] == ["theta1", "theta2", "d3", "theta4",
                                                   "theta5", "theta6"]
    assert "\\begin{bmatrix}" in doc["latex"]
    names = {j["symbol"]: sympy.Symbol(j["symbol"], real=True) for j in doc["joints"]}
    names.update({p: sympy.Symbol(p, real=True) for p in doc["parameters"]})
    names.update({a: sympy.Symbol(a, real=True) for a in doc["legend"]})
    legend = {names[a]: sympy.sympify(v, locals=names) for a, v in doc["legend"].items()}
    values = {names[p]: v for p, v in doc["parameters"].items()}
    T = sympy.Matrix([[sympy.sympify(e, locals=names) for e in row] for row in doc["T"]])
    f = sympy.lambdify([names[j["symbol"]] for j in doc["joints"]],
                       T.xreplace(legend).xreplace(values), "numpy")
    robot = kincalc.load_robot("bk_scara_euler")
    for q in _random_q(robot, np.random.default_rng(11)):
        np.testing.assert_allclose(np.array(f(*q), float), robot.fk(q), atol=1e-9)


def test_jacobian_json(capsys):
    code, out, err = run(capsys, "jacobian", "bk_rr", "--symbolic", "--json", "--frame", "tool")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["command"] == "jacobian" and doc["frame"] == "tool"
    assert doc["rows"] == ["vx", "vy", "vz", "wx", "wy", "wz"]
    assert doc["J"][0] == ["l1*S2", "0"] and doc["J"][1] == ["l1*C2 + 5", "5"]


def test_numeric_lengths_json_has_no_length_names(capsys):
    code, out, err = run(capsys, "fk", "puma560", "--symbolic", "--numeric-lengths", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["parameters"] == {} and doc["numeric_lengths"] is True
    text = json.dumps(doc["T"]) + json.dumps(doc["links"])
    for name in ("a2", "a3", "d3", "d4"):
        assert not re.search(rf"\b{name}\b", text), name
    assert doc["T"][0][3] == "C1*(0.4318*C2 + 0.0203*C23 - 0.4318*S23) + 0.15005*S1"


def test_tables(capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "100")
    code, out, err = run(capsys, "fk", "puma560", "--symbolic")
    assert code == 0, err
    assert "px  = C1·(a2·C2 + a3·C23 - d4·S23) + d3·S1" in out
    assert "C23 = cos(q2 + q3)" in out
    code, out, err = run(capsys, "fk", "bk_rr", "--symbolic")
    assert code == 0, err
    assert "joint variables: θ1 (angle), θ2 (angle)" in out
    assert "l1·C1 + 5·C12" in out and "C12 = cos(θ1 + θ2)" in out
    code, out, err = run(capsys, "jacobian", "puma560", "--symbolic")
    assert code == 0, err
    assert "J(wz, q6) = C23·C5 - S23·C4·S5" in out


def _balanced_latex(text: str) -> None:
    body = "\n".join(line for line in text.splitlines() if not line.startswith("%"))
    depth = 0
    for k, ch in enumerate(body):
        if ch in "{}" and k and body[k - 1] == "\\":
            continue
        depth += {"{": 1, "}": -1}.get(ch, 0)
        assert depth >= 0, f"unbalanced '}}' at {k}: {body[max(0, k - 40):k + 1]!r}"
    assert depth == 0, "unclosed '{'"
    stack = []
    for m in re.finditer(r"\\(begin|end)\{(\w+\*?)\}|\\(\[|\])|\\(left|right)\b", body):
        if m.group(1) == "begin":
            stack.append(m.group(2))
        elif m.group(1) == "end":
            assert stack and stack.pop() == m.group(2), f"\\end{{{m.group(2)}}} does not match"
        elif m.group(3) == "[":
            assert "[" not in stack, "nested \\["
            stack.append("[")
        elif m.group(3) == "]":
            assert stack and stack.pop() == "[", "\\] without \\["
        elif m.group(4) == "left":
            stack.append("left")
        else:
            assert stack and stack.pop() == "left", "\\right without \\left"
    assert not stack, f"unclosed {stack}"
    assert body.count("$") % 2 == 0


def test_latex_is_balanced_with_bmatrix(capsys):
    code, out, err = run(capsys, "fk", "puma560", "--latex")
    assert code == 0, err
    _balanced_latex(out)
    assert out.count("\\begin{bmatrix}") == 7           # 6 links and T_0^6
    assert "{}^{0}T_{6} = \\begin{bmatrix}" in out
    assert "$C_{23} = \\cos(q_{2} + q_{3})$" in out
    assert "$a_{2} = 0.4318\\,\\mathrm{m}$" in out
    code, out, err = run(capsys, "jacobian", "bk_rr", "--latex")
    assert code == 0, err
    _balanced_latex(out)
    assert out.count("\\begin{bmatrix}") == 1
    assert "$C_{12} = \\cos(\\theta_{1} + \\theta_{2})$" in out
    assert "- l_{1} S_{1} - 5 S_{12}" in out


def test_balanced_latex_check_can_fail():
    for bad in ("\\[ {x \\]", "\\[ x \\] }", "\\begin{bmatrix} x \\end{matrix}",
                "\\[ \\left( x \\]"):
        with pytest.raises(AssertionError):
            _balanced_latex(bad)


@pytest.mark.parametrize("argv, message", [
    (["fk", "bk_rr", "30", "40", "--symbolic"], "give no joint values Q"),
    (["fk", "bk_rr", "--numeric-lengths"], "--numeric-lengths needs --symbolic or --latex"),
    (["jacobian", "puma560", "--symbolic", "--analytic", "rpy"], "--analytic is not available"),
    (["fk", "puma560", "--symbolic", "--unit", "mm"], "add --numeric-lengths"),
    (["fk", "bk_rr", "--symbolic", "--unit", "mm"], "unitless"),
])
def test_usage_errors(capsys, argv, message):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and message in err, err


@pytest.mark.parametrize("argv, command", [
    (["fk", "bk_rr", "--symbolic"], "kincalc fk --symbolic"),
    (["fk", "bk_rr", "--latex"], "kincalc fk --latex"),
    (["jacobian", "puma560", "--symbolic", "--json"], "kincalc jacobian --symbolic"),
])
def test_without_sympy(capsys, monkeypatch, argv, command):
    monkeypatch.setitem(sys.modules, "sympy", None)     # `import sympy` raises ImportError
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    assert err == (f"kincalc: error: {command} needs sympy, which is not installed: "
                   "pip install 'kincalc[symbolic]'\n")


def test_require_sympy_without_sympy(monkeypatch):
    from kincalc.analysis.plot import MissingExtra
    monkeypatch.setitem(sys.modules, "sympy", None)
    with pytest.raises(MissingExtra) as err:
        require_sympy("kincalc fk --symbolic")
    assert err.value.exit_status == 2 and err.value.extra == "symbolic"


def test_sympy_is_imported_lazily():
    code = ("import sys, contextlib, io\n"
            "import kincalc.analysis.symbolic, kincalc.cli.fk, kincalc.cli.jacobian\n"
            "from kincalc.cli.main import main\n"
            "with contextlib.redirect_stdout(io.StringIO()): main(['fk', 'bk_rr', '30', '40'])\n"
            "print('sympy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


@pytest.mark.parametrize("name", ["puma560", "bk_6r", "kuka_kr16", "ur5"])
def test_six_joint_derivations_take_seconds(name):
    robot = kincalc.load_robot(name)
    require_sympy("test")
    t0 = time.perf_counter()
    symbolic_fk(robot)
    symbolic_jacobian(robot)
    assert time.perf_counter() - t0 < 10.0


def test_more_joints_than_symbolic_expands_is_one_line():
    """The expressions grow about 1.7 times a joint (fk --symbolic of 32 joints ran for
    hours): beyond MAX_SYMBOLIC_JOINTS both commands refuse in one line, before sympy."""
    from kincalc.errors import InputError
    from kincalc.limits import MAX_SYMBOLIC_JOINTS
    n = MAX_SYMBOLIC_JOINTS + 1
    text = ("name: snake\nconvention: dh\nunits: {length: m, angle: deg}\njoints:\n" +
            "".join(f"  - {{name: q{i + 1}, type: revolute, alpha: 90, a: 0.01, d: 0.01, "
                    "theta: 0}\n" for i in range(n)))
    robot = parse_robot_text(text, "snake.yaml")
    for build, command in ((symbolic_fk, "fk"), (symbolic_jacobian, "jacobian")):
        with pytest.raises(InputError, match=f"kincalc {command} --symbolic: snake has {n} "
                                             f"joints; symbolic expressions are expanded for "
                                             f"up to {MAX_SYMBOLIC_JOINTS} joints"):
            build(robot)


NEAR_90 = """
name: near90
convention: dh
units: {length: m, angle: deg}
joints:
  - {name: q1, type: revolute, alpha: 89.9999999, a: 0.5, d: 0.2, theta: 30.0000001}
  - {name: q2, type: revolute, alpha: 0.0000001, a: 0.4, d: 0, theta: 0}
"""


def test_a_twist_without_a_closed_form_has_the_cosine_of_the_twist_held():
    """cos(89.9999999 deg) = 1.745e-9: from the angle rounded to 12 digits first it had three
    right digits (1.74489661923e-9); it is the cosine of the twist the robot holds."""
    import math
    robot = parse_robot_text(NEAR_90)
    res = symbolic_fk(robot)
    for i, A in enumerate(res.links):
        alpha = robot.joints[i].alpha
        assert abs(float(A[2, 2]) - math.cos(alpha)) <= 1e-11 * abs(math.cos(alpha))
        assert abs(float(A[2, 1]) - math.sin(alpha)) <= 1e-11 * abs(math.sin(alpha))
