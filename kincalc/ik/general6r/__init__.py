"""All real inverse-kinematics solutions of a general 6R robot, for a batch of poses.

Method
------
Raghavan & Roth's elimination (M. Raghavan, B. Roth, "Inverse kinematics of
the general 6R manipulator and related linkages", ASME J. Mech. Des. 115,
1993; conference version 1990) in the numerically robust matrix form of
D. Manocha, J. F. Canny, "Efficient inverse kinematics for general 6R
manipulators", IEEE Trans. Robotics and Automation 10(5):648-657, 1994.
Every step runs on all poses of a batch at once (:func:`solve_general_6r_batch`;
a single pose is a batch of one).

1. **Standard DH of the six axes.** Whatever the robot's convention, the
   joint axes at q = 0 (:func:`kincalc.structure.joint_axes`) are turned into
   standard DH parameters ``A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``
   with ``theta_i = q_i + offset_i``, plus fixed transforms, so that
   ``T = B A_1 ... A_6 E``. Frame i-1 has z along joint i's axis (same sense,
   so no sign flips); x_i runs along the common normal of axes i and i+1
   (direction ``z_{i-1} x z_i``); its origin is the normal's foot on axis i+1.
   Consistent choices for the special cases: *intersecting* axes give
   ``a_i = 0`` with x_i still ``z_{i-1} x z_i``; *parallel* axes (sine of the
   angle below 1e-7) take the normal through the previous origin (``d_i = 0``),
   and *coincident* axes keep ``x_i = x_{i-1}``. Frame 0 sits at the foot of
   the 1-2 normal on axis 1 (``d_1 = 0``) with ``x_0 = x_1``; frame 6 equals
   frame 5 turned by theta_6 (``a_6 = d_6 = alpha_6 = 0``); ``B`` (base) and
   ``E`` (tool) absorb the rest. Lengths are divided by the robot's
   characteristic length so every number is O(1).
2. **The 14 Pieper / Lee-Liang equations.** From
   ``A_3 A_4 A_5 = A_2^-1 A_1^-1 T' A_6^-1`` take the third column ``l`` and
   the origin ``p`` (both free of theta_6) and form
   ``l, p, p.p, p.l, p x l, (p.p) l - 2 (p.l) p``. The left side is
   trilinear in (1, cos, sin) of theta_3, theta_4, theta_5, the right side
   bilinear in those of theta_1, theta_2 (Raghavan & Roth's observation). The
   coefficients are not typed in symbolically: they are read off exactly by
   a 3-point discrete Fourier fit per angle (grid 0, 2pi/3, 4pi/3), once per
   robot for the left side; on the right, ``l`` and ``p`` at each grid point
   of (theta_1, theta_2) are linear in ``u = (1, l_T, p_T)`` of the target, so
   the fit is a cubic in u whose 84 x 126 coefficients are also computed once
   per robot (:func:`~.common.cubic_map`), leaving one product per pose. This gives
   ``P(theta_3) X1 = Q X2`` with ``X1`` the nine products
   of (1, c4, s4) and (1, c5, s5), ``X2`` the eight non-constant products of
   (1, c1, s1) and (1, c2, s2), ``P`` 14x9 linear in (1, c3, s3), ``Q`` 14x8.
3. **Elimination.** ``X2`` is removed with an orthonormal basis ``N`` (6x14)
   of the left null space of ``Q`` (Householder QR, not Cramer's rule):
   ``N P(theta_3) X1 = 0``, a 6x9 system. Half-angle substitution
   ``x_i = tan(theta_i / 2)`` for i = 4, 5 and multiplication by ``x_4`` give
   the 12x12 matrix polynomial ``Sigma(x3) = A x3^2 + B x3 + C`` acting on
   the monomials ``x4^j x5^k`` (j <= 3, k <= 2).
4. **Eigenproblem.** ``det Sigma = 0`` has degree 24 with the spurious factor
   ``(1 + x3^2)^4``: theta_3 enters ``l`` and ``p`` only as a turn about z_2,
   so ``Sigma(+-i)`` is singular, with a right null space ``V`` (12x4) that
   depends on the left side alone (per robot). The 24x24 companion matrix
   ``[[0, I], [-A^-1 C, -A^-1 B]]`` has the invariant subspace
   ``[V; +-i V]``; an orthogonal change of basis (per robot) splits it off, and
   ``numpy.linalg.eig`` solves the remaining 16x16 block, whose eigenvalues
   are the 16 roots; the eigenvectors of the companion matrix follow from the
   block triangular form (``(lambda - M)^-1`` with ``M^2 = -I``; see
   :meth:`~.model.Model._deflation`). ``A`` and the R factor of ``Q`` are inverted
   together (one batched ``inv``); a condition estimate of R above 1e9 marks
   ``Q`` as rank deficient.
   *Degenerate leading matrix / x3 = infinity (theta_3 = pi):* numpy has no
   QZ, so instead of a generalised eigensolver the unknown is shifted,
   ``theta_3 = phi + delta``: ``A`` is then ``Sigma`` at ``theta_3 = pi +
   delta``. Four shifts are tried (0 and three irrational-looking ones): the
   first whose ``A`` has a condition estimate ``|A|_F |A^-1|_F`` below 1e4,
   else the best conditioned, so a root at or near theta_3 = pi (common: the
   published 16-solution example has theta_3 = 179.96 deg) never sits at
   infinity. Eigenvalues whose angle ``2 atan(y)`` has an imaginary part
   below 0.05 rad count as real candidates (near-double real roots come out
   as complex pairs).
5. **Back-substitution** (:func:`~.elimination._candidate_angles`, for the real candidates
   only). ``x4``, ``x5`` come from the eigenvector (least-squares ratios of
   consecutive entries, inverted ratios when |x| > 1, so theta = pi is fine);
   ``(c1, s1, c2, s2)`` from ``Q X2 = P X1`` (least squares through the same
   QR); theta_6 from ``A_6 = (A_1..A_5)^-1 T'``, with ``R1 R2`` and
   ``R3 R4 R5`` as linear maps of the products of (1, cos, sin) already at
   hand.
   *Clusters:* eigenvalues whose angles' real parts are closer than 1e-3 rad
   (solutions sharing the pivot angle, e.g. the two wrist flips of a
   spherical wrist; near-double roots split into a conjugate pair) get a
   second set of vectors (a conjugate pair of the robot's own pencil only when its
   imaginary part is below 1e-2 rad: rounding splits a double root by some
   sqrt(eps * condition), while a pair farther off the real axis is a complex root: one
   random pose in seven or eight of a generic robot has one, and its subspace vectors
   found nothing on 3,000 random and 1,000 special poses of each general 6R of the
   library; a perturbed model's pairs are all treated, see below): at their mean, the
   monomial vectors are recovered from the null space of ``Sigma`` as common
   eigenvectors of the "multiply by x4" and "multiply by x5" shift operators; the
   vectors closest to monomial structure are kept (see
   :func:`~.elimination.split_clusters`; all clusters of one size are treated
   together, their extra vectors take slots 16-31 of their pose). A cluster is a chain, so an exact multiple root can share it
   with distinct roots some 1e-4 rad away and the mean misses it: each
   *tight* sub-cluster of a chain (diameter times 10 below its distance, above
   1e-5 rad, to the chain's other eigenvalues, in the complex plane) gets the
   same treatment at its own mean as well (slots 32-47); the chain's own mean
   stays (a defective root that rounding splits into a polygon, real angle and
   conjugate pair, has its root at the polygon's centre).
6. **Polishing.** Every candidate gets up to 20 damped Newton steps on the
   *given* robot (``robot.chain``, so the DH model above only has to be
   close): error ``[(p* - p) / L; log(R* R^T)]`` against the base-frame
   geometric Jacobian (:func:`kincalc.jacobian.jacobian_and_pose` on the
   chain with lengths divided by L), steps limited to 0.5 rad
   (:func:`kincalc.ik.newton.polish`), the rotation log from the skew part
   below 90 degrees. Most candidates converge in one to three steps or are given up
   after three or six; a step whose landing the chain's curvature bounds below 1e-14
   (quadratic convergence) is not evaluated again (:func:`~.polish.newton_curvature`); the later steps serve solutions at a singular configuration,
   where Newton converges only linearly (kinova_gen3_lite folded at q2 = 180 deg, a
   pose every pivot degenerates at: the last resort's candidates start some 1e-2 rad
   away and were still at 1e-9 after ten steps, so the pose came out unreachable).
   The last resort's candidates (see below) are given up only after ten steps (above
   1e-4), and each one that converged is started once more from the reflection of its
   solution across its start (:func:`~.polish.polish_from_both_sides`).
   Candidates whose final residual ``max(|dp| / L, |dw|)`` exceeds 1e-10 are
   dropped, the rest are wrapped to (-pi, pi] and merged (per pose) when
   within 1e-6 rad of a solution from an earlier slot (only needed when some
   candidate moved or a pose had a cluster: distinct eigenvalue slots are
   farther apart than that otherwise).

Batches of more than 512 poses are solved 512 at a time (their arrays then
stay in the processor's cache; larger blocks are slower per pose).

A pose's answer has the same bits whatever else is in its batch (alone, in a block,
in any order). That matters at degenerate poses: where a pose has a continuum of
solutions, or the pencil is nearly singular, the eigenvalues and Newton's landing
points amplify a difference in the last bit into different solutions and labels. So
no step rounds a pose differently by the batch's size: products are taken per pose
(stacked, never one matrix product over the poses, whose BLAS kernel depends on the
row count), an exactly singular matrix is inverted on its own (numpy's batched
``inv`` fails for all), and Newton evaluates the chain in the same order for any
number of candidates (the column walk of :func:`kincalc.jacobian.jacobian_and_pose`).

Choice of pivot joint and special geometry
------------------------------------------
The closure ``A_1 ... A_6 = T'`` can be rotated cyclically into
``A_{k+1} ... A_6 T'^-1 A_1 ... A_k = I``: again a 6R inverse-kinematics
problem (joints k+1..6, 1..k; the pose becomes the fixed link between joints
6 and 1, the target is the identity), whose pivot is joint k + 3 (mod 6). Shift 0
(pivot joint 3) is the standard form and has its left side and the
deflation of step 4 precomputed per robot; for the other shifts the DH model
is rebuilt per pose from the same axis lines (vectorised over the poses that
need them), written in the frame of joints 1..k: their axes stay put, those
of joints k+1..6 move with the pose. So the DH frames of the shifted chain
from the first one with both axes fixed on are the same for every pose
(computed once per shift), and for shift 5 (pivot joint 2) the whole left
side and its deflation are (joints 2-4 of the robot). There joints 1 and 2 of
the shifted chain are given as general links ``A_i = Rz(q_i) M_i`` between
frame 0, which moves with the pose, and a fixed frame 1 (only ``A_1 A_2`` on
the grid of step 2 is used, so frame 1 need not be DH): per pose only ``M_1``
and the right side are built, no DH frame.

For robots with special structure the standard form degenerates: with three
parallel axes (UR arms) or a spherical wrist (PUMA, KUKA, ABB, FANUC) the
12x12 pencil is singular, every leading matrix ``A`` is singular
(condition estimate above 1e10 for all four shifts ``delta``), or ``Q``
loses rank (condition estimate of its R above 1e9). Nearly special robots
(a calibrated UR5 whose twists are off by 1e-8 .. 1e-4) are worse: the
pencil is regular but ill-conditioned and the eigenvalues are inaccurate.
So once per robot (cached) the six shifts are ranked on three seeded probe
poses by how accurately their raw candidates recover the generating
configuration; shift 0 is kept without further probing when it is accurate
to 1e-8 rad (every generic robot). In the library, UR arms end up pivoting
on joint 2 (shift 5, the parallel joints 2-3-4 on the left side) and
wrist-partitioned arms on joint 5 (shift 2) or joint 2. Per pose the ranked
shifts are tried in order until one is not degenerate. If all six
degenerate (at generic poses rare: e.g. a random arm with axes 1-2-3 parallel
and 3-4-5 intersecting pairwise; but common at the special poses of robots with
special geometry, joints at 0, +-90 and 180 deg: a quarter to a half of them
for kinova_gen3_lite, yaskawa_hc10 and fanuc_crx10ia, a tenth for
kinova_jaco2_6dof; or, at a pose a hair from such a one, a shift passes but none
of its candidates reaches the pose, Newton stalling within 1e-3), the standard form
is solved for two nearby *generic* robots (each scaled DH parameter moved
by a fixed pseudo-random 0.5 .. 1
times 1e-3, resp. 1e-4; the larger size suits robots whose solutions are
well separated, the smaller one robots close to a singular configuration) and
the union of their candidates is polished on the real robot. Those poses
often have a close pair of solutions (0.1 rad apart, a nearly singular
Jacobian, e.g. two wrist solutions sharing the pivot angle), against whose
separation the perturbation is large: a perturbed robot's pair merges, turns
complex (both candidates at its real part, near the real pair's midpoint) or
moves onto one of the two, and Newton, whose basins part near the midpoint,
took every candidate to the same solution. So each candidate that converged
is started again from the reflection ``2 c - q`` of its solution ``q``
across its start ``c``, which lies beyond the midpoint when ``c`` lay between
the pair; and since between a close pair Newton converges only linearly until
it is nearer one of them, the last resort's candidates are given up later
(after ten steps, above 1e-4, instead of six, above 1e-6). On 2,000 special
poses each (seeded), this took the regular generating configurations lost
from 26 (kinova_gen3_lite) and 11 (kinova_jaco2_6dof) to none, and the poses
without any solution (folded, singular roots) from 13 (kinova_jaco2_6dof)
and 1 (fanuc_crx10ia) to none; a pose solved by the last resort costs some
20 % more. UR5 and PUMA give their (up to) 8 solutions, the same as the
analytic family solvers of :mod:`kincalc.ik.families`. Robots with infinitely many solutions at a pose
(coincident axes; a pose on a self-motion) get whatever isolated points
Newton lands on.

A pose none of whose candidates reaches ACCEPT_TOL is rescued (found by an independent
random-robot campaign: 43 FK poses of 10 robots, fanuc_crx10ia among them, had no solution).
Where the exact root sits in a valley of near-solutions (fanuc_crx10ia at (90, 179.9, 90,
65.27, 0, -216.67) deg) Newton converges sublinearly: its candidates within ``VALLEY``
(1e-6) get ``RESCUE_ITERS`` (200) more steps and are kept where they reach ``SETTLED``
(5e-10, within the engine's 1e-9); 0 of 300 poses scattered 1e-7 .. 1e-4 deg about that
configuration now have no solution (168 before). Where every pivot and the last resort
degenerate and nothing settled (a continuum, a pose on a fold of the workspace: a 6R with
axes 1-3 parallel), Newton runs from ``STARTS`` (32) seeded starts. A rescued pose's
solutions are thinned to one per ``THIN`` (0.1 rad), those within the joint limits first,
then the best, and are flagged singular: samples of the valley or continuum where Newton
landed, not every point of it (a continuum is not marked free here). A pose outside the
workspace costs the rescue only where every pivot degenerates there.

Limitations
-----------
* Solutions at or very near a singular configuration converge slowly or to
  a neighbour and may be dropped by the 1e-10 residual test or merged: two
  distinct solutions closer than 1e-6 rad are reported once. For a generic
  6R the real count is even, so an odd count flags such a case. Special
  and nearly special robots (which need another pivot) lose a solution of
  a near-singular pair somewhat more often than generic ones. The last
  resort's restarts find a close pair's second solution when a candidate lies
  between the two; one whose candidates all lie beyond one of them can still
  lose the other (not seen on the special poses above). A restart's landing point is
  kept only where it is regular (the engine's singular test): at a singular root it
  lands on its source's root again, 1e-6 .. 1e-3 rad off, beyond the merge tolerance.
* At a pose with a continuum of solutions (a self-motion) at one pivot angle and
  isolated regular solutions at the same angle (yaskawa_hc10, fanuc_crx10ia with joints
  1 and 4 lined up), Sigma's null space there holds a curve of monomial vectors and the
  cluster's vectors are mixtures, although the pivot passes its tests: the isolated
  solutions were missed (on the 2,000 special poses above, 389 at 220 poses of
  yaskawa_hc10 and 121 at 76 of fanuc_crx10ia, every one regular: smallest singular value
  of the scaled Jacobian at least 2e-4 of the largest). Such a cluster (four or more
  eigenvalues without a monomial vector, or a chain longer than 12; see
  :func:`~.elimination.split_clusters`) now marks the pose, which gets the perturbed
  robots' candidates besides the pivot's; where a pose then has more than 16 solutions,
  the regular ones take the slots first (the continuum's points are samples with a
  singular Jacobian; regular by the engine's test, :func:`~.polish.regular`). The same measurement now misses none. The continuum itself is
  reported only as the points Newton lands on (flagged singular).
* A close pair of solutions sharing the pivot angle (a nearly singular Jacobian) whose
  cluster's vectors both land on one of the two can lose the other: one kinova_gen3_lite
  pose of the 2,000, (165.48, -89.67, -90, 0, 180, 180) deg, whose partner 0.07 rad away
  is missed. A later give-up alone does not find it (the cluster's candidate then
  converges to the found one); the last resort's restart from the reflection does, but
  applied to every cluster's vectors it cost some 10 % on generic poses (measured when
  every conjugate pair within 0.05 rad of the real axis was a cluster), so it is not done.
* The 1e-10 acceptance (5e-10 for a rescued pose) is relative to
  ``robot.characteristic_length``; a pose outside the workspace gets no solution.
* Robots with a prismatic joint are not handled (ValueError).
* Speed (``benchmarks/ik_single.py``, one thread, numpy/OpenBLAS, as multiples of
  one ``numpy.linalg.eig`` of a 24x24 matrix, 0.14-0.25 ms on the shared machine it
  was measured on; the 16x16 ``eig`` is about half of one): a generic robot takes
  about 2.5-4.5 of them for a batch of one pose (0.5-1 ms there) and 0.5-1.1 per pose
  in batches of 1000 to 10000; robots that pivot on another joint (UR, PUMA, KUKA,
  ABB arms: a model per pose) about 10-15 for one pose and 1.1-3.7 per pose in
  batches (measured again on a machine where one ``eig`` takes 0.11 ms: the library's
  arms that pivot on joint 2, whose left side is shared, 7-12 for one pose and 1.3-1.5
  per pose in batches of 1000, xarm6 (pivot joint 1) 12 and 1.6-1.8); plus a one-off
  5-30 ms per robot for the model and the pivot ranking (cached for 64 robots).

The modules: :mod:`~.common` (tolerances, robot-independent tables, vectorised
helpers), :mod:`~.model` (the robot as scaled standard DH and the left side of the
elimination), :mod:`~.elimination` (steps 3 to 5 for a batch of poses), :mod:`~.robot`
(per-robot data and the pivots), :mod:`~.polish` (step 6) and :mod:`~.solve` (the public
API and the engine's step). They use the model's chain, jacobian, spatial and the
engine's per-robot cache and Newton polish.
"""

from __future__ import annotations

from .common import BATCH_SLOTS
from .solve import general_6r, solve_general_6r, solve_general_6r_batch

__all__ = ["BATCH_SLOTS", "general_6r", "solve_general_6r", "solve_general_6r_batch"]
