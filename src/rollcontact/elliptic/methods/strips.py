"""Strips (``"strips"``): each lateral strip y of the ellipse is a 2D rolling problem (Kalker's strip theory, 1967),
with lateral creepage and spin treated as in FaStrip (Sichani, Enblom & Berg 2016), the slip directions of spin from
a FASTSIM march with flexibilities calibrated for deep spin.

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
* with spin the direction turns along the strip; it is taken from the simplified theory (a FASTSIM march with the
  elliptic bound), as FaStrip does, and the strip's tractions are summed over ``steps`` cells.  The longitudinal slip
  of spin, ``-phi y``, is the strip's own longitudinal creepage, so the march takes it with ``L1`` and the strip's
  stiffening ``f(y)`` (as the stick zones take it with ``f(y) E_x``), not with FASTSIM's ``L3``:
  ``q_x(x - dx) = q_x(x) + dx f(y) (xi - phi y) / L1``, ``q_y(x - dx) = q_y(x) + dx (eta / L2 + phi x_m / L3)``.
  The flexibilities are Vollebregt & Voltr's blended ones (:func:`.fastsim.blended_flexibilities`) times a factor
  that falls with the scaled spin ``|psi|`` (:func:`march_flexibilities`, calibrated): with Kalker's flexibilities
  the march's traction lags too far behind the rigid slip once spin drives the slip.

Two effects of the half-space that strip theory leaves out are added:

* short strips are stiffer: each strip's moduli carry a factor ``f(y) = K (1 - y^2/b^2)^(-gamma/2)`` that grows
  towards the ends ``y = +-b``, with ``gamma`` rising from 0 in the strip limit a/b -> 0 and K keeping C11 and C22
  (:func:`stiffening`; X and Y scale with f, the spin's ``psi`` does not, which keeps C23);
* the lateral traction displaces the surface along x (the cross influence of the half-space, proportional to nu):
  for a traction of Hertz's shape and the lateral force Fy this is the longitudinal creepage ``-phi_c y`` with
  ``phi_c`` proportional to Fy in closed form (:func:`cross_coefficient`), added to X by a fixed point through the
  closed form (:data:`CROSS_ITERATIONS`).  It tilts the strips' traction by a y-odd angle, whence the moment
  ``-int y q_x`` of lateral creepage.  With spin the longitudinal traction's own cross influence on the lateral slip
  is of the same order and is not modelled, so neither is applied there.

Over y the strip forces are summed by Gauss-Legendre in theta, ``y = b sin(theta)`` (``strips`` nodes);
``Mz = int (x q_y - y q_x)``.
Velocity-dependent friction (without spin): each strip is the 2D problem ``N' = pi a(y) p0(y) / 2``,
``R = E a / (2 p0)``, ``E* = E`` with ``E = f(y) E_x`` and the creep ``sqrt(X^2 + Y^2) 2 mu p0 / (E a)`` along
``(X, Y)``, solved by the project's polynomial method (:func:`rollcontact.solve`, one call per strip; the slip velocity
is the 2D one; the cross influence, a fixed point over the 2D solves, is not applied).
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
    """The scene's strips: positions, half-lengths, moduli and scaled creepages (module docstring)."""

    def __init__(self, scene, strips: int):
        h = scene.hertz
        self.a, self.b, self.p0 = h.a, h.b, h.max_pressure
        self.mu = scene.friction_coefficient
        c = self.coefficients = coefficients(scene)
        g = scene.shear_modulus
        self.moduli = (4.0 * g * c.c11 / math.pi**2, 4.0 * g * c.c22 / math.pi**2,
                       3.0 * g * c.c23 * math.sqrt(self.b / self.a) / math.pi)
        nodes, weights = gauss(strips)
        self.y = self.b * nodes
        self.weights = self.b * weights
        self.half = self.a * np.sqrt(1.0 - nodes**2)
        self.factor = stiffening(h.aspect_ratio, nodes, self.weights * self.half)
        self.scale = self.factor * self.a / (2.0 * self.mu * self.p0)  # slip length per unit modulus and creepage
        xi, eta, phi = scene.creepages
        self.rigid_x = xi - phi * self.y
        self.X = self.rigid_x * self.moduli[0] * self.scale
        self.Y = eta * self.moduli[1] * self.scale
        self.spin = phi != 0.0
        self.psi = float(phi * self.moduli[2] * self.a / (2.0 * self.mu * self.p0))  # unstiffened: keeps C23
        self.m = self.mu * self.p0 / self.a  # mu p = m sqrt(a(y)^2 - x^2)
        self.cross = 0.0 if self.spin else cross_coefficient(scene)

    def couple(self, lateral_force: float) -> float:
        """Add the longitudinal creepage ``-phi_c y`` that a lateral force [N] induces (:func:`cross_coefficient`) to
        the strips' X; returns ``phi_c`` [1/m]."""
        phi_c = self.cross * lateral_force
        self.X = (self.rigid_x - phi_c * self.y) * self.moduli[0] * self.scale
        return phi_c

    def stick(self):
        """``(d, kappa, lambda, partial)`` per strip: the slip zone's half-length, the traction direction at the stick
        edge, and whether the strip sticks anywhere (``d < a(y)``)."""
        psi, X, Y = self.psi, self.X, self.Y
        room = 1.0 - psi * psi
        safe_room = np.where(room > 0.0, room, 1.0)
        d = np.where(room > 0.0, (psi * Y + np.sqrt(Y * Y + safe_room * X * X)) / safe_room, np.inf)
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

    def strip_forces(self):
        """Each strip's ``(Fx, Fy, Mz)`` per unit width [N/m, N/m, N] without spin's lateral part (psi = 0 or d,
        kappa, lambda as given), before the weights of the strips' widths."""
        d, kappa, lam, partial = self.stick()
        rest = np.where(partial, self.half - d, 0.0)  # a*
        area = 0.5 * math.pi * self.m
        fx = area * kappa * (self.half**2 - rest**2)
        fy = area * (lam * self.half**2 - (lam - self.psi) * rest**2)
        return fx, fy, -area * (lam - self.psi) * d * rest**2 - self.y * fx

    def closed_form(self):
        """Forces without spin's lateral part (psi = 0 or d, kappa, lambda as given): ``(Fx, Fy, Mz)`` [N, N, N m]."""
        w = self.weights
        return tuple(float(w @ v) for v in self.strip_forces())

    def stick_traction(self, x, d, kappa, lam):
        """The stick-zone traction ``(q_x, q_y)`` [Pa] at x [m] (arrays broadcast over the strips' last axis)."""
        rest = self.half - d
        full = np.sqrt(np.clip(self.half**2 - x * x, 0.0, None))
        inner = np.sqrt(np.clip(rest**2 - (x - d) ** 2, 0.0, None))
        return self.m * kappa * (full - inner), self.m * (lam * full - (lam - self.psi) * inner)


