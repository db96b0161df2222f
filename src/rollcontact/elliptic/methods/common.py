"""What the elliptic methods share: the scene's creepage coefficients, the applicability of the table's range of
a/b, the no-load answer, the normalised creepage and Poisson's ratio that the accuracy models use, and the cells' slip
of the falling-friction marches (:func:`cell_slips`, with the laws' kernels :func:`friction_kernel`)."""

from __future__ import annotations

import math

import numpy as np

from rollcontact.core.friction import ExponentialFalling, LinearFalling, RationalFalling, TabulatedFriction
from rollcontact.elliptic.creep_coefficients import CreepageCoefficients, aspect_ratio_range, creepage_coefficients
from rollcontact.elliptic.result import EllipticResult
from rollcontact.elliptic.scene import EllipticScene


def coefficients(scene: EllipticScene) -> CreepageCoefficients:
    """Kalker's C11, C22, C23, C33 at the scene's a/b and nu (a ValueError outside the table's a/b)."""
    return creepage_coefficients(scene.hertz.aspect_ratio, scene.material.poisson_ratio)


def outside_table(scene: EllipticScene) -> str | None:
    """Why the scene's a/b is outside the creepage-coefficient table's range, or None."""
    low, high = aspect_ratio_range()
    g = scene.hertz.aspect_ratio
    if not low <= g <= high:
        return f"a/b = {g:.4g} is outside the creepage-coefficient table's range [{low:g}, {high:g}]"
    return None


def no_load(scene: EllipticScene, method: str) -> EllipticResult:
    """The answer at Fn = 0: no contact, no forces."""
    return EllipticResult.from_scene(scene, method, True, "no load: no contact", (0.0, 0.0, 0.0))


def linear_forces(scene: EllipticScene, c: CreepageCoefficients) -> tuple[float, float, float]:
    """Kalker's linear theory, forces on the rail: ``Fx = G c^2 C11 xi``, ``Fy = G c^2 (C22 eta + c C23 phi)``,
    ``Mz = G c^3 (-C23 eta + c C33 phi)`` [N, N, N m] (Kalker 1967; 1990, section 2.3; docs/physics.md).  The spin
    term of Mz is omitted (0) at phi = 0 so that a table without C33 serves every case without spin."""
    xi, eta, phi = scene.creepages
    g = scene.shear_modulus
    length = scene.hertz.c
    area = length * length
    fx = g * area * c.c11 * xi
    fy = g * area * (c.c22 * eta + length * c.c23 * phi)
    mz = g * area * length * (-c.c23 * eta + (length * c.c33 * phi if phi != 0.0 else 0.0))
    return fx, fy, mz


def linear_ratio(scene: EllipticScene, c: CreepageCoefficients) -> float:
    """``tau = (|(Fx, Fy)| + G c^3 C23 |phi|) / (mu Fn)`` [1] of the linear theory: the creepages in units of
    saturation, what the accuracy models scale with (the spin counted by its lateral force even where it cancels
    that of eta, since it also drives the moment)."""
    fx, fy, _ = linear_forces(scene, c._replace(c33=0.0))
    scale = scene.friction_coefficient * scene.normal_load
    spin = scene.shear_modulus * scene.hertz.c**3 * c.c23 * abs(scene.spin_creepage)
    return (math.hypot(fx, fy) + spin) / scale if scale > 0.0 else 0.0


COST_MARGIN = 5.0
"""Factor [1] from the cheap levels' calibrated times (linear, saturated, FASTSIM, strips: :data:`~.linear.LINEAR_COST`,
:data:`~.fastsim.FASTSIM_COST_PER_STEP`, :data:`~.strips.STRIPS_COST` and the others they name) to their modelled
costs (:func:`modelled_cost`), so that the modelled cost bounds a solve's real time, its worst cases included (a steep
falling law's slips, a cold cache, the stepping model's fixed work per contact, the difference Jacobian's solves):
with :data:`SOLVE_OVERHEAD` it keeps the real time of every step of ``benchmarks/bench_worst_step.py`` (every level,
friction law and Jacobian mode, a/b 0.1 to 10, loads 1 N to 1 MN) below its modelled cost on an idle machine of the
benchmarks' class (the last column of its results).  One factor for the four levels keeps their ranking, which
``auto``'s choice with a tolerance follows; a loaded machine takes longer than the model."""

SOLVE_OVERHEAD = 2e-4
"""Modelled time [s] of what every solve of the cheap levels does besides its level's own work: the scene's checks,
Hertz's ellipse and the coefficients, the dispatcher's choice, the result, and a stepping model's inputs and outputs
of the contact (``benchmarks/bench_worst_step.py``, the linear and saturated levels)."""


