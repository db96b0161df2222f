"""The polynomial approximation method (paper sections 3-4.1) in a stable Chebyshev basis.

Normal problem.  On the patch ``X = X0 + a t`` (``X0 = x_c + Delta``) the pressure is the bounded density
``p = sum_{n>=1} c_n sin(n theta)``, ``t = cos(theta)``, which answers ``(2/(pi E*)) PV-int p/(x-z) dz =
(2/E*) sum c_n T_n(t)`` (chebyshev.py).  Matching the gap slope ``h0'`` gives ``c_n = (E*/2) g_n`` with ``g_n``
the Chebyshev coefficients of ``h0'(X0 + a t)``; a bounded solution needs ``g_0 = 0`` (fixes Delta) and the
load is ``N' = (pi a / 2) c_1`` (fixes a).  For harmonics ``g_0`` and ``g_1`` are the exact Bessel forms of
physics.md eqs 28-29 (corrected), so a and Delta carry no truncation error; the order only limits p(x).
Every position is computed in axis coordinates ``u = X - x_c`` (the patch is ``u = Delta + a t``;
:class:`~rollcontact.chebyshev.SlopeExpansion`), so the answer does not depend on how far along the surface the
axis stands (surface coordinates would lose ``eps |x_c|`` in every ``X - x_c``).

Tangential problem (Coulomb).  ``q = mu p + q2`` with ``q2 = sum d_n sin(n theta*)`` on the stick zone
``[X0 - a, X0 - a + 2 a*]`` (centre ``Xs``).  No slip there, ``xi + du/dx = 0``, gives
``d_n = -(E*/2) mu G_n`` (``G_n``: coefficients of ``h0'(Xs + a* t)``) and the creep
``xi = -mu G_0`` (eq 31 corrected), ``T' = mu N' + (pi a*/2) d_1`` (eq 30).  Negative creep mirrors q.  Both
vanish at ``a* = a``; the unknown is the slip width ``a - a*``, and at small creep xi and T' are integrated from
those zeros (:func:`solve_tangential`), so T' keeps its relative accuracy down to any creep.  A velocity-dependent
law that stays within :data:`COULOMB_REDUCTION` of mu_s over the slip velocities of the patch is solved as
Coulomb friction (:func:`coulomb_reduction`), otherwise by the slip iteration of section 4.2.

Validity (one patch, one stick zone at the leading edge) is checked on the returned fields: ``p >= 0``; the
deformed gap stays open outside the patch; ``|q| <= mu p`` in the stick zone; slip has the sign of the traction
in the slip zone.  A failed check gives ``success = False`` and a message naming it.  Where the contact has
several patches (the pressure turns negative, or the gap closes outside the patch), :mod:`rollcontact.multipatch`
solves it with one expansion per patch and stick zone (one stick zone at each patch's leading edge, checked
likewise; a velocity-dependent law on its patches by :mod:`rollcontact.split_friction`), from the patches of a
coarse discretised normal solve (which also finds the one patch in contact where Newton from the Hertz patch
landed on a spurious one); only when that fails too is the result unsuccessful.

The paper's monomial formulation (eqs 21-26; note eq 26 needs ``A_n^-1 = +(1/pi) a^(2n-2)/(2n-3) prod...``
for n >= 2, the printed minus sign is wrong: ``A = -pi (1 - a^2 S)^(-1/2)`` so ``A^-1 = -(1/pi)(1 - a^2 S)^(1/2)``)
is available as ``basis="monomial"`` to measure its conditioning.

Cost.  A solve is a few dozen operations on vectors of ~10-60 entries, so per-call overhead decides the time:
Newton iterations run on plain floats, tables that depend only on sizes are cached (:mod:`rollcontact.chebyshev`),
and the pressure samples serve both the checks and ``max_pressure``.  Products of arrays are ``ndarray.dot``, the
same BLAS call as ``@`` (the same bits) without the gufunc dispatch, which costs about a microsecond per product.
Where the surface curvature allows, a theorem replaces sampling: with ``|Z''| < 1/R`` on the patch the creep
``xi(a*)`` of eq 31 decreases (unique root, no scan) and the slip has the sign of the creep; with
``|Z''| <= 1/(3R)`` the stick-zone traction bound holds; with ``Z'' < 1/R`` everywhere the deformed gap cannot close
outside the patch (:func:`validity_failures`, :func:`outside_gap`).  Otherwise the checks sample as before.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy import linalg

from rollcontact.api import register_method
from rollcontact.chebyshev import (
    SlopeExpansion,
    max_pressure,
    orders,
    outer_transform,
    pressure_samples,
    pressure_table,
    read_only,
    sine_series,
    surface_height,
    theta_grid,
    unit_grid,
)
from rollcontact.closed_form import hertz
from rollcontact.multipatch import patch_starts, solve_split, split_normal, split_target
from rollcontact.result import ContactResult, Distributions, NoContact
from rollcontact.split_friction import solve_split_velocity
from rollcontact.velocity_friction import DEFAULT_NODES, default_nodes, solve_velocity_dependent

__all__ = ["PolynomialDistributions", "monomial_density", "solve_polynomial"]

BASES = ("chebyshev", "monomial")


# ---------------------------------------------------------------------------------------------------------------
# monomial backend (paper eqs 19-26)
def monomial_matrix(h: float, order: int) -> np.ndarray:
    """The paper's matrix of eq 21: ``beta_k = sum_n A_n B_{k+2n-1}``, ``A_n = -pi h^(2n-2) prod (2i-3)/(2i-2)``
    (eqs 22-23, verified: the PV integral of ``zeta^m / ((x-zeta) sqrt(h^2-zeta^2))`` is
    ``-pi sum_{j even} h^j (j-1)!!/j!! x^(m-1-j)``)."""
    coef = np.empty(order)
    coef[0] = -math.pi
    prod = 1.0
    for n in range(2, order + 1):
        prod *= (2 * n - 3) / (2 * n - 2)
        coef[n - 1] = -math.pi * h ** (2 * n - 2) * prod
    m = np.zeros((order, order))
    for k in range(order):
        for n in range(1, order + 1):
            j = k + 2 * n - 1  # index of B_j, column j-1
            if j <= order:
                m[k, j - 1] = coef[n - 1]
    return m


def monomial_density(taylor: np.ndarray, h: float):
    """Solve ``(1/pi) PV-int f(z)/(x - z) dz = sum_k e_k x^k`` on |x| < h in the paper's monomial form.

    ``f = B(x)/sqrt(h^2 - x^2)`` with ``B(+h) = 0``.  Returns ``(B, r0, r1, cancellation)``: the power
    coefficients of B, the T0 and T1 Chebyshev coefficients of the right-hand side recovered from B
    (``r0 = -(1/h) sum_odd B_n h^n``, ``r1 = (2/(pi h)) int f - 2 r0``), and the cancellation factor
    ``sum |B_n| h^n / max |B(x)|`` (|x| <= h): how much round-off the power basis amplifies.  The triangular
    matrix itself stays well conditioned (its diagonal is -pi); the precision is lost in the power-basis sums,
    whose terms grow like (k h)^n / n! for harmonics and whose coefficients scale like h^(-n).
    """
    order = taylor.size
    m = monomial_matrix(h, order)
    with np.errstate(all="ignore"):
        b_tail = linalg.solve_triangular(m, math.pi * taylor, check_finite=False)
        powers = h ** np.arange(1, order + 1)
        b0 = -np.dot(b_tail, powers)
        b = np.concatenate(([b0], b_tail))
        odd = b[1::2] @ powers[0::2]
        r0 = -odd / h
        even_idx = np.arange(0, order + 1, 2)
        weights = np.array([math.pi * h**n * dfr(n) for n in even_idx])
        integral = b[0::2] @ weights
        r1 = 2.0 * integral / (math.pi * h) - 2.0 * r0
        xs = h * np.cos(np.pi * np.arange(33) / 32)
        peak = float(np.max(np.abs(np.polynomial.polynomial.polyval(xs, b))))
        cancellation = float(np.sum(np.abs(b) * h ** np.arange(order + 1))) / peak if peak > 0 else math.inf
    return b, r0, r1, cancellation if math.isfinite(cancellation) else math.inf


def dfr(n: int) -> float:
    r = 1.0
    for i in range(2, n + 1, 2):
        r *= (i - 1) / i
    return r


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


# ---------------------------------------------------------------------------------------------------------------
class NormalProblem:
    """T0/T1 moments G0, G1 of ``h0'(c + h t)`` (c in axis coordinates) with derivatives, in either basis."""

    def __init__(self, expansion: SlopeExpansion, basis: str, order: int | None):
        self.e = expansion
        self.basis = basis
        self.order = order
        self.cancellation = 1.0

    def moments(self, h, c):
        e = self.e
        if self.basis == "chebyshev":
            m0, m1, d0h, d0c, d1h, d1c = e.moments(h, c)
            inv_r = 1.0 / e.radius
            return (c * inv_r - m0, h * inv_r - m1, -d0h, inv_r - d0c, inv_r - d1h, -d1c)
        g0, g1 = self.monomial_moments(h, c)
        dh = 1e-7 * h
        g0h, g1h = self.monomial_moments(h + dh, c)
        g0c, g1c = self.monomial_moments(h, c + dh)
        return g0, g1, (g0h - g0) / dh, (g0c - g0) / dh, (g1h - g1) / dh, (g1c - g1) / dh

    def monomial_moments(self, h, c):
        _, r0, r1, self.cancellation = monomial_density(self.e.gap_slope_taylor(c, self.order), h)
        return r0, r1


