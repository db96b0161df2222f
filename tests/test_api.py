"""The dispatcher: method registry, automatic choice, one result type, errors that list the valid choices."""

from __future__ import annotations

import math

import numpy as np
import pytest

import rollcontact
from rollcontact import METHODS, ContactResult, ExponentialFalling, Harmonic, Scene, Surface, choose_method, solve

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
    assert METHODS["closed_form"].cost < METHODS["polynomial"].cost, "closed_form must be the cheaper method"


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


def test_auto_reports_a_split_contact_instead_of_a_wrong_answer():
    split = Scene(1e6, creep=2e-4, surface=Surface(harmonics=(Harmonic.from_wavelength(0.010, 20e-6),)),
                  axis_position=0.0045)
    result = solve(split)
    assert isinstance(result, ContactResult), f"got {type(result).__name__}"
    if result.method == "polynomial":
        assert not result.success, f"a split contact must not be reported as solved: {result.message}"
        assert "split" in result.message.lower(), f"the message must say why: {result.message!r}"
    else:  # a registered fallback (e.g. discretised) took over and says so
        assert "fallback" in result.message and result.info.get("fallback_from") == "polynomial", result.message
