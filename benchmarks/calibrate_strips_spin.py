"""Calibration of the strips' march with spin: the constants
:data:`rollcontact.elliptic.methods.strips.SPIN_FLEXIBILITY` of
:func:`~rollcontact.elliptic.methods.strips.march_flexibilities`, fitted to the strips' error against the discretised
3D level.

Run: ``python benchmarks/calibrate_strips_spin.py`` (a few minutes; ``--quick``: a/b 1 only, nothing written).  Prints
markdown tables and writes ``benchmarks/results/strips_spin.md``.

Cases (Coulomb friction, mu 0.3, Fn 100 kN, c = sqrt(ab) = 6 mm, G 82 GPa, nu 0.28, a/b 0.2, 0.5, 1, 2, 5):

* ``table B``: the spin cases of ``benchmarks/calibrate_elliptic_levels.py`` (spin alone and with longitudinal and/or
  lateral creepage, from the linear range to deep spin, around and past the strips' full slip);
* ``operating points``: small creepages with small spin, as a wheel on a rail meets them (xi 0.05 and 0.15, eta half
  that, spin 0.05, 0.15 and 0.3, in units of the creepage whose linear force is 3 mu Fn), where the march's
  flexibilities must stay Kalker's;
* ``spin sweep``: spin alone from 0.75 to 4 saturations (``elliptic_cases.spin_sweep``), through the strips' full slip,
  where the moment at a/b = 5 is least accurate;
* ``table B`` and ``operating points`` at nu = 0, 0.14 and 0.42 (:data:`POISSON_RATIOS`), so that the constants hold
  over Poisson's ratio and not at 0.28 alone, and at nu = 0.49 (:data:`CHECKED_POISSON_RATIO`, not in the fit);
* ``opposed lines`` (not in the fit): spin from 0.5 to 2.5 saturations with lateral creepage against it, along
  lines through the strips' ``|psi| = 1`` (``elliptic_cases.opposed_lines``), where strip theory's stick zones pass
  ``|psi| = 1`` and fade out once their traction would exceed mu p.  On them the script tries values of
  :data:`~rollcontact.elliptic.methods.strips.STICK_FADE` (:data:`FADES`): the largest error and the largest change of
  the error between neighbouring spins of a line (0.1 saturations apart), a measure of the jumps that are left.

Reference: the discretised level's default (the Richardson pair of 30 and 60 elements, within about 0.004 of the
converged solution: ``elliptic_levels.md``, B2).  Error: |dFx|, |dFy| over mu Fn and |dMz| over mu Fn c.  The fit
(Nelder-Mead from the constants in force) minimises a smooth stand-in for the largest error, the 12-norm of the
errors of the first three sets with the operating points' weighted 1.5 (so that the fit for deep spin does not cost the
common case) and those at the other Poisson's ratios weighted :data:`OTHER_WEIGHT`, over the first seven constants; the
onset Q is held (``--onset``: a smaller Q lowers table B's largest error and raises the operating points' median).
It reports each set's median, 90th percentile and largest error of Fx, Fy and Mz with the constants in force and with
the fit.  Copy the fitted constants into ``SPIN_FLEXIBILITY`` by hand;
the results file keeps the figures.
"""

from __future__ import annotations

import argparse
import math

import common  # before numpy: limits BLAS to one thread
import numpy as np
from elliptic_cases import cases, operating_points, opposed_lines, spin_sweep
from scipy.optimize import minimize

import rollcontact as rc
from rollcontact.elliptic.methods import strips

POISSON_RATIOS = (0.0, 0.14, 0.42)
"""Poisson's ratios besides 0.28 whose table B and operating points the fit takes."""

CHECKED_POISSON_RATIO = 0.49
"""A Poisson's ratio whose table B and operating points are checked, not fitted."""

OTHER_WEIGHT = 0.6
"""The weight of the errors at :data:`POISSON_RATIOS` in the fit: nu = 0.28 (steel) comes first."""

WEIGHTS = {"table B": 1.0, "operating points": 1.5, "spin sweep": 1.0,
           **{f"{name}, nu {nu:g}": OTHER_WEIGHT * weight for nu in POISSON_RATIOS
              for name, weight in (("table B", 1.0), ("operating points", 1.5))}}
"""The sets the fit minimises the errors of, with their weights (the others are checked)."""

FADES = (1.1, 1.2, 1.3, 1.4, 1.5, 2.0)
"""The values of ``STICK_FADE`` tried on the opposed lines."""


def signed_errors(scenes, references) -> np.ndarray:
    """``(n, 3)``: the strips' dFx, dFy over mu Fn and dMz over mu Fn c against ``references``."""
    rows = []
    for scene, ref in zip(scenes, references, strict=True):
        r = strips.solve_strips(scene)
        force = scene.friction_coefficient * scene.normal_load
        c = math.sqrt(scene.hertz.a * scene.hertz.b)
        rows.append(((r.longitudinal_force - ref[0]) / force, (r.lateral_force - ref[1]) / force,
                     (r.spin_moment - ref[2]) / (force * c)))
    return np.array(rows)


def errors(scenes, references) -> np.ndarray:
    """``(n, 3)``: the strips' |dFx|, |dFy| over mu Fn and |dMz| over mu Fn c against ``references``."""
    return np.abs(signed_errors(scenes, references))


