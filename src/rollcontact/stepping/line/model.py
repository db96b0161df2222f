"""Stepping contact model for co-simulation: parameters -> (state, inputs, step) -> outputs.

This is the library half of the ``RollingContact2D`` FMU: the FMU's slave only maps its variables to a
:class:`ContactModel` and back, so everything here can be used and tested without any FMI tool.

* :class:`~rollcontact.stepping.line.parameters.ContactParameters` holds the fixed parameters (FMU parameters of the
  same names) and checks them.
* :class:`ContactModel` precomputes what does not change between steps and evaluates one communication step
  with :meth:`ContactModel.step` (inputs in N, 1 and m/s; outputs in SI units, see
  :class:`~rollcontact.stepping.line.parameters.StepOutputs`).
* :class:`~rollcontact.stepping.line.state.ModelState` is everything the model remembers between steps: axis position,
  the input history of the stationarity measure and the last outputs.  It is a plain dataclass that can be copied,
  turned into a JSON dict or bytes and restored; restore -> step -> restore -> step gives identical outputs.
* Its instationary half (the relaxation lag and the discretised transient switched in and out) is the mixin
  :class:`~rollcontact.stepping.line.transient.InstationaryStepping`.

Frames and signs
----------------
The model's axis position ``X`` [m] runs in the rolling direction: ``X(t) = initial_position + int V dt`` with
the rolling speed ``V >= 0``.  The package's scene frame runs the other way (its cylinder rolls towards -x, see
:mod:`rollcontact`), so a surface ``Z(X)`` given to the model is solved as the mirrored scene
``Z_scene(x') = Z(-x')`` with the axis at ``x' = -X`` (:meth:`ContactModel.scene`): the corrugation is met in the
right order and the stick zone stays at the leading edge.  ``contact_offset`` is reported in the model's frame
(positive ahead of the axis, e.g. ``+R alpha`` uphill on a surface rising with slope ``alpha``).  Creep and
tangential force keep the package's meaning (xi > 0 gives T > 0).

Time stepping
-------------
Inputs are sampled at the communication points.  ``step(t_n, h, N_n, xi_n, V_n)`` first advances the axis to
``X(t_n)`` with the trapezoid of the velocity samples at ``t_(n-1)`` and ``t_n`` (accumulated as a compensated
sum, so there is no drift over long runs), then evaluates the quasi-steady contact for the inputs sampled at
``t_n`` at ``X(t_n)``.  Those are the outputs a host reads at ``t_n + h``.

Instationary rolling
--------------------
``transient`` = 2 (always) evaluates every loaded step with :class:`rollcontact.line.instationary.InstationaryModel`,
which rolls the distance ``V_n h`` with the inputs sampled at ``t_n`` held (zero-order hold, the host's view of
the step): the relaxation model (the lag (R1) around Carter, ``method_used`` 4) or, with ``method`` = 3, the
discretised transient in creep control (``method_used`` 5).  ``transient`` = 1 (auto) stays quasi-steady while
the inputs vary slowly and switches the instationary model in when the stationarity measure
(:func:`rollcontact.line.instationary.stationarity_of_samples`) falls below :meth:`ContactModel.transient_threshold`,
starting from the previous step's quasi-steady state (:meth:`ContactModel.switch_in`), and switches back once the
inputs are slow again and its force is back within the tolerance of the quasi-steady one.  The relaxation lag's
error grows with the creep swing, up to its bound :data:`~rollcontact.stepping.line.transient.RELAXATION_ACCURACY` mu N
(calibrated by ``benchmarks/calibrate_relaxation.py``): it is the default (``tolerance`` = 0), which promises no
accuracy.  For a ``tolerance`` below that bound, with ``method`` = 0, ``transient`` = 1 bounds the lag's error by
the creep swing of the last few relaxation lengths (:func:`rollcontact.line.instationary.lag_error_bound` of the
envelope in ``state.creep_envelope``) and runs the lag while that bound meets the tolerance, the discretised
transient where it does not (:meth:`ContactModel.choose_model`): the cheapest transient whose modelled error meets
the tolerance (:func:`~rollcontact.stepping.line.transient.transient_setting`: in practice the extrapolating pair of
nested grids, at most :data:`~rollcontact.stepping.line.transient.EXTRAPOLATED_MAX_ELEMENTS`; ``elements`` > 0 runs one
grid of that many), switched in from steady rolling on its grid at the previous creep, or at the lag's equivalent
creep when it takes over from the lag; it hands back to the lag once the swing has died down.  So stationary inputs
stay on the cheap closed form and small swings on the lag.  Both models assume a flat
surface and Coulomb friction: on other scenes ``transient`` = 2 is refused and ``transient`` = 1 stays quasi-steady
(:attr:`ContactModel.notices` says so).  With ``method`` = 3, ``transient`` = 1 behaves as 2: the discretised
method is asked for on every step, and its transient is exact in steady rolling too.

Frictional power
----------------
For every quasi-steady solution the power dissipated by slip per unit length is
``V int q(x) s(x) dx = V xi T'``: with ``s = xi + du/dx`` and ``du/dx = (2/(pi E*)) PV-int q(z)/(x - z) dz``
the double integral ``int int q(x) q(z)/(x - z) dz dx`` vanishes by antisymmetry.  Hence
``frictional_power = V xi T`` [W], the rigid-body creep power; the tests check it against quadrature of the
Carter distributions.  In instationary rolling ``V xi T`` is reported too: it is the power the creep puts into the
contact, which there also includes the rate of change of the stored elastic energy.
"""

