"""How the discretised transient splits a host step: whole-element substeps against equal substeps (the pair's error).

Run as ``.venv/bin/python benchmarks/bench_substep_rule.py [--signals 0,1,2]`` (about 4 minutes for all three
signals, one BLAS thread; ``--signals`` picks some of :data:`SIGNALS`).  Prints a markdown table; asserts nothing.

Question.  Two rules split a host step rolling ``ds``.  Equal substeps: ``k = ceil(ds/h)`` substeps of ``d = ds/k``,
a fraction ``r = d/h`` of the coarse element; with them the extrapolating pair's ``error n^2`` is erratic in n,
largest where r is far from 1 (``benchmarks/results/substep_rule.md``: at lambda/a = 2, 4.4 at n = 440, r = 0.97;
26.2 at n = 460, r = 0.68), and the pair's quasi-steady bias varies with r.  Whole elements, the model's rule:
substeps of exactly one element, the rest of the roll carried to the next host step
(:meth:`rollcontact.line.instationary.InstationaryModel.advance`; the output is a provisional substep of that pending
roll).  This benchmark measures both rules on the same grids.

Method.  The Pareto study's instationary scenario (``instationary_case.creep_signal``: N' = 1e7 N/m, mu = 0.3,
V = 10 m/s, 64 host steps per cycle of ``xi = (0.5 + 0.3 sin) mu a/R``) at lambda/a = 1, 2, 5 (host steps of
0.016-0.08 a, up to several coarse elements), from no traction, the last cycle measured.  Grids: the model's for the
pair (:func:`rollcontact.line.instationary.aligned_grid_load` with ``multiple`` = 2).  Whole-element commits: the
library's :class:`rollcontact.line.instationary.InstationaryModel` with ``extrapolate=True``.  Equal substeps: the same
solvers stepped ``ceil(ds/h_c)`` (coarse) and twice that (fine) equal substeps per host step
(:func:`equal_substeps`).  Reference: the library's pair at :data:`REFERENCE` elements; the same pair with equal
substeps is printed against it (both rules converge to the same solution of the host's zero-order-hold creep).
Error: max |T' - T'_ref| over the measured cycle [mu N'], shown as ``error n^2``.

What it prints goes to ``benchmarks/results/substep_rule.md`` with the machine (not after ``--quick``).
"""

from __future__ import annotations

import argparse
import math
import time

import common  # noqa: F401  (before numpy: limits BLAS to one thread)
import numpy as np
from instationary_case import ESTAR, LIMIT, LOAD_I, MU_I, R_I, SPEED, creep_signal

from rollcontact.line.instationary import InstationaryModel, aligned_grid_load
from rollcontact.stepping.line.transient import GRID_LOAD_FACTOR

# (lambda/a, the pairs' n): n where the equal substeps' ratio r is far from 1 and, for contrast, near it
SIGNALS = ((1.0, (64, 128, 156, 300, 460)), (2.0, (100, 156, 300, 440, 460)), (5.0, (64, 100, 200, 300, 460)))
REFERENCE = 600


def pair(elements: int) -> InstationaryModel:
    """The extrapolating pair n/2, n on the model's grid for N' = 1e7 N/m."""
    return InstationaryModel(R_I, ESTAR, MU_I, mode="transient", elements=elements, extrapolate=True,
                             max_normal_load_per_length=aligned_grid_load(LOAD_I, elements, GRID_LOAD_FACTOR, 2))


def whole_elements(model: InstationaryModel, xi: np.ndarray, dt: float, first: int) -> np.ndarray:
    """T' [N/m] of the library's pair (whole-element substeps) over the steps from ``first``."""
    state, out = model.initial_state(), []
    for k, value in enumerate(xi):
        state, result = model.step(state, LOAD_I, value, SPEED, dt)
        if k >= first:
            out.append(result.tangential_force_per_length)
    return np.array(out)


def equal_substeps(model: InstationaryModel, xi: np.ndarray, dt: float, first: int) -> np.ndarray:
    """T' [N/m] of the same solvers with equal substeps: ``k = ceil(ds/h_c)`` equal substeps on the coarse grid and
    2k on the fine one per host step, ``2 T'_n - T'_(n/2)``."""
    ds = SPEED * dt
    count = math.ceil(ds / model.coarse_solver.grid.element_width * (1.0 - 1e-12))
    solvers = {model.solver: 2 * count, model.coarse_solver: count}
    states = {solver: solver.initial_state() for solver in solvers}
    out = []
    for k, value in enumerate(xi):
        for solver, substeps in solvers.items():
            p = model.pressure(LOAD_I, solver)
            for _ in range(substeps):
                states[solver], _ = solver.step(states[solver], p, ds / substeps, creep=value)
        if k >= first:
            out.append(2.0 * states[model.solver].tangential_force_per_length
                       - states[model.coarse_solver].tangential_force_per_length)
    return np.array(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--signals", default="0,1,2", help="indices into SIGNALS, comma-separated")
    args = parser.parse_args()
    start = time.perf_counter()
    print("| lambda/a | n | ds / h_c | r (equal substeps) | equal substeps: error n^2 | whole elements: error n^2 |")
    print("|---|---|---|---|---|---|")
    for wavelength, pairs in (SIGNALS[int(i)] for i in args.signals.split(",")):
        xi, dt, first = creep_signal(wavelength, 0.5, 0.3)
        reference = pair(REFERENCE)
        ref = whole_elements(reference, xi, dt, first)
        other = float(np.abs(equal_substeps(reference, xi, dt, first) - ref).max() / LIMIT)
        print(f"| {wavelength:g} | {REFERENCE} (reference) | | | {other * REFERENCE**2:.2f} | 0 |", flush=True)
        for n in pairs:
            model = pair(n)
            ratio = SPEED * dt / model.coarse_solver.grid.element_width
            r = ratio / math.ceil(ratio * (1.0 - 1e-12))
            errors = (float(np.abs(run(model, xi, dt, first) - ref).max() / LIMIT) * n * n
                      for run in (equal_substeps, whole_elements))
            print(f"| {wavelength:g} | {n} | {ratio:.3f} | {r:.2f} | {next(errors):.2f} | {next(errors):.2f} |",
                  flush=True)
    print(f"\n{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    common.run_and_publish(main, "substep_rule.md")
