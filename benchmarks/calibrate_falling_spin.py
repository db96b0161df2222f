"""Falling friction with spin at the fast elliptic levels: the strips' and FASTSIM's march at each cell's own slip
(docs/physics.md, "Strips" and "FASTSIM") against the discretised level, over a matrix of a/b, friction laws, speeds
and creepages with spin; the calibration of their accuracy models' falling-friction terms.

Run: ``python benchmarks/calibrate_falling_spin.py`` (the references take 10-20 minutes; ``--reuse`` reads them from
``benchmarks/results/falling_spin.json``; ``--quick``: a/b 1 only, nothing written).  Prints markdown tables and
writes ``benchmarks/results/falling_spin.md``, ``falling_spin.json`` (the reference forces) and ``falling_spin.png``
(the wet rail's creep curves with spin at each level).

Matrix (:func:`matrix`): Fn 100 kN, c = sqrt(ab) = 6 mm, G 82 GPa, nu 0.28, a/b 0.2, 0.5, 1, 2, 5; the laws
:data:`LAWS` (Polach's dry and wet rail, and a rational, a linear and a tabulated falling law of mu(0) 0.4), the rail
conditions at 5, 20 and 50 m/s, the other laws at 5 and 50 m/s; the creepages :data:`COMBOS` (xi, eta, phi in
saturations of the static coefficient: the creepage whose linear force, Kalker's, is mu(0) Fn; longitudinal and
lateral up to 4, spin up to 3).

Tables: A, each level's largest error (Fx, Fy over mu(0) Fn, Mz over mu(0) Fn c; ``largest / estimate``: the
largest ratio of the error to the level's own estimate) and its 95th percentile; B, per law and per a/b; C, the
median time per contact in process (through ``solve_elliptic``), beside the same level with Coulomb friction in the
same run, and the strips' time per contact in batches of 8 contacts of one law (``solve_strips_many``); "Passes",
what a third march changes; D, the reference's own error on a subset (the pair 30/60 against the pair 60/120).
Reference: the discretised level's default (the Richardson pair of 30 and 60 elements); a reference that does not
converge is left out and counted.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics

import common  # before numpy: limits BLAS to one thread
import numpy as np
from elliptic_cases import LOAD, MATERIAL, C

import rollcontact as rc
from rollcontact.elliptic.methods import strips

LAWS = {
    "dry": rc.rail_condition("dry"),
    "wet": rc.rail_condition("wet"),
    "rational": rc.RationalFalling(0.4, 0.25, 0.5),
    "linear": rc.LinearFalling(0.4, 0.25, 0.3),
    "table": rc.TabulatedFriction((0.0, 0.2, 1.0, 3.0), (0.4, 0.36, 0.28, 0.25)),
}
"""The friction laws of the matrix."""

SPEEDS = {"dry": (5.0, 20.0, 50.0), "wet": (5.0, 20.0, 50.0), "rational": (5.0, 50.0), "linear": (5.0, 50.0),
          "table": (5.0, 50.0)}
"""Rolling speeds [m/s] per law."""

RATIOS = (0.2, 0.5, 1.0, 2.0, 5.0)
COMBOS = ((0.5, 0.0, 0.0), (1.0, 0.0, 0.0), (2.0, 0.0, 0.0), (4.0, 0.0, 0.0), (0.0, 1.5, 0.0), (0.0, 0.0, 1.0),
          (0.0, 0.0, 3.0), (1.0, 0.5, 1.0), (2.0, -1.0, 2.0), (0.5, 0.5, 3.0), (3.0, 1.5, 1.0))
"""(xi, eta, phi) in saturations of the static coefficient."""

LEVELS = (("strips", {}), ("fastsim", {"nx": 20, "ny": 20}), ("fastsim", {"nx": 40, "ny": 40}))
"""The fast levels and settings measured."""

JSON = common.RESULTS / "falling_spin.json"


def contact(ratio: float, law: str, speed: float, xi: float, eta: float, phi: float) -> rc.EllipticScene:
    """The matrix's scene: creepages in saturations of the law's static coefficient."""
    friction = LAWS[law]
    base = rc.EllipticScene.from_semi_axes(LOAD, C * math.sqrt(ratio), C / math.sqrt(ratio), material=MATERIAL,
                                           friction=friction, rolling_speed=speed)
    k = rc.creepage_coefficients(ratio, MATERIAL.poisson_ratio)
    unit = friction.static_coefficient * LOAD / (base.shear_modulus * C * C)
    return base.replace(longitudinal_creepage=xi * unit / k.c11, lateral_creepage=eta * unit / k.c22,
                        spin_creepage=phi * unit / (k.c23 * C))


def matrix(ratios=RATIOS) -> list[tuple[str, dict, rc.EllipticScene]]:
    """``(key, labels, scene)`` of every case."""
    out = []
    for ratio in ratios:
        for law, speeds in SPEEDS.items():
            for speed in speeds:
                for combo in COMBOS:
                    labels = {"ratio": ratio, "law": law, "speed": speed, "combo": combo}
                    out.append((json.dumps(labels, sort_keys=True), labels, contact(ratio, law, speed, *combo)))
    return out


def references(cases, reuse: bool) -> dict:
    """The discretised level's forces (force coefficients) per case key, None where it did not converge."""
    stored = json.loads(JSON.read_text()) if reuse and JSON.exists() else {}
    out = {}
    for key, _, scene in cases:
        if key in stored:
            out[key] = stored[key]
            continue
        result = rc.solve_elliptic(scene, "discretised")
        out[key] = list(result.force_coefficients) if result.success else None
    return out


