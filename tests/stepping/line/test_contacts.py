"""Several 2D contacts stepped together (rollcontact.stepping.line.contacts): each contact is a single ContactModel bit
for bit, invalid inputs are named with their contact, and a contact that fails after others were stepped sets them
back, so a refused step changes no contact."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rollcontact.stepping import ContactModel, ContactParameters, ModelError
from rollcontact.stepping.line import corrugation_table, falling_table
from rollcontact.stepping.line.contacts import ContactModels, ContactsState
from rollcontact.stepping.line.corrugation_table import CorrugationTable
from rollcontact.stepping.line.falling_table import FallingFrictionTable
from rollcontact.stepping.line.table import TOGETHER_FROM, FallingFrictionUse
from rollcontact.stepping.line.tabulation import contract

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


def bits(values) -> str:
    """The exact values (repr: the shortest text that round-trips a double, -0.0 apart from 0.0)."""
    return repr(values)


def test_stacked_products_are_each_single_matrix_vector_product_bit_for_bit():
    """tabulation.contract (numpy's stacked matmul) gives every item's ``matrix @ vector`` (gemv) bit for bit, for the
    shapes of the tables' contractions, 1 to 16 items, random magnitudes over twelve decades, and blocks sliced out of
    longer rows as the second contraction takes them."""
    rng = np.random.default_rng(36)
    for rows, columns in ((80, 9), (4, 13), (3, 9), (1 + 4 * 25 + 3 * 17, 17), (5 + 4 * 9, 5), (65, 13), (7, 3)):
        for m in range(1, 17):
            matrices = rng.standard_normal((m, rows, columns)) * 10.0 ** rng.uniform(-6, 6, (m, rows, columns))
            vectors = rng.standard_normal((m, columns)) / rng.uniform(-1.0, 1.0, (m, columns))
            got = contract(matrices, vectors)
            for i in range(m):
                assert got[i].tobytes() == (matrices[i] @ vectors[i]).tobytes(), f"{rows}x{columns}, {m} items, {i}"
            longer = rng.standard_normal((m, 2 + rows * columns))
            got = contract(longer[:, 1:-1].reshape(m, rows, columns), vectors)
            for i in range(m):
                single = longer[i, 1:-1].reshape(rows, -1) @ vectors[i]
                assert got[i].tobytes() == single.tobytes(), f"slices {rows}x{columns}, {m} items, {i}"


BUILT: dict = {}
"""Falling-friction tables built in this module, by their parameters and domain (:func:`build_each_table_once`)."""


@pytest.fixture
def build_each_table_once(monkeypatch):
    """Each certified table of the same parameters and domain is built once in this module, later builds take its
    arrays: a table is a deterministic function of them (rollcontact.stepping.line.table), and a build takes seconds."""
    for family, parameters in ((FallingFrictionTable, ("kinetic_ratio", "w_max", "radius", "mu", "material")),
                               (CorrugationTable, ("wavelength", "loads", "radius", "contact_modulus", "mu"))):
        monkeypatch.setattr(family, "build_steps", built_once(family.build_steps, parameters))


def built_once(build_steps, parameters: tuple[str, ...]):
    """``build_steps`` that builds a table of given ``parameters`` once and gives later tables its arrays."""

    def once(self):
        key = repr((type(self).__name__, *(getattr(self, name) for name in parameters)))
        if key not in BUILT:
            yield from build_steps(self)
            BUILT[key] = dict(vars(self))
        vars(self).update(BUILT[key])

    return once


FALLING = {"friction_law": 1, "friction_kinetic_ratio": 0.4, "friction_decay": 0.6, "tolerance": 1e-3, "table": 2}


def falling_rows(n: int, contacts: int) -> list[tuple[float, float, float]]:
    """Varied loads (on every third step one contact in five unloaded), creeps (zero, either sign, stick to deep full
    slip) and speeds (zero too) for ``contacts`` contacts at step n."""
    creeps = (0.0, 4e-4, -1.2e-3, 2.5e-3, -6e-3, 0.02, 1e-5)
    return [(0.0 if n % 3 == 1 and (n + k) % 5 == 4 else 2e4 * (1.0 + 0.4 * math.sin(0.9 * n + k)),
             creeps[(n + 3 * k) % 7], (0.0, 12.0, 30.0, 55.0)[(n + k) % 4] + 0.1 * k) for k in range(contacts)]


@pytest.mark.usefixtures("build_each_table_once")
def together_and_alone(fields: dict, radii: list, places: list) -> tuple[ContactModels, list[ContactModel]]:
    """The contacts of ``fields`` with their own radius and initial position, as one :class:`ContactModels` and as
    single :class:`ContactModel` instances (a run to 1 s)."""
    together = ContactModels(ContactParameters(**fields), len(radii), stop_time=1.0,
                             per_contact={"radius": radii, "initial_position": places})
    alone = [ContactModel(ContactParameters(**fields, radius=r, initial_position=x), stop_time=1.0)
             for r, x in zip(radii, places, strict=True)]
    return together, alone


@pytest.mark.parametrize(("contacts", "groups"), ((2, 0), (6, 1), (8, 1), (12, 2)))
def test_contacts_on_falling_friction_tables_together_are_each_contact_model_bit_for_bit(contacts, groups,
                                                                                        monkeypatch):
    """The falling-friction tables evaluated together (one stacked product per contraction; one by one below
    TOGETHER_FROM table contacts), each contact with its own radius (tables of different values stacked) and place,
    loads that come and go, creeps from zero through partial slip to deep full slip, speeds from zero: every output
    and state is the single ContactModel's.  With 12 contacts the tables are grouped by radius, as tables of unlike
    node counts are, each group stacked apart."""
    if groups == 2:
        monkeypatch.setattr(FallingFrictionUse, "stacking", staticmethod(
            lambda table: ((table.rows.shape, table.t_nodes.size, table.radius), table.rows)))
    radii = [(0.46, 0.3)[k % 2] for k in range(contacts)]
    places = [0.37 * k for k in range(contacts)]
    together, alone = together_and_alone(FALLING, radii, places)
    for n in range(16):
        rows = falling_rows(n, contacts)
        expected = tuple(m.step(n * H, H, *r) for m, r in zip(alone, rows, strict=True))
        assert bits(together.step(n * H, H, rows)) == bits(expected), f"step {n}"
        assert together.state.to_dict() == ContactsState(tuple(m.state for m in alone)).to_dict(), f"state {n}"
        assert n < 2 or {o.method_used for o in expected} <= {0, 6}, f"step {n} answers from the tables"
    assert len(together.tables.groups) == groups, "the steps took the tables together, in their groups"


def on_node(scale: float, node: float) -> float:
    """A coordinate c with ``c / scale == node`` exactly (near ``node * scale``), or NaN if none is found nearby."""
    return solved_exactly(lambda c: c / scale, node, node * scale)


def solved_exactly(f, target: float, start: float) -> float:
    """A c near ``start`` with ``f(c) == target`` exactly (f increasing), or NaN if none is found within 64 ulp."""
    c = start
    for _ in range(64):
        if f(c) == target:
            return c
        c = math.nextafter(c, math.inf if f(c) < target else -math.inf)
    return math.nan


@pytest.mark.usefixtures("build_each_table_once")
def test_falling_tables_evaluated_together_are_each_evaluate_bit_for_bit():
    """evaluate_together against FallingFrictionTable.evaluate at random points of partial and full slip and at the
    general path's coordinates (w and u/u_fs on nodes and ends, u = 0, w beyond the domain), 1 to 16 contacts."""
    model = ContactModel(ContactParameters(**FALLING), stop_time=1.0)
    model.step(0.0, H, 2e4, 1e-3, 30.0)
    table = model.table_use.table
    rng = np.random.default_rng(7)
    w_max = table.w_max
    points = [(float(u), float(w)) for u, w in zip(rng.uniform(0.0, 3.0, 60), rng.uniform(0.0, w_max, 60),
                                                    strict=True)]
    points += [(0.5, 0.0), (0.5, w_max), (2.0, w_max), (0.0, 0.3 * w_max), (0.7, 1.01 * w_max), (0.0, 0.0)]
    points += [(1.1, on_node(1.0 / w_max, node)) for node in table.w_unit]
    u_fs = table.onset_at(0.4 * w_max)
    points += [(on_node(1.0 / u_fs, t), 0.4 * w_max) for t in table.t_nodes]
    points += [(on_node(u_fs, 1.0 / r) if r > 0.0 else 1e300, 0.4 * w_max) for r in table.r_nodes]
    points = [(u, w) for u, w in points if u == u and w == w]
    assert len(points) > 80, "the node coordinates were found"
    for m in range(1, 17):
        for start in range(0, len(points), m):
            chosen = points[start:start + m]
            tables = [table] * len(chosen)
            got = falling_table.evaluate_together(tables, np.stack([table.rows] * len(chosen)), [u for u, _ in chosen],
                                                  [w for _, w in chosen])
            assert bits(got) == bits([table.evaluate(u, w) for u, w in chosen]), f"{m} contacts from {start}"


CORRUGATION = {"corrugation_amplitude": 20e-6, "corrugation_wavelength": 0.04, "table": 2}


@pytest.mark.usefixtures("build_each_table_once")
def test_corrugation_tables_evaluated_together_are_each_evaluate_bit_for_bit():
    """corrugation_table.evaluate_together against CorrugationTable.evaluate at random phases, loads and creeps
    (partial and full slip, zero creep) and at the general path's coordinates (the phase and the load coordinate on
    nodes and at the ends, |xi|/xi_fs on nodes, loads outside the table's), 1 to 16 contacts."""
    model = ContactModel(ContactParameters(**CORRUGATION), stop_time=1.0)
    model.step(0.0, H, 2e4, 1e-3, 30.0)
    table = model.table_use.table
    low, high = table.domain
    rng = np.random.default_rng(11)
    points = []
    for x, load in zip(rng.uniform(-1.0, 1.0, 80).tolist(), np.exp(rng.uniform(math.log(low), math.log(high),
                                                                               80)).tolist(), strict=True):
        scale = table.units(load)[2]
        points += [(x, load, scale * c) for c in (0.3, -0.9, 1.7, 0.0)]
    phase = lambda x: (x * table.wavenumber) % (2.0 * math.pi)  # noqa: E731 - a one-line helper
    ell = lambda load: (math.log(load) - table.log_low) / table.log_span  # noqa: E731 - a one-line helper
    mid = math.sqrt(low * high)
    points += [(solved_exactly(phase, theta, theta / table.wavenumber), mid, 1e-4) for theta in table.theta_nodes[1:]]
    points += [(0.0, mid, 1e-4), (0.013, low, -1e-4), (0.013, high, 2e-4), (0.013, 0.5 * low, 1e-4),
               (0.013, 2.0 * high, 1e-4)]
    points += [(0.017, solved_exactly(ell, node, math.exp(table.log_low + node * table.log_span)), 3e-4)
               for node in table.l_nodes[1:-1]]
    values = table.interpolate(phase(0.021), ell(mid))[:5].tolist()
    xi_fs = table.normal(values, mid, 0.0)[4]
    points += [(0.021, mid, solved_exactly(lambda c: abs(c) / xi_fs, t, t * xi_fs)) for t in table.t_nodes[1:-1]]
    points = [point for point in points if all(v == v for v in point)]
    assert len(points) > 330, "the node coordinates were found"
    for m in range(1, 17):
        for start in range(0, len(points), m):
            chosen = points[start:start + m]
            got = corrugation_table.evaluate_together([table] * len(chosen), np.stack([table.flat] * len(chosen)),
                                                      *([list(column) for column in zip(*chosen, strict=True)]))
            assert bits(got) == bits([table.evaluate(*point) for point in chosen]), f"{m} contacts from {start}"


@pytest.mark.usefixtures("build_each_table_once")
@pytest.mark.parametrize("contacts", (2, 6, 8))
def test_contacts_on_corrugation_tables_together_are_each_contact_model_bit_for_bit(contacts):
    """The corrugation tables evaluated together (one by one below TOGETHER_FROM table contacts): each contact with
    its own radius (tables of different values) and place along the corrugation, loads within the tables' (one
    unloaded now and then, one beyond the table once: that step solves exactly), creeps from zero to full slip: every
    output and state is the single ContactModel's."""
    radii = [(0.46, 0.43)[k % 2] for k in range(contacts)]
    places = [0.0113 * k for k in range(contacts)]
    together, alone = together_and_alone(CORRUGATION, radii, places)
    creeps = (1e-3, 0.0, -4e-4, 2e-2, 3e-5, -3e-3)
    for n in range(14):
        rows = [(0.0 if n % 3 == 1 and (n + k) % 5 == 4 else 2e4 * (1.0 + 0.3 * math.sin(0.8 * n + k) * (n > 0)),
                 creeps[(n + k) % 6], 30.0 + k) for k in range(contacts)]
        if n == 9:
            rows[-1] = (2e4 * 4.0, 1e-3, 30.0)  # beyond the table's loads
        expected = tuple(m.step(n * H, H, *r) for m, r in zip(alone, rows, strict=True))
        assert bits(together.step(n * H, H, rows)) == bits(expected), f"step {n}"
        assert together.state.to_dict() == ContactsState(tuple(m.state for m in alone)).to_dict(), f"state {n}"
        assert n in (0, 9) or {o.method_used for o in expected} <= {0, 6}, f"step {n} answers from the tables"
    assert bool(together.tables.groups) == (contacts >= TOGETHER_FROM), "the steps took the tables together"
