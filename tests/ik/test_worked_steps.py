"""--explain (issue 19): the steps the engine notes are true of the solutions they belong
to, and they are written in the textbook's equations with the numbers put in."""

import re

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.analysis.explain import worked_steps
from kincalc.analysis.results import Units
from kincalc.ik import Target
from kincalc.ik.solve import solve
from kincalc.spatial import wrap
from randrobots import random_robot


def _explained(name, q_deg):
    r = load_robot(name)
    T = r.fk(np.radians(q_deg))
    return r, T, solve(r, Target(T), explain=True)


@pytest.mark.parametrize("name", ["puma560", "puma560_mdh", "kuka_kr16", "abb_irb120",
                                  "stanford_arm", "bk_scara_euler", "siciliano_arm_6r",
                                  "spong_spherical_rrp", "stanford_arm_mdh", "spong_scara",
                                  "adept_cobra600", "ur5", "mycobot_280", "bk_offset_wrist"])
def test_noted_equations_hold_at_the_solutions(name):
    """Each noted ``A cos q + B sin q + C = t`` holds at the solution's own q, and each noted
    turn is ``q = atan2(p2, p1) - atan2(f2, f1)``: the notes are the steps that made q."""
    rng = np.random.default_rng(15)
    r = load_robot(name)
    lo, hi = np.clip(r.limits.T, -2.5, 2.5)
    for _ in range(5):
        res = solve(r, Target(r.fk(rng.uniform(lo, hi))), explain=True)
        assert res.solutions
        for s in res.solutions:
            kinds = [kind.split(":")[0] for _, _, kind in s.trace]
            assert "abc" in kinds or "turn" in kinds, s.trace
            for _, value, kind in s.trace:
                parts = kind.split(":")
                if parts[0] == "abc":
                    A, B, C, t = value[:4]
                    x = s.q[int(parts[1])]
                    scale = max(abs(A), abs(B), abs(C), abs(t), 1e-300)
                    assert abs(A * np.cos(x) + B * np.sin(x) + C - t) < 1e-8 * scale
                elif parts[0] in ("turn", "roll", "dir"):
                    g1, g2, f1, f2 = value
                    x = s.q[int(parts[1])]
                    assert abs(wrap(np.arctan2(g2, g1) - np.arctan2(f2, f1) - x)) < 1e-8
                elif parts[0] == "quad":
                    A, B, C, t = value
                    x = s.q[int(parts[1])]
                    scale = max(abs(A) * x * x, abs(B * x), abs(C), abs(t), 1e-300)
                    assert abs(A * x * x + B * x + C - t) < 1e-8 * scale
                elif parts[0] == "slide":
                    g, f = value
                    assert abs(g - f - s.q[int(parts[1])]) < 1e-9
                elif parts[0] == "sum":     # q = s (psi - sum s_i q_i), the others' values
                    psi, *others = value
                    sense = lambda x: 1.0 if x == "+" else -1.0          # noqa: E731
                    rest = [(int(i), sense(x)) for i, x in zip(parts[3::2], parts[4::2])]
                    assert [s.q[i] for i, _ in rest] == others
                    x = sense(parts[2]) * (psi - sum(w * s.q[i] for i, w in rest))
                    assert abs(wrap(x - s.q[int(parts[1])])) < 1e-9


@pytest.mark.parametrize("types", ["PRR", "RPR", "RRP", "PRP"])
def test_noted_slides_hold_on_random_arms(types):
    """Random three-joint arms with a sliding joint placing a point: each noted slide
    ``d = p - f`` and quadratic ``A d^2 + B d + C = t`` holds at the solution's own d."""
    rng = np.random.default_rng(17)
    noted = set()
    for _ in range(6):
        r = random_robot(rng, "dh", n=3, types=types)
        T = r.fk(rng.uniform(-1, 1, 3))
        res = solve(r, Target(T, orientation=False), explain=True)
        for s in res.solutions:
            for _, value, kind in s.trace:
                parts = kind.split(":")
                x = s.q[int(parts[1])]
                if parts[0] == "quad":
                    A, B, C, t = value
                    scale = max(abs(A) * x * x, abs(B * x), abs(C), abs(t), 1e-300)
                    assert abs(A * x * x + B * x + C - t) < 1e-8 * scale
                elif parts[0] == "slide":
                    assert abs(value[0] - value[1] - x) < 1e-9
                noted.add(parts[0])
    assert noted & {"quad", "slide"}, noted


