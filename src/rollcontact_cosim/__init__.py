"""rollcontact_cosim: rollcontact's contact FMUs co-simulated with host FMUs, by fmpy and libcosim.

Each scene of ``models/cosim`` is one system description (a host and a contact FMU, their parameters and
connections, and the run), and each master runs every scene from it:

* :mod:`~rollcontact_cosim.scenes`: the scene files and their system description (:class:`~.scenes.System`);
* :mod:`~rollcontact_cosim.master`: the fmpy master (Gauss-Seidel and Jacobi, FMI 2.0 and 3.0);
  :mod:`~rollcontact_cosim.osp`: the libcosim master; :mod:`~rollcontact_cosim.fmus`: the FMUs a run needs, built
  by ``build_fmu.py --if-stale``, and the result of a run;
* the hosts' physics, bundled in their FMUs (no FMI): :mod:`~rollcontact_cosim.wheel_rig` (a driven wheel, the
  ``WheelRig`` FMU, with the line contact ``RollingContact2D``) and :mod:`~rollcontact_cosim.wheelset` (a hunting
  wheelset, the ``Wheelset`` FMU, with the elliptic contact ``RollingContact3D_2``: the host model, its linear
  stability, the hunting study and its co-simulation);
* :mod:`~rollcontact_cosim.reference` (reference results with provenance, band comparison),
  :mod:`~rollcontact_cosim.stable_step` (the largest stable macro step of a scene's coupling),
  :mod:`~rollcontact_cosim.sweep` (sweeps and regression suites on dask), ``python -m rollcontact_cosim`` (the main
  job).

This module imports nothing else: the host FMUs import ``rollcontact_cosim.wheel_rig`` and
``rollcontact_cosim.wheelset`` in hosts that have neither fmpy nor matplotlib.
"""
