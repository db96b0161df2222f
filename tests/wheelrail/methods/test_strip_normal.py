"""The strips' normal problem against Hertz on quadratic gaps (a, b, p0 and Fn at a given approach converge with the
strips; tolerances measured at the default 24 strips and stated per quantity), its identities (load balance, the
given-load and given-approach entry points inverse to each other, mirror symmetry, a start from a nearby solution
giving the same solution, one at the same approach returned as it is) and general gaps: two separate
interpenetration intervals, a curvature along x that varies across the patch, a well beside a shelf, a gap sampled
too narrowly, and the normal force of the Manchester wheel's flange patch continuous and increasing in the approach."""

from __future__ import annotations

import math

import numpy as np
import pytest
from wheelrail_gaps import mirrored, quadratic, shelf, three_wells, two_wells, varying_curvature

from rollcontact import Material
from rollcontact.wheelrail.methods.strip_normal import rigid_range, rigid_runs, strip_normal
from rollcontact.wheelrail.patch import PatchGap
from rollcontact.wheelrail.scene import WheelRailScene

ESTAR = Material().contact_modulus

HERTZ_TOLERANCE = {"Fn": 4e-3, "p0": 3e-3, "a": 1e-2, "b": 1e-2}
"""Relative errors at 24 strips over a/b 0.2..5 (the largest measured: Fn 2.5e-3 at a/b = 5, p0 1.9e-3, a 3e-3, b 7e-3;
b is the edge extrapolated from the outermost strips)."""


@pytest.mark.parametrize("ratio", [0.2, 0.5, 1.0, 2.0, 5.0])
def test_quadratic_gap_gives_hertz(ratio):
    gap, scene = quadratic(ratio)
    h = scene.hertz
    contact = strip_normal(gap, ESTAR, approach=h.approach)
    assert contact.converged, contact.message
    errors = {"Fn": contact.normal_load / scene.normal_load - 1, "p0": contact.max_pressure / h.max_pressure - 1,
              "a": contact.length / (2 * h.a) - 1, "b": contact.width / (2 * h.b) - 1}
    for name, error in errors.items():
        assert abs(error) < HERTZ_TOLERANCE[name], f"a/b = {ratio}: {name} off Hertz by {error:+.2e}"


def test_hertz_converges_with_the_strips():
    """The error of Fn and p0 falls with the strip count (a circle: 12, 24, 48 strips)."""
    gap, scene = quadratic(1.0)
    h = scene.hertz
    errors = []
    for count in (12, 24, 48):
        contact = strip_normal(gap, ESTAR, approach=h.approach, strips=count)
        errors.append(abs(contact.max_pressure / h.max_pressure - 1))
    assert errors[2] < errors[1] < errors[0], f"p0 errors at 12, 24, 48 strips: {errors}"
    assert errors[2] < 1e-3, f"p0 at 48 strips off by {errors[2]:.2e}"


@pytest.mark.parametrize("make", [lambda: quadratic(0.5)[0], two_wells, varying_curvature])
def test_load_and_approach_entry_points_agree(make):
    gap = make()
    by_load = strip_normal(gap, ESTAR, normal_load=4e4)
    assert by_load.converged, by_load.message
    by_approach = strip_normal(gap, ESTAR, approach=by_load.approach)
    assert by_approach.converged, by_approach.message
    assert math.isclose(by_approach.normal_load, 4e4, rel_tol=5e-3), \
        f"Fn at the load's approach {by_approach.normal_load:.6g} N, not 4e4 N"


@pytest.mark.parametrize("make", [lambda: quadratic(2.0)[0], two_wells, varying_curvature])
def test_load_balance(make):
    contact = strip_normal(make(), ESTAR, normal_load=3e4)
    carried = float(contact.widths @ contact.loads_per_width)
    assert math.isclose(carried, 3e4, rel_tol=1e-9), f"the strips carry {carried:.9g} N of 3e4 N"


