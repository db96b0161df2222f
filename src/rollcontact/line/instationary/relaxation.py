"""The relaxation lag (R1): creep-controlled instationary rolling as a first-order lag around Carter.

Closed-form pieces, no grid: the lag's step (:func:`relaxation_step`), its relaxation length, the creep envelope of
the last few relaxation lengths and the lag's error bound for that swing (:func:`lag_error_bound`), used by
:class:`~rollcontact.line.instationary.model.InstationaryModel` (``mode="relaxation"``) and by the FMU's stepping model
to decide when the lag is accurate enough.

The datum
---------
In 2D the tangential displacement ``u = (2/(pi E*)) int q(z) ln(|x - z|/L) dz`` is defined only relative to a
datum distance L (docs/physics.md, Instationary rolling).  Changing L adds ``-(2/(pi E*)) ln(L2/L1) T'(sigma)`` to u
everywhere, so

* **force control** (T'(sigma) given) is datum-free: q(x, sigma) does not depend on L, and the creep found obeys
  ``xi_L2 = xi_L1 + (2/(pi E*)) ln(L2/L1) dT'/dsigma`` (checked by
  ``tests/methods/discretised/test_discretised.py::test_datum_relation_for_force_controlled_transient``);
* **creep control** (xi(sigma) given, what a multibody host supplies) depends on L.  The same relation read
  backwards is a first-order lag: if ``L_1`` is the datum for which the creep of a slowly varying force equals
  the steady (Carter) creep, then for any datum L

  ``xi = xi_steady(T') + (2/(pi E*)) ln(L/L_1) dT'/dsigma``,                                              (R1)

  i.e. ``dT'/dsigma = (xi - xi_steady(T')) / (kappa ln(L/L_1))`` with ``kappa = 2/(pi E*)``.  Linearised at
  T' = 0 (steady slope ``dT'/dxi = pi E* a/2 = a/kappa``) this is a relaxation length ``a ln(L/L_1)``.  ``L_1``
  follows from the discretised force-controlled transient (slow sinusoidal force, least-squares fit of
  ``xi_L - xi_steady`` against ``dT'/dsigma`` for ``T'/(mu N') = 0.1 ... 0.85``), which converges with the grid
  towards ``(sqrt(e)/2) a* = 0.8244 a*`` (a* Carter's stick half-width): ``L_1 = (sqrt(e)/2) a*`` is used
  (:data:`RELAXATION_DATUM_RATIO`), floored at ``0.1 a`` near saturation where a* -> 0.
"""

from __future__ import annotations

import math

from rollcontact.line.carter import carter
from rollcontact.line.hertz import hertz

RELAXATION_DATUM_RATIO = 0.5 * math.sqrt(math.e)
"""``L_1 / a*``: the datum for which slowly varying force control reproduces the steady creep (module docstring,
The datum)."""


RELAXATION_FLOOR = 0.1
"""Lower bound of ``L_1 / a`` (keeps the lag finite at saturation, a* = 0)."""


LAG_ERROR_COEFFICIENT = 0.038
"""C of :func:`lag_error_bound` [1 of mu N' per saturation creep]: 1.4 times the largest ratio of the lag's error
less :data:`LAG_ERROR_FLOOR` to ``(high - low)/2 (1 - d)_+`` at any step of the measured cycle ('ratio' in the table
of ``benchmarks/calibrate_relaxation.py``: creep control ``(mean + amplitude sin) mu a/R`` at lambda/a = 2..320, from
``0.2 + 0.1 sin`` to ``10 sin``, near saturation and wholly in full slip; N' = 1e7 N/m, R = 0.46 m, datum R).  The
lag's error is linear in the swing, largest where the swing passes zero creep, small near saturation and none
wholly in full slip."""


LAG_ERROR_FLOOR = 1e-4
"""e_0 of :func:`lag_error_bound` [1 of mu N']: below it the lag's error is not resolved, being of the order of the
error of the reference pair 200/400 of ``benchmarks/calibrate_relaxation.py`` (its model bound
:data:`~rollcontact.stepping.line.transient.EXTRAPOLATED_ERROR_CONSTANT`/400^2,
``benchmarks/calibrate_transient_pairs.py``)."""


