"""The fast elliptic levels with velocity-dependent friction (the strips' and FASTSIM's march at each cell's own
slip) against oracles: Kalker's linear theory at vanishing creepage, saturation at ``mu(w) Fn`` of the rigid slip
velocity, the Coulomb answer in the limit of a constant law (to round-off), the symmetries of the contact, and
``|q| <= mu(V |s|) p`` on the cells.  Tolerances: round-off (1e-12 of mu Fn) where the answer is an identity, 1e-6 for
the linear limit (the march adds nothing there), 2e-3 for saturation (the cells' slip differs from the rigid slip by
the elastic part, of the order of the saturation creepage over the creepage)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from rollcontact import (
    Coulomb,
    EllipticScene,
    ExponentialFalling,
    LinearFalling,
    RationalFalling,
    TabulatedFriction,
    creepage_coefficients,
    rail_condition,
    solve_elliptic,
)

LOAD = 1e5
LAWS = {
    "dry": rail_condition("dry"),
    "wet": rail_condition("wet"),
    "rational": RationalFalling(0.4, 0.25, 0.5),
    "linear": LinearFalling(0.4, 0.25, 0.3),
    "table": TabulatedFriction((0.0, 0.2, 1.0, 3.0), (0.4, 0.36, 0.28, 0.25)),
}
LEVELS = ("strips", "fastsim")


def scene(ratio=1.0, law="dry", speed=30.0, xi=0.0, eta=0.0, phi=0.0):
    """The contact at a/b = ratio (c = 6 mm, steel) with creepages in saturation units of the static coefficient: the
    creepage whose linear force (Kalker's C11, C22, C23) is mu(0) Fn."""
    c = 6e-3
    base = EllipticScene.from_semi_axes(LOAD, c * math.sqrt(ratio), c / math.sqrt(ratio), friction=LAWS[law],
                                        rolling_speed=speed)
    k = creepage_coefficients(ratio, base.material.poisson_ratio)
    unit = LAWS[law].static_coefficient * LOAD / (base.shear_modulus * c * c)
    return base.replace(longitudinal_creepage=xi * unit / k.c11, lateral_creepage=eta * unit / k.c22,
                        spin_creepage=phi * unit / (k.c23 * c))


@pytest.mark.parametrize("level", LEVELS)
@pytest.mark.parametrize("ratio", [0.2, 1.0, 5.0])
def test_linear_limit_is_kalkers_theory(level, ratio):
    """At 1e-7 saturations no cell slips: Fx = G c^2 C11 xi, Fy = G c^2 (C22 eta + c C23 phi) within 1e-6 (the
    strips' Coulomb closed form, FASTSIM's flexibilities), the same as with Coulomb friction."""
    for xi, eta, phi in ((1e-7, 0.0, 0.0), (0.0, 1e-7, 0.0), (0.0, 0.0, 1e-7)):
        s = scene(ratio, "dry", 50.0, xi, eta, phi)
        falling = solve_elliptic(s, level)
        coulomb = solve_elliptic(s.replace(friction=Coulomb(s.friction_coefficient)), level)
        g, c = s.shear_modulus, s.hertz.c
        k = creepage_coefficients(ratio, s.material.poisson_ratio)
        expected = (g * c * c * k.c11 * s.longitudinal_creepage,
                    g * c * c * (k.c22 * s.lateral_creepage + c * k.c23 * s.spin_creepage))
        got = (falling.longitudinal_force, falling.lateral_force)
        for name, value, reference, other in zip(("Fx", "Fy"), got, expected,
                                                 (coulomb.longitudinal_force, coulomb.lateral_force), strict=True):
            assert abs(value - other) <= 1e-9 * abs(other) + 1e-30, f"{level} {name}: {value} vs Coulomb {other}"
            if reference != 0.0:
                assert math.isclose(value, reference, rel_tol=1e-6 if level == "strips" else 0.05), \
                    f"{level} a/b {ratio} {name} = {value:.6g} vs Kalker {reference:.6g}"


@pytest.mark.parametrize("level", LEVELS)
@pytest.mark.parametrize("law", ["dry", "wet", "rational"])
@pytest.mark.parametrize("direction", [(1.0, 0.0), (0.6, 0.8)])
def test_saturation_reaches_mu_of_the_rigid_slip_velocity(level, law, direction):
    """At 400 saturations every cell slips at nearly the rigid slip: |F| -> mu(V |w|) Fn (within 2e-3 mu(0) Fn: the
    cells' slip differs from the rigid slip by its elastic part, 1/400 of it)."""
    s = scene(1.0, law, 20.0, 400 * direction[0], 400 * direction[1])
    result = solve_elliptic(s, level)
    rigid = math.hypot(s.longitudinal_creepage, s.lateral_creepage)
    expected = float(s.friction.coefficient(s.rolling_speed * rigid)) * LOAD
    total = math.hypot(result.longitudinal_force, result.lateral_force)
    assert abs(total - expected) < 2e-3 * s.friction_coefficient * LOAD, \
        f"{level} {law}: |F| = {total:.6g} N vs mu(V |w|) Fn = {expected:.6g} N"


@pytest.mark.parametrize("level", LEVELS)
@pytest.mark.parametrize("ratio", [0.2, 1.0, 5.0])
@pytest.mark.parametrize("creepages", [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.5, 0.5, 1.0), (2.0, -1.0, 2.0),
                                       (0.0, 0.0, 3.0)])
