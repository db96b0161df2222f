"""The discretised patch level against the elliptic discretised level on the same grid (a quadratic gap is Hertz's
contact; the two solve the same discrete problems), Hertz's normal contact at its approach, and the identities:
load balance, the load and approach entry points inverse to each other, |q| <= mu p on every element, zero creepage
gives no force, large creepage saturates at mu Fn, mirror symmetry, convergence with the element size, and the
strips within the goals of the fast level on non-Hertzian gaps."""

from __future__ import annotations

import math

import numpy as np
import pytest
from wheelrail_gaps import MU, quadratic, two_wells, varying_curvature

from rollcontact import ExponentialFalling
from rollcontact.core.halfspace.rolling import ellipse_grid, solve_normal
from rollcontact.core.halfspace.surface import operator_for
from rollcontact.elliptic.methods.discretised import solve_discretised_3d
from rollcontact.wheelrail.methods.discretised import (
    ITERATION_TOLERANCE,
    NORMAL_TOLERANCE,
    discretised_loaded_approach,
    discretised_normal_force,
    guide_for,
    normal_at_approach,
    patch_grid,
    solve_discretised,
)
from rollcontact.wheelrail.methods.strips import solve_strips
from rollcontact.wheelrail.scene import PatchScene

LOAD = 3e4
COARSE = 0.4e-3
"""Element size [m] of the quick tests: about 500 elements in contact at 30 kN."""


def patch_scene(gap, xi=0.0, eta=0.0, phi=0.0, friction=MU, **fields):
    fields.setdefault("normal_load", LOAD)
    return PatchScene(gap, longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi, friction=friction,
                      **fields)


@pytest.mark.parametrize("creepages", [(1e-3, 0.0, 0.5), (0.0, 1e-3, -1.0)])
@pytest.mark.parametrize("friction", [MU, ExponentialFalling(MU, 0.4, 0.5)])
def test_same_grid_as_the_elliptic_discretised_level(creepages, friction):
    gap, scene = quadratic(0.5, samples=4001)
    xi, eta, phi = creepages
    elliptic = solve_discretised_3d(scene.replace(longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi,
                                                  friction=friction, rolling_speed=2.0),
                                    elements=24, extrapolate=False, normal="discretised")
    h = scene.hertz
    grid = ellipse_grid(h.a, h.b, 24, margin=3)
    patch = solve_discretised(patch_scene(gap, *creepages, friction=friction, normal_load=scene.normal_load,
                                          rolling_speed=2.0), grid=grid)
    assert patch.success, patch.message
    scale = MU * scene.normal_load
    got = np.array([patch.longitudinal_force, patch.lateral_force, patch.spin_moment / h.c]) / scale
    assert np.abs(got - np.array(elliptic.force_coefficients)).max() < 1e-5, \
        f"patch {got} vs elliptic discretised {elliptic.force_coefficients} on the same grid"


def test_hertz_at_its_approach():
    gap, scene = quadratic(1.0, load=LOAD)
    result = solve_discretised(patch_scene(gap, approach=scene.hertz.approach, normal_load=None), element=0.2e-3)
    assert result.success, result.message
    assert math.isclose(result.normal_load, LOAD, rel_tol=5e-3), f"Fn {result.normal_load:.6g} N at Hertz's approach"
    assert math.isclose(result.max_pressure, scene.hertz.max_pressure, rel_tol=0.02), "p0 at Hertz's approach"


def test_load_and_approach_entry_points_agree():
    by_load = solve_discretised(patch_scene(two_wells()), element=COARSE)
    by_approach = solve_discretised(patch_scene(two_wells(), approach=by_load.approach, normal_load=None),
                                    element=COARSE)
    assert math.isclose(by_load.normal_load, LOAD, rel_tol=1e-9), f"load balance: {by_load.normal_load!r}"
    assert math.isclose(by_approach.normal_load, LOAD, rel_tol=2e-3), \
        f"Fn {by_approach.normal_load:.6g} N at the load's approach"


