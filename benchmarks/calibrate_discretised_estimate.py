"""Calibration of error estimates of the discretised solver: the a-priori bound and a two-grid a-posteriori estimate.

Run as ``.venv/bin/python benchmarks/calibrate_discretised_estimate.py`` (about a minute, one BLAS thread).  Prints
markdown tables; asserts nothing.

Error: the larger relative error of T' and of the peak pressure p0 (the contract of ``solve(scene, tolerance=t)``).
Estimates compared with it, for each element count n of ``DISCRETISED_ELEMENTS``:

* bound: ``DiscretisedAccuracy.error``, ``max(c w/n, 3 (w/n)^2)`` with ``c = DISCRETISED_FORCE_ERROR`` (w the
  automatic window over the Hertz width 2a);
* two-grid: ``SAFETY * max_c max(|T'_n/T'_c - 1|, |p0_n/p0_c - 1|)`` over two coarse solves c of n/2 elements on
  the same window, one of them shifted by one fine element (so its edges fall elsewhere within the coarse
  elements): option (a) of the study, cost 1/4 to 1/2 of the solve;
* shift spread: ``|T'_n / T'_n(window shifted by h/2) - 1|``, how much the answer at n itself moves when the grid
  moves by half an element.  No estimate computed from this grid and coarser ones can tell the placement it got,
  so none can certify an error below this spread.

References: Hertz/Carter closed forms; the polynomial method at tolerance 1e-12 (512 slip nodes for velocity-dependent
friction) where it applies; for split contacts, which only the discretised solver treats, the first-order Richardson
extrapolation ``2 T_4000 - T_2000`` of discretised solves on a window fitted to the patches, each the mean over
:data:`REFERENCE_PLACEMENTS` grid placements (``rollcontact.line.methods.discretised.steady.extrapolated``); its
uncertainty u is the change from ``T_4000`` and an estimate counts as a bound only when it is >= error + u.

Table C calibrates the extrapolated setting (``solve_discretised(..., extrapolate=m)``, :func:`extrapolated`): T'
from n and 2n elements on a window fitted to the patches, each level the mean over m placements, for m = 2, 4, 8,
16, against the same references; ``m c = err m n / w`` with w the fitted window over 2a (the placement mean's
first-order residue falls like 1/m), and the model's bound (``EXTRAPOLATED_FORCE_ERROR``, on the automatic
window, which is at least as long).  Its error is erratic in n, so on the worst case (the split contact near full
stick) n also runs densely from 50 to 400 (:data:`DENSE_ELEMENTS`) for the m auto offers.

Hertz/Carter cases use a fixed window (the automatic one of N' = 1 MN/m) for three loads, so the patch edges fall
at different positions within the elements (with the automatic window, which scales with a, they would not).

What it prints goes to ``benchmarks/results/discretised_estimate.md`` with the machine (not after ``--quick``).
"""

import math
import statistics
import time

import common  # noqa: F401  (before numpy: limits BLAS to one thread)

import rollcontact as rc
from rollcontact.line.carter import carter
from rollcontact.line.halfspace.grid import automatic_grid
from rollcontact.line.halfspace.solver import contact_window
from rollcontact.line.hertz import hertz
from rollcontact.line.methods.discretised.accuracy import (
    DISCRETISED_FORCE_ERROR,
    EXTRAPOLATED_FORCE_ERROR,
    EXTRAPOLATION_PLACEMENTS,
    DiscretisedAccuracy,
)
from rollcontact.line.methods.discretised.steady import DISCRETISED_ELEMENTS, extrapolated, solve_discretised

