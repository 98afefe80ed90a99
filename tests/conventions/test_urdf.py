"""URDF files: the kinematic subset, chains through a tree, and hostile XML.

FK of a URDF robot is checked against the URDF's own semantics written out here (each
joint the child frame ``origin`` in the parent frame, then a rotation about or a
translation along ``axis`` in that frame), independent of kincalc's poe chain.
"""

import math

import numpy as np
import pytest

from kincalc.conventions.urdf import parse_urdf_text
from kincalc.errors import RobotFileError
from kincalc.spatial import matrix_from_rpy

TYPES = ["revolute", "continuous", "prismatic", "fixed"]


def _rodrigues(axis, angle):
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def random_urdf(rng, n_moving=6, n_fixed=3):
    """URDF text of a random serial chain (random origins, axes, joint types, fixed
    joints anywhere), returns ``(text, joints)`` with the chain's joints as dicts for the
    reference FK."""
    kinds = ["fixed"] * n_fixed + [str(rng.choice(TYPES[:3])) for _ in range(n_moving)]
    rng.shuffle(kinds)
    links, joints = ["base"], []
    for k, kind in enumerate(kinds):
        axis = rng.normal(size=3)
        j = {"name": f"j{k}", "type": kind, "parent": links[-1], "child": f"link{k}",
             "xyz": rng.uniform(-0.5, 0.5, 3), "rpy": rng.uniform(-math.pi, math.pi, 3),
             "axis": axis, "limits": (-2.5, 2.5) if kind == "revolute" else (-0.3, 0.4)}
        links.append(j["child"])
        joints.append(j)
    parts = ['<?xml version="1.0"?>', '<robot name="random_arm">']
    parts += [f'  <link name="{name}"><visual><geometry><mesh filename="package://x/{name}.stl"/>'
              '</geometry></visual><inertial><mass value="1"/></inertial></link>'
              for name in links]
    for j in joints:
        xyz = " ".join(repr(float(v)) for v in j["xyz"])
        rpy = " ".join(repr(float(v)) for v in j["rpy"])
        axis = " ".join(repr(float(v)) for v in j["axis"])
        limit = (f'<limit lower="{j["limits"][0]}" upper="{j["limits"][1]}" effort="1" '
                 'velocity="1"/>' if j["type"] in ("revolute", "prismatic") else "")
        parts.append(f'  <joint name="{j["name"]}" type="{j["type"]}">'
                     f'<parent link="{j["parent"]}"/><child link="{j["child"]}"/>'
                     f'<origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>{limit}</joint>')
    parts.append("</robot>")
    return "\n".join(parts), joints


def reference_fk(joints, q):
    """The tip link's pose in the base link for joint values ``q`` (moving joints in
    order), from the URDF's definitions."""
    T, k = np.eye(4), 0
    for j in joints:
        O = np.eye(4)
        O[:3, :3] = matrix_from_rpy(j["rpy"])
        O[:3, 3] = j["xyz"]
        T = T @ O
        if j["type"] == "fixed":
            continue
        axis = j["axis"] / np.linalg.norm(j["axis"])
        J = np.eye(4)
        if j["type"] == "prismatic":
            J[:3, 3] = axis * q[k]
        else:
            J[:3, :3] = _rodrigues(axis, q[k])
        T = T @ J
        k += 1
    return T


def test_fk_of_random_urdfs_is_the_urdfs_own():
    rng = np.random.default_rng(2026)
    for trial in range(60):
        text, joints = random_urdf(rng, n_moving=int(rng.integers(1, 8)),
                                   n_fixed=int(rng.integers(0, 4)))
        robot = parse_urdf_text(text, "random.urdf")
        moving = [j for j in joints if j["type"] != "fixed"]
        assert [j.name for j in robot.joints] == [j["name"] for j in moving]
        assert robot.convention == "poe"
        for qq in rng.uniform(-2.5, 2.5, (20, robot.dof)):
            assert np.allclose(robot.fk(qq), reference_fk(joints, qq), atol=1e-12)
        for j, jr in zip(moving, robot.joints):
            want = None if j["type"] == "continuous" else j["limits"]
            assert jr.limits == want
            assert jr.type == ("prismatic" if j["type"] == "prismatic" else "revolute")


