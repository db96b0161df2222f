"""When the elliptic stepping model answers from the certified table of the strips
(rollcontact.stepping.elliptic.table_use): its outputs, the contacts together, the tolerance, the rules of building
(on, auto with and without the run's end, within the step budget), the state, and the Jacobian's meaning."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rollcontact import EllipticScene, Material
from rollcontact.core.friction import Coulomb
from rollcontact.elliptic.creep_coefficients import creepage_coefficients
from rollcontact.elliptic.methods.strips import METHOD as STRIPS
from rollcontact.stepping import ModelError
from rollcontact.stepping.elliptic import table as table_module
from rollcontact.stepping.elliptic.model import EllipticModel, EllipticState
from rollcontact.stepping.elliptic.parameters import LEVEL_CODES, EllipticParameters
from rollcontact.stepping.elliptic.table_use import strips_largest_error

TINY = (3, 5, 3, 3)
"""Node counts of the tables of these tests: a few hundred strips solves (a coarse table, its bound large)."""
H = 1e-3
ROW = (1e5, 1e-3, -5e-4, 0.2, 30.0)
STRIPS_STEP = STRIPS.accuracy.cost(EllipticScene(1.0, 1.087, 1.667, spin_creepage=1.0), {})
"""The strips' modelled cost of a step of ROW (with spin) [s]: what a budget leaves the build beyond it."""
CURVATURES = {"curvature_longitudinal": (1.087, 2.5, 0.9), "curvature_lateral": (1.667, 1.2, 4.0)}


def model(**parameters) -> EllipticModel:
    options = {key: parameters.pop(key) for key in ("stop_time",) if key in parameters}
    return EllipticModel(EllipticParameters(**parameters), table_nodes=TINY, **options)


def rows(rng, n: int) -> list[tuple]:
    return [(float(rng.choice([0.0, rng.uniform(1e4, 2e5)])), *rng.normal(0.0, 2e-3, 2),
             float(rng.choice([0.0, rng.normal(0.0, 0.5)])), 25.0) for _ in range(n)]


def test_table_on_builds_at_initialisation_and_answers_every_loaded_contact():
    m = model(table=2)
    assert m.state.table_batches == len(m.table_use.sizes) and m.table_use.ready is not None, "built"
    assert any("table: ready" in notice for notice in m.notices), m.notices
    out = m.step(0.0, H, [ROW])[0]
    assert out.method_used == LEVEL_CODES["table"], "method_used says table"
    exact = model(table=1).step(0.0, H, [ROW])[0]
    assert out[3:6] == exact[3:6], "the ellipse is Hertz's, as the exact levels give it"
    assert out[8:17] == exact[8:17], "jacobian = linear: the linear theory's slopes, as at every level"
    assert out.stick_fraction == -1.0 and out.frictional_power == ROW[4] * (ROW[1] * out[0] + ROW[2] * out[1] +
                                                                           ROW[3] * out[2])
    default = EllipticParameters()
    scene = EllipticScene(ROW[0], default.curvature_longitudinal[0], default.curvature_lateral[0], *ROW[1:4],
                          Material(), Coulomb(0.3))
    h = scene.hertz
    c = creepage_coefficients(h.aspect_ratio, 0.28)
    k = scene.shear_modulus * h.c**2 / (0.3 * ROW[0])
    tau = m.table_use.ready.answer(math.log(h.aspect_ratio), k * c.c11 * ROW[1], k * c.c22 * ROW[2],
                                   k * (c.c23 * h.c + 0.5 * c.c11 * h.b) * ROW[3], False)
    limit = 0.3 * ROW[0]
    assert np.allclose(out[:3], (tau[0] * limit, tau[1] * limit, tau[2] * limit * h.c), rtol=1e-12, atol=0.0), \
        "the forces are the table's normalised answer times mu Fn (mu Fn c)"
    bound = m.table_use.ready.bound + strips_largest_error(0.28)
    assert all(abs(a - b) <= bound * limit * s for a, b, s in zip(out[:3], exact[:3], (1, 1, h.c), strict=True)), \
        "within the table's bound and the strips' error of the exact step"
    assert m.step(H, H, [(0.0, *ROW[1:])])[0].method_used == 0, "no load, no contact"


@pytest.mark.parametrize("jacobian", (0, 1))
def test_the_contacts_on_the_table_are_each_contact_alone_bit_for_bit(jacobian):
    """Every subset of unloaded contacts of three, curvatures changing: the step of all three is each contact's own
    model, bit for bit."""
    rng = np.random.default_rng(3)
    together = model(table=2, jacobian=jacobian, **CURVATURES)
    alone = [model(table=2, jacobian=jacobian, curvature_longitudinal=(A,), curvature_lateral=(B,))
             for A, B in zip(*CURVATURES.values(), strict=True)]
    for mask in range(8):
        step = rows(rng, 3)
        step = [(0.0, *row[1:]) if mask >> k & 1 else row for k, row in enumerate(step)]
        gaps = [(float(rng.choice([0.0, rng.uniform(0.6, 3.0)])), 0.0) for _ in range(3)]
        got = together.step(mask * H, H, [(*row, *gap) for row, gap in zip(step, gaps, strict=True)])
        assert got == tuple(m.step(mask * H, H, [(*row, *gap)])[0]
                            for m, row, gap in zip(alone, step, gaps, strict=True)), f"unloaded {mask:03b}"
        assert all(o.method_used in (0, LEVEL_CODES["table"]) for o in got)


