"""Stepping model of the elliptic (3D) contact for co-simulation: parameters -> (state, inputs, step) -> outputs.

The library half of the ``RollingContact3D`` FMU (``fmu_src/RollingContact3D/rollcontact_fmu_contact3d.py`` maps its
variables here and back, nothing else): one or several wheel/rail contacts of one material and friction law, each with
its own gap curvatures, stepped together.

* :class:`~rollcontact.stepping.elliptic.parameters.EllipticParameters` holds the fixed parameters (FMU parameters
  of the same names; the curvatures one per contact) and checks them all at once;
* :class:`EllipticModel` evaluates one communication step, :meth:`EllipticModel.step`: for each contact the steady
  elliptic contact of the inputs sampled at ``t_n`` through :func:`rollcontact.solve_elliptic`, with the parameters'
  method, tolerance and step budget (the budget bounds each contact's solve in modelled seconds: no clock is read,
  so every output is a function of parameters and inputs alone);
* :class:`EllipticState` is what the model remembers: the last communication point and the number of steps.  The
  steady contact has no history, so a restored state repeats the steps bit for bit.

Signs (docs/physics.md, Elliptic contact): the forces and moment are those the wheel exerts on the rail, so each
creepage > 0 gives its force > 0; in Kalker's linear theory ``Fx = G c^2 C11 xi``, ``Fy = G c^2 (C22 eta + c C23
phi)``, ``Mz = G c^3 (-C23 eta + c C33 phi)``, c = sqrt(ab).

Jacobian: the outputs ``dFx_dxi`` ... ``dMz_dphi`` are d(Fx, Fy, Mz)/d(xi, eta, phi) at the step's contact.  With
``jacobian`` = 0 they are the linear theory's slopes at the step's ellipse (the derivatives of the relations above:
exact for the linear level and at vanishing creepage, the stiffness an implicit host linearises with; they do not
fall with saturation); with ``jacobian`` = 1 forward differences of the step's own method, three more solves per
contact with increments of :data:`DIFFERENCE_STEP` of each creepage's saturation value (``mu Fn`` over the linear
slope): the step's solve is then chosen within a quarter of the step budget and the three differences take its
setting, so that all four fit the budget; the linear level's derivatives are its slopes in either mode (exact).  The
linear slopes stand in, said once, where the budget does not pay the three solves or a load is so small that the
increments are no numbers, and for the column of a creepage whose increment the level cannot take.

A level is refused at initialisation when its cheapest setting is modelled above ``step_budget`` at any load
(:meth:`EllipticModel.over_budget`), since every loaded step would be.  A level's failure, and any error inside it,
is refused with the contact's inputs.

Contacts together, wherever the level a step takes has a form for several contacts, each contact's outputs bit for bit
those of :func:`rollcontact.solve_elliptic`: with ``method`` = linear (and no tolerance) the linear theory of every
contact without a solver call (:class:`LinearContacts`), the same operations as
:func:`rollcontact.elliptic.hertz_ellipse` and the linear level take for one contact; with ``method`` = strips or auto
(no tolerance, the cost with spin within the budget; auto's choice is then the strips for every contact, with
Coulomb friction or a rail condition) one :func:`~rollcontact.elliptic.methods.strips.solve_strips_many` over the
contacts, with ``method`` = fastsim (no tolerance, within the budget) one
:func:`~rollcontact.elliptic.methods.fastsim.solve_fastsim_many` (:meth:`EllipticModel.together_step`); with a
tolerance each contact's setting as solve_elliptic chooses it, the contacts on the strips or the linear theory
together (:meth:`EllipticModel.chosen_together`).  The other levels solve the contacts one after another through
solve_elliptic.

Certified table: with Coulomb friction and ``method`` auto or strips, ``table`` = on builds at initialisation (auto:
where the run pays for it) a table of the strips' normalised forces over a/b and three normalised creepages
(:mod:`rollcontact.stepping.elliptic.table`); the steps then answer every loaded contact from it, ``method_used`` =
table, where ``tolerance`` is 0 or at least its bound plus the strips' largest error
(:mod:`rollcontact.stepping.elliptic.table_use`).  The ellipse is Hertz's (the operations of :class:`LinearContacts`);
the Jacobian with ``jacobian`` = 0 the linear theory's slopes, with 1 the table's own derivatives.

Frictional power: ``V (xi Fx + eta Fy + phi Mz)`` [W], the power the creepages put into the contact (the rigid slip
velocities times the forces on the rail), which steady rolling dissipates by slip.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass

import numpy as np

from rollcontact.core.checks import error_text
from rollcontact.core.dispatch import Budget
from rollcontact.core.materials import Material
from rollcontact.core.method import UNRESOLVED
from rollcontact.elliptic.creep_coefficients import aspect_ratio_range, creepage_coefficients
from rollcontact.elliptic.dispatch import DISPATCHER as ELLIPTIC_DISPATCHER
from rollcontact.elliptic.dispatch import METHODS as ELLIPTIC_METHODS
from rollcontact.elliptic.dispatch import solve as solve_elliptic
from rollcontact.elliptic.hertz import HertzEllipse, differences, eccentricity
from rollcontact.elliptic.methods import fastsim as fastsim_level
from rollcontact.elliptic.methods import linear as linear_level
from rollcontact.elliptic.methods import strips as strips_level
from rollcontact.elliptic.scene import EllipticScene
from rollcontact.stepping.base import ModelError, SteppingModel, argument_problems, time_problems
from rollcontact.stepping.elliptic.linear import LinearContacts, contact_constants
from rollcontact.stepping.elliptic.parameters import (
    INPUTS,
    LEVEL_CODES,
    LOAD_INPUTS,
    METHOD_NAMES,
    NO_STICK,
    TABLE_OFF,
    ZERO,
    EllipticOutputs,
    EllipticParameters,
    method_code,
)
from rollcontact.stepping.elliptic.table import NODES as TABLE_NODES
from rollcontact.stepping.elliptic.table_use import TableUse
from rollcontact.stepping.parameters import AUTO, friction_law

__all__ = ["DIFFERENCE_STEP", "EllipticModel", "EllipticState"]

DIFFERENCE_STEP = 1e-4
"""Increment of a forward difference, as a share of the creepage's saturation value ``mu Fn / slope`` [1]: small
against the curvature of the creep-force curves (which bend over the saturation value), large against the rounding
of the forces (1e-16 of mu Fn)."""

















STRIPS_METHOD = strips_level.METHOD
BATCHED = {"strips": STRIPS_METHOD, "linear": linear_level.METHOD}
"""The built-in levels whose contacts a step with a tolerance solves together (the registry may replace them: then it
does not)."""
MANY = {"strips": (STRIPS_METHOD, strips_level.solve_strips_many),
        "fastsim": (fastsim_level.METHOD, fastsim_level.solve_fastsim_many)}
"""The levels with a solve of several scenes (each scene's numbers its own solve's) and the built-in level each
belongs to: what :meth:`EllipticModel.together_step` takes."""


def strips_resolve_every_scene() -> bool:
    """Whether the strips' error estimate stays below :data:`~rollcontact.core.method.UNRESOLVED` on every scene (its
    largest value: 1 % for the coefficients plus the spin's error, the excess of Poisson's ratio up to 0.5 and a
    friction law that falls to nothing over the contact), so that ``auto`` never falls back from them and a step may
    solve its contacts' strips together."""
    s = strips_level
    return 0.01 + s.STRIPS_SPIN_ERROR + s.POISSON_ERROR * 0.5 + s.STRIPS_FALLING_ERROR < UNRESOLVED


