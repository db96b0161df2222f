"""Carter/Fromm steady rolling of the line contact (paper eqs 12-17), with its distributions, and the static
limits of Cattaneo and Mindlin-Deresiewicz.

The functions here are small, pure and scalar (plain ``math``), because the FMU's closed-form step calls them
directly.  Conventions are those of the package docstring: material flows in +x, the stick zone is at the
leading edge, xi > 0 gives T' > 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rollcontact.line.hertz import ellipse
from rollcontact.line.result import Distributions


def carter(normal_load_per_length: float, creep: float, radius: float, contact_modulus: float,
           mu: float) -> tuple[float, float, float]:
    """Carter/Fromm steady rolling with Coulomb friction.

    Implements ``a* = a - R |xi| / mu`` (eq 17) and ``T' = sign(xi) mu N' (1 - (a*/a)^2)``, full slip
    (``a* = 0``, ``|T'| = mu N'``) for ``|xi| >= mu a / R``.  The creep stiffness is
    ``dT'/dxi = 2 N' R a* / a^2`` (``pi E* a / 2`` at xi = 0, 0 in full slip).

    Parameters
    ----------
    normal_load_per_length : float
        N' [N/m] >= 0.
    creep : float
        xi [1], either sign.
    radius : float
        R [m] > 0.
    contact_modulus : float
        E* [Pa] > 0.
    mu : float
        Friction coefficient [1] > 0.

    Returns
    -------
    tangential_force_per_length : float
        T' [N/m].
    stick_half_width : float
        a* [m].
    creep_stiffness_per_length : float
        dT'/dxi [N/m].
    """
    a = math.sqrt(4.0 * normal_load_per_length * radius / (math.pi * contact_modulus))
    if a == 0.0:
        return 0.0, 0.0, 0.0
    slip_length = radius * abs(creep) / mu  # a - a*
    if slip_length >= a:
        return math.copysign(mu * normal_load_per_length, creep), 0.0, 0.0
    a_star = a - slip_length
    # 1 - (a*/a)^2 = u (2 - u) with u = (a - a*)/a: no cancellation at small creep, where 1 - r^2 would keep
    # only eps/u of relative accuracy (and lose the sign of T' once u < eps); u (2 - u) <= 1 in floating point
    u = slip_length / a
    return (math.copysign(mu * normal_load_per_length * (u * (2.0 - u)), creep), a_star,
            2.0 * radius * (normal_load_per_length / a) * (a_star / a))


def cattaneo_traction(x, a: float, p0: float, mu: float, force_ratio: float):
    """Cattaneo's static shift (loading), docs/physics.md, Closed forms.

    ``q = mu p0 [sqrt(1 - x^2/a^2) - (c/a) sqrt(1 - x^2/c^2)]``, ``c/a = sqrt(1 - Q'/(mu N'))`` with
    ``force_ratio = Q'/(mu N')`` in [0, 1]; each root only inside its own zone.  x [m] from the centre.
    """
    x = np.asarray(x, dtype=float)
    c = a * math.sqrt(max(0.0, 1.0 - force_ratio))
    return mu * p0 * (ellipse(x, a) - (c / a) * ellipse(x, c)) if a > 0 else np.zeros_like(x)


def mindlin_unloading_traction(x, a: float, p0: float, mu: float, peak_ratio: float, force_ratio: float):
    """Mindlin-Deresiewicz unloading from Q* to Q (docs/physics.md, Closed forms), ratios to mu N'.

    ``q = -mu p0 [sqrt(1-x^2/a^2) - 2 (b/a) sqrt(1-x^2/b^2) + (c/a) sqrt(1-x^2/c^2)]`` with
    ``b/a = sqrt(1 - (Q* - Q)/(2 mu N'))`` and ``c/a = sqrt(1 - Q*/(mu N'))``.
    """
    x = np.asarray(x, dtype=float)
    b = a * math.sqrt(max(0.0, 1.0 - 0.5 * (peak_ratio - force_ratio)))
    c = a * math.sqrt(max(0.0, 1.0 - peak_ratio))
    return -mu * p0 * (ellipse(x, a) - 2.0 * (b / a) * ellipse(x, b) + (c / a) * ellipse(x, c))




@dataclass(frozen=True)
class CarterDistributions(Distributions):
    """Hertz pressure and Carter traction/slip, centred at ``offset`` (x from the axis projection).

    Traction and slip are evaluated in factored forms (see :meth:`zones`) that keep their relative accuracy when
    the stick zone fills nearly the whole patch (small creep) and next to the stick/slip boundary, where the
    textbook differences of square roots cancel (and then break q >= 0, |q| <= mu p by round-off).
    """

    a: float
    p0: float
    a_star: float
    offset: float
    mu: float
    creep: float
    radius: float

    def pressure(self, x):
        return self.p0 * ellipse(np.asarray(x, dtype=float) - self.offset, self.a)

    def zones(self, x):
        """``(a + x', a - x', a - x' - 2w)`` with x' = x - offset and w = a - a* (clipped to the patch).

        The third is >= 0 exactly in the stick zone ``[-a, -a + 2a*]`` and equals ``-(x*^2 - a*^2)/(a + x')``
        with the eq 16 coordinate ``x* = x' + a - a*``.
        """
        xr = np.asarray(x, dtype=float) - self.offset
        minus = np.clip(self.a - xr, 0.0, None)
        return np.clip(self.a + xr, 0.0, None), minus, minus - 2.0 * (self.a - self.a_star)

    def traction(self, x):
        # eqs 13-15: q = mu p0 [sqrt(1 - x^2/a^2) - (a*/a) sqrt(1 - (x + a - a*)^2/a*^2)] in the stick zone; with
        # the zones that is (mu p0 / a) sqrt(a + x) [sqrt(a - x) - sqrt(a - x - 2w)], and the difference of roots
        # is 2w / (sqrt(a - x) + sqrt(a - x - 2w)): no cancellation, 0 <= q <= mu p by construction
        plus, minus, stick = self.zones(x)
        root = np.sqrt(minus)
        with np.errstate(divide="ignore", invalid="ignore"):
            in_stick = 2.0 * (self.a - self.a_star) / (root + np.sqrt(np.clip(stick, 0.0, None)))
        q = np.sqrt(plus) * np.where(stick > 0.0, in_stick, root) / self.a
        return math.copysign(self.mu * self.p0, self.creep) * q

    def slip(self, x):
        # eq 16 generalised to full slip: s = sign(xi) [|xi| - mu (a - a*)/R + (mu/R) sqrt(x*^2 - a*^2)] behind
        # the stick zone, x*^2 - a*^2 = -(a + x) (a - x - 2w) from the zones
        plus, _, stick = self.zones(x)
        inside = np.abs(np.asarray(x, dtype=float) - self.offset) <= self.a
        mag = (abs(self.creep) - self.mu * (self.a - self.a_star) / self.radius
               + self.mu / self.radius * np.sqrt(np.clip(-stick * plus, 0.0, None)))
        s = np.where(stick >= 0.0, 0.0, math.copysign(1.0, self.creep) * mag)
        return np.where(inside, s, np.nan)

