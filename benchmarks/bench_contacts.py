"""Microseconds per FMU step of 1, 2, 4 and 8 contacts in one instance, against an empty FMU, in one run.

One step is what a co-simulation master does per communication point: set every input, ``doStep``, get every real
and integer output, through fmpy's ``FMU2Slave``.  Cases, each on a varying signal (load 80 kN +-10 %, creepages
swinging through a third of saturation, speed 30 m/s):

* the empty pythonfmu FMU (``common.EMPTY_SLAVE``: RollingContact2D's inputs and outputs, a ``do_step`` that returns
  True): the floor of any step;
* ``RollingContact3D_n`` (``build_fmu.py --contacts n``) with the linear level (``method`` = linear: the contacts'
  linear theory without a solver call per contact, :class:`rollcontact.stepping.elliptic.LinearContacts`), with the
  strips without spin and with spin (one ``solve_strips_many`` over the contacts), n = 1, 2, 4, 8;
* the 2D closed form: ``RollingContact2D_n`` (one ``ContactModel`` per contact), and n single-contact instances
  stepped one after another (what a host pays without several contacts per instance);
* the 2D certified table of falling friction (exponential law A 0.4, B 0.6 s/m, tolerance 1e-3, ``table`` = on: each
  contact builds its table at its first loaded step, in the untimed warm-up, and answers every step from it);
* empty FMUs with the inputs and outputs of n 2D contacts: the floor that the variables alone set (pythonfmu's and
  fmpy's work per variable).

Batches of all cases are interleaved and the table shows medians, so that a noisy machine affects every case alike;
one BLAS thread (``common.py``).  The goal of the n-contact FMU: a step of 8 contacts costs at most twice a step of
one contact of the same level.  Usage: ``python benchmarks/bench_contacts.py [--rounds N] [--quick]``; writes
``benchmarks/results/contacts.md`` (not after ``--quick``).
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

from build_fmu import build, build_variant

COUNTS = (1, 2, 4, 8)

EMPTY_CONTACTS = '''
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real


class EmptyContacts{n}(Fmi2Slave):
    """Empty pythonfmu slave with the variables of RollingContact2D_{n}: the floor of its step."""

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


def build_empty(tmp: Path, n: int) -> str:
    """The empty FMU of n contacts' variables, built and unzipped into ``tmp``; its unzip directory."""
    from fmpy import extract
    from pythonfmu.builder import FmuBuilder

    source = tmp / f"empty{n}" / f"rollcontact_bench_empty_contacts{n}.py"
    source.parent.mkdir()
    source.write_text(EMPTY_CONTACTS.format(n=n))
    return extract(str(FmuBuilder.build_FMU(source, dest=tmp / f"empty{n}")), unzipdir=str(tmp / f"empty{n}u"))
INPUTS_3D = ("normal_load", "longitudinal_creep", "lateral_creep", "spin", "velocity")