def solve_normal(problem: NormalProblem, load: float, estar: float, a0: float, max_iterations: int):
    """Newton on (a, Delta): ``G0(a, Delta) = 0`` and ``(pi E* a / 4) G1(a, Delta) = N'`` (eqs 28-29), with the
    patch centre ``Delta = X0 - x_c`` in axis coordinates.

    The start is one fixed-point step of both equations from Hertz with the surface moments frozen at
    ``(a_H, 0)``: ``Delta = R m0`` (eq 29) and the positive root of ``a^2/R - a m1 = a_H^2/R`` (eq 28,
    ``G1 = a/R - m1``).  It removes the first-order effect of the surface, which saves one or two Newton steps.
    """
    R = problem.e.radius
    a = a0
    g0, g1 = problem.moments(a, 0.0)[:2]
    c = -R * g0 if math.isfinite(g0) else 0.0
    rm1 = R * (a0 / R - g1)
    if math.isfinite(rm1):
        a = 0.5 * (rm1 + math.sqrt(rm1 * rm1 + 4.0 * a0 * a0))
    k = math.pi * estar / 4.0
    scale_f1 = a0 / R
    for it in range(1, max_iterations + 1):
        g0, g1, g0h, g0c, g1h, g1c = problem.moments(a, c)
        f1 = g0
        f2 = k * a * g1 - load
        j21, j22 = k * (g1 + a * g1h), k * a * g1c
        det = g0h * j22 - g0c * j21
        if not math.isfinite(det) or det == 0.0:
            return a, c, it, f"normal problem: singular Newton matrix at a = {a:.6g} m"
        da = (f1 * j22 - g0c * f2) / det
        dc = (g0h * f2 - f1 * j21) / det
        lim = 0.5 * a
        if abs(da) > lim or abs(dc) > lim:  # damping keeps a > 0 and the patch near its start
            s = lim / max(abs(da), abs(dc))
            da, dc = da * s, dc * s
        a -= da
        c -= dc
        # converged: Newton is quadratic here, so after a step of 1e-10 a the error is ~1e-20 a (this saves the
        # confirming evaluation); residuals at round-off (~1e-13 of their scales) are as good as it gets
        if abs(da) <= 1e-10 * a0 and abs(dc) <= 1e-10 * a0 or (abs(f1) <= 1e-13 * scale_f1 and
                                                                 abs(f2) <= 1e-13 * load):
            return a, c, it, ""
    if abs(f1) <= 1e-10 * scale_f1 and abs(f2) <= 1e-10 * load:
        return a, c, max_iterations, ""
    return a, c, max_iterations, (f"normal problem: Newton did not converge in {max_iterations} iterations "
                                  f"(a = {a:.6g} m, residuals {f1:.3g}, {f2:.3g} N/m)")


