"""Wheel/rail contact geometry from real profiles on the Manchester benchmark's S1002 wheel and UIC60 rail (1:40,
gauge 1435 mm at 14 mm, flange-back spacing 1360 mm, r0 460 mm): where the contact points lie and jump, the
contact-geometry functions, the equivalent conicity, the contact table's interpolation error, and the time of each.

Run: ``python benchmarks/wheelrail_geometry.py`` (``--quick``: fewer shifts and repeats, a table at one yaw,
nothing written).  Prints markdown tables and writes ``benchmarks/results/wheelrail_geometry.md`` and three PNGs:

A. Case A-2.2 per wheel at the benchmark's poses (its lateral shift, yaw and prescribed roll): the contact points
   and patches of each wheel, the deepest point's rolling radius, contact angle, positions on rail and wheel and
   longitudinal shift; the zone (tread, flange root, flange) and where the right wheel's contact jumps; the roll of
   the rigid wheelset whose wheels carry 10 kN each with Hertz's normal law, against the prescribed roll.
B. The rigid wheelset's contact-geometry functions over the lateral shift at zero yaw (the jumps, Delta r, contact
   angles), the equivalent conicity against the amplitude (harmonic linearisation and Klingel's integration), and
   the smoothing's effect (the default against none) on the case's contact radii and angles.
C. The contact table: nodes, jumps, and the largest interpolation error of each quantity against direct searches
   at points between the nodes, at zero yaw and over yaw.
D. Times (medians and 10th percentiles): a contact search per wheel, with the patch gap, with Hertz's
   normal solve for 10 kN; the rigid and loaded wheelset positions; a table lookup; the equivalent conicity at 3 mm.
E. Hertz's load at the search's prepared approach (DEFAULT_DEPTH) on the tread and on the flange.

Figures: ``wheelrail_contact_positions.png`` (both profiles, a line joining the contact points for each shift),
``wheelrail_conicity.png`` (Delta r and the equivalent conicity against amplitude), ``wheelrail_contact_angle.png``
(contact angles over the shift).  BLAS is limited to one thread; the machine is shared: medians, one run.
"""

import argparse
import csv
import time

import common  # before numpy: limits BLAS to one thread
import numpy as np

from rollcontact.core.materials import Material
from rollcontact.elliptic.hertz import hertz_ellipse
from rollcontact.wheelrail.conicity import QUANTITIES, ContactTable, contact_functions, equivalent_conicity
from rollcontact.wheelrail.geometry import Pose, Track, Wheelset
from rollcontact.wheelrail.normal import loaded_position, rigid_position, solve_normal
from rollcontact.wheelrail.profiles import read_simpack
from rollcontact.wheelrail.search import DEFAULT_DEPTH, search_wheel

DATA = common.ROOT / "models" / "wheelrail"


def setup(smoothing=None):
    wheel = read_simpack(DATA / "profiles" / "MBench_S1002_v3.prw", smoothing)
    rail = read_simpack(DATA / "profiles" / "MBench_UIC60_v3.prr", smoothing)
    return Track(rail, 1.435, 0.014, 0.0), Wheelset(wheel, 0.46, 1.360, 0.070)


def cases():
    with open(DATA / "manchester_a22.csv") as fh:
        return [(float(r["lateral_shift_mm"]) * 1e-3, float(r["yaw_rad"]), float(r["roll_rad"]))
                for r in csv.DictReader(fh)]


def zone(delta):
    return "tread" if delta < 0.2 else ("flange root" if delta < 0.7 else "flange")