LAG_MEMORY = 8.0
"""Memory of :func:`creep_envelope` in relaxation lengths at T' = 0 (about 35 a for a railway wheel): shorter memories
forget the stiff part of a slow swing while its error persists, and :data:`LAG_ERROR_COEFFICIENT` then has to be
larger; longer ones do not lower it (``benchmarks/calibrate_relaxation.py``)."""


CREEP_RATIO_CAP = 1e6
"""Largest creep ratio ``|xi| / (mu a/R)`` the envelope keeps (far in full slip; keeps its arithmetic finite)."""


STEADY_AFTER = 30.0
"""A step that rolls more than this many relaxation lengths (at T' = 0, the longest) with the inputs held ends in
steady rolling: Carter's force for the lag (:func:`relaxation_step`, exp(-30) of the lag left), and
:meth:`InstationaryModel.steady_state` for the transient, the fixed point its force settles on, from any start, to
round-off within fewer lengths."""


# --------------------------------------------------------------------------------------------- closed-form pieces
def carter_creep(tangential_force_per_length: float, normal_load_per_length: float, radius: float,
                 contact_modulus: float, mu: float) -> float:
    """Steady creep of Carter's solution for a force: the inverse of :func:`rollcontact.line.carter.carter`.

    ``xi = sign(T') (mu a / R) (1 - sqrt(1 - |T'|/(mu N')))`` (eq 17 with ``T' = mu N' (1 - (a*/a)^2)``); the
    saturation creep ``mu a / R`` for ``|T'| >= mu N'``.
    """
    a = hertz(normal_load_per_length, radius, contact_modulus)[0]
    limit = mu * normal_load_per_length
    if limit <= 0.0:
        return 0.0
    ratio = min(1.0, abs(tangential_force_per_length) / limit)
    # 1 - sqrt(1 - y) = y / (1 + sqrt(1 - y)): no cancellation at small force
    return math.copysign(mu * a / radius * ratio / (1.0 + math.sqrt(1.0 - ratio)), tangential_force_per_length)


def relaxation_length(tangential_force_per_length: float, normal_load_per_length: float, radius: float,
                      contact_modulus: float, mu: float, datum_length: float) -> float:
    """Relaxation length [m] of the lag (R1) at a force: ``kappa ln(L/L_1) dT'_steady/dxi``.

    ``L_1 = max(sqrt(e)/2 a*, 0.1 a)`` and ``dT'/dxi = 2 N' R a*/a^2`` (Carter), so at T' = 0 it is
    ``a ln(2 L/(sqrt(e) a))``: docs/physics.md, Instationary rolling, "the datum acts like a relaxation length
    a ln(L/L1)".
    """
    a = hertz(normal_load_per_length, radius, contact_modulus)[0]
    if a == 0.0:
        return 0.0
    a_star = stick_half_width(tangential_force_per_length, normal_load_per_length, a, mu)
    stiffness = 2.0 * radius * (normal_load_per_length / a) * (a_star / a)  # no underflow of N' a*
    return lag_compliance(a, a_star, contact_modulus, datum_length) * stiffness


def stick_half_width(force: float, load: float, half_width: float, mu: float) -> float:
    """Carter's a* for a force: ``a sqrt(1 - |T'|/(mu N'))`` (0 at and beyond saturation)."""
    limit = mu * load
    return half_width * math.sqrt(max(0.0, 1.0 - abs(force) / limit)) if limit > 0.0 else 0.0


def lag_compliance(half_width: float, a_star: float, contact_modulus: float, datum_length: float) -> float:
    """``kappa ln(L / L_1)`` [m/N] of (R1), ``L_1 = max(RELAXATION_DATUM_RATIO a*, RELAXATION_FLOOR a)``."""
    datum_1 = max(RELAXATION_DATUM_RATIO * a_star, RELAXATION_FLOOR * half_width)
    return 2.0 / (math.pi * contact_modulus) * math.log(datum_length / datum_1)


