"""Co-simulation of the WheelRig host FMU with the RollingContact2D FMU through the fmpy master.

The FMUs are built once into a temporary folder (``build_fmu.py --all``).  This process imports ``rollcontact``
and ``rollcontact_cosim`` itself, so the FMU instances run those copies rather than the bundled ones.  Tolerances:
identities and closed forms ~1e-12, the host's quasi-static equilibrium 1e-6, results against the reference CSVs
within each scene's band (1 % of a variable's range, 5 of 1000 resampled points, no outliers).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.validation import validate_fmu
from numpy.testing import assert_allclose

from rollcontact.core.materials import Material
from rollcontact.line.carter import carter
from rollcontact.line.hertz import hertz
from rollcontact_cosim.__main__ import main as main_job
from rollcontact_cosim.master import Slave, ensure_fmus, run_cosimulation, summarise
from rollcontact_cosim.reference import compare, read_reference, write_reference
from rollcontact_cosim.scenes import CONTACT, HOST, SCENE_NAMES, Band, CosimSceneError, load_cosim_scene
from rollcontact_cosim.stable_step import deviation, is_stable
from rollcontact_cosim.wheel_rig import INPUT_NAMES, WheelRigModel, WheelRigOutputs, WheelRigParameters

DISCARD = 2
CREEP, TRACTION, FORCE = f"{HOST}.creep", f"{CONTACT}.traction_coefficient", f"{CONTACT}.tangential_force"


@pytest.fixture(scope="module")
def fmu_dir(tmp_path_factory):
    """Both FMUs, built by ``build_fmu.py --all`` into a temporary folder once for the module."""
    folder = tmp_path_factory.mktemp("cosim_fmus")
    paths = ensure_fmus(folder)
    assert all(p.is_file() for p in paths.values()), f"build_fmu.py --all did not write {paths}"
    return folder


@pytest.fixture(scope="module")
def run(fmu_dir):
    """``run(scene, **options)``: run_cosimulation with the module's FMUs, each distinct run once."""
    done = {}

    def cached(scene, **options):
        key = (scene, repr(sorted(options.items())))
        if key not in done:
            done[key] = run_cosimulation(scene, fmu_dir=fmu_dir, **options)
            assert done[key].success, f"{scene} {options}: {done[key].message}"
        return done[key]

    return cached


@pytest.fixture
def host(fmu_dir):
    """A factory of initialised WheelRig instances (parameters as keywords), freed after the test."""
    made = []

    def make(**parameters) -> Slave:
        slave = Slave(fmu_dir / "WheelRig.fmu", f"rig{len(made)}")
        made.append(slave)
        slave.set_start_values(parameters)
        slave.initialise()
        return slave

    yield make
    for slave in made:
        slave.free()


def host_step(slave: Slave, t: float, h: float, force: float, stiffness: float, torque: float = 0.0):
    """Set the host's inputs, step, and return its outputs as WheelRigOutputs."""
    slave.fmu.setReal([slave.reference(n) for n in INPUT_NAMES], [force, stiffness, torque])
    slave.fmu.doStep(t, h)
    return WheelRigOutputs(*slave.fmu.getReal([slave.reference(n) for n in WheelRigOutputs._fields]))


