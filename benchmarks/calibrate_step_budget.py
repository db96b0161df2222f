"""The work of one step under a budget: the discretised transient's substep cost model, and the worst steps with
and without the FMU's default ``step_budget``.

Run: ``python benchmarks/calibrate_step_budget.py [--quick]`` (about 1 minute; ``--quick`` a few seconds).  Writes
``benchmarks/results/step_budget.md`` and prints it.

A. Time of one whole-element substep of the discretised transient on n elements (median over steps that roll 60
   elements at a slowly varying creep), the least-squares fit ``a + b n^2`` and the constants the stepping model
   uses (:data:`rollcontact.stepping.line.transient.SUBSTEP_COST`).
B. Steps that take long without a budget, each timed over a few steps of varying inputs (median wall time per step)
   with ``step_budget`` = 0 (no budget) and the default, the budget's modelled cost, and what the budget costs in
   accuracy (the force difference against the unbudgeted step, in mu N):

   * the discretised transient (``transient`` = 2, ``method`` = 3) at V = 20 m/s with host steps of 15 ms
     (0.3 m rolled per step), with the default grid and with ``elements`` = 400;
   * ``rollcontact.solve(scene, tolerance=1e-3)`` on a split corrugation that only the discretised method treats
     (methods restricted to it), with and without ``budget`` = the default.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time

import common
import numpy as np

import rollcontact as rc
from rollcontact.line.instationary import InstationaryModel, aligned_grid_load
from rollcontact.stepping import ContactModel, ContactParameters
from rollcontact.stepping.line.transient import SUBSTEP_COST
from rollcontact.stepping.parameters import DEFAULT_STEP_BUDGET

R, MU, LOAD = 0.46, 0.3, 1e6
ESTAR = rc.Material().contact_modulus


def substep_time(elements: int, steps: int) -> float:
    """Median time [s] of one whole-element substep on ``elements`` elements."""
    model = InstationaryModel(R, ESTAR, MU, mode="transient", elements=elements)
    model.build_solver(aligned_grid_load(LOAD, elements, 2.0))
    state = model.steady_state(LOAD, 5e-4)
    h = model.solver.grid.element_width
    times = []
    for k in range(steps):
        creep = 5e-4 + 2e-4 * math.sin(0.7 * k)
        start = time.perf_counter()
        state, result = model.step(state, LOAD, creep, 10.0, 60 * h / 10.0)
        times.append((time.perf_counter() - start) / result.info["substeps"])
    return statistics.median(times)


def table_a(quick: bool) -> list[str]:
    sizes = (50, 100, 200, 400) if quick else (50, 100, 200, 400, 800)
    measured = [(n, substep_time(n, 3 if quick else 7)) for n in sizes]
    n = np.array([m[0] for m in measured], dtype=float)
    t = np.array([m[1] for m in measured])
    fit = np.linalg.lstsq(np.column_stack((np.ones_like(n), n * n)) / t[:, None], np.ones_like(t), rcond=None)[0]
    a, b = SUBSTEP_COST
    lines = ["## A. One whole-element substep of the discretised transient", "",
             "| n | measured | model a + b n^2 | measured / model |", "|---|---|---|---|"]
    lines += [f"| {k} | {1e6 * s:.0f} us | {1e6 * (a + b * k * k):.0f} us | {s / (a + b * k * k):.2f} |"
              for k, s in measured]
    lines += ["", f"Least squares (relative): a = {fit[0]:.3g} s, b = {fit[1]:.3g} s; the model: a = {a:.3g} s, "
              f"b = {b:.3g} s.", ""]
    return lines


def fmu_steps(parameters: dict, steps: int) -> tuple[float, list[float], ContactModel]:
    """Median wall time [s] per step and the forces of ``steps`` host steps of 15 ms at V = 20 m/s."""
    model = ContactModel(ContactParameters(**parameters))
    times, forces = [], []
    for k in range(steps):
        creep = 1e-3 + 3e-4 * math.sin(0.9 * k)
        start = time.perf_counter()
        out = model.step(k * 0.015, 0.015, 2e4, creep, 20.0)
        times.append(time.perf_counter() - start)
        forces.append(out.tangential_force)
    return statistics.median(times), forces, model


def table_b(quick: bool) -> list[str]:
    steps = 3 if quick else 8
    lines = ["## B. Long steps with and without the default budget", "",
             f"Default `step_budget` = {DEFAULT_STEP_BUDGET} s.", "",
             "| case | no budget | default budget | modelled cost | force change (mu N) | said once |",
             "|---|---|---|---|---|---|"]
    for name, parameters in (("transient, default grid, h = 15 ms, V = 20 m/s", {"transient": 2, "method": 3}),
                             ("transient, 400 elements, h = 15 ms, V = 20 m/s",
                              {"transient": 2, "method": 3, "elements": 400})):
        free, exact, _ = fmu_steps({**parameters, "step_budget": 0.0}, steps)
        bounded, forces, model = fmu_steps(parameters, steps)
        change = max(abs(f - e) for f, e in zip(forces, exact, strict=True)) / (MU * 2e4)
        a, b = SUBSTEP_COST
        n = model.instationary.elements
        modelled = (model.instationary.max_substeps + 2) * (a + b * n * n)
        lines.append(f"| {name} | {1e3 * free:.1f} ms | {1e3 * bounded:.1f} ms | {1e3 * modelled:.1f} ms | "
                     f"{change:.2g} | {'yes' if model.take_messages() else 'no'} |")
    scene = rc.Scene(1e6, creep=2e-4, axis_position=7e-4,
                     surface=rc.Surface(harmonics=(rc.Harmonic.from_wavelength(0.004, 40e-6),)))
    timed = {}
    for budget in (None, DEFAULT_STEP_BUDGET):
        start = time.perf_counter()
        result = rc.solve(scene, methods=["discretised"], tolerance=1e-3, budget=budget)
        timed[budget] = (time.perf_counter() - start, result)
    (free, exact), (bounded, result) = timed[None], timed[DEFAULT_STEP_BUDGET]
    change = abs(result.tangential_force_per_length - exact.tangential_force_per_length) / (
        MU * scene.normal_load_per_length)
    lines.append(f"| solve, split corrugation 4 mm / 40 um, tolerance 1e-3, discretised only | {1e3 * free:.0f} ms "
                 f"({exact.info['setting']}) | {1e3 * bounded:.1f} ms ({result.info['setting']}) | "
                 f"{1e3 * result.info['predicted_cost']:.1f} ms | {change:.2g} | message: tolerance "
                 f"{'met' if result.info['tolerance_met'] else 'not met'} |")
    return lines + [""]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer sizes and steps (a few seconds)")
    args = parser.parse_args()
    start = time.perf_counter()
    lines = ["# Work of one step under a budget", "", *common.machine(os.getloadavg()[0]), ""]
    lines += table_a(args.quick) + table_b(args.quick)
    lines.append(f"Run time {time.perf_counter() - start:.0f} s{' (--quick)' if args.quick else ''}.")
    common.publish(lines, "step_budget.md", args.quick)


if __name__ == "__main__":
    main()
