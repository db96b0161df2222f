"""Influence of one lateral strip of semi-elliptic pressure on the centre line of the others: the kernels of the
non-Hertzian strip normal problem (docs/physics-wheelrail-patches.md, "The strips' normal problem").

A strip ``t_lo < t < t_hi`` across the patch carries ``p(x) = p0 sqrt(1 - x^2/a^2)`` along the rolling direction.
On the centre line ``x = 0`` at the lateral distance ``d`` its normal displacement (two quasi-identical bodies,
Boussinesq: ``u_z = (1/(pi E*)) int int p / r``) and the curvature of that displacement along x are

    ``u_z = (p0 a / (pi E*)) [Jc(rho_lo) - Jc(rho_hi)]``,
    ``d^2 u_z / dx^2 = (p0 / (pi E* a)) [Mc(rho_lo) - Mc(rho_hi)]``,  ``rho = (s - t) / a``,

with ``Jc``, ``Mc`` the antiderivatives (odd, zero at 0) of the line kernels of a semi-ellipse of unit half-length,

    ``j(rho) = int_{-1}^{1} sqrt(1 - u^2) / sqrt(u^2 + rho^2) du = 2 sqrt(1 + rho^2) (K(mu) - E(mu))``,
    ``m(rho) = int_{-1}^{1} sqrt(1 - u^2) (2 u^2 - rho^2) / (u^2 + rho^2)^(5/2) du = -j(rho) / (1 + rho^2)``,

``mu = 1 / (1 + rho^2)``, K and E the complete elliptic integrals (``m = -(1/rho) d(rho j')/drho`` since the surface
Laplacian of ``1/r`` is ``1/r^3``).  Near 0, ``j = 2 ln(4/rho) - 2 + O(rho^2 ln rho)`` and ``Jc = 2 rho ln(4/rho)``;
for large rho, ``Jc = (pi/2) ln(rho) + pi ln 2 + pi/4 + O(rho^-2)`` and ``Mc -> -pi``, the 2D half-plane's
``-2 pi``, so that an infinitely wide strip has ``d^2 u_z/dx^2 = -2 p0/(E* a)``, the 2D Hertz relation.

``Jc`` and ``Mc`` are tabulated in ``t = ln(rho)`` (cumulative Simpson of the closed-form ``rho j`` and ``rho m``)
and read by cubic Hermite interpolation with their exact t-derivatives ``rho j`` and ``rho m``.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy.integrate import cumulative_simpson
from scipy.special import ellipe, ellipkm1

TABLE_STEP = 0.01
"""Spacing of the tables in ``t = ln(rho)``: the Hermite interpolation's error is about ``TABLE_STEP^4 / 384``
relative."""

TABLE_RANGE = (-14.0, 14.0)
"""``t`` covered by the tables; below it ``Jc = 2 rho ln(4/rho)`` and ``Mc = -Jc`` (to ``O(rho^3 ln rho)``, relative
1e-12 there), above it both are linear in t to ``O(rho^-2)`` (the last interval extrapolates)."""

SERIES_BELOW = 0.01
"""``mu`` below which ``K - E`` is taken from its series (the difference of K and E cancels there)."""


def line_kernels(rho: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(j(rho), m(rho))`` (module docstring), rho > 0 (arrays)."""
    rho = np.asarray(rho, dtype=float)
    s = 1.0 + rho * rho
    mu = 1.0 / s
    with np.errstate(divide="ignore", invalid="ignore"):
        difference = ellipkm1(rho * rho / s) - ellipe(mu)
    series = 0.5 * math.pi * mu * (0.5 + mu * (3.0 / 16.0 + mu * (15.0 / 128.0 + mu * (175.0 / 2048.0))))
    difference = np.where(mu < SERIES_BELOW, series, difference)
    root = np.sqrt(s)
    return 2.0 * root * difference, -2.0 * difference / root


@lru_cache(maxsize=1)
def tables() -> tuple[float, float, np.ndarray]:
    """``(t_0, step, table)``: ``table[k, i]`` for ``k`` = 0..3 is ``Jc``, ``Mc``, ``step dJc/dt``,
    ``step dMc/dt`` at ``t_0 + i step`` (read-only; built once, a few milliseconds)."""
    t_min, t_max = TABLE_RANGE
    fine = 0.5 * TABLE_STEP
    start = -40.0
    t = start + fine * np.arange(int(round((t_max - start) / fine)) + 1)
    rho = np.exp(t)
    j, m = line_kernels(rho)
    edge = 2.0 * rho[0] * math.log(4.0 / rho[0])  # Jc and -Mc at rho_0 = e^-40, to O(rho_0^3)
    jc = edge + cumulative_simpson(rho * j, dx=fine, initial=0.0)
    mc = -edge + cumulative_simpson(rho * m, dx=fine, initial=0.0)
    keep = slice(int(round((t_min - start) / fine)), None, 2)
    table = np.stack([jc[keep], mc[keep], TABLE_STEP * rho[keep] * j[keep], TABLE_STEP * rho[keep] * m[keep]])
    table.flags.writeable = False
    return t_min, TABLE_STEP, table