def stiffening(ratio: float, nodes: np.ndarray, load_weights: np.ndarray) -> np.ndarray:
    """Each strip's modulus factor ``f(y) = K (1 - y^2/b^2)^(-gamma/2)`` [1], ``gamma = (a/b) / (a/b + s)`` with
    ``s`` = :data:`STIFFENING_SCALE`, and ``K`` such that ``sum_j w_j a(y_j)^2 f_j = sum_j w_j a(y_j)^2``
    (``load_weights``: the strips' weights times ``a(y)^2``, the linear force's share of each strip), so that the
    strips keep Kalker's C11 and C22.  A short strip has neighbours of similar traction over a width comparable to
    its length, so the half-space answers it more stiffly than the 2D half-plane does; the effect grows with a/b and
    vanishes in the strip limit a/b -> 0, where the strips are Carter's problems."""
    gamma = ratio / (ratio + STIFFENING_SCALE)
    factor = (1.0 - nodes * nodes) ** (-0.5 * gamma)
    return factor * (float(np.sum(load_weights)) / float(load_weights @ factor))


@lru_cache(maxsize=1)
def _angles(n: int = 64) -> tuple[np.ndarray, np.ndarray]:
    theta = (np.arange(n) + 0.5) * (2.0 * math.pi / n)
    return np.cos(theta) ** 2, np.sin(theta) ** 2


