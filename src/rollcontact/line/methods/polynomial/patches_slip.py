"""Velocity-dependent friction on a contact of several patches (paper section 4.2 on the patches of
:mod:`rollcontact.line.methods.polynomial.patches`).

A short corrugation splits the contact (:mod:`rollcontact.line.methods.polynomial.patches` solves its normal problem);
with a friction law ``mu(V |s|)`` each patch k carries the slip iteration of
:mod:`rollcontact.line.methods.polynomial.slip`: ``q1_k = mu(V s) p_k`` on the patch, a bounded correction ``q2_k`` on a
stick zone at its leading edge, slip behind it.  The patches act on each other through the fields their tractions
produce outside themselves: the density ``sin(n theta)`` on a patch has the slope ``w^n`` off it
(:func:`rollcontact.line.methods.polynomial.patches.field_coefficients`), so on patch k the other patches add the smooth
slope

    ``E_k = sum_{j != k} [(2/E*) sum_n e_jn w_j^n - sum_n F_jn w_(S_j)^n]``

(``e_j``: sine coefficients of ``q1_j`` on the patch ``I_j``; ``F_j``: those of the correction on its stick zone
``S_j``), which enters patch k's equations as a known slope
(:class:`~rollcontact.line.methods.polynomial.slip.SlipEquations`' ``external``: its ``T_0`` coefficient acts as creep,
the others add to H1's).

Solution.  Block Gauss-Seidel over the patches, from Coulomb's solution with mu_s
(:func:`rollcontact.line.methods.polynomial.patches.solve_stick`: stick zones and corrections, ``q1 = mu_s p``): each
patch's slip iteration (Newton, warm-started from its last solution) with the others' fields frozen at their latest
values, in sweeps until no patch's external slope changes by more than :data:`SWEEP_TOLERANCE` of the Carter saturation
creep ``mu_s a/R`` (each patch then solves its equations for the fields of the others' final state: the coupled discrete
equations hold to the slip iteration's tolerance).  Every patch runs M nodes (the largest of
:func:`rollcontact.line.methods.polynomial.slip.patch_nodes` over the patches); the external slopes are truncated at
degree M, their first neglected coefficients are reported.

Accuracy.  As for one patch, T' converges like M^-1.5 and erratically; the result is that of 2M nodes, with the
relative T' error estimated as :data:`rollcontact.line.methods.polynomial.slip.ESTIMATE_SAFETY` times its difference to
the M-node solution (plus the truncation of the external slopes and of the normal problem): against the solution on
four times the nodes it bounds the error (``tests/methods/polynomial/test_patches_slip.py``, exponential laws of 3 and
30 s/m at 0.1 and 0.9 of saturation).  The discretised slip iteration on the same patches converges to it.

Validity (checked on the returned fields, each failure named): the normal problem's (``p >= 0``, the deformed gap
open); in every stick zone ``|q| <= mu_s p``; slip with the creep in every slip zone.  A patch whose slip turns
against the creep (a second stick zone) is outside the method.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rollcontact.line.hertz import hertz
from rollcontact.line.methods.polynomial.chebyshev import max_pressure, pressure_samples
from rollcontact.line.methods.polynomial.patches import (
    EXTRA_NODES,
    PatchesDistributions,
    SplitNormal,
    field_coefficients,
    intervals_of,
    series_sum,
    solve_stick,
)
from rollcontact.line.methods.polynomial.patches import validity_failures as normal_failures
from rollcontact.line.methods.polynomial.slip import (
    ESTIMATE_SAFETY,
    SlipEquations,
    gradient_q1,
    newton,
    nodal_pressure,
    outer_powers,
    patch_nodes,
    slip_operators,
)
from rollcontact.line.result import ContactResult, Distributions

MAX_SWEEPS = 60
"""Gauss-Seidel sweeps over the patches before the coupled iteration is reported as not converged."""


SWEEP_TOLERANCE = 1e-11
"""Largest change of a patch's external slope between its solves, relative to the Carter saturation creep, at
which the sweeps end."""


STIFFNESS_STEP = 1e-5
"""Creep step of the creep stiffness's difference, relative to the Carter saturation creep: small enough that the
one-sided difference agrees with central ones, large enough that the solves' tolerance does not show (checked on the
two-patch scene of ``tests/methods/polynomial/test_patches_slip.py``, 0.1-0.9 of saturation)."""


SLIP_TOLERANCE = 1e-9
"""Newton tolerance of each patch's slip iteration (that of
:func:`~rollcontact.line.methods.polynomial.slip.solve_velocity_dependent`)."""


SLIP_ITERATIONS = 200
"""Newton iterations per patch solve."""


@dataclass(frozen=True)
class SplitVelocityDistributions(Distributions):
    """Fields of a velocity-dependent solution on several patches (x [m] from the axis projection).

    Attributes
    ----------
    patches : tuple of (float, float)
        ``(centre, half-width)`` [m] of each patch, leading first.
    pressure_coefficients : tuple of ndarray
        ``[0, c_1 .. c_m]`` [Pa] per patch: ``p = sum c_n sin(n theta)``.
    q1_coefficients : tuple of ndarray
        ``[0, e_1 .. e_M]`` [Pa] per patch: ``q1 = mu(V s) p = sum e_n sin(n theta)``.
    zones : tuple of (float, float)
        ``(centre, half-width)`` [m] of each patch's stick zone (half-width 0: the patch slips throughout).
    stick_coefficients : tuple of ndarray
        ``F_0 .. F_M`` per zone: ``q2 = -(E*/2) sum F_n sin(n phi)``.
    external : tuple of ndarray
        Chebyshev coefficients ``0 .. M`` on each patch of the slope the other patches produce there.
    contact_modulus, creep : float
        E* [Pa], xi [1].
    """

    patches: tuple
    pressure_coefficients: tuple
    q1_coefficients: tuple
    zones: tuple
    stick_coefficients: tuple
    external: tuple
    contact_modulus: float
    creep: float

    def pressure(self, x):
        return series_sum(self.patches, self.pressure_coefficients, x)

    def traction(self, x):
        q = (series_sum(self.patches, self.q1_coefficients, x)
             + series_sum(self.zones, self.stick_coefficients, x, -0.5 * self.contact_modulus))
        return math.copysign(1.0, self.creep) * q

    def slip(self, x):
        x = np.asarray(x, dtype=float)
        s = np.full(x.shape, np.nan)
        for (c, h), e, (zc, zh), f, ext in zip(self.patches, self.q1_coefficients, self.zones,
                                               self.stick_coefficients, self.external, strict=True):
            t = (x - c) / h
            on = np.abs(t) <= 1.0
            own = abs(self.creep) + gradient_q1(e, t, self.contact_modulus) + np.polynomial.chebyshev.chebval(
                np.clip(t, -1.0, 1.0), ext)
            if zh > 0.0:
                sigma = (x - zc) / zh
                own = np.where(sigma <= 1.0, 0.0, own - outer_powers(f, sigma))
            s = np.where(on, math.copysign(1.0, self.creep) * own, s)
        return s


@dataclass
class PatchSlip:
    """One patch's slip iteration: its equations' data and its latest solution."""

    centre: float
    half_width: float
    pressure: np.ndarray  # [0, c_1 ..] [Pa]
    nodal_pressure: np.ndarray  # p at the patch nodes [Pa]
    fields: dict  # j -> (size, M) Chebyshev coefficients on this patch of w_j^n (the other patches' densities)
    external: np.ndarray  # (size,) the slope of the other patches, as last used
    state: object = None  # SlipState

    @property
    def stick_zone(self) -> tuple[float, float]:
        """``(centre, half-width)`` [m] of the stick zone of the latest solution."""
        a_star = self.state.eta * self.half_width if self.state is not None else 0.0
        return self.centre - self.half_width + a_star, a_star


def coupled_iteration(normal: SplitNormal, estar: float, friction, speed: float, xi: float, nodes: int,
                      scale: float, coarser: list[PatchSlip] | None = None, coulomb: tuple | None = None):
    """The block Gauss-Seidel iteration of the module docstring at M = ``nodes`` (``xi >= 0``).

    It starts from the solution on fewer nodes ``coarser``: its nodal friction coefficients at the new nodes
    (``mu(V s)`` of its slip), its stick zones and corrections and its external slopes, which leaves the sweeps
    little to do; else from ``q1 = mu_s p`` with the stick zones and corrections of Coulomb's friction with mu_s
    (``coulomb``: the half-widths a*_k and coefficients G_k of
    :func:`rollcontact.line.methods.polynomial.patches.solve_stick`, the correction being ``F_n = mu_s G_kn``), or,
    without it, with no stick zones.  The first sweep's fields are then those of a coupled solution: from full slip they
    can reverse a patch's creep at small creep, where its slip iteration has no solution.

    Returns ``(patches, sweeps, slip iterations, tail, failure)``: the :class:`PatchSlip` of every patch, the
    sweeps and patch Newton iterations used, the largest first neglected coefficient of the external slopes
    relative to ``scale`` and a failure message ('' on success).
    """
    ops = slip_operators(nodes)
    size = nodes + 1 + EXTRA_NODES
    k2 = 2.0 / estar
    mu_s = float(friction.static_coefficient)
    intervals = intervals_of(normal.edges)
    patches = []
    for k, ((c, h), g) in enumerate(zip(intervals, normal.g, strict=True)):
        coefficients = 0.5 * estar * g
        nodal = nodal_pressure(ops, coefficients)
        fields = {j: field_coefficients((c, h), other, nodes, size) for j, other in enumerate(intervals) if j != k}
        patches.append(PatchSlip(c, h, coefficients, nodal, fields, np.zeros(size)))
    corrections = [np.zeros(nodes + 1) for _ in patches]
    zones = [(0.0, 0.0) for _ in patches]
    starts = [(np.full(nodes, mu_s), 0.0) for _ in patches]
    if coulomb is not None and coarser is None:
        for k, (patch, a_star, big_g) in enumerate(zip(patches, *coulomb, strict=True)):
            if a_star > 0.0:
                count = min(nodes + 1, big_g.size)
                corrections[k][1:count] = mu_s * big_g[1:count]
                zones[k] = (patch.centre - patch.half_width + a_star, float(a_star))
                starts[k] = (starts[k][0], float(a_star) / patch.half_width)
    if coarser is not None:
        slip = distributions(coarser, estar, xi).slip
        for k, (patch, old) in enumerate(zip(patches, coarser, strict=True)):
            x = patch.centre + patch.half_width * (ops.t_plus_one - 1.0)
            starts[k] = (friction.coefficient(speed * np.maximum(slip(x), 0.0)), old.state.eta)
            size_old = old.external.size
            patch.external[:min(size, size_old)] = old.external[:size]
            if old.state.maps is not None:
                corrections[k][:old.state.f.size] = old.state.f
                zones[k] = old.stick_zone
    densities = [k2 * (ops.dst @ (mu * patch.nodal_pressure)) for patch, (mu, _) in zip(patches, starts, strict=True)]
    iterations = 0
    history: list[float] = []
    for sweep in range(1, MAX_SWEEPS + 1):
        change = 0.0
        for k, patch in enumerate(patches):
            external = np.zeros(size)
            for j, field in patch.fields.items():
                external += field @ densities[j]
                if zones[j][1] > 0.0:
                    external -= field_coefficients((patch.centre, patch.half_width), zones[j], nodes, size) @ \
                        corrections[j][1:]
            change = max(change, float(np.abs(external - patch.external).max()))
            patch.external = external
            eq = SlipEquations(ops, patch.nodal_pressure, estar, friction, speed, xi, external=external[:nodes + 1])
            st = eq.evaluate(*((patch.state.mu, patch.state.eta) if patch.state is not None else starts[k]))
            st, it = newton(eq, st, SLIP_TOLERANCE, SLIP_ITERATIONS, history)
            iterations += it
            if not st.norm <= SLIP_TOLERANCE:
                return patches, sweep, iterations, math.inf, (
                    f"the slip iteration of patch {k + 1} did not converge in {it} iterations (last residual "
                    f"{st.norm:.3g})")
            patch.state = st
            densities[k] = k2 * st.e
            corrections[k] = st.f if st.maps is not None else np.zeros(nodes + 1)
            zones[k] = patch.stick_zone
        if change <= SWEEP_TOLERANCE * scale:
            tail = max(float(np.abs(p.external[nodes + 1:nodes + 5]).max()) for p in patches) / scale
            return patches, sweep, iterations, tail, ""
    return patches, MAX_SWEEPS, iterations, math.inf, (
        f"the patches' coupling did not converge in {MAX_SWEEPS} sweeps (last change of an external slope "
        f"{change / scale:.3g} of the saturation creep)")


def patch_force(patch: PatchSlip, estar: float) -> float:
    """T' [N/m] of one patch: ``(pi h/2) e_1 - (pi a*/2)(E*/2) F_1``."""
    st = patch.state
    force = 0.5 * math.pi * patch.half_width * float(st.e[0])
    if st.maps is not None:
        force -= 0.5 * math.pi * st.eta * patch.half_width * 0.5 * estar * float(st.f[1])
    return force


