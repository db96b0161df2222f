"""The RollingContact2D FMU's slave class (FMI 2.0 co-simulation): maps FMU variables to rollcontact.

The FMU's entry module ``rollcontact_fmu_slave.py`` only imports :class:`RollingContact2D` from here (pythonfmu
re-executes the entry module on every instantiation: see its docstring).  No physics here: the parameters become a
:class:`rollcontact.stepping.ContactParameters`, each ``do_step`` is one
:meth:`rollcontact.stepping.ContactModel.step`, and the output variables read the step's
:class:`rollcontact.stepping.StepOutputs` by position.  The variables are declared in the single table
:data:`VARIABLES` (value references follow its order: append, never reorder; outputs in StepOutputs' order).

* Bad inputs or parameters, and scenes no allowed method solves, are logged (status Discard) and answered with
  ``do_step`` returning False (fmi2Discard); no exception reaches pythonfmu (it would become fmi2Fatal).  What
  FMI 2 answers with fmi2Error is emulated (``rollcontact_fmu_xml`` module docstring).
* The FMU state (``canGetAndSetFMUstate``, ``canSerializeFMUstate``) holds every input and parameter, the outputs
  and the model's :class:`rollcontact.stepping.ModelState` as a JSON-compatible dict; a state handed back is
  checked completely (:meth:`ModelState.parse`) before anything changes.
* ``scene_file`` must name a regular file of at most :data:`SCENE_SIZE_LIMIT` bytes that is UTF-8 TOML with only
  scene tables (:func:`checked_scene_file`): a device or FIFO would block initialisation, and the log must not
  echo the content of a file that is not a scene.
* The ``rollcontact`` package is bundled in ``resources/``; a host process that imported ``rollcontact`` before
  loading the FMU uses its own copy instead (Python caches modules per process).
"""

from __future__ import annotations

import os
import re
import stat
from pathlib import Path

from pythonfmu import Fmi2Causality, Fmi2Variability, Integer, Real, String
from pythonfmu.default_experiment import DefaultExperiment
from rollcontact_fmu_xml import TableSlave

from rollcontact import __version__ as ROLLCONTACT_VERSION
from rollcontact.scene import Scene, scene_toml
from rollcontact.stepping import STATIONARY, ContactModel, ContactParameters, ModelError, ModelState

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

INPUT, OUTPUT, PARAMETER = Fmi2Causality.input, Fmi2Causality.output, Fmi2Causality.parameter
CONTINUOUS, DISCRETE, FIXED = Fmi2Variability.continuous, Fmi2Variability.discrete, Fmi2Variability.fixed
DEFAULT = ContactParameters()