def cross_coefficient(scene) -> float:
    """``phi_c / Fy`` [1/(N m)]: the longitudinal creepage ``-phi_c y`` that a lateral traction of Hertz's shape,
    ``q_y = q0 sqrt(1 - x^2/a^2 - y^2/b^2)`` with ``q0 = 3 Fy / (2 pi a b)``, induces through the half-space's
    cross influence (``u_x`` of ``q_y``, proportional to nu).  That ``u_x`` is bilinear in the ellipse, ``u_x = K x y``
    with (Hadamard's finite part of ``(nu / (pi G)) int q_y d^2/dx dy (X Y / r^3)``, both bodies)

        ``K = -(nu q0 / (2 G)) int_0^{2 pi} (15 cos^2 t sin^2 t - 2) sqrt(cos^2 t / a^2 + sin^2 t / b^2) dt``

    (the circle gives ``pi nu q0 / (8 G a)``, as Johnson's displacements of a Hertzian tangential traction on a circle
    do for two bodies: K. L. Johnson, Contact Mechanics, 1985), and the steady slip
    ``s_x = w_x + du_x/dx`` gains ``K y``: a longitudinal creepage ``-phi_c y``, ``phi_c = -K``.  Strip theory has no
    such coupling; with it the lateral force turns the traction of the strips off the y axis by a y-odd amount, which
    gives the moment ``-int y q_x`` that the exact theory finds with lateral creepage."""
    h = scene.hertz
    cos2, sin2 = _angles()
    integral = 2.0 * math.pi * float(np.mean((15.0 * cos2 * sin2 - 2.0) * np.sqrt(cos2 / h.a**2 + sin2 / h.b**2)))
    q0_per_force = 3.0 / (2.0 * math.pi * h.a * h.b)
    return 0.5 * scene.material.poisson_ratio * q0_per_force * integral / scene.shear_modulus


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
    model = StripModel(scene, strips)
    if not scene.friction.is_constant:
        return falling_friction(scene, model)
    phi_c, forces = 0.0, None
    if model.cross:  # the lateral force's longitudinal creepage, by fixed point through the closed form
        forces = model.closed_form()
        for _ in range(CROSS_ITERATIONS):
            phi_c = model.couple(forces[1])
            forces = model.closed_form()
    d, kappa, lam, partial = model.stick()
    info = {"stick_strips": float(partial.mean()), "psi": model.psi, "cross_spin": phi_c}
    field = None
    message = "strip theory (closed form)"
    if model.spin or fields:
        forces, field = marched(scene, model, steps, d, kappa, lam, partial, phi_c, fields)
        message = "strip theory, slip directions of the simplified theory" if model.spin else "strip theory"
    elif forces is None:
        forces = model.closed_form()
    return EllipticResult.from_scene(scene, "strips", True, message, forces, field, info)


solve_strips.options = ("strips", "steps", "fields")


