"""Steady 3D rolling on the discretised half-space (rollcontact.core.halfspace.rolling): normal problem, linear limit,
saturation, friction bound, symmetries, convergence, the 2D limit and velocity-dependent friction."""

import math

import numpy as np
import pytest

from rollcontact.core.friction import Coulomb, ExponentialFalling
from rollcontact.core.halfspace.rolling import ellipse_grid, hertz_pressure, solve_normal, solve_steady, total_forces
from rollcontact.core.halfspace.surface import operator_for
from rollcontact.line.carter import carter

G = 8.0e10  # Pa
LOAD = 1.0e5  # N
MU = 0.3
COULOMB = Coulomb(MU)


def setup(ratio, n, nu=0.28, c=6e-3, margin=0):
    """Grid, operator, Hertz pressure and centres of an ellipse with a/b = ratio and sqrt(ab) = c [m]."""
    a, b = c * math.sqrt(ratio), c / math.sqrt(ratio)
    grid = ellipse_grid(a, b, n, margin=margin)
    x, y = grid.mesh()
    return grid, operator_for(grid, nu), hertz_pressure(grid, a, b, LOAD), x, y


def run(case, creepages, friction=COULOMB, speed=1.0, **options):
    """Forces ``(Fx, Fy, Mz)`` over ``(mu Fn, mu Fn, mu Fn c)`` and the solution."""
    grid, op, p, x, y = case
    xi, eta, phi = creepages
    sol = solve_steady(op, p, (xi - phi * y + 0 * x, eta + phi * x), G, friction, speed, **options)
    assert sol.converged, f"solve of {creepages} failed: {sol.message}"
    fx, fy, mz = total_forces(grid, sol.traction_x, sol.traction_y)
    mu = friction.static_coefficient
    c = math.sqrt(grid.nx * grid.dx * grid.ny * grid.dy) / 2
    return np.array([fx / (mu * LOAD), fy / (mu * LOAD), mz / (mu * LOAD * c)]), sol


def saturation(c=6e-3):
    """The longitudinal creepage of full slip in linear theory, 3 mu Fn / (G c^2 C11) with C11 about 4."""
    return 3.0 * MU * LOAD / (G * c * c * 4.0)


def test_linear_limit_matches_kalkers_coefficients_on_a_coarse_grid():
    """nu = 0.25, a/b = 1 (Kalker 1990, Table E.3: C11 4.12, C22 3.67, C23 1.47): at vanishing creepage no element
    slips and ``F = G c^2 C xi``; 32 x 32 elements are within 3 % (the 1 % of the table needs the extrapolation of
    benchmarks/calibrate_creep_coefficients.py)."""
    case = setup(1.0, 32, nu=0.25)
    c, e = 6e-3, 1e-9
    table = {"C11": 4.12, "C22": 3.67, "C23": 1.47}
    forces = {}
    for name, creep in (("C11", (e, 0, 0)), ("C22", (0, e, 0)), ("C23", (0, 0, e / c))):
        f, sol = run(case, creep)
        assert sol.stick[case[2] > 0].all(), f"{name}: some element slips at creepage {e}"
        forces[name] = f
    values = {"C11": forces["C11"][0], "C22": forces["C22"][1], "C23": forces["C23"][1]}
    for name, value in values.items():
        coefficient = value * MU * LOAD / (G * c * c * e)
        assert coefficient == pytest.approx(table[name], rel=0.03), (
            f"{name} = {coefficient:.4f} from the solver vs Kalker's {table[name]}")
    # Kalker's Mz from eta is -G c^3 C23 eta on the wheel: the same C23 as Fy from spin (reciprocity)
    c23_moment = -forces["C22"][2] * MU * LOAD * c / (G * c**3 * e)
    c23_force = values["C23"] * MU * LOAD / (G * c * c * e)
    assert c23_moment == pytest.approx(c23_force, rel=0.02), (
        f"C23 from Mz(eta) {c23_moment:.4f} vs from Fy(phi) {c23_force:.4f}")


def test_saturation_gives_mu_fn_and_spin_alone_stays_below():
    """In full slip every element carries mu p; with nu > 0 the slip direction tilts by the Cerruti coupling
    (u_y from q_x, odd in y), so |F| falls short of mu Fn by a little (1e-5 here), never exceeds it."""
    case = setup(0.5, 24)
    f, sol = run(case, (20 * saturation(), 0, 0))
    assert 1.0 - 1e-4 < f[0] <= 1.0 + 1e-12, f"full slip Fx/(mu Fn) = {f[0]!r}"
    assert not sol.stick.any(), "an element sticks at 20 saturation creepages"
    q = np.hypot(sol.traction_x, sol.traction_y)
    np.testing.assert_allclose(q, MU * case[2], rtol=1e-9, atol=1e-12 * case[2].max(),
                               err_msg="|q| != mu p in full slip")
    f, _ = run(case, (0, 14 * saturation(), 0))
    assert 1.0 - 1e-4 < f[1] <= 1.0 + 1e-12, f"full slip Fy/(mu Fn) = {f[1]!r}"
    f, _ = run(case, (0, 0, 40 * saturation() / 6e-3))
    assert 0.0 < f[1] < 1.0 and 0.0 < f[2] < 1.0, f"pure spin: Fy and Mz over mu Fn (c) = {f[1:]}, not in (0, 1)"


