"""When a :class:`rollcontact.stepping.ContactModel` answers from a certified table, and building it.

Two scene families have a table (each certified to :data:`~rollcontact.stepping.line.tabulation.TARGET` of mu N', the
bound it reports):

* the exponential falling law on a flat surface:
  :class:`~rollcontact.stepping.line.falling_table.FallingFrictionTable` over ``u = |xi|/xi_sat`` and ``w = B V
  xi_sat``, its domain ``w <= w_max`` (:class:`FallingFrictionUse`);
* Coulomb friction on a surface of one harmonic (a corrugation):
  :class:`~rollcontact.stepping.line.corrugation_table.CorrugationTable` over the phase of the axis, the load and the
  creep, its domain the loads ``[N_low, N_high]`` (:class:`CorrugationUse`).

A model uses one (:func:`table_use`) when the scene is of such a family, ``method`` is auto or polynomial, no
instationary model runs, ``tolerance`` is 0 or at least the target and ``table`` is not off.  The tables of several
contacts (:class:`rollcontact.stepping.line.contacts.ContactModels`) answer a step together (:class:`TablesTogether`),
each answer its own table's bit for bit.

When to build
-------------
``table`` = auto builds where the run pays for it, each exact step modelled to cost one exact solve and a table step
nothing. When the run's end is known (the FMU's ``stopTime`` from setupExperiment: ``ContactModel(stop_time=)``), a
build (``EXPECTED_SOLVES`` exact solves) starts at the first exact step if at least as many steps remain, and never
otherwise. When it is not, the build starts once the exact steps have cost as long as the build is modelled to take: a
run then pays at most about twice what it would knowing its length (the ski-rental rule). Either way each exact step
advances the build by the solves that fit what ``step_budget`` leaves after the step's own solve, at the family's
modelled cost per solve (:meth:`TableUse.solves_this_step`): a fixed amount of modelled work, so no step's modelled work
exceeds its budget and the step at which the table takes over is the same on every machine, however fast or loaded.
``table`` = on builds at the first loaded step, whatever it takes.  The domain is what the exact steps so far have met,
widened (:meth:`TableUse.wanted_domain`). A step outside the domain of the ready table solves exactly; once such steps
have paid for a build again, a table over the union of both domains is built as auto builds (whatever ``table``), while
the old one keeps answering. A family the exact solver cannot tabulate to the target (a contact that splits, say) gives
the table up: the steps stay exact. Every decision and the figures of every table built (domain, exact solves and their
modelled seconds, bytes, bound) are logged once.

The state (:attr:`rollcontact.stepping.ModelState.table_domain`) records the domain of the table in use: a table is a
deterministic function of the parameters and of its domain, so a restored model builds the same table before its
next step and repeats the steps bit for bit.  A build in progress is not part of the state.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable

import numpy as np

from rollcontact.core.friction import ExponentialFalling
from rollcontact.line.hertz import hertz
from rollcontact.stepping.base import ModelError
from rollcontact.stepping.line import corrugation_table, falling_table
from rollcontact.stepping.line.corrugation_table import CorrugationTable
from rollcontact.stepping.line.falling_table import FallingFrictionTable
from rollcontact.stepping.line.parameters import POLYNOMIAL
from rollcontact.stepping.line.tabulation import TARGET
from rollcontact.stepping.parameters import AUTO
from rollcontact.stepping.threads import one_blas_thread

LOAD_MARGIN = 1.5
"""Factor by which the corrugation table's loads reach beyond the lowest and highest load per length met."""


