"""The Manchester Contact Benchmark's case A-2.2 at every wheel/rail level, against the discretised level.

Run: ``python benchmarks/wheelrail_manchester.py [--quick] [--dry]``.  Writes
``benchmarks/results/wheelrail_manchester.md`` and ``wheelrail_manchester.png`` (``--dry``: the dry-rail scene at
30 m/s, ``wheelrail_manchester_dry.md``).

The scene ``models/wheelrail/manchester_a22.toml`` (21 positions, S1002 on UIC60, 10 kN per wheel, mu 0.3) is solved
by each level (``strips``, ``hertz``, and the reference ``discretised``).  Tables:

A. Per level, the largest differences of its patches from the discretised level's (matched by their rigid contact
   points): normal force and peak pressure [%], Fx, Fy over mu Fn and Mz over mu Fn c (c = sqrt(area/pi) of the
   reference patch), with the level's largest error estimate beside them; the largest difference over the
   estimate calibrates ``rollcontact.wheelrail.methods.hertz.GAP_ERROR`` (Hertz's departure term).
B. Per level, the median and largest time per wheelset (both wheels), in process, and the ratio of the medians to
   the strips': each position solved :data:`ROUNDS` times by every level in turn, its time the median of its rounds
   (a noisy machine's outliers).
C. The discretised level's patches per position: contact angle, rolling radius, normal force, peak pressure, force
   coefficients, the patch count (the jumps of the contact point).
D. How the strips' normal solutions were reached (``normal_start`` of their patch results: Newton's method from
   Hertz's ellipse, from the first pass, from a start, with a lobe joined, or the placements) at the scene's loads and
   at :data:`HEAVY` times them, counted over the positions' patches.

The figure shows the discretised pressure of the right wheel's patch centred, near the flange root and in flange
contact.
"""

from __future__ import annotations

import argparse
import collections
import math
import statistics
import time
from pathlib import Path

import common  # before numpy: limits BLAS to one thread
import numpy as np

from rollcontact.wheelrail.dispatch import solve
from rollcontact.wheelrail.scene import cases_from_dict

ROOT = Path(__file__).resolve().parents[1]
SCENES = {False: ROOT / "models" / "wheelrail" / "manchester_a22.toml",
          True: ROOT / "models" / "wheelrail" / "manchester_a22_dry.toml"}
LEVELS = ("strips", "hertz")
ROUNDS = 3
"""Rounds of the timing (section B)."""
HEAVY = 8.0
"""Load factor of section D's heavy wheels: 80 kN on the scene's 10 kN, the axle of
``benchmarks/bench_wheelset_contact.py``, where the gap towards the flange root flattens into a shelf near the
approach."""
SHAPES = (1, 11, 15)
"""Cases whose right-wheel pressure the figure shows: centred, near the flange root, in flange contact."""


def load(dry: bool):
    import sys

    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib
    path = SCENES[dry]
    with open(path, "rb") as fh:
        return cases_from_dict(tomllib.load(fh), path.parent, name=path.stem)


def timed(scene, method: str) -> float:
    """Seconds of one solve."""
    started = time.perf_counter()
    solve(scene, method)
    return time.perf_counter() - started


def matched(patches, reference):
    """Pairs of (patch, reference patch) with the nearest rigid contact points on the rail."""
    out = []
    for p in patches:
        q = min(reference, key=lambda r: abs(r.point.rail_lateral - p.point.rail_lateral), default=None)
        if q is not None and abs(q.point.rail_lateral - p.point.rail_lateral) < 2e-3:
            out.append((p, q))
    return out


