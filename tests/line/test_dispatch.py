"""The dispatcher: method registry, automatic choice, one result type, errors that list the valid choices."""

from __future__ import annotations

import math

import numpy as np
import pytest

import rollcontact
from rollcontact import METHODS, ContactResult, ExponentialFalling, Harmonic, Scene, Surface, choose_method, solve
from rollcontact.core.method import ROUND_OFF, UNRESOLVED, AccuracyModel, MethodSpec, Setting
from rollcontact.line.dispatch import DISPATCHER, choose_setting, setting_for
from rollcontact.line.methods.closed_form import solve_closed_form
from rollcontact.line.methods.discretised.accuracy import EXTRAPOLATION_PLACEMENTS
from rollcontact.line.methods.discretised.steady import DISCRETISED_ELEMENTS, extrapolated
from rollcontact.line.methods.polynomial.accuracy import normal_pressure

HERTZIAN = Scene(1e6, creep=4e-4)
TILTED = Scene(1e6, creep=-4e-4, surface=Surface(polynomial=(0.0, 2e-3)))
CORRUGATED = Scene(1e6, creep=4e-4, surface=Surface(harmonics=(Harmonic.from_wavelength(0.04, 20e-6),)),
                   axis_position=0.005)
QUARTIC = Scene(1e6, creep=4e-4, surface=Surface(polynomial=(0.0, 0.0, 0.0, 0.0, -1e5)))


def all_results():
    """Every (scene, method) combination that must give a ContactResult.

    Returns
    -------
    list of tuple
        ``(label, scene, method)``.
    """
    cases = [("hertzian auto", HERTZIAN, "auto"), ("hertzian closed", HERTZIAN, "closed_form"),
             ("hertzian poly", HERTZIAN, "polynomial"), ("tilted closed", TILTED, "closed_form"),
             ("corrugated auto", CORRUGATED, "auto"), ("corrugated poly", CORRUGATED, "polynomial"),
             ("quartic auto", QUARTIC, "auto"), ("no load", Scene(0.0, creep=1e-3), "auto")]
    return cases


def test_unknown_method_lists_valid_ones():
    with pytest.raises(ValueError, match="valid methods") as info:
        solve(HERTZIAN, method="finite_elements")
    message = str(info.value)
    assert "finite_elements" in message, f"the message should name the bad method: {message}"
    for name in ("auto", "closed_form", "polynomial"):
        assert name in message, f"the message should list {name!r}: {message}"


def test_registry_holds_the_steady_methods():
    assert {"closed_form", "polynomial"} <= set(METHODS), f"registry: {sorted(METHODS)}"
    assert METHODS["closed_form"].rank < METHODS["polynomial"].rank, "closed_form must rank before polynomial"


@pytest.mark.parametrize("scene, expected", [
    (HERTZIAN, "closed_form"),
    (TILTED, "closed_form"),
    (CORRUGATED, "polynomial"),
    (QUARTIC, "polynomial"),
], ids=["hertzian", "tilted", "corrugated", "quartic"])
def test_auto_picks_the_cheapest_exact_method(scene, expected):
    assert choose_method(scene) == expected, f"choose_method gave {choose_method(scene)!r}, expected {expected!r}"
    result = solve(scene)
    assert result.method == expected, f"auto used {result.method!r}, expected {expected!r}"
    assert result.success, f"{expected}: {result.message}"


def test_auto_on_hertzian_scene_equals_explicit_closed_form():
    auto, explicit = solve(HERTZIAN), solve(HERTZIAN, method="closed_form")
    for name in ("tangential_force_per_length", "contact_half_width", "stick_half_width", "max_pressure"):
        assert getattr(auto, name) == getattr(explicit, name), f"{name}: auto {getattr(auto, name)} vs explicit"


def test_closed_form_refuses_a_corrugated_scene():
    with pytest.raises(ValueError, match="parabolic"):
        solve(CORRUGATED, method="closed_form")


def test_closed_form_refuses_velocity_dependent_friction():
    scene = HERTZIAN.replace(friction=ExponentialFalling(0.4, 0.4, 0.6))
    with pytest.raises(ValueError, match="friction"):
        solve(scene, method="closed_form")


def test_closed_form_rejects_options():
    with pytest.raises(TypeError, match="order"):
        solve(HERTZIAN, method="closed_form", order=10)


def test_auto_ignores_options_the_chosen_method_does_not_take():
    result = solve(HERTZIAN, order=12, basis="chebyshev")
    assert result.method == "closed_form" and result.success, f"auto with polynomial options: {result}"
    poly = solve(CORRUGATED, order=12)
    assert poly.method == "polynomial" and poly.info.get("order") == 12, f"order must reach the polynomial: {poly}"


def test_solve_rejects_a_non_scene():
    with pytest.raises(TypeError, match="Scene"):
        solve({"normal_load_per_length": 1e6})


