"""How fast the inputs vary over the contact width: the paper's stationarity measure lambda/a (section 4.3).

:func:`stationarity` is the wavelength of the fastest input variation over the Hertz half-width a, from the first
and second divided differences of the last few input samples (:class:`InputHistory`); above
:data:`STATIONARITY_THRESHOLD` rolling counts as stationary and quasi-steady solutions hold.  A module of its own
because the FMU's stepping model evaluates it every step, also where no instationary model runs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rollcontact.core.checks import check_real

STATIONARITY_THRESHOLD = 20.0
"""lambda/a above which rolling counts as stationary (paper section 4.3: the deviation of the oscillating part
of q from quasi-steady Carter is then below about 2.5/20 = 13 %, docs/physics.md, Instationary rolling)."""


STATIONARY = 1e9
""":func:`stationarity` for constant inputs (and its upper bound)."""


HISTORY_SAMPLES = 3


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
    u' and u'' divided differences of the last three samples (docs/physics.md, Instationary rolling; paper
    section 4.3).  Scales:
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
    # plain floats, no builtins in the arithmetic: this runs every FMU step, also on the closed-form path, the cheapest
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