def differences(p, q):
    """(normal force %, peak pressure %, |dFx|, |dFy| over mu Fn, |dMz| over mu Fn c) of patch p against q."""
    a, b = p.result, q.result
    scale = b.friction_coefficient * b.normal_load
    c = math.sqrt(b.area / math.pi) if b.area > 0 else math.nan
    return (100 * abs(a.normal_load / b.normal_load - 1), 100 * abs(a.max_pressure / b.max_pressure - 1),
            abs(a.longitudinal_force - b.longitudinal_force) / scale, abs(a.lateral_force - b.lateral_force) / scale,
            abs(a.spin_moment - b.spin_moment) / (scale * c))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="every fourth position; results not written")
    parser.add_argument("--dry", action="store_true", help="the dry-rail scene at 30 m/s")
    args = parser.parse_args()
    cases = load(args.dry)
    if args.quick:
        cases = cases[::4]
    print(f"# The Manchester case A-2.2 ({'dry rail, 30 m/s' if args.dry else 'Coulomb 0.3, 2 m/s'}) at every "
          "wheel/rail level\n")
    reference = {fields["case"]: solve(scene, "discretised") for fields, scene in cases}
    print("## A. Differences from the discretised level (largest over the positions and patches)\n")
    print("| level | patches | normal force [%] | peak pressure [%] | Fx / (mu Fn) | Fy / (mu Fn) | Mz / (mu Fn c) | "
          "largest estimate | largest difference / estimate |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name in LEVELS:
        worst, estimate, ratio, count = np.zeros(5), 0.0, 0.0, 0
        for fields, scene in cases:
            result = solve(scene, name)
            ref = reference[fields["case"]]
            if not (result.success and ref.success):
                why = result.message if not result.success else ref.message
                print(f"| {name} | case {fields['case']} failed: {why} |")
                continue
            for wheel, ref_wheel in zip(result.wheels, ref.wheels, strict=True):
                for p, q in matched(wheel.patches, ref_wheel.patches):
                    d = np.array(differences(p, q))
                    worst = np.maximum(worst, d)
                    count += 1
                    e = p.result.info.get("error_estimate", math.nan)
                    estimate = max(estimate, e)
                    ratio = max(ratio, max(d[2:]) / e if e > 0 else math.nan)
        print(f"| {name} | {count} | {worst[0]:.2f} | {worst[1]:.2f} | {worst[2]:.3f} | {worst[3]:.3f} | "
              f"{worst[4]:.3f} | {estimate:.3f} | {ratio:.2f} |")
    print("\nHertz's patches are its ellipses, one per contact point: where a patch has two lobes, the ellipse of each "
          "lobe is matched to the reference patch of its point.\n")
    rounds = {name: [[] for _ in cases] for name in (*LEVELS, "discretised")}
    for _ in range(ROUNDS):
        for k, (_, scene) in enumerate(cases):
            for name in rounds:
                rounds[name][k].append(timed(scene, name))
    times = {name: [statistics.median(r) for r in per_case] for name, per_case in rounds.items()}
    print(f"## B. Time per wheelset (both wheels), in process (the median of {ROUNDS} rounds per position)\n")
    print("| level | median [ms] | largest [ms] | median / strips' |")
    print("|---|---|---|---|")
    strips = statistics.median(times["strips"])
    for name in (*LEVELS, "discretised"):
        print(f"| {name} | {statistics.median(times[name]) * 1e3:.1f} | {max(times[name]) * 1e3:.1f} | "
              f"{statistics.median(times[name]) / strips:.1f} |")
    print("\n## C. The discretised level's patches (right wheel, then left)\n")
    print("| case | shift [mm] | wheel | patches | angle [rad] | radius [m] | N [N] | p0 [MPa] | Fx/(mu N) | "
          "Fy/(mu N) | Mz/(mu N c) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for fields, _ in cases:
        ref = reference[fields["case"]]
        for wheel in reversed(ref.wheels):
            for k, p in enumerate(wheel.patches):
                fx, fy, mz = p.result.force_coefficients
                print(f"| {fields['case']} | {fields['lateral_shift'] * 1e3:.1f} | {wheel.side} | "
                      f"{len(wheel.patches) if k == 0 else ''} | {p.point.contact_angle:.4f} | "
                      f"{p.point.rolling_radius:.5f} | {p.result.normal_load:.0f} | "
                      f"{p.result.max_pressure / 1e6:.0f} | "
                      f"{fx:.3f} | {fy:.3f} | {mz:.3f} |")
    starts_section(cases)
    if not args.quick:
        figure(cases, args.dry)


def starts_section(cases) -> None:
    """Section D: the strips' patches counted by ``normal_start``, at the scene's loads and at :data:`HEAVY` times
    them."""
    counts = {}
    for factor in (1.0, HEAVY):
        counted = collections.Counter()
        for _, scene in cases:
            loaded = scene.replace(vertical_load_left=factor * scene.vertical_load_left,
                                   vertical_load_right=factor * scene.vertical_load_right)
            result = solve(loaded, "strips")
            for wheel in result.wheels:
                counted.update(p.result.info.get("normal_start", "") or "(none)" for p in wheel.patches)
        counts[factor] = counted
    names = sorted(set().union(*counts.values()))
    print("\n## D. How the strips' normal solutions were reached (patches of all positions)\n")
    print("| loads | " + " | ".join(names) + " |")
    print("|---|" + "---:|" * len(names))
    for factor, counted in counts.items():
        print(f"| {factor:g} x the scene's | " + " | ".join(str(counted[n]) for n in names) + " |")
    print("\nhertz: Newton's method from Hertz's ellipse over the deepest part of each rigid run; first pass: from the "
          "first pass's lobes; resumed: from the wheel's previous normal solution (its second pass); lobe joined: the "
          "placements went on from that solution with a lobe where the surfaces still interpenetrated; placements: "
          "the fixed point on the first pass's lobes, then Newton's method.")


def figure(cases, dry: bool) -> None:
    """The discretised pressure of the right wheel's patch at :data:`SHAPES`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    chosen = [(f, s) for f, s in cases if f["case"] in SHAPES]
    fig, axes = plt.subplots(1, len(chosen), figsize=(4.0 * len(chosen), 3.6))
    for ax, (fields, scene) in zip(np.atleast_1d(axes), chosen, strict=True):
        result = solve(scene, "discretised", fields=True)
        patch = result.right.patches[0].result
        f = patch.fields
        shown = ax.scatter(f.y * 1e3, f.x * 1e3, c=f.pressure / 1e6, s=3, cmap="viridis")
        ax.set_title(f"case {fields['case']}: {fields['lateral_shift'] * 1e3:.1f} mm, "
                     f"angle {result.right.patches[0].point.contact_angle:.2f} rad", fontsize=9)
        ax.set_xlabel("s [mm]")
        ax.set_ylabel("x [mm]")
        ax.set_aspect("equal")
        fig.colorbar(shown, ax=ax, label="p [MPa]")
    fig.tight_layout()
    name = "wheelrail_manchester_dry.png" if dry else "wheelrail_manchester.png"
    fig.savefig(common.RESULTS / name, dpi=110)
    print(f"\n![The right wheel's patches](./{name})")


if __name__ == "__main__":
    import sys

    if "--dry" in sys.argv:
        common.run_and_publish(main, "wheelrail_manchester_dry.md")
    else:
        common.run_and_publish(main, "wheelrail_manchester.md")
