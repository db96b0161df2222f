"""ContactModel / ModelState: the stepping logic behind the RollingContact2D FMU, tested without any FMI tool."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy import integrate

import rollcontact
from rollcontact.core.method import MethodSpec
from rollcontact.line.carter import carter
from rollcontact.line.hertz import hertz
from rollcontact.line.instationary import InstationaryModel, aligned_grid_load, lag_error_bound
from rollcontact.line.result import ContactResult
from rollcontact.stepping import ContactModel, ContactParameters, ModelError, ModelState, StepOutputs
from rollcontact.stepping.line.parameters import STATIONARY
from rollcontact.stepping.line.state import STATE_VERSION
from rollcontact.stepping.line.transient import (
    EXTRAPOLATED_MAX_ELEMENTS,
    EXTRAPOLATION_COST,
    GRID_LOAD_FACTOR,
    RELAXATION_ACCURACY,
    TRANSIENT_MAX_ELEMENTS,
    TRANSIENT_MIN_ELEMENTS,
    transient_elements,
    transient_error,
    transient_model_error,
    transient_setting,
)

H = 1e-3  # communication step [s]


def closed_form_reference(parameters: ContactParameters, normal_load, creep):
    """The library's own answer (rollcontact.solve) for the model's flat, Coulomb scene."""
    scene = rollcontact.Scene(normal_load_per_length=normal_load / parameters.contact_width, creep=creep,
                              radius=parameters.radius,
                              material=rollcontact.Material(parameters.youngs_modulus, parameters.poisson_ratio),
                              friction=rollcontact.Coulomb(parameters.friction_coefficient))
    return rollcontact.solve(scene, method="closed_form")


def run(model: ContactModel, inputs, start=0.0, h=H):
    """Step through rows (normal_load, creep, velocity) at t = start + n h; the outputs as a list."""
    return [model.step(start + n * h, h, *row) for n, row in enumerate(inputs)]


# ----------------------------------------------------------------------------------------------------------------
# parameters
@pytest.mark.parametrize("field, value", [
    ("youngs_modulus", 0.0), ("poisson_ratio", 0.5), ("radius", -0.1), ("contact_width", 0.0),
    ("friction_coefficient", 0.0), ("friction_law", -1), ("friction_kinetic_ratio", 1.5), ("friction_decay", -1.0),
    ("corrugation_wavelength", 0.0), ("corrugation_amplitude", -1e-6), ("corrugation_phase", math.nan),
    ("initial_position", math.inf), ("method", 4), ("tolerance", -1e-9), ("polynomial_order", -1),
    ("elements", 2.5), ("transient", 3), ("datum", -1.0), ("scene_file", 3), ("friction_law", 5),
    ("friction_reference_velocity", 0.0), ("friction_slope", -0.1),
])
def test_parameters_out_of_range_are_refused_by_name(field, value):
    with pytest.raises(ModelError, match=field):
        ContactParameters(**{field: value})


@pytest.mark.parametrize("invalid, expected", [
    ({"youngs_modulus": 0.0, "radius": -0.1},
     ("youngs_modulus = 0.0 is out of range: it must be > 0.0", "radius = -0.1 is out of range: it must be > 0.0")),
    ({"poisson_ratio": 0.5, "friction_law": 9, "elements": -3},
     ("poisson_ratio = 0.5 is out of range: it must be < 0.5", "friction_law = 9 is out of range: it must be one of",
      "elements = -3 is out of range: it must be an integer >= 0")),
])
def test_every_invalid_parameter_is_named_in_one_refusal(invalid, expected):
    with pytest.raises(ModelError) as caught:
        ContactParameters(**invalid)
    message = str(caught.value)
    for part in expected:
        assert part in message, f"the refusal {message!r} must name {part!r}"
    assert message.count("; ") == len(invalid) - 1, f"{len(invalid)} problems, one per parameter: {message!r}"
    for name, value in invalid.items():  # each alone: the same sentence as in the joint refusal
        with pytest.raises(ModelError) as alone:
            ContactParameters(**{name: value})
        assert str(alone.value) in message, f"{name} alone says {alone.value!s}, not part of {message!r}"


@pytest.mark.parametrize(("table", "says"), [
    ("", "is not a friction table"), ("0 0.3; 1", "is not a friction table"), ("0 0.3; x 0.2", "could not convert"),
    ("0 0.3; 0 0.2", "must increase strictly"), ("0 0.3; 1 0", "coefficient = 0.0 is out of range"),
    ("0 nan", "is not finite"),
])
def test_a_friction_table_that_is_no_table_is_refused_with_its_form(table, says):
    with pytest.raises(ModelError, match="friction_table") as caught:
        ContactParameters(friction_law=4, friction_table=table)
    assert says in str(caught.value) and "e.g. '0 0.3; 1 0.25; 5 0.12'" in str(caught.value), caught.value
    ContactParameters(friction_law=1, friction_table=table)  # read only with the tabulated law


def test_unreadable_scene_file_is_a_model_error(tmp_path):
    with pytest.raises(ModelError, match="scene_file"):
        ContactModel(ContactParameters(scene_file=str(tmp_path / "missing.toml")))


def test_closed_form_method_refuses_a_corrugated_surface():
    with pytest.raises(ModelError, match="closed form"):
        ContactModel(ContactParameters(method=1, corrugation_amplitude=20e-6))


def test_unregistered_method_is_named_with_the_registered_ones(monkeypatch):
    monkeypatch.delitem(rollcontact.METHODS, "discretised", raising=False)
    with pytest.raises(ModelError, match=r"method = 3: it needs method 3 \(discretised\), but no such method is "
                                         r"registered in rollcontact.METHODS \(registered: \["):
        ContactModel(ContactParameters(method=3))


# ----------------------------------------------------------------------------------------------------------------
# closed form
@pytest.mark.parametrize("creep", [0.0, 2e-4, -2e-4, 1e-3, -1e-3, 0.05, -0.05])
def test_closed_form_step_equals_the_library_solve(creep):
    p = ContactParameters(radius=0.5, contact_width=0.015, friction_coefficient=0.25)
    model = ContactModel(p)
    out = model.step(0.0, H, 8e4, creep, 15.0)
    ref = closed_form_reference(p, 8e4, creep)
    b = p.contact_width
    expected = [ref.tangential_force_per_length * b, ref.traction_coefficient, ref.contact_half_width,
                ref.stick_half_width, ref.contact_offset, ref.max_pressure,
                15.0 * creep * ref.tangential_force_per_length * b, ref.creep_stiffness_per_length * b]
    assert_allclose(out[:8], expected, rtol=1e-13, atol=0.0, err_msg=f"closed form at creep {creep}")
    assert out.method_used == 1, "a flat Coulomb scene uses the closed form"


def test_closed_form_step_is_hertz_and_carter_bit_for_bit():
    """closed_form_step writes out rollcontact.line.hertz.hertz and carter: every output is theirs bit for bit, over
    loads per length across twelve decades, radii, friction coefficients, creeps of either sign, zero, stick, the
    onset of full slip and beyond."""
    rng = np.random.default_rng(5)
    checked = 0
    for radius, mu, width in ((0.46, 0.3, 0.02), (0.05, 0.12, 0.004), (1.7, 0.6, 0.1)):
        model = ContactModel(ContactParameters(radius=radius, friction_coefficient=mu, contact_width=width))
        for load in (10.0 ** rng.uniform(-3.0, 9.0, 40)).tolist():
            n = load * model.per_width  # N' as the step forms it
            a, p0 = hertz(n, radius, model.contact_modulus)
            onset = mu * a / radius
            for creep in (0.0, onset, -onset, *(onset * rng.uniform(-3.0, 3.0, 6)).tolist(), 1e-300, -5.0):
                t, a_star, stiffness = carter(n, creep, radius, model.contact_modulus, mu)
                out = model.closed_form_step(0.0, load, creep, 20.0)
                force = t * width
                expected = (force, t / n, a, a_star, 0.0, p0, 20.0 * creep * force, stiffness * width)
                assert repr(tuple(out[:8])) == repr(expected), f"R {radius}, mu {mu}, N {load!r}, creep {creep!r}"
                checked += 1
    assert checked == 3 * 40 * 11


def test_no_load_is_no_contact():
    out = ContactModel().step(0.0, H, 0.0, 1e-3, 20.0)
    assert out[:8] == (0.0,) * 8, f"zero load must give zero outputs, got {out}"
    assert out.method_used == 0 and out.stationarity == STATIONARY, "no contact: method 0, stationary"


def frictional_power_by_quadrature(result: ContactResult, velocity: float) -> float:
    """V int q(x) s(x) dx over the patch [W/m], with the stick/slip boundary as a breakpoint."""
    a, d = result.contact_half_width, result.contact_offset
    boundary = d - a + 2.0 * result.stick_half_width
    def integrand(x):
        return float(result.traction(x) * result.slip(x))
    pieces = [(d - a, boundary), (boundary, d + a)] if result.stick_half_width > 0 else [(d - a, d + a)]
    return velocity * sum(integrate.quad(integrand, lo, hi, epsabs=0.0, epsrel=1e-10, limit=200)[0]
                          for lo, hi in pieces if hi > lo)


@pytest.mark.parametrize("creep", [1e-4, -3e-4, 6e-4, 2e-3, -5e-3])
def test_frictional_power_is_v_xi_t_as_the_integral_of_q_v_s(creep):
    p = ContactParameters()
    velocity = 20.0
    out = ContactModel(p).step(0.0, H, 1e5, creep, velocity)
    ref = closed_form_reference(p, 1e5, creep)
    quadrature = frictional_power_by_quadrature(ref, velocity) * p.contact_width
    assert_allclose(out.frictional_power, quadrature, rtol=1e-7,
                    err_msg=f"V xi T against the quadrature of q V s at creep {creep}")
    assert out.frictional_power >= 0.0, "slip dissipates power"


def test_creep_stiffness_is_the_derivative_of_the_force():
    model = ContactModel()
    for creep in (0.0, 2e-4, -4e-4):
        d = 1e-9
        up = ContactModel().step(0.0, H, 1e5, creep + d, 20.0).tangential_force
        down = ContactModel().step(0.0, H, 1e5, creep - d, 20.0).tangential_force
        stiffness = model.step(0.0, H, 1e5, creep, 20.0).creep_stiffness
        model.reset()
        assert_allclose(stiffness, (up - down) / (2 * d), rtol=1e-5, err_msg=f"dT/dxi at creep {creep}")


def test_tilted_scene_file_moves_the_contact_uphill(tmp_path):
    slope = 2e-3  # Z = slope X rises in the rolling direction
    path = tmp_path / "tilted.toml"
    path.write_text(f"[surface]\npolynomial = [0.0, {slope}]\n[geometry]\nradius = 0.4\n"
                    "[load]\nnormal_load_per_length = 1.0  # replaced by the input\n")
    model = ContactModel(ContactParameters(scene_file=str(path)))
    out = model.step(0.0, H, 1e5, 1e-3, 20.0)
    assert out.method_used == 1, "a tilted plane keeps the closed form"
    assert_allclose(out.contact_offset, 0.4 * slope, rtol=1e-14, err_msg="contact moves uphill by R alpha")
    assert any("scene_file" in n for n in model.notices), "ignored scalar parameters must be reported"


# ----------------------------------------------------------------------------------------------------------------
# axis position and stationarity
def test_axis_position_is_the_trapezoid_of_the_velocity_without_drift():
    p = ContactParameters(initial_position=-0.3)
    model = ContactModel(p, start_time=2.0)
    h, n = 1e-4, 50_000
    rate = 3.0  # V = 5 + rate (t - 2): the trapezoid is exact for a linear V
    for k in range(n):
        t = 2.0 + k * h
        out = model.step(t, h, 1e5, 1e-3, 5.0 + rate * (t - 2.0))
    t_last = (n - 1) * h
    exact = -0.3 + 5.0 * t_last + 0.5 * rate * t_last**2
    assert abs(out.axis_position - exact) <= 4 * np.finfo(float).eps * abs(exact), \
        f"X drifted: {out.axis_position!r} vs {exact!r}"


def test_step_after_an_error_continues_from_the_unchanged_state():
    model = ContactModel()
    run(model, [(1e5, 1e-3, 20.0)] * 2)
    before = model.get_state()
    for args in [(0.002, H, -1.0, 0.0, 1.0), (0.002, H, 1e5, math.nan, 1.0), (0.002, H, 1e5, 0.0, -1.0),
                 (0.002, 0.0, 1e5, 0.0, 1.0), (0.002, H, math.inf, 0.0, 1.0), (0.0005, H, 1e5, 0.0, 1.0)]:
        with pytest.raises(ModelError):
            model.step(*args)
        assert model.state == before, f"a refused step {args} must not change the state"


@pytest.mark.parametrize("args, words", [
    ((0.0, H, -1.0, 0.0, 1.0), "normal_load = -1.0 N is out of range"),
    ((0.0, H, 1e5, math.nan, 1.0), "creep = nan is not finite"),
    ((0.0, H, 1e5, 0.0, -2.0), "velocity = -2.0 m/s is out of range"),
    ((0.0, -H, 1e5, 0.0, 1.0), "step_size = -0.001 s is out of range"),
])
def test_error_messages_say_what_which_value_and_which_limit(args, words):
    with pytest.raises(ModelError, match=words):
        ContactModel().step(*args)


def test_stationarity_of_constant_inputs_and_of_a_wheel_at_rest():
    model = ContactModel()
    outs = run(model, [(1e5, 1e-3, 20.0)] * 4)
    assert all(o.stationarity == STATIONARY for o in outs), "constant inputs are stationary"
    at_rest = ContactModel()
    outs = run(at_rest, [(1e5, 1e-3, 0.0), (1e5, 2e-3, 0.0)])
    assert outs[1].stationarity == 0.0, "an input changing while the wheel does not roll is not stationary"


@pytest.mark.parametrize("wavelength", [0.01, 0.05])
def test_stationarity_recovers_the_wavelength_of_a_creep_oscillation(wavelength):
    p = ContactParameters()
    model = ContactModel(p)
    a = model.step(0.0, H, 1e5, 0.0, 0.0).contact_half_width
    model.reset()
    scale = p.friction_coefficient * a / p.radius  # the creep scale of the measure
    velocity, h = 1.0, 2e-5
    inputs = [(1e5, scale * math.sin(2 * math.pi * velocity * k * h / wavelength), velocity) for k in range(1200)]
    values = np.array([o.stationarity for o in run(model, inputs, h=h)[2:]])
    expected = wavelength / a
    assert values.min() >= 0.97 * expected, f"stationarity {values.min():.4g} below lambda/a = {expected:.4g}"
    assert values.max() <= expected / 0.78 * 1.03, f"stationarity {values.max():.4g} above (lambda/a)/0.78"


# ----------------------------------------------------------------------------------------------------------------
# state
def test_restore_step_restore_step_gives_identical_outputs():
    model = ContactModel(ContactParameters(initial_position=0.1))
    run(model, [(1e5, 1e-3, 20.0), (1.2e5, 2e-3, 21.0), (1.1e5, -1e-3, 22.0)])
    saved = model.get_state()
    later = [(9e4, 5e-4, 20.0), (1e5, 1e-3, 19.0)]
    first = run(model, later, start=3 * H)
    model.set_state(saved)
    second = run(model, later, start=3 * H)
    assert first == second, "restore -> step must repeat the outputs exactly"
    model.set_state(ModelState.from_bytes(saved.to_bytes()))
    assert run(model, later, start=3 * H) == first, "a state through bytes must repeat the outputs exactly"


def test_state_serialisation_round_trips_exactly():
    model = ContactModel()
    run(model, [(1e5, 1e-3, 20.0), (1e5 / 3, 1e-3 / 7, 20.0 / 3)])
    state = model.get_state()
    assert ModelState.from_bytes(state.to_bytes()) == state, "bytes round trip"
    assert ModelState.from_dict(state.to_dict()) == state, "dict round trip"
    assert isinstance(ModelState.from_dict(state.to_dict()).outputs, StepOutputs), "outputs keep their type"
    copy = state.copy()
    model.step(2 * H, H, 1e5, 1e-3, 20.0)
    assert copy == state and model.state != state, "get_state() is a copy the model does not change"


def test_foreign_state_versions_are_refused():
    data = ContactModel().get_state().to_dict()
    with pytest.raises(ModelError, match="version"):
        ModelState.from_dict(dict(data, version=99))
    with pytest.raises(ModelError, match="invalid model state"):
        ModelState.from_dict({k: v for k, v in data.items() if k != "outputs"})


# ----------------------------------------------------------------------------------------------------------------
# scenes of the non-closed-form methods
def test_scene_is_the_mirror_image_in_the_package_frame():
    p = ContactParameters(corrugation_amplitude=20e-6, corrugation_wavelength=0.04, corrugation_phase=0.7)
    model = ContactModel(p)
    x_axis = 0.013
    scene = model.scene(x_axis, 2e4, 1e-3, 20.0)
    X = np.linspace(-0.05, 0.05, 101)
    z_model = p.corrugation_amplitude * np.cos(2 * np.pi * X / p.corrugation_wavelength + p.corrugation_phase)
    assert_allclose(scene.surface.height(-X), z_model, rtol=0, atol=1e-18, err_msg="Z_scene(-X) = Z(X)")
    assert scene.axis_position == -x_axis, "the axis stands at -X in the package frame"
    assert_allclose(scene.normal_load_per_length, 2e4 / p.contact_width, rtol=1e-15, err_msg="N' = N / b")


def test_corrugated_steps_equal_the_polynomial_solve():
    p = ContactParameters(corrugation_amplitude=20e-6, corrugation_wavelength=0.04, corrugation_phase=0.3)
    model = ContactModel(p)
    for k in range(3):
        out = model.step(k * H, H, 2e4, 1e-3, 5.0)
        ref = rollcontact.solve(model.scene(out.axis_position, 2e4, 1e-3, 5.0), method="polynomial")
        assert ref.success, ref.message
        b = p.contact_width
        assert_allclose(out[:8], [ref.tangential_force_per_length * b, ref.traction_coefficient,
                                  ref.contact_half_width, ref.stick_half_width, -ref.contact_offset,
                                  ref.max_pressure, 5.0 * 1e-3 * ref.tangential_force_per_length * b,
                                  ref.creep_stiffness_per_length * b],
                        rtol=1e-12, atol=1e-15, err_msg=f"polynomial outputs at X = {out.axis_position}")
        assert out.method_used == 2, "a corrugated surface uses the polynomial method"
    assert p.polynomial_order == 0 and model.options == {}, "0 means the method's default"
    assert ContactModel(dataclasses.replace(p, polynomial_order=12)).options == {"order": 12}, \
        "polynomial_order is passed as the polynomial method's 'order'"


def fake_result(name: str, success: bool) -> ContactResult:
    return ContactResult(method=name, success=success, message=f"{name} says {'ok' if success else 'no'}",
                         normal_load_per_length=1e6, tangential_force_per_length=2e5, creep=1e-3,
                         contact_half_width=2e-3, contact_offset=1e-4, stick_half_width=1e-3, max_pressure=3e8,
                         creep_stiffness_per_length=1e9)


def test_auto_falls_back_to_the_discretised_family_and_reports_it(monkeypatch):
    calls = []

    def polynomial(scene, **options):
        calls.append("polynomial")
        return fake_result("polynomial", False)

    def discretised(scene, elements=None):
        calls.append(("discretised", elements))
        return fake_result("discretised", True)

    discretised.options = ("elements",)
    monkeypatch.setitem(rollcontact.METHODS, "polynomial", MethodSpec("polynomial", polynomial, lambda s: None, 10))
    monkeypatch.setitem(rollcontact.METHODS, "discretised",
                        MethodSpec("discretised", discretised, lambda s: None, 100, True))
    model = ContactModel(ContactParameters(corrugation_amplitude=1e-5, elements=64))
    out = model.step(0.0, H, 2e4, 1e-3, 10.0)
    assert calls == ["polynomial", ("discretised", 64)], f"auto must try polynomial, then discretised: {calls}"
    assert out.method_used == 3, "method_used reports the fallback"
    assert_allclose([out.tangential_force, out.contact_offset], [2e5 * 0.02, -1e-4], rtol=1e-15,
                    err_msg="force over the width; offset back in the model's frame")

    strict = ContactModel(ContactParameters(corrugation_amplitude=1e-5, method=2))
    with pytest.raises(ModelError, match="polynomial failed: polynomial says no"):
        strict.step(0.0, H, 2e4, 1e-3, 10.0)
    assert strict.state.steps == 0, "a failed solve must not advance the state"


def test_explicit_discretised_method_with_its_creep_stiffness(monkeypatch):
    """The discretised method returns dT'/dxi (its stick block's K_SS^-1 1): no second solve for a difference."""
    p = ContactParameters(corrugation_amplitude=20e-6, method=3, elements=120)
    model = ContactModel(p)

    def refuse(*args, **kwargs):
        raise AssertionError("the discretised step must not need a difference quotient")
    monkeypatch.setattr(ContactModel, "creep_stiffness_by_difference", refuse)
    out = model.step(0.0, H, 2e4, 5e-4, 5.0)
    scene = model.scene(out.axis_position, 2e4, 5e-4, 5.0)
    ref = rollcontact.solve(scene, method="discretised", elements=120)
    assert out.method_used == 3, "method = 3 uses the discretised method"
    assert_allclose(out.tangential_force, ref.tangential_force_per_length * p.contact_width, rtol=1e-12,
                    err_msg="discretised force over the width")
    d = 2e-6
    up, down = (rollcontact.solve(scene.replace(creep=5e-4 + s), method="discretised", elements=120)
                for s in (d, -d))
    central = (up.tangential_force_per_length - down.tangential_force_per_length) / (2 * d) * p.contact_width
    assert_allclose(out.creep_stiffness, central, rtol=1e-6, err_msg="stiffness against a central difference")


def test_falling_friction_needs_more_than_the_closed_form():
    falling = ContactParameters(friction_law=1, friction_kinetic_ratio=0.4, friction_decay=0.6)
    out = ContactModel(falling).step(0.0, H, 1e5, 1e-3, 5.0)
    assert out.method_used in (2, 3), f"falling friction must not use the closed form, used {out.method_used}"
    coulomb = ContactModel(dataclasses.replace(falling, friction_kinetic_ratio=1.0)).step(0.0, H, 1e5, 1e-3, 5.0)
    assert coulomb.method_used == 1, "A = 1 is constant friction: closed form"
    assert out.tangential_force < coulomb.tangential_force, "falling friction lowers the force at the same creep"


@pytest.mark.parametrize(("code", "law"), [
    (2, rollcontact.RationalFalling(0.3, 0.3 * 0.4, 1.5)),
    (3, rollcontact.LinearFalling(0.3, 0.3 * 0.4, 0.05)),
    (4, rollcontact.TabulatedFriction((0.0, 0.5, 4.0), (0.3, 0.22, 0.15))),
])
def test_every_falling_law_of_the_library_is_a_friction_law_parameter(code, law):
    """friction_law 2 (rational), 3 (linear) and 4 (tabulated): the library's law with mu = friction_coefficient,
    mu_k = A mu and v_ref or c, or the points of friction_table; a step equals rollcontact.solve on the same scene
    built with that law directly."""
    p = ContactParameters(friction_law=code, friction_coefficient=0.3, friction_kinetic_ratio=0.4,
                          friction_reference_velocity=1.5, friction_slope=0.05,
                          friction_table=" 0 0.3;0.5 0.22 ; 4 0.15; ")
    model = ContactModel(p)
    assert model.scene(0.0, 1e5, 1e-3, 20.0).friction == law, f"law {code}: {model.scene(0.0, 1e5, 1e-3, 20.0)}"
    out = model.step(0.0, H, 1e5, 1e-3, 20.0)
    scene = rollcontact.Scene(normal_load_per_length=1e5 / p.contact_width, creep=1e-3, radius=p.radius,
                              material=rollcontact.Material(p.youngs_modulus, p.poisson_ratio), friction=law,
                              rolling_speed=20.0)
    expected = rollcontact.solve(scene, method="polynomial")
    assert out.method_used == 2 and out.tangential_force == expected.tangential_force_per_length * p.contact_width, \
        f"law {code}: {out.tangential_force} against the library's {expected.tangential_force_per_length * 0.02}"
    coulomb = ContactModel(ContactParameters(friction_coefficient=0.3)).step(0.0, H, 1e5, 1e-3, 20.0)
    assert 0.0 < out.tangential_force < coulomb.tangential_force, "a falling law lowers the force at the same creep"


def test_a_method_without_stiffness_gets_it_by_difference(monkeypatch):
    """Where a solution carries no dT'/dxi (here: a singular slip Jacobian at the solution, e.g. a law with a kink),
    the result reports NaN and the model's one-sided difference supplies it."""
    from rollcontact.line.methods.polynomial import slip

    def singular(*args, **kwargs):
        raise np.linalg.LinAlgError("singular")
    falling = ContactParameters(friction_law=1, friction_kinetic_ratio=0.4, friction_decay=3.0, method=2)
    exact = ContactModel(falling).step(0.0, H, 1e5, 1e-3, 20.0).creep_stiffness
    monkeypatch.setattr(slip.SlipEquations, "force_slope", singular)
    scene = ContactModel(falling).scene(0.0, 1e5, 1e-3, 20.0)
    assert math.isnan(rollcontact.solve(scene, method="polynomial").creep_stiffness_per_length), \
        "no derivative: NaN, not an exception"
    out = ContactModel(falling).step(0.0, H, 1e5, 1e-3, 20.0)
    assert_allclose(out.creep_stiffness, exact, rtol=1e-4, err_msg="one-sided difference against the exact slope")


