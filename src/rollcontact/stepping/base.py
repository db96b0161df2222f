"""What every geometry's stepping model shares: :class:`SteppingModel` (messages said once, the explicit state
got, set and reset, the budget and tolerance of a step, the checks of a step's arguments) and :class:`ModelError`,
what a model raises when it refuses a parameter, an input or a state.

A stepping model is the library half of an FMU: parameters -> (state, inputs, step) -> outputs, with no FMI tool
involved.  Its state is a plain object with ``copy``, ``to_dict`` and ``parse``: restore -> step -> restore -> step
gives identical outputs.  Every output is a function of the parameters, the inputs, the step times and the state
alone (budgets are modelled costs; no clock is read).
"""

from __future__ import annotations

from rollcontact.core.checks import SceneError, check_real


class ModelError(ValueError):
    """An input or parameter the model cannot use, or a scene no allowed method solves; the message says why."""


def argument_problems(rows, label: str = "") -> list[str]:
    """Every invalid value of ``rows`` ``(name, value, unit, lower, lower_open)``: not a real number, not finite
    (``normal_load = nan is not finite``), or below ``lower`` (None: no bound) with its unit (``normal_load = -1.0 N is
    out of range: it must be >= 0.0``); each message prefixed with ``label``."""
    problems = []
    for name, value, unit, lower, lower_open in rows:
        try:
            check_real(name, check_real(name, value), lower=lower, lower_open=lower_open, unit=unit)
        except SceneError as exc:
            problems.append(f"{label}{exc}")
    return problems


def time_problems(current_time, step_size) -> list[str]:
    """The problems of a step's communication point t_n [s] (finite) and step size h [s] (finite, > 0)."""
    return argument_problems((("current_time", current_time, "s", None, False),
                              ("step_size", step_size, "s", 0.0, True)))


class SteppingModel:
    """The base of every geometry's stepping model.

    A subclass sets :attr:`STATE` (its state class, with ``initial(start_time, ...)`` made by :meth:`initial_state`,
    ``copy``), :attr:`parameters`, and calls :meth:`__init__` (which takes the tolerance and the step budget of the
    shared parameter block) before it makes its state with :meth:`reset`.
    """

    STATE: type = object
    """The class of the model's state."""

    def __init__(self, parameters):
        self.parameters = parameters
        self.tolerance = parameters.tolerance if parameters.tolerance > 0.0 else None
        """Requested error of a step's solve [1], None: each method's defaults."""
        self.budget = parameters.step_budget if parameters.step_budget > 0.0 else None
        """Modelled work [s] a contact's solve may do in one step, None: no bound."""
        self.messages: list[str] = []
        """Messages of the steps not yet taken by :meth:`take_messages`."""
        self.noticed: set[str] = set()

    # messages -----------------------------------------------------------------------------------------------------
    def log(self, message: str) -> None:
        """Queue ``message`` for :meth:`take_messages`."""
        self.messages.append(message)

    def notice_once(self, kind: str, message: str) -> None:
        """Queue ``message`` for :meth:`take_messages` the first time a step meets ``kind``."""
        if kind not in self.noticed:
            self.noticed.add(kind)
            self.log(message)

    def take_messages(self) -> list[str]:
        """The messages the steps queued since the last call (e.g. for an FMU log; each kind once per model)."""
        messages, self.messages = self.messages, []
        return messages

    # state --------------------------------------------------------------------------------------------------------
    def initial_state(self, start_time: float):
        """The state at ``start_time`` [s] before any step."""
        return self.STATE.initial(float(start_time))

    def reset(self, start_time: float = 0.0) -> None:
        """Back to the initial state at ``start_time`` [s]."""
        self.state = self.initial_state(start_time)

    def get_state(self):
        """A copy of the current state."""
        return self.state.copy()

    def set_state(self, state) -> None:
        """Continue from (a copy of) ``state``; :meth:`restore` may refuse it (ModelError), leaving the model as it
        was."""
        if not isinstance(state, self.STATE):
            raise TypeError(f"state must be a {self.STATE.__name__}, got {type(state).__name__}")
        state = state.copy()
        self.restore(state)
        self.state = state

    def restore(self, state) -> None:
        """What a state needs before the model continues from it (default: nothing); raises to refuse it."""
