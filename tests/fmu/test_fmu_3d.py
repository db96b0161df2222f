"""The RollingContact3D FMU (FMI 2.0 and 3.0, one and several contacts) through fmpy: the library's answer bit for
bit on a varying signal, FMI 2.0 equal to FMI 3.0, an n-contact FMU equal to n single-contact FMUs, validation,
refusals that name the value, the limit and the contact, and a restored state that repeats the steps."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from contact_io import get_outputs, named, set_inputs, set_parameters
from fmpy.fmi1 import FMICallException
from fmu_checks import assert_fmu_is_valid

from rollcontact import EllipticScene, Material, solve_elliptic
from rollcontact.core.friction import Coulomb
from rollcontact.stepping.elliptic.model import EllipticModel
from rollcontact.stepping.elliptic.parameters import (
    METHOD_LEVELS as ELLIPTIC_LEVELS,
)
from rollcontact.stepping.elliptic.parameters import (
    EllipticOutputs,
    EllipticParameters,
)
from rollcontact_cosim.master import Slave

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ("normal_load", "longitudinal_creep", "lateral_creep", "spin", "velocity")
H = 1e-3
CONTACTS = 3  # the several-contact FMUs of the contact_variants fixture (tests/conftest.py)
CURVATURES = ((1.087, 1.667), (2.5, 1.2), (0.9, 4.0))  # A, B [1/m] per contact: a/b from about 0.5 to 1.6
DISCARD, ERROR = 2, 3


@pytest.fixture
def make(contact_variants):
    made = []

    def instance(fmi: int = 2, contacts: int = 1, initialise: bool = True, **parameters) -> Slave:
        name = "RollingContact3D" if contacts == 1 else f"RollingContact3D_{contacts}"
        slave = Slave(contact_variants[fmi] / f"{name}.fmu", f"{name}_{len(made)}")
        made.append(slave)
        set_parameters(slave, parameters)
        if initialise:
            slave.initialise()
        return slave

    yield instance
    for slave in made:
        slave.free()


def output_names(contacts: int) -> list[str]:
    return [named(n, k, contacts) for k in range(1, contacts + 1) for n in EllipticOutputs._fields]


def step(slave: Slave, t: float, rows, contacts: int = 1) -> list[float]:
    """Set every contact's inputs, step, read every contact's outputs (the integer as a float), contact by contact
    (FMI 2.0's ``name[k]`` or FMI 3.0's arrays)."""
    assert len(rows) == contacts
    set_inputs(slave, INPUTS, rows)
    slave.fmu.doStep(t, H)
    return get_outputs(slave, EllipticOutputs._fields, contacts)


def signal(n: int, k: int = 0) -> np.ndarray:
    """A varying input signal of contact ``k``: load, three creepages through saturation and back, speed."""
    t = np.arange(n) * H
    return np.column_stack([8e4 + 3e4 * np.sin(40 * t + k), 3e-3 * np.sin(25 * t + 0.3 * k),
                            -2e-3 * np.cos(31 * t + k), 0.4 * np.sin(17 * t - k), 30.0 + 5 * t])


def curvature_parameters(contacts: int, curvatures=CURVATURES) -> dict:
    return {named(name, k, contacts): curvatures[k - 1][i] for k in range(1, contacts + 1)
            for i, name in enumerate(("curvature_longitudinal", "curvature_lateral"))}


@pytest.mark.parametrize("fmi", (2, 3))
@pytest.mark.parametrize("method", (0, 1, 3))
def test_the_fmu_is_the_library_bit_for_bit(make, fmi, method):
    """Every output against solve_elliptic (forces, ellipse) and the stepping model (all of it), step by step."""
    slave = make(fmi, method=method)
    p = EllipticParameters(method=method)
    model = EllipticModel(p)
    name = "auto" if method == 0 else ELLIPTIC_LEVELS[method - 1].name
    A, B = p.curvature_longitudinal[0], p.curvature_lateral[0]
    for n, row in enumerate(signal(12)):
        got = step(slave, n * H, [row])
        expected = model.step(n * H, H, [row])[0]
        assert got == [float(v) for v in expected], f"step {n}: FMU {got} != model {expected}"
        result = solve_elliptic(EllipticScene(row[0], A, B, *row[1:4], Material(), Coulomb(0.3), row[4]), name,
                                budget=p.step_budget)
        assert got[:6] == [result.longitudinal_force, result.lateral_force, result.spin_moment, result.a, result.b,
                           result.max_pressure], f"step {n}: the FMU's forces and ellipse are solve_elliptic's"


@pytest.mark.parametrize("fmi", (2, 3))
def test_a_rail_condition_reaches_the_fmu_with_the_published_values(make, fmi):
    """``rail_condition`` = wet (strips: velocity-dependent friction) steps as the stepping model with Polach's wet
    mu_0, A, B given explicitly, whatever friction_* parameters are set beside it."""
    slave = make(fmi, rail_condition=2, method=3, friction_coefficient=0.8)
    model = EllipticModel(EllipticParameters(method=3, friction_law=1, friction_coefficient=0.3,
                                             friction_kinetic_ratio=0.4, friction_decay=0.2))
    rows = signal(3)
    rows[:, 3] = 0.0  # the strips take falling friction without spin
    for n, row in enumerate(rows):
        got, expected = step(slave, n * H, [row]), model.step(n * H, H, [row])[0]
        assert got == [float(v) for v in expected], f"step {n}: FMU {got} != the explicit wet law {expected}"


@pytest.mark.parametrize("contacts", (1, CONTACTS))
def test_fmi2_and_fmi3_give_the_same_outputs(make, contacts):
    rows = [signal(8, k) for k in range(contacts)]
    two, three = (make(fmi, contacts, jacobian=1, **curvature_parameters(contacts)) for fmi in (2, 3))
    for n in range(8):
        step_rows = [rows[k][n] for k in range(contacts)]
        assert step(two, n * H, step_rows, contacts) == step(three, n * H, step_rows, contacts), f"step {n}"


@pytest.mark.parametrize("fmi", (2, 3))
@pytest.mark.parametrize("method", (1, 2, 3))
def test_n_contacts_are_n_single_contact_fmus_bit_for_bit(make, fmi, method):
    rows = [signal(10, k) for k in range(CONTACTS)]
    several = make(fmi, CONTACTS, method=method, **curvature_parameters(CONTACTS))
    singles = [make(fmi, 1, method=method, **curvature_parameters(1, [CURVATURES[k]])) for k in range(CONTACTS)]
    width = len(EllipticOutputs._fields)
    for n in range(10):
        together = step(several, n * H, [rows[k][n] for k in range(CONTACTS)], CONTACTS)
        alone = [v for k in range(CONTACTS) for v in step(singles[k], n * H, [rows[k][n]])]
        assert together == alone, f"step {n}: contacts differ at outputs " \
            f"{[output_names(CONTACTS)[i] for i in range(CONTACTS * width) if together[i] != alone[i]]}"


@pytest.mark.parametrize("fmi", (2, 3))
def test_the_several_contact_fmu_validates(contact_variants, fmi):
    assert_fmu_is_valid(contact_variants[fmi] / f"RollingContact3D_{CONTACTS}.fmu", fmi)


def refused(slave: Slave, t: float, rows, contacts: int = 1, status: int = DISCARD) -> str:
    before = len(slave.log)
    with pytest.raises(FMICallException) as caught:
        step(slave, t, rows, contacts)
    assert caught.value.status == status, f"status {caught.value.status}, expected {status}"
    return " ".join(slave.log[before:])


@pytest.mark.parametrize("fmi", (2, 3))
def test_bad_inputs_are_refused_with_the_value_the_limit_and_the_contact(make, fmi):
    single = make(fmi)
    message = refused(single, 0.0, [(-1.0, 0.0, 0.0, 0.0, 20.0)])
    assert "normal_load = -1.0 N is out of range: it must be >= 0" in message, message
    message = refused(single, 0.0, [(1e5, math.nan, 0.0, 0.0, 20.0)])
    assert "longitudinal_creep = nan is not finite" in message, message
    several = make(fmi, CONTACTS, **curvature_parameters(CONTACTS))
    rows = [(1e5, 1e-3, 0.0, 0.0, 20.0), (1e5, 1e-3, 0.0, 0.0, 20.0), (-1.0, 1e-3, math.inf, 0.0, 20.0)]
    message = refused(several, 0.0, rows, CONTACTS)
    for part in ("contact 3: normal_load = -1.0 N is out of range", "contact 3: lateral_creep = inf"):
        assert part in message, message
    assert "contact 1" not in message and "contact 2" not in message, f"only contact 3 is named: {message}"
    good = step(several, 0.0, [rows[0]] * CONTACTS, CONTACTS)[:3]  # a refused step changes nothing
    assert good[0] > 0.0, good


@pytest.mark.parametrize("fmi", (2, 3))
def test_invalid_parameters_are_refused_all_at_once(make, fmi):
    slave = make(fmi, CONTACTS, youngs_modulus=-1.0, method=7,
                 **{**curvature_parameters(CONTACTS), "curvature_lateral[2]": 0.0})
    errors = " ".join(m for m in slave.log if m.startswith("Error: "))
    for part in ("youngs_modulus = -1.0 is out of range: it must be > 0", "method = 7 is out of range",
                 "curvature_lateral[2] = 0.0 1/m is out of range: it must be > 0"):
        assert part in errors, f"{part!r} not in {errors!r}"
    assert "invalid parameters" in refused(slave, 0.0, [(1e5, 0.0, 0.0, 0.0, 1.0)] * CONTACTS, CONTACTS)


@pytest.mark.parametrize("fmi", (2, 3))
def test_an_ellipse_outside_the_coefficient_table_is_refused_at_initialisation(make, fmi):
    slave = make(fmi, curvature_longitudinal=1.0, curvature_lateral=1e4, method=1)
    errors = " ".join(m for m in slave.log if m.startswith("Error: "))
    assert "the range of Kalker's creepage coefficients" in errors and "a/b = " in errors, errors


@pytest.mark.parametrize("fmi", (2, 3))
def test_a_restored_state_repeats_the_steps_bit_for_bit(make, fmi):
    slave = make(fmi, CONTACTS, **curvature_parameters(CONTACTS))
    rows = [signal(9, k) for k in range(CONTACTS)]
    for n in range(3):
        step(slave, n * H, [rows[k][n] for k in range(CONTACTS)], CONTACTS)
    state = slave.fmu.getFMUstate()
    data = bytes(slave.fmu.serializeFMUstate(state))
    first = [step(slave, n * H, [rows[k][n] for k in range(CONTACTS)], CONTACTS) for n in range(3, 9)]
    slave.fmu.setFMUstate(state)
    again = [step(slave, n * H, [rows[k][n] for k in range(CONTACTS)], CONTACTS) for n in range(3, 9)]
    slave.fmu.freeFMUstate(state)
    assert again == first, "setFMUstate: the steps repeat bit for bit"
    restored = slave.fmu.deSerializeFMUstate(data)
    slave.fmu.setFMUstate(restored)
    slave.fmu.freeFMUstate(restored)
    assert [step(slave, n * H, [rows[k][n] for k in range(CONTACTS)], CONTACTS) for n in range(3, 9)] == first, \
        "a serialised state: the steps repeat bit for bit"


def test_the_documented_variable_table_is_the_slave_table():
    import build_fmu

    assert build_fmu.variables_table("RollingContact3D") in (ROOT / "docs" / "fmu.md").read_text(), \
        "docs/fmu.md's RollingContact3D table differs from the slave's: run python build_fmu.py --docs"


def test_the_declared_bounds_are_the_library_checks():
    """Each parameter's declared min/max is accepted by EllipticParameters and the next value beyond is refused."""
    import build_fmu

    default = EllipticParameters()
    variables, _ = build_fmu.slave_module(build_fmu.FMUS["RollingContact3D"]).declaration()
    for name, kind, causality, _v, _u, start, lower, upper, _d in variables:
        if causality.name != "parameter" or name == "friction_table":
            continue
        per_contact = name.startswith("curvature")
        assert (getattr(default, name)[0] if per_contact else getattr(default, name)) == start, f"{name}: start"
        for bound, direction in ((lower, -math.inf), (upper, math.inf)):
            if bound is None:
                continue
            beyond = math.nextafter(bound, direction) if kind.__name__ == "Real" else bound + (
                1 if direction > 0 else -1)
            table = {"friction_table": "0 0.3"} if name == "friction_law" else {}
            wrap = (lambda v: (v,)) if per_contact else (lambda v: v)
            EllipticParameters(**{**default.__dict__, **table, name: wrap(bound)})
            with pytest.raises(ValueError):
                EllipticParameters(**{**default.__dict__, name: wrap(beyond)})