@pytest.mark.parametrize("creepages", [(0.5, 0, 0), (0, 0.7, 0), (0, 0, 1.5), (0.3, -0.2, 2.5)])
def test_traction_bound_and_slip_direction_on_every_element(creepages):
    case = setup(2.0, 24)
    s = saturation()
    _, sol = run(case, (creepages[0] * s, creepages[1] * s, creepages[2] * s / 6e-3))
    q = np.hypot(sol.traction_x, sol.traction_y)
    bound = MU * case[2]
    assert np.all(q <= bound * (1 + 1e-9) + 1e-9 * bound.max()), (
        f"|q| exceeds mu p by {np.max(q - bound) / bound.max():.2e} of max mu p")
    slip = np.hypot(sol.slip_x, sol.slip_y)
    contact = case[2] > 0
    slipping = contact & ~sol.stick
    cosine = (sol.traction_x * sol.slip_x + sol.traction_y * sol.slip_y)[slipping] / (q * slip)[slipping]
    assert np.all(cosine > 1 - 1e-6), f"traction not along the slip: smallest cosine {cosine.min():.8f}"
    assert np.all(np.abs(q[slipping] - bound[slipping]) <= 1e-7 * bound.max()), "slip below the traction bound"
    if creepages[0] == 0.5:
        assert sol.stick.any(), "no stick area at half the saturation creepage"
    if sol.stick.any():
        assert slip[sol.stick].max() <= 1e-6 * s, f"stick elements slip by {slip[sol.stick].max():.2e}"


def test_symmetries_fx_odd_in_xi_and_fy_mz_odd_in_eta_phi_together():
    case = setup(0.5, 20)
    s = saturation()
    for creepages in ((0.6 * s, 0.3 * s, 1.2 * s / 6e-3), (0.2 * s, -0.5 * s, 0.4 * s / 6e-3)):
        xi, eta, phi = creepages
        base, _ = run(case, creepages, tolerance=1e-11)
        flipped_xi, _ = run(case, (-xi, eta, phi), tolerance=1e-11)
        flipped_lateral, _ = run(case, (xi, -eta, -phi), tolerance=1e-11)
        np.testing.assert_allclose(flipped_xi * [-1, 1, 1], base, atol=1e-8,
                                   err_msg=f"Fx not odd in xi (Fy, Mz not even) at {creepages}")
        np.testing.assert_allclose(flipped_lateral * [1, -1, -1], base, atol=1e-8,
                                   err_msg=f"Fy, Mz not odd in (eta, phi) (Fx not even) at {creepages}")
    pure, _ = run(case, (0.7 * s, 0, 0), tolerance=1e-11)
    assert abs(pure[1]) < 1e-9 and abs(pure[2]) < 1e-9, f"pure xi gives Fy, Mz = {pure[1:]}"


def test_forces_converge_at_first_order_and_richardson_improves():
    s = saturation()
    creepages = (0.4 * s, 0.3 * s, 0.8 * s / 6e-3)
    forces = [run(setup(1.0, n), creepages)[0] for n in (10, 20, 40, 80)]
    differences = [np.abs(forces[i] - forces[i + 1]).max() for i in range(3)]
    orders = [math.log2(differences[i] / differences[i + 1]) for i in range(2)]
    assert all(0.6 < order < 2.5 for order in orders), f"orders {orders} from differences {differences}"
    finest = 2 * forces[3] - forces[2]  # Richardson from 40 and 80 elements: the best estimate of the limit
    richardson = 2 * forces[2] - forces[1]
    assert np.abs(richardson - finest).max() < 0.5 * np.abs(forces[2] - finest).max(), (
        "Richardson from 20 and 40 elements does not halve the error of 40 elements alone")
    assert differences[-1] < 0.01, f"40 -> 80 elements still moves the forces by {differences[-1]:.4f} mu Fn"