# the host FMU -----------------------------------------------------------------------------------------------------
def test_host_fmu_validates_and_declares_the_model(fmu_dir):
    path = fmu_dir / "WheelRig.fmu"
    assert validate_fmu(str(path)) == [], "fmpy.validation.validate_fmu must report no problems"
    slave = Slave(path, "describe")
    try:
        description = slave.description
        units = {u.name for u in description.unitDefinitions}
        variables = description.modelVariables
        for v in variables:
            assert v.description, f"{v.name} has no description"
            assert v.start is not None, f"{v.name} has no start value"
            if v.type == "Real":
                assert v.unit in units, f"{v.name} has no declared unit"
        by_causality = {c: [v.name for v in variables if v.causality == c] for c in ("input", "output", "parameter")}
        assert tuple(by_causality["input"]) == INPUT_NAMES, "inputs follow wheel_rig.INPUT_NAMES"
        assert tuple(by_causality["output"]) == WheelRigOutputs._fields, "outputs follow WheelRigOutputs"
        defaults = WheelRigParameters()
        assert by_causality["parameter"] == list(defaults.__dataclass_fields__), "one parameter per field, in order"
        for v in variables:
            if v.causality == "parameter":
                assert float(v.start) == getattr(defaults, v.name), f"{v.name}: start {v.start} is not the default"
        assert [v.valueReference for v in variables] == list(range(len(variables))), "value references = row order"
        assert all(u.dependencies == [] for u in description.outputs), "outputs are computed in do_step only"
        assert description.coSimulation.canGetAndSetFMUstate, "state handling must be declared"
    finally:
        slave.free()


def test_host_creep_is_regularised_at_standstill(host):
    """v = 0: xi = omega r / v_reg, finite; the wheel spins up under the torque alone (no contact force)."""
    rig = host(initial_velocity=0.0, torque_final=300.0, creep_regularisation_velocity=0.1)
    out = host_step(rig, 0.0, 1e-3, 0.0, 0.0)
    assert all(math.isfinite(v) for v in out), f"outputs must be finite at standstill: {out}"
    assert out.velocity == 0.0, f"no force, no resistance at v = 0: v must stay 0, got {out.velocity}"
    assert_allclose(out.wheel_speed, 300.0 / 150.0 * 1e-3, rtol=1e-12, err_msg="omega = M h / J")
    assert_allclose(out.creep, out.wheel_speed * 0.46 / 0.1, rtol=1e-12, err_msg="xi = omega r / v_reg at v = 0")


@pytest.mark.parametrize("inputs, reason", [
    ((math.nan, 0.0, 0.0), "tangential_force = nan N is not finite"),
    ((0.0, math.inf, 0.0), "creep_stiffness = inf N is not finite"),
    ((0.0, 0.0, -math.inf), "external_torque = -inf N m is not finite"),
])
def test_bad_host_inputs_are_discarded_and_a_restored_state_steps_on(host, inputs, reason):
    rig = host()
    state = rig.fmu.getFMUstate()
    with pytest.raises(FMICallException) as caught:
        host_step(rig, 0.0, 1e-3, *inputs)
    assert caught.value.status == DISCARD, f"{inputs}: expected fmi2Discard (not Fatal), got {caught.value.status}"
    assert reason in rig.log[-1] and rig.log[-1].startswith("Discard"), f"logged {rig.log[-1]!r}, want {reason!r}"
    rig.fmu.setFMUstate(state)
    rig.fmu.freeFMUstate(state)
    out = host_step(rig, 0.0, 1e-3, 1e3, 1e7)
    expected = WheelRigModel().step(0.0, 1e-3, 1e3, 1e7)
    assert out == expected, "after a Discard a restored instance steps as the model does"


@pytest.mark.parametrize("parameters, reason", [
    ({"coupling": 2}, "coupling = 2 is out of range"),
    ({"load_amplitude": 2e5}, "load_amplitude = 200000.0 N is out of range"),
    ({"wheel_radius": 0.0}, "wheel_radius = 0.0 m is out of range"),
])
def test_bad_host_parameters_are_discarded_with_the_reason(host, parameters, reason):
    rig = host(**parameters)
    with pytest.raises(FMICallException) as caught:
        host_step(rig, 0.0, 1e-3, 0.0, 0.0)
    assert caught.value.status == DISCARD, f"{parameters}: expected fmi2Discard, got {caught.value.status}"
    assert reason in rig.log[-1], f"logged {rig.log[-1]!r}, expected it to say {reason!r}"


