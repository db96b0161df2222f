"""Contacts of several patches by the polynomial method (an extension of paper section 4.1).

A corrugation short against the contact (``k a`` above about 1) splits the contact: the single-patch solution of
:mod:`rollcontact.line.methods.polynomial.solver` turns the pressure negative between two load-bearing lobes.  Each
patch ``I_k = c_k + h_k t`` then carries its own bounded density ``p_k = (E*/2) sum_{n>=1} g_kn sin(n theta)``, and the
patches act on each other through the smooth field each one produces outside itself.

Fields.  The density ``sin(n theta)`` on ``[-1, 1]`` has the finite Hilbert transform ``T_n(t)`` inside and
``w^n`` outside, ``w = t - sign(t) sqrt(t^2 - 1)`` (``|w| < 1``;
:func:`rollcontact.line.methods.polynomial.chebyshev.outer_transform`). So the elastic slope of patch j is
``v_j = sum_n g_jn T_n(t_j)`` on it and ``sum_n g_jn w_j^n`` elsewhere, and the slope ``h0'`` of the undeformed gap
holds on every patch: ``sum_n g_kn T_n(t_k) = h0' - sum_{j != k} v_j`` on I_k.

Normal problem.  With the Chebyshev coefficients of the right side on I_k (``h0'``: the exact Jacobi-Anger and
Taylor forms of :meth:`~rollcontact.line.methods.polynomial.chebyshev.SlopeExpansion.gap_slope_coefficients`; ``v_j``: a
discrete cosine transform of ``w_j^n`` at M + 8 Gauss-Chebyshev nodes of I_k, geometrically convergent because ``v_j``
is analytic on I_k) the coefficients ``g_kn``, n = 1..M, solve one linear system for given patches.  The 2K edges follow
from 2K equations: per patch the ``T_0`` coefficient vanishes (p bounded at both edges), the loads add up to N', and the
deformed gap is zero at both edges of every gap between patches (one approach for all):
``h0(l_{k+1}) - h0(r_k) = sum_j h_j sum_n g_jn [I_n(w_j)]`` between the two edges, with the antiderivative
``I_n(w) = (w^(n+1)/(n+1) - w^(n-1)/(n-1))/2`` of ``w^n`` in t (``(w^2/2 - ln|w|)/2`` for n = 1).  Newton on the edges,
with a difference Jacobian.

Tangential problem (Coulomb, steady rolling).  Every patch sticks at its leading edge (material enters each patch
free of traction): ``q = mu p + q2`` with ``q2_k = -(E*/2) mu sum G_kn sin(n phi)`` on ``S_k = [l_k, l_k +
2 a*_k]``.  No slip there, ``xi + mu (h0' - sum_j u_j) = 0`` with ``u_j`` the field of the correction on S_j,
is the normal problem's system on the stick zones with right side ``h0' + xi/mu``; its K ``T_0`` conditions fix
the K stick half-widths (0 for a patch in full slip).  ``T' = mu N' - sum_k (pi E* mu/4) a*_k G_k1``.  Newton
on the half-widths; dT'/dxi by the implicit function theorem.

Accuracy.  M is raised until the first neglected coefficients of every right side fall below the target (relative
to the Hertz-like slope ``h_k/R``), which for ``v_j`` means ``rho^-M`` with ``rho`` the Bernstein ellipse through
the nearest edge of patch j: close patches need more terms.  T' is a difference of terms of size mu N', so its
relative error grows like ``mu N'/|T'|`` at small creep: the target is the tolerance times Carter's ``|T'|/(mu
N')``, and Newton stops at :data:`ACCEPTED_FRACTION` of it.  The result's residual is :data:`RESIDUAL_SAFETY`
times the larger of the truncation and Newton's residuals, times ``mu N'/|T'|`` of the solution; it bounds the
relative error of T' and p0 (``tests/methods/polynomial/test_patches.py``).

One patch (K = 1) is the same route: where Newton from the Hertz patch lands on a spurious single patch (across a
crest, with a negative pressure), the discretised start often finds the one patch that is in contact.

Validity (checked on the returned fields, each failure named): p >= 0 on every patch; the deformed gap open
between and beyond the patches; ``|q| <= mu p`` in every stick zone; slip with the sign of the creep in every slip
zone.  A falling friction law is solved on these patches by :mod:`rollcontact.line.methods.polynomial.patches_slip`.
Outside the method (reported, left to the discretised solver): more than :data:`MAX_PATCHES` patches; a patch that slips
at its leading edge and sticks behind it (the slip of the solution turns against the creep; the discretised active set
finds the same structure there, ``benchmarks/bench_multipatch.py`` table A); patches so close that Newton stalls
(where the contact has only just split).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.linalg import lapack

from rollcontact.core.halfspace.elements import MAX_ELEMENTS
from rollcontact.line.halfspace.grid import automatic_grid, patch_geometry
from rollcontact.line.halfspace.solver import fitted_normal
from rollcontact.line.hertz import hertz
from rollcontact.line.methods.polynomial.chebyshev import (
    SlopeExpansion,
    max_pressure,
    outer_transform,
    pressure_samples,
    pressure_table,
    read_only,
    sine_series,
    surface_height,
)
from rollcontact.line.methods.polynomial.newton import Leaving, quasi_newton
from rollcontact.line.result import ContactResult, Distributions
from rollcontact.line.scene import far_gap_points

EXTRA_NODES = 8
"""Gauss-Chebyshev nodes beyond M + 1 for the transforms of the fields: the coefficients M + 1 .. M + 4 that the
residual reads are then free of aliasing from all but far smaller terms."""


@lru_cache(maxsize=16)
def cosine_transform(size: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Chebyshev nodes ``t_i = cos(pi (i + 1/2)/size)`` and the matrix of Chebyshev coefficients
    ``a_m = (2/size) sum_i f(t_i) cos(m phi_i)`` (``a_0`` halved), exact for polynomials of degree < size."""
    phi = np.pi * (np.arange(size) + 0.5) / size
    dct = (2.0 / size) * np.cos(np.multiply.outer(np.arange(size), phi))
    dct[0] *= 0.5
    return read_only(np.cos(phi), dct)