class TableUse(ABC):
    """The table a model answers from, its build and the rule of when to build (module docstring).

    Parameters
    ----------
    mode : int
        0 auto, 1 off, 2 on (``table``).
    budget : float
        ``step_budget`` [s] (0: none).
    log : callable
        Takes each message to log once (the model's queue).
    """

    expected_solves = 0
    """Exact solves a build of the family is modelled to take."""

    solve_cost = math.inf
    """Modelled time [s] of one exact solve of a build of the family."""

    def __init__(self, mode: int, budget: float, log: Callable[[str], None]):
        self.mode, self.budget, self.log = mode, budget, log
        self.table = None
        """The ready table the steps answer from (None: none yet)."""
        self.pending = None
        self.builder = None
        self.exact_steps = 0
        self.starved = False
        self.remaining: float | None = None
        """Steps left to the run's end when it is known (``(stop_time - t) / h``, set by the model each step)."""
        self.declined = False

    # ---------------------------------------------------------------------------------------- family interface
    @abstractmethod
    def lookup(self, table, x: float, load: float, creep: float, velocity: float) -> tuple | None:
        """``(T' [N/m], a [m], a* [m], offset [m], p0 [Pa], dT'/dxi [N/m])`` from ``table``, or None outside its
        domain."""

    @abstractmethod
    def see(self, load: float, velocity: float, half_width: float) -> None:
        """Record the extent of an exact step's inputs (N' [N/m], V [m/s], a [m])."""

    @abstractmethod
    def wanted_domain(self) -> tuple[float, ...]:
        """The domain of the next table: what the exact steps met, widened, joined with the ready table's."""

    @abstractmethod
    def new_table(self, domain: tuple[float, ...]):
        """A table of the family over ``domain``, not built."""

    @abstractmethod
    def valid_domain(self, domain: tuple[float, ...]) -> bool:
        """Whether ``domain`` (from a state) is one of the family's."""

    @staticmethod
    @abstractmethod
    def stacking(table) -> tuple[tuple, np.ndarray]:
        """``(key, data)``: the tables of several contacts with the same key (their node counts) are evaluated
        together on their ``data`` stacked (:class:`TablesTogether`)."""

    @staticmethod
    @abstractmethod
    def answers_together(uses: list, tables: list, stacked: np.ndarray, steps: list[tuple]) -> list[tuple | None]:
        """:meth:`lookup` of each of ``uses`` in its ``table`` for its step ``(index, X, N', creep, V)``, bit for bit,
        the tables' :meth:`stacking` data stacked in ``stacked``."""

    # --------------------------------------------------------------------------------------------- stepping
    def answer(self, x: float, load: float, creep: float, velocity: float) -> tuple | None:
        """The ready table's answer for the axis at X [m], N' [N/m], the creep and V [m/s], or None (no table, or
        outside its domain)."""
        return None if self.table is None else self.lookup(self.table, x, load, creep, velocity)

    @property
    def domain(self) -> tuple[float, ...]:
        """The ready table's domain; () for none."""
        return () if self.table is None else self.table.domain

    def exact_step_done(self, load: float, velocity: float, half_width: float, exact_cost: float) -> None:
        """Count an exact step (N' [N/m], V [m/s], a [m], its solve modelled at ``exact_cost`` [s]) and, when due,
        advance the build by :meth:`solves_this_step` exact solves."""
        self.exact_steps += 1
        self.see(load, velocity, half_width)
        first_on = self.mode == 2 and self.table is None
        if self.pending is None and self.mode != 1 and (first_on or self.due()):
            domain = self.wanted_domain()
            if domain == self.domain:  # the ready table is as wide as the family's tables go
                self.exact_steps = 0
            else:
                self.start(domain)
        if self.builder is None:
            return
        solves = math.inf if first_on else self.solves_this_step(exact_cost)
        try:
            with one_blas_thread():
                while solves > 0:
                    next(self.builder)
                    solves -= 1
        except StopIteration:
            self.finish()
        except (ArithmeticError, ValueError) as exc:  # a node the solver refuses or cannot solve to the target
            self.log(f"table: no certified table of this scene family ({exc}); the steps solve exactly")
            self.pending = self.builder = None
            self.mode = 1

    def solves_this_step(self, exact_cost: float) -> float:
        """Exact solves of the build an exact step does: as many as fit what ``step_budget`` leaves after the
        step's own solve (``exact_cost`` [s], modelled), at :attr:`solve_cost` each; all that are left without a
        budget.  A fixed, modelled amount of work: the step at which the table is ready is the same on every
        machine.  Where the budget leaves no room for one, the build does not advance (said once in the log)."""
        if not self.budget > 0.0:
            return math.inf
        room = self.budget - (exact_cost if exact_cost == exact_cost else 0.0)
        solves = int(room / self.solve_cost) if room > 0.0 else 0
        if solves == 0 and not self.starved:
            self.starved = True
            self.log(f"table: step_budget = {self.budget!r} s leaves no room for the table's exact solves (modelled "
                     f"at {self.solve_cost:.3g} s each) beside the step's own solve: the table is not built; a larger "
                     "step_budget, or table = on, builds it")
        return solves

    def due(self) -> bool:
        """Whether a build is due now (``table`` = auto, or a rebuild): with the run's end unknown, once the exact
        steps since the last build have cost as long as a build (the ski-rental rule); with :attr:`remaining`
        known, at once if at least as many steps remain as a build costs, never otherwise (said once in the log)."""
        if self.remaining is None:
            return self.exact_steps >= self.expected_solves
        pays = self.remaining >= self.expected_solves and (self.table is None or
                                                          self.exact_steps >= self.expected_solves)
        if not pays and self.table is None and not self.declined:
            self.declined = True
            self.log(f"table: {self.remaining:.0f} steps remain, fewer than the {self.expected_solves} exact solves "
                     "a table costs: the steps solve exactly")
        return pays

    def start(self, domain: tuple[float, ...]) -> None:
        """Begin building the table over ``domain``."""
        self.pending = self.new_table(domain)
        self.builder = self.pending.build_steps()
        self.exact_steps = 0
        how = "now" if self.mode == 2 and self.table is None else "within step_budget, a little in each exact step"
        self.log(f"table: building a certified table over {self.describe(domain)} {how} (modelled "
                 f"{self.expected_solves} exact solves)")

    def finish(self) -> None:
        """Answer from the table just built, and log its figures."""
        table = self.pending
        self.table, self.pending, self.builder = table, None, None
        self.exact_steps = 0
        self.log(f"table: ready over {self.describe(table.domain)}: {table.solves} exact solves (modelled "
                 f"{table.solves * self.solve_cost:.3g} s), {table.nbytes} bytes, certified to {table.bound:.2g} mu N")

    def describe(self, domain: tuple[float, ...]) -> str:
        """The domain in words, for the log."""
        return repr(domain)

    def restore(self, domain: tuple[float, ...]) -> None:
        """Have the table of a restored state ready (building it now if need be); none for ``()``.  A build in
        progress is dropped.

        Raises
        ------
        ModelError
            ``domain`` is not one of this family's, or its table cannot be built.
        """
        self.pending = self.builder = None
        self.exact_steps = 0
        if domain == ():
            self.table = None
            return
        if not self.valid_domain(domain):
            raise ModelError(f"model state table_domain = {domain!r} is not a domain of this model's table "
                             f"({type(self).__name__})")
        if self.table is None or self.table.domain != domain:
            try:
                with one_blas_thread():
                    self.table = self.new_table(domain).build()
            except (ArithmeticError, ValueError) as exc:
                raise ModelError(f"model state table_domain = {domain!r}: its table cannot be built ({exc})") from None


