"""Microseconds per FMU step of 1, 2, 4 and 8 contacts in one instance, FMI 2.0 and 3.0, against empty FMUs, in one
run.

One step is what a co-simulation master does per communication point: set every input, ``doStep``, get every real
and integer output, through fmpy, in two ways of calling it (the *host*):

* ``lists``: fmpy's ``FMU2Slave.setReal(vrs, values)`` / ``getReal(vrs)`` (FMI 3.0: ``FMU3Slave.setFloat64``,
  ``getFloat64(vrs, nValues)``, ``getInt64``), which build new ctypes arrays of the value references and the values
  on every call and convert every value between Python and C (about 0.05 us per value, so these calls cost more per
  contact than the cheap levels do);
* ``buffers``: the same FMI functions through fmpy's ctypes bindings (``fmu.fmi2SetReal(component, vrs, n,
  values)`` ...) on arrays of value references and values allocated once, as a compiled master keeps its buffers: the
  step's new inputs are copied into the input buffer, the outputs are left in theirs.

FMI 2.0 FMUs declare ``name[k]`` scalars, the FMI 3.0 FMUs (``build_fmu.py --fmi 3``) one array ``name`` of n values
per per-contact variable, so an FMI 3.0 call carries a handful of value references whatever n.  Cases, each on a
varying signal (load 80 kN +-10 %, creepages swinging through a third of saturation, speed 30 m/s):

* ``RollingContact3D_n`` (its inputs but the gap's curvatures, which keep their start: the parameters' geometry)
  with the linear level (``method`` = linear: the contacts' linear theory without a solver
  call per contact, :class:`rollcontact.stepping.elliptic.linear.LinearContacts`), with the strips without spin and with
  spin (one ``solve_strips_many`` over the contacts), and with the default ``method`` = auto (whose choice, the strips,
  is solved over the contacts in the same way), with Coulomb friction and on a wet rail (Polach's wet law: friction
  falling with each cell's slip velocity) with spin, and FASTSIM on the wet rail with spin (one
  ``solve_fastsim_many``), n = 1, 2, 4, 8;
* the 2D closed form: ``RollingContact2D_n`` (:class:`rollcontact.stepping.line.contacts.ContactModels`), and n
  single-contact instances stepped one after another (what a host pays without several contacts per instance);
* the 2D certified table of falling friction (exponential law A 0.4, B 0.6 s/m, tolerance 1e-3, ``table`` = on:
  each contact builds its table at its first loaded step, in the untimed warm-up, and answers every step from it);
* floors: empty FMUs with the inputs and outputs of n 2D contacts and a ``do_step`` that returns True, either
  pythonfmu's own getters and setters (a Python call per variable) or a slave that answers every get and set in one
  list operation (FMI 2.0 scalars, FMI 3.0 arrays): the cost of the variables alone, host and binding.

Batches of all cases are interleaved and the tables show medians, so that a noisy machine affects every case alike;
one BLAS thread (``common.py``).  The goal of the n-contact FMU: a step of 8 contacts costs at most twice a step of
one contact of the same level, FMI version and host; what it leaves for the work of the 8 contacts is twice the step
of one less the empty FMU of 8 contacts, printed against what their step takes above that empty FMU.  Last, the same
2D contacts in process, without FMU and host (:func:`in_process`): the step of ``ContactModels`` of 1, 2, 3, 4, 5 and
8 contacts against one ``ContactModel``, the certified tables (falling friction, corrugation) evaluated together and
one by one, which calibrates ``rollcontact.stepping.line.table.TOGETHER_FROM``, and the 8 contacts' closed-form outputs
alone (``ContactModel.closed_form_step``, no state, no checks): the least Python work of a closed-form step.
Usage: ``python benchmarks/bench_contacts.py [--rounds N] [--quick]``; writes ``benchmarks/results/contacts.md``
(not after ``--quick``).
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import tempfile
import time
from pathlib import Path

import common  # before numpy: limits BLAS to one thread; puts the checkout on sys.path

from build_fmu import build

COUNTS = (1, 2, 4, 8)
HOSTS = ("lists", "buffers")

EMPTY_PER_VARIABLE = '''
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real


class EmptyContacts{n}(Fmi2Slave):
    """Empty pythonfmu slave with the variables of RollingContact2D_{n}, pythonfmu's getters and setters."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        for k in range({n}):
            for name in ("normal_load", "creep", "velocity"):
                setattr(self, f"{{name}}_{{k}}", 0.0)
                self.register_variable(Real(f"{{name}}_{{k}}", causality=Fmi2Causality.input,
                                            variability=Fmi2Variability.continuous))
        for k in range({n}):
            for i in range(10):
                setattr(self, f"y{{i}}_{{k}}", 0.0)
                self.register_variable(Real(f"y{{i}}_{{k}}", causality=Fmi2Causality.output,
                                            variability=Fmi2Variability.continuous))
            setattr(self, f"method_used_{{k}}", 0)
            self.register_variable(Integer(f"method_used_{{k}}", causality=Fmi2Causality.output,
                                           variability=Fmi2Variability.discrete))

    def do_step(self, current_time, step_size):
        return True
