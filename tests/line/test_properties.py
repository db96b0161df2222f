"""Numerical stability at the extremes (issue 7): property-based tests (hypothesis) over the valid domain.

Domain
------
Drawn log-uniformly unless said otherwise:

* load per length N' from 1e-6 to 1e3 times the nominal ``NOMINAL_LOAD`` = 1e6 N/m (100 kN on a 0.1 m wide line
  contact), i.e. 1 to 1e9 N/m;
* Young's modulus E from 1e6 to 1e12 Pa (Poisson's ratio uniform in [0, 0.49]); radius R from 1e-3 to 1e2 m;
* friction mu (mu_s for falling laws) from 1e-6 to 2; rolling speed V from 1e-6 to 1e3 m/s;
* creep |xi| from 1e-12 to 100 times the Carter saturation creep ``mu a / R``, both signs, plus a band of
  +-1e-3 around saturation so that the switch to full slip is hit;
* corrugation: k a from 1e-3 to 1e3, amplitude from 1e-9 to 4 times the amplitude ``A_split`` at which the contact
  splits (``A_split = max(1, k a / 2) / (R k^2)``: for long waves the surface curvature k^2 A reaches the wheel's
  1/R, for short waves the pressure ripple E* k A reaches the Hertz p0 = E* a / (2R)), any phase and axis position;
* polynomial order 1 to 200.

Properties
----------
Closed forms (``hertz``, ``carter``, ``solve(method="closed_form")``):
    finite; load balance; T' = sign(xi) mu N' u (2 - u), u = R |xi| / (mu a), against a 40-digit decimal evaluation
    of the same formula (this is what finds cancellation at small creep); |T'| <= mu N'; T' has the sign of xi and
    is odd in xi; exact saturation for |xi| >= mu a / R and quadratic approach to it (the curve is continuous
    with zero slope there); monotone non-decreasing and Lipschitz with the initial slope pi E* a / 2 (so
    continuous everywhere); stick width in [0, a]; the scaling identity ``T'/(mu N') = f(xi R / (mu a))``;
    distributions with p >= 0, |q| <= mu p, q of the sign of xi, integrals N' and T'.
Polynomial method:
    on a flat (possibly tilted) surface it is Carter at every order 1..200; on corrugation it returns either
    ``success`` with finite outputs, load balance, p >= 0, |q| <= mu p and no dissipation of the wrong sign
    (xi T' >= 0: the slip power ``V int q s dx`` equals ``V xi T'`` and q s >= 0 pointwise), or ``success False``
    with a message naming the fallback; with Coulomb friction the creep curve is monotone and a result without
    stick zone has T' = mu N' sign(xi) exactly; the Carter limit for tiny amplitudes.
Velocity-dependent friction (exponential, rational, linear falling laws):
    |T'| <= mu_s N', xi T' >= 0; when mu varies by less than 1e-10 over the slip velocities that occur, the
    answer is Carter's.
``auto``, ``discretised`` (a handful of examples at small n), :class:`ContactModel`:
    valid outputs (``extremes.check_outputs`` for the model) or a clear error (``success False`` with a message,
    ``SceneError``/``ValueError``/``ModelError`` naming the value); never another exception; a refused step
    leaves the model's state unchanged.
Invalid values:
    every scene, material, friction and solver value out of its range raises an error naming the field and value.
Fixed bugs keep their reproducers as explicit ``@example`` s: Carter's force cancelling at small creep, Carter
    distributions beyond mu p at the edges, the discretised a* > a, the polynomial method's relative accuracy of
    T' at small creep (it now solves for the slip width) and its translation invariance (axis coordinates).

Tolerances
----------
The tiers of ``extremes.py``: ``ULP`` (4 eps) for bounds and symmetries, ``ROUND_OFF`` (1e-14) for closed forms
against the 40-digit reference, ``CONVERGED`` (1e-12) for the polynomial method where it is exact, ``SOLVER``
(1e-9) after iterations and checks with a 1e-9 tolerance; each assertion names its scale.

Budgets: the profile ``"rollcontact-properties"`` (``extremes.py``) is derandomised, so CI runs the same examples
every time, and every test has a small ``max_examples``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from decimal import Decimal, localcontext

import numpy as np
import pytest
from extremes import (
    CONVERGED,
    ELEMENTS,
    EPS,
    NOMINAL_LOAD,
    PROFILE,
    ROUND_OFF,
    SOLVER,
    ULP,
    check_outputs,
    log_uniform,
    model_inputs,
    model_parameters,
    signs,
)
from hypothesis import event, example, given, settings
from hypothesis import strategies as st

from rollcontact import (
    METHODS,
    Coulomb,
    ExponentialFalling,
    Harmonic,
    LinearFalling,
    Material,
    RationalFalling,
    Scene,
    SceneError,
    Surface,
    carter,
    hertz,
    solve,
)
from rollcontact.stepping import ContactModel, ContactParameters, ModelError

PI = Decimal("3.14159265358979323846264338327950288419716939937510")


# ---------------------------------------------------------------------------------------------------------------
# strategies
@dataclass(frozen=True)
class Contact:
    """Load, material, radius and friction of one draw; derived Hertz/Carter scales."""

    load: float
    youngs_modulus: float
    poisson_ratio: float
    radius: float
    mu: float

    @property
    def material(self) -> Material:
        return Material(self.youngs_modulus, self.poisson_ratio)

    @property
    def estar(self) -> float:
        return self.material.contact_modulus

    @property
    def half_width(self) -> float:
        return hertz(self.load, self.radius, self.estar)[0]

    @property
    def saturation(self) -> float:
        """Carter's saturation creep mu a / R."""
        return self.mu * self.half_width / self.radius

    @property
    def initial_slope(self) -> float:
        """dT'/dxi at xi = 0: pi E* a / 2 [N/m]."""
        return 0.5 * math.pi * self.estar * self.half_width

    def scene(self, creep: float = 0.0, **changes) -> Scene:
        return Scene(self.load, creep=creep, radius=self.radius, material=self.material,
                     friction=changes.pop("friction", self.mu), **changes)


