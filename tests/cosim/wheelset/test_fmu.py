"""The Wheelset host FMU (FMI 2.0) through fmpy: it equals the library model bit for bit in a Gauss-Seidel loop
with an in-process creep-force law, validates, and restores its state."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmpy.validation import validate_fmu

from rollcontact_cosim.master import Slave
from rollcontact_cosim.wheelset import SaturatedKalkerLaw, WheelsetParameters, linear_law, simulate

ROOT = Path(__file__).resolve().parents[3]
FORCES = ("longitudinal_force", "lateral_force", "spin_moment")
CREEPAGES = ("longitudinal_creep", "lateral_creep", "spin")
JACOBIAN = tuple(f"d{f}_d{c}" for f in ("Fx", "Fy", "Mz") for c in ("xi", "eta", "phi"))
STATES = ("lateral_displacement", "yaw_angle", "lateral_velocity", "yaw_rate")


@pytest.fixture(scope="module")
def fmu(tmp_path_factory) -> Path:
    dest = tmp_path_factory.mktemp("wheelset_fmu")
    done = subprocess.run([sys.executable, str(ROOT / "build_fmu.py"), "--only", "Wheelset", "--dest", str(dest)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, f"build_fmu.py --only Wheelset failed:\n{done.stdout}\n{done.stderr}"
    return dest / "Wheelset.fmu"


def started(fmu: Path, name: str, **parameters) -> Slave:
    slave = Slave(fmu, name)
    slave.set_start_values(parameters)
    slave.initialise()
    return slave


def gauss_seidel(slave: Slave, law, p: WheelsetParameters, steps: int, h: float, jacobi: bool = False) -> np.ndarray:
    """The law in place of a two-contact FMU: read the creepages, set forces and Jacobians, step; the states.
    ``jacobi``: the law sees the creepages of the previous communication point (zero forces in the first step)."""
    creep_refs = [slave.reference(f"{c}[{k}]") for k in (1, 2) for c in CREEPAGES]
    input_refs = [slave.reference(f"{f}[{k}]") for k in (1, 2) for f in FORCES] + \
                 [slave.reference(f"{j}[{k}]") for k in (1, 2) for j in JACOBIAN]
    state_refs = [slave.reference(s) for s in STATES]
    states = [slave.fmu.getReal(state_refs)]
    previous = None
    for n in range(steps):
        c = np.reshape(slave.fmu.getReal(creep_refs), (2, 3))
        if jacobi:
            c, previous = previous, c
        if c is None:
            forces, jacobians = [0.0] * 6, [0.0] * 18
        else:
            forces = [v for k in range(2) for v in law(p.normal_load, *c[k], p.speed)]
            jacobians = [float(v) for k in range(2) for v in law.jacobian(p.normal_load, *c[k], p.speed).ravel()]
        slave.fmu.setReal(input_refs, forces + jacobians)
        slave.fmu.doStep(n * h, h)
        states.append(slave.fmu.getReal(state_refs))
    return np.array(states)


def test_the_fmu_validates(fmu):
    assert validate_fmu(str(fmu)) == [], "fmpy validate"


@pytest.mark.parametrize(("saturated", "jacobi"), [(False, False), (True, False), (True, True)],
                         ids=["linear", "saturated", "saturated-jacobi"])
def test_the_fmu_in_a_master_loop_equals_the_library_run(fmu, saturated, jacobi):
    p = WheelsetParameters(speed=70.0, initial_lateral_displacement=2e-3, force_lag=int(jacobi))
    law = SaturatedKalkerLaw(linear_law(p)) if saturated else linear_law(p)
    slave = started(fmu, f"ws{int(saturated)}{int(jacobi)}", speed=70.0, initial_lateral_displacement=2e-3,
                    force_lag=int(jacobi))
    try:
        states = gauss_seidel(slave, law, p, 200, 1e-3, jacobi)
    finally:
        slave.free()
    _, expected = simulate(p, law, 0.2, 1e-3, jacobi=jacobi)
    assert np.array_equal(states, expected), f"FMU against the library: max difference " \
                                             f"{np.max(np.abs(states - expected))}"


def test_a_restored_state_repeats_the_steps(fmu):
    p = WheelsetParameters()
    law = linear_law(p)
    slave = started(fmu, "restore")
    try:
        gauss_seidel(slave, law, p, 10, 1e-3)
        saved = slave.fmu.getFMUstate()
        first = gauss_seidel(slave, law, p, 0, 1e-3)  # the states at the save point
        slave.fmu.doStep(10e-3, 1e-3)
        after = slave.fmu.getReal([slave.reference(s) for s in STATES])
        slave.fmu.setFMUstate(saved)
        assert slave.fmu.getReal([slave.reference(s) for s in STATES]) == list(first[0]), "outputs restored"
        slave.fmu.doStep(10e-3, 1e-3)
        assert slave.fmu.getReal([slave.reference(s) for s in STATES]) == after, "the same step, the same bits"
        slave.fmu.freeFMUstate(saved)
    finally:
        slave.free()


def test_a_malformed_model_state_is_refused_and_the_instance_keeps_its_own(fmu):
    import hashlib
    import json

    slave = started(fmu, "refuse")
    try:
        slave.fmu.doStep(0.0, 1e-3)
        good = slave.fmu.getFMUstate()
        data = bytes(slave.fmu.serializeFMUstate(good))
        before = slave.fmu.getReal([slave.reference(s) for s in STATES])
        state = json.loads(data)
        state.pop("sha256")
        state["model"]["yaw_rate"] = "fast"
        text = json.dumps(state, sort_keys=True)  # canonical_json of the shared slave
        state["sha256"] = hashlib.sha256(text.encode()).hexdigest()  # a valid checksum: the content is refused
        bad = slave.fmu.deSerializeFMUstate(json.dumps(state).encode())
        slave.fmu.setFMUstate(bad)
        assert any("yaw_rate = 'fast'" in line for line in slave.log), f"the reason names the field: {slave.log}"
        assert slave.fmu.getReal([slave.reference(s) for s in STATES]) == before, "the refused state changes nothing"
        slave.fmu.freeFMUstate(good)
        slave.fmu.freeFMUstate(bad)
    finally:
        slave.free()
