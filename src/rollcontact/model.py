"""Stepping contact model for co-simulation: parameters -> (state, inputs, step) -> outputs.

This is the library half of the ``RollingContact2D`` FMU: the FMU's slave only maps its variables to a
:class:`ContactModel` and back, so everything here can be used and tested without any FMI tool.

* :class:`ContactParameters` holds the fixed parameters (FMU parameters of the same names) and checks them.
* :class:`ContactModel` precomputes what does not change between steps and evaluates one communication step
  with :meth:`ContactModel.step` (inputs in N, 1 and m/s; outputs in SI units, see :class:`StepOutputs`).
* :class:`ModelState` is everything the model remembers between steps: axis position, the input history of the
  stationarity measure and the last outputs.  It is a plain dataclass that can be copied, turned into a JSON
  dict or bytes and restored; restore -> step -> restore -> step gives identical outputs.

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
``transient`` = 2 (always) evaluates every loaded step with :class:`rollcontact.instationary.InstationaryModel`,
which rolls the distance ``V_n h`` with the inputs sampled at ``t_n`` held (zero-order hold, the host's view of
the step): the relaxation model (the lag (R1) around Carter, ``method_used`` 4) or, with ``method`` = 3, the
discretised transient in creep control (``method_used`` 5).  ``transient`` = 1 (auto) stays quasi-steady while
the inputs vary slowly and switches the instationary model in when the stationarity measure
(:func:`rollcontact.instationary.stationarity_of_samples`) falls below :meth:`ContactModel.transient_threshold`,
starting from the previous step's quasi-steady state (:meth:`ContactModel.switch_in`), and switches back once the
inputs are slow again and its force is back within the tolerance of the quasi-steady one.  The relaxation lag errs
by up to 2.6 % of the creep swing (in saturation creeps), at most :data:`RELAXATION_ACCURACY` mu N as measured: it is
the default (``tolerance`` = 0), which promises no accuracy.  For a ``tolerance`` below that bound, with ``method`` =
0, ``transient`` = 1 bounds the lag's error by the creep swing of the last few relaxation lengths
(:func:`rollcontact.instationary.lag_error_bound` of the envelope in ``state.creep_envelope``) and runs the lag
while that bound meets the tolerance, the discretised transient where it does not (:meth:`ContactModel.choose_model`):
the cheapest transient whose modelled error meets the tolerance (:func:`transient_setting`: in practice the
extrapolating pair of nested grids, at most :data:`EXTRAPOLATED_MAX_ELEMENTS`; ``elements`` > 0 runs one grid of
that many), switched in from steady rolling on its grid at the previous creep, or at the lag's equivalent creep when
it takes over from the lag; it hands back to the lag once the swing has died down.  So stationary inputs stay on the
cheap closed form and small swings on the lag.  Both models assume a flat
surface and Coulomb friction: on other scenes ``transient`` = 2 is refused and ``transient`` = 1 stays quasi-steady
(:attr:`ContactModel.notices` says so).  With ``method`` = 3, ``transient`` = 1 behaves as 2: the discretised
method was asked for on every step, and its transient is exact in steady rolling too.

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

import base64
import dataclasses
import json
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rollcontact.api import METHODS, run_to_tolerance, setting_for, solve, unresolved
from rollcontact.closed_form import carter, hertz
from rollcontact.friction import Coulomb, ExponentialFalling
from rollcontact.instationary import (
    LAG_ERROR_COEFFICIENT,
    LAG_ERROR_FLOOR,
    LAG_MEMORY,
    STATIONARITY_THRESHOLD,
    InstationaryModel,
    InstationaryState,
    aligned_grid_load,
    carter_creep,
    creep_envelope,
    lag_error_bound,
    relaxation_length,
    stationarity_of_samples,
)
from rollcontact.scene import Harmonic, Material, Scene, SceneError, Surface, check_real, load_scene

__all__ = ["AUTO", "METHOD_NAMES", "OPTION_NAMES", "STATIONARY", "ContactModel", "ContactParameters",
           "ModelError", "ModelState", "StepOutputs"]

AUTO = 0
"""``method`` code of the automatic choice."""

METHOD_NAMES = {1: "closed_form", 2: "polynomial", 3: "discretised"}
"""``method`` / ``method_used`` codes and the method families they stand for (0 is auto, resp. no contact);
``method_used`` adds :data:`INSTATIONARY_CODES`.