def outer_variable(t: np.ndarray) -> np.ndarray:
    """``w = t - sign(t) sqrt(t^2 - 1)`` for ``|t| >= 1`` in the cancellation-free form ``sign(t)/(|t| +
    sqrt(t^2 - 1))``."""
    at = np.abs(t)
    return np.sign(t) / (at + np.sqrt(np.maximum(at * at - 1.0, 0.0)))


def outer_powers(w: np.ndarray, m: int) -> np.ndarray:
    """``w^n``, n = 1..m, as a (len(w), m) array (cumulative products; |w| <= 1, no overflow)."""
    return np.multiply.accumulate(np.repeat(w[:, None], m, axis=1), axis=1)


def outer_antiderivative(w: np.ndarray, m: int) -> np.ndarray:
    """``I_n(w)``, n = 1..m, the antiderivatives in t of ``w^n`` (``t = (w + 1/w)/2``): ``(w^(n+1)/(n+1) -
    w^(n-1)/(n-1))/2``, and ``(w^2/2 - ln|w|)/2`` for n = 1.  A (len(w), m) array."""
    powers = outer_powers(w, m + 1)  # w^1 .. w^(m+1)
    n = np.arange(1, m + 1, dtype=float)
    out = np.empty((w.size, m))
    out[:, 0] = 0.5 * (0.5 * powers[:, 1] - np.log(np.abs(w)))
    if m > 1:
        out[:, 1:] = 0.5 * (powers[:, 2:] / (n[1:] + 1.0) - powers[:, :-2] / (n[1:] - 1.0))
    return out


def field_coefficients(target: tuple[float, float], source: tuple[float, float], m: int, size: int) -> np.ndarray:
    """Chebyshev coefficients 0 .. size-1 on the interval ``target = (c, h)`` of ``w_s^n``, n = 1..m, the field of
    the density ``sin(n theta)`` on the disjoint interval ``source``: a (size, m) array."""
    nodes, dct = cosine_transform(size)
    t = (target[0] + target[1] * nodes - source[0]) / source[1]
    return dct @ outer_powers(outer_variable(t), m)


def solve_densities(expansion: SlopeExpansion, intervals: list[tuple[float, float]], m: int, shift: float = 0.0):
    """Coefficients ``g_k1 .. g_km`` of the bounded densities on disjoint ``intervals`` (centre, half-width) whose
    summed field is ``h0' + shift`` on every interval, and the coefficients of the part each leaves over.

    Returns
    -------
    g : list of ndarray
        ``[0, g_k1, .., g_km]`` per interval (index 0 is unused, as in
    :mod:`rollcontact.line.methods.polynomial.solver`). leftover : list of ndarray
        Per interval the Chebyshev coefficients 0 .. M + 7 of ``h0' + shift - sum_{j != k} v_j - sum g_kn T_n``:
        entry 0 must vanish for a bounded density (the interval's equation), entries above m are the truncation.
    """
    size = m + 1 + EXTRA_NODES
    k_count = len(intervals)
    gamma = [expansion.gap_slope_coefficients(h, c, size - 1) for c, h in intervals]
    for gk in gamma:
        gk[0] += shift
    fields = [[None if j == k else field_coefficients(intervals[k], intervals[j], m, size) for j in range(k_count)]
              for k in range(k_count)]
    matrix = np.eye(k_count * m)
    rhs = np.empty(k_count * m)
    for k in range(k_count):
        rhs[k * m:(k + 1) * m] = gamma[k][1:m + 1]
        for j in range(k_count):
            if j != k:
                matrix[k * m:(k + 1) * m, j * m:(j + 1) * m] = fields[k][j][1:m + 1]
    _, _, solution, info = lapack.dgesv(matrix, rhs)
    if info != 0:  # singular coupling (patches on top of each other): non-finite residuals end the iteration
        solution = np.full(k_count * m, np.nan)
    g = [np.concatenate(([0.0], solution[k * m:(k + 1) * m])) for k in range(k_count)]
    leftover = []
    for k in range(k_count):
        rest = gamma[k].copy()
        for j in range(k_count):
            if j != k:
                rest -= fields[k][j] @ g[j][1:]
        rest[1:m + 1] -= g[k][1:]
        leftover.append(rest)
    return g, leftover


