"""Co-simulation scenes: ``models/cosim/<scene>.toml`` -> :class:`CosimScene`, one system description per scene
(format in ``models/cosim/README.md``).

A scene describes its system and its run, and every master runs every scene from it:

* the system (:class:`System`): two FMU instances, a host and a contact (:class:`Instance`: model, variant - contacts
  per FMU, FMI version, integer codes - and parameters), and the connections between them: the contact's inputs
  from the host's outputs of the same names, the contact's forces and their derivatives (the creep stiffness of the
  line contact, the Jacobian of the elliptic one) back to the host's inputs of the same names.  A scene without a
  ``[system]`` table is the wheel rig's (:data:`WHEEL_RIG`: ``WheelRig`` + ``RollingContact2D``);
* the run: time span, macro step, master algorithm, the recorded variables, and how closely a rerun must follow the
  reference result (:class:`Band`).

Names are checked against the models behind the FMUs (:data:`MODELS`: :mod:`rollcontact_cosim.wheel_rig`,
:mod:`rollcontact_cosim.wheelset.model`, the stepping models of :mod:`rollcontact.stepping`), so loading a scene
needs no FMU; values are checked by constructing those models' parameter objects.
"""

from __future__ import annotations

import dataclasses
import math
import sys
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

from rollcontact.stepping import (
    ContactParameters,
    EllipticOutputs,
    EllipticParameters,
    StepOutputs,
    WheelsetContactOutputs,
    WheelsetContactParameters,
)
from rollcontact_cosim.wheel_rig import INPUT_NAMES, WheelRigOutputs, WheelRigParameters
from rollcontact_cosim.wheelset import model as wheelset

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["ALGORITHMS", "CONTACT", "COSIM_DIR", "DEFAULT_SCENE", "HOST", "MODELS", "SCENE_NAMES", "WHEEL_RIG", "Band",
           "CosimScene", "CosimSceneError", "Instance", "Model", "System", "load_cosim_scene"]

HOST = "WheelRig"
"""Model and instance name of the wheel rig scenes' host FMU."""
CONTACT = "RollingContact2D"
"""Model and instance name of the wheel rig scenes' contact FMU."""

ALGORITHMS = ("gauss-seidel", "jacobi")
"""Master algorithms: Gauss-Seidel steps the contact first and hands its force to the host in the same macro step;
Jacobi steps both from the previous outputs (libcosim's fixed-step algorithm)."""

FORCE_LAG = {"gauss-seidel": 0, "jacobi": 1}
"""The host's ``force_lag`` that matches each algorithm (the contact's force is evaluated at the host's outputs of
the current, resp. the previous, communication point)."""

FMI_VERSIONS = (2, 3)
"""FMI versions of the FMUs: 2 (FMI 2.0, pythonfmu; the default) or 3 (FMI 3.0, pythonfmu3)."""

COSIM_DIR = Path(__file__).resolve().parents[2] / "models" / "cosim"
"""Folder of the scene files and reference results (the repository's ``models/cosim``)."""

SCENE_NAMES = ("traction_ramp", "corrugated_rail", "oscillating_torque", "carter_sanity")
"""The wheel rig scenes, each with its reference CSV (the regression suite)."""
DEFAULT_SCENE = "traction_ramp"

SECTIONS = {"description", "system", "run", "host", "contact", "reference"}
SYSTEM_KEYS = {"host", "contact", "contacts", "to_contact", "to_host", "fmi_version", "integer_codes"}
SYSTEM_REQUIRED = ("host", "contact", "to_contact", "to_host")
RUN_KEYS = {"start_time", "stop_time", "step_size", "algorithm", "outputs"}
REFERENCE_KEYS = {"variables", "band_height", "band_width", "samples", "max_outliers", "stride"}


class CosimSceneError(ValueError):
    """A scene file that cannot be used; the message names the file, the key, the value and the limit."""


# the models behind the FMUs ---------------------------------------------------------------------------------------
def indexed(names, contacts: int) -> tuple[str, ...]:
    """Per-contact variable names: as they are with one contact, ``name[k]`` (k = 1 .. contacts) with several."""
    if contacts == 1:
        return tuple(names)
    return tuple(f"{name}[{k}]" for k in range(1, contacts + 1) for name in names)


