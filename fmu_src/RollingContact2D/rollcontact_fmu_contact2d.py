"""The RollingContact2D FMU's slave: :class:`RollingContact2DShared` maps the FMU's variables to rollcontact's line
contact, in both FMI versions; :func:`slave_class` gives the class of each variant (one contact or several, with
enumerations or integer codes, FMI 3.0 arrays).

No physics here: the parameters become a :class:`rollcontact.stepping.ContactParameters`, each ``do_step`` is one
:meth:`rollcontact.stepping.ContactModel.step` (several contacts: one
:meth:`rollcontact.stepping.ContactModels.step`), and the output variables read the step's
:class:`rollcontact.stepping.StepOutputs` by position.  The variables are declared in one table (:func:`table`;
value references follow its order: append, never reorder; outputs in StepOutputs' order), the enumerations derived
from the solver's tables (:func:`enumerations`).  Refusals, the emulated fmi2Error, the echo of refusals and the
FMU state are the shared :class:`rollcontact_fmu.slave.TableSlave`'s.

``scene_file`` must name a regular file of at most :data:`SCENE_SIZE_LIMIT` bytes that is UTF-8 TOML with only
scene tables (:func:`checked_scene_file`): a device or FIFO would block initialisation, and the log must not echo the
content of a file that is not a scene.
"""

from __future__ import annotations

import math
import os
import re
import stat
from functools import cache
from pathlib import Path

from pythonfmu import Integer, Real, String
from pythonfmu.default_experiment import DefaultExperiment
from rollcontact_fmu.contacts import contact_text, contact_values, contacts_step, variant_class, variant_name
from rollcontact_fmu.enumerations import (
    RAIL_CONDITION_TEXT,
    friction_law_items,
    integer_coded,
    largest,
    method_items,
    method_used_items,
    rail_condition_items,
)
from rollcontact_fmu.slave import CONTINUOUS, DISCRETE, FIXED, INPUT, OUTPUT, PARAMETER, POSITIVE, TableSlave

import rollcontact.stepping.line.parameters as line
from rollcontact import Scene, scene_toml
from rollcontact import __version__ as ROLLCONTACT_VERSION
from rollcontact.stepping import ContactModel, ContactModels, ContactParameters, ModelError, ModelState
from rollcontact.stepping.line.contacts import ContactsState

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

MODEL = "RollingContact2D"
DEFAULT = ContactParameters()
STATIONARY = line.STATIONARY

TRANSIENT_ITEMS = ((0, "quasi_static", "every step steady"),
                   (1, "auto", "instationary while the inputs vary fast"),
                   (2, "always", "every loaded step instationary"))
TABLE_ITEMS = ((0, "auto", "built when the run pays for it, within the step budget"),
               (1, "off", "every step solves exactly"),
               (2, "on", "built at the first loaded step"))
AUTO_TEXT = "the cheapest method the scene needs"
"""Description of ``method`` = auto."""


def enumerations() -> dict:
    """The Integer variables declared as FMI enumerations: variable -> (type, items (value, name, description));
    ``method`` and ``method_used`` from :data:`rollcontact.stepping.line.parameters.METHOD_LEVELS` as it is now.

    ``build_fmu.py --integer-codes`` builds the FMU with plain Integer variables instead (their codes in the
    descriptions), for hosts that do not support FMI enumerations: libcosim does not list them, so it could neither
    set nor observe these variables (``rollcontact_cosim.osp`` uses that build)."""
    return {"method": ("Method", method_items(line.METHOD_LEVELS, AUTO_TEXT)),
            "friction_law": ("FrictionLaw", friction_law_items()),
            "rail_condition": ("RailCondition", rail_condition_items()),
            "transient": ("TransientMode", TRANSIENT_ITEMS),
            "method_used": ("MethodUsed", method_used_items(line.METHOD_LEVELS)),
            "table": ("TableMode", TABLE_ITEMS)}


