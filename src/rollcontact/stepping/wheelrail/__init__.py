"""The wheelset's contact stepping model (the ``WheelsetContact`` FMUs' library half).

* :mod:`.parameters`: the fixed parameters (:class:`~.parameters.WheelsetContactParameters`), the outputs of a step
  (:class:`~.parameters.WheelsetContactOutputs`) and the codes of the FMU's integer variables;
* :mod:`.model`: :class:`~.model.WheelsetContactModel` and its state :class:`~.model.WheelsetContactState`: both
  wheels of a wheelset on real profiles stepped through the wheel/rail dispatcher
  (:func:`rollcontact.wheelrail.dispatch.solve`), or through the geometry table
  (:class:`rollcontact.wheelrail.tabulated.TabulatedWheelset`) at the fastest level.
"""