def test_two_separate_intervals_make_two_lobes():
    gap = two_wells()
    contact = strip_normal(gap, ESTAR, approach=12e-6)
    assert contact.converged, contact.message
    runs = np.flatnonzero(np.diff(np.concatenate([[0], contact.contact.astype(int), [0]])) == 1)
    assert runs.size == 2, f"{runs.size} runs of strips in contact on two wells"
    left = contact.loads_per_width[contact.centres < 4e-3] @ contact.widths[contact.centres < 4e-3]
    right = contact.loads_per_width[contact.centres > 4e-3] @ contact.widths[contact.centres > 4e-3]
    assert left > right > 0.0, f"the deeper well carries {left:.4g} N, the shallower {right:.4g} N"


@pytest.mark.parametrize("make", [two_wells, varying_curvature])
def test_mirror_symmetry(make):
    gap = make()
    one = strip_normal(gap, ESTAR, normal_load=5e4)
    other = strip_normal(mirrored(gap), ESTAR, normal_load=5e4)
    tolerance = 1e-6  # the fixed point's: its iterates differ in round-off from the mirror's
    assert math.isclose(one.approach, other.approach, rel_tol=tolerance), "the mirrored gap's approach"
    assert math.isclose(one.max_pressure, other.max_pressure, rel_tol=tolerance), "the mirrored gap's peak pressure"
    low, high = one.extent
    mirror_low, mirror_high = other.extent
    assert math.isclose(low, -mirror_high, rel_tol=tolerance) and math.isclose(high, -mirror_low, rel_tol=tolerance), \
        f"extents {one.extent} and mirrored {other.extent}"


def test_the_curvature_along_x_shapes_the_strips():
    """Where A(s) is larger the strips are shorter: the varying gap's strips against the same gap at constant A."""
    gap = varying_curvature()
    flat = PatchGap(gap.lateral, gap.lateral_gap, np.full(len(gap.lateral), 1.1))
    varying, constant = (strip_normal(g, ESTAR, normal_load=5e4) for g in (gap, flat))
    inside = varying.contact
    ratio = np.interp(varying.centres[inside], constant.centres[constant.contact],
                      constant.half_lengths[constant.contact]) / varying.half_lengths[inside]
    right = (varying.centres[inside] > 1e-3) & (varying.centres[inside] < 0.8 * varying.extent[1])
    assert np.all(ratio[right] > 1.0), f"where A grows (s > 0) the strips are shorter than at constant A: {ratio}"


def test_no_interpenetration_no_contact():
    gap, _ = quadratic(1.0)
    contact = strip_normal(gap, ESTAR, approach=0.0)
    assert contact.converged and contact.normal_load == 0.0 and not contact.contact.any(), contact.message


def test_a_gap_sampled_too_narrowly_is_reported():
    gap, scene = quadratic(1.0, span=0.8)
    contact = strip_normal(gap, ESTAR, approach=scene.hertz.approach)
    assert not contact.converged, "the contact reaching the end of the gap's samples must not pass as converged"
    assert "sampling" in contact.message, contact.message


def test_arguments_are_checked():
    gap, _ = quadratic(1.0)
    with pytest.raises(ValueError, match="exactly one"):
        strip_normal(gap, ESTAR, approach=1e-5, normal_load=1e4)
    with pytest.raises(ValueError, match="strips"):
        strip_normal(gap, ESTAR, approach=1e-5, strips=2)
    with pytest.raises(ValueError, match="increase"):
        strip_normal(PatchGap(np.array([0.0, 0.0, 1.0]), np.zeros(3), np.ones(3)), ESTAR, approach=1e-5)


JUMP = 1e-5
"""Largest departure of an increment of Fn from the mean of its neighbours', relative to Fn, over a scan of the
approach: Newton's tolerance on the solution is 1e-6 of its largest change, the smooth law's own third differences
at this step are below 1e-9, and a strip entering or leaving the contact stepped Fn by about 1e-2."""