def _hang(text, parent, name, x):
    """``text`` with a fixed leaf ``name`` hung on link ``parent`` at ``x`` along x."""
    return text.replace("</robot>", f'<link name="{name}"/><joint name="{name}_joint" '
                        f'type="fixed"><parent link="{parent}"/><child link="{name}"/>'
                        f'<origin xyz="{x} 0 0"/></joint></robot>')


def test_fixed_leaves_do_not_hide_the_tip():
    """Fixed frames hung off an early link are ignored; after the last moving joint one
    fixed leaf is the tip, and two of them leave the tip at the last moving link."""
    rng = np.random.default_rng(7)
    text, joints = random_urdf(rng, n_moving=5, n_fixed=0)
    q = rng.uniform(-2, 2, 5)
    last = joints[-1]["child"]
    off = np.eye(4)
    off[0, 3] = 0.25
    early = _hang(text, joints[1]["child"], "camera", 0.5)
    assert np.allclose(parse_urdf_text(early, "r.urdf").fk(q), reference_fk(joints, q),
                       atol=1e-12)
    one = _hang(early, last, "tool0", 0.25)
    assert np.allclose(parse_urdf_text(one, "r.urdf").fk(q), reference_fk(joints, q) @ off,
                       atol=1e-12)
    two = _hang(one, last, "ft_frame", 0.75)
    assert np.allclose(parse_urdf_text(two, "r.urdf").fk(q), reference_fk(joints, q),
                       atol=1e-12)
    chosen = parse_urdf_text(two, "r.urdf", tip_link="tool0")
    assert np.allclose(chosen.fk(q), reference_fk(joints, q) @ off, atol=1e-12)


def test_the_ik_of_a_urdf_arm_is_the_bundled_arms():
    """UR5 written as URDF joints (UR's URDF layout) and the bundled ur5 (UR's DH table):
    the same robot up to base and tool frames, so every pose has the same solutions."""
    import kincalc
    from kincalc.analysis.compare import match
    robot = parse_urdf_text(UR5, "ur5.urdf")
    ur5 = kincalc.load_robot("ur5")
    m = match(ur5, robot, allow_offsets=True, free_base=True, free_tool=True)
    assert m.same
    rng = np.random.default_rng(11)
    for q in rng.uniform(-3, 3, (30, 6)):
        T = robot.fk(q)
        mine = robot.ik(T).solutions
        assert any(np.allclose(np.angle(np.exp(1j * (s.q - q))), 0, atol=1e-7) for s in mine)
        theirs = ur5.ik(np.linalg.inv(m.base) @ T @ np.linalg.inv(m.tool)).solutions
        assert len(mine) == len(theirs)
        for s in theirs:
            mapped = s.q * m.signs + m.offsets
            assert any(np.allclose(np.angle(np.exp(1j * (t.q - mapped))), 0, atol=1e-7)
                       for t in mine)