def test_approach_conjugate_gradients_meet_the_gap():
    gap, scene = quadratic(1.0, load=LOAD)
    grid = patch_grid(0.0, 6e-3, -6e-3, 6e-3, COARSE)
    from rollcontact.core.halfspace.surface import operator_for

    x, s = grid.mesh()
    h0 = scene.longitudinal_curvature * x * x + scene.lateral_curvature * s * s
    op = operator_for(grid, scene.material.poisson_ratio)
    delta = scene.hertz.approach
    p, _, converged, message = normal_at_approach(op, h0, delta, scene.shear_modulus)
    assert converged, message
    deformed = h0 + op.normal(p) / scene.shear_modulus - delta
    contact = p > 0.0
    assert np.abs(deformed[contact]).max() < 1e-8 * delta, "the deformed gap vanishes where there is pressure"
    assert deformed[~contact].min() > -1e-8 * delta, "no interpenetration off contact"


@pytest.mark.parametrize("creepages", [(1e-3, 5e-4, 0.0), (5e-4, -5e-4, 2.0)])
def test_traction_bound_and_zero_creepage(creepages):
    result = solve_discretised(patch_scene(varying_curvature(), *creepages), element=COARSE, fields=True)
    field = result.fields
    excess = field.traction_magnitude - MU * field.pressure
    assert excess.max() <= 1e-9 * MU * field.pressure.max(), f"|q| exceeds mu p by {excess.max():.3g} Pa"
    rest = solve_discretised(patch_scene(varying_curvature()), element=COARSE)
    assert abs(rest.longitudinal_force) + abs(rest.lateral_force) < 1e-12 * MU * LOAD, "forces without creepage"


def test_large_creepage_saturates_at_mu_fn():
    result = solve_discretised(patch_scene(two_wells(), xi=0.3, eta=-0.4), element=COARSE)
    force = math.hypot(result.longitudinal_force, result.lateral_force)
    assert math.isclose(force, MU * LOAD, rel_tol=1e-6), f"|F| = {force:.8g} N at full slip, mu Fn = {MU * LOAD} N"
    assert math.isclose(result.longitudinal_force / force, 0.6, abs_tol=1e-3), "the force along the rigid slip"


def test_mirror_symmetry():
    scene = patch_scene(varying_curvature(), 1e-3, 5e-4, 1.0)
    one, other = solve_discretised(scene, element=COARSE), solve_discretised(scene.mirrored, element=COARSE)
    scale = MU * LOAD
    assert abs(one.longitudinal_force - other.longitudinal_force) < 1e-6 * scale, "Fx of the mirrored patch"
    assert abs(one.lateral_force + other.lateral_force) < 1e-6 * scale, "Fy of the mirrored patch changes sign"
    assert abs(one.spin_moment + other.spin_moment) < 1e-6 * scale * one.c, "Mz of the mirrored patch changes sign"


@pytest.mark.slow
def test_converges_at_first_order_in_the_element_size():
    """The change of the forces from one element size to its half halves (first order): 0.4, 0.2, 0.1 mm on the
    varying gap."""
    scene = patch_scene(varying_curvature(), 1e-3, 5e-4, 1.0)
    forces = [np.array([r.longitudinal_force, r.lateral_force, r.spin_moment / r.c]) / (MU * LOAD)
              for r in (solve_discretised(scene, element=e) for e in (0.4e-3, 0.2e-3, 0.1e-3))]
    first, second = np.abs(forces[1] - forces[0]).max(), np.abs(forces[2] - forces[1]).max()
    assert 1.4 < first / second < 3.5, f"changes {first:.3e} then {second:.3e}: not first order"
    assert second < 0.02, f"the 0.1 mm grid still moves by {second:.3e} mu Fn"


@pytest.mark.slow
@pytest.mark.parametrize("make", [two_wells, varying_curvature])
@pytest.mark.parametrize("creepages", [(1e-3, 0.0, 0.0), (0.0, 1e-3, 0.0), (5e-4, 5e-4, 1.0)])
def test_strips_within_the_fast_goal(make, creepages):
    """The fast level within 0.05 mu Fn of the Richardson-extrapolated reference, Fn within 3 %, p0 within 15 %."""
    scene = patch_scene(make(), *creepages)
    reference = solve_discretised(scene, element=0.2e-3, extrapolate=True)
    fast = solve_strips(scene)
    scale = MU * LOAD
    for name in ("longitudinal_force", "lateral_force"):
        error = abs(getattr(fast, name) - getattr(reference, name)) / scale
        assert error < 0.05, f"{name}: strips off the reference by {error:.3f} mu Fn"
    assert abs(fast.spin_moment - reference.spin_moment) / (scale * reference.c) < 0.05, "Mz"
    assert math.isclose(fast.approach, reference.approach, rel_tol=0.03), "the approach at the load"
    assert math.isclose(fast.max_pressure, reference.max_pressure, rel_tol=0.15), "the peak pressure"


