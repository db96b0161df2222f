"""The certified table of falling friction on a flat surface (rollcontact.stepping.table): the scaling it rests on,
its bound at random points, the exact fallback outside it, state restore with a table in use, independence of
instances, and the incremental build of ``table`` = auto."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rollcontact as rc
from rollcontact.stepping import ContactModel, ContactParameters
from rollcontact.stepping import table as table_module
from rollcontact.stepping.table import FallingFrictionTable

MU, A, R = 0.3, 0.6, 0.46
E_STAR = rc.Material().contact_modulus
LAW = {"friction_law": 1, "friction_kinetic_ratio": A, "friction_decay": math.log(2.0) / 0.1}


@pytest.fixture(scope="module")
def table() -> FallingFrictionTable:
    return FallingFrictionTable(A, 1.5).build()


def normalised(load: float, u: float, w: float, decay: float) -> tuple[float, float, float]:
    a = rc.hertz(load, R, E_STAR)[0]
    saturation = MU * a / R
    scene = rc.Scene(load, creep=u * saturation, radius=R, friction=rc.ExponentialFalling(MU, A, decay),
                     rolling_speed=w / (decay * saturation))
    result = rc.solve(scene, method="polynomial", tolerance=1e-4)
    return (result.tangential_force_per_length / (MU * load), result.stick_half_width / a,
            result.creep_stiffness_per_length * saturation / (MU * load))


@pytest.mark.parametrize(("u", "w"), [(0.3, 0.4), (0.8, 1.2), (3.0, 0.7)])
def test_the_normalised_solution_depends_on_u_and_w_alone(u, w):
    one, other = normalised(1e6, u, w, 1.0), normalised(4e6, u, w, 7.0)
    assert one == pytest.approx(other, rel=1e-9, abs=1e-12), f"u = {u}, w = {w}: {one} against {other}"


@settings(max_examples=25, deadline=None, derandomize=True)
@given(u=st.floats(0.0, 12.0), w=st.floats(0.0, 1.5))
def test_the_certified_bound_holds_at_random_points(table, u, w):
    tau = table.evaluate(u, w)[0]
    exact = table.exact(u, w).tau
    assert abs(tau - exact) <= table.bound, f"u = {u}, w = {w}: |{tau} - {exact}| above the bound {table.bound:.3g}"


def test_the_bound_meets_the_target_and_the_domain_ends_at_w_max(table):
    assert table.ready and table.bound <= table_module.TARGET, f"bound {table.bound}"
    assert table.evaluate(0.5, 1.6) is None, "beyond w_max: no answer"


def test_steps_answer_from_the_table_within_its_bound_and_fall_back_outside_it():
    on = ContactModel(ContactParameters(**LAW, table=2))
    off = ContactModel(ContactParameters(**LAW, table=1))
    h, load = 1e-3, 3.1e6 * 0.02
    for k, (creep, speed) in enumerate([(1e-3, 45.0), (4e-4, 45.0), (1.5e-3, 40.0), (8e-4, 45.0)]):
        fast, exact = on.step(k * h, h, load, creep, speed), off.step(k * h, h, load, creep, speed)
        assert abs(fast.tangential_force - exact.tangential_force) <= 2e-3 * MU * load, (fast, exact)
        assert k == 0 or fast.method_used == 6, f"step {k} answers from the table: {fast}"
    w_max = on.table_use.table.w_max
    beyond = on.step(4 * h, h, load, 1e-3, 45.0 * 3.0 * w_max)  # w = B V xi_sat beyond the table
    assert beyond.method_used == 2, f"outside the domain the step solves exactly: {beyond}"


def test_restore_then_step_is_bit_identical_with_a_table_in_use():
    first = ContactModel(ContactParameters(**LAW, table=2))
    h, load = 1e-3, 6e4
    for k in range(3):
        first.step(k * h, h, load, 5e-4 + 1e-4 * k, 45.0)
    saved = first.get_state()
    assert saved.table_domain > 0.0, "the state records the table in use"
    ahead = [first.step((3 + k) * h, h, load, 9e-4 - 1e-4 * k, 45.0) for k in range(3)]
    second = ContactModel(ContactParameters(**LAW, table=2))
    second.set_state(type(saved).from_bytes(saved.to_bytes()))
    again = [second.step((3 + k) * h, h, load, 9e-4 - 1e-4 * k, 45.0) for k in range(3)]
    assert again == ahead, "a fresh model restored into the state repeats the steps bit for bit"


def test_two_instances_with_different_tables_stay_independent():
    one = ContactModel(ContactParameters(**LAW, table=2))
    other = ContactModel(ContactParameters(**{**LAW, "friction_kinetic_ratio": 0.3}, table=2))
    h, load = 1e-3, 6e4
    outs = [(one.step(k * h, h, load, 1.2e-3, 45.0), other.step(k * h, h, load, 1.2e-3, 45.0)) for k in range(3)]
    assert one.table_use.table is not other.table_use.table, "each model has its own table"
    assert outs[-1][0].tangential_force != outs[-1][1].tangential_force, "different laws, different forces"
    alone = ContactModel(ContactParameters(**LAW, table=2))
    assert [alone.step(k * h, h, load, 1.2e-3, 45.0) for k in range(3)] == [o for o, _ in outs], \
        "a model's outputs do not depend on another instance"


def test_auto_builds_across_exact_steps_after_they_have_paid_for_it(monkeypatch):
    monkeypatch.setattr(table_module, "NODE_COUNT", 3)
    model = ContactModel(ContactParameters(**LAW, table=0, step_budget=0.01))
    h, load = 1e-3, 6e4
    used, ready_at = [], None
    for k in range(3000):
        out = model.step(k * h, h, load, 5e-4 + 1e-4 * math.sin(k), 45.0)
        used.append(out.method_used)
        if out.method_used == 6:
            ready_at = k
            break
    assert ready_at is not None and ready_at > 10, f"the table is built over many steps, ready at step {ready_at}"
    assert set(used[:-1]) == {2}, "until it is ready the steps solve exactly"
