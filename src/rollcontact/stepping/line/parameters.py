"""Fixed parameters of the line contact's stepping model, the outputs of a step and the codes of the FMU's integer
variables.

* :class:`ContactParameters` holds the fixed parameters (FMU parameters of the same names: the shared block of
  :class:`~rollcontact.stepping.parameters.ModelParameters` and the line contact's own) and checks them;
  :func:`contact_bodies` turns them into the material, radius, friction law and surface (in the model's frame).
* :class:`StepOutputs` is what one step returns (SI units).
* :data:`METHOD_LEVELS` declares the FMU's ``method`` / ``method_used`` codes once; :data:`METHOD_NAMES`,
  :data:`AUTO_CODES`, :data:`INSTATIONARY_CODES` and :data:`TABLE_CODE` follow from it, and with :data:`OPTION_NAMES`
  map the codes and the parameters to the registered methods and their options.

A module of its own so that :mod:`rollcontact.stepping.line.model` and :mod:`rollcontact.stepping.line.transient`
share these without importing each other.  The model itself (frames, time stepping, instationary rolling) is
described in :mod:`rollcontact.stepping.line.model`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, NamedTuple

from rollcontact.core.checks import SceneError
from rollcontact.core.friction import FrictionLaw
from rollcontact.core.materials import Material
from rollcontact.line.dispatch import METHODS
from rollcontact.line.scene import Harmonic, Surface, load_scene
from rollcontact.stepping.base import ModelError, argument_problems, time_problems
from rollcontact.stepping.parameters import AUTO, Level, ModelParameters, friction_law, whole_number_problems

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
takes the next code); ``tests/stepping/line/test_parameters.py`` checks that every built-in method has a code."""

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
"""``table``: a certified table of the scene family (:mod:`rollcontact.stepping.line.table`) built when the run pays for
it (auto), never, or at the first loaded step (on)."""

TABLE_CODE = LEVEL_CODES["table"]
"""``method_used`` of a step answered by the certified table."""






