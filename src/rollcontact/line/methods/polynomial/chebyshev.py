"""Chebyshev machinery of the polynomial method (docs/physics.md, Polynomial method).

On an interval of half-width ``h`` centred at ``c`` write ``x = c + h t``, ``t = cos(theta)``.  The finite
Hilbert transform pairs used throughout:

* ``(1/pi) PV-int_{-1}^{1} sqrt(1-tau^2) U_{n-1}(tau) / (t - tau) dtau = T_n(t)``             for |t| < 1,
* the same integral equals ``F_n(t) = (t - sign(t) sqrt(t^2 - 1))^n``                            for |t| > 1.

So a density ``f = sum_{n>=1} c_n sqrt(1-t^2) U_{n-1}(t) = sum c_n sin(n theta)`` (bounded, zero at both
ends) answers ``(1/pi) PV-int f(z)/(x - z) dz = sum c_n T_n(t)``; a right-hand side has a bounded solution iff
its T_0 coefficient vanishes, and ``int f dx = (pi h / 2) c_1``.

A right-hand side ``r(x)`` is handled through its Chebyshev coefficients on the interval.  Harmonics expand
exactly with Jacobi-Anger, ``cos(phi + z t) = sum eps_n J_n(z) cos(phi + n pi/2) T_n(t)`` (``eps_0 = 1``,
``eps_n = 2``), which is where the paper's Bessel functions come from.

Speed.  A solve calls these functions a few dozen times on tiny data, so the cost is per-call overhead, not
arithmetic: the scalar paths use plain floats (``math`` and the Cython scalar ``j0/j1`` of
:mod:`scipy.special.cython_special`, the same functions as the ufuncs without their dispatch), and every table that
depends only on sizes (angle grids, sine/cosine tables, their index vectors) is built once in a bounded
module-level cache keyed by those sizes and returned read-only, so no call can alter what another call sees.
Products are ``ndarray.dot``: the BLAS call of ``@`` (the same bits) without the gufunc dispatch's per-call overhead.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.polynomial import chebyshev as npcheb
from numpy.polynomial import polynomial as nppoly
from scipy import special
from scipy.special import cython_special

from rollcontact.line.scene import Harmonic, Surface

# the scalar Bessel functions of the Newton loops: bit-identical to special.j0/j1, a third of the call cost
_j0 = cython_special.j0


_j1 = cython_special.j1


_jv = special.jv


def read_only(*arrays: np.ndarray):
    """Freeze cached arrays: a caller that tried to modify one would change every later result."""
    for a in arrays:
        a.flags.writeable = False
    return arrays if len(arrays) > 1 else arrays[0]


@lru_cache(maxsize=64)
def unit_grid(m: int) -> np.ndarray:
    """m equally spaced points on [0, 1] (cached: numpy's linspace costs more per call than the arithmetic it does)."""
    return read_only(np.arange(m, dtype=float) / (m - 1))


@lru_cache(maxsize=64)
def theta_grid(m: int, n_max: int) -> tuple[np.ndarray, np.ndarray]:
    """Interior angles theta_i = pi i/m (i = 1..m-1) and the table sin(n theta_i), n = 1..n_max (cached)."""
    theta = np.pi * np.arange(1, m, dtype=float) / m
    return read_only(theta, np.sin(theta[:, None] * np.arange(1, n_max + 1)))


@lru_cache(maxsize=64)
def pressure_table(m: int, n_max: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Tables on the angles ``theta_i = pi i/m`` (i = 1..m-1) for series of n = 1..n_max terms (cached).

    Returns
    -------
    values : ndarray
        ``theta_grid(m, n_max)``'s sine table with two more rows, ``n`` and ``n (-1)^(n-1)``: one product with
        ``c_1..c_n`` gives ``p(theta_i) = sum c_n sin(n theta_i)`` and both edge slopes ``dp/dtheta = sum n c_n``
        (theta = 0, trailing edge) and ``sum n c_n (-1)^(n-1)`` (theta = pi, leading edge).
    cosines : ndarray
        ``n cos(n theta_i)`` (derivative rows, for Newton on the maximum).
    one_plus_cos : ndarray
        ``1 + cos(theta_i)`` (the stick-zone samples of the traction check).
    n, n_squared : ndarray
        ``n`` and ``n^2`` (the Newton steps on the maximum weight the series by them).
    """
    theta, sines = theta_grid(m, n_max)
    n = np.arange(1, n_max + 1, dtype=float)
    return read_only(np.vstack((sines, n, n * (-1.0) ** (n - 1))), n * np.cos(theta[:, None] * n),
                     1.0 + np.cos(theta), n, n * n)


@lru_cache(maxsize=64)
def orders(n_max: int) -> tuple[np.ndarray, np.ndarray]:
    """``n = 0..n_max`` as floats and ``eps_n (1, 0, -1, 0)[n mod 4]``-style selectors (cached).

    Returns ``n`` and the (n_max + 1, 4) matrix ``E`` with ``E[n, n mod 4] = eps_n`` (Jacobi-Anger weights
    ``eps_0 = 1``, ``eps_n = 2``): ``E @ (b_0, b_1, b_2, b_3)`` is ``eps_n b_(n mod 4)``, the period-4 pattern of
    ``cos(phi + n pi/2)``.
    """
    n = np.arange(n_max + 1, dtype=float)
    quarter = np.zeros((n_max + 1, 4))
    quarter[np.arange(n_max + 1), np.arange(n_max + 1) % 4] = 2.0
    quarter[0, 0] = 1.0
    return read_only(n, quarter)


@lru_cache(maxsize=32)
def power_to_chebyshev(size: int) -> np.ndarray:
    """The (size, size) matrix taking power coefficients in t to Chebyshev coefficients (cached).

    Its entries are dyadic rationals, exact in floats; one product replaces ``npcheb.poly2cheb``, whose argument
    checks and series arithmetic cost far more per call than the product for a quartic.
    """
    m = np.zeros((size, size))
    for j in range(size):
        m[: j + 1, j] = npcheb.poly2cheb(np.eye(1, size, j)[0])
    return read_only(m)


def double_factorial_ratio(j: int) -> float:
    """(j-1)!! / j!! for even j >= 0 (the Chebyshev-weighted mean of t^j)."""
    r = 1.0
    for i in range(2, j + 1, 2):
        r *= (i - 1) / i
    return r


@lru_cache(maxsize=32)
def slope_tables(polynomial: tuple, origin: float = 0.0) -> tuple:
    """``(slope_poly, slope_derivs, deriv_lists, horner_lists, curvature_poly)`` of ``Z(origin + u)`` in u,
    ``Z(X) = sum polynomial[j] X^j`` (:func:`taylor_shift`; cached by value).

    ``Z'`` as power coefficients with all its derivatives, as read-only arrays and as lists (the scalar paths run
    in Newton loops, where numpy scalars cost more than the maths); ``horner_lists`` are the lists that
    :meth:`SlopeExpansion.moments` evaluates (derivatives 0 to ``deg Z'' + 1``), highest coefficient first;
    ``curvature_poly`` are the coefficients of ``Z''`` without trailing zeros
    (:meth:`SlopeExpansion.curvature_bound`).
    """
    # the derivatives on lists, the products of numpy's polyder (j c_j) without its argument handling per call: with
    # the axis moving every FMU step, the origin changes and the cache cannot serve
    derivs = [derivative(taylor_shift(tuple(float(c) for c in polynomial), origin))]
    for _ in range(len(derivs[0]) + 1):
        d = derivs[-1]
        derivs.append(derivative(d) if len(d) > 1 else (0.0,))
    deriv_lists = tuple(derivs)
    slope_derivs = read_only(*(np.array(d) for d in deriv_lists))
    slope_poly = slope_derivs[0]
    curvature_poly = list(deriv_lists[1])
    while len(curvature_poly) > 1 and curvature_poly[-1] == 0.0:
        curvature_poly.pop()
    return (slope_poly, tuple(slope_derivs), deriv_lists, tuple(d[::-1] for d in deriv_lists[: slope_poly.size + 1]),
            tuple(curvature_poly))


@lru_cache(maxsize=32)
def surface_data(surface) -> tuple:
    """What :class:`SlopeExpansion` needs from a surface, cached by value (Surface is frozen and hashable).

    Returns ``(has_poly, slope_poly, slope_derivs, deriv_lists, horner_lists, curvature_poly, poly_weights,
    harmonic_list, harmonic_curvature, max_wavenumber)``: the :func:`slope_tables` of the polynomial part, the
    moment weights of :meth:`SlopeExpansion.moments` as ``(j, weight, 1/j!, j even)``, the non-zero harmonics as
    plain ``(k, Phi, Psi)`` tuples, ``sum k^2 |Z_m| >= |Z''|`` of the harmonics and their largest k (0 without
    harmonics).
    """
    has_poly = any(c != 0.0 for c in surface.polynomial[1:])
    if has_poly:
        slope_poly, slope_derivs, deriv_lists, horner_lists, curvature_poly = slope_tables(surface.polynomial)
    else:
        slope_poly = read_only(np.zeros(1))
        slope_derivs = (slope_poly, slope_poly)
        deriv_lists = ((0.0,), (0.0,))
        horner_lists = ()
        curvature_poly = (0.0,)
    harmonic_list = tuple((hm.wavenumber, hm.cos_amplitude, hm.sin_amplitude) for hm in surface.harmonics
                          if hm.amplitude != 0.0)
    return (has_poly, slope_poly, slope_derivs, deriv_lists, horner_lists, curvature_poly,
            tuple((j, double_factorial_ratio(j) if j % 2 == 0 else first_moment_weight(j), 1.0 / math.factorial(j),
                   j % 2 == 0) for j in range(slope_poly.size)),
            harmonic_list, sum(k * k * math.hypot(phi, psi) for k, phi, psi in harmonic_list),
            max((k for k, _, _ in harmonic_list), default=0.0))


def derivative(coefficients: tuple) -> tuple:
    """Power coefficients of ``P'`` from those of P, ``(1 c_1, 2 c_2, ...)``: ``numpy.polynomial.polynomial.polyder``'s
    products, to the same bits (``(0 c_0,)`` for a constant)."""
    if len(coefficients) == 1:
        return (0.0 * coefficients[0],)
    return tuple(j * coefficients[j] for j in range(1, len(coefficients)))


def taylor_shift(coefficients: tuple, origin: float) -> tuple:
    """Power coefficients of ``P(origin + u)`` in u, ``P = sum coefficients[j] X^j`` (repeated Horner division).

    The rounding is that of evaluating P near ``origin``, i.e. the accuracy to which the surface is given there.
    """
    b = list(coefficients)
    for i in range(len(b) - 1):
        for j in range(len(b) - 2, i - 1, -1):
            b[j] += origin * b[j + 1]
    return tuple(b)


class SlopeExpansion:
    """Expansions of the gap slope ``h0'(u) = u/R - Z'(x_c + u)`` on intervals ``u = c + h t``.

    All positions (``c``, interval ends) are axis coordinates ``u = X - x_c``: the gap is a function of the
    distance to the axis, so a contact a kilometre along the surface is solved as accurately as one at X = 0 (in
    surface coordinates every ``X - x_c`` would lose ``eps |x_c|``, which exceeds a nanometre-wide patch).  The
    surface is moved to the axis once, exactly up to the rounding of its own data at ``x_c``: each harmonic
    ``Phi cos kX + Psi sin kX`` becomes ``Phi' cos ku + Psi' sin ku`` with the phase ``k x_c`` reduced once,
    ``Phi' = Phi cos kx_c + Psi sin kx_c``, ``Psi' = Psi cos kx_c - Phi sin kx_c``; the polynomial part is
    re-expanded about x_c (:func:`taylor_shift`).

    Parameters
    ----------
    radius : float
        R [m].
    axis_position : float
        x_c [m] (surface coordinate).
    surface : rollcontact.Surface
        Z(X): polynomial part and harmonics, in surface coordinates.
    """

    def __init__(self, radius, axis_position, surface):
        self.radius = float(radius)
        self.axis_position = x_c = float(axis_position)
        (self.has_poly, self.slope_poly, self.slope_derivs, self.deriv_lists, self.horner_lists, self.curvature_poly,
         self.poly_weights, harmonics, self.harmonic_curvature, self.max_wavenumber) = surface_data(surface)
        self.surface_polynomial = surface.polynomial
        if x_c != 0.0:
            if self.has_poly:
                (self.slope_poly, self.slope_derivs, self.deriv_lists, self.horner_lists,
                 self.curvature_poly) = slope_tables(surface.polynomial, x_c)
            rotated = []
            for k, phi, psi in harmonics:
                cs, sn = math.cos(k * x_c), math.sin(k * x_c)
                rotated.append((k, phi * cs + psi * sn, psi * cs - phi * sn))
            harmonics = tuple(rotated)
        self.harmonic_list = harmonics
        self.has_harmonics = bool(harmonics)

    def axis_surface(self) -> Surface:
        """The surface in axis coordinates: ``Z(x_c + u)`` as a :class:`~rollcontact.Surface` in u."""
        return axis_surface(self.surface_polynomial, self.axis_position, self.harmonic_list)

    @property
    def k(self) -> np.ndarray:
        """Wavenumbers k_m [1/m] of the non-zero harmonics."""
        return np.array([k for k, _, _ in self.harmonic_list])

    # ---- T0/T1 moments with derivatives (the exact scalar equations 28-31) -------------------------------
    def moments(self, h: float, c: float):
        """T_0 and T_1 Chebyshev coefficients of ``Z'(x_c + c + h t)`` and their derivatives (plain floats).

        ``c`` and, below, Phi, Psi and Q are in axis coordinates (class docstring).

        Returns
        -------
        m0, m1, dm0_dh, dm0_dc, dm1_dh, dm1_dc : float
            For a harmonic (eqs 28-31, docs/physics.md, Corrugated surface):
            ``m0 = k J0(kh) (Psi cos kc - Phi sin kc)``, ``m1 = -2 k J1(kh) (Phi cos kc + Psi sin kc)``; for the
            polynomial part the Taylor coefficients ``e_j = h^j Q^(j)(c)/j!`` of ``Q = Z'`` about c weighted by the
            means of t^j, ``(j-1)!!/j!!`` (even j), and the first moments ``2 j!!/(j+1)!!`` (odd j).
        """
        m0 = m1 = d0h = d0c = d1h = d1c = 0.0
        if self.has_poly:
            # Z^(j+1)(c), each needed twice below, by :func:`horner` written out (this runs in every Newton step,
            # where a call per derivative costs more than its sums; the lists come reversed and the list of values
            # preallocated, for the same reason)
            q = [0.0] * len(self.horner_lists)
            i = 0
            for coefficients in self.horner_lists:
                v = 0.0
                for coef in coefficients:
                    v = v * c + coef
                q[i] = v
                i += 1
            h_prev = 0.0  # h**(j-1), carried over from the previous term: one power per term
            for j, w, inv_fact, even in self.poly_weights:
                qj = q[j] * inv_fact
                qj1 = q[j + 1] * inv_fact
                hj = h**j
                whj = w * hj
                wdhj = w * (j * h_prev) if j > 0 else 0.0
                h_prev = hj
                if even:
                    m0 += whj * qj
                    d0h += wdhj * qj
                    d0c += whj * qj1
                else:
                    m1 += whj * qj
                    d1h += wdhj * qj
                    d1c += whj * qj1
        for k, phi, psi in self.harmonic_list:
            z = k * h
            kc = k * c
            cs, sn = math.cos(kc), math.sin(kc)
            j0 = _j0(z)
            j1 = _j1(z)
            # J1'(z) = J0 - J1/z, -> 1/2 as z -> 0
            j1p = j0 - j1 / z if z > 1e-8 else 0.5 - z * z * 3.0 / 16.0
            a0 = psi * cs - phi * sn
            a1 = phi * cs + psi * sn
            kk = k * k
            m0 += k * j0 * a0
            m1 -= 2.0 * k * j1 * a1
            d0h -= kk * j1 * a0
            d0c -= kk * j0 * a1
            d1h -= 2.0 * kk * j1p * a1
            d1c -= 2.0 * kk * j1 * a0
        return m0, m1, d0h, d0c, d1h, d1c

    # ---- curvature bounds (what makes a check provably unnecessary) ----------------------------------------
    def curvature_bound(self, lo: float, hi: float) -> float:
        """A bound of ``Z''(x_c + u)`` for u in [lo, hi] (axis coordinates): of ``|Z''|`` on a finite interval, of
        ``Z''`` from above on the whole line (``lo = -inf``, ``hi = inf``).

        Harmonics contribute ``sum k^2 |Z_m|``.  The polynomial part is bounded by ``sum |q_j| max(|lo|, |hi|)^j``
        on a finite interval (q_j: power coefficients of Z'' in u); on the whole line it is bounded only for Z'' of
        degree 0, or of degree 2 opening downwards (vertex value), and is ``inf`` otherwise.
        """
        bound = self.harmonic_curvature
        if not self.has_poly:
            return bound
        q = self.curvature_poly
        if math.isfinite(lo) and math.isfinite(hi):
            r = max(abs(lo), abs(hi))
            return bound + sum(abs(c) * r**j for j, c in enumerate(q))
        if len(q) == 1:
            return bound + q[0]
        if len(q) == 3 and q[2] < 0.0:
            return bound + q[0] - q[1] * q[1] / (4.0 * q[2])
        return math.inf

    # ---- full Chebyshev series ------------------------------------------------------------------------------
    def gap_slope_coefficients(self, h: float, c: float, order: int) -> np.ndarray:
        """Chebyshev coefficients ``[g_0 .. g_order]`` of ``h0'(c + h t)`` (c in axis coordinates; exact for the
        polynomial part, Jacobi-Anger for harmonics, truncated at ``order``).

        Harmonic m contributes ``-eps_n k J_n(k h) [Psi cos(k c + n pi/2) - Phi sin(k c + n pi/2)]``, whose bracket
        repeats with period 4 in n: ``a0, -a1, -a0, a1`` (``a0 = Psi cos kc - Phi sin kc``,
        ``a1 = Phi cos kc + Psi sin kc``), so one Bessel table per harmonic is all the work (the pattern comes from
        the cached :func:`orders`).
        """
        if self.has_harmonics:
            n, quarter = orders(order)
            g = np.zeros(order + 1)
            for k, phi, psi in self.harmonic_list:
                kc = k * c
                cs, sn = math.cos(kc), math.sin(kc)
                a0 = k * (psi * cs - phi * sn)
                a1 = k * (phi * cs + psi * sn)
                g += _jv(n, k * h) * quarter.dot(np.array((-a0, a1, a0, -a1)))
        else:
            g = np.zeros(order + 1)
        g[0] += c / self.radius
        if order >= 1:
            g[1] += h / self.radius
        if self.has_poly:
            # Taylor polynomial of Z'(c + h t) in t, then to the Chebyshev basis
            taylor = np.array([horner(self.deriv_lists[j], c) * h**j / math.factorial(j)
                               for j in range(self.slope_poly.size)])
            cheb = power_to_chebyshev(taylor.size).dot(taylor)
            m = min(cheb.size, order + 1)
            g[:m] -= cheb[:m]
        return g

    def required_order(self, h: float, truncation: float, max_order: int = 400) -> int:
        """Smallest order whose neglected harmonic coefficients are below ``truncation`` times the Hertz slope
        ``h/R`` (the polynomial part is exact from its degree on).

        Uses ``|J_n(z)| <= (z/2)^n / n!``: the bound of the n-th coefficient, ``2 k |Z_m| (kh/2)^n / n!``, is
        summed over the harmonics and decreases for n > kh.
        """
        order = max(1, self.slope_poly.size)
        if not self.has_harmonics:
            return order
        target = truncation * h / self.radius
        # bounds at the start by logarithms (no overflow for any kh), then b_(n+1) = b_n z/(n+1) in floats:
        # from n > z on they only decrease
        if len(self.harmonic_list) == 1:  # the usual single harmonic, in plain floats and without lists
            k, phi, psi = self.harmonic_list[0]
            z = 0.5 * k * h
            n = max(order, int(z) + 1)
            if n >= max_order:
                return max_order
            if z > 0.0:
                b = math.exp(math.log(2.0 * k * math.hypot(phi, psi)) + n * math.log(z) - math.lgamma(n + 1))
                while n < max_order and b > target:
                    n += 1
                    b *= z / n
            return n
        terms = [(0.5 * k * h, 2.0 * k * math.hypot(phi, psi)) for k, phi, psi in self.harmonic_list]
        n = max(order, int(max(z for z, _ in terms)) + 1)
        if n >= max_order:
            return max_order
        zs = [z for z, _ in terms if z > 0.0]
        bounds = [math.exp(math.log(amp) + n * math.log(z) - math.lgamma(n + 1)) for z, amp in terms if z > 0.0]
        while n < max_order and sum(bounds) > target:
            n += 1
            bounds = [b * z / n for b, z in zip(bounds, zs, strict=True)]
        return n

    # ---- monomial (paper eqs 21-26) -------------------------------------------------------------------------
    def gap_slope_taylor(self, c: float, order: int) -> np.ndarray:
        """Taylor coefficients ``[e_0 .. e_{order-1}]`` of ``h0'(c + x)`` in x [m] (power basis, physical; c in
        axis coordinates)."""
        e = np.zeros(order)
        e[0] = c / self.radius
        if order > 1:
            e[1] = 1.0 / self.radius
        if self.has_poly:
            for j in range(min(order, self.slope_poly.size)):
                e[j] -= nppoly.polyval(c, self.slope_derivs[j]) / math.factorial(j)
        if self.has_harmonics:
            k = self.k
            phi = np.array([p for _, p, _ in self.harmonic_list])
            psi = np.array([s for _, _, s in self.harmonic_list])
            # k^(j+1)/j! by recurrence: overflows to inf (a reported failure) instead of raising at j > 170
            scale = k.copy()
            with np.errstate(over="ignore", invalid="ignore"):
                for j in range(order):
                    if j > 0:
                        scale = scale * k / j
                    ang = c * k + 0.5 * np.pi * j
                    e[j] -= np.sum(scale * (psi * np.cos(ang) - phi * np.sin(ang)))
        return e


@lru_cache(maxsize=32)
def axis_surface(polynomial: tuple, axis_position: float, harmonic_list: tuple) -> Surface:
    """:meth:`SlopeExpansion.axis_surface` of the polynomial in surface coordinates and the ``(k, Phi, Psi)``
    harmonics already in axis coordinates (cached: building a validated Surface costs more than the arithmetic that
    uses it)."""
    return Surface(taylor_shift(polynomial, axis_position),
                   tuple(Harmonic(k, phi, psi) for k, phi, psi in harmonic_list))


def horner(coefficients, x: float) -> float:
    """Power-series value sum c_j x^j for plain floats."""
    v = 0.0
    for coef in reversed(coefficients):
        v = v * x + coef
    return v


def first_moment_weight(j: int) -> float:
    """T_1 coefficient of t^j for odd j: (2/pi) int t^(j+1)/sqrt(1-t^2) dt = 2 j!!/(j+1)!!."""
    return 2.0 * double_factorial_ratio(j + 1)


def sine_series(coefficients: np.ndarray, t) -> np.ndarray:
    """``sum_{n>=1} c_n sqrt(1-t^2) U_{n-1}(t) = sum c_n sin(n acos t)`` for |t| <= 1, 0 outside.

    ``coefficients[0]`` (the T_0 term) is ignored.
    """
    t = np.asarray(t, dtype=float)
    inside = np.abs(t) <= 1.0
    theta = np.arccos(np.clip(t, -1.0, 1.0))
    n = np.arange(1, coefficients.size)
    val = np.sin(theta[..., None] * n) @ coefficients[1:] if n.size else np.zeros_like(t)
    return np.where(inside, val, 0.0)


def outer_transform(coefficients: np.ndarray, t) -> np.ndarray:
    """``sum_{n>=1} c_n G_n(t)`` with ``G_n = T_n(t)`` inside and ``(t - sign(t) sqrt(t^2-1))^n`` outside:
    the finite Hilbert transform ``(1/pi) PV-int f(z)/(x - z) dz`` of the density of :func:`sine_series`."""
    t = np.asarray(t, dtype=float)
    c = coefficients.copy()
    c[0] = 0.0
    out = np.empty(t.shape)
    inside = np.abs(t) <= 1.0
    if inside.all():
        return npcheb.chebval(t, c)
    out[inside] = npcheb.chebval(t[inside], c)
    to = t[~inside]
    w = to - np.sign(to) * np.sqrt(to * to - 1.0)
    # w^n by cumulative products (np.power is far slower), |w| < 1 so no overflow
    powers = np.cumprod(np.broadcast_to(w[:, None], (w.size, c.size - 1)), axis=1)
    out[~inside] = powers @ c[1:]
    return out


def surface_height(surface, x: np.ndarray) -> np.ndarray:
    """``surface.height(x)`` for an array x by the same operations, so to the same bits, with the polynomial part by
    Horner's rule written out: ``numpy.polynomial.polynomial.polyval``'s argument handling per call costs several
    times its arithmetic on the few dozen points of :func:`rollcontact.line.methods.polynomial.validity.outside_gap`.

    Parameters
    ----------
    surface : rollcontact.Surface
        Z(X), here in axis coordinates (:meth:`SlopeExpansion.axis_surface`).
    x : ndarray
        Positions [m].

    Returns
    -------
    ndarray
        Z(x) [m].
    """
    coefficients = surface.polynomial
    if coefficients:
        z = coefficients[-1] + x * 0  # polyval's start, kept for the same signed zeros
        for c in coefficients[-2::-1]:
            z = c + z * x
    else:
        z = np.zeros_like(x)
    for h in surface.harmonics:
        z = z + h.cos_amplitude * np.cos(h.wavenumber * x) + h.sin_amplitude * np.sin(h.wavenumber * x)
    return z


def pressure_samples(c_n: np.ndarray) -> tuple[int, np.ndarray]:
    """``m`` and ``[p(theta_1) .. p(theta_(m-1)), dp/dtheta(0), dp/dtheta(pi)]``, ``theta_i = pi i/m``.

    ``m = max(64, 4 (order + 1))``: four samples per term; one product with the cached
    :func:`pressure_table`, shared by :func:`max_pressure` and the validity checks of
    :mod:`rollcontact.line.methods.polynomial.solver` and :mod:`rollcontact.line.methods.polynomial.patches`.
    """
    m = max(64, 4 * c_n.size)
    return m, pressure_table(m, c_n.size - 1)[0].dot(c_n[1:])


def max_pressure(c_n: np.ndarray, m: int, samples: np.ndarray) -> float:
    """max of ``p(theta) = sum c_n sin(n theta)``: the largest sample, then Newton on ``dp/dtheta = 0``.

    The first step uses the cached sine and derivative rows at the sample (``|theta - theta*| <= pi/2m``); each
    further one evaluates the series.  Once a step is below 1e-5 the value at that iterate is corrected by the
    step, ``p - p'^2/(2 p'')``, whose error is third order in the step (~1e-15 of p).
    """
    p = samples[:-2]
    i = int(p.argmax())
    best = float(p[i])
    c = c_n[1:]
    sines, cosines, _, n, n_squared = pressure_table(m, c.size)
    nnc = n_squared * c
    th = math.pi * (i + 1) / m
    value = best
    d2 = -float(sines[i].dot(nnc))
    d1 = float(cosines[i].dot(c))
    for _ in range(4):
        if d2 >= 0.0:
            break
        step = d1 / d2
        if abs(step) <= 1e-5:
            return max(best, value - 0.5 * d1 * step)
        th = min(max(th - step, 0.0), math.pi)
        ang = n * th
        sn = np.sin(ang)
        value = float(sn.dot(c))
        d2 = -float(sn.dot(nnc))
        d1 = float(np.cos(ang).dot(n * c))
    return max(best, value)

