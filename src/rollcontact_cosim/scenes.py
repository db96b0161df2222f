"""Co-simulation scenes: ``models/cosim/<scene>.toml`` -> :class:`CosimScene` (format in ``models/cosim/README.md``).

A scene couples one ``WheelRig`` host FMU and one ``RollingContact2D`` contact FMU (instance names equal to the
model names) through :data:`CONNECTIONS` and says how long, with which macro step and master algorithm to run,
which variables to record and how closely a rerun must follow the reference result.  Names are checked against
the models behind the FMUs (:class:`~rollcontact_cosim.wheel_rig.WheelRigParameters`,
:class:`rollcontact.stepping.line.parameters.ContactParameters` and their outputs), so loading a scene needs no FMU;
values are checked by constructing those parameter objects.
"""

from __future__ import annotations

import dataclasses
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

from rollcontact.stepping import ContactParameters, ModelError, StepOutputs
from rollcontact_cosim.wheel_rig import INPUT_NAMES, WheelRigError, WheelRigOutputs, WheelRigParameters

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["ALGORITHMS", "CONNECTIONS", "CONTACT", "COSIM_DIR", "DEFAULT_SCENE", "HOST", "SCENE_NAMES", "Band",
           "CosimScene", "CosimSceneError", "load_cosim_scene"]

HOST = "WheelRig"
"""Model and instance name of the host FMU."""
CONTACT = "RollingContact2D"
"""Model and instance name of the contact FMU."""

CONNECTIONS = (
    (f"{HOST}.normal_load", f"{CONTACT}.normal_load"),
    (f"{HOST}.creep", f"{CONTACT}.creep"),
    (f"{HOST}.velocity", f"{CONTACT}.velocity"),
    (f"{CONTACT}.tangential_force", f"{HOST}.tangential_force"),
    (f"{CONTACT}.creep_stiffness", f"{HOST}.creep_stiffness"),
)
"""(source output, target input) of every connection, for every master."""

ALGORITHMS = ("gauss-seidel", "jacobi")
"""Master algorithms: Gauss-Seidel steps the contact first and hands its force to the host in the same macro step;
Jacobi steps both from the previous outputs (libcosim's fixed-step algorithm)."""

FORCE_LAG = {"gauss-seidel": 0, "jacobi": 1}
"""WheelRig ``force_lag`` that matches each algorithm (the contact's force is evaluated at the host's creep of
the current, resp. the previous, communication point)."""

COSIM_DIR = Path(__file__).resolve().parents[2] / "models" / "cosim"
"""Folder of the scene files and reference results (the repository's ``models/cosim``)."""

SCENE_NAMES = ("traction_ramp", "corrugated_rail", "oscillating_torque", "carter_sanity")
DEFAULT_SCENE = "traction_ramp"

VARIABLES = {
    HOST: {"outputs": WheelRigOutputs._fields, "inputs": INPUT_NAMES,
           "parameters": {f.name: f.default for f in dataclasses.fields(WheelRigParameters)}},
    CONTACT: {"outputs": StepOutputs._fields, "inputs": ("normal_load", "creep", "velocity"),
              "parameters": {f.name: f.default for f in dataclasses.fields(ContactParameters)}},
}
"""Per FMU: output, input and parameter names (parameters with their default, whose type is the FMU type)."""

SECTIONS = {"description", "run", "host", "contact", "reference"}
RUN_KEYS = {"start_time", "stop_time", "step_size", "algorithm", "outputs"}
REFERENCE_KEYS = {"variables", "band_height", "band_width", "samples", "max_outliers", "stride"}


class CosimSceneError(ValueError):
    """A scene file that cannot be used; the message names the file, the key, the value and the limit."""


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
    host, contact : Mapping
        WheelRig and RollingContact2D parameter name -> value (read-only); unlisted ones keep the FMU's start value.
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
    host: MappingProxyType = field(repr=False)
    contact: MappingProxyType = field(repr=False)
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
        """WheelRig start values for ``algorithm`` (the scene's when None).

        ``force_lag`` is set to :data:`FORCE_LAG` of the algorithm unless the scene sets it: the linearly implicit
        coupling needs the creep at which the contact evaluated its force, which depends on the master.
        """
        algorithm = self.algorithm if algorithm is None else check_algorithm(algorithm)
        values = dict(self.host)
        values.setdefault("force_lag", FORCE_LAG[algorithm])
        return values

    def contact_parameters(self) -> dict[str, Any]:
        """RollingContact2D start values."""
        return dict(self.contact)


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
        Unreadable file, unknown section or key, a parameter or variable name the FMUs do not have (the message
        lists the valid ones), a value of the wrong type or out of range, or a run that is not a whole number of
        macro steps.
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
    run = table(data, "run")
    unknown(run, RUN_KEYS, "[run] key")
    start = real(run, "start_time", 0.0, "run")
    stop = real(run, "stop_time", None, "run")
    step = real(run, "step_size", None, "run")
    macro_steps(start, stop, step)
    algorithm = run.get("algorithm", "gauss-seidel")
    check_algorithm(algorithm)
    outputs = names(run, "outputs", "run")
    if not outputs:
        raise CosimSceneError("[run] outputs must list at least one variable")
    for name in outputs:
        check_variable(name, "[run] outputs")
    host = parameters(table(data, "host"), HOST)
    contact = parameters(table(data, "contact"), CONTACT)
    try:
        WheelRigParameters(**host)
    except WheelRigError as exc:
        raise CosimSceneError(f"[host]: {exc}") from None
    try:
        ContactParameters(**contact)
    except ModelError as exc:
        raise CosimSceneError(f"[contact]: {exc}") from None
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
    steps = macro_steps(start, stop, step)
    if band.stride < 1 or steps % band.stride:
        raise CosimSceneError(f"[reference] stride = {band.stride!r} must be an integer >= 1 dividing the "
                              f"{steps} macro steps")
    return CosimScene(path.stem, path, description, start, stop, step, algorithm, outputs,
                      MappingProxyType(host), MappingProxyType(contact), band)


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


def check_variable(name: str, where: str) -> None:
    """``name`` must be ``"<instance>.<output>"`` of one of the two FMUs."""
    instance, _, variable = name.partition(".")
    if instance not in VARIABLES:
        raise CosimSceneError(f"{where}: {name!r} must be '<instance>.<output>' with instance {HOST} or {CONTACT}")
    outputs = VARIABLES[instance]["outputs"]
    if variable not in outputs:
        raise CosimSceneError(f"{where}: {instance} has no output {variable!r} (outputs: {', '.join(outputs)})")


def parameters(values: dict, instance: str) -> dict[str, Any]:
    """The parameter table of ``instance``, names and types checked against the FMU's parameters."""
    known = VARIABLES[instance]["parameters"]
    section = "host" if instance == HOST else "contact"
    for name, value in values.items():
        if name not in known:
            raise CosimSceneError(f"[{section}] {instance} has no parameter {name!r} (parameters: "
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
