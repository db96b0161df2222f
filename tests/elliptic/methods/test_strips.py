"""Strips against independent oracles: the 2D closed form (Carter, summed over the strips by adaptive quadrature) in
the strip limit b >> a, Kalker's linear theory at vanishing creepage, saturation at mu Fn, the symmetries, the
traction bound on the field, and, for velocity-dependent friction, the Coulomb strips where the law is nearly
constant.  Tolerances: the strip limit within the coefficient table's difference from it at a/b = 0.1 (0.5 %, so
0.01 mu Fn); the closed forms to 1e-10 (with spin too: the march adds only its departure from them)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from elliptic_outcome import outcome
from scipy.integrate import quad

from rollcontact import Coulomb, EllipticScene, ExponentialFalling, LinearFalling, Material, carter, solve_elliptic
from rollcontact.elliptic.creep_coefficients import creepage_coefficients
from rollcontact.elliptic.methods import strips

MU, LOAD = 0.3, 1e5


def scene(a=6e-3, b=4e-3, **fields):
    return EllipticScene.from_semi_axes(LOAD, a, b, friction=MU, **fields)


@pytest.mark.parametrize("fraction", [0.05, 0.3, 0.7, 1.0, 2.0])
def test_strips_are_carter_in_the_strip_limit(fraction):
    """a/b = 0.1, pure xi: each strip is Carter's 2D problem (N'(y) = pi a(y) p0(y) / 2, R = E* a / (2 p0))."""
    s = scene(1e-3, 1e-2)
    h, estar = s.hertz, s.material.contact_modulus
    radius = estar * h.a / (2 * h.max_pressure)
    xi = fraction * MU * h.a / radius  # Carter's saturation creepage of the central strip
    s = s.replace(longitudinal_creepage=xi)

    def per_length(y):
        half = h.a * math.sqrt(max(0.0, 1 - (y / h.b) ** 2))
        return carter(math.pi * half * half * h.max_pressure / (2 * h.a), xi, radius, estar, MU)[0]

    expected = quad(per_length, -h.b, h.b, epsabs=0, epsrel=1e-10, limit=200)[0]
    got = solve_elliptic(s, "strips").longitudinal_force
    assert abs(got - expected) < 0.01 * MU * LOAD, f"strips {got:.6g} N vs Carter over the strips {expected:.6g} N"


@pytest.mark.parametrize("ratio", [0.2, 1.0, 5.0])
@pytest.mark.parametrize("poisson_ratio", [0.0, 0.28, 0.45])
def test_linear_limit_reproduces_kalkers_coefficients(ratio, poisson_ratio):
    """Fx of xi (C11), Fy of eta (C22), Fy and Mz of spin (C23, C33), and Fx of xi with a trace of spin (the march's
    path: its departure from the closed form vanishes in the linear limit) at a/b 0.2, 1, 5 and nu 0, 0.28, 0.45."""
    s = scene(6e-3, 6e-3 / ratio, material=Material(210e9, poisson_ratio))
    g, c = s.shear_modulus, s.hertz.c
    coefficients = creepage_coefficients(ratio, poisson_ratio)
    # creepages small enough that even the shortest strips, near y = +-b, stick (their slip zone ~ creepage / a(y))
    fx = solve_elliptic(s.replace(longitudinal_creepage=1e-10), "strips").longitudinal_force
    fy = solve_elliptic(s.replace(lateral_creepage=1e-10), "strips").lateral_force
    spin = solve_elliptic(s.replace(spin_creepage=1e-8), "strips")
    fx_marched = solve_elliptic(s.replace(longitudinal_creepage=1e-10, spin_creepage=1e-14), "strips")
    assert math.isclose(fx, g * c * c * coefficients.c11 * 1e-10, rel_tol=1e-6), f"C11 slope at a/b = {ratio}"
    assert math.isclose(fy, g * c * c * coefficients.c22 * 1e-10, rel_tol=1e-6), f"C22 slope at a/b = {ratio}"
    assert math.isclose(spin.lateral_force, g * c**3 * coefficients.c23 * 1e-8, rel_tol=1e-6), \
        f"C23 slope at a/b = {ratio}: {spin.lateral_force / (g * c**3 * coefficients.c23 * 1e-8)}"
    assert math.isclose(spin.spin_moment, g * c**4 * coefficients.c33 * 1e-8, rel_tol=1e-6), \
        f"C33 slope at a/b = {ratio}: {spin.spin_moment / (g * c**4 * coefficients.c33 * 1e-8)}"
    assert fx_marched.message.startswith("strip theory, slip directions"), "the trace of spin takes the march"
    assert math.isclose(fx_marched.longitudinal_force, fx, rel_tol=1e-6), \
        f"C11 slope through the march at a/b = {ratio}: {fx_marched.longitudinal_force / fx}"


@pytest.mark.parametrize(("creepages", "tolerance"), [({"longitudinal_creepage": 0.1}, 1e-10),
                                                      ({"lateral_creepage": -0.1}, 1e-10),
                                                      ({"longitudinal_creepage": 0.03, "lateral_creepage": 0.04},
                                                       1e-10),
                                                      ({"longitudinal_creepage": 0.05, "spin_creepage": 2.0}, 0.01)])
def test_saturation_reaches_mu_fn(creepages, tolerance):
    """Full slip: |F| = mu Fn, but for the turn of the slip by the lateral force's longitudinal creepage ``-phi_c y``
    (``info["cross_spin"]``), an angle up to ``phi_c b / |w|`` at |y| = b that shortens |F| by at most its square."""
    s = scene(**creepages)
    result = solve_elliptic(s, "strips")
    total = math.hypot(result.longitudinal_force, result.lateral_force) / (MU * LOAD)
    turn = abs(result.info["cross_spin"]) * s.hertz.b / math.hypot(s.longitudinal_creepage, s.lateral_creepage)
    assert total <= 1.0 + 1e-12, f"|F| <= mu Fn: {total:.15f}"
    assert 1.0 - total < tolerance + turn**2, f"|F| -> mu Fn at large creepage: {total:.12f} (turn {turn:.3g})"


@pytest.mark.parametrize("spin", [0.0, 0.3, 3.0])
def test_symmetries(spin):
    def forces(xi, eta, phi):
        return solve_elliptic(scene(longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi), "strips")

    base, mirrored, flipped = forces(1e-3, 4e-4, spin), forces(-1e-3, 4e-4, spin), forces(1e-3, -4e-4, -spin)
    scale = MU * LOAD
    assert abs(mirrored.longitudinal_force + base.longitudinal_force) < 1e-12 * scale, "Fx odd in xi"
    assert abs(flipped.lateral_force + base.lateral_force) < 1e-12 * scale, "Fy odd in (eta, phi)"
    assert abs(flipped.spin_moment + base.spin_moment) < 1e-12 * scale * base.c, "Mz odd in (eta, phi)"


@pytest.mark.parametrize("creepages", [{"longitudinal_creepage": 1e-3, "lateral_creepage": -5e-4},
                                       {"lateral_creepage": 3e-4, "spin_creepage": 0.2},
                                       {"longitudinal_creepage": 1e-3, "spin_creepage": 2.0}])
def test_traction_bound_holds_on_the_field(creepages):
    result = solve_elliptic(scene(**creepages), "strips", fields=True)
    f = result.fields
    excess = f.traction_magnitude - MU * f.pressure
    assert np.all(excess <= 1e-9 * MU * result.max_pressure), f"|q| <= mu p: worst excess {excess.max():.3g} Pa"
    if "spin_creepage" not in creepages or creepages["spin_creepage"] < 1.0:
        assert f.stick.any() and not f.stick.all(), "partial slip: both zones present"


def cell_sums(result, scene, strips: int = 24):
    """Fx [N] and Mz [N m] of a result's traction field, summed as the strips sum it: Gauss over y (the weights of
    the scene's strips, split at its turning line with spin), midpoint cells along x."""
    from rollcontact.elliptic.methods.strips import StripStack

    f = result.fields
    area = (StripStack([scene], strips).weights[0] * (f.x[:, 0] - f.x[:, 1]))[:, None]
    return float(np.sum(f.traction_x * area)), float(np.sum((f.x * f.traction_y - f.y * f.traction_x) * area))


