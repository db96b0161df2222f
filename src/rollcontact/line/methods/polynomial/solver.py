"""The polynomial approximation method (paper sections 3-4.1) in a stable Chebyshev basis.

Normal problem.  On the patch ``X = X0 + a t`` (``X0 = x_c + Delta``) the pressure is the bounded density
``p = sum_{n>=1} c_n sin(n theta)``, ``t = cos(theta)``, which answers ``(2/(pi E*)) PV-int p/(x-z) dz =
(2/E*) sum c_n T_n(t)`` (:mod:`.chebyshev`).  Matching the gap slope ``h0'`` gives ``c_n = (E*/2) g_n`` with ``g_n``
the Chebyshev coefficients of ``h0'(X0 + a t)``; a bounded solution needs ``g_0 = 0`` (fixes Delta) and the
load is ``N' = (pi a / 2) c_1`` (fixes a).  For harmonics ``g_0`` and ``g_1`` are the exact Bessel forms of
docs/physics.md (Corrugated surface) eqs 28-29 as corrected, so a and Delta carry no truncation error; the order only
limits p(x). Every position is computed in axis coordinates ``u = X - x_c`` (the patch is ``u = Delta + a t``;
:class:`~rollcontact.line.methods.polynomial.chebyshev.SlopeExpansion`), so the answer does not depend on how far along
the surface the axis stands (surface coordinates would lose ``eps |x_c|`` in every ``X - x_c``).

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
several patches (the pressure turns negative, or the gap closes outside the patch),
:mod:`rollcontact.line.methods.polynomial.patches` solves it with one expansion per patch and stick zone (one stick zone
at each patch's leading edge, checked likewise; a velocity-dependent law on its patches by
:mod:`rollcontact.line.methods.polynomial.patches_slip`), from the patches of a coarse discretised normal solve (which
also finds the one patch in contact where Newton from the Hertz patch landed on a spurious one); only when that fails
too is the result unsuccessful.

The paper's monomial formulation (eqs 21-26; note eq 26 needs ``A_n^-1 = +(1/pi) a^(2n-2)/(2n-3) prod...``
for n >= 2, the printed minus sign is wrong: ``A = -pi (1 - a^2 S)^(-1/2)`` so ``A^-1 = -(1/pi)(1 - a^2 S)^(1/2)``)
is available as ``basis="monomial"`` to measure its conditioning.

Cost.  A solve is a few dozen operations on vectors of ~10-60 entries, so per-call overhead decides the time:
Newton iterations run on plain floats, tables that depend only on sizes are cached
(:mod:`rollcontact.line.methods.polynomial.chebyshev`), and the pressure samples serve both the checks and
``max_pressure``.  Products of arrays are ``ndarray.dot``, the same BLAS call as ``@`` (the same bits) without the
gufunc dispatch, whose overhead is comparable to such small products.  Where the surface curvature allows, a theorem
replaces sampling: with ``|Z''| < 1/R`` on the patch the creep ``xi(a*)`` of eq 31 decreases (unique root, no scan)
and the slip has the sign of the creep; with ``|Z''| <= 1/(3R)`` the stick-zone traction bound holds; with
``Z'' < 1/R`` everywhere the deformed gap cannot close outside the patch (:func:`validity_failures`,
:func:`outside_gap`).  Otherwise the checks sample the fields.
"""

from __future__ import annotations

import math

import numpy as np

from rollcontact.line.hertz import hertz
from rollcontact.line.methods.polynomial.chebyshev import SlopeExpansion, max_pressure, pressure_samples, unit_grid
from rollcontact.line.methods.polynomial.distributions import PolynomialDistributions
from rollcontact.line.methods.polynomial.monomial import BASES, monomial_density
from rollcontact.line.methods.polynomial.patches import patch_starts, solve_split, split_normal, split_target
from rollcontact.line.methods.polynomial.patches_slip import solve_split_velocity
from rollcontact.line.methods.polynomial.slip import (
    DEFAULT_NODES,
    SLIP_ITERATIONS,
    default_nodes,
    solve_velocity_dependent,
)
from rollcontact.line.methods.polynomial.validity import CONVEX, SEVERAL, validity_failures
from rollcontact.line.result import ContactResult, NoContact

