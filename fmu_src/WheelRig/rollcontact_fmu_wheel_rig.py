"""The WheelRig FMU's slave, host of the RollingContact2D FMU: :class:`WheelRigShared` (both FMI versions);
:func:`slave_class` gives the FMU's class.

A driven wheel on a rail with its share of the vehicle: wheel rotation ``J domega/dt = M(t) - r T``, vehicle
``m dv/dt = T - F_res(v)``, normal load ``N(t)``, creep ``xi = (omega r - v) / max(|v|, v_reg)`` (regularised
near standstill); input T from the contact.  No physics here: the parameters become a
:class:`rollcontact_cosim.wheel_rig.WheelRigParameters` (equations, coupling and integrator in that module's
docstring), each ``do_step`` is one :meth:`rollcontact_cosim.wheel_rig.WheelRigModel.step`, and the outputs read
the model's :class:`~rollcontact_cosim.wheel_rig.WheelRigOutputs` by position.  The variables are declared in the
single table :data:`VARIABLES` (value references follow its order: append, never reorder).

* Bad inputs (non-finite), invalid parameters and failed steps are logged (status Discard) and answered with
  ``do_step`` returning False (fmi2Discard); no exception reaches pythonfmu (it would become fmi2Fatal).  What
  FMI 2 answers with fmi2Error is emulated (:mod:`rollcontact_fmu.slave`).
* The FMU state holds every non-output variable plus the model's state as a JSON-compatible dict, checked
  completely (:func:`parse_wheel_rig_state`) before anything changes when a host sets it.
* ``rollcontact_cosim`` is bundled in ``resources/``; a host process that imported it before loading the FMU uses
  its own copy instead (Python caches modules per process).
"""

from __future__ import annotations

import dataclasses
import math
from functools import cache

from pythonfmu import Integer, Real
from pythonfmu.default_experiment import DefaultExperiment
from rollcontact_fmu.slave import CONTINUOUS, FIXED, INPUT, OUTPUT, PARAMETER, HostSlave

from rollcontact_cosim.wheel_rig import WheelRigModel, WheelRigParameters, WheelRigState

DEFAULT = WheelRigParameters()
START = WheelRigModel(DEFAULT).outputs()  # outputs at the default parameters (start values of the outputs)

# name, type, causality, variability, unit, start, min, max, description.  Append only: the value reference of a
# variable is its row number (from 0).  Outputs follow WheelRigOutputs, parameters WheelRigParameters.
VARIABLES = (
    ("tangential_force", Real, INPUT, CONTINUOUS, "N", 0.0, None, None,
     "Tangential (creep) force T of the rail on the wheel, positive forwards: drives the vehicle, brakes the wheel"),
    ("creep_stiffness", Real, INPUT, CONTINUOUS, "N", 0.0, None, None,
     "Creep stiffness dT/dxi at the creep where T was evaluated; used by coupling = 1"),
    ("external_torque", Real, INPUT, CONTINUOUS, "N.m", 0.0, None, None,
     "Torque added to the motor torque profile (e.g. from a controller), held over the macro step"),
    ("normal_load", Real, OUTPUT, CONTINUOUS, "N", START.normal_load, 0.0, None,
     "Normal load N(t) = static_load + load_amplitude sin(2 pi load_frequency t)"),
    ("creep", Real, OUTPUT, CONTINUOUS, "1", START.creep, None, None,
     "Creep xi = (omega r - v) / max(|v|, creep_regularisation_velocity): exact above the regularisation "
     "velocity, finite at standstill"),
    ("velocity", Real, OUTPUT, CONTINUOUS, "m/s", START.velocity, None, None,
     "Vehicle speed v (rolling speed of the contact)"),
    ("wheel_speed", Real, OUTPUT, CONTINUOUS, "rad/s", START.wheel_speed, None, None,
     "Wheel angular speed omega"),
    ("motor_torque", Real, OUTPUT, CONTINUOUS, "N.m", START.motor_torque, None, None,
     "Motor torque M(t): ramp + torque_amplitude sin(2 pi torque_frequency t) + external_torque"),
    ("distance", Real, OUTPUT, CONTINUOUS, "m", START.distance, None, None,
     "Distance travelled since the start time"),
    ("slip_velocity", Real, OUTPUT, CONTINUOUS, "m/s", START.slip_velocity, None, None,
     "Rigid slip velocity omega r - v"),
    ("wheel_radius", Real, PARAMETER, FIXED, "m", DEFAULT.wheel_radius, 0.0, None,
     "Rolling radius r of the wheel, > 0"),
    ("wheel_inertia", Real, PARAMETER, FIXED, "kg.m2", DEFAULT.wheel_inertia, 0.0, None,
     "Polar moment of inertia J of the wheel with the motor rotor reduced to it, > 0"),
    ("vehicle_mass", Real, PARAMETER, FIXED, "kg", DEFAULT.vehicle_mass, 0.0, None,
     "Vehicle mass m accelerated by this wheel's tangential force, > 0"),
    ("resistance_constant", Real, PARAMETER, FIXED, "N", DEFAULT.resistance_constant, 0.0, None,
     "Davis coefficient c0 of the running resistance c0 v/max(|v|, v_reg) + c1 v + c2 v |v|"),
    ("resistance_linear", Real, PARAMETER, FIXED, "N.s/m", DEFAULT.resistance_linear, 0.0, None,
     "Davis coefficient c1 of the running resistance"),
    ("resistance_quadratic", Real, PARAMETER, FIXED, "N.s2/m2", DEFAULT.resistance_quadratic, 0.0, None,
     "Davis coefficient c2 of the running resistance"),
    ("initial_velocity", Real, PARAMETER, FIXED, "m/s", DEFAULT.initial_velocity, None, None,
     "Vehicle speed v at the start time"),
    ("initial_creep", Real, PARAMETER, FIXED, "1", DEFAULT.initial_creep, None, None,
     "Creep at the start time: omega_0 = (v_0 + initial_creep max(|v_0|, v_reg)) / r"),
    ("static_load", Real, PARAMETER, FIXED, "N", DEFAULT.static_load, 0.0, None,
     "Static normal load N_0, >= 0"),
    ("load_amplitude", Real, PARAMETER, FIXED, "N", DEFAULT.load_amplitude, 0.0, None,
     "Amplitude of the oscillating normal load, 0 <= amplitude <= static_load"),
    ("load_frequency", Real, PARAMETER, FIXED, "Hz", DEFAULT.load_frequency, 0.0, None,
     "Frequency of the oscillating normal load, >= 0"),
    ("torque_initial", Real, PARAMETER, FIXED, "N.m", DEFAULT.torque_initial, None, None,
     "Motor torque before the ramp"),
    ("torque_final", Real, PARAMETER, FIXED, "N.m", DEFAULT.torque_final, None, None,
     "Motor torque after the ramp"),
    ("torque_ramp_start", Real, PARAMETER, FIXED, "s", DEFAULT.torque_ramp_start, None, None,
     "Time at which the linear torque ramp starts"),
    ("torque_ramp_duration", Real, PARAMETER, FIXED, "s", DEFAULT.torque_ramp_duration, 0.0, None,
     "Duration of the torque ramp, >= 0 (0: a step)"),
    ("torque_amplitude", Real, PARAMETER, FIXED, "N.m", DEFAULT.torque_amplitude, None, None,
     "Amplitude of the oscillating torque torque_amplitude sin(2 pi torque_frequency t)"),
    ("torque_frequency", Real, PARAMETER, FIXED, "Hz", DEFAULT.torque_frequency, 0.0, None,
     "Frequency of the oscillating torque, >= 0"),
    ("creep_regularisation_velocity", Real, PARAMETER, FIXED, "m/s", DEFAULT.creep_regularisation_velocity, 0.0,
     None, "v_reg > 0: the creep divides by max(|v|, v_reg) and the constant resistance ramps to 0 below it"),
    ("coupling", Integer, PARAMETER, FIXED, None, DEFAULT.coupling, 0, 1,
     "0 explicit (T held over the macro step), 1 linearly implicit: T_n + creep_stiffness (xi - xi_ref) "
     "integrated with the host (linearly implicit Euler)"),
    ("force_lag", Integer, PARAMETER, FIXED, None, DEFAULT.force_lag, 0, 1,
     "Communication points by which the force input lags the creep output (xi_ref of coupling 1): "
     "0 Gauss-Seidel with the contact stepped first, 1 Jacobi (libcosim)"),
    ("substeps", Integer, PARAMETER, FIXED, None, DEFAULT.substeps, 1, None,
     "Integration steps per macro step, >= 1"),
)