def test_a_contact_count_out_of_range_is_refused_with_the_limits(tmp_path):
    import build_fmu

    for contacts in (0, build_fmu.MAX_CONTACTS + 1, True):
        with pytest.raises(ValueError, match=f"from 1 to {build_fmu.MAX_CONTACTS}"):
            build_fmu.build("RollingContact3D", tmp_path, contacts=contacts)
    with pytest.raises(ValueError, match="FMI 2.0 build"):
        build_fmu.build("RollingContact3D", tmp_path, contacts=2, integer_codes=True, fmi=3)
    with pytest.raises(SystemExit):
        build_fmu.main(["--contacts", "0", "--dest", str(tmp_path)])


@pytest.mark.parametrize("model", ("RollingContact2D", "RollingContact3D"))
def test_fmi3_declares_each_per_contact_variable_once_as_an_array(contact_variants, model):
    """FMI 3.0's n-contact FMU: every variable of the FMI 2.0 twin named ``name[k]`` is one array ``name`` of n values
    (``<Dimension start="n"/>``, n start values), at the same place in the order; the shared parameters are scalars
    and equal."""
    from fmpy import read_model_description

    two, three = (read_model_description(str(contact_variants[fmi] / f"{model}_{CONTACTS}.fmu")) for fmi in (2, 3))
    arrays = [v for v in three.modelVariables if v.dimensions]
    scalars = {v.name: v for v in three.modelVariables if not v.dimensions and v.name != "time"}
    per_contact = list(dict.fromkeys(v.name.split("[")[0] for v in two.modelVariables if "[" in v.name))
    assert sorted(v.name for v in arrays) == sorted(per_contact), "the arrays are FMI 2.0's name[k] variables"
    assert [v.name for v in arrays] == per_contact, "in FMI 2.0's order of first appearance"
    for v in arrays:
        assert [d.start for d in v.dimensions] == [CONTACTS] and len(str(v.start).split()) == CONTACTS, \
            f"{v.name}: {CONTACTS} values, got dimensions {[d.start for d in v.dimensions]}, start {v.start!r}"
        first = next(w for w in two.modelVariables if w.name == f"{v.name}[1]")
        assert (v.causality, v.variability, v.unit) == (first.causality, first.variability, first.unit), v.name
    shared = {v.name: v for v in two.modelVariables if "[" not in v.name}
    assert set(scalars) == set(shared), f"shared variables: {set(scalars) ^ set(shared)}"
    for name, v in scalars.items():
        starts = (v.start, shared[name].start)
        same = starts[0] == starts[1] or (v.type == "Float64" and float(starts[0]) == float(starts[1]))
        assert v.causality == shared[name].causality and same, f"{name}: {v.causality} {starts}"


