"""Velocity-dependent friction by the polynomial method (paper section 4.2; docs/physics.md, Velocity-dependent
friction)."""

import math
import warnings

import numpy as np
import pytest

import rollcontact as rc
from rollcontact.line.dispatch import METHODS
from rollcontact.line.methods.common import friction_sharpness
from rollcontact.line.methods.polynomial import slip
from rollcontact.line.methods.polynomial.accuracy import SLIP_NODE_ERROR
from rollcontact.line.methods.polynomial.slip import solve_velocity_dependent

LOAD = 1e6  # N/m
V = 20.0  # m/s
FALLING = rc.ExponentialFalling(mu_static=0.3, kinetic_ratio=0.4, decay=0.6)


def scene(creep, friction=FALLING, **kw):
    return rc.Scene(normal_load_per_length=LOAD, creep=creep, friction=friction, rolling_speed=V, **kw)


def carter_inputs():
    ref = rc.solve(scene(1e-3, rc.Coulomb(0.3)), method="closed_form")
    pol = rc.solve(scene(1e-3, rc.Coulomb(0.3)), method="polynomial")
    return ref, pol.info["pressure_coefficients"]


@pytest.mark.parametrize("creep", [2e-4, 1e-3, -1e-3, 1.4e-3, 5e-3])
def test_coulomb_law_through_the_slip_iteration_is_carter(creep):
    ref = rc.solve(scene(creep, rc.Coulomb(0.3)), method="closed_form")
    _, c_n = carter_inputs()
    out = solve_velocity_dependent(c_n, ref.contact_half_width, 0.0, rc.Material().contact_modulus,
                                   rc.Coulomb(0.3), V, creep, nodes=96)
    assert out["converged"], out["message"]
    np.testing.assert_allclose(out["tangential_force_per_length"], ref.tangential_force_per_length, rtol=1e-11,
                               atol=1e-9 * LOAD, err_msg="T' of the slip iteration with constant mu vs Carter")
    np.testing.assert_allclose(out["stick_half_width"], ref.stick_half_width, rtol=1e-10, atol=1e-14,
                               err_msg="a* vs Carter")
    x = np.linspace(-0.999, 0.999, 301) * ref.contact_half_width
    np.testing.assert_allclose(out["distributions"].traction(x), ref.traction(x), atol=1e-10 * ref.max_pressure,
                               err_msg="q(x) vs Carter")


def test_falling_friction_creep_curve_has_a_maximum_and_decays():
    creeps = np.array([2e-4, 5e-4, 1e-3, 1.5e-3, 2e-3, 3e-3, 5e-3, 1e-2, 2e-2, 5e-2])
    results = [rc.solve(scene(float(c))) for c in creeps]
    assert all(r.method == "polynomial" and r.success for r in results), [r.message for r in results]
    mu_t = np.array([r.traction_coefficient for r in results])
    i = int(np.argmax(mu_t))
    assert 0 < i < len(creeps) - 1, f"the creep curve must peak inside the sweep, T'/N' = {mu_t}"
    assert np.all(np.diff(mu_t[: i + 1]) > 0) and np.all(np.diff(mu_t[i:]) < 0), f"rise then fall: {mu_t}"
    assert mu_t.max() < FALLING.mu_static, "T' <= mu_s N'"
    # far in full slip the traction tends to mu(V xi) N' (slip nearly uniform)
    r = results[-1]
    assert abs(r.traction_coefficient - float(FALLING.coefficient(V * creeps[-1]))) < 0.02, r.traction_coefficient


def test_odd_in_creep():
    r_pos = rc.solve(scene(1e-3))
    r_neg = rc.solve(scene(-1e-3))
    np.testing.assert_allclose(r_neg.tangential_force_per_length, -r_pos.tangential_force_per_length, rtol=1e-12,
                               err_msg="T'(-xi) = -T'(xi)")