def part_a(track, wheelset):
    lines = ["## A. Case A-2.2 per wheel at the benchmark's poses", "",
             "Deepest contact point of each wheel (mirror-symmetric: angles positive towards the flange, positions in "
             "each profile's own axes). pts/patches: contact points within the search's depth and the patches they "
             "form. Loaded roll: the rigid wheelset carrying 10 kN per wheel with Hertz's law.", "",
             "| y [mm] | yaw [mrad] | wheel | pts | patches | zone | r [mm] | delta [rad] | y rail [mm] | y wheel [mm] "
             "| x shift [mm] | 2nd point: delta, gap [um] |",
             "|---:|---:|---|---:|---:|---|---:|---:|---:|---:|---:|---|"]
    roll_lines = ["", "| y [mm] | prescribed roll [rad] | loaded roll, Hertz [rad] | difference [rad] |",
                  "|---:|---:|---:|---:|"]
    zones = []
    for y, yaw, roll in cases():
        pose = Pose(y, yaw, roll)
        for side in ("left", "right"):
            c = search_wheel(track, wheelset, pose, side)
            p = c.points[0]
            second = "" if len(c.points) < 2 else (f"{c.points[1].contact_angle:.4f}, "
                                                   f"{(c.points[1].gap - p.gap) * 1e6:.1f}")
            lines.append(f"| {y * 1e3:.1f} | {yaw * 1e3:.1f} | {side} | {len(c.points)} | {len(c.patches)} | "
                         f"{zone(p.contact_angle)} | {p.rolling_radius * 1e3:.3f} | {p.contact_angle:.4f} | "
                         f"{p.rail_lateral * 1e3:.2f} | {p.wheel_lateral * 1e3:.2f} | "
                         f"{p.longitudinal_shift * 1e3:.2f} | {second} |")
            if side == "right":
                zones.append((y, zone(p.contact_angle)))
        loaded, _, _ = loaded_position(track, wheelset, y, yaw, 1e4, 1e4)
        roll_lines.append(f"| {y * 1e3:.1f} | {roll:.8f} | {loaded.roll:.8f} | {loaded.roll - roll:+.2e} |")
    jumps = [f"{zones[k - 1][0] * 1e3:.1f} -> {zones[k][0] * 1e3:.1f} mm ({zones[k - 1][1]} to {zones[k][1]})"
             for k in range(1, len(zones)) if zones[k][1] != zones[k - 1][1]]
    return lines + ["", "Right wheel's jumps: " + "; ".join(jumps) + "."] + roll_lines + [""]


def part_b(track, wheelset, quick):
    shifts = np.linspace(-0.01, 0.01, 41 if quick else 201)
    f = contact_functions(track, wheelset, shifts)
    lines = ["## B. Contact-geometry functions of the rigid wheelset (zero yaw)", "",
             "Jumps of the contact point (bisected to 0.1 um): " + ", ".join(f"{j * 1e3:+.4f} mm" for j in f.jumps)
             + ".", "", "| y [mm] | Delta r [mm] | roll [mrad] | delta left | delta right | r right [mm] |",
             "|---:|---:|---:|---:|---:|---:|"]
    for y in (0.0, 0.001, 0.002, 0.003, 0.004, 0.005, 0.006, 0.007, 0.008, 0.009, 0.010):
        v = {name: float(np.interp(y, f.shift, f[name])) for name in QUANTITIES}
        lines.append(f"| {y * 1e3:.0f} | {v['radius_difference'] * 1e3:.4f} | {v['roll'] * 1e3:.4f} | "
                     f"{v['left_contact_angle']:.4f} | {v['right_contact_angle']:.4f} | "
                     f"{v['right_rolling_radius'] * 1e3:.3f} |")
    amps = np.arange(0.5, 8.01, 0.5) * 1e-3 if not quick else np.array([1e-3, 3e-3, 6e-3])
    wide = contact_functions(track, wheelset, np.linspace(-0.01, 0.01, 81 if quick else 401))
    harmonic = [equivalent_conicity(track, wheelset, a, functions=wide) for a in amps]
    klingel = [equivalent_conicity(track, wheelset, a, "klingel", functions=wide) for a in amps]
    lines += ["", "Equivalent conicity (EN 15302's principle; harmonic linearisation and Klingel's integration of "
              "the nonlinear kinematic oscillation):", "", "| amplitude [mm] | harmonic | Klingel |",
              "|---:|---:|---:|"]
    lines += [f"| {a * 1e3:.1f} | {h:.4f} | {k:.4f} |" for a, h, k in zip(amps, harmonic, klingel, strict=True)]
    # smoothing's effect on the case's contact geometry
    exact = setup(0.0)
    worst_r, worst_d = (0.0, None), (0.0, None)
    for y, yaw, roll in cases():
        for side in ("left", "right"):
            a = search_wheel(track, wheelset, Pose(y, yaw, roll), side).points[0]
            b = search_wheel(*exact, Pose(y, yaw, roll), side).points[0]
            worst_r = max(worst_r, (abs(a.rolling_radius - b.rolling_radius), f"{y * 1e3:.1f} mm {side}"))
            worst_d = max(worst_d, (abs(a.contact_angle - b.contact_angle), f"{y * 1e3:.1f} mm {side}"))
    lines += ["", f"Smoothing (default L_c = {track.rail.smoothing * 1e3:.1f} mm against the interpolating spline) on "
              f"case A-2.2: largest change of a rolling radius {worst_r[0] * 1e6:.2f} um ({worst_r[1]}), of a "
              f"contact angle {worst_d[0]:.2e} rad ({worst_d[1]}).", ""]
    return lines, f, wide, amps, harmonic, klingel


