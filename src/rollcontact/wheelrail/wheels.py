"""What every wheel/rail level does around its patch solver: from a wheelset's scene to both wheels' patches, their
normal and tangential contact and the forces on the rails (:func:`solve_wheels`; docs/physics.md, Wheel/rail contact:
the wheels).

For each wheel, at the scene's pose (:attr:`WheelRailScene.contacts`):

1. Normal: the wheel is pressed down by d until the z components of its contact forces carry its vertical load Q.
   Patch i, first touching at the vertical gap g_i with the contact angle delta_i, has the normal approach
   ``delta_i(d) = (d - g_i) cos(delta_i)`` and carries ``N_i(delta_i)`` of the level's normal law; its force on the
   rail has the z component ``N_i cos(delta_i) + T_i`` with ``T_i = -sign sin(delta_i) Fs_i`` the tangential force's
   (sign +1 right, -1 left; s the contact frame's lateral axis, ``s = (0, cos(delta), -sign sin(delta))``,
   ``n = (0, sign sin(delta), cos(delta))`` into the rail, :func:`~rollcontact.wheelrail.search.creepages`).  The
   balance ``sum N_i (cos(delta_i) + r_i) = Q`` with ``r_i = T_i / N_i`` of the previous pass (0 in the first) is
   solved from Hertz's displacement by the power-law update ``d <- g + (d - g) (Q / Q(d))^(1/m)`` (g the first touch),
   m = 3/2 (Hertz's) at first and then the local power of the last two displacements, so that it is exact for a law
   ``Q ~ (d - g)^m``, which the levels' laws follow closely.  Each call of the level's law on a patch starts from
   what its previous call on it left (:class:`PatchLevel`).  A wheel of one patch needs no iteration where the level
   solves for a given force (:attr:`PatchLevel.loaded`): ``N = Q / (cos(delta) + r)``, and d from its approach.
2. Tangential: each loaded patch's creepages at its rigid contact point from the wheelset's motion
   (:func:`~rollcontact.wheelrail.search.creepages`), the patch level's solve at its approach (at its normal force
   where it was solved for it).
3. Passes repeat 1 and 2 with the ratios r_i of the previous pass until the wheel's vertical force, tangential
   forces included, is within :data:`COUPLING` of Q (at most :data:`PASSES`).  The first pass takes each patch's
   r_i from Kalker's linear theory on Hertz's ellipse at its rigid contact point, saturated by Shen, Hedrick &
   Elkins at the static coefficient (:func:`predicted_ratio`), so that one pass is enough wherever that theory's
   lateral force is within ``COUPLING / sin(delta_i)`` of the level's own (on a tread, where ``sin(delta)`` is a few
   hundredths, a tenth of ``mu N``); a second pass where it is not (a flange, a patch far from Hertz's).

Forces are those the wheel exerts on the rail: per patch ``F = Fx e_x + Fs s + N n`` in track axes.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

from rollcontact.core.method import AccuracyModel, MethodSpec
from rollcontact.elliptic.creep_coefficients import extended_creepage_coefficients
from rollcontact.elliptic.hertz import hertz_ellipse
from rollcontact.elliptic.methods.saturated import saturation_factor
from rollcontact.wheelrail.geometry import side_sign
from rollcontact.wheelrail.normal import MIN_LATERAL_CURVATURE
from rollcontact.wheelrail.result import PatchResult, WheelPatch, WheelRailResult, WheelResult
from rollcontact.wheelrail.scene import PatchScene, WheelRailScene
from rollcontact.wheelrail.search import creepages

__all__ = ["COUPLING", "PatchLevel", "WheelAccuracy", "patch_scenes", "predicted_ratio", "solve_wheels", "track_force",
           "wheel_method"]

BALANCE_TOLERANCE = 1e-6
"""Relative residual [1] of the vertical balance ``|Q(d) - Q| / Q`` at which the normal problem stops (the strips'
normal problem settles to about this: ``rollcontact.wheelrail.methods.strip_normal.FIXED_POINT_TOLERANCE``)."""

POWERS = (1.0, 3.0)
"""Bounds of the local power m of the law ``Q ~ (d - g)^m`` that the vertical balance's updates take."""

BALANCE_ITERATIONS = 40
"""Cap of the power-law updates of the vertical balance."""

