"""The FMU's stepping model: parameters -> (state, inputs, step) -> outputs, with no FMI tool involved.

* :mod:`.parameters`: the fixed parameters (:class:`ContactParameters`), the outputs of a step
  (:class:`StepOutputs`) and the codes of the FMU's integer variables;
* :mod:`.state`: :class:`ModelState`, everything a model remembers between steps (copyable, serialisable);
* :mod:`.model`: :class:`ContactModel`, one quasi-steady communication step through ``rollcontact.solve`` (or the
  closed forms directly);
* :mod:`.transient`: its instationary half, the relaxation lag and the discretised transient switched in and out;
* :mod:`.table`: when a step answers from a certified table and when the table is built; the tables of
  :mod:`.falling_table` (falling friction on a flat surface) and :mod:`.corrugation_table` (a one-harmonic
  corrugation with Coulomb friction), on the interpolation of :mod:`.tabulation`.
"""

from rollcontact.stepping.model import ContactModel, mirrored
from rollcontact.stepping.parameters import (
    AUTO,
    METHOD_LEVELS,
    METHOD_NAMES,
    OPTION_NAMES,
    STATIONARY,
    ContactParameters,
    ModelError,
    StepOutputs,
)
from rollcontact.stepping.state import ModelState

__all__ = ["AUTO", "METHOD_LEVELS", "METHOD_NAMES", "OPTION_NAMES", "STATIONARY", "ContactModel", "ContactParameters",
           "ModelError", "ModelState", "StepOutputs", "mirrored"]
