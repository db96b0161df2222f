"""The polynomial approximation method (paper sections 3-4.1) in a stable Chebyshev basis.

Normal problem.  On the patch ``X = X0 + a t`` (``X0 = x_c + Delta``) the pressure is the bounded density
``p = sum_{n>=1} c_n sin(n theta)``, ``t = cos(theta)``, which answers ``(2/(pi E*)) PV-int p/(x-z) dz =
(2/E*) sum c_n T_n(t)`` (chebyshev.py).  Matching the gap slope ``h0'`` gives ``c_n = (E*/2) g_n`` with ``g_n``
the Chebyshev coefficients of ``h0'(X0 + a t)``; a bounded solution needs ``g_0 = 0`` (fixes Delta) and the
load is ``N' = (pi a / 2) c_1`` (fixes a).  For harmonics ``g_0`` and ``g_1`` are the exact Bessel forms of
physics.md eqs 28-29 (corrected), so a and Delta carry no truncation error; the order only limits p(x).

Tangential problem (Coulomb).  ``q = mu p + q2`` with ``q2 = sum d_n sin(n theta*)`` on the stick zone
``[X0 - a, X0 - a + 2 a*]`` (centre ``Xs``).  No slip there, ``xi + du/dx = 0``, gives
``d_n = -(E*/2) mu G_n`` (``G_n``: coefficients of ``h0'(Xs + a* t)``) and the creep
``xi = -mu G_0`` (eq 31 corrected), ``T' = mu N' + (pi a*/2) d_1`` (eq 30).  Negative creep mirrors q.

Validity (one patch, one stick zone at the leading edge) is checked on the returned fields: ``p >= 0``; the
deformed gap stays open outside the patch; ``|q| <= mu p`` in the stick zone; slip has the sign of the traction
in the slip zone.  A failed check gives ``success = False`` and a message naming it.

The paper's monomial formulation (eqs 21-26; note eq 26 needs ``A_n^-1 = +(1/pi) a^(2n-2)/(2n-3) prod...``
for n >= 2, the printed minus sign is wrong: ``A = -pi (1 - a^2 S)^(-1/2)`` so ``A^-1 = -(1/pi)(1 - a^2 S)^(1/2)``)
is available as ``basis="monomial"`` to measure its conditioning.

Cost.  A solve is a few dozen operations on vectors of ~10-60 entries, so per-call overhead decides the time:
Newton iterations run on plain floats, tables that depend only on sizes are cached (:mod:`rollcontact.chebyshev`),
and the pressure samples serve both the checks and ``max_pressure``.  Where the surface curvature allows, a
theorem replaces sampling: with ``|Z''| < 1/R`` on the patch the creep ``xi(a*)`` of eq 31 decreases (unique
root, no scan) and the slip has the sign of the creep; with ``|Z''| <= 1/(3R)`` the stick-zone traction bound
holds; with ``Z'' < 1/R`` everywhere the deformed gap cannot close outside the patch (:func:`validity_failures`,
:func:`outside_gap`).  Otherwise the checks sample as before.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import linalg

from rollcontact.api import register_method
from rollcontact.chebyshev import (
    SlopeExpansion,
    orders,
    outer_transform,
    pressure_table,
    sine_series,
    theta_grid,
    unit_grid,
)
from rollcontact.closed_form import hertz
from rollcontact.result import ContactResult, Distributions, NoContact
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
    """T0/T1 moments G0, G1 of ``h0'(c + h t)`` with derivatives, in either basis."""

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
            return ((c - e.axis_position) * inv_r - m0, h * inv_r - m1, -d0h, inv_r - d0c, inv_r - d1h, -d1c)
        g0, g1 = self.monomial_moments(h, c)
        dh = 1e-7 * h
        g0h, g1h = self.monomial_moments(h + dh, c)
        g0c, g1c = self.monomial_moments(h, c + dh)
        return g0, g1, (g0h - g0) / dh, (g0c - g0) / dh, (g1h - g1) / dh, (g1c - g1) / dh

    def monomial_moments(self, h, c):
        _, r0, r1, self.cancellation = monomial_density(self.e.gap_slope_taylor(c, self.order), h)
        return r0, r1