def test_a_nearly_constant_law_gives_the_coulomb_answer_to_round_off(level, ratio, creepages):
    """A law that falls by 6e-13 of mu over the contact's slip velocities: the falling path's forces are the Coulomb
    path's to 1e-11 of mu Fn (the constant law's limit of the falling path is the Coulomb answer)."""
    s = scene(ratio, "dry", 50.0, *creepages)
    falling = solve_elliptic(s.replace(friction=ExponentialFalling(0.55, 0.4, 1e-12)), level)
    coulomb = solve_elliptic(s.replace(friction=Coulomb(0.55)), level)
    difference = np.array(falling.force_coefficients) - np.array(coulomb.force_coefficients)
    assert falling.message != coulomb.message, "the falling path ran"
    assert np.abs(difference).max() < 1e-11, f"{level}: falling - Coulomb = {difference}"


@pytest.mark.parametrize("level", LEVELS)
@pytest.mark.parametrize("law", sorted(LAWS))
def test_symmetries(level, law):
    """Mirroring y (eta, phi -> -eta, -phi) turns Fy and Mz; reversing xi turns Fx; both to round-off."""
    s = scene(0.5, law, 30.0, 1.0, 0.5, 1.5)
    base = np.array(solve_elliptic(s, level).force_coefficients)
    mirrored = np.array(solve_elliptic(s.replace(lateral_creepage=-s.lateral_creepage,
                                                 spin_creepage=-s.spin_creepage), level).force_coefficients)
    assert np.allclose(mirrored, base * np.array([1.0, -1.0, -1.0]), rtol=0.0, atol=1e-12), \
        f"{level} {law}: y mirrored {mirrored} vs {base}"
    pure = scene(0.5, law, 30.0, 2.0)
    forward = np.array(solve_elliptic(pure, level).force_coefficients)
    backward = np.array(solve_elliptic(pure.replace(longitudinal_creepage=-pure.longitudinal_creepage),
                                       level).force_coefficients)
    assert np.allclose(backward, -forward, rtol=0.0, atol=1e-12), f"{level} {law}: xi reversed {backward}"


