"""The stepping model's use of the certified tables (rollcontact.stepping.line.table), for both families (falling
friction on a flat rail, a one-harmonic corrugation with Coulomb friction): steps within the bound, the exact fallback
outside the domain, state restore with a table in use, independent instances, the incremental build of ``table`` = auto,
the rebuild over a wider domain, the log, and a family the exact solver cannot tabulate."""

from __future__ import annotations

import math

import pytest

import rollcontact as rc
from rollcontact.stepping import ContactModel, ContactParameters, ModelError, ModelState
from rollcontact.stepping.line.table import CorrugationUse, FallingFrictionUse

H = 1e-3
FAMILIES = {  # parameters, speed V [m/s], load N [N] (contact width 0.02 m), creeps, a step outside the domain
    "falling friction": ({"friction_law": 1, "friction_kinetic_ratio": 0.6, "friction_decay": math.log(2.0) / 0.1},
                         45.0, 3.1e6 * 0.02, (1e-3, 4e-4, 1.5e-3, 8e-4), {"velocity": 45.0 * 20.0}),
    "corrugation": ({"corrugation_amplitude": 20e-6, "corrugation_wavelength": 0.04}, 30.0, 1e6 * 0.02,
                    (1.1e-3, 4e-4, 2.1e-3, -8e-4), {"normal_load": 1e6 * 0.02 * 2.0}),
}


def inputs(family: str, k: int) -> dict:
    """The k-th step's inputs of a family's run: a new load (+-5 %) and creep at every step."""
    _, speed, load, creeps, _ = FAMILIES[family]
    return {"normal_load": load * (1.0 + 0.05 * math.sin(0.37 * k)), "creep": creeps[k % len(creeps)],
            "velocity": speed}


def step(model: ContactModel, k: int, **kwargs):
    return model.step(k * H, H, kwargs["normal_load"], kwargs["creep"], kwargs["velocity"])


@pytest.mark.parametrize("family", FAMILIES)
def test_steps_answer_from_the_table_within_its_bound_and_fall_back_outside_it(family):
    parameters, *_, beyond = FAMILIES[family]
    model = ContactModel(ContactParameters(**parameters, table=2))
    for k in range(8):
        out = step(model, k, **inputs(family, k))
        assert k == 0 or out.method_used == 6, f"step {k} answers from the table: {out}"
        given = inputs(family, k)
        exact = rc.solve(model.scene(out.axis_position, given["normal_load"], given["creep"], given["velocity"]),
                         method="polynomial", tolerance=1e-7)
        limit = model.mu * given["normal_load"]
        error = abs(out.tangential_force - exact.tangential_force_per_length * 0.02) / limit
        assert error <= model.table_use.table.bound + 1e-12, f"step {k}: error {error:.3g} mu N above the bound"
    outside = step(model, 8, **{**inputs(family, 8), **beyond})
    assert outside.method_used == 2, f"outside the domain the step solves exactly: {outside}"


@pytest.mark.parametrize("family", FAMILIES)
def test_restore_then_step_is_bit_identical_with_a_table_in_use(family):
    parameters = FAMILIES[family][0]
    first = ContactModel(ContactParameters(**parameters, table=2))
    for k in range(3):
        step(first, k, **inputs(family, k))
    saved = first.get_state()
    assert saved.table_domain == first.table_use.table.domain != (), "the state records the table in use"
    ahead = [step(first, k, **inputs(family, k)) for k in range(3, 7)]
    second = ContactModel(ContactParameters(**parameters, table=2))
    second.set_state(ModelState.parse(saved.to_dict()))
    again = [step(second, k, **inputs(family, k)) for k in range(3, 7)]
    assert again == ahead, "a fresh model restored into the state repeats the steps bit for bit"
    assert {o.method_used for o in again} == {6}, "from the table"


@pytest.mark.parametrize(("family", "other"), [("falling friction", {"friction_kinetic_ratio": 0.3}),
                                                ("corrugation", {"corrugation_amplitude": 10e-6})])
def test_two_instances_with_different_tables_stay_independent(family, other):
    parameters = FAMILIES[family][0]
    one = ContactModel(ContactParameters(**parameters, table=2))
    two = ContactModel(ContactParameters(**{**parameters, **other}, table=2))
    outs = [(step(one, k, **inputs(family, k)), step(two, k, **inputs(family, k))) for k in range(4)]
    assert one.table_use.table is not two.table_use.table, "each model has its own table"
    assert outs[-1][0].tangential_force != outs[-1][1].tangential_force, "different scenes, different forces"
    alone = ContactModel(ContactParameters(**parameters, table=2))
    assert [step(alone, k, **inputs(family, k)) for k in range(4)] == [o for o, _ in outs], \
        "a model's outputs do not depend on another instance"