@dataclass
class EllipticState:
    """What an :class:`EllipticModel` remembers between steps: the last communication point [s], the steps taken (the
    steady contact has no other history) and the certified table's progress: the batches of its build done and, with
    ``table`` = auto and the run's end unknown, the exact steps' modelled work counted towards it [s]
    (:mod:`rollcontact.stepping.elliptic.table_use`)."""

    time: float
    steps: int = 0
    table_batches: int = 0
    exact_work: float = 0.0

    KEYS = {1: {"version", "time", "steps"}, 2: {"version", "time", "steps", "table_batches", "exact_work"}}

    @classmethod
    def initial(cls, start_time: float) -> EllipticState:
        """The state at ``start_time`` [s] before any step."""
        return cls(float(start_time))

    def copy(self) -> EllipticState:
        return EllipticState(self.time, self.steps, self.table_batches, self.exact_work)

    def to_dict(self) -> dict:
        """A JSON-compatible dict (:meth:`parse` reads it back)."""
        return {"version": 2, "time": self.time, "steps": self.steps, "table_batches": self.table_batches,
                "exact_work": self.exact_work}

    @classmethod
    def parse(cls, data) -> EllipticState:
        """The state of :meth:`to_dict`'s dict (or of version 1, without the table's fields), every field checked
        (ModelError naming the first problem)."""
        version = data.get("version") if isinstance(data, dict) else None
        if type(version) is not int or version not in cls.KEYS:
            raise ModelError(f"elliptic model state version {version!r} is not supported (this reads 1 and 2)")
        if set(data) != cls.KEYS[version]:
            raise ModelError(f"an elliptic model state of version {version} has exactly the keys "
                             f"{', '.join(sorted(cls.KEYS[version]))}; got {sorted(map(str, data))}")
        time, steps = data["time"], data["steps"]
        batches, work = data.get("table_batches", 0), data.get("exact_work", 0.0)
        if type(time) not in (int, float) or not math.isfinite(time):
            raise ModelError(f"elliptic model state time = {time!r} must be a finite real number")
        for name, value in (("steps", steps), ("table_batches", batches)):
            if type(value) is not int or value < 0:
                raise ModelError(f"elliptic model state {name} = {value!r} must be a whole number >= 0")
        if type(work) not in (int, float) or not 0.0 <= work < math.inf:
            raise ModelError(f"elliptic model state exact_work = {work!r} must be a finite real number >= 0")
        return cls(float(time), steps, batches, float(work))