@pytest.mark.parametrize("creep", [0.0, 1e-3, -3e-3])
def test_falling_friction_step_solves_once(monkeypatch, creep):
    """The polynomial method returns dT'/dxi with velocity-dependent friction (implicit function theorem), and the
    step reads no error estimate without a tolerance: one slip iteration, no difference quotient, no estimate."""
    falling = ContactParameters(friction_law=1, friction_kinetic_ratio=0.4, friction_decay=3.0, method=2)
    model = ContactModel(falling)
    from rollcontact.line.methods.polynomial import slip

    def refuse(*args, **kwargs):
        raise AssertionError("the step must not need this")
    monkeypatch.setattr(ContactModel, "creep_stiffness_by_difference", refuse)
    monkeypatch.setattr(slip, "force_error_estimate", refuse)
    out = model.step(0.0, H, 1e5, creep, 20.0)
    d = 1e-9  # central difference: truncation ~ d / xi_sat (xi_sat ~ 5e-3: the second derivative jumps at 0)
    up, down = (ContactModel(falling).step(0.0, H, 1e5, creep + s, 20.0).tangential_force for s in (d, -d))
    assert_allclose(out.creep_stiffness, (up - down) / (2 * d), rtol=1e-5, err_msg="stiffness against a difference")


# ----------------------------------------------------------------------------------------------------------------
# instationary rolling (transient = 1 auto, 2 always)
def creep_oscillation(model: ContactModel, wavelength: float, amplitude: float, steps: int, *, load=1e5,
                      velocity=10.0, h=2e-5, mean=0.0):
    """Inputs rows of a creep oscillation ``mean + amplitude * saturation creep * sin(2 pi X / wavelength)``."""
    a = hertz(load / model.parameters.contact_width, model.radius, model.contact_modulus)[0]
    saturation = model.mu * a / model.radius
    return [(load, saturation * (mean + amplitude * math.sin(2 * math.pi * velocity * k * h / wavelength)), velocity)
            for k in range(steps)], a


