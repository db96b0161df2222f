"""Strips (``"strips"``): each lateral strip y of the ellipse is a 2D rolling problem (Kalker's strip theory, 1967),
with lateral creepage and spin treated as in FaStrip (Sichani, Enblom & Berg 2016).

The strip at y has half-length ``a(y) = a sqrt(1 - y^2/b^2)`` and the pressure ``p = (p0/a) sqrt(a(y)^2 - x^2)``: a
2D Hertz problem whose ``a(y)/p0(y) = a/p0`` is the same for every strip.  Along a strip the 2D half-plane relates
each traction component to its displacement gradient with a modulus chosen so that the strips reproduce Kalker's
linear theory: ``E_x = 4 G C11 / pi^2``, ``E_y = 4 G C22 / pi^2`` and, for the lateral slip of spin,
``E_phi = 3 G C23 sqrt(b/a) / pi`` (at a/b -> 0, ``E_x -> E*`` and each strip is exactly Carter's problem).  In units
of the slip length ``a/(2 mu p0)`` the rigid slip of the strip is ``X = (xi - phi y) E_x a / (2 mu p0)`` along x and
``Y + psi x`` along y with ``Y = eta E_y a / (2 mu p0)``, ``psi = phi E_phi a / (2 mu p0)``.

Stick zone (strip theory, derived as Carter's): at the leading edge, ``[2 d - a(y), a(y)]``, the traction is

    ``q = (mu p0 / a) [(kappa, lambda) sqrt(a(y)^2 - x^2) - (kappa, lambda - psi) sqrt(a*^2 - (x - d)^2)]``,

``a* = a(y) - d``, where no-slip along both components and a saturated traction ``mu p (kappa, lambda)`` at the
stick edge give ``kappa = X/d``, ``lambda = psi + Y/d``, ``kappa^2 + lambda^2 = 1``, hence
``d = (psi Y + sqrt(Y^2 + (1 - psi^2) X^2)) / (1 - psi^2)`` (|psi| < 1; the strip slips fully where ``d >= a(y)`` or
``|psi| >= 1``).  In the slip zone the traction is ``mu p`` along the slip:

* without spin the slip direction ``(kappa, lambda)`` is uniform along the strip (exact in the strip model, also in
  full slip) and every integral is closed-form: ``Fx(y) = (mu p0/a) kappa (pi/2) (a(y)^2 - a*^2)``,
  ``Fy(y) = (mu p0/a) (pi/2) (lambda a(y)^2 - (lambda - psi) a*^2)``,
  ``int x q_y dx = -(mu p0/a) (pi/2) (lambda - psi) d a*^2``;
* with spin the direction turns along the strip; it is taken from the simplified theory (Kalker's FASTSIM march with
  the elliptic bound and Vollebregt & Voltr's blended flexibilities, :mod:`.fastsim`), as FaStrip does, and the
  strip's tractions are summed over ``steps`` cells.

Over y the strip forces are summed by Gauss-Legendre in theta, ``y = b sin(theta)`` (``strips`` nodes);
``Mz = int (x q_y - y q_x)``.
Velocity-dependent friction (without spin): each strip is the 2D problem ``N' = pi a(y) p0(y) / 2``,
``R = E_x a / (2 p0)``, ``E* = E_x`` with the creep ``sqrt(X^2 + Y^2) 2 mu p0 / (E_x a)`` along ``(X, Y)``, solved by
the project's polynomial method (:func:`rollcontact.solve`, one call per strip; the slip velocity is the 2D one).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from rollcontact.checks import check_real
from rollcontact.dispatch import solve as solve_2d
from rollcontact.elliptic.methods.common import coefficients, linear_ratio, no_load, outside_table
from rollcontact.elliptic.methods.fastsim import blended_flexibilities
from rollcontact.elliptic.result import EllipticResult, TractionField
from rollcontact.method import AccuracyModel, MethodSpec
from rollcontact.scene import Material, Scene

DEFAULT_STRIPS = 24
DEFAULT_STEPS = 20
TINY = 1e-300


@lru_cache(maxsize=16)
def gauss(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes t and weights on [-1, 1] for integrands with ``sqrt(1 - t^2)`` ends (cached per count): Gauss-Legendre in
    theta with ``t = sin(theta)``, so that ``a(y)`` and ``a(y)^2`` integrate alike to spectral accuracy."""
    u, w = np.polynomial.legendre.leggauss(n)
    theta = 0.5 * math.pi * u
    return np.sin(theta), 0.5 * math.pi * np.cos(theta) * w


