"""Host model of the hunting scene: a suspended wheelset with conical wheels on straight track (no FMI here).

A rigid wheelset runs on straight, rigid track with knife-edge rails; its centre follows a frame (bogie) that moves
at the constant speed V along the track, attached to it by the primary suspension.  Degrees of freedom: the
lateral displacement y [m] of the wheelset centre and its yaw angle psi [rad], state ``s = (y, psi, y', psi')``.
The contact forces come from a creep-force law per contact (left, right): the in-process laws of this module
(:class:`KalkerLinearLaw`, :class:`SaturatedKalkerLaw`) or, in the co-simulation, the contact FMU through its
force and Jacobian outputs (:meth:`WheelsetModel.step`).

Axes and signs
--------------
Track axes: x forwards (direction of travel), y to the left, z up; psi > 0 turns the wheelset's nose to the left.
The left contact is at lateral position +e, the right one at -e (e: half the distance between the contact points).
A contact's local axes are the wheel's: x along its rolling direction ``t = (cos psi, sin psi)``, y along the axle
``n = (-sin psi, cos psi)``, z up, the same for both wheels (no mirroring).  Creepages are Kalker's: the rigid slip
velocity of the wheel relative to the rail divided by V; forces and moments are those the wheel exerts on the
rail, so that each creepage > 0 gives its force > 0 as in the contact FMUs (linear theory: ``Fx = f11 xi``,
``Fy = f22 eta + f23 phi``, ``Mz = -f23 eta + f33 phi``; the wheel receives the opposite).

Kinematics (Wickens; Knothe & Boehm; Iwnicki, Handbook of Railway Vehicle Dynamics, ch. stability)
-------------------------------------------------------------------------------------------------
Conical treads of equivalent conicity lambda: the rolling radii are ``r_L = r0 + lambda y`` and
``r_R = r0 - lambda y`` (a displacement to the left moves the left contact towards the flange).  The axle turns at
the nominal ``Omega = V / r0`` (the pitch rotation is not a degree of freedom).  The wheel's material point in a
contact moves with the centre velocity ``(V, y')``, the yaw rate's ``-/+ e psi' t`` (left/right) and the rolling
``-Omega r_(L,R) t``, hence

* longitudinal: ``xi_(L,R) = (V cos psi + y' sin psi -/+ e psi' - Omega r_(L,R)) / V``
  ``~ -/+ (lambda y / r0 + e psi' / V)``;
* lateral: ``eta = (y' cos psi - V sin psi) / V ~ y'/V - psi`` (both contacts);
* spin: ``phi_(L,R) = psi'/V -/+ delta0 / r0`` [1/m], the yaw rate plus the axle's rotation about the tilted
  contact normal (contact angle delta0; a cone has ``tan delta0 = lambda``, ``delta0 = lambda`` to first order).
  The conicity terms are equal and opposite on the two wheels, so their forces cancel in the wheelset's equations
  at every amplitude of a symmetric law; with a linear law they drop out of the linearised equations.

Equations of motion
-------------------
With ``F_(x,y), M_z`` the forces and moment on the rail of each contact (wheel axes),

* ``m y'' = -sum (Fx sin psi + Fy cos psi) - k_y y - c_y y'``
* ``I psi'' = e (Fx_L - Fx_R) - (Mz_L + Mz_R) - k_psi psi - c_psi psi'``

(the moment of ``-F`` at ``+/- e n`` about the centre is ``+/- e Fx``).  Linearised with the linear law this is
Wickens' wheelset: ``m y'' + (2 f22/V) y' - 2 f22 psi + (2 f23/V) psi' + k_y y = 0`` and
``I psi'' + (2 e^2 f11/V + 2 f33/V) psi' + (2 e f11 lambda/r0) y - (2 f23/V) y' + 2 f23 psi + k_psi psi = 0``
(:func:`rollcontact_cosim.wheelset.stability.state_matrix`).  Gravitational stiffness is not modelled: with cones
on knife-edge rails the contact angles do not change with y, so the lateral components of the normal loads
cancel (no lateral gravitational stiffness); the yaw gravitational stiffness of profiled wheels is neglected.
The normal load N per wheel is constant.

Integration and coupling
------------------------
:meth:`WheelsetModel.step` advances one macro step with the forces ``F_n`` evaluated at the creepages of the step's
start and their Jacobians ``K = dF/d(xi, eta, phi)`` (3x3 per contact): ``substeps`` steps of the linearly implicit
trapezoidal rule (one-stage Rosenbrock method with gamma = 1/2) ``(I - h W / 2) (s_(j+1) - s_j) = h f(s_j)``,
where W is the Jacobian of the right-hand side with the forces linearised, ``F = F_n + K (c(s) - c_ref)``, and
``c_ref`` the creepages the contact evaluated ``F_n`` at: those of t_n (``force_lag = 0``: Gauss-Seidel, contact
stepped first) or of t_(n-1) (``force_lag = 1``: Jacobi, as libcosim's fixed-step algorithm, where every FMU steps
from the previous outputs), so that either ordering integrates the same linearised force.
It is second order, A-stable, and maps the imaginary axis onto the unit circle: an undamped linear mode stays
undamped at any step, so the step does not move the stability boundary (explicit methods and backward Euler add
or remove damping of order h), and the stiff creep modes (eigenvalues ~ -2 f22 / (m V)) decay at any step.
With ``K = 0`` the forces are held over the step (explicit coupling).

Profiles
--------
With ``contact_model = 1`` the wheels are real profiles and the loads come from a WheelsetContact (the library's
:class:`rollcontact.stepping.WheelsetContactModel`), whose inputs the host outputs in track axes (y to the right, z
down, yaw front to the right: ``q = -s``, :data:`TRACK_OUTPUTS`) and whose lateral force F_y and yaw moment M_z on
the wheelset (track axes) it takes with their derivatives ``J = d(F_y, M_z)/dq`` (:data:`LOAD_INPUTS`):
:meth:`WheelsetModel.step_profiles` integrates ``m y'' = -F_y - k_y y - c_y y'``, ``I psi'' = -M_z - k_psi psi -
c_psi psi'`` with the loads linearised about the state they were evaluated at, ``-F_y + J_F (s - s_ref)`` (the
signs of q and of the loads cancel), by the same linearly implicit trapezoidal rule.  The normal forces' lateral
components (gravitational stiffness), the spin creep forces of the contact angles and the flange are in the loads.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple, Protocol

import numpy as np

from rollcontact import Material, creepage_coefficients, hertz_ellipse

__all__ = ["INPUT_NAMES", "LOAD_INPUTS", "OUTPUT_NAMES", "TRACK_OUTPUTS", "ContactForces", "CreepForceLaw",
           "KalkerLinearLaw", "SaturatedKalkerLaw", "WheelsetError", "WheelsetModel", "WheelsetParameters",
           "WheelsetState", "creepage_jacobian", "creepages", "linear_law", "simulate", "simulate_profiles"]

CONTACTS = (1, 2)
"""The contacts' numbers in the host's variable names: ``name[1]`` the left wheel, ``name[2]`` the right one."""
CONTACT_OUTPUTS = ("normal_load", "longitudinal_creep", "lateral_creep", "spin", "velocity")
"""Per contact, the outputs the contact FMU takes as inputs of the same names: N [N], xi, eta [1], phi [1/m], V
[m/s] (:meth:`WheelsetModel.outputs`)."""
STATES = ("lateral_displacement", "yaw_angle", "lateral_velocity", "yaw_rate")
"""The state outputs y [m], psi [rad], y' [m/s], psi' [rad/s], after the contacts' outputs."""
FORCES = ("longitudinal_force", "lateral_force", "spin_moment")
"""Per contact, the inputs Fx, Fy [N], Mz [N m] on the rail (wheel axes), the contact FMU's outputs of those names."""
JACOBIAN = tuple(f"d{force}_d{symbol}" for force in ("Fx", "Fy", "Mz") for symbol in ("xi", "eta", "phi"))
"""Per contact, the inputs ``dFx_dxi`` ... ``dMz_dphi``: ``d(Fx, Fy, Mz)/d(xi, eta, phi)`` row-major, the contact
FMU's Jacobian outputs of those names (0: the forces held over the step)."""
TRACK_OUTPUTS = ("lateral_shift", "yaw", "track_lateral_velocity", "track_yaw_rate", "forward_speed", "pitch_rate",
                 "vertical_load_left", "vertical_load_right")
