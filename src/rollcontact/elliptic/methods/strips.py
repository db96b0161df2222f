"""Strips (``"strips"``): each lateral strip y of the ellipse is a 2D rolling problem (Kalker's strip theory, 1967),
with lateral creepage and spin treated as in FaStrip (Sichani, Enblom & Berg 2016), the slip directions of spin from
a FASTSIM march with flexibilities calibrated for deep spin.

The strip at y has half-length ``a(y) = a sqrt(1 - y^2/b^2)`` and the pressure ``p = (p0/a) sqrt(a(y)^2 - x^2)``: a
2D Hertz problem whose ``a(y)/p0(y) = a/p0`` is the same for every strip.  Along a strip the 2D half-plane relates
each traction component to its displacement gradient with a modulus chosen so that the strips reproduce Kalker's
linear theory: ``E_x = 4 G C11 / pi^2``, ``E_y = 4 G C22 / pi^2``, for the lateral slip of spin
``E_phi = 3 G C23 sqrt(b/a) / pi`` and for its longitudinal slip ``r E_x`` (at a/b -> 0, ``E_x -> E*`` and each strip
is exactly Carter's problem).  In units of the slip length ``a/(2 mu p0)`` the rigid slip of the strip is
``X = (xi - r phi y) E_x a / (2 mu p0)`` along x and ``Y + psi x`` along y with ``Y = eta E_y a / (2 mu p0)``,
``psi = phi E_phi a / (2 mu p0)``.  In the linear limit a strip's longitudinal force is ``(pi/2) f(y) E_x a(y)`` times
its creepage (``f``: the stiffening below) and the moment of spin is all ``-int y q_x``, so
``r = G c^4 C33 / ((pi/2) E_x int f(y) y^2 a(y) dy)`` keeps C33 (with ``E_x`` alone the strips' C33 is 45 % to 110 %
of Kalker's over a/b 0.2..5 and nu 0..0.45).

Stick zone (strip theory, derived as Carter's): at the leading edge, ``[2 d - a(y), a(y)]``, the traction is

    ``q = (mu p0 / a) [(kappa, lambda) sqrt(a(y)^2 - x^2) - (kappa, lambda - psi) sqrt(a*^2 - (x - d)^2)]``,

``a* = a(y) - d``, where no-slip along both components and a saturated traction ``mu p (kappa, lambda)`` at the
stick edge give ``kappa = X/d``, ``lambda = psi + Y/d``, ``kappa^2 + lambda^2 = 1``, hence
``(1 - psi^2) d^2 - 2 psi Y d - (X^2 + Y^2) = 0``, whose root

    ``d = (psi Y + sqrt(Y^2 + (1 - psi^2) X^2)) / (1 - psi^2) = (X^2 + Y^2) / (sqrt(Y^2 + (1 - psi^2) X^2) - psi Y)``

(the second form where ``psi Y < 0``, free of cancellation) is positive for ``|psi| < 1`` and, when the lateral slip
opposes the spin's (``psi Y < 0``), also past ``|psi| = 1`` while the root is real: it passes ``|psi| = 1``
continuously there.  In the stick zone ``|q| <= mu p`` holds for ``|psi| <= 1``; past it, with ``s_2 / s_1`` (the
two square roots) largest at the leading edge, ``sqrt(a*/a(y))``, it holds where the excess
``v = sqrt(a*/a(y)) (1 - 2 lambda psi + psi^2) / (2 (1 - lambda psi))`` is at most 1.  Beyond, the exact stick zone
leaves the leading edge, which strip theory cannot follow: the strip keeps the share
``(F - v) / (F - 1)`` (F = :data:`STICK_FADE`, calibrated) of its stick traction, held within mu p, and takes the
march's slip traction (below) for the rest, so that its stick zone fades out as v reaches F.  The strip slips fully
where ``d >= a(y)``, where no root is positive or where ``v >= F``.  In the slip zone the traction is ``mu p`` along
the slip:

* without spin the slip direction ``(kappa, lambda)`` is uniform along the strip (exact in the strip model, also in
  full slip) and every integral is closed-form: ``Fx(y) = (mu p0/a) kappa (pi/2) (a(y)^2 - a*^2)``,
  ``Fy(y) = (mu p0/a) (pi/2) (lambda a(y)^2 - (lambda - psi) a*^2)``,
  ``int x q_y dx = -(mu p0/a) (pi/2) (lambda - psi) d a*^2``;
* with spin the direction turns along the strip; it is taken from the simplified theory (a FASTSIM march with the
  elliptic bound), as FaStrip does, on ``steps`` cells per strip (midpoints along x, Gauss over y).  The forces are
  the closed form (uniform direction ``(kappa, lambda)``, integrated exactly) plus the sums over the cells of the
  march's departure from it, ``mu p`` times the change of direction in the slip zones: the stick zones' square-root
  traction, which the midpoint rule would miss by ``O(steps^-1/2)`` (9 % of the linear force at 20 cells), is
  integrated exactly and the linear limit holds with spin too.  The cells' mu p is Hertz's scaled so that the cells
  carry mu Fn, and the stick zones' traction on the cells takes the same scale, so that it meets the slip traction at
  the stick edge and no cell exceeds mu p.  The longitudinal slip of spin, ``-phi y``, is the strip's own
  longitudinal creepage, so the march takes it with ``L1`` and the strip's stiffening ``f(y)`` (as the stick zones
  take it with ``f(y) r E_x``), not with FASTSIM's ``L3``: ``q_x(x - dx) = q_x(x) + dx f(y) (xi - r' phi y) / L1``,
  ``q_y(x - dx) = q_y(x) + dx (eta / L2 + phi x_m / L3)``, where ``r' = 1 + (r - 1) / (1 + |psi| / R)`` is the stick
  zones' ``r`` at small spin and tends to 1, the rigid slip itself, where spin drives the slip.  The flexibilities are
  Vollebregt & Voltr's blended ones (:func:`.fastsim.blended_flexibilities`) times a factor that falls with the
  scaled spin ``|psi|`` (:func:`march_flexibilities`, calibrated with R): with Kalker's flexibilities the march's
  traction lags too far behind the rigid slip once spin drives the slip.

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

Over y the strip forces are summed by Gauss-Legendre in theta, ``y = b sin(theta)`` (``strips`` nodes), with spin
split at the turning line of the longitudinal rigid slip where it lies within the ellipse (:meth:`StripStack.split`);
``Mz = int (x q_y - y q_x)``.
Velocity-dependent friction (``falling="march"``, with or without spin): the stick zones and the closed form are
those of the static coefficient mu(0); each cell of a slip zone carries ``mu(V sigma) p`` at its own slip sigma, along
the march's traction (with spin) or ``(kappa, lambda)``.  The slip is the strip's own in its 2D half-plane, the rigid
slip less the strain of the traction (:func:`elastic_slips`: Carter's closed form for the closed form's traction, the
cells' Hilbert transform for the march's departure from it), not the simplified theory's, whose slip follows the
elliptic bound's growth and spreads towards the trailing edge; each cell solves ``sigma = S - D mu(V sigma)`` (S the
rigid slip along the traction, ``D = (S - s) / mu(0)`` the elastic slip per unit coefficient of the first march's
half-plane slip s; :func:`~.common.slips_at`).  ``falling="polynomial"`` (without spin): each strip is the 2D problem
``N' = pi a(y) p0(y) / 2``, ``R = E a / (2 p0)``, ``E* = E`` with ``E = f(y) E_x`` and the creep
``sqrt(X^2 + Y^2) 2 mu p0 / (E a)`` along ``(X, Y)``, solved by the project's polynomial method
(:func:`rollcontact.solve`, one call per strip; the cross influence, a fixed point over the 2D solves, is not
applied): the march's reference on each strip, 20 to 30 times slower.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from rollcontact.core.checks import check_real
from rollcontact.core.materials import Material
from rollcontact.core.method import AccuracyModel, MethodSpec
from rollcontact.elliptic.creep_coefficients import aspect_ratio_range, creepage_coefficients
from rollcontact.elliptic.methods.common import (
    by_scene,
    coefficients,
    falling_drop,
    friction_groups,
    friction_kernel,
    linear_ratio,
    march,
    march_slips,
    modelled_cost,
    no_load,
    outside_table,
    poisson_excess,
    slips_at,
)
from rollcontact.elliptic.methods.fastsim import blended
from rollcontact.elliptic.result import EllipticResult, TractionField
from rollcontact.line.dispatch import solve as solve_2d
from rollcontact.line.scene import Scene

DEFAULT_STRIPS = 24
DEFAULT_STEPS = 20
TINY = 1e-300

SPLIT_LEAST = 4
"""Least strips on either side of a scene's turning line (:meth:`StripStack.split`); fewer than twice as many strips
are not split."""


@lru_cache(maxsize=16)
def gauss(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nodes t, weights on [-1, 1] and ``sqrt(1 - t^2)`` for integrands with ``sqrt(1 - t^2)`` ends (cached per count,
    read-only): Gauss-Legendre in theta with ``t = sin(theta)``, so that ``a(y)`` and ``a(y)^2`` integrate alike to
    spectral accuracy."""
    u, w = np.polynomial.legendre.leggauss(n)
    theta = 0.5 * math.pi * u
    nodes = np.sin(theta)
    return frozen(nodes), frozen(0.5 * math.pi * np.cos(theta) * w), frozen(np.sqrt(1.0 - nodes**2))


