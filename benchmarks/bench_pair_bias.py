"""Where the extrapolating transient pair's error comes from: its quasi-steady bias (a diagnosis, no model change).

Run as ``.venv/bin/python benchmarks/bench_pair_bias.py`` (about 5 minutes).  Prints markdown tables; asserts
nothing.  One BLAS thread.

Question.  ``benchmarks/bench_transient_pairs.py`` measures the pair's error ``error n^2`` between 1 and 14 over
signals, in a pattern that is not monotone in lambda/a and does not grow with the amplitude of the creep swing
(0.5 + 0.1 sin and 0.5 + 0.3 sin err alike at lambda/a = 10), so ``rollcontact.model`` must bound it by its
largest value (:data:`rollcontact.model.EXTRAPOLATED_ERROR_CONSTANT`) and auto's pair is 2.6-3.6 times dearer than
needed on slow signals (``benchmarks/results/pareto.md``).  Hypothesis: the error is not the transient's but the
pair's *steady* discretisation bias ``b(xi) = R_steady(xi) - T'_Carter(xi)`` on the substep the host step
imposes (:meth:`rollcontact.instationary.InstationaryModel.steady_state`: ``r = d/h`` of the substep d to the
element h, which the steady slip ``s = xi - K_d q`` depends on), read at the creep of the current force.

Method.  The Pareto study's instationary scenario (N' = 1e7 N/m, mu = 0.3, V = 10 m/s, 64 host steps per cycle of
``xi = (mean + amplitude sin) mu a/R``).  Table 1: b(xi) n^2 [mu N'] of pairs n/2, n for the host steps of
lambda/a = 5 ... 40, with the substeps k and ratio r of the coarse grid.  Table 2: per signal and n the pair's
error over the measured cycle against the pair 400/800 (``pareto.run_instationary``), and the same error less
``b(xi_eq)``, with ``xi_eq`` Carter's steady creep of the step's force (:func:`rollcontact.instationary.carter_creep`)
and b interpolated from 81 creeps over the saturation range: if the second column is much smaller, a defect
correction ``R - b(xi_eq)`` (a table of steady solves per load and host step) would let auto use far coarser pairs.
Table 3: at lambda/a = 2, where ``benchmarks/bench_transient_pairs.py`` found the largest ``error n^2`` (21.4 at
n = 460, r = 0.68), the pair's error with the substeps of :meth:`rollcontact.instationary.InstationaryModel.substeps`
(``k = ceil(ds/h)``, r in (0.5, 1]) against ``k = round(ds/h)`` (r in [0.67, 1.5), closer to 1).

Result (``benchmarks/results/pair_bias.md``, 2026-11-22).  The hypothesis holds in part.  The steady bias is
erratic in n and r (at r ~ 0.97 it is below 0.7/n^2 for |xi| <= 0.8 saturation and jumps to ~10/n^2 at 0.9-0.95,
where the stick zone spans a few elements).  Where the pair errs most (mean 0.5 saturation at lambda/a = 5, 10:
error n^2 5-11) the bias at the force's creep accounts for most of it: 2-2.8 remain.  On the slow signal and the
creep reversal it does not (2-4.7 remain where 1.7-2.1 were).  So the correction would bring the worst case from 11
to about 5 (a bound of ~6.3 in place of 16: 1.6 times fewer elements, 3 times cheaper steps at equal tolerance), at
the price of a steady table per load and host step (81 creeps, two grids).  Not adopted: with a host's varying load
the table would be rebuilt on every step, and lambda/a = 1-2 (error n^2 up to 21) are not checked.  Table 3 points
at the cause instead: rounding the substep count, r nearer 1, takes n = 460 from 21.4 to 6.0 and n = 300 (r = 1.32
then) from 16.6 to 10.8, and leaves the n whose r was near 1 as they were.  So a grid whose coarse element divides
the host's rolled distance (r = 1) should have a far smaller constant than the 30 of
:data:`rollcontact.model.EXTRAPOLATED_ERROR_CONSTANT`; the host step is known when the transient switches in, when
its grid is built (``ContactModel.prepare_grid``).  Not built yet.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import time  # noqa: E402  (after the thread limits)

import numpy as np  # noqa: E402
import pareto  # noqa: E402

from rollcontact.closed_form import carter  # noqa: E402
from rollcontact.instationary import InstationaryModel, carter_creep  # noqa: E402

WAVELENGTHS = (5.0, 10.0, 20.0, 40.0)
SIGNALS = ((5.0, 0.5, 0.3), (10.0, 0.5, 0.1), (40.0, 0.5, 0.3), (5.0, 0.0, 0.9))
PAIRS = (100, 200)
REFERENCE = 800
TABLE_CREEPS = np.linspace(-1.0, 1.0, 81)  # xi / (mu a/R) of the bias table
SHOWN_CREEPS = (-0.9, -0.3, 0.2, 0.5, 0.8, 0.95)


def built_pair(n: int, wavelength: float):
    """The pair stepper of n after one host step of ``wavelength`` (its grid built as in the study), the host step
    [m] and the coarse grid's substeps and ratio ``r = d/h``."""
    ds = wavelength * pareto.A_I / pareto.STEPS_PER_CYCLE
    step = pareto.pair_stepper(n)
    step(0.5 * pareto.SATURATION_I, ds / pareto.SPEED)
    model = step.model.instationary
    k = model.substeps(model.coarse_solver, ds)
    return step, ds, k, ds / k / model.coarse_solver.grid.element_width