def solve_normal(problem: NormalProblem, load: float, estar: float, a0: float, max_iterations: int):
    """Newton on (a, X0): ``G0(a, X0) = 0`` and ``(pi E* a / 4) G1(a, X0) = N'`` (eqs 28-29).

    The start is one fixed-point step of both equations from Hertz with the surface moments frozen at
    ``(a_H, x_c)``: ``X0 = x_c + R m0`` (eq 29) and the positive root of ``a^2/R - a m1 = a_H^2/R`` (eq 28,
    ``G1 = a/R - m1``).  It removes the first-order effect of the surface, which saves one or two Newton steps.
    """
    e = problem.e
    R = e.radius
    xc = e.axis_position
    a = a0
    g0, g1 = problem.moments(a, xc)[:2]
    c = xc - R * g0 if math.isfinite(g0) else xc
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
        the cancellation factor of the paper's power basis (``info["cancellation_factor"]``).
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
    xc = scene.axis_position
    if load == 0.0:
        return ContactResult(method="polynomial", success=True, message="no load: no contact",
                             normal_load_per_length=0.0, tangential_force_per_length=0.0, creep=xi,
                             contact_half_width=0.0, contact_offset=0.0, stick_half_width=0.0, max_pressure=0.0,
                             creep_stiffness_per_length=0.0, distributions=NoContact())
    expansion = SlopeExpansion(R, xc, scene.surface)
    a_hertz, _ = hertz(load, R, estar)
    monomial_order = order if order is not None else max(4, expansion.slope_poly.size + 2)
    problem = NormalProblem(expansion, basis, monomial_order)
    a, x0, iterations, failure = solve_normal(problem, load, estar, a_hertz, max_iterations)
    info = {"basis": basis}
    if failure or not (a > 0.0 and math.isfinite(a) and math.isfinite(x0)):
        return failed(scene, failure or f"normal problem: no positive root for a (a = {a!r} m)", a, x0 - xc,
                      iterations, info)

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

    if not friction.is_constant:
        return solve_with_velocity_friction(scene, expansion, a, x0, c_n, g, iterations, residual, info, check,
                                            nodes, (m, samples))
    # tangential problem
    stick, d_n, G, t_force, stiffness, tang_failure = solve_tangential(expansion, a, x0, load, estar, mu, xi,
                                                                       order, tolerance)
    dist = PolynomialDistributions(a, x0 - xc, c_n, g, stick, x0 - a + stick - xc, d_n, G, mu, xi, monomial_b)
    messages = []
    if tang_failure:
        messages.append(tang_failure)
    if check:
        messages += validity_failures(dist, expansion, scene, a, x0, m, samples)
    if monomial_b is None:
        p_max = max_pressure(c_n, m, samples)
    else:
        p_max = float(np.max(dist.pressure(x0 - xc + a * (1.998 * unit_grid(401) - 0.999))))
    success = not messages
    if success:
        message = "full slip (saturated)" if stick == 0.0 and xi != 0.0 else "converged"
    else:
        message = "; ".join(messages) + "; use method='discretised'"
    info["stick_coefficients"] = d_n
    return ContactResult(method="polynomial", success=success, message=message, normal_load_per_length=load,
                         tangential_force_per_length=t_force, creep=xi, contact_half_width=a,
                         contact_offset=x0 - xc, stick_half_width=stick, max_pressure=p_max,
                         creep_stiffness_per_length=stiffness, iterations=iterations, residual=residual,
                         distributions=dist, info=info)


solve_polynomial.options = ("order", "tolerance", "basis", "max_iterations", "nodes")


def solve_with_velocity_friction(scene, expansion, a, x0, c_n, g, iterations, residual, info, check, nodes,
                                 samples):
    """Normal problem done; tangential problem by the slip iteration of :mod:`rollcontact.velocity_friction`."""
    xc = scene.axis_position
    estar = scene.material.contact_modulus
    xi = scene.creep
    messages = []
    mu_s = scene.friction_coefficient
    # zero creep: the whole patch sticks and q2 = -mu_s p cancels q1 (no tangential checks needed)
    zero = PolynomialDistributions(a, x0 - xc, c_n, g, a, x0 - xc, -mu_s * c_n, g, mu_s, 0.0)
    if check:
        messages += validity_failures(zero, expansion, scene, a, x0, *samples)
    if xi == 0.0:
        stick, t_force, dist, it = a, 0.0, zero, 0
    else:
        nodes = max(nodes, default_nodes(c_n, estar, scene.friction, scene.rolling_speed))
        out = solve_velocity_dependent(c_n, a, x0 - xc, estar, scene.friction, scene.rolling_speed, xi,
                                       nodes=nodes)
        stick, t_force, dist, it = (out["stick_half_width"], out["tangential_force_per_length"],
                                    out["distributions"], out["iterations"])
        info["slip_iteration_history"] = out["history"]
        if out["message"]:
            messages.append(out["message"])
    success = not messages
    message = ("converged" if success else "; ".join(messages) + "; use method='discretised'")
    return ContactResult(method="polynomial", success=success, message=message,
                         normal_load_per_length=scene.normal_load_per_length, tangential_force_per_length=t_force,
                         creep=xi, contact_half_width=a, contact_offset=x0 - xc, stick_half_width=stick,
                         max_pressure=max_pressure(c_n, *samples), iterations=iterations + it, residual=residual,
                         distributions=dist, info=info)


