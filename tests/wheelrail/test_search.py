"""Contact search per wheel: analytic cases, mirror symmetry, the yawed wheel's lead, several contact points and
patches on the Manchester benchmark, the creepages, and bad input.

Oracles: a cone on a narrow circular rail head and a cylinder on a crowned rail (closed-form contact points, radii,
angles, gaps); the mirror image of the problem; ``r sin(theta)`` with ``sin(theta) = lambda tan(psi)`` for a yawed
cone; the first-order creepages of a wheelset (Kalker; docs/physics.md, Wheelset hunting).
Tolerances: closed forms of positions and radii 1e-8 m (the search's Hermite interpolation), angles 1e-6 rad;
mirror images bit for bit; first-order kinematics 2 % of the value.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from wheelrail_cases import circular_head, cone, manchester_pose, manchester_rows

from rollcontact.wheelrail.geometry import GeometryError, Pose, Track, Velocities, Wheelset
from rollcontact.wheelrail.profiles import Profile
from rollcontact.wheelrail.search import MIN_RISE, creepages, search_wheel

LAMBDA = 0.05
KNIFE = 5e-3  # radius [m] of the narrow rail head (sampled every 20 um)


@pytest.fixture(scope="module")
def cone_on_knife():
    track = Track(circular_head(KNIFE, sample_step=2e-5), gauge=1.5, gauge_height=1e-3)
    return track, Wheelset(cone(LAMBDA), nominal_radius=0.46, flange_back_spacing=1.36, flange_back_distance=0.07)


@pytest.mark.parametrize("shift", [-0.004, -0.001, 0.0, 0.0025, 0.005])
def test_cone_on_a_knife_edge_gives_the_analytic_geometry(cone_on_knife, shift):
    track, wheelset = cone_on_knife
    gamma = math.atan(LAMBDA)
    left, right = (search_wheel(track, wheelset, Pose(shift), side) for side in ("left", "right"))
    for c in (left, right):
        assert len(c.points) == 1 and len(c.patches) == 1, f"{c.side}: {len(c.points)} points on a cone"
        p = c.points[0]
        assert abs(p.contact_angle - gamma) < 1e-6, f"{c.side} contact angle {p.contact_angle!r}, atan(lambda)"
        assert abs(p.rail_lateral + KNIFE * math.sin(gamma)) < 1e-8, (
            f"{c.side} rail contact at {p.rail_lateral!r} m, the circle's -R sin(gamma) = {-KNIFE * math.sin(gamma)!r}")
        assert abs(p.rolling_radius - (0.46 - LAMBDA * p.wheel_lateral)) < 1e-9, "r is not r0 - lambda y_w"
        assert abs(p.longitudinal_shift) < 1e-12, f"{c.side} contact leads by {p.longitudinal_shift!r} m without yaw"
    dr = right.points[0].rolling_radius - left.points[0].rolling_radius
    assert abs(dr - 2 * LAMBDA * shift) < 1e-8, f"Delta r = {dr!r} m at y = {shift} m, 2 lambda y {2 * LAMBDA * shift}"
    # the gap: at dz = 0 the taping line lies in the plane of the rail tops (z = 0); the circle's centre is at
    # z = R below its top, on the line y = rail_offset (right-side frame), where the cone's surface is at
    # z_w = -lambda y_w: the distance from the centre to the cone's line is (R - z_w) cos(gamma), less R
    for c, sign in ((left, -1.0), (right, 1.0)):
        y_w = track.rail_offset - (sign * shift + wheelset.taping_line)  # wheel coordinate above the centre
        z_wheel = -LAMBDA * y_w
        normal_gap = (KNIFE - z_wheel) * math.cos(gamma) - KNIFE
        assert abs(c.gap - normal_gap) < 1e-9, f"{c.side} gap {c.gap!r} m, closed form {normal_gap!r} m"


def test_yawed_cone_leads_by_r_sin_theta(cone_on_knife):
    track, wheelset = cone_on_knife
    for yaw in (-0.02, 0.005, 0.02):
        c = search_wheel(track, wheelset, Pose(0.002, yaw), "right")
        p = c.points[0]
        sin_theta = LAMBDA * math.tan(yaw)  # roll 0: cos(psi) sin(theta) = -tan(alpha) sin(psi), alpha = -gamma
        expected = p.rolling_radius * sin_theta * math.cos(yaw)
        assert abs(p.longitudinal_shift - expected) < 1e-9, (
            f"yaw {yaw}: lead {p.longitudinal_shift!r} m, r sin(theta) cos(psi) = {expected!r} m")
        approx = 0.46 * math.tan(yaw) * math.tan(p.contact_angle)
        assert abs(p.longitudinal_shift / approx - 1) < 0.01, f"lead not ~ r0 tan(psi) tan(delta) = {approx!r}"
        left = search_wheel(track, wheelset, Pose(0.002, yaw), "left").points[0]
        assert left.longitudinal_shift * p.longitudinal_shift < 0, (
            "a yawed wheelset's two contacts must lead and trail (opposite flanges)")


def test_cylinder_on_crowned_rail():
    flat = Profile(np.linspace(-0.07, 0.07, 141), np.zeros(141), smoothing=0.0, kind="wheel", source="cylinder")
    track = Track(circular_head(0.3, half_angle=0.15), gauge=1.5, gauge_height=1e-3)
    wheelset = Wheelset(flat, nominal_radius=0.46)
    for shift in (-0.01, 0.0, 0.007):
        for side in ("left", "right"):
            c = search_wheel(track, wheelset, Pose(shift), side)
            p = c.points[0]
            assert abs(p.contact_angle) < 1e-9 and abs(p.rail_lateral) < 1e-9, (
                f"{side} at {shift}: angle {p.contact_angle!r}, rail position {p.rail_lateral!r}: crown top expected")
            assert abs(p.rolling_radius - 0.46) < 1e-12, f"{side} radius {p.rolling_radius!r} m on a cylinder"
            assert abs(p.gap) < 1e-12, f"{side} gap {p.gap!r}: the crown top touches the taping-line plane"
            a, b = p.curvatures
            assert abs(a - 1 / (2 * 0.46)) < 1e-9 and abs(b / (1 / (2 * 0.3)) - 1) < 1e-4, f"curvatures {a}, {b}"
            gap = c.patches[0].gap
            s = gap.lateral
            exact = 0.3 - np.sqrt(0.3**2 - s**2)
            # linear between the samples 0.1 mm apart: the chord error kappa h^2 / 8 = 4e-9 m
            assert np.max(np.abs(gap.lateral_gap - exact)) < 5e-9, "patch gap is not the crown's circle"
            assert np.max(np.abs(gap.longitudinal_curvature - 1 / (2 * 0.46))) < 1e-12, "A(s) is not 1/(2 r0)"


def test_mirror_symmetry_at_centre(track, wheelset):
    left, right = (search_wheel(track, wheelset, Pose(), side) for side in ("left", "right"))
    assert len(left.points) == len(right.points), "the two wheels' points differ in number at the centre"
    for a, b in zip(left.points, right.points, strict=True):
        for name in ("rail_lateral", "wheel_lateral", "contact_angle", "rolling_radius", "gap", "vertical_gap",
                     "wheel_lateral_curvature", "rail_lateral_curvature"):
            assert getattr(a, name) == getattr(b, name), f"{name}: left {getattr(a, name)!r} right {getattr(b, name)!r}"
        assert a.position[1] == -b.position[1], "the points' track y are not mirror images"
    gl, gr = left.patches[0].gap, right.patches[0].gap
    assert np.array_equal(gl.lateral, -gr.lateral[::-1]), "left patch's s is not the mirror of the right's"
    assert np.array_equal(gl.lateral_gap, gr.lateral_gap[::-1]), "left patch's gap is not the mirror of the right's"
    # a shifted, yawed, rolled wheelset: the left wheel at (y, psi, phi) is the right wheel at (-y, -psi, -phi)
    pose = Pose(0.004, 0.01, -0.0003, 1e-4)
    a = search_wheel(track, wheelset, pose, "left").points[0]
    b = search_wheel(track, wheelset, pose.mirrored(), "right").points[0]
    assert (a.rolling_radius, a.contact_angle, a.gap) == (b.rolling_radius, b.contact_angle, b.gap), (
        "the left wheel is not the right wheel of the mirrored pose")


def test_manchester_jumps_tread_flange_root_flange(track, wheelset):
    """Case A-2.2 per wheel (the benchmark's roll and yaw): where the right wheel's deepest point lies."""
    table = []
    for row in manchester_rows():
        pose = manchester_pose(row)
        right = search_wheel(track, wheelset, pose, "right")
        left = search_wheel(track, wheelset, pose, "left")
        p = right.points[0]
        zone = "tread" if p.contact_angle < 0.2 else ("flange root" if p.contact_angle < 0.7 else "flange")
        table.append((float(row["lateral_shift_mm"]), zone, len(right.points), len(right.patches), p.contact_angle,
                      p.rolling_radius))
        assert left.points[0].contact_angle < 0.05, f"left wheel off its tread at {pose}"
    print("\nshift [mm]  right wheel's deepest point  points  patches  delta [rad]  r [mm]")
    for shift, zone, n, m, delta, r in table:
        print(f"{shift:6.1f}      {zone:12s}                 {n}       {m}       {delta:.4f}   {r * 1e3:.3f}")
    zones = [t[1] for t in table]
    assert zones[:10] == ["tread"] * 10, f"tread expected at 0-4.5 mm, got {zones[:10]}"
    assert zones[10:13] == ["flange root"] * 3, f"flange root expected at 5.0-6.0 mm, got {zones[10:13]}"
    assert zones[13:] == ["flange"] * 8, f"flange expected from 6.5 mm, got {zones[13:]}"
    assert table[10][2] == 2, f"5.0 mm: tread and flange root both within reach, got {table[10][2]} point(s)"
    assert table[0][2] == 2 and table[0][3] == 1, (
        f"0 mm: S1002 on UIC60 is a two-lobed patch (2 points, 1 patch), got {table[0][2]} and {table[0][3]}")


def test_two_lobed_patch_covers_both_lobes(track, wheelset):
    c = search_wheel(track, wheelset, Pose(), "right")
    patch = c.patches[0]
    assert sorted(patch.points) == [0, 1], f"the centred patch holds points {patch.points}"
    gap = patch.gap
    p0, p1 = c.points[patch.points[0]], c.points[patch.points[1]]
    s1 = (p1.position[1] - p0.position[1]) / math.cos(p0.contact_angle)  # the second lobe along the tangent
    assert gap.lateral[0] < min(0.0, s1) and gap.lateral[-1] > max(0.0, s1), "the patch gap misses a lobe"
    h1 = float(np.interp(s1, gap.lateral, gap.lateral_gap))
    assert abs(h1 - (p1.gap - p0.gap)) < 2e-6, (
        f"the gap at the second lobe is {h1!r} m, the points' separations differ by {p1.gap - p0.gap!r} m")
    assert np.all(np.diff(gap.lateral) > 0) and np.all(gap.lateral_gap >= 0), "s not increasing or a negative gap"
    assert gap.lateral_gap[np.searchsorted(gap.lateral, 0.0)] == 0.0, "the gap at s = 0 is not 0"
    assert np.all(gap.longitudinal_curvature > 0), "A(s) must be > 0"
    assert MIN_RISE > 0


def test_creepages_first_order(track, wheelset):
    V = 20.0
    pose = Pose(0.003, 0.004, -0.00018)
    vel = Velocities(V, lateral_velocity=0.02, yaw_rate=0.01)
    for side, sign in (("left", -1.0), ("right", 1.0)):
        p = search_wheel(track, wheelset, pose, side).points[0]
        cr = creepages(wheelset, pose, vel, p)
        y_axle = abs(p.position[1] - pose.lateral_shift)
        xi = 1 - p.rolling_radius / 0.46 - sign * 0.01 * y_axle / V
        eta = (0.02 / V - 0.004) / math.cos(p.contact_angle)
        phi = -sign * math.sin(p.contact_angle) / 0.46 + math.cos(p.contact_angle) * 0.01 / V
        assert abs(cr.longitudinal - xi) < 0.02 * abs(xi) + 1e-6, f"{side} xi {cr.longitudinal!r}, ~{xi!r}"
        assert abs(cr.lateral - eta) < 0.02 * abs(eta), f"{side} eta {cr.lateral!r}, ~{eta!r}"
        assert abs(cr.spin - phi) < 0.02 * abs(phi), f"{side} phi {cr.spin!r}, ~{phi!r}"
    # pure rolling at the centre: the taping line's radius slips nowhere
    p = search_wheel(track, wheelset, Pose(), "right").points[0]
    r_contact = p.rolling_radius
    cr = creepages(wheelset, Pose(), Velocities(V, pitch_rate=-V / r_contact), p)
    # (the wheel's point is the rail's less the vertical gap, both interpolated: 1e-8 of r0)
    assert abs(cr.longitudinal) < 1e-8 and abs(cr.lateral) < 1e-12, f"rolling without slip: {cr}"


def test_bad_input_messages(track, wheelset, s1002):
    narrow = Wheelset(s1002, 0.46, flange_back_spacing=1.0)  # its wheels stand inside the rails: they never meet
    with pytest.raises(GeometryError, match=r"right wheel.*lateral_shift = 0.0 m.*the rail spans track y 0.71"):
        search_wheel(track, narrow, Pose(), "right")
    with pytest.raises(ValueError, match="lateral_shift = 0.5 m is out of range: it must be <= 0.1"):
        Pose(0.5)
    with pytest.raises(GeometryError, match="side = 'middle'"):
        search_wheel(track, wheelset, Pose(), "middle")
    # a wheel profile cut at the flange root: at 8 mm the contact runs off the wheel's end
    cut = Profile(s1002.y[s1002.y > -0.036], s1002.z[s1002.y > -0.036], source="cut S1002")
    short = Wheelset(cut, 0.46, 1.36, 0.07)
    with pytest.raises(GeometryError, match=r"lateral_shift = 0.008 m.*flange end.*wheel y_w = -0.03"):
        search_wheel(track, short, Pose(0.008), "right")
    # a wheel whose flange's crest rides on the rail head has climbed its flange (derailed): said so
    with pytest.raises(GeometryError, match=r"right wheel at lateral_shift = 0.05 m.*flange's crest.*climbed"):
        search_wheel(track, wheelset, Pose(0.05, 0.0, -0.0204), "right")
    climbing = search_wheel(track, wheelset, Pose(0.012, 0.0, -0.0131), "right").points[0]
    assert climbing.contact_angle > 0.5 and climbing.wheel_lateral > wheelset.flange_tip + 5e-3, \
        f"at 12 mm the flange is in contact short of its crest: {climbing}"
    # a wheel lifted off: no contact, said so, no NaN
    lifted = search_wheel(track, wheelset, Pose(0.0, 0.0, 0.0, -1e-3), "right")
    assert not lifted.in_contact and "lifted off" in lifted.message, lifted.message
    assert all(math.isfinite(p.gap) and p.gap > 0 for p in lifted.points), "a lifted wheel's gaps must be > 0"


def test_repeatable_bit_for_bit(track, wheelset):
    pose = Pose(0.0052, 0.0125, -0.0004, 2e-5)
    a, b = (search_wheel(track, wheelset, pose, "right") for _ in range(2))
    assert a.points == b.points, "two searches of one pose differ"
    ga, gb = a.patches[0].gap, b.patches[0].gap
    for name in ("lateral", "lateral_gap", "longitudinal_curvature"):
        assert np.array_equal(getattr(ga, name), getattr(gb, name)), f"two patch gaps differ in {name}"


def test_inclination_cants_an_upright_rail(track, wheelset, uic60):
    """UIC60 turned upright by atan(1/40) and canted back by the track's inclination is the shared canted rail."""
    c = math.atan(1 / 40)
    y = math.cos(c) * uic60.y - math.sin(c) * uic60.z
    z = math.sin(c) * uic60.y + math.cos(c) * uic60.z
    upright = Profile(y, z, kind="rail", source="upright UIC60")
    canted = Track(upright, 1.435, 0.014, inclination=c)
    assert abs(canted.rail_offset - track.rail_offset) < 1e-9, (
        f"rail offset {canted.rail_offset!r} m, the canted profile's {track.rail_offset!r} m")
    for pose in (Pose(), Pose(0.004, 0.008, -0.0002), Pose(0.007, 0.017, -0.0064)):
        a = search_wheel(canted, wheelset, pose, "right").points[0]
        b = search_wheel(track, wheelset, pose, "right").points[0]
        # (the rail positions differ: each is in its own profile's axes, upright or canted)
        assert abs(a.rolling_radius - b.rolling_radius) < 1e-9 and abs(a.contact_angle - b.contact_angle) < 1e-9, (
            f"{pose}: canted upright rail r {a.rolling_radius!r}, delta {a.contact_angle!r}; shared rail "
            f"{b.rolling_radius!r}, {b.contact_angle!r}")