def part_c(track, wheelset, quick):
    lines = ["## C. Contact table: interpolation error between the nodes", ""]
    specs = [("zero yaw", (-0.01, 0.01), 1e-4, (0.0,))]
    if not quick:
        specs.append(("yaw -24..24 mrad, nodes every 4 mrad", (-0.01, 0.01), 2e-4, tuple(np.arange(-24, 25, 4) * 1e-3)))
    tables = []
    lines += ["| table | nodes (first yaw) | jumps | build [s] | samples | " + " | ".join(
        ["roll [rad]", "Delta r [m]", "r right [m]", "delta right [rad]", "y wheel right [m]", "y rail right [m]",
         "x shift right [m]", "k wheel right [1/m]", "k rail right [1/m]"]) + " |", "|---" * 14 + "|"]
    for name, rng, step, yaws in specs:
        t0 = time.perf_counter()
        table = ContactTable.build(track, wheelset, rng, step, yaws)
        built = time.perf_counter() - t0
        err = table.interpolation_error(track, wheelset, samples=40 if quick else 200)
        keys = ["roll", "radius_difference", "right_rolling_radius", "right_contact_angle", "right_wheel_lateral",
                "right_rail_lateral", "right_longitudinal_shift", "right_wheel_lateral_curvature",
                "right_rail_lateral_curvature"]
        lines.append(f"| {name} | {table.functions[0].shift.size} | {len(table.functions[0].jumps)} | {built:.1f} | "
                     f"{len(err['points'])} | " + " | ".join(f"{max(err[k], err[k.replace('right', 'left')]):.1e}"
                                                             for k in keys) + " |")
        tables.append(table)
    lines += ["", "Errors are the largest over both wheels at points halfway between the nodes (in yaw: halfway "
              "between yaw nodes); the lateral curvatures are interpolated without refinement (their jumps at the "
              "profiles' arc joints make them the least smooth quantities).", ""]
    return lines, tables


def low(function, samples=400):
    """The 10th percentile [s] of single calls: what the code costs when the shared machine lets it run (the
    medians carry the other jobs' load)."""
    function()
    times = []
    for _ in range(samples):
        t0 = time.perf_counter()
        function()
        times.append(time.perf_counter() - t0)
    return float(np.percentile(times, 10))


