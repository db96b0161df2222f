"""The 3D half-space kernel (rollcontact.core.halfspace.surface): rectangle influence coefficients against quadrature of
the Boussinesq/Cerruti point solutions, the FFT convolution against the direct sum, and Hertz's displacement."""

import math

import numpy as np
import pytest
from scipy import integrate
from scipy.special import ellipe, ellipk

from rollcontact.core.halfspace.surface import SurfaceGrid, influence_coefficients, operator_for

NU = 0.3
DX, DY = 1.0, 0.6


def kernels(s, t):
    """The point kernels (field minus source (s, t)) of the module docstring, both bodies, G = 1."""
    r = math.hypot(s, t)
    return {"zz": (1.0 - NU) / r / math.pi, "xx": ((1.0 - NU) / r + NU * s * s / r**3) / math.pi,
            "yy": ((1.0 - NU) / r + NU * t * t / r**3) / math.pi, "xy": NU * s * t / r**3 / math.pi}


def quadrature(ox, oy, key):
    """The element integral of one kernel: polar about the field point for the loaded element itself (the kernel is
    homogeneous of degree -1, so the radial integral is the distance to the edge), dblquad for the others."""
    s1, s2, t1, t2 = ox - DX / 2, ox + DX / 2, oy - DY / 2, oy + DY / 2
    if s1 < 0 < s2 and t1 < 0 < t2:
        def integrand(theta):
            c, s = math.cos(theta), math.sin(theta)
            radius = min(s2 / c if c > 0 else s1 / c, t2 / s if s > 0 else t1 / s)
            return kernels(c, s)[key] * radius  # kernel(r e) = kernel(e)/r, times r dr
        corners = sorted(math.atan2(t, s) % (2 * math.pi) for s in (s1, s2) for t in (t1, t2))
        points = [0.0, *corners, 2 * math.pi]
        pieces = zip(points[:-1], points[1:], strict=True)
        return sum(integrate.quad(integrand, lo, hi, epsabs=1e-13)[0] for lo, hi in pieces)
    return integrate.dblquad(lambda t, s: kernels(s, t)[key], s1, s2, t1, t2, epsabs=1e-13, epsrel=1e-11)[0]


@pytest.mark.parametrize("offset", [(0.0, 0.0), (1.0, 0.0), (0.0, 0.6), (-2.0, 1.2), (3.0, -2.4), (-1.0, -0.6)])
@pytest.mark.parametrize("key", ["zz", "xx", "yy", "xy"])
def test_influence_coefficients_match_quadrature_of_the_point_solutions(offset, key):
    closed = influence_coefficients(*offset, DX, DY, NU)[key]
    numeric = quadrature(*offset, key)
    assert closed == pytest.approx(numeric, rel=1e-8, abs=1e-11), (
        f"coefficient {key} at offset {offset}: closed form {closed!r} vs quadrature {numeric!r}")


def test_fft_convolution_equals_the_direct_sum_and_the_rolling_operator_is_the_upwind_difference():
    grid = SurfaceGrid(7, 5, 0.3, 0.7, -1.0, -2.0)
    op = operator_for(grid, 0.25)
    rng = np.random.default_rng(1)
    qx, qy = rng.normal(size=(2, grid.nx, grid.ny))
    x, y = grid.mesh()
    ux = np.zeros(x.shape)
    uy = np.zeros(x.shape)
    uz = np.zeros(x.shape)
    rx = np.zeros(x.shape)
    for i in range(grid.nx):
        for j in range(grid.ny):
            c = influence_coefficients(x[i, j] - x, y[i, j] - y, grid.dx, grid.dy, 0.25)
            up = influence_coefficients(x[i, j] + grid.dx - x, y[i, j] - y, grid.dx, grid.dy, 0.25)
            ux[i, j] = np.sum(c["xx"] * qx + c["xy"] * qy)
            uy[i, j] = np.sum(c["xy"] * qx + c["yy"] * qy)
            uz[i, j] = np.sum(c["zz"] * qx)
            rx[i, j] = np.sum((c["xx"] - up["xx"]) * qx + (c["xy"] - up["xy"]) * qy) / grid.dx
    fx, fy = op.tangential(qx, qy)
    np.testing.assert_allclose(fx, ux, rtol=0, atol=1e-12 * np.abs(ux).max(), err_msg="u_x by FFT vs direct sum")
    np.testing.assert_allclose(fy, uy, rtol=0, atol=1e-12 * np.abs(uy).max(), err_msg="u_y by FFT vs direct sum")
    np.testing.assert_allclose(op.normal(qx), uz, rtol=0, atol=1e-12 * np.abs(uz).max(),
                               err_msg="u_z by FFT vs direct sum")
    np.testing.assert_allclose(op.rolling(qx, qy)[0], rx, rtol=0, atol=1e-12 * np.abs(rx).max(),
                               err_msg="rolling operator by FFT vs (u(x) - u(x + dx))/dx summed directly")