UR5 = """<?xml version="1.0"?>
<robot name="ur5_test">
  <link name="base_link"/><link name="shoulder_link"/><link name="upper_arm_link"/>
  <link name="forearm_link"/><link name="wrist_1_link"/><link name="wrist_2_link"/>
  <link name="wrist_3_link"/><link name="tool0"/><link name="base"/>
  <joint name="base_fixed" type="fixed"><parent link="base_link"/><child link="base"/>
    <origin rpy="0 0 3.141592653589793"/></joint>
  <joint name="shoulder_pan_joint" type="revolute"><parent link="base_link"/>
    <child link="shoulder_link"/><origin xyz="0 0 0.089159"/><axis xyz="0 0 1"/>
    <limit lower="-6.28" upper="6.28"/></joint>
  <joint name="shoulder_lift_joint" type="revolute"><parent link="shoulder_link"/>
    <child link="upper_arm_link"/><origin xyz="0 0.13585 0" rpy="0 1.5707963267948966 0"/>
    <axis xyz="0 1 0"/><limit lower="-6.28" upper="6.28"/></joint>
  <joint name="elbow_joint" type="revolute"><parent link="upper_arm_link"/>
    <child link="forearm_link"/><origin xyz="0 -0.1197 0.425"/><axis xyz="0 1 0"/>
    <limit lower="-6.28" upper="6.28"/></joint>
  <joint name="wrist_1_joint" type="revolute"><parent link="forearm_link"/>
    <child link="wrist_1_link"/><origin xyz="0 0 0.39225" rpy="0 1.5707963267948966 0"/>
    <axis xyz="0 1 0"/><limit lower="-6.28" upper="6.28"/></joint>
  <joint name="wrist_2_joint" type="revolute"><parent link="wrist_1_link"/>
    <child link="wrist_2_link"/><origin xyz="0 0.093 0"/><axis xyz="0 0 1"/>
    <limit lower="-6.28" upper="6.28"/></joint>
  <joint name="wrist_3_joint" type="continuous"><parent link="wrist_2_link"/>
    <child link="wrist_3_link"/><origin xyz="0 0 0.09465"/><axis xyz="0 1 0"/></joint>
  <joint name="tool0_fixed" type="fixed"><parent link="wrist_3_link"/><child link="tool0"/>
    <origin xyz="0 0.0823 0" rpy="-1.5707963267948966 0 0"/></joint>
</robot>
"""


def _chain_text(extra="", joint_type="revolute", inner=""):
    return (f'<robot name="t"><link name="a"/><link name="b"/><link name="c"/>{extra}'
            f'<joint name="ja" type="{joint_type}"><parent link="a"/><child link="b"/>'
            f'<axis xyz="0 0 1"/><limit lower="-1" upper="1"/>{inner}</joint>'
            '<joint name="jb" type="revolute"><parent link="b"/><child link="c"/>'
            '<origin xyz="1 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1"/></joint>'
            '</robot>')


def _fingers():
    return _chain_text(
        extra='<link name="left"/><link name="right"/>'
              '<joint name="fl" type="prismatic"><parent link="c"/><child link="left"/>'
              '<limit lower="0" upper="0.04"/></joint>'
              '<joint name="fr" type="prismatic"><parent link="c"/><child link="right"/>'
              '<limit lower="0" upper="0.04"/><mimic joint="fl"/></joint>')


def test_a_branching_tree_names_its_leaves_and_a_tip_link_chooses():
    with pytest.raises(RobotFileError) as e:
        parse_urdf_text(_fingers(), "hand.urdf")
    msg = str(e.value)
    assert msg.startswith("hand.urdf:1: the tree branches below link 'c'")
    assert "--tip-link" in msg and "'left'" in msg and "'right'" in msg
    arm = parse_urdf_text(_fingers(), "hand.urdf", tip_link="c")
    assert [j.name for j in arm.joints] == ["ja", "jb"]
    left = parse_urdf_text(_fingers(), "hand.urdf", tip_link="left")
    assert [j.type for j in left.joints] == ["revolute", "revolute", "prismatic"]
    with pytest.raises(RobotFileError, match="'fr' is a <mimic> joint"):
        parse_urdf_text(_fingers(), "hand.urdf", tip_link="right")
    assert np.allclose(arm.fk([0.3, 0.5])[:3, 3], [math.cos(0.3), math.sin(0.3), 0])
    sub = parse_urdf_text(_fingers(), "hand.urdf", base_link="b", tip_link="c")
    assert [j.name for j in sub.joints] == ["jb"]
    T = sub.fk([0.3])             # c turns about its own origin, 1 along x of b
    assert np.allclose(T[:3, 3], [1, 0, 0]) and np.isclose(T[1, 0], math.sin(0.3))


@pytest.mark.parametrize("kwargs,words", [
    ({"tip_link": "nope"}, "--tip-link 'nope' is not a link of this URDF"),
    ({"base_link": "c", "tip_link": "a"}, "link 'a' is not below link 'c'"),
])
def test_a_chain_that_cannot_be_chosen_is_one_line(kwargs, words):
    with pytest.raises(RobotFileError, match=words):
        parse_urdf_text(_fingers(), "hand.urdf", **kwargs)