"""The outputs a WheelsetContact takes (track axes: y to the right, z down, yaw front to the right): y_t = -y
[m], psi_t = -psi [rad], their rates, V [m/s], the pitch rate -V / r0 [rad/s] of rolling at r0, the loads N [N];
the rates connect to the contact's ``lateral_velocity`` and ``yaw_rate`` (``[system] to_contact`` renames them)."""
OUTPUT_NAMES = (*(f"{name}[{k}]" for k in CONTACTS for name in CONTACT_OUTPUTS), *STATES, *TRACK_OUTPUTS)
"""The host FMU's outputs, in :meth:`WheelsetModel.outputs`' order."""
LOAD_INPUTS = ("force_y", "moment_yaw", *(f"d{load}_d{by}" for load in ("force_y", "moment_yaw")
                                            for by in ("lateral_shift", "yaw", "lateral_velocity", "yaw_rate")))
"""The inputs of ``contact_model`` = profiles: a WheelsetContact's lateral force [N] and yaw moment [N m] on the
wheelset (track axes) and their derivatives in its lateral shift, yaw, lateral velocity and yaw rate."""
CONTACT_MODELS = {0: "cones", 1: "profiles"}
"""``contact_model``: conical wheels with two contacts' forces, or profiles with a WheelsetContact's loads."""
INPUT_NAMES = (*(f"{name}[{k}]" for k in CONTACTS for name in FORCES + JACOBIAN), *LOAD_INPUTS)
"""The host FMU's inputs: per contact the forces, then the Jacobian (both contacts in the same axes, x rolling
direction, y to the left, z up: the right contact is not mirrored); then a WheelsetContact's loads."""


class WheelsetError(ValueError):
    """A parameter, input or step the wheelset model cannot use; the message names the value and the limit."""


class ContactForces(NamedTuple):
    """Forces and moment on the rail of one contact (wheel axes) [N, N, N m]."""

    longitudinal_force: float
    lateral_force: float
    spin_moment: float