def defaults(parameters_class) -> dict[str, Any]:
    """Parameter name -> default of a parameter dataclass."""
    return {f.name: f.default for f in dataclasses.fields(parameters_class)}


@dataclass(frozen=True)
class Model:
    """What a scene may name of a model behind an FMU.

    Attributes
    ----------
    inputs, outputs : callable
        ``f(contacts)`` -> the FMU's input / output names.
    parameters : callable
        ``f(contacts)`` -> parameter name -> default (whose type is the FMU's).
    check : callable
        ``f(values, contacts)`` constructs the model's parameters from ``values``; raises its ValueError.
    variants : bool
        Whether the model is built with several contacts per FMU (``build_fmu.py --contacts N``).
    """

    inputs: Callable[[int], tuple[str, ...]]
    outputs: Callable[[int], tuple[str, ...]]
    parameters: Callable[[int], dict[str, Any]]
    check: Callable[[dict, int], Any]
    variants: bool = False


ELLIPTIC_INPUTS = ("normal_load", "longitudinal_creep", "lateral_creep", "spin", "velocity")
"""A contact's inputs of the RollingContact3D FMU: N [N], xi, eta [1], phi [1/m], V [m/s]."""
CURVATURES = ("curvature_longitudinal", "curvature_lateral")
"""The RollingContact3D FMU's parameters of their own per contact (the other parameters are shared)."""


def elliptic_parameters(contacts: int) -> dict[str, Any]:
    """The RollingContact3D FMU's parameters with ``contacts`` contacts and their defaults."""
    values = {name: value for name, value in defaults(EllipticParameters).items() if name not in CURVATURES}
    values.update({name: defaults(EllipticParameters)[name.split("[")[0]][0] for name in indexed(CURVATURES, contacts)})
    return values


def elliptic_check(values: dict, contacts: int) -> EllipticParameters:
    """The EllipticParameters of the FMU's parameter values (per-contact curvatures gathered, defaults for the
    unlisted)."""
    every = {**elliptic_parameters(contacts), **values}
    curvatures = {name: tuple(every[n] for n in indexed((name,), contacts)) for name in CURVATURES}
    return EllipticParameters(**{n: v for n, v in every.items() if n.split("[")[0] not in CURVATURES}, **curvatures)


def wheelset_parameters(contacts: int) -> dict[str, Any]:
    """The Wheelset FMU's parameters and their defaults (``contact_angle``: the conicity's, a float)."""
    return {**defaults(wheelset.WheelsetParameters), "contact_angle": wheelset.WheelsetParameters().contact_angle}


WHEELSET_CONTACT_INPUTS = ("lateral_shift", "yaw", "lateral_velocity", "yaw_rate", "forward_speed", "pitch_rate",
                           "vertical_load_left", "vertical_load_right")
"""The WheelsetContact FMU's inputs (track axes)."""

MODELS = MappingProxyType({
    "WheelRig": Model(lambda n: INPUT_NAMES, lambda n: WheelRigOutputs._fields,
                      lambda n: defaults(WheelRigParameters), lambda values, n: WheelRigParameters(**values)),
    "RollingContact2D": Model(lambda n: ("normal_load", "creep", "velocity"), lambda n: StepOutputs._fields,
                              lambda n: defaults(ContactParameters), lambda values, n: ContactParameters(**values)),
    "Wheelset": Model(lambda n: wheelset.INPUT_NAMES, lambda n: wheelset.OUTPUT_NAMES, wheelset_parameters,
                      lambda values, n: wheelset.WheelsetParameters(**values)),
    "RollingContact3D": Model(lambda n: indexed(ELLIPTIC_INPUTS, n), lambda n: indexed(EllipticOutputs._fields, n),
                              elliptic_parameters, elliptic_check, variants=True),
    "WheelsetContact": Model(lambda n: WHEELSET_CONTACT_INPUTS, lambda n: WheelsetContactOutputs._fields,
                             lambda n: defaults(WheelsetContactParameters),
                             lambda values, n: WheelsetContactParameters(**values)),
})
"""The models a scene's instances may be, by the model name of their FMU (without a variant's ``_N``)."""