def test_host_state_restore_repeats_the_steps(host):
    rig = host(torque_final=5e3, coupling=1, force_lag=1)
    rows = [(1e4, 1.5e7), (1.1e4, 1.4e7), (1.05e4, 1.45e7)]
    host_step(rig, 0.0, 1e-3, 9e3, 1.6e7)
    state = rig.fmu.getFMUstate()
    first = [host_step(rig, (1 + n) * 1e-3, 1e-3, *row) for n, row in enumerate(rows)]
    rig.fmu.setFMUstate(state)
    second = [host_step(rig, (1 + n) * 1e-3, 1e-3, *row) for n, row in enumerate(rows)]
    rig.fmu.freeFMUstate(state)
    assert first == second, "restore -> step -> restore -> step must give identical outputs (incl. force_lag memory)"


# the host model ---------------------------------------------------------------------------------------------------
def test_constant_force_integrates_exactly():
    """Explicit coupling, no resistance: omega and v are linear in t, which linearly implicit Euler gets exactly."""
    p = WheelRigParameters(coupling=0, resistance_constant=0.0, resistance_linear=0.0, resistance_quadratic=0.0,
                           torque_final=6e3, substeps=3)
    model = WheelRigModel(p)
    h, force = 2e-3, 1e4
    for n in range(50):
        out = model.step(n * h, h, force, 1e9)  # the stiffness must be ignored when explicit
    t = 50 * h
    assert_allclose(out.velocity, 10.0 + force / p.vehicle_mass * t, rtol=1e-13, err_msg="v = v0 + T t / m")
    assert_allclose(out.wheel_speed, 10.0 / 0.46 + (6e3 - 0.46 * force) / p.wheel_inertia * t, rtol=1e-13,
                    err_msg="omega = omega0 + (M - r T) t / J")


def linear_law_loop(coupling: int, force_lag: int, jacobi: bool, steps: int = 30, h: float = 1e-2,
                    stiffness: float = 1.8e7) -> np.ndarray:
    """Creep history of the host in a loop with the linear law T = k xi, handed T(xi_n) (Gauss-Seidel ordering)
    or T(xi_(n-1)) (Jacobi ordering), no resistance, a constant 8 kN m."""
    model = WheelRigModel(WheelRigParameters(torque_final=8e3, coupling=coupling, force_lag=force_lag,
                                             resistance_constant=0.0, resistance_linear=0.0,
                                             resistance_quadratic=0.0))
    creep = [model.outputs().creep]
    for n in range(steps):
        seen = creep[-2] if jacobi and n > 0 else creep[-1]
        creep.append(model.step(n * h, h, stiffness * seen, stiffness).creep)
    return np.array(creep)


def quasi_static_creep(xi: float, k: float = 1.8e7, r: float = 0.46, inertia: float = 150.0,
                       mass: float = 1e4) -> float:
    """Creep of the force T = M / (r + J (1 + xi) / (m r)) that accelerates wheel and vehicle alike (M = 8 kN m)."""
    return 8e3 / (r + inertia * (1.0 + xi) / (mass * r)) / k


def test_linearly_implicit_coupling_settles_where_explicit_diverges():
    """Stiff loop at H = 10 ms (|lambda| H ~ 27): with force_lag matching the ordering the implicit host reaches
    the quasi-static creep; the explicit host diverges (amplification 1 - |lambda| H per step)."""
    for force_lag, jacobi in ((0, False), (1, True)):
        xi = linear_law_loop(1, force_lag, jacobi)[-1]
        assert_allclose(xi, quasi_static_creep(xi), rtol=1e-6,
                        err_msg=f"implicit, force_lag {force_lag}, {'Jacobi' if jacobi else 'Gauss-Seidel'}")
    explicit = linear_law_loop(0, 0, False, steps=3)
    growth = np.abs(explicit[2:] / explicit[1:-1])
    assert np.all(growth > 10.0), f"explicit at 10 ms must diverge (factor ~ -26 per step): creep {explicit}"


