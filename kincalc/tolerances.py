"""Named numerical tolerances, in one place.

Functions that use them take a keyword to override.
"""

#: cos(pitch) (or sin(b)) below which an Euler-angle extraction is treated as
#: gimbal-locked and one angle is set to zero.
GIMBAL_TOL = 1e-9

#: rotation angle (rad) below which an axis is not defined.
SMALL_ANGLE = 1e-12

#: relative threshold on singular values: sigma_i < RANK_TOL * sigma_max counts
#: as zero when computing the rank of a Jacobian.
RANK_TOL = 1e-9

#: a configuration is reported singular when the smallest singular value of
#: its Jacobian (scaled by the robot's characteristic length) is below this.
SINGULAR_TOL = 1e-6

#: geometric tests on axes (parallel, intersecting), relative to robot size.
GEOMETRY_TOL = 1e-9

#: IK families are recognised from the joint axes: axes meet when they pass within
#: STRUCTURE_POINT_TOL x the arm's size (at least 1 m) of one point, and are parallel
#: when the sine of their angle is below STRUCTURE_ANGLE_TOL. Loose enough for
#: calibrated models and rounded datasheets (a twist written 1.5708 for pi/2 is 3.7e-6
#: off): such a robot is only nearly of its family, and its closed-form solutions are
#: refined on the true robot (kincalc.ik.refine).
STRUCTURE_POINT_TOL = 1e-4
STRUCTURE_ANGLE_TOL = 1e-4

#: a family's structure is exact when it holds to these (rounding of a file's values):
#: the closed form's answers are then the robot's own, to rounding
EXACT_POINT_TOL = 1e-11
EXACT_ANGLE_TOL = 1e-12
#: a robot only nearly of its family whose axes are within this of it (of the arm's size;
#: rad) keeps the nearest robot's continua at a singular pose (kincalc.ik.nearly): along
#: one, its FK differs from that robot's by far less than the check sees (ACCEPT_POSITION,
#: ACCEPT_ORIENTATION). A twist written with 11 significant digits (1.5707963268 for pi/2)
#: is 5e-12 off. At 3e-11 and beyond the nearest robot's closed form starts to miss such
#: poses outright (their singular roots lie beyond its tangent bands), and the roots of the
#: broken continuum, traced on the robot as given (kincalc.ik.valleys), are the answer
KEEP_CONTINUA = 1e-11

#: an IK candidate is a solution when FK reaches the target to ACCEPT_POSITION x the
#: arm's size and, for the orientation the robot controls, ACCEPT_ORIENTATION rad;
#: components a robot does not control (the orientation of a position-only arm) are
#: checked to CHECK_ORIENTATION rad (at a double root the joints are only good to
#: ~sqrt(eps))
ACCEPT_POSITION = 1e-9
ACCEPT_ORIENTATION = 1e-9
CHECK_ORIENTATION = 1e-6

#: a candidate that misses by at most this (position / the arm's size, orientation in rad)
#: lies next to a solution and is polished onto it (kincalc.ik.near_miss): a double root
#: next to a singularity is good to ~sqrt(rounding) only (a 12-digit pose's, times an
#: ill-conditioned step's gain: a 5-joint arm's approach missed by 1.8e-5 rad at q5 = 0)
NEAR_MISS = 1e-4

#: a solution with a joint at most this beyond a limit (rad, or of the arm's size), where
#: the merged double root's other side is within it, is polished into the limits
#: (kincalc.ik.near_miss); wider, a distinct solution of a near double root 1e-4 rad away
#: would be polished onto its neighbour and lost
NEAR_LIMIT = 1e-5

#: the error of a pose written with 12 significant digits (kincalc's JSON) and read back:
#: up to 5e-13 an entry, re-orthonormalised; with a margin. Next to a singularity a joint
#: read from such a pose may be off by this over the sine of the singular angle
#: (kincalc.ik.wrists.into_elbow_reach)
ROUNDED_POSE = 1e-11

#: the near miss of an orientation the robot does not control (a position arm given a whole
#: pose): its joints come from the position, and next to a double root of it (the point a
#: hair off an axis) a joint is good to the square root of rounding over the lever only,
#: while the orientation moves with that joint at full rate (a pose rounded to 12 digits
#: splits such a double root into two roots ~1e-3 rad apart, each reaching the position
#: exactly, its orientation 4e-4 .. 3e-3 off). A candidate within NEAR_MISS of the position
#: and within this (rad) of the orientation is polished on the whole pose; the polish is kept
#: only where it reaches the whole pose
NEAR_MISS_UNCONTROLLED = 1e-2

#: a branch word (shoulder, elbow, wrist: the sign of a product of a solution's axes and
#: points, kincalc.ik.words) tells nothing where its product is within this (of the arm's
#: size, or of 1 for the wrist's) of zero: there two solutions meet in a double root, which
#: a closed form places only to the square root of rounding (a wrist at q5 = 0 found at
#: q5 = -4.7e-8 in one convention and at 0 in another; a UR-type wrist at q5 = 180 deg
#: found 2.9e-7 rad off in the poe file `kincalc convert` writes, a robot 1e-14 away),
#: so the word's sign is noise
WORD_BOUNDARY = 1e-6

