"""The patch strips against the elliptic strips on quadratic gaps (the same strip theory on Hertz's ellipse; the
patch's normal solution and equivalent ellipse approximate it), Kalker's linear theory, and the identities: zero
creepage gives no force, large creepage saturates at mu Fn, |q| <= mu p on the cells, mirror symmetry (Fy and Mz
change sign), Mz about the rigid contact point, and the scenes they refuse or fail on."""

from __future__ import annotations

import math

import numpy as np
import pytest
from wheelrail_gaps import LOAD, MU, quadratic, two_wells, varying_curvature

from rollcontact import ExponentialFalling, solve_elliptic
from rollcontact.elliptic.creep_coefficients import creepage_coefficients
from rollcontact.wheelrail.methods.strips import solve_strips
from rollcontact.wheelrail.scene import PatchScene

ELLIPTIC_TOLERANCE = 0.015
"""|dF|/(mu Fn) (Mz over mu Fn c) against the elliptic strips on the same quadratic gap: the largest measured is 0.010
(a/b = 0.2, deep spin, the patch's 24 cosine-spaced strips against the elliptic strips' Gauss nodes)."""

CREEPAGES = [(1e-3, 0.0, 0.0), (0.0, 1e-3, 0.0), (0.0, 0.0, 0.5), (0.0, 0.0, 3.0), (1e-3, 1e-3, 1.0),
             (-2e-3, 5e-4, -1.5)]


def patch_scene(gap, xi=0.0, eta=0.0, phi=0.0, **fields):
    fields.setdefault("normal_load", LOAD)
    return PatchScene(gap, longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi, friction=MU, **fields)


def coefficients(result, c):
    scale = MU * result.normal_load
    return np.array([result.longitudinal_force / scale, result.lateral_force / scale, result.spin_moment / (scale * c)])


@pytest.mark.parametrize("ratio", [0.2, 1.0, 5.0])
@pytest.mark.parametrize("creepages", CREEPAGES)
def test_quadratic_gap_gives_the_elliptic_strips(ratio, creepages):
    gap, scene = quadratic(ratio)
    xi, eta, phi = creepages
    elliptic = solve_elliptic(scene.replace(longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi),
                              "strips")
    patch = solve_strips(patch_scene(gap, *creepages))
    assert patch.success, patch.message
    difference = np.abs(coefficients(patch, scene.hertz.c) - np.array(elliptic.force_coefficients))
    assert difference.max() < ELLIPTIC_TOLERANCE, (
        f"a/b = {ratio}, {creepages}: patch {coefficients(patch, scene.hertz.c)} vs elliptic strips "
        f"{elliptic.force_coefficients}")


@pytest.mark.parametrize("ratio", [0.3, 1.0, 3.0])
def test_linear_limit_gives_kalkers_coefficients(ratio):
    """Fx of xi (C11), Fy of eta (C22), Fy of spin (C23): within 1.5 % (the equivalent ellipse's a/b and area come
    from the strips' normal solution, within 0.5 % and 0.3 % of Hertz's)."""
    gap, scene = quadratic(ratio)
    g, c = scene.shear_modulus, scene.hertz.c
    k = creepage_coefficients(ratio, scene.material.poisson_ratio)
    fx = solve_strips(patch_scene(gap, xi=1e-9)).longitudinal_force
    fy = solve_strips(patch_scene(gap, eta=1e-9)).lateral_force
    spin = solve_strips(patch_scene(gap, phi=1e-8)).lateral_force
    for name, got, expected in (("C11", fx, g * c * c * k.c11 * 1e-9), ("C22", fy, g * c * c * k.c22 * 1e-9),
                                ("C23", spin, g * c**3 * k.c23 * 1e-8)):
        assert math.isclose(got, expected, rel_tol=0.015), f"{name} at a/b = {ratio}: {got / expected:.4f} of Kalker's"


@pytest.mark.parametrize("make", [lambda: quadratic(1.0)[0], two_wells, varying_curvature])
def test_zero_creepage_gives_no_force(make):
    result = solve_strips(patch_scene(make(), normal_load=3e4))
    assert result.success, result.message
    assert (result.longitudinal_force, result.lateral_force, result.spin_moment) == (0.0, 0.0, 0.0), \
        f"forces without creepage: {result.longitudinal_force}, {result.lateral_force}, {result.spin_moment}"