'''
"""Source of an empty pythonfmu slave with the inputs and outputs of n 2D contacts (``{n}``: the count)."""

EMPTY_BULK2 = '''
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real


class EmptyBulk{n}(Fmi2Slave):
    """Empty pythonfmu slave with the variables of RollingContact2D_{n}, each get and set one list operation."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        for k in range({n}):
            for name in ("normal_load", "creep", "velocity"):
                self.register_variable(Real(f"{{name}}[{{k + 1}}]", causality=Fmi2Causality.input,
                                            variability=Fmi2Variability.continuous, getter=lambda: 0.0,
                                            setter=lambda value: None))
        for k in range({n}):
            for i in range(10):
                self.register_variable(Real(f"y{{i}}[{{k + 1}}]", causality=Fmi2Causality.output,
                                            variability=Fmi2Variability.continuous, getter=lambda: 0.0))
            self.register_variable(Integer(f"method_used[{{k + 1}}]", causality=Fmi2Causality.output,
                                           variability=Fmi2Variability.discrete, getter=lambda: 0))
        self.inputs = [0.0] * (3 * {n})
        self.reals = [0.0] * (10 * {n})
        self.integers = [0] * {n}

    def set_real(self, vrs, values):
        self.inputs = list(values)

    def get_real(self, vrs):
        return self.reals[:len(vrs)]

    def get_integer(self, vrs):
        return self.integers[:len(vrs)]

    def do_step(self, current_time, step_size):
        return True
'''
"""Source of an empty FMI 2.0 slave of n 2D contacts' variables answering every call in one list operation."""

EMPTY_BULK3 = '''
from pythonfmu3 import Dimension, Fmi3Causality, Fmi3Initial, Fmi3Slave, Fmi3Variability, Float64, Int64


class EmptyArrays{n}(Fmi3Slave):
    """Empty pythonfmu3 slave with the variables of RollingContact2D_{n} as arrays, each get and set one list
    operation."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        dimensions = [Dimension(start="{n}")] if {n} > 1 else []
        self.time = 0.0
        self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                       variability=Fmi3Variability.continuous))
        for name in ("normal_load", "creep", "velocity"):
            setattr(self, name, 0.0)
            self.register_variable(Float64(name, causality=Fmi3Causality.input, start=[0.0] * {n} if {n} > 1 else
                                           0.0, variability=Fmi3Variability.continuous, dimensions=dimensions,
                                           getter=lambda: 0.0, setter=lambda value: None))
        for i in range(10):
            self.register_variable(Float64(f"y{{i}}", causality=Fmi3Causality.output, start=[0.0] * {n} if {n} > 1
                                           else 0.0, variability=Fmi3Variability.continuous, dimensions=dimensions,
                                           initial=Fmi3Initial.approx, getter=lambda: 0.0))
        self.register_variable(Int64("method_used", causality=Fmi3Causality.output, start=[0] * {n} if {n} > 1
                                     else 0, variability=Fmi3Variability.discrete, dimensions=dimensions,
                                     initial=Fmi3Initial.approx, getter=lambda: 0))
        self.inputs = [0.0] * (3 * {n})
        self.reals = [0.0] * (10 * {n})
        self.integers = [0] * {n}

    def set_float64(self, vrs, values):
        if vrs != [0]:  # time: not set by hosts
            self.inputs = list(values)

    def get_float64(self, vrs):
        return self.reals[:len(vrs) * {n}] if vrs != [0] else [0.0]

    def get_int64(self, vrs):
        return self.integers[:len(vrs) * {n}]

    def do_step(self, current_time, step_size):
        return True
'''
"""Source of an empty FMI 3.0 slave of n 2D contacts' variables as arrays, answering every call in one list
operation."""


