"""kincalc: a robot kinematics calculator.

Conventions used everywhere in kincalc
--------------------------------------
* Units: inside the core, metres and radians. Robot files and the CLI use the
  user's units (``units:`` block, ``--deg/--rad``, ``--unit``); conversion
  happens only in :mod:`kincalc.conventions.reader`, :mod:`kincalc.analysis.results` and
  :mod:`kincalc.cli`. Unitless textbook robots carry their numbers as-is.
* Frames: ``T_a_b`` is the pose of frame b in frame a (it maps b coordinates
  to a coordinates). ``fk`` returns ``T_world_tool = base · T_0^n · tool``.
* DH: ``dh`` is standard (distal) DH, ``A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``;
  ``mdh`` is modified (proximal, Craig) DH,
  ``A_i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i)``; ``poe`` is the product of
  exponentials with joint axes and points given at q = 0.
* Orientation: RPY are fixed X-Y-Z angles, ``R = Rz(yaw) Ry(pitch) Rx(roll)``;
  ZYZ Euler ``R = Rz(a) Ry(b) Rz(c)``; moving X-Y-Z Euler ``R = Rx(a) Ry(b) Rz(c)``.
  Quaternions are ``(w, x, y, z)`` with ``w >= 0``.
* Jacobians: rows ordered linear then angular ``(vx, vy, vz, wx, wy, wz)``;
  ``jacobian(q, frame='base')`` gives the tool point's velocity in the world
  frame, ``frame='tool'`` the same in the tool frame.

Python API
----------
>>> import kincalc
>>> robot = kincalc.load_robot("puma560")
>>> T = robot.fk([0, 0, 0, 0, 0, 0])          # (4, 4), metres
>>> J = robot.jacobian([[0.1] * 6] * 10)      # (10, 6, 6): batched
"""

from .version import __version__  # noqa: E402

__all__ = ["load_robot", "parse_robot_text", "Robot", "Joint", "KincalcError",
           "fk_report", "jacobian_report", "__version__"]


def __getattr__(name):
    # Lazy: importing kincalc (for the CLI's --help) must not import numpy.
    if name == "load_robot":
        from .conventions.library import load
        return load
    if name == "parse_robot_text":
        from .conventions.reader import parse_robot_text
        return parse_robot_text
    if name in ("Robot", "Joint"):
        from . import model
        return getattr(model, name)
    if name == "KincalcError":
        from .errors import KincalcError
        return KincalcError
    if name in ("fk_report", "jacobian_report"):
        from . import analysis
        return getattr(analysis, name)
    raise AttributeError(f"module 'kincalc' has no attribute {name!r}")
