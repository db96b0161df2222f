"""Normal contact of a patch by lateral strips (docs/physics-wheelrail-patches.md, "The strips' normal problem").

The patch gap ``g(x, s) = h(s) + A(s) x^2`` (:class:`~rollcontact.wheelrail.patch.PatchGap`) is cut into lateral
strips ``lower_j < s < upper_j``.  Each strip in contact carries the pressure of the paper's 2D normal problem (eqs
9-11: a 2D Hertz contact is a semi-ellipse), ``p = p0_j sqrt(1 - x^2/a_j^2)``, centred on x = 0 where the gap is even
in x.  Two conditions on each strip's centre line fix its two numbers, written ``e_j = p0_j a_j`` and
``q_j = p0_j / a_j`` (``a_j = sqrt(e_j / q_j)``):

* (I) interpenetration: the centre of the strip touches, ``u_z(0, s_i) = delta - h(s_i)``;
* (II) curvature: the deformed surface there has the gap's curvature along x, ``-(1/2) d^2u_z/dx^2 (0, s_i) =
  A(s_i)``,

with ``u_z`` the displacement of all the strips together on the 3D half-space
(:func:`~rollcontact.wheelrail.methods.strip_kernels.strip_matrices`): ``U e = delta - h`` and ``C q = A`` on the
strips in contact, ``e >= 0`` and ``U e >= delta - h`` (no interpenetration at the centre) on the others.  A strip
alone (an infinitely wide one) has ``q = E* A``, the 2D Hertz relation ``p0 = E* a / (2R)``; its neighbours make it
stiffer, by Hertz's ``p0 / (a E* A)`` (4/pi on a circle) on a quadratic gap.  On ``h = B s^2`` with constant A, Hertz's
pressure satisfies (I) and (II) exactly on every line ``x = 0``, so the strips converge to Hertz with their width.
``Fn = (pi/2) sum_j (upper_j - lower_j) e_j``.

Solution: a first pass on uniform strips over the rigid interpenetration ``h < delta`` (each ``a_j`` first the
half-length of the rigid interpenetration of ``(delta - h)/2``, a circle's ratio, then from (I) and (II) with the
half-lengths fixed) finds the strips in contact and hence the patch's lateral extent.  Strips spaced as
``cos(theta)`` over that extent (narrow towards its edges, where ``a`` falls like a square root) take the fixed point
on the half-lengths: with them fixed, (I) is a linear complementarity problem in e (active sets) and (II) a linear
system in q; ``a = sqrt(e/q)``, accelerated by Anderson's mixing, to :data:`PLACEMENT_TOLERANCE`.  The strips are
placed again over the converged contact (each edge extrapolated linearly to ``e = 0``, as the load per width vanishes
at a smooth edge) where it is cut at an end of them or leaves more than :data:`EXTENT_TOLERANCE` of them free; on the
placement kept Newton's method on (I) and (II) together finishes (:func:`_polish`).  For a given load the approach
follows from ``Fn`` with (I), which is linear in it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg.lapack import dgesv

from rollcontact.elliptic.hertz import hertz_ellipse
from rollcontact.wheelrail.methods.strip_kernels import StripGeometry
from rollcontact.wheelrail.patch import PatchGap

DEFAULT_STRIPS = 24
"""Strips across the patch's lateral extent."""

FIRST_STRIPS = 24
"""Uniform strips of the first pass over the rigid interpenetration."""

FIRST_ROUNDS = 2
"""Rounds of the first pass: the linear problems (I) and (II), then the half-lengths."""

FIRST_MARGIN = 0.5
"""Share of a first-pass strip by which the first placement widens the first pass's extent at each end."""

FIXED_POINT_TOLERANCE = 1e-6
"""The fixed point stops when no half-length changes by more than this share of the largest."""

PLACEMENT_TOLERANCE = 0.1
"""The fixed point of a placement stops at this (relative change of the half-lengths) to judge the placement; on the
placement kept Newton's method finishes (:func:`_polish`), or the fixed point goes on to :data:`POLISH_RETRIES` and
Newton tries again, and failing that the fixed point to :data:`FIXED_POINT_TOLERANCE`."""

POLISH_DROPS = 2
"""Times Newton's method may drop edge strips that a step would empty."""

POLISH_RETRIES = (1e-2, 1e-3)
"""Closer starts for Newton's method where it did not take."""