def intervals_of(edges) -> list[tuple[float, float]]:
    """``[(centre, half-width), ...]`` of the patches ``edges = [l_1, r_1, l_2, r_2, ...]``."""
    return [(0.5 * (edges[i] + edges[i + 1]), 0.5 * (edges[i + 1] - edges[i])) for i in range(0, len(edges), 2)]


def gap_height(expansion: SlopeExpansion, u: np.ndarray) -> np.ndarray:
    """Undeformed gap ``h0(u) = u^2/(2R) - Z(x_c + u)`` [m] (axis coordinates)."""
    return u * u / (2.0 * expansion.radius) - surface_height(axis_surface(expansion), u)


@lru_cache(maxsize=8)
def axis_surface(expansion: SlopeExpansion):
    """:meth:`SlopeExpansion.axis_surface`, built once per expansion (the Newton iterations ask for it at every
    evaluation)."""
    return expansion.axis_surface()


def elastic_rise(g: list[np.ndarray], intervals, lo: float, hi: float) -> float:
    """``int_lo^hi sum_j v_j du`` [m] between two points outside every patch (or on an edge)."""
    centres = np.array([c for c, _ in intervals])
    widths = np.array([h for _, h in intervals])
    t = (np.array([lo, hi])[None, :] - centres[:, None]) / widths[:, None]  # (K, 2)
    table = outer_antiderivative(outer_variable(t.ravel()), g[0].size - 1)
    return sum(h * float((table[2 * j + 1] - table[2 * j]) @ gj[1:])
               for j, (gj, h) in enumerate(zip(g, widths.tolist(), strict=True)))


def normal_residuals(expansion: SlopeExpansion, edges, load: float, estar: float, m: int, a_ref: float):
    """The 2K equations of the normal problem at the patch edges (module docstring), scaled to order one, with
    the densities they were computed from."""
    intervals = intervals_of(edges)
    g, leftover = solve_densities(expansion, intervals, m)
    slope = a_ref / expansion.radius
    out = [float(rest[0]) / slope for rest in leftover]
    carried = sum(0.25 * math.pi * estar * h * float(gk[1]) for (_, h), gk in zip(intervals, g, strict=True))
    out.append(carried / load - 1.0)
    for k in range(len(intervals) - 1):
        lo, hi = edges[2 * k + 1], edges[2 * k + 2]
        h0 = gap_height(expansion, np.array([lo, hi]))
        out.append((float(h0[1] - h0[0]) - elastic_rise(g, intervals, lo, hi)) / (slope * a_ref))
    return np.array(out), g, leftover


def stick_residuals(expansion: SlopeExpansion, leading, halves, xi_over_mu: float, m: int, a_ref: float):
    """The ``T_0`` equations of the stick zones ``[l_k, l_k + 2 a*_k]`` (``leading``: the l_k of the patches that
    stick, ``halves``: their a*_k > 0), scaled by ``a_ref/R``, with the correction coefficients ``G_k`` they were
    computed from."""
    zones = [(lead + a, a) for lead, a in zip(leading, halves, strict=True)]
    big_g, leftover = solve_densities(expansion, zones, m, xi_over_mu)
    slope = a_ref / expansion.radius
    return np.array([float(rest[0]) / slope for rest in leftover]), big_g, leftover


# ---------------------------------------------------------------------------------------------------------------
MAX_TERMS = 400
"""Largest number of terms M per patch."""


MAX_UNKNOWNS = 512
"""Largest number of coefficients K M of all patches together (the dense system of :func:`solve_densities`, whose
cost grows as (K M)^3): beyond it the discretised fallback is the better buy (``benchmarks/bench_multipatch.py``,
table A, and ``benchmarks/pareto.py`` compare the two)."""


MAX_PATCHES = 8
"""More patches than this are left to the discretised solver (a corrugation much shorter than the contact)."""



ACCEPTED_FRACTION = 1e-3
"""Newton's residuals (scaled to order one) are accepted below this fraction of the requested tolerance (and below
1e-13 at the default tolerance); the result's residual reports the larger of them and the truncation."""


RESIDUAL_SAFETY = 10.0
"""Factor on the reported residual (the larger of the truncation and Newton's scaled residuals, times
``mu N'/|T'|``): a margin over the largest ratio of the relative error of T' and p0, against solutions at tolerance
1e-13, to the unfactored value on split scenes (creeps 1e-4 to 0.99 of saturation, tolerances 1e-2 to 1e-6;
``tests/methods/polynomial/test_patches.py::test_reported_residual_bounds_the_error_at_every_tolerance``)."""



DIFFERENCE_STEP = 1e-7
"""Step of the difference Jacobians, relative to the Hertz half-width."""


def series_sum(intervals, coefficients, x, factor: float = 1.0) -> np.ndarray:
    """``sum_k factor sum_n c_kn sin(n theta_k)`` at ``x`` [m] over the ``intervals`` ``(centre, half-width)`` of
    positive half-width (a density per patch or stick zone;
    :func:`rollcontact.line.methods.polynomial.chebyshev.sine_series`, 0 off the interval)."""
    x = np.asarray(x, dtype=float)
    total = np.zeros(x.shape)
    for (c, h), ck in zip(intervals, coefficients, strict=True):
        if h > 0.0:
            total = total + sine_series(factor * ck, (x - c) / h)
    return total


