"""Kalker's FASTSIM (``"fastsim"``): the simplified theory of rolling contact (Kalker 1982, "A fast algorithm for
the simplified theory of rolling contact", Vehicle System Dynamics 11) with an elliptic traction bound.

Simplified theory: the surface displacement difference is ``u = L q`` with one flexibility per creepage,
``L1 = 8a / (3 C11 G)``, ``L2 = 8a / (3 C22 G)``, ``L3 = pi a sqrt(a/b) / (4 C23 G)`` (chosen so that the linear
theory's Fx, Fy from xi, eta, phi is reproduced exactly), by default blended towards one flexibility at large
creepage (Vollebregt & Voltr, "Improved accuracy for FASTSIM using one or three flexibility values", Vehicle System
Dynamics 61, 2023; :func:`blended_flexibilities`).  Material enters the ellipse at the leading edge
``x = a(y) = a sqrt(1 - y^2/b^2)`` traction-free and moves towards -x; in stick the slip
``s = w - du/dx`` (a particle's displacement grows with the rigid slip it meets) vanishes, so along each strip

    ``q_x(x - dx) = q_x(x) + dx (xi / L1 - phi y / L3)``,  ``q_y(x - dx) = q_y(x) + dx (eta / L2 + phi x_m / L3)``

(``x_m`` the middle of the step, exact for the slip linear in x), and where ``|q|`` exceeds the traction bound
``g = mu p`` the trial traction is scaled back onto it (slip in its direction).  The bound is Hertz's pressure,
``g = mu p0 sqrt(1 - x^2/a^2 - y^2/b^2)`` (``bound="elliptic"``, the default), or Kalker's original parabola of the
same load ``g = mu (2 Fn / (pi a b)) (1 - x^2/a^2 - y^2/b^2)`` (``bound="parabolic"``), sampled at the cell
centres and scaled so that the cells carry ``mu Fn`` (then ``|F| <= mu Fn`` holds exactly).  Forces on the rail:
``Fx = int q_x``, ``Fy = int q_y``, ``Mz = int (x q_y - y q_x)`` (midpoint rule over the cells: the tractions live on
the cell centres, the first half a cell behind the leading edge).

Velocity-dependent friction (the extended FASTSIM): each cell's bound is ``mu(V sigma) p`` at its own slip sigma.
Along the trial traction's direction e the march's slip of a cell is ``sigma = S - mu D``, the rigid slip
``S = k (increment . e)`` less the pressure's growth ``D = k (p - r . e)`` per unit coefficient (``r`` the previous
cell's traction per unit coefficient, ``k = |(L1 e_x, L2 e_y)| / dx``); each cell's ``sigma = S - D mu(V sigma)`` is
solved by Newton, vectorised over the cells (:func:`~.common.falling_slips`).  The march's own response to a change of
mu along the strip, ``-L p dmu/dt``, is left out: it is the local theory's, far stiffer than the half-space's, and
makes the march's answer depend on the cell size (docs/physics.md, "FASTSIM").  The first march is Coulomb's at the
static coefficient; with spin a second marches with the cells' coefficients, whose bound turns the traction.
"""

from __future__ import annotations

import math

import numpy as np

from rollcontact.core.checks import check_real
from rollcontact.core.method import AccuracyModel, MethodSpec
from rollcontact.elliptic.methods.common import (
    by_scene,
    coefficients,
    falling_drop,
    falling_slips,
    friction_groups,
    friction_kernel,
    linear_ratio,
    march,
    modelled_cost,
    no_load,
    outside_table,
    poisson_excess,
)
from rollcontact.elliptic.result import EllipticResult, TractionField

BOUNDS = ("elliptic", "parabolic")


def flexibilities(scene, c) -> tuple[float, float, float]:
    """Kalker's (L1, L2, L3) [m/Pa] of the simplified theory from C11, C22, C23 (module docstring)."""
    h = scene.hertz
    return kalker_flexibilities(h.a, h.b, scene.shear_modulus, c.c11, c.c22, c.c23)


