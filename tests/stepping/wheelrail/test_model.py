"""The wheelset contact's stepping model (rollcontact.stepping.wheelrail): parameters checked all at once, the
library's answer bit for bit without the geometry table and within the table's interpolation with it, the derivatives
as forward differences of the same evaluation, mirror symmetry, a lifted wheel, refusals that name the value and the
limit, and a restored state that repeats the steps."""

from __future__ import annotations

import math

import pytest

from rollcontact import Coulomb, Material
from rollcontact.stepping import ModelError, WheelsetContactModel, WheelsetContactParameters, WheelsetContactState
from rollcontact.stepping.parameters import AUTO
from rollcontact.stepping.wheelrail.model import INCREMENTS
from rollcontact.stepping.wheelrail.parameters import METHOD_LEVELS, method_code
from rollcontact.wheelrail import dispatch
from rollcontact.wheelrail.loads import WheelsetLoads, wheelset_loads
from rollcontact.wheelrail.normal import rigid_position
from rollcontact.wheelrail.scene import WheelRailScene

H = 1e-3
V = 30.0
R0 = 0.46
Q = 8e4
RANGE = 0.008  # the tests' table (one build per process: the model's cache)
LOADS = len(WheelsetLoads._fields)


def inputs(y=0.002, yaw=0.001, vy=0.02, rate=-0.03, speed=V, pitch=-V / R0, left=Q, right=Q):
    return (y, yaw, vy, rate, speed, pitch, left, right)


def signal(n: int):
    """Varying inputs over tread and flange root (lateral shift up to 5.8 mm)."""
    return [inputs(0.0058 * math.sin(0.7 * k + 0.2), 0.002 * math.cos(0.5 * k), 0.05 * math.sin(k), 0.04 * math.cos(k),
                   V + k, -(V + k) / R0 * (1 + 1e-4 * k), Q * (1 + 0.1 * math.sin(k)), Q) for k in range(n)]


@pytest.fixture(scope="module")
def tabulated():
    return WheelsetContactModel(WheelsetContactParameters(table_range=RANGE))


def test_every_builtin_wheelrail_level_has_a_code():
    for spec in dispatch.BUILTIN:
        assert method_code(spec.name) > 0, f"{spec.name} has no FMU code in METHOD_LEVELS"
    assert [level.code for level in METHOD_LEVELS] == [1, 2, 3], "codes 1, 2, 3, append only"


def test_invalid_parameters_are_named_all_at_once():
    with pytest.raises(ModelError) as caught:
        WheelsetContactParameters(gauge=0.1, nominal_radius=-1.0, method=9, elliptic_method=8, geometry_table=2,
                                  table_range=0.0, wheel_profile=3)
    for part in ("gauge = 0.1 is out of range: it must be >= 0.5", "nominal_radius = -1.0 is out of range",
                 "method = 9 is out of range", "elliptic_method = 8 is out of range",
                 "geometry_table = 2 is out of range", "table_range = 0.0 is out of range: it must be > 0.0",
                 "wheel_profile must be a string"):
        assert part in str(caught.value), f"{part!r} not in {caught.value}"


def test_a_missing_profile_is_refused_with_its_path(tmp_path):
    with pytest.raises(ModelError, match="wheel_profile = '.*nowhere.prw'.* is not a profile file"):
        WheelsetContactModel(WheelsetContactParameters(wheel_profile=str(tmp_path / "nowhere.prw")))


def library(model, values, roll=None) -> WheelsetLoads:
    """The loads of rollcontact.wheelrail.dispatch.solve on the scene at the rigid wheelset's roll (or ``roll``)."""
    y, yaw, vy, rate, speed, pitch, left, right = values
    roll = rigid_position(model.track, model.wheelset, y, yaw)[0].roll if roll is None else roll
    scene = WheelRailScene(model.track, model.wheelset, y, yaw, roll, left, right, speed, vy, rate, pitch,
                           Material(), Coulomb(0.3))
    result = dispatch.solve(scene, model.method, budget=model.budget, **model.options)
    assert result.success, result.message
    return wheelset_loads(scene, result)