@pytest.mark.parametrize("label, scene, method", all_results(), ids=[c[0] for c in all_results()])
def test_every_result_is_a_contact_result_with_status(label, scene, method):
    result = solve(scene, method=method)
    assert isinstance(result, ContactResult), f"{label}: got {type(result).__name__}"
    assert isinstance(result.success, bool) and result.success, f"{label}: {result.message}"
    assert isinstance(result.message, str) and result.message, f"{label}: empty message"
    assert result.method in METHODS, f"{label}: method {result.method!r} not in the registry"
    n = scene.normal_load_per_length
    assert result.normal_load_per_length == n, f"{label}: N' {result.normal_load_per_length} vs {n}"
    expected = result.tangential_force_per_length / n if n > 0 else 0.0
    assert result.traction_coefficient == expected, f"{label}: traction_coefficient {result.traction_coefficient}"
    assert abs(result.traction_coefficient) <= scene.friction_coefficient * (1 + 1e-12), \
        f"{label}: |T'/N'| = {abs(result.traction_coefficient)} > mu"
    if n > 0:
        np.testing.assert_allclose(result.leading_edge, result.contact_offset - result.contact_half_width,
                                   rtol=1e-15, err_msg=f"{label}: leading edge = Delta - a")
        np.testing.assert_allclose(result.trailing_edge, result.contact_offset + result.contact_half_width,
                                   rtol=1e-15, err_msg=f"{label}: trailing edge = Delta + a")
        x = result.contact_offset + np.array([-1.5, 0.0, 1.5]) * result.contact_half_width
        p = result.pressure(x)
        assert p[0] == 0.0 and p[2] == 0.0 and p[1] > 0.0, f"{label}: p outside/inside the patch: {p}"
        assert math.isfinite(result.max_pressure) and result.max_pressure >= p[1], f"{label}: max_pressure"


def test_traction_coefficient_matches_carter():
    result = solve(HERTZIAN)
    a = math.sqrt(4 * 1e6 * 0.46 / (math.pi * HERTZIAN.material.contact_modulus))
    ratio = 1 - (a - 0.46 * 4e-4 / 0.3) ** 2 / a**2
    np.testing.assert_allclose(result.traction_coefficient, 0.3 * ratio, rtol=1e-13,
                               err_msg="T'/N' = mu (1 - (a*/a)^2)")


def test_package_exports_the_documented_entry_points():
    for name in ("Scene", "solve", "ContactResult", "load_scene", "SceneError", "METHODS"):
        assert hasattr(rollcontact, name) and name in rollcontact.__all__, f"rollcontact.{name} missing"


def test_auto_solves_a_split_contact_as_several_patches_never_as_one():
    split = Scene(1e6, creep=2e-4, surface=Surface(harmonics=(Harmonic.from_wavelength(0.010, 20e-6),)),
                  axis_position=0.0045)
    result = solve(split)
    assert isinstance(result, ContactResult), f"got {type(result).__name__}"
    assert result.success and result.method == "polynomial", result.message
    assert len(result.info["patches"]) == 2, f"a split contact must not be answered as one patch: {result.info}"


def test_auto_falls_back_where_several_patches_break_the_polynomial_structure():
    """A patch that slips at its leading edge and sticks behind (no stick zone at each leading edge): the slip of
    the polynomial method's solution turns against the creep, the method says so, and the discretised solver, which
    assumes no structure, answers."""
    result = solve(UNSOLVED_SPLIT)
    assert result.success and result.method == "discretised", result.message
    assert result.info["fallback_from"] == "polynomial" and "second stick zone" in result.info["fallback_reason"], \
        result.info



# a soft roller (E = 1 MPa, a = 5 cm) on a corrugation of 1.07 mm wavelength (k a = 293, ~93 waves in the patch):
# beyond what the polynomial method's order 170 resolves: its answer converges with an error estimate of 49 (and
# |q| above mu p by 1.4 % of mu p0), which auto must take as a failure
UNRESOLVED_CORRUGATION = Scene(1000.0, creep=1e-7, radius=1.0, material=rollcontact.Material(1e6, 0.0),
                               friction=rollcontact.Coulomb(0.001),
                               surface=Surface(harmonics=(Harmonic(5857.780147685687, 2.0975242650564358e-06, 0.0),)))


@pytest.mark.slow
def test_auto_falls_back_where_the_error_estimate_says_nothing():
    """An answer whose own error estimate is >= 1 (api.UNRESOLVED) is treated as a failure: auto falls back to the
    discretised solver and says why; asked for explicitly, the polynomial method still answers, its estimate
    attached; the two forces agree (the polynomial's T' was right, its distributions were not)."""
    explicit = solve(UNRESOLVED_CORRUGATION, method="polynomial")
    assert explicit.success and explicit.info["error_estimate"] >= UNRESOLVED, explicit.info
    for options in ({}, {"tolerance": 1e-3}):
        result = solve(UNRESOLVED_CORRUGATION, **options)
        assert result.method == "discretised" and result.success, f"{options}: {result.message}"
        assert result.info["fallback_from"] == "polynomial", f"{options}: {result.info}"
        assert "error estimate 49" in result.info["fallback_reason"], result.info["fallback_reason"]
        assert result.info["error_estimate"] < 0.1, f"{options}: {result.info['error_estimate']}"
        assert result.tangential_force_per_length == pytest.approx(explicit.tangential_force_per_length,
                                                                   rel=result.info["error_estimate"]), options