COUPLING = 1e-3
"""Relative difference [1] of a wheel's vertical force, tangential forces included, from its load at which the passes
of every level stop: the patch levels' (module docstring), the Hertz level's (:mod:`rollcontact.wheelrail.methods.
hertz`) and the tabulated wheelset's (:mod:`rollcontact.wheelrail.tabulated`).  It moves a patch's forces by about
as much of themselves, a fiftieth of the discretised level's accuracy goal on the Manchester case (0.02 mu Fn)."""

PASSES = 5
"""Cap of the passes of normal and tangential contact of a wheel (module docstring)."""


class PatchLevel(NamedTuple):
    """A patch solver as the wheel levels use it.

    Attributes
    ----------
    name : str
        The level's name.
    normal : callable
        ``normal(gap, approach, material, start) -> (N, state)``: the patch's normal force [N] at the normal approach
        [m], and what the level keeps of its solution (or None): the ``start`` of the next call on the same patch
        (None at the first) and of its solve.
    solve : callable
        ``solve(scene, start=state, **options) -> PatchResult`` of a :class:`~rollcontact.wheelrail.scene.PatchScene`
        at its approach, ``state`` that of the normal law's last call on the patch; a level may record in the state
        what the next pass's calls on the patch start from (the discretised level its tractions).
    accuracy : AccuracyModel or None
        The patch solver's accuracy model.
    loaded : callable or None
        ``loaded(gap, force, material, start) -> (approach, state)``: the normal approach [m] at which the patch
        carries the normal force [N] (None where the level's solution does not converge), and ``state`` as of
        ``normal``.  A wheel of one patch takes it in place of the vertical balance's iterations on ``normal``; None:
        the level has no such solve.
    nearby : callable or None
        ``nearby(state) -> start``: a state of the patch at a pose a little away (another gap) as a ``start`` of
        ``normal``, ``loaded`` and ``solve`` (the strips: :class:`~rollcontact.wheelrail.methods.strip_normal.
        Nearby`, which Newton's method starts from); None: the level takes states of the very gap alone.
    """

    name: str
    normal: Callable
    solve: Callable
    accuracy: AccuracyModel | None
    loaded: Callable | None = None
    nearby: Callable | None = None


def track_force(point, result: PatchResult) -> tuple[float, float, float]:
    """(Fx, Fy, Fz) [N] of a patch's forces on the rail in track axes (module docstring)."""
    sign = side_sign(point.side)
    sd, cd = math.sin(point.contact_angle), math.cos(point.contact_angle)
    fs, n = result.lateral_force, result.normal_load
    return result.longitudinal_force, fs * cd + n * sign * sd, -fs * sign * sd + n * cd


def balance(items, load: float, start: float, law) -> tuple[float, list[float], list[float], str | None]:
    """The displacement d, the patches' approaches and normal forces at which ``sum N_i (cos_i + r_i) = load``
    (module docstring); ``items`` are ``(g_i, cos_i, r_i, key)``, ``law(key, approach) -> N``; the message is None
    or why the balance failed.  The power-law update (module docstring, the local power within :data:`POWERS`) is
    kept within the bracket of the displacements seen on either side of the load (bisection where it would leave
    it); where the law steps over the load (the strips' normal force steps by a few 1e-4 of it where two lobes of a
    patch merge or a lobe appears) the bracket closes on the step and the last side evaluated stands (the wheel's
    force then differs from its load by the step, which the result shows)."""
    first = min(g for g, _, _, _ in items)

    def carried(d):
        approaches = [(d - g) * c for g, c, _, _ in items]
        forces = [law(key, a) if a > 0.0 else 0.0 for (_, _, _, key), a in zip(items, approaches, strict=True)]
        return sum(f * (c + r) for f, (_, c, r, _) in zip(forces, items, strict=True)), approaches, forces

    low, high = first, math.inf
    d = max(start, first + 1e-12)
    power, previous = 1.5, None
    for _ in range(BALANCE_ITERATIONS):
        q, approaches, forces = carried(d)
        if not math.isfinite(q):
            return d, approaches, forces, (f"the normal forces with the tangential forces' vertical share are {q!r} N "
                                           f"at a displacement of {d - first!r} m: the patches' forces at these "
                                           "creepages lie beyond floating point")
        if q < 0.0:
            return d, approaches, forces, (f"the normal forces with the tangential forces' vertical share carry "
                                           f"{q!r} N at a displacement of {d - first!r} m (a tangential force "
                                           "beyond the friction limit, the linear theory's, can outweigh them)")
        if abs(q - load) <= BALANCE_TOLERANCE * load:
            return d, approaches, forces, None
        if q < load:
            low = max(low, d)
        else:
            high = min(high, d)
        if math.isfinite(high) and high - low <= BALANCE_TOLERANCE * (high - first):  # the law steps over the load
            return d, approaches, forces, None
        if previous is not None and q > 0.0 and previous[1] > 0.0 and d != previous[0]:
            power = min(max(math.log(q / previous[1]) / math.log((d - first) / (previous[0] - first)), POWERS[0]),
                        POWERS[1])
        previous = d, q
        proposal = first + (d - first) * (load / q) ** (1.0 / power) if q > 0.0 else first + 2.0 * (d - first)
        if not low < proposal < high:
            proposal = 0.5 * (low + high) if math.isfinite(high) else low + 2.0 * (low - first)
        d = proposal
    return d, approaches, forces, (f"the vertical balance did not settle in {BALANCE_ITERATIONS} updates: "
                                   f"{q!r} N for {load!r} N")