# the system -------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Instance:
    """One FMU instance of a scene's system.

    Attributes
    ----------
    name : str
        Instance name, the model's name (``"RollingContact3D"``, also for its variant with several contacts).
    model : str
        A model of :data:`MODELS`.
    contacts : int
        Contacts per FMU: 1, the model's own FMU; N > 1, its variant ``<model>_N`` (``build_fmu.py --contacts N``),
        whose per-contact variables are named ``name[k]``.
    parameters : Mapping
        Start values (name -> value, read-only); unlisted ones keep the FMU's.
    """

    name: str
    model: str
    contacts: int = 1
    parameters: Mapping = field(default_factory=lambda: MappingProxyType({}), repr=False)

    @property
    def fmu_name(self) -> str:
        """Model name of the FMU: ``model``, or ``model_N`` for the variant with N contacts."""
        return self.model if self.contacts == 1 else f"{self.model}_{self.contacts}"

    @property
    def build_selection(self) -> tuple[str, ...]:
        """The ``build_fmu.py`` selection that builds this FMU: ``--only MODEL`` or ``--contacts N``."""
        return ("--only", self.model) if self.contacts == 1 else ("--contacts", str(self.contacts))

    def names(self, kind: str) -> tuple[str, ...]:
        """The FMU's ``"inputs"``, ``"outputs"`` or ``"parameters"`` by name."""
        return tuple(getattr(MODELS[self.model], kind)(self.contacts))


@dataclass(frozen=True)
class System:
    """The FMUs of a scene and their connections (module docstring).

    Attributes
    ----------
    host, contact : Instance
        The host (its outputs feed the contact) and the contact (its forces feed the host).
    to_contact : tuple of str
        Host outputs that are contact inputs of the same names, per contact (``name[k]`` with several); an entry
        ``"output -> input"`` connects an output to an input of another name (:func:`pairs`).
    to_host : tuple of str
        Contact outputs that are host inputs of the same names, per contact: the forces and their derivatives
        (``"output -> input"`` as in ``to_contact``).
    fmi_version : int
        2 (FMI 2.0) or 3 (FMI 3.0) for every FMU.
    integer_codes : bool
        The build whose enumerations are plain Integer variables (``build_fmu.py --integer-codes``: libcosim).
    """

    host: Instance
    contact: Instance
    to_contact: tuple[str, ...]
    to_host: tuple[str, ...]
    fmi_version: int = 2
    integer_codes: bool = False

    @property
    def instances(self) -> tuple[Instance, Instance]:
        """Contact, then host: the Gauss-Seidel order (the contact first)."""
        return self.contact, self.host

    @property
    def connections(self) -> tuple[tuple[str, str], ...]:
        """``(source output, target input)`` of every connection, ``"Instance.variable"`` (per contact for several)."""
        contacts = self.contact.contacts
        host, contact = self.host.name, self.contact.name
        return (*((f"{host}.{source}", f"{contact}.{target}") for source, target in pairs(self.to_contact, contacts)),
                *((f"{contact}.{source}", f"{host}.{target}") for source, target in pairs(self.to_host, contacts)))

    def variant(self, fmi_version: int | None = None, integer_codes: bool | None = None) -> System:
        """This system with its FMUs in another FMI version or build (None: as it is); ValueError for a variant
        that does not exist or that the connections cannot address."""
        fmi_version = self.fmi_version if fmi_version is None else check_fmi_version(fmi_version)
        integer_codes = self.integer_codes if integer_codes is None else bool(integer_codes)
        if integer_codes and fmi_version == 3:
            raise ValueError("the integer-codes build (for libcosim) is an FMI 2.0 build: use fmi_version = 2")
        if fmi_version == 3 and self.contact.contacts > 1:
            raise ValueError(f"the FMI 3.0 build of {self.contact.fmu_name} declares each per-contact variable as one "
                             f"array, which the connections name[k] do not address: use fmi_version = 2")
        return dataclasses.replace(self, fmi_version=fmi_version, integer_codes=integer_codes)

    def folder(self, fmu_dir: Path | str) -> Path:
        """Where ``build_fmu.py --dest fmu_dir`` puts this variant's FMUs: ``fmu_dir``, its ``fmi3/`` (FMI 3.0) or
        its ``integer_codes/`` (the integer-codes build, in a folder of its own)."""
        folder = Path(fmu_dir) / "integer_codes" if self.integer_codes else Path(fmu_dir)
        return folder / "fmi3" if self.fmi_version == 3 else folder

    def fmus(self, fmu_dir: Path | str) -> dict[str, Path]:
        """Instance name -> FMU file in :meth:`folder`."""
        return {instance.name: self.folder(fmu_dir) / f"{instance.fmu_name}.fmu" for instance in self.instances}