def kalker_flexibilities(a: float, b: float, g: float, c11: float, c22: float, c23: float
                         ) -> tuple[float, float, float]:
    """:func:`flexibilities` of the semi-axes a, b [m], G [Pa] and C11, C22, C23."""
    return 8.0 * a / (3.0 * c11 * g), 8.0 * a / (3.0 * c22 * g), math.pi * a * math.sqrt(a / b) / (4.0 * c23 * g)


def blended_flexibilities(scene, c) -> tuple[float, float, float]:
    """Kalker's flexibilities blended towards one flexibility at large creepage (Vollebregt & Voltr 2023).

    ``L_i' = (1 - w) L_i + w L``, with the creepage-weighted ``L = (xi^2 + eta^2 + (phi f)^2) / (xi^2/L1 + eta^2/L2 +
    (phi f)^2/L3)``, ``f = (pi a^2/4) / (8a/3)``, and ``w = min(1, r/3)`` of the creepage in units of its
    characteristic value, ``r = sqrt((xi^2 + eta^2) / (xi_c^2 + eta_c^2))``, ``xi_c = mu Fn / (G c^2 C11)``,
    ``eta_c = mu Fn / (G c^2 C22)``: Kalker's three in the linear range, one flexibility from three times the
    characteristic creepage on.
    """
    h = scene.hertz
    return blended(h.a, h.b, scene.shear_modulus, scene.friction_coefficient, scene.normal_load, c.c11, c.c22, c.c23,
                   *scene.creepages)


def blended(a: float, b: float, g: float, mu: float, normal_load: float, c11: float, c22: float, c23: float,
            xi: float, eta: float, phi: float) -> tuple[float, float, float]:
    """:func:`blended_flexibilities` of the semi-axes a, b [m], G [Pa], mu, Fn [N], C11, C22, C23 and the creepages
    (plain floats: the strips take it per scene)."""
    l1, l2, l3 = kalker_flexibilities(a, b, g, c11, c22, c23)
    spin = phi * (math.pi * a * a / 4.0) / (8.0 * a / 3.0)
    denominator = xi * xi / l1 + eta * eta / l2 + spin * spin / l3
    if denominator == 0.0:
        return l1, l2, l3
    single = (xi * xi + eta * eta + spin * spin) / denominator
    c = math.sqrt(a * b)
    scale = mu * normal_load / (g * c * c)
    characteristic = math.hypot(scale / c11, scale / c22)
    weight = min(1.0, math.hypot(xi, eta) / characteristic / 3.0) if characteristic > 0.0 else 1.0
    return (1.0 - weight) * l1 + weight * single, (1.0 - weight) * l2 + weight * single, \
        (1.0 - weight) * l3 + weight * single


FLEXIBILITIES = {"blended": blended_flexibilities, "kalker": flexibilities}


def solve_fastsim(scene, *, nx: int = 40, ny: int = 40, bound: str = "elliptic", flexibility: str = "blended",
                  fields: bool = False) -> EllipticResult:
    """FASTSIM on ``ny`` strips of ``nx`` steps each (module docstring).

    Parameters
    ----------
    scene : EllipticScene
        The case; Coulomb or velocity-dependent friction.
    nx, ny : int
        Steps along each strip and number of strips (>= 2).
    bound : {"elliptic", "parabolic"}
        The traction bound.
    flexibility : {"blended", "kalker"}
        Kalker's three flexibilities blended towards one at large creepage (:func:`blended_flexibilities`), or
        Kalker's three alone.
    fields : bool
        Return the tractions on the grid nodes (``result.fields``).

    Returns
    -------
    EllipticResult
        ``info["flexibilities"]`` (L1, L2, L3) [m/Pa], ``info["stick_fraction"]`` (share of the nodes in stick);
        with velocity-dependent friction ``info["steepness"]``, the largest ``-D V dmu/dv`` of the slipping cells (0
        where none is above 0).
    """
    return solve_fastsim_many((scene,), nx=nx, ny=ny, bound=bound, flexibility=flexibility, fields=fields)[0]