def test_transient_always_is_the_relaxation_model_rolled_over_each_step():
    p = ContactParameters(transient=2)
    model = ContactModel(p)
    inputs, a = creep_oscillation(model, 0.02, 0.8, 200)
    outs = run(model, inputs, h=2e-5)
    reference = InstationaryModel(p.radius, model.contact_modulus, p.friction_coefficient, mode="relaxation")
    state = reference.initial_state()
    for k, (load, creep, velocity) in enumerate(inputs):
        state, res = reference.step(state, load / p.contact_width, creep, velocity, 2e-5)
        assert outs[k].tangential_force == pytest.approx(res.tangential_force_per_length * p.contact_width,
                                                         rel=1e-14, abs=1e-9), f"step {k}: the lag's force"
        assert outs[k].method_used == 4, f"step {k}: method_used 4 (relaxation)"
    assert len(model.notices) == 1 and "creep swing" in model.notices[0], \
        f"the defaults: only the notice of what the lag is accurate to: {model.notices}"


def test_transient_auto_is_quasi_steady_for_constant_and_slow_inputs():
    auto, quasi = ContactModel(ContactParameters(transient=1)), ContactModel()
    constant = [(1e5, 1e-3, 20.0)] * 5
    assert run(auto, constant) == run(quasi, constant), "constant inputs: auto = quasi-static, bit for bit"
    auto.reset(), quasi.reset()
    slow, _ = creep_oscillation(auto, 50.0, 0.5, 300, h=1e-3)  # lambda/a ~ 7000 > threshold ~ 5500
    outs = run(auto, slow)
    assert outs == run(quasi, slow), "slowly varying creep: auto stays quasi-static"
    threshold = auto.transient_threshold(outs[-1].contact_half_width, 1e5 / auto.width)
    assert min(o.stationarity for o in outs[2:]) > threshold, "the slow case lies above the threshold"