def table() -> tuple:
    """The single-contact FMU's variable table: rows ``(name, type, causality, variability, unit, start, min, max,
    description)``, each description one line of at most 100 characters (docs/fmu.md's table is written from it by
    ``build_fmu.py --docs``).  Append only: the value reference of a variable is its row number (from 0)."""
    used = enumerations()
    return (
        ("normal_load", Real, INPUT, CONTINUOUS, "N", 0.0, 0.0, None,
         "Normal load N pressing the wheel onto the surface (0: no contact)"),
        ("creep", Real, INPUT, CONTINUOUS, "1", 0.0, None, None,
         "Longitudinal creep xi, rigid slip velocity over V (xi > 0 gives T > 0)"),
        ("velocity", Real, INPUT, CONTINUOUS, "m/s", 0.0, 0.0, None,
         "Rolling speed V; the wheel axis advances by its integral"),
        ("tangential_force", Real, OUTPUT, CONTINUOUS, "N", 0.0, None, None,
         "Tangential (creep) force T over the contact width, |T| <= mu N"),
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
        ("frictional_power", Real, OUTPUT, CONTINUOUS, "W", 0.0, None, None,
         "Power V xi T the creep puts into the contact (dissipated by slip in steady rolling)"),
        ("creep_stiffness", Real, OUTPUT, CONTINUOUS, "N", 0.0, None, None,
         "Creep stiffness dT/dxi at the current state (negative past a falling-friction peak)"),
        ("stationarity", Real, OUTPUT, CONTINUOUS, "1", STATIONARY, 0.0, STATIONARY,
         "Wavelength of the fastest input variation over a (1e9: inputs constant or no contact)"),
        ("method_used", Integer, OUTPUT, DISCRETE, None, 0, 0, largest(used["method_used"][1]),
         "Method of the last step (MethodUsed)"),
        ("axis_position", Real, OUTPUT, CONTINUOUS, "m", DEFAULT.initial_position, None, None,
         "Wheel axis position X at which the contact was evaluated"),
        ("youngs_modulus", Real, PARAMETER, FIXED, "Pa", DEFAULT.youngs_modulus, POSITIVE, None,
         "Young's modulus E of wheel and surface (quasi-identical bodies), > 0"),
        ("poisson_ratio", Real, PARAMETER, FIXED, "1", DEFAULT.poisson_ratio, 0.0, math.nextafter(0.5, 0.0),
         "Poisson's ratio nu of wheel and surface, 0 <= nu < 0.5"),
        ("radius", Real, PARAMETER, FIXED, "m", DEFAULT.radius, POSITIVE, None,
         "Effective radius R (1/R = 1/R1 + 1/R2), > 0"),
        ("contact_width", Real, PARAMETER, FIXED, "m", DEFAULT.contact_width, POSITIVE, None,
         "Lateral length b of the line contact, > 0; per-length quantities are force / b"),
        ("friction_coefficient", Real, PARAMETER, FIXED, "1", DEFAULT.friction_coefficient, POSITIVE, None,
         "Friction coefficient mu at zero slip velocity, > 0"),
        ("friction_law", Integer, PARAMETER, FIXED, None, DEFAULT.friction_law, 0, largest(used["friction_law"][1]),
         "Friction law (FrictionLaw)"),
        ("friction_kinetic_ratio", Real, PARAMETER, FIXED, "1", DEFAULT.friction_kinetic_ratio, POSITIVE, 1.0,
         "A of the falling laws: mu(infinity)/mu, 0 < A <= 1 (FrictionLaw)"),
        ("friction_decay", Real, PARAMETER, FIXED, "s/m", DEFAULT.friction_decay, 0.0, None,
         "B of the exponential law, per slip velocity v, >= 0"),
        ("corrugation_wavelength", Real, PARAMETER, FIXED, "m", DEFAULT.corrugation_wavelength, POSITIVE, None,
         "Wavelength of the corrugation Z = amplitude cos(2 pi X / wavelength + phase), > 0"),
        ("corrugation_amplitude", Real, PARAMETER, FIXED, "m", DEFAULT.corrugation_amplitude, 0.0, None,
         "Amplitude of the corrugation (0: smooth surface)"),
        ("corrugation_phase", Real, PARAMETER, FIXED, "rad", DEFAULT.corrugation_phase, None, None,
         "Phase of the corrugation at X = 0"),
        ("initial_position", Real, PARAMETER, FIXED, "m", DEFAULT.initial_position, None, None,
         "Wheel axis position X at the start time"),
        ("scene_file", String, PARAMETER, FIXED, None, DEFAULT.scene_file, None, None,
         "TOML scene replacing material, radius, friction and surface (empty: unused)"),
        ("method", Integer, PARAMETER, FIXED, None, DEFAULT.method, 0, largest(used["method"][1]),
         "Method of the steady steps (Method)"),
        ("tolerance", Real, PARAMETER, FIXED, "1", DEFAULT.tolerance, 0.0, None,
         "Requested relative error of T and p0 (0: each method's defaults)"),
        ("polynomial_order", Integer, PARAMETER, FIXED, None, DEFAULT.polynomial_order, 0, None,
         "Order of the polynomial method (0: chosen by the method)"),
        ("elements", Integer, PARAMETER, FIXED, None, DEFAULT.elements, 0, None,
         "Elements of the discretised method and transient (0: chosen by the method)"),
        ("transient", Integer, PARAMETER, FIXED, None, DEFAULT.transient, 0, largest(TRANSIENT_ITEMS),
         "Instationary rolling (TransientMode); flat surface and Coulomb friction only"),
        ("datum", Real, PARAMETER, FIXED, "m", DEFAULT.datum, 0.0, None,
         "Datum distance L of instationary rolling (0: the radius R)"),
        ("step_budget", Real, PARAMETER, FIXED, "s", DEFAULT.step_budget, 0.0, None,
         "Work budget of one step, modelled seconds (0: no budget)"),
        ("table", Integer, PARAMETER, FIXED, None, DEFAULT.table, 0, largest(TABLE_ITEMS),
         "Certified table of falling friction or a one-harmonic corrugation (TableMode)"),
        ("friction_reference_velocity", Real, PARAMETER, FIXED, "m/s", DEFAULT.friction_reference_velocity, POSITIVE,
         None, "v_ref of the rational law A mu + (1 - A) mu / (1 + v / v_ref), > 0"),
        ("friction_slope", Real, PARAMETER, FIXED, "s/m", DEFAULT.friction_slope, 0.0, None,
         "c of the linear law max(A mu, mu - c v), >= 0"),
        ("friction_table", String, PARAMETER, FIXED, None, DEFAULT.friction_table, None, None,
         "Points 'v mu; v mu; ...' of the tabulated law, v [m/s] increasing, e.g. '0 0.3; 1 0.25; 5 0.12'"),
        ("rail_condition", Integer, PARAMETER, FIXED, None, DEFAULT.rail_condition, 0,
         largest(used["rail_condition"][1]), RAIL_CONDITION_TEXT),
    )


