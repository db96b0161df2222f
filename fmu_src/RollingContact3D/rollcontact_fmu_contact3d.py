"""The RollingContact3D FMU's slave: :class:`RollingContact3DShared` maps the FMU's variables to rollcontact's
elliptic stepping model, in both FMI versions; :func:`slave_class` gives the class of each variant.

No physics here: the parameters become a :class:`rollcontact.stepping.EllipticParameters`, each ``do_step`` is one
:meth:`rollcontact.stepping.EllipticModel.step` over every contact, and the output variables read its
:class:`rollcontact.stepping.EllipticOutputs` by position.  Refusals, the emulated fmi2Error, the echo of refusals
and the FMU state are the shared :class:`rollcontact_fmu.slave.TableSlave`'s.

One declaration for every variant: :func:`declaration` writes the variable table and the enumerations for n
contacts, with enumerations or integer codes (the method enumerations from
:data:`rollcontact.stepping.elliptic.parameters.METHOD_LEVELS`), and :func:`slave_class` gives the variant's class,
one per variant and process (a Python host may load several variants: this module is imported once).  With one
contact the variables are named ``normal_load`` ...; with n they are ``normal_load[1]`` ... ``normal_load[n]`` in FMI
2.0 (its array convention), and in FMI 3.0 (``arrays``) each per-contact variable is one array ``normal_load`` of n
values (``<Dimension start="n"/>``, the shared slave's ``DIMENSIONS``); shared parameters stay scalars.  Value
references of the single-contact table: append only.
"""

from __future__ import annotations

from functools import cache

from pythonfmu import Integer, Real
from pythonfmu.default_experiment import DefaultExperiment
from rollcontact_fmu.contacts import contact_text, contact_values, contacts_step, named, variant_class, variant_name
from rollcontact_fmu.enumerations import (
    RAIL_CONDITION_TEXT,
    friction_law_items,
    integer_coded,
    largest,
    method_items,
    method_used_items,
    rail_condition_items,
)
from rollcontact_fmu.parameters import material_friction_rows
from rollcontact_fmu.slave import CONTINUOUS, DISCRETE, FIXED, INPUT, OUTPUT, PARAMETER, POSITIVE, TableSlave

import rollcontact.stepping.elliptic.parameters as elliptic
from rollcontact import __version__ as ROLLCONTACT_VERSION
from rollcontact.stepping import EllipticModel, EllipticOutputs, EllipticParameters, EllipticState

MODEL = "RollingContact3D"
DEFAULT = EllipticParameters()

INPUT_ROWS = (
    ("normal_load", "N", 0.0, "Normal load Fn pressing the wheel onto the rail (0: no contact)"),
    ("longitudinal_creep", "1", None, "Longitudinal creepage xi (xi > 0 gives Fx > 0)"),
    ("lateral_creep", "1", None, "Lateral creepage eta (eta > 0 gives Fy > 0)"),
    ("spin", "1/m", None, "Spin creepage phi (phi > 0 gives Mz > 0)"),
    ("velocity", "m/s", 0.0, "Rolling speed V (falling friction, frictional power)"),
)
"""Inputs of a contact: name, unit, min, description (the stepping model's order)."""

GAP_ROWS = (
    ("gap_curvature_longitudinal", "1/m", 0.0,
     "Curvature A of the step's gap A x^2 + B y^2 (0: the parameter curvature_longitudinal)"),
    ("gap_curvature_lateral", "1/m", 0.0,
     "Curvature B of the step's gap A x^2 + B y^2 (0: the parameter curvature_lateral)"),
)
"""Inputs of a contact appended after every variable of the first release (value references: append only): the
gap's curvatures of each step, the stepping model's last two inputs."""

JACOBIAN_UNITS = {"xi": "N", "eta": "N", "phi": "N.m"}
OUTPUT_ROWS = (
    ("longitudinal_force", "N", None, "Longitudinal force Fx of the wheel on the rail"),
    ("lateral_force", "N", None, "Lateral force Fy of the wheel on the rail"),
    ("spin_moment", "N.m", None, "Spin moment Mz of the wheel on the rail about the contact normal"),
    ("semi_axis_longitudinal", "m", 0.0, "Semi-axis a of the contact ellipse along the rolling direction"),
    ("semi_axis_lateral", "m", 0.0, "Semi-axis b of the contact ellipse across it"),
    ("max_pressure", "Pa", 0.0, "Peak Hertz pressure p0"),
    ("stick_fraction", "1", -1.0, "Share of the contact area in stick (-1: not computed by the level)"),
    ("frictional_power", "W", None, "Power V (xi Fx + eta Fy + phi Mz) the creepages put into the contact"),
    *((f"d{force}_d{symbol}", {("N", "phi"): "N.m", ("N.m", "xi"): "N.m", ("N.m", "eta"): "N.m",
                               ("N.m", "phi"): "N.m2"}.get((unit, symbol), "N"), None,
       f"d{force}/d{symbol} at the step (parameter jacobian: linear theory's slope or difference)")
      for force, unit in (("Fx", "N"), ("Fy", "N"), ("Mz", "N.m")) for symbol in ("xi", "eta", "phi")),
    ("method_used", None, 0, "Elliptic level of the last step (MethodUsed3D)"),
)
"""Outputs of a contact: name, unit, min, description (:class:`EllipticOutputs`' order)."""

