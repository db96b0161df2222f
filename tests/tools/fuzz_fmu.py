"""Fuzz of the contact FMUs through fmpy, seeded and repeatable: RollingContact2D, RollingContact3D, RollingContact3D_8,
WheelsetContact.

The targets: RollingContact2D (FMI 2.0), RollingContact3D, RollingContact3D_8 and WheelsetContact (FMI 2.0 and 3.0).

Usage::

    python tests/tools/fuzz_fmu.py [--seed 1] [--episodes N] [--steps S] [--fmu FILE ...] [--out FILE]
    python tests/tools/fuzz_fmu.py --quick                    # a few episodes per FMU (tests/fmu/test_fuzz.py)
    python tests/tools/fuzz_fmu.py --target RollingContact3D_8/3 --episode 17   # replay one episode

Without ``--fmu`` the FMUs are built by ``build_fmu.py --dest <tmp>`` (``--fmi 2,3 --only RollingContact3D``,
``--fmi 2,3 --contacts 8``, ``--fmi 2,3 --only WheelsetContact`` and the default RollingContact2D); each ``--fmu``
file is one target, named after its model and FMI version (``RollingContact3D_8/3``).
``benchmarks/fuzz_campaign.py`` runs the long campaign and writes ``benchmarks/results/fuzz.md``.  The exit status is
1 when there is a finding.

An episode is a function of the seed, its target and its index alone (``numpy.random.default_rng([seed, target,
episode])``; no clock decides anything): instantiate, set random parameters (mostly valid; extreme: 0, tiny, huge,
a/b at the ends of its range; one episode in eight invalid: NaN, inf, negative, codes out of range, a/b outside [0.1,
10], friction tables that are none), initialise, then take random operations.  Steps carry inputs from zero to 1e9,
NaN, inf and negative values, unloaded contacts (some or all), step sizes from 1e-12 s to 1e6 s; between them: state
get/set with restore -> step -> restore -> step (the same bits), serialise/deserialise, corrupted bytes (truncated, a
flipped byte, garbage, empty), crafted states (a field replaced, a valid checksum; an integer code as a JSON bool),
a fixed parameter set after initialisation, a communication point inside the last step, a value reference that does
not exist, an FMI 3.0 array set with the wrong count, and a reset (the first step after it must repeat the
episode's first step bit for bit).  After the episodes, instantiate/free cycles count the memory left per instance.

3D parameters range over every ``method`` level (auto, linear, FASTSIM, strips, discretised, saturated), both
``jacobian`` modes, the five friction laws and the rail conditions, tolerances and step budgets (0: none).
WheelsetContact's over its levels (auto, hertz with every elliptic level, strips, discretised), the geometry table on
and off, both ``jacobian`` modes, the friction laws, the track and wheelset at the ends of their ranges and profile
files that are none (missing, a folder, /dev/zero, a rail for a wheel, an empty file); its inputs over the tread and
the flange, beyond the table and the profiles, lifted wheels, yaw, speeds and loads from zero to 1e12.

Findings (each a row of the report):

* ``fatal``: a call answered with Error or Fatal (an exception reached pythonfmu), the worker dying or hanging;
* ``non-finite``: a step answered OK with a non-finite output;
* ``friction``: an OK step whose tangential force exceeds mu Fn (1 + 1e-9), mu the law's largest value (the linear
  level, which has no friction limit, apart); WheelsetContact: a wheel's force beyond ``sqrt(1 + mu^2) N``;
* ``unloaded``: an OK step whose unloaded contact has an output other than 0 (WheelsetContact: a lifted wheel's
  forces, or a loaded wheel without a patch);
* ``load``, ``sum`` (WheelsetContact): a loaded wheel whose vertical force misses its load by more than 1 %; a
  wheelset force that is not the wheels' sum;
* ``level``: an OK step of a named level answered by another;
* ``message``: a refusal (a message of status Discard or Error) that names no value or cause: Python's own error text
  without a variable and its value, a bare errno, "no registered method can solve" without the methods' reasons, an
  invalid input not named (with its contact), or a non-finite quantity that is no variable of the FMU;
* ``state``: a corrupted state accepted, a bool accepted as an integer code, a refused state, late parameter, unknown
  value reference, wrong count or inner communication point not followed by a Discard, a valid state refused, or
  restore -> step not repeating the outputs;
* ``ordinary``: an ordinary step discarded, or (3D) not repeating its first outputs bit for bit, after an extreme or
  invalid step or a reset, although it was accepted at the start of the episode (an instance unusable after bad
  input);
* ``warning``: a Python warning (a numpy overflow, say) during a step, or anything written to standard error;
* ``slow``: with ``--strict-time``, a step more than 10 times its stated worst case, at the shortest of three runs
  from the state before it (the replays undone, so the episode does not depend on the clock).  The stated worst
  case: ``step_budget`` per contact (2D: per step) in modelled seconds, counted as seconds, plus 0.02 s for the call;
  none where docs/fmu.md states none (no budget; the 2D ``table`` = on; the 2D polynomial method with
  velocity-dependent friction on a corrugation).  Without
  ``--strict-time`` (the default) such steps are reported apart, never as findings, since a wall clock decides them;
* ``memory``: more than 40 Python memory blocks left per instantiate/free cycle;
* ``exit``: the worker process ended by a signal after its last result.

Steps slower than their stated worst case, and the slowest steps without one, are listed apart.
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import hashlib
import io
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before numpy: one BLAS thread, as the tests
os.environ.setdefault("OMP_NUM_THREADS", "1")

ROOT = Path(__file__).resolve().parents[2]
OK, WARNING, DISCARD, ERROR, FATAL = range(5)
STATUS_NAMES = {OK: "OK", WARNING: "Warning", DISCARD: "Discard", ERROR: "Error", FATAL: "Fatal"}
TARGETS = (
    "RollingContact2D/2",
    "RollingContact3D/2",
    "RollingContact3D/3",
    "RollingContact3D_8/2",
    "RollingContact3D_8/3",
    "WheelsetContact/2",
    "WheelsetContact/3",
)
"""The targets of a campaign, model/FMI version, in the order the episodes' seeds number them."""
CAMPAIGN = {"RollingContact2D": 100, "RollingContact3D": 130, "RollingContact3D_8": 130, "WheelsetContact": 100}
QUICK = {"RollingContact2D": 16, "RollingContact3D": 5, "RollingContact3D_8": 4, "WheelsetContact": 3}
"""Episodes per target of a campaign and of ``--quick``."""
FRICTION_TOLERANCE = 1e-9
"""Relative excess of |F| over mu Fn that counts as a finding (rounding of the sums over a level's elements)."""
STEP_OVERHEAD = 0.02
"""Seconds a step may take beyond its modelled work in the stated worst case: the FMI call, the slave's checks."""
SLOW_FACTOR = 10.0
"""A step this many times its stated worst case is a finding with ``--strict-time``."""
REPLAYS = 2
"""Runs more of a step over :data:`SLOW_FACTOR` times its worst case, from the state before it: the shortest counts."""
MEMORY_BLOCKS = 40
"""Python memory blocks left per instantiate/free cycle that count as a finding."""


# ----------------------------------------------------------------------------------------------------- the FMUs
class Host:
    """One FMU through fmpy, FMI 2.0 (``FMU2Slave``) or 3.0 (``FMU3Slave``): variables by name, per-contact values
    in either form (FMI 2.0 ``name[k]``, FMI 3.0 arrays), steps with their status, states and the log."""

    def __init__(self, unzipped: str, description):
        self.version = int(description.fmiVersion[0])
        self.description = description
        self.variables = {v.name: v for v in description.modelVariables}
        self.model = description.modelName
        self.log: list[tuple[int, str]] = []
        kwargs = {
            "guid": description.guid,
            "unzipDirectory": unzipped,
            "instanceName": "fuzz",
            "modelIdentifier": description.coSimulation.modelIdentifier,
        }
        if self.version == 2:
            from fmpy.fmi2 import FMU2Slave, defaultCallbacks, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE

            self.fmu = FMU2Slave(**kwargs)
            self.callbacks = fmi2CallbackFunctions()
            self.callbacks.logger = fmi2CallbackLoggerTYPE(self.logger2)
            self.callbacks.allocateMemory = defaultCallbacks.allocateMemory
            self.callbacks.freeMemory = defaultCallbacks.freeMemory
        else:
            from fmpy.fmi3 import FMU3Slave

            self.fmu = FMU3Slave(**kwargs)
        self.contacts = max((int(v.dimensions[0].start) for v in description.modelVariables if v.dimensions), default=1)
        if self.contacts == 1:
            self.contacts = sum(1 for name in self.variables if name.startswith("normal_load[")) or 1
        self.arrays = any(v.dimensions for v in description.modelVariables)

    def logger2(self, environment, name, status, category, message):
        self.log.append((status, message.decode(errors="replace").replace("%%", "%")))

    def logger3(self, environment, status, category, message):
        self.log.append((status, message.decode(errors="replace")))

    # life cycle ---------------------------------------------------------------------------------------------------
    def instantiate(self) -> None:
        if self.version == 2:
            self.fmu.instantiate(callbacks=self.callbacks, loggingOn=True)
        else:
            self.fmu.instantiate(loggingOn=True, logMessage=self.logger3)

    def initialise(self, start_time: float = 0.0) -> None:
        if self.version == 2:
            self.fmu.setupExperiment(None, start_time)
            self.fmu.enterInitializationMode()
        else:
            self.fmu.enterInitializationMode(startTime=start_time)
        self.fmu.exitInitializationMode()

    def reset(self) -> None:
        self.fmu.reset()

    def free(self) -> None:
        """Terminate and free the instance, the library staying loaded for the next (fmpy's ``freeInstance`` would
        unload it)."""
        with contextlib.suppress(Exception):
            self.fmu.terminate()
        if self.version == 2:
            self.fmu.fmi2FreeInstance(self.fmu.component)
        else:
            self.fmu.fmi3FreeInstance(self.fmu.component)

    def do_step(self, t: float, h: float) -> int:
        """The step's status (OK, or the status of fmpy's exception)."""
        from fmpy.fmi1 import FMICallException

        try:
            self.fmu.doStep(t, h)
            return OK
        except FMICallException as exc:
            return exc.status

    # variables ----------------------------------------------------------------------------------------------------
    def kind(self, name: str) -> str:
        """``Real``, ``Integer``, ``Enumeration`` or ``String`` of a variable (FMI 3.0's types mapped)."""
        kind = self.variables[name].type
        return {"Float64": "Real", "Int32": "Integer"}.get(kind, kind)

    def vr(self, name: str) -> int:
        return self.variables[name].valueReference

    def names(self, base: str) -> list[str]:
        """The variables of per-contact ``base``: ``[base]`` (one contact, or an FMI 3.0 array), else ``base[k]``."""
        if self.contacts == 1 or base in self.variables:
            return [base]
        return [f"{base}[{k}]" for k in range(1, self.contacts + 1)]

    def setter(self, kind: str):
        if self.version == 2:
            return {
                "Real": self.fmu.setReal,
                "Integer": self.fmu.setInteger,
                "Enumeration": self.fmu.setInteger,
                "String": self.fmu.setString,
            }[kind]
        return {
            "Real": self.fmu.setFloat64,
            "Integer": self.fmu.setInt32,
            "Enumeration": self.fmu.setInt64,
            "String": self.fmu.setString,
        }[kind]

    def getter(self, kind: str):
        if self.version == 2:
            return {
                "Real": self.fmu.getReal,
                "Integer": self.fmu.getInteger,
                "Enumeration": self.fmu.getInteger,
                "String": self.fmu.getString,
            }[kind]
        return {
            "Real": self.fmu.getFloat64,
            "Integer": self.fmu.getInt32,
            "Enumeration": self.fmu.getInt64,
            "String": self.fmu.getString,
        }[kind]

    def size(self, name: str) -> int:
        v = self.variables[name]
        return int(v.dimensions[0].start) if v.dimensions else 1

    def set(self, base: str, value) -> None:
        """Set a shared variable, or every contact's of per-contact ``base`` (``value``: a list of one per
        contact)."""
        names = self.names(base)
        kind = self.kind(names[0])
        values = list(value) if isinstance(value, list) else [value]
        if len(names) == 1 and self.size(names[0]) == len(values):
            self.setter(kind)([self.vr(names[0])], values)
        else:
            self.setter(kind)([self.vr(n) for n in names], values)

    def get(self, base: str):
        """A scalar variable's value, or the list of every contact's (per-contact ``base`` of several contacts)."""
        names = self.names(base)
        kind = self.kind(names[0])
        if len(names) > 1:
            values = self.getter(kind)([self.vr(n) for n in names])
        elif self.size(names[0]) > 1:
            values = self.getter(kind)([self.vr(names[0])], self.size(names[0]))
        else:
            values = self.getter(kind)([self.vr(names[0])])
        values = [v.decode() if isinstance(v, bytes) else v for v in values]
        return values if len(names) > 1 or self.size(names[0]) > 1 else values[0]

    def set_rows(self, bases: tuple[str, ...], rows) -> None:
        """Set the Real inputs ``bases`` of every contact, ``rows[k]`` contact k's values (one call)."""
        if self.arrays:
            self.setter("Real")([self.vr(b) for b in bases], [float(row[i]) for i in range(len(bases)) for row in rows])
        else:
            self.setter("Real")(
                [self.vr(n) for k in range(self.contacts) for n in (self.names(b)[k] for b in bases)],
                [float(v) for row in rows for v in row],
            )

    def get_rows(self, bases: tuple[str, ...]) -> list[list]:
        """The outputs ``bases`` of every contact, a row per contact (integers as they are)."""
        columns = []
        for base in bases:
            value = self.get(base)
            columns.append(value if isinstance(value, list) else [value])
        return [[column[k] for column in columns] for k in range(self.contacts)]

    # states -------------------------------------------------------------------------------------------------------
    def get_state(self):
        return self.fmu.getFMUstate() if self.version == 2 else self.fmu.getFMUState()

    def set_state(self, state) -> None:
        (self.fmu.setFMUstate if self.version == 2 else self.fmu.setFMUState)(state)

    def free_state(self, state) -> None:
        (self.fmu.freeFMUstate if self.version == 2 else self.fmu.freeFMUState)(state)

    def serialise(self, state) -> bytes:
        return bytes((self.fmu.serializeFMUstate if self.version == 2 else self.fmu.serializeFMUState)(state))

    def deserialise(self, data: bytes):
        return (self.fmu.deSerializeFMUstate if self.version == 2 else self.fmu.deserializeFMUState)(data)


