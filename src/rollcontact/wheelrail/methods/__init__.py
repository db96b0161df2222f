"""The wheel/rail patch methods: the normal and tangential contact of one patch on its general gap, at two levels.

* :mod:`~rollcontact.wheelrail.methods.strips`: the fast non-Hertzian level, lateral strips each carrying a 2D
  normal and a 2D tangential problem;
* :mod:`~rollcontact.wheelrail.methods.discretised`: the discretised half-space on the actual gap, the reference.
"""