@pytest.mark.parametrize("text,words", [
    # entity expansion and external entities never happen: a DOCTYPE is refused
    ('<?xml version="1.0"?>\n<!DOCTYPE lolz [<!ENTITY lol "lol"><!ENTITY lol2 '
     '"&lol;&lol;&lol;&lol;">]>\n<robot name="x">&lol2;</robot>', ":2: a DOCTYPE is not accepted"),
    ('<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
     '<robot>&x;</robot>', "a DOCTYPE is not accepted"),
    ('<robot name="x">\n<link name="a">\n</robot>', ":3: not well-formed XML: mismatched tag"),
    ("", "not well-formed XML: no element found"),
    ('<sdf version="1.6"/>', "the root element is <sdf>, not <robot>: not a URDF"),
    ('<robot name="x"/>', "the URDF has no <link>"),
    (_chain_text(joint_type="floating"), "joint 'ja': a floating joint (6 DOF) is not a "
                                         "serial joint"),
    (_chain_text(joint_type="planar"), "a planar joint (3 DOF)"),
    (_chain_text(joint_type="ball"), "type 'ball' is not a URDF joint type"),
    (_chain_text(inner='<mimic joint="jb"/>'), "'ja' is a <mimic> joint"),
    # a joint's name heads a table's column: a newline split the table's lines
    (_chain_text().replace('name="ja"', 'name="el&#10;bow"', 1),
     "joint 'el\\nbow': its name must not hold a control character"),
    # a link's name too (fuzz campaign: a CR and an empty name were taken)
    (_chain_text().replace('"b"', '"b&#13;c"'),
     "link 'b\\rc': its name must not hold a control character"),
    (_chain_text().replace('"b"', '""'), "<link name> is empty: a link has a name"),
    (_chain_text().replace('name="ja"', 'name="' + "j" * 65 + '"', 1),
     "its name is 65 characters long; kincalc takes names of up to 64"),
    (_chain_text().replace('<limit lower="-1" upper="1"/>', "", 1),
     "a revolute joint needs <limit lower upper> (a revolute joint without limits is "
     "'continuous')"),

    # URDF's default of a missing bound, 0, held the joint still: limits [0, 0]
    (_chain_text().replace('<limit lower="-1" upper="1"/>', '<limit effort="1"/>', 1),
     "joint 'ja': <limit> has no lower or upper: a revolute joint needs both"),
    (_chain_text().replace('lower="-1" upper="1"', 'upper="1"', 1), "<limit> has no lower:"),
    (_chain_text().replace('lower="-1" upper="1"', 'lower="1" upper="-1"', 1),
     "lower 1 is above upper -1"),
    (_chain_text().replace('<axis xyz="0 0 1"/>', '<axis xyz="0 0 0"/>', 1),
     "<axis xyz> is the zero vector"),
    (_chain_text().replace('xyz="1 0 0"', 'xyz="${a2} 0 0"'),
     "<origin xyz> '${a2} 0 0' is not 3 numbers (an unexpanded xacro expression?"),
    (_chain_text().replace('xyz="1 0 0"', 'xyz="1 0"'), "<origin xyz> needs 3 numbers, got 2"),
    (_chain_text().replace('upper="1"', 'upper=""', 1),     # (it said "got 0", a value)
     "<limit upper> needs a number, got an empty value"),
    (_chain_text().replace('xyz="1 0 0"', 'xyz="1 nan 0"'), "not finite"),
    (_chain_text().replace('<child link="b"/>', '<child link="z"/>'),
     "joint 'ja' names link 'z', which is not defined"),
    (_chain_text().replace('<parent link="a"/>', ""), "joint 'ja' has no <parent>"),
    (_chain_text().replace('<link name="b"/>', '<link name="b"/><link name="b"/>'),
     "link 'b' is defined twice"),
    (_chain_text().replace('<parent link="b"/><child link="c"/>',
                           '<parent link="b"/><child link="b"/>'),
     "link 'b' is the child of two joints"),
    (_chain_text().replace('<parent link="a"/><child link="b"/>',
                           '<parent link="c"/><child link="b"/>'),
     "the joints form a loop: links 'b', 'c' are not below the root link 'a'"),
    (_chain_text(extra='<link name="d"/>'), "not one tree: 2 links have no parent"),
    ('<robot name="x"><link name="a"/><link name="b"/><joint name="j" type="fixed">'
     '<parent link="a"/><child link="b"/></joint></robot>', "the chain has no moving joint"),
    ('<robot name="x"><link/></robot>', "<link> has no 'name' attribute"),
    # a 1000-joint chain (200 kB) made ik run for minutes
    ('<robot name="x"><link name="l0"/>' + "".join(
        f'<link name="l{i + 1}"/><joint name="j{i}" type="continuous"><parent link="l{i}"/>'
        f'<child link="l{i + 1}"/><origin xyz="0 0 0.01"/><axis xyz="1 0 0"/></joint>'
        for i in range(33)) + "</robot>",
     "the chain has 33 moving joints; kincalc takes robots of up to 32"),
])
def test_bad_urdfs_are_one_line_naming_file_and_line(text, words):
    with pytest.raises(RobotFileError) as e:
        parse_urdf_text(text, "bad.urdf")
    msg = str(e.value)
    assert msg.startswith("bad.urdf:") and "\n" not in msg
    assert words in msg