def test_centre_strip_of_a_long_ellipse_approaches_carter():
    """b = 20 a, pure xi: the strip y = 0 is a 2D rolling contact of half-width a and peak pressure p0 (Carter,
    E* = G / (1 - nu), R from a^2 = 4 N' R / (pi E*)): its traction per length within 0.015 mu N'."""
    nu = 0.25
    a, b = 1e-3, 20e-3
    grid = ellipse_grid(a, b, (40, 21))
    x, y = grid.mesh()
    pressure = hertz_pressure(grid, a, b, LOAD)
    op = operator_for(grid, nu)
    middle = grid.ny // 2
    load_per_length = pressure[:, middle].sum() * grid.dx
    contact_modulus = G / (1 - nu)
    radius = math.pi * contact_modulus * a * a / (4 * math.pi * a * pressure.max() / 2)
    for fraction in (0.2, 0.5, 0.8):
        creep = fraction * MU * a / radius
        sol = solve_steady(op, pressure, (creep + 0 * x, 0 * y), G, Coulomb(MU))
        strip = sol.traction_x[:, middle].sum() * grid.dx
        expected = carter(load_per_length, creep, radius, contact_modulus, MU)[0]
        assert strip == pytest.approx(expected, abs=0.015 * MU * load_per_length), (
            f"centre strip T'/(mu N') = {strip / (MU * load_per_length):.4f} vs Carter "
            f"{expected / (MU * load_per_length):.4f} at {fraction} of full slip")


def test_discretised_normal_problem_matches_hertz_and_balances_the_load():
    """Polonsky-Keer on the gap A x^2 + B y^2 of a sphere (A = B = pi p0 / (4 E* a)): load balance at round-off,
    contact and peak pressure as Hertz's, and the tangential forces as those on the sampled Hertz pressure."""
    nu, a = 0.28, 6e-3
    grid, op, sampled, x, y = setup(1.0, 30, nu=nu, c=a, margin=3)
    contact_modulus = G / (1 - nu)
    p0 = 3 * LOAD / (2 * math.pi * a * a)
    curvature = math.pi * p0 / (4 * contact_modulus * a)
    normal = solve_normal(op, curvature * (x**2 + y**2), LOAD, G)
    assert normal.converged, normal.message
    assert normal.load_balance < 1e-12, f"load balance {normal.load_balance:.1e}"
    assert normal.pressure.max() == pytest.approx(p0, rel=0.01), f"peak {normal.pressure.max() / p0:.4f} p0"
    assert abs(int(normal.contact.sum()) - int((sampled > 0).sum())) <= 4 * 30, "contact area differs from Hertz's"
    assert np.abs(normal.pressure - sampled).max() < 0.05 * p0, "pressure differs from Hertz's by more than 5 % p0"
    s = saturation()
    for creepages in ((0.5 * s, 0, 0), (0.2 * s, 0.4 * s, 1.5 * s / a)):
        with_hertz, _ = run((grid, op, sampled, x, y), creepages)
        with_normal, _ = run((grid, op, normal.pressure, x, y), creepages)
        np.testing.assert_allclose(with_normal, with_hertz, atol=3e-3,
                                   err_msg=f"forces on the two pressures differ at {creepages}")


def test_falling_friction_shows_the_falling_branch_and_constant_law_is_coulomb():
    """Polach's exponential law on the Eurosprinter's ellipse (a/b 0.5, a 6.3 mm, 106.7 kN, V 10 m/s)."""
    a, b, load, speed = 6.3e-3, 12.6e-3, 106.7e3, 10.0
    grid = ellipse_grid(a, b, 20)
    x, y = grid.mesh()
    op = operator_for(grid, 0.28)
    pressure = hertz_pressure(grid, a, b, load)
    law = ExponentialFalling(0.55, 0.4, 0.6)
    curve = []
    for creep in (0.001, 0.004, 0.02, 0.08):
        sol = solve_steady(op, pressure, (creep + 0 * x, 0 * y), G, law, speed)
        assert sol.converged, f"falling friction at xi = {creep}: {sol.message}"
        mu_local = law.coefficient(speed * np.hypot(sol.slip_x, sol.slip_y))
        assert np.all(np.hypot(sol.traction_x, sol.traction_y) <= mu_local * pressure * (1 + 1e-8) + 1e-9), (
            f"|q| > mu(V|s|) p at xi = {creep}")
        curve.append(total_forces(grid, sol.traction_x, sol.traction_y)[0] / (0.55 * load))
    peak = int(np.argmax(curve))
    assert 0 < peak < len(curve) - 1, f"no interior peak on the creep curve {curve}"
    assert curve[-1] < 0.9 * curve[peak], f"no falling branch: {curve}"
    flat = ExponentialFalling(0.55, 1.0, 0.6)  # A = 1: mu = mu_s at every speed
    for creep in (0.002, 0.01):
        one = solve_steady(op, pressure, (creep + 0 * x, 0 * y), G, flat, speed, tolerance=1e-11)
        two = solve_steady(op, pressure, (creep + 0 * x, 0 * y), G, Coulomb(0.55), speed, tolerance=1e-11)
        np.testing.assert_allclose(one.traction_x, two.traction_x, atol=1e-8 * pressure.max(),
                                   err_msg="a law with mu = mu_s everywhere differs from Coulomb")


