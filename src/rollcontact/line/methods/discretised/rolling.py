"""Rolling over a surface as a true transient: :func:`roll_over_surface` and its :class:`RollingHistory`.

The cylinder rolls over ``scene.surface`` step by step on an axis-fixed grid, the normal problem solved afresh at
each axis position and the tangential one by :class:`~rollcontact.line.halfspace.solver.TransientSolver`, in force or
creep control.  It is the reference for the quasi-steady corrugation formulas (paper eqs 28-31), which freeze the
geometry; a module of its own because it is no steady solve and is not registered as a method.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rollcontact.core.halfspace.elements import Grid
from rollcontact.line.halfspace.grid import (
    ITERATION_TOLERANCE,
    automatic_grid,
    check_count,
    patch_geometry,
    positive_length,
)
from rollcontact.line.halfspace.solver import TransientSolver, TransientState
from rollcontact.line.scene import Scene


# ------------------------------------------------------------------------------------------ rolling over a surface
@dataclass(frozen=True)
class RollingHistory:
    """Transient rolling over a surface: one entry per axis position (index 0: the steady start).

    Attributes
    ----------
    distance : ndarray
        Rolled distance [m], ``k ds``.
    axis_position : ndarray
        x_c [m] = x_c0 - k ds (the cylinder rolls towards -X, material flows in +x).
    tangential_force_per_length, creep : ndarray
        T' [N/m] and xi [1] (one of them prescribed).
    contact_half_width, contact_offset, stick_half_width, max_pressure : ndarray
        a [m], Delta [m], a* [m] (half the stick length), max p [Pa].
    patches : ndarray
        Number of contact patches.
    grid : Grid
        The axis-fixed grid used.
    final_state : TransientState
        State after the last step (to continue rolling).
    success : bool
        False when a step did not converge or a patch reached the window edge (arrays then end there).
    message : str
        Status.
    """

    distance: np.ndarray
    axis_position: np.ndarray
    tangential_force_per_length: np.ndarray
    creep: np.ndarray
    contact_half_width: np.ndarray
    contact_offset: np.ndarray
    stick_half_width: np.ndarray
    max_pressure: np.ndarray
    patches: np.ndarray
    grid: Grid = field(repr=False)
    final_state: TransientState = field(repr=False)
    success: bool = True
    message: str = ""


def roll_over_surface(scene: Scene, distance: float, steps: int, *, tangential_force_per_length=None,
                      elements=None, window=None, datum_length=None,
                      iteration_tolerance: float = ITERATION_TOLERANCE) -> RollingHistory:
    """Roll the cylinder over ``scene.surface`` as a true transient, from steady rolling at ``scene.axis_position``.

    Each step of ``ds = distance/steps`` moves the axis by -ds over the surface (x_c = x_c0 - k ds), solves the
    normal problem there (quasi-static, no memory) and takes one :meth:`TransientSolver.step` (material convected
    by ds through the axis-fixed grid).  Control: T' fixed (``tangential_force_per_length``, datum-free as long
    as T' is constant) or ``scene.creep``.  This is the reference for the quasi-steady corrugation formulas
    (paper eqs 28-31 as corrected in docs/physics.md, Corrugated surface): with the patch centre moving as
    ``Delta(x_c)`` the creep for a given T' is close to the frozen-geometry value times ``1 + dDelta/dx_c``.

    Parameters
    ----------
    scene : Scene
        Geometry, load, friction (constant), start position; ``scene.creep`` in creep control.
    distance : float
        Rolled distance [m] > 0.
    steps : int
        Number of steps >= 1.
    tangential_force_per_length : float, optional
        T' [N/m] for force control.
    elements, window, datum_length, iteration_tolerance
        As in :func:`rollcontact.line.methods.discretised.steady.solve_discretised`; the automatic window covers every
        axis position of the roll.
    """
    distance = positive_length("distance", distance)
    check_count("steps", steps, 1)
    if not scene.friction.is_constant:
        raise ValueError(f"roll_over_surface needs constant friction, got {scene.friction!r}: with dmu/dv < 0 "
                         "the transient problem is ill-posed")
    if scene.normal_load_per_length == 0.0:
        raise ValueError("normal_load_per_length = 0.0 N/m: nothing to roll on; it must be > 0")
    ds = distance / steps
    positions = scene.axis_position - ds * np.arange(steps + 1)
    grid = automatic_grid(scene, elements, window, axis_positions=positions)
    solver = TransientSolver.from_scene(scene, grid, datum_length=datum_length, iteration_tolerance=iteration_tolerance)
    control = ({"tangential_force": float(tangential_force_per_length)}
               if tangential_force_per_length is not None else {"creep": scene.creep})
    columns = {k: np.full(steps + 1, np.nan) for k in ("t", "xi", "a", "delta", "astar", "pmax", "patches")}
    state = None
    success, message, last = True, "completed", steps
    for k, x_c in enumerate(positions):
        normal = solver.normal(scene.normal_load_per_length, x_c)
        if not normal.converged or normal.contact[0] or normal.contact[-1]:
            success, last = False, k - 1
            message = (f"step {k}: normal problem {normal.message}" if not normal.converged else
                       f"step {k}: a patch reaches the window edge ({grid.x_min!r}, {grid.x_max!r}) m")
            break
        if state is None:
            state, res = solver.steady_state(normal.pressure, **control)
        else:
            state, res = solver.step(state, normal.pressure, ds, **control)
        if not res.converged:
            success, last, message = False, k - 1, f"step {k}: {res.message}"
            break
        a, offset, patches = patch_geometry(grid, normal.contact)
        for key, value in (("t", res.tangential_force_per_length), ("xi", res.creep), ("a", a),
                           ("delta", offset), ("astar", 0.5 * grid.element_width * res.stick_elements),
                           ("pmax", normal.pressure.max()), ("patches", len(patches))):
            columns[key][k] = value
    keep = slice(0, last + 1)
    return RollingHistory(ds * np.arange(steps + 1)[keep], positions[keep], columns["t"][keep],
                          columns["xi"][keep], columns["a"][keep], columns["delta"][keep], columns["astar"][keep],
                          columns["pmax"][keep], columns["patches"][keep].astype(int), grid,
                          state if state is not None else solver.initial_state(), success, message)