def part_d(track, wheelset, tables, quick):
    repeats = dict(min_repeats=20 if quick else 200, min_seconds=0.2 if quick else 1.0)
    poses = [Pose(y, yaw, roll) for y, yaw, roll in cases()]
    rows = []
    for label, pose in (("tread (0 mm)", poses[0]), ("flange root (5.5 mm)", poses[11]), ("flange (8 mm)", poses[16])):
        calls = (lambda p=pose: search_wheel(track, wheelset, p, "right"),
                 lambda p=pose: search_wheel(track, wheelset, p, "right").patches[0].gap,
                 lambda p=pose: solve_normal(search_wheel(track, wheelset, p, "right"), 1e4))
        cells = [f"{common.median_time(c, **repeats) * 1e6:.0f} / {low(c) * 1e6:.0f}" for c in calls]
        rows.append(f"| {label} | " + " | ".join(cells) + " |")
    lines = ["## D. Times", "", "Median / 10th percentile of single calls (the machine is shared: the percentile is "
             "what the code costs when it gets the core). Per wheel, right wheel at the benchmark's pose:", "",
             "| position | search [us] | search + patch gap [us] | search + Hertz normal solve, 10 kN [us] |",
             "|---|---:|---:|---:|", *rows, ""]
    rigid = common.median_time(lambda: rigid_position(track, wheelset, 0.003, 0.0072), min_repeats=10,
                               min_seconds=0.5)
    loaded = common.median_time(lambda: loaded_position(track, wheelset, 0.003, 0.0072, 1e4, 1e4), min_repeats=10,
                                min_seconds=0.5)
    lookups = []
    for table in tables:
        psi = 0.0 if table.yaws.size == 1 else 0.0071
        def call(t=table, p=psi):
            return t(0.00433, p)

        lookups.append((common.median_time(call, min_repeats=20, min_seconds=0.5, batch_seconds=0.02), low(call)))
    t0 = time.perf_counter()
    equivalent_conicity(track, wheelset, 0.003)
    conicity = time.perf_counter() - t0
    lines += ["| operation | time (median / 10th percentile) |", "|---|---:|",
              f"| rigid wheelset position (both wheels touching), 3 mm, 7.2 mrad | {rigid * 1e3:.1f} ms |",
              f"| loaded wheelset position (10 kN per wheel, Hertz), 3 mm, 7.2 mrad | {loaded * 1e3:.1f} ms |",
              f"| table lookup, zero-yaw table | {lookups[0][0] * 1e6:.1f} / {lookups[0][1] * 1e6:.1f} us |"]
    if len(lookups) > 1:
        lines.append(f"| table lookup, yawed table (quadratic in yaw) | {lookups[1][0] * 1e6:.1f} / "
                     f"{lookups[1][1] * 1e6:.1f} us |")
    lines += [f"| equivalent conicity at 3 mm (Delta r at 61 shifts, jumps resolved; one run) | {conicity:.2f} s |", ""]
    return lines


def part_e(track, wheelset):
    estar = Material().contact_modulus
    lines = ["## E. Hertz's load at the prepared approach", "",
             f"The search prepares patches for approaches up to DEFAULT_DEPTH = {DEFAULT_DEPTH * 1e3:.2f} mm.", "",
             "| contact | A [1/m] | B [1/m] | approach at 10 kN [um] | load at DEFAULT_DEPTH [kN] |",
             "|---|---:|---:|---:|---:|"]
    for label, pose in (("tread, 0 mm", Pose(0.0)), ("flange, 8 mm", Pose(0.008, 0.0192, -0.008606))):
        p = search_wheel(track, wheelset, pose, "right").points[0]
        a, b = p.curvatures
        unit = hertz_ellipse(1.0, a, b, estar).approach
        lines.append(f"| {label} | {a:.3f} | {b:.2f} | {unit * 1e4 ** (2 / 3) * 1e6:.1f} | "
                     f"{(DEFAULT_DEPTH / unit) ** 1.5 / 1e3:.0f} |")
    return lines + [""]


