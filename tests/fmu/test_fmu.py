"""The RollingContact2D FMU, built once by ``python build_fmu.py`` and driven through fmpy (and a small C host).

The test process imports ``rollcontact`` itself, so the FMU instances in this process run that copy rather than
the one bundled in ``resources/`` (Python caches modules per process); the C host runs the bundled copy.
"""

from __future__ import annotations

import dataclasses
import math
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.validation import validate_fmu
from fmu_host import C_HOST, OUTPUTS, H, Instance, discarded, model_outputs, shared_libpython
from numpy.testing import assert_allclose

import rollcontact
from rollcontact.core.method import MethodSpec
from rollcontact.stepping import ContactParameters, StepOutputs
from rollcontact.stepping.line.parameters import STATIONARY

ROOT = Path(__file__).resolve().parents[2]


# ----------------------------------------------------------------------------------------------------------------
def test_fmu_validates_and_declares_units_bounds_and_starts(fmu_path, description):
    assert validate_fmu(str(fmu_path)) == [], "fmpy.validation.validate_fmu must report no problems"
    units = {u.name for u in description.unitDefinitions}
    for v in description.modelVariables:
        assert v.description, f"{v.name} has no description"
        assert v.start is not None, f"{v.name} has no start value"
        if v.type == "Real":
            assert v.unit in units, f"{v.name} has no declared unit"
    outputs = [v.name for v in description.modelVariables if v.causality == "output"]
    assert tuple(outputs) == OUTPUTS, "the FMU's outputs must follow StepOutputs"
    assert [v.valueReference for v in description.modelVariables] == list(range(len(description.modelVariables))), \
        "value references follow the order of the variable table"
    assert all(u.dependencies == [] for u in description.outputs), "outputs are computed in do_step only"
    caps = description.coSimulation
    assert caps.canGetAndSetFMUstate and caps.canSerializeFMUstate, "state handling must be declared"
    params = {v.name: v for v in description.modelVariables if v.causality == "parameter"}
    assert set(params) == {f.name for f in dataclasses.fields(ContactParameters)}, \
        "one FMU parameter per ContactParameters field"
    for name, v in params.items():
        default = getattr(ContactParameters(), name)
        start = {"Real": float, "Integer": int, "Enumeration": int, "String": str}[v.type](v.start)
        assert start == default, f"start of {name} ({v.start}) differs from the library default {default}"


def test_closed_form_outputs_equal_the_library_solve(instance):
    p = {"radius": 0.5, "contact_width": 0.015, "friction_coefficient": 0.25}
    fmu = instance(**p)
    rows = [(8e4, 0.0, 10.0), (8e4, 3e-4, 10.0), (1.2e5, -6e-4, 12.0), (5e4, 0.02, 12.0), (0.0, 1e-3, 12.0)]
    b = p["contact_width"]
    for n, (load, creep, speed) in enumerate(rows):
        out = fmu.step(n * H, H, load, creep, speed)
        scene = rollcontact.Scene(normal_load_per_length=load / b, creep=creep, radius=p["radius"],
                                  friction=rollcontact.Coulomb(p["friction_coefficient"]))
        ref = rollcontact.solve(scene)
        expected = [ref.tangential_force_per_length * b, ref.traction_coefficient, ref.contact_half_width,
                    ref.stick_half_width, ref.contact_offset, ref.max_pressure,
                    speed * creep * ref.tangential_force_per_length * b, ref.creep_stiffness_per_length * b]
        assert_allclose(out[:8], expected, rtol=1e-13, atol=0.0, err_msg=f"step {n}: FMU against rollcontact.solve")
        assert out.method_used == (1 if load > 0 else 0), f"step {n}: method_used {out.method_used}"


def test_carter_creep_curve_through_the_fmu(instance):
    fmu = instance()
    load, p = 1e5, ContactParameters()
    n_prime = load / p.contact_width
    a, _ = rollcontact.hertz(n_prime, p.radius, rollcontact.Material().contact_modulus)
    saturation = p.friction_coefficient * a / p.radius
    creeps = np.linspace(-2.0, 2.0, 41) * saturation
    forces = np.array([fmu.step(n * H, H, load, xi, 20.0).tangential_force for n, xi in enumerate(creeps)])
    r = np.clip(np.abs(creeps) / saturation, 0.0, 1.0)
    expected = np.sign(creeps) * p.friction_coefficient * load * (1.0 - (1.0 - r) ** 2)
    assert_allclose(forces, expected, rtol=1e-12, atol=1e-9 * load, err_msg="Carter: T = mu N (1 - (a*/a)^2)")
    assert_allclose(forces, -forces[::-1], rtol=1e-14, err_msg="the creep curve is odd")
    slope = fmu.step(len(creeps) * H, H, load, 0.0, 20.0).creep_stiffness
    estar = rollcontact.Material().contact_modulus
    assert_allclose(slope, math.pi * estar * a / 2 * p.contact_width, rtol=1e-13,
                    err_msg="initial slope pi E* a / 2 over the width")


