"""The answers of the wheel/rail contact: :class:`WheelRailResult`, one type for every wheel/rail level (both wheels,
each a :class:`WheelResult` of its patches), and :class:`PatchResult`, one patch's answer, the same for every patch
method.

Sign convention (docs/physics.md, Elliptic contact): forces and moment are those the WHEEL EXERTS ON THE RAIL, in the
patch's contact plane (x along the track, s across the patch), each positive for its creepage positive; ``Mz`` is
taken about the rigid contact point (``s = 0``, ``x = 0``).  Traction fields reuse the elliptic
:class:`~rollcontact.elliptic.result.TractionField` (its y is the patch's s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from rollcontact.elliptic.result import TractionField

__all__ = ["PatchResult", "TractionField", "WheelPatch", "WheelRailResult", "WheelResult"]


@dataclass(frozen=True)
class PatchResult:
    """Normal and tangential contact of one patch (SI units).

    Attributes
    ----------
    method : str
        The level that produced it (``"strips"``, ``"discretised"``).
    success : bool
        False when the method's assumptions failed or it did not converge; ``message`` says why, and the numbers
        must not be trusted.
    message : str
        Human-readable status.
    normal_load : float
        Fn [N].
    approach : float
        delta [m], the rigid interpenetration at the rigid contact point that the solution has.
    max_pressure : float
        The largest pressure [Pa].
    length : float
        The patch's extent along x [m] (twice its longest half-length).
    width : float
        The patch's extent across, along s [m].
    longitudinal_force, lateral_force : float
        Fx, Fy [N] the wheel exerts on the rail in the contact plane.
    spin_moment : float
        Mz [N m] about the rigid contact point, exerted by the wheel on the rail.
    longitudinal_creepage, lateral_creepage : float
        xi, eta [1].
    spin_creepage : float
        phi [1/m].
    friction_coefficient : float
        mu at zero slip velocity [1] (the normalisation of :attr:`force_coefficients`).
    area : float
        The contact area [m^2].
    fields : TractionField or None
        Pressure and traction on the method's points (``fields=True``).
    info : dict
        Method-specific extras; ``error_estimate`` (the estimated error of Fx, Fy over mu Fn and of Mz over
        mu Fn c, the largest), ``normal_error_estimate`` (relative error of Fn at a given approach, of the approach
        at a given load) and ``pressure_error_estimate`` (relative error of the peak pressure).
    """

    method: str
    success: bool
    message: str
    normal_load: float
    approach: float
    max_pressure: float
    length: float
    width: float
    longitudinal_force: float
    lateral_force: float
    spin_moment: float
    longitudinal_creepage: float
    lateral_creepage: float
    spin_creepage: float
    friction_coefficient: float
    area: float
    fields: TractionField | None = field(default=None, repr=False)
    info: dict = field(default_factory=dict, repr=False)

    @property
    def c(self) -> float:
        """``sqrt(area / pi)`` [m]: the length of Kalker's normalisation, sqrt(ab) on an ellipse."""
        return math.sqrt(self.area / math.pi)

    @property
    def force_coefficients(self) -> tuple[float, float, float]:
        """(Fx / (mu Fn), Fy / (mu Fn), Mz / (mu Fn c)) [1]; zeros without load."""
        scale = self.friction_coefficient * self.normal_load
        if not scale > 0.0:
            return 0.0, 0.0, 0.0
        return self.longitudinal_force / scale, self.lateral_force / scale, self.spin_moment / (scale * self.c)


@dataclass(frozen=True)
class WheelPatch:
    """One patch of a wheel in the wheel/rail answer: where it is and what it carries.

    Attributes
    ----------
    point : ContactPoint
        Its rigid contact point (the patch's deepest): contact angle, rolling radius, positions on wheel and rail
        (:class:`~rollcontact.wheelrail.search.ContactPoint`).
    result : PatchResult
        Its normal and tangential contact in the contact plane.
    track_force : tuple of float
        (Fx, Fy, Fz) [N]: the force the wheel exerts on the rail through the patch, in track axes.
    """

    point: object
    result: PatchResult
    track_force: tuple


@dataclass(frozen=True)
class WheelResult:
    """One wheel's answer (SI units, track axes; forces of the wheel on the rail).

    Attributes
    ----------
    side : str
        ``"left"`` or ``"right"``.
    patches : tuple of WheelPatch
        By decreasing normal force.
    vertical_load : float
        Q [N], the load the wheel was to carry.
    vertical_displacement : float
        d [m] the wheel is pressed down from the pose to carry it.
    force : tuple of float
        (Fx, Fy, Fz) [N], the patches' track forces summed; Fz is the vertical force it carries.
    message : str
        The state of contact.
    normal_states : tuple of (PatchGap, tuple)
        Per patch of the wheel's contact (in the order of its ``patches`` at the scene's pose,
        :class:`~rollcontact.wheelrail.search.WheelContact`), its gap and what the patch level kept of its normal
        solution after each pass (None where the patch carried nothing): what a solve on the same gaps starts from
        (``starts`` of :func:`~rollcontact.wheelrail.wheels.solve_wheels`); empty where the level keeps none
        (Hertz's) or the wheel carries no load or fails.
    """

    side: str
    patches: tuple
    vertical_load: float
    vertical_displacement: float
    force: tuple
    message: str
    normal_states: tuple = field(default=(), repr=False, compare=False)

    @property
    def in_contact(self) -> bool:
        """Whether the wheel carries load."""
        return any(p.result.normal_load > 0.0 for p in self.patches)


@dataclass(frozen=True)
class WheelRailResult:
    """The answer of every wheel/rail level: both wheels' patches and forces (SI units; track axes).

    Attributes
    ----------
    method : str
        The level that produced it.
    success : bool
        False when a patch's method failed or a wheel's load could not be carried; ``message`` says why.
    message : str
        Human-readable status.
    wheels : tuple of WheelResult
        (left, right).
    info : dict
        ``error_estimate`` (the largest of the patches': Fx, Fy over mu Fn, Mz over mu Fn c), with a tolerance also
        ``tolerance``, ``tolerance_met``, ``setting``; ``predicted_cost`` [s] where the dispatcher chose by cost.
    """

    method: str
    success: bool
    message: str
    wheels: tuple
    info: dict = field(default_factory=dict, repr=False)

    @property
    def left(self) -> WheelResult:
        return self.wheels[0]

    @property
    def right(self) -> WheelResult:
        return self.wheels[1]
