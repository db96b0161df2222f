"""Kalker's linear theory (``"linear"``): the forces at vanishing creepage, from the creepage coefficients.

``Fx = G c^2 C11 xi``, ``Fy = G c^2 (C22 eta + c C23 phi)``, ``Mz = G c^3 (-C23 eta + c C33 phi)`` on the rail, with
c = sqrt(ab) and C11..C33 from :func:`rollcontact.elliptic.creepage_coefficients` (Kalker 1967; Kalker 1990,
section 2.3 and Table E.3).  Exact as the creepages vanish; unbounded (no friction limit) beyond, which its
accuracy model says.
"""

from __future__ import annotations

import math

from rollcontact.elliptic.methods.common import coefficients, linear_forces, linear_ratio, no_load, outside_table
from rollcontact.elliptic.result import EllipticResult
from rollcontact.method import AccuracyModel, MethodSpec, Setting

TABLE_ERROR = 0.01
"""Relative error [1] of the interpolated creepage coefficients (the table's three digits and its interpolation
between rows; ``tests/elliptic/test_creep_coefficients.py`` checks the rows within it)."""

LINEAR_MARGIN = 2.5
"""Factor on the Vermeulen-Johnson excess: the exact creep-force curves (the moment of lateral creepage most) bend
away from the linear theory faster than the cubic; against the discretised 3D solver the excess times 2.5 bounds the
linear theory's error over a/b 0.2..5 (``benchmarks/bench_elliptic_levels.py``, table B)."""

LINEAR_COST = 6e-6
"""Modelled time of one solve [s] (``benchmarks/bench_elliptic_levels.py``, results/bench_elliptic_levels.md)."""


def solve_linear(scene, **options) -> EllipticResult:
    """Kalker's linear theory (module docstring) for an elliptic scene.

    Returns
    -------
    EllipticResult
        ``info["coefficients"]`` holds (C11, C22, C23, C33).

    Raises
    ------
    ValueError
        a/b outside the coefficient table, or spin creepage while the table has no C33 (the message says so).
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
    """Why the linear theory cannot treat the scene (a/b outside the table; spin without C33), or None."""
    why = outside_table(scene)
    if why is not None:
        return why
    if scene.spin_creepage != 0.0 and math.isnan(coefficients(scene).c33):
        return "the creepage-coefficient table has no C33, which the spin moment of the linear theory needs"
    return None


class LinearAccuracy(AccuracyModel):
    """Error of the linear theory against the saturating creep-force curve, modelled by Vermeulen & Johnson's
    cubic ``F/(mu Fn) = 1 - (1 - tau/3)^3`` (tau = ``|F_linear| / (mu Fn)`` < 3, then 1; Vermeulen & Johnson 1964):
    ``error = LINEAR_MARGIN (tau - (1 - (1 - tau/3)^3))`` (``tau - 1`` in the bracket beyond tau = 3), plus
    :data:`TABLE_ERROR` tau."""

    floor = LINEAR_COST

    def ladder(self, scene):
        return ({},)

    def cost(self, scene, options):
        return LINEAR_COST

    def error(self, scene, options):
        if scene.normal_load == 0.0:
            return 0.0
        tau = linear_ratio(scene, coefficients(scene))
        saturating = 1.0 - (1.0 - tau / 3.0) ** 3 if tau < 3.0 else 1.0
        return LINEAR_MARGIN * (tau - saturating) + TABLE_ERROR * tau

    def setting_for(self, name, scene, tolerance):
        return Setting(name, {}, self.error(scene, {}), LINEAR_COST)


METHOD = MethodSpec("linear", solve_linear, inapplicable, rank=30, accuracy=LinearAccuracy())