def failed(scene, message, a, offset, iterations, info):
    return ContactResult(method="polynomial", success=False, message=message + "; use method='discretised'",
                         normal_load_per_length=scene.normal_load_per_length, tangential_force_per_length=math.nan,
                         creep=scene.creep, contact_half_width=a, contact_offset=offset, stick_half_width=math.nan,
                         max_pressure=math.nan, iterations=iterations, residual=math.inf, info=info)


def solve_tangential(e: SlopeExpansion, a, x0, load, estar, mu, xi, order, tolerance):
    """Stick-zone half-width a* from ``xi = -mu G0(a*, Xs)`` (eq 31), then q2 and T' (eq 30).

    ``xi(a*)`` runs from its full-slip value at ``a* = 0`` to 0 at ``a* = a`` (the normal solution makes
    ``G0(a, X0) = 0``).  Along the family of leading-edge stick zones ``d xi / d a* = mu (-1/R + <Z''(X)(1 + t)>)``
    (mean over the zone with the Chebyshev weight), so ``Z'' < 1/R`` on the patch makes xi strictly decreasing:
    then the root is unique, and safeguarded Newton from the Carter interpolation
    ``a* = a (xi(0) - |xi|)/xi(0)`` (exact for a parabolic gap) finds it in a few steps.  Otherwise every root is
    bracketed on a 9-point scan and the one with the smallest |T'| is kept.

    Returns ``(a*, d_n, G_n, T', dT'/dxi, failure message)``.
    """
    target = abs(xi)
    R = e.radius
    xc = e.axis_position
    lead = x0 - a

    def creep_of(h):
        xs = lead + h
        m = e.moments(h, xs)
        return mu * ((xc - xs) / R + m[0]), mu * (-1.0 / R + m[2] + m[3]), m

    if xi == 0.0:  # the whole patch sticks: q2 = -mu p cancels q1 exactly
        h, d, G, _, stiffness = tangential_solution(e, a, x0, load, estar, mu, xi, a, order, tolerance, creep_of)
        return h, d, G, 0.0, stiffness, ""

    if e.curvature_bound(lead, x0 + a) * R < CONVEX:
        f0 = creep_of(0.0)[0] - target
        candidates = [0.0] if f0 <= 0.0 else [refine_root(creep_of, target, 0.0, a, f0, a * f0 / (f0 + target))]
    else:
        # scan a* in [0, a] for every root of xi(a*) = |xi| (plain floats: 9 scalar calls beat one array call)
        grid = [a * i / 8.0 for i in range(9)]
        f = [creep_of(h)[0] - target for h in grid]
        candidates = []
        if f[0] <= 0.0:
            candidates.append(0.0)
        for i in range(8):
            if f[i + 1] == 0.0:  # a root on the grid itself
                candidates.append(grid[i + 1])
            elif (f[i] < 0.0) != (f[i + 1] < 0.0) and f[i] != 0.0:
                candidates.append(refine_root(creep_of, target, grid[i], grid[i + 1], f[i], 0.5 * (grid[i] +
                                                                                                   grid[i + 1])))
        if not candidates:
            return 0.0, np.zeros(2), np.zeros(2), math.nan, math.nan, (
                f"tangential problem: no stick zone satisfies xi(a*) = {target:.6g} for a* in [0, {a:.6g}] m")
    best = None
    for h in candidates:
        sol = tangential_solution(e, a, x0, load, estar, mu, xi, h, order, tolerance, creep_of)
        if best is None or abs(sol[3]) < abs(best[3]):
            best = sol
    return (*best, "")