@pytest.mark.parametrize("model", ("RollingContact2D", "RollingContact3D"))
def test_fmi3_refuses_a_set_of_the_wrong_number_of_values_and_keeps_the_arrays(contact_variants, model):
    """An array takes exactly n values: a set of any other count is refused (emulated fmi3Error naming the counts),
    changes nothing, and every later step is discarded until a state is set."""
    slave = Slave(contact_variants[3] / f"{model}_{CONTACTS}.fmu", f"{model}_count")
    try:
        slave.initialise()
        load = slave.reference("normal_load")
        slave.fmu.setReal([load], [1e5] * CONTACTS)
        state = slave.fmu.getFMUstate()
        before = len(slave.log)
        slave.fmu.setReal([load], [2e5] * (CONTACTS - 1))
        errors = " ".join(m for m in slave.log[before:] if m.startswith("Error: "))
        assert f"setFloat64 of {CONTACTS - 1} values for the value references [{load}] refused: they take " \
               f"{CONTACTS} values" in errors, errors
        assert slave.fmu.getReal([load], CONTACTS) == [1e5] * CONTACTS, "the refused set changed nothing"
        with pytest.raises(FMICallException) as caught:
            slave.fmu.doStep(0.0, H)
        assert caught.value.status == DISCARD, caught.value.status
        slave.fmu.setFMUstate(state)
        slave.fmu.freeFMUstate(state)
        slave.fmu.doStep(0.0, H)
    finally:
        slave.free()