# ------------------------------------------------------------------------------------------------------ generation
def log_uniform(rng, low: float, high: float) -> float:
    return float(math.exp(rng.uniform(math.log(low), math.log(high))))


TABLES = ("0 0.4; 1 0.3; 5 0.15; 30 0.1", "0 0.3", "0 0.6; 0.01 0.59; 1e6 0.05")
"""Tabulated friction laws the fuzz draws: falling, constant, a steep fall at once."""


def draw_friction(rng, p: dict, custom: float, tables: list[str]) -> None:
    """A rail condition (a quarter of the draws) or, up to the share ``custom``, a friction law of random parameters
    (a tabulated law one of ``tables``) into the parameters ``p``; else Coulomb friction."""
    law = rng.random()
    if law < 0.25:
        p["rail_condition"] = int(rng.integers(1, 3))
    elif law < custom:
        p["friction_law"] = int(rng.integers(1, 5))
        p["friction_kinetic_ratio"] = float(rng.uniform(0.05, 1.0))
        p["friction_decay"] = log_uniform(rng, 1e-3, 50.0)
        p["friction_reference_velocity"] = log_uniform(rng, 1e-2, 100.0)
        p["friction_slope"] = log_uniform(rng, 1e-3, 10.0)
        if p["friction_law"] == 4:
            p["friction_table"] = pick(rng, tables)


def pick(rng, values):
    """One of ``values`` (any objects), uniformly."""
    return values[int(rng.integers(0, len(values)))]


class Profile2D:
    """What the fuzz draws and checks for RollingContact2D (``quick``: no table built at the first loaded step and no
    step without a budget, which may take seconds)."""

    def __init__(self, quick: bool = False):
        self.quick = quick

    inputs = ("normal_load", "creep", "velocity")
    outputs = (
        "tangential_force",
        "traction_coefficient",
        "contact_half_width",
        "stick_half_width",
        "contact_offset",
        "max_pressure",
        "frictional_power",
        "creep_stiffness",
        "stationarity",
        "method_used",
        "axis_position",
    )
    ordinary = (5e4, 1e-3, 10.0)
    late = {
        "youngs_modulus": 1e11,
        "radius": 0.2,
        "friction_coefficient": 0.5,
        "method": 2,
        "transient": 1,
        "tolerance": 1e-2,
    }
    stateless = False  # the axis position and the instationary models remember

    def draw_parameters(self, rng, contacts: int) -> tuple[dict, str | None]:
        """Parameters (those that differ from the defaults) and the name of an invalid one, if any."""
        p: dict = {}
        if rng.random() < 0.3:
            p["method"] = int(rng.integers(0, 4))
        if rng.random() < 0.3:
            p["transient"] = int(rng.integers(0, 3))
        if rng.random() < 0.25:
            p["friction_law"] = 1
            p["friction_kinetic_ratio"] = float(rng.uniform(0.2, 1.0))
            p["friction_decay"] = log_uniform(rng, 0.1, 20.0)
        if rng.random() < 0.3:
            p["corrugation_amplitude"] = log_uniform(rng, 1e-7, 5e-5)
            p["corrugation_wavelength"] = log_uniform(rng, 0.005, 0.2)
            p["corrugation_phase"] = float(rng.uniform(-math.pi, math.pi))
        if rng.random() < 0.2:
            p["tolerance"] = float(pick(rng, [1e-2, 3e-3, 1e-3]))
        if rng.random() < 0.2:
            p["elements"] = int(pick(rng, [20, 40, 80]))
        if rng.random() < 0.15:
            p["step_budget"] = float(pick(rng, [1e-3, 0.01] if self.quick else [0.0, 1e-3, 0.01]))
        if rng.random() < 0.2:
            p["table"] = int(rng.integers(0, 2 if self.quick else 3))
        if rng.random() < 0.3:  # a material, wheel or friction at the edge of its range
            name = pick(
                rng,
                [
                    "youngs_modulus",
                    "radius",
                    "friction_coefficient",
                    "contact_width",
                    "poisson_ratio",
                    "initial_position",
                ],
            )
            p[name] = {
                "youngs_modulus": lambda: log_uniform(rng, 1e6, 1e13),
                "radius": lambda: log_uniform(rng, 1e-3, 50.0),
                "friction_coefficient": lambda: log_uniform(rng, 1e-4, 5.0),
                "contact_width": lambda: log_uniform(rng, 1e-5, 10.0),
                "poisson_ratio": lambda: float(pick(rng, [0.0, 0.4999999])),
                "initial_position": lambda: float(pick(rng, [-1e6, 1e-300, 1e9])),
            }[name]()
        invalid = None
        if rng.random() < 0.125:
            invalid, value = pick(
                rng,
                [
                    ("youngs_modulus", -1.0),
                    ("radius", 0.0),
                    ("friction_coefficient", -0.1),
                    ("poisson_ratio", 0.5),
                    ("corrugation_wavelength", 0.0),
                    ("friction_law", 7),
                    ("method", 9),
                    ("contact_width", math.nan),
                    ("tolerance", math.inf),
                    ("scene_file", "/dev/zero"),
                    ("scene_file", "/nonexistent.toml"),
                    ("scene_file", "/"),
                ],
            )
            p[invalid] = value
        return p, invalid

    def draw_inputs(self, rng, contacts: int) -> tuple[float, list, str, str | None]:
        """``(h, rows, kind, invalid)``: kind "valid", "extreme" or "invalid", invalid the variable made invalid."""
        kind = str(pick(rng, ["valid"] * 12 + ["extreme"] * 5 + ["invalid"] * 3))
        h = log_uniform(rng, 1e-5, 1e-2)
        load, creep, speed = log_uniform(rng, 1e2, 3e5), float(rng.normal(0.0, 2e-3)), log_uniform(rng, 0.1, 60.0)
        if rng.random() < 0.1:
            load = 0.0
        bad = None
        if kind == "extreme":
            which = int(rng.integers(0, 4))
            if which == 0:
                load = float(pick(rng, [5e-324, 1e-300, 1e-12, 1e9, 1e12, 1e100, 1e300]))
            elif which == 1:
                creep = float(pick(rng, [-1.0, 1.0])) * float(pick(rng, [1e-300, 1e-12, 0.5, 1e3, 1e300]))
            elif which == 2:
                speed = float(pick(rng, [0.0, 1e-300, 1e3, 1e6, 1e300]))
            else:
                h = float(pick(rng, [1e-12, 1e-9, 1.0, 10.0, 1e6]))
        elif kind == "invalid":
            bad, value = pick(
                rng,
                [
                    ("normal_load", -1.0),
                    ("normal_load", math.nan),
                    ("normal_load", math.inf),
                    ("creep", math.nan),
                    ("creep", -math.inf),
                    ("velocity", -0.5),
                    ("velocity", math.nan),
                    ("step_size", 0.0),
                    ("step_size", -1e-3),
                    ("step_size", math.nan),
                ],
            )
            if bad == "normal_load":
                load = value
            elif bad == "creep":
                creep = value
            elif bad == "velocity":
                speed = value
            else:
                h = value
        return h, [(load, creep, speed)], kind, bad

    def friction_limit(self, host: Host) -> float:
        """mu of the law in force (a crafted state brings its own): the largest of both laws at zero slip."""
        return host.get("friction_coefficient")

    def check(self, episode, rows, outputs) -> None:
        load = rows[0][0]
        force = outputs[0][0]
        if "scene_file" not in episode.parameters and abs(force) > self.friction_limit(episode.host) * load:
            episode.find("friction", f"|T| = {abs(force)!r} > mu N (N = {load!r})")

    def step_bound(self, parameters: dict, contacts: int) -> float | None:
        """The stated worst case of a step [s]: the step budget in modelled seconds plus the call (None: none stated,
        docs/fmu.md: no budget; ``table`` = on, which builds at the first loaded step; the polynomial method with
        velocity-dependent friction on a corrugation that may split the contact, or a scene file)."""
        budget = parameters.get("step_budget", 0.05)
        if not (isinstance(budget, float) and 0.0 < budget < math.inf) or parameters.get("table") == 2:
            return None
        falling = parameters.get("friction_law", 0) != 0 and parameters.get("method", 0) in (0, 2)
        if "scene_file" in parameters or falling and parameters.get("corrugation_amplitude", 0.0) > 0.0:
            return None
        return budget + STEP_OVERHEAD

    def episode_length(self, parameters: dict, steps: int) -> int:
        return steps


