"""The fast non-Hertzian level of a patch (``"strips"``): lateral strips, each a 2D normal problem with its own
curvature and interpenetration corrected for the half-space (:mod:`~rollcontact.wheelrail.methods.strip_normal`),
then each the 2D tangential problem of the elliptic strips on its semi-elliptic pressure
(:mod:`~rollcontact.wheelrail.methods.strip_tangential`).  docs/physics-wheelrail-patches.md, "Strips on a patch".

Coulomb or velocity-dependent friction, with spin (the elliptic strips' falling-friction march on the patch's
strips: :func:`~rollcontact.wheelrail.methods.strip_tangential.falling_march_forces`).
"""

from __future__ import annotations

import math

import numpy as np

from rollcontact.core.checks import check_real
from rollcontact.core.method import AccuracyModel
from rollcontact.elliptic.methods.strips import (
    POISSON_ERROR,
    SPIN_ONSET,
    STRIPS_ERROR,
    STRIPS_FALLING_ERROR,
    STRIPS_SPIN_ERROR,
)
from rollcontact.wheelrail.methods.strip_normal import DEFAULT_STRIPS, Nearby, StripContact, refined, strip_normal
from rollcontact.wheelrail.methods.strip_tangential import (
    DEFAULT_STEPS,
    Lobes,
    coulomb_forces,
    falling_march_forces,
)
from rollcontact.wheelrail.result import PatchResult
from rollcontact.wheelrail.scene import PatchScene
from rollcontact.wheelrail.wheels import PatchLevel, wheel_method

__all__ = ["PatchStripsAccuracy", "normal_contact", "solve_strips"]

TANGENTIAL_STRIPS = 24
"""Strips of the tangential problem: the elliptic strips' count, at which their march's constants are calibrated."""


def normal_contact(scene: PatchScene, strips: int = DEFAULT_STRIPS, start: StripContact | Nearby | None = None
                   ) -> StripContact:
    """The strips' normal solution of the scene, at its approach or its load, from ``start`` if given
    (:func:`~rollcontact.wheelrail.methods.strip_normal.strip_normal`)."""
    return strip_normal(scene.gap, scene.material.contact_modulus, approach=scene.approach,
                        normal_load=scene.normal_load, strips=strips, start=start)


def solve_strips(scene: PatchScene, *, strips: int = DEFAULT_STRIPS, tangential_strips: int = TANGENTIAL_STRIPS,
                 steps: int = DEFAULT_STEPS, fields: bool = False,
                 start: StripContact | Nearby | None = None) -> PatchResult:
    """Normal and tangential contact of a patch by strips (module docstring).

    Parameters
    ----------
    scene : PatchScene
        The patch's case; Coulomb friction or a velocity-dependent law.
    strips : int
        Strips across the patch of the normal problem (>= 4).
    tangential_strips : int
        Strips of the tangential problem, the normal solution carried over to them
        (:func:`~rollcontact.wheelrail.methods.strip_normal.refined`; >= 4).
    steps : int
        Cells along each strip of the march (with spin) and of the fields (>= 2).
    fields : bool
        Return the pressure and traction on the strips' cells.
    start : StripContact or Nearby, optional
        A normal solution of the same gap nearby (or at the scene's approach) for the normal problem to start from,
        or one of a nearby gap (:class:`~rollcontact.wheelrail.methods.strip_normal.Nearby`).

    Returns
    -------
    PatchResult
        ``info``: ``strips_in_contact``, ``lobes`` (runs of strips in contact), ``equivalent_ratios`` (each lobe's
        a/b), ``outside_table`` (a lobe's a/b beyond Kalker's rows, its coefficients those of the rows beyond them,
        :func:`~rollcontact.elliptic.creep_coefficients.extended_creepage_coefficients`), ``normal_iterations``,
        ``normal_start`` (how the normal solution was reached,
        :attr:`~rollcontact.wheelrail.methods.strip_normal.StripContact.start`), ``error_estimate``,
        ``normal_error_estimate``, ``pressure_error_estimate``.

    Raises
    ------
    ValueError
        A count out of range (the strips treat every patch scene: Coulomb or velocity-dependent friction, with
        spin).
    """
    steps = int(check_real("steps", steps, lower=2))
    contact = normal_contact(scene, strips, start)
    mu = scene.friction_coefficient
    xi, eta, phi = scene.creepages
    if not contact.converged:
        return PatchResult("strips", False, f"normal problem: {contact.message}", contact.normal_load,
                           contact.approach, math.nan, math.nan, math.nan, math.nan, math.nan, math.nan, xi, eta, phi,
                           mu, math.nan, info={"normal_iterations": contact.iterations})
    if not np.count_nonzero(contact.contact):
        return PatchResult("strips", True, contact.message, 0.0, contact.approach, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, xi,
                           eta, phi, mu, 0.0, info={"error_estimate": 0.0})
    tangential_strips = int(check_real("tangential_strips", tangential_strips, lower=4))
    lobes = Lobes(refined(contact, scene.gap, tangential_strips), scene.material, scene.friction, scene.rolling_speed,
                  scene.creepages)
    if scene.friction.is_constant:
        forces, field = coulomb_forces(lobes, steps, fields)
    else:
        forces, field, _ = falling_march_forces(lobes, scene.friction, scene.rolling_speed, steps, fields)
    area = 2.0 * float(contact.widths @ contact.half_lengths)
    info = {"strips_in_contact": int(contact.contact.sum()), "lobes": len(lobes.runs),
            "equivalent_ratios": tuple(lobes.ratios), "outside_table": any(lobes.clamped),
            "normal_iterations": contact.iterations, "normal_start": contact.start}
    accuracy = PatchStripsAccuracy()
    info.update(accuracy.estimates(scene, lobes, contact))
    return PatchResult("strips", True, "strips", contact.normal_load, contact.approach, contact.max_pressure,
                       contact.length, contact.width, float(forces[0]), float(forces[1]), float(forces[2]), xi, eta,
                       phi, mu, area, field, info)