def test_a_carried_normal_solution_is_taken_at_its_force_and_only_its_guide_at_another(monkeypatch):
    """The normal problem a wheel's given-force solve found (PatchState) is taken by the solve at that force, not
    solved again, with the same bits; at another force only its guide is taken, and the answer is that force's."""
    import rollcontact.wheelrail.methods.discretised as module

    gap, _ = quadratic(0.5, c=4e-3)
    scene = patch_scene(gap, 1e-3, -5e-4, 0.2)
    approach, carried = discretised_loaded_approach(gap, scene.normal_load, scene.material)
    assert approach is not None and carried.force == scene.normal_load
    again = solve_discretised(scene)
    calls = []
    solved = module.normal_problem
    monkeypatch.setattr(module, "normal_problem", lambda *a, **k: calls.append(a) or solved(*a, **k))
    reused = solve_discretised(scene, start=carried)
    assert not calls, "the carried normal problem was solved again"
    assert reused.success, reused.message
    assert reused.info["normal_iterations"] == again.info["normal_iterations"]
    for name in ("normal_load", "approach", "max_pressure", "longitudinal_force", "lateral_force", "spin_moment"):
        assert getattr(reused, name) == getattr(again, name), f"{name}: {getattr(reused, name)!r} reused, " \
                                                              f"{getattr(again, name)!r} solved again"
    other = scene.replace(normal_load=1.2 * scene.normal_load)
    moved = solve_discretised(other, start=carried)
    assert math.isclose(moved.normal_load, other.normal_load, rel_tol=1e-9), \
        f"another force is solved for: {moved.normal_load!r} N for {other.normal_load!r} N"


@pytest.mark.parametrize("make", [two_wells, varying_curvature])
def test_a_wheels_next_pass_starts_from_the_last_and_gives_its_answer(make):
    """A PatchState carries a pass's tractions to the wheel's next pass on the patch (its force changed by 1 %, as the
    tangential forces' share of the load changes it), also through a solve at a given approach (the normal law of a
    wheel of several patches): the next pass's steady iteration starts from them and takes fewer operator
    applications, and its answer is the fresh solve's within 1e-6 mu Fn (Fx, Fy; Mz over mu Fn c)."""
    gap = make()
    scene = patch_scene(gap, 1e-3, -5e-4, 0.5, friction=ExponentialFalling(MU, 0.4, 0.5), rolling_speed=20.0)
    _, state = discretised_loaded_approach(gap, scene.normal_load, scene.material)
    first = solve_discretised(scene, start=state)
    assert first.success and state.traction is not None, "the solve records its tractions in the state"
    other = scene.replace(normal_load=1.01 * scene.normal_load)
    _, fresh_state = discretised_loaded_approach(gap, other.normal_load, other.material)
    fresh = solve_discretised(other, start=fresh_state)
    _, next_state = discretised_loaded_approach(gap, other.normal_load, other.material, start=state)
    resumed = solve_discretised(other, start=next_state)
    assert resumed.success, resumed.message
    assert resumed.info["operator_applications"] < fresh.info["operator_applications"], \
        f"steady applications {resumed.info['operator_applications']} resumed, " \
        f"{fresh.info['operator_applications']} fresh"
    scale = MU * other.normal_load
    for name, unit in (("longitudinal_force", 1.0), ("lateral_force", 1.0), ("spin_moment", fresh.c)):
        error = abs(getattr(resumed, name) - getattr(fresh, name)) / (scale * unit)
        assert error < 1e-6, f"{name}: resumed off the fresh solve by {error:.1e}"
    assert math.isclose(resumed.approach, fresh.approach, rel_tol=1e-7), "the approach"
    approach = fresh.approach
    force, at_approach = discretised_normal_force(gap, approach, other.material, start=state)
    fresh_force, fresh_at_approach = discretised_normal_force(gap, approach, other.material)
    assert at_approach.traction is state.traction, "at an approach the state passes the tractions on"
    assert math.isclose(force, fresh_force, rel_tol=1e-7), f"{force!r} N resumed, {fresh_force!r} N fresh"