def test_hertz_pressure_gives_the_quadratic_displacement_of_an_ellipse():
    """Johnson, Contact Mechanics, sec. 3.9: under ``p0 sqrt(1 - x^2/a^2 - y^2/b^2)`` (b < a, e^2 = 1 - b^2/a^2)
    the two bodies approach by ``delta - A x^2 - B y^2`` with ``delta = p0 b K / E*``,
    ``A = p0 b (K - E) / (E* a^2 e^2)``, ``B = p0 b (a^2/b^2 E - K) / (E* a^2 e^2)``; E* = G / (1 - nu)."""
    a, b, nu = 1.0, 0.5, 0.25
    contact_modulus = 1.0 / (1.0 - nu)
    e2 = 1.0 - (b / a) ** 2
    k, e = ellipk(e2), ellipe(e2)
    scale = b / (contact_modulus * a * a * e2)
    A, B, delta = scale * (k - e), scale * (a * a / (b * b) * e - k), b * k / contact_modulus
    errors = []
    for n in (40, 80):
        grid = SurfaceGrid.centred(a, b, n, n)
        x, y = grid.mesh()
        pressure = np.sqrt(np.clip(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0, None))
        inside = (x / a) ** 2 + (y / b) ** 2 < 0.8
        u = operator_for(grid, nu).normal(pressure)
        errors.append(np.abs(u - (delta - A * x**2 - B * y**2))[inside].max() / delta)
    assert errors[1] < 2e-3, f"Hertz displacement off by {errors[1]:.2e} of the approach on 80 x 80 elements"
    assert errors[1] < 0.6 * errors[0], f"no convergence under refinement: errors {errors} on 40 and 80 elements"


def test_bad_grids_are_refused_with_the_value():
    with pytest.raises(ValueError, match="nx = 2"):
        SurfaceGrid(2, 10, 1.0, 1.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="dy = -1"):
        SurfaceGrid(10, 10, 1.0, -1.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="x_min"):
        SurfaceGrid(10, 10, 1.0, 1.0, math.nan, 0.0)


def test_a_field_carried_between_grids():
    """SurfaceGrid.carried: on one lattice the values themselves (a grid shifted by whole elements), a linear field
    reproduced exactly between the source's centres at half the element, 0 beyond the source's outer centres."""
    source = SurfaceGrid(10, 12, 0.2e-3, 0.2e-3, -1e-3, 0.4e-3)
    values = np.random.default_rng(1).random((10, 12))
    shifted = SurfaceGrid(14, 10, 0.2e-3, 0.2e-3, -1.4e-3, 0.6e-3)
    moved = shifted.carried(values, source)
    assert np.abs(moved[2:12, :] - values[:, 1:11]).max() < 1e-12, "the same lattice: the values themselves"
    assert not moved[:2].any() and not moved[12:].any(), "beyond the source's outer centres: 0"
    x, y = source.mesh()
    finer = SurfaceGrid(20, 24, 0.1e-3, 0.1e-3, -1e-3, 0.4e-3)
    fx, fy = finer.mesh()
    linear = finer.carried(3.0 + 2e3 * x - 5e3 * y, source)
    inside = (fx >= source.x[0]) & (fx <= source.x[-1]) & (fy >= source.y[0]) & (fy <= source.y[-1])
    assert np.abs(linear - (3.0 + 2e3 * fx - 5e3 * fy))[inside].max() < 1e-12, "a linear field is carried exactly"
    assert not linear[~inside].any(), "0 beyond the source's outer centres"