def modelled_cost(seconds: float) -> float:
    """``SOLVE_OVERHEAD + COST_MARGIN seconds`` [s]: the modelled cost of a cheap level's solve whose calibrated time
    is ``seconds`` (:data:`COST_MARGIN`)."""
    return SOLVE_OVERHEAD + COST_MARGIN * seconds


MEASURED_POISSON_RATIO = 0.28
"""Poisson's ratio [1] of steel, at which the accuracy models' main constants are measured; their errors grow with
nu above it (``benchmarks/calibrate_elliptic_levels.py``, table B3)."""


def poisson_excess(scene: EllipticScene) -> float:
    """``max(0, nu - MEASURED_POISSON_RATIO)`` [1]: how far the scene's Poisson's ratio lies above steel's."""
    return max(0.0, scene.material.poisson_ratio - MEASURED_POISSON_RATIO)


def falling_drop(scene: EllipticScene) -> float:
    """``1 - mu(V w)/mu(0)`` [1] with ``w = |(|xi| + |phi| b, |eta| + |phi| a)|``, the largest rigid slip over the
    ellipse: how far the law falls over the contact's slip velocities, what the falling-friction terms of the fast
    levels' accuracy models scale with (0 for Coulomb friction)."""
    if scene.friction.is_constant:
        return 0.0
    h = scene.hertz
    xi, eta, phi = scene.creepages
    slip = math.hypot(abs(xi) + abs(phi) * h.b, abs(eta) + abs(phi) * h.a)
    static = scene.friction_coefficient
    return max(0.0, 1.0 - float(scene.friction.coefficient(scene.rolling_speed * slip)) / static)


def friction_kernel(law):
    """``v -> (mu(v), dmu/dv(v))`` of a friction law on arrays of slip velocity [m/s], in few numpy operations for the
    package's laws (:mod:`rollcontact.core.friction`), by the law's own ``coefficient`` and ``derivative`` for any
    other.  The falling-friction marches call it once per Newton iteration on all their cells."""
    if isinstance(law, ExponentialFalling):
        kinetic, falling, decay = law.mu_static * law.kinetic_ratio, law.mu_static * (1.0 - law.kinetic_ratio), \
            law.decay

        def exponential(v):
            e = np.exp(-decay * v)
            return kinetic + falling * e, (-decay * falling) * e

        return exponential
    if isinstance(law, RationalFalling):
        kinetic, step, reference = law.mu_kinetic, law.mu_static - law.mu_kinetic, law.reference_velocity

        def rational(v):
            u = 1.0 / (1.0 + v / reference)
            return kinetic + step * u, (-step / reference) * u * u

        return rational
    if isinstance(law, LinearFalling):
        static, kinetic, slope = law.mu_static, law.mu_kinetic, law.slope

        def linear(v):
            falling = static - slope * v
            return np.maximum(kinetic, falling), np.where(falling > kinetic, -slope, 0.0)

        return linear
    if isinstance(law, TabulatedFriction):
        velocities, values = np.array(law.velocities), np.array(law.coefficients)
        slopes = np.append(np.diff(values) / np.diff(velocities), 0.0) if velocities.size > 1 else np.zeros(1)

        def tabulated(v):
            index = np.searchsorted(velocities, v, side="right") - 1
            return np.interp(v, velocities, values), np.where(index >= 0, slopes[np.maximum(index, 0)], 0.0)

        return tabulated

    def general(v):
        return np.asarray(law.coefficient(v), dtype=float), np.asarray(law.derivative(v), dtype=float)

    return general


NEWTON_STEPS = 2
"""Plain Newton steps of :func:`cell_slips` before its check (from the Coulomb slip, or a previous march's slips)."""

SLIP_ITERATIONS = 60
"""Cap of the safeguarded iterations of :func:`cell_slips` on the cells that plain Newton leaves unconverged (the root
is bracketed, so bisection alone reaches round-off in about 60)."""

SLIP_TOLERANCE = 1e-6
"""Tolerance of :func:`cell_slips` on the residual ``|F|``, relative to the scale ``S + |D| mu_max`` of its terms
(Newton converges quadratically: its last step has taken the slip much closer)."""


