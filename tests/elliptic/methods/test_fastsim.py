"""FASTSIM against independent oracles: Kalker's linear theory at vanishing creepage (its flexibilities are chosen
for it), saturation at mu Fn, the symmetries of the exact theory, the traction bound on its field, and the field
reference code's own FASTSIM on its published example (CONTACT, examples/fastsim.inp, case 3 at 200 x 200:
Fy/(mu Fn) = 0.5956, Mz = 45.30 N m on the rail).  Tolerances: grid error of 40 x 40 cells (1e-3 relative in the
linear limit, 1 % at saturation); the published example within its coefficient table's differences (0.015)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from elliptic_outcome import outcome

from rollcontact import EllipticScene, Material, solve_elliptic
from rollcontact.elliptic.creep_coefficients import creepage_coefficients

MU, LOAD = 0.3, 1e5


def scene(a=6e-3, b=4e-3, **creepages):
    return EllipticScene.from_semi_axes(LOAD, a, b, friction=MU, **creepages)


@pytest.mark.parametrize("ratio", [0.2, 1.0, 5.0])
def test_linear_limit_reproduces_kalkers_coefficients(ratio):
    s = scene(6e-3, 6e-3 / ratio)
    g, c, nu = s.shear_modulus, s.hertz.c, s.material.poisson_ratio
    coefficients = creepage_coefficients(ratio, nu)
    fx = solve_elliptic(s.replace(longitudinal_creepage=1e-7), "fastsim").longitudinal_force
    fy = solve_elliptic(s.replace(lateral_creepage=1e-7), "fastsim").lateral_force
    fy_spin = solve_elliptic(s.replace(spin_creepage=1e-5), "fastsim").lateral_force
    assert math.isclose(fx, g * c * c * coefficients.c11 * 1e-7, rel_tol=2e-3), f"C11 slope at a/b = {ratio}"
    assert math.isclose(fy, g * c * c * coefficients.c22 * 1e-7, rel_tol=2e-3), f"C22 slope at a/b = {ratio}"
    assert math.isclose(fy_spin, g * c**3 * coefficients.c23 * 1e-5, rel_tol=2e-3), f"C23 slope at a/b = {ratio}"


@pytest.mark.parametrize("creepages", [{"longitudinal_creepage": 0.1}, {"lateral_creepage": -0.1},
                                       {"longitudinal_creepage": 0.05, "lateral_creepage": 0.05, "spin_creepage": 1.0}])
def test_saturation_reaches_mu_fn(creepages):
    result = solve_elliptic(scene(**creepages), "fastsim")
    total = math.hypot(result.longitudinal_force, result.lateral_force) / (MU * LOAD)
    assert abs(total - 1.0) < 0.01, f"|F| -> mu Fn at large creepage: {total:.4f}"


def test_symmetries():
    base = solve_elliptic(scene(longitudinal_creepage=1e-3, lateral_creepage=4e-4, spin_creepage=0.3), "fastsim")
    mirrored = solve_elliptic(scene(longitudinal_creepage=-1e-3, lateral_creepage=4e-4, spin_creepage=0.3), "fastsim")
    flipped = solve_elliptic(scene(longitudinal_creepage=1e-3, lateral_creepage=-4e-4, spin_creepage=-0.3), "fastsim")
    scale = MU * LOAD
    assert abs(mirrored.longitudinal_force + base.longitudinal_force) < 1e-12 * scale, "Fx odd in xi"
    assert abs(mirrored.lateral_force - base.lateral_force) < 1e-12 * scale, "Fy even in xi"
    assert abs(flipped.lateral_force + base.lateral_force) < 1e-12 * scale, "Fy odd in (eta, phi)"
    assert abs(flipped.spin_moment + base.spin_moment) < 1e-12 * scale * base.c, "Mz odd in (eta, phi)"
    assert abs(flipped.longitudinal_force - base.longitudinal_force) < 1e-12 * scale, "Fx even in (eta, phi)"


def test_creepage_gives_its_force_on_the_rail():
    result = solve_elliptic(scene(longitudinal_creepage=1e-4, lateral_creepage=1e-4, spin_creepage=0.0), "fastsim")
    assert result.longitudinal_force > 0 and result.lateral_force > 0 and result.spin_moment < 0, \
        "xi, eta > 0 give Fx, Fy > 0 on the rail; eta > 0 gives Mz < 0 (Mz = G c^3 (-C23 eta + ...))"


def test_traction_bound_holds_on_the_field():
    result = solve_elliptic(scene(longitudinal_creepage=2e-3, lateral_creepage=-1e-3, spin_creepage=1.0), "fastsim",
                            fields=True)
    f = result.fields
    excess = f.traction_magnitude - MU * f.pressure
    assert np.all(excess <= 1e-9 * MU * result.max_pressure), f"|q| <= mu p: worst excess {excess.max():.3g} Pa"
    assert f.stick.any() and not f.stick.all(), "partial slip: both zones present"


def test_the_field_reference_codes_fastsim_example():
    g, nu = 82e9, 0.28
    s = EllipticScene.from_semi_axes(82000.0, 8e-3, 4e-3, material=Material(2 * g * (1 + nu), nu), friction=0.3,
                                     lateral_creepage=-0.000625, spin_creepage=0.625)
    result = solve_elliptic(s, "fastsim", nx=200, ny=200)
    fy = result.lateral_force / (0.3 * 82000.0)
    mz = result.spin_moment / (0.3 * 82000.0 * result.c)
    assert abs(fy - 0.5956) < 0.015, f"Fy/(mu Fn) {fy:.4f} vs CONTACT's 0.5956"
    assert abs(mz - 45.30 / (0.3 * 82000.0 * result.c)) < 0.015, f"Mz/(mu Fn c) {mz:.4f} vs CONTACT's"


def test_grid_error_decreases_under_refinement():
    s = scene(longitudinal_creepage=1e-3, spin_creepage=0.5)
    fine = solve_elliptic(s, "fastsim", nx=320, ny=320).force_coefficients
    errors = [max(abs(u - v) for u, v in zip(solve_elliptic(s, "fastsim", nx=n, ny=n).force_coefficients, fine,
                                             strict=True)) for n in (20, 40, 80)]
    assert errors[0] > errors[1] > errors[2], f"errors against 320 x 320 fall with n: {errors}"
    assert errors[1] < 0.5 / 40, f"within the accuracy model's grid term at 40 x 40: {errors[1]:.4f}"


def test_bad_options_are_refused():
    with pytest.raises(ValueError, match="bound"):
        solve_elliptic(scene(longitudinal_creepage=1e-3), "fastsim", bound="square")
    with pytest.raises(ValueError, match="nx"):
        solve_elliptic(scene(longitudinal_creepage=1e-3), "fastsim", nx=1)


def test_blended_flexibilities_are_kalkers_in_the_linear_range_and_one_at_large_creepage():
    """Vollebregt & Voltr (2023): weight 0 below the characteristic creepage's scale, 1 from three times it on."""
    from rollcontact.elliptic.creep_coefficients import creepage_coefficients
    from rollcontact.elliptic.methods.fastsim import blended_flexibilities, flexibilities

    s = scene(longitudinal_creepage=1e-9, lateral_creepage=2e-9, spin_creepage=0.1)
    c = creepage_coefficients(s.hertz.aspect_ratio, s.material.poisson_ratio)
    for blended, kalker in zip(blended_flexibilities(s, c), flexibilities(s, c), strict=True):
        assert math.isclose(blended, kalker, rel_tol=1e-5), "tiny creepage: Kalker's three flexibilities"
    large = s.replace(longitudinal_creepage=0.05, lateral_creepage=0.02)
    values = blended_flexibilities(large, c)
    assert values[0] == values[1] == values[2], f"large creepage: one flexibility, got {values}"
    low, high = min(flexibilities(large, c)), max(flexibilities(large, c))
    assert low <= values[0] <= high, "the single flexibility is a weighted mean of Kalker's"
    with pytest.raises(ValueError, match="flexibility"):
        solve_elliptic(s, "fastsim", flexibility="one")