def solve_polynomial(scene, *, order: int | None = None, tolerance: float = 1e-10, basis: str = "chebyshev",
                     max_iterations: int = 60, check: bool = True, nodes: int = DEFAULT_NODES) -> ContactResult:
    """Polynomial method for a steady scene (paper sections 3, 4.1 and, for velocity-dependent friction, 4.2).

    Parameters
    ----------
    scene : Scene
        Any surface: polynomial part and/or harmonics.
    order : int, optional
        Number of Chebyshev terms (or monomial degree) of the distributions; by default the smallest order
        whose neglected coefficients are below ``tolerance`` (relative to the Hertz slope a/R).  With Coulomb
        friction a, Delta, a* and T' are exact at every order (eqs 28-31 are closed forms); the order sets the
        accuracy of p(x), q(x), s(x) and of the checks.
    tolerance : float
        Target relative truncation error of the distributions, > 0.
    basis : {"chebyshev", "monomial"}
        The stable basis, or the paper's monomial matrices (eqs 21-26) whose conditioning degrades as a^(2n).
    max_iterations : int
        Newton iterations for the normal problem.
    nodes : int
        Least number of Chebyshev nodes of the slip iteration for velocity-dependent friction (paper section
        4.2).  Raised to 32 or 64 for steep laws, which need them for 1e-3 in T'
        (:func:`rollcontact.velocity_friction.default_nodes`, measured in ``benchmarks/bench_steady.py``), and to
        twice the number of pressure terms.
    check : bool
        Run the validity checks (one patch, stick at the leading edge).  Only switch off when the caller has
        established validity otherwise.

    Returns
    -------
    ContactResult
        ``residual`` is the truncation estimate of the distributions (size of the first neglected coefficients
        relative to the leading one); ``info`` holds the order, basis, coefficients and, for the monomial basis,
        the cancellation factor of the paper's power basis (``info["cancellation_factor"]``); for a
        velocity-dependent law solved as Coulomb friction, ``info["coulomb_reduction"]`` says why
        (:func:`coulomb_reduction`).  Solved as several patches (:func:`rollcontact.multipatch.solve_split`):
        ``info["patches"]`` and ``info["stick_zones"]`` (leading and trailing ends [m]), a and Delta from the outer
        edges, the stick half-width the sum of the zones'.
    """
    if basis not in BASES:
        raise ValueError(f"unknown basis {basis!r}; valid bases are {list(BASES)}")
    if order is not None and (int(order) != order or not 1 <= order <= 2000):
        raise ValueError(f"order = {order!r} is out of range: it must be an integer in [1, 2000]")
    if not (math.isfinite(tolerance) and tolerance > 0.0):
        raise ValueError(f"tolerance = {tolerance!r} must be finite and > 0")
    friction = scene.friction
    if not friction.is_constant and basis != "chebyshev":
        raise ValueError("velocity-dependent friction needs basis='chebyshev'")
    load = scene.normal_load_per_length
    estar = scene.material.contact_modulus
    mu = friction.static_coefficient
    xi = scene.creep
    R = scene.radius
    if load == 0.0:
        return ContactResult(method="polynomial", success=True, message="no load: no contact",
                             normal_load_per_length=0.0, tangential_force_per_length=0.0, creep=xi,
                             contact_half_width=0.0, contact_offset=0.0, stick_half_width=0.0, max_pressure=0.0,
                             creep_stiffness_per_length=0.0, distributions=NoContact())
    expansion = SlopeExpansion(R, scene.axis_position, scene.surface)
    a_hertz, _ = hertz(load, R, estar)
    monomial_order = order if order is not None else max(4, expansion.slope_poly.size + 2)
    problem = NormalProblem(expansion, basis, monomial_order)
    a, x0, iterations, failure = solve_normal(problem, load, estar, a_hertz, max_iterations)
    info = {"basis": basis}
    several_apply = check and basis == "chebyshev"
    if failure or not (a > 0.0 and math.isfinite(a) and math.isfinite(x0)):
        failure = failure or f"normal problem: no positive root for a (a = {a!r} m)"
        if several_apply and expansion.has_harmonics:  # a short corrugation: Newton lost among the crests
            several = several_patches(scene, expansion, tolerance, order, None, nodes)
            if several.success:
                return several
            failure += "; " + several.message
        return failed(scene, failure, a, x0, iterations, info)

    n_order = order if order is not None else expansion.required_order(a, tolerance)
    g = expansion.gap_slope_coefficients(a, x0, n_order + 4)
    g_list = g.tolist()
    residual = max(map(abs, g_list[n_order + 1:])) / abs(g_list[1]) if g_list[1] != 0 else math.inf
    g = g[: n_order + 1]
    c_n = 0.5 * estar * g
    monomial_b = None
    if basis == "monomial":
        b, _, _, cancellation = monomial_density(expansion.gap_slope_taylor(x0, monomial_order), a)
        monomial_b = 0.5 * estar * b
        info["cancellation_factor"] = cancellation
        residual = cancellation * float(np.finfo(float).eps)
    info.update(order=n_order, pressure_coefficients=c_n)
    m, samples = pressure_samples(c_n)

    if friction.is_constant:
        tangential = solve_tangential(expansion, a, x0, load, estar, mu, xi, order, tolerance)
    else:
        tangential = coulomb_reduction(scene, expansion, a, x0, g, info, order, tolerance)
        if tangential is None:
            return solve_with_velocity_friction(scene, expansion, a, x0, c_n, g, iterations, residual, info, check,
                                                nodes, (m, samples), tolerance, order)
    stick, d_n, G, t_force, stiffness, tang_failure = tangential
    dist = PolynomialDistributions(a, x0, c_n, g, stick, x0 - a + stick, d_n, G, mu, xi, monomial_b)
    messages = []
    if tang_failure:
        messages.append(tang_failure)
    if check:
        messages += validity_failures(dist, expansion, scene, a, x0, m, samples)
        if several_apply and any(text.startswith(SEVERAL) for text in messages):
            several = several_patches(scene, expansion, tolerance, order, (x0, a, samples[:-2]), nodes)
            if several.success:
                return several
            messages.append(several.message)
            info["patches"] = several.info["patches"]
    if monomial_b is None:
        p_max = max_pressure(c_n, m, samples)
    else:
        p_max = float(np.max(dist.pressure(x0 + a * (1.998 * unit_grid(401) - 0.999))))
    success = not messages
    if success:
        message = "full slip (saturated)" if stick == 0.0 and xi != 0.0 else "converged"
    else:
        message = "; ".join(messages) + "; use method='discretised'"
    info["stick_coefficients"] = d_n
    return ContactResult(method="polynomial", success=success, message=message, normal_load_per_length=load,
                         tangential_force_per_length=t_force, creep=xi, contact_half_width=a,
                         contact_offset=x0, stick_half_width=stick, max_pressure=p_max,
                         creep_stiffness_per_length=stiffness, iterations=iterations, residual=residual,
                         distributions=dist, info=info)


