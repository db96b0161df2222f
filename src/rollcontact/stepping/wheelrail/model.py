"""Stepping model of a wheelset's contact on real profiles for co-simulation: parameters -> (state, inputs, step) ->
outputs.

The library half of the ``WheelsetContact`` FMU (``fmu_src/WheelsetContact/rollcontact_fmu_wheelset_contact.py`` maps
its variables here and back, nothing else): a rigid wheelset of one wheel profile on a track of one rail profile
(:mod:`rollcontact.wheelrail`), whose lateral shift, yaw, velocities and wheel loads a host gives at each
communication point, and which answers with the loads of the rails on the wheelset.

* :class:`~rollcontact.stepping.wheelrail.parameters.WheelsetContactParameters` holds the fixed parameters and checks
  them all at once;
* :class:`WheelsetContactModel` evaluates one communication step, :meth:`WheelsetContactModel.step`, for the inputs
  sampled at ``t_n``:

  1. the pose: the rigid wheelset's roll and height at the lateral shift and yaw, where both wheels touch their
     rails, and each wheel's contact there (:func:`rollcontact.wheelrail.normal.rigid_contacts`: the roll's
     iteration scans the gap over the profiles, the root's scans are made into contact points), or, with
     ``geometry_table`` on, their lookup at the lateral shift in the table built at initialisation
     (:class:`rollcontact.wheelrail.conicity.ContactTable`, one yaw node: the yaw's effect on the geometry, the lead
     of a yawed flange's contact point, is left out);
  2. the contact: each wheel pressed down from the pose until it carries its vertical load, by the parameters'
     level, tolerance and step budget through :func:`rollcontact.wheelrail.dispatch.solve` (the scene
     :class:`rollcontact.wheelrail.scene.WheelRailScene` at the pose's roll, given the contact of step 1 rather
     than searching again).  With the table, the ``hertz`` level
     with a closed-form elliptic level (:data:`~rollcontact.stepping.wheelrail.parameters.TABULATED_LAWS`) and no
     tolerance is answered by the table's contact points in float arithmetic
     (:class:`rollcontact.wheelrail.tabulated.TabulatedWheelset`): one Hertzian contact per wheel, what depends on
     the geometry alone computed at every node once;
  3. the loads: the forces of the rails on the wheelset summed in track axes, their moments about its centre, the
     per-wheel forces, contact angle, rolling radius, patches and frictional power
     (:mod:`rollcontact.wheelrail.loads`), and the derivatives of ``force_y`` and ``moment_yaw`` in the lateral
     shift, yaw, lateral velocity and yaw rate by forward differences of the same evaluation
     (:data:`INCREMENTS`; with the table, the lateral shift's within the table's segment, so that the derivative
     never spans a jump of the contact point; the velocities' differences share the step's geometry, its contact
     and Hertz's normal contact, :meth:`rollcontact.wheelrail.scene.WheelRailScene.with_velocities`; every
     difference's normal problems start from the step's own solutions where its level can, the ``starts`` of
     :func:`rollcontact.wheelrail.wheels.solve_wheels`);

* :class:`WheelsetContactState` is what the model remembers: the last communication point and the number of steps.
  The outputs are a function of the parameters and the inputs alone (budgets are modelled costs, no clock is read),
  so a restored state repeats the steps bit for bit.

Bad input: a negative or non-finite input, or a loaded wheel at ``forward_speed`` = 0, is refused (ModelError naming
the value and the limit), as is a pose the geometry cannot treat (a flange climbing beyond the profiles' data, a
lateral shift outside the table).  A wheel of vertical load 0 is lifted: it carries nothing, its forces are 0 and the
model says so once while the other wheel is loaded (with both at 0 there is no contact and nothing to say).
"""

from __future__ import annotations

