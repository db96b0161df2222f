"""The FMUs' stepping models: parameters -> (state, inputs, step) -> outputs, with no FMI tool involved.

* :mod:`.base`: :class:`SteppingModel`, what every geometry's model shares (messages said once, the explicit state,
  the budget and tolerance of a step, the checks of a step's arguments), and :class:`ModelError`;
* :mod:`.parameters`: :class:`ModelParameters`, the validated parameter block every geometry shares (material,
  friction law, rail condition, method, tolerance, step budget), and the codes of the FMUs' integer variables;
* :mod:`.line`: the line contact's model (:class:`ContactModel`, several contacts :class:`ContactModels`), its
  instationary half and its certified tables;
* :mod:`.elliptic`: the elliptic contact's model (:class:`EllipticModel`, one or several contacts) and its
  certified table of the strips;
* :mod:`.wheelrail`: a wheelset's contact on real profiles (:class:`WheelsetContactModel`), through the wheel/rail
  dispatcher or a geometry table;
* :mod:`.threads`: one BLAS thread while a model steps.
"""

from rollcontact.stepping.base import ModelError, SteppingModel
from rollcontact.stepping.elliptic.model import EllipticModel, EllipticState
from rollcontact.stepping.elliptic.parameters import EllipticOutputs, EllipticParameters
from rollcontact.stepping.line.contacts import ContactModels
from rollcontact.stepping.line.model import ContactModel
from rollcontact.stepping.line.parameters import ContactParameters, StepOutputs
from rollcontact.stepping.line.state import ModelState
from rollcontact.stepping.parameters import ModelParameters
from rollcontact.stepping.wheelrail.model import WheelsetContactModel, WheelsetContactState
from rollcontact.stepping.wheelrail.parameters import WheelsetContactOutputs, WheelsetContactParameters

__all__ = ["ContactModel", "ContactModels", "ContactParameters", "EllipticModel", "EllipticOutputs",
           "EllipticParameters", "EllipticState", "ModelError", "ModelParameters", "ModelState", "StepOutputs",
           "SteppingModel", "WheelsetContactModel", "WheelsetContactOutputs", "WheelsetContactParameters",
           "WheelsetContactState"]