class FallingFrictionUse(TableUse):
    """The table of the exponential falling law on a flat surface; its domain ``(w_max,)``: twice the largest
    ``B V xi_sat`` met, at least 1 and at most :func:`~rollcontact.stepping.line.falling_table.w_limit` of the kinetic
    ratio."""

    expected_solves = falling_table.EXPECTED_SOLVES
    solve_cost = falling_table.SOLVE_COST

    def __init__(self, friction: ExponentialFalling, material, radius: float, offset: float, mode: int,
                 budget: float, log: Callable[[str], None]):
        super().__init__(mode, budget, log)
        self.friction, self.material, self.radius, self.offset = friction, material, radius, offset
        self.saturation_per_half_width = friction.static_coefficient / radius
        self.w_seen = 0.0
        self.w_limit = falling_table.w_limit(friction.kinetic_ratio)

    def lookup(self, table, x, load, creep, velocity):
        """Hertz's a and p0; ``T' = sign(xi) tau mu N'``, ``a* = (a*/a) a``, ``dT'/dxi = kappa mu N' / xi_sat``."""
        a, p0, saturation, u, w = self.coordinates(load, creep, velocity)
        return self.assembled(table.evaluate(u, w), a, p0, saturation, load, creep)

    def coordinates(self, load: float, creep: float, velocity: float) -> tuple[float, float, float, float, float]:
        """Hertz's a [m] and p0 [Pa], Carter's saturation creep ``xi_sat = mu_s a / R`` [1] and the table's
        coordinates ``u = |xi| / xi_sat`` and ``w = B V xi_sat`` [1] at N' [N/m], the creep and V [m/s]."""
        a, p0 = hertz(load, self.radius, self.material.contact_modulus)
        saturation = self.saturation_per_half_width * a
        return a, p0, saturation, abs(creep) / saturation, self.friction.decay * velocity * saturation

    def assembled(self, answer: tuple | None, a: float, p0: float, saturation: float, load: float,
                  creep: float) -> tuple | None:
        """:meth:`lookup`'s answer from the table's ``(tau, a*/a, kappa)`` (None: none) and :meth:`coordinates`."""
        if answer is None:
            return None
        tau, alpha, kappa = answer
        limit = self.friction.static_coefficient * load
        return (math.copysign(tau * limit, creep) if creep != 0.0 else 0.0, a, alpha * a, self.offset, p0,
                kappa * limit / saturation)

    @staticmethod
    def stacking(table):
        return (table.rows.shape, table.t_nodes.size), table.rows

    @staticmethod
    def answers_together(uses, tables, stacked, steps):
        coordinates = [use.coordinates(step[2], step[3], step[4]) for use, step in zip(uses, steps, strict=True)]
        evaluated = falling_table.evaluate_together(tables, stacked, [c[3] for c in coordinates],
                                                    [c[4] for c in coordinates])
        return [use.assembled(answer, c[0], c[1], c[2], step[2], step[3])
                for use, step, answer, c in zip(uses, steps, evaluated, coordinates, strict=True)]

    def see(self, load, velocity, half_width):
        self.w_seen = max(self.w_seen, self.friction.decay * velocity * self.saturation_per_half_width * half_width)

    def wanted_domain(self):
        return (min(self.w_limit, max(1.0, 2.0 * self.w_seen, *self.domain)),)

    def new_table(self, domain):
        return FallingFrictionTable(self.friction.kinetic_ratio, domain[0], self.material, self.radius,
                                    self.friction.static_coefficient)

    def valid_domain(self, domain):
        return len(domain) == 1 and 0.0 < domain[0] <= self.w_limit

    def describe(self, domain):
        return f"w = B V xi_sat <= {domain[0]:.4g}"


