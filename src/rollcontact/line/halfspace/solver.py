"""The discretised half-space solver that the methods and instationary rolling share: :class:`TransientSolver`.

Kalker's transient rolling (TANG) on a fixed grid, one step of rolled distance per call, with its explicit
:class:`TransientState`; ``ds = 0`` is a static step.  Steady rolling (:mod:`rollcontact.line.methods.discretised`) and
creep-controlled instationary rolling (:mod:`rollcontact.line.instationary.model`) both run on it, which is why it lives
here rather than in either.  :func:`fitted_normal` and :func:`contact_window` place the grid on the contact; the
elements and the active-set solvers are :mod:`rollcontact.core.halfspace.elements`, the automatic grid
:mod:`rollcontact.line.halfspace.grid`.

* Normal problem (NORM): ``g = h0 + M p - c >= 0``, ``p >= 0``, ``p g = 0``, ``h sum p = N'`` with the
  undeformed gap ``h0 = x^2/(2R) - Z(x + x_c)``, solved exactly by an active set for any gap, several patches
  included; the certificate (load balance, gap >= 0, p >= 0, complementarity) is returned.
* Tangential transient (TANG): per step of rolled distance ``ds = V dt`` the particle now at x_i was at
  ``x_i - ds``, so the slip distance is ``S_i = w + u_new(x_i) - u_old(x_i - ds)`` (w = xi ds the rigid
  shift); stick ``S = 0``, slip ``q = mu p sign(S)``.  This is the upwind (first-order) discretisation of
  ``s = xi + (1/V) Du/Dt``; the old displacement at the shifted points is integrated exactly for any ds.

Datum: in 2D the tangential displacement is defined relative to a datum distance L (docs/physics.md, Instationary
rolling).  Force control is datum-free; creep control of a transient is not, and is well posed only for L above the
logarithmic capacity of the grid, a quarter of its length.  The default datum is the cylinder radius R: the size of
the body, beyond which the half-space idealisation that produces the logarithm fails.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rollcontact.core.friction import Coulomb, FrictionLaw
from rollcontact.core.halfspace.elements import (
    Control,
    Grid,
    NormalSolution,
    initial_stick,
    operators_for,
    solve_normal,
    solve_stick_slip,
    tangential_certificate,
)
from rollcontact.line.halfspace.grid import (
    CONTACT_MARGIN,
    ITERATION_TOLERANCE,
    WINDOW_RETRIES,
    automatic_grid,
    check_iteration_tolerance,
    patch_geometry,
    positive_length,
)
from rollcontact.line.scene import Scene, Surface


def contact_window(scene: Scene) -> tuple[float, float]:
    """A window (x_min, x_max) [m] fitted to the contact: the patches of a normal solve on :func:`automatic_grid`
    (its element count), plus :data:`CONTACT_MARGIN` of their span and two search elements on each side (a patch
    edge moves by less than one element between resolutions); :func:`automatic_grid`'s window without harmonics
    or when the search fails.

    For references (:func:`rollcontact.line.methods.discretised.steady.extrapolated`): the rigid-gap window adds the
    corrugation's depth ``2 sum|Z_m|`` to the Hertz depth and is several times wider than the contact on
    corrugations, so at the same element count this window's elements are that much finer.  It is not the solver's
    default: the cost of a solve grows with the elements in contact, not with those outside it, so at equal accuracy
    the fitted window saves nothing, and its search adds a normal solve to every discretised FMU step.
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
                  iteration_tolerance: float = ITERATION_TOLERANCE) -> tuple[Grid, TransientSolver, NormalSolution]:
    """The normal problem on :func:`automatic_grid`, widened 1.5 times per retry (at most :data:`WINDOW_RETRIES`)
    while the contact reaches the window's edge; a given ``window`` is kept.  Returns the grid, its solver (datum
    ``datum_length``, default the grid length) and the normal solution, which may still touch the edge."""
    for attempt in range(WINDOW_RETRIES + 1):
        grid = automatic_grid(scene, elements, window, widen=1.5**attempt)
        solver = TransientSolver.from_scene(scene, grid, datum_length=grid.length if datum_length is None
                                            else datum_length, iteration_tolerance=iteration_tolerance)
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
        See :func:`rollcontact.core.halfspace.elements.tangential_certificate`.
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
    ``xi_L = xi_Lw + (2/(pi E*)) ln(L/L_w) dT'/ds`` (docs/physics.md, Instationary rolling), which is how both are
    solved with one SPD matrix of datum L_w.  ``ds = 0`` is a static step (Cattaneo, Mindlin-Deresiewicz); force
    control only.

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
    iteration_tolerance : float
        Relative tolerance of the active-set iteration.

    Examples
    --------
    >>> solver = TransientSolver.from_scene(scene)                   # doctest: +SKIP
    >>> normal = solver.normal(scene.normal_load_per_length)          # doctest: +SKIP
    >>> state = solver.initial_state()                                # doctest: +SKIP
    >>> state, step = solver.step(state, normal.pressure, solver.grid.element_width, creep=1e-3)  # doctest: +SKIP
    """

    def __init__(self, grid: Grid, *, contact_modulus: float, radius: float, surface: Surface | None = None,
                 friction: FrictionLaw | None = None, rolling_speed: float = 1.0, datum_length=None,
                 iteration_tolerance: float = ITERATION_TOLERANCE):
        if not isinstance(grid, Grid):
            raise TypeError(f"grid must be a rollcontact.line.halfspace.grid.Grid, got {type(grid).__name__}")
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
        self.iteration_tolerance = check_iteration_tolerance(iteration_tolerance)
        self.ops = operators_for(grid, self.contact_modulus)
        # datum term: u_L = u_Lw - kappa ln(L/L_w) T' for every x
        self.datum_factor = self.ops.kappa * math.log(self.datum_length / self.ops.working_datum)
        self.max_iterations = 4 * grid.elements + 50

    @classmethod
    def from_scene(cls, scene: Scene, grid: Grid | None = None, *, elements=None, window=None,
                   datum_length=None, iteration_tolerance: float = ITERATION_TOLERANCE) -> TransientSolver:
        """Solver for a scene's material, radius, surface, friction and speed (grid: given or automatic)."""
        grid = automatic_grid(scene, elements, window) if grid is None else grid
        return cls(grid, contact_modulus=scene.material.contact_modulus, radius=scene.radius,
                   surface=scene.surface, friction=scene.friction, rolling_speed=scene.rolling_speed,
                   datum_length=datum_length, iteration_tolerance=iteration_tolerance)

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
        return solve_normal(self.ops, self.gap(axis_position), load, self.iteration_tolerance, self.max_iterations)

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
                               self.iteration_tolerance * scale, self.max_iterations)
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
                               self.iteration_tolerance * scale, self.max_iterations)
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
        converged = sol.converged and max(certificate.values()) <= 100.0 * self.iteration_tolerance
        message = sol.message if not sol.converged or converged else f"certificate fails: {certificate}"
        slip[sol.stick] = 0.0
        return t_new, slip, certificate, converged, message