def test_simulate_fmu_with_input_signals(unzipped):
    t = np.linspace(0.0, 0.05, 6)
    signals = np.array(list(zip(t, 1e5 + 4e5 * t, 1e-3 - 0.02 * t, 10.0 + 100.0 * t, strict=True)),
                       dtype=[("time", float), ("normal_load", float), ("creep", float), ("velocity", float)])
    result = simulate_fmu(str(unzipped), validate=False, start_time=0.0, stop_time=0.05, output_interval=H,
                          input=signals, output=list(OUTPUTS), start_values={"initial_position": 0.25})
    times = result["time"]
    assert_allclose(np.diff(times), H, rtol=1e-9, err_msg="one row per communication step")
    # row k holds the outputs of the step from t_(k-1): the inputs sampled there, the axis at X(t_(k-1))
    sample_times = times[1:] - H
    rows = [(1e5 + 4e5 * s, 1e-3 - 0.02 * s, 10.0 + 100.0 * s) for s in sample_times]
    expected = model_outputs({"initial_position": 0.25}, rows)
    for name in ("tangential_force", "contact_half_width", "frictional_power", "creep_stiffness"):
        assert_allclose(result[name][1:], [getattr(o, name) for o in expected], rtol=1e-9,
                        err_msg=f"simulate_fmu {name} against ContactModel")
    exact_position = 0.25 + 10.0 * sample_times + 50.0 * sample_times**2  # V is linear: the trapezoid is exact
    assert_allclose(result["axis_position"][1:], exact_position, rtol=1e-13, err_msg="X = X0 + int V dt")
    assert np.all(result["stationarity"][3:] < STATIONARY), "ramped inputs are not stationary"


def test_corrugated_surface_uses_the_polynomial_method(instance):
    p = {"corrugation_amplitude": 20e-6, "corrugation_wavelength": 0.04, "corrugation_phase": 0.3}
    fmu = instance(**p)
    b = ContactParameters().contact_width
    for n in range(4):
        out = fmu.step(n * H, H, 2e4, 1e-3, 5.0)
        x = out.axis_position
        # independent scene in the package frame: the mirror image, axis at -X
        scene = rollcontact.Scene(normal_load_per_length=2e4 / b, creep=1e-3, rolling_speed=5.0, axis_position=-x,
                                  surface=rollcontact.Surface(harmonics=(rollcontact.Harmonic.from_wavelength(
                                      0.04, 20e-6, -0.3),)))
        ref = rollcontact.solve(scene, method="polynomial")
        assert ref.success, ref.message
        assert out.method_used == 2, f"X = {x}: a corrugated surface needs the polynomial method"
        assert_allclose(out[:8], [ref.tangential_force_per_length * b, ref.traction_coefficient,
                                  ref.contact_half_width, ref.stick_half_width, -ref.contact_offset,
                                  ref.max_pressure, 5.0 * 1e-3 * ref.tangential_force_per_length * b,
                                  ref.creep_stiffness_per_length * b], rtol=1e-11, atol=1e-15,
                        err_msg=f"X = {x}: FMU against rollcontact.solve(method='polynomial')")
    assert_allclose(x, 3 * H * 5.0, rtol=1e-14, err_msg="the corrugation phase moves with X")


