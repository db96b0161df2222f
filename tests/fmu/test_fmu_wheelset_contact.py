"""The WheelsetContact FMU (FMI 2.0 and 3.0) through fmpy: the stepping model bit for bit with the geometry table
and the library's wheel/rail solve bit for bit without it, FMI 2.0 equal to FMI 3.0, the carried profiles, refusals
with the value and the limit, a lifted wheel, and a restored state that repeats the steps (validation: with every
FMU in tests/fmu3/test_fmi3_fmu.py)."""

from __future__ import annotations

import math

import pytest
from fmpy.fmi1 import FMICallException

from rollcontact import Coulomb, Material
from rollcontact.stepping import WheelsetContactModel, WheelsetContactOutputs, WheelsetContactParameters
from rollcontact.stepping.wheelrail.parameters import INPUTS
from rollcontact.wheelrail import dispatch
from rollcontact.wheelrail.loads import WheelsetLoads, wheelset_loads
from rollcontact.wheelrail.normal import rigid_position
from rollcontact.wheelrail.scene import WheelRailScene
from rollcontact_cosim.master import Slave

H = 1e-3
V = 30.0
R0 = 0.46
Q = 8e4
RANGE = 0.008  # one table per test process (the model's cache: a Python host's FMU uses the host's rollcontact)
NAMES = tuple(name for name, _, _ in INPUTS)
INTEGERS = ("patches_left", "patches_right", "method_used")
DISCARD = 2


@pytest.fixture
def make(fmu_folders):
    made = []

    def instance(fmi: int = 2, initialise: bool = True, **parameters) -> Slave:
        slave = Slave(fmu_folders[fmi] / "WheelsetContact.fmu", f"WheelsetContact_{len(made)}")
        made.append(slave)
        slave.set_start_values({"table_range": RANGE, **parameters})
        if initialise:
            slave.initialise()
        return slave

    yield instance
    for slave in made:
        slave.free()


def step(slave: Slave, t: float, values) -> list[float]:
    """Set the inputs, step, read every output in WheelsetContactOutputs' order (the integers as floats)."""
    slave.fmu.setReal([slave.reference(n) for n in NAMES], [float(v) for v in values])
    slave.fmu.doStep(t, H)
    reals = [n for n in WheelsetContactOutputs._fields if n not in INTEGERS]
    got = dict(zip(reals, slave.fmu.getReal([slave.reference(n) for n in reals]), strict=True))
    got.update(zip(INTEGERS, (float(v) for v in slave.fmu.getInteger([slave.reference(n) for n in INTEGERS])),
                   strict=True))
    return [got[n] for n in WheelsetContactOutputs._fields]


def signal(n: int):
    return [(0.0055 * math.sin(0.6 * k + 0.3), 0.0015 * math.cos(0.4 * k), 0.04 * math.sin(k), 0.03 * math.cos(k),
             V + k, -(V + k) / R0, Q * (1 + 0.1 * math.sin(k)), Q) for k in range(n)]


@pytest.mark.parametrize("fmi", (2, 3))
def test_the_fmu_is_the_stepping_model_bit_for_bit(make, fmi):
    """With the geometry table (the default level: hertz with the saturated linear theory, through the table)."""
    slave = make(fmi)
    model = WheelsetContactModel(WheelsetContactParameters(table_range=RANGE))
    for n, values in enumerate(signal(10)):
        got = step(slave, n * H, values)
        assert got == [float(v) for v in model.step(n * H, H, values)], f"step {n}: FMU and model differ"


def test_without_the_table_the_fmu_is_the_librarys_solve_bit_for_bit(make):
    slave = make(2, geometry_table=0, jacobian=1)
    model = WheelsetContactModel(WheelsetContactParameters(geometry_table=0))
    for n, values in enumerate(signal(2)):
        got = step(slave, n * H, values)
        y, yaw, vy, rate, speed, pitch, left, right = values
        roll = rigid_position(model.track, model.wheelset, y, yaw)[0].roll
        scene = WheelRailScene(model.track, model.wheelset, y, yaw, roll, left, right, speed, vy, rate, pitch,
                               Material(), Coulomb(0.3))
        result = dispatch.solve(scene, "hertz", elliptic="saturated", budget=0.05)
        expected = wheelset_loads(scene, result)
        assert got[:len(WheelsetLoads._fields)] == [float(v) for v in expected], f"step {n}: not the library's loads"
        assert got[WheelsetContactOutputs._fields.index("roll")] == roll, f"step {n}: roll"


