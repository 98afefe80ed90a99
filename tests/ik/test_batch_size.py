"""A pose's answer does not depend on how many poses are solved with it.

BLAS rounds a row of a product by a kernel that depends on how many rows it is given (a
lone row, ``M = 1``, by a dot product; two rows otherwise than four); and the Newton polish
evaluated a few candidates by stacked 4x4 products, many by the column walk. At a singular
configuration such a last bit decides a tangent or a near miss, and a UR-type arm lost a
solution (and relabelled two) when its pose was solved with others: found by an
independent random-robot campaign (15 poses among 68,000, then one more on a nearly
structured arm, whose subproblem-4 cone read ``h . v`` from a BLAS product of 2 rows
alone and of 4 in a batch). Checked against the same pose solved alone: the solutions,
their labels and flags.
"""

import numpy as np
import pytest

from kincalc.ik.families import plan
from kincalc.model import Joint, Robot
from kincalc.subproblems.solutions import cross, dot

P = np.pi


def _dh(rows, convention="dh", base=np.eye(4), tool=np.eye(4)):
    return Robot(name="arm", convention=convention, joints=tuple(
        Joint(f"q{i + 1}", "revolute", alpha=al, a=a, d=d, theta=0.0, limits=(-2 * P, 2 * P))
        for i, (al, a, d) in enumerate(rows)), base=np.asarray(base), tool=np.asarray(tool))


def test_dot_and_cross_of_rows_are_their_bits_in_any_batch():
    rng = np.random.default_rng(5)
    a, b = rng.normal(size=(2, 200, 3))
    v = rng.normal(size=3)
    for f in (lambda x, y: dot(x, v), lambda x, y: dot(v, x), lambda x, y: dot(x, y),
              lambda x, y: cross(x, v), lambda x, y: cross(v, x), lambda x, y: cross(x, y)):
        whole = f(a, b)
        for m in (1, 2, 3, 5):
            for i in range(0, 200 - m, 7):
                assert np.array_equal(f(a[i:i + m], b[i:i + m]), whole[i:i + m]), (m, i)


def test_transposed_views_too():
    """The same with the rows handed over as transposed views (Screws.turn returns such a
    view, and BLAS took them by another kernel: 2 rows otherwise than 4)."""
    from kincalc.subproblems.solutions import rows_times
    rng = np.random.default_rng(9)
    a = np.ascontiguousarray(rng.normal(size=(3, 200))).T        # (200, 3), a view
    v, K = rng.normal(size=3), rng.normal(size=(3, 3))
    for f in (lambda x: dot(x, v), lambda x: dot(x, x), lambda x: cross(v, x),
              lambda x: rows_times(x, K)):
        whole = f(a)
        for m in (1, 2, 3, 4, 5):
            for i in range(0, 200 - m, 11):
                assert np.array_equal(f(a[i:i + m]), whole[i:i + m]), (m, i)


@pytest.mark.parametrize("layout", ["rows", "transposed view"])
def test_turn_of_rows_is_their_bits_in_any_batch(layout):
    """Screws.turn gives each vector the same bits in any batch and either layout (numpy's
    sum of products took a transposed view's rows by another kernel, two or more rows
    otherwise than one, and the turned vectors, themselves such views, are turned again)."""
    from kincalc.ik.screws import Screws
    from kincalc.spatial import matrix_from_axis_angle
    base = np.eye(4)
    base[:3, :3] = matrix_from_axis_angle(np.array([0.3, -0.5, 0.8]) / np.sqrt(0.98), 0.7)
    S = Screws.of(_dh([(P / 2, 0.0, 0.2), (0.0, 0.4, 0.0), (0.0, 0.3, 0.0)], base=base))
    rng = np.random.default_rng(6)
    v, x = rng.normal(size=(200, 3)), rng.uniform(-P, P, 200)
    rows = S.turn(1, np.cos(x), np.sin(x), v)
    if layout == "transposed view":
        v = np.ascontiguousarray(v.T).T
    whole = S.turn(1, np.cos(x), np.sin(x), v)
    assert np.array_equal(whole, rows)
    for m in (1, 2, 3, 5):
        for i in range(0, 200 - m, 7):
            alone = S.turn(1, np.cos(x[i:i + m]), np.sin(x[i:i + m]), v[i:i + m])
            assert np.array_equal(alone, whole[i:i + m]), (m, i)


