"""The Wheelset FMU's slave, host of the hunting scene with two contacts: :class:`WheelsetShared` (both FMI
versions); :func:`slave_class` gives the FMU's class.

A suspended wheelset on straight track (lateral displacement and yaw); no physics here: the parameters become a
:class:`rollcontact_cosim.wheelset.WheelsetParameters` (equations, signs and integrator in that module's docstring),
each ``do_step`` is one :meth:`rollcontact_cosim.wheelset.WheelsetModel.step` with the forces and Jacobians of the two
contacts of conical wheels (``contact_model`` = 0), or one :meth:`~rollcontact_cosim.wheelset.WheelsetModel.
step_profiles` with the loads of a WheelsetContact and their derivatives (``contact_model`` = 1), and the outputs are
:meth:`~rollcontact_cosim.wheelset.WheelsetModel.outputs` by position (the WheelsetContact's inputs, in track axes,
among them).  Contact 1 is the left wheel, 2 the right one; the per-contact variables follow the FMI 2.0 array
convention ``name[1]``, ``name[2]``.  Forces are those the wheel exerts on the rail, in the wheel's axes (the
contact FMUs' sign).  The variables are declared in the single table :data:`VARIABLES` (value references follow
its order: append, never reorder).
"""

from __future__ import annotations

import dataclasses
from functools import cache

from pythonfmu import Integer, Real
from pythonfmu.default_experiment import DefaultExperiment
from rollcontact_fmu.slave import CONTINUOUS, FIXED, INPUT, OUTPUT, PARAMETER, HostSlave

from rollcontact_cosim.wheelset import WheelsetModel, WheelsetParameters, WheelsetState
from rollcontact_cosim.wheelset.model import LOAD_INPUTS, TRACK_OUTPUTS

DEFAULT = WheelsetParameters()
START = WheelsetModel(DEFAULT).outputs()
CONTACTS = (1, 2)
SIDES = {1: "left", 2: "right"}

FORCES = (("longitudinal_force", "N", "Longitudinal force Fx of the wheel on the rail (wheel axes)"),
          ("lateral_force", "N", "Lateral force Fy of the wheel on the rail (wheel axes)"),
          ("spin_moment", "N.m", "Spin moment Mz of the wheel on the rail about the contact normal"))
CREEPAGES = (("longitudinal_creep", "xi"), ("lateral_creep", "eta"), ("spin", "phi"))
JACOBIAN = tuple((f"d{force}_d{symbol}", force, symbol) for force in ("Fx", "Fy", "Mz")
                 for _, symbol in CREEPAGES)
"""Jacobian inputs ``dFx_dxi`` ... ``dMz_dphi`` (row-major in (Fx, Fy, Mz) x (xi, eta, phi))."""
JACOBIAN_UNITS = {(force, symbol): {("N", False): "N", ("N", True): "N.m", ("N.m", False): "N.m",
                                    ("N.m", True): "N.m2"}[unit, symbol == "phi"]
                  for force, unit in (("Fx", "N"), ("Fy", "N"), ("Mz", "N.m")) for _, symbol in CREEPAGES}
"""Unit of each Jacobian entry: the force's unit, times m for the spin (phi in 1/m)."""

OUTPUT_ROWS = []
for k in CONTACTS:
    side = SIDES[k]
    OUTPUT_ROWS += [
        (f"normal_load[{k}]", Real, OUTPUT, CONTINUOUS, "N", None, 0.0, None, f"Normal load N of the {side} wheel"),
        (f"longitudinal_creep[{k}]", Real, OUTPUT, CONTINUOUS, "1", None, None, None,
         f"Longitudinal creepage xi of the {side} contact (rigid slip of the wheel relative to the rail / V)"),
        (f"lateral_creep[{k}]", Real, OUTPUT, CONTINUOUS, "1", None, None, None,
         f"Lateral creepage eta of the {side} contact"),
        (f"spin[{k}]", Real, OUTPUT, CONTINUOUS, "1/m", None, None, None,
         f"Spin creepage phi of the {side} contact (yaw rate / V and the conicity's -+ delta0 / r0)"),
        (f"velocity[{k}]", Real, OUTPUT, CONTINUOUS, "m/s", None, None, None, f"Rolling speed V of the {side} wheel"),
    ]