# ------------------------------------------------------------------------------------------ tolerance-aware auto
# One case per benchmark family (benchmarks/pareto.py has more).  Error: the larger relative error of T' and p0
# against a reference independent of the setting under test.
SATURATION = 0.3 * rollcontact.hertz(1e6, 0.46, HERTZIAN.material.contact_modulus)[0] / 0.46  # Carter mu a / R
FAMILY_CASES = {
    "hertz/carter": HERTZIAN,
    "polynomial profile": QUARTIC,
    "corrugation 40 mm / 20 um": CORRUGATED,
    "corrugation 20 mm / 5 um": CORRUGATED.replace(
        surface=Surface(harmonics=(Harmonic.from_wavelength(0.02, 5e-6),))),
    "split contact 10 mm / 20 um": Scene(1e6, creep=1e-3, axis_position=0.0045,
                                         surface=Surface(harmonics=(Harmonic.from_wavelength(0.010, 20e-6),))),
    "velocity-dependent friction": Scene(1e6, creep=0.3 * SATURATION, rolling_speed=20.0,
                                         friction=ExponentialFalling(0.3, 0.4, 3.0)),
}
TOLERANCES = {name: (1e-2, 1e-3, 1e-4) for name in FAMILY_CASES}
# 10 mm / 10 um, axis 5.42 mm, half the saturation creep: two patches, the trailing one slipping at its leading
# edge ahead of its stick zone (the discretised active set), outside the structure of rollcontact.multipatch: only the
# discretised solver treats it
UNSOLVED_SPLIT = Scene(1e6, creep=0.5 * SATURATION, axis_position=0.010 * 13 / 24,
                       surface=Surface(harmonics=(Harmonic.from_wavelength(0.010, 10e-6),)))
# How pessimistic each kind of setting's error bound may be (bound / error, measured by benchmarks/pareto.py): auto
# pays at most for that much accuracy it did not need.  The polynomial truncation tolerance costs nothing (flat cost
# model), so its slack only concerns the slip iteration's nodes.  The extrapolated discretised pair errs too
# erratically for any slack (bound / error 1.4 to 1000, benchmarks/calibrate_discretised_estimate.py table C): it
# enters only the comparison with settings whose own bound meets t.
SLACK = {"closed_form": 1.0, "polynomial": 20.0, "discretised": 12.0, "discretised extrapolated": math.inf}


def kind(setting) -> str:
    """The key of :data:`SLACK`: the method, told apart for the extrapolated discretised pair."""
    return setting.method + (" extrapolated" if setting.options.get("extrapolate") else "")


def reference(scene):
    """Converged reference: the closed form; the polynomial method at tolerance 1e-12 (nodes 512 for
    velocity-dependent friction; several patches for the split contact), itself checked against the extrapolated
    discretised solver in test_cross_methods.py and test_multipatch.py; where the polynomial method fails, the
    discretised solver extrapolated from n = 1000/2000, each level the mean over 8 grid placements
    (:func:`extrapolated`)."""
    if scene.surface.is_flat and scene.friction.is_constant:
        return solve(scene, method="closed_form")
    poly = solve(scene, method="polynomial", truncation=1e-12, nodes=512)
    return poly if poly.success else extrapolated(scene, (1000, 2000), placements=8)


def relative_error(result, ref) -> float:
    return max(abs(result.tangential_force_per_length / ref.tangential_force_per_length - 1.0),
               abs(result.max_pressure / ref.max_pressure - 1.0))


def measured_settings(scene):
    """Every setting of every applicable method's ladder (to keep the test short: nodes <= 128, and extrapolated
    discretised pairs up to 200/400 where another method treats the scene):
    ``[(setting, error, envelope)]``, the envelope being the largest error of this and the finer settings of the
    same kind (a setting has converged to t when its envelope is <= t; the discretised error is not monotone
    in n)."""
    ref = reference(scene)
    rows = []
    for spec in METHODS.values():
        if spec.accuracy is None or spec.inapplicable(scene) is not None:
            continue
        method_rows = []
        for options in spec.accuracy.ladder(scene):
            if options.get("nodes", 0) > 128 or (options.get("extrapolate") and options["elements"] > 200
                                                 and ref.method != "discretised"):
                continue
            result = solve(scene, method=spec.name, **options)
            if result.success:
                setting = Setting(spec.name, options, spec.accuracy.error(scene, options),
                                                  spec.accuracy.cost(scene, options))
                method_rows.append((setting, relative_error(result, ref)))
        for i, (setting, error) in enumerate(method_rows):
            finer = [e for s, e in method_rows[i:] if kind(s) == kind(setting)]
            rows.append((setting, error, max(finer)))
    return ref, rows