def cell_slips(rigid, growth, kernel, speed, static: float, largest: float, start=None):
    """Each cell's slip ``sigma >= 0`` [1] of the march's falling friction and the law's ``(mu, dmu/dv)`` there: the
    root of

        ``F(sigma) = sigma + D mu(V sigma) - S = 0``

    (``rigid`` S: the rigid slip along the traction; ``growth`` D: the elastic slip per unit friction coefficient of
    the pressure's growth along the strip, docs/physics.md, "Strips"), for cells with ``S > D mu(0)`` (a cell the
    static coefficient cannot hold).  :data:`NEWTON_STEPS` plain Newton steps from ``start`` (by default the Coulomb
    slip ``S - D mu(0)``); where the residual is then above :data:`SLIP_TOLERANCE` (or the slip negative), a
    safeguarded Newton: ``F(0) = D mu(0) - S < 0`` and ``F(S + max(0, -D) mu_max) >= 0`` bracket a root and steps
    that leave the bracket are replaced by bisection, so it converges for any law.  Where the law falls faster than
    the cell resolves (``-D V dmu/dv > 1``: F is not monotone) the bracket still holds a root: for the package's laws
    (convex in v) F is convex with ``F(0) < 0``, and the root is unique; for a tabulated law that is not convex, the
    root Newton reaches from the Coulomb slip.  ``kernel``: :func:`friction_kernel`; ``speed`` V [m/s] (a float, or
    one per cell); ``static``, ``largest``: mu(0) and sup mu [1].  Every cell's iteration is its own (a cell's numbers
    do not depend on the others passed with it)."""
    sigma = np.maximum(rigid - growth * static if start is None else start, 0.0)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for _ in range(NEWTON_STEPS):
            mu, slope = kernel(speed * sigma)
            sigma = sigma - (sigma + growth * mu - rigid) / (1.0 + growth * speed * slope)
        mu, slope = kernel(speed * sigma)
        residual = sigma + growth * mu - rigid
    failed = ~(np.abs(residual) <= SLIP_TOLERANCE * (rigid + np.abs(growth) * largest)) | ~(sigma >= 0.0)
    if failed.any():
        speed_failed = speed if np.ndim(speed) == 0 else speed[failed]
        sigma[failed] = bracketed(rigid[failed], growth[failed], kernel, speed_failed, static, largest)
        mu[failed], slope[failed] = kernel(speed_failed * sigma[failed])
    return sigma, mu, slope


def bracketed(rigid, growth, kernel, speed, static: float, largest: float):
    """:func:`cell_slips`' safeguarded Newton: bisection where a Newton step leaves the bracket ``[0, S + max(0, -D)
    mu_max]``; each cell stops after the step at which its residual is within :data:`SLIP_TOLERANCE` of its bracket's
    upper end (its numbers are its own, whatever the other cells)."""
    low = np.zeros_like(rigid)
    high = rigid + np.maximum(0.0, -growth) * largest
    sigma = np.clip(rigid - growth * static, low, high)
    active = np.ones(rigid.shape, dtype=bool)
    for _ in range(SLIP_ITERATIONS):
        mu, slope = kernel(speed * sigma)
        residual = sigma + growth * mu - rigid
        below = residual < 0.0
        low = np.where(active & below, sigma, low)
        high = np.where(active & ~below, sigma, high)
        derivative = 1.0 + growth * speed * slope
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = sigma - residual / derivative
        inside = (newton >= low) & (newton <= high) & (derivative > 0.0)
        sigma = np.where(active, np.where(inside, newton, 0.5 * (low + high)), sigma)
        active &= np.abs(residual) > SLIP_TOLERANCE * high
        if not active.any():
            break
    return sigma


def friction_groups(scenes) -> list[list[int]]:
    """The loaded scenes' indices grouped for the stacked solves of several scenes (the strips' and FASTSIM's): the
    scenes of constant friction together (each at its own coefficient), and those of each velocity-dependent law
    together, in the order the laws first appear."""
    groups: list[list[int]] = []
    keys: list = []  # None for constant friction, else the law
    for k, scene in enumerate(scenes):
        if scene.normal_load == 0.0:
            continue
        key = None if scene.friction.is_constant else scene.friction
        if key in keys:
            groups[keys.index(key)].append(k)
        else:
            keys.append(key)
            groups.append([k])
    return groups