@pytest.mark.parametrize("wavelength_over_a", [5.0, 50.0])
def test_transient_auto_follows_the_lag_where_quasi_static_errs(wavelength_over_a):
    """A fast creep oscillation: auto switches the lag in and matches transient = 2, quasi-static does not."""
    auto, always, quasi = (ContactModel(ContactParameters(transient=t)) for t in (1, 2, 0))
    _, a = creep_oscillation(auto, 1.0, 0.0, 1)
    inputs, _ = creep_oscillation(auto, wavelength_over_a * a, 0.6, 1500, mean=0.2, h=a / 10.0 / 10.0)
    outs = {name: run(m, inputs, h=a / 100.0) for name, m in (("auto", auto), ("always", always),
                                                               ("quasi", quasi))}
    limit = auto.mu * 1e5
    tail = slice(1000, None)  # after several relaxation lengths and wavelengths
    force = {k: np.array([o.tangential_force for o in v])[tail] for k, v in outs.items()}
    assert np.all(np.array([o.method_used for o in outs["auto"]])[tail] == 4), "auto uses the lag (code 4)"
    assert_allclose(force["auto"], force["always"], atol=1e-3 * limit,
                    err_msg="auto must follow the lag once it is switched in")
    assert np.max(np.abs(force["quasi"] - force["always"])) > 0.05 * limit, \
        "the case must be one where quasi-static errs (else the test shows nothing)"