def test_a_slide_without_limits_is_not_told_about_revolute_joints():
    """A prismatic joint without <limit> was told "(a revolute joint without limits is
    'continuous')"."""
    text = _chain_text(joint_type="prismatic").replace('<limit lower="-1" upper="1"/>', "", 1)
    with pytest.raises(RobotFileError) as e:
        parse_urdf_text(text, "bad.urdf")
    assert str(e.value).endswith("joint 'ja': a prismatic joint needs <limit lower upper>")



def test_a_robot_name_that_is_no_name_or_too_long_is_the_files():
    """A 900,000-character robot name was printed whole in every table's heading; a name
    that is not a robot name, or longer than MAX_NAME, gives way to the file's name."""
    from kincalc.limits import MAX_NAME
    long = _chain_text().replace('<robot name="', '<robot name="r' + "x" * 900_000, 1)
    assert parse_urdf_text(long, "my arm.urdf", stem="my arm").name == "my_arm"
    assert parse_urdf_text(long, "x.urdf", stem="a" * 200).name == "a" * MAX_NAME


@pytest.mark.parametrize("old, new, line, words", [
    # an attribute on a continuation line of its start tag is reported on its own line
    ('<limit lower="-1" upper="1"/>', '<limit lower="-1"\n       upper="oops"/>', 2,
     "<limit upper> 'oops' is not a number"),
    ('<origin xyz="1 0 0"/>', '<origin\n  rpy = \'0 0\'\n  xyz="1 0 0"/>', 2,
     "<origin rpy> needs 3 numbers, got 2"),
    # a value over several lines is named by its lines, never quoted
    ('xyz="1 0 0"', 'xyz="1 0\nS3CRET"', 1, "<origin xyz> a value over lines 1-2 is not 3"),
    ('type="revolute"><parent link="a"/>', 'type="revo\nS3CRET"><parent link="a"/>', 1,
     "type a value over lines 1-2 is not a URDF joint type"),
])
def test_an_attribute_error_names_the_attributes_line_and_shows_no_other(old, new, line,
                                                                         words):
    text = _chain_text().replace(old, new, 1)
    with pytest.raises(RobotFileError) as e:
        parse_urdf_text(text, "bad.urdf")
    assert e.value.line == line and words in str(e.value), str(e.value)
    assert "S3CRET" not in str(e.value)


