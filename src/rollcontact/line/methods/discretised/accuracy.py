"""Accuracy model of the discretised method: its settings (one grid of n elements, or an extrapolated pair n/2n
over m placements), their error bounds and their modelled cost.

:class:`DiscretisedAccuracy` is what ``auto`` asks (:mod:`rollcontact.line.dispatch`): T' is first order and p0 second
order in the elements across the contact, ``max(c w/n, 3 (w/n)^2)`` with w the window over the Hertz width 2a; a
result's estimate puts in its patches' widths (:func:`patch_widths`).  A module of its own so that the solver
modules do not carry the calibration.  The error constants are calibrated by
``benchmarks/calibrate_discretised_estimate.py`` (its Summary, and table C for the extrapolated pair) and checked on
several patches by ``benchmarks/bench_multipatch.py`` (table B); the cost constants against
``benchmarks/pareto.py`` (``benchmarks/results/pareto.md``, section "Cost and error models of auto").
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from rollcontact.core.method import AccuracyModel, Setting
from rollcontact.line.halfspace.grid import automatic_grid
from rollcontact.line.methods.common import friction_sharpness, hertz_half_width
from rollcontact.line.methods.discretised.steady import DISCRETISED_ELEMENTS
from rollcontact.line.result import ContactResult

DIRECT_COST = (1.7e-3, 2.8e-8, 0.0)  # s: discretised Coulomb, a + b n^2 + c n^3 (c = 0: n^2 dominates to n = 1600)


STRUCTURED_ITERATIONS = (20.0, 85.0)  # Newton iterations of the discretised velocity-dependent solve ~ 20 + 85 beta


STRUCTURED_COST = (1.5e-4, 9.6e-9, 8.9e-12)  # s per such Newton iteration, a + b n^2 + c n^3


# relative T' error <= 4.0 w/n (w = window over the Hertz width 2a): a margin over the largest coefficient measured
# by benchmarks/calibrate_discretised_estimate.py (its Summary; the largest is on the split contact at small creep)
DISCRETISED_FORCE_ERROR = 4.0


DISCRETISED_PRESSURE_ERROR = 3.0  # relative p0 error <= 3 (w/n)^2


# The extrapolated setting (solve_discretised(extrapolate=m)): T' from n and 2n elements, each level the mean over m
# grid placements.  Relative T' error <= 3.2 w/(m n) (n the coarser level): the placement mean leaves a first-order
# residue that falls like 1/m (benchmarks/calibrate_discretised_estimate.py, table C: m c = err m n / w, largest on the
# split contact near full stick, scanned densely at n = 50..400; m = 2, 4, 8, 16 alike; table C also gives the
# bound's margin over every error on the automatic window); p0 is the finer level's, <= 3 (w/2n)^2.
# Calibrated for m in [2, 16]; auto offers m = 8 and 16
EXTRAPOLATION_PLACEMENTS = (8, 16)


EXTRAPOLATED_FORCE_ERROR = 3.2


EXTRAPOLATION_CALIBRATED = (2, 16)  # the range of m the bound is calibrated for (table C)


class DiscretisedAccuracy(AccuracyModel):
    """Discretised method: T' first order and p0 second order in the elements across the contact.

    The bound ``max(4.0 w/n, 3 (w/n)^2)`` (w the grid length over the Hertz width 2a, n the elements) holds
    for every case of ``benchmarks/calibrate_discretised_estimate.py`` (Hertz/Carter at three loads on a fixed window
    and six creeps of both signs, corrugations up to a split contact at four creeps, a quartic profile,
    falling friction).  The first-order coefficient varies with where the patch edges fall on the grid and with
    the creep (largest on the split contact at small creep), so the bound is several times pessimistic in the
    median.  The bound uses the Hertz width 2a and holds where the patches are about as wide; a result's estimate
    (:meth:`achieved`) puts in its patches' widths where they are narrower (:func:`patch_widths`): on short
    corrugations with small satellite patches T' can exceed the Hertz-width bound, not the estimate
    (``benchmarks/bench_multipatch.py``, table B: against the polynomial method's several patches on 4-10 mm /
    10-40 um corrugations), and ``auto`` escalates while the estimate misses the tolerance (:meth:`escalation`).
    No estimate from the solution's convergence replaces the bound:
    the answer at n itself moves by up to the error when the grid moves by half an element, and the two-grid
    estimate (3 times the largest difference to two solves of n/2 elements at different placements) bounds the
    error but is larger than this bound in the median (same benchmark).  Element counts below the automatic
    grid's resolution of the shortest surface wavelength are not offered.

    The extrapolated setting ``{"elements": n, "extrapolate": m}`` averages that placement-dependent part over m
    placements and removes the smooth first-order part by Richardson extrapolation from n and 2n elements: its
    bound is ``max(3.2 w/(m n), 3 (w/2n)^2)`` (:data:`EXTRAPOLATED_FORCE_ERROR`), w from the automatic window,
    which is at least as long as the fitted window it runs on; m outside :data:`EXTRAPOLATION_CALIBRATED` has no
    calibrated bound (NaN).  It costs ``m`` solves at n and at 2n, and pays where a single grid would need several
    times 2n elements: tight tolerances on a scene only this method treats (a split contact).
    Offered with m = :data:`EXTRAPOLATION_PLACEMENTS`, its finer level at most the largest single grid offered,
    for constant friction (with velocity-dependent friction each of the 2m structured solves costs
    :data:`STRUCTURED_ITERATIONS` Newton iterations).
    """

    floor = DIRECT_COST[0]  # the structured (velocity-dependent) solve's iterations cost more

    def ladder(self, scene):
        needed = self.resolution(scene)
        rungs = tuple({"elements": n} for n in DISCRETISED_ELEMENTS if n >= needed)
        pairs = tuple({"elements": n, "extrapolate": m} for m in EXTRAPOLATION_PLACEMENTS for n in DISCRETISED_ELEMENTS
                      if n >= needed and 2 * n <= DISCRETISED_ELEMENTS[-1]) if scene.friction.is_constant else ()
        return (rungs + pairs) or ({},)  # the automatic grid resolves the shortest wavelength

    def cost(self, scene, options):
        placements = options.get("extrapolate", 0)
        if placements:
            n = self.pair_elements(options)
            # plus the normal solve on the automatic grid that fits the window, costed as a whole solve
            return (placements * (self.solve_cost(scene, n) + self.solve_cost(scene, 2 * n))
                    + self.solve_cost(scene, automatic_grid(scene).elements))
        return self.solve_cost(scene, options.get("elements") or automatic_grid(scene).elements)

    @staticmethod
    def pair_elements(options) -> int:
        """The coarser level's elements of an extrapolated pair (``solve_discretised``'s default when unset)."""
        from rollcontact.line.halfspace.grid import DEFAULT_ELEMENTS

        return options.get("elements") or DEFAULT_ELEMENTS

    @staticmethod
    def solve_cost(scene, n: int) -> float:
        """Modelled time [s] of one solve on n elements."""
        if scene.friction.is_constant:
            a, b, c = DIRECT_COST
            return a + b * n * n + c * n**3
        a, b, c = STRUCTURED_COST
        iterations = STRUCTURED_ITERATIONS[0] + STRUCTURED_ITERATIONS[1] * friction_sharpness(scene)
        return iterations * (a + b * n * n + c * n**3)

    def minimum_cost(self, scene):
        return self.cost(scene, {"elements": DISCRETISED_ELEMENTS[0]})

    def merged(self, options, user):
        """A caller's ``elements`` fixes one grid of that many elements: the extrapolated pair is then dropped
        unless the caller asks for it too."""
        if "elements" in user and "extrapolate" not in user:
            options = {k: v for k, v in options.items() if k != "extrapolate"}
        return {**options, **user}

    def setting_for(self, name, scene, tolerance):
        """The cheapest of the fewest single-grid elements and, for each m offered, the fewest extrapolated pair
        whose bounds meet the tolerance, any count from the ladder's first to its last (at least the surface
        resolution); when none does, the most accurate of them at their largest counts, with its bound.

        Not only the ladder's rungs: the bounds are within a small factor of the worst error measured
        (``benchmarks/calibrate_discretised_estimate.py``), so the next rung up, up to twice the elements needed, would
        cost up to 4-8 times (n^2 to n^3).
        """
        if scene.normal_load_per_length == 0.0:
            return super().setting_for(name, scene, tolerance)
        ratio = automatic_length(scene) / (2.0 * hertz_half_width(scene))  # n times w/n of the bound
        floor = max(self.resolution(scene), DISCRETISED_ELEMENTS[0])
        largest = DISCRETISED_ELEMENTS[-1]
        single = self.fewest({}, ratio * max(DISCRETISED_FORCE_ERROR / tolerance,
                                             math.sqrt(DISCRETISED_PRESSURE_ERROR / tolerance)),
                             floor, largest, scene, tolerance)
        candidates = [single]
        if floor <= largest // 2 and scene.friction.is_constant:
            candidates += [self.fewest({"extrapolate": m},
                                       ratio * max(EXTRAPOLATED_FORCE_ERROR / (m * tolerance),
                                                   0.5 * math.sqrt(DISCRETISED_PRESSURE_ERROR / tolerance)),
                                       floor, largest // 2, scene, tolerance) for m in EXTRAPOLATION_PLACEMENTS]
        meeting = [s for s in candidates if s.error_estimate <= tolerance]
        if meeting:
            return Setting(name, *min(meeting, key=lambda s: s.cost)[1:])
        return Setting(name, *min(candidates, key=lambda s: s.error_estimate)[1:])

    def fewest(self, extra: dict, needed: float, floor: int, top: int, scene, tolerance) -> Setting:
        """The setting ``{"elements": n, **extra}`` with the fewest n in [floor, top] whose bound meets the
        tolerance (``needed``: the real n the bound asks for), else n = top."""
        n = min(max(math.ceil(min(needed, top)), floor), top)
        options = {"elements": n, **extra}
        while n < top and self.error(scene, options) > tolerance:  # rounding of the ceil
            n += 1
            options = {"elements": n, **extra}
        return Setting("", options, self.error(scene, options), self.cost(scene, options))

    def error(self, scene, options):
        if scene.normal_load_per_length == 0.0:
            return 0.0
        placements = options.get("extrapolate", 0)
        if placements:
            return self.extrapolated_bound(scene, automatic_length(scene), self.pair_elements(options), placements)
        window = options.get("window")
        length = automatic_length(scene) if window is None else float(window[1]) - float(window[0])
        elements = options.get("elements") or automatic_grid(scene, None, window).elements
        return self.bound(scene, length, elements)

    def achieved(self, scene, options, result, tolerance=None):
        """The bound with the result's patches: the Hertz width 2a in it replaced by :func:`patch_widths`' widths
        where the patches are narrower (short corrugations), so never below the a-priori :meth:`error` (as cheap
        with a tolerance as without)."""
        grid = result.info.get("grid")
        if grid is None:  # no load: no grid, nothing to get wrong
            return 0.0
        widths = patch_widths(result, 2.0 * hertz_half_width(scene))
        placements = options.get("extrapolate", 0)
        if placements:  # the grid is the finer level's, on the fitted window
            return self.extrapolated_bound(scene, grid.length, grid.elements // 2, placements, widths)
        return self.bound(scene, grid.length, grid.elements, widths)

    def escalation(self, scene, options, estimate, tolerance) -> dict | None:
        """Options to run next when the result's patch-aware estimate (:meth:`achieved`) misses the tolerance
        that the a-priori bound (Hertz width) promised: :meth:`setting_for` with the tolerance tightened by the
        factor the patches cost, ``t error/estimate`` (one grid or the pair, whichever is then cheaper).  None
        when the estimate meets the tolerance (or is NaN), or that setting's bound is not below the one run:
        every call lowers the bound, so escalating until None ends.
        """
        if not estimate > tolerance or "elements" not in options:
            return None
        predicted = self.error(scene, options)
        if not predicted > 0.0:  # NaN (an uncalibrated m) or no load: nothing to scale
            return None
        following = self.setting_for("discretised", scene, tolerance * predicted / estimate).options
        return following if self.error(scene, following) < predicted else None

    def retry(self, scene, options, result) -> dict | None:
        """After a failed slip iteration (velocity-dependent friction) on a single grid, twice the elements, up to
        the largest offered: the failure is mostly a slip zone shorter than an element at a patch end (see
        :func:`~rollcontact.line.methods.discretised.steady.solve_discretised`, which does the same on its automatic
        grid)."""
        elements = options.get("elements")
        if scene.friction.is_constant or not elements or options.get("extrapolate") \
                or 2 * elements > DISCRETISED_ELEMENTS[-1]:
            return None
        return {"elements": 2 * elements}

    @staticmethod
    def resolution(scene) -> int:
        """Elements the automatic grid needs for the shortest surface wavelength (0 without harmonics)."""
        from rollcontact.line.halfspace.grid import ELEMENTS_PER_WAVELENGTH

        waves = [2.0 * math.pi / h.wavenumber for h in scene.surface.harmonics if h.amplitude > 0.0]
        if not waves or scene.normal_load_per_length == 0.0:
            return 0
        return math.ceil(ELEMENTS_PER_WAVELENGTH * automatic_length(scene) / min(waves))

    @staticmethod
    def bound(scene, length: float, elements: int, widths: PatchWidths | None = None) -> float:
        """``max(4.0 h/W_T, 3 (h/W_p)^2)``, h = length/elements; the widths W [m] default to the Hertz width 2a
        (then h/2a = w/n)."""
        force, pressure = widths or PatchWidths.hertz(scene)
        h = length / elements
        return max(DISCRETISED_FORCE_ERROR * h / force, DISCRETISED_PRESSURE_ERROR * (h / pressure) ** 2)

    @staticmethod
    def extrapolated_bound(scene, length: float, elements: int, placements: int,
                           widths: PatchWidths | None = None) -> float:
        """``max(3.2 h/(m W_T), 3 (h/(2 W_p))^2)`` for the coarser level's n (h = length/n) and m placements, the
        widths as in :meth:`bound`; NaN for an m outside :data:`EXTRAPOLATION_CALIBRATED`."""
        low, high = EXTRAPOLATION_CALIBRATED
        if not low <= placements <= high:
            return math.nan
        force, pressure = widths or PatchWidths.hertz(scene)
        h = length / elements
        return max(EXTRAPOLATED_FORCE_ERROR * h / (placements * force),
                   DISCRETISED_PRESSURE_ERROR * (0.5 * h / pressure) ** 2)


@lru_cache(maxsize=32)
def automatic_length(scene) -> float:
    """Length [m] of the automatic grid's window (cached: each setting of the ladder asks for it)."""
    return automatic_grid(scene).length