def test_without_the_table_the_model_is_the_library_bit_for_bit():
    model = WheelsetContactModel(WheelsetContactParameters(geometry_table=0, jacobian=1))
    for n, values in enumerate(signal(3)):
        got = model.step(n * H, H, values)
        assert tuple(got[:LOADS]) == tuple(library(model, values)), f"step {n}: the loads are not the library's"
        assert got.roll == rigid_position(model.track, model.wheelset, values[0], values[1])[0].roll, "roll"
        assert got.method_used == method_code("hertz"), got.method_used


SEARCHES = {0: (78, 24), 1: (26, 8)}
"""The gap scans and contact-point constructions of the four steps of signal(4) without the table, with the
derivatives (jacobian 0) and without (1): per step and wheel one construction per pose solved (the step's; with the
derivatives also the shifted lateral shift's and yaw's), and the scans of the roll's iteration at each pose."""


@pytest.mark.parametrize("jacobian", [0, 1])
def test_the_searches_of_a_step_without_the_table(monkeypatch, jacobian):
    """The search's two passes counted wherever they are called: the scene searches nothing (it is given the rigid
    wheelset's contacts), the velocities' differences nothing (they share the step's geometry), and the counts are
    SEARCHES' (a change of the roll's iteration changes them: say so there)."""
    from rollcontact.wheelrail import normal, search
    from rollcontact.wheelrail import scene as scene_module

    counts = {"scans": 0, "contacts": 0, "scene searches": 0}

    def counted(function, key):
        def wrapper(*args, **kwargs):
            counts[key] += 1
            return function(*args, **kwargs)
        return wrapper

    for module in (search, normal):
        monkeypatch.setattr(module, "scan_gap", counted(module.scan_gap, "scans"))
        monkeypatch.setattr(module, "contact_from_scan", counted(module.contact_from_scan, "contacts"))
    monkeypatch.setattr(scene_module, "search_wheel", counted(scene_module.search_wheel, "scene searches"))
    model = WheelsetContactModel(WheelsetContactParameters(geometry_table=0, jacobian=jacobian))
    rows = signal(4)
    for n, values in enumerate(rows):
        model.step(n * H, H, values)
    poses = 3 if jacobian == 0 else 1
    assert counts["contacts"] == 2 * poses * len(rows), counts
    assert counts["scene searches"] == 0, counts
    assert (counts["scans"], counts["contacts"]) == SEARCHES[jacobian], counts


def test_the_derivatives_are_forward_differences_of_the_step():
    """Each derivative output is (force at the input + its increment - force) / increment, of the model's own
    evaluation (without the table: the library's solve at the shifted pose)."""
    model = WheelsetContactModel(WheelsetContactParameters(geometry_table=0))
    values = inputs(0.0031, 0.0015, 0.04, 0.05)
    got = model.step(0.0, H, values)
    steps = (INCREMENTS["lateral_shift"], INCREMENTS["yaw"], INCREMENTS["lateral_velocity"] * V,
             INCREMENTS["yaw_rate"] * V / model.wheelset.taping_line)
    base = library(model, values)
    for j, (name, h) in enumerate(zip(("lateral_shift", "yaw", "lateral_velocity", "yaw_rate"), steps, strict=True)):
        moved = list(values)
        moved[j] += h
        other = library(model, moved)
        assert getattr(got, f"dforce_y_d{name}") == (other.force_y - base.force_y) / h, f"dforce_y_d{name}"
        assert getattr(got, f"dmoment_yaw_d{name}") == (other.moment_yaw - base.moment_yaw) / h, \
            f"dmoment_yaw_d{name}"
    assert got.dforce_y_dlateral_velocity < 0.0 < got.dforce_y_dyaw, \
        f"creep damping and yaw stiffness of the lateral force: {got.dforce_y_dlateral_velocity}, {got.dforce_y_dyaw}"


