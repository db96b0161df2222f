"""Hertz's line contact (paper eqs 9-11): half-width, peak pressure and the semi-elliptic pressure.

Small, pure, scalar functions (plain ``math``): the FMU's closed-form step calls them directly.
"""

from __future__ import annotations

import math

import numpy as np


def hertz(normal_load_per_length: float, radius: float, contact_modulus: float) -> tuple[float, float]:
    """Hertz line contact: half-width and peak pressure.

    Implements ``a = sqrt(4 N' R / (pi E*))`` and ``p0 = 2 N' / (pi a)`` (paper eqs 10-11 with
    ``E* = E / (2 (1 - nu^2))``; docs/physics.md, Closed forms); ``p(x) = p0 sqrt(1 - x^2/a^2)`` (eq 9).

    Parameters
    ----------
    normal_load_per_length : float
        N' [N/m] >= 0.
    radius : float
        Effective radius R [m] > 0.
    contact_modulus : float
        E* [Pa] > 0.

    Returns
    -------
    a : float
        Contact half-width [m].
    p0 : float
        Peak pressure [Pa] (0 when N' = 0).
    """
    a = math.sqrt(4.0 * normal_load_per_length * radius / (math.pi * contact_modulus))
    # p0 = E* a / (2R) equals 2N'/(pi a) and stays finite at N' = 0
    return a, contact_modulus * a / (2.0 * radius)


def ellipse(x, half_width):
    """sqrt(1 - x^2/c^2) inside |x| < c, 0 outside (and 0 for c = 0).

    Evaluated as ``sqrt((c - x)(c + x)) / c``: ``1 - (x/c)^2`` cancels near the edges, where the root then
    magnifies its rounding, up to sqrt(eps) ~ 1.5e-8 within a few eps c of an edge.
    """
    if half_width <= 0.0:
        return np.zeros_like(x)
    return np.sqrt(np.clip((half_width - x) * (half_width + x), 0.0, None)) / half_width
