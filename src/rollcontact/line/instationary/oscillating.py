"""Force control with an oscillating force ``T' = T0 + T1 sin(2 pi sigma / lambda)`` (paper section 4.3, eqs 32-35).

Two routes to the traction q(x) at phases of a cycle, which is datum-free under force control:

* :func:`oscillating_force_chebyshev`, the paper's: the stick-zone strain is a travelling wave, solved with the
  Chebyshev/Jacobi-Anger expansion the polynomial method uses for a corrugation;
* :func:`oscillating_force_discretised`, the transient solver (:mod:`rollcontact.line.halfspace.solver`); lambda = 0 is
  the static limit (Cattaneo and Mindlin-Deresiewicz).

:func:`quasi_steady_deviation` measures the L2 deviation of the oscillating part of q from quasi-steady Carter,
about ``2.5 a / lambda`` (the basis of the paper's stationarity threshold,
:data:`rollcontact.line.instationary.stationarity.STATIONARITY_THRESHOLD`).  A module of its own: neither route steps
creep-controlled rolling, which is :mod:`rollcontact.line.instationary.model`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, special

from rollcontact.core.checks import check_real
from rollcontact.core.halfspace.elements import Grid
from rollcontact.line.carter import CarterDistributions, carter
from rollcontact.line.halfspace.grid import patch_geometry
from rollcontact.line.halfspace.solver import TransientSolver
from rollcontact.line.hertz import ellipse, hertz
from rollcontact.line.instationary.model import WINDOW_FACTOR
from rollcontact.line.instationary.relaxation import carter_creep
from rollcontact.line.result import ContactResult, Distributions, TabulatedDistributions


# ---------------------------------------------------------------------------------------- force control
@dataclass(frozen=True)
class OscillatingForce:
    """``T'(sigma) = mean + amplitude sin(2 pi sigma / wavelength)`` [N/m] over the rolled distance sigma [m].

    ``wavelength = 0`` is the static limit (V -> 0 at a fixed frequency): then sigma stands for the phase times
    one, and nothing rolls.  ``wavelength = inf`` is steady rolling at the mean force.
    """

    mean: float
    amplitude: float
    wavelength: float

    def __post_init__(self):
        for name in ("mean", "amplitude"):
            object.__setattr__(self, name, check_real(name, getattr(self, name), unit="N/m"))
        try:
            w = float(self.wavelength)
        except (TypeError, ValueError):
            raise ValueError(f"wavelength must be a real number in m, got {self.wavelength!r}") from None
        if not w >= 0.0:
            raise ValueError(f"wavelength = {w!r} m is out of range: it must be >= 0 (0 static, inf steady)")
        object.__setattr__(self, "wavelength", w)

    def at_phase(self, phase):
        """T' [N/m] at the phase ``sigma / wavelength`` (fraction of a cycle); the mean for an infinite wavelength."""
        amplitude = 0.0 if math.isinf(self.wavelength) else self.amplitude
        return self.mean + amplitude * np.sin(2.0 * np.pi * np.asarray(phase, dtype=float))


def check_force(force: OscillatingForce, load: float, mu: float) -> None:
    if not isinstance(force, OscillatingForce):
        raise TypeError(f"force must be an OscillatingForce, got {type(force).__name__}")
    peak = abs(force.mean) + abs(force.amplitude)
    if peak >= mu * load:
        raise ValueError(f"force peak |T0| + |T1| = {peak!r} N/m is out of range: it must stay below mu N' = "
                         f"{mu * load!r} N/m")


