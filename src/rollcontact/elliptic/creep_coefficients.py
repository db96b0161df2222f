"""Kalker's creepage coefficients C11, C22, C23, C33 as functions of a/b and nu, interpolated in the table of
:mod:`rollcontact.elliptic.creep_table`.

Interpolation (Kalker 1990, section E; the usual practice): in nu, ``1/C`` is the quadratic through the table's
three Poisson ratios (Lagrange; exact at the nodes); in a/b, ``log C`` is a cubic spline in ``log(a/b)``
(not-a-knot, through every row of Kalker's range, :data:`KALKER_RANGE`), smooth where the coefficients vary as
powers of a/b.  That range is the range :func:`creepage_coefficients` serves: outside it a ValueError names the
value and the limits.

The table also holds rows beyond Kalker's, a/b down to 1/30 and up to 30 (a flange's ellipse reaches a/b 20 and
more), computed on coarser grids (the surface grid holds fewer elements across so long an ellipse: their spreads in
``benchmarks/results/creep_coefficients_beyond.md``).  :func:`extended_creepage_coefficients` serves them: ``log C``
linear in ``log(a/b)`` between neighbouring rows there, and beyond the last rows continued as the power law through
the two outermost.  They stay out of the spline, so that their coarser error does not reach into Kalker's range.

The linear theory of the forces on the RAIL (the library's sign, docs/physics.md) is
``Fx = G c^2 C11 xi``, ``Fy = G c^2 (C22 eta + c C23 phi)``, ``Mz = G c^3 (-C23 eta + c C33 phi)``, c = sqrt(ab).
"""

from __future__ import annotations

import bisect
import math
from functools import lru_cache
from typing import NamedTuple

import numpy as np
from scipy.interpolate import CubicSpline

import rollcontact.elliptic.creep_table as creep_table
from rollcontact.core.checks import check_real

__all__ = ["KALKER_RANGE", "CreepageCoefficients", "aspect_ratio_range", "creepage_coefficients",
           "extended_creepage_coefficients"]


class CreepageCoefficients(NamedTuple):
    """Kalker's creepage coefficients [1] at one a/b and nu; ``c33`` is NaN where the table has none."""

    c11: float
    c22: float
    c23: float
    c33: float


KALKER_RANGE = (0.1, 10.0)
"""a/b [1] of Kalker's published rows (Kalker 1990, Table E.3): the rows of the spline, the range of
:func:`creepage_coefficients`."""


def aspect_ratio_range() -> tuple[float, float]:
    """(smallest, largest) a/b [1] of :func:`creepage_coefficients`: Kalker's rows (:data:`KALKER_RANGE`)."""
    return KALKER_RANGE


def _kalker_rows() -> slice:
    """The table's rows within :data:`KALKER_RANGE`."""
    ratios = creep_table.ASPECT_RATIOS
    low, high = KALKER_RANGE
    first = next(k for k, g in enumerate(ratios) if g >= low)
    last = max(k for k, g in enumerate(ratios) if g <= high)
    return slice(first, last + 1)


def in_nu(values, nu: float) -> np.ndarray:
    """Per row, the quadratic in nu through ``1/C`` at the table's Poisson ratios (Lagrange), as C."""
    nodes = creep_table.POISSON_RATIOS
    inverse = 1.0 / np.asarray(values, dtype=float)
    weights = np.ones(len(nodes))
    for i, ni in enumerate(nodes):
        for j, nj in enumerate(nodes):
            if i != j:
                weights[i] *= (nu - nj) / (ni - nj)
    return 1.0 / (inverse @ weights)


@lru_cache(maxsize=32)
def splines(nu: float) -> CubicSpline:
    """The cubic splines of log C in log(a/b) at this nu, one per coefficient, as the columns of one spline (each
    column's the same as a spline of its own, one evaluation for the four)."""
    rows = _kalker_rows()
    log_ratio = np.log(creep_table.ASPECT_RATIOS[rows])
    columns = [np.log(in_nu(table[rows], nu)) for table in (creep_table.C11, creep_table.C22, creep_table.C23,
                                                             creep_table.C33)]
    return CubicSpline(log_ratio, np.stack(columns, axis=1))