def loaded(items, load: float, level: PatchLevel, contact, material, states):
    """The displacement d, the approach and the normal force of a wheel of one patch, ``items`` as of
    :func:`balance`, from the level's solve for a given force (:attr:`PatchLevel.loaded`): the balance
    ``N (cos + r) = load`` gives ``N`` at once, and ``d = g + approach / cos`` (g the first touch); ``states`` takes
    the solve's state.  ``(None, None, None)`` where the level has no such solve, the wheel has several patches,
    ``cos + r <= 0`` or the solve does not converge (the balance then finds d)."""
    if level.loaded is None or len(items) != 1:
        return None, None, None
    touch, cosine, ratio, key = items[0]
    if not cosine + ratio > 0.0:
        return None, None, None
    force = load / (cosine + ratio)
    approach, state = level.loaded(contact.patches[key].gap, force, material, states[key])
    if approach is None:
        return None, None, None
    states[key] = state
    return touch + approach / cosine, [approach], [force]


def predicted_ratio(scene: WheelRailScene, point, force: float) -> float:
    """``r = T_z / N`` [1] of a patch before its first pass (module docstring): the tangential force's vertical share
    ``T_z = -sign sin(delta) Fs`` of the saturated linear theory on Hertz's ellipse under the force [N] > 0 at the
    rigid contact point ``point``, ``Fs = e(u) G c^2 (C22 eta + c C23 phi)`` with ``u = G c^2 |(C11 xi, C22 eta + c
    C23 phi)| / (mu N)`` and Shen, Hedrick & Elkins' ``e(u)`` (:func:`~rollcontact.elliptic.methods.saturated.
    saturation_factor`), ``c = sqrt(ab)``, Kalker's coefficients beyond his rows too, as the strips take them
    (:func:`~rollcontact.elliptic.creep_coefficients.extended_creepage_coefficients`), mu the static
    coefficient; the creepages those of the point (:func:`~rollcontact.wheelrail.search.creepages`); ``u`` infinite
    where only the bound ``mu N`` underflows to 0.  0 where the share is not a finite number (creepages or a load at
    the ends of floating point: the level's own solve then says what it makes of them)."""
    material = scene.material
    a_curv, b_curv = point.curvatures
    ellipse = hertz_ellipse(force, a_curv, max(b_curv, MIN_LATERAL_CURVATURE), material.contact_modulus)
    coefficients = extended_creepage_coefficients(ellipse.aspect_ratio, material.poisson_ratio)
    xi, eta, phi = creepages(scene.wheelset, scene.pose, scene.velocities, point)
    c = math.sqrt(ellipse.a * ellipse.b)
    area = material.shear_modulus * c * c
    fx = area * coefficients.c11 * xi
    fs = area * (coefficients.c22 * eta + c * coefficients.c23 * phi)
    bound, size = scene.friction.maximum_coefficient * force, math.hypot(fx, fs)
    fs *= saturation_factor(size / bound if bound > 0.0 else (math.inf if size > 0.0 else 0.0))
    share = -side_sign(point.side) * math.sin(point.contact_angle) * fs / force
    return share if math.isfinite(share) else 0.0


