"""Velocity-dependent friction: calibration of the slip iteration's error estimate and of auto's node choice.

Run: ``python benchmarks/calibrate_slip_nodes.py [--quick] [--jobs N] [--records FILE]`` (full: ~340 cases, ~20 min
on two cores; ``--quick``: 48 cases against 512 nodes, ~1 min; ``--records`` keeps the measurements of A-C).
Prints markdown tables:

A. The a-posteriori estimate (:func:`rollcontact.line.methods.polynomial.slip.force_error_estimate`) against the true
   relative T' error, over exponential laws (B = 1..100 s/m), two rational laws and a user table law, V = 1..50 m/s,
   creeps 0.1-0.95 of Carter's saturation creep and beyond the peak of the creep curve (2 and 5 times), on a flat and
   a 40 mm / 20 um corrugated surface, at every node count of auto's ladder up to 128.  True error: against the slip
   iteration with 1024 nodes (``--quick``: 512); cases whose reference does not converge, or whose error is below
   three times the reference's own estimate, are left out.  Per law family: how often the estimate is below the error
   (misses), the smallest, median and largest ratio estimate/error, and the same for the a-priori bound
   ``SLIP_NODE_ERROR beta/N^2``.  Summary by error level: the basis of ``ESTIMATE_SAFETY``.
B. The fine grids of the estimate: the ratio ``|T'_K/T'_M - 1| / error`` for K = 2M, 3M, 4M, 6M and the larger
   of two (ESTIMATE_REFINEMENTS).
C. The a-priori bound of ``rollcontact.line.methods.polynomial.accuracy``: the largest ``error N^2/beta``
   (SLIP_NODE_ERROR bounds it with a margin); and a replay of the adaptive path (start, escalate by
   ``PolynomialAccuracy.escalation``) on every case at t = 1e-2 .. 1e-6, its modelled cost against the cheapest
   rung whose estimate meets t, starting at the floor or where the bound meets t, for several SLIP_CONVERGENCE.
D. auto on the three one-patch velocity-dependent cases of ``benchmarks/pareto.py`` at t = 1e-2, 1e-3, 1e-4: the
   a-priori choice (the cheapest requested node count whose bound ``1.0 beta/N^2`` meets t, solved without the
   a-posteriori estimate; requests below the floor run the floor) against the adaptive path (``setting_for``, then
   ``escalation`` until None, the loop ``solve`` runs), with median times, errors against 1024 nodes and estimates.
E. The cost model: Newton iterations against beta (SLIP_ITERATIONS) and the time per iteration against N
   (SLIP_COST), least squares on timed solves.

One BLAS thread per process (set before numpy loads).  Times are medians on a shared, noisy machine: compare
ratios from the same run.

What it prints goes to ``benchmarks/results/slip_nodes.md`` with the machine (not after ``--quick``).
"""

import argparse
import itertools
import math
import os
import pickle
from multiprocessing import Pool
from pathlib import Path

import common  # before numpy: limits BLAS to one thread
import numpy as np
from pareto_cases import FULL, steady_cases
from scipy import optimize

import rollcontact as rc
from rollcontact.line.dispatch import METHODS
from rollcontact.line.methods.common import friction_sharpness
from rollcontact.line.methods.polynomial import accuracy as polynomial_accuracy
from rollcontact.line.methods.polynomial import slip
from rollcontact.line.methods.polynomial.accuracy import (
    POLYNOMIAL_COST,
    POLYNOMIAL_HARMONIC_COST,
    SLIP_COST,
    SLIP_ITERATIONS,
    SLIP_NODE_ERROR,
    SLIP_NODES,
    slip_nodes,
)

LOAD = 1e6  # N' [N/m]
MU = 0.3
BASE = rc.Scene(LOAD, friction=MU)
SATURATION = MU * rc.hertz(LOAD, BASE.radius, BASE.material.contact_modulus)[0] / BASE.radius
CORRUGATION = {"surface": rc.Surface(harmonics=(rc.Harmonic.from_wavelength(0.04, 20e-6, 0.7),)),
               "axis_position": 0.002}
LAWS = {**{f"exponential B = {b:g}": rc.ExponentialFalling(MU, 0.4, float(b)) for b in (1, 3, 10, 30, 100)},
        "rational v1 = 0.5": rc.RationalFalling(MU, 0.2, 0.5),
        "rational v1 = 0.02": rc.RationalFalling(MU, 0.15, 0.02),
        "table": rc.TabulatedFriction((0.0, 0.05, 0.2, 1.0, 5.0), (MU, 0.27, 0.24, 0.2, 0.18))}