def build_empty(tmp: Path, n: int, source: str, fmi: int = 2) -> str:
    """The empty FMU of ``source`` for n contacts, built and unzipped into ``tmp``; its unzip directory."""
    from fmpy import extract

    if fmi == 2:
        from pythonfmu.builder import FmuBuilder
    else:
        from pythonfmu3 import FmuBuilder
    folder = tmp / f"empty_{abs(hash(source))}_{n}"
    script = folder / f"rollcontact_bench_empty_{fmi}_{abs(hash(source))}_{n}.py"
    folder.mkdir()
    script.write_text(source.format(n=n))
    return extract(str(FmuBuilder.build_FMU(script, dest=folder)), unzipdir=str(folder / "u"))


def unlogged(environment, status, category, message) -> None:
    """The FMI 3.0 instances' log callback: nothing printed (pythonfmu3 passes every message of status Warning on,
    such as a certified table's build notices, whatever the debug logging; the FMI 2.0 instances log nothing
    without it)."""


class Instances:
    """FMU instances stepped together as one case: each step sets every instance's inputs, steps it and reads its
    outputs, in the way of ``host`` (module docstring); the signal of contact k of step n is :meth:`inputs_of`.
    ``parameters``: name -> value, a list for an FMI 3.0 array."""

    def __init__(self, label: str, unzipped: str, copies: int, parameters: dict, steps: int, spin: float,
                 host: str = "lists"):
        import ctypes

        from fmpy import read_model_description
        from fmpy.fmi2 import FMU2Slave
        from fmpy.fmi3 import FMU3Slave

        self.label, self.steps, self.spin, self.host = label, steps, spin, host
        md = read_model_description(unzipped)
        self.fmi = 3 if md.fmiVersion.startswith("3") else 2
        variables = {v.name: v for v in md.modelVariables}

        def count(v) -> int:
            return math.prod(int(d.start) for d in v.dimensions) if self.fmi == 3 else 1

        self.fmus = []
        for i in range(copies):
            kind = FMU3Slave if self.fmi == 3 else FMU2Slave
            fmu = kind(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                       instanceName=f"{label} {i}")
            fmu.instantiate(**({"logMessage": unlogged} if self.fmi == 3 else {}))
            for name, value in parameters.items():
                vr, real = [variables[name].valueReference], variables[name].type in ("Real", "Float64")
                values = value if isinstance(value, list) else [value]
                if self.fmi == 2:
                    (fmu.setReal if real else fmu.setInteger)(vr, values)
                else:
                    (fmu.setFloat64 if real else fmu.setInt64)(vr, values)
            if self.fmi == 2:
                fmu.setupExperiment(startTime=0.0)
                fmu.enterInitializationMode()
            else:
                fmu.enterInitializationMode(startTime=0.0)
            fmu.exitInitializationMode()
            self.fmus.append(fmu)
        inputs = [v for v in md.modelVariables if v.causality == "input" and not v.name.startswith("gap_")]
        reals = [v for v in md.modelVariables if v.causality == "output" and v.type in ("Real", "Float64")]
        integers = [v for v in md.modelVariables if v.causality == "output" and v.type not in ("Real", "Float64")]
        self.inputs, self.reals, self.integers = ([v.valueReference for v in group]
                                                  for group in (inputs, reals, integers))
        self.counts = [sum(count(v) for v in group) for group in (inputs, reals, integers)]
        self.kind = "3d" if any(v.name.startswith("longitudinal_creep") for v in inputs) else "2d"
        self.contacts = self.counts[0] // (5 if self.kind == "3d" else 3)
        self.by_input = self.fmi == 3 and self.contacts > 1  # arrays: values input by input
        if host == "buffers":
            from fmpy.fmi2 import fmi2Integer, fmi2Real, fmi2ValueReference
            from fmpy.fmi3 import fmi3Float64, fmi3Int64, fmi3ValueReference

            vr_type = fmi3ValueReference if self.fmi == 3 else fmi2ValueReference
            real, integer = (fmi3Float64, fmi3Int64) if self.fmi == 3 else (fmi2Real, fmi2Integer)
            self.buffers = [((vr_type * len(vrs))(*vrs), (kind * n)()) for vrs, n, kind in
                            zip((self.inputs, self.reals, self.integers), self.counts, (real, real, integer),
                                strict=True)]
            self.ctypes = ctypes
        self.n = 0
        self.times: list[float] = []
        self.discards = 0

    def inputs_of(self, n: int) -> list[float]:
        rows = []
        for k in range(self.contacts):
            phase = 0.01 * n + 0.7 * k
            load = 8e4 * (1.0 + 0.1 * math.sin(phase))
            if self.kind == "2d":
                rows.append((load, 1e-3 * math.cos(phase), 30.0))
            else:
                rows.append((load, 1e-3 * math.cos(phase), -5e-4 * math.sin(phase), self.spin * math.sin(phase),
                             30.0))
        if self.by_input:
            return [row[i] for i in range(len(rows[0])) for row in rows]
        return [v for row in rows for v in row]

    def step_calls(self, fmu):
        """The host's calls of one step for ``fmu``: ``(set(values), get())``."""
        n_in, n_real, n_int = self.counts
        if self.host == "lists":
            if self.fmi == 2:
                return (lambda values: fmu.setReal(self.inputs, values),
                        lambda: (fmu.getReal(self.reals), fmu.getInteger(self.integers)))
            return (lambda values: fmu.setFloat64(self.inputs, values),
                    lambda: (fmu.getFloat64(self.reals, n_real), fmu.getInt64(self.integers, n_int)))
        (vr_in, values_in), (vr_real, values_real), (vr_int, values_int) = self.buffers
        component = fmu.component
        if self.fmi == 2:
            set_real, get_real, get_int = fmu.fmi2SetReal, fmu.fmi2GetReal, fmu.fmi2GetInteger

            def put(values):
                values_in[:] = values
                set_real(component, vr_in, len(vr_in), values_in)

            return put, lambda: (get_real(component, vr_real, len(vr_real), values_real),
                                 get_int(component, vr_int, len(vr_int), values_int))
        set_real, get_real, get_int = fmu.fmi3SetFloat64, fmu.fmi3GetFloat64, fmu.fmi3GetInt64

        def put3(values):
            values_in[:] = values
            set_real(component, vr_in, len(vr_in), values_in, n_in)

        return put3, lambda: (get_real(component, vr_real, len(vr_real), values_real, n_real),
                              get_int(component, vr_int, len(vr_int), values_int, n_int))

    def batch(self) -> None:
        from fmpy.fmi1 import FMICallException

        h = 1e-3
        signals = [self.inputs_of(n) for n in range(self.n, self.n + self.steps)]
        calls = [(fmu, *self.step_calls(fmu)) for fmu in self.fmus]
        start = time.perf_counter()
        for n, values in enumerate(signals, start=self.n):
            for fmu, put, get in calls:
                put(values)
                try:
                    fmu.doStep(n * h, h)
                except FMICallException:
                    self.discards += 1
                get()
        self.times.append((time.perf_counter() - start) / self.steps * 1e6)
        self.n += self.steps

    def free(self) -> None:
        for fmu in self.fmus:
            fmu.terminate()
            fmu.freeInstance()