def by_scene(values: np.ndarray, n: int) -> np.ndarray:
    """Each scene's sum of ``values`` ``(..., steps, n S)`` over its cells (``(..., n)``), taken over the scene's
    ``(steps, S)`` cells in their row-major order."""
    *lead, steps, columns = values.shape
    if n == 1:
        return np.add.reduce(values.reshape(*lead, 1, -1), axis=-1)
    axes = (*range(len(lead)), len(lead) + 1, len(lead), len(lead) + 2)  # (..., n, steps, S): a scene per row
    per_scene = values.reshape(*lead, steps, n, columns // n).transpose(axes).copy()
    return np.add.reduce(per_scene.reshape(*lead, n, -1), axis=-1)


TINY = 1e-300
"""A floor of the trial tractions' size (an empty strip's)."""


def march(first, increment, limit):
    """FASTSIM's march on cells ``(steps, 2, S)``: from the traction-free leading edge (``first``: the trial traction of
    the first cell ``(2, S)``), each cell's trial ``t`` is the previous cell's traction plus ``increment`` (the rigid
    slip over the flexibility times the step), the traction is ``t min(1, limit / |t|)`` (``t`` where ``|t| = 0``:
    ``fmin`` takes 1 over the quotient's inf or NaN).  Returns the trials, the tractions ``(steps, 2, S)`` and the
    trials' sizes ``max(|t|, TINY)`` ``(steps, S)``."""
    steps, count = limit.shape
    trial = np.empty((steps, 2, count))
    traction = np.empty((steps, 2, count))
    size = np.empty((steps, count))
    trial[0] = first
    ratio = np.empty(count)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        for i in range(steps):
            np.hypot(trial[i, 0], trial[i, 1], out=size[i])
            np.divide(limit[i], size[i], out=ratio)
            np.fmin(1.0, ratio, out=ratio)
            np.multiply(trial[i], ratio, out=traction[i])
            if i + 1 < steps:
                np.add(traction[i], increment[i], out=trial[i + 1])
    np.maximum(size, TINY, out=size)
    return trial, traction, size


def march_slips(marched, first, increment, flexibility):
    """The march's cells' directions and rigid slips (``marched``: what :func:`march` returns, the trials, tractions
    and the trials' sizes; ``flexibility``: each strip's flexibility over its step along x and along y),
    docs/physics.md, "FASTSIM": the trial's direction ``e = t / |t|``, the cell's flexibility over the step along e
    ``k = |(k_x e_x, k_y e_y)| = k_x sqrt(e_x^2 + (k_y e_y / k_x)^2)`` (the root of a unit vector's squares: no
    overflow whatever the flexibilities) and the rigid slip along the traction ``S = k (increment . e)`` [1].  Returns
    ``(e_x, e_y, k, S)`` per cell; every operation is elementwise."""
    trial, _, size = marched
    ex, ey = trial[:, 0] / size, trial[:, 1] / size
    turned = (flexibility[1] / flexibility[0]) * ey
    k = flexibility[0] * np.sqrt(ex * ex + turned * turned)
    rigid = np.empty_like(size)
    rigid[0] = first[0] * ex[0] + first[1] * ey[0]
    rigid[1:] = increment[:-1, 0] * ex[1:] + increment[:-1, 1] * ey[1:]
    rigid *= k
    return ex, ey, k, rigid


def falling_slips(marched, first, increment, coefficient, pressure, flexibility, law, kernel, speed, start):
    """Each cell's slip [1] and friction coefficient after a march of the simplified theory (the extended FASTSIM;
    ``marched``, ``flexibility``: :func:`march_slips`'; ``coefficient``: the coefficients the march took ``(steps,
    S)``, ``pressure`` p on the cells), docs/physics.md, "FASTSIM": along the trial's direction e the cell's slip is
    ``sigma = S - mu D`` with the rigid slip S of :func:`march_slips` and the pressure's growth ``D = k (p - r . e)``,
    ``r`` the previous cell's traction per unit coefficient, ``mu`` the coefficient of the cell's own slip velocity
    (:func:`slips_at`).  Returns ``(sigma, mu, steepness)`` per cell (:func:`slips_at`).  Every operation is
    elementwise: a strip's numbers are the same whatever the other strips marched with it."""
    _, traction, size = marched
    ex, ey, k, rigid = march_slips(marched, first, increment, flexibility)
    along = np.zeros_like(size)  # r . e, r the previous cell's traction per unit coefficient
    along[1:] = (traction[:-1, 0] * ex[1:] + traction[:-1, 1] * ey[1:]) / coefficient[:-1]
    growth = k * (pressure - along)
    return slips_at(rigid, growth, rigid > growth * law.static_coefficient, law, kernel, speed, start)


def slips_at(rigid, growth, slipping, law, kernel, speed, start):
    """Each cell's slip ``sigma`` [1], coefficient ``mu`` and steepness of ``sigma = S - D mu(V sigma)`` (``rigid`` S,
    ``growth`` D per cell; :func:`cell_slips`) on the cells ``slipping`` (those with ``S > D mu(0)``, and the
    caller's own conditions), ``sigma = 0`` and the static coefficient elsewhere; ``speed`` V [m/s] (a float or one
    per strip ``(S,)``), ``start``: the previous march's slips, or None.  The steepness is ``-D V dmu/dv`` on the
    slipping cells and 0 on the others (above 1 the cell's equation is not monotone).  Every operation is
    elementwise."""
    static = law.static_coefficient
    sigma = np.zeros_like(rigid)
    mu = np.full_like(rigid, static)
    steepness = np.zeros_like(rigid)
    if slipping.any():
        guess = None if start is None else start[slipping]
        cell_speed = speed if np.ndim(speed) == 0 else np.broadcast_to(speed, rigid.shape)[slipping]
        sigma[slipping], values, slopes = cell_slips(rigid[slipping], growth[slipping], kernel, cell_speed, static,
                                                     law.maximum_coefficient, guess)
        mu[slipping] = values
        steepness[slipping] = -growth[slipping] * cell_speed * slopes
    return sigma, mu, steepness