@dataclass(frozen=True)
class PatchesDistributions(Distributions):
    """Fields of a solution with several patches (x [m] from the axis projection, as every method's).

    Attributes
    ----------
    patches : tuple of (float, float)
        ``(centre, half-width)`` [m] of each patch, leading first.
    slope_coefficients : tuple of ndarray
        ``[0, g_1 .. g_M]`` per patch: ``p = (E*/2) sum g_n sin(n theta)``.
    zones : tuple of (float, float)
        ``(centre, half-width)`` [m] of each patch's stick zone (half-width 0: the patch slips throughout).
    stick_slope_coefficients : tuple of ndarray
        ``[0, G_1 .. G_M]`` per zone: ``q2 = -(E*/2) mu sum G_n sin(n phi)``.
    contact_modulus, mu, creep : float
        E* [Pa], mu [1], xi [1].
    """

    patches: tuple
    slope_coefficients: tuple
    zones: tuple
    stick_slope_coefficients: tuple
    contact_modulus: float
    mu: float
    creep: float

    def pressure(self, x):
        return series_sum(self.patches, self.slope_coefficients, x, 0.5 * self.contact_modulus)

    def stick_correction(self, x):
        """``q2`` [Pa] (for the creep's sign taken positive)."""
        return series_sum(self.zones, self.stick_slope_coefficients, x, -0.5 * self.contact_modulus * self.mu)

    def traction(self, x):
        return math.copysign(1.0, self.creep) * (self.mu * self.pressure(x) + self.stick_correction(x))

    def slip(self, x):
        # s = |xi| + mu (sum_j v_j - sum_j u_j): the fields of p and of q2 (chebyshev.outer_transform)
        x = np.asarray(x, dtype=float)
        s = np.full(x.shape, abs(self.creep))
        inside = np.zeros(x.shape, dtype=bool)
        sticking = np.zeros(x.shape, dtype=bool)
        for (c, h), g in zip(self.patches, self.slope_coefficients, strict=True):
            t = (x - c) / h
            s = s + self.mu * outer_transform(g, t)
            inside |= np.abs(t) <= 1.0
        for (c, h), big_g in zip(self.zones, self.stick_slope_coefficients, strict=True):
            if h > 0.0:
                sigma = (x - c) / h
                s = s - self.mu * outer_transform(big_g, sigma)
                sticking |= np.abs(sigma) <= 1.0
        s = np.where(sticking, 0.0, s)
        return np.where(inside, math.copysign(1.0, self.creep) * s, np.nan)


START_ELEMENTS = (64, 8)
"""Elements of the discretised normal solve whose patches start the Newton iteration on the edges: at least the
first, and the second per shortest wavelength of the surface over the solver's automatic window."""


def patch_starts(scene, single: tuple | None) -> list[list[float]]:
    """Edges ``[l_1, r_1, l_2, r_2, ...]`` [m] (axis coordinates) to start :func:`solve_split` from, in the order
    to try them.

    First the patches of a coarse discretised normal solve (:data:`START_ELEMENTS` on the solver's automatic
    window): the single-patch solution that failed is no guide in general, since forced to one patch it can land
    across several crests of a short corrugation, far from where the bodies touch, while the discretised normal
    problem finds the contact set whatever its shape, to an element (a few per cent of a).  Where it finds one
    patch, either that is the patch in contact (the single patch landed astray) or the contact has only just split
    and the gap between the patches is narrower than an element; for the second, the runs of positive pressure of
    the single-patch solution (:func:`lobes`), which is close to the split one there, follow (``single``: its
    offset, half-width and pressure samples; None where the single-patch normal problem did not converge).
    """
    runs = lobes(*single) if single is not None else []
    least, per_wavelength = START_ELEMENTS
    shortest = min((2.0 * math.pi / h.wavenumber for h in scene.surface.harmonics if h.amplitude > 0.0),
                   default=math.inf)
    try:
        elements = max(least, math.ceil(per_wavelength * automatic_grid(scene, least).length / shortest))
        grid, _, normal = fitted_normal(scene, elements=min(elements, MAX_ELEMENTS))
    except ValueError:  # no window the discretised solver accepts (extreme scenes): the single patch's runs
        return [runs] if runs else []
    edges = [edge for patch in patch_geometry(grid, normal.contact)[2] for edge in patch]
    return [edges] if len(edges) > 2 or len(runs) <= 2 else [edges, runs]


def lobes(offset: float, half_width: float, samples: np.ndarray) -> list[float]:
    """Edges ``[l_1, r_1, ...]`` [m] of the runs of positive pressure of a single-patch solution whose ``samples``
    are ``p`` at ``x = offset + a cos(pi i/m)``, i = 1..m-1 (trailing edge first); zero crossings interpolated
    linearly."""
    m = samples.size + 1
    x = offset + half_width * np.cos(np.pi * np.arange(m + 1) / m)[::-1]  # leading edge first
    p = np.concatenate(([0.0], samples[::-1], [0.0]))
    edges = []
    for i in range(1, m + 1):
        if (len(edges) % 2 == 0) == (p[i] > 0.0) and (i < m or len(edges) % 2 == 0):
            # a run starts (p turns positive) or ends (p turns non-positive, before the trailing edge)
            edges.append(x[i - 1] + (x[i] - x[i - 1]) * p[i - 1] / (p[i - 1] - p[i]))
    if len(edges) % 2:
        edges.append(x[m])
    return edges


