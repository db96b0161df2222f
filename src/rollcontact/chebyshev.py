"""Chebyshev machinery of the polynomial method (physics.md section 3).

On an interval of half-width ``h`` centred at ``c`` write ``x = c + h t``, ``t = cos(theta)``.  The finite
Hilbert transform pairs used throughout:

* ``(1/pi) PV-int_{-1}^{1} sqrt(1-tau^2) U_{n-1}(tau) / (t - tau) dtau = T_n(t)``             for |t| < 1,
* the same integral equals ``F_n(t) = (t - sign(t) sqrt(t^2 - 1))^n``                            for |t| > 1.

So a density ``f = sum_{n>=1} c_n sqrt(1-t^2) U_{n-1}(t) = sum c_n sin(n theta)`` (bounded, zero at both
ends) answers ``(1/pi) PV-int f(z)/(x - z) dz = sum c_n T_n(t)``; a right-hand side has a bounded solution iff
its T_0 coefficient vanishes, and ``int f dx = (pi h / 2) c_1``.

A right-hand side ``r(x)`` is handled through its Chebyshev coefficients on the interval.  Harmonics expand
exactly with Jacobi-Anger, ``cos(phi + z t) = sum eps_n J_n(z) cos(phi + n pi/2) T_n(t)`` (``eps_0 = 1``,
``eps_n = 2``), which is where the paper's Bessel functions come from.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.polynomial import chebyshev as npcheb
from numpy.polynomial import polynomial as nppoly
from scipy import special

__all__ = ["SlopeExpansion", "outer_transform", "sine_series", "theta_grid", "unit_grid"]


@lru_cache(maxsize=64)
def unit_grid(m: int) -> np.ndarray:
    """m equally spaced points on [0, 1] (cached: numpy's linspace costs ~15 us per call)."""
    g = np.arange(m, dtype=float) / (m - 1)
    g.flags.writeable = False
    return g


@lru_cache(maxsize=64)
def theta_grid(m: int, n_max: int) -> tuple[np.ndarray, np.ndarray]:
    """Interior angles theta_i = pi i/m (i = 1..m-1) and the table sin(n theta_i), n = 1..n_max (cached)."""
    theta = np.pi * np.arange(1, m, dtype=float) / m
    table = np.sin(np.multiply.outer(theta, np.arange(1, n_max + 1)))
    theta.flags.writeable = False
    table.flags.writeable = False
    return theta, table


def double_factorial_ratio(j: int) -> float:
    """(j-1)!! / j!! for even j >= 0 (the Chebyshev-weighted mean of t^j)."""
    r = 1.0
    for i in range(2, j + 1, 2):
        r *= (i - 1) / i
    return r


class SlopeExpansion:
    """Expansions of the gap slope ``h0'(X) = (X - x_c)/R - Z'(X)`` on intervals ``X = c + h t``.

    Parameters
    ----------
    radius : float
        R [m].
    axis_position : float
        x_c [m].
    surface : rollcontact.Surface
        Z(X): polynomial part and harmonics.
    """

    def __init__(self, radius, axis_position, surface):
        self.radius = radius
        self.axis_position = axis_position
        # surface slope Z'(X) as a polynomial (power basis in X) plus harmonics
        self.has_poly = any(c != 0.0 for c in surface.polynomial[1:])
        if self.has_poly:
            self.slope_poly = nppoly.polyder(np.asarray(surface.polynomial, dtype=float))
            self.slope_derivs = [self.slope_poly]
            for _ in range(self.slope_poly.size + 1):
                d = self.slope_derivs[-1]
                self.slope_derivs.append(nppoly.polyder(d) if d.size > 1 else np.zeros(1))
        else:
            self.slope_poly = np.zeros(1)
            self.slope_derivs = [self.slope_poly, self.slope_poly]
        h = [hm for hm in surface.harmonics if hm.amplitude != 0.0]
        self.k = np.array([hm.wavenumber for hm in h])
        self.phi = np.array([hm.cos_amplitude for hm in h])
        self.psi = np.array([hm.sin_amplitude for hm in h])
        self.has_harmonics = self.k.size > 0
        # plain-float copies for the scalar path (numpy calls on scalars dominate otherwise)
        self.harmonic_list = list(zip(self.k.tolist(), self.phi.tolist(), self.psi.tolist(), strict=True))
        self.deriv_lists = [d.tolist() for d in self.slope_derivs]
        self.poly_weights = [(j, double_factorial_ratio(j) if j % 2 == 0 else first_moment_weight(j),
                              1.0 / math.factorial(j)) for j in range(self.slope_poly.size)]

    # ---- T0/T1 moments with derivatives (the exact scalar equations 28-31) -------------------------------
    def moments(self, h, c):
        """T_0 and T_1 Chebyshev coefficients of ``Z'(c + h t)`` and their derivatives.

        Returns
        -------
        m0, m1, dm0_dh, dm0_dc, dm1_dh, dm1_dc : float or ndarray
            Broadcast over ``h`` and ``c``.  For a harmonic (physics.md eqs 28-31):
            ``m0 = k J0(kh) (Psi cos kc - Phi sin kc)``, ``m1 = -2 k J1(kh) (Phi cos kc + Psi sin kc)``.
        """
        if isinstance(h, float) and isinstance(c, float):
            return self.moments_scalar(h, c)
        h = np.asarray(h, dtype=float)
        c = np.asarray(c, dtype=float)
        shape = np.broadcast(h, c).shape
        m0 = np.zeros(shape)
        m1 = np.zeros(shape)
        d0h = np.zeros(shape)
        d0c = np.zeros(shape)
        d1h = np.zeros(shape)
        d1c = np.zeros(shape)
        if self.has_poly:
            # Taylor coefficients e_j = h^j Q^(j)(c)/j! of Q = Z' about c; means of t^j: (j-1)!!/j!! (even j),
            # first moment 2 j!!/(j+1)!! (odd j)
            nd = self.slope_poly.size
            for j in range(nd):
                qj = nppoly.polyval(c, self.slope_derivs[j]) / math.factorial(j)
                qj1 = nppoly.polyval(c, self.slope_derivs[j + 1]) / math.factorial(j)
                hj = h**j
                dhj = j * h ** (j - 1) if j > 0 else 0.0 * h
                if j % 2 == 0:
                    w = double_factorial_ratio(j)
                    m0 = m0 + w * hj * qj
                    d0h = d0h + w * dhj * qj
                    d0c = d0c + w * hj * qj1
                else:
                    w = first_moment_weight(j)
                    m1 = m1 + w * hj * qj
                    d1h = d1h + w * dhj * qj
                    d1c = d1c + w * hj * qj1
        if self.has_harmonics:
            k = self.k
            z = h[..., None] * k
            kc = c[..., None] * k
            cs, sn = np.cos(kc), np.sin(kc)
            j0 = special.j0(z)
            j1 = special.j1(z)
            # J1'(z) = J0 - J1/z, -> 1/2 as z -> 0
            with np.errstate(divide="ignore", invalid="ignore"):
                j1p = np.where(z > 1e-8, j0 - j1 / np.where(z > 1e-8, z, 1.0), 0.5 - z * z * 3.0 / 16.0)
            a0 = self.psi * cs - self.phi * sn
            a1 = self.phi * cs + self.psi * sn
            m0 = m0 + np.sum(k * j0 * a0, axis=-1)
            m1 = m1 + np.sum(-2.0 * k * j1 * a1, axis=-1)
            d0h = d0h + np.sum(-k * k * j1 * a0, axis=-1)
            d0c = d0c + np.sum(-k * k * j0 * a1, axis=-1)
            d1h = d1h + np.sum(-2.0 * k * k * j1p * a1, axis=-1)
            d1c = d1c + np.sum(-2.0 * k * k * j1 * a0, axis=-1)
        return m0, m1, d0h, d0c, d1h, d1c

    def moments_scalar(self, h: float, c: float):
        """:meth:`moments` for plain floats (same formulas, no array overhead)."""
        m0 = m1 = d0h = d0c = d1h = d1c = 0.0
        if self.has_poly:
            for j, w, inv_fact in self.poly_weights:
                qj = horner(self.deriv_lists[j], c) * inv_fact
                qj1 = horner(self.deriv_lists[j + 1], c) * inv_fact
                hj = h**j
                dhj = j * h ** (j - 1) if j > 0 else 0.0
                if j % 2 == 0:
                    m0 += w * hj * qj
                    d0h += w * dhj * qj
                    d0c += w * hj * qj1
                else:
                    m1 += w * hj * qj
                    d1h += w * dhj * qj
                    d1c += w * hj * qj1
        for k, phi, psi in self.harmonic_list:
            z = k * h
            kc = k * c
            cs, sn = math.cos(kc), math.sin(kc)
            j0 = float(special.j0(z))
            j1 = float(special.j1(z))
            j1p = j0 - j1 / z if z > 1e-8 else 0.5 - z * z * 3.0 / 16.0
            a0 = psi * cs - phi * sn
            a1 = phi * cs + psi * sn
            kk = k * k
            m0 += k * j0 * a0
            m1 -= 2.0 * k * j1 * a1
            d0h -= kk * j1 * a0
            d0c -= kk * j0 * a1
            d1h -= 2.0 * kk * j1p * a1
            d1c -= 2.0 * kk * j1 * a0
        return m0, m1, d0h, d0c, d1h, d1c

    # ---- full Chebyshev series ------------------------------------------------------------------------------
    def gap_slope_coefficients(self, h: float, c: float, order: int) -> np.ndarray:
        """Chebyshev coefficients ``[g_0 .. g_order]`` of ``h0'(c + h t)`` (exact for the polynomial part,
        Jacobi-Anger for harmonics, truncated at ``order``)."""
        g = np.zeros(order + 1)
        g[0] = (c - self.axis_position) / self.radius
        if order >= 1:
            g[1] = h / self.radius
        if self.has_poly:
            # Taylor polynomial of Z'(c + h t) in t, then to the Chebyshev basis
            taylor = np.array([nppoly.polyval(c, self.slope_derivs[j]) * h**j / math.factorial(j)
                               for j in range(self.slope_poly.size)])
            cheb = npcheb.poly2cheb(taylor)
            m = min(cheb.size, order + 1)
            g[:m] -= cheb[:m]
        if self.has_harmonics:
            n = np.arange(order + 1)
            eps = np.where(n == 0, 1.0, 2.0)
            jn = special.jv(n[:, None], h * self.k[None, :])
            ang = c * self.k[None, :] + 0.5 * np.pi * n[:, None]
            g -= eps * np.sum(self.k * jn * (self.psi * np.cos(ang) - self.phi * np.sin(ang)), axis=1)
        return g

    def required_order(self, h: float, tolerance: float, max_order: int = 400) -> int:
        """Smallest order whose neglected harmonic coefficients are below ``tolerance`` times the Hertz slope
        ``h/R`` (the polynomial part is exact from its degree on).

        Uses ``|J_n(z)| <= (z/2)^n / n!``: the bound of the n-th coefficient, ``2 k |Z_m| (kh/2)^n / n!``, is
        summed over the harmonics and decreases for n > kh.
        """
        order = max(1, self.slope_poly.size)
        if not self.has_harmonics:
            return order
        target = tolerance * h / self.radius
        terms = [(0.5 * k * h, 2.0 * k * math.hypot(phi, psi)) for k, phi, psi in self.harmonic_list]
        n_start = max(order, int(max(z for z, _ in terms)) + 1)
        for n in range(n_start, max_order + 1):
            lg = math.lgamma(n + 1)
            bound = sum(amp * math.exp(n * math.log(z) - lg) if z > 0 else 0.0 for z, amp in terms)
            if bound <= target:
                return n
        return max_order

    # ---- monomial (paper eqs 21-26) -------------------------------------------------------------------------
    def gap_slope_taylor(self, c: float, order: int) -> np.ndarray:
        """Taylor coefficients ``[e_0 .. e_{order-1}]`` of ``h0'(c + x)`` in x [m] (power basis, physical)."""
        e = np.zeros(order)
        e[0] = (c - self.axis_position) / self.radius
        if order > 1:
            e[1] = 1.0 / self.radius
        if self.has_poly:
            for j in range(min(order, self.slope_poly.size)):
                e[j] -= nppoly.polyval(c, self.slope_derivs[j]) / math.factorial(j)
        if self.has_harmonics:
            # k^(j+1)/j! by recurrence: overflows to inf (a reported failure) instead of raising at j > 170
            scale = self.k.copy()
            with np.errstate(over="ignore", invalid="ignore"):
                for j in range(order):
                    if j > 0:
                        scale = scale * self.k / j
                    ang = c * self.k + 0.5 * np.pi * j
                    e[j] -= np.sum(scale * (self.psi * np.cos(ang) - self.phi * np.sin(ang)))
        return e


def horner(coefficients: list[float], x: float) -> float:
    """Power-series value sum c_j x^j for plain floats."""
    v = 0.0
    for coef in reversed(coefficients):
        v = v * x + coef
    return v


def first_moment_weight(j: int) -> float:
    """T_1 coefficient of t^j for odd j: (2/pi) int t^(j+1)/sqrt(1-t^2) dt = 2 j!!/(j+1)!!."""
    return 2.0 * double_factorial_ratio(j + 1)


def sine_series(coefficients: np.ndarray, t) -> np.ndarray:
    """``sum_{n>=1} c_n sqrt(1-t^2) U_{n-1}(t) = sum c_n sin(n acos t)`` for |t| <= 1, 0 outside.

    ``coefficients[0]`` (the T_0 term) is ignored.
    """
    t = np.asarray(t, dtype=float)
    inside = np.abs(t) <= 1.0
    theta = np.arccos(np.clip(t, -1.0, 1.0))
    n = np.arange(1, coefficients.size)
    val = np.sin(np.multiply.outer(theta, n)) @ coefficients[1:] if n.size else np.zeros_like(t)
    return np.where(inside, val, 0.0)


def outer_transform(coefficients: np.ndarray, t) -> np.ndarray:
    """``sum_{n>=1} c_n G_n(t)`` with ``G_n = T_n(t)`` inside and ``(t - sign(t) sqrt(t^2-1))^n`` outside:
    the finite Hilbert transform ``(1/pi) PV-int f(z)/(x - z) dz`` of the density of :func:`sine_series`."""
    t = np.asarray(t, dtype=float)
    c = coefficients.copy()
    c[0] = 0.0
    out = np.empty(t.shape)
    inside = np.abs(t) <= 1.0
    if inside.all():
        return npcheb.chebval(t, c)
    out[inside] = npcheb.chebval(t[inside], c)
    to = t[~inside]
    w = to - np.sign(to) * np.sqrt(to * to - 1.0)
    # w^n by cumulative products (np.power is far slower), |w| < 1 so no overflow
    powers = np.cumprod(np.broadcast_to(w[:, None], (w.size, c.size - 1)), axis=1)
    out[~inside] = powers @ c[1:]
    return out