@pytest.mark.parametrize("name", list(FAMILY_CASES))
def test_auto_meets_the_tolerance_at_the_lowest_cost(name):
    """auto's result errs by at most t against the reference, and no measured setting that converged to
    t / SLACK (the documented pessimism of its method's bound; where none did, no setting whose bound meets t) is
    cheaper by the deterministic cost model: auto is the cheapest setting up to what an a-priori error bound can
    know."""
    scene = FAMILY_CASES[name]
    ref, rows = measured_settings(scene)
    assert rows, f"{name}: no measured setting"
    for tolerance in TOLERANCES[name]:
        auto = solve(scene, tolerance=tolerance)
        assert auto.success and auto.info["tolerance_met"], f"{name}, t = {tolerance}: {auto.message}"
        error = relative_error(auto, ref)
        assert error <= tolerance, \
            f"{name}: auto ({auto.method}, {auto.info['setting']}) error {error:.3g} > {tolerance}"
        assert auto.info["error_estimate"] <= tolerance, f"{name}: estimate {auto.info['error_estimate']}"
        cost = METHODS[auto.method].accuracy.cost(scene, auto.info["setting"])
        # every measured setting that converged to t with room for its model's slack costs at least as much
        enough = [(s, e) for s, e, envelope in rows if envelope <= tolerance / SLACK[kind(s)]]
        if not enough:  # the split contact: no rung up to 1600 elements converges to t / slack; then no setting
            # whose own bound meets t may be cheaper
            enough = [(s, e) for s, e, _ in rows if s.error_estimate <= tolerance]
        assert enough, f"{name}, t = {tolerance}: no measured setting converged to t / slack or is bounded by t"
        cheapest = min(enough, key=lambda row: row[0].cost)[0]
        assert cost <= cheapest.cost * (1 + 1e-12), \
            f"{name}, t = {tolerance}: auto took {auto.method} {auto.info['setting']} (model cost {cost:.3g} s), " \
            f"but {cheapest.method} {cheapest.options} converged (model cost {cheapest.cost:.3g} s)"


@pytest.mark.parametrize("name", ["corrugation 40 mm / 20 um", "split contact 10 mm / 20 um",
                                  "velocity-dependent friction"])
def test_predicted_errors_bound_the_measured_errors(name):
    """What makes auto safe: no measured setting errs by more than its prediction (how pessimistic the bounds are
    varies with the case, benchmarks/results/pareto.md lists the ratios)."""
    scene = FAMILY_CASES[name]
    _, rows = measured_settings(scene)
    for setting, error, _ in rows:
        assert error <= setting.error_estimate, f"{name}: {setting} has error {error:.3g} above its bound"


def test_cost_model_ranks_the_methods_and_settings():
    """Deterministic cost model (no timing): closed form < polynomial < discretised, cost grows with n and nodes."""
    cost = {name: METHODS[name].accuracy.cost for name in ("closed_form", "polynomial", "discretised")}
    assert cost["closed_form"](CORRUGATED, {}) < cost["polynomial"](CORRUGATED, {"tolerance": 1e-12}), "closed < poly"
    assert cost["polynomial"](CORRUGATED, {"tolerance": 1e-12}) < cost["discretised"](CORRUGATED, {"elements": 50}), \
        "polynomial < coarsest discretised"
    falling = FAMILY_CASES["velocity-dependent friction"]
    poly = [cost["polynomial"](falling, {"nodes": n}) for n in (8, 16, 32, 64)]
    disc = [cost["discretised"](falling, {"elements": n}) for n in (50, 100, 200, 400)]
    assert poly == sorted(poly) and disc == sorted(disc), f"costs must grow with the resolution: {poly}, {disc}"


@pytest.mark.parametrize("name", list(FAMILY_CASES))
def test_each_models_floor_is_below_every_cost_it_models(name):
    """auto skips a method once its best setting costs at most the method's ``floor``; that is only safe if no
    setting of the method, on any scene, is cheaper than the floor."""
    scene = FAMILY_CASES[name]
    for spec in METHODS.values():
        model = spec.accuracy
        if model is None:
            continue
        costs = [model.cost(scene, options) for options in model.ladder(scene)] + [model.minimum_cost(scene)]
        assert model.floor <= min(costs), f"{name}: {spec.name} floor {model.floor:.3g} s > cost {min(costs):.3g} s"


@pytest.mark.slow
def test_auto_reports_a_tolerance_it_cannot_reach():
    """Only the discretised solver treats UNSOLVED_SPLIT, and none of its settings certifies 1e-4."""
    scene = UNSOLVED_SPLIT
    result = solve(scene, tolerance=1e-4)
    assert result.success and result.method == "discretised", result.message
    assert not result.info["tolerance_met"] and result.info["error_estimate"] > 1e-4, result.info
    assert "not reached" in result.message, f"the message must say so: {result.message!r}"
    most_accurate = {"elements": max(DISCRETISED_ELEMENTS) // 2,
                     "extrapolate": max(EXTRAPOLATION_PLACEMENTS)}
    assert result.info["setting"] == most_accurate, \
        f"the most accurate setting should be used: {result.info['setting']}"