def refine_root(creep_of, target, lo, hi, f_lo, h):
    """Safeguarded Newton from ``h`` on the bracket [lo, hi] of ``creep_of(h) - target``.

    Quadratic convergence: a step below 1e-9 of the bracket leaves an error ~1e-18 of it after the update.
    """
    for _ in range(60):
        val, der, _ = creep_of(h)
        fv = val - target
        step = fv / der if der != 0 else math.inf
        if abs(step) <= 1e-9 * hi:
            return h - step
        if (fv < 0) == (f_lo < 0):
            lo = h
        else:
            hi = h
        h_new = h - step
        h = h_new if lo < h_new < hi else 0.5 * (lo + hi)
    return h


def tangential_solution(e, a, x0, load, estar, mu, xi, h, order, tolerance, creep_of):
    sign = math.copysign(1.0, xi)
    if h == 0.0:
        return 0.0, np.zeros(2), np.zeros(2), sign * mu * load, 0.0
    xs = x0 - a + h
    n_order = order if order is not None else e.required_order(h, tolerance)
    G = e.gap_slope_coefficients(h, xs, n_order)
    d = -0.5 * estar * mu * G
    t_force = mu * load + 0.5 * math.pi * h * float(d[1])
    # dT'/dxi = (dT'/da*)/(dxi/da*) along the stick zone's leading-edge-fixed family
    _, dxi, m = creep_of(h)
    dt = -mu * 0.25 * math.pi * estar * (2.0 * h / e.radius - m[1] - h * (m[4] + m[5]))
    stiffness = float(dt / dxi) if dxi != 0 else math.nan
    return h, d, G, sign * t_force, stiffness


# ---------------------------------------------------------------------------------------------------------------
# fields on the patch, validity
def pressure_samples(c_n: np.ndarray) -> tuple[int, np.ndarray]:
    """``m`` and ``[p(theta_1) .. p(theta_(m-1)), dp/dtheta(0), dp/dtheta(pi)]``, ``theta_i = pi i/m``.

    ``m = max(64, 4 (order + 1))``: four samples per term; one product with the cached
    :func:`rollcontact.chebyshev.pressure_table`, shared by :func:`max_pressure` and :func:`validity_failures`.
    """
    m = max(64, 4 * c_n.size)
    return m, pressure_table(m, c_n.size - 1)[0] @ c_n[1:]


def max_pressure(c_n: np.ndarray, m: int, samples: np.ndarray) -> float:
    """max of ``p(theta) = sum c_n sin(n theta)``: the largest sample, then Newton on ``dp/dtheta = 0``.

    The first step uses the cached sine and derivative rows at the sample (``|theta - theta*| <= pi/2m``); each
    further one evaluates the series.  Once a step is below 1e-5 the value at that iterate is corrected by the
    step, ``p - p'^2/(2 p'')``, whose error is third order in the step (~1e-15 of p).
    """
    p = samples[:-2]
    i = int(p.argmax())
    best = float(p[i])
    n = orders(c_n.size - 1)[0][1:]
    c = c_n[1:]
    sines, cosines, _ = pressure_table(m, n.size)
    nnc = n * n * c
    th = math.pi * (i + 1) / m
    value = best
    d2 = -float(sines[i] @ nnc)
    d1 = float(cosines[i] @ c)
    for _ in range(4):
        if d2 >= 0.0:
            break
        step = d1 / d2
        if abs(step) <= 1e-5:
            return max(best, value - 0.5 * d1 * step)
        th = min(max(th - step, 0.0), math.pi)
        ang = n * th
        sn = np.sin(ang)
        value = float(sn @ c)
        d2 = -float(sn @ nnc)
        d1 = float(np.cos(ang) @ (n * c))
    return max(best, value)


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
    p_min = float(p.min())
    p_scale = max(float(p.max()), -p_min, 1e-300)
    if p_min < -tol * p_scale or min(edges) < -tol * p_scale:
        i = int(np.argmin(p))
        out.append(f"contact splits: the pressure turns negative (min p = {p[i]:.4g} Pa near x = "
                   f"{dist.offset + a * math.cos(math.pi * (i + 1) / m):.6g} m, edge slopes {edges[0]:.3g}, "
                   f"{edges[1]:.3g} Pa), more than one contact patch")
    gap = outside_gap(dist, e, scene, a, x0)
    if gap is not None:
        out.append(f"the deformed gap closes outside the patch (gap = {gap[1]:.3g} m at x = {gap[0]:.6g} m): "
                   "a second contact patch")
    if dist.creep == 0.0:
        return out
    mu = dist.mu
    h = dist.stick_half_width
    if h > 0.0 and not curvature <= STICK_PROVEN:
        d = dist.stick_coefficients
        theta, table_s = theta_grid(m, d.size - 1)
        q2 = table_s @ d[1:]
        # p at the zone's points x = Xs + h cos(theta_i), i.e. t = -1 + (h/a)(1 + cos(theta_i))
        cos_theta = pressure_table(m, c_n.size - 1)[2]
        ps = np.sin(np.arccos((h / a) * (1.0 + cos_theta) - 1.0)[:, None] * orders(c_n.size - 1)[0][1:]) @ c_n[1:]
        excess = np.maximum(q2, -2.0 * mu * ps - q2)
        if float(excess.max()) > tol * mu * p_scale:
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
    s = np.cos(np.arccos(t)[:, None] * orders(g.size - 1)[0][1:]) @ g[1:]
    if h > 0.0:
        sigma = (1.0 + t) * (a / h) - 1.0  # >= 1 up to round-off
        w = 1.0 / (sigma + np.sqrt(np.maximum(sigma * sigma - 1.0, 0.0)))
        big_g = dist.stick_slope_coefficients
        s -= (w[:, None] ** orders(big_g.size - 1)[0][1:]) @ big_g[1:]
    return abs(dist.creep) + dist.mu * s, t