def test_the_table_answers_where_its_bound_meets_the_tolerance():
    bound = model(table=2).table_use.ready.bound + strips_largest_error(0.28)
    assert model(table=2, tolerance=1.01 * bound).step(0.0, H, [ROW])[0].method_used == LEVEL_CODES["table"]
    tight = model(table=2, tolerance=0.99 * bound)
    assert tight.step(0.0, H, [ROW])[0].method_used != LEVEL_CODES["table"], "a tighter tolerance solves exactly"


def test_the_difference_jacobian_of_a_table_step_is_the_tables_derivative():
    """jacobian = difference on the table: central differences of the table's own forces."""
    m = model(table=2, jacobian=1)
    out = m.step(0.0, H, [ROW])[0]
    plain = model(table=2)
    row = list(ROW)
    for j, step in enumerate((1e-8, 1e-8, 1e-6)):
        up, down = list(row), list(row)
        up[1 + j] += step
        down[1 + j] -= step
        difference = (np.array(plain.step(0.0, H, [up])[0][:3]) - np.array(plain.step(0.0, H, [down])[0][:3])) / (
            2 * step)
        column = np.array(out[8:17]).reshape(3, 3)[:, j]
        assert np.allclose(difference, column, rtol=1e-5, atol=1e-9 * np.abs(column).max()), \
            f"column {j}: {difference} != {column}"


def test_no_table_without_its_level():
    for parameters in ({"table": 1}, {"table": 2, "method": 1}, {"table": 2, "rail_condition": 1}):
        assert model(**parameters).table_use is None, f"{parameters}: no table"


def test_auto_with_the_runs_end_known_builds_at_once_where_the_steps_left_pay_for_it():
    long = model(stop_time=1e6)
    first = long.step(0.0, H, [ROW])[0]
    assert first.method_used == LEVEL_CODES["strips"], "the step that decides solves exactly"
    assert any("table: building" in m for m in long.take_messages())
    assert long.step(H, H, [ROW])[0].method_used == LEVEL_CODES["table"], "built within the first step's budget"
    short = model(stop_time=0.01)
    assert all(short.step(n * H, H, [ROW])[0].method_used == LEVEL_CODES["strips"] for n in range(5))
    assert sum("steps remain" in m for m in short.take_messages()) == 1, "said once"


def test_auto_without_the_runs_end_builds_once_the_exact_steps_have_cost_as_much():
    m = model()
    cost = m.table_use.cost
    n = 0
    while m.step(n * H, H, [ROW])[0].method_used != LEVEL_CODES["table"]:
        n += 1
        assert n < 10_000, "the table takes over"
    assert m.state.exact_work >= cost, f"the exact steps paid {m.state.exact_work:.3g} s of the build's {cost:.3g} s"


def test_a_budget_spreads_the_build_over_the_steps_and_none_too_small_builds_nothing():
    sizes = model().table_use.sizes
    spread = model(stop_time=1e6, step_budget=table_module.SOLVE_COST * max(sizes) * 2 + STRIPS_STEP)
    steps = 0
    while spread.step(steps * H, H, [ROW])[0].method_used != LEVEL_CODES["table"]:
        steps += 1
    assert steps > len(sizes) // 3, f"a few batches per step: ready after {steps} steps of {len(sizes)} batches"
    starved = model(stop_time=1e6, step_budget=STRIPS_STEP)
    assert all(starved.step(n * H, H, [ROW])[0].method_used != LEVEL_CODES["table"] for n in range(5))
    assert sum("leaves no room" in m for m in starved.take_messages()) == 1, "said once"


def test_a_restored_state_repeats_the_steps_through_the_build_and_after():
    m = model(stop_time=1e6, step_budget=table_module.SOLVE_COST * 40 + STRIPS_STEP)
    rng = np.random.default_rng(4)
    signal = [[(1e5 * (1 + 0.1 * math.sin(n)), *rng.normal(0.0, 2e-3, 2), 0.3, 20.0)] for n in range(40)]
    m.step(0.0, H, signal[0])
    saved = EllipticState.parse(m.get_state().to_dict())
    first = [m.step(n * H, H, signal[n]) for n in range(1, 40)]
    assert {o[0].method_used for o in first} == {LEVEL_CODES["strips"], LEVEL_CODES["table"]}, "through the build"
    fresh = model(stop_time=1e6, step_budget=table_module.SOLVE_COST * 40 + STRIPS_STEP)
    fresh.set_state(saved)
    assert [fresh.step(n * H, H, signal[n]) for n in range(1, 40)] == first, "a new model from the state"
    with pytest.raises(ModelError, match="exceeds the table's"):
        fresh.set_state(EllipticState(0.0, 0, 10**6))
    with pytest.raises(ModelError, match="has no table"):
        model(table=1).set_state(EllipticState(0.0, 0, 3))
    assert EllipticState.parse({"version": 1, "time": 0.5, "steps": 2}) == EllipticState(0.5, 2), "version 1"
