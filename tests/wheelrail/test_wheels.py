"""The wheels around their patch level: a wheel at the strips level carries its vertical load, tangential forces
included, to the passes' tolerance where its patch is in flange-root contact; a wheel of one patch solved for its
force at once gives the vertical balance's answer; the first pass's predicted share of the load is the tread's; a
solve started from the normal solutions of the same geometry, or the strips' of a pose nearby, gives the fresh
answer."""

from __future__ import annotations

import math

import pytest

from rollcontact.wheelrail.dispatch import solve
from rollcontact.wheelrail.methods import discretised, strips
from rollcontact.wheelrail.scene import WheelRailScene
from rollcontact.wheelrail.wheels import COUPLING, predicted_ratio, solve_wheels

LOAD_TOLERANCE = COUPLING
"""Relative difference of a wheel's vertical force from its load: the passes stop within ``COUPLING`` of it."""


@pytest.mark.parametrize("yaw_rate", [0.0, 0.01])
def test_a_wheel_in_flange_root_contact_carries_its_load(track, wheelset, yaw_rate):
    scene = WheelRailScene(track, wheelset, lateral_shift=6.5e-3, vertical_load_left=1e4, vertical_load_right=1e4,
                           forward_speed=2.0, yaw_rate=yaw_rate, friction=0.3)
    result = solve(scene, "strips")
    assert result.success, result.message
    for wheel in result.wheels:
        error = wheel.force[2] / wheel.vertical_load - 1.0
        assert abs(error) < LOAD_TOLERANCE, \
            f"yaw rate {yaw_rate} rad/s, {wheel.side} wheel: Fz = {wheel.force[2]:.6g} N for {wheel.vertical_load} N"


BALANCE_AGREEMENT = 1e-5
"""Relative difference of the patches' normal forces and force coefficients (over mu N) between a wheel solved for
its force at once and by the vertical balance, which stops at 1e-6 of the load (``BALANCE_TOLERANCE``), at the strips
and the discretised level."""


@pytest.mark.parametrize(("level", "shift"), [(strips.LEVEL, s) for s in (0.0, 3e-3, 6.5e-3, 9e-3)]
                         + [(discretised.LEVEL, s) for s in (0.0, 6.5e-3)], ids=lambda v: getattr(v, "name", v))
def test_a_wheel_of_one_patch_solved_for_its_force_is_the_balance_answer(track, wheelset, level, shift):
    scene = WheelRailScene(track, wheelset, lateral_shift=shift, yaw=2e-4 * shift / 1e-3, vertical_load_left=1e4,
                           vertical_load_right=1.2e4, forward_speed=2.0, yaw_rate=0.01, friction=0.3)
    calls = []

    def normal(*arguments):
        calls.append(arguments[1])
        return level.normal(*arguments)

    at_once = solve_wheels(scene, level._replace(normal=normal))
    assert not calls, f"the balance iterated on the normal law at approaches {calls}"
    balanced = solve_wheels(scene, level._replace(loaded=None))
    assert at_once.success and balanced.success, (at_once.message, balanced.message)
    for wheel, reference in zip(at_once.wheels, balanced.wheels, strict=True):
        assert len(wheel.patches) == len(reference.patches) == 1, f"{wheel.side}: one patch at {shift} m"
        p, q = wheel.patches[0].result, reference.patches[0].result
        scale = q.friction_coefficient * q.normal_load
        for name, a, b in (("N", p.normal_load / q.normal_load, 1.0), ("Fx", p.longitudinal_force / scale,
                                                                        q.longitudinal_force / scale),
                           ("Fy", p.lateral_force / scale, q.lateral_force / scale)):
            assert abs(a - b) < BALANCE_AGREEMENT, f"shift {shift} m, {wheel.side} wheel: {name} {a!r} against {b!r}"
        assert abs(wheel.force[2] / wheel.vertical_load - 1.0) < LOAD_TOLERANCE, f"{wheel.side}: Fz {wheel.force[2]}"