def oscillating_force_discretised(normal_load_per_length: float, force: OscillatingForce, *, radius: float,
                                  contact_modulus: float, mu: float, phases: int = 16, elements: int = 200,
                                  datum_length=None, cycles=None) -> tuple[ContactResult, ...]:
    """q(x) for an oscillating force by the discretised transient solver (force control, datum-free q).

    Starts from steady rolling at ``T'(0)`` (static: from the unloaded state, loaded to ``T'(0)`` in 20 static
    steps), rolls ``cycles`` cycles (default: 2, more when the wavelength is shorter than the contact so that
    ~3 contact lengths pass) in steps of at most one element width and at least 64 per cycle, and
    returns the last cycle at ``phases`` equally spaced phases.  ``wavelength = inf`` gives the steady state.

    Returns
    -------
    tuple of ContactResult
        One per phase, method ``"instationary_discretised"``; ``creep`` is the creep for ``datum_length``
        (default R; NaN for static steps); ``info`` holds ``phase``, ``distance`` and ``dissipation_per_cycle``
        [J/m] (frictional work of the last cycle, datum-free).
    """
    load = check_real("normal_load_per_length", normal_load_per_length, lower=0.0, lower_open=True, unit="N/m")
    check_force(force, load, mu)
    a, _ = hertz(load, radius, contact_modulus)
    grid = Grid(-WINDOW_FACTOR * a, WINDOW_FACTOR * a, elements)
    solver = TransientSolver(grid, contact_modulus=contact_modulus, radius=radius, datum_length=datum_length)
    p = solver.normal(load).pressure
    lam = force.wavelength
    h = grid.element_width
    if math.isinf(lam):
        state, res = solver.steady_state(p, tangential_force=force.mean)
        return tuple(discretised_result(solver, p, state, res.creep, res.converged, res.message,
                                        {"phase": j / phases, "distance": math.inf, "dissipation_per_cycle": 0.0})
                     for j in range(phases))
    per_phase = max(math.ceil(64 / phases), math.ceil(lam / (phases * h)))
    ds = lam / (phases * per_phase)
    if cycles is None:
        cycles = 2 if lam == 0.0 else max(2, math.ceil(6.0 * a / lam) + 1)
    if lam == 0.0:
        state = solver.initial_state()
        for k in range(1, 21):
            state, res = solver.step(state, p, 0.0, tangential_force=float(force.at_phase(0.0)) * k / 20)
    else:
        state, res = solver.steady_state(p, tangential_force=float(force.at_phase(0.0)))
    out, energy, ok, message = [], 0.0, res.converged, res.message
    total = cycles * phases * per_phase
    for k in range(1, total + 1):
        phase = k / (phases * per_phase)
        state, res = solver.step(state, p, ds, tangential_force=float(force.at_phase(phase)))
        ok &= res.converged
        message = res.message if not res.converged else message
        if k > total - phases * per_phase:
            energy += res.dissipation
            if k % per_phase == 0:
                out.append((state, res.creep, round(phase % 1.0, 12), phase * lam))
    out.sort(key=lambda entry: entry[2])
    return tuple(discretised_result(solver, p, s, creep, ok, message,
                                    {"phase": ph, "distance": dist, "dissipation_per_cycle": energy})
                 for s, creep, ph, dist in out)


def discretised_result(solver, p, state, creep, converged, message, info) -> ContactResult:
    grid = solver.grid
    a, offset, _ = patch_geometry(grid, p > 0)
    h = grid.element_width
    return ContactResult(method="instationary_discretised", success=bool(converged), message=message,
                         normal_load_per_length=h * float(p.sum()),
                         tangential_force_per_length=state.tangential_force_per_length, creep=creep,
                         contact_half_width=a, contact_offset=offset,
                         stick_half_width=0.5 * h * int((state.stick & (p > 0)).sum()), max_pressure=float(p.max()),
                         iterations=state.steps, distributions=TabulatedDistributions(
                             grid.centres, p, state.traction, np.where(p > 0, state.slip, np.nan)),
                         info=info | {"grid": grid})


@dataclass(frozen=True)
class TravellingWaveDistributions(Distributions):
    """Hertz pressure and ``q = sign (mu p + q2)``, ``q2 = sum d_n sin(n theta*)`` on the stick zone."""

    a: float
    p0: float
    mu: float
    sign: float
    stick_half_width: float
    stick_coefficients: np.ndarray  # d_n [Pa], index 0 unused

    def pressure(self, x):
        return self.p0 * ellipse(np.asarray(x, dtype=float), self.a)

    def traction(self, x):
        x = np.asarray(x, dtype=float)
        b = self.stick_half_width
        q = self.mu * self.pressure(x)
        if b > 0.0:
            t = (x + self.a - b) / b
            inside = np.abs(t) <= 1.0
            theta = np.arccos(np.clip(t, -1.0, 1.0))
            n = np.arange(1, self.stick_coefficients.size)
            q = q + np.where(inside, np.sin(np.multiply.outer(theta, n)) @ self.stick_coefficients[1:], 0.0)
        return self.sign * q

    def slip(self, x):
        return np.full_like(np.asarray(x, dtype=float), np.nan)