from __future__ import annotations

import math
import sys
from math import isfinite

import numpy as np

from rollcontact.core.dispatch import used_options
from rollcontact.core.method import unresolved
from rollcontact.line.dispatch import METHODS, solve
from rollcontact.line.instationary.stationarity import stationarity_of_samples
from rollcontact.line.scene import Harmonic, Scene, Surface
from rollcontact.stepping.base import ModelError, SteppingModel
from rollcontact.stepping.line.parameters import (
    CLOSED_FORM,
    OPTION_NAMES,
    STATIONARY,
    TABLE_CODE,
    ContactParameters,
    StepOutputs,
    contact_bodies,
    input_problem,
    method_code,
    step_methods,
)
from rollcontact.stepping.line.state import ModelState
from rollcontact.stepping.line.table import table_use
from rollcontact.stepping.line.transient import InstationaryStepping
from rollcontact.stepping.parameters import new_tuple
from rollcontact.stepping.threads import one_blas_thread

INF = math.inf


def resolved_load(contact_modulus: float, radius: float) -> float:
    """Smallest load per length [N/m] a step resolves: the smallest normal double, and the load whose squared Hertz
    half-width ``a^2 = 4 N' R / (pi E*)`` is that double.  A smaller load is no contact, as zero is: its half-width
    and pressure underflow, so no method gives it a finite, meaningful answer."""
    tiny = sys.float_info.min
    return max(tiny, tiny * math.pi * contact_modulus / (4.0 * radius))


def non_finite(outputs: StepOutputs, normal_load: float, creep: float, velocity: float) -> str:
    """The message for a step whose outputs are not all finite: which output, its value, the inputs, the limit."""
    name, value = next((n, v) for n, v in zip(StepOutputs._fields, outputs, strict=True) if not isfinite(v))
    return (f"{name} = {value!r} is not finite at N = {normal_load!r} N, creep = {creep!r}, V = {velocity!r} m/s: "
            f"the inputs are beyond what the model represents in floating point (outputs up to "
            f"{sys.float_info.max:.4g} in SI units)")


def advanced_position(state: ModelState, velocity: float, dt: float) -> tuple[float, float]:
    """The axis position ``X(t_n) = high + low`` [m] after ``dt`` [s] at the sampled speed ``velocity`` [m/s]: the
    trapezoid of V between the communication points (the previous sample's speed and this one), accumulated as a
    Neumaier-compensated sum (``state.position`` high part, ``state.position_error`` low part)."""
    previous = state.previous
    increment = 0.5 * ((velocity if previous is None else previous[3]) + velocity) * dt
    high = state.position + increment
    if abs(state.position) >= abs(increment):
        return high, state.position_error + ((state.position - high) + increment)
    return high, state.position_error + ((increment - high) + state.position)


