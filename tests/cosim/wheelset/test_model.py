"""The wheelset host model: kinematics, the in-process creep-force laws, the linearly implicit step and its
contract."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import rollcontact
from rollcontact_cosim.wheelset import (
    SaturatedKalkerLaw,
    WheelsetError,
    WheelsetModel,
    WheelsetParameters,
    creepage_jacobian,
    creepages,
    linear_law,
    simulate,
)
from rollcontact_cosim.wheelset.stability import klingel_wavelength
from rollcontact_cosim.wheelset.study import decay_rate

P = WheelsetParameters()
LAW = linear_law(P)


# kinematics ---------------------------------------------------------------------------------------------------
def test_a_lateral_displacement_gives_opposite_longitudinal_creepages_and_no_lateral_one():
    y = 2e-3
    c = creepages(P, (y, 0.0, 0.0, 0.0))
    expected = P.conicity * y / P.rolling_radius
    assert c[0, 0] == pytest.approx(-expected, rel=1e-12), "left wheel on the larger radius: xi_L = -lambda y / r0"
    assert c[1, 0] == pytest.approx(expected, rel=1e-12), "right wheel on the smaller radius: xi_R = +lambda y / r0"
    assert c[0, 1] == c[1, 1] == 0.0, "a pure displacement gives no lateral creepage"


def test_yaw_gives_lateral_creepage_and_yaw_rate_longitudinal_and_spin():
    psi, rate, vy = 2e-3, 0.05, 0.01
    c = creepages(P, (0.0, psi, 0.0, 0.0))
    assert c[0, 1] == c[1, 1] == pytest.approx(-math.sin(psi), rel=1e-12), "yaw: eta = -sin psi on both wheels"
    assert abs(c[0, 0]) < 1e-5 and c[0, 0] == c[1, 0], "yaw alone: xi = cos psi - 1, second order, equal"
    c = creepages(P, (0.0, 0.0, vy, rate))
    assert c[0, 1] == pytest.approx(vy / P.speed, rel=1e-12), "a lateral velocity: eta = y'/V"
    e_rate = P.contact_half_distance * rate / P.speed
    assert (c[0, 0], c[1, 0]) == pytest.approx((-e_rate, e_rate), rel=1e-12), "yaw rate: xi = -/+ e psi'/V"
    spin = P.contact_angle / P.rolling_radius
    assert (c[0, 2], c[1, 2]) == pytest.approx((rate / P.speed - spin, rate / P.speed + spin), rel=1e-12), \
        "spin: psi'/V -/+ delta0/r0"


def test_the_creep_forces_steer_a_displaced_wheelset_back_to_the_centre(law_rhs):
    model = WheelsetModel(dataclasses.replace(P, lateral_stiffness=0.0, yaw_stiffness=0.0))
    accel = law_rhs(model, LAW, np.array([1e-3, 0.0, 0.0, 0.0]))
    assert accel[3] < 0.0, f"y > 0 must yaw the nose to the right (psi'' < 0), got {accel[3]!r}"
    accel = law_rhs(model, LAW, np.array([0.0, -1e-3, 0.0, 0.0]))
    assert accel[2] < 0.0, f"psi < 0 (nose right) must push the wheelset right (y'' < 0), got {accel[2]!r}"


def test_the_creepage_jacobian_is_the_derivative_of_the_creepages(finite_difference):
    state = np.array([3e-3, 4e-3, 0.02, -0.03])
    numeric = finite_difference(lambda s: creepages(P, s), state, 1e-6)
    assert np.allclose(creepage_jacobian(P, state), numeric, rtol=1e-7, atol=1e-10), "dc/ds"


# contact geometry and laws ---------------------------------------------------------------------------------------
def test_the_linear_law_takes_the_librarys_ellipse_and_coefficients():
    """f11 = G c^2 C11, f22 = G c^2 C22, f23 = G c^3 C23 with rollcontact's Hertz ellipse and Kalker coefficients,
    on the circle of the default (rail profile radius r0) and the ellipse of a 0.3 m rail head; on the circle the
    coefficients are Kalker's Table E.3 (a/b = 1, nu = 0.25: 4.12, 3.67, 1.47) within 0.3 %."""
    shear = 210e9 / 2.5
    for rail in (None, 0.3):
        ellipse = rollcontact.hertz_ellipse(P.normal_load, 0.5 / P.rolling_radius,
                                            0.5 / (P.rolling_radius if rail is None else rail), 210e9 / 1.875)
        c11, c22, c23, _ = rollcontact.creepage_coefficients(ellipse.aspect_ratio, 0.25)
        law = linear_law(P, rail_profile_radius=rail, spin=True)
        c2 = ellipse.a * ellipse.b
        assert law.f11 == pytest.approx(shear * c2 * c11, rel=1e-15), f"f11 = G c^2 C11 (rail {rail})"
        assert law.f22 == pytest.approx(shear * c2 * c22, rel=1e-15), f"f22 = G c^2 C22 (rail {rail})"
        assert law.f23 == pytest.approx(shear * c2 ** 1.5 * c23, rel=1e-14), f"f23 = G c^3 C23 (rail {rail})"
        assert law.f33 == 0.0 and linear_law(P, rail_profile_radius=rail).f23 == 0.0, "spin terms only with spin"
    a = (3 * P.normal_load * P.rolling_radius / (4 * 210e9 / 1.875)) ** (1 / 3)
    assert LAW.f11 == pytest.approx(shear * a * a * 4.12, rel=3e-3), "Kalker's C11 = 4.12 on the circle"
    assert LAW.f22 == pytest.approx(shear * a * a * 3.67, rel=3e-3), "Kalker's C22 = 3.67 on the circle"
    with pytest.raises(ValueError, match="aspect ratio a/b"):
        linear_law(P, rail_profile_radius=1e-3)


