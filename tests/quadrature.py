"""Independent quadrature oracles shared by the tests (QUADPACK on the returned fields, never the solvers' own
expansions)."""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.integrate import IntegrationWarning, quad


def edge_quad(f, breakpoints, epsrel=1e-13):
    """``int f dx`` over consecutive intervals whose ends may carry square-root behaviour.

    Each interval ``[l, r]`` is mapped by ``x = l + (r - l)(1 - cos theta)/2``, which makes sqrt end behaviour
    smooth in theta, so QUADPACK converges to round-off.

    Parameters
    ----------
    f : callable
        Vectorised integrand of x.
    breakpoints : sequence of float
        Increasing interval ends.
    epsrel : float
        Requested relative accuracy per interval.

    Returns
    -------
    float
        The integral.
    """
    total = 0.0
    for lo, hi in zip(breakpoints[:-1], breakpoints[1:], strict=True):
        if hi <= lo:
            continue
        half = 0.5 * (hi - lo)

        def g(theta, lo=lo, half=half):
            return float(f(np.array([lo + half * (1.0 - math.cos(theta))]))[0]) * half * math.sin(theta)

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", IntegrationWarning)
            total += quad(g, 0.0, math.pi, epsabs=0.0, epsrel=epsrel, limit=200)[0]
    return total


def pv_hilbert(f, breakpoints, x, *, epsrel=1e-12):
    """Principal value ``(1/pi) PV-int f(z) / (x - z) dz`` over ``[breakpoints[0], breakpoints[-1]]``.

    The piece holding ``x`` goes to QUADPACK's QAWC (``quad(weight='cauchy')`` computes ``PV-int f/(z - x)``,
    hence the sign flip); the other pieces are regular and go through :func:`edge_quad`.

    Parameters
    ----------
    f : callable
        Vectorised density.
    breakpoints : sequence of float
        Increasing ends of the pieces on which ``f`` is smooth.
    x : float
        Singular point, strictly inside one piece.
    epsrel : float
        Requested relative accuracy of the singular piece.

    Returns
    -------
    float
        The principal value divided by pi.
    """
    total = 0.0
    for lo, hi in zip(breakpoints[:-1], breakpoints[1:], strict=True):
        if hi <= lo:
            continue
        if lo < x < hi:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", IntegrationWarning)
                val, _ = quad(lambda z: float(f(np.array([z]))[0]), lo, hi, weight="cauchy", wvar=x, epsabs=0.0,
                              epsrel=epsrel, limit=500)
            total -= val
        else:
            total += edge_quad(lambda z: f(z) / (x - z), [lo, hi])
    return total / math.pi


def pressure_integral(result, nodes=400):
    """``int p dx`` by Gauss-Chebyshev quadrature of the second kind (interior nodes only).

    Parameters
    ----------
    result : ContactResult
        Solution; with several patches (``info["stick_zones"]``: rollcontact.multipatch) the rule runs on each.
    nodes : int
        Number of nodes (per patch).

    Returns
    -------
    float
        N' recomputed from ``result.pressure``.
    """
    theta = np.pi * np.arange(1, nodes + 1) / (nodes + 1)
    patches = (result.info["patches"] if "stick_zones" in result.info
               else [(result.contact_offset - result.contact_half_width,
                      result.contact_offset + result.contact_half_width)])
    total = 0.0
    for lo, hi in patches:
        a, centre = 0.5 * (hi - lo), 0.5 * (hi + lo)
        total += float(a * np.pi / (nodes + 1) * np.sum(np.sin(theta) * result.pressure(centre + a * np.cos(theta))))
    return total
