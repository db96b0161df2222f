"""A wheelset's contact from its contact-geometry table: one Hertzian contact per wheel at the tabulated deepest
point, Kalker's linear theory (saturated or not) for its creep forces, and the loads on the wheelset, in float
arithmetic fit for a co-simulation step (docs/physics.md, "The wheelset from a geometry table").

Geometry.  The rigid wheelset's pose (roll, height) and each wheel's deepest contact point (contact angle delta,
rolling radius r, lateral position y_w on the wheel profile, curvatures) are the :class:`~rollcontact.wheelrail.
conicity.ContactTable` lookup at the lateral shift (one yaw node: the yaw enters the kinematics, not the geometry).
What depends on the geometry alone is computed at every node once and interpolated with the table's weights: Hertz's
ellipse under 1 N (``a_1``, ``b_1``, the approach ``delta_1``, the perimeter ``P_1``) from the gap curvatures
``A = cos(alpha) / (2 r)``, ``B = max((k_wheel + k_rail) / 2, MIN_LATERAL_CURVATURE)``, and Kalker's coefficients
C11 ... C33 at its a/b (beyond Kalker's rows the table's rows beyond them,
:func:`~rollcontact.elliptic.creep_coefficients.extended_creepage_coefficients`).  Under the normal force N Hertz's
ellipse scales as ``a = a_1 N^(1/3)``, ``b = b_1 N^(1/3)``, ``delta = delta_1 N^(2/3)`` (Johnson, *Contact
Mechanics*, 1985, section 4.2).

Kinematics.  The wheel's material point at the contact is the lowest point of its circle, ``d = R_z(psi) R_x(phi)
(0, Y, r)`` from the wheelset's centre in the wheel's right-side frame (``Y = Y_t + y_w``; the left wheel's
mirrored), and the creepages are those of :func:`~rollcontact.wheelrail.search.creepages` at it (Kalker's, the rigid
slip of the wheel relative to the rail over V, in the contact frame).

Normal and tangential contact per wheel, as :mod:`rollcontact.wheelrail.methods.hertz` does for one contact point:
``N = Q / (cos(delta) + rho)`` carries the vertical load Q, with ``rho = T_z / N`` (``T_z = -sign sin(delta) Fs`` the
tangential force's vertical component) first of the saturated theory under ``Q / cos(delta)``
(:func:`~rollcontact.wheelrail.wheels.predicted_ratio`); where the wheel's vertical force ``N cos(delta) + T_z``
misses Q by more than :data:`~rollcontact.wheelrail.wheels.COUPLING` of it (a flange), the next pass takes the
ratio of the last (at most :data:`~rollcontact.wheelrail.wheels.PASSES`).  The forces are Kalker's linear theory
on the ellipse (``Fx = G c^2 C11 xi``, ``Fs = G c^2 (C22 eta + c C23 phi)``, ``Mz = G c^3 (-C23 eta + c C33 phi)``,
c = sqrt(ab)), with ``law = "saturated"`` scaled by Shen, Hedrick & Elkins' ``g(u)/u`` as
:mod:`rollcontact.elliptic.methods.saturated` scales them.  The loads on the wheelset follow as
:mod:`rollcontact.wheelrail.loads` states them.

Where the profiles touch at two points (the two-lobed tread of S1002 on UIC60 within about 0.2 mm of the centre, the
transitions to the flange root and the flange over some tens of micrometres) the table's single point carries the
whole load: the contact searched afresh shares it (:mod:`rollcontact.wheelrail.methods.hertz`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ellipe

from rollcontact.core.friction import FrictionLaw
from rollcontact.core.materials import Material
from rollcontact.elliptic.creep_coefficients import extended_creepage_coefficients
from rollcontact.elliptic.hertz import hertz_ellipse
from rollcontact.wheelrail.conicity import QUANTITIES, ContactTable
from rollcontact.wheelrail.geometry import GeometryError, Wheelset
from rollcontact.wheelrail.loads import WheelsetLoads
from rollcontact.wheelrail.normal import MIN_LATERAL_CURVATURE
from rollcontact.wheelrail.wheels import COUPLING, PASSES

__all__ = ["LAWS", "NODE_CONSTANTS", "TabulatedWheelset"]

LAWS = ("linear", "saturated")
"""The creep-force laws of a tabulated wheelset: Kalker's linear theory, and the same saturated at mu Fn."""