def within_friction_bound(outputs: StepOutputs, bound: float, normal_load: float, creep: float,
                          velocity: float) -> StepOutputs:
    """The outputs with ``|T| <= mu_max N`` exactly (``bound`` = mu_max, the law's largest coefficient).

    The methods bound the force per length, ``|T'| <= mu_max N'``; its conversion to the whole width,
    ``T = T' b`` with ``N' = N (1/b)``, can exceed ``mu_max N`` by the rounding of the two products (a few ulp).
    Only that rounding is removed here: the force, the traction coefficient and the power take the bound.  A
    NaN force stays NaN (the step is then refused).
    """
    if outputs[0] != outputs[0]:
        return outputs
    force = math.copysign(bound * normal_load, outputs[0])
    return outputs._replace(tangential_force=force, traction_coefficient=math.copysign(bound, force),
                            frictional_power=velocity * creep * force)


def mirrored(surface: Surface) -> Surface:
    """The surface ``Z(-X)``: odd polynomial terms and sine amplitudes change sign."""
    return Surface(polynomial=tuple(c if j % 2 == 0 else -c for j, c in enumerate(surface.polynomial)),
                   harmonics=tuple(Harmonic(h.wavenumber, h.cos_amplitude, -h.sin_amplitude)
                                   for h in surface.harmonics))