SPEEDS = (1.0, 5.0, 20.0, 50.0)
CREEPS = (0.1, 0.3, 0.6, 0.95, 2.0, 5.0)  # of Carter's saturation creep
MAX_NODES = 128  # largest rung measured in A-C
REFINEMENTS = (2, 3, 4, 6)  # single fine grids K/M measured for table B
TOLERANCES = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6)
PARETO = dict(steady_cases(FULL)["velocity-dependent friction"][:3])  # the Pareto study's one-patch cases
POLYNOMIAL = METHODS["polynomial"].accuracy


def cases(quick: bool) -> list[tuple[tuple, rc.Scene]]:
    """(label, scene) over laws, speeds, creeps and surfaces; an exponential law depends on B V only, so each
    product B V is kept once."""
    out, products = [], set()
    for (name, law), speed in itertools.product(LAWS.items(), SPEEDS):
        if isinstance(law, rc.ExponentialFalling):
            if law.decay * speed in products:
                continue
            products.add(law.decay * speed)
        for creep, (surface, geometry) in itertools.product(CREEPS, (("flat", {}), ("corrugated", CORRUGATION))):
            scene = BASE.replace(friction=law, rolling_speed=speed, creep=creep * SATURATION, **geometry)
            out.append(((name, speed, creep, surface), scene))
    return out[::7] if quick else out


def reference(scene: rc.Scene, nodes: int) -> tuple[float, float]:
    """(T', its own error estimate) of the slip iteration with ``nodes`` nodes; NaN when it does not converge
    (steep laws at high speed: Newton stalls and the relaxed fixed point is given 40 iterations)."""
    normal = rc.solve(scene.replace(friction=MU), method="polynomial", truncation=1e-12)
    out = slip.solve_velocity_dependent(
        normal.info["pressure_coefficients"], normal.contact_half_width, normal.contact_offset,
        scene.material.contact_modulus, scene.friction, scene.rolling_speed, scene.creep, nodes=nodes,
        max_iterations=40)
    if not out["converged"]:
        return math.nan, math.nan
    return out["tangential_force_per_length"], out["distributions"].force_error


def with_refinement(factor: int, scene: rc.Scene, nodes: int) -> rc.ContactResult:
    """The polynomial solve with the estimate from the one fine grid K = ``factor`` M (this process only)."""
    default = slip.ESTIMATE_REFINEMENTS
    slip.ESTIMATE_REFINEMENTS = (factor,)
    try:
        return rc.solve(scene, method="polynomial", nodes=nodes)
    finally:
        slip.ESTIMATE_REFINEMENTS = default


def measure(job) -> dict:
    """One case: the reference and, per rung up to MAX_NODES, T', the estimate and the raw fine-grid differences."""
    (label, scene), reference_nodes = job
    t_ref, ref_estimate = reference(scene, reference_nodes)
    beta = friction_sharpness(scene)
    rungs = []
    for options in POLYNOMIAL.ladder(scene):
        if options["nodes"] > MAX_NODES:
            break
        result = rc.solve(scene, method="polynomial", **options)
        if not (result.success and isinstance(result.distributions, slip.VelocityFrictionDistributions)):
            rungs.append({"nodes": options["nodes"], "failed": result.message})
            continue
        raw = {k: with_refinement(k, scene, options["nodes"]).distributions.force_error
               / slip.ESTIMATE_SAFETY for k in REFINEMENTS}
        rungs.append({"nodes": result.distributions.nodes, "force": result.tangential_force_per_length, "raw": raw})
    return {"label": label, "scene": scene, "reference": t_ref, "reference_estimate": ref_estimate, "beta": beta,
            "rungs": rungs}


def estimate(rung: dict) -> float:
    """The slip estimate of a measured rung with the current ESTIMATE_SAFETY and ESTIMATE_REFINEMENTS."""
    return slip.ESTIMATE_SAFETY * max(rung["raw"][k] for k in slip.ESTIMATE_REFINEMENTS)


def measurable(record: dict) -> list[tuple[dict, float]]:
    """(rung, true error) of the rungs whose error the reference can resolve."""
    if not math.isfinite(record["reference"]):
        return []
    floor = 3.0 * record["reference_estimate"] / slip.ESTIMATE_SAFETY  # the reference's own error
    out = []
    for rung in record["rungs"]:
        if "force" in rung:
            error = abs(rung["force"] / record["reference"] - 1.0)
            if error > max(floor, 1e-12):
                out.append((rung, error))
    return out