def test_traction_bounds_and_slip_direction():
    r = rc.solve(scene(1e-3))
    a = r.contact_half_width
    x = np.linspace(-0.995, 0.995, 801) * a
    q, p, s = r.traction(x), r.pressure(x), r.slip(x)
    mu = FALLING.coefficient(V * np.abs(np.nan_to_num(s)))
    assert np.all(np.abs(q) <= mu * p * (1 + 1e-3) + 1e-6 * r.max_pressure), "|q| <= mu(V|s|) p"
    slip_zone = x > r.leading_edge + 2 * r.stick_half_width + 0.02 * a
    assert np.all(s[slip_zone] > 0), "slip has the sign of the creep behind the stick zone"
    np.testing.assert_allclose(q[slip_zone], (mu * p)[slip_zone], rtol=2e-3, atol=2e-4 * r.max_pressure,
                               err_msg="q = mu(V s) p in the slip zone")


def test_spike_at_the_stick_slip_boundary():
    """Paper Figure 5: with falling friction q/p peaks at the stick/slip boundary, above its trailing values."""
    steep = rc.ExponentialFalling(mu_static=0.3, kinetic_ratio=0.4, decay=30.0)
    r = rc.solve(scene(5e-4, steep))
    assert r.success, r.message
    a = r.contact_half_width
    xb = r.leading_edge + 2 * r.stick_half_width
    x = np.linspace(r.leading_edge + 0.01 * a, r.trailing_edge - 0.01 * a, 2001)
    ratio = r.traction(x) / r.pressure(x)
    ib = int(np.argmax(ratio))
    assert abs(x[ib] - xb) < 0.05 * a, f"q/p peaks at the boundary x = {xb:.4g}, found {x[ib]:.4g}"
    assert ratio[ib] > ratio[-1] + 0.05, f"q/p falls behind the boundary: {ratio[ib]:.3f} -> {ratio[-1]:.3f}"


def test_convergence_in_nodes():
    t = [rc.solve(scene(1e-3), nodes=n).tangential_force_per_length for n in (48, 96, 192, 384)]
    d = np.abs(np.diff(t))
    assert d[-1] < 1e-4 * abs(t[-1]), f"T' converged to 1e-4 at 384 nodes: {t}"
    assert d[-1] < d[0], f"differences shrink with the number of nodes: {d}"


def test_corrugated_surface_with_falling_friction_reduces_with_flat_surface():
    flat = rc.solve(scene(1e-3))
    tiny = rc.solve(scene(1e-3, surface=rc.Surface(harmonics=(rc.Harmonic.from_wavelength(0.04, 1e-12),))))
    np.testing.assert_allclose(tiny.tangential_force_per_length, flat.tangential_force_per_length, rtol=1e-6,
                               err_msg="a vanishing corrugation leaves the falling-friction solution unchanged")


# ---------------------------------------------------------------------------------------------------------------
# the Newton solution of the discrete equations
CORRUGATION = rc.Surface(harmonics=(rc.Harmonic.from_wavelength(0.04, 20e-6, 0.7),))
LAWS = {"polach": rc.ExponentialFalling(0.3, 0.4, 0.6), "steep": rc.ExponentialFalling(0.3, 0.4, 30.0),
        "rational": rc.RationalFalling(0.3, 0.15, 0.02), "linear": rc.LinearFalling(0.3, 0.2, 2.0)}
# (a*, T') of the fixed-point implementation before the speed-up (commit 640c1e1) at nodes = 48, corrugated scene
PREVIOUS = {("polach", 3e-4): (0.001706437014525037, 102559.177461051),
            ("polach", 1e-3): (0.0007713495874827801, 256879.71063316375),
            ("steep", 3e-4): (0.0016298002713876474, 99375.2166362892),
            ("steep", 1e-3): (0.0004294222059206191, 206783.9215560846),
            ("rational", 3e-4): (0.0016304617804024277, 99561.15589750459),
            ("rational", 1e-3): (0.00046154009957652793, 215328.71401851912)}