def outside_gap(dist: PolynomialDistributions, e: SlopeExpansion, scene, a, x0):
    """First point outside the patch where the deformed gap closes; ``(x, gap)`` or None.

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
        reach = max(reach, math.sqrt(8.0 * scene.radius * amp) + abs(x0 - e.axis_position))
        spacing = min(spacing, 0.2 * math.pi / max(k for k, _, _ in e.harmonic_list))
    m = int(min(2000, max(32, reach / spacing)))
    u = unit_grid(m + 1)[1:] ** 2 * (reach / a)
    t = np.concatenate((1.0 + u, -1.0 - u))
    gap = deformed_gap(dist, scene, a, x0, t)
    i = int(np.argmin(gap))
    if gap[i] < -1e-9 * a * a / scene.radius:
        return float(x0 + a * t[i] - e.axis_position), float(gap[i])
    return None


def deformed_gap(dist: PolynomialDistributions, scene, a: float, x0: float, t: np.ndarray) -> np.ndarray:
    """Deformed gap [m] at ``X = X0 + a t`` outside the patch (``|t| > 1``), in closed form.

    With ``t = (w + 1/w)/2`` (``|w| < 1``) the elastic slope is ``v = sum g_n w^n`` and
    ``int w^n dt = (w^(n+1)/(n+1) - w^(n-1)/(n-1))/2`` (``(w^2/2 - ln|w|)/2`` for n = 1), so
    ``h(X) = h0(X) - h0(X_edge) - a sum g_n [I_n(w) - I_n(w_edge)]`` with ``w_edge = sign(t)``: exact at every
    point, no quadrature.
    """
    g = dist.slope_coefficients
    n_max = g.size - 1
    sign = np.sign(t)
    w = 1.0 / (t + sign * np.sqrt(t * t - 1.0))
    # antiderivative coefficients: sum_n g_n I_n(w) = sum_j beta_j w^j - (g_1/2) ln|w|
    beta = np.zeros(n_max + 2)
    n = np.arange(1, n_max + 1)
    beta[2:] += 0.5 * g[1:] / (n + 1)
    beta[1:n_max] -= 0.5 * g[2:] / n[:-1]
    antiderivative = (w[:, None] ** np.arange(1, n_max + 2)) @ beta[1:] - 0.5 * g[1] * np.log(np.abs(w))
    # at the edges w = +-1: ln|w| = 0
    at_edge = np.where(sign > 0.0, beta[1:].sum(), beta[1:] @ (-1.0) ** np.arange(1, n_max + 2))
    xc, R = scene.axis_position, scene.radius
    X = x0 + a * t
    edge = x0 + a * sign
    h0 = (X - xc) ** 2 / (2.0 * R) - scene.surface.height(X)
    h0_edge = (edge - xc) ** 2 / (2.0 * R) - scene.surface.height(edge)
    return h0 - h0_edge - a * (antiderivative - at_edge)


def inapplicable(scene) -> str | None:
    return None


register_method("polynomial", solve_polynomial, inapplicable, cost=10)