class CreepForceLaw(Protocol):
    """A creep-force law of one contact: ``law(N, xi, eta, phi, V) -> ContactForces`` (force on the rail).

    ``law.jacobian(N, xi, eta, phi, V)`` returns ``dF/d(xi, eta, phi)`` (3x3, rows Fx, Fy, Mz).
    """

    def __call__(self, normal_load: float, xi: float, eta: float, phi: float, velocity: float) -> ContactForces: ...

    def jacobian(self, normal_load: float, xi: float, eta: float, phi: float, velocity: float) -> np.ndarray: ...


# creep-force laws -----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class KalkerLinearLaw:
    """Kalker's linear theory (force on the rail): ``Fx = f11 xi, Fy = f22 eta + f23 phi, Mz = -f23 eta + f33 phi``.

    Attributes
    ----------
    f11, f22 : float
        ``G c^2 C11``, ``G c^2 C22`` [N].
    f23 : float
        ``G c^3 C23`` [N m] (0: spin creep force omitted).
    f33 : float
        ``G c^4 C33`` [N m^2] (0: spin moment omitted).
    """

    f11: float
    f22: float
    f23: float = 0.0
    f33: float = 0.0

    def __call__(self, normal_load, xi, eta, phi, velocity) -> ContactForces:
        """The forces on the rail [N, N, N m] at the creepages [1, 1, 1/m] (load and speed do not enter)."""
        return ContactForces(self.f11 * xi, self.f22 * eta + self.f23 * phi, -self.f23 * eta + self.f33 * phi)

    def jacobian(self, normal_load, xi, eta, phi, velocity) -> np.ndarray:
        """``d(Fx, Fy, Mz)/d(xi, eta, phi)``: the constant coefficient matrix."""
        return np.array([[self.f11, 0.0, 0.0], [0.0, self.f22, self.f23], [0.0, -self.f23, self.f33]])


@dataclass(frozen=True)
class SaturatedKalkerLaw:
    """Kalker's linear forces saturated at ``mu N`` (Shen, Hedrick & Elkins 1983, Johnson-Vermeulen's cubic).

    With ``F_lin = (f11 xi, f22 eta + f23 phi)``, ``u = |F_lin| / (mu N)`` the tangential force is scaled by
    ``g(u) / u`` with ``g(u) = u - u^2/3 + u^3/27`` for ``u < 3`` and ``g = 1`` beyond; the spin moment by the
    same factor.  Its Jacobian at zero creepage is the linear law's, so it serves as the nonlinear right-hand side
    whose linearisation :mod:`rollcontact_cosim.wheelset.stability` must reproduce.  With spin terms (f23 > 0)
    the conicity's spin ``-/+ delta0 / r0`` loads each contact laterally in the centred state and the saturation
    lowers the slopes there: the linear analysis with Kalker's coefficients then describes the law only without
    spin.
    """

    linear: KalkerLinearLaw
    friction_coefficient: float = 0.3

    def __call__(self, normal_load, xi, eta, phi, velocity) -> ContactForces:
        """The saturated forces on the rail [N, N, N m] at the creepages [1, 1, 1/m] under ``normal_load`` [N]."""
        fx, fy, mz = self.linear(normal_load, xi, eta, phi, velocity)
        return ContactForces(*(value * self.factor(normal_load, fx, fy) for value in (fx, fy, mz)))

    def factor(self, normal_load: float, fx: float, fy: float) -> float:
        """``g(u) / u`` [1] at the linear tangential force (fx, fy) [N]."""
        u = math.hypot(fx, fy) / (self.friction_coefficient * normal_load)
        return 1.0 - u / 3.0 + u * u / 27.0 if u < 3.0 else 1.0 / u

    def jacobian(self, normal_load, xi, eta, phi, velocity, step: float = 1e-7) -> np.ndarray:
        """Central differences in each creepage (step relative to ``mu N / f11``)."""
        h = step * self.friction_coefficient * normal_load / self.linear.f11
        out = np.empty((3, 3))
        for j in range(3):
            plus, minus = [xi, eta, phi], [xi, eta, phi]
            plus[j] += h
            minus[j] -= h
            out[:, j] = (np.array(self(normal_load, *plus, velocity)) - self(normal_load, *minus, velocity)) / (2 * h)
        return out


