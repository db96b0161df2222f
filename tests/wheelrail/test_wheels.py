"""The wheels around their patch level: a wheel at the strips level carries its vertical load, tangential forces
included, to the passes' tolerance where its patch is in flange-root contact."""

from __future__ import annotations

import pytest

from rollcontact.wheelrail.dispatch import solve
from rollcontact.wheelrail.scene import WheelRailScene

LOAD_TOLERANCE = 1e-4
"""Relative difference of a wheel's vertical force from its load: the passes stop at 1e-5 of it
(``rollcontact.wheelrail.wheels.LOAD_TOLERANCE``); a step of the strips' normal force over the load left 1e-2."""


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