JACOBIAN_ITEMS = ((0, "linear", "the linear theory's slopes at the step's ellipse"),
                  (1, "difference", "forward differences of the step's level, 3 more solves; a table's derivatives"))
TABLE_ITEMS = ((0, "auto", "built when the run pays for it, within the step budget"),
               (1, "off", "every step solves exactly"),
               (2, "on", "built at initialisation"))
AUTO_TEXT = "the lowest-ranked level that applies; with a tolerance the cheapest"
"""Description of ``method`` = auto."""


def enumerations() -> dict:
    """The enumerations of the single-contact FMU (variable -> (type, items)); ``method`` and ``method_used`` from
    :data:`rollcontact.stepping.elliptic.parameters.METHOD_LEVELS` as it is now."""
    return {"method_used": ("MethodUsed3D", method_used_items(elliptic.METHOD_LEVELS)),
            "method": ("Method3D", method_items(elliptic.METHOD_LEVELS, AUTO_TEXT)),
            "friction_law": ("FrictionLaw", friction_law_items()),
            "rail_condition": ("RailCondition", rail_condition_items()),
            "jacobian": ("JacobianMode", JACOBIAN_ITEMS),
            "table": ("TableMode", TABLE_ITEMS)}


def shared_parameters(used: dict) -> tuple:
    """The parameters of every contact (name, type, unit, min, max, description) before the per-contact curvatures,
    the bounds of the enumerations ``used`` (:func:`enumerations`)."""
    return (
        *material_friction_rows(used),
        ("method", Integer, None, 0, largest(used["method"][1]), "Elliptic level of every step (Method3D)"),
        ("tolerance", Real, "1", 0.0, None, "Requested error of Fx, Fy over mu Fn and Mz over mu Fn c (0: defaults)"),
        ("step_budget", Real, "s", 0.0, None,
         "Work budget of each contact's solve, modelled seconds (0: no budget)"),
        ("jacobian", Integer, None, 0, largest(JACOBIAN_ITEMS), "How the dF_d outputs are computed (JacobianMode)"),
    )


CONTACT_PARAMETERS = (
    ("curvature_longitudinal", "1/m", "Curvature A of the gap A x^2 + B y^2 along x, > 0"),
    ("curvature_lateral", "1/m", "Curvature B of the gap A x^2 + B y^2 across, > 0"),
)


def appended_parameters(used: dict) -> tuple:
    """Shared parameters declared after the per-contact curvatures (value references: append only)."""
    return (("rail_condition", Integer, None, 0, largest(used["rail_condition"][1]), RAIL_CONDITION_TEXT),)


def table_parameters(used: dict) -> tuple:
    """Shared parameters declared after the gap's curvature inputs (value references: append only)."""
    return (("table", Integer, None, 0, largest(used["table"][1]),
             "Certified table of the strips, Coulomb friction (TableMode)"),)