NODE_CONSTANTS = ("a1", "b1", "approach1", "perimeter1", "c11", "c22", "c23", "c33")
"""Per wheel, what each node adds to the table's :data:`~rollcontact.wheelrail.conicity.QUANTITIES`: Hertz's semi-axes
[m], approach [m] and perimeter [m] under 1 N, Kalker's coefficients [1] at its a/b."""

SIDES = (("left", -1.0), ("right", 1.0))
COLUMN = {name: k for k, name in enumerate(QUANTITIES)}
CONSTANT = {(side, name): len(QUANTITIES) + 8 * s + k
            for s, (side, _) in enumerate(SIDES) for k, name in enumerate(NODE_CONSTANTS)}


def node_constants(values, side: str, material: Material) -> list[float]:
    """:data:`NODE_CONSTANTS` of one wheel at a node (``values`` its :data:`QUANTITIES`)."""
    q = dict(zip(QUANTITIES, values, strict=True))
    a_curv = 0.5 * q[f"{side}_wheel_rolling_curvature"]
    b_curv = max(0.5 * (q[f"{side}_wheel_lateral_curvature"] + q[f"{side}_rail_lateral_curvature"]),
                 MIN_LATERAL_CURVATURE)
    unit = hertz_ellipse(1.0, a_curv, b_curv, material.contact_modulus)
    major, minor = max(unit.a, unit.b), min(unit.a, unit.b)
    perimeter = 4.0 * major * float(ellipe(1.0 - (minor / major) ** 2))
    c = extended_creepage_coefficients(unit.aspect_ratio, material.poisson_ratio)
    return [unit.a, unit.b, unit.approach, perimeter, c.c11, c.c22, c.c23, c.c33]


