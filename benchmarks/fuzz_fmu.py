"""Fuzz campaign of the RollingContact2D FMU through fmpy: a seeded, time-bounded, reproducible study.

Usage::

    python benchmarks/fuzz_fmu.py [--seed 1] [--time 120] [--fmu RollingContact2D.fmu] [--out FILE]
    python benchmarks/fuzz_fmu.py --quick            # 150 short episodes, a few seconds (tests/fmu/test_fuzz.py)
    python benchmarks/fuzz_fmu.py --seed 1 --episode 17   # replay one episode

Without ``--fmu`` the FMU is built by ``build_fmu.py --dest <tmp>``.  A full run writes its report to
``benchmarks/results/fuzz.md`` (``--out``); ``--quick`` writes only to stdout unless ``--out`` is given.  The exit
status is 1 when there is a finding.

What an episode does (its random generator is ``numpy.random.default_rng([seed, episode])``, so every episode can
be replayed alone): instantiate with random parameters (mostly valid, some extreme, one in eight invalid),
initialise, then take steps with random inputs (valid, extreme or invalid; step sizes from 1e-12 s to 1e6 s)
interleaved with state operations: get/set, restore-and-repeat (restore -> step -> restore -> step must give the
same outputs), serialise/deserialise, corrupted bytes (truncated, a flipped byte, garbage, empty), crafted states
(a field replaced, valid checksum), a fixed parameter set after initialisation, a communication point inside the
previous step.  After the episodes, instantiate/free cycles measure the memory left per instance.

Findings (each a row of the report):

* ``fatal``: any call returning fmi2Error or fmi2Fatal (the FMU emulates fmi2Error, see docs/fmu.md), or the
  worker process dying (signal) or hanging (no episode finished within ``--hang`` seconds);
* ``non-finite``: an OK step with a non-finite output;
* ``friction``: an OK step with |T| > mu N (mu the friction coefficient at zero slip, the largest of both laws);
* ``slow``: an OK or discarded step slower than ``--slow`` seconds with a step budget of at most 0.05 s (and not
  ``table`` = on, whose first loaded step builds the table whatever it takes);
* ``ordinary``: on a flat surface, an ordinary step (N = 5e4 N, creep 1e-3, V = 10 m/s) discarded right after an
  extreme or invalid one, although the same step was accepted at the start of the episode;
* ``state``: a corrupted state accepted, a refused state, late parameter or wrong communication point not followed
  by a Discard, a valid state refused, or restore -> step not repeating the outputs;
* ``warning``: a Python warning (e.g. a numpy overflow) during a step: the test suite treats one in a solver as a
  numerical defect (``filterwarnings = error::RuntimeWarning``); "after a crafted state" when the step follows a
  crafted state that was accepted (finite but absurd values pass the state check);
* ``memory``: more than 40 Python memory blocks left per instantiate/free cycle;
* ``exit``: the worker process ended by a signal after its last result (at exit: interpreter finalisation,
  ``exit()``'s handlers and the libraries' destructors; docs/fmu.md, "Exit").
"""

from __future__ import annotations

import argparse
import collections
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

import common  # the benchmarks' first import: one BLAS thread, the checkout on sys.path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results" / "fuzz.md"
OK, WARNING, DISCARD, ERROR, FATAL = range(5)
ORDINARY = (5e4, 1e-3, 10.0)
ORDINARY_H = 1e-3
OUTPUTS = ("tangential_force", "traction_coefficient", "contact_half_width", "stick_half_width", "contact_offset",
           "max_pressure", "frictional_power", "creep_stiffness", "stationarity", "method_used", "axis_position")
FIXED_PARAMETERS = ("youngs_modulus", "radius", "friction_coefficient", "method", "transient", "tolerance")


# ---------------------------------------------------------------------------------------------------- generation
def log_uniform(rng, low, high):
    return float(math.exp(rng.uniform(math.log(low), math.log(high))))


