"""Kalker's linear theory (``"linear"``): the forces at vanishing creepage, from the creepage coefficients.

``Fx = G c^2 C11 xi``, ``Fy = G c^2 (C22 eta + c C23 phi)``, ``Mz = G c^3 (-C23 eta + c C33 phi)`` on the rail, with
c = sqrt(ab) and C11..C33 from :func:`rollcontact.elliptic.creepage_coefficients` (Kalker 1967; Kalker 1990,
section 2.3 and Table E.3).  Exact as the creepages vanish; unbounded (no friction limit) beyond, which its
accuracy model says.
"""

from __future__ import annotations

from rollcontact.core.method import AccuracyModel, MethodSpec, Setting
from rollcontact.elliptic.methods.common import (
    coefficients,
    linear_forces,
    linear_ratio,
    modelled_cost,
    no_load,
    outside_table,
)
from rollcontact.elliptic.result import EllipticResult

TABLE_ERROR = 0.01
"""Relative error [1] of the interpolated creepage coefficients (the table's three digits and its interpolation
between rows; ``tests/elliptic/test_creep_coefficients.py`` checks the rows within it)."""

LINEAR_MARGIN = 2.5
"""Factor on the Vermeulen-Johnson excess: the exact creep-force curves (the moment of lateral creepage most) bend
away from the linear theory faster than the cubic; against the discretised 3D solver the excess times 2.5 bounds the
linear theory's error over a/b 0.2..5 (``benchmarks/calibrate_elliptic_levels.py``, table B)."""

MOMENT_SATURATION = 0.5
"""Level [1 of mu Fn c] at which the accuracy model lets the spin moment saturate: below the full-slip moment of pure
spin (``3 pi/16 = 0.59`` for a circle, less for an elongated ellipse), so that the modelled excess of the linear
moment bounds its error over a/b 0.2..5 against the discretised 3D solver (``benchmarks/bench_elliptic.py``, part B's
reference forces in ``benchmarks/results/bench_elliptic.json``: the largest error/estimate is 0.69)."""

LINEAR_COST = 6e-6
"""Calibrated time of one solve [s] (``benchmarks/calibrate_elliptic_levels.py``, results/elliptic_levels.md); the
modelled cost of the linear and saturated levels is :func:`~.common.modelled_cost` of it."""


def solve_linear(scene, **options) -> EllipticResult:
    """Kalker's linear theory (module docstring) for an elliptic scene.

    Returns
    -------
    EllipticResult
        ``info["coefficients"]`` holds (C11, C22, C23, C33).

    Raises
    ------
    ValueError
        a/b outside the coefficient table (the message says so).
    """
    if options:
        raise TypeError(f"linear takes no options, got {sorted(options)}")
    why = inapplicable(scene)
    if why is not None:
        raise ValueError(f"linear theory cannot solve this scene: {why}")
    if scene.normal_load == 0.0:
        return no_load(scene, "linear")
    c = coefficients(scene)
    return EllipticResult.from_scene(scene, "linear", True, "Kalker's linear theory", linear_forces(scene, c),
                                     info={"coefficients": tuple(c)})


def inapplicable(scene) -> str | None:
    """Why the linear theory cannot treat the scene (a/b outside the table), or None."""
    return outside_table(scene)


class LinearAccuracy(AccuracyModel):
    """Error of the linear theory against the saturating creep-force curve, modelled by Vermeulen & Johnson's
    cubic ``F/(mu Fn) = 1 - (1 - tau/3)^3`` (tau = ``|F_linear| / (mu Fn)`` < 3, then 1; Vermeulen & Johnson 1964):
    ``error = LINEAR_MARGIN (tau - (1 - (1 - tau/3)^3))`` (``tau - 1`` in the bracket beyond tau = 3), plus
    :data:`TABLE_ERROR` tau; and the same for the moment, whose linear value
    ``tau_M = G c^2 (C33 c |phi| + C23 |eta|) / (mu Fn)`` (of mu Fn c) saturates at :data:`MOMENT_SATURATION`
    instead of 1: ``M(tau_M) = m (1 - (1 - tau_M/(3 m))^3)``.  The larger of the two."""

    floor = modelled_cost(LINEAR_COST)

    def ladder(self, scene):
        return ({},)

    def cost(self, scene, options):
        return modelled_cost(LINEAR_COST)

    def error(self, scene, options):
        if scene.normal_load == 0.0:
            return 0.0
        c = coefficients(scene)
        return max(excess(linear_ratio(scene, c), 1.0), excess(moment_ratio(scene, c), MOMENT_SATURATION))

    def setting_for(self, name, scene, tolerance):
        return Setting(name, {}, self.error(scene, {}), modelled_cost(LINEAR_COST))


def excess(tau: float, limit: float) -> float:
    """``LINEAR_MARGIN (tau - M(tau)) + TABLE_ERROR tau`` with Vermeulen & Johnson's cubic saturating at ``limit``,
    ``M = limit (1 - (1 - tau/(3 limit))^3)`` below ``tau = 3 limit``, ``limit`` beyond (class docstring)."""
    saturating = limit * (1.0 - (1.0 - tau / (3.0 * limit)) ** 3) if tau < 3.0 * limit else limit
    return LINEAR_MARGIN * (tau - saturating) + TABLE_ERROR * tau


def moment_ratio(scene, c) -> float:
    """``tau_M = G c^2 (C33 c |phi| + C23 |eta|) / (mu Fn)`` [1]: the linear theory's largest spin moment over
    mu Fn c (the terms counted with one sign)."""
    size = scene.hertz.c
    scale = scene.friction_coefficient * scene.normal_load
    return (scene.shear_modulus * size * size * (c.c33 * size * abs(scene.spin_creepage)
                                                 + c.c23 * abs(scene.lateral_creepage)) / scale)


METHOD = MethodSpec("linear", solve_linear, inapplicable, rank=30, accuracy=LinearAccuracy())
