"""Accuracy model of the polynomial method: its settings, their predicted error and their modelled cost.

:class:`PolynomialAccuracy` is what ``auto`` asks (:mod:`rollcontact.line.dispatch`): with constant friction T', a,
Delta and a* are exact (Bessel moments, paper eqs 28-31) and the ``truncation`` bounds the p0 error; with
velocity-dependent friction the slip iteration's node count N sets the T' error, bounded a priori by
``SLIP_NODE_ERROR beta/N^2`` and a posteriori by the result's own estimate.  A module of its own so that the solver
modules do not carry the calibration, and the dispatcher does not import the solvers to rank settings.

Calibration: the cost constants (:data:`POLYNOMIAL_COST`, :data:`POLYNOMIAL_HARMONIC_COST`, :data:`SLIP_COST`) are
checked against ``benchmarks/pareto.py`` (``benchmarks/results/pareto.md``, section "Cost and error models of
auto"); the slip iteration's constants by ``benchmarks/calibrate_slip_nodes.py`` (tables C and E).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from rollcontact.core.method import ROUND_OFF, AccuracyModel, Setting
from rollcontact.line.methods.common import friction_sharpness
from rollcontact.line.methods.polynomial.slip import DEFAULT_NODES
from rollcontact.line.methods.polynomial.solver import TRUNCATION
from rollcontact.line.scene import Scene

POLYNOMIAL_COST = 7.5e-5  # s, normal Newton, tangential root and validity checks (about independent of the order)


POLYNOMIAL_HARMONIC_COST = 7.5e-5  # s per surface harmonic


# slip iteration (benchmarks/calibrate_slip_nodes.py, table E): Newton steps ~ 3 + 6.8 beta (beta: friction_sharpness);
# s per step with N nodes a + b N^2 + c N^3 (dense node tables; a also carries the a-posteriori estimate's share)
SLIP_ITERATIONS = (3.0, 6.8)


SLIP_COST = (5.2e-4, 8.6e-8, 5.7e-10)


TRUNCATIONS = tuple(10.0**-k for k in range(2, 13))


SLIP_NODES = (8, 16, 32, 64, 128, 256, 512)  # requested; the ladder offers the distinct counts that run


# Slip-iteration T' error against the nodes N that run (benchmarks/calibrate_slip_nodes.py, table C, 1024-node
# references): the bound with a margin over the largest ``error N^2/beta`` measured there
SLIP_NODE_ERROR = 1.5  # relative T' error <= SLIP_NODE_ERROR * sharpness / N^2


SLIP_CONVERGENCE = 2.0  # escalation aims at N (estimate / t)^(1/2): the estimate's typical decay


class PolynomialAccuracy(AccuracyModel):
    """Polynomial method: T', a, Delta and a* are exact (Bessel moments); the order limits p(x) and p0.

    Settings: the ``truncation`` (the method picks the order whose neglected coefficients stay below
    it relative to the Hertz slope; the p0 error follows) and, for velocity-dependent friction, the slip
    iteration's ``nodes``.  Counts are the nodes N that run (:func:`slip_nodes`: requests below the law's and the
    pressure's floor run the floor, so the ladder offers each count once).  A priori the T' error is below
    ``SLIP_NODE_ERROR * beta / N^2`` with the law's sharpness ``beta`` (:func:`friction_sharpness`), a bound over
    ``benchmarks/calibrate_slip_nodes.py``'s cases but mostly pessimistic (its table A); a result carries the slip
    iteration's a-posteriori estimate (:func:`rollcontact.line.methods.polynomial.slip.force_error_estimate`), which
    :meth:`achieved` reports.  So :meth:`setting_for` starts at the cheapest count and :meth:`escalation` names
    the count to run next while the estimate misses the tolerance.  An explicit ``order`` has no prediction
    (NaN); the result's truncation residual then gives the estimate.
    """

    floor = POLYNOMIAL_COST

    def ladder(self, scene):
        if scene.friction.is_constant:
            return tuple({"truncation": t} for t in TRUNCATIONS)
        floor = slip_floor(scene)  # slip_nodes per rung, without hashing the scene for each
        return tuple({"nodes": n} for n in sorted({max(n, floor) for n in SLIP_NODES}))

    def cost(self, scene, options):
        base = POLYNOMIAL_COST + POLYNOMIAL_HARMONIC_COST * len(scene.surface.harmonics)
        if scene.friction.is_constant:
            return base
        nodes = slip_nodes(scene, options.get("nodes", DEFAULT_NODES))
        iterations = SLIP_ITERATIONS[0] + SLIP_ITERATIONS[1] * friction_sharpness(scene)
        a, b, c = SLIP_COST
        return base + iterations * (a + b * nodes * nodes + c * nodes**3)

    def minimum_cost(self, scene):
        # with constant friction every setting costs the same: no ladder to build
        return self.cost(scene, {}) if scene.friction.is_constant else super().minimum_cost(scene)

    def error(self, scene, options):
        if options.get("order") is not None:
            return math.nan
        truncation = options.get("truncation", TRUNCATION)
        return max(truncation, SLIP_NODE_ERROR * self.slip_scale(scene, options))

    def achieved(self, scene, options, result, tolerance=None):
        """The truncation residual and, for the slip iteration, its a-posteriori estimate (a Newton step's cost,
        :func:`slip_estimate`); with a ``tolerance`` that the a-priori bound ``SLIP_NODE_ERROR beta/N^2`` of the
        nodes that ran already meets (a converged result), that bound instead: as certain as the estimate (both
        are calibrated on ``benchmarks/calibrate_slip_nodes.py``'s cases, the discretised method is certified by its
        bound alone) and free, where the estimate costs a Newton step (:func:`ran_slip_bound`)."""
        # residual: the first neglected coefficients relative to the leading one (inf when the solve failed)
        if not math.isfinite(result.residual):
            return math.nan
        floor = max(result.residual, ROUND_OFF)
        if tolerance is not None and result.success:
            bound = max(floor, ran_slip_bound(scene, result))
            if bound <= tolerance:
                return bound
        slip = slip_estimate(result)
        return math.nan if math.isnan(slip) else max(floor, slip)

    def free_estimate(self, result):
        """The truncation residual (the slip iteration's estimate, the rest of :meth:`achieved`, costs a Newton
        step)."""
        return result.residual if math.isfinite(result.residual) else math.nan

    def setting_for(self, name, scene, tolerance):
        """For velocity-dependent friction the cheapest count, the start of the adaptive path (:meth:`escalation`
        moves up while the result's estimate misses the tolerance), with the bound of the largest count, which the
        path can reach, as its error; otherwise the cheapest setting whose bound meets the tolerance.

        Starting at the floor rather than where the bound meets t is cheaper: the bound is pessimistic for most
        laws, and escalation from the floor costs little more than the cheapest count whose estimate meets t
        (``benchmarks/calibrate_slip_nodes.py``, table C, the replay of the adaptive path).
        """
        if scene.friction.is_constant:
            # every truncation tolerance costs the same and bounds the error by itself: the loosest one <= t (the
            # ladder walk's answer without its model calls, per auto solve)
            loosest = next((t for t in TRUNCATIONS if t <= tolerance), TRUNCATIONS[-1])
            options = {"truncation": loosest}
            return Setting(name, options, self.error(scene, options), self.cost(scene, options))
        ladder = self.ladder(scene)
        return Setting(name, ladder[0], self.error(scene, ladder[-1]), self.cost(scene, ladder[0]))

    def escalation(self, scene, options, estimate, tolerance) -> dict | None:
        """Options to run next when a result run with ``options`` has error ``estimate`` above ``tolerance``.

        For velocity-dependent friction, the rung expected to meet it: the slip estimate ``E`` at N nodes typically
        falls like ``N^-SLIP_CONVERGENCE`` (``benchmarks/calibrate_slip_nodes.py``, table C), so the first count
        ``>= N (E/t)^(1/SLIP_CONVERGENCE)``, else the largest.  None when the estimate meets the tolerance (or is
        NaN), for Coulomb friction, or when no count of the ladder exceeds N: every call moves up, so escalating
        until None ends.
        """
        if scene.friction.is_constant or not estimate > tolerance:
            return None
        nodes = slip_nodes(scene, options.get("nodes", DEFAULT_NODES))
        larger = [o for o in self.ladder(scene) if o["nodes"] > nodes]
        if not larger:
            return None
        target = nodes * (estimate / tolerance) ** (1.0 / SLIP_CONVERGENCE)
        return next((o for o in larger if o["nodes"] >= target), larger[-1])

    @staticmethod
    def slip_scale(scene, options) -> float:
        """``beta / N^2`` of the nodes N that run (0 when the slip iteration does not)."""
        if scene.friction.is_constant or scene.creep == 0.0:
            return 0.0
        nodes = slip_nodes(scene, options.get("nodes", DEFAULT_NODES))
        return friction_sharpness(scene) / (nodes * nodes)


def slip_estimate(result) -> float:
    """The slip iteration's a-posteriori relative T' error of a polynomial result (NaN when it did not converge;
    0 when it did not run: Coulomb friction, zero creep, or the polynomial method's Coulomb reduction; and 0 on
    several patches, whose estimate is the result's residual,
    :mod:`rollcontact.line.methods.polynomial.patches_slip`)."""
    from rollcontact.line.methods.polynomial.slip import VelocityFrictionDistributions

    dist = result.distributions
    return dist.force_error if isinstance(dist, VelocityFrictionDistributions) else 0.0


def ran_slip_bound(scene, result) -> float:
    """The a-priori T' error bound ``SLIP_NODE_ERROR beta/N^2`` of the N nodes the slip iteration of a polynomial
    result ran (0 where it did not run, as :func:`slip_estimate`)."""
    from rollcontact.line.methods.polynomial.slip import VelocityFrictionDistributions

    dist = result.distributions
    if not isinstance(dist, VelocityFrictionDistributions):
        return 0.0
    return SLIP_NODE_ERROR * friction_sharpness(scene) / dist.nodes**2


def slip_nodes(scene, nodes: int) -> int:
    """Nodes the slip iteration runs for ``nodes`` requested: at least :func:`slip_floor`."""
    return max(int(nodes), slip_floor(scene))


@lru_cache(maxsize=64)
def slip_floor(scene) -> int:
    """Fewest nodes the slip iteration runs for the scene
    (:func:`rollcontact.line.methods.polynomial.slip.effective_nodes` with the scene's pressure; 0 without a polynomial
    normal solution).  Cached: every rung of a ladder asks."""
    from rollcontact.line.methods.polynomial.slip import effective_nodes

    pressure = normal_pressure(scene.normal_load_per_length, scene.radius, scene.material, scene.surface,
                               scene.axis_position)
    if pressure is None:  # no load, or the normal problem failed: nothing to raise against
        return 0
    return effective_nodes(0, pressure, scene.material.contact_modulus, scene.friction, scene.rolling_speed)


@lru_cache(maxsize=32)
def normal_pressure(load, radius, material, surface, axis_position) -> np.ndarray | None:
    """Sine coefficients of p from the polynomial method's normal problem at its default tolerance, or None.

    Cached on the geometry alone (creep, friction and speed do not enter): every rung of a ladder asks for it.  A
    flat surface has Hertz's ``p = p0 sin(theta)`` (eq 9): no normal solve, which the FMU's model would otherwise
    repeat at every step whose load changed.
    """
    from rollcontact.line.hertz import hertz
    from rollcontact.line.methods.polynomial.solver import solve_polynomial

    if surface.is_flat:
        return None if load == 0.0 else np.array([0.0, hertz(load, radius, material.contact_modulus)[1]])
    normal = solve_polynomial(Scene(load, radius=radius, material=material, surface=surface,
                                    axis_position=axis_position), check=False)
    return normal.info.get("pressure_coefficients")