def draw_parameters(rng) -> tuple[dict, str | None]:
    """Parameters (only those that differ from the defaults) and the name of an invalid one, if any."""
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
        p["tolerance"] = float(rng.choice([1e-2, 3e-3, 1e-3]))
    if rng.random() < 0.2:
        p["elements"] = int(rng.choice([20, 40, 80]))
    if rng.random() < 0.15:
        p["step_budget"] = float(rng.choice([0.0, 1e-3, 0.01]))
    if rng.random() < 0.2:
        p["table"] = int(rng.integers(0, 3))
    extreme = rng.random() < 0.3
    if extreme:  # a material, wheel or friction at the edge of its range
        name = str(rng.choice(["youngs_modulus", "radius", "friction_coefficient", "contact_width",
                               "poisson_ratio", "initial_position"]))
        p[name] = {"youngs_modulus": lambda: log_uniform(rng, 1e6, 1e13),
                   "radius": lambda: log_uniform(rng, 1e-3, 50.0),
                   "friction_coefficient": lambda: log_uniform(rng, 1e-4, 5.0),
                   "contact_width": lambda: log_uniform(rng, 1e-5, 10.0),
                   "poisson_ratio": lambda: float(rng.choice([0.0, 0.4999999])),
                   "initial_position": lambda: float(rng.choice([-1e6, 1e-300, 1e9]))}[name]()
    invalid = None
    if rng.random() < 0.125:
        invalid, value = [("youngs_modulus", -1.0), ("radius", 0.0), ("friction_coefficient", -0.1),
                          ("poisson_ratio", 0.5), ("corrugation_wavelength", 0.0), ("friction_law", 7),
                          ("method", 9), ("contact_width", math.nan), ("tolerance", math.inf),
                          ("scene_file", "/dev/zero"), ("scene_file", "/nonexistent.toml"),
                          ("scene_file", "/")][int(rng.integers(0, 12))]
        p[invalid] = value
    return p, invalid


def draw_inputs(rng) -> tuple[tuple[float, float, float, float], str]:
    """``(h, N, creep, V)`` and its kind: "valid", "extreme" or "invalid"."""
    kind = str(rng.choice(["valid", "extreme", "invalid"], p=[0.6, 0.25, 0.15]))
    h = log_uniform(rng, 1e-5, 1e-2)
    load, creep, speed = log_uniform(rng, 1e2, 3e5), float(rng.normal(0.0, 2e-3)), log_uniform(rng, 0.1, 60.0)
    if rng.random() < 0.1:
        load = 0.0
    if kind == "extreme":
        which = int(rng.integers(0, 4))
        if which == 0:
            load = float(rng.choice([5e-324, 1e-300, 1e-12, 1e9, 1e12, 1e100, 1e300]))
        elif which == 1:
            creep = float(rng.choice([-1.0, 1.0])) * float(rng.choice([1e-300, 1e-12, 0.5, 1e3, 1e300]))
        elif which == 2:
            speed = float(rng.choice([0.0, 1e-300, 1e3, 1e6, 1e300]))
        else:
            h = float(rng.choice([1e-12, 1e-9, 1.0, 10.0, 1e6]))
    elif kind == "invalid":
        bad = [("load", -1.0), ("load", math.nan), ("load", math.inf), ("creep", math.nan), ("creep", -math.inf),
               ("speed", -0.5), ("speed", math.nan), ("h", 0.0), ("h", -1e-3), ("h", math.nan)]
        name, value = bad[int(rng.integers(0, len(bad)))]
        if name == "load":
            load = value
        elif name == "creep":
            creep = value
        elif name == "speed":
            speed = value
        else:
            h = value
    return (h, load, creep, speed), kind


def corrupt(rng, data: bytes) -> tuple[bytes, str]:
    """Corrupted serialised state bytes and how they were corrupted."""
    how = str(rng.choice(["truncate", "flip", "garbage", "empty", "nonutf8"]))
    if how == "truncate":
        return data[: int(rng.integers(0, len(data)))], how
    if how == "flip":
        at = int(rng.integers(0, len(data)))
        return data[:at] + bytes([data[at] ^ int(rng.integers(1, 256))]) + data[at + 1:], how
    if how == "garbage":
        return bytes(rng.integers(0, 256, int(rng.integers(1, 200)), dtype=int).astype("uint8")), how
    if how == "empty":
        return b"", how
    return b"\xff\xfe\xfd" + data[3:], how


