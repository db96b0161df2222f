"""Track and wheelset: where the rails and wheels stand in track axes, the wheelset's pose and velocities
(docs/physics.md, Wheel/rail geometry: track and wheelset).

Track axes: x along the track in the direction of travel, y lateral to the right, z downward (right-handed; the
Manchester Contact Benchmark's and CONTACT's axes).  The profiles describe the RIGHT wheel and rail in their own axes
(:mod:`rollcontact.wheelrail.profiles`); the left ones are their mirror images ``y -> -y``.

* Rails: the right rail's profile, turned by its inclination towards the track centre, stands with its top (the
  least z of the head) at z = 0 and its gauge face, ``gauge_height`` below the top, at ``y = gauge / 2``.
* Wheelset: the axle's centre C = (0, y_ws, z_ws) with ``z_ws = -r0 + dz`` (dz = ``Pose.vertical``, positive down:
  at dz = 0 and no roll the taping-line circles touch the plane z = 0 of the rail tops); orientation
  ``R = R_z(yaw) R_x(roll)``.  The right wheel's profile point (y_w, z_w) is the circle of radius
  ``r = r0 + z_w`` about the axle at the axle's lateral coordinate ``Y = Y_t + y_w``, ``Y_t = flange_back_spacing/2
  + flange_back_distance`` (the taping line); the left wheel's at ``Y = -(Y_t + y_w)``.
* Positive lateral shift moves the wheelset towards the right rail, positive yaw turns its front to the right,
  roll is by the right-hand rule about x (positive roll lowers the right wheel), the pitch rate is negative for
  forward rolling.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rollcontact.core.checks import check_real
from rollcontact.wheelrail.profiles import Profile, ProfileError

__all__ = ["GeometryError", "MAX_SURFACE_ANGLE", "SEARCH_STRIDE", "Pose", "Track", "Velocities", "Wheelset"]

MAX_SURFACE_ANGLE = 1.40
"""The steepest surface [rad] (80 deg from the horizontal) the contact search considers: samples of the profiles
steeper than this (a rail's vertical flanks below the gauge corner, a wheel's flange back) are left out.  A flange
climbing onto them is reported (:class:`GeometryError`)."""


SEARCH_STRIDE = 2
"""The contact search's pass takes every SEARCH_STRIDE-th sample of both profiles (0.2 mm of arc length at the
default sampling; contiguous copies are kept): its Hermite interpolation keeps the minima within a micrometre of a
search on all samples, and the quantities at each point are interpolated on all samples."""


class GeometryError(ValueError):
    """A contact geometry that cannot be computed: the message names the value and the limit."""


@dataclass(frozen=True, eq=False)
class RailSamples:
    """The right rail in track axes (arrays over the rail's samples, surface angle within MAX_SURFACE_ANGLE)."""

    y: np.ndarray          # Y [m], strictly increasing
    z: np.ndarray          # Z [m]
    slope: np.ndarray      # dZ/dY
    angle: np.ndarray      # atan(dZ/dY) [rad]
    curvature: np.ndarray  # [1/m], positive convex (bending towards +z)
    profile_y: np.ndarray  # y on the rail profile, its own axes [m]

    def __post_init__(self):
        object.__setattr__(self, "coarse", tuple(np.ascontiguousarray(a[::SEARCH_STRIDE])
                                                 for a in (self.y, self.z, self.slope)))


@dataclass(frozen=True, eq=False)
class Track:
    """Straight track: two rails of one profile, mirror images of each other.

    Parameters
    ----------
    rail : Profile
        The right rail's profile in its own axes (gauge side at negative y).
    gauge : float
        Track gauge [m] between the gauge faces, measured ``gauge_height`` below the rail tops.
    gauge_height : float
        [m] below the rail top where the gauge is measured (14 mm in Europe).
    inclination : float
        Cant of each rail towards the track centre [rad] (1:40: ``atan(1/40)``); 0 when the profile is already
        canted (as the shared UIC60 is).
    """

    rail: Profile
    gauge: float = 1.435
    gauge_height: float = 0.014
    inclination: float = 0.0
    samples: RailSamples = field(init=False, repr=False)
    rail_offset: float = field(init=False)
    top: float = field(init=False)

    def __post_init__(self):
        if not isinstance(self.rail, Profile):
            raise GeometryError(f"rail must be a Profile, got {type(self.rail).__name__}")
        object.__setattr__(self, "gauge", check_real("gauge", self.gauge, lower=0.5, upper=3.0, unit="m"))
        object.__setattr__(self, "gauge_height",
                           check_real("gauge_height", self.gauge_height, lower=0.0, upper=0.05, unit="m"))
        object.__setattr__(self, "inclination",
                           check_real("inclination", self.inclination, lower=-0.2, upper=0.2, unit="rad"))
        smp = self.rail.samples
        c, s = math.cos(-self.inclination), math.sin(-self.inclination)  # cant towards -y (the track centre)
        y = c * smp.y - s * smp.z
        z = s * smp.y + c * smp.z
        angle = smp.angle - self.inclination
        top = float(np.min(z))
        k_top = int(np.argmin(z))
        depth = z - top
        gauge_side = np.nonzero(depth[:k_top + 1] >= self.gauge_height)[0]
        if gauge_side.size == 0:
            raise GeometryError(f"{self.rail.source}: the rail profile reaches {depth[0]!r} m below its top on the "
                                f"gauge side, less than gauge_height = {self.gauge_height!r} m")
        k = int(gauge_side[-1])
        f = (self.gauge_height - depth[k + 1]) / (depth[k] - depth[k + 1])
        y_gauge = y[k + 1] + f * (y[k] - y[k + 1])
        offset = 0.5 * self.gauge - y_gauge
        keep = np.abs(angle) <= MAX_SURFACE_ANGLE
        first, last = np.nonzero(keep)[0][[0, -1]]
        part = slice(int(first), int(last) + 1)
        if not keep[part].all():
            raise GeometryError(f"{self.rail.source}: the rail head is steeper than {MAX_SURFACE_ANGLE} rad inside "
                                "its running surface (near y = "
                                f"{float(smp.y[part][~keep[part]][0])!r} m)")
        if np.any(np.diff(y[part]) <= 0.0):
            raise GeometryError(f"{self.rail.source}: the inclined rail folds back (inclination "
                                f"{self.inclination!r} rad)")
        object.__setattr__(self, "samples", RailSamples(y[part] + offset, z[part] - top, np.tan(angle[part]),
                                                        angle[part], smp.curvature[part], smp.y[part]))
        object.__setattr__(self, "rail_offset", offset)
        object.__setattr__(self, "top", top)

    def rail_points(self, side: str = "right") -> tuple[np.ndarray, np.ndarray]:
        """The rail's surface (Y, Z) [m] in track axes (the running surface the search uses)."""
        sign = side_sign(side)
        return sign * self.samples.y, self.samples.z


@dataclass(frozen=True, eq=False)
class WheelSamples:
    """The right wheel's profile samples within MAX_SURFACE_ANGLE (arrays; the profile's own axes)."""

    y: np.ndarray          # y_w [m], strictly increasing
    radius: np.ndarray     # r = r0 + z_w [m]
    cos: np.ndarray        # cos(alpha), alpha = atan(dz_w/dy_w)
    sin: np.ndarray        # sin(alpha)
    tan: np.ndarray        # tan(alpha)
    axle: np.ndarray       # Y = Y_t + y_w [m], the axle's lateral coordinate of the circle
    curvature: np.ndarray  # [1/m] of the profile, positive where it bends towards +z (concave for a wheel)

    def __post_init__(self):
        object.__setattr__(self, "coarse", {name: np.ascontiguousarray(getattr(self, name)[::SEARCH_STRIDE])
                                            for name in ("y", "radius", "cos", "sin", "tan", "axle")})


@dataclass(frozen=True, eq=False)
class Wheelset:
    """A rigid wheelset with two wheels of one profile, mirror images of each other.

    Parameters
    ----------
    wheel : Profile
        The right wheel's profile in its own axes (flange at negative y, z away from the axle, taping line at y = 0).
    nominal_radius : float
        r0 [m], the rolling radius at the taping line (the profile's z = 0).
    flange_back_spacing : float
        [m] between the two wheels' flange backs.
    flange_back_distance : float
        [m] from the taping line to the flange back along the axle (70 mm for the S1002 file of the Manchester
        benchmark).

    Attributes
    ----------
    flange_tip : float
        y_w [m] of the flange's crest on the wheel profile (its largest radius on the flange side, y_w < 0).
    """

    wheel: Profile
    nominal_radius: float = 0.46
    flange_back_spacing: float = 1.360
    flange_back_distance: float = 0.070
    samples: WheelSamples = field(init=False, repr=False)
    steepest: float = field(init=False, repr=False)
    flange_tip: float = field(init=False, repr=False)

    def __post_init__(self):
        if not isinstance(self.wheel, Profile):
            raise GeometryError(f"wheel must be a Profile, got {type(self.wheel).__name__}")
        object.__setattr__(self, "nominal_radius",
                           check_real("nominal_radius", self.nominal_radius, lower=0.05, upper=5.0, unit="m"))
        object.__setattr__(self, "flange_back_spacing",
                           check_real("flange_back_spacing", self.flange_back_spacing, lower=0.3, upper=3.0, unit="m"))
        object.__setattr__(self, "flange_back_distance",
                           check_real("flange_back_distance", self.flange_back_distance, lower=0.0, upper=0.2,
                                      unit="m"))
        smp = self.wheel.samples
        keep = np.abs(smp.angle) <= MAX_SURFACE_ANGLE
        radius = self.nominal_radius + smp.z
        if np.any(radius[keep] <= 0.0):
            raise GeometryError(f"{self.wheel.source}: nominal_radius = {self.nominal_radius!r} m gives a radius "
                                f"{float(np.min(radius[keep]))!r} m <= 0 on the profile")
        object.__setattr__(self, "samples", WheelSamples(smp.y[keep], radius[keep], np.cos(smp.angle[keep]),
                                                         np.sin(smp.angle[keep]), np.tan(smp.angle[keep]),
                                                         self.taping_line + smp.y[keep],
                                                         smp.curvature[keep]))
        object.__setattr__(self, "steepest", float(np.max(np.abs(self.samples.tan))))
        flange = smp.y < 0.0
        tip = float(smp.y[flange][np.argmax(smp.z[flange])]) if flange.any() else float(smp.y[0])
        object.__setattr__(self, "flange_tip", tip)

    @property
    def taping_line(self) -> float:
        """Y_t [m]: the axle's lateral coordinate of the right wheel's taping line."""
        return 0.5 * self.flange_back_spacing + self.flange_back_distance


@dataclass(frozen=True)
class Pose:
    """The wheelset's position on the track (module docstring for the axes).

    Parameters
    ----------
    lateral_shift : float
        y_ws [m], towards the right rail positive.
    yaw : float
        psi [rad], the front turned to the right positive.
    roll : float
        phi [rad] about x (right-hand rule: positive lowers the right wheel).
    vertical : float
        dz [m], downward displacement of the axle from the height at which, without roll, the taping-line circles
        touch the plane of the rail tops.
    """

    lateral_shift: float = 0.0
    yaw: float = 0.0
    roll: float = 0.0
    vertical: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "lateral_shift",
                           check_real("lateral_shift", self.lateral_shift, lower=-0.1, upper=0.1, unit="m"))
        object.__setattr__(self, "yaw", check_real("yaw", self.yaw, lower=-0.2, upper=0.2, unit="rad"))
        object.__setattr__(self, "roll", check_real("roll", self.roll, lower=-0.1, upper=0.1, unit="rad"))
        object.__setattr__(self, "vertical", check_real("vertical", self.vertical, lower=-0.1, upper=0.1, unit="m"))

    def mirrored(self) -> Pose:
        """The mirror image in the track's x-z plane: the left wheel's problem seen as a right wheel's."""
        return Pose(-self.lateral_shift, -self.yaw, -self.roll, self.vertical)