@pytest.mark.parametrize("level", LEVELS)
@pytest.mark.parametrize("law", sorted(LAWS))
@pytest.mark.parametrize("creepages", [(1.0, 0.0, 0.0), (0.5, 0.5, 1.0), (2.0, -1.0, 2.0), (0.0, 0.0, 3.0)])
def test_traction_is_within_the_falling_bound_on_the_cells(level, law, creepages):
    """Every cell's |q| <= mu(0) p (the stick zones hold at most the static coefficient) and the force is below
    mu(0) Fn; the cells that slip carry less than the static bound where the law has fallen (the force below the
    Coulomb force at full slip)."""
    s = scene(1.0, law, 50.0, *creepages)
    result = solve_elliptic(s, level, fields=True)
    field = result.fields
    bound = s.friction_coefficient * field.pressure
    assert np.all(field.traction_magnitude <= bound * (1 + 1e-12) + 1e-9), f"{level} {law}: |q| > mu(0) p"
    assert math.hypot(result.longitudinal_force, result.lateral_force) <= s.friction_coefficient * LOAD * (1 + 1e-12)
    coulomb = solve_elliptic(s.replace(friction=Coulomb(s.friction_coefficient)), level)
    assert math.hypot(result.longitudinal_force, result.lateral_force) < math.hypot(
        coulomb.longitudinal_force, coulomb.lateral_force), f"{level} {law}: falling friction lowers the force"


@pytest.mark.parametrize("level", LEVELS)
def test_the_forces_fall_past_the_peak_of_the_creep_curve(level):
    """Dry rail at 50 m/s: the longitudinal creep curve peaks and falls."""
    forces = [solve_elliptic(scene(1.0, "dry", 50.0, xi), level).longitudinal_force for xi in (0.5, 1.5, 4.0, 10.0)]
    assert forces[1] > forces[2] > forces[3] > 0.0, f"{level}: {forces}"



