"""RollingContact2D with several contacts per instance (``build_fmu.py --contacts n``) through fmpy: n contacts equal
n single-contact FMUs bit for bit (closed form, polynomial on a corrugation, instationary auto, certified tables of
falling friction evaluated together; each contact with its own radius, width and place along the track), FMI 2.0
equals FMI 3.0, validation, refusals that name the contact and change nothing, and a restored state that repeats the
steps."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from contact_io import get_outputs, set_inputs, set_parameters
from fmpy.fmi1 import FMICallException
from fmu_checks import assert_fmu_is_valid

import rollcontact
from rollcontact.stepping import StepOutputs
from rollcontact_cosim.master import Slave

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ("normal_load", "creep", "velocity")
H = 1e-3
CONTACTS = 3  # the several-contact FMUs of the contact_variants fixture (tests/conftest.py)
DISCARD = 2


@pytest.fixture
def make(contact_variants):
    made = []

    def instance(fmi: int = 2, contacts: int = 1, **parameters) -> Slave:
        name = "RollingContact2D" if contacts == 1 else f"RollingContact2D_{contacts}"
        slave = Slave(contact_variants[fmi] / f"{name}.fmu", f"{name}_{len(made)}")
        made.append(slave)
        set_parameters(slave, parameters)
        slave.initialise()
        return slave

    yield instance
    for slave in made:
        slave.free()


def step(slave: Slave, t: float, rows, contacts: int = 1) -> list[float]:
    """Set every contact's inputs, step, read every contact's outputs contact by contact (FMI 2.0's ``name[k]`` or
    FMI 3.0's arrays)."""
    assert len(rows) == contacts
    set_inputs(slave, INPUTS, rows)
    slave.fmu.doStep(t, H)
    return get_outputs(slave, StepOutputs._fields, contacts)


def signal(n: int, k: int) -> list[tuple[float, float, float]]:
    t = np.arange(n) * H
    return list(zip(2e4 * (1 + 0.2 * np.sin(30 * t + k)), 2e-3 * np.sin(50 * t + 2 * k), 20.0 + 3 * k + 0 * t,
                    strict=True))


CASES = {"closed form": ({}, 12), "instationary auto": ({"transient": 1}, 12)}
if "polynomial" in rollcontact.METHODS:
    CASES["polynomial, corrugated"] = ({"method": 2, "corrugation_amplitude": 20e-6}, 4)
    CASES["falling friction, certified tables"] = ({"friction_law": 1, "friction_kinetic_ratio": 0.4,
                                                    "friction_decay": 0.6, "tolerance": 1e-3, "table": 2}, 8)


GEOMETRY = ({"radius": 0.46, "contact_width": 0.02, "initial_position": 0.0},
            {"radius": 0.43, "contact_width": 0.025, "initial_position": 2.5},
            {"radius": 0.46, "contact_width": 0.02, "initial_position": 17.013})
"""Each contact's own geometry and place along the track (the parameters ``radius[k]`` ... of the n-contact FMU)."""


OWN = {f"{name}[{k + 1}]": value for k, geometry in enumerate(GEOMETRY) for name, value in geometry.items()}
""":data:`GEOMETRY` as the n-contact FMU's parameters (FMI 3.0: the elements of the arrays ``radius`` ...)."""


@pytest.mark.parametrize("fmi", (2, 3))
@pytest.mark.parametrize("case", list(CASES))
def test_n_contacts_are_n_single_contact_fmus_bit_for_bit(make, case, fmi):
    parameters, steps = CASES[case]
    rows = [signal(steps, k) for k in range(CONTACTS)]
    several = make(fmi, CONTACTS, **parameters, **OWN)
    singles = [make(fmi, 1, **parameters, **GEOMETRY[k]) for k in range(CONTACTS)]
    for n in range(steps):
        together = step(several, n * H, [rows[k][n] for k in range(CONTACTS)], CONTACTS)
        alone = [v for k in range(CONTACTS) for v in step(singles[k], n * H, [rows[k][n]])]
        assert together == alone, f"{case}, step {n}"


def test_fmi2_and_fmi3_give_the_same_outputs(make):
    rows = [signal(8, k) for k in range(CONTACTS)]
    two, three = make(2, CONTACTS, transient=1, **OWN), make(3, CONTACTS, transient=1, **OWN)
    for n in range(8):
        step_rows = [rows[k][n] for k in range(CONTACTS)]
        assert step(two, n * H, step_rows, CONTACTS) == step(three, n * H, step_rows, CONTACTS), f"step {n}"


@pytest.mark.parametrize("fmi", (2, 3))
def test_the_several_contact_fmu_validates(contact_variants, fmi):
    assert_fmu_is_valid(contact_variants[fmi] / f"RollingContact2D_{CONTACTS}.fmu", fmi)


@pytest.mark.parametrize("fmi", (2, 3))
def test_a_refusal_names_the_contact_and_changes_no_contact(make, fmi):
    slave = make(fmi, CONTACTS, transient=1)
    good = [(2e4, 1e-3, 20.0)] * CONTACTS
    first = step(slave, 0.0, good, CONTACTS)
    before = len(slave.log)
    with pytest.raises(FMICallException) as caught:
        step(slave, H, [good[0], (-5.0, math.nan, 20.0), good[2]], CONTACTS)
    assert caught.value.status == DISCARD
    message = " ".join(slave.log[before:])
    assert "contact 2: normal_load = -5.0 N is out of range" in message, message
    assert "contact 1:" not in message and "contact 3:" not in message, message
    reference = make(fmi, CONTACTS, transient=1)
    assert step(reference, 0.0, good, CONTACTS) == first
    assert step(slave, H, good, CONTACTS) == step(reference, H, good, CONTACTS), "the refused step changed nothing"


@pytest.mark.parametrize("fmi", (2, 3))
def test_a_restored_state_repeats_the_steps_bit_for_bit(make, fmi):
    slave = make(fmi, CONTACTS, transient=1)
    rows = [signal(10, k) for k in range(CONTACTS)]
    for n in range(4):
        step(slave, n * H, [rows[k][n] for k in range(CONTACTS)], CONTACTS)
    state = slave.fmu.getFMUstate()
    data = bytes(slave.fmu.serializeFMUstate(state))
    first = [step(slave, n * H, [rows[k][n] for k in range(CONTACTS)], CONTACTS) for n in range(4, 10)]
    slave.fmu.setFMUstate(state)
    slave.fmu.freeFMUstate(state)
    assert [step(slave, n * H, [rows[k][n] for k in range(CONTACTS)], CONTACTS) for n in range(4, 10)] == first
    restored = slave.fmu.deSerializeFMUstate(data)
    slave.fmu.setFMUstate(restored)
    slave.fmu.freeFMUstate(restored)
    assert [step(slave, n * H, [rows[k][n] for k in range(CONTACTS)], CONTACTS) for n in range(4, 10)] == first


def test_an_invalid_per_contact_parameter_is_named_with_its_contact(make):
    slave = make(2, CONTACTS, **{"radius[2]": -1.0, "contact_width[3]": 0.0})
    errors = " ".join(m for m in slave.log if m.startswith("Error: "))
    for part in ("contact 2: radius = -1.0", "contact 3: contact_width = 0.0"):
        assert part in errors, errors
