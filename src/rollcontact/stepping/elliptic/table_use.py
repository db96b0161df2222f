"""When an :class:`~rollcontact.stepping.elliptic.model.EllipticModel` answers from the certified table of the strips
(:mod:`rollcontact.stepping.elliptic.table`), building it, and its answers: :class:`TableUse`.

A model uses the table (``table`` = auto or on) where the strips are what its steps solve, with their defaults:
Coulomb friction and ``method`` auto or strips.  Its steps answer from a ready table when ``tolerance`` is 0 or at least
the table's bound plus the strips' largest error estimate (:meth:`TableUse.meets`), every loaded contact from it;
otherwise they solve exactly.

When to build
-------------
``table`` = on builds at initialisation (the model's construction), whatever it takes.  ``table`` = auto builds where
the run pays for it, counting an exact step's work as its contacts' modelled solves and a table step's as nothing,
and the build as its solves at :data:`~rollcontact.stepping.elliptic.table.SOLVE_COST` each: when the run's end is
known (the FMU's ``stopTime``), it starts at the first exact step from which as many steps remain as pay for it, and
never otherwise; when it is not, it starts once the exact steps have cost as much (a run then pays at most about twice
what it would knowing its length).  Either way each exact step advances the build by the batches of solves that fit
what ``step_budget`` leaves after the step's costliest contact (all of it without a budget), so the step at which the
table takes over is the same on every machine.  A table of the same Poisson's ratio built before in the process is
taken instead of solving again, the build's modelled batches counted all the same.

The model's state records the batches of the build done and, for auto, the exact work counted: a restored model
advances from there (building at once what the state says is done), so its steps repeat bit for bit.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from rollcontact.elliptic.methods import strips as strips_level
from rollcontact.stepping.elliptic.parameters import LEVEL_CODES, NO_STICK, ZERO, EllipticOutputs
from rollcontact.stepping.elliptic.table import (
    NODES,
    SOLVE_COST,
    TARGET,
    EllipticTable,
    TableAnswer,
    cached_table,
    remember,
)
from rollcontact.stepping.parameters import new_tuple
from rollcontact.stepping.threads import one_blas_thread

__all__ = ["TableUse", "strips_largest_error"]

OFF, ON = 1, 2
"""``table`` codes (0 is auto)."""


def strips_largest_error(poisson_ratio: float) -> float:
    """The largest error estimate [1 of mu Fn] of the strips at Poisson's ratio nu (their accuracy model's value at
    full spin and saturation): ``0.01 + STRIPS_SPIN_ERROR + POISSON_ERROR max(0, nu - 0.28)``."""
    s = strips_level
    return 0.01 + s.STRIPS_SPIN_ERROR + s.POISSON_ERROR * max(0.0, poisson_ratio - 0.28)


class TableUse:
    """The certified table of a model's contacts: its build, the rule of when to build and its answers (module
    docstring).

    Parameters
    ----------
    poisson_ratio : float
        nu of the contacts.
    mode : int
        0 auto, 1 off, 2 on (``table``).
    tolerance : float or None
        The model's tolerance (None: the levels' defaults).
    budget : float or None
        ``step_budget`` [s] (None: none).
    stop_time : float or None
        The run's end [s] when the host gives it.
    log : callable
        Takes each message to log.
    nodes : tuple of int
        The table's node counts (tests take small ones).
    """

    def __init__(self, poisson_ratio: float, mode: int, tolerance: float | None, budget: float | None,
                 stop_time: float | None, log: Callable[[str], None], nodes: tuple = NODES):
        self.mode, self.tolerance, self.budget, self.stop_time, self.log = mode, tolerance, budget, stop_time, log
        self.table = EllipticTable(poisson_ratio, nodes)
        self.sizes = self.table.batch_sizes()
        """The solves of each batch of a build, in order."""
        self.cost = SOLVE_COST * sum(self.sizes)
        """The build's modelled work [s]."""
        self.limit = strips_largest_error(poisson_ratio)
        self.builder = None
        self.built = 0
        """Batches the real build (:attr:`builder`) has done."""
        self.starved = self.declined = False
        self.ready: EllipticTable | None = None
        """The built table (None: not yet)."""

    # ------------------------------------------------------------------------------------------------- rules
    def meets(self) -> bool:
        """Whether a ready table may answer the steps: ``tolerance`` 0, or at least its bound plus the strips'
        largest error."""
        return self.ready is not None and (self.tolerance is None or self.ready.bound + self.limit <= self.tolerance)

    def may_meet(self) -> bool:
        """Whether a table reaching its target could answer the steps (auto builds none that could not)."""
        return self.tolerance is None or TARGET + self.limit <= self.tolerance

    def describe(self) -> str:
        return (f"the strips' table at nu = {self.table.poisson_ratio!r} ({sum(self.sizes)} strips solves in "
                f"{len(self.sizes)} batches, modelled {self.cost:.3g} s)")

    def initialise(self) -> int:
        """The batches done at initialisation: all of them with ``table`` = on (built now), none otherwise."""
        if self.mode != ON:
            return 0
        self.advance_to(len(self.sizes))
        return len(self.sizes)

    def after_exact_step(self, state, current_time: float, step_size: float, work: float, costliest: float) -> None:
        """Count an exact step (``work``: its contacts' modelled solves [s], ``costliest``: its costliest contact's)
        and advance the build as the rules say (module docstring), in ``state`` (its ``table_batches`` and
        ``exact_work``)."""
        if self.mode == OFF or state.table_batches >= len(self.sizes):
            return
        if state.table_batches == 0:
            if not self.may_meet():
                if not self.declined:
                    self.declined = True
                    self.log(f"table: tolerance = {self.tolerance!r} is below what the strips' table can meet (its "
                             f"target {TARGET:g} plus the strips' largest error {self.limit:.3g} mu Fn): the steps "
                             "solve exactly")
                return
            if self.stop_time is not None:
                remaining = (self.stop_time - current_time) / step_size
                if not remaining * work >= self.cost:
                    if not self.declined:
                        self.declined = True
                        self.log(f"table: {remaining:.0f} steps remain, whose exact solves are modelled at "
                                 f"{remaining * work:.3g} s, less than {self.describe()}: the steps solve exactly")
                    return
            else:
                state.exact_work += work
                if state.exact_work < self.cost:
                    return
            self.log(f"table: building {self.describe()}, within step_budget, a little in each exact step")
        room = math.inf if self.budget is None else self.budget - costliest
        target = state.table_batches
        while target < len(self.sizes) and SOLVE_COST * self.sizes[target] <= room:
            room -= SOLVE_COST * self.sizes[target]
            target += 1
        if target == state.table_batches:
            if not self.starved:
                self.starved = True
                self.log(f"table: step_budget = {self.budget!r} s leaves no room for a batch of the table's solves "
                         f"(modelled at {SOLVE_COST * max(self.sizes):.3g} s) beside the step's own solves: the table "
                         "is not built; a larger step_budget, or table = on, builds it")
            return
        self.advance_to(target)
        state.table_batches = target

    def advance_to(self, batches: int) -> None:
        """Have the real build done ``batches`` batches (all of them: the table ready), from a table of the process
        when there is one."""
        if self.ready is not None:
            return
        cached = cached_table(*self.table.key)
        if cached is not None:
            if batches >= len(self.sizes):
                self.ready = cached
                self.log(f"table: ready: {self.figures(cached)} (built before in this process)")
            return
        if self.builder is None:
            self.builder = self.table.build_steps()
            self.built = 0
        with one_blas_thread():
            while self.built < batches:
                try:
                    next(self.builder)
                except StopIteration:
                    break
                self.built += 1
            if batches >= len(self.sizes) and not self.table.ready:
                for _ in self.builder:
                    pass
        if self.table.ready:
            remember(self.table)
            self.ready, self.builder = self.table, None
            self.log(f"table: ready: {self.figures(self.table)}")

    def figures(self, table: EllipticTable) -> str:
        meets = "meets" if table.bound <= TARGET else "misses"
        return (f"{table.solves or sum(self.sizes)} strips solves (modelled {self.cost:.3g} s), {table.nbytes} bytes, "
                f"certified to {table.bound:.3g} mu Fn against the strips ({meets} the target {TARGET:g}); the "
                f"strips' own error is up to {self.limit:.3g} mu Fn")

    def restore(self, batches: int) -> None:
        """Have the build as far as a restored state says (``batches`` done), building at once what it has done."""
        if batches < self.built or (self.ready is not None and batches < len(self.sizes)):
            self.builder = None
            self.built = 0
            self.ready = None
        if batches:
            self.advance_to(batches)

    # ------------------------------------------------------------------------------------------------ answers
    def step(self, constants, rows, shear_modulus: float, mu: float, difference: bool) -> tuple[EllipticOutputs, ...]:
        """The outputs of every contact from the table: Hertz's ellipse of the load (the operations of
        :class:`~rollcontact.stepping.elliptic.linear.LinearContacts`), the normalised creepages, the table's
        answer, and the Jacobian of the linear theory or, with ``difference``, the table's own derivatives.

        ``constants``: per contact what :meth:`LinearContacts.contact_constants` gives and ``ln(a/b)``."""
        table = self.ready
        code = LEVEL_CODES["table"]
        outputs = []
        for (fn, xi, eta, phi, velocity), (linear, rho) in zip(rows, constants, strict=True):
            if fn == 0.0:
                outputs.append(ZERO)
                continue
            major, denominator, g, pressure_scale, g_major, along_x, c11, c22, c23, c33 = linear
            alpha = (3.0 * fn * major / denominator) ** (1.0 / 3.0)
            beta = g * alpha
            p0 = pressure_scale * alpha / g_major
            a, b = (alpha, beta) if along_x else (beta, alpha)
            length = math.sqrt(a * b)
            area = shear_modulus * length * length
            limit = mu * fn
            lever = c23 * length + 0.5 * c11 * b
            kx, ky, ks = area * c11, area * c22, area * lever  # d(linear force)/d(creepage), u = k * creepage / limit
            answer: TableAnswer = table.answer(rho, kx * xi / limit, ky * eta / limit, ks * phi / limit, difference)
            tx, ty, tz, derivatives = answer
            fx, fy, mz = limit * tx, limit * ty, limit * length * tz
            if derivatives is None:
                slope = area
                cross = slope * length * c23
                jacobian = (slope * c11, 0.0, 0.0, 0.0, slope * c22, cross, 0.0, -cross,
                            slope * length * length * c33)
            else:
                d = derivatives
                jacobian = (d[0] * kx, d[1] * ky, d[2] * ks, d[3] * kx, d[4] * ky, d[5] * ks,
                            length * d[6] * kx, length * d[7] * ky, length * d[8] * ks)
            power = velocity * (xi * fx + eta * fy + phi * mz)
            outputs.append(new_tuple(EllipticOutputs, (fx, fy, mz, a, b, p0, NO_STICK, power, *jacobian, code)))
        return tuple(outputs)