def march_flexibilities(scene, c, psi: float) -> tuple[float, float, float]:
    """The march's ``(L1, L2, L3)`` [m/Pa]: Vollebregt & Voltr's blended flexibilities
    (:func:`.fastsim.blended_flexibilities`) times ``k_x`` (L1) and ``k_y`` (L2, L3),

        ``k = (1 + (k_0 - 1) |psi| / (|psi| + Q)) / (1 + |psi| / P)``,  ``k_0,x = A_x0 + A_x1 ln(a/b)``,
        ``k_0,y = A_y0 + A_y1 ln(a/b)``,  ``P = P_1 (1 + a/b)^m``

    (:data:`SPIN_FLEXIBILITY`: calibrated, not derived).  At small spin the factors are 1: Kalker's flexibilities,
    chosen for the linear forces, hold where the stick zones carry the traction.  In the slip zones the march's
    traction lags behind the rigid slip by the flexibility times the rate at which the traction turns; that lag is too
    large once spin drives the slip (the lateral force of spin is overestimated, most at a/b 0.5..2), so the factors
    fall with the scaled spin ``|psi|``; their a/b dependence ``k_0`` follows the strips' own error, which changes sign
    between the strip limit a/b -> 0 and long strips (a/b = 5)."""
    l1, l2, l3 = blended_flexibilities(scene, c)
    x0, x1, y0, y1, scale, power, onset = SPIN_FLEXIBILITY
    ratio = scene.hertz.aspect_ratio
    spin = abs(psi)
    fall = 1.0 + spin / (scale * (1.0 + ratio) ** power)
    rise = spin / (spin + onset)
    log_ratio = math.log(ratio)
    k_x = (1.0 + (x0 + x1 * log_ratio - 1.0) * rise) / fall
    k_y = (1.0 + (y0 + y1 * log_ratio - 1.0) * rise) / fall
    return k_x * l1, k_y * l2, k_y * l3


def marched(scene, model: StripModel, steps: int, d, kappa, lam, partial, phi_c: float, fields: bool):
    """The strips on ``steps`` cells each: strip theory's traction in the stick zones, ``mu p`` along the direction
    of the simplified theory's traction (a FASTSIM march with the strips' flexibilities, module docstring) in the slip
    zones.  Returns the forces and, with ``fields``, the traction field (else None)."""
    h = scene.hertz
    xi, eta, phi = scene.creepages
    l1, l2, l3 = march_flexibilities(scene, model.coefficients, model.psi)
    y, half = model.y, model.half
    dx = 2.0 * half / steps
    x = half * (1.0 - (2.0 * np.arange(steps)[:, None] + 1.0) / steps)  # cell centres from the leading edge
    bound = model.mu * h.pressure(x, y)
    bound *= model.mu * scene.normal_load / float(np.sum(bound * (dx * model.weights)))  # the cells carry mu Fn
    step = np.empty((steps, 2, y.size))  # the march's increment from cell i to i + 1 (midpoint x_i - dx/2)
    step[:, 0] = dx * (xi - (phi + phi_c) * y) / l1 * model.factor  # the strip's stiffening, as in its stick zone
    step[:, 1] = dx * (eta / l2 + phi * (x - 0.5 * dx) / l3)
    trial = np.empty((steps, 2, y.size))
    t = np.stack((0.5 * step[0, 0], 0.5 * dx * (eta / l2 + phi * (half - 0.25 * dx) / l3)))
    for i in range(steps):  # one vector operation over the strips per cell
        trial[i] = t
        t = t * np.minimum(1.0, bound[i] / np.maximum(np.hypot(t[0], t[1]), TINY)) + step[i]
    trial_x, trial_y = trial[:, 0], trial[:, 1]
    size = np.maximum(np.hypot(trial_x, trial_y), TINY)
    direction_x, direction_y = trial_x / size, trial_y / size
    if not model.spin:  # without spin the slip direction is uniform along the strip
        direction_x = np.broadcast_to(kappa, x.shape)
        direction_y = np.broadcast_to(lam, x.shape)
    in_stick = partial & (x > 2.0 * d - half)
    sx, sy = model.stick_traction(x, d, kappa, lam)
    qx = np.where(in_stick, sx, bound * direction_x)
    qy = np.where(in_stick, sy, bound * direction_y)
    weight = model.weights * dx  # Gauss over y, midpoint cells along x
    forces = (float(np.sum(qx * weight)), float(np.sum(qy * weight)), float(np.sum((x * qy - y * qx) * weight)))
    if not fields:
        return forces, None
    field = TractionField(x.T.copy(), np.broadcast_to(y, x.shape).T.copy(), (bound / model.mu).T.copy(), qx.T.copy(),
                          qy.T.copy(), in_stick.T.copy())
    return forces, field