def plot(track, wheelset, f, wide, amps, harmonic, klingel):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    # contact positions: rail in its own axes, the wheel at the centred position above it (8 mm apart)
    lift = 0.008
    offset = wheelset.taping_line - track.rail_offset  # wheel y_w -> rail profile y at zero shift
    rail, wheel = track.rail.samples, wheelset.wheel.samples
    fig, ax = plt.subplots(figsize=(9, 6))
    ax.plot(rail.y * 1e3, -rail.z * 1e3, "k", lw=1.2, label="UIC60 rail (right)")
    ax.plot((wheel.y + offset) * 1e3, (-wheel.z + lift) * 1e3, "b", lw=1.2, label="S1002 wheel (right), lifted 8 mm")
    shifts = np.linspace(-0.008, 0.010, 37)
    cmap = plt.get_cmap("viridis")
    for k, y in enumerate(shifts):
        _, _, right = rigid_position(track, wheelset, float(y))
        p = right.points[0]
        zr = float(track.rail.z_at(p.rail_lateral))
        zw = float(wheelset.wheel.z_at(p.wheel_lateral))
        ax.plot([p.rail_lateral * 1e3, (p.wheel_lateral + offset) * 1e3], [-zr * 1e3, (-zw + lift) * 1e3],
                color=cmap(k / (len(shifts) - 1)), lw=0.8)
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(shifts[0] * 1e3, shifts[-1] * 1e3))
    fig.colorbar(sm, ax=ax, label="lateral shift [mm]")
    ax.set_xlabel("y on the rail profile [mm] (gauge side left)")
    ax.set_ylabel("height [mm] (up)")
    ax.set_title("Contact points of the rigid wheelset, right wheel, zero yaw")
    ax.set_aspect("equal")
    ax.set_xlim(-85, 40)
    ax.set_ylim(-30, 15)
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(common.RESULTS / "wheelrail_contact_positions.png", dpi=110)
    plt.close(fig)

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.5))
    a1.plot(wide.shift * 1e3, wide["radius_difference"] * 1e3, "k")
    a1.set_xlabel("lateral shift [mm]")
    a1.set_ylabel("Delta r = r_right - r_left [mm]")
    a1.grid(alpha=0.3)
    a1.set_title("Rolling-radius difference")
    a2.plot(amps * 1e3, harmonic, "o-", label="harmonic linearisation")
    a2.plot(amps * 1e3, klingel, "s--", label="Klingel (nonlinear oscillation)")
    a2.set_xlabel("amplitude [mm]")
    a2.set_ylabel("equivalent conicity [1]")
    a2.grid(alpha=0.3)
    a2.legend()
    a2.set_title("Equivalent conicity, S1002/UIC60 1:40, 1435/1360")
    fig.tight_layout()
    fig.savefig(common.RESULTS / "wheelrail_conicity.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(f.shift * 1e3, f["right_contact_angle"], "r", label="right wheel")
    ax.plot(f.shift * 1e3, f["left_contact_angle"], "b", label="left wheel")
    ax.set_xlabel("lateral shift [mm]")
    ax.set_ylabel("contact angle [rad] (towards the flange)")
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title("Contact angle of the rigid wheelset, zero yaw")
    fig.tight_layout()
    fig.savefig(common.RESULTS / "wheelrail_contact_angle.png", dpi=110)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer shifts and repeats, one yaw; nothing written")
    args = parser.parse_args()
    load = common.os.getloadavg()[0]
    started = time.perf_counter()
    track, wheelset = setup()
    lines_a = part_a(track, wheelset)
    lines_b, f, wide, amps, harmonic, klingel = part_b(track, wheelset, args.quick)
    lines_c, tables = part_c(track, wheelset, args.quick)
    lines_d = part_d(track, wheelset, tables, args.quick)
    lines_e = part_e(track, wheelset)
    lines = ["# Wheel/rail contact geometry: S1002 on UIC60 (Manchester benchmark)", "", *common.machine(load), "",
             f"Study took {time.perf_counter() - started:.0f} s.", "", *lines_a, *lines_b, *lines_c, *lines_d,
             *lines_e]
    common.publish(lines, "wheelrail_geometry.md", args.quick)
    if not args.quick:
        plot(track, wheelset, f, wide, amps, harmonic, klingel)


if __name__ == "__main__":
    main()