def test_fmi3_an_array_parameter_is_fixed_after_initialisation(contact_variants):
    """Setting a per-contact parameter array after initialisation: its values in force again change nothing, any
    other values are refused (emulated fmi3Error naming the array and the values in force) and steps are discarded."""
    slave = Slave(contact_variants[3] / f"RollingContact3D_{CONTACTS}.fmu", "RollingContact3D_fixed")
    try:
        set_parameters(slave, curvature_parameters(CONTACTS))
        slave.initialise()
        lateral = slave.reference("curvature_lateral")
        in_force = [CURVATURES[k][1] for k in range(CONTACTS)]
        assert slave.fmu.getReal([lateral], CONTACTS) == in_force
        before = len(slave.log)
        slave.fmu.setReal([lateral], in_force)
        assert not [m for m in slave.log[before:] if m.startswith("Error: ")], slave.log[before:]
        slave.fmu.setReal([lateral], [2.0] * CONTACTS)
        errors = " ".join(m for m in slave.log[before:] if m.startswith("Error: "))
        assert "set curvature_lateral = [2.0, 2.0, 2.0] refused: curvature_lateral is a fixed parameter" in errors \
            and f"the value in force stays {in_force!r}" in errors, errors
        assert slave.fmu.getReal([lateral], CONTACTS) == in_force, "the refused set changed nothing"
        with pytest.raises(FMICallException) as caught:
            step(slave, 0.0, [signal(1, k)[0] for k in range(CONTACTS)], CONTACTS)
        assert caught.value.status == DISCARD, caught.value.status
    finally:
        slave.free()