def test_the_field_sums_to_the_closed_form():
    s = scene(longitudinal_creepage=1e-3, lateral_creepage=-5e-4)
    closed = solve_elliptic(s, "strips")
    with_fields = solve_elliptic(s, "strips", fields=True, steps=400)
    assert with_fields.force_coefficients == closed.force_coefficients, "the forces do not depend on fields"
    fx, mz = cell_sums(with_fields, s)
    assert abs(fx - closed.longitudinal_force) < 2e-3 * MU * LOAD, f"Fx of the cells {fx:.6g} N"
    assert abs(mz - closed.spin_moment) < 2e-3 * MU * LOAD * closed.c, f"Mz of the cells {mz:.6g} N m"


@pytest.mark.parametrize("creepages", [{"longitudinal_creepage": 3e-4}, {"lateral_creepage": -2e-3},
                                       {"lateral_creepage": 3e-4, "spin_creepage": 0.2},
                                       {"longitudinal_creepage": 1e-3, "spin_creepage": 2.0}])
def test_asking_for_the_fields_changes_no_force(creepages):
    """The forces are the same with or without ``fields``; with spin they are the closed form plus the march's
    departure from it, which the cells' sums approach as the cells get finer (the midpoint rule misses the stick
    zones' square-root ends by O(steps^-1/2))."""
    s = scene(**creepages)
    plain, with_fields = solve_elliptic(s, "strips"), solve_elliptic(s, "strips", fields=True)
    assert with_fields.force_coefficients == plain.force_coefficients, \
        f"fields changed the forces: {with_fields.force_coefficients} against {plain.force_coefficients}"
    if s.spin_creepage != 0.0:
        gaps = []
        for steps in (20, 80, 320):
            fine = solve_elliptic(s, "strips", fields=True, steps=steps)
            fx, mz = cell_sums(fine, s)
            gaps.append(max(abs(fx - fine.longitudinal_force) / (MU * LOAD),
                            abs(mz - fine.spin_moment) / (MU * LOAD * fine.c)))
        assert gaps[-1] < 2e-3 and gaps[-1] <= max(gaps[0], 1e-12), \
            f"the cells' sums approach the forces (or equal them to rounding in full slip): gaps {gaps}"