def test_split_contact_through_the_fmu_is_solved_with_several_patches(instance):
    """10 mm / 20 um corrugation, axis where the contact splits: the FMU's steps are the polynomial method's
    several-patch solutions (rollcontact.multipatch), method_used 2, for auto and for method = 2."""
    b = ContactParameters().contact_width
    p = {"corrugation_amplitude": 20e-6, "corrugation_wavelength": 0.01, "initial_position": -0.0045}
    for method in (0, 2):
        fmu = instance(method=method, **p)
        for n in range(3):
            out = fmu.step(n * H, H, 1e6 * b, 1e-3, 0.01)  # 10 um per step: the contact stays split
            x = out.axis_position
            scene = rollcontact.Scene(normal_load_per_length=1e6, creep=1e-3, rolling_speed=0.01, axis_position=-x,
                                      surface=rollcontact.Surface(harmonics=(rollcontact.Harmonic.from_wavelength(
                                          0.01, 20e-6),)))
            ref = rollcontact.solve(scene, method="polynomial")
            assert ref.success and len(ref.info["patches"]) == 2, ref.message
            assert out.method_used == 2, f"method {method}, X = {x}: {out.method_used}"
            assert_allclose(out[:8], [ref.tangential_force_per_length * b, ref.traction_coefficient,
                                      ref.contact_half_width, ref.stick_half_width, -ref.contact_offset,
                                      ref.max_pressure, 1e-5 * ref.tangential_force_per_length * b,
                                      ref.creep_stiffness_per_length * b], rtol=1e-11, atol=1e-15,
                            err_msg=f"method {method}, X = {x}: FMU against rollcontact.solve(method='polynomial')")


@pytest.mark.parametrize(("method", "used"), [(0, 2), (3, 3)], ids=["auto: polynomial", "discretised"])
def test_falling_friction_on_a_split_contact_through_the_fmu(instance, method, used):
    """The same split contact with a falling law: auto's step is the polynomial slip iteration on both patches
    (method_used 2), method 3 the discretised one on both (3); each the library's ContactModel's outputs."""
    b = ContactParameters().contact_width
    p = {"corrugation_amplitude": 20e-6, "corrugation_wavelength": 0.01, "initial_position": -0.0045,
         "friction_law": 1, "friction_kinetic_ratio": 0.4, "friction_decay": 3.0, "elements": 200, "method": method}
    fmu = instance(**p)
    rows = [(1e6 * b, 1e-3, 20.0), (1e6 * b, -5e-4, 20.0)]
    outs = [fmu.step(n * H, H, *row) for n, row in enumerate(rows)]
    for out, expected in zip(outs, model_outputs(p, rows), strict=True):
        assert out.method_used == used and out == expected, f"FMU {out} against ContactModel {expected}"
        assert 0.0 < abs(out.tangential_force) <= 0.3 * 1e6 * b, out


@pytest.mark.parametrize("parameters", [
    {"friction_law": 2, "friction_kinetic_ratio": 0.5, "friction_reference_velocity": 1.5},
    {"friction_law": 3, "friction_kinetic_ratio": 0.5, "friction_slope": 0.05},
    {"friction_law": 4, "friction_table": "0 0.3; 0.5 0.2; 4 0.15"},
], ids=["rational", "linear", "tabulated"])
def test_every_falling_law_is_an_fmu_parameter(instance, parameters):
    """Every falling law of the library without a scene file: the FMU's steps are the ContactModel's, whose law is
    the library's (tests/stepping/test_model.py checks it against rollcontact.solve)."""
    fmu = instance(**parameters)
    rows = [(1e5, 1e-3, 20.0), (1e5, 3e-3, 20.0)]
    outs = [fmu.step(n * H, H, *row) for n, row in enumerate(rows)]
    assert outs == model_outputs(parameters, rows), f"FMU {outs} against the ContactModel"
    coulomb = model_outputs({}, rows)
    assert all(0.0 < o.tangential_force < c.tangential_force for o, c in zip(outs, coulomb, strict=True)), \
        "a falling law lowers the force at the same creep"


@pytest.mark.parametrize(("code", "law"), [(1, (0.55, 0.4, 0.6)), (2, (0.3, 0.4, 0.2))], ids=["dry", "wet"])
def test_a_rail_condition_reaches_the_fmu_with_the_published_values(instance, code, law):
    """``rail_condition`` = dry or wet steps as the exponential law with Polach's mu_0, A, B given explicitly, and
    overrides the friction_* parameters set beside it."""
    fmu = instance(rail_condition=code, friction_coefficient=0.9, friction_law=3)
    rows = [(1e5, 1e-3, 20.0), (1e5, 4e-3, 20.0)]
    outs = [fmu.step(n * H, H, *row) for n, row in enumerate(rows)]
    explicit = {"friction_law": 1, "friction_coefficient": law[0], "friction_kinetic_ratio": law[1],
                "friction_decay": law[2]}
    assert outs == model_outputs(explicit, rows), f"rail_condition {code}: FMU {outs} against the explicit law"
    assert outs != model_outputs({}, rows), "the condition is not the default Coulomb law"