def solve_strips_many(scenes, *, strips: int = DEFAULT_STRIPS, steps: int = DEFAULT_STEPS, fields: bool = False
                      ) -> list[EllipticResult]:
    """:func:`solve_strips` of several loaded scenes with Coulomb friction at once: the stick zones, the closed form
    with its cross-influence fixed point and the march are array operations over the scenes (:class:`StripStack`,
    :func:`marched_many`), each scene's result bit for bit :func:`solve_strips`'s (the same operations per element,
    each sum over one scene's own values in :func:`solve_strips`'s order).  The caller checks what
    :func:`solve_strips` checks (applicability, a load > 0, constant friction, the counts)."""
    stack = StripStack([StripModel(scene, strips) for scene in scenes])
    n = len(scenes)
    phi_c = np.zeros(n)
    forces = None
    if stack.coupled.any():  # the lateral force's longitudinal creepage, by fixed point through the closed form
        forces = stack.closed_form()
        for _ in range(CROSS_ITERATIONS):
            phi_c = stack.couple(forces[1])
            forces = stack.closed_form()
    d, kappa, lam, partial = stack.stick()
    march = stack.spin | fields
    out = np.empty((n, 3))
    field = [None] * n
    if not march.all():
        out[~march] = np.column_stack(stack.closed_form() if forces is None else forces)[~march]
    if march.any():
        index = np.flatnonzero(march)
        marched_forces, marched_fields = marched_many([scenes[k] for k in index], stack.rows(index), steps,
                                                 *(v[index] for v in (d, kappa, lam, partial)), phi_c[index], fields)
        out[index] = marched_forces
        for k, f in zip(index, marched_fields, strict=True):
            field[k] = f
    results = []
    for k, scene in enumerate(scenes):
        spin = bool(stack.spin[k])
        message = ("strip theory, slip directions of the simplified theory" if spin else "strip theory") \
            if march[k] else "strip theory (closed form)"
        info = {"stick_strips": float(partial[k].mean()), "psi": float(stack.psi[k, 0]), "cross_spin": float(phi_c[k])}
        results.append(EllipticResult.from_scene(scene, "strips", True, message, out[k].tolist(), field[k], info))
    return results


class StripStack:
    """The strips of several scenes (:class:`StripModel` each) stacked along a leading axis: each array ``(n, S)``,
    each scalar of a scene a column ``(n, 1)``; the stick zones, the closed form and the cross influence of
    :class:`StripModel` as array operations over the scenes, each sum over one scene's row."""

    SCALARS = ("a", "b", "p0", "mu", "psi", "m", "cross")
    ARRAYS = ("y", "weights", "half", "factor", "scale", "rigid_x", "X", "Y")

    def __init__(self, models):
        self.models = list(models)
        scalars = np.array([[getattr(m, name) for name in self.SCALARS] + [m.moduli[0]] for m in self.models],
                           dtype=float)
        for i, name in enumerate(self.SCALARS):
            setattr(self, name, scalars[:, i:i + 1])
        self.modulus_x = scalars[:, -1:]
        for name in self.ARRAYS:
            setattr(self, name, np.array([getattr(m, name) for m in self.models], dtype=float))
        self.spin = np.array([m.spin for m in self.models], dtype=bool)
        self.coupled = self.cross[:, 0] != 0.0
        self.coefficients = [m.coefficients for m in self.models]

    def rows(self, index) -> StripStack:
        """The stack of the scenes ``index`` (this one when it holds all), with their current X."""
        if len(index) == len(self.models):
            return self
        rows = StripStack([self.models[k] for k in index])
        rows.X = self.X[index]
        return rows

    def couple(self, lateral_force):
        """:meth:`StripModel.couple` of the coupled scenes (``lateral_force`` [N] per scene); ``phi_c`` [1/m] per
        scene (0 where a scene has no cross influence, whose X is left as it is)."""
        phi_c = np.where(self.coupled, self.cross[:, 0] * lateral_force, 0.0)
        self.X = np.where(self.coupled[:, None], (self.rigid_x - phi_c[:, None] * self.y) * self.modulus_x * self.scale,
                          self.X)
        return phi_c

    stick = StripModel.stick
    stick_traction = StripModel.stick_traction
    strip_forces = StripModel.strip_forces

    def closed_form(self):
        """:meth:`StripModel.closed_form` of every scene: ``(Fx, Fy, Mz)``, arrays over the scenes."""
        w = self.weights
        # each scene's sums as StripModel.closed_form takes them (a dot product per scene)
        return tuple(np.array([w[k] @ v[k] for k in range(len(w))]) for v in self.strip_forces())


