"""The line contact on the discretised plane-strain half-space (:mod:`rollcontact.core.halfspace.elements`), which
its discretised method, its polynomial method's several patches and instationary rolling share.

* :mod:`.grid`: the grid a scene needs (its window and element count) and the patches of a contact on it;
* :mod:`.solver`: :class:`~.solver.TransientSolver`, the traction history of rolling one element at a time (explicit
  state), and the normal problem fitted to a scene's contact.
"""