def test_explicit_discretised_method_through_the_fmu(instance):
    fmu = instance(method=3, corrugation_amplitude=20e-6, elements=100)
    out = fmu.step(0.0, H, 2e4, 1e-3, 5.0)
    assert out.method_used == 3, f"method = 3 must report 3, got {out.method_used}"
    expected = model_outputs({"method": 3, "corrugation_amplitude": 20e-6, "elements": 100}, [(2e4, 1e-3, 5.0)])
    assert out == expected[0], "the FMU's discretised step equals ContactModel's"


TILTED_SCENE = "[surface]\npolynomial = [0.0, 1e-3]\n[load]\nnormal_load_per_length = 1.0\n"


def test_tilted_scene_file_moves_the_contact_uphill(instance, tmp_path):
    path = tmp_path / "tilted.toml"
    path.write_text(TILTED_SCENE)
    fmu = instance(scene_file=str(path))
    out = fmu.step(0.0, H, 1e5, 1e-3, 20.0)
    assert_allclose(out.contact_offset, 0.46e-3, rtol=1e-13, err_msg="uphill (ahead) by R alpha")
    assert any("scene_file" in m for _, _, m in fmu.log), "the scene file's overrides are logged"


def test_relative_scene_file_is_read_from_the_resources_folder(instance, unzipped, monkeypatch, tmp_path):
    folder = unzipped / "resources" / "test_scenes"
    folder.mkdir()
    try:
        (folder / "tilted.toml").write_text(TILTED_SCENE)
        monkeypatch.chdir(tmp_path)  # not the resources folder
        out = instance(scene_file="test_scenes/tilted.toml").step(0.0, H, 1e5, 1e-3, 20.0)
    finally:
        shutil.rmtree(folder)
    assert_allclose(out.contact_offset, 0.46e-3, rtol=1e-13, err_msg="the bundled tilted scene was used")


def test_relative_scene_file_is_read_from_the_working_directory_and_a_missing_one_names_every_path(
        instance, monkeypatch, tmp_path):
    """``scene_file="models/corrugated.toml"`` from the project root (not in the resources folder): the working
    directory's file; a name found nowhere: the error names the resources path and the working directory's."""
    monkeypatch.chdir(ROOT)
    out = instance(scene_file="models/corrugated.toml").step(0.0, H, 1e5, 1e-3, 20.0)
    assert out.method_used == 2, f"the corrugated scene of models/ was used: {out}"
    missing = instance(scene_file="models/no_such_scene.toml")
    message = discarded(missing, 0.0, H, 1e5, 1e-3, 20.0)
    assert "resources" in message and str(ROOT / "models" / "no_such_scene.toml") in message, message


def test_enumerations_bounds_and_descriptions_say_what_the_model_accepts(description):
    """method, friction_law, transient and method_used are FMI enumerations with the model's codes; every
    description fits a tooltip; every declared min and max is a value the model accepts, and the next value beyond
    it one it refuses (FMI bounds are inclusive: > 0 is declared as the smallest normal double)."""
    from rollcontact.stepping.line.parameters import (
        INSTATIONARY_CODES,
        METHOD_NAMES,
        TABLE_CODE,
        TABLE_MODES,
        TRANSIENT_MODES,
    )
    from rollcontact.stepping.parameters import FRICTION_LAWS, RAIL_CONDITION_CODES

    variables = {v.name: v for v in description.modelVariables}
    types = {t.name: {item.value: item.name for item in t.items} for t in description.typeDefinitions}
    expected = {"method": [0, *METHOD_NAMES], "friction_law": list(FRICTION_LAWS), "transient": list(TRANSIENT_MODES),
                "method_used": [0, *METHOD_NAMES, *INSTATIONARY_CODES.values(), TABLE_CODE],
                "table": list(TABLE_MODES), "rail_condition": list(RAIL_CONDITION_CODES)}
    for name, codes in expected.items():
        v = variables[name]
        assert v.type == "Enumeration" and v.declaredType is not None, f"{name} is an enumeration"
        assert sorted(int(value) for value in types[v.declaredType.name]) == sorted(codes), \
            f"{name}: items {types[v.declaredType.name]} against the model's codes {codes}"
    for v in description.modelVariables:
        assert len(v.description) <= 100, f"{v.name}: a description of {len(v.description)} characters"
    default = ContactParameters()
    for v in description.modelVariables:
        if v.causality != "parameter" or v.type == "String":
            continue
        for bound, direction in ((v.min, -math.inf), (v.max, math.inf)):
            if bound is None:
                continue
            value = float(bound) if v.type == "Real" else int(bound)
            table = {"friction_table": "0 0.3"} if v.name == "friction_law" else {}  # the tabulated law's points
            ContactParameters(**{**default.__dict__, **table, v.name: value})  # accepted
            beyond = math.nextafter(value, direction) if v.type == "Real" else value + (1 if direction > 0 else -1)
            with pytest.raises(ValueError):
                ContactParameters(**{**default.__dict__, v.name: beyond})


