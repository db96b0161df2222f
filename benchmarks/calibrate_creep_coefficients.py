"""Kalker's creepage coefficients C11, C22, C23, C33 from the discretised 3D solver at vanishing creepage.

Run: ``python benchmarks/calibrate_creep_coefficients.py [--quick] [--write-table]`` (about ten minutes; ``--quick``:
three aspect ratios, nu = 0.25, about ten seconds).  Writes ``benchmarks/results/creep_coefficients.md``; with
``--write-table`` also the data module ``src/rollcontact/elliptic/creep_table.py`` that
:mod:`rollcontact.elliptic.creep_coefficients` interpolates.  ``--end-rows`` (about two minutes) writes
``benchmarks/results/creep_coefficients_end_rows.md`` instead: Kalker's end rows a/b = 0.1 and 10 by a second
discretisation (below) beside the table and the published values.

Method.  At a creepage of 1e-9 no element slips and the tangential problem is linear (Kalker's linear theory):
``Fx = G c^2 C11 xi``, ``Fy = G c^2 (C22 eta + c C23 phi)``, ``Mz = G c^4 C33 phi`` (forces on the rail, c =
sqrt(ab); :mod:`rollcontact.core.halfspace.rolling`).  Each coefficient is computed on square elements, N of them
across the shorter axis (N = 24, 32, 48, 64, 96; beyond Kalker's rows, a/b above 10 or below 0.1, the largest five of
16 and these that the surface grid holds along the longer axis, :func:`levels_for`), and

* scaled by the ratio of the ellipse's area ``pi a b`` to the area of the elements whose centres lie inside it,
  to the power of the coefficient's length dimension over two (1 for C11 and C22, 3/2 for C23, 2 for C33): the
  staircase outline's area fluctuates from grid to grid, and this removes most of the fluctuation it causes;
* extrapolated to zero element size by a least-squares line in h = 1/N through the levels (the convergence
  is first order); the spread to a quadratic fit is reported as the extrapolation's uncertainty.

Kalker's published values (Kalker 1990, Table E.3, all its rows: g = a/b and g = b/a from 0.1 to 1) are compared where
they exist; the rows beyond them (g down to 1/30: a flange's ellipse reaches a/b 20 and more) are compared with the
power law that continued the table from its end rows before they were computed.  At Kalker's end rows (a/b = 0.1
and 10) a second discretisation checks the table: elements shaped as the ellipse (the same count N along both axes,
so each element has the ellipse's aspect ratio, N up to :data:`END_LEVELS`' last), extrapolated the same way.
"""

import argparse
import math
import textwrap
import time

import common  # before numpy: limits BLAS to one thread
import numpy as np

from rollcontact.core.friction import Coulomb
from rollcontact.core.halfspace.rolling import ellipse_grid, hertz_pressure, solve_steady, total_forces
from rollcontact.core.halfspace.surface import operator_for

LEVELS = (24, 32, 48, 64, 96)
"""Elements across the shorter axis of the ellipse, square elements."""


END_LEVELS = (64, 96, 128, 192, 256, 384)
"""Elements along each axis of the second discretisation of the end rows (``--end-rows``)."""


