"""Several 2D contacts of one parameter set stepped together: :class:`ContactModels` (the ``RollingContact2D_n``
FMU's model).

Each contact is a :class:`rollcontact.stepping.ContactModel` of the same parameters with its own inputs and state, so
a contact is stepped exactly as a single-contact model steps it (bit for bit).  A step checks every contact's inputs
first and names each invalid one with its contact (``contact 3: normal_load = -1.0 N is out of range ...``); when a
contact's solve fails after others were stepped, those are set back, so a refused step changes no contact.  Messages
of the contacts are prefixed with their contact.

Quasi-steady contacts on the closed forms (a flat surface with Coulomb friction) or on a certified table (every
contact alike: the parameters they share decide it) are stepped together (:meth:`ContactModels.steps_together`):
every contact is evaluated before any state changes and the states are committed together
(:meth:`rollcontact.stepping.ModelState.commit`), so that no contact's state needs saving for a refusal.  Each
closed-form contact takes :meth:`ContactModel.closed_form_step`, a Python loop over the contacts: with a handful of
contacts the closed forms cost less as Python floats than as numpy arrays (a numpy call on a few values costs about
as much as a contact's Hertz and Carter in floats, and they take some twenty).  The table contacts' answers come in
one call (:class:`~rollcontact.stepping.line.table.TablesTogether`): the tables' contractions of all contacts are one
stacked matrix product each, bit for bit each contact's own
(:func:`~rollcontact.stepping.line.falling_table.evaluate_together`,
:func:`~rollcontact.stepping.line.corrugation_table.evaluate_together`; fewer contacts than
:data:`~rollcontact.stepping.line.table.TOGETHER_FROM` answer one by one, as they come); the outputs of each answer are
:meth:`ContactModel.table_outputs`, as a single contact's.  A step that meets anything else there (an invalid input,
time going backwards, a load beyond the floating-point range, a table without an answer, outputs out of the friction
bound or not finite) is stepped contact by contact instead, which refuses, solves or corrects it as a single contact
does.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, fields
from math import isfinite
from operator import attrgetter

from rollcontact.stepping.base import ModelError
from rollcontact.stepping.line import table
from rollcontact.stepping.line.model import ContactModel, advanced_position
from rollcontact.stepping.line.parameters import STATIONARY, ContactParameters, StepOutputs, input_problem
from rollcontact.stepping.line.state import ModelState
from rollcontact.stepping.line.table import TablesTogether

__all__ = ["ContactModels", "ContactsState"]

INF = float("inf")

snapshot = attrgetter(*(f.name for f in fields(ModelState)))
"""``snapshot(state)``: the fields of a :class:`ModelState` as a tuple, ``ModelState(*snapshot(state))`` its copy
(every field is an immutable value); cheaper than :meth:`ModelState.copy` on every step."""


@dataclass
class ContactsState:
    """The states of the contacts, in contact order (each a :class:`ModelState`)."""

    states: tuple[ModelState, ...]

    @property
    def steps(self) -> int:
        """Steps taken (the same for every contact)."""
        return self.states[0].steps

    def copy(self) -> ContactsState:
        return ContactsState(tuple(state.copy() for state in self.states))

    def to_dict(self) -> dict:
        return {"version": 1, "contacts": [state.to_dict() for state in self.states]}

    @classmethod
    def parse(cls, data, contacts: int) -> ContactsState:
        """The state of :meth:`to_dict`'s dict for ``contacts`` contacts, each checked by :meth:`ModelState.parse`
        (ModelError naming the contact of the first problem)."""
        if not isinstance(data, dict) or set(data) != {"version", "contacts"} or data["version"] != 1:
            raise ModelError(f"a state of several contacts is {{'version': 1, 'contacts': [...]}}, got "
                             f"{str(data)[:80]}")
        states = data["contacts"]
        if not isinstance(states, list) or len(states) != contacts:
            raise ModelError(f"a state of {contacts} contacts holds {contacts} contact states")
        parsed = []
        for k, state in enumerate(states, start=1):
            try:
                parsed.append(ModelState.parse(state))
            except ModelError as exc:
                raise ModelError(f"contact {k}: {exc}") from None
        return cls(tuple(parsed))


class ContactModels:
    """``contacts`` 2D contacts of one :class:`ContactParameters` (module docstring), with ``per_contact`` values
    (parameter name -> one value per contact, e.g. ``radius``, ``initial_position``) replacing shared ones.

    Raises
    ------
    ModelError
        Invalid parameters (as :class:`ContactModel`; a per-contact value named with its contact).
    """

    def __init__(self, parameters: ContactParameters, contacts: int, *, start_time: float = 0.0,
                 stop_time: float | None = None, per_contact: dict | None = None):
        if isinstance(contacts, bool) or not isinstance(contacts, int) or contacts < 1:
            raise ModelError(f"contacts = {contacts!r} must be a whole number >= 1")
        per_contact = per_contact or {}
        if any(len(values) != contacts for values in per_contact.values()):
            raise ModelError(f"per-contact parameters need {contacts} values each, got "
                             f"{ {name: len(values) for name, values in per_contact.items()} }")
        models, problems = [], []
        for k in range(contacts):
            try:
                own = dataclasses.replace(parameters, **{name: values[k] for name, values in per_contact.items()})
                models.append(ContactModel(own, start_time=start_time, stop_time=stop_time))
            except ModelError as exc:
                problems.append(f"contact {k + 1}: {exc}")
        if problems:
            raise ModelError("; ".join(problems))
        self.models = tuple(models)
        self.notices = self.models[0].notices
        self.together = all(m.instationary is None and (m.closed_form or m.table_use is not None) for m in models)
        """Whether the contacts are stepped in one loop (module docstring): :meth:`steps_together`."""
        self.tables = TablesTogether(tuple(model.table_use for model in models)) if self.together and \
            models[0].table_use is not None else None
        """The table contacts' answers in one step (:class:`~rollcontact.stepping.line.table.TablesTogether`)."""

    @property
    def state(self) -> ContactsState:
        """The contacts' current states (the models' own objects)."""
        return ContactsState(tuple(model.state for model in self.models))

    def reset(self, start_time: float = 0.0) -> None:
        for model in self.models:
            model.reset(start_time)

    def set_state(self, state: ContactsState) -> None:
        """Continue from (copies of) ``state``; a contact that refuses its state leaves every contact as it was."""
        before = [model.get_state() for model in self.models]
        try:
            for model, contact_state in zip(self.models, state.states, strict=True):
                model.set_state(contact_state)
        except Exception:
            for model, previous in zip(self.models, before, strict=True):
                model.set_state(previous)
            raise

    def take_messages(self) -> list[str]:
        if not any(model.messages for model in self.models):  # the usual step: nothing queued
            return []
        return [f"contact {k}: {message}" for k, model in enumerate(self.models, start=1)
                for message in model.take_messages()]

    def step(self, current_time: float, step_size: float, inputs) -> tuple[StepOutputs, ...]:
        """One step of every contact; ``inputs`` holds ``(normal_load [N], creep [1], velocity [m/s])`` per contact.

        Raises
        ------
        ModelError
            An invalid input (every one named with its contact) or a contact that cannot be solved (named); no
            contact's state is then changed.
        """
        if len(inputs) != len(self.models):
            raise ModelError(f"{len(inputs)} input rows for {len(self.models)} contacts")
        if self.together and 0.0 < step_size < INF and -INF < current_time < INF:
            outputs = self.steps_together(current_time, inputs)
            if outputs is not None:
                return outputs
        problems = [f"contact {k}: {input_problem(current_time, step_size, *row)}"
                    for k, row in enumerate(inputs, start=1)
                    if not (0.0 <= row[0] < INF and -INF < row[1] < INF and 0.0 <= row[2] < INF)]
        if problems or not (0.0 < step_size < INF and -INF < current_time < INF):
            raise ModelError("; ".join(problems) or input_problem(current_time, step_size, *inputs[0]))
        before = [snapshot(model.state) for model in self.models]
        outputs = []
        for k, (model, row) in enumerate(zip(self.models, inputs, strict=True)):
            try:
                outputs.append(model.step(current_time, step_size, *row))
            except ModelError as exc:
                for stepped, previous in zip(self.models[:k], before, strict=False):
                    stepped.set_state(ModelState(*previous))
                raise ModelError(f"contact {k + 1}: {exc}") from None
        return tuple(outputs)

    def steps_together(self, current_time: float, inputs) -> tuple[StepOutputs, ...] | None:
        """The step of contacts on the closed forms or a table (module docstring) at a valid time (and step size): what
        :meth:`ContactModel.step` gives each, every contact evaluated before any is committed; None, with no contact
        changed, when a contact needs its own :meth:`ContactModel.step` (an invalid input, time going backwards, a
        load beyond the floating-point range, a table without an answer, outputs out of the friction bound or not
        finite)."""
        evaluated = []  # per contact: [model, high, low, inputs, outputs, unloaded]
        tabled = []  # the loaded table contacts' (index, X, N', creep, V), answered together
        alone = len(self.models) < table.TOGETHER_FROM  # too few to answer together: each as it comes
        for model, row in zip(self.models, inputs, strict=True):
            normal_load, creep, velocity = row
            if not (0.0 <= normal_load < INF and -INF < creep < INF and 0.0 <= velocity < INF):
                return None
            dt = current_time - model.state.time
            if dt < 0.0:
                return None
            high, low = advanced_position(model.state, velocity, dt)
            x = high + low
            load = normal_load * model.per_width
            if load < model.resolved_load:  # as ContactModel.step: no contact
                evaluated.append([model, high, low, row, StepOutputs(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, STATIONARY,
                                                                     0, x), True])
                continue
            if load == INF:
                return None
            if model.closed_form or alone:
                if model.closed_form:
                    outputs = model.closed_form_step(x, normal_load, creep, velocity)
                elif (answer := model.table_use.answer(x, load, creep, velocity)) is not None:
                    outputs = model.table_outputs(x, normal_load, creep, velocity, answer)
                else:
                    return None
                if not in_bound(outputs, model.friction_bound, normal_load):
                    return None
            else:  # (a table's steps left, TableUse.remaining, count in exact steps only: none is taken here)
                outputs = None
                tabled.append((len(evaluated), x, load, creep, velocity))
            evaluated.append([model, high, low, row, outputs, False])
        if tabled:
            for (i, x, _, creep, velocity), answer in zip(tabled, self.tables.answers(tabled), strict=True):
                if answer is None:
                    return None
                item = evaluated[i]
                model, normal_load = item[0], item[3][0]
                item[4] = outputs = model.table_outputs(x, normal_load, creep, velocity, answer)
                if not in_bound(outputs, model.friction_bound, normal_load):
                    return None
        for model, high, low, (normal_load, creep, velocity), outputs, unloaded in evaluated:
            state = model.state
            if unloaded:
                state.creep_envelope = None
            state.commit(current_time, high, low, normal_load, creep, velocity, outputs, None,
                         None if model.table_use is None else model.table_use.domain)
        return tuple(item[4] for item in evaluated)


def in_bound(outputs: StepOutputs, bound: float, normal_load: float) -> bool:
    """Whether the outputs of a contact's step are finite and within the friction bound ``|T| <= bound N``,
    ``|T/N| <= bound`` (``bound``: the law's largest coefficient; a sum of finite outputs is finite unless it
    overflows, and the contact's own step then checks each)."""
    return (-bound * normal_load <= outputs[0] <= bound * normal_load and -bound <= outputs[1] <= bound
            and isfinite(sum(outputs)))