def test_force_lag_must_match_the_algorithm():
    """Jacobi ordering with force_lag 0 linearises about the wrong creep and rings: the roots of
    (1 + a) z^2 - (1 + a) z + a = 0 have |z| = sqrt(a / (1 + a)) ~ 0.98 at a = |lambda| H ~ 27."""
    creep = linear_law_loop(1, 0, True)
    mismatch = np.abs(creep[-10:] / quasi_static_creep(creep[-1]) - 1.0)
    assert mismatch.max() > 0.1, f"Jacobi with force_lag 0 must still ring after 30 steps: {mismatch}"


# scenes and references --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("text, message", [
    ("[run]\nstop_time = 1.0\nstep_size = 0.3\noutputs = ['WheelRig.creep']\n", "whole number of macro steps"),
    ("[run]\nstop_time = 1.0\nstep_size = 0.1\noutputs = ['WheelRig.creeep']\n", "WheelRig has no output 'creeep'"),
    ("[run]\nstop_time = 1.0\nstep_size = 0.1\noutputs = ['WheelRig.creep']\n[host]\nmass = 1.0\n",
     "WheelRig has no parameter 'mass' (parameters: wheel_radius"),
    ("[run]\nstop_time = 1.0\nstep_size = 0.1\noutputs = ['WheelRig.creep']\n[contact]\nfriction_law = 1.0\n",
     "friction_law = 1.0 must be of type int"),
    ("[run]\nstop_time = 1.0\nstep_size = 0.1\noutputs = ['WheelRig.creep']\n[contact]\npoisson_ratio = 0.6\n",
     "[contact]: poisson_ratio = 0.6 is out of range"),
    ("[run]\nstop_time = 1.0\nstep_size = 0.1\nalgorithm = 'euler'\noutputs = ['WheelRig.creep']\n",
     "algorithm = 'euler' is unknown: use one of gauss-seidel, jacobi"),
])
def test_bad_scene_files_are_refused_with_the_reason(tmp_path, text, message):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(CosimSceneError, match="bad.toml") as caught:
        load_cosim_scene(path)
    assert message in str(caught.value), f"error {caught.value} should say {message!r}"


@pytest.mark.parametrize("name", SCENE_NAMES)
def test_reference_files_record_their_provenance(name):
    scene = load_cosim_scene(name)
    values, header = read_reference(scene.reference_path)
    for key in ("command", "rollcontact", "git_commit", "master", "algorithm", "step_size", "date", "band"):
        assert header.get(key), f"{scene.reference_path.name}: provenance lacks {key!r}: {header}"
    assert float(header["step_size"]) == scene.step_size, "the reference was made with the scene's step"
    assert header["algorithm"] == scene.algorithm, "the reference was made with the scene's algorithm"
    assert values.dtype.names == ("time", *scene.outputs), "the reference records the scene's outputs"
    assert values.size == scene.steps // scene.band.stride + 1, "one row per stride communication points"


def test_reference_round_trip_and_band(tmp_path):
    t = np.linspace(0.0, 1.0, 201)
    values = np.empty(t.size, dtype=[("time", float), ("y", float)])
    values["time"], values["y"] = t, np.sin(2 * np.pi * 3 * t) + 0.1 / 3
    path = write_reference(tmp_path / "x_ref.csv", values, {"what": "test", "note": "a: b"})
    again, header = read_reference(path)
    assert header == {"what": "test", "note": "a: b"}, f"provenance must round-trip: {header}"
    assert_allclose(again["y"], values["y"], rtol=1e-11, atol=1e-14, err_msg="12 significant digits")
    band = Band(("y",))
    assert compare(again, values, band) == [], "a result equal to its reference passes"
    shifted = values.copy()
    shifted["y"] = values["y"] * 1.03
    assert compare(shifted, values, band), "a 3 % change must leave the 1 % band"


# co-simulation ----------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", SCENE_NAMES)
def test_scene_matches_its_reference(run, name):
    scene = load_cosim_scene(name)
    result = run(name)
    reference, header = read_reference(scene.reference_path)
    problems = compare(result.values, reference, scene.band)
    assert not problems, f"{name} against {scene.reference_path.name} ({header.get('date')}): {problems}"


