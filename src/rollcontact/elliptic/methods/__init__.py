"""The elliptic fidelity levels: each module solves a steady elliptic scene one way and exports ``METHOD``, its
:class:`~rollcontact.core.method.MethodSpec` (solver, applicability, rank, accuracy model), which the method table of
:mod:`rollcontact.elliptic.dispatch` lists.

* :mod:`~rollcontact.elliptic.methods.linear`: Kalker's linear theory (the creepage coefficients);
* :mod:`~rollcontact.elliptic.methods.fastsim`: Kalker's FASTSIM (simplified theory) with an elliptic traction bound;
* :mod:`~rollcontact.elliptic.methods.strips`: each lateral strip a 2D rolling problem of the project's 2D kernel;
* :mod:`~rollcontact.elliptic.methods.discretised`: Kalker's exact theory on rectangular elements (the reference and
  the fallback).

:mod:`~rollcontact.elliptic.methods.common` holds what they share (the scene's coefficients, applicability).
"""