def solve_wheels(scene: WheelRailScene, level: PatchLevel, starts: WheelRailResult | None = None,
                 **options) -> WheelRailResult:
    """Both wheels of the scene with the patch level ``level`` (module docstring); ``options`` go to its solve.

    ``starts``: a result of this level whose patches' normal solutions start this solve's (each wheel's
    :attr:`~rollcontact.wheelrail.result.WheelResult.normal_states`), each pass from the same pass of the start,
    where the wheel has as many patches: a scene of other velocities on the same geometry
    (:meth:`~rollcontact.wheelrail.scene.WheelRailScene.with_velocities`, which shares the contacts) takes them as
    they are (a normal solution within the tolerance of the load it is asked for is the solution); a scene of a pose
    a little away (other gaps) takes them where the level can start from another gap's solution
    (:attr:`PatchLevel.nearby`: the strips, whose Newton's method starts from it).  The solution is the level's to
    its tolerance from any start; a stepping model's differences take the step's own."""
    if starts is not None and not isinstance(starts, WheelRailResult):
        raise TypeError(f"starts must be a WheelRailResult, got {type(starts).__name__}")
    wheels, failures, estimates = [], [], []
    for k, (contact, hertz) in enumerate(zip(scene.contacts, scene.hertz, strict=True)):
        given = starts.wheels[k].normal_states if starts is not None and len(starts.wheels) == 2 else ()
        wheel, problems, estimate = solve_wheel(scene, contact, hertz, level, options, given)
        wheels.append(wheel)
        failures += problems
        estimates.append(estimate)
    success = not failures
    message = f"{level.name}: " + ("; ".join(failures) if failures else
                                   "; ".join(w.message for w in wheels))
    return WheelRailResult(level.name, success, message, tuple(wheels), {"error_estimate": max(estimates)})


def solve_wheel(scene, contact, hertz, level: PatchLevel, options, starts=()):
    """One wheel: ``(WheelResult, problems, error estimate)`` (module docstring); ``starts``: ``(gap, states)`` per
    patch of the wheel's contact, the states of its passes (:func:`solve_wheels`)."""
    side, load = contact.side, scene.load(contact.side)
    if load == 0.0:
        return (WheelResult(side, (), 0.0, 0.0, (0.0, 0.0, 0.0), f"{side} wheel: no load, no contact"), [], 0.0)
    points = contact.points
    references = [points[patch.points[0]] for patch in contact.patches]
    ratios = [0.0] * len(references)
    material = scene.material
    problems: list[str] = []
    start = hertz.vertical_displacement
    states = [None] * len(references)
    carried = [None] * len(references)  # per patch the starts' states of its passes (of another gap: nearby)
    if len(starts) == len(contact.patches):
        carried = [passes if gap is patch.gap else None if level.nearby is None else
                   tuple(None if state is None else level.nearby(state) for state in passes)
                   for (gap, passes), patch in zip(starts, contact.patches, strict=True)]
    history: list[list] = [[] for _ in references]
    for k, patch in enumerate(contact.patches):
        force = sum(hertz.normal_forces[i] for i in patch.points)
        if force > 0.0:
            ratios[k] = predicted_ratio(scene, references[k], force)

    def law(k, approach):
        force, states[k] = level.normal(contact.patches[k].gap, approach, material, states[k])
        return force

    for done in range(PASSES):
        for k, passes in enumerate(carried):  # pass p starts from the starts' pass p, the nearest normal problem
            if passes is not None and done < len(passes) and passes[done] is not None:
                states[k] = passes[done]
        items = [(point.vertical_gap, math.cos(point.contact_angle), r, k)
                 for k, (point, r) in enumerate(zip(references, ratios, strict=True))]
        d, approaches, forces = loaded(items, load, level, contact, material, states)
        at_force, why = d is not None, None
        if not at_force:
            d, approaches, forces, why = balance(items, load, start, law)
        if why is not None:
            return (WheelResult(side, (), load, d, (math.nan,) * 3, f"{side} wheel: {why}"),
                    [f"{side} wheel: {why}"], math.nan)
        patches = []
        for k, (point, approach, force) in enumerate(zip(references, approaches, forces, strict=True)):
            if not force > 0.0:
                continue
            xi, eta, phi = creepages(scene.wheelset, scene.pose, scene.velocities, point)
            given = {"normal_load": force} if at_force else {"approach": approach}
            patch_scene = PatchScene(contact.patches[k].gap, **given, longitudinal_creepage=xi,
                                     lateral_creepage=eta, spin_creepage=phi, material=material,
                                     friction=scene.friction, rolling_speed=scene.forward_speed,
                                     name=f"{side} patch {k + 1}")
            result = level.solve(patch_scene, start=states[k], **options)
            patches.append((k, WheelPatch(point, result, track_force(point, result))))
        for k, state in enumerate(states):
            history[k].append(state)
        if abs(sum(p.track_force[2] for _, p in patches) - load) <= COUPLING * load:
            break
        tangential = [(k, p.track_force[2] - p.result.normal_load * math.cos(p.point.contact_angle))
                      for k, p in patches]
        ratios = [0.0] * len(references)
        for (k, t), (_, p) in zip(tangential, patches, strict=True):
            ratios[k] = t / p.result.normal_load if p.result.normal_load > 0.0 else 0.0
        start = d
    patches = sorted((p for _, p in patches), key=lambda p: -p.result.normal_load)
    problems += [f"{side} wheel, patch at rail y = {p.point.rail_lateral:.4g} m: {p.result.message}"
                 for p in patches if not p.result.success]
    force = tuple(sum(p.track_force[i] for p in patches) for i in range(3))
    estimate = max((p.result.info.get("error_estimate", math.nan) for p in patches), default=0.0)
    message = (f"{side} wheel carries {force[2]:.6g} N of {load:.6g} N on {len(patches)} patch(es)")
    kept = tuple((patch.gap, tuple(passes)) for patch, passes in zip(contact.patches, history, strict=True))
    return WheelResult(side, tuple(patches), load, d, force, message, kept), problems, estimate