def contact_parameters(fmi: int, n: int, parameters: dict, curvatures: bool) -> dict:
    """The case's parameters with the 3D contacts' curvatures (contact k: A = 1.087 + 0.1 k, B = 1.667 [1/m]) as
    FMI 2.0 ``name[k]`` scalars or FMI 3.0 arrays."""
    if not curvatures:
        return dict(parameters)
    values = {"curvature_longitudinal": [1.087 + 0.1 * k for k in range(1, n + 1)], "curvature_lateral": [1.667] * n}
    if n == 1:
        return {**parameters, **{name: value[0] for name, value in values.items()}}
    if fmi == 3:
        return {**parameters, **values}
    return {**parameters, **{f"{name}[{k}]": value[k - 1] for name, value in values.items() for k in range(1, n + 1)}}


FAMILIES = {  # label -> (model, parameters, steps per batch, spin [1/m])
    "2D closed form": ("RollingContact2D", {"method": 1}, 100, 0.0),
    "2D table, falling friction": ("RollingContact2D", {"friction_law": 1, "friction_kinetic_ratio": 0.4,
                                                        "friction_decay": 0.6, "tolerance": 1e-3, "table": 2}, 100,
                                   0.0),
    "3D linear": ("RollingContact3D", {"method": 1}, 100, 0.0),
    "3D strips, no spin": ("RollingContact3D", {"method": 3}, 30, 0.0),
    "3D strips, spin": ("RollingContact3D", {"method": 3}, 10, 0.3),
    "3D auto, no spin": ("RollingContact3D", {}, 30, 0.0),
    "3D auto, spin": ("RollingContact3D", {}, 10, 0.3),
    "3D auto, wet rail, spin": ("RollingContact3D", {"rail_condition": 2}, 10, 0.3),
    "3D fastsim, wet rail, spin": ("RollingContact3D", {"method": 2, "rail_condition": 2}, 10, 0.3),
}
FLOORS = ("empty, pythonfmu's getters and setters", "empty, one list operation per call")


