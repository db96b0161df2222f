"""The line contact's stepping model (the ``RollingContact2D`` FMUs' library half).

* :mod:`.parameters`: the fixed parameters (:class:`~.parameters.ContactParameters`), the outputs of a step
  (:class:`~.parameters.StepOutputs`) and the codes of the FMU's integer variables;
* :mod:`.state`: :class:`~.state.ModelState`, everything a model remembers between steps (copyable, serialisable);
* :mod:`.model`: :class:`~.model.ContactModel`, one quasi-steady communication step through
  :func:`rollcontact.solve` (or the closed forms directly);
* :mod:`.transient`: its instationary half, the relaxation lag and the discretised transient switched in and out;
* :mod:`.contacts`: :class:`~.contacts.ContactModels`, several contacts of one parameter set stepped together;
* :mod:`.table`: when a step answers from a certified table and when the table is built; the tables of
  :mod:`.falling_table` (falling friction on a flat surface) and :mod:`.corrugation_table` (a one-harmonic
  corrugation with Coulomb friction), on the interpolation of :mod:`.tabulation`.
"""