@pytest.mark.parametrize(("ratio", "eta", "phi"), [(0.2, 0.6, 1.2), (5.0, 0.0, 1.2)])
def test_an_incompressible_material_stays_within_the_estimate(ratio, eta, phi):
    """At nu = 0.49 FASTSIM misses the lateral force of deep spin by more than at steel's 0.28 (0.12 mu Fn at a/b 0.2
    with lateral creepage and at a/b 5); its estimate grows with nu and covers it, against the discretised solver's
    pair of 30 and 60 elements.  Creepages in saturations (Kalker's linear force mu Fn)."""
    c = 6e-3
    s = EllipticScene.from_semi_axes(LOAD, c * math.sqrt(ratio), c / math.sqrt(ratio), friction=MU,
                                     material=Material(210e9, 0.49))
    k = creepage_coefficients(ratio, 0.49)
    unit = MU * LOAD / (s.shear_modulus * c * c)
    s = s.replace(lateral_creepage=eta * unit / k.c22, spin_creepage=phi * unit / (k.c23 * c))
    reference = np.array(solve_elliptic(s, "discretised", elements=60, extrapolate=True).force_coefficients)
    result = solve_elliptic(s, "fastsim")
    error = np.abs(np.array(result.force_coefficients) - reference)
    assert error.max() > 0.1, f"the case is one of FASTSIM's largest misses: {error}"
    assert error.max() <= result.info["error_estimate"], (
        f"errors {error} beyond the estimate {result.info['error_estimate']:.4f} at a/b {ratio}")


