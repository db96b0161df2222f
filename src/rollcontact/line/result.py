"""The one result type returned by every method of :func:`rollcontact.solve`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["ContactResult", "Distributions", "NoContact", "TabulatedDistributions"]


class Distributions:
    """Interface of the traction fields of a solution, at x [m] measured from the axis projection.

    ``x = X - x_c``: material flows in +x, the leading edge is at ``x = offset - a``.  Outside the contact
    patch pressure and traction are zero; slip is returned where the method defines it and NaN elsewhere.
    """

    def pressure(self, x):  # pragma: no cover - interface
        """Normal pressure p(x) [Pa]."""
        raise NotImplementedError

    def traction(self, x):  # pragma: no cover - interface
        """Tangential traction q(x) [Pa] that the cylinder exerts on the counter-surface."""
        raise NotImplementedError

    def slip(self, x):  # pragma: no cover - interface
        """Steady local slip s(x) [1] (relative slip velocity over V)."""
        raise NotImplementedError


class NoContact(Distributions):
    """N' = 0: no patch, all fields zero."""

    def pressure(self, x):
        return np.zeros_like(np.asarray(x, dtype=float))

    traction = pressure

    def slip(self, x):
        return np.full_like(np.asarray(x, dtype=float), np.nan)


@dataclass(frozen=True)
class TabulatedDistributions(Distributions):
    """Piecewise-constant fields on element centres ``x`` [m] of uniform width (discretised methods)."""

    x: np.ndarray
    p: np.ndarray
    q: np.ndarray
    s: np.ndarray

    def lookup(self, values, x):
        x = np.asarray(x, dtype=float)
        dx = self.x[1] - self.x[0] if self.x.size > 1 else 1.0
        i = np.floor((x - (self.x[0] - 0.5 * dx)) / dx).astype(int)
        inside = (i >= 0) & (i < self.x.size)
        out = np.where(inside, values[np.clip(i, 0, self.x.size - 1)], 0.0)
        return out

    def pressure(self, x):
        return self.lookup(self.p, x)

    def traction(self, x):
        return self.lookup(self.q, x)

    def slip(self, x):
        return self.lookup(self.s, x)


@dataclass(frozen=True)
class ContactResult:
    """Solution of a 2D rolling-contact scene, the same for every method (SI units, per unit length).

    Attributes
    ----------
    method : str
        Registry name of the method that produced it.
    success : bool
        False when the method's assumptions failed or it did not converge; ``message`` says why.  The numbers
        of an unsuccessful result are the method's last iterate and must not be trusted.
    message : str
        Human-readable status.
    normal_load_per_length : float
        N' [N/m].
    tangential_force_per_length : float
        T' [N/m], sign of the creep in steady rolling.
    creep : float
        xi [1] (given in creep control, found in force control).
    contact_half_width : float
        a [m] (for several patches: half the distance between the outer edges).
    contact_offset : float
        Delta [m]: contact centre minus axis projection.
    stick_half_width : float
        a* [m]: half-length of the stick zone at the leading edge (0 in full slip, a at zero creep).
    max_pressure : float
        max p [Pa] (p0 for Hertz).
    creep_stiffness_per_length : float
        dT'/dxi [N/m] at this state, NaN where the method does not provide it.
    iterations : int
        Nonlinear iterations or time steps used.
    residual : float
        Method-specific error measure (see the method's docs); 0 for closed forms.
    distributions : Distributions
        p(x), q(x), s(x), evaluable anywhere.
    info : dict
        Method-specific extras (coefficients, iteration history, ...).
    """

    method: str
    success: bool
    message: str
    normal_load_per_length: float
    tangential_force_per_length: float
    creep: float
    contact_half_width: float
    contact_offset: float
    stick_half_width: float
    max_pressure: float
    creep_stiffness_per_length: float = math.nan
    iterations: int = 0
    residual: float = 0.0
    distributions: Distributions = field(default_factory=NoContact, repr=False)
    info: dict = field(default_factory=dict, repr=False)

    @property
    def traction_coefficient(self) -> float:
        """T'/N' [1]; 0 when there is no load."""
        n = self.normal_load_per_length
        return self.tangential_force_per_length / n if n > 0.0 else 0.0

    @property
    def leading_edge(self) -> float:
        """x [m] of the leading edge (material enters the patch here)."""
        return self.contact_offset - self.contact_half_width

    @property
    def trailing_edge(self) -> float:
        """x [m] of the trailing edge."""
        return self.contact_offset + self.contact_half_width

    def pressure(self, x):
        """p(x) [Pa] at x [m] from the axis projection."""
        return self.distributions.pressure(x)

    def traction(self, x):
        """q(x) [Pa] at x [m] from the axis projection."""
        return self.distributions.traction(x)

    def slip(self, x):
        """s(x) [1] at x [m] from the axis projection."""
        return self.distributions.slip(x)