def craft(rng, data: bytes) -> tuple[bytes, str]:
    """The state with one field replaced by a random JSON value, with a valid checksum."""
    import hashlib

    state = json.loads(data)
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
    value = [None, math.nan, math.inf, -1, 0, 1e308, "x", [], {}, True, "/dev/zero", 2**40][int(rng.integers(0, 12))]
    node = state
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    if rng.random() < 0.2 and isinstance(node, dict):
        node["log"] = 0  # an unknown key beside it
    text = json.dumps(state, sort_keys=True)
    state["sha256"] = hashlib.sha256(text.encode()).hexdigest()
    return json.dumps(state, sort_keys=True).encode(), "/".join(map(str, path))


# ---------------------------------------------------------------------------------------------------- the worker
class Episode:
    """One instance of the FMU driven by one episode's random generator; collects statistics and findings."""

    def __init__(self, fmu, description, index: int, seed: int, slow: float):
        import numpy as np
        from fmpy.fmi2 import defaultCallbacks, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE

        self.np = np
        self.fmu, self.index, self.slow = fmu, index, slow
        self.rng = np.random.default_rng([seed, index])
        self.vr = {v.name: v.valueReference for v in description.modelVariables}
        self.types = {v.name: "Integer" if v.type == "Enumeration" else v.type for v in description.modelVariables}
        self.log: list[tuple[int, str]] = []
        self.findings: list[dict] = []
        self.steps = collections.Counter()
        self.reasons = collections.Counter()  # Discards of valid inputs with valid parameters, numbers as #
        self.ops = collections.Counter()
        self.times: list[float] = []
        self.dead = False
        self.previous = None  # the last step before the current one (context of a finding)
        self.crafted = ""  # the field of the last crafted state that was accepted
        self.current = None
        self.callbacks = fmi2CallbackFunctions()
        self.callbacks.logger = fmi2CallbackLoggerTYPE(self.logger)
        self.callbacks.allocateMemory = defaultCallbacks.allocateMemory
        self.callbacks.freeMemory = defaultCallbacks.freeMemory

    def logger(self, environment, name, status, category, message):
        self.log.append((status, message.decode(errors="replace")))

    def find(self, kind: str, detail: str) -> None:
        previous = "" if self.previous is None else f"; the step before: {self.previous}"
        self.findings.append({"kind": kind, "episode": self.index, "detail": (detail[:400] + previous)[:600]})

    def call(self, what: str, function, *args):
        """``function(*args)``: its result, or None after fmi2Discard; a Fatal/Error is a finding (and the
        instance is given up: pythonfmu leaves it broken)."""
        from fmpy.fmi1 import FMICallException

        try:
            return function(*args)
        except FMICallException as exc:
            if exc.status >= ERROR:
                self.find("fatal", f"{what}: status {exc.status}; log {self.log[-1:]}")
                self.dead = True
                raise
            return None

    # steps -----------------------------------------------------------------------------------------------------
    def set_inputs(self, load, creep, speed):
        self.call("setReal inputs", self.fmu.setReal, [self.vr["normal_load"], self.vr["creep"], self.vr["velocity"]],
                  [load, creep, speed])

    def outputs(self) -> list[float]:
        reals = [self.vr[n] for n in OUTPUTS if n != "method_used"]
        values = iter(self.call("getReal", self.fmu.getReal, reals))
        method = self.call("getInteger", self.fmu.getInteger, [self.vr["method_used"]])[0]
        return [method if n == "method_used" else next(values) for n in OUTPUTS]

    def step(self, t, h, load, creep, speed, kind: str) -> tuple[int, list[float] | None, str]:
        """One step: ``(status, outputs or None, last logged message)``."""
        from fmpy.fmi1 import FMICallException

        self.previous = self.current
        self.current = f"{kind} doStep(t={t!r}, h={h!r}) N={load!r}, xi={creep!r}, V={speed!r}"
        self.set_inputs(load, creep, speed)
        before = len(self.log)
        started = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                self.fmu.doStep(t, h)
                status = OK
            except FMICallException as exc:
                status = exc.status
        elapsed = time.perf_counter() - started
        self.times.append(elapsed)
        self.steps[(kind, status)] += 1
        self.current += f" -> status {status}"
        for warning in caught:  # the test suite treats a numpy warning in a solver as a numerical defect
            crafted = kind.startswith("after craft")
            self.find("warning after a crafted state" if crafted else "warning",
                      f"{warning.category.__name__} at {Path(warning.filename).name}:{warning.lineno}: "
                      f"{warning.message} in {self.current}{f' (field {self.crafted})' if crafted else ''}, "
                      f"parameters {self.parameters}")
        message = self.log[-1][1] if len(self.log) > before else ""
        if status >= ERROR:
            self.find("fatal", f"doStep(t={t!r}, h={h!r}) with N={load!r}, xi={creep!r}, V={speed!r}: status "
                               f"{status}; {message}")
            self.dead = True
            return status, None, message
        if elapsed > self.slow and 0.0 < self.parameters.get("step_budget", 0.05) <= 0.05 \
                and self.parameters.get("table") != 2:  # table = on builds at the first loaded step, as asked
            self.find("slow", f"{elapsed:.2f} s: doStep(t={t!r}, h={h!r}) N={load!r}, xi={creep!r}, V={speed!r}, "
                              f"parameters {self.parameters}")
        if status != OK:
            if status == DISCARD and kind in ("valid", "ordinary") and self.invalid is None:
                reason = message.split(" discarded: ", 1)[-1]
                self.reasons[re.sub(r"-?\d[\d.e+-]*", "#", reason)[:160]] += 1
            return status, None, message
        out = self.outputs()
        if not all(math.isfinite(v) for v in out):
            self.find("non-finite", f"OK step N={load!r}, xi={creep!r}, V={speed!r}, h={h!r}: outputs {out}")
        mu = self.fmu.getReal([self.vr["friction_coefficient"]])[0]  # in force (a crafted state brings its own)
        if "scene_file" not in self.parameters and abs(out[0]) > mu * load:
            self.find("friction", f"|T| = {abs(out[0])!r} > mu N = {mu * load!r} (N={load!r}, xi={creep!r}, "
                                  f"V={speed!r}, h={h!r}, parameters {self.parameters})")
        return status, out, message

    # the episode -----------------------------------------------------------------------------------------------
    def run(self, steps: int) -> None:
        from fmpy.fmi1 import FMICallException

        try:
            self.episode(steps)
        except FMICallException:
            pass  # a Fatal: recorded, the instance is abandoned (calling it again would be a use after free)
        finally:
            if not self.dead:
                self.fmu.fmi2FreeInstance(self.fmu.component)

    def episode(self, steps: int) -> None:
        rng = self.rng
        self.parameters, self.invalid = draw_parameters(rng)
        self.fmu.instantiate(callbacks=self.callbacks, loggingOn=True)
        for name, value in self.parameters.items():
            setter = {"Real": self.fmu.setReal, "Integer": self.fmu.setInteger, "String": self.fmu.setString}
            self.call(f"set {name}", setter[self.types[name]], [self.vr[name]], [value])
        self.call("setupExperiment", self.fmu.setupExperiment, None, 0.0)
        self.call("enterInitializationMode", self.fmu.enterInitializationMode)
        self.call("exitInitializationMode", self.fmu.exitInitializationMode)
        self.t = 0.0
        start = self.get_state()
        status, _, message = self.step(self.t, ORDINARY_H, *ORDINARY, "ordinary")
        self.ordinary_ok = status == OK
        if self.invalid is not None and status == OK:
            self.find("state", f"invalid parameter {self.invalid} = {self.parameters[self.invalid]!r} accepted")
        self.set_state(start, "restore the start")
        self.free_state(start)
        self.flat = "corrugation_amplitude" not in self.parameters and "scene_file" not in self.parameters
        for _ in range(steps):
            if self.dead:
                return
            self.operation(str(rng.choice(["step"] * 10 + ["repeat", "serialise", "corrupt", "craft", "late",
                                                           "inside"])))

    def operation(self, op: str) -> None:
        rng = self.rng
        self.ops[op] += 1
        if op == "step":
            (h, load, creep, speed), kind = draw_inputs(rng)
            status, _, _ = self.step(self.t, h, load, creep, speed, kind)
            if status == OK:
                self.t += h
            if kind != "valid" and self.ordinary_ok and self.flat and self.invalid is None:
                status, _, message = self.step(self.t, ORDINARY_H, *ORDINARY, "ordinary")
                if status != OK:
                    self.find("ordinary", f"after a {kind} step (h={h!r}, N={load!r}, xi={creep!r}, V={speed!r}): "
                                          f"{message} (parameters {self.parameters})")
                else:
                    self.t += ORDINARY_H
            return
        state = self.get_state()
        try:
            if op == "repeat":
                (h, load, creep, speed), kind = draw_inputs(rng)
                first = self.step(self.t, h, load, creep, speed, kind)
                self.set_state(state, "restore")
                second = self.step(self.t, h, load, creep, speed, kind)
                same = first[0] == second[0] and (first[1] is None or all(
                    a == b or (a != a and b != b) for a, b in zip(first[1], second[1], strict=True)))
                if not same:
                    self.find("state", f"restore -> step differs: {first[:2]} then {second[:2]} (h={h!r}, "
                                       f"N={load!r}, xi={creep!r}, V={speed!r}, parameters {self.parameters})")
                self.set_state(state, "restore")
            elif op == "serialise":
                data = self.serialise(state)
                self.set_bytes(data, refused_expected=False, what="valid serialised state")
            elif op in ("corrupt", "craft"):
                data = self.serialise(state)
                bad, how = corrupt(rng, data) if op == "corrupt" else craft(rng, data)
                refused = self.set_bytes(bad, refused_expected=None, what=f"{op} ({how})")
                if not refused and op == "corrupt" and not self.same_json(bad, data):
                    self.find("state", f"corrupted bytes ({how}) accepted as a state")
                if not refused:  # an accepted crafted state is a consistent one: it steps without Fatal
                    self.crafted = how
                    self.step(self.t, ORDINARY_H, *ORDINARY, f"after {op}")
                self.set_state(state, "restore after a bad state")
            elif op == "late":
                name = str(rng.choice(FIXED_PARAMETERS))
                value = {"youngs_modulus": 1e11, "radius": 0.2, "friction_coefficient": 0.5, "method": 2,
                         "transient": 1, "tolerance": 1e-2}[name]
                setter = self.fmu.setInteger if self.types[name] == "Integer" else self.fmu.setReal
                current = (self.fmu.getInteger if self.types[name] == "Integer" else self.fmu.getReal)(
                    [self.vr[name]])[0]
                before = len(self.log)
                self.call(f"late set {name}", setter, [self.vr[name]], [value])
                if value != current:
                    self.expect_refusal(before, f"late set {name} = {value!r}")
                self.set_state(state, "restore after a late set")
            elif op == "inside" and self.t > 1e-6:
                status, _, message = self.step(self.t * 0.5, ORDINARY_H, *ORDINARY, "inside")
                if status != DISCARD or "not the end of the previous step" not in message:
                    self.find("state", f"communication point {self.t * 0.5!r} inside the previous step: status "
                                       f"{status}, {message!r}")
        finally:
            if not self.dead:
                self.free_state(state)

    # state helpers ---------------------------------------------------------------------------------------------
    def get_state(self):
        self.ops["getFMUstate"] += 1
        return self.call("getFMUstate", self.fmu.getFMUstate)

    def free_state(self, state) -> None:
        self.call("freeFMUstate", self.fmu.freeFMUstate, state)

    def set_state(self, state, what: str) -> None:
        before = len(self.log)
        self.call(f"setFMUstate ({what})", self.fmu.setFMUstate, state)
        refused = [m for s, m in self.log[before:] if s == ERROR]
        if refused:
            self.find("state", f"a valid state was refused ({what}): {refused[0]}")

    def serialise(self, state) -> bytes:
        return bytes(self.call("serializeFMUstate", self.fmu.serializeFMUstate, state))

    def set_bytes(self, data: bytes, refused_expected: bool | None, what: str) -> bool:
        """Deserialise and set ``data``; whether it was refused (logged with status Error)."""
        before = len(self.log)
        state = self.call(f"deSerializeFMUstate ({what})", self.fmu.deSerializeFMUstate, data)
        try:
            self.call(f"setFMUstate ({what})", self.fmu.setFMUstate, state)
        finally:
            self.free_state(state)
        refused = any(s == ERROR for s, _ in self.log[before:])
        if refused_expected is False and refused:
            self.find("state", f"{what} refused: {[m for s, m in self.log[before:] if s == ERROR][:1]}")
        if refused:
            self.expect_refusal(before, what)
        return refused

    def expect_refusal(self, before: int, what: str) -> None:
        """An emulated fmi2Error: logged with status Error, and the next step is discarded."""
        if not any(s == ERROR for s, _ in self.log[before:]):
            self.find("state", f"{what}: no message with status Error")
        status, _, message = self.step(self.t, ORDINARY_H, *ORDINARY, "after refusal")
        if status != DISCARD or "error state" not in message:
            self.find("state", f"{what}: the next step was not discarded for the error state: {status}, {message!r}")

    @staticmethod
    def same_json(a: bytes, b: bytes) -> bool:
        try:
            return json.dumps(json.loads(a), sort_keys=True) == json.dumps(json.loads(b), sort_keys=True)
        except ValueError:
            return False


