"""Elliptic (3D) levels in-process: median time per case of the linear theory, FASTSIM (40 x 40 cells), the strips
(Coulomb friction, with and without spin) and the strips with falling friction (Polach's exponential law), over
creepages from the linear range to deep saturation; and, where the discretised 3D level is registered, each level's
error against it.

Run: ``python benchmarks/calibrate_elliptic_levels.py`` (``--quick``: fewer repeats, results not written).  Prints
markdown tables and writes ``benchmarks/results/elliptic_levels.md``:

A. Median time per case [us] of each level through ``solve_elliptic(scene, name)`` and directly (the method's
   function), per group of cases, with the ratio to the linear theory measured in the same run.  The cases
   (:func:`cases`, 205): a/b 0.2, 0.5, 1, 2, 5; pure longitudinal, lateral and spin creepage at 0.05, 0.3, 1 and 3
   times the creepage whose linear force is 3 mu Fn, and spin with longitudinal and/or lateral creepage, also at 0.4,
   0.6, 1.5, 2 and 5 times it (spin around and past the strips' full slip, ``|psi|`` 1.2..15).
A2. The strips of several contacts in one :func:`~rollcontact.elliptic.methods.strips.solve_strips_many` (1, 8 and
   32 scenes: 8 contacts of different a/b with spin, and the 3 shifted scenes each of the stepping model's Jacobian
   by differences), the median time per call and its ratio to one scene, and :func:`solve_strips` of the first scene
   alone in the same run (``--several-only``: this section alone, printed).
B. (Only with a level named ``discretised`` registered.)  Largest error of Fx, Fy over mu Fn and Mz over mu Fn c of
   each level against the discretised level with its ``extrapolate=True`` (Richardson pair) on the same cases,
   without and with spin, and the strips' per a/b; the accuracy models' constants cite these figures.  B2: that
   reference (the pair of 30 and 60 elements) against the pair of 60 and 120 on the strips' test of large spin.
   B3: FASTSIM and the strips on the same cases at other Poisson's ratios (:data:`POISSON_RATIOS`; G kept), against
   the same reference at that ratio, and the largest error over each level's own estimate.
D. (Same condition.)  The discretised level's work: operator applications per solve on 16, 30 and 60 elements
   (median, p99, largest) over table B's cases and a third of them with each rail condition's law, the time per
   application, and the largest real time against the capped cost model: the constants ``WORK_CAP`` and
   ``APPLICATION_SECONDS`` of :mod:`rollcontact.elliptic.methods.discretised`.
C. (Same condition.)  Falling friction on the Eurosprinter geometry (a/b 0.5, a 6.3 mm, Fn 106.7 kN, V 10 m/s,
   Polach's exponential law mu = 0.36 ((1 - 0.4) exp(-0.6 w) + 0.4)): Fx/(mu_s Fn) of the strips and of the
   discretised level over a creep curve, and their difference.

BLAS is limited to one thread (before numpy loads).  Machines here are noisy: medians, ratios from the same run.
"""

import argparse
import math
import os
import statistics

import common  # before numpy: limits BLAS to one thread
import numpy as np
from elliptic_cases import LOAD, MATERIAL, MU, C, cases

import rollcontact as rc
from rollcontact.elliptic.dispatch import METHODS as ELLIPTIC_METHODS
from rollcontact.elliptic.methods.strips import solve_strips, solve_strips_many