GAPS = ("gap_curvature_longitudinal", "gap_curvature_lateral")


@pytest.mark.parametrize("fmi", (2, 3))
@pytest.mark.parametrize("contacts", (1, CONTACTS))
def test_curvature_inputs_changing_every_step_are_fresh_instances_of_those_parameters(make, fmi, contacts):
    """The gap's curvatures set every step (0: the parameters') give the outputs of a new instance initialised with
    them as parameters, bit for bit, contact by contact; a curvature the coefficient table does not cover is refused
    naming the contact, and the instance steps on."""
    rng = np.random.default_rng(17)
    slave = make(fmi, contacts, **curvature_parameters(contacts))
    for n, row in enumerate(signal(3)):
        gaps = [(float(rng.choice([0.0, rng.uniform(0.6, 3.0)])), float(rng.uniform(0.6, 3.0)))
                for _ in range(contacts)]
        set_inputs(slave, GAPS, gaps)
        got = step(slave, n * H, [row] * contacts, contacts)
        fresh = make(fmi, contacts, **curvature_parameters(contacts, [
            (gap[0] or CURVATURES[k][0], gap[1]) for k, gap in enumerate(gaps)]))
        assert got == step(fresh, 0.0, [row] * contacts, contacts), f"step {n}: gaps {gaps}"
    set_inputs(slave, GAPS, [(1.0, 1e4)] * contacts)
    message = refused(slave, 3 * H, [signal(1)[0]] * contacts, contacts)
    assert f"{'contact 1: ' if contacts > 1 else ''}gap curvatures A = 1.0, B = 10000.0 1/m give a/b" in message, \
        message
    set_inputs(slave, GAPS, [(0.0, 0.0)] * contacts)
    assert step(slave, 3 * H, [signal(1)[0]] * contacts, contacts)[0] > 0.0, "the instance steps on"


@pytest.mark.parametrize("fmi", (2, 3))
def test_table_on_answers_from_the_certified_table_as_the_model_does(make, fmi, monkeypatch):
    """``table`` = on: the FMU's steps are the stepping model's, answered from the table (``method_used`` table), its
    derivatives with ``jacobian`` = difference.  The FMU runs in this process (fmpy loads its Python here): a small
    table put into the process's tables under the default key stands in for the default table's build."""
    from rollcontact.stepping.elliptic import table

    small = table.EllipticTable(0.28, (3, 5, 3, 3)).build()
    monkeypatch.setitem(table.TABLES, (0.28, table.NODES), small)
    slave = make(fmi, table=2, jacobian=1)
    model = EllipticModel(EllipticParameters(table=2, jacobian=1))
    for n, row in enumerate(signal(6)):
        got, expected = step(slave, n * H, [row]), model.step(n * H, H, [row])[0]
        assert got == [float(v) for v in expected], f"step {n}: FMU {got} != model {expected}"
        assert got[-1] == ELLIPTIC_LEVELS[-1].code and ELLIPTIC_LEVELS[-1].name == "table", "method_used: table"