def evaluate(cases, refs) -> list[dict]:
    """Every level's signed errors and estimate per case (cases with a reference)."""
    rows = []
    for key, labels, scene in cases:
        ref = refs[key]
        if ref is None:
            continue
        for name, options in LEVELS:
            result = rc.solve_elliptic(scene, name, **options)
            error = np.array(result.force_coefficients) - np.array(ref)
            rows.append({**labels, "level": level_name(name, options), "error": error.tolist(),
                         "estimate": result.info["error_estimate"], "steepness": result.info.get("steepness", 0.0)})
    return rows


def level_name(name: str, options: dict) -> str:
    return name if not options else f"{name} {options['nx']} x {options['ny']}"


def summary(rows, group) -> str:
    e = np.abs(np.array([r["error"] for r in rows]))
    ratio = max(np.max(np.abs(r["error"])) / r["estimate"] for r in rows)
    largest = " | ".join(f"{v:.3f}" for v in e.max(axis=0))
    p95 = " / ".join(f"{v:.3f}" for v in np.percentile(e, 95, axis=0))
    return f"| {group} | {len(rows)} | {largest} | {p95} | {ratio:.2f} |"


def tables(rows, refs) -> list[str]:
    missing = sum(v is None for v in refs.values())
    head = ["| level | n | Fx / (mu Fn) | Fy / (mu Fn) | Mz / (mu Fn c) | 95th percentile Fx / Fy / Mz | "
            "largest / estimate |", "|---|---|---|---|---|---|---|"]
    lines = ["## A. Largest error against the discretised level", "",
             f"{len(refs)} cases, {missing} without a converged reference (left out).", "", *head]
    for name, options in LEVELS:
        level = level_name(name, options)
        lines.append(summary([r for r in rows if r["level"] == level], level))
        spin = [r for r in rows if r["level"] == level and r["combo"][2] != 0.0]
        lines.append(summary(spin, f"{level}, with spin"))
    lines += ["", "## B. Per law and per a/b (largest errors)", ""]
    for name, options in LEVELS:
        level = level_name(name, options)
        lines += [f"### {level}", "", *head]
        for law in LAWS:
            lines.append(summary([r for r in rows if r["level"] == level and r["law"] == law], law))
        for ratio in RATIOS:
            chosen = [r for r in rows if r["level"] == level and r["ratio"] == ratio]
            if chosen:
                lines.append(summary(chosen, f"a/b {ratio:g}"))
        for speed in (5.0, 20.0, 50.0):
            lines.append(summary([r for r in rows if r["level"] == level and r["speed"] == speed], f"{speed:g} m/s"))
        lines.append("")
    worst = sorted((r for r in rows if r["level"] == "strips"), key=lambda r: -np.max(np.abs(r["error"])))[:8]
    lines += ["Strips' largest errors (a/b, law, speed, creepages in saturations: error Fx / Fy / Mz, estimate, "
              "steepness):", ""]
    lines += [f"- a/b {r['ratio']:g}, {r['law']}, {r['speed']:g} m/s, {tuple(r['combo'])}: "
              f"{' / '.join(f'{v:+.3f}' for v in r['error'])}, estimate {r['estimate']:.3f}, steepness "
              f"{r['steepness']:.2f}" for r in worst]
    steep = [r for r in rows if r["level"] == "strips" and r["steepness"] > 1.0]
    lines += ["", f"Strips' cases with a non-monotone cell (steepness `-D V dmu/dv` above 1): {len(steep)}; their "
              f"largest error {max((np.max(np.abs(r['error'])) for r in steep), default=0.0):.3f}.", ""]
    return lines


