"""The classical wheel/rail level (``"hertz"``): Hertz's ellipse at each contact point from the local curvatures,
the tangential forces by the elliptic ladder (docs/physics.md, Wheel/rail contact: the levels).

Each contact point of a wheel (:func:`~rollcontact.wheelrail.search.search_wheel`: the tread and flange-root lobes
of a patch are points of their own here) is an ellipse of the gap curvatures ``A = cos(alpha)/(2 r)`` and
``B = (k_wheel + k_rail)/2`` at the point; the wheel's vertical displacement carries its load with Hertz's
``N = (delta / delta_1)^(3/2)`` per point (:func:`~rollcontact.wheelrail.normal.solve_normal`), the tangential
forces' share of the vertical load included as :mod:`rollcontact.wheelrail.wheels` does; each ellipse's forces come
from :func:`rollcontact.solve_elliptic` with the level the ``elliptic`` option names (``"auto"`` by default).
Exact where the gap is quadratic over the patch; where it is not (a two-lobed tread, a flange root whose curvature
changes across the patch) its accuracy model says by how much.
"""

from __future__ import annotations

import math

import numpy as np

from rollcontact.core.method import AccuracyModel, MethodSpec
from rollcontact.elliptic.dispatch import METHODS as ELLIPTIC_METHODS
from rollcontact.elliptic.dispatch import solve as solve_elliptic
from rollcontact.elliptic.scene import EllipticScene
from rollcontact.wheelrail.normal import MIN_LATERAL_CURVATURE, hertz_contacts
from rollcontact.wheelrail.result import PatchResult, WheelPatch, WheelRailResult, WheelResult
from rollcontact.wheelrail.scene import SIDES, WheelRailScene
from rollcontact.wheelrail.search import creepages
from rollcontact.wheelrail.wheels import COUPLING, PASSES, balance, predicted_ratio, track_force

__all__ = ["METHOD", "inapplicable", "solve_hertz"]

GAP_ERROR = 0.18
"""Error [1] of the forces (over mu Fn, Mz over mu Fn c) per unit of a patch's departure from Hertz's gap
(:func:`departure`): with it each ellipse's estimate bounds its difference from the discretised patch on the
Manchester positions with a margin (``benchmarks/wheelrail_manchester.py``, table A, the largest difference over the
estimate, for Coulomb friction and on the dry rail; the largest differences at 0.5 mm, where the tread's second lobe
touches within the one point's patch, and at the centred two-lobed tread)."""

LOBES_ERROR = 0.1
"""Error [1] added where a contact point shares its patch with another (two lobes whose interpenetrations merge):
Hertz's ellipse per lobe shares the load and the slip between them otherwise than the one patch does
(``benchmarks/wheelrail_manchester.py``, table A: the centred position's two-lobed tread)."""

HERTZ_COST = 2e-4
"""Modelled time [s] of the geometry and Hertz's normal problem of a wheelset (``benchmarks/wheelrail_manchester.py``),
beyond the elliptic solves."""


def solve_hertz(scene: WheelRailScene, *, elliptic: str = "auto") -> WheelRailResult:
    """Both wheels by Hertz's ellipses and the elliptic level ``elliptic`` (module docstring).

    Returns
    -------
    WheelRailResult
        One patch per loaded contact point, its ``info`` the elliptic answer's with ``error_estimate`` its ellipse's
        estimate plus its gap's departure from Hertz's (:func:`shape_error`; the ellipse's alone in
        ``ellipse_error_estimate``); ``info["error_estimate"]`` the largest of the patches' (:class:`HertzAccuracy`).
    """
    if elliptic != "auto" and elliptic not in ELLIPTIC_METHODS:
        raise ValueError(f"elliptic = {elliptic!r} is not an elliptic level; valid: "
                         f"{['auto', *sorted(ELLIPTIC_METHODS)]}")
    wheels, failures, estimates = [], [], []
    for contact in scene.contacts:
        wheel, problems, estimate = hertz_wheel(scene, contact, elliptic)
        wheels.append(wheel)
        failures += problems
        estimates.append(estimate)
    message = "hertz: " + ("; ".join(failures) if failures else "; ".join(w.message for w in wheels))
    return WheelRailResult("hertz", not failures, message, tuple(wheels), {"error_estimate": max(estimates)})