def test_the_normal_force_is_continuous_and_increasing_in_the_approach(track, wheelset):
    """The flange patch of the Manchester wheelset shifted by 9 mm (a/b about 20), over approaches where strips of a
    fixed placement would enter the contact."""
    gap = WheelRailScene(track, wheelset, lateral_shift=9e-3, vertical_load_left=1e4,
                         vertical_load_right=1e4).contacts[1].patches[0].gap
    approaches = np.linspace(34e-6, 46e-6, 241)
    loads = np.array([strip_normal(gap, ESTAR, approach=d).normal_load for d in approaches])
    steps = np.diff(loads)
    jumps = np.abs(steps[1:-1] - 0.5 * (steps[:-2] + steps[2:])) / loads[2:-1]
    k = int(np.argmax(jumps))
    assert jumps[k] < JUMP, f"Fn steps by {jumps[k]:.2e} of itself at an approach of {approaches[k + 2] * 1e6:.3f} um"
    assert np.all(steps > 0.0), f"Fn falls as the approach grows at {approaches[1:][steps <= 0.0]} m"


@pytest.mark.parametrize("make", [lambda: quadratic(2.0)[0], two_wells])
def test_a_start_nearby_gives_the_same_solution(make):
    gap = make()
    start = strip_normal(gap, ESTAR, normal_load=3e4)
    fresh = strip_normal(gap, ESTAR, normal_load=4e4)
    resumed = strip_normal(gap, ESTAR, normal_load=4e4, start=start)
    assert resumed.converged, resumed.message
    assert math.isclose(resumed.approach, fresh.approach, rel_tol=1e-6), \
        f"approach {resumed.approach!r} m from the start, {fresh.approach!r} m afresh"
    assert len(resumed.newton_steps) <= len(fresh.newton_steps), "the start saves none of Newton's steps"
    assert resumed.start == "resumed", f"the solution says it started from {resumed.start!r}"
    same = strip_normal(gap, ESTAR, approach=resumed.approach, start=resumed)
    assert same is resumed, "a start at the same approach is the solution, returned as it is"


PATHS = {"hertz": [("_hertzian", True)], "hertz, lobe joined": [("_placements", True), ("_hertzian", True)],
         "first pass": [("_hertzian", False), ("_from_first_pass", True)]}
"""The starts of :func:`test_newton_alone_gives_the_fixed_points_solution` (``StripContact.start``) and the calls
that take them, as they return (inner first)."""


@pytest.mark.parametrize("make, start, load", [
    (lambda: quadratic(0.5)[0], "hertz", 3e4), (varying_curvature, "hertz", 3e4), (two_wells, "hertz", 3e4),
    (shelf, "hertz", 8e4), (lambda: shelf(0.8), "hertz, lobe joined", 8e4), (three_wells, "first pass", 3e4)])