class ContactModel(InstationaryStepping, SteppingModel):
    """Quasi-steady 2D rolling contact of a wheel on a (corrugated) surface, advanced one step at a time.

    Parameters
    ----------
    parameters : ContactParameters, optional
        Fixed parameters (defaults when omitted).
    start_time : float
        Time [s] of the initial state.
    stop_time : float, optional
        End time [s] of the run when known (an FMU's setupExperiment): ``table`` = auto then builds a certified table
        only when the steps left pay for it (:mod:`rollcontact.stepping.line.table`).

    Raises
    ------
    ModelError
        A parameter is out of range, the scene file cannot be read, or the requested method cannot treat the
        scene (e.g. ``method`` = 1 on a corrugated surface, or a method that is not registered).

    Notes
    -----
    With ``method`` = 0 (auto) each step uses the cheapest model the scene needs: the closed forms
    (:func:`rollcontact.line.hertz.hertz` and :func:`rollcontact.line.carter.carter`, written out with precomputed
    constants in :meth:`closed_form_step`) for a flat surface with constant friction; otherwise ``"polynomial"`` and
    then ``"discretised"``, whichever are registered in :data:`rollcontact.METHODS`, the first that accepts the scene
    and succeeds.  An explicit method is used as it is or the step fails with a :class:`ModelError`.
    """

    STATE = ModelState

    def __init__(self, parameters: ContactParameters | None = None, *, start_time: float = 0.0,
                 stop_time: float | None = None):
        p = ContactParameters() if parameters is None else parameters
        if not isinstance(p, ContactParameters):
            raise TypeError(f"parameters must be ContactParameters, got {type(p).__name__}")
        super().__init__(p)
        material, radius, friction, surface, notices = contact_bodies(p)
        notices += self.setup_instationary(p, material, radius, friction, surface)
        self.notices: tuple[str, ...] = tuple(notices)
        """Messages worth showing once (e.g. in an FMU log): ignored parameters, modes not implemented."""
        self.material = material
        self.radius = float(radius)
        self.friction = friction
        self.surface = surface
        self.scene_surface = mirrored(surface)
        self.velocity_dependent = not friction.is_constant
        self.closed_form, self.candidates = step_methods(p, surface, friction)
        self.table_use = table_use(p, material, float(radius), friction, surface,
                                   lambda x, load, creep: self.scene_per_length(x, load, creep, 0.0),
                                   self.instationary is not None, self.log)
        """The certified table of the scene family and its build (:mod:`rollcontact.stepping.line.table`; None: not
        applicable)."""
        self.stop_time = stop_time if stop_time is not None and start_time < stop_time < INF else None
        """End time [s] of the run, None when unknown (also for a stop time not after the start)."""
        self.options = {OPTION_NAMES[name]: getattr(p, name) for name in OPTION_NAMES if getattr(p, name) != 0}
        """Options of the parameters that ``rollcontact.solve`` passes to the methods that accept them."""

        # constants of the closed-form path (no Scene is built there)
        self.contact_modulus = material.contact_modulus
        self.resolved_load = resolved_load(material.contact_modulus, self.radius)
        self.mu = friction.static_coefficient
        self.friction_bound = friction.maximum_coefficient
        self.width = p.contact_width
        self.per_width = 1.0 / p.contact_width
        slope = surface.polynomial[1] if len(surface.polynomial) > 1 else 0.0
        self.flat_offset = self.radius * slope  # uphill by R alpha (docs/physics.md, The tilted surface)
        self.saturation_per_half_width = self.mu / self.radius  # Carter saturation creep over a
        self.length_cache = (math.nan, 0.0)  # (N', zero_force_length(N'))
        self.reset(start_time)

    def initial_state(self, start_time: float) -> ModelState:
        """The state at ``start_time`` [s]: the axis at ``initial_position``, nothing remembered."""
        return ModelState.initial(start_time, self.parameters.initial_position)

    def restore(self, state: ModelState) -> None:
        """Build the certified table ``state`` refers to, if any (a table that cannot be built refuses the state,
        leaving the model as it is)."""
        if self.table_use is not None:
            self.table_use.restore(state.table_domain)

    def scene(self, axis_position: float, normal_load: float, creep: float, velocity: float) -> Scene:
        """The scene solved for axis position X [m], load N [N], creep [1] and speed V [m/s].

        It is in the package's frame (mirrored surface, axis at ``-X``, see the module docstring) with the load
        per unit length ``N / contact_width``.
        """
        return self.scene_per_length(axis_position, normal_load * self.per_width, creep, velocity)

    def scene_per_length(self, axis_position: float, load: float, creep: float, velocity: float) -> Scene:
        """:meth:`scene` for the load per length N' [N/m]."""
        return Scene(normal_load_per_length=load, creep=creep, radius=self.radius, material=self.material,
                     friction=self.friction, surface=self.scene_surface, axis_position=-axis_position,
                     rolling_speed=velocity, name="RollingContact2D")

    def step(self, current_time: float, step_size: float, normal_load: float, creep: float,
             velocity: float) -> StepOutputs:
        """Advance to ``current_time`` and evaluate the contact for the inputs sampled there.

        Parameters
        ----------
        current_time : float
            Communication point t_n [s], not before the previous one.
        step_size : float
            h [s] > 0 (the host reads the outputs at t_n + h).
        normal_load : float
            N [N] >= 0 (0: no contact, all outputs 0).
        creep : float
            xi [1], any finite value (beyond saturation: full slip).
        velocity : float
            Rolling speed V [m/s] >= 0.

        Returns
        -------
        StepOutputs
            Also kept in ``state.outputs``.

        Raises
        ------
        ModelError
            Non-finite or out-of-range input, time going backwards, or no allowed method solves the scene.  The
            state is left unchanged, so the model stays usable.
        """
        if not (0.0 <= normal_load < INF and -INF < creep < INF and 0.0 <= velocity < INF
                and 0.0 < step_size < INF and -INF < current_time < INF):
            raise ModelError(input_problem(current_time, step_size, normal_load, creep, velocity))
        state = self.state
        dt = current_time - state.time
        if dt < 0.0:
            raise ModelError(f"current_time = {current_time!r} s lies before the last communication point "
                             f"{state.time!r} s; restore a saved state to step from an earlier time")
        high, low = advanced_position(state, velocity, dt)
        x = high + low

        lag = None
        load = normal_load * self.per_width
        if self.stop_time is not None and self.table_use is not None:
            self.table_use.remaining = (self.stop_time - current_time) / step_size
        if load < self.resolved_load:  # zero, or below what floating point resolves: no contact
            outputs = StepOutputs(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, STATIONARY, 0, x)
            state.creep_envelope = None
        elif load == INF:
            raise ModelError(f"normal_load = {normal_load!r} N over contact_width = {self.width!r} m is beyond the "
                             f"largest load per length a step represents ({sys.float_info.max:.4g} N/m)")
        elif self.closed_form and self.instationary is None:
            outputs = self.closed_form_step(x, normal_load, creep, velocity)
        elif self.table_use is not None and (answer := self.table_use.answer(x, load, creep, velocity)) is not None:
            outputs = self.table_outputs(x, normal_load, creep, velocity, answer)
        else:
            # a floating-point overflow or invalid operation in the solvers (inputs or parameters beyond what they
            # represent) raises, and the step is refused with it, rather than a numpy warning in the host's streams
            with np.errstate(over="raise", divide="raise", invalid="raise"):
                try:
                    if self.instationary is not None:
                        outputs, lag = self.instationary_step(x, normal_load, creep, velocity, step_size)
                    else:
                        outputs = self.solve_step(x, normal_load, creep, velocity)
                except FloatingPointError as exc:
                    raise ModelError(f"the step at X = {x!r} m (N = {normal_load!r} N, creep = {creep!r}, V = "
                                     f"{velocity!r} m/s) leaves the floating-point range: {exc}") from None

        if not (-self.friction_bound * normal_load <= outputs[0] <= self.friction_bound * normal_load
                and -self.friction_bound <= outputs[1] <= self.friction_bound):
            outputs = within_friction_bound(outputs, self.friction_bound, normal_load, creep, velocity)
        if not all(map(isfinite, outputs)):
            raise ModelError(non_finite(outputs, normal_load, creep, velocity))
        state.commit(current_time, high, low, normal_load, creep, velocity, outputs, lag,
                     None if self.table_use is None else self.table_use.domain)
        return outputs

    def closed_form_step(self, x: float, normal_load: float, creep: float, velocity: float) -> StepOutputs:
        """Outputs of Hertz and Carter at axis position x [m]: :func:`rollcontact.line.hertz.hertz` and
        :func:`~rollcontact.line.carter.carter` written out (their operations in their order, so bit for bit theirs,
        ``tests/stepping/test_model.py``): no Scene, no call per formula, one square root."""
        n, radius, modulus, mu = normal_load * self.per_width, self.radius, self.contact_modulus, self.mu
        a = math.sqrt(4.0 * n * radius / (math.pi * modulus))
        slip_length = radius * abs(creep) / mu  # a - a*
        if a == 0.0:
            t = a_star = stiffness = 0.0
        elif slip_length >= a:
            t, a_star, stiffness = math.copysign(mu * n, creep), 0.0, 0.0
        else:
            a_star, u = a - slip_length, slip_length / a
            t, stiffness = math.copysign(mu * n * (u * (2.0 - u)), creep), 2.0 * radius * (n / a) * (a_star / a)
        force = t * self.width
        return new_tuple(StepOutputs, (force, t / n, a, a_star, self.flat_offset, modulus * a / (2.0 * radius),
                                       velocity * creep * force, stiffness * self.width,
                                       self.stationarity(x, normal_load, creep, velocity, a), CLOSED_FORM, x))

    def solve_step(self, x: float, normal_load: float, creep: float, velocity: float) -> StepOutputs:
        """Outputs of ``rollcontact.solve`` among the model's methods (auto: polynomial, then discretised as the
        fallback) at axis position x [m].

        With ``tolerance`` > 0 the method runs with its cheapest setting whose error estimate (relative error of T'
        and p0) meets it; without, only the part of the estimate that costs nothing is checked (``estimate="free"``:
        the polynomial slip iteration's would cost a Newton step per FMU step).
        """
        scene = self.scene(x, normal_load, creep, velocity)
        tolerance = self.parameters.tolerance or None
        try:
            with one_blas_thread():
                result, stiffness = self.solved(scene, x, tolerance)
        except (ValueError, ArithmeticError) as exc:
            raise ModelError(f"no method solved the scene at X = {x!r} m (N = {normal_load!r} N, creep = {creep!r}, "
                             f"V = {velocity!r} m/s): {exc}") from None
        force = float(result.tangential_force_per_length) * self.width
        a = float(result.contact_half_width)
        if self.table_use is not None:
            self.table_use.exact_step_done(scene.normal_load_per_length, velocity, a,
                                           result.info.get("modelled_cost", math.nan))
        return StepOutputs(force, float(result.traction_coefficient), a, float(result.stick_half_width),
                           0.0 - float(result.contact_offset), float(result.max_pressure),
                           velocity * creep * force, stiffness * self.width,
                           self.stationarity(x, normal_load, creep, velocity, a), method_code(result.method), x)

    def solved(self, scene: Scene, x: float, tolerance: float | None):
        """The result of ``rollcontact.solve`` for the step's scene and its dT'/dxi [N/m] (by a difference where the
        method does not give it); a failed or unresolved result raises :class:`ModelError`."""
        result = solve(scene, methods=self.candidates, tolerance=tolerance, estimate="free",
                       budget=self.parameters.step_budget or None, **self.options)
        name = result.method
        if not result.success:
            raise ModelError(f"{name} failed: {result.message}")
        if tolerance is not None and not result.info.get("tolerance_met", True):
            self.notice_once("tolerance", f"tolerance = {tolerance!r} is not met within step_budget = "
                             f"{self.parameters.step_budget!r} s (first at X = {x!r} m, estimated error "
                             f"{result.info.get('error_estimate', math.nan):.2g}): the steps run the most accurate "
                             "setting that fits. Raise step_budget (0: no budget) or the tolerance.")
        why = unresolved(result)
        if why is not None:
            raise ModelError(f"{name}: {why}")
        stiffness = float(result.creep_stiffness_per_length)
        if not math.isfinite(stiffness):
            options = result.info.get("setting") or used_options(METHODS[name], self.options)
            stiffness = self.creep_stiffness_by_difference(scene, name, result, options)
        return result, stiffness

    def table_outputs(self, x: float, normal_load: float, creep: float, velocity: float, answer: tuple) -> StepOutputs:
        """The outputs of the certified table's ``answer`` (:meth:`rollcontact.stepping.line.table.TableUse.answer`):
        T = T' b, dT/dxi = (dT'/dxi) b with the contact width b."""
        force, a, a_star, offset, p0, stiffness = answer
        force_total = force * self.width
        return new_tuple(StepOutputs, (force_total, force / (normal_load * self.per_width), a, a_star, offset, p0,
                                       velocity * creep * force_total, stiffness * self.width,
                                       self.stationarity(x, normal_load, creep, velocity, a), TABLE_CODE, x))

    def creep_stiffness_by_difference(self, scene: Scene, name: str, result, options: dict) -> float:
        """dT'/dxi [N/m] by a one-sided difference, for methods that do not return it.

        The step is 1e-6 of the Carter saturation creep ``mu a / R``, taken towards zero creep so that it does
        not cross into full slip.
        """
        delta = 1e-6 * self.saturation_per_half_width * max(result.contact_half_width, 1e-12)
        delta = -math.copysign(delta, scene.creep) if scene.creep != 0.0 else delta
        other = solve(scene.replace(creep=scene.creep + delta), method=name, **options)
        if not other.success:
            raise ModelError(f"{name} failed at the creep {scene.creep + delta!r} of the creep-stiffness "
                             f"difference: {other.message}")
        return float(other.tangential_force_per_length - result.tangential_force_per_length) / delta

    def stationarity(self, x: float, normal_load: float, creep: float, velocity: float,
                     half_width: float) -> float:
        """Wavelength of the fastest input variation over the contact half-width [1].

        :func:`rollcontact.line.instationary.stationarity_of_samples` along the axis position X of the current and the
        two previous communication points, with Carter's saturation creep ``mu a / R`` as the creep scale and the
        speed counted only with velocity-dependent friction.  The corrugation is geometry, not an input, and does
        not enter.
        """
        state = self.state
        previous = state.previous
        if previous is None:
            return STATIONARY
        current = (x, normal_load, creep, velocity)
        return stationarity_of_samples((previous, current) if state.older is None else (state.older, previous, current),
                                       half_width, self.saturation_per_half_width * half_width,
                                       self.velocity_dependent)
