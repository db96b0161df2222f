"""Where the discretised half-space's elements go: the automatic grid of a scene, and the checks of grid options.

:func:`automatic_grid` chooses a window from the Hertz width and the surface (at least
:data:`ELEMENTS_PER_WAVELENGTH` elements per shortest surface wavelength) and :func:`patch_geometry` reads the
contact's half-width, offset and patches off a solved grid.  A module of its own because the steady method, its
accuracy model and the transient solver all place grids the same way, and the accuracy model needs the grid
without the solver.
"""

from __future__ import annotations

import math

import numpy as np

from rollcontact.core.checks import check_real
from rollcontact.core.halfspace.elements import MAX_ELEMENTS, Grid, runs
from rollcontact.line.hertz import hertz
from rollcontact.line.scene import Scene

DEFAULT_ELEMENTS = 200


ELEMENTS_PER_WAVELENGTH = 16  # piecewise-constant elements per shortest surface wavelength


ITERATION_TOLERANCE = 1e-9


WINDOW_RETRIES = 3


CONTACT_MARGIN = 0.05  # of the patches' span, each side of contact_window (plus two search elements)


def check_iteration_tolerance(iteration_tolerance) -> float:
    try:
        value = float(iteration_tolerance)
    except (TypeError, ValueError):
        raise ValueError(f"iteration_tolerance must be a real number, got {iteration_tolerance!r}") from None
    if not 1e-14 <= value <= 1e-3:
        raise ValueError(f"iteration_tolerance = {value!r} is out of range: it must lie in [1e-14, 1e-3]")
    return value


def check_window(window) -> tuple[float, float]:
    try:
        x_min, x_max = (float(v) for v in window)
    except (TypeError, ValueError):
        raise ValueError(f"window must be a pair (x_min, x_max) of reals in m, got {window!r}") from None
    return x_min, x_max


def positive_length(name: str, value, unit: str = "m") -> float:
    """A finite quantity > 0 (a ValueError naming the value and the limit otherwise)."""
    return check_real(name, value, lower=0.0, lower_open=True, unit=unit)


def check_count(name: str, value, lower: int, upper: int | None = None, why: str = "") -> int:
    """An integer count in [lower, upper] (no upper limit when None; a ValueError naming the value, the limits and
    ``why`` otherwise)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < lower or (
            upper is not None and value > upper):
        limits = f">= {lower}" if upper is None else f"in [{lower}, {upper}]"
        raise ValueError(f"{name} must be an integer {limits}{why}, got {value!r}")
    return int(value)


# --------------------------------------------------------------------------------------------------- grid choice
def automatic_grid(scene: Scene, elements=None, window=None, axis_positions=None, widen: float = 1.0) -> Grid:
    """Grid for a scene: the given window and element count, or chosen from the Hertz width and the surface.

    The window covers every x where the rigid gap ``h0 = x^2/(2R) - Z(x + x_c)`` lies within
    ``1.15^2 a_H^2/(2R) + 2 sum|Z_m|`` of its minimum, for each axis position x_c (a_H the Hertz half-width,
    ``a_H^2/(2R) = 2N'/(pi E*)`` the Hertz depth, ``Z_m`` the harmonic amplitudes): the Hertz patch with 15 %
    margin, plus the depth the corrugation can add, padded by 2 %.  ``widen`` scales it about its centre (used
    when a patch reaches the window edge).  Elements: ``elements`` or ``max(200, 16 per shortest wavelength)``.

    Raises
    ------
    ValueError
        Element count out of [8, 4000], or an empty/non-finite window.
    """
    if window is None:
        positions = np.atleast_1d(np.asarray(scene.axis_position if axis_positions is None else axis_positions,
                                             dtype=float))
        a_h = hertz(scene.normal_load_per_length, scene.radius, scene.material.contact_modulus)[0]
        amplitude = sum(h.amplitude for h in scene.surface.harmonics)
        poly = scene.surface.polynomial
        centre = scene.radius * poly[1] if len(poly) > 1 else 0.0
        half = 4.0 * a_h + math.sqrt(8.0 * scene.radius * amplitude) + 1e-9
        shortest = min((2 * math.pi / h.wavenumber for h in scene.surface.harmonics if h.amplitude > 0),
                       default=math.inf)
        samples = int(min(200_000, max(2001, 40 * 2 * half / shortest)))
        xs = centre + np.linspace(-half, half, samples)
        # positions in chunks keep the (positions x samples) table small for long rolls
        inside = np.zeros(samples, dtype=bool)
        for chunk in np.array_split(positions, max(1, positions.size * samples // 2_000_000 + 1)):
            gap = xs**2 / (2.0 * scene.radius) - scene.surface.height(xs[None, :] + chunk[:, None])
            rel = gap - gap.min(axis=1, keepdims=True)
            inside |= (rel <= 1.3225 * a_h**2 / (2.0 * scene.radius) + 2.0 * amplitude).any(axis=0)
        lo, hi = xs[inside].min(), xs[inside].max()
        mid, half_width = 0.5 * (lo + hi), 0.51 * (hi - lo) * widen
        window = (mid - half_width, mid + half_width)
    x_min, x_max = check_window(window)
    if elements is None:
        shortest = min((2 * math.pi / h.wavenumber for h in scene.surface.harmonics if h.amplitude > 0),
                       default=math.inf)
        elements = max(DEFAULT_ELEMENTS, math.ceil(ELEMENTS_PER_WAVELENGTH * (x_max - x_min) / shortest))
        if elements > MAX_ELEMENTS:
            raise ValueError(f"resolving the shortest surface wavelength {shortest!r} m over the window "
                             f"({x_min!r}, {x_max!r}) m needs {elements} elements, above the limit {MAX_ELEMENTS}")
    return Grid(x_min, x_max, elements)


# ---------------------------------------------------------------------------------------------- solve_discretised
def patch_geometry(grid: Grid, contact: np.ndarray) -> tuple[float, float, list[tuple[float, float]]]:
    """Half-width a and offset Delta from the outer patch edges (element boundaries), and the patch list [m]."""
    h = grid.element_width
    spans = runs(contact)
    if not spans:
        return 0.0, 0.0, []
    patches = [(grid.x_min + start * h, grid.x_min + stop * h) for start, stop in spans]
    lead, trail = patches[0][0], patches[-1][1]
    # a from the element count, like the stick half-width (0.5 h n_stick): a* <= a holds exactly
    return 0.5 * h * (spans[-1][1] - spans[0][0]), 0.5 * (trail + lead), patches
