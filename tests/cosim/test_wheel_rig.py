"""The WheelRig host: its FMU (validation, refusals with the reason, state restore) and its model (exact
integration, the linearly implicit coupling and force_lag, the parameters' refusals)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.validation import validate_fmu
from numpy.testing import assert_allclose

from rollcontact_cosim.master import Slave
from rollcontact_cosim.wheel_rig import INPUT_NAMES, WheelRigModel, WheelRigOutputs, WheelRigParameters

DISCARD = 2


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