class StripModel:
    """The strips of one or several scenes: positions, half-lengths, moduli and scaled creepages (module docstring),
    each array with a leading axis over the scenes (a scalar of a scene as a column of shape (n, 1)).

    Several scenes are solved together with the same operations per scene as one scene alone (elementwise, and each
    sum over one scene's row), so a scene's forces do not depend on the others (:func:`solve_strips_many`)."""

    def __init__(self, scenes, strips: int):
        rows, moduli_rows = [], []
        for scene in scenes:
            h = scene.hertz
            c = coefficients(scene)
            g = scene.shear_modulus
            moduli = (4.0 * g * c.c11 / math.pi**2, 4.0 * g * c.c22 / math.pi**2,
                      3.0 * g * c.c23 * math.sqrt(h.b / h.a) / math.pi)
            mu = scene.friction_coefficient
            scale = h.a / (2.0 * mu * h.max_pressure)
            xi, eta, phi = scene.creepages
            rows.append((h.a, h.b, h.max_pressure, mu, xi, phi, moduli[0], scale, eta * moduli[1] * scale,
                         phi * moduli[2] * scale, mu * h.max_pressure / h.a))
            moduli_rows.append(moduli)
        self.coefficients = [coefficients(scene) for scene in scenes]
        self.moduli = moduli_rows
        columns = np.array(rows).T[:, :, None]
        self.a, self.b, self.p0, self.mu, xi, phi, modulus, scale, self.Y, self.psi, self.m = columns
        nodes, weights = gauss(strips)
        self.y = self.b * nodes
        self.weights = self.b * weights
        self.half = self.a * np.sqrt(1.0 - nodes**2)
        self.X = (xi - phi * self.y) * modulus * scale
        # mu p = m sqrt(a(y)^2 - x^2)

    def stick(self):
        """``(d, kappa, lambda, partial)`` per strip: the slip zone's half-length, the traction direction at the stick
        edge, and whether the strip sticks anywhere (``d < a(y)``)."""
        psi, X, Y = self.psi, self.X, self.Y
        with np.errstate(divide="ignore", invalid="ignore"):  # |psi| >= 1 is not used
            d = np.where(np.abs(psi) < 1.0, (psi * Y + np.sqrt(Y * Y + (1.0 - psi * psi) * X * X)) / (1.0 - psi * psi),
                         np.inf)
        partial = d < self.half
        safe = np.where(partial & (d > 0.0), d, 1.0)
        kappa = np.where(partial & (d > 0.0), X / safe, 0.0)
        lam = np.where(partial & (d > 0.0), psi + Y / safe, 0.0)
        norm = np.hypot(X, Y)
        slip_x = np.where(norm > 0.0, X / np.where(norm > 0.0, norm, 1.0), 0.0)
        slip_y = np.where(norm > 0.0, Y / np.where(norm > 0.0, norm, 1.0), 0.0)
        kappa = np.where(partial, kappa, slip_x)  # full slip without spin: along (X, Y)
        lam = np.where(partial, lam, slip_y)
        return np.where(partial, d, self.half), kappa, lam, partial

    def closed_form(self):
        """Forces without spin's lateral part (psi = 0 or d, kappa, lambda as given): ``(Fx, Fy, Mz)`` [N, N, N m],
        arrays over the scenes."""
        d, kappa, lam, partial = self.stick()
        rest = np.where(partial, self.half - d, 0.0)  # a*
        area = 0.5 * math.pi * self.m
        fx = area * kappa * (self.half**2 - rest**2)
        fy = area * (lam * self.half**2 - (lam - self.psi) * rest**2)
        moment = -area * (lam - self.psi) * d * rest**2 - self.y * fx
        w = self.weights
        return np.sum(w * fx, axis=-1), np.sum(w * fy, axis=-1), np.sum(w * moment, axis=-1)

    def stick_traction(self, x, d, kappa, lam):
        """The stick-zone traction ``(q_x, q_y)`` [Pa] at x [m] (arrays broadcast over the strips' last axis)."""
        rest = self.half - d
        full = np.sqrt(np.clip(self.half**2 - x * x, 0.0, None))
        inner = np.sqrt(np.clip(rest**2 - (x - d) ** 2, 0.0, None))
        return self.m * kappa * (full - inner), self.m * (lam * full - (lam - self.psi) * inner)