def corrugated(creep, law):
    return scene(creep, law, surface=CORRUGATION, axis_position=0.002)


@pytest.mark.parametrize("law, creep", sorted(PREVIOUS))
def test_same_discrete_solution_as_the_previous_fixed_point(law, creep):
    """Newton solves the equations the fixed point solved (to its 1e-9 tolerance), at equal nodes."""
    r = rc.solve(corrugated(creep, LAWS[law]), method="polynomial", nodes=48)
    assert r.success, r.message
    np.testing.assert_allclose((r.stick_half_width, r.tangential_force_per_length), PREVIOUS[(law, creep)],
                               rtol=1e-8, err_msg=f"{law}, xi = {creep}: (a*, T')")


@pytest.mark.parametrize("law", sorted(LAWS))
@pytest.mark.parametrize("creep", [3e-4, 1e-3, -1.4e-3, 5e-3])
def test_returned_fields_satisfy_the_discrete_equations(law, creep):
    """At the patch nodes q1 = mu(V s) p with s and q1 read from the returned fields, and xi = -F_0(a*).

    The fields are series (q1: sine series of the nodal values, s: xi + H1 - sum F_n w^n), so this checks the
    converged state of the solver independently of how it was reached.
    """
    law_ = LAWS[law]
    r = rc.solve(corrugated(creep, law_), method="polynomial")
    assert r.success, r.message
    dist = r.distributions
    m = dist.q1_coefficients.size - 1
    t = np.cos(np.pi * (np.arange(m) + 0.5) / m)
    x = dist.offset + dist.half_width * t
    slipping = x > r.leading_edge + 2 * r.stick_half_width
    s = np.abs(r.slip(x[slipping]))
    q = np.abs(r.traction(x[slipping]))
    mu_p = law_.coefficient(V * s) * r.pressure(x[slipping])
    np.testing.assert_allclose(q, mu_p, rtol=1e-8, atol=1e-8 * r.max_pressure, err_msg="q1 = mu(V s) p at the nodes")
    if r.stick_half_width > 0:
        f0 = dist.stick_coefficients[0]
        np.testing.assert_allclose(-f0, abs(creep), rtol=1e-8, err_msg="xi = -F_0(a*)")


def test_jacobian_equals_finite_differences():
    """The analytic Jacobian of the slip equations (mu_j and a*/a) against central differences."""
    from rollcontact.line.methods.polynomial.slip import SlipEquations, slip_operators

    r = rc.solve(corrugated(1e-3, LAWS["steep"]), method="polynomial", nodes=12)
    c_n = r.info["pressure_coefficients"]
    ops = slip_operators(12)
    p = np.clip(np.sin(ops.theta[:, None] * np.arange(1, c_n.size)) @ c_n[1:], 0.0, None)
    eq = SlipEquations(ops, p, rc.Material().contact_modulus, LAWS["steep"], V, 1e-3)
    mu = np.linspace(0.3, 0.17, 12)  # a state away from the solution, with slip behind a stick zone
    eta = 0.31
    st = eq.evaluate(mu, eta)
    assert st.maps is not None and st.maps.slipping.any() and not st.maps.slipping.all()
    jac = eq.jacobian(st)

    def residual(v):
        other = eq.evaluate(v[:-1], v[-1])
        assert np.array_equal(other.maps.slipping, st.maps.slipping), "finite difference crossed a node"
        return np.append(other.r_mu, other.r_h)

    x = np.append(mu, eta)
    for j in range(x.size):
        h = 1e-7 * max(abs(x[j]), 1e-3)
        up, down = x.copy(), x.copy()
        up[j] += h
        down[j] -= h
        np.testing.assert_allclose(jac[:, j], (residual(up) - residual(down)) / (2 * h), rtol=1e-5,
                                   atol=1e-6 * np.abs(jac).max(), err_msg=f"column {j}")