def test_fmi2_and_fmi3_give_the_same_outputs(make):
    two, three = make(2), make(3)
    for n, values in enumerate(signal(6)):
        assert step(two, n * H, values) == step(three, n * H, values), f"step {n}"


@pytest.mark.parametrize("fmi", (2, 3))
def test_the_carried_profiles_and_a_path_in_the_resources(make, fmi):
    """'' takes the S1002 and UIC60 in resources/profiles; a relative path is found in the resources folder."""
    carried, named = make(fmi), make(fmi, wheel_profile="profiles/MBench_S1002_v3.prw",
                                     rail_profile="profiles/MBench_UIC60_v3.ban")
    values = signal(1)[0]
    first, second = step(carried, 0.0, values), step(named, 0.0, values)
    assert first[:6] == pytest.approx(second[:6], rel=1e-6, abs=1e-3), "the Miniprof copy of the rail differs"


def refused(slave: Slave, t: float, values) -> str:
    before = len(slave.log)
    with pytest.raises(FMICallException) as caught:
        step(slave, t, values)
    assert caught.value.status == DISCARD, f"status {caught.value.status}, expected Discard"
    return " ".join(slave.log[before:])


@pytest.mark.parametrize("fmi", (2, 3))
def test_bad_inputs_and_a_lifted_wheel(make, fmi):
    slave = make(fmi)
    message = refused(slave, 0.0, (0.002, 0.0, 0.0, 0.0, V, -V / R0, -1.0, Q))
    assert "vertical_load_left = -1.0 N is out of range: it must be >= 0.0" in message, message
    message = refused(slave, 0.0, (0.0095, 0.0, 0.0, 0.0, V, -V / R0, Q, Q))
    assert "lateral_shift = 0.0095 m is outside the table's [-0.008, 0.008] m" in message, message
    lifted = step(slave, 0.0, (0.002, 0.0, 0.0, 0.0, V, -V / R0, Q, 0.0))
    out = dict(zip(WheelsetContactOutputs._fields, lifted, strict=True))
    assert out["normal_force_right"] == 0.0 and out["patches_right"] == 0.0 and out["normal_force_left"] > 0.0, out
    assert any("right wheel carries vertical_load_right = 0 N: lifted" in m for m in slave.log), slave.log[-3:]


@pytest.mark.parametrize("fmi", (2, 3))
def test_invalid_parameters_are_refused(make, fmi):
    slave = make(fmi, gauge=0.2, wheel_profile="no/such/profile.prw")
    errors = " ".join(m for m in slave.log if m.startswith("Error: "))
    assert "profile 'no/such/profile.prw' was not found" in errors, errors
    assert "invalid parameters" in refused(slave, 0.0, signal(1)[0])


@pytest.mark.parametrize("fmi", (2, 3))
def test_a_restored_state_repeats_the_steps_bit_for_bit(make, fmi):
    slave = make(fmi)
    rows = signal(8)
    for n in range(3):
        step(slave, n * H, rows[n])
    state = slave.fmu.getFMUstate()
    data = bytes(slave.fmu.serializeFMUstate(state))
    first = [step(slave, n * H, rows[n]) for n in range(3, 8)]
    slave.fmu.setFMUstate(state)
    slave.fmu.freeFMUstate(state)
    assert [step(slave, n * H, rows[n]) for n in range(3, 8)] == first, "setFMUstate: the steps repeat"
    restored = slave.fmu.deSerializeFMUstate(data)
    slave.fmu.setFMUstate(restored)
    slave.fmu.freeFMUstate(restored)
    assert [step(slave, n * H, rows[n]) for n in range(3, 8)] == first, "a serialised state: the steps repeat"
