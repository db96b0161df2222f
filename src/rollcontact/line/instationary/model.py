"""Creep-controlled instationary rolling step by step (paper section 4.3; docs/physics.md, Instationary rolling).

:class:`InstationaryModel` is what an FMU calls each communication step, with an explicit
:class:`InstationaryState` that can be copied, serialised and restored.  Conventions are the package's (see
:mod:`rollcontact`): x fixed to the contact, material flows in +x, the leading edge is ``x = -a``,
``s = xi + du/dx + (1/V) du/dt``, in slip ``q = mu p sign(s)``.  ``sigma = V t`` is the rolled distance [m]; with it
the slip is ``s = xi + du/dx + du/dsigma``.  Constant load, Hertz geometry and Coulomb friction throughout.

Default datum.  ``L = R`` (the effective wheel radius), as for
:class:`rollcontact.line.halfspace.solver.TransientSolver`: the logarithm is a half-space idealisation that holds up to
distances of the order of the body size and fails beyond it, so the body size is the natural place to anchor it.  It
lies far above the quarter grid length the discretised creep control needs (grid length ~2.5 a, a << R).  With it the
relaxation length at zero force is ``a ln(2R/(sqrt(e) a))`` (about 4.4 a for a = 7 mm, R = 0.46 m;
:mod:`rollcontact.line.instationary.relaxation`).

Models
------
* ``mode="transient"``: the discretised :class:`~rollcontact.line.halfspace.solver.TransientSolver` in creep control
  (the reference).  The grid commits substeps of exactly one element; a host step that ends between element
  boundaries leaves the rest of its roll pending for the next, and its output is a provisional substep of that
  roll (:meth:`InstationaryModel.advance`).  :meth:`InstationaryModel.steady_state` gives steady rolling on the
  transient's grid as the fixed point of the whole-element substeps, to switch the transient in mid-run without a
  jump.  With ``extrapolate=True`` the transient runs on two nested grids (n/2 and n elements, both aligned by
  :func:`aligned_grid_load`, each committing its own elements) and reports ``2 T'_n - T'_(n/2)``: their
  first-order errors cancel and the rest falls as n^-2 (``benchmarks/calibrate_transient_pairs.py``).
* ``mode="relaxation"``: the lag (R1) around Carter (:mod:`rollcontact.line.instationary.relaxation`): closed-form
  arithmetic per substep, no grid.  How closely it tracks the transient, and where quasi-static Carter fails, is
  checked by ``tests/instationary/test_instationary.py::test_relaxation_model_tracks_creep_controlled_transient``
  and measured by ``benchmarks/calibrate_relaxation.py`` and ``benchmarks/bench_instationary.py``.

Oscillating force control is :mod:`rollcontact.line.instationary.oscillating`, the stationarity measure
:mod:`rollcontact.line.instationary.stationarity`.

Limits: ``V = 0`` is the static limit: nothing rolls, the creep has no effect and T' is held (capped by mu N'; the
transient mode redistributes q by a static force-controlled step when N' changes).  ``N' = 0`` lifts the wheel:
T' = 0 and the history of q is lost.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass, field, replace
from typing import NamedTuple

import numpy as np

from rollcontact.core.checks import check_real
from rollcontact.core.friction import Coulomb
from rollcontact.core.halfspace.elements import Grid
from rollcontact.line.carter import CarterDistributions
from rollcontact.line.halfspace.grid import patch_geometry
from rollcontact.line.halfspace.solver import TransientSolver, TransientState
from rollcontact.line.hertz import hertz
from rollcontact.line.instationary.relaxation import (
    STEADY_AFTER,
    carter_creep,
    relaxation_length,
    relaxation_step,
    stick_half_width,
)
from rollcontact.line.instationary.stationarity import STATIONARY, InputHistory, stationarity
from rollcontact.line.result import ContactResult, NoContact, TabulatedDistributions

MODES = ("relaxation", "transient")


WINDOW_FACTOR = 1.25  # transient grid: +-1.25 a_max


FORCE_MARGIN = 1.0 - 1e-9  # static steps hold |T'| just below the friction limit


# -------------------------------------------------------------------------------------------------------- state
@dataclass(frozen=True)
class InstationaryState:
    """Everything an :class:`InstationaryModel` remembers between steps (copy, serialise, restore).

    Attributes
    ----------
    mode : str
        ``"relaxation"`` or ``"transient"`` (a state is only valid for the mode that made it).
    tangential_force_per_length : float
        T' [N/m] after the last step; transient mode: of the committed traction below (the step's result reports
        T' after the pending roll).
    distance : float
        Rolled distance sigma [m] since the initial state.
    steps : int
        Steps taken.
    traction, stick, slip : ndarray
        Transient mode: q_i [Pa], stick mask and slip s_i [1] on the model's grid (see
        :class:`rollcontact.line.halfspace.solver.TransientState`), committed at the last whole-element substep
        (:meth:`InstationaryModel.advance`); empty in relaxation mode.
    history : InputHistory
        Last input samples (for :func:`stationarity`).
    coarse : TransientState or None
        Extrapolating transient mode: the state on the grid of half the elements (its ``steps`` unused).  The
        force above stays the finer grid's, which its traction history needs; the step's result reports the
        extrapolation.  None otherwise.
    pending, coarse_pending : tuple of float
        Transient mode: the roll the model's grid (the coarse grid's) has not committed yet, less than one
        element: its distance [m] and its rigid slip, the integral of xi over it [m].
    """

    mode: str
    tangential_force_per_length: float = 0.0
    distance: float = 0.0
    steps: int = 0
    traction: np.ndarray = field(default_factory=lambda: np.zeros(0))
    stick: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    slip: np.ndarray = field(default_factory=lambda: np.zeros(0))
    history: InputHistory = field(default_factory=InputHistory)
    coarse: TransientState | None = None
    pending: tuple[float, float] = (0.0, 0.0)
    coarse_pending: tuple[float, float] = (0.0, 0.0)

    def copy(self) -> InstationaryState:
        """Deep copy (arrays copied)."""
        return InstationaryState.from_bytes(self.to_bytes())

    def to_bytes(self) -> bytes:
        """Serialise with ``numpy.savez`` (exact: floats are stored as float64)."""
        buffer = io.BytesIO()
        coarse = {} if self.coarse is None else {
            "coarse_traction": self.coarse.traction, "coarse_stick": self.coarse.stick,
            "coarse_slip": self.coarse.slip, "coarse_force": np.float64(self.coarse.tangential_force_per_length)}
        np.savez(buffer, mode=np.array(self.mode), force=np.float64(self.tangential_force_per_length),
                 distance=np.float64(self.distance), steps=np.int64(self.steps), traction=self.traction,
                 stick=self.stick, slip=self.slip, history_distance=self.history.distance,
                 history_load=self.history.normal_load_per_length, history_creep=self.history.creep,
                 pending=np.array(self.pending, dtype=float),
                 coarse_pending=np.array(self.coarse_pending, dtype=float), **coarse)
        return buffer.getvalue()

    @classmethod
    def from_bytes(cls, data: bytes) -> InstationaryState:
        """Restore a state written by :meth:`to_bytes`; ValueError for anything else."""
        try:
            with np.load(io.BytesIO(data), allow_pickle=False) as f:
                coarse = (TransientState(f["coarse_traction"].astype(float), f["coarse_stick"].astype(bool),
                                         f["coarse_slip"].astype(float), float(f["coarse_force"]))
                          if "coarse_traction" in f.files else None)
                return cls(str(f["mode"]), float(f["force"]), float(f["distance"]), int(f["steps"]),
                           f["traction"].astype(float), f["stick"].astype(bool), f["slip"].astype(float),
                           InputHistory(f["history_distance"].astype(float), f["history_load"].astype(float),
                                        f["history_creep"].astype(float)), coarse,
                           *(pending_pair(f[name]) for name in ("pending", "coarse_pending")))
        except (OSError, KeyError, ValueError, TypeError) as exc:
            raise ValueError(f"not a serialised InstationaryState: {exc}") from None

    def transient(self) -> TransientState:
        """The discretised solver's view of this state."""
        return TransientState(self.traction, self.stick, self.slip, self.tangential_force_per_length, self.steps)