def test_planar_rr_in_the_chapters_words():
    """Example 4.2: cos theta2 = (px^2 + py^2 - l1^2 - l2^2) / (2 l1 l2), worked out by hand
    as (12.99^2 + 2.5^2 - 100 - 25) / 100 = 0.499901, theta2 = +-60.0065 deg; then
    theta1 = atan2(py, px) - atan2(l2 sin theta2, l1 + l2 cos theta2)."""
    r = load_robot("bk_rr")
    T = np.eye(4)
    T[:3, 3] = [12.99, 2.5, 0]
    res = solve(r, Target(T, orientation=False), explain=True)
    for s in res.solutions:
        steps = worked_steps(r, s, T, Units("deg", "unitless"), res.family)
        assert [e["step"] for e in steps] == ["theta2", "theta1"]
        two, one = steps[0]["text"], steps[1]["text"]
        assert "cos theta2 = (|p - o|² - l1² - l2²) / (2 l1 l2)" in two
        assert "(174.9901 - 100 - 25) / (2·10·5) = 0.499901" in two and "±60.0065°" in two
        q2 = np.arccos(0.499901) * np.sign(s.q[1])
        f = (10 + 5 * np.cos(q2), 5 * np.sin(q2))
        got = re.search(r"atan2\(2\.5, 12\.99\) - atan2\(([-\d.e]+), ([-\d.e]+)\)", one)
        assert got and np.allclose([float(got.group(1)), float(got.group(2))], f[::-1],
                                   atol=1e-5)
        assert f": theta1 = {np.degrees(s.q[0]):.6g}° (p: where the point placed must go" in one


def test_spherical_wrist_in_the_chapters_words():
    """The PUMA: p_w = p (d6 = 0), then R_3^6 = (R_0^3)^T R and its ZYZ angles, which are
    (q4, -q5, q6) for Corke's twists (alpha4 = 90, alpha5 = -90 deg)."""
    r, T, res = _explained("puma560", [10, -30, 40, 25, 40, 35])
    for s in res.solutions:
        steps = worked_steps(r, s, T, Units(), res.family)
        names = [e["step"] for e in steps]
        assert names[0] == "wrist centre" and names[-4:] == ["R_3^6", "q5", "q4", "q6"]
        text = {e["step"]: e["text"] for e in steps}
        assert text["q5"].startswith("-q5 = atan2(")
        for j, name in ((3, "q4"), (5, "q6")):
            got = float(re.search(name + r" = (-?[\d.e+-]+)°", text[name]).group(1))
            assert abs(wrap(np.radians(got) - s.q[j])) < 1e-5


def test_wrist_centre_is_p_minus_d_along_the_approach():
    """The KUKA KR 16's flange is 158 mm beyond the wrist centre along the approach."""
    r, T, res = _explained("kuka_kr16", [10, -60, 70, 20, 30, 40])
    steps = worked_steps(r, res.solutions[0], T, Units("deg", "mm"), res.family)
    assert steps[0]["text"].startswith("p_w = p - d·a = ") and "- 158·(" in steps[0]["text"]


def test_no_symbol_of_the_dh_table():
    """alpha, theta, a and d are the DH table's: the steps use A, B, C, t, p, o, f."""
    for name, q in [("puma560", [10, -30, 40, 25, 40, 35]), ("kuka_kr16", [10, -60, 70, 20, 30, 40])]:
        r, T, res = _explained(name, q)
        for s in res.solutions:
            for e in worked_steps(r, s, T, Units(), res.family):
                assert "α" not in e["text"] and "alpha" not in e["text"]