OUTPUT_ROWS += [
    ("lateral_displacement", Real, OUTPUT, CONTINUOUS, "m", None, None, None, "Lateral displacement y (left > 0)"),
    ("yaw_angle", Real, OUTPUT, CONTINUOUS, "rad", None, None, None, "Yaw angle psi (nose to the left > 0)"),
    ("lateral_velocity", Real, OUTPUT, CONTINUOUS, "m/s", None, None, None, "Lateral velocity y'"),
    ("yaw_rate", Real, OUTPUT, CONTINUOUS, "rad/s", None, None, None, "Yaw rate psi'"),
]
TRACK_ROWS = {
    "lateral_shift": ("m", None, "Lateral shift in track axes, -y (to the right > 0), a WheelsetContact's input"),
    "yaw": ("rad", None, "Yaw in track axes, -psi (front to the right > 0), a WheelsetContact's input"),
    "track_lateral_velocity": ("m/s", None, "Lateral velocity in track axes, -y', a WheelsetContact's input"),
    "track_yaw_rate": ("rad/s", None, "Yaw rate in track axes, -psi', a WheelsetContact's yaw_rate"),
    "forward_speed": ("m/s", 0.0, "Speed V of the wheelset along the track, a WheelsetContact's input"),
    "pitch_rate": ("rad/s", None, "Pitch rate -V/r0 of rolling at the rolling radius, a WheelsetContact's input"),
    "vertical_load_left": ("N", 0.0, "Vertical load N of the left wheel, a WheelsetContact's input"),
    "vertical_load_right": ("N", 0.0, "Vertical load N of the right wheel, a WheelsetContact's input"),
}
# start values to 16 significant digits, as pythonfmu writes FMI 2.0 starts (FMI 3.0's keep 17): both
# modelDescriptions then declare the same numbers (the outputs' initial values are approx, computed at initialisation)
OUTPUT_ROWS = [(*row[:5], float(f"{start:.16g}"), *row[6:])
               for row, start in zip(OUTPUT_ROWS, START[:len(OUTPUT_ROWS)], strict=True)]
TRACK_OUTPUT_ROWS = [(name, Real, OUTPUT, CONTINUOUS, TRACK_ROWS[name][0], float(f"{start:.16g}"),
                      TRACK_ROWS[name][1], None, TRACK_ROWS[name][2])
                     for name, start in zip(TRACK_OUTPUTS, START[len(OUTPUT_ROWS):], strict=True)]

INPUT_ROWS = [(f"{name}[{k}]", Real, INPUT, CONTINUOUS, unit, 0.0, None, None, f"{text}, contact {k} ({SIDES[k]})")
              for k in CONTACTS for name, unit, text in FORCES]
INPUT_ROWS += [(f"{name}[{k}]", Real, INPUT, CONTINUOUS, JACOBIAN_UNITS[force, symbol], 0.0, None, None,
    f"d{force}/d{symbol} of contact {k} ({SIDES[k]}) at the creepages of the step's start (0: held forces)")
    for k in CONTACTS for name, force, symbol in JACOBIAN]

PARAMETER_TEXT = {
    "mass": ("kg", 0.0, "Wheelset mass m, > 0"),
    "yaw_inertia": ("kg.m2", 0.0, "Yaw moment of inertia I, > 0"),
    "rolling_radius": ("m", 0.0, "Centred rolling radius r0, > 0"),
    "contact_half_distance": ("m", 0.0, "Half the distance e between the contact points, > 0"),
    "conicity": ("1", 0.0, "Equivalent conicity lambda, >= 0"),
    "contact_angle": ("rad", 0.0, "Contact angle delta0 of the spin creepage (a cone: the conicity, to first order)"),
    "normal_load": ("N", 0.0, "Normal load N per wheel, > 0"),
    "lateral_stiffness": ("N/m", 0.0, "Primary lateral stiffness k_y, >= 0"),
    "yaw_stiffness": ("N.m/rad", 0.0, "Primary yaw stiffness k_psi, >= 0"),
    "lateral_damping": ("N.s/m", 0.0, "Primary lateral damping c_y, >= 0"),
    "yaw_damping": ("N.m.s/rad", 0.0, "Primary yaw damping c_psi, >= 0"),
    "speed": ("m/s", 0.0, "Speed V of the frame along the track, > 0"),
    "initial_lateral_displacement": ("m", None, "y at the start time"),
    "initial_yaw_angle": ("rad", None, "psi at the start time"),
    "initial_lateral_velocity": ("m/s", None, "y' at the start time"),
    "initial_yaw_rate": ("rad/s", None, "psi' at the start time"),
}
PARAMETER_ROWS = [(f.name, Real, PARAMETER, FIXED, *PARAMETER_TEXT[f.name][:1], getattr(DEFAULT, f.name),
                   PARAMETER_TEXT[f.name][1], None, PARAMETER_TEXT[f.name][2])
                  for f in dataclasses.fields(WheelsetParameters)
                  if f.name not in ("substeps", "force_lag", "contact_model")]
