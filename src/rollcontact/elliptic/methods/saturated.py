"""Kalker's linear theory saturated at the friction limit (``"saturated"``): the field's cheapest answer that keeps
``|F| <= mu Fn``.

The linear forces ``F' = (Fx', Fy')`` (:func:`~rollcontact.elliptic.methods.common.linear_forces`) are scaled by
``e = g(u) / u`` with ``u = |F'| / (mu Fn)`` and Shen, Hedrick & Elkins' cubic ``g(u) = u - u^2/3 + u^3/27`` up to
``u = 3``, ``g = 1`` beyond (Shen, Hedrick & Elkins, "A comparison of alternative creep force models for rail vehicle
dynamic analysis", Vehicle System Dynamics 12, 1983): ``Fx = e Fx'``, ``Fy = e Fy'``.  ``g`` rises with Kalker's
slopes at zero creepage and reaches 1 with a horizontal tangent at ``u = 3``, so ``|F| = g(u) mu Fn <= mu Fn`` with mu
the friction law's largest coefficient (its static one for the falling laws).

The moment has two linear parts (docs/physics.md, Kalker's linear theory): ``-G c^3 C23 eta``, which partial slip
makes and full slip removes (the tractions of a sliding contact are symmetric about the lateral axis), scaled by
``e^2``; and the spin's ``G c^4 C33 phi``, saturated by the same cubic at the full-slip moment of pure spin
``M_s = mu Fn r_m`` (:func:`spin_limit`).
"""

from __future__ import annotations

import math

from scipy.special import ellipe

from rollcontact.core.method import AccuracyModel, MethodSpec, Setting
from rollcontact.elliptic.methods.common import (
    coefficients,
    linear_forces,
    linear_ratio,
    modelled_cost,
    no_load,
    outside_table,
)
from rollcontact.elliptic.methods.linear import LINEAR_COST, TABLE_ERROR
from rollcontact.elliptic.result import EllipticResult

SATURATED_MARGIN = (0.31, 1.17)
"""``(force, spin)`` factors of the saturated level's error model (:class:`SaturatedAccuracy`): 1.2 times the
smallest that bound its errors against the discretised 3D level over the case matrix without and with spin
(``benchmarks/calibrate_elliptic_levels.py``, table B: the force term from the cases without spin, the spin term
from the rest; with deep spin the exact forces turn and shrink where the saturated linear ones keep their direction,
so the estimate reaches the size of the answer there)."""


def saturation_factor(u: float) -> float:
    """``e = g(u) / u`` [1] of Shen, Hedrick & Elkins: ``g = u - u^2/3 + u^3/27`` for ``u < 3``, else 1 (module
    docstring); 1 at ``u = 0``."""
    if u >= 3.0:
        return 1.0 / u
    return 1.0 - u / 3.0 + u * u / 27.0


def spin_limit(scene) -> float:
    """``M_s = mu Fn r_m`` [N m]: the moment of pure spin in full slip, ``r_m = (3/32) P`` the mean distance from the
    centre under Hertz's pressure, P the ellipse's perimeter ``4 a_max E(1 - (a_min/a_max)^2)`` (the pressure
    ``p0 sqrt(1 - rho^2)`` in ``x = a rho cos t``, ``y = b rho sin t`` separates: ``int p r dA / Fn = (pi/16) P /
    (2 pi/3)``; Johnson, *Contact Mechanics*, 1985, section 4.2 for the pressure)."""
    h = scene.hertz
    major, minor = max(h.a, h.b), min(h.a, h.b)
    perimeter = 4.0 * major * float(ellipe(1.0 - (minor / major) ** 2))
    return scene.friction.maximum_coefficient * scene.normal_load * 3.0 / 32.0 * perimeter


def solve_saturated(scene, **options) -> EllipticResult:
    """Kalker's linear theory saturated by Shen, Hedrick & Elkins (module docstring).

    Returns
    -------
    EllipticResult
        ``info["coefficients"]`` holds (C11, C22, C23, C33), ``info["saturation"]`` the factor e.

    Raises
    ------
    ValueError
        a/b outside the coefficient table (the message says so).
    """
    if options:
        raise TypeError(f"saturated takes no options, got {sorted(options)}")
    why = inapplicable(scene)
    if why is not None:
        raise ValueError(f"saturated linear theory cannot solve this scene: {why}")
    if scene.normal_load == 0.0:
        return no_load(scene, "saturated")
    c = coefficients(scene)
    fx, fy, _ = linear_forces(scene, c)
    bound = scene.friction.maximum_coefficient * scene.normal_load
    factor = saturation_factor(math.hypot(fx, fy) / bound)
    size = scene.hertz.c
    stiffness = scene.shear_modulus * size * size * size
    spin = stiffness * size * c.c33 * scene.spin_creepage
    limit = spin_limit(scene)
    moment = factor * factor * (-stiffness * c.c23 * scene.lateral_creepage) + \
        saturation_factor(abs(spin) / limit) * spin
    return EllipticResult.from_scene(scene, "saturated", True, "Kalker's linear theory, saturated (Shen, Hedrick & "
                                     "Elkins)", (factor * fx, factor * fy, moment),
                                     info={"coefficients": tuple(c), "saturation": factor})


def inapplicable(scene) -> str | None:
    """Why the saturated linear theory cannot treat the scene (a/b outside the table), or None."""
    return outside_table(scene)


class SaturatedAccuracy(AccuracyModel):
    """Error of the saturated linear theory: ``TABLE_ERROR t + SATURATED_MARGIN[0] t^2 + SATURATED_MARGIN[1] s``
    with ``t = min(tau, 1)``, tau the linear forces over mu Fn (:func:`~rollcontact.elliptic.methods.common.
    linear_ratio`), and ``s = min(G c^3 C33 |phi| / (mu Fn), 1)``, the spin's linear moment over mu Fn c: exact as
    the creepages vanish, the creepages' error growing into saturation, the spin's from its onset."""

    floor = modelled_cost(LINEAR_COST)

    def ladder(self, scene):
        return ({},)

    def cost(self, scene, options):
        return modelled_cost(LINEAR_COST)

    def error(self, scene, options):
        if scene.normal_load == 0.0:
            return 0.0
        c = coefficients(scene)
        t = min(linear_ratio(scene, c), 1.0)
        size = scene.hertz.c
        s = min(scene.shear_modulus * size**3 * c.c33 * abs(scene.spin_creepage)
                / (scene.friction.maximum_coefficient * scene.normal_load), 1.0)
        return TABLE_ERROR * t + SATURATED_MARGIN[0] * t * t + SATURATED_MARGIN[1] * s

    def setting_for(self, name, scene, tolerance):
        return Setting(name, {}, self.error(scene, {}), modelled_cost(LINEAR_COST))


METHOD = MethodSpec("saturated", solve_saturated, inapplicable, rank=25, accuracy=SaturatedAccuracy())