def timing(quick: bool) -> list[str]:
    coulomb = cases()
    falling = [(g, s.replace(friction=rc.ExponentialFalling(MU, 0.4, 0.6), rolling_speed=10.0)) for g, s in coulomb
               if g == "no spin"]
    levels = [("linear", "no spin", coulomb), ("saturated", "spin", coulomb), ("fastsim", "no spin", coulomb),
              ("fastsim", "spin", coulomb),
              ("strips", "no spin", coulomb), ("strips", "spin", coulomb),
              ("strips", "no spin (falling friction)", falling)]
    seconds = 0.02 if quick else 0.1
    lines = ["## A. Median time per case", "",
             "| level | cases | n | via solve_elliptic [us] | direct [us] | ratio to linear (via solve_elliptic) |",
             "|---|---|---|---|---|---|"]
    linear_time = None
    for name, group, pool in levels:
        scenes = [s for g, s in pool if g == group.split(" (")[0]]
        function = ELLIPTIC_METHODS[name].function
        via = statistics.median(common.median_time(lambda s=s, name=name: rc.solve_elliptic(s, name), min_repeats=3,
                                                   min_seconds=seconds) for s in scenes)
        direct = statistics.median(common.median_time(lambda s=s, f=function: f(s), min_repeats=3,
                                                      min_seconds=seconds) for s in scenes)
        linear_time = via if name == "linear" else linear_time
        lines.append(f"| {name} | {group} | {len(scenes)} | {via * 1e6:.0f} | {direct * 1e6:.0f} | "
                     f"{via / linear_time:.1f} |")
    return lines + ["", "FASTSIM on its default 40 x 40 cells; strips on 24 strips (20 cells each where spin needs the "
                    "march); falling friction: one 2D polynomial solve per strip.", ""] + several(seconds)


