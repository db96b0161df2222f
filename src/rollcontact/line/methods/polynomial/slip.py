"""Steady rolling with velocity-dependent friction by the polynomial method (paper section 4.2).

Structure (as the paper's, docs/physics.md, Velocity-dependent friction): one stick zone at the leading edge, slip
behind it.  The traction is ``q = q1 + q2`` with ``q1 = mu(V s(x)) p(x)`` over the whole patch (``mu_s p`` in the stick
zone, where s = 0) and ``q2`` a bounded correction on the stick zone that cancels the slip there.

Discrete equations.  On the patch ``t = cos(theta_j)``, ``theta_j = pi (j + 1/2)/M``, the nodal values
``Q_j = mu(V s_j) p_j`` define the sine series ``q1 = sum e_n sin(n theta)`` (a DST of ``Q``: the Chebyshev fit of
the paper), whose displacement gradient is ``H1 = (2/E*) sum e_n T_n(t)``.  On the stick zone
``X = Xs + a* sigma`` (``t = -1 + (a*/a)(1 + sigma)``) the Chebyshev coefficients ``F_0..F_M`` of ``H1``, exact
from ``M + 1`` nodes since H1 has degree M, give the creep ``xi = -F_0(a*)`` and
``q2 = -(E*/2) sum_{n>=1} F_n sin(n phi)``; the slip behind the stick zone is
``s = xi + H1 - sum F_n w^n``, ``w = sigma - sqrt(sigma^2 - 1)``.  Every map ``Q -> (e, H1, F, s)`` is a matrix:
those that depend only on M are cached (:func:`slip_operators`), those that depend on a* are built once per
iteration (:func:`stick_maps`).

Solution.  Newton on the ``M + 1`` unknowns ``(mu_j, a*/a)`` of ``mu_j = mu(V s_j)``, ``s = S(mu p, a*)`` and
``F_0(a*) + xi = 0``, with the exact Jacobian (``dmu/dv`` from the law; the a*-derivatives of the stick-zone
re-expansion, ``d T_n(t)/dt = n sin(n psi)/sin(psi)``, and of ``w^n``, ``-n w^n / sqrt(sigma^2 - 1) d sigma``),
from the Carter state (``mu = mu_s``, ``a* = a (1 - xi/xi_sat)``); in full slip (``xi >= -H1(-1)``) the unknowns
are the ``mu_j`` alone.  The nodal friction coefficients, not the slips, are the unknowns because q1 is linear in
them and they stay bounded where a steep law saturates.  Steps are halved until the residual decreases; if Newton
stalls (a node next to the stick/slip boundary, where the slip goes like the square root of the distance, makes
the equations kinked) the paper's under-relaxed fixed point takes over.  Typically 3 (Polach-type laws) to 6
(steep laws) Newton steps replace the fixed point's 7-25 iterations, each of which needed an inner root search.
With dmu/dv < 0 the creep curve has a maximum and q a spike at the stick/slip boundary.

Accuracy.  T' converges like M^-1.5 and erratically (it depends on where the stick/slip boundary falls between
nodes), the slower the steeper the law: ``kappa = |dmu/dv(0)| V xi_sat / mu_s``, the fall of mu over the Carter
saturation slip relative to mu_s, decides (Polach's B = 0.6 s/m at 20 m/s has kappa = 0.01, B = 100 s/m at
20 m/s kappa > 1).  :data:`NODES_BY_STEEPNESS` encodes the default counts per kappa, from the errors against
M = 256 of ``benchmarks/bench_steady.py`` table C (random exponential, rational and linear laws, creeps 0.01-3
saturation, flat and corrugated); for steep laws small M can have several discrete solutions.  Because the
convergence is so erratic (a larger M can err more), every converged solution carries an a-posteriori estimate of
its T' error, computed when first read (the distributions' ``force_error``), :func:`force_error_estimate` (one
step of the fixed point on 2M and 6M nodes from the converged slip), calibrated by
``benchmarks/calibrate_slip_nodes.py`` (table A) to bound every error against 1024 nodes over exponential B = 1-100 s/m,
rational and table laws, V = 1-50 m/s, creeps 0.1-5 saturation, flat and corrugated (:data:`ESTIMATE_SAFETY`).

Creep stiffness.  ``dT'/dxi`` of the discrete solution follows from the converged state by the implicit function
theorem (:meth:`SlipEquations.force_slope`): one more Jacobian and linear solve, where a difference quotient would
need a second slip iteration.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property, lru_cache

import numpy as np
from scipy import fft
from scipy.linalg import lapack

from rollcontact.line.methods.polynomial.chebyshev import read_only, sine_series
from rollcontact.line.result import Distributions

DEFAULT_NODES = 16
"""Patch nodes M of the slip iteration unless the law is steep (:func:`default_nodes`)."""


NODES_BY_STEEPNESS = ((0.3, DEFAULT_NODES), (1.0, 32), (math.inf, 64))
"""Patch nodes M by the law's steepness ``kappa`` (:func:`default_nodes`): the first M whose bound exceeds kappa.
Calibrated against M = 256 on random laws, creeps and surfaces by ``benchmarks/bench_steady.py`` table C (module
docstring, Accuracy)."""


SLIP_ITERATIONS = 200
"""Default largest number of Newton iterations of the slip iteration (as many again for the relaxed fixed point)."""


STALL_RESIDUAL = 1e-5
"""Residual up to which a slip iteration that ends above its ``newton_tolerance`` still counts as converged.  Near a
kink of the discrete equations (a node next to the stick/slip boundary) the relaxed fixed point can stall above a
tight tolerance; a residual r in the nodal friction coefficients (relative to mu_s) changes T' = int mu p dx by at
most ``r mu_s / min mu_j`` relative, which the result's error estimate then includes
(:func:`solve_velocity_dependent`)."""


NEWTON_PATIENCE = 8
"""Newton iterations after which the residual must have halved, else the relaxed fixed point takes over."""


ESTIMATE_REFINEMENTS = (2, 6)
"""Fine nodes per patch node, K/M, of the a-posteriori estimate (:func:`force_error_estimate`, the larger of the
steps).  One step alone misses where T'_K happens to err like T'_M (erratic convergence); two rarely both do.  Each
grid nests in the finest (6M holds the nodes of 2M), which shares the evaluations; none may nest with M's (3M:
M and 3M often err alike).  ``benchmarks/calibrate_slip_nodes.py``, table B."""


ESTIMATE_SAFETY = 2.0
"""Factor on ``max_K |T'_K/T'_M - 1|`` in :func:`force_error_estimate`: with it the estimate exceeds the error against
1024 nodes, with a margin, in every case of ``benchmarks/calibrate_slip_nodes.py`` (table A)."""


@dataclass(frozen=True)
class SlipOperators:
    """Matrices of the slip iteration that depend only on the number of patch nodes M (see module docstring).

    Attributes
    ----------
    t_plus_one : ndarray
        ``1 + t_j`` at the patch nodes ``t_j = cos(theta_j)``.
    theta : ndarray
        ``theta_j = pi (j + 1/2)/M``.
    n : ndarray
        ``1..M`` as floats.
    dst : ndarray
        (M, M): ``e_1..e_M = dst @ Q`` (sine coefficients of nodal values).
    cosines : ndarray
        (M, M): ``T_n(t_j) = cos(n theta_j)``, so ``H1 = (2/E*) cosines @ e``.
    gradient : ndarray
        (M, M): ``cosines @ dst``, so ``H1 = (2/E*) gradient @ Q``.
    alternating : ndarray
        (M,): ``(-1)^n``, so ``H1(-1) = (2/E*) alternating @ e``.
    stacked : ndarray
        (2M + 1, M): ``dst``, ``alternating @ dst`` and ``gradient`` stacked, so that one product gives ``e``,
        ``(E*/2) H1(-1)`` and ``(E*/2) H1`` at the nodes (the slip iteration's evaluations are bound by the number
        of numpy calls at these sizes, not by arithmetic).
    sines : ndarray
        (M, M): ``sin(n theta_j)``, n = 1..M, so that p at the nodes is ``sines[:, :N] @ c_1..c_N`` (N <= M).
    sigma, sigma_plus_one : ndarray
        Stick-zone nodes ``cos(phi_k)``, ``phi_k = pi (k + 1/2)/(M + 1)``, and ``1 + sigma``.
    dct : ndarray
        (M + 1, M + 1): Chebyshev coefficients ``F_0..F_M = dct @ values`` at ``sigma_k``.
    stick_sines : ndarray
        (M + 1, M): ``sin(n phi_k)``, n = 1..M.
    """

    t_plus_one: np.ndarray
    theta: np.ndarray
    n: np.ndarray
    dst: np.ndarray
    cosines: np.ndarray
    gradient: np.ndarray
    alternating: np.ndarray
    stacked: np.ndarray
    sines: np.ndarray
    sigma: np.ndarray
    sigma_plus_one: np.ndarray
    dct: np.ndarray
    stick_sines: np.ndarray


@lru_cache(maxsize=16)
def slip_operators(m: int) -> SlipOperators:
    """The cached :class:`SlipOperators` for M = ``m`` patch nodes (arrays read-only)."""
    theta = np.pi * (np.arange(m) + 0.5) / m
    n = np.arange(1, m + 1, dtype=float)
    dst = (2.0 / m) * np.sin(np.multiply.outer(n, theta))
    dst[-1] *= 0.5
    cosines = np.cos(np.multiply.outer(theta, n))
    k = m + 1
    phi = np.pi * (np.arange(k) + 0.5) / k
    dct = (2.0 / k) * np.cos(np.multiply.outer(np.arange(k), phi))
    dct[0] *= 0.5
    sigma = np.cos(phi)
    alternating = (-1.0) ** n
    gradient = cosines @ dst
    stacked = np.vstack((dst, alternating @ dst, gradient))
    return SlipOperators(*read_only(1.0 + np.cos(theta), theta, n, dst, cosines, gradient, alternating, stacked,
                                    np.sin(np.multiply.outer(theta, n)), sigma, 1.0 + sigma, dct,
                                    np.sin(np.multiply.outer(phi, n))))


@dataclass(frozen=True)
class VelocityFrictionDistributions(Distributions):
    """Fields of a velocity-dependent solution (x [m] from the axis projection).

    ``force_error`` (the a-posteriori relative T' error, :func:`force_error_estimate`) is computed on first access
    and kept: it costs about as much as a Newton step, and callers that need no error (an FMU step without a
    tolerance) should not pay it.
    """

    half_width: float
    offset: float
    pressure_coefficients: np.ndarray
    q1_coefficients: np.ndarray  # e_n, sine series of mu(V s) p on the patch
    stick_half_width: float
    stick_offset: float
    stick_coefficients: np.ndarray  # F_n, Chebyshev coefficients of H1 on the stick zone
    contact_modulus: float
    creep: float
    estimator: Callable[[], float] = field(repr=False, compare=False)  # -> force_error

    @cached_property
    def force_error(self) -> float:
        """A-posteriori relative error of T' [1] (:func:`force_error_estimate`; NaN unless converged)."""
        return self.estimator()

    @property
    def nodes(self) -> int:
        """Patch nodes M the slip iteration used."""
        return self.q1_coefficients.size - 1

    def pressure(self, x):
        return sine_series(self.pressure_coefficients, (np.asarray(x, dtype=float) - self.offset) / self.half_width)

    def traction(self, x):
        x = np.asarray(x, dtype=float)
        q = sine_series(self.q1_coefficients, (x - self.offset) / self.half_width)
        if self.stick_half_width > 0.0:
            sigma = (x - self.stick_offset) / self.stick_half_width
            q = q - 0.5 * self.contact_modulus * sine_series(self.stick_coefficients, sigma)
        return math.copysign(1.0, self.creep) * q

    def slip(self, x):
        x = np.asarray(x, dtype=float)
        t = (x - self.offset) / self.half_width
        s = abs(self.creep) + gradient_q1(self.q1_coefficients, t, self.contact_modulus)
        if self.stick_half_width > 0.0:
            sigma = (x - self.stick_offset) / self.stick_half_width
            s = np.where(sigma <= 1.0, 0.0, s - outer_powers(self.stick_coefficients, sigma))
        return np.where(np.abs(t) <= 1.0, math.copysign(1.0, self.creep) * s, np.nan)


def nodal_pressure(ops: SlipOperators, c: np.ndarray) -> np.ndarray:
    """``p = max(sum_n c_n sin(n theta_j), 0)`` at the patch nodes (``c.size - 1 <= M``, as :func:`patch_nodes`
    ensures)."""
    return np.maximum(ops.sines[:, : c.size - 1] @ c[1:], 0.0)


def gradient_q1(e: np.ndarray, t, estar: float):
    """``H1 = (2/E*) sum e_n T_n(t)`` for |t| <= 1."""
    t = np.clip(np.asarray(t, dtype=float), -1.0, 1.0)
    return (2.0 / estar) * np.polynomial.chebyshev.chebval(t, np.concatenate(([0.0], e[1:])))


def outer_powers(f: np.ndarray, sigma) -> np.ndarray:
    """``sum_{n>=1} F_n w^n``, ``w = sigma - sqrt(sigma^2 - 1)`` for sigma > 1 (0 elsewhere)."""
    sigma = np.asarray(sigma, dtype=float)
    w = np.where(sigma > 1.0, sigma - np.sqrt(np.clip(sigma * sigma - 1.0, 0.0, None)), 0.0)
    powers = np.cumprod(np.broadcast_to(w[..., None], (*w.shape, f.size - 1)), axis=-1)
    return powers @ f[1:]


@dataclass
class StickMaps:
    """The a*-dependent quantities at one stick half-width ``a* = eta a`` (see :func:`stick_maps`)."""

    eta: float
    # at the stick nodes t_k = eta (1 + sigma_k) - 1 = cos(psi_k):
    cosines: np.ndarray  # (M+1, M): T_n(t_k) = cos(n psi_k)
    sines: np.ndarray  # (M+1, M): sin(n psi_k)
    slipping: np.ndarray  # bool (M,): patch nodes behind the stick zone
    sigma: np.ndarray  # their stick-zone coordinate (1 + t_j)/eta - 1 (> 1 where slipping)
    root: np.ndarray  # sqrt(sigma^2 - 1) where slipping, 1 inside the zone
    powers: np.ndarray  # (M, M): w_j^n, w = 1/(sigma + root), zero rows inside the zone


def stick_maps(ops: SlipOperators, eta: float) -> StickMaps:
    """Stick-zone nodes ``t_k = eta (1 + sigma_k) - 1`` with ``T_n(t_k)`` and ``sin(n psi_k)``, and the outer
    powers ``w_j^n`` behind it.

    ``F = (2/E*) dct @ cosines @ e`` re-expands ``H1`` on the zone; behind it ``sigma_j = (1 + t_j)/eta - 1 > 1``
    and ``w_j = 1/(sigma_j + sqrt(sigma_j^2 - 1))`` (the cancellation-free form of ``sigma - sqrt(sigma^2 - 1)``);
    inside it the powers are zero.  ``root`` is 1 inside (``sqrt(sigma^2 - 1)`` behind), so that the divisions here
    and in the eta-derivative stay finite without branches.  ``cos(n psi) + i sin(n psi) = (e^(i psi))^n`` by
    cumulative products: one complex exponential per node instead of 2M cosines and sines, rounding ~M eps.
    """
    psi = np.arccos(eta * ops.sigma_plus_one - 1.0)
    rotations = np.empty((psi.size, ops.n.size), dtype=complex)
    rotations[:] = np.exp(1j * psi)[:, None]
    np.cumprod(rotations, axis=1, out=rotations)
    sig = ops.t_plus_one / eta - 1.0
    slipping = sig > 1.0
    root = np.sqrt(np.maximum(sig * sig - 1.0, 0.0)) + ~slipping
    w = slipping / (sig + root)  # inside: 0/(sigma + 1) with sigma > -1
    return StickMaps(eta, rotations.real, rotations.imag, slipping, sig, root, w[:, None] ** ops.n)


def gradient_deta(ops: SlipOperators, maps: StickMaps, e: np.ndarray) -> np.ndarray:
    """``d/deta sum_n e_n T_n(t_k)`` at the stick nodes ``t_k = cos(psi_k) = eta (1 + sigma_k) - 1``.

    ``dT_n/dt = n sin(n psi)/sin(psi)`` and ``dt_k/deta = 1 + sigma_k``; ``sin(psi_k) > 0`` since every node is
    interior.
    """
    return (ops.sigma_plus_one / maps.sines[:, 0]) * (maps.sines @ (ops.n * e))


@dataclass
class SlipState:
    """One evaluation of the discrete equations at ``(mu_j, eta)`` (see :class:`SlipEquations`)."""

    mu: np.ndarray  # friction coefficient at the patch nodes
    eta: float  # a*/a (0: full slip)
    q: np.ndarray  # q1 = mu p at the nodes
    e: np.ndarray  # its sine coefficients e_1..e_M
    h: np.ndarray  # Chebyshev coefficients 1..M of the slope H1 + external on the patch
    s: np.ndarray  # slip S(q, a*) at the nodes (0 in the stick zone)
    f: np.ndarray | None  # F_0..F_M (partial slip)
    maps: StickMaps | None
    r_mu: np.ndarray  # mu - mu(V max(s, 0))
    r_h: float  # (F_0 + xi)/xi_scale (partial slip), else 0
    norm: float  # max(|r_mu|/mu_s, |r_h|)


class SlipEquations:
    """The discrete equations for one patch and law, in the nodal friction coefficients ``mu_j`` and ``eta = a*/a``.

    ``mu_j - mu(V max(s_j, 0)) = 0`` with ``s = S(mu p, a*)`` and ``F_0(a*) + xi = 0``.  The unknowns are the
    ``mu_j``, not the slips: q1 is linear in them, and where the law saturates (``dmu/dv ~ 0``, steep laws far into
    slip) the equations become linear instead of losing the slip's sensitivity, which is what makes Newton on the
    slips bounce.

    ``external`` (optional): Chebyshev coefficients ``0 .. M`` on the patch of a slope the patch does not produce
    (the other patches of a split contact, :mod:`rollcontact.line.methods.polynomial.patches_slip`), added to the slip
    everywhere.
    """

    def __init__(self, ops: SlipOperators, p: np.ndarray, estar: float, friction, rolling_speed: float, xi: float,
                 external: np.ndarray | None = None):
        self.ops, self.p, self.friction, self.speed, self.xi = ops, p, friction, rolling_speed, xi
        self.k2 = 2.0 / estar
        # a slope the patch does not produce itself (the other patches of a split contact): its T_0 coefficient acts
        # as creep, the others add to H1's
        self.creep = xi if external is None else xi + float(external[0])
        self.external = None if external is None else external[1:]
        # the external slope's -H1(-1) and H1 at the nodes, added to the patch's own in evaluate()
        self.external_end = 0.0 if external is None else float(ops.alternating @ self.external)
        self.external_nodes = None if external is None else ops.cosines @ self.external
        self.mu_s = float(friction.static_coefficient)
        # creep scale of the creep equation: |xi|, but at least 1e-5 of the Carter saturation creep, since F_0 sums
        # M terms of that size and cannot be resolved below ~M eps xi_sat (Newton would never meet the tolerance)
        self.xi_scale = max(xi, -1e-5 * self.k2 * self.mu_s * float(ops.alternating @ (ops.dst @ p)))

    def evaluate(self, mu: np.ndarray, eta: float) -> SlipState:
        """Residuals at ``(mu, eta)``; the branch follows ``xi < -H1(-1)`` (partial slip) or not (full slip)."""
        ops, xi, m = self.ops, self.creep, self.ops.n.size
        q = mu * self.p
        y = ops.stacked @ q
        e = y[:m]
        k2e = self.k2 * e
        h1 = self.k2 * y[m + 1 :]
        if self.external is not None:
            k2e += self.external
            h1 += self.external_nodes
        xi_full = -self.k2 * float(y[m]) - self.external_end  # creep of a vanishing stick zone, -H1(-1)
        if xi >= xi_full:
            eta = 0.0
        elif eta == 0.0:
            # Carter: xi(a*) = xi_full (1 - a*/a); a patch whose creep the other patches' fields reverse (split
            # contacts) starts sticking throughout
            eta = 1.0 - xi / xi_full if 0.0 < xi else 1.0
        if eta > 0.0:
            maps = stick_maps(ops, eta)
            f = ops.dct @ (maps.cosines @ k2e)
            s = np.where(maps.slipping, xi + h1 - maps.powers @ f[1:], 0.0)
            r_h = (float(f[0]) + xi) / self.xi_scale
        else:
            maps = f = None
            s = xi + h1
            r_h = 0.0
        r_mu = mu - self.friction.coefficient(self.speed * np.maximum(s, 0.0))
        return SlipState(mu, eta, q, e, k2e, s, f, maps, r_mu, r_h,
                         max(float(np.abs(r_mu).max()) / self.mu_s, abs(r_h)))

    def jacobian(self, st: SlipState) -> np.ndarray:
        """Exact Jacobian of ``(r_mu, r_h)`` in ``(mu, eta)`` at ``st`` (of ``r_mu`` in ``mu`` in full slip)."""
        return self.linearisation(st)[0]

    def linearisation(self, st: SlipState) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None]:
        """The Jacobian (:meth:`jacobian`), ``d r_mu/d mu``'s law factor ``dlaw = V dmu/dv`` at the slipping nodes
        (``d r_mu / d xi = -dlaw``), the stick-zone re-expansion ``re`` (``F = (2/E*) re @ q``) and ``dF/deta``
        (None in full slip).

        In eta: the stick-zone re-expansion through :func:`gradient_deta` and, behind the zone,
        ``d w^n/deta = n w^n (sigma + 1)/(eta sqrt(sigma^2 - 1))``; the jump of a node from slip to stick is not
        differentiated (s is continuous there).
        """
        ops, k2, p = self.ops, self.k2, self.p
        m = ops.n.size
        # d mu(V s+)/ds, zero in the stick zone and where s < 0
        dlaw = self.speed * self.friction.derivative(self.speed * np.maximum(st.s, 0.0)) * (st.s > 0.0)
        if st.maps is None:
            jac = (dlaw[:, None] * (-k2 * ops.gradient)) * p
            jac.flat[:: m + 1] += 1.0
            return jac, dlaw, None, None
        mp, f = st.maps, st.f
        # F = (2/E*) re @ q, and its eta-derivative applied to q
        re = ops.dct @ (mp.cosines @ ops.dst)
        df = ops.dct @ gradient_deta(ops, mp, st.h)
        # zero rows of the powers inside the zone make the (finite) factor irrelevant there
        factor = (mp.sigma + 1.0) / (mp.eta * mp.root)
        ds_deta = -((mp.powers @ (ops.n * f[1:])) * factor + mp.powers @ df[1:])
        jac = np.empty((m + 1, m + 1))
        jac[:m, :m] = (dlaw[:, None] * (-k2 * (ops.gradient - mp.powers @ re[1:]))) * p
        jac[:m, m] = -dlaw * ds_deta
        jac[m, :m] = (k2 / self.xi_scale) * re[0] * p
        jac[m, m] = float(df[0]) / self.xi_scale
        jac.flat[: m * (m + 1) : m + 2] += 1.0  # identity on the mu block only
        return jac, dlaw, re, df

    def force_slope(self, st: SlipState, a: float) -> float:
        """``dT'/dxi`` [N/m] of the discrete solution at a converged ``st`` (implicit function theorem).

        With the residuals ``R(u; xi) = 0`` in ``u = (mu, eta)``: ``du/dxi = -J^-1 dR/dxi``, where
        ``d r_mu/d xi = -dlaw`` (the slip behind the zone is ``xi + ...``) and ``d r_h/d xi = 1/xi_scale``, and
        ``dT'/dxi = grad_u T' . du/dxi`` with ``T' = (pi a/2)(e_1 - eta (E*/2) F_1)``, ``e_1 = dst_1 @ (mu p)``,
        ``(E*/2) F_1 = re_1 @ (mu p)``.  One Jacobian and one solve instead of a second slip iteration for a
        difference quotient; exact for the discrete equations (not differentiated: a node crossing the stick/slip
        boundary, where T' is continuous).
        """
        ops, p = self.ops, self.p
        m = ops.n.size
        jac, dlaw, re, df = self.linearisation(st)
        scale = 0.5 * math.pi * a
        if re is None:
            return scale * float((ops.dst[0] * p) @ solve_linear(jac, dlaw))
        rhs = np.empty(m + 1)
        rhs[:m] = dlaw
        rhs[m] = -1.0 / self.xi_scale
        du = solve_linear(jac, rhs)
        grad_mu = (ops.dst[0] - st.eta * re[1]) * p
        grad_eta = -(float(st.f[1]) + st.eta * float(df[1])) / self.k2
        return scale * (float(grad_mu @ du[:m]) + grad_eta * float(du[m]))

    def newton_step(self, st: SlipState) -> tuple[np.ndarray, float]:
        """``(dmu, deta)`` of Newton's method at ``st`` (``deta = 0`` in full slip)."""
        m = self.ops.n.size
        if st.maps is None:
            return solve_linear(self.jacobian(st), -st.r_mu), 0.0
        rhs = np.empty(m + 1)
        rhs[:m] = -st.r_mu
        rhs[m] = -st.r_h
        step = solve_linear(self.jacobian(st), rhs)
        return step[:m], float(step[m])

    def exact_stick(self, mu: np.ndarray, eta: float) -> SlipState:
        """:meth:`evaluate` at the root a* of ``F_0(a*) + xi = 0`` for fixed ``mu`` (safeguarded Newton in eta).

        ``F_0 + xi`` is negative as a* -> 0 (partial slip: ``xi < xi_full``) and ``xi > 0`` at a* = a (the mean
        of H1 over the patch is ``(2/E*) e_0 = 0``), so the root is bracketed by (0, 1].
        """
        st = self.evaluate(mu, eta)
        lo, hi = 0.0, 1.0
        ops = self.ops
        for _ in range(60):
            if st.maps is None or abs(st.r_h) <= 1e-13:
                return st
            if st.r_h < 0.0:
                lo = st.eta
            else:
                hi = st.eta
            slope = float(ops.dct[0] @ gradient_deta(ops, st.maps, st.h)) / self.xi_scale
            eta = st.eta - st.r_h / slope if slope > 0.0 else 0.5 * (lo + hi)
            if not lo < eta < hi:
                eta = 0.5 * (lo + hi)
            if abs(eta - st.eta) <= 1e-15:
                return st
            st = self.evaluate(mu, eta)
        return st

    def relaxed_iteration(self, newton_tolerance: float, max_iterations: int, history: list[float]):
        """The paper's fixed point, under-relaxed: ``s <- s + omega (S(mu(V s) p, a*) - s)``, a* exact at every step.

        From the Carter state (s = 0); ``omega`` halves (down to 0.05) whenever the largest change of s grows: slow,
        but it converges where Newton stalls on a kink of the discrete equations (a node next to the stick/slip
        boundary, whose slip goes like the square root of its distance).  Returns ``(state, iterations)``.
        """
        s = np.zeros(self.ops.n.size)
        st = self.evaluate(np.full(s.size, self.mu_s), 0.0)
        omega = 1.0
        last = math.inf
        for it in range(1, max_iterations + 1):
            st = self.exact_stick(self.friction.coefficient(self.speed * np.maximum(s, 0.0)), st.eta)
            history.append(st.norm)
            if st.norm <= newton_tolerance:
                return st, it
            change = float(np.abs(st.s - s).max())
            if change > last:
                omega = max(0.05, 0.5 * omega)
            last = change
            s = s + omega * (st.s - s)
        return st, max_iterations