import hashlib
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rollcontact.core.materials import Material
from rollcontact.stepping.base import ModelError, SteppingModel, argument_problems, time_problems
from rollcontact.stepping.parameters import AUTO, friction_law
from rollcontact.stepping.wheelrail.parameters import (
    CARRIED_PROFILES,
    DEFAULT_RAIL,
    DEFAULT_WHEEL,
    ELLIPTIC_NAMES,
    INPUTS,
    METHOD_NAMES,
    TABLE_STEP,
    TABULATED_LAWS,
    WheelsetContactOutputs,
    WheelsetContactParameters,
    method_code,
)
from rollcontact.wheelrail import dispatch
from rollcontact.wheelrail.conicity import ContactFunctions, ContactTable, equivalent_conicity, harmonic_conicity
from rollcontact.wheelrail.geometry import Pose, Track, Wheelset
from rollcontact.wheelrail.loads import WheelsetLoads, wheelset_loads
from rollcontact.wheelrail.normal import rigid_contacts
from rollcontact.wheelrail.profiles import read_profile
from rollcontact.wheelrail.result import WheelRailResult
from rollcontact.wheelrail.scene import WheelRailScene
from rollcontact.wheelrail.tabulated import TabulatedWheelset

__all__ = ["INCREMENTS", "TABULATED_COST", "WheelsetContactModel", "WheelsetContactState"]

INCREMENTS = {"lateral_shift": 1e-6, "yaw": 1e-6, "lateral_velocity": 1e-6, "yaw_rate": 1e-6}
"""Forward-difference increments of the derivative outputs: 1 um of lateral shift, 1 urad of yaw, and 1e-6 V of the
lateral velocity [m/s] and 1e-6 V / Y_t of the yaw rate [rad/s] (V the forward speed, Y_t the taping line's lateral
coordinate): each changes the creepages by about 1e-6, small against their saturation values (mu Fn over the creep
coefficients, some 1e-3) and large against the forces' rounding."""

TABULATED_COST = 3.0e-4
"""Modelled time [s] of a step through the geometry table (the evaluation and its four differences): above the
medians of the FMU's whole steps through the table, fmpy's calls included, that ``benchmarks/bench_wheelset_contact.py``
measures (``benchmarks/results/wheelset_contact.md``, "hertz, saturated, table on"); what ``step_budget`` compares it
with."""

TABLE_CACHE = 4
"""Geometry tables kept per process (a sweep's worker runs one wheelset many times): keyed by the profiles' bytes and
every parameter of the geometry, so a table from the cache is the one a build would make."""

_tables: dict[tuple, ContactTable] = {}


@dataclass
class WheelsetContactState:
    """What a :class:`WheelsetContactModel` remembers between steps: the last communication point [s] and the steps
    taken (the steady contact has no other history)."""

    time: float
    steps: int = 0

    @classmethod
    def initial(cls, start_time: float) -> WheelsetContactState:
        """The state at ``start_time`` [s] before any step."""
        return cls(float(start_time))

    def copy(self) -> WheelsetContactState:
        return WheelsetContactState(self.time, self.steps)

    def to_dict(self) -> dict:
        """A JSON-compatible dict (:meth:`parse` reads it back)."""
        return {"version": 1, "time": self.time, "steps": self.steps}

    @classmethod
    def parse(cls, data) -> WheelsetContactState:
        """The state of :meth:`to_dict`'s dict, every field checked (ModelError naming the first problem)."""
        if not isinstance(data, dict) or set(data) != {"version", "time", "steps"}:
            keys = sorted(map(str, data)) if isinstance(data, dict) else type(data).__name__
            raise ModelError(f"a wheelset contact state has exactly the keys version, time, steps; got {keys}")
        if data["version"] != 1 or type(data["version"]) is not int:
            raise ModelError(f"wheelset contact state version {data['version']!r} is not supported (this reads 1)")
        time, steps = data["time"], data["steps"]
        if type(time) not in (int, float) or not math.isfinite(time):
            raise ModelError(f"wheelset contact state time = {time!r} must be a finite real number")
        if type(steps) is not int or steps < 0:
            raise ModelError(f"wheelset contact state steps = {steps!r} must be a whole number >= 0")
        return cls(float(time), steps)


