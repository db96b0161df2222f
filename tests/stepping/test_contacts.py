"""Several 2D contacts stepped together (rollcontact.stepping.contacts): each contact is a single ContactModel bit
for bit, invalid inputs are named with their contact, and a contact that fails after others were stepped sets them
back, so a refused step changes no contact."""

from __future__ import annotations

import math

import pytest

from rollcontact.stepping import ContactModel, ContactParameters, ModelError
from rollcontact.stepping.contacts import ContactModels, ContactsState

H = 1e-3


def rows(n: int) -> list[tuple[float, float, float]]:
    return [(2e4 * (1 + 0.1 * k + 0.05 * math.sin(n)), 1e-3 * math.cos(n + k), 20.0 + k) for k in range(3)]


@pytest.mark.parametrize("parameters", ({}, {"transient": 1}), ids=("closed form", "instationary auto"))
def test_each_contact_is_a_single_contact_model_bit_for_bit(parameters):
    p = ContactParameters(**parameters)
    together = ContactModels(p, 3)
    alone = [ContactModel(p) for _ in range(3)]
    for n in range(20):
        assert together.step(n * H, H, rows(n)) == tuple(m.step(n * H, H, *r) for m, r in zip(alone, rows(n),
                                                                                               strict=True)), n


def test_a_contact_that_fails_after_others_were_stepped_sets_them_back():
    models = ContactModels(ContactParameters(), 3)
    models.step(0.0, H, rows(0))
    before = ContactsState.parse(models.state.to_dict(), 3)
    bad = rows(1)
    bad[2] = (1.7e308, 1e-3, 20.0)  # finite, but beyond the largest load per length a step represents
    with pytest.raises(ModelError, match="contact 3: normal_load = 1.7e"):
        models.step(H, H, bad)
    assert models.state.to_dict() == before.to_dict(), "the contacts stepped before the failure are set back"
    with pytest.raises(ModelError) as caught:
        models.step(H, H, [rows(1)[0], (-1.0, math.nan, 20.0), rows(1)[2]])
    assert "contact 2: normal_load = -1.0 N" in str(caught.value) and "contact 1" not in str(caught.value)


def test_a_state_of_the_wrong_contact_count_or_a_bad_contact_state_is_refused():
    data = ContactModels(ContactParameters(), 2).state.to_dict()
    with pytest.raises(ModelError, match="holds 3 contact states"):
        ContactsState.parse(data, 3)
    data["contacts"][1]["steps"] = -1
    with pytest.raises(ModelError, match="contact 2: "):
        ContactsState.parse(data, 2)


def edge_rows(n: int) -> list[tuple[float, float, float]]:
    """Rows through the closed form's branches: no load, a load below what floating point resolves, full slip of
    either sign (where T = mu N can round past the bound and is corrected), stick and slip, speed zero."""
    return [(0.0 if n % 4 == 0 else 2e4 * (1 + 0.3 * math.sin(n)), 0.2 * math.sin(0.7 * n), 20.0),
            (1e-310 if n % 3 == 0 else 3.3e4, -1e-3 * (n % 5), 0.0 if n % 2 else 31.0),
            (12345.678 + n, 0.05 * math.cos(n), 25.0 + n)]


def test_the_closed_form_loop_is_each_contact_model_bit_for_bit():
    """ContactModels steps closed-form contacts in one loop (together); every output and every state field is the
    single ContactModel's, through all the closed form's branches, with each contact's own radius and width."""
    p = ContactParameters(method=1)
    per_contact = {"radius": (0.46, 0.3, 0.5), "contact_width": (0.02, 0.015, 0.03)}
    together = ContactModels(p, 3, per_contact=per_contact)
    assert together.together, "closed-form contacts take the loop"
    assert not ContactModels(ContactParameters(transient=1), 2).together, "instationary contacts do not"
    alone = [ContactModel(ContactParameters(method=1, radius=r, contact_width=w))
             for r, w in zip(*per_contact.values(), strict=True)]
    for n in range(40):
        expected = tuple(m.step(n * H, H, *r) for m, r in zip(alone, edge_rows(n), strict=True))
        assert together.step(n * H, H, edge_rows(n)) == expected, f"step {n}"
        assert together.state.to_dict() == ContactsState(tuple(m.state for m in alone)).to_dict(), f"state {n}"


def test_the_closed_form_loop_refuses_time_going_back_as_a_contact_does_and_changes_nothing():
    models = ContactModels(ContactParameters(), 2)
    models.step(0.0, H, rows(0)[:2])
    models.step(H, H, rows(1)[:2])
    before = models.state.to_dict()
    single = ContactModel(ContactParameters())
    single.step(H, H, *rows(1)[0])
    with pytest.raises(ModelError) as expected:
        single.step(0.0, H, *rows(2)[0])
    with pytest.raises(ModelError) as caught:
        models.step(0.0, H, rows(2)[:2])
    assert str(caught.value) == f"contact 1: {expected.value}", str(caught.value)
    assert models.state.to_dict() == before, "a refused step changes no contact"


@pytest.mark.parametrize(("surface", "beyond"), (
    ({"friction_law": 1, "friction_kinetic_ratio": 0.6, "friction_decay": 7.0}, (2e4, 1e-3, 45.0 * 20.0)),
    ({"corrugation_amplitude": 20e-6, "corrugation_wavelength": 0.04}, (2e4 * 2.0, 1e-3, 45.0))),
    ids=("falling friction", "corrugation"))
def test_contacts_on_a_certified_table_in_one_loop_are_each_contact_model_bit_for_bit(surface, beyond):
    """Contacts answered from a certified table take the loop too; the first loaded step builds each table, a load
    far beyond a corrugation table's domain or a speed beyond a falling-friction table's is solved exactly (the
    contact-by-contact step), and every output and state is the single ContactModel's."""
    p = ContactParameters(**surface, table=2)
    per_contact = {"initial_position": (0.0, 0.013, 2.5)}
    together = ContactModels(p, 3, per_contact=per_contact, stop_time=1.0)
    assert together.together, "table contacts take the loop"
    alone = [ContactModel(ContactParameters(**surface, table=2, initial_position=x), stop_time=1.0)
             for x in per_contact["initial_position"]]
    for n in range(12):
        row = [(2e4 * (1.0 + 0.05 * math.sin(0.37 * n + k)), (1e-3, 4e-4, -1.5e-3)[(n + k) % 3], 45.0)
               for k in range(3)]
        if n == 9:
            row[1] = beyond  # outside the table's domain
        expected = tuple(m.step(n * H, H, *r) for m, r in zip(alone, row, strict=True))
        assert together.step(n * H, H, row) == expected, f"step {n}"
        assert together.state.to_dict() == ContactsState(tuple(m.state for m in alone)).to_dict(), f"state {n}"
        assert n == 0 or n == 9 or {o.method_used for o in expected} == {6}, f"step {n} answers from the tables"
