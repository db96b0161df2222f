"""The discretised elastic half-space of quasi-identical bodies, for every geometry.

* :mod:`.elements`: the plane-strain (2D) half-space on piecewise-constant elements: influence coefficients, the
  normal problem with exact complementarity and the stick/slip solve (the line contact's
  :mod:`rollcontact.line.halfspace` builds its grids and transient solver on it);
* :mod:`.surface`: the 3D half-space on rectangular elements of a surface grid, influence coefficients of
  Boussinesq and Cerruti, convolved by FFT;
* :mod:`.rolling`: the normal problem on any gap and steady 3D rolling on a surface grid (the elliptic and wheel/rail
  contacts' discretised levels wrap it).
"""
