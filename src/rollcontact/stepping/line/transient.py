"""The instationary side of the stepping model: which instationary model a step runs, and their error models.

``transient`` = 1 runs quasi-static steps while the inputs vary slowly (stationarity above
:meth:`InstationaryStepping.transient_threshold`), then the relaxation lag (R1) while its error bound for the creep
swing seen (:func:`rollcontact.line.instationary.lag_error_bound`) meets the tolerance, else the discretised transient
on the cheapest grid, or extrapolating pair of nested grids, whose error model ``C / n^p`` meets it
(:func:`transient_setting`).  The constants of those error models are calibrated by
``benchmarks/bench_transient_auto.py`` and ``benchmarks/calibrate_transient_pairs.py``.  A module of its own so that
:mod:`rollcontact.stepping.line.model` keeps the quasi-steady step and this the instationary models and their choice.
"""

from __future__ import annotations

import math

from rollcontact.line.instationary.model import InstationaryModel, InstationaryState, aligned_grid_load
from rollcontact.line.instationary.relaxation import (
    LAG_MEMORY,
    carter_creep,
    creep_envelope,
    lag_error_bound,
    relaxation_length,
)
from rollcontact.line.instationary.stationarity import STATIONARITY_THRESHOLD
from rollcontact.line.scene import Surface
from rollcontact.stepping.base import ModelError
from rollcontact.stepping.line.parameters import DISCRETISED, INSTATIONARY_CODES, StepOutputs
from rollcontact.stepping.parameters import AUTO, new_tuple

DEFAULT_TRANSIENT_TOLERANCE = 1e-2
"""Quasi-static error [1 of mu N] that ``transient`` = 1 tolerates before it switches the relaxation lag in, when the
``tolerance`` parameter is 0 (the defaults: no accuracy is promised for the lag itself, :data:`RELAXATION_ACCURACY`)."""


RELAXATION_ACCURACY = 0.21
"""Error bound [1 of mu N] of the relaxation lag: 1.4 times the largest error against the discretised transient
measured by ``benchmarks/calibrate_relaxation.py`` (its table) over lambda/a = 1..40 and creep swings up to 10
saturation creeps.  The lag's error grows with the swing, most where it passes zero creep.  So ``transient`` = 1
with ``method`` = 0 and a ``tolerance`` below this runs the lag only while its bound for the swing actually seen
(:func:`rollcontact.line.instationary.lag_error_bound`) meets the tolerance and the discretised transient
(:func:`transient_setting`) otherwise; the lag runs unconditionally with ``tolerance`` = 0 (the cheap default, no
accuracy promised) or ``transient`` = 2."""


LAG_RETURN = 0.5
"""A running discretised transient hands back to the lag once the lag's bound is below this times the tolerance
(:meth:`ContactModel.choose_model`)."""


GRID_LOAD_FACTOR = 2.0
"""The discretised transient's grid holds loads up to about this factor times the load it is aligned to (a up to
sqrt(2) times; :func:`rollcontact.line.instationary.aligned_grid_load`)."""


TRANSIENT_ERROR_ORDER = 1.0
"""p of the discretised transient's error model ``max |T' - T'_converged| <= C / n^p`` [1 of mu N]
(:func:`transient_error`; n elements on the model's grid): with whole-element substeps ``error n`` is regular
in n on every signal of ``benchmarks/calibrate_transient_pairs.py`` (``benchmarks/results/transient_pairs.md``), and
``benchmarks/bench_transient_auto.py`` observes first order (``benchmarks/results/transient_auto.md``, section (3)
Error model)."""


TRANSIENT_ERROR_CONSTANT = 0.82
"""C of that error model: 1.4 times the largest ``error n`` measured by ``benchmarks/calibrate_transient_pairs.py``
(the single grids of ``benchmarks/results/transient_pairs.md`` against the pair 500/1000, lambda/a = 1..40 and creep
reversals, n = 50..500), checked up to n = 600 against a Richardson 400/800 by ``benchmarks/bench_transient_auto.py``
(``benchmarks/results/transient_auto.md``, section (3)).  Whole-element substeps keep the error regular: what remains
is the quasi-steady bias of steady rolling on the grid against Carter (section (2) of the same results), which also
bounds the switch-in and hand-back jumps."""


TRANSIENT_MIN_ELEMENTS = 50
"""Fewest elements (of a single grid, or the finer of a pair) the models choose: the coarsest grid their error models
are calibrated on."""