def pending_pair(values: np.ndarray) -> tuple[float, float]:
    """A serialised pending roll ``(distance [m], rigid slip [m])``; ValueError for any other shape."""
    if values.shape != (2,):
        raise ValueError(f"a pending roll has two values, got shape {values.shape}")
    return float(values[0]), float(values[1])


# -------------------------------------------------------------------------------------------------------- model
class InstationaryModel:
    """Creep-controlled instationary rolling, one step per call: what an FMU calls each communication step.

    Inputs per step: N' [N/m], xi [1], V [m/s] and dt [s]; the rolled distance of the step is ``V dt`` (zero-order
    hold: the new inputs act over the whole step, as in :meth:`TransientSolver.step`).

    Parameters
    ----------
    radius : float
        Effective radius R [m] > 0.
    contact_modulus : float
        E* [Pa] > 0.
    friction_coefficient : float
        Coulomb mu [1] > 0.
    mode : {"relaxation", "transient"}
        ``"relaxation"``: the lag (R1) around Carter, ``dT'/dsigma = (xi - xi_steady(T'))/(kappa ln(L/L_1))``
        (module docstring); ``"transient"``: the discretised :class:`TransientSolver` in creep control.
    datum_length : float, optional
        Datum L [m] of the tangential displacement (creep control depends on it); default R (module docstring
        explains why).  Transient mode needs L above a quarter of its grid length (2.5 a_max / 4).
    max_normal_load_per_length : float, optional
        Transient mode: the largest N' [N/m] the grid must hold (window +-1.25 a(N'_max)); default 0 means the
        first loaded step's N'.
    elements : int
        Transient mode: grid elements n (default 100).
    extrapolate : bool
        Transient mode: also step a grid of n/2 elements on the same window (n even) and report the first-order
        Richardson extrapolation ``2 T'_n - T'_(n/2)``, clipped to ``|T'| <= mu N'`` (second order on nested
        grids aligned by :func:`aligned_grid_load`; module docstring).  Distributions, a* and p0 are the finer's.
    max_substeps : int, optional
        Transient mode: the most whole-element substeps one step runs on a grid (a bound of its work).  A step that
        rolls further starts its last ``max_substeps`` elements from steady rolling under its held inputs: the
        history before them is forgotten, which changes T' by at most :meth:`memory_cut_bound`.  None: no limit.
    """

    def __init__(self, radius: float, contact_modulus: float, friction_coefficient: float, *,
                 mode: str = "relaxation", datum_length=None, max_normal_load_per_length: float = 0.0,
                 elements: int = 100, extrapolate: bool = False, max_substeps: int | None = None):
        if mode not in MODES:
            raise ValueError(f"unknown mode {mode!r}; valid modes are {list(MODES)}")
        if extrapolate and (mode != "transient" or elements % 2 or elements < 16):
            raise ValueError(f"extrapolate needs mode 'transient' and an even number of elements >= 16, got mode "
                             f"{mode!r} and elements = {elements!r}")
        self.mode = mode
        self.radius = check_real("radius", radius, lower=0.0, lower_open=True, unit="m")
        self.contact_modulus = check_real("contact_modulus", contact_modulus, lower=0.0, lower_open=True, unit="Pa")
        self.mu = check_real("friction_coefficient", friction_coefficient, lower=0.0, lower_open=True, unit="1")
        self.datum_length = (self.radius if datum_length is None
                             else check_real("datum_length", datum_length, lower=0.0, lower_open=True, unit="m"))
        self.max_load = check_real("max_normal_load_per_length", max_normal_load_per_length, lower=0.0, unit="N/m")
        self.elements = elements
        self.extrapolate = bool(extrapolate)
        self.max_substeps = max_substeps
        self.solver: TransientSolver | None = None
        self.coarse_solver: TransientSolver | None = None
        """Extrapolating: the solver on n/2 elements of the same window."""
        self.pressure_cache: dict[tuple[int, float], np.ndarray] = {}
        if mode == "transient" and self.max_load > 0.0:
            self.build_solver(self.max_load)

    def build_solver(self, load: float) -> None:
        """Transient grid for loads up to ``load``: window +-1.25 a(load), datum checked here."""
        a_max = hertz(load, self.radius, self.contact_modulus)[0]
        grid = Grid(-WINDOW_FACTOR * a_max, WINDOW_FACTOR * a_max, self.elements)
        if not self.holds(load):
            raise ValueError(f"datum_length = {self.datum_length!r} m is out of range for the transient mode: it must "
                             f"exceed a quarter of the grid length ({0.25 * grid.length!r} m)")
        self.max_load = load
        self.solver, self.coarse_solver = (
            TransientSolver(g, contact_modulus=self.contact_modulus, radius=self.radius, friction=Coulomb(self.mu),
                            datum_length=self.datum_length) if g is not None else None
            for g in (grid, Grid(grid.x_min, grid.x_max, self.elements // 2) if self.extrapolate else None))
        self.pressure_cache = {}

    def memory_cut_bound(self, load: float, kept: float) -> float:
        """Bound [N/m] of the change of T' when the history before the last ``kept`` [m] of a roll with held inputs
        is replaced by steady rolling: ``2 mu N' exp(-kept/l)``, the largest force difference decaying over the
        relaxation length l at zero force, the longest
        (:func:`rollcontact.line.instationary.relaxation.relaxation_length`, the lag (R1) linearised)."""
        length = relaxation_length(0.0, load, self.radius, self.contact_modulus, self.mu, self.datum_length)
        return 2.0 * self.mu * load * math.exp(-kept / length)

    def holds(self, load: float) -> bool:
        """Whether the transient grid for loads up to ``load`` [N/m] is short enough for the datum: the datum length
        must exceed a quarter of the grid length ``2 WINDOW_FACTOR a(load)`` (the logarithmic kernel's reference
        distance lies outside the grid)."""
        return self.datum_length > 0.5 * WINDOW_FACTOR * hertz(load, self.radius, self.contact_modulus)[0]

    def solvers(self) -> tuple[TransientSolver, ...]:
        """The transient solvers of the current grid: the model's, then the coarse one when extrapolating."""
        return (self.solver,) if self.coarse_solver is None else (self.solver, self.coarse_solver)

    def initial_state(self) -> InstationaryState:
        """Unloaded, no traction, no history."""
        if self.mode == "transient" and self.solver is not None:
            fine, *coarse = (solver.initial_state() for solver in self.solvers())
            return InstationaryState("transient", traction=fine.traction, stick=fine.stick, slip=fine.slip,
                                     coarse=coarse[0] if coarse else None)
        return InstationaryState(self.mode)

    def steady_state(self, normal_load_per_length: float, creep: float) -> InstationaryState:
        """Transient mode: steady rolling on the grid, the state that holding the inputs keeps unchanged.

        The model commits substeps of exactly one element h (:meth:`advance`); with q and T' unchanged,
        :meth:`TransientSolver.step` gives the slip ``S = xi h - (M - M_h) q`` (the datum term drops out), i.e. the
        steady slip ``s = xi - K_h q`` that :meth:`TransientSolver.steady_state` solves.  So a held step leaves the
        committed state unchanged to the solver's tolerance; its output, a provisional substep of the pending roll,
        ripples with the phase of that roll by O(h^2) (``tests/instationary/test_instationary.py``).

        Raises
        ------
        ValueError
            No grid built yet, the load does not fit it, or the active set fails.
        """
        if self.mode != "transient" or self.solver is None:
            raise ValueError("steady_state needs the transient mode with its grid built (build_solver)")
        load = check_real("normal_load_per_length", normal_load_per_length, lower=0.0, lower_open=True, unit="N/m")
        xi = self.capped(check_real("creep", creep, unit="1"))
        fine, *coarse = (self.steady_on(solver, load, xi) for solver in self.solvers())
        return InstationaryState("transient", fine.tangential_force_per_length, traction=fine.traction,
                                 stick=fine.stick, slip=fine.slip, coarse=coarse[0] if coarse else None)

    def capped(self, creep: float) -> float:
        """The creep within 1e6 saturation creeps of the grid's load: beyond, every element slips whatever the
        elastic slip (~ mu a/R ln n), so the solution is the same, without overflow in products of the creep."""
        cap = 1e6 * self.mu * hertz(self.max_load, self.radius, self.contact_modulus)[0] / self.radius
        return max(-cap, min(cap, creep))

    def steady_on(self, solver: TransientSolver, load: float, xi: float) -> TransientState:
        """:meth:`steady_state` on one of the model's solvers."""
        state, result = solver.steady_state(self.pressure(load, solver), creep=xi)
        if not result.converged:
            raise ValueError(f"steady rolling on the transient grid failed: {result.message}")
        return state

    def regrid(self, state: InstationaryState, grid_load: float) -> InstationaryState:
        """Transient mode: build the grid for ``grid_load`` (larger than the current one's) and carry ``state`` over
        (:func:`remap`, each grid's traction when extrapolating; the pending rolls, shorter than the old elements,
        are shorter than the new ones too)."""
        old = [solver.grid for solver in self.solvers()]
        self.build_solver(grid_load)
        states = (state.transient(),) if state.coarse is None else (state.transient(), state.coarse)
        fine, *coarse = (remap(current, before, solver.grid) for current, before, solver in
                         zip(states, old, self.solvers(), strict=True))
        return InstationaryState("transient", state.tangential_force_per_length, state.distance, state.steps,
                                 fine.traction, fine.stick, fine.slip, state.history, coarse[0] if coarse else None,
                                 state.pending, state.coarse_pending)

    def pressure(self, load: float, solver: TransientSolver | None = None) -> np.ndarray:
        """Discretised normal pressure for N' on ``solver``'s grid (default the model's; cached: constant loads are
        the common case)."""
        solver = self.solver if solver is None else solver
        key = (solver.grid.elements, load)
        p = self.pressure_cache.get(key)
        if p is None:
            normal = solver.normal(load)
            if not normal.converged or normal.contact[0] or normal.contact[-1]:
                raise ValueError(f"normal_load_per_length = {load!r} N/m: the contact does not fit the transient "
                                 f"grid built for max_normal_load_per_length = {self.max_load!r} N/m")
            if len(self.pressure_cache) >= 16:
                self.pressure_cache.pop(next(iter(self.pressure_cache)))
            p = self.pressure_cache[key] = normal.pressure
        return p

    def step(self, state: InstationaryState, normal_load_per_length: float, creep: float, rolling_speed: float,
             dt: float) -> tuple[InstationaryState, ContactResult]:
        """Advance by one communication step.

        Parameters
        ----------
        state : InstationaryState
            State before the step (not modified).
        normal_load_per_length : float
            N' [N/m] >= 0 during the step.
        creep : float
            xi [1] during the step.
        rolling_speed : float
            V [m/s] >= 0 (0: static, nothing rolls).
        dt : float
            Step size [s] > 0.

        Returns
        -------
        state : InstationaryState
        result : ContactResult
            T', a, a*, max p, the creep given; ``info`` has ``distance``, ``stationarity``, ``datum_length``,
            ``relaxation_length`` (relaxation mode) and ``substeps`` (transient mode: 0 when the step rolls more
            than :data:`STEADY_AFTER` relaxation lengths and ends in steady rolling).
        """
        if not isinstance(state, InstationaryState):
            raise TypeError(f"state must be an InstationaryState, got {type(state).__name__}")
        if state.mode != self.mode:
            raise ValueError(f"state of mode {state.mode!r} given to a model of mode {self.mode!r}")
        load = check_real("normal_load_per_length", normal_load_per_length, lower=0.0, unit="N/m")
        xi = check_real("creep", creep, unit="1")
        speed = check_real("rolling_speed", rolling_speed, lower=0.0, unit="m/s")
        dt = check_real("dt", dt, lower=0.0, lower_open=True, unit="s")
        distance = state.distance + speed * dt
        history = state.history.append(distance, load, xi)
        a, p0 = hertz(load, self.radius, self.contact_modulus)
        if load > 0.0 and not a > 0.0:
            raise ValueError(f"normal_load_per_length = {load!r} N/m is too small: the Hertz half-width "
                             "sqrt(4 N' R/(pi E*)) underflows to 0 m, so there is no contact to roll through")
        measure = stationarity(history, a, self.mu * a / self.radius) if a > 0 else STATIONARY
        info = {"distance": distance, "stationarity": measure, "datum_length": self.datum_length}
        if load == 0.0:
            new = InstationaryState(self.mode, 0.0, distance, state.steps + 1,
                                    np.zeros_like(state.traction), np.ones_like(state.stick),
                                    np.zeros_like(state.slip), history)
            return new, ContactResult(method=f"instationary_{self.mode}", success=True, message="no load: no contact",
                                      normal_load_per_length=0.0, tangential_force_per_length=0.0, creep=xi,
                                      contact_half_width=0.0, contact_offset=0.0, stick_half_width=0.0,
                                      max_pressure=0.0, iterations=0, distributions=NoContact(), info=info)
        if self.mode == "relaxation":
            return relaxation_result(self, state, load, xi, speed * dt, distance, history, a, p0, info)
        return self.transient(state, load, xi, speed * dt, distance, history, info)

    def transient(self, state, load, xi, ds, distance, history, info):
        if self.solver is None or load > self.max_load * (1.0 + 1e-12):
            if self.solver is not None:
                raise ValueError(f"normal_load_per_length = {load!r} N/m is out of range: the transient grid holds "
                                 f"loads up to max_normal_load_per_length = {self.max_load!r} N/m")
            self.build_solver(load)
            state = replace(self.initial_state(), distance=state.distance, steps=state.steps, history=state.history)
        solver = self.solver
        if state.traction.shape != (solver.grid.elements,):
            raise ValueError(f"state has {state.traction.size} traction values, the model's grid "
                             f"{solver.grid.elements} elements")
        if (state.coarse is None) == self.extrapolate:
            raise ValueError("state and model differ in extrapolation: a state of an extrapolating model carries the "
                             "coarse grid's traction, any other none")
        creep = self.capped(xi)
        # the step ends in steady rolling: marching would cost ds/h substeps for nothing
        steady = ds > STEADY_AFTER * relaxation_length(0.0, load, self.radius, self.contact_modulus, self.mu,
                                                       self.datum_length)
        fine = advance(self, solver, state.transient(), state.pending, load, creep, ds, steady)
        substeps, iterations, converged, messages = fine.substeps, fine.iterations, fine.converged, fine.messages
        force = fine.output.tangential_force_per_length
        coarse = None
        if self.extrapolate:
            coarse = advance(self, self.coarse_solver, state.coarse, state.coarse_pending, load, creep, ds, steady)
            iterations += coarse.iterations
            converged &= coarse.converged
            messages += coarse.messages
            # first-order Richardson on nested grids (h halved), within the friction limit mu N'
            limit = self.mu * load
            force = max(-limit, min(limit, 2.0 * force - coarse.output.tangential_force_per_length))
            info |= {"fine_force": fine.output.tangential_force_per_length,
                     "coarse_force": coarse.output.tangential_force_per_length}
        p = self.pressure(load)
        h = solver.grid.element_width
        a, offset, _ = patch_geometry(solver.grid, p > 0)
        info |= {"substeps": substeps, "dissipation": fine.dissipation, "grid": solver.grid,
                 "memory_cut_bound": max(fine.cut_bound, 0.0 if coarse is None else coarse.cut_bound)}
        committed = fine.committed
        new = InstationaryState("transient", committed.tangential_force_per_length, distance, state.steps + 1,
                                committed.traction, committed.stick, committed.slip, history,
                                None if coarse is None else coarse.committed, fine.pending,
                                (0.0, 0.0) if coarse is None else coarse.pending)
        message = ("discretised transient, creep control" if ds > 0.0 else
                   "discretised transient, static step (force held)") if converged else "; ".join(messages)
        if self.extrapolate:
            message += f", extrapolated from n = {self.coarse_solver.grid.elements}/{solver.grid.elements}"
        if steady:
            message += " (rolled into steady rolling)"
        output = fine.output
        slip = np.where(p > 0, output.slip, np.nan)
        return new, ContactResult(method="instationary_transient", success=converged, message=message,
                                  normal_load_per_length=load, tangential_force_per_length=force, creep=xi,
                                  contact_half_width=a, contact_offset=offset,
                                  stick_half_width=0.5 * h * int((output.stick & (p > 0)).sum()),
                                  max_pressure=float(p.max()), iterations=iterations,
                                  distributions=TabulatedDistributions(solver.grid.centres, p, output.traction,
                                                                       slip), info=info)


def relaxation_result(model: InstationaryModel, state: InstationaryState, load, xi, ds, distance, history, a, p0,
                      info) -> tuple[InstationaryState, ContactResult]:
    """One step of ``model``'s relaxation lag (:func:`rollcontact.line.instationary.relaxation.relaxation_step`) over
    the rolled distance ``ds`` [m]: the new state and the result, q(x) Carter's distribution for the lag's force."""
    force, substeps = relaxation_step(state.tangential_force_per_length, xi, ds, load, model.radius,
                                      model.contact_modulus, model.mu, model.datum_length)
    a_star = stick_half_width(force, load, a, model.mu)
    steady_creep = carter_creep(force, load, model.radius, model.contact_modulus, model.mu)
    info |= {"relaxation_length": relaxation_length(force, load, model.radius, model.contact_modulus, model.mu,
                                                    model.datum_length),
             "equivalent_steady_creep": steady_creep, "substeps": substeps}
    new = InstationaryState("relaxation", force, distance, state.steps + 1, history=history)
    # q(x): Carter's distribution for the current force (the lag models T', not the shape of q)
    dist = CarterDistributions(a, p0, a_star, 0.0, model.mu, steady_creep if force != 0.0 else 1.0, model.radius)
    return new, ContactResult(method="instationary_relaxation", success=True,
                              message="first-order lag around Carter (static: force held)" if ds == 0.0
                              else "first-order lag around Carter", normal_load_per_length=load,
                              tangential_force_per_length=force, creep=xi, contact_half_width=a,
                              contact_offset=0.0, stick_half_width=a_star, max_pressure=p0, iterations=substeps,
                              distributions=dist, info=info)


def advance(model: InstationaryModel, solver: TransientSolver, current: TransientState, pending: tuple[float, float],
            load: float, creep: float, ds: float, steady: bool) -> Advance:
    """One step of ``model``'s ``solver`` rolling ``ds`` [m] from the committed state ``current`` and its
    ``pending`` roll.

    The grid commits substeps of exactly one element h: the convected traction then moves by whole elements,
    and the pair's extrapolation cancels the first-order error cleanly.  Substeps of a fraction r of an element
    (what splitting each host step into equal substeps gives) leave an O(h^2) bias that varies erratically with
    r, and with it the pair's ``error n^2`` (``benchmarks/bench_substep_rule.py``,
    ``benchmarks/results/substep_rule.md``).  A host step that ends between element boundaries leaves
    a pending roll, its distance and rigid slip (the creep integrated over it, each host step's creep held over
    its part); the next steps complete it.  The step's output is a provisional substep of the pending roll from
    the committed state, not kept: its error is one step's, which ripples with the roll's phase by O(h^2) and
    does not accumulate.  ``ds`` = 0 (a static step) first commits the pending roll as one short substep, then
    redistributes q at the held force.  ``steady``: straight to steady rolling, nothing pending.
    """
    p = model.pressure(load, solver)
    h = solver.grid.element_width
    if steady:
        current = model.steady_on(solver, load, creep)
        return Advance(current, (0.0, 0.0), current, 0, 0, ds * h * float(np.dot(current.traction, current.slip)),
                       True, [])
    run = Run()
    distance, rigid = pending
    cut = 0.0
    if ds > 0.0:
        rest = ds
        commits = math.floor((distance + rest) / h * (1.0 + 1e-12))
        if model.max_substeps is not None and commits > model.max_substeps:
            # the history of the roll beyond its last max_substeps elements becomes steady rolling under the held
            # inputs; the same pending roll remains at the end
            rest = distance + rest - (commits - model.max_substeps) * h
            distance = rigid = 0.0
            current = model.steady_on(solver, load, creep)
            cut = model.memory_cut_bound(load, model.max_substeps * h)
        while distance + rest >= h * (1.0 - 1e-12):
            take = min(rest, max(0.0, h - distance))
            distance, rigid, rest = distance + take, rigid + creep * take, rest - take
            # exactly h (the roll may fall short by round-off): one convected matrix for every commit
            current = run.add(*solver.step(current, p, h, creep=rigid / distance))
            distance = rigid = 0.0
        distance, rigid = distance + rest, rigid + creep * rest
        output = current
        if distance > 1e-9 * h:
            output, res = solver.step(current, p, distance, creep=rigid / distance)
            run.add(output, res, committed=False)
        return Advance(current, (distance, rigid), output, run.substeps, run.iterations, run.dissipation,
                       run.converged, run.messages, cut)
    if distance > 0.0:
        current = run.add(*solver.step(current, p, distance, creep=rigid / distance))
    held = current.tangential_force_per_length
    if abs(held) >= FORCE_MARGIN * h * model.mu * p.sum():
        # saturated: full slip, which force control (it needs a stick element) cannot represent
        q = math.copysign(model.mu, held) * p
        current = TransientState(q, np.zeros(q.size, dtype=bool), np.zeros(q.size), h * q.sum(), current.steps + 1)
    else:
        current = run.add(*solver.step(current, p, 0.0, tangential_force=held))
    return Advance(current, (0.0, 0.0), current, max(1, run.substeps), run.iterations, run.dissipation,
                   run.converged, run.messages)


class Advance(NamedTuple):
    """What :meth:`InstationaryModel.advance` returns for one grid."""

    committed: TransientState
    """State after the last whole-element substep (what the next step starts from)."""
    pending: tuple[float, float]
    """The roll not yet committed: distance [m] (less than one element) and rigid slip, xi integrated over it [m]."""
    output: TransientState
    """State at the end of the host step: the committed one after a provisional substep of the pending roll."""
    substeps: int
    """Solves of the step, the provisional one included (0 when it rolled into steady rolling)."""
    iterations: int
    """Active-set iterations of those solves."""
    dissipation: float
    """Frictional work [J/m] of the committed substeps (a pending roll's with the substep that commits it)."""
    converged: bool
    """Every solve converged."""
    messages: list[str]
    """The messages of those that did not."""
    cut_bound: float = 0.0
    """Bound [N/m] of the force error of a memory cut (:attr:`InstationaryModel.max_substeps`); 0: none."""


class Run:
    """Tally of the solves of one :meth:`InstationaryModel.advance`."""

    def __init__(self):
        self.substeps, self.iterations, self.dissipation, self.converged, self.messages = 0, 0, 0.0, True, []

    def add(self, state: TransientState, res, committed: bool = True) -> TransientState:
        """Count one solve (its work only when ``committed``); returns its state."""
        self.substeps += 1
        self.iterations += res.iterations
        if committed:
            self.dissipation += res.dissipation
        self.converged &= res.converged
        if not res.converged:
            self.messages.append(res.message)
        return state


def remap(state: TransientState, old: Grid, new: Grid) -> TransientState:
    """A transient state carried from grid ``old`` to the larger window ``new``.

    q is piecewise constant, so its integral from the window's start is piecewise linear: the new elements take
    the averages of q over them (a conservative remap: T' is kept, q is smeared over at most one old element).
    The stick mask is taken at the nearest old element (it only warm-starts the active set); the slip is reset
    (Coulomb friction does not use it).
    """
    integral = np.concatenate(([0.0], np.cumsum(state.traction) * old.element_width))
    old_edges = np.linspace(old.x_min, old.x_max, old.elements + 1)
    new_edges = np.linspace(new.x_min, new.x_max, new.elements + 1)
    traction = np.diff(np.interp(new_edges, old_edges, integral)) / new.element_width
    stick = np.interp(new.centres, old.centres, state.stick.astype(float)) >= 0.5
    return TransientState(traction, stick, np.zeros(new.elements), state.tangential_force_per_length, state.steps)


def aligned_grid_load(load: float, elements: int, factor: float, multiple: int = 1) -> float:
    """Grid load [N/m] near ``factor * load`` whose window puts the edges of the Hertz patch of ``load`` on element
    boundaries.

    The window ``+-W = +-1.25 a(grid load)`` of n elements ``h = 2W/n`` has the patch edges ``+-a`` on element
    boundaries when ``(W - a)/h = m`` is an integer, i.e. ``W = a / (1 - 2m/n)``; m is rounded from
    ``W = 1.25 sqrt(factor) a`` and ``a ~ sqrt(N')`` gives the load.  Then the discretised patch covers whole elements
    and the steady force converges regularly, ``|T'_n - T'_Carter| = 0.57/n mu N'`` for factor 2; with the edges
    inside elements it scatters up to 4e-3 mu N' for n = 50..400 (``benchmarks/bench_transient_auto.py``).  Grids
    of fewer than three elements cannot be aligned: ``factor * load``.  With ``multiple`` = 2, m is even, so that
    the grid of n/2 elements on the same window is aligned too (the extrapolating transient).
    """
    ratio = WINDOW_FACTOR * math.sqrt(factor)  # W / a wanted
    m = multiple * round(0.5 * elements * (1.0 - 1.0 / ratio) / multiple)
    if not 0 < 2 * m < elements:
        return factor * load
    return load * (1.0 / (WINDOW_FACTOR * (1.0 - 2.0 * m / elements))) ** 2