# name, type, causality, variability, unit, start, min, max, description.  Append only: the value reference of a
# variable is its row number (from 0).
VARIABLES = (
    ("normal_load", Real, INPUT, CONTINUOUS, "N", 0.0, 0.0, None,
     "Normal load N pressing the wheel onto the surface (0: no contact)"),
    ("creep", Real, INPUT, CONTINUOUS, "1", 0.0, None, None,
     "Longitudinal creep xi (rigid slip velocity over V); xi > 0 gives a positive tangential force"),
    ("velocity", Real, INPUT, CONTINUOUS, "m/s", 0.0, 0.0, None,
     "Rolling speed V; the wheel axis advances by the integral of V"),
    ("tangential_force", Real, OUTPUT, CONTINUOUS, "N", 0.0, None, None,
     "Tangential (creep) force T over the contact width, the sign of the creep in steady rolling"),
    ("traction_coefficient", Real, OUTPUT, CONTINUOUS, "1", 0.0, None, None,
     "Traction coefficient T/N (0 without load)"),
    ("contact_half_width", Real, OUTPUT, CONTINUOUS, "m", 0.0, 0.0, None,
     "Half-width a of the contact patch in the rolling direction"),
    ("stick_half_width", Real, OUTPUT, CONTINUOUS, "m", 0.0, 0.0, None,
     "Half-width a* of the stick zone at the leading edge (0 in full slip)"),
    ("contact_offset", Real, OUTPUT, CONTINUOUS, "m", 0.0, None, None,
     "Contact centre minus wheel axis position, positive ahead of the axis"),
    ("max_pressure", Real, OUTPUT, CONTINUOUS, "Pa", 0.0, 0.0, None,
     "Peak contact pressure"),
    ("frictional_power", Real, OUTPUT, CONTINUOUS, "W", 0.0, 0.0, None,
     "Power dissipated by slip, V xi T (the integral of q V s over the patch)"),
    ("creep_stiffness", Real, OUTPUT, CONTINUOUS, "N", 0.0, 0.0, None,
     "Creep stiffness dT/dxi at the current state"),
    ("stationarity", Real, OUTPUT, CONTINUOUS, "1", STATIONARY, 0.0, STATIONARY,
     "Wavelength of the fastest input variation over a (1e9: inputs constant or no contact)"),
    ("method_used", Integer, OUTPUT, DISCRETE, None, 0, 0, 5,
     "Method of the last step: 1 closed form, 2 polynomial, 3 discretised, 4 instationary relaxation (lag around "
     "Carter), 5 instationary discretised transient, 0 none (no contact)"),
    ("axis_position", Real, OUTPUT, CONTINUOUS, "m", DEFAULT.initial_position, None, None,
     "Wheel axis position X at which the contact was evaluated"),
    ("youngs_modulus", Real, PARAMETER, FIXED, "Pa", DEFAULT.youngs_modulus, 0.0, None,
     "Young's modulus E of wheel and surface (quasi-identical bodies), > 0"),
    ("poisson_ratio", Real, PARAMETER, FIXED, "1", DEFAULT.poisson_ratio, 0.0, 0.5,
     "Poisson's ratio nu of wheel and surface, 0 <= nu < 0.5"),
    ("radius", Real, PARAMETER, FIXED, "m", DEFAULT.radius, 0.0, None,
     "Effective wheel radius R (1/R = 1/R1 + 1/R2), > 0"),
    ("contact_width", Real, PARAMETER, FIXED, "m", DEFAULT.contact_width, 0.0, None,
     "Lateral length b of the line contact, > 0; per-length quantities are force / b"),
    ("friction_coefficient", Real, PARAMETER, FIXED, "1", DEFAULT.friction_coefficient, 0.0, None,
     "Friction coefficient mu at zero slip velocity, > 0"),
    ("friction_law", Integer, PARAMETER, FIXED, None, DEFAULT.friction_law, 0, 1,
     "Friction law: 0 Coulomb, 1 exponential falling mu [(1 - A) exp(-B v) + A]"),
    ("friction_kinetic_ratio", Real, PARAMETER, FIXED, "1", DEFAULT.friction_kinetic_ratio, 0.0, 1.0,
     "A of the exponential falling law: mu(infinity)/mu, 0 < A <= 1"),
    ("friction_decay", Real, PARAMETER, FIXED, "s/m", DEFAULT.friction_decay, 0.0, None,
     "B of the exponential falling law (slip velocity v in m/s), >= 0"),
    ("corrugation_wavelength", Real, PARAMETER, FIXED, "m", DEFAULT.corrugation_wavelength, 0.0, None,
     "Wavelength of the surface corrugation Z = amplitude cos(2 pi X / wavelength + phase), > 0"),
    ("corrugation_amplitude", Real, PARAMETER, FIXED, "m", DEFAULT.corrugation_amplitude, 0.0, None,
     "Amplitude of the surface corrugation (0: smooth surface)"),
    ("corrugation_phase", Real, PARAMETER, FIXED, "rad", DEFAULT.corrugation_phase, None, None,
     "Phase of the surface corrugation at X = 0"),
    ("initial_position", Real, PARAMETER, FIXED, "m", DEFAULT.initial_position, None, None,
     "Wheel axis position X at the start time"),
    ("scene_file", String, PARAMETER, FIXED, None, DEFAULT.scene_file, None, None,
     "TOML scene (rollcontact.load_scene) whose material, radius, friction and surface replace the scalar "
     "parameters; relative paths are taken from the FMU's resources folder; empty: unused"),
    ("method", Integer, PARAMETER, FIXED, None, DEFAULT.method, 0, 3,
     "Method: 0 auto (cheapest the scene needs), 1 closed form, 2 polynomial, 3 discretised"),
    ("tolerance", Real, PARAMETER, FIXED, "1", DEFAULT.tolerance, 0.0, None,
     "Requested relative error of T and p0: each method runs with its cheapest setting that meets it; with "
     "transient = 1 also the error of T (of mu N) tolerated before the instationary model takes over: the "
     "relaxation lag while its error bound for the creep swing meets it, else the discretised transient with the "
     "elements the tolerance needs (0: defaults, the relaxation lag, whose error grows with the creep swing)"),
    ("polynomial_order", Integer, PARAMETER, FIXED, None, DEFAULT.polynomial_order, 0, None,
     "Order of the polynomial method (0: chosen from the tolerance)"),
    ("elements", Integer, PARAMETER, FIXED, None, DEFAULT.elements, 0, None,
     "Number of elements of the discretised method (0: the method's default; for the discretised transient a "
     "pair of nested grids extrapolated, chosen from the tolerance; > 0: one grid of this many)"),
    ("transient", Integer, PARAMETER, FIXED, None, DEFAULT.transient, 0, 2,
     "Transient rolling (flat surface, Coulomb friction): 0 quasi-static, 1 auto (while the stationarity measure "
     "is below its threshold: the relaxation model for tolerance 0 or >= 0.21 (its measured error bound), else the "
     "relaxation model while its bound for the creep swing meets the tolerance and the discretised transient "
     "where it does not; the discretised transient with method 3), 2 always (relaxation; discretised transient "
     "with method 3)"),
    ("datum", Real, PARAMETER, FIXED, "m", DEFAULT.datum, 0.0, None,
     "Datum distance L of instationary rolling (creep control depends on it; 0: the effective radius)"),
    ("step_budget", Real, PARAMETER, FIXED, "s", DEFAULT.step_budget, 0.0, None,
     "Work budget of one step by the methods' cost models (modelled seconds): the steady solve runs the most "
     "accurate setting that meets the tolerance within it, the discretised transient at most the substeps that "
     "fit; where that costs accuracy the log says so once (status Warning).  0: no budget"),
)