def default_nodes(pressure_coefficients: np.ndarray, estar: float, friction, rolling_speed: float) -> int:
    """Patch nodes for 1e-3 in T': :data:`NODES_BY_STEEPNESS` at ``kappa = |dmu/dv(0)| V xi_sat / mu_s``.

    ``xi_sat = -(2/E*) mu_s sum c_n (-1)^n`` is the creep at which the stick zone of Coulomb friction with mu_s
    vanishes (Carter's ``mu a / R`` for a parabolic gap).
    """
    mu_s = float(friction.static_coefficient)
    c = pressure_coefficients
    xi_sat = -(2.0 / estar) * mu_s * float(c[1:] @ (-1.0) ** np.arange(1, c.size))
    kappa = abs(float(friction.derivative(0.0))) * rolling_speed * abs(xi_sat) / mu_s
    return next(m for bound, m in NODES_BY_STEEPNESS if kappa < bound)


def effective_nodes(nodes: int, pressure_coefficients: np.ndarray, estar: float, friction,
                    rolling_speed: float) -> int:
    """Patch nodes that ``solve_polynomial(scene, nodes=nodes)`` runs: ``nodes`` raised to :func:`default_nodes`
    and then to :func:`patch_nodes`."""
    return patch_nodes(max(int(nodes), default_nodes(pressure_coefficients, estar, friction, rolling_speed)),
                       pressure_coefficients)


