"""The worst step of the elliptic stepping model (the RollingContact3D FMU's library half) at every level, friction
law and Jacobian mode, against the modelled cost that its step budget bounds.

Run: ``python benchmarks/bench_worst_step.py [--quick] [--repeats 3]``.  Writes ``benchmarks/results/worst_step.md``.

For each level (``method`` 0 auto, 1 linear, 2 FASTSIM, 3 strips, 4 discretised, 5 saturated), each friction law
(:data:`LAWS`) and each Jacobian mode, one contact is stepped over a set of inputs from the linear range to deep
saturation, with spin and without, at the supported extremes of a/b (about 0.11 and 8.9) and of the load (1 N ...
1 MN), at the default ``step_budget`` (0.05 s).  Each step is
timed once with the model's caches cold (the first pass over the inputs), then ``--repeats`` times warm; a step's time
is the median of its warm repeats (the machine may be shared: the median leaves out another job's interruptions).
The modelled cost of a step is ``EllipticModel.last_modelled_cost``, the work the step budget bounds.  Per level, law
and mode the table gives the largest cold step, the largest step, the largest modelled cost, the real time over the
modelled cost of the step whose modelled cost is largest (where the budget binds) and the largest such ratio of any
step: the check that the modelled cost bounds the real time, the step's fixed work included (the checks and outputs
of ``EllipticModel.step``; ``rollcontact.elliptic.methods.common.COST_MARGIN`` and ``SOLVE_OVERHEAD`` are set so
that it stays below 1 on an idle machine).  Steps the model refuses (outside what a level treats, or a level refused
at initialisation because its cheapest setting exceeds the budget) are counted, not timed.

The discretised level's cheapest setting is modelled above the default budget, so a second table times it at budgets
it fits, and a third without a budget (``step_budget`` 0), where a step may take far longer.
"""

from __future__ import annotations

import argparse
import itertools
import math
import statistics
import time

import common  # before numpy: limits BLAS to one thread

from rollcontact.stepping import EllipticModel, EllipticParameters, ModelError

LEVELS = {0: "auto", 1: "linear", 2: "fastsim", 3: "strips", 4: "discretised", 5: "saturated"}
DISCRETISED = 4
LAWS = {
    "Coulomb": {},
    "dry rail": {"rail_condition": 1},
    "wet rail": {"rail_condition": 2},
    "tabulated": {"friction_law": 4, "friction_table": "0 0.4; 1 0.3; 5 0.15; 30 0.1"},
    "steep exponential": {"friction_law": 1, "friction_kinetic_ratio": 0.4, "friction_decay": 20.0},
}
"""The friction laws: Coulomb (mu 0.3), Polach's dry and wet rail (B 0.6 and 0.2 s/m), a tabulated law, and an
exponential law falling 30 times faster than the wet rail's (B 20 s/m), which the fuzz of the FMUs draws."""
CURVATURES = ((1.087, 1.667), (1.0, 30.0), (30.0, 1.0))
"""(A, B) [1/m]: a wheel on a rail head (a/b about 0.8), and ellipses of a/b about 8.9 and 0.11."""
DISCRETISED_BUDGETS = (0.1, 0.5)
"""Step budgets [s] of the discretised level's own table: its 16 x 16 grid, and the finer settings that fit 0.5 s."""
DISCRETISED_ROWS = [
    (1e5, *c, v)
    for c in ((2e-3, 0.0, 0.0), (1e-3, -2e-3, 0.5), (0.02, 0.01, 5.0), (0.0, 0.0, 20.0))
    for v in (2.0, 30.0)
]
"""The discretised level's inputs: its grid does not depend on the load, its work on the creepages and the speed."""
UNBUDGETED_ROWS = [(1e5, *c, 30.0) for c in ((2e-3, 0.0, 0.0), (1e-3, -2e-3, 0.5), (0.02, 0.01, 5.0))]
"""Inputs of the steps without a budget (seconds each)."""


def inputs(quick: bool):
    """(Fn [N], xi, eta, phi [1/m], V [m/s]) rows: the linear range to deep saturation, spin, extreme loads."""
    loads = (1.0, 1e5) if quick else (1.0, 1e3, 1e5, 1e6)
    creepages = (
        (1e-5, 0.0, 0.0),
        (2e-3, 0.0, 0.0),
        (0.0, 5e-3, 0.0),
        (1e-3, -2e-3, 0.5),
        (0.02, 0.01, 5.0),
        (0.5, 0.0, 0.0),
        (0.0, 0.0, 20.0),
    )
    if quick:
        creepages = creepages[1::2]
    return [(fn, *c, v) for fn in loads for c in creepages for v in (2.0, 30.0)]


