"""The wheelset on profiles (rollcontact_cosim.wheelset: the host's ``contact_model`` = profiles, the scene
``wheelset_hunting_profiles``, the study's measures): the host's step is the trapezoidal rule on linear loads, a cone
contact through the profile path reproduces the linear scene's critical speed, the co-simulation through fmpy is the
in-process run bit for bit and through libcosim the Jacobi run, the scene's renamed connections, and the study's
reading of a limit cycle."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rollcontact.stepping import WheelsetContactModel, WheelsetContactParameters
from rollcontact_cosim.master import run_cosimulation
from rollcontact_cosim.scenes import CosimSceneError, load_cosim_scene, pairs
from rollcontact_cosim.wheelset import WheelsetParameters, linear_law
from rollcontact_cosim.wheelset.model import (
    LOAD_INPUTS,
    OUTPUT_NAMES,
    TRACK_OUTPUTS,
    WheelsetError,
    WheelsetModel,
    creepages,
    simulate_profiles,
)
from rollcontact_cosim.wheelset.profiles import SCENE, Linearisation, analyse, scene_models
from rollcontact_cosim.wheelset.stability import critical_speed, klingel_wavelength
from rollcontact_cosim.wheelset.study import decay_rate, zero_crossing

RANGE = {"table_range": 0.008}  # the tests' geometry table (one build per process)


def test_a_profile_step_is_the_trapezoidal_rule_on_linear_loads():
    """Loads linear in the state, F_y = J_F q and M_z = J_M q (q = -s, track axes): one step is
    ``(I - hW/2)^-1 (I + hW/2) s`` with W the host's linear system, W[2:] = (J - suspension) / (m, I)."""
    p = WheelsetParameters(contact_model=1, lateral_damping=300.0, yaw_damping=50.0)
    model = WheelsetModel(p)
    jf, jm = np.array([-2e6, 1.5e7, -4e5, -6e4]), np.array([-1.6e6, 1.7e6, -5e4, -3e5])
    s = model.state.vector
    q = -s
    loads = [jf @ q, jm @ q, *jf, *jm]
    h = 2e-3
    w = np.zeros((4, 4))
    w[0, 2] = w[1, 3] = 1.0
    w[2] = jf / p.mass
    w[3] = jm / p.yaw_inertia
    w[2, 0] -= p.lateral_stiffness / p.mass
    w[2, 2] -= p.lateral_damping / p.mass
    w[3, 1] -= p.yaw_stiffness / p.yaw_inertia
    w[3, 3] -= p.yaw_damping / p.yaw_inertia
    expected = np.linalg.solve(np.eye(4) - 0.5 * h * w, (np.eye(4) + 0.5 * h * w) @ s)
    np.testing.assert_allclose(model.step_profiles(0.0, h, loads), expected, rtol=1e-12, atol=1e-18,
                               err_msg="not the trapezoidal rule on the linear loads")
    outputs = dict(zip(OUTPUT_NAMES, model.outputs(), strict=True))
    assert outputs["lateral_shift"] == -outputs["lateral_displacement"] and outputs["yaw"] == -outputs["yaw_angle"]
    assert outputs["pitch_rate"] == -p.speed / p.rolling_radius, "pure rolling at r0"
    with pytest.raises(WheelsetError, match="set contact_model = 1"):
        WheelsetModel(WheelsetParameters()).step_profiles(0.0, h, loads)
    with pytest.raises(WheelsetError, match="loads must be 10 finite numbers"):
        model.step_profiles(h, h, loads[:9])


class ConeContact:
    """The cone wheelset's two contacts with a linear law as one contact of the profile path: the host's force and
    moment in track axes (``force_y = -F``, ``moment_yaw = -M``) and their derivatives by central differences in the
    track state, from the inputs a WheelsetContact takes."""

    def __init__(self, parameters: WheelsetParameters, law):
        self.model, self.law = WheelsetModel(dataclasses.replace(parameters, contact_model=0)), law

    def loads(self, q) -> np.ndarray:
        s = -np.asarray(q, dtype=float)
        p = self.model.parameters
        c = creepages(p, s)
        forces = np.array([self.law(p.normal_load, *c[k], p.speed) for k in range(2)])
        rhs = self.model.rhs(s, forces)  # accelerations with the suspension: take it back out
        force = rhs[2] * p.mass + p.lateral_stiffness * s[0] + p.lateral_damping * s[2]
        moment = rhs[3] * p.yaw_inertia + p.yaw_stiffness * s[1] + p.yaw_damping * s[3]
        return np.array([-force, -moment])

    def step(self, t, h, inputs):
        q = np.array(inputs[:4])
        steps = np.array([1e-7, 1e-7, 1e-5, 1e-5])
        columns = [(self.loads(q + d) - self.loads(q - d)) / (2 * d.sum()) for d in np.diag(steps)]
        out = dict(zip(("force_y", "moment_yaw"), self.loads(q), strict=True))
        out.update({name: columns[j][i] for i, load in enumerate(("force_y", "moment_yaw"))
                    for j, name in enumerate(n for n in LOAD_INPUTS if n.startswith(f"d{load}"))})
        return type("Loads", (), out)


