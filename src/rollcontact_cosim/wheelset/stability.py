"""Linear stability of the wheelset of :mod:`rollcontact_cosim.wheelset` with Kalker's linear creep forces.

The linearised equations (Wickens 1965; Knothe & Boehm 1999; Iwnicki, Handbook of Railway Vehicle Dynamics,
ch. stability), with ``f11, f22, f23, f33`` of :class:`~rollcontact_cosim.wheelset.KalkerLinearLaw` per contact::

    m y''   + (2 f22 / V + c_y) y'  + k_y y   - 2 f22 psi + (2 f23 / V) psi'                                  = 0
    I psi'' + (2 e^2 f11 / V + 2 f33 / V + c_psi) psi' + (k_psi + 2 f23) psi + (2 e f11 lambda / r0) y
            - (2 f23 / V) y'                                                                                  = 0

give ``s' = A(V) s`` with ``s = (y, psi, y', psi')`` (:func:`state_matrix`).  The critical speed is where the
real part of the least-damped eigenvalue of A(V) crosses zero from below (:func:`critical_speed`, root bracketing
in V).  Without suspension and inertia the motion is Klingel's kinematic oscillation (Klingel 1883): ``xi = 0``
and ``eta = 0`` give ``y'' = -(V^2 lambda / (e r0)) y``, wavelength ``L = 2 pi sqrt(r0 e / lambda)``, frequency
``V / L`` (:func:`klingel_wavelength`).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from rollcontact_cosim.wheelset.model import KalkerLinearLaw, WheelsetError, WheelsetParameters

__all__ = ["critical_speed", "eigenvalues", "kinematic_frequency", "klingel_wavelength", "least_damped", "linearised",
           "state_matrix"]


def linearised(law, parameters: WheelsetParameters) -> KalkerLinearLaw:
    """The linear law with the coefficients of ``law.jacobian`` at zero creepage (a KalkerLinearLaw as it is)."""
    if isinstance(law, KalkerLinearLaw):
        return law
    jac = law.jacobian(parameters.normal_load, 0.0, 0.0, 0.0, parameters.speed)
    return KalkerLinearLaw(float(jac[0, 0]), float(jac[1, 1]), float(jac[1, 2]), float(jac[2, 2]))


def state_matrix(parameters: WheelsetParameters, law: KalkerLinearLaw) -> np.ndarray:
    """A (4x4) of the linearised equations (module docstring) at ``parameters.speed``."""
    p = parameters
    v, e, r0 = p.speed, p.contact_half_distance, p.rolling_radius
    m, inertia = p.mass, p.yaw_inertia
    f11, f22, f23, f33 = law.f11, law.f22, law.f23, law.f33
    stiffness = np.array([[p.lateral_stiffness, -2.0 * f22],
                          [2.0 * e * f11 * p.conicity / r0, p.yaw_stiffness + 2.0 * f23]])
    damping = np.array([[2.0 * f22 / v + p.lateral_damping, 2.0 * f23 / v],
                        [-2.0 * f23 / v, 2.0 * (e * e * f11 + f33) / v + p.yaw_damping]])
    inverse_mass = np.diag([1.0 / m, 1.0 / inertia])
    return np.block([[np.zeros((2, 2)), np.eye(2)], [-inverse_mass @ stiffness, -inverse_mass @ damping]])


def eigenvalues(parameters: WheelsetParameters, law: KalkerLinearLaw) -> np.ndarray:
    """Eigenvalues [1/s] of :func:`state_matrix`, by decreasing real part."""
    values = np.linalg.eigvals(state_matrix(parameters, law))
    return values[np.argsort(-values.real, kind="stable")]


def least_damped(parameters: WheelsetParameters, law: KalkerLinearLaw) -> complex:
    """The eigenvalue with the largest real part [1/s] (of the pair, the one with imaginary part >= 0)."""
    value = eigenvalues(parameters, law)[0]
    return complex(value.real, abs(value.imag))


def critical_speed(parameters: WheelsetParameters, law: KalkerLinearLaw, speeds=None,
                   rtol: float = 1e-10) -> float:
    """The lowest speed V [m/s] at which ``max Re(eigenvalue)`` crosses zero from below.

    ``speeds`` (default 1 ... 300 m/s in steps of 1 m/s) brackets the crossing; ``brentq`` refines it to ``rtol``.

    Raises
    ------
    WheelsetError
        No crossing in ``speeds`` (stable or unstable throughout).
    """
    from scipy.optimize import brentq

    grid = np.arange(1.0, 301.0) if speeds is None else np.asarray(speeds, dtype=float)

    def growth(speed):
        return least_damped(dataclasses.replace(parameters, speed=float(speed)), law).real

    rates = [growth(v) for v in grid]
    for k in range(len(grid) - 1):
        if rates[k] < 0.0 <= rates[k + 1]:
            return float(brentq(growth, grid[k], grid[k + 1], rtol=rtol))
    state = "stable" if rates[-1] < 0.0 else "unstable"
    raise WheelsetError(f"no critical speed in {grid[0]:g} ... {grid[-1]:g} m/s: the wheelset is {state} at "
                        f"{grid[-1]:g} m/s and no zero crossing of the least-damped eigenvalue lies between")


def klingel_wavelength(parameters: WheelsetParameters) -> float:
    """Klingel's wavelength ``2 pi sqrt(r0 e / lambda)`` [m] (conicity > 0)."""
    p = parameters
    if not p.conicity > 0.0:
        raise WheelsetError(f"conicity = {p.conicity!r} is out of range: Klingel's wavelength needs lambda > 0")
    return 2.0 * math.pi * math.sqrt(p.rolling_radius * p.contact_half_distance / p.conicity)


def kinematic_frequency(parameters: WheelsetParameters) -> float:
    """Klingel's frequency ``V / L`` [Hz] at ``parameters.speed``: the hunting frequency in the kinematic limit."""
    return parameters.speed / klingel_wavelength(parameters)
