"""Kalker's creepage coefficients C11, C22, C23, C33 as functions of a/b and nu, interpolated in the table of
:mod:`rollcontact.elliptic.creep_table`.

Interpolation (Kalker 1990, section E; the usual practice): in nu, ``1/C`` is the quadratic through the table's
three Poisson ratios (Lagrange; exact at the nodes); in a/b, ``log C`` is a cubic spline in ``log(a/b)``
(not-a-knot, through every row), smooth where the coefficients vary as powers of a/b.  The table's range of a/b
is the range served: outside it a ValueError names the value and the limits.

The linear theory of the forces on the RAIL (the library's sign, docs/physics.md) is
``Fx = G c^2 C11 xi``, ``Fy = G c^2 (C22 eta + c C23 phi)``, ``Mz = G c^3 (-C23 eta + c C33 phi)``, c = sqrt(ab).
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import NamedTuple

import numpy as np
from scipy.interpolate import CubicSpline

import rollcontact.elliptic.creep_table as creep_table
from rollcontact.core.checks import check_real

__all__ = ["CreepageCoefficients", "aspect_ratio_range", "creepage_coefficients", "extended_creepage_coefficients"]


class CreepageCoefficients(NamedTuple):
    """Kalker's creepage coefficients [1] at one a/b and nu; ``c33`` is NaN where the table has none."""

    c11: float
    c22: float
    c23: float
    c33: float


def aspect_ratio_range() -> tuple[float, float]:
    """(smallest, largest) a/b [1] of the table."""
    return creep_table.ASPECT_RATIOS[0], creep_table.ASPECT_RATIOS[-1]


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
    log_ratio = np.log(creep_table.ASPECT_RATIOS)
    columns = [np.log(in_nu(table, nu)) for table in (creep_table.C11, creep_table.C22, creep_table.C23,
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


@lru_cache(maxsize=1024)
def interpolated(g: float, nu: float) -> CreepageCoefficients:
    """The coefficients at checked a/b and nu (cached: a vehicle model asks for the same contacts every step)."""
    return CreepageCoefficients(*(math.exp(v) for v in splines(nu)(math.log(g)).tolist()))


def extended_creepage_coefficients(aspect_ratio: float, poisson_ratio: float) -> CreepageCoefficients:
    """Kalker's C11, C22, C23, C33 [1] at any a/b > 0: the table's (:func:`creepage_coefficients`) within its range,
    beyond it each ``log C`` continued linearly in ``log(a/b)`` from the table's two end rows (a power law,
    ``C = C_end (C_end / C_inner)^(log(g / g_end) / log(g_end / g_inner))`` with ``g_inner = g_end / 1.5`` above the
    table, ``1.5 g_end`` below it): the rule of the wheel/rail strips for a flange patch longer than the table's
    a/b = 10 (docs/physics.md, "Strips on a patch: the tangential problem").

    Raises
    ------
    ValueError
        a/b not finite and > 0, or nu outside [0, 0.5]; the message names the value and the limit.
    """
    low, high = aspect_ratio_range()
    g = check_real("aspect ratio a/b", aspect_ratio, lower=0.0, lower_open=True)
    if low <= g <= high:
        return creepage_coefficients(g, poisson_ratio)
    first, second = (high, high / 1.5) if g > high else (low, low * 1.5)
    end, inner = creepage_coefficients(first, poisson_ratio), creepage_coefficients(second, poisson_ratio)
    power = math.log(g / first) / math.log(first / second)
    return CreepageCoefficients(*(e * (e / i) ** power for e, i in zip(end, inner, strict=True)))