def solve_strips(scene, *, strips: int = DEFAULT_STRIPS, steps: int = DEFAULT_STEPS, fields: bool = False
                 ) -> EllipticResult:
    """Strip theory with FaStrip's slip directions (module docstring).

    Parameters
    ----------
    scene : EllipticScene
        The case (Coulomb friction; velocity-dependent friction without spin).
    strips : int
        Strips across 2b (>= 2), at Gauss-Legendre nodes in theta.
    steps : int
        Cells along each strip where the tractions are summed (with spin, or for ``fields``; >= 2).
    fields : bool
        Return the tractions on the strips' cells (``result.fields``).

    Returns
    -------
    EllipticResult
        ``info["stick_strips"]``: the share of strips with a stick zone; ``info["psi"]``: the scaled spin.
    """
    why = inapplicable(scene)
    if why is not None:
        raise ValueError(f"strips cannot solve this scene: {why}")
    strips = int(check_real("strips", strips, lower=2))
    steps = int(check_real("steps", steps, lower=2))
    if scene.normal_load == 0.0:
        return no_load(scene, "strips")
    if not scene.friction.is_constant:
        return falling_friction(scene, StripModel((scene,), strips))
    return solve_strips_many((scene,), strips=strips, steps=steps, fields=fields)[0]


solve_strips.options = ("strips", "steps", "fields")


def solve_strips_many(scenes, *, strips: int = DEFAULT_STRIPS, steps: int = DEFAULT_STEPS, fields: bool = False
                      ) -> list[EllipticResult]:
    """:func:`solve_strips` of several loaded scenes with Coulomb friction at once: one array operation over the
    scenes where :func:`solve_strips` makes one over the strips, each scene's result bit for bit its own solve's.

    The scenes with spin march (their cells), those without take the closed form (unless ``fields``); the caller
    checks what :func:`solve_strips` checks (applicability, a load > 0, constant friction, the counts).
    """
    model = StripModel(scenes, strips)
    d, kappa, lam, partial = model.stick()
    spin = (model.psi[:, 0] != 0.0) | fields
    forces = np.empty((len(scenes), 3))
    field = [None] * len(scenes)
    if not spin.all():
        forces[~spin] = np.column_stack(model.closed_form())[~spin]
    if spin.any():
        index = np.flatnonzero(spin)
        sub = subset(model, index)
        marched_forces, marched_fields = marched([scenes[k] for k in index], sub, steps,
                                                 *(v[index] for v in (d, kappa, lam, partial)), fields=fields)
        forces[index] = marched_forces
        for k, f in zip(index, marched_fields, strict=True):
            field[k] = f
    results = []
    for k, scene in enumerate(scenes):
        psi = float(model.psi[k, 0])
        message = ("strip theory, slip directions of the simplified theory" if psi else "strip theory") \
            if spin[k] else "strip theory (closed form)"
        results.append(EllipticResult.from_scene(scene, "strips", True, message, forces[k].tolist(),
                                                 field[k] if fields else None,
                                                 {"stick_strips": float(partial[k].mean()), "psi": psi}))
    return results


def subset(model: StripModel, index) -> StripModel:
    """The strips of the scenes ``index`` of ``model`` (a view of the same arrays, rows taken)."""
    sub = object.__new__(StripModel)
    for name, value in vars(model).items():
        sub.__dict__[name] = [value[k] for k in index] if isinstance(value, list) else value[index]
    return sub


