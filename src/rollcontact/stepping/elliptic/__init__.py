"""The elliptic contact's stepping model (the ``RollingContact3D`` FMUs' library half).

* :mod:`.parameters`: the fixed parameters (:class:`~.parameters.EllipticParameters`), the outputs of a contact's
  step (:class:`~.parameters.EllipticOutputs`) and the codes of the FMU's integer variables;
* :mod:`.model`: :class:`~.model.EllipticModel` and its state :class:`~.model.EllipticState`, one or several contacts
  stepped through :func:`rollcontact.solve_elliptic`;
* :mod:`.linear`: :class:`~.linear.LinearContacts`, Kalker's linear theory of every contact at once.
"""
