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