TRANSIENT_MAX_ELEMENTS = 800
"""Most elements :func:`transient_elements` chooses: the finest grid the error model was calibrated on (it is not
extrapolated); the cost per host step grows about as n^2.5 (``benchmarks/results/transient_auto.md``, section (1))."""


EXTRAPOLATED_ERROR_ORDER = 2.0
"""p of the extrapolating transient's error model ``max |T' - T'_converged| <= C / n^p`` [1 of mu N]
(:func:`transient_model_error`; n the finer grid's elements): the first-order errors of the nested grids cancel
and what remains falls as n^-2 (``benchmarks/calibrate_transient_pairs.py``, ``benchmarks/results/transient_pairs.md``).
Each grid commits whole-element substeps (:meth:`InstationaryModel.advance`): with equal substeps of a fraction r of
an element per host step ``error n^2`` is erratic in r (``benchmarks/bench_substep_rule.py``,
``benchmarks/results/substep_rule.md``)."""


EXTRAPOLATED_ERROR_CONSTANT = 6.6
"""C of that model: 1.4 times the largest ``error n^2`` measured by ``benchmarks/calibrate_transient_pairs.py``
(``benchmarks/results/transient_pairs.md``) against the pair 500/1000, over lambda/a = 1..40,
``(0.5 + 0.3 sin) mu a/R`` and a creep reversal ``0.9 sin`` at lambda/a = 5 and 20, n = 50..500.  By this model the
pair 129/258 certifies 1e-4 mu N'."""


EXTRAPOLATED_MAX_ELEMENTS = 500
"""Most elements (of the finer grid) :func:`transient_setting` chooses for a pair: the finest pair calibrated against a
finer reference (the pair 500/1000)."""


EXTRAPOLATION_COST = 1.4
"""Time per step of a pair over the single grid of n elements: the median of the ratio of the pair's to the plain
transient's time per step in ``benchmarks/results/transient_pairs.md`` (``benchmarks/calibrate_transient_pairs.py``):
the coarse grid adds about 2^-2.5 of the cost (it grows as n^2.5) and one provisional substep per host step."""


def transient_error(elements: int) -> float:
    """Modelled error [1 of mu N] of the discretised transient with n elements: ``C / n^p``.

    :data:`TRANSIENT_ERROR_CONSTANT` and :data:`TRANSIENT_ERROR_ORDER` bound max |T' - T'_converged| / (mu N') of
    ``benchmarks/bench_transient_auto.py`` and ``benchmarks/calibrate_transient_pairs.py`` on the model's grid
    (:func:`rollcontact.line.instationary.aligned_grid_load`).
    """
    return TRANSIENT_ERROR_CONSTANT / elements ** TRANSIENT_ERROR_ORDER


def transient_elements(tolerance: float) -> int:
    """Fewest elements whose :func:`transient_error` meets ``tolerance`` > 0, from :data:`TRANSIENT_MIN_ELEMENTS` to
    :data:`TRANSIENT_MAX_ELEMENTS`.

    ``n = ceil((C / tolerance)^(1/p))``; the cost per step grows with n (about n^2.5), so the fewest is the cheapest.
    """
    needed = (TRANSIENT_ERROR_CONSTANT / tolerance) ** (1.0 / TRANSIENT_ERROR_ORDER)
    # C/t = 400.0000001 asks for 400
    return min(TRANSIENT_MAX_ELEMENTS, max(TRANSIENT_MIN_ELEMENTS, math.ceil(needed * (1.0 - 1e-12))))


def transient_model_error(elements: int, extrapolate: bool) -> float:
    """Modelled error [1 of mu N] of the discretised transient with n elements: :func:`transient_error`, or for
    the extrapolating pair n/2, n ``C_e / n^2`` (:data:`EXTRAPOLATED_ERROR_CONSTANT`)."""
    if extrapolate:
        return EXTRAPOLATED_ERROR_CONSTANT / elements**EXTRAPOLATED_ERROR_ORDER
    return transient_error(elements)


