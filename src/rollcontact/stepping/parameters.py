"""Fixed parameters of the stepping model, the outputs of a step and the codes of the FMU's integer variables.

* :class:`ContactParameters` holds the fixed parameters (FMU parameters of the same names) and checks them;
  :func:`contact_bodies` turns them into the material, radius, friction law and surface (in the model's frame).
* :class:`StepOutputs` is what one step returns (SI units); :class:`ModelError` what it raises.
* :data:`METHOD_LEVELS` declares the FMU's ``method`` / ``method_used`` codes once; :data:`METHOD_NAMES`,
  :data:`AUTO_CODES`, :data:`INSTATIONARY_CODES` and :data:`TABLE_CODE` follow from it, and with :data:`OPTION_NAMES`
  map the codes and the parameters to the registered methods and their options.

A module of its own so that :mod:`rollcontact.stepping.model` and :mod:`rollcontact.stepping.transient` share these
without importing each other.  The model itself (frames, time stepping, instationary rolling) is described in
:mod:`rollcontact.stepping.model`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rollcontact.checks import SceneError, check_real
from rollcontact.dispatch import METHODS
from rollcontact.friction import (
    RAIL_CONDITIONS,
    Coulomb,
    ExponentialFalling,
    FrictionLaw,
    LinearFalling,
    RationalFalling,
    TabulatedFriction,
)
from rollcontact.scene import Harmonic, Material, Surface, load_scene

AUTO = 0
"""``method`` code of the automatic choice."""


class Level(NamedTuple):
    """One row of :data:`METHOD_LEVELS`: a code of the FMU's ``method_used`` (and of ``method`` where it is a choice).

    Attributes
    ----------
    code : int
        The code (> 0; 0 is auto, resp. no contact).  Never reused or changed: hosts and recorded runs hold it.
    name : str
        The item's name in the FMU's enumerations; for a choice also the family: a registered method belongs to the
        level when its registry name starts with it (e.g. ``"polynomial_friction"`` is a polynomial method).
    choice : str
        Description of the ``method`` item ("": not a value of ``method``, only reported by ``method_used``).
    used : str
        Description of the ``method_used`` item.
    auto : bool
        Whether ``method`` = auto tries the family's registered methods (in table order, by rank within a family)
        on scenes the closed forms cannot treat.
    """

    code: int
    name: str
    choice: str
    used: str
    auto: bool = False


METHOD_LEVELS = (
    Level(1, "closed_form", "Hertz and Carter: flat surface, Coulomb friction", "Hertz and Carter"),
    Level(2, "polynomial", "the polynomial method", "the polynomial method", auto=True),
    Level(3, "discretised", "the discretised (boundary-element) method", "the discretised method", auto=True),
    Level(4, "relaxation_lag", "", "instationary: the relaxation lag around Carter"),
    Level(5, "discretised_transient", "", "instationary: the discretised transient"),
    Level(6, "table", "", "the certified table of the scene family"),
)
"""The 2D fidelity levels as the FMU numbers them: the ``method`` choices, the ``method_used`` codes, the FMU's
``Method`` and ``MethodUsed`` enumerations and their documented table all follow from it.  Append only (a new level
takes the next code); ``tests/stepping/test_parameters.py`` checks that every built-in method has a code."""

LEVEL_CODES = {level.name: level.code for level in METHOD_LEVELS}
"""Level name -> code."""

CLOSED_FORM, POLYNOMIAL, DISCRETISED = LEVEL_CODES["closed_form"], LEVEL_CODES["polynomial"], LEVEL_CODES["discretised"]
"""``method`` codes the model treats by name: the closed forms' own path, the polynomial family that certified tables
stand in for, the discretised family whose transient is exact."""

METHOD_NAMES = {level.code: level.name for level in METHOD_LEVELS if level.choice}
"""``method`` codes and the method families they stand for (0 is auto), from :data:`METHOD_LEVELS`."""

AUTO_CODES = tuple(level.code for level in METHOD_LEVELS if level.auto)
"""Families ``method`` = auto tries, in this order, on scenes the closed forms cannot treat."""


STATIONARY = 1e9
"""``stationarity`` reported when nothing varies (constant inputs or no contact); also its upper bound."""


INSTATIONARY_CODES = {"relaxation": LEVEL_CODES["relaxation_lag"], "transient": LEVEL_CODES["discretised_transient"]}
"""``method_used`` of the instationary models by their mode: the relaxation lag around Carter, the discretised
transient."""


TRANSIENT_MODES = {0: "quasi-static", 1: "auto", 2: "always"}

TABLE_MODES = {0: "auto", 1: "off", 2: "on"}
"""``table``: a certified table of the scene family (:mod:`rollcontact.stepping.table`) built when the run pays for it
(auto), never, or at the first loaded step (on)."""

TABLE_CODE = LEVEL_CODES["table"]
"""``method_used`` of a step answered by the certified table."""


FRICTION_LAWS = {0: "Coulomb", 1: "exponential falling", 2: "rational falling", 3: "linear falling", 4: "tabulated"}
"""``friction_law`` codes: every law of :mod:`rollcontact.friction` (:func:`contact_bodies` builds it)."""

TABLE_LAW = 4
"""``friction_law`` of the tabulated law, whose points ``friction_table`` gives (:func:`friction_table_points`)."""

RAIL_CONDITION_CODES = {0: "custom", **{k: name for k, name in enumerate(RAIL_CONDITIONS, start=1)}}
"""``rail_condition`` codes: 0 custom (the ``friction_*`` parameters), else a named condition of
:data:`rollcontact.friction.RAIL_CONDITIONS` whose law replaces them."""


OPTION_NAMES = {"polynomial_order": "order", "elements": "elements", "datum": "datum_length"}
"""Parameter -> the option under which it is passed to a method that lists it in its ``options``.