#: two IK solutions are one when every joint agrees to this (rad, or m; wrapped)
DUPLICATE = 1e-6
#: ... and two polished candidates of a resultant's double root when they agree to this (rad,
#: or of the arm's size): Gauss-Newton converges there linearly, and candidates reaching it
#: from several roots of the fitted resultant (a cluster's mean, a real root beside it) stop
#: some 1e-6 apart, each reaching the target (kincalc.ik.place); never two that each reach
#: the target to INEXACT while the joints halfway miss it by more: two roots, however close
#: (next to a fold the target changes to second order only: a PUMA's two elbows 4e-6 rad
#: apart, 2e-6 from the stretched elbow, each reach it to 1e-16 and halfway to 1e-12)
SAME_DOUBLE_ROOT = 1e-5
#: ... and two solutions of a flat double root when they agree to this (rad, or of the arm's
#: size), each misses the target by more than INEXACT and the joints halfway between them
#: miss it by less than half the better one: where the target changes to second order only
#: as the joints leave a double root (a stretched elbow's, an aligned wrist's), a solver
#: places it no better than to the square root of its own error, and two copies 1e-4 rad
#: either side of it both reach the target to 1e-11 (a reversed parallel-four-wrist arm
#: at its stretched elbow). Two distinct roots that close each reach it to rounding, and
#: between them it is missed
SPLIT_DOUBLE_ROOT = 1e-3
#: ... and two copies of a point that a resultant placed at a fold of the arm, by the same
#: rule, when they agree to this (rad, or of the arm's size): there one joint moves along
#: the fold hundreds of times faster than the others, and its copies stay some 5e-3 apart
#: (kincalc.ik.pieces)
SPLIT_PLACEMENT = 1e-2
#: a solution that misses its target by more than this (m per m of the arm's size, plus rad)
#: was not found to rounding: the forward kinematics of an exact one misses by some 1e-16 ..
#: 2e-14 (SPLIT_DOUBLE_ROOT; two copies of a double root whose halfway joints miss by no more
#: are answered there, the middle of what rounding cannot tell apart)
INEXACT = 2e-14
#: a solution that reaches its target less well than this (m per m of the arm's size, plus
#: rad) is polished by Newton to rounding (kincalc.ik.near_miss): a root that a few
#: Gauss-Newton steps left short (a resultant's placement, a general 6R arm next to a
#: singularity: 1e-12 .. 1e-9); far above rounding, so that the decision is the same however
#: FK was evaluated (a batch's column walk, a single pose's frames)
ROUGH = 1e-12

#: a joint counts as within its limits up to this much beyond them (rad; times the
#: arm's size for prismatic joints): rounding of a solution at its limit
LIMIT_TOL = 1e-9

#: a placing joint left free (the point on its axis) solves its invariant to this (of the
#: invariant's scale, length^2): a point that the joint after it put on the axis by a double
#: root, taken within subproblem 4's ROUNDING of the tangent, lies off it by up to
#: sqrt(2 ROUNDING) ~ 2e-7 of the arm's size; the engine's check and polish judge the
#: candidate (at subproblem 4's own 1e-9, bk_6r 8e-7 deg from q3 = 90 and q5 = 180 lost
#: every solution)
FREE_REACH = 1e-6

#: a joint moves a point at all when its lever on it is at least this (of the arm's size per
#: rad; kincalc.ik.pieces)
MOVES = 1e-5

#: a point a double root of subproblem 4 leaves within this (of the arm's size) of an axis is
#: folded through it (kincalc.ik.pieces.split_fold): the band of the tangent (ROUNDING) moves
#: it by up to ~2e-7, which turns the joint about that axis by 2e-7 / its distance, 2e-4
#: rad 1e-3 from it (a planar arm of links equal to 1e-4, 1e-7 rad from folded: its two
#: elbows 2e-3 rad apart in joint 1)
FOLD_NEAR_AXIS = 1e-3

#: a three-parallel-offset arm (kincalc.ik.solvers): subproblem 6's roots for joints 1 and 5
#: with axis 6 within this sine of the parallel axes are sharpened by Newton's method on the
#: sines, where subproblem 6's cosines lose (rounding over the sine) of the angles
SHARPEN_NEAR_PARALLEL = 1e-2
#: ... and within this sine a root is tried on the singularity itself (axis 6 along them):
#: the two roots that touch there come out of subproblem 6 about the square root of
#: rounding apart
SNAP_PARALLEL = 1e-6
#: a planar shoulder's axis 5, turned by joint 4, counts as along its parallel axes within
#: this sine: there subproblem 1 gives the planar turn only to rounding, and the turn is
#: a representative of the continuum (kincalc.ik.five_joints)
ALONG_PARALLEL = 1e-9

#: a rotation matrix the user gives (a pose, ``--matrix``, a robot file's base or tool) is one
#: when ``R R^T`` is the identity to this, entrywise, with ``det R > 0``: rounding every entry
#: to 6 decimals moves ``R R^T`` by up to ``2 sqrt(3) 5e-7 = 1.7e-6``
ROTATION_TOL = 2e-6
#: a rotation matrix orthonormal to this (entrywise) is one to rounding, kept as given: a
#: product of a few rotations, as FK makes, is some 1e-16 off
ORTHONORMAL = 1e-14