def test_the_stick_zone_traction_meets_the_slip_traction_at_the_stick_edge():
    """The cells' mu p is Hertz's scaled so that the cells carry mu Fn (0.9966 at the default cells); the stick zones'
    traction takes the same scale, so that it is mu p at the stick edge, as the slip zone's.  A strip whose stick
    edge lies just behind a cell's centre (pure xi: the edge at ``2 d - a(y)``, ``d = X``) has that cell in its stick
    zone at mu p; unscaled it exceeded mu p there by 0.34 %."""
    from rollcontact.elliptic.methods.strips import DEFAULT_STEPS, StripStack

    s = scene()
    unit = StripStack((s.replace(longitudinal_creepage=1.0),), 24)  # X per unit xi
    for k, j in ((8, 6), (12, 3), (20, 9)):  # (strip, cell of its leading half)
        half = float(unit.half[0, k])
        centre = half * (1 - (2 * j + 1) / DEFAULT_STEPS)
        xi = (centre + half - 1e-9 * half) / 2 / float(unit.X[0, k])
        f = solve_elliptic(s.replace(longitudinal_creepage=xi), "strips", fields=True).fields
        assert f.stick[k, j] and not f.stick[k, j + 1], f"strip {k}: the stick edge just behind cell {j}"
        ratio = f.traction_magnitude[k, j] / (MU * f.pressure[k, j])
        assert 0.999 < ratio <= 1 + 1e-12, f"strip {k}, cell {j} at the stick edge: |q| / mu p = {ratio:.8f}"


def test_nearly_constant_falling_friction_gives_the_coulomb_strips():
    """The polynomial method per strip (its own path) against the closed form when mu barely falls."""
    s = scene(longitudinal_creepage=8e-4, lateral_creepage=3e-4, rolling_speed=10.0)
    coulomb = solve_elliptic(s, "strips")
    falling = solve_elliptic(s.replace(friction=ExponentialFalling(MU, 0.999, 1e-3)), "strips", falling="polynomial")
    assert falling.success, falling.message
    for name in ("longitudinal_force", "lateral_force"):
        assert abs(getattr(falling, name) - getattr(coulomb, name)) < 2e-3 * MU * LOAD, name
    assert abs(falling.spin_moment - coulomb.spin_moment) < 5e-3 * MU * LOAD * coulomb.c, "Mz"


