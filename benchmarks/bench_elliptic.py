"""The elliptic (3D) levels against the converged discretised solution: time per case, error, convergence order.

Run: ``python benchmarks/bench_elliptic.py [--quick]`` (about fifteen minutes; ``--quick``: a/b 1 only, coarse
grids, nothing written).  Writes ``benchmarks/results/bench_elliptic.md``, the figure
``benchmarks/results/bench_elliptic.png`` and the reference forces ``benchmarks/results/bench_elliptic.json``.

The case matrix (as the field's reference code is measured on): a/b = 0.2, 0.5, 1, 2, 5; pure xi, eta and phi at
0.05, 0.2, 0.5, 1, 2 and 3 saturation creepages; combined cases with large spin.  A creepage's saturation is where
Kalker's linear theory reaches mu Fn: ``G c^2 C11 xi = mu Fn``, ``G c^2 C22 eta = mu Fn``,
``G c^3 C23 phi = mu Fn`` (the coefficients of the discretised solver at N = 24, module ``linear_coefficients``).
Forces are over mu Fn, the moment over mu Fn c (c = sqrt(ab)).

* A. The discretised solver on 60 x 60 elements across 2a x 2b: the median time per case (one thread) and its error
  against the reference, the Richardson extrapolation ``2 F(120) - F(60)`` (its own uncertainty: the largest
  ``|R(30, 60) - R(60, 120)|``, and a spot check at 240 elements); the convergence order from the differences over
  N = 15, 30, 60, 120, and the error of the Richardson pair ``2 F(60) - F(30)``.
* B. Each level of the elliptic dispatcher against the same reference, when the package is importable.
* C. Falling friction (Polach's exponential law) on the Eurosprinter's contact: strips vs discretised.
* D. ``solve_elliptic(scene, tolerance=t)`` over the matrix: the settings auto picks, whether they meet t, their time
  (the 3D levels' speed-accuracy front, the plot's middle panel).
"""

import argparse
import json
import math
import time

import common  # before numpy: limits BLAS to one thread
import numpy as np

from rollcontact.core.friction import Coulomb
from rollcontact.core.halfspace.rolling import ellipse_grid, hertz_pressure, solve_steady, total_forces
from rollcontact.core.halfspace.surface import operator_for

YOUNG, NU, LOAD, SIZE, MU = 210e9, 0.28, 100e3, 6e-3, 0.3  # Pa, 1, N, c = sqrt(ab) [m], 1
SHEAR = YOUNG / (2 * (1 + NU))
RATIOS = (0.2, 0.5, 1.0, 2.0, 5.0)
LEVELS = (0.05, 0.2, 0.5, 1.0, 2.0, 3.0)
COMBINED = ((0.5, 0.5, 1.0), (0.5, 0.5, 3.0), (1.0, -0.5, 3.0))
"""(xi, eta, phi) in saturation creepages."""


def axes(ratio):
    return SIZE * math.sqrt(ratio), SIZE / math.sqrt(ratio)


def linear_coefficients(ratio, n=24):
    """(C11, C22, C23) of the discretised solver at vanishing creepage on n x n elements (the case matrix's scale)."""
    a, b = axes(ratio)
    grid = ellipse_grid(a, b, n)
    op = operator_for(grid, NU)
    p = hertz_pressure(grid, a, b, LOAD)
    x, y = grid.mesh()
    e = 1e-9
    fx = total_forces(grid, *traction(op, p, x, y, (e, 0, 0)))[0]
    fy = total_forces(grid, *traction(op, p, x, y, (0, e, 0)))[1]
    fs = total_forces(grid, *traction(op, p, x, y, (0, 0, e / SIZE)))[1]
    scale = SHEAR * SIZE * SIZE * e
    return fx / scale, fy / scale, fs / scale


