"""The wheelset's contact through its geometry table (:mod:`rollcontact.wheelrail.tabulated`) against the library's
``hertz`` level on a fresh contact search (oracle: the same physics from the search, at the table's nodes where the
geometry is the search's own), and its identities: load balance, mirror symmetry, dissipation, zero creepage without
tangential force (the library's kinematics as the oracle), a lifted wheel."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rollcontact import Coulomb, Material
from rollcontact.wheelrail import dispatch
from rollcontact.wheelrail.geometry import Pose, Velocities
from rollcontact.wheelrail.loads import WheelsetLoads, wheelset_loads
from rollcontact.wheelrail.normal import rigid_position
from rollcontact.wheelrail.scene import WheelRailScene
from rollcontact.wheelrail.search import ContactPoint, creepages
from rollcontact.wheelrail.tabulated import COLUMN, TabulatedWheelset

V = 30.0
R0 = 0.46
Q = 8e4
MIRRORED = {"force_y", "moment_roll", "moment_yaw", "lateral_force"}
"""The loads whose sign the mirror image y -> -y changes (the others keep it; left and right swap): the lateral ones
and the moment's x and z components (a pseudovector)."""
SWAP = {"left": "right", "right": "left"}


@pytest.fixture(scope="module", params=("saturated", "linear"))
def tabulated(request, contact_table, wheelset):
    return TabulatedWheelset(contact_table, wheelset, Material(), Coulomb(0.3), request.param)


def nodes_near(table, shifts):
    """The table's node shifts nearest each of ``shifts`` (where the tabulated geometry is the search's own)."""
    nodes = table.functions[0].shift
    return [float(nodes[np.argmin(np.abs(nodes - y))]) for y in shifts]


def library_loads(track, wheelset, law, y, yaw=0.0, vy=0.0, rate=0.0, pitch=-V / R0, left=Q, right=Q):
    pose = rigid_position(track, wheelset, y, yaw)[0]
    scene = WheelRailScene(track, wheelset, y, yaw, pose.roll, left, right, V, vy, rate, pitch, Material(),
                           Coulomb(0.3))
    result = dispatch.solve(scene, "hertz", elliptic=law)
    assert result.success, result.message
    assert all(len(w.patches) <= 1 for w in result.wheels), f"y = {y}: more than one patch per wheel"
    return wheelset_loads(scene, result)


@pytest.mark.parametrize("y", (-0.0035, 0.002, 0.0057))
def test_at_the_nodes_the_tabulated_contact_is_the_hertz_level_on_the_search(tabulated, track, wheelset, y):
    """At a node (zero yaw: the table's geometry is the search's), every load within 5e-5 of its size (at least Q):
    the vertical balance (the library's to a relative 1e-6) and the search repeated at the scene's pose (the
    table's at the rigid one's height) are what differ."""
    y = nodes_near(tabulated.table, [y])[0]
    row, _ = tabulated.row(y)
    got, roll, _ = tabulated.loads(row, 0.0, 0.02, 0.05, V, -V / R0, Q, Q)
    expected = library_loads(track, wheelset, tabulated.law, y, vy=0.02, rate=0.05)
    assert roll == pytest.approx(rigid_position(track, wheelset, y, 0.0)[0].roll, rel=1e-12, abs=1e-15), "roll"
    for name, a, b in zip(WheelsetLoads._fields, got, expected, strict=True):
        size = 1.0 if name.startswith(("contact_angle", "rolling_radius", "patches")) else max(abs(b), Q)
        assert abs(a - b) <= 5e-5 * size, f"y = {y}: {name} tabulated {a!r}, library {b!r}"