def creepage_coefficients(aspect_ratio: float, poisson_ratio: float) -> CreepageCoefficients:
    """Kalker's C11, C22, C23, C33 [1] at a/b = ``aspect_ratio`` and nu = ``poisson_ratio`` (module docstring).

    Raises
    ------
    ValueError
        a/b outside the table's range or nu outside [0, 0.5]; the message names the value and the limits.
    """
    low, high = aspect_ratio_range()
    g = check_real("aspect ratio a/b", aspect_ratio, lower=low, upper=high, unit="(Kalker's table)")
    nu = check_real("poisson_ratio", poisson_ratio, lower=creep_table.POISSON_RATIOS[0],
                    upper=creep_table.POISSON_RATIOS[-1])
    return interpolated(g, nu)


@lru_cache(maxsize=32)
def pieces(nu: float) -> tuple[list[float], list[tuple[tuple[float, float, float, float], ...]]]:
    """The splines of :func:`splines` as plain floats: the breakpoints in log(a/b) and, per interval, each
    coefficient's cubic ``(c0, c1, c2, c3)`` in the distance d from the interval's left end, ``c3 + c2 d + c1 d^2 +
    c0 d^3``."""
    spline = splines(nu)
    c = spline.c.tolist()  # (power, interval, coefficient)
    rows = [tuple((c[0][i][j], c[1][i][j], c[2][i][j], c[3][i][j]) for j in range(len(c[0][i])))
            for i in range(len(c[0]))]
    return spline.x.tolist(), rows


@lru_cache(maxsize=1024)
def interpolated(g: float, nu: float) -> CreepageCoefficients:
    """The coefficients at checked a/b and nu (cached: a vehicle model asks for the same contacts every step): the
    splines evaluated in plain floats (:func:`pieces`), in the order of scipy's ``PPoly`` (the same numbers at a few
    microseconds, for contacts whose a/b changes every step)."""
    breaks, rows = pieces(nu)
    v = math.log(g)
    i = min(max(bisect.bisect_right(breaks, v) - 1, 0), len(breaks) - 2)
    d = v - breaks[i]
    d2 = d * d
    d3 = d2 * d
    return CreepageCoefficients(*(math.exp(c3 + c2 * d + c1 * d2 + c0 * d3) for c0, c1, c2, c3 in rows[i]))


def extended_creepage_coefficients(aspect_ratio: float, poisson_ratio: float) -> CreepageCoefficients:
    """Kalker's C11, C22, C23, C33 [1] at any a/b > 0 (module docstring): within Kalker's range
    :func:`creepage_coefficients`; beyond it each ``log C`` linear in ``log(a/b)`` between the table's neighbouring
    rows (Kalker's end row and the rows beyond it), and beyond the table's last row the power law through its two
    outermost rows, ``C = C_end (C_end / C_inner)^(log(g / g_end) / log(g_end / g_inner))``: the rule of the wheel/rail
    levels for a flange patch longer than Kalker's a/b = 10 (docs/physics.md, "Kalker's creepage coefficients").

    Raises
    ------
    ValueError
        a/b not finite and > 0, or nu outside [0, 0.5]; the message names the value and the limit.
    """
    low, high = KALKER_RANGE
    g = check_real("aspect ratio a/b", aspect_ratio, lower=0.0, lower_open=True)
    if low <= g <= high:
        return creepage_coefficients(g, poisson_ratio)
    nu = check_real("poisson_ratio", poisson_ratio, lower=creep_table.POISSON_RATIOS[0],
                    upper=creep_table.POISSON_RATIOS[-1])
    return beyond_kalker(g, nu)


@lru_cache(maxsize=1024)
def beyond_kalker(g: float, nu: float) -> CreepageCoefficients:
    """:func:`extended_creepage_coefficients` at a checked a/b outside Kalker's range and nu (cached as
    :func:`interpolated`)."""
    ratios = creep_table.ASPECT_RATIOS
    rows = range(_kalker_rows().stop - 1, len(ratios)) if g > KALKER_RANGE[1] else range(_kalker_rows().start, -1, -1)
    rows = list(rows)  # from Kalker's end row outwards
    k = next((j for j in range(1, len(rows)) if (ratios[rows[j]] >= g if g > 1.0 else ratios[rows[j]] <= g)),
             len(rows) - 1)
    inner, outer = rows[k - 1], rows[k]
    values = [in_nu((table[inner], table[outer]), nu) for table in (creep_table.C11, creep_table.C22,
                                                                     creep_table.C23, creep_table.C33)]
    share = math.log(g / ratios[inner]) / math.log(ratios[outer] / ratios[inner])
    return CreepageCoefficients(*(float(i * (o / i) ** share) for i, o in values))