contacts = st.builds(Contact, load=log_uniform(1e-6 * NOMINAL_LOAD, 1e3 * NOMINAL_LOAD),
                     youngs_modulus=log_uniform(1e6, 1e12), poisson_ratio=st.floats(0.0, 0.49),
                     radius=log_uniform(1e-3, 1e2), mu=log_uniform(1e-6, 2.0))


def creeps(saturation: float):
    """|xi| from 1e-12 to 100 saturation creeps, or within 1e-3 of saturation; both signs."""
    top = max(math.log10(100.0 * saturation), -11.0)
    anywhere = st.floats(-12.0, top).map(lambda e: 10.0**e)
    near = st.floats(-1e-3, 1e-3).map(lambda d: saturation * (1.0 + d))
    return st.tuples(signs, st.one_of(anywhere, near)).map(lambda t: t[0] * t[1])


@st.composite
def contact_and_creep(draw):
    contact = draw(contacts)
    return contact, draw(creeps(contact.saturation))


@st.composite
def corrugations(draw, contact: Contact, largest: float = 4.0):
    """A harmonic with k a in [1e-3, 1e3] and amplitude up to ``largest`` times A_split; (harmonic, A/A_split)."""
    a = contact.half_width
    k = draw(log_uniform(1e-3, 1e3)) / a
    split = max(1.0, 0.5 * k * a) / (contact.radius * k * k)
    ratio = draw(log_uniform(1e-9, largest))
    phase = draw(st.floats(0.0, 2.0 * math.pi))
    return Harmonic.from_wavelength(2.0 * math.pi / k, ratio * split, phase), ratio


law_shapes = st.tuples(st.sampled_from(("exponential", "rational", "linear")), log_uniform(1e-3, 0.999),
                       log_uniform(1e-3, 1e3))
"""(kind, mu_k/mu_s, scale) of a falling law: it falls by 0.1 % to 99.9 %, scale in s/m or m/s."""


def falling_law(mu: float, shape):
    """The exponential, rational or linear falling law of ``shape`` (:data:`law_shapes`) with mu(0) = mu."""
    kind, fraction, scale = shape
    if kind == "exponential":
        return ExponentialFalling(mu, fraction, scale)
    if kind == "rational":
        return RationalFalling(mu, mu * fraction, scale)
    return LinearFalling(mu, mu * fraction, mu * scale)


# ---------------------------------------------------------------------------------------------------------------
# helpers
def carter_reference(contact: Contact, creep: float) -> tuple[float, float]:
    """(T'/(sign(xi) mu N'), a*/a) of Carter's formulas in 40-digit decimal arithmetic from the same floats."""
    with localcontext() as ctx:
        ctx.prec = 40
        load, radius, estar = Decimal(contact.load), Decimal(contact.radius), Decimal(contact.estar)
        a = (4 * load * radius / (PI * estar)).sqrt()
        u = radius * abs(Decimal(creep)) / (Decimal(contact.mu) * a)
        if u >= 1:
            return 1.0, 0.0
        return float(u * (2 - u)), float(1 - u)


def patch_nodes(result, m: int):
    """Midpoint nodes x_j = offset + a cos(theta_j) and weights with ``sum w f(x_j) = int f dx`` over the patch.

    Exact for ``f = sum_{n < 2m - 1} c_n sin(n theta)`` (Hertz and polynomial pressures): the integrand in theta,
    ``f a sin(theta)``, is then a cosine series of degree below 2m.
    """
    theta = math.pi * (np.arange(m) + 0.5) / m
    if "stick_zones" in result.info:  # several patches (rollcontact.multipatch): the rule on each
        halves = [(0.5 * (lo + hi), 0.5 * (hi - lo)) for lo, hi in result.info["patches"]]
        return (np.concatenate([c + h * np.cos(theta) for c, h in halves]),
                np.concatenate([h * math.pi / m * np.sin(theta) for _, h in halves]))
    a = result.contact_half_width
    return result.contact_offset + a * np.cos(theta), a * math.pi / m * np.sin(theta)


def mapped_gauss(f, breakpoints, nodes: int = 64) -> float:
    """``int f dx`` over consecutive pieces with square-root ends, vectorised (``quadrature.edge_quad``'s map).

    ``x = l + (r - l)(1 - cos theta)/2`` makes sqrt end behaviour smooth in theta; Gauss-Legendre in theta then
    converges geometrically (64 nodes: Carter's T' to 1e-10 mu N', the rest is eps |Delta| / a of the nodes).
    """
    t, w = np.polynomial.legendre.leggauss(nodes)
    theta = 0.5 * math.pi * (t + 1.0)
    total = 0.0
    for lo, hi in zip(breakpoints[:-1], breakpoints[1:], strict=True):
        if hi > lo:
            half = 0.5 * (hi - lo)
            total += 0.5 * math.pi * half * float(w @ (f(lo + half * (1.0 - np.cos(theta))) * np.sin(theta)))
    return total


def assert_finite(result, what: str):
    values = {name: getattr(result, name) for name in ("tangential_force_per_length", "contact_half_width",
                                                         "contact_offset", "stick_half_width", "max_pressure")}
    bad = {k: v for k, v in values.items() if not math.isfinite(v)}
    assert not bad, f"{what}: success with non-finite outputs {bad} ({result.message})"