def profile_path(given: str, default: str, folder: Path | None, name: str) -> Path:
    """The profile file of the parameter ``name``: ``default`` in ``folder`` (the carried profiles) when ``given``
    is "", else the path as given; ModelError when it names no regular file."""
    path = Path(folder if folder is not None else CARRIED_PROFILES, default) if given == "" else Path(given)
    if not path.is_file():
        raise ModelError(f"{name} = {given!r}: {str(path)!r} is not a profile file (give a .prw/.prr/.whl/.ban file, "
                         "or '' for the carried profile)")
    return path


def geometry_table(track: Track, wheelset: Wheelset, key: tuple, half_range: float) -> tuple[ContactTable, bool]:
    """The contact table of ``track`` and ``wheelset`` over ``[-half_range, half_range]`` m (one yaw node at 0,
    :data:`~rollcontact.stepping.wheelrail.parameters.TABLE_STEP`), built or from this process's cache (``key``
    names the geometry: :data:`TABLE_CACHE`); and whether it was built."""
    if key in _tables:
        return _tables[key], False
    table = ContactTable.build(track, wheelset, (-half_range, half_range), TABLE_STEP, yaws=(0.0,))
    while len(_tables) >= TABLE_CACHE:
        del _tables[next(iter(_tables))]
    _tables[key] = table
    return table, True


