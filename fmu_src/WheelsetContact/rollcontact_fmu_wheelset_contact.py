"""The WheelsetContact FMU's slave: :class:`WheelsetContactShared` maps the FMU's variables to rollcontact's wheelset
contact model, in both FMI versions; :func:`slave_class` gives the class of each variant (with enumerations or
integer codes).

No physics here: the parameters become a :class:`rollcontact.stepping.WheelsetContactParameters` (the profile paths
resolved: "" the S1002 and UIC60 profiles carried in ``resources/profiles/``, a relative path against the resources
folder, then the working directory), each ``do_step`` is one :meth:`rollcontact.stepping.WheelsetContactModel.step`,
and the output variables read its :class:`rollcontact.stepping.WheelsetContactOutputs` by position.  Track axes: x
forward, y to the right, z down; the outputs are the loads of the rails ON the wheelset.  Value references follow the
table's order: append, never reorder.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

from pythonfmu import Integer, Real, String
from pythonfmu.default_experiment import DefaultExperiment
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
import rollcontact.stepping.wheelrail.parameters as wheelrail
from rollcontact import __version__ as ROLLCONTACT_VERSION
from rollcontact.stepping import (
    ModelError,
    WheelsetContactModel,
    WheelsetContactOutputs,
    WheelsetContactParameters,
    WheelsetContactState,
)

MODEL = "WheelsetContact"
DEFAULT = WheelsetContactParameters()
PROFILES = "profiles"
"""The folder of ``resources/`` that carries the default profiles (``models/wheelrail/profiles``, with their
licence)."""

INPUT_ROWS = (
    ("lateral_shift", "m", None, "Lateral shift y of the wheelset centre, towards the right rail > 0"),
    ("yaw", "rad", None, "Yaw angle psi, the front turned to the right > 0"),
    ("lateral_velocity", "m/s", None, "Lateral velocity dy/dt"),
    ("yaw_rate", "rad/s", None, "Yaw rate dpsi/dt"),
    ("forward_speed", "m/s", 0.0, "Speed V along the track (> 0 with a loaded wheel)"),
    ("pitch_rate", "rad/s", None, "Angular velocity about the axle, negative forwards (pure rolling: -V/r0)"),
    ("vertical_load_left", "N", 0.0, "Vertical load Q the left wheel puts on its rail (0: lifted)"),
    ("vertical_load_right", "N", 0.0, "Vertical load Q the right wheel puts on its rail (0: lifted)"),
)
"""Inputs: name, unit, min, description (the stepping model's order)."""

WHEEL_ROWS = (
    ("normal_force", "N", 0.0, "Normal force of the {side} wheel's patches, summed"),
    ("longitudinal_force", "N", None, "Longitudinal force (track x) of the rail on the {side} wheel"),
    ("lateral_force", "N", None, "Lateral force (track y) of the rail on the {side} wheel"),
    ("vertical_force", "N", None, "Vertical force (track z, down) of the rail on the {side} wheel"),
    ("contact_angle", "rad", None, "Contact angle of the {side} wheel's largest patch, towards the flange > 0"),
    ("rolling_radius", "m", 0.0, "Rolling radius of the {side} wheel's largest patch (0: no contact)"),
    ("patches", None, 0, "Contact patches of the {side} wheel"),
    ("frictional_power", "W", None, "Frictional power V (xi Fx + eta Fy + phi Mz) of the {side} wheel's patches"),
)
DERIVATIVE_UNITS = {("force_y", "lateral_shift"): "N/m", ("force_y", "yaw"): "N/rad",
                    ("force_y", "lateral_velocity"): "N.s/m", ("force_y", "yaw_rate"): "N.s/rad",
                    ("moment_yaw", "lateral_shift"): "N.m/m", ("moment_yaw", "yaw"): "N.m/rad",
                    ("moment_yaw", "lateral_velocity"): "N.s", ("moment_yaw", "yaw_rate"): "N.m.s/rad"}
OUTPUT_ROWS = (
    ("force_x", "N", None, "Longitudinal force of the rails on the wheelset (track x, forward)"),
    ("force_y", "N", None, "Lateral force of the rails on the wheelset (track y, to the right)"),
    ("force_z", "N", None, "Vertical force of the rails on the wheelset (track z, down)"),
    ("moment_roll", "N.m", None, "Moment of the rails' forces about the wheelset centre, track x"),
    ("moment_pitch", "N.m", None, "Moment of the rails' forces about the wheelset centre, track y (the axle)"),
    ("moment_yaw", "N.m", None, "Moment of the rails' forces about the wheelset centre, track z (down)"),
    *((f"{name}_{side}", unit, low, text.format(side=side)) for side in ("left", "right")
      for name, unit, low, text in WHEEL_ROWS),
    ("roll", "rad", None, "Roll angle of the wheelset from the geometry (positive lowers the right wheel)"),
    ("vertical_position", "m", None, "Downward displacement of the axle from the rails' top plane at r0"),
    *((f"d{force}_d{by}", unit, None, f"d{force}/d{by} at the step (forward difference; parameter jacobian)")
      for (force, by), unit in DERIVATIVE_UNITS.items()),
    ("method_used", None, 0, "Wheel/rail level of the last step (MethodUsedWheelRail)"),
)
"""Outputs: name, unit, min, description (:class:`WheelsetContactOutputs`' order)."""

assert tuple(row[0] for row in OUTPUT_ROWS) == WheelsetContactOutputs._fields
assert tuple(row[0] for row in INPUT_ROWS) == tuple(name for name, _, _ in wheelrail.INPUTS)

GEOMETRY_TABLE_ITEMS = ((0, "off", "a contact search at every step"),
                        (1, "on", "the contact geometry tabulated over the lateral shift at initialisation"))
JACOBIAN_ITEMS = ((0, "difference", "forward differences of the step's evaluation, 4 more"),
                  (1, "none", "no derivatives (they read 0)"))
AUTO_TEXT = "the wheel/rail dispatcher's choice; with a tolerance the cheapest"
ELLIPTIC_AUTO_TEXT = "the lowest-ranked elliptic level that applies; with a tolerance the cheapest"


def enumerations() -> dict:
    """The enumerations (variable -> (type, items)), from the solver's tables as they are now."""
    return {"method_used": ("MethodUsedWheelRail", method_used_items(wheelrail.METHOD_LEVELS)),
            "method": ("MethodWheelRail", method_items(wheelrail.METHOD_LEVELS, AUTO_TEXT)),
            "elliptic_method": ("Method3D", method_items(elliptic.METHOD_LEVELS, ELLIPTIC_AUTO_TEXT)),
            "friction_law": ("FrictionLaw", friction_law_items()),
            "rail_condition": ("RailCondition", rail_condition_items()),
            "geometry_table": ("GeometryTable", GEOMETRY_TABLE_ITEMS),
            "jacobian": ("JacobianWheelRail", JACOBIAN_ITEMS)}


def parameters(used: dict) -> tuple:
    """The parameters (name, type, unit, min, max, description)."""
    return (
        ("wheel_profile", String, None, None, None,
         "Right wheel profile file (.prw, .whl); '' the S1002 carried in resources/profiles"),
        ("rail_profile", String, None, None, None,
         "Right rail profile file (.prr, .ban); '' the UIC60 1:40 carried in resources/profiles"),
        ("gauge", Real, "m", 0.5, 3.0, "Track gauge between the gauge faces at gauge_height"),
        ("gauge_height", Real, "m", 0.0, 0.05, "Depth below the rail tops where the gauge is measured"),
        ("rail_inclination", Real, "rad", -0.2, 0.2, "Cant of each rail towards the track centre (0: profile canted)"),
        ("flange_back_spacing", Real, "m", 0.3, 3.0, "Distance between the wheels' flange backs"),
        ("flange_back_distance", Real, "m", 0.0, 0.2, "Distance from a wheel's taping line to its flange back"),
        ("nominal_radius", Real, "m", 0.05, 5.0, "Rolling radius r0 at the taping line"),
        *material_friction_rows(used),
        ("rail_condition", Integer, None, 0, largest(used["rail_condition"][1]), RAIL_CONDITION_TEXT),
        ("method", Integer, None, 0, largest(used["method"][1]), "Wheel/rail level of every step (MethodWheelRail)"),
        ("elliptic_method", Integer, None, 0, largest(used["elliptic_method"][1]),
         "Elliptic level of the hertz level's contacts (Method3D)"),
        ("tolerance", Real, "1", 0.0, None, "Requested error of each patch's Fx, Fy over mu Fn (0: defaults)"),
        ("step_budget", Real, "s", 0.0, None, "Work budget of each solve of a step, modelled seconds (0: none)"),
        ("geometry_table", Integer, None, 0, largest(GEOMETRY_TABLE_ITEMS),
         "Contact geometry tabulated at initialisation (GeometryTable)"),
        ("table_range", Real, "m", POSITIVE, 0.05, "Half range of the table's lateral shifts"),
        ("jacobian", Integer, None, 0, largest(JACOBIAN_ITEMS), "How the d outputs are computed (JacobianWheelRail)"),
    )


def declaration(integer_codes: bool = False) -> tuple[tuple, dict]:
    """The variable table (rows ``(name, type, causality, variability, unit, start, min, max, description)``,
    value reference = row) and the enumerations (variable name -> (type, items)): inputs, outputs, parameters."""
    used = enumerations()
    rows = [(name, Real, INPUT, CONTINUOUS, unit, 0.0, low, None, text) for name, unit, low, text in INPUT_ROWS]
    for name, unit, low, text in OUTPUT_ROWS:
        if unit is None:  # patches, method_used
            high = largest(used["method_used"][1]) if name == "method_used" else None
            rows.append((name, Integer, OUTPUT, DISCRETE, None, 0, 0, high, text))
        else:
            rows.append((name, Real, OUTPUT, CONTINUOUS, unit, 0.0, low, None, text))
    for name, kind, unit, low, high, text in parameters(used):
        rows.append((name, kind, PARAMETER, FIXED, unit, getattr(DEFAULT, name), low, high, text))
    enumerated = {name: used[name] for name in used}
    if integer_codes:
        return integer_coded(tuple(rows), enumerated), {}
    return tuple(rows), enumerated


PARAMETER_NAMES = tuple(row[0] for row in parameters(enumerations()))


def resolved_profile(path: str, resources: str | None) -> str:
    """The profile file a ``wheel_profile`` / ``rail_profile`` names: "" stays (the carried one), an absolute path
    as given, else the first that exists of the path relative to the FMU's ``resources`` folder and to the current
    working directory (ModelError naming every path tried)."""
    if path == "" or Path(path).is_absolute():
        return path
    tried = [*([Path(resources, path)] if resources else []), Path.cwd() / path]
    found = next((candidate for candidate in tried if candidate.is_file()), None)
    if found is None:
        raise ModelError(f"profile {path!r} was not found; tried " + ", ".join(str(c) for c in tried))
    return str(found)


class WheelsetContactShared(TableSlave):
    """A wheelset on real wheel and rail profiles (rollcontact's wheel/rail levels): the slave logic of both FMI
    versions."""

    description = ("Wheelset on real wheel and rail profiles: the rails' forces and moments on the wheelset in track "
                   "axes, per-wheel forces, contact angles, rolling radii and frictional power, the roll, and the "
                   "derivatives of the lateral force and yaw moment, from its lateral shift, yaw, velocities and "
                   "wheel loads")
    version = ROLLCONTACT_VERSION
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=1.0, step_size=1e-3)

    def new_model(self, values: dict):
        """A WheelsetContactModel of the parameter values (the profiles resolved) and its notices."""
        for name in ("wheel_profile", "rail_profile"):
            if isinstance(values[name], str):
                values[name] = resolved_profile(values[name], self.resources)
        folder = Path(self.resources, PROFILES) if self.resources else None
        model = WheelsetContactModel(WheelsetContactParameters(**values), start_time=self.start_time,
                                     profile_folder=folder)
        return model, model.notices

    def step_model(self, current_time, step_size):
        return self.model.step(current_time, step_size, self.read_inputs(self))

    def step_messages(self):
        return self.model.take_messages()

    def parse_model_state(self, data):
        return WheelsetContactState.parse(data)


@cache
def slave_class(integer_codes: bool = False) -> type:
    """The shared slave class (no FMI binding) of a variant, named ``WheelsetContact``, one per variant and
    process."""
    from operator import attrgetter

    variables, enumerated = declaration(integer_codes)
    return type(MODEL, (WheelsetContactShared,), {
        "__doc__": WheelsetContactShared.__doc__, "__module__": __name__, "VARIABLES": variables,
        "ENUMERATIONS": enumerated, "read_inputs": attrgetter(*(row[0] for row in INPUT_ROWS))})