def assert_fields_admissible(result, mu: float, m: int, what: str):
    """p >= 0 and |q| <= mu p at patch nodes, relative to mu p0 (SOLVER: the methods' own check tolerance)."""
    x, _ = patch_nodes(result, m)
    fraction = 0.5 + 0.5 * np.cos(math.pi * (np.arange(m) + 0.5) / m)
    zones = result.info.get("stick_zones", [(result.leading_edge, result.leading_edge + 2 * result.stick_half_width)])
    x = np.concatenate([x] + [lo + (hi - lo) * fraction for lo, hi in zones])
    p, q = result.pressure(x), result.traction(x)
    p0 = result.max_pressure
    assert np.all(np.isfinite(p)) and np.all(np.isfinite(q)), f"{what}: non-finite p or q"
    assert float(np.min(p)) >= -SOLVER * p0, f"{what}: p < 0 (min p / p0 = {float(np.min(p)) / p0:.3g})"
    excess = float(np.max(np.abs(q) - mu * p)) / (mu * p0)
    assert excess <= SOLVER, f"{what}: |q| exceeds mu p by {excess:.3g} mu p0"


def assert_clear_failure(result, what: str):
    """success False with a message; the polynomial method's also names its fallback (documented behaviour)."""
    assert result.success is False and isinstance(result.message, str) and result.message.strip(), \
        f"{what}: an unsuccessful result needs a message, got {result.message!r}"
    if result.method == "polynomial":
        assert "discretised" in result.message, f"{what}: the message should name the fallback: {result.message!r}"


# ---------------------------------------------------------------------------------------------------------------
# closed forms
@settings(PROFILE, max_examples=150)
@given(contacts)
def test_hertz_is_finite_and_carries_the_load(contact):
    a, p0 = hertz(contact.load, contact.radius, contact.estar)
    assert math.isfinite(a) and math.isfinite(p0) and a > 0.0 and p0 > 0.0, f"a = {a}, p0 = {p0}"
    assert abs(0.5 * math.pi * a * p0 / contact.load - 1.0) <= ROUND_OFF, "N' = pi a p0 / 2"
    assert abs(0.25 * math.pi * contact.estar * a * a / (contact.load * contact.radius) - 1.0) <= ROUND_OFF, \
        "a^2 = 4 N' R / (pi E*)"


@settings(PROFILE, max_examples=300)
@given(contact_and_creep())
@example((Contact(1e9, 1e6, 0.3, 1e-3, 2.0), 1e-12))  # a/R ~ 1e3: 1 - (a*/a)^2 made T' 1.4 % too large
def test_carter_creep_curve(case):
    contact, creep = case
    t, a_star, stiffness = carter(contact.load, creep, contact.radius, contact.estar, contact.mu)
    a, mu_n = contact.half_width, contact.mu * contact.load
    assert all(map(math.isfinite, (t, a_star, stiffness))), f"non-finite Carter output {(t, a_star, stiffness)}"
    assert abs(t) <= mu_n * (1.0 + ULP), f"|T'| = {abs(t)!r} > mu N' = {mu_n!r}"
    assert t != 0.0 and math.copysign(1.0, t) == math.copysign(1.0, creep), f"T' = {t!r} for xi = {creep!r}"
    assert carter(contact.load, -creep, contact.radius, contact.estar, contact.mu) == (-t, a_star, stiffness), \
        "odd in xi: T'(-xi) = -T'(xi), same a* and stiffness"
    assert 0.0 <= a_star <= a, f"a* = {a_star!r} outside [0, a = {a!r}]"
    assert 0.0 <= stiffness <= contact.initial_slope * (1.0 + ROUND_OFF), "0 <= dT'/dxi <= pi E* a / 2"
    ratio, stick = carter_reference(contact, creep)
    assert abs(abs(t) / mu_n - ratio) <= ROUND_OFF * ratio, \
        f"T'/(mu N') = {abs(t) / mu_n!r}, 40-digit reference {ratio!r} (relative accuracy at every creep)"
    assert abs(a_star / a - stick) <= ROUND_OFF, f"a*/a = {a_star / a!r}, reference {stick!r}"
    assert abs(stiffness / contact.initial_slope - stick) <= ROUND_OFF, "dT'/dxi = (pi E* a / 2) a*/a"


@settings(PROFILE, max_examples=150)
@given(contacts, signs, st.one_of(st.just(0.0), log_uniform(1e-12, 1e3)), log_uniform(1e-12, 0.5))
def test_carter_saturates_exactly_and_continuously(contact, sign, excess, below):
    def force(creep):
        return carter(contact.load, creep, contact.radius, contact.estar, contact.mu)

    mu_n = contact.mu * contact.load
    t, a_star, stiffness = force(sign * contact.saturation * (1.0 + excess))
    assert abs(t - sign * mu_n) <= ULP * mu_n, f"full slip: T' = {t!r}, mu N' = {mu_n!r}"
    assert a_star <= ULP * contact.half_width and stiffness <= ULP * contact.initial_slope, \
        f"full slip: a* = {a_star!r} (a = {contact.half_width!r}), dT'/dxi = {stiffness!r}"
    # below saturation by the fraction `below`: mu N' - |T'| = mu N' below^2 (zero slope at saturation)
    t, _, _ = force(sign * contact.saturation * (1.0 - below))
    gap = (mu_n - abs(t)) / mu_n
    assert abs(gap - below**2) <= 16.0 * EPS * (below + 1.0), f"1 - |T'|/(mu N') = {gap!r}, expected {below**2!r}"


@settings(PROFILE, max_examples=200)
@given(contact_and_creep(), signs, st.floats(-16.0, 1.0))
def test_carter_is_monotone_and_lipschitz(case, sign, log_step):
    contact, xi1 = case
    xi2 = xi1 + sign * contact.saturation * 10.0**log_step
    t1, t2 = (carter(contact.load, xi, contact.radius, contact.estar, contact.mu)[0] for xi in (xi1, xi2))
    mu_n = contact.mu * contact.load
    lo, hi = (t1, t2) if xi1 <= xi2 else (t2, t1)
    assert lo <= hi + ULP * mu_n, f"not monotone: T'({min(xi1, xi2)!r}) = {lo!r} > T'({max(xi1, xi2)!r}) = {hi!r}"
    bound = contact.initial_slope * abs(xi2 - xi1) * (1.0 + ROUND_OFF) + ULP * mu_n
    assert abs(t2 - t1) <= bound, f"|dT'| = {abs(t2 - t1)!r} exceeds (pi E* a / 2)|dxi| = {bound!r}"


