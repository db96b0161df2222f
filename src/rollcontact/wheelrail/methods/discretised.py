"""The discretised reference level of a patch (``"discretised"``): the 3D half-space on the patch's actual gap
(docs/physics-wheelrail-patches.md, "The discretised patch").

A grid of square elements (``element``: :data:`DEFAULT_ELEMENT` by default, smaller for a patch narrower than
:data:`MIN_ACROSS` of them) in the patch's tangent plane covers the contact with a margin: sized from the strips'
solution (:mod:`~rollcontact.wheelrail.methods.strip_normal`), grown while the contact touches its border.  The
normal problem is Polonsky & Keer's constrained conjugate gradients on ``g(x, s) = h(s) + A(s) x^2`` (Wear 231,
1999): for a given load :func:`rollcontact.core.halfspace.rolling.solve_normal`, for a given approach
:func:`normal_at_approach` (the same iteration without the load's constraint).  The tangential problem is
:func:`rollcontact.core.halfspace.rolling.solve_steady` (Kalker's exact steady rolling, any friction law) on the grid
trimmed to the elements in contact (exact: the tractions vanish outside), on the rigid slip
``w = (xi - phi s, eta + phi x)`` about the rigid contact point; Mz is taken about it.  The influence coefficients
are cached per grid shape and nu (:func:`rollcontact.core.halfspace.surface.operator_for`: grids that differ only in
their origin, as a patch's do from call to call, share them).  The normal iteration starts from the strips'
pressure; a wheel's passes on a patch keep a :class:`PatchState`, which carries the normal problem solved for a force
to the solve at that force and the last pass's tractions to the next pass's steady iteration.

Forces converge at first order in the element size (docs/physics.md, "Discretised 3D steady rolling");
``extrapolate=True`` returns the Richardson pair ``2 F(h) - F(2 h)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from rollcontact.core.halfspace.rolling import (
    NEWTON_ITERATIONS,
    NORMAL_ITERATIONS,
    solve_normal,
    solve_steady,
    total_forces,
)
from rollcontact.core.halfspace.surface import MAX_ELEMENTS_3D, SurfaceGrid, operator_for
from rollcontact.core.method import AccuracyModel
from rollcontact.elliptic.hertz import hertz_ellipse
from rollcontact.elliptic.result import TractionField
from rollcontact.wheelrail.methods.strip_normal import StripContact, check_gap, rigid_range, strip_normal
from rollcontact.wheelrail.result import PatchResult
from rollcontact.wheelrail.scene import PatchScene
from rollcontact.wheelrail.wheels import PatchLevel, wheel_method

__all__ = ["DiscretisedPatchAccuracy", "PatchState", "normal_at_approach", "solve_discretised"]

DEFAULT_ELEMENT = 0.2e-3
"""Element size [m] (square elements)."""

MIN_ACROSS = 12
"""Fewest elements across the patch's shorter extent of the default element (with it the default's error on the
flange patch of ``benchmarks/wheelrail_patches.py``, table "Tangential", stays within the goal of 0.02 mu Fn)."""

MARGIN = 0.15
"""Share of the strips' contact length and width the first grid adds on each side (and two elements)."""

GROWTHS = 4
"""Times the grid grows by half while the contact touches its border."""


