"""Instationary rolling (paper section 4.3): the contact when the inputs vary over a few contact widths.

* :mod:`.relaxation`: the relaxation lag (R1) around Carter, its relaxation length and its error bound;
* :mod:`.stationarity`: how fast the inputs vary over the contact width (the paper's lambda/a);
* :mod:`.model`: :class:`InstationaryModel`, creep-controlled rolling step by step, by the lag or by the
  discretised transient (explicit state);
* :mod:`.oscillating`: an oscillating force, by the paper's travelling wave and by the discretised transient.
"""

from rollcontact.line.instationary.model import MODES, InstationaryModel, InstationaryState, aligned_grid_load
from rollcontact.line.instationary.oscillating import (
    OscillatingForce,
    oscillating_force_chebyshev,
    oscillating_force_discretised,
    quasi_steady_deviation,
)
from rollcontact.line.instationary.relaxation import (
    CREEP_RATIO_CAP,
    LAG_ERROR_COEFFICIENT,
    LAG_ERROR_FLOOR,
    LAG_MEMORY,
    RELAXATION_DATUM_RATIO,
    STEADY_AFTER,
    carter_creep,
    creep_envelope,
    lag_error_bound,
    relaxation_length,
    relaxation_step,
)
from rollcontact.line.instationary.stationarity import (
    STATIONARITY_THRESHOLD,
    STATIONARY,
    InputHistory,
    stationarity,
    stationarity_of_samples,
)

__all__ = ["CREEP_RATIO_CAP", "LAG_ERROR_COEFFICIENT", "LAG_ERROR_FLOOR", "LAG_MEMORY", "MODES",
           "RELAXATION_DATUM_RATIO", "STATIONARITY_THRESHOLD", "STATIONARY", "STEADY_AFTER", "InputHistory",
           "InstationaryModel", "InstationaryState", "OscillatingForce", "aligned_grid_load", "carter_creep",
           "creep_envelope", "lag_error_bound", "oscillating_force_chebyshev", "oscillating_force_discretised",
           "quasi_steady_deviation", "relaxation_length", "relaxation_step", "stationarity",
           "stationarity_of_samples"]