CONTACT_PARAMETERS = ("radius", "contact_width", "initial_position")
"""Parameters of their own per contact in an FMU of several contacts (the wheels' geometry and their places along
the track); the others are shared."""


def declaration(contacts: int = 1, integer_codes: bool = False, arrays: bool = False) -> tuple[tuple, dict]:
    """The variable table and enumerations of the FMU with ``contacts`` contacts: with several, every input and
    output of :func:`table` once per contact, named ``name[k]`` (k from 1; inputs of every contact first, then the
    outputs), the parameters shared but those of :data:`CONTACT_PARAMETERS`, which follow once per contact; with
    ``arrays`` (FMI 3.0) each of those is one array variable of :func:`dimensions` in the same order (the inputs, the
    outputs, the shared parameters, the per-contact ones); with ``integer_codes`` plain Integer variables."""
    single, enumerated = table(), enumerations()
    if contacts == 1:
        rows = single
    elif arrays:
        sized = dimensions(contacts, arrays)
        rows = tuple((*row[:8], contact_text(row[8], None)) if row[0] in sized else row
                     for row in sorted(single, key=lambda row: row[0] in CONTACT_PARAMETERS))
    else:
        per_contact = [row for row in single if row[2] is not PARAMETER]
        rows = tuple((f"{row[0]}[{k}]", *row[1:8], contact_text(row[8], k))
                     for causality in (INPUT, OUTPUT) for k in range(1, contacts + 1)
                     for row in per_contact if row[2] is causality) + tuple(
            row for row in single if row[2] is PARAMETER and row[0] not in CONTACT_PARAMETERS) + tuple(
            (f"{row[0]}[{k}]", *row[1:8], contact_text(row[8], k)) for row in single
            if row[0] in CONTACT_PARAMETERS for k in range(1, contacts + 1))
    if contacts > 1:  # in the order of the variables
        enumerated = {row[0]: enumerated[row[0].split("[")[0]] for row in rows if row[0].split("[")[0] in enumerated}
    if integer_codes:
        return integer_coded(rows, enumerated), {}
    return rows, enumerated


def dimensions(contacts: int, arrays: bool) -> dict:
    """The array variables of the FMI 3.0 FMU with ``contacts`` contacts (inputs, outputs and
    :data:`CONTACT_PARAMETERS`) -> ``contacts``; none with one contact or without ``arrays``."""
    if not arrays or contacts == 1:
        return {}
    return {row[0]: contacts for row in table() if row[2] is not PARAMETER or row[0] in CONTACT_PARAMETERS}


