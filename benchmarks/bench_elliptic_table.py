"""The certified table of the elliptic strips (``rollcontact.stepping.elliptic.table``): its build, its certificate, an
audit of its answers, and the RollingContact3D FMU step it makes, in one run.

* **Build**: the default table at nu = 0.28 (Coulomb friction, every a/b of Kalker's table, every creepage), built
  twice: wall seconds, strips solves, their modelled cost (``SOLVE_COST`` each) and the second build against the
  first, bit for bit.  In the same run, one strips solve with spin through ``solve_elliptic`` (``STRIPS_COST`` +
  ``STRIPS_COST_PER_CELL`` x steps modelled): the build's seconds per solve over it calibrate ``SOLVE_COST`` on the
  strips' own scale of modelled seconds.
* **Certificate**: the bound and the largest differences at the cells' centres, with spin and without.
* **Audit**: the table's answers against the strips at points it was not built on: points uniform in the table's
  coordinates (rho, q, sigma, alpha, the cells' centres excluded), and scenes of random a/b 0.1..10, load, size,
  modulus, friction coefficient and creepages of either sign up to a few saturation values, with spin and without;
  the largest error against the bound.
* **FMU step**: microseconds per fmpy step (set every input, ``doStep``, get every output; ``FMU2Slave``) of
  RollingContact3D with one contact on a varying signal (load 80 kN +-10 %, the three creepages swinging through
  saturation, spin included): ``table`` = on with Coulomb friction (``jacobian`` linear and difference), the exact
  strips (``method`` = auto) and the linear level for comparison, and RollingContact3D_8 on the table; against two
  empty FMUs with the single contact's variables (7 inputs, 17 real and one integer output, ``do_step`` returns
  True): pythonfmu's own getters and setters, and one list operation per call.  Batches interleaved, medians, ratios
  in the same run.

Usage: ``python benchmarks/bench_elliptic_table.py [--quick]`` (``--quick``: a small table, a short audit and few
rounds, nothing written); writes ``benchmarks/results/elliptic_table.md``.  Slow: two builds of the default table.
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
import numpy as np

from build_fmu import build
from rollcontact import EllipticScene, Material, solve_elliptic
from rollcontact.core.friction import Coulomb
from rollcontact.elliptic.creep_coefficients import creepage_coefficients
from rollcontact.elliptic.methods import strips
from rollcontact.elliptic.methods.strips import solve_strips
from rollcontact.stepping.elliptic import table as table_module
from rollcontact.stepping.elliptic.table import EllipticTable

EMPTY = '''
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real


class {name}(Fmi2Slave):
    """Empty pythonfmu slave with the variables of RollingContact3D ({how})."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        for name in ("normal_load", "longitudinal_creep", "lateral_creep", "spin", "velocity",
                     "gap_curvature_longitudinal", "gap_curvature_lateral"):
            setattr(self, name, 0.0)
            self.register_variable(Real(name, causality=Fmi2Causality.input, variability=Fmi2Variability.continuous))
        for i in range(17):
            setattr(self, f"y{{i}}", 0.0)
            self.register_variable(Real(f"y{{i}}", causality=Fmi2Causality.output,
                                        variability=Fmi2Variability.continuous))
        self.method_used = 0
        self.register_variable(Integer("method_used", causality=Fmi2Causality.output,
                                       variability=Fmi2Variability.discrete))
        self.reals = [0.0] * 17
{bulk}
    def do_step(self, current_time, step_size):
        return True
'''
BULK = '''
    def set_real(self, vrs, values):
        self.inputs = list(values)

    def get_real(self, vrs):
        return self.reals[:len(vrs)]

    def get_integer(self, vrs):
        return [0] * len(vrs)