solve_polynomial.options = ("order", "tolerance", "basis", "max_iterations", "nodes")


def several_patches(scene, expansion: SlopeExpansion, tolerance: float, order: int | None,
                    single: tuple | None, nodes: int) -> ContactResult:
    """The scene as several patches from each start of :func:`rollcontact.multipatch.patch_starts` in turn: the
    first success, else the last failure.  ``single`` is ``(offset, half-width, pressure samples)`` of the failed
    single-patch solution, None where its normal problem did not converge.

    Coulomb friction, and any law at zero creep (full stick, q = 0): :func:`rollcontact.multipatch.solve_split`.
    A velocity-dependent law: the patches of :func:`rollcontact.multipatch.split_normal`, then the slip iteration
    on them (:func:`rollcontact.split_friction.solve_split_velocity`, at least ``nodes`` nodes per patch).
    """
    load, estar, friction, xi = (scene.normal_load_per_length, scene.material.contact_modulus, scene.friction,
                                 scene.creep)
    mu_s = friction.static_coefficient
    target = split_target(tolerance, xi, mu_s, hertz(load, scene.radius, estar)[0] / scene.radius)
    for start in patch_starts(scene, single) or [[]]:  # no start: solve_split reports that no patch was found
        if friction.is_constant or xi == 0.0:
            several = solve_split(expansion, load, estar, mu_s, xi, start, tolerance, order)
        else:
            normal = split_normal(expansion, load, estar, start, target, order)
            several = (normal.failed(xi) if normal.failure else
                       solve_split_velocity(expansion, normal, estar, friction, scene.rolling_speed, xi,
                                            max(nodes, *(default_nodes(0.5 * estar * g, estar, friction,
                                                                       scene.rolling_speed) for g in normal.g))))
        if several.success:
            several.info["basis"] = "chebyshev"
            return several
    return several