class TravellingWave:
    """Stick-zone condition of the paper's route, dimensionless (lengths over a, strains over mu a / R).

    In the stick zone ``Du/Dsigma = du/dsigma + du/dx = -xi(sigma)``: the strain is convected with the material,
    ``du/dx = U'(x - sigma)`` (eqs 32-35), a travelling wave.  For a force of wavelength lambda
    (``k = 2 pi a / lambda``) it is ``U'(zeta) = -xi_bar + sum_m Re(C_m e^{i m k zeta})``.  With
    ``du/dx = (2/(pi E*)) PV-int q/(x - z) dz``, ``q = mu p + q2`` and ``x = -a + b (1 + t)`` on the stick zone
    of half-width b, ``(1/pi) PV-int q2/(x - z) dz = sum d_n T_n(t)``
    (:mod:`rollcontact.line.methods.polynomial.chebyshev`) gives, by Jacobi-Anger,

    ``r_0 = -xi_bar - x_s + sum_m Re(C_m e^{i m k (x_s - sigma)}) J_0(m k b)``   (must vanish: bounded q2)
    ``r_n = sum_m Re(C_m e^{i m k (x_s - sigma)} 2 i^n J_n(m k b)) - b delta_n1``,  ``d_n = mu p0 r_n``,

    ``x_s = -1 + b`` the stick centre, and ``T'/(mu N') = 1 + b r_1`` (Carter: r_1 = -b).  These are eqs 30-31 of
    the corrugation with the surface slope replaced by the convected strain.
    """

    def __init__(self, wavenumber: float, harmonics: int, order: int):
        self.k = wavenumber
        self.m = np.arange(1, harmonics + 1)
        self.n = np.arange(order + 1)
        self.ipow = 1j ** self.n

    def coefficients(self, b: float, sigma: float, xi_bar: float, c: np.ndarray) -> np.ndarray:
        """``[r_0, ..., r_order]`` at stick half-width b and phase distance sigma (both over a)."""
        xs = -1.0 + b
        km = self.m * self.k
        rot = c * np.exp(1j * km * (xs - sigma))
        jn = special.jv(self.n[:, None], km[None, :] * b)
        eps = np.where(self.n == 0, 1.0, 2.0)
        r = np.real(eps * self.ipow * (jn @ rot))
        r[0] += -xi_bar - xs
        if r.size > 1:
            r[1] -= b
        return r

    def low(self, b, sigma, xi_bar: float, c: np.ndarray):
        """``(r_0, r_1)`` vectorised over b and sigma (broadcast)."""
        b, sigma = np.broadcast_arrays(np.asarray(b, dtype=float), np.asarray(sigma, dtype=float))
        km = self.m * self.k
        xs = -1.0 + b
        rot = c * np.exp(1j * km * (xs[..., None] - sigma[..., None]))
        z = km * b[..., None]
        r0 = np.real(np.sum(rot * special.j0(z), axis=-1)) - xi_bar - xs
        r1 = np.real(np.sum(rot * 2j * special.j1(z), axis=-1)) - b
        return r0, r1

    def stick_width(self, sigma: float, xi_bar: float, c: np.ndarray) -> float:
        """Root b in (0, 1) of r_0 (NaN when there is none or more than one sign change on a fine scan)."""
        bs = np.linspace(1e-6, 1.0, 201)
        r0 = self.low(bs, sigma, xi_bar, c)[0]
        changes = np.flatnonzero(np.sign(r0[:-1]) != np.sign(r0[1:]))
        if changes.size != 1:
            return math.nan
        i = changes[0]
        return optimize.brentq(lambda b: float(self.low(b, sigma, xi_bar, c)[0]), bs[i], bs[i + 1], xtol=1e-14)