# parameters, state, kinematics ------------------------------------------------------------------------------------
@dataclass(frozen=True)
class WheelsetParameters:
    """Fixed parameters of a :class:`WheelsetModel` (the host FMU's parameters of the same names).

    Defaults: a passenger-coach wheelset (Iwnicki's handbook's orders of magnitude: m 1250 kg, I 700 kg m^2,
    r0 0.46 m, e 0.75 m), conicity 0.15 and contact angle 0.15 rad (a cone, to first order), 80 kN per wheel, primary
    stiffnesses 1 MN/m laterally (two axle boxes of 0.5 MN/m) and 2 MN m/rad in yaw (``2 k_x b^2``, longitudinal
    axle-box stiffness k_x = 1 MN/m at the lateral semi-spacing b = 1 m), which with the default creep
    coefficients put the critical speed in the 30-150 m/s of passenger stock (``models/cosim/
    wheelset_hunting_inprocess.md``), no dampers, starting 0.1 mm off the centre line.

    Parameters
    ----------
    mass : float
        m [kg] > 0.
    yaw_inertia : float
        I [kg m^2] > 0 about the vertical axis.
    rolling_radius : float
        r0 [m] > 0, centred.
    contact_half_distance : float
        e [m] > 0.
    conicity : float
        lambda [1] >= 0.
    contact_angle : float or None
        delta0 [rad] in [0, pi/2) of the spin creepage; None: the conicity (a cone's ``arctan(lambda)`` to first
        order, the order of the cone geometry here).
    normal_load : float
        N [N] > 0 per wheel.
    lateral_stiffness, yaw_stiffness : float
        k_y [N/m], k_psi [N m/rad] >= 0.
    lateral_damping, yaw_damping : float
        c_y [N s/m], c_psi [N m s/rad] >= 0.
    speed : float
        V [m/s] > 0.
    initial_lateral_displacement, initial_yaw_angle : float
        y [m] and psi [rad] at the start time.
    initial_lateral_velocity, initial_yaw_rate : float
        y' [m/s] and psi' [rad/s] at the start time.
    substeps : int
        Integration steps per macro step >= 1.
    force_lag : int
        0 or 1: communication points by which the force inputs lag the creepage outputs (module docstring).
    contact_model : int
        0: conical wheels, the forces of two contacts (:meth:`WheelsetModel.step`); 1: profiles, the loads of a
        WheelsetContact (:meth:`WheelsetModel.step_profiles`), where ``conicity``, ``contact_angle`` and
        ``contact_half_distance`` only shape the cone outputs nobody reads.
    """

    mass: float = 1250.0
    yaw_inertia: float = 700.0
    rolling_radius: float = 0.46
    contact_half_distance: float = 0.75
    conicity: float = 0.15
    contact_angle: float | None = None
    normal_load: float = 80e3
    lateral_stiffness: float = 1e6
    yaw_stiffness: float = 2e6
    lateral_damping: float = 0.0
    yaw_damping: float = 0.0
    speed: float = 50.0
    initial_lateral_displacement: float = 1e-4
    initial_yaw_angle: float = 0.0
    initial_lateral_velocity: float = 0.0
    initial_yaw_rate: float = 0.0
    substeps: int = 1
    force_lag: int = 0
    contact_model: int = 0

    def __post_init__(self):
        if self.contact_angle is None:
            object.__setattr__(self, "contact_angle", self.conicity)
        rules = {"mass": (0, "kg"), "yaw_inertia": (0, "kg m^2"), "rolling_radius": (0, "m"),
                 "contact_half_distance": (0, "m"), "normal_load": (0, "N"), "speed": (0, "m/s"),
                 "conicity": (1, "1"), "lateral_stiffness": (1, "N/m"), "yaw_stiffness": (1, "N m/rad"),
                 "lateral_damping": (1, "N s/m"), "yaw_damping": (1, "N m s/rad"), "contact_angle": (1, "rad"),
                 "initial_lateral_displacement": (2, "m"), "initial_yaw_angle": (2, "rad"),
                 "initial_lateral_velocity": (2, "m/s"), "initial_yaw_rate": (2, "rad/s")}
        for name, (kind, unit) in rules.items():
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise WheelsetError(f"{name} = {value!r} must be a finite real number [{unit}]")
            if (kind == 0 and value <= 0.0) or (kind == 1 and value < 0.0):
                raise WheelsetError(f"{name} = {value!r} {unit} is out of range: it must be "
                                    f"{'> 0' if kind == 0 else '>= 0'}")
            object.__setattr__(self, name, float(value))
        if self.contact_angle >= math.pi / 2:
            raise WheelsetError(f"contact_angle = {self.contact_angle!r} rad is out of range: it must be < pi/2")
        if isinstance(self.substeps, bool) or not isinstance(self.substeps, int) or self.substeps < 1:
            raise WheelsetError(f"substeps = {self.substeps!r} is out of range: it must be an integer >= 1")
        if isinstance(self.force_lag, bool) or self.force_lag not in (0, 1):
            raise WheelsetError(f"force_lag = {self.force_lag!r} is out of range: it must be 0 (Gauss-Seidel) or 1 "
                                "(Jacobi)")
        if isinstance(self.contact_model, bool) or self.contact_model not in CONTACT_MODELS:
            raise WheelsetError(f"contact_model = {self.contact_model!r} is out of range: it must be 0 (cones, two "
                                "contacts) or 1 (profiles, the WheelsetContact's loads)")

    @property
    def initial_state(self) -> np.ndarray:
        """``(y, psi, y', psi')`` at the start time."""
        return np.array([self.initial_lateral_displacement, self.initial_yaw_angle, self.initial_lateral_velocity,
                         self.initial_yaw_rate])