def worst(level: int, law: dict, jacobian: int, budget: float | None, rows, repeats: int) -> dict:
    """The worst steps of one level, law and Jacobian mode over the input ``rows`` and the ellipses (module
    docstring): the largest cold and warm step [s], the largest modelled cost [s] and the real over modelled ratios;
    steps (timed) and refusals (a model refused at initialisation refuses all its steps)."""
    out = {
        "cold": 0.0,
        "warm": 0.0,
        "modelled": 0.0,
        "at_modelled": math.nan,
        "ratio": math.nan,
        "steps": 0,
        "refused": 0,
    }
    for curvature in CURVATURES:
        parameters = {
            "method": level,
            "jacobian": jacobian,
            "curvature_longitudinal": (curvature[0],),
            "curvature_lateral": (curvature[1],),
            **law,
        }
        if budget is not None:
            parameters["step_budget"] = budget
        try:
            model = EllipticModel(EllipticParameters(**parameters))
        except ModelError:
            out["refused"] += len(rows)
            continue
        t = 0.0
        for row in rows:
            times = []
            for _ in range(1 + repeats):
                started = time.perf_counter()
                try:
                    model.step(t, 1e-3, [row])
                except ModelError:
                    break
                times.append(time.perf_counter() - started)
                t += 1e-3
            if not times:
                out["refused"] += 1
                continue
            out["steps"] += 1
            out["cold"] = max(out["cold"], times[0])
            warm = statistics.median(times[1:]) if repeats else times[0]
            out["warm"] = max(out["warm"], warm)
            modelled = model.last_modelled_cost
            if modelled > 0.0:
                ratio = warm / modelled
                out["ratio"] = ratio if math.isnan(out["ratio"]) else max(out["ratio"], ratio)
                if modelled >= out["modelled"]:
                    out["modelled"], out["at_modelled"] = modelled, ratio
    return out


def row(cells) -> str:
    return "| " + " | ".join(map(str, cells)) + " |"


def ms(seconds: float) -> str:
    return f"{seconds * 1e3:.2f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer inputs and laws; results not written")
    parser.add_argument("--repeats", type=int, default=3, help="warm repeats of each step, their median taken")
    args = parser.parse_args()
    print("# The worst step of the elliptic stepping model, per level\n")
    print(
        f"One contact; inputs from the linear range to deep saturation, with and without spin, a/b about 0.1, 0.8 "
        f"and 10, loads {'1 N and 100 kN' if args.quick else '1 N to 1 MN'}, 2 and 30 m/s; a step's time is the "
        f"median of {args.repeats} warm repeats, the first step of each input cold.  Times are wall-clock times on "
        "the machine below: compare the ratios, not the times, with another run.\n"
    )
    print("## At the default `step_budget` (0.05 s)\n")
    header = (
        "| level | friction | jacobian | steps | refused | largest first step [ms] | largest step [ms] | "
        "largest modelled [ms] | real / modelled at the largest modelled | largest real / modelled |"
    )
    print(header)
    print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|")
    laws = {k: v for k, v in LAWS.items() if not (args.quick and k == "tabulated")}
    for level, (law_name, law), jacobian in itertools.product(LEVELS, laws.items(), (0, 1)):
        w = worst(level, law, jacobian, None, inputs(args.quick), args.repeats)
        print(
            row(
                (
                    LEVELS[level],
                    law_name,
                    ("linear", "difference")[jacobian],
                    w["steps"],
                    w["refused"],
                    ms(w["cold"]),
                    ms(w["warm"]),
                    ms(w["modelled"]),
                    f"{w['at_modelled']:.2f}",
                    f"{w['ratio']:.2f}",
                )
            )
        )
    print("\n## The discretised level at budgets it fits\n")
    print(
        "Load 100 kN (the grid does not depend on it), four sets of creepages with and without spin, 2 and 30 m/s; "
        "the three ellipses.\n"
    )
    print(
        "| step_budget [s] | friction | jacobian | steps | refused | largest first step [ms] | largest step [ms] | "
        "largest modelled [ms] | real / modelled at the largest modelled | largest real / modelled |"
    )
    print("|---:|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for budget, (law_name, law), jacobian in itertools.product(DISCRETISED_BUDGETS, list(LAWS.items())[:2], (0, 1)):
        w = worst(DISCRETISED, law, jacobian, budget, DISCRETISED_ROWS, args.repeats)
        print(
            row(
                (
                    budget,
                    law_name,
                    ("linear", "difference")[jacobian],
                    w["steps"],
                    w["refused"],
                    ms(w["cold"]),
                    ms(w["warm"]),
                    ms(w["modelled"]),
                    f"{w['at_modelled']:.2f}",
                    f"{w['ratio']:.2f}",
                )
            )
        )
    print("\n## Without a budget (`step_budget` 0)\n")
    print(
        "The discretised level's defaults (the 60 x 60 / 30 x 30 pair), Jacobian by differences (four solves a "
        "step), load 100 kN, 30 m/s, creepages in the linear range, saturated, and with spin, the three ellipses, "
        "each step once:\n"
    )
    print("| friction | steps | refused | largest step [ms] |")
    print("|---|---:|---:|---:|")
    for law_name, law in LAWS.items():
        w = worst(DISCRETISED, law, 1, 0.0, UNBUDGETED_ROWS, 0)
        print(row((law_name, w["steps"], w["refused"], f"{w['cold'] * 1e3:.1f}")))


if __name__ == "__main__":
    common.run_and_publish(main, "worst_step.md")