def patch_nodes(nodes: int, pressure_coefficients: np.ndarray) -> int:
    """``nodes`` raised to two per pressure term: fewer would alias mu(V s) p (short corrugation, high order)."""
    return max(int(nodes), 2 * (pressure_coefficients.size - 1))


@dataclass(frozen=True)
class EstimateOperators:
    """Tables of :func:`force_error_estimate` for M patch nodes, on the finest grid of ``K = max(r) M`` nodes, r in
    ``ESTIMATE_REFINEMENTS``; the grid of ``K/j`` nodes (j odd) is every j-th node from the ``(j - 1)/2``-th.

    Attributes
    ----------
    theta, t_plus_one : ndarray
        ``theta_i = pi (i + 1/2)/K`` and ``1 + cos(theta_i)``.
    cosines : ndarray
        (K, M): ``T_n(t_i) = cos(n theta_i)``, n = 1..M (H1 of the M-node solution at the fine nodes).
    sines : ndarray
        (K, M): ``sin(n theta_i)``, n = 1..M (p at the fine nodes from its at most M/2 coefficients).
    masks, scales : ndarray
        (S, K) per grid of K' nodes: its nodes among the fine ones, and the factors turning scipy's DST-II of the
        masked values (twice the sum) into the sine coefficients ``e_1..e_K'`` (``1/K'``, half at n = K', 0 beyond).
    stick_cos : ndarray
        ``cos(phi_j)`` of the ``P = K/2 + 1`` stick-zone nodes (Gauss-Chebyshev, exact for the degree K + 1 of
        ``H1 T_1``).
    weights : ndarray
        (P, 2): ``F_0, F_1`` from values at the stick nodes.
    """

    theta: np.ndarray
    t_plus_one: np.ndarray
    cosines: np.ndarray
    sines: np.ndarray
    masks: np.ndarray
    scales: np.ndarray
    stick_cos: np.ndarray
    weights: np.ndarray


