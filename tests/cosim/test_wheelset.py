"""The hunting wheelset: kinematics, contact geometry, linear stability, and the in-process time simulations
against Klingel's wavelength and the eigenvalues' critical speed."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.special import ellipe, ellipk

from rollcontact_cosim.wheelset import (
    KalkerLinearLaw,
    SaturatedKalkerLaw,
    WheelsetError,
    WheelsetModel,
    WheelsetParameters,
    creepage_jacobian,
    creepages,
    hertz_semi_axes,
    kalker_coefficients,
    linear_law,
    simulate,
)
from rollcontact_cosim.wheelset_stability import (
    critical_speed,
    eigenvalues,
    klingel_wavelength,
    least_damped,
    state_matrix,
)
from rollcontact_cosim.wheelset_study import decay_rate, hunting_sweep, klingel_study, wavelength

P = WheelsetParameters()
LAW = linear_law(P)


def law_rhs(model, law, state):
    """ds/dt with the law's forces at the state's creepages (the nonlinear right-hand side)."""
    p = model.parameters
    c = creepages(p, state)
    forces = np.array([law(p.normal_load, *c[k], p.speed) for k in range(2)])
    return model.rhs(state, forces)


def finite_difference(function, x, step):
    x = np.asarray(x, dtype=float)
    columns = []
    for j in range(x.size):
        d = np.zeros_like(x)
        d[j] = step[j] if np.ndim(step) else step
        columns.append((np.asarray(function(x + d)) - np.asarray(function(x - d))) / (2.0 * d[j]))
    return np.stack(columns, axis=-1)


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


def test_the_creep_forces_steer_a_displaced_wheelset_back_to_the_centre():
    model = WheelsetModel(dataclasses.replace(P, lateral_stiffness=0.0, yaw_stiffness=0.0))
    accel = law_rhs(model, LAW, np.array([1e-3, 0.0, 0.0, 0.0]))
    assert accel[3] < 0.0, f"y > 0 must yaw the nose to the right (psi'' < 0), got {accel[3]!r}"
    accel = law_rhs(model, LAW, np.array([0.0, -1e-3, 0.0, 0.0]))
    assert accel[2] < 0.0, f"psi < 0 (nose right) must push the wheelset right (y'' < 0), got {accel[2]!r}"


def test_the_creepage_jacobian_is_the_derivative_of_the_creepages():
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


# linear stability ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("speed", [10.0, 63.9, 120.0])
@pytest.mark.parametrize("law", [SaturatedKalkerLaw(LAW), linear_law(P, spin=True)], ids=["saturated", "spin"])
def test_the_state_matrix_is_the_jacobian_of_the_nonlinear_right_hand_side(speed, law):
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


def test_the_rhs_jacobian_with_linearised_forces_is_the_derivative_of_the_nonlinear_rhs():
    model = WheelsetModel(dataclasses.replace(P, lateral_damping=2e3))
    law = SaturatedKalkerLaw(linear_law(P, spin=True))
    state = np.array([4e-3, -3e-3, 0.05, 0.08])
    c = creepages(P, state)
    forces = np.array([law(P.normal_load, *c[k], P.speed) for k in range(2)])
    jacobians = np.array([law.jacobian(P.normal_load, *c[k], P.speed) for k in range(2)])
    numeric = finite_difference(lambda s: law_rhs(model, law, s), state, 1e-8)
    assert np.allclose(model.rhs_jacobian(state, forces, jacobians), numeric, rtol=1e-5,
                       atol=1e-6 * np.max(np.abs(numeric))), "W of the linearly implicit step"


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


# time simulation ---------------------------------------------------------------------------------------------------
def test_the_measurements_recover_a_known_damped_oscillation():
    t = np.linspace(0.0, 5.0, 5001)
    y = 1e-3 * np.exp(-0.4 * t) * np.sin(2 * math.pi * 1.3 * t + 0.3)
    rate, peaks = decay_rate(t, y)
    assert rate == pytest.approx(-0.4, rel=2e-3) and peaks >= 12, f"decay rate {rate} from {peaks} peaks"
    assert wavelength(t, y, 10.0) == pytest.approx(10.0 / 1.3, rel=1e-4), "wavelength V / f"


def test_klingels_wavelength_within_2_percent_and_the_suspension_moves_it_away():
    points = klingel_study(P, LAW, speeds=(5.0,), suspension_scales=(1.0, 0.1, 0.0), periods=5)
    errors = [p.error for p in points]
    assert abs(errors[-1]) < 0.02, f"free wheelset at 5 m/s: wavelength off Klingel's by {errors[-1]:+.4%}"
    assert abs(errors[-1]) < 1e-3, f"the limit is reached to the step's phase error, got {errors[-1]:+.4%}"
    assert abs(errors[0]) > abs(errors[1]) > abs(errors[2]) - 1e-4, f"softer suspension, closer to Klingel: {errors}"
    for point in points:
        assert point.measured / point.eigenvalue - 1 == pytest.approx(0.0, abs=5e-4), \
            f"simulated wavelength {point.measured} against the eigenvalue's {point.eigenvalue}"


def test_the_simulated_critical_speed_matches_the_eigenvalues_within_5_percent():
    sweep = hunting_sweep([58.0, 62.0, 66.0, 70.0], P, LAW, periods=10, n_workers=0)
    assert sweep.simulated_critical_speed is not None, [r.simulated for r in sweep.runs]
    assert abs(sweep.error) < 0.05, f"simulated {sweep.simulated_critical_speed} against predicted " \
                                    f"{sweep.predicted_critical_speed} m/s"
    for run in sweep.runs:
        assert run.simulated == pytest.approx(run.predicted, abs=0.02 * abs(run.predicted) + 0.01), \
            f"decay rate at {run.speed} m/s: simulated {run.simulated}, eigenvalue {run.predicted}"


def test_the_nonlinear_law_at_small_amplitude_hunts_at_the_same_speed():
    law = SaturatedKalkerLaw(LAW)
    sweep = hunting_sweep([60.0, 68.0], dataclasses.replace(P, initial_lateral_displacement=1e-4), law,
                          periods=10, n_workers=0)
    assert abs(sweep.error) < 0.05, f"saturated law: V_c {sweep.simulated_critical_speed} against " \
                                    f"{sweep.predicted_critical_speed} m/s"


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


def test_the_scene_runs_in_process_and_refuses_the_cosimulation_options(capsys):
    from rollcontact_cosim.__main__ import main

    assert main(["--scene", "wheelset_hunting", "--fmi", "3"]) == 2, "exit code 2 for a bad option"
    assert "runs in process" in capsys.readouterr().err, "the message says why"


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
    from rollcontact_cosim.wheelset_stability import kinematic_frequency

    p = dataclasses.replace(P, speed=2.0, lateral_stiffness=0.0, yaw_stiffness=0.0)
    mode = least_damped(p, LAW)
    assert mode.imag / (2 * math.pi) == pytest.approx(kinematic_frequency(p), rel=1e-4), "Im / 2 pi = V / L"
    assert kinematic_frequency(p) == pytest.approx(2.0 / klingel_wavelength(p), rel=1e-15)


def test_the_simulated_critical_speed_does_not_depend_on_the_step():
    coarse = hunting_sweep([60.0, 66.0], P, LAW, periods=10, steps_per_period=40, n_workers=0)
    fine = hunting_sweep([60.0, 66.0], P, LAW, periods=10, steps_per_period=400, n_workers=0)
    assert coarse.simulated_critical_speed == pytest.approx(fine.simulated_critical_speed, rel=2e-3), \
        f"40 steps per period: {coarse.simulated_critical_speed}, 400: {fine.simulated_critical_speed} m/s"


@pytest.mark.slow
def test_the_sweep_on_dask_workers_equals_the_serial_sweep():
    pytest.importorskip("dask.distributed")
    from dask.distributed import Client

    from rollcontact_cosim.sweep import local_cluster

    speeds = [55.0, 65.0, 75.0]
    with local_cluster(2) as cluster, Client(cluster) as client:
        distributed = hunting_sweep(speeds, P, LAW, periods=8, client=client)
    serial = hunting_sweep(speeds, P, LAW, periods=8, n_workers=0)
    assert distributed == serial, "worker processes give the serial results bit for bit"


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


@pytest.mark.slow
def test_the_reference_results_are_the_studys(tmp_path):
    from rollcontact_cosim.wheelset_study import REFERENCE, write_reference

    fresh = write_reference(tmp_path / "reference.md")
    assert fresh.read_text() == REFERENCE.read_text(), \
        "models/cosim/wheelset_hunting_inprocess.md is not what the study gives: rerun write_reference()"