def transient_setting(tolerance: float) -> tuple[int, bool]:
    """``(elements, extrapolate)`` of the cheapest discretised transient whose modelled error meets ``tolerance``.

    The fewest plain elements (:func:`transient_elements`) against the fewest of an extrapolating pair (even, from
    :data:`TRANSIENT_MIN_ELEMENTS` to :data:`EXTRAPOLATED_MAX_ELEMENTS`), by their cost per step ``n^2.5`` (the
    pair's times :data:`EXTRAPOLATION_COST`); when neither meets the tolerance, the more accurate.  Below about 1.4e-2
    the pair wins: by the models 82 elements meet 1e-3 where a single grid would need 820, beyond
    :data:`TRANSIENT_MAX_ELEMENTS`.
    """
    plain = transient_elements(tolerance)
    needed = (EXTRAPOLATED_ERROR_CONSTANT / tolerance) ** (1.0 / EXTRAPOLATED_ERROR_ORDER)
    pair = min(EXTRAPOLATED_MAX_ELEMENTS, max(TRANSIENT_MIN_ELEMENTS, 2 * math.ceil(0.5 * needed * (1.0 - 1e-12))))
    options = [(plain**2.5, plain, False), (EXTRAPOLATION_COST * pair**2.5, pair, True)]
    meeting = [o for o in options if transient_model_error(o[1], o[2]) <= tolerance]
    if meeting:
        return min(meeting)[1:]
    return min(options, key=lambda o: transient_model_error(o[1], o[2]))[1:]


def transient_notice(tolerance: float, elements: int, given: bool, extrapolate: bool = False,
                     adaptive: bool = False) -> str:
    """What the discretised transient chosen for ``tolerance`` reaches, whether that meets it and what to change if
    not; ``adaptive``: it runs only where the relaxation lag's bound does not meet the tolerance
    (:meth:`ContactModel.choose_model`).  The error models behind it are in docs/accuracy.md."""
    reached = transient_model_error(elements, extrapolate)
    grid = f"{elements // 2}/{elements} extrapolated" if extrapolate else f"{elements}"
    where = ", where the relaxation lag would miss it" if adaptive else ""
    text = (f"tolerance = {tolerance!r}: instationary steps run the discretised transient (method_used 5) on "
            f"elements = {grid}, modelled error {reached:.2g} mu N{where}.")
    if reached <= tolerance:
        return text
    fix = "set more elements (0: chosen from the tolerance)" if given else \
        f"raise the tolerance to {reached:.2g} (the finest grid)"
    return text + f" NOT met: {fix}."


def instationary_unavailable(surface: Surface, friction) -> str | None:
    """Why the instationary models cannot treat a scene (they assume a flat surface and Coulomb friction)."""
    if not surface.is_flat:
        return "the instationary models assume a flat surface, and this one is corrugated or curved"
    if not friction.is_constant:
        return "the instationary models assume Coulomb friction, and this friction depends on slip velocity"
    return None


SUBSTEP_COST = (9e-5, 1.6e-9)
"""Modelled time [s] of one whole-element substep of the discretised transient on n elements, ``a + b n^2``
(the active-set solve on the stick block and the convected traction; measured and fitted by
``benchmarks/calibrate_step_budget.py``, table A, which prints the fit next to these constants)."""


def max_substeps(budget: float, elements: int, extrapolate: bool) -> int | None:
    """The most whole-element substeps of one host step that fit ``budget`` [s] (0: None, no limit) on n =
    ``elements`` (and n/2 when ``extrapolate``): :data:`SUBSTEP_COST` per substep, two of the budget's substeps kept
    for the provisional substep and the steady start of a memory cut.  At least one."""
    if not budget > 0.0:
        return None
    a, b = SUBSTEP_COST
    cost = a + b * elements * elements
    if extrapolate:
        half = elements // 2
        cost += a + b * half * half
    return max(1, int(budget / cost) - 2)