@lru_cache(maxsize=16)
def estimate_operators(m: int, refinements: tuple[int, ...]) -> EstimateOperators:
    """The cached :class:`EstimateOperators` for M = ``m`` and the grids ``refinements`` M (arrays read-only)."""
    k = max(refinements) * m
    theta = np.pi * (np.arange(k) + 0.5) / k
    masks = np.zeros((len(refinements), k))
    scales = np.zeros((len(refinements), k))
    for row, refinement in enumerate(refinements):
        size = refinement * m
        step = k // size
        masks[row, (step - 1) // 2 :: step] = 1.0
        scales[row, :size] = 1.0 / size
        scales[row, size - 1] *= 0.5
    stick = k // 2 + 1
    stick_cos = np.cos(np.pi * (np.arange(stick) + 0.5) / stick)
    weights = np.column_stack((np.full(stick, 1.0 / stick), (2.0 / stick) * stick_cos))
    angles = np.multiply.outer(theta, np.arange(1.0, m + 1.0))
    return EstimateOperators(*read_only(theta, 1.0 + np.cos(theta), np.cos(angles), np.sin(angles), masks, scales,
                                        stick_cos, weights))


def cosine_sine_sums(a: np.ndarray, b: np.ndarray, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``sum_n a_sn cos(n psi_p)`` and ``sum_n b_sn sin(n psi_p)`` (n = 1..K) for rows s of ``a``, ``b`` (S, K).

    By blocks: with ``n = B m + j`` (``B ~ sqrt(K)``), ``e^(i n psi) = (e^(i B psi))^m (e^(i psi))^j``, powers by
    cumulative products (rounding ~K eps), so each point needs one complex exponential instead of K cosines and K
    sines, and the sum is one matrix product and one weighted sum.  Returns two (S, P) arrays.
    """
    sets, k = a.shape
    block = math.isqrt(k) + 1
    rows = -(-(k + 1) // block)
    table = np.zeros((2 * sets, rows * block))
    table[:sets, 1 : k + 1] = a
    table[sets:, 1 : k + 1] = b
    powers = np.ones((psi.size, block + rows), dtype=complex)  # [e^(i j psi), j < B | e^(i B m psi), m < R]
    powers[:, 1:block] = np.exp(1j * psi)[:, None]
    np.cumprod(powers[:, :block], axis=1, out=powers[:, :block])
    powers[:, block + 1 :] = (powers[:, block - 1] * powers[:, 1])[:, None]
    np.cumprod(powers[:, block:], axis=1, out=powers[:, block:])
    # partial[p, (s, m)] = sum_j c_s,Bm+j e^(i j psi_p)
    partial = powers[:, :block] @ table.reshape(-1, block).T
    sums = np.einsum("psm,pm->sp", partial.reshape(psi.size, 2 * sets, rows), powers[:, block:])
    return sums[:sets].real, sums[sets:].imag


def force_error_estimate(eq: SlipEquations, st: SlipState, pressure_coefficients: np.ndarray) -> float:
    """A-posteriori relative error of T' of a converged state of one patch (no external slope):
    ``ESTIMATE_SAFETY max_K |T'_K / T'_M - 1|``.

    ``T'_K`` is one step of the paper's fixed point on ``K = r M`` patch nodes (r in ``ESTIMATE_REFINEMENTS``)
    from the converged state, without a new Newton solve: the converged slip series ``s_M`` (exact anywhere) gives
    ``q1 = mu(V s_M) p`` at the fine nodes, its sine coefficients ``e^K`` (a DST), the stick-zone coefficients
    ``F_0, F_1`` of ``H1 = (2/E*) sum e^K_n T_n`` and their a*-derivatives (:class:`EstimateOperators`,
    :func:`cosine_sine_sums`), a* re-solved from ``F_0 + xi = 0`` to first order, and
    ``T' = (pi a/2) (e_1 - (E*/2) eta F_1)``.  From the converged state that step lands within a few per cent of
    the K-node solution, so ``T'_K - T'_M`` is, up to T'_K's own smaller error, the error of T'_M.
    ``benchmarks/calibrate_slip_nodes.py`` calibrates ``ESTIMATE_SAFETY`` against 1024-node solutions.  Cost:
    ``O(K log K)`` transforms and ``O(K^1.5)`` products; about a Newton step of the M-node solve.
    """
    ops = estimate_operators(eq.ops.n.size, ESTIMATE_REFINEMENTS)
    k = ops.theta.size
    c = pressure_coefficients
    p = ops.sines[:, : c.size - 1] @ c[1:]
    s = ops.cosines @ (eq.k2 * st.e) + eq.xi  # the converged slip at the fine nodes
    if st.maps is not None:
        # the nodes behind the stick zone, sigma > 1, are the first ones (t decreases); pow(0, n) is slow
        behind = int(np.searchsorted(-ops.t_plus_one, -2.0 * st.eta))
        s[:behind] -= outer_powers(st.f, ops.t_plus_one[:behind] / st.eta - 1.0)
        s[behind:] = 0.0
    q = eq.friction.coefficient(np.maximum(eq.speed * s, 0.0)) * np.maximum(p, 0.0)
    e = fft.dst(ops.masks * q, type=2) * ops.scales  # (S, K): e_1..e_K' of each grid
    coarse = float(st.e[0])
    if st.maps is None:
        if coarse == 0.0:  # no traction at the nodes (p <= 0 there: a normal solution that failed): no ratio
            return math.nan
        return ESTIMATE_SAFETY * max(abs(fine / coarse - 1.0) for fine in e[:, 0].tolist())
    # stick nodes t = eta (1 + cos phi) - 1 = cos psi; dt/deta = 1 + cos phi, dT_n/dt = n sin(n psi)/sin(psi)
    psi = np.arccos(st.eta * ops.stick_cos + (st.eta - 1.0))
    values, slopes = cosine_sine_sums(e, e * np.arange(1, k + 1), psi)
    moments = (np.vstack((values, slopes * ((1.0 + ops.stick_cos) / np.sin(psi)))) @ ops.weights).tolist()
    eta, k2, xi = st.eta, eq.k2, eq.xi
    coarse -= eta * float(st.f[1]) / k2
    if coarse == 0.0:
        return math.nan
    error = 0.0
    for e1, (f0, f1), (df0, df1) in zip(e[:, 0].tolist(), moments[: len(e)], moments[len(e) :], strict=True):
        deta = -(k2 * f0 + xi) / (k2 * df0)  # a* re-solved to first order
        error = max(error, abs((e1 - eta * f1 - (f1 + eta * df1) * deta) / coarse - 1.0))
    return ESTIMATE_SAFETY * error


def solve_velocity_dependent(pressure_coefficients: np.ndarray, a: float, offset: float, estar: float, friction,
                             rolling_speed: float, creep: float, *, nodes: int = DEFAULT_NODES,
                             newton_tolerance: float = 1e-9, max_iterations: int = SLIP_ITERATIONS):
    """Creep-controlled steady rolling with ``mu = friction.coefficient(V |s|)`` (paper section 4.2).

    Parameters
    ----------
    pressure_coefficients : ndarray
        Sine coefficients c_n [Pa] of p on the patch (from the normal problem).
    a, offset : float
        Patch half-width and centre [m] (x from the axis projection).
    estar : float
        Contact modulus E* [Pa].
    friction : FrictionLaw
        mu(v), v [m/s], with ``derivative(v)``.
    rolling_speed : float
        V [m/s] > 0.
    creep : float
        xi [1].
    nodes : int
        Chebyshev nodes M on the patch (M + 1 on the stick zone) for the fit of mu(V s) p, raised to twice the
        number of pressure terms when p has more (:func:`patch_nodes`).  :func:`default_nodes` gives the count
        for 1e-3 in T' (``solve_polynomial`` applies it: :func:`effective_nodes`).
    newton_tolerance : float
        Convergence: largest Newton residual, ``|mu_j - mu(V s_j)| / mu_s`` and ``|F_0 + xi| / max(|xi|, 1e-5
        xi_sat)``.
    max_iterations : int
        Newton iterations, and as many again for the relaxed fixed point if Newton stalls.  An iteration that ends
        with a residual above ``newton_tolerance`` but at most :data:`STALL_RESIDUAL` counts as converged, its
        residual added to the error estimate; above it the solve has not converged.

    Returns
    -------
    dict
        ``stick_half_width``, ``tangential_force_per_length``, ``distributions``, ``iterations``, ``converged``,
        ``message``, ``history`` (residual norm per iteration), ``nodes`` (M used) and
        ``creep_stiffness_per_length`` (dT'/dxi [N/m], :meth:`SlipEquations.force_slope`; NaN unless converged).
        The distributions' ``force_error`` is :func:`force_error_estimate` (relative, NaN unless converged),
        computed when first read.
    """
    sign = math.copysign(1.0, creep)
    xi = abs(creep)
    c = pressure_coefficients
    ops = slip_operators(patch_nodes(nodes, c))
    p = nodal_pressure(ops, c)
    mu_s = float(friction.static_coefficient)
    eq = SlipEquations(ops, p, estar, friction, rolling_speed, xi)
    # Carter state: mu = mu_s everywhere (evaluate() sets a* = a (1 - xi/xi_sat))
    st = eq.evaluate(np.full(ops.n.size, mu_s), 0.0)
    history = [st.norm]
    st, it = newton(eq, st, newton_tolerance, max_iterations, history)
    stalled = st.norm * mu_s / float(st.mu.min()) if st.norm > newton_tolerance else 0.0
    converged = st.norm <= max(newton_tolerance, STALL_RESIDUAL)
    message = "" if converged else (f"velocity-dependent friction: the slip iteration did not converge in {it} "
                                    f"iterations (last residual {history[-1]:.3g})")
    h = st.eta * a
    e = np.concatenate(([0.0], st.e))
    f_coef = st.f if h > 0.0 else np.zeros(2)
    t_force = 0.5 * math.pi * a * e[1] - (0.5 * math.pi * h * 0.5 * estar * f_coef[1] if h > 0.0 else 0.0)
    slope = math.nan
    if converged:
        try:
            slope = eq.force_slope(st, a)
        except np.linalg.LinAlgError:  # a law with a kink at the solution: no derivative to give
            pass
    dist = VelocityFrictionDistributions(a, offset, pressure_coefficients, e, h, offset - a + h, f_coef, estar, creep,
                                         (lambda: force_error_estimate(eq, st, c) + stalled) if converged
                                         else nan_estimate)
    failures = []
    if float(st.s.min()) < -newton_tolerance * max(xi, 1e-300) * 10:
        failures.append("slip opposes the traction in the slip zone (a second stick zone)")
    if h > 0.0:
        q2 = -0.5 * estar * (ops.stick_sines @ f_coef[1:])
        ps = st.maps.sines[:, : c.size - 1] @ c[1:]  # p at the stick nodes (M >= 2 (c.size - 1) columns)
        pmax = float(p.max())
        if float(np.maximum(q2, -2.0 * mu_s * ps - q2).max()) > 1e-6 * mu_s * pmax:
            failures.append("traction bound |q| <= mu_s p violated in the stick zone")
    if failures:
        message = "; ".join(([message] if message else []) + failures)
    return {
        "stick_half_width": h,
        "tangential_force_per_length": sign * float(t_force),
        "distributions": dist,
        "iterations": it,
        "converged": converged and not failures,
        "message": message,
        "history": history,
        "nodes": ops.n.size,
        "creep_stiffness_per_length": slope,
    }


def newton(eq: SlipEquations, st: SlipState, newton_tolerance: float, max_iterations: int,
           history: list[float]) -> tuple[SlipState, int]:
    """Newton's method on ``eq`` from the state ``st`` until the residual norm is at most ``newton_tolerance``; the
    relaxed fixed point (:meth:`SlipEquations.relaxed_iteration`) takes over where Newton stalls or its matrix is
    singular.  Appends each residual norm to ``history``; returns the last state and the iterations."""
    it = 0
    best = st.norm
    while st.norm > newton_tolerance and it < max_iterations:
        it += 1
        try:
            dmu, deta = eq.newton_step(st)
        except np.linalg.LinAlgError:  # singular Jacobian (e.g. a law with a kink): the fixed point needs none
            st, extra = eq.relaxed_iteration(newton_tolerance, max_iterations, history)
            return st, it + extra
        # backtracking within a branch (a* kept inside (0, a]; a zone that wants to vanish is halved, the branch
        # test then decides).  A step that moves the stick/slip boundary across a node is taken as it is: the node
        # changes equation there (its slip goes like sqrt(a*_node - a*)), so the residuals of the two sides do not
        # compare, and backtracking would keep Newton on the wrong side of the kink
        lam = 1.0
        for _ in range(6):
            eta = st.eta + lam * deta
            trial = eq.evaluate(st.mu + lam * dmu, min(eta, 1.0) if eta > 0.0 else 0.5 * st.eta)
            if trial.norm < st.norm or not same_branch(st, trial):
                break
            lam *= 0.5
        st = trial
        history.append(st.norm)
        if it % NEWTON_PATIENCE == 0:
            if st.norm > 0.5 * best:  # stalled: a kink of the discrete equations, leave it to the fixed point
                st, extra = eq.relaxed_iteration(newton_tolerance, max_iterations, history)
                return st, it + extra
            best = st.norm
    return st, it


def nan_estimate() -> float:
    """The error estimate of a solution that did not converge."""
    return math.nan


def same_branch(one: SlipState, other: SlipState) -> bool:
    """Whether two states have the same slipping nodes (full slip: all of them)."""
    if one.maps is None or other.maps is None:
        return one.maps is None and other.maps is None
    return bool(np.array_equal(one.maps.slipping, other.maps.slipping))


def solve_linear(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """``matrix^-1 rhs`` by LAPACK's gesv directly (numpy.linalg.solve adds call overhead of its own)."""
    _, _, x, info = lapack.dgesv(matrix, rhs)
    if info != 0:
        raise np.linalg.LinAlgError("singular Newton matrix in the slip iteration")
    return x
