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

The strips of each lobe of the contact (a run of strips in contact) are spaced as ``cos(theta)`` over exactly its
lateral extent ``[M - R, M + R]`` (narrow towards its edges, where ``a`` falls like a square root), all in contact,
and the extent is an unknown of the problem with them: at a smooth edge the load per width vanishes linearly, so each
edge is where e extrapolated linearly from the lobe's two outermost strips vanishes, ``e_1 = kappa e_2`` with
``kappa = (1 - cos(pi/2n)) / (1 - cos(3 pi/2n))`` for n strips (and likewise at the upper edge).  No strip enters or
leaves the contact as the approach changes, and the strips move with the edges: the solution and Fn are smooth
functions of the approach wherever the lobes do not change (a strip that enters the contact at a fixed place takes
a finite half-length at once, through (II), and Fn a step).  h and A are interpolated between the gap's samples by
monotone cubics (:class:`_SampledGap`) so that they are smooth as the strips move.

Solution: a first pass on uniform strips over the rigid interpenetration ``h < delta`` (each ``a_j`` first the
half-length of the rigid interpenetration of ``(delta - h)/2``, a circle's ratio, then from (I) and (II) with the
half-lengths fixed) finds the runs of strips in contact, the first lobes.  Cosine-spaced strips over each take the
fixed point on the half-lengths: with them fixed, (I) is a linear complementarity problem in e (active sets) and
(II) a linear system in q; ``a = sqrt(e/q)``, accelerated by Anderson's mixing, to :data:`PLACEMENT_TOLERANCE`.  The
lobes are laid again over its runs of strips in contact (their edges extrapolated to ``e = 0``) and Newton's method on
(I), (II) and the edge conditions for e, q and every lobe's M and R finishes (:func:`_polish`).  Where the surfaces then
interpenetrate outside the lobes at a sample of the gap, a lobe joins there and the passes go on
(:func:`_penetrating`).  From a nearby solution (``start``) Newton's method alone finishes (:func:`_resumed`); without
one, Newton's method first starts from Hertz's ellipse at the gap's deepest sample laid over the deepest part of the
one or two runs of the rigid interpenetration at its approach (:func:`_hertzian`), then from the first pass's lobes
(:func:`_from_first_pass`), and the fixed point runs where neither takes.  Where Newton's method takes from Hertz's
ellipse but the surfaces then interpenetrate outside its lobes, the placements go on from its solution with a lobe
joined there (:func:`_newton_alone`).  For a given load the approach follows from
``Fn`` with (I), which is linear in it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
from scipy.linalg.lapack import dgesv

from rollcontact.elliptic.hertz import hertz_ellipse
from rollcontact.wheelrail.methods.strip_kernels import StripGeometry
from rollcontact.wheelrail.patch import PatchGap

DEFAULT_STRIPS = 24
"""Strips across each lobe."""

FIRST_STRIPS = 24
"""Uniform strips of the first pass over the rigid interpenetration."""

FIRST_ROUNDS = 2
"""Rounds of the first pass: the linear problems (I) and (II), then the half-lengths."""

FIRST_MARGIN = 0.5
"""Share of a first-pass strip by which the first lobes widen the first pass's runs at each end."""

FIXED_POINT_TOLERANCE = 1e-6
"""Newton's method stops when no e, q or edge changes by more than this share of the largest (:func:`_polish`), the
fixed point when no half-length does."""

PLACEMENT_TOLERANCE = 0.1
"""The fixed point on the first lobes stops at this (relative change of the half-lengths) to lay the lobes again for
Newton's method; where Newton does not take, the fixed point on the lobes laid again goes on to
:data:`POLISH_RETRIES` and Newton tries again, and failing that the fixed point to :data:`FIXED_POINT_TOLERANCE` (on
strips then not placed on the edges)."""

POLISH_RETRIES = (1e-2, 1e-3)
"""Closer starts for Newton's method where it did not take."""

FIXED_POINT_ITERATIONS = 60
"""Cap of the fixed-point iterations of one placement."""

POLISH_ITERATIONS = 8
"""Cap of Newton's iterations."""

GROWTH = 4.0
"""Newton's method gives up where the largest residual grows by more than this factor in a step."""

BOUNDARY = 0.8
"""A Newton step that would empty a strip or flip a curvature is cut to this share of the way to zero."""

LEAST_FRACTION = 0.1
"""Newton's method gives up where a step is cut to less than this share."""

PENETRATION = 1e-4
"""Interpenetration [1] of the deformed surfaces outside the lobes, relative to the approach, at a sample of the gap
that makes a lobe of it (:func:`_penetrating`); the solutions of the Manchester patches leave at least 2e-5 of the
approach free outside their lobes."""

NEWTON_CONTRACTION = 100.0
"""Bound K of Newton's quadratic convergence, ``c_{k+1} <= K c_k^2`` for the relative changes c of its steps near the
solution: Newton stops once ``K c^2`` is within :data:`FIXED_POINT_TOLERANCE` (its next step would be), a step
before the step itself is.  The largest ratio over the final steps of the patches of
``benchmarks/wheelrail_patches.py``, table "Newton", is a margin below it."""

ANDERSON = 3
"""Earlier iterates Anderson's mixing takes."""

SETTLING = 3
"""Iterations of a fixed point after which a strip that leaves the contact stays out."""