@dataclass(frozen=True, eq=False)
class TabulatedWheelset:
    """A wheelset's contact through its geometry table (module docstring).

    Parameters
    ----------
    table : ContactTable
        The rigid wheelset's contact functions over the lateral shift, one yaw node
        (:meth:`ContactTable.build <rollcontact.wheelrail.conicity.ContactTable.build>` with ``yaws=(0.0,)``).
    wheelset : Wheelset
        The wheelset the table was built for (its nominal radius and taping line).
    material : Material
        Elastic constants of wheel and rail.
    friction : FrictionLaw
        The saturated law's bound is ``friction.maximum_coefficient`` times N.
    law : str
        One of :data:`LAWS`.
    """

    table: ContactTable
    wheelset: Wheelset
    material: Material
    friction: FrictionLaw
    law: str = "saturated"

    def __post_init__(self):
        if self.law not in LAWS:
            raise ValueError(f"law = {self.law!r} is unknown: use one of {', '.join(LAWS)}")
        if self.table.yaws.size != 1:
            raise GeometryError(f"a tabulated wheelset needs a table of one yaw node, got {self.table.yaws.size}")
        rows = self.table.rows
        extra = [[v for side, _ in SIDES for v in node_constants(row, side, self.material)] for row in rows.tolist()]
        object.__setattr__(self, "values", np.ascontiguousarray(np.hstack([rows, np.array(extra)])))
        object.__setattr__(self, "shear_modulus", self.material.shear_modulus)

    @property
    def lateral_range(self) -> tuple[float, float]:
        """The lateral shifts [m] the table covers."""
        shift = self.table.functions[0].shift
        return float(shift[0]), float(shift[-1])

    def row(self, lateral_shift: float, shift: float | None = None) -> tuple[list[float], list[float] | None]:
        """The node values interpolated at the lateral shift [m] (:data:`QUANTITIES`, then :data:`NODE_CONSTANTS`
        of the left and right wheels), and with ``shift`` [m] also at ``lateral_shift + shift`` continued within the
        segment (the same two nodes: never across a jump; else None); GeometryError outside the table."""
        k, t, width = self.table.locate(lateral_shift)
        v0 = self.values[k]
        step = self.values[k + 1] - v0
        return (v0 + t * step).tolist(), None if shift is None else (v0 + (t + shift / width) * step).tolist()

    def creep_coefficients(self, row, side: str, load: float) -> tuple[float, float, float, float]:
        """Kalker's linear creep coefficients ``(G c^2 C11, G c^2 C22, G c^3 C23, G c^4 C33)`` [N, N, N m, N m^2] of
        the ``side`` wheel's contact at the interpolated ``row`` (:meth:`row`) under the vertical load [N] > 0
        (``N = Q / cos(delta)``)."""
        base = CONSTANT[side, "a1"]
        a1, b1, _, _, c11, c22, c23, c33 = row[base:base + 8]
        normal = load / math.cos(row[COLUMN[f"{side}_contact_angle"]])
        c = math.sqrt(a1 * b1) * normal ** (1.0 / 3.0)
        area = self.shear_modulus * c * c
        return area * c11, area * c22, area * c * c23, area * c * c * c33

    def loads(self, row, yaw: float, lateral_velocity: float, yaw_rate: float, forward_speed: float,
              pitch_rate: float, load_left: float, load_right: float, full: bool = True):
        """The loads on the wheelset (:class:`~rollcontact.wheelrail.loads.WheelsetLoads`, track axes), its roll
        [rad] and vertical position [m] (``Pose.vertical`` of the loaded wheelset: the rigid one's plus the mean
        elastic approach of the loaded wheels, vertically) at the interpolated ``row`` (:meth:`row`) and the inputs
        (yaw [rad], lateral velocity [m/s], yaw rate [rad/s], V [m/s] > 0, pitch rate [rad/s], the wheels' vertical
        loads Q [N] >= 0).  Without ``full`` only ``(force_y, moment_yaw)`` (what the derivatives need)."""
        roll = row[0]
        taping = self.wheelset.taping_line
        shear = self.shear_modulus
        mu = self.friction.maximum_coefficient
        saturated = self.law == "saturated"
        sin, cos, sqrt, hypot = math.sin, math.cos, math.sqrt, math.hypot
        cpsi, spsi = cos(yaw), sin(yaw)
        cphi, sphi = cos(roll), sin(roll)
        om0, om1, om2 = -pitch_rate * spsi * cphi, pitch_rate * cpsi * cphi, pitch_rate * sphi + yaw_rate
        fx_sum = fy_sum = fz_sum = mx_sum = my_sum = mz_sum = 0.0
        wheels = []
        approach_sum, loaded = 0.0, 0
        for (sign, angle, radius_at, lateral_at, base), load in zip(WHEELS, (load_left, load_right), strict=True):
            if load == 0.0:
                wheels += NO_WHEEL
                continue
            a1, b1, approach1, perimeter1, c11, c22, c23, c33 = row[base:base + 8]
            delta = row[angle]
            radius = row[radius_at]
            axle = taping + row[lateral_at]
            # the lever d = R_z(psi_f) R_x(phi_f) (0, Y, r) in the wheel's right-side frame, mirrored for the left
            sf = sign * sphi
            v = axle * cphi - radius * sf
            dx = -v * sign * spsi
            dy = sign * v * cpsi
            dz = axle * sf + radius * cphi
            vz = om0 * dy - om1 * dx
            sd, cd = sin(delta), cos(delta)
            ny = sign * sd
            xi = (forward_speed + om1 * dz - om2 * dy) / forward_speed
            eta = ((lateral_velocity + om2 * dx - om0 * dz) * cd - vz * ny) / forward_speed
            phi = (om1 * ny + om2 * cd) / forward_speed
            c1 = sqrt(a1 * b1)
            # the first pass's ratio: the saturated theory's under Q / cos(delta) (wheels.predicted_ratio)
            normal = load / cd
            c = c1 * normal ** (1.0 / 3.0)
            area = shear * c * c
            fx = area * c11 * xi
            fs = area * (c22 * eta + c * c23 * phi)
            u = ratio_of(hypot(fx, fs), mu * normal)
            ratio = -fs * (1.0 / u if u >= 3.0 else 1.0 - u / 3.0 + u * u / 27.0) * ny / normal
            for _ in range(PASSES):
                normal = load / (cd + ratio)
                scale = normal ** (1.0 / 3.0)
                c = c1 * scale
                area = shear * c * c
                fx = area * c11 * xi
                fs = area * (c22 * eta + c * c23 * phi)
                cross = -area * c * c23 * eta
                spin = area * c * c * c33 * phi if phi != 0.0 else 0.0
                if saturated:  # a load so small that a bound underflows to 0: deep in saturation (u, w infinite)
                    bound = mu * normal
                    u = ratio_of(hypot(fx, fs), bound)
                    factor = 1.0 / u if u >= 3.0 else 1.0 - u / 3.0 + u * u / 27.0
                    fx *= factor
                    fs *= factor
                    w = ratio_of(abs(spin), bound * 0.09375 * perimeter1 * scale)
                    mz = factor * factor * cross + (1.0 / w if w >= 3.0 else 1.0 - w / 3.0 + w * w / 27.0) * spin
                else:
                    mz = cross + spin
                vertical_tangential = -fs * ny
                if abs(normal * cd + vertical_tangential - load) <= COUPLING * load:
                    break
                ratio = vertical_tangential / normal
                if not cd + ratio > 0.0:  # the tangential force would carry the load: no normal force does
                    raise ValueError(
                        f"the {'left' if sign < 0 else 'right'} wheel's lateral force of the {self.law} theory, "
                        f"{fs!r} N at the contact angle {delta!r} rad, would carry more than its vertical load "
                        f"{load!r} N (the linear theory has no friction limit: the saturated one has)")
            f0, f1, f2 = -fx, -(fs * cd + normal * ny), -(vertical_tangential + normal * cd)
            fy_sum += f1
            mz_sum += dx * f1 - dy * f0 - mz * cd
            if full:
                fx_sum += f0
                fz_sum += f2
                mx_sum += dy * f2 - dz * f1
                my_sum += dz * f0 - dx * f2 - mz * ny
                wheels += (normal, f0, f1, f2, delta, radius, 1, forward_speed * (xi * fx + eta * fs + phi * mz))
                approach_sum += approach1 * scale * scale / cd
                loaded += 1
        if not full:
            return fy_sum, mz_sum
        vertical = row[1] + (approach_sum / loaded if loaded else 0.0)
        return new_tuple(WheelsetLoads, (fx_sum, fy_sum, fz_sum, mx_sum, my_sum, mz_sum, *wheels)), roll, vertical


def ratio_of(size: float, bound: float) -> float:
    """``size / bound`` of two numbers >= 0, infinite where only the bound underflows to 0 and 0 where both do."""
    return size / bound if bound > 0.0 else (math.inf if size > 0.0 else 0.0)


WHEELS = tuple((sign, COLUMN[f"{side}_contact_angle"], COLUMN[f"{side}_rolling_radius"],
                COLUMN[f"{side}_wheel_lateral"], CONSTANT[side, "a1"]) for side, sign in SIDES)
"""Per wheel (left, right): its sign and the row's columns of its contact angle, rolling radius, lateral position on
the wheel and first node constant."""

NO_WHEEL = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0, 0.0)
"""A lifted wheel's fields of :class:`~rollcontact.wheelrail.loads.WheelsetLoads`."""

new_tuple = tuple.__new__