TRUNCATION = 1e-10
"""Default ``truncation`` of :func:`solve_polynomial`: the neglected coefficients relative to the Hertz slope."""


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


def solve_polynomial(scene, *, order: int | None = None, truncation: float = TRUNCATION, basis: str = "chebyshev",
                     max_iterations: int = 60, check: bool = True, nodes: int = DEFAULT_NODES,
                     slip_iterations: int = SLIP_ITERATIONS) -> ContactResult:
    """Polynomial method for a steady scene (paper sections 3, 4.1 and, for velocity-dependent friction, 4.2).

    Parameters
    ----------
    scene : Scene
        Any surface: polynomial part and/or harmonics.
    order : int, optional
        Number of Chebyshev terms (or monomial degree) of the distributions; by default the smallest order
        whose neglected coefficients are below ``truncation`` (relative to the Hertz slope a/R).  With Coulomb
        friction a, Delta, a* and T' are exact at every order (eqs 28-31 are closed forms); the order sets the
        accuracy of p(x), q(x), s(x) and of the checks.
    truncation : float
        Target relative truncation error of the distributions, > 0.
    basis : {"chebyshev", "monomial"}
        The stable basis, or the paper's monomial matrices (eqs 21-26) whose conditioning degrades as a^(2n).
    max_iterations : int
        Newton iterations for the normal problem.
    nodes : int
        Least number of Chebyshev nodes of the slip iteration for velocity-dependent friction (paper section
        4.2).  Raised to 32 or 64 for steep laws, which need them for 1e-3 in T'
        (:func:`rollcontact.line.methods.polynomial.slip.default_nodes`, from ``benchmarks/bench_steady.py`` table C),
        and to twice the number of pressure terms.
    slip_iterations : int
        Largest number of Newton iterations of the slip iteration, and as many again of its relaxed fixed point
        where Newton stalls (:func:`rollcontact.line.methods.polynomial.slip.solve_velocity_dependent`): bounds the work
        of a solve with velocity-dependent friction; a solve that does not converge within them fails and says so.
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
        (:func:`coulomb_reduction`).  Solved as several patches
        (:func:`rollcontact.line.methods.polynomial.patches.solve_split`): ``info["patches"]`` and
        ``info["stick_zones"]`` (leading and trailing ends [m]), a and Delta from the outer edges, the stick half-width
        the sum of the zones'.
    """
    if basis not in BASES:
        raise ValueError(f"unknown basis {basis!r}; valid bases are {list(BASES)}")
    if order is not None and (int(order) != order or not 1 <= order <= 2000):
        raise ValueError(f"order = {order!r} is out of range: it must be an integer in [1, 2000]")
    if not (math.isfinite(truncation) and truncation > 0.0):
        raise ValueError(f"truncation = {truncation!r} must be finite and > 0")
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
            several = several_patches(scene, expansion, truncation, order, None, nodes)
            if several.success:
                return several
            failure += "; " + several.message
        return failed(scene, failure, a, x0, iterations, info)

    n_order = order if order is not None else expansion.required_order(a, truncation)
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
        tangential = solve_tangential(expansion, a, x0, load, estar, mu, xi, order, truncation)
    else:
        tangential = coulomb_reduction(scene, expansion, a, x0, g, info, order, truncation)
        if tangential is None:
            return solve_with_velocity_friction(scene, expansion, a, x0, c_n, g, iterations, residual, info, check,
                                                nodes, (m, samples), truncation, order, slip_iterations)
    stick, d_n, G, t_force, stiffness, tang_failure = tangential
    dist = PolynomialDistributions(a, x0, c_n, g, stick, x0 - a + stick, d_n, G, mu, xi, monomial_b)
    messages = []
    if tang_failure:
        messages.append(tang_failure)
    if check:
        messages += validity_failures(dist, expansion, scene, a, x0, m, samples)
        if several_apply and any(text.startswith(SEVERAL) for text in messages):
            several = several_patches(scene, expansion, truncation, order, (x0, a, samples[:-2]), nodes)
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


