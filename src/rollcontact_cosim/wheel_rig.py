"""Host model of the co-simulation: a driven wheel on a rail carrying its share of the vehicle (no FMI here).

The ``WheelRig`` FMU (``fmu_src/wheel_rig_slave.py``) only maps its variables to a :class:`WheelRigModel`, as the
``RollingContact2D`` FMU does with :class:`rollcontact.stepping.line.model.ContactModel`; this module imports neither
fmpy nor pythonfmu and is bundled in the FMU's resources.

Equations (SI units; T is the tangential force of the rail on the wheel, positive forwards)
-------------------------------------------------------------------------------------------
* wheel rotation: ``J d(omega)/dt = M(t) - r T``
* vehicle (the mass share of this wheel): ``m dv/dt = T - F_res(v)``, distance ``dx/dt = v``
* motor torque: ``M(t) = M_ramp(t) + M_amp sin(2 pi f_M t) + M_ext``, where ``M_ramp`` goes linearly from
  ``torque_initial`` to ``torque_final`` over ``[torque_ramp_start, torque_ramp_start + torque_ramp_duration]``
  (a step when the duration is 0: with the default start 0 a constant torque is ``torque_final``) and ``M_ext``
  is the input ``external_torque``
* normal load: ``N(t) = N_0 + N_amp sin(2 pi f_N t)``, ``0 <= N_amp <= N_0`` so that ``N >= 0``
* running resistance (Davis): ``F_res(v) = c_0 v / D(v) + c_1 v + c_2 v |v|``
* creep, regularised near standstill: ``xi = (omega r - v) / D(v)`` with ``D(v) = max(|v|, v_reg)``.  Above the
  ``creep_regularisation_velocity`` v_reg this is the exact creep ``(omega r - v) / v``; below it the rigid slip
  velocity is divided by v_reg, so xi stays finite at v = 0 (a wheel spinning at standstill reports
  ``omega r / v_reg``) and ``c_0 v / D`` ramps the constant resistance to zero instead of jumping.

The contact law gives T > 0 for xi > 0: a wheel turning faster than it rolls pushes the vehicle forwards and is
braked.  ``t`` is absolute time (the profiles do not restart at the start time).

Coupling (parameter ``coupling``)
---------------------------------
Over a macro step ``[t_n, t_n + H]`` the host receives ``T_n`` (input ``tangential_force``) and
``k_n = dT/dxi`` (input ``creep_stiffness``), both evaluated by the contact model at a creep ``xi_ref``.

* 0, explicit: ``T = T_n`` is held over the step.  The creep-force loop has the eigenvalue
  ``lambda = -k (r^2/J + 1/m) / D(v)``; with ``k ~ 1.8e7 N`` (Carter at zero creep, 98 kN) and ``v = 10 m/s``
  ``|lambda| ~ 2.7e3 1/s``, so a Gauss-Seidel master is stable only for ``H < 2/|lambda|`` (~0.7 ms) and a Jacobi
  master for ``H < 1/|lambda|``.
* 1, linearly implicit: ``T(xi) = T_n + k_n (xi - xi_ref)`` inside the step, integrated together with the
  host's equations by the linearly implicit Euler method below, so the loop is damped at any step.
  ``xi_ref`` is the host's creep output at ``t_(n - force_lag)``: ``force_lag`` = 0 when the contact was stepped
  with this step's creep (Gauss-Seidel, contact first), 1 when it was stepped with the previous one (Jacobi,
  libcosim's fixed-step algorithm, where all slaves step from the previous outputs; in its first step the host
  sees the contact's start values, T = k = 0).  With a quasi-static contact, T(xi) is an algebraic function and
  this linearisation about the creep the force belongs to makes either ordering behave like backward Euler on
  the whole loop.  With an instationary contact (``transient`` = 1, 2) T_n is the force at the end of the
  contact's step and k_n its sensitivity to the creep held over that step, and the same update applies; there
  the contact's force is a state, and Jacobi's extra step of delay costs accuracy (``models/cosim/README.md``).

Integration
-----------
``substeps`` steps of ``h = H / substeps`` from ``t_j = t_n + j h`` of the linearly implicit (Rosenbrock-)Euler
method ``(I - h W) (y_(j+1) - y_j) = h f(t_(j+1), y_j)`` with ``y = (omega, v, x)`` and W the exact Jacobian of the
right-hand side (including the linearised force) at ``y_j``.  On the linearised loop this is backward Euler:
L-stable and stiffly accurate, so the stiff creep tracks its quasi-static equilibrium at ``t_(j+1)`` without lag
(first order in the slow dynamics).  A two-stage L-stable Rosenbrock method (ROS2) would not serve: it is not
stiffly accurate, and its stiff component lags a moving equilibrium by ~0.7 h, a first-order creep error larger
than Euler's.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import NamedTuple

__all__ = ["INPUT_NAMES", "WheelRigError", "WheelRigModel", "WheelRigOutputs", "WheelRigParameters",
           "WheelRigState"]

INPUT_NAMES = ("tangential_force", "creep_stiffness", "external_torque")
"""Inputs of :meth:`WheelRigModel.step`, in the FMU's order: T [N], dT/dxi [N], M_ext [N m]."""