REACH = 0.1
"""Where the contact is cut at an end of a lobe's strips, the lobe laid again reaches out by at most this share of
its width."""

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
        The relative changes of Newton's steps (:func:`_polish`), in order.
    lobes : tuple of (float, float)
        The lateral edges [m] of each lobe, over which its strips are placed (consecutive in the arrays, a strip out
        of contact between lobes); empty where there are none.
    start : str
        How the solution was reached (module docstring): ``"resumed"`` (Newton's method from a given start),
        ``"hertz"`` (from Hertz's ellipse), ``"hertz, lobe joined"`` (the placements went on from that solution with
        a lobe joined), ``"first pass"`` (from the first pass's lobes), ``"placements"`` (the placements' fixed point
        and Newton's method), ``"fixed point"`` (the fixed point alone); a given start returned as it is keeps its
        own; empty without contact.
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
    lobes: tuple = ()
    start: str = ""

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

    def pressure_on(self, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        """The pressure [Pa] at the points ``(x, s)`` [m]: each strip's semi-ellipse ``p0 sqrt(1 - x^2/a^2)``, with
        ``a`` and ``p0`` linear in s between the strips' centres and 0 beyond the outer ones."""
        half = np.interp(s, self.centres, self.half_lengths, left=0.0, right=0.0)
        peak = np.interp(s, self.centres, self.peak_pressures, left=0.0, right=0.0)
        inside = half > np.abs(x)
        ratio = np.where(inside, x / np.where(inside, half, 1.0), 1.0)
        return np.where(inside, peak * np.sqrt(1.0 - ratio * ratio), 0.0)


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
    runs = rigid_runs(s, h, depth)
    return (runs[0][0], runs[-1][1]) if runs else None


def rigid_runs(s, h, depth) -> list[tuple[float, float, float]]:
    """``(lo, hi, least h)`` [m] of each run of ``h(s) < depth``, its ends interpolated between samples; empty where
    there is none or where one reaches an end of the samples."""
    inside = h < depth
    if not np.count_nonzero(inside) or inside[0] or inside[-1]:
        return []
    ends = np.flatnonzero(inside[1:] != inside[:-1])  # the sample before each crossing
    out = []
    for before, last in zip(ends[::2].tolist(), ends[1::2].tolist(), strict=True):
        first = before + 1
        lo = s[first - 1] + (s[first] - s[first - 1]) * (h[first - 1] - depth) / (h[first - 1] - h[first])
        hi = s[last] + (s[last + 1] - s[last]) * (depth - h[last]) / (h[last + 1] - h[last])
        out.append((float(lo), float(hi), float(h[first:last + 1].min())))
    return out


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


@dataclass(frozen=True)
class Nearby:
    """A strips normal solution of a nearby gap (the same patch at a pose a little away) as the start of
    :func:`strip_normal`: Newton's method starts from it, but at its own approach or load it is not the solution."""

    contact: StripContact


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
                 normal_load: float | None = None, strips: int = DEFAULT_STRIPS,
                 start: StripContact | Nearby | None = None) -> StripContact:
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
        Strips over each lobe (>= 4).
    start : StripContact or Nearby, optional
        A solution of the same gap with as many strips for Newton's method to start from, its lobes and loads
        scaled as Hertz's (:func:`_resumed`); where it does not take, the passes start afresh.  At its own approach
        (or load), to the tolerance it is solved to, it is returned as it is.  A :class:`Nearby` solution (of a gap
        nearby, another pose's) starts Newton's method alike but is never the solution as it is.

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
        resumed = None if start is None else _resumed(start, s, h, curvature, estar, approach, normal_load,
                                                      int(strips))
        if resumed is not None:
            return resumed
        hertzian = _hertzian(s, h, curvature, estar, approach, normal_load, int(strips))
        if hertzian is not None:
            return hertzian
        delta, lobes, first = _first_pass(s, h, curvature, estar, approach, normal_load)
        direct = _from_first_pass(s, h, curvature, estar, approach, normal_load, delta, first, int(strips))
        if direct is not None:
            return direct
        return _placements(s, h, curvature, estar, approach, normal_load, delta, lobes, first, int(strips))
    except _Failure as failure:
        given = f"normal_load = {normal_load!r} N" if approach is None else f"approach = {approach!r} m"
        return _empty(math.nan if approach is None else approach, f"{failure} ({given})", normal_load,
                      converged=False)


def _empty(approach, message, load=0.0, converged=True) -> StripContact:
    none = np.zeros(0)
    return StripContact(none, none, none, none, none, none, none, approach, math.nan if not converged else load,
                        converged, message, 0)


def _deepest_ellipse(s, h, curvature, estar, normal_load=None, approach=None):
    """``(k, ellipse, B)``: the gap's deepest sample k (within its inner samples) and Hertz's ellipse
    (:func:`~rollcontact.elliptic.hertz.hertz_ellipse`) for the curvatures there, the lateral one B [1/m] from the
    samples' second difference held within a factor 100 of A, at the load [N] or at the approach [m]."""
    k = int(np.argmin(h))
    k = min(max(k, 1), h.size - 2)
    slope_left = (h[k] - h[k - 1]) / (s[k] - s[k - 1])
    slope_right = (h[k + 1] - h[k]) / (s[k + 1] - s[k])
    lateral = (slope_right - slope_left) / (s[k + 1] - s[k - 1])
    longitudinal = float(curvature[k])
    lateral = min(max(lateral, 0.01 * longitudinal), 100.0 * longitudinal)
    if normal_load is None:  # Hertz's approach grows as the load to the power 2/3
        normal_load = (approach / hertz_ellipse(1.0, longitudinal, lateral, estar).approach) ** 1.5
    return k, hertz_ellipse(normal_load, longitudinal, lateral, estar), lateral


def _first_guess(s, h, curvature, estar, normal_load) -> float:
    """An approach [m] to start the first pass of a given load: Hertz's at the gap's deepest sample
    (:func:`_deepest_ellipse`)."""
    return _deepest_ellipse(s, h, curvature, estar, normal_load)[1].approach


def _hertzian(s, h, curvature, estar, approach, normal_load, count) -> StripContact | None:
    """Newton's method (:func:`_polish`) from Hertz's ellipse at the gap's deepest sample (:func:`_deepest_ellipse`)
    on the runs of the gap's rigid interpenetration at Hertz's approach delta (:func:`rigid_runs`), one lobe of
    ``count`` strips over the deepest part of each: where the gap lies within ``k = min(1, b^2 B / delta)`` of the
    run's depth above its deepest sample, ``h < h_min + k (delta - h_min)`` (on a quadratic gap ``h = B s^2`` that is
    Hertz's ``|s| < b``; where the gap flattens into a shelf near the approach, the lobe stays off the shelf, which the
    rigid run spans), ``e = p0 a (1 - u^2) (b / R) (d / delta)`` (Hertz's load over the lobe, R its half-width, d its
    deepest interpenetration) and ``q = p0 / a`` on its strips (u their place across it, -1..1), Hertz's approach.
    None where that gives no lobe or more than two, or where Newton's method does not take (:func:`_newton_alone`):
    the passes find the lobes."""
    _, ellipse, lateral = _deepest_ellipse(s, h, curvature, estar, normal_load, approach)
    if not all(0.0 < v < math.inf for v in (ellipse.a, ellipse.b, ellipse.approach, ellipse.max_pressure)):
        return None  # a load at the ends of floating point: the passes say what they make of it
    depth = ellipse.approach if approach is None else approach
    share = min(1.0, ellipse.b * ellipse.b * lateral / depth)
    runs = [inner for lo, hi, least in rigid_runs(s, h, depth)
            for inner in rigid_runs(s, h, least + share * (depth - least)) if lo <= inner[0] and inner[1] <= hi]
    if not 0 < len(runs) <= 2:
        return None
    across = _unit_strips(count)[0]
    radii = [0.5 * (hi - lo) for lo, hi, _ in runs]
    e = [ellipse.max_pressure * ellipse.a * (1.0 - across * across) * (ellipse.b / radius) * ((depth - least) / depth)
         for (_, _, least), radius in zip(runs, radii, strict=True)]
    return _newton_alone(np.array([0.5 * (lo + hi) for lo, hi, _ in runs]), np.array(radii), count, s, h, curvature,
                         estar, approach, normal_load, depth, np.concatenate(e),
                         np.full(count * len(runs), ellipse.max_pressure / ellipse.a), "hertz")


def _newton_alone(middle, radius, count, s, h, curvature, estar, approach, normal_load, delta, e, q, start):
    """Newton's method (:func:`_polish`) from the lobes ``(middle, radius)`` of ``count`` strips each with ``e`` and
    ``q`` on them and the approach ``delta``: the solution; where the surfaces then interpenetrate outside the lobes
    (:func:`_penetrating`), the placements (:func:`_placements`) from this solution with a lobe joined over each such
    range where ``start`` (:attr:`StripContact.start`) is Hertz's ellipse (after the other starts the cold passes,
    and then the placements from the first pass, run anyway: a solve runs the placements at most twice).  None where
    Newton's method does not take, the surfaces interpenetrate after another start, or the placements fail (the
    caller's next start goes on)."""
    unit = _unit_strips(count)
    sampled = _SampledGap(s, h, curvature)
    polished = _polish(middle, radius, unit, sampled, estar, approach, normal_load, delta, e, q)
    if polished is None:
        return None
    middle, radius, delta, e, q, used, steps = polished
    missed = _penetrating(middle, radius, unit, s, h, e, q, delta, estar)
    if not missed:
        return _contact(middle, radius, unit, sampled, e, q, delta, used, steps, "converged", start)
    if start != "hertz":
        return None
    lobes, prior = _joined(middle, radius, unit, sampled, e, q, missed)
    try:
        joined = _placements(s, h, curvature, estar, approach, normal_load, delta, lobes, prior, count)
    except _Failure:
        return None
    return replace(joined, iterations=joined.iterations + used, start=f"{start}, lobe joined")


def _first_pass(s, h, curvature, estar, approach, normal_load):
    """Uniform strips over the rigid interpenetration: each ``a_j`` first the half-length of the rigid
    interpenetration of ``(delta - h)/2``, then :data:`FIRST_ROUNDS` times the load per width from the linear
    complementarity of (I), q from (II) on the strips in contact and ``a = sqrt(e/q)``.  Returns the approach, the
    first lobes ``(middle, radius)`` over its runs of strips in contact (:func:`_lobes`, each widened by
    :data:`FIRST_MARGIN` of a strip) and a start ``(centres, lower, upper, e, q, A, 1)`` to carry over
    (:func:`_carried`)."""
    depth = approach if approach is not None else _first_guess(s, h, curvature, estar, normal_load)
    for _ in range(LOAD_GUESSES):
        bounds = rigid_range(s, h, depth)
        if bounds is None:
            if approach is None and np.count_nonzero(h < depth):
                depth *= 0.7  # a guess too deep for the sampling: shallower first
                continue
            raise _Failure(f"the rigid interpenetration {depth:.4g} m reaches an end of the patch gap's sampling "
                           f"(s = {s[0]:.4g} .. {s[-1]:.4g} m): the contact may extend beyond it")
        centres_all, lower_all, upper_all = uniform_strips(*bounds, FIRST_STRIPS)
        gaps = np.interp(centres_all, s, h)
        curv = np.interp(centres_all, s, curvature)
        index = (gaps < depth).nonzero()[0]
        if index.size == 0:
            raise _Failure("the rigid interpenetration falls between the strips")
        gaps, curv = gaps[index], curv[index]
        centres, lower, upper = centres_all[index], lower_all[index], upper_all[index]
        half = np.sqrt((depth - gaps) / (2.0 * curv))
        if np.count_nonzero(half > 0.0) < half.size:
            raise _Failure(f"the rigid interpenetration {depth!r} m gives a strip a half-length of 0 m: a contact "
                           "below floating point's resolution")
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
        margin = FIRST_MARGIN * float(widths[0])  # the edges are known to a fraction of a strip of this pass
        full = np.zeros((3, FIRST_STRIPS))
        full[0, index], full[1, index], full[2, index] = e, q, curv
        edges = [contact_edges(centres_all[run], lower_all[run], upper_all[run], full[0, run])
                 for run in _runs(full[0] > 0.0)]
        lobes = _lobes([(low - margin, high + margin) for low, high in edges])
        return delta, lobes, (centres_all, lower_all, upper_all, full[0], full[1], full[2], 1)
    raise _Failure(f"no rigid interpenetration held the contact after {LOAD_GUESSES} enlargements")


def _from_first_pass(s, h, curvature, estar, approach, normal_load, delta, first, count) -> StripContact | None:
    """Newton's method (:func:`_polish`) from the first pass ``first`` (:func:`_first_pass`): a lobe of ``count``
    strips over each of its runs of strips in contact, its edges extrapolated to zero load per width
    (:func:`_relaid`), e and q carried over (:func:`_carried`).  None where the lobes leave the gap's sampling, a
    strip would start without load, Newton's method does not take or the surfaces then interpenetrate outside the
    lobes (:func:`_newton_alone`), or its arithmetic leaves floating point (a load or approach at its ends): the
    placements' fixed point finds the lobes, or says why not."""
    middle, radius = _relaid(*first[:4], 1)
    centres, lower, upper = _placed(middle, radius, _unit_strips(count))
    if lower[0] <= s[0] or upper[-1] >= s[-1]:
        return None
    e, q = _carried(centres, np.interp(centres, s, curvature), first)
    if np.count_nonzero(e <= 0.0):
        return None
    try:
        with np.errstate(over="raise", divide="raise", invalid="raise"):
            return _newton_alone(middle, radius, count, s, h, curvature, estar, approach, normal_load, delta, e, q,
                                 "first pass")
    except FloatingPointError:  # a contact at the ends of floating point: the fixed point says what it makes of it
        return None


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
    with np.errstate(all="ignore"):  # what is not a positive finite number is refused below
        ratio = e[sub] / q[sub]
    if np.count_nonzero(np.isfinite(ratio) & (ratio > 0.0)) < sub.size:
        raise _Failure(f"the strips in contact carry e = p0 a from {float(e[sub].min())!r} N/m with q = p0 / a from "
                       f"{float(q[sub].min())!r} Pa/m: a contact beyond floating point's resolution")
    half = np.zeros(count)
    half[sub] = np.sqrt(ratio)
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


def _runs(active: np.ndarray, blocks: int = 1) -> list[np.ndarray]:
    """The runs of consecutive strips in contact (index arrays), none across the boundaries of ``blocks`` equal
    blocks of strips (the lobes' placements)."""
    count = active.size // blocks
    out = []
    for b in range(blocks):
        index = np.flatnonzero(active[b * count:(b + 1) * count]) + b * count
        if index.size:
            out += np.split(index, np.flatnonzero(np.diff(index) > 1) + 1)
    return out


def _lobes(edges: list[tuple[float, float]]) -> tuple[np.ndarray, np.ndarray]:
    """``(middle, radius)`` [m] of the lobes over the lateral ranges ``edges`` (in increasing order), those that
    overlap merged."""
    merged: list[list[float]] = []
    for low, high in edges:
        if merged and low <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], high)
        else:
            merged.append([low, high])
    ranges = np.array(merged)
    return 0.5 * (ranges[:, 0] + ranges[:, 1]), 0.5 * (ranges[:, 1] - ranges[:, 0])


@lru_cache(maxsize=8)
def _unit_strips(count: int) -> np.ndarray:
    """:func:`cosine_strips` over [-1, 1]: the rows ``(centres, lower, upper)`` of a ``(3, count)`` array
    (read-only)."""
    out = np.array(cosine_strips(-1.0, 1.0, count))
    out.flags.writeable = False
    return out


@lru_cache(maxsize=8)
def _unit_geometry(count: int, contact_modulus: float) -> StripGeometry:
    """The :class:`StripGeometry` of :func:`_unit_strips`."""
    return StripGeometry(*_unit_strips(count), contact_modulus)


def _placed(middle, radius, unit) -> np.ndarray:
    """The rows ``(centres, lower, upper)`` of the lobes' cosine-spaced strips, lobe after lobe (``unit``:
    :func:`_unit_strips`)."""
    return (middle[:, None] + radius[:, None] * unit[:, None, :]).reshape(3, -1)


class _SampledGap:
    """h and A between the gap's samples by monotone cubic interpolation (Fritsch & Carlson's slopes, as
    ``scipy.interpolate.PchipInterpolator``): smooth (C1) across the samples and within each interval between its
    samples' values (A stays > 0, h >= 0)."""

    def __init__(self, s, h, curvature):
        self.s = s
        values = np.stack([h, curvature])
        step = np.diff(s)
        rise = np.diff(values, axis=1)
        secant = rise / step
        left, right = secant[:, :-1], secant[:, 1:]
        w1, w2 = 2.0 * step[1:] + step[:-1], step[1:] + 2.0 * step[:-1]
        product = left * right
        slopes = np.zeros_like(values)
        np.divide((w1 + w2) * product, w1 * right + w2 * left, out=slopes[:, 1:-1], where=product > 0.0)
        for end, first, second in ((0, 0, 1), (-1, -1, -2)):
            h0, h1 = float(step[first]), float(step[second])
            for row in range(2):
                near, far = float(secant[row, first]), float(secant[row, second])
                d = ((2.0 * h0 + h1) * near - h0 * far) / (h0 + h1)
                if d * near <= 0.0:
                    d = 0.0
                elif near * far < 0.0 and abs(d) > 3.0 * abs(near):
                    d = 3.0 * near
                slopes[row, end] = d
        # per interval, both quantities (h, A): v0 + t (d0 + t (c2 + t c3)) in its fraction t; 1 / its length
        d0, d1 = slopes[:, :-1] * step, slopes[:, 1:] * step
        self.coefficients = np.stack([values[:, :-1], d0, 3.0 * rise - 2.0 * d0 - d1, d0 + d1 - 2.0 * rise])
        self.inverse = 1.0 / step
        self.inner = s[1:-1].copy()  # the interval of a point: the count of the inner samples at or below it

    def at(self, points):
        """``(h, dh/ds, A, dA/ds)`` at ``points`` (within the samples; beyond them the end intervals' cubics)."""
        k = np.searchsorted(self.inner, points, side="right")
        v0, d0, c2, c3 = self.coefficients.take(k, axis=2)  # each (h, A) at the points
        inverse = self.inverse.take(k)
        t = (points - self.s.take(k)) * inverse
        value = v0 + t * (d0 + t * (c2 + t * c3))
        slope = (d0 + t * (2.0 * c2 + 3.0 * t * c3)) * inverse
        return value[0], slope[0], value[1], slope[1]


def _run_edges(centres, lower, upper, e, blocks) -> list[tuple[np.ndarray, float, float]]:
    """``(run, low, high)`` of each run of strips in contact of a placement of ``blocks`` lobes: its edges
    extrapolated to zero load per width (:func:`contact_edges`, reaching out by up to :data:`REACH` of its lobe's
    width where the contact is cut at the end of the strips)."""
    count = centres.size // blocks
    out = []
    for run in _runs(e > 0.0, blocks):
        start = run[0] // count * count
        reach = REACH * float(upper[start + count - 1] - lower[start])
        out.append((run, *contact_edges(centres[run], lower[run], upper[run], e[run], reach)))
    return out


def _relaid(centres, lower, upper, e, blocks):
    """The lobes ``(middle, radius)`` over the runs of strips in contact of a placement of ``blocks`` lobes
    (:func:`_run_edges`), runs that then overlap merged."""
    edges = [(low, high) for _, low, high in _run_edges(centres, lower, upper, e, blocks)]
    if not edges:
        raise _Failure("the fixed point lost every strip")
    return _lobes(edges)


def _carried(centres, curv, prior) -> tuple[np.ndarray, np.ndarray]:
    """e and q on new strips from a prior solution ``(centres, lower, upper, e, q, A, blocks)``: e interpolated
    linearly between the prior runs' strips in contact and each run's edges (:func:`_run_edges`, where it vanishes),
    0 beyond; q / A likewise between the prior strips in contact (the strips' stiffening), constant beyond."""
    p_centres, p_lower, p_upper, p_e, p_q, p_curv, blocks = prior
    nodes, values = [], []
    for run, low, high in _run_edges(p_centres, p_lower, p_upper, p_e, blocks):
        if nodes and low <= nodes[-1]:  # runs that meet: no vanishing edges between them
            nodes.pop(), values.pop()
        else:
            nodes.append(low), values.append(0.0)
        nodes += [*p_centres[run], high]
        values += [*p_e[run], 0.0]
    e = np.interp(centres, nodes, values, left=0.0, right=0.0)
    known = (p_e > 0.0) & (p_q > 0.0)
    q = np.interp(centres, p_centres[known], p_q[known] / p_curv[known]) * curv
    return e, q


def _polish(middle, radius, unit, sampled, estar, approach, normal_load, delta, e, q):
    """Newton's method on (I), (II), the edge conditions (and the load) for e, q and the lobes' middles and
    half-widths together, from a start near the solution (module docstring): ``(middle, radius, delta, e, q,
    iterations, steps)`` (steps: the relative changes of its steps) once no e, q or edge changes by more than
    :data:`FIXED_POINT_TOLERANCE` of the largest (the edges of their lobe's half-width), or its next step would not
    (:data:`NEWTON_CONTRACTION`), on a step taken whole.  A step that would empty a strip or flip a curvature is cut
    short (:data:`BOUNDARY`), as is one that moves an edge by half its lobe's width; None where a step is cut to less
    than :data:`LEAST_FRACTION`, where lobes would overlap or leave the gap's sampling, where the residual grows by
    more than :data:`GROWTH` in a step, or after :data:`POLISH_ITERATIONS`.  Within a lobe U and C depend on its
    half-width R as on ``R/a``: ``R dU/dR = -a dU/da``, and not on its middle M; between lobes the derivatives with
    respect to the positions of field points and edges
    (:meth:`~rollcontact.wheelrail.methods.strip_kernels.StripGeometry.matrices`) give the lobes' interactions, and
    the gap's slopes the rest."""
    unit_centres, unit_lower, unit_upper = unit
    count = unit_centres.size
    lobes = middle.size
    n = lobes * count
    kappa = (unit_centres[0] + 1.0) / (unit_centres[1] + 1.0)  # e_1 / e_2 of a load per width linear at the edge
    given_load = approach is None
    blocks = [slice(k * count, (k + 1) * count) for k in range(lobes)]
    cu, lu, uu = (np.tile(u, lobes) for u in unit)
    first = np.arange(lobes) * count
    last = first + count - 1
    rows = 2 * n + np.arange(lobes)
    size = 2 * n + 2 * lobes + given_load
    middles, radii = slice(2 * n, 2 * n + lobes), slice(2 * n + lobes, 2 * n + 2 * lobes)
    e_scale, q_scale = float(e.max()), float(q.mean())
    previous = math.inf
    steps: list[float] = []
    jacobian = np.zeros((size, size))  # its constant entries, the edge conditions' and the load's, set once
    jacobian[rows, first] = 1.0
    jacobian[rows, first + 1] = -kappa
    jacobian[rows + lobes, last] = 1.0
    jacobian[rows + lobes, last - 1] = -kappa
    if given_load:
        jacobian[:n, -1] = -1.0
    for used in range(1, POLISH_ITERATIONS + 1):
        centres, lower, upper = _placed(middle, radius, unit)
        if np.count_nonzero(lower[first[1:]] <= upper[last[:-1]]) or lower[0] <= sampled.s[0] \
                or upper[-1] >= sampled.s[-1]:
            return None
        gaps, h_slope, curv, a_slope = sampled.at(centres)
        half = np.sqrt(e / q)
        if lobes == 1:  # U and C depend on the distances over a: those of the unit lobe over a / R
            U, C, dU, dC = _unit_geometry(count, estar).matrices(half / radius[0], derivative=True)
        else:
            U, C, dU, dC, gU, gC = StripGeometry(centres, lower, upper, estar).matrices(half, distances=True)
        Ue, Cq = U @ e, C @ q
        widths = upper - lower
        inverse_curv = 1.0 / curv
        residual = np.empty(size)
        residual[:n] = (Ue - (delta - gaps)) / delta
        residual[n:2 * n] = Cq * inverse_curv - 1.0
        residual[rows] = (e[first] - kappa * e[first + 1]) / e_scale
        residual[rows + lobes] = (e[last] - kappa * e[last - 1]) / e_scale
        if given_load:
            residual[-1] = 0.5 * math.pi * float(widths @ e) / normal_load - 1.0
        norm = float(np.abs(residual).max())
        if norm > GROWTH * previous:
            return None
        previous = norm
        # a = sqrt(e/q): a d/da enters d/de with 1/(2e) and d/dq with -1/(2q)
        block = jacobian[:n, :n]
        np.multiply(dU, 0.5, out=block)
        block += U
        block *= e_scale / delta
        np.multiply(dU, (-0.5 * q_scale / delta) * (e / q), out=jacobian[:n, n:2 * n])
        block = jacobian[n:2 * n, :n]
        np.multiply(dC, (0.5 * e_scale) * (q / e), out=block)
        block *= inverse_curv[:, None]
        block = jacobian[n:2 * n, n:2 * n]
        np.multiply(dC, -0.5, out=block)
        block += C
        block *= (q_scale * inverse_curv)[:, None]
        # the lobes' middles and half-widths: a field point s_i = M + R c_i, an edge t = M + R tau
        if lobes == 1:  # translation moves the gap alone; R dU/dR = -a dU/da
            r = float(radius[0])
            jacobian[:n, 2 * n] = h_slope * (r / delta)
            jacobian[:n, 2 * n + 1] = (r * cu * h_slope - dU @ e) / delta
            along_c = Cq * a_slope * inverse_curv * inverse_curv
            jacobian[n:2 * n, 2 * n] = -r * along_c
            jacobian[n:2 * n, 2 * n + 1] = -(dC @ q) * inverse_curv - r * cu * along_c
        else:  # (lu, uu: the edges' tau) each row changes with its field point and with the edges of each lobe
            moving_u = (gU[0] @ e + gU[1] @ e) + h_slope  # d/ds_i of (I)'s row, times delta
            moving_c = (gC[0] @ q + gC[1] @ q - Cq * a_slope * inverse_curv) * inverse_curv  # d/ds_i of (II)'s
            lu_e, uu_e, lu_q, uu_q = lu * e, uu * e, lu * q, uu * q
            for k, part in enumerate(blocks):
                for column, field, source_u, source_c in (
                        (2 * n + k, 1.0, gU[0][:, part] @ e[part] + gU[1][:, part] @ e[part],
                         gC[0][:, part] @ q[part] + gC[1][:, part] @ q[part]),
                        (2 * n + lobes + k, cu[part], gU[0][:, part] @ lu_e[part] + gU[1][:, part] @ uu_e[part],
                         gC[0][:, part] @ lu_q[part] + gC[1][:, part] @ uu_q[part])):
                    source_u *= -radius[k] / delta
                    source_u[part] += field * moving_u[part] * (radius[k] / delta)
                    source_c *= -radius[k] * inverse_curv
                    source_c[part] += field * moving_c[part] * radius[k]
                    jacobian[:n, column] = source_u
                    jacobian[n:2 * n, column] = source_c
        if given_load:
            jacobian[-1, :n] = 0.5 * math.pi * widths * e_scale / normal_load
            jacobian[-1, radii] = [0.5 * math.pi * float(widths[part] @ e[part]) / normal_load for part in blocks]
        step = _solve(jacobian, -residual)
        de, dq = step[:n] * e_scale, step[n:2 * n] * q_scale
        moved, widened = step[middles] * radius, step[radii] * radius
        # a step that would empty a strip, flip a curvature or move an edge by half its lobe is cut short
        fraction = min(1.0, BOUNDARY * _room(e, de), BOUNDARY * _room(q, dq),
                       0.5 * _room(radius, -(np.abs(moved) + np.abs(widened))))
        if fraction < 1.0:
            if fraction < LEAST_FRACTION:
                return None
            step *= fraction
            de, dq, moved, widened = de * fraction, dq * fraction, moved * fraction, widened * fraction
        e, q, middle, radius = e + de, q + dq, middle + moved, radius + widened
        if given_load:
            delta *= 1.0 + float(step[-1])
        change = max(float(np.abs(de).max()) / float(e.max()), float(np.abs(dq).max()) / float(q.max()),
                     float(np.max((np.abs(moved) + np.abs(widened)) / radius)))
        steps.append(change)
        if fraction == 1.0 and (change <= FIXED_POINT_TOLERANCE
                                or NEWTON_CONTRACTION * change * change <= FIXED_POINT_TOLERANCE):
            return middle, radius, delta, e, q, used, tuple(steps)
    return None


def _room(values: np.ndarray, change: np.ndarray) -> float:
    """The least ``values / -change`` over the entries that ``change`` decreases (inf where none does): the share of a
    step that takes the first of them to zero (``-max(values / change)`` over them: the same number)."""
    falling = change < 0.0
    return -float((values[falling] / change[falling]).max()) if np.count_nonzero(falling) else math.inf


def _contact(middle, radius, unit, sampled, e, q, delta, iterations, steps, message, start) -> StripContact:
    """The solution on the lobes' strips, a strip out of contact spanning each gap between lobes (``start``:
    :attr:`StripContact.start`)."""
    centres, lower, upper = _placed(middle, radius, unit)
    count = unit[0].size
    if middle.size > 1:
        at = np.arange(1, middle.size) * count
        between_lower, between_upper = upper[at - 1], lower[at]
        centres = np.insert(centres, at, 0.5 * (between_lower + between_upper))
        lower, upper = np.insert(lower, at, between_lower), np.insert(upper, at, between_upper)
        e, q = np.insert(e, at, 0.0), np.insert(q, at, 0.0)
    gaps, _, curv, _ = sampled.at(centres)
    active = e > 0.0
    half = np.where(active, np.sqrt(np.where(active, e, 0.0) / np.where(active, q, 1.0)), 0.0)
    peak = np.where(active, q * half, 0.0)
    load = 0.5 * math.pi * float((upper - lower) @ e)
    lobes = tuple(zip((middle - radius).tolist(), (middle + radius).tolist(), strict=True))
    return StripContact(centres, lower, upper, half, peak, gaps, curv, float(delta), load, True, message, iterations,
                        steps, lobes, start)


def _resumed(start, s, h, curvature, estar, approach, normal_load, count) -> StripContact | None:
    """Newton's method from the solution ``start`` (:func:`strip_normal`): its lobes' half-widths scaled by
    ``sqrt(r)``, e by r and the approach by r, ``r = delta / delta_start`` (for a given load ``(Fn / Fn_start)^(2/3)``),
    as Hertz's contact scales (``start`` itself where r is 1 to :data:`FIXED_POINT_TOLERANCE`, the tolerance it is
    solved to, unless it is :class:`Nearby`); None where ``start`` has no lobes of ``count`` strips all in contact,
    where Newton's method does not take or where the surfaces then interpenetrate outside the lobes
    (:func:`_newton_alone`)."""
    nearby = isinstance(start, Nearby)
    if nearby:
        start = start.contact
    lobes = len(start.lobes)
    if not (start.converged and lobes and start.centres.size == lobes * (count + 1) - 1 and start.approach > 0.0
            and start.normal_load > 0.0):
        return None
    kept = np.ones(start.centres.size, dtype=bool)
    kept[count::count + 1] = False  # the strips between lobes
    half, peak = start.half_lengths[kept], start.peak_pressures[kept]
    if np.count_nonzero(half <= 0.0):
        return None
    ratio = approach / start.approach if approach is not None else (normal_load / start.normal_load) ** (2.0 / 3.0)
    if not nearby and abs(ratio - 1.0) <= FIXED_POINT_TOLERANCE:  # start is solved to this: it is the solution
        return start
    low, high = np.array(start.lobes).T
    return _newton_alone(0.5 * (low + high), 0.5 * (high - low) * math.sqrt(ratio), count, s, h, curvature, estar,
                         approach, normal_load, start.approach * ratio, peak * half * ratio, peak / half, "resumed")


def _placements(s, h, curvature, estar, approach, normal_load, delta, lobes, start, count) -> StripContact:
    """Cosine-spaced strips over each lobe, the fixed point on (I) and (II), the lobes laid again over its runs of
    strips in contact, and Newton's method on the lobes' edges too (module docstring)."""
    unit = _unit_strips(count)
    sampled = _SampledGap(s, h, curvature)
    prior = start
    iterations = 0
    middle, radius = lobes
    for tolerance in (PLACEMENT_TOLERANCE, *POLISH_RETRIES, FIXED_POINT_TOLERANCE):
        centres, lower, upper = _placed(middle, radius, unit)
        if rigid_range(s, h, delta) is None or lower[0] <= s[0] or upper[-1] >= s[-1]:
            raise _Failure(f"the contact at the approach {delta:.4g} m reaches an end of the patch gap's sampling "
                           f"(s = {s[0]:.4g} .. {s[-1]:.4g} m): it may extend beyond it")
        gaps, _, curv, _ = sampled.at(centres)
        e, q = _carried(centres, curv, prior)
        if not np.count_nonzero(e > 0.0):
            e[np.argmin(gaps)] = max(float(prior[3].max()), 1.0)
        geometry = StripGeometry(centres, lower, upper, estar)
        delta, e, q, active, used = _fixed_point(centres, lower, upper, gaps, curv, geometry, approach, normal_load,
                                                 delta, e, q, e > 0.0, tolerance)
        iterations += used
        e, q = np.where(active, e, 0.0), np.where(active, q, 0.0)
        if tolerance == FIXED_POINT_TOLERANCE:  # Newton's method never took: the fixed point's own solution
            return _contact(middle, radius, unit, sampled, e, q, delta, iterations, (),
                            "converged by the fixed point alone (Newton's method on the lobes' edges did not take)",
                            "fixed point")
        prior = centres, lower, upper, e, q, curv, middle.size
        middle, radius = _relaid(centres, lower, upper, e, middle.size)
        centres, lower, upper = _placed(middle, radius, unit)
        if lower[0] <= s[0] or upper[-1] >= s[-1]:
            continue
        _, _, curv, _ = sampled.at(centres)
        e_start, q_start = _carried(centres, curv, prior)
        if np.count_nonzero(e_start <= 0.0):
            continue
        polished = _polish(middle, radius, unit, sampled, estar, approach, normal_load, delta, e_start, q_start)
        if polished is None:
            continue
        middle, radius, delta, e, q, used, steps = polished
        iterations += used
        missed = _penetrating(middle, radius, unit, s, h, e, q, delta, estar)
        if not missed:
            return _contact(middle, radius, unit, sampled, e, q, delta, iterations, steps, "converged", "placements")
        # the surfaces interpenetrate outside the lobes: a lobe the passes missed joins them
        (middle, radius), prior = _joined(middle, radius, unit, sampled, e, q, missed)
    raise AssertionError("unreachable")


def _joined(middle, radius, unit, sampled, e, q, missed):
    """``((middle, radius), prior)``: the lobes with one joined over each of the ``missed`` ranges
    (:func:`_penetrating`; merged where they overlap, :func:`_lobes`) and the solution ``e``, ``q`` on the lobes'
    strips as the placements' start to carry over (:func:`_carried`)."""
    centres, lower, upper = _placed(middle, radius, unit)
    prior = centres, lower, upper, e, q, sampled.at(centres)[2], middle.size
    lobes = zip((middle - radius).tolist(), (middle + radius).tolist(), strict=True)
    return _lobes(sorted([*lobes, *missed])), prior


def _penetrating(middle, radius, unit, s, h, e, q, delta, estar) -> list[tuple[float, float]]:
    """The lateral ranges [m] of the gap's samples outside the lobes where the deformed surfaces interpenetrate,
    ``h + u_z - delta < -`` :data:`PENETRATION` ``delta``, each widened to the samples beside it."""
    outside = h < delta
    for low, high in zip(middle - radius, middle + radius, strict=True):
        outside &= (s < low) | (s > high)
    candidates = np.flatnonzero(outside)
    if not candidates.size:
        return []
    _, lower, upper = _placed(middle, radius, unit)
    U = StripGeometry(s[candidates], lower, upper, estar).matrices(np.sqrt(e / q))[0]
    inside = candidates[h[candidates] + U @ e - delta < -PENETRATION * delta]
    return [(float(s[max(run[0] - 1, 0)]), float(s[min(run[-1] + 1, s.size - 1)]))
            for run in np.split(inside, np.flatnonzero(np.diff(inside) > 1) + 1) if run.size]


def _spread(half):
    """The half-lengths of the strips in contact (``half > 0``), and for the others a third of those of the strips in
    contact interpolated by index (the nearest one's beyond the ends): the length a strip entering the contact starts
    with."""
    inside = (half > 0.0).nonzero()[0]
    if inside.size == half.size:
        return half
    if not inside.size:
        raise _Failure("every strip's half-length is 0 m: a contact below floating point's resolution")
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
                        contact.newton_steps, start=contact.start)