def test_law_of_cosines_only_for_a_planar_triangle():
    """The SCARA of Example 4.6 measures |p - o| in space, with the wrist centre below the
    arm's plane: C is not l1^2 + l2^2 of its links (26 and 18), so no law of cosines with
    sides made up from C and A; a height (the FER arm's q2) is never one."""
    r = load_robot("bk_scara_euler")
    from kincalc.spatial import matrix_from_rpy, transform
    T = transform(matrix_from_rpy(np.radians([42, -17, 25])), [28, 31, 6])
    res = solve(r, Target(T), explain=True)
    text = {e["step"]: e["text"] for e in worked_steps(r, res.solutions[0], T,
                                                        Units("deg", "unitless"), res.family)}
    assert text["theta2"].startswith("cos theta2 = (t - C) / A = ")
    assert "law of cosines" not in text["theta2"]
    r, T, res = _explained("fer_rrpr", [30, 60, 0, 20])
    for s in res.solutions:
        for e in worked_steps(r, s, T, Units(), res.family):
            assert "law of cosines" not in e["text"]


def test_a_turn_beyond_the_formulas_range_is_said():
    """q2 = 200 deg is within the PUMA's limits [-45, 225]: the formula gives -160 deg and
    the step says the solution keeps 200 (the table's value)."""
    r, T, res = _explained("puma560", [10, 200, -30, 40, 50, 60])
    texts = [e["text"] for s in res.solutions for e in worked_steps(r, s, T, Units(), res.family)]
    assert any("q2 = -160° (= 200° within its limits)" in t for t in texts)


def test_the_wrist_starts_from_the_target_not_the_answer():
    """The KUKA KR 16 has a base and a tool transform: R_0^6 is the target's rotation with
    them taken off, (R_0^3)^T R_0^6 computed here from the target and the solution's
    first three links."""
    r, T, res = _explained("kuka_kr16", [10, -80, 100, 40, 50, 60])
    for s in res.solutions:
        A = r.link_transforms(s.q)
        R36 = (A[0] @ A[1] @ A[2])[:3, :3].T @ (np.linalg.inv(r.base) @ T @ np.linalg.inv(r.tool))[:3, :3]
        text = {e["step"]: e["text"] for e in worked_steps(r, s, T, Units(), res.family)}
        got = [float(x) for x in re.search(r"R_0\^6 = \[([^\]]*)\]", text["R_3^6"]).group(1)
               .replace(";", " ").split()]
        assert np.allclose(np.reshape(got, (3, 3)), R36, atol=1e-8)


def test_the_command_line_shows_the_steps():
    """`kincalc ik bk_rr --xyz 12.99 2.5 0 --explain` prints each solution's steps under
    its branch; --json carries them as trace [{step, text}]."""
    import json

    from cli_contract import run_cli
    argv = ["ik", "bk_rr", "--xyz", "12.99", "2.5", "0", "--explain"]
    status, out, err = run_cli(argv)
    assert status == 0 and err == ""
    assert "solution 1: elbow down" in out and "cos theta2 = (|p - o|² - l1² - l2²)" in out
    status, out, _ = run_cli(argv + ["--json"])
    trace = json.loads(out)["solutions"][0]["trace"]
    assert [e["step"] for e in trace] == ["theta2", "theta1"]
    assert all(set(e) == {"step", "text"} for e in trace)