def integrated(rho: np.ndarray, derivative: bool = False):
    """``(Jc(rho), Mc(rho))`` stacked (shape ``(2, *rho.shape)``) for rho > 0, and with ``derivative`` also their
    t-derivatives ``(rho j, rho m)`` (cubic Hermite on :func:`tables`)."""
    t0, step, table = tables()
    with np.errstate(divide="ignore"):
        raw = (np.log(rho) - t0) * (1.0 / step)
    f = np.maximum(raw, 0.0)
    i = np.minimum(f.astype(np.intp), table.shape[1] - 2)
    u = f - i
    lo = table[:, i]
    hi = table[:, i + 1]
    rise = hi[:2] - lo[:2]
    v = 1.0 - u
    # Hermite: f0 + u rise + u v [v (d0 - rise) - u (d1 - rise)]
    a0 = lo[2:] - rise
    a1 = hi[2:] - rise
    value = lo[:2] + u * (rise + v * (v * a0 - u * a1))
    slope = (rise + a0 * v * (1.0 - 3.0 * u) + a1 * u * (3.0 * u - 2.0)) * (1.0 / step) if derivative else None
    below = raw < 0.0
    if below.any():  # Jc = 2 rho ln(4/rho) = -Mc, t-derivatives 2 rho (ln(4/rho) - 1)
        r = np.where(below, rho, 1.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            near = np.where(r > 0.0, 2.0 * r * np.log(4.0 / r), 0.0)
            value = np.where(below, np.stack([near, -near]), value)
            if derivative:
                rate = np.where(r > 0.0, near - 2.0 * r, 0.0)
                slope = np.where(below, np.stack([rate, -rate]), slope)
    return (value, slope) if derivative else value


@lru_cache(maxsize=1)
def _planes() -> np.ndarray:
    """The tables' cubic Hermite interpolants as polynomials in the fraction u of each interval: the flat array of
    the planes ``(power k, kernel, interval)``, k = 0..3, kernel Jc then Mc, so that the coefficient of ``u^k`` of
    kernel ``c`` on interval ``i`` is at ``i + intervals (c + 2 k)`` (read-only).  ``f0 + u d0 + u^2 (3 r - 2 d0 -
    d1) + u^3 (d0 + d1 - 2 r)``, ``r = f1 - f0``, ``d`` the nodes' ``step df/dt``."""
    _, _, table = tables()
    f0, f1, d0, d1 = table[:2, :-1], table[:2, 1:], table[2:, :-1], table[2:, 1:]
    rise = f1 - f0
    planes = np.stack([f0, d0, 3.0 * rise - 2.0 * d0 - d1, d0 + d1 - 2.0 * rise]).ravel()
    planes.flags.writeable = False
    return planes


class StripGeometry:
    """Field points and source strips of fixed positions (one placement): the logarithms of their distances and
    their signs, so that each evaluation of :meth:`matrices` for new half-lengths only shifts the logarithms.

    :meth:`matrices` reads all eight planes of :func:`_planes` with one gather along the intervals and evaluates both
    kernels at both edges of every strip together in Horner's form.

    Parameters
    ----------
    centres : ndarray
        n field points s_i [m].
    lower, upper : ndarray
        m source strips' edges [m]; no field point on an edge.
    contact_modulus : float
        E* [Pa].
    """

    def __init__(self, centres: np.ndarray, lower: np.ndarray, upper: np.ndarray, contact_modulus: float):
        distances = np.empty((2, centres.size, lower.size))
        np.subtract(centres[:, None], lower, out=distances[0])
        np.subtract(centres[:, None], upper, out=distances[1])
        self.sign = np.sign(distances)
        with np.errstate(divide="ignore"):
            self.log_distance = np.log(np.abs(distances))
            self.inverse_distance = 1.0 / distances
        t0, step, table = tables()
        self.offset = (self.log_distance - t0) * (1.0 / step)  # the table's index of a = 1 m
        self.inverse_step = 1.0 / step
        self.last = table.shape[1] - 2  # the last interval (extrapolated beyond)
        self.planes = _planes().reshape(8, table.shape[1] - 1)  # row kernel + 2 power
        self.scale = (1.0 / (math.pi * contact_modulus), -0.5 / (math.pi * contact_modulus))
        # (kernel, end, n, m): the sign of each end's distance, the lower end added and the upper subtracted, and the
        # kernel's scale (U's, C's)
        self.weights = self.sign * np.array([[[[self.scale[0]]], [[-self.scale[0]]]],
                                             [[[self.scale[1]]], [[-self.scale[1]]]]])

    def subset(self, kept: np.ndarray) -> StripGeometry:
        """The geometry of the field points and sources ``kept`` (indices; square geometries, field point i the
        centre of source i): the same numbers, so its matrices are the blocks of this one's."""
        part = object.__new__(StripGeometry)
        part.__dict__.update(self.__dict__)
        for name in ("sign", "log_distance", "inverse_distance", "offset"):
            setattr(part, name, getattr(self, name).take(kept, -2).take(kept, -1))
        part.weights = self.weights.take(kept, -2).take(kept, -1)
        return part

    def matrices(self, half_lengths: np.ndarray, derivative: bool = False, distances: bool = False):
        """``(U, C)`` (:func:`strip_matrices`) at the sources' ``half_lengths`` [m], with ``derivative`` also
        ``(dU, dC)``, and with ``distances`` (implies ``derivative``) also ``(gU, gC)``, each ``(2, n, m)``: the
        derivatives [1/(Pa m)] of U and C with respect to the distance ``s_i - t`` from the field point to the lower
        (``[0]``) and the upper (``[1]``) edge of each source, ``-(a d/da)/(s_i - t)`` of that edge's term."""
        derivative = derivative or distances
        raw = self.offset - np.log(half_lengths) * self.inverse_step
        whole = np.floor(raw)
        index = whole.astype(np.intp)
        below = np.count_nonzero(raw < 0.0)  # (counts: cheaper than numpy's reductions at these sizes)
        if below or np.count_nonzero(raw >= self.last + 1):
            index = np.minimum(np.maximum(index, 0), self.last)
            whole = index.astype(float)
        # the fraction, once per kernel: in-place products with an operand broadcast over an axis are slow in numpy
        u = np.empty((2, *raw.shape))
        np.subtract(raw, whole, out=u[0])
        u[1] = u[0]
        # (power, kernel, end, n, m): the eight planes' rows at the intervals' indices (in range), in one gather
        q = np.take(self.planes, index, axis=1, mode="clip").reshape(4, 2, *index.shape)
        value = q[3] * u
        value += q[2]
        value *= u
        value += q[1]
        value *= u
        value += q[0]
        if derivative:
            slope = q[3] * (3.0 * u)
            slope += 2.0 * q[2]
            slope *= u
            slope += q[1]
            slope *= -self.inverse_step  # a d/da = -d/dt
        if below:  # Jc = 2 rho ln(4/rho) = -Mc below the table, t-derivatives 2 rho (ln(4/rho) - 1)
            below = raw < 0.0
            r = np.where(below, np.exp(self.log_distance) / half_lengths, 1.0)
            with np.errstate(divide="ignore", invalid="ignore"):
                near = np.where(r > 0.0, 2.0 * r * np.log(4.0 / r), 0.0)
                value = np.where(below, np.stack([near, -near]), value)
                if derivative:
                    rate = np.where(r > 0.0, 2.0 * r * (np.log(4.0 / r) - 1.0), 0.0)
                    slope = np.where(below, np.stack([-rate, rate]), slope)
        value *= self.weights
        U, C = value[:, 0] + value[:, 1]
        if not derivative:
            return U, C
        slope *= self.weights
        dU, dC = slope[:, 0] + slope[:, 1]
        if not distances:
            return U, C, dU, dC
        slope *= -self.inverse_distance
        return U, C, dU, dC, slope[0], slope[1]


def strip_matrices(centres: np.ndarray, lower: np.ndarray, upper: np.ndarray, half_lengths: np.ndarray,
                   contact_modulus: float, derivative: bool = False):
    """The strips' influence on each other's centre lines, per unit ``e = p0 a`` [Pa m] and ``q = p0 / a`` [Pa/m].

    Returns ``(U, C)`` [1/Pa], each ``(n, m)`` for n field points ``centres`` and m source strips
    ``[lower, upper]`` of half-lengths ``half_lengths``: the centre-line displacement
    ``u_z(s_i) = sum_j U_ij e_j`` and the curvature ``-(1/2) d^2u_z/dx^2 (s_i) = sum_j C_ij q_j``, i.e.
    ``U = (Jc(rho_lo) - Jc(rho_hi)) / (pi E*)``, ``C = -(Mc(rho_lo) - Mc(rho_hi)) / (2 pi E*)`` (module docstring).
    With ``derivative`` also ``(dU, dC)``, their derivatives times ``a_j`` with respect to ``a_j``
    (``a d/da K(x/a) = -dK/dt``).  One evaluation of :class:`StripGeometry`.
    """
    return StripGeometry(centres, lower, upper, contact_modulus).matrices(half_lengths, derivative)

