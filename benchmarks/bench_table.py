"""Real-time steps through the certified table: FMU steps through fmpy on varying signals against the empty step.

Run: ``python benchmarks/bench_table.py [--quick]`` (a few minutes; ``--quick`` about a minute).  Writes
``benchmarks/results/table.md`` and prints it.

Every case drives the contact FMU through fmpy with a new load and creep at every step (so no cache of a repeated
scene is hit), timed in interleaved batches with an empty pythonfmu FMU (the floor of any pythonfmu step), and
reports the median microseconds per step (set the inputs, doStep, get the outputs) and their ratio to the empty step.
Error: the largest |T - T_ref| / (mu N) over sampled steps, the reference the library's exact solve of that step's
scene at tolerance 1e-5 (falling friction) or the closed form (Carter).  The table's build time (its first loaded
step with ``table`` = on), its exact solves, its size and its certified bound come from the stepping model in this
process.

Families, each with the table on and off (the exact path at tolerance 1e-3): falling friction on a flat rail (the
exponential law at three laws and speeds, among them ``mu_s 0.3, A 0.6, B ln2/0.1 s/m, V 45 m/s, N' 3.1e6 N/m,
creep 2e-4..1.8e-3``); Coulomb friction on a corrugation of one harmonic at three wavelengths and amplitudes (among
them ``40 mm / 20 um, V 30 m/s, N' 1e6 N/m, creep 1.1e-3..2.1e-3``); the Carter case as control.  The reference of
the error is the library's exact solve of the step's scene at tolerance 1e-6.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import common

import rollcontact as rc
from rollcontact.stepping import ContactModel, ContactParameters
from rollcontact.stepping.line import falling_table
from rollcontact.stepping.line.falling_table import FallingFrictionTable
from rollcontact.stepping.threads import one_blas_thread

WIDTH = common.CONTACT_WIDTH
LAWS = (  # (label, kinetic ratio A, decay B [s/m], speed V [m/s], load per length N' [N/m], creep range)
    ("A 0.6, B ln2/0.1, V 45", 0.6, math.log(2.0) / 0.1, 45.0, 3.1e6, (2e-4, 1.8e-3)),
    ("A 0.4, B 0.6, V 20", 0.4, 0.6, 20.0, 1e6, (1e-4, 3e-3)),
    ("A 0.5, B 3, V 10", 0.5, 3.0, 10.0, 2e6, (1e-4, 4e-3)),
)
CORRUGATIONS = (  # (label, wavelength [m], amplitude [m], speed V [m/s], load per length N' [N/m], creep range)
    ("40 mm / 20 um, V 30", 0.04, 20e-6, 30.0, 1e6, (1.1e-3, 2.1e-3)),
    ("60 mm / 40 um, V 50", 0.06, 40e-6, 50.0, 1.5e6, (2e-4, 2.5e-3)),
    ("25 mm / 5 um, V 20", 0.025, 5e-6, 20.0, 8e5, (1e-4, 1.5e-3)),
)


def signal(load_per_length: float, creeps: tuple[float, float]):
    """``n -> (N [N], creep)``: a new load (+-5 %) and creep over the range at every step."""
    low, high = creeps

    def inputs(n: int) -> tuple[float, float]:
        return (load_per_length * WIDTH * (1.0 + 0.05 * math.sin(0.37 * n)),
                low + (high - low) * (0.5 + 0.5 * math.sin(0.61 * n + 0.3 * math.sin(0.07 * n))))
    return inputs


def reference_error(parameters: dict, inputs, speed: float, samples: int) -> float:
    """Largest |T - T_ref| / (mu N) of the model with ``parameters`` against the exact solve at 1e-5."""
    model = ContactModel(ContactParameters(**parameters))
    worst = 0.0
    for n in range(samples):
        load, creep = inputs(n)
        out = model.step(n * 1e-3, 1e-3, load, creep, speed)
        scene = model.scene(out.axis_position, load, creep, speed)
        exact = rc.solve(scene, method="polynomial", tolerance=1e-6)
        limit = model.mu * load
        worst = max(worst, abs(out.tangential_force - exact.tangential_force_per_length * WIDTH) / limit)
    return worst


def table_build(parameters: dict, inputs, speed: float) -> tuple[float, int, int, float, str]:
    """Seconds of the first loaded step with the table on, its exact solves, its size [bytes], its bound, its
    domain."""
    model = ContactModel(ContactParameters(**parameters, table=2))
    load, creep = inputs(0)
    start = time.perf_counter()
    model.step(0.0, 1e-3, load, creep, speed)
    table = model.table_use.table
    domain = ", ".join(f"{v:.3g}" for v in table.domain)
    return time.perf_counter() - start, table.solves, table.nbytes, table.bound, domain


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one law and one corrugation, fewer rounds and samples")
    args = parser.parse_args()
    laws = LAWS[:1] if args.quick else LAWS
    corrugations = CORRUGATIONS[:1] if args.quick else CORRUGATIONS
    rounds, steps, samples = (5, 200, 20) if args.quick else (15, 400, 60)
    lines = ["# Real-time steps through the certified table", "", *common.machine(0.0), ""]
    builds = []
    with tempfile.TemporaryDirectory(prefix="bench_table_") as tmp:
        from functools import partial

        from build_fmu import build

        empty, contact = common.build_and_extract(Path(tmp), partial(build, "RollingContact2D"))
        carter = signal(1e6, (1e-4, 2e-3))
        cases = [common.Case("empty", empty, {}, steps, 20.0, signal=carter)]  # the same per-step work of the host
        cases.append(common.Case("Carter (closed form)", contact, {}, steps, 20.0, signal=carter))
        errors = {"Carter (closed form)": reference_error({}, carter, 20.0, samples)}
        for label, ratio, decay, speed, load, creeps in laws:
            label = f"falling friction {label}"
            law = {"friction_law": 1, "friction_kinetic_ratio": ratio, "friction_decay": decay, "tolerance": 1e-3}
            inputs = signal(load, creeps)
            builds.append((label, *table_build(law, inputs, speed)))
            for mode, name in ((2, "table"), (1, "exact, tolerance 1e-3")):
                case = f"{label}: {name}"
                cases.append(common.Case(case, contact, {**law, "table": mode}, steps, speed, signal=inputs))
                errors[case] = reference_error({**law, "table": mode}, inputs, speed, samples)
        for label, wavelength, amplitude, speed, load, creeps in corrugations:
            scene = {"corrugation_wavelength": wavelength, "corrugation_amplitude": amplitude, "tolerance": 1e-3}
            inputs = signal(load, creeps)
            builds.append((f"corrugation {label}", *table_build(scene, inputs, speed)))
            for mode, name in ((2, "table"), (1, "exact, tolerance 1e-3")):
                case = f"corrugation {label}: {name}"
                cases.append(common.Case(case, contact, {**scene, "table": mode}, steps, speed, signal=inputs))
                errors[case] = reference_error({**scene, "table": mode}, inputs, speed, samples)
        common.run_interleaved(cases, rounds)
        floor = statistics.median(cases[0].times)
        lines += ["| case | us per step | over the empty step | error (mu N) | method_used |", "|---|---|---|---|---|"]
        for case in cases:
            median = statistics.median(case.times)
            error = errors.get(case.label)
            lines.append(f"| {case.label} | {median:.1f} | {median / floor:.2f} | "
                         f"{'' if error is None else f'{error:.2g}'} | {sorted(case.methods_used)} |")
        for case in cases:
            case.free()
    lines += ["", "## Builds", "",
              "Built at the first loaded step (``table`` = on) over the domain that step implies (w_max of falling "
              "friction; N_low, N_high [N/m] of a corrugation). Seconds over solves is what ``SOLVE_COST`` of each "
              "family models (2e-3 s falling friction, 1.2e-4 s corrugation).", "",
              "| scene | domain | build (s) | exact solves | s per solve | size (bytes) | certified bound (mu N) |",
              "|---|---|---|---|---|---|---|"]
    lines += [f"| {label} | {domain} | {seconds:.2f} | {solves} | {seconds / solves:.2g} | {size} | {bound:.2g} |"
              for label, seconds, solves, size, bound, domain in builds]
    lines += largest_domains(args.quick) + blas_threads()
    common.publish(lines, "table.md", args.quick)


def largest_domains(quick: bool) -> list[str]:
    """Falling-friction builds over the largest domain of each kinetic ratio (``w_limit(A)``), with one BLAS thread as
    the model builds: solves, seconds, the slowest solve, the bound or why the build was given up."""
    ratios = (0.05, 0.3, 0.6, 0.9) if quick else (0.01, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95)
    lines = ["", "## Largest domains", "",
             "Falling friction (exponential law): a table over the largest domain of each kinetic ratio A, "
             "``w_max = w_limit(A) = min(5, 0.8 / (1 - A))``, built as a model builds it (one BLAS thread). The "
             "work of any build is at most ``max_solves`` solves, each bounded by ``NODE_NODES`` and "
             "``NODE_ITERATIONS``.", "",
             "| A | w_max | exact solves | build (s) | slowest solve (s) | certified bound (mu N) |",
             "|---|---|---|---|---|---|"]
    for ratio in ratios:
        table = FallingFrictionTable(ratio, falling_table.w_limit(ratio))
        exact, slowest = table.exact, [0.0]

        def timed(*coordinates, exact=exact, slowest=slowest):
            start = time.perf_counter()
            value = exact(*coordinates)
            slowest[0] = max(slowest[0], time.perf_counter() - start)
            return value

        table.exact = timed
        start = time.perf_counter()
        try:
            with one_blas_thread():
                table.build()
            outcome = f"{table.bound:.2g}"
        except ArithmeticError as exc:
            outcome = f"given up: {exc}"
        lines.append(f"| {ratio} | {table.w_max:.3g} | {table.solves} | {time.perf_counter() - start:.2f} | "
                     f"{slowest[0]:.3f} | {outcome} |")
    return lines


THREADS_SCRIPT = """
import time
from rollcontact.stepping.line.falling_table import FallingFrictionTable, w_limit
from rollcontact.stepping.threads import one_blas_thread
for limited in (False, True, False, True):
    table = FallingFrictionTable(0.6, w_limit(0.6))
    start = time.perf_counter()
    if limited:
        with one_blas_thread():
            table.build()
    else:
        table.build()
    print(limited, time.perf_counter() - start)
"""


def blas_threads() -> list[str]:
    """One falling-friction build (A 0.6 at its largest domain) in a fresh process with the BLAS's default threads
    (no ``OPENBLAS_NUM_THREADS``), without and with the model's one-thread limit, alternated twice."""
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")}
    env["PYTHONPATH"] = str(common.ROOT / "src")
    out = subprocess.run([sys.executable, "-c", THREADS_SCRIPT], env=env, capture_output=True, text=True,
                         check=True).stdout.split()
    times = {"True": [], "False": []}
    for flag, seconds in zip(out[::2], out[1::2], strict=True):
        times[flag].append(float(seconds))
    free, limited = statistics.median(times["False"]), statistics.median(times["True"])
    return ["", "## BLAS threads", "",
            f"One build (A 0.6 at w_limit, {os.cpu_count()} cores) in a process with the BLAS's default threads: "
            "as it is, and with the one-thread limit the model takes (``rollcontact.stepping.threads``); medians "
            "of two each, alternated.", "",
            "| BLAS threads | build (s) |", "|---|---|",
            f"| default | {free:.2f} |", f"| one (the model's limit) | {limited:.2f} |",
            f"| ratio default / one | {free / limited:.2f} |"]


if __name__ == "__main__":
    main()