'''


def build_empty(tmp: Path, bulk: bool) -> str:
    """An empty FMU with RollingContact3D's variables (``bulk``: every get and set one list operation), unzipped."""
    from fmpy import extract
    from pythonfmu.builder import FmuBuilder

    name = "EmptyContact3DBulk" if bulk else "EmptyContact3D"
    folder = tmp / name
    folder.mkdir()
    script = folder / f"rollcontact_bench_{name.lower()}.py"
    script.write_text(EMPTY.format(name=name, how="one list operation per call" if bulk else "pythonfmu's getters "
                                   "and setters", bulk=BULK if bulk else ""))
    return extract(str(FmuBuilder.build_FMU(script, dest=folder)), unzipdir=str(folder / "u"))


class Stepped:
    """An initialised FMU instance (FMI 2.0, fmpy's ``FMU2Slave``) of n contacts stepped in timed batches on the
    varying signal :meth:`inputs` (contact k its own phase)."""

    def __init__(self, label: str, unzipped: str, parameters: dict, steps: int, contacts: int = 1):
        from fmpy import read_model_description
        from fmpy.fmi2 import FMU2Slave

        self.label, self.steps, self.contacts = label, steps, contacts
        md = read_model_description(unzipped)
        variables = {v.name: v for v in md.modelVariables}
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped,
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=label)
        self.fmu.instantiate()
        for name, value in parameters.items():
            v = variables[name]
            (self.fmu.setReal if v.type == "Real" else self.fmu.setInteger)([v.valueReference], [value])
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        names = ("normal_load", "longitudinal_creep", "lateral_creep", "spin", "velocity")
        self.inputs = [variables[n if contacts == 1 else f"{n}[{k}]"].valueReference
                       for k in range(1, contacts + 1) for n in names]
        self.reals = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
        self.integers = [v.valueReference for v in md.modelVariables
                         if v.causality == "output" and v.type in ("Integer", "Enumeration")]
        self.n = 0
        self.times: list[float] = []
        self.used: set[int] = set()

    def inputs_at(self, n: int) -> list[float]:
        values = []
        for k in range(self.contacts):
            phase = 0.01 * n + 0.7 * k
            values += [8e4 * (1.0 + 0.1 * math.sin(phase)), 3e-3 * math.sin(1.3 * phase),
                       -2e-3 * math.cos(0.9 * phase), 0.4 * math.sin(0.7 * phase), 30.0]
        return values

    def batch(self) -> None:
        h = 1e-3
        fmu, inputs, reals, integers = self.fmu, self.inputs, self.reals, self.integers
        signal = [self.inputs_at(n) for n in range(self.n, self.n + self.steps)]
        used = []
        start = time.perf_counter()
        for n, values in enumerate(signal, start=self.n):
            fmu.setReal(inputs, values)
            fmu.doStep(n * h, h)
            fmu.getReal(reals)
            used.append(fmu.getInteger(integers)[0])
        self.times.append((time.perf_counter() - start) / self.steps * 1e6)
        self.used.update(used)
        self.n += self.steps

    def free(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()


def normalised(scene: EllipticScene) -> tuple[tuple, tuple]:
    """The strips' normalised forces of the scene and its table query ``(rho, u_x, u_y, u_s)``."""
    h = scene.hertz
    c = creepage_coefficients(h.aspect_ratio, scene.material.poisson_ratio)
    limit = scene.friction_coefficient * scene.normal_load
    k = scene.shear_modulus * h.c * h.c / limit
    r = solve_strips(scene)
    return (r.longitudinal_force / limit, r.lateral_force / limit, r.spin_moment / (limit * h.c)), (
        math.log(h.aspect_ratio), k * c.c11 * scene.longitudinal_creepage, k * c.c22 * scene.lateral_creepage,
        k * (c.c23 * h.c + 0.5 * c.c11 * h.b) * scene.spin_creepage)


def random_scene(rng, spin: bool) -> EllipticScene:
    """A scene of random a/b 0.1..10, load, size, modulus, friction coefficient and creepages (module docstring)."""
    load, mu, modulus = rng.uniform(1e3, 3e5), rng.uniform(0.05, 0.8), rng.uniform(5e10, 3e11)
    while True:
        A = rng.uniform(0.2, 5.0)
        scene = EllipticScene(load, A, A * math.exp(rng.uniform(-3.0, 3.0)), material=Material(modulus, 0.28),
                              friction=Coulomb(mu))
        if 0.1 <= scene.hertz.aspect_ratio <= 10.0:
            break
    saturation = mu * load / (scene.shear_modulus * scene.hertz.c**2 * 4.0)
    return scene.replace(longitudinal_creepage=rng.normal(0.0, 2.0 * saturation),
                         lateral_creepage=rng.normal(0.0, 2.0 * saturation),
                         spin_creepage=rng.normal(0.0, 3.0 * saturation / scene.hertz.c) if spin else 0.0)


def audit(table: EllipticTable, points: int) -> list[str]:
    """The audit's table rows (module docstring)."""
    rng = np.random.default_rng(2024)
    rows = []
    groups = {"uniform in the coordinates, spin": [], "uniform in the coordinates, no spin": [],
              "random scenes, spin": [], "random scenes, no spin": []}
    centres = {name: set(axis.centres.tolist()) for name, axis in (("q", table.q), ("alpha", table.alpha))}
    for n in range(points):
        spin = n % 4 != 0
        rho = rng.uniform(table.rho.lo, table.rho.hi)
        q, alpha = rng.uniform(0.0, 1.0), rng.uniform(0.0, 0.5 * math.pi)
        if q in centres["q"] or alpha in centres["alpha"]:
            continue
        sigma = rng.uniform(-1.0, 1.0) if spin else 0.0
        creepages = table.creepages(q, sigma, alpha, no_spin=not spin)
        forces = _finished(table.solve([creepages], table.base_at(rho)))[0]
        answer = table.answer(rho, *creepages, False)
        groups[f"uniform in the coordinates, {'spin' if spin else 'no spin'}"].append(
            max(abs(a - b) for a, b in zip(answer[:3], forces, strict=True)))
        forces, query = normalised(random_scene(rng, spin))
        answer = table.answer(*query, False)
        groups[f"random scenes, {'spin' if spin else 'no spin'}"].append(
            max(abs(a - b) for a, b in zip(answer[:3], forces, strict=True)))
    rows.append("| points | n | largest error [mu Fn] | 99th percentile | median | largest / bound |")
    rows.append("|---|---:|---:|---:|---:|---:|")
    for name, errors in groups.items():
        e = np.array(errors)
        rows.append(f"| {name} | {e.size} | {e.max():.4f} | {np.percentile(e, 99):.4f} | {np.median(e):.4f} | "
                    f"{e.max() / table.bound:.2f} |")
    worst = max(max(e) for e in groups.values())
    rows.append(f"\nLargest error of the audit {worst:.4f} mu Fn, the certified bound {table.bound:.4f}: "
                f"{'within' if worst <= table.bound else 'BEYOND'} the bound.")
    return rows


def _finished(generator):
    """The return value of a build-step generator run to its end."""
    try:
        while True:
            next(generator)
    except StopIteration as stop:
        return stop.value


def build_section(nodes: tuple) -> tuple[EllipticTable, list[str]]:
    """Build the table twice; the build and certificate rows."""
    start = time.perf_counter()
    first = EllipticTable(0.28, nodes).build()
    seconds = time.perf_counter() - start
    start = time.perf_counter()
    second = EllipticTable(0.28, nodes).build()
    again = time.perf_counter() - start
    same = all(np.array_equal(first.tables[k].data, second.tables[k].data) for k in first.tables) and \
        first.bound == second.bound
    scene = EllipticScene(8e4, 1.087, 1.667, 1e-3, -5e-4, 0.3)
    single = common.median_time(lambda: solve_elliptic(scene, "strips"), min_repeats=20)
    modelled_single = strips.StripsAccuracy.calibrated(scene, {})  # with spin: the split and the march
    per_solve = min(seconds, again) / first.solves
    rows = ["## Build\n", f"Node counts (rho, q, sigma per half, alpha) {nodes}, nu = 0.28, Coulomb friction.\n",
            "| build | wall seconds | strips solves | modelled seconds (SOLVE_COST each) | us per solve |",
            "|---|---:|---:|---:|---:|",
            f"| first | {seconds:.1f} | {first.solves} | {first.solves * table_module.SOLVE_COST:.1f} | "
            f"{seconds / first.solves * 1e6:.1f} |",
            f"| second | {again:.1f} | {second.solves} | {second.solves * table_module.SOLVE_COST:.1f} | "
            f"{again / second.solves * 1e6:.1f} |",
            f"\nThe second build equals the first bit for bit: {'yes' if same else 'NO'}. Planned solves "
            f"{first.solves_planned()}, {len(first.batch_sizes())} batches of at most {table_module.CHUNK}; "
            f"{first.nbytes / 1e6:.1f} MB of interpolation data.",
            f"\nCalibration of SOLVE_COST: one strips solve with spin through solve_elliptic takes {single * 1e6:.0f} "
            f"us in this run, modelled at {modelled_single:.3g} s; a build's solve {per_solve * 1e6:.0f} us, "
            f"{per_solve / single:.3f} of it, that is {per_solve / single * modelled_single:.3g} s on the strips' "
            f"scale (SOLVE_COST = {table_module.SOLVE_COST:g} s).",
            "\n## Certificate\n",
            "| table | tau_x | tau_y | tau_z |", "|---|---:|---:|---:|",
            "| spin, largest difference at the cells' centres | " + " | ".join(
                f"{v:.4f}" for v in first.check_error[:3]) + " |",
            "| no spin, largest difference at the cells' centres | " + " | ".join(
                f"{v:.4f}" for v in first.check_error[3:]) + " |",
            f"\nCertified bound: {table_module.BOUND_FACTOR:g} x {max(first.check_error):.4f} = {first.bound:.4f} mu "
            f"Fn against the strips (target {table_module.TARGET:g}: "
            f"{'met' if first.bound <= table_module.TARGET else 'missed'}); without spin alone the differences "
            f"would certify {table_module.BOUND_FACTOR * max(first.check_error[3:]):.4f}."]
    return first, rows


def fmu_section(rounds: int, table: EllipticTable) -> list[str]:
    """The FMU step rows (module docstring)."""
    table_module.TABLES[(0.28, table.nodes)] = table  # the FMUs run in this process: their builds take it
    with tempfile.TemporaryDirectory(prefix="bench_elliptic_table_") as tmp:
        from fmpy import extract

        tmp = Path(tmp)
        one = extract(str(build("RollingContact3D", tmp / "one")), unzipdir=str(tmp / "u1"))
        eight = extract(str(build("RollingContact3D", tmp / "eight", contacts=8)), unzipdir=str(tmp / "u8"))
        cases = [Stepped("empty, pythonfmu's getters and setters", build_empty(tmp, False), {}, 200),
                 Stepped("empty, one list operation per call", build_empty(tmp, True), {}, 200),
                 Stepped("table, jacobian linear", one, {"table": 2}, 200),
                 Stepped("table, jacobian difference", one, {"table": 2, "jacobian": 1}, 200),
                 Stepped("linear level", one, {"method": 1}, 200),
                 Stepped("strips (auto), exact", one, {"table": 1}, 20),
                 Stepped("8 contacts, table", eight, {"table": 2, **{f"curvature_longitudinal[{k}]": 1.087 + 0.1 * k
                                                                     for k in range(1, 9)}}, 50, contacts=8)]
        for case in cases:
            case.batch()
            case.times.clear()
        for _ in range(rounds):
            for case in cases:
                case.batch()
        median = {case.label: statistics.median(case.times) for case in cases}
        empty = median["empty, pythonfmu's getters and setters"]
        bulk = median["empty, one list operation per call"]
        rows = ["\n## FMU step\n", f"{rounds} interleaved rounds, medians; fmpy "
                f"{__import__('fmpy').__version__}, pythonfmu {__import__('pythonfmu').__version__}.\n",
                "| case | us per step | over the empty step (getters) | over the empty step (one list operation) | "
                "method_used seen |", "|---|---:|---:|---:|---|"]
        for case in cases:
            rows.append(f"| {case.label} | {median[case.label]:.1f} | {median[case.label] / empty:.2f} | "
                        f"{median[case.label] / bulk:.2f} | {sorted(case.used)} |")
        for case in cases:
            case.free()
    ratio = median["table, jacobian linear"] / bulk
    rows.append(f"\nA table step (one contact, Coulomb friction, spin) costs {ratio:.2f} empty steps of one list "
                f"operation per call (the goal: at most 4), {median['table, jacobian linear'] / empty:.2f} of "
                f"pythonfmu's own getters and setters; the exact strips "
                f"{median['strips (auto), exact'] / median['table, jacobian linear']:.1f} times a table step.")
    return rows


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a small table, a short audit, 3 rounds")
    args = parser.parse_args(argv)
    nodes = (5, 9, 7, 5) if args.quick else table_module.NODES
    table, rows = build_section(nodes)
    print("# The certified table of the elliptic strips\n")
    print("\n".join(rows))
    print("\n## Audit\n")
    print("\n".join(audit(table, 200 if args.quick else 2000)))
    print("\n".join(fmu_section(3 if args.quick else 15, table)))


if __name__ == "__main__":
    sys.exit(common.run_and_publish(main, "elliptic_table.md"))