def test_a_creep_reversed_by_an_external_slope_starts_sticking_throughout():
    """An external slope whose T_0 coefficient outweighs the creep (the other patches of a split contact) makes the
    patch's creep negative: the Carter start ``a*/a = 1 - xi/xi_full`` would exceed 1 (stick nodes beyond the patch,
    arccos of more than 1: NaN); the start is the whole patch sticking, every residual finite."""
    from rollcontact.line.methods.polynomial.slip import SlipEquations, slip_operators

    ops = slip_operators(12)
    p = 1e9 * np.sqrt(1.0 - (ops.t_plus_one - 1.0) ** 2)
    external = np.zeros(13)
    external[0] = -3e-3
    eq = SlipEquations(ops, p, rc.Material().contact_modulus, LAWS["steep"], V, 1e-3, external=external)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        st = eq.evaluate(np.full(12, 0.3), 0.0)
    assert st.eta == 1.0 and np.isfinite(st.s).all() and np.isfinite(st.norm), (st.eta, st.s)


@pytest.mark.parametrize("law", ["polach", "steep", "rational"])
def test_relaxed_fixed_point_reaches_the_newton_solution(law):
    """The fallback (the paper's under-relaxed fixed point) and Newton converge to the same state."""
    from rollcontact.line.methods.polynomial.slip import SlipEquations, slip_operators

    r = rc.solve(corrugated(1e-3, LAWS[law]), method="polynomial")
    c_n = r.info["pressure_coefficients"]
    ops = slip_operators(r.distributions.q1_coefficients.size - 1)  # the nodes the solver chose
    p = np.clip(np.sin(ops.theta[:, None] * np.arange(1, c_n.size)) @ c_n[1:], 0.0, None)
    eq = SlipEquations(ops, p, rc.Material().contact_modulus, LAWS[law], V, 1e-3)
    st, it = eq.relaxed_iteration(1e-10, 400, [])
    assert st.norm <= 1e-10, f"fixed point did not converge in {it} iterations"
    np.testing.assert_allclose(st.eta * r.contact_half_width, r.stick_half_width, rtol=1e-7, err_msg="a*")
    np.testing.assert_allclose(0.5 * np.pi * r.contact_half_width * (ops.dst @ st.q)[0]
                               - 0.25 * np.pi * st.eta * r.contact_half_width * rc.Material().contact_modulus
                               * st.f[1], r.tangential_force_per_length, rtol=1e-7, err_msg="T'")


@pytest.mark.parametrize("law, most", [("polach", 4), ("rational", 10), ("linear", 6), ("steep", 8)])
def test_newton_needs_few_iterations(law, most):
    """The cost claim: a handful of Newton steps (the fixed point needed 7-25 iterations with inner root searches)."""
    for creep in (3e-4, 1e-3, 1.4e-3, 5e-3):
        r = rc.solve(corrugated(creep, LAWS[law]), method="polynomial")
        steps = len(r.info["slip_iteration_history"]) - 1
        assert r.success and steps <= most, f"{law}, xi = {creep}: {steps} Newton steps ({r.message})"


def test_nodes_follow_the_pressure_order():
    """A short corrugation needs many pressure terms; the slip iteration must not alias mu(V s) p on few nodes."""
    short = rc.Surface(harmonics=(rc.Harmonic.from_wavelength(0.004, 0.5e-6, 0.3),))
    r = rc.solve(scene(1e-3, surface=short), method="polynomial")
    assert r.success, r.message
    terms = r.info["pressure_coefficients"].size - 1
    assert terms > 16, f"the test needs a pressure with more terms than the default nodes, got {terms}"
    assert r.distributions.q1_coefficients.size - 1 >= 2 * terms, "nodes below twice the pressure terms"
    assert abs(r.tangential_force_per_length) <= FALLING.mu_static * LOAD, "T' <= mu_s N'"
    more = rc.solve(scene(1e-3, surface=short), method="polynomial", nodes=4 * terms)
    np.testing.assert_allclose(r.tangential_force_per_length, more.tangential_force_per_length, rtol=2e-3)