def test_between_the_nodes_within_the_tables_interpolation(tabulated, track, wheelset):
    """Halfway between nodes the loads follow the table's interpolation: within 1 % of Q on the forces (the
    contact angle's 1e-3 rad of TOLERANCES moves N sin(delta) by 1e-3 Q; the curvatures, interpolated without a
    bound, the creep forces by a few per mille)."""
    shift = tabulated.table.functions[0].shift
    for y in (-0.0031, 0.0017, 0.0044):
        k = int(np.searchsorted(shift, y))
        middle = 0.5 * (shift[k - 1] + shift[k])
        row, _ = tabulated.row(middle)
        got, _, _ = tabulated.loads(row, 0.0, 0.01, 0.0, V, -V / R0, Q, Q)
        expected = library_loads(track, wheelset, tabulated.law, middle, vy=0.01)
        for name in ("force_x", "force_y", "force_z", "moment_yaw"):
            a, b = getattr(got, name), getattr(expected, name)
            assert abs(a - b) <= 1e-2 * Q, f"y = {middle}: {name} tabulated {a!r}, library {b!r}"


def test_the_loads_carry_the_vertical_loads(tabulated):
    """Each wheel's vertical force is its load Q (the balance of the normal and tangential forces' z components,
    one pass, or two where the tangential forces carry part of it)."""
    for y, left, right in ((0.001, 7e4, 9e4), (0.0055, Q, Q), (0.0075, 6e4, 1.1e5)):
        row, _ = tabulated.row(y)
        got, _, _ = tabulated.loads(row, 0.002, 0.1, 0.0, V, -V / R0, left, right)
        for side, load in (("left", left), ("right", right)):
            vertical = getattr(got, f"vertical_force_{side}")
            assert abs(vertical + load) <= 2e-2 * load, f"y = {y}, {side}: vertical force {vertical!r} for {load!r}"


def test_mirror_symmetry(tabulated):
    """The mirror image (y, yaw, velocities -> their negatives) swaps the wheels and reverses the lateral loads, to
    the table's symmetry (its refinement bisects in floating point)."""
    for y, yaw, vy, rate in ((0.0023, 0.001, 0.03, -0.02), (0.0061, -0.002, -0.05, 0.1)):
        plus = tabulated.loads(tabulated.row(y)[0], yaw, vy, rate, V, -V / R0, 7e4, 9e4)[0]
        minus = tabulated.loads(tabulated.row(-y)[0], -yaw, -vy, -rate, V, -V / R0, 9e4, 7e4)[0]
        for name, value in plus._asdict().items():
            base, _, side = name.rpartition("_")
            other = f"{base}_{SWAP[side]}" if side in SWAP else name
            mirrored = getattr(minus, other) * (-1.0 if (base if side in SWAP else name) in MIRRORED else 1.0)
            assert abs(value - mirrored) <= 1e-6 * max(abs(value), Q), f"y = {y}: {name} {value!r}, mirror {mirrored!r}"


def test_the_linear_law_dissipates(contact_table, wheelset):
    """Kalker's linear theory puts power into the contacts at any creepages, V (xi Fx + eta Fy + phi Mz) >= 0: its
    spin cross terms (C23) cancel in the power."""
    linear = TabulatedWheelset(contact_table, wheelset, Material(), Coulomb(0.3), "linear")
    rng = np.random.default_rng(3)
    for y, yaw, vy, rate, pitch in rng.uniform([-0.007, -0.005, -0.2, -0.3, -1.02 * V / R0],
                                               [0.007, 0.005, 0.2, 0.3, -0.98 * V / R0], size=(40, 5)):
        got = linear.loads(linear.row(y)[0], yaw, vy, rate, V, pitch, Q, Q)[0]
        for side in ("left", "right"):
            power = getattr(got, f"frictional_power_{side}")
            assert power >= -1e-9 * Q * V, f"y = {y}: {side} wheel's frictional power {power!r} W < 0"