solve_hertz.options = ("elliptic",)


def hertz_wheel(scene: WheelRailScene, contact, elliptic: str):
    """One wheel by Hertz: ``(WheelResult, problems, error estimate)``; the vertical balance and the passes of
    :mod:`rollcontact.wheelrail.wheels` (its :func:`~rollcontact.wheelrail.wheels.balance`) with Hertz's
    ``N = (delta / delta_1)^(3/2)`` per contact point, the first from the ratios of
    :func:`~rollcontact.wheelrail.wheels.predicted_ratio` at the scene's Hertz loads, until the wheel's vertical
    force, tangential forces included, meets its load to :data:`~rollcontact.wheelrail.wheels.COUPLING` of it (at
    most :data:`~rollcontact.wheelrail.wheels.PASSES`)."""
    side, load = contact.side, scene.load(contact.side)
    if load == 0.0:
        return WheelResult(side, (), 0.0, 0.0, (0.0, 0.0, 0.0), f"{side} wheel: no load, no contact"), [], 0.0
    unit, _ = hertz_contacts(contact, scene.material)
    patch_of = {i: patch for patch in contact.patches for i in patch.points}
    hertz = scene.hertz[SIDES.index(side)]
    ratios = [predicted_ratio(scene, point, force) if force > 0.0 else 0.0
              for point, force in zip(contact.points, hertz.normal_forces, strict=True)]
    start = hertz.vertical_displacement
    for _ in range(PASSES):
        items = [(p.vertical_gap, math.cos(p.contact_angle), r, k)
                 for k, (p, r) in enumerate(zip(contact.points, ratios, strict=True))]
        d, approaches, forces, why = balance(items, load, start, lambda k, approach: (approach / unit[k]) ** 1.5)
        if why is not None:
            return (WheelResult(side, (), load, d, (math.nan,) * 3, f"{side} wheel: {why}"),
                    [f"{side} wheel: {why}"], math.nan)
        patches, estimates = [], []
        for k, (point, approach, force) in enumerate(zip(contact.points, approaches, forces, strict=True)):
            if not force > 0.0:
                continue
            a_curv, b_curv = point.curvatures
            xi, eta, phi = creepages(scene.wheelset, scene.pose, scene.velocities, point)
            ellipse_scene = EllipticScene(force, a_curv, max(b_curv, MIN_LATERAL_CURVATURE), xi, eta, phi,
                                          scene.material, scene.friction, scene.forward_speed)
            answer = solve_elliptic(ellipse_scene, elliptic)
            h = ellipse_scene.hertz
            ellipse_estimate = answer.info.get("error_estimate", math.nan)
            estimate = ellipse_estimate + shape_error(patch_of[k], h.b, approach)
            result = PatchResult("hertz", answer.success, answer.message, force, approach, h.max_pressure,
                                 2.0 * h.a, 2.0 * h.b, answer.longitudinal_force, answer.lateral_force,
                                 answer.spin_moment, xi, eta, phi, scene.friction_coefficient, math.pi * h.a * h.b,
                                 info={"elliptic_method": answer.method, **answer.info,
                                       "ellipse_error_estimate": ellipse_estimate, "error_estimate": estimate})
            patches.append((k, WheelPatch(point, result, track_force(point, result))))
            estimates.append(estimate)
        if abs(sum(p.track_force[2] for _, p in patches) - load) <= COUPLING * load:
            break
        tangential = [(k, p.track_force[2] - p.result.normal_load * math.cos(p.point.contact_angle))
                      for k, p in patches]
        ratios = [0.0] * len(contact.points)
        for (k, v), (_, p) in zip(tangential, patches, strict=True):
            ratios[k] = v / p.result.normal_load
        start = d
    patches = sorted((p for _, p in patches), key=lambda p: -p.result.normal_load)
    problems = [f"{side} wheel, contact at rail y = {p.point.rail_lateral:.4g} m: {p.result.message}"
                for p in patches if not p.result.success]
    force = tuple(sum(p.track_force[i] for p in patches) for i in range(3))
    estimate = max(estimates, default=0.0)
    message = f"{side} wheel carries {force[2]:.6g} N of {load:.6g} N on {len(patches)} contact(s)"
    return WheelResult(side, tuple(patches), load, d, force, message), problems, estimate