def distributions(patches: list[PatchSlip], estar: float, creep: float) -> SplitVelocityDistributions:
    nodes = patches[0].state.e.size
    return SplitVelocityDistributions(
        tuple((p.centre, p.half_width) for p in patches), tuple(p.pressure for p in patches),
        tuple(np.concatenate(([0.0], p.state.e)) for p in patches), tuple(p.stick_zone for p in patches),
        tuple(p.state.f if p.state.maps is not None else np.zeros(nodes + 1) for p in patches),
        tuple(p.external[:nodes + 1] for p in patches), estar, creep)


def tangential_failures(dist: SplitVelocityDistributions, mu_s: float, scale: float) -> list[str]:
    """``|q| <= mu_s p`` in every stick zone and slip with the creep in every slip zone, sampled; each failure
    named."""
    out = []
    sign = math.copysign(1.0, dist.creep)
    p_scale = max(float(np.abs(c).sum()) for c in dist.pressure_coefficients)
    zones = [(zc, zh) for zc, zh in dist.zones if zh > 0.0]
    if zones:
        x = np.concatenate([zc + zh * np.cos(np.pi * np.arange(1, 64) / 64) for zc, zh in zones])
        q = sign * dist.traction(x)
        excess = np.abs(q) - mu_s * dist.pressure(x)
        j = int(excess.argmax())
        if excess[j] > 1e-6 * mu_s * p_scale:
            out.append(f"traction bound |q| <= mu_s p violated in the stick zone at x = {x[j]:.6g} m")
    slipping = [(zc + zh, c + h) for (c, h), (zc, zh) in zip(dist.patches, dist.zones, strict=True)
                if zc + zh < c + h]
    if slipping:
        x = np.concatenate([lo + (hi - lo) * np.arange(1, 48) / 48 for lo, hi in slipping])
        s = sign * dist.slip(x)
        j = int(s.argmin())
        if s[j] < -1e-8 * scale:
            out.append(f"slip opposes the traction in the slip zone (s = {s[j]:.3g} at x = {x[j]:.6g} m): a second "
                       "stick zone")
    return out