def test_the_saturated_law_is_linear_at_small_creepage_and_bounded_by_friction():
    law = SaturatedKalkerLaw(LAW, 0.3)
    assert np.allclose(law.jacobian(P.normal_load, 0.0, 0.0, 0.0, P.speed), LAW.jacobian(0, 0, 0, 0, 0),
                       rtol=1e-6), "the slope at zero creepage is Kalker's"
    for xi, eta in ((0.01, 0.0), (0.3, -0.2), (1e-4, 2e-4)):
        fx, fy, _ = law(P.normal_load, xi, eta, 0.0, P.speed)
        assert math.hypot(fx, fy) <= 0.3 * P.normal_load * (1 + 1e-12), f"|F| <= mu N at ({xi}, {eta})"


def test_the_rhs_jacobian_with_linearised_forces_is_the_derivative_of_the_nonlinear_rhs(law_rhs, finite_difference):
    model = WheelsetModel(dataclasses.replace(P, lateral_damping=2e3))
    law = SaturatedKalkerLaw(linear_law(P, spin=True))
    state = np.array([4e-3, -3e-3, 0.05, 0.08])
    c = creepages(P, state)
    forces = np.array([law(P.normal_load, *c[k], P.speed) for k in range(2)])
    jacobians = np.array([law.jacobian(P.normal_load, *c[k], P.speed) for k in range(2)])
    numeric = finite_difference(lambda s: law_rhs(model, law, s), state, 1e-8)
    assert np.allclose(model.rhs_jacobian(state, forces, jacobians), numeric, rtol=1e-5,
                       atol=1e-6 * np.max(np.abs(numeric))), "W of the linearly implicit step"


# the model's contract ------------------------------------------------------------------------------------------
def test_bad_parameters_and_steps_are_refused_with_the_value():
    with pytest.raises(WheelsetError, match="speed = -1"):
        WheelsetParameters(speed=-1.0)
    with pytest.raises(WheelsetError, match="yaw_stiffness = nan"):
        WheelsetParameters(yaw_stiffness=float("nan"))
    with pytest.raises(WheelsetError, match="conicity = 0"):
        klingel_wavelength(WheelsetParameters(conicity=0.0))
    model = WheelsetModel()
    before = model.get_state()
    with pytest.raises(WheelsetError, match="not finite"):
        model.step(0.0, 1e-3, [[float("nan"), 0, 0], [0, 0, 0]])
    with pytest.raises(WheelsetError, match="not the model time"):
        model.step(1.0, 1e-3, np.zeros((2, 3)))
    assert model.get_state() == before, "a refused step leaves the state"


def test_a_saved_state_continues_bit_for_bit():
    model = WheelsetModel()
    forces = np.array([[1e3, -2e3, 5.0], [-1e3, 3e3, -4.0]])
    model.step(0.0, 1e-3, forces)
    saved = model.get_state()
    first = model.step(1e-3, 1e-3, forces).copy()
    model.set_state(saved)
    assert np.array_equal(model.step(1e-3, 1e-3, forces), first), "restored state, same step, same bits"


def test_a_jacobi_master_with_force_lag_integrates_the_gauss_seidel_motion():
    """Forces of the previous communication point, linearised about the creepages they belong to (force_lag = 1),
    give the Gauss-Seidel motion (exactly, for a linear law, after the first step's zero forces); linearised about
    the current ones (force_lag = 0) they lag a step and destabilise the coarse step."""
    rates = {}
    for label, jacobi, lag in (("gauss-seidel", False, 0), ("jacobi", True, 1), ("jacobi, no lag", True, 0)):
        p = dataclasses.replace(P, speed=60.0, force_lag=lag)
        period = klingel_wavelength(p) / p.speed
        times, states = simulate(p, LAW, 0.005 * 320, 0.005, jacobi=jacobi)
        rates[label] = decay_rate(times, states[:, 0], start=2 * period, limit=0.01)[0]
    assert rates["gauss-seidel"] < 0.0, rates
    assert rates["jacobi"] == pytest.approx(rates["gauss-seidel"], rel=1e-4), f"force_lag = 1: {rates}"
    assert rates["jacobi, no lag"] > 0.0, f"force_lag = 0 under Jacobi with H = 5 ms must be unstable: {rates}"
    with pytest.raises(WheelsetError, match="force_lag = 2"):
        WheelsetParameters(force_lag=2)
