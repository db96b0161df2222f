"""Steady rolling by the discretised method (Kalker-type boundary elements), registered as method ``"discretised"``.

The accuracy yardstick for the polynomial method and the fallback where it cannot apply (split contacts, rough
profiles, velocity-dependent friction).  Conventions are the package's (docs/physics.md, Conventions): x is fixed to
the cylinder axis (``x = X - x_c``), material flows in +x, the leading edge is ``x = Delta - a``,
``s = xi + du/dx + (1/V) du/dt`` and in slip ``q = mu p sign(s)``.  The grid, the normal problem (NORM) and the
transient stepper (TANG) this builds on are :mod:`rollcontact.core.halfspace`.

* Steady rolling: the fixed point of the transient stepper for ``ds = h``, ``s = xi - K q`` with
  ``K = (M - M_1)/h``, solved directly by the same active set, or reached by marching (``steady="march"``,
  :func:`march_to_steady`).
* Velocity-dependent friction (``steady="structured"``, :func:`steady_leading_edge_stick`): a stick zone at the
  leading edge of each patch, slip behind it with ``q = mu(V |s|) p sign(xi)`` (paper section 4.2); Newton on the
  slip for each set of stick lengths, bisection on each patch's stick length (the shortest stick zone behind which
  the material slips in the traction's direction), the patches' zones in turn until none changes.  With
  dmu/dv < 0 the transient problem is ill-posed, so this is the only way to that steady state (docs/physics.md,
  Velocity-dependent friction).
* :func:`extrapolated`: T' by Richardson extrapolation from two grids, each the mean over several grid placements
  (the converged references, and the ``extrapolate`` setting ``auto`` offers).

The steady state does not depend on the datum L of the tangential displacement (docs/physics.md, Instationary
rolling); only the marching's approach to it does.  The settings ``auto`` chooses from, and their error bounds,
are :mod:`rollcontact.line.methods.discretised.accuracy`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy import linalg

from rollcontact.core.friction import FrictionLaw
from rollcontact.core.halfspace.elements import (
    MAX_ELEMENTS,
    MIN_ELEMENTS,
    Grid,
    Operators,
    runs,
    tangential_certificate,
)
from rollcontact.line.halfspace.grid import (
    DEFAULT_ELEMENTS,
    ITERATION_TOLERANCE,
    automatic_grid,
    check_count,
    check_iteration_tolerance,
    patch_geometry,
)
from rollcontact.line.halfspace.solver import (
    StepResult,
    TransientSolver,
    TransientState,
    contact_window,
    fitted_normal,
)
from rollcontact.line.result import ContactResult, NoContact, TabulatedDistributions
from rollcontact.line.scene import Scene, far_gap_points

STEADY_MODES = ("direct", "march", "structured")


STRUCTURED_SWEEPS = 8  # of the several-patch stick-zone search (each patch's zone with the others held)


# ------------------------------------------------------------------------------ velocity-dependent friction
@dataclass(frozen=True)
class StructuredSteady:
    """Steady solution with a stick zone at the leading edge of each patch (velocity-dependent friction)."""

    traction: np.ndarray
    slip: np.ndarray
    stick: np.ndarray
    iterations: int
    converged: bool
    message: str
    certificate: dict
    creep_slope: float = math.nan  # d(sum q)/dxi [Pa]: dT'/dxi over the element width, for the final sets


def steady_leading_edge_stick(ops: Operators, pressure: np.ndarray, creep: float, law: FrictionLaw,
                              speed: float, iteration_tolerance: float,
                              stick_fraction: float = 0.5) -> StructuredSteady:
    """Steady rolling with ``q = mu(V |s|) p sign(xi)`` in slip and a stick zone at the leading edge of each patch.

    For stick zones S (in patch k, m_k elements starting j0_k elements behind its leading edge; j0_k > 0 only
    where the pressure of the first elements is too small to hold their stick traction) the stick tractions are
    eliminated, ``q_S = K_SS^-1 (xi - K_SP Q(s_P))``, and the slip of the other elements P of all patches satisfies
    ``R(s) = s - (xi - K_PS K_SS^-1 xi) + (K_PP - K_PS K_SS^-1 K_SP) Q(s) = 0``, ``Q(s) = mu(V|s|) p sign(xi)``,
    solved by damped Newton (paper section 4.2; Nielsen & Theiler 1996).  A patch's stick length is the smallest
    m_k for which its material slips in the direction of the traction, ``sign(xi) s >= 0`` (bisection on m_k; for
    a Coulomb law on one patch this is Carter's a*); j0_k grows while the first stick element exceeds ``mu(0) p``.
    The patches act on each other through K: with several, each patch's zone is found with the others' held, in
    sweeps until none changes (at most :data:`STRUCTURED_SWEEPS`).  The certificate checks both conditions on every
    element.  ``stick_fraction`` (e.g. Carter's a*/a) seeds the search for each m_k, as that fraction of the patch.

    ``creep_slope`` is ``d(sum q)/dxi`` for the final sets by the implicit function theorem: ``r0`` and ``q_S`` are
    linear in xi, so ``(I + Schur dQ/ds) ds/dxi = r0/xi`` and ``dq_S/dxi = y0/xi - W dq_P/dxi``.
    """
    contact = pressure > 0.0
    n = pressure.size
    spans = runs(contact)
    if not spans:
        return StructuredSteady(np.zeros(n), np.zeros(n), contact.copy(), 0, False, "no contact patch", {})
    elements = np.flatnonzero(contact)  # the patches' elements in order
    sizes = [stop - start for start, stop in spans]
    offsets = np.cumsum([0, *sizes[:-1]]).tolist()  # of each patch among the contact elements
    nc = elements.size
    K = ops.K[np.ix_(elements, elements)]
    p = pressure[elements]
    mu_static = law.static_coefficient
    if creep == 0.0:  # full stick: dq/dxi = K^-1 1
        slope = float(linalg.solve(K, np.ones(nc), check_finite=False).sum())
        return StructuredSteady(np.zeros(n), np.zeros(n), contact.copy(), 0, True, "zero creep: no traction",
                                {"stick_slip": 0.0, "traction_bound": 0.0, "slip_direction": 0.0}, slope)
    sigma = math.copysign(1.0, creep)
    tol = 1e-3 * iteration_tolerance * abs(creep)
    slip_tolerance = iteration_tolerance * ops.kappa * mu_static * pressure.max()
    total_newton = 0
    cache: dict[tuple, tuple] = {}
    last_slip = np.full(nc, creep)

    def eliminated(zones):
        """Stick mask, slip indices, their pressures and ``y0 = K_SS^-1 xi``, ``W = K_SS^-1 K_SP``, ``r0``, Schur
        complement for the stick zones ``((j0_k, m_k), ...)``, one per patch."""
        stick = np.zeros(nc, dtype=bool)
        for offset, (j0, m) in zip(offsets, zones, strict=True):
            stick[offset + j0:offset + j0 + m] = True
        si, pi = np.flatnonzero(stick), np.flatnonzero(~stick)
        if si.size:
            lu = linalg.lu_factor(K[np.ix_(si, si)], check_finite=False)
            y0 = linalg.lu_solve(lu, np.full(si.size, creep), check_finite=False)
            w = linalg.lu_solve(lu, K[np.ix_(si, pi)], check_finite=False)
            r0 = creep - K[np.ix_(pi, si)] @ y0
            schur = K[np.ix_(pi, pi)] - K[np.ix_(pi, si)] @ w
        else:
            y0, w = np.zeros(0), np.zeros((0, nc))
            r0, schur = np.full(nc, creep), K
        return stick, pi, p[pi], y0, w, r0, schur

    def traction_rate(s, pp):
        """dQ/ds of ``Q(s) = mu(V|s|) p sign(xi)``."""
        return law.derivative(speed * np.abs(s)) * speed * np.where(s * sigma >= 0, 1.0, -1.0) * pp

    def solve_for(zones):
        """q, s on the contact elements, Newton success and the slip-direction test per patch for the zones."""
        nonlocal total_newton
        if zones in cache:
            return cache[zones]
        stick, pi, pp, y0, w, r0, schur = eliminated(zones)

        def traction(s):
            return law.coefficient(speed * np.abs(s)) * pp * sigma

        def residual(s):
            return s - r0 + schur @ traction(s)

        # warm start from the last solved stick lengths: the slip behind the zones barely changes
        s = np.where(sigma * last_slip[pi] > 0, last_slip[pi], creep)
        ok = True
        if pi.size:
            r = residual(s)
            ok = False
            for _ in range(100):
                total_newton += 1
                norm = np.abs(r).max()
                if norm <= tol:
                    ok = True
                    break
                dq = traction_rate(s, pp)
                step = linalg.solve(np.eye(pi.size) + schur * dq[None, :], -r, check_finite=False)
                t = 1.0
                while True:
                    s_try = s + t * step
                    r_try = residual(s_try)
                    # Armijo-type damping keeps Newton on the branch where |R| decreases
                    if np.abs(r_try).max() < (1.0 - 1e-4 * t) * norm or t < 1e-6:
                        break
                    t *= 0.5
                s, r = s_try, r_try
        q = np.zeros(nc)
        q[pi] = traction(s)
        q[stick] = y0 - w @ q[pi]
        slip = np.zeros(nc)
        slip[pi] = s
        last_slip[pi] = s
        wrong = sigma * slip < -slip_tolerance
        feasible = tuple(not wrong[offset:offset + size].any() for offset, size in zip(offsets, sizes, strict=True))
        cache[zones] = (q, slip, stick, ok, feasible)
        return cache[zones]

    def shortest_feasible(zones, k, j0, guess):
        """Smallest m_k passing patch k's slip-direction test, the other zones held: bracket outwards from
        ``guess``, then bisect.

        The test fails for too short a stick zone and holds beyond the true one (too long a zone breaks the
        traction bound instead); m_k = size - j0 (no slip behind the zone) counts as passing.
        """
        def passes(m):
            return solve_for(zones[:k] + ((j0, m),) + zones[k + 1:])[4][k]

        top = sizes[k] - j0
        guess = min(max(guess, 0), top)
        step = 1
        if guess < top and passes(guess):
            hi, lo = guess, guess - 1
            while lo >= 0 and passes(lo):
                hi, lo, step = lo, lo - step, 2 * step
            lo = max(lo, -1)
        else:
            lo, hi = guess, guess + 1
            while hi < top and not passes(hi):
                lo, hi, step = hi, hi + step, 2 * step
            hi = min(hi, top)
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if passes(mid):
                hi = mid
            else:
                lo = mid
        return hi

    def patch_zone(zones, k):
        """Patch k's zone (j0_k, m_k) with the other zones held."""
        offset = offsets[k]
        m = zones[k][1] + zones[k][0]
        for j0 in range(sizes[k]):
            m = shortest_feasible(zones, k, j0, m)
            found = zones[:k] + ((j0, m),) + zones[k + 1:]
            q_c = solve_for(found)[0]
            if m == 0 or abs(q_c[offset + j0]) <= mu_static * p[offset + j0] * (1.0 + 1e-12):
                break
            # the stick zone starts one element later and is one element shorter (the next guess)
            m -= 1
        return found

    final = tuple((0, int(round(stick_fraction * size))) for size in sizes)
    for _ in range(STRUCTURED_SWEEPS if len(sizes) > 1 else 1):  # one patch: nothing to hold, one pass
        start = final
        for k in range(len(sizes)):
            final = patch_zone(final, k)
        if final == start:
            break
    q_c, s_c, stick_c, ok, _ = solve_for(final)
    q, slip = np.zeros(n), np.zeros(n)
    q[elements], slip[elements] = q_c, s_c
    stick = np.zeros(n, dtype=bool)
    stick[elements] = stick_c
    slip_check = np.where(contact, creep - ops.K[:, elements] @ q_c, 0.0)
    scale = ops.kappa * mu_static * pressure.max()
    bound = np.where(stick, mu_static, law.coefficient(speed * np.abs(slip))) * pressure
    certificate = tangential_certificate(q, slip_check, stick, bound, contact, scale)
    converged = ok and max(certificate.values()) <= 100.0 * iteration_tolerance
    message = ("converged" if converged else
               "Newton did not converge" if not ok else f"leading-edge stick structure fails: {certificate}")
    slope = math.nan
    if converged:
        _, pi, pp, y0, w, r0, schur = eliminated(final)
        dq = traction_rate(s_c[pi], pp)
        dq_p = dq * linalg.solve(np.eye(pi.size) + schur * dq[None, :], r0 / creep, check_finite=False)
        slope = float(dq_p.sum() + y0.sum() / creep - (w @ dq_p).sum())
    return StructuredSteady(q, slip, stick, total_newton, converged, message, certificate, slope)


def no_contact_result(scene: Scene) -> ContactResult:
    return ContactResult(method="discretised", success=True, message="no load: no contact",
                         normal_load_per_length=0.0, tangential_force_per_length=0.0, creep=scene.creep,
                         contact_half_width=0.0, contact_offset=0.0, stick_half_width=0.0, max_pressure=0.0,
                         distributions=NoContact())


def far_gap_closing(scene: Scene, grid: Grid, pressure: np.ndarray, patches) -> tuple[float, float] | None:
    """``(X, gap)`` [m] of a point beyond the window where the deformed gap closes, or None.

    At the :func:`rollcontact.line.scene.far_gap_points` outside the window the deformed gap is, from the nearest outer
    patch edge e, ``h(x) = h0(x) - h0(e) - (2/(pi E*)) sum_i p_i w ln|(x - z_i)/(e - z_i)|`` (x axis coordinates,
    z_i the element centres, w their width): the undeformed gap less the elastic rise, the integral of the slope of
    the normal displacement from e to x.
    """
    far = far_gap_points(scene.surface, scene.radius, scene.axis_position) - scene.axis_position
    far = far[(far < grid.x_min) | (far > grid.x_max)]
    if not far.size or not patches:
        return None
    edge = np.where(far < patches[0][0], patches[0][0], patches[-1][1])
    z, w = grid.centres, grid.element_width
    rise = (2.0 * w / (math.pi * scene.material.contact_modulus)) * (
        np.log(np.abs(far[:, None] - z)) - np.log(np.abs(edge[:, None] - z))).dot(pressure)
    h0 = far**2 / (2.0 * scene.radius) - scene.surface.height(far + scene.axis_position)
    h0_edge = edge**2 / (2.0 * scene.radius) - scene.surface.height(edge + scene.axis_position)
    gap = h0 - h0_edge - rise
    i = int(gap.argmin())
    if gap[i] < 0.0:
        return float(far[i] + scene.axis_position), float(gap[i])
    return None


def solve_discretised(scene: Scene, *, elements=None, window=None, iteration_tolerance=ITERATION_TOLERANCE, steady=None,
                      finish: bool = True, datum_length=None, tangential_force_per_length=None,
                      extrapolate: int = 0) -> ContactResult:
    """Solve a scene with the discretised (Kalker-type boundary-element) method.

    Parameters
    ----------
    scene : Scene
        The case; ``scene.creep`` is used unless ``tangential_force_per_length`` is given.
    elements : int, optional
        Number of elements n in [8, 4000]; default 200 (more for short surface wavelengths: 16 per wavelength).
    window : (float, float), optional
        Grid window (x_min, x_max) [m] in the axis coordinate; default from the Hertz width and the surface,
        widened automatically (up to 3 times) when a patch reaches its edge.
    iteration_tolerance : float
        Relative tolerance of the active-set iteration and certificates, in [1e-14, 1e-3].
    steady : {"direct", "march", "structured"}, optional
        How the steady state is found: ``"direct"`` (default for constant friction) the active set on the
        steady operator; ``"march"`` Kalker's transient marching with ``ds = h`` until the slip pattern
        settles (finished by the direct solve when ``finish``); ``"structured"`` (default for
        velocity-dependent friction) a stick zone at the leading edge of each patch, Newton on the slip
        (:func:`steady_leading_edge_stick`).  Where it fails on the automatic grid (no ``elements``, no
        ``window``), once more on twice the elements, up to the largest grid ``auto`` offers
        (:data:`DISCRETISED_ELEMENTS`, as
        :meth:`~rollcontact.line.methods.discretised.accuracy.DiscretisedAccuracy.retry` does for a grid chosen for a
        tolerance): a slip zone shorter than an element at a patch end leaves a stick element above mu p, or one
        slipping against the traction; the message says so.
    finish : bool
        With ``steady="march"``: polish the marched state by the direct steady solve.
    datum_length : float, optional
        Datum L [m] of the transient marching (creep control needs L > window/4).  The steady state does not
        depend on it, only the speed of the approach does (the datum acts as a relaxation length), so the
        default is the shortest safe choice, the window length.
    tangential_force_per_length : float, optional
        T' [N/m]: force control (constant friction only); the creep is then found.
    extrapolate : int
        0 (default): one solve.  m >= 1: T' extrapolated from ``elements`` (default 200) and twice as many, each
        level the mean over m grid placements on a window fitted to the patches (:func:`extrapolated`); the other
        fields are the finer level's first placement, p0 its mean.  Creep control only, no ``window``.

    Returns
    -------
    ContactResult
        ``residual`` is the largest certificate entry; ``info`` holds ``grid``, ``patches`` [(x_lead, x_trail)],
        ``normal_certificate``, ``tangential_certificate``, iteration counts and the mode used.  The creep
        stiffness dT'/dxi is given under creep control (:meth:`TransientSolver.steady_creep_stiffness`; with
        velocity-dependent friction ``StructuredSteady.creep_slope``), NaN under force control.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a rollcontact.Scene, got {type(scene).__name__}")
    if check_count("extrapolate", extrapolate, 0, why=" (grid placements per level)"):
        if window is not None or tangential_force_per_length is not None:
            raise ValueError("extrapolate fits its own windows to the patches and extrapolates T' under creep "
                             "control: it takes neither window nor tangential_force_per_length")
        n = check_count("elements", DEFAULT_ELEMENTS if elements is None else elements, MIN_ELEMENTS,
                        MAX_ELEMENTS // 2, " with extrapolate (the finer level has twice as many)")
        return extrapolated(scene, (n, 2 * n), extrapolate, iteration_tolerance=iteration_tolerance, steady=steady,
                            finish=finish, datum_length=datum_length)
    iteration_tolerance = check_iteration_tolerance(iteration_tolerance)
    constant = scene.friction.is_constant
    if steady is None:
        steady = "direct" if constant else "structured"
    if steady not in STEADY_MODES:
        raise ValueError(f"unknown steady mode {steady!r}; valid modes are {list(STEADY_MODES)}")
    if steady != "structured" and not constant:
        raise ValueError(f"steady={steady!r} needs constant friction, got {scene.friction!r}: with dmu/dv < 0 "
                         "the transient problem is ill-posed; use steady='structured'")
    force_control = tangential_force_per_length is not None
    if force_control and steady == "structured":
        raise ValueError("tangential_force_per_length (force control) needs steady='direct' or 'march' and "
                         "constant friction")
    if scene.normal_load_per_length == 0.0:
        return no_contact_result(scene)
    grid, solver, normal = fitted_normal(scene, elements, window, datum_length=datum_length,
                                         iteration_tolerance=iteration_tolerance)
    a, offset, patches = patch_geometry(grid, normal.contact)
    p = normal.pressure
    info = {"grid": grid, "patches": patches, "normal_certificate": normal.certificate,
            "normal_iterations": normal.iterations, "steady": steady}

    def result(success, message, q, slip, stick, t, creep, iterations, residual, stiffness=math.nan):
        s = np.where(normal.contact, slip, np.nan)
        return ContactResult(method="discretised", success=success, message=message,
                             normal_load_per_length=scene.normal_load_per_length, tangential_force_per_length=t,
                             creep=creep, contact_half_width=a, contact_offset=offset,
                             stick_half_width=0.5 * grid.element_width * int(stick.sum()),
                             max_pressure=float(p.max()), creep_stiffness_per_length=stiffness,
                             iterations=iterations, residual=residual,
                             distributions=TabulatedDistributions(grid.centres, p, q, s), info=info)

    zeros = np.zeros(grid.elements)
    if not normal.converged:
        return result(False, f"normal problem: {normal.message}", zeros, zeros, zeros, 0.0, scene.creep,
                      normal.iterations, normal.residual)
    if normal.contact[0] or normal.contact[-1]:
        return result(False, f"contact reaches the window edge ({grid.x_min!r}, {grid.x_max!r}) m: enlarge the "
                      "window", zeros, zeros, zeros, 0.0, scene.creep, normal.iterations, normal.residual)
    closing = far_gap_closing(scene, grid, p, patches)
    if closing is not None:
        return result(False, f"the deformed gap closes outside the window (gap = {closing[1]:.3g} m at X = "
                      f"{closing[0]:.6g} m): the surface meets the cylinder again there", zeros, zeros, zeros, 0.0,
                      scene.creep, normal.iterations, normal.residual)
    control = ({"tangential_force": tangential_force_per_length} if force_control else {"creep": scene.creep})
    if steady == "structured":
        half = 0.5 * grid.element_width * normal.contact.sum()
        fraction = max(0.0, 1.0 - scene.radius * abs(scene.creep) / (scene.friction_coefficient * half))
        sol = steady_leading_edge_stick(solver.ops, p, scene.creep, scene.friction, scene.rolling_speed,
                                        iteration_tolerance, fraction)
        info["tangential_certificate"] = sol.certificate
        residual = max(normal.residual, max(sol.certificate.values(), default=0.0))
        t = grid.element_width * sol.traction.sum()
        message = f"steady, leading-edge stick, {len(patches)} patch(es): {sol.message}"
        if not sol.converged and elements is None and window is None \
                and 2 * grid.elements <= DISCRETISED_ELEMENTS[-1]:
            # the automatic grid leaves a slip zone shorter than an element at a patch end (a stick element
            # above mu p, or one slipping against the traction): twice the elements resolve it
            finer = solve_discretised(scene, elements=2 * grid.elements, iteration_tolerance=iteration_tolerance,
                                      steady=steady, datum_length=datum_length)
            return replace(finer, message=f"{finer.message} (refined from the automatic grid of {grid.elements} "
                                          f"elements, where the structure failed: {sol.message})")
        return result(sol.converged, message, sol.traction, sol.slip, sol.stick, t, scene.creep,
                      sol.iterations, residual, grid.element_width * sol.creep_slope)
    state = None
    iterations = 0
    if steady == "march":
        state, marched = march_to_steady(solver, p, control, iteration_tolerance)
        iterations = state.steps
        info["march_tangential_force"] = state.tangential_force_per_length
        info["march_steps"] = state.steps
        if not marched.converged or not finish:
            residual = max(normal.residual, max(marched.certificate.values(), default=0.0))
            info["tangential_certificate"] = marched.certificate
            return result(marched.converged, f"steady by marching: {marched.message}", state.traction,
                          state.slip, state.stick, state.tangential_force_per_length, marched.creep, iterations,
                          residual)
    state, steady_result = solver.steady_state(p, state=state, **control)
    info["tangential_certificate"] = steady_result.certificate
    residual = max(normal.residual, max(steady_result.certificate.values()))
    kind = "marched and finished directly" if steady == "march" else "direct steady solve"
    message = f"{kind}, {len(patches)} patch(es): {steady_result.message}"
    # dT'/dxi of creep control; under force control the creep is the unknown and the model does not ask
    stiffness = (solver.steady_creep_stiffness(state.stick) if steady_result.converged and not force_control
                 else math.nan)
    return result(steady_result.converged, message, state.traction, state.slip, state.stick,
                  steady_result.tangential_force_per_length, steady_result.creep,
                  iterations + steady_result.iterations, residual, stiffness)


solve_discretised.options = ("elements", "window", "iteration_tolerance", "steady", "finish", "datum_length",
                             "tangential_force_per_length", "extrapolate")


def extrapolated(scene: Scene, elements: tuple[int, int] = (1000, 2000), placements: int = 2,
                 **options) -> ContactResult:
    """A converged discretised solution: T' by first-order Richardson extrapolation, each level the mean over
    ``placements`` grid placements.

    ``T'_ref = T'_2 + (T'_2 - T'_1)/(r - 1)`` with ``r = n_2/n_1`` (T' is first order in the element width), where
    ``T'_k`` is the mean of the solves at ``n_k`` elements on :func:`contact_window` (fitted to the patches) shifted
    by ``j h_k / m``, j = 0..m-1 (m = ``placements``).  The answer at one n moves by about its error with where the
    patch edges fall in their elements (``benchmarks/calibrate_discretised_estimate.py``): that part of the error is
    periodic in the shift, the mean over m placements is its trapezoidal average, and extrapolation alone would
    amplify it.  The smooth first-order part is then removed by the extrapolation.  The error is bounded by
    ``c w/(m n_1)`` (w the window over the Hertz width 2a), erratic in n and largest on a split contact at small
    creep, with c calibrated for m = 2 to 16 by ``benchmarks/calibrate_discretised_estimate.py`` (table C, n_2 = 2 n_1;
    :data:`rollcontact.line.methods.discretised.accuracy.EXTRAPOLATED_FORCE_ERROR`).  The other fields are the finer
    level's first placement; p0 (second order) is the finer level's mean.

    Parameters
    ----------
    scene : Scene
        The case (creep control).
    elements : (int, int)
        Element counts n_1 < n_2.
    placements : int
        Grid placements m >= 1 per level.
    **options
        Passed to :func:`solve_discretised` (not ``elements``, ``window`` or ``extrapolate``).

    Returns
    -------
    ContactResult
        ``success`` only if all ``2 m`` solves succeeded; ``info["levels"]`` holds the mean T' [N/m] per level,
        ``info["change"]`` the relative change of T' from the finer level to the extrapolation and
        ``info["placements"]`` m.
    """
    coarse, fine = (int(n) for n in elements)
    if not coarse < fine:
        raise ValueError(f"elements = {elements!r}: need n_1 < n_2")
    placements = check_count("placements", placements, 1)
    if scene.normal_load_per_length == 0.0:
        return no_contact_result(scene)
    lo, hi = contact_window(scene)
    levels = {}
    for n in (coarse, fine):
        h = (hi - lo) / n
        levels[n] = [solve_discretised(scene, elements=n, window=(lo + j * h / placements, hi + j * h / placements),
                                       **options) for j in range(placements)]
    solves = levels[coarse] + levels[fine]
    means = {n: sum(r.tangential_force_per_length for r in rs) / placements for n, rs in levels.items()}
    force = means[fine] + (means[fine] - means[coarse]) / (fine / coarse - 1.0)
    best = levels[fine][0]
    failed = [r.message for r in solves if not r.success]
    info = dict(best.info, levels=means, change=abs(means[fine] / force - 1.0) if force else 0.0,
                placements=placements)
    return ContactResult(**{**best.__dict__, "success": not failed, "tangential_force_per_length": force,
                            "max_pressure": sum(r.max_pressure for r in levels[fine]) / placements, "info": info,
                            "message": f"Richardson extrapolation of n = {coarse}/{fine}, each the mean of "
                                       f"{placements} grid placement{'s' if placements > 1 else ''}"
                                       + (f"; failed: {failed[0]}" if failed else "")})


def march_to_steady(solver: TransientSolver, pressure: np.ndarray, control: dict,
                    iteration_tolerance: float) -> tuple[TransientState, StepResult]:
    """Kalker's marching to steady rolling: steps of ``ds = h`` from q = 0 until the slip pattern settles.

    Settled means: the stick set unchanged and ``|dT'| <= iteration_tolerance mu N'`` for as many consecutive steps
    as the patch has elements (one passage of material).  At most 20 n steps.
    """
    h = solver.grid.element_width
    contact = pressure > 0
    passage = int(contact.sum())
    limit = solver.friction.static_coefficient * h * pressure.sum()
    state = solver.initial_state()
    quiet = 0
    result = None
    for _ in range(20 * solver.grid.elements):
        previous = state
        state, result = solver.step(state, pressure, h, **control)
        if not result.converged:
            return state, result
        calm = (np.array_equal(state.stick, previous.stick) and abs(state.tangential_force_per_length
                - previous.tangential_force_per_length) <= iteration_tolerance * limit)
        quiet = quiet + 1 if calm else 0
        if quiet >= passage:
            return state, result
    return state, StepResult(result.tangential_force_per_length, result.creep, result.rigid_shift,
                             result.slip_distance, result.dissipation, result.stick_elements, result.iterations,
                             False, f"slip pattern did not settle within {20 * solver.grid.elements} steps",
                             result.certificate)


# ------------------------------------------------------------------------------------------------ registration
def inapplicable(scene: Scene) -> str | None:
    """Why the default grid cannot resolve the scene (None when it can, up to the discretisation error).

    The automatic grid needs 16 elements per shortest surface wavelength across its window; beyond
    ``MAX_ELEMENTS`` the dense matrices would not fit.
    """
    if scene.normal_load_per_length == 0.0:
        return None
    try:
        automatic_grid(scene)
    except ValueError as exc:
        return str(exc)
    return None


DISCRETISED_ELEMENTS = (50, 100, 200, 400, 800, 1600)
