"""The polynomial method's assumptions, checked on its returned fields: one patch, p >= 0, the deformed gap open
outside the patch, ``|q| <= mu p`` in the stick zone at the leading edge and slip with the sign of the creep behind
it.

:func:`validity_failures` names each failure; proven instead of sampled where the surface curvature allows
(:data:`CONVEX`, :data:`STICK_PROVEN`).  Failures that mean several patches (:data:`SEVERAL`) hand the scene to
:mod:`rollcontact.line.methods.polynomial.patches`.  A module of its own so that
:mod:`rollcontact.line.methods.polynomial.solver` holds the solve and this module the checks of its answer.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from rollcontact.line.methods.polynomial.chebyshev import (
    SlopeExpansion,
    orders,
    pressure_table,
    read_only,
    surface_height,
    theta_grid,
    unit_grid,
)
from rollcontact.line.methods.polynomial.distributions import PolynomialDistributions
from rollcontact.line.scene import far_gap_points

# ---------------------------------------------------------------------------------------------------------------
# fields on the patch, validity
SPLIT = "contact splits"


GAP_CLOSES = "the deformed gap closes outside the patch"


SEVERAL = (SPLIT, GAP_CLOSES)
"""How :func:`validity_failures` begins the messages that mean several patches (a negative pressure, a gap that
closes outside the patch): then :func:`rollcontact.line.methods.polynomial.patches.solve_split` takes over."""


CONVEX = 0.99
"""``sup |Z''| < CONVEX / R`` on the patch proves the slip-sign check (and makes xi(a*) monotone)."""


STICK_PROVEN = 0.33
"""``sup |Z''| <= STICK_PROVEN / R`` on the patch proves the stick-zone traction bound."""


def validity_failures(dist: PolynomialDistributions, e: SlopeExpansion, scene, a, x0, m: int,
                      samples: np.ndarray) -> list[str]:
    """The assumptions of the method, checked on the returned fields; each failure named.

    Sampled: ``p >= 0`` on the samples of :func:`pressure_samples` and both edge slopes ``>= 0``; the gap
    outside the patch (:func:`outside_gap`); in the stick zone ``-2 mu p <= q2 <= 0`` (i.e. ``|q| <= mu p``) on
    the angles ``theta_i`` of the zone; in the slip zone ``s xi >= 0`` (:func:`slip_zone_samples`).

    Proven instead of sampled where the curvature allows.  The bounded solution on an interval of half-width h
    about c is ``p(x) = (E*/2) sqrt(h^2 - (x - c)^2) (1/pi) int K(x, tau) dtau / sqrt(1 - tau^2)`` with
    ``K = (h0'(tau) - h0'(x))/(tau - x)``, a mean of ``h0'' = 1/R - Z''``; so ``sup |Z''| <= B`` on the patch
    bounds ``p`` between ``(E*/2) S (1/R -+ B)``, ``S = sqrt(a^2 - (x - X0)^2)``, and the stick-zone correction
    ``q2 = -mu p_h`` (the same solution on the zone, whose root lies inside S) by ``(E*/2) S (1/R + B)``:

    * ``B < 1/R``: ``p_h >= 0``; behind the zone the slip is ``mu D`` with ``D = h0' - G_0 - v_h`` (``v_h``: the
      field of ``p_h``), ``D = 0`` at the zone's edge and ``D' = h0'' - v_h' > 0`` (``v_h' < 0`` outside the zone
      for ``p_h >= 0``): the slip has the sign of the creep (also in full slip, where ``h0'`` increases);
    * ``B <= 1/(3R)``: also ``p_h <= 2 p`` in the zone, the traction bound.

    ``B`` is :meth:`SlopeExpansion.curvature_bound`; the margins are :data:`CONVEX` and :data:`STICK_PROVEN`.
    The fields of the monomial basis are always sampled (that basis is there to measure its own errors).
    """
    out = []
    tol = 1e-9
    c_n = dist.pressure_coefficients
    if dist.monomial_pressure is None:
        p = samples[:-2]
        edges = (float(samples[-2]), float(samples[-1]))
        curvature = e.curvature_bound(x0 - a, x0 + a) * scene.radius
    else:
        p = dist.pressure(dist.offset + a * np.cos(theta_grid(m, c_n.size - 1)[0]))
        edges = (0.0, 0.0)
        curvature = math.inf
    # the extremes by index (argmin/argmax cost a third of the min/max reductions; the same values, NaN included)
    p_min = float(p[p.argmin()])
    p_scale = max(float(p[p.argmax()]), -p_min, 1e-300)
    if p_min < -tol * p_scale or min(edges) < -tol * p_scale:
        i = int(np.argmin(p))
        out.append(f"{SPLIT}: the pressure turns negative (min p = {p[i]:.4g} Pa near x = "
                   f"{dist.offset + a * math.cos(math.pi * (i + 1) / m):.6g} m, edge slopes {edges[0]:.3g}, "
                   f"{edges[1]:.3g} Pa), more than one contact patch")
    gap = outside_gap(dist, e, a, x0)
    if gap is not None:
        out.append(f"{GAP_CLOSES} (gap = {gap[1]:.3g} m at x = {gap[0]:.6g} m): "
                   "a second contact patch")
    if dist.creep == 0.0:
        return out
    mu = dist.mu
    h = dist.stick_half_width
    if h > 0.0 and not curvature <= STICK_PROVEN:
        d = dist.stick_coefficients
        theta, table_s = theta_grid(m, d.size - 1)
        q2 = table_s.dot(d[1:])
        # p at the zone's points x = Xs + h cos(theta_i), i.e. t = -1 + (h/a)(1 + cos(theta_i))
        _, _, one_plus_cos, n, _ = pressure_table(m, c_n.size - 1)
        ps = np.sin(np.arccos((h / a) * one_plus_cos - 1.0)[:, None] * n).dot(c_n[1:])
        excess = np.maximum(q2, -2.0 * mu * ps - q2)
        if float(excess[excess.argmax()]) > tol * mu * p_scale:  # max by index, as p_scale
            i = int(np.argmax(excess > tol * mu * p_scale))
            out.append(f"traction bound |q| <= mu p violated in the stick zone at x = "
                       f"{dist.stick_offset + h * math.cos(theta[i]):.6g} m "
                       "(the stick zone is not a single zone at the leading edge)")
    if not curvature < CONVEX:
        s, t = slip_zone_samples(dist, a)
        if float(s.min()) < -tol * mu * a / scene.radius:
            i = int(np.argmin(s))
            out.append(f"slip opposes the traction in the slip zone (s = {s[i]:.3g} at x = "
                       f"{dist.offset + a * t[i]:.6g} m): a second stick zone")
    return out


def slip_zone_samples(dist: PolynomialDistributions, a: float) -> tuple[np.ndarray, np.ndarray]:
    """``s sign(xi)`` at 47 equally spaced points ``t`` of the slip zone ``(2 a*/a - 1, 1]`` (patch coordinate).

    The field of :meth:`PolynomialDistributions.slip` without its generic branches: there
    ``|xi| + mu sum g_n T_n(t) - mu sum G_n w^n``, ``T_n(t) = cos(n arccos t)``, with the stick-zone coordinate
    ``sigma = (1 + t) a/a* - 1 > 1`` and ``w = 1/(sigma + sqrt(sigma^2 - 1))``.
    """
    h = dist.stick_half_width
    t_lo = 2.0 * h / a - 1.0
    t = t_lo + (1.0 - t_lo) * unit_grid(48)[1:]
    g = dist.slope_coefficients
    s = np.cos(np.arccos(t)[:, None] * orders(g.size - 1)[0][1:]).dot(g[1:])
    if h > 0.0:
        sigma = (1.0 + t) * (a / h) - 1.0  # >= 1 up to round-off
        w = 1.0 / (sigma + np.sqrt(np.maximum(sigma * sigma - 1.0, 0.0)))
        big_g = dist.stick_slope_coefficients
        s -= (w[:, None] ** orders(big_g.size - 1)[0][1:]).dot(big_g[1:])
    return abs(dist.creep) + dist.mu * s, t


def outside_gap(dist: PolynomialDistributions, e: SlopeExpansion, a, x0):
    """First point outside the patch where the deformed gap closes; ``(x, gap)`` or None (axis coordinates).

    Convex gap (``Z'' < CONVEX/R`` everywhere, :meth:`SlopeExpansion.curvature_bound`): the gap cannot close,
    no sampling needed.  Outside the patch the deformed gap is ``h(X) = h0(X) - int_edge^X v``, with
    ``v = (2/(pi E*)) int p(z)/(X - z) dz``; for ``p >= 0`` (checked separately) ``v' < 0`` on both sides, so
    ``h'' = h0'' - v' > 0``, and ``h = h' = 0`` at the edge (bounded solution) makes ``h > 0``.

    Otherwise :func:`deformed_gap` is sampled as far as the surface could touch again (where ``(X - x_c)^2/2R``
    exceeds four times the total amplitude, at least 2a past each edge), 10 samples per shortest wavelength,
    quadratically graded towards the edges.
    """
    if e.curvature_bound(-math.inf, math.inf) * e.radius < CONVEX:
        return None
    reach = 2.0 * a
    spacing = a / 8.0
    if e.has_harmonics:
        amp = sum(math.hypot(phi, psi) for _, phi, psi in e.harmonic_list)
        reach = max(reach, math.sqrt(8.0 * e.radius * amp) + abs(x0))
        spacing = min(spacing, 0.2 * math.pi / e.max_wavenumber)
    m = int(min(2000, max(32, reach / spacing)))
    t, *points = outside_points(m, reach / a)
    gap = deformed_gap(dist, e, a, x0, t, points)
    far = far_points(e, a, x0)
    if far.size:
        t = np.concatenate((t, far))
        gap = np.concatenate((gap, deformed_gap(dist, e, a, x0, far)))
    i = int(gap.argmin())
    if gap[i] < -1e-9 * a * a / e.radius:
        return float(x0 + a * t[i]), float(gap[i])
    return None


def far_points(e: SlopeExpansion, a: float, x0: float) -> np.ndarray:
    """Patch coordinates ``t`` (``|t| > 1``) of :func:`rollcontact.line.scene.far_gap_points` (in axis coordinates):
    where a polynomial part of degree >= 3 can close the gap beyond the sampled reach."""
    t = (far_gap_points(e.axis_surface(), e.radius) - x0) / a
    return t[np.abs(t) > 1.0]


def outer_points(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """What :func:`deformed_gap` needs of its points ``t`` (``|t| > 1``) alone, whatever the patch and its fields.

    Parameters
    ----------
    t : ndarray
        Patch coordinates outside the patch.

    Returns
    -------
    t_edges : ndarray
        ``t`` followed by the two edges, 1 and -1.
    trailing : ndarray of bool
        ``t > 0``: the points behind the trailing edge.
    w : ndarray
        ``1/(t + sign(t) sqrt(t^2 - 1))``, ``|w| < 1``.
    log_w : ndarray
        ``ln|w|``.
    """
    sign = np.sign(t)
    w = 1.0 / (t + sign * np.sqrt(t * t - 1.0))
    return np.append(t, (1.0, -1.0)), sign > 0.0, w, np.log(np.abs(w))


@lru_cache(maxsize=32)
def outside_points(m: int, reach: float) -> tuple[np.ndarray, ...]:
    """The samples of :func:`outside_gap` and their :func:`outer_points`, cached read-only by ``(m, reach)``: a
    profile without harmonics always samples the same ``m = 32`` points at ``reach = 2``, and so does every repeated
    scene.

    Parameters
    ----------
    m : int
        Samples on each side of the patch.
    reach : float
        How far they go past each edge, in half-widths.

    Returns
    -------
    tuple of ndarray
        ``t = 1 + reach (i/m)^2`` then ``-t`` (i = 1..m, quadratically graded towards the edges), followed by the
        four arrays of :func:`outer_points`.
    """
    u = unit_grid(m + 1)[1:] ** 2 * reach
    t = np.concatenate((1.0 + u, -1.0 - u))
    return read_only(t, *outer_points(t))


def deformed_gap(dist: PolynomialDistributions, e: SlopeExpansion, a: float, x0: float, t: np.ndarray,
                 points: tuple | None = None) -> np.ndarray:
    """Deformed gap [m] at ``u = Delta + a t`` (axis coordinates, ``x0 = Delta``) outside the patch (``|t| > 1``),
    in closed form, with the surface of :meth:`SlopeExpansion.axis_surface`.

    With ``t = (w + 1/w)/2`` (``|w| < 1``) the elastic slope is ``v = sum g_n w^n`` and
    ``int w^n dt = (w^(n+1)/(n+1) - w^(n-1)/(n-1))/2`` (``(w^2/2 - ln|w|)/2`` for n = 1), so
    ``h(u) = h0(u) - h0(u_edge) - a sum g_n [I_n(w) - I_n(w_edge)]`` with ``w_edge = sign(t)``: exact at every
    point, no quadrature.  ``points`` are the :func:`outer_points` of ``t`` if the caller has them (cached by
    :func:`outside_points`); they are computed otherwise.
    """
    t_edges, trailing, w, log_w = outer_points(t) if points is None else points
    g = dist.slope_coefficients.tolist()
    n_max = len(g) - 1
    # antiderivative coefficients beta_1 .. beta_(n_max+1): sum_n g_n I_n(w) = sum_j beta_j w^j - (g_1/2) ln|w|
    # (plain floats: a few terms, where each numpy call would cost more than the arithmetic)
    beta = [0.0, *(0.5 * g[j - 1] / j for j in range(2, n_max + 2))]
    for j in range(1, n_max):
        beta[j - 1] -= 0.5 * g[j + 1] / j
    # w^j by cumulative products (np.power is far slower), |w| < 1 so no overflow
    powers = np.multiply.accumulate(np.repeat(w[:, None], n_max + 1, axis=1), axis=1)
    antiderivative = powers.dot(np.array(beta)) - 0.5 * g[1] * log_w
    # h0 at the points and, last, at the two edges (one surface evaluation); there w = +-1 and ln|w| = 0
    u = x0 + a * t_edges
    h0 = u**2 / (2.0 * e.radius) - surface_height(e.axis_surface(), u)
    at_edges = (math.fsum(beta), math.fsum(b if j % 2 else -b for j, b in enumerate(beta)))
    at_edge = np.where(trailing, h0[-2] - a * at_edges[0], h0[-1] - a * at_edges[1])
    return h0[:-2] - a * antiderivative - at_edge