def relaxation_step(force: float, creep: float, distance: float, load: float, radius: float,
                    contact_modulus: float, mu: float, datum_length: float) -> tuple[float, int]:
    """Advance the lag (R1) by a rolled distance; returns ``(T'_new, substeps)``.

    Backward Euler on ``dT'/dsigma = (xi - xi_steady(T')) / C`` with the compliance C frozen per substep (it
    varies only logarithmically); each substep is solved exactly: with ``beta = ds/C``, ``s = mu a/R`` and
    ``|T'| = mu N' (1 - r^2)``, ``T' + beta xi_steady(T') = T'_old + beta xi =: g`` is the quadratic
    ``mu N' r^2 + beta s r - (mu N' + beta s - |g|) = 0`` (sign of T' = sign of g), saturated where
    ``|g| >= mu N' + beta s``.  Substeps of at most a/8 keep the first-order error a small fraction of the lag.  A step
    rolling more than :data:`STEADY_AFTER` relaxation lengths ends on the lag's fixed point, Carter's force.
    """
    a = hertz(load, radius, contact_modulus)[0]
    limit = mu * load
    if limit <= 0.0:
        return 0.0, 0
    force = max(-limit, min(limit, force))
    if distance == 0.0:
        return force, 0
    if distance > STEADY_AFTER * relaxation_length(0.0, load, radius, contact_modulus, mu, datum_length):
        # the lag has relaxed onto its fixed point, Carter's force (T'(0) has the longest length); marching would
        # cost distance / (a/8) substeps for nothing
        return carter(load, creep, radius, contact_modulus, mu)[0], 0
    substeps = max(1, math.ceil(distance / (0.125 * a)))
    ds = distance / substeps
    saturation = mu * a / radius
    for _ in range(substeps):
        a_star = stick_half_width(force, load, a, mu)
        beta = ds / lag_compliance(a, a_star, contact_modulus, datum_length)
        g = force + beta * creep
        top = limit + beta * saturation
        if abs(g) >= top:
            force = math.copysign(limit, g)
            continue
        bs = beta * saturation
        r = (-bs + math.sqrt(bs * bs + 4.0 * limit * (top - abs(g)))) / (2.0 * limit)
        force = math.copysign(limit * (1.0 - r * r), g)
    return force, substeps


# ------------------------------------------------------------------------------------ the lag's error bound
def creep_envelope(envelope: tuple[float, float] | None, creep_ratio: float,
                   memory_distance: float) -> tuple[float, float]:
    """Peak-hold envelope ``(high, low)`` of the creep [1 of Carter's saturation creep mu a/R] after one step.

    ``high <- r + max(0, high - r) exp(-d)`` and ``low <- r - max(0, r - low) exp(-d)``, with r the step's
    creep ratio ``xi / (mu a/R)`` (clipped to +-:data:`CREEP_RATIO_CAP`) and d the distance the step rolls in
    units of the envelope's memory (:data:`LAG_MEMORY` relaxation lengths): the extremes the creep visited over
    the last few relaxation lengths, which is what the lag's error depends on (:func:`lag_error_bound`).  None
    (no history) starts at ``(r, r)``.
    """
    r = max(-CREEP_RATIO_CAP, min(CREEP_RATIO_CAP, creep_ratio))
    if envelope is None:
        return r, r
    shrink = -math.expm1(-memory_distance)  # as the extremes' distance decays by exp(-d), exactly held at d = 0
    high, low = envelope
    return (r if r >= high else high - (high - r) * shrink), (r if r <= low else low + (r - low) * shrink)


def lag_error_bound(envelope: tuple[float, float]) -> float:
    """Bound [1 of mu N'] on the relaxation lag's T' error for a creep that swung over ``envelope``.

    ``C (high - low)/2 (1 - d)_+ + e_0`` with ``C`` = :data:`LAG_ERROR_COEFFICIENT`, d the distance of the envelope
    (:func:`creep_envelope`) from zero creep in saturation creeps and ``e_0`` = :data:`LAG_ERROR_FLOOR`: the lag's
    error is linear in the creep swing and largest where the swing passes the stiff stick regime (Carter's slope,
    relative to that at zero creep, is ``1 - |xi|/(mu a/R)``); a swing wholly in full slip (d >= 1) adds
    nothing, both models give ``mu N'``.
    """
    high, low = envelope
    nearest = 0.0 if low <= 0.0 <= high else min(abs(low), abs(high))
    return LAG_ERROR_COEFFICIENT * 0.5 * (high - low) * max(0.0, 1.0 - nearest) + LAG_ERROR_FLOOR
