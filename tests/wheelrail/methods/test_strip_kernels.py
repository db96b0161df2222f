"""The strips' kernels against quadrature: the closed-form line kernels j and m against their defining integrals, the
tabulated antiderivatives Jc, Mc against the integral of the closed forms, their limits (Jc ~ (pi/2) ln rho + pi ln 2
+ pi/4, Mc -> -pi, the 2D half-plane), and the strip matrices against the displacement and curvature of a semi-elliptic
strip by 2D quadrature of Boussinesq's kernel."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import dblquad, quad

from rollcontact.wheelrail.methods.strip_kernels import integrated, line_kernels, strip_matrices


@pytest.mark.filterwarnings("ignore::scipy.integrate.IntegrationWarning")
@pytest.mark.parametrize("rho", [1e-3, 0.05, 0.4, 1.0, 3.0, 40.0])
def test_line_kernels_are_their_integrals(rho):
    j, m = line_kernels(np.array([rho]))
    j_quad = quad(lambda u: math.sqrt(1 - u * u) / math.sqrt(u * u + rho * rho), -1, 1, points=[0], limit=200,
                  epsabs=1e-13, epsrel=1e-12)[0]
    m_quad = 2 * quad(lambda u: math.sqrt(1 - u * u) * (2 * u * u - rho * rho) / (u * u + rho * rho) ** 2.5, 0, 1,
                      points=[min(rho, 0.5)], limit=400, epsabs=1e-12, epsrel=1e-11)[0]
    assert math.isclose(j[0], j_quad, rel_tol=1e-10), f"j({rho}) = {j[0]!r}, quadrature {j_quad!r}"
    assert math.isclose(m[0], m_quad, rel_tol=1e-8, abs_tol=1e-12), f"m({rho}) = {m[0]!r}, quadrature {m_quad!r}"


@pytest.mark.parametrize("rho", [1e-4, 0.02, 0.7, 1.0, 5.0, 300.0])
def test_tables_are_the_antiderivatives(rho):
    (jc, mc), (djc, dmc) = integrated(np.array([rho]), derivative=True)
    j_int = quad(lambda r: line_kernels(np.array([r]))[0][0], 0, rho, limit=200, epsabs=1e-13, epsrel=1e-12)[0]
    m_int = quad(lambda r: line_kernels(np.array([r]))[1][0], 0, rho, limit=200, epsabs=1e-13, epsrel=1e-12)[0]
    j, m = line_kernels(np.array([rho]))
    assert abs(jc[0] - j_int) < 1e-9 * max(1.0, abs(j_int)), f"Jc({rho}) = {jc[0]!r}, quadrature {j_int!r}"
    assert abs(mc[0] - m_int) < 1e-9 * max(1.0, abs(m_int)), f"Mc({rho}) = {mc[0]!r}, quadrature {m_int!r}"
    assert math.isclose(djc[0], rho * j[0], rel_tol=1e-7), "dJc/dt = rho j"
    assert math.isclose(dmc[0], rho * m[0], rel_tol=1e-7), "dMc/dt = rho m"


def test_limits_of_the_antiderivatives():
    big = np.array([1e7])
    jc, mc = integrated(big)
    expected = 0.5 * math.pi * math.log(1e7) + math.pi * math.log(2) + math.pi / 4
    assert math.isclose(jc[0], expected, rel_tol=1e-8), f"Jc at 1e7: {jc[0]!r}, asymptote {expected!r}"
    assert math.isclose(mc[0], -math.pi, rel_tol=1e-8), f"Mc at 1e7: {mc[0]!r} is not -pi (the 2D half-plane)"
    small = np.array([1e-8])
    jc, mc = integrated(small)
    assert math.isclose(jc[0], 2e-8 * math.log(4e8), rel_tol=1e-4), "Jc near 0 is 2 rho ln(4 / rho)"


def test_strip_matrices_are_boussinesq_quadrature():
    """Displacement and curvature on the centre line of a strip at a lateral distance, and of its own centre."""
    estar, a, p0 = 1.1e11, 2e-3, 1e9
    lower, upper = np.array([0.4e-3]), np.array([1.0e-3])
    centres = np.array([-0.5e-3, 0.7e-3])  # off the strip, then on it (its own centre)
    U, C = strip_matrices(centres, lower, upper, np.array([a]), estar)

    def displacement(s):  # the t-integral of 1/r in closed form (asinh), then x by quadrature (log singular at 0)
        def inner(x):
            x = max(abs(x), 1e-300)
            return math.sqrt(max(0.0, 1 - (x / a) ** 2)) * (math.asinh((upper[0] - s) / x)
                                                             - math.asinh((lower[0] - s) / x))
        return p0 * 2 * quad(inner, 0, a, limit=400, epsabs=0, epsrel=1e-11)[0] / (math.pi * estar)

    for i, s in enumerate(centres):
        expected = displacement(s)
        got = U[i, 0] * p0 * a
        assert math.isclose(got, expected, rel_tol=1e-7), f"u_z at s = {s}: {got!r} vs quadrature {expected!r}"
    # curvature off the strip: -(1/2) d^2u/dx^2 at x = 0 by quadrature of d^2/dx^2 (1/r)
    s = centres[0]
    f = lambda t, x: p0 * math.sqrt(max(0.0, 1 - (x / a) ** 2)) * (2 * x * x - (s - t) ** 2) / (  # noqa: E731
        x * x + (s - t) ** 2) ** 2.5
    curvature = dblquad(f, -a, a, lower[0], upper[0], epsabs=1e-3, epsrel=1e-8)[0] / (math.pi * estar)
    assert math.isclose(C[0, 0] * p0 / a, -0.5 * curvature, rel_tol=1e-5), "the curvature kernel off the strip"