@dataclass(frozen=True)
class Velocities:
    """The wheelset's velocities in track axes.

    Parameters
    ----------
    forward_speed : float
        V [m/s] > 0 along x.
    lateral_velocity : float
        dy_ws/dt [m/s].
    yaw_rate : float
        dpsi/dt [rad/s].
    pitch_rate : float or None
        The wheelset's angular velocity about its axle [rad/s], negative for forward rolling; None: ``-V / r0``
        (pure rolling at the nominal radius).
    roll_rate : float
        dphi/dt [rad/s].
    vertical_velocity : float
        dz_ws/dt [m/s] (downward).
    """

    forward_speed: float
    lateral_velocity: float = 0.0
    yaw_rate: float = 0.0
    pitch_rate: float | None = None
    roll_rate: float = 0.0
    vertical_velocity: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "forward_speed",
                           check_real("forward_speed", self.forward_speed, lower=0.0, lower_open=True, unit="m/s"))
        for name in ("lateral_velocity", "yaw_rate", "roll_rate", "vertical_velocity"):
            object.__setattr__(self, name, check_real(name, getattr(self, name)))
        if self.pitch_rate is not None:
            object.__setattr__(self, "pitch_rate", check_real("pitch_rate", self.pitch_rate, unit="rad/s"))


def side_sign(side: str) -> float:
    """+1 for ``"right"``, -1 for ``"left"``."""
    if side == "right":
        return 1.0
    if side == "left":
        return -1.0
    raise GeometryError(f"side = {side!r} must be 'left' or 'right'")


__all__ += ["ProfileError", "side_sign"]