INPUTS = tuple(row[0] for row in VARIABLES if row[2] is INPUT)

STATE_FIELDS = tuple(f.name for f in dataclasses.fields(WheelRigState))


def parse_wheel_rig_state(data) -> WheelRigState:
    """A WheelRigState from its dict, every field checked (ValueError naming the first problem)."""
    if not isinstance(data, dict) or set(data) != set(STATE_FIELDS):
        keys = sorted(map(str, data)) if isinstance(data, dict) else type(data).__name__
        raise ValueError(f"a wheel-rig model state has the keys {list(STATE_FIELDS)}, got {keys!r:.200}")
    for name in STATE_FIELDS:
        value = data[name]
        if name == "steps":
            ok = type(value) is int and value >= 0
        else:
            ok = (value is None and name == "previous_creep") or (type(value) in (int, float)
                                                                  and math.isfinite(value))
        if not ok:
            raise ValueError(f"wheel-rig model state: {name} = {value!r:.80} is out of range or not a finite "
                             "number")
    return WheelRigState.from_dict(data)


class WheelRigShared(HostSlave):
    """Driven wheel on a rail (or roller rig) with longitudinal vehicle dynamics, host of RollingContact2D."""

    description = ("Driven railway wheel with its share of the vehicle: wheel rotation under a motor torque "
                   "profile, longitudinal dynamics with running resistance, normal load; outputs the regularised "
                   "creep, speed and load for a contact model, takes its tangential force and creep stiffness")
    version = "0.1.0"
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=1.0, step_size=1e-3)

    VARIABLES = VARIABLES
    MODEL, PARAMETERS = WheelRigModel, WheelRigParameters

    def step_model(self, current_time, step_size):
        return self.model.step(current_time, step_size, *(getattr(self, name) for name in INPUTS))

    def parse_model_state(self, data):
        return parse_wheel_rig_state(data)


def declaration() -> tuple[tuple, dict]:
    """The variable table and enumerations (none) of the WheelRig FMU."""
    return VARIABLES, {}


@cache
def slave_class() -> type:
    """The shared slave class (no FMI binding) of the WheelRig FMU, named ``WheelRig``, one per process."""
    return type("WheelRig", (WheelRigShared,), {"__doc__": WheelRigShared.__doc__, "__module__": __name__})