def quantiles(values) -> str:
    v = np.asarray(values, dtype=float)
    return " | ".join(f"{q:.3g}" for q in (v.min(), np.median(v), v.max())) if v.size else "- | - | -"


def table_a(records: list[dict]) -> None:
    print("## A. Estimate against the true error\n")
    print(f"ESTIMATE_SAFETY = {slip.ESTIMATE_SAFETY}, K/M = {slip.ESTIMATE_REFINEMENTS}, "
          f"a-priori bound SLIP_NODE_ERROR beta/N^2 with SLIP_NODE_ERROR = {SLIP_NODE_ERROR}.  Ratios: "
          "estimate (or bound) over the true error, min | median | max.\n")
    no_reference = [r["label"] for r in records if not math.isfinite(r["reference"])]
    failed = [(r["label"], g["nodes"]) for r in records for g in r["rungs"] if "failed" in g]
    print("| law | surface | rungs | misses | estimate / error | bound / error |")
    print("|---|---|---|---|---|---|")
    for name, surface in itertools.product(LAWS, ("flat", "corrugated")):
        rows = [(g, e, r["beta"]) for r in records if r["label"][0] == name and r["label"][3] == surface
                for g, e in measurable(r)]
        ratio = [estimate(g) / e for g, e, _ in rows]
        bound = [SLIP_NODE_ERROR * beta / g["nodes"] ** 2 / e for g, e, beta in rows]
        print(f"| {name} | {surface} | {len(rows)} | {sum(x < 1.0 for x in ratio)} | {quantiles(ratio)} | "
              f"{quantiles(bound)} |")
    print("\n| true error above | rungs | misses | ratio < 1.5 | estimate / error |")
    print("|---|---|---|---|---|")
    rows = [(g, e) for r in records for g, e in measurable(r)]
    for level in (0.0, 1e-8, 1e-7, 1e-6, 1e-5):
        ratio = [estimate(g) / e for g, e in rows if e > level]
        print(f"| {level:g} | {len(ratio)} | {sum(x < 1.0 for x in ratio)} | {sum(x < 1.5 for x in ratio)} | "
              f"{quantiles(ratio)} |")
    worst = sorted(((estimate(g) / e, r["label"], g["nodes"], e) for r in records for g, e in measurable(r)))[:5]
    print("\nLowest ratios: " + "; ".join(f"{label} N = {n}: error {e:.2g}, ratio {x:.2g}"
                                          for x, label, n, e in worst))
    print(f"\nNo reference (the {len(no_reference)} cases left out): {no_reference or 'none'}; "
          f"failed rungs: {failed or 'none'}\n")


def table_b(records: list[dict]) -> None:
    print("## B. Fine grids of the estimate\n")
    print("Ratio max_K |T'_K/T'_M - 1| / true error (no safety factor) over the rungs with error above 1e-7.\n")
    print("| K/M | misses (< 1) | below 0.5 | 1st percentile | median | 99th percentile |")
    print("|---|---|---|---|---|---|")
    rows = [(g, e) for r in records for g, e in measurable(r) if e > 1e-7]
    for grids in [(k,) for k in REFINEMENTS] + [(2, 4), (2, 6)]:
        ratio = np.array([max(g["raw"][k] for k in grids) / e for g, e in rows])
        print(f"| {grids} | {np.sum(ratio < 1.0)} / {ratio.size} | {np.sum(ratio < 0.5)} | "
              f"{np.quantile(ratio, 0.01):.3g} | {np.median(ratio):.3g} | {np.quantile(ratio, 0.99):.3g} |")
    print()


def replay(record: dict, tolerance: float, start: str) -> tuple[float, float, int] | None:
    """Modelled cost of the adaptive path from the ``start`` rung ("floor": ``setting_for``; "bound": the
    cheapest whose bound meets t), of the cheapest rung whose estimate meets t, and the escalations; None when
    no measured rung meets t or the path leaves the measured rungs."""
    scene = record["scene"]
    by_nodes = {g["nodes"]: g for g in record["rungs"] if "force" in g}
    meeting = [POLYNOMIAL.cost(scene, {"nodes": n}) for n, g in by_nodes.items() if estimate(g) <= tolerance]
    if not meeting:
        return None
    ladder = POLYNOMIAL.ladder(scene)
    options = (POLYNOMIAL.setting_for("polynomial", scene, tolerance).options if start == "floor" else
               next((o for o in ladder if POLYNOMIAL.error(scene, o) <= tolerance), ladder[-1]))
    cost, runs = 0.0, 0
    while options is not None:
        rung = by_nodes.get(options["nodes"])
        if rung is None:
            return None
        cost += POLYNOMIAL.cost(scene, options)
        runs += 1
        options = POLYNOMIAL.escalation(scene, options, estimate(rung), tolerance)
    return cost, min(meeting), runs - 1