def test_falling_friction_shows_the_falling_branch():
    """Eurosprinter geometry (a/b 0.5, a 6.3 mm, Fn 106.7 kN, V 10 m/s) with Polach's exponential law."""
    law = ExponentialFalling(0.36, 0.4, 0.6)
    s = EllipticScene.from_semi_axes(106.7e3, 6.3e-3, 12.6e-3, friction=law, rolling_speed=10.0)
    curve = [solve_elliptic(s.replace(longitudinal_creepage=xi), "strips") for xi in (0.002, 0.01, 0.05, 0.2)]
    assert all(r.success for r in curve), [r.message for r in curve]
    forces = [r.longitudinal_force for r in curve]
    assert forces[1] > forces[2] > forces[3] > 0, f"past the peak the force falls: {forces}"


def test_spin_with_falling_friction_is_served_by_the_march_and_refused_by_the_polynomial_path():
    s = scene(spin_creepage=0.5).replace(friction=ExponentialFalling(MU))
    result = solve_elliptic(s, "strips")
    assert result.success and result.message == "strip theory, falling friction on the march's cells", result.message
    with pytest.raises(ValueError, match="no spin"):
        solve_elliptic(s, "strips", falling="polynomial")
    with pytest.raises(ValueError, match="falling"):
        solve_elliptic(s, "strips", falling="other")
    assert solve_elliptic(s.replace(friction=Coulomb(MU)), "strips").success, "Coulomb spin is served"


def saturated(ratio, xi=0.0, eta=0.0, phi=0.0, poisson_ratio=None):
    """The scene at a/b = ratio (c = 6 mm; steel, or E 210 GPa and nu = ``poisson_ratio``) with creepages in saturation
    units: the creepage whose linear force (Kalker's C11, C22, C23) is mu Fn."""
    c = 6e-3
    material = {} if poisson_ratio is None else {"material": Material(210e9, poisson_ratio)}
    s = EllipticScene.from_semi_axes(LOAD, c * math.sqrt(ratio), c / math.sqrt(ratio), friction=MU, **material)
    k = creepage_coefficients(ratio, s.material.poisson_ratio)
    unit = MU * LOAD / (s.shear_modulus * c * c)
    return s.replace(longitudinal_creepage=xi * unit / k.c11, lateral_creepage=eta * unit / k.c22,
                     spin_creepage=phi * unit / (k.c23 * c))


@pytest.mark.parametrize("ratio", [0.2, 1.0, 2.0, 5.0])
@pytest.mark.parametrize("creepages", [(0.0, 0.0, 1.0), (0.0, 0.0, 3.0), (0.5, 0.5, 1.0), (0.5, 0.5, 3.0),
                                       (1.0, -0.5, 3.0)])
def test_spin_against_the_discretised_solution(ratio, creepages):
    """Large spin (psi 1..3), alone and with longitudinal and lateral creepage, at a/b 0.2, 1, 2 and 5, against the
    discretised solver's Richardson pair of 30 and 60 elements (within 0.0038 of the pair of 60 and 120 on these
    cases: ``benchmarks/calibrate_elliptic_levels.py``, table B2).  The goal is 0.03 mu Fn (Fx, Fy) and 0.03 mu Fn c
    (Mz).  Every error is also within the level's own estimate."""
    s = saturated(ratio, *creepages)
    reference = np.array(solve_elliptic(s, "discretised", elements=60, extrapolate=True).force_coefficients)
    result = solve_elliptic(s, "strips")
    error = np.abs(np.array(result.force_coefficients) - reference)
    tolerance = 0.03
    assert result.info["psi"] >= 0.9, f"the case is in the large-spin region: psi = {result.info['psi']:.3g}"
    assert error.max() <= tolerance, (
        f"errors Fx {error[0]:.4f}, Fy {error[1]:.4f}, Mz {error[2]:.4f} beyond {tolerance} at a/b {ratio}, "
        f"creepages {creepages}")
    assert error.max() <= result.info["error_estimate"], (
        f"error {error.max():.4f} beyond the estimate {result.info['error_estimate']:.4f}")


@pytest.mark.parametrize("poisson_ratio", [0.0, 0.45])
@pytest.mark.parametrize(("ratio", "creepages"), [(0.2, (0.0, 0.9, 0.0)), (1.0, (0.5, 0.5, 1.0)),
                                                  (5.0, (0.0, 0.0, 2.0)), (2.0, (0.3, -0.5, 3.0))])