class CorrugationUse(TableUse):
    """The table of Coulomb friction on a surface of one harmonic; its domain ``(N_low, N_high)`` [N/m]: the loads
    per length met, :data:`LOAD_MARGIN` beyond both ends."""

    expected_solves = corrugation_table.EXPECTED_SOLVES
    solve_cost = corrugation_table.SOLVE_COST

    def __init__(self, scene: Callable, wavelength: float, radius: float, contact_modulus: float, mu: float,
                 mode: int, budget: float, log: Callable[[str], None]):
        super().__init__(mode, budget, log)
        self.scene, self.wavelength = scene, wavelength
        self.radius, self.contact_modulus, self.mu = radius, contact_modulus, mu
        self.loads_seen = (math.inf, 0.0)

    def lookup(self, table, x, load, creep, velocity):
        """The table's answer with the offset in the model's frame (the scene's mirrored)."""
        return in_model_frame(table.evaluate(x, load, creep))

    @staticmethod
    def stacking(table):
        return table.data.shape, table.flat

    @staticmethod
    def answers_together(uses, tables, stacked, steps):
        return [in_model_frame(answer) for answer in corrugation_table.evaluate_together(
            tables, stacked, [step[1] for step in steps], [step[2] for step in steps], [step[3] for step in steps])]

    def see(self, load, velocity, half_width):
        self.loads_seen = (min(self.loads_seen[0], load), max(self.loads_seen[1], load))

    def wanted_domain(self):
        low, high = self.loads_seen[0] / LOAD_MARGIN, self.loads_seen[1] * LOAD_MARGIN
        if self.table is not None:
            low, high = min(low, self.table.domain[0]), max(high, self.table.domain[1])
        return (low, high)

    def new_table(self, domain):
        return CorrugationTable(self.scene, self.wavelength, domain, self.radius, self.contact_modulus, self.mu)

    def valid_domain(self, domain):
        return len(domain) == 2 and 0.0 < domain[0] < domain[1] < math.inf

    def describe(self, domain):
        return f"N' in [{domain[0]:.4g}, {domain[1]:.4g}] N/m, every phase of the corrugation and every creep"


def in_model_frame(answer: tuple | None) -> tuple | None:
    """A corrugation table's answer with the offset in the model's frame (the scene's mirrored); None stays None."""
    if answer is None:
        return None
    force, a, a_star, offset, p0, stiffness = answer
    return force, a, a_star, 0.0 - offset, p0, stiffness