def test_tiny_creep_converges():
    """xi = 1e-8 of saturation: the creep equation is resolved to round-off of F_0, not of xi (Newton stops)."""
    r = rc.solve(scene(1e-11), method="polynomial")
    assert r.success, r.message
    carter = rc.solve(scene(1e-11, rc.Coulomb(0.3)), method="closed_form")
    np.testing.assert_allclose(r.tangential_force_per_length, carter.tangential_force_per_length, rtol=1e-3)


# ---------------------------------------------------------------------------------------------------------------
# the a-posteriori error estimate, and the node counts auto offers (api.PolynomialAccuracy)
SATURATION = 0.3 * rc.hertz(LOAD, 0.46, rc.Material().contact_modulus)[0] / 0.46  # Carter mu a / R
TABLE = rc.TabulatedFriction((0.0, 0.05, 0.2, 1.0, 5.0), (0.3, 0.27, 0.24, 0.2, 0.18))
ESTIMATE_CASES = {  # partial slip, the error well above the 256-node reference's own (~1e-7)
    "exponential B = 3 s/m, flat": scene(0.3 * SATURATION, rc.ExponentialFalling(0.3, 0.4, 3.0)),
    "exponential B = 30 s/m, flat": scene(1e-3, LAWS["steep"]),
    "exponential B = 10 s/m, corrugated": corrugated(0.6 * SATURATION, rc.ExponentialFalling(0.3, 0.4, 10.0)),
    "table, corrugated": corrugated(0.6 * SATURATION, TABLE),
}
POLYNOMIAL = METHODS["polynomial"].accuracy


def test_error_estimate_bounds_the_error():
    """The a-posteriori estimate reported by solve bounds the T' error, typically at 2-3 times it
    (benchmarks/calibrate_slip_nodes.py: median 2.2; more where M happens to err much less than 2M, as the table law at
    16 nodes; the a-priori bound beta/N^2 is mostly 10-100 times pessimistic)."""
    ratios = []
    for name, s in ESTIMATE_CASES.items():
        reference = rc.solve(s, method="polynomial", nodes=256)
        for nodes in (16, 32):
            r = rc.solve(s, method="polynomial", nodes=nodes)
            error = abs(r.tangential_force_per_length / reference.tangential_force_per_length - 1.0)
            estimate = r.info["error_estimate"]
            assert error > 3 * reference.info["error_estimate"], f"{name}: the reference must resolve the error"
            assert error <= estimate, f"{name}, {nodes} nodes: error {error:.3g} above the estimate {estimate:.3g}"
            ratios.append(estimate / error)
    assert np.median(ratios) < 3 and max(ratios) < 20, f"estimate / error: {np.round(ratios, 2)}"


def test_error_estimate_is_returned_on_demand_and_vanishes_in_full_slip(monkeypatch):
    ref, c_n = carter_inputs()
    args = (c_n, ref.contact_half_width, 0.0, rc.Material().contact_modulus, FALLING, V)
    calls = []
    real = slip.force_error_estimate
    monkeypatch.setattr(slip, "force_error_estimate", lambda *a: calls.append(1) or real(*a))
    partial = solve_velocity_dependent(*args, 1e-3, nodes=24)
    assert not calls, "the estimate costs a Newton step: it must not run before it is read"
    estimate = partial["distributions"].force_error
    assert partial["nodes"] == 24 and estimate > 0.0 and len(calls) == 1, (estimate, calls)
    assert partial["distributions"].force_error == estimate and len(calls) == 1, "computed once, then kept"
    # full slip: q1 = mu(V s) p is smooth, the nodes resolve T' to round-off
    full = solve_velocity_dependent(*args, 3.0 * SATURATION, nodes=24)
    error = full["distributions"].force_error
    assert full["stick_half_width"] == 0.0 and error < 1e-12, error


