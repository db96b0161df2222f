"""The elliptic stepping model (rollcontact.stepping.elliptic): parameters checked all at once, the library's answer
per contact, signs, the Jacobian against differences of the linear theory and of the level, frictional power,
budget, state, repeatability, and the refusals of what no level represents."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from rollcontact import EllipticScene, Material, solve_elliptic
from rollcontact.core.friction import Coulomb
from rollcontact.elliptic.dispatch import BUILTIN
from rollcontact.elliptic.methods.strips import METHOD as STRIPS
from rollcontact.stepping import ModelError
from rollcontact.stepping.elliptic.model import EllipticModel, EllipticState
from rollcontact.stepping.elliptic.parameters import METHOD_LEVELS as ELLIPTIC_LEVELS
from rollcontact.stepping.elliptic.parameters import NO_STICK, EllipticParameters
from rollcontact.stepping.elliptic.parameters import method_code as level_code

METHODS = (0, *(level.code for level in ELLIPTIC_LEVELS if level.choice))
"""Every ``method`` code: auto and the levels a user may choose."""
H = 1e-3
ROW = (1e5, 1e-3, -5e-4, 0.2, 30.0)  # Fn [N], xi, eta, phi [1/m], V [m/s]


def jacobian(outputs) -> np.ndarray:
    return np.reshape(outputs[8:17], (3, 3))


def test_every_builtin_elliptic_method_has_a_code():
    for spec in BUILTIN:
        assert level_code(spec.name) > 0, f"{spec.name} has no FMU code in ELLIPTIC_LEVELS"
    assert [level.name for level in ELLIPTIC_LEVELS][:5] == ["linear", "fastsim", "strips", "discretised",
                                                             "saturated"], "codes are append only"
    assert [level.code for level in ELLIPTIC_LEVELS] == list(range(1, len(ELLIPTIC_LEVELS) + 1)), "codes 1, 2, ..."


def test_invalid_parameters_are_named_all_at_once():
    with pytest.raises(ModelError) as caught:
        EllipticParameters(youngs_modulus=0.0, poisson_ratio=0.5, friction_law=9, method=-1, jacobian=2,
                           curvature_longitudinal=(1.0, -2.0), curvature_lateral=(1.0, math.nan), step_budget=-1.0)
    message = str(caught.value)
    for part in ("youngs_modulus = 0.0 is out of range: it must be > 0", "poisson_ratio = 0.5 is out of range",
                 "friction_law = 9", "method = -1", "jacobian = 2", "curvature_longitudinal[2] = -2.0 1/m",
                 "curvature_lateral[2] = nan", "step_budget = -1.0"):
        assert part in message, f"{part!r} missing from {message!r}"
    with pytest.raises(ModelError, match="one curvature of each per contact"):
        EllipticParameters(curvature_longitudinal=(1.0, 2.0), curvature_lateral=(1.0,))


@pytest.mark.parametrize("method", METHODS)
def test_each_contact_is_solve_elliptic_bit_for_bit(method):
    curvatures = ((1.087, 1.667), (2.5, 1.2))
    budget = {"step_budget": 2.0} if ELLIPTIC_LEVELS[method - 1].name == "discretised" else {}  # its capped work
    p = EllipticParameters(curvature_longitudinal=tuple(c[0] for c in curvatures),
                           curvature_lateral=tuple(c[1] for c in curvatures), method=method, **budget)
    rows = [ROW, (5e4, -2e-3, 1e-3, -0.5, 10.0)]
    outputs = EllipticModel(p).step(0.0, H, rows)
    name = "auto" if method == 0 else ELLIPTIC_LEVELS[method - 1].name
    for k, (row, (A, B)) in enumerate(zip(rows, curvatures, strict=True)):
        r = solve_elliptic(EllipticScene(row[0], A, B, *row[1:4], Material(), Coulomb(0.3), row[4]), name,
                           budget=p.step_budget)
        assert outputs[k][:6] == (r.longitudinal_force, r.lateral_force, r.spin_moment, r.a, r.b, r.max_pressure), \
            f"contact {k + 1}"
        assert outputs[k].method_used == level_code(r.method)
        assert outputs[k].stick_fraction == r.info.get("stick_fraction", NO_STICK)


@pytest.mark.parametrize("method", (1, 3))
@pytest.mark.parametrize("component", range(3))
def test_each_creepage_above_zero_gives_its_force_above_zero(method, component):
    row = [1e5, 0.0, 0.0, 0.0, 20.0]
    row[1 + component] = (1e-4, 1e-4, 0.05)[component]
    out = EllipticModel(EllipticParameters(method=method)).step(0.0, H, [row])[0]
    assert out[component] > 0.0, f"{('xi', 'eta', 'phi')[component]} > 0 gives {out[:3]}"


def test_linear_slopes_are_the_derivatives_of_the_linear_theory():
    """The linear level is linear: a central difference of it is its slope to rounding."""
    model = EllipticModel(EllipticParameters(method=1))
    slopes = jacobian(model.step(0.0, H, [ROW])[0])
    steps = (1e-6, 1e-6, 1e-3)
    for j in range(3):
        up, down = list(ROW), list(ROW)
        up[1 + j] += steps[j]
        down[1 + j] -= steps[j]
        difference = (np.array(model.step(0.0, H, [up])[0][:3]) - np.array(model.step(0.0, H, [down])[0][:3])) / (
            2 * steps[j])
        scale = np.abs(slopes[:, j]).max()
        assert np.allclose(difference, slopes[:, j], rtol=0, atol=1e-7 * scale), f"column {j}: {difference}"
    assert slopes[0, 1] == slopes[0, 2] == slopes[1, 0] == slopes[2, 0] == 0.0
    assert slopes[2, 1] == -slopes[1, 2], "Mz of eta is minus Fy of phi (G c^3 C23)"


def test_the_difference_jacobian_falls_with_saturation_and_meets_the_slope_at_zero():
    linear = jacobian(EllipticModel(EllipticParameters(method=3)).step(0.0, H, [(1e5, 0, 0, 0, 20.0)])[0])
    near_zero = jacobian(EllipticModel(EllipticParameters(method=3, jacobian=1)).step(
        0.0, H, [(1e5, 0.0, 0.0, 0.0, 20.0)])[0])
    for i in range(2):
        assert abs(near_zero[i, i] / linear[i, i] - 1.0) < 0.01, \
            f"strips reproduce the linear theory at vanishing creepage: {near_zero[i, i]} against {linear[i, i]}"
    saturated = jacobian(EllipticModel(EllipticParameters(method=3, jacobian=1)).step(
        0.0, H, [(1e5, 0.05, 0.0, 0.0, 20.0)])[0])
    assert 0.0 <= saturated[0, 0] < 0.01 * linear[0, 0], f"full slip: dFx/dxi {saturated[0, 0]} about 0"


@pytest.mark.parametrize("method", (2, 3))
def test_frictional_power_is_the_creepage_power_and_not_negative(method):
    model = EllipticModel(EllipticParameters(method=method))
    rng = np.random.default_rng(3)
    for _ in range(20):
        row = (1e5, *rng.normal(0.0, 2e-3, 2), rng.normal(0.0, 0.5), 25.0)
        out = model.step(0.0, H, [row])[0]
        power = row[4] * (row[1] * out[0] + row[2] * out[1] + row[3] * out[2])
        assert out.frictional_power == power
        assert power >= -1e-9 * row[4] * 0.3 * row[0] * 1e-3, f"dissipation >= 0: {power} W at {row}"


def test_no_load_is_no_contact():
    out = EllipticModel(EllipticParameters()).step(0.0, H, [(0.0, 1e-3, 1e-3, 1.0, 10.0)])[0]
    assert tuple(out) == (0.0,) * 17 + (0,)


def test_a_budget_below_the_cheapest_setting_refuses_the_step_naming_the_contact():
    """A budget between the strips' modelled cost without spin and with it: the steps with spin are refused, those
    without fit (a budget no step fits is refused at initialisation)."""
    strips = STRIPS.accuracy
    plain, spinning = (strips.cost(EllipticScene(1e5, 1.0, 1.0, spin_creepage=phi), {}) for phi in (0.0, 0.2))
    assert plain < spinning, "the march with spin is modelled dearer than the closed form"
    model = EllipticModel(EllipticParameters(method=3, step_budget=0.5 * (plain + spinning),
                                             curvature_longitudinal=(1.0, 1.0), curvature_lateral=(1.0, 1.0)))
    with pytest.raises(ModelError, match="contact 1: .*budget"):
        model.step(0.0, H, [ROW, ROW])
    assert model.state.steps == 0, "a refused step changes nothing"
    model.step(0.0, H, [(*ROW[:3], 0.0, ROW[4])] * 2)
    assert model.state.steps == 1, "without spin the step fits"


def test_bad_inputs_are_named_with_their_contact_and_change_nothing():
    model = EllipticModel(EllipticParameters(curvature_longitudinal=(1.0, 1.0), curvature_lateral=(1.0, 1.0)))
    with pytest.raises(ModelError) as caught:
        model.step(0.0, H, [ROW, (-1.0, math.nan, 0.0, 0.0, -2.0)])
    message = str(caught.value)
    for part in ("contact 2: normal_load = -1.0 N", "contact 2: longitudinal_creep = nan",
                 "contact 2: velocity = -2.0 m/s"):
        assert part in message, message
    assert "contact 1" not in message and model.state.steps == 0


def test_a_restored_state_repeats_the_steps_and_a_bad_state_is_refused():
    model = EllipticModel(EllipticParameters())
    model.step(0.0, H, [ROW])
    saved = EllipticState.parse(model.get_state().to_dict())
    first = [model.step(n * H, H, [ROW]) for n in range(1, 4)]
    model.set_state(saved)
    assert [model.step(n * H, H, [ROW]) for n in range(1, 4)] == first
    with pytest.raises(ModelError, match="time going|lies before"):
        model.step(0.0, H, [ROW])
    for bad in ({"version": 1, "time": math.nan, "steps": 0}, {"version": 1, "time": 0.0, "steps": -1},
                {"version": 2, "time": 0.0, "steps": 0}, {"time": 0.0}):
        with pytest.raises(ModelError):
            EllipticState.parse(bad)


def test_the_contacts_linear_theory_together_is_each_contact_alone_bit_for_bit():
    """LinearContacts (numpy over the contacts) against the per-contact path through solve_elliptic, every output,
    over loads from 0 to 2e5 N, both orientations of the ellipse and creepages of either sign."""
    rng = np.random.default_rng(7)
    curvatures = ((1.087, 1.667), (2.5, 1.2), (0.9, 4.0), (3.0, 3.0), (1.0, 1.0 + 1e-12))
    p = EllipticParameters(method=1, curvature_longitudinal=tuple(c[0] for c in curvatures),
                           curvature_lateral=tuple(c[1] for c in curvatures))
    together = EllipticModel(p)
    alone = EllipticModel(p)
    alone.batch = None
    assert together.batch is not None, "the linear level is evaluated over the contacts together"
    for n in range(30):
        rows = [(float(rng.choice([0.0, rng.uniform(1e3, 2e5)])), *rng.normal(0, 2e-3, 2), float(rng.normal(0, 0.5)),
                 float(rng.uniform(0, 40))) for _ in curvatures]
        assert together.step(n * H, H, rows) == alone.step(n * H, H, rows), f"step {n}: {rows}"


@pytest.mark.parametrize("jacobian", (0, 1))
def test_the_contacts_strips_together_are_each_contact_alone_bit_for_bit(jacobian):
    """The strips of every contact in one solve_strips_many against each contact through solve_elliptic, every
    output, with and without spin, with the linear or the difference Jacobian."""
    rng = np.random.default_rng(5)
    curvatures = ((1.087, 1.667), (2.5, 1.2), (0.9, 4.0), (3.0, 3.0))
    p = EllipticParameters(method=3, jacobian=jacobian, curvature_longitudinal=tuple(c[0] for c in curvatures),
                           curvature_lateral=tuple(c[1] for c in curvatures))
    together, alone = EllipticModel(p), EllipticModel(p)
    alone.strips_together = alone.choose_together = False
    assert together.strips_together, "the strips of the contacts are solved together"
    for n in range(12):
        rows = [(float(rng.choice([0.0, rng.uniform(1e3, 2e5)])), *rng.normal(0, 2e-3, 2),
                 float(rng.choice([0.0, rng.normal(0, 0.5)])), float(rng.uniform(0, 40))) for _ in curvatures]
        assert together.step(n * H, H, rows) == alone.step(n * H, H, rows), f"step {n}: {rows}"


def test_the_linear_levels_jacobian_is_its_slopes_in_either_mode():
    rows = [ROW, (5e4, -2e-3, 1e-3, -0.5, 10.0)]
    p = {"method": 1, "curvature_longitudinal": (1.087, 2.5), "curvature_lateral": (1.667, 1.2)}
    slopes = EllipticModel(EllipticParameters(**p)).step(0.0, H, rows)
    together = EllipticModel(EllipticParameters(**p, jacobian=1))
    alone = EllipticModel(EllipticParameters(**p, jacobian=1))
    alone.batch = None
    assert together.step(0.0, H, rows) == alone.step(0.0, H, rows) == slopes


# what no level represents, and the bounds of a step (each a finding of a fuzz of the 3D FMUs)

@pytest.mark.parametrize("method", METHODS)
def test_outputs_beyond_floating_point_are_refused_by_name_without_a_numpy_warning(method):
    """E = 1e-300 Pa under 1e9 N: the ellipse overflows; every level refuses the step, naming the output."""
    model = EllipticModel(EllipticParameters(method=method, youngs_modulus=1e-300, step_budget=0.0))
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        with pytest.raises(ModelError, match="is not finite at normal_load = 1000000000.0 N") as refused:
            model.step(0.0, H, [(1e9, 1e-3, 0.0, 0.0, 1.0)])
    assert not seen, f"no warning escapes the step: {[str(w.message) for w in seen]}"
    assert "youngs_modulus = 1e-300 Pa" in str(refused.value), "the message names the parameter"
    assert model.step(0.0, H, [(0.0, 0.0, 0.0, 0.0, 1.0)])[0].method_used == 0, "the model stays usable"


def test_a_contact_no_level_can_step_is_refused_at_initialisation_by_name():
    for method in METHODS:
        with pytest.raises(ModelError, match=r"contact 2: curvatures A = 0\.001, B = 1000\.0 1/m give a/b = "
                                             r"2890\.59, outside \[0\.1, 10\]") as refused:
            EllipticModel(EllipticParameters(method=method, curvature_longitudinal=(1.087, 1e-3),
                                             curvature_lateral=(1.667, 1e3)))
        assert "Jacobian" in str(refused.value), "the message says why every level needs the range"


def test_an_arithmetic_breakdown_names_the_level_and_the_values():
    model = EllipticModel(EllipticParameters(method=3, youngs_modulus=1e-300))
    with pytest.raises(ModelError, match=r"strips cannot represent this contact in floating point \(Overflow"):
        model.step(0.0, H, [(1e-9, 1e-3, 0.0, 0.0, 1.0)])


def test_the_strips_step_spin_on_a_falling_rail_condition():
    """The strips take spin with a velocity-dependent law (their march at each cell's own slip): Polach's dry rail."""
    model = EllipticModel(EllipticParameters(method=3, rail_condition=1))
    out = model.step(0.0, H, [(1e5, 1e-3, 0.0, 0.2, 30.0)])[0]
    assert out.method_used == 3, f"the strips answer ({out.method_used})"
    assert 0.0 < out.longitudinal_force <= 0.55 * 1e5, f"Fx = {out.longitudinal_force} within mu(0) Fn"


def test_the_cheapest_fallback_a_budget_forces_keeps_the_friction_limit():
    """auto, tolerance 1e-3 and a budget of twice the linear levels' cost: only they fit; the saturated one
    answers."""
    from rollcontact import ELLIPTIC_METHODS

    budget = 2.0 * ELLIPTIC_METHODS["saturated"].accuracy.floor
    assert budget < STRIPS.accuracy.floor, "the budget leaves out the strips"
    law = {"friction_law": 1, "friction_coefficient": 0.6557}
    model = EllipticModel(EllipticParameters(method=0, tolerance=1e-3, step_budget=budget, **law))
    out = model.step(0.0, H, [(1e5, -0.0046, 0.0, 0.0, 10.0)])[0]
    assert out.method_used == 5, f"the saturated linear theory ({out.method_used})"
    assert abs(out.longitudinal_force) <= 0.6557 * 1e5, f"|Fx| = {abs(out.longitudinal_force)} > mu Fn"
    assert any("not met within the step budget" in m for m in model.take_messages()), "the miss is said"


@pytest.mark.parametrize("method", [3, 0])
def test_all_contacts_unloaded_give_no_contact(method):
    n = 8
    model = EllipticModel(EllipticParameters(method=method, curvature_longitudinal=(1.087,) * n,
                                             curvature_lateral=(1.667,) * n))
    outputs = model.step(0.0, H, [(0.0, 1e-3, 0.0, 0.1, 10.0)] * n)
    assert all(o.method_used == 0 and o.longitudinal_force == 0.0 for o in outputs), "zeros without load"


def test_the_difference_jacobian_is_paid_within_the_step_budget():
    """jacobian = difference: the step's solve is chosen within a quarter of the budget and the three differences
    take its setting, so that the four solves' modelled cost fits the budget; a budget whose quarter pays no setting
    refuses the step by naming it."""
    from rollcontact import ELLIPTIC_METHODS

    row = [(1e5, 2e-3, 0.0, 0.0, 10.0)]
    one = ELLIPTIC_METHODS["fastsim"].accuracy.cost(EllipticScene(1e5, 1.087, 1.667, 2e-3), {})
    cheapest = ELLIPTIC_METHODS["fastsim"].accuracy.minimum_cost(EllipticScene(1e5, 1.087, 1.667, 2e-3))
    linear = EllipticModel(EllipticParameters(method=1)).step(0.0, H, row)[0]
    for budget in (4.5 * cheapest, 5.0 * one):
        model = EllipticModel(EllipticParameters(method=2, jacobian=1, step_budget=budget))
        out = model.step(0.0, H, row)[0]
        assert out.dFx_dxi < 0.9 * linear.dFx_dxi, f"FASTSIM's slope falls with saturation ({out.dFx_dxi:.4g})"
        assert 0.0 < model.last_modelled_cost <= budget, \
            f"the four solves are modelled at {model.last_modelled_cost:.3g} s, over the budget {budget:.3g} s"
        assert not any("no room for the difference Jacobian" in m for m in model.take_messages()), \
            "the differences fit the three quarters of the budget left"
    starved = EllipticModel(EllipticParameters(method=2, jacobian=1, step_budget=2.0 * cheapest))
    with pytest.raises(ModelError, match="more than the budget"):
        starved.step(0.0, H, row)


# the gap's curvatures as inputs (a host that computes the contact geometry from profiles)

@pytest.mark.parametrize("method", METHODS)
def test_curvature_inputs_changing_every_step_are_fresh_models_of_those_parameters_bit_for_bit(method):
    """Each step's gap curvatures (0: the parameter's) give the outputs of a new model made with them as parameters,
    at every level, for two contacts whose geometry changes independently."""
    slow = method and ELLIPTIC_LEVELS[method - 1].name == "discretised"  # its capped work: two steps
    rng = np.random.default_rng(11)
    parameters = {"method": method, "curvature_longitudinal": (1.087, 2.5), "curvature_lateral": (1.667, 1.2),
                  **({"step_budget": 2.0} if slow else {})}
    model = EllipticModel(EllipticParameters(**parameters))
    for n in range(2 if slow else 6):
        gaps = [(float(rng.choice([0.0, rng.uniform(0.5, 4.0)])), float(rng.choice([0.0, rng.uniform(0.5, 4.0)])))
                for _ in range(2)]
        rows = [(*ROW[:3], float(rng.normal(0.0, 0.3)), ROW[4], *gap) for gap in gaps]
        outputs = model.step(n * H, H, rows)
        fresh = EllipticModel(EllipticParameters(**{**parameters, **{
            name: tuple(gap[i] or parameters[name][k] for k, gap in enumerate(gaps))
            for i, name in enumerate(("curvature_longitudinal", "curvature_lateral"))}}))
        assert outputs == fresh.step(n * H, H, [row[:5] for row in rows]), f"step {n}: gaps {gaps}"


def test_rows_of_five_are_the_parameters_curvatures_whatever_the_last_step_had():
    model = EllipticModel(EllipticParameters(method=1))
    first = model.step(0.0, H, [ROW])
    model.step(H, H, [(*ROW, 3.0, 0.5)])
    assert model.step(2 * H, H, [ROW]) == first, "a row without curvatures takes the parameters'"
    assert model.step(3 * H, H, [(*ROW, 0.0, 0.0)]) == first, "curvatures 0 are the parameters'"


def test_invalid_curvature_inputs_are_refused_by_name_and_change_nothing():
    model = EllipticModel(EllipticParameters(curvature_longitudinal=(1.0, 1.0), curvature_lateral=(1.0, 1.0)))
    with pytest.raises(ModelError) as caught:
        model.step(0.0, H, [(*ROW, 1.0, 1.0), (*ROW, -1.0, math.nan)])
    message = str(caught.value)
    for part in ("contact 2: gap_curvature_longitudinal = -1.0 1/m is out of range",
                 "contact 2: gap_curvature_lateral = nan"):
        assert part in message, message
    with pytest.raises(ModelError, match=r"contact 1: gap curvatures A = 0\.001, B = 1000\.0 1/m give a/b = "
                                         r"2890\.59, outside \[0\.1, 10\]"):
        model.step(0.0, H, [(*ROW, 1e-3, 1e3), ROW])
    assert model.state.steps == 0, "a refused step changes nothing"
    assert model.step(0.0, H, [ROW, ROW])[0].method_used > 0, "the model stays usable"


# contacts stepped together wherever the chosen level allows, bit for bit each contact alone

def contact_by_contact(model: EllipticModel) -> EllipticModel:
    """``model`` made to step each contact through solve_elliptic (its batches off)."""
    model.batch = model.linear_together = None
    model.strips_together = model.fastsim_together = model.choose_together = False
    return model


BATCH_CURVATURES = ((1.087, 1.667), (2.5, 1.2), (0.9, 4.0), (3.0, 3.0))


@pytest.mark.parametrize("tolerance", (0.0, 0.05, 0.012))
@pytest.mark.parametrize("jacobian", (0, 1))
@pytest.mark.parametrize("method", METHODS)
def test_every_unloaded_combination_together_is_contact_by_contact_bit_for_bit(method, jacobian, tolerance):
    """Every subset of unloaded contacts, at every level, with and without a tolerance, both Jacobians: the outputs
    and the messages of the step together are those of each contact through solve_elliptic."""
    slow = method and ELLIPTIC_LEVELS[method - 1].name == "discretised"
    if slow and (jacobian or tolerance):
        pytest.skip("the discretised level has no batch: one case shows it steps each contact alone")
    curvatures = BATCH_CURVATURES[:2] if slow else BATCH_CURVATURES
    n = len(curvatures)
    p = EllipticParameters(method=method, jacobian=jacobian, tolerance=tolerance,
                           curvature_longitudinal=tuple(c[0] for c in curvatures),
                           curvature_lateral=tuple(c[1] for c in curvatures), **({"step_budget": 2.0} if slow else {}))
    together, alone = EllipticModel(p), contact_by_contact(EllipticModel(p))
    rng = np.random.default_rng(method + 10 * jacobian)
    for mask in range(2**n):
        rows = [(0.0 if mask >> k & 1 else float(rng.uniform(2e4, 1.5e5)), *(rng.normal(0.0, 1.5e-3, 2)
                 * rng.choice([0.02, 1.0, 3.0])), float(rng.choice([0.0, rng.normal(0.0, 0.4)])), 20.0)
                for k in range(n)]
        assert together.step(mask * H, H, rows) == alone.step(mask * H, H, rows), f"unloaded {mask:0{n}b}: {rows}"
        assert together.take_messages() == alone.take_messages(), f"unloaded {mask:0{n}b}: the messages"


@pytest.mark.parametrize("tolerance", (0.0, 0.05))
@pytest.mark.parametrize("jacobian", (0, 1))
@pytest.mark.parametrize("method, condition", [(0, 1), (0, 2), (3, 2), (2, 1)])
def test_falling_friction_contacts_together_are_contact_by_contact_bit_for_bit(method, condition, jacobian,
                                                                              tolerance):
    """A rail condition (Polach's dry and wet rail: friction falling with the slip velocity) with auto, strips and
    fastsim, with and without a tolerance: the contacts on the strips (and without a tolerance on FASTSIM) are one
    batch (each contact at its own rolling speed, with and without spin), and every subset of unloaded contacts gives
    the outputs and messages of each contact through solve_elliptic."""
    p = EllipticParameters(method=method, rail_condition=condition, jacobian=jacobian, tolerance=tolerance,
                           curvature_longitudinal=tuple(c[0] for c in BATCH_CURVATURES),
                           curvature_lateral=tuple(c[1] for c in BATCH_CURVATURES))
    together, alone = EllipticModel(p), contact_by_contact(EllipticModel(p))
    batched = together.strips_together or together.fastsim_together or together.choose_together
    assert batched == (method != 2 or not tolerance), "the strips' contacts batch, FASTSIM's without a tolerance"
    rng = np.random.default_rng(100 * condition + 10 * jacobian + method)
    n = len(BATCH_CURVATURES)
    for mask in range(2**n):
        rows = [(0.0 if mask >> k & 1 else float(rng.uniform(2e4, 1.5e5)), *(rng.normal(0.0, 1.5e-3, 2)
                 * rng.choice([0.02, 1.0, 3.0])), float(rng.choice([0.0, rng.normal(0.0, 0.4)])),
                 float(rng.uniform(5.0, 50.0))) for k in range(n)]
        outputs = together.step(mask * H, H, rows)
        assert outputs == alone.step(mask * H, H, rows), f"unloaded {mask:0{n}b}: {rows}"
        assert together.take_messages() == alone.take_messages(), f"unloaded {mask:0{n}b}: the messages"
        assert tolerance or all(o.method_used == (method or 3) for o, row in zip(outputs, rows, strict=True)
                                if row[0] != 0.0), f"unloaded {mask:0{n}b}: without a tolerance the level answers"


def test_auto_steps_the_contacts_strips_together_while_they_are_its_choice():
    """auto without a tolerance takes the strips for Coulomb friction and solves them together; a method of lower
    rank registered beside them, or strips replaced in the registry, leaves each contact to solve_elliptic."""
    from rollcontact.elliptic.dispatch import DISPATCHER
    from rollcontact.elliptic.methods import linear

    model = EllipticModel(EllipticParameters(curvature_longitudinal=(1.087, 2.5), curvature_lateral=(1.667, 1.2)))
    assert model.strips_together and model.strips_chosen(), "auto's strips are solved together"
    assert [o.method_used for o in model.step(0.0, H, [ROW, ROW])] == [3, 3], "auto reports the strips"
    DISPATCHER.register("toy_linear", linear.solve_linear, linear.inapplicable, rank=5)
    try:
        assert not model.strips_chosen(), "a lower-ranked method is auto's choice: no strips together"
        assert [o.method_used for o in model.step(0.0, H, [ROW, ROW])] == [0, 0], "the toy answers (no code)"
    finally:
        DISPATCHER.methods.pop("toy_linear")
    assert model.strips_chosen(), "the registry restored"


def test_the_difference_jacobian_at_a_load_whose_slopes_underflow_takes_the_linear_slopes():
    """Fn = 1e-300 N: the linear spin slope G c^4 C33 underflows to 0, so the increment mu Fn c / slope is not a
    number; the linear slopes stand in (said once, naming the load) instead of a division by zero."""
    row = [(1e-300, 1e-3, 0.0, 0.1, 10.0)]
    model = EllipticModel(EllipticParameters(method=2, jacobian=1))
    out = model.step(0.0, H, row)[0]
    linear = EllipticModel(EllipticParameters(method=2)).step(0.0, H, row)[0]
    assert out[8:17] == linear[8:17], f"the linear slopes stand in: {out[8:17]} != {linear[8:17]}"
    messages = model.take_messages()
    assert any("difference Jacobian" in m and "normal_load = 1e-300 N" in m for m in messages), messages
    model.step(H, H, row)
    assert not model.take_messages(), "said once"


def test_a_level_that_fails_names_the_contacts_inputs():
    """An error inside a level (here an overflow the strips meet at a vanishing modulus) is refused with the
    contact's number and inputs, so the host sees which contact of which step it was (contact 1 unloaded)."""
    model = EllipticModel(EllipticParameters(method=3, rail_condition=1, youngs_modulus=1e-300,
                                             curvature_longitudinal=(1.087, 1.087), curvature_lateral=(1.667, 1.667)))
    with pytest.raises(ModelError) as refused:
        model.step(0.0, H, [(0.0, 1e-3, 0.0, 0.0, 10.0), (5e4, 1e-3, 0.0, 0.0, 10.0)])
    message = str(refused.value)
    assert message.startswith("contact 2: ") and "normal_load = 50000.0 N" in message, message


@pytest.mark.parametrize(("method", "budget"), [(4, 0.05), (0, 1e-9), (1, 1e-9)])
def test_a_level_whose_cheapest_setting_exceeds_the_budget_is_refused_at_initialisation(method, budget):
    """Every loaded step would be refused: the parameters are, at initialisation, naming the cost and the budget."""
    with pytest.raises(ModelError, match=rf"cheapest setting is modelled at .* s at any load, more than step_budget = "
                                         rf"{budget!r} s") as refused:
        EllipticModel(EllipticParameters(method=method, step_budget=budget))
    assert "every loaded step" in str(refused.value), str(refused.value)
    for fitting in (0.0, 1.0):  # no budget, a budget the level fits
        EllipticModel(EllipticParameters(method=method, step_budget=fitting))


@pytest.mark.parametrize("method", [3, 0])
def test_an_overflow_is_named_by_its_words_not_an_errno_tuple(method):
    """math's OverflowError carries (errno, text): the refusal gives the text, with the inputs (and, where the level
    raised it, the modulus; auto reports it as the level's failure)."""
    model = EllipticModel(EllipticParameters(method=method, rail_condition=1, youngs_modulus=1e-300))
    with pytest.raises(ModelError) as refused:
        model.step(0.0, H, [(5e4, 1e-3, 5e-4, 0.0, 10.0)])
    message = str(refused.value)
    assert "(34, " not in message and "Numerical result out of range" in message, message
    assert "normal_load = 50000.0 N" in message, message
    assert method == 0 or "youngs_modulus = 1e-300 Pa" in message, message


@pytest.mark.parametrize(("jacobian", "budget"), [(0, 0.01), (1, 0.01), (1, 0.02)])
def test_contacts_chosen_together_are_one_batch_within_the_budget(jacobian, budget, monkeypatch):
    """auto with a tolerance, 8 contacts, a falling law with spin: the contacts whose choice is the strips are solved
    in one batch, and no contact's modelled work, the difference Jacobian's solves included, exceeds step_budget
    (0.01 s pays the strips' solve once, not four times: the difference Jacobian's choice is then another level)."""
    import rollcontact.stepping.elliptic.model as model_module

    batches = []
    spec, original = model_module.MANY["strips"]

    def counted(scenes, **options):
        batches.append(len(scenes))
        return original(scenes, **options)

    monkeypatch.setitem(model_module.MANY, "strips", (spec, counted))
    n = 8
    model = EllipticModel(EllipticParameters(method=0, jacobian=jacobian, tolerance=0.1, step_budget=budget,
                                             friction_law=2, curvature_longitudinal=(1.087,) * n,
                                             curvature_lateral=(1.667,) * n))
    outputs = model.step(0.0, H, [(5e4, 1e-3, 5e-4, 0.3, 10.0)] * n)
    strips = sum(o.method_used == level_code("strips") for o in outputs)
    assert 0.0 < model.last_modelled_cost <= budget, \
        f"a contact's work is modelled at {model.last_modelled_cost:.3g} s, over step_budget {budget} s"
    assert model.last_work <= n * budget, f"the step's work {model.last_work:.3g} s exceeds {n} budgets"
    assert batches == ([strips * (4 if jacobian else 1)] if strips else []), \
        f"one batch of the {strips} strips contacts' scenes, got {batches}"
    assert strips == (0 if budget == 0.01 and jacobian else n), [o.method_used for o in outputs]