def test_the_cone_through_the_profile_path_has_the_linear_scenes_critical_speed():
    """The linear scene's wheelset (cones, Kalker's linear law) through the host's profile path: the decay rate of y
    crosses zero within 1 % of the eigenvalues' critical speed, as through the cone path."""
    p = WheelsetParameters(contact_model=1)
    law = linear_law(p)
    predicted = critical_speed(p, law)
    rates = []
    speeds = (0.97 * predicted, 1.03 * predicted)
    for speed in speeds:
        q = dataclasses.replace(p, speed=speed)
        period = klingel_wavelength(q) / speed
        step = period / 200
        times, states = simulate_profiles(q, ConeContact(q, law), 12 * 200 * step, step)
        rates.append(decay_rate(times, states[:, 0], start=2 * period, limit=0.01)[0])
    assert rates[0] < 0.0 < rates[1], f"decay rates {rates} at {speeds} m/s"
    crossing = zero_crossing(speeds, rates)
    assert abs(crossing / predicted - 1) < 0.01, f"zero crossing {crossing} m/s, eigenvalues {predicted} m/s"


def test_the_scene_connects_the_track_velocities_by_rename():
    scene = load_cosim_scene(SCENE)
    links = dict(scene.system.connections)
    assert links["Wheelset.track_lateral_velocity"] == "WheelsetContact.lateral_velocity", links
    assert links["Wheelset.track_yaw_rate"] == "WheelsetContact.yaw_rate", links
    assert links["WheelsetContact.dmoment_yaw_dyaw_rate"] == "Wheelset.dmoment_yaw_dyaw_rate", links
    assert len(links) == len(TRACK_OUTPUTS) + len(LOAD_INPUTS), "8 connections to the contact, 10 back"
    assert pairs(["a", "b -> c"], 2) == (("a[1]", "a[1]"), ("a[2]", "a[2]"), ("b[1]", "c[1]"), ("b[2]", "c[2]"))
    bad = scene.path.read_text().replace('"track_yaw_rate -> yaw_rate"', '"track_yaw_rate -> spin"')
    path = scene.path.parent / "wheelset_hunting_profiles_bad.toml"
    try:
        path.write_text(bad)
        with pytest.raises(CosimSceneError, match="WheelsetContact has no input 'spin'"):
            load_cosim_scene(path)
    finally:
        path.unlink()


def in_process(stop_time: float, jacobi: bool = False):
    host, contact = scene_models(RANGE)
    host = dataclasses.replace(host, force_lag=int(jacobi))
    return simulate_profiles(host, contact, stop_time, 1e-3, jacobi=jacobi)


def test_through_fmpy_the_cosimulation_is_the_in_process_run_bit_for_bit(fmu_folders):
    result = run_cosimulation(SCENE, stop_time=0.15, contact=RANGE, fmu_dir=fmu_folders[2], build=False)
    assert result.success, result.message
    times, states = in_process(0.15)
    assert np.array_equal(result.values["time"], times), "times"
    for k, name in enumerate(("lateral_displacement", "yaw_angle", "lateral_velocity", "yaw_rate")):
        assert np.array_equal(result.values[f"Wheelset.{name}"], states[:, k]), f"{name} differs"


def test_through_libcosim_the_cosimulation_is_the_jacobi_run(tmp_path):
    pytest.importorskip("libcosimpy")
    result = run_cosimulation(SCENE, master="libcosim", stop_time=0.1, contact=RANGE, fmu_dir=tmp_path)
    assert result.success, result.message
    _, states = in_process(0.1, jacobi=True)
    np.testing.assert_allclose(result.values["Wheelset.lateral_displacement"], states[:, 0], rtol=1e-9, atol=1e-15,
                               err_msg="libcosim's run is not the in-process Jacobi run")


def test_the_studys_reading_of_a_run():
    """A steady oscillation is a limit cycle of its amplitude and frequency; a decaying one is none; the growth rate
    is the fitted slope of log |y|."""
    times = np.arange(0.0, 10.0, 1e-3)
    steady = analyse(50.0, 5e-4, times, 1.2e-3 * np.sin(2 * math.pi * 7.0 * times))
    assert steady.amplitude == pytest.approx(1.2e-3, rel=1e-3) and steady.frequency == pytest.approx(7.0, rel=1e-3)
    growing = 5e-4 * np.exp(0.3 * times) * np.sin(2 * math.pi * 5.0 * times)
    assert analyse(50.0, 5e-4, times, growing).growth == pytest.approx(0.3, rel=2e-2), "growth rate"
    decaying = 5e-4 * np.exp(-0.05 * times) * np.sin(2 * math.pi * 5.0 * times)
    run = analyse(30.0, 5e-4, times, decaying)
    assert run.amplitude == 0.0 and run.final > 0.0 and run.growth < 0.0, run


def test_the_equivalent_linearisation():
    """At the small start the cone of the equivalent conicity, stiffened by the contact angles' change, has a
    critical speed between the unstiffened cone's and the flange's; the free wheelset's wavelength at the start is
    Klingel's (model: WheelsetContactModel.equivalent_conicity)."""
    host, contact = scene_models(RANGE)
    linear = Linearisation(host, contact)
    assert linear.gravitational_stiffness(5e-4) > 0.0, "the contact angles' change stiffens laterally"
    stiffened = linear.critical_speed(5e-4)
    bare = critical_speed(dataclasses.replace(linear.parameters(5e-4), lateral_stiffness=host.lateral_stiffness),
                          linear.law)
    assert bare < stiffened < 80.0, f"critical speeds {bare}, {stiffened} m/s"
    assert isinstance(contact, WheelsetContactModel) and contact.parameters == WheelsetContactParameters(
        **{**load_cosim_scene(SCENE).contact_parameters(), **RANGE}), "the scene's contact"