def oscillating_force_chebyshev(normal_load_per_length: float, force: OscillatingForce, *, radius: float,
                                contact_modulus: float, mu: float, phases: int = 16, harmonics: int = 8,
                                order: int = 40) -> tuple[ContactResult, ...]:
    """q(x) for an oscillating force by the paper's route (section 4.3, eqs 32-35), with validity checks.

    Unknowns: the travelling wave ``U'`` (``xi_bar`` and ``C_1..C_M``, see :class:`TravellingWave`) and the stick
    half-widths b_j at ``2M + 1`` collocation phases; equations: ``r_0(b_j) = 0`` and ``T'(b_j) = T'(sigma_j)``,
    solved by least squares from the quasi-steady guess (``U'`` = minus the Carter creep of the force at which the
    material entered the patch).  Then b is found at each output phase from ``r_0 = 0`` alone and the force
    misfit there is the ``residual`` (the truncation error of M harmonics, relative to mu N').

    The route assumes one stick zone at the leading edge whose material all entered through the leading edge.
    It is reported as failed (``success=False``, message naming the phase) when: T' changes sign; the stick zone
    vanishes or fills the patch (no root b in (0, a), or several); ``|q| > mu p`` in the stick zone; the rear
    stick boundary overtakes the material (``2 db/dsigma >= 1``: slipped material would be caught again, its
    strain is then no longer the travelling wave); the solve does not converge.  The slip direction in the slip
    zone is not checked here (it needs du/dt there); the agreement with :func:`oscillating_force_discretised`
    covers it in the tests.

    Returns
    -------
    tuple of ContactResult
        One per output phase (method ``"instationary_chebyshev"``); ``creep`` is NaN (it needs a datum:
        paper eq 33-34, docs/physics.md, Instationary rolling); ``info``: ``phase``, ``distance``, ``xi_bar``
        (mean stick strain, over mu a/R), ``wave`` (C_m), ``rear_boundary_speed`` (max 2 db/dsigma).
    """
    load = check_real("normal_load_per_length", normal_load_per_length, lower=0.0, lower_open=True, unit="N/m")
    check_force(force, load, mu)
    if not 0.0 < force.wavelength:
        raise ValueError(f"wavelength = {force.wavelength!r} m is out of range: the paper's route needs rolling, "
                         "wavelength > 0 (use oscillating_force_discretised for the static limit)")
    a, p0 = hertz(load, radius, contact_modulus)
    limit = mu * load
    lam = force.wavelength / a if math.isfinite(force.wavelength) else 0.0  # sigma per phase, over a
    k = 2.0 * math.pi / lam if lam > 0.0 else 0.0
    harmonics = harmonics if k > 0.0 else 0
    sign = math.copysign(1.0, force.mean)
    wave = TravellingWave(k, harmonics, order)

    def target(phase):
        return sign * force.at_phase(phase) / limit

    sign_change = force.amplitude != 0.0 and abs(force.amplitude) >= abs(force.mean)
    # quasi-steady guess: the material at zeta entered at the leading edge at sigma_e = -1 - zeta
    fine = np.arange(256) / 256
    steady_strain = -(1.0 - np.sqrt(np.clip(1.0 - target(fine), 0.0, None)))
    if harmonics:
        zeta = -1.0 - fine * lam
        basis = np.column_stack([np.ones_like(zeta)] + [f(m * k * zeta) for m in wave.m for f in (np.cos, np.sin)])
        fit = np.linalg.lstsq(basis, steady_strain, rcond=None)[0]
    else:
        fit = np.array([steady_strain[0]])
    colloc = np.arange(2 * harmonics + 1) / (2 * harmonics + 1)
    b0 = np.sqrt(np.clip(1.0 - target(colloc), 1e-6, 1.0))

    def unpack(z):
        c = z[1:1 + 2 * harmonics:2] - 1j * z[2:1 + 2 * harmonics:2]
        return -z[0], c

    targets = target(colloc)

    def residuals(z):
        xi_bar, c = unpack(z[:1 + 2 * harmonics])
        b = z[1 + 2 * harmonics:]
        r0, r1 = wave.low(b, colloc * lam, xi_bar, c)
        return np.concatenate((r0, 1.0 + b * r1 - targets))

    z = np.concatenate((fit, b0))
    problems, evaluations = [], 0
    if sign_change:
        problems.append("T' changes sign over the cycle (the slip-zone traction direction flips)")
    else:
        lower = np.concatenate((np.full(fit.size, -np.inf), np.full(b0.size, 1e-9)))
        upper = np.concatenate((np.full(fit.size, np.inf), np.ones(b0.size)))
        sol = optimize.least_squares(residuals, z, bounds=(lower, upper), xtol=1e-14, ftol=1e-14, gtol=1e-14,
                                     max_nfev=200)
        z, evaluations = sol.x, sol.nfev
        if np.abs(sol.fun).max() > 1e-8:
            problems.append(f"collocation did not converge (residual {np.abs(sol.fun).max():.2e})")
    xi_bar, c = unpack(z[:1 + 2 * harmonics])
    # stick widths on a fine phase grid: existence and the speed of the rear boundary
    dense = np.arange(8 * phases) / (8 * phases)
    widths = np.array([wave.stick_width(ph * lam, xi_bar, c) for ph in dense]) if harmonics else \
        np.full(dense.size, z[-1])
    if not np.all(np.isfinite(widths)) or widths.min() <= 1e-6 or widths.max() >= 1.0 - 1e-9:
        bad = dense[~np.isfinite(widths) | (widths <= 1e-6) | (widths >= 1.0 - 1e-9)]
        problems.append(f"no single stick zone inside the patch at phase {bad[0]:.3f} (full slip, full stick or "
                        "several roots)")
    speed = 0.0
    if harmonics and np.all(np.isfinite(widths)):
        speed = float(np.max(2.0 * np.diff(np.append(widths, widths[0])) / (lam / dense.size)))
        if speed >= 1.0:
            problems.append(f"the rear stick boundary overtakes the material (2 db/dsigma = {speed:.3f} >= 1): "
                            "slipped material is caught again and its strain is not the travelling wave")
    results = []
    x = np.linspace(-a, a, 801)
    for j in range(phases):
        phase = j / phases
        b = widths[8 * j]
        r = wave.coefficients(b, phase * lam, xi_bar, c) if np.isfinite(b) else np.zeros(order + 1)
        dist = TravellingWaveDistributions(a, p0, mu, sign, b * a if np.isfinite(b) else 0.0, mu * p0 * r)
        t = sign * dist.traction(x)
        bound = mu * dist.pressure(x)
        local = list(problems)
        if np.any(np.abs(t) > bound * (1.0 + 1e-6) + 1e-9 * mu * p0):
            local.append(f"|q| > mu p in the stick zone at phase {phase:.3f}")
        force_found = sign * limit * (1.0 + b * r[1]) if np.isfinite(b) else math.nan
        misfit = abs(force_found - float(force.at_phase(phase))) / limit
        message = "; ".join(local) if local else "travelling-wave stick zone at the leading edge"
        results.append(ContactResult(
            method="instationary_chebyshev", success=not local, message=message, normal_load_per_length=load,
            tangential_force_per_length=force_found, creep=math.nan, contact_half_width=a, contact_offset=0.0,
            stick_half_width=b * a if np.isfinite(b) else 0.0, max_pressure=p0, iterations=int(evaluations),
            residual=misfit, distributions=dist,
            info={"phase": phase, "distance": phase * force.wavelength, "xi_bar": xi_bar, "wave": c,
                  "rear_boundary_speed": speed}))
    return tuple(results)


