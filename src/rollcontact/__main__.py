"""Command line ``python -m rollcontact``: solves TOML scenes of every geometry (line, elliptic, wheel/rail), prints
each result and, with ``--csv PATH``, writes them as CSV.

A scene file names its geometry in ``[scene] geometry`` (``"line"`` when absent; formats in ``models/README.md`` and
``models/wheelrail/README.md``).  The CSV is written before anything is printed, so it is complete whatever happens
to standard output (a pipe into ``head`` closes it early: the rest of the printout is dropped, the exit code kept).
"""

from __future__ import annotations

import argparse
import csv
import os
import sys
from pathlib import Path

import numpy as np

from rollcontact.core.checks import SceneError
from rollcontact.elliptic.dispatch import METHODS as ELLIPTIC_METHODS
from rollcontact.elliptic.dispatch import solve as solve_elliptic
from rollcontact.elliptic.scene import scene_from_dict as elliptic_scene
from rollcontact.line.dispatch import METHODS, solve
from rollcontact.line.scene import scene_from_dict as line_scene
from rollcontact.wheelrail.dispatch import METHODS as WHEELRAIL_METHODS
from rollcontact.wheelrail.dispatch import solve as solve_wheelrail
from rollcontact.wheelrail.geometry import GeometryError
from rollcontact.wheelrail.profiles import ProfileError
from rollcontact.wheelrail.scene import cases_from_dict

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

DESCRIPTION = "Solve rolling-contact scenes (TOML files) and print the contact force and geometry of each."

EPILOG = """\
Quantities are in SI units; the line contact's forces are per length of the line [N/m], the elliptic and
wheel/rail contacts' forces [N] and moments [N m] are those the wheel exerts on the rail.
Scene formats: models/README.md (line, elliptic), models/wheelrail/README.md (wheel/rail).

examples:
  python -m rollcontact models/carter.toml --creep-curve --csv carter.csv
  python -m rollcontact models/wheelrail/manchester_a22.toml --csv a22.csv --method strips
"""

CSV_COLUMNS = (
    ("scene_file", None), ("scene", None), ("case", None), ("method", None), ("success", None),
    ("normal_load_per_length", "N/m"), ("creep", "1"), ("tangential_force_per_length", "N/m"),
    ("traction_coefficient", "1"), ("contact_half_width", "m"), ("contact_offset", "m"),
    ("stick_half_width", "m"), ("max_pressure", "Pa"), ("creep_stiffness_per_length", "N/m"),
)
"""Columns of ``--csv`` for line scenes: name and SI unit (None: a text column); the header reads ``name [unit]``.
``case`` is ``scene`` for the scene's own creep and ``creep curve`` for the points of ``--creep-curve``; numbers are
written with every digit (``repr``), so they read back as the same floats."""

ELLIPTIC_COLUMNS = (
    ("scene_file", None), ("scene", None), ("case", None), ("method", None), ("success", None),
    ("normal_load", "N"), ("longitudinal_creepage", "1"), ("lateral_creepage", "1"), ("spin_creepage", "1/m"),
    ("longitudinal_force", "N"), ("lateral_force", "N"), ("spin_moment", "N.m"), ("a", "m"), ("b", "m"),
    ("max_pressure", "Pa"),
)
"""Columns of ``--csv`` for elliptic scenes (the forces and moment of the wheel on the rail)."""

WHEELRAIL_COLUMNS = (
    "case", "lateral_shift", "yaw", "wheel", "patch", "normal_force", "contact_angle", "rolling_radius",
    "rail_lateral_position", "longitudinal_creepage", "lateral_creepage", "spin_creepage", "longitudinal_force",
    "lateral_force", "spin_moment", "max_pressure", "length", "width", "method", "wheel_force_x", "wheel_force_y",
    "wheel_force_z",
)
"""Columns of ``--csv`` for wheel/rail scenes, one row per case, wheel and patch (patches by decreasing normal force),
in SI units without unit suffixes (``models/wheelrail/README.md`` states each one's unit and axes): the contact plane's
creepages, forces and moment of the wheel on the rail, the wheel's forces on its rail in track axes."""


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


def describe_elliptic(result) -> str:
    rows = [("method", result.method, ""), ("success", result.success, result.message),
            ("normal load Fn", f"{result.normal_load:.6g}", "N"),
            ("creepages xi, eta", f"{result.longitudinal_creepage:.4g}, {result.lateral_creepage:.4g}", "1"),
            ("spin phi", f"{result.spin_creepage:.6g}", "1/m"),
            ("longitudinal force Fx", f"{result.longitudinal_force:.6g}", "N"),
            ("lateral force Fy", f"{result.lateral_force:.6g}", "N"),
            ("spin moment Mz", f"{result.spin_moment:.6g}", "N m"),
            ("semi-axes a, b", f"{result.a:.4g}, {result.b:.4g}", "m"),
            ("max pressure", f"{result.max_pressure:.6g}", "Pa")]
    return "\n".join(f"  {name:<32} {value!s:>14}  {unit}" for name, value, unit in rows)