def linear_law(parameters: WheelsetParameters | None = None, *, youngs_modulus: float = 210e9,
               poisson_ratio: float = 0.25, rail_profile_radius: float | None = None,
               spin: bool = False) -> KalkerLinearLaw:
    """Kalker's linear law of one contact of the wheelset, with the library's Hertz ellipse
    (:func:`rollcontact.hertz_ellipse`) and creepage coefficients (:func:`rollcontact.creepage_coefficients`).

    The gap is ``A x^2 + B y^2`` with ``A = 1/(2 r0)`` (wheel rolling radius, straight rail) and
    ``B = 1/(2 R_rail)`` (straight cone generatrix, rail head profile radius ``rail_profile_radius``, default r0:
    a circular contact).  Identical steel bodies: ``E* = E / (2 (1 - nu^2))``, ``G = E / (2 (1 + nu))``,
    ``c = sqrt(a b)``, ``f11 = G c^2 C11``, ``f22 = G c^2 C22`` and, with ``spin``, the lateral force of spin
    ``f23 = G c^3 C23`` (the spin moment's ``f33`` is left out).

    Raises
    ------
    ValueError
        A load, radius or modulus out of range, or an aspect ratio a/b outside the coefficients' table; the message
        names the value and the limit.
    """
    p = WheelsetParameters() if parameters is None else parameters
    rail = p.rolling_radius if rail_profile_radius is None else rail_profile_radius
    ellipse = hertz_ellipse(p.normal_load, 0.5 / p.rolling_radius, 0.5 / rail,
                            Material(youngs_modulus, poisson_ratio).contact_modulus)
    c11, c22, c23, _ = creepage_coefficients(ellipse.aspect_ratio, poisson_ratio)
    shear = youngs_modulus / (2.0 * (1.0 + poisson_ratio))
    c2 = ellipse.a * ellipse.b
    return KalkerLinearLaw(shear * c2 * c11, shear * c2 * c22, shear * c2 * math.sqrt(c2) * c23 if spin else 0.0)


def creepages(parameters: WheelsetParameters, state) -> np.ndarray:
    """Creepages ``(xi, eta, phi)`` [1, 1, 1/m] of the left and right contacts (rows) in the state (module docstring).

    ``xi = (V cos psi + y' sin psi -/+ e psi' - (V / r0) r_(L,R)) / V``, ``eta = (y' cos psi - V sin psi) / V``,
    ``phi = psi'/V -/+ delta0 / r0``, ``r_(L,R) = r0 +/- lambda y``.
    """
    y, psi, vy, rate = state
    p = parameters
    v, e, r0 = p.speed, p.contact_half_distance, p.rolling_radius
    cos, sin = math.cos(psi), math.sin(psi)
    common = cos + vy * sin / v - 1.0
    rolling = p.conicity * y / r0 + e * rate / v
    eta = vy * cos / v - sin
    spin = p.contact_angle / r0
    return np.array([[common - rolling, eta, rate / v - spin], [common + rolling, eta, rate / v + spin]])


def creepage_jacobian(parameters: WheelsetParameters, state) -> np.ndarray:
    """d(xi, eta, phi)/d(y, psi, y', psi') of both contacts (shape 2x3x4) in the state."""
    y, psi, vy, rate = state
    p = parameters
    v, e, r0 = p.speed, p.contact_half_distance, p.rolling_radius
    cos, sin = math.cos(psi), math.sin(psi)
    out = np.zeros((2, 3, 4))
    for k, side in enumerate((1.0, -1.0)):
        out[k, 0] = (-side * p.conicity / r0, -sin + vy * cos / v, sin / v, -side * e / v)
        out[k, 1] = (0.0, -vy * sin / v - cos, cos / v, 0.0)
        out[k, 2] = (0.0, 0.0, 0.0, 1.0 / v)
    return out


# the model ----------------------------------------------------------------------------------------------------------
@dataclass(slots=True)
class WheelsetState:
    """Everything a :class:`WheelsetModel` remembers (plain, copyable, JSON-compatible via :meth:`to_dict`).

    Attributes
    ----------
    time : float
        Current communication point [s].
    lateral_displacement, yaw_angle, lateral_velocity, yaw_rate : float
        y [m], psi [rad], y' [m/s], psi' [rad/s].
    steps : int
        Successful steps taken.
    previous : tuple of float or None
        ``(y, psi, y', psi')`` at the previous communication point (the reference of ``force_lag = 1``); None
        before the first step.
    """

    time: float
    lateral_displacement: float
    yaw_angle: float
    lateral_velocity: float
    yaw_rate: float
    steps: int = 0
    previous: tuple[float, float, float, float] | None = None

    @property
    def vector(self) -> np.ndarray:
        """``(y, psi, y', psi')``."""
        return np.array([self.lateral_displacement, self.yaw_angle, self.lateral_velocity, self.yaw_rate])

    def to_dict(self) -> dict:
        """JSON-compatible dict (floats survive ``json`` exactly)."""
        data = {name: getattr(self, name) for name in self.__slots__}
        data["previous"] = None if self.previous is None else list(self.previous)
        return data

    @classmethod
    def from_dict(cls, data: dict) -> WheelsetState:
        """Inverse of :meth:`to_dict`; every field checked (WheelsetError naming the first problem)."""
        if not isinstance(data, dict) or set(data) != set(cls.__slots__):
            raise WheelsetError(f"a wheelset state has the keys {list(cls.__slots__)}, got {data!r:.200}")
        previous = data["previous"]
        for name in cls.__slots__:
            value = data[name]
            if name == "steps":
                ok = type(value) is int and value >= 0
            elif name == "previous":
                ok = value is None or (isinstance(value, list) and len(value) == 4 and all(
                    type(v) in (int, float) and math.isfinite(v) for v in value))
            else:
                ok = type(value) in (int, float) and math.isfinite(value)
            if not ok:
                raise WheelsetError(f"wheelset state: {name} = {value!r:.80} is out of range or not a finite number")
        return cls(*(float(data[name]) for name in cls.__slots__[:5]), data["steps"],
                   None if previous is None else tuple(float(v) for v in previous))