A parameter equal to 0 is not passed (the method's default applies).  ``tolerance`` is not an option: it is the
requested accuracy of :func:`rollcontact.solve`, which picks each method's cheapest setting that meets it; these
explicit parameters then override that setting.
"""


new_tuple = tuple.__new__
"""``new_tuple(StepOutputs, values)`` builds outputs without ``NamedTuple.__new__``'s extra Python frame (the
closed-form step's hot path)."""


DEFAULT_STEP_BUDGET = 0.05
"""Default ``step_budget`` [s]: a few tens of milliseconds, what a host stepping a few contacts at 1 kHz in a
soft real-time loop can give one contact; ``benchmarks/bench_step_budget.py`` measures the steps it bounds."""


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
        Code of the level that answered (:data:`METHOD_LEVELS`), 0 no contact.
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
        0 Coulomb (mu constant), 1 exponential falling ``mu(v) = mu [(1 - A) exp(-B v) + A]``, 2 rational falling
        ``mu(v) = A mu + (1 - A) mu / (1 + v / v_ref)``, 3 linear falling ``mu(v) = max(A mu, mu - c v)``
        (:mod:`rollcontact.friction`; v the slip velocity [m/s], mu = ``friction_coefficient``), 4 tabulated:
        piecewise linear through the points of ``friction_table`` (``friction_coefficient`` is then unused).
    friction_kinetic_ratio : float
        A [1] in (0, 1]: mu(infinity)/mu of the falling laws (the kinetic coefficient A mu of the rational and
        linear laws).
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
        0 auto, else a choice of :data:`METHOD_LEVELS` (1 closed form, 2 polynomial, 3 discretised).
    tolerance : float
        Requested relative error [1] >= 0 of T' and p0: each step's method runs with its cheapest setting whose
        error estimate meets it (:func:`rollcontact.dispatch.setting_for`, as ``rollcontact.solve(scene,
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
    step_budget : float
        Work budget [s] >= 0 of one step, by the methods' cost models (modelled seconds, no clock: the same bound
        on every machine): the steady solve runs the most accurate setting that meets ``tolerance`` within it
        (``rollcontact.solve(..., budget=...)``), a table build the exact solves that fit what is left
        (:mod:`rollcontact.stepping.table`), the discretised transient at most as many substeps as fit
        (:func:`rollcontact.stepping.transient.max_substeps`);
        where that costs accuracy, the model says so once (:meth:`ContactModel.take_messages`).  0: no budget, as
        long as each step takes.
    friction_reference_velocity : float
        v_ref [m/s] > 0 of the rational law.
    friction_slope : float
        c [s/m] >= 0 of the linear law.
    friction_table : str
        Points ``"v mu; v mu; ..."`` (v [m/s] increasing from >= 0, mu [1] > 0) of the tabulated law, e.g.
        ``"0 0.3; 1 0.25; 5 0.12"``; mu is constant beyond the ends.  Read only with ``friction_law`` = 4.
    table : int
        0 auto, 1 off, 2 on: where the scene family has a certified table (falling friction on a flat surface, or
        Coulomb friction on a corrugation of one harmonic: :mod:`rollcontact.stepping.table`) and ``tolerance`` is 0 or
        at least its target, the steps answer from the table once it is built: ``auto`` builds it a little in each exact
        step, within ``step_budget`` (modelled work), once the exact steps have cost as much as the build (so a run pays
        at most twice what it would have paid knowing its length); ``on`` builds it at the first loaded step, whatever
        that takes.
    rail_condition : int
        A code of :data:`RAIL_CONDITION_CODES`: 0 custom (the ``friction_*`` parameters above), 1 dry, 2 wet rail
        (:data:`rollcontact.friction.RAIL_CONDITIONS`, Polach's parameter sets of the exponential law), whose law
        replaces ``friction_law``, ``friction_coefficient``, ``friction_kinetic_ratio`` and ``friction_decay``.
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
    step_budget: float = DEFAULT_STEP_BUDGET
    table: int = 0
    friction_reference_velocity: float = 2.0
    friction_slope: float = 0.1
    friction_table: str = ""
    rail_condition: int = 0

    def __post_init__(self):
        """Check every parameter and raise one :class:`ModelError` naming each invalid value and its limit
        (``"; "``-separated, in field order), so that a user corrects them all at once."""
        set_ = object.__setattr__
        problems = []
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
                ("datum", 0.0, None, False, False),
                ("step_budget", 0.0, None, False, False),
                ("friction_reference_velocity", 0.0, None, True, False),
                ("friction_slope", 0.0, None, False, False)):
            try:
                set_(self, name, check_real(name, getattr(self, name), lower=lower, upper=upper,
                                            lower_open=lower_open, upper_open=upper_open))
            except SceneError as exc:
                problems.append(str(exc))
        for name, allowed in (("friction_law", FRICTION_LAWS), ("method", {AUTO: "auto", **METHOD_NAMES}),
                              ("transient", TRANSIENT_MODES), ("table", TABLE_MODES),
                              ("rail_condition", RAIL_CONDITION_CODES)):
            value = getattr(self, name)
            if value not in allowed:
                choices = ", ".join(f"{k} {v}" for k, v in allowed.items())
                problems.append(f"{name} = {value!r} is out of range: it must be one of {choices}")
            else:
                set_(self, name, int(value))
        for name in ("polynomial_order", "elements"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
                problems.append(f"{name} = {value!r} is out of range: it must be an integer >= 0 "
                                "(0: the method's default)")
            else:
                set_(self, name, int(value))
        if not isinstance(self.scene_file, str):
            problems.append(f"scene_file must be a string (a path or empty), got {self.scene_file!r}")
        problems += friction_table_problems(self.friction_table, self.friction_law)
        if problems:
            raise ModelError("; ".join(problems))


def friction_table_problems(table, law: int) -> list[str]:
    """What is wrong with the ``friction_table`` parameter (a string, and with ``friction_law`` = tabulated a
    table :func:`friction_table_points` reads); [] when nothing is.  Both contact FMUs' parameters check it so."""
    if not isinstance(table, str):
        return [f"friction_table must be a string ('v mu; v mu; ...'), got {table!r}"]
    if law == TABLE_LAW:
        try:
            friction_table_points(table)
        except ValueError as exc:
            return [str(exc)]
    return []


def friction_table_points(text: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Velocities [m/s] and coefficients [1] of a ``friction_table`` ``"v mu; v mu; ..."``, checked as
    :class:`rollcontact.friction.TabulatedFriction` checks them.

    Raises
    ------
    ValueError
        The text is no such table; the message shows the form and the first problem.
    """
    form = "write 'v mu' pairs (v [m/s] increasing, mu [1] > 0) separated by ';', e.g. '0 0.3; 1 0.25; 5 0.12'"
    rows = [row.split() for row in text.split(";") if row.strip()]
    if not rows or any(len(row) != 2 for row in rows):
        raise ValueError(f"friction_table = {text[:80]!r} is not a friction table: {form}")
    try:
        law = TabulatedFriction(tuple(float(v) for v, _ in rows), tuple(float(mu) for _, mu in rows))
    except ValueError as exc:
        raise ValueError(f"friction_table = {text[:80]!r}: {exc}; {form}") from None
    return law.velocities, law.coefficients


def method_code(name: str) -> int:
    """``method_used`` code of a registry name (0 when it belongs to no family of :data:`METHOD_NAMES`)."""
    return next((code for code, family in METHOD_NAMES.items() if name.startswith(family)), 0)


def registered_methods(codes: tuple[int, ...]) -> tuple[str, ...]:
    """Registered methods of the families ``codes``, in that family order and by rank within a family."""
    specs = sorted((s for s in METHODS.values() if method_code(s.name) in codes),
                   key=lambda s: (codes.index(method_code(s.name)), s.rank))
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


def contact_bodies(p: ContactParameters) -> tuple[Material, float, FrictionLaw, Surface, list[str]]:
    """Material, radius [m], friction law and surface (in the model's frame) of the parameters, or of their
    ``scene_file``, and the notices that go with them.

    Raises
    ------
    ModelError
        The scene file cannot be read, or the parameters make no valid material, law or surface.
    """
    if p.scene_file:
        try:
            base = load_scene(p.scene_file)
        except SceneError as exc:
            raise ModelError(f"scene_file: {exc}") from None
        notice = (f"scene_file {p.scene_file!r} sets material, radius, friction and surface; the scalar parameters "
                  "for them are ignored, and the inputs replace its load, creep and speed")
        return base.material, base.radius, base.friction, base.surface, [notice]
    try:
        material = Material(p.youngs_modulus, p.poisson_ratio)
        friction = friction_law(p)
        harmonics = ()
        if p.corrugation_amplitude != 0.0:
            harmonics = (Harmonic.from_wavelength(p.corrugation_wavelength, p.corrugation_amplitude,
                                                  p.corrugation_phase),)
        surface = Surface(harmonics=harmonics)
    except ValueError as exc:
        raise ModelError(str(exc)) from None
    return material, p.radius, friction, surface, []


def friction_law(p) -> FrictionLaw:
    """The friction law of the FMU parameters ``friction_law`` (a code of :data:`FRICTION_LAWS`),
    ``friction_coefficient``, ``friction_kinetic_ratio``, ``friction_decay``, ``friction_reference_velocity``,
    ``friction_slope`` and ``friction_table`` of ``p`` (any object with them: the 2D and the elliptic parameters), or
    the law of its ``rail_condition`` when that is not 0 (custom).

    Raises
    ------
    ValueError
        The values make no valid law (the law's message).
    """
    if p.rail_condition:
        return RAIL_CONDITIONS[RAIL_CONDITION_CODES[p.rail_condition]].law()
    mu, ratio = p.friction_coefficient, p.friction_kinetic_ratio
    laws = {0: lambda: Coulomb(mu), 1: lambda: ExponentialFalling(mu, ratio, p.friction_decay),
            2: lambda: RationalFalling(mu, ratio * mu, p.friction_reference_velocity),
            3: lambda: LinearFalling(mu, ratio * mu, p.friction_slope),
            4: lambda: TabulatedFriction(*friction_table_points(p.friction_table))}
    return laws[p.friction_law]()


def step_methods(p: ContactParameters, surface: Surface, friction) -> tuple[bool, tuple[str, ...]]:
    """Whether the steps take the closed forms, else the registered methods they may use (auto: polynomial,
    then discretised).

    Raises
    ------
    ModelError
        ``method`` = 1 on a scene the closed forms cannot treat, or no method of the family is registered.
    """
    flat_reason = None
    if not surface.is_flat:
        flat_reason = "the surface is not flat (corrugation, harmonics or polynomial terms of degree >= 2)"
    elif not friction.is_constant:
        flat_reason = "friction depends on slip velocity"
    if p.method == CLOSED_FORM and flat_reason is not None:
        *others, last = [f"{AUTO} (auto)", *(f"{code} ({name})" for code, name in METHOD_NAMES.items()
                                             if code != CLOSED_FORM)]
        raise ModelError(f"method = {CLOSED_FORM} (closed form) cannot solve this scene: {flat_reason}; "
                         f"use method = {', '.join(others)} or {last}")
    if p.method == CLOSED_FORM or (p.method == AUTO and flat_reason is None):
        return True, ()
    codes = AUTO_CODES if p.method == AUTO else (p.method,)
    candidates = registered_methods(codes)
    if not candidates:
        wanted = " or ".join(f"{c} ({METHOD_NAMES[c]})" for c in codes)
        why = f"{flat_reason}, which needs" if p.method == AUTO else "it needs"
        raise ModelError(f"method = {p.method}: {why} method {wanted}, but no such method is registered "
                         f"in rollcontact.METHODS (registered: {sorted(METHODS)})")
    return False, candidates