solve_fastsim.options = ("nx", "ny", "bound", "flexibility", "fields")


def solve_fastsim_many(scenes, *, nx: int = 40, ny: int = 40, bound: str = "elliptic", flexibility: str = "blended",
                       fields: bool = False) -> list[EllipticResult]:
    """:func:`solve_fastsim` of each scene (the same arguments), the loaded scenes with constant friction at once and
    those of each velocity-dependent law at once (:func:`~.common.friction_groups`): their strips side by side in one
    march (:func:`stacked`), each scene's numbers those it has alone (:func:`solve_fastsim` is this function of one
    scene).  A scene without load has no contact.

    Raises
    ------
    ValueError
        A scene FASTSIM cannot solve (:func:`inapplicable`; the message names its index), a count < 2, or an unknown
        bound or flexibility.
    """
    for k, scene in enumerate(scenes):
        why = inapplicable(scene)
        if why is not None:
            raise ValueError(f"fastsim cannot solve this scene: {why}" if len(scenes) == 1 else
                             f"fastsim cannot solve scene {k}: {why}")
    nx = int(check_real("nx", nx, lower=2))
    ny = int(check_real("ny", ny, lower=2))
    if bound not in BOUNDS:
        raise ValueError(f"bound = {bound!r} is not one of {BOUNDS}")
    if flexibility not in FLEXIBILITIES:
        raise ValueError(f"flexibility = {flexibility!r} is not one of {tuple(FLEXIBILITIES)}")
    results = [no_load(scene, "fastsim") if scene.normal_load == 0.0 else None for scene in scenes]
    for group in friction_groups(scenes):
        for k, result in zip(group, stacked([scenes[k] for k in group], nx, ny, bound, flexibility, fields),
                             strict=True):
            results[k] = result
    return results


FALLING_PASSES = 2
"""Marches of the extended FASTSIM with spin (one without: the directions are uniform), as the strips'
(:data:`rollcontact.elliptic.methods.strips.FALLING_PASSES`)."""