def normal_at_approach(operator, gap: np.ndarray, approach: float, shear_modulus: float, tolerance: float = 1e-10,
                       max_iterations: int = NORMAL_ITERATIONS, initial: np.ndarray | None = None):
    """Normal contact at a given approach delta [m] by Polonsky & Keer's constrained conjugate gradients (Wear 231,
    1999, their scheme without the load's constraint): ``g = h0 + A_zz p / G - delta >= 0``, ``p >= 0``,
    ``p g = 0``.  Returns ``(pressure [Pa], iterations, converged, message)``; stops when the pressure changes by
    less than ``tolerance`` of its sum in one iteration.  Starts from ``initial`` [Pa] on the grid (a nearby
    solution; its negative part dropped) where it has a positive value, else from half the rigid interpenetration
    over the self-influence of an element."""
    p = None if initial is None else np.maximum(initial, 0.0)
    if p is None or not p.max() > 0.0:
        p = np.maximum(approach - gap, 0.0) * (0.5 * shear_modulus / operator.diagonal["zz"])
    direction = np.zeros(gap.shape)
    previous = 1.0
    restart = True
    change = math.inf
    for iteration in range(1, max_iterations + 1):
        contact = p > 0.0
        if not contact.any():
            return p, iteration, False, "the pressure vanished everywhere"
        surface = gap + operator.normal(p) / shear_modulus - approach
        residual = np.where(contact, surface, 0.0)
        norm = float(np.sum(residual * residual))
        direction = residual + (0.0 if restart else norm / previous) * direction
        direction[~contact] = 0.0
        previous = norm
        response = operator.normal(direction) / shear_modulus
        denominator = float(np.sum(response[contact] * direction[contact]))
        step = norm / denominator if denominator > 0.0 else 0.0
        old = p
        p = np.clip(p - step * direction, 0.0, None)
        overlap = (p == 0.0) & (surface < 0.0)
        restart = bool(overlap.any())
        if restart:
            p[overlap] -= step * surface[overlap]
        total = float(p.sum())
        change = float(np.abs(p - old).sum()) / total if total > 0.0 else math.inf
        if change <= tolerance:
            return p, iteration, True, "converged"
    return p, max_iterations, False, (f"pressure still changes by {change:.2e} of its sum after {max_iterations} "
                                      "iterations")


def patch_grid(centre_x: float, x_half: float, s_low: float, s_high: float, element: float) -> SurfaceGrid:
    """The grid of square elements ``element`` [m] covering ``[-x_half, x_half] x [s_low, s_high]`` [m] (x symmetric
    about 0, where the gap is even in x), each direction at least :data:`MIN_ELEMENTS` (ValueError beyond
    :data:`~rollcontact.core.halfspace.surface.MAX_ELEMENTS_3D`)."""
    nx = max(MIN_ELEMENTS, 2 * int(math.ceil(x_half / element)))
    s_low = element * math.floor(s_low / element)
    ny = max(MIN_ELEMENTS, int(math.ceil((s_high - s_low) / element)))
    if max(nx, ny) > MAX_ELEMENTS_3D:
        raise ValueError(f"the patch needs {nx} x {ny} elements of {element:.3g} m, beyond {MAX_ELEMENTS_3D} per "
                         "direction: take larger elements")
    return SurfaceGrid(nx, ny, element, element, centre_x - 0.5 * nx * element, s_low)


MIN_ELEMENTS = 8
"""Fewest elements per direction of a patch grid."""


def _gap_on(grid: SurfaceGrid, scene: PatchScene) -> np.ndarray:
    s, h, curvature = check_gap(scene.gap)
    x, y = grid.mesh()
    return np.interp(y, s, h) + np.interp(y, s, curvature) * x * x


def _touches(contact: np.ndarray) -> bool:
    return bool(contact[0].any() or contact[-1].any() or contact[:, 0].any() or contact[:, -1].any())


def guide_for(scene: PatchScene, start: StripContact | None = None) -> StripContact:
    """The strips' normal solution of the scene, which sizes the grid (from ``start``, a solution of the same gap
    nearby, if given)."""
    return strip_normal(scene.gap, scene.material.contact_modulus, approach=scene.approach,
                        normal_load=scene.normal_load, start=start)


def automatic_element(guide) -> float:
    """The default element [m]: :data:`DEFAULT_ELEMENT`, or less so that the strips' patch is at least
    :data:`MIN_ACROSS` elements across its shorter extent (a flange's narrow patch), but no less than a grid of
    half the largest count across the longer extent allows (a sliver of a patch that barely touches)."""
    if not guide.converged or not guide.contact.any():
        return DEFAULT_ELEMENT
    return max(min(DEFAULT_ELEMENT, min(guide.length, guide.width) / MIN_ACROSS),
               2.0 * max(guide.length, guide.width) / MAX_ELEMENTS_3D)