solve_polynomial.options = ("order", "truncation", "basis", "max_iterations", "nodes", "slip_iterations")


def several_patches(scene, expansion: SlopeExpansion, truncation: float, order: int | None,
                    single: tuple | None, nodes: int) -> ContactResult:
    """The scene as several patches from each start of :func:`rollcontact.line.methods.polynomial.patches.patch_starts`
    in turn: the first success, else the last failure.  ``single`` is ``(offset, half-width, pressure samples)`` of the
    failed single-patch solution, None where its normal problem did not converge.

    Coulomb friction, and any law at zero creep (full stick, q = 0):
    :func:`rollcontact.line.methods.polynomial.patches.solve_split`. A velocity-dependent law: the patches of
    :func:`rollcontact.line.methods.polynomial.patches.split_normal`, then the slip iteration on them
    (:func:`rollcontact.line.methods.polynomial.patches_slip.solve_split_velocity`, at least ``nodes`` nodes per patch).
    """
    load, estar, friction, xi = (scene.normal_load_per_length, scene.material.contact_modulus, scene.friction,
                                 scene.creep)
    mu_s = friction.static_coefficient
    target = split_target(truncation, xi, mu_s, hertz(load, scene.radius, estar)[0] / scene.radius)
    for start in patch_starts(scene, single) or [[]]:  # no start: solve_split reports that no patch was found
        if friction.is_constant or xi == 0.0:
            several = solve_split(expansion, load, estar, mu_s, xi, start, truncation, order)
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
iteration's truncation."""


def friction_change(friction, slip_velocity: float) -> float:
    """``|mu(v)/mu_s - 1|`` at ``v``: the largest change over [0, v] for a law monotone there (every law of
    :mod:`rollcontact.core.friction`; a user table if its coefficients are monotone up to v)."""
    return abs(float(friction.coefficient(slip_velocity)) / friction.static_coefficient - 1.0)


def coulomb_reduction(scene, e: SlopeExpansion, a, x0, g, info, order, truncation):
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
                                  order, truncation)
    fastest = speed * (patch_slip + mu_s * float(np.abs(tangential[2][1:]).sum()))
    change = friction_change(friction, fastest)
    if change > COULOMB_REDUCTION:
        return None
    info["coulomb_reduction"] = (f"solved as Coulomb friction with mu_s = {mu_s!r}: mu(v) changes by {change:.3g} of "
                                 f"mu_s <= {COULOMB_REDUCTION} for slip velocities up to {fastest:.3g} m/s")
    return tangential


def solve_with_velocity_friction(scene, expansion, a, x0, c_n, g, iterations, residual, info, check, nodes,
                                 samples, truncation, order, slip_iterations):
    """Normal problem done; tangential problem by the slip iteration of :mod:`rollcontact.line.methods.polynomial.slip`,
    or, where the contact splits, on the patches of :func:`several_patches`; where those fail too, the failure (no
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
            several = several_patches(scene, expansion, truncation, order, (x0, a, samples[1][:-2]), nodes)
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
        out = solve_velocity_dependent(c_n, a, x0, estar, scene.friction, scene.rolling_speed, xi, nodes=nodes,
                                       max_iterations=slip_iterations)
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


def solve_tangential(e: SlopeExpansion, a, x0, load, estar, mu, xi, order, truncation):
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
            G = e.gap_slope_coefficients(h, lead + h, order if order is not None else e.required_order(h, truncation))
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


def inapplicable(scene) -> str | None:
    return None
