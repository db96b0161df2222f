"""The Pareto study's analysis of a run's rows: Pareto fronts, equal-accuracy ratios, the cost model refitted.

The method: the docstring of ``benchmarks/pareto.py``.
"""

from __future__ import annotations

import math
import statistics
from dataclasses import dataclass

import numpy as np
from pareto_cases import NOT_STEADY_2D, Row, fmt_error, fmt_time
from scipy import optimize, stats

from rollcontact.line.methods.closed_form import CLOSED_FORM_COST
from rollcontact.line.methods.discretised.accuracy import DIRECT_COST, STRUCTURED_COST, STRUCTURED_ITERATIONS
from rollcontact.line.methods.polynomial.accuracy import (
    POLYNOMIAL_COST,
    POLYNOMIAL_HARMONIC_COST,
    SLIP_COST,
    SLIP_ITERATIONS,
)


def pareto_front(rows: list[Row]) -> list[Row]:
    """Rows not dominated in (time, error), by time."""
    front, best = [], math.inf
    for row in sorted((r for r in rows if math.isfinite(r.time) and math.isfinite(r.error)),
                      key=lambda r: (r.time, r.error)):
        if row.error < best:
            front.append(row)
            best = row.error
    return front


def envelope(rows: list[Row], row: Row) -> float:
    """Largest error of this and the finer settings of the same method on the same case (listed after it)."""
    same = [r for r in rows if r.case == row.case and r.method == row.method and r.family == row.family
            and r.options.keys() == row.options.keys()]
    return max(r.error for r in same[same.index(row):])


@dataclass(frozen=True)
class EqualAccuracy:
    """One case's discretised/polynomial time ratio at an accuracy level (:func:`equal_accuracy_ratios`)."""

    case: str
    ratio: float
    polynomial: Row  # the fastest polynomial setting meeting the level
    discretised: Row  # the fastest discretised setting converged to it, else the slowest measured
    lower_bound: bool  # no discretised setting measured converged to the level: the ratio is at least this


def equal_accuracy_ratios(rows: list[Row], level: float, extrapolated: bool) -> list[EqualAccuracy]:
    """Per case: time of the cheapest discretised setting of one kind (single grids, or the extrapolated pairs)
    converged to ``level`` (its error and its finer settings' at most ``level``: :func:`envelope`) over the
    cheapest polynomial setting meeting it; where none converged, the slowest measured one, a lower bound."""
    out = []
    for case in dict.fromkeys(r.case for r in rows):
        poly = [r for r in rows if r.case == case and r.method == "polynomial" and r.error <= level]
        disc = [r for r in rows if r.case == case and r.method == "discretised" and math.isfinite(r.error)
                and bool(r.options.get("extrapolate")) == extrapolated]
        if not poly or not disc:
            continue
        fastest = min(poly, key=lambda r: r.time)
        converged = [r for r in disc if envelope(rows, r) <= level]
        best = min(converged, key=lambda r: r.time) if converged else max(disc, key=lambda r: r.time)
        out.append(EqualAccuracy(case, best.time / fastest.time, fastest, best, not converged))
    return out


def equal_accuracy_lines(rows: list[Row]) -> tuple[list[str], list[str]]:
    """Headline lines of the discretised/polynomial ratios at 1e-2 and 1e-3, and their table per case."""
    lines, table = [], []
    steady = [r for r in rows if r.family not in NOT_STEADY_2D]
    for extrapolated, kind in ((False, "single-grid"), (True, "extrapolated (8 or 16 placements)")):
        for level in (1e-2, 1e-3):
            ratios = equal_accuracy_ratios(steady, level, extrapolated)
            if not ratios:
                continue
            values = [q.ratio for q in ratios]
            bounds = sum(q.lower_bound for q in ratios)
            lines.append(f"- Discretised vs polynomial at equal accuracy {level:.0e} (time of the cheapest {kind} "
                         f"discretised setting converged to it over the polynomial's): median "
                         f"{statistics.median(values):.3g}x, range {min(values):.3g}-{max(values):.3g}x over "
                         f"{len(values)} cases" + (f" ({bounds} of them lower bounds: no {kind} setting measured "
                                                   "converged to it)" if bounds else ""))
            for q in ratios:
                errs = f" (errs {fmt_error(q.discretised.error)})" if q.lower_bound else ""
                table.append(f"| {q.case} | {level:.0e} | {kind} | {q.polynomial.label} | "
                             f"{fmt_time(q.polynomial.time)} | {q.discretised.label}{errs} | "
                             f"{fmt_time(q.discretised.time)} | {'>= ' if q.lower_bound else ''}{q.ratio:.3g} |")
    if table:
        table = ["", "Per case (the fastest polynomial setting meeting the level; the fastest discretised setting "
                 "whose error, and that of its finer settings, meets it; '>=' where none measured did, against the "
                 "finest):", "", "| case | level | discretised kind | polynomial | time | discretised | time | "
                 "ratio |", "|---|---|---|---|---|---|---|---|", *table, ""]
    return lines, table