def test_the_documented_variable_table_is_the_slave_table():
    import build_fmu

    assert build_fmu.variables_table() in (ROOT / "docs" / "fmu.md").read_text(), \
        "docs/fmu.md's variable table differs from the slave's: run python build_fmu.py --docs"


@pytest.mark.parametrize("args, reason", [
    ((0.0, H, math.nan, 1e-3, 20.0), "normal_load = nan is not finite"),
    ((0.0, H, math.inf, 1e-3, 20.0), "normal_load = inf is not finite"),
    ((0.0, H, -1.0, 1e-3, 20.0), "normal_load = -1.0 N is out of range: it must be >= 0"),
    ((0.0, H, 1e5, math.nan, 20.0), "creep = nan is not finite"),
    ((0.0, H, 1e5, -math.inf, 20.0), "creep = -inf is not finite"),
    ((0.0, H, 1e5, 1e-3, -0.5), "velocity = -0.5 m/s is out of range: it must be >= 0"),
    ((0.0, H, 1e5, 1e-3, math.nan), "velocity = nan is not finite"),
    ((0.0, 0.0, 1e5, 1e-3, 20.0), "step_size = 0.0 s is out of range: it must be > 0"),
    ((0.0, -H, 1e5, 1e-3, 20.0), "step_size = -0.001 s is out of range: it must be > 0"),
])
def test_bad_inputs_are_discarded_with_the_reason_and_restoring_a_state_recovers(instance, args, reason):
    fmu = instance()
    state = fmu.fmu.getFMUstate()
    message = discarded(fmu, *args)
    assert reason in message, f"logged {message!r}, expected it to say {reason!r}"
    fmu.fmu.setFMUstate(state)
    fmu.fmu.freeFMUstate(state)
    out = fmu.step(0.0, H, 1e5, 1e-3, 20.0)
    assert out == model_outputs({}, [(1e5, 1e-3, 20.0)])[0], "after a Discard a restored instance steps normally"


@pytest.mark.parametrize("parameters, reason", [
    ({"poisson_ratio": 0.6}, "poisson_ratio = 0.6 is out of range"),
    ({"contact_width": 0.0}, "contact_width = 0.0 is out of range"),
    ({"friction_law": 7}, "friction_law = 7 is out of range"),
    ({"method": 1, "corrugation_amplitude": 1e-5}, "method = 1 (closed form) cannot solve this scene"),
    ({"scene_file": "/nonexistent/100%.toml"}, "scene_file '/nonexistent/100%.toml' was not found"),
])
def test_bad_parameters_are_discarded_with_the_reason(instance, parameters, reason):
    fmu = instance(**parameters)
    state = fmu.fmu.getFMUstate()
    message = discarded(fmu, 0.0, H, 1e5, 1e-3, 20.0)
    assert reason in message, f"logged {message!r}, expected it to say {reason!r}"
    fmu.fmu.setFMUstate(state)
    fmu.fmu.freeFMUstate(state)
    assert reason in discarded(fmu, 0.0, H, 1e5, 1e-3, 20.0), "a restored state keeps its parameter problem"


@pytest.mark.parametrize("parameters", [
    {"radius": -0.1, "friction_coefficient": 0.0},
    {"poisson_ratio": 0.6, "contact_width": 0.0, "friction_law": 7},
])
def test_every_invalid_parameter_is_named_in_one_refusal(instance, parameters):
    fmu = instance(**parameters)
    message = discarded(fmu, 0.0, H, 1e5, 1e-3, 20.0)
    for name, value in parameters.items():
        assert f"{name} = {value!r} is out of range" in message, f"{message!r} must name {name} = {value!r}"
    refusals = [m for s, _, m in fmu.log if s == 3 and "invalid parameters" in m]
    assert len(refusals) == 1, f"one refusal at initialisation, naming all: {refusals}"
    assert all(f"{name} = {value!r}" in refusals[0] for name, value in parameters.items()), refusals[0]