def test_other_poisson_ratios_within_the_estimate(poisson_ratio, ratio, creepages):
    """Far from steel's nu (the constants are fitted at 0.28 first): the moment of lateral creepage at a/b = 0.2 (the
    largest error without spin grows with nu), spin with creepage and deep spin, against the discretised solver's
    pair of 30 and 60 elements, within the level's own estimate (which grows with nu above 0.28)."""
    s = saturated(ratio, *creepages, poisson_ratio=poisson_ratio)
    reference = np.array(solve_elliptic(s, "discretised", elements=60, extrapolate=True).force_coefficients)
    result = solve_elliptic(s, "strips")
    error = np.abs(np.array(result.force_coefficients) - reference)
    assert error.max() <= result.info["error_estimate"], (
        f"errors Fx, Fy, Mz {error} beyond the estimate {result.info['error_estimate']:.4f} at nu {poisson_ratio}, "
        f"a/b {ratio}, creepages {creepages}")


@pytest.mark.parametrize("ratio", [1.0, 5.0])
@pytest.mark.parametrize("creepages", [(0.0, -0.5), (0.3, -0.5), (0.0, -1.0)])
def test_lateral_creepage_against_the_spin_passes_psi_one_continuously(ratio, creepages):
    """Where the lateral creepage opposes the spin, strip theory's stick zone exists past |psi| = 1: the forces just
    below and just above it agree (a switch to full slip there jumps by up to 0.18 mu Fn on these cases)."""
    xi, eta = creepages
    below, above = (solve_elliptic(saturated(ratio, xi * f, eta * f, f), "strips") for f in (1.0 - 1e-7, 1.0 + 1e-7))
    assert below.info["psi"] < 1.0 < above.info["psi"], "the pair straddles |psi| = 1"
    assert above.info["stick_strips"] > 0.0, "strips still stick past |psi| = 1"
    jump = np.abs(np.array(above.force_coefficients) - np.array(below.force_coefficients))
    assert jump.max() < 1e-5, f"Fx, Fy, Mz change by {jump} across |psi| = 1 at a/b {ratio}, creepages {creepages}"


@pytest.mark.parametrize(("ratio", "creepages"), [(1.0, (0.0, -1.0)), (5.0, (0.3, -0.5))])
def test_stick_zones_past_psi_one_fade_out_without_a_jump(ratio, creepages):
    """Along spin 0.9 .. 2.5 saturations with the lateral creepage against it, in steps of 0.01, where the stick zones
    kept past |psi| = 1 fade out (STICK_FADE): no force changes between neighbouring steps by more than 0.012 mu Fn
    (dropping the zones where their traction first exceeds mu p jumps by 0.026 and 0.038 on these lines)."""
    xi, eta = creepages
    forces = np.array([solve_elliptic(saturated(ratio, xi * f, eta * f, f), "strips").force_coefficients
                       for f in np.arange(0.9, 2.5, 0.01)])
    change = np.abs(np.diff(forces, axis=0)).max(axis=0)
    assert change.max() < 0.012, f"largest change of Fx, Fy, Mz between neighbouring spins {change} at a/b {ratio}"


@pytest.mark.parametrize("ratio", [1.0, 5.0])
@pytest.mark.parametrize("spin", [1.0, 1.1, 1.2])
def test_lateral_creepage_against_the_spin_against_the_discretised_solution(ratio, spin):
    """Spin just past |psi| = 1 with half as much lateral creepage against it, against the discretised solver's pair of
    30 and 60 elements: within 0.05 (Fx, Fy over mu Fn, Mz over mu Fn c; the largest error along such lines is 0.047,
    where the stick zones fade out: ``benchmarks/calibrate_strips_spin.py``), and within the level's own estimate;
    the stick zones that remain keep |q| <= mu p."""
    s = saturated(ratio, 0.0, -0.5 * spin, spin)
    reference = np.array(solve_elliptic(s, "discretised", elements=60, extrapolate=True).force_coefficients)
    result = solve_elliptic(s, "strips", fields=True)
    error = np.abs(np.array(result.force_coefficients) - reference)
    assert error.max() <= 0.05, f"errors Fx, Fy, Mz {error} at a/b {ratio}, spin {spin}"
    assert error.max() <= result.info["error_estimate"], (
        f"error {error.max():.4f} beyond the estimate {result.info['error_estimate']:.4f}")
    f = result.fields
    excess = f.traction_magnitude - MU * f.pressure
    assert np.all(excess <= 1e-9 * MU * result.max_pressure), f"|q| <= mu p: worst excess {excess.max():.3g} Pa"