def marched_many(scenes, stack: StripStack, steps: int, d, kappa, lam, partial, phi_c, fields: bool):
    """The strips of the scenes on ``steps`` cells each: strip theory's traction in the stick zones, ``mu p`` along
    the direction of the simplified theory's traction (a FASTSIM march with the strips' flexibilities, module
    docstring) in the slip zones.  Returns the forces ``(n, 3)`` and, with ``fields``, the traction fields (else
    None each)."""
    rows = []
    for scene, c, psi in zip(scenes, stack.coefficients, stack.psi[:, 0].tolist(), strict=True):
        h = scene.hertz
        rows.append((*scene.creepages, *march_flexibilities(scene, c, psi), h.max_pressure, h.a, h.b,
                     scene.friction_coefficient, scene.friction_coefficient * scene.normal_load))
    xi, eta, phi, l1, l2, l3, p0, a, b, mu, limit = np.array(rows).T[:, :, None, None]  # (n, 1, 1) each
    phi_c = np.asarray(phi_c, dtype=float)[:, None, None]
    n = len(scenes)
    y, half, weights = (v[:, None, :] for v in (stack.y, stack.half, stack.weights))  # (n, 1, S)
    dx = 2.0 * half / steps
    x = half * (1.0 - (2.0 * np.arange(steps)[:, None] + 1.0) / steps)  # cell centres from the leading edge
    bound = mu * (p0 * np.sqrt(np.clip(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0, None)))  # mu p (Hertz)
    bound *= limit / np.sum((bound * (dx * weights)).reshape(n, -1), axis=-1)[:, None, None]  # the cells carry mu Fn
    step = np.empty((n, steps, 2, y.shape[-1]))  # the march's increment from cell i to i + 1 (midpoint x_i - dx/2)
    step[:, :, 0] = dx * (xi - (phi + phi_c) * y) / l1 * stack.factor[:, None, :]
    step[:, :, 1] = dx * (eta / l2 + phi * (x - 0.5 * dx) / l3)
    trial = np.empty_like(step)
    t = np.stack((0.5 * step[:, 0, 0], (0.5 * dx * (eta / l2 + phi * (half - 0.25 * dx) / l3))[:, 0]), axis=1)
    for i in range(steps):  # one vector operation over the scenes and strips per cell
        trial[:, i] = t
        t = t * np.minimum(1.0, bound[:, i] / np.maximum(np.hypot(t[:, 0], t[:, 1]), TINY))[:, None, :] + step[:, i]
    trial_x, trial_y = trial[:, :, 0], trial[:, :, 1]
    size = np.maximum(np.hypot(trial_x, trial_y), TINY)
    direction_x, direction_y = trial_x / size, trial_y / size
    d, kappa, lam, partial = (v[:, None, :] for v in (d, kappa, lam, partial))
    uniform = ~stack.spin[:, None, None]  # without spin the slip direction is uniform along the strip
    direction_x = np.where(uniform, np.broadcast_to(kappa, x.shape), direction_x)
    direction_y = np.where(uniform, np.broadcast_to(lam, x.shape), direction_y)
    in_stick = partial & (x > 2.0 * d - half)
    rest = half - d
    full = np.sqrt(np.clip(half**2 - x * x, 0.0, None))
    inner = np.sqrt(np.clip(rest**2 - (x - d) ** 2, 0.0, None))
    m, psi = stack.m[:, :, None], stack.psi[:, :, None]
    qx = np.where(in_stick, m * kappa * (full - inner), bound * direction_x)
    qy = np.where(in_stick, m * (lam * full - (lam - psi) * inner), bound * direction_y)
    weight = weights * dx  # Gauss over y, midpoint cells along x
    forces = np.column_stack([np.sum((q * weight).reshape(n, -1), axis=-1) for q in (qx, qy, x * qy - y * qx)])
    if not fields:
        return forces, [None] * n
    return forces, [TractionField(x[k].T.copy(), np.broadcast_to(y[k], x[k].shape).T.copy(),
                                  (bound[k] / mu[k]).T.copy(), qx[k].T.copy(), qy[k].T.copy(), in_stick[k].T.copy())
                    for k in range(n)]