def test_the_slide_of_a_stanford_arm_is_a_step():
    """The Stanford arm's d3 from |p_w - o|^2 = d3^2 + d2^2 (o on axis 1, d2 = 0.154 m the
    shoulder offset; Spong's derivation: d3 = sqrt(r^2 + s^2), r^2 = xc^2 + yc^2 - d2^2):
    written as the quadratic with its two roots +-d3, in the user's length unit."""
    r = load_robot("stanford_arm")
    q = np.radians([10.0, 20.0, 0.0, 30.0, 40.0, 50.0])
    q[2] = 0.3
    T = r.fk(q)
    res = solve(r, Target(T), explain=True)
    for units, d3 in ((Units("deg", "m"), "0.3"), (Units("deg", "mm"), "300")):
        for s in res.solutions:
            steps = worked_steps(r, s, T, units, res.family)
            assert [e["step"] for e in steps][:2] == ["wrist centre", "d3"]
            text = steps[1]["text"]
            c = {"m": 0.154 ** 2, "mm": 154.0 ** 2}[units.length]
            assert text.startswith(f"d3² + {c:.9g} = t = "), text
            assert f"= -{d3} or {d3}: d3 = " in text, text


def test_a_scaras_roll_is_a_step():
    """A SCARA's last joint from the orientation: a line ``theta4 = atan2(u2, u1) -
    atan2(e2, e1) = ...: theta4 = <its value>`` after the placing joints', in every
    solution, and d3 from the height, ``-d3 = t`` (Spong's d3 = -z up to the offsets)."""
    r = load_robot("spong_scara")
    T = r.fk(np.array([np.radians(30), np.radians(40), 0.1, np.radians(50)]))
    res = solve(r, Target(T), explain=True)
    assert len(res.solutions) == 2
    for s in res.solutions:
        steps = worked_steps(r, s, T, Units("deg", "m"), res.family)
        assert [e["step"] for e in steps] == ["d3", "theta2", "theta1", "theta4"]
        assert steps[0]["text"].startswith("-d3 = t = -0.1 ")
        want = f"theta4 = {float(wrap(s.q[3])) * 180 / np.pi:.6g}°"
        assert steps[3]["text"].startswith("theta4 = atan2(u2, u1) - atan2(e2, e1) = ")
        assert want in steps[3]["text"], (want, steps[3]["text"])


def test_a_joint_whose_axis_holds_the_point_is_said_to_be_free():
    """Two joints, the second's axis through the tool point (a = 0 after it): its step is
    ``0 cos q2 + 0 sin q2 + 0 = t``, which every q2 solves. It once read ``0° ± nan°``
    (acos of 0 / 0), in the table and in the JSON trace (a fuzz campaign's finding)."""
    from kincalc import parse_robot_text
    r = parse_robot_text("name: min\nconvention: dh\nunits: {length: m, angle: deg}\njoints:\n"
                         "  - {name: j1, type: revolute, alpha: 0, a: 1, d: 0, theta: 0}\n"
                         "  - {name: j2, type: revolute, alpha: 0, a: 0, d: 0, theta: 0}\n")
    T = np.eye(4)
    T[0, 3] = 1.0
    res = solve(r, Target(T, orientation=False), explain=True)
    assert len(res.solutions) == 1 and res.solutions[0].free == (1,)
    text = " ".join(e["text"] for e in worked_steps(r, res.solutions[0], T, Units("deg", "m"),
                                                    res.family))
    assert "nan" not in text.lower()
    assert "every j2 solves it (j2 free)" in text


@pytest.mark.parametrize("name", ["puma560", "ur5", "bk_offset_wrist", "dobot_magician",
                                  "manocha_canny_6r", "stanford_arm"])