@pytest.mark.parametrize("shift", [2e-3, 3e-3, 4e-3])
def test_a_tread_wheel_takes_one_pass_from_the_predicted_share(track, wheelset, shift):
    """On the tread (contact angles of a few hundredths) the saturated theory's share of the load
    (``predicted_ratio``) is the strips' own to within the passes' tolerance, so that each wheel's patch is solved
    once; the prediction has the sign and size of the strips' share (a wrong sign or a missing ``sin(delta)`` fails
    here: the share is 5 to 30 times the tolerance)."""
    scene = WheelRailScene(track, wheelset, lateral_shift=shift, yaw=2e-4 * shift / 1e-3, vertical_load_left=1e4,
                           vertical_load_right=1.2e4, forward_speed=2.0, lateral_velocity=-0.02, yaw_rate=0.01,
                           friction=0.3)
    solves = []
    level = strips.LEVEL

    def counted(*arguments, **options):
        solves.append(arguments[0].name)
        return level.solve(*arguments, **options)

    result = solve_wheels(scene, level._replace(solve=counted))
    assert result.success, result.message
    assert len(solves) == 2, f"shift {shift} m: patch solves {solves} (one per wheel)"
    shares = []
    for wheel in result.wheels:
        patch = wheel.patches[0]
        share = (patch.track_force[2] - patch.result.normal_load * math.cos(patch.point.contact_angle)) \
            / patch.result.normal_load
        predicted = predicted_ratio(scene, patch.point, wheel.vertical_load / math.cos(patch.point.contact_angle))
        assert abs(predicted - share) < COUPLING, f"shift {shift} m, {wheel.side}: predicted {predicted!r}, {share!r}"
        shares.append(abs(share))
    assert max(shares) > 5.0 * COUPLING, f"shift {shift} m: shares {shares} (the test's premise)"


def test_a_share_beyond_floating_point_is_none(track, wheelset):
    """Creepages near 1e306 (a lateral velocity at a forward speed of 1e-306 m/s) take the saturated theory's
    lateral force to inf * 0: the predicted share is 0, never NaN (which would leave the first pass no normal
    force); a force of 5e-324 N, whose friction bound underflows to 0, is deep saturation, not a division by zero."""
    scene = WheelRailScene(track, wheelset, lateral_shift=2e-3, vertical_load_left=1e4, vertical_load_right=1e4,
                           forward_speed=1e-306, lateral_velocity=1.0, friction=0.3)
    for contact, hertz in zip(scene.contacts, scene.hertz, strict=True):
        point = contact.points[0]
        share = predicted_ratio(scene, point, hertz.normal_forces[0])
        assert share == 0.0, f"{contact.side}: predicted share {share!r}"
    ordinary = WheelRailScene(track, wheelset, lateral_shift=2e-3, vertical_load_left=1e4, vertical_load_right=1e4,
                              forward_speed=2.0, lateral_velocity=-0.02, friction=0.3)
    point = ordinary.contacts[1].points[0]
    share = predicted_ratio(ordinary, point, 5e-324)  # mu N underflows to 0: u infinite, no division by zero
    assert math.isfinite(share) and abs(share) <= 0.3 * math.sin(point.contact_angle), f"share {share!r} at 5e-324 N"


STARTS_AGREEMENT = 2e-6
"""Relative difference of the patches' normal forces and force coefficients (over mu N) between a wheel solved from
the normal solutions of a scene of nearby velocities (``starts``) and one solved afresh: both solve each normal
problem to 1e-6 (``FIXED_POINT_TOLERANCE``); a start within it of its load is taken as it is."""


@pytest.mark.parametrize(("level", "shift"), [(strips.LEVEL, s) for s in (0.0, 6.5e-3, 9e-3)]
                         + [(discretised.LEVEL, 6.5e-3)], ids=lambda v: getattr(v, "name", v))
def test_starts_of_the_same_geometry_give_the_fresh_answer(monkeypatch, track, wheelset, level, shift):
    """A scene of other velocities on the same geometry (``with_velocities``) solved from a solve's normal solutions
    carries the fresh solve's forces to the tolerance; the strips' normal problems are then taken as they are or
    resumed (each pass from the start's same pass), never started afresh from Hertz's ellipse."""
    import rollcontact.wheelrail.methods.strip_normal as normal_module

    base = WheelRailScene(track, wheelset, lateral_shift=shift, yaw=2e-4 * shift / 1e-3, vertical_load_left=8e4,
                          vertical_load_right=8e4, forward_speed=30.0, yaw_rate=0.01, friction=0.3)
    first = solve_wheels(base, level)
    moved = base.with_velocities(lateral_velocity=1e-5 * 30.0, yaw_rate=0.01 + 1e-5)
    fresh = solve_wheels(moved, level)
    afresh = []
    hertzian = normal_module._hertzian
    monkeypatch.setattr(normal_module, "_hertzian", lambda *a: afresh.append(a[5]) or hertzian(*a))
    started = solve_wheels(moved, level, starts=first)
    monkeypatch.undo()
    if level is strips.LEVEL:
        assert not afresh, f"normal problems started afresh at the loads {afresh} N"
    assert first.success and started.success and fresh.success, (first.message, started.message, fresh.message)
    assert all(len(w.normal_states) == len(c.patches) for w, c in zip(first.wheels, base.contacts, strict=True)), \
        "a normal state per patch of each wheel's contact"
    for wheel, reference in zip(started.wheels, fresh.wheels, strict=True):
        assert len(wheel.patches) == len(reference.patches), f"{wheel.side}: the same patches"
        for p, q in zip(wheel.patches, reference.patches, strict=True):
            p, q = p.result, q.result
            scale = q.friction_coefficient * q.normal_load
            for name, a, b in (("N", p.normal_load / q.normal_load, 1.0),
                               ("Fx", p.longitudinal_force / scale, q.longitudinal_force / scale),
                               ("Fy", p.lateral_force / scale, q.lateral_force / scale)):
                assert abs(a - b) < STARTS_AGREEMENT, f"shift {shift} m, {wheel.side} wheel: {name} {a!r} against {b!r}"


