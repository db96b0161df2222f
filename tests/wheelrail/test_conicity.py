"""Contact-geometry functions, equivalent conicity and the contact table.

Oracles: the rigid wheelset of two cones on narrow circular rail heads, computed here independently in closed form
per roll (the cone's cross-section is a line; its distance from the head's centre gives the descent to touch and the
contact point), its roll found by bisection, and the harmonic linearisation of its Delta r by Gauss-Chebyshev
quadrature; the same for a function Delta r given in closed form; direct searches between the table's nodes.
Tolerances: the cone's Delta r 1e-8 m and conicity 1e-5; Klingel's and the harmonic conicity of a linear Delta r
1e-6; the table within twice the tolerances it refines to (TOLERANCES) on the refined quantities.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from wheelrail_cases import circular_head, cone

from rollcontact.wheelrail.conicity import (
    QUANTITIES,
    TOLERANCES,
    ContactTable,
    contact_functions,
    equivalent_conicity,
    harmonic_conicity,
    klingel_conicity,
    rolling_radius_difference,
)
from rollcontact.wheelrail.geometry import Track, Wheelset

LAMBDA, R0, HEAD = 0.05, 0.46, 5e-3


@pytest.fixture(scope="module")
def cones():
    track = Track(circular_head(HEAD, sample_step=2e-5), gauge=1.5, gauge_height=1e-3)
    return track, Wheelset(cone(LAMBDA), nominal_radius=R0, flange_back_spacing=1.36, flange_back_distance=0.07)


def oracle_delta_r(track, wheelset, shift):
    """Delta r of the rigid cone wheelset (module docstring), independent of the search."""
    yt, centre = wheelset.taping_line, (track.rail_offset, HEAD)
    norm = math.hypot(1.0, LAMBDA)

    def wheel(y_ws, roll):  # right-side frame: descent to touch and the contact's axle coordinate
        c, s = math.cos(roll), math.sin(roll)
        p0 = (y_ws + yt * c - R0 * s, -R0 + yt * s + R0 * c)  # the taping-line point at dz = 0
        u = ((c + LAMBDA * s) / norm, (s - LAMBDA * c) / norm)  # along the line, Y increasing
        n = (-u[1], u[0]) if u[0] > 0 else (u[1], -u[0])  # towards the rail (n_z > 0)
        dist = (centre[0] - p0[0]) * n[0] + (centre[1] - p0[1]) * n[1]
        t = (centre[0] - p0[0]) * u[0] + (centre[1] - p0[1]) * u[1]
        return (dist - HEAD) / n[1], R0 - LAMBDA * t / norm

    def level(roll):
        return wheel(-shift, -roll)[0] - wheel(shift, roll)[0]

    roll = brentq(level, -0.02, 0.02, xtol=1e-16)
    return wheel(shift, roll)[1] - wheel(-shift, -roll)[1]


def test_cone_delta_r_and_conicity(cones):
    track, wheelset = cones
    shifts = [-0.004, -0.0015, 0.001, 0.003]
    computed = rolling_radius_difference(track, wheelset, shifts)
    for y, dr in zip(shifts, computed, strict=True):
        expected = oracle_delta_r(track, wheelset, y)
        assert abs(dr - expected) < 1e-8, f"Delta r at {y} m: {dr!r}, the closed form's {expected!r}"
    amp = 0.003
    nodes = 48  # Gauss-Chebyshev of int Delta r(a sin t) sin t dt
    t = (np.arange(nodes) + 0.5) * 2 * math.pi / nodes
    oracle = sum(oracle_delta_r(track, wheelset, amp * math.sin(ti)) * math.sin(ti) for ti in t) / (nodes * amp)
    lam = equivalent_conicity(track, wheelset, amp, step=2.5e-4)
    assert abs(lam - oracle) < 1e-5, f"conicity {lam!r}, the cone's harmonic oracle {oracle!r}"
    # the roll makes a cone's rigid Delta r steeper than 2 lambda y: lambda / (1 - lambda r0 / e) to first order
    assert abs(lam / (LAMBDA / (1 - LAMBDA * R0 / wheelset.taping_line)) - 1) < 2e-3, f"conicity {lam!r}"


def test_conicity_formulas_on_closed_forms():
    y = np.linspace(-0.006, 0.006, 241)
    assert abs(harmonic_conicity(y, 2 * 0.1 * y, 0.003) - 0.1) < 1e-12, "harmonic conicity of 2 lambda y"
    assert abs(klingel_conicity(y, 2 * 0.1 * y, 0.003) - 0.1) < 1e-6, "Klingel's conicity of 2 lambda y"
    # Delta r = 2 (l1 y + l3 y^3): harmonic linearisation l1 + (3/4) l3 a^2
    dr = 2 * (0.1 * y + 2000.0 * y**3)
    expected = 0.1 + 0.75 * 2000.0 * 0.003**2
    assert abs(harmonic_conicity(y, dr, 0.003) - expected) < 2e-5, "harmonic conicity of a cubic Delta r"


def test_s1002_uic60_conicity(track, wheelset):
    functions = contact_functions(track, wheelset, np.linspace(-0.004, 0.004, 33))
    dr = functions["radius_difference"]
    assert np.max(np.abs(dr + dr[::-1])) < 1e-9, "Delta r of the symmetric wheelset is not odd"
    harmonic = equivalent_conicity(track, wheelset, 0.003, functions=functions)
    klingel = equivalent_conicity(track, wheelset, 0.003, "klingel", functions=functions)
    print(f"\nS1002/UIC60 1:40, 1435/1360: equivalent conicity at 3 mm {harmonic:.4f} (harmonic), "
          f"{klingel:.4f} (Klingel); jumps at {[round(j * 1e3, 4) for j in functions.jumps]} mm")
    assert 0.15 < harmonic < 0.22, f"conicity {harmonic!r} at 3 mm, outside S1002/UIC60's 0.15-0.22"
    assert abs(klingel / harmonic - 1) < 0.03, f"Klingel's {klingel!r} and the harmonic {harmonic!r} differ > 3 %"
    assert any(abs(abs(j) - 2.1e-4) < 2e-5 for j in functions.jumps), "the centre's lobes' jump is missing"


def test_table_interpolation_within_its_bound(track, wheelset):
    table = ContactTable.build(track, wheelset, (0.0055, 0.0065), step=2.5e-4)
    assert len(table.functions[0].jumps) == 1, f"jumps {table.functions[0].jumps}: flange root to flange expected"
    errors = table.interpolation_error(track, wheelset, samples=12)
    for name, tol in TOLERANCES.items():
        assert errors[name] < 2 * tol, f"{name}: interpolation error {errors[name]!r}, bound 2 x {tol!r}"
    entry = table.lookup(0.006)
    assert set(entry) == set(QUANTITIES), "lookup does not return every quantity"
    jump = table.functions[0].jumps[0]
    before, after = table.lookup(jump - 2e-7), table.lookup(jump + 2e-7)
    assert before["right_contact_angle"] < 0.8 < after["right_contact_angle"], (
        f"across the jump at {jump!r} m the table blends: {before['right_contact_angle']!r}, "
        f"{after['right_contact_angle']!r} rad")
    with pytest.raises(ValueError, match="lateral_shift = 0.01 m is outside the table's"):
        table(0.01)


@pytest.mark.slow
def test_yawed_table_between_yaw_nodes(track, wheelset):
    """Quadratic in yaw through 3 nodes 4 mrad apart: within 25 um of radius and 4 mrad of contact angle at the
    midpoints (the steep flange root next to a jump that moves with yaw is the worst)."""
    table = ContactTable.build(track, wheelset, (0.004, 0.007), step=5e-4, yaws=(0.0, 0.004, 0.008))
    assert len({len(f.jumps) for f in table.functions}) == 1, "the yaw nodes' jumps do not pair up"
    errors = table.interpolation_error(track, wheelset, samples=20)
    assert errors["right_rolling_radius"] < 2.5e-5, f"radius error {errors['right_rolling_radius']!r} m"
    assert errors["right_contact_angle"] < 4e-3, f"contact angle error {errors['right_contact_angle']!r} rad"
    assert errors["roll"] < 2e-5, f"roll error {errors['roll']!r} rad"


def test_locate_gives_the_lookups_row_weight_and_segment_slope(contact_table):
    """locate(y) names the two nodes and the weight of the lookup at y, within the segment between jumps, and the
    distance of the nodes (the lookup's derivative in y there)."""
    rows = contact_table.rows
    for y in (-0.0071, -0.0031, 0.0, 0.00021, 0.0023, 0.0049, 0.0079):
        k, t, width = contact_table.locate(y)
        np.testing.assert_allclose((1 - t) * rows[k] + t * rows[k + 1], contact_table(y), rtol=1e-13, atol=1e-15,
                                   err_msg=f"locate({y}) is not the lookup's row and weight")
        shift = contact_table.functions[0].shift
        assert width == shift[k + 1] - shift[k] > 0.0, f"width {width!r} at y = {y}"
        assert not any(shift[k] < j < shift[k + 1] for j in contact_table.functions[0].jumps), \
            f"y = {y}: the nodes {k}, {k + 1} span a jump"
    with pytest.raises(ValueError, match="lateral_shift = 0.009 m is outside the table's"):
        contact_table.locate(0.009)
