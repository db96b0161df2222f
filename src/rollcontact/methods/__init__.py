"""The fidelity levels: each module (or package) here solves a steady scene one way and exports ``METHOD``, its
:class:`~rollcontact.method.MethodSpec` (solver, applicability, rank, accuracy model), which the method table of
:mod:`rollcontact.dispatch` lists.

* :mod:`~rollcontact.methods.closed_form`: Hertz and Carter, exact for a parabolic gap and Coulomb friction.
* :mod:`~rollcontact.methods.polynomial`: the polynomial method in a Chebyshev basis (corrugation, several
  patches, velocity-dependent friction).
* :mod:`~rollcontact.methods.discretised`: boundary elements on the half-space, any gap and friction law; the
  fallback of the others.
"""