TOGETHER_FROM = 5
"""Fewest table contacts of a step evaluated together (:class:`TablesTogether`); fewer answer one by one, which costs
less than the stacked products' numpy calls: together costs about as much as one by one at 4 falling-friction
contacts and less from 5 (``benchmarks/bench_contacts.py``, "In process"); the answers are the same bit for bit
either way."""


class TablesTogether:
    """The answers of the ready tables of several contacts' uses in one step (the contacts of
    :class:`rollcontact.stepping.line.contacts.ContactModels`, of one family): each :meth:`TableUse.answer`, bit for
    bit.

    The tables of like node counts (:meth:`TableUse.stacking`) are evaluated together
    (:meth:`TableUse.answers_together`: one stacked matrix product per contraction,
    :func:`~rollcontact.stepping.line.falling_table.evaluate_together`,
    :func:`~rollcontact.stepping.line.corrugation_table.evaluate_together`); their data are stacked once per change of
    the contacts' tables.  Contacts without a ready table answer one by one.
    """

    def __init__(self, uses: tuple[TableUse, ...]):
        self.uses = uses
        self.family = type(uses[0]) if len({type(use) for use in uses}) == 1 else None
        self.tables: tuple = ()
        """The tables :attr:`groups` were made of, one per use."""
        self.groups: tuple = ()
        """Per node count: (the indices of its contacts, their tables' data stacked)."""

    def answers(self, steps: list[tuple[int, float, float, float, float]]) -> list[tuple | None]:
        """:meth:`TableUse.answer` for each of ``steps``: ``(contact index, X [m], N' [N/m], creep [1], V [m/s])``,
        in ascending contact order."""
        uses = self.uses
        tables = tuple(use.table for use in uses)
        if self.family is None or None in tables or len(steps) < TOGETHER_FROM:
            return [uses[i].answer(x, load, creep, velocity) for i, x, load, creep, velocity in steps]
        if tables != self.tables:
            self.regroup(tables)
        if len(self.groups) == 1 and len(steps) == len(uses):  # the usual step: every contact on tables alike
            return self.family.answers_together(uses, tables, self.groups[0][1], steps)
        by_index = {step[0]: step for step in steps}
        answers = {}
        for members, stacked in self.groups:
            chosen = [k for k, i in enumerate(members) if i in by_index]
            indices = [members[k] for k in chosen]
            if indices:
                for i, answer in zip(indices, self.family.answers_together(
                        [uses[i] for i in indices], [tables[i] for i in indices],
                        stacked if len(chosen) == len(members) else stacked[chosen], [by_index[i] for i in indices]),
                                     strict=True):
                    answers[i] = answer
        return [answers[step[0]] for step in steps]

    def regroup(self, tables: tuple) -> None:
        """Group the contacts by their tables' node counts and stack each group's data."""
        groups: dict = {}
        for i, table in enumerate(tables):
            key, data = self.family.stacking(table)
            groups.setdefault(key, ([], []))
            groups[key][0].append(i)
            groups[key][1].append(data)
        self.groups = tuple((members, np.stack(data)) for members, data in groups.values())
        self.tables = tables


def table_use(p, material, radius: float, friction, surface, scene: Callable, instationary: bool,
              log: Callable[[str], None]) -> TableUse | None:
    """The certified table for the parameters ``p`` and the bodies, or None where the scene family has none or the
    parameters rule it out (module docstring).

    ``scene(X, N', xi)`` is the scene the model solves for the axis at X [m], N' [N/m] and the creep.
    """
    if (p.table == 1 or p.method not in (AUTO, POLYNOMIAL) or instationary
            or not (p.tolerance == 0.0 or p.tolerance >= TARGET)):
        return None
    if isinstance(friction, ExponentialFalling) and surface.is_flat:
        slope = surface.polynomial[1] if len(surface.polynomial) > 1 else 0.0
        return FallingFrictionUse(friction, material, radius, radius * slope, p.table, p.step_budget, log)
    if (friction.is_constant and len(surface.harmonics) == 1 and surface.harmonics[0].amplitude != 0.0
            and all(c == 0.0 for c in surface.polynomial[1:])):
        return CorrugationUse(scene, 2.0 * math.pi / surface.harmonics[0].wavenumber, radius,
                              material.contact_modulus, friction.static_coefficient, p.table, p.step_budget, log)
    return None