@pytest.mark.parametrize("given", ["normal_load", "approach"])
def test_newton_alone_gives_the_fixed_points_solution(monkeypatch, make, start, load, given):
    """A gap whose rigid interpenetration at Hertz's approach is one run or two (two wells: two lobes) is solved by
    Newton's method from Hertz's ellipse laid over their deepest parts (on a shelf beside a well the lobe stays in
    the well, where the contact is; a lower shelf takes a second lobe at its far end, joined to Newton's solution
    of the well by the placements); three runs (three wells) by Newton's method from the first pass's lobes; each
    without the first pass's fixed point, to its solution (the approach or the load within 1e-6, the loads per
    width within 1e-5 of the largest)."""
    import rollcontact.wheelrail.methods.strip_normal as module

    gap = make()
    value = load if given == "normal_load" else strip_normal(gap, ESTAR, normal_load=load).approach
    taken = []

    def recorded(name):
        function = getattr(module, name)

        def wrapper(*arguments):
            out = function(*arguments)
            taken.append((name, out is not None))
            return out
        return wrapper

    for name in ("_hertzian", "_from_first_pass", "_placements"):
        monkeypatch.setattr(module, name, recorded(name))
    direct = strip_normal(gap, ESTAR, **{given: value})
    assert direct.converged, direct.message
    assert taken == PATHS[start], f"the paths taken: {taken}"
    assert direct.start == start, f"the solution says it started from {direct.start!r}"
    monkeypatch.setattr(module, "_hertzian", lambda *a: None)
    monkeypatch.setattr(module, "_from_first_pass", lambda *a: None)
    by_fixed_point = strip_normal(gap, ESTAR, **{given: value})
    assert by_fixed_point.converged, by_fixed_point.message
    assert by_fixed_point.start == "placements", f"the passes say they started from {by_fixed_point.start!r}"
    for name in ("approach", "normal_load"):
        assert math.isclose(getattr(direct, name), getattr(by_fixed_point, name), rel_tol=1e-6), \
            f"{name}: {getattr(direct, name)!r} by Newton alone, {getattr(by_fixed_point, name)!r} by the fixed point"
    assert len(direct.lobes) == len(by_fixed_point.lobes) and direct.centres.size == by_fixed_point.centres.size, \
        "the same lobes and strips"
    difference = np.abs(direct.loads_per_width - by_fixed_point.loads_per_width).max()
    assert difference <= 1e-5 * by_fixed_point.loads_per_width.max(), f"loads per width differ by {difference:.3g} N/m"


@pytest.mark.parametrize("make", [lambda: quadratic(0.5)[0], two_wells, varying_curvature])
@pytest.mark.parametrize("given", [{"normal_load": 5e-324}, {"normal_load": 1e-300}, {"normal_load": 1e-30},
                                   {"approach": 5e-324}, {"approach": 1e-300}, {"approach": 1e-20}])
def test_loads_and_approaches_at_the_ends_of_floating_point(make, given):
    """A load or approach so small that the contact underflows: a StripContact, no exception and no numpy warning;
    converged (no contact, or the load carried) or not with the reason and a number in it."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        contact = strip_normal(make(), ESTAR, **given)
    if contact.converged:
        carried = float(contact.widths @ contact.loads_per_width) if contact.centres.size else 0.0
        assert math.isclose(carried, contact.normal_load, rel_tol=1e-6, abs_tol=1e-300), contact.message
    else:
        assert any(ch.isdigit() for ch in contact.message), contact.message


def test_the_runs_of_the_rigid_interpenetration():
    """rigid_runs: a quadratic gap one run about its minimum, ends where the parabola crosses the depth (to the linear
    interpolation's error between samples); two wells two runs, each with its least gap; rigid_range their hull; an
    interpenetration that reaches the end of the sampling none."""
    gap, _ = quadratic(1.0)
    s, h = np.asarray(gap.lateral), np.asarray(gap.lateral_gap)
    curvature = (h[-1] - h.min()) / s[-1] ** 2
    depth = 0.25 * float(h.max())
    (lo, hi, least), = rigid_runs(s, h, depth)
    half = math.sqrt(depth / curvature)
    step = float(s[1] - s[0])
    assert abs(lo + half) < 0.25 * step and abs(hi - half) < 0.25 * step, f"ends {lo!r}, {hi!r} m, +-{half!r} m"
    assert least == float(h.min())
    wells = two_wells()
    s, h = np.asarray(wells.lateral), np.asarray(wells.lateral_gap)
    runs = rigid_runs(s, h, 5e-5)
    assert len(runs) == 2 and runs[0][1] < runs[1][0], runs
    ridge = 4e-3  # halfway between the wells
    assert (runs[0][2], runs[1][2]) == (float(h[s < ridge].min()), float(h[s > ridge].min())), "each run's least gap"
    assert rigid_range(s, h, 5e-5) == (runs[0][0], runs[1][1]), "the hull of the runs"
    assert rigid_runs(s, h, 10.0) == [] and rigid_range(s, h, 10.0) is None, "beyond the sampling: none"