def pairs(entries, contacts: int) -> tuple[tuple[str, str], ...]:
    """``(output, input)`` of every entry of ``to_contact`` or ``to_host``, per contact (:func:`indexed`): ``"name"``
    connects the variables of that name, ``"output -> input"`` an output to an input of another name (the Wheelset
    host's track-axis velocities to a WheelsetContact's ``lateral_velocity`` and ``yaw_rate``, the host's own
    ``lateral_velocity`` being in its axes)."""
    out = []
    for entry in entries:
        source, _, target = (part.strip() for part in entry.partition("->"))
        out += zip(indexed((source,), contacts), indexed((target or source,), contacts), strict=True)
    return tuple(out)


def check_fmi_version(fmi_version) -> int:
    """``fmi_version`` if it is 2 or 3, else ValueError."""
    if isinstance(fmi_version, bool) or fmi_version not in FMI_VERSIONS:
        raise ValueError(f"fmi_version = {fmi_version!r} is unknown: use 2 (FMI 2.0) or 3 (FMI 3.0)")
    return int(fmi_version)


WHEEL_RIG_SYSTEM = {"host": HOST, "contact": CONTACT, "to_contact": ["normal_load", "creep", "velocity"],
                    "to_host": ["tangential_force", "creep_stiffness"]}
"""The ``[system]`` table of a scene without one: the wheel rig and the line contact, the contact's creep stiffness
to the host's linearly implicit coupling (:data:`WHEEL_RIG`)."""


# the scene --------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Band:
    """How closely a result must follow a reference (``[reference]``; :func:`rollcontact_cosim.reference.compare`).

    As fmpy's cross-check ``validate_signal``: the reference is resampled on ``samples`` uniform times over the
    run, widened by a running min/max over ``band_width`` samples (a horizontal tolerance; the reference's own
    samples in the window count too) and by ``band_height`` times the reference's range (times its magnitude when
    it is constant; 1e-12 absolute when it is constant zero); a result sample outside that band is an outlier,
    and at most ``max_outliers`` (a fraction) of them are allowed per variable.

    Attributes
    ----------
    variables : tuple of str
        Recorded variables (``"Instance.name"``) that are compared.
    band_height : float
        Relative vertical tolerance [1] > 0.
    band_width : int
        Horizontal tolerance in samples >= 1 (odd; 1: none).
    samples : int
        Uniform resampling points >= 2.
    max_outliers : float
        Allowed fraction of outliers in [0, 1).
    stride : int
        The reference CSV keeps every ``stride``-th communication point (>= 1, dividing the number of steps), so
        that fine-step scenes stay small files; the band interpolates it.
    """

    variables: tuple[str, ...]
    band_height: float = 0.01
    band_width: int = 5
    samples: int = 1000
    max_outliers: float = 0.0
    stride: int = 1