def normal_problem(scene: PatchScene, element: float, grid: SurfaceGrid | None, tolerance: float, guide=None):
    """``(grid, pressure, approach, message or None, iterations)`` of the scene's normal problem on a grid of
    ``element`` [m] sized and grown as the module docstring says (or on ``grid`` as given); ``guide``: the strips'
    normal solution, if already at hand.  The iteration starts from the guide's pressure
    (:meth:`~rollcontact.wheelrail.methods.strip_normal.StripContact.pressure_on`) where it converged, else from a
    uniform pressure (a given load) or the rigid interpenetration (a given approach).  From the guide's it needs
    fewer iterations (about three quarters on the Manchester patches), as few as from the solution of a force 1 %
    away: the decades down to the tolerance set the count."""
    shear = scene.shear_modulus
    if grid is None:
        guide = guide_for(scene) if guide is None else guide
        if not guide.converged:
            s, h, _ = check_gap(scene.gap)
            depth = scene.approach if scene.approach is not None else None
            bounds = rigid_range(s, h, depth) if depth is not None else None
            if bounds is None:
                return None, None, math.nan, f"no grid: the strips' normal problem failed ({guide.message})", 0
            x_half = math.sqrt(depth / float(np.min(scene.gap.longitudinal_curvature)))
            low, high = bounds
        else:
            low, high = guide.extent
            x_half = 0.5 * guide.length
            spare = MARGIN * (high - low)
            low, high, x_half = low - spare, high + spare, x_half * (1.0 + 2.0 * MARGIN)
        low, high, x_half = low - 2.0 * element, high + 2.0 * element, x_half + 2.0 * element
    iterations = 0
    for _ in range(GROWTHS + 1):
        if grid is None:
            current = patch_grid(0.0, x_half, low, high, element)
        else:
            current = grid
        op = operator_for(current, scene.material.poisson_ratio)
        gap = _gap_on(current, scene)
        start = guide.pressure_on(*current.mesh()) if guide is not None and guide.converged else None
        if scene.approach is None:
            solution = solve_normal(op, gap, scene.normal_load, shear, tolerance=tolerance, initial=start)
            pressure, approach, converged, message = (solution.pressure, solution.approach, solution.converged,
                                                      solution.message)
            iterations += solution.iterations
        else:
            pressure, used, converged, message = normal_at_approach(op, gap, scene.approach, shear, tolerance,
                                                                    initial=start)
            approach = scene.approach
            iterations += used
        if grid is not None or not _touches(pressure > 0.0):
            return current, pressure, approach, None if converged else f"normal problem: {message}", iterations
        width, middle = high - low, 0.5 * (low + high)
        low, high, x_half = middle - 0.75 * width, middle + 0.75 * width, 1.5 * x_half
    return current, pressure, approach, (f"the contact still touches the grid's border after {GROWTHS} growths"
                                         ), iterations