def marched(scenes, model: StripModel, steps: int, d, kappa, lam, partial, fields: bool = False):
    """The strips on ``steps`` cells each: strip theory's traction in the stick zones, ``mu p`` along the direction
    of the simplified theory's traction (a FASTSIM march, :mod:`.fastsim`) in the slip zones; ``(forces (n, 3),
    fields)`` over the scenes (the fields None unless ``fields``)."""
    rows = []
    for scene, c in zip(scenes, model.coefficients, strict=True):
        h = scene.hertz
        rows.append((*scene.creepages, *blended_flexibilities(scene, c), h.max_pressure, h.a, h.b,
                     scene.friction_coefficient, scene.friction_coefficient * scene.normal_load))
    xi, eta, phi, l1, l2, l3, p0, a, b, mu, limit = np.array(rows).T[:, :, None, None]  # (n, 1, 1) each
    y, half = model.y[:, None, :], model.half[:, None, :]  # (n, 1, S)
    dx = 2.0 * half / steps
    x = half * (1.0 - (2.0 * np.arange(steps)[:, None] + 1.0) / steps)  # cell centres from the leading edge
    weights = model.weights[:, None, :]
    bound = mu * (p0 * np.sqrt(np.clip(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0, None)))  # mu p (Hertz)
    total = np.sum((bound * (dx * weights)).reshape(len(scenes), -1), axis=-1)[:, None, None]
    bound *= limit / total  # the cells carry mu Fn
    step_x = dx * (xi / l1 - phi * y / l3)  # the march's increment from cell i to i + 1 (midpoint x_i - dx/2)
    step_y = dx * (eta / l2 + phi * (x - 0.5 * dx) / l3)
    n, count = len(scenes), y.shape[-1]
    trial_x = np.empty((n, steps, count))
    trial_y = np.empty((n, steps, count))
    tx, ty = 0.5 * step_x[:, 0], 0.5 * dx[:, 0] * (eta[:, 0] / l2[:, 0] + phi[:, 0] * (half[:, 0] - 0.25 * dx[:, 0])
                                                    / l3[:, 0])
    for i in range(steps):  # one vector operation over the scenes and strips per cell
        trial_x[:, i], trial_y[:, i] = tx, ty
        scale = np.minimum(1.0, bound[:, i] / np.maximum(np.hypot(tx, ty), TINY))
        tx = tx * scale + step_x[:, 0]
        ty = ty * scale + step_y[:, i]
    size = np.maximum(np.hypot(trial_x, trial_y), TINY)
    direction_x, direction_y = trial_x / size, trial_y / size
    d, kappa, lam, partial = (v[:, None, :] for v in (d, kappa, lam, partial))
    no_spin = model.psi[:, :, None] == 0.0  # without spin the slip direction is uniform along the strip
    direction_x = np.where(no_spin, np.broadcast_to(kappa, x.shape), direction_x)
    direction_y = np.where(no_spin, np.broadcast_to(lam, x.shape), direction_y)
    in_stick = partial & (x > 2.0 * d - half)
    rest = half - d
    full = np.sqrt(np.clip(half**2 - x * x, 0.0, None))
    inner = np.sqrt(np.clip(rest**2 - (x - d) ** 2, 0.0, None))
    m, psi = model.m[:, :, None], model.psi[:, :, None]
    sx, sy = m * kappa * (full - inner), m * (lam * full - (lam - psi) * inner)
    qx = np.where(in_stick, sx, bound * direction_x)
    qy = np.where(in_stick, sy, bound * direction_y)
    weight = weights * dx  # Gauss over y, midpoint cells along x
    forces = np.column_stack([np.sum((q * weight).reshape(n, -1), axis=-1)
                              for q in (qx, qy, x * qy - y * qx)])
    if not fields:
        return forces, [None] * n
    return forces, [TractionField(x[k].T.copy(), np.broadcast_to(y[k], x[k].shape).T.copy(),
                                  (bound[k] / mu[k]).T.copy(), qx[k].T.copy(), qy[k].T.copy(), in_stick[k].T.copy())
                    for k in range(n)]


def falling_friction(scene, model: StripModel) -> EllipticResult:
    """Velocity-dependent friction without spin: one 2D polynomial solve per strip (module docstring); ``model`` holds
    the one scene."""
    e_x = model.moduli[0][0]
    a, p0, mu, Y, psi = (float(v[0, 0]) for v in (model.a, model.p0, model.mu, model.Y, model.psi))
    X, y, half = model.X[0], model.y[0], model.half[0]
    nu = scene.material.poisson_ratio
    material = Material(2.0 * e_x * (1.0 - nu * nu), nu)
    radius = e_x * a / (2.0 * p0)
    norm = np.hypot(X, Y)
    creep = norm / (e_x * a / (2.0 * mu * p0))
    direction = (np.where(norm > 0.0, X / np.where(norm > 0.0, norm, 1.0), 0.0),
                 np.where(norm > 0.0, Y / np.where(norm > 0.0, norm, 1.0), 0.0))
    nodes, weights = gauss(32)
    force = np.empty(y.size)
    lever = np.empty(y.size)
    failures = []
    for j in range(y.size):
        load = 0.5 * math.pi * half[j] * p0 * half[j] / a
        result = solve_2d(Scene(load, creep=float(creep[j]), radius=radius, material=material, friction=scene.friction,
                                rolling_speed=scene.rolling_speed), "polynomial")
        if not result.success:
            failures.append(f"strip y = {y[j]:.4g} m: {result.message}")
        force[j] = result.tangential_force_per_length
        # int x q dx in the 3D frame (leading edge at +a(y)): x3D = -(x2D - offset)
        x2d = result.contact_offset + result.contact_half_width * nodes
        lever[j] = -result.contact_half_width * float(weights @ ((x2d - result.contact_offset) * result.traction(x2d)))
    fx = direction[0] * force
    fy = direction[1] * force
    w = model.weights[0]
    forces = (float(w @ fx), float(w @ fy), float(w @ (direction[1] * lever - y * fx)))
    message = "strip theory, polynomial method per strip" + (": " + "; ".join(failures) if failures else "")
    return EllipticResult.from_scene(scene, "strips", not failures, message, forces,
                                     info={"stick_strips": math.nan, "psi": psi})