def traction(op, p, x, y, creepages, friction=None, speed=1.0):
    friction = Coulomb(MU) if friction is None else friction
    xi, eta, phi = creepages
    sol = solve_steady(op, p, (xi - phi * y, eta + phi * x), SHEAR, friction, speed)
    if not sol.converged:
        raise RuntimeError(f"discretised solve of {creepages} failed: {sol.message}")
    return sol.traction_x, sol.traction_y


def cases(ratios):
    """[(name, ratio, (xi, eta, phi))] of the matrix."""
    out = []
    for ratio in ratios:
        c11, c22, c23 = linear_coefficients(ratio)
        unit = MU * LOAD / (SHEAR * SIZE * SIZE)
        saturation = (unit / c11, unit / c22, unit / (c23 * SIZE))
        for kind, k in (("xi", 0), ("eta", 1), ("phi", 2)):
            for level in LEVELS:
                creepages = [0.0, 0.0, 0.0]
                creepages[k] = level * saturation[k]
                out.append((f"{kind} {level:g}", ratio, tuple(creepages)))
        for combo in COMBINED:
            out.append(("xi/eta/phi " + "/".join(f"{v:g}" for v in combo), ratio,
                        tuple(v * s for v, s in zip(combo, saturation, strict=True))))
    return out


def discretised(ratio, creepages, n):
    """(Fx/(mu Fn), Fy/(mu Fn), Mz/(mu Fn c)) on n x n elements across the ellipse."""
    a, b = axes(ratio)
    grid = ellipse_grid(a, b, n)
    op = operator_for(grid, NU)
    p = hertz_pressure(grid, a, b, LOAD)
    x, y = grid.mesh()
    fx, fy, mz = total_forces(grid, *traction(op, p, x, y, creepages))
    return np.array([fx / (MU * LOAD), fy / (MU * LOAD), mz / (MU * LOAD * SIZE)])