def describe_wheelrail(fields: dict, result) -> str:
    lines = [f"  case {fields['case']}: lateral shift {fields['lateral_shift'] * 1e3:.4g} mm, yaw "
             f"{fields['yaw'] * 1e3:.4g} mrad: {result.method}, success {result.success}"]
    if not result.success:
        lines.append(f"    {result.message}")
    for wheel in result.wheels:
        lines.append(f"    {wheel.side:<5} Fx {wheel.force[0]:10.5g} N  Fy {wheel.force[1]:10.5g} N  "
                     f"Fz {wheel.force[2]:10.5g} N  ({len(wheel.patches)} patch(es))")
        for k, patch in enumerate(wheel.patches, start=1):
            r = patch.result
            lines.append(f"      patch {k}: N {r.normal_load:9.5g} N, angle {patch.point.contact_angle:7.4f} rad, "
                         f"r {patch.point.rolling_radius:.6g} m, Fx {r.longitudinal_force:9.5g} N, Fy "
                         f"{r.lateral_force:9.5g} N, Mz {r.spin_moment:9.4g} N m, p0 {r.max_pressure:.4g} Pa")
    return "\n".join(lines)


def csv_header() -> list[str]:
    """The line scenes' CSV header: ``name [unit]`` of every :data:`CSV_COLUMNS` entry (the name alone for text)."""
    return [name if unit is None else f"{name} [{unit}]" for name, unit in CSV_COLUMNS]


def csv_row(path: str, scene_name: str, case: str, result, columns=CSV_COLUMNS) -> dict:
    """One CSV row of a line or elliptic ``result`` (keys: the header's names)."""
    given = {"scene_file": path, "scene": scene_name, "case": case, "method": result.method,
             "success": str(bool(result.success))}
    return {name if unit is None else f"{name} [{unit}]":
            given[name] if unit is None else repr(float(getattr(result, name))) for name, unit in columns}


def wheelrail_rows(fields: dict, result) -> list[dict]:
    """The CSV rows of a wheel/rail case (:data:`WHEELRAIL_COLUMNS`): one per wheel and patch."""
    rows = []
    for wheel in result.wheels:
        for k, patch in enumerate(wheel.patches, start=1):
            r, point = patch.result, patch.point
            values = {"case": fields["case"], "lateral_shift": fields["lateral_shift"], "yaw": fields["yaw"],
                      "wheel": wheel.side, "patch": k, "normal_force": r.normal_load,
                      "contact_angle": point.contact_angle, "rolling_radius": point.rolling_radius,
                      "rail_lateral_position": point.rail_lateral, "longitudinal_creepage": r.longitudinal_creepage,
                      "lateral_creepage": r.lateral_creepage, "spin_creepage": r.spin_creepage,
                      "longitudinal_force": r.longitudinal_force, "lateral_force": r.lateral_force,
                      "spin_moment": r.spin_moment, "max_pressure": r.max_pressure, "length": r.length,
                      "width": r.width, "method": r.method, "wheel_force_x": wheel.force[0],
                      "wheel_force_y": wheel.force[1], "wheel_force_z": wheel.force[2]}
            rows.append({key: repr(float(v)) if isinstance(v, float) else str(v) for key, v in values.items()})
    return rows


def parser() -> argparse.ArgumentParser:
    """The command line's options (``--help`` shows them with their units and examples)."""
    p = argparse.ArgumentParser(prog="python -m rollcontact", description=DESCRIPTION, epilog=EPILOG,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scenes", nargs="+", metavar="SCENE.toml", help="scene files (formats: models/README.md)")
    p.add_argument("--method", default="auto",
                   help=f"method: auto (the cheapest that applies, default) or a level of the scene's geometry: "
                        f"line {', '.join(sorted(METHODS))}; elliptic {', '.join(sorted(ELLIPTIC_METHODS))}; "
                        f"wheel/rail {', '.join(sorted(WHEELRAIL_METHODS))}")
    p.add_argument("--creep-curve", action="store_true",
                   help="line scenes: also print the traction coefficient T'/N' [1] at 11 creeps xi [1] from 0 to "
                        "1.5 mu a/R (a: contact half-width [m], R: radius [m])")
    p.add_argument("--csv", metavar="PATH",
                   help="also write every result as CSV to PATH, one row per solve (line: units in the header, "
                        "e.g. 'tangential_force_per_length [N/m]'; wheel/rail: one row per case, wheel and patch)")
    return p


class Output:
    """What the command prints: lines collected while solving and printed after the CSV is written; a closed
    standard output (a pipe's reader gone) drops the rest of the printout, nothing else."""

    def __init__(self):
        self.lines: list[str] = []

    def say(self, text: str) -> None:
        self.lines.append(text)

    def flush(self) -> None:
        try:
            for line in self.lines:
                print(line)
            sys.stdout.flush()
        except BrokenPipeError:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())  # the interpreter's own flush at exit must not fail either