def stacked(scenes, nx: int, ny: int, bound: str, flexibility: str, fields: bool) -> list[EllipticResult]:
    """FASTSIM of loaded scenes of constant friction (each at its own coefficient) or of one velocity-dependent law
    (module docstring): Coulomb's march, or the extended FASTSIM's marches with the cells at the coefficient of their
    own slip (:data:`FALLING_PASSES` with spin, one without).

    The cells are arrays ``(nx, n ny)``: the scenes' strips side by side, each scene's scalars repeated over its
    strips; every operation is elementwise or a sum over one scene's cells in one order
    (:func:`~.common.by_scene`), so each scene's numbers are those it has alone."""
    n = len(scenes)
    law = scenes[0].friction
    rows = []
    for scene in scenes:
        h = scene.hertz
        mu = scene.friction_coefficient
        l1, l2, l3 = FLEXIBILITIES[flexibility](scene, coefficients(scene))
        peak = mu * (h.max_pressure if bound == "elliptic" else 2.0 * scene.normal_load / (math.pi * h.a * h.b))
        rows.append((h.a, h.b, mu, mu * scene.normal_load, l1, l2, l3, *scene.creepages, peak, scene.rolling_speed))
    scalars = np.array(rows).T  # (scalars, n): per scene
    a, b, mu, _, l1, l2, l3, xi, eta, phi, peak, speed = np.repeat(scalars, ny, axis=1)  # per strip
    dy = 2.0 * b / ny
    y = -b + dy * np.tile(np.arange(ny) + 0.5, n)
    half = a * np.sqrt(1.0 - (y / b) ** 2)  # a(y)
    dx = 2.0 * half / nx
    x = half * (1.0 - (2.0 * np.arange(nx)[:, None] + 1.0) / nx)  # cell centres from the leading edge, x[i, j]
    room = np.clip(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0, None)
    limit = peak * (np.sqrt(room) if bound == "elliptic" else room)
    carried, strip_width = scalars[3], 2.0 * scalars[1] / ny  # mu Fn and dy per scene
    limit *= np.repeat(carried / (by_scene(limit * dx, n) * strip_width), ny)  # the cells carry mu Fn: |F| <= mu Fn
    pressure = limit / mu
    increment = np.empty((nx, 2, y.size))  # from cell i to i + 1: the rigid slip over the flexibility times the step
    increment[:, 0] = dx * (xi / l1 - phi * y / l3)
    increment[:, 1] = dx * (eta / l2 + phi * (x - 0.5 * dx) / l3)
    first = np.array([0.5 * increment[0, 0], 0.5 * dx * (eta / l2 + phi * (half - 0.25 * dx) / l3)])  # half a cell
    steepness = None
    if law.is_constant:
        _, traction, size = march(first, increment, limit)
        qx, qy = traction[:, 0], traction[:, 1]
        stick = size <= limit
    else:
        kernel = friction_kernel(law)
        coefficient = np.full(limit.shape, law.static_coefficient)
        spin = phi != 0.0
        sigma = kept = None
        for k in range(FALLING_PASSES if spin.any() else 1):  # without spin the directions do not change
            marched = march(first, increment, coefficient * pressure)
            sigma, coefficient, steepness = falling_slips(marched, first, increment, coefficient, pressure,
                                                          (l1 / dx, l2 / dx), law, kernel, speed, sigma)
            if k == 0 and not spin.all():
                kept = marched[0], marched[2], sigma, coefficient, steepness
        trial, _, size = marched
        if kept is not None and spin.any():  # the scenes without spin keep their one march
            trial, size, sigma, coefficient, steepness = (np.where(spin, new, old) for new, old in zip(
                (trial, size, sigma, coefficient, steepness), kept, strict=True))
        stick = size <= limit
        with np.errstate(over="ignore"):  # an empty cell (|t| = TINY) has mu p / TINY = inf, whose min with 1 is 1
            scale = np.minimum(1.0, coefficient * pressure / size)
        qx, qy = trial[:, 0] * scale, trial[:, 1] * scale
    area = dx * dy  # midpoint rule over the cells
    forces = by_scene(np.array([qx * area, qy * area, (x * qy - y * qx) * area]), n).T.tolist()
    sticking = (by_scene(stick.astype(float), n) / (nx * ny)).tolist()
    if steepness is not None:
        steepness = steepness.reshape(nx, n, ny).max(axis=(0, 2)).tolist()
    what = "FASTSIM" if law.is_constant else "FASTSIM with falling friction"
    message = f"{what} ({bound} bound, {flexibility} flexibilities, {nx} x {ny})"
    if fields:
        cells = [np.broadcast_to(v, x.shape).reshape(nx, n, ny) for v in (x, y, pressure, qx, qy, stick)]
    results = []
    for k, scene in enumerate(scenes):
        field = TractionField(*(v[:, k].T.copy() for v in cells)) if fields else None
        info = {"flexibilities": tuple(rows[k][4:7]), "stick_fraction": sticking[k]}
        if steepness is not None:
            info["steepness"] = steepness[k]
        results.append(EllipticResult.from_scene(scene, "fastsim", True, message, tuple(forces[k]), field, info))
    return results


def inapplicable(scene) -> str | None:
    """Why FASTSIM cannot treat the scene (a/b outside the coefficient table), or None."""
    return outside_table(scene)


FASTSIM_THEORY_ERROR = 0.1
"""Largest error [1] of the simplified theory against the exact one over mu Fn (mu Fn c for Mz) between the linear
range and saturation: against the discretised 3D solver over a/b 0.2..5, pure and combined creepages up to 9 mu Fn of
linear force and spin, this FASTSIM (elliptic bound, blended flexibilities, 40 x 40) misses by up to
0.027 / 0.085 / 0.047 (Fx / Fy / Mz; ``benchmarks/calibrate_elliptic_levels.py``, table B; with Kalker's three
flexibilities alone 0.075 / 0.096 / 0.065); the field's FASTSIM by up to 0.037 / 0.081 / 0.047 on the issue's
matrix."""