class EllipticModel(SteppingModel):
    """n elliptic contacts of one material and friction law stepped together (module docstring).

    Parameters
    ----------
    parameters : EllipticParameters
        The fixed parameters (default: one contact of the defaults).
    start_time : float
        The first communication point [s].
    stop_time : float, optional
        The run's end [s] when known (the FMU's ``stopTime``): ``table`` = auto builds the certified table only where
        the steps left pay for it (:mod:`rollcontact.stepping.elliptic.table_use`).
    table_nodes : tuple of int, optional
        Node counts of the certified table (default :data:`rollcontact.stepping.elliptic.table.NODES`; tests take
        small ones).

    Raises
    ------
    ModelError
        The material or friction law is invalid, or a contact's ellipse is one the chosen method cannot treat
        (e.g. a/b outside the creepage-coefficient table); the message names the contact.
    """

    STATE = EllipticState

    def __init__(self, parameters: EllipticParameters | None = None, *, start_time: float = 0.0,
                 stop_time: float | None = None, table_nodes: tuple[int, int, int, int] = TABLE_NODES):
        p = EllipticParameters() if parameters is None else parameters
        if not isinstance(p, EllipticParameters):
            raise TypeError(f"parameters must be EllipticParameters, got {type(p).__name__}")
        super().__init__(p)
        try:
            self.material = Material(p.youngs_modulus, p.poisson_ratio)
            self.friction = friction_law(p)
        except ValueError as exc:
            raise ModelError(str(exc)) from None
        self.method = "auto" if p.method == AUTO else METHOD_NAMES[p.method]
        self.parameter_curvatures = tuple(zip(p.curvature_longitudinal, p.curvature_lateral, strict=True))
        """Each contact's (A, B) [1/m] of the parameters: its gap where a step's inputs give none."""
        self.curvatures = self.parameter_curvatures
        """Each contact's (A, B) [1/m] of the last step (the parameters' before the first)."""
        self.shear_modulus = self.material.shear_modulus
        problems = list(dict.fromkeys(why for k in range(p.contacts) if (why := self.inapplicable(k)) is not None))
        over = self.over_budget()
        if over is not None:
            problems.append(over)
        if problems:
            raise ModelError("; ".join(problems))
        self.batch = LinearContacts(self) if self.method == "linear" and self.tolerance is None and \
            self.fits_budget("linear") else None
        """The contacts' linear theory evaluated together (None: each contact through solve_elliptic)."""
        self.strips_together = self.method in ("strips", "auto") and self.tolerance is None and \
            self.fits_budget("strips", spin=True) and strips_resolve_every_scene()
        """The contacts' strips solved together (:func:`~rollcontact.elliptic.methods.strips.solve_strips_many`, bit
        for bit each contact's solve): ``method`` = strips, or auto while the strips are what auto takes
        (:meth:`strips_chosen`)."""
        self.fastsim_together = self.method == "fastsim" and self.tolerance is None and self.fits_budget("fastsim")
        """The contacts' FASTSIM solved together with its defaults
        (:func:`~rollcontact.elliptic.methods.fastsim.solve_fastsim_many`, bit for bit each contact's solve):
        ``method`` = fastsim while the registry's fastsim is the built-in level."""
        self.choose_together = self.tolerance is not None and self.method in ("auto", "strips", "linear")
        """With a tolerance: each contact's setting chosen as solve_elliptic chooses it, the contacts whose choice is
        the strips or the linear theory with their defaults solved together (:meth:`chosen_together`)."""
        self.linear_together = LinearContacts(self) if self.choose_together and self.method != "strips" else None
        self.last_modelled_cost = 0.0
        """The modelled work [s] of the last step's costliest contact, its failures, fallbacks and difference
        Jacobian included: what ``step_budget`` bounds (``benchmarks/bench_worst_step.py`` sets it against the real
        time)."""
        self.last_work = 0.0
        """The modelled work [s] of the last step's contacts together (a table step: none)."""
        self.constants_cache: dict[int, tuple] = {}
        """Per contact what its steps take from its curvatures alone (:meth:`contact_constants`)."""
        self.table_use = None
        """The certified table of the strips, where the steps solve the strips with their defaults: Coulomb
        friction, ``method`` auto or strips, ``table`` not off (:class:`TableUse`)."""
        if p.table != TABLE_OFF and self.friction.is_constant and self.method in ("auto", "strips"):
            self.table_use = TableUse(p.poisson_ratio, p.table, self.tolerance, self.budget, stop_time, self.log,
                                      table_nodes)
            self.table_constants = [self.table_contact(A, B) for A, B in self.curvatures]
        self.reset(start_time)
        self.notices: tuple[str, ...] = tuple(self.take_messages())
        """Messages worth showing once at initialisation (the certified table built, with ``table`` = on)."""

    def initial_state(self, start_time: float) -> EllipticState:
        """The state at ``start_time`` [s] before any step: with ``table`` = on, the certified table built."""
        state = EllipticState.initial(start_time)
        if self.table_use is not None:
            state.table_batches = self.table_use.initialise()
        return state

    def restore(self, state: EllipticState) -> None:
        """Have the certified table as far as ``state`` says (building at once what it says is done); ModelError
        for a state of more batches than the table has."""
        if self.table_use is None:
            if state.table_batches or state.exact_work:
                raise ModelError("the model state holds a certified table's progress, but this model has no table "
                                 "(table = off, a falling law, or another method)")
            return
        if state.table_batches > len(self.table_use.sizes):
            raise ModelError(f"model state table_batches = {state.table_batches} exceeds the table's "
                             f"{len(self.table_use.sizes)} batches")
        self.table_use.restore(state.table_batches)

    def table_contact(self, A: float, B: float) -> tuple[tuple, float]:
        """What a contact's table steps take from its curvatures: the linear theory's constants
        (:meth:`LinearContacts.contact_constants`) and ``ln(a/b)``."""
        constants = contact_constants(A, B, self.material.contact_modulus, self.material.poisson_ratio)
        g, along_x = constants[2], constants[5]
        return constants, (-math.log(g) if along_x else math.log(g))

    def table_answers(self) -> bool:
        """Whether this step answers from the certified table (built, and its bound meets the tolerance)."""
        use = self.table_use
        return use is not None and self.state.table_batches == len(use.sizes) and use.meets()

    @property
    def contacts(self) -> int:
        return self.parameters.contacts

    def fits_budget(self, method: str, spin: bool = False) -> bool:
        """Whether the level's modelled cost (with spin: its cost with spin; with ``jacobian`` = difference four
        times it) fits the step budget (else each contact's solve is left to solve_elliptic, which refuses or takes a
        cheaper setting)."""
        spec = ELLIPTIC_METHODS[method]
        A, B = self.curvatures[0]
        scene = EllipticScene(1.0, A, B, spin_creepage=1.0 if spin else 0.0, material=self.material,
                              friction=self.friction)
        solves = 4 if self.parameters.jacobian == 1 else 1
        return self.budget is None or spec.accuracy is None or solves * spec.accuracy.cost(scene, {}) <= self.budget

    def over_budget(self) -> str | None:
        """Why no loaded step can fit the step budget, or None: the cheapest setting of every level ``method`` may
        take (``auto``: any registered level) is modelled above it at any load (the accuracy model's ``floor``, a lower
        bound of its cost over every scene and setting), so every loaded step would be refused."""
        if self.budget is None:
            return None
        specs = list(ELLIPTIC_METHODS.values()) if self.method == "auto" else \
            [spec for spec in (ELLIPTIC_METHODS.get(self.method),) if spec is not None]
        floors = [spec.accuracy.floor if spec.accuracy is not None else 0.0 for spec in specs]
        if not floors or min(floors) <= self.budget:
            return None
        return (f"method = {self.method}: its cheapest setting is modelled at {min(floors):.4g} s at any load, more "
                f"than step_budget = {self.budget!r} s, so every loaded step would be refused (raise step_budget, or "
                "set 0 for no budget)")

    def label(self, k: int) -> str:
        """``"contact k: "`` (k from 1) with several contacts, else ``""``: the prefix of a contact's messages."""
        return f"contact {k + 1}: " if self.contacts > 1 else ""

    def inapplicable(self, k: int, curvatures: tuple[float, float] | None = None) -> str | None:
        """Why contact ``k`` (from 0) cannot be stepped at any load with its curvatures (default: the last step's;
        its ellipse's a/b is that of every load), or None: an a/b outside Kalker's coefficient table (every step's
        Jacobian outputs and the linear, FASTSIM and strips levels need the coefficients), or a method that cannot
        treat the ellipse (a cause that is no contact's, such as the friction law, is named without the contact: the
        same message for every contact)."""
        A, B = self.curvatures[k] if curvatures is None else curvatures
        scene = EllipticScene(1.0, A, B, material=self.material, friction=self.friction)
        low, high = aspect_ratio_range()
        ratio = scene.hertz.aspect_ratio
        where = f"{self.label(k)}curvatures A = {A!r}, B = {B!r} 1/m give a/b = {ratio:.6g}"
        if not low <= ratio <= high:
            return (f"{where}, outside [{low:g}, {high:g}], the range of Kalker's creepage coefficients that every "
                    "step's Jacobian outputs need (and the linear, FASTSIM and strips levels)")
        if self.method == "auto":
            reasons = [f"{s.name}: {why}" for s in ELLIPTIC_METHODS.values() if (why := s.inapplicable(scene))]
            if len(reasons) < len(ELLIPTIC_METHODS):
                return None
            return f"{where}: no elliptic method can solve it (" + "; ".join(reasons) + ")"
        spec = ELLIPTIC_METHODS.get(self.method)
        if spec is None:
            return f"method {self.method!r} is not registered in rollcontact.ELLIPTIC_METHODS"
        why = spec.inapplicable(scene)
        if why is None:
            return None
        if spec.inapplicable(EllipticScene(1.0, 1.0, 1.0, material=self.material, friction=self.friction)) == why:
            return f"method = {self.method}: {why}"  # the friction law's or the material's doing, not the ellipse's
        return f"{where}: {why}"

    # stepping ---------------------------------------------------------------------------------------------------
    def step(self, current_time: float, step_size: float, inputs) -> tuple[EllipticOutputs, ...]:
        """Evaluate every contact for the inputs sampled at ``current_time``.

        Parameters
        ----------
        current_time : float
            Communication point t_n [s], not before the previous one.
        step_size : float
            h [s] > 0.
        inputs : sequence
            Per contact ``(normal_load [N] >= 0, longitudinal_creep [1], lateral_creep [1], spin [1/m],
            velocity [m/s] >= 0)``, optionally followed by the gap's curvatures of the step
            ``(gap_curvature_longitudinal, gap_curvature_lateral)`` [1/m] >= 0 (0, or a row of five: the parameters'
            curvature of that contact), all finite.  A step's outputs depend on its curvatures alone, not on those
            of earlier steps.

        Returns
        -------
        tuple of EllipticOutputs
            One per contact.

        Raises
        ------
        ModelError
            Invalid inputs (every one named, with its contact), time going backwards, curvatures whose ellipse no
            level treats, or a contact no allowed method solves within the budget.  The state is then unchanged.
        """
        inf = math.inf
        try:  # per contact seven real numbers with the gap's curvatures (an FMU's step), or five
            rows = [(float(fn), float(xi), float(eta), float(phi), float(v)) for fn, xi, eta, phi, v, _, _ in inputs]
            gaps = [(float(row[5]), float(row[6])) for row in inputs]
            if not any(A or B for A, B in gaps):
                gaps = None
        except (TypeError, ValueError):
            try:
                rows = [(float(fn), float(xi), float(eta), float(phi), float(v)) for fn, xi, eta, phi, v in inputs]
                gaps = None
            except (TypeError, ValueError):  # rows of either length, or of other values (listed below)
                rows, gaps = self.gap_rows(inputs)
        valid = rows is not None and len(rows) == self.contacts and 0.0 < step_size < inf and -inf < current_time < inf
        for fn, xi, eta, phi, v in rows if valid else ():
            if not (0.0 <= fn < inf and -inf < xi < inf and -inf < eta < inf and -inf < phi < inf and 0.0 <= v < inf):
                valid = False
                break
        for A, B in gaps if valid and gaps is not None else ():
            if not (0.0 <= A < inf and 0.0 <= B < inf):
                valid = False
                break
        if not valid:
            raise ModelError("; ".join(self.input_problems(current_time, step_size, inputs)) or
                             f"invalid step inputs {inputs!r}")
        if current_time < self.state.time:
            raise ModelError(f"current_time = {current_time!r} s lies before the last communication point "
                             f"{self.state.time!r} s; restore a saved state to step from an earlier time")
        curvatures = self.parameter_curvatures if gaps is None else tuple(
            (A if A != 0.0 else default[0], B if B != 0.0 else default[1])
            for (A, B), default in zip(gaps, self.parameter_curvatures, strict=True))
        if curvatures != self.curvatures:
            self.use_curvatures(curvatures)
        self.last_modelled_cost = self.last_work = 0.0
        tabled = self.table_answers()
        if tabled:  # Python floats and small matrix products; a contact beyond floating point steps exactly (below)
            try:
                outputs = self.table_use.step(self.table_constants, rows, self.shear_modulus,
                                              self.friction.static_coefficient, self.parameters.jacobian == 1)
                tabled = all(all(map(math.isfinite, contact)) for contact in outputs)
            except (ArithmeticError, ValueError):  # a coordinate that is no number
                tabled = False
        if not tabled:
            with np.errstate(all="ignore"):  # what overflows is refused below, by its output: no numpy warning
                outputs = self.evaluate(rows)
        for k, (contact, row) in enumerate(zip(outputs, rows, strict=True)):
            if not all(map(math.isfinite, contact)):
                raise ModelError(self.non_finite(k, contact, row))
        if self.table_use is not None and not tabled:
            self.table_use.after_exact_step(self.state, current_time, step_size, self.last_work,
                                            self.last_modelled_cost)
        self.state.time = float(current_time)
        self.state.steps += 1
        return outputs

    @staticmethod
    def gap_rows(inputs) -> tuple[list | None, list | None]:
        """``(rows, gaps)`` of input rows of seven real numbers or five (whose gap is ``(0, 0)``): the first five of
        each and its gap's curvatures; ``(None, None)`` when a row is neither."""
        rows, gaps = [], []
        try:
            for row in inputs:
                if len(row) not in (LOAD_INPUTS, len(INPUTS)):
                    return None, None
                values = tuple(map(float, row))
                rows.append(values[:LOAD_INPUTS])
                gaps.append(values[LOAD_INPUTS:] or (0.0, 0.0))
        except (TypeError, ValueError):
            return None, None
        return rows, gaps

    def use_curvatures(self, curvatures: tuple[tuple[float, float], ...]) -> None:
        """Step with the contacts' ``curvatures`` ((A, B) [1/m] each) from now on: the same as a model made with
        them as parameters.  ModelError, naming each contact whose ellipse no level treats, changes nothing."""
        changed = [k for k, (new, old) in enumerate(zip(curvatures, self.curvatures, strict=True)) if new != old]
        problems = [why for k in changed if (why := self.inapplicable(k, curvatures[k])) is not None]
        if problems:
            raise ModelError("; ".join(p.replace("curvatures A", "gap curvatures A", 1) for p in problems))
        self.curvatures = curvatures
        for batch in (self.batch, self.linear_together):
            if batch is not None:
                batch.use_curvatures(changed, curvatures)
        if self.table_use is not None:
            for k in changed:
                self.table_constants[k] = self.table_contact(*curvatures[k])

    def evaluate(self, rows) -> tuple[EllipticOutputs, ...]:
        """The outputs of every contact for its checked inputs: together where the level allows
        (:class:`~rollcontact.stepping.elliptic.linear.LinearContacts`, :meth:`together_step`, and with a tolerance
        :meth:`chosen_together`), else contact by contact (:meth:`contact_step`), which also answers a batch that
        breaks down in floating point, naming the contact."""
        try:
            if self.batch is not None:
                outputs = self.batch.step(rows)
                costs = [ELLIPTIC_METHODS["linear"].accuracy.cost(self.scene(k, *row), {})
                         for k, row in enumerate(rows) if row[0] != 0.0]
                self.last_modelled_cost, self.last_work = max(costs, default=0.0), sum(costs)
                return outputs
            if self.strips_together and self.strips_chosen():
                return self.together_step("strips", rows, range(len(rows)))
            if self.fastsim_together and ELLIPTIC_METHODS.get("fastsim") is MANY["fastsim"][0]:
                return self.together_step("fastsim", rows, range(len(rows)))
            if self.choose_together:
                return self.chosen_together(rows)
        except ArithmeticError:
            pass
        return tuple(self.contact_step(k, *row) for k, row in enumerate(rows))

    def strips_chosen(self) -> bool:
        """Whether every loaded contact's solve is the package's strips with their defaults: ``method`` = strips,
        or auto while the strips are the lowest-ranked registered method (they treat every contact the model
        steps without a tolerance: a/b within Kalker's table, any friction law), both the built-in level."""
        strips = STRIPS_METHOD
        if ELLIPTIC_METHODS.get("strips") is not strips:
            return False
        return self.method == "strips" or ELLIPTIC_DISPATCHER.ranked()[0] is strips

    def chosen_together(self, rows) -> tuple[EllipticOutputs, ...]:
        """With a tolerance: each loaded contact's setting as :func:`rollcontact.solve_elliptic` chooses it with the
        parameters' tolerance and budget (the cheapest that meets the tolerance within :meth:`solve_budget`); the
        contacts whose choice is the built-in strips or linear theory with their defaults are solved together, the
        strips in one batch (:meth:`together_step`, :class:`~rollcontact.stepping.elliptic.linear.LinearContacts`), the
        others one by one (:meth:`contact_step`), each bit for bit its own solve (neither level escalates or falls
        back: the strips' and the linear theory's ladders hold one setting, and their estimates stay below
        :data:`~rollcontact.core.method.UNRESOLVED`).  A tolerance the choice does not meet is said once per contact,
        as the contact's own solve says it."""
        names = None if self.method == "auto" else (self.method,)
        chosen: dict[int, tuple] = {}
        for k, row in enumerate(rows):
            if row[0] == 0.0:
                continue
            scene = self.scene(k, *row)
            budget = self.solve_budget()
            try:
                setting = ELLIPTIC_DISPATCHER.cheapest_setting(scene, self.tolerance, names,
                                                               None if budget is None else Budget(budget))
            except ValueError:  # the contact's own solve says why
                continue
            spec = ELLIPTIC_METHODS.get(setting.method)
            if setting.options or spec is not BATCHED.get(setting.method) or (
                    setting.method == "linear" and self.linear_together is None):
                continue
            chosen[k] = (setting, scene)
        strips = [k for k, (setting, _) in chosen.items() if setting.method == "strips"]
        linear = [k for k, (setting, _) in chosen.items() if setting.method == "linear"]
        together = {}
        if strips:
            batch = self.together_step("strips", rows, strips, [chosen[k][1] for k in strips])
            together.update((k, batch[k]) for k in strips)
        if linear:
            together.update(zip(linear, self.linear_together.step([rows[k] for k in linear], linear), strict=True))
        outputs = []
        cost = 0.0
        for k, row in enumerate(rows):
            if k not in together:
                outputs.append(self.contact_step(k, *row))
                continue
            setting = chosen[k][0]
            if not setting.error_estimate <= self.tolerance:
                self.notice_once(f"tolerance {k}", f"{self.label(k)}the tolerance {self.tolerance!r} is not met within "
                                 f"the step budget {self.budget!r} s: {setting.method}'s error estimate is "
                                 f"{setting.error_estimate!r} (said once)")
            solves = 4 if self.parameters.jacobian == 1 and setting.method == "strips" else 1
            cost = max(cost, solves * setting.cost)
            if setting.method != "strips":  # together_step counted the strips' work
                self.last_work += setting.cost
            outputs.append(together[k])
        self.last_modelled_cost = max(self.last_modelled_cost, cost)
        return tuple(outputs)

    def non_finite(self, k: int, outputs: EllipticOutputs, row) -> str:
        """The message for contact ``k``'s outputs that are not all finite: which output, its value, the inputs."""
        name, value = next((n, v) for n, v in zip(EllipticOutputs._fields, outputs, strict=True)
                           if not math.isfinite(v))
        return self.beyond_floats(k, f"{name} = {value!r}", row)

    def beyond_floats(self, k: int, what: str, row) -> str:
        """The message for contact ``k`` whose ``what`` (a quantity and its value) is not finite at the inputs
        ``row``."""
        return (f"{self.label(k)}{what} is not finite at {inputs_text(row)}: these inputs with "
                f"youngs_modulus = {self.parameters.youngs_modulus!r} Pa are beyond what the level represents in "
                f"floating point (outputs up to {sys.float_info.max:.4g} in SI units)")

    def input_problems(self, current_time, step_size, inputs) -> list[str]:
        """Every invalid step argument: what, which value, which limit (with its contact)."""
        problems = time_problems(current_time, step_size)
        if len(inputs) != self.contacts:
            return [*problems, f"{len(inputs)} input rows for {self.contacts} contacts"]
        for k, row in enumerate(inputs):
            if len(row) not in (LOAD_INPUTS, len(INPUTS)):
                problems.append(f"{self.label(k)}{len(row)} inputs, not {LOAD_INPUTS} or {len(INPUTS)}")
                continue
            problems += argument_problems(((name, value, unit, lower, False)
                                           for (name, unit, lower), value in zip(INPUTS, row, strict=False)),
                                          self.label(k))
        return problems

    def scene(self, k: int, normal_load: float, xi: float, eta: float, phi: float, velocity: float) -> EllipticScene:
        """The scene of contact ``k`` (from 0) for the inputs."""
        A, B = self.curvatures[k]
        return EllipticScene(normal_load, A, B, xi, eta, phi, self.material, self.friction, velocity)

    def contact_constants(self, k: int) -> tuple:
        """What contact ``k``'s steps take from its curvatures alone: ``((A, B), constants, template, K)`` with the
        constants of :func:`~rollcontact.stepping.elliptic.linear.contact_constants`, its scene of no load and no
        creepage as a template and the elliptic integral K of its eccentricity; kept until the curvatures change."""
        A, B = self.curvatures[k]
        cached = self.constants_cache.get(k)
        if cached is None or cached[0] != (A, B):
            major_curvature, minor_curvature = (A, B) if A <= B else (B, A)
            cached = ((A, B), contact_constants(A, B, self.material.contact_modulus, self.material.poisson_ratio),
                      EllipticScene(0.0, A, B, material=self.material, friction=self.friction),
                      differences(eccentricity(minor_curvature / major_curvature))[2])
            self.constants_cache[k] = cached
        return cached

    def quick_scene(self, k: int, normal_load: float, xi: float, eta: float, phi: float,
                    velocity: float) -> EllipticScene:
        """:meth:`scene` of checked inputs (finite floats, load > 0) without checking them again, its Hertz ellipse
        from the contact's constants by :func:`~rollcontact.elliptic.hertz.hertz_ellipse`'s operations: the same
        scene and ellipse bit for bit, without their checks and the eccentricity's root per step."""
        _, constants, template, k_integral = self.contact_constants(k)
        major, denominator, g, pressure_scale, g_major, along_x = constants[:6]
        alpha = (3.0 * normal_load * major / denominator) ** (1.0 / 3.0)
        beta = g * alpha
        p0 = pressure_scale * alpha / g_major if alpha > 0.0 else 0.0
        a, b = (alpha, beta) if along_x else (beta, alpha)
        hertz = HertzEllipse(a, b, p0, p0 * beta * k_integral / self.material.contact_modulus,
                             1.0 / g if along_x else g)
        scene = object.__new__(EllipticScene)
        scene.__dict__.update(template.__dict__, normal_load=normal_load, longitudinal_creepage=xi,
                              lateral_creepage=eta, spin_creepage=phi, rolling_speed=velocity, hertz=hertz)
        return scene

    def contact_slopes(self, k: int, scene: EllipticScene) -> tuple[tuple[float, float, float], ...]:
        """:meth:`linear_slopes` from contact ``k``'s constants (Kalker's coefficients of its a/b), bit for bit."""
        c11, c22, c23, c33 = self.contact_constants(k)[1][6:]
        length = scene.hertz.c
        area = self.shear_modulus * length * length
        return ((area * c11, 0.0, 0.0),
                (0.0, area * c22, area * length * c23),
                (0.0, -area * length * c23, area * length * length * c33))

    def solve_budget(self) -> float | None:
        """The budget [s] within which a contact's solve is chosen: ``step_budget``, a quarter of it with ``jacobian``
        = difference (the three difference solves at the solve's setting take the rest), None without a budget."""
        if self.budget is not None and self.parameters.jacobian == 1:
            return 0.25 * self.budget
        return self.budget

    def solved(self, k: int, scene: EllipticScene, method: str, setting: dict | None = None):
        """:func:`rollcontact.solve_elliptic` of the scene with the parameters' tolerance and budget, or with a fixed
        ``setting`` (the options of an earlier solve: no choice, no budget); ModelError (naming the contact) when it
        fails.  With ``jacobian`` = difference the solve is chosen within a quarter of the step budget, so that the
        three difference solves at its setting fit in the rest (:meth:`differences`)."""
        try:
            if setting is None:
                result = solve_elliptic(scene, method, tolerance=self.tolerance, budget=self.solve_budget())
            else:
                result = solve_elliptic(scene, method, **setting)
        except ValueError as exc:
            raise ModelError(f"{self.label(k)}{exc} (at {scene_text(scene)})") from None
        except ArithmeticError as exc:
            raise ModelError(f"{self.label(k)}{method} cannot represent this contact in floating point "
                             f"({error_text(exc)}) at {scene_text(scene)} with "
                             f"youngs_modulus = {self.parameters.youngs_modulus!r} Pa") from None
        if not result.success:
            raise ModelError(f"{self.label(k)}{result.method} failed at {scene_text(scene)}: {result.message}")
        if setting is None and result.info.get("tolerance_met") is False:
            self.notice_once(f"tolerance {k}", f"{self.label(k)}the tolerance {self.tolerance!r} is not met within "
                             f"the step budget {self.budget!r} s: {result.method}'s error estimate is "
                             f"{result.info.get('error_estimate')!r} (said once)")
        return result

    def contact_step(self, k: int, normal_load: float, xi: float, eta: float, phi: float,
                     velocity: float) -> EllipticOutputs:
        """The outputs of contact ``k`` (from 0) for its inputs (module docstring)."""
        if normal_load == 0.0:
            return ZERO
        scene = self.scene(k, normal_load, xi, eta, phi, velocity)
        h = scene.hertz
        if not (math.isfinite(h.a) and math.isfinite(h.b) and math.isfinite(h.max_pressure)):
            raise ModelError(self.beyond_floats(k, f"the contact ellipse a = {h.a!r} m, b = {h.b!r} m, p0 = "
                                                   f"{h.max_pressure!r} Pa", (normal_load, xi, eta, phi, velocity)))
        result = self.solved(k, scene, self.method)
        forces = (result.longitudinal_force, result.lateral_force, result.spin_moment)
        slopes = self.linear_slopes(scene)
        jacobian = None
        cost = result.info.get("modelled_cost", result.info.get("predicted_cost", 0.0))
        if self.parameters.jacobian == 1 and method_code(result.method) != LEVEL_CODES["linear"]:
            jacobian, solves = self.differences(k, scene, result, forces, slopes)
            cost += solves * result.info.get("predicted_cost", 0.0)
        self.last_modelled_cost = max(self.last_modelled_cost, cost)
        self.last_work += cost
        if jacobian is None:
            jacobian = tuple(v for row in slopes for v in row)
        stick = result.info.get("stick_fraction", NO_STICK)
        power = velocity * (xi * forces[0] + eta * forces[1] + phi * forces[2])
        return EllipticOutputs(*forces, result.a, result.b, result.max_pressure, float(stick), power, *jacobian,
                               method_code(result.method))

    def together_step(self, level: str, rows, contacts, scenes=None) -> tuple[EllipticOutputs, ...]:
        """The loaded ones among ``contacts`` (indices) at ``level`` (strips or fastsim, with its defaults) in one
        solve of several scenes (:data:`MANY`; with ``jacobian`` = difference also the three shifted scenes of each),
        the outputs as :meth:`contact_step` makes them from each contact's own solve; the other contacts' outputs are
        :data:`ZERO`.  ``scenes``: those of the loaded contacts, when made already."""
        loaded = [k for k in contacts if rows[k][0] != 0.0]
        if not loaded:
            return (ZERO,) * len(rows)
        if scenes is None:
            scenes = [self.quick_scene(k, *rows[k]) for k in loaded]
        spec, solve_many = MANY[level]
        solves = 4 if self.parameters.jacobian == 1 else 1
        costs = [solves * spec.accuracy.cost(scene, {}) for scene in scenes]
        self.last_modelled_cost, self.last_work = max(costs), self.last_work + sum(costs)
        slopes = [self.contact_slopes(k, scene) for k, scene in zip(loaded, scenes, strict=True)]
        shifted = []
        if self.parameters.jacobian == 1:
            for scene, slope in zip(scenes, slopes, strict=True):
                increments = self.increments(scene, slope)
                if not usable(scene, increments):  # contact by contact, which says why once
                    raise FloatingPointError("the difference Jacobian's increments are not usable")
                shifted += [scene.replace(**{name: scene.creepages[j] + delta}) for j, name, delta in increments]
        results = solve_many(scenes + shifted)
        outputs = [ZERO] * len(rows)
        for i, (k, scene) in enumerate(zip(loaded, scenes, strict=True)):
            result = results[i]
            forces = (result.longitudinal_force, result.lateral_force, result.spin_moment)
            if self.parameters.jacobian == 1:
                others = results[len(scenes) + 3 * i:len(scenes) + 3 * i + 3]
                columns = [[(v - f) / delta for v, f in zip((r.longitudinal_force, r.lateral_force, r.spin_moment),
                                                            forces, strict=True)]
                           for r, (_, _, delta) in zip(others, self.increments(scene, slopes[i]), strict=True)]
                jacobian = tuple(columns[j][m] for m in range(3) for j in range(3))
            else:
                jacobian = tuple(v for row in slopes[i] for v in row)
            xi, eta, phi, velocity = rows[k][1:]
            power = velocity * (xi * forces[0] + eta * forces[1] + phi * forces[2])
            stick = float(result.info.get("stick_fraction", NO_STICK))
            outputs[k] = EllipticOutputs(*forces, result.a, result.b, result.max_pressure, stick, power, *jacobian,
                                         LEVEL_CODES[level])
        return tuple(outputs)

    def increments(self, scene: EllipticScene, slopes):
        """``(index, creepage name, increment)`` of the forward differences (:meth:`differences`); an increment is NaN
        where its slope is 0 (a load so small that the slope underflows) and may be infinite or shift its creepage
        beyond the floats (:func:`usable`)."""
        limit = scene.friction_coefficient * scene.normal_load
        return [(j, name, DIFFERENCE_STEP * (limit * (scene.hertz.c if j == 2 else 1.0) / slopes[j][j])
                 if slopes[j][j] != 0.0 else math.nan)
                for j, name in enumerate(("longitudinal_creepage", "lateral_creepage", "spin_creepage"))]

    def linear_slopes(self, scene: EllipticScene) -> tuple[tuple[float, float, float], ...]:
        """The linear theory's d(Fx, Fy, Mz)/d(xi, eta, phi) at the scene's ellipse: ``G c^2 C11``, ``G c^2 C22``,
        ``G c^3 C23`` (Fy of phi), ``-G c^3 C23`` (Mz of eta), ``G c^4 C33``, the others 0 (module docstring)."""
        h = scene.hertz
        c = creepage_coefficients(h.aspect_ratio, scene.material.poisson_ratio)
        length = h.c
        area = self.shear_modulus * length * length
        return ((area * c.c11, 0.0, 0.0),
                (0.0, area * c.c22, area * length * c.c23),
                (0.0, -area * length * c.c23, area * length * length * c.c33))

    def differences(self, k: int, scene: EllipticScene, result, forces,
                    slopes) -> tuple[tuple[float, ...] | None, int]:
        """Forward differences of the step's solve in each creepage, row-major (Fx, Fy, Mz) x (xi, eta, phi), each
        with the solve's own setting (``result.method`` and ``info["setting"]``); the increment
        :data:`DIFFERENCE_STEP` times ``mu Fn / slope`` (``mu Fn c`` for phi); and the number of solves run.

        The linear slopes stand in, said once: for the whole Jacobian where the increments are not positive finite
        numbers (a load so small that a slope underflows to 0) or where the budget does not pay the solves (their
        modelled cost must fit what the step's solve left of it, its failures and fallbacks included); for the
        column of a creepage the level cannot treat once it is shifted.
        ``(None, 0)``: the linear slopes for every column.
        """
        increments = self.increments(scene, slopes)
        if not usable(scene, increments):
            self.notice_once(f"jacobian {k}", f"{self.label(k)}the difference Jacobian's increments (mu Fn over the "
                             f"linear slopes) are {[delta for _, _, delta in increments]!r} at "
                             f"{scene_text(scene)}, not positive finite numbers: the linear theory's slopes stand in "
                             "(said once)")
            return None, 0
        spec = ELLIPTIC_METHODS[result.method]
        treated = []
        for j, name, delta in increments:
            moved = scene.replace(**{name: scene.creepages[j] + delta})
            why = spec.inapplicable(moved)
            if why is None:
                treated.append((j, delta, moved))
            else:
                self.notice_once(f"jacobian {k} {name}", f"{self.label(k)}{result.method} cannot take the {name} "
                                 f"increment of the difference Jacobian ({why}): its {COLUMNS[j]} column is the linear "
                                 "theory's slopes (said once)")
        setting = result.info.get("setting", {})
        if self.budget is not None:
            spent = result.info.get("modelled_cost", 0.0)
            each = result.info.get("predicted_cost", math.nan)
            if not spent + len(treated) * each <= self.budget:
                self.notice_once(f"jacobian {k}", f"{self.label(k)}the step budget {self.budget!r} s leaves no room "
                                 f"for the difference Jacobian of {result.method} ({len(treated)} solves modelled at "
                                 f"{each:.3g} s each after {spent:.3g} s): the linear theory's slopes stand in (said "
                                 "once)")
                return None, 0
        columns = [[slopes[i][j] for i in range(3)] for j in range(3)]
        for j, delta, moved in treated:
            solved = self.solved(k, moved, result.method, setting)
            values = (solved.longitudinal_force, solved.lateral_force, solved.spin_moment)
            columns[j] = [(values[i] - forces[i]) / delta for i in range(3)]
        return tuple(columns[j][i] for i in range(3) for j in range(3)), len(treated)


def usable(scene: EllipticScene, increments) -> bool:
    """Whether every increment of :meth:`EllipticModel.increments` is a positive finite number that leaves its
    creepage finite."""
    return all(0.0 < delta < math.inf and math.isfinite(scene.creepages[j] + delta) for j, _, delta in increments)


COLUMNS = ("xi", "eta", "spin")
"""The creepages of the Jacobian's columns, as messages name them."""


def inputs_text(row) -> str:
    """A contact's inputs ``(normal_load, longitudinal_creep, lateral_creep, spin, velocity)`` as messages name them
    (the FMU's input names)."""
    return (f"normal_load = {row[0]!r} N, longitudinal_creep = {row[1]!r}, lateral_creep = {row[2]!r}, spin = "
            f"{row[3]!r} 1/m, velocity = {row[4]!r} m/s")


def scene_text(scene: EllipticScene) -> str:
    """:func:`inputs_text` of a scene."""
    return inputs_text((scene.normal_load, *scene.creepages, scene.rolling_speed))