class Profile3D:
    """What the fuzz draws and checks for RollingContact3D and RollingContact3D_n."""

    inputs = ("normal_load", "longitudinal_creep", "lateral_creep", "spin", "velocity")
    outputs = (
        "longitudinal_force",
        "lateral_force",
        "spin_moment",
        "semi_axis_longitudinal",
        "semi_axis_lateral",
        "max_pressure",
        "stick_fraction",
        "frictional_power",
        "dFx_dxi",
        "dFx_deta",
        "dFx_dphi",
        "dFy_dxi",
        "dFy_deta",
        "dFy_dphi",
        "dMz_dxi",
        "dMz_deta",
        "dMz_dphi",
        "method_used",
    )
    ordinary = (5e4, 1e-3, 5e-4, 0.0, 10.0)
    late = {
        "youngs_modulus": 1e11,
        "friction_coefficient": 0.5,
        "method": 1,
        "jacobian": 1,
        "tolerance": 1e-2,
        "step_budget": 0.02,
        "curvature_longitudinal": 2.0,
    }
    stateless = True  # a steady contact: the same inputs give the same outputs after anything
    LINEAR, STRIPS, DISCRETISED = 1, 3, 4
    """``method`` codes of the linear theory (no friction limit), the strips and the discretised level."""

    def __init__(self, rail_mu: dict[int, float], quick: bool = False):
        self.rail_mu = rail_mu
        self.quick = quick

    def draw_parameters(self, rng, contacts: int) -> tuple[dict, str | None]:
        """Parameters (those that differ from the defaults; per-contact ones as lists) and the name of an invalid one,
        if any."""
        p: dict = {"method": int(rng.integers(0, 6))}
        if rng.random() < 0.4:
            p["jacobian"] = 1
        draw_friction(rng, p, 0.55, [*TABLES[:2], "0 0.2; 2 0.5", TABLES[2]])
        if rng.random() < 0.25:
            p["tolerance"] = float(pick(rng, [0.3, 0.1, 0.03, 0.01, 1e-3, 1e-9]))
        budgets = [1e-9, 1e-6, 1e-4, 1e-3, 0.01, 0.05, 0.1, 0.2] + (
            [0.0, 1.0] if contacts == 1 and not self.quick else []
        )
        if rng.random() < 0.4:
            p["step_budget"] = float(pick(rng, budgets))
        if p["method"] == self.DISCRETISED or p.get("tolerance", 1.0) < 0.03:  # room for the discretised level
            p["step_budget"] = float(
                pick(rng, [0.05, 0.1, 0.2] + ([0.0, 0.5] if contacts == 1 and not self.quick else []))
            )
        if rng.random() < 0.3:  # a material or friction at the edge of its range
            name = pick(rng, ["youngs_modulus", "poisson_ratio", "friction_coefficient"])
            p[name] = {
                "youngs_modulus": lambda: float(pick(rng, [1e-300, 1e-3, log_uniform(rng, 1e3, 1e15), 1e300])),
                "poisson_ratio": lambda: float(pick(rng, [0.0, 0.25, 0.4999999])),
                "friction_coefficient": lambda: float(pick(rng, [1e-300, 1e-6, log_uniform(rng, 1e-3, 5.0), 1e6])),
            }[name]()
        longitudinal, lateral = [], []
        for _ in range(contacts):  # a/b from about 0.11 to 8.9 (curvature ratios up to 30), sizes from 1e-3 to 1e3
            a = log_uniform(rng, 1e-3, 1e3) if rng.random() < 0.2 else log_uniform(rng, 0.2, 20.0)
            longitudinal.append(a)
            lateral.append(
                a * (float(pick(rng, [1 / 30, 30.0])) if rng.random() < 0.15 else log_uniform(rng, 1 / 30, 30.0))
            )
        p["curvature_longitudinal"], p["curvature_lateral"] = longitudinal, lateral
        invalid = None
        if rng.random() < 0.125:
            invalid, value = pick(
                rng,
                [
                    ("youngs_modulus", -1.0),
                    ("youngs_modulus", 0.0),
                    ("youngs_modulus", math.nan),
                    ("youngs_modulus", math.inf),
                    ("poisson_ratio", 0.5),
                    ("poisson_ratio", -0.1),
                    ("friction_coefficient", 0.0),
                    ("friction_coefficient", -0.1),
                    ("friction_coefficient", math.nan),
                    ("friction_law", 7),
                    ("friction_law", -1),
                    ("friction_kinetic_ratio", 1.5),
                    ("friction_kinetic_ratio", 0.0),
                    ("friction_decay", -1.0),
                    ("friction_reference_velocity", 0.0),
                    ("friction_slope", math.inf),
                    ("method", 9),
                    ("method", -1),
                    ("tolerance", -1.0),
                    ("tolerance", math.nan),
                    ("step_budget", -1.0),
                    ("step_budget", math.inf),
                    ("jacobian", 2),
                    ("rail_condition", 3),
                    ("curvature_longitudinal", 0.0),
                    ("curvature_lateral", -1.0),
                    ("curvature_lateral", math.nan),
                    ("curvature_lateral", math.inf),
                    ("a/b", 1e-3),
                    ("a/b", 1e3),
                    ("friction_table", ""),
                    ("friction_table", "1 0.3; 0 0.2"),
                    ("friction_table", "0 -0.3"),
                    ("friction_table", "x y"),
                    ("friction_table", "0 nan"),
                ],
            )
            if invalid.startswith("curvature") or invalid == "a/b":  # one contact's
                k = int(rng.integers(0, contacts))
                if invalid == "a/b":
                    p["curvature_lateral"][k] = p["curvature_longitudinal"][k] * value
                else:
                    p[invalid][k] = value
            elif invalid == "friction_table":
                p.pop("rail_condition", None)
                p["friction_law"], p["friction_table"] = 4, value
            else:
                p[invalid] = value
        return p, invalid

    def draw_inputs(self, rng, contacts: int) -> tuple[float, list, str, str | None]:
        """``(h, rows, kind, invalid)``: a row per contact; kind "valid", "extreme" or "invalid", invalid the
        variable made invalid (``step_size`` or an input name with its contact)."""
        kind = str(pick(rng, ["valid"] * 12 + ["extreme"] * 5 + ["invalid"] * 3))
        h = log_uniform(rng, 1e-5, 1e-2)
        base = (
            log_uniform(rng, 1e2, 3e5),
            float(rng.normal(0.0, 3e-3)),
            float(rng.normal(0.0, 3e-3)),
            float(rng.normal(0.0, 0.5)) if rng.random() < 0.6 else 0.0,
            log_uniform(rng, 0.1, 60.0),
        )
        rows = []
        for _ in range(contacts):  # the contacts of a vehicle: alike, each its own
            rows.append(
                [
                    base[0] * float(rng.uniform(0.5, 1.5)),
                    base[1] + float(rng.normal(0.0, 1e-3)),
                    base[2] + float(rng.normal(0.0, 1e-3)),
                    base[3] * float(rng.uniform(0.5, 1.5)),
                    base[4],
                ]
            )
        unloaded = rng.random()
        if unloaded < 0.08:
            for row in rows:
                row[0] = 0.0
        elif unloaded < 0.25:
            for row in rows:
                if rng.random() < 0.4:
                    row[0] = 0.0
        bad = None
        if kind == "extreme":
            k = int(rng.integers(0, contacts))
            which = int(rng.integers(0, 6))
            if which == 0:
                rows[k][0] = float(pick(rng, [5e-324, 1e-300, 1e-12, 1e-3, 1e6, 1e9]))
            elif which in (1, 2):
                rows[k][which] = float(pick(rng, [-1.0, 1.0])) * float(pick(rng, [1e-300, 1e-12, 0.5, 1.0, 1e3, 1e9]))
            elif which == 3:
                rows[k][3] = float(pick(rng, [-1.0, 1.0])) * float(pick(rng, [1e-300, 1e-6, 20.0, 1e3, 1e9]))
            elif which == 4:
                rows[k][4] = float(pick(rng, [0.0, 1e-300, 1e3, 1e9]))
            else:
                h = float(pick(rng, [1e-12, 1e-9, 1.0, 1e6]))
        elif kind == "invalid":
            k = int(rng.integers(0, contacts))
            which, value = pick(
                rng,
                [
                    (0, -1.0),
                    (0, math.nan),
                    (0, math.inf),
                    (1, math.nan),
                    (2, -math.inf),
                    (3, math.nan),
                    (3, math.inf),
                    (4, -0.5),
                    (4, math.nan),
                    (5, 0.0),
                    (5, -1e-3),
                    (5, math.nan),
                ],
            )
            if which == 5:
                h, bad = value, "step_size"
            else:
                rows[k][which] = value
                bad = f"contact {k + 1}: {self.inputs[which]}" if contacts > 1 else self.inputs[which]
        return h, [tuple(row) for row in rows], kind, bad

    def friction_limit(self, host: Host) -> float:
        """mu of the law in force at zero slip, the largest value of every law (a tabulated law: its largest point;
        a crafted state brings its own parameters)."""
        condition = host.get("rail_condition")
        if condition in self.rail_mu:
            return self.rail_mu[condition]
        if host.get("friction_law") == 4:
            try:
                return max(float(point.split()[1]) for point in host.get("friction_table").split(";"))
            except (ValueError, IndexError):
                return math.inf
        return host.get("friction_coefficient")

    def check(self, episode, rows, outputs) -> None:
        host, p = episode.host, episode.parameters
        mu = None
        method = p.get("method", 0) if episode.crafted == "" else None
        for k, (row, out) in enumerate(zip(rows, outputs, strict=True)):
            load, used = row[0], out[-1]
            where = f"contact {k + 1}" if len(rows) > 1 else "the contact"
            if load == 0.0:
                if any(v != 0 for v in out):
                    episode.find("unloaded", f"{where} without load: outputs {out}")
                continue
            if method and used != method:
                episode.find("level", f"{where}: method = {method} answered by method_used = {used}")
            if used == self.LINEAR:
                continue
            mu = self.friction_limit(host) if mu is None else mu
            force = math.hypot(out[0], out[1])
            if force > mu * load * (1.0 + FRICTION_TOLERANCE):
                episode.find(
                    "friction",
                    f"{where}: |F| = {force!r} > mu Fn = {mu * load!r} (method_used {used}, "
                    f"|F| / (mu Fn) - 1 = {force / (mu * load) - 1.0:.3g})",
                )

    def step_bound(self, parameters: dict, contacts: int) -> float | None:
        """The stated worst case of a step [s]: the step budget per contact in modelled seconds plus the call (None:
        none stated, docs/fmu.md: no budget)."""
        budget = parameters.get("step_budget", 0.05)
        if not (isinstance(budget, float) and 0.0 < budget < math.inf):
            return None
        return contacts * budget + STEP_OVERHEAD

    def episode_length(self, parameters: dict, steps: int) -> int:
        """Fewer operations where no budget bounds a step (``step_budget`` 0: docs/fmu.md says it may be slow)."""
        return min(steps, 6) if parameters.get("step_budget") == 0.0 else steps