def solve_split_velocity(expansion, normal: SplitNormal, estar: float, friction, speed: float, creep: float,
                         nodes: int) -> ContactResult:
    """Steady rolling with ``mu = friction.coefficient(V |s|)`` on the patches of ``normal`` (module docstring).

    Parameters
    ----------
    expansion : SlopeExpansion
        The gap of the scene (for the normal problem's validity checks).
    normal : SplitNormal
        The patches and their pressure (:func:`rollcontact.line.methods.polynomial.patches.split_normal`, converged).
    estar : float
        E* [Pa].
    friction : FrictionLaw
        mu(v), v [m/s], with ``derivative(v)``.
    speed : float
        V [m/s] > 0.
    creep : float
        xi [1].
    nodes : int
        Least patch nodes M of the coarser solution (raised to twice the pressure terms, as for one patch); the
        result is that of 2M.

    Returns
    -------
    ContactResult
        ``residual``: the relative T' error estimate (module docstring, Accuracy); ``info["patches"]``,
        ``info["stick_zones"]`` (leading and trailing ends [m]), ``info["nodes"]`` (2M), ``info["sweeps"]``;
        ``creep_stiffness_per_length``: a one-sided difference of T' over :data:`STIFFNESS_STEP` of the saturation
        creep towards zero creep, the perturbed solution warm-started from the result's (a few sweeps, NaN if they
        fail).
    """
    xi = abs(creep)
    sign = math.copysign(1.0, creep)
    mu_s = float(friction.static_coefficient)
    scale = mu_s * sum(0.5 * (normal.edges[i + 1] - normal.edges[i])
                       for i in range(0, normal.edges.size, 2)) / expansion.radius
    coarse = max(patch_nodes(nodes, 0.5 * estar * g) for g in normal.g)
    geometry, info = normal.geometry(creep), normal.info()
    forces = []
    sweeps = iterations = 0
    failure = ""
    tail = 0.0
    patches = None
    halves, big_g, *_, stick_failure = solve_stick(
        expansion, normal.edges, intervals_of(normal.edges), normal.load, estar, mu_s, xi, normal.terms,
        hertz(normal.load, expansion.radius, estar)[0], normal.accept)
    coulomb = None if stick_failure else (halves, big_g)
    for m in (coarse, 2 * coarse):
        patches, used, its, tail_m, failure = coupled_iteration(normal, estar, friction, speed, xi, m, scale, patches,
                                                                coulomb)
        sweeps += used
        iterations += its
        tail = max(tail, tail_m)
        if failure:
            break
        forces.append(sum(patch_force(p, estar) for p in patches))
    info.update(nodes=2 * coarse, sweeps=sweeps)
    if failure:
        return ContactResult(method="polynomial", success=False, message=f"several patches: {failure}",
                             tangential_force_per_length=math.nan, stick_half_width=math.nan, max_pressure=math.nan,
                             iterations=normal.iterations + iterations, residual=math.inf, info=info, **geometry)
    force = forces[-1]
    dist = distributions(patches, estar, creep)
    if xi == 0.0:
        force = 0.0
    estimate = (ESTIMATE_SAFETY * abs(forces[0] / force - 1.0) if force != 0.0 else 0.0) + tail + normal.residual
    info["stick_zones"] = [(zc - zh, zc + zh) for zc, zh in dist.zones]
    check = PatchesDistributions(dist.patches, tuple(normal.g), (), (), estar, mu_s, 0.0)
    messages = normal_failures(expansion, check, normal.edges) + tangential_failures(dist, mu_s, scale)
    p_max = max(max_pressure(c, *pressure_samples(c)) for c in dist.pressure_coefficients)
    success = not messages
    stiffness = math.nan
    if success:
        step = STIFFNESS_STEP * scale if xi < 2.0 * STIFFNESS_STEP * scale else -STIFFNESS_STEP * scale
        # the start re-samples mu(V s) with the perturbed creep: the result's own nodal mu would meet the slip
        # iteration's tolerance before any step in full slip (the stiffness would be off there)
        perturbed, _, its, _, perturbed_failure = coupled_iteration(normal, estar, friction, speed, xi + step,
                                                                    2 * coarse, scale, patches)
        iterations += its
        if not perturbed_failure:
            stiffness = (sum(patch_force(p, estar) for p in perturbed) - forces[-1]) / step
    count = len(patches)
    message = (f"converged ({count} patch{'es' if count > 1 else ''}, velocity-dependent friction)" if success
               else "several patches: " + "; ".join(messages))
    return ContactResult(method="polynomial", success=success, message=message,
                         tangential_force_per_length=sign * force, creep_stiffness_per_length=stiffness,
                         stick_half_width=float(sum(zh for _, zh in dist.zones)), max_pressure=p_max,
                         iterations=normal.iterations + iterations, residual=estimate, distributions=dist, info=info,
                         **geometry)
