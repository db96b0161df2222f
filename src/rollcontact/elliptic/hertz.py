"""Hertz's solution for an elliptic contact of two quasi-identical elastic bodies (Johnson, Contact Mechanics,
1985, section 4.2), and the gap curvatures of a wheel on a rail.

The undeformed gap is ``h(x, y) = A x^2 + B y^2`` (x rolling direction, y lateral; A, B > 0 [1/m]).  The pressure is
``p = p0 sqrt(1 - x^2/a^2 - y^2/b^2)`` on the ellipse of semi-axes a (along x) and b (along y).  With the major
semi-axis ``alpha`` along the axis of the smaller curvature, the minor one ``beta``, ``e^2 = 1 - beta^2/alpha^2`` and
the complete elliptic integrals ``K(e)``, ``E(e)`` (``scipy.special.ellipk``/``ellipe`` take ``m = e^2``):

* ``A_major = (p0 / E*) (beta / alpha^2) (K - E) / e^2``  (curvature along the major axis),
* ``A_minor = (p0 / E*) (beta / alpha^2) ((alpha^2 / beta^2) E - K) / e^2``,
* ``delta = (p0 / E*) beta K``  (approach of distant points),
* ``Fn = (2/3) pi a b p0``,

with ``E* = E / (2 (1 - nu^2))`` (:attr:`rollcontact.Material.contact_modulus`).  The ratio of the curvatures fixes e
(``A_minor / A_major = ((1 - e^2)^-1 E - K) / (K - E)`` rises monotonically from 1 at e = 0); then
``alpha^3 = 3 Fn (K - E) / (2 pi E* A_major e^2)``.  At ``A = B`` (e -> 0, ``(K - E)/e^2 -> pi/4``) this is the
sphere, ``a = b = (3 Fn R / (4 E*))^(1/3)`` with ``R = 1/(2A)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from rollcontact.core.checks import check_real

__all__ = ["HertzEllipse", "curvatures_from_radii", "curvatures_from_semi_axes", "hertz_ellipse"]

SMALL_ECCENTRICITY = 1e-6
"""Below this ``m = e^2`` the integrals' differences are taken from their series (``K - E = (pi/4) m (1 + 3m/8)``,
``E/(1-m) - K = (pi/4) m (1 + 5m/8)``): the differences of K and E cancel there."""


@dataclass(frozen=True)
class HertzEllipse:
    """The Hertz contact ellipse (SI units).

    Attributes
    ----------
    a : float
        Semi-axis along the rolling direction x [m].
    b : float
        Semi-axis along the lateral direction y [m].
    max_pressure : float
        p0 = 3 Fn / (2 pi a b) [Pa].
    approach : float
        delta [m], the approach of distant points of the two bodies.
    aspect_ratio : float
        a/b [1] (fixed by the curvatures alone, also at zero load).
    """

    a: float
    b: float
    max_pressure: float
    approach: float
    aspect_ratio: float

    @property
    def c(self) -> float:
        """sqrt(a b) [m], the length of Kalker's normalisation."""
        return math.sqrt(self.a * self.b)

    def pressure(self, x, y):
        """p(x, y) = p0 sqrt(1 - x^2/a^2 - y^2/b^2) [Pa] inside the ellipse, 0 outside (x, y [m], numpy arrays)."""
        import numpy as np

        r = 1.0 - (np.asarray(x, dtype=float) / self.a) ** 2 - (np.asarray(y, dtype=float) / self.b) ** 2
        return self.max_pressure * np.sqrt(np.clip(r, 0.0, None))


@lru_cache(maxsize=1024)
def differences(m: float) -> tuple[float, float, float]:
    """``((K - E)/m, (E/(1 - m) - K)/m, K)`` at ``m = e^2`` (series below :data:`SMALL_ECCENTRICITY`; cached: a
    contact's ellipse has the same m at every load, and each scipy call costs microseconds)."""
    k = float(ellipk(m))
    if m < SMALL_ECCENTRICITY:
        return 0.25 * math.pi * (1.0 + 0.375 * m), 0.25 * math.pi * (1.0 + 0.625 * m), k
    e = float(ellipe(m))
    return (k - e) / m, (e / (1.0 - m) - k) / m, k


@lru_cache(maxsize=256)
def eccentricity(ratio: float) -> float:
    """``m = e^2`` whose curvature ratio ``A_minor / A_major`` is ``ratio`` >= 1 (root of the module's relation)."""
    if ratio - 1.0 < 1e-9:  # series: ratio = (1 + 5m/8) / (1 + 3m/8) = 1 + m/4 + O(m^2)
        return 4.0 * (ratio - 1.0)

    def residual(log_g):
        m = -math.expm1(2.0 * log_g)  # 1 - g^2 with g = beta/alpha = exp(log_g), exact near g = 1
        major, minor, _ = differences(m)
        return math.log(minor / major) - math.log(ratio)

    log_g = brentq(residual, math.log(1e-6), -1e-10, xtol=1e-15, rtol=1e-15, maxiter=200)
    return -math.expm1(2.0 * log_g)