def trimmed(grid: SurfaceGrid, contact: np.ndarray) -> tuple[SurfaceGrid, tuple[slice, slice]]:
    """The grid reduced to the bounding box of the elements in contact (at least :data:`MIN_ELEMENTS` each way,
    within the grid) and the slices that cut it out."""
    rows = np.flatnonzero(contact.any(axis=1))
    columns = np.flatnonzero(contact.any(axis=0))

    def span(indices, size):
        low, high = int(indices[0]), int(indices[-1]) + 1
        missing = MIN_ELEMENTS - (high - low)
        if missing > 0:
            low = max(0, low - (missing + 1) // 2)
            high = min(size, low + MIN_ELEMENTS)
            low = max(0, high - MIN_ELEMENTS)
        return slice(low, high)

    sx, sy = span(rows, grid.nx), span(columns, grid.ny)
    sub = SurfaceGrid(sx.stop - sx.start, sy.stop - sy.start, grid.dx, grid.dy, grid.x_min + sx.start * grid.dx,
                      grid.y_min + sy.start * grid.dy)
    return sub, (sx, sy)


def solve_on_grid(scene: PatchScene, element: float, grid: SurfaceGrid | None, iteration_tolerance: float,
                  max_iterations: int, normal_tolerance: float, guide=None, normal=None, traction=None):
    """One level: the normal problem (``normal``: :func:`normal_problem`'s answer, already at hand), then the steady
    tangential problem on the trimmed grid (from ``traction``, :attr:`PatchState.traction` of a nearby solve, carried
    to the grid and scaled by the normal forces' ratio; else from full stick), its tractions projected onto the
    friction bound ``|q| <= g``.  Returns a dict of what the result needs."""
    current, pressure, approach, message, normal_iterations = normal if normal is not None else \
        normal_problem(scene, element, grid, normal_tolerance, guide)
    if current is None:
        return {"failure": message}
    contact = pressure > 0.0
    if not contact.any():
        return {"failure": None, "empty": True, "approach": approach}
    sub, (sx, sy) = trimmed(current, contact)
    p = pressure[sx, sy]
    x, s = sub.mesh()
    xi, eta, phi = scene.creepages
    op = operator_for(sub, scene.material.poisson_ratio)
    initial = None
    if traction is not None:
        ratio = float(p.sum() * sub.area) / traction[3]
        initial = tuple(ratio * sub.carried(q, traction[0]) for q in traction[1:3])
    steady = solve_steady(op, p, (xi - phi * s, eta + phi * x), scene.shear_modulus, scene.friction,
                          scene.rolling_speed, iteration_tolerance, max_iterations, initial)
    # Newton's tolerance leaves |q| up to its share of max g beyond the bound g: the tractions projected onto it
    magnitude = np.hypot(steady.traction_x, steady.traction_y)
    over = magnitude > steady.bound
    if over.any():
        shrink = np.where(over, steady.bound / np.where(over, magnitude, 1.0), 1.0)
        steady = replace(steady, traction_x=steady.traction_x * shrink, traction_y=steady.traction_y * shrink)
    forces = total_forces(sub, steady.traction_x, steady.traction_y)
    in_contact = p > 0.0
    rows = np.flatnonzero(in_contact.any(axis=1))
    columns = np.flatnonzero(in_contact.any(axis=0))
    messages = [m for m in (message, None if steady.converged else f"tangential problem: {steady.message}") if m]
    return {"failure": None, "empty": False, "grid": sub, "pressure": p, "steady": steady, "forces": forces,
            "approach": approach, "normal_load": float(p.sum() * sub.area), "max_pressure": float(p.max()),
            "length": float((rows[-1] - rows[0] + 1) * sub.dx), "width": float((columns[-1] - columns[0] + 1) * sub.dy),
            "area": float(in_contact.sum() * sub.area), "messages": messages, "normal_iterations": normal_iterations,
            "elements": (current.nx, current.ny), "contact_elements": int(in_contact.sum())}


@dataclass(eq=False)
class PatchState:
    """What the discretised level keeps of a patch between the calls of a wheel's passes (the state of
    :class:`~rollcontact.wheelrail.wheels.PatchLevel`): the normal problem solved for a given force
    (:func:`discretised_loaded_approach`), which the patch's solve at that force takes instead of solving it again,
    and the tractions of the last solve on the patch, which the next pass's solve starts from.

    Attributes
    ----------
    guide : StripContact
        The strips' solution at the force, which sized the grid.
    force : float or None
        The normal force [N] it was solved for; None where it was solved at an approach (``normal``'s).
    normal : tuple
        :func:`normal_problem`'s answer at the default element: ``(grid, pressure, approach, message, iterations)``.
    traction : tuple or None
        ``(grid, q_x, q_y, force)``: the trimmed grid, the tractions [Pa] and the normal force [N] of the last
        :func:`solve_discretised` given this state (it records them here), None before.
    """

    guide: StripContact
    force: float | None
    normal: tuple
    traction: tuple | None = None


ITERATION_TOLERANCE = 1e-6
"""Newton's default tolerance of the tangential problem on ``max |q - P_g(q + r s)| / max mu p``: the forces settle
to about 1e-7 mu Fn (``tests/wheelrail/methods/test_discretised.py`` holds them within 1e-6 of a solve 100 times
tighter), four orders below the level's own error estimates."""

NORMAL_TOLERANCE = 1e-8
"""The conjugate gradients' default tolerance on the change of the pressure in one iteration, relative to the load:
two orders below the wheels' vertical balance (:data:`rollcontact.wheelrail.wheels.BALANCE_TOLERANCE`) and six below
the level's own error estimates."""


def solve_discretised(scene: PatchScene, *, element: float | None = None, grid: SurfaceGrid | None = None,
                      extrapolate: bool = False, fields: bool = False, iteration_tolerance: float = ITERATION_TOLERANCE,
                      max_iterations: int = NEWTON_ITERATIONS, normal_tolerance: float = NORMAL_TOLERANCE,
                      start: StripContact | PatchState | None = None) -> PatchResult:
    """Normal and tangential contact of a patch on the discretised half-space (module docstring).

    Parameters
    ----------
    scene : PatchScene
        Any friction law.
    element : float, optional
        Element size [m] (square), ignored with ``grid``; by default :data:`DEFAULT_ELEMENT`, smaller where the
        patch is narrower than :data:`MIN_ACROSS` of them (:func:`automatic_element`).
    grid : SurfaceGrid, optional
        Solve the normal problem on this grid (x along the track, y the patch's s) as given, without sizing or
        growing it.
    extrapolate : bool
        Richardson ``2 F(h) - F(2h)`` of the forces (the normal load and sizes stay the finer grid's); not with
        ``grid``.
    fields : bool
        Attach the pressure and traction on the elements in contact's bounding box.
    iteration_tolerance : float
        Newton's tolerance of the tangential problem on ``max |q - P_g(q + r s)| / max mu p``.
    max_iterations : int
        Newton's cap; a solve that does not converge returns ``success`` False with the reason.
    normal_tolerance : float
        The conjugate gradients' tolerance on the change of the pressure.
    start : StripContact or PatchState, optional
        The strips' normal solution of the same gap nearby, for the strips' solution that sizes the grid to start
        from (:func:`guide_for`); or a wheel's state of the patch (:class:`PatchState`): the normal problem of the
        scene's own gap and normal load, solved already at the default element and tolerance, which the solve takes
        (with ``element``, ``grid`` or ``normal_tolerance`` given, or another load, only its guide), and the
        tractions of its last solve, which the steady iteration starts from (scaled to the normal force); the solve
        records its own tractions in it.

    Returns
    -------
    PatchResult
        ``info``: ``element`` [m], ``elements`` (the normal grid's), ``contact_elements``, ``normal_iterations``,
        ``newton_iterations``, ``operator_applications``, ``residual``, ``stick_fraction``, ``error_estimate``,
        ``normal_error_estimate``, ``pressure_error_estimate``.
    """
    if extrapolate and grid is not None:
        raise ValueError("extrapolate takes the grids from element, not from grid")
    carried, state = None, None
    if isinstance(start, PatchState):
        at_force = scene.normal_load == start.force if start.force is not None else \
            scene.approach is not None and scene.approach == start.normal[2]
        if element is None and grid is None and normal_tolerance == NORMAL_TOLERANCE and at_force:
            carried = start.normal
        state, start = start, start.guide
    guide = guide_for(scene, start) if grid is None else None
    element = automatic_element(guide) if element is None and guide is not None else \
        DEFAULT_ELEMENT if element is None else float(element)
    if not (math.isfinite(element) and element > 0.0):
        raise ValueError(f"element = {element!r} m must be finite and > 0")
    xi, eta, phi = scene.creepages
    mu = scene.friction_coefficient
    fine = solve_on_grid(scene, element, grid, iteration_tolerance, max_iterations, normal_tolerance, guide, carried,
                         None if state is None else state.traction)
    if fine["failure"] is not None:
        return PatchResult("discretised", False, fine["failure"], math.nan, math.nan, math.nan, math.nan, math.nan,
                           math.nan, math.nan, math.nan, xi, eta, phi, mu, math.nan)
    if fine["empty"]:
        return PatchResult("discretised", True, "no contact", 0.0, fine["approach"], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, xi,
                           eta, phi, mu, 0.0, info={"error_estimate": 0.0})
    forces = np.array(fine["forces"])
    messages = list(fine["messages"])
    steady = fine["steady"]
    newton, applications = steady.newton_iterations, steady.applications
    if state is not None:
        state.traction = (fine["grid"], steady.traction_x, steady.traction_y, fine["normal_load"])
    if extrapolate:
        coarse = solve_on_grid(scene, 2.0 * element, None, iteration_tolerance, max_iterations, normal_tolerance,
                               guide)
        if coarse["failure"] is not None or coarse["empty"]:
            messages.append(f"coarse level: {coarse['failure'] or 'no contact'}")
        else:
            forces = 2.0 * forces - np.array(coarse["forces"])
            messages += [f"coarse level: {m}" for m in coarse["messages"]]
            newton += coarse["steady"].newton_iterations
            applications += coarse["steady"].applications
    in_contact = fine["pressure"] > 0.0
    info = {"element": element, "elements": fine["elements"], "contact_elements": fine["contact_elements"],
            "normal_iterations": fine["normal_iterations"], "newton_iterations": newton,
            "operator_applications": applications, "residual": steady.residual,
            "stick_fraction": float(steady.stick[in_contact].mean()), "extrapolate": extrapolate}
    result_fields = None
    if fields:
        x, s = fine["grid"].mesh()
        result_fields = TractionField(x, s, fine["pressure"], steady.traction_x, steady.traction_y,
                                      steady.stick & in_contact)
    provisional = PatchResult("discretised", not messages, "; ".join(messages) or "converged", fine["normal_load"],
                              fine["approach"], fine["max_pressure"], fine["length"], fine["width"],
                              *map(float, forces), xi, eta, phi, mu, fine["area"], result_fields, info)
    info.update(DiscretisedPatchAccuracy().estimates(provisional, element, extrapolate))
    return provisional


solve_discretised.options = ("element", "extrapolate", "fields")


ERROR_PER_ELEMENT = 0.5
"""The error [1] of Fx, Fy (over mu Fn) and Mz (over mu Fn c) on one grid is at most this over the elements across the
patch's shorter extent: a margin over the largest error times that count in ``benchmarks/wheelrail_patches.py``,
table "Tangential" (the default 0.2 mm on the three patches; the two-lobed tread's is the largest)."""

PAIR_ERROR = (20.0, 0.3)
"""The same for the Richardson pair, ``max(20 / N^2, 0.3 / N)``: the elliptic discretised level's
(``benchmarks/bench_elliptic.py``, section B), whose first-order term is above the single grid's constant here."""

NORMAL_PER_ELEMENT = 0.05
PRESSURE_PER_ELEMENT = 0.1
"""Relative errors [1] of Fn (at a given approach) and of the peak pressure times the elements across the shorter
extent: margins over ``benchmarks/wheelrail_patches.py``, table "Normal" (the flange's pressure the largest)."""

SECONDS_PER_ELEMENT = 1e-4
"""Modelled time [s] per element in contact on an idle machine (``benchmarks/wheelrail_patches.py``, table "Time":
the normal and the tangential problem and the grid's sizing by the strips)."""


SPREAD = 2.0
"""Share [1] by which a patch's elements in contact may exceed those of Hertz's ellipse at its deepest point (a second
lobe, a flatter gap across) in :func:`hertz_elements`."""


def hertz_elements(scene: PatchScene, element: float | None) -> float:
    """:data:`SPREAD` times the elements of ``element`` [m] (None: as :func:`automatic_element` sizes them, from the
    ellipse's extent) in Hertz's ellipse ``pi a b`` at the gap's deepest sample under the scene's load (at a given
    approach, Hertz's load there): the curvatures there, A of the gap and B from its samples' second difference, B
    held within a factor 100 of A.  What the patch's grid will hold, before the strips size it; 0 where there is no
    load."""
    s, h, curvature = check_gap(scene.gap)
    k = min(max(int(np.argmin(h)), 1), h.size - 2)
    lateral = ((h[k + 1] - h[k]) / (s[k + 1] - s[k]) - (h[k] - h[k - 1]) / (s[k] - s[k - 1])) / (s[k + 1] - s[k - 1])
    longitudinal = float(curvature[k])
    lateral = min(max(lateral, 0.01 * longitudinal), 100.0 * longitudinal)
    unit = hertz_ellipse(1.0, longitudinal, lateral, scene.material.contact_modulus)
    load = scene.normal_load if scene.normal_load is not None else (scene.approach / unit.approach) ** 1.5
    if not load > 0.0:
        return 0.0
    scale = load ** (1.0 / 3.0)
    a, b = unit.a * scale, unit.b * scale
    if element is None:
        element = max(min(DEFAULT_ELEMENT, 2.0 * min(a, b) / MIN_ACROSS), 4.0 * max(a, b) / MAX_ELEMENTS_3D)
    return SPREAD * math.pi * a * b / (element * element)


class DiscretisedPatchAccuracy(AccuracyModel):
    """First order in the element size: the errors above over the elements across the patch's shorter extent; cost
    proportional to the elements in contact."""

    def ladder(self, scene):
        return tuple({"element": e, "extrapolate": False} for e in (0.4e-3, 0.3e-3, 0.2e-3, 0.15e-3, 0.1e-3))

    def cost(self, scene, options):
        """Before solving: :data:`SECONDS_PER_ELEMENT` per element in contact, at least 1000 of the default element,
        more where Hertz's ellipse at the gap's deepest point (:func:`hertz_elements`) has more."""
        element = options.get("element")
        least = 1000.0 * (DEFAULT_ELEMENT / (DEFAULT_ELEMENT if element is None else element)) ** 2
        return SECONDS_PER_ELEMENT * max(least, hertz_elements(scene, element))

    def error(self, scene, options):
        """Before solving, for a patch 20 default elements across."""
        return ERROR_PER_ELEMENT / 20.0 * options.get("element", DEFAULT_ELEMENT) / DEFAULT_ELEMENT

    def estimates(self, result: PatchResult, element: float, extrapolate: bool) -> dict:
        """``error_estimate``, ``normal_error_estimate``, ``pressure_error_estimate`` of a solved patch."""
        across = max(1.0, min(result.length, result.width) / element)
        tangential = max(PAIR_ERROR[0] / across**2, PAIR_ERROR[1] / across) if extrapolate else \
            ERROR_PER_ELEMENT / across
        return {"error_estimate": tangential, "normal_error_estimate": NORMAL_PER_ELEMENT / across,
                "pressure_error_estimate": PRESSURE_PER_ELEMENT / across}


def discretised_normal_force(gap, approach: float, material, start: StripContact | PatchState | None = None):
    """``(N, state)``: the discretised normal force [N] of a patch at the normal approach [m] and the
    :class:`PatchState` of it, which the patch's solve at that approach takes (the wheel level's normal law).  From
    ``start``, a previous call's on the same gap, as :func:`discretised_loaded_approach`."""
    scene = PatchScene(gap, approach=approach, material=material)
    state = start if isinstance(start, PatchState) else None
    guide = guide_for(scene, start if state is None else state.guide)
    normal = normal_problem(scene, automatic_element(guide), None, NORMAL_TOLERANCE, guide)
    grid, pressure, _, message, _ = normal
    if message is not None:
        raise ArithmeticError(f"the discretised normal problem at approach {approach!r} m failed: {message}")
    return float(pressure.sum() * grid.area), PatchState(guide, None, normal, None if state is None else state.traction)


def discretised_loaded_approach(gap, force: float, material, start: StripContact | PatchState | None = None):
    """``(approach, state)``: the discretised normal approach [m] of a patch carrying the normal force [N]
    (Polonsky & Keer's iteration with the load's constraint; None where it fails) and the :class:`PatchState` of
    it, which the patch's solve at that force takes (the wheel level's solve for a given force).  From ``start``, a
    previous call's on the same gap: its guide, and its tractions, which the state passes on to the solve."""
    scene = PatchScene(gap, normal_load=force, material=material)
    state = start if isinstance(start, PatchState) else None
    guide = guide_for(scene, start if state is None else state.guide)
    normal = normal_problem(scene, automatic_element(guide), None, NORMAL_TOLERANCE, guide)
    return (normal[2] if normal[3] is None else None), \
        PatchState(guide, force, normal, None if state is None else state.traction)


LEVEL = PatchLevel("discretised", discretised_normal_force, solve_discretised, DiscretisedPatchAccuracy(),
                   discretised_loaded_approach)
"""The discretised patch as a patch level of the wheels (:mod:`rollcontact.wheelrail.wheels`)."""

METHOD = wheel_method(LEVEL, rank=100, fallback=True)