@pytest.mark.parametrize("tolerance, extrapolate", [(3e-2, False), (1e-2, None), (3e-3, True), (1e-3, True)])
@pytest.mark.slow
def test_discretised_setting_is_the_fewest_elements_whose_bound_meets_the_tolerance(tolerance, extrapolate):
    """Any count between the ladder's ends, not only its rungs (the bound is within 1.3-2x of the worst-placement
    error, so the next rung could cost 4-8x), of the cheapest kind by the cost model: a single grid, or from ~1e-2
    down an extrapolated pair over 8 or 16 placements (None: either); on a split contact only the discretised
    method treats."""
    scene = UNSOLVED_SPLIT
    model = METHODS["discretised"].accuracy
    setting = setting_for("discretised", scene, tolerance)
    options = setting.options
    n = options["elements"]
    if extrapolate is not None:
        assert bool(options.get("extrapolate")) == extrapolate, setting
    assert setting.error_estimate <= tolerance < model.error(scene, {**options, "elements": n - 1}), setting
    tops = {0: max(DISCRETISED_ELEMENTS)}
    tops.update((m, tops[0] // 2) for m in EXTRAPOLATION_PLACEMENTS)
    for m, top in tops.items():  # the fewest elements of every kind that meets t costs at least as much
        other = {"elements": 1, **({"extrapolate": m} if m else {})}
        while model.error(scene, other) > tolerance and other["elements"] < top:
            other["elements"] += 1
        if model.error(scene, other) <= tolerance:
            assert setting.cost <= model.cost(scene, other), f"{other} would be cheaper than {setting}"
    # run: the chosen setting, then finer ones while the result's patch-aware estimate misses t (the small leading
    # patch is narrower than the Hertz width of the a-priori bound)
    result = solve(scene, tolerance=tolerance)
    used = result.info["setting"]
    assert result.method == "discretised" and model.error(scene, used) <= setting.error_estimate, \
        f"{used} is neither the chosen {options} nor finer"
    assert result.info["tolerance_met"] == (result.info["error_estimate"] <= tolerance), result.info
    pair = bool(used.get("extrapolate"))
    assert result.info["grid"].elements == used["elements"] * (2 if pair else 1), result.info


def test_user_elements_fix_one_grid_instead_of_the_extrapolated_pair():
    """auto's discretised setting for a split contact at 1e-3 is the extrapolated pair; a caller who fixes
    ``elements`` gets one grid of that many (the tolerance is then only reported), unless they ask for the pair."""
    scene = UNSOLVED_SPLIT
    assert setting_for("discretised", scene, 1e-3).options.get("extrapolate"), "premise"
    single = solve(scene, tolerance=1e-3, elements=300)
    assert single.info["setting"] == {"elements": 300} and single.info["grid"].elements == 300, single.info
    assert not single.info["tolerance_met"], "300 elements cannot certify 1e-3"
    pair = solve(scene, tolerance=1e-3, elements=100, extrapolate=8)
    assert pair.info["setting"] == {"elements": 100, "extrapolate": 8}, pair.info["setting"]
    assert pair.info["grid"].elements == 200 and pair.info["placements"] == 8, pair.info


def test_without_tolerance_auto_keeps_the_method_defaults():
    result = solve(CORRUGATED)
    assert "tolerance" not in result.info and result.info["order"] == solve(CORRUGATED, method="polynomial").info[
        "order"], "no tolerance: the polynomial's own default order"
    assert 0 < result.info["error_estimate"] <= 1e-9, f"default estimate {result.info['error_estimate']}"


@pytest.mark.parametrize("method", ["closed_form", "polynomial", "discretised"])
def test_every_method_reports_an_error_estimate(method):
    result = solve(HERTZIAN, method=method)
    estimate = result.info["error_estimate"]
    assert math.isfinite(estimate) and estimate > 0.0, f"{method}: {estimate}"
    error = abs(result.tangential_force_per_length / solve(HERTZIAN, method="closed_form").tangential_force_per_length
                - 1.0)
    assert error <= estimate, f"{method}: error {error:.3g} above its estimate {estimate:.3g}"


def test_explicit_options_override_the_chosen_setting():
    result = solve(CORRUGATED, tolerance=1e-2, order=12)
    assert result.info["order"] == 12 and result.info["setting"]["order"] == 12, result.info["setting"]
    assert result.info["error_estimate"] == max(result.residual, ROUND_OFF), \
        "with an explicit order the estimate is the truncation residual"


@pytest.mark.parametrize("tolerance", [0.0, -1e-3, math.nan, math.inf, "tight"])
def test_a_bad_tolerance_is_refused(tolerance):
    with pytest.raises(ValueError, match="tolerance"):
        solve(CORRUGATED, tolerance=tolerance)


def test_an_explicit_method_with_a_tolerance_runs_its_cheapest_setting_that_meets_it():
    """``tolerance`` is the requested accuracy with a named method too (its own knob is ``truncation``): the
    method's cheapest setting whose estimate meets it, judged like auto's, and no other method."""
    result = solve(CORRUGATED, method="polynomial", tolerance=1e-3)
    assert result.method == "polynomial" and result.info["tolerance_met"], result.message
    assert result.info["setting"] == {"truncation": 1e-3}, f"the loosest truncation that meets 1e-3: {result.info}"
    truncated = solve(CORRUGATED, method="polynomial", truncation=1e-3)
    assert result.info["order"] == truncated.info["order"] < solve(CORRUGATED, method="polynomial").info["order"], \
        "the setting is the method's truncation, coarser than its default"
    assert "tolerance_met" not in truncated.info, "without a tolerance nothing is judged"
    grid = solve(HERTZIAN, method="discretised", tolerance=2e-2)
    assert grid.method == "discretised" and grid.info["tolerance_met"], grid.message


def test_a_registered_method_with_its_own_accuracy_model_competes(monkeypatch):
    class Cheap(AccuracyModel):
        def ladder(self, scene):
            return ({"level": 1}, {"level": 2})

        def cost(self, scene, options):
            return 1e-9 * options["level"]

        def error(self, scene, options):
            return 10.0 ** -options["level"]

    def surrogate(scene, level=1):
        exact = solve(scene, method="polynomial", truncation=1e-12)
        return ContactResult(**{**exact.__dict__, "method": "surrogate", "info": {"level": level}})

    surrogate.options = ("level",)
    monkeypatch.setitem(METHODS, "surrogate", MethodSpec("surrogate", surrogate, lambda s: None, 5,
                                                                         accuracy=Cheap()))
    assert solve(CORRUGATED, tolerance=0.5).info["level"] == 1, "cheapest setting meeting 0.5"
    assert solve(CORRUGATED, tolerance=0.05).info["level"] == 2, "0.1 does not meet 0.05"
    assert solve(CORRUGATED, tolerance=1e-3).method == "polynomial", "the surrogate cannot reach 1e-3"
    assert choose_method(CORRUGATED, tolerance=0.05) == "surrogate", "choose_method with a tolerance"


def test_a_method_without_accuracy_model_is_used_only_when_nothing_else_applies(monkeypatch):
    only = solve_closed_form

    for name in list(METHODS):
        monkeypatch.delitem(METHODS, name)
    monkeypatch.setitem(METHODS, "plain", MethodSpec("plain", only, lambda s: None, 0))
    result = solve(HERTZIAN, tolerance=1e-3)
    assert result.success and math.isnan(choose_setting(HERTZIAN, 1e-3).error_estimate), \
        "an unmodelled method gives no estimate"
    assert result.info["tolerance_met"] is False, "an unknown error cannot be said to meet the tolerance"


FALLING = Scene(1e6, creep=1e-3, rolling_speed=20.0, friction=ExponentialFalling(0.3, 0.4, 3.0))


def test_auto_escalates_the_slip_nodes_until_its_estimate_meets_the_tolerance():
    """The slip iteration starts at its cheapest node count; its a-posteriori estimate (a bound of the error,
    benchmarks/calibrate_slip_nodes.py) then drives the count up until it meets t, checked here against 512 nodes."""
    start = choose_setting(FALLING, 1e-6).options["nodes"]
    result = solve(FALLING, tolerance=1e-6)
    fine = solve(FALLING, method="polynomial", nodes=512)
    assert result.info["tolerance_met"], result.message
    assert result.info["setting"]["nodes"] > start, f"no escalation from {start} nodes"
    error = abs(result.tangential_force_per_length / fine.tangential_force_per_length - 1.0)
    assert error <= 1e-6, f"T' off by {error:.3g} at {result.info['setting']['nodes']} nodes"


def test_user_nodes_stop_the_escalation():
    result = solve(FALLING, tolerance=1e-9, nodes=16)
    assert result.info["setting"]["nodes"] == 16
    assert not result.info["tolerance_met"] and "not reached" in result.message


def test_the_fmu_model_escalates_like_solve():
    from rollcontact.stepping import ContactModel, ContactParameters

    model = ContactModel(ContactParameters(friction_law=1, friction_coefficient=0.3, friction_kinetic_ratio=0.4,
                                           friction_decay=3.0, tolerance=1e-6))
    out = model.step(0.0, 1e-3, 1e6 * model.width, 1e-3, 20.0)
    scene = model.scene(out.axis_position, 1e6 * model.width, 1e-3, 20.0)
    reference = solve(scene, tolerance=1e-6)
    assert out.tangential_force == pytest.approx(reference.tangential_force_per_length * model.width, rel=1e-12)


# ------------------------------------------------------------------- the discretised estimate on narrow patches
# 4 mm / 40 um at 0.1 of saturation: three patches of 0.07-0.15 times the Hertz width, the outer two slipping fully
THREE_PATCHES = Scene(1e6, creep=0.1 * SATURATION, axis_position=0.0,
                      surface=Surface(harmonics=(Harmonic.from_wavelength(0.004, 40e-6),)))


@pytest.fixture(scope="module")
def three_patches():
    reference = solve(THREE_PATCHES, method="polynomial", truncation=1e-12)
    assert reference.success and len(reference.info["patches"]) == 3, reference.message
    return reference


def relative_errors(result, reference) -> tuple[float, float]:
    """Relative errors of T' and p0."""
    return (abs(result.tangential_force_per_length / reference.tangential_force_per_length - 1.0),
            abs(result.max_pressure / reference.max_pressure - 1.0))


@pytest.mark.parametrize("options", [{"elements": 100}, {"elements": 400}, {"elements": 50, "extrapolate": 16}],
                         ids=["100", "400", "pair 50/100 x 16"])
def test_discretised_estimate_bounds_the_error_on_narrow_patches(three_patches, options):
    """The a-priori bound (the Hertz width) is exceeded here; the result's estimate, with the patch widths
    (``api.patch_widths``), bounds the T' and p0 errors against the polynomial method's three patches."""
    model = METHODS["discretised"].accuracy
    result = solve(THREE_PATCHES, method="discretised", **options)
    assert result.success and len(result.info["patches"]) == 3, result.message
    force, pressure = relative_errors(result, three_patches)
    estimate = result.info["error_estimate"]
    assert max(force, pressure) > model.error(THREE_PATCHES, options), \
        f"premise: the Hertz-width bound {model.error(THREE_PATCHES, options):.3g} should miss here"
    assert force <= estimate and pressure <= estimate, \
        f"{options}: T' error {force:.3g}, p0 error {pressure:.3g} above the estimate {estimate:.3g}"


@pytest.mark.parametrize("creep", [0.0, 0.2 * SATURATION, 3.0 * SATURATION])
def test_discretised_estimate_of_one_hertzian_patch_is_the_a_priori_bound(creep):
    """One patch as wide as Hertz: the patch widths change nothing (within the element the grid patch may lose);
    at zero creep (no traction to weigh) the Hertz width."""
    scene = HERTZIAN.replace(creep=creep)
    for options in ({"elements": 100}, {"elements": 50, "extrapolate": 8}):
        bound = METHODS["discretised"].accuracy.error(scene, options)
        estimate = solve(scene, method="discretised", **options).info["error_estimate"]
        assert bound <= estimate <= 1.1 * bound, f"{options}, creep {creep}: estimate {estimate:.3g}, bound {bound:.3g}"


def test_discretised_escalation_meets_the_tolerance_the_a_priori_choice_missed(three_patches):
    """auto's discretised route (as where the polynomial method fails): the a-priori choice's estimate misses t,
    the escalation runs finer settings until it meets it, and the error is then within t."""
    model = METHODS["discretised"].accuracy
    tolerance = 3e-2
    first = setting_for("discretised", THREE_PATCHES, tolerance)
    assert solve(THREE_PATCHES, method="discretised", **first.options).info["error_estimate"] > tolerance, \
        "premise: the a-priori choice misses t"
    _, result = DISPATCHER.run_to_tolerance(first, THREE_PATCHES, {}, tolerance)
    used = result.info["setting"]
    assert result.success and result.info["tolerance_met"], result.message
    assert model.error(THREE_PATCHES, used) < first.error_estimate, f"{used} is not finer than {first.options}"
    force, pressure = relative_errors(result, three_patches)
    assert max(force, pressure) <= tolerance, f"{used}: errors {force:.3g}, {pressure:.3g} above {tolerance}"
    grid = {"elements": max(DISCRETISED_ELEMENTS)}
    assert model.escalation(THREE_PATCHES, grid, 1.0, tolerance).get("extrapolate"), "the pair is finer"
    top = {"elements": max(DISCRETISED_ELEMENTS) // 2,
           "extrapolate": max(EXTRAPOLATION_PLACEMENTS)}
    assert model.escalation(THREE_PATCHES, top, 1.0, tolerance) is None, "nothing finer than the finest pair"
    assert model.escalation(THREE_PATCHES, first.options, 0.5 * tolerance, tolerance) is None, "t met: stop"
    assert model.escalation(THREE_PATCHES, first.options, math.nan, tolerance) is None, "no estimate: stop"


def test_auto_retries_a_failed_slip_iteration_on_a_finer_grid():
    """A falling law on three patches (4 mm / 40 um, 0.9 of saturation): the grid auto chooses for t = 0.1 (152
    elements) leaves a slip zone shorter than an element, and the structure fails there; auto's run of the
    discretised method (``run_to_tolerance``, as after a failure of the polynomial method, which solves this scene
    itself: tests/test_split_friction.py) runs twice the elements (``DiscretisedAccuracy.retry``), succeeds, and
    the message keeps the failure."""
    scene = THREE_PATCHES.replace(creep=0.9 * SATURATION, rolling_speed=20.0,
                                  friction=ExponentialFalling(0.3, 0.4, 3.0))
    model = METHODS["discretised"].accuracy
    first = setting_for("discretised", scene, 0.1).options
    assert not solve(scene, method="discretised", **first).success, f"premise: {first} fails"
    spec, result = DISPATCHER.run_to_tolerance(setting_for("discretised", scene, 0.1), scene,
                                                    {}, 0.1)
    assert result.success and spec.name == "discretised", result.message
    assert result.info["setting"]["elements"] > first["elements"], result.info["setting"]
    assert f"after failing with {first}" in result.message, result.message
    assert model.retry(scene, {"elements": 1600}, result) is None, "nothing above the largest grid"
    assert model.retry(scene, {"elements": 100, "extrapolate": 8}, result) is None, "pairs: not retried"
    assert model.retry(THREE_PATCHES, {"elements": 100}, result) is None, "Coulomb: the direct solve has no structure"
    assert model.retry(scene, {"elements": 100}, result) == {"elements": 200}


@pytest.mark.parametrize("surface", [Surface(), Surface(polynomial=(1e-5, 2e-3))], ids=["flat", "tilted"])
@pytest.mark.parametrize("load", [0.0, 3e5, 1e6])
def test_the_pressure_of_a_flat_surface_for_the_slip_floor_is_hertz(surface, load):
    """normal_pressure (the slip-node floor's input, asked at every FMU step with a tolerance) takes Hertz's
    coefficients on a flat surface instead of a normal solve: the same as the polynomial method's."""
    scene = Scene(load, radius=0.3, surface=surface)
    fast = normal_pressure(load, scene.radius, scene.material, surface, scene.axis_position)
    solved = solve(scene, method="polynomial").info.get("pressure_coefficients")
    if load == 0.0:
        assert fast is None and solved is None, (fast, solved)
    else:
        np.testing.assert_allclose(fast, solved, rtol=1e-12, atol=1e-12 * float(np.abs(solved).max()),
                                   err_msg="Hertz's p0 sin(theta) against the polynomial normal solve")


# ----------------------------------------------------------------------------------------------------------------
# a budget of modelled seconds
SPLIT_CORRUGATION = Scene(1e6, creep=2e-4, axis_position=7e-4,
                          surface=Surface(harmonics=(Harmonic.from_wavelength(0.004, 40e-6),)))


def test_the_chosen_setting_and_its_modelled_cost_are_known_before_solving_and_fit_the_budget():
    for budget in (5e-3, 5e-2, 5e-1):
        setting = choose_setting(SPLIT_CORRUGATION, 1e-4, names=["discretised"], budget=budget)
        assert setting.cost <= budget, f"budget {budget}: modelled cost {setting.cost}"
        result = solve(SPLIT_CORRUGATION, methods=["discretised"], tolerance=1e-4, budget=budget)
        assert result.info["predicted_cost"] <= budget, f"budget {budget}: {result.info['predicted_cost']}"
        assert result.info["setting"] == setting.options, "solve runs the setting choose_setting names"
    unlimited = choose_setting(SPLIT_CORRUGATION, 1e-4, names=["discretised"])
    assert unlimited.cost > 5e-1, "the test's tolerance asks for more than the largest budget"


def test_within_the_budget_the_most_accurate_setting_runs_and_the_message_says_the_tolerance_is_missed():
    result = solve(SPLIT_CORRUGATION, methods=["discretised"], tolerance=1e-4, budget=2e-2)
    fitting = [o for o in METHODS["discretised"].accuracy.ladder(SPLIT_CORRUGATION)
               if METHODS["discretised"].accuracy.cost(SPLIT_CORRUGATION, o) <= 2e-2]
    best = min(METHODS["discretised"].accuracy.error(SPLIT_CORRUGATION, o) for o in fitting)
    assert result.info["error_estimate"] >= best * (1 - 1e-12) and not result.info["tolerance_met"], result.info
    assert "not reached" in result.message, result.message


def test_a_budget_no_setting_fits_solves_nothing_and_says_why(monkeypatch):
    calls = []
    spec = METHODS["polynomial"]
    monkeypatch.setitem(METHODS, "polynomial", MethodSpec(
        "polynomial", lambda scene, **o: calls.append(o) or spec.function(scene, **o), spec.inapplicable, spec.rank,
        spec.fallback, spec.accuracy))
    for tolerance in (None, 1e-3):
        result = solve(CORRUGATED, tolerance=tolerance, budget=1e-7)
        assert not result.success and "budget" in result.message and math.isnan(result.tangential_force_per_length), \
            f"tolerance {tolerance}: {result.message}"
    assert not calls, "nothing is solved when nothing fits"


def test_escalation_stops_where_the_next_setting_would_exceed_the_budget():
    scene = Scene(1e6, creep=1e-3, rolling_speed=20.0, friction=ExponentialFalling(0.3, 0.4, 30.0))
    free = solve(scene, tolerance=1e-9)
    assert free.info["setting"]["nodes"] >= 64, f"the tolerance escalates far without a budget: {free.info}"
    budget = 1.5 * METHODS["polynomial"].accuracy.cost(scene, {"nodes": free.info["setting"]["nodes"] // 4})
    result = solve(scene, tolerance=1e-9, budget=budget)
    assert result.info["predicted_cost"] <= budget and "budget" in result.message, (result.info, result.message)


def test_without_a_tolerance_a_default_beyond_the_budget_becomes_the_most_accurate_setting_within_it():
    model = METHODS["discretised"].accuracy
    default = model.cost(HERTZIAN, {})
    result = solve(HERTZIAN, method="discretised", budget=0.8 * default)
    assert result.success and result.info["predicted_cost"] <= 0.8 * default, result.info
    assert "budget" in result.message and result.info["grid"].elements < 200, result.message