@pytest.mark.parametrize("name, change", [
    ("carter_sanity", {"friction_coefficient": 0.3 * 1.05}),
    ("carter_sanity", {"poisson_ratio": 0.30}),
    ("traction_ramp", {"friction_coefficient": 0.35 * 1.05}),
    ("corrugated_rail", {"corrugation_amplitude": 25e-6}),
    ("oscillating_torque", {"transient": 0}),
])
def test_a_deliberate_change_of_the_physics_fails_the_reference(run, name, change):
    scene = load_cosim_scene(name)
    reference, _ = read_reference(scene.reference_path)
    problems = compare(run(name, contact=change).values, reference, scene.band)
    assert problems, f"{name} with {change} must leave the reference band"


@pytest.mark.parametrize("name", SCENE_NAMES)
def test_jacobi_agrees_with_gauss_seidel(run, name):
    """With force_lag following the algorithm both orderings stay within the band at the scene's step."""
    scene = load_cosim_scene(name)
    gauss_seidel, jacobi = run(name, algorithm="gauss-seidel"), run(name, algorithm="jacobi")
    assert jacobi.algorithm == "jacobi" and gauss_seidel.algorithm == "gauss-seidel", "algorithms as requested"
    assert not np.array_equal(jacobi.values[FORCE], gauss_seidel.values[FORCE]), "the two orderings differ at all"
    problems = compare(jacobi.values, gauss_seidel.values, scene.band)
    assert not problems, f"{name}: Jacobi leaves the band of Gauss-Seidel: {problems}"


def test_explicit_coupling_oscillates_where_linearly_implicit_matches_the_fine_run(run):
    """carter_sanity at H = 2 ms: |lambda| H ~ 3.9 > 2 for the explicit Gauss-Seidel loop (module
    rollcontact_cosim.wheel_rig), which ends in a limit cycle between the saturations; the linearly implicit
    host is within 1 % of a 0.1 ms run."""
    fine = run("carter_sanity", step_size=1e-4)
    implicit = run("carter_sanity", step_size=2e-3, host={"coupling": 1})
    explicit = run("carter_sanity", step_size=2e-3, host={"coupling": 0})
    assert deviation(implicit, fine) < 0.01, f"implicit deviates by {deviation(implicit, fine):.3g} of max T/N"
    assert not is_stable(explicit, fine), f"explicit should be unstable, deviates by {deviation(explicit, fine):.3g}"
    late = explicit.values[TRACTION][explicit.values["time"] > 0.3]
    assert np.ptp(late) > 0.3, f"explicit T/N must keep swinging (limit cycle), range {np.ptp(late):.3g}"


def test_carter_sanity_is_hertz_and_carter(run):
    """Row k pairs the contact's outputs with the creep they were evaluated at: T = Carter(xi), a = Hertz; the
    steady creep is the host's quasi-static one."""
    values = run("carter_sanity").values
    n_per_length = 98.1e3 / 0.02
    modulus = Material(210e9, 0.28).contact_modulus
    expected = np.array([carter(n_per_length, xi, 0.46, modulus, 0.3)[0] * 0.02 for xi in values[CREEP]])
    assert_allclose(values[FORCE], expected, rtol=1e-12, atol=1e-9, err_msg="T = Carter(xi) row by row")
    assert_allclose(values[f"{CONTACT}.contact_half_width"], hertz(n_per_length, 0.46, modulus)[0], rtol=1e-12,
                    err_msg="a = Hertz")
    v, xi = values[f"{HOST}.velocity"][-1], values[CREEP][-1]
    resistance = 100.0 + 5.0 * v + 0.5 * v * v
    # quasi-static: J omega' = M - r T and m v' = T - F_res with omega' r = (1 + xi) v'
    force = (7.25e3 + 150.0 * (1.0 + xi) * resistance / (1e4 * 0.46)) / (0.46 + 150.0 * (1.0 + xi) / (1e4 * 0.46))
    assert_allclose(values[FORCE][-1], force, rtol=1e-4, err_msg="steady traction of the torque balance")


