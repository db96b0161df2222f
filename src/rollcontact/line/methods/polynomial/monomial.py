"""The paper's monomial formulation of the polynomial method (eqs 19-26), kept to measure its conditioning.

:func:`monomial_matrix` is the matrix of eq 21 and :func:`monomial_density` the pressure coefficients ``B_n`` it
gives; the solver uses them with ``basis="monomial"`` (:data:`BASES`).  Their conditioning degrades as a^(2n), which
is why the solver's default is the stable Chebyshev basis (:mod:`rollcontact.line.methods.polynomial.chebyshev`).  Note
eq 26 needs ``A_n^-1 = +(1/pi) a^(2n-2)/(2n-3) prod...`` for n >= 2: the printed minus sign is wrong.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import linalg

BASES = ("chebyshev", "monomial")


# ---------------------------------------------------------------------------------------------------------------
# monomial backend (paper eqs 19-26)
def monomial_matrix(h: float, order: int) -> np.ndarray:
    """The paper's matrix of eq 21: ``beta_k = sum_n A_n B_{k+2n-1}``, ``A_n = -pi h^(2n-2) prod (2i-3)/(2i-2)``
    (eqs 22-23, verified: the PV integral of ``zeta^m / ((x-zeta) sqrt(h^2-zeta^2))`` is
    ``-pi sum_{j even} h^j (j-1)!!/j!! x^(m-1-j)``)."""
    coef = np.empty(order)
    coef[0] = -math.pi
    prod = 1.0
    for n in range(2, order + 1):
        prod *= (2 * n - 3) / (2 * n - 2)
        coef[n - 1] = -math.pi * h ** (2 * n - 2) * prod
    m = np.zeros((order, order))
    for k in range(order):
        for n in range(1, order + 1):
            j = k + 2 * n - 1  # index of B_j, column j-1
            if j <= order:
                m[k, j - 1] = coef[n - 1]
    return m


def monomial_density(taylor: np.ndarray, h: float):
    """Solve ``(1/pi) PV-int f(z)/(x - z) dz = sum_k e_k x^k`` on |x| < h in the paper's monomial form.

    ``f = B(x)/sqrt(h^2 - x^2)`` with ``B(+h) = 0``.  Returns ``(B, r0, r1, cancellation)``: the power
    coefficients of B, the T0 and T1 Chebyshev coefficients of the right-hand side recovered from B
    (``r0 = -(1/h) sum_odd B_n h^n``, ``r1 = (2/(pi h)) int f - 2 r0``), and the cancellation factor
    ``sum |B_n| h^n / max |B(x)|`` (|x| <= h): how much round-off the power basis amplifies.  The triangular
    matrix itself stays well conditioned (its diagonal is -pi); the precision is lost in the power-basis sums,
    whose terms grow like (k h)^n / n! for harmonics and whose coefficients scale like h^(-n).
    """
    order = taylor.size
    m = monomial_matrix(h, order)
    with np.errstate(all="ignore"):
        b_tail = linalg.solve_triangular(m, math.pi * taylor, check_finite=False)
        powers = h ** np.arange(1, order + 1)
        b0 = -np.dot(b_tail, powers)
        b = np.concatenate(([b0], b_tail))
        odd = b[1::2] @ powers[0::2]
        r0 = -odd / h
        even_idx = np.arange(0, order + 1, 2)
        weights = np.array([math.pi * h**n * dfr(n) for n in even_idx])
        integral = b[0::2] @ weights
        r1 = 2.0 * integral / (math.pi * h) - 2.0 * r0
        xs = h * np.cos(np.pi * np.arange(33) / 32)
        peak = float(np.max(np.abs(np.polynomial.polynomial.polyval(xs, b))))
        cancellation = float(np.sum(np.abs(b) * h ** np.arange(order + 1))) / peak if peak > 0 else math.inf
    return b, r0, r1, cancellation if math.isfinite(cancellation) else math.inf


def dfr(n: int) -> float:
    r = 1.0
    for i in range(2, n + 1, 2):
        r *= (i - 1) / i
    return r