@settings(PROFILE, max_examples=150)
@given(contacts, contacts, log_uniform(1e-12, 1e2))
def test_carter_scaling_identity(first, second, u):
    """T'/(mu N'), a*/a and (dT'/dxi)/(pi E* a / 2) depend on xi R / (mu a) only."""
    out = []
    for c in (first, second):
        t, a_star, stiffness = carter(c.load, u * c.saturation, c.radius, c.estar, c.mu)
        out.append((t / (c.mu * c.load), a_star / c.half_width, stiffness / c.initial_slope))
    (t1, s1, k1), (t2, s2, k2) = out
    assert abs(t1 - t2) <= ROUND_OFF * max(t1, t2), f"T'/(mu N') = {t1!r} vs {t2!r} at u = {u!r}"
    assert abs(s1 - s2) <= ROUND_OFF and abs(k1 - k2) <= ROUND_OFF, f"a*/a {s1!r} vs {s2!r}, stiffness {k1!r} vs {k2!r}"


@settings(PROFILE, max_examples=100)
@given(contact_and_creep(), st.floats(-0.1, 0.1))
def test_solve_closed_form_result_and_distributions(case, tilt):
    contact, creep = case
    result = solve(contact.scene(creep, surface=Surface(polynomial=(0.0, tilt))), method="closed_form")
    t, a_star, stiffness = carter(contact.load, creep, contact.radius, contact.estar, contact.mu)
    a, p0 = hertz(contact.load, contact.radius, contact.estar)
    assert result.success, result.message
    assert (result.tangential_force_per_length, result.stick_half_width, result.creep_stiffness_per_length,
            result.contact_half_width, result.max_pressure) == (t, a_star, stiffness, a, p0), "solve = carter/hertz"
    assert result.contact_offset == contact.radius * tilt, "a tilt alpha moves the patch uphill by R alpha"
    assert ("full slip" in result.message) == (a_star == 0.0), f"message {result.message!r} with a* = {a_star!r}"
    assert_fields_admissible(result, contact.mu, 64, "closed form")
    # the nodes are absolute positions: they carry eps |Delta| of rounding, eps |Delta| / a relative to the patch
    x, w = patch_nodes(result, 64)
    load_error = abs(float(w @ result.pressure(x)) / contact.load - 1.0)
    assert load_error <= ROUND_OFF * (1.0 + abs(result.contact_offset) / a), f"int p dx / N' - 1 = {load_error:.3g}"
    q_sign = math.copysign(1.0, creep) * result.traction(x)
    assert float(np.min(q_sign)) >= -ULP * contact.mu * p0, "q has the sign of xi"
    force = mapped_gauss(result.traction, (result.leading_edge, result.leading_edge + 2.0 * a_star,
                                           result.trailing_edge))
    assert abs(force - t) <= SOLVER * contact.mu * contact.load, f"int q dx = {force!r}, T' = {t!r}"


# ---------------------------------------------------------------------------------------------------------------
# polynomial method
def check_polynomial(result, contact: Contact, what: str, mu: float | None = None):
    """Success: finite, |T'| <= mu N', xi T' >= 0, a* in [0, a], load balance, p >= 0, |q| <= mu p."""
    mu = contact.mu if mu is None else mu
    assert_finite(result, what)
    mu_n = mu * contact.load
    t, creep = result.tangential_force_per_length, result.creep
    assert abs(t) <= mu_n * (1.0 + SOLVER), f"{what}: |T'|/(mu N') = {abs(t) / mu_n!r} > 1"
    slip_power = t * math.copysign(1.0, creep) if creep else -abs(t)
    assert slip_power >= -SOLVER * mu_n, f"{what}: T' = {t!r} against xi = {creep!r}: negative slip power V xi T'"
    a = result.contact_half_width
    assert a > 0.0 and 0.0 <= result.stick_half_width <= a * (1.0 + CONVERGED), \
        f"{what}: a = {a!r}, a* = {result.stick_half_width!r}"
    order = result.info.get("order", 1)
    x, w = patch_nodes(result, 2 * order + 8)
    load = float(w @ result.pressure(x))
    assert abs(load / contact.load - 1.0) <= SOLVER, f"{what}: int p dx / N' - 1 = {load / contact.load - 1.0:.3g}"
    assert_fields_admissible(result, mu, 2 * order + 8, what)


@settings(PROFILE, max_examples=60)
@given(contact_and_creep(), st.integers(1, 200), st.floats(-0.1, 0.1))
def test_polynomial_is_carter_on_flat_surfaces_at_every_order(case, order, tilt):
    contact, creep = case
    scene = contact.scene(creep, surface=Surface(polynomial=(0.0, tilt)))
    result = solve(scene, method="polynomial", order=order)
    reference = solve(scene, method="closed_form")
    assert result.success, result.message
    check_polynomial(result, contact, f"flat, order {order}")
    a, mu_n = reference.contact_half_width, contact.mu * contact.load
    # positions are absolute coordinates (X0 = x_c + R alpha), so a* and T' carry eps |Delta| / a of rounding
    # (see test_polynomial_is_translation_invariant): allowed here as 8 eps |Delta| / a
    shift = 8.0 * EPS * abs(reference.contact_offset) / a
    dt = abs(result.tangential_force_per_length - reference.tangential_force_per_length) / mu_n
    assert dt <= CONVERGED + shift, f"|T' - T'_Carter| / (mu N') = {dt:.3g}"
    assert abs(result.contact_half_width / a - 1.0) <= CONVERGED, "a = Hertz"
    assert abs(result.contact_offset - reference.contact_offset) <= CONVERGED * max(a, abs(reference.contact_offset))
    ds = abs(result.stick_half_width - reference.stick_half_width) / a
    assert ds <= CONVERGED + shift, f"|a* - a*_Carter| / a = {ds:.3g}"
    assert abs(result.max_pressure / reference.max_pressure - 1.0) <= CONVERGED, "p0 = Hertz"
    dk = abs(result.creep_stiffness_per_length - reference.creep_stiffness_per_length) / contact.initial_slope
    assert dk <= CONVERGED + shift, f"creep stiffness off Carter by {dk:.3g} of pi E* a / 2"