@dataclass(frozen=True)
class CosimScene:
    """A validated co-simulation scene (:func:`load_cosim_scene`).

    Attributes
    ----------
    name : str
        File stem (``traction_ramp`` for ``traction_ramp.toml``).
    path : Path
        The scene file.
    description : str
        Free text.
    start_time, stop_time, step_size : float
        t_0, t_end and the macro step H [s]; ``(t_end - t_0) / H`` is an integer (within 1e-9).
    algorithm : str
        ``"gauss-seidel"`` or ``"jacobi"``.
    outputs : tuple of str
        Recorded variables ``"Instance.output"``, in this order after ``time``.
    system : System
        The FMU instances with their parameters, and their connections.
    band : Band
        Comparison with the reference result.
    """

    name: str
    path: Path
    description: str
    start_time: float
    stop_time: float
    step_size: float
    algorithm: str
    outputs: tuple[str, ...]
    system: System = field(repr=False)
    band: Band = field(repr=False)

    @property
    def steps(self) -> int:
        """Number of macro steps N = (t_end - t_0) / H."""
        return macro_steps(self.start_time, self.stop_time, self.step_size)

    @property
    def reference_path(self) -> Path:
        """``<scene folder>/<name>_ref.csv``."""
        return self.path.with_name(f"{self.name}_ref.csv")

    def host_parameters(self, algorithm: str | None = None) -> dict[str, Any]:
        """The host's start values for ``algorithm`` (the scene's when None).

        ``force_lag`` is set to :data:`FORCE_LAG` of the algorithm unless the scene sets it: the linearly implicit
        coupling needs the host outputs at which the contact evaluated its force, which depends on the master.
        """
        algorithm = self.algorithm if algorithm is None else check_algorithm(algorithm)
        values = dict(self.system.host.parameters)
        values.setdefault("force_lag", FORCE_LAG[algorithm])
        return values

    def contact_parameters(self) -> dict[str, Any]:
        """The contact's start values."""
        return dict(self.system.contact.parameters)


def macro_steps(start_time: float, stop_time: float, step_size: float) -> int:
    """N with ``t_0 + N H = t_end`` (within 1e-9 N); raises CosimSceneError otherwise."""
    if not (math.isfinite(start_time) and math.isfinite(stop_time) and stop_time > start_time):
        raise CosimSceneError(f"stop_time = {stop_time!r} s must be finite and after start_time = {start_time!r} s")
    if not (math.isfinite(step_size) and step_size > 0.0):
        raise CosimSceneError(f"step_size = {step_size!r} s is out of range: it must be > 0")
    ratio = (stop_time - start_time) / step_size
    steps = round(ratio)
    if steps < 1 or abs(ratio - steps) > 1e-9 * max(1.0, ratio):
        raise CosimSceneError(f"(stop_time - start_time) / step_size = {ratio!r} must be a whole number of macro "
                              f"steps (start_time = {start_time!r} s, stop_time = {stop_time!r} s, "
                              f"step_size = {step_size!r} s)")
    return steps


def check_algorithm(algorithm: str) -> str:
    """``algorithm`` if it is one of :data:`ALGORITHMS`, else CosimSceneError listing them."""
    if algorithm not in ALGORITHMS:
        raise CosimSceneError(f"algorithm = {algorithm!r} is unknown: use one of {', '.join(ALGORITHMS)}")
    return algorithm


def scene_path(name_or_path: str | Path) -> Path:
    """A scene name (``traction_ramp``) resolved in :data:`COSIM_DIR`, or a path to a TOML file."""
    text = str(name_or_path)
    if isinstance(name_or_path, Path) or text.endswith(".toml") or "/" in text:
        return Path(name_or_path)
    path = COSIM_DIR / f"{text}.toml"
    if not path.is_file():
        known = sorted(p.stem for p in COSIM_DIR.glob("*.toml"))
        raise CosimSceneError(f"no co-simulation scene {text!r} in {COSIM_DIR} (scenes: {', '.join(known)})")
    return path


def load_cosim_scene(name_or_path: str | Path | CosimScene) -> CosimScene:
    """Read and validate a co-simulation scene.

    Parameters
    ----------
    name_or_path : str, Path or CosimScene
        A scene name of :data:`COSIM_DIR` (e.g. ``"traction_ramp"``), a path to a TOML file, or a scene (returned
        as it is).

    Returns
    -------
    CosimScene

    Raises
    ------
    CosimSceneError
        Unreadable file, unknown section or key, a model, parameter or variable name the FMUs do not have (the
        message lists the valid ones), a value of the wrong type or out of range, or a run that is not a whole
        number of macro steps.
    """
    if isinstance(name_or_path, CosimScene):
        return name_or_path
    path = scene_path(name_or_path)
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise CosimSceneError(f"cannot read co-simulation scene {str(path)!r}: {exc}") from None
    try:
        return parse_scene(data, path)
    except CosimSceneError as exc:
        raise CosimSceneError(f"{path}: {exc}") from None