def hertz_ellipse(normal_load: float, longitudinal_curvature: float, lateral_curvature: float,
                  contact_modulus: float) -> HertzEllipse:
    """Hertz's elliptic contact from the load, the gap curvatures and the contact modulus (module docstring).

    Parameters
    ----------
    normal_load : float
        Fn [N] >= 0.
    longitudinal_curvature, lateral_curvature : float
        A and B [1/m] > 0 of the gap ``A x^2 + B y^2``.
    contact_modulus : float
        E* [Pa] > 0.

    Returns
    -------
    HertzEllipse
        a, b, p0, the approach and a/b; at Fn = 0 the sizes are 0 and a/b is that of any load.

    Raises
    ------
    ValueError
        A value out of range; the message names it and the limit.  The aspect ratio is limited to
        ``1e-6 < a/b < 1e6`` (curvature ratios up to about 1e11).
    """
    fn = check_real("normal_load", normal_load, lower=0.0, unit="N")
    A = check_real("longitudinal_curvature", longitudinal_curvature, lower=0.0, lower_open=True, unit="1/m")
    B = check_real("lateral_curvature", lateral_curvature, lower=0.0, lower_open=True, unit="1/m")
    estar = check_real("contact_modulus", contact_modulus, lower=0.0, lower_open=True, unit="Pa")
    major_curvature, minor_curvature = (A, B) if A <= B else (B, A)
    m = eccentricity(minor_curvature / major_curvature)
    major, _, k = differences(m)
    g = math.sqrt(1.0 - m)  # beta / alpha
    alpha = (3.0 * fn * major / (2.0 * math.pi * estar * major_curvature)) ** (1.0 / 3.0)
    beta = g * alpha
    # p0 from the curvature relation, finite at Fn = 0: A_major = (p0/E*) (beta/alpha^2) (K - E)/e^2
    p0 = major_curvature * estar * alpha / (g * major) if alpha > 0.0 else 0.0
    a, b = (alpha, beta) if A <= B else (beta, alpha)
    return HertzEllipse(a, b, p0, p0 * beta * k / estar, g if A > B else 1.0 / g)


def curvatures_from_semi_axes(a: float, b: float, normal_load: float, contact_modulus: float) -> tuple[float, float]:
    """The gap curvatures (A, B) [1/m] whose Hertz ellipse under ``normal_load`` [N] has semi-axes a, b [m]
    (the inverse of :func:`hertz_ellipse`, by the module's relations)."""
    a = check_real("a", a, lower=0.0, lower_open=True, unit="m")
    b = check_real("b", b, lower=0.0, lower_open=True, unit="m")
    fn = check_real("normal_load", normal_load, lower=0.0, lower_open=True, unit="N")
    estar = check_real("contact_modulus", contact_modulus, lower=0.0, lower_open=True, unit="Pa")
    alpha, beta = max(a, b), min(a, b)
    m = -math.expm1(2.0 * math.log(beta / alpha))
    major, minor, _ = differences(m)
    p0 = 3.0 * fn / (2.0 * math.pi * a * b)
    scale = p0 * beta / (estar * alpha * alpha)
    along_major, along_minor = scale * major, scale * minor
    return (along_major, along_minor) if a >= b else (along_minor, along_major)


def curvatures_from_radii(wheel_rolling_radius: float, wheel_profile_radius: float = math.inf,
                          rail_profile_radius: float = 0.3, rail_longitudinal_radius: float = math.inf
                          ) -> tuple[float, float]:
    """Gap curvatures (A, B) [1/m] of a wheel on a rail from their principal radii [m].

    ``A = (1/R_wheel,x + 1/R_rail,x) / 2`` and ``B = (1/R_wheel,y + 1/R_rail,y) / 2`` (Johnson 1985, section 4.2;
    the principal axes of both bodies aligned with x and y).  A convex radius is positive, a concave one negative
    (a hollow wheel tread or flange root), a straight profile infinite.

    Parameters
    ----------
    wheel_rolling_radius : float
        Rolling radius of the wheel [m] > 0.
    wheel_profile_radius : float
        Transverse radius of the wheel profile at the contact [m] (negative: concave; inf: straight).
    rail_profile_radius : float
        Transverse radius of the rail head profile at the contact [m] (crown radius, positive).
    rail_longitudinal_radius : float
        Radius of the rail along the track [m] (inf: straight; a roller of a test rig: its radius).

    Raises
    ------
    ValueError
        A radius of zero or NaN, or a curvature sum A or B <= 0 (the surfaces would not touch in a point): the
        message names the radii and the sum.
    """
    inverse = []
    for name, radius in (("wheel_rolling_radius", wheel_rolling_radius), ("wheel_profile_radius", wheel_profile_radius),
                         ("rail_profile_radius", rail_profile_radius),
                         ("rail_longitudinal_radius", rail_longitudinal_radius)):
        try:
            r = float(radius)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be a real number in m, got {radius!r}") from None
        if math.isnan(r) or r == 0.0:
            raise ValueError(f"{name} = {r!r} m: a radius must be nonzero (inf for a straight profile)")
        inverse.append(1.0 / r)
    if wheel_rolling_radius <= 0.0:
        raise ValueError(f"wheel_rolling_radius = {wheel_rolling_radius!r} m is out of range: it must be > 0")
    A = 0.5 * (inverse[0] + inverse[3])
    B = 0.5 * (inverse[1] + inverse[2])
    if not A > 0.0:
        raise ValueError(f"longitudinal curvature A = (1/{wheel_rolling_radius!r} + 1/{rail_longitudinal_radius!r})/2 "
                         f"= {A!r} 1/m must be > 0: the bodies conform along x")
    if not B > 0.0:
        raise ValueError(f"lateral curvature B = (1/{wheel_profile_radius!r} + 1/{rail_profile_radius!r})/2 = {B!r} "
                         "1/m must be > 0: the profiles conform (a concave wheel radius must be larger in size than "
                         "the rail's)")
    return A, B