SCENE_SIZE_LIMIT = 1 << 20
"""Largest scene file read [bytes] (a scene is a small TOML file)."""

SCENE_TABLES = frozenset(tomllib.loads(scene_toml(Scene(normal_load_per_length=1.0))))
"""Top-level tables of a scene file (those :func:`rollcontact.scene_toml` writes)."""

KINDS = {stat.S_IFCHR: "a character device", stat.S_IFBLK: "a block device", stat.S_IFIFO: "a FIFO",
         stat.S_IFSOCK: "a socket", stat.S_IFDIR: "a directory"}


def checked_scene_file(path: str) -> None:
    """Raise ModelError unless ``path`` can be a scene: a regular file of at most :data:`SCENE_SIZE_LIMIT` bytes,
    UTF-8 TOML whose top-level tables are scene tables.

    Nothing of the file's content enters the message (only its kind, size or the line of a syntax error): the
    path may name any file the host user can read.  A path that cannot be examined is left to
    :func:`rollcontact.load_scene`, whose message names it.  A file that passes is a scene, and the library's
    messages about its keys and values are shown.
    """
    try:
        info = os.stat(path)
    except OSError:
        return
    kind = KINDS.get(stat.S_IFMT(info.st_mode), "not a regular file")
    if not stat.S_ISREG(info.st_mode):
        raise ModelError(f"scene_file {path!r} is {kind}, not a regular file: a scene is a TOML file")
    if info.st_size > SCENE_SIZE_LIMIT:
        raise ModelError(f"scene_file {path!r} has {info.st_size} bytes, more than a scene's limit of "
                         f"{SCENE_SIZE_LIMIT} bytes")
    try:
        with open(path, "rb") as fh:
            data = fh.read(SCENE_SIZE_LIMIT + 1)
    except OSError:
        return
    if len(data) > SCENE_SIZE_LIMIT:
        raise ModelError(f"scene_file {path!r} has more than a scene's limit of {SCENE_SIZE_LIMIT} bytes")
    try:
        tables = tomllib.loads(data.decode("utf-8"))
    except UnicodeDecodeError:
        raise ModelError(f"scene_file {path!r} is not a scene: it is not UTF-8 text") from None
    except tomllib.TOMLDecodeError as exc:
        where = re.search(r"\(at line \d+, column \d+\)|\(at end of document\)", str(exc))
        raise ModelError(f"scene_file {path!r} is not a scene: a TOML syntax error "
                         f"{where.group(0) if where else ''}") from None
    if not set(tables) <= SCENE_TABLES:
        raise ModelError(f"scene_file {path!r} is not a scene: its top-level keys are not all scene tables "
                         f"{sorted(SCENE_TABLES)}")


class RollingContact2D(TableSlave):
    """2D wheel/rail rolling contact (Hertz/Carter, polynomial and discretised methods of rollcontact)."""

    author = "rollcontact"
    description = ("Quasi-steady 2D rolling contact of a wheel on a smooth or corrugated surface: tangential force, "
                   "contact geometry and frictional power from normal load, creep and rolling speed")
    license = "MIT"
    version = ROLLCONTACT_VERSION
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=1.0, step_size=1e-3)
    VARIABLES = VARIABLES

    def new_model(self, values: dict):
        """A ContactModel and its notices; a relative ``scene_file`` is taken from the resources folder."""
        if values["scene_file"] and isinstance(values["scene_file"], str):
            if self.resources:
                values["scene_file"] = str(Path(self.resources, values["scene_file"]))
            checked_scene_file(values["scene_file"])
        model = ContactModel(ContactParameters(**values), start_time=self.start_time)
        return model, model.notices

    def step_model(self, current_time, step_size):
        return self.model.step(current_time, step_size, self.normal_load, self.creep, self.velocity)

    def step_messages(self):
        return self.model.take_messages()

    def parse_model_state(self, data):
        return ModelState.parse(data)