def table_c(records: list[dict]) -> None:
    print("## C. A-priori bound and the adaptive path\n")
    rows = [(g, e, r["beta"]) for r in records for g, e in measurable(r)]
    scaled = np.array([e * g["nodes"] ** 2 / beta for g, e, beta in rows])
    print(f"error N^2/beta: largest {scaled.max():.3g} (SLIP_NODE_ERROR = {SLIP_NODE_ERROR}: margin "
          f"{SLIP_NODE_ERROR / scaled.max():.2f}), median {np.median(scaled):.3g}.\n")
    print("Replay of the adaptive path on the measured rungs: modelled cost over that of the cheapest rung whose "
          "estimate meets t (mean, max), and how many paths escalated once and more than once, by start and "
          "SLIP_CONVERGENCE; paths that leave the measured rungs (above 128 nodes) are left out.\n")
    variants = [("floor", c) for c in (1.5, 2.0, 2.5)] + [("bound", polynomial_accuracy.SLIP_CONVERGENCE)]
    print("| t | cases | " + " | ".join(f"{start}, {c}" for start, c in variants) + " |")
    print("|---|---|" + "---|" * len(variants))
    default = polynomial_accuracy.SLIP_CONVERGENCE
    for tolerance in TOLERANCES:
        cells, count = [], 0
        for start, convergence in variants:
            polynomial_accuracy.SLIP_CONVERGENCE = convergence  # read by PolynomialAccuracy.escalation
            played = [p for p in (replay(r, tolerance, start) for r in records) if p is not None]
            polynomial_accuracy.SLIP_CONVERGENCE = default
            ratio = [c / best for c, best, _ in played]
            count = max(count, len(played))
            cells.append(f"{np.mean(ratio):.2f}, {max(ratio):.2g} ({sum(n == 1 for *_, n in played)}, "
                         f"{sum(n > 1 for *_, n in played)})")
        print(f"| {tolerance:g} | {count} | " + " | ".join(cells) + " |")
    print()


def a_priori_choice(scene: rc.Scene, tolerance: float) -> dict:
    """The cheapest requested count whose bound 1.0 beta/N^2 meets t (a request below the floor runs the floor)."""
    beta = friction_sharpness(scene)
    return next(({"nodes": n} for n in SLIP_NODES if beta / n**2 <= tolerance), {"nodes": SLIP_NODES[-1]})


def adaptive(scene: rc.Scene, tolerance: float) -> list[tuple[dict, rc.ContactResult]]:
    """The adaptive path as ``solve`` runs it: :meth:`PolynomialAccuracy.setting_for`, then its escalation."""
    options = POLYNOMIAL.setting_for("polynomial", scene, tolerance).options
    runs = []
    while options is not None:
        result = rc.solve(scene, method="polynomial", **options)
        runs.append((options, result))
        options = POLYNOMIAL.escalation(scene, options, result.info["error_estimate"], tolerance)
    return runs


def without_estimate(function):
    """``function()`` with the slip iteration's a-posteriori estimate switched off."""
    real = slip.force_error_estimate
    slip.force_error_estimate = lambda *args: math.nan
    try:
        return function()
    finally:
        slip.force_error_estimate = real


