"""The fidelity levels: each module (or package) here solves a steady scene one way and exports ``METHOD``, its
:class:`~rollcontact.core.method.MethodSpec` (solver, applicability, rank, accuracy model), which the method table of
:mod:`rollcontact.line.dispatch` lists.

* :mod:`~rollcontact.line.methods.closed_form`: Hertz and Carter, exact for a parabolic gap and Coulomb friction.
* :mod:`~rollcontact.line.methods.polynomial`: the polynomial method in a Chebyshev basis (corrugation, several
  patches, velocity-dependent friction).
* :mod:`~rollcontact.line.methods.discretised`: boundary elements on the half-space, any gap and friction law; the
  fallback of the others.
"""