@pytest.mark.parametrize("parameters", [dict(tolerance=RELAXATION_ACCURACY), dict(tolerance=1e-3, elements=40)])
def test_transient_auto_switches_back_without_a_jump_once_the_lag_has_decayed(parameters):
    """Relaxation lag (tolerance at its accuracy) and discretised transient (tighter, 40 elements to stay cheap)."""
    model = ContactModel(ContactParameters(transient=1, **parameters))
    code = 5 if model.instationary.mode == "transient" else 4
    _, a = creep_oscillation(model, 1.0, 0.0, 1)
    h = a / 100.0  # V = 10 m/s: a/10 rolled per step
    fast, _ = creep_oscillation(model, 10 * a, 0.5, 100 if code == 5 else 400, h=h, mean=0.3)
    settle = [fast[-1]] * 3000  # constant creep: 300 a rolled
    outs = run(model, fast + settle, h=h)
    codes = np.array([o.method_used for o in outs])
    force = np.array([o.tangential_force for o in outs])
    swinging = codes[2:len(fast)]
    first = int(np.argmax(swinging == code))
    assert np.all(swinging[first:] == code) and np.all(swinging[:first] == 4) and first <= 2, \
        f"the fast part switches the instationary model (code {code}) in, the lag at most while the swing is small"
    back = int(np.argmax(codes[len(fast):] == 1)) + len(fast)
    assert codes[-1] == 1 and back > len(fast), "constant inputs eventually return to the closed form"
    jump = abs(force[back] - force[back - 1])
    # the force was off the quasi-steady one by more than settle_tolerance one step earlier: allow one step's
    # relaxation, a/10 over l ~ 4 a
    limit = model.settle_tolerance * model.mu * 1e5
    assert jump <= 1.05 * limit, f"switching back jumps by {jump:.3g} N ({limit:.3g} N allowed)"
    assert model.state.instationary is None, "no instationary state is kept once quasi-steady"


def test_transient_discretised_mode_is_the_creep_controlled_transient():
    p = ContactParameters(transient=1, method=3, elements=60)  # method 3: auto behaves as always
    model = ContactModel(p)
    inputs, a = creep_oscillation(model, 0.02, 0.5, 30, mean=0.3)
    outs = run(model, inputs, h=2e-5)
    grid_load = aligned_grid_load(1e5 / p.contact_width, 60, GRID_LOAD_FACTOR)  # about twice the first load
    reference = InstationaryModel(p.radius, model.contact_modulus, p.friction_coefficient, mode="transient",
                                  max_normal_load_per_length=grid_load, elements=60)
    state = reference.initial_state()
    for k, (load, creep, velocity) in enumerate(inputs):
        state, res = reference.step(state, load / p.contact_width, creep, velocity, 2e-5)
        assert outs[k].tangential_force == pytest.approx(res.tangential_force_per_length * p.contact_width,
                                                         rel=1e-12, abs=1e-9), f"step {k}"
    assert {o.method_used for o in outs} == {5}, "method_used 5 (discretised transient)"
    assert model.state.grid_load == grid_load, "the grid load is part of the state"
    out = model.step(30 * 2e-5, 2e-5, 2.5e5, 1e-3, 10.0)
    assert out.method_used == 5 and model.state.grid_load == aligned_grid_load(2.5e5 / p.contact_width, 60, 2.0), \
        "a load the grid does not hold moves the history to a larger grid"


@pytest.mark.parametrize("parameters", [dict(transient=1), dict(transient=2), dict(transient=2, method=3, elements=50),
                                        dict(transient=1, tolerance=1e-3, elements=50)])
def test_instationary_history_survives_restore_and_serialisation(parameters):
    model = ContactModel(ContactParameters(**parameters))
    inputs, a = creep_oscillation(model, 0.01, 0.7, 40, mean=0.1)
    run(model, inputs[:20], h=2e-5)
    saved = model.get_state()
    assert saved.instationary is not None, "the state mid-oscillation carries the instationary history"
    first = run(model, inputs[20:], start=20 * 2e-5, h=2e-5)
    model.set_state(saved)
    assert run(model, inputs[20:], start=20 * 2e-5, h=2e-5) == first, "restore -> step repeats exactly"
    fresh = ContactModel(ContactParameters(**parameters))
    fresh.set_state(ModelState.from_bytes(saved.to_bytes()))
    assert run(fresh, inputs[20:], start=20 * 2e-5, h=2e-5) == first, \
        "a state through bytes into a fresh model repeats exactly (grid rebuilt from the state)"


def test_a_load_whose_contact_width_underflows_is_no_contact_in_every_transient_mode():
    """N = 5e-324 N: the Hertz half-width is 0.  Every mode answers it as no contact (T = 0, method_used 0, the
    envelope and the instationary state dropped) and continues normally afterwards."""
    rows = [(1e5, 1e-3, 10.0), (5e-324, 1e-3, 10.0), (1e5, 2e-3, 10.0)]
    for parameters in (dict(transient=1, tolerance=1e-2), dict(transient=1), dict(transient=2),
                       dict(transient=2, method=3, elements=40)):
        model = ContactModel(ContactParameters(**parameters))
        model.step(0.0, H, *rows[0])
        out = model.step(H, H, *rows[1])
        assert out.method_used == 0 and out.tangential_force == 0.0, f"{parameters}: {out}"
        assert model.state.creep_envelope is None and model.state.instationary is None, parameters
        out = model.step(2 * H, H, *rows[2])
        assert out.tangential_force > 0.0 and math.isfinite(out.tangential_force), f"{parameters}: {out}"


