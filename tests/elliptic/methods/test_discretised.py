"""The discretised elliptic method (rollcontact.elliptic.methods.discretised) through the elliptic dispatcher: sign
convention, linear limit against the coefficient table, FASTSIM within both estimates, the traction field, the
Richardson pair, bad input and reported failure."""

import math

import numpy as np
import pytest

from rollcontact.core.friction import ExponentialFalling
from rollcontact.elliptic import EllipticScene, creepage_coefficients
from rollcontact.elliptic.dispatch import solve as solve_elliptic
from rollcontact.elliptic.methods.discretised import DiscretisedAccuracy3D

LOAD, C = 100e3, 6e-3  # N, sqrt(ab) [m]


def scene(ratio=0.7, **creepages):
    return EllipticScene.from_semi_axes(LOAD, C * math.sqrt(ratio), C / math.sqrt(ratio), friction=0.3,
                                        **creepages)


def test_each_creepage_gives_its_force_on_the_rail_positive():
    for field, index in (("longitudinal_creepage", 0), ("lateral_creepage", 1), ("spin_creepage", 2)):
        value = 2.0 if field == "spin_creepage" else 1e-3
        result = solve_elliptic(scene(**{field: value}), "discretised", elements=20)
        assert result.success, result.message
        assert result.force_coefficients[index] > 0.05, f"{field} > 0 gives {result.force_coefficients}"


def test_linear_limit_matches_the_coefficient_table():
    """At vanishing creepage ``Fx = G c^2 C11 xi``, ``Fy = G c^2 (C22 eta + c C23 phi)``: 32 x 32 elements within
    3 % of the table (which benchmarks/calibrate_creep_coefficients.py extrapolates from the same solver)."""
    base = scene(ratio=1.5)
    nu, g, c = base.material.poisson_ratio, base.shear_modulus, base.hertz.c
    table = creepage_coefficients(base.hertz.aspect_ratio, nu)
    e = 1e-9
    one_grid = {"elements": 32, "extrapolate": False}
    fx = solve_elliptic(base.replace(longitudinal_creepage=e), "discretised", **one_grid).longitudinal_force
    fy = solve_elliptic(base.replace(lateral_creepage=e), "discretised", **one_grid).lateral_force
    spin = solve_elliptic(base.replace(spin_creepage=e / c), "discretised", **one_grid)
    for name, got, expected in (("C11", fx, table.c11), ("C22", fy, table.c22), ("C23", spin.lateral_force,
                                                                                     table.c23)):
        coefficient = got / (g * c * c * e)
        assert coefficient == pytest.approx(expected, rel=0.03), f"{name} {coefficient:.4f} vs table {expected:.4f}"


def test_fastsim_is_within_both_error_estimates_of_the_discretised_solution():
    case = scene(ratio=0.6, longitudinal_creepage=8e-4, lateral_creepage=4e-4, spin_creepage=0.8)
    reference = solve_elliptic(case, "discretised", elements=40, extrapolate=True)
    fast = solve_elliptic(case, "fastsim")
    allowed = fast.info["error_estimate"] + reference.info["error_estimate"]
    gap = np.abs(np.subtract(fast.force_coefficients, reference.force_coefficients)).max()
    assert gap <= allowed, f"FASTSIM {fast.force_coefficients} vs discretised {reference.force_coefficients}: " \
                           f"{gap:.4f} > {allowed:.4f}"


def test_traction_field_respects_the_bound_and_the_pair_moves_toward_refinement():
    case = scene(ratio=1.2, longitudinal_creepage=3e-4, spin_creepage=0.5)
    result = solve_elliptic(case, "discretised", elements=20, extrapolate=False, fields=True)
    f = result.fields
    assert np.all(f.traction_magnitude <= 0.3 * f.pressure * (1 + 1e-9) + 1e-9 * f.pressure.max()), "|q| > mu p"
    assert 0.0 < f.stick[f.pressure > 0].mean() < 1.0, "a partial-slip case has both stick and slip"
    assert 0.0 < result.info["stick_fraction"] < 1.0
    fine = np.array(solve_elliptic(case, "discretised", elements=80, extrapolate=False).force_coefficients)
    single = np.abs(np.array(result.force_coefficients) - fine).max()
    pair = np.abs(np.array(solve_elliptic(case, "discretised", elements=40,
                                          extrapolate=True).force_coefficients) - fine).max()
    assert pair < single, f"Richardson pair 20/40 ({pair:.4f}) not closer to 80 elements than 20 alone ({single:.4f})"
    assert single <= DiscretisedAccuracy3D().error(case, {"elements": 20, "extrapolate": False}), (
        "error above the model's estimate")