COUPLINGS = {0: "explicit", 1: "linearly implicit"}
TWO_PI = 2.0 * math.pi


class WheelRigError(ValueError):
    """An input, parameter or step the wheel-rig model cannot use; the message says what, which value, which limit."""


class WheelRigOutputs(NamedTuple):
    """Outputs at a communication point (the FMU's outputs, in this order).

    Attributes
    ----------
    normal_load : float
        N(t) [N].
    creep : float
        xi = (omega r - v) / max(|v|, v_reg) [1].
    velocity : float
        Vehicle speed v [m/s].
    wheel_speed : float
        omega [rad/s].
    motor_torque : float
        M(t) [N m] including the external torque last set.
    distance : float
        Travelled distance x [m] since the start.
    slip_velocity : float
        Rigid slip velocity omega r - v [m/s].
    """

    normal_load: float
    creep: float
    velocity: float
    wheel_speed: float
    motor_torque: float
    distance: float
    slip_velocity: float


@dataclass(frozen=True)
class WheelRigParameters:
    """Fixed parameters of a :class:`WheelRigModel` (FMU parameters of the same names), checked on creation.

    Defaults: a 0.46 m railway wheel with its share of a wheelset and traction motor (150 kg m^2), 10 t of
    vehicle mass and 98.1 kN of load on it, rolling at 10 m/s without torque.

    Parameters
    ----------
    wheel_radius : float
        r [m] > 0.
    wheel_inertia : float
        J [kg m^2] > 0, with the rotor inertia reduced to the wheel.
    vehicle_mass : float
        m [kg] > 0 accelerated by this wheel's tangential force.
    resistance_constant, resistance_linear, resistance_quadratic : float
        Davis coefficients c_0 [N], c_1 [N s/m], c_2 [N s^2/m^2] >= 0 of the running resistance.
    initial_velocity : float
        v at the start time [m/s].
    initial_creep : float
        xi at the start time [1]; sets ``omega_0 = (v_0 + xi_0 D(v_0)) / r``.
    static_load, load_amplitude, load_frequency : float
        N_0 [N] >= 0, N_amp [N] in [0, N_0], f_N [Hz] >= 0 of the normal load.
    torque_initial, torque_final : float
        Motor torque [N m] before and after the ramp.
    torque_ramp_start, torque_ramp_duration : float
        Ramp start [s] and duration [s] >= 0 (0: a step).
    torque_amplitude, torque_frequency : float
        M_amp [N m] and f_M [Hz] >= 0 of the oscillating torque.
    creep_regularisation_velocity : float
        v_reg [m/s] > 0 (module docstring).
    coupling : int
        0 explicit, 1 linearly implicit (module docstring).
    force_lag : int
        0 or 1: communication points by which the force input lags the creep output (module docstring).
    substeps : int
        Integration steps per macro step, >= 1.
    """

    wheel_radius: float = 0.46
    wheel_inertia: float = 150.0
    vehicle_mass: float = 10000.0
    resistance_constant: float = 100.0
    resistance_linear: float = 5.0
    resistance_quadratic: float = 0.5
    initial_velocity: float = 10.0
    initial_creep: float = 0.0
    static_load: float = 98.1e3
    load_amplitude: float = 0.0
    load_frequency: float = 0.0
    torque_initial: float = 0.0
    torque_final: float = 0.0
    torque_ramp_start: float = 0.0
    torque_ramp_duration: float = 0.0
    torque_amplitude: float = 0.0
    torque_frequency: float = 0.0
    creep_regularisation_velocity: float = 0.1
    coupling: int = 1
    force_lag: int = 0
    substeps: int = 1

    def __post_init__(self):
        """Check every parameter and raise one :class:`WheelRigError` naming each invalid value and its limit
        (``"; "``-separated)."""
        positive, non_negative = (True, False), (False, False)
        problems = []
        for name, unit, bounds in (
                ("wheel_radius", "m", positive), ("wheel_inertia", "kg m^2", positive),
                ("vehicle_mass", "kg", positive), ("resistance_constant", "N", non_negative),
                ("resistance_linear", "N s/m", non_negative), ("resistance_quadratic", "N s^2/m^2", non_negative),
                ("initial_velocity", "m/s", None), ("initial_creep", "1", None),
                ("static_load", "N", non_negative), ("load_amplitude", "N", non_negative),
                ("load_frequency", "Hz", non_negative), ("torque_initial", "N m", None),
                ("torque_final", "N m", None), ("torque_ramp_start", "s", None),
                ("torque_ramp_duration", "s", non_negative), ("torque_amplitude", "N m", None),
                ("torque_frequency", "Hz", non_negative), ("creep_regularisation_velocity", "m/s", positive)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                problems.append(f"{name} = {value!r} must be a finite real number [{unit}]")
            elif bounds is not None and (value < 0.0 or (bounds[0] and value == 0.0)):
                problems.append(f"{name} = {value!r} {unit} is out of range: it must be "
                                f"{'> 0' if bounds[0] else '>= 0'}")
            else:
                object.__setattr__(self, name, float(value))
        loads_valid = not any(p.startswith(("static_load ", "load_amplitude ")) for p in problems)
        if loads_valid and self.load_amplitude > self.static_load:
            problems.append(f"load_amplitude = {self.load_amplitude!r} N is out of range: it must be <= "
                            f"static_load = {self.static_load!r} N so that the normal load stays >= 0")
        for name, allowed in (("coupling", COUPLINGS), ("force_lag", {0: "Gauss-Seidel", 1: "Jacobi"})):
            value = getattr(self, name)
            if isinstance(value, bool) or value not in allowed:
                choices = ", ".join(f"{k} ({v})" for k, v in allowed.items())
                problems.append(f"{name} = {value!r} is out of range: it must be one of {choices}")
            else:
                object.__setattr__(self, name, int(value))
        if isinstance(self.substeps, bool) or not isinstance(self.substeps, int) or self.substeps < 1:
            problems.append(f"substeps = {self.substeps!r} is out of range: it must be an integer >= 1")
        if problems:
            raise WheelRigError("; ".join(problems))


@dataclass(slots=True)
class WheelRigState:
    """Everything a :class:`WheelRigModel` remembers (plain, copyable, JSON-compatible via :meth:`to_dict`).

    Attributes
    ----------
    time : float
        Current communication point t_n [s].
    wheel_speed, velocity, distance : float
        omega [rad/s], v [m/s] and x [m] at t_n.
    previous_creep : float or None
        The creep output at t_(n-1) (reference creep of ``force_lag`` = 1); None before the first step.
    external_torque : float
        M_ext [N m] of the last step (enters the ``motor_torque`` output).
    steps : int
        Successful steps taken.
    """

    time: float
    wheel_speed: float
    velocity: float
    distance: float
    previous_creep: float | None
    external_torque: float
    steps: int

    def to_dict(self) -> dict:
        """JSON-compatible dict (floats survive ``json`` exactly)."""
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> WheelRigState:
        """Inverse of :meth:`to_dict`; raises WheelRigError for missing or malformed fields."""
        try:
            previous = data["previous_creep"]
            return cls(float(data["time"]), float(data["wheel_speed"]), float(data["velocity"]),
                       float(data["distance"]), None if previous is None else float(previous),
                       float(data["external_torque"]), int(data["steps"]))
        except (KeyError, TypeError, ValueError) as exc:
            raise WheelRigError(f"invalid wheel-rig state: {exc!r}") from None


class WheelRigModel:
    """Driven wheel on a rail with longitudinal vehicle dynamics, advanced one macro step at a time.

    Parameters
    ----------
    parameters : WheelRigParameters, optional
        Fixed parameters (defaults when omitted).
    start_time : float
        t_0 [s] of the initial state.
    """

    def __init__(self, parameters: WheelRigParameters | None = None, *, start_time: float = 0.0):
        p = WheelRigParameters() if parameters is None else parameters
        if not isinstance(p, WheelRigParameters):
            raise TypeError(f"parameters must be WheelRigParameters, got {type(p).__name__}")
        self.parameters = p
        self.reset(start_time)

    def reset(self, start_time: float = 0.0) -> None:
        """Back to the initial state at ``start_time`` [s]: ``omega_0 = (v_0 + xi_0 D(v_0)) / r``."""
        p = self.parameters
        v0 = p.initial_velocity
        omega0 = (v0 + p.initial_creep * self.regularised_speed(v0)) / p.wheel_radius
        self.state = WheelRigState(float(start_time), omega0, v0, 0.0, None, 0.0, 0)

    def get_state(self) -> WheelRigState:
        """A copy of the current state."""
        return dataclasses.replace(self.state)

    def set_state(self, state: WheelRigState) -> None:
        """Continue from (a copy of) ``state``."""
        if not isinstance(state, WheelRigState):
            raise TypeError(f"state must be a WheelRigState, got {type(state).__name__}")
        self.state = dataclasses.replace(state)

    # profiles and constitutive functions -----------------------------------------------------------------------
    def regularised_speed(self, velocity: float) -> float:
        """D(v) = max(|v|, v_reg) [m/s], the creep's denominator."""
        speed = abs(velocity)
        reg = self.parameters.creep_regularisation_velocity
        return speed if speed > reg else reg

    def creep(self, wheel_speed: float, velocity: float) -> float:
        """xi = (omega r - v) / D(v) [1]."""
        return (wheel_speed * self.parameters.wheel_radius - velocity) / self.regularised_speed(velocity)

    def motor_torque(self, time: float) -> float:
        """M_ramp(t) + M_amp sin(2 pi f_M t) [N m], without the external torque."""
        p = self.parameters
        elapsed = time - p.torque_ramp_start
        if elapsed <= 0.0:
            torque = p.torque_initial
        elif elapsed >= p.torque_ramp_duration:
            torque = p.torque_final
        else:
            torque = p.torque_initial + (p.torque_final - p.torque_initial) * elapsed / p.torque_ramp_duration
        if p.torque_amplitude != 0.0:
            torque += p.torque_amplitude * math.sin(TWO_PI * p.torque_frequency * time)
        return torque

    def normal_load(self, time: float) -> float:
        """N(t) = N_0 + N_amp sin(2 pi f_N t) [N]."""
        p = self.parameters
        return p.static_load + p.load_amplitude * math.sin(TWO_PI * p.load_frequency * time)

    def resistance(self, velocity: float) -> tuple[float, float]:
        """F_res(v) [N] and dF_res/dv [N s/m]."""
        p = self.parameters
        speed = abs(velocity)
        saturated = speed > p.creep_regularisation_velocity
        sign = velocity / (speed if saturated else p.creep_regularisation_velocity)
        force = p.resistance_constant * sign + (p.resistance_linear + p.resistance_quadratic * speed) * velocity
        slope = p.resistance_linear + 2.0 * p.resistance_quadratic * speed
        if not saturated:
            slope += p.resistance_constant / p.creep_regularisation_velocity
        return force, slope

    # stepping --------------------------------------------------------------------------------------------------
    def outputs(self) -> WheelRigOutputs:
        """Outputs at the current communication point."""
        s = self.state
        r = self.parameters.wheel_radius
        return WheelRigOutputs(self.normal_load(s.time), self.creep(s.wheel_speed, s.velocity), s.velocity,
                               s.wheel_speed, self.motor_torque(s.time) + s.external_torque, s.distance,
                               s.wheel_speed * r - s.velocity)

    def step(self, current_time: float, step_size: float, tangential_force: float, creep_stiffness: float,
             external_torque: float = 0.0) -> WheelRigOutputs:
        """Advance from ``current_time`` to ``current_time + step_size`` and return the outputs there.

        Parameters
        ----------
        current_time : float
            t_n [s]; must be the model's time (up to round-off of ``t_0 + n H``).
        step_size : float
            H [s] > 0.
        tangential_force : float
            T_n [N], finite.
        creep_stiffness : float
            k_n = dT/dxi [N], finite (negative on the falling branch of a friction law); unused when explicit.
        external_torque : float
            M_ext [N m], finite, held over the step.

        Raises
        ------
        WheelRigError
            Non-finite or out-of-range arguments, a time that is not the model's, a singular linearly implicit
            matrix (the step is too large for an unstable, falling-friction loop) or a non-finite result.  The
            state is left unchanged.
        """
        for name, value, unit in (("current_time", current_time, "s"), ("step_size", step_size, "s"),
                                  ("tangential_force", tangential_force, "N"),
                                  ("creep_stiffness", creep_stiffness, "N"),
                                  ("external_torque", external_torque, "N m")):
            if not math.isfinite(value):
                raise WheelRigError(f"{name} = {value!r} {unit} is not finite")
        if not step_size > 0.0:
            raise WheelRigError(f"step_size = {step_size!r} s is out of range: it must be > 0")
        s = self.state
        if abs(current_time - s.time) > 1e-9 * max(1.0, abs(s.time)):
            raise WheelRigError(f"current_time = {current_time!r} s is not the model time {s.time!r} s; restore a "
                                "saved state to step from another time")
        p = self.parameters
        creep_now = self.creep(s.wheel_speed, s.velocity)
        if p.coupling == 0:
            stiffness = 0.0
            reference_creep = creep_now
        else:
            stiffness = creep_stiffness
            reference_creep = creep_now if p.force_lag == 0 or s.previous_creep is None else s.previous_creep
        h = step_size / p.substeps
        omega, v, x = s.wheel_speed, s.velocity, s.distance
        for j in range(p.substeps):
            omega, v, x = self.euler_step(current_time + j * h, h, omega, v, x, tangential_force, stiffness,
                                               reference_creep, external_torque)
        if not (math.isfinite(omega) and math.isfinite(v) and math.isfinite(x)):
            raise WheelRigError(f"the step from t = {current_time!r} s with H = {step_size!r} s gave a non-finite "
                                f"state (omega = {omega!r} rad/s, v = {v!r} m/s)")
        s.time = current_time + step_size
        s.wheel_speed, s.velocity, s.distance = omega, v, x
        s.previous_creep = creep_now
        s.external_torque = external_torque
        s.steps += 1
        return self.outputs()

    def euler_step(self, t: float, h: float, omega: float, v: float, x: float, force: float, stiffness: float,
                   reference_creep: float, external_torque: float) -> tuple[float, float, float]:
        """One linearly implicit Euler step of ``(omega, v, x)`` from t [s] to t + h.

        ``T = force + stiffness (xi - reference_creep)``; the torque is taken at t + h (module docstring).
        """
        p = self.parameters
        r, inertia, mass = p.wheel_radius, p.wheel_inertia, p.vehicle_mass
        t_force = force + stiffness * (self.creep(omega, v) - reference_creep)
        resistance, resistance_slope = self.resistance(v)
        f_omega = (self.motor_torque(t + h) + external_torque - r * t_force) / inertia
        f_v = (t_force - resistance) / mass
        # I - h W, W the Jacobian of (d omega/dt, dv/dt) with respect to (omega, v); dx/dt = v adds the row (0, 1)
        d = self.regularised_speed(v)
        dxi_dv = -1.0 / d  # plus the derivative of the denominator where D(v) = |v|
        if abs(v) > p.creep_regularisation_velocity:
            dxi_dv -= (omega * r - v) * math.copysign(1.0, v) / (d * d)
        dt_domega, dt_dv = stiffness * r / d, stiffness * dxi_dv
        a11 = 1.0 + h * r * dt_domega / inertia
        a12 = h * r * dt_dv / inertia
        a21 = -h * dt_domega / mass
        a22 = 1.0 - h * (dt_dv - resistance_slope) / mass
        det = a11 * a22 - a12 * a21
        if not det > 0.0:
            raise WheelRigError(f"the linearly implicit matrix is singular or indefinite at t = {t!r} s (det = "
                                f"{det!r}, creep_stiffness = {stiffness!r} N): the substep {h!r} s is too large "
                                "for this loop; reduce the step or raise substeps")
        d_omega = h * (a22 * f_omega - a12 * f_v) / det
        d_v = h * (a11 * f_v - a21 * f_omega) / det
        return omega + d_omega, v + d_v, x + h * (v + d_v)
