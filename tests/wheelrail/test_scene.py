"""The patch scene's checks and its mirror image; the patch result's normalised forces."""

from __future__ import annotations

import math

import numpy as np
import pytest
from wheelrail_gaps import two_wells

from rollcontact import Coulomb
from rollcontact.core.checks import SceneError
from rollcontact.wheelrail.result import PatchResult
from rollcontact.wheelrail.scene import PatchScene


def test_exactly_one_of_load_and_approach():
    with pytest.raises(SceneError, match="exactly one"):
        PatchScene(two_wells())
    with pytest.raises(SceneError, match="exactly one"):
        PatchScene(two_wells(), normal_load=1e4, approach=1e-5)
    with pytest.raises(SceneError, match="normal_load"):
        PatchScene(two_wells(), normal_load=-1.0)
    scene = PatchScene(two_wells(), normal_load=1e4, friction=0.25)
    assert scene.friction == Coulomb(0.25)
    moved = scene.replace(approach=2e-5)
    assert moved.normal_load is None and moved.approach == 2e-5, "replace swaps the load for the approach"


def test_mirrored_scene_reverses_the_lateral_direction():
    scene = PatchScene(two_wells(), normal_load=1e4, longitudinal_creepage=1e-3, lateral_creepage=2e-3,
                       spin_creepage=0.5)
    mirror = scene.mirrored
    assert (mirror.longitudinal_creepage, mirror.lateral_creepage, mirror.spin_creepage) == (1e-3, -2e-3, -0.5)
    s = np.asarray(scene.gap.lateral)
    assert np.array_equal(np.asarray(mirror.gap.lateral), -s[::-1]), "s -> -s"
    assert np.array_equal(np.asarray(mirror.gap.lateral_gap), np.asarray(scene.gap.lateral_gap)[::-1]), "h(-s)"


def test_force_coefficients():
    result = PatchResult("strips", True, "", 1e4, 1e-5, 1e9, 8e-3, 6e-3, 600.0, -300.0, 2.0, 0.0, 0.0, 0.0, 0.3,
                         math.pi * 4e-3 * 3e-3)
    fx, fy, mz = result.force_coefficients
    assert (fx, fy) == (0.2, -0.1)
    assert math.isclose(mz, 2.0 / (3e3 * math.sqrt(12e-6))), "Mz over mu Fn sqrt(area / pi)"


def test_a_wheelset_scene_takes_its_contacts_and_shares_its_geometry(track, wheelset):
    """Given the rigid wheelset's contacts at its roll, a scene solves as if it had searched (bit for bit); contacts of
    another pose are refused; a copy with other velocities shares the contacts and Hertz's normal contact and solves
    as a new scene of those velocities does."""
    from rollcontact.wheelrail import dispatch
    from rollcontact.wheelrail.loads import wheelset_loads
    from rollcontact.wheelrail.normal import rigid_contacts
    from rollcontact.wheelrail.scene import WheelRailScene

    pose, left, right = rigid_contacts(track, wheelset, 0.0043, 0.0012)
    scene = WheelRailScene(track, wheelset, 0.0043, 0.0012, pose.roll, 7e4, 8e4, 30.0, 0.02, -0.01)
    given = scene.with_contacts((left, right))
    assert given.contacts == (left, right) and "contacts" not in scene.__dict__, "the original scene is unchanged"

    def loads(s):
        return wheelset_loads(s, dispatch.solve(s, "hertz", elliptic="saturated"))

    assert loads(given) == loads(scene), "the given contacts solve as the searched ones"
    other = WheelRailScene(track, wheelset, 0.0043, 0.0012, pose.roll + 1e-6, 7e4, 8e4, 30.0, 0.02, -0.01)
    with pytest.raises(SceneError, match="not at the scene's pose"):
        other.with_contacts((left, right))
    with pytest.raises(SceneError, match="the \\(left, right\\) wheels"):
        scene.with_contacts((right, left))
    moving = given.with_velocities(lateral_velocity=0.05, yaw_rate=0.02)
    assert moving.contacts is given.contacts and moving.hertz is given.hertz, "the geometry is shared"
    fresh = WheelRailScene(track, wheelset, 0.0043, 0.0012, pose.roll, 7e4, 8e4, 30.0, 0.05, 0.02)
    assert loads(moving) == loads(fresh), "the shared geometry solves as a new scene's"
    assert all(p.memo for c in given.contacts for p in c.patches), "Hertz's departure kept with the shared patches"
    with pytest.raises(SceneError, match="changes only"):
        given.with_velocities(roll=0.0)