def test_with_the_table_within_its_interpolation(tabulated):
    """Through the table, where each wheel touches at one point: every force within 1 % of the wheel load of the
    library's on a fresh search (the table's interpolation, tests/wheelrail/test_tabulated.py, and the yaw's lead of
    the contact point, which a one-yaw table leaves out), the roll within 2e-6 rad.  (Where the search finds two
    points under load, the table's one carries the load of both: test_two_point_contact_is_the_tables_one_point.)"""
    untabulated = WheelsetContactModel(WheelsetContactParameters(geometry_table=0, jacobian=1))
    rows = [inputs(y, 0.0015 * math.sin(7 * y / 0.001), 0.04, -0.02) for y in (-0.0039, -0.0011, 0.0006, 0.0024,
                                                                                0.0033, 0.0057)]
    for n, values in enumerate(rows):
        got, expected = tabulated.step(n * H, H, values), untabulated.step(n * H, H, values)
        for name in ("force_x", "force_y", "force_z", "moment_yaw", "lateral_force_left", "lateral_force_right"):
            a, b = getattr(got, name), getattr(expected, name)
            assert abs(a - b) <= 1e-2 * Q, f"step {n}: {name} {a!r} with the table, {b!r} without"
        assert abs(got.roll - expected.roll) <= 2e-6, f"step {n}: roll {got.roll!r}, {expected.roll!r}"


def test_two_point_contact_is_the_tables_one_point(tabulated):
    """Where the search loads two points of a wheel (the tread and the flange root of S1002 at 4.6 mm), the table's
    single point carries the wheel: the lateral force then differs by a few per cent of the load."""
    untabulated = WheelsetContactModel(WheelsetContactParameters(geometry_table=0, jacobian=1))
    values = inputs(0.0046, 0.0, 0.0, 0.0)
    got, expected = tabulated.step(tabulated.state.time, H, values), untabulated.step(0.0, H, values)
    assert got.patches_right == 1 and expected.patches_right == 2, (got.patches_right, expected.patches_right)
    assert abs(got.force_y - expected.force_y) <= 0.05 * Q, f"force_y {got.force_y!r}, {expected.force_y!r}"


def test_another_level_through_the_table_is_the_library_at_the_tables_roll(tabulated):
    """With the table, a level other than hertz with a closed-form elliptic level takes the table's pose and the
    library's solve there (hertz with FASTSIM here)."""
    model = WheelsetContactModel(WheelsetContactParameters(table_range=RANGE, elliptic_method=2, jacobian=1))
    values = inputs(-0.0042, 0.0, 0.01, 0.0)
    got = model.step(0.0, H, values)
    assert tuple(got[:LOADS]) == tuple(library(model, values, model.pose(-0.0042, 0.0).roll)), "not the library's"


def test_mirror_symmetry_without_the_table():
    model = WheelsetContactModel(WheelsetContactParameters(geometry_table=0, jacobian=1))
    plus = model.step(0.0, H, inputs(0.0037, 0.001, 0.03, -0.02, left=7e4, right=9e4))
    minus = model.step(H, H, inputs(-0.0037, -0.001, -0.03, 0.02, left=9e4, right=7e4))
    for name in ("force_x", "force_z", "moment_pitch"):
        assert getattr(plus, name) == pytest.approx(getattr(minus, name), rel=1e-9, abs=1e-6), name
    for name in ("force_y", "moment_roll", "moment_yaw", "roll"):
        assert getattr(plus, name) == pytest.approx(-getattr(minus, name), rel=1e-9, abs=1e-6), name
    assert plus.lateral_force_left == pytest.approx(-minus.lateral_force_right, rel=1e-9), "per wheel"