class WheelsetModel:
    """The suspended wheelset (module docstring), advanced one macro step at a time with given contact forces.

    Parameters
    ----------
    parameters : WheelsetParameters, optional
    start_time : float
        t_0 [s].
    """

    def __init__(self, parameters: WheelsetParameters | None = None, *, start_time: float = 0.0):
        p = WheelsetParameters() if parameters is None else parameters
        if not isinstance(p, WheelsetParameters):
            raise TypeError(f"parameters must be WheelsetParameters, got {type(p).__name__}")
        self.parameters = p
        self.reset(start_time)

    def reset(self, start_time: float = 0.0) -> None:
        """Back to the initial state at ``start_time`` [s]."""
        self.state = WheelsetState(float(start_time), *(float(v) for v in self.parameters.initial_state))

    def get_state(self) -> WheelsetState:
        """A copy of the current state."""
        return WheelsetState(*(getattr(self.state, name) for name in WheelsetState.__slots__))

    def set_state(self, state: WheelsetState) -> None:
        """Continue from (a copy of) ``state``."""
        if not isinstance(state, WheelsetState):
            raise TypeError(f"state must be a WheelsetState, got {type(state).__name__}")
        self.state = WheelsetState(*(getattr(state, name) for name in WheelsetState.__slots__))

    def creepages(self, state=None) -> np.ndarray:
        """:func:`creepages` in the current state (or the state vector given), rows left and right."""
        return creepages(self.parameters, self.state.vector if state is None else state)

    def outputs(self) -> tuple[float, ...]:
        """The host FMU's outputs: per contact (left, right) N [N], xi, eta [1], phi [1/m], V [m/s], then
        y [m], psi [rad], y' [m/s], psi' [rad/s], then the WheelsetContact's inputs (:data:`TRACK_OUTPUTS`)."""
        p = self.parameters
        c = self.creepages()
        per_contact = [value for k in range(2) for value in (p.normal_load, *map(float, c[k]), p.speed)]
        y, psi, vy, rate = map(float, self.state.vector)
        track = (-y, -psi, -vy, -rate, p.speed, -p.speed / p.rolling_radius, p.normal_load, p.normal_load)
        return (*per_contact, y, psi, vy, rate, *track)

    def rhs(self, state, forces) -> np.ndarray:
        """``ds/dt`` with the contact forces ``forces`` (2x3: rows left, right; Fx, Fy, Mz on the rail)."""
        p = self.parameters
        y, psi, vy, rate = state
        forces = np.asarray(forces, dtype=float)
        cos, sin = math.cos(psi), math.sin(psi)
        lateral = -float(np.sum(forces[:, 0]) * sin + np.sum(forces[:, 1]) * cos)
        moment = p.contact_half_distance * (forces[0, 0] - forces[1, 0]) - forces[0, 2] - forces[1, 2]
        return np.array([vy, rate,
                         (lateral - p.lateral_stiffness * y - p.lateral_damping * vy) / p.mass,
                         (moment - p.yaw_stiffness * psi - p.yaw_damping * rate) / p.yaw_inertia])

    def rhs_jacobian(self, state, forces, force_jacobians) -> np.ndarray:
        """Jacobian (4x4) of :meth:`rhs` with the forces ``F_n + K (c(s) - c_n)`` (``force_jacobians``: 2x3x3)."""
        p = self.parameters
        psi = state[1]
        forces = np.asarray(forces, dtype=float)
        cos, sin = math.cos(psi), math.sin(psi)
        jac = np.zeros((4, 4))
        jac[0, 2] = jac[1, 3] = 1.0
        jac[2, 0] = -p.lateral_stiffness / p.mass
        jac[2, 2] = -p.lateral_damping / p.mass
        jac[3, 1] = -p.yaw_stiffness / p.yaw_inertia
        jac[3, 3] = -p.yaw_damping / p.yaw_inertia
        jac[2, 1] -= float(np.sum(forces[:, 0]) * cos - np.sum(forces[:, 1]) * sin) / p.mass
        # d(accelerations)/d(forces) of each contact, times dF/dc, times dc/ds
        dc_ds = creepage_jacobian(p, state)
        for k, side in enumerate((1.0, -1.0)):
            d_accel_d_force = np.array([[-sin / p.mass, -cos / p.mass, 0.0],
                                        [side * p.contact_half_distance / p.yaw_inertia, 0.0, -1.0 / p.yaw_inertia]])
            jac[2:] += d_accel_d_force @ np.asarray(force_jacobians[k], dtype=float) @ dc_ds[k]
        return jac

    def advance(self, state, h: float, forces, force_jacobians) -> np.ndarray:
        """One linearly implicit trapezoidal step ``s + (I - h W/2)^(-1) h f(s)`` (module docstring)."""
        w = self.rhs_jacobian(state, forces, force_jacobians)
        return state + np.linalg.solve(np.eye(4) - 0.5 * h * w, h * self.rhs(state, forces))

    def step(self, current_time: float, step_size: float, forces, force_jacobians=None) -> np.ndarray:
        """Advance from ``current_time`` by ``step_size`` with the contact forces at the step's start; the state.

        Parameters
        ----------
        current_time, step_size : float
            t_n [s] (the model's time) and H [s] > 0.
        forces : array_like (2, 3)
            ``F_n``: Fx, Fy [N], Mz [N m] on the rail of the left and right contacts at the creepages of t_n.
        force_jacobians : array_like (2, 3, 3), optional
            ``dF/d(xi, eta, phi)`` per contact at those creepages; None: zero (the forces held over the step).

        Raises
        ------
        WheelsetError
            A non-finite argument or result, a time that is not the model's; the state is then unchanged.
        """
        forces = np.asarray(forces, dtype=float)
        jacobians = np.zeros((2, 3, 3)) if force_jacobians is None else np.asarray(force_jacobians, dtype=float)
        if forces.shape != (2, 3) or jacobians.shape != (2, 3, 3):
            raise WheelsetError(f"forces must be 2x3 and force_jacobians 2x3x3, got {forces.shape} and "
                                f"{jacobians.shape}")
        for name, value in (("forces", forces), ("force_jacobians", jacobians)):
            if not np.all(np.isfinite(value)):
                raise WheelsetError(f"{name} = {value.tolist()!r} is not finite")
        if not (math.isfinite(step_size) and step_size > 0.0):
            raise WheelsetError(f"step_size = {step_size!r} s is out of range: it must be finite and > 0")
        now = self.state.time
        if not abs(current_time - now) <= 1e-9 * max(1.0, abs(now)):
            raise WheelsetError(f"current_time = {current_time!r} s is not the model time {now!r} s")
        # the forces are linearised about the creepages they belong to: F(c) = F_n + K (c - c_ref)
        p = self.parameters
        before = self.state
        lagged = p.force_lag == 1 and before.previous is not None
        reference = self.creepages(np.array(before.previous) if lagged else None)
        h = step_size / p.substeps
        state = before.vector
        for _ in range(p.substeps):
            local = forces + np.einsum("kij,kj->ki", jacobians, self.creepages(state) - reference)
            state = self.advance(state, h, local, jacobians)
        if not np.all(np.isfinite(state)):
            raise WheelsetError(f"the step from t = {current_time!r} s with H = {step_size!r} s gave the non-finite "
                                f"state {state.tolist()!r}")
        self.state = WheelsetState(current_time + step_size, *map(float, state), before.steps + 1,
                                   tuple(map(float, before.vector)))
        return state

    def step_profiles(self, current_time: float, step_size: float, loads) -> np.ndarray:
        """Advance from ``current_time`` by ``step_size`` with a WheelsetContact's loads at the step's start; the
        state (``contact_model`` = profiles).

        ``loads`` are :data:`LOAD_INPUTS`: the lateral force F_y [N] and yaw moment M_z [N m] of the rails on the
        wheelset in track axes (y to the right, z down) at the state s_ref the contact evaluated them at (of t_n,
        or with ``force_lag = 1`` of t_(n-1)), and their derivatives ``J`` in the track state ``q = -s`` (lateral
        shift, yaw, their rates).  In the host's axes the loads are ``-F_y``, ``-M_z``, linearised as
        ``-F_y + J_F (s - s_ref)``, ``-M_z + J_M (s - s_ref)`` (the signs of q and of the loads cancel), and the
        linearly implicit trapezoidal rule integrates ``m y'' = -F_y(s) - k_y y - c_y y'``, ``I psi'' = -M_z(s) -
        k_psi psi - c_psi psi'`` as :meth:`step` does the cones' (module docstring).

        Raises
        ------
        WheelsetError
            A non-finite argument or result, a time that is not the model's, or ``contact_model`` = cones; the
            state is then unchanged.
        """
        p = self.parameters
        if p.contact_model != 1:
            raise WheelsetError("step_profiles takes a WheelsetContact's loads: set contact_model = 1 (profiles)")
        loads = np.asarray(loads, dtype=float)
        if loads.shape != (len(LOAD_INPUTS),) or not np.all(np.isfinite(loads)):
            raise WheelsetError(f"loads must be {len(LOAD_INPUTS)} finite numbers ({', '.join(LOAD_INPUTS)}), got "
                                f"{loads.tolist()!r}")
        self.check_time(current_time, step_size)
        before = self.state
        lagged = p.force_lag == 1 and before.previous is not None
        reference = np.array(before.previous) if lagged else before.vector
        force, moment, slopes = -loads[0], -loads[1], loads[2:].reshape(2, 4)
        jac = np.zeros((4, 4))
        jac[0, 2] = jac[1, 3] = 1.0
        jac[2] = slopes[0] / p.mass
        jac[3] = slopes[1] / p.yaw_inertia
        jac[2, 0] -= p.lateral_stiffness / p.mass
        jac[2, 2] -= p.lateral_damping / p.mass
        jac[3, 1] -= p.yaw_stiffness / p.yaw_inertia
        jac[3, 3] -= p.yaw_damping / p.yaw_inertia
        h = step_size / p.substeps
        matrix = np.eye(4) - 0.5 * h * jac
        state = before.vector
        for _ in range(p.substeps):
            offset = state - reference
            y, psi, vy, rate = state
            rhs = np.array([vy, rate,
                            (force + slopes[0] @ offset - p.lateral_stiffness * y - p.lateral_damping * vy) / p.mass,
                            (moment + slopes[1] @ offset - p.yaw_stiffness * psi - p.yaw_damping * rate)
                            / p.yaw_inertia])
            state = state + np.linalg.solve(matrix, h * rhs)
        if not np.all(np.isfinite(state)):
            raise WheelsetError(f"the step from t = {current_time!r} s with H = {step_size!r} s gave the non-finite "
                                f"state {state.tolist()!r}")
        self.state = WheelsetState(current_time + step_size, *map(float, state), before.steps + 1,
                                   tuple(map(float, before.vector)))
        return state

    def check_time(self, current_time: float, step_size: float) -> None:
        """WheelsetError unless ``step_size`` is finite and > 0 and ``current_time`` the model's time."""
        if not (math.isfinite(step_size) and step_size > 0.0):
            raise WheelsetError(f"step_size = {step_size!r} s is out of range: it must be finite and > 0")
        now = self.state.time
        if not abs(current_time - now) <= 1e-9 * max(1.0, abs(now)):
            raise WheelsetError(f"current_time = {current_time!r} s is not the model time {now!r} s")