WHEEL_OUTPUTS = (
    "normal_force",
    "longitudinal_force",
    "lateral_force",
    "vertical_force",
    "contact_angle",
    "rolling_radius",
    "patches",
    "frictional_power",
)
"""WheelsetContact's outputs of each wheel, ``<name>_left`` and ``<name>_right``."""


class ProfileWheelset:
    """What the fuzz draws and checks for WheelsetContact: the wheelset's pose, velocities and wheel loads on the
    profiles carried in its resources (or others, or files that are no profiles), every level, the geometry table on
    and off."""

    inputs = (
        "lateral_shift",
        "yaw",
        "lateral_velocity",
        "yaw_rate",
        "forward_speed",
        "pitch_rate",
        "vertical_load_left",
        "vertical_load_right",
    )
    outputs = (
        "force_x",
        "force_y",
        "force_z",
        "moment_roll",
        "moment_pitch",
        "moment_yaw",
        *(f"{name}_{side}" for side in ("left", "right") for name in WHEEL_OUTPUTS),
        "roll",
        "vertical_position",
        "dforce_y_dlateral_shift",
        "dforce_y_dyaw",
        "dforce_y_dlateral_velocity",
        "dforce_y_dyaw_rate",
        "dmoment_yaw_dlateral_shift",
        "dmoment_yaw_dyaw",
        "dmoment_yaw_dlateral_velocity",
        "dmoment_yaw_dyaw_rate",
        "method_used",
    )
    RADIUS = 0.46
    """The default nominal radius [m]: pure rolling's pitch rate is ``-V / RADIUS``."""
    ordinary = (1e-3, 0.0, 0.0, 0.0, 10.0, -10.0 / RADIUS, 5e4, 5e4)
    late = {
        "youngs_modulus": 1e11,
        "friction_coefficient": 0.5,
        "method": 2,
        "gauge": 1.44,
        "geometry_table": 0,
        "step_budget": 0.02,
        "wheel_profile": "MBench_S1002_v3.prw",
    }
    stateless = True  # steady contact: the same inputs give the same outputs after anything
    DISCRETISED = 3
    """``method`` code of the discretised level (seconds a step: drawn rarely, in short episodes)."""
    LOAD_TOLERANCE = 1e-2
    """Relative difference of a loaded wheel's vertical force from its load beyond which a step is a finding: the
    levels meet the load to 1e-5 (the strips' normal force steps by a few 1e-4 where lobes merge), the table's
    interpolation to its stated error."""

    def __init__(self, rail_mu: dict[int, float], quick: bool = False):
        self.rail_mu = rail_mu
        self.quick = quick

    def draw_parameters(self, rng, contacts: int) -> tuple[dict, str | None]:
        """Parameters (those that differ from the defaults) and the name of an invalid one, if any."""
        p: dict = {}
        if rng.random() < 0.6:
            p["method"] = int(pick(rng, [0, 1, 1, 2, 2] + ([] if self.quick else [self.DISCRETISED])))
        if rng.random() < 0.3:
            p["elliptic_method"] = int(rng.integers(0, 6))
        if rng.random() < 0.3:
            p["geometry_table"] = 0
        if rng.random() < 0.3 and p.get("method") != self.DISCRETISED:
            p["jacobian"] = 1
        draw_friction(rng, p, 0.45, list(TABLES))
        if rng.random() < 0.2:
            p["tolerance"] = float(pick(rng, [0.3, 0.1, 0.03, 0.01]))
        if rng.random() < 0.3:
            p["step_budget"] = float(pick(rng, [1e-9, 1e-4, 1e-3, 0.01, 0.05, 0.2]))
        if p.get("method") == self.DISCRETISED:
            p["step_budget"] = float(pick(rng, [0.5, 2.0]))
        if rng.random() < 0.35:  # the track, the wheelset or the material at the edge of its range
            name = pick(
                rng,
                [
                    "gauge",
                    "gauge_height",
                    "rail_inclination",
                    "flange_back_spacing",
                    "flange_back_distance",
                    "nominal_radius",
                    "table_range",
                    "rail_profile",
                    "youngs_modulus",
                    "poisson_ratio",
                    "friction_coefficient",
                ],
            )
            p[name] = {
                "gauge": lambda: float(pick(rng, [0.5, 1.0, rng.uniform(1.425, 1.445), 2.0, 3.0])),
                "gauge_height": lambda: float(pick(rng, [0.0, 0.01, 0.05])),
                "rail_inclination": lambda: float(pick(rng, [-0.2, -0.025, 0.025, 0.2])),
                "flange_back_spacing": lambda: float(pick(rng, [0.3, rng.uniform(1.355, 1.365), 1.5, 3.0])),
                "flange_back_distance": lambda: float(pick(rng, [0.0, 0.065, 0.075, 0.2])),
                "nominal_radius": lambda: float(pick(rng, [0.05, rng.uniform(0.3, 0.6), 5.0])),
                "table_range": lambda: float(pick(rng, [1e-6, 1e-3, 0.02, 0.05])),
                "rail_profile": lambda: str(pick(rng, ["MBench_UIC60_v3.ban", "MBench_UIC60_v3.prr"])),
                "youngs_modulus": lambda: float(pick(rng, [1e-300, 1e-3, log_uniform(rng, 1e3, 1e15), 1e300])),
                "poisson_ratio": lambda: float(pick(rng, [0.0, 0.25, 0.4999999])),
                "friction_coefficient": lambda: float(pick(rng, [1e-300, 1e-6, log_uniform(rng, 1e-3, 5.0), 1e6])),
            }[name]()
        invalid = None
        if rng.random() < 0.15:
            invalid, value = pick(
                rng,
                [
                    ("wheel_profile", "/nonexistent.prw"),
                    ("wheel_profile", "/"),
                    ("wheel_profile", "/dev/zero"),
                    ("wheel_profile", "MBench_UIC60_v3.prr"),
                    ("rail_profile", "/dev/null"),
                    ("rail_profile", "/etc/hostname"),
                    ("gauge", 0.4),
                    ("gauge", math.nan),
                    ("nominal_radius", 0.0),
                    ("flange_back_spacing", math.inf),
                    ("table_range", 0.0),
                    ("youngs_modulus", -1.0),
                    ("poisson_ratio", 0.5),
                    ("friction_coefficient", 0.0),
                    ("friction_law", 7),
                    ("method", 9),
                    ("elliptic_method", 7),
                    ("geometry_table", 3),
                    ("jacobian", 2),
                    ("rail_condition", 3),
                    ("tolerance", -1.0),
                    ("step_budget", math.nan),
                    ("friction_table", "1 0.3; 0 0.2"),
                ],
            )
            if invalid == "friction_table":
                p.pop("rail_condition", None)
                p["friction_law"] = 4
            p[invalid] = value
        return p, invalid

    def draw_inputs(self, rng, contacts: int) -> tuple[float, list, str, str | None]:
        """``(h, [row], kind, invalid)``: kind "valid", "extreme" or "invalid", invalid the variable made invalid."""
        kind = str(pick(rng, ["valid"] * 12 + ["extreme"] * 5 + ["invalid"] * 3))
        h = log_uniform(rng, 1e-5, 1e-2)
        speed = log_uniform(rng, 0.5, 60.0)
        row = [
            float(rng.normal(0.0, 3e-3)),
            float(rng.normal(0.0, 1e-3)),
            float(rng.normal(0.0, 0.05)),
            float(rng.normal(0.0, 0.05)),
            speed,
            -speed / self.RADIUS * (1.0 + float(rng.normal(0.0, 2e-3))),
            log_uniform(rng, 1e3, 2e5),
            log_uniform(rng, 1e3, 2e5),
        ]
        lifted = rng.random()
        if lifted < 0.05:
            row[6] = row[7] = 0.0
        elif lifted < 0.15:
            row[int(rng.integers(6, 8))] = 0.0
        bad = None
        if kind == "extreme":
            which = int(rng.integers(0, 8))
            sign = float(pick(rng, [-1.0, 1.0]))
            if which == 0:
                row[0] = sign * float(pick(rng, [1e-300, 0.009, 0.012, 0.02, 0.1, 1e3]))
            elif which == 1:
                row[1] = sign * float(pick(rng, [1e-300, 0.02, 0.2, 1.5, 1e3]))
            elif which in (2, 3):
                row[which] = sign * float(pick(rng, [1e-300, 10.0, 1e6]))
            elif which == 4:
                row[4] = float(pick(rng, [0.0, 1e-300, 1e3, 1e9]))
                row[5] = -row[4] / self.RADIUS if rng.random() < 0.5 else row[5]
            elif which == 5:
                row[5] = float(pick(rng, [0.0, 1e-300, 1e6, -1e9]))
            elif which == 6:
                row[int(rng.integers(6, 8))] = float(pick(rng, [5e-324, 1e-300, 1e-3, 1e7, 1e9, 1e12]))
            else:
                h = float(pick(rng, [1e-12, 1e-9, 1.0, 1e6]))
        elif kind == "invalid":
            which, value = pick(
                rng,
                [
                    (0, math.nan),
                    (0, math.inf),
                    (1, -math.inf),
                    (2, math.nan),
                    (3, math.inf),
                    (4, -0.5),
                    (4, math.nan),
                    (5, math.nan),
                    (6, -1.0),
                    (7, math.nan),
                    (7, math.inf),
                    (8, 0.0),
                    (8, -1e-3),
                    (8, math.nan),
                ],
            )
            if which == 8:
                h, bad = value, "step_size"
            else:
                row[which], bad = value, self.inputs[which]
        return h, [tuple(row)], kind, bad

    def friction_limit(self, host: Host) -> float:
        """mu of the law in force at zero slip, the largest value of every law (as :class:`Profile3D`'s)."""
        return Profile3D.friction_limit(self, host)

    def check(self, episode, rows, outputs) -> None:
        """Per wheel: none of its forces without load, else at least a patch, the vertical force its load (to
        :data:`LOAD_TOLERANCE`) and ``|F| <= sqrt(1 + mu^2) N`` (each patch's force within its friction cone); the
        wheelset's forces the wheels' sums; the level asked for answers."""
        row, out = rows[0], dict(zip(self.outputs, outputs[0], strict=True))
        p = episode.parameters
        method = p.get("method", 1) if episode.crafted == "" else None
        if method and out["method_used"] not in (0, method):
            episode.find("level", f"method = {method} answered by method_used = {out['method_used']}")
        mu = None
        elliptic = p.get("elliptic_method", 5)
        # the linear theory (no friction limit) may answer: its forces may leave the cone and miss the load
        unlimited = episode.crafted != "" or elliptic == 1 or elliptic == 0 and "tolerance" in p
        for side, load in (("left", row[6]), ("right", row[7])):
            wheel = {name: out[f"{name}_{side}"] for name in WHEEL_OUTPUTS}
            forces = (wheel["longitudinal_force"], wheel["lateral_force"], wheel["vertical_force"])
            if load == 0.0:
                if any(v != 0 for v in (*forces, wheel["normal_force"], wheel["patches"], wheel["frictional_power"])):
                    episode.find("unloaded", f"the {side} wheel without load: {wheel}")
                continue
            if wheel["patches"] < 1 or not wheel["normal_force"] > 0.0:
                episode.find("unloaded", f"the {side} wheel loaded with {load!r} N has no contact: {wheel}")
                continue
            if unlimited:
                continue
            if abs(abs(wheel["vertical_force"]) / load - 1.0) > self.LOAD_TOLERANCE:
                episode.find("load", f"the {side} wheel carries {wheel['vertical_force']!r} N for {load!r} N")
            mu = self.friction_limit(episode.host) if mu is None else mu
            size = math.sqrt(sum(f * f for f in forces))
            if size > math.sqrt(1.0 + mu * mu) * wheel["normal_force"] * (1.0 + FRICTION_TOLERANCE):
                episode.find("friction", f"the {side} wheel: |F| = {size!r} > sqrt(1 + mu^2) N, N = "
                             f"{wheel['normal_force']!r}, mu = {mu!r}")
        for total, name in (("force_x", "longitudinal_force"), ("force_y", "lateral_force"),
                            ("force_z", "vertical_force")):
            parts = out[f"{name}_left"] + out[f"{name}_right"]
            scale = abs(out[f"{name}_left"]) + abs(out[f"{name}_right"])
            if abs(out[total] - parts) > 1e-9 * scale:
                episode.find("sum", f"{total} = {out[total]!r}, the wheels' sum {parts!r}")

    def step_bound(self, parameters: dict, contacts: int) -> float | None:
        """None: ``step_budget`` bounds each solve of a step, the contact search lies outside it (docs/fmu.md,
        WheelsetContact, Cost), and no worst case of a step is stated."""
        return None

    def episode_length(self, parameters: dict, steps: int) -> int:
        """Fewer operations with the discretised level (seconds a step)."""
        return min(steps, 6) if parameters.get("method") == self.DISCRETISED else steps


