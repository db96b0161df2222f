"""The wheelset host model: kinematics, the in-process creep-force laws, the linearly implicit step and its
contract."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.special import ellipe, ellipk

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
from rollcontact_cosim.wheelset.model import hertz_semi_axes, kalker_coefficients
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
def test_hertz_gives_the_sphere_and_satisfies_both_of_johnsons_relations():
    e_star = 112e9
    a, b = hertz_semi_axes(80e3, 1.0, 1.0, e_star)
    assert a == b == pytest.approx((3 * 80e3 * 0.5 / (4 * e_star)) ** (1 / 3), rel=1e-14), "sphere"
    for big, small in ((0.5 / 0.3, 0.5 / 0.46), (40.0, 1.0)):
        a, b = hertz_semi_axes(80e3, small, big, e_star)
        assert a > b, "the longer axis lies along the smaller curvature"
        m = 1.0 - (b / a) ** 2
        p0 = 3 * 80e3 / (2 * math.pi * a * b)
        scale = p0 * b / (e_star * m * a * a)
        assert scale * (ellipk(m) - ellipe(m)) == pytest.approx(small, rel=1e-9), "A from a, b (Johnson 4.2)"
        assert scale * ((a / b) ** 2 * ellipe(m) - ellipk(m)) == pytest.approx(big, rel=1e-9), "B from a, b"
        assert hertz_semi_axes(80e3, big, small, e_star) == pytest.approx((b, a), rel=1e-14), "swapped curvatures"


def test_kalkers_table_and_the_linear_law():
    assert kalker_coefficients(1.0, 0.25) == pytest.approx((4.12, 3.67, 1.47), rel=1e-12), "table row a/b = 1"
    low, high = kalker_coefficients(1.0, 0.0), kalker_coefficients(2.0, 0.0)
    middle = kalker_coefficients(math.sqrt(2.0), 0.0)
    assert all(min(x, y) < z < max(x, y) for x, y, z in zip(low, high, middle, strict=True)), "between rows"
    with pytest.raises(WheelsetError, match="poisson_ratio = 0.3"):
        kalker_coefficients(1.0, 0.3)
    with pytest.raises(WheelsetError, match="a/b = 20"):
        kalker_coefficients(20.0, 0.25)
    shear, a = 210e9 / 2.5, hertz_semi_axes(P.normal_load, 0.5 / P.rolling_radius, 0.5 / P.rolling_radius,
                                           210e9 / 1.875)[0]
    assert LAW.f11 == pytest.approx(shear * a * a * 4.12, rel=1e-12), "f11 = G c^2 C11 on a circle"
    assert LAW.f22 == pytest.approx(shear * a * a * 3.67, rel=1e-12), "f22 = G c^2 C22"
    assert linear_law(P, spin=True).f23 == pytest.approx(shear * a ** 3 * 1.47, rel=1e-12), "f23 = G c^3 C23"


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