@pytest.mark.parametrize("make", [lambda: quadratic(1.0)[0], two_wells, varying_curvature])
@pytest.mark.parametrize("direction", [(1.0, 0.0), (0.6, -0.8)])
def test_large_creepage_saturates_at_mu_fn(make, direction):
    result = solve_strips(patch_scene(make(), xi=0.5 * direction[0], eta=0.5 * direction[1], normal_load=3e4))
    force = math.hypot(result.longitudinal_force, result.lateral_force)
    assert math.isclose(force, MU * 3e4, rel_tol=1e-3), f"|F| = {force:.6g} N at full slip, mu Fn = {MU * 3e4:.6g} N"
    if direction[1] == 0.0:  # combined, the strips' full slip follows (E_x xi, E_y eta), as the elliptic strips'
        assert math.isclose(result.longitudinal_force / force, 1.0, abs_tol=1e-9), "the force along the slip"


@pytest.mark.parametrize("make", [lambda: quadratic(2.0)[0], two_wells, varying_curvature])
@pytest.mark.parametrize("creepages", [(1e-3, 0.0, 0.0), (5e-4, 5e-4, 2.0), (0.0, -1e-3, 6.0)])
def test_traction_bound_holds_on_the_cells(make, creepages):
    result = solve_strips(patch_scene(make(), *creepages, normal_load=3e4), fields=True)
    field = result.fields
    excess = field.traction_magnitude - MU * field.pressure
    assert excess.max() <= 1e-9 * MU * field.pressure.max(), f"|q| exceeds mu p by {excess.max():.3g} Pa"


@pytest.mark.parametrize("make", [two_wells, varying_curvature])
@pytest.mark.parametrize("creepages", [(1e-3, 5e-4, 0.0), (5e-4, -5e-4, 1.5)])
def test_mirror_symmetry(make, creepages):
    scene = patch_scene(make(), *creepages, normal_load=3e4)
    one, other = solve_strips(scene), solve_strips(scene.mirrored)
    scale = 1e-6 * MU * 3e4  # the normal fixed point's tolerance: its iterates differ in round-off from the mirror's
    assert abs(one.longitudinal_force - other.longitudinal_force) < scale, "Fx of the mirrored patch"
    assert abs(one.lateral_force + other.lateral_force) < scale, "Fy of the mirrored patch changes sign"
    assert abs(one.spin_moment + other.spin_moment) < scale * one.c, "Mz of the mirrored patch changes sign"


def test_moment_is_about_the_rigid_contact_point():
    """The second well's longitudinal force turns about s = 0: Mz of xi alone is -sum(s Fx), negative for a patch
    whose load lies at s > 0."""
    result = solve_strips(patch_scene(two_wells(), xi=1e-3, normal_load=3e4))
    assert result.info["lobes"] == 2, result.info
    assert result.spin_moment < -1e-3 * result.longitudinal_force * 1e-3, \
        f"Mz = {result.spin_moment:.4g} N m for Fx = {result.longitudinal_force:.4g} N on wells at s = 0 and 8 mm"


FALLING = ExponentialFalling(0.55, 0.4, 0.6)
"""Polach's dry rail."""

FALLING_CREEPAGES = [(2e-3, 0.0, 0.0), (1e-3, 1e-3, 1.0), (-2e-3, 5e-4, -1.5), (0.0, 0.0, 3.0)]


@pytest.mark.parametrize("ratio", [0.2, 1.0, 5.0])
@pytest.mark.parametrize("creepages", FALLING_CREEPAGES)
def test_falling_friction_with_spin_on_a_quadratic_gap_gives_the_elliptic_strips(ratio, creepages):
    """Polach's dry rail at 40 m/s with spin: the patch strips and the elliptic strips share the falling march, within
    the tolerance of their Coulomb forces (:data:`ELLIPTIC_TOLERANCE`)."""
    gap, scene = quadratic(ratio)
    xi, eta, phi = creepages
    elliptic = solve_elliptic(scene.replace(longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi,
                                            friction=FALLING, rolling_speed=40.0), "strips")
    patch = solve_strips(PatchScene(gap, normal_load=LOAD, longitudinal_creepage=xi, lateral_creepage=eta,
                                    spin_creepage=phi, friction=FALLING, rolling_speed=40.0))
    assert patch.success, patch.message
    scale = FALLING.static_coefficient * patch.normal_load
    got = np.array([patch.longitudinal_force / scale, patch.lateral_force / scale,
                    patch.spin_moment / (scale * scene.hertz.c)])
    difference = np.abs(got - np.array(elliptic.force_coefficients))
    assert difference.max() < ELLIPTIC_TOLERANCE, f"a/b = {ratio}, {creepages}: {got} vs {elliptic.force_coefficients}"