def test_a_scene_the_method_cannot_solve_is_discarded(instance, monkeypatch):
    def failing(scene, **options):
        return rollcontact.ContactResult(method="polynomial", success=False, message="contact splits (test)",
                                         normal_load_per_length=0.0, tangential_force_per_length=0.0, creep=0.0,
                                         contact_half_width=0.0, contact_offset=0.0, stick_half_width=0.0,
                                         max_pressure=0.0)

    spec = rollcontact.METHODS.get("polynomial")
    monkeypatch.setitem(rollcontact.METHODS, "polynomial",
                        MethodSpec("polynomial", failing, lambda s: None, 10))
    fmu = instance(method=2, corrugation_amplitude=1e-5)
    message = discarded(fmu, 0.0, H, 1e5, 1e-3, 20.0)
    assert "polynomial failed: contact splits (test)" in message, f"logged {message!r}"
    assert spec is None or rollcontact.METHODS["polynomial"] is not spec, "the failing method was in use"


def test_state_get_set_and_serialise(instance, unzipped, description):
    fmu = instance(initial_position=0.1)
    warmup = [(1e5, 1e-3, 20.0), (1.2e5, 2e-3, 21.0), (1.1e5, -1e-3, 22.0)]
    later = [(9e4, 5e-4, 20.0), (1e5, 1e-3, 19.0), (1e5, 1e-3, 19.0)]
    for n, row in enumerate(warmup):
        fmu.step(n * H, H, *row)
    state = fmu.fmu.getFMUstate()
    saved_outputs = fmu.outputs()
    first = [fmu.step((3 + n) * H, H, *row) for n, row in enumerate(later)]
    fmu.fmu.setFMUstate(state)
    assert fmu.outputs() == saved_outputs, "restoring a state restores the outputs"
    second = [fmu.step((3 + n) * H, H, *row) for n, row in enumerate(later)]
    assert first == second, "restore -> step -> restore -> step must give identical outputs"
    serialized = fmu.fmu.serializeFMUstate(state)
    fmu.fmu.freeFMUstate(state)
    other = instance(radius=0.3)  # other parameters: the state brings its own
    restored = other.fmu.deSerializeFMUstate(serialized)
    other.fmu.setFMUstate(restored)
    other.fmu.freeFMUstate(restored)
    third = [other.step((3 + n) * H, H, *row) for n, row in enumerate(later)]
    assert third == first, "a serialised state continues identically in another instance"
    assert first == model_outputs({"initial_position": 0.1}, warmup + later)[3:], "and equals ContactModel"


def test_two_instances_are_independent(instance):
    a = instance()
    b = instance(radius=0.3, friction_coefficient=0.2, contact_width=0.01)
    rows = [(1e5, 1e-3, 20.0), (1.1e5, 2e-3, 10.0), (9e4, -1e-3, 15.0)]
    out_a = [a.step(n * H, H, *row) for n, row in enumerate(rows)]
    out_b = [b.step(n * H, H, *row) for n, row in enumerate(rows)]
    assert out_a == model_outputs({}, rows), "instance a keeps its own parameters and state"
    assert out_b == model_outputs({"radius": 0.3, "friction_coefficient": 0.2, "contact_width": 0.01}, rows), \
        "instance b keeps its own parameters and state"


CORRUGATION_TABLE = {"corrugation_amplitude": 20e-6, "corrugation_wavelength": 0.04, "table": 2}


def test_state_round_trips_and_instances_stay_independent_with_certified_tables_in_use(instance):
    rows = [(2e4 * (1.0 + 0.05 * math.sin(n)), 1.1e-3 + 1e-3 * math.sin(0.6 * n) ** 2, 30.0) for n in range(9)]
    fmu = instance(**CORRUGATION_TABLE)
    for n, row in enumerate(rows[:3]):
        fmu.step(n * H, H, *row)
    state = fmu.fmu.getFMUstate()
    first = [fmu.step((3 + n) * H, H, *row) for n, row in enumerate(rows[3:])]
    assert {o.method_used for o in first} == {6}, "the steps answer from the table"
    serialized = fmu.fmu.serializeFMUstate(state)
    fmu.fmu.setFMUstate(state)
    fmu.fmu.freeFMUstate(state)
    assert [fmu.step((3 + n) * H, H, *row) for n, row in enumerate(rows[3:])] == first, "restore -> step repeats"
    other = instance(table=1)  # the state brings its parameters and its table's domain
    restored = other.fmu.deSerializeFMUstate(serialized)
    other.fmu.setFMUstate(restored)
    other.fmu.freeFMUstate(restored)
    assert [other.step((3 + n) * H, H, *row) for n, row in enumerate(rows[3:])] == first, \
        "a serialised state builds the same table in another instance and continues bit for bit"
    assert first == model_outputs(CORRUGATION_TABLE, rows)[3:], "and equals ContactModel"
    shallow = instance(**{**CORRUGATION_TABLE, "corrugation_amplitude": 10e-6})
    outs = [shallow.step(n * H, H, *row) for n, row in enumerate(rows)]
    assert outs == model_outputs({**CORRUGATION_TABLE, "corrugation_amplitude": 10e-6}, rows), \
        "an instance with another table keeps its own"
    assert [o.contact_half_width for o in outs[3:]] != [o.contact_half_width for o in first], "another contact"