@settings(PROFILE, max_examples=20)
@given(contacts, st.integers(1, 7), signs)
@example(Contact(1e6, 210e9, 0.28, 0.46, 0.3), 6, 1.0)  # xi = saturation / 4: "no stick zone satisfies ..."
def test_polynomial_finds_stick_zones_on_its_scan_grid(contact, i, sign):
    """Regression: a* = a i/8 falls on the scan grid of solve_tangential, where a root used to be missed."""
    creep = sign * contact.saturation * (1.0 - i / 8.0)
    result = solve(contact.scene(creep), method="polynomial")
    assert result.success, result.message
    stick = result.stick_half_width / contact.half_width
    assert abs(stick - i / 8.0) <= SOLVER, f"a*/a = {stick!r}, Carter {i / 8.0}"


@settings(PROFILE, max_examples=40)
@given(contacts, signs, st.floats(-16.0, -3.0), st.booleans())
@example(Contact(1e9, 1e6, 0.3, 1e-3, 2.0), 1.0, -15.5, False)  # was 10-25 % off, wrong sign at smaller creep
@example(Contact(1e6, 210e9, 0.28, 0.46, 0.3), 1.0, -9.0, False)  # reference contact, xi = 1.5e-12: was ~1e-7 off
@example(Contact(1e9, 1e6, 0.3, 1e-3, 2.0), 1.0, -15.8, True)  # was 13 % off through the slip iteration
def test_polynomial_small_creep_is_relatively_accurate(contact, sign, log_u, falling):
    """In the linear range the answer is (pi E* a / 2) xi: T' must keep its relative accuracy and sign.

    Regression: T' = mu N' + (pi a*/2) d_1 and a root on a* with an absolute tolerance lost it (the polynomial
    method now solves for the slip width a - a* and takes xi and T' from their zeros at a* = a).

    ``falling``: an exponential law whose mu drops by at most 1e-12 of mu_s over the slip velocities that occur,
    which moves T' by at most 1e-12 of itself (the slip zone carries the force difference); the polynomial method
    then solves the Coulomb problem with mu_s (its documented reduction) instead of the slip iteration of
    section 4.2.
    """
    creep = sign * contact.saturation * 10.0**log_u
    friction = contact.mu
    if falling:
        friction = ExponentialFalling(contact.mu, 0.5, 2e-12 / (abs(creep) + 2.0 * contact.saturation))
    scene = contact.scene(creep, friction=friction)
    result = solve(scene, method="polynomial")
    t_ref = solve(scene.replace(friction=contact.mu), method="closed_form").tangential_force_per_length
    assert result.success, result.message
    assert abs(result.tangential_force_per_length / t_ref - 1.0) <= SOLVER, \
        f"T' = {result.tangential_force_per_length!r}, Carter {t_ref!r} at xi / saturation = {10.0**log_u:.3g}"


@settings(PROFILE, max_examples=30)
@given(contact_and_creep(), st.floats(-1e3, 1e3))
@example((Contact(1.0, 1e12, 0.3, 1e-3, 0.3), 1e-14), 1e3)  # a = 48 nm, 1 km along: was 1e-9..1e-6 mu N' off
def test_polynomial_is_translation_invariant(case, axis_position):
    """Regression: the polynomial method worked in surface coordinates, where every X - x_c loses eps |x_c|; it
    now works relative to the axis."""
    contact, creep = case
    here = solve(contact.scene(creep), method="polynomial")
    there = solve(contact.scene(creep, axis_position=axis_position), method="polynomial")
    assert here.success and there.success, (here.message, there.message)
    dt = abs(here.tangential_force_per_length - there.tangential_force_per_length) / (contact.mu * contact.load)
    assert dt <= 1e-12, f"moving the axis by {axis_position!r} m changes T' by {dt:.3g} mu N'"


@settings(PROFILE, max_examples=120)
@given(st.data(), contact_and_creep(), st.integers(1, 200), st.floats(-1.0, 1.0))
def test_polynomial_on_corrugation_succeeds_or_says_why(data, case, order, axis_fraction):
    contact, creep = case
    harmonic, ratio = data.draw(corrugations(contact))
    scene = contact.scene(creep, surface=Surface(harmonics=(harmonic,)),
                          axis_position=axis_fraction * 2.0 * math.pi / harmonic.wavenumber)
    result = solve(scene, method="polynomial", order=order)
    event(f"polynomial success={result.success}, amplitude {'<' if ratio < 1 else '>='} A_split")
    if result.success:
        check_polynomial(result, contact, f"corrugated, order {order}, A/A_split = {ratio:.3g}")
    else:
        assert_clear_failure(result, "corrugated polynomial")


@settings(PROFILE, max_examples=60)
@given(st.data(), contacts, st.floats(-1.0, 1.0))
@pytest.mark.slow
def test_polynomial_creep_curve_on_corrugation_is_monotone(data, contact, axis_fraction):
    """Coulomb friction: more creep never gives less force, and no stick zone means T' = mu N' sign(xi) exactly
    (a falling law's creep curve has a maximum, so this is for Coulomb only)."""
    harmonic, ratio = data.draw(corrugations(contact))
    xi1, xi2 = sorted(data.draw(st.lists(creeps(contact.saturation), min_size=2, max_size=2)))
    scenes = [contact.scene(xi, surface=Surface(harmonics=(harmonic,)),
                            axis_position=axis_fraction * 2.0 * math.pi / harmonic.wavenumber) for xi in (xi1, xi2)]
    results = [solve(scene, method="polynomial") for scene in scenes]
    event(f"monotone: both solved = {all(r.success for r in results)}")
    mu_n = contact.mu * contact.load
    for r in results:
        if r.success and r.stick_half_width == 0.0:
            assert abs(abs(r.tangential_force_per_length) - mu_n) <= ULP * mu_n, "full slip: |T'| = mu N'"
    if all(r.success for r in results):
        t1, t2 = (r.tangential_force_per_length for r in results)
        assert t1 <= t2 + SOLVER * mu_n, \
            f"T'({xi1!r}) = {t1!r} > T'({xi2!r}) = {t2!r} (A/A_split = {ratio:.3g}, k = {harmonic.wavenumber!r})"