@pytest.mark.parametrize("moved", [{"lateral_shift": 6.5e-3 + 1e-6}, {"yaw": 1.3e-3 + 1e-6}],
                         ids=["shift", "yaw"])
def test_starts_of_a_pose_nearby(monkeypatch, track, wheelset, moved):
    """Normal solutions of a pose a little away (other gaps) start the strips' Newton's method (``nearby``): the
    fresh answer to the tolerance, no normal problem started from Hertz's ellipse; the discretised level takes none
    (the fresh answer bit for bit); a start that is not a wheel/rail result is refused."""
    import rollcontact.wheelrail.methods.strip_normal as normal_module

    scene = WheelRailScene(track, wheelset, lateral_shift=6.5e-3, yaw=1.3e-3, vertical_load_left=8e4,
                           vertical_load_right=8e4, forward_speed=30.0, yaw_rate=0.01, friction=0.3)
    shifted = scene.replace(**moved)
    base, fresh = solve_wheels(scene, strips.LEVEL), solve_wheels(shifted, strips.LEVEL)
    afresh = []
    hertzian = normal_module._hertzian
    monkeypatch.setattr(normal_module, "_hertzian", lambda *a: afresh.append(a[5]) or hertzian(*a))
    started = solve_wheels(shifted, strips.LEVEL, starts=base)
    monkeypatch.undo()
    assert not afresh, f"normal problems started afresh at the loads {afresh} N"
    for wheel, reference in zip(started.wheels, fresh.wheels, strict=True):
        for p, q in zip(wheel.patches, reference.patches, strict=True):
            p, q = p.result, q.result
            scale = q.friction_coefficient * q.normal_load
            for name, a, b in (("N", p.normal_load / q.normal_load, 1.0),
                               ("Fy", p.lateral_force / scale, q.lateral_force / scale)):
                assert abs(a - b) < STARTS_AGREEMENT, f"{moved}, {wheel.side} wheel: {name} {a!r} against {b!r}"
    base = solve_wheels(scene, discretised.LEVEL)
    started, fresh = solve_wheels(shifted, discretised.LEVEL, starts=base), solve_wheels(shifted, discretised.LEVEL)
    for wheel, reference in zip(started.wheels, fresh.wheels, strict=True):
        assert wheel.force == reference.force, f"discretised, {wheel.side}: {wheel.force} against {reference.force}"
    with pytest.raises(TypeError, match="starts must be a WheelRailResult"):
        solve_wheels(scene, strips.LEVEL, starts=base.wheels)


def test_a_pass_the_start_did_not_load_keeps_the_patch_own_state(monkeypatch, track, wheelset):
    """Where the start's patch carried nothing in a pass (its state None), the patch goes on from its own last normal
    solution rather than afresh: no normal problem starts from Hertz's ellipse."""
    import dataclasses

    import rollcontact.wheelrail.methods.strip_normal as normal_module

    scene = WheelRailScene(track, wheelset, lateral_shift=6.5e-3, yaw=1.3e-3, vertical_load_left=8e4,
                           vertical_load_right=8e4, forward_speed=30.0, yaw_rate=0.01, friction=0.3)
    base = solve_wheels(scene, strips.LEVEL)
    passes = [len(states) for wheel in base.wheels for _, states in wheel.normal_states]
    assert max(passes) >= 2, f"a wheel of two passes to test on, got {passes}"
    wheels = tuple(dataclasses.replace(wheel, normal_states=tuple((gap, (states[0], *(None,) * (len(states) - 1)))
                                                                  for gap, states in wheel.normal_states))
                   for wheel in base.wheels)
    afresh = []
    hertzian = normal_module._hertzian
    monkeypatch.setattr(normal_module, "_hertzian", lambda *a: afresh.append(a[5]) or hertzian(*a))
    started = solve_wheels(scene, strips.LEVEL, starts=dataclasses.replace(base, wheels=wheels))
    assert started.success, started.message
    assert not afresh, f"normal problems started afresh at the loads {afresh} N"
