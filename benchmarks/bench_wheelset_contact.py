"""Microseconds per WheelsetContact FMU step through fmpy, per level, with and without the geometry table, FMI 2.0 and
3.0, against empty FMUs of the same variables, in one run; the table's initialisation; the search's passes (scans of
the gap, contact points) a step makes without the table.

One step is what a master does per communication point: set the 8 inputs, ``doStep``, get the 30 real and 3 integer
outputs (fmpy's ``FMU2Slave``, or ``FMU3Slave`` behind the same calls, ``rollcontact_cosim.master.Slave``).  The inputs
vary every step (lateral shift over the tread and flange root, yaw, their rates, loads); batches of all cases are
interleaved and the tables show medians, so that a noisy machine affects every case alike.  The empty FMUs (pythonfmu
and pythonfmu3, ``do_step`` returning True) have the FMU's inputs and outputs: the floor of a step.

Cases: ``hertz`` with the saturated linear theory (the default: through the table, the fastest level), ``strips`` and
``discretised`` (without the derivatives, ``jacobian`` = none: the level's own step; the discretised level without a
step budget), and ``strips`` with the derivatives (the default ``jacobian``), each with the table on and off.
Usage: ``python benchmarks/bench_wheelset_contact.py [--rounds N] [--quick]``; the results go to
``results/wheelset_contact.md`` with the machine (not after ``--quick``).
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import tempfile
import textwrap
import time
from pathlib import Path

import common  # before numpy: limits BLAS to one thread; puts the checkout on sys.path

import rollcontact.stepping.wheelrail.model as stepping_model
import rollcontact.wheelrail.normal as normal
import rollcontact.wheelrail.search as search
from build_fmu import build
from rollcontact.stepping import WheelsetContactModel, WheelsetContactParameters

INPUTS = ("lateral_shift", "yaw", "lateral_velocity", "yaw_rate", "forward_speed", "pitch_rate",
          "vertical_load_left", "vertical_load_right")
REALS, INTEGERS = 30, 3
V = 30.0

EMPTY = {2: textwrap.dedent('''
    """Empty pythonfmu slave with WheelsetContact's inputs and outputs."""
    from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real


    class EmptyWheelset2(Fmi2Slave):
        def __init__(self, **kwargs):
            super().__init__(**kwargs)
            for name in {inputs}:
                setattr(self, name, 0.0)
                self.register_variable(Real(name, causality=Fmi2Causality.input,
                                            variability=Fmi2Variability.continuous))
            for i in range({reals}):
                setattr(self, f"y{{i}}", 0.0)
                self.register_variable(Real(f"y{{i}}", causality=Fmi2Causality.output,
                                            variability=Fmi2Variability.continuous))
            for i in range({integers}):
                setattr(self, f"n{{i}}", 0)
                self.register_variable(Integer(f"n{{i}}", causality=Fmi2Causality.output,
                                               variability=Fmi2Variability.discrete))

        def do_step(self, current_time, step_size):
            return True
'''), 3: textwrap.dedent('''
    """Empty pythonfmu3 slave with WheelsetContact's inputs and outputs."""
    from pythonfmu3 import Fmi3Causality, Fmi3Slave, Fmi3Variability, Float64, Int32


    class EmptyWheelset3(Fmi3Slave):
        def __init__(self, **kwargs):
            super().__init__(**kwargs)
            self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                           variability=Fmi3Variability.continuous))
            for name in {inputs}:
                setattr(self, name, 0.0)
                self.register_variable(Float64(name, causality=Fmi3Causality.input,
                                               variability=Fmi3Variability.continuous))
            for i in range({reals}):
                setattr(self, f"y{{i}}", 0.0)
                self.register_variable(Float64(f"y{{i}}", causality=Fmi3Causality.output,
                                               variability=Fmi3Variability.continuous))
            for i in range({integers}):
                setattr(self, f"n{{i}}", 0)
                self.register_variable(Int32(f"n{{i}}", causality=Fmi3Causality.output,
                                             variability=Fmi3Variability.discrete))

        def do_step(self, current_time, step_size):
            return True