def fit_costs(rows: list[Row]) -> list[tuple[str, str, str]]:
    """Least-squares constants of the cost model (relative residuals) next to the package's."""

    def fit(columns, times):
        a = np.column_stack(columns) / times[:, None]
        return optimize.nnls(a, np.ones(times.size))[0]

    out = []
    rows = [r for r in rows if math.isfinite(r.time)]
    closed = [r.time for r in rows if r.method == "closed_form"]
    if closed:
        out.append(("CLOSED_FORM_COST", f"{CLOSED_FORM_COST:.3g}", f"{statistics.median(closed):.3g}"))
    coulomb = [r for r in rows if r.method == "polynomial" and "nodes" not in r.options]
    if len(coulomb) > 2:
        harmonics = np.array([r.harmonics for r in coulomb], dtype=float)
        base, per = fit([np.ones(len(coulomb)), harmonics], np.array([r.time for r in coulomb]))
        out.append(("POLYNOMIAL_COST, POLYNOMIAL_HARMONIC_COST",
                    f"{POLYNOMIAL_COST:.3g}, {POLYNOMIAL_HARMONIC_COST:.3g}", f"{base:.3g}, {per:.3g}"))
    direct = [r for r in rows if r.method == "discretised" and r.sharpness == 0.0 and not r.options.get("extrapolate")]
    if len(direct) > 3:
        n = np.array([r.options["elements"] for r in direct], dtype=float)
        fitted = fit([np.ones(n.size), n**2, n**3], np.array([r.time for r in direct]))
        out.append(("DIRECT_COST (a, b, c)", ", ".join(f"{c:.3g}" for c in DIRECT_COST),
                    ", ".join(f"{c:.3g}" for c in fitted)))
    # velocity-dependent friction: times per modelled iteration (the iteration counts are part of the model)
    # on one patch: a split contact runs each patch's iteration in sweeps, which the model does not count
    structured = [r for r in rows if r.method == "discretised" and r.sharpness > 0.0 and r.patches == 1]
    if len(structured) > 3:
        n = np.array([r.options["elements"] for r in structured], dtype=float)
        iterations = np.array([STRUCTURED_ITERATIONS[0] + STRUCTURED_ITERATIONS[1] * r.sharpness
                               for r in structured])
        fitted = fit([np.ones(n.size), n**2, n**3], np.array([r.time for r in structured]) / iterations)
        out.append(("STRUCTURED_COST (a, b, c) per iteration", ", ".join(f"{c:.3g}" for c in STRUCTURED_COST),
                    ", ".join(f"{c:.3g}" for c in fitted)))
    velocity = [r for r in rows if r.method == "polynomial" and "nodes" in r.options and r.patches == 1]
    if len(velocity) > 3:
        nodes = np.array([r.options["nodes"] for r in velocity], dtype=float)
        iterations = np.array([SLIP_ITERATIONS[0] + SLIP_ITERATIONS[1] * r.sharpness for r in velocity])
        extra = (np.array([r.time for r in velocity]) - POLYNOMIAL_COST) / iterations
        fitted = fit([np.ones(nodes.size), nodes**2, nodes**3], np.maximum(extra, 1e-7))
        out.append(("SLIP_COST (a, b, c) per iteration", ", ".join(f"{c:.3g}" for c in SLIP_COST),
                    ", ".join(f"{c:.3g}" for c in fitted)))
    return out


def rank_agreement(rows: list[Row]) -> tuple[float, float, int]:
    """Spearman correlation of model cost and measured time over all settings, and the fraction of same-case
    pairs whose measured times differ by more than 30 % that the model orders the same way."""
    good = [r for r in rows if math.isfinite(r.model_cost) and math.isfinite(r.time)]
    rho = stats.spearmanr([r.model_cost for r in good], [r.time for r in good])[0]
    agree = total = 0
    for i, r in enumerate(good):
        for s in good[i + 1:]:
            if r.case != s.case or max(r.time, s.time) < 1.3 * min(r.time, s.time):
                continue
            total += 1
            agree += (r.model_cost < s.model_cost) == (r.time < s.time)
    return float(rho), agree / total if total else math.nan, total
