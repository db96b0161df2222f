"""Normal approach for a prescribed vertical load, the hook for other normal laws, and the rigid wheelset's roll.

Oracles: Hertz's ellipse for a single contact (the approach of :func:`hertz_ellipse` under the load); the load
balance; the Manchester benchmark's prescribed roll, found by CONTACT for 10 kN on each wheel of the same rigid
wheelset (our Hertzian normal contact replaces CONTACT's non-Hertzian one: the flange contacts differ most).
Tolerances: identities 1e-9 relative; the benchmark's roll 2e-5 rad (1e-4 rad at 6.5 mm, the first flange contact).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from wheelrail_cases import circular_head, manchester_rows

from rollcontact.core.materials import Material
from rollcontact.elliptic.hertz import hertz_ellipse
from rollcontact.wheelrail.geometry import Pose, Track, Wheelset
from rollcontact.wheelrail.normal import (
    loaded_position,
    rigid_contacts,
    rigid_position,
    solve_normal,
    wheel_forces_at_pose,
)
from rollcontact.wheelrail.profiles import Profile
from rollcontact.wheelrail.search import scan_gap, search_wheel


@pytest.fixture(scope="module")
def cylinder_on_crown():
    flat = Profile(np.linspace(-0.07, 0.07, 141), np.zeros(141), smoothing=0.0, kind="wheel", source="cylinder")
    return Track(circular_head(0.3, half_angle=0.15), gauge=1.5, gauge_height=1e-3), Wheelset(flat, 0.46)


def test_single_hertz_contact(cylinder_on_crown):
    track, wheelset = cylinder_on_crown
    contact = search_wheel(track, wheelset, Pose(0.002, 0.0, 0.0, -2e-5), "right")
    sol = solve_normal(contact, 5e4)
    ellipse = hertz_ellipse(5e4, 1 / (2 * 0.46), 1 / (2 * 0.3), Material().contact_modulus)
    assert abs(sol.vertical_force / 5e4 - 1) < 1e-9, f"vertical force {sol.vertical_force!r} N, load 5e4 N"
    approach = sol.vertical_displacement - contact.vertical_gap
    assert abs(approach / ellipse.approach - 1) < 1e-6, f"approach {approach!r} m, Hertz's {ellipse.approach!r} m"
    assert abs(sol.lateral_force) < 1e-6, f"lateral force {sol.lateral_force!r} N at a zero contact angle"
    assert sol.in_contact and "carries" in sol.message, sol.message
    none = solve_normal(contact, 0.0)
    assert not none.in_contact and none.vertical_force == 0.0, "a zero load leaves the wheel touching, unloaded"


def test_other_normal_law_per_patch(track, wheelset):
    calls = []

    def spring(patch, approach):
        calls.append((patch.gap.lateral.size, approach))
        return 2e9 * approach  # a linear spring of 2 kN/um

    contact = search_wheel(track, wheelset, Pose(), "right")  # one two-lobed patch
    sol = solve_normal(contact, 1e4, normal_law=spring)
    assert len(sol.normal_forces) == len(contact.patches) == 1, "the law is called per patch"
    assert abs(sol.vertical_force / 1e4 - 1) < 1e-9, f"vertical force {sol.vertical_force!r} N"
    expected = 1e4 / math.cos(contact.patches[0].contact_angle) / 2e9
    assert abs(sol.approaches[0] / expected - 1) < 1e-9, f"approach {sol.approaches[0]!r}, the spring's {expected!r}"
    assert calls and all(n > 10 for n, _ in calls), "the law did not receive the patch's sampled gap"


def test_lifted_wheel_reports_no_contact(track, wheelset):
    contact = search_wheel(track, wheelset, Pose(0.0, 0.0, -0.002, 0.0), "right")  # the roll lifts the right wheel
    forces = wheel_forces_at_pose(contact)
    assert not forces.in_contact, "a lifted wheel carries load"
    assert all(f == 0.0 for f in forces.normal_forces) and forces.vertical_force == 0.0, forces.normal_forces
    assert "no contact" in forces.message and "lifted off its rail by" in forces.message, forces.message
    assert all(math.isfinite(a) for a in forces.approaches), "approaches must be finite"


def test_rigid_position_touches_both_rails(track, wheelset):
    for shift, yaw in ((0.0, 0.0), (0.003, 0.0), (0.0065, 0.01), (-0.005, -0.004)):
        pose, left, right = rigid_position(track, wheelset, shift, yaw)
        assert abs(left.vertical_gap) < 1e-10 and abs(right.vertical_gap) < 1e-10, (
            f"shift {shift}, yaw {yaw}: vertical gaps {left.vertical_gap!r}, {right.vertical_gap!r} m")
        assert (shift == 0.0) == (pose.roll == 0.0), f"roll {pose.roll!r} rad at shift {shift}"


def test_rigid_contacts_are_the_searches_at_rigid_positions_roll(track, wheelset):
    """The roll and height of rigid_position, bit for bit, and each wheel's contact at that roll and vertical = 0 as
    a search finds it; a scan's least gap is the search's vertical gap."""
    for shift, yaw in ((0.0, 0.0), (0.0012, 0.002), (0.0046, 0.0), (-0.0061, -0.003)):
        pose, left, right = rigid_contacts(track, wheelset, shift, yaw)
        assert pose == rigid_position(track, wheelset, shift, yaw)[0], f"shift {shift}, yaw {yaw}"
        at = Pose(shift, yaw, pose.roll, 0.0)
        for contact in (left, right):
            searched = search_wheel(track, wheelset, at, contact.side)
            assert contact.pose == at and contact.points == searched.points, f"{contact.side} at {shift}, {yaw}"
            assert [(p.points, p.contact_angle, p.source.region) for p in contact.patches] == \
                [(p.points, p.contact_angle, p.source.region) for p in searched.patches], "patches"
            assert scan_gap(track, wheelset, at, contact.side).least_gap == contact.vertical_gap
        assert pose.vertical == 0.5 * (left.vertical_gap + right.vertical_gap)


def test_the_least_gaps_slope_in_roll_is_its_central_difference(track, wheelset):
    """GapScan.roll_slope (the envelope theorem at the deepest point, what the roll's Newton steps take) against
    central differences of the least gap, on the tread (to 1e-6) and at the flange (to 2e-4: there the slope is a
    difference of terms near 1, each as close to the sampled profiles' as their Hermite interpolation), with yaw."""
    for shift, yaw, roll, rel in ((0.0, 0.0, 0.0, 1e-6), (0.003, 0.002, -2e-4, 1e-6), (0.0058, -0.01, -5e-4, 1e-6),
                                  (0.0068, 0.004, -5.7e-3, 2e-4)):
        for side in ("left", "right"):
            slope = scan_gap(track, wheelset, Pose(shift, yaw, roll), side).roll_slope
            h = 1e-7
            gaps = [scan_gap(track, wheelset, Pose(shift, yaw, roll + d), side).least_gap for d in (h, -h)]
            assert slope == pytest.approx((gaps[0] - gaps[1]) / (2 * h), rel=rel), (shift, yaw, roll, side)


@pytest.mark.parametrize("case", [1, 4, 8, 11, 13, 14, 17, 21])
def test_loaded_roll_matches_the_benchmark(track, wheelset, case):
    row = manchester_rows()[case - 1]
    shift, yaw, roll = float(row["lateral_shift_mm"]) * 1e-3, float(row["yaw_rad"]), float(row["roll_rad"])
    pose, left, right = loaded_position(track, wheelset, shift, yaw, 1e4, 1e4)
    for wheel in (left, right):
        assert abs(wheel.vertical_force / 1e4 - 1) < 1e-9, f"{wheel.contact.side} carries {wheel.vertical_force!r} N"
        assert abs(wheel.vertical_displacement) < 1e-9, "the pose is not the loaded position"
    tolerance = 1e-4 if case == 14 else 2e-5
    assert abs(pose.roll - roll) < tolerance, (
        f"case {case} (y = {shift * 1e3} mm): roll {pose.roll:.8f} rad, the benchmark's {roll:.8f} rad")