def falling_friction(scene, model: StripModel) -> EllipticResult:
    """Velocity-dependent friction without spin: one 2D polynomial solve per strip (module docstring)."""
    e_x = model.moduli[0]
    nu = scene.material.poisson_ratio
    norm = np.hypot(model.X, model.Y)
    creep = norm / (e_x * model.scale)  # the strip's creepage along (X, Y), on its own modulus factor * E_x
    direction = (np.where(norm > 0.0, model.X / np.where(norm > 0.0, norm, 1.0), 0.0),
                 np.where(norm > 0.0, model.Y / np.where(norm > 0.0, norm, 1.0), 0.0))
    nodes, weights = gauss(32)
    force = np.empty(model.y.size)
    lever = np.empty(model.y.size)
    failures = []
    for j in range(model.y.size):
        load = 0.5 * math.pi * model.half[j] * model.p0 * model.half[j] / model.a
        modulus = e_x * model.factor[j]
        result = solve_2d(Scene(load, creep=float(creep[j]), radius=modulus * model.a / (2.0 * model.p0),
                                material=Material(2.0 * modulus * (1.0 - nu * nu), nu), friction=scene.friction,
                                rolling_speed=scene.rolling_speed), "polynomial")
        if not result.success:
            failures.append(f"strip y = {model.y[j]:.4g} m: {result.message}")
        force[j] = result.tangential_force_per_length
        # int x q dx in the 3D frame (leading edge at +a(y)): x3D = -(x2D - offset)
        x2d = result.contact_offset + result.contact_half_width * nodes
        lever[j] = -result.contact_half_width * float(weights @ ((x2d - result.contact_offset) * result.traction(x2d)))
    fx = direction[0] * force
    fy = direction[1] * force
    w = model.weights
    forces = (float(w @ fx), float(w @ fy), float(w @ (direction[1] * lever - model.y * fx)))
    message = "strip theory, polynomial method per strip" + (": " + "; ".join(failures) if failures else "")
    return EllipticResult.from_scene(scene, "strips", not failures, message, forces,
                                     info={"stick_strips": math.nan, "psi": model.psi})


def inapplicable(scene) -> str | None:
    """Why the strips cannot treat the scene (a/b outside the coefficient table; spin with velocity-dependent
    friction), or None."""
    why = outside_table(scene)
    if why is not None:
        return why
    if not scene.friction.is_constant and scene.spin_creepage != 0.0:
        return "strips with velocity-dependent friction take no spin (the 2D kernel has one traction component)"
    return None


CROSS_ITERATIONS = 2
"""Fixed-point passes of the lateral force's longitudinal creepage (:func:`cross_coefficient`) through the closed form
(the second changes the forces by less than 1e-3 mu Fn on ``benchmarks/bench_elliptic_levels.py``'s cases)."""