COULOMB_REDUCTION = 1e-10
"""Largest relative change ``|mu(v)/mu_s - 1|`` over the slip velocities of the patch for which a
velocity-dependent law is solved as Coulomb friction with mu_s (:func:`coulomb_reduction`): a tenth of the slip
iteration's tolerance."""


def friction_change(friction, slip_velocity: float) -> float:
    """``|mu(v)/mu_s - 1|`` at ``v``: the largest change over [0, v] for a law monotone there (every law of
    :mod:`rollcontact.friction`; a user table if its coefficients are monotone up to v)."""
    return abs(float(friction.coefficient(slip_velocity)) / friction.static_coefficient - 1.0)


def coulomb_reduction(scene, e: SlopeExpansion, a, x0, g, info, order, tolerance):
    """:func:`solve_tangential` with ``mu = mu_s`` if a velocity-dependent law cannot tell it from Coulomb's, else
    None (then :func:`solve_with_velocity_friction` solves the problem).

    The Coulomb solution with mu_s slips, by its series (:meth:`PolynomialDistributions.slip`: ``|T_n| <= 1`` on
    the patch, ``|w^n| <= 1`` off the stick zone), at most ``S = |xi| + mu_s (sum_{n>=1} |g_n| + sum_{n>=1} |G_n|)``
    (Carter: ``|xi| + mu_s (a + a*)/R``).  If ``|mu(v)/mu_s - 1| <= COULOMB_REDUCTION`` for ``v <= V S``
    (:func:`friction_change`), it satisfies the velocity-dependent problem, ``q = mu(V |s|) p`` in the slip zone, to
    that relative residual, ten times below what the slip iteration accepts (1e-9), and T' is within about that
    fraction of the exact answer (only the slip zone's traction changes).  It is then the answer, exact in a* and
    T' at any creep (the slip iteration's creep equation cannot resolve xi below ~M eps xi_sat), and
    ``info["coulomb_reduction"]`` says so.  The law is first tested at the smaller ``V (|xi| + mu_s sum |g_n|)``,
    which needs no tangential solution: where it fails there the reduction cannot apply.  Zero creep is left to
    the slip iteration's own shortcut.
    """
    xi = scene.creep
    friction, speed = scene.friction, scene.rolling_speed
    mu_s = friction.static_coefficient
    patch_slip = abs(xi) + mu_s * float(np.abs(g[1:]).sum())
    if xi == 0.0 or friction_change(friction, speed * patch_slip) > COULOMB_REDUCTION:
        return None
    tangential = solve_tangential(e, a, x0, scene.normal_load_per_length, scene.material.contact_modulus, mu_s, xi,
                                  order, tolerance)
    fastest = speed * (patch_slip + mu_s * float(np.abs(tangential[2][1:]).sum()))
    change = friction_change(friction, fastest)
    if change > COULOMB_REDUCTION:
        return None
    info["coulomb_reduction"] = (f"solved as Coulomb friction with mu_s = {mu_s!r}: mu(v) changes by {change:.3g} of "
                                 f"mu_s <= {COULOMB_REDUCTION} for slip velocities up to {fastest:.3g} m/s")
    return tangential