class PatchWidths(NamedTuple):
    """Widths [m] that scale the discretised error bounds: T' error ~ h/force, p0 error ~ (h/pressure)^2."""

    force: float
    pressure: float

    @classmethod
    def hertz(cls, scene) -> PatchWidths:
        """Both the Hertz width 2a: the a-priori bounds, before the patches are known."""
        width = 2.0 * hertz_half_width(scene)
        return cls(width, width)


def patch_widths(result: ContactResult, hertz_width: float) -> PatchWidths:
    """The widths of a discretised result's patches in its error bounds, at most the Hertz width ``hertz_width``.

    T': every patch k (width ``w_k``, force ``T'_k``, from the tabulated fields) errs by about ``h/w_k |T'_k|`` to
    first order, its edges and its stick zone lying anywhere within their elements, so relative to T' the error is
    ~ ``h/W_T`` with ``1/W_T = sum_k |T'_k| / (w_k |T'|)``.  A small satellite patch beside the main one weighs by
    its force: at small creep it slips fully while |T'| is small.  p0 (second order): the width of the patch that
    holds the largest pressure.  ``benchmarks/bench_multipatch.py`` (table B, ``benchmarks/results/multipatch.md``)
    measures the T' and p0 errors over this estimate against the polynomial method's several patches, for one grid
    and for the pair over m placements; with the Hertz width alone a small satellite patch lets the T' error exceed
    the bound.  Without traction (zero creep, a failed solve) W_T is the Hertz width.
    """
    fields = result.distributions
    x, p, q = np.asarray(fields.x), np.asarray(fields.p), np.asarray(fields.q)
    patches = result.info.get("patches") or []
    if x.size < 2 or not patches:
        return PatchWidths(hertz_width, hertz_width)
    h = x[1] - x[0]
    # element centres lie half an element inside the patch edges
    forces = [(h * float(q[(x > lo) & (x < hi)].sum()), hi - lo) for lo, hi in patches]
    total = abs(sum(force for force, _ in forces))
    weighted = sum(abs(force) / width for force, width in forces) / total if total > 0.0 else 0.0
    peak = x[int(np.argmax(p))]
    holding = next((hi - lo for lo, hi in patches if lo <= peak <= hi), hertz_width)
    return PatchWidths(min(hertz_width, 1.0 / weighted) if weighted > 0.0 else hertz_width,
                       min(hertz_width, holding))