def parse_scene(data: dict, path: Path) -> CosimScene:
    """The :class:`CosimScene` of the TOML tables ``data`` read from ``path``."""
    unknown(data, SECTIONS, "top-level key")
    description = data.get("description", "")
    if not isinstance(description, str):
        raise CosimSceneError(f"description must be a string, got {description!r}")
    system = parse_system(table(data, "system") if "system" in data else WHEEL_RIG_SYSTEM, table(data, "host"),
                          table(data, "contact"))
    run = table(data, "run")
    unknown(run, RUN_KEYS, "[run] key")
    start = real(run, "start_time", 0.0, "run")
    stop = real(run, "stop_time", None, "run")
    step = real(run, "step_size", None, "run")
    steps = macro_steps(start, stop, step)
    algorithm = run.get("algorithm", "gauss-seidel")
    check_algorithm(algorithm)
    outputs = names(run, "outputs", "run")
    if not outputs:
        raise CosimSceneError("[run] outputs must list at least one variable")
    for name in outputs:
        check_variable(system, name, "[run] outputs")
    reference = table(data, "reference")
    unknown(reference, REFERENCE_KEYS, "[reference] key")
    compared = names(reference, "variables", "reference") if "variables" in reference else outputs
    missing = [n for n in compared if n not in outputs]
    if missing:
        raise CosimSceneError(f"[reference] variables {missing} are not recorded: add them to [run] outputs")
    band = Band(compared, real(reference, "band_height", Band.band_height, "reference"),
                integer(reference, "band_width", Band.band_width, "reference"),
                integer(reference, "samples", Band.samples, "reference"),
                real(reference, "max_outliers", Band.max_outliers, "reference"),
                integer(reference, "stride", Band.stride, "reference"))
    if not band.band_height > 0.0:
        raise CosimSceneError(f"[reference] band_height = {band.band_height!r} is out of range: it must be > 0")
    if band.band_width < 1 or band.band_width % 2 == 0:
        raise CosimSceneError(f"[reference] band_width = {band.band_width!r} must be an odd integer >= 1")
    if band.samples < 2:
        raise CosimSceneError(f"[reference] samples = {band.samples!r} is out of range: it must be >= 2")
    if not 0.0 <= band.max_outliers < 1.0:
        raise CosimSceneError(f"[reference] max_outliers = {band.max_outliers!r} must lie in [0, 1)")
    if band.stride < 1 or steps % band.stride:
        raise CosimSceneError(f"[reference] stride = {band.stride!r} must be an integer >= 1 dividing the "
                              f"{steps} macro steps")
    return CosimScene(path.stem, path, description, start, stop, step, algorithm, outputs, system, band)


def parse_system(data: dict, host: dict, contact: dict) -> System:
    """The :class:`System` of a ``[system]`` table and the ``[host]`` and ``[contact]`` parameter tables."""
    unknown(data, SYSTEM_KEYS, "[system] key")
    missing = [key for key in SYSTEM_REQUIRED if key not in data]
    if missing:
        raise CosimSceneError(f"[system] {missing[0]} is missing: a [system] table names {', '.join(SYSTEM_REQUIRED)}")
    models = {}
    for role in ("host", "contact"):
        model = data[role]
        if model not in MODELS:
            raise CosimSceneError(f"[system] {role} = {model!r} is not a model: use one of {', '.join(MODELS)}")
        models[role] = model
    contacts = integer(data, "contacts", 1, "system")
    if contacts < 1 or (contacts > 1 and not MODELS[models["contact"]].variants):
        with_variants = [name for name, m in MODELS.items() if m.variants]
        raise CosimSceneError(f"[system] contacts = {contacts!r} is out of range: it must be 1, or >= 2 for a contact "
                              f"model built with several contacts ({', '.join(with_variants)})")
    fmi_version = integer(data, "fmi_version", 2, "system")
    integer_codes = data.get("integer_codes", False)
    if not isinstance(integer_codes, bool):
        raise CosimSceneError(f"[system] integer_codes = {integer_codes!r} must be true or false")
    instances = {"host": Instance(models["host"], models["host"]),
                 "contact": Instance(models["contact"], models["contact"], contacts)}
    for role, values in (("host", host), ("contact", contact)):
        instance = instances[role]
        checked = parameters(values, instance, role)
        try:
            MODELS[instance.model].check(checked, instance.contacts)
        except ValueError as exc:
            raise CosimSceneError(f"[{role}]: {exc}") from None
        instances[role] = dataclasses.replace(instance, parameters=MappingProxyType(checked))
    system = System(instances["host"], instances["contact"], names(data, "to_contact", "system"),
                    names(data, "to_host", "system"))
    for key, source, target in (("to_contact", system.host, system.contact), ("to_host", system.contact, system.host)):
        for names_ in pairs(getattr(system, key), contacts):
            for name, instance, kind in zip(names_, (source, target), ("outputs", "inputs"), strict=True):
                if name not in instance.names(kind):
                    raise CosimSceneError(f"[system] {key}: {instance.name} has no {kind[:-1]} {name!r} ({kind}: "
                                          f"{', '.join(instance.names(kind))})")
    try:
        return system.variant(fmi_version, integer_codes)
    except ValueError as exc:
        raise CosimSceneError(f"[system]: {exc}") from None