def test_lag_stiffness_is_the_derivative_of_the_step_force():
    model = ContactModel(ContactParameters(transient=2))
    inputs, a = creep_oscillation(model, 0.02, 0.5, 30, mean=0.3)
    run(model, inputs, h=2e-5)
    saved = model.get_state()
    t, (load, creep, velocity) = 30 * 2e-5, inputs[-1]
    out = model.step(t, 2e-5, load, creep, velocity)
    delta = 1e-6 * model.mu * a / model.radius
    forces = []
    for sign in (1, -1):
        model.set_state(saved)
        forces.append(model.step(t, 2e-5, load, creep + sign * delta, velocity).tangential_force)
    difference = (forces[0] - forces[1]) / (2 * delta)
    assert out.creep_stiffness == pytest.approx(difference, rel=2e-2), \
        "creep_stiffness must be dT/dxi of the step (the host's linearly implicit coupling uses it)"
    assert out.creep_stiffness < 0.5 * 2 * 1e5 * model.radius / a, "far below the steady Carter slope for a short step"


def test_wheel_at_rest_holds_the_lag_force():
    model = ContactModel(ContactParameters(transient=2))
    run(model, [(1e5, 1e-3, 10.0)] * 50, h=1e-4)
    held = model.state.outputs.tangential_force
    out = model.step(50e-4, 1e-4, 1e5, 5e-3, 0.0)
    assert out.tangential_force == held, "V = 0: nothing rolls, the force is held"


def test_instationary_models_refuse_scenes_they_do_not_treat():
    with pytest.raises(ModelError, match="transient = 2 .* flat surface"):
        ContactModel(ContactParameters(transient=2, corrugation_amplitude=5e-6))
    with pytest.raises(ModelError, match="transient = 2 .* Coulomb friction"):
        ContactModel(ContactParameters(transient=2, friction_law=1))
    model = ContactModel(ContactParameters(transient=1, corrugation_amplitude=5e-6))
    assert any("quasi-steady" in n for n in model.notices), "transient = 1 on a corrugated rail is reported"
    quasi = ContactModel(ContactParameters(corrugation_amplitude=5e-6))
    rows = [(1e5, 1e-3 * (1 + k), 10.0) for k in range(3)]
    assert run(model, rows) == run(quasi, rows), "... and solved quasi-steady"


def test_version_1_states_are_read_as_quasi_steady_history():
    model = ContactModel()
    run(model, [(1e5, 1e-3, 20.0)] * 2)
    data = model.get_state().to_dict()
    del data["instationary"], data["grid_load"]
    state = ModelState.from_dict(dict(data, version=1))
    assert state.instationary is None and state.version == STATE_VERSION, "version 1 reads as the current version"


@pytest.mark.parametrize("tolerance", [1e-2, 1e-3])
def test_tolerance_selects_a_setting_that_meets_it(tolerance):
    """The FMU's ``tolerance`` is the requested accuracy of T (as ``rollcontact.solve(scene, tolerance=...)``)."""
    rows = [(1e5, 2e-3, 20.0)]
    coarse = run(ContactModel(ContactParameters(friction_law=1, friction_decay=5.0, tolerance=tolerance)), rows)[0]
    fine = run(ContactModel(ContactParameters(friction_law=1, friction_decay=5.0, tolerance=1e-7)), rows)[0]
    error = abs(coarse.tangential_force - fine.tangential_force) / abs(fine.tangential_force)
    assert error <= tolerance, f"tolerance {tolerance}: T off by {error:.2e}"


# ----------------------------------------------------------------------------------------------------------------
# transient = 1 at tolerances below the relaxation lag's accuracy: the discretised transient
@pytest.mark.parametrize("parameters, mode, setting", [
    (dict(transient=1), "relaxation", None),
    (dict(transient=1, tolerance=RELAXATION_ACCURACY), "relaxation", None),
    (dict(transient=1, tolerance=1e-2), "transient", (TRANSIENT_MIN_ELEMENTS, True)),
    (dict(transient=1, tolerance=1e-3), "transient", (82, True)),
    (dict(transient=1, tolerance=1e-4), "transient", (258, True)),
    (dict(transient=1, tolerance=1e-5), "transient", (EXTRAPOLATED_MAX_ELEMENTS, True)),
    (dict(transient=1, tolerance=1e-3, elements=60), "transient", (60, False)),
    (dict(transient=1, tolerance=1e-3, method=1), "relaxation", None),
    (dict(transient=2, tolerance=1e-3), "relaxation", None),
    (dict(transient=2, tolerance=1e-3, method=3), "transient", (82, True)),
])
def test_tolerance_selects_the_instationary_model_and_its_elements(parameters, mode, setting):
    model = ContactModel(ContactParameters(**parameters))
    tolerance = parameters.get("tolerance", 0.0)
    assert model.instationary.mode == mode, f"{parameters}: {model.instationary.mode}"
    notices = " ".join(model.notices)
    if mode == "relaxation":
        assert ("relaxation lag" in notices) == (tolerance < RELAXATION_ACCURACY), notices
        return
    elements, extrapolate = setting
    assert (model.instationary.elements, model.instationary.extrapolate) == setting, \
        f"{parameters}: {model.instationary.elements} elements, extrapolate {model.instationary.extrapolate}"
    met = transient_model_error(elements, extrapolate) <= tolerance
    if "elements" not in parameters and met and elements > TRANSIENT_MIN_ELEMENTS:
        assert transient_model_error(elements - 2, extrapolate) > tolerance, "the fewest elements that meet it"
    grids = f"elements = {elements // 2}/{elements} extrapolated" if extrapolate else f"elements = {elements}"
    assert grids in notices and ("NOT met" in notices) == (not met), notices


def test_transient_setting_is_the_cheapest_that_meets_the_error_models():
    """Over the tolerances below the relaxation lag's accuracy: the setting meets its model where any can, and the
    other kind (plain or pair) that meets it costs more per step (n^2.5, the pair's times EXTRAPOLATION_COST)."""
    reachable = transient_model_error(EXTRAPOLATED_MAX_ELEMENTS, True)
    for tolerance in np.geomspace(1.01 * reachable, 0.99 * RELAXATION_ACCURACY, 9):
        elements, extrapolate = transient_setting(tolerance)
        assert transient_model_error(elements, extrapolate) <= tolerance, f"tolerance {tolerance}"
        plain = transient_elements(tolerance)
        if transient_error(plain) <= tolerance and extrapolate:
            assert EXTRAPOLATION_COST * elements**2.5 <= plain**2.5, f"tolerance {tolerance}: pair {elements}"
    assert transient_setting(1e-3) == (82, True), "1e-3: the pair 41/82, where a single grid needs 820"


def test_transient_elements_follow_the_error_model():
    for tolerance in np.geomspace(1.01 * transient_error(TRANSIENT_MAX_ELEMENTS), 0.99 * RELAXATION_ACCURACY, 7):
        n = transient_elements(tolerance)
        assert transient_error(n) <= tolerance, f"tolerance {tolerance}: n = {n} does not meet it"
        assert n == TRANSIENT_MIN_ELEMENTS or tolerance < transient_error(n - 1), \
            f"tolerance {tolerance}: n = {n} is not the fewest above the coarsest measured grid"
    assert transient_elements(1e-9) == TRANSIENT_MAX_ELEMENTS, "capped"
    assert transient_elements(0.5) == TRANSIENT_MIN_ELEMENTS, "no grid coarser than the error model was measured on"