class Instances:
    """FMU instances stepped together as one case: each step sets every instance's inputs, steps it and reads its
    outputs; the signal of contact k of step n is :meth:`inputs`."""

    def __init__(self, label: str, unzipped: str, copies: int, parameters: dict, steps: int, spin: float):
        from fmpy import read_model_description
        from fmpy.fmi2 import FMU2Slave

        self.label, self.steps, self.spin = label, steps, spin
        md = read_model_description(unzipped)
        variables = {v.name: v for v in md.modelVariables}
        self.fmus = []
        for i in range(copies):
            fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                            instanceName=f"{label} {i}")
            fmu.instantiate()
            for name, value in parameters.items():
                setter = fmu.setReal if variables[name].type == "Real" else fmu.setInteger
                setter([variables[name].valueReference], [value])
            fmu.setupExperiment(startTime=0.0)
            fmu.enterInitializationMode()
            fmu.exitInitializationMode()
            self.fmus.append(fmu)
        self.inputs = [v.valueReference for v in md.modelVariables if v.causality == "input"]
        self.kind = "3d" if "longitudinal_creep" in variables or "longitudinal_creep[1]" in variables else "2d"
        self.contacts = len(self.inputs) // (5 if self.kind == "3d" else 3)
        self.reals = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
        self.integers = [v.valueReference for v in md.modelVariables
                         if v.causality == "output" and v.type in ("Integer", "Enumeration")]
        self.n = 0
        self.times: list[float] = []
        self.discards = 0

    def inputs_of(self, n: int) -> list[float]:
        values = []
        for k in range(self.contacts):
            phase = 0.01 * n + 0.7 * k
            load = 8e4 * (1.0 + 0.1 * math.sin(phase))
            if self.kind == "2d":
                values += [load, 1e-3 * math.cos(phase), 30.0]
            else:
                values += [load, 1e-3 * math.cos(phase), -5e-4 * math.sin(phase), self.spin * math.sin(phase), 30.0]
        return values

    def batch(self) -> None:
        from fmpy.fmi1 import FMICallException

        h = 1e-3
        signals = [self.inputs_of(n) for n in range(self.n, self.n + self.steps)]
        start = time.perf_counter()
        for n, values in enumerate(signals, start=self.n):
            for fmu in self.fmus:
                fmu.setReal(self.inputs, values)
                try:
                    fmu.doStep(n * h, h)
                except FMICallException:
                    self.discards += 1
                fmu.getReal(self.reals)
                fmu.getInteger(self.integers)
        self.times.append((time.perf_counter() - start) / self.steps * 1e6)
        self.n += self.steps

    def free(self) -> None:
        for fmu in self.fmus:
            fmu.terminate()
            fmu.freeInstance()


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=20, help="interleaved rounds (default 20)")
    parser.add_argument("--quick", action="store_true", help="3 rounds, results not written")
    args = parser.parse_args(argv)
    rounds = 3 if args.quick else args.rounds
    from fmpy import extract

    with tempfile.TemporaryDirectory(prefix="bench_contacts_") as tmp:
        empty, contact2d = common.build_and_extract(Path(tmp), build)
        unzipped = {n: extract(str(build_variant(Path(tmp, f"n{n}"), n)), unzipdir=str(Path(tmp, f"u{n}")))
                    for n in COUNTS}
        unzipped2d = {n: extract(str(build_variant(Path(tmp, f"m{n}"), n, model="RollingContact2D")),
                                 unzipdir=str(Path(tmp, f"v{n}"))) for n in COUNTS}
        cases = {("empty FMU", 0): Instances("empty", empty, 1, {}, 100, 0.0)}
        for label, parameters, steps, spin in (("3D linear", {"method": 1}, 100, 0.0),
                                               ("3D strips, no spin", {"method": 3}, 50, 0.0),
                                               ("3D strips, spin", {"method": 3}, 10, 0.3)):
            for n in COUNTS:
                curvatures = {f"{name}[{k}]" if n > 1 else name: value for k in range(1, n + 1)
                              for name, value in (("curvature_longitudinal", 1.087 + 0.1 * k),
                                                  ("curvature_lateral", 1.667))}
                cases[label, n] = Instances(f"{label} {n}", unzipped[n], 1, {**parameters, **curvatures}, steps,
                                            spin)
        for n in COUNTS:
            cases["empty FMU with the variables of n 2D contacts", n] = Instances(
                f"empty {n}", build_empty(Path(tmp), n), 1, {}, 100, 0.0)
        for n in COUNTS:
            cases["2D closed form", n] = Instances(f"2D {n}", unzipped2d[n], 1, {"method": 1}, 100, 0.0)
        table = {"friction_law": 1, "friction_kinetic_ratio": 0.4, "friction_decay": 0.6, "tolerance": 1e-3,
                 "table": 2}
        for n in COUNTS:
            cases["2D table, falling friction", n] = Instances(f"2D table {n}", unzipped2d[n], 1, table, 100, 0.0)
        for n in COUNTS:
            cases["2D closed form, n instances", n] = Instances(f"2D x{n}", contact2d, n, {"method": 1}, 100, 0.0)
        for case in cases.values():
            case.batch()
            case.times.clear()
        for _ in range(rounds):
            for case in cases.values():
                case.batch()
        median = {key: statistics.median(case.times) for key, case in cases.items()}
        floor = median["empty FMU", 0]
        print(f"fmpy {__import__('fmpy').__version__}, pythonfmu {__import__('pythonfmu').__version__}, Python "
              f"{sys.version.split()[0]}, {rounds} rounds; one step = set every input + doStep + get every output "
              f"(of every instance); medians in us per step; the empty FMU: {floor:.1f} us\n")
        print("| case | contacts | us per step | above the empty FMU | per contact above empty | "
              "ratio to 1 contact | discarded |")
        print("|---|---:|---:|---:|---:|---:|---:|")
        for (label, n), case in cases.items():
            if n == 0:
                continue
            ratio = median[label, n] / median[label, 1]
            print(f"| {label} | {n} | {median[label, n]:.1f} | {median[label, n] - floor:.1f} | "
                  f"{(median[label, n] - floor) / n:.1f} | {ratio:.2f} | {case.discards} |")
        for case in cases.values():
            case.free()


if __name__ == "__main__":
    common.run_and_publish(main, "contacts.md")