def initial_terms(expansion: SlopeExpansion, edges: np.ndarray, truncation: float, largest: int) -> int:
    """Terms M to start with: the gap's own :meth:`~SlopeExpansion.required_order` on every patch (at least 8) and
    the decay of the neighbours' fields, ``rho^-M <= truncation`` with ``rho = t + sqrt(t^2 - 1)`` the Bernstein
    ellipse through the nearest neighbouring edge, ``t = 1 + d/h`` (d: the gap to it, h: the patch's half-width);
    at most ``largest``."""
    intervals = intervals_of(edges)
    m = max(8, *(expansion.required_order(h, truncation) for _, h in intervals))
    gaps = np.diff(edges)[1::2]
    for k, (_, h) in enumerate(intervals):
        near = min(gaps[k - 1] if k > 0 else math.inf, gaps[k] if k < gaps.size else math.inf)
        if 0.0 < near < math.inf:
            t = 1.0 + near / h
            m = max(m, math.ceil(math.log(1.0 / truncation) / math.log(t + math.sqrt(t * t - 1.0))))
    return min(m, largest)


def tail(leftover: list[np.ndarray], intervals, m: int, radius: float) -> float:
    """The first neglected coefficients, ``max |leftover_n|`` for n = M+1..M+4, relative to ``h_k/R``."""
    return max(float(np.abs(rest[m + 1:m + 5]).max()) * radius / h for rest, (_, h) in zip(leftover, intervals,
                                                                                         strict=True))


def solve_edges(expansion: SlopeExpansion, edges: np.ndarray, load: float, estar: float, m: int, a_ref: float,
                accept: float):
    """The patch edges at M = ``m`` terms by :func:`quasi_newton`; returns ``(edges, g, leftover, residual,
    evaluations, failure)``, ``residual`` the largest scaled residual left.

    Every step is shortened so that no patch and no gap between patches shrinks by more than half (the edges keep
    their order); the iteration ends after a step below 1e-12 a_ref or at residuals below ``accept``.
    """
    def residuals(x):
        f, g, leftover = normal_residuals(expansion, x, load, estar, m, a_ref)
        return f, (g, leftover)

    def limit(x, dx):
        lengths, dl = np.diff(x), np.diff(dx)
        shrinking = dl < -0.5 * lengths
        if not shrinking.any():
            return dx
        return dx * float((-0.5 * lengths[shrinking] / dl[shrinking]).min())

    edges, f, (g, leftover), evaluations, failure = quasi_newton(residuals, edges, DIFFERENCE_STEP * a_ref, limit,
                                                                 1e-12 * a_ref, accept)
    return edges, g, leftover, float(np.abs(f).max()), evaluations, (f"the patch edges: {failure}" if failure else "")


def tangential_force(load: float, estar: float, mu: float, halves, big_g) -> float:
    """``T' = mu N' - sum_k (pi E* mu/4) a*_k G_k1`` [N/m] (for the creep's sign taken positive): the patches'
    loads ``(pi E*/4) h_k g_k1`` add up to N' (the normal problem), so full slip gives exactly mu N'."""
    quarter = 0.25 * math.pi * estar * mu
    return mu * load - sum(quarter * a * float(gk[1]) for a, gk in zip(halves, big_g, strict=True))