def test_a_lifted_wheel_carries_nothing_and_is_said_once(tabulated):
    tabulated.take_messages()
    got = tabulated.step(tabulated.state.time, H, inputs(0.003, left=0.0))
    assert got.normal_force_left == 0.0 and got.patches_left == 0 and got.normal_force_right > 0.0, got
    assert got.force_z == pytest.approx(-Q, rel=2e-2), got.force_z
    tabulated.step(tabulated.state.time, H, inputs(0.003, left=0.0))
    messages = tabulated.take_messages()
    assert len(messages) == 1 and "left wheel carries vertical_load_left = 0 N: lifted" in messages[0], messages
    nothing = tabulated.step(tabulated.state.time, H, inputs(0.003, speed=0.0, left=0.0, right=0.0))
    assert all(v == 0 for v in nothing[:LOADS]) and nothing.method_used == 0, nothing


@pytest.mark.parametrize(("values", "parts"), [
    (inputs(left=-1.0), ("vertical_load_left = -1.0 N is out of range: it must be >= 0.0",)),
    (inputs(y=math.nan, speed=-2.0), ("lateral_shift = nan is not finite",
                                      "forward_speed = -2.0 m/s is out of range: it must be >= 0.0")),
    (inputs(speed=0.0), ("forward_speed = 0.0 m/s with vertical loads", "need forward_speed > 0")),
    (inputs(y=0.0095), ("lateral_shift = 0.0095 m is outside the table's [-0.008, 0.008] m",)),
])
def test_bad_inputs_are_refused_with_the_value_and_the_limit(tabulated, values, parts):
    before = tabulated.get_state()
    with pytest.raises(ModelError) as caught:
        tabulated.step(tabulated.state.time, H, values)
    for part in parts:
        assert part in str(caught.value), f"{part!r} not in {caught.value}"
    assert tabulated.get_state() == before, "a refused step changed the state"


@pytest.mark.parametrize("table", [1, 0])
def test_linear_forces_that_would_carry_the_load_are_refused_by_name(table):
    """The linear theory has no friction limit: at large lateral creepage its tangential force's vertical component
    would carry more than the wheel's load, where no normal force balances it; the step is refused naming the wheel,
    the force and the load (with the table; the search's vertical balance says so without it), and the instance steps
    on."""
    model = WheelsetContactModel(WheelsetContactParameters(method=1, elliptic_method=1, geometry_table=table,
                                                           table_range=RANGE))
    extreme = inputs(y=7.8e-4, yaw=1.4e-4, vy=0.065, rate=-0.116, speed=0.617, pitch=-1.342, left=3.6e3, right=4.4e4)
    with pytest.raises(ModelError) as caught:
        model.step(0.0, H, extreme)
    message = str(caught.value)
    assert "right wheel" in message and ("linear theory has no friction limit" in message if table else
                                         "tangential forces' vertical share" in message), message
    assert all(map(math.isfinite, model.step(0.0, H, inputs())[:LOADS])), "the instance steps on"


@pytest.mark.parametrize(("method", "table"), [(0, 1), (1, 0), (2, 1), (2, 0), (3, 0)])
def test_every_level_outputs_python_numbers(method, table):
    """The outputs are Python floats and ints at every level, the discretised one's numpy sums included: the FMU's
    state stores them and checks their types when a host restores it."""
    model = WheelsetContactModel(WheelsetContactParameters(method=method, geometry_table=table, table_range=RANGE,
                                                           step_budget=0.0 if method == 3 else 0.05))
    outputs = model.step(0.0, H, inputs())
    odd = [(name, type(value).__name__) for name, value in zip(type(outputs)._fields, outputs, strict=True)
           if type(value) not in (float, int)]
    assert not odd, f"method {method}, table {table}: outputs of other types {odd}"


def test_a_load_so_small_that_the_saturation_bounds_underflow_is_deep_saturation(tabulated):
    """Through the table the saturated linear theory's bounds mu N underflow to 0 at a load of 1e-300 N or less:
    the forces are then those of deep saturation, finite, never a division by zero."""
    for load in (1e-300, 5e-324):
        outputs = tabulated.step(tabulated.state.time, H, inputs(left=0.0, right=load))
        assert all(map(math.isfinite, outputs)), f"load {load!r} N: {outputs}"
        assert abs(outputs.vertical_force_right) <= 1.01 * load, f"load {load!r} N: {outputs.vertical_force_right!r}"


