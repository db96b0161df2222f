"""Several contact patches by the polynomial method (``rollcontact.line.methods.polynomial.patches``): where it
applies, what it costs, and what it shows about the discretised solver's error bounds on such scenes.

Run ``.venv/bin/python benchmarks/bench_multipatch.py``: writes ``benchmarks/results/multipatch.md`` (~4 min).

Scenes: N' = 1 MN/m, R = 0.46 m, steel, mu = 0.3, a corrugation of wavelength 4, 5, 8, 10 mm and amplitude 10,
20, 40 um (k a = 0.7-3.6), creep 0.1, 0.5, 0.9 of Carter's saturation creep, the axis at 24 positions over a
wavelength: 864 scenes.

Table A: ``solve(scene, method="polynomial", tolerance=1e-3)``: one patch by the single-patch method, one or
several patches by ``multipatch`` (where the single patch failed), or failed (why); median time of each.

Table B: the discretised solver's settings (one grid of n = 50..800 elements; the extrapolated pair n/2n over m = 8,
16 placements) against the polynomial method at tolerance 1e-12 on every three-patch scene of table A and a random
sample of the two- and one-patch ones: the largest ratio of the relative T' and p0 errors to the setting's a-priori
bound (``DiscretisedAccuracy.error``, the Hertz width) and to the result's a-posteriori estimate (the patch
widths, ``patch_widths``), by number of patches.

Table C: a falling friction law (exponential, mu_k/mu_s = 0.4, 3 s/m, V = 20 m/s) on every other axis position
of table A's scenes: ``solve(scene)``'s outcome by method and number of patches, median time.  One BLAS thread.
"""

from __future__ import annotations

import collections
import math
import os
import time

import common  # before numpy: limits BLAS to one thread
import numpy as np

import rollcontact as rc

LOAD = 1e6  # N' [N/m]
A_HERTZ = rc.hertz(LOAD, 0.46, rc.Scene(LOAD).material.contact_modulus)[0]
SATURATION = 0.3 * A_HERTZ / 0.46
WAVELENGTHS = (0.004, 0.005, 0.008, 0.010)  # m
AMPLITUDES = (10e-6, 20e-6, 40e-6)  # m
CREEPS = (0.1, 0.5, 0.9)  # of the saturation creep
POSITIONS = 24
FALLING = rc.ExponentialFalling(0.3, 0.4, 3.0)  # table C
SPEED = 20.0  # m/s, table C
DISCRETISED = ([{"elements": n} for n in (50, 100, 200, 400, 800)]
               + [{"elements": n, "extrapolate": m} for m in (8, 16) for n in (50, 100, 200, 400)])
COLUMNS = ("T' / a priori", "T' / estimate", "p0 / a priori", "p0 / estimate")


def scenes(every: int = 1):
    """Table A's scenes; ``every``: only every so many axis positions."""
    for wavelength in WAVELENGTHS:
        for amplitude in AMPLITUDES:
            for ratio in CREEPS:
                for position in wavelength * np.arange(0, POSITIONS, every) / POSITIONS:
                    yield rc.Scene(LOAD, creep=ratio * SATURATION, axis_position=float(position),
                                   surface=rc.Surface(harmonics=(rc.Harmonic.from_wavelength(wavelength, amplitude),)))


def outcome(result) -> str:
    """single | 'K patches' | 'failed: reason'."""
    if result.success:
        return "one patch (single-patch method)" if "stick_zones" not in result.info else \
            f"{len(result.info['patches'])} patch(es) (multipatch)"
    message = result.message
    for key in ("second stick zone", "traction bound", "the stick zones", "the patch edges", "more patches"):
        if key in message:
            return f"failed: {key}"
    return "failed: " + message[:60]


def table_a():
    counts, times, found = collections.Counter(), collections.defaultdict(list), collections.defaultdict(list)
    for scene in scenes():
        start = time.perf_counter()
        result = rc.solve(scene, method="polynomial", tolerance=1e-3)
        elapsed = time.perf_counter() - start
        kind = outcome(result)
        counts[kind] += 1
        times[kind].append(elapsed)
        if result.success and "stick_zones" in result.info:
            found[len(result.info["patches"])].append(scene)
    return counts, times, found