def shape_error(patch, half_width: float, approach: float) -> float:
    """What a patch's shape adds to an ellipse's error: :data:`GAP_ERROR` times its :func:`departure` over the
    ellipse's half-width, and :data:`LOBES_ERROR` where the patch has more than one contact point."""
    return GAP_ERROR * departure(patch, half_width, approach) + (LOBES_ERROR if len(patch.points) > 1 else 0.0)


def departure(patch, half_width: float, approach: float) -> float:
    """How far [1] a patch's gap departs from Hertz's where the surfaces interpenetrate: ``max |h(s) - B s^2| /
    delta`` over the samples with ``h(s) <= delta`` (a second lobe of the patch among them), B fitted to the gap
    over ``|s| <= half_width`` (b of the ellipse at the patch's rigid contact point, s = 0) and delta the point's
    approach; at most 1.  A quadratic gap gives 0.  Kept in the patch's memo by its exact arguments (the solves
    of one geometry at other velocities ask again)."""
    key = ("hertz departure", half_width, approach)
    if key not in patch.memo:
        patch.memo[key] = _departure(patch, half_width, approach)
    return patch.memo[key]


def _departure(patch, half_width: float, approach: float) -> float:
    gap = patch.gap
    s = np.asarray(gap.lateral)
    h = np.asarray(gap.lateral_gap)
    inner = np.abs(s) <= half_width
    touching = h <= approach
    if inner.sum() < 4 or not approach > 0.0:
        return 0.0
    fit = np.polyfit(s[inner], h[inner], 2)
    return min(1.0, float(np.max(np.abs(h[touching] - np.polyval(fit, s[touching])))) / approach)


def inapplicable(scene: WheelRailScene) -> str | None:
    """Hertz's level treats every scene the contact search does (an ellipse beyond the elliptic levels' table
    goes to the elliptic discretised level)."""
    return None


class HertzAccuracy(AccuracyModel):
    """The elliptic level's estimate of each ellipse plus its patch's :func:`shape_error`; the cost of the
    geometry, Hertz and one elliptic solve per contact point."""

    floor = HERTZ_COST

    def ladder(self, scene):
        return ({"elliptic": "auto"},)

    def cost(self, scene, options):
        points = sum(sum(f > 0.0 for f in w.normal_forces) for w in scene.hertz)
        return HERTZ_COST + points * 2.0e-4

    def error(self, scene, options):
        worst = 0.0
        for contact, normal in zip(scene.contacts, scene.hertz, strict=True):
            if scene.load(contact.side) == 0.0:
                continue
            patch_of = {i: patch for patch in contact.patches for i in patch.points}
            for k, (point, force, approach, unit) in enumerate(zip(contact.points, normal.normal_forces,
                                                                   normal.approaches, normal.ellipses, strict=True)):
                if force > 0.0:
                    half_width = unit.b * force ** (1.0 / 3.0)
                    worst = max(worst, ellipse_estimate(scene, point, force)
                                + shape_error(patch_of[k], half_width, approach))
        return worst


def ellipse_estimate(scene: WheelRailScene, point, force: float) -> float:
    """The error estimate [1] of the elliptic level ``auto`` takes at a contact point (the lowest-ranked that
    applies, with its defaults)."""
    a_curv, b_curv = point.curvatures
    xi, eta, phi = creepages(scene.wheelset, scene.pose, scene.velocities, point)
    ellipse = EllipticScene(force, a_curv, max(b_curv, MIN_LATERAL_CURVATURE), xi, eta, phi, scene.material,
                            scene.friction, scene.forward_speed)
    for spec in sorted(ELLIPTIC_METHODS.values(), key=lambda s: s.rank):
        if spec.inapplicable(ellipse) is None:
            return spec.accuracy.error(ellipse, {}) if spec.accuracy is not None else math.nan
    return math.nan


METHOD = MethodSpec("hertz", solve_hertz, inapplicable, rank=20, accuracy=HertzAccuracy())
