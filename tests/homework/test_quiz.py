"""kincalc quiz: random exercise sheets whose answer keys are right.

Every answer is checked against its definition by means that do not share
code with the generator: the sheet is read back with PyYAML as a student's
tools would, the written (rounded) inputs are converted with unit factors of
this file, FK is compared to ``Robot.fk``/``link_transforms``, IK answers are
compared with a multi-start damped least-squares solver written here (every
answer reaches the pose, and it finds no solution the key lacks), the
Jacobian with a central finite difference of FK, singularity with the
singular values of that finite-difference Jacobian, reachability with the
same numerical solver, and the DH table by evaluating its cells here. Then
``kincalc check`` must grade the key 100 % and a blank sheet as failed.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import yaml

from kincalc.cli.main import main
from kincalc.conventions.library import load
from kincalc.homework.quiz import DEFAULT_KINDS, make_sheet, sheet_yaml

#: bundled robots the sheets are drawn for: 6R (DH, MDH, POE), a planar RR,
#: prismatic joints (SCARA with Euler wrist, RRP, Stanford arm)
ROBOTS = ["puma560", "puma560_mdh", "bk_rr", "bk_scara_euler", "ur5", "ur5_poe", "bk_rrp",
          "stanford_arm", "planar_3r"]
SEEDS = [1, 2]
ANGLE = {"deg": math.pi / 180, "rad": 1.0}
LENGTH = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "unitless": 1.0}


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def sheets():
    """{(robot, seed, angle unit): the --answers sheet as PyYAML reads it}."""
    out = {}
    for name in ROBOTS:
        robot = load(name)
        for seed in SEEDS:
            text = sheet_yaml(make_sheet(robot, seed, answers=True))
            out[name, seed, "robot"] = yaml.safe_load(text)
        text = sheet_yaml(make_sheet(robot, 9, answers=True,
                                     angle_unit="rad" if robot.angle_unit == "deg" else "deg"))
        out[name, 9, "other"] = yaml.safe_load(text)
    return out


def cases():
    return [(name, seed, unit) for name in ROBOTS for seed, unit in
            [(s, "robot") for s in SEEDS] + [(9, "other")]]


def items_of(sheet, kind):
    return [it for it in sheet["items"] if it["kind"] == kind]


# --- independent helpers -----------------------------------------------------------------

def factors(robot, sheet):
    """Per joint: SI per written unit, and (A, L) the angle and length factors."""
    A = ANGLE[sheet["units"]["angle"]]
    L = LENGTH[sheet["units"]["length"]]
    return np.where(robot.is_revolute, A, L), A, L


def q_si(robot, sheet, q):
    return np.asarray(q, float) * factors(robot, sheet)[0]


def pose_T(sheet, pose):
    """The written pose as a 4x4 (SI): R = Rz(Y) Ry(P) Rx(R), by hand."""
    A, L = ANGLE[sheet["units"]["angle"]], LENGTH[sheet["units"]["length"]]
    T = np.eye(4)
    T[:3, 3] = np.asarray(pose["xyz"], float) * L
    if "rpy" in pose:
        r, p, y = np.asarray(pose["rpy"], float) * A
        cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
        Rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
        Ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
        Rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
        T[:3, :3] = Rz @ Ry @ Rx
    return T


def rotvec(R):
    """Rotation vector of R (3, 3) or (N, 3, 3): axis * angle."""
    v = 0.5 * np.stack([R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0],
                        R[..., 1, 0] - R[..., 0, 1]], axis=-1)
    s = np.linalg.norm(v, axis=-1)
    c = 0.5 * (np.trace(R, axis1=-2, axis2=-1) - 1)
    angle = np.arctan2(s, c)
    scale = np.where(s > 1e-12, angle / np.maximum(s, 1e-300), 1.0)
    return v * scale[..., None]


def fd_jacobian(robot, q, h=1e-6):
    """Central finite difference of FK: rows vx vy vz (m/rad, m/m) wx wy wz."""
    n = robot.dof
    step = np.where(robot.is_revolute, h, h * robot.characteristic_length)
    Q = np.concatenate([q + np.diag(step), q - np.diag(step)])
    T = robot.fk(Q)
    J = np.zeros((6, n))
    for k in range(n):
        Tp, Tm = T[k], T[n + k]
        J[:3, k] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * step[k])
        J[3:, k] = rotvec(Tp[:3, :3] @ Tm[:3, :3].T) / (2 * step[k])
    return J


def scaled_singular_values(robot, J):
    L = robot.characteristic_length
    Jn = J.copy()
    Jn[:3] /= L
    Jn[:, ~robot.is_revolute] *= L
    return np.linalg.svd(Jn, compute_uv=False), np.linalg.svd(Jn[:3], compute_uv=False)


def generic_ranks(robot):
    """Ranks of the scaled FD Jacobian and of its linear rows at random joints."""
    rng = np.random.default_rng(0)
    lo, hi = np.clip(robot.limits, -3, 3).T
    best = (0, 0)
    for _ in range(5):
        s, sv = scaled_singular_values(robot, fd_jacobian(robot, rng.uniform(lo, hi)))
        best = (max(best[0], int(np.sum(s > 1e-5 * s[0]))),
                max(best[1], int(np.sum(sv > 1e-5 * sv[0]))))
    return best


def wrap(x):
    return (x + np.pi) % (2 * np.pi) - np.pi


def into_limits(robot, q):
    """Revolute joints wrapped into (-pi, pi] or shifted by 2 pi into the limits; None
    when a joint cannot be."""
    q = q.copy()
    lo, hi = robot.limits.T
    for i in range(robot.dof):
        if robot.is_revolute[i]:
            q[i] = wrap(q[i])
            for shift in (0, 2 * np.pi, -2 * np.pi):
                if lo[i] - 1e-9 <= q[i] + shift <= hi[i] + 1e-9:
                    q[i] += shift
                    break
        if not lo[i] - 1e-9 <= q[i] <= hi[i] + 1e-9:
            return None
    return q


def numeric_solutions(robot, T, orientation, starts=300, seed=0):
    """Every configuration within the limits reaching ``T`` that damped least squares
    finds from ``starts`` random starts (clustered modulo 2 pi)."""
    rng = np.random.default_rng(seed)
    lo, hi = robot.limits.T
    span = np.where(robot.is_revolute, np.pi, robot.characteristic_length)
    Q = rng.uniform(np.where(np.isfinite(lo), lo, -span), np.where(np.isfinite(hi), hi, span),
                    (starts, robot.dof))
    rows = slice(0, 6 if orientation else 3)
    L = robot.characteristic_length
    for _ in range(150):
        F = robot.fk(Q)
        e = np.zeros((starts, 6))
        e[:, :3] = (T[:3, 3] - F[:, :3, 3]) / L
        e[:, 3:] = rotvec(T[:3, :3] @ np.swapaxes(F[:, :3, :3], -1, -2))
        J = robot.jacobian(Q)
        J[:, :3] /= L
        J, e = J[:, rows], e[:, rows]
        lam = 1e-4
        JT = np.swapaxes(J, -1, -2)
        dq = np.linalg.solve(JT @ J + lam * np.eye(robot.dof), (JT @ e[..., None]))[..., 0]
        Q = Q + dq
    F = robot.fk(Q)
    err = np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=-1) / L
    if orientation:
        err = err + np.linalg.norm(rotvec(T[:3, :3] @ np.swapaxes(F[:, :3, :3], -1, -2)), axis=-1)
    found = []
    for q, e in zip(Q, err):
        if e > 1e-8:
            continue
        q = into_limits(robot, q)
        if q is None:
            continue
        if not any(np.max(np.abs(np.where(robot.is_revolute, wrap(q - f), (q - f) / L))) < 1e-5
                   for f in found):
            found.append(q)
    return found


def dh_from_table(robot, answer, sheet):
    """Joint -> transform functions from a compact DH table answer, evaluated here."""
    A, L = ANGLE[sheet["units"]["angle"]], LENGTH[sheet["units"]["length"]]
    cols = answer["columns"]
    rows = []
    for row in answer["table"]:
        cell = dict(zip(cols, row))
        params, var = {}, None
        for key, v in cell.items():
            unit = A if key in ("theta", "alpha") else L
            if isinstance(v, str):
                parts = v.split()
                off = 0.0 if len(parts) == 1 else float(parts[2]) * (1 if parts[1] == "+" else -1)
                params[key], var = off * unit, key
            else:
                params[key] = float(v) * unit
        rows.append((params, var))

    def rz(t):
        c, s = np.cos(t), np.sin(t)
        return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])

    def rx(t):
        c, s = np.cos(t), np.sin(t)
        return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])

    def tr(x, z):
        M = np.eye(4)
        M[0, 3], M[2, 3] = x, z
        return M

    def fk(q):
        T = np.eye(4)
        for (p, var), qi in zip(rows, q):
            th = p["theta"] + (qi if var == "theta" else 0.0)
            d = p["d"] + (qi if var == "d" else 0.0)
            if answer["convention"] == "dh":
                T = T @ rz(th) @ tr(0, d) @ tr(p["a"], 0) @ rx(p["alpha"])
            else:
                T = T @ rx(p["alpha"]) @ tr(p["a"], 0) @ rz(th) @ tr(0, d)
        return T
    return rows, fk


# --- the answers satisfy their definitions --------------------------------------------------

@pytest.mark.parametrize("name,seed,unit", cases())
def test_fk_answer_is_fk_at_the_written_joints(sheets, name, seed, unit):
    robot, sheet = load(name), sheets[name, seed, unit]
    _, _, L = factors(robot, sheet)
    for it in items_of(sheet, "fk"):
        T = np.array(it["answer"], float)
        T[:3, 3] *= L
        want = robot.fk(q_si(robot, sheet, it["q"]))
        assert np.allclose(T, want, atol=1e-9 * robot.characteristic_length + 1e-9), it["id"]


@pytest.mark.parametrize("name,seed,unit", cases())
def test_link_answer_is_the_link_transform(sheets, name, seed, unit):
    robot, sheet = load(name), sheets[name, seed, unit]
    per, _, L = factors(robot, sheet)
    rng = np.random.default_rng(3)
    for it in items_of(sheet, "link"):
        i = it["link"] - 1
        assert isinstance(it["q"], (int, float)), "a link item writes only q_i"
        q = rng.uniform(-1, 1, robot.dof)            # the other joints do not matter
        q[i] = it["q"] * per[i]
        T = np.array(it["answer"], float)
        T[:3, 3] *= L
        assert np.allclose(T, robot.link_transforms(q)[i], atol=1e-9), it["id"]


@pytest.mark.parametrize("name,seed,unit", cases())
def test_jacobian_answer_matches_finite_differences(sheets, name, seed, unit):
    robot, sheet = load(name), sheets[name, seed, unit]
    _, _, L = factors(robot, sheet)
    for it in items_of(sheet, "jacobian"):
        assert it.get("frame", "base") == "base"
        J = np.array(it["answer"], float)
        assert J.shape == (6, robot.dof)
        J[:3, robot.is_revolute] *= L               # length unit per rad -> m per rad
        fd = fd_jacobian(robot, q_si(robot, sheet, it["q"]))
        scale = max(1.0, robot.characteristic_length)
        assert np.allclose(J, fd, atol=1e-6 * scale), (it["id"], np.abs(J - fd).max())


@pytest.mark.parametrize("name,seed,unit", cases())
def test_singular_answer_agrees_with_the_smallest_singular_value(sheets, name, seed, unit):
    robot, sheet = load(name), sheets[name, seed, unit]
    full, full_pos = generic_ranks(robot)
    for it in items_of(sheet, "singular"):
        s, sv = scaled_singular_values(robot, fd_jacobian(robot, q_si(robot, sheet, it["q"])))
        smallest = min(s[full - 1] / max(s[0], 1.0), sv[full_pos - 1] / max(sv[0], 1.0))
        if it["answer"] is True:
            assert smallest < 1e-7, (it["id"], smallest)
        else:
            assert it["answer"] is False and smallest > 1e-3, (it["id"], smallest)


@pytest.mark.parametrize("name,seed,unit", cases())
def test_ik_answers_reach_the_written_pose_and_are_all_there_is(sheets, name, seed, unit):
    robot, sheet = load(name), sheets[name, seed, unit]
    L = robot.characteristic_length
    for it in items_of(sheet, "ik"):
        T = pose_T(sheet, it["pose"])
        orient = "rpy" in it["pose"]
        answers = [q_si(robot, sheet, q) for q in it["answer"]]
        assert answers, "an ik item of a quiz has a reachable pose"
        for q in answers:
            F = robot.fk(q)
            assert np.linalg.norm(F[:3, 3] - T[:3, 3]) < 1e-7 * L, (it["id"], q)
            if orient:
                assert np.linalg.norm(rotvec(F[:3, :3] @ T[:3, :3].T)) < 1e-7, (it["id"], q)
            assert into_limits(robot, q) is not None, "answers are within the joint limits"
        found = numeric_solutions(robot, T, orient)
        for f in found:
            assert any(np.max(np.abs(np.where(robot.is_revolute, wrap(f - a), (f - a) / L)))
                       < 1e-4 for a in answers), f"key misses the solution {f} ({it['id']})"
        assert len(found) == len(answers), (it["id"], len(found), len(answers))


@pytest.mark.parametrize("name,seed,unit", cases())
def test_reach_answer_agrees_with_a_numerical_search(sheets, name, seed, unit):
    robot, sheet = load(name), sheets[name, seed, unit]
    for it in items_of(sheet, "reach"):
        found = numeric_solutions(robot, pose_T(sheet, it["pose"]), "rpy" in it["pose"],
                                  starts=200)
        assert (it["answer"] is True) == bool(found), (it["id"], it["answer"], len(found))


@pytest.mark.parametrize("name,seed,unit", cases())
def test_dh_answer_is_the_robots_table(sheets, name, seed, unit):
    robot, sheet = load(name), sheets[name, seed, unit]
    items = items_of(sheet, "dh")
    if robot.convention == "poe":
        assert not items
        return
    (it,) = items
    assert it["answer"]["convention"] == robot.convention
    _, fk = dh_from_table(robot, it["answer"], sheet)
    # the table is frame 0 -> frame n; a base or tool the robot has is left out of it
    assert it.get("tool") == (None if np.allclose(robot.tool, np.eye(4)) else "ignore")
    assert it.get("base") == (None if np.allclose(robot.base, np.eye(4)) else "ignore")
    rng = np.random.default_rng(5)
    for _ in range(5):
        q = rng.uniform(-2, 2, robot.dof)
        want = np.linalg.inv(robot.base) @ robot.fk(q) @ np.linalg.inv(robot.tool)
        assert np.allclose(fk(q), want, atol=1e-9)


def test_checks_here_can_fail(sheets):
    """The helpers above reject a wrong key (a slipped entry, a lost IK solution)."""
    robot, sheet = load("puma560"), sheets["puma560", 1, "robot"]
    (fk,) = items_of(sheet, "fk")
    T = np.array(fk["answer"], float)
    T[0, 3] += 1e-3
    assert not np.allclose(T, robot.fk(q_si(robot, sheet, fk["q"])), atol=1e-9)
    (jac,) = items_of(sheet, "jacobian")
    fd = fd_jacobian(robot, q_si(robot, sheet, jac["q"]) + np.r_[0, 0, 0.01, 0, 0, 0])
    assert not np.allclose(np.array(jac["answer"]), fd, atol=1e-6)
    (ik,) = items_of(sheet, "ik")
    found = numeric_solutions(robot, pose_T(sheet, ik["pose"]), True)
    assert len(found) == len(ik["answer"]) > 1
    s, _ = scaled_singular_values(robot, fd_jacobian(robot, np.r_[0.1, 0.2, 0.3, 0.4, 0.0, 0.6]))
    assert s[-1] < 1e-7, "the wrist-aligned PUMA is singular by this test's measure"


def test_sheet_layout_and_units(sheets):
    sheet = sheets["puma560", 1, "robot"]
    assert sheet["kincalc-sheet"] == 1 and sheet["robot"] == "puma560" and sheet["seed"] == 1
    assert sheet["units"] == {"angle": "deg", "length": "m"}
    assert [it["kind"] for it in sheet["items"]] == list(DEFAULT_KINDS)
    assert [it["id"] for it in sheet["items"]] == [str(k) for k in range(1, 8)]
    for it in sheet["items"]:
        assert "Answer" in it["question"], it["question"]
    fk = items_of(sheet, "fk")[0]
    assert all(isinstance(v, int) for v in fk["q"]), "whole degrees a student can type"
    rad = sheets["puma560", 9, "other"]
    assert rad["units"] == {"angle": "rad", "length": "m"}
    q = items_of(rad, "fk")[0]["q"]
    assert all(round(v, 2) == v and abs(v) <= math.pi for v in q)
    scara = sheets["bk_scara_euler", 1, "robot"]
    d3 = items_of(scara, "fk")[0]["q"][2]
    assert 0 <= d3 <= 30 and round(d3, 3) == d3, "prismatic: three decimals within limits"


def test_yaml_text_reads_back_as_the_dict():
    robot = load("bk_scara_euler")
    sheet = make_sheet(robot, 4, answers=True)
    text = sheet_yaml(sheet, ["a comment"])
    assert text.startswith("# a comment\n")
    assert yaml.safe_load(text) == sheet
    assert "answer: yes" in text or "answer: no" in text


def test_singular_items_find_singularities():
    """Across seeds, both answers occur, and singular ones sit on a whole degree when
    the singularity does (the PUMA's wrist at q5 = 0)."""
    robot = load("puma560")
    answers = [make_sheet(robot, s, ["singular"], answers=True)["items"][0] for s in range(12)]
    assert {it["answer"] for it in answers} == {True, False}
    robot7 = load("iiwa7")
    sheet = make_sheet(robot7, 3, ["singular", "singular"], answers=True)
    full, full_pos = generic_ranks(robot7)
    for it in sheet["items"]:
        s, sv = scaled_singular_values(robot7, fd_jacobian(robot7, q_si(robot7, sheet, it["q"])))
        smallest = min(s[full - 1] / max(s[0], 1.0), sv[full_pos - 1] / max(sv[0], 1.0))
        assert (smallest < 1e-7) == it["answer"]


# --- the command ---------------------------------------------------------------------------

def test_same_seed_same_bytes_other_seed_other_sheet(capsys):
    code, a, _ = run(capsys, "quiz", "puma560", "--seed", 7, "--answers")
    assert code == 0
    code, b, _ = run(capsys, "quiz", "puma560", "--seed", 7, "--answers")
    assert a == b
    code, c, _ = run(capsys, "quiz", "puma560", "--seed", 8, "--answers")
    assert code == 0 and c != a
    assert a.startswith("# Generated by kincalc ") and "--seed 7" in a.splitlines()[0]


def test_items_option_and_independent_draws(capsys):
    code, out, _ = run(capsys, "quiz", "ur5", "--seed", 3, "--items", "fk,fk,reach", "--answers")
    assert code == 0
    sheet = yaml.safe_load(out)
    assert [it["kind"] for it in sheet["items"]] == ["fk", "fk", "reach"]
    assert sheet["items"][0]["q"] != sheet["items"][1]["q"]
    full = yaml.safe_load(run(capsys, "quiz", "ur5", "--seed", 3, "--answers")[1])
    assert items_of(full, "fk")[0]["q"] == sheet["items"][0]["q"], \
        "a kind's draws do not depend on the other kinds asked for"


def test_blank_sheet_is_the_key_without_answers(capsys):
    key = yaml.safe_load(run(capsys, "quiz", "bk_rr", "--seed", 5, "--answers")[1])
    code, out, _ = run(capsys, "quiz", "bk_rr", "--seed", 5)
    blank = yaml.safe_load(out)
    assert code == 0 and all("answer" not in it for it in blank["items"])
    for it in key["items"]:
        it.pop("answer")
    assert blank["items"] == key["items"]


def test_default_items_are_the_cores():
    import inspect

    from kincalc.cli.quiz import ItemsOpt, quiz
    # no --items means the default kinds, drawn leniently (see
    # test_default_items_leave_out_a_kind_that_cannot_be_drawn)
    assert inspect.signature(quiz).parameters["items"].default is None
    assert ",".join(DEFAULT_KINDS) in ItemsOpt.__metadata__[0].help


def test_rad_option_and_default_unit(capsys):
    sheet = yaml.safe_load(run(capsys, "quiz", "puma560", "--seed", 1, "--rad")[1])
    assert sheet["units"]["angle"] == "rad"
    sheet = yaml.safe_load(run(capsys, "quiz", "panda", "--seed", 1, "--items", "fk")[1])
    assert sheet["units"] == {"angle": load("panda").angle_unit, "length": "m"}


def test_output_file_refuses_to_overwrite(capsys, tmp_path):
    path = tmp_path / "hw.yaml"
    code, out, err = run(capsys, "quiz", "bk_rr", "--seed", 2, "-o", path)
    assert code == 0 and out == "" and "wrote" in err
    text = path.read_text()
    assert text == run(capsys, "quiz", "bk_rr", "--seed", 2)[1]
    code, _, err = run(capsys, "quiz", "bk_rr", "--seed", 3, "--output", path)
    assert code == 2 and "--force" in err and path.read_text() == text
    code, _, _ = run(capsys, "quiz", "bk_rr", "--seed", 3, "-o", path, "--force")
    assert code == 0 and path.read_text() != text


def test_robot_file_path_is_relative_to_the_sheet(capsys, tmp_path):
    src = load("bk_rr").path
    robots = tmp_path / "robots"
    robots.mkdir()
    (robots / "arm.yaml").write_text(open(src, encoding="utf-8").read())
    (tmp_path / "sheets").mkdir()
    out = tmp_path / "sheets" / "hw.yaml"
    code, _, _ = run(capsys, "quiz", robots / "arm.yaml", "--seed", 1, "-o", out)
    assert code == 0 and yaml.safe_load(out.read_text())["robot"] == "../robots/arm.yaml"


def test_poe_robot_has_no_dh_item(capsys):
    code, out, err = run(capsys, "quiz", "ur5_poe", "--seed", 1)
    assert code == 0 and "dh left out" in err and "# dh left out" in out
    assert "dh" not in [it["kind"] for it in yaml.safe_load(out)["items"]]
    code, _, err = run(capsys, "quiz", "ur5_poe", "--seed", 1, "--items", "dh")
    assert code == 2 and "none of the exercises" in err


@pytest.mark.parametrize("argv,message", [
    (["--items", "fk,fx"], "unknown exercise kind 'fx'"),
    (["--items", ","], "at least one kind"),
    (["--seed", "-1"], "--seed"),
    # a sheet of 201 items was written, which check then refused ("at most 200")
    (["--items", ",".join(["fk"] * 201)], "a sheet holds at most 200 items"),
])
def test_bad_options_exit_2(capsys, argv, message):
    code, out, err = run(capsys, "quiz", "puma560", *argv)
    assert code == 2 and out == "" and message in err and err.count("\n") == 1


# --- kincalc check grades the key ------------------------------------------------------------

@pytest.mark.parametrize("name", ["puma560", "bk_rr", "bk_scara_euler", "ur5", "bk_rrp",
                                  "ur5_poe"])
def test_check_grades_the_key_full_and_the_blank_sheet_failed(capsys, tmp_path, name):
    key, blank = tmp_path / "key.yaml", tmp_path / "blank.yaml"
    assert run(capsys, "quiz", name, "--seed", 11, "--answers", "-o", key)[0] == 0
    assert run(capsys, "quiz", name, "--seed", 11, "-o", blank)[0] == 0
    code, out, err = run(capsys, "check", key, "--json")
    doc = json.loads(out)
    wrong = [(i["id"], i["kind"], i.get("message")) for i in doc["items"] if not i["passed"]]
    assert code == 0 and not wrong, (err, wrong)
    assert doc["score"]["percent"] == 100
    code, out, _ = run(capsys, "check", blank, "--json")
    doc = json.loads(out)
    assert code == 1 and not any(i["passed"] for i in doc["items"])


def test_output_dash_is_standard_output_and_a_folder_is_refused(tmp_path, monkeypatch, capsys):
    # found in review: '-o -' wrote a file named '-'; '-o FOLDER' asked for --force
    from kincalc.cli.main import main
    monkeypatch.chdir(tmp_path)
    assert main(["quiz", "bk_rr", "--seed", "1", "-o", "-"]) == 0
    assert capsys.readouterr().out.startswith("# Generated by kincalc")
    assert not (tmp_path / "-").exists()
    assert main(["quiz", "bk_rr", "--seed", "1", "-o", str(tmp_path)]) == 2
    assert "is a folder" in capsys.readouterr().err


# a product-of-exponentials robot whose two revolute joints share one axis: redundant (one
# independent motion for two joints), so no 'ik' exercise asking for every solution
COAXIAL_POE = """\
name: coaxial
convention: poe
units: {length: cm, angle: rad}
joints:
  - {name: j1, type: revolute, axis: [0, 0, 1], point: [0, 0, 21.4082], limits: [-1.086316, 1.533684]}
  - {name: j2, type: revolute, axis: [0, 0, 1], point: [0, 0, 12.702]}
tool: {xyz: [-24.9758, 29.8658, 19.9408], rpy: [-2.910514, 0.424365, 0.687004]}
base: {xyz: [-19.255, -20.1047, -2.2825], rpy: [0.420996, -0.302163, 2.637528]}
"""


def test_default_items_leave_out_a_kind_that_cannot_be_drawn(tmp_path, capsys):
    (tmp_path / "coaxial.yaml").write_text(COAXIAL_POE, encoding="utf-8")
    key = tmp_path / "key.yaml"
    code, _, err = run(capsys, "quiz", tmp_path / "coaxial.yaml", "--seed", 17, "--answers",
                       "-o", key)
    assert code == 0, err
    assert "note: ik left out: kincalc has no closed-form IK for coaxial (redundant: " in err
    text = key.read_text()
    assert "# ik left out: kincalc has no closed-form IK" in text
    assert "--items" not in text.splitlines()[0]
    items = yaml.safe_load(text)["items"]
    assert [it["kind"] for it in items] == ["link", "fk", "jacobian", "singular", "reach"]
    assert [it["id"] for it in items] == ["1", "2", "3", "4", "5"]
    code, out, _ = run(capsys, "check", key, "-q")
    assert code == 0 and "(100 %)" in out
    # the others are the draws they are with --items naming them (own random streams)
    code, out, _ = run(capsys, "quiz", tmp_path / "coaxial.yaml", "--seed", 17, "--answers",
                       "--items", "link,fk,jacobian,singular,reach")
    assert code == 0 and yaml.safe_load(out)["items"] == items
    # asked for by name, a kind that does not apply is left out with its note too (as ik of
    # a seven-joint arm is)
    code, out, err = run(capsys, "quiz", tmp_path / "coaxial.yaml", "--seed", 17, "--items",
                         "link,ik")
    assert code == 0 and "ik left out: kincalc has no closed-form IK" in err
    assert [it["kind"] for it in yaml.safe_load(out)["items"]] == ["link"]


def test_a_kind_that_could_not_be_drawn_is_left_out_or_an_error(monkeypatch, capsys):
    """An exercise the draw fails to find (no fair 'ik' pose in ATTEMPTS tries, here none
    tried): with the default --items the kind is left out with a note and the sheet made;
    named by --items it is an error naming --items."""
    from kincalc.homework.quiz import poses
    monkeypatch.setattr(poses, "ATTEMPTS", 0)
    code, out, err = run(capsys, "quiz", "bk_rr", "--seed", 17)
    assert code == 0 and "note: ik left out: could not draw an 'ik' exercise" in err
    assert "ik" not in [it["kind"] for it in yaml.safe_load(out)["items"]]
    code, _, err = run(capsys, "quiz", "bk_rr", "--seed", 17, "--items", "link,ik")
    assert code == 2 and "could not draw an 'ik' exercise" in err and "--items" in err


def test_a_reach_exercise_of_a_numerically_solved_robot_draws_a_few_times(monkeypatch):
    """Each draw of a 'reach' exercise is a reach analysis, numerical where no closed form
    solves the robot (up to a second on a long chain: a fuzzed 12-joint arm's quiz took a
    minute in 120 draws). Such a robot gets NUMERIC_ATTEMPTS draws of each answer, a
    closed-form one ATTEMPTS; then the kind cannot be drawn."""
    from kincalc.analysis import reach as reach_module
    from kincalc.analysis.results import Units
    from kincalc.homework.quiz import poses
    from kincalc.homework.quiz.rules import ATTEMPTS, NUMERIC_ATTEMPTS, QuizError
    calls = []

    def never_fair(robot, target, **kw):         # a verdict no draw can use
        calls.append(robot.name)

        class Verdict:
            verdict, reachable, distance = "not-found", False, 0.0
        return Verdict()
    monkeypatch.setattr(reach_module, "reach", never_fair)
    for name, attempts in (("iiwa14", NUMERIC_ATTEMPTS), ("puma560", ATTEMPTS)):
        calls.clear()
        with pytest.raises(QuizError, match=f"in {2 * attempts} tries"):
            poses.item_reach(load(name), np.random.default_rng(3), Units())
        assert attempts <= len(calls) <= 3 * 2 * attempts        # (up to 3 forms a draw)
    assert NUMERIC_ATTEMPTS < ATTEMPTS / 10


def test_a_singular_search_zooms_only_into_minima_that_may_vanish():
    """The sweep of a joint zooms into a sampled minimum of sigma only where it may be a
    zero between samples (a cone: at most a quarter of its neighbours' sum), not into a
    smooth minimum above 0 (about half of it). A 12-joint arm, whose singular set a single
    joint seldom meets, zoomed into 636 minima of one quiz and found none (6 s)."""
    from kincalc.homework.quiz.singular import _may_vanish
    rng = np.random.default_rng(11)
    h = 0.0082                                         # the sweep's step (rad)
    x = np.arange(-3, 4) * h
    for _ in range(500):
        c, off = rng.uniform(0.05, 50.0), rng.uniform(-h / 2, h / 2)
        cone = c * np.abs(x - off)                     # sampled; the minimum at sample 3
        assert _may_vanish(cone, int(np.argmin(cone)))
        m, a = rng.uniform(2e-3, 1.0), rng.uniform(0.0, 20.0)
        smooth = m + a * (x - off) ** 2                # a minimum of m > 0
        assert not _may_vanish(smooth, int(np.argmin(smooth)))


def test_a_long_redundant_arms_sweeps_zoom_into_few_minima(monkeypatch):
    """The sweeps of a 12-joint arm's joints (whose singular set a single joint seldom
    meets) zoom into few of their sampled minima; what the search finds is singular."""
    from kincalc.analysis.results import Units
    from kincalc.homework.quiz import singular
    from kincalc.model import Joint, Robot
    from kincalc.tolerances import SINGULAR_TOL
    rng = np.random.default_rng(0)
    robot = Robot(name="arm12", convention="dh", joints=tuple(
        Joint(f"q{i + 1}", "revolute", alpha=float(rng.choice([0.0, np.pi / 2, -np.pi / 2])),
              a=float(rng.uniform(0, 0.3)), d=float(rng.uniform(0, 0.3)), theta=0.0,
              limits=(-3.0, 3.0)) for i in range(12)), base=np.eye(4), tool=np.eye(4))
    zooms = []
    real_zoom = singular._zoom
    monkeypatch.setattr(singular, "_zoom", lambda *a: zooms.append(a) or real_zoom(*a))
    for s in range(4):
        found = singular.singular_configuration(robot, list(rng.uniform(-2.5, 2.5, 12)),
                                                np.random.default_rng(s), Units(angle="rad"))
        assert found is None or float(singular.scaled_sigma(robot, found[1])) < SINGULAR_TOL
    assert len(zooms) < 4 * 3          # before: about 30 a search (3 a joint, 12 joints)