A registered method belongs to a family when its registry name starts with the family's name (e.g.
``"polynomial_friction"`` is a polynomial method, code 2); methods of no family are not used by the model.
"""

STATIONARY = 1e9
"""``stationarity`` reported when nothing varies (constant inputs or no contact); also its upper bound."""

INSTATIONARY_CODES = {"relaxation": 4, "transient": 5}
"""``method_used`` of the instationary models: 4 relaxation (lag around Carter), 5 discretised transient."""

DEFAULT_TRANSIENT_TOLERANCE = 1e-2
"""Quasi-static error [1 of mu N] that ``transient`` = 1 tolerates before it switches the relaxation lag in, when the
``tolerance`` parameter is 0 (the defaults: no accuracy is promised for the lag itself, :data:`RELAXATION_ACCURACY`)."""

RELAXATION_ACCURACY = 0.21
"""Error bound [1 of mu N] of the relaxation lag: 1.4 times the largest error against the discretised transient
measured by ``benchmarks/bench_relaxation.py`` over lambda/a = 1..40 and creep swings up to 10 saturation creeps
(0.15 mu N at lambda/a = 2 for ``10 sin``).  The lag's error grows with the swing, up to 2.6 % of its amplitude in
saturation creeps: 3e-3 mu N on the Pareto study's ``(0.5 + 0.3 sin) mu a/R``, 2.3e-2 for a reversal ``0.9 sin`` at
lambda/a = 5.  So ``transient`` = 1 with ``method`` = 0 and a ``tolerance`` below this runs the lag only while its
bound for the swing actually seen (:func:`rollcontact.instationary.lag_error_bound`) meets the tolerance and the
discretised transient (:func:`transient_setting`) otherwise; the lag runs unconditionally with ``tolerance`` = 0 (the
cheap default, no accuracy promised) or ``transient`` = 2."""

LAG_RETURN = 0.5
"""A running discretised transient hands back to the lag once the lag's bound is below this times the tolerance
(:meth:`ContactModel.choose_model`)."""

GRID_LOAD_FACTOR = 2.0
"""The discretised transient's grid holds loads up to about this factor times the load it is aligned to (a up to
sqrt(2) times; :func:`rollcontact.instationary.aligned_grid_load`)."""

TRANSIENT_ERROR_ORDER = 1.0
"""p of the discretised transient's error model ``max |T' - T'_converged| <= C / n^p`` [1 of mu N]
(:func:`transient_error`; n elements on the model's grid): with whole-element substeps ``error n`` is 0.49-0.58
for n = 50..500 on every signal of ``benchmarks/bench_transient_pairs.py``, and the order observed in
``benchmarks/bench_transient_auto.py`` is 0.97-0.98 (least squares over n = 50..600: 1.00)."""

TRANSIENT_ERROR_CONSTANT = 0.82
"""C of that error model: 1.4 times the largest ``error n`` measured, 0.58 (lambda/a = 40, n = 50; the single grids
of ``benchmarks/bench_transient_pairs.py`` against the pair 500/1000, lambda/a = 1..40 and creep reversals,
n = 50..500).  With the equal substeps of sessions 12-14 it was 1.3 (0.94 at lambda/a = 1, n = 50, erratic);
committing whole elements made the error regular: the quasi-steady bias, steady rolling on the grid being off
Carter by 0.57/n (``benchmarks/bench_transient_auto.py``), which also bounds the switch-in and hand-back jumps.
``bench_transient_auto.py`` measured at most 0.58 up to n = 600 against a Richardson 400/800 (lambda/a = 5..40)."""

TRANSIENT_MIN_ELEMENTS = 50
"""Fewest elements (of a single grid, or the finer of a pair) the models choose: the coarsest grid their error models
were measured on."""

TRANSIENT_MAX_ELEMENTS = 800
"""Most elements :func:`transient_elements` chooses: the finest grid measured (its error model is not extrapolated)
and already 30-210 ms per host step in that benchmark (lambda/a = 5..40; the cost grows about as n^2.5)."""

EXTRAPOLATED_ERROR_ORDER = 2.0
"""p of the extrapolating transient's error model ``max |T' - T'_converged| <= C / n^p`` [1 of mu N]
(:func:`transient_model_error`; n the finer grid's elements): the first-order errors of the nested grids cancel
and what remains falls as n^-2 (``benchmarks/bench_transient_pairs.py``: ``error n^2`` between 1.1 and 4.7 for
n = 50..500).  Each grid commits whole-element substeps (:meth:`InstationaryModel.advance`); with equal substeps
of a fraction r of an element per host step (sessions 12-14) ``error n^2`` was erratic in r, 1.0 to 21.4
(``benchmarks/bench_substep_rule.py``)."""

EXTRAPOLATED_ERROR_CONSTANT = 6.6
"""C of that model: 1.4 times the largest ``error n^2`` measured by ``benchmarks/bench_transient_pairs.py``, 4.69 at
lambda/a = 1, n = 460 (4.05 at lambda/a = 40, n = 460; at most 2.2 for the creep reversals), against the pair
500/1000, over lambda/a = 1..40, ``(0.5 + 0.3 sin) mu a/R`` and a creep reversal ``0.9 sin`` at lambda/a = 5 and
20, n = 50..500 (14 values).  It was 30 with equal substeps (16 until session 14).  The pair 129/258 certifies
1e-4 mu N'; the finest measured, 250/500, reaches 2.6e-5."""

EXTRAPOLATED_MAX_ELEMENTS = 500
"""Most elements (of the finer grid) :func:`transient_setting` chooses for a pair: the finest pair measured against a
finer reference (the pair 500/1000)."""

EXTRAPOLATION_COST = 1.4
"""Time per step of a pair over the single grid of n elements: median 1.41 over ``benchmarks/bench_transient_pairs.py``
(1.08-2.0 between the 10th and 90th percentiles, a loaded machine): the coarse grid adds about 2^-2.5 of the cost
(it grows as n^2.5) and one provisional substep per host step."""

TRANSIENT_MODES = {0: "quasi-static", 1: "auto", 2: "always"}
FRICTION_LAWS = {0: "Coulomb", 1: "exponential falling"}

OPTION_NAMES = {"polynomial_order": ("order", "polynomial_order"), "elements": ("elements",),
                "datum": ("datum_length", "datum")}
"""Parameter -> option names under which it is passed to a method that lists them in its ``options``.

A parameter equal to 0 is not passed (the method's default applies).  ``tolerance`` is not passed as such: it
selects each method's cheapest setting that meets it (:func:`rollcontact.api.setting_for`), which these explicit
parameters then override.
"""

STATE_VERSION = 3
READABLE_STATE_VERSIONS = (1, 2, 3)  # 1 had no instationary state (reads as quasi-steady history), 2 no envelope
INF = math.inf
new_tuple = tuple.__new__  # StepOutputs without NamedTuple.__new__'s extra Python frame, on the closed-form path


class ModelError(ValueError):
    """An input or parameter the model cannot use, or a scene no allowed method solves; the message says why."""


class StepOutputs(NamedTuple):
    """Outputs of one step (SI units; forces over the whole contact width).

    Attributes
    ----------
    tangential_force : float
        T [N], the sign of the creep in steady rolling.
    traction_coefficient : float
        T/N [1] (0 without load).
    contact_half_width : float
        a [m].
    stick_half_width : float
        a* [m], stick zone at the leading edge (0 in full slip).
    contact_offset : float
        Contact centre minus axis position [m] in the model's frame (positive ahead of the axis).
    max_pressure : float
        Peak pressure [Pa].
    frictional_power : float
        Power dissipated by slip, ``V xi T`` [W] (module docstring).
    creep_stiffness : float
        dT/dxi [N] at this state.
    stationarity : float
        Wavelength of the fastest input variation over a [1] (:meth:`ContactModel.stationarity`).
    method_used : int
        1 closed form, 2 polynomial, 3 discretised, 4 instationary relaxation, 5 instationary discretised
        transient, 0 no contact.
    axis_position : float
        X [m] at which the contact was evaluated.
    """

    tangential_force: float
    traction_coefficient: float
    contact_half_width: float
    stick_half_width: float
    contact_offset: float
    max_pressure: float
    frictional_power: float
    creep_stiffness: float
    stationarity: float
    method_used: int
    axis_position: float


@dataclass(frozen=True)
class ContactParameters:
    """Fixed parameters of a :class:`ContactModel` (the FMU parameters of the same names), checked on creation.

    Parameters
    ----------
    youngs_modulus : float
        E [Pa] > 0 of both bodies.
    poisson_ratio : float
        nu [1], 0 <= nu < 0.5.
    radius : float
        Effective wheel radius R [m] > 0.
    contact_width : float
        Lateral length b [m] > 0 of the line contact; per-length quantities are force / b.
    friction_coefficient : float
        mu at zero slip velocity [1] > 0.
    friction_law : int
        0 Coulomb (mu constant), 1 exponential falling ``mu(v) = mu [(1 - A) exp(-B v) + A]``.
    friction_kinetic_ratio : float
        A [1] in (0, 1] of the exponential law.
    friction_decay : float
        B [s/m] >= 0 of the exponential law.
    corrugation_wavelength : float
        Wavelength [m] > 0 of ``Z(X) = amplitude cos(2 pi X / wavelength + phase)``.
    corrugation_amplitude : float
        Amplitude [m] >= 0; 0 means a smooth surface.
    corrugation_phase : float
        Phase [rad].
    initial_position : float
        Axis position X [m] at the start time.
    scene_file : str
        TOML scene (:func:`rollcontact.load_scene`, so it must be a complete scene including ``[load]``); when
        given, its material, radius, friction and surface replace the scalar parameters above (the surface is
        read in the model's frame), while its load, creep, axis position and speed are replaced by the inputs.
        Empty: unused.
    method : int
        0 auto, 1 closed form, 2 polynomial, 3 discretised.
    tolerance : float
        Requested relative error [1] >= 0 of T' and p0: each step's method runs with its cheapest setting whose
        error estimate meets it (:func:`rollcontact.api.setting_for`, as ``rollcontact.solve(scene,
        tolerance=...)``); with ``transient`` = 1 also the error of T' (of mu N) it tolerates before the
        instationary model takes over.  It sets the grids of the discretised transient
        (:func:`transient_setting`) with ``method`` = 3, and with ``method`` = 0 below
        :data:`RELAXATION_ACCURACY`, where ``transient`` = 1 uses that transient wherever the relaxation lag's bound
        for the creep swing does not meet the tolerance.  0: the methods' defaults and
        :data:`DEFAULT_TRANSIENT_TOLERANCE`.
    polynomial_order : int
        Polynomial order >= 0 for methods that accept it (0: the method's default).
    elements : int
        Element count >= 0 for methods that accept it and for the discretised transient (0: the method's
        default; the transient's grids are chosen from ``tolerance``, else one grid of 100; > 0: one grid).
    transient : int
        0 quasi-static, 1 auto (instationary model only while the stationarity measure calls for it), 2 always
        (module docstring, "Instationary rolling").
    datum : float
        Datum distance L [m] >= 0 of instationary rolling, for methods that accept it (0: the method's default).
    """

    youngs_modulus: float = 210e9
    poisson_ratio: float = 0.28
    radius: float = 0.46
    contact_width: float = 0.02
    friction_coefficient: float = 0.3
    friction_law: int = 0
    friction_kinetic_ratio: float = 0.4
    friction_decay: float = 0.6
    corrugation_wavelength: float = 0.04
    corrugation_amplitude: float = 0.0
    corrugation_phase: float = 0.0
    initial_position: float = 0.0
    scene_file: str = ""
    method: int = AUTO
    tolerance: float = 0.0
    polynomial_order: int = 0
    elements: int = 0
    transient: int = 0
    datum: float = 0.0

    def __post_init__(self):
        set_ = object.__setattr__
        for name, lower, upper, lower_open, upper_open in (
                ("youngs_modulus", 0.0, None, True, False),
                ("poisson_ratio", 0.0, 0.5, False, True),
                ("radius", 0.0, None, True, False),
                ("contact_width", 0.0, None, True, False),
                ("friction_coefficient", 0.0, None, True, False),
                ("friction_kinetic_ratio", 0.0, 1.0, True, False),
                ("friction_decay", 0.0, None, False, False),
                ("corrugation_wavelength", 0.0, None, True, False),
                ("corrugation_amplitude", 0.0, None, False, False),
                ("corrugation_phase", None, None, False, False),
                ("initial_position", None, None, False, False),
                ("tolerance", 0.0, None, False, False),
                ("datum", 0.0, None, False, False)):
            try:
                value = check_real(name, getattr(self, name), lower=lower, upper=upper, lower_open=lower_open,
                                   upper_open=upper_open)
            except SceneError as exc:
                raise ModelError(str(exc)) from None
            set_(self, name, value)
        for name, allowed in (("friction_law", FRICTION_LAWS), ("method", {AUTO: "auto", **METHOD_NAMES}),
                              ("transient", TRANSIENT_MODES)):
            value = getattr(self, name)
            if value not in allowed:
                choices = ", ".join(f"{k} {v}" for k, v in allowed.items())
                raise ModelError(f"{name} = {value!r} is out of range: it must be one of {choices}")
            set_(self, name, int(value))
        for name in ("polynomial_order", "elements"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
                raise ModelError(f"{name} = {value!r} is out of range: it must be an integer >= 0 "
                                 "(0: the method's default)")
            set_(self, name, int(value))
        if not isinstance(self.scene_file, str):
            raise ModelError(f"scene_file must be a string (a path or empty), got {self.scene_file!r}")


@dataclass(slots=True)
class ModelState:
    """Everything a :class:`ContactModel` remembers between steps (plain, copyable, JSON-serialisable).

    Attributes
    ----------
    time : float
        Last communication point t_n [s] (the start time before the first step).
    position : float
        Axis position X(t_n) [m], high part of a compensated sum.
    position_error : float
        Low part [m] of the compensated sum; ``X = position + position_error``.
    previous : tuple or None
        ``(X, normal_load, creep, velocity)`` sampled at t_n; None before the first step.
    older : tuple or None
        The same one communication point earlier (second differences of the stationarity measure).
    steps : int
        Successful steps taken.
    outputs : StepOutputs
        Outputs of the last successful step (start values before the first).
    instationary : InstationaryState or None
        State of the instationary model while it is in use (None: quasi-steady).  Never modified in place.
    grid_load : float
        N' [N/m] the discretised transient's grid was built for (0: none yet; about twice the load it was
        aligned to, :meth:`ContactModel.prepare_grid`); part of the state because the traction history lives on
        that grid.
    creep_envelope : tuple or None
        ``(high, low)`` creep [1 of mu a/R] of :func:`rollcontact.instationary.creep_envelope`, kept by
        ``transient`` = 1 with a tolerance (the lag's error bound); None otherwise and after an unloaded step.
    version : int
        Layout version of this state; states of another version are refused by :meth:`from_dict`.
    """

    time: float
    position: float
    position_error: float
    previous: tuple[float, float, float, float] | None
    older: tuple[float, float, float, float] | None
    steps: int
    outputs: StepOutputs
    instationary: InstationaryState | None = None
    grid_load: float = 0.0
    creep_envelope: tuple[float, float] | None = None
    version: int = STATE_VERSION

    @classmethod
    def initial(cls, start_time: float, initial_position: float) -> ModelState:
        """State at ``start_time`` [s] with the axis at ``initial_position`` [m] and no history."""
        outputs = StepOutputs(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, STATIONARY, 0, float(initial_position))
        return cls(float(start_time), float(initial_position), 0.0, None, None, 0, outputs)

    def copy(self) -> ModelState:
        """An independent copy (all fields are immutable values)."""
        return dataclasses.replace(self)

    def to_dict(self) -> dict:
        """JSON-compatible dict; floats survive ``json`` exactly (``repr`` round trip), the instationary state as
        base64 of its exact bytes."""
        return {"version": self.version, "time": self.time, "position": self.position,
                "position_error": self.position_error,
                "previous": None if self.previous is None else list(self.previous),
                "older": None if self.older is None else list(self.older),
                "steps": self.steps, "outputs": list(self.outputs),
                "instationary": None if self.instationary is None
                else base64.b64encode(self.instationary.to_bytes()).decode("ascii"),
                "grid_load": self.grid_load,
                "creep_envelope": None if self.creep_envelope is None else list(self.creep_envelope)}

    @classmethod
    def from_dict(cls, data: dict) -> ModelState:
        """Inverse of :meth:`to_dict`; raises ModelError for an unknown layout version or missing fields."""
        if data.get("version") not in READABLE_STATE_VERSIONS:
            raise ModelError(f"model state version {data.get('version')!r} is not supported "
                             f"(this rollcontact reads versions {READABLE_STATE_VERSIONS})")
        try:
            previous = data["previous"]
            older = data["older"]
            packed = data.get("instationary")
            envelope = data.get("creep_envelope")
            instationary = None if packed is None else InstationaryState.from_bytes(base64.b64decode(packed))
            return cls(float(data["time"]), float(data["position"]), float(data["position_error"]),
                       None if previous is None else tuple(float(v) for v in previous),
                       None if older is None else tuple(float(v) for v in older),
                       int(data["steps"]), StepOutputs(*data["outputs"]), instationary,
                       float(data.get("grid_load", 0.0)),
                       None if envelope is None else (float(envelope[0]), float(envelope[1])), STATE_VERSION)
        except (KeyError, TypeError, ValueError) as exc:
            raise ModelError(f"invalid model state: {exc!r}") from None

    def to_bytes(self) -> bytes:
        """UTF-8 JSON of :meth:`to_dict`."""
        return json.dumps(self.to_dict()).encode("utf-8")

    @classmethod
    def from_bytes(cls, data: bytes) -> ModelState:
        """Inverse of :meth:`to_bytes`."""
        return cls.from_dict(json.loads(data.decode("utf-8")))


def mirrored(surface: Surface) -> Surface:
    """The surface ``Z(-X)``: odd polynomial terms and sine amplitudes change sign."""
    return Surface(polynomial=tuple(c if j % 2 == 0 else -c for j, c in enumerate(surface.polynomial)),
                   harmonics=tuple(Harmonic(h.wavenumber, h.cos_amplitude, -h.sin_amplitude)
                                   for h in surface.harmonics))


class ContactModel:
    """Quasi-steady 2D rolling contact of a wheel on a (corrugated) surface, advanced one step at a time.

    Parameters
    ----------
    parameters : ContactParameters, optional
        Fixed parameters (defaults when omitted).
    start_time : float
        Time [s] of the initial state.

    Raises
    ------
    ModelError
        A parameter is out of range, the scene file cannot be read, or the requested method cannot treat the
        scene (e.g. ``method`` = 1 on a corrugated surface, or a method that is not registered).

    Notes
    -----
    With ``method`` = 0 (auto) each step uses the cheapest model the scene needs: the closed forms
    (:func:`rollcontact.closed_form.hertz`, :func:`rollcontact.closed_form.carter`, called with precomputed
    constants) for a flat surface with constant friction; otherwise ``"polynomial"`` and then ``"discretised"``,
    whichever are registered in :data:`rollcontact.METHODS`, the first that accepts the scene and succeeds.
    An explicit method is used as it is or the step fails with a :class:`ModelError`.
    """

    def __init__(self, parameters: ContactParameters | None = None, *, start_time: float = 0.0):
        p = ContactParameters() if parameters is None else parameters
        if not isinstance(p, ContactParameters):
            raise TypeError(f"parameters must be ContactParameters, got {type(p).__name__}")
        self.parameters = p
        notices = []
        if p.scene_file:
            try:
                base = load_scene(p.scene_file)
            except SceneError as exc:
                raise ModelError(f"scene_file: {exc}") from None
            material, radius, friction, surface = base.material, base.radius, base.friction, base.surface
            notices.append(f"scene_file {p.scene_file!r} sets material, radius, friction and surface; the scalar "
                           "parameters for them are ignored, and the inputs replace its load, creep and speed")
        else:
            try:
                material = Material(p.youngs_modulus, p.poisson_ratio)
                radius = p.radius
                if p.friction_law == 0:
                    friction = Coulomb(p.friction_coefficient)
                else:
                    friction = ExponentialFalling(p.friction_coefficient, p.friction_kinetic_ratio, p.friction_decay)
                harmonics = ()
                if p.corrugation_amplitude != 0.0:
                    harmonics = (Harmonic.from_wavelength(p.corrugation_wavelength, p.corrugation_amplitude,
                                                          p.corrugation_phase),)
                surface = Surface(harmonics=harmonics)
            except ValueError as exc:
                raise ModelError(str(exc)) from None
        self.instationary: InstationaryModel | None = None
        """The instationary model of ``transient`` = 1/2 (None: every step quasi-steady)."""
        self.lag: InstationaryModel | None = None
        """``transient`` = 1 with ``method`` = 0 and a tolerance below :data:`RELAXATION_ACCURACY`: the relaxation
        lag, run instead of the discretised transient ``instationary`` while its error bound for the creep swing
        (:func:`rollcontact.instationary.lag_error_bound`) meets the tolerance."""
        self.transient_auto = p.transient == 1 and p.method != 3
        self.transient_tolerance = p.tolerance or DEFAULT_TRANSIENT_TOLERANCE
        self.settle_tolerance = self.transient_tolerance
        """Distance [1 of mu N] from the quasi-steady force within which ``transient`` = 1 hands back."""
        if p.transient != 0:
            unavailable = instationary_unavailable(surface, friction)
            if unavailable is not None and p.transient == 2:
                raise ModelError(f"transient = 2 (always) cannot treat this scene: {unavailable}; use transient = 0 "
                                 "or 1 (1 solves it quasi-steady)")
            if unavailable is not None:
                notices.append(f"transient = 1 (auto): {unavailable}, so every step is solved quasi-steady and the "
                               "stationarity output shows how far that holds")
            else:
                tight = 0.0 < p.tolerance < RELAXATION_ACCURACY
                adaptive = tight and self.transient_auto and p.method == AUTO
                discretised = p.method == 3 or adaptive
                elements, extrapolate = p.elements or 100, False
                if discretised and p.tolerance:
                    if not p.elements:
                        elements, extrapolate = transient_setting(p.tolerance)
                    notices.append(transient_notice(p.tolerance, elements, p.elements > 0, extrapolate, adaptive))
                    # the transient settles on its own steady force, which is within its error of Carter's
                    self.settle_tolerance = max(self.transient_tolerance,
                                                transient_model_error(elements, extrapolate))
                elif not discretised and (tight or not p.tolerance):
                    notices.append(f"tolerance = {p.tolerance!r}: the relaxation lag of transient = {p.transient} errs "
                                   "by up to 2.6 % of the creep swing in saturation creeps (3e-3 mu N for a swing of "
                                   f"0.3), at most {RELAXATION_ACCURACY!r} mu N as measured "
                                   "(benchmarks/bench_relaxation.py); for a modelled error use transient = 1 with "
                                   "method = 0 and a tolerance, which then runs the discretised transient with as "
                                   "many elements as the tolerance needs")
                self.instationary = InstationaryModel(
                    radius, material.contact_modulus, friction.static_coefficient,
                    mode="transient" if discretised else "relaxation", datum_length=p.datum or None,
                    elements=elements, extrapolate=extrapolate)
                if adaptive:
                    self.lag = InstationaryModel(radius, material.contact_modulus, friction.static_coefficient,
                                                 mode="relaxation", datum_length=p.datum or None)
        self.notices: tuple[str, ...] = tuple(notices)
        """Messages worth showing once (e.g. in an FMU log): ignored parameters, modes not implemented."""
        self.material = material
        self.radius = float(radius)
        self.friction = friction
        self.surface = surface
        self.scene_surface = mirrored(surface)
        self.velocity_dependent = not friction.is_constant

        flat_reason = None
        if not surface.is_flat:
            flat_reason = "the surface is not flat (corrugation, harmonics or polynomial terms of degree >= 2)"
        elif not friction.is_constant:
            flat_reason = "friction depends on slip velocity"
        if p.method == 1 and flat_reason is not None:
            raise ModelError(f"method = 1 (closed form) cannot solve this scene: {flat_reason}; "
                             "use method = 0 (auto), 2 (polynomial) or 3 (discretised)")
        self.closed_form = p.method == 1 or (p.method == AUTO and flat_reason is None)
        if self.closed_form:
            self.candidates: tuple[str, ...] = ()
        else:
            codes = (2, 3) if p.method == AUTO else (p.method,)
            self.candidates = registered_methods(codes)
            if not self.candidates:
                wanted = " or ".join(f"{c} ({METHOD_NAMES[c]})" for c in codes)
                why = f"{flat_reason}, which needs" if p.method == AUTO else "it needs"
                raise ModelError(f"method = {p.method}: {why} method {wanted}, but no such method is registered "
                                 f"in rollcontact.METHODS (registered: {sorted(METHODS)})")
        self.options = {name: self.method_options(name) for name in self.candidates}

        # constants of the closed-form path (no Scene is built there)
        self.contact_modulus = material.contact_modulus
        self.mu = friction.static_coefficient
        self.width = p.contact_width
        self.per_width = 1.0 / p.contact_width
        slope = surface.polynomial[1] if len(surface.polynomial) > 1 else 0.0
        self.flat_offset = self.radius * slope  # uphill by R alpha (physics.md section 4)
        self.saturation_per_half_width = self.mu / self.radius  # Carter saturation creep over a
        self.length_cache = (math.nan, 0.0)  # (N', zero_force_length(N'))
        self.state = ModelState.initial(start_time, p.initial_position)

    def method_options(self, name: str) -> dict:
        """Options for method ``name``: the nonzero parameters of :data:`OPTION_NAMES` that it accepts."""
        accepted = getattr(METHODS[name].function, "options", ())
        options = {}
        for parameter, names in OPTION_NAMES.items():
            value = getattr(self.parameters, parameter)
            option = next((n for n in names if n in accepted), None)
            if value != 0 and option is not None:
                options[option] = value
        return options

    def reset(self, start_time: float = 0.0) -> None:
        """Back to the initial state at ``start_time`` [s]."""
        self.state = ModelState.initial(start_time, self.parameters.initial_position)

    def get_state(self) -> ModelState:
        """A copy of the current state."""
        return self.state.copy()

    def set_state(self, state: ModelState) -> None:
        """Continue from (a copy of) ``state``."""
        if not isinstance(state, ModelState):
            raise TypeError(f"state must be a ModelState, got {type(state).__name__}")
        self.state = state.copy()

    def scene(self, axis_position: float, normal_load: float, creep: float, velocity: float) -> Scene:
        """The scene solved for axis position X [m], load N [N], creep [1] and speed V [m/s].

        It is in the package's frame (mirrored surface, axis at ``-X``, see the module docstring) with the load
        per unit length ``N / contact_width``.
        """
        return Scene(normal_load_per_length=normal_load * self.per_width, creep=creep, radius=self.radius,
                     material=self.material, friction=self.friction, surface=self.scene_surface,
                     axis_position=-axis_position, rolling_speed=velocity, name="RollingContact2D")

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
        previous = state.previous
        # trapezoid of V between the communication points, Neumaier-compensated accumulation of X
        increment = 0.5 * ((velocity if previous is None else previous[3]) + velocity) * dt
        high = state.position + increment
        if abs(state.position) >= abs(increment):
            low = state.position_error + ((state.position - high) + increment)
        else:
            low = state.position_error + ((increment - high) + state.position)
        x = high + low

        lag = None
        if normal_load == 0.0:
            outputs = StepOutputs(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, STATIONARY, 0, x)
            state.creep_envelope = None
        elif self.instationary is not None:
            outputs, lag = self.instationary_step(x, normal_load, creep, velocity, step_size)
        elif self.closed_form:
            outputs = self.closed_form_step(x, normal_load, creep, velocity)
        else:
            outputs = self.solve_step(x, normal_load, creep, velocity)

        state.instationary = lag
        state.time = current_time
        state.position = high
        state.position_error = low
        state.older = previous
        state.previous = (x, normal_load, creep, velocity)
        state.steps += 1
        state.outputs = outputs
        return outputs

    def closed_form_step(self, x: float, normal_load: float, creep: float, velocity: float) -> StepOutputs:
        """Outputs of Hertz and Carter (closed forms, no Scene built) at axis position x [m]."""
        n = normal_load * self.per_width
        a, p0 = hertz(n, self.radius, self.contact_modulus)
        t, a_star, stiffness = carter(n, creep, self.radius, self.contact_modulus, self.mu)
        force = t * self.width
        return new_tuple(StepOutputs, (force, t / n, a, a_star, self.flat_offset, p0, velocity * creep * force,
                                       stiffness * self.width, self.stationarity(x, normal_load, creep, velocity, a),
                                       1, x))

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
                lag = self.switch_in(model, handover) if quasi is not None else model.initial_state()
            lag, result = model.step(lag, load, creep, velocity, step_size)
        except (ValueError, ArithmeticError) as exc:
            raise ModelError(f"instationary {model.mode} model at X = {x!r} m (N = {normal_load!r} N, creep = "
                             f"{creep!r}, V = {velocity!r} m/s): {exc}") from None
        if not result.success:
            raise ModelError(f"instationary {model.mode} model failed at X = {x!r} m: {result.message}")
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
        aligned to it (:func:`rollcontact.instationary.aligned_grid_load`), so the grid is a function of the state
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
        if model.solver is None or model.max_load != grid_load:
            model.build_solver(grid_load)
        if lag is not None and load > grid_load:
            grid_load = aligned_grid_load(load, model.elements, GRID_LOAD_FACTOR, multiple)
            lag = model.regrid(lag, grid_load)
        return grid_load, lag

    def switch_in(self, model: InstationaryModel, handover: bool = False) -> InstationaryState:
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
        creep = previous[2]
        if handover:
            creep = carter_creep(self.state.outputs.tangential_force * self.per_width, load, self.radius,
                                 self.contact_modulus, self.mu)
        return model.steady_state(load, creep)

    def choose_model(self, running: InstationaryState | None, load: float, creep: float, distance: float,
                     half_width: float) -> tuple[tuple[float, float], InstationaryModel]:
        """The creep envelope after this step and the model to run it with, for ``transient`` = 1 with a tolerance.

        The lag (:attr:`lag`) while :func:`rollcontact.instationary.lag_error_bound` of the envelope meets the
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
        about 4.4 a for a railway wheel, :func:`rollcontact.instationary.relaxation_length`).  For a creep
        oscillation over Carter's saturation creep and wavelength lambda = stationarity * a, the quasi-steady force
        then errs by about ``2 (2 pi l / lambda)`` mu N' (the Carter slope at zero force is 2 mu N' per saturation
        creep), so the threshold is ``4 pi (l / a) / tolerance``, at least :data:`STATIONARITY_THRESHOLD` (the
        paper's 20, a rule for force control that creep control would miss: quasi-static Carter was measured
        12-37 % off for lambda/a = 5..50, ``benchmarks/bench_instationary.py``).
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
        (l the relaxation length, :func:`rollcontact.instationary.relaxation_length`).  Exact for the relaxation
        model to first order in the force change; for the discretised transient the same linearisation.
        """
        a_star = half_width * math.sqrt(max(0.0, 1.0 - abs(force) / (self.mu * load)))
        steady = 2.0 * load * self.radius * a_star / (half_width * half_width)
        length = relaxation_length(force, load, self.radius, self.contact_modulus, self.mu,
                                   self.instationary.datum_length)
        if length <= 0.0:
            return steady
        return -math.expm1(-distance / length) * steady

    def solve_step(self, x: float, normal_load: float, creep: float, velocity: float) -> StepOutputs:
        """Outputs from the registered methods (auto: polynomial, then discretised) at axis position x [m].

        With ``tolerance`` > 0 each method runs with its cheapest setting whose error estimate (relative error of
        T' and p0) meets it, the same choice as ``rollcontact.solve(scene, tolerance=...)``.
        """
        scene = self.scene(x, normal_load, creep, velocity)
        reasons = []
        for name in self.candidates:
            spec = METHODS[name]
            why = spec.inapplicable(scene)
            if why is not None:
                reasons.append(f"{name} cannot treat the scene: {why}")
                continue
            try:
                options = self.options[name]
                tolerance = self.parameters.tolerance
                if tolerance > 0.0:  # as solve(scene, tolerance=...), within this method
                    _, result = run_to_tolerance(setting_for(name, scene, tolerance), scene, options, tolerance)
                    options = result.info["setting"]
                else:  # the method itself: of its error estimate only what costs nothing (the polynomial slip
                    # iteration's costs a Newton step per FMU step)
                    result = spec.function(scene, **options)
            except (ValueError, ArithmeticError) as exc:
                reasons.append(f"{name} raised {type(exc).__name__}: {exc}")
                continue
            if not result.success:
                reasons.append(f"{name} failed: {result.message}")
                continue
            why = (unresolved(result) if tolerance > 0.0 else
                   unresolved(result, math.nan if spec.accuracy is None else spec.accuracy.free_estimate(result)))
            if why is not None:
                reasons.append(f"{name}: {why}")
                continue
            stiffness = float(result.creep_stiffness_per_length)
            if not math.isfinite(stiffness):
                try:
                    stiffness = self.creep_stiffness_by_difference(scene, name, result, options)
                except ModelError as exc:  # the next method may still give both force and stiffness
                    reasons.append(str(exc))
                    continue
            force = float(result.tangential_force_per_length) * self.width
            a = float(result.contact_half_width)
            return StepOutputs(force, float(result.traction_coefficient), a, float(result.stick_half_width),
                               0.0 - float(result.contact_offset), float(result.max_pressure),
                               velocity * creep * force, stiffness * self.width,
                               self.stationarity(x, normal_load, creep, velocity, a), method_code(name), x)
        raise ModelError(f"no method solved the scene at X = {x!r} m (N = {normal_load!r} N, creep = {creep!r}, "
                         f"V = {velocity!r} m/s): " + "; ".join(reasons))

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

        :func:`rollcontact.instationary.stationarity_of_samples` along the axis position X of the current and the
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


def transient_error(elements: int) -> float:
    """Modelled error [1 of mu N] of the discretised transient with n elements: ``C / n^p``.

    :data:`TRANSIENT_ERROR_CONSTANT` and :data:`TRANSIENT_ERROR_ORDER` bound max |T' - T'_converged| / (mu N') of
    ``benchmarks/bench_transient_auto.py`` and ``benchmarks/bench_transient_pairs.py`` on the model's grid
    (:func:`rollcontact.instationary.aligned_grid_load`).
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
    the pair wins: 82 elements meet 1e-3 where a single grid would need 820, beyond the 800 measured.
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
    """What the discretised transient chosen for ``tolerance`` reaches, and whether that meets it; ``adaptive``:
    it runs only where the relaxation lag's bound does not meet the tolerance (:meth:`ContactModel.choose_model`)."""
    reached = transient_model_error(elements, extrapolate)
    largest = EXTRAPOLATED_MAX_ELEMENTS if extrapolate else TRANSIENT_MAX_ELEMENTS
    how = "as given" if given else f"chosen for the tolerance, at most {largest}"
    grids = (f"elements = {elements // 2}/{elements} extrapolated ({how}), modelled error {reached:.2g} mu N "
             "(benchmarks/bench_transient_pairs.py)" if extrapolate else
             f"elements = {elements} ({how}), modelled error {reached:.2g} mu N (benchmarks/bench_transient_pairs.py)")
    text = f"tolerance = {tolerance!r}: instationary steps run the discretised transient (method_used 5) with {grids}"
    if adaptive:
        text += (" where the relaxation lag (method_used 4) would not meet the tolerance: the lag runs while its "
                 f"error bound for the creep swing over the last {LAG_MEMORY:g} relaxation lengths, "
                 f"{LAG_ERROR_COEFFICIENT:g} mu N per saturation creep of half the swing (less where the swing stays "
                 f"away from zero creep) + {LAG_ERROR_FLOOR:g} mu N (rollcontact.instationary.lag_error_bound, "
                 "benchmarks/bench_relaxation.py), meets it")
    if reached > tolerance:
        return text + f"; the tolerance is NOT met, {reached:.2g} mu N is reached"
    return text


def instationary_unavailable(surface: Surface, friction) -> str | None:
    """Why the instationary models cannot treat a scene (they assume a flat surface and Coulomb friction)."""
    if not surface.is_flat:
        return "the instationary models assume a flat surface, and this one is corrugated or curved"
    if not friction.is_constant:
        return "the instationary models assume Coulomb friction, and this friction depends on slip velocity"
    return None


def method_code(name: str) -> int:
    """``method_used`` code of a registry name (0 when it belongs to no family of :data:`METHOD_NAMES`)."""
    return next((code for code, family in METHOD_NAMES.items() if name.startswith(family)), 0)


def registered_methods(codes: tuple[int, ...]) -> tuple[str, ...]:
    """Registered methods of the families ``codes``, in that family order and by cost within a family."""
    specs = sorted((s for s in METHODS.values() if method_code(s.name) in codes),
                   key=lambda s: (codes.index(method_code(s.name)), s.cost))
    return tuple(s.name for s in specs)


def input_problem(current_time, step_size, normal_load, creep, velocity) -> str:
    """The message for the first invalid step argument (what, which value, which limit)."""
    checks = (
        ("current_time", current_time, "s", None),
        ("step_size", step_size, "s", "> 0"),
        ("normal_load", normal_load, "N", ">= 0"),
        ("creep", creep, "1", None),
        ("velocity", velocity, "m/s", ">= 0"),
    )
    for name, value, unit, bound in checks:
        try:
            v = float(value)
        except (TypeError, ValueError):
            return f"{name} must be a real number, got {value!r}"
        if not math.isfinite(v):
            return f"{name} = {v!r} is not finite"
        if (bound == "> 0" and not v > 0.0) or (bound == ">= 0" and not v >= 0.0):
            return f"{name} = {v!r} {unit} is out of range: it must be {bound}"
    return "invalid step arguments"