class WheelsetContactModel(SteppingModel):
    """The contact of a wheelset on real profiles, stepped (module docstring).

    Parameters
    ----------
    parameters : WheelsetContactParameters
        The fixed parameters (default: S1002 on UIC60 1:40, Hertz with the saturated linear theory, the table on).
    start_time : float
        The first communication point [s].
    profile_folder : Path, optional
        Where the default profiles are (an FMU's resources folder); the repository's ``models/wheelrail/profiles``
        when None.

    Raises
    ------
    ModelError
        A profile that cannot be read, a track or wheelset the geometry refuses, a table that cannot be built, an
        invalid material or friction law; the message names the value and the limit.
    """

    STATE = WheelsetContactState

    def __init__(self, parameters: WheelsetContactParameters | None = None, *, start_time: float = 0.0,
                 profile_folder: Path | str | None = None):
        p = WheelsetContactParameters() if parameters is None else parameters
        if not isinstance(p, WheelsetContactParameters):
            raise TypeError(f"parameters must be WheelsetContactParameters, got {type(p).__name__}")
        super().__init__(p)
        folder = None if profile_folder is None else Path(profile_folder)
        paths = (profile_path(p.wheel_profile, DEFAULT_WHEEL, folder, "wheel_profile"),
                 profile_path(p.rail_profile, DEFAULT_RAIL, folder, "rail_profile"))
        try:
            self.material = Material(p.youngs_modulus, p.poisson_ratio)
            self.friction = friction_law(p)
            wheel, rail = (read_profile(path) for path in paths)
            self.track = Track(rail, p.gauge, p.gauge_height, p.rail_inclination)
            self.wheelset = Wheelset(wheel, p.nominal_radius, p.flange_back_spacing, p.flange_back_distance)
        except ValueError as exc:
            raise ModelError(str(exc)) from None
        self.method = "auto" if p.method == AUTO else METHOD_NAMES[p.method]
        self.elliptic = "auto" if p.elliptic_method == AUTO else ELLIPTIC_NAMES[p.elliptic_method]
        self.options = {"elliptic": self.elliptic} if self.method == "hertz" else {}
        notices = []
        self.table = None
        if p.geometry_table:
            key = (*(hashlib.sha256(path.read_bytes()).hexdigest() for path in paths), p.gauge, p.gauge_height,
                   p.rail_inclination, p.flange_back_spacing, p.flange_back_distance, p.nominal_radius, p.table_range)
            try:
                self.table, built = geometry_table(self.track, self.wheelset, key, p.table_range)
            except ValueError as exc:
                raise ModelError(f"the geometry table over +-{p.table_range!r} m cannot be built: {exc}") from None
            functions = self.table.functions[0]
            jumps = ", ".join(f"{1e3 * j:+.4f}" for j in functions.jumps) or "none"
            notices.append(f"geometry table {'built' if built else 'taken from this process'}: {functions.shift.size} "
                           f"nodes over [{-p.table_range!r}, {p.table_range!r}] m, jumps of the contact point at "
                           f"{jumps} mm")
        self.tabulated = None
        if self.table is not None and self.method == "hertz" and self.elliptic in TABULATED_LAWS and \
                self.tolerance is None:
            self.tabulated = TabulatedWheelset(self.table, self.wheelset, self.material, self.friction, self.elliptic)
            if self.budget is not None and TABULATED_COST > self.budget:
                raise ModelError(f"step_budget = {self.budget!r} s is below the modelled cost {TABULATED_COST!r} s "
                                 "of a step through the geometry table")
        self.notices: tuple[str, ...] = tuple(notices)
        """Messages worth showing once at initialisation (the table's figures)."""
        self.last_modelled_cost = 0.0
        """The modelled work [s] of the last step (the tabulated step's, or the largest of its solves')."""
        self.reset(start_time)

    # geometry -----------------------------------------------------------------------------------------------------
    def pose(self, lateral_shift: float, yaw: float) -> Pose:
        """The rigid wheelset's pose at the lateral shift [m] and yaw [rad]: from the table (its yaw node), else
        :func:`rollcontact.wheelrail.normal.rigid_contacts`; ModelError where the geometry refuses it."""
        try:
            if self.table is not None:
                k, t, _ = self.table.locate(lateral_shift)
                rows = self.table.rows
                roll = float(rows[k, 0] + t * (rows[k + 1, 0] - rows[k, 0]))
                vertical = float(rows[k, 1] + t * (rows[k + 1, 1] - rows[k, 1]))
                return Pose(lateral_shift, yaw, roll, vertical)
            return rigid_contacts(self.track, self.wheelset, lateral_shift, yaw)[0]
        except ValueError as exc:
            raise ModelError(str(exc)) from None

    def contact_functions(self) -> ContactFunctions:
        """The rigid wheelset's contact functions over the table's lateral shifts (ModelError without a table)."""
        if self.table is None:
            raise ModelError("the contact functions are the geometry table's: set geometry_table = 1")
        return self.table.functions[0]

    def equivalent_conicity(self, amplitude: float, method: str = "harmonic") -> float:
        """The equivalent conicity [1] at the amplitude [m] (:func:`rollcontact.wheelrail.conicity.
        equivalent_conicity`, on the table's contact functions when there is a table)."""
        functions = self.table.functions[0] if self.table is not None else None
        try:
            return equivalent_conicity(self.track, self.wheelset, amplitude, method, functions=functions)
        except ValueError as exc:
            raise ModelError(str(exc)) from None

    def gravitational_stiffness(self, amplitude: float, load: float) -> float:
        """The lateral stiffness [N/m] of the contact angles' change at the amplitude [m] under the vertical load Q
        [N] per wheel: the harmonic linearisation (the describing function, as :meth:`equivalent_conicity`'s) of
        ``F(y) = -(Q - f23 / r0) (tan(delta_R(y)) - tan(delta_L(y)))``, the lateral components of the normal forces
        ``Q tan(delta)`` less the spin creep forces ``f23 sin(delta) / r0`` the contact angles bring (Wickens' wheelset
        on profiles; f23 of the centred contacts, :meth:`creep_coefficients`): what a linear analysis adds to the
        suspension's lateral stiffness (ModelError without a table)."""
        functions = self.contact_functions()
        f23 = self.creep_coefficients(0.0, load)[0][2]
        difference = np.tan(functions["right_contact_angle"]) - np.tan(functions["left_contact_angle"])
        try:
            slope = 2.0 * harmonic_conicity(functions.shift, difference, float(amplitude))
        except ValueError as exc:
            raise ModelError(str(exc)) from None
        return (load - f23 / self.wheelset.nominal_radius) * slope

    def creep_coefficients(self, lateral_shift: float, load: float) -> tuple[tuple[float, float, float, float], ...]:
        """Kalker's linear creep coefficients ``(f11, f22, f23, f33)`` [N, N, N m, N m^2] of the left and right
        wheels' tabulated contacts at the lateral shift [m] under the vertical load [N] per wheel: ``f11 = G c^2
        C11``, ``f22 = G c^2 C22``, ``f23 = G c^3 C23``, ``f33 = G c^4 C33`` on Hertz's ellipse of ``N = Q /
        cos(delta)`` (what a linear stability analysis of the wheelset takes; ModelError without a table)."""
        if self.table is None:
            raise ModelError("the tabulated contacts need the geometry table: set geometry_table = 1")
        tabulated = self.tabulated or TabulatedWheelset(self.table, self.wheelset, self.material, self.friction)
        row, _ = tabulated.row(lateral_shift)
        return tuple(tabulated.creep_coefficients(row, side, load) for side in ("left", "right"))

    # stepping -----------------------------------------------------------------------------------------------------
    def step(self, current_time: float, step_size: float, inputs) -> WheelsetContactOutputs:
        """Evaluate the contact for the inputs sampled at ``current_time``.

        Parameters
        ----------
        current_time : float
            Communication point t_n [s], not before the previous one.
        step_size : float
            h [s] > 0.
        inputs : sequence of float
            ``(lateral_shift [m], yaw [rad], lateral_velocity [m/s], yaw_rate [rad/s], forward_speed [m/s] >= 0,
            pitch_rate [rad/s], vertical_load_left [N] >= 0, vertical_load_right [N] >= 0)``, track axes.

        Returns
        -------
        WheelsetContactOutputs

        Raises
        ------
        ModelError
            Invalid inputs (every one named), time going backwards, a pose the geometry refuses, or a contact no
            allowed level solves within the budget.  The state is then unchanged.
        """
        inf = math.inf
        try:
            values = tuple(float(v) for v in inputs)
        except (TypeError, ValueError):
            values = None
        valid = values is not None and len(values) == len(INPUTS) and 0.0 < step_size < inf and \
            -inf < current_time < inf and all(-inf < v < inf for v in values) and values[4] >= 0.0 and \
            values[6] >= 0.0 and values[7] >= 0.0
        if not valid:
            raise ModelError("; ".join(self.input_problems(current_time, step_size, inputs)) or
                             f"invalid step inputs {inputs!r}")
        if values[4] == 0.0 and (values[6] > 0.0 or values[7] > 0.0):
            raise ModelError(f"forward_speed = 0.0 m/s with vertical loads {values[6]!r} N, {values[7]!r} N: a loaded "
                             "wheelset's creepages need forward_speed > 0")
        if current_time < self.state.time:
            raise ModelError(f"current_time = {current_time!r} s lies before the last communication point "
                             f"{self.state.time!r} s; restore a saved state to step from an earlier time")
        for side, load, other in (("left", values[6], values[7]), ("right", values[7], values[6])):
            if load == 0.0 and other > 0.0:
                self.notice_once(f"lifted {side}", f"the {side} wheel carries vertical_load_{side} = 0 N: lifted "
                                 "off its rail, its forces are 0 (said once)")
        self.last_modelled_cost = 0.0
        with np.errstate(all="ignore"):  # what overflows is refused below, by its output: no numpy warning
            outputs = self.evaluate(values)
        if not all(map(math.isfinite, outputs)):
            name, value = next((n, v) for n, v in zip(WheelsetContactOutputs._fields, outputs, strict=True)
                               if not math.isfinite(v))
            raise ModelError(f"{name} = {value!r} is not finite at the inputs {values!r} (outputs up to "
                             f"{sys.float_info.max:.4g} in SI units)")
        self.state.time = float(current_time)
        self.state.steps += 1
        return outputs

    def input_problems(self, current_time, step_size, inputs) -> list[str]:
        """Every invalid step argument: what, which value, which limit."""
        problems = time_problems(current_time, step_size)
        try:
            values = list(inputs)
        except TypeError:
            return [*problems, f"inputs must be {len(INPUTS)} numbers, got {inputs!r}"]
        if len(values) != len(INPUTS):
            return [*problems, f"{len(values)} inputs for the {len(INPUTS)} of {', '.join(n for n, _, _ in INPUTS)}"]
        return problems + argument_problems((name, value, unit, lower, False)
                                             for (name, unit, lower), value in zip(INPUTS, values, strict=True))

    def evaluate(self, values) -> WheelsetContactOutputs:
        """The outputs for checked inputs (module docstring)."""
        y, yaw, vy, rate, speed, pitch, left, right = values
        loaded = left > 0.0 or right > 0.0
        differences_on = loaded and self.parameters.jacobian == 0
        if self.tabulated is not None:
            try:
                row, shifted = self.tabulated.row(y, INCREMENTS["lateral_shift"] if differences_on else None)
                loads, roll, vertical = self.tabulated.loads(row, yaw, vy, rate, speed, pitch, left, right) \
                    if loaded else (ZERO_LOADS, row[0], row[1])
                derivatives = (0.0,) * 8
                if differences_on:
                    steps = (INCREMENTS["lateral_shift"], INCREMENTS["yaw"], INCREMENTS["lateral_velocity"] * speed,
                             INCREMENTS["yaw_rate"] * speed / self.wheelset.taping_line)
                    evaluate = self.tabulated.loads
                    others = (evaluate(shifted, yaw, vy, rate, speed, pitch, left, right, False),
                              evaluate(row, yaw + steps[1], vy, rate, speed, pitch, left, right, False),
                              evaluate(row, yaw, vy + steps[2], rate, speed, pitch, left, right, False),
                              evaluate(row, yaw, vy, rate + steps[3], speed, pitch, left, right, False))
                    derivatives = differences(loads, [(0.0, fy, 0.0, 0.0, 0.0, mz) for fy, mz in others], steps)
            except ValueError as exc:
                raise ModelError(f"{exc} at the inputs {values!r}") from None
            self.last_modelled_cost = TABULATED_COST
            code = method_code("hertz") if loaded else 0
            return WheelsetContactOutputs(*loads, roll, vertical, *derivatives, code)
        pose, contacts = self.placed(y, yaw)
        scene = self.scene(pose, values, contacts) if loaded else None
        loads, vertical, code, result = self.solved(scene, pose)
        derivatives = (0.0,) * 8
        if differences_on:
            steps = (INCREMENTS["lateral_shift"], INCREMENTS["yaw"], INCREMENTS["lateral_velocity"] * speed,
                     INCREMENTS["yaw_rate"] * speed / self.wheelset.taping_line)
            others = []
            for j, h in enumerate(steps):
                shifted = list(values)
                shifted[j] += h
                if j >= 2:  # the velocities: the same geometry, searched and pressed down once
                    try:
                        other = scene.with_velocities(lateral_velocity=shifted[2], yaw_rate=shifted[3])
                    except ValueError as exc:
                        raise ModelError(str(exc)) from None
                elif j == 0 and self.table is not None:  # the pose within the table's segment (module docstring)
                    k, t, width = self.table.locate(y)
                    rows = self.table.rows
                    moved = Pose(y + h, yaw, *((rows[k, i] + (t + h / width) * (rows[k + 1, i] - rows[k, i])) for i
                                               in (0, 1)))
                    other = self.scene(moved, shifted, None)
                else:
                    moved, moved_contacts = self.placed(shifted[0], shifted[1])
                    other = self.scene(moved, shifted, moved_contacts)
                others.append(self.solved(other, pose, result)[0])
            derivatives = differences(loads, others, steps)
        return WheelsetContactOutputs(*loads, pose.roll, vertical, *derivatives, code)

    def placed(self, lateral_shift: float, yaw: float) -> tuple[Pose, tuple | None]:
        """The rigid wheelset's pose at the lateral shift [m] and yaw [rad] (:meth:`pose`) and, without the table, its
        wheels' contact there (what the scene would search again, :func:`rollcontact.wheelrail.normal.
        rigid_contacts`); ModelError where the geometry refuses it."""
        if self.table is not None:
            return self.pose(lateral_shift, yaw), None
        try:
            pose, left, right = rigid_contacts(self.track, self.wheelset, lateral_shift, yaw)
        except ValueError as exc:
            raise ModelError(str(exc)) from None
        return pose, (left, right)

    def scene(self, pose: Pose, values, contacts: tuple | None) -> WheelRailScene:
        """The wheel/rail scene at ``pose`` (its roll) for the inputs, with the wheels' contact ``contacts`` found
        there (None: the scene searches); ModelError on a value it refuses."""
        y, yaw, vy, rate, speed, pitch, left, right = values
        try:
            scene = WheelRailScene(self.track, self.wheelset, pose.lateral_shift, pose.yaw, pose.roll, left, right,
                                   speed, vy, rate, pitch, self.material, self.friction)
            return scene if contacts is None else scene.with_contacts(contacts)
        except ValueError as exc:
            raise ModelError(str(exc)) from None

    def solved(self, scene: WheelRailScene | None, pose: Pose, starts: WheelRailResult | None = None
               ) -> tuple[WheelsetLoads, float, int, WheelRailResult | None]:
        """The loads, the vertical position [m], the level's code and the result of ``scene`` through
        :func:`rollcontact.wheelrail.dispatch.solve` (None, no load: zero loads at ``pose``'s vertical position, no
        result); ModelError when it fails.  ``starts``: the result of a scene of the same geometry whose patches'
        normal solutions this one's start from (:func:`rollcontact.wheelrail.wheels.solve_wheels`; taken where its
        level kept them)."""
        if scene is None:
            return ZERO_LOADS, pose.vertical, 0, None
        given = {"starts": starts} if starts is not None and any(w.normal_states for w in starts.wheels) else {}
        try:
            result = dispatch.solve(scene, self.method, tolerance=self.tolerance, budget=self.budget,
                                    **self.options, **given)
        except ValueError as exc:
            raise ModelError(str(exc)) from None
        if not result.success:
            raise ModelError(f"{result.method} failed: {result.message}")
        if result.info.get("tolerance_met") is False:
            self.notice_once("tolerance", f"the tolerance {self.tolerance!r} is not met within the step budget "
                             f"{self.budget!r} s: {result.method}'s error estimate is "
                             f"{result.info.get('error_estimate')!r} (said once)")
        cost = result.info.get("modelled_cost", result.info.get("predicted_cost", 0.0))
        self.last_modelled_cost = max(self.last_modelled_cost, cost)
        displacements = [w.vertical_displacement for w in result.wheels if w.patches]
        vertical = sum(displacements) / len(displacements) if displacements else pose.vertical
        return wheelset_loads(scene, result), vertical, method_code(result.method), result


ZERO_LOADS = WheelsetLoads(*(0.0,) * 12, 0, 0.0, *(0.0,) * 6, 0, 0.0)
"""The loads without load on either wheel."""

FORCE_Y = WheelsetLoads._fields.index("force_y")
MOMENT_YAW = WheelsetLoads._fields.index("moment_yaw")


def differences(loads: WheelsetLoads, others, steps) -> tuple[float, ...]:
    """``d force_y`` then ``d moment_yaw`` by each input of :data:`~rollcontact.stepping.wheelrail.parameters.
    DERIVED`: forward differences of the loads ``others`` at the increments ``steps``."""
    return (*((o[FORCE_Y] - loads[FORCE_Y]) / h for o, h in zip(others, steps, strict=True)),
            *((o[MOMENT_YAW] - loads[MOMENT_YAW]) / h for o, h in zip(others, steps, strict=True)))