def solve_stick(expansion: SlopeExpansion, edges: np.ndarray, intervals, load: float, estar: float, mu: float,
                xi: float, m: int, a_ref: float, accept: float):
    """Stick half-widths a*_k (0: the patch slips throughout), ``G_k``, T' and dT'/dxi for ``xi >= 0``.

    :func:`quasi_newton` on the a*_k of the sticking patches from Carter's interpolation ``a* = h (1 - xi/xi_k)``
    (at least h/10) with each patch's own saturation creep ``xi_k = -mu h0'(l_k)`` (the creep that a vanishing
    zone at its leading edge needs, the other zones' fields left out), each step kept inside ``(0, h_k]`` (halfway
    to a bound it would cross).  A step that would take a* to 0 or below first probes the patch's equation at
    ``a* = 1e-9 h``: if it still asks for less (``xi`` above the patch's saturation), the patch slips throughout
    and leaves the unknowns.  The iteration ends at residuals below ``accept`` (or a step below 1e-12 a_ref).
    dT'/dxi by the implicit function theorem with a difference Jacobian: ``da*/dxi = -J^-1 dF/dxi``, ``dF_k/dxi =
    1/(mu a_ref/R)``, T' differenced with the same steps.

    Returns ``(halves, big_g, force, stiffness, residual, evaluations, failure)``, ``residual`` the largest scaled
    residual left.
    """
    radius = expansion.radius
    widths = np.array([h for _, h in intervals])
    slope = a_ref / radius
    step = DIFFERENCE_STEP * a_ref
    active = list(range(len(intervals)))
    halves = widths.copy()
    if xi > 0.0:
        lead_slopes = np.array([edges[2 * k] / radius - expansion.moments(0.0, edges[2 * k])[0]
                                for k in range(len(intervals))])
        saturation = np.maximum(-mu * lead_slopes, 1e-300)
        # Carter's a* = h (1 - xi/xi_k), at least 0.1 h (the ratio bounded first: no overflow at any creep)
        halves = widths * np.where(xi >= 0.9 * saturation, 0.1, 1.0 - np.minimum(xi, 0.9 * saturation) / saturation)

    def evaluate(values, which):
        full = np.zeros(len(intervals))
        full[which] = values
        f, big_g, _ = stick_residuals(expansion, edges[0::2][which], full[which], xi / mu, m, a_ref)
        coefficients = [np.zeros(2)] * len(intervals)
        for k, gk in zip(which, big_g, strict=True):
            coefficients[k] = gk
        return f, (coefficients, tangential_force(load, estar, mu, full, coefficients))

    evaluations = 0
    solution = None
    while xi > 0.0 and active:
        which = list(active)
        bounds = widths[which]

        def residuals(values, which=which):
            return evaluate(values, which)

        def limit(values, da, which=which, bounds=bounds):
            nonlocal evaluations
            trial = values + da
            for i in np.flatnonzero(trial <= 0.0):
                probe = values.copy()
                probe[i] = 1e-9 * bounds[i]
                evaluations += 1
                if residuals(probe)[0][i] >= 0.0:
                    raise Leaving(which[i])
            trial = np.where(trial <= 0.0, 0.5 * values, np.where(trial > bounds, 0.5 * (values + bounds), trial))
            return da if np.array_equal(trial, values + da) else trial - values

        try:
            values, f, extras, count, failure = quasi_newton(residuals, halves[which], -step, limit, 1e-12 * a_ref,
                                                             accept)
        except Leaving as leaving:
            halves[leaving.index] = 0.0
            active.remove(leaving.index)
            continue
        evaluations += count
        halves[which] = values
        if failure:
            return halves, None, math.nan, math.nan, math.inf, evaluations, f"the stick zones: {failure}"
        solution = f, extras
        break
    if not active:
        none = [np.zeros(2)] * len(intervals)
        return halves, none, tangential_force(load, estar, mu, halves, none), 0.0, 0.0, evaluations, ""
    values = halves[active]
    if solution is None:  # zero creep: every patch sticks throughout
        solution = evaluate(values, active)
        evaluations += 1
    f, (big_g, force) = solution
    # difference Jacobian and force gradient (inwards: a* = h is a bound)
    jac = np.empty((len(active), len(active)))
    grad = np.empty(len(active))
    for i in range(len(active)):
        shifted = values.copy()
        shifted[i] -= step
        fi, (_, force_i) = evaluate(shifted, active)
        jac[:, i] = (f - fi) / step
        grad[i] = (force - force_i) / step
    evaluations += len(active)
    _, _, rate, info = lapack.dgesv(jac, np.full(len(active), -1.0 / (mu * slope)))
    stiffness = float(grad @ rate) if info == 0 else math.nan
    return halves, big_g, force, stiffness, float(np.abs(f).max()), evaluations, ""


