"""The elliptic dispatcher keeps the 2D contract: named methods, ``auto`` by rank, by tolerance (the cheapest setting
whose error estimate meets it), a budget on the modelled cost, the registry as extension point, and the one fallback
rule; its registry is its own (the 2D registry does not see the 3D levels)."""

from __future__ import annotations

import math

import pytest

import rollcontact
from rollcontact import ELLIPTIC_METHODS, EllipticResult, EllipticScene, register_elliptic_method, solve_elliptic
from rollcontact.core.method import AccuracyModel


def scene(**creepages):
    return EllipticScene.from_semi_axes(1e5, 6e-3, 4e-3, friction=0.3, **creepages)


def test_named_methods_report_their_name_and_the_force_signs():
    for name in ("linear", "fastsim"):
        result = solve_elliptic(scene(longitudinal_creepage=1e-4, lateral_creepage=1e-4), name)
        assert result.method == name and result.success, f"{name}: {result.message}"
        assert result.longitudinal_force > 0 and result.lateral_force > 0, f"{name}: creepage > 0 gives force > 0"
        assert math.isfinite(result.info["error_estimate"]), f"{name} reports its error estimate"


def test_unknown_method_and_wrong_scene_are_refused():
    with pytest.raises(ValueError, match="valid methods are"):
        solve_elliptic(scene(), "carter3d")
    with pytest.raises(TypeError, match="EllipticScene"):
        solve_elliptic(rollcontact.Scene(1e5), "fastsim")


def test_auto_by_tolerance_takes_the_cheapest_level_that_meets_it():
    small = solve_elliptic(scene(longitudinal_creepage=1e-7), tolerance=0.01)
    assert small.method == "saturated" and small.info["tolerance_met"], \
        f"at vanishing creepage the saturated linear theory meets 1 % at the linear theory's cost, ranked before it " \
        f"({small.method}, {small.info})"
    large = solve_elliptic(scene(longitudinal_creepage=3e-3), tolerance=0.1)
    assert large.method != "linear" and large.info["tolerance_met"], \
        f"past saturation the linear theory misses 10 % of mu Fn ({large.method})"


def test_a_budget_below_every_modelled_cost_refuses_without_solving():
    result = solve_elliptic(scene(longitudinal_creepage=1e-3), budget=1e-9)
    assert not result.success and result.info.get("over_budget"), f"refused: {result.message}"
    assert math.isnan(result.longitudinal_force), "nothing solved"


def test_the_2d_registry_does_not_see_the_elliptic_levels():
    assert "fastsim" not in rollcontact.METHODS and "linear" not in rollcontact.METHODS, "2D registry untouched"


class Exact(AccuracyModel):
    def ladder(self, scene):
        return ({},)

    def cost(self, scene, options):
        return 1.0

    def error(self, scene, options):
        return 1e-6


def broken(scene, **options):
    return EllipticResult.from_scene(scene, "broken", False, "did not converge")


def reference(scene, **options):
    return EllipticResult.from_scene(scene, "reference", True, "reference", (1.0, 2.0, 3.0))


@pytest.fixture
def registered():
    register_elliptic_method("broken", broken, lambda s: None, -5)
    # rank 90: below the built-in discretised fallback (100), so that the fallback rule picks this one
    register_elliptic_method("reference", reference, lambda s: None, 90, fallback=True, accuracy=Exact())
    yield
    del ELLIPTIC_METHODS["broken"], ELLIPTIC_METHODS["reference"]


def test_auto_falls_back_to_the_registered_fallback_once(registered):
    result = solve_elliptic(scene(longitudinal_creepage=1e-3))
    assert result.method == "reference" and result.success, f"fell back: {result.message}"
    assert result.info["fallback_from"] == "broken" and "did not converge" in result.info["fallback_reason"], \
        "the failed method and its reason are reported"
    named = solve_elliptic(scene(longitudinal_creepage=1e-3), "broken")
    assert not named.success and named.method == "broken", "a named method never falls back"