def simulate(parameters: WheelsetParameters, law: CreepForceLaw, stop_time: float, step_size: float,
             *, implicit: bool = True, jacobi: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """In-process run: times [s] and states (rows ``y, psi, y', psi'``) at every step of ``step_size`` [s].

    Each step evaluates ``law`` (and its Jacobian when ``implicit``) at the step's creepages and calls
    :meth:`WheelsetModel.step`: the sequence a Gauss-Seidel co-simulation master runs with a contact FMU.  With
    ``jacobi`` the law is evaluated at the creepages of the previous communication point, and the first step sees
    zero forces and Jacobians (a contact FMU's start values), as in a Jacobi master; set ``force_lag = 1`` then.
    """
    model = WheelsetModel(parameters)
    n = int(round(stop_time / step_size))
    if n < 1 or abs(n * step_size - stop_time) > 1e-9 * stop_time:
        raise WheelsetError(f"stop_time = {stop_time!r} s is not a positive multiple of step_size = {step_size!r} s")
    p = parameters
    states = np.empty((n + 1, 4))
    states[0] = model.state.vector
    forces = np.empty((2, 3))
    jacobians = np.zeros((2, 3, 3))
    previous = None
    for i in range(n):
        creep = model.creepages()
        if jacobi:
            creep, previous = previous, creep
        if creep is None:
            forces[:] = 0.0
            jacobians[:] = 0.0
            states[i + 1] = model.step(i * step_size, step_size, forces, jacobians)
            continue
        for k in range(2):
            forces[k] = law(p.normal_load, *creep[k], p.speed)
            if implicit:
                jacobians[k] = law.jacobian(p.normal_load, *creep[k], p.speed)
        states[i + 1] = model.step(i * step_size, step_size, forces, jacobians)
    return np.arange(n + 1) * step_size, states


def simulate_profiles(parameters: WheelsetParameters, contact, stop_time: float, step_size: float, *,
                      jacobi: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """In-process run of the wheelset on profiles: times [s] and states (rows ``y, psi, y', psi'``) at every step.

    ``contact`` is the WheelsetContact's model (a :class:`rollcontact.stepping.WheelsetContactModel`), stepped at
    each communication point with the host's :data:`TRACK_OUTPUTS` before the host steps with its loads
    (:meth:`WheelsetModel.step_profiles`): the sequence a Gauss-Seidel master runs with the two FMUs.  With ``jacobi``
    the host takes the loads of the previous communication point (zero at the first, the contact FMU's start values)
    and ``parameters.force_lag`` must be 1.
    """
    if parameters.contact_model != 1:
        raise WheelsetError("simulate_profiles runs the wheelset on profiles: set contact_model = 1")
    model = WheelsetModel(parameters)
    n = int(round(stop_time / step_size))
    if n < 1 or abs(n * step_size - stop_time) > 1e-9 * stop_time:
        raise WheelsetError(f"stop_time = {stop_time!r} s is not a positive multiple of step_size = {step_size!r} s")
    states = np.empty((n + 1, 4))
    states[0] = model.state.vector
    names = ("force_y", "moment_yaw", *LOAD_INPUTS[2:])
    held = np.zeros(len(LOAD_INPUTS))
    track = len(OUTPUT_NAMES) - len(TRACK_OUTPUTS)
    for i in range(n):
        t = i * step_size
        outputs = contact.step(t, step_size, model.outputs()[track:])
        loads = np.array([getattr(outputs, name) for name in names])
        if jacobi:
            loads, held = held, loads
        states[i + 1] = model.step_profiles(t, step_size, loads)
    return np.arange(n + 1) * step_size, states