@settings(PROFILE, max_examples=60)
@given(st.data(), contact_and_creep())
def test_polynomial_tends_to_carter_for_tiny_corrugation(data, case):
    """First order in the amplitude: by eq 28, a^2 changes by 2 J1(k a) A/A_split <= 1.2 A/A_split (factor 8)."""
    contact, creep = case
    harmonic, ratio = data.draw(corrugations(contact, largest=1e-7))
    result = solve(contact.scene(creep, surface=Surface(harmonics=(harmonic,))), method="polynomial")
    assert result.success, result.message
    check_polynomial(result, contact, f"tiny corrugation A/A_split = {ratio:.3g}")
    t_ref, _, _ = carter(contact.load, creep, contact.radius, contact.estar, contact.mu)
    dt = abs(result.tangential_force_per_length - t_ref) / (contact.mu * contact.load)
    assert dt <= 8.0 * ratio + 1e-10, f"|T' - T'_Carter| / (mu N') = {dt:.3g} at A/A_split = {ratio:.3g}"
    da = abs(result.contact_half_width / contact.half_width - 1.0)
    assert da <= 8.0 * ratio + CONVERGED, f"a / a_Hertz - 1 = {da:.3g} at A/A_split = {ratio:.3g}"


# ---------------------------------------------------------------------------------------------------------------
# velocity-dependent friction
@settings(PROFILE, max_examples=25)
@given(contact_and_creep(), law_shapes, log_uniform(1e-6, 1e3))
def test_falling_friction_is_bounded_by_static_friction(case, shape, speed):
    contact, creep = case
    law = falling_law(contact.mu, shape)
    result = solve(contact.scene(creep, friction=law, rolling_speed=speed), method="polynomial")
    event(f"falling friction success={result.success}")
    if result.success:
        check_polynomial(result, contact, f"{law!r}, V = {speed!r}")
        assert math.isfinite(result.creep_stiffness_per_length), \
            f"{law!r}, V = {speed!r}: dT'/dxi = {result.creep_stiffness_per_length!r} (implicit function theorem)"
    else:
        assert_clear_failure(result, "falling friction")


@settings(PROFILE, max_examples=25)
@given(contacts, law_shapes, signs, st.floats(2.0, 4.0), log_uniform(1e-6, 1e3))
@example(Contact(1.0, 1e6, 0.0, 1.0, 1e-4), ("exponential", 0.1, 0.1), 1.0, 2.0, 1.0)  # mu falls by 1.4e-6 mu_s
def test_falling_friction_saturates_at_the_sliding_coefficient(contact, shape, sign, log_excess, speed):
    """Deep in full slip (|xi| = 1e2..1e4 mu_s a / R) there is no stick zone and T'/N' = mu(V s) averaged over p.

    The slip differs from xi by the elastic du/dx, a few mu_s a / R (Carter: +-mu a / R), so T'/(N' sign(xi)) lies
    between mu at V (|xi| +- 10 mu_s a / R); on a flat surface the discrete T' is a p-weighted mean of nodal mu,
    so the bracket holds to round-off.
    """
    law = falling_law(contact.mu, shape)
    creep = sign * contact.saturation * 10.0**log_excess
    result = solve(contact.scene(creep, friction=law, rolling_speed=speed), method="polynomial")
    if not result.success:
        assert_clear_failure(result, "falling friction, full slip")
        return
    spread = 10.0 * contact.saturation
    fastest = float(law.coefficient(speed * (abs(creep) + spread)))
    slowest = float(law.coefficient(speed * (abs(creep) - spread)))
    ratio = result.tangential_force_per_length * sign / contact.load
    assert result.stick_half_width == 0.0, f"a* = {result.stick_half_width!r} at {10.0**log_excess:.3g} saturations"
    assert fastest - SOLVER * contact.mu <= ratio <= slowest + SOLVER * contact.mu, \
        f"T'/N' = {ratio!r} outside [mu(V(|xi| + 10 sat)), mu(V(|xi| - 10 sat))] = [{fastest!r}, {slowest!r}]"


@settings(PROFILE, max_examples=15)
@given(st.data(), contact_and_creep(), log_uniform(1e-6, 1e3))
@example(None, (Contact(8498390.0, 139620099.85100973, 0.28, 0.7940175128489882, 2.7664517564714073e-05), 0.1), 1e-3)
def test_falling_friction_on_short_corrugation_is_bounded(data, case, speed):
    """Regression: the slip iteration once sampled mu(V s) p at 128 nodes whatever the pressure order (up to
    400); the aliasing gave |T'| > mu_s N'."""
    contact, creep = case
    if data is None:  # the pinned reproducer: k a = 340, A/A_split ~ 5e-3, x_c = 2 mm
        law = ExponentialFalling(contact.mu, 0.005959958439226405, 0.016323299777387505)
        harmonic, axis = Harmonic.from_wavelength(0.006226031791272123, 1.919656634986393e-07, 0.3), 0.002
    else:
        law = falling_law(contact.mu, data.draw(law_shapes))
        harmonic, _ = data.draw(corrugations(contact, largest=1e-2))
        axis = 0.0
    scene = contact.scene(creep, friction=law, rolling_speed=speed, surface=Surface(harmonics=(harmonic,)),
                          axis_position=axis)
    result = solve(scene, method="polynomial")
    if result.success:
        check_polynomial(result, contact, f"{law!r}, V = {speed!r}, corrugated")
    else:
        assert_clear_failure(result, "falling friction, corrugated")