def part_a(matrix, quick):
    """Time at 60, errors and convergence; returns the reference per case and the table lines."""
    grids = (8, 16, 32) if quick else (15, 30, 60, 120)
    timed = 32 if quick else 60
    rows, reference, times, errors, orders, pair_errors, uncertainty = [], {}, [], [], [], [], []
    reference_forces = {}
    for name, ratio, creepages in matrix:
        forces = {n: discretised(ratio, creepages, n) for n in grids}
        fine, coarse = forces[grids[-1]], forces[grids[-2]]
        ref = 2 * fine - coarse
        previous = 2 * coarse - forces[grids[-3]]
        uncertainty.append(np.abs(ref - previous).max())
        reference[f"{ratio:g} {name}"] = ref.tolist()
        reference_forces[f"{ratio:g} {name}"] = forces
        t = common.median_time(lambda r=ratio, c=creepages: discretised(r, c, timed), min_repeats=3,
                               min_seconds=0.0)
        error = np.abs(forces[timed] - ref).max()
        pair = np.abs(2 * forces[timed] - forces[timed // 2] - ref).max()
        d = [np.abs(forces[grids[i]] - forces[grids[i + 1]]).max() for i in range(len(grids) - 1)]
        order = math.log2(d[-2] / d[-1]) if d[-1] > 1e-7 and d[-2] > 1e-7 else math.nan
        times.append(t)
        errors.append(error)
        pair_errors.append(pair)
        if not math.isnan(order):
            orders.append(order)
        rows.append(f"| {ratio:g} | {name} | {' / '.join(f'{v:+.4f}' for v in ref)} | {error:.4f} | {pair:.4f} | "
                     f"{order:.2f} | {1e3 * t:.0f} |")
        print(rows[-1], flush=True)
    spot = []
    if not quick:
        for name, ratio, creepages in matrix:
            if ratio in (0.2, 1.0, 5.0) and name in ("xi 0.5", "phi 1", "xi/eta/phi 0.5/0.5/3"):
                finest = discretised(ratio, creepages, 240)
                richardson = 2 * finest - np.array(reference_forces[f"{ratio:g} {name}"][grids[-1]])
                spot.append(f"| {ratio:g} | {name} | {np.abs(finest - reference[f'{ratio:g} {name}']).max():.4f} | "
                            f"{np.abs(richardson - reference[f'{ratio:g} {name}']).max():.4f} |")
                print(spot[-1], flush=True)
    lines = [f"## A. Discretised on {timed} x {timed} elements", "",
             f"Reference: Richardson ``2 F({grids[-1]}) - F({grids[-2]})``; its uncertainty (largest "
             f"|R({grids[-3]}, {grids[-2]}) - R({grids[-2]}, {grids[-1]})|) is {max(uncertainty):.4f}. "
             f"Errors over mu Fn (forces) and mu Fn c (moment), the largest of the three; 'pair' is "
             f"``2 F({timed}) - F({timed // 2})``; order from the last two differences over N = "
             f"{', '.join(map(str, grids))}.", "",
             f"- time per case at {timed} x {timed}: median {1e3 * np.median(times):.0f} ms, largest "
             f"{1e3 * max(times):.0f} ms over {len(times)} cases",
             f"- error at {timed} x {timed}: median {np.median(errors):.4f}, largest {max(errors):.4f}",
             f"- Richardson pair ({timed // 2}, {timed}): median {np.median(pair_errors):.4f}, largest "
             f"{max(pair_errors):.4f}",
             f"- convergence order: median {np.median(orders):.2f} (range {min(orders):.2f} .. {max(orders):.2f})",
             "", "| a/b | case | reference Fx / Fy / Mz | error | pair | order | ms |", "|---|---|---|---|---|---|---|",
             *rows, ""]
    if spot:
        lines += ["Spot check of the reference against 240 x 240 elements (F(240) and R(120, 240) minus the "
                  "reference):",
                  "", "| a/b | case | F(240) | R(120, 240) |", "|---|---|---|---|", *spot, ""]
    return reference, lines, {"times": times, "errors": errors, "pairs": pair_errors}


COST_CASES = ("xi 0.5", "phi 1", "xi/eta/phi 0.5/0.5/3")
COST_GRIDS = (15, 30, 60, 120)


def part_cost(matrix, quick):
    """Median time of one solve at N = 15 ... 120 on three a/b = 1 cases, and the exponent of N it grows with."""
    grids = COST_GRIDS[:3] if quick else COST_GRIDS
    chosen = [(name, ratio, creepages) for name, ratio, creepages in matrix if ratio == 1.0 and name in COST_CASES]
    rows, exponents = [], []
    for name, ratio, creepages in chosen:
        times = [common.median_time(lambda n=n, r=ratio, c=creepages: discretised(r, c, n), min_repeats=3,
                                    min_seconds=0.0) for n in grids]
        exponents.append(math.log(times[-1] / times[-2]) / math.log(grids[-1] / grids[-2]))
        rows.append(f"| {name} | " + " | ".join(f"{1e3 * t:.1f}" for t in times) + f" | {exponents[-1]:.2f} |")
        print(rows[-1], flush=True)
    return ["## Cost against the element count", "",
            f"Median time of one solve [ms] on N x N elements, a/b = 1; the exponent p of t ~ N^p between the two "
            f"finest grids: median {np.median(exponents):.2f}.", "",
            "| case | " + " | ".join(f"N = {n}" for n in grids) + " | p |", "|---|" + "---|" * (len(grids) + 1),
            *rows, ""]


def scene_of(ratio, creepages, **fields):
    from rollcontact.core.materials import Material
    from rollcontact.elliptic import EllipticScene

    a, b = axes(ratio)
    xi, eta, phi = creepages
    fields = {"friction": MU, **fields}
    return EllipticScene.from_semi_axes(LOAD, a, b, material=Material(YOUNG, NU), longitudinal_creepage=xi,
                                        lateral_creepage=eta, spin_creepage=phi, **fields)


def levels():
    """(label, method, options) of part B: every registered level with its defaults, and the discretised grids."""
    from rollcontact.elliptic.dispatch import METHODS as ELLIPTIC_METHODS

    out = [(name, name, {}) for name in sorted(ELLIPTIC_METHODS) if name != "discretised"]
    out += [("discretised 20", "discretised", {"elements": 20, "extrapolate": False}),
            ("discretised 60", "discretised", {"elements": 60, "extrapolate": False}),
            ("discretised 8/16 pair", "discretised", {"elements": 16, "extrapolate": True}),
            ("discretised 16/32 pair", "discretised", {"elements": 32, "extrapolate": True}),
            ("discretised 30/60 pair", "discretised", {"elements": 60, "extrapolate": True})]
    return out


def part_b(matrix, reference):
    """Each level's largest error per a/b and kind of case against the reference, and its median time."""
    from rollcontact.elliptic.dispatch import solve as solve_elliptic

    table, worst, timing = {}, {}, {}
    for label, method, options in levels():
        errors, times = {}, []
        for name, ratio, creepages in matrix:
            scene = scene_of(ratio, creepages)
            try:
                result = solve_elliptic(scene, method, **options)
            except ValueError as exc:  # a level that does not cover the scene
                print(f"{label}: {ratio:g} {name}: {exc}")
                continue
            t0 = time.perf_counter()
            solve_elliptic(scene, method, **options)
            times.append(time.perf_counter() - t0)
            error = np.abs(np.subtract(result.force_coefficients, reference[f"{ratio:g} {name}"]))
            key = (ratio, name.split()[0])
            errors[key] = np.maximum(errors.get(key, 0.0), error)
        table[label] = errors
        worst[label] = np.max(list(errors.values()), axis=0) if errors else np.full(3, np.nan)
        timing[label] = float(np.median(times)) if times else math.nan
        print(label, worst[label], timing[label], flush=True)
    kinds = ("xi", "eta", "phi", "xi/eta/phi")
    lines = ["## B. Each level against the reference", "",
             "Largest error over the case matrix, Fx / Fy (over mu Fn) / Mz (over mu Fn c), and the median time per "
             "case (one thread, the machine shared).  Anchors from the field's reference code on its own matrix: "
             "FASTSIM 0.037 / 0.081 / 0.047, FaStrip 0.019 / 0.080 / 0.041.", "",
             "| level | Fx | Fy | Mz | median time [ms] |", "|---|---|---|---|---|"]
    for label in table:
        lines.append(f"| {label} | " + " | ".join(f"{v:.4f}" for v in worst[label])
                     + f" | {1e3 * timing[label]:.2f} |")
    lines += ["", "Largest of the three errors per a/b and kind of case:", "",
              "| level | a/b | " + " | ".join(kinds) + " |", "|---|---|" + "---|" * len(kinds)]
    for label, errors in table.items():
        for ratio in sorted({r for r, _ in errors}):
            cells = [f"{errors[(ratio, k)].max():.4f}" if (ratio, k) in errors else "-" for k in kinds]
            lines.append(f"| {label} | {ratio:g} | " + " | ".join(cells) + " |")
    return lines + [""], table, {label: (float(worst[label].max()), timing[label]) for label in table}


TOLERANCES = (0.1, 0.05, 0.03, 0.01, 0.005)


def part_d(matrix, reference):
    """``solve_elliptic(scene, tolerance=t)`` over the matrix: what auto chooses, whether it meets t, its time."""
    from collections import Counter

    from rollcontact.elliptic.dispatch import solve as solve_elliptic

    rows, points = [], []
    for tolerance in TOLERANCES:
        chosen, errors, times = Counter(), [], []
        for name, ratio, creepages in matrix:
            scene = scene_of(ratio, creepages)
            result = solve_elliptic(scene, tolerance=tolerance)
            t0 = time.perf_counter()
            solve_elliptic(scene, tolerance=tolerance)
            times.append(time.perf_counter() - t0)
            errors.append(float(np.abs(np.subtract(result.force_coefficients,
                                                   reference[f"{ratio:g} {name}"])).max()))
            setting = result.info.get("setting") or {}
            detail = f" {setting.get('elements')}{' pair' if setting.get('extrapolate') else ''}" if setting else ""
            chosen[result.method + detail] += 1
        met = sum(e <= tolerance for e in errors)
        points.append((tolerance, float(np.median(times)), max(errors)))
        rows.append(f"| {tolerance:g} | {met} / {len(errors)} | {max(errors):.4f} | {1e3 * np.median(times):.2f} | "
                    + ", ".join(f"{k} ({v})" for k, v in chosen.most_common()) + " |")
        print(rows[-1], flush=True)
    return ["## D. auto with a tolerance", "",
            "``solve_elliptic(scene, tolerance=t)`` on every case of the matrix: the cases whose error against the "
            "reference meets t, the largest error, the median time per case and the settings chosen (with counts).",
            "", "| t | met | largest error | median time [ms] | chosen |", "|---|---|---|---|---|", *rows, ""], points


EUROSPRINTER = {"a": 6.3e-3, "b": 12.6e-3, "load": 106.7e3, "speed": 10.0}
POLACH = (0.55, 0.4, 0.6)
"""Polach's exponential law mu_s, A, B [s/m] (Polach 2005's dry Eurosprinter fit shape)."""


def part_c(quick):
    """Falling friction on the Eurosprinter: a creep curve by the discretised pair and by strips, when present."""
    from rollcontact.core.friction import ExponentialFalling
    from rollcontact.elliptic import EllipticScene
    from rollcontact.elliptic.dispatch import METHODS as ELLIPTIC_METHODS
    from rollcontact.elliptic.dispatch import solve as solve_elliptic

    law = ExponentialFalling(*POLACH)
    creeps = (0.001, 0.003, 0.006) if quick else (0.0005, 0.001, 0.002, 0.003, 0.005, 0.0075, 0.01, 0.02, 0.04,
                                                  0.08)
    e = EUROSPRINTER
    rows, gaps, curve, strip_curve = [], [], [], []
    for creep in creeps:
        scene = EllipticScene.from_semi_axes(e["load"], e["a"], e["b"], friction=law, rolling_speed=e["speed"],
                                             longitudinal_creepage=creep)
        reference = solve_elliptic(scene, "discretised", elements=32 if quick else 60, extrapolate=True)
        cells = [f"{reference.force_coefficients[0]:.4f}"]
        if "strips" in ELLIPTIC_METHODS:
            strips = solve_elliptic(scene, "strips")
            strip_curve.append(strips.force_coefficients[0])
            gaps.append(abs(strips.force_coefficients[0] - reference.force_coefficients[0]))
            cells += [f"{strips.force_coefficients[0]:.4f}", f"{gaps[-1]:.4f}"]
        else:
            cells += ["-", "-"]
        curve.append(reference.force_coefficients[0])
        rows.append(f"| {creep:g} | " + " | ".join(cells) + " |")
        print(rows[-1], flush=True)
    peak = int(np.argmax(curve))
    lines = ["## C. Falling friction on the Eurosprinter", "",
             f"a = {e['a'] * 1e3:g} mm, b = {e['b'] * 1e3:g} mm, Fn = {e['load'] / 1e3:g} kN, V = {e['speed']:g} m/s, "
             f"mu(v) = {POLACH[0]} ((1 - {POLACH[1]}) exp(-{POLACH[2]} v) + {POLACH[1]}); Fx over mu_s Fn.  The "
             f"curve peaks at xi = {creeps[peak]:g} and falls to {curve[-1] / curve[peak]:.3f} of the peak at "
             f"xi = {creeps[-1]:g}." + (f"  Largest strips - discretised gap: {max(gaps):.4f}." if gaps else ""),
             "", "| xi | discretised pair | strips | gap |", "|---|---|---|---|", *rows, ""]
    return lines, creeps, (curve, strip_curve)


def plot(table, creeps, curves, fronts, autos):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (left, middle, right) = plt.subplots(1, 3, figsize=(16, 4.4))
    for label, (error, seconds) in fronts.items():
        middle.loglog(seconds * 1e3, error, "o")
        middle.annotate(label, (seconds * 1e3, error), fontsize=7, xytext=(4, 2), textcoords="offset points")
    middle.loglog([1e3 * t for _, t, _ in autos], [e for _, _, e in autos], "k^-", label="auto(tolerance)")
    for tolerance, seconds, error in autos:
        middle.annotate(f"t={tolerance:g}", (seconds * 1e3, error), fontsize=7, xytext=(4, -9),
                        textcoords="offset points")
    middle.set_xlabel("median time per case [ms]")
    middle.set_ylabel("largest error over the matrix")
    middle.set_title("speed and accuracy of the 3D levels")
    middle.legend(fontsize=7)
    for label, errors in table.items():
        ratios = sorted({r for r, _ in errors})
        worst = [max(errors[(r, k)].max() for rr, k in errors if rr == r) for r in ratios]
        left.semilogy(ratios, worst, "o-", label=label)
    left.axhline(0.01, color="k", lw=0.8, ls="--")
    left.set_xscale("log")
    left.set_xticks(RATIOS, [f"{r:g}" for r in RATIOS])
    left.minorticks_off()
    left.set_xlabel("a/b")
    left.set_ylabel("largest error (Fx, Fy / mu Fn; Mz / mu Fn c)")
    left.set_title("levels against the converged discretised solution")
    left.legend(fontsize=7)
    right.semilogx(creeps, curves[0], "ko-", label="discretised 30/60 pair")
    if curves[1]:
        right.semilogx(creeps, curves[1], "C2s--", label="strips")
    right.legend(fontsize=8)
    right.set_xlabel("longitudinal creepage xi")
    right.set_ylabel("Fx / (mu_s Fn)")
    right.set_title("Eurosprinter, Polach's falling friction")
    fig.tight_layout()
    fig.savefig(common.RESULTS / "bench_elliptic.png", dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a/b = 1 only, coarse grids; nothing written")
    parser.add_argument("--levels-only", action="store_true",
                        help="parts B and C against the stored reference (results/bench_elliptic.json)")
    args = parser.parse_args()
    load = common.os.getloadavg()[0]
    started = time.perf_counter()
    matrix = cases((1.0,) if args.quick else RATIOS)
    stored = common.RESULTS / "bench_elliptic.json"
    if args.levels_only:
        reference = json.loads(stored.read_text())
        previous = (common.RESULTS / "bench_elliptic.md").read_text()
        end = previous.index("## Cost") if "## Cost" in previous else None
        lines_a = previous[previous.index("## A."):end]
        lines_a = lines_a.rstrip("\n").split("\n") + [""]
    else:
        reference, lines_a, _ = part_a(matrix, args.quick)
        if not args.quick:
            stored.write_text(json.dumps(reference, indent=1) + "\n")
    lines_cost = part_cost(matrix, args.quick)
    lines_b, table, fronts = part_b(matrix, reference)
    lines_d, autos = part_d(matrix, reference)
    lines_c, creeps, curves = part_c(args.quick)
    lines = ["# Elliptic (3D) contact: levels against the converged discretised solution", "",
             *common.machine(load), "", f"Case matrix of {len(matrix)} cases (module docstring); study took "
             f"{time.perf_counter() - started:.0f} s.", "", *lines_a, *lines_cost, *lines_b, *lines_d, *lines_c]
    common.publish(lines, "bench_elliptic.md", args.quick)
    if not args.quick:
        plot(table, creeps, curves, fronts, autos)


if __name__ == "__main__":
    main()
