"""The certified table of Coulomb friction on a corrugated surface (rollcontact.stepping.line.corrugation_table): its
bound at random points of the domain against independent exact solves, the symmetries it rests on, full slip, the
end of its domain and a contact that splits.  Its use by the stepping model: test_table.py."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rollcontact as rc
from rollcontact.stepping import ContactModel, ContactParameters
from rollcontact.stepping.line.corrugation_table import CorrugationTable
from rollcontact.stepping.line.tabulation import TARGET

WAVELENGTH, AMPLITUDE = 0.04, 20e-6
LOADS = (1e6 / 1.5, 1.5e6)


def new_table(wavelength: float = WAVELENGTH, amplitude: float = AMPLITUDE, loads=LOADS):
    model = ContactModel(ContactParameters(corrugation_wavelength=wavelength, corrugation_amplitude=amplitude))
    return CorrugationTable(lambda x, load, creep: model.scene_per_length(x, load, creep, 0.0), wavelength, loads,
                            model.radius, model.contact_modulus, model.mu), model


@pytest.fixture(scope="module")
def built():
    table, model = new_table()
    return table.build(), model


def test_the_bound_meets_the_target(built):
    table, _ = built
    assert table.ready and 0.0 < table.bound <= TARGET, f"bound {table.bound}"


@settings(max_examples=30, deadline=None, derandomize=True)
@given(x=st.floats(-0.1, 0.1), ell=st.floats(0.0, 1.0), v=st.floats(-2.0, 2.0))
def test_the_certified_bound_holds_at_random_points(built, x, ell, v):
    table, model = built
    load = LOADS[0] * (LOADS[1] / LOADS[0]) ** ell
    creep = v * model.mu * rc.hertz(load, model.radius, model.contact_modulus)[0] / model.radius
    exact = rc.solve(model.scene_per_length(x, load, creep, 0.0), method="polynomial", tolerance=1e-7)
    force, a, _, offset, p0, _ = table.evaluate(x, load, creep)
    limit = model.mu * load
    assert abs(force - exact.tangential_force_per_length) <= table.bound * limit, \
        f"X = {x}, N' = {load}, creep = {creep}: T' {force} against {exact.tangential_force_per_length}"
    assert abs(a / exact.contact_half_width - 1.0) <= table.bound, f"a {a} against {exact.contact_half_width}"
    assert abs(p0 / exact.max_pressure - 1.0) <= table.bound, f"p0 {p0} against {exact.max_pressure}"
    assert abs(offset - exact.contact_offset) <= table.bound * a, f"offset {offset} against {exact.contact_offset}"


def test_the_answer_is_periodic_in_the_axis_position_and_odd_in_the_creep(built):
    table, _ = built
    one = table.evaluate(0.0123, 1.1e6, 8e-4)
    later = table.evaluate(0.0123 + 3 * WAVELENGTH, 1.1e6, 8e-4)
    assert later == pytest.approx(one, rel=1e-9, abs=1e-15), "a wavelength on, the same contact"
    mirrored = table.evaluate(0.0123, 1.1e6, -8e-4)
    assert mirrored[0] == -one[0] and mirrored[1:] == one[1:], "T' odd in the creep, the rest even"


def test_full_slip_is_exact_and_the_domain_ends_at_its_loads(built):
    table, model = built
    force, _, stick, _, _, stiffness = table.evaluate(0.01, 1e6, -5e-3)
    assert (force, stick, stiffness) == (-model.mu * 1e6, 0.0, 0.0), "full slip: T' = -mu N', no stick zone"
    assert table.evaluate(0.01, LOADS[1] * 1.01, 1e-3) is None, "above N_high: no answer"
    assert table.evaluate(0.01, LOADS[0] / 1.01, 1e-3) is None, "below N_low: no answer"


def test_a_contact_that_splits_gives_the_table_up():
    table, _ = new_table(wavelength=0.01)  # at 10 mm the contact splits into two patches at some phases
    with pytest.raises(ArithmeticError, match="patches"):
        table.build()


def test_loads_must_be_an_interval_of_positive_loads():
    with pytest.raises(ValueError, match="N_low < N_high"):
        new_table(loads=(2e6, 1e6))
    with pytest.raises(ValueError, match="0 < N_low"):
        new_table(loads=(0.0, 1e6))


def test_the_table_is_a_deterministic_function_of_its_parameters(built):
    table, _ = built
    again = new_table()[0].build()
    assert again.data.tobytes() == table.data.tobytes() and again.bound == table.bound, "the same table, bit for bit"
    assert math.isfinite(again.bound)


def test_the_step_path_and_the_general_interpolant_agree_at_the_ends_and_between(built):
    table, _ = built
    for x in (0.0, 0.0137, 0.04 - 1e-17):
        at_end = table.evaluate(x, LOADS[0], 1e-3)  # l = 0: the general path
        inside = table.evaluate(x, LOADS[0] * (1.0 + 1e-13), 1e-3)  # the step's path
        assert inside == pytest.approx(at_end, rel=1e-9), f"X = {x}: {inside} against {at_end}"
        still = table.evaluate(x, 1.1e6, 0.0)
        moving = table.evaluate(x, 1.1e6, 1e-15)
        assert moving == pytest.approx(still, rel=1e-9, abs=1e-6), f"X = {x}: creep 0 against 1e-15 (T' ~ 4e-7 N/m)"


@pytest.mark.parametrize(("x", "creep"), [(0.0137, 8e-4), (0.031, -1.4e-3)])
def test_the_table_agrees_with_the_discretised_method_within_both_bounds(built, x, creep):
    table, model = built
    load = 1.1e6
    discretised = rc.solve(model.scene_per_length(x, load, creep, 0.0), method="discretised", tolerance=2e-3)
    tau = table.evaluate(x, load, creep)[0] / (model.mu * load)
    reference = discretised.tangential_force_per_length / (model.mu * load)
    allowed = table.bound + discretised.info["error_estimate"] * abs(reference)
    assert abs(tau - reference) <= allowed, f"X = {x}, creep = {creep}: tau {tau} against discretised {reference}"