SCENE_SIZE_LIMIT = 1 << 20
"""Largest scene file read [bytes] (a scene is a small TOML file)."""

SCENE_TABLES = frozenset(tomllib.loads(scene_toml(Scene(normal_load_per_length=1.0))))
"""Top-level tables of a scene file (those :func:`rollcontact.scene_toml` writes)."""

KINDS = {stat.S_IFCHR: "a character device", stat.S_IFBLK: "a block device", stat.S_IFIFO: "a FIFO",
         stat.S_IFSOCK: "a socket", stat.S_IFDIR: "a directory"}


def resolved_scene_file(path: str, resources: str | None) -> str:
    """The scene file a ``scene_file`` parameter names: the path itself when absolute, else the first that exists
    of the path relative to the FMU's ``resources`` folder and to the current working directory.

    Raises
    ------
    ModelError
        None of them exists; the message names every path tried.
    """
    given = Path(path)
    tried = [given] if given.is_absolute() else [*([Path(resources, path)] if resources else []), Path.cwd() / path]
    found = next((candidate for candidate in tried if candidate.exists()), None)
    if found is None:
        raise ModelError(f"scene_file {path!r} was not found; tried " + ", ".join(str(c) for c in tried))
    return str(found)


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


class RollingContact2DShared(TableSlave):
    """2D wheel/rail rolling contact (Hertz/Carter, polynomial and discretised methods of rollcontact): the slave
    logic of both FMI versions."""

    description = ("2D rolling contact of a wheel on a smooth or corrugated surface, steady or instationary: "
                   "tangential force, contact geometry and frictional power from normal load, creep and speed")
    version = ROLLCONTACT_VERSION
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=1.0, step_size=1e-3)

    def scene_values(self, values: dict) -> dict:
        """``values`` with a relative ``scene_file`` resolved (the resources folder first) and checked to be a scene
        (:func:`checked_scene_file`)."""
        if values["scene_file"] and isinstance(values["scene_file"], str):
            values["scene_file"] = resolved_scene_file(values["scene_file"], self.resources)
            checked_scene_file(values["scene_file"])
        return values

    def new_model(self, values: dict):
        """A ContactModel and its notices."""
        values = self.scene_values(values)
        model = ContactModel(ContactParameters(**values), start_time=self.start_time, stop_time=self.stop_time)
        return model, model.notices

    def step_model(self, current_time, step_size):
        return self.model.step(current_time, step_size, self.normal_load, self.creep, self.velocity)

    def step_messages(self):
        return self.model.take_messages()

    def parse_model_state(self, data):
        return ModelState.parse(data)


class RollingContact2DContacts(RollingContact2DShared):
    """Several 2D contacts of one parameter set in one instance (:class:`rollcontact.stepping.ContactModels`;
    :func:`slave_class` sets the table)."""

    def new_model(self, values: dict):
        values = self.scene_values(values)
        n = self.CONTACTS
        per_contact = {name: contact_values(values, name, n, self.DIMENSIONS) for name in CONTACT_PARAMETERS}
        shared = {name: value for name, value in values.items() if name.split("[")[0] not in CONTACT_PARAMETERS}
        model = ContactModels(ContactParameters(**shared), n, start_time=self.start_time, stop_time=self.stop_time,
                              per_contact=per_contact)
        return model, model.notices

    def step_model(self, current_time, step_size):
        return contacts_step(self.model.step, current_time, step_size, self.read_inputs(self), 3,
                             bool(self.DIMENSIONS))

    def parse_model_state(self, data):
        return ContactsState.parse(data, self.CONTACTS)


@cache
def slave_class(contacts: int = 1, integer_codes: bool = False, arrays: bool = False) -> type:
    """The shared slave class of a variant (no FMI binding), one per variant and process (a host may load several):
    named ``RollingContact2D`` or ``RollingContact2D_n``, with the variant's table (integer codes: ``build_fmu.py
    --integer-codes``; ``arrays``: the per-contact variables as arrays, the FMI 3.0 build)."""
    base = RollingContact2DShared if contacts == 1 else RollingContact2DContacts
    return variant_class(base, variant_name(MODEL, contacts), contacts, declaration(contacts, integer_codes, arrays),
                         dimensions(contacts, arrays))