def table_d(quick: bool) -> None:
    print("## D. auto on the Pareto study's velocity-dependent cases\n")
    print("A priori: the choice by the bound alone, solved without the a-posteriori estimate; nodes requested -> "
          "run.  Adaptive: the adaptive path with its estimate; nodes of each run.  Times: medians of the choice and "
          "the solve(s).\n")
    print("| case | t | a priori: nodes | time | error | adaptive: nodes | time | error | estimate | meets t |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    repeats = (3, 0.05) if quick else (9, 1.0)
    for label, scene in PARETO.items():
        t_ref, _ = reference(scene, 512 if quick else 1024)
        for tolerance in (1e-2, 1e-3, 1e-4):
            prior = a_priori_choice(scene, tolerance)
            prior_result = rc.solve(scene, method="polynomial", **prior)
            t_prior = common.median_time(lambda s=scene, t=tolerance: without_estimate(
                lambda: rc.solve(s, method="polynomial", **a_priori_choice(s, t))), *repeats)
            runs = adaptive(scene, tolerance)
            t_adaptive = common.median_time(lambda s=scene, t=tolerance: adaptive(s, t), *repeats)
            result = runs[-1][1]
            estimate = result.info["error_estimate"]
            print(f"| {label} | {tolerance:g} | {prior['nodes']} -> {prior_result.distributions.nodes} | "
                  f"{1e3 * t_prior:.2f} ms | {abs(prior_result.tangential_force_per_length / t_ref - 1):.1e} | "
                  f"{' -> '.join(str(r.distributions.nodes) for _, r in runs)} | {1e3 * t_adaptive:.2f} ms | "
                  f"{abs(result.tangential_force_per_length / t_ref - 1):.1e} | {estimate:.1e} | "
                  f"{'yes' if estimate <= tolerance else 'no'} |")
    print()


def table_e(quick: bool) -> None:
    print("## E. Cost model\n")
    scenes = list(PARETO.values()) + [BASE.replace(friction=LAWS["exponential B = 10"], rolling_speed=20.0,
                                                   creep=0.6 * SATURATION, **CORRUGATION)]
    nodes = (16, 32, 64) if quick else (16, 32, 64, 128, 256)
    repeats = (3, 0.05) if quick else (5, 0.3)
    rows = []
    for scene in scenes:
        beta = friction_sharpness(scene)
        base = common.median_time(lambda s=scene: rc.solve(s.replace(friction=MU), method="polynomial"), *repeats)
        for n in nodes:
            if slip_nodes(scene, n) != n:
                continue
            result = rc.solve(scene, method="polynomial", nodes=n)
            iterations = len(result.info["slip_iteration_history"]) - 1
            time = common.median_time(lambda s=scene, n=n: rc.solve(s, method="polynomial", nodes=n), *repeats)
            bare = common.median_time(lambda s=scene, n=n: without_estimate(
                lambda: rc.solve(s, method="polynomial", nodes=n)), *repeats)
            rows.append((beta, n, iterations, time - base, time - bare,
                         POLYNOMIAL.cost(scene, {"nodes": n}) - POLYNOMIAL_COST
                         - POLYNOMIAL_HARMONIC_COST * len(scene.surface.harmonics)))
    beta, n, iterations, extra, estimate_time, modelled = (np.array(c, dtype=float) for c in zip(*rows, strict=True))
    fitted_iterations = np.polyfit(beta, iterations, 1)[::-1]
    model_iterations = fitted_iterations[0] + fitted_iterations[1] * beta
    columns = np.column_stack((np.ones(n.size), n**2, n**3)) * model_iterations[:, None]
    fitted_cost = optimize.nnls(columns / extra[:, None], np.ones(n.size))[0]
    print("| beta | N | Newton iterations | time - normal solve | of which the estimate | model | model refitted |")
    print("|---|---|---|---|---|---|---|")
    for b, m, it, t, t_estimate, model, refitted in zip(beta, n, iterations, extra, estimate_time, modelled,
                                                         columns @ fitted_cost, strict=True):
        print(f"| {b:.3g} | {m:.0f} | {it:.0f} | {1e3 * t:.2f} ms | {1e3 * t_estimate:.2f} ms | {1e3 * model:.2f} ms | "
              f"{1e3 * refitted:.2f} ms |")
    print(f"\nSLIP_ITERATIONS: in methods/polynomial/accuracy.py {SLIP_ITERATIONS}, fitted "
          f"({fitted_iterations[0]:.3g}, {fitted_iterations[1]:.3g}); SLIP_COST: in methods/polynomial/accuracy.py "
          f"{SLIP_COST}, fitted "
          f"({', '.join(f'{c:.3g}' for c in fitted_cost)})\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="48 cases, 512-node references, short timings")
    parser.add_argument("--jobs", type=int, default=os.cpu_count(), help="processes for A-C")
    parser.add_argument("--records", type=Path, help="pickle of the measurements of A-C: read if it exists, else "
                        "written (the tables can then be redone with other constants without measuring again)")
    args = parser.parse_args()
    if args.records is not None and args.records.exists():
        records = pickle.loads(args.records.read_bytes())
    else:
        jobs = [(case, 512 if args.quick else 1024) for case in cases(args.quick)]
        with Pool(args.jobs) as pool:
            records = pool.map(measure, jobs, chunksize=1)
        if args.records is not None:
            args.records.write_bytes(pickle.dumps(records))
    table_a(records)
    table_b(records)
    table_c(records)
    table_d(args.quick)
    table_e(args.quick)


if __name__ == "__main__":
    common.run_and_publish(main, "slip_nodes.md")