FASTSIM_POISSON_ERROR = 0.1
"""Growth [1 per unit nu] of :data:`FASTSIM_THEORY_ERROR` with Poisson's ratio above steel's 0.28
(:func:`~rollcontact.elliptic.methods.common.poisson_excess`): at nu = 0.49 FASTSIM misses Fy of spin by up to 0.123
(``benchmarks/calibrate_elliptic_levels.py``, table B3; below 0.28 it stays within its error at 0.28)."""

FASTSIM_GRID_ERROR = 0.5
"""The grid's error [1] is modelled as this over min(nx, ny) (first order in the step;
``tests/elliptic/methods/test_fastsim.py`` checks it against a 320 x 320 grid)."""

FASTSIM_FALLING_ERROR = 0.1
"""Error [1] per unit of the law's fall over the contact (:func:`~.common.falling_drop`) that velocity-dependent
friction adds to FASTSIM's estimate.  With it the estimate bounds the error over the matrix of
``benchmarks/calibrate_falling_spin.py`` (table A: largest error 0.104 of mu(0) Fn at 20 x 20, Fy with spin at a/b 5,
as with Coulomb friction; largest error over estimate 0.79 at 20 x 20, 0.86 at 40 x 40)."""

FASTSIM_FALLING_COST_FACTOR = 3.0
"""The extended FASTSIM's time over Coulomb FASTSIM's on the same grid [1]: a margin over the ratios of
``benchmarks/calibrate_falling_spin.py``, table C (both march by :func:`~.common.march`; the extended FASTSIM solves
each cell's slip after each march and marches twice with spin)."""

FASTSIM_COST_PER_STEP = 9e-6
"""Calibrated time [s] per step along the strips (one vector operation over the ny strips;
``benchmarks/calibrate_elliptic_levels.py``); the modelled cost is :func:`~.common.modelled_cost` of the grid's."""


class FastsimAccuracy(AccuracyModel):
    """The simplified theory's error (``3 tau`` times :data:`FASTSIM_THEORY_ERROR` up to it, plus
    :data:`FASTSIM_POISSON_ERROR` per unit of Poisson's ratio above 0.28; tau of
    :func:`~rollcontact.elliptic.methods.common.linear_ratio`: exact at vanishing creepage but for the spin moment,
    whose linear coefficient the three flexibilities do not fit) plus the grid's (:data:`FASTSIM_GRID_ERROR` / n),
    plus with velocity-dependent friction :data:`FASTSIM_FALLING_ERROR` times the law's fall over the contact
    (:func:`~.common.falling_drop`); cost per step along x (:data:`FASTSIM_FALLING_COST_FACTOR` times it with
    velocity-dependent friction)."""

    floor = modelled_cost(10 * FASTSIM_COST_PER_STEP)

    def ladder(self, scene):
        return ({"nx": 20, "ny": 20}, {"nx": 40, "ny": 40}, {"nx": 100, "ny": 100})

    def cost(self, scene, options):
        factor = 1.0 if scene.friction.is_constant else FASTSIM_FALLING_COST_FACTOR
        return modelled_cost(factor * FASTSIM_COST_PER_STEP * options.get("nx", 40)
                             * (1.0 + options.get("ny", 40) / 400.0))

    def error(self, scene, options):
        if scene.normal_load == 0.0:
            return 0.0
        tau = linear_ratio(scene, coefficients(scene))
        return ((FASTSIM_THEORY_ERROR + FASTSIM_POISSON_ERROR * poisson_excess(scene)) * min(1.0, 3.0 * tau)
                + FASTSIM_GRID_ERROR / min(options.get("nx", 40), options.get("ny", 40))
                + FASTSIM_FALLING_ERROR * falling_drop(scene))


METHOD = MethodSpec("fastsim", solve_fastsim, inapplicable, rank=20, accuracy=FastsimAccuracy())