PARAMETER_ROWS += [("substeps", Integer, PARAMETER, FIXED, None, DEFAULT.substeps, 1, None,
                    "Integration steps per macro step, >= 1"),
                   ("force_lag", Integer, PARAMETER, FIXED, None, DEFAULT.force_lag, 0, 1,
                    "Communication points by which the force inputs lag the creepage outputs: 0 Gauss-Seidel with "
                    "the contact stepped first, 1 Jacobi (libcosim)")]

LOAD_UNITS = {"force_y": "N", "moment_yaw": "N.m", "dforce_y_dlateral_shift": "N/m", "dforce_y_dyaw": "N/rad",
              "dforce_y_dlateral_velocity": "N.s/m", "dforce_y_dyaw_rate": "N.s/rad", "dmoment_yaw_dlateral_shift":
              "N.m/m", "dmoment_yaw_dyaw": "N.m/rad", "dmoment_yaw_dlateral_velocity": "N.s",
              "dmoment_yaw_dyaw_rate": "N.m.s/rad"}
LOAD_ROWS = [(name, Real, INPUT, CONTINUOUS, LOAD_UNITS[name], 0.0, None, None,
              f"{name} of a WheelsetContact (track axes; contact_model = profiles)") for name in LOAD_INPUTS]
APPENDED_ROWS = [*TRACK_OUTPUT_ROWS, *LOAD_ROWS,
                 ("contact_model", Integer, PARAMETER, FIXED, None, DEFAULT.contact_model, 0, 1,
                  "The contact: 0 cones, the forces of two contacts; 1 profiles, the loads of a WheelsetContact")]

# name, type, causality, variability, unit, start, min, max, description.  Append only: the value reference of a
# variable is its row number (from 0).
VARIABLES = tuple(INPUT_ROWS + OUTPUT_ROWS + PARAMETER_ROWS + APPENDED_ROWS)
FORCE_INPUTS = tuple(f"{name}[{k}]" for k in CONTACTS for name, _, _ in FORCES)
JACOBIAN_INPUTS = tuple(f"{name}[{k}]" for k in CONTACTS for name, _, _ in JACOBIAN)


class WheelsetShared(HostSlave):
    """Suspended wheelset with conical wheels on straight track, host of a contact FMU with two contacts."""

    description = ("Wheelset on straight track (lateral displacement and yaw, conical wheels, primary suspension "
                   "to a frame at constant speed): outputs the creepages, loads and speeds of its two contacts, "
                   "takes their forces and Jacobians")
    version = "0.1.0"
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=2.0, step_size=1e-3)
    TIME_REFERENCE = 56  # released with 56 rows; the profile contact's rows came after FMI 3.0's time

    VARIABLES = VARIABLES
    MODEL, PARAMETERS = WheelsetModel, WheelsetParameters

    def step_model(self, current_time, step_size):
        if self.model.parameters.contact_model == 1:
            self.model.step_profiles(current_time, step_size, [getattr(self, name) for name in LOAD_INPUTS])
            return self.model.outputs()
        forces = [[getattr(self, FORCE_INPUTS[3 * k + i]) for i in range(3)] for k in range(2)]
        jacobians = [[[getattr(self, JACOBIAN_INPUTS[9 * k + 3 * i + j]) for j in range(3)] for i in range(3)]
                     for k in range(2)]
        self.model.step(current_time, step_size, forces, jacobians)
        return self.model.outputs()

    def parse_model_state(self, data):
        return WheelsetState.from_dict(data)  # a WheelsetError (ValueError) names the first bad field


def declaration() -> tuple[tuple, dict]:
    """The variable table and enumerations (none) of the Wheelset FMU."""
    return VARIABLES, {}


@cache
def slave_class() -> type:
    """The shared slave class (no FMI binding) of the Wheelset FMU, named ``Wheelset``, one per process."""
    return type("Wheelset", (WheelsetShared,), {"__doc__": WheelsetShared.__doc__, "__module__": __name__})