def corrupt(rng, data: bytes) -> tuple[bytes, str]:
    """Corrupted serialised state bytes and how they were corrupted."""
    how = str(pick(rng, ["truncate", "flip", "garbage", "empty", "nonutf8"]))
    if how == "truncate":
        return data[: int(rng.integers(0, len(data)))], how
    if how == "flip":
        at = int(rng.integers(0, len(data)))
        return data[:at] + bytes([data[at] ^ int(rng.integers(1, 256))]) + data[at + 1 :], how
    if how == "garbage":
        return bytes(rng.integers(0, 256, int(rng.integers(1, 200))).astype("uint8")), how
    if how == "empty":
        return b"", how
    return b"\xff\xfe\xfd" + data[3:], how


def with_checksum(state: dict) -> bytes:
    """The serialised form of ``state``: JSON with sorted keys and its SHA-256 (docs/fmu-internals.md)."""
    state = {k: v for k, v in state.items() if k != "sha256"}
    text = json.dumps(state, sort_keys=True)
    return json.dumps({**state, "sha256": hashlib.sha256(text.encode()).hexdigest()}, sort_keys=True).encode()


def craft(rng, data: bytes, integers: list[str]) -> tuple[bytes, str, bool]:
    """The state with one field replaced by a random JSON value, with a valid checksum; how; and whether it must be
    refused (an integer code of ``integers`` as a JSON bool)."""
    state = json.loads(data)
    if integers and rng.random() < 0.3:
        name = pick(rng, integers)
        value = bool(rng.random() < 0.5)
        state["variables"][name] = (
            [value] * len(state["variables"][name]) if isinstance(state["variables"][name], list) else value
        )
        return with_checksum(state), f"variables/{name} = {value}", True
    state.pop("sha256", None)
    paths = []

    def walk(node, path):
        if isinstance(node, dict):
            for key, value in node.items():
                paths.append((*path, key))
                walk(value, (*path, key))
        elif isinstance(node, list):
            for index, value in enumerate(node):
                paths.append((*path, index))
                walk(value, (*path, index))

    walk(state, ())
    path = paths[int(rng.integers(0, len(paths)))]
    value = pick(rng, [None, math.nan, math.inf, -1, 0, 1e308, "x", [], {}, True, False, "/dev/zero", 2**40, -1e-300])
    node = state
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    if rng.random() < 0.2 and isinstance(node, dict):
        node["log"] = 0  # an unknown key beside it
    return with_checksum(state), "/".join(map(str, path)) + f" = {value!r}", False


# ---------------------------------------------------------------------------------------------- refusal messages
PYTHON_TEXTS = (
    "division by zero",
    "math domain error",
    "index out of range",
    "has no attribute",
    "'NoneType'",
    "unsupported operand",
    "not subscriptable",
    "object is not iterable",
    "unhashable type",
    "positional argument",
    "referenced before assignment",
    "Traceback",
    "maximum recursion",
    "could not convert",
    "invalid literal",
)
"""Python's own error texts: a refusal showing one must also name a variable and its value."""


def vague(message: str, variables) -> str | None:
    """Why a refusal ``message`` names no value or cause (None: it does)."""
    reason = message.split(" discarded: ", 1)[-1]
    named = re.search(r"\b([A-Za-z_]\w*(?:\[\d+\])?) = ", reason) is not None
    if re.search(r"\(\d+, '[^']*'\)", reason) or re.search(r"\[Errno \d+\][^/']*$", reason):
        return "a bare errno"
    if any(text in reason for text in PYTHON_TEXTS) and not named:
        return "Python's error text without a variable and its value"
    if "no registered method can solve" in reason and not re.search(r"no registered method can solve[^(]*\(\w", reason):
        return "no registered method can solve, without the methods' reasons"
    known = set(variables) | {name.split("[")[0] for name in variables} | {"current_time", "step_size"}
    quantities = re.findall(r"\b([A-Za-z_]\w*) = (?:nan|-?inf) is not finite", reason)
    if any(name not in known for name in quantities) and not any(f"{name} = " in reason for name in known):
        return f"{quantities[0]} is no variable of the FMU, and none is named"
    if len(reason.strip()) < 12:
        return "too short to say anything"
    return None


# ------------------------------------------------------------------------------------------------------- the worker
class Dead(Exception):
    """The instance answered Error or Fatal: pythonfmu left it broken, the episode ends."""