def deformed_gaps(expansion: SlopeExpansion, g, intervals, u: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Deformed gap [m] at points ``u`` outside every patch, relative to its value (zero) at the edges
    ``reference``: ``h0(u) - h0(ref) - sum_j h_j sum_n g_jn [I_n(w_j(u)) - I_n(w_j(ref))]``."""
    h0 = gap_height(expansion, np.concatenate((u, reference)))
    gap = h0[:u.size] - h0[u.size:]
    m = g[0].size - 1
    both = np.concatenate((u, reference))
    for gj, (c, h) in zip(g, intervals, strict=True):
        rise = outer_antiderivative(outer_variable((both - c) / h), m) @ gj[1:]
        gap -= h * (rise[:u.size] - rise[u.size:])
    return gap


def validity_failures(expansion: SlopeExpansion, dist: PatchesDistributions, edges: np.ndarray) -> list[str]:
    """The assumptions, checked on the fields: ``p >= 0`` on every patch with non-negative edge slopes; the deformed
    gap open between and beyond the patches; ``-2 mu p <= q2 <= 0`` in every stick zone; in every slip zone slip
    with the sign of the creep.  Each failure named."""
    out = []
    tol = 1e-9
    intervals, g = dist.patches, dist.slope_coefficients
    estar, mu = dist.contact_modulus, dist.mu
    p_scale = 0.0
    lowest = (math.inf, 0.0)
    for (c, h), gk in zip(intervals, g, strict=True):
        samples = pressure_table(max(64, 4 * gk.size), gk.size - 1)[0].dot(0.5 * estar * gk[1:])
        theta = np.pi * np.arange(1, samples.size - 1) / (samples.size - 1)
        p_scale = max(p_scale, float(samples[:-2].max()))
        i = int(samples[:-2].argmin())
        lowest = min(lowest, (float(samples[:-2][i]), c + h * math.cos(theta[i])))
        lowest = min(lowest, (float(samples[-2]), c + h), (float(samples[-1]), c - h))
    if lowest[0] < -tol * p_scale:
        out.append(f"more patches than {len(intervals)}: the pressure (or its slope at an edge) turns negative "
                   f"({lowest[0]:.4g} near x = {lowest[1]:.6g} m)")
    # the deformed gap between the patches and beyond them, graded towards the edges
    radius = expansion.radius
    lead, trail = float(edges[0]), float(edges[-1])
    half = 0.5 * (trail - lead)
    reach = 2.0 * half
    spacing = half / 8.0
    if expansion.has_harmonics:
        amp = sum(math.hypot(phi, psi) for _, phi, psi in expansion.harmonic_list)
        reach = max(reach, math.sqrt(8.0 * radius * amp) + 0.5 * abs(lead + trail))
        spacing = min(spacing, 0.2 * math.pi / expansion.max_wavenumber)
    count = int(min(2000, max(32, reach / spacing)))
    grade = (np.arange(1, count + 1) / count) ** 2
    points = [lead - reach * grade, trail + reach * grade]
    references = [np.full(count, lead), np.full(count, trail)]
    for k in range(len(intervals) - 1):
        lo, hi = float(edges[2 * k + 1]), float(edges[2 * k + 2])
        inner = 0.5 * (1.0 - np.cos(np.pi * np.arange(1, 32) / 32))
        points.append(lo + (hi - lo) * inner)
        references.append(np.where(inner < 0.5, lo, hi))
    far = far_gap_points(expansion.axis_surface(), radius)
    far = far[(far < lead) | (far > trail)]
    points.append(far)
    references.append(np.where(far < lead, lead, trail))
    u, reference = np.concatenate(points), np.concatenate(references)
    gap = deformed_gaps(expansion, g, intervals, u, reference)
    i = int(gap.argmin())
    if gap[i] < -tol * half * half / radius:
        out.append(f"the deformed gap closes outside the patches (gap = {gap[i]:.3g} m at x = {u[i]:.6g} m): "
                   "another contact patch")
    if dist.creep == 0.0:
        return out
    # all zones' samples in one evaluation of the fields, all slip zones' in another
    zones = [(zc, zh) for zc, zh in dist.zones if zh > 0.0]
    if zones:
        x = np.concatenate([zc + zh * np.cos(np.pi * np.arange(1, 64) / 64) for zc, zh in zones])
        q2 = dist.stick_correction(x)
        excess = np.maximum(q2, -2.0 * mu * dist.pressure(x) - q2)
        j = int(excess.argmax())
        if excess[j] > tol * mu * p_scale:
            out.append(f"traction bound |q| <= mu p violated in the stick zone at x = {x[j]:.6g} m (the stick zone "
                       "of a patch is not a single zone at its leading edge)")
    slipping = [(c - h + 2.0 * zh, c + h) for (c, h), (_, zh) in zip(intervals, dist.zones, strict=True)
                if c - h + 2.0 * zh < c + h]
    if slipping:
        x = np.concatenate([lo + (hi - lo) * np.arange(1, 48) / 48 for lo, hi in slipping])
        s = dist.slip(x) * math.copysign(1.0, dist.creep)
        j = int(s.argmin())
        if s[j] < -tol * mu * half / radius:
            out.append(f"slip opposes the traction in the slip zone (s = {s[j]:.3g} at x = {x[j]:.6g} m): a second "
                       "stick zone")
    return out


def split_target(truncation: float, xi: float, mu: float, slope: float) -> float:
    """The truncation target of the patches for a relative error ``truncation`` of T' and p0 (``slope``: the Hertz
    a/R).

    T' = mu N' - sum (...) loses relative accuracy like mu N'/|T'| at small creep: the target is the truncation times
    Carter's ``|T'|/(mu N')`` on the Hertz patch (the reported residual carries the ratio of the solution); at zero
    creep T' = 0 exactly, nothing to amplify.
    """
    if xi == 0.0:
        return truncation
    ratio = min(abs(xi) / (mu * slope), 1.0)
    return max(truncation * ratio * (2.0 - ratio), 1e-16)


@dataclass(frozen=True)
class SplitNormal:
    """The normal problem of several patches at M = ``terms`` (:func:`split_normal`)."""

    load: float
    edges: np.ndarray  # [l_1, r_1, l_2, r_2, ...] [m], axis coordinates
    g: list  # [0, g_k1 .. g_kM] per patch: p_k = (E*/2) sum g_kn sin(n theta)
    terms: int
    residual: float  # the larger of the truncation (relative to h_k/R) and Newton's scaled residual
    accept: float  # Newton's acceptance of scaled residuals, for the tangential iterations that follow
    iterations: int
    failure: str

    def geometry(self, xi: float) -> dict:
        """The :class:`ContactResult` fields of the outer edges (a, Delta), the load and the creep."""
        lead, trail = float(self.edges[0]), float(self.edges[-1])
        return dict(normal_load_per_length=self.load, creep=xi, contact_half_width=0.5 * (trail - lead),
                    contact_offset=0.5 * (trail + lead))

    def info(self) -> dict:
        edges = self.edges
        return {"patches": [(float(edges[i]), float(edges[i + 1])) for i in range(0, edges.size, 2)],
                "order": self.terms}

    def failed(self, xi: float) -> ContactResult:
        """The failed result that reports :attr:`failure`."""
        if self.edges.size == 0:
            geometry = dict(normal_load_per_length=self.load, creep=xi, contact_half_width=math.nan,
                            contact_offset=math.nan)
            info = {"patches": []}
        else:
            geometry, info = self.geometry(xi), self.info()
        return ContactResult(method="polynomial", success=False, message=f"several patches: {self.failure}",
                             tangential_force_per_length=math.nan, stick_half_width=math.nan, max_pressure=math.nan,
                             iterations=self.iterations, residual=math.inf, info=info, **geometry)


def split_normal(expansion: SlopeExpansion, load: float, estar: float, start: list[float], target: float,
                 order: int | None) -> SplitNormal:
    """The patch edges and pressure densities from the edges ``start`` (:func:`solve_edges`), with M from
    :func:`initial_terms` doubled (at most :data:`MAX_TERMS`, :data:`MAX_UNKNOWNS` over all patches) until the
    first neglected coefficients fall below ``target`` (relative to ``h_k/R``), or M = ``order``."""
    radius = expansion.radius
    a_ref = hertz(load, radius, estar)[0]
    edges = np.array(start, dtype=float)
    count = edges.size // 2
    if not 1 <= count <= MAX_PATCHES or edges.size % 2:
        return SplitNormal(load, np.empty(0), [], 0, math.inf, 0.0, 0,
                           f"{count} patches found, the method takes 1 to {MAX_PATCHES}")
    largest = min(MAX_TERMS, MAX_UNKNOWNS // count)
    m = min(order, largest) if order is not None else initial_terms(expansion, edges, target, largest)
    # Newton stops at residuals ACCEPTED_FRACTION of the target: the error they leave is far below it
    accept = max(1e-13, ACCEPTED_FRACTION * target)
    iterations = 0
    while True:
        edges, g, leftover, left, it, failure = solve_edges(expansion, edges, load, estar, m, a_ref, accept)
        iterations += it
        residual = max(tail(leftover, intervals_of(edges), m, radius), left) if not failure else math.inf
        # converged but truncated: more terms from there (a failure is not retried: Newton stalls where the patches
        # nearly touch, whatever the terms)
        if failure or order is not None or m >= largest or residual <= target:
            break
        m = min(2 * m, largest)
    if not failure and not all(h > 0.0 for _, h in intervals_of(edges)):
        failure = "a patch closed up (its edges crossed)"
    return SplitNormal(load, edges, g, m, residual, accept, iterations, failure)


def solve_split(expansion: SlopeExpansion, load: float, estar: float, mu: float, xi: float, start: list[float],
                truncation: float, order: int | None = None) -> ContactResult:
    """Polynomial method for a contact of several patches (module docstring), from the patch edges ``start``
    (axis coordinates, leading first: :func:`patch_starts`).

    Parameters
    ----------
    expansion : SlopeExpansion
        The gap of the scene.
    load, estar, mu, xi : float
        N' [N/m], E* [Pa], Coulomb's mu [1], creep [1].
    start : list of float
        ``[l_1, r_1, l_2, r_2, ...]`` [m].
    truncation : float
        Requested relative error of T' and p0: M starts from :func:`initial_terms` and doubles (at most
        :data:`MAX_TERMS`, :data:`MAX_UNKNOWNS` over all patches) until the first neglected coefficients fall below
        the target of the module docstring (Accuracy), where Newton also stops.
    order : int, optional
        A fixed M instead.

    Returns
    -------
    ContactResult
        ``residual`` is the error estimate of the module docstring (Accuracy); ``info["patches"]`` the patches'
        ``(leading, trailing)`` edges [m], ``info["stick_zones"]`` the stick zones', ``info["order"]`` M; a, Delta
        from the outer edges, the stick half-width the sum of the zones' (as the discretised method reports them).
    """
    radius = expansion.radius
    a_ref = hertz(load, radius, estar)[0]
    sign = math.copysign(1.0, xi)
    normal = split_normal(expansion, load, estar, start, split_target(truncation, xi, mu, a_ref / radius), order)
    if normal.failure:
        return normal.failed(xi)
    edges, g, m, residual, accept, iterations = (normal.edges, normal.g, normal.terms, normal.residual,
                                                 normal.accept, normal.iterations)
    intervals = intervals_of(edges)
    geometry, info = normal.geometry(xi), normal.info()
    halves, big_g, force, stiffness, left, it, failure = solve_stick(expansion, edges, intervals, load, estar, mu,
                                                                     abs(xi), m, a_ref, accept)
    iterations += it
    residual = RESIDUAL_SAFETY * max(residual, left) * (max(1.0, mu * load / abs(force)) if xi != 0.0 and force
                                                        else 1.0)
    if xi == 0.0:  # every patch sticks throughout: q = mu p - mu p vanishes identically
        force = 0.0
    zones = tuple((float(edges[2 * k]) + float(a), float(a)) for k, a in enumerate(halves))
    info["stick_zones"] = [(float(edges[2 * k]), float(edges[2 * k]) + 2.0 * float(a)) for k, a in enumerate(halves)]
    dist = PatchesDistributions(tuple(intervals), tuple(g), zones, tuple(big_g) if big_g is not None else (),
                                estar, mu, xi)
    messages = [failure] if failure else validity_failures(expansion, dist, edges)
    p_max = max(max_pressure(0.5 * estar * gk, *pressure_samples(0.5 * estar * gk)) for gk in g)
    success = not messages
    count = len(intervals)
    message = (f"converged ({count} patch{'es' if count > 1 else ''})" if success
               else "several patches: " + "; ".join(messages))
    return ContactResult(method="polynomial", success=success, message=message,
                         tangential_force_per_length=sign * force, stick_half_width=float(halves.sum()),
                         max_pressure=p_max, creep_stiffness_per_length=stiffness, iterations=iterations,
                         residual=residual, distributions=dist, info=info, **geometry)
