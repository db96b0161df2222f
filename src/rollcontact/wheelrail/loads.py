"""The loads of the rails on a wheelset: its contact forces summed in track axes, their moments about its centre, and
what a vehicle model reads per wheel (docs/physics.md, "The wheelset's loads").

Track axes (docs/physics.md, Wheel/rail geometry: axes): x along the track in the direction of travel, y to the right,
z downward.  The wheel/rail levels report the forces the WHEEL EXERTS ON THE RAIL; the loads here are those the rails
exert ON THE WHEELSET, their negatives.  A patch with the normal force N, the tangential forces Fx (along x) and Fs
(along its contact plane's lateral axis ``s = (0, cos(delta), -sign sin(delta))``) and the spin moment Mz about its
normal ``n = (0, sign sin(delta), cos(delta))`` (sign +1 right, -1 left; :mod:`rollcontact.wheelrail.wheels`) loads the
wheelset with

    F = -(Fx e_x + Fs s + N n),        M = d x F - Mz n,

d the wheel's material point in the patch relative to the wheelset's centre C (the lever of
:func:`~rollcontact.wheelrail.search.creepages`).  The force and moment on the wheelset are the sums over both wheels'
patches; per wheel the sums of its patches' normal forces and of the track components of F, the contact angle and
rolling radius of its largest patch, its number of patches and the frictional power ``V (xi Fx + eta Fs + phi Mz)``
its creepages put into the contacts (the T-gamma of wear models, times V), >= 0 in steady rolling.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from rollcontact.wheelrail.geometry import side_sign

__all__ = ["WHEEL_FIELDS", "WheelsetLoads", "wheelset_loads"]

WHEEL_FIELDS = ("normal_force", "longitudinal_force", "lateral_force", "vertical_force", "contact_angle",
                "rolling_radius", "patches", "frictional_power")
"""Per wheel (left, then right), the fields of :class:`WheelsetLoads` after the wheelset's: the normal force [N] (the
sum over its patches), the track x, y and z components [N] of the rails' force on it, the contact angle [rad]
(positive towards the flange on both wheels) and rolling radius [m] of its largest patch (0 without contact), its
number of patches, and its frictional power [W]."""


class WheelsetLoads(NamedTuple):
    """The rails' loads on the wheelset (SI units, track axes; module docstring)."""

    force_x: float
    force_y: float
    force_z: float
    moment_roll: float
    moment_pitch: float
    moment_yaw: float
    normal_force_left: float
    longitudinal_force_left: float
    lateral_force_left: float
    vertical_force_left: float
    contact_angle_left: float
    rolling_radius_left: float
    patches_left: int
    frictional_power_left: float
    normal_force_right: float
    longitudinal_force_right: float
    lateral_force_right: float
    vertical_force_right: float
    contact_angle_right: float
    rolling_radius_right: float
    patches_right: int
    frictional_power_right: float


def patch_load(sign: float, delta: float, lever, normal, fx, fs, mz):
    """The force and moment (about the centre) of one patch on the wheelset, and its force in track axes on the rail
    (module docstring): ``((Fx, Fy, Fz), (Mx, My, Mz))`` on the wheelset."""
    sd, cd = math.sin(delta), math.cos(delta)
    ny, nz = sign * sd, cd
    fy_rail = fs * cd + normal * ny
    fz_rail = -fs * sign * sd + normal * nz
    force = (-fx, -fy_rail, -fz_rail)
    dx, dy, dz = lever
    moment = (dy * force[2] - dz * force[1], dz * force[0] - dx * force[2] - mz * ny,
              dx * force[1] - dy * force[0] - mz * nz)
    return force, (moment[0], moment[1], moment[2])


def wheelset_loads(scene, result) -> WheelsetLoads:
    """The loads of a :class:`~rollcontact.wheelrail.result.WheelRailResult` of ``scene`` (a
    :class:`~rollcontact.wheelrail.scene.WheelRailScene`) on the wheelset (module docstring): each patch's lever from
    its contact point at the scene's pose, as :func:`~rollcontact.wheelrail.search.creepages` takes it."""
    pose = scene.pose
    centre_z = pose.vertical - scene.wheelset.nominal_radius
    speed = scene.forward_speed
    total = [0.0] * 6
    wheels = []
    for wheel in result.wheels:
        sign = side_sign(wheel.side)
        sums = [0.0, 0.0, 0.0, 0.0]  # normal, track x, y, z
        power = 0.0
        for patch in wheel.patches:
            point, res = patch.point, patch.result
            px, py, pz = point.position
            lever = (px, py - pose.lateral_shift, pz - point.vertical_gap - centre_z)
            force, moment = patch_load(sign, point.contact_angle, lever, res.normal_load, res.longitudinal_force,
                                       res.lateral_force, res.spin_moment)
            for i in range(3):
                total[i] += force[i]
                total[3 + i] += moment[i]
                sums[1 + i] += force[i]
            sums[0] += res.normal_load
            power += speed * (res.longitudinal_creepage * res.longitudinal_force
                              + res.lateral_creepage * res.lateral_force + res.spin_creepage * res.spin_moment)
        largest = wheel.patches[0].point if wheel.patches else None
        wheels += [*sums, largest.contact_angle if largest else 0.0, largest.rolling_radius if largest else 0.0,
                   len(wheel.patches), power]
    return WheelsetLoads(*total, *wheels)