def quasi_steady_deviation(results, mean_force: float, *, radius: float, contact_modulus: float, mu: float,
                           points: int = 801) -> float:
    """L2 deviation of the oscillating part of q from quasi-steady Carter (docs/physics.md, Instationary rolling).

    ``||q(x, sigma) - q_C(x; T'(sigma))|| / ||q_C(x; T'(sigma)) - q_C(x; T0)||`` over the phases of ``results``
    and ``points`` points across the patch, q_C Carter's distribution at the same force (T'(sigma) is taken
    from each result).  About ``2.5 a / lambda``.
    """
    num = den = 0.0
    for r in results:
        load = r.normal_load_per_length
        a, p0 = hertz(load, radius, contact_modulus)
        x = np.linspace(-a, a, points)
        q_c = carter_traction(x, r.tangential_force_per_length, load, a, p0, radius, contact_modulus, mu)
        q_0 = carter_traction(x, mean_force, load, a, p0, radius, contact_modulus, mu)
        num += float(np.sum((r.traction(x) - q_c) ** 2))
        den += float(np.sum((q_c - q_0) ** 2))
    return math.sqrt(num / den)


def carter_traction(x, force, load, a, p0, radius, contact_modulus, mu):
    """Carter's q(x) at a force (via its creep), centred patch."""
    xi = carter_creep(force, load, radius, contact_modulus, mu)
    a_star = carter(load, xi, radius, contact_modulus, mu)[1]
    return CarterDistributions(a, p0, a_star, 0.0, mu, xi if xi != 0.0 else 1.0, radius).traction(x) \
        if force != 0.0 else np.zeros_like(x)