@pytest.mark.parametrize("ratio", [0.3, 1.0, 3.0])
def test_cross_coefficient_against_the_half_space_influence(ratio):
    """``u_x`` of a lateral traction of Hertz's shape, by the discretised half-space's influence coefficients (80 x 80
    elements, G = 1 Pa), is ``K x y`` on the ellipse; the strips' closed form gives ``phi_c = -K`` per unit Fy.
    Tolerance 0.5 % (the grid's error of the fitted slope, 0.05 % measured); the circle also against Johnson's
    ``K = pi nu q0 / (8 G a)`` to 1e-12."""
    from rollcontact.core.halfspace.rolling import ellipse_grid, hertz_pressure
    from rollcontact.core.halfspace.surface import operator_for
    from rollcontact.elliptic.methods.strips import cross_coefficient

    s = scene(6e-3, 6e-3 / ratio)
    h, nu = s.hertz, s.material.poisson_ratio
    grid = ellipse_grid(h.a, h.b, 80)
    q = hertz_pressure(grid, h.a, h.b, 1.0)  # lateral traction of Hertz's shape carrying 1 N
    ux, _ = operator_for(grid, nu).tangential(np.zeros_like(q), q)
    x, y = grid.mesh()
    inner = (x / h.a) ** 2 + (y / h.b) ** 2 < 0.5
    slope = float(np.sum(ux[inner] * x[inner] * y[inner]) / np.sum((x[inner] * y[inner]) ** 2))  # u_x = K x y
    expected = -slope / s.shear_modulus  # phi_c per newton of Fy at the scene's G
    got = cross_coefficient(s)
    assert abs(got - expected) < 5e-3 * abs(expected), f"phi_c/Fy {got:.6g} vs half-space {expected:.6g} 1/(N m)"
    if ratio == 1.0:
        johnson = -math.pi * nu * (3.0 / (2.0 * math.pi * h.a * h.b)) / (8.0 * s.shear_modulus * h.a)  # -K
        assert abs(got - johnson) < 1e-12 * abs(johnson), f"circle: {got:.12g} vs Johnson {johnson:.12g}"


def test_several_scenes_together_are_each_scene_alone_bit_for_bit():
    """solve_strips_many: one array operation over the scenes, each result bit for bit solve_strips of its scene (with
    and without spin, either ellipse orientation, stick and full slip)."""
    from rollcontact.elliptic.methods.strips import solve_strips, solve_strips_many

    rng = np.random.default_rng(11)
    scenes = []
    for _ in range(9):
        A, B = rng.uniform(0.5, 4.0, 2)
        creepages = rng.normal(0.0, 2e-3, 2).tolist() + [float(rng.choice([0.0, rng.normal(0.0, 1.0)]))]
        scenes.append(EllipticScene(float(rng.uniform(1e4, 2e5)), float(A), float(B), *creepages))
    together = solve_strips_many(scenes)
    for scene, result in zip(scenes, together, strict=True):
        alone = solve_strips(scene)
        assert (result.longitudinal_force, result.lateral_force, result.spin_moment) == (
            alone.longitudinal_force, alone.lateral_force, alone.spin_moment), scene
        assert result.message == alone.message and result.info == alone.info