STIFFENING_SCALE = 3.0
"""``s`` [1] of :func:`stiffening`: the a/b where the short strips' stiffening reaches half its full exponent.
Calibrated, not derived: of s = 0.3, 0.5, 0.8, 1.2, 2, 3, 5, s = 3 keeps Fx and Fy without spin closest to the
discretised solver on the cases of ``benchmarks/bench_elliptic_levels.py`` (table B, the calibration set: within
0.010 mu Fn) and on the disjoint matrix of ``benchmarks/bench_elliptic.py`` (the validation set: also 0.010); the
strips without it miss by up to 0.023."""

SPIN_FLEXIBILITY = (0.9956, 0.0953, 0.8155, 0.1248, 9.8629, 1.0005, 0.8)
"""``(A_x0, A_x1, A_y0, A_y1, P_1, m, Q)`` of :func:`march_flexibilities`.  Calibrated, not derived:
``benchmarks/calibrate_strips_spin.py`` fits the first six (Q held) to the strips' errors with spin against the
discretised level, on the spin cases of ``benchmarks/bench_elliptic_levels.py`` (table B: spin around and past the
strips' full slip, ``|psi|`` 0.15..15) and on operating points of small creepage and spin; the disjoint matrix of
``benchmarks/bench_elliptic.py`` checks it.  The results files carry the errors.  The fit holds at the default counts
(:data:`DEFAULT_STRIPS`, :data:`DEFAULT_STEPS`): it also absorbs the march's lag of half a cell, so other counts move
the errors with spin by up to about 0.02."""

STRIPS_ERROR = 0.03
"""Error [1] of the strips without spin (Fx, Fy over mu Fn, Mz over mu Fn c): against the discretised 3D solver over
a/b 0.2..5 and creepages up to 9 mu Fn of linear force, the largest is Mz of lateral creepage at a/b = 5
(``benchmarks/bench_elliptic_levels.py``, table B)."""

STRIPS_SPIN_ERROR = 0.06
"""Error [1] of the strips with spin beyond ``|psi|`` = :data:`SPIN_ONSET` (the slip directions of the march):
against the discretised solver the largest errors with spin are about 0.05 (``benchmarks/bench_elliptic_levels.py``,
table B, around the strips' full slip ``|psi|`` 1..2 and at a/b = 5); this bound keeps a margin over it and the
reference's own error."""

SPIN_ONSET = 0.5
"""``|psi|`` up to which the spin's error grows linearly from :data:`STRIPS_ERROR` to :data:`STRIPS_SPIN_ERROR`."""

STRIPS_COST = 1.2e-4
STRIPS_COST_PER_CELL = 2.5e-6
STRIPS_FALLING_COST_PER_STRIP = 5e-4
"""Modelled times [s]: the closed form, each cell of a march, each strip's 2D polynomial solve
(``benchmarks/bench_elliptic_levels.py``)."""


class StripsAccuracy(AccuracyModel):
    """Error: :data:`STRIPS_ERROR` without spin, rising to :data:`STRIPS_SPIN_ERROR` with |psi|, both reached from
    the linear limit within ``5 tau`` (tau of :func:`~rollcontact.elliptic.methods.common.linear_ratio`: the forces
    are exact there; the moment of lateral creepage is above Kalker's C23 by 14 % at a/b = 5 to 31 % at a/b = 0.2,
    the cross influence taking Hertz's shape for a lateral traction that is not yet saturated, about 0.07 tau at
    most), plus 1 % of tau for the coefficients.  Cost: closed form, march or 2D solves."""

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
        c = coefficients(scene)
        tau = min(1.0, linear_ratio(scene, c))
        h = scene.hertz
        psi = abs(scene.spin_creepage) * 3.0 * scene.shear_modulus * c.c23 * h.c / (
            2.0 * math.pi * scene.friction_coefficient * h.max_pressure)
        spin = min(1.0, psi / SPIN_ONSET)
        return 0.01 * tau + (STRIPS_ERROR + (STRIPS_SPIN_ERROR - STRIPS_ERROR) * spin) * min(1.0, 5.0 * tau + spin)


METHOD = MethodSpec("strips", solve_strips, inapplicable, rank=10, accuracy=StripsAccuracy())