def solve_with_velocity_friction(scene, expansion, a, x0, c_n, g, iterations, residual, info, check, nodes,
                                 samples, tolerance, order):
    """Normal problem done; tangential problem by the slip iteration of :mod:`rollcontact.velocity_friction`, or,
    where the contact splits, on the patches of :func:`several_patches`; where those fail too, the failure (no
    slip iteration on a patch that is not the contact)."""
    estar = scene.material.contact_modulus
    xi = scene.creep
    messages = []
    mu_s = scene.friction_coefficient
    # zero creep: the whole patch sticks and q2 = -mu_s p cancels q1 (no tangential checks needed)
    zero = PolynomialDistributions(a, x0, c_n, g, a, x0, -mu_s * c_n, g, mu_s, 0.0)
    if check:
        messages += validity_failures(zero, expansion, scene, a, x0, *samples)
        if any(text.startswith(SEVERAL) for text in messages):
            several = several_patches(scene, expansion, tolerance, order, (x0, a, samples[1][:-2]), nodes)
            if several.success:
                return several
            messages.append(several.message)
            info["patches"] = several.info["patches"]
        if messages:  # the normal solution is not the contact's: a slip iteration on it (seconds at large M) is moot
            return failed(scene, "; ".join(messages), a, x0, iterations, info)
    if xi == 0.0:
        # full stick: dT'/dxi of the stick zone growing from the leading edge, as with Coulomb friction (the
        # slip velocities vanish, mu = mu_s; the ratio of the rates does not depend on mu)
        dxi, dt = stick_rates(expansion, x0 - a, mu_s, 0.25 * math.pi * estar * mu_s, a)
        stick, t_force, dist, it, stiffness = a, 0.0, zero, 0, dt / dxi if dxi != 0.0 else math.nan
    else:
        nodes = max(nodes, default_nodes(c_n, estar, scene.friction, scene.rolling_speed))
        out = solve_velocity_dependent(c_n, a, x0, estar, scene.friction, scene.rolling_speed, xi, nodes=nodes)
        stick, t_force, dist, it, stiffness = (out["stick_half_width"], out["tangential_force_per_length"],
                                               out["distributions"], out["iterations"],
                                               out["creep_stiffness_per_length"])
        info["slip_iteration_history"] = out["history"]
        if out["message"]:
            messages.append(out["message"])
    success = not messages
    message = ("converged" if success else "; ".join(messages) + "; use method='discretised'")
    return ContactResult(method="polynomial", success=success, message=message,
                         normal_load_per_length=scene.normal_load_per_length, tangential_force_per_length=t_force,
                         creep=xi, contact_half_width=a, contact_offset=x0, stick_half_width=stick,
                         max_pressure=max_pressure(c_n, *samples), creep_stiffness_per_length=stiffness,
                         iterations=iterations + it, residual=residual, distributions=dist, info=info)


def failed(scene, message, a, offset, iterations, info):
    return ContactResult(method="polynomial", success=False, message=message + "; use method='discretised'",
                         normal_load_per_length=scene.normal_load_per_length, tangential_force_per_length=math.nan,
                         creep=scene.creep, contact_half_width=a, contact_offset=offset, stick_half_width=math.nan,
                         max_pressure=math.nan, iterations=iterations, residual=math.inf, info=info)


DIFFERENCE_WIDTH = 1e-3
"""Slip widths ``w = a - a*`` below this fraction of a (and below ``DIFFERENCE_PHASE / k_max``) have xi and T'
evaluated from their zeros at ``a* = a`` (:func:`solve_tangential`); above it the direct forms lose at most
``eps / DIFFERENCE_WIDTH ~ 2e-13`` of relative accuracy."""
DIFFERENCE_PHASE = 0.3
"""Largest ``k w`` of the difference form: the 5-point rule's error is then ``~4e-13 (k w)^10 < 3e-18``."""