SHORT = (0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
BEYOND = (1.0 / 30.0, 0.04, 0.05, 1.0 / 15.0, 0.08)
ASPECT_RATIOS = tuple(sorted({*(round(g, 6) for g in (*BEYOND, *SHORT)),
                              *(round(1.0 / g, 6) for g in (*BEYOND, *SHORT))}))
"""a/b of the table: g = a/b and g = b/a over Kalker's rows 0.1 ... 1, and beyond them to 1/30 (a flange's ellipse
reaches a/b 20 and more)."""

GRID_ELEMENTS = 1000
"""Most elements along the longer axis of a level (the surface grid takes at most 1024 with its margins)."""


def levels_for(ratio: float) -> tuple[int, ...]:
    """The element counts across the shorter axis for a/b = ``ratio``: :data:`LEVELS`, or beyond a/b = 10 (and below
    0.1) the five largest of 16 and :data:`LEVELS` that the grid holds (three at a/b 30)."""
    longer = max(ratio, 1.0 / ratio)
    return tuple([n for n in (16, *LEVELS) if n * longer <= GRID_ELEMENTS][-5:])


POISSON_RATIOS = (0.0, 0.25, 0.5)


KALKER_ROWS = {  # g = 0.1 .. 1: (C11, C22, C23 at nu = 0, 0.25, 0.5) for a/b = g, then for a/b = 1/g; Kalker 1990, E.3
    0.1: ((2.51, 3.31, 4.85, 2.51, 2.52, 2.53, 0.334, 0.473, 0.731),
          (10.7, 11.7, 12.9, 10.7, 12.8, 16.0, 12.2, 14.6, 18.0)),
    0.2: ((2.59, 3.37, 4.81, 2.59, 2.63, 2.66, 0.483, 0.603, 0.809),
          (6.96, 7.78, 8.82, 6.96, 8.14, 9.79, 5.72, 6.63, 7.89)),
    0.3: ((2.68, 3.44, 4.80, 2.68, 2.75, 2.81, 0.607, 0.715, 0.889),
          (5.57, 6.34, 7.34, 5.57, 6.40, 7.51, 3.79, 4.32, 5.01)),
    0.4: ((2.78, 3.53, 4.82, 2.78, 2.88, 2.98, 0.720, 0.823, 0.977),
          (4.84, 5.57, 6.57, 4.84, 5.48, 6.31, 2.88, 3.24, 3.70)),
    0.5: ((2.88, 3.62, 4.83, 2.88, 3.01, 3.14, 0.827, 0.929, 1.07),
          (4.37, 5.10, 6.11, 4.37, 4.90, 5.56, 2.35, 2.62, 2.96)),
    0.6: ((2.98, 3.72, 4.91, 2.98, 3.14, 3.31, 0.930, 1.03, 1.18),
          (4.06, 4.78, 5.80, 4.06, 4.50, 5.04, 2.01, 2.23, 2.50)),
    0.7: ((3.09, 3.81, 4.97, 3.09, 3.28, 3.48, 1.03, 1.14, 1.29),
          (3.82, 4.54, 5.58, 3.82, 4.21, 4.67, 1.76, 1.95, 2.18)),
    0.8: ((3.19, 3.91, 5.05, 3.19, 3.41, 3.65, 1.13, 1.25, 1.40),
          (3.65, 4.36, 5.42, 3.65, 3.99, 4.39, 1.58, 1.75, 1.94)),
    0.9: ((3.29, 4.01, 5.12, 3.29, 3.54, 3.82, 1.23, 1.36, 1.51),
          (3.51, 4.22, 5.30, 3.51, 3.81, 4.16, 1.44, 1.59, 1.77)),
    1.0: ((3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63),
          (3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63)),
}

KALKER = {ratio: {nu: row[k::3] for k, nu in enumerate(POISSON_RATIOS)}
          for g, rows in KALKER_ROWS.items() for ratio, row in ((g, rows[0]), (round(1.0 / g, 6), rows[1]))}
"""a/b (the table's keys): {nu: (C11, C22, C23)}, Kalker 1990, Table E.3, all its rows."""


CREEPAGE = 1e-9
"""Small enough that no element slips (checked)."""


def level(ratio: float, nu: float, n: int, shaped: bool = False) -> np.ndarray:
    """(C11, C22, C23, C33) on square elements, n across the shorter axis, area-corrected (module docstring); with
    ``shaped`` on n x n elements of the ellipse's aspect ratio."""
    a, b = math.sqrt(ratio), 1.0 / math.sqrt(ratio)  # c = 1, G = 1, Fn = 1, mu = 1
    elements = (n, n) if shaped else (round(n * max(1.0, ratio)), round(n * max(1.0, 1.0 / ratio)))
    grid = ellipse_grid(a, b, elements)
    op = operator_for(grid, nu)
    pressure = hertz_pressure(grid, a, b, 1.0)
    x, y = grid.mesh()
    e = CREEPAGE
    forces = []
    for xi, eta, phi in ((e, 0.0, 0.0), (0.0, e, 0.0), (0.0, 0.0, e)):
        sol = solve_steady(op, pressure, (xi - phi * y, eta + phi * x), 1.0, Coulomb(1.0), tolerance=1e-10)
        if not sol.converged or not sol.stick[pressure > 0].all():
            raise RuntimeError(f"a/b = {ratio}, nu = {nu}, n = {n}: {sol.message}, "
                               f"{int((~sol.stick & (pressure > 0)).sum())} elements slip")
        forces.append(total_forces(grid, sol.traction_x, sol.traction_y))
    raw = np.array([forces[0][0], forces[1][1], forces[2][1], forces[2][2]]) / e
    area_ratio = math.pi * a * b / (np.count_nonzero(pressure) * grid.area)
    return raw * area_ratio ** np.array([1.0, 1.0, 1.5, 2.0])


def extrapolated(ratio: float, nu: float, levels=None, shaped: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """The coefficients at zero element size (linear least squares in h = 1/N) and |linear - quadratic fit|; the levels
    :func:`levels_for` the ratio by default."""
    levels = levels_for(ratio) if levels is None else levels
    values = np.array([level(ratio, nu, n, shaped) for n in levels])
    h = 1.0 / np.asarray(levels, dtype=float)
    linear = np.linalg.lstsq(np.vstack([np.ones_like(h), h]).T, values, rcond=None)[0][0]
    quadratic = np.linalg.lstsq(np.vstack([np.ones_like(h), h, h * h]).T, values, rcond=None)[0][0]
    return linear, np.abs(linear - quadratic)


def table_module(table: dict) -> str:
    """The text of ``src/rollcontact/elliptic/creep_table.py`` for ``table[(ratio, nu)] = (C11, C22, C23, C33)``."""
    lines = ['"""Kalker\'s creepage coefficients as a table: the data behind '
             ':mod:`rollcontact.elliptic.creep_coefficients`.',
             "",
             "Written by ``benchmarks/calibrate_creep_coefficients.py --write-table`` (do not edit by hand): the "
             "discretised",
             "3D solver (:mod:`rollcontact.core.halfspace.rolling`) at vanishing creepage, extrapolated to zero "
             "element size;",
             "the script's results file ``benchmarks/results/creep_coefficients.md`` compares them with Kalker 1990, "
             "Table E.3.",
             "Layout:",
             "``ASPECT_RATIOS`` (a/b, increasing), ``POISSON_RATIOS`` (increasing), and for each coefficient a tuple "
             "per aspect",
             "ratio of values per Poisson ratio.",
             '"""',
             "",
             'SOURCE = "discretised 3D solver at vanishing creepage (benchmarks/calibrate_creep_coefficients.py)"',
             "",
             *textwrap.wrap(f"ASPECT_RATIOS = {tuple(ASPECT_RATIOS)!r}", 116, subsequent_indent=" " * 17),
             '"""a/b [1] of the rows."""',
             "",
             f"POISSON_RATIOS = {tuple(POISSON_RATIOS)!r}",
             '"""nu [1] of the columns."""',
             ""]
    for k, name in enumerate(("C11", "C22", "C23", "C33")):
        rows = [f"({', '.join(f'{table[(g, nu)][k]:.4f}' for nu in POISSON_RATIOS)})" for g in ASPECT_RATIOS]
        lines.append(f"{name} = ({rows[0]},")
        lines += [f"       {row}," for row in rows[1:-1]]
        lines.append(f"       {rows[-1]})")
        lines.append("")
    return "\n".join(lines[:-1]) + "\n"


def end_rows(quick: bool) -> None:
    """Kalker's end rows by elements shaped as the ellipse, beside the table (square elements) and Kalker's values."""
    from rollcontact.elliptic.creep_coefficients import creepage_coefficients

    load = common.os.getloadavg()[0]
    started = time.perf_counter()
    lines = ["# Kalker's creepage coefficients: the end rows by a second discretisation", "", *common.machine(load),
             "", f"Elements shaped as the ellipse, N x N with N = {', '.join(map(str, END_LEVELS))}, staircase area "
             "corrected, extrapolated linearly in 1/N ('shaped', with |linear - quadratic fit| as 'spread'); "
             "'table': the square elements of `creep_coefficients.md` (the library's table); Kalker 1990, Table E.3.",
             "", "| a/b | nu | coefficient | shaped | spread | table | shaped / table - 1 [%] | Kalker | "
             "table / Kalker - 1 [%] |", "|---|---|---|---|---|---|---|---|---|"]
    rows = [(g, nu) for g in (0.1, 10.0) for nu in POISSON_RATIOS]
    for g, nu in rows[:1] if quick else rows:
        shaped, spread = extrapolated(g, nu, END_LEVELS[:3] if quick else END_LEVELS, shaped=True)
        k = creepage_coefficients(g, nu)
        for j, (name, table) in enumerate((("C11", k.c11), ("C22", k.c22), ("C23", k.c23))):
            published = KALKER[g][nu][j]
            lines.append(f"| {g:g} | {nu:g} | {name} | {shaped[j]:.4f} | {spread[j]:.4f} | {table:.4f} | "
                         f"{100 * (shaped[j] / table - 1):+.2f} | {published:.3g} | "
                         f"{100 * (table / published - 1):+.2f} |")
    lines += ["", f"Computed in {time.perf_counter() - started:.0f} s."]
    common.publish(lines, "creep_coefficients_end_rows.md", quick)


def main():
    from rollcontact.elliptic.creep_coefficients import creepage_coefficients

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a/b 0.5, 1, 2 at nu = 0.25 only; nothing written")
    parser.add_argument("--write-table", action="store_true", help="also write src/rollcontact/elliptic/creep_table.py")
    parser.add_argument("--end-rows", action="store_true",
                        help="only the end rows a/b 0.1 and 10 by elements shaped as the ellipse")
    parser.add_argument("--beyond", action="store_true",
                        help="only the rows beyond Kalker's (a/b below 0.1, above 10); with --write-table the table "
                             "keeps the rows it holds within Kalker's")
    args = parser.parse_args()
    if args.end_rows:
        end_rows(args.quick)
        return
    ratios = (0.5, 1.0, 2.0) if args.quick else ASPECT_RATIOS
    if args.beyond:
        ratios = (20.0,) if args.quick else tuple(g for g in ASPECT_RATIOS if not 0.1 <= g <= 10.0)
    nus = (0.25,) if args.quick else POISSON_RATIOS
    load = common.os.getloadavg()[0]
    started = time.perf_counter()
    table, spread = {}, {}
    for g in ratios:
        for nu in nus:
            table[(g, nu)], spread[(g, nu)] = extrapolated(g, nu)
    title = "beyond Kalker's rows" if args.beyond else "from the discretised 3D solver"
    lines = [f"# Kalker's creepage coefficients {title}", "", *common.machine(load), "",
             f"Square elements, N = {', '.join(map(str, LEVELS))} across the shorter axis (beyond a/b = 10 and "
             f"below 0.1 the five largest of 16 and these that fit {GRID_ELEMENTS} elements along the longer axis: "
             "three at a/b 30), staircase area corrected, extrapolated linearly in 1/N "
             "(benchmarks/calibrate_creep_coefficients.py); 'spread' is |linear - quadratic fit|. "
             f"Computed in {time.perf_counter() - started:.0f} s.", ""]
    if not args.beyond:
        lines += ["## Against Kalker 1990, Table E.3", "",
                  "| a/b | nu | C11 | Kalker | dev % | C22 | Kalker | dev % | C23 | Kalker | dev % |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        deviations = []
        for g, by_nu in sorted(KALKER.items()):
            for nu, published in by_nu.items():
                if (g, nu) not in table:
                    continue
                cells = []
                for k in range(3):
                    deviation = 100.0 * (table[(g, nu)][k] / published[k] - 1.0)
                    deviations.append(abs(deviation))
                    cells += [f"{table[(g, nu)][k]:.3f}", f"{published[k]:.3g}", f"{deviation:+.2f}"]
                lines.append(f"| {g:g} | {nu:g} | " + " | ".join(cells) + " |")
        worst = max(deviations, default=0.0)
        within = sum(d <= 1.0 for d in deviations)
        lines += ["", f"Largest deviation from the published values: {worst:.2f} %; within 1 %: {within} of "
                  f"{len(deviations)}.", ""]
    lines += ["## The table", "", "Beyond Kalker's rows (a/b below 0.1 and above 10) the last column compares the row "
              "with the power law through the library's end rows of Kalker's range (each log C linear in log(a/b) "
              "through a/b 10 and 6.67, 0.1 and 0.15), which would continue his table without these rows: the "
              "largest |power law / row - 1| over the four coefficients.", "",
              "| a/b | nu | C11 | C22 | C23 | C33 | largest spread | largest relative spread | power law [%] |",
              "|---|---|---|---|---|---|---|---|---|"]
    for (g, nu), values in table.items():
        beyond = ""
        if not 0.1 <= g <= 10.0:
            first, second = (10.0, 10.0 / 1.5) if g > 1.0 else (0.1, 0.15)
            end, inner = (np.array(creepage_coefficients(r, nu)) for r in (first, second))
            law = end * (end / inner) ** (math.log(g / first) / math.log(first / second))
            beyond = f"{100.0 * float(np.max(np.abs(law / values - 1.0))):.2f}"
        lines.append(f"| {g:g} | {nu:g} | " + " | ".join(f"{v:.4f}" for v in values)
                     + f" | {spread[(g, nu)].max():.4f} | {float(np.max(spread[(g, nu)] / values)):.2%} | {beyond} |")
    if args.beyond:
        common.publish(lines, "creep_coefficients_beyond.md", args.quick)
    else:
        common.publish(lines, "creep_coefficients.md", args.quick)
    if args.write_table and not args.quick:
        if args.beyond:  # the table's rows within Kalker's, as they are
            from rollcontact.elliptic import creep_table

            for k, g in enumerate(creep_table.ASPECT_RATIOS):
                if 0.1 <= g <= 10.0:
                    for j, nu in enumerate(POISSON_RATIOS):
                        table[(g, nu)] = tuple(column[k][j] for column in (creep_table.C11, creep_table.C22,
                                                                           creep_table.C23, creep_table.C33))
        path = common.ROOT / "src" / "rollcontact" / "elliptic" / "creep_table.py"
        path.write_text(table_module(table))
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