def mixed_batch():
    """Scenes of every kind: a/b 0.2..5 either way round, loads 1 kN..200 kN and none, three materials, Coulomb
    friction of three coefficients and two falling laws at several speeds, creepages with and without spin."""
    from rollcontact import ExponentialFalling, LinearFalling

    rng = np.random.default_rng(17)
    materials = (Material(), Material(2.1e11, 0.28), Material(1.9e11, 0.25))
    laws = (0.3, 0.2, ExponentialFalling(0.3, 0.4, 0.6), 0.45, LinearFalling(0.4, 0.25, 0.3))
    scenes = []
    for k in range(30):
        ratio = float(np.exp(rng.uniform(np.log(0.2), np.log(5.0))))
        load = 0.0 if k in (4, 19, 22) else float(np.exp(rng.uniform(np.log(1e3), np.log(2e5))))
        xi, eta = rng.normal(0.0, 2e-3, 2)
        phi = float(rng.normal(0.0, 1.0)) * (10.0 if k % 4 == 3 else 1.0)
        xi, eta, phi = ((xi, eta, 0.0), (0.0, 0.0, phi), (xi, eta, phi))[k % 3]
        scenes.append(EllipticScene.from_semi_axes(
            load if load else 1e5, 6e-3 * math.sqrt(ratio), 6e-3 / math.sqrt(ratio), material=materials[k % 3],
            friction=laws[k % 5], rolling_speed=float(5.0 + 2.0 * k), longitudinal_creepage=float(xi),
            lateral_creepage=float(eta), spin_creepage=phi).replace(normal_load=load))
    return scenes


@pytest.mark.parametrize("options", [{"fields": True}, {"nx": 20, "ny": 20},
                                     {"nx": 13, "ny": 7, "bound": "parabolic", "flexibility": "kalker"}])
def test_a_mixed_batch_is_each_scene_alone_bit_for_bit(options):
    """solve_fastsim_many of a mixed batch (mixed_batch: no load, Coulomb and falling friction, with and without
    spin) in two orders and in pairs: every result bit for bit solve_fastsim of its scene, fields included."""
    from rollcontact.elliptic.methods.fastsim import solve_fastsim, solve_fastsim_many

    scenes = mixed_batch()
    assert sum(s.normal_load == 0.0 for s in scenes) == 3 and sum(not s.friction.is_constant for s in scenes) > 4
    alone = [outcome(solve_fastsim(s, **options)) for s in scenes]
    together = [outcome(r) for r in solve_fastsim_many(scenes, **options)]
    backwards = [outcome(r) for r in solve_fastsim_many(scenes[::-1], **options)][::-1]
    pairs = [outcome(r) for k in range(0, len(scenes), 2) for r in solve_fastsim_many(scenes[k:k + 2], **options)]
    for k, scene in enumerate(scenes):
        assert together[k] == alone[k], f"scene {k} in the batch differs from alone: {scene}"
        assert backwards[k] == alone[k], f"scene {k} in the reversed batch differs from alone: {scene}"
        assert pairs[k] == alone[k], f"scene {k} in a pair differs from alone: {scene}"


def test_a_batch_names_the_scene_it_cannot_solve():
    from rollcontact.elliptic.methods.fastsim import solve_fastsim_many

    scenes = mixed_batch()[:3] + [EllipticScene.from_semi_axes(LOAD, 6e-3, 2e-4, friction=MU)]
    with pytest.raises(ValueError, match="fastsim cannot solve scene 3: a/b = 30 is outside"):
        solve_fastsim_many(scenes)
    with pytest.raises(ValueError, match="nx"):
        solve_fastsim_many(scenes[:3], nx=1)