FIXED_POINT_ITERATIONS = 60
"""Cap of the fixed-point iterations of one placement."""

POLISH_ITERATIONS = 6
"""Cap of the Newton iterations that finish a placement's fixed point."""

NEWTON_CONTRACTION = 100.0
"""Bound K of Newton's quadratic convergence, ``c_{k+1} <= K c_k^2`` for the relative changes c of its steps near the
solution: Newton stops once ``K c^2`` is within :data:`FIXED_POINT_TOLERANCE` (its next step would be), a step
before the step itself is.  The largest ratio over the final steps of the patches of
``benchmarks/wheelrail_patches.py``, table "Newton", is a margin below it."""

ANDERSON = 3
"""Earlier iterates Anderson's mixing takes."""

SETTLING = 3
"""Iterations of a fixed point after which a strip that leaves the contact stays out."""

PLACEMENTS = 5
"""Cap of the placements of the strips over the lateral extent."""

EXTENT_TOLERANCE = 0.05
"""The strips are placed again where the converged contact is cut at an end of them or leaves more than this share
of their extent free at an end (with cosine spacing the narrowest one or two strips)."""

EXTENT_MARGIN = 0.01
"""A placement over the converged contact leaves this share of its width free at each end."""

REACH = 0.1
"""An edge of the contact moves outward by at most this share of the width from one placement to the next."""

LOAD_GUESSES = 12
"""Cap of the enlargements of the rigid interpenetration of the first pass for a given load."""


@dataclass(frozen=True)
class StripContact:
    """The strips' normal solution (SI units; module docstring).

    Attributes
    ----------
    centres, lower, upper : ndarray
        Lateral centre and edges of each strip [m] (s of the patch gap).
    half_lengths : ndarray
        a_j [m], 0 off contact.
    peak_pressures : ndarray
        p0_j [Pa], 0 off contact.
    lateral_gap, longitudinal_curvature : ndarray
        h(s_j) [m] and A(s_j) [1/m] at the centres.
    approach : float
        delta [m], the rigid interpenetration at the rigid contact point.
    normal_load : float
        Fn [N].
    converged : bool
    message : str
    iterations : int
        Fixed-point and Newton iterations over the placements.
    newton_steps : tuple of float
        The relative changes of Newton's steps on the placement kept (:func:`_polish`), in order.
    """

    centres: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    half_lengths: np.ndarray
    peak_pressures: np.ndarray
    lateral_gap: np.ndarray
    longitudinal_curvature: np.ndarray
    approach: float
    normal_load: float
    converged: bool
    message: str
    iterations: int
    newton_steps: tuple = ()

    @property
    def contact(self) -> np.ndarray:
        """Strips in contact (bool)."""
        return self.half_lengths > 0.0

    @property
    def widths(self) -> np.ndarray:
        """Strip widths [m]."""
        return self.upper - self.lower

    @property
    def loads_per_width(self) -> np.ndarray:
        """``(pi/2) p0_j a_j`` [N/m]."""
        return 0.5 * math.pi * self.peak_pressures * self.half_lengths

    @property
    def max_pressure(self) -> float:
        """The largest p0_j [Pa]."""
        return float(self.peak_pressures.max()) if self.peak_pressures.size else 0.0

    @property
    def length(self) -> float:
        """The patch's extent along x, ``2 max a_j`` [m]."""
        return 2.0 * float(self.half_lengths.max()) if self.half_lengths.size else 0.0

    @property
    def extent(self) -> tuple[float, float]:
        """The lateral edges of the contact [m]: each extrapolated linearly to zero load per width from the two
        outermost strips in contact (within the outermost strip)."""
        return contact_edges(self.centres, self.lower, self.upper, self.loads_per_width)

    @property
    def width(self) -> float:
        """The patch's extent across, between :attr:`extent`'s edges [m]."""
        low, high = self.extent
        return high - low