def timing(cases, quick: bool) -> list[str]:
    chosen = cases[:: max(1, len(cases) // (12 if quick else 60))]
    seconds = 0.02 if quick else 0.1
    lines = ["## C. Median time per contact in process [us] (`solve_elliptic`)", "",
             f"{len(chosen)} cases of the matrix; Coulomb: the same scenes at the static coefficient, same run.", "",
             "| level | falling friction | Coulomb | ratio |", "|---|---|---|---|"]
    for name, options in LEVELS:
        times = {}
        pools = {"falling": [s for _, _, s in chosen],
                 "coulomb": [s.replace(friction=rc.Coulomb(s.friction_coefficient)) for _, _, s in chosen]}
        for label, pool in pools.items():
            times[label] = statistics.median(common.median_time(
                lambda s=s, name=name, options=options: rc.solve_elliptic(s, name, **options), min_repeats=3,
                min_seconds=seconds) for s in pool)
        lines.append(f"| {level_name(name, options)} | {times['falling'] * 1e6:.0f} | {times['coulomb'] * 1e6:.0f} | "
                     f"{times['falling'] / times['coulomb']:.2f} |")
    batches = together(cases, quick)
    times = {label: statistics.median(common.median_time(lambda b=b: strips.solve_strips_many(b), min_repeats=3,
                                                         min_seconds=seconds) / len(b) for b in pool)
             for label, pool in batches.items()}
    lines.append(f"| strips, {BATCH} contacts of one law together (`solve_strips_many`), per contact | "
                 f"{times['falling'] * 1e6:.0f} | {times['coulomb'] * 1e6:.0f} | "
                 f"{times['falling'] / times['coulomb']:.2f} |")
    return lines + ["", f"The last row: {len(batches['falling'])} batches of {BATCH} cases of one law and speed "
                    "(a vehicle's contacts: one rail, one speed, their own a/b and creepages), each batch's time over "
                    f"{BATCH}.", ""]


BATCH = 8
"""Contacts per batch of the last row of table C."""


def together(cases, quick: bool) -> dict[str, list[list]]:
    """Batches of :data:`BATCH` scenes of one law and speed from the matrix (falling, and the same at the static
    coefficient), every ``step``-th batch."""
    pools: dict = {}
    for _, labels, scene in cases:
        pools.setdefault((labels["law"], labels["speed"]), []).append(scene)
    batches = [pool[k:k + BATCH] for pool in pools.values() for k in range(0, len(pool) - BATCH + 1, BATCH)]
    batches = batches[:: max(1, len(batches) // (4 if quick else 16))]
    return {"falling": batches,
            "coulomb": [[s.replace(friction=rc.Coulomb(s.friction_coefficient)) for s in b] for b in batches]}


def passes(cases) -> list[str]:
    """The largest change of the strips' forces from a third march (with spin)."""
    worst = np.zeros(3)
    kept = strips.FALLING_PASSES
    try:
        for _, _, scene in cases[::3]:
            if scene.spin_creepage == 0.0:
                continue
            strips.FALLING_PASSES = kept
            two = np.array(rc.solve_elliptic(scene, "strips").force_coefficients)
            strips.FALLING_PASSES = kept + 1
            three = np.array(rc.solve_elliptic(scene, "strips").force_coefficients)
            worst = np.maximum(worst, np.abs(three - two))
    finally:
        strips.FALLING_PASSES = kept
    return ["## Passes", "", f"A third march changes the strips' forces by at most {worst[0]:.4f} / {worst[1]:.4f} / "
            f"{worst[2]:.4f} (Fx / Fy / Mz) on a third of the cases with spin.", ""]


def reference_check(cases) -> list[str]:
    worst, n = np.zeros(3), 0
    for _, labels, scene in cases:
        if labels["law"] in ("dry", "wet") and labels["speed"] == 50.0 and labels["ratio"] in (0.2, 1.0, 5.0) \
                and labels["combo"] in ((4.0, 0.0, 0.0), (2.0, -1.0, 2.0), (0.0, 0.0, 3.0)):
            coarse = rc.solve_elliptic(scene, "discretised", elements=60)
            fine = rc.solve_elliptic(scene, "discretised", elements=120)
            if coarse.success and fine.success:
                worst = np.maximum(worst, np.abs(np.array(coarse.force_coefficients) - fine.force_coefficients))
                n += 1
    return ["## D. The reference's own error: pair 30/60 against pair 60/120", "",
            f"{n} cases (dry and wet at 50 m/s, a/b 0.2, 1, 5, xi/eta/phi 4/0/0, 2/-1/2, 0/0/3): largest "
            f"{worst[0]:.4f} / {worst[1]:.4f} / {worst[2]:.4f} (Fx / Fy / Mz).", ""]


def figure(path) -> None:
    """The wet rail's creep curves with spin (a/b 1, 30 m/s): Fx and Fy against xi at spin 0, 1.5 and 3 saturations,
    each fast level beside the discretised level."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    fine = np.linspace(0.0, 4.0, 33)
    coarse = np.linspace(0.0, 4.0, 9)
    for spin, colour in ((0.0, "C0"), (1.5, "C1"), (3.0, "C2")):
        for name, options, style, xs in (("strips", {}, "-", fine), ("fastsim", {"nx": 20, "ny": 20}, "--", fine),
                                         ("discretised", {}, "o", coarse)):
            values = np.array([rc.solve_elliptic(contact(1.0, "wet", 30.0, x, 0.0, spin), name,
                                                 **options).force_coefficients for x in xs])
            label = f"{name}, spin {spin:g}" if spin == 0.0 or name == "discretised" else None
            for axis, column in zip(axes, (0, 1), strict=True):
                axis.plot(xs, values[:, column], style, color=colour, label=label if column == 0 else None,
                          markersize=4)
    for axis, name in zip(axes, ("Fx / (mu(0) Fn)", "Fy / (mu(0) Fn)"), strict=True):
        axis.set_xlabel("xi [saturations]")
        axis.set_ylabel(name)
        axis.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle("Wet rail (Polach), a/b 1, 30 m/s: strips (solid), FASTSIM 20 x 20 (dashed), discretised (dots); "
                 "spin 0 / 1.5 / 3 saturations (blue / orange / green)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a/b 1 only, nothing written")
    parser.add_argument("--reuse", action="store_true", help="read the reference forces from falling_spin.json")
    args = parser.parse_args()
    cases = matrix((1.0,) if args.quick else RATIOS)
    refs = references(cases, args.reuse)
    if not args.quick:
        stored = json.loads(JSON.read_text()) if JSON.exists() else {}
        stored.update(refs)
        JSON.write_text(json.dumps(stored, indent=0, sort_keys=True))
    rows = evaluate(cases, refs)
    load = os.getloadavg()[0]
    lines = ["# Falling friction with spin at the fast elliptic levels", "", *common.machine(load), "",
             *tables(rows, refs), *passes(cases), *timing(cases, args.quick)]
    if not args.quick:
        lines += reference_check(cases)
        figure(common.RESULTS / "falling_spin.png")
    common.publish(lines, "falling_spin.md", args.quick)


if __name__ == "__main__":
    main()