GEOMETRY_COST = 4e-4
"""Modelled time [s] of the contact search of both wheels and Hertz's normal problem
(``benchmarks/wheelrail_geometry.py``)."""

PATCH_SOLVES = 3.0
"""A wheel's work per loaded patch in units of the patch level's modelled solve: the vertical balance's normal
solves and the tangential solve, twice where the tangential forces carry part of the load."""


def patch_scenes(scene: WheelRailScene) -> list[PatchScene]:
    """Each loaded patch's case at Hertz's normal load (the sum of its points'), with its creepages: what the
    accuracy models judge a wheel level by before it runs."""
    out = []
    for contact, normal in zip(scene.contacts, scene.hertz, strict=True):
        if scene.load(contact.side) == 0.0:
            continue
        for patch in contact.patches:
            load = sum(normal.normal_forces[i] for i in patch.points)
            if not load > 0.0:
                continue
            point = contact.points[patch.points[0]]
            xi, eta, phi = creepages(scene.wheelset, scene.pose, scene.velocities, point)
            out.append(PatchScene(patch.gap, normal_load=load, longitudinal_creepage=xi, lateral_creepage=eta,
                                  spin_creepage=phi, material=scene.material, friction=scene.friction,
                                  rolling_speed=scene.forward_speed))
    return out


class WheelAccuracy(AccuracyModel):
    """A wheel level's error and cost from its patch level's: the largest error of the loaded patches (at Hertz's
    loads, before solving; the patches' own estimates after), and the cost of :data:`PATCH_SOLVES` solves per patch
    plus the geometry's."""

    def __init__(self, level: PatchLevel):
        self.level = level
        self.floor = GEOMETRY_COST

    def ladder(self, scene):
        patches = patch_scenes(scene)
        return self.level.accuracy.ladder(patches[0]) if patches else ({},)

    def cost(self, scene, options):
        return GEOMETRY_COST + PATCH_SOLVES * sum(self.level.accuracy.cost(p, options) for p in patch_scenes(scene))

    def error(self, scene, options):
        return max((self.level.accuracy.error(p, options) for p in patch_scenes(scene)), default=0.0)

    def achieved(self, scene, options, result, tolerance=None):
        return result.info.get("error_estimate", math.nan)


def wheel_method(level: PatchLevel, rank: int, fallback: bool = False) -> MethodSpec:
    """The wheel level of a patch level: :func:`solve_wheels` with it, :class:`WheelAccuracy`; it treats every scene
    the contact search does (the patch levels treat every patch: any gap, friction law and creepages)."""

    def solve(scene: WheelRailScene, **options) -> WheelRailResult:
        return solve_wheels(scene, level, **options)

    def inapplicable(scene: WheelRailScene) -> str | None:
        return None

    solve.options = (*getattr(level.solve, "options", ()), "starts")
    solve.__doc__ = f"Both wheels of a wheel/rail scene by the patch level {level.name!r} (:func:`solve_wheels`)."
    return MethodSpec(level.name, solve, inapplicable, rank, fallback, WheelAccuracy(level))