def inapplicable(scene) -> str | None:
    """Why the strips cannot treat the scene (a/b outside the coefficient table; spin with velocity-dependent
    friction), or None."""
    why = outside_table(scene)
    if why is not None:
        return why
    if not scene.friction.is_constant and scene.spin_creepage != 0.0:
        return "strips with velocity-dependent friction take no spin (the 2D kernel has one traction component)"
    return None


STRIPS_ERROR = 0.035
"""Error [1] of the strips without spin (Fx, Fy over mu Fn, Mz over mu Fn c): against the discretised 3D solver over
a/b 0.2..5 and creepages up to 9 mu Fn of linear force, 0.018 / 0.018 / 0.034 (the largest: Mz of lateral
creepage at a/b = 0.2 near saturation; ``benchmarks/bench_elliptic_levels.py``, table B)."""

STRIPS_SPIN_ERROR = 0.1
"""Error [1] of the strips with spin beyond ``|psi|`` = :data:`SPIN_ONSET` (the slip directions of the simplified
theory): against the same reference up to 0.034 / 0.085 / 0.034, Fy worst near ``psi = 1`` at a/b = 0.2 with
lateral creepage; this bound keeps a margin over it and the reference's own error."""

SPIN_ONSET = 0.5
"""``|psi|`` up to which the spin's error grows linearly from :data:`STRIPS_ERROR` to :data:`STRIPS_SPIN_ERROR`."""

STRIPS_COST = 6e-5
STRIPS_COST_PER_CELL = 6e-6
STRIPS_FALLING_COST_PER_STRIP = 5e-4
"""Modelled times [s]: the closed form, each cell of a march, each strip's 2D polynomial solve
(``benchmarks/bench_elliptic_levels.py``)."""


class StripsAccuracy(AccuracyModel):
    """Error: :data:`STRIPS_ERROR` without spin, rising to :data:`STRIPS_SPIN_ERROR` with |psi|, both reached from
    the linear limit within ``5 tau`` (tau of :func:`~rollcontact.elliptic.methods.common.linear_ratio`: the forces
    are exact there, the moment of lateral creepage is strip theory's, off Kalker's C23 by up to 0.02 mu Fn c at
    tau = 0.15), plus 1 % of tau for the coefficients.  Cost: closed form, march or 2D solves."""

    floor = STRIPS_COST

    def ladder(self, scene):
        return ({},)

    def cost(self, scene, options):
        if not scene.friction.is_constant:
            return STRIPS_FALLING_COST_PER_STRIP * options.get("strips", DEFAULT_STRIPS)
        if scene.spin_creepage == 0.0 and not options.get("fields"):
            return STRIPS_COST
        return STRIPS_COST + STRIPS_COST_PER_CELL * options.get("steps", DEFAULT_STEPS)

    def error(self, scene, options):
        if scene.normal_load == 0.0:
            return 0.0
        tau = min(1.0, linear_ratio(scene, coefficients(scene)))
        h = scene.hertz
        psi = abs(scene.spin_creepage) * 3.0 * scene.shear_modulus * coefficients(scene).c23 * h.c / (
            2.0 * math.pi * scene.friction_coefficient * h.max_pressure)
        spin = min(1.0, psi / SPIN_ONSET)
        return 0.01 * tau + (STRIPS_ERROR + (STRIPS_SPIN_ERROR - STRIPS_ERROR) * spin) * min(1.0, 5.0 * tau + spin)


METHOD = MethodSpec("strips", solve_strips, inapplicable, rank=10, accuracy=StripsAccuracy())