def declaration(contacts: int = 1, integer_codes: bool = False, arrays: bool = False) -> tuple[tuple, dict]:
    """The variable table (rows ``(name, type, causality, variability, unit, start, min, max, description)``,
    value reference = row) and the enumerations (variable name -> (type, items)) of the FMU with ``contacts``
    contacts: inputs per contact, outputs per contact, shared parameters, per-contact curvatures.  With ``arrays``
    (FMI 3.0) every per-contact variable is one row, an array of :func:`dimensions`."""
    if arrays and contacts > 1:
        single, enumerated = declaration(1, integer_codes)
        return tuple((*row[:8], contact_text(row[8], None)) if row[0] in PER_CONTACT else row
                     for row in single), enumerated
    used = enumerations()
    of = (lambda k: "") if contacts == 1 else (lambda k: f", contact {k}")
    rows = []
    for k in range(1, contacts + 1):
        rows += [(named(n, k, contacts), Real, INPUT, CONTINUOUS, u, 0.0, lo, None, f"{text}{of(k)}")
                 for n, u, lo, text in INPUT_ROWS]
    for k in range(1, contacts + 1):
        for n, u, lo, text in OUTPUT_ROWS:
            if n == "method_used":
                rows.append((named(n, k, contacts), Integer, OUTPUT, DISCRETE, None, 0, 0,
                             largest(used["method_used"][1]), f"{text.split(' (')[0]}{of(k)} (MethodUsed3D)"))
            else:
                rows.append((named(n, k, contacts), Real, OUTPUT, CONTINUOUS, u, 0.0, lo, None, f"{text}{of(k)}"))
    for n, kind, u, lo, hi, text in shared_parameters(used):
        rows.append((n, kind, PARAMETER, FIXED, u, getattr(DEFAULT, n), lo, hi, text))
    for n, u, text in CONTACT_PARAMETERS:
        start = getattr(DEFAULT, n)[0]
        rows += [(named(n, k, contacts), Real, PARAMETER, FIXED, u, start, POSITIVE, None, f"{text}{of(k)}")
                 for k in range(1, contacts + 1)]
    for n, kind, u, lo, hi, text in appended_parameters(used):
        rows.append((n, kind, PARAMETER, FIXED, u, getattr(DEFAULT, n), lo, hi, text))
    for k in range(1, contacts + 1):
        rows += [(named(n, k, contacts), Real, INPUT, CONTINUOUS, u, 0.0, lo, None, f"{text}{of(k)}")
                 for n, u, lo, text in GAP_ROWS]
    for n, kind, u, lo, hi, text in table_parameters(used):
        rows.append((n, kind, PARAMETER, FIXED, u, getattr(DEFAULT, n), lo, hi, text))
    enumerated = {named("method_used", k, contacts): used["method_used"] for k in range(1, contacts + 1)}
    enumerated.update({n: used[n] for n in ("method", "friction_law", "rail_condition", "jacobian", "table")})
    if integer_codes:
        return integer_coded(tuple(rows), enumerated), {}
    return tuple(rows), enumerated


PER_CONTACT = frozenset(name for rows in (INPUT_ROWS, OUTPUT_ROWS, CONTACT_PARAMETERS, GAP_ROWS)
                        for name, *_ in rows)
"""Variables of their own per contact (arrays in FMI 3.0); the other parameters are shared."""


def dimensions(contacts: int, arrays: bool) -> dict:
    """The array variables of the FMI 3.0 FMU with ``contacts`` contacts -> ``contacts`` (none with one contact or
    without ``arrays``)."""
    return {name: contacts for name in sorted(PER_CONTACT)} if arrays and contacts > 1 else {}


SHARED_NAMES = tuple(row[0] for used in (enumerations(),)
                     for row in (*shared_parameters(used), *appended_parameters(used), *table_parameters(used)))
"""The shared parameters' names (those of :class:`rollcontact.stepping.EllipticParameters` but the curvatures)."""

assert len(INPUT_ROWS) + len(GAP_ROWS) == len(elliptic.INPUTS) and len(OUTPUT_ROWS) == len(EllipticOutputs._fields)


class RollingContact3DShared(TableSlave):
    """Elliptic wheel/rail rolling contact (linear theory, FASTSIM, strips, discretised) of rollcontact: the slave
    logic of both FMI versions."""

    description = ("Elliptic (3D) wheel/rail rolling contact: longitudinal and lateral force, spin moment, contact "
                   "ellipse and creep-force Jacobian from normal load, creepages and speed, for one or several "
                   "contacts")
    version = ROLLCONTACT_VERSION
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=1.0, step_size=1e-3)
    TIME_REFERENCE = 39  # released with 39 rows; the gap curvature inputs and `table` came after FMI 3.0's time

    def new_model(self, values: dict):
        """An EllipticModel of the parameter values (the per-contact curvatures gathered)."""
        n = self.CONTACTS
        shared = {name: values[name] for name in SHARED_NAMES}
        curvatures = {name: contact_values(values, name, n, self.DIMENSIONS) for name, *_ in CONTACT_PARAMETERS}
        model = EllipticModel(EllipticParameters(**shared, **curvatures), start_time=self.start_time,
                              stop_time=self.stop_time)
        return model, model.notices

    def step_model(self, current_time, step_size):
        return contacts_step(self.model.step, current_time, step_size, self.read_inputs(self), len(INPUT_ROWS),
                             bool(self.DIMENSIONS), len(GAP_ROWS))

    def step_messages(self):
        return self.model.take_messages()

    def parse_model_state(self, data):
        return EllipticState.parse(data)


@cache
def slave_class(contacts: int = 1, integer_codes: bool = False, arrays: bool = False) -> type:
    """The shared slave class of a variant (no FMI binding), one per variant and process: named
    ``RollingContact3D`` or ``RollingContact3D_n``, with the variant's table (``arrays``: the per-contact variables as
    arrays, the FMI 3.0 build)."""
    return variant_class(RollingContact3DShared, variant_name(MODEL, contacts), contacts,
                         declaration(contacts, integer_codes, arrays), dimensions(contacts, arrays))