def table_b(found):
    rng = np.random.default_rng(11)
    sample = list(found.get(3, []))
    for patches, size in ((2, 40), (1, 12)):
        pool = found.get(patches, [])
        sample += [pool[i] for i in rng.choice(len(pool), min(size, len(pool)), replace=False)]
    model = rc.METHODS["discretised"].accuracy
    worst = {}
    for scene in sample:
        reference = rc.solve(scene, method="polynomial", truncation=1e-12)
        patches = len(reference.info["patches"])
        for options in DISCRETISED:
            if options["elements"] < model.resolution(scene):
                continue
            result = rc.solve(scene, method="discretised", **options)
            if not result.success:
                continue
            force = abs(result.tangential_force_per_length / reference.tangential_force_per_length - 1.0)
            # the pair's p0 is the finer level's mean, second order: its error is not what the pair improves
            pressure = abs(result.max_pressure / reference.max_pressure - 1.0)
            kind = ("pair" if "extrapolate" in options else "one grid", patches)
            record = worst.setdefault(kind, {})
            for column, error, bound in (("T' / a priori", force, model.error(scene, options)),
                                         ("T' / estimate", force, result.info["error_estimate"]),
                                         ("p0 / a priori", pressure, model.error(scene, options)),
                                         ("p0 / estimate", pressure, result.info["error_estimate"])):
                if error / bound > record.get(column, (0.0,))[0]:
                    record[column] = (error / bound, options, scene.creep / SATURATION)
            # how pessimistic the estimate is (where the error is above round-off)
            if force > 1e-12:
                record.setdefault("pessimism", []).append(result.info["error_estimate"] / force)
    return len(sample), worst


def table_c():
    """Falling friction on every other axis position of table A's scenes: auto's outcome, by method and patches."""
    counts, times = collections.Counter(), collections.defaultdict(list)
    for scene in scenes(every=2):
        scene = scene.replace(friction=FALLING, rolling_speed=SPEED)
        start = time.perf_counter()
        result = rc.solve(scene)
        elapsed = time.perf_counter() - start
        patches = len(result.info.get("patches") or [None])
        kind = (f"{result.method}, {patches} patch(es)" if result.success
                else f"failed ({result.method}): {result.message[:70]}")
        counts[kind] += 1
        times[kind].append(elapsed)
    return counts, times


def main():
    start, load = time.time(), os.getloadavg()[0]
    counts, times, found = table_a()
    sampled, worst = table_b(found)
    falling_counts, falling_times = table_c()
    total = sum(counts.values())
    lines = ["# Several contact patches by the polynomial method", "",
             f"Generated by `.venv/bin/python benchmarks/bench_multipatch.py` in {time.time() - start:.0f} s; the "
             "scenes and the method: the module docstring.", "",
             f"## A. `solve(method=\"polynomial\", tolerance=1e-3)` on {total} corrugated scenes", "",
             "| outcome | scenes | median time |", "|---|---|---|"]
    for kind, count in sorted(counts.items(), key=lambda item: -item[1]):
        lines.append(f"| {kind} | {count} | {1e3 * float(np.median(times[kind])):.2f} ms |")
    solved = sum(c for k, c in counts.items() if not k.startswith("failed"))
    lines += ["", f"The polynomial method answers {solved} of {total}: "
                  f"{counts['one patch (single-patch method)']} by the single-patch method, the rest by `multipatch`.",
              "",
              f"## B. The discretised solver's T' and p0 bounds against the polynomial method ({sampled} scenes)",
              "", "The largest ratio of the relative error to the a-priori bound (`DiscretisedAccuracy.error`, "
              "the Hertz width) and to the a-posteriori estimate of the result (`info[\"error_estimate\"]`, the "
              "patch widths of `patch_widths`); where, at what creep / saturation.", "",
              "| setting kind | patches | " + " | ".join(COLUMNS) + " | estimate / T' error, median (max) |",
              "|---|---|" + "---|" * (len(COLUMNS) + 1)]
    for (kind, patches), record in sorted(worst.items()):
        cells = [f"{record[c][0]:.2f} ({record[c][1]}, {record[c][2]:.1f})" if c in record else "-" for c in COLUMNS]
        pessimism = record.get("pessimism", [math.nan])
        cells.append(f"{np.median(pessimism):.1f} ({max(pessimism):.3g})")
        lines.append(f"| {kind} | {patches} | " + " | ".join(cells) + " |")
    lines += ["", "A ratio above 1 is a bound exceeded.  The a-priori bounds use the Hertz width: where the "
                  "patches are narrower (small satellite patches, short corrugations) they are exceeded, and `auto`, "
                  "which chooses by them, escalates while the estimate misses the tolerance "
                  "(`DiscretisedAccuracy.escalation`).", ""]
    total = sum(falling_counts.values())
    lines += [f"## C. Falling friction: `solve(scene)` on {total} of the scenes", "",
              f"Every other axis position of table A, with `{FALLING!r}` at V = {SPEED:g} m/s.  The polynomial method "
              "solves one patch, and several by each patch's slip iteration under the others' fields "
              "(`patches_slip.py`); where that fails auto falls back to the discretised slip iteration (a stick "
              "zone at each patch's leading edge, on the automatic grid, refined once where the structure fails "
              "there).", "",
              "| outcome | scenes | median time |", "|---|---|---|"]
    for kind, count in sorted(falling_counts.items(), key=lambda item: -item[1]):
        lines.append(f"| {kind} | {count} | {1e3 * float(np.median(falling_times[kind])):.2f} ms |")
    lines += ["", *common.machine(load)]
    common.publish(lines, "multipatch.md", quick=False)


if __name__ == "__main__":
    main()