@lru_cache(maxsize=16)
def split_rules(n: int) -> np.ndarray:
    """The rules of n strips split at theta* (:meth:`StripStack.split`), for every count ``left`` of the left part:
    ``rules[:, left]`` holds ``(A, B, C, D)`` ``(4, n)`` such that the nodes are ``theta = A theta* + B`` and their
    weights in theta ``C + D theta*``: Gauss-Legendre over ``[-pi/2, theta*]`` (``left`` nodes) and over
    ``[theta*, pi/2]`` (the others) (cached per count, read-only)."""
    rules = np.zeros((4, n + 1, n))
    quarter = 0.25 * math.pi
    for left in range(1, n):
        for part, (u, w) in enumerate(np.polynomial.legendre.leggauss(k) for k in (left, n - left)):
            span = slice(0, left) if part == 0 else slice(left, n)
            if part == 0:  # theta = (theta* - pi/2)/2 + (theta* + pi/2)/2 u, weight (theta* + pi/2)/2 w
                rules[:, left, span] = (0.5 * (1.0 + u), quarter * (u - 1.0), quarter * w, 0.5 * w)
            else:  # theta = (theta* + pi/2)/2 + (pi/2 - theta*)/2 u, weight (pi/2 - theta*)/2 w
                rules[:, left, span] = (0.5 * (1.0 - u), quarter * (1.0 + u), quarter * w, -0.5 * w)
    return frozen(rules)


def frozen(array: np.ndarray) -> np.ndarray:
    """``array``, made read-only (a cached array is shared by every call)."""
    array.flags.writeable = False
    return array


@lru_cache(maxsize=1024)
def ratio_constants(ratio: float, poisson_ratio: float, strips: int) -> tuple[tuple[float, ...], np.ndarray]:
    """What a scene's strips take from its a/b and nu alone, cached by their exact values (a vehicle's contacts keep
    their curvatures from step to step): ``(C11, C22, C23, C33, A_x0 + A_x1 ln(a/b), A_y0 + A_y1 ln(a/b), P)``
    (:func:`march_flexibilities`) and the shape ``(1 - t^2)^(-gamma/2)`` of :func:`stiffening` at the strips' nodes
    (read-only).  A ValueError for a/b or nu outside the coefficient table."""
    c = creepage_coefficients(ratio, poisson_ratio)
    nodes = gauss(strips)[0]
    gamma = ratio / (ratio + STIFFENING_SCALE)
    x0, x1, y0, y1, scale, power, *_ = SPIN_FLEXIBILITY
    log_ratio = math.log(ratio)
    return ((c.c11, c.c22, c.c23, c.c33, x0 + x1 * log_ratio, y0 + y1 * log_ratio, scale * (1.0 + ratio) ** power),
            frozen((1.0 - nodes * nodes) ** (-0.5 * gamma)))


def stiffening(shape: np.ndarray, load_weights: np.ndarray) -> np.ndarray:
    """The gain K ``(n, 1)`` of each scene's strips' modulus factor ``f(y) = K (1 - y^2/b^2)^(-gamma/2)`` [1] (rows
    ``(n, S)``), ``gamma = (a/b) / (a/b + s)`` with ``s`` = :data:`STIFFENING_SCALE` (``shape``: the power at the
    strips' nodes, :func:`ratio_constants` or :meth:`StripStack.split`), such that
    ``sum_j w_j a(y_j) f_j = sum_j w_j a(y_j)`` (``load_weights``: the strips' weights times ``a(y)``, each strip's
    share of the linear force ``(pi/2) f(y) E_x a(y)`` per unit creepage), so that the strips keep Kalker's C11 and
    C22.  A short strip has neighbours of similar traction over a width comparable to its length, so the half-space
    answers it more stiffly than the 2D half-plane does; the effect grows with a/b and vanishes in the strip limit
    a/b -> 0, where the strips are Carter's problems."""
    return (np.sum(load_weights, axis=1) / dots(load_weights, shape))[:, None]