def mixed_batch():
    """Scenes of every kind: a/b 0.2..5 either way round, loads 1 kN..200 kN and none, three materials and friction
    coefficients, no creepage, creepages without spin (the cross influence), spin alone and with creepages (stick and
    full slip, |psi| past 1), and velocity-dependent friction of two laws at several speeds, with spin and without,
    loaded and not."""
    rng = np.random.default_rng(36)
    materials = (Material(), Material(2.1e11, 0.28), Material(1.9e11, 0.25))
    scenes = []
    for k in range(24):
        ratio = float(np.exp(rng.uniform(np.log(0.2), np.log(5.0))))
        load = 0.0 if k in (3, 17) else float(np.exp(rng.uniform(np.log(1e3), np.log(2e5))))
        xi, eta = rng.normal(0.0, 2e-3, 2)
        phi = float(rng.normal(0.0, 1.0)) * (10.0 if k % 4 == 3 else 1.0)
        xi, eta, phi = ((0.0, 0.0, 0.0), (xi, eta, 0.0), (0.0, 0.0, phi), (xi, eta, phi), (xi, 0.0, 0.0),
                        (xi, eta, phi))[k % 6]
        base = EllipticScene.from_semi_axes(1e5, 6e-3 * math.sqrt(ratio), 6e-3 / math.sqrt(ratio),
                                            material=materials[k % 3], friction=(0.3, 0.2, 0.45)[k % 3])
        scenes.append(base.replace(normal_load=load, longitudinal_creepage=float(xi), lateral_creepage=float(eta),
                                   spin_creepage=phi))
    scenes.append(scenes[1].replace(friction=ExponentialFalling(0.3, 0.4, 0.6), rolling_speed=10.0, spin_creepage=0.0))
    laws = (ExponentialFalling(0.3, 0.4, 0.6), LinearFalling(0.4, 0.25, 0.3))
    for k in (1, 3, 5, 7, 9, 11, 13, 17):
        scenes.append(scenes[k].replace(friction=laws[k % 4 // 2], rolling_speed=float(5.0 + 3.0 * k)))
    return scenes


@pytest.mark.parametrize("fields", [False, True])
def test_a_mixed_batch_is_each_scene_alone_bit_for_bit(fields):
    """solve_strips_many of a mixed batch (mixed_batch: no load, no spin, spin, falling friction) in two orders and in
    small groups: every result bit for bit solve_strips of its scene, fields included; the stack's numbers of a scene do
    not depend on its neighbours (the march computes the stick zones on the sticking strips alone in large stacks and
    on all strips in small ones: the same elementwise operations)."""
    from rollcontact.elliptic.methods.strips import solve_strips, solve_strips_many

    scenes = mixed_batch()
    alone = [outcome(solve_strips(s, fields=fields)) for s in scenes]
    assert sum(s.normal_load == 0.0 for s in scenes) == 4 and any(s.spin_creepage == 0.0 for s in scenes)
    together = [outcome(r) for r in solve_strips_many(scenes, fields=fields)]
    backwards = [outcome(r) for r in solve_strips_many(scenes[::-1], fields=fields)][::-1]
    pairs = [outcome(r) for k in range(0, len(scenes), 2) for r in solve_strips_many(scenes[k:k + 2], fields=fields)]
    for k, scene in enumerate(scenes):
        assert together[k] == alone[k], f"scene {k} in the batch differs from alone: {scene}"
        assert backwards[k] == alone[k], f"scene {k} in the reversed batch differs from alone: {scene}"
        assert pairs[k] == alone[k], f"scene {k} in a pair differs from alone: {scene}"
    marched = [(r.message, s.friction.is_constant) for r, s in zip(solve_strips_many(scenes, fields=fields), scenes,
                                                                    strict=True)
               if r.spin_creepage != 0.0 and r.normal_load > 0.0]
    assert {m for m, coulomb in marched if coulomb} == {"strip theory, slip directions of the simplified theory"}
    assert {m for m, coulomb in marched if not coulomb} == {"strip theory, falling friction on the march's cells"}


def test_a_batch_names_the_scene_it_cannot_solve():
    from rollcontact.elliptic.methods.strips import solve_strips_many

    scenes = mixed_batch()[:3] + [EllipticScene.from_semi_axes(LOAD, 6e-3, 2e-4, friction=MU)]
    with pytest.raises(ValueError, match="strips cannot solve scene 3: a/b = 30 is outside"):
        solve_strips_many(scenes)
    with pytest.raises(ValueError, match="steps"):
        solve_strips_many(scenes[:3], steps=1)


@pytest.mark.parametrize("ratio", [0.2, 1.0, 5.0])
def test_march_flexibilities_are_fastsims_blended_ones_times_the_spin_factor(ratio):
    """The stack's march flexibilities (plain floats per scene) against FASTSIM's blended flexibilities of the scene
    times the factors of SPIN_FLEXIBILITY written out here, and the march's ratio r' of the longitudinal slip of spin
    against the stick zones' r, to round-off."""
    from rollcontact.elliptic.methods.fastsim import blended_flexibilities
    from rollcontact.elliptic.methods.strips import SPIN_FLEXIBILITY, StripStack

    s = scene(6e-3, 6e-3 / ratio, longitudinal_creepage=1e-3, lateral_creepage=-5e-4, spin_creepage=0.7)
    stack = StripStack((s,), 24)
    psi = stack.psi[0, 0]
    x0, x1, y0, y1, p1, power, half_way, onset = SPIN_FLEXIBILITY
    fall = 1.0 + abs(psi) / (p1 * (1.0 + ratio) ** power)
    rise = abs(psi) / (abs(psi) + onset)
    k_x = (1.0 + (x0 + x1 * math.log(ratio) - 1.0) * rise) / fall
    k_y = (1.0 + (y0 + y1 * math.log(ratio) - 1.0) * rise) / fall
    factors = (k_x, k_y, k_y)
    expected = [f * v for f, v in zip(factors, blended_flexibilities(s, creepage_coefficients(ratio, 0.28)),
                                      strict=True)]
    got = [float(v[0, 0]) for v in stack.flexibilities]
    assert np.allclose(got, expected, rtol=1e-12, atol=0.0), f"march flexibilities {got} vs {expected}"
    r = stack.moment_ratio[0, 0]
    assert math.isclose(stack.march_ratio[0, 0], 1.0 + (r - 1.0) / (1.0 + abs(psi) / half_way), rel_tol=1e-14), \
        f"march ratio {stack.march_ratio[0, 0]} against r = {r}"


def opposed_spin(ratio: float = 0.2):
    """a/b 0.2, creepages (2, -1, 2) in saturations of mu Fn (the lateral against the spin, past |psi| = 1): the
    strips' turning line ``xi / (r phi)`` lies within the ellipse, where a strip's longitudinal traction turns over a
    layer narrower than the strips' spacing."""
    k = creepage_coefficients(ratio, 0.28)
    base = EllipticScene.from_semi_axes(LOAD, 6e-3 * math.sqrt(ratio), 6e-3 / math.sqrt(ratio), friction=MU)
    unit = MU * LOAD / (base.shear_modulus * 36e-6)
    return base.replace(longitudinal_creepage=2.0 * unit / k.c11, lateral_creepage=-1.0 * unit / k.c22,
                        spin_creepage=2.0 * unit / (k.c23 * 6e-3))


def test_strips_split_at_the_turning_line_converge_at_the_default_count():
    """With the strips split at the turning line the default 24 strips are within 0.002 mu Fn (Mz over mu Fn c) of 192
    strips; across the whole ellipse they missed Fx by 0.04 (the layer fell between the Gauss nodes)."""
    s = opposed_spin()
    stack = strips.StripStack([s], strips.DEFAULT_STRIPS)
    line = s.longitudinal_creepage / (float(stack.march_ratio[0, 0]) * s.spin_creepage)
    assert abs(line) < s.hertz.b, f"the case's turning line {line:.4g} m lies within the ellipse"
    coarse = solve_elliptic(s, "strips").force_coefficients
    fine = solve_elliptic(s, "strips", strips=192).force_coefficients
    worst = max(abs(a - b) for a, b in zip(coarse, fine, strict=True))
    assert worst < 2e-3, f"24 strips {coarse} against 192 strips {fine}: {worst:.4f}"


def test_the_forces_do_not_jump_as_the_turning_line_moves():
    """Along a line of creepages that moves the turning line across the ellipse (xi from -4 to 4 saturations in steps
    of 0.05, spin 2, the lateral creepage against it) neighbouring forces differ by at most 0.005 mu Fn (0.003 here);
    the strips across the whole ellipse jumped by 0.014 in Fx as the line crossed their nodes."""
    base = opposed_spin()
    k = creepage_coefficients(0.2, 0.28)
    unit = MU * LOAD / (base.shear_modulus * 36e-6) / k.c11
    values = np.array([solve_elliptic(base.replace(longitudinal_creepage=x * unit), "strips").force_coefficients
                       for x in np.linspace(-4.0, 4.0, 161)])
    steps = np.abs(np.diff(values, axis=0)).max(axis=0)
    assert steps.max() < 5e-3, f"largest change between neighbours (Fx, Fy, Mz): {steps}"
