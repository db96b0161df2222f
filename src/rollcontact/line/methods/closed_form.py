"""The closed-form method (``"closed_form"``): Hertz (paper eqs 9-11) and Carter (eqs 12-17) for a parabolic gap
and constant friction, registered with its accuracy model.

The lowest-ranked method, exact to round-off wherever it applies (:class:`ClosedFormAccuracy`).  The formulas are
:mod:`rollcontact.line.carter`; this module wraps them as a method (:func:`solve_closed_form`, :func:`inapplicable`,
:data:`METHOD`) for :mod:`rollcontact.line.dispatch`.
"""

from __future__ import annotations

from rollcontact.core.method import ROUND_OFF, AccuracyModel, MethodSpec, Setting
from rollcontact.line.carter import CarterDistributions, carter
from rollcontact.line.hertz import hertz
from rollcontact.line.result import ContactResult, NoContact


def solve_closed_form(scene, **options) -> ContactResult:
    """Hertz + Carter for a scene whose gap is parabolic (a linear surface tilt only moves the patch).

    A surface slope ``Z' = alpha`` moves the contact uphill by ``Delta = R alpha`` (docs/physics.md, Corrugated surface
    check).  Raises ValueError when the scene is not Hertzian or the friction is not constant.
    """
    if options:
        raise TypeError(f"closed_form takes no options, got {sorted(options)}")
    if not scene.surface.is_flat:
        raise ValueError("closed_form needs a parabolic gap (no harmonics, surface polynomial of degree <= 1); "
                         "use method='polynomial' or 'auto'")
    if not scene.friction.is_constant:
        raise ValueError(f"closed_form needs constant (Coulomb) friction, got {scene.friction!r}; "
                         "use method='polynomial' or 'auto'")
    n = scene.normal_load_per_length
    R = scene.radius
    mu = scene.friction_coefficient
    estar = scene.material.contact_modulus
    a, p0 = hertz(n, R, estar)
    t, a_star, stiffness = carter(n, scene.creep, R, estar, mu)
    poly = scene.surface.polynomial
    offset = R * poly[1] if len(poly) > 1 else 0.0
    if n == 0.0:
        dist = NoContact()
        message = "no load: no contact"
    else:
        dist = CarterDistributions(a, p0, a_star, offset, mu, scene.creep, R)
        message = "full slip (saturated)" if a_star == 0.0 and scene.creep != 0.0 else "Hertz + Carter"
    return ContactResult(method="closed_form", success=True, message=message, normal_load_per_length=n,
                         tangential_force_per_length=t, creep=scene.creep, contact_half_width=a,
                         contact_offset=offset, stick_half_width=a_star, max_pressure=p0,
                         creep_stiffness_per_length=stiffness, distributions=dist)


def inapplicable(scene) -> str | None:
    if not scene.surface.is_flat:
        return "the gap is not parabolic (harmonics or polynomial terms of degree >= 2)"
    if not scene.friction.is_constant:
        return "friction depends on slip velocity"
    return None


# ----------------------------------------------------------------------------- accuracy models of the methods
# Cost constant checked by benchmarks/pareto.py (benchmarks/results/pareto.md, section "Cost and error models of auto",
# which fits it and checks the cost model's ranking against measured times).
CLOSED_FORM_COST = 8.8e-6  # s, Hertz + Carter through solve()


class ClosedFormAccuracy(AccuracyModel):
    """Hertz + Carter: exact (round-off) wherever applicable, one setting."""

    floor = CLOSED_FORM_COST

    def ladder(self, scene):
        return ({},)

    def cost(self, scene, options):
        return CLOSED_FORM_COST

    def error(self, scene, options):
        return ROUND_OFF

    def minimum_cost(self, scene):
        return CLOSED_FORM_COST

    def setting_for(self, name, scene, tolerance):
        # the one setting, without the ladder walk: auto asks on every solve of a Hertzian scene
        return Setting(name, {}, ROUND_OFF, CLOSED_FORM_COST)


METHOD = MethodSpec("closed_form", solve_closed_form, inapplicable, rank=0, accuracy=ClosedFormAccuracy())