def test_the_lines_of_many_attributes_of_one_tag():
    # the newlines before each attribute were counted from the tag's start for every one of
    # them: 70,000 attributes (1 MB) took 25 s; now counted on from the last
    pad = "".join(f'\n  x{i}="{i}"' for i in range(3000))
    text = _chain_text().replace('<limit lower="-1" upper="1"/>',
                                 f'<limit lower="-1"{pad}\n  upper="oops"/>', 1)
    first = _chain_text().split("\n").index(
        next(x for x in _chain_text().split("\n") if "<limit" in x)) + 1
    with pytest.raises(RobotFileError) as e:
        parse_urdf_text(text, "many.urdf")
    assert e.value.line == first + 3001 and "<limit upper> 'oops'" in str(e.value)


def test_a_floating_joint_off_the_chain_is_ignored():
    text = _chain_text(extra='<link name="w"/><joint name="free" type="floating">'
                             '<parent link="w"/><child link="a"/></joint>')
    robot = parse_urdf_text(text, "f.urdf", base_link="a")
    assert robot.dof == 2


def test_a_deep_chain_is_read_without_recursion():
    """3000 links deep (fixed joints but every hundredth, within MAX_JOINTS)."""
    n = 3000
    links = "".join(f'<link name="l{i}"/>' for i in range(n + 1))
    joints = "".join(f'<joint name="j{i}" type="{"continuous" if i % 100 == 0 else "fixed"}">'
                     f'<parent link="l{i}"/><child link="l{i + 1}"/><origin xyz="0.001 0 0"/>'
                     '</joint>' for i in range(n))
    robot = parse_urdf_text(f'<robot name="deep">{links}{joints}</robot>', "deep.urdf")
    assert robot.dof == n // 100
    assert np.isclose(robot.fk(np.zeros(robot.dof))[0, 3], n * 0.001)


# --- manufacturers' URDFs against the bundled robots (tests/conventions/urdf/SOURCES.md) ---

HERE = __import__("pathlib").Path(__file__).parent / "urdf"


@pytest.mark.parametrize("file,links,bundled,words", [
    # UR's DH frame 0 is the URDF's `base` (turned 180 deg from base_link): the chain walks
    # up the fixed joint from `base` to base_link, then down to tool0
    ("ur5.urdf", {"base_link": "base", "tip_link": "tool0"}, "ur5", "tool"),
    ("panda.urdf", {"tip_link": "panda_link8"}, "panda", "same"),
    ("iiwa14.urdf", {"tip_link": "iiwa_link_ee_kuka"}, "iiwa14", "same"),
])
def test_manufacturer_urdfs_are_the_bundled_arms(file, links, bundled, words):
    """Same joint values, same flange pose: the makers' URDFs and the DH tables kincalc
    bundles (from UR's manual, Franka's docs, KUKA's dimensions) are one arm."""
    import kincalc
    from kincalc.analysis.compare import match
    from kincalc.conventions.urdf import load_urdf
    robot = load_urdf(HERE / file, **links)
    ref = kincalc.load_robot(bundled)
    q = np.random.default_rng(5).uniform(-1.5, 1.5, (200, robot.dof))
    assert robot.dof == ref.dof
    if words == "same":
        assert np.allclose(robot.fk(q), ref.fk(q), atol=1e-9)
    else:   # UR's tool0 differs from the DH frame 6 by a turn: positions agree
        assert np.allclose(robot.fk(q)[:, :3, 3], ref.fk(q)[:, :3, 3], atol=1e-9)
    m = match(ref, robot, allow_offsets=True, free_base=True, free_tool=True)
    assert m.same and np.allclose(m.signs, 1) and np.allclose(m.offsets, 0)


def test_manufacturer_urdfs_default_chains():
    from kincalc.conventions.urdf import load_urdf
    ur5 = load_urdf(HERE / "ur5.urdf")          # tool0 and ee_link both hang on wrist_3_link
    assert "'world' -> 'wrist_3_link'" in ur5.source and ur5.dof == 6
    iiwa = load_urdf(HERE / "iiwa14.urdf")
    assert "'base' -> 'iiwa_link_7'" in iiwa.source and iiwa.dof == 7
    with pytest.raises(RobotFileError, match="'panda_leftfinger', 'panda_rightfinger'"):
        load_urdf(HERE / "panda.urdf")             # the hand's two fingers branch
    gen3 = load_urdf(HERE / "gen3_7dof.urdf", tip_link="end_effector_link")
    assert [j.limits is None for j in gen3.joints] == [True, False] * 3 + [True]


