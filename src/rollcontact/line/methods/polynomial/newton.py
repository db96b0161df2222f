"""A quasi-Newton iteration with a difference Jacobian and step limits, for the small nonlinear systems of several
patches (their edges, their stick zones): unknowns that may leave the problem raise :class:`Leaving`."""

from __future__ import annotations

import numpy as np
from scipy.linalg import lapack

NEWTON_ITERATIONS = 40
"""Newton steps (or Jacobian refreshes) of one iteration on the edges or on the zones."""

MAX_EVALUATIONS = 60
"""Evaluations of the residuals (Jacobian columns included) per Newton iteration on the edges or the zones: a
margin over what converging cases need, so that a stalled iteration ends."""



class Leaving(Exception):
    """Raised by a step limit of :func:`quasi_newton` when unknown ``index`` leaves the problem (a patch that slips
    throughout)."""

    def __init__(self, index: int):
        super().__init__(index)
        self.index = index


def difference_jacobian(function, x: np.ndarray, f: np.ndarray, step: float) -> np.ndarray:
    """Forward differences of the residuals of ``function`` at ``x`` (``f``: its residuals there) with the step
    ``step`` (``function(x) -> (residuals, extras)``)."""
    jac = np.empty((f.size, x.size))
    for i in range(x.size):
        shifted = x.copy()
        shifted[i] += step
        jac[:, i] = (function(shifted)[0] - f) / step
    return jac


def quasi_newton(function, x: np.ndarray, step: float, limit, tiny: float, accept: float = 1e-13):
    """Solve ``residuals(x) = 0`` (scaled to order one) by Newton steps on a difference Jacobian kept up to date
    by Broyden's update, refreshed when a step fails to reduce the residual.

    ``function(x)`` returns ``(residuals, extras)``: what the evaluation computed on the way, handed back for the
    solution so that it need not be evaluated again.  ``limit(x, dx)`` returns the step to take (it may shorten
    it, or raise :class:`Leaving`).  Ends at residuals below ``accept`` (by default of round-off size) or after
    a full step below ``tiny``.  Returns ``(x, f, extras, evaluations, failure)``; a singular Jacobian, non-finite
    residuals and more than :data:`MAX_EVALUATIONS` evaluations are failures.
    """
    f, extras = function(x)
    evaluations = 1
    jac = None
    fresh = False
    for _ in range(NEWTON_ITERATIONS):
        if evaluations > MAX_EVALUATIONS:
            break
        if not np.isfinite(f).all():
            return x, f, extras, evaluations, f"non-finite residuals at {x.tolist()}"
        if float(np.abs(f).max()) <= accept:
            return x, f, extras, evaluations, ""
        if jac is None:
            jac = difference_jacobian(function, x, f, step)
            evaluations += x.size
            fresh = True
        _, _, dx, info = lapack.dgesv(jac, -f)
        if info != 0:
            return x, f, extras, evaluations, "singular Jacobian"
        limited = limit(x, dx)
        trial, trial_extras = function(x + limited)
        evaluations += 1
        if not (np.isfinite(trial).all() and (fresh or np.linalg.norm(trial) < np.linalg.norm(f))):
            if fresh:
                return x, f, extras, evaluations, f"non-finite residuals at {(x + limited).tolist()}"
            jac = None  # the secant model has gone stale: difference again at x
            continue
        length = float(limited @ limited)
        if length == 0.0:  # a step below the resolution of x: nothing left to gain
            return x, f, extras, evaluations, ""
        jac += np.outer(trial - f - jac @ limited, limited) / length
        fresh = False
        x, f, extras = x + limited, trial, trial_extras
        if limited is dx and float(np.abs(dx).max()) <= tiny:
            return x, f, extras, evaluations, ""
    return x, f, extras, evaluations, (f"no convergence in {evaluations} evaluations (largest residual "
                                       f"{float(np.abs(f).max()):.3g})")