solve_strips.options = ("strips", "tangential_strips", "steps", "fields")


NORMAL_ERROR = 0.01
"""Relative error [1] of Fn at a given approach (of the approach at a given load) of the default 24 strips against the
reference: a margin over the largest in ``benchmarks/wheelrail_patches.py``, table "Normal" (the flange root)."""

PRESSURE_ERROR = 0.03
"""Relative error [1] of the peak pressure of the default 24 strips against the reference: a margin over the largest
in ``benchmarks/wheelrail_patches.py``, table "Normal" (the two-lobed tread's narrow lobe)."""

PATCH_ERROR = 0.02
"""Error [1] (Fx, Fy over mu Fn, Mz over mu Fn c) that a non-elliptic patch adds to the elliptic strips' estimate on
its equivalent ellipse, at full creepage: with it every largest error of ``benchmarks/wheelrail_patches.py``, table
"Tangential", lies within its estimate (the largest on the tread and the flange root is Mz of lateral creepage and of
spin)."""

OUTSIDE_TABLE_ERROR = 0.05
"""Error [1] added where a lobe's equivalent a/b lies beyond Kalker's rows of the coefficient table (its coefficients
the table's rows beyond them): the flange patch of ``benchmarks/wheelrail_patches.py``, table "Tangential", whose
largest error (Mz of combined creepage at two saturations) this keeps within its estimate."""

STRIPS_PATCH_COST = 1.4e-3
STRIPS_PATCH_COST_PER_CELL = 4e-6
"""Modelled times [s] on an idle machine: the normal solution and the closed form, each cell of the march
(``benchmarks/wheelrail_patches.py``, table "Time": the strips' CPU time without spin, at most 7.5 times the elliptic
strips' in the same rounds, and the march's share, spin against no spin, up to 0.4 times, each times the elliptic
strips' modelled time with spin, :data:`rollcontact.elliptic.methods.strips.STRIPS_COST` and 20 cells of
``STRIPS_COST_PER_CELL``, 1.7e-4 s; with a margin)."""


FALLING_REACH = 0.02
"""Half-size [m] of a patch that :meth:`PatchStripsAccuracy.error` takes before solving, for the largest rigid slip of
spin (a flange's patch is up to about 20 mm long)."""


def falling_drop(scene: PatchScene, half_length: float, half_width: float) -> float:
    """``1 - mu(V w)/mu(0)`` [1], ``w = |(|xi| + |phi| half_width, |eta| + |phi| half_length)|`` the largest rigid slip
    over the patch (the elliptic :func:`~rollcontact.elliptic.methods.common.falling_drop`); 0 for Coulomb friction."""
    if scene.friction.is_constant:
        return 0.0
    xi, eta, phi = scene.creepages
    slip = math.hypot(abs(xi) + abs(phi) * half_width, abs(eta) + abs(phi) * half_length)
    static = scene.friction_coefficient
    return max(0.0, 1.0 - float(scene.friction.coefficient(scene.rolling_speed * slip)) / static)