class InstationaryStepping:
    """The instationary half of :class:`rollcontact.stepping.line.model.ContactModel` (``transient`` = 1 or 2).

    A mixin: it reads the model's state and constants (``state``, ``per_width``, ``mu``, ...) and its quasi-steady
    step, and adds the instationary models, the switching between them and the quasi-steady step, and the
    stepping of a loaded step through them (module docstring of :mod:`rollcontact.stepping.line.model`).
    """

    instationary: InstationaryModel | None = None
    """The instationary model of ``transient`` = 1/2 (None: every step quasi-steady)."""
    lag: InstationaryModel | None = None
    """``transient`` = 1 with ``method`` = 0 and a tolerance below :data:`RELAXATION_ACCURACY`: the relaxation
    lag, run instead of the discretised transient ``instationary`` while its error bound for the creep swing
    (:func:`rollcontact.line.instationary.lag_error_bound`) meets the tolerance."""

    def setup_instationary(self, p, material, radius: float, friction, surface) -> list[str]:
        """Build the instationary models the parameters ``p`` ask for; returns the notices about them.

        Raises
        ------
        ModelError
            ``transient`` = 2 on a scene the instationary models cannot treat.
        """
        notices = []
        self.transient_auto = p.transient == 1 and p.method != DISCRETISED
        self.transient_tolerance = p.tolerance or DEFAULT_TRANSIENT_TOLERANCE
        self.settle_tolerance = self.transient_tolerance
        """Distance [1 of mu N] from the quasi-steady force within which ``transient`` = 1 hands back."""
        if p.transient == 0:
            return notices
        unavailable = instationary_unavailable(surface, friction)
        if unavailable is not None and p.transient == 2:
            raise ModelError(f"transient = 2 (always) cannot treat this scene: {unavailable}; use transient = 0 "
                             "or 1 (1 solves it quasi-steady)")
        if unavailable is not None:
            notices.append(f"transient = 1 (auto): {unavailable}, so every step is solved quasi-steady and the "
                           "stationarity output shows how far that holds")
            return notices
        tight = 0.0 < p.tolerance < RELAXATION_ACCURACY
        adaptive = tight and self.transient_auto and p.method == AUTO
        discretised = p.method == DISCRETISED or adaptive
        elements, extrapolate = p.elements or 100, False
        if discretised and p.tolerance:
            if not p.elements:
                elements, extrapolate = transient_setting(p.tolerance)
            notices.append(transient_notice(p.tolerance, elements, p.elements > 0, extrapolate, adaptive))
            # the transient settles on its own steady force, which is within its error of Carter's
            self.settle_tolerance = max(self.transient_tolerance, transient_model_error(elements, extrapolate))
        elif not discretised and (tight or not p.tolerance):
            notices.append(f"tolerance = {p.tolerance!r}: instationary steps run the relaxation lag (method_used 4), "
                           f"whose error grows with the creep swing, up to {RELAXATION_ACCURACY:g} mu N. For less, set "
                           f"transient = 1, method = 0 and a tolerance below {RELAXATION_ACCURACY:g}.")
        self.instationary = InstationaryModel(
            radius, material.contact_modulus, friction.static_coefficient,
            mode="transient" if discretised else "relaxation", datum_length=p.datum or None,
            elements=elements, extrapolate=extrapolate,
            max_substeps=max_substeps(p.step_budget, elements, extrapolate) if discretised else None)
        if adaptive:
            self.lag = InstationaryModel(radius, material.contact_modulus, friction.static_coefficient,
                                         mode="relaxation", datum_length=p.datum or None)
        return notices

    def instationary_step(self, x: float, normal_load: float, creep: float, velocity: float,
                          step_size: float) -> tuple[StepOutputs, InstationaryState | None]:
        """Outputs and new instationary state (None: quasi-steady) of a loaded step with ``transient`` = 1 or 2.

        The instationary model rolls ``V h`` with the inputs held.  In auto mode the step is quasi-steady while
        the stationarity measure stays at or above :meth:`transient_threshold` and no lag is pending; the
        instationary model then starts from the previous step's quasi-steady state (:meth:`switch_in`) and hands
        back once the measure is back above the threshold and its force is within ``settle_tolerance`` mu N of the
        quasi-steady force.
        """
        state = self.state
        model = self.instationary
        load = normal_load * self.per_width
        lag = state.instationary
        quasi = envelope = None
        if self.transient_auto:
            quasi = (self.closed_form_step if self.closed_form else self.solve_step)(x, normal_load, creep, velocity)
            if not quasi.contact_half_width > 0.0:  # a load so small that a underflows: no contact to roll through
                state.creep_envelope = None
                return quasi, None
            if self.lag is not None:
                envelope, model = self.choose_model(lag, load, creep, velocity * step_size, quasi.contact_half_width)
            if lag is None and not quasi.stationarity < self.transient_threshold(quasi.contact_half_width, load):
                state.creep_envelope = envelope
                return quasi, None
        try:
            handover = lag is not None and lag.mode != model.mode
            if handover:
                lag = None  # the model takes over from the other one's force (switch_in)
            grid_load, lag = self.prepare_grid(load, lag) if model.mode == "transient" else (0.0, lag)
            if lag is None:
                lag = self.switch_in(model, load, handover) if quasi is not None else model.initial_state()
            lag, result = model.step(lag, load, creep, velocity, step_size)
        except (ValueError, ArithmeticError) as exc:
            raise ModelError(f"instationary {model.mode} model at X = {x!r} m (N = {normal_load!r} N, creep = "
                             f"{creep!r}, V = {velocity!r} m/s): {exc}") from None
        if not result.success:
            raise ModelError(f"instationary {model.mode} model failed at X = {x!r} m: {result.message}")
        cut = result.info.get("memory_cut_bound", 0.0)
        if cut > self.transient_tolerance * self.mu * load:
            self.notice_once("memory cut", f"step_budget = {self.parameters.step_budget!r} s allows "
                             f"{model.max_substeps} substeps of the discretised transient per step: steps that roll "
                             f"further (first at X = {x!r} m) err by up to {cut / (self.mu * load):.2g} mu N, above "
                             f"the tolerance {self.transient_tolerance!r}. Raise step_budget or shorten the host "
                             "steps.")
        force_per_length = float(result.tangential_force_per_length)
        a = float(result.contact_half_width)
        if quasi is not None:
            settled = abs(force_per_length - quasi.tangential_force * self.per_width) <= (
                self.settle_tolerance * self.mu * load)
            if settled and not quasi.stationarity < self.transient_threshold(a, load):
                state.creep_envelope = envelope
                return quasi, None
            measure = quasi.stationarity
        else:
            measure = self.stationarity(x, normal_load, creep, velocity, a)
        state.grid_load = grid_load  # last: a refused step leaves the state as it was
        state.creep_envelope = envelope
        force = force_per_length * self.width
        stiffness = self.lag_stiffness(force_per_length, load, a, velocity * step_size)
        return new_tuple(StepOutputs, (force, force_per_length / load, a, float(result.stick_half_width),
                                       self.flat_offset, float(result.max_pressure), velocity * creep * force,
                                       stiffness * self.width, measure, INSTATIONARY_CODES[model.mode], x)), lag

    def prepare_grid(self, load: float, lag: InstationaryState | None) -> tuple[float, InstationaryState | None]:
        """Build the discretised transient's grid for this step; returns its load (for ``state.grid_load``) and
        ``lag`` on it.

        A running transient keeps the grid its traction history lives on (``state.grid_load``, also after a
        restore into a fresh model) until the load outgrows it; then the history moves to a larger grid
        (:meth:`InstationaryModel.regrid`).  One that starts gets a new grid.  New grids hold about
        :data:`GRID_LOAD_FACTOR` times the load (when starting: the larger of this and the previous step's) and are
        aligned to it (:func:`rollcontact.line.instationary.aligned_grid_load`), so the grid is a function of the state
        and the inputs.
        """
        state = self.state
        model = self.instationary
        multiple = 2 if model.extrapolate else 1  # both grids of a pair aligned
        if lag is not None:
            grid_load = state.grid_load
            if not grid_load > 0.0:
                raise ValueError(f"the state carries a transient traction history but grid_load = {grid_load!r}")
        else:
            previous = 0.0 if state.previous is None else state.previous[1] * self.per_width
            grid_load = aligned_grid_load(max(load, previous), model.elements, GRID_LOAD_FACTOR, multiple)
            if not model.holds(grid_load):  # a previous load beyond the datum's grid: start from this one
                grid_load = aligned_grid_load(load, model.elements, GRID_LOAD_FACTOR, multiple)
        if model.solver is None or model.max_load != grid_load:
            model.build_solver(grid_load)
        if lag is not None and load > grid_load:
            grid_load = aligned_grid_load(load, model.elements, GRID_LOAD_FACTOR, multiple)
            lag = model.regrid(lag, grid_load)
        return grid_load, lag

    def switch_in(self, model: InstationaryModel, current_load: float, handover: bool = False) -> InstationaryState:
        """State of ``model`` that continues the previous step (quasi-steady, or the other model's) without a jump.

        Relaxation: the lag starts at the previous step's force.  Discretised transient: steady rolling at the
        previous step's load and creep on the grid (:meth:`InstationaryModel.steady_state`, the fixed point of the
        whole-element substeps, so holding the inputs changes T' only by the O(h^2) ripple of the provisional
        substep); its force differs from the quasi-steady one by the discretisation error, at most
        :func:`transient_model_error`.  When it takes over
        from the lag (``handover``), the creep is the lag's equivalent steady creep (Carter's creep of its force):
        the traction history the lag does not carry starts as Carter's, an error the lag's bound covered at the
        step before.  No traction after an unloaded step.
        """
        if model.mode == "relaxation":
            return InstationaryState("relaxation", self.state.outputs.tangential_force * self.per_width)
        previous = self.state.previous
        if previous is None or previous[1] == 0.0:
            return model.initial_state()
        load = previous[1] * self.per_width
        if load > model.max_load:  # the grid cannot hold the previous contact (prepare_grid): start at this load
            load = current_load
        creep = previous[2]
        if handover:
            creep = carter_creep(self.state.outputs.tangential_force * self.per_width, load, self.radius,
                                 self.contact_modulus, self.mu)
        return model.steady_state(load, creep)

    def choose_model(self, running: InstationaryState | None, load: float, creep: float, distance: float,
                     half_width: float) -> tuple[tuple[float, float], InstationaryModel]:
        """The creep envelope after this step and the model to run it with, for ``transient`` = 1 with a tolerance.

        The lag (:attr:`lag`) while :func:`rollcontact.line.instationary.lag_error_bound` of the envelope meets the
        tolerance, else the discretised transient (:attr:`instationary`); a running transient hands back to the
        lag only below :data:`LAG_RETURN` times the tolerance, so that a swing near the limit does not switch
        models every step.
        """
        envelope = creep_envelope(self.state.creep_envelope, creep / (self.saturation_per_half_width * half_width),
                                  distance / (LAG_MEMORY * self.zero_force_length(load)))
        limit = self.transient_tolerance
        if running is not None and running.mode == "transient":
            limit *= LAG_RETURN
        return envelope, self.lag if lag_error_bound(envelope) <= limit else self.instationary

    def transient_threshold(self, half_width: float, load: float) -> float:
        """Stationarity below which ``transient`` = 1 switches the lag in [1].

        Under creep control the contact lags by the relaxation length l (``a ln(2L/(sqrt(e) a))`` at zero force,
        about 4.4 a for a railway wheel, :func:`rollcontact.line.instationary.relaxation_length`).  For a creep
        oscillation over Carter's saturation creep and wavelength lambda = stationarity * a, the quasi-steady force
        then errs by about ``2 (2 pi l / lambda)`` mu N' (the Carter slope at zero force is 2 mu N' per saturation
        creep), so the threshold is ``4 pi (l / a) / tolerance``, at least :data:`STATIONARITY_THRESHOLD` (the
        paper's 20, a rule for force control that creep control would miss: ``benchmarks/bench_instationary.py``
        compares quasi-static Carter with the transient for lambda/a = 5..50).
        """
        return max(STATIONARITY_THRESHOLD,
                   4.0 * math.pi * self.zero_force_length(load) / (half_width * self.transient_tolerance))

    def zero_force_length(self, load: float) -> float:
        """Relaxation length [m] at T' = 0 for N' = ``load`` [N/m] (the longest; one-entry cache: up to three calls
        per step of ``transient`` = 1, and constant loads are the common case)."""
        if self.length_cache[0] != load:
            self.length_cache = (load, relaxation_length(0.0, load, self.radius, self.contact_modulus, self.mu,
                                                         self.instationary.datum_length))
        return self.length_cache[1]

    def lag_stiffness(self, force: float, load: float, half_width: float, distance: float) -> float:
        """dT'/dxi [N/m] of one instationary step of rolled distance ``distance`` [m]: ``(1 - exp(-ds/l)) k``.

        The derivative of the step's end force with respect to the creep held over it, for the lag linearised at
        the current force: Carter's slope ``k = 2 N' R a*/a^2`` times the fraction of the step's lag that relaxes
        (l the relaxation length, :func:`rollcontact.line.instationary.relaxation_length`).  Exact for the relaxation
        model to first order in the force change; for the discretised transient the same linearisation.
        """
        a_star = half_width * math.sqrt(max(0.0, 1.0 - abs(force) / (self.mu * load)))
        steady = 2.0 * self.radius * (load / half_width) * (a_star / half_width)  # no underflow of N' a*
        length = relaxation_length(force, load, self.radius, self.contact_modulus, self.mu,
                                   self.instationary.datum_length)
        if length <= 0.0:
            return steady
        return -math.expm1(-distance / length) * steady

