"""The one result type of every elliptic (3D) method: :class:`EllipticResult`, with the traction fields
:class:`TractionField` where a method computes them.

Sign convention (docs/physics.md, Elliptic contact): forces and moment are those the WHEEL EXERTS ON THE RAIL, the
opposite of Kalker's (forces on the wheel), so each creepage > 0 gives its force > 0, as the 2D library does
(creep > 0 gives T' > 0).  In the linear theory ``Fx = G c^2 C11 xi``, ``Fy = G c^2 (C22 eta + c C23 phi)``,
``Mz = G c^3 (-C23 eta + c C33 phi)`` with ``c = sqrt(a b)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["EllipticResult", "TractionField"]


@dataclass(frozen=True)
class TractionField:
    """Tractions on points of the contact ellipse (arrays of one shape; SI units).

    Attributes
    ----------
    x, y : ndarray
        Positions [m] (x rolling direction, the leading edge at ``x = +a(y)``).
    pressure : ndarray
        p [Pa], the pressure the method bounds the traction with (Hertz's, sampled and scaled to the load on a
        method's cells).
    traction_x, traction_y : ndarray
        Tangential traction [Pa] the wheel exerts on the rail.
    stick : ndarray of bool
        True where the bodies stick.
    """

    x: np.ndarray
    y: np.ndarray
    pressure: np.ndarray
    traction_x: np.ndarray
    traction_y: np.ndarray
    stick: np.ndarray

    @property
    def traction_magnitude(self) -> np.ndarray:
        """|q| [Pa]."""
        return np.hypot(self.traction_x, self.traction_y)


@dataclass(frozen=True)
class EllipticResult:
    """Solution of an elliptic rolling-contact scene, the same for every method (SI units).

    Attributes
    ----------
    method : str
        Registry name of the method that produced it.
    success : bool
        False when the method's assumptions failed or it did not converge; ``message`` says why, and the numbers
        must not be trusted.
    message : str
        Human-readable status.
    normal_load : float
        Fn [N].
    longitudinal_force : float
        Fx [N] the wheel exerts on the rail (> 0 for xi > 0).
    lateral_force : float
        Fy [N] the wheel exerts on the rail (> 0 for eta > 0).
    spin_moment : float
        Mz [N m] about the contact centre, exerted by the wheel on the rail (> 0 for phi > 0).
    longitudinal_creepage, lateral_creepage : float
        xi, eta [1] of the scene.
    spin_creepage : float
        phi [1/m] of the scene.
    a, b : float
        Hertz semi-axes [m] along x and y.
    max_pressure : float
        p0 [Pa].
    approach : float
        Normal approach delta [m].
    friction_coefficient : float
        mu at zero slip velocity [1] (the normalisation of :attr:`force_coefficients`).
    fields : TractionField or None
        The traction on the method's points, where it computed them (methods take ``fields=True``).
    info : dict
        Method-specific extras; ``error_estimate`` (the estimated error of Fx and Fy over mu Fn and of Mz over
        mu Fn c, the largest), with a tolerance also ``tolerance``, ``tolerance_met``, ``setting``, and
        ``predicted_cost`` [s] (the modelled cost) where the dispatcher chose by cost.
    """

    method: str
    success: bool
    message: str
    normal_load: float
    longitudinal_force: float
    lateral_force: float
    spin_moment: float
    longitudinal_creepage: float
    lateral_creepage: float
    spin_creepage: float
    a: float
    b: float
    max_pressure: float
    approach: float
    friction_coefficient: float
    fields: TractionField | None = field(default=None, repr=False)
    info: dict = field(default_factory=dict, repr=False)

    @property
    def c(self) -> float:
        """sqrt(a b) [m]."""
        return math.sqrt(self.a * self.b)

    @property
    def force_coefficients(self) -> tuple[float, float, float]:
        """(Fx / (mu Fn), Fy / (mu Fn), Mz / (mu Fn c)) [1]; zeros without load."""
        scale = self.friction_coefficient * self.normal_load
        if scale <= 0.0:
            return 0.0, 0.0, 0.0
        return self.longitudinal_force / scale, self.lateral_force / scale, self.spin_moment / (scale * self.c)

    @classmethod
    def from_scene(cls, scene, method: str, success: bool, message: str, forces=(math.nan,) * 3, fields=None,
                   info=None) -> EllipticResult:
        """A result for ``scene`` (its creepages and Hertz ellipse) with ``forces = (Fx, Fy, Mz)`` [N, N, N m].  A
        solve that reports success with a force that is not finite (creepages so large that a level's own scaling
        overflows) is a failure, and says so."""
        h = scene.hertz
        forces = tuple(float(f) for f in forces)
        if success and not all(map(math.isfinite, forces)):
            success = False
            creepages = (scene.longitudinal_creepage, scene.lateral_creepage, scene.spin_creepage)
            message = (f"{message}: its forces {forces} are not finite at the creepages {creepages} (1, 1, 1/m) and "
                       f"load {scene.normal_load!r} N, beyond what this level computes in floating point")
        return cls(method, success, message, scene.normal_load, forces[0], forces[1], forces[2],
                   scene.longitudinal_creepage, scene.lateral_creepage, scene.spin_creepage, h.a, h.b,
                   h.max_pressure, h.approach, scene.friction_coefficient, fields, {} if info is None else info)
