"""Rotations and rigid transforms, batched over leading axes.

Conventions (see also the package docstring):

* A rotation matrix ``R_a_b`` has shape ``(..., 3, 3)`` and maps vectors in
  frame b to frame a; a transform ``T_a_b`` has shape ``(..., 4, 4)`` and is
  the pose of frame b in frame a.
* Angles are in radians, lengths in metres (or in the robot's own unit for
  unitless robots); nothing here converts units.
* RPY means fixed-axis X-Y-Z angles ``(roll, pitch, yaw)`` with
  ``R = Rz(yaw) @ Ry(pitch) @ Rx(roll)`` (Craig, *Introduction to Robotics*,
  3rd ed., sec. 2.8, "X-Y-Z fixed angles").
* ZYZ Euler angles ``(a, b, c)`` mean ``R = Rz(a) @ Ry(b) @ Rz(c)``; moving
  X-Y-Z Euler angles ("1-2-3") mean ``R = Rx(a) @ Ry(b) @ Rz(c)``.
* Quaternions are ``(w, x, y, z)``, scalar first, returned with ``w >= 0``.
* Twists and Jacobian rows are ordered linear then angular ``(v, w)``.

Every function accepts any number of leading batch dimensions, returns new
arrays and never writes into its arguments.

The room is four modules: :mod:`~kincalc.spatial.rotations` (rotation matrices and their
vector forms), :mod:`~kincalc.spatial.angles` (RPY and Euler angles),
:mod:`~kincalc.spatial.orthonormal` (is it a rotation, the nearest one) and
:mod:`~kincalc.spatial.transforms` (rigid transforms); every name is imported from here.
"""

from .angles import (euler_xyz_from_matrix, euler_zyz_from_matrix, matrix_from_euler_xyz,
                     matrix_from_euler_zyz, matrix_from_rpy, rpy_from_matrix)
from .orthonormal import is_rotation, nearest_rotations, orthonormality_error
from .rotations import (LEVI_CIVITA, TURN, axis_angle_from_matrix, cross,
                        matrix_from_axis_angle,
                        matrix_from_quaternion, matrix_from_rotvec, 
                        quaternion_from_matrix, rot_x, rot_y, rot_z, rotation_angle,
                        rotation_error, rotvec_from_matrix, skew, turn_toward, wrap,
                        into_limits, into_turn)
from .transforms import (TCV_MAX_ROLL, adjoint, invert_transform, log_transform,
                         tcv_from_transform, transform, transform_from_tcv)

__all__ = [
    "wrap", "turn_toward", "into_limits", "into_turn", "TURN", "TCV_MAX_ROLL", "LEVI_CIVITA",
    "rot_x", "rot_y", "rot_z", "transform", "invert_transform", "cross", "skew",
    "matrix_from_rpy", "rpy_from_matrix",
    "matrix_from_euler_zyz", "euler_zyz_from_matrix",
    "matrix_from_euler_xyz", "euler_xyz_from_matrix",
    "quaternion_from_matrix", "matrix_from_quaternion",
    "axis_angle_from_matrix", "matrix_from_axis_angle",
    "rotvec_from_matrix", "matrix_from_rotvec",
    "tcv_from_transform", "transform_from_tcv",
    "log_transform", "adjoint", "rotation_error", "rotation_angle",
    "is_rotation", "nearest_rotations", "orthonormality_error",
]