def test_a_registered_method_takes_part_in_auto_with_a_tolerance(registered):
    result = solve_elliptic(scene(longitudinal_creepage=3e-3), tolerance=1e-4)
    assert result.method == "reference" and result.info["tolerance_met"], \
        f"only its error model meets 1e-4 ({result.method})"


@pytest.mark.parametrize(("field", "value", "match"), [("normal_load", -1.0, "normal_load"),
                                                        ("longitudinal_creepage", math.nan, "longitudinal_creepage"),
                                                        ("spin_creepage", math.inf, "spin_creepage"),
                                                        ("lateral_curvature", 0.0, "lateral_curvature")])
def test_bad_scene_values_are_refused_with_the_field(field, value, match):
    with pytest.raises(ValueError, match=match):
        scene().replace(**{field: value})


def test_a_level_refuses_an_aspect_ratio_outside_its_table():
    slender = EllipticScene.from_semi_axes(1e5, 1e-3, 2e-2, longitudinal_creepage=1e-3)
    with pytest.raises(ValueError, match="a/b = 0.05 is outside"):
        solve_elliptic(slender, "fastsim")


def test_zero_load_gives_no_forces():
    result = solve_elliptic(EllipticScene(0.0, 1.0, 2.0, longitudinal_creepage=1e-3), "fastsim")
    assert result.success and result.longitudinal_force == 0.0 and result.force_coefficients == (0.0, 0.0, 0.0), \
        "no load, no contact"


@pytest.mark.parametrize("name", ["strips", "fastsim"])
def test_random_scenes_stay_within_the_friction_bound(name):
    """200 random scenes (a/b 0.1..10, creepages 1e-7..1e-1 of both signs, spin alone, none, and psi at +-1 where strip
    theory's stick zone vanishes): finite forces, success, and |(Fx, Fy)| <= mu Fn to round-off."""
    import numpy as np

    from rollcontact.elliptic.methods.strips import StripStack

    rng = np.random.default_rng(7)
    for _ in range(200):
        g = math.exp(rng.uniform(math.log(0.1), math.log(10.0)))
        s = EllipticScene.from_semi_axes(1e5, 5e-3 * math.sqrt(g), 5e-3 / math.sqrt(g), friction=0.3)
        xi, eta, phi = rng.normal(size=3) * 10 ** rng.uniform(-7, -1) * (1.0, 1.0, 300.0)
        kind = rng.integers(0, 4)
        if kind == 1:
            phi = 0.0
        elif kind == 2:
            xi = eta = 0.0
        elif kind == 3:
            phi = rng.choice([-1.0, 1.0]) * (1.0 + rng.choice([0.0, 1e-12, -1e-12])) / StripStack(
                (s.replace(spin_creepage=1.0),), 4).psi[0, 0]
        result = solve_elliptic(s.replace(longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi), name)
        f = result.force_coefficients
        assert result.success and all(math.isfinite(v) for v in f), f"{name} at {g, xi, eta, phi}: {result.message}"
        total = math.hypot(f[0], f[1])
        assert total <= 1.0 + 1e-12, f"{name}: |F| = {total} mu Fn at {g, xi, eta, phi}"


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # a level's own overflow, which its result then reports
@pytest.mark.parametrize("creepages", [{"longitudinal_creepage": 1e300}, {"lateral_creepage": -1e300},
                                       {"spin_creepage": 1e300}, {"longitudinal_creepage": 1e160}])
def test_forces_beyond_floating_point_are_a_failure_that_says_so(creepages):
    """Creepages so large that a level's own scaling overflows (FASTSIM's from about 1e155, the strips' from about
    1e300) give either finite forces or an unsuccessful result naming the creepages, never a success with NaN."""
    for name in ("linear", "saturated", "fastsim", "strips"):
        result = solve_elliptic(scene(**creepages), name)
        finite = all(map(math.isfinite, (result.longitudinal_force, result.lateral_force, result.spin_moment)))
        assert finite == result.success, f"{name} at {creepages}: success {result.success}, {result.message}"
        if not result.success:
            assert "not finite at the creepages" in result.message and "e+" in result.message, result.message