def test_switching_the_transient_in_starts_from_steady_rolling_at_the_previous_inputs():
    """No jump: the switched-in state is held by a step with the previous inputs (its output ripples by the
    provisional substep's O(h^2)), and its force is within the discretisation error of the quasi-steady (Carter)
    force that the host saw before."""
    model = ContactModel(ContactParameters(transient=1, tolerance=1e-3, elements=80))
    load, creep, velocity, h = 1e5, 4e-4, 10.0, 1e-4
    quasi = run(model, [(load, creep, velocity)] * 3, h=h)[-1]
    assert quasi.method_used == 1, "constant inputs are quasi-steady"
    per_length = load / model.width
    model.prepare_grid(per_length, None)
    lag = model.switch_in(model.instationary, per_length)
    limit = model.mu * per_length
    offset = abs(lag.tangential_force_per_length - quasi.tangential_force / model.width) / limit
    assert offset <= transient_error(80), f"steady start {offset:.2e} mu N' off Carter"
    kept, held = model.instationary.step(lag, per_length, creep, velocity, h)
    change = abs(kept.tangential_force_per_length - lag.tangential_force_per_length) / limit
    assert change < 1e-12, f"holding the previous inputs moves the committed T' by {change:.1e} mu N'"
    change = abs(held.tangential_force_per_length - lag.tangential_force_per_length) / limit
    assert change < 1.0 / 80**2, f"holding the previous inputs changes T' by {change:.1e} mu N' (ripple O(h^2))"
    # through step(): a creep change switches the transient in, from the same steady state (a change of 0.24
    # saturation creeps: the lag's bound does not meet the tolerance)
    out = model.step(3 * h, h, load, 3 * creep, velocity)
    assert out.method_used == 5 and model.state.instationary is not None, "the creep change switches it in"
    reference = model.instationary.step(lag, per_length, 3 * creep, velocity, h)[1]
    assert out.tangential_force == pytest.approx(reference.tangential_force_per_length * model.width, rel=1e-14)


def test_tight_tolerance_meets_its_error_against_a_refined_transient():
    """One cheap case (lambda/a = 8, a quarter cycle of ``(0.2 + 0.5 sin) mu a/R``): auto at tolerance 3.9e-3 (the lag
    while the swing is small, then the extrapolating pair 25/50 from the lag's force) against the Richardson
    extrapolation (first order, benchmarks/bench_transient_auto.py) of the plain transient alone on 2 and 4 times the
    elements a single grid would need (422, 844), switched in the same way."""
    tolerance = 3.9e-3
    forces = {}
    for factor in (1, 2, 4):
        model = ContactModel(ContactParameters(transient=1, tolerance=tolerance,
                                               elements=factor * transient_elements(tolerance) if factor > 1 else 0))
        assert factor > 1 or model.instationary.extrapolate, "auto runs the pair"
        if factor > 1:
            model.lag = None  # the reference: the transient on every instationary step
        inputs, a = creep_oscillation(model, 1.0, 0.0, 1)
        inputs, _ = creep_oscillation(model, 8 * a, 0.5, 20, mean=0.2, h=a / 10 / 10.0)
        outs = run(model, inputs, h=a / 100.0)
        codes = [o.method_used for o in outs[2:]]
        assert codes == sorted(codes) and codes[-1] == 5 and (factor > 1 or codes[0] == 4), \
            f"auto: the lag while the swing is small, then the discretised transient; the references it alone: {codes}"
        forces[factor] = np.array([o.tangential_force for o in outs])
    reference = 2 * forces[4] - forces[2]
    error = np.abs(forces[1] - reference).max() / (model.mu * 1e5)
    assert error <= tolerance, f"error {error:.2e} mu N against the extrapolated transient (tolerance {tolerance})"


def pair_reference(parameters: ContactParameters, elements: int = 200) -> ContactModel:
    """The model with the extrapolating transient pair n/2, n in place of auto's choice and no lag: switched in and
    out like auto, accurate to C/n^2 mu N' (``EXTRAPOLATED_ERROR_CONSTANT``)."""
    model = ContactModel(parameters)
    model.lag = None
    model.instationary = InstationaryModel(model.radius, model.contact_modulus, model.mu, mode="transient",
                                           elements=elements, extrapolate=True)
    return model


def test_tight_tolerance_runs_the_lag_while_its_bound_meets_it():
    """``(0.5 + 0.1 sin) mu a/R`` at lambda/a = 10 (a swing not in the bound's calibration): at tolerance 1e-2 every
    instationary step runs the lag, and its error against the pair 100/200 stays within the lag's bound (plus the
    reference's 4e-4) at every step."""
    parameters = ContactParameters(transient=1, tolerance=1e-2)
    model, reference = ContactModel(parameters), pair_reference(parameters)
    _, a = creep_oscillation(model, 1.0, 0.0, 1)
    h = a / 50.0  # a/5 rolled per step
    inputs, _ = creep_oscillation(model, 10 * a, 0.1, 300, mean=0.5, h=h)
    outs, exact = run(model, inputs, h=h), run(reference, inputs, h=h)
    codes = [o.method_used for o in outs]
    assert set(codes[2:]) == {4}, f"the lag runs: {sorted(set(codes))}"
    error = np.abs([o.tangential_force - r.tangential_force for o, r in zip(outs, exact, strict=True)]) / (
        model.mu * 1e5)
    assert error.max() > 1e-4, "the case must tell the lag from the transient"
    bound = lag_error_bound(model.state.creep_envelope)
    assert error[-50:].max() <= bound + 16 / 200**2, f"lag error {error[-50:].max():.2e} mu N, bound {bound:.2e}"


@pytest.mark.slow
def test_tight_tolerance_hands_between_lag_and_transient_as_the_swing_grows_and_shrinks():
    """At tolerance 5e-3 a creep swing around 0.3 mu a/R growing from 0.02 to 0.6 mu a/R (lambda/a = 10): the lag
    until its bound passes the tolerance, then the transient pair from the lag's force; the swing back at 0.05: the
    lag again once its bound is below half the tolerance.  Every step within the tolerance of the pair 100/200."""
    parameters = ContactParameters(transient=1, tolerance=5e-3)
    model, reference = ContactModel(parameters), pair_reference(parameters)
    _, a = creep_oscillation(model, 1.0, 0.0, 1)
    h = a / 50.0
    saturation = model.mu * a / model.radius
    growing = 400
    swing = [0.02 + 0.58 * min(k, growing) / growing if k <= growing else 0.05 for k in range(800)]
    inputs = [(1e5, saturation * (0.3 + swing[k] * math.sin(2 * math.pi * k / 50)), 10.0) for k in range(800)]
    outs, exact = run(model, inputs, h=h), run(reference, inputs, h=h)
    codes = np.array([o.method_used for o in outs])
    switched = int(np.argmax(codes == 5))
    back = switched + int(np.argmax(codes[switched:] == 4))
    assert 2 < switched < growing and np.all(codes[2:switched] == 4), "the lag while the swing is small"
    assert growing < back and np.all(codes[switched:back] == 5) and np.all(codes[back:] == 4), \
        f"the transient from step {switched} while the swing is large, the lag again from step {back}"
    error = np.abs([o.tangential_force - r.tangential_force for o, r in zip(outs, exact, strict=True)]) / (
        model.mu * 1e5)
    assert error.max() <= 5e-3, f"largest error {error.max():.2e} mu N at step {int(error.argmax())}"