@pytest.mark.parametrize("fraction", [0.0, 0.05, 0.5, 0.95, 1.5, -0.4])
@pytest.mark.parametrize("decay", [0.6, 30.0])
def test_creep_stiffness_is_the_slope_of_the_discrete_solution(fraction, decay):
    """dT'/dxi by the implicit function theorem against a central difference of two solves (h = 1e-6 xi_sat,
    truncation ~1e-12 relative), in partial slip, on the falling branch (B = 30 s/m at 0.95 saturation has a
    negative slope), in full slip and at zero creep (the full-stick slope, Carter's 2 N' R / a)."""
    law = rc.ExponentialFalling(0.3, 0.4, decay)
    base = scene(0.0, friction=law)
    ref, _ = carter_inputs()
    xi_sat = 0.3 * ref.contact_half_width / base.radius
    s = base.replace(creep=fraction * xi_sat)
    slope = rc.solve(s, method="polynomial").creep_stiffness_per_length
    h = 1e-6 * xi_sat
    up, down = (rc.solve(s.replace(creep=s.creep + d), method="polynomial").tangential_force_per_length
                for d in (h, -h))
    difference = (up - down) / (2.0 * h)
    assert abs(slope - difference) <= 1e-6 * abs(difference) + 1e-9 * 2.0 * ref.normal_load_per_length / xi_sat, (
        f"dT'/dxi {slope:.9e} against the difference {difference:.9e}")
    if fraction == 0.0:
        carter = 2.0 * ref.normal_load_per_length * base.radius / ref.contact_half_width
        assert slope == pytest.approx(carter, rel=1e-9), "zero creep: Carter's full-stick slope"


def test_ladder_offers_each_node_count_that_runs_once():
    """Requests below the floor (default_nodes, two nodes per pressure term) run the floor: the ladder, the cost
    and the bound use the count that runs, each once."""
    short = scene(1e-3, surface=rc.Surface(harmonics=(rc.Harmonic.from_wavelength(0.004, 0.5e-6, 0.3),)))
    terms = rc.solve(short).info["pressure_coefficients"].size - 1
    for s, floor in ((ESTIMATE_CASES["exponential B = 3 s/m, flat"], 16),
                     (ESTIMATE_CASES["exponential B = 30 s/m, flat"], 32), (short, 2 * terms)):
        nodes = [options["nodes"] for options in POLYNOMIAL.ladder(s)]
        assert nodes[0] == floor and nodes == sorted(set(nodes)), nodes
        assert rc.solve(s, method="polynomial", nodes=8).distributions.nodes == floor
        assert rc.solve(s, method="polynomial", **POLYNOMIAL.ladder(s)[1]).distributions.nodes == nodes[1]
        assert POLYNOMIAL.cost(s, {"nodes": 8}) == POLYNOMIAL.cost(s, {"nodes": floor})
        assert POLYNOMIAL.error(s, {"nodes": 8}) == POLYNOMIAL.error(s, {"nodes": floor})


def test_escalation_moves_up_until_the_estimate_meets_the_tolerance():
    s = ESTIMATE_CASES["exponential B = 3 s/m, flat"]
    tolerance = 5e-6
    reference = rc.solve(s, method="polynomial", nodes=256)
    options, runs = {"nodes": 16}, []
    while options is not None:
        r = rc.solve(s, method="polynomial", **options)
        runs.append(r.distributions.nodes)
        options = POLYNOMIAL.escalation(s, options, r.info["error_estimate"], tolerance)
    assert runs == [16, 64], f"one step to the count the estimate's N^-1.5 decay predicts: {runs}"
    assert abs(r.tangential_force_per_length / reference.tangential_force_per_length - 1) <= r.info[
        "error_estimate"] <= tolerance
    largest = POLYNOMIAL.ladder(s)[-1]
    assert POLYNOMIAL.escalation(s, largest, 1.0, tolerance) is None, "nothing above the largest count"
    assert POLYNOMIAL.escalation(s, {"nodes": 16}, math.nan, tolerance) is None
    assert POLYNOMIAL.escalation(s, {"nodes": 16}, 1.0, tolerance) == largest