SAFETY = 3.0  # factor of the two-grid estimate: the largest error / raw difference measured here is 2.52
RADIUS = 0.46
MU = 0.3
ESTAR = rc.Material().contact_modulus
LOAD = 1e6
WINDOW = (lambda g: (g.x_min, g.x_max))(automatic_grid(rc.Scene(LOAD)))
STRUCTURED_ELEMENTS = (50, 100, 200, 400)  # velocity-dependent friction: n = 800 takes ~1 s
REFERENCE_ELEMENTS = (2000, 4000)  # split contacts: extrapolated from these, its uncertainty from half as many
REFERENCE_PLACEMENTS = 8
EXTRAPOLATED_ELEMENTS = (50, 100, 200, 400, 800)  # n of the pairs n/2n of table C (velocity-dependent: to 200)
PLACEMENT_COUNTS = (2, 4, 8, 16)
DENSE_ELEMENTS = range(50, 401, 7)  # table C's dense n on the worst case
DENSE_CASE = ("20 um, x_c = 4.5 mm", "xi = 0.01 sat")  # label parts of the split contact near full stick


def corrugated(wavelength, amplitude, axis, creep=1e-3):
    return rc.Scene(LOAD, creep=creep, axis_position=axis,
                    surface=rc.Surface(harmonics=(rc.Harmonic.from_wavelength(wavelength, amplitude),)))


def cases():
    """(label, scene, window or None for the automatic one)."""
    out = []
    for load in (0.6e6, 1e6, 1.7e6):
        saturation = MU * hertz(load, RADIUS, ESTAR)[0] / RADIUS
        for fraction in (0.01, 0.1, 0.5, 0.95, -0.3, -0.8):
            scene = rc.Scene(load, creep=fraction * saturation)
            out.append((f"Carter N' = {load / 1e6:.1f} MN/m, xi = {fraction:+.2f} sat", scene, WINDOW))
    a_h = hertz(LOAD, RADIUS, ESTAR)[0]
    saturation = MU * a_h / RADIUS
    # creep 1e-3 = 0.68 of saturation; the relative T' error is largest at small creep (near full stick)
    for wavelength, amplitude, axis, creep in ((0.04, 20e-6, 0.003, 1e-3), (0.04, 20e-6, 0.003, 0.01 * saturation),
                                               (0.02, 5e-6, 0.003, 1e-3), (0.01, 20e-6, 0.0, 1e-3),
                                               (0.01, 10e-6, 0.0045, 1e-3), (0.01, 20e-6, 0.0045, 1e-3),
                                               (0.01, 20e-6, 0.0045, 0.1 * saturation),
                                               (0.01, 20e-6, 0.0045, 0.01 * saturation),
                                               (0.01, 20e-6, 0.0045, 0.001 * saturation)):
        label = f"corrugation {wavelength * 1e3:.0f} mm / {amplitude * 1e6:.0f} um, x_c = {axis * 1e3:.1f} mm, " \
                f"k a = {2 * math.pi * a_h / wavelength:.2f}, xi = {creep / saturation:.3g} sat"
        out.append((label, corrugated(wavelength, amplitude, axis, creep), None))
    for creep in (1e-3, 0.01 * saturation):
        out.append((f"quartic profile, xi = {creep / saturation:.3g} sat",
                    rc.Scene(LOAD, creep=creep, surface=rc.Surface(polynomial=(0, 0, 0, 0, -2e4))), None))
    falling = rc.Scene(LOAD, creep=0.3 * saturation, rolling_speed=20.0, friction=rc.ExponentialFalling(MU, 0.4, 3.0))
    out.append(("exponential falling mu, B = 3 s/m, V = 20 m/s", falling, None))
    return out