def test_non_convergence_is_reported_not_hidden():
    grid, op, p, x, y = setup(1.0, 16)
    s = saturation()
    sol = solve_steady(op, p, (0.5 * s + 0 * x, 1.5 * s / 6e-3 * x), G, Coulomb(MU), max_iterations=1)
    assert not sol.converged, "one Newton step from the full-stick start cannot settle a spin case"
    assert "did not converge" in sol.message and "residual" in sol.message, sol.message
    empty = solve_steady(op, 0 * p, (0 * x, 0 * y), G, Coulomb(MU))
    assert not empty.converged and "no element in contact" in empty.message, empty.message


def test_a_law_falling_faster_than_the_grid_resolves_is_reported():
    """mu(v) = 0.4 (0.7 exp(-18 v) + 0.3) at 30 m/s: an element's slip equation ``|s| + g(|s|) / r`` is not monotone
    where ``-(p / r) V dmu/dv > 1``; the solve stops on the stall and says why instead of iterating to the cap."""
    grid, op, p, x, y = setup(1.5, 40)
    law = ExponentialFalling(0.4, 0.3, 18.0)
    sol = solve_steady(op, p, (0.001 + 0 * x, 0 * y), G, law, 30.0)
    assert not sol.converged, "this law is beyond what the grid resolves, yet the solve reports convergence"
    assert "stagnates" in sol.message and "not monotone" in sol.message, sol.message
    assert sol.newton_iterations < 40, f"the stall took {sol.newton_iterations} Newton iterations to detect"


def test_the_work_cap_bounds_the_operator_applications_and_says_so():
    """A spin case needs several Newton steps: a cap of 40 applications stops it, within one GMRES iteration (an
    operator and a preconditioner application) and a step's backtracking of the cap; uncapped it converges, spending
    more."""
    grid, op, p, x, y = setup(1.0, 16)
    s = saturation()
    slip = (0.5 * s + 0 * x, 1.5 * s / 6e-3 * x)
    free = solve_steady(op, p, slip, G, Coulomb(MU))
    assert free.converged and free.applications > 40, f"uncapped: {free.applications} applications"
    capped = solve_steady(op, p, slip, G, Coulomb(MU), max_applications=40)
    assert not capped.converged and "work cap of 40 operator applications" in capped.message, capped.message
    assert capped.applications <= 40 + 2 + 7, f"{capped.applications} applications for a cap of 40"
    again = solve_steady(op, p, slip, G, Coulomb(MU), max_applications=free.applications + 50)
    assert again.converged and np.array_equal(again.traction_x, free.traction_x), \
        "a cap the solve does not reach changes nothing"


@pytest.mark.parametrize("creepage", [1e298, math.inf, math.nan])
def test_a_rigid_slip_beyond_floating_point_stops_newton_at_once(creepage):
    """A residual that is no finite number never stalls nor converges: Newton stops before its first step and says
    why (it ran to its cap of iterations, tens of seconds on a flange's grid).  The overflow's numpy warnings are the
    caller's to silence, as the stepping models do."""
    grid, op, p, x, y = setup(1.0, 16)
    with np.errstate(all="ignore"):
        sol = solve_steady(op, p, (creepage + 0 * x, 0 * y), G, ExponentialFalling(MU, 0.4, 0.6), 30.0)
    assert not sol.converged and "beyond floating point" in sol.message, sol.message
    assert sol.newton_iterations == 0, f"{sol.newton_iterations} Newton iterations"


def test_the_normal_problem_starts_from_a_given_pressure():
    """solve_normal's ``initial``: its own solution (scaled by 2, which the load's scaling undoes) converges at once to
    the same contact; a start of another shape is refused with both shapes; one without a positive value is the
    uniform start."""
    grid, op, sampled, x, y = setup(1.0, 30, margin=3)
    curvature = 1.0 / (2 * 0.46)
    gap = curvature * (x**2 + y**2)
    fresh = solve_normal(op, gap, LOAD, G)
    again = solve_normal(op, gap, LOAD, G, initial=2.0 * fresh.pressure)
    assert fresh.converged and again.converged, (fresh.message, again.message)
    assert again.iterations <= 2 < fresh.iterations, f"{again.iterations} iterations from the solution, " \
                                                     f"{fresh.iterations} fresh"
    assert np.abs(again.pressure - fresh.pressure).max() < 1e-8 * fresh.pressure.max(), "the same solution"
    with pytest.raises(ValueError, match=r"shape \(3, 3\), the grid \(36, 36\)"):
        solve_normal(op, gap, LOAD, G, initial=np.ones((3, 3)))
    zero = solve_normal(op, gap, LOAD, G, initial=np.zeros(gap.shape))
    assert zero.iterations == fresh.iterations and np.array_equal(zero.pressure, fresh.pressure), "uniform start"