def steady_bias(model, ds: float, ratios) -> np.ndarray:
    """``b(xi)`` [mu N'] of the pair's steady rolling on substeps of the host step ``ds`` at creeps ``ratios``
    saturation."""
    out = []
    for ratio in ratios:
        xi = float(ratio) * pareto.SATURATION_I
        state = model.steady_state(pareto.LOAD_I, xi, ds)
        pair = 2.0 * state.tangential_force_per_length - state.coarse.tangential_force_per_length
        exact = carter(pareto.LOAD_I, xi, pareto.R_I, pareto.ESTAR, pareto.MU_I)[0]
        out.append((pair - exact) / (pareto.MU_I * pareto.LOAD_I))
    return np.array(out)


def run(step, signal) -> np.ndarray:
    """T' [N/m] over the measured cycle of ``signal`` from a fresh stepper."""
    xi, dt, first = pareto.creep_signal(*signal)
    return np.array([step(value, dt) for value in xi])[first:]


class RoundedSubsteps(InstationaryModel):
    """The extrapolating transient with ``k = round(ds/h)`` coarse substeps (the fine grid twice as many)."""

    def substeps(self, solver, ds):
        if self.coarse_solver is None or ds == 0.0:
            return super().substeps(solver, ds)
        coarse = max(1, round(ds / self.coarse_solver.grid.element_width))
        return coarse if solver is self.coarse_solver else 2 * coarse


def rounded_pair_stepper(n: int):
    """:func:`pareto.pair_stepper` with :class:`RoundedSubsteps`."""
    step = pareto.pair_stepper(n)
    model = step.model
    model.instationary = RoundedSubsteps(model.radius, model.contact_modulus, model.mu, mode="transient", elements=n,
                                         extrapolate=True)
    return step


def main() -> None:
    start = time.perf_counter()
    print("## 1. Steady bias of the pair, b(xi) n^2 [mu N']\n")
    print("| lambda/a | n | substeps k | r = d/h | " + " | ".join(f"xi = {c:g}" for c in SHOWN_CREEPS) + " |")
    print("|---|---|---|---|" + "---|" * len(SHOWN_CREEPS))
    for wavelength in WAVELENGTHS:
        for n in (64, *PAIRS):
            step, ds, k, r = built_pair(n, wavelength)
            bias = steady_bias(step.model.instationary, ds, SHOWN_CREEPS) * n * n
            print(f"| {wavelength:g} | {n} | {k} | {r:.3f} | " + " | ".join(f"{b:.2f}" for b in bias) + " |",
                  flush=True)
    print("\n## 2. Instationary error of the pair against its steady bias at the force's creep\n")
    print("| lambda/a | xi / (mu a/R) | n | r | max error n^2 | max (error - b(xi_eq)) n^2 | reduction |")
    print("|---|---|---|---|---|---|---|")
    limit = pareto.MU_I * pareto.LOAD_I
    for signal in SIGNALS:
        reference = run(pareto.pair_stepper(REFERENCE), signal)
        for n in PAIRS:
            step, ds, _, r = built_pair(n, signal[0])
            table = steady_bias(step.model.instationary, ds, TABLE_CREEPS)
            forces = run(pareto.pair_stepper(n), signal)
            error = (forces - reference) / limit
            creeps = np.array([carter_creep(f, pareto.LOAD_I, pareto.R_I, pareto.ESTAR, pareto.MU_I)
                               for f in forces]) / pareto.SATURATION_I
            rest = error - np.interp(creeps, TABLE_CREEPS, table)
            worst, left = float(np.abs(error).max()) * n * n, float(np.abs(rest).max()) * n * n
            print(f"| {signal[0]:g} | {signal[1]:g} + {signal[2]:g} sin | {n} | {r:.3f} | {worst:.2f} | {left:.2f} | "
                  f"{worst / left:.1f}x |", flush=True)
    print("\n## 3. The substep rule at lambda/a = 2: error n^2 with k = ceil(ds/h) and k = round(ds/h)\n")
    print("| n | r (ceil) | ceil | round |")
    print("|---|---|---|---|")
    signal = (2.0, 0.5, 0.3)
    reference = run(pareto.pair_stepper(1000), signal)  # bench_transient_pairs.py's reference
    for n in (200, 300, 400, 440, 460):
        _, _, _, r = built_pair(n, signal[0])
        errors = [float(np.abs(run(stepper(n), signal) - reference).max()) / limit * n * n
                  for stepper in (pareto.pair_stepper, rounded_pair_stepper)]
        print(f"| {n} | {r:.2f} | {errors[0]:.2f} | {errors[1]:.2f} |", flush=True)
    print(f"\n{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