def cycles(fmu, count: int) -> dict:
    """Instantiate/free ``count`` times after a warm-up: Python blocks and RSS left per cycle."""
    import gc

    def one():
        fmu.instantiate(loggingOn=False)
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        fmu.doStep(0.0, 1e-3)
        fmu.terminate()
        fmu.fmi2FreeInstance(fmu.component)

    def rss() -> int:
        try:
            with open("/proc/self/statm") as f:
                return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
        except OSError:
            return 0

    for _ in range(max(count // 10, 10)):
        one()
    gc.collect()
    blocks, memory, started = sys.getallocatedblocks(), rss(), time.perf_counter()
    for _ in range(count):
        one()
    gc.collect()
    return {"cycles": count, "blocks": (sys.getallocatedblocks() - blocks) / count,
            "rss": (rss() - memory) / count, "seconds": (time.perf_counter() - started) / count}


def worker(args) -> None:
    """Run episodes ``args.first``... until the deadline; one JSON line per episode, then one for the cycles."""
    from fmpy import read_model_description
    from fmpy.fmi2 import FMU2Slave

    description = read_model_description(args.unzipped)
    fmu = FMU2Slave(guid=description.guid, unzipDirectory=args.unzipped,
                    modelIdentifier=description.coSimulation.modelIdentifier, instanceName="fuzz")
    index = args.first
    while time.time() < args.deadline and (args.episode is None or index == args.episode) and (
            args.episodes is None or index < args.episodes):
        print(json.dumps({"start": index}), flush=True)
        episode = Episode(fmu, description, index, args.seed, args.slow)
        episode.run(args.steps)
        print(json.dumps({"episode": index, "steps": {f"{k}|{s}": n for (k, s), n in episode.steps.items()},
                          "ops": dict(episode.ops), "findings": episode.findings, "reasons": dict(episode.reasons),
                          "max_step": max(episode.times, default=0.0), "step_time": sum(episode.times),
                          "parameters": {k: repr(v) for k, v in episode.parameters.items()}}), flush=True)
        if episode.dead:
            return  # a Fatal leaves pythonfmu's objects freed: a fresh worker continues
        index += 1
        if args.episode is not None:
            break
    if args.cycles and args.episode is None:
        print(json.dumps({"memory": cycles(fmu, args.cycles)}), flush=True)


# ---------------------------------------------------------------------------------------------------- the runner
def build(folder: Path) -> Path:
    done = subprocess.run([sys.executable, str(ROOT / "build_fmu.py"), "--dest", str(folder)], capture_output=True,
                          text=True, timeout=300)
    if done.returncode != 0:
        raise SystemExit(f"build_fmu.py failed:\n{done.stdout}\n{done.stderr}")
    return folder / "RollingContact2D.fmu"


def campaign(args, unzipped: str) -> dict:
    """Run workers until the time budget is spent; restart after a crash or hang (each a finding)."""
    started = time.time()
    deadline = started + args.time
    results = {"episodes": [], "findings": [], "memory": None}
    first = 0 if args.episode is None else args.episode
    while True:
        command = [sys.executable, __file__, "--worker", "--unzipped", unzipped, "--seed", str(args.seed),
                   "--first", str(first), "--deadline", repr(deadline), "--steps", str(args.steps),
                   "--slow", repr(args.slow), "--cycles", str(args.cycles)]
        if args.episodes is not None:
            command += ["--episodes", str(args.episodes)]
        if args.episode is not None:
            command += ["--episode", str(args.episode)]
        process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        current, finished = None, False
        try:
            stdout, stderr = process.communicate(timeout=max(deadline - time.time(), 0.0) + args.hang)
        except subprocess.TimeoutExpired:
            process.kill()
            stdout, stderr = process.communicate()
        for line in stdout.splitlines():
            record = json.loads(line)
            if "start" in record:
                current = record["start"]
            elif "episode" in record:
                results["episodes"].append(record)
                results["findings"] += record["findings"]
                current = None
            elif "memory" in record:
                results["memory"] = record["memory"]
                finished = True
        code = process.returncode
        if code is not None and code > 0:
            raise SystemExit(f"the fuzz worker failed (a defect of this script, not a finding):\n{stderr[-3000:]}")
        if current is None and code is not None and code < 0:  # every result delivered, then the process died
            results["findings"].append({"kind": "exit", "episode": -1,
                                        "detail": f"worker process ended (signal {-code}) after its last result: "
                                                  f"{stderr.strip()[-300:]}"})
        if current is not None:  # the worker died (a signal) or hung inside an episode
            why = f"signal {-code}" if code is not None and code < 0 else f"exit {code}"
            results["findings"].append({"kind": "fatal", "episode": current,
                                        "detail": f"worker process ended ({why}): {stderr.strip()[-300:]}"})
            first = current + 1
        elif results["episodes"] and results["episodes"][-1]["findings"] and any(
                f["kind"] == "fatal" for f in results["episodes"][-1]["findings"]):
            first = results["episodes"][-1]["episode"] + 1  # after a Fatal the worker stopped
        else:
            finished = True
        if finished or time.time() >= deadline or args.episode is not None:
            break
    results["seconds"] = time.time() - started
    return results


def report(args, results: dict) -> str:
    """The markdown report."""
    episodes = results["episodes"]
    steps = collections.Counter()
    ops = collections.Counter()
    for e in episodes:
        steps.update({tuple(k.split("|")): n for k, n in e["steps"].items()})
        ops.update(e["ops"])
    names = {str(OK): "OK", str(WARNING): "Warning", str(DISCARD): "Discard", str(ERROR): "Error", str(FATAL): "Fatal"}
    kinds = sorted({k for k, _ in steps})
    lines = [f"# FMU fuzz campaign (seed {args.seed}{', quick' if args.quick else ''})", "",
             f"RollingContact2D through fmpy: {len(episodes)} episodes of up to {args.steps} operations in "
             f"{results['seconds']:.0f} s (budget {args.time:.0f} s); Python {sys.version.split()[0]}.  "
             f"Reproduce: `python benchmarks/fuzz_fmu.py --seed {args.seed} --episodes {len(episodes)} --steps "
             f"{args.steps}`; one episode: `--seed {args.seed} --steps {args.steps} --episode K`.", "",
             "## Steps by input kind and status", "",
             "| inputs | " + " | ".join(names.values()) + " | total |", "|---|" + "---:|" * (len(names) + 1)]
    for kind in kinds:
        row = [steps.get((kind, s), 0) for s in names]
        lines.append(f"| {kind} | " + " | ".join(map(str, row)) + f" | {sum(row)} |")
    reasons = collections.Counter()
    for e in episodes:
        reasons.update(e["reasons"])
    times = [e["max_step"] for e in episodes]
    total_steps = sum(steps.values())
    lines += ["", "## Operations", "", "| operation | count |", "|---|---:|"]
    lines += [f"| {name} | {count} |" for name, count in sorted(ops.items())]
    lines += ["", f"Slowest step {max(times, default=0.0):.3f} s; mean step "
                  f"{sum(e['step_time'] for e in episodes) / max(total_steps, 1) * 1e3:.2f} ms over {total_steps} "
                  "steps."]
    lines += ["", "## Why valid inputs with valid parameters were discarded (not findings)", "",
              "Numbers replaced by #; valid inputs on extreme parameters, after extreme steps or on corrugations.", "",
              "| reason | steps |", "|---|---:|"]
    lines += [f"| {reason.replace('|', '/')} | {n} |" for reason, n in reasons.most_common(12)]
    memory = results["memory"]
    if memory:
        lines += ["", f"Instantiate/free cycles: {memory['cycles']}, {memory['blocks']:.1f} Python memory blocks and "
                      f"{memory['rss'] / 1e3:.1f} kB RSS left per cycle, {memory['seconds'] * 1e3:.1f} ms per cycle."]
        if memory["blocks"] > 40:
            results["findings"].append({"kind": "memory", "episode": -1,
                                        "detail": f"{memory['blocks']:.1f} Python blocks left per cycle"})
    findings = results["findings"]
    lines += ["", f"## Findings: {len(findings)}", ""]
    if findings:
        lines += ["| kind | episode | detail |", "|---|---:|---|"]
        lines += [f"| {f['kind']} | {f['episode']} | {f['detail'].replace('|', '/')} |" for f in findings]
        counts = collections.Counter(f["kind"] for f in findings)
        lines += ["", "By kind: " + ", ".join(f"{k} {n}" for k, n in sorted(counts.items())) + "."]
    else:
        lines.append("None.")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--time", type=float, default=120.0, help="time budget [s] (default 120; quick 30)")
    parser.add_argument("--quick", action="store_true", help="a few seconds, no report file unless --out")
    parser.add_argument("--fmu", help="the FMU to fuzz (default: build it with build_fmu.py)")
    parser.add_argument("--out", help=f"report file (default {RESULTS.relative_to(ROOT)}; none with --quick)")
    parser.add_argument("--episode", type=int, help="replay this episode only")
    parser.add_argument("--episodes", type=int, default=None,
                        help="run episodes 0 to N-1 (default: as many as the time allows; quick 150)")
    parser.add_argument("--steps", type=int, default=None, help="operations per episode (default 40; quick 12)")
    parser.add_argument("--slow", type=float, default=5.0, help="a step slower than this [s] is a finding")
    parser.add_argument("--hang", type=float, default=60.0, help="a worker silent this long [s] is a hang")
    parser.add_argument("--cycles", type=int, default=None, help="instantiate/free cycles (default 400; quick 60)")
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--unzipped", help=argparse.SUPPRESS)
    parser.add_argument("--first", type=int, default=0, help=argparse.SUPPRESS)
    parser.add_argument("--deadline", type=float, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.steps is None:
        args.steps = 12 if args.quick else 40
    if args.cycles is None:
        args.cycles = 60 if args.quick else 400
    if args.worker:
        worker(args)
        return 0
    if args.quick and args.time == 120.0:
        args.time = 30.0  # a cap: quick runs a fixed number of episodes, the same on any machine
    if args.quick and args.episodes is None:
        args.episodes = 150
    from fmpy import extract

    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="fuzz_fmu_") as tmp:
        fmu = Path(args.fmu) if args.fmu else build(Path(tmp))
        unzipped = extract(str(fmu), unzipdir=str(Path(tmp) / "unzipped"))
        results = campaign(args, unzipped)
    text = report(args, results) + "\nRun on:\n\n" + "\n".join(common.machine(load)) + "\n"
    print(text)
    out = args.out or (None if args.quick or args.episode is not None else RESULTS)
    if out:
        Path(out).parent.mkdir(parents=True, exist_ok=True)
        Path(out).write_text(text)
    print(json.dumps({"findings": len(results["findings"]), "episodes": len(results["episodes"])}))
    return 1 if results["findings"] else 0


if __name__ == "__main__":
    sys.exit(main())