@pytest.mark.parametrize(("family", "use"), [("falling friction", FallingFrictionUse), ("corrugation", CorrugationUse)])
def test_auto_builds_across_exact_steps_after_they_have_paid_for_it(monkeypatch, family, use):
    monkeypatch.setattr(use, "expected_solves", 3)
    budget = 0.02
    model = ContactModel(ContactParameters(**FAMILIES[family][0], table=0, step_budget=budget))
    used, ready_at = [], None
    for k in range(5000):
        out = step(model, k, **inputs(family, k))
        used.append(out.method_used)
        if out.method_used == 6:
            ready_at = k
            break
    solves = model.table_use.table.solves
    most_per_step = budget / use.solve_cost
    assert ready_at is not None and ready_at >= solves / most_per_step, \
        f"the table is built over many steps, at most {most_per_step:.0f} solves each: ready at step {ready_at}"
    assert set(used[:-1]) == {2}, "until it is ready the steps solve exactly"
    log = " | ".join(model.take_messages())
    assert "building a certified table" in log and "within step_budget" in log, log
    assert "ready over" in log and "exact solves (modelled" in log and "bytes, certified to" in log, log


@pytest.mark.parametrize("family", FAMILIES)
def test_outputs_are_the_same_however_fast_the_machine_solves(monkeypatch, family):
    """table = auto over a run that builds its table, once as it is and once with every exact solve delayed (a slow
    or loaded machine): the same outputs bit for bit, the table taking over at the same step."""
    import dataclasses
    import time

    from rollcontact.line import dispatch

    monkeypatch.setattr(FallingFrictionUse, "expected_solves", 5)
    monkeypatch.setattr(CorrugationUse, "expected_solves", 5)

    def run():
        model = ContactModel(ContactParameters(**FAMILIES[family][0], table=0, step_budget=0.05))
        outs = []
        for k in range(2000):
            outs.append(step(model, k, **inputs(family, k)))
            if [o.method_used for o in outs[-8:]] == [6] * 8:
                break
        return outs

    fast = run()
    spec = dispatch.METHODS["polynomial"]

    def slow(scene, **options):
        time.sleep(2e-4)
        return spec.function(scene, **options)

    slow.options = spec.function.options
    monkeypatch.setitem(dispatch.METHODS, "polynomial", dataclasses.replace(spec, function=slow))
    delayed = run()
    assert [o.method_used for o in fast].count(6) > 5, "the run reaches the table"
    assert delayed == fast, "the same inputs give the same outputs on a slower machine"


def test_a_step_budget_without_room_for_the_build_says_so_and_stays_exact(monkeypatch):
    monkeypatch.setattr(CorrugationUse, "expected_solves", 3)
    model = ContactModel(ContactParameters(**FAMILIES["corrugation"][0], table=0, step_budget=2e-4))
    used = {step(model, k, **inputs("corrugation", k)).method_used for k in range(30)}
    log = " | ".join(model.take_messages())
    assert used == {2}, f"exact steps: {used}"
    assert "leaves no room for the table's exact solves" in log and "table = on" in log, log


def test_steps_outside_the_domain_pay_for_a_table_over_the_wider_domain(monkeypatch):
    monkeypatch.setattr(CorrugationUse, "expected_solves", 3)
    parameters, *_ = FAMILIES["corrugation"]
    model = ContactModel(ContactParameters(**parameters, table=2))
    step(model, 0, **inputs("corrugation", 0))
    low, high = model.table_use.table.domain
    heavy = {**inputs("corrugation", 1), "normal_load": 2.0 * high * 0.02}
    used = []
    for k in range(1, 400):
        used.append(step(model, k, **{**heavy, "creep": 1e-3 + 1e-4 * math.sin(k)}).method_used)
        if used[-1] == 6:
            break
    assert used[-1] == 6 and len(used) > 4, f"the wider table is built within the budget over the steps: {used}"
    assert set(used[:-1]) == {2}, "outside the domain: exact steps, while they pay for the wider table"
    assert model.table_use.domain[1] > 2.0 * high and model.table_use.domain[0] == low, model.table_use.domain
    assert step(model, 500, **inputs("corrugation", 5)).method_used == 6, "and it answers where the first one did"


def test_a_family_the_solver_cannot_tabulate_stays_exact_and_says_why():
    model = ContactModel(ContactParameters(corrugation_amplitude=20e-6, corrugation_wavelength=0.01, table=2))
    outs = [step(model, k, **inputs("corrugation", k)) for k in range(3)]
    assert {o.method_used for o in outs} == {2}, "exact steps"
    log = " | ".join(model.take_messages())
    assert "no certified table" in log and "patches" in log, log
    assert model.get_state().table_domain == ()


