"""Kalker's linear theory: its forces against Kalker's published coefficients (typed here from Table E.3, not read from
the data module), its signs on the rail, its symmetries, and its refusal of what it cannot give."""

from __future__ import annotations

import math

import numpy as np

from rollcontact import EllipticScene, Material, solve_elliptic


def circle(**creepages):
    return EllipticScene.from_semi_axes(1e5, 5e-3, 5e-3, material=Material(210e9, 0.25), friction=0.3, **creepages)


def test_forces_on_the_rail_follow_kalkers_table():
    """a/b = 1, nu = 0.25: C11 4.12, C22 3.67, C23 1.47 (Kalker 1990, Table E.3), within the 1 % to which the
    table (the discretised solver's, benchmarks/calibrate_creep_coefficients.py) meets Kalker's."""
    s = circle(longitudinal_creepage=1e-4, lateral_creepage=-2e-4)
    g, c = s.shear_modulus, s.hertz.c
    result = solve_elliptic(s, "linear")
    assert math.isclose(result.longitudinal_force, g * c * c * 4.12 * 1e-4, rel_tol=1e-2), "Fx = G c^2 C11 xi"
    assert math.isclose(result.lateral_force, g * c * c * 3.67 * -2e-4, rel_tol=1e-2), "Fy = G c^2 C22 eta"
    assert math.isclose(result.spin_moment, -g * c**3 * 1.47 * -2e-4, rel_tol=1e-2), "Mz = -G c^3 C23 eta"


def test_spin_follows_the_tables_c23_and_c33():
    """Fy = G c^3 C23 phi and Mz = G c^4 C33 phi on the rail, with the table's coefficients."""
    from rollcontact.elliptic import creepage_coefficients

    s = circle(spin_creepage=0.05)
    g, c = s.shear_modulus, s.hertz.c
    table = creepage_coefficients(1.0, 0.25)
    result = solve_elliptic(s, "linear")
    assert math.isclose(result.lateral_force, g * c**3 * table.c23 * 0.05, rel_tol=1e-9), "Fy = G c^3 C23 phi"
    assert math.isclose(result.spin_moment, g * c**4 * table.c33 * 0.05, rel_tol=1e-9), "Mz = G c^4 C33 phi"


def test_symmetries_and_signs():
    plus = solve_elliptic(circle(longitudinal_creepage=1e-4, lateral_creepage=1e-4), "linear")
    minus = solve_elliptic(circle(longitudinal_creepage=-1e-4, lateral_creepage=-1e-4), "linear")
    assert plus.longitudinal_force > 0 and plus.lateral_force > 0, "creepage > 0 gives force > 0 on the rail"
    assert plus.longitudinal_force == -minus.longitudinal_force, "Fx odd in xi"
    assert plus.lateral_force == -minus.lateral_force and plus.spin_moment == -minus.spin_moment, \
        "Fy, Mz odd in eta"


def test_the_error_estimate_grows_with_the_creepage():
    small = solve_elliptic(circle(longitudinal_creepage=1e-7), "linear").info["error_estimate"]
    large = solve_elliptic(circle(longitudinal_creepage=1e-2), "linear").info["error_estimate"]
    assert small < 1e-3 < 1.0 < large, f"exact at vanishing creepage, unbounded past saturation ({small}, {large})"


def test_the_error_estimate_covers_the_spin_moment_of_an_elongated_contact():
    """The spin moment saturates long before the lateral force of the same spin (its tractions lie far from the
    centre): at a/b 0.2 and a twentieth of the spin's saturation, the linear Mz is off by several percent of
    mu Fn c, which the estimate must cover (the discretised 3D solver as the oracle, a Richardson pair 16/32)."""
    scene = EllipticScene.from_semi_axes(1e5, 6e-3 * math.sqrt(0.2), 6e-3 / math.sqrt(0.2), spin_creepage=0.3)
    linear = solve_elliptic(scene, "linear")
    exact = solve_elliptic(scene, "discretised", elements=32, extrapolate=True)
    error = float(np.abs(np.array(linear.force_coefficients) - np.array(exact.force_coefficients)).max())
    assert error > 0.01, f"the case is one the linear theory gets wrong by more than a percent: {error:.3g}"
    assert error <= linear.info["error_estimate"], \
        f"error {error:.3g} of mu Fn (c) above the estimate {linear.info['error_estimate']:.3g}"