def unknown(data: dict, allowed: set[str], what: str) -> None:
    extra = sorted(set(data) - allowed)
    if extra:
        raise CosimSceneError(f"unknown {what} {extra[0]!r}: allowed are {', '.join(sorted(allowed))}")


def table(data: dict, name: str) -> dict:
    value = data.get(name, {})
    if not isinstance(value, dict):
        raise CosimSceneError(f"[{name}] must be a table, got {value!r}")
    return value


def real(data: dict, key: str, default: float | None, section: str) -> float:
    if key not in data:
        if default is None:
            raise CosimSceneError(f"[{section}] {key} is missing")
        return default
    value = data[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise CosimSceneError(f"[{section}] {key} = {value!r} must be a finite number")
    return float(value)


def integer(data: dict, key: str, default: int, section: str) -> int:
    value = data.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int):
        raise CosimSceneError(f"[{section}] {key} = {value!r} must be an integer")
    return value


def names(data: dict, key: str, section: str) -> tuple[str, ...]:
    value = data.get(key, [])
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise CosimSceneError(f"[{section}] {key} must be a list of strings, got {value!r}")
    if len(set(value)) != len(value):
        raise CosimSceneError(f"[{section}] {key} lists a variable twice: {value!r}")
    return tuple(value)


def check_variable(system: System, name: str, where: str) -> None:
    """``name`` must be ``"<instance>.<output>"`` of one of the system's instances."""
    instance, _, variable = name.partition(".")
    by_name = {i.name: i for i in system.instances}
    if instance not in by_name:
        raise CosimSceneError(f"{where}: {name!r} must be '<instance>.<output>' with instance "
                              f"{system.host.name} or {system.contact.name}")
    outputs = by_name[instance].names("outputs")
    if variable not in outputs:
        raise CosimSceneError(f"{where}: {instance} has no output {variable!r} (outputs: {', '.join(outputs)})")


def parameters(values: dict, instance: Instance, section: str) -> dict[str, Any]:
    """The parameter table of ``instance``, names and types checked against the FMU's parameters."""
    known = MODELS[instance.model].parameters(instance.contacts)
    for name, value in values.items():
        if name not in known:
            raise CosimSceneError(f"[{section}] {instance.name} has no parameter {name!r} (parameters: "
                                  f"{', '.join(known)})")
        default = known[name]
        if isinstance(default, str):
            ok = isinstance(value, str)
        elif isinstance(default, int):
            ok = isinstance(value, int) and not isinstance(value, bool)
        else:
            ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        if not ok:
            raise CosimSceneError(f"[{section}] {name} = {value!r} must be of type {type(default).__name__} "
                                  f"(the FMU's {'Integer' if type(default) is int else type(default).__name__})")
    return {name: float(v) if isinstance(known[name], float) else v for name, v in values.items()}


WHEEL_RIG = parse_system(WHEEL_RIG_SYSTEM, {}, {})
"""The wheel rig scenes' system, the FMUs with their own parameters."""
