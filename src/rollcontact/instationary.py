"""Instationary rolling (paper section 4.3, physics.md section 6): force control, creep control, stationarity.

Conventions are the package's (see :mod:`rollcontact`): x fixed to the contact, material flows in +x, the
leading edge is ``x = -a``, ``s = xi + du/dx + (1/V) du/dt``, in slip ``q = mu p sign(s)``.  ``sigma = V t`` is
the rolled distance [m]; with it the slip is ``s = xi + du/dx + du/dsigma``.  Constant load, Hertz geometry
and Coulomb friction throughout.

The datum
---------
In 2D the tangential displacement ``u = (2/(pi E*)) int q(z) ln(|x - z|/L) dz`` is defined only relative to a
datum distance L.  Changing L adds ``-(2/(pi E*)) ln(L2/L1) T'(sigma)`` to u everywhere, so

* **force control** (T'(sigma) given) is datum-free: q(x, sigma) does not depend on L, and the creep found obeys
  ``xi_L2 = xi_L1 + (2/(pi E*)) ln(L2/L1) dT'/dsigma`` (checked to 1e-9 in
  ``tests/test_discretised.py::test_datum_relation_for_force_controlled_transient``);
* **creep control** (xi(sigma) given, what a multibody host supplies) depends on L.  The same relation read
  backwards is a first-order lag: if ``L_1`` is the datum for which the creep of a slowly varying force equals
  the steady (Carter) creep, then for any datum L

  ``xi = xi_steady(T') + (2/(pi E*)) ln(L/L_1) dT'/dsigma``,                                              (R1)

  i.e. ``dT'/dsigma = (xi - xi_steady(T')) / (kappa ln(L/L_1))`` with ``kappa = 2/(pi E*)``.  Linearised at
  T' = 0 (steady slope ``dT'/dxi = pi E* a/2 = a/kappa``) this is a relaxation length ``a ln(L/L_1)``, the
  physics.md statement.  ``L_1`` was measured with the discretised force-controlled transient (slow sinusoidal
  force, least-squares fit of ``xi_L - xi_steady`` against ``dT'/dsigma``): ``L_1 / a* = 0.834 ... 0.859``
  with 100 elements and ``0.827 ... 0.838`` with 200 elements for ``T'/(mu N') = 0.1 ... 0.85`` (a* Carter's
  stick half-width), converging towards ``sqrt(e)/2 = 0.8244``: ``L_1 = (sqrt(e)/2) a*`` is used
  (:data:`RELAXATION_DATUM_RATIO`), floored at ``0.1 a`` near saturation where a* -> 0.

Default datum.  ``L = R`` (the effective wheel radius), as for :class:`rollcontact.discretised.TransientSolver`:
the logarithm is a half-space idealisation that holds up to distances of the order of the body size and fails
beyond it, so the body size is the natural place to anchor it.  It lies far above the quarter grid length the
discretised creep control needs (grid length ~2.5 a, a << R).  With it the relaxation length at zero force is
``a ln(2R/(sqrt(e) a))`` (about 4.4 a for a = 7 mm, R = 0.46 m).

Models
------
* :class:`InstationaryModel` with ``mode="transient"``: the discretised :class:`TransientSolver` in creep
  control (the reference; ~0.4 ms per step of one element width with n = 100-200).  The grid commits substeps of
  exactly one element; a host step that ends between element boundaries leaves the rest of its roll pending for
  the next, and its output is a provisional substep of that roll (:meth:`InstationaryModel.advance`).
  ``mode="relaxation"``: the lag (R1) around Carter (~50 us per step, mostly bookkeeping).
  :meth:`InstationaryModel.steady_state` gives steady rolling on the transient's grid as the fixed point of the
  whole-element substeps, to switch the transient in mid-run without a jump.  With ``extrapolate=True`` the
  transient runs on two nested grids (n/2 and n elements, both aligned by :func:`aligned_grid_load`, each
  committing its own elements) and reports ``2 T'_n - T'_(n/2)``: their first-order errors cancel and the rest
  falls as n^-2 (``benchmarks/bench_transient_pairs.py``).  Measured against each other
  (``tests/test_instationary.py``, ``benchmarks/bench_instationary.py``): T' within 0.7 % of mu N' for
  lambda/a >= 5 with the default datum (2 % with L = 10 a), where quasi-static Carter is off by 12-78 %.
* Force control, oscillating force ``T' = T0 + T1 sin(2 pi sigma / lambda)``:
  :func:`oscillating_force_chebyshev` (the paper's route: the stick-zone strain is a travelling wave,
  eqs 32-35, solved with the Chebyshev/Jacobi-Anger machinery of the corrugation) and
  :func:`oscillating_force_discretised` (the transient solver; lambda = 0 is the static limit, Cattaneo and
  Mindlin-Deresiewicz).  :func:`quasi_steady_deviation` measures the L2 deviation of the oscillating part of q
  from quasi-steady Carter, about ``2.5 a / lambda``.
* :func:`stationarity`: the wavelength of the fastest input variation over a; stationary above
  :data:`STATIONARITY_THRESHOLD` (20, the paper's rule).
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass, field, replace
from typing import NamedTuple

import numpy as np
from scipy import optimize, special

from rollcontact.closed_form import CarterDistributions, carter, ellipse, hertz
from rollcontact.discretised import Grid, TransientSolver, TransientState, patch_geometry
from rollcontact.friction import Coulomb
from rollcontact.result import ContactResult, Distributions, NoContact, TabulatedDistributions
from rollcontact.scene import check_real

__all__ = ["MODES", "RELAXATION_DATUM_RATIO", "STATIONARITY_THRESHOLD", "STATIONARY", "InputHistory",
           "InstationaryModel", "InstationaryState", "LAG_ERROR_COEFFICIENT", "LAG_MEMORY", "OscillatingForce",
           "carter_creep", "creep_envelope", "lag_error_bound", "oscillating_force_chebyshev",
           "oscillating_force_discretised", "quasi_steady_deviation", "relaxation_length", "stationarity",
           "stationarity_of_samples"]

STATIONARITY_THRESHOLD = 20.0
"""lambda/a above which rolling counts as stationary (paper section 4.3: the deviation of the oscillating part
of q from quasi-steady Carter is then below about 2.5/20 = 13 %, physics.md section 6)."""

STATIONARY = 1e9
""":func:`stationarity` for constant inputs (and its upper bound)."""

RELAXATION_DATUM_RATIO = 0.5 * math.sqrt(math.e)
"""``L_1 / a*``: the datum for which slowly varying force control reproduces the steady creep (module doc)."""

RELAXATION_FLOOR = 0.1
"""Lower bound of ``L_1 / a`` (keeps the lag finite at saturation, a* = 0)."""

LAG_ERROR_COEFFICIENT = 0.038
"""C of :func:`lag_error_bound` [1 of mu N' per saturation creep]: 1.4 times the largest ratio, 0.027, of the lag's
error less :data:`LAG_ERROR_FLOOR` to ``(high - low)/2 (1 - d)_+`` at any step of the measured cycle, over
``benchmarks/bench_relaxation.py`` (creep control ``(mean + amplitude sin) mu a/R`` at lambda/a = 2..320, from
``0.2 + 0.1 sin`` to ``10 sin``, near saturation and wholly in full slip; N' = 1e7 N/m, R = 0.46 m, datum R,
where the relaxation length is 4.35 a).  The lag's error is linear in the swing: 0.7-2.6 % of its amplitude, most
where the swing passes zero creep, 0.2-0.5 % near saturation and none wholly in full slip."""

LAG_ERROR_FLOOR = 1e-4
"""e_0 of :func:`lag_error_bound` [1 of mu N']: below it the lag's error is not resolved (the reference pair
200/400 erred by at most 6.2/400^2 = 3.9e-5 mu N' in ``benchmarks/bench_transient_pairs.py``, and its model allows
30/400^2 = 1.9e-4); at lambda/a = 320 every swing that touched saturation measured 7.5e-5."""

LAG_MEMORY = 8.0
"""Memory of :func:`creep_envelope` in relaxation lengths at T' = 0 (about 35 a for a railway wheel): shorter memories
forget the stiff part of a slow swing while its error persists (at lambda/a = 40, 4 lengths needed C/1.4 = 0.031,
8 need 0.027, longer ones the same to 2 %)."""

CREEP_RATIO_CAP = 1e6
"""Largest creep ratio ``|xi| / (mu a/R)`` the envelope keeps (far in full slip; keeps its arithmetic finite)."""

MODES = ("relaxation", "transient")
HISTORY_SAMPLES = 3
WINDOW_FACTOR = 1.25  # transient grid: +-1.25 a_max
FORCE_MARGIN = 1.0 - 1e-9  # static steps hold |T'| just below the friction limit
STEADY_AFTER = 30.0
"""A step that rolls more than this many relaxation lengths (at T' = 0, the longest) with the inputs held ends in
steady rolling: Carter's force for the lag (:func:`relaxation_step`, exp(-30) of the lag left), and
:meth:`InstationaryModel.steady_state` for the transient: from any start, the force was measured
within 2e-13 mu N' of it after 25 lengths (n = 100, datum R and 100 m, xi from -0.9 to 0.5 of saturation)."""


# --------------------------------------------------------------------------------------------- closed-form pieces
def carter_creep(tangential_force_per_length: float, normal_load_per_length: float, radius: float,
                 contact_modulus: float, mu: float) -> float:
    """Steady creep of Carter's solution for a force: the inverse of :func:`rollcontact.closed_form.carter`.

    ``xi = sign(T') (mu a / R) (1 - sqrt(1 - |T'|/(mu N')))`` (eq 17 with ``T' = mu N' (1 - (a*/a)^2)``); the
    saturation creep ``mu a / R`` for ``|T'| >= mu N'``.
    """
    a = hertz(normal_load_per_length, radius, contact_modulus)[0]
    limit = mu * normal_load_per_length
    if limit <= 0.0:
        return 0.0
    r = math.sqrt(max(0.0, 1.0 - abs(tangential_force_per_length) / limit))
    return math.copysign(mu * a / radius * (1.0 - r), tangential_force_per_length)


def relaxation_length(tangential_force_per_length: float, normal_load_per_length: float, radius: float,
                      contact_modulus: float, mu: float, datum_length: float) -> float:
    """Relaxation length [m] of the lag (R1) at a force: ``kappa ln(L/L_1) dT'_steady/dxi``.

    ``L_1 = max(sqrt(e)/2 a*, 0.1 a)`` and ``dT'/dxi = 2 N' R a*/a^2`` (Carter), so at T' = 0 it is
    ``a ln(2 L/(sqrt(e) a))``: physics.md section 6, "the datum acts like a relaxation length a ln(L/L1)".
    """
    a = hertz(normal_load_per_length, radius, contact_modulus)[0]
    if a == 0.0:
        return 0.0
    a_star = stick_half_width(tangential_force_per_length, normal_load_per_length, a, mu)
    stiffness = 2.0 * normal_load_per_length * radius * a_star / (a * a)
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
    ``|g| >= mu N' + beta s``.  Substeps of at most a/8 keep the first-order error below ~1 % of the lag.  A step
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


# ---------------------------------------------------------------------------------------------- stationarity
@dataclass(frozen=True)
class InputHistory:
    """The last few input samples (oldest first), what :func:`stationarity` needs.

    Attributes
    ----------
    distance : ndarray
        Rolled distance sigma [m] at the samples (non-decreasing).
    normal_load_per_length : ndarray
        N' [N/m].
    creep : ndarray
        xi [1].
    """

    distance: np.ndarray = field(default_factory=lambda: np.zeros(0))
    normal_load_per_length: np.ndarray = field(default_factory=lambda: np.zeros(0))
    creep: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def append(self, distance: float, normal_load_per_length: float, creep: float) -> InputHistory:
        """A new history with the sample added (at most :data:`HISTORY_SAMPLES` kept)."""
        keep = 1 - HISTORY_SAMPLES
        return InputHistory(np.array(self.distance.tolist()[keep:] + [float(distance)]),
                            np.array(self.normal_load_per_length.tolist()[keep:] + [float(normal_load_per_length)]),
                            np.array(self.creep.tolist()[keep:] + [float(creep)]))


def stationarity(history: InputHistory, half_width: float, creep_scale: float) -> float:
    """Wavelength of the fastest input variation over the contact half-width, ``lambda / a`` [1].

    :func:`stationarity_of_samples` of the history's samples (load and creep; the speed does not enter).
    """
    creep_scale = check_real("creep_scale", creep_scale, lower=0.0, lower_open=True, unit="1")
    samples = tuple(zip(history.distance.tolist(), history.normal_load_per_length.tolist(), history.creep.tolist(),
                        (0.0, 0.0, 0.0), strict=False))
    return stationarity_of_samples(samples, half_width, creep_scale)


def stationarity_of_samples(samples, half_width: float, creep_scale: float, speed_varies: bool = False) -> float:
    """Wavelength of the fastest input variation over the contact half-width, ``lambda / a`` [1].

    The one definition of the measure (the FMU's stepping model calls it with its own samples).  For each input u
    with a scale S the local wavenumber along the rolled distance is ``k = max(|u'| / S, sqrt(|u''| / S))`` with
    u' and u'' divided differences of the last three samples (physics.md section 6; paper section 4.3).  Scales:
    the largest of the sampled loads (relative change), ``creep_scale`` for the creep (use Carter's saturation
    creep ``mu a / R``: a variation over it swings T' by mu N') and, with ``speed_varies``, the largest sampled
    speed.  For ``u = u0 + S sin(2 pi sigma / lambda)`` sampled finely, ``2 pi / k`` lies between 1 and 1.3 lambda
    at every phase; an amplitude A < S counts as the longer wavelength ``lambda S / A``, so that
    ``2.5 / stationarity`` estimates the deviation of quasi-steady rolling in units of the full scale.  Compare
    with :data:`STATIONARITY_THRESHOLD`.

    Parameters
    ----------
    samples : sequence of tuple
        Two or three ``(sigma [m], N >= 0, xi [1], V >= 0 [m/s])`` samples, oldest first (N in any unit: only its
        relative changes count); fewer means stationary.
    half_width : float
        Contact half-width a [m] (<= 0: no contact, stationary).
    creep_scale : float
        Creep scale S [1] > 0.
    speed_varies : bool
        Whether speed changes count (velocity-dependent friction).

    Returns
    -------
    float
        ``min(2 pi / (k a), STATIONARY)``; :data:`STATIONARY` (1e9) for constant inputs, fewer than two samples
        or no contact; 0 when an input changes while nothing rolls.
    """
    # plain floats, no builtins in the arithmetic: this runs every FMU step, also on the ~1 us closed-form path
    if len(samples) < 2 or half_width <= 0.0:
        return STATIONARY
    s0, n0, xi0, v0 = samples[-1]
    s1, n1, xi1, v1 = samples[-2]
    s2, n2, xi2, v2 = samples[-3] if len(samples) > 2 else samples[-2]
    varies = speed_varies and not v0 == v1 == v2
    if n0 == n1 == n2 and xi0 == xi1 == xi2 and not varies:
        return STATIONARY
    ds = s0 - s1
    if ds <= 0.0:
        changed = n0 != n1 or xi0 != xi1 or (varies and v0 != v1)
        return 0.0 if changed else STATIONARY
    load_scale = n0 if n0 > n1 else n1  # loads are >= 0
    if n2 > load_scale:
        load_scale = n2
    if load_scale <= 0.0:
        load_scale = 1e-300
    # slopes of the inputs over their scales, over the last step (e_) and the one before (f_)
    e_n, e_xi = (n0 - n1) / (load_scale * ds), (xi0 - xi1) / (creep_scale * ds)
    k = abs(e_n) if abs(e_n) > abs(e_xi) else abs(e_xi)
    e_v = 0.0
    if varies:
        speed_scale = v0 if v0 > v1 else v1
        if v2 > speed_scale:
            speed_scale = v2
        e_v = (v0 - v1) / (speed_scale * ds)
        if abs(e_v) > k:
            k = abs(e_v)
    ds_older = s1 - s2
    if ds_older > 0.0:
        c_n = abs(e_n - (n1 - n2) / (load_scale * ds_older))
        c_xi = abs(e_xi - (xi1 - xi2) / (creep_scale * ds_older))
        curvature = c_n if c_n > c_xi else c_xi
        if varies:
            c_v = abs(e_v - (v1 - v2) / (speed_scale * ds_older))
            if c_v > curvature:
                curvature = c_v
        curvature *= 2.0 / (ds + ds_older)
        if curvature > k * k:
            k = math.sqrt(curvature)
    if k == 0.0:
        return STATIONARY
    measure = 2.0 * math.pi / (k * half_width)
    return measure if measure < STATIONARY else STATIONARY


# -------------------------------------------------------------------------------------------------------- state
@dataclass(frozen=True)
class InstationaryState:
    """Everything an :class:`InstationaryModel` remembers between steps (copy, serialise, restore).

    Attributes
    ----------
    mode : str
        ``"relaxation"`` or ``"transient"`` (a state is only valid for the mode that made it).
    tangential_force_per_length : float
        T' [N/m] after the last step; transient mode: of the committed traction below (the step's result reports
        T' after the pending roll).
    distance : float
        Rolled distance sigma [m] since the initial state.
    steps : int
        Steps taken.
    traction, stick, slip : ndarray
        Transient mode: q_i [Pa], stick mask and slip s_i [1] on the model's grid (see
        :class:`rollcontact.discretised.TransientState`), committed at the last whole-element substep
        (:meth:`InstationaryModel.advance`); empty in relaxation mode.
    history : InputHistory
        Last input samples (for :func:`stationarity`).
    coarse : TransientState or None
        Extrapolating transient mode: the state on the grid of half the elements (its ``steps`` unused).  The
        force above stays the finer grid's, which its traction history needs; the step's result reports the
        extrapolation.  None otherwise.
    pending, coarse_pending : tuple of float
        Transient mode: the roll the model's grid (the coarse grid's) has not committed yet, less than one
        element: its distance [m] and its rigid slip, the integral of xi over it [m].
    """

    mode: str
    tangential_force_per_length: float = 0.0
    distance: float = 0.0
    steps: int = 0
    traction: np.ndarray = field(default_factory=lambda: np.zeros(0))
    stick: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    slip: np.ndarray = field(default_factory=lambda: np.zeros(0))
    history: InputHistory = field(default_factory=InputHistory)
    coarse: TransientState | None = None
    pending: tuple[float, float] = (0.0, 0.0)
    coarse_pending: tuple[float, float] = (0.0, 0.0)

    def copy(self) -> InstationaryState:
        """Deep copy (arrays copied)."""
        return InstationaryState.from_bytes(self.to_bytes())

    def to_bytes(self) -> bytes:
        """Serialise with ``numpy.savez`` (exact: floats are stored as float64)."""
        buffer = io.BytesIO()
        coarse = {} if self.coarse is None else {
            "coarse_traction": self.coarse.traction, "coarse_stick": self.coarse.stick,
            "coarse_slip": self.coarse.slip, "coarse_force": np.float64(self.coarse.tangential_force_per_length)}
        np.savez(buffer, mode=np.array(self.mode), force=np.float64(self.tangential_force_per_length),
                 distance=np.float64(self.distance), steps=np.int64(self.steps), traction=self.traction,
                 stick=self.stick, slip=self.slip, history_distance=self.history.distance,
                 history_load=self.history.normal_load_per_length, history_creep=self.history.creep,
                 pending=np.array(self.pending, dtype=float),
                 coarse_pending=np.array(self.coarse_pending, dtype=float), **coarse)
        return buffer.getvalue()

    @classmethod
    def from_bytes(cls, data: bytes) -> InstationaryState:
        """Restore a state written by :meth:`to_bytes`; ValueError for anything else."""
        try:
            with np.load(io.BytesIO(data), allow_pickle=False) as f:
                coarse = (TransientState(f["coarse_traction"].astype(float), f["coarse_stick"].astype(bool),
                                         f["coarse_slip"].astype(float), float(f["coarse_force"]))
                          if "coarse_traction" in f.files else None)
                return cls(str(f["mode"]), float(f["force"]), float(f["distance"]), int(f["steps"]),
                           f["traction"].astype(float), f["stick"].astype(bool), f["slip"].astype(float),
                           InputHistory(f["history_distance"].astype(float), f["history_load"].astype(float),
                                        f["history_creep"].astype(float)), coarse,
                           *(pending_pair(f[name]) for name in ("pending", "coarse_pending")))
        except (OSError, KeyError, ValueError, TypeError) as exc:
            raise ValueError(f"not a serialised InstationaryState: {exc}") from None

    def transient(self) -> TransientState:
        """The discretised solver's view of this state."""
        return TransientState(self.traction, self.stick, self.slip, self.tangential_force_per_length, self.steps)


def pending_pair(values: np.ndarray) -> tuple[float, float]:
    """A serialised pending roll ``(distance [m], rigid slip [m])``; ValueError for any other shape."""
    if values.shape != (2,):
        raise ValueError(f"a pending roll has two values, got shape {values.shape}")
    return float(values[0]), float(values[1])


# -------------------------------------------------------------------------------------------------------- model
class InstationaryModel:
    """Creep-controlled instationary rolling, one step per call: what an FMU calls each communication step.

    Inputs per step: N' [N/m], xi [1], V [m/s] and dt [s]; the rolled distance of the step is ``V dt`` (zero-order
    hold: the new inputs act over the whole step, as in :meth:`TransientSolver.step`).

    Parameters
    ----------
    radius : float
        Effective radius R [m] > 0.
    contact_modulus : float
        E* [Pa] > 0.
    friction_coefficient : float
        Coulomb mu [1] > 0.
    mode : {"relaxation", "transient"}
        ``"relaxation"``: the lag (R1) around Carter, ``dT'/dsigma = (xi - xi_steady(T'))/(kappa ln(L/L_1))``
        (module docstring); ``"transient"``: the discretised :class:`TransientSolver` in creep control.
    datum_length : float, optional
        Datum L [m] of the tangential displacement (creep control depends on it); default R (module docstring
        explains why).  Transient mode needs L above a quarter of its grid length (2.5 a_max / 4).
    max_normal_load_per_length : float, optional
        Transient mode: the largest N' [N/m] the grid must hold (window +-1.25 a(N'_max)); default 0 means the
        first loaded step's N'.
    elements : int
        Transient mode: grid elements n (default 100).
    extrapolate : bool
        Transient mode: also step a grid of n/2 elements on the same window (n even) and report the first-order
        Richardson extrapolation ``2 T'_n - T'_(n/2)``, clipped to ``|T'| <= mu N'``.  The error of T' is first
        order and regular on nested grids whose patch edges fall on element boundaries (``aligned_grid_load``
        with ``multiple`` = 2), so the extrapolation is far more accurate than either grid (second order,
        ``benchmarks/bench_transient_pairs.py``) for about 1.4 times (1.1-2.0) the cost of the finer one alone.
        Distributions, a* and p0 are the finer grid's.

    Notes
    -----
    ``V = 0`` is the static limit: nothing rolls, the creep has no effect and T' is held (capped by mu N'; the
    transient mode redistributes q by a static force-controlled step when N' changes).  ``N' = 0`` lifts the
    wheel: T' = 0 and the history of q is lost.
    """

    def __init__(self, radius: float, contact_modulus: float, friction_coefficient: float, *,
                 mode: str = "relaxation", datum_length=None, max_normal_load_per_length: float = 0.0,
                 elements: int = 100, extrapolate: bool = False):
        if mode not in MODES:
            raise ValueError(f"unknown mode {mode!r}; valid modes are {list(MODES)}")
        if extrapolate and (mode != "transient" or elements % 2 or elements < 16):
            raise ValueError(f"extrapolate needs mode 'transient' and an even number of elements >= 16, got mode "
                             f"{mode!r} and elements = {elements!r}")
        self.mode = mode
        self.radius = check_real("radius", radius, lower=0.0, lower_open=True, unit="m")
        self.contact_modulus = check_real("contact_modulus", contact_modulus, lower=0.0, lower_open=True, unit="Pa")
        self.mu = check_real("friction_coefficient", friction_coefficient, lower=0.0, lower_open=True, unit="1")
        self.datum_length = (self.radius if datum_length is None
                             else check_real("datum_length", datum_length, lower=0.0, lower_open=True, unit="m"))
        self.max_load = check_real("max_normal_load_per_length", max_normal_load_per_length, lower=0.0, unit="N/m")
        self.elements = elements
        self.extrapolate = bool(extrapolate)
        self.solver: TransientSolver | None = None
        self.coarse_solver: TransientSolver | None = None
        """Extrapolating: the solver on n/2 elements of the same window."""
        self.pressure_cache: dict[tuple[int, float], np.ndarray] = {}
        if mode == "transient" and self.max_load > 0.0:
            self.build_solver(self.max_load)

    def build_solver(self, load: float) -> None:
        """Transient grid for loads up to ``load``: window +-1.25 a(load), datum checked here."""
        a_max = hertz(load, self.radius, self.contact_modulus)[0]
        grid = Grid(-WINDOW_FACTOR * a_max, WINDOW_FACTOR * a_max, self.elements)
        if self.datum_length <= 0.25 * grid.length:
            raise ValueError(f"datum_length = {self.datum_length!r} m is out of range for the transient mode: it must "
                             f"exceed a quarter of the grid length ({0.25 * grid.length!r} m)")
        self.max_load = load
        self.solver, self.coarse_solver = (
            TransientSolver(g, contact_modulus=self.contact_modulus, radius=self.radius, friction=Coulomb(self.mu),
                            datum_length=self.datum_length) if g is not None else None
            for g in (grid, Grid(grid.x_min, grid.x_max, self.elements // 2) if self.extrapolate else None))
        self.pressure_cache = {}

    def solvers(self) -> tuple[TransientSolver, ...]:
        """The transient solvers of the current grid: the model's, then the coarse one when extrapolating."""
        return (self.solver,) if self.coarse_solver is None else (self.solver, self.coarse_solver)

    def initial_state(self) -> InstationaryState:
        """Unloaded, no traction, no history."""
        if self.mode == "transient" and self.solver is not None:
            fine, *coarse = (solver.initial_state() for solver in self.solvers())
            return InstationaryState("transient", traction=fine.traction, stick=fine.stick, slip=fine.slip,
                                     coarse=coarse[0] if coarse else None)
        return InstationaryState(self.mode)

    def steady_state(self, normal_load_per_length: float, creep: float) -> InstationaryState:
        """Transient mode: steady rolling on the grid, the state that holding the inputs keeps unchanged.

        The model commits substeps of exactly one element h (:meth:`advance`); with q and T' unchanged,
        :meth:`TransientSolver.step` gives the slip ``S = xi h - (M - M_h) q`` (the datum term drops out), i.e. the
        steady slip ``s = xi - K_h q`` that :meth:`TransientSolver.steady_state` solves.  So a held step leaves the
        committed state unchanged to the solver's tolerance; its output, a provisional substep of the pending roll,
        ripples with the phase of that roll by O(h^2) (``tests/test_instationary.py``).

        Raises
        ------
        ValueError
            No grid built yet, the load does not fit it, or the active set fails.
        """
        if self.mode != "transient" or self.solver is None:
            raise ValueError("steady_state needs the transient mode with its grid built (build_solver)")
        load = check_real("normal_load_per_length", normal_load_per_length, lower=0.0, lower_open=True, unit="N/m")
        xi = check_real("creep", creep, unit="1")
        fine, *coarse = (self.steady_on(solver, load, xi) for solver in self.solvers())
        return InstationaryState("transient", fine.tangential_force_per_length, traction=fine.traction,
                                 stick=fine.stick, slip=fine.slip, coarse=coarse[0] if coarse else None)

    def steady_on(self, solver: TransientSolver, load: float, xi: float) -> TransientState:
        """:meth:`steady_state` on one of the model's solvers."""
        state, result = solver.steady_state(self.pressure(load, solver), creep=xi)
        if not result.converged:
            raise ValueError(f"steady rolling on the transient grid failed: {result.message}")
        return state

    def regrid(self, state: InstationaryState, grid_load: float) -> InstationaryState:
        """Transient mode: build the grid for ``grid_load`` (larger than the current one's) and carry ``state`` over
        (:func:`remap`, each grid's traction when extrapolating; the pending rolls, shorter than the old elements,
        are shorter than the new ones too)."""
        old = [solver.grid for solver in self.solvers()]
        self.build_solver(grid_load)
        states = (state.transient(),) if state.coarse is None else (state.transient(), state.coarse)
        fine, *coarse = (remap(current, before, solver.grid) for current, before, solver in
                         zip(states, old, self.solvers(), strict=True))
        return InstationaryState("transient", state.tangential_force_per_length, state.distance, state.steps,
                                 fine.traction, fine.stick, fine.slip, state.history, coarse[0] if coarse else None,
                                 state.pending, state.coarse_pending)

    def pressure(self, load: float, solver: TransientSolver | None = None) -> np.ndarray:
        """Discretised normal pressure for N' on ``solver``'s grid (default the model's; cached: constant loads are
        the common case)."""
        solver = self.solver if solver is None else solver
        key = (solver.grid.elements, load)
        p = self.pressure_cache.get(key)
        if p is None:
            normal = solver.normal(load)
            if not normal.converged or normal.contact[0] or normal.contact[-1]:
                raise ValueError(f"normal_load_per_length = {load!r} N/m: the contact does not fit the transient "
                                 f"grid built for max_normal_load_per_length = {self.max_load!r} N/m")
            if len(self.pressure_cache) >= 16:
                self.pressure_cache.pop(next(iter(self.pressure_cache)))
            p = self.pressure_cache[key] = normal.pressure
        return p

    def step(self, state: InstationaryState, normal_load_per_length: float, creep: float, rolling_speed: float,
             dt: float) -> tuple[InstationaryState, ContactResult]:
        """Advance by one communication step.

        Parameters
        ----------
        state : InstationaryState
            State before the step (not modified).
        normal_load_per_length : float
            N' [N/m] >= 0 during the step.
        creep : float
            xi [1] during the step.
        rolling_speed : float
            V [m/s] >= 0 (0: static, nothing rolls).
        dt : float
            Step size [s] > 0.

        Returns
        -------
        state : InstationaryState
        result : ContactResult
            T', a, a*, max p, the creep given; ``info`` has ``distance``, ``stationarity``, ``datum_length``,
            ``relaxation_length`` (relaxation mode) and ``substeps`` (transient mode: 0 when the step rolls more
            than :data:`STEADY_AFTER` relaxation lengths and ends in steady rolling).
        """
        if not isinstance(state, InstationaryState):
            raise TypeError(f"state must be an InstationaryState, got {type(state).__name__}")
        if state.mode != self.mode:
            raise ValueError(f"state of mode {state.mode!r} given to a model of mode {self.mode!r}")
        load = check_real("normal_load_per_length", normal_load_per_length, lower=0.0, unit="N/m")
        xi = check_real("creep", creep, unit="1")
        speed = check_real("rolling_speed", rolling_speed, lower=0.0, unit="m/s")
        dt = check_real("dt", dt, lower=0.0, lower_open=True, unit="s")
        distance = state.distance + speed * dt
        history = state.history.append(distance, load, xi)
        a, p0 = hertz(load, self.radius, self.contact_modulus)
        if load > 0.0 and not a > 0.0:
            raise ValueError(f"normal_load_per_length = {load!r} N/m is too small: the Hertz half-width "
                             "sqrt(4 N' R/(pi E*)) underflows to 0 m, so there is no contact to roll through")
        measure = stationarity(history, a, self.mu * a / self.radius) if a > 0 else STATIONARY
        info = {"distance": distance, "stationarity": measure, "datum_length": self.datum_length}
        if load == 0.0:
            new = InstationaryState(self.mode, 0.0, distance, state.steps + 1,
                                    np.zeros_like(state.traction), np.ones_like(state.stick),
                                    np.zeros_like(state.slip), history)
            return new, ContactResult(method=f"instationary_{self.mode}", success=True, message="no load: no contact",
                                      normal_load_per_length=0.0, tangential_force_per_length=0.0, creep=xi,
                                      contact_half_width=0.0, contact_offset=0.0, stick_half_width=0.0,
                                      max_pressure=0.0, iterations=0, distributions=NoContact(), info=info)
        if self.mode == "relaxation":
            return self.relaxation(state, load, xi, speed * dt, distance, history, a, p0, info)
        return self.transient(state, load, xi, speed * dt, distance, history, info)

    def relaxation(self, state, load, xi, ds, distance, history, a, p0, info):
        force, substeps = relaxation_step(state.tangential_force_per_length, xi, ds, load, self.radius,
                                          self.contact_modulus, self.mu, self.datum_length)
        a_star = stick_half_width(force, load, a, self.mu)
        steady_creep = carter_creep(force, load, self.radius, self.contact_modulus, self.mu)
        info |= {"relaxation_length": relaxation_length(force, load, self.radius, self.contact_modulus, self.mu,
                                                        self.datum_length),
                 "equivalent_steady_creep": steady_creep, "substeps": substeps}
        new = InstationaryState("relaxation", force, distance, state.steps + 1, history=history)
        # q(x): Carter's distribution for the current force (the lag models T', not the shape of q)
        dist = CarterDistributions(a, p0, a_star, 0.0, self.mu, steady_creep if force != 0.0 else 1.0, self.radius)
        return new, ContactResult(method="instationary_relaxation", success=True,
                                  message="first-order lag around Carter (static: force held)" if ds == 0.0
                                  else "first-order lag around Carter", normal_load_per_length=load,
                                  tangential_force_per_length=force, creep=xi, contact_half_width=a,
                                  contact_offset=0.0, stick_half_width=a_star, max_pressure=p0, iterations=substeps,
                                  distributions=dist, info=info)

    def transient(self, state, load, xi, ds, distance, history, info):
        if self.solver is None or load > self.max_load * (1.0 + 1e-12):
            if self.solver is not None:
                raise ValueError(f"normal_load_per_length = {load!r} N/m is out of range: the transient grid holds "
                                 f"loads up to max_normal_load_per_length = {self.max_load!r} N/m")
            self.build_solver(load)
            state = replace(self.initial_state(), distance=state.distance, steps=state.steps, history=state.history)
        solver = self.solver
        if state.traction.shape != (solver.grid.elements,):
            raise ValueError(f"state has {state.traction.size} traction values, the model's grid "
                             f"{solver.grid.elements} elements")
        if (state.coarse is None) == self.extrapolate:
            raise ValueError("state and model differ in extrapolation: a state of an extrapolating model carries the "
                             "coarse grid's traction, any other none")
        # beyond 1e6 saturation creeps every element slips whatever the elastic slip (~ mu a/R ln n): the same
        # step, without overflow in xi ds
        cap = 1e6 * self.mu * hertz(self.max_load, self.radius, self.contact_modulus)[0] / self.radius
        creep = max(-cap, min(cap, xi))
        # the step ends in steady rolling: marching would cost ds/h substeps for nothing
        steady = ds > STEADY_AFTER * relaxation_length(0.0, load, self.radius, self.contact_modulus, self.mu,
                                                       self.datum_length)
        fine = self.advance(solver, state.transient(), state.pending, load, creep, ds, steady)
        substeps, iterations, converged, messages = fine.substeps, fine.iterations, fine.converged, fine.messages
        force = fine.output.tangential_force_per_length
        coarse = None
        if self.extrapolate:
            coarse = self.advance(self.coarse_solver, state.coarse, state.coarse_pending, load, creep, ds, steady)
            iterations += coarse.iterations
            converged &= coarse.converged
            messages += coarse.messages
            # first-order Richardson on nested grids (h halved), within the friction limit mu N'
            limit = self.mu * load
            force = max(-limit, min(limit, 2.0 * force - coarse.output.tangential_force_per_length))
            info |= {"fine_force": fine.output.tangential_force_per_length,
                     "coarse_force": coarse.output.tangential_force_per_length}
        p = self.pressure(load)
        h = solver.grid.element_width
        a, offset, _ = patch_geometry(solver.grid, p > 0)
        info |= {"substeps": substeps, "dissipation": fine.dissipation, "grid": solver.grid}
        committed = fine.committed
        new = InstationaryState("transient", committed.tangential_force_per_length, distance, state.steps + 1,
                                committed.traction, committed.stick, committed.slip, history,
                                None if coarse is None else coarse.committed, fine.pending,
                                (0.0, 0.0) if coarse is None else coarse.pending)
        message = ("discretised transient, creep control" if ds > 0.0 else
                   "discretised transient, static step (force held)") if converged else "; ".join(messages)
        if self.extrapolate:
            message += f", extrapolated from n = {self.coarse_solver.grid.elements}/{solver.grid.elements}"
        if steady:
            message += " (rolled into steady rolling)"
        output = fine.output
        slip = np.where(p > 0, output.slip, np.nan)
        return new, ContactResult(method="instationary_transient", success=converged, message=message,
                                  normal_load_per_length=load, tangential_force_per_length=force, creep=xi,
                                  contact_half_width=a, contact_offset=offset,
                                  stick_half_width=0.5 * h * int((output.stick & (p > 0)).sum()),
                                  max_pressure=float(p.max()), iterations=iterations,
                                  distributions=TabulatedDistributions(solver.grid.centres, p, output.traction,
                                                                       slip), info=info)

    def advance(self, solver: TransientSolver, current: TransientState, pending: tuple[float, float], load: float,
                creep: float, ds: float, steady: bool) -> Advance:
        """One step of ``solver`` rolling ``ds`` [m] from the committed state ``current`` and its ``pending`` roll.

        The grid commits substeps of exactly one element h: the convected traction then moves by whole elements,
        and the pair's extrapolation cancels the first-order error cleanly.  Substeps of a fraction r of an element
        (what splitting each host step into equal substeps gives) leave an O(h^2) bias that varies erratically with
        r: on the same grids the pair's ``error n^2`` was 4.4-26 with equal substeps and is 2.5-5.3 with whole
        elements (``benchmarks/bench_substep_rule.py``).  A host step that ends between element boundaries leaves
        a pending roll, its distance and rigid slip (the creep integrated over it, each host step's creep held over
        its part); the next steps complete it.  The step's output is a provisional substep of the pending roll from
        the committed state, not kept: its error is one step's, which ripples with the roll's phase by O(h^2) and
        does not accumulate.  ``ds`` = 0 (a static step) first commits the pending roll as one short substep, then
        redistributes q at the held force.  ``steady``: straight to steady rolling, nothing pending.
        """
        p = self.pressure(load, solver)
        h = solver.grid.element_width
        if steady:
            current = self.steady_on(solver, load, creep)
            return Advance(current, (0.0, 0.0), current, 0, 0, ds * h * float(np.dot(current.traction, current.slip)),
                           True, [])
        run = Run()
        distance, rigid = pending
        if ds > 0.0:
            rest = ds
            while distance + rest >= h * (1.0 - 1e-12):
                take = min(rest, max(0.0, h - distance))
                distance, rigid, rest = distance + take, rigid + creep * take, rest - take
                # exactly h (the roll may fall short by round-off): one convected matrix for every commit
                current = run.add(*solver.step(current, p, h, creep=rigid / distance))
                distance = rigid = 0.0
            distance, rigid = distance + rest, rigid + creep * rest
            output = current
            if distance > 1e-9 * h:
                output, res = solver.step(current, p, distance, creep=rigid / distance)
                run.add(output, res, committed=False)
            return Advance(current, (distance, rigid), output, run.substeps, run.iterations, run.dissipation,
                           run.converged, run.messages)
        if distance > 0.0:
            current = run.add(*solver.step(current, p, distance, creep=rigid / distance))
        held = current.tangential_force_per_length
        if abs(held) >= FORCE_MARGIN * h * self.mu * p.sum():
            # saturated: full slip, which force control (it needs a stick element) cannot represent
            q = math.copysign(self.mu, held) * p
            current = TransientState(q, np.zeros(q.size, dtype=bool), np.zeros(q.size), h * q.sum(), current.steps + 1)
        else:
            current = run.add(*solver.step(current, p, 0.0, tangential_force=held))
        return Advance(current, (0.0, 0.0), current, max(1, run.substeps), run.iterations, run.dissipation,
                       run.converged, run.messages)


class Advance(NamedTuple):
    """What :meth:`InstationaryModel.advance` returns for one grid."""

    committed: TransientState
    """State after the last whole-element substep (what the next step starts from)."""
    pending: tuple[float, float]
    """The roll not yet committed: distance [m] (less than one element) and rigid slip, xi integrated over it [m]."""
    output: TransientState
    """State at the end of the host step: the committed one after a provisional substep of the pending roll."""
    substeps: int
    """Solves of the step, the provisional one included (0 when it rolled into steady rolling)."""
    iterations: int
    """Active-set iterations of those solves."""
    dissipation: float
    """Frictional work [J/m] of the committed substeps (a pending roll's with the substep that commits it)."""
    converged: bool
    """Every solve converged."""
    messages: list[str]
    """The messages of those that did not."""


class Run:
    """Tally of the solves of one :meth:`InstationaryModel.advance`."""

    def __init__(self):
        self.substeps, self.iterations, self.dissipation, self.converged, self.messages = 0, 0, 0.0, True, []

    def add(self, state: TransientState, res, committed: bool = True) -> TransientState:
        """Count one solve (its work only when ``committed``); returns its state."""
        self.substeps += 1
        self.iterations += res.iterations
        if committed:
            self.dissipation += res.dissipation
        self.converged &= res.converged
        if not res.converged:
            self.messages.append(res.message)
        return state


def remap(state: TransientState, old: Grid, new: Grid) -> TransientState:
    """A transient state carried from grid ``old`` to the larger window ``new``.

    q is piecewise constant, so its integral from the window's start is piecewise linear: the new elements take
    the averages of q over them (a conservative remap: T' is kept, q is smeared over at most one old element).
    The stick mask is taken at the nearest old element (it only warm-starts the active set); the slip is reset
    (Coulomb friction does not use it).
    """
    integral = np.concatenate(([0.0], np.cumsum(state.traction) * old.element_width))
    old_edges = np.linspace(old.x_min, old.x_max, old.elements + 1)
    new_edges = np.linspace(new.x_min, new.x_max, new.elements + 1)
    traction = np.diff(np.interp(new_edges, old_edges, integral)) / new.element_width
    stick = np.interp(new.centres, old.centres, state.stick.astype(float)) >= 0.5
    return TransientState(traction, stick, np.zeros(new.elements), state.tangential_force_per_length, state.steps)


def aligned_grid_load(load: float, elements: int, factor: float, multiple: int = 1) -> float:
    """Grid load [N/m] near ``factor * load`` whose window puts the edges of the Hertz patch of ``load`` on element
    boundaries.

    The window ``+-W = +-1.25 a(grid load)`` of n elements ``h = 2W/n`` has the patch edges ``+-a`` on element
    boundaries when ``(W - a)/h = m`` is an integer, i.e. ``W = a / (1 - 2m/n)``; m is rounded from
    ``W = 1.25 sqrt(factor) a`` and ``a ~ sqrt(N')`` gives the load.  Then the discretised patch covers whole elements
    and the steady force converges regularly, ``|T'_n - T'_Carter| = 0.57/n mu N'`` for factor 2; with the edges
    inside elements it scatters up to 4e-3 mu N' for n = 50..400 (``benchmarks/bench_transient_auto.py``).  Grids
    of fewer than three elements cannot be aligned: ``factor * load``.  With ``multiple`` = 2, m is even, so that
    the grid of n/2 elements on the same window is aligned too (the extrapolating transient).
    """
    ratio = WINDOW_FACTOR * math.sqrt(factor)  # W / a wanted
    m = multiple * round(0.5 * elements * (1.0 - 1.0 / ratio) / multiple)
    if not 0 < 2 * m < elements:
        return factor * load
    return load * (1.0 / (WINDOW_FACTOR * (1.0 - 2.0 * m / elements))) ** 2


# ---------------------------------------------------------------------------------------- force control
@dataclass(frozen=True)
class OscillatingForce:
    """``T'(sigma) = mean + amplitude sin(2 pi sigma / wavelength)`` [N/m] over the rolled distance sigma [m].

    ``wavelength = 0`` is the static limit (V -> 0 at a fixed frequency): then sigma stands for the phase times
    one, and nothing rolls.  ``wavelength = inf`` is steady rolling at the mean force.
    """

    mean: float
    amplitude: float
    wavelength: float

    def __post_init__(self):
        for name in ("mean", "amplitude"):
            object.__setattr__(self, name, check_real(name, getattr(self, name), unit="N/m"))
        try:
            w = float(self.wavelength)
        except (TypeError, ValueError):
            raise ValueError(f"wavelength must be a real number in m, got {self.wavelength!r}") from None
        if not w >= 0.0:
            raise ValueError(f"wavelength = {w!r} m is out of range: it must be >= 0 (0 static, inf steady)")
        object.__setattr__(self, "wavelength", w)

    def at_phase(self, phase):
        """T' [N/m] at the phase ``sigma / wavelength`` (fraction of a cycle); the mean for an infinite wavelength."""
        amplitude = 0.0 if math.isinf(self.wavelength) else self.amplitude
        return self.mean + amplitude * np.sin(2.0 * np.pi * np.asarray(phase, dtype=float))


def check_force(force: OscillatingForce, load: float, mu: float) -> None:
    if not isinstance(force, OscillatingForce):
        raise TypeError(f"force must be an OscillatingForce, got {type(force).__name__}")
    peak = abs(force.mean) + abs(force.amplitude)
    if peak >= mu * load:
        raise ValueError(f"force peak |T0| + |T1| = {peak!r} N/m is out of range: it must stay below mu N' = "
                         f"{mu * load!r} N/m")


def oscillating_force_discretised(normal_load_per_length: float, force: OscillatingForce, *, radius: float,
                                  contact_modulus: float, mu: float, phases: int = 16, elements: int = 200,
                                  datum_length=None, cycles=None) -> tuple[ContactResult, ...]:
    """q(x) for an oscillating force by the discretised transient solver (force control, datum-free q).

    Starts from steady rolling at ``T'(0)`` (static: from the unloaded state, loaded to ``T'(0)`` in 20 static
    steps), rolls ``cycles`` cycles (default: 2, more when the wavelength is shorter than the contact so that
    ~3 contact lengths pass) in steps of at most one element width and at least 64 per cycle, and
    returns the last cycle at ``phases`` equally spaced phases.  ``wavelength = inf`` gives the steady state.

    Returns
    -------
    tuple of ContactResult
        One per phase, method ``"instationary_discretised"``; ``creep`` is the creep for ``datum_length``
        (default R; NaN for static steps); ``info`` holds ``phase``, ``distance`` and ``dissipation_per_cycle``
        [J/m] (frictional work of the last cycle, datum-free).
    """
    load = check_real("normal_load_per_length", normal_load_per_length, lower=0.0, lower_open=True, unit="N/m")
    check_force(force, load, mu)
    a, _ = hertz(load, radius, contact_modulus)
    grid = Grid(-WINDOW_FACTOR * a, WINDOW_FACTOR * a, elements)
    solver = TransientSolver(grid, contact_modulus=contact_modulus, radius=radius, datum_length=datum_length)
    p = solver.normal(load).pressure
    lam = force.wavelength
    h = grid.element_width
    if math.isinf(lam):
        state, res = solver.steady_state(p, tangential_force=force.mean)
        return tuple(discretised_result(solver, p, state, res.creep, res.converged, res.message,
                                        {"phase": j / phases, "distance": math.inf, "dissipation_per_cycle": 0.0})
                     for j in range(phases))
    per_phase = max(math.ceil(64 / phases), math.ceil(lam / (phases * h)))
    ds = lam / (phases * per_phase)
    if cycles is None:
        cycles = 2 if lam == 0.0 else max(2, math.ceil(6.0 * a / lam) + 1)
    if lam == 0.0:
        state = solver.initial_state()
        for k in range(1, 21):
            state, res = solver.step(state, p, 0.0, tangential_force=float(force.at_phase(0.0)) * k / 20)
    else:
        state, res = solver.steady_state(p, tangential_force=float(force.at_phase(0.0)))
    out, energy, ok, message = [], 0.0, res.converged, res.message
    total = cycles * phases * per_phase
    for k in range(1, total + 1):
        phase = k / (phases * per_phase)
        state, res = solver.step(state, p, ds, tangential_force=float(force.at_phase(phase)))
        ok &= res.converged
        message = res.message if not res.converged else message
        if k > total - phases * per_phase:
            energy += res.dissipation
            if k % per_phase == 0:
                out.append((state, res.creep, round(phase % 1.0, 12), phase * lam))
    out.sort(key=lambda entry: entry[2])
    return tuple(discretised_result(solver, p, s, creep, ok, message,
                                    {"phase": ph, "distance": dist, "dissipation_per_cycle": energy})
                 for s, creep, ph, dist in out)


def discretised_result(solver, p, state, creep, converged, message, info) -> ContactResult:
    grid = solver.grid
    a, offset, _ = patch_geometry(grid, p > 0)
    h = grid.element_width
    return ContactResult(method="instationary_discretised", success=bool(converged), message=message,
                         normal_load_per_length=h * float(p.sum()),
                         tangential_force_per_length=state.tangential_force_per_length, creep=creep,
                         contact_half_width=a, contact_offset=offset,
                         stick_half_width=0.5 * h * int((state.stick & (p > 0)).sum()), max_pressure=float(p.max()),
                         iterations=state.steps, distributions=TabulatedDistributions(
                             grid.centres, p, state.traction, np.where(p > 0, state.slip, np.nan)),
                         info=info | {"grid": grid})


@dataclass(frozen=True)
class TravellingWaveDistributions(Distributions):
    """Hertz pressure and ``q = sign (mu p + q2)``, ``q2 = sum d_n sin(n theta*)`` on the stick zone."""

    a: float
    p0: float
    mu: float
    sign: float
    stick_half_width: float
    stick_coefficients: np.ndarray  # d_n [Pa], index 0 unused

    def pressure(self, x):
        return self.p0 * ellipse(np.asarray(x, dtype=float), self.a)

    def traction(self, x):
        x = np.asarray(x, dtype=float)
        b = self.stick_half_width
        q = self.mu * self.pressure(x)
        if b > 0.0:
            t = (x + self.a - b) / b
            inside = np.abs(t) <= 1.0
            theta = np.arccos(np.clip(t, -1.0, 1.0))
            n = np.arange(1, self.stick_coefficients.size)
            q = q + np.where(inside, np.sin(np.multiply.outer(theta, n)) @ self.stick_coefficients[1:], 0.0)
        return self.sign * q

    def slip(self, x):
        return np.full_like(np.asarray(x, dtype=float), np.nan)


class TravellingWave:
    """Stick-zone condition of the paper's route, dimensionless (lengths over a, strains over mu a / R).

    In the stick zone ``Du/Dsigma = du/dsigma + du/dx = -xi(sigma)``: the strain is convected with the material,
    ``du/dx = U'(x - sigma)`` (eqs 32-35), a travelling wave.  For a force of wavelength lambda
    (``k = 2 pi a / lambda``) it is ``U'(zeta) = -xi_bar + sum_m Re(C_m e^{i m k zeta})``.  With
    ``du/dx = (2/(pi E*)) PV-int q/(x - z) dz``, ``q = mu p + q2`` and ``x = -a + b (1 + t)`` on the stick zone
    of half-width b, ``(1/pi) PV-int q2/(x - z) dz = sum d_n T_n(t)`` (chebyshev.py) gives, by Jacobi-Anger,

    ``r_0 = -xi_bar - x_s + sum_m Re(C_m e^{i m k (x_s - sigma)}) J_0(m k b)``   (must vanish: bounded q2)
    ``r_n = sum_m Re(C_m e^{i m k (x_s - sigma)} 2 i^n J_n(m k b)) - b delta_n1``,  ``d_n = mu p0 r_n``,

    ``x_s = -1 + b`` the stick centre, and ``T'/(mu N') = 1 + b r_1`` (Carter: r_1 = -b).  These are eqs 30-31 of
    the corrugation with the surface slope replaced by the convected strain.
    """

    def __init__(self, wavenumber: float, harmonics: int, order: int):
        self.k = wavenumber
        self.m = np.arange(1, harmonics + 1)
        self.n = np.arange(order + 1)
        self.ipow = 1j ** self.n

    def coefficients(self, b: float, sigma: float, xi_bar: float, c: np.ndarray) -> np.ndarray:
        """``[r_0, ..., r_order]`` at stick half-width b and phase distance sigma (both over a)."""
        xs = -1.0 + b
        km = self.m * self.k
        rot = c * np.exp(1j * km * (xs - sigma))
        jn = special.jv(self.n[:, None], km[None, :] * b)
        eps = np.where(self.n == 0, 1.0, 2.0)
        r = np.real(eps * self.ipow * (jn @ rot))
        r[0] += -xi_bar - xs
        if r.size > 1:
            r[1] -= b
        return r

    def low(self, b, sigma, xi_bar: float, c: np.ndarray):
        """``(r_0, r_1)`` vectorised over b and sigma (broadcast)."""
        b, sigma = np.broadcast_arrays(np.asarray(b, dtype=float), np.asarray(sigma, dtype=float))
        km = self.m * self.k
        xs = -1.0 + b
        rot = c * np.exp(1j * km * (xs[..., None] - sigma[..., None]))
        z = km * b[..., None]
        r0 = np.real(np.sum(rot * special.j0(z), axis=-1)) - xi_bar - xs
        r1 = np.real(np.sum(rot * 2j * special.j1(z), axis=-1)) - b
        return r0, r1

    def stick_width(self, sigma: float, xi_bar: float, c: np.ndarray) -> float:
        """Root b in (0, 1) of r_0 (NaN when there is none or more than one sign change on a fine scan)."""
        bs = np.linspace(1e-6, 1.0, 201)
        r0 = self.low(bs, sigma, xi_bar, c)[0]
        changes = np.flatnonzero(np.sign(r0[:-1]) != np.sign(r0[1:]))
        if changes.size != 1:
            return math.nan
        i = changes[0]
        return optimize.brentq(lambda b: float(self.low(b, sigma, xi_bar, c)[0]), bs[i], bs[i + 1], xtol=1e-14)


def oscillating_force_chebyshev(normal_load_per_length: float, force: OscillatingForce, *, radius: float,
                                contact_modulus: float, mu: float, phases: int = 16, harmonics: int = 8,
                                order: int = 40) -> tuple[ContactResult, ...]:
    """q(x) for an oscillating force by the paper's route (section 4.3, eqs 32-35), with validity checks.

    Unknowns: the travelling wave ``U'`` (``xi_bar`` and ``C_1..C_M``, see :class:`TravellingWave`) and the stick
    half-widths b_j at ``2M + 1`` collocation phases; equations: ``r_0(b_j) = 0`` and ``T'(b_j) = T'(sigma_j)``,
    solved by least squares from the quasi-steady guess (``U'`` = minus the Carter creep of the force at which the
    material entered the patch).  Then b is found at each output phase from ``r_0 = 0`` alone and the force
    misfit there is the ``residual`` (the truncation error of M harmonics, relative to mu N').

    The route assumes one stick zone at the leading edge whose material all entered through the leading edge.
    It is reported as failed (``success=False``, message naming the phase) when: T' changes sign; the stick zone
    vanishes or fills the patch (no root b in (0, a), or several); ``|q| > mu p`` in the stick zone; the rear
    stick boundary overtakes the material (``2 db/dsigma >= 1``: slipped material would be caught again, its
    strain is then no longer the travelling wave); the solve does not converge.  The slip direction in the slip
    zone is not checked here (it needs du/dt there); the agreement with :func:`oscillating_force_discretised`
    covers it in the tests.

    Returns
    -------
    tuple of ContactResult
        One per output phase (method ``"instationary_chebyshev"``); ``creep`` is NaN (it needs a datum:
        paper eq 33-34, physics.md section 6); ``info``: ``phase``, ``distance``, ``xi_bar`` (mean stick strain,
        over mu a/R), ``wave`` (C_m), ``rear_boundary_speed`` (max 2 db/dsigma).
    """
    load = check_real("normal_load_per_length", normal_load_per_length, lower=0.0, lower_open=True, unit="N/m")
    check_force(force, load, mu)
    if not 0.0 < force.wavelength:
        raise ValueError(f"wavelength = {force.wavelength!r} m is out of range: the paper's route needs rolling, "
                         "wavelength > 0 (use oscillating_force_discretised for the static limit)")
    a, p0 = hertz(load, radius, contact_modulus)
    limit = mu * load
    lam = force.wavelength / a if math.isfinite(force.wavelength) else 0.0  # sigma per phase, over a
    k = 2.0 * math.pi / lam if lam > 0.0 else 0.0
    harmonics = harmonics if k > 0.0 else 0
    sign = math.copysign(1.0, force.mean)
    wave = TravellingWave(k, harmonics, order)

    def target(phase):
        return sign * force.at_phase(phase) / limit

    sign_change = force.amplitude != 0.0 and abs(force.amplitude) >= abs(force.mean)
    # quasi-steady guess: the material at zeta entered at the leading edge at sigma_e = -1 - zeta
    fine = np.arange(256) / 256
    steady_strain = -(1.0 - np.sqrt(np.clip(1.0 - target(fine), 0.0, None)))
    if harmonics:
        zeta = -1.0 - fine * lam
        basis = np.column_stack([np.ones_like(zeta)] + [f(m * k * zeta) for m in wave.m for f in (np.cos, np.sin)])
        fit = np.linalg.lstsq(basis, steady_strain, rcond=None)[0]
    else:
        fit = np.array([steady_strain[0]])
    colloc = np.arange(2 * harmonics + 1) / (2 * harmonics + 1)
    b0 = np.sqrt(np.clip(1.0 - target(colloc), 1e-6, 1.0))

    def unpack(z):
        c = z[1:1 + 2 * harmonics:2] - 1j * z[2:1 + 2 * harmonics:2]
        return -z[0], c

    targets = target(colloc)

    def residuals(z):
        xi_bar, c = unpack(z[:1 + 2 * harmonics])
        b = z[1 + 2 * harmonics:]
        r0, r1 = wave.low(b, colloc * lam, xi_bar, c)
        return np.concatenate((r0, 1.0 + b * r1 - targets))

    z = np.concatenate((fit, b0))
    problems, evaluations = [], 0
    if sign_change:
        problems.append("T' changes sign over the cycle (the slip-zone traction direction flips)")
    else:
        lower = np.concatenate((np.full(fit.size, -np.inf), np.full(b0.size, 1e-9)))
        upper = np.concatenate((np.full(fit.size, np.inf), np.ones(b0.size)))
        sol = optimize.least_squares(residuals, z, bounds=(lower, upper), xtol=1e-14, ftol=1e-14, gtol=1e-14,
                                     max_nfev=200)
        z, evaluations = sol.x, sol.nfev
        if np.abs(sol.fun).max() > 1e-8:
            problems.append(f"collocation did not converge (residual {np.abs(sol.fun).max():.2e})")
    xi_bar, c = unpack(z[:1 + 2 * harmonics])
    # stick widths on a fine phase grid: existence and the speed of the rear boundary
    dense = np.arange(8 * phases) / (8 * phases)
    widths = np.array([wave.stick_width(ph * lam, xi_bar, c) for ph in dense]) if harmonics else \
        np.full(dense.size, z[-1])
    if not np.all(np.isfinite(widths)) or widths.min() <= 1e-6 or widths.max() >= 1.0 - 1e-9:
        bad = dense[~np.isfinite(widths) | (widths <= 1e-6) | (widths >= 1.0 - 1e-9)]
        problems.append(f"no single stick zone inside the patch at phase {bad[0]:.3f} (full slip, full stick or "
                        "several roots)")
    speed = 0.0
    if harmonics and np.all(np.isfinite(widths)):
        speed = float(np.max(2.0 * np.diff(np.append(widths, widths[0])) / (lam / dense.size)))
        if speed >= 1.0:
            problems.append(f"the rear stick boundary overtakes the material (2 db/dsigma = {speed:.3f} >= 1): "
                            "slipped material is caught again and its strain is not the travelling wave")
    results = []
    x = np.linspace(-a, a, 801)
    for j in range(phases):
        phase = j / phases
        b = widths[8 * j]
        r = wave.coefficients(b, phase * lam, xi_bar, c) if np.isfinite(b) else np.zeros(order + 1)
        dist = TravellingWaveDistributions(a, p0, mu, sign, b * a if np.isfinite(b) else 0.0, mu * p0 * r)
        t = sign * dist.traction(x)
        bound = mu * dist.pressure(x)
        local = list(problems)
        if np.any(np.abs(t) > bound * (1.0 + 1e-6) + 1e-9 * mu * p0):
            local.append(f"|q| > mu p in the stick zone at phase {phase:.3f}")
        force_found = sign * limit * (1.0 + b * r[1]) if np.isfinite(b) else math.nan
        misfit = abs(force_found - float(force.at_phase(phase))) / limit
        message = "; ".join(local) if local else "travelling-wave stick zone at the leading edge"
        results.append(ContactResult(
            method="instationary_chebyshev", success=not local, message=message, normal_load_per_length=load,
            tangential_force_per_length=force_found, creep=math.nan, contact_half_width=a, contact_offset=0.0,
            stick_half_width=b * a if np.isfinite(b) else 0.0, max_pressure=p0, iterations=int(evaluations),
            residual=misfit, distributions=dist,
            info={"phase": phase, "distance": phase * force.wavelength, "xi_bar": xi_bar, "wave": c,
                  "rear_boundary_speed": speed}))
    return tuple(results)


def quasi_steady_deviation(results, mean_force: float, *, radius: float, contact_modulus: float, mu: float,
                           points: int = 801) -> float:
    """L2 deviation of the oscillating part of q from quasi-steady Carter (physics.md section 6).

    ``||q(x, sigma) - q_C(x; T'(sigma))|| / ||q_C(x; T'(sigma)) - q_C(x; T0)||`` over the phases of ``results``
    and ``points`` points across the patch, q_C Carter's distribution at the same force (T'(sigma) is taken
    from each result).  About ``2.5 a / lambda``.
    """
    num = den = 0.0
    for r in results:
        load = r.normal_load_per_length
        a, p0 = hertz(load, radius, contact_modulus)
        x = np.linspace(-a, a, points)
        q_c = carter_traction(x, r.tangential_force_per_length, load, a, p0, radius, contact_modulus, mu)
        q_0 = carter_traction(x, mean_force, load, a, p0, radius, contact_modulus, mu)
        num += float(np.sum((r.traction(x) - q_c) ** 2))
        den += float(np.sum((q_c - q_0) ** 2))
    return math.sqrt(num / den)


def carter_traction(x, force, load, a, p0, radius, contact_modulus, mu):
    """Carter's q(x) at a force (via its creep), centred patch."""
    xi = carter_creep(force, load, radius, contact_modulus, mu)
    a_star = carter(load, xi, radius, contact_modulus, mu)[1]
    return CarterDistributions(a, p0, a_star, 0.0, mu, xi if xi != 0.0 else 1.0, radius).traction(x) \
        if force != 0.0 else np.zeros_like(x)