IN_PROCESS = {  # label -> the ContactParameters of the contacts stepped in process
    "2D closed form": {"method": 1},
    "2D table, falling friction": FAMILIES["2D table, falling friction"][1],
    "2D table, corrugation": {"corrugation_amplitude": 20e-6, "corrugation_wavelength": 0.04, "table": 2},
}
IN_PROCESS_COUNTS = (1, 2, 3, 4, 5, 8)


def in_process(rounds: int) -> None:
    """Print the microseconds per step of ``ContactModels`` in process (no FMU, no host) on the 2D signal of the FMU
    cases, against one ``ContactModel``: the closed forms' loop, and the certified tables evaluated together
    (``TablesTogether``) or one by one (``rollcontact.stepping.line.table.TOGETHER_FROM`` set for the batch), the same
    answers bit for bit; the calibration of ``TOGETHER_FROM``; and the 8 contacts' ``closed_form_step`` alone.  Batches
    of every case interleaved, medians."""
    from rollcontact.stepping import ContactModel, ContactParameters
    from rollcontact.stepping.line import table
    from rollcontact.stepping.line.contacts import ContactModels

    default = table.TOGETHER_FROM
    modes = {"one by one": 10 ** 9, "together": 1}
    signal = [[(8e4 * (1.0 + 0.1 * math.sin(0.01 * n + 0.7 * k)), 1e-3 * math.cos(0.01 * n + 0.7 * k), 30.0)
               for k in range(max(IN_PROCESS_COUNTS))] for n in range(200)]
    cases = {}  # (label, contacts, mode) -> [step(t, rows), times]
    for label, parameters in IN_PROCESS.items():
        single = ContactModel(ContactParameters(**parameters), stop_time=1e6)
        cases[label, 1, "ContactModel"] = [lambda t, rows, m=single: m.step(t, 1e-3, *rows[0]), []]
        for n in IN_PROCESS_COUNTS:
            for mode in modes if label != "2D closed form" else ("together",):
                models = ContactModels(ContactParameters(**parameters), n, stop_time=1e6)
                cases[label, n, mode] = [lambda t, rows, m=models, n=n: m.step(t, 1e-3, rows[:n]), []]
    alone = ContactModels(ContactParameters(**IN_PROCESS["2D closed form"]), 8, stop_time=1e6).models
    cases["2D closed form", 8, "closed forms alone"] = [
        lambda t, rows, models=alone: [m.closed_form_step(30.0 * t, *row)
                                       for m, row in zip(models, rows, strict=False)], []]
    try:
        for round_ in range(rounds + 1):  # the first round builds the tables, untimed
            for (_, _, mode), (step, times) in cases.items():
                table.TOGETHER_FROM = modes.get(mode, default)
                start = time.perf_counter()
                for i, rows in enumerate(signal):
                    step((round_ * len(signal) + i) * 1e-3, rows)
                if round_:
                    times.append((time.perf_counter() - start) / len(signal) * 1e6)
    finally:
        table.TOGETHER_FROM = default
    median = {key: statistics.median(times) for key, (_, times) in cases.items()}
    print(f"\nIn process (no FMU): us per step of n contacts (`ContactModels`) against one `ContactModel`; the tables "
          f"evaluated one by one or together (`TOGETHER_FROM` = {default} chooses together from {default} table "
          "contacts on); medians of the same run:\n")
    print("| case | contacts | tables one by one | stepped together | together / one by one | "
          "together / ContactModel |")
    print("|---|---:|---:|---:|---:|---:|")
    for label in IN_PROCESS:
        one = median[label, 1, "ContactModel"]
        print(f"| {label} | 1, ContactModel | | {one:.1f} | | 1.00 |")
        for n in IN_PROCESS_COUNTS:
            alone, together = median.get((label, n, "one by one")), median[label, n, "together"]
            print(f"| {label} | {n} | {'' if alone is None else f'{alone:.1f}'} | {together:.1f} | "
                  f"{'' if alone is None else f'{together / alone:.2f}'} | {together / one:.2f} |")
    alone = median["2D closed form", 8, "closed forms alone"]
    print(f"| 2D closed form | 8, `closed_form_step` alone (no state, no checks) | | {alone:.1f} | | "
          f"{alone / median['2D closed form', 1, 'ContactModel']:.2f} |")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=15, help="interleaved rounds (default 15)")
    parser.add_argument("--quick", action="store_true", help="3 rounds, results not written")
    args = parser.parse_args(argv)
    rounds = 3 if args.quick else args.rounds
    from fmpy import extract

    with tempfile.TemporaryDirectory(prefix="bench_contacts_") as tmp:
        unzipped = {(model, fmi, n): extract(str(build(model, Path(tmp, f"{model}{fmi}_{n}"), fmi=fmi, contacts=n)),
                                             unzipdir=str(Path(tmp, f"u{model}{fmi}_{n}")))
                    for model in ("RollingContact2D", "RollingContact3D") for fmi in (2, 3) for n in COUNTS}
        cases: dict[tuple, Instances] = {}
        for n in COUNTS:
            cases[FLOORS[0], 2, "lists", n] = Instances(f"empty {n}", build_empty(Path(tmp), n, EMPTY_PER_VARIABLE),
                                                        1, {}, 100, 0.0)
            bulk = {2: build_empty(Path(tmp), n, EMPTY_BULK2), 3: build_empty(Path(tmp), n, EMPTY_BULK3, fmi=3)}
            for fmi in (2, 3):
                for host in HOSTS:
                    cases[FLOORS[1], fmi, host, n] = Instances(f"bulk {fmi} {host} {n}", bulk[fmi], 1, {}, 100, 0.0,
                                                               host)
        for label, (model, parameters, steps, spin) in FAMILIES.items():
            for fmi in (2, 3):
                for host in HOSTS:
                    for n in COUNTS:
                        cases[label, fmi, host, n] = Instances(
                            f"{label} {fmi} {host} {n}", unzipped[model, fmi, n], 1,
                            contact_parameters(fmi, n, parameters, model == "RollingContact3D"), steps, spin, host)
        for n in COUNTS:
            cases["2D closed form, n instances", 2, "lists", n] = Instances(
                f"2D x{n}", unzipped["RollingContact2D", 2, 1], n, {"method": 1}, 100, 0.0)
        for case in cases.values():
            case.batch()
            case.times.clear()
        for _ in range(rounds):
            for case in cases.values():
                case.batch()
        median = {key: statistics.median(case.times) for key, case in cases.items()}
        print(f"fmpy {__import__('fmpy').__version__}, pythonfmu {__import__('pythonfmu').__version__}, pythonfmu3 "
              f"{__import__('pythonfmu3').__version__}, Python {sys.version.split()[0]}, {rounds} rounds; one step = "
              "set every input + doStep + get every output (of every instance); medians in us per step\n")
        print("Ratio of the step of 8 contacts to the step of one (the goal: at most 2):\n")
        print("| case | FMI 2.0, lists | FMI 2.0, buffers | FMI 3.0, lists | FMI 3.0, buffers |")
        print("|---|---:|---:|---:|---:|")
        labels = list(dict.fromkeys(key[0] for key in cases))
        for label in labels:
            cells = [f"{median[label, fmi, host, 8] / median[label, fmi, host, 1]:.2f}"
                     if (label, fmi, host, 8) in median else "" for fmi in (2, 3) for host in HOSTS]
            print(f"| {label} | " + " | ".join(cells) + " |")
        print("\nWhat the goal leaves for the work of 8 contacts: twice the step of one contact less the empty FMU of "
              "8 contacts (one list operation per call), against what their step takes above that empty FMU (us):\n")
        print("| case | FMI 2.0, lists | FMI 2.0, buffers | FMI 3.0, lists | FMI 3.0, buffers |")
        print("|---|---:|---:|---:|---:|")
        for label in FAMILIES:
            cells = [f"{2 * median[label, fmi, host, 1] - median[FLOORS[1], fmi, host, 8]:.1f} / "
                     f"{median[label, fmi, host, 8] - median[FLOORS[1], fmi, host, 8]:.1f}"
                     for fmi in (2, 3) for host in HOSTS]
            print(f"| {label} | " + " | ".join(cells) + " |")
        print("\nEvery case (above the floor: minus the empty FMU of one list operation per call, same FMI version, "
              "host and contacts):\n")
        print("| case | FMI | host | contacts | us per step | above the floor | ratio to 1 contact | discarded |")
        print("|---|---:|---|---:|---:|---:|---:|---:|")
        for (label, fmi, host, n), case in cases.items():
            floor = median[FLOORS[1], fmi, host, n]
            print(f"| {label} | {fmi}.0 | {host} | {n} | {median[label, fmi, host, n]:.1f} | "
                  f"{median[label, fmi, host, n] - floor:.1f} | "
                  f"{median[label, fmi, host, n] / median[label, fmi, host, 1]:.2f} | {case.discards} |")
        for case in cases.values():
            case.free()
    in_process(rounds)


if __name__ == "__main__":
    common.run_and_publish(main, "contacts.md")