@pytest.mark.parametrize("level", LEVELS)
@pytest.mark.parametrize("law", sorted(LAWS))
def test_rolling_without_creepage_gives_no_force_and_no_warning(level, law):
    """No creepage: no force, and no floating-point warning reaches the caller (an empty cell's bound over its zero
    trial traction is inf, whose min with 1 is 1)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        result = solve_elliptic(scene(1.0, law, 30.0), level)
    assert result.success, result.message
    assert np.abs(result.force_coefficients).max() <= 1e-15, f"{level} {law}: {result.force_coefficients}"


@pytest.mark.parametrize("law", ["linear", "dry"])
@pytest.mark.parametrize("ratio", [1.0, 2.0])
def test_strips_with_spin_on_a_steep_law_within_the_goal_of_the_discretised_level(law, ratio):
    """The combined creepage with spin (2, -1, 2 saturations) at 50 m/s, where the laws fall most over the patch: the
    strips within 0.03 mu(0) Fn (Mz over mu(0) Fn c) of the discretised level's default, their march's flexibilities
    at the coefficient of the rigid slip velocity (at mu(0) the lateral force came out 0.028-0.035 too large)."""
    s = scene(ratio, law, 50.0, 2.0, -1.0, 2.0)
    reference = solve_elliptic(s, "discretised")
    assert reference.success, reference.message
    error = np.array(solve_elliptic(s, "strips").force_coefficients) - np.array(reference.force_coefficients)
    assert np.abs(error).max() < 0.03, f"a/b {ratio}, {law}: strips - discretised = {error}"


@pytest.mark.parametrize("law", ["rational", "table", "dry"])
def test_each_cells_slip_is_its_own_whatever_the_cells_solved_with_it(law):
    """cell_slips, and its safeguarded iteration alone (the cells whose plain Newton steps leave the residual unmet,
    where a law falls faster than the cells resolve), on cells of several rolling speeds: every cell's slip,
    coefficient and slope are those it gets alone, bit for bit, so that a batch of contacts equals its contacts solved
    one by one (the safeguarded iteration stops each cell at its own convergence, not at the last cell's)."""
    from rollcontact.elliptic.methods import common

    law = LAWS[law]
    kernel = common.friction_kernel(law)
    rng = np.random.default_rng(5)
    rigid = rng.uniform(1e-4, 2e-2, 300)
    growth = rng.uniform(-2e-2, 8e-2, 300)
    speed = rng.choice([5.0, 50.0, 400.0, 2000.0], 300)
    limits = (law.static_coefficient, law.maximum_coefficient)
    together = common.bracketed(rigid, growth, kernel, speed, *limits)
    for k in range(rigid.size):
        alone = common.bracketed(rigid[k:k + 1], growth[k:k + 1], kernel, speed[k:k + 1], *limits)
        assert alone[0] == together[k], f"cell {k} of the safeguarded iteration: {alone[0]!r} != {together[k]!r}"
    together = common.cell_slips(rigid, growth, kernel, speed, *limits)
    for k in range(rigid.size):
        alone = common.cell_slips(rigid[k:k + 1], growth[k:k + 1], kernel, speed[k:k + 1], *limits)
        assert all(a[0] == t[k] for a, t in zip(alone, together, strict=True)), f"cell {k}: {alone} != together"


@pytest.mark.parametrize("law", ["linear", "dry"])
@pytest.mark.parametrize("ratio", [0.2, 1.0])
def test_strips_without_spin_follow_each_strips_2d_half_plane(law, ratio):
    """Without spin each strip is a 2D rolling problem, which the polynomial method solves exactly with falling
    friction (``falling="polynomial"``, one 2D solve per strip, the same strips' moduli): the march's cells, at the
    coefficient of their slip in the strip's half-plane, stay within 0.03 mu(0) Fn of it on pure longitudinal
    creepage at 50 m/s, where the steep linear law falls by a third over the slip zone (the simplified theory's slip,
    spread towards the trailing edge, missed it by 0.05)."""
    for xi in (1.0, 2.0, 4.0):
        s = scene(ratio, law, 50.0, xi)
        march = solve_elliptic(s, "strips").force_coefficients[0]
        exact = solve_elliptic(s, "strips", falling="polynomial").force_coefficients[0]
        assert abs(march - exact) < 0.03, f"a/b {ratio}, {law}, xi {xi} saturations: march {march:.4f}, 2D {exact:.4f}"


def test_the_closed_forms_slip_is_the_half_planes():
    """:func:`elastic_slips`' closed form (Carter's strip: slip ``sqrt((x - d)^2 - a*^2)`` behind the stick zone, in
    units of the slip length) against the half-plane's strain of the same traction on 400 cells (the rigid slip less
    :func:`hilbert` applied to it, given as a departure from no traction): within 1e-2 of the strip's half-length
    from 5 % of it behind the stick edge to 5 % before the trailing edge (the midpoint cells' error grows towards
    both, where the traction has a square root's slope), 0 in the stick zone."""
    from rollcontact.elliptic.methods import strips

    steps, d = 400, 0.4
    x = strips.cells(steps)[:, 0]
    inner = np.sqrt(np.maximum((1.0 - d) ** 2 - (x - d) ** 2, 0.0))
    traction = np.sqrt(1.0 - x * x) - np.where(x > 2.0 * d - 1.0, inner, 0.0)
    stick = x > 2.0 * d - 1.0
    ones, zeros = np.ones(1), np.zeros(1)
    common = (x[:, None], ones, ones * d, ones, zeros, zeros, ones * d, zeros)
    closed = strips.elastic_slips(*common, ones.astype(bool), stick[:, None], ones, (0.5 * ones, 0.5 * ones))[:, 0]
    numeric = strips.elastic_slips(x[:, None], ones, ones, zeros, zeros, zeros, ones * d, zeros, ~ones.astype(bool),
                                   np.zeros((steps, 1), bool), ones, (0.5 * ones, 0.5 * ones),
                                   np.array([traction[:, None], np.zeros((steps, 1))]))[:, 0]
    assert np.all(closed[stick] == 0.0), "no slip in the stick zone"
    behind = (x < 2.0 * d - 1.0 - 0.05) & (x > -0.95)
    exact = np.sqrt((x[behind] - d) ** 2 - (1.0 - d) ** 2)
    assert np.max(np.abs(closed[behind] - exact)) < 1e-12, "the closed form is Carter's slip"
    error = np.max(np.abs(numeric[behind] - exact))
    assert error < 1e-2, f"the half-plane's strain on 400 cells misses Carter's slip by {error:.3g}"