def unit_gauss_rule(n: int) -> tuple:
    """The n-point Gauss-Legendre rule on [0, 1] as ``((node, weight), ...)`` in plain floats (weights sum to 1)."""
    x, w = np.polynomial.legendre.leggauss(n)
    return tuple(zip((0.5 * (1.0 + x)).tolist(), (0.5 * w).tolist(), strict=True))


DIFFERENCE_RULE = unit_gauss_rule(5)
"""The difference form's rule: (fraction of w, weight)."""


def solve_tangential(e: SlopeExpansion, a, x0, load, estar, mu, xi, order, tolerance):
    """Stick-zone half-width a* from ``xi = -mu G0(a*, Xs)`` (eq 31), then q2 and T' (eq 30).

    The unknown is the slip width ``w = a - a*``.  ``xi(a*)`` runs from its full-slip value at ``a* = 0`` (w = a) to
    0 at ``a* = a`` (the normal solution makes ``G0(a, X0) = 0``).  Along the family of leading-edge stick zones
    (``Xs = X0 - a + a*``) ``d xi / d a* = mu (-1/R + dm0/dh + dm0/dc) = mu (-1/R + <Z''(X)(1 + t)>)`` (mean over
    the zone with the Chebyshev weight), so ``Z'' < 1/R`` on the patch makes xi strictly decreasing: then the root
    is unique, and safeguarded Newton from the Carter interpolation ``w = a |xi| / xi(0)`` (exact for a parabolic
    gap) finds it in a few steps.  Otherwise every root is bracketed on a 9-point scan and the one with the
    smallest |T'| is kept.

    Small creep.  xi and ``T' = mu N' - (pi E* mu / 4) a* G1(a*, Xs)`` (eq 30) both vanish at ``a* = a`` (the normal
    problem: ``G0 = 0``, ``N' = (pi E* a / 4) G1``).  Eq 31 is taken less ``mu G0(a, X0) = 0``,
    ``xi = mu (w/R + m0(a*, Xs) - m0(a, X0))``, which leaves out ``Delta/R`` (large on a steep tilt, where it
    cancels against m0), but this and eq 30 are still differences of terms of size ``mu a/R`` and ``mu N'`` that
    keep only ``eps a / w`` of relative accuracy.  For ``w <= min(DIFFERENCE_WIDTH a,
    DIFFERENCE_PHASE / k_max)`` they are taken from their exact zeros instead,
    ``xi(a - w) = -int_{a-w}^{a} dxi/da*(s) ds`` and ``T'(a - w) = -int_{a-w}^{a} dT'/da*(s) ds`` with
    the rates of :func:`stick_rates`, by the 5-point Gauss-Legendre rule :data:`DIFFERENCE_RULE`
    (:func:`from_full_stick`): the integrands are analytic on the scale 1/k_max (harmonics) and polynomials of degree
    at most ``deg Z - 1`` (exact to degree 9), so the rule is exact to round-off and T' keeps the relative
    accuracy of w at any creep (Carter: ``xi = mu w / R``).

    Returns ``(a*, d_n, G_n, T', dT'/dxi, failure message)``.
    """
    target = abs(xi)
    sign = math.copysign(1.0, xi)
    inv_r = 1.0 / e.radius
    lead = x0 - a
    quarter = 0.25 * math.pi * estar * mu
    near = DIFFERENCE_WIDTH * a
    if e.max_wavenumber > 0.0:
        near = min(near, DIFFERENCE_PHASE / e.max_wavenumber)

    # eq 31 less mu G0(a, X0) = 0 (eq 29): Delta/R, large on a steep tilt, cancels without rounding
    m0_patch = e.moments(a, x0)[0]

    def creep_of(w):
        """``(xi, dxi/da*)`` at the slip width w: the Newton loop's function, without T' and with the moments
        and the rate of :func:`stick_rates` inlined (a call less per iteration)."""
        h = a - w
        m = e.moments(h, lead + h)
        xi_w = mu * (w * inv_r + (m[0] - m0_patch)) if w > near else from_full_stick(e, a, lead, mu, quarter, w)[0]
        return xi_w, mu * (m[2] + m[3] - inv_r)

    if xi == 0.0:  # the whole patch sticks: q2 = -mu p cancels q1 exactly
        candidates = [0.0]
    elif e.curvature_bound(lead, x0 + a) * e.radius < CONVEX:
        f_full = creep_of(a)[0] - target
        candidates = [a] if f_full <= 0.0 else [refine_root(creep_of, target, 0.0, a, -target,
                                                            a * target / (f_full + target))]
    else:
        # scan w in [0, a] for every root of xi(a - w) = |xi| (plain floats: 9 scalar calls beat one array call);
        # f[0] = -|xi| < 0, and f[8] <= 0 (no stick zone) makes full slip a candidate
        grid = [a * i / 8.0 for i in range(9)]
        f = [creep_of(w)[0] - target for w in grid]
        candidates = [a] if f[8] <= 0.0 else []
        for i in range(8):
            if f[i] == 0.0:  # a root on the grid itself
                candidates.append(grid[i])
            elif (f[i] < 0.0) != (f[i + 1] < 0.0) and f[i + 1] != 0.0:
                candidates.append(refine_root(creep_of, target, grid[i], grid[i + 1], f[i],
                                              0.5 * (grid[i] + grid[i + 1])))
        if not candidates:
            return 0.0, np.zeros(2), np.zeros(2), math.nan, math.nan, (
                f"tangential problem: no stick zone satisfies xi(a*) = {target:.6g} for a* in [0, {a:.6g}] m")
    best = None
    for w in candidates:  # (a*, d_n, G_n, T', dT'/dxi) at each, keep the smallest |T'|
        h = a - w
        if h == 0.0:
            sol = 0.0, np.zeros(2), np.zeros(2), sign * mu * load, 0.0
        else:
            G = e.gap_slope_coefficients(h, lead + h, order if order is not None else e.required_order(h, tolerance))
            t_force = (mu * load - quarter * h * float(G[1]) if w > near else
                       from_full_stick(e, a, lead, mu, quarter, w)[1])
            # dT'/dxi = (dT'/da*)/(dxi/da*) along the stick zone's leading-edge-fixed family
            dxi, dt = stick_rates(e, lead, mu, quarter, h)
            sol = h, -0.5 * estar * mu * G, G, sign * t_force, dt / dxi if dxi != 0 else math.nan
        if best is None or abs(sol[3]) < abs(best[3]):
            best = sol
    return (*best, "")


