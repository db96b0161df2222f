"""Discretised reference solver (Kalker-type boundary elements), registered as method ``"discretised"``.

The accuracy yardstick for the polynomial method and the fallback where it cannot apply (split contacts, rough
profiles, velocity-dependent friction, instationary rolling).  Conventions are the package's (physics.md
section 1): x is fixed to the cylinder axis (``x = X - x_c``), material flows in +x, the leading edge is
``x = Delta - a``, ``du/dx = +(2/(pi E*)) PV-int q(z)/(x - z) dz``, ``s = xi + du/dx + (1/V) du/dt`` and in
slip ``q = mu p sign(s)``.

Discretisation (Kalker, *Three-Dimensional Elastic Bodies in Rolling Contact*, Kluwer 1990, ch. 5):
piecewise-constant p and q on a uniform grid of n elements, influence coefficients integrated exactly over each
element (log kernel for displacements, Cauchy kernel for gradients), collocation at the element centres.

* Normal problem (NORM): ``g = h0 + M p - c >= 0``, ``p >= 0``, ``p g = 0``, ``h sum p = N'`` with the
  undeformed gap ``h0 = x^2/(2R) - Z(x + x_c)``, solved exactly by an active set for any gap, several patches
  included; the certificate (load balance, gap >= 0, p >= 0, complementarity) is returned.
* Tangential transient (TANG): per step of rolled distance ``ds = V dt`` the particle now at x_i was at
  ``x_i - ds``, so the slip distance is ``S_i = w + u_new(x_i) - u_old(x_i - ds)`` (w = xi ds the rigid
  shift); stick ``S = 0``, slip ``q = mu p sign(S)``.  This is the upwind (first-order) discretisation of
  ``s = xi + (1/V) Du/Dt``; the old displacement at the shifted points is integrated exactly for any ds.
* Steady rolling: the fixed point of that stepper for ``ds = h``, ``s = xi - K q`` with ``K = (M - M_1)/h``,
  solved directly by the same active set, or reached by marching (``steady="march"``).
* Velocity-dependent friction (``steady="structured"``): a stick zone at the leading edge of each patch, slip
  behind it with ``q = mu(V |s|) p sign(xi)`` (paper section 4.2); Newton on the slip for each set of stick
  lengths, bisection on each patch's stick length (the shortest stick zone behind which the material slips in the
  traction's direction), the patches' zones in turn until none changes.
  With dmu/dv < 0 the transient problem is ill-posed, so this is the only way to that steady state
  (physics.md section 5).

Datum: in 2D the tangential displacement is defined relative to a datum distance L (physics.md section 6).
Force control is datum-free; creep control of a transient is not, and is well posed only for L above the
logarithmic capacity of the grid, a quarter of its length.  The default ``datum_length`` is the cylinder
radius R: the size of the body, beyond which the half-space idealisation that produces the logarithm fails.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy import linalg

from rollcontact._bem import (
    MAX_ELEMENTS,
    MIN_ELEMENTS,
    Control,
    Grid,
    NormalSolution,
    Operators,
    initial_stick,
    operators_for,
    runs,
    solve_normal,
    solve_stick_slip,
    tangential_certificate,
)
from rollcontact.api import DISCRETISED_ELEMENTS, register_method
from rollcontact.closed_form import hertz
from rollcontact.friction import Coulomb, FrictionLaw
from rollcontact.result import ContactResult, NoContact, TabulatedDistributions
from rollcontact.scene import Scene, Surface, check_real

__all__ = ["Grid", "NormalSolution", "RollingHistory", "StepResult", "TransientSolver", "TransientState",
           "automatic_grid", "contact_window", "extrapolated", "inapplicable", "roll_over_surface",
           "solve_discretised"]

DEFAULT_ELEMENTS = 200
ELEMENTS_PER_WAVELENGTH = 16  # piecewise-constant elements per shortest surface wavelength
DEFAULT_TOLERANCE = 1e-9
STEADY_MODES = ("direct", "march", "structured")
STRUCTURED_SWEEPS = 8  # of the several-patch stick-zone search (each patch's zone with the others held)
WINDOW_RETRIES = 3
CONTACT_MARGIN = 0.05  # of the patches' span, each side of contact_window (plus two search elements)


def check_tolerance(tolerance) -> float:
    try:
        value = float(tolerance)
    except (TypeError, ValueError):
        raise ValueError(f"tolerance must be a real number, got {tolerance!r}") from None
    if not 1e-14 <= value <= 1e-3:
        raise ValueError(f"tolerance = {value!r} is out of range: it must lie in [1e-14, 1e-3]")
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


def contact_window(scene: Scene) -> tuple[float, float]:
    """A window (x_min, x_max) [m] fitted to the contact: the patches of a normal solve on :func:`automatic_grid`
    (its element count), plus :data:`CONTACT_MARGIN` of their span and two search elements on each side (a patch
    edge moves by less than one element between resolutions); :func:`automatic_grid`'s window without harmonics
    or when the search fails.

    For references (:func:`extrapolated`): the rigid-gap window adds the corrugation's depth ``2 sum|Z_m|`` to the
    Hertz depth and is 1.5-4.5 times wider than the contact on ``benchmarks/pareto.py``'s corrugations, so at the
    same element count this window's elements are that much finer.  It is not the solver's default: the cost of a
    solve grows with the elements in contact, not with those outside it, so at equal accuracy the fitted window
    saved nothing and its search doubled the cost of a discretised FMU step (measured in ``benchmarks/pareto.py``).
    """
    if scene.normal_load_per_length == 0.0 or not any(h.amplitude > 0.0 for h in scene.surface.harmonics):
        grid = automatic_grid(scene)
        return grid.x_min, grid.x_max
    grid, _, normal = fitted_normal(scene)
    if not normal.converged or normal.contact[0] or normal.contact[-1]:
        return grid.x_min, grid.x_max
    _, _, patches = patch_geometry(grid, normal.contact)
    lo, hi = patches[0][0], patches[-1][1]
    margin = CONTACT_MARGIN * (hi - lo) + 2.0 * grid.element_width
    return max(lo - margin, grid.x_min), min(hi + margin, grid.x_max)


def fitted_normal(scene: Scene, elements=None, window=None, *, datum_length=None,
                  tolerance: float = DEFAULT_TOLERANCE) -> tuple[Grid, TransientSolver, NormalSolution]:
    """The normal problem on :func:`automatic_grid`, widened 1.5 times per retry (at most :data:`WINDOW_RETRIES`)
    while the contact reaches the window's edge; a given ``window`` is kept.  Returns the grid, its solver (datum
    ``datum_length``, default the grid length) and the normal solution, which may still touch the edge."""
    for attempt in range(WINDOW_RETRIES + 1):
        grid = automatic_grid(scene, elements, window, widen=1.5**attempt)
        solver = TransientSolver.from_scene(scene, grid, datum_length=grid.length if datum_length is None
                                            else datum_length, tolerance=tolerance)
        normal = solver.normal(scene.normal_load_per_length, scene.axis_position)
        if window is not None or not (normal.contact[0] or normal.contact[-1]):
            break
    return grid, solver, normal


# ------------------------------------------------------------------------------------------- transient stepper
@dataclass(frozen=True)
class TransientState:
    """Explicit, copyable state of a transient (all arrays on the solver's grid).

    Attributes
    ----------
    traction : ndarray
        q_i [Pa] after the last step.
    stick : ndarray
        Boolean stick mask after the last step (warm start of the next active set).
    slip : ndarray
        s_i = S_i / ds [1] of the last step (0 for a static step and outside contact); the friction law is
        evaluated at the slip velocity ``V |s|`` of the previous step.
    tangential_force_per_length : float
        T' = h sum q [N/m].
    steps : int
        Steps taken since the initial state.
    """

    traction: np.ndarray
    stick: np.ndarray
    slip: np.ndarray
    tangential_force_per_length: float = 0.0
    steps: int = 0

    def copy(self) -> TransientState:
        """Deep copy (the arrays are copied)."""
        return TransientState(self.traction.copy(), self.stick.copy(), self.slip.copy(),
                              self.tangential_force_per_length, self.steps)


@dataclass(frozen=True)
class StepResult:
    """Outcome of one transient step (or of a steady solve).

    Attributes
    ----------
    tangential_force_per_length : float
        T' [N/m] after the step.
    creep : float
        xi [1] (given in creep control, found in force control; NaN for a static step ds = 0).
    rigid_shift : float
        w = xi ds [m] for the solver's datum (the static shift when ds = 0).
    slip_distance : ndarray
        S_i [m] over the step (for the steady state: the slip s_i [1]).
    dissipation : float
        Frictional work per unit length ``h sum q_i S_i`` [J/m] in the step (>= 0).
    stick_elements : int
        Elements in stick.
    iterations : int
        Active-set iterations.
    converged : bool
        False when the active set did not settle; ``message`` says why.
    message : str
        Status.
    certificate : dict
        See :func:`rollcontact._bem.tangential_certificate`.
    """

    tangential_force_per_length: float
    creep: float
    rigid_shift: float
    slip_distance: np.ndarray = field(repr=False)
    dissipation: float
    stick_elements: int
    iterations: int
    converged: bool
    message: str
    certificate: dict = field(repr=False)


class TransientSolver:
    """Kalker's transient rolling (TANG) on a fixed grid: one step of rolled distance per call.

    Per step ``ds = V dt >= 0`` the slip distance is ``S = w + u_new(x) - u_old(x - ds)`` with
    ``u = (2/(pi E*)) int q(z) ln(|x - z|/L) dz`` (the log kernel integrated exactly over each element, also at
    the shifted points), w = xi ds; stick ``S = 0`` and ``|q| <= mu p``, slip ``q = mu p sign(S)``.  Creep
    control (xi given) depends on the datum L, force control (T' given) does not: for a datum L,
    ``xi_L = xi_Lw + (2/(pi E*)) ln(L/L_w) dT'/ds`` (physics.md section 6), which is how both are solved with
    one SPD matrix of datum L_w.  ``ds = 0`` is a static step (Cattaneo, Mindlin-Deresiewicz); force control only.

    Parameters
    ----------
    grid : Grid
        Elements [m] (axis-fixed).
    contact_modulus : float
        E* [Pa].
    radius : float
        Effective radius R [m] (gap of the normal problem).
    surface : Surface
        Counter-surface Z(X).
    friction : FrictionLaw
        mu(v); evaluated at the previous step's slip velocity.
    rolling_speed : float
        V [m/s] (slip velocity ``v = V |s|``).
    datum_length : float, optional
        L [m] of the tangential displacement; default ``radius``.  Creep control needs ``L > grid.length / 4``.
    tolerance : float
        Relative tolerance of the active sets.

    Examples
    --------
    >>> solver = TransientSolver.from_scene(scene)                   # doctest: +SKIP
    >>> normal = solver.normal(scene.normal_load_per_length)          # doctest: +SKIP
    >>> state = solver.initial_state()                                # doctest: +SKIP
    >>> state, step = solver.step(state, normal.pressure, solver.grid.element_width, creep=1e-3)  # doctest: +SKIP
    """

    def __init__(self, grid: Grid, *, contact_modulus: float, radius: float, surface: Surface | None = None,
                 friction: FrictionLaw | None = None, rolling_speed: float = 1.0, datum_length=None,
                 tolerance: float = DEFAULT_TOLERANCE):
        if not isinstance(grid, Grid):
            raise TypeError(f"grid must be a rollcontact.discretised.Grid, got {type(grid).__name__}")
        self.grid = grid
        self.contact_modulus = positive_length("contact_modulus", contact_modulus, "Pa")
        self.radius = positive_length("radius", radius)
        self.surface = Surface() if surface is None else surface
        self.friction = Coulomb(0.3) if friction is None else friction
        if not isinstance(self.friction, FrictionLaw):
            raise TypeError(f"friction must be a FrictionLaw, got {type(self.friction).__name__}")
        self.rolling_speed = float(rolling_speed)
        if not (math.isfinite(self.rolling_speed) and self.rolling_speed >= 0.0):
            raise ValueError(f"rolling_speed = {rolling_speed!r} m/s is out of range: it must be finite and >= 0")
        self.datum_length = self.radius if datum_length is None else positive_length("datum_length", datum_length)
        self.tolerance = check_tolerance(tolerance)
        self.ops = operators_for(grid, self.contact_modulus)
        # datum term: u_L = u_Lw - kappa ln(L/L_w) T' for every x
        self.datum_factor = self.ops.kappa * math.log(self.datum_length / self.ops.working_datum)
        self.max_iterations = 4 * grid.elements + 50

    @classmethod
    def from_scene(cls, scene: Scene, grid: Grid | None = None, *, elements=None, window=None,
                   datum_length=None, tolerance: float = DEFAULT_TOLERANCE) -> TransientSolver:
        """Solver for a scene's material, radius, surface, friction and speed (grid: given or automatic)."""
        grid = automatic_grid(scene, elements, window) if grid is None else grid
        return cls(grid, contact_modulus=scene.material.contact_modulus, radius=scene.radius,
                   surface=scene.surface, friction=scene.friction, rolling_speed=scene.rolling_speed,
                   datum_length=datum_length, tolerance=tolerance)

    def gap(self, axis_position: float = 0.0) -> np.ndarray:
        """Undeformed gap ``h0(x_i) = x_i^2/(2R) - Z(x_i + x_c)`` [m] at the element centres."""
        x = self.grid.centres
        return x**2 / (2.0 * self.radius) - self.surface.height(x + axis_position)

    def normal(self, normal_load_per_length: float, axis_position: float = 0.0) -> NormalSolution:
        """Normal problem (NORM active set with the load constraint) for N' [N/m] > 0 at axis position x_c [m]."""
        load = float(normal_load_per_length)
        if not (math.isfinite(load) and load > 0.0):
            raise ValueError(f"normal_load_per_length = {normal_load_per_length!r} N/m is out of range: "
                             "it must be finite and > 0")
        return solve_normal(self.ops, self.gap(axis_position), load, self.tolerance, self.max_iterations)

    def initial_state(self) -> TransientState:
        """Unloaded state: q = 0 everywhere, everything in stick."""
        n = self.grid.elements
        return TransientState(np.zeros(n), np.ones(n, dtype=bool), np.zeros(n))

    def check_pressure(self, pressure) -> np.ndarray:
        p = np.asarray(pressure, dtype=float)
        if p.shape != (self.grid.elements,):
            raise ValueError(f"pressure must have shape ({self.grid.elements},) (one value per element), "
                             f"got {p.shape}")
        if not (p.min() >= 0.0 and p.max() < math.inf):  # NaN fails the first test
            raise ValueError(f"pressure must be finite and >= 0, got minimum {float(p.min())!r} Pa and maximum "
                             f"{float(p.max())!r} Pa")
        return p

    def control(self, creep, tangential_force, bound) -> tuple[str, float]:
        if (creep is None) == (tangential_force is None):
            raise ValueError("give exactly one of creep (creep control) or tangential_force (force control)")
        if creep is not None:
            value = float(creep)
            if not math.isfinite(value):
                raise ValueError(f"creep must be finite, got {creep!r}")
            if self.datum_length <= 0.25 * self.grid.length:
                raise ValueError(f"creep control needs datum_length = {self.datum_length!r} m above a quarter of "
                                 f"the grid length ({0.25 * self.grid.length!r} m); use force control or a "
                                 "larger datum")
            return "creep", value
        value = float(tangential_force)
        limit = self.grid.element_width * bound.sum()
        if not (math.isfinite(value) and abs(value) < limit):
            raise ValueError(f"tangential_force = {tangential_force!r} N/m is out of range: |T'| must be below "
                             f"the friction limit sum(mu p) h = {limit!r} N/m")
        return "force", value

    def step(self, state: TransientState, pressure, distance: float, *, creep=None,
             tangential_force=None) -> tuple[TransientState, StepResult]:
        """Advance the transient by a rolled distance ``ds = V dt`` [m] (0: a static step).

        Parameters
        ----------
        state : TransientState
            State before the step (not modified).
        pressure : array_like
            p_i [Pa] after the step (e.g. ``self.normal(N', x_c).pressure``).
        distance : float
            ds >= 0 [m]; ``ds = h`` convects exactly one element per step.
        creep : float, optional
            xi [1] during the step (creep control; needs ds > 0 and the datum condition).
        tangential_force : float, optional
            T' [N/m] after the step (force control, datum-free).

        Returns
        -------
        state : TransientState
            New state.
        result : StepResult
            Forces, creep, slip, dissipation, convergence.
        """
        if not isinstance(state, TransientState):
            raise TypeError(f"state must be a TransientState, got {type(state).__name__}")
        p = self.check_pressure(pressure)
        ds = float(distance)
        if not (math.isfinite(ds) and ds >= 0.0):
            raise ValueError(f"distance = {distance!r} m is out of range: it must be finite and >= 0")
        friction = self.friction
        mu = (friction.static_coefficient if friction.is_constant
              else friction.coefficient(self.rolling_speed * np.abs(state.slip)))
        bound = mu * p
        contact = p > 0.0
        mode, value = self.control(creep, tangential_force, bound)
        if mode == "creep" and ds == 0.0:
            raise ValueError("creep control needs distance > 0 (a static step has no creep); use force control")
        ops = self.ops
        h = self.grid.element_width
        told = state.tangential_force_per_length
        lam = self.datum_factor
        # c = w - lam (T'_new - T'_old) is the constant slip term for the working datum
        control = Control(1.0, lam, value * ds + lam * told) if mode == "creep" else Control(0.0, 1.0, value)
        b = ops.convected(ds) @ state.traction
        default_sign = 1.0 if value >= 0 else -1.0
        sign0 = np.where(state.traction > 0, 1.0, np.where(state.traction < 0, -1.0, default_sign))
        stick0 = contact & (state.stick | (state.traction == 0.0))
        scale = ops.kappa * max(bound.max(), 1e-300) * max(ds, h)
        sol = solve_stick_slip(ops.M, ops.m_factors, b, bound, contact, control, h, stick0, sign0,
                               self.tolerance * scale, self.max_iterations)
        q = sol.traction
        t_new, slip_distance, certificate, converged, message = self.certify(sol, bound, contact, scale, mode,
                                                                              value)
        shift = sol.constant + lam * (t_new - told)
        new_state = TransientState(q, sol.stick & contact, slip_distance / ds if ds > 0 else np.zeros_like(q),
                                   t_new, state.steps + 1)
        result = StepResult(t_new, shift / ds if ds > 0 else math.nan, shift, slip_distance,
                            float(h * np.dot(q, slip_distance)), int((sol.stick & contact).sum()),
                            sol.iterations, converged, message, certificate)
        return new_state, result

    def steady_state(self, pressure, *, creep=None, tangential_force=None,
                     state: TransientState | None = None) -> tuple[TransientState, StepResult]:
        """Steady rolling directly: the fixed point of :meth:`step` with ``ds = h`` (Coulomb friction mu(0)).

        Solves ``s = xi - K q`` with stick ``s = 0``, slip ``q = mu p sign(s)`` by the active set, starting from
        ``state`` (e.g. after marching) or from Carter's structure (stick at the leading edge, length from
        eq 17 with the patch width).  Datum-free in both controls.  The returned ``slip_distance`` is the
        slip s [1].
        """
        p = self.check_pressure(pressure)
        mu = self.friction.static_coefficient
        bound = mu * p
        contact = p > 0.0
        mode, value = self.control(creep, tangential_force, bound)
        ops = self.ops
        h = self.grid.element_width
        control = Control(1.0, 0.0, value) if mode == "creep" else Control(0.0, 1.0, value)
        sign = 1.0 if value >= 0 else -1.0
        if state is None:
            load = h * p.sum()
            if mode == "creep":
                half = 0.5 * h * contact.sum()
                fraction = max(0.0, 1.0 - self.radius * abs(value) / (mu * half)) if half > 0 else 0.0
            else:
                fraction = math.sqrt(max(0.0, 1.0 - abs(value) / (mu * load)))
            stick0 = initial_stick(contact, fraction)
            sign0 = np.full(p.size, sign)
        else:
            stick0 = state.stick & contact
            sign0 = np.where(state.traction != 0, np.sign(state.traction), sign)
        scale = ops.kappa * max(bound.max(), 1e-300)
        sol = solve_stick_slip(ops.K, ops.k_factors, np.zeros(p.size), bound, contact, control, h, stick0, sign0,
                               self.tolerance * scale, self.max_iterations)
        q = sol.traction
        t_new, slip, certificate, converged, message = self.certify(sol, bound, contact, scale, mode, value)
        steps = 0 if state is None else state.steps
        new_state = TransientState(q, sol.stick & contact, slip, t_new, steps)
        result = StepResult(t_new, sol.constant, sol.constant * h, slip, float(h * np.dot(q, slip)),
                            int((sol.stick & contact).sum()), sol.iterations, converged, message, certificate)
        return new_state, result

    def steady_creep_stiffness(self, stick: np.ndarray) -> float:
        """dT'/dxi [N/m] of a steady creep-controlled solution with the stick set ``stick``: ``h 1^T K_SS^-1 1``.

        In steady rolling ``s = xi - K q``: with the sets fixed, the stick tractions are
        ``q_S = K_SS^-1 (xi 1 - K_SP q_P)`` and the slip tractions ``mu p sign(s)`` do not depend on xi, so
        ``dq_S/dxi = K_SS^-1 1``, the vector the active set's cached factorisation already holds.  0 in full slip.
        The derivative of the discrete solution for its sets (an element crossing the stick/slip boundary is not
        differentiated, as in a one-sided difference that stays within the sets).
        """
        if not stick.any():
            return 0.0
        _, z, _ = self.ops.k_factors.get(stick)
        return self.grid.element_width * float(z.sum())

    def certify(self, sol, bound, contact, scale, mode, value):
        """T', slip (zero in stick), certificate, converged flag and message of a stick/slip solution.

        Shared by :meth:`step` and :meth:`steady_state`: the certificate is taken on the raw slip (it holds the
        round-off actually found in the stick set) before stick elements are set to S = 0 by definition.
        """
        h = self.grid.element_width
        t_new = h * sol.traction.sum()
        slip = np.where(contact, sol.slip, 0.0)
        certificate = tangential_certificate(sol.traction, slip, sol.stick, bound, contact, scale)
        if mode == "force":
            certificate["force_balance"] = abs(t_new - value) / max(h * bound.sum(), 1e-300)
        converged = sol.converged and max(certificate.values()) <= 100.0 * self.tolerance
        message = sol.message if not sol.converged or converged else f"certificate fails: {certificate}"
        slip[sol.stick] = 0.0
        return t_new, slip, certificate, converged, message


# ------------------------------------------------------------------------------ velocity-dependent friction
@dataclass(frozen=True)
class StructuredSteady:
    """Steady solution with a stick zone at the leading edge of each patch (velocity-dependent friction)."""

    traction: np.ndarray
    slip: np.ndarray
    stick: np.ndarray
    iterations: int
    converged: bool
    message: str
    certificate: dict
    creep_slope: float = math.nan  # d(sum q)/dxi [Pa]: dT'/dxi over the element width, for the final sets


def steady_leading_edge_stick(ops: Operators, pressure: np.ndarray, creep: float, law: FrictionLaw,
                              speed: float, tolerance: float, stick_fraction: float = 0.5) -> StructuredSteady:
    """Steady rolling with ``q = mu(V |s|) p sign(xi)`` in slip and a stick zone at the leading edge of each patch.

    For stick zones S (in patch k, m_k elements starting j0_k elements behind its leading edge; j0_k > 0 only
    where the pressure of the first elements is too small to hold their stick traction) the stick tractions are
    eliminated, ``q_S = K_SS^-1 (xi - K_SP Q(s_P))``, and the slip of the other elements P of all patches satisfies
    ``R(s) = s - (xi - K_PS K_SS^-1 xi) + (K_PP - K_PS K_SS^-1 K_SP) Q(s) = 0``, ``Q(s) = mu(V|s|) p sign(xi)``,
    solved by damped Newton (paper section 4.2; Nielsen & Theiler 1996).  A patch's stick length is the smallest
    m_k for which its material slips in the direction of the traction, ``sign(xi) s >= 0`` (bisection on m_k; for
    a Coulomb law on one patch this is Carter's a*); j0_k grows while the first stick element exceeds ``mu(0) p``.
    The patches act on each other through K: with several, each patch's zone is found with the others' held, in
    sweeps until none changes (at most :data:`STRUCTURED_SWEEPS`).  The certificate checks both conditions on every
    element.  ``stick_fraction`` (e.g. Carter's a*/a) seeds the search for each m_k, as that fraction of the patch.

    ``creep_slope`` is ``d(sum q)/dxi`` for the final sets by the implicit function theorem: ``r0`` and ``q_S`` are
    linear in xi, so ``(I + Schur dQ/ds) ds/dxi = r0/xi`` and ``dq_S/dxi = y0/xi - W dq_P/dxi``.
    """
    contact = pressure > 0.0
    n = pressure.size
    spans = runs(contact)
    if not spans:
        return StructuredSteady(np.zeros(n), np.zeros(n), contact.copy(), 0, False, "no contact patch", {})
    elements = np.flatnonzero(contact)  # the patches' elements in order
    sizes = [stop - start for start, stop in spans]
    offsets = np.cumsum([0, *sizes[:-1]]).tolist()  # of each patch among the contact elements
    nc = elements.size
    K = ops.K[np.ix_(elements, elements)]
    p = pressure[elements]
    mu_static = law.static_coefficient
    if creep == 0.0:  # full stick: dq/dxi = K^-1 1
        slope = float(linalg.solve(K, np.ones(nc), check_finite=False).sum())
        return StructuredSteady(np.zeros(n), np.zeros(n), contact.copy(), 0, True, "zero creep: no traction",
                                {"stick_slip": 0.0, "traction_bound": 0.0, "slip_direction": 0.0}, slope)
    sigma = math.copysign(1.0, creep)
    tol = 1e-3 * tolerance * abs(creep)
    slip_tolerance = tolerance * ops.kappa * mu_static * pressure.max()
    total_newton = 0
    cache: dict[tuple, tuple] = {}
    last_slip = np.full(nc, creep)

    def eliminated(zones):
        """Stick mask, slip indices, their pressures and ``y0 = K_SS^-1 xi``, ``W = K_SS^-1 K_SP``, ``r0``, Schur
        complement for the stick zones ``((j0_k, m_k), ...)``, one per patch."""
        stick = np.zeros(nc, dtype=bool)
        for offset, (j0, m) in zip(offsets, zones, strict=True):
            stick[offset + j0:offset + j0 + m] = True
        si, pi = np.flatnonzero(stick), np.flatnonzero(~stick)
        if si.size:
            lu = linalg.lu_factor(K[np.ix_(si, si)], check_finite=False)
            y0 = linalg.lu_solve(lu, np.full(si.size, creep), check_finite=False)
            w = linalg.lu_solve(lu, K[np.ix_(si, pi)], check_finite=False)
            r0 = creep - K[np.ix_(pi, si)] @ y0
            schur = K[np.ix_(pi, pi)] - K[np.ix_(pi, si)] @ w
        else:
            y0, w = np.zeros(0), np.zeros((0, nc))
            r0, schur = np.full(nc, creep), K
        return stick, pi, p[pi], y0, w, r0, schur

    def traction_rate(s, pp):
        """dQ/ds of ``Q(s) = mu(V|s|) p sign(xi)``."""
        return law.derivative(speed * np.abs(s)) * speed * np.where(s * sigma >= 0, 1.0, -1.0) * pp

    def solve_for(zones):
        """q, s on the contact elements, Newton success and the slip-direction test per patch for the zones."""
        nonlocal total_newton
        if zones in cache:
            return cache[zones]
        stick, pi, pp, y0, w, r0, schur = eliminated(zones)

        def traction(s):
            return law.coefficient(speed * np.abs(s)) * pp * sigma

        def residual(s):
            return s - r0 + schur @ traction(s)

        # warm start from the last solved stick lengths: the slip behind the zones barely changes
        s = np.where(sigma * last_slip[pi] > 0, last_slip[pi], creep)
        ok = True
        if pi.size:
            r = residual(s)
            ok = False
            for _ in range(100):
                total_newton += 1
                norm = np.abs(r).max()
                if norm <= tol:
                    ok = True
                    break
                dq = traction_rate(s, pp)
                step = linalg.solve(np.eye(pi.size) + schur * dq[None, :], -r, check_finite=False)
                t = 1.0
                while True:
                    s_try = s + t * step
                    r_try = residual(s_try)
                    # Armijo-type damping keeps Newton on the branch where |R| decreases
                    if np.abs(r_try).max() < (1.0 - 1e-4 * t) * norm or t < 1e-6:
                        break
                    t *= 0.5
                s, r = s_try, r_try
        q = np.zeros(nc)
        q[pi] = traction(s)
        q[stick] = y0 - w @ q[pi]
        slip = np.zeros(nc)
        slip[pi] = s
        last_slip[pi] = s
        wrong = sigma * slip < -slip_tolerance
        feasible = tuple(not wrong[offset:offset + size].any() for offset, size in zip(offsets, sizes, strict=True))
        cache[zones] = (q, slip, stick, ok, feasible)
        return cache[zones]

    def shortest_feasible(zones, k, j0, guess):
        """Smallest m_k passing patch k's slip-direction test, the other zones held: bracket outwards from
        ``guess``, then bisect.

        The test fails for too short a stick zone and holds beyond the true one (too long a zone breaks the
        traction bound instead); m_k = size - j0 (no slip behind the zone) counts as passing.
        """
        def passes(m):
            return solve_for(zones[:k] + ((j0, m),) + zones[k + 1:])[4][k]

        top = sizes[k] - j0
        guess = min(max(guess, 0), top)
        step = 1
        if guess < top and passes(guess):
            hi, lo = guess, guess - 1
            while lo >= 0 and passes(lo):
                hi, lo, step = lo, lo - step, 2 * step
            lo = max(lo, -1)
        else:
            lo, hi = guess, guess + 1
            while hi < top and not passes(hi):
                lo, hi, step = hi, hi + step, 2 * step
            hi = min(hi, top)
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if passes(mid):
                hi = mid
            else:
                lo = mid
        return hi

    def patch_zone(zones, k):
        """Patch k's zone (j0_k, m_k) with the other zones held."""
        offset = offsets[k]
        m = zones[k][1] + zones[k][0]
        for j0 in range(sizes[k]):
            m = shortest_feasible(zones, k, j0, m)
            found = zones[:k] + ((j0, m),) + zones[k + 1:]
            q_c = solve_for(found)[0]
            if m == 0 or abs(q_c[offset + j0]) <= mu_static * p[offset + j0] * (1.0 + 1e-12):
                break
            # the stick zone starts one element later and is one element shorter (the next guess)
            m -= 1
        return found

    final = tuple((0, int(round(stick_fraction * size))) for size in sizes)
    for _ in range(STRUCTURED_SWEEPS if len(sizes) > 1 else 1):  # one patch: nothing to hold, one pass
        start = final
        for k in range(len(sizes)):
            final = patch_zone(final, k)
        if final == start:
            break
    q_c, s_c, stick_c, ok, _ = solve_for(final)
    q, slip = np.zeros(n), np.zeros(n)
    q[elements], slip[elements] = q_c, s_c
    stick = np.zeros(n, dtype=bool)
    stick[elements] = stick_c
    slip_check = np.where(contact, creep - ops.K[:, elements] @ q_c, 0.0)
    scale = ops.kappa * mu_static * pressure.max()
    bound = np.where(stick, mu_static, law.coefficient(speed * np.abs(slip))) * pressure
    certificate = tangential_certificate(q, slip_check, stick, bound, contact, scale)
    converged = ok and max(certificate.values()) <= 100.0 * tolerance
    message = ("converged" if converged else
               "Newton did not converge" if not ok else f"leading-edge stick structure fails: {certificate}")
    slope = math.nan
    if converged:
        _, pi, pp, y0, w, r0, schur = eliminated(final)
        dq = traction_rate(s_c[pi], pp)
        dq_p = dq * linalg.solve(np.eye(pi.size) + schur * dq[None, :], r0 / creep, check_finite=False)
        slope = float(dq_p.sum() + y0.sum() / creep - (w @ dq_p).sum())
    return StructuredSteady(q, slip, stick, total_newton, converged, message, certificate, slope)


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


def no_contact_result(scene: Scene) -> ContactResult:
    return ContactResult(method="discretised", success=True, message="no load: no contact",
                         normal_load_per_length=0.0, tangential_force_per_length=0.0, creep=scene.creep,
                         contact_half_width=0.0, contact_offset=0.0, stick_half_width=0.0, max_pressure=0.0,
                         distributions=NoContact())


def solve_discretised(scene: Scene, *, elements=None, window=None, tolerance=DEFAULT_TOLERANCE, steady=None,
                      finish: bool = True, datum_length=None, tangential_force_per_length=None,
                      extrapolate: int = 0) -> ContactResult:
    """Solve a scene with the discretised (Kalker-type boundary-element) method.

    Parameters
    ----------
    scene : Scene
        The case; ``scene.creep`` is used unless ``tangential_force_per_length`` is given.
    elements : int, optional
        Number of elements n in [8, 4000]; default 200 (more for short surface wavelengths: 16 per wavelength).
    window : (float, float), optional
        Grid window (x_min, x_max) [m] in the axis coordinate; default from the Hertz width and the surface,
        widened automatically (up to 3 times) when a patch reaches its edge.
    tolerance : float
        Relative tolerance of the active sets and certificates, in [1e-14, 1e-3].
    steady : {"direct", "march", "structured"}, optional
        How the steady state is found: ``"direct"`` (default for constant friction) the active set on the
        steady operator; ``"march"`` Kalker's transient marching with ``ds = h`` until the slip pattern
        settles (finished by the direct solve when ``finish``); ``"structured"`` (default for
        velocity-dependent friction) a stick zone at the leading edge of each patch, Newton on the slip
        (:func:`steady_leading_edge_stick`).  Where it fails on the automatic grid (no ``elements``, no
        ``window``), once more on twice the elements, up to the largest grid ``auto`` offers
        (:data:`rollcontact.api.DISCRETISED_ELEMENTS`, as its :meth:`~rollcontact.api.DiscretisedAccuracy.retry`
        does for a grid chosen for a tolerance): a slip zone shorter than an element at a patch end leaves a
        stick element above mu p, or one slipping against the traction; the message says so.
    finish : bool
        With ``steady="march"``: polish the marched state by the direct steady solve.
    datum_length : float, optional
        Datum L [m] of the transient marching (creep control needs L > window/4).  The steady state does not
        depend on it, only the speed of the approach does (the datum acts as a relaxation length), so the
        default is the shortest safe choice, the window length.
    tangential_force_per_length : float, optional
        T' [N/m]: force control (constant friction only); the creep is then found.
    extrapolate : int
        0 (default): one solve.  m >= 1: T' extrapolated from ``elements`` (default 200) and twice as many, each
        level the mean over m grid placements on a window fitted to the patches (:func:`extrapolated`); the other
        fields are the finer level's first placement, p0 its mean.  Creep control only, no ``window``.

    Returns
    -------
    ContactResult
        ``residual`` is the largest certificate entry; ``info`` holds ``grid``, ``patches`` [(x_lead, x_trail)],
        ``normal_certificate``, ``tangential_certificate``, iteration counts and the mode used.  The creep
        stiffness dT'/dxi is given under creep control (:meth:`TransientSolver.steady_creep_stiffness`; with
        velocity-dependent friction ``StructuredSteady.creep_slope``), NaN under force control.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a rollcontact.Scene, got {type(scene).__name__}")
    if check_count("extrapolate", extrapolate, 0, why=" (grid placements per level)"):
        if window is not None or tangential_force_per_length is not None:
            raise ValueError("extrapolate fits its own windows to the patches and extrapolates T' under creep "
                             "control: it takes neither window nor tangential_force_per_length")
        n = check_count("elements", DEFAULT_ELEMENTS if elements is None else elements, MIN_ELEMENTS,
                        MAX_ELEMENTS // 2, " with extrapolate (the finer level has twice as many)")
        return extrapolated(scene, (n, 2 * n), extrapolate, tolerance=tolerance, steady=steady, finish=finish,
                            datum_length=datum_length)
    tolerance = check_tolerance(tolerance)
    constant = scene.friction.is_constant
    if steady is None:
        steady = "direct" if constant else "structured"
    if steady not in STEADY_MODES:
        raise ValueError(f"unknown steady mode {steady!r}; valid modes are {list(STEADY_MODES)}")
    if steady != "structured" and not constant:
        raise ValueError(f"steady={steady!r} needs constant friction, got {scene.friction!r}: with dmu/dv < 0 "
                         "the transient problem is ill-posed; use steady='structured'")
    force_control = tangential_force_per_length is not None
    if force_control and steady == "structured":
        raise ValueError("tangential_force_per_length (force control) needs steady='direct' or 'march' and "
                         "constant friction")
    if scene.normal_load_per_length == 0.0:
        return no_contact_result(scene)
    grid, solver, normal = fitted_normal(scene, elements, window, datum_length=datum_length, tolerance=tolerance)
    a, offset, patches = patch_geometry(grid, normal.contact)
    p = normal.pressure
    info = {"grid": grid, "patches": patches, "normal_certificate": normal.certificate,
            "normal_iterations": normal.iterations, "steady": steady}

    def result(success, message, q, slip, stick, t, creep, iterations, residual, stiffness=math.nan):
        s = np.where(normal.contact, slip, np.nan)
        return ContactResult(method="discretised", success=success, message=message,
                             normal_load_per_length=scene.normal_load_per_length, tangential_force_per_length=t,
                             creep=creep, contact_half_width=a, contact_offset=offset,
                             stick_half_width=0.5 * grid.element_width * int(stick.sum()),
                             max_pressure=float(p.max()), creep_stiffness_per_length=stiffness,
                             iterations=iterations, residual=residual,
                             distributions=TabulatedDistributions(grid.centres, p, q, s), info=info)

    zeros = np.zeros(grid.elements)
    if not normal.converged:
        return result(False, f"normal problem: {normal.message}", zeros, zeros, zeros, 0.0, scene.creep,
                      normal.iterations, normal.residual)
    if normal.contact[0] or normal.contact[-1]:
        return result(False, f"contact reaches the window edge ({grid.x_min!r}, {grid.x_max!r}) m: enlarge the "
                      "window", zeros, zeros, zeros, 0.0, scene.creep, normal.iterations, normal.residual)
    control = ({"tangential_force": tangential_force_per_length} if force_control else {"creep": scene.creep})
    if steady == "structured":
        half = 0.5 * grid.element_width * normal.contact.sum()
        fraction = max(0.0, 1.0 - scene.radius * abs(scene.creep) / (scene.friction_coefficient * half))
        sol = steady_leading_edge_stick(solver.ops, p, scene.creep, scene.friction, scene.rolling_speed,
                                        tolerance, fraction)
        info["tangential_certificate"] = sol.certificate
        residual = max(normal.residual, max(sol.certificate.values(), default=0.0))
        t = grid.element_width * sol.traction.sum()
        message = f"steady, leading-edge stick, {len(patches)} patch(es): {sol.message}"
        if not sol.converged and elements is None and window is None \
                and 2 * grid.elements <= DISCRETISED_ELEMENTS[-1]:
            # the automatic grid leaves a slip zone shorter than an element at a patch end (a stick element
            # above mu p, or one slipping against the traction): twice the elements resolve it
            finer = solve_discretised(scene, elements=2 * grid.elements, tolerance=tolerance, steady=steady,
                                      datum_length=datum_length)
            return replace(finer, message=f"{finer.message} (refined from the automatic grid of {grid.elements} "
                                          f"elements, where the structure failed: {sol.message})")
        return result(sol.converged, message, sol.traction, sol.slip, sol.stick, t, scene.creep,
                      sol.iterations, residual, grid.element_width * sol.creep_slope)
    state = None
    iterations = 0
    if steady == "march":
        state, marched = march_to_steady(solver, p, control, tolerance)
        iterations = state.steps
        info["march_tangential_force"] = state.tangential_force_per_length
        info["march_steps"] = state.steps
        if not marched.converged or not finish:
            residual = max(normal.residual, max(marched.certificate.values(), default=0.0))
            info["tangential_certificate"] = marched.certificate
            return result(marched.converged, f"steady by marching: {marched.message}", state.traction,
                          state.slip, state.stick, state.tangential_force_per_length, marched.creep, iterations,
                          residual)
    state, steady_result = solver.steady_state(p, state=state, **control)
    info["tangential_certificate"] = steady_result.certificate
    residual = max(normal.residual, max(steady_result.certificate.values()))
    kind = "marched and finished directly" if steady == "march" else "direct steady solve"
    message = f"{kind}, {len(patches)} patch(es): {steady_result.message}"
    # dT'/dxi of creep control; under force control the creep is the unknown and the model does not ask
    stiffness = (solver.steady_creep_stiffness(state.stick) if steady_result.converged and not force_control
                 else math.nan)
    return result(steady_result.converged, message, state.traction, state.slip, state.stick,
                  steady_result.tangential_force_per_length, steady_result.creep,
                  iterations + steady_result.iterations, residual, stiffness)


solve_discretised.options = ("elements", "window", "tolerance", "steady", "finish", "datum_length",
                             "tangential_force_per_length", "extrapolate")


def extrapolated(scene: Scene, elements: tuple[int, int] = (1000, 2000), placements: int = 2,
                 **options) -> ContactResult:
    """A converged discretised solution: T' by first-order Richardson extrapolation, each level the mean over
    ``placements`` grid placements.

    ``T'_ref = T'_2 + (T'_2 - T'_1)/(r - 1)`` with ``r = n_2/n_1`` (T' is first order in the element width), where
    ``T'_k`` is the mean of the solves at ``n_k`` elements on :func:`contact_window` (fitted to the patches) shifted
    by ``j h_k / m``, j = 0..m-1 (m = ``placements``).  The answer at one n moves by about its error with where the
    patch edges fall in their elements (``benchmarks/bench_discretised_estimate.py``): that part of the error is
    periodic in the shift, the mean over m placements is its trapezoidal average, and extrapolation alone would
    amplify it.  The smooth first-order part is then removed by the extrapolation.  Measured over the cases of
    ``benchmarks/bench_discretised_estimate.py`` (table C, n_2 = 2 n_1) the error is at most ``c w/(m n_1)`` (w the
    window over the Hertz width 2a) with c = 2.12 for m = 2 to 16 (erratic in n), largest on a split contact at
    small creep.  The other fields are the finer level's first placement; p0 (second order) is the
    finer level's mean.

    Parameters
    ----------
    scene : Scene
        The case (creep control).
    elements : (int, int)
        Element counts n_1 < n_2.
    placements : int
        Grid placements m >= 1 per level.
    **options
        Passed to :func:`solve_discretised` (not ``elements``, ``window`` or ``extrapolate``).

    Returns
    -------
    ContactResult
        ``success`` only if all ``2 m`` solves succeeded; ``info["levels"]`` holds the mean T' [N/m] per level,
        ``info["change"]`` the relative change of T' from the finer level to the extrapolation and
        ``info["placements"]`` m.
    """
    coarse, fine = (int(n) for n in elements)
    if not coarse < fine:
        raise ValueError(f"elements = {elements!r}: need n_1 < n_2")
    placements = check_count("placements", placements, 1)
    if scene.normal_load_per_length == 0.0:
        return no_contact_result(scene)
    lo, hi = contact_window(scene)
    levels = {}
    for n in (coarse, fine):
        h = (hi - lo) / n
        levels[n] = [solve_discretised(scene, elements=n, window=(lo + j * h / placements, hi + j * h / placements),
                                       **options) for j in range(placements)]
    solves = levels[coarse] + levels[fine]
    means = {n: sum(r.tangential_force_per_length for r in rs) / placements for n, rs in levels.items()}
    force = means[fine] + (means[fine] - means[coarse]) / (fine / coarse - 1.0)
    best = levels[fine][0]
    failed = [r.message for r in solves if not r.success]
    info = dict(best.info, levels=means, change=abs(means[fine] / force - 1.0) if force else 0.0,
                placements=placements)
    return ContactResult(**{**best.__dict__, "success": not failed, "tangential_force_per_length": force,
                            "max_pressure": sum(r.max_pressure for r in levels[fine]) / placements, "info": info,
                            "message": f"Richardson extrapolation of n = {coarse}/{fine}, each the mean of "
                                       f"{placements} grid placement{'s' if placements > 1 else ''}"
                                       + (f"; failed: {failed[0]}" if failed else "")})


def march_to_steady(solver: TransientSolver, pressure: np.ndarray, control: dict,
                    tolerance: float) -> tuple[TransientState, StepResult]:
    """Kalker's marching to steady rolling: steps of ``ds = h`` from q = 0 until the slip pattern settles.

    Settled means: the stick set unchanged and ``|dT'| <= tolerance mu N'`` for as many consecutive steps as the
    patch has elements (one passage of material).  At most 20 n steps.
    """
    h = solver.grid.element_width
    contact = pressure > 0
    passage = int(contact.sum())
    limit = solver.friction.static_coefficient * h * pressure.sum()
    state = solver.initial_state()
    quiet = 0
    result = None
    for _ in range(20 * solver.grid.elements):
        previous = state
        state, result = solver.step(state, pressure, h, **control)
        if not result.converged:
            return state, result
        calm = (np.array_equal(state.stick, previous.stick) and abs(state.tangential_force_per_length
                - previous.tangential_force_per_length) <= tolerance * limit)
        quiet = quiet + 1 if calm else 0
        if quiet >= passage:
            return state, result
    return state, StepResult(result.tangential_force_per_length, result.creep, result.rigid_shift,
                             result.slip_distance, result.dissipation, result.stick_elements, result.iterations,
                             False, f"slip pattern did not settle within {20 * solver.grid.elements} steps",
                             result.certificate)


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
                      tolerance: float = DEFAULT_TOLERANCE) -> RollingHistory:
    """Roll the cylinder over ``scene.surface`` as a true transient, from steady rolling at ``scene.axis_position``.

    Each step of ``ds = distance/steps`` moves the axis by -ds over the surface (x_c = x_c0 - k ds), solves the
    normal problem there (quasi-static, no memory) and takes one :meth:`TransientSolver.step` (material convected
    by ds through the axis-fixed grid).  Control: T' fixed (``tangential_force_per_length``, datum-free as long
    as T' is constant) or ``scene.creep``.  This is the reference for the quasi-steady corrugation formulas
    (paper eqs 28-31 as corrected in physics.md section 4): with the patch centre moving as ``Delta(x_c)`` the
    creep for a given T' is close to the frozen-geometry value times ``1 + dDelta/dx_c``.

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
    elements, window, datum_length, tolerance
        As in :func:`solve_discretised`; the automatic window covers every axis position of the roll.
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
    solver = TransientSolver.from_scene(scene, grid, datum_length=datum_length, tolerance=tolerance)
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


# ------------------------------------------------------------------------------------------------ registration
def inapplicable(scene: Scene) -> str | None:
    """Why the default grid cannot resolve the scene (None when it can, up to the discretisation error).

    The automatic grid needs 16 elements per shortest surface wavelength across its window; beyond
    ``MAX_ELEMENTS`` the dense matrices would not fit.
    """
    if scene.normal_load_per_length == 0.0:
        return None
    try:
        automatic_grid(scene)
    except ValueError as exc:
        return str(exc)
    return None


register_method("discretised", solve_discretised, inapplicable, cost=100, fallback=True)