def test_traction_ramp_passes_the_adhesion_maximum(run):
    result = run("traction_ramp")
    s = summarise(result)
    values = result.values
    assert 0.3 < s["peak_traction_coefficient"] < 0.35, f"peak adhesion below mu = 0.35: {s}"
    assert 2e-3 < s["creep_at_peak"] < 6e-3, f"peak near the Carter saturation creep mu a / R ~ 3.8e-3: {s}"
    assert values[CREEP][-1] > 0.03, f"beyond the maximum the wheel spins up to several % creep: {values[CREEP][-1]}"
    assert values[TRACTION][-1] < 0.8 * s["peak_traction_coefficient"], "falling friction lowers T/N after the peak"
    assert np.all(values[f"{CONTACT}.method_used"] == 2), "falling friction takes the polynomial method"


def test_a_refused_step_ends_the_run_with_the_reason(fmu_dir):
    result = run_cosimulation("carter_sanity", fmu_dir=fmu_dir, contact={"friction_coefficient": -1.0})
    assert not result.success, "a negative friction coefficient must stop the run"
    assert "RollingContact2D" in result.message and "friction_coefficient" in result.message, result.message
    assert result.values.size == 0 and result.steps == 0, "no complete row before the first refused step"


def test_main_job_prints_the_summary_and_writes_the_plot(fmu_dir, tmp_path, capsys):
    png = tmp_path / "carter.png"
    assert main_job(["carter_sanity", "--plot", str(png), "--fmu-dir", str(fmu_dir)]) == 0, "main job failed"
    out = capsys.readouterr().out
    assert "peak adhesion T/N = 0.15" in out and "500 macro steps" in out and "us per step" in out, out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", "the plot must be a PNG"


def test_main_job_writes_the_run_as_csv_with_units(fmu_dir, run, tmp_path, capsys):
    import csv

    path = tmp_path / "carter.csv"
    assert main_job(["carter_sanity", "--plot", str(tmp_path / "c.png"), "--csv", str(path),
                     "--fmu-dir", str(fmu_dir)]) == 0, "main job failed"
    assert f"csv: {path}" in capsys.readouterr().out
    with open(path, newline="") as fh:
        header, *rows = list(csv.reader(fh))
    expected = run("carter_sanity").values
    names = expected.dtype.names
    assert header[0] == "time [s]" and f"{FORCE} [N]" in header and f"{CREEP} [1]" in header and \
        f"{HOST}.velocity [m/s]" in header and f"{CONTACT}.contact_half_width [m]" in header, header
    assert [h.split(" [")[0] for h in header] == list(names), "one column per recorded variable, in order"
    table = np.genfromtxt(path, delimiter=",", skip_header=1)
    assert table.shape == (expected.size, len(names)) and len(rows) == expected.size
    for j, name in enumerate(names):
        assert np.array_equal(table[:, j], expected[name]), f"{name}: the CSV holds other values than the run"


def test_unknown_override_is_refused_with_the_choices(fmu_dir):
    with pytest.raises(KeyError, match="WheelRig has no parameter 'mass' \\(choices: wheel_radius"):
        run_cosimulation("carter_sanity", fmu_dir=fmu_dir, host={"mass": 1e4})


def test_every_invalid_wheel_rig_parameter_is_named_in_one_refusal():
    from rollcontact_cosim.wheel_rig import WheelRigError

    with pytest.raises(WheelRigError) as caught:
        WheelRigParameters(wheel_radius=0.0, vehicle_mass=-1.0, substeps=0)
    message = str(caught.value)
    for part in ("wheel_radius = 0.0 m is out of range", "vehicle_mass = -1.0 kg is out of range",
                 "substeps = 0 is out of range"):
        assert part in message, f"the refusal {message!r} must name {part!r}"
    with pytest.raises(WheelRigError, match="load_amplitude = 2.0 N is out of range: it must be <= static_load"):
        WheelRigParameters(static_load=1.0, load_amplitude=2.0, substeps=0)