def several(seconds: float) -> list[str]:
    """A2: solve_strips_many of 1, 8 and 32 scenes with spin (8 contacts of different a/b, each with the 3 shifted
    scenes of a Jacobian by differences), median time per call and the ratio to one scene, from the same run."""
    pool = [s for g, s in cases() if g == "spin" and s.longitudinal_creepage != 0.0 and s.lateral_creepage != 0.0]
    contacts = [pool[k * len(pool) // 8] for k in range(8)]
    jacobian = [s.replace(**{name: getattr(s, name) * 1.001}) for s in contacts
                for name in ("longitudinal_creepage", "lateral_creepage", "spin_creepage")]
    lines = ["## A2. Several contacts' strips together (`solve_strips_many`, spin)", "",
             "| scenes | median per call [us] | ratio to one scene |", "|---|---|---|"]
    alone = common.median_time(lambda: solve_strips(contacts[0]), min_repeats=5, min_seconds=5 * seconds)
    one = None
    for scenes in (contacts[:1], contacts, contacts + jacobian):
        t = common.median_time(lambda scenes=scenes: solve_strips_many(scenes), min_repeats=5,
                               min_seconds=5 * seconds)
        one = t if one is None else one
        lines.append(f"| {len(scenes)} | {t * 1e6:.0f} | {t / one:.2f} |")
    return lines + ["", f"The 8 contacts: a/b {', '.join(f'{s.hertz.aspect_ratio:.2g}' for s in contacts)}; 32 scenes: "
                    f"each with its three shifted scenes. `solve_strips` of the first scene alone: "
                    f"{alone * 1e6:.0f} us in the same run.", ""]


def accuracy() -> list[str]:
    if "discretised" not in ELLIPTIC_METHODS:
        return ["## B. Error against the discretised level", "", "Not run: no level named `discretised` is registered.",
                ""]
    pool = cases()
    reference = [np.array(rc.solve_elliptic(s, "discretised", extrapolate=True).force_coefficients) for _, s in pool]
    lines = ["## B. Largest error against the discretised level (Richardson pair, 60 elements)", "",
             "| level | cases | n | Fx / (mu Fn) | Fy / (mu Fn) | Mz / (mu Fn c) | largest error / estimate |",
             "|---|---|---|---|---|---|---|"]
    for name in ("linear", "saturated", "fastsim", "strips"):
        for group in ("no spin", "spin"):
            worst, ratio, n = np.zeros(3), 0.0, 0
            for (g, s), ref in zip(pool, reference, strict=True):
                if g != group or ELLIPTIC_METHODS[name].inapplicable(s) is not None:
                    continue
                result = rc.solve_elliptic(s, name)
                error = np.abs(np.array(result.force_coefficients) - ref)
                worst, n = np.maximum(worst, error), n + 1
                ratio = max(ratio, error.max() / result.info["error_estimate"])
            if n:
                lines.append(f"| {name} | {group} | {n} | {worst[0]:.3f} | {worst[1]:.3f} | {worst[2]:.3f} | "
                             f"{ratio:.2f} |")
    lines += ["", "Strips per a/b (same reference):", "",
              "| a/b | group | n | Fx / (mu Fn) | Fy / (mu Fn) | Mz / (mu Fn c) |", "|---|---|---|---|---|---|"]
    for ratio in sorted({round(s.hertz.aspect_ratio, 6) for _, s in pool}):
        for group in ("no spin", "spin"):
            chosen = [(s, ref) for (g, s), ref in zip(pool, reference, strict=True)
                      if g == group and round(s.hertz.aspect_ratio, 6) == ratio]
            worst = np.max([np.abs(np.array(rc.solve_elliptic(s, "strips").force_coefficients) - ref)
                            for s, ref in chosen], axis=0)
            lines.append(f"| {ratio:g} | {group} | {len(chosen)} | {worst[0]:.3f} | {worst[1]:.3f} | {worst[2]:.3f} |")
    return lines + [""] + reference_check() + poisson() + falling_curve()


POISSON_RATIOS = (0.0, 0.14, 0.42, 0.49)
"""The Poisson's ratios of table B3 (table B is at 0.28)."""


def poisson() -> list[str]:
    """Table B3: FASTSIM's and the strips' largest errors at other Poisson's ratios, without and with spin."""
    lines = ["## B3. Other Poisson's ratios (same cases, G 82 GPa, reference at each ratio)", "",
             "| nu | level | cases | Fx / (mu Fn) | Fy / (mu Fn) | Mz / (mu Fn c) | largest error / estimate |",
             "|---|---|---|---|---|---|---|"]
    for nu in POISSON_RATIOS:
        pool = cases(poisson_ratio=nu)
        reference = [np.array(rc.solve_elliptic(s, "discretised", extrapolate=True).force_coefficients)
                     for _, s in pool]
        for name in ("fastsim", "strips"):
            for group in ("no spin", "spin"):
                worst, ratio = np.zeros(3), 0.0
                for (g, s), ref in zip(pool, reference, strict=True):
                    if g == group:
                        result = rc.solve_elliptic(s, name)
                        error = np.abs(np.array(result.force_coefficients) - ref)
                        worst = np.maximum(worst, error)
                        ratio = max(ratio, error.max() / result.info["error_estimate"])
                lines.append(f"| {nu:g} | {name} | {group} | {worst[0]:.3f} | {worst[1]:.3f} | {worst[2]:.3f} | "
                             f"{ratio:.2f} |")
    return lines + [""]


def reference_check() -> list[str]:
    """The Richardson pair of 30 and 60 elements (table B's reference, and the reference of the strips' test of large
    spin in ``tests/elliptic/methods/test_strips.py``) against the pair of 60 and 120 on that test's cases."""
    worst = np.zeros(3)
    for ratio in (0.2, 1.0, 2.0, 5.0):
        for xi, eta, phi in ((0, 0, 1), (0, 0, 3), (0.5, 0.5, 1), (0.5, 0.5, 3), (1, -0.5, 3)):
            s = saturated(ratio, xi, eta, phi)
            coarse = rc.solve_elliptic(s, "discretised", elements=60, extrapolate=True).force_coefficients
            fine = rc.solve_elliptic(s, "discretised", elements=120, extrapolate=True).force_coefficients
            worst = np.maximum(worst, np.abs(np.array(coarse) - np.array(fine)))
    return ["## B2. The reference's own error: pair 30/60 against pair 60/120", "",
            "Large spin, alone and with creepage, at a/b 0.2, 1, 2 and 5 (xi/eta/phi in saturation creepages: 0/0/1, "
            "0/0/3, 0.5/0.5/1, 0.5/0.5/3, 1/-0.5/3), the cases of the strips' test against the discretised level.", "",
            "| Fx / (mu Fn) | Fy / (mu Fn) | Mz / (mu Fn c) |", "|---|---|---|",
            f"| {worst[0]:.4f} | {worst[1]:.4f} | {worst[2]:.4f} |", ""]


def saturated(ratio, xi, eta, phi):
    """The scene at a/b = ratio with creepages in units of the creepage whose linear force is mu Fn."""
    base = rc.EllipticScene.from_semi_axes(LOAD, C * math.sqrt(ratio), C / math.sqrt(ratio), material=MATERIAL,
                                           friction=MU)
    k = rc.creepage_coefficients(ratio, MATERIAL.poisson_ratio)
    unit = MU * LOAD / (base.shear_modulus * C * C)
    return base.replace(longitudinal_creepage=xi * unit / k.c11, lateral_creepage=eta * unit / k.c22,
                        spin_creepage=phi * unit / (k.c23 * C))


WORK_GRIDS = (16, 30, 60)
"""Element counts of table D."""


def work() -> list[str]:
    """Table D: the discretised level's operator applications per solve on one grid (uncapped) over the case matrix
    and the rail conditions' falling laws, the time per application, and the largest real time against the capped
    model (:func:`rollcontact.elliptic.methods.discretised.bounded_cost`)."""
    import time

    from rollcontact.elliptic.methods.discretised import APPLICATION_SECONDS, bounded_cost, work_cap

    pool = cases()
    pool += [(g, s.replace(friction=rc.rail_condition("wet"), rolling_speed=30.0)) for g, s in cases()[::3]]
    pool += [(g, s.replace(friction=rc.rail_condition("dry"), rolling_speed=5.0)) for g, s in cases()[::3]]
    lines = ["## D. The discretised level's work: operator applications and time per solve (one grid, uncapped)", "",
             f"{len(pool)} cases: table B's and a third of them with each rail condition's law (wet at 30 m/s, dry at "
             "5 m/s).", "",
             "| elements | applications median | p99 | max | cap | time per application median [us] | min [us] | "
             "modelled [us] | largest time [ms] | capped model [ms] | largest / model |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for n in WORK_GRIDS:
        applications, seconds = [], []
        for _, s in pool:
            started = time.perf_counter()
            result = rc.solve_elliptic(s, "discretised", elements=n, extrapolate=False, bounded=False)
            seconds.append(time.perf_counter() - started)
            applications.append(result.info["operator_applications"])
        applications, seconds = np.array(applications), np.array(seconds)
        per = seconds / applications
        modelled = APPLICATION_SECONDS[0] + APPLICATION_SECONDS[1] * n * n / 3600.0
        lines.append(f"| {n} x {n} | {np.median(applications):.0f} | {np.percentile(applications, 99):.0f} | "
                     f"{applications.max()} | {work_cap((n, n))} | {np.median(per) * 1e6:.0f} | "
                     f"{per.min() * 1e6:.0f} | {modelled * 1e6:.0f} | {seconds.max() * 1e3:.1f} | "
                     f"{bounded_cost((n, n)) * 1e3:.1f} | {seconds.max() / bounded_cost((n, n)):.2f} |")
    return lines + ["", "The cap (`WORK_CAP`) is a margin over the largest; the time per application (`APPLICATION_"
                    "SECONDS`) is fitted to the medians of an idle run; a run on a loaded machine takes longer than "
                    "its model.", ""]


def falling_curve() -> list[str]:
    law = rc.ExponentialFalling(0.36, 0.4, 0.6)
    base = rc.EllipticScene.from_semi_axes(106.7e3, 6.3e-3, 12.6e-3, friction=law, rolling_speed=10.0)
    lines = ["## C. Falling friction, Eurosprinter geometry: strips against the discretised level", "",
             "| xi | strips Fx/(mu_s Fn) | discretised | difference |", "|---|---|---|---|"]
    for xi in (0.0005, 0.001, 0.002, 0.004, 0.01, 0.03, 0.1):
        s = base.replace(longitudinal_creepage=xi)
        strips = rc.solve_elliptic(s, "strips").force_coefficients[0]
        reference = rc.solve_elliptic(s, "discretised", extrapolate=True).force_coefficients[0]
        lines.append(f"| {xi:g} | {strips:.4f} | {reference:.4f} | {strips - reference:+.4f} |")
    return lines + [""]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats; results not written")
    parser.add_argument("--several-only", action="store_true", help="section A2 alone, printed; results not written")
    args = parser.parse_args()
    if args.several_only:
        print("\n".join(several(0.1)))
        return
    load = os.getloadavg()[0]
    lines = ["# Elliptic levels: time per case and error", "", *common.machine(load), "", *timing(args.quick)]
    if not args.quick:
        lines += accuracy() + work()
    common.publish(lines, "elliptic_levels.md", args.quick)


if __name__ == "__main__":
    main()