OPTION_NAMES = {"polynomial_order": "order", "elements": "elements", "datum": "datum_length"}
"""Parameter -> the option under which it is passed to a method that lists it in its ``options``.

A parameter equal to 0 is not passed (the method's default applies).  ``tolerance`` is not an option: it is the
requested accuracy of :func:`rollcontact.solve`, which picks each method's cheapest setting that meets it; these
explicit parameters then override that setting.
"""








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
class ContactParameters(ModelParameters):
    """Fixed parameters of a :class:`~rollcontact.stepping.line.model.ContactModel` (the FMU parameters of the same
    names), checked on creation: the shared block (:class:`~rollcontact.stepping.parameters.ModelParameters`:
    material, friction law, rail condition, ``method``, ``tolerance``, ``step_budget``) and the line contact's own.

    Parameters
    ----------
    radius : float
        Effective wheel radius R [m] > 0.
    contact_width : float
        Lateral length b [m] > 0 of the line contact; per-length quantities are force / b.
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
        given, its material, radius, friction and surface replace the scalar parameters (the surface is read in the
        model's frame), while its load, creep, axis position and speed are replaced by the inputs.  Empty: unused.
    polynomial_order : int
        Polynomial order >= 0 for methods that accept it (0: the method's default).
    elements : int
        Element count >= 0 for methods that accept it and for the discretised transient (0: the method's
        default; the transient's grids are chosen from ``tolerance``, else one grid of 100; > 0: one grid).
    transient : int
        0 quasi-static, 1 auto (instationary model only while the stationarity measure calls for it), 2 always
        (:mod:`rollcontact.stepping.line.model`, "Instationary rolling").
    datum : float
        Datum distance L [m] >= 0 of instationary rolling, for methods that accept it (0: the method's default).
    table : int
        0 auto, 1 off, 2 on: where the scene family has a certified table (falling friction on a flat surface, or
        Coulomb friction on a corrugation of one harmonic: :mod:`rollcontact.stepping.line.table`) and ``tolerance``
        is 0 or at least its target, the steps answer from the table once it is built: ``auto`` builds it a little in
        each exact step, within ``step_budget`` (modelled work), once the exact steps have cost as much as the build
        (so a run pays at most twice what it would have paid knowing its length); ``on`` builds it at the first
        loaded step, whatever that takes.

    Notes
    -----
    The shared parameters take these meanings here: ``method`` 0 auto, else a choice of :data:`METHOD_LEVELS`
    (1 closed form, 2 polynomial, 3 discretised); ``tolerance`` the requested relative error [1] of T' and p0: each
    step's method runs with its cheapest setting whose error estimate meets it (as ``rollcontact.solve(scene,
    tolerance=...)``); with ``transient`` = 1 also the error of T' (of mu N) it tolerates before the instationary
    model takes over.  It sets the grids of the discretised transient with ``method`` = 3, and with ``method`` = 0
    below :data:`~rollcontact.stepping.line.transient.RELAXATION_ACCURACY`, where ``transient`` = 1 uses that
    transient wherever the relaxation lag's bound for the creep swing does not meet the tolerance (0: the methods'
    defaults and :data:`~rollcontact.stepping.line.transient.DEFAULT_TRANSIENT_TOLERANCE`).  ``step_budget``
    bounds the steady solve (the most accurate setting that meets ``tolerance`` within it, as
    ``rollcontact.solve(..., budget=...)``), a table build (the exact solves that fit what is left) and the
    discretised transient (at most as many substeps as fit); where that costs accuracy, the model says so once.
    """

    radius: float = 0.46
    contact_width: float = 0.02
    corrugation_wavelength: float = 0.04
    corrugation_amplitude: float = 0.0
    corrugation_phase: float = 0.0
    initial_position: float = 0.0
    scene_file: str = ""
    polynomial_order: int = 0
    elements: int = 0
    transient: int = 0
    datum: float = 0.0
    table: int = 0

    LEVELS: ClassVar[tuple[Level, ...]] = METHOD_LEVELS
    REALS: ClassVar[tuple] = ModelParameters.REALS + (
        ("radius", 0.0, None, True, False),
        ("contact_width", 0.0, None, True, False),
        ("corrugation_wavelength", 0.0, None, True, False),
        ("corrugation_amplitude", 0.0, None, False, False),
        ("corrugation_phase", None, None, False, False),
        ("initial_position", None, None, False, False),
        ("datum", 0.0, None, False, False))

    def codes(self) -> dict[str, dict]:
        return {**super().codes(), "transient": TRANSIENT_MODES, "table": TABLE_MODES}

    def problems(self) -> list[str]:
        problems = super().problems() + whole_number_problems(self, ("polynomial_order", "elements"))
        if not isinstance(self.scene_file, str):
            problems.append(f"scene_file must be a string (a path or empty), got {self.scene_file!r}")
        return problems


def method_code(name: str) -> int:
    """``method_used`` code of a registry name (0 when it belongs to no family of :data:`METHOD_NAMES`)."""
    return next((code for code, family in METHOD_NAMES.items() if name.startswith(family)), 0)


def registered_methods(codes: tuple[int, ...]) -> tuple[str, ...]:
    """Registered methods of the families ``codes``, in that family order and by rank within a family."""
    specs = sorted((s for s in METHODS.values() if method_code(s.name) in codes),
                   key=lambda s: (codes.index(method_code(s.name)), s.rank))
    return tuple(s.name for s in specs)


def input_problem(current_time, step_size, normal_load, creep, velocity) -> str:
    """The message for the invalid step arguments (each: what, which value, which limit)."""
    problems = time_problems(current_time, step_size) + argument_problems(
        (("normal_load", normal_load, "N", 0.0, False), ("creep", creep, "", None, False),
         ("velocity", velocity, "m/s", 0.0, False)))
    return "; ".join(problems) or "invalid step arguments"


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