@pytest.mark.parametrize("make", [two_wells, varying_curvature])
def test_the_normal_problem_starts_from_the_strips_pressure(make):
    """The strips' pressure (StripContact.pressure_on) starts Polonsky & Keer's iteration: fewer iterations than from
    a uniform pressure to the same contact, within the tolerance."""
    gap = make()
    scene = patch_scene(gap)
    guide = guide_for(scene)
    grid = patch_grid(0.0, 0.6 * guide.length + 1e-3, guide.extent[0] - 1e-3, guide.extent[1] + 1e-3, COARSE)
    op = operator_for(grid, scene.material.poisson_ratio)
    x, s = grid.mesh()
    h = np.interp(s, gap.lateral, gap.lateral_gap) + np.interp(s, gap.lateral, gap.longitudinal_curvature) * x * x
    uniform = solve_normal(op, h, LOAD, scene.shear_modulus, tolerance=NORMAL_TOLERANCE)
    started = solve_normal(op, h, LOAD, scene.shear_modulus, tolerance=NORMAL_TOLERANCE,
                           initial=guide.pressure_on(x, s))
    assert uniform.converged and started.converged, (uniform.message, started.message)
    assert started.iterations < uniform.iterations, \
        f"{started.iterations} iterations from the strips' pressure, {uniform.iterations} from a uniform one"
    assert np.abs(started.pressure - uniform.pressure).max() < 1e-5 * uniform.pressure.max(), "the same pressure"


def test_the_default_tolerances_settle_the_forces():
    """Newton's default tolerance (ITERATION_TOLERANCE) and the normal problem's (NORMAL_TOLERANCE) give the forces
    of a solve 100 times tighter in both within 1e-6 mu Fn, the approach within 1e-7."""
    scene = patch_scene(two_wells(), 1e-3, -5e-4, 0.5, friction=ExponentialFalling(MU, 0.4, 0.5), rolling_speed=20.0)
    default = solve_discretised(scene)
    tight = solve_discretised(scene, iteration_tolerance=ITERATION_TOLERANCE / 100,
                              normal_tolerance=NORMAL_TOLERANCE / 100)
    assert default.success and tight.success, (default.message, tight.message)
    scale = MU * scene.normal_load
    for name, unit in (("longitudinal_force", 1.0), ("lateral_force", 1.0), ("spin_moment", tight.c)):
        error = abs(getattr(default, name) - getattr(tight, name)) / (scale * unit)
        assert error < 1e-6, f"{name}: the default tolerances off a tighter solve by {error:.1e}"
    assert math.isclose(default.approach, tight.approach, rel_tol=1e-7), "the approach"


def test_the_modelled_cost_follows_the_patch_and_bounds_its_elements():
    """The cost before solving counts the elements of Hertz's ellipse at the gap's deepest point (twice them): at
    least those the solve then has in contact, and growing with the load as the area does (N^(2/3)), so that a budget
    refuses a patch too large for it before any work."""
    from rollcontact.wheelrail.methods.discretised import SECONDS_PER_ELEMENT, DiscretisedPatchAccuracy

    model = DiscretisedPatchAccuracy()
    gap, _ = quadratic(0.5, c=6e-3)
    scene = patch_scene(gap, 1e-3)
    solved = solve_discretised(scene)
    assert model.cost(scene, {}) >= SECONDS_PER_ELEMENT * solved.info["contact_elements"], \
        f"modelled {model.cost(scene, {}):.3g} s for {solved.info['contact_elements']} elements in contact"
    heavy, fixed = scene.replace(normal_load=1e3 * scene.normal_load), {"element": 0.2e-3}
    assert model.cost(heavy, fixed) >= 0.99 * 100.0 * model.cost(scene, fixed), \
        f"a thousand times the load: {model.cost(heavy, fixed):.3g} s against {model.cost(scene, fixed):.3g} s"
