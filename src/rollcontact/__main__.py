"""Command line: ``python -m rollcontact SCENE.toml [--method M] [--creep-curve]`` solves a scene and prints it."""

from __future__ import annotations

import argparse
import sys

import numpy as np

from rollcontact import METHODS, SceneError, load_scene, solve


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


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m rollcontact", description=__doc__)
    parser.add_argument("scenes", nargs="+", help="TOML scene files (see models/README.md)")
    parser.add_argument("--method", default="auto", help=f"auto or one of {sorted(METHODS)}")
    parser.add_argument("--creep-curve", action="store_true", help="also print T'/N' over a creep sweep")
    args = parser.parse_args(argv)
    status = 0
    for path in args.scenes:
        try:
            scene = load_scene(path)
            result = solve(scene, method=args.method)
        except (SceneError, ValueError) as exc:
            print(f"{path}: error: {exc}", file=sys.stderr)
            status = 2
            continue
        print(f"{path} ({scene.name}):\n{describe(result)}")
        status = status or (0 if result.success else 1)
        if args.creep_curve:
            mu = scene.friction_coefficient
            a = result.contact_half_width
            for xi in np.linspace(0.0, 1.5 * mu * a / scene.radius, 11):
                r = solve(scene.replace(creep=float(xi)), method=args.method)
                print(f"    xi = {xi:10.4e}   T'/N' = {r.traction_coefficient:8.5f}   ({r.method})")
    return status


if __name__ == "__main__":
    sys.exit(main())
