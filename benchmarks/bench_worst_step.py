"""The worst step of the elliptic stepping model (the RollingContact3D FMU's library half) at every level, friction
law and Jacobian mode, against what its step budget bounds.

Run: ``python benchmarks/bench_worst_step.py [--quick]``.  Writes ``benchmarks/results/worst_step.md``.

For each level (``method`` 0 auto, 1 linear, 2 FASTSIM, 3 strips, 4 discretised, 5 saturated), each friction law
(Coulomb, the dry and the wet rail's falling laws, a tabulated law) and each Jacobian mode, one contact is stepped
over a set of inputs from the linear range to deep saturation, with spin and without, at the supported extremes of
a/b (about 0.11 and 8.9) and of the load (1 N ... 1 MN), each step timed, twice over: the first pass meets the
model's caches cold, the second warm.  The table gives, per level, the largest first step, the largest warm step,
the modelled cost that the step budget bounds (``EllipticModel.last_modelled_cost``) and the ratio of the last two;
a ratio below 1 means the model bounds the real cost on this machine.  Steps the model refuses (outside what a level
treats) are counted, not timed.  With ``step_budget`` 0 (no budget) a discretised step may take far longer: the last
table shows how long.
"""

from __future__ import annotations

import argparse
import itertools
import math
import time

import common  # before numpy: limits BLAS to one thread

from rollcontact.stepping import EllipticModel, EllipticParameters, ModelError

LEVELS = {0: "auto", 1: "linear", 2: "fastsim", 3: "strips", 4: "discretised", 5: "saturated"}
LAWS = {"Coulomb": {}, "dry rail": {"rail_condition": 1}, "wet rail": {"rail_condition": 2},
        "tabulated": {"friction_law": 4, "friction_table": "0 0.4; 1 0.3; 5 0.15; 30 0.1"}}
CURVATURES = ((1.087, 1.667), (1.0, 30.0), (30.0, 1.0))
"""(A, B) [1/m]: a wheel on a rail head (a/b about 0.8), and ellipses of a/b about 8.9 and 0.11."""


def inputs(quick: bool):
    """(Fn [N], xi, eta, phi [1/m], V [m/s]) rows: the linear range to deep saturation, spin, extreme loads."""
    loads = (1.0, 1e5) if quick else (1.0, 1e3, 1e5, 1e6)
    creepages = ((1e-5, 0.0, 0.0), (2e-3, 0.0, 0.0), (0.0, 5e-3, 0.0), (1e-3, -2e-3, 0.5), (0.02, 0.01, 5.0),
                 (0.5, 0.0, 0.0), (0.0, 0.0, 20.0))
    if quick:
        creepages = creepages[1::2]
    return [(fn, *c, v) for fn in loads for c in creepages for v in (2.0, 30.0)]


def worst(level: int, law: dict, jacobian: int, budget: float | None, quick: bool):
    """Largest step time [s] of the first pass over the inputs (the model's caches cold) and of the second (warm),
    the largest modelled cost [s] of a step, steps (per pass) and refusals (a model refused at initialisation refuses
    all its steps)."""
    cold, warm, modelled, steps, refused = 0.0, 0.0, 0.0, 0, 0
    rows = inputs(quick)
    for curvature in CURVATURES:
        parameters = {"method": level, "jacobian": jacobian, "curvature_longitudinal": (curvature[0],),
                      "curvature_lateral": (curvature[1],), **law}
        if budget is not None:
            parameters["step_budget"] = budget
        try:
            model = EllipticModel(EllipticParameters(**parameters))
        except ModelError:
            refused += len(rows)
            continue
        for rounds, k_row in itertools.product(range(2), enumerate(rows)):
            k, row = k_row
            started = time.perf_counter()
            try:
                model.step((rounds * len(rows) + k) * 1e-3, 1e-3, [row])
            except ModelError:
                refused += rounds == 0
                continue
            elapsed = time.perf_counter() - started
            if rounds == 0:
                cold, steps = max(cold, elapsed), steps + 1
            else:
                warm = max(warm, elapsed)
            modelled = max(modelled, model.last_modelled_cost)
    return cold, warm, modelled, steps, refused


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer inputs; results not written")
    args = parser.parse_args()
    print("# The worst step of the elliptic stepping model, per level\n")
    print("One contact; inputs from the linear range to deep saturation, with and without spin, a/b about 0.1, 0.8 "
          "and 10, loads 1 N to 1 MN, 2 and 30 m/s; default `step_budget` (0.05 s) unless said.\n")
    print("| level | friction | jacobian | steps | refused | largest first step [ms] | largest step [ms] | "
          "largest modelled [ms] | largest / modelled |")
    print("|---|---|---|---|---|---|---|---|---|")
    for level, (law_name, law), jacobian in itertools.product(LEVELS, LAWS.items(), (0, 1)):
        if args.quick and law_name == "tabulated":
            continue
        cold, warm, modelled, steps, refused = worst(level, law, jacobian, None, args.quick)
        ratio = warm / modelled if modelled > 0 else math.nan
        print(f"| {LEVELS[level]} | {law_name} | {('linear', 'difference')[jacobian]} | {steps} | {refused} | "
              f"{cold * 1e3:.2f} | {warm * 1e3:.2f} | {modelled * 1e3:.2f} | {ratio:.2f} |")
    print("\nWithout a budget (`step_budget` 0), the discretised level's worst step (Jacobian by differences):\n")
    print("| friction | steps | refused | largest step [ms] |")
    print("|---|---|---|---|")
    for law_name, law in LAWS.items():
        _, longest, _, steps, refused = worst(4, law, 1, 0.0, True)
        print(f"| {law_name} | {steps} | {refused} | {longest * 1e3:.1f} |")


if __name__ == "__main__":
    common.run_and_publish(main, "worst_step.md")