def dots(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``u_k . v_k`` of each row k of two ``(..., S)`` arrays: one vector dot product per row, as ``u_k @ v_k`` takes
    it."""
    return (u[..., None, :] @ v[..., :, None])[..., 0, 0]


@lru_cache(maxsize=1)
def _angles(n: int = 64) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    theta = (np.arange(n) + 0.5) * (2.0 * math.pi / n)
    cos2, sin2 = np.cos(theta) ** 2, np.sin(theta) ** 2
    return frozen(cos2), frozen(sin2), frozen(15.0 * cos2 * sin2 - 2.0)


def cross_coefficients(a, b, a2, b2, poisson_ratio, shear_modulus) -> np.ndarray:
    """``phi_c / Fy`` [1/(N m)] per scene (arrays ``(n, 1)``: the semi-axes a, b [m], their squares, nu and G [Pa]):
    the longitudinal creepage ``-phi_c y`` that a lateral traction of Hertz's shape,
    ``q_y = q0 sqrt(1 - x^2/a^2 - y^2/b^2)`` with ``q0 = 3 Fy / (2 pi a b)``, induces through the half-space's cross
    influence (``u_x`` of ``q_y``, proportional to nu).  That ``u_x`` is bilinear in the ellipse, ``u_x = K x y`` with
    (Hadamard's finite part of ``(nu / (pi G)) int q_y d^2/dx dy (X Y / r^3)``, both bodies)

        ``K = -(nu q0 / (2 G)) int_0^{2 pi} (15 cos^2 t sin^2 t - 2) sqrt(cos^2 t / a^2 + sin^2 t / b^2) dt``

    (the circle gives ``pi nu q0 / (8 G a)``, as Johnson's displacements of a Hertzian tangential traction on a circle
    do for two bodies: K. L. Johnson, Contact Mechanics, 1985), and the steady slip
    ``s_x = w_x + du_x/dx`` gains ``K y``: a longitudinal creepage ``-phi_c y``, ``phi_c = -K``.  Strip theory has no
    such coupling; with it the lateral force turns the traction of the strips off the y axis by a y-odd amount, which
    gives the moment ``-int y q_x`` that the exact theory finds with lateral creepage."""
    cos2, sin2, kernel = _angles()
    integral = 2.0 * math.pi * np.mean(kernel * np.sqrt(cos2 / a2 + sin2 / b2), axis=1, keepdims=True)
    q0_per_force = 3.0 / (2.0 * math.pi * a * b)
    return 0.5 * poisson_ratio * q0_per_force * integral / shear_modulus


def cross_coefficient(scene) -> float:
    """:func:`cross_coefficients` of one scene [1/(N m)]."""
    h = scene.hertz
    values = (h.a, h.b, h.a**2, h.b**2, scene.material.poisson_ratio, scene.shear_modulus)
    return float(cross_coefficients(*(np.array([[v]]) for v in values))[0, 0])


FALLING = ("march", "polynomial")
"""The falling-friction paths: the march's cells at their own slip's coefficient (spin and lateral creepage, the
default), or one 2D polynomial solve per strip (no spin; slower, for comparison)."""


def solve_strips(scene, *, strips: int = DEFAULT_STRIPS, steps: int = DEFAULT_STEPS, fields: bool = False,
                 falling: str = "march") -> EllipticResult:
    """Strip theory with FaStrip's slip directions (module docstring).

    Parameters
    ----------
    scene : EllipticScene
        The case (Coulomb or velocity-dependent friction).
    strips : int
        Strips across 2b (>= 2), at Gauss-Legendre nodes in theta.
    steps : int
        Cells along each strip where the tractions are summed (with spin) and given (``fields``); >= 2.
    fields : bool
        Return the tractions on the strips' cells (``result.fields``).  The forces do not depend on it: without spin
        they are the closed form's, which the cells' sums approach with the cells.
    falling : {"march", "polynomial"}
        Velocity-dependent friction by the march's cells at their own slip's coefficient (with or without spin), or
        by one 2D polynomial solve per strip (without spin).

    Returns
    -------
    EllipticResult
        ``info["stick_strips"]``: the share of the width whose strips have a stick zone; ``info["psi"]``: the
        scaled spin; with velocity-dependent friction ``info["steepness"]``, the largest ``-D V dmu/dv`` of the
        march's slipping cells (above 1 a cell's slip equation is not monotone; :func:`~.common.slips_at`).
    """
    if falling not in FALLING:
        raise ValueError(f"falling = {falling!r} is not one of {FALLING}")
    why = inapplicable(scene)
    if why is not None:
        raise ValueError(f"strips cannot solve this scene: {why}")
    strips = int(check_real("strips", strips, lower=2))
    steps = int(check_real("steps", steps, lower=2))
    if scene.normal_load == 0.0:
        return no_load(scene, "strips")
    if not scene.friction.is_constant:
        if falling == "polynomial":
            if scene.spin_creepage != 0.0:
                raise ValueError("strips with falling='polynomial' take no spin (the 2D kernel has one traction "
                                 "component); falling='march' does")
            return polynomial_strips(scene, StripStack((scene,), strips))
        return falling_strips((scene,), strips, steps, fields)[0]
    return stacked((scene,), strips, steps, fields)[0]


solve_strips.options = ("strips", "steps", "fields", "falling")


def solve_strips_many(scenes, *, strips: int = DEFAULT_STRIPS, steps: int = DEFAULT_STEPS, fields: bool = False
                      ) -> list[EllipticResult]:
    """:func:`solve_strips` of each scene (the same arguments), the loaded scenes with Coulomb friction at once and
    those of each velocity-dependent friction law at once: their strips are one :class:`StripStack`, whose stick
    zones, closed form, cross-influence fixed point and march are array operations over the scenes, each scene's
    numbers independent of the others (:func:`solve_strips` is this function of one scene).  A scene without load has
    no contact.

    Raises
    ------
    ValueError
        A scene the strips cannot solve (:func:`inapplicable`; the message names its index), or a count < 2.
    """
    low, high = aspect_ratio_range()
    for k, scene in enumerate(scenes):
        if not low <= scene.hertz.aspect_ratio <= high:
            raise ValueError(f"strips cannot solve scene {k}: {inapplicable(scene)}")
    strips = int(check_real("strips", strips, lower=2))
    steps = int(check_real("steps", steps, lower=2))
    if all(scene.normal_load != 0.0 and scene.friction.is_constant for scene in scenes):
        return stacked(scenes, strips, steps, fields)
    results = [no_load(scene, "strips") if scene.normal_load == 0.0 else None for scene in scenes]
    for group in friction_groups(scenes):
        solve = stacked if scenes[group[0]].friction.is_constant else falling_strips
        for k, result in zip(group, solve([scenes[k] for k in group], strips, steps, fields), strict=True):
            results[k] = result
    return results


def stacked(scenes, strips: int, steps: int, fields: bool) -> list[EllipticResult]:
    """:func:`solve_strips` of loaded scenes with Coulomb friction (checked), as one :class:`StripStack`."""
    stack = StripStack(scenes, strips, fields)
    phi_c, forces = np.zeros((len(scenes), 1)), None
    sticking = stack.stick()
    if stack.coupled.any():  # the lateral force's longitudinal creepage, by fixed point through the closed form
        forces = stack.closed_form(sticking)
        for _ in range(CROSS_ITERATIONS):
            phi_c = stack.couple(forces[1])
            sticking = stack.stick()
            forces = stack.closed_form(sticking)
    d, kappa, lam, partial = sticking
    field = (None,) * len(scenes)
    out = np.column_stack(stack.closed_form(sticking) if forces is None else forces)
    if fields or stack.spin.any():  # a scene with spin adds its march's departure from the closed form (all scenes
        # march together, each on its own numbers); fields come from the march whatever the forces
        departure, field = marched(stack, steps, d, kappa, lam, partial, phi_c, fields)
        out = out + departure if stack.spin.all() else np.where(stack.spin[:, None], out + departure, out)
    results = []
    for scene, spin, values, f, stick, psi, cross in zip(
            scenes, stack.spin.tolist(), out.tolist(), field, stick_shares(stack, partial),
            stack.psi[:, 0].tolist(), phi_c[:, 0].tolist(), strict=True):
        message = "strip theory, slip directions of the simplified theory" if spin else "strip theory (closed form)"
        results.append(EllipticResult.from_scene(scene, "strips", True, message, values, f,
                                                 {"stick_strips": stick, "psi": psi, "cross_spin": cross}))
    return results


def stick_shares(stack: StripStack, partial: np.ndarray) -> list[float]:
    """Each scene's share of its width [1] whose strips have a stick zone (the weights of those strips over 2b)."""
    return (dots(np.where(partial, stack.weights, 0.0), np.ones_like(stack.weights)) / (2.0 * stack.b[:, 0])).tolist()


class StripStack:
    """The strips of n loaded scenes (module docstring), stacked: each array ``(n, S)`` over the scenes and their S
    strips, each scalar of a scene a column ``(n, 1)``.  Every operation is elementwise or a sum over one scene's own
    values in one fixed order, so a scene's numbers are the same in any stack.  A scene's scalars are taken in plain
    floats, those that depend on a/b and nu alone from :func:`ratio_constants`.

    Attributes: ``rows`` (each scene's scalars, plain floats) and ``table`` (the same, an array ``(scalars, n)``);
    as columns ``a``, ``b``, ``p0`` [m, m, Pa], ``mu``, ``limit`` (mu Fn [N]), the creepages ``xi``, ``eta``, ``phi``,
    ``flexibilities`` (the march's, :func:`march_flexibilities`; with ``fields`` of every scene, else of those with
    spin, 1 elsewhere); per strip ``y`` [m], ``weights`` [m] (Gauss over y), ``half`` (``a(y)`` [m]), ``factor``
    (:func:`stiffening`), ``scale`` (the slip length per unit modulus and creepage [1/Pa]), the scaled rigid slips
    ``X``, ``Y`` (``rigid_x``: ``xi - r phi y``), per scene ``moment_ratio`` (r, which keeps C33) and ``march_ratio``
    (the march's r', module docstring), ``psi`` (the scaled spin, unstiffened: it keeps C23), ``m``
    (``mu p = m sqrt(a(y)^2 - x^2)``), ``modulus_x`` (E_x [Pa]), ``cross`` (:func:`cross_coefficients`, 0 with spin)
    and ``spin`` (phi != 0, per scene)."""

    def __init__(self, scenes, strips: int, fields: bool = False):
        nodes, weights, root = gauss(strips)
        rows, shapes, powers = [], [], []
        for scene in scenes:
            h = scene.hertz
            powers.append(h.aspect_ratio / (h.aspect_ratio + STIFFENING_SCALE))
            material = scene.material
            (c11, c22, c23, c33, k_x, k_y, spin_scale), shape = ratio_constants(h.aspect_ratio,
                                                                                material.poisson_ratio, strips)
            a, b, p0, mu, load, g = h.a, h.b, h.max_pressure, scene.friction_coefficient, scene.normal_load, \
                scene.shear_modulus
            xi, eta, phi = scene.creepages
            two_mu_p0 = 2.0 * mu * p0
            psi = phi * (3.0 * g * c23 * math.sqrt(b / a) / math.pi) * a / two_mu_p0  # E_phi (module docstring)
            flexibilities = march_flexibilities(a, b, g, scene.friction, scene.rolling_speed, load, c11, c22, c23, xi,
                                                eta, phi, psi, k_x, k_y, spin_scale) \
                if phi != 0.0 or fields else (1.0, 1.0, 1.0)
            rows.append((a, b, p0, mu, mu * load, xi, eta, phi, 4.0 * g * c11 / math.pi**2, 4.0 * g * c22 / math.pi**2,
                         psi, mu * p0 / a, two_mu_p0, *flexibilities, g, material.poisson_ratio,
                         *((1.0, 1.0) if phi != 0.0 else (a**2, b**2)), g * (a * b) ** 2 * c33))
            shapes.append(shape)
        self.rows = rows  # each scene's scalars, plain floats
        self.table = np.array(rows).T  # (scalars, n)
        (a, b, self.p0, self.mu, self.limit, xi, self.eta, phi, self.modulus_x, self.modulus_y, self.psi, self.m,
         two_mu_p0, l1, l2, l3, g, nu, a2, b2, moment33) = self.table[:, :, None]
        self.a, self.b, self.xi, self.phi, self.flexibilities = a, b, xi, phi, (l1, l2, l3)
        self.y = b * nodes
        self.weights = b * weights
        self.half = a * root
        shapes = np.array(shapes)
        self.factor = shapes * stiffening(shapes, self.weights * self.half)
        self.moment_ratio = moment33 / (0.5 * math.pi * self.modulus_x * dots(self.weights * self.half,
                                                                               self.factor * self.y**2)[:, None])
        self.march_ratio = 1.0 + (self.moment_ratio - 1.0) / (1.0 + np.abs(self.psi) / SPIN_FLEXIBILITY[6])
        self.spin = phi[:, 0] != 0.0
        if self.spin.any() and strips >= 2 * SPLIT_LEAST:
            self.split(strips, np.array(powers)[:, None], moment33)
        self.half2 = self.half**2
        self.scale = self.factor * a / two_mu_p0
        self.rigid_x = xi - self.moment_ratio * phi * self.y
        self.X = self.rigid_x * self.modulus_x * self.scale
        self.Y = self.eta * self.modulus_y * self.scale
        self.usual = all(abs(row[10]) < 1.0 and row[10] * row[6] >= 0.0 for row in rows)
        """Whether every scene has ``|psi| < 1`` and its lateral creepage not against the spin (``psi eta >= 0``)."""
        self.deep = any(abs(row[10]) >= 1.0 for row in rows)
        """Whether a scene has ``|psi| >= 1``."""
        self.share = None
        """Per strip, the share of its stick zone's traction the march keeps (:meth:`stick`, with ``deep``; else
        None: all of it)."""
        self.cross = np.zeros_like(a) if self.spin.all() else \
            np.where(self.spin[:, None], 0.0, cross_coefficients(a, b, a2, b2, nu, g))
        self.coupled = self.cross[:, 0] != 0.0

    def split(self, strips: int, gamma: np.ndarray, moment33: np.ndarray) -> None:
        """Place the strips of each scene whose turning line lies within the ellipse on both sides of it: Gauss-Legendre
        in theta (``y = b sin(theta)``) over ``[-pi/2, theta*]`` and ``[theta*, pi/2]``, ``y* = b sin(theta*)``, the
        strips shared in proportion to the two ranges (at least :data:`SPLIT_LEAST` a side); the modulus factors'
        gain (:func:`stiffening`), the moment ratio and the march's ratio on those strips.  The other scenes keep
        the strips across the whole ellipse.

        With spin the longitudinal rigid slip ``xi - r phi y`` changes sign on the turning line ``y* = xi / (r phi)``
        (taken midway between :attr:`moment_ratio`'s line, where the stick zones' slip turns, and
        :attr:`march_ratio`'s, where the march's does).  Across it a strip's longitudinal traction turns from one
        saturation to the other over a layer that narrows as the spin grows, below the strips' spacing past
        ``|psi| = 1``, where with the lateral creepage against the spin the stick zones also lie only in a band around
        it (:meth:`stick`).  Strips across the whole ellipse alias that layer, the forces jumping by up to
        0.04 mu Fn as it moves across them (a/b = 0.2, ``benchmarks/calibrate_falling_spin.py``); the split rule
        has strips clustered on both sides of the line, and integrands smooth on each side keep their spectral
        accuracy (the linear limit is Kalker's)."""
        turns, lefts, within = [], [], []
        for k, (row, r, r_march) in enumerate(zip(self.rows, self.moment_ratio[:, 0].tolist(),
                                                  self.march_ratio[:, 0].tolist(), strict=True)):
            b, xi, phi = row[1], row[5], row[7]
            if phi == 0.0:
                continue
            line = 0.5 * xi * (1.0 / (r * phi) + 1.0 / (r_march * phi))
            if abs(line) < b:
                turn = math.asin(line / b)
                within.append(k)
                turns.append(turn)
                lefts.append(min(max(round(strips * (turn / math.pi + 0.5)), SPLIT_LEAST), strips - SPLIT_LEAST))
        if not within:
            return
        every = len(within) == len(self.rows)
        inside = slice(None) if every else np.array(within)
        turn = np.array(turns)[:, None]
        A, B, C, D = split_rules(strips)[:, lefts]
        theta = A * turn
        theta += B
        t = np.sin(theta)
        root = np.sqrt(1.0 - t * t)
        bk = self.b[inside]
        y = bk * t
        weights = bk * (np.cos(theta) * (C + D * turn))
        half = self.a[inside] * root
        shapes = (1.0 - t * t) ** (-0.5 * gamma[inside])
        factor = shapes * stiffening(shapes, weights * half)
        ratio = moment33[inside] / (0.5 * math.pi * self.modulus_x[inside] * dots(weights * half,
                                                                                   factor * y**2)[:, None])
        if every:
            self.y, self.weights, self.half, self.factor, self.moment_ratio = y, weights, half, factor, ratio
        else:
            for name, value in (("y", y), ("weights", weights), ("half", half), ("factor", factor),
                                ("moment_ratio", ratio)):
                merged = getattr(self, name).copy()
                merged[inside] = value
                setattr(self, name, merged)
        self.march_ratio = 1.0 + (self.moment_ratio - 1.0) / (1.0 + np.abs(self.psi) / SPIN_FLEXIBILITY[6])

    def couple(self, lateral_force: np.ndarray) -> np.ndarray:
        """Add the longitudinal creepage ``-phi_c y`` that a lateral force [N] (per scene) induces
        (:func:`cross_coefficients`) to the strips' X of the coupled scenes; returns ``phi_c`` [1/m] ``(n, 1)`` (0
        where a scene has no cross influence, whose X is left as it is)."""
        phi_c = self.cross * lateral_force[:, None]
        coupled_x = (self.rigid_x - phi_c * self.y) * self.modulus_x * self.scale
        if self.coupled.all():
            self.X = coupled_x
            return phi_c
        self.X = np.where(self.coupled[:, None], coupled_x, self.X)
        return np.where(self.coupled[:, None], phi_c, 0.0)

    def stick(self):
        """``(d, kappa, lambda, partial)`` per strip: the slip zone's half-length, the traction direction at the stick
        edge, and whether the strip sticks anywhere (``d < a(y)`` with an admissible stick traction; module
        docstring)."""
        psi, X, Y = self.psi, self.X, self.Y
        room = 1.0 - psi * psi
        if self.usual:
            d = (psi * Y + np.sqrt(Y * Y + room * X * X)) / room
        elif len(self.rows) == 1:  # one scene: its spin and lateral creepage decide which root, as below
            psi_1, eta_1 = self.rows[0][10], self.rows[0][6]
            if psi_1 * eta_1 < 0.0:
                square = Y * Y + room * X * X
                d = (X * X + Y * Y) / (np.sqrt(np.maximum(square, 0.0)) - psi * Y)
                if psi_1 * psi_1 > 1.0:
                    d = np.where(square >= 0.0, d, np.inf)
            else:  # |psi| >= 1 with the lateral creepage not against the spin: no stick zone
                d = np.full_like(X, np.inf)
        elif not self.deep:  # |psi| < 1 in every scene: each strip's root as its scene alone takes it
            turned = psi * Y
            root = np.sqrt(Y * Y + room * X * X)
            with np.errstate(divide="ignore", invalid="ignore"):  # the root not taken may be 0 / 0
                d = np.where(turned < 0.0, (X * X + Y * Y) / (root - turned), (turned + root) / room)
        else:
            turned = psi * Y
            square = Y * Y + room * X * X
            real = square >= 0.0
            root = np.sqrt(np.where(real, square, 0.0))
            with np.errstate(divide="ignore", invalid="ignore"):
                alike = (turned + root) / np.where(room > 0.0, room, 1.0)
                opposed = (X * X + Y * Y) / (root - turned)  # psi Y < 0: the same root without cancellation
            d = np.where(turned < 0.0, np.where(real, opposed, np.inf), np.where(room > 0.0, alike, np.inf))
        partial = d < self.half
        edge = partial & (d > 0.0)
        safe = np.where(edge, d, 1.0)
        kappa = np.where(edge, X / safe, 0.0)
        lam = np.where(edge, psi + Y / safe, 0.0)
        self.share = None
        if self.deep and partial.any():  # |psi| >= 1 somewhere: stick zones fade with their excess over mu p
            along = 1.0 - lam * psi
            rest = np.sqrt(np.where(partial, (self.half - d) / self.half, 0.0))
            with np.errstate(divide="ignore", invalid="ignore"):
                excess = np.where(room > 0.0, 0.0, np.where(along > 0.0, rest * (2.0 * along - room) / (2.0 * along),
                                                            np.inf))
            partial &= excess < STICK_FADE
            self.share = np.clip((STICK_FADE - excess) / (STICK_FADE - 1.0), 0.0, 1.0)
        norm = np.hypot(X, Y)
        slipping = norm > 0.0
        safe_norm = np.where(slipping, norm, 1.0)
        kappa = np.where(partial, kappa, np.where(slipping, X / safe_norm, 0.0))  # full slip without spin: along (X, Y)
        lam = np.where(partial, lam, np.where(slipping, Y / safe_norm, 0.0))
        return np.where(partial, d, self.half), kappa, lam, partial

    def closed_form(self, stick):
        """Forces without spin's lateral part (psi = 0 or d, kappa, lambda as given) from :meth:`stick`'s
        ``(d, kappa, lambda, partial)``: ``(Fx, Fy, Mz)`` [N, N, N m], arrays over the scenes.  Per strip and unit
        width ``Fx = (pi m / 2) kappa (a(y)^2 - a*^2)``, ``Fy = (pi m / 2) (lambda a(y)^2 - (lambda - psi) a*^2)``,
        ``Mz = -(pi m / 2) (lambda - psi) d a*^2 - y Fx`` (module docstring), summed with the strips' weights."""
        d, kappa, lam, partial = stick
        rest = np.where(partial, self.half - d, 0.0)  # a*
        rest2 = rest**2
        turned = lam - self.psi
        area = 0.5 * math.pi * self.m
        fx = area * kappa * (self.half2 - rest2)
        fy = area * (lam * self.half2 - turned * rest2)
        mz = -area * turned * d * rest2 - self.y * fx
        return dots(self.weights, fx), dots(self.weights, fy), dots(self.weights, mz)


def march_coefficient(law, speed: float, a: float, b: float, xi: float, eta: float, phi: float) -> float:
    """The friction coefficient [1] the march's flexibilities are taken at (:func:`march_flexibilities`): mu(0) with
    constant friction; with velocity-dependent friction the law's coefficient at the rigid slip velocity's root mean
    square over Hertz's pressure on the ellipse of semi-axes a, b [m],

        ``mu(V sqrt(xi^2 + eta^2 + phi^2 (a^2 + b^2) / 5))``

    (V = ``speed`` [m/s]; the pressure's moments ``int x^2 p dA / int p dA = a^2/5``, ``b^2/5``).  The flexibilities'
    blend and their spin factors measure the creepage and the spin against the bound the march's traction saturates
    at, which falling friction lowers from mu(0) towards the slip's coefficient; taken at mu(0) on a steep law, the
    march's traction lags too far behind the rigid slip of spin and overestimates the lateral force of lateral
    creepage against the spin (``benchmarks/calibrate_falling_spin.py``, table A, measures the level's errors)."""
    if law.is_constant:
        return law.static_coefficient
    return float(law.coefficient(speed * math.sqrt(xi * xi + eta * eta + phi * phi * (a * a + b * b) / 5.0)))


def march_flexibilities(a: float, b: float, g: float, friction, speed: float, normal_load: float, c11: float,
                        c22: float, c23: float, xi: float, eta: float, phi: float, psi: float, k_x0: float,
                        k_y0: float, spin_scale: float) -> tuple[float, float, float]:
    """The march's ``(L1, L2, L3)`` [m/Pa] of a scene (its semi-axes a, b [m], G [Pa], friction law and rolling speed
    [m/s], Fn [N], C11, C22, C23, the creepages, the scaled spin psi at mu(0) and, from :func:`ratio_constants`,
    ``A_x0 + A_x1 ln(a/b)``, ``A_y0 + A_y1 ln(a/b)`` and P), at the coefficient mu of :func:`march_coefficient`, with
    the scaled spin ``psi mu(0) / mu``: Vollebregt & Voltr's blended flexibilities
    (:func:`.fastsim.blended_flexibilities`) times ``k_x`` (L1) and ``k_y`` (L2, L3),

        ``k = (1 + (k_0 - 1) |psi| / (|psi| + Q)) / (1 + |psi| / P)``,  ``k_0,x = A_x0 + A_x1 ln(a/b)``,
        ``k_0,y = A_y0 + A_y1 ln(a/b)``,  ``P = P_1 (1 + a/b)^m``

    (:data:`SPIN_FLEXIBILITY`: calibrated, not derived; Q its last).  At small spin the factors are 1: Kalker's
    flexibilities, chosen for the linear forces, hold where the stick zones carry the traction.  In the slip zones the
    march's traction lags behind the rigid slip by the flexibility times the rate at which the traction turns; that lag
    is too large once spin drives the slip (the lateral force of spin is overestimated, most at a/b 0.5..2), so the
    factors fall with the scaled spin ``|psi|``; their a/b dependence ``k_0`` follows the strips' own error, which
    changes sign between the strip limit a/b -> 0 and long strips (a/b = 5)."""
    mu = march_coefficient(friction, speed, a, b, xi, eta, phi)
    if not friction.is_constant:
        psi = psi * friction.static_coefficient / mu
    l1, l2, l3 = blended(a, b, g, mu, normal_load, c11, c22, c23, xi, eta, phi)
    spin = abs(psi)
    fall = 1.0 + spin / spin_scale
    rise = spin / (spin + SPIN_FLEXIBILITY[7])
    k_x = (1.0 + (k_x0 - 1.0) * rise) / fall
    k_y = (1.0 + (k_y0 - 1.0) * rise) / fall
    return k_x * l1, k_y * l2, k_y * l3


@lru_cache(maxsize=16)
def cells(steps: int) -> np.ndarray:
    """The cell centres' ``x / a(y)`` from the leading edge, ``1 - (2 i + 1) / steps`` ``(steps, 1)`` (read-only)."""
    return frozen(1.0 - (2.0 * np.arange(steps)[:, None] + 1.0) / steps)


@lru_cache(maxsize=16)
def hilbert(steps: int) -> np.ndarray:
    """The half-plane's strain at the cell centres of a strip of ``steps`` cells per unit traction on each cell
    ``(steps, steps)`` (read-only): ``H_ij = (1/pi) ln|(x_i - x_j + h/2) / (x_i - x_j - h/2)|``, the principal
    value ``(1/pi) PV int_cell_j dt / (x_i - t)`` in the cells' coordinates ``x / a(y)`` (h = 2/steps; free of the
    strip's length, 0 on the diagonal)."""
    x = cells(steps)[:, 0]
    offset = x[:, None] - x[None, :]
    half = 1.0 / steps
    return frozen(np.log(np.abs((offset + half) / (offset - half))) / math.pi)


def elastic_slips(x, half, d, kappa, lam, psi, X, Y, partial, in_stick, m, compliance, departure=None):
    """Each cell's slip speed [1] (slip velocity over V) in the strip's 2D half-plane, outside the stick zones
    (docs/physics.md, "Strips"): ``s = 2 C (m s_c - H dq)`` per component, ``C = 1/(f E)`` its compliance
    (``compliance``: along x and along y, per strip), ``m`` the cells' ``mu p / sqrt(a(y)^2 - x^2)``.  ``s_c`` is the
    closed form's slip in units of the slip length, the rigid slip less the strain of its traction (Carter's, the
    Hilbert transform of a semi-ellipse being linear): ``(kappa, lambda - psi) sqrt((x - d)^2 - a*^2)`` in the slip
    zone of a strip that sticks, ``(X - kappa x, Y + (psi - lambda) x)`` on a strip in full slip; ``H dq`` is the
    strain of the cells' departure ``dq`` ``(2, steps, S)`` [Pa] from the closed form's traction (:func:`hilbert`;
    None: none), each cell's sum over its strip's cells in their order (``einsum`` without BLAS: a strip's numbers are
    its own whatever the strips beside it).  Arrays ``(steps, S)`` and per strip ``(S,)``; 0 in the stick zones."""
    root = np.sqrt(np.maximum((x - d) ** 2 - (half - d) ** 2, 0.0))
    slip_x = m * np.where(partial, np.where(in_stick, 0.0, kappa * root), X - kappa * x)
    slip_y = m * np.where(partial, np.where(in_stick, 0.0, (lam - psi) * root), Y + (psi - lam) * x)
    if departure is not None:
        strain = np.einsum("ij,cjk->cik", hilbert(x.shape[0]), departure)
        slip_x -= strain[0]
        slip_y -= strain[1]
    return 2.0 * np.where(in_stick, 0.0, np.hypot(compliance[0] * slip_x, compliance[1] * slip_y))


def marched(stack: StripStack, steps: int, d, kappa, lam, partial, phi_c, fields: bool):
    """The strips of the stack's scenes on ``steps`` cells each: strip theory's traction in the stick zones, ``mu p``
    along the direction of the simplified theory's traction (a FASTSIM march with the strips' flexibilities, module
    docstring) in the slip zones.  Returns the forces ``(n, 3)`` and, with ``fields``, the traction fields (else
    None each).

    The cells are arrays ``(steps, n S)``: the scenes' strips side by side along the last axis (each scene's scalars
    repeated over its strips), so that each operation runs over every strip of every scene at once."""
    n, count = stack.y.shape
    columns = n * count
    if n == 1:  # one scene: its scalars as plain floats, which numpy broadcasts alike
        a, b, p0, mu, _, xi, eta, phi, _, _, psi, m, _, l1, l2, l3, *_ = stack.rows[0]
        phi_x = float(stack.march_ratio[0, 0]) * phi + float(phi_c[0, 0])
    else:  # each scene's scalars over its strips
        xi, eta, phi_x, l1, l2, l3, p0, a, b, mu, m, psi, phi = np.repeat(np.hstack(
            (stack.xi, stack.eta, stack.march_ratio * stack.phi + phi_c, *stack.flexibilities, stack.p0, stack.a,
             stack.b, stack.mu, stack.m, stack.psi, stack.phi)).T, count, axis=1)
    y, half, weights, factor, d, kappa, lam, partial = (v.reshape(columns) for v in (
        stack.y, stack.half, stack.weights, stack.factor, d, kappa, lam, partial))
    dx = 2.0 * half / steps
    x = half * cells(steps)  # cell centres from the leading edge
    bound = mu * (p0 * np.sqrt(np.maximum(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0)))  # mu p (Hertz)
    scaling = np.repeat(stack.limit[:, 0] / by_scene(bound * (dx * weights), n), count)  # the cells carry mu Fn
    bound *= scaling
    step = np.empty((steps, 2, columns))  # the march's increment from cell i to i + 1 (midpoint x_i - dx/2)
    step[:, 0] = dx * (xi - phi_x * y) / l1 * factor  # the strip's stiffening, as in its stick zone
    np.multiply(dx, eta / l2 + phi * (x - 0.5 * dx) / l3, out=step[:, 1])
    trial = np.empty((steps, 2, columns))
    trial[0, 0] = 0.5 * step[0, 0]
    trial[0, 1] = 0.5 * dx * (eta / l2 + phi * (half - 0.25 * dx) / l3)
    size = np.empty((steps, columns))  # max(|t|, TINY) of each cell's trial traction
    ratio = np.empty(columns)
    with np.errstate(over="ignore"):  # an empty strip (t = 0) has mu p / TINY = inf, whose min with 1 is 1
        for t, t_x, t_y, following, increment, limit, length in zip(trial[:-1], trial[:-1, 0], trial[:-1, 1],
                                                                    trial[1:], step, bound, size, strict=False):
            np.hypot(t_x, t_y, out=length)  # t <- t min(1, mu p / |t|) + increment, over scenes and strips at once
            np.maximum(length, TINY, out=length)
            np.divide(limit, length, out=ratio)
            np.minimum(1.0, ratio, out=ratio)
            np.multiply(t, ratio, out=following)
            np.add(following, increment, out=following)
    np.maximum(np.hypot(trial[-1, 0], trial[-1, 1]), TINY, out=size[-1])
    np.divide(trial, size[:, None], out=trial)  # mu p along the march's traction: bound (t / |t|), in place
    np.multiply(bound[:, None], trial, out=trial)
    qx, qy = trial[:, 0], trial[:, 1]
    if not stack.spin.all():  # without spin the slip direction is uniform along the strip
        uniform = ~stack.spin.repeat(count)
        qx = np.where(uniform, bound * kappa, qx)
        qy = np.where(uniform, bound * lam, qy)
    ux, uy = bound * kappa, bound * lam  # the closed form's traction: the slip direction uniform along the strip
    if partial.any():  # the stick zone's traction (module docstring), on the strips that stick (when they are few)
        gather = columns > GATHER
        sticking = np.flatnonzero(partial) if gather else slice(None)
        x_s, half_s, d_s, kappa_s, lam_s = x[:, sticking], half[sticking], d[sticking], kappa[sticking], lam[sticking]
        in_s = x_s > 2.0 * d_s - half_s  # the stick zone [2 d - a(y), a(y)] of a strip that sticks
        if not gather:
            in_s &= partial
        m_s, psi_s = (m, psi) if n == 1 else (m[sticking], psi[sticking])
        m_s = m_s * scaling[sticking]  # the cells' scale of mu p, as the bound's: continuous at the stick edge
        rest = half_s - d_s
        full = np.sqrt(np.maximum(half_s**2 - x_s * x_s, 0.0))
        inner = np.sqrt(np.maximum(rest**2 - (x_s - d_s) ** 2, 0.0))
        stick_x, stick_y = m_s * kappa_s * (full - inner), m_s * (lam_s * full - (lam_s - psi_s) * inner)
        share = None if stack.share is None else stack.share.reshape(columns)[sticking]
        place((ux, uy), (stick_x, stick_y), sticking if gather else None, in_s)
        if share is not None and (share < 1.0).any():  # past |psi| = 1: within mu p, faded into the slip traction
            fading = share < 1.0
            within = np.minimum(1.0, bound[:, sticking] / np.maximum(np.hypot(stick_x, stick_y), TINY))
            stick_x = np.where(fading, share * within * stick_x + (1.0 - share) * qx[:, sticking], stick_x)
            stick_y = np.where(fading, share * within * stick_y + (1.0 - share) * qy[:, sticking], stick_y)
        place((qx, qy), (stick_x, stick_y), sticking if gather else None, in_s)
    weight = weights * dx  # Gauss over y, midpoint cells along x
    products = np.empty((3, steps, columns))
    np.subtract(qx, ux, out=ux)  # the march's departure from the closed form's traction
    np.subtract(qy, uy, out=uy)
    np.multiply(ux, weight, out=products[0])
    np.multiply(uy, weight, out=products[1])
    np.multiply(x, uy, out=products[2])
    np.subtract(products[2], y * ux, out=products[2])
    np.multiply(products[2], weight, out=products[2])
    departure = by_scene(products, n)
    if not fields:
        return departure.T, (None,) * n
    in_stick = partial & (x > 2.0 * d - half)
    return departure.T, traction_fields(stack, steps, x, y, bound / mu, qx, qy, in_stick)


def traction_fields(stack: StripStack, steps: int, *cells) -> tuple[TractionField, ...]:
    """Each scene's :class:`TractionField` from the cells' ``x, y, pressure, qx, qy, stick`` (arrays broadcast to
    ``(steps, n S)``)."""
    n, count = stack.y.shape
    x, y, pressure, qx, qy, in_stick = (np.broadcast_to(v, (steps, n * count)).reshape(steps, n, count)
                                        for v in cells)
    return tuple(TractionField(*(v[:, k].T.copy() for v in (x, y, pressure, qx, qy, in_stick))) for k in range(n))


def place(targets, values, columns, where) -> None:
    """Write ``values`` (the stick zones' traction components) into ``targets`` (cell arrays ``(steps, columns)``) at
    the cells ``where`` holds, in place: on the gathered ``columns`` (indices), or on all columns (None)."""
    for target, value in zip(targets, values, strict=True):
        if columns is None:
            np.copyto(target, value, where=where)
        else:
            target[:, columns] = np.where(where, value, target[:, columns])


GATHER = 96
"""Strips (all scenes') from which the march computes the stick zones' traction on the strips that stick alone."""


def falling_strips(scenes, strips: int, steps: int, fields: bool) -> list[EllipticResult]:
    """Velocity-dependent friction, with or without spin (``falling="march"``, module docstring), of loaded scenes of
    one friction law stacked (:class:`StripStack`): the strips' stick zones and closed form at the static coefficient,
    the march's cells at the coefficient of their own slip (:func:`falling_marched`).  Each scene's numbers are those
    it has alone."""
    stack = StripStack(scenes, strips, fields=True)  # the march's flexibilities, also without spin
    phi_c, forces = np.zeros((len(scenes), 1)), None
    sticking = stack.stick()
    if stack.coupled.any():  # the lateral force's longitudinal creepage, as the Coulomb strips take it
        forces = stack.closed_form(sticking)
        for _ in range(CROSS_ITERATIONS):
            phi_c = stack.couple(forces[1])
            sticking = stack.stick()
            forces = stack.closed_form(sticking)
    closed = np.column_stack(stack.closed_form(sticking) if forces is None else forces)
    speeds = np.array([scene.rolling_speed for scene in scenes])
    departure, field, steepness = falling_marched(stack, steps, sticking, phi_c, scenes[0].friction, speeds, fields)
    results = []
    for scene, values, f, stick, psi, cross, steep in zip(
            scenes, (closed + departure).tolist(), field, stick_shares(stack, sticking[3]),
            stack.psi[:, 0].tolist(), phi_c[:, 0].tolist(), steepness.tolist(), strict=True):
        info = {"stick_strips": stick, "psi": psi, "cross_spin": cross, "steepness": steep}
        results.append(EllipticResult.from_scene(scene, "strips", True, "strip theory, falling friction on the "
                                                 "march's cells", tuple(values), f, info))
    return results


FALLING_PASSES = 2
"""Marches of the falling-friction path with spin: the first at the static coefficient gives each cell's slip and
coefficient (and the elastic slip per unit coefficient of its half-plane slip), the second marches with those
coefficients' bound (the directions of the traction follow the falling friction) and solves the slips again along
them (without spin the directions are uniform and one march is kept).  A third changes the forces by little
(``benchmarks/calibrate_falling_spin.py``, table "Passes")."""


def falling_marched(stack: StripStack, steps: int, sticking, phi_c, law, speeds: np.ndarray, fields: bool):
    """The departures ``(n, 3)`` of the stack's scenes (one friction law, rolling speeds ``speeds`` [m/s] per scene)
    from their closed forms (at the static coefficient), their traction fields (with ``fields``, else None each) and
    steepness ``(n,)`` (the largest ``-D V dmu/dv`` of a scene's slipping cells, 0 where none is above 0;
    :func:`~.common.slips_at`): the Coulomb strips' march (:func:`marched`) with each cell's bound ``mu(V sigma) p``
    at its own slip in the strip's half-plane (:func:`elastic_slips`, module docstring), found over
    :data:`FALLING_PASSES` marches (:func:`~.common.march`; one for a scene without spin, whose second march's numbers
    are dropped); the stick zones' traction is the closed form's.

    The cells are arrays ``(steps, n S)`` as in :func:`marched`: every operation is elementwise or a sum over one
    scene's cells in one order (:func:`by_scene`, :func:`elastic_slips`), so each scene's numbers are those it has
    alone."""
    n, count = stack.y.shape
    columns = n * count
    if n == 1:  # one scene: its scalars as plain floats, which numpy broadcasts alike
        a, b, p0, mu, _, xi, eta, phi, modulus_x, modulus_y, psi, m, _, l1, l2, l3, *_ = stack.rows[0]
        phi_x = float(stack.march_ratio[0, 0]) * phi + float(phi_c[0, 0])
        speed = float(speeds[0])
    else:  # each scene's scalars over its strips
        xi, eta, phi_x, l1, l2, l3, p0, a, b, mu, m, psi, phi, speed, modulus_x, modulus_y = np.repeat(np.hstack(
            (stack.xi, stack.eta, stack.march_ratio * stack.phi + phi_c, *stack.flexibilities, stack.p0, stack.a,
             stack.b, stack.mu, stack.m, stack.psi, stack.phi, speeds[:, None], stack.modulus_x, stack.modulus_y)).T,
            count, axis=1)
    y, half, weights, factor, d, kappa, lam, partial, X, Y = (v.reshape(columns) for v in (
        stack.y, stack.half, stack.weights, stack.factor, *sticking, stack.X, stack.Y))
    dx = 2.0 * half / steps
    x = half * cells(steps)
    bound = mu * (p0 * np.sqrt(np.maximum(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0)))  # mu p (Hertz), mu static
    scaling = np.repeat(stack.limit[:, 0] / by_scene(bound * (dx * weights), n), count)  # the cells carry mu Fn
    bound *= scaling
    pressure = bound / mu
    increment = np.empty((steps, 2, columns))
    increment[:, 0] = dx * (xi - phi_x * y) / l1 * factor
    increment[:, 1] = dx * (eta / l2 + phi * (x - 0.5 * dx) / l3)
    first = np.array([0.5 * increment[0, 0], 0.5 * dx * (eta / l2 + phi * (half - 0.25 * dx) / l3)])
    flexibility = (l1 / (factor * dx), l2 / dx)
    kernel = friction_kernel(law)
    static = law.static_coefficient
    coefficient = np.full(bound.shape, static)
    spin = stack.spin.repeat(count)
    ux, uy = bound * kappa, bound * lam  # the closed form's traction
    in_stick = partial & (x > 2.0 * d - half)
    m_s = m * scaling  # the cells' scale of mu p, as the bound's: continuous at the stick edge
    if partial.any():
        full = np.sqrt(np.maximum(half * half - x * x, 0.0))
        inner = np.sqrt(np.maximum((half - d) ** 2 - (x - d) ** 2, 0.0))
        stick_x, stick_y = m_s * kappa * (full - inner), m_s * (lam * full - (lam - psi) * inner)
        ux, uy = np.where(in_stick, stick_x, ux), np.where(in_stick, stick_y, uy)
    compliance = (1.0 / (factor * modulus_x), 1.0 / (factor * modulus_y))
    slip_of = (x, half, d, kappa, lam, psi, X, Y, partial, in_stick, m_s, compliance)
    sigma = kept = growth = None
    for k in range(FALLING_PASSES if spin.any() else 1):  # without spin the directions do not change
        marched = march(first, increment, coefficient * pressure)
        *_, rigid = march_slips(marched, first, increment, flexibility)
        if growth is None:  # the elastic slip per unit coefficient, from the first march's (at mu(0)) half-plane slip
            departure = None
            if spin.any():  # the march's traction turns away from the closed form's (without spin it is the same)
                trial, _, size = marched
                moved = spin & ~in_stick
                departure = np.where(moved, bound * trial.transpose(1, 0, 2) / size - (ux, uy), 0.0)
            growth = (rigid - elastic_slips(*slip_of, departure)) / static
        sigma, coefficient, steepness = slips_at(rigid, growth, ~in_stick & (rigid > growth * static), law, kernel,
                                                 speed, sigma)
        if k == 0 and not spin.all():
            kept = marched[0], sigma, coefficient, steepness
    trial, _, size = marched
    if kept is not None and spin.any():  # the scenes without spin keep their one march
        trial, sigma, coefficient, steepness = (np.where(spin, new, old) for new, old in zip(
            (trial, sigma, coefficient, steepness), kept, strict=True))
    limit = coefficient * pressure
    qx, qy = limit * kappa, limit * lam  # without spin the slip direction is uniform along the strip
    if spin.any():  # the last march's trials (the scenes with spin took it)
        qx, qy = np.where(spin, limit * trial[:, 0] / size, qx), np.where(spin, limit * trial[:, 1] / size, qy)
    if partial.any():
        share = None if stack.share is None else stack.share.reshape(columns)
        if share is not None and (share < 1.0).any():  # past |psi| = 1: within mu p, faded into the slip traction
            within = np.minimum(1.0, bound / np.maximum(np.hypot(stick_x, stick_y), TINY))
            stick_x = np.where(share < 1.0, share * within * stick_x + (1.0 - share) * qx, stick_x)
            stick_y = np.where(share < 1.0, share * within * stick_y + (1.0 - share) * qy, stick_y)
        qx, qy = np.where(in_stick, stick_x, qx), np.where(in_stick, stick_y, qy)
    weight = weights * dx
    dqx, dqy = qx - ux, qy - uy
    departure = by_scene(np.array([dqx * weight, dqy * weight, (x * dqy - y * dqx) * weight]), n).T
    largest = steepness.reshape(steps, n, count).max(axis=(0, 2))
    if not fields:
        return departure, (None,) * n, largest
    return departure, traction_fields(stack, steps, x, y, pressure, qx, qy, in_stick), largest


def polynomial_strips(scene, stack: StripStack) -> EllipticResult:
    """Velocity-dependent friction without spin by one 2D polynomial solve per strip (``falling="polynomial"``, module
    docstring); ``stack``: the scene's strips alone."""
    a, p0, e_x, psi = (float(v[0, 0]) for v in (stack.a, stack.p0, stack.modulus_x, stack.psi))
    X, Y, y, half, factor, scale, w = (v[0] for v in (stack.X, stack.Y, stack.y, stack.half, stack.factor,
                                                      stack.scale, stack.weights))
    nu = scene.material.poisson_ratio
    norm = np.hypot(X, Y)
    creep = norm / (e_x * scale)  # the strip's creepage along (X, Y), on its own modulus factor * E_x
    direction = (np.where(norm > 0.0, X / np.where(norm > 0.0, norm, 1.0), 0.0),
                 np.where(norm > 0.0, Y / np.where(norm > 0.0, norm, 1.0), 0.0))
    nodes, weights, _ = gauss(32)
    force = np.empty(y.size)
    lever = np.empty(y.size)
    failures = []
    for j in range(y.size):
        load = 0.5 * math.pi * half[j] * p0 * half[j] / a
        modulus = e_x * factor[j]
        result = solve_2d(Scene(load, creep=float(creep[j]), radius=modulus * a / (2.0 * p0),
                                material=Material(2.0 * modulus * (1.0 - nu * nu), nu), friction=scene.friction,
                                rolling_speed=scene.rolling_speed), "polynomial")
        if not result.success:
            failures.append(f"strip y = {y[j]:.4g} m: {result.message}")
        force[j] = result.tangential_force_per_length
        # int x q dx in the 3D frame (leading edge at +a(y)): x3D = -(x2D - offset)
        x2d = result.contact_offset + result.contact_half_width * nodes
        lever[j] = -result.contact_half_width * float(weights @ ((x2d - result.contact_offset) * result.traction(x2d)))
    fx = direction[0] * force
    fy = direction[1] * force
    forces = (float(w @ fx), float(w @ fy), float(w @ (direction[1] * lever - y * fx)))
    message = "strip theory, polynomial method per strip" + (": " + "; ".join(failures) if failures else "")
    return EllipticResult.from_scene(scene, "strips", not failures, message, forces,
                                     info={"stick_strips": math.nan, "psi": psi})


def inapplicable(scene) -> str | None:
    """Why the strips cannot treat the scene (a/b outside the coefficient table), or None."""
    return outside_table(scene)


CROSS_ITERATIONS = 2
"""Fixed-point passes of the lateral force's longitudinal creepage (:func:`cross_coefficient`) through the closed form
(the second changes the forces by less than 1e-3 mu Fn on ``benchmarks/calibrate_elliptic_levels.py``'s cases)."""

STIFFENING_SCALE = 3.0
"""``s`` [1] of :func:`stiffening`: the a/b where the short strips' stiffening reaches half its full exponent.
Calibrated, not derived: of s = 0.3, 0.5, 0.8, 1.2, 2, 3, 5, s = 3 keeps Fx and Fy without spin closest to the
discretised solver on the cases of ``benchmarks/calibrate_elliptic_levels.py`` (table B, the calibration set: within
0.010 mu Fn) and on the matrix of ``benchmarks/bench_elliptic.py`` (the validation set, which shares with it only
the creepages of 3 saturations: also 0.010); the strips without it miss by up to 0.023."""

SPIN_FLEXIBILITY = (0.9911, 0.0548, 0.9339, 0.122, 11.0538, 0.7492, 2.6791, 0.8)
"""``(A_x0, A_x1, A_y0, A_y1, P_1, m, R, Q)`` of :func:`march_flexibilities` (R: the spin at which the march's
longitudinal slip of spin has gone half way from the stick zones' modulus to the rigid slip, module docstring).
Calibrated, not derived: ``benchmarks/calibrate_strips_spin.py`` fits the first seven (Q held) to the strips' errors
with spin against the discretised level, on the spin cases of ``benchmarks/calibrate_elliptic_levels.py`` (table B: spin
around and past the strips' full slip, ``|psi|`` 0.15..15), on operating points of small creepage and spin and on
spin alone through the strips' full slip, at nu = 0.28 and, weighted less, at nu = 0, 0.14 and 0.42; the matrix of
``benchmarks/bench_elliptic.py`` checks it (of its cases with spin the fit holds only pure spin at 3 saturations). The
results files carry the errors. The fit is of the strips split at their turning line (:meth:`StripStack.split`), which
are converged at the default count, and holds at the default cells (:data:`DEFAULT_STEPS`): it also absorbs the
march's lag of half a cell, so other cell counts move the errors with spin (80 cells against 20 on table B: by up to
0.037 in Fy)."""

STRIPS_ERROR = 0.03
"""Error [1] of the strips without spin (Fx, Fy over mu Fn, Mz over mu Fn c): against the discretised 3D solver over
a/b 0.2..5 and creepages up to 9 mu Fn of linear force, the largest is Mz of lateral creepage at a/b = 5
(``benchmarks/calibrate_elliptic_levels.py``, table B)."""

STRIPS_SPIN_ERROR = 0.06
"""Error [1] of the strips with spin beyond ``|psi|`` = :data:`SPIN_ONSET` (the slip directions of the march):
against the discretised solver the largest error with spin at nu = 0.28 is 0.046, on spin with the lateral creepage
against it where the stick zones past ``|psi| = 1`` fade out (``benchmarks/calibrate_strips_spin.py``, the opposed
lines; at most 0.031 on table B of ``benchmarks/calibrate_elliptic_levels.py``, and 0.047 at nu = 0); this bound keeps a
margin over it and the reference's own error."""

SPIN_ONSET = 0.5
"""``|psi|`` up to which the spin's error grows linearly from :data:`STRIPS_ERROR` to :data:`STRIPS_SPIN_ERROR`."""

POISSON_ERROR = 0.15
"""Growth [1 per unit nu] of both errors with Poisson's ratio above steel's 0.28
(:func:`~rollcontact.elliptic.methods.common.poisson_excess`): the lateral
force's cross influence, taken of Hertz's shape, and the march's constants, fitted at 0.28 first, miss more as nu
grows (at nu = 0.49 the largest errors are 0.055 without spin, Mz of lateral creepage at a/b = 0.2, and 0.076 with
spin: ``benchmarks/calibrate_elliptic_levels.py``, table B3; below 0.28 they stay within the errors at 0.28)."""

STICK_FADE = 1.3
"""Excess ``v`` [1] at which a strip's stick zone past ``|psi| = 1`` has faded out: a stick zone whose traction
would exceed mu p by the measure ``v = sqrt(a*/a(y)) (1 - 2 lambda psi + psi^2) / (2 (1 - lambda psi))`` (> 1) keeps
the share ``(STICK_FADE - v) / (STICK_FADE - 1)`` of its traction, held within mu p, the rest being the march's slip
traction; beyond, the strip slips fully.  Calibrated, not derived: of 1.1, 1.2, 1.3, 1.4, 1.5 and 2, 1.3 and 1.4
keep the largest error of the three forces lowest on the opposed lines of ``benchmarks/calibrate_strips_spin.py``
(within 0.001 of each other; the results file carries the errors), 2 raises the error in Fy and 1.1 the jumps in Fx;
dropping the stick zones at ``v = 1`` jumps there by several hundredths of mu Fn."""

STRIPS_COST = 1.2e-4
STRIPS_COST_PER_CELL = 2.5e-6
STRIPS_FALLING_COST_PER_STRIP = 5e-4
"""Calibrated times [s]: the closed form, each cell of a march, each strip's 2D polynomial solve
(``benchmarks/calibrate_elliptic_levels.py``); the modelled cost is :func:`~.common.modelled_cost` of their sum."""

STRIPS_SPLIT_COST = 3e-5
"""Calibrated time [s] of the strips' split at the turning line with spin (:meth:`StripStack.split`): without it a
strips step with spin took up to 1.05 times its modelled cost in ``benchmarks/bench_worst_step.py``, with it every
step keeps within."""

STRIPS_FALLING_COST_FACTOR = 3.5
"""The falling-friction march's time over the Coulomb strips' with a march [1] (the march and each cell's slip, twice
with spin): a margin over the ratio of ``benchmarks/calibrate_falling_spin.py``, table C (to the Coulomb strips of the
same scenes, most of which take the closed form alone)."""

STRIPS_FALLING_ERROR = 0.05
"""Error [1] per unit of the law's fall over the contact (:func:`~.common.falling_drop`) that velocity-dependent
friction adds to the strips' estimate: the cells' slips are each strip's half-plane's, the half-space's own slip
differs.  With it the estimate bounds the error over the matrix of ``benchmarks/calibrate_falling_spin.py`` (table A,
the largest error over estimate; the largest errors are those of the steepest law, the linear one at 50 m/s: Fy of
lateral creepage against the spin at a/b 2, Mz of lateral creepage at a/b 5)."""


class StripsAccuracy(AccuracyModel):
    """Error: :data:`STRIPS_ERROR` without spin, rising to :data:`STRIPS_SPIN_ERROR` with |psi|, both growing with
    Poisson's ratio above 0.28 (:data:`POISSON_ERROR`) and reached from the linear limit within ``5 tau`` (tau of
    :func:`~rollcontact.elliptic.methods.common.linear_ratio`: the forces are exact there; the moment of lateral
    creepage is above Kalker's C23 by 14 % at a/b = 5 to 31 % at a/b = 0.2, the cross influence taking Hertz's shape
    for a lateral traction that is not yet saturated, about 0.07 tau at most), plus 1 % of tau for the coefficients.
    Cost: closed form, march or 2D solves."""

    floor = modelled_cost(STRIPS_COST)

    def ladder(self, scene):
        return ({},)

    def cost(self, scene, options):
        return modelled_cost(self.calibrated(scene, options))

    @staticmethod
    def calibrated(scene, options) -> float:
        """The solve's calibrated time [s] (before :func:`~.common.modelled_cost`)."""
        split = STRIPS_SPLIT_COST if scene.spin_creepage != 0.0 else 0.0
        march = STRIPS_COST + split + STRIPS_COST_PER_CELL * options.get("steps", DEFAULT_STEPS)
        if not scene.friction.is_constant:
            if options.get("falling", "march") == "polynomial":
                return STRIPS_FALLING_COST_PER_STRIP * options.get("strips", DEFAULT_STRIPS)
            return STRIPS_FALLING_COST_FACTOR * march
        if scene.spin_creepage == 0.0 and not options.get("fields"):
            return STRIPS_COST
        return march

    def error(self, scene, options):
        if scene.normal_load == 0.0:
            return 0.0
        c = coefficients(scene)
        tau = min(1.0, linear_ratio(scene, c))
        h = scene.hertz
        psi = abs(scene.spin_creepage) * 3.0 * scene.shear_modulus * c.c23 * h.c / (
            2.0 * math.pi * scene.friction_coefficient * h.max_pressure)
        spin = min(1.0, psi / SPIN_ONSET)
        poisson = POISSON_ERROR * poisson_excess(scene)
        return 0.01 * tau + (STRIPS_ERROR + (STRIPS_SPIN_ERROR - STRIPS_ERROR) * spin + poisson) * min(
            1.0, 5.0 * tau + spin) + STRIPS_FALLING_ERROR * falling_drop(scene)


METHOD = MethodSpec("strips", solve_strips, inapplicable, rank=10, accuracy=StripsAccuracy())