def test_explain_names_every_joint_of_every_solution(name):
    """--explain wrote theta1's step alone for the textbook's offset-wrist arm and nothing at
    all for a general 6R (a check of the seed documents). Every joint is now in a step: a
    worked one, or the line that says how the closed form found the rest, with its value."""
    robot = load_robot(name)
    q = np.radians([10, -30, 40, 20, 50, 30])[:robot.dof]
    q[~robot.is_revolute] = 0.2
    T = robot.fk(q)
    res = solve(robot, Target(T), explain=True)
    assert res.solutions
    for s in res.solutions:
        steps = worked_steps(robot, s, T, Units(), res.family)
        named = [p.strip() for step in steps for p in step["step"].split(",")]
        assert {j.name for j in robot.joints} <= set(named), (name, named)
        rest = [step for step in steps if "not written out here" in step["text"]]
        if res.family == "general-6r":
            assert len(rest) == 1 and "Manocha and Canny" in rest[0]["text"]
        for step in rest:
            for n in step["step"].split(", "):
                i = [j.name for j in robot.joints].index(n)
                shown = re.search(rf"{re.escape(n)} = (-?[0-9.e+-]+)", step["text"]).group(1)
                d = float(shown) - (np.degrees(s.q[i]) if robot.is_revolute[i] else s.q[i])
                if robot.is_revolute[i]:
                    d = (d + 180.0) % 360.0 - 180.0      # (shown within (-180, 180])
                assert abs(d) < 1e-3
    without = solve(robot, Target(T))
    assert all(s.trace is None for s in without.solutions)


def test_a_closing_turn_against_the_axis_is_worked_with_its_sense():
    """The last joint about parallel axes closes their turn psi (UR, offset-wrist, planar
    arms): ``q = s (psi - sum s_i q_i)``. A planar-4 arm whose joint 2 turns against the
    others: the step holds at every solution and the table writes the sense."""
    from kincalc.model import Joint, Robot
    P = np.pi
    r = Robot(name="p4", convention="dh", base=np.eye(4), tool=np.eye(4), joints=(
        Joint("a", "revolute", alpha=0.0, a=0.4, d=0.1, theta=0.0, limits=(-P, P)),
        Joint("b", "revolute", alpha=P, a=0.3, d=0.05, theta=0.0, limits=(-P, P)),
        Joint("c", "revolute", alpha=P / 2, a=0.1, d=0.0, theta=0.0, limits=(-P, P)),
        Joint("d", "revolute", alpha=0.0, a=0.0, d=0.2, theta=0.0, limits=(-P, P))))
    T = r.fk(np.array([0.3, -1.2, 0.8, 0.4]))
    res = solve(r, Target(T), explain=True)
    assert res.family == "planar-4" and res.solutions
    for s in res.solutions:
        (_, value, kind), = [n for n in s.trace if n[2].startswith("sum:")]
        assert kind == "sum:2:-:0:+:1:+"
        psi = value[0]
        assert abs(wrap(-(psi - (s.q[0] + s.q[1])) - s.q[2])) < 1e-9
        text = next(w["text"] for w in worked_steps(r, s, T, Units(), res.family)
                    if w["step"] == "c")
        assert text.startswith("c = -(ψ - (a + b)) = -(")


def test_a_ur_arms_joint_6_is_worked_and_said_free_at_the_wrist_singularity():
    """Joint 6 of a UR-type arm turns the parallel axes' direction seen from the tool onto
    it (a worked step, checked at every solution above); at q5 = 0 the two lie along axis 6
    and the step says joint 6 is free, with the representative shown."""
    r, T, res = _explained("ur5", [10, -50, 80, -30, 0, 20])
    free = [s for s in res.solutions if 5 in s.free]        # (the other shoulder's: q5 != 0)
    assert len(free) >= 2
    for s in free:
        text = next(w["text"] for w in worked_steps(r, s, T, Units(), res.family)
                    if w["step"] == "wrist_3")
        assert "wrist_3 is free (the wrist singularity)" in text
    r, T, res = _explained("ur5", [10, -50, 80, -30, 60, 20])
    for s in res.solutions:
        text = next(w["text"] for w in worked_steps(r, s, T, Units(), res.family)
                    if w["step"] == "wrist_3")
        assert text.startswith("wrist_3 = atan2(b2, b1) - atan2(a2, a1) = atan2(")