class PatchStripsAccuracy(AccuracyModel):
    """The strips' error: the elliptic strips' estimate (:class:`rollcontact.elliptic.methods.strips.StripsAccuracy`'s
    form) on each lobe's equivalent ellipse, plus :data:`PATCH_ERROR` for a non-elliptic patch (scaled, like the
    elliptic estimate, by the creepage in units of saturation), the falling friction's term of the elliptic strips
    (:data:`~rollcontact.elliptic.methods.strips.STRIPS_FALLING_ERROR` times :func:`falling_drop`), and the normal
    level's :data:`NORMAL_ERROR` and :data:`PRESSURE_ERROR`.  Cost: the normal solution and the march."""

    floor = STRIPS_PATCH_COST

    def ladder(self, scene):
        return ({},)

    def cost(self, scene, options):
        if scene.spin_creepage == 0.0 and not options.get("fields"):
            return STRIPS_PATCH_COST
        return STRIPS_PATCH_COST + STRIPS_PATCH_COST_PER_CELL * options.get("steps", DEFAULT_STEPS)

    def error(self, scene, options):
        """Before solving: the largest the estimate can be, the elliptic strips' bound with spin plus the patch's (and
        the falling friction's over a patch half-size of :data:`FALLING_REACH`)."""
        poisson = POISSON_ERROR * max(0.0, scene.material.poisson_ratio - 0.28)
        spin = STRIPS_SPIN_ERROR if scene.spin_creepage != 0.0 else STRIPS_ERROR
        return spin + poisson + PATCH_ERROR + STRIPS_FALLING_ERROR * falling_drop(scene, FALLING_REACH, FALLING_REACH)

    def estimates(self, scene: PatchScene, lobes: Lobes, contact: StripContact) -> dict:
        """``error_estimate``, ``normal_error_estimate`` and ``pressure_error_estimate`` of a solved scene."""
        mu, load = scene.friction_coefficient, contact.normal_load
        g, nu = scene.shear_modulus, scene.material.poisson_ratio
        xi, eta, phi = scene.creepages
        worst = 0.0
        for run, c, psi_e in zip(lobes.runs, lobes.coefficients, lobes.psi_e, strict=True):
            w, half = lobes.w[run], lobes.half[run]
            area = 2.0 * float(w @ half)
            lobe_load = float(w @ (0.5 * math.pi * lobes.q[run] * half * half))
            c2 = area / math.pi
            xi_lobe = xi - phi * float(lobes.centroid[run][0])
            linear = math.hypot(g * c2 * c.c11 * xi_lobe, g * c2 * c.c22 * eta) + g * c2**1.5 * c.c23 * abs(phi)
            tau = min(1.0, linear / (mu * lobe_load)) if lobe_load > 0.0 else 0.0
            spin = min(1.0, abs(psi_e) / SPIN_ONSET)
            poisson = POISSON_ERROR * max(0.0, nu - 0.28)
            lobe = 0.01 * tau + (STRIPS_ERROR + (STRIPS_SPIN_ERROR - STRIPS_ERROR) * spin + poisson) * min(
                1.0, 5.0 * tau + spin)
            share = lobe_load / load if load > 0.0 else 0.0
            worst = max(worst, share * lobe)
        tau_patch = min(1.0, 5.0 * worst / max(STRIPS_ERROR, 1e-12))
        ratio_penalty = OUTSIDE_TABLE_ERROR if any(lobes.clamped) else 0.0
        falling = STRIPS_FALLING_ERROR * falling_drop(scene, 0.5 * contact.length, 0.5 * contact.width)
        return {"error_estimate": worst + PATCH_ERROR * tau_patch + ratio_penalty + falling,
                "normal_error_estimate": NORMAL_ERROR, "pressure_error_estimate": PRESSURE_ERROR}


def strips_normal_force(gap, approach: float, material, start: StripContact | Nearby | None = None):
    """``(N, contact)``: the strips' normal force [N] of a patch at the normal approach [m] and their solution, from
    ``start`` (the solution of a previous call on the same gap, or :class:`~rollcontact.wheelrail.methods.strip_normal.
    Nearby`) (the wheel level's normal law)."""
    contact = strip_normal(gap, material.contact_modulus, approach=approach, start=start)
    return contact.normal_load, contact


def strips_loaded_approach(gap, force: float, material, start: StripContact | Nearby | None = None):
    """``(approach, contact)``: the strips' normal approach [m] of a patch carrying the normal force [N] (None where
    they do not converge) and their solution, from ``start`` (the solution of a previous call on the same gap, or
    :class:`~rollcontact.wheelrail.methods.strip_normal.Nearby`) (the wheel level's solve for a given force)."""
    contact = strip_normal(gap, material.contact_modulus, normal_load=force, start=start)
    return (contact.approach if contact.converged else None), contact


LEVEL = PatchLevel("strips", strips_normal_force, solve_strips, PatchStripsAccuracy(), strips_loaded_approach, Nearby)
"""The strips as a patch level of the wheels (:mod:`rollcontact.wheelrail.wheels`)."""

METHOD = wheel_method(LEVEL, rank=10)
