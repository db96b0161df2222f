"""Profile readers and the smoothing spline.

Oracles: the shared files' own numbers (point counts, the mirrored S1002's flange back and taping line, UIC60's
point 14 mm below its top), the Miniprof copy of the same rail, hand-made files whose options have a known effect,
UIC60's design radii (300 mm crown, 80 mm, 13 mm gauge corner) and the contact radii without smoothing.
Tolerances: coordinates of unchanged points 1e-12 m; design radii 1 % (crown 2 %: its curvature is the smallest);
the default smoothing's effect on the benchmark's contact radii 10 um (a fifth of the 0.05 mm goal).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from wheelrail_cases import PROFILES, manchester_pose, manchester_rows

from rollcontact.wheelrail.geometry import Track, Wheelset
from rollcontact.wheelrail.profiles import (
    DEFAULT_SMOOTHING,
    Profile,
    ProfileError,
    read_miniprof,
    read_profile,
    read_simpack,
    read_text_profile,
)
from rollcontact.wheelrail.search import search_wheel

HEADER = """  header.begin
    version = 1
    type = {kind}
  header.end
  spline.begin
    approx.smooth = 0.0
{options}    point.begin
{points}    point.end
  spline.end
"""


def simpack(tmp_path, points, options="", kind=1, name="hand.prw"):
    """A SIMPACK file with the given point lines and option lines."""
    path = tmp_path / name
    path.write_text(HEADER.format(kind=kind, options=options, points="".join(f"{p}\n" for p in points)))
    return path


def arc_points(n=41, scale=1000.0):
    """Points of a 50 mm-radius arc, y from -20 to 20 mm (in the file's unit: ``scale`` per metre)."""
    y = np.linspace(-0.02, 0.02, n)
    z = 0.05 - np.sqrt(0.05**2 - y**2)
    return y * scale, z * scale


def test_shared_wheel_reads_mirrored_and_inverted(s1002):
    # 400 point lines, one commented out; mirror.y puts the flange back at -70 mm, the taping line at y = 0, z = 0
    assert s1002.y.size == 399, f"S1002 has {s1002.y.size} points, the file 399 (and one commented out)"
    assert s1002.kind == "wheel", f"kind {s1002.kind!r}, the header says type 1"
    assert abs(s1002.y[0] + 0.069612628) < 1e-12, f"first y {s1002.y[0]!r} m, the mirrored file's -69.612628 mm"
    assert abs(s1002.y[-1] - 0.060) < 1e-12, f"last y {s1002.y[-1]!r} m, the mirrored file's 60 mm"
    assert abs(s1002.z_at(0.0)) < 2e-7, f"z at the taping line {s1002.z_at(0.0)!r} m, the file's 0"
    lo, hi = s1002.lateral_extent
    assert -0.0697 < lo < -0.0695 and 0.0599 < hi < 0.0601, f"extent {lo!r}, {hi!r} m"
    # the flange: its tip (largest z, about 28 mm) lies on the negative side
    tip = s1002.samples.y[np.argmax(s1002.samples.z)]
    assert -0.060 < tip < -0.045, f"flange tip at y = {tip!r} m, expected between -60 and -45 mm"


def test_shared_rail_and_miniprof_copy_agree(uic60):
    ban = read_miniprof(PROFILES / "MBench_UIC60_v3.ban")
    assert uic60.kind == "rail" and ban.kind == "rail", f"kinds {uic60.kind!r}, {ban.kind!r}"
    assert uic60.y.size == ban.y.size == 495, f"{uic60.y.size} and {ban.y.size} points, the files 495"
    assert np.max(np.abs(uic60.y - ban.y)) < 1e-12, "the .ban's -X is not the .prr's y"
    assert np.max(np.abs(uic60.z - ban.z)) < 1e-12, "the .ban's Y is not the .prr's z"
    ys = np.linspace(-0.04, 0.028, 30)
    assert np.max(np.abs(uic60.z_at(ys) - ban.z_at(ys))) < 1e-12, "the two splines differ"
    # 14 mm below the top on the gauge side at y = -43.03 mm (the notes' value)
    y14 = ys[0]
    for y in np.linspace(-0.0437, -0.040, 3701):
        if uic60.z_at(y) <= 0.014:
            y14 = y
            break
    assert abs(y14 + 0.04303) < 2e-5, f"14 mm below the top at y = {y14!r} m, the benchmark's -43.03 mm"


@pytest.mark.parametrize(("y", "radius", "tolerance"), [(0.0, 0.300, 0.02), (-0.020, 0.080, 0.01),
                                                       (0.016, 0.080, 0.01), (-0.038, 0.013, 0.01),
                                                       (0.024, 0.013, 0.01)])
def test_uic60_design_radii_from_the_curvature(uic60, y, radius, tolerance):
    r = 1.0 / float(uic60.curvature(y))
    assert abs(r / radius - 1.0) < tolerance, f"radius at y = {y} m is {r * 1e3:.2f} mm, UIC60's {radius * 1e3} mm"


def test_smoothing_default_moves_contact_radii_by_micrometres(s1002, uic60, track, wheelset):
    exact = (Track(uic60.with_smoothing(0.0)), Wheelset(s1002.with_smoothing(0.0)))
    worst = (0.0, None)
    for row in manchester_rows():
        pose = manchester_pose(row)
        for side in ("left", "right"):
            a = search_wheel(track, wheelset, pose, side).points[0]
            b = search_wheel(*exact, pose, side).points[0]
            worst = max(worst, (abs(a.rolling_radius - b.rolling_radius), (row["lateral_shift_mm"], side)))
            assert abs(a.contact_angle - b.contact_angle) < 3e-3, (
                f"smoothing L_c = {DEFAULT_SMOOTHING} m moves the contact angle at {pose} {side} by "
                f"{a.contact_angle - b.contact_angle:.2e} rad")
    assert worst[0] < 1e-5, f"smoothing moves a contact radius by {worst[0] * 1e6:.2f} um at {worst[1]} (limit 10 um)"


def test_smoothing_quiets_measurement_noise(uic60):
    # 1 um of white noise on the rail's points: the 13 mm gauge corner's curvature stays within 15 %
    rng = np.random.default_rng(7)
    noisy = Profile(uic60.y, uic60.z + rng.normal(0.0, 1e-6, uic60.y.size), kind="rail", source="noisy")
    raw = Profile(noisy.y, noisy.z, smoothing=0.0, source="noisy raw")
    ys = np.linspace(-0.0385, -0.0365, 5)
    smoothed = 1.0 / noisy.curvature(ys)
    assert np.all(np.abs(smoothed / 0.013 - 1.0) < 0.15), f"gauge corner radii {smoothed * 1e3} mm with noise"
    assert np.std(raw.curvature(ys) - 1 / 0.013) > 5 * np.std(noisy.curvature(ys) - 1 / 0.013), (
        "the interpolating spline is not noisier than the smoothed one: the test does not exercise the smoothing")


def test_simpack_options_units_mirror_inversion_shift_comments(tmp_path):
    y, z = arc_points()
    lines = [f"{a:.9f} {b:.9f}" for a, b in zip(y, z, strict=True)]
    lines.insert(5, "! 1.0 2.0  a commented-out point")
    lines.insert(9, f"!{y[8] + 0.01:.6f} {z[8]:.6f}")
    plain = read_simpack(simpack(tmp_path, lines, "    units.len.f = 1000.0\n"), smoothing=0.0)
    assert plain.y.size == 41, f"{plain.y.size} points, 41 written (comments skipped)"
    assert np.max(np.abs(plain.y - y / 1000)) < 1e-12, "millimetres not converted to metres"
    opts = ("    units.len.f = 1000.0\n    shift.y = 5.0\n    shift.z = 1.0\n    mirror.y = 1\n    inversion = 1\n"
            "    bound.y.min = 1.0\n    bound.y.max = 0.0\n")
    moved = read_simpack(simpack(tmp_path, lines, opts, name="moved.prw"), smoothing=0.0)
    # shift first, then mirror: y -> -(y + 5 mm); stored with y increasing
    assert np.max(np.abs(np.sort(moved.y) - np.sort(-(y + 5.0) / 1000))) < 1e-12, "shift then mirror.y not applied"
    assert np.max(np.abs(moved.z_at(-(y[3] + 5.0) / 1000) - (z[3] + 1.0) / 1000)) < 1e-9, "shift.z not applied"
    bounded = read_simpack(simpack(tmp_path, lines, "    units.len.f = 1000.0\n    bound.y.min = -10.0\n"
                                   "    bound.y.max = 10.0\n", name="bounded.prw"), smoothing=0.0)
    assert bounded.y.size == 21 and np.all(np.abs(bounded.y) <= 0.010 + 1e-12), (
        f"bounds keep {bounded.y.size} points, y in [{bounded.y[0]}, {bounded.y[-1]}]: expected 21 within 10 mm")
    turned = read_simpack(simpack(tmp_path, lines, "    units.len.f = 1000.0\n    units.ang.f = 1000.0\n"
                                  "    rotate = 10.0\n", name="turned.prw"), smoothing=0.0)
    c, s = math.cos(0.01), math.sin(0.01)
    assert np.max(np.abs(turned.y - (c * y - s * z) / 1000)) < 1e-12, "rotate (mrad, units.ang.f) not applied"
    flipped = read_simpack(simpack(tmp_path, lines, "    units.len.f = 1000.0\n    mirror.z = 1\n",
                                   name="flip.prw"), smoothing=0.0)
    assert np.max(np.abs(flipped.z + z / 1000)) < 1e-12, "mirror.z not applied"


@pytest.mark.parametrize(("edit", "expected"), [
    (lambda p: p[:10] + ["1.0 two"] + p[10:], "line 19: y = 1.0 two"),
    (lambda p: p[:10] + [p[12]] + p[10:], "line 19"),                      # unsorted: folds back
    (lambda p: p[:10] + [p[9]] + p[10:], "duplicates the one of line 18"),
    (lambda p: p[:10] + p[30:], "a gap of"),
    (lambda p: p[:3], "3 points in the point block"),
])
def test_bad_simpack_files_name_the_line(tmp_path, edit, expected):
    y, z = arc_points()
    lines = [f"{a:.9f} {b:.9f}" for a, b in zip(y, z, strict=True)]
    path = simpack(tmp_path, edit(lines), "    units.len.f = 1000.0\n")
    with pytest.raises(ProfileError) as err:
        read_simpack(path)
    message = str(err.value)
    assert "hand.prw" in message, f"the message does not name the file: {message}"
    assert expected.split(":")[0] in message, f"expected {expected!r} in: {message}"


def test_bad_files_missing_block_and_unit(tmp_path):
    path = tmp_path / "empty.prr"
    path.write_text("  header.begin\n    type = 0\n  header.end\n")
    with pytest.raises(ProfileError, match="empty.prr: no point block"):
        read_simpack(path)
    text = tmp_path / "rail.txt"
    y, z = arc_points()
    text.write_text("".join(f"{a} {b}\n" for a, b in zip(y, z, strict=True)))
    with pytest.raises(ProfileError, match="needs its unit"):
        read_profile(text)
    with pytest.raises(ProfileError, match="unit = 'inch'"):
        read_text_profile(text, "inch")
    prof = read_profile(text, unit="mm", smoothing=0.0)
    assert np.max(np.abs(prof.y - y / 1000)) < 1e-12, "plain text in mm not converted"
    missing = tmp_path / "missing.ban"
    with pytest.raises(ProfileError, match="missing.ban: cannot read"):
        read_miniprof(missing)
    bad = tmp_path / "bad.ban"
    bad.write_text("XYPoints=41\nColumnDef=X,Y\n" + "".join(f"{a} {b}\n" for a, b in zip(y[:40], z[:40],
                                                                                         strict=True)))
    with pytest.raises(ProfileError, match="line 1: XYPoints = 41 but the file has 40 points"):
        read_miniprof(bad)


def test_profile_evaluation_matches_an_analytic_arc():
    y, z = arc_points(201, 1.0)
    arc = Profile(y, z, smoothing=0.0)
    ys = np.linspace(-0.015, 0.015, 7)
    assert np.max(np.abs(arc.z_at(ys) - (0.05 - np.sqrt(0.05**2 - ys**2)))) < 1e-9, "z(y) off the arc"
    assert np.max(np.abs(arc.slope(ys) - ys / np.sqrt(0.05**2 - ys**2))) < 1e-6, "slope off the arc"
    assert np.max(np.abs(arc.curvature(ys) * 0.05 - 1.0)) < 1e-4, "curvature off 1/50 mm"
    assert np.max(np.abs(arc.normal_angle(ys) - np.arcsin(ys / 0.05))) < 1e-6, "normal angle off the arc"
    with pytest.raises(ProfileError, match="outside the profile's extent"):
        arc.z_at(0.03)