def check_gap(gap: PatchGap) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The gap's arrays as floats, checked: at least 3 samples, s strictly increasing, all finite, A > 0
    (ValueError naming the first violation)."""
    s, h, curvature = (np.asarray(v, dtype=float) for v in (gap.lateral, gap.lateral_gap, gap.longitudinal_curvature))
    if not (s.ndim == h.ndim == curvature.ndim == 1 and s.size == h.size == curvature.size):
        raise ValueError(f"the patch gap's arrays must be 1D of one length, got shapes {s.shape}, {h.shape}, "
                         f"{curvature.shape}")
    if s.size < 3:
        raise ValueError(f"the patch gap needs at least 3 samples, got {s.size}")
    for name, values in (("lateral", s), ("lateral_gap", h), ("longitudinal_curvature", curvature)):
        if not np.all(np.isfinite(values)):
            raise ValueError(f"the patch gap's {name} has a value that is not finite")
    if not np.all(np.diff(s) > 0.0):
        raise ValueError("the patch gap's lateral coordinates must increase strictly")
    if not np.all(curvature > 0.0):
        raise ValueError(f"the patch gap's longitudinal curvature must be > 0, its least is {curvature.min()!r} 1/m")
    return s, h, curvature


def contact_edges(centres, lower, upper, loads, reach: float = 0.0) -> tuple[float, float]:
    """The lateral edges [m] of the strips in contact (``loads > 0``), each extrapolated linearly to zero load per
    width from the outermost two strips in contact: outward beyond the outermost strip by at most twice the distance
    of the two centres or ``reach`` [m], the larger.  Where the outermost strip carries more than its inner
    neighbour the contact is cut there: the edge is ``reach`` beyond it (with ``reach`` > 0), else the strip's own
    edge, as for a strip without an inner neighbour in contact."""
    active = (loads > 0.0).nonzero()[0]
    if active.size == 0:
        return 0.0, 0.0
    first, last = active[0], active[-1]

    def edge(i, inner, towards):
        bound = towards[i]
        if inner is None:
            return bound
        spacing = centres[inner] - centres[i]  # > 0 at the lower edge, < 0 at the upper one
        limit = bound - math.copysign(max(2.0 * abs(spacing), reach), spacing)
        if loads[inner] <= loads[i]:  # the outermost strip carries more: the contact is cut there
            return limit if reach > 0.0 else bound
        crossing = centres[i] - loads[i] * spacing / (loads[inner] - loads[i])
        return min(max(crossing, limit), centres[i]) if spacing > 0.0 else max(min(crossing, limit), centres[i])

    low = edge(first, first + 1 if first + 1 <= last else None, lower)
    high = edge(last, last - 1 if last - 1 >= first else None, upper)
    return float(low), float(high)


def rigid_range(s, h, depth) -> tuple[float, float] | None:
    """``[lo, hi]`` [m], the hull of ``h(s) < depth`` with its ends interpolated between samples; None if empty or
    if it reaches an end of the samples (the contact may extend beyond the gap's sampling)."""
    inside = h < depth
    if not np.count_nonzero(inside) or inside[0] or inside[-1]:
        return None
    first = int(np.argmax(inside))
    last = h.size - 1 - int(np.argmax(inside[::-1]))
    lo = s[first - 1] + (s[first] - s[first - 1]) * (h[first - 1] - depth) / (h[first - 1] - h[first])
    hi = s[last] + (s[last + 1] - s[last]) * (depth - h[last]) / (h[last + 1] - h[last])
    return float(lo), float(hi)


def cosine_strips(lo: float, hi: float, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(centres, lower, upper)`` of ``count`` strips over ``[lo, hi]`` with edges at
    ``s = (lo + hi)/2 - (hi - lo)/2 cos(theta)``, theta uniform over [0, pi], centres at the middle thetas."""
    theta = np.linspace(0.0, math.pi, count + 1)
    middle, radius = 0.5 * (lo + hi), 0.5 * (hi - lo)
    edges = middle - radius * np.cos(theta)
    edges[0], edges[-1] = lo, hi
    centres = middle - radius * np.cos(0.5 * (theta[:-1] + theta[1:]))
    return centres, edges[:-1], edges[1:]


def uniform_strips(lo: float, hi: float, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(centres, lower, upper)`` of ``count`` equal strips over ``[lo, hi]``."""
    edges = np.linspace(lo, hi, count + 1)
    return 0.5 * (edges[:-1] + edges[1:]), edges[:-1], edges[1:]


class _Failure(Exception):
    """A pass that cannot go on: the message says why."""


def _solve(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """``matrix^-1 rhs`` by LAPACK's ``gesv`` (numpy.linalg's checks and wrappers cost more than the solve at these
    sizes); a singular matrix is a :class:`_Failure`."""
    _, _, x, info = dgesv(matrix, rhs)
    if info != 0:
        raise _Failure("the strips' influence matrix is singular")
    return x


def strip_normal(gap: PatchGap, contact_modulus: float, *, approach: float | None = None,
                 normal_load: float | None = None, strips: int = DEFAULT_STRIPS) -> StripContact:
    """The patch's normal contact by strips (module docstring), for a given approach or a given load.

    Parameters
    ----------
    gap : PatchGap
        The undeformed gap ``h(s) + A(s) x^2`` [m].
    contact_modulus : float
        E* [Pa] (:attr:`rollcontact.Material.contact_modulus`).
    approach : float, optional
        delta [m] >= 0, the rigid interpenetration at the rigid contact point (``h = 0``).
    normal_load : float, optional
        Fn [N] >= 0; exactly one of ``approach`` and ``normal_load``.
    strips : int
        Strips over the lateral extent (>= 4).

    Returns
    -------
    StripContact
        ``converged`` False with the reason in ``message`` where the passes did not converge or the contact reaches
        the end of the gap's sampling.
    """
    if (approach is None) == (normal_load is None):
        raise ValueError("give exactly one of approach and normal_load")
    if isinstance(strips, bool) or not isinstance(strips, (int, np.integer)) or strips < 4:
        raise ValueError(f"strips must be an integer >= 4, got {strips!r}")
    s, h, curvature = check_gap(gap)
    estar = float(contact_modulus)
    if approach is not None:
        approach = float(approach)
        if not (math.isfinite(approach) and approach >= 0.0):
            raise ValueError(f"approach = {approach!r} m must be finite and >= 0")
        if approach == 0.0 or not np.count_nonzero(h < approach):
            return _empty(approach, "no interpenetration: no contact")
    else:
        normal_load = float(normal_load)
        if not (math.isfinite(normal_load) and normal_load >= 0.0):
            raise ValueError(f"normal_load = {normal_load!r} N must be finite and >= 0")
        if normal_load == 0.0:
            return _empty(0.0, "no load: no contact")
    try:
        delta, extent, start = _first_pass(s, h, curvature, estar, approach, normal_load)
        return _placements(s, h, curvature, estar, approach, normal_load, delta, extent, start, int(strips))
    except _Failure as failure:
        return _empty(math.nan if approach is None else approach, str(failure), normal_load, converged=False)


def _empty(approach, message, load=0.0, converged=True) -> StripContact:
    none = np.zeros(0)
    return StripContact(none, none, none, none, none, none, none, approach, math.nan if not converged else load,
                        converged, message, 0)


def _first_guess(s, h, curvature, estar, normal_load) -> float:
    """An approach [m] to start the first pass of a given load: Hertz's for the curvatures at the gap's minimum
    (its lateral one from the samples, held within a factor 100 of A)."""
    k = int(np.argmin(h))
    k = min(max(k, 1), h.size - 2)
    slope_left = (h[k] - h[k - 1]) / (s[k] - s[k - 1])
    slope_right = (h[k + 1] - h[k]) / (s[k + 1] - s[k])
    lateral = (slope_right - slope_left) / (s[k + 1] - s[k - 1])
    longitudinal = float(curvature[k])
    lateral = min(max(lateral, 0.01 * longitudinal), 100.0 * longitudinal)
    return hertz_ellipse(normal_load, longitudinal, lateral, estar).approach


def _first_pass(s, h, curvature, estar, approach, normal_load):
    """Uniform strips over the rigid interpenetration: each ``a_j`` first the half-length of the rigid
    interpenetration of ``(delta - h)/2``, then :data:`FIRST_ROUNDS` times the load per width from the linear
    complementarity of (I), q from (II) on the strips in contact and ``a = sqrt(e/q)``.  Returns the approach, the
    lateral extent of the strips in contact and a start ``(centres, e, q)`` to interpolate."""
    depth = approach if approach is not None else _first_guess(s, h, curvature, estar, normal_load)
    for _ in range(LOAD_GUESSES):
        bounds = rigid_range(s, h, depth)
        if bounds is None:
            if approach is None and np.count_nonzero(h < depth):
                depth *= 0.7  # a guess too deep for the sampling: shallower first
                continue
            raise _Failure(f"the rigid interpenetration {depth:.4g} m reaches an end of the patch gap's sampling "
                           f"(s = {s[0]:.4g} .. {s[-1]:.4g} m): the contact may extend beyond it")
        centres, lower, upper = uniform_strips(*bounds, FIRST_STRIPS)
        gaps = np.interp(centres, s, h)
        curv = np.interp(centres, s, curvature)
        index = (gaps < depth).nonzero()[0]
        if index.size == 0:
            raise _Failure("the rigid interpenetration falls between the strips")
        gaps, curv, centres, lower, upper = gaps[index], curv[index], centres[index], lower[index], upper[index]
        half = np.sqrt((depth - gaps) / (2.0 * curv))
        widths = upper - lower
        active = depth - gaps > 0.5 * (depth - gaps.min())  # the circle's share of the rigid interpenetration
        q = np.zeros(index.size)
        geometry = StripGeometry(centres, lower, upper, estar)
        for _ in range(FIRST_ROUNDS):
            matrix, curving = geometry.matrices(half)
            delta, e, active = _complementarity(matrix, gaps, widths, approach, normal_load, active)
            sub = active.nonzero()[0]
            q = np.zeros(index.size)
            q[sub] = _solve(curving.take(sub, 0).take(sub, 1), curv[sub])
            positive = active & (q > 0.0)
            half = np.where(positive, np.sqrt(np.where(positive, e, 0.0) / np.where(positive, q, 1.0)), half)
        if approach is None and delta >= depth:  # the contact lies within h < delta: the range was too narrow
            depth = 1.5 * delta
            continue
        e = np.where(active, e, 0.0)
        q = np.where(active & (q > 0.0), q, 0.0)
        if not np.count_nonzero(q > 0.0):
            raise _Failure("the first pass found no strip of positive curvature ratio")
        low, high = contact_edges(centres, lower, upper, e)
        margin = FIRST_MARGIN * float(widths[0])  # the edges are known to a fraction of a strip of this pass
        return delta, (low - margin, high + margin), (centres, e, q)
    raise _Failure(f"no rigid interpenetration held the contact after {LOAD_GUESSES} enlargements")


def _complementarity(matrix, gaps, widths, approach, normal_load, active, allowed=None):
    """The linear complementarity of (I) with fixed half-lengths by active sets, from ``active``, only the strips
    ``allowed`` entering: returns the approach (given, or from the load), e and the strips in contact."""
    count = gaps.size
    if approach is None:
        sides = np.ones((count, 2))  # the load's two right-hand sides: delta's coefficient and the gaps
        sides[:, 1] = gaps
    for _ in range(2 * count):
        sub = active.nonzero()[0]
        block = matrix.take(sub, 0).take(sub, 1)  # (cheaper than indexing with two arrays)
        if approach is not None:
            delta = approach
            e_sub = _solve(block, delta - gaps[sub])
        else:
            both = _solve(block, sides[sub])
            unit, offset = widths[sub] @ both
            delta = (normal_load / (0.5 * math.pi) + offset) / unit
            e_sub = delta * both[:, 0] - both[:, 1]
        e = np.zeros(count)
        e[sub] = e_sub
        negative = e_sub < 0.0
        if np.count_nonzero(negative):
            active = active.copy()
            active[sub[negative]] = False
            if not np.count_nonzero(active):
                raise _Failure("the first pass lost every strip")
            continue
        shortfall = (delta - gaps) - matrix @ e
        penetrating = ~active & (shortfall > 1e-12 * delta)
        if allowed is not None:
            penetrating &= allowed
        if np.count_nonzero(penetrating):
            active = active | penetrating
            continue
        return delta, e, active
    raise _Failure("the first pass's active set did not settle")


def _placements(s, h, curvature, estar, approach, normal_load, delta, extent, start, count) -> StripContact:
    """Cosine-spaced strips over the extent, the fixed point on (I) and (II), placed again while the contact is cut at
    an end of them or leaves too much of them free (module docstring)."""
    iterations = 0
    newton_steps: tuple = ()
    prior_centres, prior_e, prior_q = start
    message = "converged"
    converged = False
    for _ in range(PLACEMENTS):
        lo, hi = extent
        if not hi > lo:
            raise _Failure("the contact's lateral extent collapsed")
        if rigid_range(s, h, delta) is None:
            raise _Failure(f"the rigid interpenetration {delta:.4g} m reaches an end of the patch gap's sampling "
                           f"(s = {s[0]:.4g} .. {s[-1]:.4g} m): the contact may extend beyond it")
        centres, lower, upper = cosine_strips(lo, hi, count)
        gaps = np.interp(centres, s, h)
        curv = np.interp(centres, s, curvature)
        e = np.maximum(np.interp(centres, prior_centres, prior_e, left=0.0, right=0.0), 0.0)
        if not np.count_nonzero(e > 0.0):
            e[np.argmin(gaps)] = max(prior_e.max(), 1.0)
        known = prior_q > 0.0
        q = np.interp(centres, prior_centres[known], prior_q[known] / np.interp(prior_centres[known], s, curvature)) \
            * curv  # q / A interpolated: the strips' stiffening
        active = e > 0.0
        e = np.where(active, e, 0.0)
        geometry = StripGeometry(centres, lower, upper, estar)
        delta, e, q, active, used = _fixed_point(centres, lower, upper, gaps, curv, geometry, approach, normal_load,
                                                 delta, e, q, active, PLACEMENT_TOLERANCE)
        iterations += used
        widths = upper - lower
        width = hi - lo
        low, high = contact_edges(centres, lower, upper, np.where(active, e, 0.0), REACH * width)
        prior_centres, prior_e, prior_q = centres, np.where(active, e, 0.0), np.where(active, q, 0.0)
        spare = EXTENT_MARGIN * (high - low)
        slack = EXTENT_MARGIN * width
        if -slack <= low - lo <= EXTENT_TOLERANCE * width and -slack <= hi - high <= EXTENT_TOLERANCE * width:
            for closer in (*POLISH_RETRIES, None):
                polished = _polish(centres, lower, upper, gaps, curv, geometry, approach, normal_load, delta, e, q,
                                   active)
                if polished is not None:
                    delta, e, q, used, active, newton_steps = polished
                    iterations += used
                    break
                # Newton did not take: the fixed point goes closer (to the end where Newton never takes)
                delta, e, q, active, used = _fixed_point(centres, lower, upper, gaps, curv, geometry, approach,
                                                         normal_load, delta, e, q, active,
                                                         FIXED_POINT_TOLERANCE if closer is None else closer)
                iterations += used
                if closer is None:
                    break
            converged = True
            break
        extent = (low - spare if low >= lo else low, high + spare if high <= hi else high)
    else:
        message = (f"the strips' lateral extent [{extent[0]:.4g}, {extent[1]:.4g}] m still moves after "
                   f"{PLACEMENTS} placements")
    half = np.where(active, np.sqrt(np.where(active, e, 0.0) / np.where(active, q, 1.0)), 0.0)
    peak = np.where(active, q * half, 0.0)
    load = 0.5 * math.pi * float(widths @ np.where(active, e, 0.0))
    return StripContact(centres, lower, upper, half, peak, gaps, curv, float(delta), load, converged, message,
                        iterations, newton_steps)


def _fixed_point(centres, lower, upper, gaps, curv, geometry, approach, normal_load, delta, e, q, active, tolerance):
    """Fixed-point iteration on the half-lengths: with them fixed, (I) is a linear complementarity problem in e
    (:func:`_complementarity`, the load's equation with it) and (II) a linear system in q on the strips in contact;
    then ``a = sqrt(e/q)``, accelerated by Anderson's mixing of the last :data:`ANDERSON` iterates in ``ln a`` (the
    strips off contact at a third of their nearest neighbour's, :func:`_spread`).  After :data:`SETTLING`
    iterations a strip that leaves the contact stays out (an edge strip may otherwise flip in and out with its
    half-length).  Stops when no a changes by more than ``tolerance`` of the largest.  Returns
    ``(delta, e, q, active, iterations)``."""
    widths = upper - lower
    count = centres.size
    sub = active.nonzero()[0]
    half = np.zeros(count)
    half[sub] = np.sqrt(e[sub] / q[sub])
    half = _spread(half)
    xs: list[np.ndarray] = []  # the last ANDERSON + 1 iterates ln a and their residuals
    fs: list[np.ndarray] = []
    barred = np.zeros(count, dtype=bool)
    allowed = np.ones(count, dtype=bool)
    for used in range(1, FIXED_POINT_ITERATIONS + 1):
        U, C = geometry.matrices(half)
        before = active
        delta, e, active = _complementarity(U, gaps, widths, approach, normal_load, active, allowed)
        sub = active.nonzero()[0]
        if used > SETTLING:
            barred |= before & ~active
            allowed = ~barred
        q_sub = _solve(C.take(sub, 0).take(sub, 1), curv[sub])
        if np.count_nonzero(q_sub > 0.0) < q_sub.size:
            raise _Failure("the strips' curvature condition gave a strip a negative pressure curvature")
        q = np.zeros(count)
        q[sub] = q_sub
        target = np.zeros(count)
        target[sub] = np.sqrt(e[sub] / q_sub)
        target = _spread(target)
        change = float(np.abs(target[sub] - half[sub]).max()) / float(target[sub].max())
        if change <= tolerance:
            return delta, e, q, active, used
        x = np.log(half)
        fx = np.log(target) - x
        xs.append(x)
        fs.append(fx)
        if len(xs) > ANDERSON + 1:
            del xs[0], fs[0]
        if len(xs) > 1:
            dx = np.diff(xs, axis=0).T
            df = np.diff(fs, axis=0).T
            gamma = np.linalg.lstsq(df, fx, rcond=None)[0]
            step = np.minimum(np.maximum(fx - (dx + df) @ gamma, -1.0), 1.0)  # at most a factor e per iteration
            half = np.zeros(count)
            half[sub] = np.exp(x[sub] + step[sub])
            half = _spread(half)
        else:
            half = target
    raise _Failure(f"the strips' half-lengths did not settle in {FIXED_POINT_ITERATIONS} iterations")


def _polish(centres, lower, upper, gaps, curv, geometry, approach, normal_load, delta, e, q, active):
    """Newton's method on (I) and (II) (and the load) with the strips in contact fixed, from a fixed point near the
    solution: ``(delta, e, q, iterations, active, steps)`` (steps: the relative changes of its steps) once no e or q
    changes by more than :data:`FIXED_POINT_TOLERANCE` of the largest, or its next step would not
    (:data:`NEWTON_CONTRACTION`); a step that would empty strips at the ends of runs in contact only drops them (at most
    :data:`POLISH_DROPS` times; Newton restarts on the strips kept, from the same iterate, whose matrices are the
    blocks of those already evaluated); None where a step would empty another strip, lose the curvature's sign or the
    residual grows (the fixed point then goes on), or after :data:`POLISH_ITERATIONS` on one set of strips.
    ``a = sqrt(e/q)`` enters U and C; ``a dU/da`` from the tables' t-derivatives
    (:class:`~rollcontact.wheelrail.methods.strip_kernels.StripGeometry`)."""
    index = active.nonzero()[0]
    ea, qa = e[index].copy(), q[index].copy()
    geometry = geometry.subset(index)
    given_load = approach is None
    evaluated = None  # the matrices at the current iterate, kept over a drop
    total = 0
    steps: list[float] = []
    for drops in range(POLISH_DROPS + 1):
        n = index.size
        widths = (upper - lower)[index]
        targets = gaps[index]
        curvatures = curv[index]
        e_scale, q_scale = float(ea.max()), float(qa.mean())
        size = 2 * n + given_load
        previous = math.inf
        restart = False
        for used in range(1, POLISH_ITERATIONS + 1):
            if evaluated is None:
                U, C, dU, dC = geometry.matrices(np.sqrt(ea / qa), derivative=True)
            else:
                U, C, dU, dC = evaluated
                evaluated = None
            residual = np.empty(size)
            residual[:n] = (U @ ea - (delta - targets)) / delta
            residual[n:2 * n] = C @ qa / curvatures - 1.0
            jacobian = np.zeros((size, size))
            # a = sqrt(e/q): a d/da enters d/de with 1/(2e) and d/dq with -1/(2q)
            jacobian[:n, :n] = (U + 0.5 * dU) * (e_scale / delta)
            jacobian[:n, n:2 * n] = dU * (-0.5 * q_scale / delta * ea / qa)
            jacobian[n:2 * n, :n] = dC * (0.5 * e_scale * qa / ea) / curvatures[:, None]
            jacobian[n:2 * n, n:2 * n] = (C - 0.5 * dC) * (q_scale / curvatures[:, None])
            if given_load:
                jacobian[:n, 2 * n] = -1.0
                jacobian[2 * n, :n] = 0.5 * math.pi * widths * e_scale / normal_load
                residual[2 * n] = 0.5 * math.pi * float(widths @ ea) / normal_load - 1.0
            norm = float(np.abs(residual).max())
            if norm > previous:
                return None
            previous = norm
            step = _solve(jacobian, -residual)
            de, dq = step[:n] * e_scale, step[n:2 * n] * q_scale
            emptied = ea + de <= 0.0
            if np.count_nonzero(emptied):
                if drops == POLISH_DROPS:
                    return None
                ends = np.zeros(n, dtype=bool)
                ends[[0, -1]] = True
                steps_apart = index[1:] - index[:-1]
                ends[1:-1] = (steps_apart[1:] > 1) | (steps_apart[:-1] > 1)
                if np.count_nonzero(ends[emptied]) < np.count_nonzero(emptied):
                    return None
                # the contact ends before these edge strips: they leave, Newton restarts on the others
                kept = (~emptied).nonzero()[0]
                index, ea, qa = index[kept], ea[kept], qa[kept]
                evaluated = tuple(m.take(kept, 0).take(kept, 1) for m in (U, C, dU, dC))
                geometry = geometry.subset(kept)
                total += used
                restart = True
                break
            if np.count_nonzero(qa + dq <= 0.0):
                return None
            ea, qa = ea + de, qa + dq
            if given_load:
                delta *= 1.0 + float(step[2 * n])
            change = max(float(np.abs(de).max()) / float(ea.max()), float(np.abs(dq).max()) / float(qa.max()))
            steps.append(change)
            if change <= FIXED_POINT_TOLERANCE or NEWTON_CONTRACTION * change * change <= FIXED_POINT_TOLERANCE:
                e, q = np.zeros(centres.size), np.zeros(centres.size)
                e[index], q[index] = ea, qa
                kept = np.zeros(centres.size, dtype=bool)
                kept[index] = True
                return delta, e, q, total + used, kept, tuple(steps)
        if not restart:
            return None
    return None


def _spread(half):
    """The half-lengths of the strips in contact (``half > 0``), and for the others a third of those of the strips in
    contact interpolated by index (the nearest one's beyond the ends): the length a strip entering the contact starts
    with."""
    inside = (half > 0.0).nonzero()[0]
    if inside.size == half.size:
        return half
    spread = np.interp(np.arange(half.size), inside, half[inside]) / 3.0
    spread[inside] = half[inside]
    return spread


def refined(contact: StripContact, gap: PatchGap, count: int) -> StripContact:
    """The normal solution carried over to ``count`` cosine-spaced strips over the same lateral range: e = p0 a
    interpolated linearly between the strips in contact and each run's extrapolated edges (where it vanishes), q/A
    likewise between the strips in contact (constant beyond), e scaled so that the strips carry the same load.  The
    tangential strips take it where they are more than the normal ones."""
    if contact.centres.size == 0 or count == contact.centres.size:
        return contact
    s, h, curvature = check_gap(gap)
    active = contact.contact
    e = contact.peak_pressures * contact.half_lengths
    nodes, values = [], []
    breaks = np.flatnonzero(np.diff(np.flatnonzero(active)) > 1) + 1
    for run in np.split(np.flatnonzero(active), breaks):
        low, high = contact_edges(contact.centres[run], contact.lower[run], contact.upper[run], e[run])
        nodes += [low, *contact.centres[run], high]
        values += [0.0, *e[run], 0.0]
    nodes, values = np.array(nodes), np.array(values)
    centres, lower, upper = cosine_strips(float(contact.lower[0]), float(contact.upper[-1]), count)
    load = np.interp(centres, nodes, values, left=0.0, right=0.0)
    curv = np.interp(centres, s, curvature)
    ratio = contact.peak_pressures[active] / contact.half_lengths[active] / contact.longitudinal_curvature[active]
    q = np.interp(centres, contact.centres[active], ratio) * curv
    load *= contact.normal_load / (0.5 * math.pi * float((upper - lower) @ load))
    half = np.sqrt(load / q)
    return StripContact(centres, lower, upper, half, q * half, np.interp(centres, s, h), curv, contact.approach,
                        contact.normal_load, contact.converged, contact.message, contact.iterations,
                        contact.newton_steps)