@settings(PROFILE, max_examples=25)
@given(contact_and_creep(), log_uniform(1e-6, 1e3), st.sampled_from(("exponential", "rational", "linear")),
       st.floats(1e-3, 0.999))
def test_falling_friction_that_barely_falls_is_carter(case, speed, kind, kinetic):
    """If mu drops by at most 1e-10 mu_s over the slip velocities that occur (V s <= V (|xi| + 2 mu a / R)),
    T' is Carter's to 1e-10 + SOLVER."""
    contact, creep = case
    mu = contact.mu
    fastest = speed * (abs(creep) + 2.0 * contact.saturation)
    drop = 1e-10
    if kind == "exponential":  # mu_s - mu(v) <= mu_s (1 - A) B v
        law = ExponentialFalling(mu, kinetic, drop / ((1.0 - kinetic) * fastest))
    elif kind == "rational":  # <= (mu_s - mu_k) v / v_ref
        law = RationalFalling(mu, kinetic * mu, (1.0 - kinetic) * fastest / drop)
    else:  # <= slope v
        law = LinearFalling(mu, kinetic * mu, drop * mu / fastest)
    result = solve(contact.scene(creep, friction=law, rolling_speed=speed), method="polynomial")
    assert result.success, result.message
    check_polynomial(result, contact, repr(law))
    t_ref, _, _ = carter(contact.load, creep, contact.radius, contact.estar, mu)
    dt = abs(result.tangential_force_per_length - t_ref) / (mu * contact.load)
    assert dt <= drop + SOLVER, f"|T' - T'_Carter| / (mu N') = {dt:.3g} with mu constant to {drop}"


# ---------------------------------------------------------------------------------------------------------------
# auto and discretised
@st.composite
def any_scene(draw):
    """A scene from the whole domain: flat or corrugated, Coulomb or falling friction; with its Contact."""
    contact, creep = draw(contact_and_creep())
    changes = {"rolling_speed": draw(log_uniform(1e-6, 1e3))}
    if draw(st.booleans()):
        changes["surface"] = Surface(harmonics=(draw(corrugations(contact))[0],))
    if draw(st.booleans()):
        changes["friction"] = falling_law(contact.mu, draw(law_shapes))
    return contact, contact.scene(creep, **changes)


@settings(PROFILE, max_examples=40)
@given(any_scene())
def test_auto_succeeds_or_says_why(case):
    contact, scene = case
    result = solve(scene, elements=ELEMENTS)
    assert result.method in METHODS, f"unknown method {result.method!r}"
    event(f"auto: {result.method}, success={result.success}")
    if scene.surface.is_flat and scene.friction.is_constant:
        assert result.method == "closed_form" and result.success, "a Hertzian Coulomb scene is the closed form's"
    if not result.success:
        assert_clear_failure(result, "auto")
    elif result.method == "discretised":
        assert_finite(result, "auto -> discretised")
        assert abs(result.tangential_force_per_length) <= contact.mu * contact.load * (1.0 + SOLVER)
    else:
        check_polynomial(result, contact, f"auto -> {result.method}")


@settings(PROFILE, max_examples=60)
@given(st.data(), contact_and_creep(), law_shapes, log_uniform(1e-6, 1e3))
def test_auto_with_falling_friction_on_corrugation_up_to_splits(data, case, shape, speed):
    """A falling law on corrugations up to 4 A_split (one patch: the polynomial slip iteration; several: the
    discretised one, a stick zone at each leading edge): solve() never raises; an answer is finite within mu_s N',
    a failure names its reason.  (Its error estimate once divided 0 by 0 on a spurious single patch.)"""
    contact, creep = case
    harmonic, ratio = data.draw(corrugations(contact))
    scene = contact.scene(creep, friction=falling_law(contact.mu, shape), rolling_speed=speed,
                          surface=Surface(harmonics=(harmonic,)), axis_position=data.draw(st.floats(-1.0, 1.0))
                          * 2.0 * math.pi / harmonic.wavenumber)
    result = solve(scene, elements=ELEMENTS)
    event(f"falling, corrugated: {result.method}, success={result.success}, A/A_split {'<' if ratio < 1 else '>='} 1")
    if not result.success:
        assert_clear_failure(result, "auto, falling friction, corrugated")
        return
    assert_finite(result, "auto, falling friction, corrugated")
    assert abs(result.tangential_force_per_length) <= contact.mu * contact.load * (1.0 + SOLVER), \
        f"|T'| = {abs(result.tangential_force_per_length)!r} above mu_s N' ({result.method})"


@settings(PROFILE, max_examples=6)
@given(any_scene(), st.integers(16, 48))
def test_discretised_at_small_n_succeeds_or_says_why(case, elements):
    contact, scene = case
    result = solve(scene, method="discretised", elements=elements)
    if not result.success:
        assert_clear_failure(result, "discretised")
        return
    assert_finite(result, "discretised")
    mu_n = contact.mu * contact.load
    t = result.tangential_force_per_length
    assert abs(t) <= mu_n * (1.0 + SOLVER), f"|T'|/(mu N') = {abs(t) / mu_n!r}"
    assert t * math.copysign(1.0, scene.creep) >= -SOLVER * mu_n, f"T' = {t!r} against xi = {scene.creep!r}"
    assert 0.0 <= result.stick_half_width <= result.contact_half_width