def test_auto_starts_at_the_floor_where_the_estimate_meets_the_tolerance():
    """B = 30 s/m at 1e-4: 32 nodes (the floor) meet it by the estimate, where the bound beta/N^2 wanted 128."""
    s = ESTIMATE_CASES["exponential B = 30 s/m, flat"]
    r = rc.solve(s, tolerance=1e-4)
    assert r.distributions.nodes == 32 and r.info["tolerance_met"], (r.info["setting"], r.info["error_estimate"])
    assert r.info["error_estimate"] == r.distributions.force_error


def test_auto_certifies_by_the_bound_where_it_meets_the_tolerance(monkeypatch):
    """Where the a-priori bound SLIP_NODE_ERROR beta/N^2 of the nodes that ran meets t, auto reports it and skips
    the a-posteriori estimate (a Newton step's cost); where it does not, the estimate decides (as above)."""
    s = ESTIMATE_CASES["exponential B = 3 s/m, flat"]
    reference = rc.solve(s, method="polynomial", nodes=256)
    calls = []
    real = slip.force_error_estimate
    monkeypatch.setattr(slip, "force_error_estimate", lambda *a: calls.append(1) or real(*a))
    r = rc.solve(s, tolerance=1e-3)
    bound = SLIP_NODE_ERROR * friction_sharpness(s) / r.distributions.nodes**2
    assert r.info["tolerance_met"] and not calls, f"the bound {bound:.3g} meets 1e-3: no estimate ({r.info})"
    assert r.info["error_estimate"] == pytest.approx(bound, rel=1e-12), (r.info["error_estimate"], bound)
    error = abs(r.tangential_force_per_length / reference.tangential_force_per_length - 1.0)
    assert error <= r.distributions.force_error <= bound <= 1e-3, (error, r.distributions.force_error, bound)
    tight = rc.solve(s, tolerance=0.5 * bound)
    assert tight.distributions.nodes == r.distributions.nodes and tight.info["tolerance_met"], tight.info
    assert tight.info["error_estimate"] == tight.distributions.force_error, "below the bound the estimate decides"


def test_a_slip_iteration_without_traction_has_no_estimate_rather_than_an_error():
    """Regression (bench_multipatch table C): on a 4 mm / 40 um corrugation the single-patch normal problem lands
    on a spurious patch with p <= 0 at every slip node, so q1 = 0 and the estimate's ratio T'_K / T'_M was 0/0,
    raised as ZeroDivisionError out of solve().  Now NaN; the method finds the two patches instead
    (tests/test_split_friction.py) and auto answers with them."""
    from rollcontact.line.methods.polynomial.solver import solve_polynomial

    scene = rc.Scene(1e6, creep=1.4786792607177798e-4, axis_position=0.0004 / 1.2, rolling_speed=20.0,
                     friction=rc.ExponentialFalling(0.3, 0.4, 3.0),
                     surface=rc.Surface(harmonics=(rc.Harmonic.from_wavelength(0.004, 40e-6),)))
    single = solve_polynomial(scene, check=False)  # the spurious patch, unchecked
    assert math.isnan(single.distributions.force_error), single.distributions.force_error
    auto = rc.solve(scene, tolerance=1e-2)
    assert auto.success and auto.method == "polynomial" and len(auto.info["patches"]) == 2, auto.message
    assert math.isfinite(auto.tangential_force_per_length) and auto.info["error_estimate"] <= 1e-2