def test_gen3_urdf_is_the_user_guides_dh_to_its_rounding():
    """Kinova's URDF holds its dimensions to 0.01 mm and pi/2 as 1.5708; the bundled
    kinova_gen3 is the user guide's DH table (0.1 mm): the same arm within that."""
    import kincalc
    from kincalc.conventions.urdf import load_urdf
    robot = load_urdf(HERE / "gen3_7dof.urdf", tip_link="end_effector_link")
    ref = kincalc.load_robot("kinova_gen3")
    q = np.random.default_rng(6).uniform(-2, 2, (500, 7))
    D = robot.fk(q) - ref.fk(q)
    assert np.abs(D[:, :3, 3]).max() < 5e-4 and np.abs(D[:, :3, :3]).max() < 5e-5


# --- poe (and so URDF) to DH: the line-geometry construction ------------------------------

@pytest.mark.parametrize("to", ["dh", "mdh"])
def test_random_urdfs_convert_to_dh_with_the_same_fk(to):
    from kincalc.conventions import convert
    from kincalc.conventions.reader import parse_robot_text
    from kincalc.conventions.writer import dump_robot
    rng = np.random.default_rng({"dh": 31, "mdh": 32}[to])
    for _ in range(40):
        text, joints = random_urdf(rng, n_moving=int(rng.integers(1, 8)),
                                   n_fixed=int(rng.integers(0, 3)))
        robot = parse_urdf_text(text, "r.urdf")
        out = convert(robot, to)
        assert out.convention == to and out.M is None
        back = parse_robot_text(dump_robot(out))           # and through its file
        for qq in rng.uniform(-2.5, 2.5, (20, robot.dof)):
            want = reference_fk(joints, qq)
            assert np.allclose(out.fk(qq), want, atol=1e-10)
            assert np.allclose(back.fk(qq), want, atol=1e-9)


def _poe(axes, points, types=None):
    from kincalc.model import Joint, Robot
    types = types or ["revolute"] * len(axes)
    joints = tuple(Joint(f"q{i + 1}", t, axis=tuple(np.array(a, float) / np.linalg.norm(a)),
                         point=tuple(map(float, p))) for i, (a, p, t)
                   in enumerate(zip(axes, points, types)))
    return Robot("special", "poe", joints, M=np.eye(4))


@pytest.mark.parametrize("axes,points,types,table", [
    # planar RRR, parallel axes: a = the distances, alpha = d = 0
    ([[0, 0, 1]] * 3, [[0, 0, 0], [1, 0, 0], [2.5, 0, 0]], None,
     [(0, 1, 0), (0, 1.5, 0), (0, 0, 0)]),
    # an elbow: axis 2 meets axis 1 at height 0.5: a = 0, x1 = z x y = -x, and
    # Rx(alpha) about -x takes z onto +y for alpha = +90 deg
    ([[0, 0, 1], [0, 1, 0]], [[0, 0, 0], [0, 0, 0.5]], None, [(0.5, 0, np.pi / 2), (0, 0, 0)]),
    # skew axes 0.3 apart at height 0.2, at right angles: x1 = z x y = -x, the foot on
    # axis 2 at (0.3, 0, 0.2), so a = -0.3 along x1, and Rx(alpha) about -x takes z onto
    # +y for alpha = +90 deg
    ([[0, 0, 1], [0, 1, 0]], [[0, 0, 0], [0.3, 0, 0.2]], None,
     [(0.2, -0.3, np.pi / 2), (0, 0, 0)]),
    # coincident axes: nothing between them
    ([[0, 0, 1], [0, 0, 1]], [[0, 0, 0], [0, 0, 0.7]], None, [(0, 0, 0), (0, 0, 0)]),
    # a prismatic joint along axis 1's direction, off to the side: its line is free
    ([[0, 0, 1], [0, 0, 1]], [[0, 0, 0], [5, 5, 5]], ["revolute", "prismatic"],
     [(0, 0, 0), (0, 0, 0)]),
])
def test_special_geometries_give_the_textbook_rows(axes, points, types, table):
    """(d, a, alpha) of each row: hand-derived for each geometry."""
    from kincalc.conventions import convert
    robot = _poe(axes, points, types)
    dh = convert(robot, "dh")
    got = [(j.d, j.a, j.alpha) for j in dh.joints]
    assert np.allclose(got, table, atol=1e-12), got
    q = np.random.default_rng(1).uniform(-2, 2, (50, robot.dof))
    assert np.allclose(dh.fk(q), robot.fk(q), atol=1e-12)