def stick_rates(e: SlopeExpansion, lead, mu, quarter, h):
    """``(dxi/da*, dT'/da*)`` along the family of stick zones at the leading edge ``lead``, at ``a* = h``.

    ``dxi/da* = mu (dm0/dh + dm0/dc - 1/R)``, ``dT'/da* = -(pi E* mu / 4)(2 a*/R - m1 - a* (dm1/dh + dm1/dc))``
    (``quarter = pi E* mu / 4``; moments of :meth:`SlopeExpansion.moments` on the zone, centre ``lead + h``).
    """
    m = e.moments(h, lead + h)
    inv_r = 1.0 / e.radius
    return mu * (m[2] + m[3] - inv_r), -quarter * (2.0 * h * inv_r - m[1] - h * (m[4] + m[5]))


def from_full_stick(e: SlopeExpansion, a, lead, mu, quarter, w):
    """``(xi, T')`` (for xi > 0) at the slip width ``w = a - a*`` from their zeros at ``a* = a``:
    ``-int_{a-w}^{a} (dxi/da*, dT'/da*) ds`` (:func:`stick_rates`) by :data:`DIFFERENCE_RULE`."""
    if w == 0.0:  # the whole patch sticks
        return 0.0, 0.0
    xi_w = t_w = 0.0
    for fraction, weight in DIFFERENCE_RULE:
        dxi, dt = stick_rates(e, lead, mu, quarter, a - fraction * w)
        xi_w -= weight * dxi
        t_w -= weight * dt
    return w * xi_w, w * t_w


def refine_root(creep_of, target, lo, hi, f_lo, w):
    """Safeguarded Newton from ``w`` on the bracket [lo, hi] of ``f(w) = xi(a - w) - target`` (``creep_of``: see
    :func:`solve_tangential`); ``df/dw = -dxi/da*``.

    Quadratic convergence: a step below 1e-9 of w leaves an error ~1e-18 of w after the update, so the slip width
    keeps its relative accuracy however small it is.
    """
    for _ in range(60):
        val, der = creep_of(w)
        fv = val - target
        step = fv / der if der != 0 else math.inf
        if abs(step) <= 1e-9 * w:
            return min(max(w + step, lo), hi)
        if (fv < 0) == (f_lo < 0):
            lo = w
        else:
            hi = w
        w_new = w + step
        w = w_new if lo < w_new < hi else 0.5 * (lo + hi)
    return w


# ---------------------------------------------------------------------------------------------------------------
# fields on the patch, validity
SPLIT = "contact splits"
GAP_CLOSES = "the deformed gap closes outside the patch"
SEVERAL = (SPLIT, GAP_CLOSES)
"""How :func:`validity_failures` begins the messages that mean several patches (a negative pressure, a gap that
closes outside the patch): then :func:`rollcontact.multipatch.solve_split` takes over."""
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
    i = int(gap.argmin())
    if gap[i] < -1e-9 * a * a / e.radius:
        return float(x0 + a * t[i]), float(gap[i])
    return None


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


def inapplicable(scene) -> str | None:
    return None


register_method("polynomial", solve_polynomial, inapplicable, cost=10)