def reference(scene):
    """(T', p0, how, relative uncertainty of T')."""
    if scene.surface.is_flat and scene.friction.is_constant:
        return (carter(scene.normal_load_per_length, scene.creep, RADIUS, ESTAR, MU)[0],
                hertz(scene.normal_load_per_length, RADIUS, ESTAR)[1], "closed form", 0.0)
    poly = rc.solve(scene, method="polynomial", truncation=1e-12, nodes=512)
    if poly.success:
        return poly.tangential_force_per_length, poly.max_pressure, "polynomial 1e-12", 0.0
    ref = extrapolated(scene, REFERENCE_ELEMENTS, REFERENCE_PLACEMENTS)
    half = extrapolated(scene, tuple(n // 2 for n in REFERENCE_ELEMENTS), REFERENCE_PLACEMENTS)
    return (ref.tangential_force_per_length, ref.max_pressure,
            f"Richardson discretised {REFERENCE_ELEMENTS[0]}/{REFERENCE_ELEMENTS[1]}, "
            f"{REFERENCE_PLACEMENTS} placements",
            relative(half.tangential_force_per_length, ref.tangential_force_per_length))


def relative(a, b):
    return abs(a / b - 1.0)


def two_grid(scene, result):
    """Raw two-grid difference (without SAFETY) of a result on its grid, or NaN when a coarse solve fails."""
    grid = result.info["grid"]
    h = grid.element_width
    worst = 0.0
    for shift in (0.0, h):
        coarse = solve_discretised(scene, elements=grid.elements // 2, window=(grid.x_min + shift, grid.x_max + shift))
        if not coarse.success:
            return math.nan
        worst = max(worst, relative(result.tangential_force_per_length, coarse.tangential_force_per_length),
                    relative(result.max_pressure, coarse.max_pressure))
    return worst


def extrapolated_rows(label, scene, force, pressure, uncertainty, model):
    """Table C rows: (label, n, m, error, u, m c, bound or NaN, time [s])."""
    rows = []
    lo, hi = contact_window(scene)
    width = (hi - lo) / (2.0 * hertz(scene.normal_load_per_length, RADIUS, ESTAR)[0])
    sizes = EXTRAPOLATED_ELEMENTS if scene.friction.is_constant else EXTRAPOLATED_ELEMENTS[:3]
    runs = [(n, m) for n in sizes for m in PLACEMENT_COUNTS]
    if all(part in label for part in DENSE_CASE):
        runs += [(n, m) for m in EXTRAPOLATION_PLACEMENTS for n in DENSE_ELEMENTS if n not in sizes]
    for n, m in runs:
        t0 = time.perf_counter()
        result = solve_discretised(scene, elements=n, extrapolate=m)
        elapsed = time.perf_counter() - t0
        if not result.success:
            continue
        error = max(relative(result.tangential_force_per_length, force), relative(result.max_pressure, pressure))
        bound = model.error(scene, {"elements": n, "extrapolate": m})
        force_error = relative(result.tangential_force_per_length, force)
        rows.append((label, n, m, error, uncertainty, force_error * m * n / width, bound, elapsed))
    return rows


def main():
    start = time.perf_counter()
    model = DiscretisedAccuracy()
    rows = []
    table_c = []
    for label, scene, window in cases():
        force, pressure, how, uncertainty = reference(scene)
        if not label.startswith("Carter") or "N' = 1.0" in label:  # the fitted window scales with a: loads alike
            table_c += extrapolated_rows(label, scene, force, pressure, uncertainty, model)
        sizes = DISCRETISED_ELEMENTS if scene.friction.is_constant else STRUCTURED_ELEMENTS
        for n in sizes:
            if n < model.resolution(scene):
                continue
            result = solve_discretised(scene, elements=n, window=window)
            if not result.success:
                continue
            grid = result.info["grid"]
            error = max(relative(result.tangential_force_per_length, force), relative(result.max_pressure, pressure))
            options = {"elements": n} if window is None else {"elements": n, "window": window}
            bound = model.error(scene, options)
            estimate = SAFETY * two_grid(scene, result)
            shifted = solve_discretised(scene, elements=n, window=(grid.x_min + 0.5 * grid.element_width,
                                                                   grid.x_max + 0.5 * grid.element_width))
            spread = relative(result.tangential_force_per_length, shifted.tangential_force_per_length)
            half_width = hertz(scene.normal_load_per_length, RADIUS, ESTAR)[0]
            coefficient = relative(result.tangential_force_per_length, force) * 2.0 * half_width * n / grid.length
            rows.append((label, how, n, error, uncertainty, estimate, bound, spread, coefficient))
        print(f"<!-- {label}: {time.perf_counter() - start:.0f} s -->", flush=True)
    print(f"\nTwo-grid estimate (SAFETY = {SAFETY:g}) and a-priori bound (c = {DISCRETISED_FORCE_ERROR:g}) against "
          "the true error of T' and p0.  u: the reference's uncertainty (0 for exact references).\n")
    print("| case | reference | n | error | u | two-grid estimate | estimate / error | bound | bound / error | "
          "shift spread | c = err_T' n / w |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for label, how, n, error, u, estimate, bound, spread, coefficient in rows:
        print(f"| {label} | {how} | {n} | {error:.2e} | {u:.1e} | {estimate:.2e} | {estimate / error:.2f} | "
              f"{bound:.2e} | {bound / error:.2f} | {spread:.1e} | {coefficient:.2f} |")
    print("\n## Summary\n")
    for name, column in (("two-grid estimate", 5), ("a-priori bound", 6)):
        ratios = [row[column] / row[3] for row in rows if math.isfinite(row[column])]
        misses = [row for row in rows if not row[column] >= row[3] + row[4]]
        print(f"* {name}: estimate / error min {min(ratios):.2f}, median {statistics.median(ratios):.2f}, "
              f"max {max(ratios):.3g} over {len(ratios)} results; below error + u: "
              + (", ".join(f"{r[0]} n = {r[2]} ({r[column]:.2e} < {r[3]:.2e} + {r[4]:.1e})" for r in misses)
                 or "none"))
    print(f"* largest first-order coefficient c = err_T' n / w: {max(row[8] for row in rows):.2f} "
          f"(the a-priori bound uses {DISCRETISED_FORCE_ERROR:g})")
    print(f"* shift spread over error: median {statistics.median(r[7] / r[3] for r in rows):.2f}, "
          f"max {max(r[7] / r[3] for r in rows):.2f}")
    print("\n## C. Extrapolated settings: n/2n, each level the mean over m placements\n")
    print("| case | n/2n | m | error | u | m c = err_T' m n / w | bound | bound / error | time [ms] |")
    print("|---|---|---|---|---|---|---|---|---|")
    for label, n, m, error, u, c, bound, elapsed in table_c:
        print(f"| {label} | {n}/{2 * n} | {m} | {error:.2e} | {u:.1e} | {c:.3f} | {bound:.2e} | {bound / error:.2f} | "
              f"{elapsed * 1e3:.0f} |")
    print()
    for m in PLACEMENT_COUNTS:
        picked = [r for r in table_c if r[2] == m]
        worst = max(picked, key=lambda r: r[5])
        print(f"* m = {m}: largest m c = {worst[5]:.3g} ({worst[0]}, n = {worst[1]}), median "
              f"{statistics.median(r[5] for r in picked):.3g} over {len(picked)} results")
    bounded = [r for r in table_c if math.isfinite(r[6])]
    misses = [r for r in bounded if not r[6] >= r[3] + r[4]]
    print(f"* bound max({EXTRAPOLATED_FORCE_ERROR:g} w/(m n), 3 (w/2n)^2) on the automatic window: bound / error "
          f"min {min(r[6] / r[3] for r in bounded):.2f}, median {statistics.median(r[6] / r[3] for r in bounded):.2f} "
          f"over {len(bounded)} results; below error + u: "
          + (", ".join(f"{r[0]} n = {r[1]}, m = {r[2]} ({r[6]:.2e} < {r[3]:.2e} + {r[4]:.1e})" for r in misses)
             or "none"))
    print(f"\n{len(rows) + len(table_c)} results in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    common.run_and_publish(main, "discretised_estimate.md")
