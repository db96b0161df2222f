"""Command line ``python -m rollcontact``: solves TOML scenes, prints each result and, with ``--csv PATH``, writes
them as CSV with the units in the header (:data:`CSV_COLUMNS`)."""

from __future__ import annotations

import argparse
import csv
import sys

import numpy as np

from rollcontact import METHODS, SceneError, load_scene, solve

DESCRIPTION = "Solve rolling-contact scenes (TOML files) and print the contact force and geometry of each."

EPILOG = """\
Quantities are in SI units; forces are per length of the line contact [N/m].
The scene format is described in models/README.md.

example:
  python -m rollcontact models/carter.toml --creep-curve --csv carter.csv
"""

CSV_COLUMNS = (
    ("scene_file", None), ("scene", None), ("case", None), ("method", None), ("success", None),
    ("normal_load_per_length", "N/m"), ("creep", "1"), ("tangential_force_per_length", "N/m"),
    ("traction_coefficient", "1"), ("contact_half_width", "m"), ("contact_offset", "m"),
    ("stick_half_width", "m"), ("max_pressure", "Pa"), ("creep_stiffness_per_length", "N/m"),
)
"""Columns of ``--csv``: name and SI unit (None: a text column); the header reads ``name [unit]``.  ``case`` is
``scene`` for the scene's own creep and ``creep curve`` for the points of ``--creep-curve``; numbers are written
with every digit (``repr``), so they read back as the same floats."""


def describe(result) -> str:
    rows = [
        ("method", result.method, ""),
        ("success", result.success, result.message),
        ("normal load per length N'", f"{result.normal_load_per_length:.6g}", "N/m"),
        ("creep xi", f"{result.creep:.6g}", "1"),
        ("tangential force per length T'", f"{result.tangential_force_per_length:.6g}", "N/m"),
        ("traction coefficient T'/N'", f"{result.traction_coefficient:.6g}", "1"),
        ("contact half-width a", f"{result.contact_half_width:.6g}", "m"),
        ("contact offset Delta", f"{result.contact_offset:.6g}", "m"),
        ("stick half-width a*", f"{result.stick_half_width:.6g}", "m"),
        ("max pressure", f"{result.max_pressure:.6g}", "Pa"),
        ("creep stiffness dT'/dxi", f"{result.creep_stiffness_per_length:.6g}", "N/m"),
    ]
    return "\n".join(f"  {name:<32} {value!s:>14}  {unit}" for name, value, unit in rows)


def csv_header() -> list[str]:
    """The CSV header: ``name [unit]`` of every :data:`CSV_COLUMNS` entry (the name alone for text)."""
    return [name if unit is None else f"{name} [{unit}]" for name, unit in CSV_COLUMNS]


def csv_row(path: str, scene_name: str, case: str, result) -> list[str]:
    """One CSV row of ``result`` (:data:`CSV_COLUMNS`)."""
    given = {"scene_file": path, "scene": scene_name, "case": case, "method": result.method,
             "success": str(bool(result.success))}
    return [given[name] if unit is None else repr(float(getattr(result, name))) for name, unit in CSV_COLUMNS]


def parser() -> argparse.ArgumentParser:
    """The command line's options (``--help`` shows them with their units and an example)."""
    p = argparse.ArgumentParser(prog="python -m rollcontact", description=DESCRIPTION, epilog=EPILOG,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scenes", nargs="+", metavar="SCENE.toml", help="scene files (format: models/README.md)")
    p.add_argument("--method", default="auto",
                   help=f"method: auto (the cheapest that applies, default) or one of {', '.join(sorted(METHODS))}")
    p.add_argument("--creep-curve", action="store_true",
                   help="also print the traction coefficient T'/N' [1] at 11 creeps xi [1] from 0 to 1.5 mu a/R "
                        "(a: contact half-width [m], R: radius [m])")
    p.add_argument("--csv", metavar="PATH",
                   help="also write every result as CSV to PATH, one row per solve, units in the header "
                        "(e.g. 'tangential_force_per_length [N/m]')")
    return p


def main(argv=None) -> int:
    args = parser().parse_args(argv)
    status = 0
    rows = []
    for path in args.scenes:
        try:
            scene = load_scene(path)
            result = solve(scene, method=args.method)
        except (SceneError, ValueError) as exc:
            print(f"{path}: error: {exc}", file=sys.stderr)
            status = 2
            continue
        print(f"{path} ({scene.name}):\n{describe(result)}")
        rows.append(csv_row(path, scene.name, "scene", result))
        status = status or (0 if result.success else 1)
        if args.creep_curve:
            mu = scene.friction_coefficient
            a = result.contact_half_width
            for xi in np.linspace(0.0, 1.5 * mu * a / scene.radius, 11):
                r = solve(scene.replace(creep=float(xi)), method=args.method)
                print(f"    xi = {xi:10.4e}   T'/N' = {r.traction_coefficient:8.5f}   ({r.method})")
                rows.append(csv_row(path, scene.name, "creep curve", r))
    if args.csv:
        try:
            with open(args.csv, "w", newline="") as fh:
                writer = csv.writer(fh)
                writer.writerow(csv_header())
                writer.writerows(rows)
        except OSError as exc:
            print(f"--csv {args.csv}: error: {exc}", file=sys.stderr)
            return 2
        print(f"csv: {args.csv} ({len(rows)} rows)")
    return status


if __name__ == "__main__":
    sys.exit(main())