# ---------------------------------------------------------------------------------------------------------------
# errors that name the value
BAD_REALS = (math.nan, math.inf, -math.inf)
INVALID = {  # field: (builds an object from the value, values out of range besides the non-finite ones)
    "normal_load_per_length": (lambda v: Scene(v), (-1.0, -1e-300)),
    "creep": (lambda v: Scene(1e6, creep=v), ()),
    "radius": (lambda v: Scene(1e6, radius=v), (0.0, -0.46)),
    "rolling_speed": (lambda v: Scene(1e6, rolling_speed=v), (-1e-6,)),
    "axis_position": (lambda v: Scene(1e6, axis_position=v), ()),
    "youngs_modulus": (lambda v: Material(v), (0.0, -1e6)),
    "poisson_ratio": (lambda v: Material(210e9, v), (0.5, -0.1, 0.7)),
    "friction coefficient mu": (lambda v: Coulomb(v), (0.0, -0.3)),
    "friction kinetic_ratio": (lambda v: ExponentialFalling(0.3, v), (0.0, 1.5)),
    "friction decay": (lambda v: ExponentialFalling(0.3, 0.4, v), (-1.0,)),
    "harmonic wavenumber": (lambda v: Harmonic(v, 1e-6), (0.0, -1.0)),
    "corrugation wavelength": (lambda v: Harmonic.from_wavelength(v, 1e-6), (0.0, -0.04)),
}


@settings(PROFILE, max_examples=80)
@given(st.sampled_from(sorted(INVALID)), st.data())
def test_invalid_values_raise_a_scene_error_naming_them(field, data):
    build, out_of_range = INVALID[field]
    value = data.draw(st.sampled_from(BAD_REALS + out_of_range))
    with pytest.raises(SceneError) as caught:
        build(value)
    message = str(caught.value)
    assert field in message and repr(float(value)) in message, f"{field} = {value!r}: message {message!r}"


@settings(PROFILE, max_examples=20)
@given(st.one_of(st.integers(-5, 0), st.integers(2001, 10**6), st.floats(1.5, 199.5).filter(lambda v: v % 1)))
def test_invalid_polynomial_order_is_named(order):
    with pytest.raises(ValueError, match=f"order = {order!r} is out of range"):
        solve(Scene(1e6, creep=1e-4), method="polynomial", order=order)


# ---------------------------------------------------------------------------------------------------------------
# the stepping model behind the FMU
@settings(PROFILE, max_examples=40)
@given(model_parameters(), st.data())
def test_contact_model_steps_to_valid_outputs_or_a_model_error(case, data):
    """Parameters and inputs at the extremes: valid outputs, or a ModelError naming the invalid value (a valid
    step may also be refused when no allowed method solves the scene), with the state left unchanged."""
    parameters, problem = case
    try:
        model = ContactModel(ContactParameters(**parameters))
    except ModelError as exc:
        event("model: parameters refused")
        assert problem is not None and f"{problem} = " in str(exc), f"refused {parameters}: {exc}"
        return
    assert problem is None, f"{problem} = {parameters[problem]!r} was accepted"
    step_at_the_extremes(model, parameters, data, 3, "no method solved")


def step_at_the_extremes(model, parameters: dict, data, steps: int, refusal: str, instationary: bool = False):
    """``steps`` steps with inputs of :func:`extremes.model_inputs`: valid outputs (:func:`extremes.check_outputs`),
    or a ModelError naming the invalid input, or for valid inputs containing ``refusal``; a refused step leaves
    the state unchanged."""
    t = 0.0
    for _ in range(steps):
        (h, normal_load, creep, velocity), problem = data.draw(model_inputs(parameters["contact_width"]))
        before = model.get_state()
        try:
            out = model.step(t, h, normal_load, creep, velocity)
        except ModelError as exc:
            event(f"model: step refused ({'input' if problem else 'valid input'})")
            message = str(exc)
            assert f"{problem} = " in message if problem else refusal in message, message
            assert model.get_state() == before, "a refused step leaves the state unchanged"
            continue
        assert problem is None, f"{problem} invalid, yet the step was accepted: {out}"
        event(f"model: method_used {out.method_used}")
        check_outputs(out, parameters, normal_load, creep, velocity, instationary)
        t += h


@st.composite
def instationary_parameters(draw):
    """``ContactParameters`` keywords of instationary rolling (flat surface, Coulomb friction, which the instationary
    models need) over the domain of :func:`extremes.model_parameters`: ``transient`` 1 or 2, ``method`` 0 or 3,
    ``tolerance`` 0 (the defaults), 1e-2 or 2e-3 (with ``transient`` 1 and ``method`` 0: the relaxation lag while its
    swing bound meets the tolerance, else the extrapolating pair 25/50 resp. 29/58), ``elements`` 0 or
    :data:`extremes.ELEMENTS` (one grid)."""
    return {"youngs_modulus": draw(log_uniform(1e6, 1e12)), "poisson_ratio": draw(st.floats(0.0, 0.49)),
            "radius": draw(log_uniform(1e-3, 1e2)), "contact_width": draw(log_uniform(1e-3, 1.0)),
            "friction_coefficient": draw(log_uniform(1e-6, 2.0)), "transient": draw(st.sampled_from((1, 2))),
            "method": draw(st.sampled_from((0, 3))), "tolerance": draw(st.sampled_from((0.0, 1e-2, 2e-3))),
            "elements": draw(st.sampled_from((0, ELEMENTS)))}


@settings(PROFILE, max_examples=30)
@given(instationary_parameters(), st.data())
def test_instationary_model_steps_to_valid_outputs_or_a_model_error(parameters, data):
    """The instationary models (relaxation lag, discretised transient, extrapolating pair) at the extremes of the
    inputs, 4 steps: valid outputs (|T| <= mu N, 0 <= a* <= a, finite), or a ModelError: naming the invalid input,
    or, for valid inputs, saying what failed (e.g. a contact so wide that the transient's datum falls inside its
    grid: the half-space theory does not apply); the state is then left unchanged."""
    step_at_the_extremes(ContactModel(ContactParameters(**parameters)), parameters, data, 4, "instationary",
                         instationary=True)