UR_LIKE = (_dh([(0.0, 0.0, -0.022733834037133804), (P / 2, 0.417065106676333, 0.0),
                (0.0, 0.29097547600131113, 0.0), (0.0, -0.15999993212559305, -0.32005370878623607),
                (-P / 2, 0.19976471578091048, 0.018855569744463785),
                (P / 2, 0.0, -0.09235336230124302)], "mdh",
               base=[[-0.007217298793474145, -0.5136999545423887, 0.8579395475797077,
                      -0.06646078305589431],
                     [-0.22921876218789003, -0.8342675148067326, -0.5014543576430956,
                      0.3891428398647504],
                     [0.9733481749400762, -0.20027498705865884, -0.11172850978813241,
                      -0.2904557467108265], [0.0, 0.0, 0.0, 1.0]],
               tool=[[0.6047791347120135, -0.7962097645133039, -0.017094125033396416,
                      -0.45338279401134374],
                     [-0.6983046375417228, -0.5404886617113794, 0.46930015954521614,
                      0.26000789317615036],
                     [-0.3829005502799799, -0.27188603762442687, -0.8828732361671053,
                      0.4377815441706875], [0.0, 0.0, 0.0, 1.0]]),
           [-1.5707963220004073, 3.1415926583842824, 3.141592648795304,
            -4.794489186130156e-09, 3.1415926583842824, -1.5707963315893858])
#: a UR-type arm with a5 = -3e-8 (nearly structured: its candidates are polished by Newton)
NEARLY_UR = (_dh([(P / 2, 0.0, 0.17799083567729135), (P, 0.3977891559121358, -0.3395290603034915),
                  (0.0, 0.15242504754302, 0.3780316734753586), (P / 2, 0.0, 0.11674305823901276),
                  (P / 2, -2.9734718369676377e-08, 0.2813347409771977),
                  (P / 2, 0.12441226660705207, 0.3849769786291364)]),
             [1.570796326405618, 3.8927855271463154e-10, 3.8927855271463154e-10,
              -1.5707963271841752, 3.1415926532005147, -3.8927855271463154e-10])


#: a UR-type arm with a5 = -1.1e-6, a base and a tool, its shoulder at 180, 180 deg and the
#: elbow straight: a cone's ``h . v`` of 2 rows alone and of 4 rows in a batch differed by an
#: ulp, and the pose had 3 solutions alone and 2 in any batch
NEARLY_UR_STRAIGHT = (_dh([(P / 2, 0.379174581107803, 0.17383452386923437),
                           (0.0, 0.15081257456816077, 0.0), (0.0, 0.487313322684474, 0.0),
                           (-P / 2, 0.0, 0.0), (P / 2, -1.1131894641844347e-06, 0.1558795946061472),
                           (P, 0.0, -0.083744014472387)],
                          base=[[-0.2305207390244982, -0.8720358701761013, -0.43175644755557363,
                                 0.449445960650137],
                                [-0.3660197035533399, 0.4888276917411411, -0.7918819763056569,
                                 0.1307407911768057],
                                [0.9016039959374206, -0.02451385145662601, -0.43186723144554295,
                                 -0.4020525861050176], [0.0, 0.0, 0.0, 1.0]],
                          tool=[[-0.4839568424234425, -0.4550230812932108, 0.7474889766156846,
                                 -0.3115854147553636],
                                [0.8746370898989339, -0.22397832861256295, 0.42993449417910995,
                                 -0.1531785728941012],
                                [-0.02820878665692045, 0.8618513234905165, 0.506375908345756,
                                 -0.011179294494303105], [0.0, 0.0, 0.0, 1.0]]),
                      [P, P, 0.0, -P / 2, 0.6010763706921458, -P / 2])


@pytest.mark.parametrize("robot, q", [UR_LIKE, NEARLY_UR, NEARLY_UR_STRAIGHT],
                         ids=["ur-like", "nearly-ur", "nearly-ur-straight"])
def test_a_singular_pose_alone_and_in_batches(robot, q):
    """The arm a hair from q2 = q3 = q5 = 180 deg (and its nearly structured cousin): the
    pose alone, and the same pose 2, 8 and 64 times over, have the same solutions, labels
    and flags; each solution reaches the pose."""
    assert plan(robot)[1] is not None
    T = robot.fk(np.array(q))
    alone = robot.ik(T)
    want = sorted((s.branch, bool(s.singular), bool(s.within_limits)) for s in alone.solutions)
    assert len(want) >= 1
    for N in (1, 2, 8, 64):
        solved = robot.ik_batch(np.repeat(T[None], N, 0))
        for i in (0, N - 1):
            v = solved.valid[i]
            got = sorted(zip(solved.labels[i][v].tolist(), solved.singular[i][v].tolist(),
                             solved.within[i][v].tolist()))
            assert got == want, (N, i)
    Tq = robot.fk(np.array([s.q for s in alone.solutions]))
    assert np.abs(Tq - T).max() < 1e-9


