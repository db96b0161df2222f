"""The discretised elastic half-space that the methods and instationary rolling share.

* :mod:`.elements`: piecewise-constant elements, influence coefficients, the normal problem with exact
  complementarity and the stick/slip solve;
* :mod:`.grid`: the grid a scene needs (its window and element count) and the patches of a contact on it;
* :mod:`.solver`: :class:`TransientSolver`, the traction history of rolling one element at a time (explicit state),
  and the normal problem fitted to a scene's contact;
* :mod:`.surface3d` and :mod:`.rolling3d`: the 3D half-space on rectangular elements (FFT convolution of the
  Boussinesq/Cerruti coefficients) and steady 3D rolling on it, which the elliptic method ``discretised`` wraps.
"""