def test_a_state_from_before_corrugation_tables_and_a_foreign_domain():
    parameters, *_ = FAMILIES["falling friction"]
    model = ContactModel(ContactParameters(**parameters, table=2))
    step(model, 0, **inputs("falling friction", 0))
    data = model.get_state().to_dict()
    old = {**data, "version": 4, "table_domain": data["table_domain"][0]}
    assert ModelState.parse(old).table_domain == tuple(data["table_domain"]), "version 4: w_max as one real"
    assert ModelState.parse({**old, "table_domain": 0.0}).table_domain == (), "version 4: 0 for none"
    with pytest.raises(ModelError, match="not a domain of this model's table"):
        model.set_state(ModelState.parse({**data, "table_domain": [1e5, 2e5]}))
    for bad in ([1.0, 2.0, 3.0], [-1.0], ["1"], [math.nan]):
        with pytest.raises(ModelError, match="table_domain"):
            ModelState.parse({**data, "table_domain": bad})


@pytest.mark.parametrize(("steps", "builds"), [(20000, True), (300, False)])
def test_a_known_end_builds_at_once_where_the_run_pays_and_never_where_it_does_not(steps, builds):
    model = ContactModel(ContactParameters(**FAMILIES["corrugation"][0], table=0, step_budget=0.005),
                         stop_time=steps * H)
    used = [step(model, k, **inputs("corrugation", k)).method_used for k in range(300)]
    log = " | ".join(model.take_messages())
    if builds:
        assert used[-1] == 6 and used.index(6) < CorrugationUse.expected_solves / 4, \
            f"the build starts at the first step, ready at step {used.index(6) if 6 in used else None}"
        assert "building a certified table" in log, log
    else:
        assert set(used) == {2} and "300 steps remain, fewer than the" in log, log
    unknown = ContactModel(ContactParameters(**FAMILIES["corrugation"][0], table=0), stop_time=-1.0)
    assert unknown.stop_time is None, "a stop time before the start is no known end"


def test_a_state_whose_table_cannot_be_built_is_refused_and_the_model_stays_as_it_was():
    model = ContactModel(ContactParameters(corrugation_amplitude=20e-6, corrugation_wavelength=0.01, table=1))
    before = step(model, 0, **inputs("corrugation", 0))
    crafted = model.get_state().to_dict()
    crafted["table_domain"] = [1e5, 2e5]
    other = ContactModel(ContactParameters(corrugation_amplitude=20e-6, corrugation_wavelength=0.01, table=2))
    step(other, 0, **inputs("corrugation", 0))
    kept = other.get_state()
    with pytest.raises(ModelError, match="its table cannot be built .*patches"):
        other.set_state(ModelState.parse(crafted))
    assert other.get_state() == kept, "the refused state changed nothing"
    assert step(other, 1, **inputs("corrugation", 1)).method_used == 2 and before.method_used == 2


def test_every_build_and_domain_is_bounded(monkeypatch):
    from rollcontact.stepping.line import falling_table

    monkeypatch.setattr(falling_table.FallingFrictionTable, "max_solves", 40)
    with pytest.raises(ArithmeticError, match="within 40 exact solves"):
        falling_table.FallingFrictionTable(0.6, 1.0).build()
    parameters = FAMILIES["falling friction"][0]
    model = ContactModel(ContactParameters(**parameters, table=2))
    step(model, 0, **inputs("falling friction", 0))
    data = model.get_state().to_dict()
    with pytest.raises(ModelError, match="not a domain of this model's table"):
        model.set_state(ModelState.parse({**data, "table_domain": [falling_table.W_LIMIT * 1.5]}))
    model.table_use.w_seen = 100.0  # steps far beyond: the next table stops at the limit of the kinetic ratio
    limit = falling_table.w_limit(parameters["friction_kinetic_ratio"])
    assert model.table_use.wanted_domain() == (limit,), "the domain stops at w_limit(A)"
    assert limit == min(falling_table.W_LIMIT, falling_table.FALL_LIMIT / (1.0 - 0.6)), limit


def test_a_node_that_does_not_converge_within_its_steps_gives_the_build_up(monkeypatch):
    from rollcontact.stepping.line import falling_table

    monkeypatch.setattr(falling_table, "NODE_ITERATIONS", 1)
    table = falling_table.FallingFrictionTable(0.6, 1.0)
    with pytest.raises(ArithmeticError, match="did not converge in"):
        table.build()
    assert table.solves < 20, f"given up at the first node that needs more steps, after {table.solves} solves"
