"""p(x), q(x) and s(x) of a polynomial-method solution of one patch, evaluable anywhere."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rollcontact.line.methods.polynomial.chebyshev import outer_transform, sine_series
from rollcontact.line.result import Distributions


# ---------------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class PolynomialDistributions(Distributions):
    """Fields of a polynomial-method solution (x [m] from the axis projection)."""

    half_width: float
    offset: float
    pressure_coefficients: np.ndarray  # c_n [Pa], sine series on the patch
    slope_coefficients: np.ndarray  # g_n [1] of h0' on the patch
    stick_half_width: float
    stick_offset: float  # centre of the stick zone, x [m]
    stick_coefficients: np.ndarray  # d_n [Pa] of q2 (for the creep's sign taken positive)
    stick_slope_coefficients: np.ndarray  # G_n [1] of h0' on the stick zone
    mu: float
    creep: float
    monomial_pressure: np.ndarray | None = None  # B_n when the monomial basis was used

    def t(self, x):
        return (np.asarray(x, dtype=float) - self.offset) / self.half_width

    def pressure(self, x):
        t = self.t(x)
        if self.monomial_pressure is not None:
            xr = t * self.half_width
            inside = np.abs(t) < 1.0
            with np.errstate(all="ignore"):
                val = np.polynomial.polynomial.polyval(xr, self.monomial_pressure) / np.sqrt(
                    np.where(inside, self.half_width**2 - xr * xr, 1.0))
            return np.where(inside, val, 0.0)
        return sine_series(self.pressure_coefficients, t)

    def stick_correction(self, x):
        if self.stick_half_width <= 0.0:
            return np.zeros_like(np.asarray(x, dtype=float))
        sigma = (np.asarray(x, dtype=float) - self.stick_offset) / self.stick_half_width
        return sine_series(self.stick_coefficients, sigma)

    def traction(self, x):
        sign = math.copysign(1.0, self.creep)
        return sign * (self.mu * self.pressure(x) + self.stick_correction(x))

    def slip(self, x):
        # s = |xi| + du/dx with du/dx = mu sum g_n T_n(t) - mu sum G_n F_n(sigma) (chebyshev.outer_transform)
        x = np.asarray(x, dtype=float)
        t = self.t(x)
        du = self.mu * outer_transform(self.slope_coefficients, t)
        if self.stick_half_width > 0.0:
            sigma = (x - self.stick_offset) / self.stick_half_width
            du = du - self.mu * outer_transform(self.stick_slope_coefficients, sigma)
            in_stick = np.abs(sigma) <= 1.0
        else:
            in_stick = np.zeros(x.shape, dtype=bool)
        s = np.where(in_stick, 0.0, abs(self.creep) + du)
        return np.where(np.abs(t) <= 1.0, math.copysign(1.0, self.creep) * s, np.nan)