@pytest.mark.parametrize(("stop_time", "builds"), [(10.0, True), (0.2, False)])
def test_the_stop_time_of_setup_experiment_decides_whether_auto_builds_a_table(instance, stop_time, builds):
    fmu = instance(stop_time=stop_time, step_budget=0.005, **{**CORRUGATION_TABLE, "table": 0})
    used = [fmu.step(n * H, H, 2e4, 1.1e-3 + 1e-3 * math.sin(0.6 * n) ** 2, 30.0).method_used for n in range(200)]
    log = " | ".join(message for _, _, message in fmu.log)
    if builds:  # 10 000 steps pay for the build: it starts at once, not after a build's worth of exact steps
        assert 6 in used and used[-1] == 6, f"the table is built within the budget over the first steps: {used}"
        assert "building a certified table" in log and "ready over" in log, log
    else:
        assert set(used) == {2}, "200 steps do not pay for a build: exact steps"
        assert "steps remain, fewer than" in log, log


def test_load_free_load_and_independence_of_the_current_directory(unzipped, description, monkeypatch, tmp_path):
    rows = [(1e5, 1e-3, 20.0), (1.1e5, 2e-3, 10.0)]
    expected = model_outputs({}, rows)
    for attempt in range(2):
        monkeypatch.chdir(tmp_path if attempt else ROOT)
        fmu = Instance(unzipped, description, name=f"again{attempt}")
        got = [fmu.step(n * H, H, *row) for n, row in enumerate(rows)]
        fmu.free()
        assert got == expected, f"load {attempt + 1} (cwd {Path.cwd()}) must give the same outputs"


def oscillating_creep(steps: int, wavelength=0.02, velocity=10.0, h=2e-5):
    """Rows (normal_load, creep, velocity) of a creep oscillation fast enough for the lag (lambda/a ~ 4)."""
    return [(1e5, 4e-4 + 3e-3 * math.sin(2 * math.pi * velocity * k * h / wavelength), velocity) for k in range(steps)]


@pytest.mark.parametrize("parameters, code", [({"transient": 1}, 4), ({"transient": 2}, 4),
                                              ({"transient": 2, "method": 3, "elements": 40}, 5),
                                              ({"transient": 2, "method": 3, "tolerance": 2e-3}, 5)])
def test_instationary_steps_equal_the_model_and_their_state_round_trips(instance, parameters, code):
    """Also the extrapolating pair (tolerance 2e-3: 29/58 elements), whose state carries both grids' traction and
    pending rolls."""
    h = 2e-5
    rows = oscillating_creep(24, h=h)
    fmu = instance(**parameters)
    got = [fmu.step(n * h, h, *row) for n, row in enumerate(rows[:12])]
    state = fmu.fmu.getFMUstate()
    got += [fmu.step((12 + n) * h, h, *row) for n, row in enumerate(rows[12:])]
    expected = model_outputs(parameters, rows, h=h)
    assert got == expected, "the FMU's instationary steps equal ContactModel's"
    assert got[-1].method_used == code, f"method_used {code} for {parameters}"
    serialized = fmu.fmu.serializeFMUstate(state)
    fmu.fmu.freeFMUstate(state)
    other = instance(**parameters)
    restored = other.fmu.deSerializeFMUstate(serialized)
    other.fmu.setFMUstate(restored)
    other.fmu.freeFMUstate(restored)
    again = [other.step((12 + n) * h, h, *row) for n, row in enumerate(rows[12:])]
    assert again == got[12:], "a serialised state carries the instationary history into another instance"