#: a prismatic first joint, then revolute joints, a spherical wrist: joints 1-3 place the
#: wrist centre through the resultant (an independent campaign's r0_pieper_dh_nb); its
#: placement's invariants were read from BLAS products (``d @ k`` of N K rows, the
#: resultant's samples times the fit): a pose's bits depended on its batch, and at a
#: shoulder-singular pose the count (5 alone, 4 in batches of 9 or more, with the second
#: roots of subproblem 4 kept there)
PRR_WRIST = Robot(name="prr", convention="dh", base=np.eye(4), tool=np.eye(4), joints=(
    Joint("j1", "prismatic", alpha=-3.03774645687452, a=-0.4159716076401226,
          d=0.46074000977497476, theta=1.441969420022903, limits=(-1.0, 1.0)),
    *(Joint(f"j{i + 2}", "revolute", alpha=al, a=a, d=d, theta=th, limits=(-P, P))
      for i, (al, a, d, th) in enumerate([
          (0.27410390540137985, 0.4707825907044957, 0.4171340993546895, 2.2456372993781644),
          (-2.930568260297326, -0.3783449508934748, -0.12904502927115158, 0.2605085298868297),
          (-1.2584473065782806, 0.0, 0.2402092495389463, 0.0),
          (-2.9636549119444626, 0.0, 0.0, 0.0),
          (-2.3606977967595952, 0.35178098661213364, 0.32692330016656423, 0.0)]))))


def test_a_resultant_placement_gives_a_pose_its_bits_in_any_batch():
    """Each pose's candidates, solutions and labels, solved with 0, 1, 2, 7, 8 or 63 others,
    are those of the whole batch bit for bit (random poses and the shoulder-singular one)."""
    from kincalc.ik import place
    S = plan(PRR_WRIST)[0]
    assert place.plan(S, (0, 1, 2), tuple(S.point[3].tolist())).mode == "resultant"
    rng = np.random.default_rng(19)
    Q = np.column_stack([rng.uniform(-1, 1, 80), rng.uniform(-P, P, (80, 5))])
    T = np.concatenate([PRR_WRIST.fk(Q), [[[-0.53515504805504732, -0.10282431712638879,
                                             -0.83847256028369299, 0.069453913088146482],
                                            [-0.84454969845843852, 0.043303453185833708,
                                             0.53372335322331821, -0.86237130638318393],
                                            [-0.018570982067743123, 0.99375649469559391,
                                             -0.11001430759390102, -0.78491916097947678],
                                            [0.0, 0.0, 0.0, 1.0]]]])
    whole = PRR_WRIST.ik_batch(T)
    for m in (1, 2, 3, 8, 9, 64):
        for i in range(0, len(T) - m + 1, 9):
            part = PRR_WRIST.ik_batch(T[i:i + m])
            assert np.array_equal(part.valid, whole.valid[i:i + m]), (m, i)
            assert np.array_equal(part.q, whole.q[i:i + m]), (m, i)
            assert np.array_equal(part.labels, whole.labels[i:i + m]), (m, i)


@pytest.mark.parametrize("name", ["puma560", "ur5", "adept_cobra600", "siciliano_arm",
                                  "bk_rr", "craig_3r", "lynxmotion_al5d", "bk_offset_wrist",
                                  "spong_cylindrical", "manocha_canny_6r"])
def test_every_family_gives_a_pose_its_bits_in_any_batch(name):
    """A robot of each family at random and at special joints (0, +-90, 180 deg, a hair off
    them): each pose's answer solved alone or with 1 or 8 others is the whole batch's, bit for
    bit (a guard: the products whose bits depended on the batch were found by campaigns)."""
    from kincalc import load_robot
    r = load_robot(name)
    rng = np.random.default_rng(20)
    lo, hi = np.where(np.isfinite(r.limits), r.limits, [-P, P]).T
    Q = rng.uniform(lo, hi, (30, r.dof))
    special = np.radians(rng.choice([0.0, 90.0, -90.0, 180.0], (30, r.dof)))
    special += rng.choice([0.0, 0.0, 1e-9, -1e-7], special.shape)
    Q[15:] = np.where(r.is_revolute, special[15:], Q[15:])
    T = r.fk(Q)
    whole = r.ik_batch(T)
    for m in (1, 2, 9):
        for i in range(0, len(T) - m + 1, 4):
            part = r.ik_batch(T[i:i + m])
            assert np.array_equal(part.valid, whole.valid[i:i + m]), (m, i)
            assert np.array_equal(part.q, whole.q[i:i + m]), (m, i)
            assert np.array_equal(part.labels, whole.labels[i:i + m]), (m, i)