@pytest.mark.parametrize("make", [lambda: quadratic(1.0)[0], two_wells, varying_curvature])
@pytest.mark.parametrize("creepages", FALLING_CREEPAGES)
def test_a_nearly_constant_law_gives_the_coulomb_strips_to_round_off(make, creepages):
    """A law falling by 6e-13 of mu over the patch's slip velocities: the falling path's forces are the Coulomb
    path's within 1e-11 mu Fn (Mz over mu Fn c)."""
    gap = make()
    xi, eta, phi = creepages
    falling = solve_strips(PatchScene(gap, normal_load=3e4, longitudinal_creepage=xi, lateral_creepage=eta,
                                      spin_creepage=phi, friction=ExponentialFalling(MU, 0.4, 1e-12)))
    coulomb = solve_strips(patch_scene(gap, *creepages, normal_load=3e4))
    assert falling.success, falling.message
    scale = MU * coulomb.normal_load
    for name, unit in (("longitudinal_force", scale), ("lateral_force", scale), ("spin_moment", scale * coulomb.c)):
        assert abs(getattr(falling, name) - getattr(coulomb, name)) < 1e-11 * unit, name


@pytest.mark.parametrize("make", [two_wells, varying_curvature])
@pytest.mark.parametrize("creepages", [(1e-3, 5e-4, 1.5), (0.0, -1e-3, 3.0)])
def test_falling_friction_stays_within_the_falling_bound_on_the_cells(make, creepages):
    """|q| <= mu(0) p on every cell and the forces below the Coulomb strips' where the law has fallen."""
    gap = make()
    xi, eta, phi = creepages
    scene = PatchScene(gap, normal_load=3e4, longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi,
                       friction=FALLING, rolling_speed=40.0)
    result = solve_strips(scene, fields=True)
    field = result.fields
    assert np.all(field.traction_magnitude <= FALLING.static_coefficient * field.pressure * (1 + 1e-12) + 1e-9)
    coulomb = solve_strips(PatchScene(gap, normal_load=3e4, longitudinal_creepage=xi, lateral_creepage=eta,
                                      spin_creepage=phi, friction=FALLING.static_coefficient))
    assert math.hypot(result.longitudinal_force, result.lateral_force) < math.hypot(
        coulomb.longitudinal_force, coulomb.lateral_force), "falling friction lowers the force"


PATCH_FALLING_TOLERANCE = 0.05
"""|dF|/(mu(0) Fn) (Mz over mu(0) Fn c) of the patch strips with falling friction and spin against the discretised
patch level on the non-elliptic gaps: the Coulomb strips' own error there (``PATCH_ERROR`` and the spin's) and the
falling march's (``benchmarks/calibrate_falling_spin.py``), with a margin."""


@pytest.mark.slow
@pytest.mark.parametrize("make", [two_wells, varying_curvature])
@pytest.mark.parametrize("creepages", [(2e-3, 0.0, 0.0), (1e-3, 5e-4, 1.5), (0.0, -1e-3, 3.0)])
def test_falling_friction_with_spin_against_the_discretised_patch(make, creepages):
    from rollcontact.wheelrail.methods.discretised import solve_discretised

    gap = make()
    xi, eta, phi = creepages
    scene = PatchScene(gap, normal_load=3e4, longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi,
                       friction=FALLING, rolling_speed=40.0)
    strips_result, reference = solve_strips(scene), solve_discretised(scene)
    assert reference.success, reference.message
    scale = FALLING.static_coefficient * reference.normal_load
    got = np.array([strips_result.longitudinal_force, strips_result.lateral_force, strips_result.spin_moment])
    want = np.array([reference.longitudinal_force, reference.lateral_force, reference.spin_moment])
    error = np.abs(got - want) / np.array([scale, scale, scale * reference.c])
    assert error.max() < PATCH_FALLING_TOLERANCE, f"{creepages}: strips {got} vs discretised {want}: {error}"


def test_a_failed_normal_problem_is_reported():
    gap, scene = quadratic(1.0, span=0.8)
    result = solve_strips(patch_scene(gap, xi=1e-3, normal_load=None, approach=scene.hertz.approach))
    assert not result.success and "normal problem" in result.message, result.message
    assert math.isnan(result.longitudinal_force)