@pytest.mark.parametrize("method", [2, 3])
def test_creepages_beyond_floating_point_are_refused_without_a_numpy_warning(method):
    """forward_speed 1e-300 m/s with a lateral velocity: creepages near 1e298 that overflow the strips' march and the
    discretised level's Newton iteration; the step is refused naming the cause, at once, and no numpy warning
    escapes."""
    import time
    import warnings

    model = WheelsetContactModel(WheelsetContactParameters(method=method, geometry_table=0, step_budget=2.0))
    started = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ModelError, match="beyond floating point"):
            model.step(0.0, H, inputs(vy=0.0277, rate=0.0139, speed=1e-300, pitch=-2.17e-300, left=1.3e3,
                                      right=1.18e5))
    assert time.process_time() - started < 10.0, "the refusal took the solver's cap of iterations"


@pytest.mark.parametrize("table", [1, 0])
def test_a_light_wheel_at_the_flange_root_carries_its_load(table):
    """A light right wheel (6.4 kN beside 73 kN) at the flange root on a dry rail: the tangential force's vertical
    share changes from pass to pass, and the passes go on until the wheel's vertical force meets its load to
    COUPLING (two passes left it 2 % short).  Without the table the ellipse's a/b (22) is beyond Kalker's table, so
    auto takes the elliptic discretised level."""
    from rollcontact.wheelrail.wheels import COUPLING

    model = WheelsetContactModel(WheelsetContactParameters(method=1, rail_condition=1, gauge_height=0.01,
                                                           geometry_table=table, table_range=RANGE,
                                                           elliptic_method=5 if table else 0))
    values = inputs(y=5.25e-3, yaw=5.35e-4, vy=-0.0396, rate=-0.0564, speed=33.6, pitch=-73.268, left=7.3e4,
                    right=6.39e3)
    outputs = model.step(0.0, H, values)
    for side, load in (("left", values[6]), ("right", values[7])):
        carried = -getattr(outputs, f"vertical_force_{side}")
        assert abs(carried / load - 1.0) <= COUPLING, \
            f"table {table}: the {side} wheel carries {carried!r} N of {load} N"


def test_a_discretised_patch_beyond_the_budget_is_refused_before_any_work():
    """method = discretised, step_budget 2 s: loads of 1e9 N make patches whose modelled cost (their Hertz elements)
    is hundreds of seconds; the step is refused at once, naming the cost and the budget."""
    import time

    model = WheelsetContactModel(WheelsetContactParameters(method=3, step_budget=2.0, table_range=RANGE))
    started = time.process_time()
    with pytest.raises(ModelError, match=r"modelled at .* s, more than the budget of 2 s"):
        model.step(0.0, H, inputs(left=1e9, right=1e9))
    assert time.process_time() - started < 1.0, "refused after solving"


def test_a_flange_beyond_the_profiles_is_refused_without_the_table():
    model = WheelsetContactModel(WheelsetContactParameters(geometry_table=0))
    with pytest.raises(ModelError, match="lateral_shift = 0.06 m"):
        model.step(0.0, H, inputs(0.06))