class Episode:
    """One instance of a target driven by one episode's random generator; its statistics and findings."""

    def __init__(self, host: Host, profile, target: int, index: int, seed: int, steps: int):
        import numpy as np

        self.host, self.profile, self.index = host, profile, index
        self.rng = np.random.default_rng([seed, target, index])
        self.steps_wanted = steps
        self.findings: list[dict] = []
        self.found: set[tuple[str, str]] = set()
        self.statuses = collections.Counter()  # step statuses
        self.kinds = collections.Counter()  # (input kind, status)
        self.ops = collections.Counter()
        self.errors = 0  # emulated errors: messages of status Error
        self.reasons = collections.Counter()  # Discards of valid inputs with valid parameters, numbers as #
        self.times: list[float] = []
        self.over: list[dict] = []  # steps over their stated worst case
        self.unbounded: list[float] = []  # step times without a budget
        self.previous = self.current = None  # the last steps (context of a finding)
        self.crafted = ""  # the field of the last crafted state that was accepted
        self.parameters: dict = {}
        self.invalid: str | None = None
        self.refused: str | None = None  # why valid parameters were refused at the first step
        self.ordinary_ok = False
        self.t = 0.0
        self.seen_log = 0
        self.strict_time = False

    def find(self, kind: str, detail: str) -> None:
        """Record a finding (once per kind and detail in the episode), with the steps and the parameters."""
        if (kind, detail) in self.found:
            return
        self.found.add((kind, detail))
        context = f"; step: {self.current}" if self.current else ""
        previous = f"; the step before: {self.previous}" if self.previous else ""
        parameters = f"; parameters {self.shown()}"
        self.findings.append(
            {
                "kind": kind,
                "episode": self.index,
                "detail": (detail[:500] + context + previous)[:900] + parameters[:700],
            }
        )

    def shown(self) -> str:
        return "{" + ", ".join(f"{k}: {v!r}" for k, v in self.parameters.items()) + "}"

    def call(self, what: str, function, *args):
        """``function(*args)``; an Error or Fatal status is a finding and ends the episode."""
        from fmpy.fmi1 import FMICallException

        try:
            return function(*args)
        except FMICallException as exc:
            if exc.status >= ERROR:
                self.find(
                    "fatal", f"{what}: status {STATUS_NAMES.get(exc.status, exc.status)}; log {self.host.log[-1:]}"
                )
                raise Dead from None
            return None

    def new_log(self) -> list[tuple[int, str]]:
        """The messages logged since the last call; each refusal's is checked (:func:`vague`)."""
        entries = self.host.log[self.seen_log :]
        self.seen_log = len(self.host.log)
        for status, message in entries:
            if status == ERROR:
                self.errors += 1
            if status in (DISCARD, ERROR) and (why := vague(message, self.host.variables)) is not None:
                self.find("message", f"{why}: {message[:400]!r}")
        return entries

    # steps ----------------------------------------------------------------------------------------------------------
    def step(self, h: float, rows, kind: str, bad: str | None = None) -> tuple[int, list | None, str]:
        """One step from ``self.t``: ``(status, outputs per contact or None, last message)``; the time advances after
        an OK step."""
        self.previous = self.current
        self.current = f"{kind} doStep(t={self.t!r}, h={h!r}) inputs {rows}"
        self.call("set inputs", self.host.set_rows, self.profile.inputs, rows)
        self.new_log()
        before = self.call("getFMUstate", self.host.get_state) if self.strict_time else None
        started = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            status = self.host.do_step(self.t, h)
        elapsed = time.perf_counter() - started
        log = self.new_log()
        message = log[-1][1] if log else ""
        self.current += f" -> {STATUS_NAMES.get(status, status)}"
        self.statuses[status] += 1
        self.kinds[(kind, status)] += 1
        self.times.append(elapsed)
        for warning in caught:  # the test suite treats a numpy warning in a solver as a numerical defect
            self.find(
                "warning",
                f"{warning.category.__name__} at {Path(warning.filename).name}:{warning.lineno}: "
                f"{warning.message}" + (f" after the crafted state {self.crafted}" if self.crafted else ""),
            )
        if status >= ERROR:
            self.find("fatal", f"doStep: status {STATUS_NAMES.get(status, status)}; {message}")
            raise Dead
        try:
            self.time_step(elapsed, rows, status, lambda: self.retimed(before, h, elapsed))
        finally:
            if before is not None:
                self.call("freeFMUstate", self.host.free_state, before)
        if status != OK:
            if (
                bad is not None
                and bad not in message
                and "invalid parameters" not in message
                and "error state" not in message
            ):
                self.find("message", f"the invalid {bad} is not named: {message[:400]!r}")
            if status == DISCARD and kind == "valid" and self.invalid is None and self.ordinary_ok:
                self.reasons[masked(message)] += 1
            return status, None, message
        if bad is not None:
            self.find("state", f"the invalid {bad} was accepted")
        outputs = self.call("get outputs", self.host.get_rows, self.profile.outputs)
        if not all(math.isfinite(v) for row in outputs for v in row):
            self.find("non-finite", f"OK step with outputs {outputs}")
        else:
            self.profile.check(self, rows, outputs)
        self.t += h
        return status, outputs, message

    def retimed(self, before, h: float, elapsed: float) -> float:
        """The step's shortest time: ``elapsed`` and :data:`REPLAYS` more runs from the state ``before`` it, each
        undone (the episode goes on from the step's own result), so that another job's interruption is not taken for
        the step's work."""
        after = self.call("getFMUstate", self.host.get_state)
        times = [elapsed]
        try:
            for _ in range(REPLAYS):
                self.call("setFMUstate (replay)", self.host.set_state, before)
                started = time.perf_counter()
                self.host.do_step(self.t, h)
                times.append(time.perf_counter() - started)
            self.call("setFMUstate (after the replays)", self.host.set_state, after)
        finally:
            self.call("freeFMUstate", self.host.free_state, after)
        self.new_log()
        return min(times)

    def time_step(self, elapsed: float, rows, status: int, retime) -> None:
        """Set a step's time against its stated worst case (reported apart; a finding with ``--strict-time`` when its
        shortest time over replays, ``retime()``, is beyond :data:`SLOW_FACTOR` times it)."""
        if not any(row[0] != 0.0 for row in rows):
            return
        bound = self.profile.step_bound(self.parameters, len(rows)) if not self.crafted else None
        if bound is None:
            self.unbounded.append(elapsed)
            return
        if elapsed > bound:
            self.over.append(
                {
                    "episode": self.index,
                    "seconds": elapsed,
                    "bound": bound,
                    "status": status,
                    "step": self.current,
                    "parameters": self.shown()[:400],
                }
            )
            if self.strict_time and elapsed > SLOW_FACTOR * bound and (shortest := retime()) > SLOW_FACTOR * bound:
                self.find(
                    "slow",
                    f"{shortest:.3f} s at the shortest of {1 + REPLAYS} runs, {shortest / bound:.1f} "
                    f"times the stated worst case {bound:.3g} s",
                )

    def ordinary(self, kind: str = "ordinary") -> tuple[int, list | None, str]:
        rows = [self.profile.ordinary] * self.host.contacts
        return self.step(1e-3, rows, kind)

    def check_ordinary(self, after: str) -> None:
        """The ordinary step after something unusual: accepted where it was at the start, and (3D) the same bits."""
        status, outputs, message = self.ordinary()
        if not self.ordinary_ok or self.invalid is not None or self.crafted or not self.flat:
            return
        if status != OK:
            self.find("ordinary", f"after {after}: {message[:400]}")
        elif self.profile.stateless and outputs != self.first_outputs:
            self.find(
                "ordinary", f"after {after}: outputs {outputs} differ from the episode's first {self.first_outputs}"
            )

    # the episode ----------------------------------------------------------------------------------------------------
    def run(self, strict_time: bool) -> bool:
        """The episode; whether the instance is still usable (an Error or Fatal leaves it broken)."""
        self.strict_time = strict_time
        captured = io.StringIO()
        try:
            with contextlib.redirect_stderr(captured):
                self.episode()
        except Dead:
            return False
        finally:
            if captured.getvalue():
                self.find("warning", f"written to standard error: {captured.getvalue()[:400]!r}")
        self.host.free()
        return True

    def set_parameters(self) -> None:
        for name, value in self.parameters.items():
            self.call(f"set {name}", self.host.set, name, value)

    def start(self, before: bool = False) -> tuple[int, list | None, str]:
        """Parameters set, initialised at t = 0, the ordinary step taken and the state of t = 0 restored.  With
        ``before``, the state of before initialisation is also set after the step (a valid state) and the instance
        initialised again."""
        self.set_parameters()
        early = self.call("getFMUstate", self.host.get_state) if before else None
        try:
            self.call("initialise", self.host.initialise)
            self.t = 0.0
            start = self.call("getFMUstate", self.host.get_state)
            result = self.ordinary()
            self.set_state(start, "restore the start")
            self.call("freeFMUstate", self.host.free_state, start)
            if early is not None:
                self.set_state(early, "restore a state of before initialisation")
                self.call("initialise", self.host.initialise)
        finally:
            if early is not None:
                self.call("freeFMUstate", self.host.free_state, early)
        self.t = 0.0
        return result

    def episode(self) -> None:
        rng = self.rng
        self.parameters, self.invalid = self.profile.draw_parameters(rng, self.host.contacts)
        self.host.log.clear()
        self.seen_log = 0
        self.call("instantiate", self.host.instantiate)
        self.ordinary_ok, self.flat = False, False
        status, self.first_outputs, message = self.start(before=rng.random() < 0.1)
        self.ordinary_ok = status == OK
        if status != OK and self.invalid is None:
            self.refused = masked(message)
        if self.invalid is not None and status == OK:
            self.find("state", f"invalid parameter {self.invalid} accepted")
        self.flat = "corrugation_amplitude" not in self.parameters and "scene_file" not in self.parameters
        self.t0 = self.t
        operations = ["step"] * 10 + ["repeat", "serialise", "corrupt", "craft", "late", "inside", "reset", "unknown"]
        if self.host.arrays:
            operations.append("count")
        for _ in range(self.profile.episode_length(self.parameters, self.steps_wanted)):
            self.operation(pick(rng, operations))

    def operation(self, op: str) -> None:
        rng, contacts = self.rng, self.host.contacts
        self.ops[op] += 1
        if op == "step":
            h, rows, kind, bad = self.profile.draw_inputs(rng, contacts)
            self.step(h, rows, kind, bad)
            if kind != "valid":
                self.check_ordinary(f"a {kind} step")
            return
        if op == "reset":
            self.call("reset", self.host.reset)
            self.crafted = ""
            status, outputs, message = self.start()
            self.t0 = self.t
            if (status == OK) != self.ordinary_ok or (status == OK and outputs != self.first_outputs):
                self.find(
                    "ordinary",
                    f"after a reset the first step is {STATUS_NAMES.get(status)} {outputs}, at the "
                    f"start of the episode {self.first_outputs} ({message[:300]})",
                )
            return
        state = self.call("getFMUstate", self.host.get_state)
        try:
            if op == "repeat":
                h, rows, kind, bad = self.profile.draw_inputs(rng, contacts)
                t = self.t
                first = self.step(h, rows, kind, bad)
                self.set_state(state, "restore")
                self.t = t
                second = self.step(h, rows, kind, bad)
                same = first[0] == second[0] and (
                    first[1] is None
                    or all(
                        a == b or (a != a and b != b)
                        for x, y in zip(first[1], second[1], strict=True)
                        for a, b in zip(x, y, strict=True)
                    )
                )
                if not same:
                    self.find("state", f"restore -> step differs: {first[:2]} then {second[:2]}")
                self.set_state(state, "restore")
                self.t = t
            elif op == "serialise":
                data = self.call("serialise", self.host.serialise, state)
                self.set_bytes(data, "valid serialised state", refused_expected=False)
            elif op in ("corrupt", "craft"):
                data = self.call("serialise", self.host.serialise, state)
                t = self.t
                if op == "corrupt":
                    bad, how = corrupt(rng, data)
                    must = not same_json(bad, data)
                else:
                    integers = [
                        n
                        for n in self.host.variables
                        if self.host.kind(n) in ("Integer", "Enumeration")
                        and self.host.variables[n].causality == "parameter"
                    ]
                    bad, how, must = craft(rng, data, integers)
                refused = self.set_bytes(bad, f"{op} ({how})", refused_expected=True if must else None)
                if not refused:  # an accepted crafted state is a consistent one: it steps without Fatal
                    self.crafted = how
                    self.step(1e-3, [self.profile.ordinary] * contacts, f"after {op}")
                self.crafted = ""
                self.set_state(state, "restore after a bad state")
                self.t = t
            elif op == "late":
                name = pick(rng, sorted(self.profile.late))
                value = self.profile.late[name]
                current = self.call(f"get {name}", self.host.get, name)
                value = [value] * contacts if isinstance(current, list) else value
                self.new_log()
                self.call(f"late set {name}", self.host.set, name, value)
                if value != current:
                    self.expect_refusal(f"late set {name} = {value!r}")
                self.set_state(state, "restore after a late set")
            elif op == "unknown":
                self.new_log()
                self.call("set an unknown value reference", self.host.setter("Real"), [987654], [1.0])
                self.expect_refusal("a set of the unknown value reference 987654")
                self.set_state(state, "restore after an unknown value reference")
            elif op == "count":
                self.new_log()
                vr = self.host.vr("normal_load")
                self.call("set an array of the wrong count", self.host.setter("Real"), [vr], [1e5] * (contacts - 1))
                self.expect_refusal(f"a set of {contacts - 1} values of normal_load")
                self.set_state(state, "restore after a wrong count")
            elif op == "inside" and self.t - self.t0 > 1e-9:  # further than the slave's rounding tolerance
                t = self.t
                self.t = self.t0 + 0.5 * (t - self.t0)
                status, _, message = self.ordinary("inside")
                self.t = t
                if status != DISCARD or "not the end of the previous step" not in message:
                    self.find(
                        "state",
                        f"the communication point {self.t0 + 0.5 * (t - self.t0)!r} inside the last "
                        f"step: {STATUS_NAMES.get(status)}, {message[:300]!r}",
                    )
        finally:
            self.call("freeFMUstate", self.host.free_state, state)

    # state helpers --------------------------------------------------------------------------------------------------
    def set_state(self, state, what: str) -> None:
        self.new_log()
        self.call(f"setFMUstate ({what})", self.host.set_state, state)
        refused = [m for s, m in self.new_log() if s == ERROR]
        if refused:
            self.find("state", f"a valid state was refused ({what}): {refused[0][:300]}")

    def set_bytes(self, data: bytes, what: str, refused_expected: bool | None) -> bool:
        """Deserialise and set ``data``; whether it was refused (logged with status Error)."""
        self.new_log()
        state = self.call(f"deserialise ({what})", self.host.deserialise, data)
        try:
            self.call(f"setFMUstate ({what})", self.host.set_state, state)
        finally:
            self.call("freeFMUstate", self.host.free_state, state)
        log = self.new_log()
        refused = any(s == ERROR for s, _ in log)
        if refused_expected is False and refused:
            self.find("state", f"{what} refused: {[m[:300] for s, m in log if s == ERROR][:1]}")
        if refused_expected is True and not refused:
            self.find("state", f"{what} accepted")
        if refused:
            self.after_refusal(what)
        return refused

    def expect_refusal(self, what: str) -> None:
        """An emulated Error: logged with status Error, and the next step discarded for the error state."""
        if not any(s == ERROR for s, _ in self.new_log()):
            self.find("state", f"{what}: no message with status Error")
        self.after_refusal(what)

    def after_refusal(self, what: str) -> None:
        status, _, message = self.ordinary("after a refusal")
        if status != DISCARD or "error state" not in message:
            self.find(
                "state",
                f"{what}: the next step was not discarded for the error state: "
                f"{STATUS_NAMES.get(status)}, {message[:300]!r}",
            )


