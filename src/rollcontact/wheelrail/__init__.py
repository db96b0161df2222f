"""Wheel on rail from real profiles: a wheelset on its track, the contact search, tread and flange patches, and their
normal and tangential contact at several fidelity levels behind one dispatcher.

* :mod:`.profiles` (profile files and :class:`~.profiles.Profile`), :mod:`.geometry` (:class:`~.geometry.Track`,
  :class:`~.geometry.Wheelset`, the pose and velocities), :mod:`.search` (contact points, patches and their gaps,
  creepages), :mod:`.normal` (Hertz's normal contact of each point and the loaded position), :mod:`.conicity` (the
  contact-geometry functions, the equivalent conicity, the contact table), :mod:`.patch` (a patch's gap),
  :mod:`.scene` (:class:`~.scene.WheelRailScene`, :class:`~.scene.PatchScene`), :mod:`.result`
  (:class:`~.result.WheelRailResult`, :class:`~.result.PatchResult`): the data layer;
* :mod:`.wheels`: what every level does around its patch solver (each wheel's vertical balance, the patches'
  tangential solves, the forces on the rails);
* :mod:`.methods`: the fidelity levels (Hertz's ellipses, strips, discretised), each exporting ``METHOD`` (a
  :class:`rollcontact.core.method.MethodSpec`);
* :mod:`.dispatch`: :func:`~.dispatch.solve`, the method table and the registry.

Track axes (docs/physics.md, Wheel/rail geometry): x along the track in the direction of travel, y lateral to the
right, z downward (right-handed, the Manchester Contact Benchmark's and CONTACT's axes); the result reports the forces
the wheels exert on the rails.
"""