''')}

LEVELS = {"hertz, saturated": {"method": 1, "elliptic_method": 5},
          "strips": {"method": 2, "jacobian": 1},
          "strips, with its derivatives": {"method": 2},
          "discretised": {"method": 3, "jacobian": 1, "step_budget": 0.0}}
"""The levels timed and their parameters (the default jacobian, forward differences, for hertz and the strips' second
row: four more solves per step, the velocities' two from the step's normal solutions; the discretised level without a
step budget: its cheapest setting is modelled above the default 0.05 s, which refuses the step)."""


def signal(n: int) -> list[float]:
    """Step n's inputs: the lateral shift over tread and flange root (+-5.5 mm), yaw, rates, speed, loads."""
    t = 1e-3 * n
    return [5.5e-3 * math.sin(2 * math.pi * 1.3 * t), 2e-3 * math.cos(2 * math.pi * 1.3 * t),
            0.045 * math.cos(2 * math.pi * 1.3 * t), -0.016 * math.sin(2 * math.pi * 1.3 * t), V, -V / 0.46,
            8e4 * (1 + 0.05 * math.sin(2 * math.pi * 3 * t)), 8e4 * (1 - 0.05 * math.sin(2 * math.pi * 3 * t))]


class Case:
    """One initialised instance, stepped on :func:`signal` and timed in batches."""

    def __init__(self, label: str, fmu: Path, parameters: dict, steps: int, fmi: int):
        from rollcontact_cosim.master import INTEGER_TYPES, REAL_TYPES, Slave

        self.label, self.steps, self.fmi = label, steps, fmi
        self.slave = Slave(fmu, label)
        self.slave.set_start_values(parameters)
        clock = time.perf_counter()
        self.slave.initialise()
        self.init_time = time.perf_counter() - clock
        variables = self.slave.description.modelVariables
        self.inputs = [v.valueReference for v in variables if v.causality == "input"]
        self.reals = [v.valueReference for v in variables if v.causality == "output" and v.type in REAL_TYPES]
        self.integers = [v.valueReference for v in variables if v.causality == "output" and v.type in INTEGER_TYPES]
        assert (len(self.inputs), len(self.reals), len(self.integers)) == (8, REALS, INTEGERS), label
        self.n, self.times, self.discards = 0, [], 0

    def batch(self) -> None:
        from fmpy.fmi1 import FMICallException

        fmu = self.slave.fmu
        start = time.perf_counter()
        for n in range(self.n, self.n + self.steps):
            fmu.setReal(self.inputs, signal(n))
            try:
                fmu.doStep(n * 1e-3, 1e-3)
            except FMICallException:
                self.discards += 1
            fmu.getReal(self.reals)
            fmu.getInteger(self.integers)
        self.times.append((time.perf_counter() - start) / self.steps * 1e6)
        self.n += self.steps

    def free(self) -> None:
        self.slave.free()


def empty_fmus(tmp: Path) -> dict[int, Path]:
    """Build the empty FMUs (FMI 2.0 and 3.0)."""
    from pythonfmu.builder import FmuBuilder as Builder2
    from pythonfmu3 import FmuBuilder as Builder3

    out = {}
    for fmi, builder in ((2, Builder2), (3, Builder3)):
        script = tmp / f"rollcontact_bench_empty_wheelset{fmi}.py"
        script.write_text(EMPTY[fmi].format(inputs=INPUTS, reals=REALS, integers=INTEGERS))
        out[fmi] = Path(builder.build_FMU(script, dest=tmp / f"empty{fmi}"))
    return out


SEARCH_STEPS = 20
"""Steps of the signal (every 50th) the searches are counted over."""


def searches_per_step(parameters: dict) -> tuple[float, float]:
    """The search's two passes of one wheel per step of the model without the table, on the signal: the scans of the
    gap over the profiles (``scan_gap``: the rigid wheelset's roll iterates on them) and the contact points and
    patches made of them (``contact_from_scan``), wherever they are called (over two wheels)."""
    calls = {"scan_gap": 0, "contact_from_scan": 0}
    originals = [(module, name, getattr(module, name)) for module in (search, normal) for name in calls]

    def counted(name, function):
        def wrapper(*args, **kwargs):
            calls[name] += 1
            return function(*args, **kwargs)
        return wrapper

    for module, name, function in originals:
        setattr(module, name, counted(name, function))
    try:
        model = WheelsetContactModel(WheelsetContactParameters(geometry_table=0, **parameters))
        for n in range(SEARCH_STEPS):
            model.step(n * 1e-3, 1e-3, signal(50 * n))
    finally:
        for module, name, function in originals:
            setattr(module, name, function)
    return calls["scan_gap"] / SEARCH_STEPS / 2, calls["contact_from_scan"] / SEARCH_STEPS / 2


def table_initialisation(repeats: int) -> list[float]:
    """Seconds to build the model with the table (the process's table cache emptied first), ``repeats`` times."""
    out = []
    for _ in range(repeats):
        stepping_model._tables.clear()
        clock = time.perf_counter()
        WheelsetContactModel(WheelsetContactParameters())
        out.append(time.perf_counter() - clock)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=9, help="timed batches per case (default 9)")
    parser.add_argument("--quick", action="store_true", help="3 rounds, fewer steps; nothing written")
    args = parser.parse_args()
    rounds = 3 if args.quick else args.rounds
    initialisation = table_initialisation(1 if args.quick else 3)
    searches = {"hertz, saturated, with its derivatives": searches_per_step(LEVELS["hertz, saturated"]),
                "hertz, saturated, jacobian = none": searches_per_step({"method": 1, "jacobian": 1})}
    with tempfile.TemporaryDirectory(prefix="bench_wheelset_contact_") as folder:
        tmp = Path(folder)
        fmus = {fmi: build("WheelsetContact", tmp / f"fmi{fmi}", fmi=fmi) for fmi in (2, 3)}
        empty = empty_fmus(tmp)
        cases = []
        for fmi in (2, 3):
            cases.append(Case(f"empty, FMI {fmi}.0", empty[fmi], {}, 400, fmi))
            for level, parameters in LEVELS.items():
                for table in (1, 0):
                    slow = level != "hertz, saturated" or not table
                    steps = (1 if level == "discretised" else 4 if slow else 400) // (2 if args.quick else 1) or 1
                    cases.append(Case(f"{level}, table {'on' if table else 'off'}, FMI {fmi}.0", fmus[fmi],
                                      {**parameters, "geometry_table": table}, steps, fmi))
        for case in cases:
            case.batch()
            case.times.clear()
        for _ in range(rounds):
            for case in cases:
                if case.label.startswith("discretised") and len(case.times) >= 3:
                    continue
                case.batch()
        floor = {case.fmi: statistics.median(case.times) for case in cases if case.label.startswith("empty")}
        lines = ["# WheelsetContact: the step's cost", "",
                 f"fmpy, pythonfmu 0.7.0, pythonfmu3 0.3.4, Python {sys.version.split()[0]}; one step = set the 8 "
                 "inputs + doStep + get the 30 real and 3 integer outputs, on inputs varying every step (S1002/UIC60, "
                 "lateral shift +-5.5 mm at 1.3 Hz, 30 m/s, 80 kN +-5 % per wheel); medians of interleaved batches "
                 "(the discretised level: 3 batches of one step, without a step budget); strips and discretised "
                 "without the derivatives (jacobian = none), hertz and the strips' second row with them (the "
                 "default); the ratio is to the empty FMU of the same FMI version in the same run.", "",
                 "| case | us per step | ratio to the empty FMU | batches | discarded |", "|---|---:|---:|---:|---:|"]
        for case in cases:
            median = statistics.median(case.times)
            lines.append(f"| {case.label} | {median:.1f} | {median / floor[case.fmi]:.1f} | {len(case.times)} | "
                         f"{case.discards} |")
        for case in cases:
            case.free()
    lines += ["", "Initialisation with the geometry table (the model with an empty table cache: the table over "
              "+-12 mm built, the tabulated contact's constants computed): "
              + ", ".join(f"{t:.2f} s" for t in initialisation)
              + f" (median {statistics.median(initialisation):.2f} s)",
              "", f"The search's passes per wheel and step without the table ({SEARCH_STEPS} steps of the signal): "
              "scans of the gap over the profiles (`scan_gap`, the rigid wheelset's roll iterates on them; at each "
              "pose solved, the step's and with the derivatives the shifted lateral shift's and yaw's) and the "
              "contact points and patches made of them (`contact_from_scan`, once per pose: the scene is given "
              "them, the velocities' differences share the step's):", ""]
    lines += [f"- {label}: {scans:.1f} scans, {contacts:.1f} contact points" for label, (scans, contacts)
              in searches.items()]
    print("\n".join(lines))


if __name__ == "__main__":
    common.run_and_publish(main, "wheelset_contact.md")
