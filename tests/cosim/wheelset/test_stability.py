"""The linearised wheelset: its state matrix against the nonlinear right-hand side, eigenvalues, critical speed
(against Hurwitz's determinant) and Klingel's frequency."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rollcontact_cosim.wheelset import (
    KalkerLinearLaw,
    SaturatedKalkerLaw,
    WheelsetError,
    WheelsetModel,
    WheelsetParameters,
    linear_law,
    simulate,
)
from rollcontact_cosim.wheelset.stability import (
    critical_speed,
    eigenvalues,
    klingel_wavelength,
    least_damped,
    state_matrix,
)

P = WheelsetParameters()
LAW = linear_law(P)


# linear stability ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("speed", [10.0, 63.9, 120.0])
@pytest.mark.parametrize("law", [SaturatedKalkerLaw(LAW), linear_law(P, spin=True)], ids=["saturated", "spin"])
def test_the_state_matrix_is_the_jacobian_of_the_nonlinear_right_hand_side(speed, law, law_rhs, finite_difference):
    """Exact trigonometric kinematics, and either the saturated law (nonlinear forces) or the linear law with the
    spin terms f23 (with spin, a saturated law is pre-loaded by the conicity's spin in the centred state)."""
    p = dataclasses.replace(P, speed=speed, lateral_damping=2e3, yaw_damping=1e3)
    model = WheelsetModel(p)
    numeric = finite_difference(lambda s: law_rhs(model, law, s), np.zeros(4), 1e-8)
    analytic = state_matrix(p, getattr(law, "linear", law))
    assert np.allclose(analytic, numeric, rtol=1e-5, atol=1e-6 * np.max(np.abs(analytic))), \
        f"A(V) against the finite-difference Jacobian at {speed} m/s:\n{analytic}\n{numeric}"
    exact, approx = np.sort_complex(np.linalg.eigvals(analytic)), np.sort_complex(np.linalg.eigvals(numeric))
    assert np.allclose(exact, approx, rtol=1e-5), f"eigenvalues {exact} against {approx}"


def test_without_creep_forces_and_damping_the_suspension_oscillates_undamped():
    p = dataclasses.replace(P, lateral_damping=0.0, yaw_damping=0.0)
    values = eigenvalues(p, KalkerLinearLaw(0.0, 0.0))
    assert np.max(np.abs(values.real)) == 0.0, f"purely imaginary eigenvalues, got {values}"
    expected = sorted([math.sqrt(p.lateral_stiffness / p.mass), math.sqrt(p.yaw_stiffness / p.yaw_inertia)] * 2)
    assert sorted(np.abs(values.imag)) == pytest.approx(expected, rel=1e-12), "sqrt(k_y/m), sqrt(k_psi/I)"
    # the trapezoidal step keeps the energy of an undamped linear system exactly
    p = dataclasses.replace(p, initial_yaw_angle=2e-3, initial_lateral_velocity=0.01)
    _, states = simulate(p, KalkerLinearLaw(0.0, 0.0), 1.0, 1e-2)
    energy = 0.5 * (p.lateral_stiffness * states[:, 0] ** 2 + p.yaw_stiffness * states[:, 1] ** 2
                    + p.mass * states[:, 2] ** 2 + p.yaw_inertia * states[:, 3] ** 2)
    assert np.ptp(energy) <= 1e-12 * energy[0], f"energy drifts by {np.ptp(energy) / energy[0]:.2e}"


def test_the_critical_speed_is_a_zero_of_the_least_damped_eigenvalue():
    vc = critical_speed(P, LAW)
    assert 30.0 < vc < 150.0, f"default parameters give a critical speed of {vc} m/s"
    assert abs(least_damped(dataclasses.replace(P, speed=vc), LAW).real) < 1e-8, "Re = 0 at V_c"
    assert least_damped(dataclasses.replace(P, speed=0.95 * vc), LAW).real < 0.0 < \
        least_damped(dataclasses.replace(P, speed=1.05 * vc), LAW).real, "stable below, unstable above"
    assert critical_speed(dataclasses.replace(P, yaw_stiffness=5e6), LAW) > vc, "a stiffer yaw raises V_c"
    with pytest.raises(WheelsetError, match="no critical speed in 1 ... 20 m/s"):
        critical_speed(P, LAW, speeds=np.arange(1.0, 21.0))


def hurwitz(p: WheelsetParameters, law: KalkerLinearLaw, speed: float) -> float:
    """Hurwitz's determinant ``a3 a2 a1 - a1^2 a4 - a3^2 a0`` of the characteristic polynomial, expanded by hand
    (no spin terms): ``(m s^2 + a s + k_y)(I s^2 + b s + k_psi) + 4 f22 f11 e lambda / r0``,
    ``a = 2 f22 / V + c_y``, ``b = 2 e^2 f11 / V + c_psi``; > 0 stable, < 0 unstable (all a_i > 0)."""
    a = 2 * law.f22 / speed + p.lateral_damping
    b = 2 * p.contact_half_distance ** 2 * law.f11 / speed + p.yaw_damping
    a4, a3 = p.mass * p.yaw_inertia, p.mass * b + p.yaw_inertia * a
    a2 = p.mass * p.yaw_stiffness + a * b + p.yaw_inertia * p.lateral_stiffness
    a1 = a * p.yaw_stiffness + b * p.lateral_stiffness
    a0 = p.lateral_stiffness * p.yaw_stiffness + 4 * law.f22 * law.f11 * p.contact_half_distance * p.conicity \
        / p.rolling_radius
    return a3 * a2 * a1 - a1 ** 2 * a4 - a3 ** 2 * a0


@pytest.mark.parametrize("changes", [{}, {"yaw_stiffness": 5e6, "lateral_damping": 1e4}, {"conicity": 0.3}])
def test_the_critical_speed_is_where_hurwitzs_determinant_vanishes(changes):
    from scipy.optimize import brentq

    p = dataclasses.replace(P, **changes)
    expected = brentq(lambda v: hurwitz(p, LAW, v), 5.0, 300.0, rtol=1e-13)
    assert critical_speed(p, LAW) == pytest.approx(expected, rel=1e-8), f"{changes}: eigenvalues against Hurwitz"


def test_at_low_speed_the_hunting_frequency_is_klingels():
    from rollcontact_cosim.wheelset.stability import kinematic_frequency

    p = dataclasses.replace(P, speed=2.0, lateral_stiffness=0.0, yaw_stiffness=0.0)
    mode = least_damped(p, LAW)
    assert mode.imag / (2 * math.pi) == pytest.approx(kinematic_frequency(p), rel=1e-4), "Im / 2 pi = V / L"
    assert kinematic_frequency(p) == pytest.approx(2.0 / klingel_wavelength(p), rel=1e-15)
