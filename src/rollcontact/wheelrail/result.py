"""The answer for one contact patch of a wheel on a rail, the same for every patch method: :class:`PatchResult`.

Sign convention (docs/physics.md, Elliptic contact): forces and moment are those the WHEEL EXERTS ON THE RAIL, in the
patch's contact plane (x along the track, s across the patch), each positive for its creepage positive; ``Mz`` is
taken about the rigid contact point (``s = 0``, ``x = 0``).  Traction fields reuse the elliptic
:class:`~rollcontact.elliptic.result.TractionField` (its y is the patch's s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from rollcontact.elliptic.result import TractionField

__all__ = ["PatchResult", "TractionField"]


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