def test_pure_rolling_of_the_centred_wheelset_has_no_longitudinal_force(tabulated):
    """Centred, rolling at the contact's own radius, no yaw: xi = 0 on both wheels, so no longitudinal force; the
    spin's lateral forces cancel between the wheels; the wheelset carries both loads (to the share the spin's
    lateral forces take of them: one pass of the vertical balance with them)."""
    row, _ = tabulated.row(0.0)
    radius = row[COLUMN["right_rolling_radius"]]
    got = tabulated.loads(row, 0.0, 0.0, 0.0, V, -V / radius, Q, Q)[0]
    assert abs(got.force_x) <= 1e-9 * Q and abs(got.moment_yaw) <= 1e-9 * Q, \
        f"Fx {got.force_x!r}, Mz {got.moment_yaw!r}"
    assert abs(got.longitudinal_force_left) <= 1e-9 * Q, f"left Fx {got.longitudinal_force_left!r}"
    assert abs(got.force_y) <= 1e-9 * Q, f"the spin's lateral forces do not cancel: {got.force_y!r}"
    assert got.force_z == pytest.approx(-2 * Q, rel=1e-3), f"Fz {got.force_z!r}"


def test_a_lifted_wheel_carries_nothing(tabulated):
    row, _ = tabulated.row(0.003)
    got, _, vertical = tabulated.loads(row, 0.0, 0.05, 0.0, V, -V / R0, 0.0, Q)
    for name in ("normal_force", "longitudinal_force", "lateral_force", "vertical_force", "frictional_power"):
        assert getattr(got, f"{name}_left") == 0.0, f"the lifted left wheel's {name} is not 0"
    assert got.patches_left == 0 and got.patches_right == 1, f"patches {got.patches_left}, {got.patches_right}"
    assert got.force_z == pytest.approx(-Q, rel=2e-2), f"the loaded wheel carries Fz {got.force_z!r}"
    assert math.isfinite(vertical), vertical
    nothing = tabulated.loads(row, 0.0, 0.05, 0.0, V, -V / R0, 0.0, 0.0)[0]
    assert all(v == 0 for v in nothing), f"no load, yet loads {nothing}"


def test_zero_creepage_is_zero_tangential_force(contact_table, wheelset):
    """With the right wheel alone loaded and the pitch rate, yaw rate and lateral velocity that zero its creepages
    (the library's kinematics, rollcontact.wheelrail.search.creepages, at the wheel's lowest point R_z R_x (0, Y, r)),
    it carries its load by the normal force alone: no tangential force, no frictional power, vertical force Q, lateral
    force Q tan(delta)."""
    linear = TabulatedWheelset(contact_table, wheelset, Material(), Coulomb(0.3), "linear")
    y, yaw = 0.0023, 0.001
    row, _ = linear.row(y)
    roll, height = row[0], row[1]
    delta, radius = row[COLUMN["right_contact_angle"]], row[COLUMN["right_rolling_radius"]]
    axle = wheelset.taping_line + row[COLUMN["right_wheel_lateral"]]
    v = axle * math.cos(roll) - radius * math.sin(roll)
    lever = (-v * math.sin(yaw), v * math.cos(yaw), axle * math.sin(roll) + radius * math.cos(roll))
    point = ContactPoint(0.0, 0.0, delta, radius, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                         (lever[0], y + lever[1], height - R0 + lever[2]), "right")
    pose = Pose(y, yaw, roll, height)

    def creeps(x):
        return np.array(creepages(wheelset, pose, Velocities(V, x[2], x[1], x[0]), point))

    x0 = np.array([-V / R0, 0.0, 0.0])
    base = creeps(x0)
    columns = [creeps(x0 + d) - base for d in np.diag([1.0, 1.0, 1.0])]
    x = x0 - np.linalg.solve(np.column_stack(columns), base)
    assert np.max(np.abs(creeps(x))) < 1e-14, f"creepages {creeps(x)}"
    loads = linear.loads(row, yaw, x[2], x[1], V, x[0], 0.0, Q)[0]
    assert abs(loads.longitudinal_force_right) <= 1e-9 * Q, f"Fx {loads.longitudinal_force_right!r}"
    assert loads.lateral_force_right == pytest.approx(-Q * math.tan(delta), rel=1e-9), \
        f"the lateral force is not the normal force's: {loads.lateral_force_right!r}"
    assert loads.vertical_force_right == pytest.approx(-Q, rel=1e-12), f"Fz {loads.vertical_force_right!r}"
    assert abs(loads.frictional_power_right) <= 1e-9 * Q * V, f"power {loads.frictional_power_right!r} W"
