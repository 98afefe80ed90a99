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