def test_tolerance_picks_a_setting_that_meets_it_and_discretised_normal_agrees():
    case = scene(longitudinal_creepage=5e-4, lateral_creepage=2e-4)
    result = solve_elliptic(case, "discretised", tolerance=0.01)
    assert result.success and result.info["error_estimate"] <= 0.01, result.info
    other = solve_elliptic(case, "discretised", elements=24, extrapolate=False, normal="discretised")
    hertz = solve_elliptic(case, "discretised", elements=24, extrapolate=False)
    assert other.success, other.message
    np.testing.assert_allclose(other.force_coefficients, hertz.force_coefficients, atol=3e-3,
                               err_msg="discretised normal problem vs sampled Hertz pressure")


def test_velocity_dependent_friction_solves():
    case = EllipticScene.from_semi_axes(106.7e3, 6.3e-3, 12.6e-3, friction=ExponentialFalling(0.55, 0.4, 0.6),
                                        rolling_speed=10.0, longitudinal_creepage=0.02)
    result = solve_elliptic(case, "discretised", elements=20)
    assert result.success, result.message
    assert 0.5 < result.force_coefficients[0] < 1.0, f"Fx/(mu_s Fn) = {result.force_coefficients[0]}"


@pytest.mark.parametrize(("options", "match"), [({"elements": 4}, "elements = 4"), ({"elements": 2000}, "2000"),
                                                ({"normal": "exact"}, "normal"),
                                                ({"elements": 25, "extrapolate": True}, "even"),
                                                ({"elements": 2.5}, "integers")])
def test_bad_options_are_refused_with_the_value(options, match):
    with pytest.raises(ValueError, match=match):
        solve_elliptic(scene(longitudinal_creepage=1e-3), "discretised", **options)


def test_no_load_and_non_convergence_are_reported():
    empty = solve_elliptic(scene().replace(normal_load=0.0), "discretised")
    assert empty.success and empty.force_coefficients == (0.0, 0.0, 0.0), empty
    stuck = solve_elliptic(scene(longitudinal_creepage=6e-4, spin_creepage=1.5), "discretised", elements=16,
                           max_iterations=1)
    assert not stuck.success and "did not converge" in stuck.message, stuck.message


def test_falling_friction_agrees_with_strips_on_the_eurosprinter():
    """Polach's exponential law on the Eurosprinter's ellipse (a/b 0.5, a 6.3 mm, 106.7 kN, V 10 m/s): strips and
    the discretised pair within 0.02 mu_s Fn over the creep curve, through its peak and falling branch."""
    law = ExponentialFalling(0.55, 0.4, 0.6)
    curve = []
    for creep in (0.001, 0.003, 0.006, 0.02, 0.08):
        case = EllipticScene.from_semi_axes(106.7e3, 6.3e-3, 12.6e-3, friction=law, rolling_speed=10.0,
                                            longitudinal_creepage=creep)
        discretised = solve_elliptic(case, "discretised", elements=32)
        strips = solve_elliptic(case, "strips")
        assert discretised.success and strips.success, (discretised.message, strips.message)
        gap = abs(discretised.force_coefficients[0] - strips.force_coefficients[0])
        assert gap < 0.02, f"xi = {creep}: discretised {discretised.force_coefficients[0]:.4f}, strips " \
                           f"{strips.force_coefficients[0]:.4f}"
        curve.append(discretised.force_coefficients[0])
    assert max(curve) > curve[-1] + 0.1, f"no falling branch on {curve}"


@pytest.mark.parametrize("creepages", [(6e-4, 0.0, 0.0), (0.0, 5e-4, 0.0), (3e-4, 2e-4, 0.6)])
def test_strips_are_within_both_error_estimates_of_the_discretised_solution(creepages):
    xi, eta, phi = creepages
    case = scene(ratio=0.4, longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi)
    reference = solve_elliptic(case, "discretised", elements=40)
    strips = solve_elliptic(case, "strips")
    allowed = strips.info["error_estimate"] + reference.info["error_estimate"]
    gap = np.abs(np.subtract(strips.force_coefficients, reference.force_coefficients)).max()
    assert gap <= allowed, f"strips {strips.force_coefficients} vs discretised {reference.force_coefficients}: " \
                           f"{gap:.4f} > {allowed:.4f}"