def test_transient_on_a_scene_the_instationary_models_do_not_treat(instance):
    fmu = instance(transient=1, corrugation_amplitude=5e-6)
    for n in range(3):
        fmu.step(n * H, H, 1e5, 1e-3, 20.0)
    notices = [m for _, _, m in fmu.log if "solved quasi-steady" in m]
    assert len(notices) == 1, f"transient = 1 on a corrugated rail is logged once, got {notices}"
    always = instance(transient=2, corrugation_amplitude=5e-6)
    message = discarded(always, 0.0, H, 1e5, 1e-3, 20.0)
    assert "transient = 2 (always) cannot treat this scene" in message, f"logged {message!r}"


def test_a_c_host_gets_the_same_numbers_as_fmpy(unzipped, description, instance, tmp_path):
    gcc = shutil.which("gcc")
    if gcc is None:
        pytest.skip("gcc is not installed: the C host cannot be compiled")
    libpython = shared_libpython()
    if libpython is None:
        pytest.skip("this Python has no shared libpython (built without --enable-shared): a non-Python host "
                    "cannot load the pythonfmu binary, which needs LD_PRELOAD=<libpython3.x.so>")
    source, host = tmp_path / "host.c", tmp_path / "host"
    source.write_text(C_HOST)
    built = subprocess.run([gcc, "-std=c99", "-Wall", "-Werror", "-o", str(host), str(source), "-ldl"],
                           capture_output=True, text=True)
    assert built.returncode == 0, f"C host does not compile:\n{built.stderr}"
    fmu = instance()
    binary = next((unzipped / "binaries" / "linux64").glob("*.so"))
    rows = [(1e5, 1e-3, 20.0), (2e5, -1e-3, 20.0), (-1.0, 0.0, 0.0), (1.5e5, 3e-3, 25.0), (0.0, 0.0, 25.0)]
    args = [str(host), str(binary), description.guid, (unzipped / "resources").as_uri(), repr(H),
            *map(str, fmu.inputs), str(fmu.integer[0]), *map(str, fmu.reals)]
    # PYTHONHOME: the embedded interpreter would otherwise locate its library through the first python3 on PATH
    env = {"PATH": "/usr/bin:/bin", "LD_PRELOAD": str(libpython), "PYTHONHOME": sys.base_prefix,
           "PYTHONPATH": sysconfig.get_paths()["purelib"]}
    ran = subprocess.run(args, input="".join(f"{n!r} {c!r} {v!r}\n" for n, c, v in rows), capture_output=True,
                         text=True, env=env, cwd=tmp_path, timeout=120)
    assert ran.returncode == 0, f"C host failed ({ran.returncode}):\n{ran.stderr}"
    lines = [line.split() for line in ran.stdout.splitlines()]
    assert len(lines) == len(rows), f"one line per step expected:\n{ran.stdout}\n{ran.stderr}"
    assert "normal_load = -1.0 N is out of range" in ran.stderr, \
        f"the Discard reason must reach the C host's logger:\n{ran.stderr}"
    assert "RollingContact2D (instance 'c_host')" not in ran.stderr, \
        f"the logger received the reason: the FMU does not repeat it on standard error:\n{ran.stderr}"
    for n, (row, line) in enumerate(zip(rows, lines, strict=True)):
        try:
            expected, status = fmu.step(n * H, H, *row), 0
        except FMICallException as exc:
            expected, status = fmu.outputs(), exc.status
        reals = iter(float(v) for v in line[1:-1])
        got = StepOutputs(*(int(line[-1]) if name == "method_used" else next(reals) for name in OUTPUTS))
        assert int(line[0]) == status, f"step {n}: C host status {line[0]}, fmpy {status}"
        assert got == expected, f"step {n}: the C host and fmpy must agree exactly:\n{got}\n{expected}"


def test_the_integer_codes_build_serves_hosts_without_enumerations(integer_codes):
    """``build_fmu.py --integer-codes`` (the test run's build, ``tests/conftest.py``): the same FMU with plain Integer
    variables whose descriptions give the codes (libcosim lists no enumeration variables); fmpy validates it."""
    from fmpy import read_model_description

    path = integer_codes / "RollingContact2D.fmu"
    assert validate_fmu(str(path)) == [], "fmpy validates the integer-codes build"
    variables = {v.name: v for v in read_model_description(str(path)).modelVariables}
    for name, codes in (("method", "0 auto, 1 closed_form, 2 polynomial, 3 discretised"),
                        ("transient", "0 quasi_static, 1 auto, 2 always")):
        assert variables[name].type == "Integer" and codes in variables[name].description, \
            f"{name}: {variables[name].type}, {variables[name].description!r}"
