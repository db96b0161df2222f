"""Steady rolling with velocity-dependent friction by the polynomial method (paper section 4.2).

Structure (as the paper's, physics.md section 5): one stick zone at the leading edge, slip behind it.  The
traction is ``q = q1 + q2`` with ``q1 = mu(V s(x)) p(x)`` over the whole patch (``mu_s p`` in the stick zone,
where s = 0) and ``q2`` a bounded correction on the stick zone that cancels the slip there.

Iteration: guess s(x) (Carter), evaluate ``mu(V s)`` at the patch's Chebyshev nodes and expand ``q1`` as a sine
series (``q1 = sum e_n sin(n theta)``, a DST of the nodal values: the Chebyshev fit of the paper); its
displacement gradient is ``H1 = (2/E*) sum e_n T_n(t)``.  On the stick zone ``X = Xs + a* sigma`` the
Chebyshev coefficients ``F_n`` of ``H1`` give the creep ``xi = -F_0(a*)`` (solved for a* in creep control) and
``q2 = -(E*/2) sum_{n>=1} F_n sin(n phi)``; the new slip is ``s = xi + H1 - sum F_n w^n``,
``w = sigma - sqrt(sigma^2 - 1)``, behind the stick zone.  Repeat until s settles (under-relaxed when the
iteration oscillates).  With dmu/dv < 0 the creep curve has a maximum and q a spike at the stick/slip boundary.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import fft, optimize

from rollcontact.chebyshev import sine_series
from rollcontact.result import Distributions

__all__ = ["VelocityFrictionDistributions", "solve_velocity_dependent"]


def dst_coefficients(values: np.ndarray) -> np.ndarray:
    """Sine coefficients ``e_1..e_M`` with ``values_j = sum e_n sin(n theta_j)``, theta_j = pi (j + 1/2)/M."""
    m = values.size
    e = fft.dst(values, type=2) / m
    e[-1] *= 0.5
    return np.concatenate(([0.0], e))


def cheb_coefficients(values: np.ndarray) -> np.ndarray:
    """Chebyshev coefficients ``F_0..F_{K-1}`` interpolating values at sigma_k = cos(pi (k + 1/2)/K)."""
    k = values.size
    f = fft.dct(values, type=2) / k
    f[0] *= 0.5
    return f


@dataclass(frozen=True)
class VelocityFrictionDistributions(Distributions):
    """Fields of a velocity-dependent solution (x [m] from the axis projection)."""

    half_width: float
    offset: float
    pressure_coefficients: np.ndarray
    q1_coefficients: np.ndarray  # e_n, sine series of mu(V s) p on the patch
    stick_half_width: float
    stick_offset: float
    stick_coefficients: np.ndarray  # F_n, Chebyshev coefficients of H1 on the stick zone
    contact_modulus: float
    creep: float

    def pressure(self, x):
        return sine_series(self.pressure_coefficients, (np.asarray(x, dtype=float) - self.offset) / self.half_width)

    def traction(self, x):
        x = np.asarray(x, dtype=float)
        q = sine_series(self.q1_coefficients, (x - self.offset) / self.half_width)
        if self.stick_half_width > 0.0:
            sigma = (x - self.stick_offset) / self.stick_half_width
            q = q - 0.5 * self.contact_modulus * sine_series(self.stick_coefficients, sigma)
        return math.copysign(1.0, self.creep) * q

    def slip(self, x):
        x = np.asarray(x, dtype=float)
        t = (x - self.offset) / self.half_width
        s = abs(self.creep) + gradient_q1(self.q1_coefficients, t, self.contact_modulus)
        if self.stick_half_width > 0.0:
            sigma = (x - self.stick_offset) / self.stick_half_width
            s = np.where(sigma <= 1.0, 0.0, s - outer_powers(self.stick_coefficients, sigma))
        return np.where(np.abs(t) <= 1.0, math.copysign(1.0, self.creep) * s, np.nan)


def gradient_q1(e: np.ndarray, t, estar: float):
    """``H1 = (2/E*) sum e_n T_n(t)`` for |t| <= 1."""
    t = np.clip(np.asarray(t, dtype=float), -1.0, 1.0)
    return (2.0 / estar) * np.polynomial.chebyshev.chebval(t, np.concatenate(([0.0], e[1:])))


def outer_powers(f: np.ndarray, sigma) -> np.ndarray:
    """``sum_{n>=1} F_n w^n``, ``w = sigma - sqrt(sigma^2 - 1)`` for sigma > 1 (0 elsewhere)."""
    sigma = np.asarray(sigma, dtype=float)
    w = np.where(sigma > 1.0, sigma - np.sqrt(np.clip(sigma * sigma - 1.0, 0.0, None)), 0.0)
    powers = np.cumprod(np.broadcast_to(w[..., None], (*w.shape, f.size - 1)), axis=-1)
    return powers @ f[1:]


def solve_velocity_dependent(pressure_coefficients: np.ndarray, a: float, offset: float, estar: float, friction,
                             rolling_speed: float, creep: float, *, nodes: int = 192, tolerance: float = 1e-9,
                             max_iterations: int = 200):
    """Creep-controlled steady rolling with ``mu = friction.coefficient(V |s|)`` (paper section 4.2).

    Parameters
    ----------
    pressure_coefficients : ndarray
        Sine coefficients c_n [Pa] of p on the patch (from the normal problem).
    a, offset : float
        Patch half-width and centre [m] (x from the axis projection).
    estar : float
        Contact modulus E* [Pa].
    friction : FrictionLaw
        mu(v), v [m/s].
    rolling_speed : float
        V [m/s] > 0.
    creep : float
        xi [1].
    nodes : int
        Chebyshev nodes on the patch (and on the stick zone) for the fit of mu(V s) p.
    tolerance : float
        Convergence of the slip field, relative to mu_s a / R-like scale max|s|.
    max_iterations : int
        Fixed-point iterations.

    Returns
    -------
    dict
        ``stick_half_width``, ``tangential_force_per_length``, ``distributions``, ``iterations``, ``converged``,
        ``message``, ``history`` (max change of s per iteration).
    """
    sign = math.copysign(1.0, creep)
    xi = abs(creep)
    m = nodes
    theta = np.pi * (np.arange(m) + 0.5) / m
    t = np.cos(theta)
    p = np.sin(np.multiply.outer(theta, np.arange(1, pressure_coefficients.size))) @ pressure_coefficients[1:]
    p = np.clip(p, 0.0, None)
    mu_s = float(friction.static_coefficient)
    k_nodes = m
    phi = np.pi * (np.arange(k_nodes) + 0.5) / k_nodes
    sigma_nodes = np.cos(phi)
    n_idx = np.arange(1, m + 1)

    def stick_coefficients(e, h):
        """F_n of H1 on the stick zone [-1, -1 + 2h/a] (in t)."""
        ts = -1.0 + (h / a) * (1.0 + sigma_nodes)
        h1 = (2.0 / estar) * (np.cos(np.multiply.outer(np.arccos(np.clip(ts, -1, 1)), n_idx)) @ e[1:])
        return cheb_coefficients(h1)

    # start from Coulomb with mu_s (Carter-like): s = 0 everywhere gives q1 = mu_s p
    s = np.zeros(m)
    history = []
    omega = 1.0
    h = a
    e = None
    f_coef = None
    converged = False
    message = ""
    last_change = math.inf
    it = 0
    while it < max_iterations:
        it += 1
        mu_nodes = friction.coefficient(rolling_speed * s)
        e = dst_coefficients(mu_nodes * p)
        h1_patch = (2.0 / estar) * (np.cos(np.multiply.outer(theta, n_idx)) @ e[1:])

        def residual(hh, e=e):
            return -stick_coefficients(e, hh)[0] - xi

        lo = a * 1e-9
        r_lo, r_hi = residual(lo), residual(a)
        if r_lo <= 0.0:
            h = 0.0
            f_coef = np.zeros(2)
            s_new = xi + h1_patch
        else:
            if r_hi >= 0.0:
                h = a
            else:
                h = optimize.brentq(residual, lo, a, xtol=1e-15 * a, rtol=1e-14)
            f_coef = stick_coefficients(e, h)
            sigma = (t + 1.0) * a / h - 1.0
            s_new = np.where(sigma <= 1.0, 0.0, xi + h1_patch - outer_powers(f_coef, sigma))
        scale = max(float(np.max(np.abs(s_new))), xi, 1e-300)
        change = float(np.max(np.abs(s_new - s))) / scale
        history.append(change)
        if change > last_change:
            omega = max(0.05, 0.5 * omega)
        last_change = change
        s = s + omega * (s_new - s)
        if change <= tolerance:
            converged = True
            s = s_new
            break
    if not converged:
        message = (f"velocity-dependent friction: the slip iteration did not converge in {max_iterations} "
                   f"iterations (last relative change {history[-1]:.3g})")
    # final consistent fields from the last slip field
    mu_nodes = friction.coefficient(rolling_speed * np.clip(s, 0.0, None))
    e = dst_coefficients(mu_nodes * p)
    t_force = 0.5 * math.pi * a * e[1] - (0.5 * math.pi * h * 0.5 * estar * f_coef[1] if h > 0.0 else 0.0)
    dist = VelocityFrictionDistributions(a, offset, pressure_coefficients, e, h, offset - a + h,
                                         f_coef if h > 0.0 else np.zeros(2), estar, creep)
    failures = []
    if np.any(s < -tolerance * max(xi, 1e-300) * 10):
        failures.append("slip opposes the traction in the slip zone (a second stick zone)")
    if h > 0.0:
        q2 = -0.5 * estar * (np.sin(np.multiply.outer(phi, np.arange(1, f_coef.size))) @ f_coef[1:])
        ps = dist.pressure(offset - a + h + h * sigma_nodes)
        pmax = float(np.max(p))
        if np.any(q2 > 1e-6 * mu_s * pmax) or np.any(q2 < -2.0 * mu_s * ps - 1e-6 * mu_s * pmax):
            failures.append("traction bound |q| <= mu_s p violated in the stick zone")
    if failures:
        message = "; ".join(([message] if message else []) + failures)
    return {
        "stick_half_width": h,
        "tangential_force_per_length": sign * t_force,
        "distributions": dist,
        "iterations": it,
        "converged": converged and not failures,
        "message": message,
        "history": history,
    }