def test_a_flanges_ellipse_is_refused_by_the_saturated_theory_without_the_table_and_answered_with_it(tabulated):
    """In flange contact (7 mm: the ellipse's a/b about 21) the saturated theory refuses without the table, naming a/b
    and Kalker's range, and the instance takes the next step; ``auto`` answers by the discretised elliptic level; the
    table's node constants take the coefficient table's rows beyond Kalker's and answer."""
    model = WheelsetContactModel(WheelsetContactParameters(geometry_table=0, jacobian=1))
    refusal = r"a/b = 2\d\.\d+ is outside the creepage-coefficient table's range \[0.1, 10\]"
    with pytest.raises(ModelError, match=refusal):
        model.step(0.0, H, inputs(0.007, yaw=0.0))
    assert model.step(0.0, H, inputs(0.002)).force_y != 0.0, "the instance does not take the next step"
    auto = WheelsetContactModel(WheelsetContactParameters(geometry_table=0, jacobian=1, elliptic_method=AUTO))
    assert math.isfinite(auto.step(0.0, H, inputs(0.007, yaw=0.0)).force_y), "auto does not answer the flange"
    flange = tabulated.step(tabulated.state.time, H, inputs(0.007, yaw=0.0))
    assert math.isfinite(flange.force_y), "the table does not answer"


def test_a_restored_state_repeats_the_steps_bit_for_bit(tabulated):
    tabulated.reset(0.0)
    rows = signal(8)
    for n in range(3):
        tabulated.step(n * H, H, rows[n])
    state = tabulated.get_state()
    first = [tabulated.step(n * H, H, rows[n]) for n in range(3, 8)]
    tabulated.set_state(WheelsetContactState.parse(state.to_dict()))
    assert [tabulated.step(n * H, H, rows[n]) for n in range(3, 8)] == first, "the steps do not repeat"
    with pytest.raises(ModelError, match="current_time = 0.001 s lies before the last communication point"):
        tabulated.step(H, H, rows[1])
    for bad in ({"version": 1, "time": math.nan, "steps": 0}, {"version": 2, "time": 0.0, "steps": 0}, [1]):
        with pytest.raises(ModelError):
            WheelsetContactState.parse(bad)


def test_the_geometry_helpers(tabulated):
    """The equivalent conicity from the table's functions is the library's; Kalker's coefficients of the centred
    contacts are positive and equal on both wheels."""
    assert 0.55 < tabulated.equivalent_conicity(5e-4) < 0.7, tabulated.equivalent_conicity(5e-4)
    left, right = tabulated.creep_coefficients(0.0, Q)
    assert left == pytest.approx(right, rel=1e-12) and min(left[:3]) > 0.0, (left, right)


def test_the_outputs_are_a_function_of_the_inputs_alone(tabulated):
    """The same inputs give the same outputs bit for bit whatever came before and whenever they come."""
    tabulated.reset(0.0)
    values = inputs(0.0027, 0.0008, -0.03, 0.05)
    first = tabulated.step(0.0, H, values)
    for n, other in enumerate(signal(5), start=1):
        tabulated.step(n * H, H, other)
    assert tabulated.step(7.3, 0.01, values) == first, "the outputs depend on the history"


@pytest.mark.parametrize("options, values", [
    ({"method": method_code("strips"), "jacobian": 1},
     (0.004001527595821222, 0.001687771706151042, 0.02164490441291539, -0.005071040475120116, 1.254882686621549,
      -2.7147507496068966, 18901.362350813124, 5e-324)),
    ({"method": AUTO, "rail_condition": 2},
     (0.001159420531216681, 0.0010812561823059048, -0.012256707750551479, -0.055391561953596305, 10.414469297422292,
      -22.607326780841216, 3997.120074940494, 5e-324))])
def test_a_wheel_load_at_the_end_of_floating_point_is_refused_by_value(options, values):
    """A wheel load of 5e-324 N (two of the fuzz's steps, where the strips' Hertz start divided by an underflowed
    semi-axis): the strips cannot resolve the contact, and the step is refused naming the load, never with Python's
    bare error text; the instance answers the next step."""
    model = WheelsetContactModel(WheelsetContactParameters(**options))
    with pytest.raises(ModelError) as refused:
        model.step(0.0, H, values)
    assert "5e-324 N" in str(refused.value) and "division" not in str(refused.value), str(refused.value)
    after = model.step(0.0, H, inputs())
    assert math.isclose(-after.force_z, 2 * Q, rel_tol=1e-3), f"the instance stays usable: {after.force_z!r} N"