@pytest.mark.parametrize("rows", [
    [(1e5, 1e-3, 10.0), (1e5, -0.5, 10.0), (1e5, 0.5, 10.0), (1e5, 1e-3, 0.0), (1e5, 2e-3, 0.0)],
    [(1e5, 1e-3, 10.0), (0.0, 1e-3, 10.0), (1e5, 2e-3, 10.0), (1.5e5, 1e-3, 10.0), (1e9, 1e-3, 10.0)],
    [(1e-20, 1e-3, 10.0), (1e-20, 2e-3, 10.0), (1e5, 0.0, 1e6), (1e5, 1e-4, 1e-12), (1e5, 1e300, 10.0)],
])
def test_extreme_inputs_on_the_transient_path_give_outputs_or_model_errors(rows):
    model = ContactModel(ContactParameters(transient=1, tolerance=1e-3, elements=40))
    for k, row in enumerate(rows):
        try:
            out = model.step(k * H, H, *row)
        except ModelError:
            continue
        assert all(math.isfinite(v) for v in out), f"inputs {row}: outputs {out}"
        assert abs(out.traction_coefficient) <= model.mu * (1 + 1e-9), f"inputs {row}: |T/N| above mu"


def unresolved_corrugation_model(**parameters) -> ContactModel:
    """The scene of tests/test_api.py::UNRESOLVED_CORRUGATION in the model's parameters."""
    return ContactModel(ContactParameters(youngs_modulus=1e6, poisson_ratio=0.0, radius=1.0, friction_coefficient=0.001,
                                          corrugation_amplitude=2.0975242650564358e-06,
                                          corrugation_wavelength=2 * math.pi / 5857.780147685687, **parameters))


@pytest.mark.parametrize("tolerance", [1e-3, 0.0])
@pytest.mark.slow
def test_an_answer_whose_estimate_says_nothing_falls_through(tolerance):
    """The corrugation of tests/test_api.py::UNRESOLVED_CORRUGATION (k a = 293, the polynomial method's truncation
    estimate 49): the model, like solve(), takes the discretised answer, with a tolerance and without one (then it
    checks only the part of the estimate that costs nothing, the truncation); the polynomial method alone ends in
    an error naming the estimate (a Discard in the FMU)."""
    model = unresolved_corrugation_model(tolerance=tolerance, step_budget=0.0)
    out = model.step(0.0, 1e-9, 1000.0 * model.width, 1e-7, 1.0)
    assert out.method_used == 3, f"tolerance {tolerance}: method_used {out.method_used}"
    assert 0.0 < out.traction_coefficient <= model.mu, out
    with pytest.raises(ModelError, match="polynomial: its error estimate 49"):
        unresolved_corrugation_model(tolerance=tolerance, method=2).step(0.0, 1e-9, 1000.0 * model.width, 1e-7, 1.0)
    # the default step budget: the discretised grid this corrugation needs does not fit, and the step says so
    with pytest.raises(ModelError, match="budget"):
        unresolved_corrugation_model(tolerance=tolerance).step(0.0, 1e-9, 1000.0 * model.width, 1e-7, 1.0)


@pytest.mark.parametrize("parameters", [{"transient": 1, "tolerance": 1e-3}, {"transient": 1, "tolerance": 1e-3,
                                                                              "elements": 60}])
def test_an_extreme_step_leaves_no_state_that_fails_ordinary_steps(parameters):
    """A load whose contact no transient grid can hold with the datum (N = 1e12 N: a of metres) passes
    quasi-steady; the transient that then switches in at ordinary loads starts from the current load, not from
    that one."""
    model = ContactModel(ContactParameters(**parameters))
    outputs = run(model, [(1e12, 1e-3, 20.0)] + [(2e4, 1e-3, 20.0)] * 4, h=1e-4)
    ordinary = ContactModel(ContactParameters(**parameters)).step(0.0, 1e-4, 2e4, 1e-3, 20.0)
    for out in outputs[1:]:
        assert out.method_used in (1, 4, 5), f"an ordinary step after the extreme one: {out}"
        assert abs(out.tangential_force - ordinary.tangential_force) <= 1e-2 * 0.3 * 2e4, \
            f"the ordinary steps continue near the steady force: {out.tangential_force} vs {ordinary.tangential_force}"


@pytest.mark.parametrize(("parameters", "load", "creep", "speed", "named"), [
    ({}, 1e308, 1e-3, 20.0, "normal_load = 1e+308 N"),
    ({}, 5405.0, 1e300, 1e6, "frictional_power = inf"),
])
def test_a_step_whose_outputs_cannot_be_finite_is_refused_naming_the_value(parameters, load, creep, speed, named):
    model = ContactModel(ContactParameters(**parameters))
    with pytest.raises(ModelError, match=named.replace("+", r"\+")):
        model.step(0.0, H, load, creep, speed)
    assert model.state.steps == 0, "a refused step leaves the state"
    assert model.step(0.0, H, 2e4, 1e-3, 20.0).tangential_force > 0.0, "and the model stays usable"


@pytest.mark.parametrize("parameters", [{}, {"corrugation_amplitude": 2e-5}, {"friction_law": 1},
                                        {"transient": 2}, {"method": 3, "elements": 40}])
def test_a_subnormal_load_is_no_contact_on_every_path(parameters):
    """N' below the smallest normal double (or a^2 below it): the Hertz width and pressure underflow on every
    method alike."""
    for load in (5e-324, 1e-310, 1e-300):
        out = ContactModel(ContactParameters(**parameters)).step(0.0, H, load, 1e-3, 20.0)
        assert out.method_used == 0 and out.tangential_force == 0.0 and out.contact_half_width == 0.0, \
            f"{parameters}, N = {load}: {out}"


@pytest.mark.parametrize("parameters", [{}, {"friction_law": 1}, {"method": 2}])
def test_the_force_never_exceeds_mu_n_not_even_by_rounding(parameters):
    """In full slip the force per length is mu N' exactly; its conversion to the width, (mu N (1/b)) b, can round
    above mu N: the outputs keep |T| <= mu N and |T/N| <= mu exactly."""
    rng = np.random.default_rng(4)
    model = ContactModel(ContactParameters(**parameters))
    mu = model.friction_bound
    loads = np.concatenate(([21892.15873656356], rng.uniform(1e3, 1e5, 60)))
    for k, load in enumerate(loads):
        for creep in (0.01, -0.05):
            out = model.step(k * H, H, float(load), creep, 20.0)
            assert abs(out.tangential_force) <= mu * load and abs(out.traction_coefficient) <= mu, \
                f"N = {load!r}, creep {creep}: T = {out.tangential_force!r} > mu N = {mu * load!r}"


@pytest.mark.parametrize("parameters", [{"method": 3, "elements": 40}, {"transient": 2, "method": 3, "elements": 40},
                                        {"transient": 1, "tolerance": 1e-3}, {"corrugation_amplitude": 2e-5},
                                        {"friction_law": 1}, {"method": 3, "friction_law": 1, "elements": 40}])
def test_extreme_loads_give_finite_outputs_or_a_model_error_and_no_numpy_warning(parameters):
    """Loads per length from just above what floating point resolves to far beyond any contact: every step either
    answers finitely or refuses with a ModelError; no numpy warning (the suite turns RuntimeWarning into an error),
    no other exception, and the model goes on afterwards."""
    model = ContactModel(ContactParameters(step_budget=0.0, **parameters))
    t = 0.0
    for load in (1e-300, 1e-295, 1e-290, 1e-250, 1e-30, 1e12, 1e200, 1e300):
        for creep, speed in ((1e-3, 20.0), (-1e3, 1e6), (1e100, 0.0)):
            try:
                out = model.step(t, H, load, creep, speed)
            except ModelError:
                continue
            finally:
                t += H
            assert all(math.isfinite(v) for v in out), f"N = {load}, creep {creep}, V = {speed}: {out}"
    assert model.step(t, H, 2e4, 1e-3, 20.0).tangential_force > 0.0, "an ordinary step after the extremes"