def test_ur5_urdf_converts_to_urs_dh_table():
    """UR's URDF, base -> tool0, as standard DH: UR's published table up to the signs
    the construction picks (a >= 0, alpha the twist of that normal)."""
    from kincalc.conventions import convert
    from kincalc.conventions.urdf import load_urdf
    dh = convert(load_urdf(HERE / "ur5.urdf", base_link="base", tip_link="tool0"), "dh")
    assert np.allclose([abs(j.a) for j in dh.joints], [0, 0.425, 0.39225, 0, 0, 0], atol=1e-9)
    assert np.allclose([j.d for j in dh.joints], [0.089159, 0, 0, 0.10915, 0.09465, 0.0823],
                       atol=1e-9)
    assert np.allclose([abs(np.sin(j.alpha)) for j in dh.joints], [1, 0, 0, 1, 1, 0],
                       atol=1e-9)


def test_a_chain_of_fixed_joints_the_user_chose_names_its_ends():
    """--base-link and --tip-link on two sibling frames (fixed joints only between them)
    was "the chain has no moving joint", naming neither."""
    text = _chain_text(extra='<link name="d"/><link name="e"/>'
                             '<joint name="fd" type="fixed"><parent link="c"/><child link="d"/>'
                             '</joint><joint name="fe" type="fixed"><parent link="c"/>'
                             '<child link="e"/></joint>')
    with pytest.raises(RobotFileError) as e:
        parse_urdf_text(text, "bad.urdf", base_link="d", tip_link="e")
    assert str(e.value).endswith("the chain from link 'd' to link 'e' has no moving joint")


def test_a_base_frame_hanging_off_the_arm_finds_the_arms_tip():
    """ROS's layout: ``base`` hangs off ``base_link`` by a fixed joint (UR's URDF). With
    --base-link base and no --tip-link the tip was sought below ``base`` alone, where there
    is nothing: "the chain from link 'base' to its tip has no moving joint"."""
    from kincalc.conventions.urdf import load_urdf
    alone = load_urdf(HERE / "ur5.urdf", base_link="base")
    default = load_urdf(HERE / "ur5.urdf")                          # from base_link
    q = np.random.default_rng(4).uniform(-3, 3, (20, 6))
    assert alone.dof == 6
    # the same tip; base is base_link turned half a turn about z
    assert np.allclose(alone.fk(q), np.diag([-1.0, -1, 1, 1]) @ default.fk(q), atol=1e-12)
    # a base with moving joints below it keeps its own chain; a tip with nothing above it
    # that moves is still refused
    with pytest.raises(RobotFileError, match="no moving joint"):
        load_urdf(HERE / "ur5.urdf", base_link="tool0")


@pytest.mark.parametrize("second", ['<axis xyz="1 0 0"/>',
                                    '<origin xyz="0 0 1"/><origin xyz="0 0 2"/>',
                                    '<limit lower="-2" upper="2"/>', '<parent link="c"/>',
                                    '<child link="c"/>'])
def test_a_joint_with_two_of_an_element_is_refused(second):
    """Two <axis> (or <parent>, ...) in one joint were read as the first, silently: which
    one a URDF reader takes is not defined, and the file's author meant one of them."""
    tag = second.split()[0][1:]
    with pytest.raises(RobotFileError) as e:
        parse_urdf_text(_chain_text(inner=second), "two.urdf")
    assert str(e.value).startswith(f"two.urdf:1: joint 'ja' has a second <{tag}>")