def masked(message: str) -> str:
    """A refusal's reason with its numbers as #, for counting reasons."""
    return re.sub(r"-?\d[\d.e+-]*", "#", message.split(" discarded: ", 1)[-1])[:200]


def same_json(a: bytes, b: bytes) -> bool:
    try:
        return json.dumps(json.loads(a), sort_keys=True) == json.dumps(json.loads(b), sort_keys=True)
    except ValueError:
        return False


def cycles(host: Host, count: int) -> dict:
    """Instantiate/free ``count`` times after a warm-up: Python memory blocks and RSS left per cycle."""
    import gc

    def one():
        host.instantiate()
        host.initialise()
        host.do_step(0.0, 1e-3)
        host.free()

    def rss() -> int:
        try:
            with open("/proc/self/statm") as f:
                return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
        except OSError:
            return 0

    for _ in range(max(count // 10, 10)):
        one()
    gc.collect()
    blocks, memory = sys.getallocatedblocks(), rss()
    for _ in range(count):
        one()
    gc.collect()
    return {"cycles": count, "blocks": (sys.getallocatedblocks() - blocks) / count, "rss": (rss() - memory) / count}


def profile_of(model: str, rail_mu: dict[int, float], quick: bool):
    """The profile of a target's model (``quick``: without the draws that may take seconds a step)."""
    if model.startswith("RollingContact2D"):
        return Profile2D(quick)
    return ProfileWheelset(rail_mu, quick) if model == "WheelsetContact" else Profile3D(rail_mu, quick)


def worker(args) -> None:
    """Run the episodes ``args.first`` ... ``args.last - 1`` of one target, one JSON line per episode, then one for
    the instantiate/free cycles."""
    from fmpy import read_model_description

    description = read_model_description(args.unzipped)
    host = Host(args.unzipped, description)
    profile = profile_of(host.model, {int(k): v for k, v in json.loads(args.rail_mu).items()}, args.quick)
    for index in range(args.first, args.last):
        print(json.dumps({"start": index}), flush=True)
        episode = Episode(host, profile, args.target_index, index, args.seed, args.steps)
        alive = episode.run(args.strict_time)
        print(
            json.dumps(
                {
                    "episode": index,
                    "statuses": {str(k): n for k, n in episode.statuses.items()},
                    "kinds": {f"{k}|{s}": n for (k, s), n in episode.kinds.items()},
                    "ops": dict(episode.ops),
                    "errors": episode.errors,
                    "findings": episode.findings,
                    "reasons": dict(episode.reasons),
                    "refused": episode.refused,
                    "over": episode.over,
                    "unbounded": max(episode.unbounded, default=0.0),
                    "max_step": max(episode.times, default=0.0),
                    "step_time": sum(episode.times),
                }
            ),
            flush=True,
        )
        if not alive:
            return  # an Error or Fatal leaves pythonfmu's objects freed: a fresh worker continues
    if args.cycles:
        print(json.dumps({"memory": cycles(host, args.cycles)}), flush=True)


# ------------------------------------------------------------------------------------------------------- the runner
def build(folder: Path) -> list[Path]:
    """The campaign's FMUs, built by build_fmu.py into ``folder``."""
    for extra in ([], ["--fmi", "2,3", "--only", "RollingContact3D"], ["--fmi", "2,3", "--contacts", "8"],
                  ["--fmi", "2,3", "--only", "WheelsetContact"]):
        done = subprocess.run(
            [sys.executable, str(ROOT / "build_fmu.py"), *extra, "--dest", str(folder)],
            capture_output=True,
            text=True,
            timeout=600,
        )
        if done.returncode != 0:
            raise SystemExit(f"build_fmu.py {' '.join(extra)} failed:\n{done.stdout}\n{done.stderr}")
    return [
        folder / "RollingContact2D.fmu",
        folder / "RollingContact3D.fmu",
        folder / "fmi3" / "RollingContact3D.fmu",
        folder / "RollingContact3D_8.fmu",
        folder / "fmi3" / "RollingContact3D_8.fmu",
        folder / "WheelsetContact.fmu",
        folder / "fmi3" / "WheelsetContact.fmu",
    ]


def rail_friction() -> dict[int, float]:
    """mu at zero slip of each rail condition's law (``rollcontact.stepping.parameters.RAIL_CONDITION_SETS``)."""
    sys.path.insert(0, str(ROOT / "src"))
    from rollcontact.stepping.parameters import RAIL_CONDITION_SETS

    return {code: float(condition.mu_static) for code, condition in RAIL_CONDITION_SETS.items()}


def target_name(path: Path, folder: Path) -> tuple[str, str]:
    """``(model/version, unzipped folder)`` of an FMU file, unzipped into a new folder in ``folder``."""
    from fmpy import extract, read_model_description

    unzipped = extract(str(path), unzipdir=tempfile.mkdtemp(prefix=f"{path.stem}_", dir=folder))
    description = read_model_description(unzipped)
    return f"{description.modelName}/{description.fmiVersion[0]}", unzipped


def run_target(args, name: str, unzipped: str, episodes: range, rail_mu: dict) -> dict:
    """Workers over one target's episodes; a crash or hang is a finding, and a fresh worker goes on."""
    results = {"episodes": [], "findings": [], "memory": None}
    first = episodes.start
    while first < episodes.stop:
        command = (
            [
                sys.executable,
                str(Path(__file__).resolve()),
                "--worker",
                "--unzipped",
                unzipped,
                "--seed",
                str(args.seed),
                "--target-index",
                str(TARGETS.index(name)),
                "--first",
                str(first),
                "--last",
                str(episodes.stop),
                "--steps",
                str(args.steps),
                "--cycles",
                str(args.cycles),
                "--rail-mu",
                json.dumps(rail_mu),
            ]
            + (["--strict-time"] if args.strict_time else [])
            + (["--quick"] if args.quick else [])
        )
        process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        current = None
        lines: list[str] = []
        stderr = ""
        try:  # a worker silent for --hang seconds hangs
            import selectors

            selector = selectors.DefaultSelector()
            selector.register(process.stdout, selectors.EVENT_READ)
            while True:
                if not selector.select(timeout=args.hang):
                    process.kill()
                    break
                line = process.stdout.readline()
                if not line:
                    break
                lines.append(line)
            process.wait()
            stderr = process.stderr.read()
        finally:
            if process.poll() is None:
                process.kill()
                process.wait()
        finished = False
        for line in lines:
            record = json.loads(line)
            if "start" in record:
                current = record["start"]
            elif "episode" in record:
                results["episodes"].append(record)
                results["findings"] += record["findings"]
                current = None
                first = record["episode"] + 1
            elif "memory" in record:
                results["memory"] = record["memory"]
                finished = True
        code = process.returncode
        if code is not None and code > 0:
            raise SystemExit(f"the fuzz worker failed (a defect of this script, not a finding):\n{stderr[-3000:]}")
        if current is None and code is not None and code < 0:
            results["findings"].append(
                {
                    "kind": "exit",
                    "episode": -1,
                    "detail": f"worker process ended (signal {-code}) after its last result: {stderr.strip()[-300:]}",
                }
            )
        if current is not None:  # the worker died (a signal) or hung inside an episode
            why = f"signal {-code}" if code is not None and code < 0 else f"silent {args.hang:.0f} s, killed"
            results["findings"].append(
                {
                    "kind": "fatal",
                    "episode": current,
                    "detail": f"worker process ended ({why}): {stderr.strip()[-300:]}",
                }
            )
            first = current + 1
        elif finished or first >= episodes.stop:
            break
    return results


def campaign(args, fmus: list[Path], folder: Path) -> dict:
    """Every target's episodes (``--episodes`` or :data:`CAMPAIGN` / :data:`QUICK` per model), the FMUs unzipped in
    ``folder``."""
    rail_mu = rail_friction()
    runs = {}
    for path in fmus:
        name, unzipped = target_name(path, folder)
        if name not in TARGETS:
            raise SystemExit(f"{path}: {name} is not a target of this fuzz ({', '.join(TARGETS)})")
        if args.target is not None and name != args.target:
            continue
        model = name.split("/")[0]
        count = args.episodes if args.episodes is not None else (QUICK if args.quick else CAMPAIGN)[model]
        episodes = range(args.episode, args.episode + 1) if args.episode is not None else range(count)
        started = time.perf_counter()
        runs[name] = run_target(args, name, unzipped, episodes, rail_mu)
        runs[name]["seconds"] = time.perf_counter() - started
    return runs


def report(args, runs: dict) -> str:
    """The markdown report: per target, episodes, steps by status, emulated errors and findings; what was refused
    though valid; steps over their stated worst case; the findings."""
    command = (
        "python tests/tools/fuzz_fmu.py" + (" --quick" if args.quick else "") + f" --seed {args.seed} "
        f"--steps {args.steps}" + (f" --episodes {args.episodes}" if args.episodes is not None else "")
    )
    lines = [
        f"# Fuzz of the contact FMUs (seed {args.seed}{', quick' if args.quick else ''})",
        "",
        f"`{command}`: each episode a function of the seed, its target and its index (replay one: "
        f"`--seed {args.seed} --steps {args.steps} --target MODEL/FMI --episode K`); up to {args.steps} "
        "operations per episode (tests/tools/fuzz_fmu.py's docstring lists them and what counts as a finding).",
        "",
        "| FMU | FMI | episodes | steps | OK | Discard | Error (emulated, logged) | Error or Fatal returned | "
        "findings | minutes |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    totals = collections.Counter()
    for name, run in runs.items():
        model, version = name.split("/")
        statuses = collections.Counter()
        for e in run["episodes"]:
            statuses.update({int(k): n for k, n in e["statuses"].items()})
        errors = sum(e["errors"] for e in run["episodes"])
        steps = sum(statuses.values())
        returned = statuses[ERROR] + statuses[FATAL] + sum(f["kind"] == "fatal" for f in run["findings"])
        row = {
            "episodes": len(run["episodes"]),
            "steps": steps,
            "ok": statuses[OK],
            "discard": statuses[DISCARD],
            "errors": errors,
            "returned": returned,
            "findings": len(run["findings"]),
        }
        totals.update(row)
        lines.append(
            f"| {model} | {version}.0 | {row['episodes']} | {steps} | {row['ok']} | {row['discard']} | "
            f"{errors} | {returned} | {row['findings']} | {run['seconds'] / 60:.1f} |"
        )
    lines.append(
        f"| all | | {totals['episodes']} | {totals['steps']} | {totals['ok']} | {totals['discard']} | "
        f"{totals['errors']} | {totals['returned']} | {totals['findings']} | |"
    )
    lines += [
        "",
        "## Steps by input kind and status",
        "",
        "| FMU | inputs | OK | Discard | Error or Fatal |",
        "|---|---|---:|---:|---:|",
    ]
    for name, run in runs.items():
        kinds = collections.Counter()
        for e in run["episodes"]:
            kinds.update({tuple(k.split("|")): n for k, n in e["kinds"].items()})
        for kind in sorted({k for k, _ in kinds}):
            fatal = sum(kinds.get((kind, str(s)), 0) for s in (ERROR, FATAL))
            lines.append(
                f"| {name} | {kind} | {kinds.get((kind, str(OK)), 0)} | {kinds.get((kind, str(DISCARD)), 0)} "
                f"| {fatal} |"
            )
    lines += ["", "## Operations", "", "| FMU | " + " | ".join(OPERATIONS) + " |", "|---|" + "---:|" * len(OPERATIONS)]
    for name, run in runs.items():
        ops = collections.Counter()
        for e in run["episodes"]:
            ops.update(e["ops"])
        lines.append(f"| {name} | " + " | ".join(str(ops.get(op, 0)) for op in OPERATIONS) + " |")
    lines += [
        "",
        "## Valid parameters refused at initialisation (not findings)",
        "",
        "Episodes whose parameters, each within its range, make a model that cannot step (numbers as #): a level "
        "that does not treat the friction law, a budget below every setting.",
        "",
        "| FMU | reason | episodes |",
        "|---|---|---:|",
    ]
    for name, run in runs.items():
        refused = collections.Counter(e["refused"] for e in run["episodes"] if e["refused"])
        lines += [f"| {name} | {reason.replace('|', '/')} | {n} |" for reason, n in refused.most_common(6)]
    lines += [
        "",
        "## Valid inputs that were refused (not findings)",
        "",
        "Discards of valid inputs on an instance that took the episode's first step (numbers as #), each naming its "
        "cause: what a level does not treat or a step budget does not pay.",
        "",
        "| FMU | reason | steps |",
        "|---|---|---:|",
    ]
    for name, run in runs.items():
        reasons = collections.Counter()
        for e in run["episodes"]:
            reasons.update(e["reasons"])
        lines += [f"| {name} | {reason.replace('|', '/')} | {n} |" for reason, n in reasons.most_common(8)]
    lines += [
        "",
        "## Step times against the stated worst case (not findings)",
        "",
        f"The stated worst case of a step: `step_budget` per contact (RollingContact2D: per step) in modelled "
        f"seconds, counted as seconds, plus {STEP_OVERHEAD} s for the call; none where docs/fmu.md states none (no "
        "budget; the 2D `table` = on; the 2D polynomial method with velocity-dependent friction on a corrugation).  "
        "Wall-clock times on the machine below, so they move with its load.",
        "",
        "| FMU | steps | slowest [s] | over the worst case | most over (time / worst case) | slowest without a "
        "stated worst case [s] |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    slow_rows = []
    for name, run in runs.items():
        over = [o for e in run["episodes"] for o in e["over"]]
        worst = max(over, key=lambda o: o["seconds"] / o["bound"], default=None)
        steps = sum(sum(e["statuses"].values()) for e in run["episodes"])
        lines.append(
            f"| {name} | {steps} | {max((e['max_step'] for e in run['episodes']), default=0.0):.3f} | "
            f"{len(over)} | " + (f"{worst['seconds'] / worst['bound']:.1f}" if worst else "-") + " | "
            f"{max((e['unbounded'] for e in run['episodes']), default=0.0):.3f} |"
        )
        slow_rows += [(o["seconds"] / o["bound"], name, o) for o in over]
    if slow_rows:
        lines += [
            "",
            "Steps most over their stated worst case:",
            "",
            "| FMU | episode | time [s] | worst case [s] | step | parameters |",
            "|---|---:|---:|---:|---|---|",
        ]
        for _, name, o in sorted(slow_rows, key=lambda r: -r[0])[:8]:
            lines.append(
                f"| {name} | {o['episode']} | {o['seconds']:.3f} | {o['bound']:.3g} | "
                f"{o['step'].replace('|', '/')[:300]} | {o['parameters'].replace('|', '/')[:300]} |"
            )
    memory = [(name, run["memory"]) for name, run in runs.items() if run["memory"]]
    if memory:
        lines += [
            "",
            "## Memory per instance",
            "",
            "| FMU | instantiate/free cycles | Python blocks left per cycle | RSS left per cycle [kB] |",
            "|---|---:|---:|---:|",
        ]
        for name, m in memory:
            lines.append(f"| {name} | {m['cycles']} | {m['blocks']:.1f} | {m['rss'] / 1e3:.1f} |")
            if m["blocks"] > MEMORY_BLOCKS:
                runs[name]["findings"].append(
                    {"kind": "memory", "episode": -1, "detail": f"{m['blocks']:.1f} Python blocks left per cycle"}
                )
    findings = [(name, f) for name, run in runs.items() for f in run["findings"]]
    lines += ["", f"## Findings: {len(findings)}", ""]
    if findings:
        lines += ["| FMU | kind | episode | detail |", "|---|---|---:|---|"]
        lines += [
            f"| {name} | {f['kind']} | {f['episode']} | {f['detail'].replace('|', '/')} |" for name, f in findings
        ]
        counts = collections.Counter(f["kind"] for _, f in findings)
        lines += ["", "By kind: " + ", ".join(f"{k} {n}" for k, n in sorted(counts.items())) + "."]
    else:
        lines.append("None.")
    return "\n".join(lines) + "\n"


OPERATIONS = ("step", "repeat", "serialise", "corrupt", "craft", "late", "inside", "reset", "unknown", "count")


def parser() -> argparse.ArgumentParser:
    """The command line (also ``benchmarks/fuzz_campaign.py``'s)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0], add_help=False)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--quick", action="store_true", help="a few episodes per target (the test suite's)")
    parser.add_argument(
        "--fmu",
        action="append",
        type=Path,
        help="an FMU to fuzz (repeat; default: the five targets built with build_fmu.py)",
    )
    parser.add_argument(
        "--episodes",
        type=int,
        default=None,
        help="episodes per target (default: 100 of RollingContact2D and 130 of each 3D target; with --quick: 16, 5 "
        "and 4 of RollingContact3D_8)",
    )
    parser.add_argument("--steps", type=int, default=None, help="operations per episode (default 20; quick 12)")
    parser.add_argument("--target", choices=TARGETS, help="this target only")
    parser.add_argument("--episode", type=int, help="replay this episode only (with --target)")
    parser.add_argument(
        "--strict-time",
        action="store_true",
        help=f"a step more than {SLOW_FACTOR:g} times its stated worst case is a finding",
    )
    parser.add_argument("--hang", type=float, default=600.0, help="a worker silent this long [s] hangs")
    parser.add_argument("--cycles", type=int, default=None, help="instantiate/free cycles (default 200; quick 30)")
    return parser


def defaults(args, error) -> argparse.Namespace:
    """``args`` of :func:`parser` with the defaults that depend on ``--quick`` filled in; ``error(message)`` for a
    combination that makes no sense."""
    if args.steps is None:
        args.steps = 12 if args.quick else 20
    if args.cycles is None:
        args.cycles = 30 if args.quick else 200
    if args.episode is not None and args.target is None:
        error("--episode needs --target")
    if args.episode is not None:
        args.cycles = 0
    return args


def options(argv: list[str] | None = None) -> argparse.Namespace:
    """This tool's command line: :func:`parser`'s, ``--out`` and the worker's own options."""
    full = argparse.ArgumentParser(description=__doc__.splitlines()[0], parents=[parser()])
    full.add_argument("--out", help="write the report to this file too")
    full.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    full.add_argument("--unzipped", help=argparse.SUPPRESS)
    full.add_argument("--target-index", type=int, default=0, help=argparse.SUPPRESS)
    full.add_argument("--first", type=int, default=0, help=argparse.SUPPRESS)
    full.add_argument("--last", type=int, default=0, help=argparse.SUPPRESS)
    full.add_argument("--rail-mu", default="{}", help=argparse.SUPPRESS)
    return defaults(full.parse_args(argv), full.error)


def run(args) -> tuple[str, dict]:
    """The campaign of ``args`` (building the FMUs unless given): its report and a summary."""
    with tempfile.TemporaryDirectory(prefix="fuzz_fmu_") as tmp:
        fmus = args.fmu if args.fmu else build(Path(tmp))
        runs = campaign(args, fmus, Path(tmp))
    text = report(args, runs)
    summary = {
        "episodes": sum(len(r["episodes"]) for r in runs.values()),
        "findings": sum(len(r["findings"]) for r in runs.values()),
        "targets": {name: len(r["episodes"]) for name, r in runs.items()},
    }
    return text, summary


def main(argv: list[str] | None = None) -> int:
    args = options(argv)
    if args.worker:
        worker(args)
        return 0
    text, summary = run(args)
    print(text)
    if args.out:
        Path(args.out).write_text(text)
    print(json.dumps(summary))
    return 1 if summary["findings"] else 0


if __name__ == "__main__":
    sys.exit(main())