def largest_jump(names, scenes, references) -> np.ndarray:
    """The largest change of the signed errors (Fx, Fy, Mz) between neighbouring scenes of one line (``names``: the
    line of each scene, a line's scenes in order)."""
    e = signed_errors(scenes, references)
    same = np.array([a == b for a, b in zip(names[:-1], names[1:], strict=True)])
    return np.abs(np.diff(e, axis=0))[same].max(axis=0)


def summary(name: str, constants, e: np.ndarray) -> str:
    def cells(q):
        return " / ".join(f"{v:.4f}" for v in q)

    return (f"| {name} | {constants} | {len(e)} | {cells(np.median(e, axis=0))} | "
            f"{cells(np.percentile(e, 90, axis=0))} | {cells(e.max(axis=0))} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a/b 1 only, few iterations; nothing written")
    parser.add_argument("--onset", type=float, default=None, metavar="Q",
                        help="the onset Q [1] held in the fit (default: the one in force)")
    args = parser.parse_args()
    ratios = (1.0,) if args.quick else (0.2, 0.5, 1.0, 2.0, 5.0)
    opposed = opposed_lines(ratios)
    sets = {"table B": [s for g, s in cases(ratios) if g == "spin"], "operating points": operating_points(ratios),
            "spin sweep": spin_sweep(ratios), "opposed lines": [s for _, s in opposed]}
    for nu in (*POISSON_RATIOS, CHECKED_POISSON_RATIO):
        sets[f"table B, nu {nu:g}"] = [s for g, s in cases(ratios, poisson_ratio=nu) if g == "spin"]
        sets[f"operating points, nu {nu:g}"] = operating_points(ratios, poisson_ratio=nu)
    references = {name: [(r.longitudinal_force, r.lateral_force, r.spin_moment)
                         for r in (rc.solve_elliptic(s, "discretised") for s in scenes)]
                  for name, scenes in sets.items()}
    in_force = tuple(strips.SPIN_FLEXIBILITY)
    fade_in_force = strips.STICK_FADE
    onset = in_force[7] if args.onset is None else args.onset

    def use(constants) -> None:
        strips.SPIN_FLEXIBILITY = tuple(constants)
        strips.ratio_constants.cache_clear()  # it caches the constants' a/b terms

    def all_errors(constants) -> dict:
        use((*constants, onset))
        return {name: errors(scenes, references[name]) for name, scenes in sets.items() if name in WEIGHTS}

    def objective(constants) -> float:
        if constants[4] <= 0.0 or constants[6] <= 0.0:
            return math.inf
        e = all_errors(constants)
        weighted = np.concatenate([WEIGHTS[name] * values.ravel() for name, values in e.items()])
        return float(np.mean(weighted**12)) ** (1.0 / 12.0)

    try:
        start = objective(np.array(in_force[:7]))
        fit = minimize(objective, np.array(in_force[:7]), method="Nelder-Mead",
                       options={"maxiter": 60 if args.quick else 1200, "xatol": 1e-4, "fatol": 1e-6})
        fitted = (*(round(float(v), 4) for v in fit.x), onset)
        lines = ["# Strips with spin: calibration of the march's flexibilities", "",
                 "The fit of the module docstring (12-norm of the sets at nu 0.28 but the opposed lines, operating "
                 f"points weighted 1.5, the other Poisson's ratios but {CHECKED_POISSON_RATIO:g} {OTHER_WEIGHT:g}, "
                 f"onset Q {onset:g} held); errors Fx / Fy over mu Fn, Mz over mu Fn c against the discretised "
                 "level.", "",
                 "| set | SPIN_FLEXIBILITY | n | median | 90th percentile | largest |", "|---|---|---|---|---|---|"]
        for label, constants in (("in force", in_force), ("fitted", fitted)):
            use(constants)
            for name, scenes in sets.items():
                lines.append(summary(f"{name}, {label}", constants, errors(scenes, references[name])))
        use(in_force)
        lines += ["", f"Nelder-Mead: {fit.nit} iterations, objective {start:.4f} in force, {fit.fun:.4f} fitted; "
                  f"fitted SPIN_FLEXIBILITY = {fitted}.", "",
                  "`STICK_FADE` on the opposed lines (SPIN_FLEXIBILITY in force): the largest error and the largest "
                  "change of the error between neighbouring spins, Fx / Fy / Mz.", "",
                  "| STICK_FADE | largest error | largest change |", "|---|---|---|"]
        names = [name for name, _ in opposed]
        for fade in FADES:
            strips.STICK_FADE = fade
            e = errors(sets["opposed lines"], references["opposed lines"])
            jump = largest_jump(names, sets["opposed lines"], references["opposed lines"])
            lines.append(f"| {fade:g}{' (in force)' if fade == fade_in_force else ''} | "
                         f"{' / '.join(f'{v:.4f}' for v in e.max(axis=0))} | {' / '.join(f'{v:.4f}' for v in jump)} |")
    finally:
        use(in_force)
        strips.STICK_FADE = fade_in_force
    print("\n".join(lines))


if __name__ == "__main__":
    common.run_and_publish(main, "strips_spin.md")