def solve_file(path: str, args, out: Output, tables: dict) -> int:
    """Solve the scene file ``path``: its printout to ``out``, its CSV rows to ``tables[kind]``; the exit status
    (0 every solve succeeded, 1 one failed, 2 the file could not be read or solved)."""
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except (OSError, tomllib.TOMLDecodeError) as exc:
        print(f"{path}: error: cannot read scene file: {exc}", file=sys.stderr)
        return 2
    geometry = str(data.get("scene", {}).get("geometry", "line"))
    try:
        if geometry == "wheelrail":
            cases = cases_from_dict(data, Path(path).resolve().parent, name=Path(path).stem)
            status = 0
            out.say(f"{path} ({cases[0][1].name}, wheel/rail, {len(cases)} case(s)):")
            for fields, scene in cases:
                result = solve_wheelrail(scene, method=args.method)
                out.say(describe_wheelrail(fields, result))
                tables.setdefault("wheelrail", []).extend(wheelrail_rows(fields, result))
                status = status or (0 if result.success else 1)
            return status
        if geometry == "elliptic":
            scene = elliptic_scene(data, name=Path(path).stem)
            result = solve_elliptic(scene, method=args.method)
            out.say(f"{path} ({scene.name}, elliptic):\n{describe_elliptic(result)}")
            tables.setdefault("elliptic", []).append(csv_row(path, scene.name, "scene", result, ELLIPTIC_COLUMNS))
            return 0 if result.success else 1
        if geometry != "line":
            raise SceneError(f"[scene] geometry = {geometry!r} is not one of 'line', 'elliptic', 'wheelrail'")
        meta = {k: v for k, v in data.get("scene", {}).items() if k != "geometry"}
        scene = line_scene({**data, "scene": meta}, name=Path(path).stem)
        result = solve(scene, method=args.method)
    except (SceneError, ProfileError, GeometryError, ValueError, TypeError) as exc:
        print(f"{path}: error: {exc}", file=sys.stderr)
        return 2
    out.say(f"{path} ({scene.name}):\n{describe(result)}")
    tables.setdefault("line", []).append(csv_row(path, scene.name, "scene", result))
    status = 0 if result.success else 1
    if args.creep_curve:
        mu = scene.friction_coefficient
        a = result.contact_half_width
        for xi in np.linspace(0.0, 1.5 * mu * a / scene.radius, 11):
            r = solve(scene.replace(creep=float(xi)), method=args.method)
            out.say(f"    xi = {xi:10.4e}   T'/N' = {r.traction_coefficient:8.5f}   ({r.method})")
            tables["line"].append(csv_row(path, scene.name, "creep curve", r))
    return status


def write_csv(path: str, tables: dict) -> int:
    """Write the rows of every geometry solved to ``path`` (the columns of the first geometry, then the others'
    new ones); the number of rows."""
    header = []
    for kind in ("line", "elliptic", "wheelrail"):
        for row in tables.get(kind, ()):
            header += [key for key in row if key not in header]
    rows = [row for kind in ("line", "elliptic", "wheelrail") for row in tables.get(kind, ())]
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=header or csv_header(), restval="")
        writer.writeheader()
        writer.writerows(rows)
    return len(rows)


def main(argv=None) -> int:
    args = parser().parse_args(argv)
    status = 0
    out = Output()
    tables: dict[str, list[dict]] = {}
    for path in args.scenes:
        code = solve_file(path, args, out, tables)
        status = max(status, code) if code == 2 else (status or code)
    if args.csv:
        try:
            count = write_csv(args.csv, tables)
        except OSError as exc:
            out.flush()
            print(f"--csv {args.csv}: error: {exc}", file=sys.stderr)
            return 2
        out.say(f"csv: {args.csv} ({count} rows)")
    out.flush()
    return status


if __name__ == "__main__":
    sys.exit(main())
